/*
 * calls_fmi3.c - the call kinds of FMI 3.0 (Co-Simulation with and without early return and Event
 * Mode, Model Exchange, and the functions the FMU refuses) for the harness (fuzz.h; codes 60-99).
 * Linked into fuzz_<FMU> beside the FMI 2.0 kinds, and alone into fuzz_<FMU>_fmi3.
 *
 * Besides the sanitizers, the watchdog and the logger's checks (FMI 3.0's logger takes the message as
 * it is, not as a format, and names no instance: its instanceEnvironment must be a slot), each kind
 * checks what the standard and the FMU's documentation (doc/fmi3.md, src/fmi/vi_fmi3.c) promise:
 *   - the state machines of FMI 3.0 (Co-Simulation: Instantiated, Initialization Mode, Step Mode,
 *     Event Mode with eventModeUsed, Step Discarded, Terminated; Model Exchange: Event Mode and
 *     Continuous-Time Mode instead of the step states): a call that changes the mode or sets values
 *     returns fmi3OK only in a state where it is allowed, Model Exchange functions never for a
 *     Co-Simulation instance and the Co-Simulation ones never for Model Exchange; the harness follows
 *     the states the instance may be in (after fmi3Error: the state before, or the error state);
 *   - fmi3Set* returns fmi3OK only with one value per value reference, for variables of the call's
 *     type that may be set then (inputs and their derivatives der(<input>), tunable parameters;
 *     fixed parameters until the end of Initialization Mode; never outputs, calculated parameters,
 *     `time` or event indicators; in Continuous-Time Mode only continuous Float64 inputs), for
 *     finite Float64 values and for Strings that are not NULL and fit;
 *   - no NaN from fmi3GetFloat64 with fmi3OK; fmi3GetString gives terminated strings;
 *   - fmi3DoStep: a step accepted (fmi3OK or fmi3Warning) without early return ends at
 *     currentCommunicationPoint + communicationStepSize exactly (lastSuccessfulTime); earlyReturn
 *     only with earlyReturnAllowed and fmi3OK or fmi3Warning, and then lastSuccessfulTime lies in
 *     (currentCommunicationPoint, currentCommunicationPoint + communicationStepSize];
 *     eventHandlingNeeded only with eventModeUsed and earlyReturnAllowed; after fmi3Discard
 *     lastSuccessfulTime lies in the step; terminateSimulation never;
 *   - the numbers of states and event indicators are the model's; states, derivatives (also
 *     directional ones) and indicators with fmi3OK are finite, nominals finite and positive; the
 *     event iteration of Model Exchange settles within FZ_EVENT_PASS_BOUND passes;
 *   - the call order in Continuous-Time Mode of Model Exchange does not matter (fz_call_order,
 *     order.c);
 *   - the functions of what the FMU does not offer (Scheduled Execution, Configuration Mode, clocks,
 *     output and adjoint derivatives, the data types it has no variable of) never return fmi3OK for a
 *     value reference; the intermediate update callback is never called (providesIntermediateUpdate
 *     is false).
 * FMU states are taken, restored (also those the other slot took), serialized (also into a buffer one
 * byte short) and deserialized from altered buffers (maybe sealed again with the documented
 * checksum, fz_corrupted) or from raw input bytes; serialized buffers are shared with the FMI 2.0
 * kinds (both versions have one format).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "fuzz.h"

#define MODEL (&vi_fmu_this_model)

static fmi3Status ended(const char *call, fmi3Status st)
{
    fz_end();
    fz_trace("    -> %d", (int)st);
    if ((unsigned)st > (unsigned)fmi3Fatal) fz_fail("%s returned %d, which is no fmi3Status", call, (int)st);
    return st;
}
#define CALL(fn, ...) ended(#fn, (fz_begin(#fn), fn(__VA_ARGS__)))

static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    if ((unsigned)status > (unsigned)fmi3Fatal) fz_fail("logger: status %d is no fmi3Status", (int)status);
    fz_check_message(env, (int)status, category, message, 0);
}

/* The FMU declares providesIntermediateUpdate = false and documents that it never calls it. */
static void intermediate_update(fmi3InstanceEnvironment env, fmi3Float64 time, fmi3Boolean set_requested,
                                fmi3Boolean get_allowed, fmi3Boolean step_finished, fmi3Boolean can_return_early,
                                fmi3Boolean *early_return_requested, fmi3Float64 *early_return_time)
{
    (void)set_requested, (void)get_allowed, (void)step_finished, (void)can_return_early;
    (void)early_return_requested, (void)early_return_time;
    fz_fail("the FMU called intermediateUpdate (instance environment %p, t = %g), which it documents never to call",
            env, time);
}

static int fmi3_available(void) { return 1; }

/* ---- the state machine ---- */

#define CS_WRITABLE (FZ_INSTANTIATED | FZ_INIT | FZ_STEP_COMPLETE | FZ_EVENT)
#define ME_WRITABLE (FZ_INSTANTIATED | FZ_INIT | FZ_EVENT)

static int is_cs(const fz_slot *s) { return s->fmu_type == fmi2CoSimulation; }

/* The states of mask m as text (two buffers in turn: a message may show two masks). */
static const char *mask_text(unsigned m)
{
    static char buffers[2][160];
    static int turn;
    char *text = buffers[turn ^= 1];
    static const char *const names[] = {"Instantiated", "Initialization Mode", "Step Mode", "Step Discarded",
                                        "Terminated", "error", "fatal", "Event Mode", "Continuous-Time Mode"};
    text[0] = '\0';
    for (int i = 0; i < 9; i++)
        if (m >> i & 1u)
            snprintf(text + strlen(text), sizeof buffers[0] - strlen(text), "%s%s", text[0] ? "|" : "", names[i]);
    return text[0] ? text : "none";
}

/* The outcome of a call allowed in the states `allowed`: fmi3OK or fmi3Warning in none of the states
 * the instance may be in is a finding; then the instance is in `next` (0: those of the states it may
 * be in that allow the call). fmi3Error: refused with the state unchanged, or the instance is in the
 * error state now. */
static void outcome(fz_slot *s, const char *call, unsigned allowed, fmi3Status st, unsigned next)
{
    if (st == fmi3OK || st == fmi3Warning) {
        if (!s->c) fz_fail("%s returned %d for a NULL instance", call, (int)st);
        if (!(s->mask & allowed))
            fz_fail("%s returned %d for a %s instance in state %s; allowed in %s only", call, (int)st,
                    is_cs(s) ? "Co-Simulation" : "Model Exchange", mask_text(s->mask), mask_text(allowed));
        s->mask = next ? next : s->mask & allowed;
    } else if (st == fmi3Error || st == fmi3Fatal) {
        s->mask |= FZ_ERROR;
    }
}

