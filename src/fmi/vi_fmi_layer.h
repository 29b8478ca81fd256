/*
 * vi_fmi_layer.h - the generic FMI layer as its faces see it: what every version of the standard
 * shares, in src/fmi/vi_fmi_*.c, one concern a file: the state machine (vi_fmi_state_machine.c, a table
 * of the FMI states in which each call is allowed), logging with categories (vi_fmi_log.c), the
 * instance life cycle (vi_fmi_instance.c), value access through the model's variable table with
 * its checks (vi_fmi_values.c), the checked FMU-state envelope with its checksum and serialization
 * (vi_fmi_fmu_state.c), the Co-Simulation step (vi_fmi_cosim.c) and the Model Exchange calls
 * (vi_fmi_model_exchange.c), all reaching the model through its hooks (vi_fmu.h).
 *
 * A face (src/fmi/vi_fmi2.c, src/fmi/vi_fmi3.c) is a thin translation of one version's C API into the calls
 * below. It writes no state machine, checksum or state format, and checks only what exists in its
 * version alone (FMI 2.0: the status queries; FMI 3.0: nValues, nSeed and nSensitivity, the result
 * pointers of fmi3DoStep and fmi3UpdateDiscreteStates, Event Mode asked for at instantiation),
 * refusing through vi_fmi_refuse_call; every other check is the layer's.
 *
 * Conventions: every layer call that takes an instance takes the name of the standard's function
 * it serves (`fn`, used in every message) and returns a vi_status, whose values are those of
 * fmi2Status and fmi3Status (OK, Warning, Discard, Error, Fatal), so that a face returns it cast.
 * A NULL instance gives VI_STATUS_ERROR without a message (nobody to tell). The status says whether the
 * result is right, the log says what happened: a call that did what it was asked returns OK even when
 * it logged notes with status Warning; Warning, Discard and Error are for results that are not right
 * (a run asked to terminate, a step not completed, a call refused or failed).
 */
#ifndef VI_FMI_LAYER_H
#define VI_FMI_LAYER_H

#include <stddef.h>
#include <stdint.h>

#include "vi_format.h"
#include "vi_fmu.h"

typedef enum { VI_STATUS_OK, VI_STATUS_WARNING, VI_STATUS_DISCARD, VI_STATUS_ERROR, VI_STATUS_FATAL } vi_status;

/* The interface an instance was created for. */
typedef enum { VI_KIND_CS, VI_KIND_ME } vi_kind;

/* FMI states, one bit each (Co-Simulation: instantiated, init, step complete, step failed,
 * terminated, error; Model Exchange: instantiated, init, event, continuous time, terminated, error).
 * The numbers are stored in FMU states: never renumber. */
enum {
    VI_ST_INSTANTIATED = 1 << 0,
    VI_ST_INIT = 1 << 1,
    VI_ST_STEP_COMPLETE = 1 << 2,
    VI_ST_STEP_FAILED = 1 << 3,
    VI_ST_TERMINATED = 1 << 4,
    VI_ST_ERROR = 1 << 5,
    VI_ST_FATAL = 1 << 6,
    VI_ST_EVENT = 1 << 7,
    VI_ST_CONTINUOUS = 1 << 8,
};
#define VI_ST_ANY_BUT_FATAL                                                                                   \
    (VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED | VI_ST_ERROR | \
     VI_ST_EVENT | VI_ST_CONTINUOUS)
/* After initialization (an FMU state taken there is restored with a running model). */
#define VI_ST_RUNNING (VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED | VI_ST_EVENT | VI_ST_CONTINUOUS)

