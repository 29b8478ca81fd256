/*
 * vi_run.h - what both drivers share: one run of the contact model, set up from its parameters, with
 * the event engine, time and state, the outputs computed from the model, and the validity warnings.
 * The Co-Simulation driver (vi_sim.h) integrates it with its own solver; the Model Exchange driver
 * (vi_me.h) lets the importer integrate it. Neither driver calls the other: each works on a vi_run
 * and its own data; each driver holds an event engine (vi_hybrid.h) bound to the run's model and
 * engine state. Nothing here integrates, and nothing here calls FMI.
 *
 * vi_run_data is plain data: part of what fmi2GetFMUstate copies and fmi2SerializeFMUstate writes.
 * Its one pointer, the model's profile (rolling), is never trusted from a saved state: vi_run_prepare
 * and vi_run_restore point it at the run's own profile. The run points to its data and the engine
 * into it: neither moves after vi_run_init.
 */
#ifndef VI_RUN_H
#define VI_RUN_H

#include "vi_format.h"
#include "vi_hybrid.h"
#include "vi_model.h"
#include "vi_variables.h"

/* Longest path of the resources folder or a profile file. */
#define VI_PATH_MAX 4096

typedef struct {
    vi_parameters par;
    vi_inputs in;        /* input values as last set */
    vi_inputs din;       /* their time derivatives (order 1); setting a value resets its derivative */
    int inputs_changed;  /* set by the setters; applied at the start of the next step */
    double t_start;
    double tolerance;    /* the importer's (fmi2SetupExperiment, fmi3EnterInitializationMode), 0 when not
                            defined (then par.rtol counts) */
    int initialized;     /* a driver initialized the run: atol, model and state are those of a running simulation */
    vi_model model;
    double t, x[2];      /* time [s] and state (delta [m], v [m/s]); Co-Simulation: between events x is the
                            solver's interpolant at t, the solver itself may be ahead */
    vi_hybrid_state events;          /* the event engine's state: tolerances, guard bands, Zeno count */
    double step_t0, step_v0;         /* start of the last step and the velocity there (for F_mean) */
    double W_damping, F_peak;        /* the damping's work [J] (vi_model_damping_power; Model Exchange: the
                                        importer's third state); the largest force [N] since step_t0
                                        (Co-Simulation) */
} vi_run_data;

typedef struct {
    vi_run_data *d;
    unsigned out_valid;  /* the groups of outputs (VI_OUT_*) out holds at the current d */
    vi_outputs out;
    vi_log_fn log;
    void *log_env;
    int warned_validity; /* VI_INVALID_* bits: the causes warned of (once each; not part of the FMU state) */
    int validity_unchecked; /* a state was restored: check every cause at the next communication point */
    /* Rolling: the profile the model points to (owned here, outside the FMU state), the file it came
     * from with the radius and periodicity it was built for, and the FMU's resources folder. */
    vi_profile *profile;
    char profile_key[VI_PATH_MAX + 64];
    char resources[VI_PATH_MAX];
    char msg[1024];      /* last error message (of the run and of its driver) */
} vi_run;

/* The model's parameters (vi_model.h) from the FMU's. */
vi_model_params vi_run_model_params(const vi_parameters *p);
/* Bind r to its data d and set d to the defaults of the variable table. */
void vi_run_init(vi_run *r, vi_run_data *d, vi_log_fn log, void *log_env);
/* Back to the defaults, keeping the resources folder; frees the profile. */
void vi_run_reset(vi_run *r);
void vi_run_free(vi_run *r);
/* The FMU's resources folder (a path, not a URI; NULL or "" for none), where a relative
 * profile_file is looked up first (then the working directory). Kept across vi_run_reset. */
void vi_run_set_resources(vi_run *r, const char *dir);

/* Check what the ranges of the variable table cannot say (each parameter lies in its range: the
 * FMI layer refuses other values when they are set): the experiment's tolerance in [VI_RTOL_MIN,
 * VI_RTOL_MAX], max_step 0 or at least VI_MAX_STEP_MIN, a radius > 0 (vi_model_setup), a profile
 * that loads for R1 > 0; then compute the derived parameters and the initial state. 0, or -1 with the
 * reason in r->msg. */