/* Where each Model Exchange function is allowed: nowhere for a Co-Simulation instance. */
static unsigned me_only(const fz_slot *s, unsigned allowed) { return is_cs(s) ? 0u : allowed; }
static unsigned cs_only(const fz_slot *s, unsigned allowed) { return is_cs(s) ? allowed : 0u; }

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

/* flags: bit 0 visible, 1 loggingOn, 2 eventModeUsed, 3 no logMessage callback, 4 earlyReturnAllowed,
 * 5 two required intermediate variables, 6 an intermediateUpdate callback. */
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
    s->version = 3;
    s->options = 0;
    if (kind % 8 < 5) {
        fmi3ValueReference required[2] = {fz_vr(r, -1), fz_vr(r, -1)};
        fz_begin("fmi3InstantiateCoSimulation");
        s->c = fmi3InstantiateCoSimulation(name, token_arg, resources, flags & 1, flags >> 1 & 1, flags >> 2 & 1,
                                           flags >> 4 & 1, required, flags >> 5 & 1 ? 2 : 0, s, log,
                                           flags & 64 ? intermediate_update : NULL);
        fz_end();
        s->fmu_type = fmi2CoSimulation;
        s->options = (flags & 4 ? FZ_EVENT_MODE_USED : 0u) | (flags & 16 ? FZ_EARLY_RETURN_ALLOWED : 0u);
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
    s->mask = FZ_INSTANTIATED;
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
    int known = 1;
    for (size_t i = 0; i < n; i++) {
        cats[i] = names[fz_u8(r) % 10];
        known &= cats[i] && strncmp(cats[i], "log", 3) == 0 && strcmp(cats[i], "logFmi2Call") != 0;
    }
    fmi3Status st = CALL(fmi3SetDebugLogging, s->c, on & 1, n, on & 2 && n ? NULL : cats);
    if (st == fmi3OK && (!known || (on & 2 && n)))
        fz_fail("fmi3SetDebugLogging accepted an unknown category or a NULL array");
}

static void k_enter_init(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t flags = fz_u8(r);
    double tol = fz_real(r, 1e-6), start = flags & 4 ? fz_real(r, 1.0) : 0.0, stop = fz_real(r, 0.1);
    fz_trace("    tolerance %d %g start %g stop %d %g", flags & 1, tol, start, flags >> 1 & 1, stop);
    fmi3Status st = CALL(fmi3EnterInitializationMode, s->c, flags & 1, tol, start, flags >> 1 & 1, stop);
    outcome(s, "fmi3EnterInitializationMode", FZ_INSTANTIATED, st, FZ_INIT);
    if (st == fmi3OK) {
        if (!isfinite(start) || (flags & 1 && !(tol > 0.0 && tol < 1.0)) || (flags & 2 && !(stop >= start)))
            fz_fail("fmi3EnterInitializationMode accepted start %g, tolerance %g, stop %g", start, tol, stop);
        s->t = s->start_time = start;
        fz_energy_tolerance(s, flags & 1, tol);
    }
}