/* The calls of the state machine; vi_fmi_allowed[call] is the set of states it is allowed in. */
typedef enum {
    VI_CALL_SET_DEBUG_LOGGING,
    VI_CALL_SETUP_EXPERIMENT,
    VI_CALL_ENTER_INIT,
    VI_CALL_EXIT_INIT,
    VI_CALL_TERMINATE,
    VI_CALL_RESET,
    VI_CALL_GET,            /* values of any type */
    VI_CALL_SET_REAL,       /* Real values (in continuous time: inputs of continuous variability) */
    VI_CALL_SET_DISCRETE,   /* Integer, Boolean, String values */
    VI_CALL_FMU_STATE,      /* get, set, free, serialize, deserialize an FMU state */
    VI_CALL_DIRECTIONAL_DERIVATIVE,
    VI_CALL_SET_INPUT_DERIVATIVES,
    VI_CALL_GET_OUTPUT_DERIVATIVES,
    VI_CALL_DO_STEP,
    VI_CALL_CANCEL_STEP,
    VI_CALL_GET_STATUS,     /* the Co-Simulation status queries */
    VI_CALL_GET_LAST_STATUS, /* last successful time, terminated: also after an error */
    VI_CALL_ENTER_EVENT_MODE,
    VI_CALL_NEW_DISCRETE_STATES,
    VI_CALL_ENTER_CONTINUOUS_MODE,
    VI_CALL_COMPLETED_STEP,
    VI_CALL_SET_TIME,
    VI_CALL_SET_STATES,
    VI_CALL_GET_DERIVATIVES,
    VI_CALL_GET_EVENT_INDICATORS,
    VI_CALL_GET_STATES,
    VI_CALL_GET_NOMINALS,
    VI_CALL_ENTER_STEP_MODE, /* Co-Simulation with Event Mode (FMI 3.0): back to stepping */
    VI_CALL_COUNT
} vi_call;
extern const unsigned vi_fmi_allowed[VI_CALL_COUNT];

/* Log categories (as listed in every modelDescription.xml); the call category is named by the
 * face (logFmi2Call). Warnings, discards and errors are logged whatever is enabled. */
enum { VI_CAT_EVENTS, VI_CAT_SOLVER, VI_CAT_WARNING, VI_CAT_DISCARD, VI_CAT_ERROR, VI_CAT_CALL, VI_CAT_ALL, VI_CAT_COUNT };

typedef struct vi_fmi_instance vi_fmi_instance;

/* The longest message text a face's emit gets, with its NUL (control characters written \\xNN). */
#define VI_FMI_MESSAGE_MAX 4096

/* What a face tells the layer about itself. */
typedef struct {
    const char *call_category; /* the name of the category VI_CAT_CALL, e.g. "logFmi2Call" */
    /* Hand one finished message to the importer's logger (escape it as the version requires). The
     * text is printable ASCII, at most VI_FMI_MESSAGE_MAX bytes with its NUL. */
    void (*emit)(const vi_fmi_instance *c, vi_status status, const char *category, const char *text);
    /* Nonzero (FMI 3.0): Integer rows with an enumeration, and Enumeration rows, are accessed as
     * VI_Enumeration (the face's Int64 calls), the other Integer rows as VI_Integer (Int32); zero
     * (FMI 2.0): all of them as VI_Integer. */
    int named_enumerations;
    /* The names of the vi_type values as the face's API calls them (messages); NULL: the table's. */
    const char *const *type_names;
    /* Nonzero: time_vr is the value reference of the independent variable time, read as a Real
     * (the model's time; in initialization mode the start time) and never set. This one and the
     * derivative and indicator references below lie beyond the table's rows (vi_fmi_get looks for
     * them only there). */
    int has_time;
    unsigned time_vr;
    /* Nonzero: derivative_vr_base + r is the value reference of the first time derivative of the Real
     * input in row r (FMI 3.0 has no fmi2SetRealInputDerivatives: the derivatives are variables, read
     * and written as Reals; setting an input's value resets its derivative to 0 as before). */
    int has_input_derivatives;
    unsigned derivative_vr_base;
    /* Nonzero: Co-Simulation has Event Mode (FMI 3.0), so FMU states taken there may be restored. */
    int cs_event_mode;
    /* Nonzero: indicator_vr_base + i is the value reference of the model's event indicator i, read
     * as a Real by a Model Exchange instance (FMI 3.0 lists event indicators as variables). */
    int has_indicator_vrs;
    unsigned indicator_vr_base;
} vi_face;

/* The importer's callbacks as the layer keeps them: memory (calloc and free semantics) and an
 * opaque logger with its environment, called only by the face's emit. */
typedef void (*vi_any_fn)(void);
typedef struct {
    void *(*alloc)(size_t n, size_t size);
    void (*free)(void *p);
    vi_any_fn logger;
    void *env;
} vi_callbacks;

/* The instance. Faces read it (their emit, their status queries) but change it only through the
 * calls below. */
