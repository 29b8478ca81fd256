/*
 * calls_fmi2.c - the call kinds of FMI 2.0 (common functions and Co-Simulation) for the harness
 * (fuzz.h; codes 0-39).
 *
 * Besides the sanitizers, the watchdog and the logger's checks, each kind checks what the standard
 * and the FMU's documentation promise about its outcome:
 *   - the state machines of FMI 2.0 Co-Simulation (section 4.2.4) and Model Exchange (section
 *     3.2.3): a call returns fmi2OK only in a state where it is allowed for the instance's
 *     interface (the Co-Simulation functions never for Model Exchange); the harness follows the
 *     states the instance may be in (after fmi2Error: the state before, or Error);
 *   - fmi2SetXXX returns fmi2OK only for variables that may be set then: inputs and parameters
 *     before the end of initialization; inputs and tunable parameters in Co-Simulation's
 *     stepComplete and Model Exchange's Event Mode; continuous Real inputs only in Continuous-Time
 *     Mode; never outputs and calculated parameters; only finite Reals and Strings that are not
 *     NULL and fit (VI_STRING_SIZE);
 *   - fmi2GetReal with fmi2OK gives no NaN; fmi2GetString gives terminated strings; directional
 *     and output derivatives with fmi2OK are finite; output derivatives are never fmi2OK (the FMU
 *     declares maxOutputDerivativeOrder = 0);
 *   - fmi2DoStep with fmi2OK or fmi2Warning (a step accepted) ends at currentCommunicationPoint +
 *     communicationStepSize exactly (fmi2LastSuccessfulTime), with fmi2Discard somewhere in [the
 *     time before, that end);
 *   - fmi2CancelStep never returns fmi2OK (fmi2DoStep is synchronous).
 * Serialized states may be corrupted before they are deserialized, and then sealed again with the
 * checksum the FMU documents (fz_corrupted, fuzz_main.c), so that the field checks behind the
 * checksum are reached as well.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, nanosleep, mkdtemp, strnlen */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"

#define MODEL (&vi_fmu_this_model)

#define CS_WRITABLE (FZ_INSTANTIATED | FZ_INIT | FZ_STEP_COMPLETE)
#define ME_WRITABLE (FZ_INSTANTIATED | FZ_INIT | FZ_EVENT)
/* fmi2GetXXX (values, directional derivatives): everywhere but Instantiated */
#define CS_READABLE (FZ_INIT | FZ_STEP_COMPLETE | FZ_STEP_FAILED | FZ_TERMINATED | FZ_ERROR)
#define ME_READABLE (FZ_INIT | FZ_EVENT | FZ_CONTINUOUS | FZ_TERMINATED | FZ_ERROR)

/* Run an FMI function under the watchdog; a status outside fmi2Status is a finding. */
static fmi2Status ended(const char *call, fmi2Status st)
{
    fz_end();
    fz_trace("    -> %d", (int)st);
    return fz_status(call, st);
}
#define CALL(fn, ...) ended(#fn, (fz_begin(#fn), fn(__VA_ARGS__)))

/* The states of mask m as text (two buffers in turn: a message may show two masks). */
static const char *mask_text(unsigned m)
{
    static char buffers[2][160];
    static int turn;
    char *text = buffers[turn ^= 1];
    static const char *const names[] = {"instantiated", "initialization", "stepComplete", "stepFailed", "terminated",
                                        "error", "", "Event Mode", "Continuous-Time Mode"};
    text[0] = '\0';
    for (int i = 0; i < 9; i++)
        if (m >> i & 1u && names[i][0])
            snprintf(text + strlen(text), sizeof buffers[0] - strlen(text), "%s%s", text[0] ? "|" : "", names[i]);
    return text[0] ? text : "none";
}

unsigned fz_by_type(const fz_slot *s, unsigned cs, unsigned me)
{
    return s->fmu_type == fmi2CoSimulation ? cs : s->fmu_type == fmi2ModelExchange ? me : 0u;
}

