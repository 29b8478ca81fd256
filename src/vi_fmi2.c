/*
 * vi_fmi2.c - FMI 2.0 Co-Simulation glue: argument and state-machine checks, value references
 * (through vi_variable_table), logging, FMU state. All physics lives in vi_sim / vi_model.
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fmi2Functions.h"
#include "vi_sim.h"
#include "vi_variables.h"

/* ---- instance ---------------------------------------------------------------------------- */

typedef enum {
    ST_INSTANTIATED = 1 << 0,
    ST_INIT = 1 << 1,
    ST_STEP_COMPLETE = 1 << 2,
    ST_STEP_FAILED = 1 << 3,
    ST_TERMINATED = 1 << 4,
    ST_ERROR = 1 << 5,
    ST_FATAL = 1 << 6,
} vi_fmu_state;

#define ST_ANY_BUT_FATAL (ST_INSTANTIATED | ST_INIT | ST_STEP_COMPLETE | ST_STEP_FAILED | ST_TERMINATED | ST_ERROR)
#define ST_READABLE (ST_INIT | ST_STEP_COMPLETE | ST_STEP_FAILED | ST_TERMINATED | ST_ERROR)
#define ST_WRITABLE (ST_INSTANTIATED | ST_INIT | ST_STEP_COMPLETE)
#define ST_RUNNING (ST_STEP_COMPLETE | ST_STEP_FAILED | ST_TERMINATED)

/* Log categories, as listed in modelDescription.xml. Errors are logged whatever is enabled. */
#define VI_LOG_CATEGORIES(C) C(logEvents) C(logSolver) C(logStatusWarning) C(logStatusError) C(logFmi2Call) C(logAll)
#define VI_CAT_ENUM_(name) CAT_##name,
enum { VI_LOG_CATEGORIES(VI_CAT_ENUM_) CAT_COUNT };
#define VI_CAT_NAME_(name) #name,
static const char *const category_names[CAT_COUNT] = {VI_LOG_CATEGORIES(VI_CAT_NAME_)};

typedef struct {
    vi_sim sim;
    fmi2CallbackFunctions cb;
    char *name;
    vi_fmu_state state;
    unsigned log_mask; /* bit per category */
    int stop_time_defined;
    double stop_time;
} Component;

static int enabled(const Component *c, int cat) { return (c->log_mask >> cat & 1u) || (c->log_mask >> CAT_logAll & 1u); }

static void vlog(const Component *c, fmi2Status status, int cat, const char *fmt, va_list ap)
{
    if (!c->cb.logger || (status < fmi2Discard && !enabled(c, cat))) return; /* discard, error: always */
    char text[1024], escaped[2 * sizeof text];
    vsnprintf(text, sizeof text, fmt, ap);
    size_t j = 0; /* the logger treats the message as a format: escape '%' */
    for (size_t i = 0; text[i] && j + 2 < sizeof escaped; i++) {
        if (text[i] == '%') escaped[j++] = '%';
        escaped[j++] = text[i];
    }
    escaped[j] = '\0';
    c->cb.logger(c->cb.componentEnvironment, c->name, status, category_names[cat], escaped);
}

static void logf_(const Component *c, fmi2Status status, int cat, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vlog(c, status, cat, fmt, ap);
    va_end(ap);
}
#define LOG_ERROR(c, ...) logf_(c, fmi2Error, CAT_logStatusError, __VA_ARGS__)
#define LOG_CALL(c, ...) do { if (enabled(c, CAT_logFmi2Call)) logf_(c, fmi2OK, CAT_logFmi2Call, __VA_ARGS__); } while (0)

/* Logger handed to the simulation layer. */
static void sim_log(void *env, int category, const char *fmt, ...)
{
    const Component *c = env;
    static const int cat_of[] = {[VI_LOG_EVENTS] = CAT_logEvents, [VI_LOG_SOLVER] = CAT_logSolver,
                                 [VI_LOG_WARNING] = CAT_logStatusWarning, [VI_LOG_ERROR] = CAT_logStatusError};
    static const fmi2Status status_of[] = {[VI_LOG_EVENTS] = fmi2OK, [VI_LOG_SOLVER] = fmi2OK,
                                           [VI_LOG_WARNING] = fmi2Warning, [VI_LOG_ERROR] = fmi2Error};
    va_list ap;
    va_start(ap, fmt);
    vlog(c, status_of[category], cat_of[category], fmt, ap);
    va_end(ap);
}

