/*
 * calls_fmi3.c - the call kinds of FMI 3.0 (Co-Simulation, Model Exchange, and the functions the FMU
 * refuses) for the harness (fuzz.h; codes 60-99), in the FMU's FMI 3.0 binary (fuzz_<FMU>_fmi3).
 *
 * Besides the sanitizers, the watchdog and the logger's checks (FMI 3.0's logger takes the message as
 * it is, not as a format, and names no instance: its instanceEnvironment must be the slot called):
 * fmi3OK from fmi3SetFloat64 only for finite values and from fmi3SetString only for Strings that are
 * not NULL and fit; no NaN from fmi3GetFloat64 with fmi3OK; fmi3DoStep with fmi3OK ends at
 * currentCommunicationPoint + communicationStepSize unless it returned early, then (and after
 * fmi3Discard) lastSuccessfulTime lies in the step; terminateSimulation is never set; with fmi3OK,
 * fmi3GetNumberOfContinuousStates and fmi3GetNumberOfEventIndicators give the model's numbers, and
 * states, derivatives and indicators are not NaN; fmi3InstantiateScheduledExecution gives no
 * instance (the FMU offers none).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "fuzz.h"

#define MODEL (&vi_fmu_this_model)

static fmi3Status ended(const char *call, fmi3Status st)
{
    fz_end();
    fz_trace("    -> %d", (int)st);
    return (fmi3Status)fz_status(call, (fmi2Status)st);
}
#define CALL(fn, ...) ended(#fn, (fz_begin(#fn), fn(__VA_ARGS__)))

static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    fz_slot *s = env;
    fz_check_message(s, (int)status, category, message, 0);
}

static int fmi3_available(void) { return 1; }

/* ---- instances ---- */

static void free_states(fz_slot *s)
{
    for (int i = 0; i < FZ_STATES; i++)
        if (s->saved[i].handle) {
            CALL(fmi3FreeFMUState, s->c, &s->saved[i].handle);
            if (s->saved[i].handle) fz_fail("fmi3FreeFMUState left the handle set");
        }
}

static void release(fz_context *ctx, fz_slot *s)
{
    (void)ctx;
    if (!s->c) return;
    free_states(s);
    fz_begin("fmi3FreeInstance");
    fmi3FreeInstance(s->c);
    fz_end();
    s->c = NULL;
}

static void k_instantiate(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    release(ctx, s);
    const char *name;
    uint8_t k = fz_u8(r), kind = fz_u8(r), tok = fz_u8(r), res = fz_u8(r), flags = fz_u8(r);
    switch (k % 8) {
    case 4: name = ""; break;
    case 5: name = NULL; break;
    case 6: s->name[fz_bytes(r, (uint8_t *)s->name, fz_u8(r) % 64)] = '\0', name = s->name; break;
    default: snprintf(s->name, sizeof s->name, "fuzz%d", (int)(s - ctx->slot)), name = s->name;
    }
    static char token[128];
    snprintf(token, sizeof token, "%s", MODEL->guid);
    if (tok % 8 == 6) token[strlen(token) / 2] = '\0';
    const char *token_arg = tok % 8 < 6 ? MODEL->guid : tok % 8 == 6 ? token : tok % 16 == 7 ? NULL : "{0000}";
    static char path[512];
    snprintf(path, sizeof path, "%s/", ctx->resources);
    const char *resources = res % 8 < 4 ? path : res % 8 == 4 ? NULL : res % 8 == 5 ? "" : fz_string(r, 0);
    fmi3LogMessageCallback log = flags & 8 ? NULL : logger;
    fz_expect_name(s, name);
    fz_trace("    %s name '%.40s' token %s resources %.60s flags %d", kind % 8 < 5 ? "CS" : kind % 8 < 7 ? "ME" : "SE",
             name ? name : "(null)", token_arg ? token_arg : "(null)", resources ? resources : "(null)", flags);
    if (kind % 8 < 5) {
        fmi3ValueReference required[2] = {fz_vr(r, -1), fz_vr(r, -1)};
        fz_begin("fmi3InstantiateCoSimulation");
        s->c = fmi3InstantiateCoSimulation(name, token_arg, resources, flags & 1, flags >> 1 & 1, flags >> 2 & 1,
                                           flags >> 4 & 1, required, flags >> 5 & 1 ? 2 : 0, s, log, NULL);
        fz_end();
        s->fmu_type = fmi2CoSimulation;
    } else if (kind % 8 < 7) {
        fz_begin("fmi3InstantiateModelExchange");
        s->c = fmi3InstantiateModelExchange(name, token_arg, resources, flags & 1, flags >> 1 & 1, s, log);
        fz_end();
        s->fmu_type = fmi2ModelExchange;
    } else {
        fz_begin("fmi3InstantiateScheduledExecution");
        s->c = fmi3InstantiateScheduledExecution(name, token_arg, resources, flags & 1, flags >> 1 & 1, s, log, NULL,
                                                 NULL, NULL);
        fz_end();
        if (s->c) fz_fail("fmi3InstantiateScheduledExecution gave an instance; the FMU offers no Scheduled Execution");
    }
    fz_trace("    -> %p", s->c);
    s->t = s->start_time = 0.0;
}

