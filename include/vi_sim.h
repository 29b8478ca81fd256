/*
 * vi_sim.h - one simulation: parameters, inputs, the hybrid model, its state, and the solver.
 * The FMI glue (src/vi_fmu_contact.c) owns one vi_sim per instance and calls it through the
 * functions below; nothing here calls FMI. Comments and messages name the FMI call a value comes
 * from where the user needs it: the tolerance is the one of fmi2SetupExperiment.
 *
 * vi_sim_data is plain data: it is what fmi2GetFMUstate copies and what
 * fmi2SerializeFMUstate writes. Its one pointer, the model's profile (rolling), is never trusted
 * from a saved state: vi_sim_prepare and vi_sim_restore point it at the instance's own profile.
 * vi_sim_checkpoint before the copy and vi_sim_restore after it make a
 * restored copy continue bit for bit like the original (doc/model.md section 7.5).
 * The solver points into s->d: a vi_sim stays where it was initialized (never copied or moved).
 */
#ifndef VI_SIM_H
#define VI_SIM_H

#include "vi_format.h"
#include "vi_hybrid.h"
#include "vi_model.h"
#include "vi_solver.h"
#include "vi_variables.h"

/* Longest path of the resources folder or a profile file. */
#define VI_PATH_MAX 4096

/* Results of vi_sim_advance (doc/model.md section 7.1); VI_SIM_EVENT only from vi_sim_advance_until. */
enum { VI_SIM_OK = 0, VI_SIM_DISCARD = 1, VI_SIM_ERROR = -1, VI_SIM_EVENT = 2 };

/* Work bounds of one vi_sim_advance (one fmi2DoStep): internal solver steps and events. When either
 * is reached the advance ends with VI_SIM_DISCARD at the time reached (a consistent state). At about
 * 1 us per step the step bound is about a second of CPU. */
#define VI_MAX_STEPS_PER_ADVANCE 1000000L
#define VI_MAX_EVENTS_PER_ADVANCE 100000L
/* Early return (vi_sim_advance_until): a change of mode ends the advance only when it comes more than
 * this many units of the time resolution DBL_EPSILON max(1 s, |t|) after the advance's start (the
 * FMI layer takes steps of at least 16 such units); a change closer to the start is taken in the
 * same advance, as one at its very instant. */
#define VI_EARLY_RETURN_UNITS 1024.0
/* A breakpoint of the platform motion (a kink of the rolling profile) closer than this many ulps of
 * the time is taken at once, without integrating (the solver cannot step that little). */
#define VI_BREAKPOINT_ULPS 64.0

typedef struct {
    vi_parameters par;
    vi_inputs in;        /* input values as last set */
    vi_inputs din;       /* their time derivatives (order 1); setting a value resets its derivative */
    int inputs_changed;  /* set by the setters; applied at the start of the next step */
    double t_start;
    double tolerance;    /* the importer's (fmi2SetupExperiment, fmi3EnterInitializationMode), 0 when not
                            defined (then par.rtol counts) */
    int initialized;     /* vi_sim_initialize done: atol, model and state are those of a running simulation */
    vi_model model;
    double t, x[2];      /* time [s] and state (delta [m], v [m/s]); between events x is the solver's
                            interpolant at t, the solver itself may be ahead */
    double y_me;         /* Model Exchange: the mass position y [m] the importer integrates (delta =
                            yC(t) - y), kept as given so that a restored state gives it back bit for bit */
    vi_hybrid_state events;          /* the event engine's state: tolerances, guard bands, Zeno count */
    double step_t0, step_v0;         /* start of the last step and the velocity there (for F_mean) */
    double step_u0;                  /* Model Exchange: yC_in [m] at step_t0 */
    double yC_in_rate;               /* Model Exchange without velocity_input: the rate of yC_in [m/s] the
                                        model runs, estimated at completed steps (vi_me.h) */
    double W_damping, F_peak;        /* the damping's work [J] (vi_model_damping_power; Model Exchange: the
                                        importer's third state); the largest force [N] since step_t0
                                        (Co-Simulation) */
    vi_ode ode;                      /* solver = dop853 or auto: the one-step method's whole continuation */
    vi_solver_auto auto_choice;      /* solver = auto: which method runs, and its stiffness counts */
} vi_sim_data;

