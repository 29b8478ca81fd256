/*
 * calls_fmi2me.c - the call kinds of FMI 2.0 Model Exchange for the harness (fuzz.h; codes 40-59).
 * An instance is made Model Exchange by fmi2Instantiate with fmi2ModelExchange (calls_fmi2.c); the
 * common functions (values, FMU states, initialization) are those of calls_fmi2.c, which checks them
 * against the Model Exchange state machine as well.
 *
 * Arrays are passed with exactly the length given (heap), so that AddressSanitizer sees a write
 * beyond it; lengths are the model's numbers of states and indicators (vi_fmu_this_model), one more
 * or one less, zero, or eight. Beyond the sanitizers, the watchdog and the logger's checks:
 *   - the state machine of FMI 2.0 Model Exchange (section 3.2.3): each call returns fmi2OK only in
 *     a state that allows it, never for a Co-Simulation instance (fz_outcome2);
 *   - with fmi2OK, states, derivatives and indicators are finite, nominals finite and positive;
 *   - the event iteration settles: a pass of fmi2NewDiscreteStates that returns fmi2OK and asks
 *     for another after FZ_EVENT_PASS_BOUND such passes in a row is a finding;
 *   - the call order in Continuous-Time Mode does not matter (fz_call_order, order.c).
 * The kind "Euler step" makes the calls an explicit-Euler importer makes for one step, so that the
 * fuzzer reaches events and mode changes without having to find the sequence byte by byte.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"

#define MODEL (&vi_fmu_this_model)
#define outcome fz_outcome2

/* The states in which each Model Exchange function is allowed (FMI 2.0, section 3.2.3). */
#define ME_EVENT_OR_CT (FZ_EVENT | FZ_CONTINUOUS)
#define ME_AFTER_INIT (FZ_EVENT | FZ_CONTINUOUS | FZ_TERMINATED | FZ_ERROR) /* fmi2GetDerivatives */
#define ME_FROM_INIT (FZ_INIT | ME_AFTER_INIT) /* fmi2GetEventIndicators, fmi2GetContinuousStates */
#define ME_NOMINALS (FZ_INSTANTIATED | ME_AFTER_INIT)
#define ME_WRITABLE_INPUT (FZ_INSTANTIATED | FZ_INIT | FZ_EVENT | FZ_CONTINUOUS) /* a continuous Real input */

static fmi2Status ended(const char *call, fmi2Status st)
{
    fz_end();
    fz_trace("    -> %d", (int)st);
    return fz_status(call, st);
}
#define CALL(fn, ...) ended(#fn, (fz_begin(#fn), fn(__VA_ARGS__)))

static int me_available(void) { return MODEL->n_states > 0; }

/* A length around n (the model's count): n, n + 1, n - 1, 0 or 8. */
static size_t length(fz_reader *r, int n)
{
    static const int delta[] = {0, 0, 0, 0, 0, 1, -1};
    uint8_t k = fz_u8(r);
    if (k % 8 == 7) return k >= 128 ? 8 : 0;
    int m = n + delta[k % 7];
    return m > 0 ? (size_t)m : 0;
}

static double *array(size_t n) { return calloc(n ? n : 1, sizeof(double)); }

/* A Model Exchange function: never fmi2OK for a Co-Simulation instance. */
static unsigned me_only(const fz_slot *s, unsigned allowed) { return fz_by_type(s, 0u, allowed); }

/* With fmi2OK or fmi2Warning (values given) every element finite (and positive: nominals). */
static void finite(const char *call, fmi2Status st, const double *x, size_t n, int positive)
{
    if (st != fmi2OK && st != fmi2Warning) return;
    fz_finite(call, x, n);
    for (size_t i = 0; positive && i < n; i++)
        if (!(x[i] > 0.0)) fz_fail("%s returned fmi2OK with element %zu = %g, not positive", call, i, x[i]);
}

/* The calls of the kinds below, each with its outcome checked. */
static fmi2Status set_time(fz_slot *s, double t)
{
    fmi2Status st = CALL(fmi2SetTime, s->c, t);
    outcome(s, "fmi2SetTime", me_only(s, ME_EVENT_OR_CT), st, 0);
    if (st == fmi2OK) s->t = t;
    return st;
}

static fmi2Status set_states(fz_slot *s, const double *x, size_t n)
{
    fmi2Status st = CALL(fmi2SetContinuousStates, s->c, x, n);
    outcome(s, "fmi2SetContinuousStates", me_only(s, FZ_CONTINUOUS), st, 0);
    return st;
}