static void k_free(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)r;
    release(ctx, s);
}

static void k_debug_logging(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    static const char *const names[] = {"logEvents", "logSolver", "logStatusWarning", "logStatusDiscard",
                                        "logStatusError", "logFmi3Call", "logAll", "logFmi2Call", NULL, ""};
    const char *cats[4];
    uint8_t k = fz_u8(r), on = fz_u8(r);
    size_t n = k % 5;
    for (size_t i = 0; i < n; i++) cats[i] = names[fz_u8(r) % 10];
    CALL(fmi3SetDebugLogging, s->c, on & 1, n, on & 2 && n ? NULL : cats);
}

static void k_enter_init(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t flags = fz_u8(r);
    double tol = fz_real(r, 1e-6), start = flags & 4 ? fz_real(r, 1.0) : 0.0, stop = fz_real(r, 0.1);
    fz_trace("    tolerance %d %g start %g stop %d %g", flags & 1, tol, start, flags >> 1 & 1, stop);
    if (CALL(fmi3EnterInitializationMode, s->c, flags & 1, tol, start, flags >> 1 & 1, stop) == fmi3OK)
        s->t = s->start_time = start;
}

static void k_simple(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    switch (fz_u8(r) % 8) {
    case 0: CALL(fmi3ExitInitializationMode, s->c); break;
    case 1: CALL(fmi3EnterEventMode, s->c); break;
    case 2: CALL(fmi3Terminate, s->c); break;
    case 3:
        if (CALL(fmi3Reset, s->c) == fmi3OK) s->t = s->start_time = 0.0;
        break;
    case 4: CALL(fmi3EnterStepMode, s->c); break;
    case 5: CALL(fmi3EnterContinuousTimeMode, s->c); break;
    case 6: CALL(fmi3EnterConfigurationMode, s->c); break;
    default: CALL(fmi3ExitConfigurationMode, s->c);
    }
}

/* ---- values ---- */

/* A value reference: mostly the table's (of the type), sometimes the FMI 3.0 face's own (time,
 * der(<input>), event indicators) or one that does not exist. */
static fmi3ValueReference vr3(fz_reader *r, int type)
{
    uint8_t k = fz_u8(r);
    if (k < 224) return fz_vr(r, type);
    switch (k % 4) {
    case 0: return VI_FMI3_TIME_VR;
    case 1: return VI_FMI3_DERIVATIVE_VR_BASE + fz_u8(r) % 4;
    case 2: return VI_FMI3_INDICATOR_VR_BASE + fz_u8(r) % 4;
    default: return fz_vr(r, -1) + 100000u;
    }
}

static size_t pick(fz_reader *r, int type, fmi3ValueReference vr[FZ_ARRAY], size_t *n_values)
{
    uint8_t k = fz_u8(r);
    size_t n = k % FZ_ARRAY;
    for (size_t i = 0; i < n; i++) vr[i] = vr3(r, type);
    *n_values = k >= 240 ? n + 1 : n; /* sometimes not one value per reference */
    return n;
}