void fz_outcome2(fz_slot *s, const char *call, unsigned allowed, fmi2Status st, unsigned next)
{
    if (s->fmu_type != fmi2CoSimulation && s->fmu_type != fmi2ModelExchange) return; /* no instance was made */
    if (st == fmi2OK || st == fmi2Warning) {
        if (!(s->mask & allowed))
            fz_fail("%s returned %d for a %s instance in state %s; FMI 2.0 allows it in %s only", call, (int)st,
                    s->fmu_type == fmi2CoSimulation ? "Co-Simulation" : "Model Exchange", mask_text(s->mask),
                    mask_text(allowed));
        s->mask = next ? next : s->mask & allowed;
    } else if (st == fmi2Error) {
        s->mask |= FZ_ERROR;
    }
}
#define outcome fz_outcome2

/* ---- instances ---- */

static int fmi2_available(void) { return 1; }

static void free_states(fz_slot *s)
{
    for (int i = 0; i < FZ_STATES; i++)
        if (s->saved[i].handle) {
            CALL(fmi2FreeFMUstate, s->c, &s->saved[i].handle);
            if (s->saved[i].handle) fz_fail("fmi2FreeFMUstate left the handle set");
        }
}

static void release(fz_context *ctx, fz_slot *s)
{
    (void)ctx;
    if (!s->c) return;
    free_states(s);
    fz_begin("fmi2FreeInstance");
    fmi2FreeInstance(s->c);
    fz_end();
    s->c = NULL;
}

static void k_instantiate(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    release(ctx, s);
    const char *name;
    uint8_t k = fz_u8(r);
    switch (k % 8) {
    case 4: name = ""; break;
    case 5: name = NULL; break;
    case 6: memset(s->name, 'n', FZ_NAME_SIZE - 1), s->name[FZ_NAME_SIZE - 1] = '\0', name = s->name; break;
    case 7: s->name[fz_bytes(r, (uint8_t *)s->name, fz_u8(r) % 64)] = '\0', name = s->name; break;
    default: snprintf(s->name, sizeof s->name, "fuzz%d", (int)(s - ctx->slot)), name = s->name;
    }
    uint8_t t = fz_u8(r), g = fz_u8(r), res = fz_u8(r), cb = fz_u8(r), flags = fz_u8(r);
    fmi2Type type = t % 8 < 6 ? fmi2CoSimulation : t % 8 == 6 ? fmi2ModelExchange : (fmi2Type)(t % 2 ? 2 : -1);
    static char guid[128];
    snprintf(guid, sizeof guid, "%s", MODEL->guid);
    if (g % 8 == 6) guid[strlen(guid) / 2] = '\0'; /* a truncated GUID */
    const char *guid_arg = g % 8 < 6 ? MODEL->guid : g % 8 == 6 ? guid : g % 16 == 7 ? NULL : "{00000000-0000}";
    const char *uri = res % 8 < 4 ? ctx->resources_uri
                      : res % 8 == 4 ? NULL
                      : res % 8 == 5 ? "file://otherhost/x"
                      : res % 8 == 6 ? "file:///nonexistent%2Fdir%zz%4"
                                     : fz_string(r, 0);
    fmi2CallbackFunctions f = fz_callbacks(s);
    if (cb % 16 == 0) f.logger = NULL;
    if (cb % 16 == 1) f.allocateMemory = NULL;
    fz_expect_name(s, name);
    fz_trace("    name '%.40s' type %d guid %s uri %.60s callbacks %d flags %d", name ? name : "(null)", (int)type,
             guid_arg ? guid_arg : "(null)", uri ? uri : "(null)", cb % 16, flags & 3);
    s->version = 2;
    fz_begin("fmi2Instantiate");
    s->c = fmi2Instantiate(name, type, guid_arg, uri, cb % 16 == 2 ? NULL : &f, flags & 1, flags >> 1 & 1);
    fz_end();
    fz_trace("    -> %p", s->c);
    s->fmu_type = type;
    s->mask = FZ_INSTANTIATED;
    s->t = s->start_time = 0.0;
    s->logging = flags >> 1 & 1;
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
                                        "logStatusError", "logFmi2Call", "logAll", "noSuchCategory", NULL, ""};
    const char *cats[4];
    uint8_t k = fz_u8(r), on = fz_u8(r);
    size_t n = k % 5;
    for (size_t i = 0; i < n; i++) cats[i] = names[fz_u8(r) % 10];
    CALL(fmi2SetDebugLogging, s->c, on & 1, n, on & 2 && n ? NULL : cats);
}

