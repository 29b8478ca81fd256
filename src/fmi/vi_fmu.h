/*
 * vi_fmu.h - the generic FMI layer and what a model gives it.
 *
 * The layer (src/fmi/vi_fmi_*.c, src/fmi/vi_fmi_layer.h, with one face per version of the standard: src/fmi/vi_fmi2.c,
 * src/fmi/vi_fmi3.c) implements every function of a Co-Simulation and a Model Exchange FMU and knows no
 * model: argument and state-machine checks, value access through the model's variable table
 * (vi_table.h), logging with categories, the FMU state envelope and its serialization, the status
 * functions, the checks of a step (communication point, step size, stop time), and the Model
 * Exchange calls (time, states, derivatives, event indicators, the event iteration, nominals,
 * directional derivatives). It never integrates anything itself: in co-simulation the model
 * advances with its own solver inside fmi2DoStep or fmi3DoStep; in Model Exchange the importer's integrator does,
 * through the Model Exchange hooks below (a model without them offers co-simulation only).
 *
 * To build an FMU of a model, a model author writes, in one folder:
 *   1. a table header and one .c with VI_TABLE_DEFINE (see vi_table.h): the variables, the model's
 *      identity (VI_MODEL_IDENTIFIER = the FMU's CMake name, VI_GUID, VI_MODEL_DESCRIPTION), its
 *      default experiment and whether it interpolates its inputs;
 *   2. the model file: the hooks below, and one definition
 *          const vi_fmu_model vi_fmu_this_model = {VI_FMU_TABLE_FIELDS(...), .init = ..., ...};
 *   3. in CMake (cmake/vi_fmu.cmake):  vi_add_fmu(<Name> SOURCES <model .c files>
 *      [LIBRARIES <libs>] [INCLUDE_DIRS <dirs>] [RESOURCES <files>] [DOCUMENTATION <files>])
 *      which generates the model descriptions from the table (cmake/vi_model_description.py),
 *      builds the binaries and packs build/<Name>.fmu (FMI 2.0) and build/fmi3/<Name>.fmu.
 *
 * The model's instance is one block of instance_size bytes, allocated zeroed by the layer with
 * the importer's allocateMemory and passed to every hook as `m`. Everything that an FMU state
 * must hold lies in one plain-data block of state_size bytes inside it (the `state` hook): the
 * parameter, input and input-derivative structs (where: the *_offset fields), time, continuous
 * and discrete state. Pointers
 * in it are never trusted after a restore. Rules for hooks: no allocation in `advance` (allocate
 * in `init` or `initialize`, release in `release`); report a failure by returning a negative
 * value with a one-line reason in the buffer `message` returns; never call exit or abort.
 *
 * What the layer guarantees to the hooks: called only in the FMI states where it makes sense
 * (below); values are written into the model's structs only after all values of the call were
 * checked (type, settable now, finite Real, inside the table's range or an item of its enumeration,
 * String length), so the model sees only values inside their ranges; the model's `changed` hook is called
 * after an input (any time but continuous-time mode) or a tunable parameter (between steps, in event
 * mode) was set.
 */
#ifndef VI_FMU_H
#define VI_FMU_H

#include <stddef.h>

#include "vi_table.h"

/* How a model talks to the importer's logger: category VI_FMU_LOG_* and a printf format. Events
 * and solver messages are shown when their category is enabled; warnings always, with status Warning,
 * as notes the computation goes on through (the call that logged one still returns OK: a result that
 * is not right is a hook's return value, not a message); errors always. */
typedef void (*vi_fmu_log_fn)(void *env, int category, const char *fmt, ...);
enum { VI_FMU_LOG_EVENTS, VI_FMU_LOG_SOLVER, VI_FMU_LOG_WARNING, VI_FMU_LOG_ERROR };

/* `running` of the restore hook. */
enum { VI_FMU_RUNNING_CS = 1, VI_FMU_RUNNING_ME = 2 };

/* Result of the advance hooks (VI_FMU_EVENT: advance_to_event only). */
enum { VI_FMU_ERROR = -1, VI_FMU_OK = 0, VI_FMU_DISCARD = 1, VI_FMU_EVENT = 2 };

/* What one pass of the discrete-state iteration (event_update hook) reports. The layer zeroes it
 * before the call. */
typedef struct {
    int another_pass;        /* the mode is not yet consistent: call again at the same time */
    int terminate;           /* nothing can go on from here (the message says why) */
    int states_changed;      /* the continuous states changed (snapped onto a surface, say) */
    int nominals_changed;    /* the nominals of the continuous states changed */
    int next_time_defined;   /* a time event is due at next_time (> the current time) */
    double next_time;
} vi_fmu_event;

/* The default experiment the model descriptions declare (VI_DEFAULT_EXPERIMENT). */
typedef struct {
    double start_s, stop_s;
    double tolerance; /* 0: none declared */
    double step_s;    /* communication step size */
} vi_fmu_experiment;