static const char *state_name(vi_fmu_state s)
{
    switch (s) {
    case ST_INSTANTIATED: return "instantiated";
    case ST_INIT: return "initialization mode";
    case ST_STEP_COMPLETE: return "step complete";
    case ST_STEP_FAILED: return "step failed";
    case ST_TERMINATED: return "terminated";
    case ST_ERROR: return "error";
    default: return "fatal";
    }
}

/* Every function that takes a component starts here: NULL check, state check, call log. */
static Component *enter(fmi2Component comp, const char *fn, unsigned allowed)
{
    Component *c = comp;
    if (!c) return NULL;
    if (!(c->state & allowed)) {
        LOG_ERROR(c, "%s: not allowed in state '%s'", fn, state_name(c->state));
        return NULL;
    }
    LOG_CALL(c, "%s", fn);
    return c;
}
#define ENTER(fn, allowed)                         \
    Component *c = enter(comp, fn, allowed);       \
    if (!c) return fmi2Error

/* A failed simulation call: log the reason and put the instance into the error state. */
static fmi2Status fail(Component *c, const char *fn)
{
    LOG_ERROR(c, "%s: %s", fn, c->sim.msg);
    c->state = ST_ERROR;
    return fmi2Error;
}

/* ---- common functions --------------------------------------------------------------------- */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    ENTER("fmi2SetDebugLogging", ST_ANY_BUT_FATAL);
    if (nCategories > 0 && !categories) {
        LOG_ERROR(c, "fmi2SetDebugLogging: categories is NULL");
        return fmi2Error;
    }
    unsigned mask = 0;
    for (size_t i = 0; i < nCategories; i++) {
        int k = 0;
        while (k < CAT_COUNT && (!categories[i] || strcmp(categories[i], category_names[k]) != 0)) k++;
        if (k == CAT_COUNT) {
            LOG_ERROR(c, "fmi2SetDebugLogging: unknown log category '%s'", categories[i] ? categories[i] : "(null)");
            return fmi2Error;
        }
        mask |= 1u << k;
    }
    if (nCategories == 0) mask = (1u << CAT_COUNT) - 1u;
    c->log_mask = loggingOn ? c->log_mask | mask : c->log_mask & ~mask;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    (void)fmuResourceLocation, (void)visible;
    if (!functions || !functions->logger) return NULL; /* nobody to tell */
    Component tmp = {.cb = *functions, .name = (char *)(instanceName ? instanceName : "?")};
    if (!functions->allocateMemory || !functions->freeMemory) {
        LOG_ERROR(&tmp, "fmi2Instantiate: the callbacks allocateMemory and freeMemory are required");
        return NULL;
    }
    if (!instanceName || !*instanceName) {
        LOG_ERROR(&tmp, "fmi2Instantiate: instanceName must be a non-empty string");
        return NULL;
    }
    if (fmuType != fmi2CoSimulation) {
        LOG_ERROR(&tmp, "fmi2Instantiate: VibroImpact is a Co-Simulation FMU; fmuType %d is not supported", (int)fmuType);
        return NULL;
    }
    if (!fmuGUID || strcmp(fmuGUID, VI_GUID) != 0) {
        LOG_ERROR(&tmp, "fmi2Instantiate: GUID '%s' does not match this FMU's '%s'", fmuGUID ? fmuGUID : "(null)", VI_GUID);
        return NULL;
    }
    Component *c = functions->allocateMemory(1, sizeof *c);
    char *name = functions->allocateMemory(strlen(instanceName) + 1, 1);
    if (!c || !name) {
        LOG_ERROR(&tmp, "fmi2Instantiate: out of memory");
        if (c) functions->freeMemory(c);
        if (name) functions->freeMemory(name);
        return NULL;
    }
    memset(c, 0, sizeof *c);
    strcpy(name, instanceName);
    c->cb = *functions;
    c->name = name;
    c->state = ST_INSTANTIATED;
    c->log_mask = loggingOn ? (1u << CAT_COUNT) - 1u : 0u;
    vi_sim_init(&c->sim, sim_log, c);
    LOG_CALL(c, "fmi2Instantiate: %s", instanceName);
    return c;
}

void fmi2FreeInstance(fmi2Component comp)
{
    Component *c = comp;
    if (!c) return;
    LOG_CALL(c, "fmi2FreeInstance");
    vi_sim_free(&c->sim);
    fmi2CallbackFreeMemory free_memory = c->cb.freeMemory;
    free_memory(c->name);
    free_memory(c);
}

fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    ENTER("fmi2SetupExperiment", ST_INSTANTIATED);
    if (!isfinite(startTime) || (toleranceDefined && !(tolerance > 0.0 && tolerance < 1.0)) ||
        (stopTimeDefined && !(stopTime >= startTime))) {
        LOG_ERROR(c, "fmi2SetupExperiment: need a finite start time, a tolerance in (0, 1) and stop time >= start "
                     "time (got start %g, tolerance %g, stop %g)", startTime, tolerance, stopTime);
        return fmi2Error;
    }
    c->sim.d.t_start = startTime;
    c->sim.d.tolerance = toleranceDefined ? tolerance : 0.0;
    c->stop_time_defined = stopTimeDefined != 0;
    c->stop_time = stopTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component comp)
{
    ENTER("fmi2EnterInitializationMode", ST_INSTANTIATED);
    c->state = ST_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component comp)
{
    ENTER("fmi2ExitInitializationMode", ST_INIT);
    if (vi_sim_initialize(&c->sim) < 0) return fail(c, "fmi2ExitInitializationMode");
    logf_(c, fmi2OK, CAT_logEvents, "initial mode %d, delta = %.9g m, v = %.9g m/s", c->sim.d.M.mode, c->sim.d.x[0],
          c->sim.d.x[1]);
    c->state = ST_STEP_COMPLETE;
    return fmi2OK;
}

static void log_statistics(const Component *c)
{
    vi_solver_stats st;
    vi_sim_statistics(&c->sim, &st);
    logf_(c, fmi2OK, CAT_logSolver,
          "CVODE statistics: %ld steps, %ld rhs evaluations, %ld Jacobian evaluations, %ld nonlinear iterations, "
          "%ld nonlinear failures, %ld error test failures, %ld guard evaluations, %ld restarts, %ld events",
          st.steps, st.rhs_evals, st.jac_evals, st.nonlin_iters, st.nonlin_fails, st.err_test_fails, st.guard_evals,
          st.resets, c->sim.d.n_events);
}

fmi2Status fmi2Terminate(fmi2Component comp)
{
    ENTER("fmi2Terminate", ST_STEP_COMPLETE | ST_STEP_FAILED);
    log_statistics(c);
    c->state = ST_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component comp)
{
    ENTER("fmi2Reset", ST_ANY_BUT_FATAL);
    vi_sim_reset(&c->sim);
    c->stop_time_defined = 0;
    c->state = ST_INSTANTIATED;
    return fmi2OK;
}

/* ---- variables ---------------------------------------------------------------------------- */

static void *storage(Component *c, const vi_variable *v)
{
    switch (v->group) {
    case VI_GROUP_PARAMETERS: return (char *)&c->sim.d.par + v->offset;
    case VI_GROUP_INPUTS: return (char *)&c->sim.d.in + v->offset;
    default: return NULL; /* outputs are computed on demand */
    }
}

/* The variable behind vr if it is accessed through the API type `api` (Real, Integer or Boolean;
 * enumerations go through Integer); NULL (logged) otherwise. */
static const vi_variable *lookup(Component *c, const char *fn, fmi2ValueReference vr, vi_type api)
{
    if (vr >= VI_NVARS) {
        LOG_ERROR(c, "%s: unknown value reference %u", fn, (unsigned)vr);
        return NULL;
    }
    const vi_variable *v = &vi_variable_table[vr];
    vi_type t = v->type == VI_Enumeration ? VI_Integer : v->type;
    if (t != api) {
        static const char *const type_names[] = {"Real", "Integer", "Boolean", "Enumeration"};
        LOG_ERROR(c, "%s: value reference %u (%s) is of type %s", fn, (unsigned)vr, v->name, type_names[v->type]);
        return NULL;
    }
    return v;
}

/* Outputs and calculated parameters: computed from the current state (in initialization mode from
 * the initial state the current parameters give). */
static int current_outputs(Component *c, const char *fn, vi_outputs *out)
{
    if (c->state == ST_INIT && vi_sim_prepare(&c->sim) < 0) {
        LOG_ERROR(c, "%s: %s", fn, c->sim.msg);
        return -1;
    }
    vi_sim_outputs(&c->sim, out);
    return 0;
}

