/*
 * vi_fmi3.c - the FMI 3.0 face of the generic layer: every fmi3* function, each a translation into
 * the layer (vi_fmi_layer.h), which does the checks, the state machine, value access, logging and
 * FMU states. What is FMI 3.0 only lives here, with the checks of arguments FMI 2.0 does not have:
 * instantiation with its options (eventModeUsed, earlyReturnAllowed), the tolerance and times given
 * to fmi3EnterInitializationMode, Event Mode in Co-Simulation, the results of fmi3DoStep (early
 * return at the model's events), the independent variable `time`, the derivatives of the Real
 * inputs as variables `der(<input>)` (FMI 3.0 has no fmi3SetInputDerivatives), the event indicators
 * of Model Exchange as variables `event_indicator_<i>`, and the data types (Float64, Int32,
 * Enumeration as Int64, Boolean, String; the model has no other). Model Exchange is the layer's
 * (its Model Exchange calls on the model's hooks) for a model that has them. The capabilities this
 * face offers are listed in the FMI 3.0 model description (cmake/vi_model_description.py).
 *
 * Co-Simulation states map onto the layer's: Step Mode = step complete, Step Discarded = step
 * failed, Event Mode = event.
 *
 * fmi3DoStep: with earlyReturnAllowed, it returns at the first change of the model's mode inside
 * the step (the model's advance_to_event hook) with earlyReturn = true and lastSuccessfulTime at
 * the event, the new mode in force; with eventModeUsed too, it sets eventHandlingNeeded there, and
 * the importer passes through fmi3EnterEventMode, fmi3UpdateDiscreteStates (nothing more to update:
 * the event was applied) and fmi3EnterStepMode. Without earlyReturnAllowed every step goes to its
 * end and events inside it are handled there, as in FMI 2.0.
 */
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "vi_fmi_layer.h"

#if !defined(VI_FMI3_TIME_VR) || !defined(VI_FMI3_DERIVATIVE_VR_BASE) || !defined(VI_FMI3_INDICATOR_VR_BASE)
#error "VI_FMI3_TIME_VR, VI_FMI3_DERIVATIVE_VR_BASE and VI_FMI3_INDICATOR_VR_BASE come from cmake/vi_fmu.cmake"
#endif

_Static_assert((int)VI_STATUS_OK == (int)fmi3OK && (int)VI_STATUS_WARNING == (int)fmi3Warning &&
                   (int)VI_STATUS_DISCARD == (int)fmi3Discard && (int)VI_STATUS_ERROR == (int)fmi3Error &&
                   (int)VI_STATUS_FATAL == (int)fmi3Fatal,
               "the layer's status codes are fmi3Status");
_Static_assert(sizeof(fmi3ValueReference) == sizeof(unsigned) && sizeof(fmi3Int32) == sizeof(int) &&
                   sizeof(fmi3Int64) == sizeof(int64_t) && sizeof(fmi3Float64) == sizeof(double) &&
                   sizeof(fmi3Boolean) == sizeof(bool),
               "fmi3 arrays are read as the layer's element types");

/* face_options of an instance: its fmi3InstantiateCoSimulation arguments. */
enum { OPT_EVENT_MODE = 1u << 0, OPT_EARLY_RETURN = 1u << 1 };

/* The FMI 3.0 logger takes the message as it is (no format). */
static void emit(const vi_fmi_instance *c, vi_status status, const char *category, const char *text)
{
    fmi3LogMessageCallback logger = (fmi3LogMessageCallback)c->cb.logger;
    logger(c->cb.env, (fmi3Status)status, category, text);
}

static const char *const type_names[] = {[VI_Real] = "Float64", [VI_Integer] = "Int32", [VI_Boolean] = "Boolean",
                                         [VI_Enumeration] = "Enumeration (Int64)", [VI_String] = "String"};

