/*
 * vi_fmi_core.c - the part of the generic FMI layer that every face shares (vi_fmi_core.h):
 * instance life cycle, the state machine, value access through the variable table, logging, the
 * checked FMU-state envelope, and the simulation calls. It knows no model and no version of the
 * standard: it reaches the one model of this binary through vi_fmu_this_model and its hooks, and
 * the importer through the face's emit.
 */
#include "vi_fmi_core.h"

#include "vi_check.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MODEL (&vi_fmu_this_model)

/* ---- the state machine ------------------------------------------------------------------------ */

#define ST_READABLE (VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED | VI_ST_ERROR | \
                     VI_ST_EVENT | VI_ST_CONTINUOUS)
#define ST_ME_READABLE (VI_ST_INIT | VI_ST_EVENT | VI_ST_CONTINUOUS | VI_ST_TERMINATED | VI_ST_ERROR)

/* In which FMI states each call is allowed (FMI 2.0, section 3.2.3 and 4.2.4 state machines). */
const unsigned vi_core_allowed[VI_CALL_COUNT] = {
    [VI_CALL_SET_DEBUG_LOGGING] = VI_ST_ANY_BUT_FATAL,
    [VI_CALL_SETUP_EXPERIMENT] = VI_ST_INSTANTIATED,
    [VI_CALL_ENTER_INIT] = VI_ST_INSTANTIATED,
    [VI_CALL_EXIT_INIT] = VI_ST_INIT,
    [VI_CALL_TERMINATE] = VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_EVENT | VI_ST_CONTINUOUS,
    [VI_CALL_RESET] = VI_ST_ANY_BUT_FATAL,
    [VI_CALL_GET] = ST_READABLE,
    [VI_CALL_SET_REAL] = VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_EVENT | VI_ST_CONTINUOUS,
    [VI_CALL_SET_DISCRETE] = VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_EVENT,
    [VI_CALL_FMU_STATE] = VI_ST_ANY_BUT_FATAL,
    [VI_CALL_DIRECTIONAL_DERIVATIVE] = ST_READABLE,
    [VI_CALL_SET_INPUT_DERIVATIVES] = VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_STEP_COMPLETE,
    [VI_CALL_GET_OUTPUT_DERIVATIVES] = VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED |
                                       VI_ST_ERROR,
    [VI_CALL_DO_STEP] = VI_ST_STEP_COMPLETE,
    [VI_CALL_CANCEL_STEP] = VI_ST_ANY_BUT_FATAL,
    [VI_CALL_GET_STATUS] = VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED,
    [VI_CALL_GET_LAST_STATUS] = VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED | VI_ST_ERROR,
    [VI_CALL_ENTER_EVENT_MODE] = VI_ST_EVENT | VI_ST_CONTINUOUS | VI_ST_STEP_COMPLETE,
    [VI_CALL_NEW_DISCRETE_STATES] = VI_ST_EVENT,
    [VI_CALL_ENTER_CONTINUOUS_MODE] = VI_ST_EVENT,
    [VI_CALL_COMPLETED_STEP] = VI_ST_CONTINUOUS,
    [VI_CALL_SET_TIME] = VI_ST_EVENT | VI_ST_CONTINUOUS,
    [VI_CALL_SET_STATES] = VI_ST_CONTINUOUS,
    [VI_CALL_GET_DERIVATIVES] = VI_ST_EVENT | VI_ST_CONTINUOUS | VI_ST_TERMINATED | VI_ST_ERROR,
    [VI_CALL_GET_EVENT_INDICATORS] = ST_ME_READABLE,
    [VI_CALL_GET_STATES] = ST_ME_READABLE,
    [VI_CALL_GET_NOMINALS] = VI_ST_INSTANTIATED | VI_ST_EVENT | VI_ST_CONTINUOUS | VI_ST_TERMINATED | VI_ST_ERROR,
    [VI_CALL_ENTER_STEP_MODE] = VI_ST_EVENT,
};

static const char *state_name(unsigned s)
{
    switch (s) {
    case VI_ST_INSTANTIATED: return "instantiated";
    case VI_ST_INIT: return "initialization mode";
    case VI_ST_STEP_COMPLETE: return "step complete";
    case VI_ST_STEP_FAILED: return "step failed";
    case VI_ST_TERMINATED: return "terminated";
    case VI_ST_ERROR: return "error";
    case VI_ST_EVENT: return "event mode";
    case VI_ST_CONTINUOUS: return "continuous-time mode";
    default: return "fatal";
    }
}

/* ---- logging ------------------------------------------------------------------------------------ */

static const char *category_name(const vi_core *c, int cat)
{
    static const char *const names[VI_CAT_COUNT] = {
        [VI_CAT_EVENTS] = "logEvents", [VI_CAT_SOLVER] = "logSolver", [VI_CAT_WARNING] = "logStatusWarning",
        [VI_CAT_DISCARD] = "logStatusDiscard", [VI_CAT_ERROR] = "logStatusError", [VI_CAT_ALL] = "logAll"};
    return cat == VI_CAT_CALL ? c->face->call_category : names[cat];
}

int vi_core_logs(const vi_core *c, int cat) { return (c->log_mask >> cat & 1u) || (c->log_mask >> VI_CAT_ALL & 1u); }

/* Hand a message to the face's emit, with every byte outside printable ASCII (a control character of
 * an instance name or of a String value the importer gave) written \xNN. */