static void k_setup(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t flags = fz_u8(r);
    double tol = fz_real(r, 1e-6), start = flags & 4 ? fz_real(r, 1.0) : 0.0, stop = fz_real(r, 0.1);
    fz_trace("    tolerance %d %g start %g stop %d %g", flags & 1, tol, start, flags >> 1 & 1, stop);
    fmi2Status st = CALL(fmi2SetupExperiment, s->c, flags & 1, tol, start, flags >> 1 & 1, stop);
    outcome(s, "fmi2SetupExperiment", FZ_INSTANTIATED, st, 0);
    if (st == fmi2OK) s->t = s->start_time = start, fz_energy_tolerance(s, flags & 1, tol);
}

static void k_enter_init(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    outcome(s, "fmi2EnterInitializationMode", FZ_INSTANTIATED, CALL(fmi2EnterInitializationMode, s->c), FZ_INIT);
}

static void k_exit_init(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    outcome(s, "fmi2ExitInitializationMode", FZ_INIT, CALL(fmi2ExitInitializationMode, s->c),
            fz_by_type(s, FZ_STEP_COMPLETE, FZ_EVENT));
}

static void k_terminate(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    outcome(s, "fmi2Terminate", fz_by_type(s, FZ_STEP_COMPLETE | FZ_STEP_FAILED, FZ_EVENT | FZ_CONTINUOUS),
            CALL(fmi2Terminate, s->c), FZ_TERMINATED);
}

static void k_reset(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    fmi2Status st = CALL(fmi2Reset, s->c);
    outcome(s, "fmi2Reset", FZ_ANY3, st, FZ_INSTANTIATED);
    if (st == fmi2OK) s->t = s->start_time = 0.0;
}

/* ---- values ---- */

/* The states in which v may be set through fmi2Set<type> (FMI 2.0: sections 3.2.3 and 4.2.4, and
 * the causality/variability rules); 0: never. In Model Exchange's Continuous-Time Mode only
 * continuous Real inputs. */
static unsigned settable_in(const fz_slot *s, const vi_variable *v, int type)
{
    if (!v) return 0;
    unsigned writable = fz_by_type(s, CS_WRITABLE, ME_WRITABLE);
    if (strcmp(v->causality, "input") == 0)
        return writable | (type == VI_Real && strcmp(v->variability, "continuous") == 0
                               ? fz_by_type(s, 0u, FZ_CONTINUOUS) : 0u);
    if (strcmp(v->causality, "parameter") != 0) return 0;
    return strcmp(v->variability, "tunable") == 0 ? writable : FZ_INSTANTIATED | FZ_INIT;
}

/* n value references of `type`, maybe a NULL array; returns the states in which all may be set. */
static unsigned pick_vrs(const fz_slot *s, fz_reader *r, int type, fmi2ValueReference vr[FZ_ARRAY], size_t *n,
                         int *null_array)
{
    uint8_t k = fz_u8(r);
    *n = k % FZ_ARRAY;
    *null_array = k >= 250 && *n > 0;
    unsigned allowed = fz_by_type(s, CS_WRITABLE, ME_WRITABLE | (type == VI_Real ? FZ_CONTINUOUS : 0u));
    for (size_t i = 0; i < *n; i++) {
        vr[i] = fz_vr(r, type);
        const vi_variable *v = fz_variable(vr[i]);
        int same = v && (type == VI_Integer ? v->type == VI_Integer || v->type == VI_Enumeration : (int)v->type == type);
        allowed &= same ? settable_in(s, v, type) : 0;
    }
    return allowed;
}

static double typical(fmi2ValueReference vr)
{
    const vi_variable *v = fz_variable(vr);
    return v ? v->start : 1.0;
}