typedef struct {
    /* ---- identity (what the model descriptions are generated from, with the table) ---- */
    const char *model_identifier, *guid;
    const char *description;                  /* one sentence on what the model simulates */
    vi_fmu_experiment default_experiment;
    int can_interpolate_inputs;               /* the model uses the first derivatives of its Real inputs */
    const vi_variable *variables;             /* vi_variable_table */
    int nvariables;                           /* VI_NVARS */
    const vi_enum_item *enum_items;           /* vi_enum_items (for the table dump) */
    int n_enum_items;                         /* vi_enum_item_count */
    const vi_enum_type *enum_types;           /* vi_enum_types (for the table dump) */
    int n_enum_types;                         /* vi_enum_type_count */
    size_t instance_size;                     /* bytes of the model's instance */
    size_t state_size;                        /* bytes of the plain-data block of the `state` hook */
    size_t outputs_size;                      /* sizeof(vi_outputs) */
    /* Where the values live inside the plain-data block: offsets of its vi_parameters struct, its
     * vi_inputs struct, and the vi_inputs struct of the input derivatives (offsetof). */
    size_t parameters_offset, inputs_offset, input_derivatives_offset;

    /* ---- life cycle ---- */
    /* Zeroed memory -> defaults (start values of the table); keep log and env for messages. */
    void (*init)(void *m, vi_fmu_log_fn log, void *env);
    /* Back to the defaults (fmi2Reset, fmi3Reset). */
    void (*reset)(void *m);
    /* Release what the model allocated (not m itself). */
    void (*release)(void *m);
    /* Optional (NULL: none). The FMU's resources folder as a path (decoded from the file URI
     * fmuResourceLocation), once after init; NULL when the importer gave none that is a local
     * folder. 0 or -1. */
    int (*set_resources)(void *m, const char *dir);

    /* ---- values ---- */
    /* An input, or a tunable parameter between steps, was set: apply at the next step (Model
     * Exchange: set in event mode, apply in the event iteration; inputs set in continuous-time mode
     * are not announced: the model reads them at every evaluation). */
    void (*changed)(void *m);
    /* Outputs and calculated parameters at the current time into *out (a vi_outputs). In
     * initialization mode the layer calls `prepare` first. */
    void (*outputs)(void *m, void *out);
    /* Optional (NULL: `outputs`): where the outputs and calculated parameters at the current time
     * are (a vi_outputs inside the model, read before the next call into the model), of which only
     * those among the nvr value references vr[] need be up to date: a get call passes its own
     * array, so a model computes what is read and nothing is copied. */
    const void *(*outputs_of)(void *m, const unsigned vr[], size_t nvr);

    /* ---- simulation ---- */
    /* fmi2SetupExperiment, or the same arguments of fmi3EnterInitializationMode: they are checked
     * (finite start, tolerance in (0, 1), stop >= start); tolerance_defined = 0 means none given. */
    void (*setup_experiment)(void *m, double start_time, int tolerance_defined, double tolerance);
    /* Check what the table's ranges cannot say about the parameters (the layer has refused values
     * outside their ranges) and compute calculated values and the initial state, so that outputs
     * can be read in initialization mode. 0 or -1. */
    int (*prepare)(void *m);
    /* fmi2ExitInitializationMode, fmi3ExitInitializationMode: everything needed for stepping. 0 or -1. */
    int (*initialize)(void *m);
    /* Advance from the current time to t_end. VI_FMU_OK: time is t_end. VI_FMU_DISCARD: stopped
     * earlier at a consistent state (time = the last successful time; the message says why).
     * VI_FMU_ERROR: failed. */
    int (*advance)(void *m, double t_end);
    /* Optional (NULL: the model never stops at events; the FMI 3.0 face then never returns early).
     * As advance, and it also ends at the first change of the model's mode inside the step (its
     * events, as accurately as its solver locates them): VI_FMU_EVENT, time() is that instant, the
     * new mode in force; the next advance goes on from there. */
    int (*advance_to_event)(void *m, double t_end);
    /* Current time [s]. */
    double (*time)(const void *m);
    /* Optional: fmi2Terminate, fmi3Terminate (e.g. log statistics). */
    void (*terminate)(void *m);

    /* ---- FMU state ---- */
    /* The plain-data block saved in an FMU state. */
    void *(*state)(void *m);
    /* Optional: make the block the complete continuation before it is copied. 0 or -1. */
    int (*checkpoint)(void *m);
    /* Optional: the block was overwritten by a saved state; `running` is nonzero when the saved
     * FMI state was after initialization (step complete, step failed, event, continuous time,
     * terminated, error): VI_FMU_RUNNING_CS or VI_FMU_RUNNING_ME, the interface of the instance.
     * 0 or -1. */
    int (*restore)(void *m, int running);
    /* Optional: check a saved block before it is used: every field finite and in range, modes
     * consistent; `running` as for `restore` (before initialization only the settings matter; in
     * Model Exchange the importer's states may lie beyond the mode's surfaces until the next event).
     * 0, or -1 naming the first bad field in msg. The layer itself has already checked the
     * header, the checksum and the table's values (Reals finite, Reals and Integers inside their
     * ranges, enumerations items of their type, Booleans 0 or 1, Strings terminated). */
    int (*state_check)(const void *state, int running, char *msg, size_t n);

    /* The reason of the last failure (a NUL-terminated string inside the instance). */
    const char *(*message)(const void *m);

    /* ---- Model Exchange (optional: a model with n_states = 0 offers Co-Simulation only, and its
     * generated model descriptions have no <ModelExchange>; with n_states > 0 every hook below is required,
     * but `indicators` when n_indicators = 0 and `directional_derivative`, whose absence the XML
     * declares with providesDirectionalDerivative="false").
     * The importer integrates x' = f(t, x, u); the model keeps its mode, memory and time. The layer
     * has checked every argument: states and time finite, the call allowed in the FMI state. ---- */
    int n_states;     /* continuous states (numberOfContinuousStates) */
    int n_indicators; /* event indicators (numberOfEventIndicators) */
    /* Value references of the states and of their derivatives (n_states each), in state order. */
    const unsigned *state_vrs, *derivative_vrs;
    /* The end of initialization mode of a Model Exchange instance: like `initialize`, for an importer's
     * integrator (the model's own solver is not used). 0 or -1. */
    int (*me_initialize)(void *m);
    /* The importer sets the time [s] (states keep their values, inputs theirs). */
    void (*set_time)(void *m, double t);
    /* The continuous states, read and written in the order of state_vrs. */
    void (*get_states)(void *m, double x[]);
    void (*set_states)(void *m, const double x[]);
    /* The derivatives x' at the current time, states and inputs (in the current mode). */
    void (*derivatives)(void *m, double dx[]);
    /* The event indicators z at the current time, states and inputs: an event is due where one
     * changes sign (a guard of the mode reached zero). */
    void (*indicators)(void *m, double z[]);
    /* Nominal magnitudes of the states (for the importer's absolute tolerances): the scales of the
     * problem once initialized, 1 before. */
    void (*nominals)(const void *m, double nominal[]);
    /* One pass of the discrete-state iteration at the current time (event mode): apply what is due
     * (guards that reached zero, time events, inputs and tunable parameters set since the last
     * pass) and fill *ev. 0 or -1 (message). */
    int (*event_update)(void *m, vi_fmu_event *ev);
    /* The importer completed an integrator step at the current state: 1 to ask for an event now,
     * else 0. */
    int (*completed_step)(void *m);
    /* Optional: continuous-time mode begins (fmi2/fmi3EnterContinuousTimeMode); inputs set after the last
     * pass of the event iteration act from now on as continuous-time inputs do. */
    void (*enter_continuous)(void *m);
    /* Directional derivative at the current point: dunknown = J dknown, J the partial derivatives
     * of the unknowns (state derivatives and outputs, value references) with respect to the knowns
     * (states and inputs, value references). 0, or -1 naming the first pair it cannot give. */
    int (*directional_derivative)(void *m, const unsigned unknown[], size_t n_unknown, const unsigned known[],
                                  size_t n_known, const double dknown[], double dunknown[]);
} vi_fmu_model;