static void emit_printable(const vi_core *c, vi_status status, const char *category, const char *text)
{
    char clean[VI_CORE_MESSAGE_MAX];
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
static void vlog(const vi_core *c, vi_status status, int cat, const char *fmt, va_list ap)
{
    if (!c->cb.logger || (status < VI_STATUS_WARNING && !vi_core_logs(c, cat))) return;
    char text[1024];
    vi_vsnprintf(text, sizeof text, fmt, ap);
    emit_printable(c, status, category_name(c, cat), text);
}

void vi_core_log(const vi_core *c, vi_status status, int cat, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vlog(c, status, cat, fmt, ap);
    va_end(ap);
}
#define LOG_ERROR(c, ...) vi_core_log(c, VI_STATUS_ERROR, VI_CAT_ERROR, __VA_ARGS__)

vi_status vi_core_refuse(const vi_core *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vlog(c, VI_STATUS_ERROR, VI_CAT_ERROR, fmt, ap);
    va_end(ap);
    return VI_STATUS_ERROR;
}

/* Logger handed to the model: its categories mapped onto the layer's. */
static void model_log(void *env, int category, const char *fmt, ...)
{
    static const int cat_of[] = {[VI_FMU_LOG_EVENTS] = VI_CAT_EVENTS, [VI_FMU_LOG_SOLVER] = VI_CAT_SOLVER,
                                 [VI_FMU_LOG_WARNING] = VI_CAT_WARNING, [VI_FMU_LOG_ERROR] = VI_CAT_ERROR};
    static const vi_status status_of[] = {[VI_FMU_LOG_EVENTS] = VI_STATUS_OK, [VI_FMU_LOG_SOLVER] = VI_STATUS_OK,
                                          [VI_FMU_LOG_WARNING] = VI_STATUS_WARNING,
                                          [VI_FMU_LOG_ERROR] = VI_STATUS_ERROR};
    vi_core *c = env;
    int known = category >= 0 && category < (int)(sizeof cat_of / sizeof cat_of[0]);
    if (known && status_of[category] == VI_STATUS_WARNING && c->cb.logger) c->warned = 1;
    if (!known) /* a model's mistake: its message still reaches the importer, as an error */
        vi_core_log(c, VI_STATUS_ERROR, VI_CAT_ERROR, "the model logged with the unknown category %d:", category);
    va_list ap;
    va_start(ap, fmt);
    vlog(c, known ? status_of[category] : VI_STATUS_ERROR, known ? cat_of[category] : VI_CAT_ERROR, fmt, ap);
    va_end(ap);
}

vi_core *vi_core_enter(void *instance, vi_call call, const char *fn)
{
    vi_core *c = instance;
    if (!c) return NULL;
    if (!(c->state & vi_core_allowed[call])) {
        LOG_ERROR(c, "%s: not allowed in state '%s'", fn, state_name(c->state));
        return NULL;
    }
    if (vi_core_logs(c, VI_CAT_CALL)) vi_core_log(c, VI_STATUS_OK, VI_CAT_CALL, "%s", fn);
    c->warned = 0;
    return c;
}

/* The status of a call that did what it was asked: VI_STATUS_WARNING when it logged a warning. */
static vi_status done(const vi_core *c) { return c->warned ? VI_STATUS_WARNING : VI_STATUS_OK; }
#define ENTER(call)                                  \
    vi_core *c = vi_core_enter(instance, call, fn);  \
    if (!c) return VI_STATUS_ERROR

vi_status vi_core_fail(vi_core *c, const char *fn)
{
    LOG_ERROR(c, "%s: %s", fn, MODEL->message(c->model));
    c->state = VI_ST_ERROR;
    return VI_STATUS_ERROR;
}

/* ---- life cycle ------------------------------------------------------------------------------- */

vi_status vi_core_set_debug_logging(void *instance, const char *fn, int on, size_t n, const char *const categories[])
{
    ENTER(VI_CALL_SET_DEBUG_LOGGING);
    if (n > 0 && !categories) return vi_core_refuse(c, "%s: categories is NULL", fn);
    unsigned mask = 0;
    for (size_t i = 0; i < n; i++) {
        int k = 0;
        while (k < VI_CAT_COUNT && (!categories[i] || strcmp(categories[i], category_name(c, k)) != 0)) k++;
        if (k == VI_CAT_COUNT)
            return vi_core_refuse(c, "%s: unknown log category '%s'", fn, categories[i] ? categories[i] : "(null)");
        mask |= 1u << k;
    }
    if (n == 0) mask = (1u << VI_CAT_COUNT) - 1u;
    c->log_mask = on ? mask : c->log_mask & ~mask; /* on: exactly the categories named */
    return done(c);
}

vi_core *vi_core_instantiate(const vi_face *face, const vi_callbacks *cb, const char *fn, const char *name,
                             vi_kind kind, const char *guid, const char *resource_dir, const char *resource_label,
                             int logging_on)
{
    vi_core tmp = {.face = face, .cb = *cb, .name = (char *)(name ? name : "?")};
    if (!cb->alloc || !cb->free) {
        LOG_ERROR(&tmp, "%s: the callbacks allocateMemory and freeMemory are required", fn);
        return NULL;
    }
    if (!name || !*name) {
        LOG_ERROR(&tmp, "%s: instanceName must be a non-empty string", fn);
        return NULL;
    }
    if (kind != VI_KIND_CS && !(kind == VI_KIND_ME && MODEL->n_states > 0)) {
        LOG_ERROR(&tmp, "%s: %s does not offer the interface type asked for (%s)", fn, MODEL->model_identifier,
                  kind == VI_KIND_ME ? "Model Exchange" : "unknown type");
        return NULL;
    }
    if (!guid || strcmp(guid, MODEL->guid) != 0) {
        LOG_ERROR(&tmp, "%s: GUID '%s' does not match this FMU's '%s'", fn, guid ? guid : "(null)", MODEL->guid);
        return NULL;
    }
    vi_core *c = cb->alloc(1, sizeof *c);
    char *copy = cb->alloc(strlen(name) + 1, 1);
    void *model = cb->alloc(1, MODEL->instance_size);
    void *outputs = cb->alloc(1, MODEL->outputs_size);
    if (!c || !copy || !model || !outputs) {
        LOG_ERROR(&tmp, "%s: out of memory", fn);
        void *blocks[] = {c, copy, model, outputs};
        for (int i = 0; i < 4; i++)
            if (blocks[i]) cb->free(blocks[i]);
        return NULL;
    }
    memset(c, 0, sizeof *c);
    memset(model, 0, MODEL->instance_size);
    strcpy(copy, name);
    c->face = face;
    c->cb = *cb;
    c->kind = kind;
    c->model = model;
    c->outputs = outputs;
    c->name = copy;
    c->state = VI_ST_INSTANTIATED;
    c->log_mask = logging_on ? (1u << VI_CAT_COUNT) - 1u : 0u;
    MODEL->init(c->model, model_log, c);
    if (MODEL->set_resources && MODEL->set_resources(c->model, resource_dir) < 0) {
        LOG_ERROR(c, "%s: resources '%s': %s", fn, resource_label ? resource_label : "(null)", MODEL->message(c->model));
        vi_core_free(c, fn);
        return NULL;
    }
    if (vi_core_logs(c, VI_CAT_CALL)) vi_core_log(c, VI_STATUS_OK, VI_CAT_CALL, "%s: %s", fn, name);
    return c;
}

void vi_core_free(vi_core *c, const char *fn)
{
    if (!c) return;
    if (vi_core_logs(c, VI_CAT_CALL)) vi_core_log(c, VI_STATUS_OK, VI_CAT_CALL, "%s", fn);
    MODEL->release(c->model);
    void (*release)(void *) = c->cb.free;
    release(c->outputs);
    release(c->model);
    release(c->name);
    release(c);
}

vi_status vi_core_setup_experiment(void *instance, const char *fn, int tolerance_defined, double tolerance,
                                   double start, int stop_defined, double stop)
{
    ENTER(VI_CALL_SETUP_EXPERIMENT);
    if (!isfinite(start) || (tolerance_defined && !(tolerance > 0.0 && tolerance < 1.0)) ||
        (stop_defined && !(stop >= start)))
        return vi_core_refuse(c, "%s: need a finite start time, a tolerance in (0, 1) and stop time >= start time (got "
                                 "start %g, tolerance %g, stop %g)", fn, start, tolerance, stop);
    MODEL->setup_experiment(c->model, start, tolerance_defined != 0, tolerance);
    c->stop_time_defined = stop_defined != 0;
    c->stop_time = stop;
    return done(c);
}

vi_status vi_core_enter_init(void *instance, const char *fn)
{
    ENTER(VI_CALL_ENTER_INIT);
    c->state = VI_ST_INIT;
    return done(c);
}

vi_status vi_core_exit_init(void *instance, const char *fn)
{
    ENTER(VI_CALL_EXIT_INIT);
    if (c->kind == VI_KIND_ME) {
        if (MODEL->me_initialize(c->model) < 0) return vi_core_fail(c, fn);
        c->initialized = 1;
        c->state = VI_ST_EVENT; /* the importer runs the initial event iteration */
        c->t_committed = MODEL->time(c->model);
        c->event_passes = 0;
        return done(c);
    }
    if (MODEL->initialize(c->model) < 0) return vi_core_fail(c, fn);
    c->initialized = 1;
    c->state = VI_ST_STEP_COMPLETE;
    return done(c);
}

vi_status vi_core_terminate(void *instance, const char *fn)
{
    ENTER(VI_CALL_TERMINATE);
    if (MODEL->terminate) MODEL->terminate(c->model);
    c->state = VI_ST_TERMINATED;
    return done(c);
}

vi_status vi_core_reset(void *instance, const char *fn)
{
    ENTER(VI_CALL_RESET);
    MODEL->reset(c->model);
    c->stop_time_defined = 0;
    c->initialized = 0;
    c->state = VI_ST_INSTANTIATED;
    return done(c);
}

double vi_core_time(const vi_core *c) { return MODEL->time(c->model); }

/* ---- values ----------------------------------------------------------------------------------- */

/* The struct of a group inside a plain-data block of the model (NULL for outputs). */
static void *group_in(const void *block, vi_group group)
{
    switch (group) {
    case VI_GROUP_PARAMETERS: return (char *)block + MODEL->parameters_offset;
    case VI_GROUP_INPUTS: return (char *)block + MODEL->inputs_offset;
    case VI_GROUP_INPUT_DERIVATIVES: return (char *)block + MODEL->input_derivatives_offset;
    default: return NULL;
    }
}

/* Where the value of v lives; NULL for outputs (computed on demand). */
static void *storage(vi_core *c, const vi_variable *v)
{
    if (v->group == VI_GROUP_OUTPUTS) return NULL;
    return (char *)group_in(MODEL->state(c->model), v->group) + v->offset;
}

/* The derivative of the Real input v. */
static double *derivative(vi_core *c, const vi_variable *v)
{
    return (double *)((char *)group_in(MODEL->state(c->model), VI_GROUP_INPUT_DERIVATIVES) + v->offset);
}

/* The variable behind vr if it is accessed through the API type `api` (Real, Integer or Boolean;
 * enumerations go through Integer); NULL (logged) otherwise. */
static inline const vi_variable *lookup(vi_core *c, const char *fn, unsigned vr, vi_type api)
{
    if (vr >= (unsigned)MODEL->nvariables) {
        LOG_ERROR(c, "%s: unknown value reference %u", fn, vr);
        return NULL;
    }
    const vi_variable *v = &MODEL->variables[vr];
    vi_type t = v->type;
    if (t == VI_Integer || t == VI_Enumeration)
        t = c->face->named_enumerations && strcmp(v->enumeration, "none") != 0 ? VI_Enumeration : VI_Integer;
    if (t != api) {
        static const char *const type_names[] = {"Real", "Integer", "Boolean", "Enumeration", "String"};
        const char *type = c->face->type_names ? c->face->type_names[t] : type_names[v->type];
        LOG_ERROR(c, "%s: value reference %u (%s) is of type %s", fn, vr, v->name, type);
        return NULL;
    }
    return v;
}

/* Is vr the independent variable time of the face? */
static int is_time(const vi_core *c, unsigned vr) { return c->face->has_time && vr == c->face->time_vr; }

/* Is vr an event indicator of the face (its index), else -1? */
static int indicator_of(const vi_core *c, unsigned vr)
{
    if (!c->face->has_indicator_vrs || vr < c->face->indicator_vr_base) return -1;
    unsigned i = vr - c->face->indicator_vr_base;
    return i < (unsigned)MODEL->n_indicators ? (int)i : -1;
}

/* The Real input whose derivative has the value reference vr in the face, else NULL. */
static const vi_variable *input_of_derivative(const vi_core *c, unsigned vr)
{
    if (!c->face->has_input_derivatives || vr < c->face->derivative_vr_base) return NULL;
    unsigned row = vr - c->face->derivative_vr_base;
    if (row >= (unsigned)MODEL->nvariables) return NULL;
    const vi_variable *v = &MODEL->variables[row];
    return v->group == VI_GROUP_INPUTS && v->type == VI_Real ? v : NULL;
}

/* Where the outputs and calculated parameters among vr[] are, computed from the current state (in
 * initialization mode, and in the error state of an initialization that failed, from the initial
 * state the current parameters give: the model may never have been set up): the model's own, or
 * c->outputs; NULL (logged) when preparing failed. */
static inline const void *current_outputs(vi_core *c, const char *fn, const unsigned vr[], size_t nvr)
{
    int unset = c->state == VI_ST_INIT || (c->state == VI_ST_ERROR && !c->initialized);
    if (unset && MODEL->prepare(c->model) < 0) {
        LOG_ERROR(c, "%s: %s", fn, MODEL->message(c->model));
        return NULL;
    }
    if (MODEL->outputs_of) return MODEL->outputs_of(c->model, vr, nvr);
    MODEL->outputs(c->model, c->outputs);
    return c->outputs;
}

/* Element i of a face's array as a double, or as an int; stored into one. */
static double elem_real(const void *a, vi_elem e, size_t i)
{
    switch (e) {
    case VI_ELEM_DOUBLE: return ((const double *)a)[i];
    case VI_ELEM_INT: return ((const int *)a)[i];
    case VI_ELEM_INT64: return (double)((const int64_t *)a)[i];
    case VI_ELEM_BOOL: return ((const bool *)a)[i];
    default: return NAN;
    }
}
static long long elem_int(const void *a, vi_elem e, size_t i)
{
    switch (e) {
    case VI_ELEM_INT: return ((const int *)a)[i];
    case VI_ELEM_INT64: return ((const int64_t *)a)[i];
    case VI_ELEM_BOOL: return ((const bool *)a)[i];
    default: return (long long)((const double *)a)[i];
    }
}
static void elem_store(void *a, vi_elem e, size_t i, double x, int k)
{
    switch (e) {
    case VI_ELEM_DOUBLE: ((double *)a)[i] = x; break;
    case VI_ELEM_INT: ((int *)a)[i] = k; break;
    case VI_ELEM_INT64: ((int64_t *)a)[i] = k; break;
    case VI_ELEM_BOOL: ((bool *)a)[i] = k != 0; break;
    default: break;
    }
}

vi_status vi_core_get(void *instance, const char *fn, const unsigned vr[], size_t nvr, vi_type api, void *values,
                      vi_elem elem)
{
    ENTER(VI_CALL_GET);
    if (nvr > 0 && (!vr || !values)) return vi_core_refuse(c, "%s: NULL array", fn);
    const void *outs = NULL;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] >= (unsigned)MODEL->nvariables && api == VI_Real) { /* the face's own, beyond the table's rows */
            if (is_time(c, vr[i])) { /* in initialization mode: the start time (prepare) */
                if (!outs && !(outs = current_outputs(c, fn, vr, nvr))) return VI_STATUS_ERROR;
                elem_store(values, elem, i, MODEL->time(c->model), 0);
                continue;
            }
            const vi_variable *in = input_of_derivative(c, vr[i]);
            if (in) {
                elem_store(values, elem, i, *derivative(c, in), 0);
                continue;
            }
            int k = indicator_of(c, vr[i]);
            if (k >= 0) { /* the model's indicators at the current state (in initialization mode: the initial
                           * one), in Co-Simulation too, where they are declared as well */
                double z[VI_MAX_INDICATORS];
                if (!MODEL->indicators || MODEL->n_indicators > VI_MAX_INDICATORS)
                    return vi_core_refuse(c, "%s: value reference %u is an event indicator this model cannot evaluate",
                                          fn, vr[i]);
                if (!outs && !(outs = current_outputs(c, fn, vr, nvr))) return VI_STATUS_ERROR;
                MODEL->indicators(c->model, z);
                elem_store(values, elem, i, z[k], 0);
                continue;
            }
        }
        const vi_variable *v = lookup(c, fn, vr[i], api);
        if (!v) return VI_STATUS_ERROR;
        const void *p = storage(c, v);
        if (api == VI_String) { /* the stored value: valid until it is set again */
            ((const char **)values)[i] = p;
            continue;
        }
        if (!p) {
            if (!outs && !(outs = current_outputs(c, fn, vr, nvr))) return VI_STATUS_ERROR;
            p = (const char *)outs + v->offset;
        }
        if (api == VI_Real && !isfinite(*(const double *)p)) /* no value (after a failed initialization, say) */
            return vi_core_refuse(c, "%s: %s = %g has no value in state '%s'", fn, v->name, *(const double *)p,
                                  state_name(c->state));
        if (api == VI_Real) elem_store(values, elem, i, *(const double *)p, 0);
        else elem_store(values, elem, i, 0.0, *(const int *)p);
    }
    return done(c);
}