struct vi_fmi_instance {
    const vi_face *face;
    vi_callbacks cb;
    vi_kind kind;
    void *model;   /* the model's instance (MODEL->instance_size bytes) */
    void *outputs; /* scratch for outputs computed on demand (MODEL->outputs_size bytes) */
    char *name;
    unsigned state; /* one VI_ST_* bit */
    unsigned log_mask; /* bit per VI_CAT_* */
    int result_warning; /* the current call's result is not all that was asked: it returns VI_STATUS_WARNING
                           (the model's warnings are notes: logged with status Warning, the call returns OK) */
    int stop_time_defined;
    double stop_time;
    unsigned face_options; /* the face's own settings of the instance (not in FMU states) */
    int initialized;       /* initialization mode was left successfully (or a state taken after that was
                              restored): the model's outputs are those of a state it set up */
    /* Model Exchange */
    double t_committed; /* the last event or completed integrator step: time never goes back before it */
    int event_passes;   /* passes in a row of the discrete-state iteration that asked for another one */
};

/* ---- logging and the state machine (for the faces' own calls) ---- */
/* Is the category enabled? */
int vi_fmi_logs(const vi_fmi_instance *c, int category);
void vi_fmi_log(const vi_fmi_instance *c, vi_status status, int category, const char *fmt, ...) VI_PRINTF_FORMAT(4, 5);
/* The instance if `call` is allowed in its state (logs the call), else NULL (logs why). */
vi_fmi_instance *vi_fmi_enter(void *instance, vi_call call, const char *fn);
/* A failed simulation call: log the model's reason, enter the error state, VI_STATUS_ERROR. */
vi_status vi_fmi_fail(vi_fmi_instance *c, const char *fn);
/* A message for a call refused before anything changed (state unchanged): VI_STATUS_ERROR. */
vi_status vi_fmi_refuse(const vi_fmi_instance *c, const char *fmt, ...) VI_PRINTF_FORMAT(2, 3);
/* A call of the face refused for one of its own arguments: the state machine's check of `call`
 * first (its message when the call is not allowed now), then the message: VI_STATUS_ERROR. */
vi_status vi_fmi_refuse_call(void *instance, vi_call call, const char *fn, const char *fmt, ...)
    VI_PRINTF_FORMAT(4, 5);

/* ---- life cycle ---- */
/* Check the arguments, allocate the instance with cb (logging through face), initialize the model
 * and hand it its resources folder (a local path or NULL). NULL (logged) on any failure. */
vi_fmi_instance *vi_fmi_instantiate(const vi_face *face, const vi_callbacks *cb, const char *fn, const char *name,
                             vi_kind kind, const char *guid, const char *resource_dir, const char *resource_label,
                             int logging_on);
void vi_fmi_free(vi_fmi_instance *c, const char *fn);
vi_status vi_fmi_set_debug_logging(void *instance, const char *fn, int on, size_t n, const char *const categories[]);
vi_status vi_fmi_setup_experiment(void *instance, const char *fn, int tolerance_defined, double tolerance,
                                   double start, int stop_defined, double stop);
vi_status vi_fmi_enter_init(void *instance, const char *fn);
vi_status vi_fmi_exit_init(void *instance, const char *fn);
vi_status vi_fmi_terminate(void *instance, const char *fn);
vi_status vi_fmi_reset(void *instance, const char *fn);

/* ---- values ---- */
/* How a face's array holds values: double, int (fmi2Integer, fmi2Boolean, int32), int64, C bool,
 * const char *. */
typedef enum { VI_ELEM_DOUBLE, VI_ELEM_INT, VI_ELEM_INT64, VI_ELEM_BOOL, VI_ELEM_STRING } vi_elem;
/* Read nvr values of API type `api` (Real, Integer (enumerations too), Boolean, String). */
vi_status vi_fmi_get(void *instance, const char *fn, const unsigned vr[], size_t nvr, vi_type api, void *values,
                      vi_elem elem);
/* Write nvr values: all are checked (type, settable now, finite Real in its range, integer in the
 * range of the table's int, String length) before any is stored. */
vi_status vi_fmi_set(void *instance, const char *fn, const unsigned vr[], size_t nvr, vi_type api,
                      const void *values, vi_elem elem);
/* First derivatives of Real inputs (Co-Simulation): order 1 only, finite. */
vi_status vi_fmi_set_input_derivatives(void *instance, const char *fn, const unsigned vr[], size_t nvr,
                                        const int order[], const double values[]);