/* The fields of vi_fmu_model that follow from the model's table header (VI_MODEL_IDENTIFIER,
 * VI_GUID, VI_MODEL_DESCRIPTION, VI_DEFAULT_EXPERIMENT, VI_CAN_INTERPOLATE_INPUTS and what
 * VI_TABLE_DECLARE generates), its instance type, and its plain-data type, whose members par
 * (vi_parameters), in and din (vi_inputs) hold the values:
 *     const vi_fmu_model vi_fmu_this_model = {VI_FMU_TABLE_FIELDS(my_instance, my_data), .init = ..., ...};
 * VI_FMU_ROWS_FIELDS takes the VI_NVARS rows from another array (a test's, with rows after them). */
#define VI_FMU_TABLE_FIELDS(instance_type, data_type)                                                   \
    VI_FMU_ROWS_FIELDS(instance_type, data_type, vi_variable_table)
#define VI_FMU_ROWS_FIELDS(instance_type, data_type, rows)                                              \
    .model_identifier = VI_MODEL_IDENTIFIER, .guid = VI_GUID, .description = VI_MODEL_DESCRIPTION,     \
    .default_experiment = VI_DEFAULT_EXPERIMENT, .can_interpolate_inputs = VI_CAN_INTERPOLATE_INPUTS,   \
    .variables = (rows), .nvariables = VI_NVARS, .enum_items = vi_enum_items,                          \
    .n_enum_items = VI_NENUM_ITEMS, .enum_types = vi_enum_types, .n_enum_types = VI_NENUM_TYPES,        \
    .instance_size = sizeof(instance_type), .state_size = sizeof(data_type),                           \
    .outputs_size = sizeof(vi_outputs), .parameters_offset = offsetof(data_type, par),                 \
    .inputs_offset = offsetof(data_type, in), .input_derivatives_offset = offsetof(data_type, din)

/* Defined by the model: the one model of this FMU binary. */
extern const vi_fmu_model vi_fmu_this_model;

#endif