static fmi2Status get_states(fz_slot *s, double *x, size_t n)
{
    fmi2Status st = CALL(fmi2GetContinuousStates, s->c, x, n);
    outcome(s, "fmi2GetContinuousStates", me_only(s, ME_FROM_INIT), st, 0);
    finite("fmi2GetContinuousStates", st, x, n, 0);
    return st;
}

static fmi2Status derivatives(fz_slot *s, double *dx, size_t n)
{
    fmi2Status st = CALL(fmi2GetDerivatives, s->c, dx, n);
    outcome(s, "fmi2GetDerivatives", me_only(s, ME_AFTER_INIT), st, 0);
    finite("fmi2GetDerivatives", st, dx, n, 0);
    return st;
}

static fmi2Status indicators(fz_slot *s, double *z, size_t n)
{
    fmi2Status st = CALL(fmi2GetEventIndicators, s->c, z, n);
    outcome(s, "fmi2GetEventIndicators", me_only(s, ME_FROM_INIT), st, 0);
    finite("fmi2GetEventIndicators", st, z, n, 0);
    return st;
}

static fmi2Status enter_event_mode(fz_slot *s)
{
    fmi2Status st = CALL(fmi2EnterEventMode, s->c);
    outcome(s, "fmi2EnterEventMode", me_only(s, ME_EVENT_OR_CT), st, FZ_EVENT);
    return st;
}

static fmi2Status enter_continuous(fz_slot *s)
{
    fmi2Status st = CALL(fmi2EnterContinuousTimeMode, s->c);
    outcome(s, "fmi2EnterContinuousTimeMode", me_only(s, FZ_EVENT), st, FZ_CONTINUOUS);
    return st;
}

static fmi2Status completed_step(fz_slot *s, int no_prior, fmi2Boolean *enter, fmi2Boolean *terminate)
{
    fmi2Status st = CALL(fmi2CompletedIntegratorStep, s->c, no_prior, enter, terminate);
    outcome(s, "fmi2CompletedIntegratorStep", me_only(s, FZ_CONTINUOUS), st, 0);
    return st;
}

static double time_arg(fz_reader *r, double t)
{
    uint8_t k = fz_u8(r);
    static const double dt[] = {0.0, 1e-9, 1e-6, 1e-4, 1e-3, 1e-2, -1e-6, 1.0};
    return k < 224 ? t + dt[k % 8] : fz_real(r, 1e-3);
}

static void k_set_time(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    double t = time_arg(r, isnan(s->t) ? 0.0 : s->t);
    fz_trace("    t %.17g", t);
    if (set_time(s, t) == fmi2OK && !isfinite(t)) fz_fail("fmi2SetTime accepted t = %g", t);
}

static void k_set_states(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    size_t n = length(r, MODEL->n_states);
    double *x = array(n);
    if (fz_u8(r) & 1) { /* near the current states */
        double *now = array(n);
        if (get_states(s, now, n) == fmi2OK) memcpy(x, now, n * sizeof *x);
        free(now);
    }
    int finite_x = 1;
    for (size_t i = 0; i < n; i++) {
        uint8_t how = fz_u8(r);
        x[i] = how < 128 ? x[i] * (1.0 + (int8_t)fz_u8(r) / 1024.0) : fz_real(r, x[i] != 0.0 ? x[i] : 1e-4);
        finite_x &= isfinite(x[i]) != 0;
        fz_trace("    x[%zu] = %.17g", i, x[i]);
    }
    int null_x = fz_u8(r) == 255;
    if (set_states(s, null_x ? NULL : x, n) == fmi2OK && (!finite_x || (null_x && n > 0)))
        fz_fail("fmi2SetContinuousStates accepted a state that is not finite, or NULL");
    free(x);
}

/* fmi2GetDerivatives, fmi2GetEventIndicators, fmi2GetContinuousStates, fmi2GetNominalsOfContinuousStates */
static void k_get_arrays(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t which = fz_u8(r) % 4;
    size_t n = length(r, which == 1 ? MODEL->n_indicators : MODEL->n_states);
    double *x = array(n);
    fmi2Real *arg = fz_u8(r) == 255 ? NULL : x;
    switch (which) {
    case 0: derivatives(s, arg, n); break;
    case 1: indicators(s, arg, n); break;
    case 2: get_states(s, arg, n); break;
    default: {
        fmi2Status st = CALL(fmi2GetNominalsOfContinuousStates, s->c, arg, n);
        outcome(s, "fmi2GetNominalsOfContinuousStates", me_only(s, ME_NOMINALS), st, 0);
        finite("fmi2GetNominalsOfContinuousStates", st, x, n, 1);
    }
    }
    free(x);
}