static void k_simple(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    int event_mode = (s->options & FZ_EVENT_MODE_USED) != 0;
    fmi3Status st;
    switch (fz_u8(r) % 8) {
    case 0:
        st = CALL(fmi3ExitInitializationMode, s->c);
        outcome(s, "fmi3ExitInitializationMode", FZ_INIT, st, is_cs(s) && !event_mode ? FZ_STEP_COMPLETE : FZ_EVENT);
        break;
    case 1:
        st = CALL(fmi3EnterEventMode, s->c);
        outcome(s, "fmi3EnterEventMode", is_cs(s) ? (event_mode ? FZ_STEP_COMPLETE : 0u) : FZ_EVENT | FZ_CONTINUOUS,
                st, FZ_EVENT);
        break;
    case 2:
        st = CALL(fmi3Terminate, s->c);
        outcome(s, "fmi3Terminate",
                is_cs(s) ? FZ_STEP_COMPLETE | FZ_STEP_FAILED | FZ_EVENT : FZ_EVENT | FZ_CONTINUOUS, st, FZ_TERMINATED);
        break;
    case 3:
        st = CALL(fmi3Reset, s->c);
        outcome(s, "fmi3Reset", FZ_ANY3, st, FZ_INSTANTIATED);
        if (st == fmi3OK) s->t = s->start_time = 0.0;
        break;
    case 4:
        st = CALL(fmi3EnterStepMode, s->c);
        outcome(s, "fmi3EnterStepMode", cs_only(s, FZ_EVENT), st, FZ_STEP_COMPLETE);
        break;
    case 5:
        st = CALL(fmi3EnterContinuousTimeMode, s->c);
        outcome(s, "fmi3EnterContinuousTimeMode", me_only(s, FZ_EVENT), st, FZ_CONTINUOUS);
        break;
    case 6: outcome(s, "fmi3EnterConfigurationMode", 0, CALL(fmi3EnterConfigurationMode, s->c), 0); break;
    default: outcome(s, "fmi3ExitConfigurationMode", 0, CALL(fmi3ExitConfigurationMode, s->c), 0);
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

/* The API types of the FMI 3.0 calls the FMU has variables of. */
enum { T_FLOAT64, T_INT32, T_INT64, T_BOOLEAN, T_STRING };

/* Does the FMI 3.0 face access v through the call of type t? (Integers with an enumeration are
 * Enumerations, read and written as Int64; the others Int32.) */
static int of_type(const vi_variable *v, int t)
{
    int enumerated = strcmp(v->enumeration, "none") != 0;
    switch (t) {
    case T_FLOAT64: return v->type == VI_Real;
    case T_INT32: return (v->type == VI_Integer || v->type == VI_Enumeration) && !enumerated;
    case T_INT64: return (v->type == VI_Integer || v->type == VI_Enumeration) && enumerated;
    case T_BOOLEAN: return v->type == VI_Boolean;
    default: return v->type == VI_String;
    }
}

/* The states in which vr may be set through the call of type t (the FMU's rules, src/fmi/vi_fmi_values.c
 * settable and doc/fmi3.md); 0: never. */
static unsigned settable_in(const fz_slot *s, fmi3ValueReference vr, int t)
{
    unsigned writable = is_cs(s) ? CS_WRITABLE : ME_WRITABLE;
    if (vr >= VI_FMI3_DERIVATIVE_VR_BASE && vr < VI_FMI3_DERIVATIVE_VR_BASE + (unsigned)MODEL->nvariables &&
        t == T_FLOAT64) { /* der(<input>) of a Float64 input */
        const vi_variable *in = fz_variable(vr - VI_FMI3_DERIVATIVE_VR_BASE);
        if (in && in->type == VI_Real && strcmp(in->causality, "input") == 0)
            return is_cs(s) ? CS_WRITABLE : ME_WRITABLE | FZ_CONTINUOUS;
        return 0;
    }
    const vi_variable *v = fz_variable(vr);
    if (!v || !of_type(v, t)) return 0;
    if (strcmp(v->causality, "input") == 0)
        return writable | (!is_cs(s) && t == T_FLOAT64 && strcmp(v->variability, "continuous") == 0 ? FZ_CONTINUOUS : 0u);
    if (strcmp(v->causality, "parameter") != 0) return 0;
    return strcmp(v->variability, "tunable") == 0 ? writable : FZ_INSTANTIATED | FZ_INIT;
}

static size_t pick(fz_reader *r, int type, fmi3ValueReference vr[FZ_ARRAY], size_t *n_values)
{
    uint8_t k = fz_u8(r);
    size_t n = k % FZ_ARRAY;
    for (size_t i = 0; i < n; i++) vr[i] = vr3(r, type);
    *n_values = k >= 240 ? n + 1 : n; /* sometimes not one value per reference */
    return n;
}

/* The states in which the n value references may all be set with nv values of type t. */
static unsigned set_allowed(const fz_slot *s, const fmi3ValueReference vr[], size_t n, size_t nv, int t)
{
    unsigned allowed = nv == n ? (is_cs(s) ? CS_WRITABLE : ME_WRITABLE | FZ_CONTINUOUS) : 0u;
    for (size_t i = 0; i < n; i++) allowed &= settable_in(s, vr[i], t);
    return allowed;
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
        fmi3Status st = CALL(fmi3SetFloat64, s->c, vr, n, x, nv);
        if (st == fmi3OK && !finite) fz_fail("fmi3SetFloat64 accepted a value that is not finite");
        outcome(s, "fmi3SetFloat64", set_allowed(s, vr, n, nv, T_FLOAT64), st, 0);
    } else {
        fmi3Status st = CALL(fmi3GetFloat64, s->c, vr, n, x, nv);
        if (st == fmi3OK && nv != n) fz_fail("fmi3GetFloat64 returned fmi3OK with nValues %zu for %zu references", nv, n);
        for (size_t i = 0; st == fmi3OK && i < n; i++)
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
    fmi3Status st;
    switch (which) {
    case 0:
        if (set) outcome(s, "fmi3SetInt32", set_allowed(s, vr, n, nv, T_INT32), CALL(fmi3SetInt32, s->c, vr, n, i32, nv), 0);
        else CALL(fmi3GetInt32, s->c, vr, n, i32, nv);
        break;
    case 1:
        if (set) outcome(s, "fmi3SetInt64", set_allowed(s, vr, n, nv, T_INT64), CALL(fmi3SetInt64, s->c, vr, n, i64, nv), 0);
        else CALL(fmi3GetInt64, s->c, vr, n, i64, nv);
        break;
    case 2:
        if (set) outcome(s, "fmi3SetBoolean", set_allowed(s, vr, n, nv, T_BOOLEAN), CALL(fmi3SetBoolean, s->c, vr, n, b, nv), 0);
        else CALL(fmi3GetBoolean, s->c, vr, n, b, nv);
        break;
    case 3:
        if (set) {
            st = CALL(fmi3SetString, s->c, vr, n, str, nv);
            if (st == fmi3OK && !fits) fz_fail("fmi3SetString accepted NULL or a string of %d bytes or more", VI_STRING_SIZE);
            outcome(s, "fmi3SetString", set_allowed(s, vr, n, nv, T_STRING), st, 0);
        } else if (CALL(fmi3GetString, s->c, vr, n, str, nv) == fmi3OK) {
            for (size_t i = 0; i < n; i++)
                if (!str[i] || strnlen(str[i], VI_STRING_SIZE) == VI_STRING_SIZE)
                    fz_fail("fmi3GetString gave NULL or an unterminated string for value reference %u", vr[i]);
        }
        break;
    default: { /* the types of which the FMU has no variable: fmi3OK for no value reference only */
        union {
            float f[FZ_ARRAY + 1];
            uint64_t u[FZ_ARRAY + 1];
        } any;
        memset(&any, 0, sizeof any);
        size_t sizes[FZ_ARRAY + 1] = {0};
        fmi3Binary bins[FZ_ARRAY + 1] = {0};
        fmi3Clock clocks[FZ_ARRAY + 1] = {0};
        const char *fn = "fmi3GetNumberOfVariableDependencies";
        st = fmi3Error;
        switch (fz_u8(r) % 10) {
        case 0: fn = "fmi3Get/SetFloat32"; st = set ? CALL(fmi3SetFloat32, s->c, vr, n, any.f, nv) : CALL(fmi3GetFloat32, s->c, vr, n, any.f, nv); break;
        case 1: fn = "fmi3Get/SetInt8"; st = set ? CALL(fmi3SetInt8, s->c, vr, n, (int8_t *)any.u, nv) : CALL(fmi3GetInt8, s->c, vr, n, (int8_t *)any.u, nv); break;
        case 2: fn = "fmi3Get/SetUInt8"; st = set ? CALL(fmi3SetUInt8, s->c, vr, n, (uint8_t *)any.u, nv) : CALL(fmi3GetUInt8, s->c, vr, n, (uint8_t *)any.u, nv); break;
        case 3: fn = "fmi3Get/SetInt16"; st = set ? CALL(fmi3SetInt16, s->c, vr, n, (int16_t *)any.u, nv) : CALL(fmi3GetInt16, s->c, vr, n, (int16_t *)any.u, nv); break;
        case 4: fn = "fmi3Get/SetUInt16"; st = set ? CALL(fmi3SetUInt16, s->c, vr, n, (uint16_t *)any.u, nv) : CALL(fmi3GetUInt16, s->c, vr, n, (uint16_t *)any.u, nv); break;
        case 5: fn = "fmi3Get/SetUInt32"; st = set ? CALL(fmi3SetUInt32, s->c, vr, n, (uint32_t *)any.u, nv) : CALL(fmi3GetUInt32, s->c, vr, n, (uint32_t *)any.u, nv); break;
        case 6: fn = "fmi3Get/SetUInt64"; st = set ? CALL(fmi3SetUInt64, s->c, vr, n, any.u, nv) : CALL(fmi3GetUInt64, s->c, vr, n, any.u, nv); break;
        case 7: fn = "fmi3Get/SetBinary"; st = set ? CALL(fmi3SetBinary, s->c, vr, n, sizes, bins, nv) : CALL(fmi3GetBinary, s->c, vr, n, sizes, bins, nv); break;
        case 8: fn = "fmi3Get/SetClock"; st = set ? CALL(fmi3SetClock, s->c, vr, n, clocks) : CALL(fmi3GetClock, s->c, vr, n, clocks); break;
        default: {
            size_t nd = 0;
            st = CALL(fmi3GetNumberOfVariableDependencies, s->c, vr3(r, -1), &nd);
            n = 1; /* never offered */
        }
        }
        if (st == fmi3OK && n > 0) fz_fail("%s returned fmi3OK for a value reference; the FMU has no such variable", fn);
    }
    }
}

/* ---- FMU states ---- */

/* A state handle of slot s, or of the other slot when that holds no instance of FMI 2.0. */
static fz_saved *saved_of(fz_context *ctx, fz_slot *s, uint8_t which)
{
    fz_slot *from = &ctx->slot[which >> 7];
    if (from->c && from->version != s->version) from = s;
    return &from->saved[which % FZ_STATES];
}

static void deserialize(fz_slot *s, fz_saved *sv, const uint8_t *p, size_t n, int null_data)
{
    void *before = sv->handle;
    fmi3Status st = CALL(fmi3DeserializeFMUState, s->c, null_data ? NULL : p, n, &sv->handle);
    outcome(s, "fmi3DeserializeFMUState", FZ_ANY3, st, 0);
    if (st == fmi3OK) {
        if (!sv->handle) fz_fail("fmi3DeserializeFMUState returned fmi3OK and no state");
        sv->mask = fz_recorded_mask(p, n);
        sv->t = NAN; /* the time of that state: read from `time` when needed */
    } else if (sv->handle != before) {
        fz_fail("fmi3DeserializeFMUState failed and changed the handle");
    }
}

static void k_state(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    uint8_t k = fz_u8(r), which = fz_u8(r);
    fz_saved *mine = &s->saved[which % FZ_STATES], *any = saved_of(ctx, s, which);
    fz_buffer *b = &ctx->buffer[fz_u8(r) % FZ_BUFFERS];
    fmi3Status st;
    switch (k % 5) {
    case 0:
        st = CALL(fmi3GetFMUState, s->c, which == 127 ? NULL : &mine->handle);
        outcome(s, "fmi3GetFMUState", FZ_ANY3, st, 0);
        if (st == fmi3OK && which != 127) {
            if (!mine->handle) fz_fail("fmi3GetFMUState returned fmi3OK and no state");
            mine->mask = s->mask, mine->t = s->t;
        }
        break;
    case 1:
        st = CALL(fmi3SetFMUState, s->c, any->handle);
        if (st == fmi3OK && !any->handle) fz_fail("fmi3SetFMUState accepted a NULL state");
        outcome(s, "fmi3SetFMUState", FZ_ANY3, st, st == fmi3OK ? any->mask : 0);
        if (st == fmi3OK) s->t = any->t;
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
        st = CALL(fmi3SerializeFMUState, s->c, mine->handle, data, n);
        if (st == fmi3OK && n < size) fz_fail("fmi3SerializeFMUState wrote into %zu bytes, %zu needed", n, size);
        if (st != fmi3OK) {
            free(data);
            break;
        }
        free(b->data);
        b->data = data, b->n = n;
        break;
    }
    default: { /* deserialize a buffer with a few bits flipped (the checksum catches them) */
        if (!b->data) break;
        uint8_t *p = malloc(b->n);
        memcpy(p, b->data, b->n);
        size_t n = b->n;
        uint8_t edits = fz_u8(r);
        for (int e = 0; e < edits % 3 && n; e++) p[fz_u16(r) % n] ^= (uint8_t)(1u << (fz_u8(r) % 8));
        if (edits & 0x40) n = fz_u16(r) % (n + 1);
        if (edits & 0x80) fz_reseal(p, n);
        deserialize(s, mine, p, n, 0);
        free(p);
    }
    }
}

/* A serialized state (of either FMI version's kinds) altered by fz_corrupted, into a handle of the
 * slot (maybe a fresh one). */
static void k_deserialize_altered(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    fz_buffer *b = &ctx->buffer[fz_u8(r) % FZ_BUFFERS];
    if (!b->data) return;
    size_t n;
    uint8_t *p = fz_corrupted(r, b, &n);
    uint8_t k = fz_u8(r);
    fz_saved *sv = &s->saved[k % FZ_STATES];
    if (k & 0x40 && sv->handle) { /* into a fresh handle: drop ours first */
        CALL(fmi3FreeFMUState, s->c, &sv->handle);
        sv->handle = NULL;
    }
    deserialize(s, sv, p, n, k == 255);
    free(p);
}

static void k_deserialize_raw(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    size_t want = fz_u16(r) % 8192;
    uint8_t *p = malloc(want ? want : 1);
    size_t n = fz_bytes(r, p, want);
    if (fz_u8(r) & 1) fz_reseal(p, n);
    deserialize(s, &s->saved[fz_u8(r) % FZ_STATES], p, n, 0);
    free(p);
}

/* ---- Co-Simulation ---- */

/* One fmi3DoStep from the slot's time (its checks, fuzz.h); returns its status, the flags in *out
 * (event handling needed, early return). */
/* After a restored deserialized state the importer's time is unknown: read the FMU's `time`. */
static void sync_time(fz_slot *s)
{
    if (!isnan(s->t) || !s->c) return;
    fmi3ValueReference time_vr = VI_FMI3_TIME_VR;
    double now = NAN;
    if (CALL(fmi3GetFloat64, s->c, &time_vr, 1, &now, 1) == fmi3OK) s->t = now;
}

static fmi3Status do_step(fz_slot *s, double tc, double h, int no_set_prior, int nulls, fmi3Boolean out[2])
{
    double t = s->t;
    fmi3Boolean event = false, terminate = false, early = false;
    double last = NAN;
    fz_trace("    tc %.17g h %.17g", tc, h);
    fmi3Status st = CALL(fmi3DoStep, s->c, tc, h, no_set_prior, nulls ? NULL : &event, &terminate, &early, &last);
    int accepted = st == fmi3OK || st == fmi3Warning;
    outcome(s, "fmi3DoStep", cs_only(s, FZ_STEP_COMPLETE), st, FZ_STEP_COMPLETE);
    if (out) out[0] = event, out[1] = early;
    if (st == fmi3Discard) {
        if (!is_cs(s) || !(s->mask & FZ_STEP_COMPLETE))
            fz_fail("fmi3DoStep returned fmi3Discard in state %s", mask_text(s->mask));
        s->mask = FZ_STEP_FAILED;
    }
    if (!accepted && st != fmi3Discard) return st;
    if (nulls) fz_fail("fmi3DoStep returned %d with NULL output arguments", (int)st);
    if (terminate) fz_fail("fmi3DoStep set terminateSimulation; this FMU never asks to end");
    if (early && (!accepted || !(s->options & FZ_EARLY_RETURN_ALLOWED)))
        fz_fail("fmi3DoStep returned status %d with earlyReturn, earlyReturnAllowed %d", (int)st,
                (s->options & FZ_EARLY_RETURN_ALLOWED) != 0);
    if (event && (s->options & (FZ_EVENT_MODE_USED | FZ_EARLY_RETURN_ALLOWED)) !=
                     (FZ_EVENT_MODE_USED | FZ_EARLY_RETURN_ALLOWED))
        fz_fail("fmi3DoStep set eventHandlingNeeded for an instance with eventModeUsed %d, earlyReturnAllowed %d",
                (s->options & FZ_EVENT_MODE_USED) != 0, (s->options & FZ_EARLY_RETURN_ALLOWED) != 0);
    if (accepted && !early && last != tc + h)
        fz_fail("fmi3DoStep returned %d (the step accepted) without early return, and lastSuccessfulTime is %.17g, not "
                "the communication point %.17g + %.17g", (int)st, last, tc, h);
    if (early && !(last > tc && last <= tc + h))
        fz_fail("fmi3DoStep returned early at lastSuccessfulTime %.17g, outside (%.17g, %.17g + %.17g]", last, tc, tc, h);
    double from = isnan(t) ? -INFINITY : fmin(t, tc) - 1e-9 * fabs(tc);
    if (st == fmi3Discard && !(last >= from && last < tc + h))
        fz_fail("fmi3DoStep returned fmi3Discard, and lastSuccessfulTime %.17g is not in [%.17g, %.17g)", last, t,
                tc + h);
    s->t = last;
    return st;
}

/* fz_get_reals for the energy check */
static int get_reals(fz_slot *s, const unsigned *vr, size_t n, double *x)
{
    return CALL(fmi3GetFloat64, s->c, vr, n, x, n) != fmi3OK;
}

/* fz_get_int for the energy check (the law, an enumeration) */
static int get_int(fz_slot *s, unsigned vr, long *value)
{
    fmi3Int64 v = 0;
    if (CALL(fmi3GetInt64, s->c, &vr, 1, &v, 1) != fmi3OK) return 1;
    *value = (long)v;
    return 0;
}

static void k_do_step(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    static const double steps[] = {1e-6, 1e-5, 1e-4, 1e-4, 1e-3, 1e-3, 1e-2, 0.1, 1.0, 1e6, 0.0, -1e-3, 1e-15, NAN};
    uint8_t k = fz_u8(r), hk = fz_u8(r);
    sync_time(s);
    double t = isnan(s->t) ? 0.0 : s->t;
    double tc = k % 16 < 14 ? t : k % 16 == 14 ? t + 1.0 : fz_real(r, 1.0);
    double h = hk < 240 ? steps[hk % (sizeof steps / sizeof steps[0])] : fz_real(r, 1e-3);
    double before[FZ_ENERGY_VALUES], after[FZ_ENERGY_VALUES];
    int undriven = fz_energy_read(s, get_reals, get_int, before);
    fmi3Status st = do_step(s, tc, h, k >> 6 & 1, k >= 250, NULL);
    if (undriven && (st == fmi3OK || st == fmi3Warning) && fz_energy_read(s, get_reals, get_int, after))
        fz_energy_check(s, before, after, tc, h);
}

/* A master's steps with early return and Event Mode: fmi3DoStep from the last successful time, and
 * where the FMU asks for event handling: fmi3EnterEventMode, the event iteration (maybe an input
 * set there), fmi3EnterStepMode. */
static void k_master(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    static const double hs[] = {1e-5, 1e-4, 1e-3, 1e-2};
    double h = hs[fz_u8(r) % 4];
    int steps = 1 + fz_u8(r) % 16;
    uint8_t input = fz_u8(r);
    for (int k = 0; k < steps; k++) {
        fmi3Boolean out[2];
        sync_time(s);
        double t = isnan(s->t) ? 0.0 : s->t;
        if (do_step(s, t, h, 1, 0, out) != fmi3OK) return;
        if (!out[0]) continue;
        fz_trace("    master: event at t %.17g", s->t);
        fmi3Status st = CALL(fmi3EnterEventMode, s->c);
        outcome(s, "fmi3EnterEventMode", FZ_STEP_COMPLETE, st, FZ_EVENT);
        if (st != fmi3OK) return;
        fmi3Boolean need = false, term = false, nom = false, val = false, next_defined = false;
        double next = 0.0;
        st = CALL(fmi3UpdateDiscreteStates, s->c, &need, &term, &nom, &val, &next_defined, &next);
        outcome(s, "fmi3UpdateDiscreteStates", FZ_EVENT, st, 0);
        if ((st == fmi3OK || st == fmi3Warning) && (need || term))
            fz_fail("fmi3UpdateDiscreteStates in Co-Simulation asked for another pass or to terminate");
        if (input & 1) { /* an input set in Event Mode takes effect in the next step */
            fmi3ValueReference vr = fz_vr(r, VI_Real);
            const vi_variable *v = fz_variable(vr);
            double x = fz_real(r, v ? v->start : 1.0);
            outcome(s, "fmi3SetFloat64", set_allowed(s, &vr, 1, 1, T_FLOAT64), CALL(fmi3SetFloat64, s->c, &vr, 1, &x, 1), 0);
        }
        st = CALL(fmi3EnterStepMode, s->c);
        outcome(s, "fmi3EnterStepMode", FZ_EVENT, st, FZ_STEP_COMPLETE);
        if (st != fmi3OK) return;
    }
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

/* Every element finite (and positive: nominals), or a finding. */
static void finite(const char *call, const double *x, size_t n, int positive)
{
    fz_finite(call, x, n);
    for (size_t i = 0; positive && i < n; i++)
        if (!(x[i] > 0.0)) fz_fail("%s returned fmi3OK with element %zu = %g, not positive", call, i, x[i]);
}

/* An array call of Model Exchange: never fmi3OK or fmi3Warning for Co-Simulation or with the wrong length. */
static void me_array(fz_slot *s, const char *call, fmi3Status st, const double *x, size_t n, size_t expected, int positive)
{
    if (st != fmi3OK && st != fmi3Warning) return;
    if (is_cs(s)) fz_fail("%s returned %d for a Co-Simulation instance", call, (int)st);
    if (n != expected) fz_fail("%s returned %d for %zu elements; the model has %zu", call, (int)st, n, expected);
    finite(call, x, n, positive);
}

/* The event iteration: fmi3UpdateDiscreteStates until no further pass is needed, at most `passes`
 * times. Passes in a row that return fmi3OK and ask for another: the FMU stops the run with an
 * error at FZ_EVENT_PASS_BOUND of them, so one more is a finding. */
static void event_iteration(fz_slot *s, int passes)
{
    for (int k = 0; k < passes && k <= FZ_EVENT_PASS_BOUND; k++) {
        fmi3Boolean need = false, term = false, nom = false, val = false, next_defined = false;
        double next = 0.0;
        fmi3Status st = CALL(fmi3UpdateDiscreteStates, s->c, &need, &term, &nom, &val, &next_defined, &next);
        outcome(s, "fmi3UpdateDiscreteStates", FZ_EVENT, st, 0);
        if (st != fmi3OK || !need || term) return;
        if (k + 1 >= FZ_EVENT_PASS_BOUND)
            fz_fail("the event iteration does not settle: %d passes of fmi3UpdateDiscreteStates in a row returned "
                    "fmi3OK and asked for another (the FMU documents an error at %d)", k + 1, FZ_EVENT_PASS_BOUND);
    }
}

static void k_me(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t which = fz_u8(r) % 10;
    size_t ns = (size_t)MODEL->n_states, ni = (size_t)MODEL->n_indicators;
    size_t n = length(r, which == 3 ? MODEL->n_indicators : MODEL->n_states);
    double *x = array(n);
    fmi3Status st;
    switch (which) {
    case 0: {
        static const double dt[] = {0.0, 1e-9, 1e-6, 1e-4, 1e-3, -1e-6, NAN, INFINITY};
        double t = (isnan(s->t) ? 0.0 : s->t) + dt[fz_u8(r) % 8];
        st = CALL(fmi3SetTime, s->c, t);
        outcome(s, "fmi3SetTime", me_only(s, FZ_EVENT | FZ_CONTINUOUS), st, 0);
        if (st == fmi3OK && !isfinite(t)) fz_fail("fmi3SetTime accepted t = %g", t);
        if (st == fmi3OK) s->t = t;
        break;
    }
    case 1:
        if (CALL(fmi3GetContinuousStates, s->c, x, n) != fmi3OK) break;
        for (size_t i = 0; i < n; i++) x[i] = fz_u8(r) < 200 ? x[i] * (1.0 + (int8_t)fz_u8(r) / 1024.0) : fz_real(r, 1e-4);
        st = CALL(fmi3SetContinuousStates, s->c, x, n);
        outcome(s, "fmi3SetContinuousStates", me_only(s, FZ_CONTINUOUS), st, 0);
        if (st == fmi3OK) finite("fmi3SetContinuousStates (its argument)", x, n, 0);
        break;
    case 2:
        st = CALL(fmi3GetContinuousStateDerivatives, s->c, x, n);
        me_array(s, "fmi3GetContinuousStateDerivatives", st, x, n, ns, 0);
        break;
    case 3:
        st = CALL(fmi3GetEventIndicators, s->c, x, n);
        me_array(s, "fmi3GetEventIndicators", st, x, n, ni, 0);
        break;
    case 4:
        st = CALL(fmi3GetNominalsOfContinuousStates, s->c, x, n);
        me_array(s, "fmi3GetNominalsOfContinuousStates", st, x, n, ns, 1);
        break;
    case 5: {
        size_t count_s = 99, count_i = 99;
        st = CALL(fmi3GetNumberOfContinuousStates, s->c, &count_s);
        if (st == fmi3OK && (is_cs(s) || count_s != ns))
            fz_fail("fmi3GetNumberOfContinuousStates gave %zu (the model has %zu) for a %s instance", count_s, ns,
                    is_cs(s) ? "Co-Simulation" : "Model Exchange");
        st = CALL(fmi3GetNumberOfEventIndicators, s->c, &count_i);
        if (st == fmi3OK && (is_cs(s) || count_i != ni))
            fz_fail("fmi3GetNumberOfEventIndicators gave %zu (the model has %zu) for a %s instance", count_i, ni,
                    is_cs(s) ? "Co-Simulation" : "Model Exchange");
        break;
    }
    case 6: {
        fmi3Boolean enter = false, terminate = false;
        st = CALL(fmi3CompletedIntegratorStep, s->c, fz_u8(r) & 1, &enter, &terminate);
        outcome(s, "fmi3CompletedIntegratorStep", me_only(s, FZ_CONTINUOUS), st, 0);
        break;
    }
    case 7: {
        uint8_t k = fz_u8(r);
        event_iteration(s, k % 16 == 15 ? FZ_EVENT_PASS_BOUND : 1 + k % 8);
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
                st = CALL(fmi3EnterEventMode, s->c);
                outcome(s, "fmi3EnterEventMode", me_only(s, FZ_EVENT | FZ_CONTINUOUS), st, FZ_EVENT);
                event_iteration(s, FZ_EVENT_PASS_BOUND);
                st = CALL(fmi3EnterContinuousTimeMode, s->c);
                outcome(s, "fmi3EnterContinuousTimeMode", me_only(s, FZ_EVENT), st, FZ_CONTINUOUS);
            }
        }
        free(dx);
        break;
    }
    default: { /* the directional and adjoint derivatives */
        fmi3ValueReference u[2] = {vr3(r, VI_Real), vr3(r, VI_Real)}, kn[2] = {vr3(r, VI_Real), vr3(r, VI_Real)};
        double seed[2] = {1.0, fz_real(r, 1.0)}, sens[3];
        uint8_t m = fz_u8(r);
        if (m & 1) {
            size_t nu = m / 2 % 3, nk = m / 8 % 3, nseed = nu ? nk : 0;
            st = CALL(fmi3GetDirectionalDerivative, s->c, u, nu, kn, nk, seed, nseed, sens, nu);
            if (st == fmi3OK && (is_cs(s) || nseed != nk))
                fz_fail("fmi3GetDirectionalDerivative returned fmi3OK (%s, nSeed %zu, nKnowns %zu)",
                        is_cs(s) ? "Co-Simulation" : "Model Exchange", nseed, nk);
            if (st == fmi3OK || st == fmi3Warning) finite("fmi3GetDirectionalDerivative", sens, nu, 0);
        } else if (CALL(fmi3GetAdjointDerivative, s->c, u, m / 2 % 3, kn, m / 8 % 3, seed, m / 2 % 3, sens, m / 8 % 3) ==
                   fmi3OK) {
            fz_fail("fmi3GetAdjointDerivative returned fmi3OK; the FMU does not provide it");
        }
    }
    }
    free(x);
}