#define DEFINE_GET(Api, ctype, api_type)                                                                       \
    fmi2Status fmi2Get##Api(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, ctype value[])    \
    {                                                                                                          \
        ENTER("fmi2Get" #Api, ST_READABLE);                                                                    \
        if (nvr > 0 && (!vr || !value)) {                                                                      \
            LOG_ERROR(c, "fmi2Get" #Api ": NULL array");                                                       \
            return fmi2Error;                                                                                  \
        }                                                                                                      \
        vi_outputs out;                                                                                        \
        int have_out = 0;                                                                                      \
        for (size_t i = 0; i < nvr; i++) {                                                                     \
            const vi_variable *v = lookup(c, "fmi2Get" #Api, vr[i], api_type);                                \
            if (!v) return fmi2Error;                                                                          \
            const void *p = storage(c, v);                                                                     \
            if (!p) {                                                                                          \
                if (!have_out && current_outputs(c, "fmi2Get" #Api, &out) < 0) return fmi2Error;              \
                have_out = 1;                                                                                  \
                p = (const char *)&out + v->offset;                                                            \
            }                                                                                                  \
            value[i] = (ctype) * (const VI_CTYPE_##Api *)p;                                                    \
        }                                                                                                      \
        return fmi2OK;                                                                                         \
    }
DEFINE_GET(Real, fmi2Real, VI_Real)
DEFINE_GET(Integer, fmi2Integer, VI_Integer)
DEFINE_GET(Boolean, fmi2Boolean, VI_Boolean)

/* May v be set now? Inputs: before and after initialization; fixed parameters: until the end of
 * initialization mode; nothing else ever. */
static int settable(Component *c, const char *fn, const vi_variable *v)
{
    if (v->group == VI_GROUP_INPUTS) return 1;
    if (v->group == VI_GROUP_PARAMETERS && (c->state & (ST_INSTANTIATED | ST_INIT))) return 1;
    if (v->group == VI_GROUP_PARAMETERS)
        LOG_ERROR(c, "%s: %s is a fixed parameter: set it before fmi2ExitInitializationMode (or after fmi2Reset)", fn,
                  v->name);
    else
        LOG_ERROR(c, "%s: %s is an %s and cannot be set", fn, v->name, v->causality);
    return 0;
}

#define DEFINE_SET(Api, ctype, api_type, check)                                                                \
    fmi2Status fmi2Set##Api(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, const ctype value[]) \
    {                                                                                                          \
        ENTER("fmi2Set" #Api, ST_WRITABLE);                                                                    \
        if (nvr > 0 && (!vr || !value)) {                                                                      \
            LOG_ERROR(c, "fmi2Set" #Api ": NULL array");                                                       \
            return fmi2Error;                                                                                  \
        }                                                                                                      \
        for (size_t i = 0; i < nvr; i++) {                                                                     \
            const vi_variable *v = lookup(c, "fmi2Set" #Api, vr[i], api_type);                                \
            if (!v || !settable(c, "fmi2Set" #Api, v)) return fmi2Error;                                       \
            if (!(check)) {                                                                                    \
                LOG_ERROR(c, "fmi2Set" #Api ": %s must be finite", v->name);                                   \
                return fmi2Error;                                                                              \
            }                                                                                                  \
        }                                                                                                      \
        for (size_t i = 0; i < nvr; i++) {                                                                     \
            const vi_variable *v = &vi_variable_table[vr[i]];                                                  \
            *(VI_CTYPE_##Api *)storage(c, v) = (VI_CTYPE_##Api)value[i];                                       \
            if (v->group == VI_GROUP_INPUTS) { /* a new value: zero-order hold until a derivative is set */ \
                *(double *)((char *)&c->sim.d.din + v->offset) = 0.0;                                          \
                c->sim.d.inputs_changed = 1;                                                                   \
            }                                                                                                  \
        }                                                                                                      \
        return fmi2OK;                                                                                         \
    }
DEFINE_SET(Real, fmi2Real, VI_Real, isfinite(value[i]))
DEFINE_SET(Integer, fmi2Integer, VI_Integer, 1)
DEFINE_SET(Boolean, fmi2Boolean, VI_Boolean, 1)

/* There are no String variables: any value reference is an error. */
static fmi2Status no_strings(Component *c, const char *fn, const fmi2ValueReference vr[], size_t nvr)
{
    if (nvr == 0) return fmi2OK;
    if (!vr || vr[0] >= VI_NVARS) LOG_ERROR(c, "%s: unknown value reference", fn);
    else LOG_ERROR(c, "%s: value reference %u (%s) is not a String", fn, (unsigned)vr[0], vi_variable_table[vr[0]].name);
    return fmi2Error;
}

fmi2Status fmi2GetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    (void)value;
    ENTER("fmi2GetString", ST_READABLE);
    return no_strings(c, "fmi2GetString", vr, nvr);
}

fmi2Status fmi2SetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    (void)value;
    ENTER("fmi2SetString", ST_WRITABLE);
    return no_strings(c, "fmi2SetString", vr, nvr);
}

/* ---- FMU state ---------------------------------------------------------------------------- */

#define VI_STATE_MAGIC 0x56494d55u /* "VIMU" */
#define VI_STATE_VERSION 1u

typedef struct {
    unsigned magic, version, size, fmu_state;
    vi_sim_data data;
} vi_saved_state;

fmi2Status fmi2GetFMUstate(fmi2Component comp, fmi2FMUstate *FMUstate)
{
    ENTER("fmi2GetFMUstate", ST_RUNNING);
    if (!FMUstate) {
        LOG_ERROR(c, "fmi2GetFMUstate: FMUstate is NULL");
        return fmi2Error;
    }
    if (vi_sim_checkpoint(&c->sim) < 0) return fail(c, "fmi2GetFMUstate"); /* contract C7 */
    vi_saved_state *s = *FMUstate ? *FMUstate : c->cb.allocateMemory(1, sizeof *s);
    if (!s) {
        LOG_ERROR(c, "fmi2GetFMUstate: out of memory");
        return fmi2Error;
    }
    *s = (vi_saved_state){VI_STATE_MAGIC, VI_STATE_VERSION, (unsigned)sizeof *s, (unsigned)c->state, c->sim.d};
    *FMUstate = s;
    return fmi2OK;
}

static int valid_state(const vi_saved_state *s)
{
    return s && s->magic == VI_STATE_MAGIC && s->version == VI_STATE_VERSION && s->size == sizeof *s &&
           (s->fmu_state & ST_RUNNING);
}

fmi2Status fmi2SetFMUstate(fmi2Component comp, fmi2FMUstate FMUstate)
{
    ENTER("fmi2SetFMUstate", ST_RUNNING | ST_ERROR);
    const vi_saved_state *s = FMUstate;
    if (!valid_state(s)) {
        LOG_ERROR(c, "fmi2SetFMUstate: not a state of this FMU");
        return fmi2Error;
    }
    c->sim.d = s->data;
    if (vi_sim_restore(&c->sim) < 0) return fail(c, "fmi2SetFMUstate");
    c->state = (vi_fmu_state)s->fmu_state;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component comp, fmi2FMUstate *FMUstate)
{
    ENTER("fmi2FreeFMUstate", ST_ANY_BUT_FATAL);
    if (FMUstate && *FMUstate) {
        c->cb.freeMemory(*FMUstate);
        *FMUstate = NULL;
    }
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component comp, fmi2FMUstate FMUstate, size_t *size)
{
    ENTER("fmi2SerializedFMUstateSize", ST_ANY_BUT_FATAL);
    if (!size || !valid_state(FMUstate)) {
        LOG_ERROR(c, "fmi2SerializedFMUstateSize: invalid arguments");
        return fmi2Error;
    }
    *size = sizeof(vi_saved_state);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component comp, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size)
{
    ENTER("fmi2SerializeFMUstate", ST_ANY_BUT_FATAL);
    if (!serializedState || size < sizeof(vi_saved_state) || !valid_state(FMUstate)) {
        LOG_ERROR(c, "fmi2SerializeFMUstate: invalid arguments (need %zu bytes)", sizeof(vi_saved_state));
        return fmi2Error;
    }
    memcpy(serializedState, FMUstate, sizeof(vi_saved_state));
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{
    ENTER("fmi2DeSerializeFMUstate", ST_ANY_BUT_FATAL);
    vi_saved_state tmp;
    if (!serializedState || !FMUstate || size != sizeof tmp) {
        LOG_ERROR(c, "fmi2DeSerializeFMUstate: invalid arguments (expected %zu bytes, got %zu)", sizeof tmp, size);
        return fmi2Error;
    }
    memcpy(&tmp, serializedState, sizeof tmp);
    if (!valid_state(&tmp)) {
        LOG_ERROR(c, "fmi2DeSerializeFMUstate: the bytes are not a serialized state of this FMU version");
        return fmi2Error;
    }
    vi_saved_state *s = *FMUstate ? *FMUstate : c->cb.allocateMemory(1, sizeof *s);
    if (!s) {
        LOG_ERROR(c, "fmi2DeSerializeFMUstate: out of memory");
        return fmi2Error;
    }
    *s = tmp;
    *FMUstate = s;
    return fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component comp, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    (void)vUnknown_ref, (void)nUnknown, (void)vKnown_ref, (void)nKnown, (void)dvKnown, (void)dvUnknown;
    ENTER("fmi2GetDirectionalDerivative", ST_ANY_BUT_FATAL);
    LOG_ERROR(c, "fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative=false)");
    return fmi2Error;
}

/* ---- co-simulation ------------------------------------------------------------------------ */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    ENTER("fmi2SetRealInputDerivatives", ST_WRITABLE);
    if (nvr > 0 && (!vr || !order || !value)) {
        LOG_ERROR(c, "fmi2SetRealInputDerivatives: NULL array");
        return fmi2Error;
    }
    for (size_t i = 0; i < nvr; i++) {
        const vi_variable *v = lookup(c, "fmi2SetRealInputDerivatives", vr[i], VI_Real);
        if (!v) return fmi2Error;
        if (v->group != VI_GROUP_INPUTS || order[i] != 1 || !isfinite(value[i])) {
            LOG_ERROR(c, "fmi2SetRealInputDerivatives: %s order %d = %g: only finite first derivatives of inputs",
                      v->name, (int)order[i], value[i]);
            return fmi2Error;
        }
    }
    for (size_t i = 0; i < nvr; i++) {
        *(double *)((char *)&c->sim.d.din + vi_variable_table[vr[i]].offset) = value[i];
        c->sim.d.inputs_changed = 1;
    }
    return fmi2OK;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr, (void)nvr, (void)order, (void)value;
    ENTER("fmi2GetRealOutputDerivatives", ST_READABLE);
    LOG_ERROR(c, "fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder=0)");
    return fmi2Error;
}

fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    ENTER("fmi2DoStep", ST_STEP_COMPLETE);
    double tc = currentCommunicationPoint, h = communicationStepSize, t = c->sim.d.t;
    double eps = 1e3 * DBL_EPSILON * fmax(1.0, fabs(t));
    if (!isfinite(tc) || !isfinite(h) || !(h > 0.0)) {
        LOG_ERROR(c, "fmi2DoStep: the communication step size must be finite and positive (got %g)", h);
        return fmi2Error;
    }
    if (fabs(tc - t) > eps) {
        LOG_ERROR(c, "fmi2DoStep: currentCommunicationPoint %.17g does not match the FMU's time %.17g", tc, t);
        return fmi2Error;
    }
    if (c->stop_time_defined && tc + h > c->stop_time + eps) {
        LOG_ERROR(c, "fmi2DoStep: the step to %.17g passes the stop time %.17g", tc + h, c->stop_time);
        return fmi2Error;
    }
    int rc = vi_sim_advance(&c->sim, tc + h);
    if (rc == VI_SIM_DISCARD) { /* contract C1: stopped at c->sim.d.t (fmi2LastSuccessfulTime) */
        logf_(c, fmi2Discard, CAT_logStatusWarning, "fmi2DoStep: %s", c->sim.msg);
        c->state = ST_STEP_FAILED;
        return fmi2Discard;
    }
    if (rc != VI_SIM_OK) return fail(c, "fmi2DoStep");
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component comp)
{
    ENTER("fmi2CancelStep", ST_ANY_BUT_FATAL);
    LOG_ERROR(c, "fmi2CancelStep: fmi2DoStep is synchronous; there is nothing to cancel");
    return fmi2Error;
}

fmi2Status fmi2GetStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s, (void)value;
    ENTER("fmi2GetStatus", ST_RUNNING);
    logf_(c, fmi2Discard, CAT_logStatusWarning, "fmi2GetStatus: no asynchronous step is pending");
    return fmi2Discard;
}

fmi2Status fmi2GetRealStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Real *value)
{
    ENTER("fmi2GetRealStatus", ST_RUNNING | ST_ERROR);
    if (s != fmi2LastSuccessfulTime || !value) return fmi2Discard;
    *value = c->sim.d.t;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s, (void)value;
    ENTER("fmi2GetIntegerStatus", ST_RUNNING);
    return fmi2Discard;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Boolean *value)
{
    ENTER("fmi2GetBooleanStatus", ST_RUNNING | ST_ERROR);
    if (s != fmi2Terminated || !value) return fmi2Discard;
    *value = fmi2False; /* the FMU never asks to end the simulation */
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component comp, const fmi2StatusKind s, fmi2String *value)
{
    (void)s, (void)value;
    ENTER("fmi2GetStringStatus", ST_RUNNING);
    return fmi2Discard;
}