/* The force F [N] and its rate g [N/s] at a point (t, x) of the solution in a mode: where the last piece
 * of the solution ended (vi_sim.c, the largest force); valid until the model changes otherwise than by
 * integration. Not part of an FMU state. */
typedef struct {
    double t, x[2], F, g;
    int mode, valid;
} vi_peak_point;

/* The solver's warnings as relayed to the importer (vi_sim_solver_log): counted by kind, a kind being a
 * text with its numbers left out. The first warning of each kind is relayed, with the contact's time
 * scale; the others are counted and reported once, at the end of the advance (vi_sim_report_warnings).
 * Not part of the FMU state. */
#define VI_RELAY_KINDS 4      /* kinds remembered; warnings of further kinds are counted together */
#define VI_RELAY_KIND_MAX 160 /* the bytes of a warning that make its kind */
typedef struct {
    char kind[VI_RELAY_KINDS][VI_RELAY_KIND_MAX]; /* the first warning of each kind (truncated) */
    long repeats[VI_RELAY_KINDS]; /* warnings of each kind since the last report, not relayed */
    long others;                  /* warnings of further kinds since the last report */
    int kinds;                    /* kinds seen in this run */
} vi_relay;

typedef struct {
    vi_sim_data d;
    vi_hybrid engine;    /* the event engine over d.model and d.events */
    vi_solver *solver;
    int solver_stale;    /* the state changed outside the solver: restart before the next advance */
    unsigned out_valid;  /* the groups of outputs (VI_OUT_*) out holds at the current d */
    vi_outputs out;
    vi_log_fn log;
    void *log_env;
    vi_peak_point peak_end; /* where the last piece ended, or the model last changed (the largest force) */
    int warned_validity; /* VI_INVALID_* bits: the causes warned of (once each; not part of the FMU state) */
    int validity_unchecked; /* a state was restored: check every cause at the next communication point */
    /* Rolling: the profile the model points to (owned here, outside the FMU state), the file it came
     * from with the radius and periodicity it was built for, and the FMU's resources folder. */
    vi_profile *profile;
    char profile_key[VI_PATH_MAX + 64];
    char resources[VI_PATH_MAX];
    vi_relay relay;      /* the solver's warnings relayed and counted */
    double advance_end;  /* the end of the advance in progress [s] (the failure messages') */
    char msg[1024];      /* last error message */
} vi_sim;

/* The FMU's resources folder (a path, not a URI; NULL or "" for none), where a relative
 * profile_file is looked up first (then the working directory). Kept across vi_sim_reset. */
void vi_sim_set_resources(vi_sim *s, const char *dir);

/* The model's parameters (vi_model.h) from the FMU's. */
vi_model_params vi_sim_model_params(const vi_parameters *p);
/* Defaults of the variable table; no solver yet. */
void vi_sim_init(vi_sim *s, vi_log_fn log, void *log_env);
/* Back to the defaults; frees the solver. */
void vi_sim_reset(vi_sim *s);
void vi_sim_free(vi_sim *s);

/* Check what the ranges of the variable table cannot say (each parameter lies in its range: the
 * FMI layer refuses other values when they are set): the experiment's tolerance in [VI_RTOL_MIN,
 * VI_RTOL_MAX], max_step 0 or at least VI_MAX_STEP_MIN, a radius > 0 (vi_model_setup), a profile
 * that loads for R1 > 0; then compute the derived parameters and the initial state (no solver).
 * 0, or -1 with the reason in s->msg. */
int vi_sim_prepare(vi_sim *s);
/* The inputs from t on, as ramps (doc/model.md section 5): each input's value as last set, at the rate
 * the importer gave as its derivative (Co-Simulation; 0 when none was given, and always in Model
 * Exchange); with velocity_input, yC_in at the rate vC_in instead, so that the platform's rate is the
 * importer's wherever the model needs it (damping, rate guards, mode choice, static start) and, in
 * Co-Simulation, yC_in is carried through the step at that rate. */
void vi_sim_input_ramps(const vi_sim_data *d, double t, vi_ramp *yC_in, vi_ramp *F_ext);
/* The relative tolerance the simulation runs at: rtol when set (> 0), else the experiment's tolerance
 * when given, else VI_RTOL_DEFAULT (doc/model.md section 5). */