static void k_float64(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi3ValueReference vr[FZ_ARRAY];
    size_t nv, n = pick(r, VI_Real, vr, &nv);
    double *x = calloc(nv + 1, sizeof *x);
    if (fz_u8(r) & 1) {
        int finite = 1;
        for (size_t i = 0; i < nv; i++) {
            const vi_variable *v = fz_variable(vr[i < n ? i : 0]);
            x[i] = fz_real(r, v ? v->start : 1.0);
            finite &= isfinite(x[i]) != 0;
            fz_trace("    vr %u = %.17g", i < n ? vr[i] : 0u, x[i]);
        }
        if (CALL(fmi3SetFloat64, s->c, vr, n, x, nv) == fmi3OK && !finite)
            fz_fail("fmi3SetFloat64 accepted a value that is not finite");
    } else if (CALL(fmi3GetFloat64, s->c, vr, n, x, nv) == fmi3OK) {
        for (size_t i = 0; i < n; i++)
            if (isnan(x[i])) fz_fail("fmi3GetFloat64 gave NaN for value reference %u with fmi3OK", vr[i]);
    }
    free(x);
}

static void k_discrete(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi3ValueReference vr[FZ_ARRAY];
    uint8_t which = fz_u8(r) % 6;
    static const int types[] = {VI_Integer, VI_Enumeration, VI_Boolean, VI_String, VI_String, VI_Integer};
    size_t nv, n = pick(r, types[which], vr, &nv);
    int set = fz_u8(r) & 1;
    int32_t i32[FZ_ARRAY + 1];
    int64_t i64[FZ_ARRAY + 1];
    bool b[FZ_ARRAY + 1];
    fmi3String str[FZ_ARRAY + 1];
    int fits = 1;
    for (size_t i = 0; i < nv; i++) {
        const vi_variable *v = fz_variable(vr[i < n ? i : 0]);
        i32[i] = fz_integer(r, v ? v->enumeration : "none");
        i64[i] = i32[i] + (fz_u8(r) == 255 ? (int64_t)1 << 40 : 0);
        b[i] = fz_u8(r) & 1;
        str[i] = fz_string(r, (int)i);
        fits &= str[i] && strlen(str[i]) < VI_STRING_SIZE;
    }
    switch (which) {
    case 0: set ? CALL(fmi3SetInt32, s->c, vr, n, i32, nv) : CALL(fmi3GetInt32, s->c, vr, n, i32, nv); break;
    case 1: set ? CALL(fmi3SetInt64, s->c, vr, n, i64, nv) : CALL(fmi3GetInt64, s->c, vr, n, i64, nv); break;
    case 2: set ? CALL(fmi3SetBoolean, s->c, vr, n, b, nv) : CALL(fmi3GetBoolean, s->c, vr, n, b, nv); break;
    case 3:
        if (set) {
            if (CALL(fmi3SetString, s->c, vr, n, str, nv) == fmi3OK && !fits)
                fz_fail("fmi3SetString accepted NULL or a string of %d bytes or more", VI_STRING_SIZE);
        } else if (CALL(fmi3GetString, s->c, vr, n, str, nv) == fmi3OK) {
            for (size_t i = 0; i < n; i++)
                if (!str[i] || strnlen(str[i], VI_STRING_SIZE) == VI_STRING_SIZE)
                    fz_fail("fmi3GetString gave NULL or an unterminated string for value reference %u", vr[i]);
        }
        break;
    default: { /* the types of which the FMU has no variable */
        union {
            float f[FZ_ARRAY + 1];
            uint64_t u[FZ_ARRAY + 1];
        } any;
        memset(&any, 0, sizeof any);
        size_t sizes[FZ_ARRAY + 1] = {0};
        fmi3Binary bins[FZ_ARRAY + 1] = {0};
        fmi3Clock clocks[FZ_ARRAY + 1] = {0};
        switch (fz_u8(r) % 10) {
        case 0: set ? CALL(fmi3SetFloat32, s->c, vr, n, any.f, nv) : CALL(fmi3GetFloat32, s->c, vr, n, any.f, nv); break;
        case 1: set ? CALL(fmi3SetInt8, s->c, vr, n, (int8_t *)any.u, nv) : CALL(fmi3GetInt8, s->c, vr, n, (int8_t *)any.u, nv); break;
        case 2: set ? CALL(fmi3SetUInt8, s->c, vr, n, (uint8_t *)any.u, nv) : CALL(fmi3GetUInt8, s->c, vr, n, (uint8_t *)any.u, nv); break;
        case 3: set ? CALL(fmi3SetInt16, s->c, vr, n, (int16_t *)any.u, nv) : CALL(fmi3GetInt16, s->c, vr, n, (int16_t *)any.u, nv); break;
        case 4: set ? CALL(fmi3SetUInt16, s->c, vr, n, (uint16_t *)any.u, nv) : CALL(fmi3GetUInt16, s->c, vr, n, (uint16_t *)any.u, nv); break;
        case 5: set ? CALL(fmi3SetUInt32, s->c, vr, n, (uint32_t *)any.u, nv) : CALL(fmi3GetUInt32, s->c, vr, n, (uint32_t *)any.u, nv); break;
        case 6: set ? CALL(fmi3SetUInt64, s->c, vr, n, any.u, nv) : CALL(fmi3GetUInt64, s->c, vr, n, any.u, nv); break;
        case 7: set ? CALL(fmi3SetBinary, s->c, vr, n, sizes, bins, nv) : CALL(fmi3GetBinary, s->c, vr, n, sizes, bins, nv); break;
        case 8: set ? CALL(fmi3SetClock, s->c, vr, n, clocks) : CALL(fmi3GetClock, s->c, vr, n, clocks); break;
        default: {
            size_t nd = 0;
            CALL(fmi3GetNumberOfVariableDependencies, s->c, vr3(r, -1), &nd);
        }
        }
    }
    }
}

