/*
 * vi_fmu_contact.c - the contact model (vi_sim) as a model of the generic FMI 2.0 layer (vi_fmu.h).
 * Everything FMI-specific lives in src/vi_fmi2.c; this file only maps the layer's hooks onto vi_sim.
 */
#include <stddef.h>

#include "vi_fmu.h"
#include "vi_sim.h"

_Static_assert((int)VI_FMU_LOG_EVENTS == (int)VI_LOG_EVENTS && (int)VI_FMU_LOG_SOLVER == (int)VI_LOG_SOLVER &&
                   (int)VI_FMU_LOG_WARNING == (int)VI_LOG_WARNING && (int)VI_FMU_LOG_ERROR == (int)VI_LOG_ERROR,
               "vi_sim logs with the layer's categories");

static void init(void *m, vi_fmu_log_fn log, void *env) { vi_sim_init(m, log, env); }
static void reset(void *m) { vi_sim_reset(m); }
static void release(void *m) { vi_sim_free(m); }

static int set_resources(void *m, const char *dir)
{
    vi_sim_set_resources(m, dir);
    return 0;
}

static void changed(void *m) { ((vi_sim *)m)->d.inputs_changed = 1; }
static void outputs(void *m, void *out) { vi_sim_outputs(m, out); }

static void setup_experiment(void *m, double start_time, int tolerance_defined, double tolerance)
{
    vi_sim_data *d = &((vi_sim *)m)->d;
    d->t_start = start_time;
    d->tolerance = tolerance_defined ? tolerance : 0.0;
}

static int prepare(void *m) { return vi_sim_prepare(m); }

static int initialize(void *m)
{
    vi_sim *s = m;
    if (vi_sim_initialize(s) < 0) return -1;
    s->log(s->log_env, VI_LOG_EVENTS, "initial mode %d, delta = %.9g m, v = %.9g m/s", s->d.M.mode, s->d.x[0],
           s->d.x[1]);
    return 0;
}

static int advance(void *m, double t_end) { return vi_sim_advance(m, t_end); }
static double time_of(const void *m) { return ((const vi_sim *)m)->d.t; }

static void terminate(void *m)
{
    const vi_sim *s = m;
    vi_solver_stats st;
    vi_sim_statistics(s, &st);
    s->log(s->log_env, VI_LOG_SOLVER,
           "%s statistics: %ld steps, %ld rhs evaluations, %ld Jacobian evaluations, %ld nonlinear iterations, "
           "%ld nonlinear failures, %ld error test failures, %ld guard evaluations, %ld restarts, %ld events",
           st.method ? st.method : "solver", st.steps, st.rhs_evals, st.jac_evals, st.nonlin_iters, st.nonlin_fails, st.err_test_fails, st.guard_evals,
           st.resets, s->d.n_events);
}

static void *state(void *m) { return &((vi_sim *)m)->d; }

/* A state saved before initialization needs no solver: fmi2ExitInitializationMode creates one. */
static int restore(void *m, int running) { return running ? vi_sim_restore(m) : 0; }

/* A state taken from a running instance is its complete continuation (doc/model.md section 7.5). */
static int checkpoint(void *m) { return vi_sim_checkpoint(m); }

/* Every field of a saved block (doc/model.md section 7.6); before initialization only the settings exist. */
static int state_check(const void *state, int running, char *msg, size_t n)
{
    return running ? vi_sim_data_check(state, msg, n) : 0;
}

static const char *message(const void *m) { return ((const vi_sim *)m)->msg; }

const vi_fmu_model vi_fmu_this_model = {
    VI_FMU_TABLE_FIELDS(vi_sim, vi_sim_data),
    .init = init,
    .reset = reset,
    .release = release,
    .set_resources = set_resources,
    .changed = changed,
    .outputs = outputs,
    .setup_experiment = setup_experiment,
    .prepare = prepare,
    .initialize = initialize,
    .advance = advance,
    .time = time_of,
    .terminate = terminate,
    .state = state,
    .checkpoint = checkpoint,
    .restore = restore,
    .state_check = state_check,
    .message = message,
};
