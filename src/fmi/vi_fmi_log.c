/*
 * vi_fmi_log.c - the FMI layer's logging: categories, the filter of what reaches the importer,
 * messages made printable, and the logger handed to the model.
 */
#include "vi_fmi_layer_internal.h"

#include <stdarg.h>
#include <stdio.h>

const char *vi_fmi_category_name(const vi_fmi_instance *c, int cat)
{
    static const char *const names[VI_CAT_COUNT] = {
        [VI_CAT_EVENTS] = "logEvents", [VI_CAT_SOLVER] = "logSolver", [VI_CAT_WARNING] = "logStatusWarning",
        [VI_CAT_DISCARD] = "logStatusDiscard", [VI_CAT_ERROR] = "logStatusError", [VI_CAT_ALL] = "logAll"};
    return cat == VI_CAT_CALL ? c->face->call_category : names[cat];
}

int vi_fmi_logs(const vi_fmi_instance *c, int cat) { return (c->log_mask >> cat & 1u) || (c->log_mask >> VI_CAT_ALL & 1u); }

/* Hand a message to the face's emit, with every byte outside printable ASCII (a control character of
 * an instance name or of a String value the importer gave) written \xNN. */
void vi_fmi_emit(const vi_fmi_instance *c, vi_status status, const char *category, const char *text)
{
    char clean[VI_FMI_MESSAGE_MAX];
    size_t j = 0;
    for (size_t i = 0; text[i] && j + 4 < sizeof clean; i++) {
        unsigned char ch = (unsigned char)text[i];
        if (ch < 0x20 || ch > 0x7e) j += (size_t)vi_snprintf(clean + j, sizeof clean - j, "\\x%02x", ch);
        else clean[j++] = (char)ch;
    }
    clean[j] = '\0';
    c->face->emit(c, status, category, clean);
}

/* Warnings, discards and errors always reach the logger (FMI: the user is expected to see them); debug
 * messages (status OK) only in the categories enabled. */
static void vlog(const vi_fmi_instance *c, vi_status status, int cat, const char *fmt, va_list ap)
{
    if (!c->cb.logger || (status < VI_STATUS_WARNING && !vi_fmi_logs(c, cat))) return;
    char text[1024];
    vi_vsnprintf(text, sizeof text, fmt, ap);
    vi_fmi_emit(c, status, vi_fmi_category_name(c, cat), text);
}

void vi_fmi_log(const vi_fmi_instance *c, vi_status status, int cat, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vlog(c, status, cat, fmt, ap);
    va_end(ap);
}

vi_status vi_fmi_refuse(const vi_fmi_instance *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vlog(c, VI_STATUS_ERROR, VI_CAT_ERROR, fmt, ap);
    va_end(ap);
    return VI_STATUS_ERROR;
}

vi_status vi_fmi_refuse_call(void *instance, vi_call call, const char *fn, const char *fmt, ...)
{
    const vi_fmi_instance *c = vi_fmi_enter(instance, call, fn);
    if (!c) return VI_STATUS_ERROR;
    va_list ap;
    va_start(ap, fmt);
    vlog(c, VI_STATUS_ERROR, VI_CAT_ERROR, fmt, ap);
    va_end(ap);
    return VI_STATUS_ERROR;
}

void vi_fmi_warn_result(vi_fmi_instance *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vlog(c, VI_STATUS_WARNING, VI_CAT_WARNING, fmt, ap);
    va_end(ap);
    c->result_warning = 1;
}

/* Logger handed to the model: its categories mapped onto the layer's. A warning of the model is a note
 * the computation goes on through (validity, tolerance, an option ignored, a solver's remark): logged
 * with status Warning whatever is enabled, so that every importer shows it, while the call returns OK
 * (importers such as fmusim and PyFMI stop a run at any status but OK). A result that is not right is
 * the hook's return value (an error, a discarded step, a request to terminate), never a message. */
void vi_fmi_model_log(void *env, int category, const char *fmt, ...)
{
    static const int cat_of[] = {[VI_FMU_LOG_EVENTS] = VI_CAT_EVENTS, [VI_FMU_LOG_SOLVER] = VI_CAT_SOLVER,
                                 [VI_FMU_LOG_WARNING] = VI_CAT_WARNING, [VI_FMU_LOG_ERROR] = VI_CAT_ERROR};
    static const vi_status status_of[] = {[VI_FMU_LOG_EVENTS] = VI_STATUS_OK, [VI_FMU_LOG_SOLVER] = VI_STATUS_OK,
                                          [VI_FMU_LOG_WARNING] = VI_STATUS_WARNING,
                                          [VI_FMU_LOG_ERROR] = VI_STATUS_ERROR};
    const vi_fmi_instance *c = env;
    int known = category >= 0 && category < (int)(sizeof cat_of / sizeof cat_of[0]);
    if (!known) /* a model's mistake: its message still reaches the importer, as an error */
        vi_fmi_log(c, VI_STATUS_ERROR, VI_CAT_ERROR, "the model logged with the unknown category %d:", category);
    va_list ap;
    va_start(ap, fmt);
    vlog(c, known ? status_of[category] : VI_STATUS_ERROR, known ? cat_of[category] : VI_CAT_ERROR, fmt, ap);
    va_end(ap);
}
