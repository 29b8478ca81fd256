/*
 * vi_fmi_model_exchange.c - the FMI layer's Model Exchange calls: event mode and the event iteration,
 * continuous-time mode, time, states, derivatives, event indicators, nominals and directional
 * derivatives, on the model's Model Exchange hooks.
 */
#include "vi_fmi_layer_internal.h"

#include <math.h>
#include <string.h>

/* A Model Exchange call on an instance of the other interface, or an array of the wrong length. */
static int me_args(vi_fmi_instance *c, const char *fn, const void *array, size_t n, size_t expected, const char *what)
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

vi_status vi_fmi_enter_event_mode(void *instance, const char *fn)
{
    ENTER(VI_CALL_ENTER_EVENT_MODE);
    if (c->kind == VI_KIND_CS) { /* Co-Simulation with Event Mode (FMI 3.0): from Step Mode */
        if (c->state != VI_ST_STEP_COMPLETE || !c->face->cs_event_mode)
            return vi_fmi_refuse(c, "%s: not allowed in state '%s'", fn, vi_fmi_state_name(c->state));
        c->state = VI_ST_EVENT;
        return done(c);
    }
    ME_ARGS(NULL, 0, 0, "");
    if (c->state == VI_ST_CONTINUOUS) c->event_passes = 0;
    c->state = VI_ST_EVENT;
    c->t_committed = MODEL->time(c->model);
    return done(c);
}

vi_status vi_fmi_enter_step_mode(void *instance, const char *fn)
{
    ENTER(VI_CALL_ENTER_STEP_MODE);
    if (c->kind != VI_KIND_CS) return vi_fmi_refuse(c, "%s: only for Co-Simulation", fn);
    c->state = VI_ST_STEP_COMPLETE;
    return done(c);
}

vi_status vi_fmi_new_discrete_states(void *instance, const char *fn, vi_fmu_event *ev)
{
    ENTER(VI_CALL_NEW_DISCRETE_STATES);
    ME_ARGS(NULL, 0, 0, "");
    if (!ev) return vi_fmi_refuse(c, "%s: fmi2EventInfo is NULL", fn);
    memset(ev, 0, sizeof *ev);
    if (MODEL->event_update(c->model, ev) < 0) return vi_fmi_fail(c, fn);
    c->event_passes = ev->another_pass ? c->event_passes + 1 : 0;
    if (c->event_passes >= VI_MAX_EVENT_PASSES) {
        LOG_ERROR(c, "%s: the discrete states do not settle at t = %.17g s: %d passes of the event iteration in a row "
                     "each asked for another one (the state stays inconsistent with its mode: chattering); stopped",
                  fn, MODEL->time(c->model), VI_MAX_EVENT_PASSES);
        c->state = VI_ST_ERROR;
        return VI_STATUS_ERROR;
    }
    if (ev->next_time_defined && !(ev->next_time > MODEL->time(c->model))) ev->next_time_defined = 0;
    /* the run ends before the time asked for: why, logged whatever is enabled, and a Warning status */
    if (ev->terminate) vi_fmi_warn_result(c, "%s: terminateSimulation: %s", fn, MODEL->message(c->model));
    c->t_committed = MODEL->time(c->model);
    return done(c);
}

vi_status vi_fmi_enter_continuous_mode(void *instance, const char *fn)
{
    ENTER(VI_CALL_ENTER_CONTINUOUS_MODE);
    ME_ARGS(NULL, 0, 0, "");
    if (MODEL->enter_continuous) MODEL->enter_continuous(c->model);
    c->state = VI_ST_CONTINUOUS;
    c->event_passes = 0;
    return done(c);
}

vi_status vi_fmi_completed_step(void *instance, const char *fn, int *enter_event, int *terminate)
{
    ENTER(VI_CALL_COMPLETED_STEP);
    ME_ARGS(NULL, 0, 0, "");
    if (!enter_event || !terminate) return vi_fmi_refuse(c, "%s: NULL argument", fn);
    *enter_event = MODEL->completed_step(c->model) != 0;
    *terminate = 0;
    c->t_committed = MODEL->time(c->model);
    return done(c);
}

vi_status vi_fmi_set_time(void *instance, const char *fn, double t)
{
    ENTER(VI_CALL_SET_TIME);
    ME_ARGS(NULL, 0, 0, "");
    if (!isfinite(t)) return vi_fmi_refuse(c, "%s: time %g is not finite", fn, t);
    if (t < c->t_committed)
        return vi_fmi_refuse(c, "%s: t = %.17g s lies before the last event or completed integrator step (%.17g s); "
                                 "time goes back only within the current step (restore an FMU state to go further)",
                              fn, t, c->t_committed);
    if (c->state == VI_ST_EVENT && t != MODEL->time(c->model))
        return vi_fmi_refuse(c, "%s: t = %.17g s in event mode, whose time is %.17g s: time moves in continuous-time "
                                 "mode only", fn, t, MODEL->time(c->model));
    MODEL->set_time(c->model, t);
    return done(c);
}

vi_status vi_fmi_set_states(void *instance, const char *fn, const double x[], size_t n)
{
    ENTER(VI_CALL_SET_STATES);
    ME_ARGS(x, n, (size_t)MODEL->n_states, "states");
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return vi_fmi_refuse(c, "%s: state %zu (%s) = %g is not finite; nothing was set", fn, i,
                                  MODEL->variables[MODEL->state_vrs[i]].name, x[i]);
    MODEL->set_states(c->model, x);
    return done(c);
}

