/*
 * vi_fmi2.c - the generic FMI 2.0 Co-Simulation layer (vi_fmu.h): argument and state-machine
 * checks, value access through the model's variable table, logging with categories, the FMU state
 * envelope and its serialization, status functions, fmi2DoStep checks. It knows no model: it
 * reaches the one model of this binary through vi_fmu_this_model and its hooks.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fmi2Functions.h"
#include "vi_fmu.h"

#define MODEL (&vi_fmu_this_model)

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

/* Log categories, as listed in modelDescription.xml. Discards and errors are logged whatever is enabled. */
#define VI_LOG_CATEGORIES(C) \
    C(logEvents) C(logSolver) C(logStatusWarning) C(logStatusDiscard) C(logStatusError) C(logFmi2Call) C(logAll)
#define VI_CAT_ENUM_(name) CAT_##name,
enum { VI_LOG_CATEGORIES(VI_CAT_ENUM_) CAT_COUNT };
#define VI_CAT_NAME_(name) #name,
static const char *const category_names[CAT_COUNT] = {VI_LOG_CATEGORIES(VI_CAT_NAME_)};

typedef struct {
    void *model;   /* the model's instance (MODEL->instance_size bytes) */
    void *outputs; /* scratch for outputs computed on demand (MODEL->outputs_size bytes) */
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
    if (!c->cb.logger || (status < fmi2Discard && !enabled(c, cat))) return;
    char text[1024], escaped[4 * sizeof text];
    vsnprintf(text, sizeof text, fmt, ap);
    /* the logger treats the message as a format: '%' as "%%"; a byte that is no printable ASCII (a
     * control character of an instance name or a String value the importer gave) as \xNN */
    size_t j = 0;
    for (size_t i = 0; text[i] && j + 4 < sizeof escaped; i++) {
        unsigned char ch = (unsigned char)text[i];
        if (ch < 0x20 || ch > 0x7e) {
            j += (size_t)snprintf(escaped + j, sizeof escaped - j, "\\x%02x", ch);
            continue;
        }
        if (ch == '%') escaped[j++] = '%';
        escaped[j++] = (char)ch;
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

/* Logger handed to the model. */
static void model_log(void *env, int category, const char *fmt, ...)
{
    const Component *c = env;
    static const int cat_of[] = {[VI_FMU_LOG_EVENTS] = CAT_logEvents, [VI_FMU_LOG_SOLVER] = CAT_logSolver,
                                 [VI_FMU_LOG_WARNING] = CAT_logStatusWarning, [VI_FMU_LOG_ERROR] = CAT_logStatusError};
    static const fmi2Status status_of[] = {[VI_FMU_LOG_EVENTS] = fmi2OK, [VI_FMU_LOG_SOLVER] = fmi2OK,
                                           [VI_FMU_LOG_WARNING] = fmi2Warning, [VI_FMU_LOG_ERROR] = fmi2Error};
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
    LOG_ERROR(c, "%s: %s", fn, MODEL->message(c->model));
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

static int hex_digit(char ch)
{
    if (ch >= '0' && ch <= '9') return ch - '0';
    if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
    return -1;
}

/* The local path of a file URI (file:///p, file:/p or file://localhost/p), percent-decoded, in a
 * new block of the importer's memory; NULL when the URI is missing or names no local file. */
static char *resource_path(const fmi2CallbackFunctions *cb, const char *uri)
{
    if (!uri || strncmp(uri, "file:", 5) != 0) return NULL;
    const char *p = uri + 5;
    if (strncmp(p, "///", 3) == 0) p += 2;
    else if (strncmp(p, "//localhost/", 12) == 0) p += 11;
    else if (strncmp(p, "//", 2) == 0) return NULL; /* another host */
    if (*p != '/') return NULL;
    char *path = cb->allocateMemory(strlen(p) + 1, 1);
    if (!path) return NULL;
    size_t j = 0;
    for (size_t i = 0; p[i]; i++) {
        int hi, lo;
        if (p[i] == '%' && (hi = hex_digit(p[i + 1])) >= 0 && (lo = hex_digit(p[i + 2])) >= 0) {
            path[j++] = (char)(hi * 16 + lo);
            i += 2;
        } else {
            path[j++] = p[i];
        }
    }
    path[j] = '\0';
    return path;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    (void)visible;
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
        LOG_ERROR(&tmp, "fmi2Instantiate: %s is a Co-Simulation FMU; fmuType %d is not supported",
                  MODEL->model_identifier, (int)fmuType);
        return NULL;
    }
    if (!fmuGUID || strcmp(fmuGUID, MODEL->guid) != 0) {
        LOG_ERROR(&tmp, "fmi2Instantiate: GUID '%s' does not match this FMU's '%s'", fmuGUID ? fmuGUID : "(null)",
                  MODEL->guid);
        return NULL;
    }
    Component *c = functions->allocateMemory(1, sizeof *c);
    char *name = functions->allocateMemory(strlen(instanceName) + 1, 1);
    void *model = functions->allocateMemory(1, MODEL->instance_size);
    void *outputs = functions->allocateMemory(1, MODEL->outputs_size);
    if (!c || !name || !model || !outputs) {
        LOG_ERROR(&tmp, "fmi2Instantiate: out of memory");
        void *blocks[] = {c, name, model, outputs};
        for (int i = 0; i < 4; i++)
            if (blocks[i]) functions->freeMemory(blocks[i]);
        return NULL;
    }
    memset(c, 0, sizeof *c);
    memset(model, 0, MODEL->instance_size);
    strcpy(name, instanceName);
    c->model = model;
    c->outputs = outputs;
    c->cb = *functions;
    c->name = name;
    c->state = ST_INSTANTIATED;
    c->log_mask = loggingOn ? (1u << CAT_COUNT) - 1u : 0u;
    MODEL->init(c->model, model_log, c);
    if (MODEL->set_resources) {
        char *dir = resource_path(functions, fmuResourceLocation);
        int rc = MODEL->set_resources(c->model, dir);
        if (dir) functions->freeMemory(dir);
        if (rc < 0) {
            LOG_ERROR(c, "fmi2Instantiate: resources '%s': %s", fmuResourceLocation ? fmuResourceLocation : "(null)",
                      MODEL->message(c->model));
            fmi2FreeInstance(c);
            return NULL;
        }
    }
    LOG_CALL(c, "fmi2Instantiate: %s", instanceName);
    return c;
}

void fmi2FreeInstance(fmi2Component comp)
{
    Component *c = comp;
    if (!c) return;
    LOG_CALL(c, "fmi2FreeInstance");
    MODEL->release(c->model);
    fmi2CallbackFreeMemory free_memory = c->cb.freeMemory;
    free_memory(c->outputs);
    free_memory(c->model);
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
    MODEL->setup_experiment(c->model, startTime, toleranceDefined != 0, tolerance);
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
    if (MODEL->initialize(c->model) < 0) return fail(c, "fmi2ExitInitializationMode");
    c->state = ST_STEP_COMPLETE;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component comp)
{
    ENTER("fmi2Terminate", ST_STEP_COMPLETE | ST_STEP_FAILED);
    if (MODEL->terminate) MODEL->terminate(c->model);
    c->state = ST_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component comp)
{
    ENTER("fmi2Reset", ST_ANY_BUT_FATAL);
    MODEL->reset(c->model);
    c->stop_time_defined = 0;
    c->state = ST_INSTANTIATED;
    return fmi2OK;
}

/* ---- variables ---------------------------------------------------------------------------- */

/* Where the value of v lives; NULL for outputs (computed on demand). */
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

static void *storage(Component *c, const vi_variable *v)
{
    if (v->group == VI_GROUP_OUTPUTS) return NULL;
    return (char *)group_in(MODEL->state(c->model), v->group) + v->offset;
}

/* The derivative of the Real input v. */
static double *derivative(Component *c, const vi_variable *v)
{
    return (double *)((char *)group_in(MODEL->state(c->model), VI_GROUP_INPUT_DERIVATIVES) + v->offset);
}

/* The variable behind vr if it is accessed through the API type `api` (Real, Integer or Boolean;
 * enumerations go through Integer); NULL (logged) otherwise. */
static const vi_variable *lookup(Component *c, const char *fn, fmi2ValueReference vr, vi_type api)
{
    if (vr >= (fmi2ValueReference)MODEL->nvariables) {
        LOG_ERROR(c, "%s: unknown value reference %u", fn, (unsigned)vr);
        return NULL;
    }
    const vi_variable *v = &MODEL->variables[vr];
    vi_type t = v->type == VI_Enumeration ? VI_Integer : v->type;
    if (t != api) {
        static const char *const type_names[] = {"Real", "Integer", "Boolean", "Enumeration", "String"};
        LOG_ERROR(c, "%s: value reference %u (%s) is of type %s", fn, (unsigned)vr, v->name, type_names[v->type]);
        return NULL;
    }
    return v;
}

/* Outputs and calculated parameters into c->outputs: computed from the current state (in
 * initialization mode from the initial state the current parameters give). */
static int current_outputs(Component *c, const char *fn)
{
    if (c->state == ST_INIT && MODEL->prepare(c->model) < 0) {
        LOG_ERROR(c, "%s: %s", fn, MODEL->message(c->model));
        return -1;
    }
    MODEL->outputs(c->model, c->outputs);
    return 0;
}

#define DEFINE_GET(Api, ctype, api_type, valid)                                                              \
    fmi2Status fmi2Get##Api(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, ctype value[])    \
    {                                                                                                        \
        ENTER("fmi2Get" #Api, ST_READABLE);                                                                  \
        if (nvr > 0 && (!vr || !value)) {                                                                    \
            LOG_ERROR(c, "fmi2Get" #Api ": NULL array");                                                     \
            return fmi2Error;                                                                                \
        }                                                                                                    \
        int have_out = 0;                                                                                    \
        for (size_t i = 0; i < nvr; i++) {                                                                   \
            const vi_variable *v = lookup(c, "fmi2Get" #Api, vr[i], api_type);                               \
            if (!v) return fmi2Error;                                                                        \
            const void *p = storage(c, v);                                                                   \
            if (!p) {                                                                                        \
                if (!have_out && current_outputs(c, "fmi2Get" #Api) < 0) return fmi2Error;                   \
                have_out = 1;                                                                                \
                p = (const char *)c->outputs + v->offset;                                                    \
            }                                                                                                \
            value[i] = (ctype) * (const VI_CTYPE_##Api *)p;                                                  \
            if (!(valid)) { /* an output without a value (after a failed initialization, say) */             \
                LOG_ERROR(c, "fmi2Get" #Api ": %s = %g has no value in state '%s'", v->name, (double)value[i], \
                          state_name(c->state));                                                             \
                return fmi2Error;                                                                            \
            }                                                                                                \
        }                                                                                                    \
        return fmi2OK;                                                                                       \
    }
DEFINE_GET(Real, fmi2Real, VI_Real, isfinite(value[i]))
DEFINE_GET(Integer, fmi2Integer, VI_Integer, 1)
DEFINE_GET(Boolean, fmi2Boolean, VI_Boolean, 1)

static int tunable(const vi_variable *v) { return strcmp(v->variability, "tunable") == 0; }

/* May v be set now? Inputs and tunable parameters: before and after initialization; fixed
 * parameters: until the end of initialization mode; nothing else ever. (The callers allow only
 * Instantiated, InitializationMode and StepComplete.) */
static int settable(Component *c, const char *fn, const vi_variable *v)
{
    if (v->group == VI_GROUP_INPUTS) return 1;
    if (v->group == VI_GROUP_PARAMETERS && ((c->state & (ST_INSTANTIATED | ST_INIT)) || tunable(v))) return 1;
    if (v->group == VI_GROUP_PARAMETERS)
        LOG_ERROR(c, "%s: %s is a fixed parameter: set it before fmi2ExitInitializationMode (or after fmi2Reset)", fn,
                  v->name);
    else
        LOG_ERROR(c, "%s: %s is an %s and cannot be set", fn, v->name, v->causality);
    return 0;
}

/* After a value was set: a new input value holds (zero-order) until a derivative is set; an input or
 * a tunable parameter set between steps takes effect at the start of the next step. */
static void changed(Component *c, const vi_variable *v)
{
    if (v->group == VI_GROUP_INPUTS && v->type == VI_Real)
        *derivative(c, v) = 0.0;
    if (v->group == VI_GROUP_INPUTS || c->state == ST_STEP_COMPLETE) MODEL->changed(c->model);
}

#define DEFINE_SET(Api, ctype, api_type, check, stored)                                                        \
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
            const vi_variable *v = &MODEL->variables[vr[i]];                                                   \
            *(VI_CTYPE_##Api *)storage(c, v) = (VI_CTYPE_##Api)(stored);                                       \
            changed(c, v);                                                                                     \
        }                                                                                                      \
        return fmi2OK;                                                                                         \
    }
DEFINE_SET(Real, fmi2Real, VI_Real, isfinite(value[i]), value[i])
DEFINE_SET(Integer, fmi2Integer, VI_Integer, 1, value[i])
DEFINE_SET(Boolean, fmi2Boolean, VI_Boolean, 1, value[i] != fmi2False) /* stored as 0 or 1 */

fmi2Status fmi2GetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    ENTER("fmi2GetString", ST_READABLE);
    if (nvr > 0 && (!vr || !value)) {
        LOG_ERROR(c, "fmi2GetString: NULL array");
        return fmi2Error;
    }
    for (size_t i = 0; i < nvr; i++) {
        const vi_variable *v = lookup(c, "fmi2GetString", vr[i], VI_String);
        if (!v) return fmi2Error;
        value[i] = storage(c, v); /* the stored value: valid until it is set again */
    }
    return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    ENTER("fmi2SetString", ST_WRITABLE);
    if (nvr > 0 && (!vr || !value)) {
        LOG_ERROR(c, "fmi2SetString: NULL array");
        return fmi2Error;
    }
    for (size_t i = 0; i < nvr; i++) {
        const vi_variable *v = lookup(c, "fmi2SetString", vr[i], VI_String);
        if (!v || !settable(c, "fmi2SetString", v)) return fmi2Error;
        if (!value[i]) {
            LOG_ERROR(c, "fmi2SetString: the value of %s is NULL", v->name);
            return fmi2Error;
        }
        size_t n = 0;
        while (n < VI_STRING_SIZE && value[i][n]) n++;
        if (n == VI_STRING_SIZE) {
            LOG_ERROR(c, "fmi2SetString: the value of %s is longer than %d characters", v->name, VI_STRING_SIZE - 1);
            return fmi2Error;
        }
    }
    for (size_t i = 0; i < nvr; i++) {
        const vi_variable *v = &MODEL->variables[vr[i]];
        char *p = storage(c, v);
        memmove(p, value[i], strlen(value[i]) + 1); /* the value may be our own (from fmi2GetString) */
        changed(c, v);
    }
    return fmi2OK;
}

/* ---- FMU state ---------------------------------------------------------------------------- */

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
    uint32_t fmu_state;         /* the FMI state it was taken in (one ST_* bit) */
    uint32_t stop_time_defined; /* fmi2SetupExperiment's stop time */
    double stop_time;
    uint64_t checksum;          /* hash (below) of all bytes, this field taken as 0 */
} vi_saved_state;

static size_t saved_size(void) { return sizeof(vi_saved_state) + MODEL->state_size; }
static void *payload(const vi_saved_state *s) { return (char *)s + sizeof *s; }

/* The checksum: FNV-1a's round (Fowler, Noll, Vo: xor, then multiply by the 64-bit FNV prime) on
 * 64-bit words instead of bytes, each followed by a xor-shift so that high bits feed back into low
 * ones, in four interleaved lanes (a state of a few kB then costs a fraction of a microsecond, where
 * byte-wise FNV-1a took 5 us on every fmi2GetFMUstate), the lanes and the tail bytes folded in at the
 * end. Every round is a bijection of its lane and of its word, so any change of a single word (a
 * single bit flip, say) changes the result. Start with h = VI_FNV_OFFSET. */
#define VI_FNV_OFFSET 0xcbf29ce484222325u
#define VI_FNV_PRIME 0x100000001b3u
#define VI_HASH_LANES 4
static uint64_t hash_round(uint64_t h, uint64_t w)
{
    h = (h ^ w) * VI_FNV_PRIME;
    return h ^ (h >> 32);
}

static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
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

static uint64_t model_id(void) { return fnv1a(VI_FNV_OFFSET, MODEL->guid, strlen(MODEL->guid)); }

static uint64_t checksum(const vi_saved_state *s)
{
    vi_saved_state head = *s;
    head.checksum = 0;
    return fnv1a(fnv1a(VI_FNV_OFFSET, &head, sizeof head), payload(s), MODEL->state_size);
}

/* Is enumeration value k an item of type? */
static int enum_item(const char *type, int k)
{
    for (int i = 0; i < MODEL->n_enum_items; i++)
        if (MODEL->enum_items[i].value == k && strcmp(MODEL->enum_items[i].type, type) == 0) return 1;
    return 0;
}

/* The table's values in a saved block: what the setters guarantee (finite Reals, Booleans 0 or 1,
 * terminated Strings) and, once running, enumeration items. 0, or -1 with the first bad one. */
static int check_values(const void *block, int running, char *msg, size_t n)
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
            if (!isfinite(x)) return snprintf(msg, n, "%s = %g is not finite", v->name, x), -1;
            if (v->group != VI_GROUP_INPUTS) break;
            memcpy(&dx, (const char *)group_in(block, VI_GROUP_INPUT_DERIVATIVES) + v->offset, sizeof dx);
            if (!isfinite(dx)) return snprintf(msg, n, "the derivative of %s = %g is not finite", v->name, dx), -1;
            break;
        case VI_String:
            if (!memchr(p, '\0', VI_STRING_SIZE)) return snprintf(msg, n, "%s is not a terminated string", v->name), -1;
            break;
        default:
            memcpy(&k, p, sizeof k);
            if (v->type == VI_Boolean && k != 0 && k != 1)
                return snprintf(msg, n, "%s = %d is not a Boolean", v->name, k), -1;
            if (running && strcmp(v->enumeration, "none") != 0 && !enum_item(v->enumeration, k))
                return snprintf(msg, n, "%s = %d is not an item of %s", v->name, k, v->enumeration), -1;
        }
    }
    return 0;
}

/* Was the saved FMI state after initialization? */
static int saved_running(const vi_saved_state *s) { return (s->fmu_state & (ST_RUNNING | ST_ERROR)) != 0; }

/* Is s (aligned, at least a header) a state of this FMU that may be used? Logs the first reason
 * why not. `size`: the bytes the caller has. */
static int check_saved(Component *c, const char *fn, const vi_saved_state *s, size_t size)
{
    char why[320] = "";
    if (!s) snprintf(why, sizeof why, "the state is NULL");
    else if (s->magic != VI_STATE_MAGIC) snprintf(why, sizeof why, "not an FMU state of this layer (magic number)");
    else if (s->version != VI_STATE_VERSION) snprintf(why, sizeof why, "an FMU state of another layer version");
    else if (s->model != model_id()) snprintf(why, sizeof why, "an FMU state of another model (GUID)");
    else if (s->size != saved_size() || size != saved_size())
        snprintf(why, sizeof why, "size %zu bytes: a state of this build of %s has %zu", size, MODEL->model_identifier,
                 saved_size());
    else if (s->checksum != checksum(s)) snprintf(why, sizeof why, "checksum mismatch: the state was altered");
    else if (!(s->fmu_state & ST_ANY_BUT_FATAL) || (s->fmu_state & (s->fmu_state - 1u)))
        snprintf(why, sizeof why, "field fmu_state = %u is not an FMI state", (unsigned)s->fmu_state);
    else if (s->stop_time_defined > 1u || (s->stop_time_defined && !isfinite(s->stop_time)))
        snprintf(why, sizeof why, "field stop_time is not finite");
    else if (check_values(payload(s), saved_running(s), why, sizeof why) < 0 ||
             (MODEL->state_check && MODEL->state_check(payload(s), saved_running(s), why, sizeof why) < 0)) {
        if (!why[0]) snprintf(why, sizeof why, "invalid field");
    }
    if (why[0]) LOG_ERROR(c, "%s: invalid FMU state: %s", fn, why);
    return why[0] == '\0';
}

fmi2Status fmi2GetFMUstate(fmi2Component comp, fmi2FMUstate *FMUstate)
{
    ENTER("fmi2GetFMUstate", ST_ANY_BUT_FATAL);
    if (!FMUstate) {
        LOG_ERROR(c, "fmi2GetFMUstate: FMUstate is NULL");
        return fmi2Error;
    }
    if ((c->state & ST_RUNNING) && MODEL->checkpoint && MODEL->checkpoint(c->model) != 0)
        return fail(c, "fmi2GetFMUstate");
    vi_saved_state *s = *FMUstate ? *FMUstate : c->cb.allocateMemory(1, saved_size());
    if (!s) {
        LOG_ERROR(c, "fmi2GetFMUstate: out of memory");
        return fmi2Error;
    }
    *s = (vi_saved_state){.magic = VI_STATE_MAGIC, .version = VI_STATE_VERSION, .size = saved_size(),
                          .model = model_id(), .fmu_state = (uint32_t)c->state,
                          .stop_time_defined = (uint32_t)c->stop_time_defined, .stop_time = c->stop_time};
    memcpy(payload(s), MODEL->state(c->model), MODEL->state_size);
    s->checksum = checksum(s);
    *FMUstate = s;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component comp, fmi2FMUstate FMUstate)
{
    ENTER("fmi2SetFMUstate", ST_ANY_BUT_FATAL);
    const vi_saved_state *s = FMUstate;
    if (!check_saved(c, "fmi2SetFMUstate", s, s ? s->size : 0)) return fmi2Error;
    memcpy(MODEL->state(c->model), payload(s), MODEL->state_size);
    c->stop_time_defined = (int)s->stop_time_defined;
    c->stop_time = s->stop_time;
    c->state = (vi_fmu_state)s->fmu_state;
    if (MODEL->restore && MODEL->restore(c->model, saved_running(s)) != 0)
        return fail(c, "fmi2SetFMUstate");
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
    if (!size) {
        LOG_ERROR(c, "fmi2SerializedFMUstateSize: size is NULL");
        return fmi2Error;
    }
    const vi_saved_state *s = FMUstate;
    if (!check_saved(c, "fmi2SerializedFMUstateSize", s, s ? s->size : 0)) return fmi2Error;
    *size = saved_size();
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component comp, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size)
{
    ENTER("fmi2SerializeFMUstate", ST_ANY_BUT_FATAL);
    if (!serializedState || size < saved_size()) {
        LOG_ERROR(c, "fmi2SerializeFMUstate: need a buffer of %zu bytes (got %zu)", saved_size(), size);
        return fmi2Error;
    }
    const vi_saved_state *s = FMUstate;
    if (!check_saved(c, "fmi2SerializeFMUstate", s, s ? s->size : 0)) return fmi2Error;
    memcpy(serializedState, FMUstate, saved_size());
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{
    ENTER("fmi2DeSerializeFMUstate", ST_ANY_BUT_FATAL);
    if (!serializedState || !FMUstate) {
        LOG_ERROR(c, "fmi2DeSerializeFMUstate: NULL argument");
        return fmi2Error;
    }
    if (size < sizeof(vi_saved_state) || size > saved_size()) {
        LOG_ERROR(c, "fmi2DeSerializeFMUstate: invalid FMU state: size %zu bytes: a state of this build of %s has %zu",
                  size, MODEL->model_identifier, saved_size());
        return fmi2Error;
    }
    vi_saved_state *s = c->cb.allocateMemory(1, saved_size()); /* aligned, checked before it replaces anything */
    if (!s) {
        LOG_ERROR(c, "fmi2DeSerializeFMUstate: out of memory");
        return fmi2Error;
    }
    memcpy(s, serializedState, size);
    if (!check_saved(c, "fmi2DeSerializeFMUstate", s, size)) {
        c->cb.freeMemory(s);
        return fmi2Error;
    }
    if (*FMUstate) {
        memcpy(*FMUstate, s, saved_size());
        c->cb.freeMemory(s);
    } else {
        *FMUstate = s;
    }
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

/* fmi2DoStep: currentCommunicationPoint may differ from the FMU's time by this many units of the
 * time resolution (DBL_EPSILON max(1 s, |t|)); a step must advance time by at least VI_MIN_STEP_ULPS. */
#define VI_TIME_MATCH_ULPS 1e3
#define VI_MIN_STEP_ULPS 16.0

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
        *derivative(c, &MODEL->variables[vr[i]]) = value[i];
        MODEL->changed(c->model);
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
    double tc = currentCommunicationPoint, h = communicationStepSize, t = MODEL->time(c->model);
    double unit = DBL_EPSILON * fmax(1.0, fabs(t)); /* the resolution of time here, at least that at 1 s */
    double t_end = tc + h;
    /* Refused arguments leave the instance as it was (fmi2Error from fmi2DoStep: "the step could
     * not be carried out at all"; the master may try another step). */
    if (!isfinite(tc) || !isfinite(h) || !(h > 0.0)) {
        LOG_ERROR(c, "fmi2DoStep: the communication step size must be finite and positive (got %g)", h);
        return fmi2Error;
    }
    if (fabs(tc - t) > VI_TIME_MATCH_ULPS * unit) {
        LOG_ERROR(c, "fmi2DoStep: currentCommunicationPoint %.17g does not match the FMU's time %.17g", tc, t);
        return fmi2Error;
    }
    if (!(t_end - t >= VI_MIN_STEP_ULPS * unit)) {
        LOG_ERROR(c, "fmi2DoStep: a step of %g s is too short to advance time at t = %.17g s: use at least %g s "
                     "(16 units of the time resolution there); nothing was done",
                  h, t, VI_MIN_STEP_ULPS * unit);
        return fmi2Error;
    }
    if (c->stop_time_defined && t_end > c->stop_time + VI_TIME_MATCH_ULPS * unit) {
        LOG_ERROR(c, "fmi2DoStep: the step to %.17g passes the stop time %.17g", t_end, c->stop_time);
        return fmi2Error;
    }
    int rc = MODEL->advance(c->model, t_end);
    if (rc < 0) return fail(c, "fmi2DoStep");
    if (rc == 0 && MODEL->time(c->model) != t_end) { /* never fmi2OK for a step that did not happen */
        LOG_ERROR(c, "fmi2DoStep: the model stopped at t = %.17g s instead of %.17g s", MODEL->time(c->model), t_end);
        c->state = ST_ERROR;
        return fmi2Error;
    }
    if (rc > 0) { /* stopped early at a consistent state: fmi2LastSuccessfulTime tells where */
        logf_(c, fmi2Discard, CAT_logStatusDiscard, "fmi2DoStep: %s", MODEL->message(c->model));
        c->state = ST_STEP_FAILED;
        return fmi2Discard;
    }
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component comp)
{
    ENTER("fmi2CancelStep", ST_ANY_BUT_FATAL);
    LOG_ERROR(c, "fmi2CancelStep: fmi2DoStep is synchronous; there is nothing to cancel");
    return fmi2Error;
}

/* Status queries: fmi2DoStep runs synchronously, so only fmi2LastSuccessfulTime and fmi2Terminated
 * have an answer; any other kind gets fmi2Discard ("not able to return the status information"). */
static fmi2Status no_status(Component *c, const char *fn, fmi2StatusKind kind, const void *value)
{
    if (!value) {
        LOG_ERROR(c, "%s: value is NULL", fn);
        return fmi2Error;
    }
    logf_(c, fmi2Discard, CAT_logStatusDiscard, "%s: no status of kind %d (fmi2DoStep runs synchronously)", fn,
          (int)kind);
    return fmi2Discard;
}

fmi2Status fmi2GetStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Status *value)
{
    ENTER("fmi2GetStatus", ST_RUNNING);
    return no_status(c, "fmi2GetStatus", s, value);
}

fmi2Status fmi2GetRealStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Real *value)
{
    ENTER("fmi2GetRealStatus", ST_RUNNING | ST_ERROR);
    if (s != fmi2LastSuccessfulTime || !value) return no_status(c, "fmi2GetRealStatus", s, value);
    *value = MODEL->time(c->model); /* after fmi2Discard: where the step stopped */
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Integer *value)
{
    ENTER("fmi2GetIntegerStatus", ST_RUNNING);
    return no_status(c, "fmi2GetIntegerStatus", s, value);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Boolean *value)
{
    ENTER("fmi2GetBooleanStatus", ST_RUNNING | ST_ERROR);
    if (s != fmi2Terminated || !value) return no_status(c, "fmi2GetBooleanStatus", s, value);
    *value = fmi2False; /* the FMU never asks to end the simulation */
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component comp, const fmi2StatusKind s, fmi2String *value)
{
    ENTER("fmi2GetStringStatus", ST_RUNNING);
    return no_status(c, "fmi2GetStringStatus", s, value);
}