static void k_set_real(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi2ValueReference vr[FZ_ARRAY];
    fmi2Real x[FZ_ARRAY];
    size_t n;
    int null_array, finite = 1;
    unsigned allowed = pick_vrs(s, r, VI_Real, vr, &n, &null_array);
    for (size_t i = 0; i < n; i++) {
        x[i] = fz_real(r, typical(vr[i]));
        finite &= isfinite(x[i]) != 0;
        fz_trace("    vr %u = %.17g", vr[i], x[i]);
    }
    fmi2Status st = CALL(fmi2SetReal, s->c, null_array ? NULL : vr, n, x);
    if (st == fmi2OK && !finite) fz_fail("fmi2SetReal accepted a value that is not finite");
    outcome(s, "fmi2SetReal", allowed, st, 0);
}

static void k_set_integer(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi2ValueReference vr[FZ_ARRAY];
    fmi2Integer x[FZ_ARRAY];
    size_t n;
    int null_array;
    unsigned allowed = pick_vrs(s, r, VI_Integer, vr, &n, &null_array);
    for (size_t i = 0; i < n; i++) {
        const vi_variable *v = fz_variable(vr[i]);
        x[i] = fz_integer(r, v ? v->enumeration : "none");
        fz_trace("    vr %u = %d", vr[i], x[i]);
    }
    outcome(s, "fmi2SetInteger", allowed, CALL(fmi2SetInteger, s->c, null_array ? NULL : vr, n, x), 0);
}

static void k_set_boolean(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi2ValueReference vr[FZ_ARRAY];
    fmi2Boolean x[FZ_ARRAY];
    size_t n;
    int null_array;
    unsigned allowed = pick_vrs(s, r, VI_Boolean, vr, &n, &null_array);
    for (size_t i = 0; i < n; i++) {
        x[i] = fz_boolean(r);
        fz_trace("    vr %u = %d", vr[i], x[i]);
    }
    outcome(s, "fmi2SetBoolean", allowed, CALL(fmi2SetBoolean, s->c, null_array ? NULL : vr, n, x), 0);
}

static void k_set_string(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi2ValueReference vr[FZ_ARRAY];
    fmi2String x[FZ_ARRAY];
    size_t n;
    int null_array, fits = 1;
    unsigned allowed = pick_vrs(s, r, VI_String, vr, &n, &null_array);
    for (size_t i = 0; i < n; i++) {
        x[i] = fz_string(r, (int)i);
        fits &= x[i] && strlen(x[i]) < VI_STRING_SIZE;
        fz_trace("    vr %u = '%.60s' (%zu bytes)", vr[i], x[i] ? x[i] : "(null)", x[i] ? strlen(x[i]) : 0);
    }
    fmi2Status st = CALL(fmi2SetString, s->c, null_array ? NULL : vr, n, x);
    if (st == fmi2OK && !fits) fz_fail("fmi2SetString accepted NULL or a string of %d bytes or more", VI_STRING_SIZE);
    outcome(s, "fmi2SetString", allowed, st, 0);
}

static void k_get(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t which = fz_u8(r) % 4;
    static const int types[] = {VI_Real, VI_Integer, VI_Boolean, VI_String};
    fmi2ValueReference vr[FZ_ARRAY];
    size_t n;
    int null_array;
    pick_vrs(s, r, types[which], vr, &n, &null_array);
    const fmi2ValueReference *v = null_array ? NULL : vr;
    /* arrays of exactly n elements (heap), so that AddressSanitizer sees a write beyond them */
    void *out = malloc(n ? n * sizeof(double) : 1);
    fmi2Status st;
    switch (which) {
    case 0:
        st = CALL(fmi2GetReal, s->c, v, n, out);
        for (size_t i = 0; st == fmi2OK && i < n; i++)
            if (isnan(((fmi2Real *)out)[i])) fz_fail("fmi2GetReal gave NaN for value reference %u with fmi2OK", vr[i]);
        break;
    case 1: st = CALL(fmi2GetInteger, s->c, v, n, out); break;
    case 2: st = CALL(fmi2GetBoolean, s->c, v, n, out); break;
    default:
        st = CALL(fmi2GetString, s->c, v, n, out);
        for (size_t i = 0; st == fmi2OK && i < n; i++) {
            fmi2String x = ((fmi2String *)out)[i];
            if (!x || strnlen(x, VI_STRING_SIZE) == VI_STRING_SIZE)
                fz_fail("fmi2GetString gave NULL or an unterminated string for value reference %u", vr[i]);
        }
    }
    outcome(s, "fmi2GetXXX", fz_by_type(s, CS_READABLE, ME_READABLE), st, 0);
    free(out);
}

