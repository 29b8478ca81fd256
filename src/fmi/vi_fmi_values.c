/*
 * vi_fmi_values.c - the FMI layer's value access through the model's variable table (vi_table.h):
 * get and set with every check (type, settable now, finite, inside the table's range or an item of
 * the enumeration, String length) made before anything is stored, and the inputs' derivatives.
 */
#include "vi_fmi_layer_internal.h"

#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <string.h>

/* The struct of a group inside a plain-data block of the model (NULL for outputs). */
void *vi_fmi_group_in(const void *block, vi_group group)
{
    switch (group) {
    case VI_GROUP_PARAMETERS: return (char *)block + MODEL->parameters_offset;
    case VI_GROUP_INPUTS: return (char *)block + MODEL->inputs_offset;
    case VI_GROUP_INPUT_DERIVATIVES: return (char *)block + MODEL->input_derivatives_offset;
    default: return NULL;
    }
}

/* Where the value of v lives; NULL for outputs (computed on demand). */
static void *storage(vi_fmi_instance *c, const vi_variable *v)
{
    if (v->group == VI_GROUP_OUTPUTS) return NULL;
    return (char *)vi_fmi_group_in(MODEL->state(c->model), v->group) + v->offset;
}

/* The derivative of the Real input v. */
static double *derivative(vi_fmi_instance *c, const vi_variable *v)
{
    return (double *)((char *)vi_fmi_group_in(MODEL->state(c->model), VI_GROUP_INPUT_DERIVATIVES) + v->offset);
}

/* The variable behind vr if it is accessed through the API type `api` (Real, Integer or Boolean;
 * enumerations go through Integer); NULL (logged) otherwise. */
const vi_variable *vi_fmi_lookup(vi_fmi_instance *c, const char *fn, unsigned vr, vi_type api)
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

/* The row of vr when it is a Real of the table read as a Real (vi_fmi_lookup's answer without its
 * call, for the common read of outputs), else NULL: vi_fmi_lookup decides and logs. */
static inline const vi_variable *real_row(unsigned vr, vi_type api)
{
    if (api != VI_Real || vr >= (unsigned)MODEL->nvariables) return NULL;
    const vi_variable *v = &MODEL->variables[vr];
    return v->type == VI_Real ? v : NULL;
}

/* Is vr the independent variable time of the face? */
static int is_time(const vi_fmi_instance *c, unsigned vr) { return c->face->has_time && vr == c->face->time_vr; }

/* Is vr an event indicator of the face (its index), else -1? */
static int indicator_of(const vi_fmi_instance *c, unsigned vr)
{
    if (!c->face->has_indicator_vrs || vr < c->face->indicator_vr_base) return -1;
    unsigned i = vr - c->face->indicator_vr_base;
    return i < (unsigned)MODEL->n_indicators ? (int)i : -1;
}

/* The Real input whose derivative has the value reference vr in the face, else NULL. */
static const vi_variable *input_of_derivative(const vi_fmi_instance *c, unsigned vr)
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
static inline const void *current_outputs(vi_fmi_instance *c, const char *fn, const unsigned vr[], size_t nvr)
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

vi_status vi_fmi_get(void *instance, const char *fn, const unsigned vr[], size_t nvr, vi_type api, void *values,
                      vi_elem elem)
{
    ENTER(VI_CALL_GET);
    if (nvr > 0 && (!vr || !values)) return vi_fmi_refuse(c, "%s: NULL array", fn);
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
                    return vi_fmi_refuse(c, "%s: value reference %u is an event indicator this model cannot evaluate",
                                          fn, vr[i]);
                if (!outs && !(outs = current_outputs(c, fn, vr, nvr))) return VI_STATUS_ERROR;
                MODEL->indicators(c->model, z);
                elem_store(values, elem, i, z[k], 0);
                continue;
            }
        }
        const vi_variable *v = real_row(vr[i], api);
        if (!v && !(v = vi_fmi_lookup(c, fn, vr[i], api))) return VI_STATUS_ERROR;
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
            return vi_fmi_refuse(c, "%s: %s = %g has no value in state '%s'", fn, v->name, *(const double *)p,
                                  vi_fmi_state_name(c->state));
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
int vi_fmi_check_range(const vi_variable *v, double x, char *msg, size_t n)
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
static int settable(vi_fmi_instance *c, const char *fn, const vi_variable *v)
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
static void changed(vi_fmi_instance *c, const vi_variable *v)
{
    if (v->group == VI_GROUP_INPUTS && v->type == VI_Real) *derivative(c, v) = 0.0;
    if (c->state == VI_ST_CONTINUOUS) return; /* Model Exchange reads its inputs at every evaluation */
    if (v->group == VI_GROUP_INPUTS || (c->state & (VI_ST_STEP_COMPLETE | VI_ST_EVENT))) MODEL->changed(c->model);
}

/* Is the value acceptable for v (checked before anything is stored)? Logs why not. */
static int acceptable(vi_fmi_instance *c, const char *fn, const vi_variable *v, const void *values, vi_elem elem, size_t i)
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
        vi_fmi_check_range(v, v->type == VI_Real ? elem_real(values, elem, i) : (double)elem_int(values, elem, i), why,
                    sizeof why) < 0)
        return LOG_ERROR(c, "%s: %s; nothing was set", fn, why), 0;
    return 1;
}

vi_status vi_fmi_set(void *instance, const char *fn, const unsigned vr[], size_t nvr, vi_type api,
                      const void *values, vi_elem elem)
{
    ENTER(api == VI_Real ? VI_CALL_SET_REAL : VI_CALL_SET_DISCRETE);
    if (nvr > 0 && (!vr || !values)) return vi_fmi_refuse(c, "%s: NULL array", fn);
    for (size_t i = 0; i < nvr; i++) {
        if (is_time(c, vr[i])) return vi_fmi_refuse(c, "%s: time is the independent variable: it cannot be set", fn);
        if (indicator_of(c, vr[i]) >= 0)
            return vi_fmi_refuse(c, "%s: value reference %u is an event indicator: it cannot be set", fn, vr[i]);
        const vi_variable *in = api == VI_Real ? input_of_derivative(c, vr[i]) : NULL;
        if (in && !isfinite(elem_real(values, elem, i)))
            return vi_fmi_refuse(c, "%s: the derivative of %s must be finite", fn, in->name);
        if (in) continue;
        const vi_variable *v = vi_fmi_lookup(c, fn, vr[i], api);
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

vi_status vi_fmi_set_input_derivatives(void *instance, const char *fn, const unsigned vr[], size_t nvr,
                                        const int order[], const double values[])
{
    ENTER(VI_CALL_SET_INPUT_DERIVATIVES);
    if (c->kind != VI_KIND_CS)
        return vi_fmi_refuse(c, "%s: a Co-Simulation function; this instance is a Model Exchange one", fn);
    if (nvr > 0 && (!vr || !order || !values)) return vi_fmi_refuse(c, "%s: NULL array", fn);
    for (size_t i = 0; i < nvr; i++) {
        const vi_variable *v = vi_fmi_lookup(c, fn, vr[i], VI_Real);
        if (!v) return VI_STATUS_ERROR;
        if (v->group != VI_GROUP_INPUTS || order[i] != 1 || !isfinite(values[i]))
            return vi_fmi_refuse(c, "%s: %s order %d = %g: only finite first derivatives of inputs", fn, v->name,
                                  order[i], values[i]);
    }
    for (size_t i = 0; i < nvr; i++) {
        *derivative(c, &MODEL->variables[vr[i]]) = values[i];
        MODEL->changed(c->model);
    }
    return done(c);
}