/* ---- FMU states ---- */

static void k_state(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    uint8_t k = fz_u8(r), which = fz_u8(r);
    fz_saved *mine = &s->saved[which % FZ_STATES], *any = &ctx->slot[which >> 7].saved[which % FZ_STATES];
    fz_buffer *b = &ctx->buffer[fz_u8(r) % FZ_BUFFERS];
    switch (k % 5) {
    case 0:
        if (CALL(fmi3GetFMUState, s->c, which == 127 ? NULL : &mine->handle) == fmi3OK && which != 127) {
            if (!mine->handle) fz_fail("fmi3GetFMUState returned fmi3OK and no state");
            mine->t = s->t;
        }
        break;
    case 1:
        if (CALL(fmi3SetFMUState, s->c, any->handle) == fmi3OK) s->t = any->t;
        break;
    case 2:
        if (CALL(fmi3FreeFMUState, s->c, &mine->handle) == fmi3OK && mine->handle)
            fz_fail("fmi3FreeFMUState returned fmi3OK and left the handle set");
        break;
    case 3: { /* serialize into a buffer of the size asked for, or one byte short */
        size_t size = 0;
        if (CALL(fmi3SerializedFMUStateSize, s->c, mine->handle, &size) != fmi3OK) break;
        if (size == 0 || size > (1u << 24)) fz_fail("fmi3SerializedFMUStateSize gave %zu bytes", size);
        size_t n = fz_u8(r) % 8 == 7 ? size - 1 : size;
        uint8_t *data = malloc(n);
        fmi3Status st = CALL(fmi3SerializeFMUState, s->c, mine->handle, data, n);
        if (st == fmi3OK && n < size) fz_fail("fmi3SerializeFMUState wrote into %zu bytes, %zu needed", n, size);
        if (st != fmi3OK) {
            free(data);
            break;
        }
        free(b->data);
        b->data = data, b->n = n;
        break;
    }
    default: { /* deserialize a buffer with a few bytes changed (the checksum catches them) */
        if (!b->data) break;
        uint8_t *p = malloc(b->n);
        memcpy(p, b->data, b->n);
        size_t n = b->n;
        uint8_t edits = fz_u8(r);
        for (int e = 0; e < edits % 3 && n; e++) p[fz_u16(r) % n] ^= (uint8_t)(1u << (fz_u8(r) % 8));
        if (edits & 0x40) n = fz_u16(r) % (n + 1);
        void *before = mine->handle;
        fmi3Status st = CALL(fmi3DeserializeFMUState, s->c, p, n, &mine->handle);
        if (st == fmi3OK && !mine->handle) fz_fail("fmi3DeserializeFMUState returned fmi3OK and no state");
        if (st == fmi3OK) mine->t = NAN; /* the time of that state: read from `time` when needed */
        if (st != fmi3OK && mine->handle != before) fz_fail("fmi3DeserializeFMUState failed and changed the handle");
        free(p);
    }
    }
}

/* ---- Co-Simulation ---- */