/* ---- FMU state ---- */
vi_status vi_fmi_get_fmu_state(void *instance, const char *fn, void **state);
vi_status vi_fmi_set_fmu_state(void *instance, const char *fn, const void *state);
vi_status vi_fmi_free_fmu_state(void *instance, const char *fn, void **state);
vi_status vi_fmi_fmu_state_size(void *instance, const char *fn, const void *state, size_t *size);
vi_status vi_fmi_serialize(void *instance, const char *fn, const void *state, unsigned char *bytes, size_t size);
vi_status vi_fmi_deserialize(void *instance, const char *fn, const unsigned char *bytes, size_t size, void **state);

/* ---- Co-Simulation ---- */
vi_status vi_fmi_do_step(void *instance, const char *fn, double current_time, double step);
/* vi_fmi_do_step that also ends at the first change of the model's mode inside the step (the
 * model's advance_to_event hook; without it, as vi_fmi_do_step): VI_STATUS_OK with *event = 1 and
 * vi_fmi_time() at the event, or *event = 0 when the step went to its end without one. */
vi_status vi_fmi_do_step_to_event(void *instance, const char *fn, double current_time, double step, int *event);
/* Co-Simulation with Event Mode (FMI 3.0): Event Mode -> Step Mode (vi_fmi_enter_event_mode, below,
 * enters it from Step Mode). */
vi_status vi_fmi_enter_step_mode(void *instance, const char *fn);
/* The model's current time [s] (the last successful time after a discarded step). */
double vi_fmi_time(const vi_fmi_instance *c);

/* ---- Model Exchange ----
 * Time may go back within the current integrator step (root location, interpolation), never before
 * the last event or completed integrator step (going further back needs an FMU state). States and
 * time must be finite; a call in a state the standard does not allow it in is refused with the
 * state named. Array lengths must be the model's numbers of states and event indicators. */
/* At most this many passes of the discrete-state iteration in a row may ask for another one; then
 * the discrete states do not settle and the instance goes into the error state. */
#define VI_MAX_EVENT_PASSES 100
/* Event indicators a face may read one by one (indicator_vr_base). */
#define VI_MAX_INDICATORS 64
/* Model Exchange: continuous-time mode -> Event Mode; Co-Simulation with Event Mode (FMI 3.0): Step
 * Mode -> Event Mode. */
vi_status vi_fmi_enter_event_mode(void *instance, const char *fn);
/* One pass (the model's event_update); *ev as the model filled it. When the model asks to terminate, its
 * reason is logged as a warning whatever is enabled and the call returns VI_STATUS_WARNING (the run ends
 * before the time asked for). */
vi_status vi_fmi_new_discrete_states(void *instance, const char *fn, vi_fmu_event *ev);
vi_status vi_fmi_enter_continuous_mode(void *instance, const char *fn);
/* *enter_event: the model asks for an event now; *terminate: always 0 (the model asks at events). */
vi_status vi_fmi_completed_step(void *instance, const char *fn, int *enter_event, int *terminate);
vi_status vi_fmi_set_time(void *instance, const char *fn, double t);
vi_status vi_fmi_set_states(void *instance, const char *fn, const double x[], size_t n);
vi_status vi_fmi_get_states(void *instance, const char *fn, double x[], size_t n);
vi_status vi_fmi_get_derivatives(void *instance, const char *fn, double dx[], size_t n);
vi_status vi_fmi_get_event_indicators(void *instance, const char *fn, double z[], size_t n);
vi_status vi_fmi_get_nominals(void *instance, const char *fn, double nominal[], size_t n);
/* The model's number of continuous states (VI_COUNT_STATES) or event indicators (VI_COUNT_INDICATORS)
 * into *count: Model Exchange instances only. */
enum { VI_COUNT_STATES, VI_COUNT_INDICATORS };
vi_status vi_fmi_me_count(void *instance, const char *fn, int which, size_t *count);
/* Model Exchange only (the Co-Simulation interface declares none): unknowns are state derivatives
 * and outputs, knowns are states and inputs. */
vi_status vi_fmi_directional_derivative(void *instance, const char *fn, const unsigned unknown[], size_t n_unknown,
                                         const unsigned known[], size_t n_known, const double dknown[],
                                         double dunknown[]);

#endif