/* ---- FMU states ---- */

/* A state handle of slot s or of the other slot (when that holds no instance of another FMI version:
 * an FMU state belongs to the FMU binary that made it). */
static fz_saved *saved_of(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    uint8_t k = fz_u8(r);
    fz_slot *from = &ctx->slot[k >> 7];
    if (from->c && from->version != s->version) from = s;
    return &from->saved[k % FZ_STATES];
}

static void k_get_state(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t k = fz_u8(r);
    fz_saved *sv = &s->saved[k % FZ_STATES];
    fmi2Status st = CALL(fmi2GetFMUstate, s->c, k >= 250 ? NULL : &sv->handle);
    if (st == fmi2OK && k < 250) {
        if (!sv->handle) fz_fail("fmi2GetFMUstate returned fmi2OK and no state");
        sv->mask = s->mask, sv->t = s->t;
    }
}

static void k_set_state(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    fz_saved *sv = saved_of(ctx, s, r); /* also one the other instance took */
    fmi2Status st = CALL(fmi2SetFMUstate, s->c, sv->handle);
    if (st == fmi2OK && !sv->handle) fz_fail("fmi2SetFMUstate accepted a NULL state");
    outcome(s, "fmi2SetFMUstate", FZ_ANY3, st, sv->mask);
    if (st == fmi2OK) s->t = sv->t;
}

static void k_free_state(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fz_saved *sv = &s->saved[fz_u8(r) % FZ_STATES];
    fmi2Status st = CALL(fmi2FreeFMUstate, s->c, &sv->handle);
    if (st == fmi2OK && sv->handle) fz_fail("fmi2FreeFMUstate returned fmi2OK and left the handle set");
}

static void k_serialize(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    fz_saved *sv = &s->saved[fz_u8(r) % FZ_STATES];
    fz_buffer *b = &ctx->buffer[fz_u8(r) % FZ_BUFFERS];
    uint8_t how = fz_u8(r);
    size_t size = 0;
    fmi2Status st = CALL(fmi2SerializedFMUstateSize, s->c, sv->handle, how == 255 ? NULL : &size);
    if (st != fmi2OK) return;
    if (size == 0 || size > (1u << 24)) fz_fail("fmi2SerializedFMUstateSize gave %zu bytes", size);
    size_t n = how % 8 == 7 ? size - 1 : size; /* sometimes a buffer one byte short */
    uint8_t *data = malloc(n);
    st = CALL(fmi2SerializeFMUstate, s->c, sv->handle, (fmi2Byte *)data, n);
    if (st == fmi2OK && n < size) fz_fail("fmi2SerializeFMUstate wrote into a buffer of %zu bytes, %zu needed", n, size);
    if (st != fmi2OK) {
        free(data);
        return;
    }
    free(b->data);
    b->data = data, b->n = n;
}

static void deserialize(fz_slot *s, fz_reader *r, const uint8_t *data, size_t n)
{
    uint8_t k = fz_u8(r);
    fz_saved *sv = &s->saved[k % FZ_STATES];
    if (k & 0x40 && sv->handle) { /* into a fresh handle: drop ours first */
        CALL(fmi2FreeFMUstate, s->c, &sv->handle);
        sv->handle = NULL;
    }
    void *before = sv->handle;
    fmi2Status st = CALL(fmi2DeSerializeFMUstate, s->c, k == 255 ? NULL : (const fmi2Byte *)data, n, &sv->handle);
    if (st == fmi2OK) {
        if (!sv->handle) fz_fail("fmi2DeSerializeFMUstate returned fmi2OK and no state");
        sv->mask = fz_recorded_mask(data, n);
        sv->t = NAN; /* unknown: fmi2GetRealStatus tells after fmi2SetFMUstate */
    } else if (sv->handle != before) {
        fz_fail("fmi2DeSerializeFMUstate failed and changed the handle");
    }
}