static const vi_face face = {.call_category = "logFmi3Call", .emit = emit, .named_enumerations = 1,
                             .type_names = type_names, .has_time = 1, .time_vr = VI_FMI3_TIME_VR,
                             .has_input_derivatives = 1, .derivative_vr_base = VI_FMI3_DERIVATIVE_VR_BASE,
                             .cs_event_mode = 1, .has_indicator_vrs = 1,
                             .indicator_vr_base = VI_FMI3_INDICATOR_VR_BASE};

/* A function this FMU does not provide: refused (after the state check of `call`). */
static fmi3Status not_provided(fmi3Instance instance, vi_call call, const char *fn, const char *why)
{
    return (fmi3Status)vi_fmi_refuse_call(instance, call, fn, "%s: not provided (%s)", fn, why);
}

/* ---- common functions --------------------------------------------------------------------- */

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    return (fmi3Status)vi_fmi_set_debug_logging(instance, "fmi3SetDebugLogging", loggingOn, nCategories, categories);
}

static fmi3Instance instantiate(const char *fn, vi_kind kind, fmi3String instanceName, fmi3String instantiationToken,
                                fmi3String resourcePath, fmi3Boolean loggingOn, fmi3InstanceEnvironment env,
                                fmi3LogMessageCallback logMessage, unsigned options)
{
    vi_callbacks cb = {.alloc = calloc, .free = free, .logger = (vi_any_fn)logMessage, .env = env};
    vi_fmi_instance *c = vi_fmi_instantiate(&face, &cb, fn, instanceName, kind, instantiationToken,
                                     resourcePath && *resourcePath ? resourcePath : NULL, resourcePath, loggingOn);
    if (c) c->face_options = options;
    return c;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    (void)visible;
    return instantiate("fmi3InstantiateModelExchange", VI_KIND_ME, instanceName, instantiationToken, resourcePath,
                       loggingOn, instanceEnvironment, logMessage, 0);
}

/* requiredIntermediateVariables only matter in Intermediate Update Mode, which this FMU never enters
 * (providesIntermediateUpdate = false; intermediateUpdate is never called). */
fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate)
{
    (void)visible, (void)requiredIntermediateVariables, (void)nRequiredIntermediateVariables, (void)intermediateUpdate;
    return instantiate("fmi3InstantiateCoSimulation", VI_KIND_CS, instanceName, instantiationToken, resourcePath,
                       loggingOn, instanceEnvironment, logMessage,
                       (eventModeUsed ? OPT_EVENT_MODE : 0u) | (earlyReturnAllowed ? OPT_EARLY_RETURN : 0u));
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instantiationToken, (void)resourcePath, (void)visible, (void)loggingOn, (void)clockUpdate,
        (void)lockPreemption, (void)unlockPreemption;
    (void)instanceName;
    if (logMessage)
        logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                   vi_fmu_this_model.n_states > 0
                       ? "fmi3InstantiateScheduledExecution: this FMU offers Co-Simulation and Model Exchange, not "
                         "Scheduled Execution"
                       : "fmi3InstantiateScheduledExecution: this FMU offers Co-Simulation only, not Scheduled "
                         "Execution");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) { vi_fmi_free(instance, "fmi3FreeInstance"); }

/* The tolerance, start and stop time are those of FMI 2.0's fmi2SetupExperiment. */
fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    const char *fn = "fmi3EnterInitializationMode";
    vi_status st = vi_fmi_setup_experiment(instance, fn, toleranceDefined, tolerance, startTime, stopTimeDefined,
                                            stopTime);
    if (st > VI_STATUS_WARNING) return (fmi3Status)st;
    vi_status entered = vi_fmi_enter_init(instance, fn);
    return (fmi3Status)(entered > st ? entered : st);
}

static int uses_event_mode(fmi3Instance instance)
{
    return (((vi_fmi_instance *)instance)->face_options & OPT_EVENT_MODE) != 0;
}

