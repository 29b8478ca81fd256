/*
 * calls_fmi2me.c - the call kinds of FMI 2.0 Model Exchange for the harness (fuzz.h; codes 40-59).
 * An instance is made Model Exchange by fmi2Instantiate with fmi2ModelExchange (calls_fmi2.c); the
 * common functions (values, FMU states, initialization) are those of calls_fmi2.c.
 *
 * Arrays are passed with exactly the length given (heap), so that AddressSanitizer sees a write
 * beyond it; lengths are the model's numbers of states and indicators (vi_fmu_this_model), one more
 * or one less, zero, or eight. Beyond the sanitizers, the watchdog and the logger's checks: with
 * fmi2OK, states, derivatives and indicators are not NaN, nominals are finite and positive, and the
 * event loop of fmi2NewDiscreteStates settles (newDiscreteStatesNeeded) within a bound. The kind
 * "Euler step" makes the calls an explicit-Euler importer makes for one step, so that the fuzzer
 * reaches events and mode changes without having to find the sequence byte by byte.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"

#define MODEL (&vi_fmu_this_model)
#define FZ_EVENT_PASSES 64 /* fmi2NewDiscreteStates calls in one event before the harness gives up */

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

static void no_nan(const char *call, const double *x, size_t n, int positive)
{
    for (size_t i = 0; i < n; i++)
        if (isnan(x[i]) || (positive && !(isfinite(x[i]) && x[i] > 0.0)))
            fz_fail("%s returned fmi2OK with element %zu = %g", call, i, x[i]);
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
    if (CALL(fmi2SetTime, s->c, t) == fmi2OK) s->t = t;
}

static void k_set_states(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    size_t n = length(r, MODEL->n_states);
    double *x = array(n);
    if (fz_u8(r) & 1) { /* near the current states */
        double *now = array(n);
        if (CALL(fmi2GetContinuousStates, s->c, now, n) == fmi2OK) memcpy(x, now, n * sizeof *x);
        free(now);
    }
    for (size_t i = 0; i < n; i++) {
        uint8_t how = fz_u8(r);
        x[i] = how < 128 ? x[i] * (1.0 + (int8_t)fz_u8(r) / 1024.0) : fz_real(r, x[i] != 0.0 ? x[i] : 1e-4);
        fz_trace("    x[%zu] = %.17g", i, x[i]);
    }
    CALL(fmi2SetContinuousStates, s->c, fz_u8(r) == 255 ? NULL : x, n);
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
    case 0:
        if (CALL(fmi2GetDerivatives, s->c, arg, n) == fmi2OK) no_nan("fmi2GetDerivatives", x, n, 0);
        break;
    case 1:
        if (CALL(fmi2GetEventIndicators, s->c, arg, n) == fmi2OK) no_nan("fmi2GetEventIndicators", x, n, 0);
        break;
    case 2:
        if (CALL(fmi2GetContinuousStates, s->c, arg, n) == fmi2OK) no_nan("fmi2GetContinuousStates", x, n, 0);
        break;
    default:
        if (CALL(fmi2GetNominalsOfContinuousStates, s->c, arg, n) == fmi2OK)
            no_nan("fmi2GetNominalsOfContinuousStates", x, n, 1);
    }
    free(x);
}

static void k_enter_event(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    CALL(fmi2EnterEventMode, s->c);
}

/* The event iteration: fmi2NewDiscreteStates until no new discrete states are needed (bounded). */
static void event_iteration(fz_slot *s, int passes)
{
    for (int k = 0; k < passes; k++) {
        fmi2EventInfo ev;
        memset(&ev, 0, sizeof ev);
        if (CALL(fmi2NewDiscreteStates, s->c, &ev) != fmi2OK || !ev.newDiscreteStatesNeeded) return;
    }
}

static void k_new_discrete_states(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t k = fz_u8(r);
    if (k == 255) {
        CALL(fmi2NewDiscreteStates, s->c, NULL);
        return;
    }
    event_iteration(s, 1 + k % 4);
}

static void k_enter_continuous(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    CALL(fmi2EnterContinuousTimeMode, s->c);
}

