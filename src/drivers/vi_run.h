/*
 * vi_run.h - what both drivers share: one run of the contact model, set up from plain settings (SI
 * units) with its inputs, time and state, the engine's state, the values computed from the model,
 * and the validity warnings. The Co-Simulation driver (vi_sim.h) integrates it with its own solver;
 * the Model Exchange driver (vi_me.h) lets the importer integrate it. Neither driver calls the
 * other: each works on a vi_run and its own data; each driver holds an event engine (vi_hybrid.h)
 * bound to the run's model and engine state, and changes them only through the engine's functions
 * (the run too: it sets the model up and restores it through its own view of the engine). Nothing here integrates, and nothing here knows FMI:
 * the settings and inputs come from a source (the FMU's instance, vi_contact_instance.h, maps its
 * variables onto them).
 *
 * vi_run_data is plain data: part of what fmi2GetFMUstate copies and fmi2SerializeFMUstate writes.
 * Its one pointer, the model's profile (rolling), is never trusted from a saved state: vi_run_prepare
 * and vi_run_restore point it at the run's own profile. The run points to its data, and the drivers'
 * engines into it: neither moves after vi_run_init.
 */
#ifndef VI_RUN_H
#define VI_RUN_H

#include "vi_format.h"
#include "vi_hybrid.h"
#include "vi_model.h"
#include "vi_solver.h" /* VI_METHOD_*, VI_RTOL_DEFAULT */

/* Longest path of the resources folder or a profile file. */
#define VI_PATH_MAX 4096

/* What a run is set up from (SI units): the model's parameters and how it is integrated. */
typedef struct {
    vi_model_params model;
    double t_start;           /* the start time [s] */
    double rtol;              /* the relative tolerance in force (doc/model.md section 5) */
    double rtol_given;        /* the parameter rtol (0: none), and */
    double tolerance;         /* the experiment's tolerance (0: none), for the warning when both differ */
    double max_step;          /* the solver's largest internal step [s] (0: no limit) */
    int method;               /* the solver: VI_METHOD_* (vi_solver.h) */
    int velocity_input;       /* the platform's rate is the input vC_in */
    const char *profile_file; /* the profile rolled over ("": none), relative paths in the resources
                                 folder, then the working directory */
} vi_run_settings;

/* Where the inputs as the importer set them are read, whenever the run needs them (values and, in
 * Co-Simulation, their derivatives, 0 when none was given; the tunable excitation): the FMU
 * instance's storage, which does not move. */
typedef struct {
    const double *yC_in, *yC_in_rate; /* platform displacement input [m], its derivative [m/s] */
    const double *F_ext, *F_ext_rate; /* external force [N], its derivative [N/s] */
    const double *vC_in;              /* platform velocity input [m/s] (the rate of yC_in with velocity_input) */
    const double *a, *f;              /* harmonic excitation: amplitude [m], frequency [Hz] */
} vi_run_inputs;

/* Where a run takes its settings and inputs from: the FMU instance's storage of the parameters and
 * inputs (vi_contact_instance.h). settings, read at set-up and restore: 0, or -1 with the reason in
 * msg (a value out of the run's ranges). */
typedef struct {
    int (*settings)(void *env, vi_run_settings *out, char *msg, size_t n);
    vi_run_inputs inputs;
    /* the outputs the importer reads, at a prepared run: 0, or -1 naming one that is not finite */
    int (*outputs_check)(void *env, char *msg, size_t n);
    void *env;
} vi_run_source;

/* The outputs and calculated parameters of the run at its current time: the model's, and the run's
 * and drivers' own. */
typedef struct {
    vi_model_values model;    /* groups VI_OUT_STATE ... VI_OUT_CALCULATED */
    double F_peak;            /* the largest force since the last step's start [N] (VI_OUT_FORCE) */
    double W_damping, W_dissipated; /* the damping's work, and W_plastic + W_damping [J] (VI_OUT_MEMORY) */
    double F_mean;            /* N (VI_OUT_MEAN) */
    double k_contact;         /* N/m (VI_OUT_STIFFNESS) */
    double der_y, der_v, der_W_damping; /* Model Exchange: the states' derivatives (VI_OUT_DERIVATIVES) */
} vi_run_values;