static int tunable(const vi_variable *v) { return strcmp(v->variability, "tunable") == 0; }

/* Is enumeration value k an item of type? */
static int enum_item(const char *type, int k)
{
    for (int i = 0; i < MODEL->n_enum_items; i++)
        if (MODEL->enum_items[i].value == k && strcmp(MODEL->enum_items[i].type, type) == 0) return 1;
    return 0;
}

/* x in as few digits as read back as x (at most 17). */
static void format_value(double x, char *text, size_t n)
{
    for (int digits = 15; digits <= 17; digits++) {
        vi_snprintf(text, n, "%.*g", digits, x);
        if (vi_strtod(text, NULL) == x) return;
    }
}

/* Is x a valid value of the Real or Integer variable v: inside its range (the table's min and max)
 * and, for an enumerated Integer, one of its items? 0, or -1 with a message naming the variable,
 * the value and what is allowed. */
static int check_range(const vi_variable *v, double x, char *msg, size_t n)
{
    char range[256] = "";
    if (strcmp(v->enumeration, "none") != 0) {
        if (x >= INT_MIN && x <= INT_MAX && x == (int)x && enum_item(v->enumeration, (int)x)) return 0;
        size_t used = 0;
        for (int i = 0; i < MODEL->n_enum_items && used < sizeof range; i++) {
            const vi_enum_item *e = &MODEL->enum_items[i];
            if (strcmp(e->type, v->enumeration) != 0) continue;
            int k = vi_snprintf(range + used, sizeof range - used, "%s%s=%d", used ? ", " : "", e->name, e->value);
            used += k > 0 ? (size_t)k : 0;
        }
        VI_FAIL(msg, n, "%s = %.0f is not one of its items %s", v->name, x, range);
    }
    if (vi_in_range(v, x)) return 0;
    char value[32];
    format_value(x, value, sizeof value);
    vi_range_text(v, range, sizeof range);
    VI_FAIL(msg, n, "%s = %s is outside its range %s (%s)", v->name, value, range, v->description);
}

