/*
 * vi_sim.h - one simulation: parameters, inputs, the hybrid model, its state, and the solver.
 * The FMI glue owns one vi_sim per instance; nothing here knows FMI.
 *
 * vi_sim_data is plain data (no pointers): it is what fmi2GetFMUstate copies and what
 * fmi2SerializeFMUstate writes. After it is restored the solver restarts from the restored state.
 */
#ifndef VI_SIM_H
#define VI_SIM_H

#include "vi_model.h"
#include "vi_solver.h"
#include "vi_variables.h"

/* Longest path of the resources folder or a profile file. */
#define VI_PATH_MAX 4096

typedef struct {
    vi_parameters par;
    vi_inputs in;        /* input values as last set */
    vi_inputs din;       /* their time derivatives (order 1); setting a value resets its derivative */
    int inputs_changed;  /* set by the setters; applied at the start of the next step */
    double t_start;
    double tolerance;    /* from fmi2SetupExperiment, 0 when not defined (then par.rtol counts) */
    vi_model M;
    double t, x[2];      /* time [s] and state (delta [m], v [m/s]) */
    double atol[2];      /* absolute tolerances, from the problem's scales at initialization */
    long n_events;
} vi_sim_data;

typedef struct {
    vi_sim_data d;
    vi_solver *solver;
    int solver_stale;    /* the state changed outside the solver: restart before the next advance */
    vi_log_fn log;
    void *log_env;
    int warned_validity; /* the model left its range of validity: warned once (not part of the FMU state) */
    /* Rolling: the profile the model points to (owned here, outside the FMU state), the file it came
     * from with the radius and periodicity it was built for, and the FMU's resources folder. */
    vi_profile *profile;
    char profile_key[VI_PATH_MAX + 64];
    char resources[VI_PATH_MAX];
    char msg[512];       /* last error message */
} vi_sim;

/* Contract C5: the FMU's resources folder (a path, not a URI; NULL or "" for none), where a relative
 * profile_file is looked up first (then the working directory). Kept across vi_sim_reset. */
void vi_sim_set_resources(vi_sim *s, const char *dir);

/* Defaults of the variable table; no solver yet. */
void vi_sim_init(vi_sim *s, vi_log_fn log, void *log_env);
/* Back to the defaults; frees the solver. */
void vi_sim_reset(vi_sim *s);
void vi_sim_free(vi_sim *s);

/* Check the parameters and compute the derived ones and the initial state (no solver).
 * 0, or -1 with the reason in s->msg. */
int vi_sim_prepare(vi_sim *s);
/* vi_sim_prepare, then create the solver. 0 or -1 (s->msg). */
int vi_sim_initialize(vi_sim *s);
/* Integrate from s->d.t to t_end, locating and applying every event. 0 or -1 (s->msg). */
int vi_sim_advance(vi_sim *s, double t_end);
/* Outputs and calculated parameters at the current time. */
void vi_sim_outputs(const vi_sim *s, vi_outputs *out);
/* Restart the solver from s->d after it was overwritten by a saved state. 0 or -1 (s->msg). */
int vi_sim_restore(vi_sim *s);
void vi_sim_statistics(const vi_sim *s, vi_solver_stats *st);

#endif