/* ---- the call-order property (order.c) through the FMI 3.0 functions ---- */

static int o_set_time(fz_slot *s, double t)
{
    fmi3Status st = CALL(fmi3SetTime, s->c, t);
    outcome(s, "fmi3SetTime", me_only(s, FZ_EVENT | FZ_CONTINUOUS), st, 0);
    if (st == fmi3OK) s->t = t;
    return (int)st;
}

static int o_set_states(fz_slot *s, const double *x, size_t n)
{
    fmi3Status st = CALL(fmi3SetContinuousStates, s->c, x, n);
    outcome(s, "fmi3SetContinuousStates", me_only(s, FZ_CONTINUOUS), st, 0);
    return (int)st;
}

static int o_set_reals(fz_slot *s, const unsigned *vr, size_t n, const double *x)
{
    fmi3Status st = CALL(fmi3SetFloat64, s->c, vr, n, x, n);
    outcome(s, "fmi3SetFloat64", set_allowed(s, vr, n, n, T_FLOAT64), st, 0);
    return (int)st;
}

static int o_get_states(fz_slot *s, double *x, size_t n)
{
    fmi3Status st = CALL(fmi3GetContinuousStates, s->c, x, n);
    me_array(s, "fmi3GetContinuousStates", st, x, n, (size_t)MODEL->n_states, 0);
    return (int)st;
}