/* May v be set now? Inputs and tunable parameters: before and after initialization; fixed
 * parameters: until the end of initialization mode; nothing else ever. (The callers allow only
 * the states of their call.) */
static int settable(vi_core *c, const char *fn, const vi_variable *v)
{
    if (c->state == VI_ST_CONTINUOUS && !(v->group == VI_GROUP_INPUTS && strcmp(v->variability, "continuous") == 0)) {
        LOG_ERROR(c, "%s: %s cannot be set in continuous-time mode (only continuous inputs can): set it in event mode",
                  fn, v->name);
        return 0;
    }
    if (v->group == VI_GROUP_INPUTS) return 1;
    if (v->group == VI_GROUP_PARAMETERS && ((c->state & (VI_ST_INSTANTIATED | VI_ST_INIT)) || tunable(v))) return 1;
    if (v->group == VI_GROUP_PARAMETERS)
        LOG_ERROR(c, "%s: %s is a fixed parameter: set it before the end of initialization mode (or after a reset)",
                  fn, v->name);
    else
        LOG_ERROR(c, "%s: %s is an %s and cannot be set", fn, v->name, v->causality);
    return 0;
}

/* After a value was set: a new input value holds (zero-order) until a derivative is set; an input or
 * a tunable parameter set between steps (co-simulation) or in event mode (model exchange) is
 * announced to the model. */
static void changed(vi_core *c, const vi_variable *v)
{
    if (v->group == VI_GROUP_INPUTS && v->type == VI_Real) *derivative(c, v) = 0.0;
    if (c->state == VI_ST_CONTINUOUS) return; /* Model Exchange reads its inputs at every evaluation */
    if (v->group == VI_GROUP_INPUTS || (c->state & (VI_ST_STEP_COMPLETE | VI_ST_EVENT))) MODEL->changed(c->model);
}

/* Is the value acceptable for v (checked before anything is stored)? Logs why not. */
static int acceptable(vi_core *c, const char *fn, const vi_variable *v, const void *values, vi_elem elem, size_t i)
{
    if (v->type == VI_String) {
        const char *s = ((const char *const *)values)[i];
        if (!s) return LOG_ERROR(c, "%s: the value of %s is NULL", fn, v->name), 0;
        size_t n = 0;
        while (n < VI_STRING_SIZE && s[n]) n++;
        if (n == VI_STRING_SIZE)
            return LOG_ERROR(c, "%s: the value of %s is longer than %d characters", fn, v->name, VI_STRING_SIZE - 1), 0;
        return 1;
    }
    if (v->type == VI_Real && !isfinite(elem_real(values, elem, i)))
        return LOG_ERROR(c, "%s: %s must be finite", fn, v->name), 0;
    char why[512];
    if (v->type != VI_Boolean &&
        check_range(v, v->type == VI_Real ? elem_real(values, elem, i) : (double)elem_int(values, elem, i), why,
                    sizeof why) < 0)
        return LOG_ERROR(c, "%s: %s; nothing was set", fn, why), 0;
    return 1;
}