/* Co-Simulation with eventModeUsed: Event Mode after initialization, else Step Mode. */
fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    const char *fn = "fmi3ExitInitializationMode";
    vi_status st = vi_fmi_exit_init(instance, fn);
    if (st > VI_STATUS_WARNING || !uses_event_mode(instance)) return (fmi3Status)st;
    vi_status entered = vi_fmi_enter_event_mode(instance, fn);
    return (fmi3Status)(entered > st ? entered : st);
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    const char *fn = "fmi3EnterEventMode";
    const vi_fmi_instance *c = instance;
    if (c && c->kind == VI_KIND_CS && !uses_event_mode(instance))
        return (fmi3Status)vi_fmi_refuse_call(instance, VI_CALL_ENTER_EVENT_MODE, fn,
                                              "%s: the instance was created with eventModeUsed = false", fn);
    return (fmi3Status)vi_fmi_enter_event_mode(instance, fn);
}

fmi3Status fmi3Terminate(fmi3Instance instance) { return (fmi3Status)vi_fmi_terminate(instance, "fmi3Terminate"); }
fmi3Status fmi3Reset(fmi3Instance instance) { return (fmi3Status)vi_fmi_reset(instance, "fmi3Reset"); }

/* ---- variables ---------------------------------------------------------------------------- */

/* Every variable is a scalar: nValues must equal nValueReferences. */
static int scalars(fmi3Instance instance, vi_call call, const char *fn, size_t nvr, size_t nValues)
{
    if (nValues == nvr) return 1;
    vi_fmi_refuse_call(instance, call, fn, "%s: nValues = %zu must equal nValueReferences = %zu (every variable is a "
                                           "scalar)", fn, nValues, nvr);
    return 0;
}