static void k_enter_event(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    enter_event_mode(s);
}

/* The event iteration: fmi2NewDiscreteStates until no new discrete states are needed, at most
 * `passes` times. Passes in a row that return fmi2OK and ask for another: the FMU stops the run
 * with an error at FZ_EVENT_PASS_BOUND of them, so one more is a finding. */
static void event_iteration(fz_slot *s, int passes)
{
    for (int k = 0; k < passes && k <= FZ_EVENT_PASS_BOUND; k++) {
        fmi2EventInfo ev;
        memset(&ev, 0, sizeof ev);
        fmi2Status st = CALL(fmi2NewDiscreteStates, s->c, &ev);
        outcome(s, "fmi2NewDiscreteStates", me_only(s, FZ_EVENT), st, 0);
        if (st != fmi2OK || !ev.newDiscreteStatesNeeded || ev.terminateSimulation) return;
        if (k + 1 >= FZ_EVENT_PASS_BOUND)
            fz_fail("the event iteration does not settle: %d passes of fmi2NewDiscreteStates in a row returned fmi2OK "
                    "and asked for another (the FMU documents an error at %d)", k + 1, FZ_EVENT_PASS_BOUND);
    }
}

static void k_new_discrete_states(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t k = fz_u8(r);
    if (k == 255) {
        outcome(s, "fmi2NewDiscreteStates", me_only(s, FZ_EVENT), CALL(fmi2NewDiscreteStates, s->c, NULL), 0);
        return;
    }
    event_iteration(s, k % 8 == 7 ? FZ_EVENT_PASS_BOUND : 1 + k % 4);
}

static void k_enter_continuous(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    enter_continuous(s);
}

static void k_completed_step(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t k = fz_u8(r);
    fmi2Boolean enter = fmi2False, terminate = fmi2False;
    completed_step(s, k & 1, k & 2 ? NULL : &enter, k & 4 ? NULL : &terminate);
}

/* ---- the call-order property (order.c) through the FMI 2.0 functions ---- */

static int o_set_time(fz_slot *s, double t) { return (int)set_time(s, t); }
static int o_set_states(fz_slot *s, const double *x, size_t n) { return (int)set_states(s, x, n); }
static int o_get_states(fz_slot *s, double *x, size_t n) { return (int)get_states(s, x, n); }
static int o_derivatives(fz_slot *s, double *dx, size_t n) { return (int)derivatives(s, dx, n); }
static int o_indicators(fz_slot *s, double *z, size_t n) { return (int)indicators(s, z, n); }

static int o_set_reals(fz_slot *s, const unsigned *vr, size_t n, const double *x)
{
    fmi2Status st = CALL(fmi2SetReal, s->c, vr, n, x);
    outcome(s, "fmi2SetReal", me_only(s, ME_WRITABLE_INPUT), st, 0);
    return (int)st;
}

static int o_get_reals(fz_slot *s, const unsigned *vr, size_t n, double *x)
{
    fmi2Status st = CALL(fmi2GetReal, s->c, vr, n, x);
    outcome(s, "fmi2GetReal", me_only(s, ME_FROM_INIT), st, 0);
    if (st == fmi2OK)
        for (size_t i = 0; i < n; i++)
            if (isnan(x[i])) fz_fail("fmi2GetReal gave NaN for value reference %u with fmi2OK", vr[i]);
    return (int)st;
}

static int o_save(fz_slot *s, void **state)
{
    fmi2Status st = CALL(fmi2GetFMUstate, s->c, state);
    if (st == fmi2OK && !*state) fz_fail("fmi2GetFMUstate returned fmi2OK and no state");
    return (int)st;
}

static int o_restore(fz_slot *s, void *state, unsigned mask)
{
    fmi2Status st = CALL(fmi2SetFMUstate, s->c, state);
    outcome(s, "fmi2SetFMUstate", FZ_ANY3, st, mask);
    return (int)st;
}

static void o_drop(fz_slot *s, void **state)
{
    if (CALL(fmi2FreeFMUstate, s->c, state) == fmi2OK && *state) fz_fail("fmi2FreeFMUstate left the handle set");
}

static const fz_me_face face = {
    {"fmi2GetDerivatives", "fmi2GetEventIndicators", "fmi2GetReal"},
    o_set_time, o_set_states, o_set_reals, o_get_states, o_derivatives, o_indicators, o_get_reals,
    o_save, o_restore, o_drop,
};