int vi_run_prepare(vi_run *r);
/* The tolerances a prepared run integrates with: vi_run_rtol, and atol = rtol times the scales of the
 * problem at the initial state (vi_model_scales). */
void vi_run_tolerances(const vi_run *r, double *rtol, double atol[2]);
/* Bind an event engine (a driver's) to the run's model and engine state, for the driver's integrator:
 * integrates_y, it holds y = yC(t) - delta (Model Exchange), else delta (Co-Simulation). */
void vi_run_bind_engine(const vi_run *r, vi_hybrid *engine, int integrates_y);
/* A driver takes the run: its own data (own_size bytes) zeroed, its engine bound for an integrator of
 * delta (vi_run_bind_engine); returns the run's data. */
vi_run_data *vi_run_attach(const vi_run *r, vi_hybrid *engine, void *own, size_t own_size);
/* The warnings of an initialization: options that do not apply, an rtol that overrides the
 * experiment's tolerance, and the validity of the initial state. */
void vi_run_warn_settings(vi_run *r);
/* The inputs from t on, as ramps (doc/model.md section 5): each input's value as last set, at the rate
 * the importer gave as its derivative (Co-Simulation; 0 when none was given, and always in Model
 * Exchange); with velocity_input, yC_in at the rate vC_in instead, so that the platform's rate is the
 * importer's wherever the model needs it (damping, rate guards, mode choice, static start) and, in
 * Co-Simulation, yC_in is carried through the step at that rate. */
void vi_run_input_ramps(const vi_run_data *d, double t, vi_ramp *yC_in, vi_ramp *F_ext);
/* The relative tolerance the simulation runs at: rtol when set (> 0), else the experiment's tolerance
 * when given, else VI_RTOL_DEFAULT (doc/model.md section 5). */
double vi_run_rtol(const vi_run_data *d);
/* The outputs of the groups VI_OUT_STATE ... VI_OUT_STIFFNESS in `groups` at the current time: r->out,
 * where each group is computed when first asked for at the current state (lazy, cached until a
 * driver marks the state changed by clearing r->out_valid); other groups may be stale there. */
const vi_outputs *vi_run_outputs_of(vi_run *r, unsigned groups);
/* Warn (once per cause and run) when the contact leaves the model's range of validity at the
 * current state (vi_model_validity). */
void vi_run_check_validity(vi_run *r);
/* A saved state was copied into r->d: outputs and validity to be checked afresh, and (when
 * initialized) the model's profile pointer replaced by the run's own. 0 or -1 (r->msg). */
int vi_run_restore(vi_run *r);
/* The contact's time scale T = sqrt(m/k) [s] at the current state, k the tangent stiffness there (out
 * of contact: the law's at the indentation scale of vi_model_scales), with m, k and what sets k in
 * `note`; *k_out = k [N/m]. */
double vi_run_time_scale(const vi_run *r, double *k_out, char *note, size_t n);
/* Tangent contact stiffness dF/ddelta [N/m] at (t, x) (0 out of contact). */
double vi_run_contact_stiffness(const vi_model *model, double t, const double x[2]);

/* Is d a run this FMU could have produced (doc/model.md section 7.6)? Checks the fields the run owns
 * (finite times and state, the tolerances, counters >= 0, flags 0 or 1, the engine's state), not the
 * model: vi_run_data_check_model follows. The parameters and inputs (par, in, din) are the variable
 * table's: the FMI layer checks them (finite, in their ranges, items of their enumerations) before.
 * 0 when valid, else -1 with the first bad field named in msg. No pointer in d is followed. */
int vi_run_data_check(const vi_run_data *d, char *msg, size_t n);
/* The model's part: with its surfaces (vi_model_check: the state lies in its mode), or between
 * events (vi_model_check_between_events: the state of an outside integrator, Model Exchange). */
int vi_run_data_check_model(const vi_run_data *d, int surfaces, char *msg, size_t n);

#endif