static int o_derivatives(fz_slot *s, double *dx, size_t n)
{
    fmi3Status st = CALL(fmi3GetContinuousStateDerivatives, s->c, dx, n);
    me_array(s, "fmi3GetContinuousStateDerivatives", st, dx, n, (size_t)MODEL->n_states, 0);
    return (int)st;
}

static int o_indicators(fz_slot *s, double *z, size_t n)
{
    fmi3Status st = CALL(fmi3GetEventIndicators, s->c, z, n);
    me_array(s, "fmi3GetEventIndicators", st, z, n, (size_t)MODEL->n_indicators, 0);
    return (int)st;
}

static int o_get_reals(fz_slot *s, const unsigned *vr, size_t n, double *x)
{
    fmi3Status st = CALL(fmi3GetFloat64, s->c, vr, n, x, n);
    for (size_t i = 0; st == fmi3OK && i < n; i++)
        if (isnan(x[i])) fz_fail("fmi3GetFloat64 gave NaN for value reference %u with fmi3OK", vr[i]);
    return (int)st;
}

static int o_save(fz_slot *s, void **state)
{
    fmi3Status st = CALL(fmi3GetFMUState, s->c, state);
    outcome(s, "fmi3GetFMUState", FZ_ANY3, st, 0);
    if (st == fmi3OK && !*state) fz_fail("fmi3GetFMUState returned fmi3OK and no state");
    return (int)st;
}