static void k_call_order(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fz_call_order(s, r, &face);
}

/* Steps of an explicit-Euler importer: x += h x', t += h, then the event handling the standard
 * describes when an indicator changed sign or the FMU asks for it. With_order: the call-order
 * property is checked before the step a further byte names (none when it names none). */
static void euler(fz_slot *s, fz_reader *r, int with_order)
{
    static const double steps[] = {1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2};
    double h = steps[fz_u8(r) % 6];
    int nx = MODEL->n_states, nz = MODEL->n_indicators, steps_n = 1 + fz_u8(r) % 8;
    int order_at = with_order ? fz_u8(r) % 16 : -1;
    double *x = array((size_t)nx), *dx = array((size_t)nx), *z0 = array((size_t)nz), *z1 = array((size_t)nz);
    if (indicators(s, z0, (size_t)nz) != fmi2OK) goto done;
    for (int k = 0; k < steps_n; k++) {
        if (k == order_at) fz_call_order(s, r, &face);
        double t = isnan(s->t) ? 0.0 : s->t;
        if (get_states(s, x, (size_t)nx) != fmi2OK) break;
        if (derivatives(s, dx, (size_t)nx) != fmi2OK) break;
        for (int i = 0; i < nx; i++) x[i] += h * dx[i];
        t += h;
        fz_trace("    Euler: t %.17g x %.9g %.9g z %.9g", t, nx > 0 ? x[0] : 0.0, nx > 1 ? x[1] : 0.0, nz > 0 ? z0[0] : 0.0);
        if (set_time(s, t) != fmi2OK) break;
        if (set_states(s, x, (size_t)nx) != fmi2OK) break;
        fmi2Boolean enter = fmi2False, terminate = fmi2False;
        if (completed_step(s, fmi2True, &enter, &terminate) != fmi2OK) break;
        if (indicators(s, z1, (size_t)nz) != fmi2OK) break;
        int crossed = 0;
        for (int i = 0; i < nz; i++) crossed |= (z0[i] > 0.0) != (z1[i] > 0.0);
        if (enter || crossed) {
            fz_trace("    Euler: event (%s) at t %.17g", enter ? "the FMU asks" : "an indicator changed sign", t);
            if (enter_event_mode(s) != fmi2OK) break;
            event_iteration(s, FZ_EVENT_PASS_BOUND);
            if (enter_continuous(s) != fmi2OK) break;
            if (indicators(s, z1, (size_t)nz) != fmi2OK) break;
        }
        memcpy(z0, z1, (size_t)nz * sizeof *z0);
    }
done:
    free(x), free(dx), free(z0), free(z1);
}

static void k_euler(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    euler(s, r, 0);
}

static void k_euler_order(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    euler(s, r, 1);
}

static const fz_call calls[] = {
    {40, "fmi2SetTime", k_set_time, 0, FZ_RUN_DRIVES},
    {41, "fmi2SetContinuousStates", k_set_states, 0, FZ_RUN_DRIVES},
    {42, "fmi2GetDerivatives/EventIndicators/ContinuousStates/Nominals", k_get_arrays, 0, FZ_RUN_DRIVES},
    {43, "fmi2EnterEventMode", k_enter_event, 0, FZ_RUN_DRIVES},
    {44, "fmi2NewDiscreteStates", k_new_discrete_states, 0, FZ_RUN_DRIVES},
    {45, "fmi2EnterContinuousTimeMode", k_enter_continuous, 0, FZ_RUN_DRIVES},
    {46, "fmi2CompletedIntegratorStep", k_completed_step, 0, FZ_RUN_DRIVES},
    {47, "an explicit-Euler step (Model Exchange)", k_euler, 0, FZ_RUN_DRIVES},
    {48, "an explicit-Euler step (Model Exchange)", k_euler, 0, FZ_RUN_DRIVES},
    {49, "the call order in Continuous-Time Mode (Model Exchange)", k_call_order, 0, FZ_RUN_DRIVES},
    {50, "explicit-Euler steps with a call-order check (Model Exchange)", k_euler_order, 0, FZ_RUN_DRIVES},
};

static void release(fz_context *ctx, fz_slot *s) { (void)ctx, (void)s; } /* calls_fmi2.c frees the instance */

const fz_interface fz_fmi2me = {"FMI 2.0 Model Exchange", me_available, calls, sizeof calls / sizeof calls[0], release, 2};