static void k_deserialize(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    fz_buffer *b = &ctx->buffer[fz_u8(r) % FZ_BUFFERS];
    if (!b->data) return;
    size_t n;
    uint8_t *p = fz_corrupted(r, b, &n);
    deserialize(s, r, p, n);
    free(p);
}

static void k_deserialize_raw(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    size_t want = fz_u16(r) % 8192;
    uint8_t *p = malloc(want ? want : 1);
    size_t n = fz_bytes(r, p, want);
    if (fz_u8(r) & 1) fz_reseal(p, n);
    deserialize(s, r, p, n);
    free(p);
}

/* ---- the rest of the API ---- */

static void k_directional(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi2ValueReference u[2] = {fz_vr(r, VI_Real), fz_vr(r, VI_Real)}, k[2] = {fz_vr(r, VI_Real), fz_vr(r, VI_Real)};
    uint8_t n = fz_u8(r);
    /* the first seed: 1, or from n / 9 (large, tiny, negative), so that a product may overflow */
    static const double seeds[] = {1.0, 1.0, -1.0, 1e300, DBL_MAX, -DBL_MAX, 1e-300, DBL_TRUE_MIN};
    fmi2Real dk[2] = {seeds[n / 9 % 8], 0.0}, du[2];
    size_t nu = n % 3;
    fmi2Status st = CALL(fmi2GetDirectionalDerivative, s->c, u, nu, k, n / 3 % 3, dk, du);
    outcome(s, "fmi2GetDirectionalDerivative", fz_by_type(s, CS_READABLE, ME_READABLE), st, 0);
    if (st == fmi2OK || st == fmi2Warning) fz_finite("fmi2GetDirectionalDerivative", du, nu);
}

static void k_input_derivatives(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi2ValueReference vr[FZ_ARRAY];
    fmi2Integer order[FZ_ARRAY];
    fmi2Real x[FZ_ARRAY];
    size_t n;
    int null_array, valid = 1;
    unsigned allowed = pick_vrs(s, r, VI_Real, vr, &n, &null_array);
    for (size_t i = 0; i < n; i++) {
        uint8_t o = fz_u8(r);
        order[i] = o % 8 < 6 ? 1 : o % 8 == 6 ? 2 : 0;
        x[i] = fz_real(r, 1e-3);
        const vi_variable *v = fz_variable(vr[i]);
        valid &= v && strcmp(v->causality, "input") == 0 && order[i] == 1 && isfinite(x[i]);
        fz_trace("    vr %u order %d = %g", vr[i], order[i], x[i]);
    }
    fmi2Status st = CALL(fmi2SetRealInputDerivatives, s->c, null_array ? NULL : vr, n, order, x);
    if (st == fmi2OK && !valid) fz_fail("fmi2SetRealInputDerivatives accepted what it documents to refuse");
    outcome(s, "fmi2SetRealInputDerivatives", fz_by_type(s, allowed, 0u), st, 0);
}

static void k_output_derivatives(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    fmi2ValueReference vr[2] = {fz_vr(r, VI_Real), fz_vr(r, VI_Real)};
    fmi2Integer order[2] = {1, 2};
    fmi2Real x[2];
    size_t n = fz_u8(r) % 3;
    fmi2Status st = CALL(fmi2GetRealOutputDerivatives, s->c, vr, n, order, x);
    if (st != fmi2OK && st != fmi2Warning) return;
    fz_finite("fmi2GetRealOutputDerivatives", x, n);
    if (n > 0) fz_fail("fmi2GetRealOutputDerivatives returned fmi2OK; the FMU declares maxOutputDerivativeOrder = 0");
}

static double step_size(fz_reader *r)
{
    static const double h[] = {1e-6, 1e-5, 1e-4, 1e-4, 1e-3, 1e-3, 1e-2, 0.1, 1.0, 10.0, 1e6,
                               0.0, -1e-3, DBL_TRUE_MIN, 1e-15, NAN, INFINITY};
    uint8_t k = fz_u8(r);
    return k < 240 ? h[k % (sizeof h / sizeof h[0])] : fz_real(r, 1e-3);
}