static void k_do_step(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    static const double steps[] = {1e-6, 1e-5, 1e-4, 1e-4, 1e-3, 1e-3, 1e-2, 0.1, 1.0, 1e6, 0.0, -1e-3, 1e-15, NAN};
    uint8_t k = fz_u8(r), hk = fz_u8(r);
    if (isnan(s->t)) { /* after a restored deserialized state: its time */
        fmi3ValueReference time_vr = VI_FMI3_TIME_VR;
        double now = NAN;
        if (CALL(fmi3GetFloat64, s->c, &time_vr, 1, &now, 1) == fmi3OK) s->t = now;
    }
    double t = isnan(s->t) ? 0.0 : s->t;
    double tc = k % 16 < 14 ? t : k % 16 == 14 ? t + 1.0 : fz_real(r, 1.0);
    double h = hk < 240 ? steps[hk % (sizeof steps / sizeof steps[0])] : fz_real(r, 1e-3);
    fmi3Boolean event = false, terminate = false, early = false;
    double last = NAN;
    int nulls = k >= 250;
    fz_trace("    tc %.17g h %.17g", tc, h);
    fmi3Status st = CALL(fmi3DoStep, s->c, tc, h, k >> 6 & 1, nulls ? NULL : &event, &terminate, &early, &last);
    if (st != fmi3OK && st != fmi3Discard) return;
    if (nulls) fz_fail("fmi3DoStep returned %d with NULL output arguments", (int)st);
    if (terminate) fz_fail("fmi3DoStep set terminateSimulation; this FMU never asks to end");
    if (st == fmi3OK && !early && last != tc + h)
        fz_fail("fmi3DoStep returned fmi3OK without early return, and lastSuccessfulTime is %.17g, not %.17g + %.17g",
                last, tc, h);
    if ((st == fmi3Discard || early) && !(last >= fmin(t, tc) - 1e-9 * fabs(tc) && last < tc + h))
        fz_fail("fmi3DoStep (status %d, early return %d): lastSuccessfulTime %.17g is not in [%.17g, %.17g)", (int)st,
                early, last, t, tc + h);
    s->t = last;
}

/* ---- Model Exchange ---- */

static double *array(size_t n) { return calloc(n ? n : 1, sizeof(double)); }

static size_t length(fz_reader *r, int n)
{
    static const int delta[] = {0, 0, 0, 0, 0, 1, -1};
    uint8_t k = fz_u8(r);
    if (k % 8 == 7) return k >= 128 ? 8 : 0;
    int m = n + delta[k % 7];
    return m > 0 ? (size_t)m : 0;
}

static void no_nan(const char *call, const double *x, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (isnan(x[i])) fz_fail("%s returned fmi3OK with element %zu = NaN", call, i);
}