vi_status vi_core_set(void *instance, const char *fn, const unsigned vr[], size_t nvr, vi_type api,
                      const void *values, vi_elem elem)
{
    ENTER(api == VI_Real ? VI_CALL_SET_REAL : VI_CALL_SET_DISCRETE);
    if (nvr > 0 && (!vr || !values)) return vi_core_refuse(c, "%s: NULL array", fn);
    for (size_t i = 0; i < nvr; i++) {
        if (is_time(c, vr[i])) return vi_core_refuse(c, "%s: time is the independent variable: it cannot be set", fn);
        if (indicator_of(c, vr[i]) >= 0)
            return vi_core_refuse(c, "%s: value reference %u is an event indicator: it cannot be set", fn, vr[i]);
        const vi_variable *in = api == VI_Real ? input_of_derivative(c, vr[i]) : NULL;
        if (in && !isfinite(elem_real(values, elem, i)))
            return vi_core_refuse(c, "%s: the derivative of %s must be finite", fn, in->name);
        if (in) continue;
        const vi_variable *v = lookup(c, fn, vr[i], api);
        if (!v || !settable(c, fn, v) || !acceptable(c, fn, v, values, elem, i)) return VI_STATUS_ERROR;
    }
    for (size_t i = 0; i < nvr; i++) {
        const vi_variable *in = api == VI_Real ? input_of_derivative(c, vr[i]) : NULL;
        if (in) { /* in the order given: a value set after its derivative resets it */
            *derivative(c, in) = elem_real(values, elem, i);
            MODEL->changed(c->model);
            continue;
        }
        const vi_variable *v = &MODEL->variables[vr[i]];
        void *p = storage(c, v);
        if (api == VI_String) {
            const char *s = ((const char *const *)values)[i];
            memmove(p, s, strlen(s) + 1); /* the value may be our own (from a get) */
        } else if (api == VI_Real) {
            *(double *)p = elem_real(values, elem, i);
        } else if (api == VI_Boolean) {
            *(int *)p = elem_int(values, elem, i) != 0; /* stored as 0 or 1 */
        } else {
            *(int *)p = (int)elem_int(values, elem, i);
        }
        changed(c, v);
    }
    return done(c);
}

vi_status vi_core_set_input_derivatives(void *instance, const char *fn, const unsigned vr[], size_t nvr,
                                        const int order[], const double values[])
{
    ENTER(VI_CALL_SET_INPUT_DERIVATIVES);
    if (c->kind != VI_KIND_CS)
        return vi_core_refuse(c, "%s: a Co-Simulation function; this instance is a Model Exchange one", fn);
    if (nvr > 0 && (!vr || !order || !values)) return vi_core_refuse(c, "%s: NULL array", fn);
    for (size_t i = 0; i < nvr; i++) {
        const vi_variable *v = lookup(c, fn, vr[i], VI_Real);
        if (!v) return VI_STATUS_ERROR;
        if (v->group != VI_GROUP_INPUTS || order[i] != 1 || !isfinite(values[i]))
            return vi_core_refuse(c, "%s: %s order %d = %g: only finite first derivatives of inputs", fn, v->name,
                                  order[i], values[i]);
    }
    for (size_t i = 0; i < nvr; i++) {
        *derivative(c, &MODEL->variables[vr[i]]) = values[i];
        MODEL->changed(c->model);
    }
    return done(c);
}

/* ---- FMU state -------------------------------------------------------------------------------- */

/* An FMU state: this header, then MODEL->state_size bytes of the model's plain data. It is taken
 * and restored in every FMI state but fatal; restoring puts the instance into the FMI state the
 * state was taken in. Serialized, it is the same bytes (for the same build of the FMU). Before a
 * state is used (set, serialized, deserialized) every part is checked: header, checksum, the
 * table's values, and the model's own fields (state_check hook); the first bad part is named. */
#define VI_STATE_MAGIC 0x554d4956u /* "VIMU" */
#define VI_STATE_VERSION 4u

typedef struct {
    uint32_t magic, version;
    uint64_t size;              /* bytes in all, this header included */
    uint64_t model;             /* hash (below) of the model's GUID: a state of another model is refused */
    uint32_t fmu_state;         /* the FMI state it was taken in (one VI_ST_* bit) */
    uint32_t stop_time_defined; /* the setup's stop time */
    double stop_time;
    uint64_t checksum;          /* hash (below) of all bytes, this field taken as 0 */
} vi_saved_state;

static size_t saved_size(void) { return sizeof(vi_saved_state) + MODEL->state_size; }
static void *payload(const vi_saved_state *s) { return (char *)s + sizeof *s; }

/* The hash behind model_id and checksum: the multiply-xor round of FNV-1a (Fowler, Noll, Vo: xor,
 * then multiply by the 64-bit FNV prime) applied to 64-bit words instead of bytes, each followed by
 * a xor-shift so that high bits feed back into low ones, in four interleaved lanes, the lanes and
 * the tail bytes folded in at the end. It is not FNV-1a itself (which goes byte by byte): a state of
 * a few kB costs a fraction of a microsecond. Every round is a bijection of its lane and of its
 * word, so any change of a single word (a single bit flip, say) changes the result. Start with
 * h = VI_FNV_OFFSET. */
#define VI_FNV_OFFSET 0xcbf29ce484222325u
#define VI_FNV_PRIME 0x100000001b3u
#define VI_HASH_LANES 4
static uint64_t hash_round(uint64_t h, uint64_t w)
{
    h = (h ^ w) * VI_FNV_PRIME;
    return h ^ (h >> 32);
}

static uint64_t state_hash(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    uint64_t lane[VI_HASH_LANES], w;
    for (int k = 0; k < VI_HASH_LANES; k++) lane[k] = hash_round(h, (uint64_t)k);
    size_t i = 0;
    for (; i + 8 * VI_HASH_LANES <= n; i += 8 * VI_HASH_LANES)
        for (int k = 0; k < VI_HASH_LANES; k++) {
            memcpy(&w, p + i + 8 * (size_t)k, sizeof w);
            lane[k] = hash_round(lane[k], w);
        }
    h = hash_round(lane[0], (uint64_t)n);
    for (int k = 1; k < VI_HASH_LANES; k++) h = hash_round(h, lane[k]);
    for (; i < n; i++) h = hash_round(h, p[i]);
    return h;
}

static uint64_t model_id(void) { return state_hash(VI_FNV_OFFSET, MODEL->guid, strlen(MODEL->guid)); }

static uint64_t checksum(const vi_saved_state *s)
{
    vi_saved_state head = *s;
    head.checksum = 0;
    return state_hash(state_hash(VI_FNV_OFFSET, &head, sizeof head), payload(s), MODEL->state_size);
}

/* The table's values in a saved block: what the setters guarantee (finite Reals inside their
 * ranges, Integers inside theirs, enumerations items of their type, Booleans 0 or 1, terminated
 * Strings). 0, or -1 with the first bad one. */
static int check_values(const void *block, char *msg, size_t n)
{
    for (int vr = 0; vr < MODEL->nvariables; vr++) {
        const vi_variable *v = &MODEL->variables[vr];
        if (v->group == VI_GROUP_OUTPUTS) continue;
        const char *p = (const char *)group_in(block, v->group) + v->offset;
        double x, dx;
        int k;
        switch (v->type) {
        case VI_Real:
            memcpy(&x, p, sizeof x);
            if (!isfinite(x)) VI_FAIL(msg, n, "%s = %g is not finite", v->name, x);
            if (check_range(v, x, msg, n) < 0) return -1;
            if (v->group != VI_GROUP_INPUTS) break;
            memcpy(&dx, (const char *)group_in(block, VI_GROUP_INPUT_DERIVATIVES) + v->offset, sizeof dx);
            if (!isfinite(dx)) VI_FAIL(msg, n, "the derivative of %s = %g is not finite", v->name, dx);
            break;
        case VI_String:
            if (!memchr(p, '\0', VI_STRING_SIZE)) VI_FAIL(msg, n, "%s is not a terminated string", v->name);
            break;
        default:
            memcpy(&k, p, sizeof k);
            if (v->type == VI_Boolean && k != 0 && k != 1)
                VI_FAIL(msg, n, "%s = %d is not a Boolean", v->name, k);
            if (v->type != VI_Boolean && check_range(v, k, msg, n) < 0) return -1;
        }
    }
    return 0;
}