static int o_restore(fz_slot *s, void *state, unsigned mask)
{
    fmi3Status st = CALL(fmi3SetFMUState, s->c, state);
    outcome(s, "fmi3SetFMUState", FZ_ANY3, st, mask);
    return (int)st;
}

static void o_drop(fz_slot *s, void **state)
{
    if (CALL(fmi3FreeFMUState, s->c, state) == fmi3OK && *state) fz_fail("fmi3FreeFMUState left the handle set");
}

static const fz_me_face face = {
    {"fmi3GetContinuousStateDerivatives", "fmi3GetEventIndicators", "fmi3GetFloat64"},
    o_set_time, o_set_states, o_set_reals, o_get_states, o_derivatives, o_indicators, o_get_reals,
    o_save, o_restore, o_drop,
};

static void k_call_order(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fz_call_order(s, r, &face);
}

/* Steps of an explicit-Euler importer: x += h x', t += h, then the event handling the standard
 * describes when an indicator changed sign or the FMU asks for it (fmi3EnterEventMode, the event
 * iteration, fmi3EnterContinuousTimeMode). With_order: the call-order property is checked before
 * the step a further byte names (none when it names none). */
static void euler(fz_slot *s, fz_reader *r, int with_order)
{
    static const double steps[] = {1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2};
    double h = steps[fz_u8(r) % 6];
    int steps_n = 1 + fz_u8(r) % 8, order_at = with_order ? fz_u8(r) % 16 : -1;
    size_t nx = (size_t)MODEL->n_states, nz = (size_t)MODEL->n_indicators;
    double *x = array(nx), *dx = array(nx), *z0 = array(nz), *z1 = array(nz);
    fmi3Status st;
    if (o_indicators(s, z0, nz) != fmi3OK) goto done;
    for (int k = 0; k < steps_n; k++) {
        if (k == order_at) fz_call_order(s, r, &face);
        double t = isnan(s->t) ? 0.0 : s->t;
        if (CALL(fmi3GetContinuousStates, s->c, x, nx) != fmi3OK) break;
        if (o_derivatives(s, dx, nx) != fmi3OK) break;
        for (size_t i = 0; i < nx; i++) x[i] += h * dx[i];
        t += h;
        if (o_set_time(s, t) != fmi3OK) break;
        if (o_set_states(s, x, nx) != fmi3OK) break;
        fmi3Boolean enter = false, terminate = false;
        st = CALL(fmi3CompletedIntegratorStep, s->c, true, &enter, &terminate);
        outcome(s, "fmi3CompletedIntegratorStep", me_only(s, FZ_CONTINUOUS), st, 0);
        if (st != fmi3OK) break;
        if (o_indicators(s, z1, nz) != fmi3OK) break;
        int crossed = 0;
        for (size_t i = 0; i < nz; i++) crossed |= (z0[i] > 0.0) != (z1[i] > 0.0);
        if (enter || crossed) {
            fz_trace("    Euler: event (%s) at t %.17g", enter ? "the FMU asks" : "an indicator changed sign", t);
            st = CALL(fmi3EnterEventMode, s->c);
            outcome(s, "fmi3EnterEventMode", me_only(s, FZ_EVENT | FZ_CONTINUOUS), st, FZ_EVENT);
            if (st != fmi3OK) break;
            event_iteration(s, FZ_EVENT_PASS_BOUND);
            st = CALL(fmi3EnterContinuousTimeMode, s->c);
            outcome(s, "fmi3EnterContinuousTimeMode", me_only(s, FZ_EVENT), st, FZ_CONTINUOUS);
            if (st != fmi3OK) break;
            if (CALL(fmi3GetEventIndicators, s->c, z1, nz) != fmi3OK) break;
        }
        memcpy(z0, z1, nz * sizeof *z0);
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

/* ---- what the FMU does not offer, and the version ---- */

static void k_not_offered(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi3ValueReference vr[2] = {vr3(r, VI_Real), vr3(r, -1)};
    fmi3Int32 orders[2] = {1, 2};
    double values[2], intervals[2] = {1e-3, 1e-3};
    fmi3IntervalQualifier q[2];
    fmi3UInt64 counters[2] = {1, 1}, resolutions[2] = {1000, 1000};
    size_t idx[2], nd = 0;
    fmi3DependencyKind kinds[2];
    fmi3ValueReference indep[2];
    uint8_t k = fz_u8(r), n = 1 + fz_u8(r) % 2;
    fmi3Status st;
    const char *fn;
    switch (k % 8) {
    case 0: fn = "fmi3GetOutputDerivatives"; st = CALL(fmi3GetOutputDerivatives, s->c, vr, n, orders, values, n); break;
    case 1: fn = "fmi3GetVariableDependencies"; st = CALL(fmi3GetVariableDependencies, s->c, vr[0], idx, indep, idx, kinds, nd); break;
    case 2: fn = "fmi3GetIntervalDecimal"; st = CALL(fmi3GetIntervalDecimal, s->c, vr, n, intervals, q); break;
    case 3: fn = "fmi3SetIntervalFraction"; st = CALL(fmi3SetIntervalFraction, s->c, vr, n, counters, resolutions); break;
    case 4: fn = "fmi3GetShiftFraction"; st = CALL(fmi3GetShiftFraction, s->c, vr, n, counters, resolutions); break;
    case 5: fn = "fmi3EvaluateDiscreteStates"; st = CALL(fmi3EvaluateDiscreteStates, s->c); break;
    case 6: fn = "fmi3ActivateModelPartition"; st = CALL(fmi3ActivateModelPartition, s->c, vr[0], fz_real(r, 1.0)); break;
    default: {
        fz_begin("fmi3GetVersion");
        const char *v = fmi3GetVersion();
        fz_end();
        if (!v || strcmp(v, fmi3Version) != 0) fz_fail("fmi3GetVersion: '%s'", v ? v : "(null)");
        return;
    }
    }
    if (st == fmi3OK) fz_fail("%s returned fmi3OK; the FMU does not provide it", fn);
}

static const fz_call calls[] = {
    {60, "fmi3Instantiate*", k_instantiate, 1, FZ_RUN_DRIVES},
    {61, "fmi3FreeInstance", k_free, 0, FZ_RUN_KEEPS},
    {62, "fmi3SetDebugLogging", k_debug_logging, 0, FZ_RUN_KEEPS},
    {63, "fmi3EnterInitializationMode", k_enter_init, 0, FZ_RUN_STARTS},
    {64, "fmi3 mode changes (exit initialization, event, step, continuous-time, configuration, terminate, reset)",
     k_simple, 0, FZ_RUN_STARTS},
    {65, "fmi3 mode changes", k_simple, 0, FZ_RUN_STARTS},
    {66, "fmi3Get/SetFloat64", k_float64, 0, FZ_RUN_STARTS},
    {67, "fmi3Get/SetFloat64", k_float64, 0, FZ_RUN_STARTS},
    {68, "fmi3Get/Set of the other types", k_discrete, 0, FZ_RUN_STARTS},
    {69, "fmi3 FMU states", k_state, 0, FZ_RUN_DRIVES},
    {70, "fmi3DoStep", k_do_step, 0, FZ_RUN_KEEPS},
    {71, "fmi3DoStep", k_do_step, 0, FZ_RUN_KEEPS},
    {72, "fmi3 Model Exchange and derivatives", k_me, 0, FZ_RUN_DRIVES},
    {73, "fmi3 Model Exchange and derivatives", k_me, 0, FZ_RUN_DRIVES},
    {74, "fmi3DeserializeFMUState (a serialized state, altered)", k_deserialize_altered, 0, FZ_RUN_DRIVES},
    {75, "fmi3DeserializeFMUState (bytes of the input)", k_deserialize_raw, 0, FZ_RUN_DRIVES},
    {76, "fmi3 Co-Simulation master steps (early return, Event Mode)", k_master, 0, FZ_RUN_DRIVES},
    {77, "an explicit-Euler step (FMI 3.0 Model Exchange)", k_euler, 0, FZ_RUN_DRIVES},
    {78, "fmi3 functions the FMU does not provide; fmi3GetVersion", k_not_offered, 0, FZ_RUN_KEEPS},
    {79, "the call order in Continuous-Time Mode (FMI 3.0 Model Exchange)", k_call_order, 0, FZ_RUN_DRIVES},
    {80, "explicit-Euler steps with a call-order check (FMI 3.0 Model Exchange)", k_euler_order, 0, FZ_RUN_DRIVES},
};

const fz_interface fz_fmi3 = {"FMI 3.0", fmi3_available, calls, sizeof calls / sizeof calls[0], release, 3};
