/*
 * vi_sim.h - the Co-Simulation driver: integrates a run of the contact model (vi_run.h) with its own
 * solver between the events, which the event engine locates and applies (doc/model.md section 7.1).
 * The FMI glue (src/adapter/vi_fmu_contact.c) owns one vi_run and one vi_sim per instance and calls them
 * through the functions below; nothing here calls FMI. Comments and messages name the FMI call a
 * value comes from where the user needs it: the tolerance is the one of fmi2SetupExperiment.
 *
 * vi_sim_data is plain data, the driver's part of an FMU state: the one-step method's continuation.
 * vi_sim_checkpoint before the copy and vi_sim_restore after it make a restored copy continue bit for
 * bit like the original (doc/model.md section 7.5). The solver points into the run's data and into
 * the driver's: a vi_sim stays where it was initialized (never copied or moved), as its data does.
 */
#ifndef VI_SIM_H
#define VI_SIM_H

#include "vi_run.h"
#include "vi_solver.h"

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
    int unreported;               /* warnings were counted since the last report */
    long others;                  /* warnings of further kinds since the last report */
    int kinds;                    /* kinds seen in this run */
} vi_relay;

typedef struct {
    vi_run *r;           /* the run it integrates (model, outputs, message) */
    vi_run_data *d;      /* r->d: the run's data */
    vi_sim_data *own;    /* the driver's data */
    vi_hybrid engine;    /* the event engine over the run, for this solver (delta integrated) */
    vi_solver *solver;
    int solver_stale;    /* the state changed outside the solver: restart before the next advance */
    vi_log_fn log;       /* the run's */
    void *log_env;
    vi_peak_point peak_end; /* where the last piece ended, or the model last changed (the largest force) */
    vi_relay relay;      /* the solver's warnings relayed and counted */
    double advance_end;  /* the end of the advance in progress [s] (the failure messages') */
} vi_sim;

/* Bind the driver to a run and to its own data (zeroed); no solver yet. */
void vi_sim_init(vi_sim *s, vi_run *r, vi_sim_data *d);
/* Free the solver. */
void vi_sim_free(vi_sim *s);

/* vi_run_prepare, start the engine, create the solver. 0 or -1 (the run's msg). */
int vi_sim_initialize(vi_sim *s);
/* Log (category solver) the method, the tolerances and the scales of an initialized simulation. */
void vi_sim_log_solver(const vi_sim *s);
/* Integrate the run from its time t to t_end > t, locating and applying every event (doc/model.md
 * section 7.1); t, x below are the run's (s->r->d):
 *   VI_SIM_OK:      t = t_end;
 *   VI_SIM_DISCARD: a work bound was reached or events accumulate at one instant (Zeno); t is
 *                   where the simulation got, the state there is consistent and usable, and the
 *                   run's msg names that time and the cause;
 *   VI_SIM_ERROR:   the run's msg says why (t_end not beyond t, solver failure, non-finite state). */
int vi_sim_advance(vi_sim *s, double t_end);
/* vi_sim_advance, and with stop_at_mode_change nonzero it also ends at the first change of mode
 * (contact, separation, yield, turning point, stick entry or exit; by an event or a kink of the
 * profile) after the instant it starts (more than VI_EARLY_RETURN_UNITS units of time after it):
 *   VI_SIM_EVENT:   t is the time of that change as the solver located it (t_end or earlier),
 *                   the new mode is in force and the state there is consistent; the next advance
 *                   continues from it as an uninterrupted one would. */
int vi_sim_advance_until(vi_sim *s, double t_end, int stop_at_mode_change);
/* Make the run's data and s->own the complete continuation before they are copied into an FMU state.
 * CVODE: the running solver restarts at the run's (t, x), exactly as vi_sim_restore makes a restored
 * copy start, so both continue from identical data. 0 or -1 (the run's msg). */
int vi_sim_checkpoint(vi_sim *s);
/* The run (vi_run_restore) and the solver from s->own after both were overwritten by a saved state (any
 * FMI state of Co-Simulation). 0 or -1. */
int vi_sim_restore(vi_sim *s);
void vi_sim_statistics(const vi_sim *s, vi_solver_stats *st);
/* The logger the solver gets (a vi_log_fn; env is the vi_sim): its warnings relayed, counted by kind
 * (vi_relay), everything else passed on. */
void vi_sim_solver_log(void *env, int category, const char *fmt, ...) VI_PRINTF_FORMAT(3, 4);
/* Report the warnings counted since the last report, one message per kind (and one for the further
 * kinds): how many, up to the current time. Every advance ends with it. */
void vi_sim_report_warnings(vi_sim *s);

/* Is (r, d) a state of Co-Simulation this FMU could have produced with the settings set (doc/model.md
 * section 7.6)? The run's fields (vi_run_data_check), the one-step method's continuation, then the
 * model's part (vi_model_check). 0 when valid, else -1 with the first bad field named in msg. No
 * pointer is followed (the model's profile pointer is not). */
int vi_sim_data_check(const vi_run_data *r, const vi_sim_data *d, const vi_run_settings *set, char *msg, size_t n);

#endif