/* Was the saved FMI state after initialization? Then VI_FMU_RUNNING_CS or _ME (the instance's interface). */
static int saved_running(const vi_core *c, const vi_saved_state *s)
{
    if (!(s->fmu_state & (VI_ST_RUNNING | VI_ST_ERROR))) return 0;
    return c->kind == VI_KIND_ME ? VI_FMU_RUNNING_ME : VI_FMU_RUNNING_CS;
}

/* The states an instance of this kind can be in. */
static unsigned kind_states(const vi_core *c)
{
    unsigned common = VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_TERMINATED | VI_ST_ERROR;
    return common | (c->kind == VI_KIND_ME ? VI_ST_EVENT | VI_ST_CONTINUOUS
                                           : VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED |
                                                 (c->face->cs_event_mode ? VI_ST_EVENT : 0u));
}

/* Is s (aligned, at least a header) a state of this FMU that may be used? Logs the first reason
 * why not. `size`: the bytes the caller has. */
static int check_saved(vi_core *c, const char *fn, const vi_saved_state *s, size_t size)
{
    char why[320] = "";
    if (!s) vi_snprintf(why, sizeof why, "the state is NULL");
    else if (s->magic != VI_STATE_MAGIC) vi_snprintf(why, sizeof why, "not an FMU state of this layer (magic number)");
    else if (s->version != VI_STATE_VERSION) vi_snprintf(why, sizeof why, "an FMU state of another layer version");
    else if (s->model != model_id()) vi_snprintf(why, sizeof why, "an FMU state of another model (GUID)");
    else if (s->size != saved_size() || size != saved_size())
        vi_snprintf(why, sizeof why, "size %zu bytes: a state of this build of %s has %zu", size, MODEL->model_identifier,
                    saved_size());
    else if (s->checksum != checksum(s)) vi_snprintf(why, sizeof why, "checksum mismatch: the state was altered");
    else if (!(s->fmu_state & VI_ST_ANY_BUT_FATAL) || (s->fmu_state & (s->fmu_state - 1u)))
        vi_snprintf(why, sizeof why, "field fmu_state = %u is not an FMI state", (unsigned)s->fmu_state);
    else if (!(s->fmu_state & kind_states(c)))
        vi_snprintf(why, sizeof why, "taken in state '%s', which an instance of this interface never is in",
                    state_name(s->fmu_state));
    else if (s->stop_time_defined > 1u || (s->stop_time_defined && !isfinite(s->stop_time)))
        vi_snprintf(why, sizeof why, "field stop_time is not finite");
    else if (check_values(payload(s), why, sizeof why) < 0 ||
             (MODEL->state_check && MODEL->state_check(payload(s), saved_running(c, s), why, sizeof why) < 0)) {
        if (!why[0]) vi_snprintf(why, sizeof why, "invalid field");
    }
    if (why[0]) LOG_ERROR(c, "%s: invalid FMU state: %s", fn, why);
    return why[0] == '\0';
}

vi_status vi_core_get_fmu_state(void *instance, const char *fn, void **state)
{
    ENTER(VI_CALL_FMU_STATE);
    if (!state) return vi_core_refuse(c, "%s: FMUstate is NULL", fn);
    if ((c->state & VI_ST_RUNNING) && MODEL->checkpoint && MODEL->checkpoint(c->model) != 0)
        return vi_core_fail(c, fn);
    vi_saved_state *s = *state ? *state : c->cb.alloc(1, saved_size());
    if (!s) return vi_core_refuse(c, "%s: out of memory", fn);
    *s = (vi_saved_state){.magic = VI_STATE_MAGIC, .version = VI_STATE_VERSION, .size = saved_size(),
                          .model = model_id(), .fmu_state = (uint32_t)c->state,
                          .stop_time_defined = (uint32_t)c->stop_time_defined, .stop_time = c->stop_time};
    memcpy(payload(s), MODEL->state(c->model), MODEL->state_size);
    s->checksum = checksum(s);
    *state = s;
    return done(c);
}

vi_status vi_core_set_fmu_state(void *instance, const char *fn, const void *state)
{
    ENTER(VI_CALL_FMU_STATE);
    const vi_saved_state *s = state;
    if (!check_saved(c, fn, s, s ? s->size : 0)) return VI_STATUS_ERROR;
    memcpy(MODEL->state(c->model), payload(s), MODEL->state_size);
    c->stop_time_defined = (int)s->stop_time_defined;
    c->stop_time = s->stop_time;
    c->state = s->fmu_state;
    c->event_passes = 0;
    c->initialized = saved_running(c, s) != 0;
    if (MODEL->restore && MODEL->restore(c->model, saved_running(c, s)) != 0) return vi_core_fail(c, fn);
    c->t_committed = MODEL->time(c->model);
    return done(c);
}

vi_status vi_core_free_fmu_state(void *instance, const char *fn, void **state)
{
    ENTER(VI_CALL_FMU_STATE);
    if (state && *state) {
        c->cb.free(*state);
        *state = NULL;
    }
    return done(c);
}

vi_status vi_core_fmu_state_size(void *instance, const char *fn, const void *state, size_t *size)
{
    ENTER(VI_CALL_FMU_STATE);
    if (!size) return vi_core_refuse(c, "%s: size is NULL", fn);
    const vi_saved_state *s = state;
    if (!check_saved(c, fn, s, s ? s->size : 0)) return VI_STATUS_ERROR;
    *size = saved_size();
    return done(c);
}

vi_status vi_core_serialize(void *instance, const char *fn, const void *state, unsigned char *bytes, size_t size)
{
    ENTER(VI_CALL_FMU_STATE);
    if (!bytes || size < saved_size())
        return vi_core_refuse(c, "%s: need a buffer of %zu bytes (got %zu)", fn, saved_size(), size);
    const vi_saved_state *s = state;
    if (!check_saved(c, fn, s, s ? s->size : 0)) return VI_STATUS_ERROR;
    memcpy(bytes, state, saved_size());
    return done(c);
}

vi_status vi_core_deserialize(void *instance, const char *fn, const unsigned char *bytes, size_t size, void **state)
{
    ENTER(VI_CALL_FMU_STATE);
    if (!bytes || !state) return vi_core_refuse(c, "%s: NULL argument", fn);
    if (size < sizeof(vi_saved_state) || size > saved_size())
        return vi_core_refuse(c, "%s: invalid FMU state: size %zu bytes: a state of this build of %s has %zu", fn, size,
                              MODEL->model_identifier, saved_size());
    vi_saved_state *s = c->cb.alloc(1, saved_size()); /* aligned, checked before it replaces anything */
    if (!s) return vi_core_refuse(c, "%s: out of memory", fn);
    memcpy(s, bytes, size);
    if (!check_saved(c, fn, s, size)) {
        c->cb.free(s);
        return VI_STATUS_ERROR;
    }
    if (*state) {
        memcpy(*state, s, saved_size());
        c->cb.free(s);
    } else {
        *state = s;
    }
    return done(c);
}