static void k_completed_step(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t k = fz_u8(r);
    fmi2Boolean enter = fmi2False, terminate = fmi2False;
    CALL(fmi2CompletedIntegratorStep, s->c, k & 1, k & 2 ? NULL : &enter, k & 4 ? NULL : &terminate);
}

/* One step of an explicit-Euler importer: x += h x', t += h, then the event handling the standard
 * describes when an indicator changed sign or the FMU asks for it. */
static void k_euler(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    static const double steps[] = {1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2};
    double h = steps[fz_u8(r) % 6];
    int nx = MODEL->n_states, nz = MODEL->n_indicators, steps_n = 1 + fz_u8(r) % 8;
    double *x = array((size_t)nx), *dx = array((size_t)nx), *z0 = array((size_t)nz), *z1 = array((size_t)nz);
    double t = isnan(s->t) ? 0.0 : s->t;
    if (CALL(fmi2GetEventIndicators, s->c, z0, (size_t)nz) != fmi2OK) goto done;
    for (int k = 0; k < steps_n; k++) {
        if (CALL(fmi2GetContinuousStates, s->c, x, (size_t)nx) != fmi2OK) break;
        if (CALL(fmi2GetDerivatives, s->c, dx, (size_t)nx) != fmi2OK) break;
        no_nan("fmi2GetDerivatives", dx, (size_t)nx, 0);
        for (int i = 0; i < nx; i++) x[i] += h * dx[i];
        t += h;
        fz_trace("    Euler: t %.17g x %.9g %.9g z %.9g", t, nx > 0 ? x[0] : 0.0, nx > 1 ? x[1] : 0.0, nz > 0 ? z0[0] : 0.0);
        if (CALL(fmi2SetTime, s->c, t) != fmi2OK) break;
        s->t = t;
        if (CALL(fmi2SetContinuousStates, s->c, x, (size_t)nx) != fmi2OK) break;
        fmi2Boolean enter = fmi2False, terminate = fmi2False;
        if (CALL(fmi2CompletedIntegratorStep, s->c, fmi2True, &enter, &terminate) != fmi2OK) break;
        if (CALL(fmi2GetEventIndicators, s->c, z1, (size_t)nz) != fmi2OK) break;
        int crossed = 0;
        for (int i = 0; i < nz; i++) crossed |= (z0[i] > 0.0) != (z1[i] > 0.0);
        if (enter || crossed) {
            fz_trace("    Euler: event (%s) at t %.17g", enter ? "the FMU asks" : "an indicator changed sign", t);
            if (CALL(fmi2EnterEventMode, s->c) != fmi2OK) break;
            event_iteration(s, FZ_EVENT_PASSES);
            if (CALL(fmi2EnterContinuousTimeMode, s->c) != fmi2OK) break;
            if (CALL(fmi2GetEventIndicators, s->c, z1, (size_t)nz) != fmi2OK) break;
        }
        memcpy(z0, z1, (size_t)nz * sizeof *z0);
    }
done:
    free(x), free(dx), free(z0), free(z1);
}

static const fz_call calls[] = {
    {40, "fmi2SetTime", k_set_time, 0},
    {41, "fmi2SetContinuousStates", k_set_states, 0},
    {42, "fmi2GetDerivatives/EventIndicators/ContinuousStates/Nominals", k_get_arrays, 0},
    {43, "fmi2EnterEventMode", k_enter_event, 0},
    {44, "fmi2NewDiscreteStates", k_new_discrete_states, 0},
    {45, "fmi2EnterContinuousTimeMode", k_enter_continuous, 0},
    {46, "fmi2CompletedIntegratorStep", k_completed_step, 0},
    {47, "an explicit-Euler step (Model Exchange)", k_euler, 0},
    {48, "an explicit-Euler step (Model Exchange)", k_euler, 0},
};

static void release(fz_context *ctx, fz_slot *s) { (void)ctx, (void)s; } /* calls_fmi2.c frees the instance */

const fz_interface fz_fmi2me = {"FMI 2.0 Model Exchange", me_available, calls, sizeof calls / sizeof calls[0], release, 2};