typedef struct {
    int inputs_changed;  /* inputs or the tunable excitation were set since they were applied (the
                            adapter's `changed`); applied at the start of the next step or event pass */
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
    vi_hybrid engine;    /* the run's view of the event engine over d (set-up, restore, reads) */
    vi_run_source src;
    vi_run_settings set; /* as last taken from the source (vi_run_prepare, vi_run_restore) */
    unsigned out_valid;  /* the groups of outputs (VI_OUT_*) out holds at the current d */
    vi_run_values out;
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

/* Bind r to its data d (zeroed) and to the source of its settings and inputs. */
void vi_run_init(vi_run *r, vi_run_data *d, vi_run_source src, vi_log_fn log, void *log_env);
/* Back to the start (d zeroed), keeping the resources folder and the source; frees the profile. */
void vi_run_reset(vi_run *r);
void vi_run_free(vi_run *r);
/* The FMU's resources folder (a path, not a URI; NULL or "" for none), where a relative
 * profile_file is looked up first (then the working directory). Kept across vi_run_reset. */
void vi_run_set_resources(vi_run *r, const char *dir);

/* Take the settings from the source (which checks their ranges), set the model up (a radius > 0,
 * vi_model_setup; a profile that loads for R1 > 0), compute the derived parameters and the initial
 * state, and have the source check the outputs there. 0, or -1 with the reason in r->msg. */
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
static inline void vi_run_input_ramps(const vi_run *r, double t, vi_ramp *yC_in, vi_ramp *F_ext)
{
    const vi_run_inputs *in = &r->src.inputs;
    *yC_in = (vi_ramp){*in->yC_in, r->set.velocity_input ? *in->vC_in : *in->yC_in_rate, t};
    *F_ext = (vi_ramp){*in->F_ext, *in->F_ext_rate, t};
}
/* The tunable excitation as last set: amplitude a [m], frequency f [Hz]. */
static inline void vi_run_excitation(const vi_run *r, double *a, double *f) { *a = *r->src.inputs.a, *f = *r->src.inputs.f; }
/* Compute the groups `need` (VI_OUT_STATE ... VI_OUT_STIFFNESS) into r->out and mark them valid. */
void vi_run_compute_outputs(vi_run *r, unsigned need);
/* The values of the groups VI_OUT_STATE ... VI_OUT_STIFFNESS in `groups` at the current time: r->out,
 * where each group is computed when first asked for at the current state (lazy, cached until a
 * driver marks the state changed by clearing r->out_valid); other groups may be stale there (inline:
 * every get call of the FMU asks). */
static inline const vi_run_values *vi_run_outputs_of(vi_run *r, unsigned groups)
{
    unsigned need = groups & (VI_OUT_ALL & ~VI_OUT_DERIVATIVES) & ~r->out_valid;
    if (need) vi_run_compute_outputs(r, need);
    return &r->out;
}
/* Warn (once per cause and run) when the contact leaves the model's range of validity at the
 * current state (vi_model_validity). */
void vi_run_check_validity(vi_run *r);
/* A saved state was copied into r->d (and the source's storage): the settings taken afresh, outputs
 * and validity to be checked afresh, and (when initialized) the model's profile pointer replaced by
 * the run's own. 0 or -1 (r->msg). */
int vi_run_restore(vi_run *r);
/* The contact's time scale T = sqrt(m/k) [s] at the current state, k the tangent stiffness there (out
 * of contact: the law's at the indentation scale of vi_model_scales), with m, k and what sets k in
 * `note`; *k_out = k [N/m]. */
double vi_run_time_scale(const vi_run *r, double *k_out, char *note, size_t n);
/* Tangent contact stiffness dF/ddelta [N/m] at (t, x) (0 out of contact). */
double vi_run_contact_stiffness(const vi_model *model, double t, const double x[2]);

/* Is d a run this FMU could have produced (doc/model.md section 7.6), with the start time t_start [s]
 * and the relative tolerance rtol of its settings? Checks the fields the run owns (finite times and
 * state, the tolerances, counters >= 0, flags 0 or 1, the engine's state), not the model:
 * vi_run_data_check_model follows. 0 when valid, else -1 with the first bad field named in msg. No
 * pointer in d is followed. */
int vi_run_data_check(const vi_run_data *d, double t_start, double rtol, char *msg, size_t n);
/* The model's part: with its surfaces (vi_model_check: the state lies in its mode), or between
 * events (vi_model_check_between_events: the state of an outside integrator, Model Exchange). */
int vi_run_data_check_model(const vi_run_data *d, int surfaces, char *msg, size_t n);

#endif