static void k_me(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t which = fz_u8(r) % 10;
    size_t n = length(r, which == 3 ? MODEL->n_indicators : MODEL->n_states);
    double *x = array(n);
    switch (which) {
    case 0: {
        static const double dt[] = {0.0, 1e-9, 1e-6, 1e-4, 1e-3, -1e-6, NAN, INFINITY};
        double t = (isnan(s->t) ? 0.0 : s->t) + dt[fz_u8(r) % 8];
        if (CALL(fmi3SetTime, s->c, t) == fmi3OK) s->t = t;
        break;
    }
    case 1:
        if (CALL(fmi3GetContinuousStates, s->c, x, n) != fmi3OK) break;
        for (size_t i = 0; i < n; i++) x[i] = fz_u8(r) < 200 ? x[i] * (1.0 + (int8_t)fz_u8(r) / 1024.0) : fz_real(r, 1e-4);
        CALL(fmi3SetContinuousStates, s->c, x, n);
        break;
    case 2:
        if (CALL(fmi3GetContinuousStateDerivatives, s->c, x, n) == fmi3OK) no_nan("fmi3GetContinuousStateDerivatives", x, n);
        break;
    case 3:
        if (CALL(fmi3GetEventIndicators, s->c, x, n) == fmi3OK) no_nan("fmi3GetEventIndicators", x, n);
        break;
    case 4:
        if (CALL(fmi3GetNominalsOfContinuousStates, s->c, x, n) == fmi3OK) no_nan("fmi3GetNominalsOfContinuousStates", x, n);
        break;
    case 5: {
        size_t ns = 99, ni = 99;
        if (CALL(fmi3GetNumberOfContinuousStates, s->c, &ns) == fmi3OK && ns != (size_t)MODEL->n_states)
            fz_fail("fmi3GetNumberOfContinuousStates gave %zu, the model has %d", ns, MODEL->n_states);
        if (CALL(fmi3GetNumberOfEventIndicators, s->c, &ni) == fmi3OK && ni != (size_t)MODEL->n_indicators)
            fz_fail("fmi3GetNumberOfEventIndicators gave %zu, the model has %d", ni, MODEL->n_indicators);
        break;
    }
    case 6: {
        fmi3Boolean enter = false, terminate = false;
        CALL(fmi3CompletedIntegratorStep, s->c, fz_u8(r) & 1, &enter, &terminate);
        break;
    }
    case 7: { /* the event iteration, bounded */
        for (int k = 0; k < 1 + fz_u8(r) % 8; k++) {
            fmi3Boolean need = false, term = false, nom = false, val = false, next_defined = false;
            double next = 0.0;
            if (CALL(fmi3UpdateDiscreteStates, s->c, &need, &term, &nom, &val, &next_defined, &next) != fmi3OK || !need)
                break;
        }
        break;
    }
    case 8: { /* explicit-Euler steps with the event handling of the standard */
        static const double hs[] = {1e-6, 1e-5, 1e-4, 1e-3};
        double h = hs[fz_u8(r) % 4], t = isnan(s->t) ? 0.0 : s->t, *dx = array(n);
        for (int k = 0; k < 1 + fz_u8(r) % 8; k++) {
            if (CALL(fmi3GetContinuousStates, s->c, x, n) != fmi3OK) break;
            if (CALL(fmi3GetContinuousStateDerivatives, s->c, dx, n) != fmi3OK) break;
            for (size_t i = 0; i < n; i++) x[i] += h * dx[i];
            t += h;
            if (CALL(fmi3SetTime, s->c, t) != fmi3OK) break;
            s->t = t;
            if (CALL(fmi3SetContinuousStates, s->c, x, n) != fmi3OK) break;
            fmi3Boolean enter = false, terminate = false;
            if (CALL(fmi3CompletedIntegratorStep, s->c, true, &enter, &terminate) != fmi3OK) break;
            if (enter) {
                CALL(fmi3EnterEventMode, s->c);
                fmi3Boolean need = true, term, nom, val, next_defined;
                double next;
                for (int j = 0; j < 64 && need; j++)
                    if (CALL(fmi3UpdateDiscreteStates, s->c, &need, &term, &nom, &val, &next_defined, &next) != fmi3OK) break;
                CALL(fmi3EnterContinuousTimeMode, s->c);
            }
        }
        free(dx);
        break;
    }
    default: { /* the directional and adjoint derivatives */
        fmi3ValueReference u[2] = {vr3(r, VI_Real), vr3(r, VI_Real)}, kn[2] = {vr3(r, VI_Real), vr3(r, VI_Real)};
        double seed[2] = {1.0, fz_real(r, 1.0)}, sens[3];
        uint8_t m = fz_u8(r);
        if (m & 1)
            CALL(fmi3GetDirectionalDerivative, s->c, u, m / 2 % 3, kn, m / 8 % 3, seed, m / 2 % 3 ? m / 8 % 3 : 0, sens,
                 m / 2 % 3);
        else
            CALL(fmi3GetAdjointDerivative, s->c, u, m / 2 % 3, kn, m / 8 % 3, seed, m / 2 % 3, sens, m / 8 % 3);
    }
    }
    free(x);
}

static const fz_call calls[] = {
    {60, "fmi3Instantiate*", k_instantiate},
    {61, "fmi3FreeInstance", k_free},
    {62, "fmi3SetDebugLogging", k_debug_logging},
    {63, "fmi3EnterInitializationMode", k_enter_init},
    {64, "fmi3 mode changes (exit initialization, event, step, continuous-time, configuration, terminate, reset)",
     k_simple},
    {65, "fmi3 mode changes", k_simple},
    {66, "fmi3Get/SetFloat64", k_float64},
    {67, "fmi3Get/SetFloat64", k_float64},
    {68, "fmi3Get/Set of the other types", k_discrete},
    {69, "fmi3 FMU states", k_state},
    {70, "fmi3DoStep", k_do_step},
    {71, "fmi3DoStep", k_do_step},
    {72, "fmi3 Model Exchange and derivatives", k_me},
    {73, "fmi3 Model Exchange and derivatives", k_me},
};

const fz_interface fz_fmi3 = {"FMI 3.0", fmi3_available, calls, sizeof calls / sizeof calls[0], release};
