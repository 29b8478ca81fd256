/*
 * vi_fmi2.c - the FMI 2.0 face of the generic layer: every fmi2* function of a Co-Simulation and
 * Model Exchange FMU, each a translation into the layer (vi_fmi_layer.h), which does the checks, the
 * state machine, value access, logging and FMU states. What is FMI 2.0 only lives here: the logger's
 * calling convention, the memory functions, the resource URI, the status queries.
 */
#include <stdarg.h>
#include <stdlib.h> /* calloc, free: an importer without memory functions */
#include <string.h>

#include "fmi2Functions.h"
#include "vi_fmi_layer.h"

_Static_assert((int)VI_STATUS_OK == (int)fmi2OK && (int)VI_STATUS_WARNING == (int)fmi2Warning &&
                   (int)VI_STATUS_DISCARD == (int)fmi2Discard && (int)VI_STATUS_ERROR == (int)fmi2Error &&
                   (int)VI_STATUS_FATAL == (int)fmi2Fatal,
               "the layer's status codes are fmi2Status");
_Static_assert(sizeof(fmi2ValueReference) == sizeof(unsigned) && sizeof(fmi2Integer) == sizeof(int) &&
                   sizeof(fmi2Boolean) == sizeof(int) && sizeof(fmi2Real) == sizeof(double),
               "fmi2 arrays are read as the layer's element types");

/* The FMI 2.0 logger takes the message as a printf format: '%' is escaped. */
static void emit(const vi_fmi_instance *c, vi_status status, const char *category, const char *text)
{
    char escaped[2 * VI_FMI_MESSAGE_MAX];
    size_t j = 0;
    for (size_t i = 0; text[i] && j + 2 < sizeof escaped; i++) {
        if (text[i] == '%') escaped[j++] = '%';
        escaped[j++] = text[i];
    }
    escaped[j] = '\0';
    fmi2CallbackLogger logger = (fmi2CallbackLogger)c->cb.logger;
    logger(c->cb.env, c->name, (fmi2Status)status, category, escaped);
}

static const vi_face face = {.call_category = "logFmi2Call", .emit = emit};

/* ---- common functions --------------------------------------------------------------------- */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    return (fmi2Status)vi_fmi_set_debug_logging(c, "fmi2SetDebugLogging", loggingOn, nCategories, categories);
}

static int hex_digit(char ch)
{
    if (ch >= '0' && ch <= '9') return ch - '0';
    if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
    return -1;
}

/* The local path of a file URI (file:///p, file:/p or file://localhost/p), percent-decoded, in a
 * new block of cb's memory (on Windows /C:/p gives C:/p); NULL when the URI is missing or names no
 * local file. */
static char *resource_path(const vi_callbacks *cb, const char *uri)
{
    if (!uri || strncmp(uri, "file:", 5) != 0) return NULL;
    const char *p = uri + 5;
    if (strncmp(p, "///", 3) == 0) p += 2;
    else if (strncmp(p, "//localhost/", 12) == 0) p += 11;
    else if (strncmp(p, "//", 2) == 0) return NULL; /* another host */
    if (*p != '/') return NULL;
    char *path = cb->alloc(strlen(p) + 1, 1);
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
#ifdef _WIN32
    /* file:///C:/dir names the Windows path C:/dir */
    char drive = (char)(path[1] | 0x20);
    if (path[0] == '/' && drive >= 'a' && drive <= 'z' && path[2] == ':') memmove(path, path + 1, j);
#endif
    return path;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    (void)visible;
    if (!functions || !functions->logger) return NULL; /* nobody to tell */
    vi_callbacks cb = {.alloc = functions->allocateMemory, .free = functions->freeMemory,
                       .logger = (vi_any_fn)functions->logger, .env = functions->componentEnvironment};
    /* canNotUseMemoryManagementFunctions="true": an importer may leave the memory functions out; the
     * instance then comes from the C library's, as everything else the FMU allocates. */
    if (!cb.alloc || !cb.free) cb.alloc = calloc, cb.free = free;
    vi_kind kind = fmuType == fmi2ModelExchange ? VI_KIND_ME : fmuType == fmi2CoSimulation ? VI_KIND_CS : (vi_kind)-1;
    char *dir = resource_path(&cb, fmuResourceLocation);
    vi_fmi_instance *c = vi_fmi_instantiate(&face, &cb, "fmi2Instantiate", instanceName, kind, fmuGUID, dir,
                                     fmuResourceLocation, loggingOn);
    if (dir) cb.free(dir);
    return c;
}