/* fz_get_reals for the energy check */
static int get_reals(fz_slot *s, const unsigned *vr, size_t n, double *x)
{
    return CALL(fmi2GetReal, s->c, vr, n, x) != fmi2OK;
}

/* fz_get_int for the energy check (the law) */
static int get_int(fz_slot *s, unsigned vr, long *value)
{
    fmi2Integer v = 0;
    if (CALL(fmi2GetInteger, s->c, &vr, 1, &v) != fmi2OK) return 1;
    *value = v;
    return 0;
}

static void k_do_step(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t k = fz_u8(r);
    double t = isnan(s->t) ? 0.0 : s->t;
    double tc = k % 16 < 13 ? t : k % 16 == 13 ? t + 1e-13 : k % 16 == 14 ? t + 1.0 : fz_real(r, 1.0);
    double h = step_size(r);
    if (isnan(s->t) && s->c && s->fmu_type == fmi2CoSimulation) { /* after a restore of a deserialized state */
        fmi2Real last = NAN;
        if (CALL(fmi2GetRealStatus, s->c, fmi2LastSuccessfulTime, &last) == fmi2OK && k % 16 < 13) tc = last;
    }
    fz_trace("    tc %.17g h %.17g", tc, h);
    double before[FZ_ENERGY_VALUES], after[FZ_ENERGY_VALUES];
    int undriven = fz_energy_read(s, get_reals, get_int, before);
    fmi2Status st = CALL(fmi2DoStep, s->c, tc, h, k >> 7);
    int accepted = st == fmi2OK || st == fmi2Warning;
    outcome(s, "fmi2DoStep", fz_by_type(s, FZ_STEP_COMPLETE, 0u), st, accepted ? FZ_STEP_COMPLETE : 0);
    if (st == fmi2Discard) {
        if (s->fmu_type == fmi2CoSimulation && !(s->mask & FZ_STEP_COMPLETE))
            fz_fail("fmi2DoStep returned fmi2Discard in state %s", mask_text(s->mask));
        s->mask = FZ_STEP_FAILED;
    }
    if (!accepted && st != fmi2Discard) return;
    fmi2Real last = NAN;
    if (CALL(fmi2GetRealStatus, s->c, fmi2LastSuccessfulTime, &last) != fmi2OK)
        fz_fail("fmi2GetRealStatus(fmi2LastSuccessfulTime) failed after fmi2DoStep returned %d", (int)st);
    if (accepted && last != tc + h)
        fz_fail("fmi2DoStep returned %d (the step accepted), and the last successful time is %.17g, not the "
                "communication point %.17g + %.17g", (int)st, last, tc, h);
    if (st == fmi2Discard && !(last >= (isnan(s->t) ? -INFINITY : fmin(s->t, tc) - 1e-9 * fabs(tc)) && last < tc + h))
        fz_fail("fmi2DoStep returned fmi2Discard, and the last successful time %.17g is not in [%.17g, %.17g)", last,
                s->t, tc + h);
    s->t = last;
    if (undriven && accepted && fz_energy_read(s, get_reals, get_int, after)) fz_energy_check(s, before, after, tc, h);
}

static void k_cancel(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)r;
    if (CALL(fmi2CancelStep, s->c) == fmi2OK) fz_fail("fmi2CancelStep returned fmi2OK: there is no asynchronous step");
}

static void k_status(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx;
    uint8_t k = fz_u8(r), kind = fz_u8(r);
    fmi2StatusKind sk = (fmi2StatusKind)(kind % 5 == 4 ? 99 : kind % 5);
    int null_value = kind >= 250;
    union {
        fmi2Status st;
        fmi2Real x;
        fmi2Integer i;
        fmi2Boolean b;
        fmi2String str;
    } v;
    fmi2Status st;
    switch (k % 5) {
    case 0: st = CALL(fmi2GetStatus, s->c, sk, null_value ? NULL : &v.st); break;
    case 1: st = CALL(fmi2GetRealStatus, s->c, sk, null_value ? NULL : &v.x); break;
    case 2: st = CALL(fmi2GetIntegerStatus, s->c, sk, null_value ? NULL : &v.i); break;
    case 3: st = CALL(fmi2GetBooleanStatus, s->c, sk, null_value ? NULL : &v.b); break;
    default:
        st = CALL(fmi2GetStringStatus, s->c, sk, null_value ? NULL : &v.str);
        if (st == fmi2OK && !v.str) fz_fail("fmi2GetStringStatus returned fmi2OK and NULL");
    }
    /* Co-Simulation functions: never for Model Exchange (the states of Co-Simulation are left open) */
    outcome(s, "fmi2Get*Status", fz_by_type(s, FZ_ANY3, 0u), st, 0);
}