/* ---- Co-Simulation ---------------------------------------------------------------------------- */

/* A step's current communication point may differ from the FMU's time by this many units of the
 * time resolution (DBL_EPSILON max(1 s, |t|)); a step must advance time by at least VI_MIN_STEP_ULPS. */
#define VI_TIME_MATCH_ULPS 1e3
#define VI_MIN_STEP_ULPS 16.0

static vi_status do_step(void *instance, const char *fn, double tc, double h, int *event)
{
    ENTER(VI_CALL_DO_STEP);
    double t = MODEL->time(c->model);
    double unit = DBL_EPSILON * (fabs(t) > 1.0 ? fabs(t) : 1.0); /* the resolution of time here, at least that at 1 s */
    double t_end = tc + h;
    /* Refused arguments leave the instance as it was (fmi2Error from fmi2DoStep: "the step could
     * not be carried out at all"; the master may try another step). */
    if (!isfinite(tc) || !isfinite(h) || !(h > 0.0))
        return vi_core_refuse(c, "%s: the communication step size must be finite and positive (got %g)", fn, h);
    if (fabs(tc - t) > VI_TIME_MATCH_ULPS * unit)
        return vi_core_refuse(c, "%s: currentCommunicationPoint %.17g does not match the FMU's time %.17g", fn, tc, t);
    if (!(t_end - t >= VI_MIN_STEP_ULPS * unit))
        return vi_core_refuse(c, "%s: a step of %g s is too short to advance time at t = %.17g s: use at least %g s "
                                 "(%g units of the time resolution there); nothing was done",
                              fn, h, t, VI_MIN_STEP_ULPS * unit, VI_MIN_STEP_ULPS);
    if (c->stop_time_defined && t_end > c->stop_time + VI_TIME_MATCH_ULPS * unit)
        return vi_core_refuse(c, "%s: the step to %.17g passes the stop time %.17g", fn, t_end, c->stop_time);
    int rc = event && MODEL->advance_to_event ? MODEL->advance_to_event(c->model, t_end)
                                              : MODEL->advance(c->model, t_end);
    if (rc < 0) return vi_core_fail(c, fn);
    double t_now = MODEL->time(c->model);
    if ((rc == VI_FMU_OK && t_now != t_end) || (rc == VI_FMU_EVENT && !(event && t_now > t && t_now <= t_end))) {
        /* never OK for a step that did not happen */
        LOG_ERROR(c, "%s: the model stopped at t = %.17g s instead of %s %.17g s", fn, t_now,
                  rc == VI_FMU_EVENT ? "after the start and at most" : "", t_end);
        c->state = VI_ST_ERROR;
        return VI_STATUS_ERROR;
    }
    if (rc == VI_FMU_EVENT) {
        *event = 1;
        return done(c);
    }
    if (rc > 0) { /* stopped early at a consistent state: the last successful time tells where */
        vi_core_log(c, VI_STATUS_DISCARD, VI_CAT_DISCARD, "%s: %s", fn, MODEL->message(c->model));
        c->state = VI_ST_STEP_FAILED;
        return VI_STATUS_DISCARD;
    }
    return done(c);
}

vi_status vi_core_do_step(void *instance, const char *fn, double tc, double h) { return do_step(instance, fn, tc, h, NULL); }

vi_status vi_core_do_step_to_event(void *instance, const char *fn, double tc, double h, int *event)
{
    int stopped = 0;
    vi_status st = do_step(instance, fn, tc, h, &stopped);
    if (event) *event = stopped;
    return st;
}

/* ---- Model Exchange --------------------------------------------------------------------------- */

/* A Model Exchange call on an instance of the other interface, or an array of the wrong length. */
static int me_args(vi_core *c, const char *fn, const void *array, size_t n, size_t expected, const char *what)
{
    if (c->kind != VI_KIND_ME)
        return LOG_ERROR(c, "%s: a Model Exchange function; this instance is a Co-Simulation one", fn), 0;
    if (expected > 0 && !array) return LOG_ERROR(c, "%s: the array is NULL", fn), 0;
    if (n != expected)
        return LOG_ERROR(c, "%s: %zu %s given; %s has %zu", fn, n, what, MODEL->model_identifier, expected), 0;
    return 1;
}
#define ME_ARGS(array, n, expected, what) \
    if (!me_args(c, fn, array, n, expected, what)) return VI_STATUS_ERROR

vi_status vi_core_enter_event_mode(void *instance, const char *fn)
{
    ENTER(VI_CALL_ENTER_EVENT_MODE);
    if (c->kind == VI_KIND_CS) { /* Co-Simulation with Event Mode (FMI 3.0): from Step Mode */
        if (c->state != VI_ST_STEP_COMPLETE || !c->face->cs_event_mode)
            return vi_core_refuse(c, "%s: not allowed in state '%s'", fn, state_name(c->state));
        c->state = VI_ST_EVENT;
        return done(c);
    }
    ME_ARGS(NULL, 0, 0, "");
    if (c->state == VI_ST_CONTINUOUS) c->event_passes = 0;
    c->state = VI_ST_EVENT;
    c->t_committed = MODEL->time(c->model);
    return done(c);
}

vi_status vi_core_enter_step_mode(void *instance, const char *fn)
{
    ENTER(VI_CALL_ENTER_STEP_MODE);
    if (c->kind != VI_KIND_CS) return vi_core_refuse(c, "%s: only for Co-Simulation", fn);
    c->state = VI_ST_STEP_COMPLETE;
    return done(c);
}

vi_status vi_core_new_discrete_states(void *instance, const char *fn, vi_fmu_event *ev)
{
    ENTER(VI_CALL_NEW_DISCRETE_STATES);
    ME_ARGS(NULL, 0, 0, "");
    if (!ev) return vi_core_refuse(c, "%s: fmi2EventInfo is NULL", fn);
    memset(ev, 0, sizeof *ev);
    if (MODEL->event_update(c->model, ev) < 0) return vi_core_fail(c, fn);
    c->event_passes = ev->another_pass ? c->event_passes + 1 : 0;
    if (c->event_passes >= VI_MAX_EVENT_PASSES) {
        LOG_ERROR(c, "%s: the discrete states do not settle at t = %.17g s: %d passes of the event iteration in a row "
                     "each asked for another one (the state stays inconsistent with its mode: chattering); stopped",
                  fn, MODEL->time(c->model), VI_MAX_EVENT_PASSES);
        c->state = VI_ST_ERROR;
        return VI_STATUS_ERROR;
    }
    if (ev->next_time_defined && !(ev->next_time > MODEL->time(c->model))) ev->next_time_defined = 0;
    if (ev->terminate && c->cb.logger) { /* why the run ends: logged whatever is enabled */
        char text[1024];
        vi_snprintf(text, sizeof text, "%s: terminateSimulation: %s", fn, MODEL->message(c->model));
        emit_printable(c, VI_STATUS_WARNING, category_name(c, VI_CAT_WARNING), text);
        c->warned = 1;
    }
    c->t_committed = MODEL->time(c->model);
    return done(c);
}

