/*
 * vi_fmi_layer_internal.h - what the files of the FMI layer (src/fmi/vi_fmi_*.c) share among themselves
 * and no face uses: the one model of the binary, the entry of a call, and the helpers that more than
 * one concern needs (state and category names, the variable's storage, range checks).
 */
#ifndef VI_FMI_LAYER_INTERNAL_H
#define VI_FMI_LAYER_INTERNAL_H

#include "vi_check.h"
#include "vi_fmi_layer.h"

#define MODEL (&vi_fmu_this_model)

#define LOG_ERROR(c, ...) vi_fmi_log(c, VI_STATUS_ERROR, VI_CAT_ERROR, __VA_ARGS__)

/* The status of a call that did what it was asked: VI_STATUS_OK, whatever notes it logged (a message of
 * status Warning the computation went on through does not make its result wrong); VI_STATUS_WARNING only
 * when the call flagged its result as not all that was asked (vi_fmi_warn_result). */
static inline vi_status done(const vi_fmi_instance *c) { return c->result_warning ? VI_STATUS_WARNING : VI_STATUS_OK; }

/* Log a warning about the current call's result (it is not all that was asked, e.g. the model asks to
 * terminate) whatever is enabled: the call then returns VI_STATUS_WARNING through done(). */
void vi_fmi_warn_result(vi_fmi_instance *c, const char *fmt, ...) VI_PRINTF_FORMAT(2, 3);

/* The first statement of a layer call on `instance` named `fn`: c, or VI_STATUS_ERROR when the call
 * is not allowed in the instance's state (vi_fmi_enter logged why). */
#define ENTER(call)                                  \
    vi_fmi_instance *c = enter_call(instance, call, fn);  \
    if (!c) return VI_STATUS_ERROR

/* vi_fmi_enter inline where it has nothing to log (the call allowed, its category off): every call
 * of a communication step passes here. */
static inline vi_fmi_instance *enter_call(void *instance, vi_call call, const char *fn)
{
    vi_fmi_instance *c = instance;
    if (!c || !(c->state & vi_fmi_allowed[call]) || (c->log_mask & (1u << VI_CAT_CALL | 1u << VI_CAT_ALL)))
        return vi_fmi_enter(instance, call, fn);
    c->result_warning = 0;
    return c;
}

/* ---- state machine (src/fmi/vi_fmi_state_machine.c) ---- */
/* The FMI state s (one VI_ST_* bit) as messages name it, e.g. "step complete". */
const char *vi_fmi_state_name(unsigned s);

/* ---- logging (src/fmi/vi_fmi_log.c) ---- */
/* The name of log category cat (the call category as the face names it). */
const char *vi_fmi_category_name(const vi_fmi_instance *c, int cat);
/* Hand text to the face's emit with every byte outside printable ASCII written \xNN. */
void vi_fmi_emit(const vi_fmi_instance *c, vi_status status, const char *category, const char *text);
/* The logger handed to the model (vi_fmu_log_fn); env is the instance. */
void vi_fmi_model_log(void *env, int category, const char *fmt, ...) VI_PRINTF_FORMAT(3, 4);

/* ---- values (src/fmi/vi_fmi_values.c) ---- */
/* The struct of a group inside a plain-data block of the model (NULL for outputs). */
void *vi_fmi_group_in(const void *block, vi_group group);
/* The variable behind vr if it is accessed through the API type `api`; NULL (logged) otherwise. */
const vi_variable *vi_fmi_lookup(vi_fmi_instance *c, const char *fn, unsigned vr, vi_type api);
/* Is x a valid value of the Real or Integer variable v (its range; an item of its enumeration)?
 * 0, or -1 with a message naming the variable, the value and what is allowed. */
int vi_fmi_check_range(const vi_variable *v, double x, char *msg, size_t n);

#endif