void fmi2FreeInstance(fmi2Component c) { vi_fmi_free(c, "fmi2FreeInstance"); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    return (fmi2Status)vi_fmi_setup_experiment(c, "fmi2SetupExperiment", toleranceDefined, tolerance, startTime,
                                                stopTimeDefined, stopTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    return (fmi2Status)vi_fmi_enter_init(c, "fmi2EnterInitializationMode");
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    return (fmi2Status)vi_fmi_exit_init(c, "fmi2ExitInitializationMode");
}

fmi2Status fmi2Terminate(fmi2Component c) { return (fmi2Status)vi_fmi_terminate(c, "fmi2Terminate"); }
fmi2Status fmi2Reset(fmi2Component c) { return (fmi2Status)vi_fmi_reset(c, "fmi2Reset"); }

/* ---- variables ---------------------------------------------------------------------------- */

#define DEFINE_GET_SET(Api, ctype, api_type, elem)                                                             \
    fmi2Status fmi2Get##Api(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, ctype value[])       \
    {                                                                                                          \
        return (fmi2Status)vi_fmi_get(c, "fmi2Get" #Api, vr, nvr, api_type, value, elem);                     \
    }                                                                                                          \
    fmi2Status fmi2Set##Api(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const ctype value[]) \
    {                                                                                                          \
        return (fmi2Status)vi_fmi_set(c, "fmi2Set" #Api, vr, nvr, api_type, value, elem);                     \
    }
DEFINE_GET_SET(Real, fmi2Real, VI_Real, VI_ELEM_DOUBLE)
DEFINE_GET_SET(Integer, fmi2Integer, VI_Integer, VI_ELEM_INT)
DEFINE_GET_SET(Boolean, fmi2Boolean, VI_Boolean, VI_ELEM_INT)
DEFINE_GET_SET(String, fmi2String, VI_String, VI_ELEM_STRING)

/* ---- FMU state ---------------------------------------------------------------------------- */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    return (fmi2Status)vi_fmi_get_fmu_state(c, "fmi2GetFMUstate", FMUstate);
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    return (fmi2Status)vi_fmi_set_fmu_state(c, "fmi2SetFMUstate", FMUstate);
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    return (fmi2Status)vi_fmi_free_fmu_state(c, "fmi2FreeFMUstate", FMUstate);
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    return (fmi2Status)vi_fmi_fmu_state_size(c, "fmi2SerializedFMUstateSize", FMUstate, size);
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size)
{
    return (fmi2Status)vi_fmi_serialize(c, "fmi2SerializeFMUstate", FMUstate, (unsigned char *)serializedState,
                                         size);
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{
    return (fmi2Status)vi_fmi_deserialize(c, "fmi2DeSerializeFMUstate", (const unsigned char *)serializedState, size,
                                           FMUstate);
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    return (fmi2Status)vi_fmi_directional_derivative(c, "fmi2GetDirectionalDerivative", vUnknown_ref, nUnknown,
                                                      vKnown_ref, nKnown, dvKnown, dvUnknown);
}

/* ---- co-simulation ------------------------------------------------------------------------ */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    return (fmi2Status)vi_fmi_set_input_derivatives(c, "fmi2SetRealInputDerivatives", vr, nvr, order, value);
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr, (void)nvr, (void)order, (void)value;
    const char *fn = "fmi2GetRealOutputDerivatives";
    return (fmi2Status)vi_fmi_refuse_call(comp, VI_CALL_GET_OUTPUT_DERIVATIVES, fn,
                                          "%s: not provided (maxOutputDerivativeOrder=0)", fn);
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    return (fmi2Status)vi_fmi_do_step(c, "fmi2DoStep", currentCommunicationPoint, communicationStepSize);
}

fmi2Status fmi2CancelStep(fmi2Component comp)
{
    const char *fn = "fmi2CancelStep";
    return (fmi2Status)vi_fmi_refuse_call(comp, VI_CALL_CANCEL_STEP, fn,
                                          "%s: fmi2DoStep is synchronous; there is nothing to cancel", fn);
}

/* Status queries: fmi2DoStep runs synchronously, so only fmi2LastSuccessfulTime and fmi2Terminated
 * have an answer; any other kind gets fmi2Discard ("not able to return the status information"). */
static fmi2Status no_status(vi_fmi_instance *c, const char *fn, fmi2StatusKind kind, const void *value)
{
    if (!value) return (fmi2Status)vi_fmi_refuse(c, "%s: value is NULL", fn);
    vi_fmi_log(c, VI_STATUS_DISCARD, VI_CAT_DISCARD, "%s: no status of kind %d (fmi2DoStep runs synchronously)", fn,
                (int)kind);
    return fmi2Discard;
}

/* The instance of a status query: a Co-Simulation one in a state that allows the query. */
static vi_fmi_instance *status_enter(fmi2Component comp, vi_call call, const char *fn)
{
    vi_fmi_instance *c = vi_fmi_enter(comp, call, fn);
    if (c && c->kind != VI_KIND_CS) {
        vi_fmi_refuse(c, "%s: a Co-Simulation function; this instance is a Model Exchange one", fn);
        return NULL;
    }
    return c;
}

#define STATUS_ENTER(call, name)                    \
    const char *fn = name;                          \
    vi_fmi_instance *c = status_enter(comp, call, fn);      \
    if (!c) return fmi2Error

fmi2Status fmi2GetStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Status *value)
{
    STATUS_ENTER(VI_CALL_GET_STATUS, "fmi2GetStatus");
    return no_status(c, fn, s, value);
}

fmi2Status fmi2GetRealStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Real *value)
{
    STATUS_ENTER(VI_CALL_GET_LAST_STATUS, "fmi2GetRealStatus");
    if (s != fmi2LastSuccessfulTime || !value) return no_status(c, fn, s, value);
    *value = vi_fmi_time(c); /* after fmi2Discard: where the step stopped */
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Integer *value)
{
    STATUS_ENTER(VI_CALL_GET_STATUS, "fmi2GetIntegerStatus");
    return no_status(c, fn, s, value);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Boolean *value)
{
    STATUS_ENTER(VI_CALL_GET_LAST_STATUS, "fmi2GetBooleanStatus");
    if (s != fmi2Terminated || !value) return no_status(c, fn, s, value);
    *value = fmi2False; /* the FMU never asks to end the simulation */
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component comp, const fmi2StatusKind s, fmi2String *value)
{
    STATUS_ENTER(VI_CALL_GET_STATUS, "fmi2GetStringStatus");
    return no_status(c, fn, s, value);
}