#define DEFINE_GET_SET(Api, ctype, api_type, elem, set_call)                                                       \
    fmi3Status fmi3Get##Api(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, ctype values[],     \
                            size_t nValues)                                                                        \
    {                                                                                                              \
        if (!scalars(instance, VI_CALL_GET, "fmi3Get" #Api, nvr, nValues)) return fmi3Error;                       \
        return (fmi3Status)vi_fmi_get(instance, "fmi3Get" #Api, vr, nvr, api_type, values, elem);                  \
    }                                                                                                              \
    fmi3Status fmi3Set##Api(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const ctype values[], \
                            size_t nValues)                                                                        \
    {                                                                                                              \
        if (!scalars(instance, set_call, "fmi3Set" #Api, nvr, nValues)) return fmi3Error;                          \
        return (fmi3Status)vi_fmi_set(instance, "fmi3Set" #Api, vr, nvr, api_type, values, elem);                  \
    }
DEFINE_GET_SET(Float64, fmi3Float64, VI_Real, VI_ELEM_DOUBLE, VI_CALL_SET_REAL)
DEFINE_GET_SET(Int32, fmi3Int32, VI_Integer, VI_ELEM_INT, VI_CALL_SET_DISCRETE)
DEFINE_GET_SET(Int64, fmi3Int64, VI_Enumeration, VI_ELEM_INT64, VI_CALL_SET_DISCRETE) /* the Enumerations */
DEFINE_GET_SET(Boolean, fmi3Boolean, VI_Boolean, VI_ELEM_BOOL, VI_CALL_SET_DISCRETE)
DEFINE_GET_SET(String, fmi3String, VI_String, VI_ELEM_STRING, VI_CALL_SET_DISCRETE)

/* Types of which the FMU has no variable: any value reference is refused, an empty call is fine. */
static fmi3Status no_such_type(fmi3Instance instance, vi_call call, const char *fn, const char *type,
                               const fmi3ValueReference vr[], size_t nvr)
{
    if (nvr == 0) return vi_fmi_enter(instance, call, fn) ? fmi3OK : fmi3Error;
    return (fmi3Status)vi_fmi_refuse_call(instance, call, fn, "%s: value reference %u is not a %s variable: this FMU "
                                                               "has none", fn, vr ? vr[0] : 0u, type);
}

#define DEFINE_NO_TYPE(Api, ctype)                                                                                 \
    fmi3Status fmi3Get##Api(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, ctype values[],     \
                            size_t nValues)                                                                        \
    {                                                                                                              \
        (void)values, (void)nValues;                                                                               \
        return no_such_type(instance, VI_CALL_GET, "fmi3Get" #Api, #Api, vr, nvr);                                 \
    }                                                                                                              \
    fmi3Status fmi3Set##Api(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const ctype values[], \
                            size_t nValues)                                                                        \
    {                                                                                                              \
        (void)values, (void)nValues;                                                                               \
        return no_such_type(instance, VI_CALL_SET_DISCRETE, "fmi3Set" #Api, #Api, vr, nvr);                        \
    }
DEFINE_NO_TYPE(Float32, fmi3Float32)
DEFINE_NO_TYPE(Int8, fmi3Int8)
DEFINE_NO_TYPE(UInt8, fmi3UInt8)
DEFINE_NO_TYPE(Int16, fmi3Int16)
DEFINE_NO_TYPE(UInt16, fmi3UInt16)
DEFINE_NO_TYPE(UInt32, fmi3UInt32)
DEFINE_NO_TYPE(UInt64, fmi3UInt64)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, size_t valueSizes[],
                         fmi3Binary values[], size_t nValues)
{
    (void)valueSizes, (void)values, (void)nValues;
    return no_such_type(instance, VI_CALL_GET, "fmi3GetBinary", "Binary", vr, nvr);
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const size_t valueSizes[],
                         const fmi3Binary values[], size_t nValues)
{
    (void)valueSizes, (void)values, (void)nValues;
    return no_such_type(instance, VI_CALL_SET_DISCRETE, "fmi3SetBinary", "Binary", vr, nvr);
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Clock values[])
{
    (void)values;
    return no_such_type(instance, VI_CALL_GET, "fmi3GetClock", "Clock", vr, nvr);
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock values[])
{
    (void)values;
    return no_such_type(instance, VI_CALL_SET_DISCRETE, "fmi3SetClock", "Clock", vr, nvr);
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies)
{
    (void)valueReference, (void)nDependencies;
    return not_provided(instance, VI_CALL_GET, "fmi3GetNumberOfVariableDependencies",
                        "providesPerElementDependencies = false; the model description lists them");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies)
{
    (void)dependent, (void)elementIndicesOfDependent, (void)independents, (void)elementIndicesOfIndependents,
        (void)dependencyKinds, (void)nDependencies;
    return not_provided(instance, VI_CALL_GET, "fmi3GetVariableDependencies",
                        "providesPerElementDependencies = false; the model description lists them");
}

/* ---- FMU state ---------------------------------------------------------------------------- */

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    return (fmi3Status)vi_fmi_get_fmu_state(instance, "fmi3GetFMUState", FMUState);
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{
    return (fmi3Status)vi_fmi_set_fmu_state(instance, "fmi3SetFMUState", FMUState);
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    return (fmi3Status)vi_fmi_free_fmu_state(instance, "fmi3FreeFMUState", FMUState);
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size)
{
    return (fmi3Status)vi_fmi_fmu_state_size(instance, "fmi3SerializedFMUStateSize", FMUState, size);
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[], size_t size)
{
    return (fmi3Status)vi_fmi_serialize(instance, "fmi3SerializeFMUState", FMUState, serializedState, size);
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState)
{
    return (fmi3Status)vi_fmi_deserialize(instance, "fmi3DeserializeFMUState", serializedState, size, FMUState);
}

/* ---- derivatives, configuration, clocks: not provided ------------------------------------- */

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    const char *fn = "fmi3GetDirectionalDerivative";
    if (nSeed != nKnowns || nSensitivity != nUnknowns) /* every variable is a scalar */
        return (fmi3Status)vi_fmi_refuse_call(instance, VI_CALL_DIRECTIONAL_DERIVATIVE, fn,
                                              "%s: nSeed = %zu and nSensitivity = %zu must equal nKnowns = %zu and "
                                              "nUnknowns = %zu (every variable is a scalar)",
                                              fn, nSeed, nSensitivity, nKnowns, nUnknowns);
    return (fmi3Status)vi_fmi_directional_derivative(instance, fn, unknowns, nUnknowns, knowns, nKnowns, seed,
                                                      sensitivity);
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns, (void)nUnknowns, (void)knowns, (void)nKnowns, (void)seed, (void)nSeed, (void)sensitivity,
        (void)nSensitivity;
    return not_provided(instance, VI_CALL_DIRECTIONAL_DERIVATIVE, "fmi3GetAdjointDerivative",
                        "providesAdjointDerivatives = false");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return not_provided(instance, VI_CALL_RESET, "fmi3EnterConfigurationMode", "the FMU has no structural parameters");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return not_provided(instance, VI_CALL_RESET, "fmi3ExitConfigurationMode", "the FMU has no structural parameters");
}

#define NO_CLOCKS(instance, fn) not_provided(instance, VI_CALL_RESET, fn, "the FMU has no clocks")

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                  fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    (void)vr, (void)nvr, (void)intervals, (void)qualifiers;
    return NO_CLOCKS(instance, "fmi3GetIntervalDecimal");
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                   fmi3UInt64 counters[], fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[])
{
    (void)vr, (void)nvr, (void)counters, (void)resolutions, (void)qualifiers;
    return NO_CLOCKS(instance, "fmi3GetIntervalFraction");
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 shifts[])
{
    (void)vr, (void)nvr, (void)shifts;
    return NO_CLOCKS(instance, "fmi3GetShiftDecimal");
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)vr, (void)nvr, (void)counters, (void)resolutions;
    return NO_CLOCKS(instance, "fmi3GetShiftFraction");
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                  const fmi3Float64 intervals[])
{
    (void)vr, (void)nvr, (void)intervals;
    return NO_CLOCKS(instance, "fmi3SetIntervalDecimal");
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                   const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr, (void)nvr, (void)counters, (void)resolutions;
    return NO_CLOCKS(instance, "fmi3SetIntervalFraction");
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                               const fmi3Float64 shifts[])
{
    (void)vr, (void)nvr, (void)shifts;
    return NO_CLOCKS(instance, "fmi3SetShiftDecimal");
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr, (void)nvr, (void)counters, (void)resolutions;
    return NO_CLOCKS(instance, "fmi3SetShiftFraction");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    return not_provided(instance, VI_CALL_NEW_DISCRETE_STATES, "fmi3EvaluateDiscreteStates",
                        "providesEvaluateDiscreteStates = false");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    (void)clockReference, (void)activationTime;
    return not_provided(instance, VI_CALL_RESET, "fmi3ActivateModelPartition", "no Scheduled Execution");
}

/* ---- Event Mode ----------------------------------------------------------------------------- */

/* Model Exchange: one pass of the model's event iteration. In Co-Simulation the model applies each
 * event inside fmi3DoStep, so Event Mode has nothing left to update: the importer may set inputs and
 * tunable parameters there (they take effect in the next step) and read the outputs just after the
 * event. */
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime)
{
    const char *fn = "fmi3UpdateDiscreteStates";
    if (!discreteStatesNeedUpdate || !terminateSimulation || !nominalsOfContinuousStatesChanged ||
        !valuesOfContinuousStatesChanged || !nextEventTimeDefined || !nextEventTime)
        return (fmi3Status)vi_fmi_refuse_call(instance, VI_CALL_NEW_DISCRETE_STATES, fn, "%s: NULL argument", fn);
    vi_fmi_instance *c = vi_fmi_enter(instance, VI_CALL_NEW_DISCRETE_STATES, fn);
    if (!c) return fmi3Error;
    if (c->kind == VI_KIND_ME) { /* one pass of the model's event iteration */
        vi_fmu_event ev;
        vi_status st = vi_fmi_new_discrete_states(instance, fn, &ev);
        if (st <= VI_STATUS_WARNING) {
            *discreteStatesNeedUpdate = ev.another_pass, *terminateSimulation = ev.terminate;
            *nominalsOfContinuousStatesChanged = ev.nominals_changed;
            *valuesOfContinuousStatesChanged = ev.states_changed;
            *nextEventTimeDefined = ev.next_time_defined, *nextEventTime = ev.next_time_defined ? ev.next_time : 0.0;
        }
        return (fmi3Status)st;
    }
    *discreteStatesNeedUpdate = false;
    *terminateSimulation = false;
    *nominalsOfContinuousStatesChanged = false;
    *valuesOfContinuousStatesChanged = false;
    *nextEventTimeDefined = false;
    *nextEventTime = 0.0;
    return fmi3OK;
}