/* A Model Exchange array the model filled: refused when an element is not finite (the error state of
 * an initialization that failed, say), naming it; else VI_STATUS_OK. */
static vi_status me_values(const vi_fmi_instance *c, const char *fn, const double v[], size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return vi_fmi_refuse(c, "%s: element %zu = %g has no value in state '%s'", fn, i, v[i], vi_fmi_state_name(c->state));
    return done(c);
}

vi_status vi_fmi_get_states(void *instance, const char *fn, double x[], size_t n)
{
    ENTER(VI_CALL_GET_STATES);
    ME_ARGS(x, n, (size_t)MODEL->n_states, "states");
    if (c->state == VI_ST_INIT && MODEL->prepare(c->model) < 0) return vi_fmi_refuse(c, "%s: %s", fn, MODEL->message(c->model));
    MODEL->get_states(c->model, x);
    return me_values(c, fn, x, n);
}

vi_status vi_fmi_get_derivatives(void *instance, const char *fn, double dx[], size_t n)
{
    ENTER(VI_CALL_GET_DERIVATIVES);
    ME_ARGS(dx, n, (size_t)MODEL->n_states, "derivatives");
    MODEL->derivatives(c->model, dx);
    return me_values(c, fn, dx, n);
}

vi_status vi_fmi_get_event_indicators(void *instance, const char *fn, double z[], size_t n)
{
    ENTER(VI_CALL_GET_EVENT_INDICATORS);
    ME_ARGS(z, n, (size_t)MODEL->n_indicators, "event indicators");
    if (n == 0) return done(c);
    if (c->state == VI_ST_INIT && MODEL->prepare(c->model) < 0) return vi_fmi_refuse(c, "%s: %s", fn, MODEL->message(c->model));
    MODEL->indicators(c->model, z);
    return me_values(c, fn, z, n);
}

vi_status vi_fmi_get_nominals(void *instance, const char *fn, double nominal[], size_t n)
{
    ENTER(VI_CALL_GET_NOMINALS);
    ME_ARGS(nominal, n, (size_t)MODEL->n_states, "nominals");
    MODEL->nominals(c->model, nominal);
    return me_values(c, fn, nominal, n);
}

vi_status vi_fmi_me_count(void *instance, const char *fn, int which, size_t *count)
{
    ENTER(VI_CALL_GET_STATES);
    ME_ARGS(NULL, 0, 0, "");
    if (!count) return vi_fmi_refuse(c, "%s: NULL argument", fn);
    *count = (size_t)(which == VI_COUNT_STATES ? MODEL->n_states : MODEL->n_indicators);
    return done(c);
}

/* Is vr a state of the model (its index in state order), or -1? */
static int state_index(unsigned vr)
{
    for (int i = 0; i < MODEL->n_states; i++)
        if (MODEL->state_vrs[i] == vr) return i;
    return -1;
}

vi_status vi_fmi_directional_derivative(void *instance, const char *fn, const unsigned unknown[], size_t n_unknown,
                                         const unsigned known[], size_t n_known, const double dknown[],
                                         double dunknown[])
{
    ENTER(VI_CALL_DIRECTIONAL_DERIVATIVE);
    if (c->kind != VI_KIND_ME || !MODEL->directional_derivative)
        return vi_fmi_refuse(c, "%s: not provided (providesDirectionalDerivative=false%s)", fn,
                              c->kind != VI_KIND_ME ? " in Co-Simulation" : "");
    if ((n_unknown > 0 && (!unknown || !dunknown)) || (n_known > 0 && (!known || !dknown)))
        return vi_fmi_refuse(c, "%s: NULL array", fn);
    for (size_t i = 0; i < n_unknown; i++) {
        const vi_variable *v = vi_fmi_lookup(c, fn, unknown[i], VI_Real);
        if (!v) return VI_STATUS_ERROR;
        int is_derivative = 0;
        for (int k = 0; k < MODEL->n_states; k++) is_derivative |= MODEL->derivative_vrs[k] == unknown[i];
        if (!is_derivative && v->group != VI_GROUP_OUTPUTS)
            return vi_fmi_refuse(c, "%s: unknown %s is neither a state derivative nor an output", fn, v->name);
    }
    for (size_t i = 0; i < n_known; i++) {
        const vi_variable *v = vi_fmi_lookup(c, fn, known[i], VI_Real);
        if (!v) return VI_STATUS_ERROR;
        if (state_index(known[i]) < 0 && v->group != VI_GROUP_INPUTS)
            return vi_fmi_refuse(c, "%s: known %s is neither a state nor an input", fn, v->name);
        if (!isfinite(dknown[i])) return vi_fmi_refuse(c, "%s: the seed of %s is not finite", fn, v->name);
    }
    if (c->state == VI_ST_INIT && MODEL->prepare(c->model) < 0) return vi_fmi_refuse(c, "%s: %s", fn, MODEL->message(c->model));
    if (MODEL->directional_derivative(c->model, unknown, n_unknown, known, n_known, dknown, dunknown) < 0)
        return vi_fmi_refuse(c, "%s: %s", fn, MODEL->message(c->model));
    for (size_t i = 0; i < n_unknown; i++) /* a large seed times a steep slope overflows */
        if (!isfinite(dunknown[i]))
            return vi_fmi_refuse(c, "%s: the derivative of %s along the seeds of %s%s is %g, not finite: scale the "
                                     "seeds down", fn, MODEL->variables[unknown[i]].name,
                                  n_known ? MODEL->variables[known[0]].name : "no known", n_known > 1 ? ", ..." : "",
                                  dunknown[i]);
    return done(c);
}