/* ---- model exchange ----------------------------------------------------------------------- */

fmi2Status fmi2EnterEventMode(fmi2Component c) { return (fmi2Status)vi_fmi_enter_event_mode(c, "fmi2EnterEventMode"); }

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *fmi2eventInfo)
{
    vi_fmu_event ev;
    vi_status st = vi_fmi_new_discrete_states(c, "fmi2NewDiscreteStates", fmi2eventInfo ? &ev : NULL);
    if (st <= VI_STATUS_WARNING) {
        fmi2eventInfo->newDiscreteStatesNeeded = ev.another_pass ? fmi2True : fmi2False;
        fmi2eventInfo->terminateSimulation = ev.terminate ? fmi2True : fmi2False;
        fmi2eventInfo->nominalsOfContinuousStatesChanged = ev.nominals_changed ? fmi2True : fmi2False;
        fmi2eventInfo->valuesOfContinuousStatesChanged = ev.states_changed ? fmi2True : fmi2False;
        fmi2eventInfo->nextEventTimeDefined = ev.next_time_defined ? fmi2True : fmi2False;
        fmi2eventInfo->nextEventTime = ev.next_time_defined ? ev.next_time : 0.0;
    }
    return (fmi2Status)st;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    return (fmi2Status)vi_fmi_enter_continuous_mode(c, "fmi2EnterContinuousTimeMode");
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint; /* nothing is kept for earlier points */
    int enter = 0, terminate = 0;
    vi_status st = vi_fmi_completed_step(c, "fmi2CompletedIntegratorStep", enterEventMode && terminateSimulation
                                                                                 ? &enter : NULL, &terminate);
    if (st <= VI_STATUS_WARNING) {
        *enterEventMode = enter ? fmi2True : fmi2False;
        *terminateSimulation = terminate ? fmi2True : fmi2False;
    }
    return (fmi2Status)st;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) { return (fmi2Status)vi_fmi_set_time(c, "fmi2SetTime", time); }

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    return (fmi2Status)vi_fmi_set_states(c, "fmi2SetContinuousStates", x, nx);
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    return (fmi2Status)vi_fmi_get_derivatives(c, "fmi2GetDerivatives", derivatives, nx);
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{
    return (fmi2Status)vi_fmi_get_event_indicators(c, "fmi2GetEventIndicators", eventIndicators, ni);
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    return (fmi2Status)vi_fmi_get_states(c, "fmi2GetContinuousStates", x, nx);
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    return (fmi2Status)vi_fmi_get_nominals(c, "fmi2GetNominalsOfContinuousStates", x_nominal, nx);
}