/* ---- Model Exchange ------------------------------------------------------------------------- */

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    return (fmi3Status)vi_fmi_enter_continuous_mode(instance, "fmi3EnterContinuousTimeMode");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint; /* nothing is kept for earlier points */
    int enter = 0, terminate = 0;
    vi_status st = vi_fmi_completed_step(instance, "fmi3CompletedIntegratorStep",
                                          enterEventMode && terminateSimulation ? &enter : NULL, &terminate);
    if (st <= VI_STATUS_WARNING) *enterEventMode = enter, *terminateSimulation = terminate;
    return (fmi3Status)st;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    return (fmi3Status)vi_fmi_set_time(instance, "fmi3SetTime", time);
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{
    return (fmi3Status)vi_fmi_set_states(instance, "fmi3SetContinuousStates", continuousStates, nContinuousStates);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates)
{
    return (fmi3Status)vi_fmi_get_derivatives(instance, "fmi3GetContinuousStateDerivatives", derivatives,
                                               nContinuousStates);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators)
{
    return (fmi3Status)vi_fmi_get_event_indicators(instance, "fmi3GetEventIndicators", eventIndicators,
                                                    nEventIndicators);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    return (fmi3Status)vi_fmi_get_states(instance, "fmi3GetContinuousStates", continuousStates, nContinuousStates);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nContinuousStates)
{
    return (fmi3Status)vi_fmi_get_nominals(instance, "fmi3GetNominalsOfContinuousStates", nominals, nContinuousStates);
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators)
{
    return (fmi3Status)vi_fmi_me_count(instance, "fmi3GetNumberOfEventIndicators", VI_COUNT_INDICATORS,
                                       nEventIndicators);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates)
{
    return (fmi3Status)vi_fmi_me_count(instance, "fmi3GetNumberOfContinuousStates", VI_COUNT_STATES,
                                       nContinuousStates);
}