vi_status vi_core_enter_continuous_mode(void *instance, const char *fn)
{
    ENTER(VI_CALL_ENTER_CONTINUOUS_MODE);
    ME_ARGS(NULL, 0, 0, "");
    if (MODEL->enter_continuous) MODEL->enter_continuous(c->model);
    c->state = VI_ST_CONTINUOUS;
    c->event_passes = 0;
    return done(c);
}

vi_status vi_core_completed_step(void *instance, const char *fn, int *enter_event, int *terminate)
{
    ENTER(VI_CALL_COMPLETED_STEP);
    ME_ARGS(NULL, 0, 0, "");
    if (!enter_event || !terminate) return vi_core_refuse(c, "%s: NULL argument", fn);
    *enter_event = MODEL->completed_step(c->model) != 0;
    *terminate = 0;
    c->t_committed = MODEL->time(c->model);
    return done(c);
}

vi_status vi_core_set_time(void *instance, const char *fn, double t)
{
    ENTER(VI_CALL_SET_TIME);
    ME_ARGS(NULL, 0, 0, "");
    if (!isfinite(t)) return vi_core_refuse(c, "%s: time %g is not finite", fn, t);
    if (t < c->t_committed)
        return vi_core_refuse(c, "%s: t = %.17g s lies before the last event or completed integrator step (%.17g s); "
                                 "time goes back only within the current step (restore an FMU state to go further)",
                              fn, t, c->t_committed);
    if (c->state == VI_ST_EVENT && t != MODEL->time(c->model))
        return vi_core_refuse(c, "%s: t = %.17g s in event mode, whose time is %.17g s: time moves in continuous-time "
                                 "mode only", fn, t, MODEL->time(c->model));
    MODEL->set_time(c->model, t);
    return done(c);
}

vi_status vi_core_set_states(void *instance, const char *fn, const double x[], size_t n)
{
    ENTER(VI_CALL_SET_STATES);
    ME_ARGS(x, n, (size_t)MODEL->n_states, "states");
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return vi_core_refuse(c, "%s: state %zu (%s) = %g is not finite; nothing was set", fn, i,
                                  MODEL->variables[MODEL->state_vrs[i]].name, x[i]);
    MODEL->set_states(c->model, x);
    return done(c);
}

/* A Model Exchange array the model filled: refused when an element is not finite (the error state of
 * an initialization that failed, say), naming it; else VI_STATUS_OK. */
static vi_status me_values(const vi_core *c, const char *fn, const double v[], size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return vi_core_refuse(c, "%s: element %zu = %g has no value in state '%s'", fn, i, v[i], state_name(c->state));
    return done(c);
}

vi_status vi_core_get_states(void *instance, const char *fn, double x[], size_t n)
{
    ENTER(VI_CALL_GET_STATES);
    ME_ARGS(x, n, (size_t)MODEL->n_states, "states");
    if (c->state == VI_ST_INIT && MODEL->prepare(c->model) < 0) return vi_core_refuse(c, "%s: %s", fn, MODEL->message(c->model));
    MODEL->get_states(c->model, x);
    return me_values(c, fn, x, n);
}

vi_status vi_core_get_derivatives(void *instance, const char *fn, double dx[], size_t n)
{
    ENTER(VI_CALL_GET_DERIVATIVES);
    ME_ARGS(dx, n, (size_t)MODEL->n_states, "derivatives");
    MODEL->derivatives(c->model, dx);
    return me_values(c, fn, dx, n);
}

vi_status vi_core_get_event_indicators(void *instance, const char *fn, double z[], size_t n)
{
    ENTER(VI_CALL_GET_EVENT_INDICATORS);
    ME_ARGS(z, n, (size_t)MODEL->n_indicators, "event indicators");
    if (n == 0) return done(c);
    if (c->state == VI_ST_INIT && MODEL->prepare(c->model) < 0) return vi_core_refuse(c, "%s: %s", fn, MODEL->message(c->model));
    MODEL->indicators(c->model, z);
    return me_values(c, fn, z, n);
}

vi_status vi_core_get_nominals(void *instance, const char *fn, double nominal[], size_t n)
{
    ENTER(VI_CALL_GET_NOMINALS);
    ME_ARGS(nominal, n, (size_t)MODEL->n_states, "nominals");
    MODEL->nominals(c->model, nominal);
    return me_values(c, fn, nominal, n);
}

/* Is vr a state of the model (its index in state order), or -1? */
static int state_index(unsigned vr)
{
    for (int i = 0; i < MODEL->n_states; i++)
        if (MODEL->state_vrs[i] == vr) return i;
    return -1;
}

vi_status vi_core_directional_derivative(void *instance, const char *fn, const unsigned unknown[], size_t n_unknown,
                                         const unsigned known[], size_t n_known, const double dknown[],
                                         double dunknown[])
{
    ENTER(VI_CALL_DIRECTIONAL_DERIVATIVE);
    if (c->kind != VI_KIND_ME || !MODEL->directional_derivative)
        return vi_core_refuse(c, "%s: not provided (providesDirectionalDerivative=false%s)", fn,
                              c->kind != VI_KIND_ME ? " in Co-Simulation" : "");
    if ((n_unknown > 0 && (!unknown || !dunknown)) || (n_known > 0 && (!known || !dknown)))
        return vi_core_refuse(c, "%s: NULL array", fn);
    for (size_t i = 0; i < n_unknown; i++) {
        const vi_variable *v = lookup(c, fn, unknown[i], VI_Real);
        if (!v) return VI_STATUS_ERROR;
        int is_derivative = 0;
        for (int k = 0; k < MODEL->n_states; k++) is_derivative |= MODEL->derivative_vrs[k] == unknown[i];
        if (!is_derivative && v->group != VI_GROUP_OUTPUTS)
            return vi_core_refuse(c, "%s: unknown %s is neither a state derivative nor an output", fn, v->name);
    }
    for (size_t i = 0; i < n_known; i++) {
        const vi_variable *v = lookup(c, fn, known[i], VI_Real);
        if (!v) return VI_STATUS_ERROR;
        if (state_index(known[i]) < 0 && v->group != VI_GROUP_INPUTS)
            return vi_core_refuse(c, "%s: known %s is neither a state nor an input", fn, v->name);
        if (!isfinite(dknown[i])) return vi_core_refuse(c, "%s: the seed of %s is not finite", fn, v->name);
    }
    if (c->state == VI_ST_INIT && MODEL->prepare(c->model) < 0) return vi_core_refuse(c, "%s: %s", fn, MODEL->message(c->model));
    if (MODEL->directional_derivative(c->model, unknown, n_unknown, known, n_known, dknown, dunknown) < 0)
        return vi_core_refuse(c, "%s: %s", fn, MODEL->message(c->model));
    for (size_t i = 0; i < n_unknown; i++) /* a large seed times a steep slope overflows */
        if (!isfinite(dunknown[i]))
            return vi_core_refuse(c, "%s: the derivative of %s along the seeds of %s%s is %g, not finite: scale the "
                                     "seeds down", fn, MODEL->variables[unknown[i]].name,
                                  n_known ? MODEL->variables[known[0]].name : "no known", n_known > 1 ? ", ..." : "",
                                  dunknown[i]);
    return done(c);
}