static void k_version(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)ctx, (void)s, (void)r;
    fz_begin("fmi2GetVersion");
    const char *v = fmi2GetVersion(), *p = fmi2GetTypesPlatform();
    fz_end();
    if (!v || strcmp(v, fmi2Version) != 0 || !p || strcmp(p, fmi2TypesPlatform) != 0)
        fz_fail("fmi2GetVersion/fmi2GetTypesPlatform: '%s' '%s'", v ? v : "(null)", p ? p : "(null)");
}

static const fz_call calls[] = {
    {0, "fmi2Instantiate", k_instantiate, 1, FZ_RUN_DRIVES},
    {1, "fmi2FreeInstance", k_free, 0, FZ_RUN_KEEPS},
    {2, "fmi2SetDebugLogging", k_debug_logging, 0, FZ_RUN_KEEPS},
    {3, "fmi2SetupExperiment", k_setup, 0, FZ_RUN_STARTS},
    {4, "fmi2EnterInitializationMode", k_enter_init, 0, FZ_RUN_STARTS},
    {5, "fmi2ExitInitializationMode", k_exit_init, 0, FZ_RUN_STARTS},
    {6, "fmi2Terminate", k_terminate, 0, FZ_RUN_DRIVES},
    {7, "fmi2Reset", k_reset, 0, FZ_RUN_DRIVES},
    {8, "fmi2SetReal", k_set_real, 0, FZ_RUN_STARTS},
    {9, "fmi2SetInteger", k_set_integer, 0, FZ_RUN_STARTS},
    {10, "fmi2SetBoolean", k_set_boolean, 0, FZ_RUN_STARTS},
    {11, "fmi2SetString", k_set_string, 0, FZ_RUN_STARTS},
    {12, "fmi2Get*", k_get, 0, FZ_RUN_KEEPS},
    {13, "fmi2GetFMUstate", k_get_state, 0, FZ_RUN_KEEPS},
    {14, "fmi2SetFMUstate", k_set_state, 0, FZ_RUN_DRIVES},
    {15, "fmi2FreeFMUstate", k_free_state, 0, FZ_RUN_KEEPS},
    {16, "fmi2SerializeFMUstate", k_serialize, 0, FZ_RUN_KEEPS},
    {17, "fmi2DeSerializeFMUstate (a serialized state, altered)", k_deserialize, 0, FZ_RUN_DRIVES},
    {18, "fmi2DeSerializeFMUstate (bytes of the input)", k_deserialize_raw, 0, FZ_RUN_DRIVES},
    {19, "fmi2GetDirectionalDerivative", k_directional, 0, FZ_RUN_KEEPS},
    {20, "fmi2SetRealInputDerivatives", k_input_derivatives, 0, FZ_RUN_DRIVES},
    {21, "fmi2GetRealOutputDerivatives", k_output_derivatives, 0, FZ_RUN_KEEPS},
    {22, "fmi2DoStep", k_do_step, 0, FZ_RUN_KEEPS},
    {23, "fmi2DoStep", k_do_step, 0, FZ_RUN_KEEPS}, /* twice the weight: stepping is where the work is */
    {24, "fmi2CancelStep", k_cancel, 0, FZ_RUN_KEEPS},
    {25, "fmi2Get*Status", k_status, 0, FZ_RUN_KEEPS},
    {26, "fmi2GetVersion", k_version, 0, FZ_RUN_KEEPS},
};

const fz_interface fz_fmi2 = {"FMI 2.0 Co-Simulation", fmi2_available, calls, sizeof calls / sizeof calls[0], release, 2};