/* ---- Co-Simulation -------------------------------------------------------------------------- */

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    return (fmi3Status)vi_fmi_enter_step_mode(instance, "fmi3EnterStepMode");
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                    const fmi3Int32 orders[], fmi3Float64 values[], size_t nValues)
{
    (void)vr, (void)nvr, (void)orders, (void)values, (void)nValues;
    return not_provided(instance, VI_CALL_GET_OUTPUT_DERIVATIVES, "fmi3GetOutputDerivatives",
                        "maxOutputDerivativeOrder = 0");
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean *eventHandlingNeeded,
                      fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    const char *fn = "fmi3DoStep";
    const vi_fmi_instance *c = instance;
    if (!c) return fmi3Error;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime)
        return (fmi3Status)vi_fmi_refuse_call(instance, VI_CALL_DO_STEP, fn, "%s: NULL argument", fn);
    int event = 0;
    double tc = currentCommunicationPoint, h = communicationStepSize;
    vi_status st = c->face_options & OPT_EARLY_RETURN ? vi_fmi_do_step_to_event(instance, fn, tc, h, &event)
                                                      : vi_fmi_do_step(instance, fn, tc, h);
    double t = vi_fmi_time(c);
    *lastSuccessfulTime = t; /* after fmi3Discard: where the step stopped */
    *earlyReturn = event && t < tc + h;
    *eventHandlingNeeded = event && uses_event_mode(instance);
    *terminateSimulation = false; /* the FMU never asks to end the simulation */
    return (fmi3Status)st;
}