double vi_sim_rtol(const vi_sim_data *d);
/* vi_sim_prepare, then create the solver. 0 or -1 (s->msg). */
int vi_sim_initialize(vi_sim *s);
/* Log (category solver) the method, the tolerances and the scales of an initialized simulation. */
void vi_sim_log_solver(const vi_sim *s);
/* Integrate from s->d.t to t_end > s->d.t, locating and applying every event (doc/model.md section 7.1):
 *   VI_SIM_OK:      s->d.t = t_end;
 *   VI_SIM_DISCARD: a work bound was reached or events accumulate at one instant (Zeno); s->d.t is
 *                   where the simulation got, the state there is consistent and usable, and s->msg
 *                   names that time and the cause;
 *   VI_SIM_ERROR:   s->msg says why (t_end not beyond s->d.t, solver failure, non-finite state). */
int vi_sim_advance(vi_sim *s, double t_end);
/* vi_sim_advance, and with stop_at_mode_change nonzero it also ends at the first change of mode
 * (contact, separation, yield, turning point, stick entry or exit; by an event or a kink of the
 * profile) after the instant it starts (more than VI_EARLY_RETURN_UNITS units of time after it):
 *   VI_SIM_EVENT:   s->d.t is the time of that change as the solver located it (t_end or earlier),
 *                   the new mode is in force and the state there is consistent; the next advance
 *                   continues from it as an uninterrupted one would. */
int vi_sim_advance_until(vi_sim *s, double t_end, int stop_at_mode_change);
/* The outputs of `groups` (VI_OUT_*, vi_model.h; VI_OUT_DERIVATIVES is Model Exchange's) at the
 * current time: s->out, where each group is computed when first asked for at the current state
 * (lazy, cached until the state changes through a vi_sim call); other groups may be stale there. */
const vi_outputs *vi_sim_outputs_of(vi_sim *s, unsigned groups);
/* Every output and calculated parameter at the current time. */
void vi_sim_outputs(vi_sim *s, vi_outputs *out);
/* Make s->d the complete continuation before it is copied into an FMU state. CVODE:
 * the running solver restarts at (s->d.t, s->d.x), exactly as vi_sim_restore makes a restored copy
 * start, so both continue from identical data. 0 or -1 (s->msg). */
int vi_sim_checkpoint(vi_sim *s);
/* Start the solver from s->d after it was overwritten by a saved state (any FMI state). 0 or -1. */
int vi_sim_restore(vi_sim *s);
/* As vi_sim_restore for a state of Model Exchange, where the importer integrates: no solver is made
 * (and the solver's continuation in s->d is neither used nor checked). */
int vi_sim_restore_without_solver(vi_sim *s);
void vi_sim_statistics(const vi_sim *s, vi_solver_stats *st);
/* Warn (once per cause and instance) when the contact leaves the model's range of validity at the
 * current state (vi_model_validity). */
void vi_sim_check_validity(vi_sim *s);
/* The logger the solver gets (a vi_log_fn; env is the vi_sim): its warnings relayed, counted by kind
 * (vi_relay), everything else passed on. */
void vi_sim_solver_log(void *env, int category, const char *fmt, ...) VI_PRINTF_FORMAT(3, 4);
/* Report the warnings counted since the last report, one message per kind (and one for the further
 * kinds): how many, up to the current time. Every advance ends with it. */
void vi_sim_report_warnings(vi_sim *s);

/* Is d a state this FMU could have produced (doc/model.md section 7.6)? Checks every field of
 * vi_sim_data that the simulation layer owns (finite times and state, the tolerances, counters >= 0,
 * flags 0 or 1, the one-step method's continuation) and then the model's part (vi_model_check). The
 * parameters and inputs (par, in, din) are the variable table's: the FMI layer checks them (finite,
 * in their ranges, items of their enumerations) before it calls this. 0 when valid, else -1 with the
 * first bad field named in msg. No pointer in d is followed (the model's profile pointer is not). */
int vi_sim_data_check(const vi_sim_data *d, char *msg, size_t n);
/* The same with vi_model_check_between_events and without the solver's continuation (ode, auto_choice): the
 * state of an outside integrator (Model Exchange). */
int vi_sim_data_check_between_events(const vi_sim_data *d, char *msg, size_t n);

#endif
