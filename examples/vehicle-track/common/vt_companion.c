/* vt_companion.c - the generic FMI-layer hooks of the vehicle-track companion models; see
 * vt_companion.h. */
#include "vt_companion.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vi_check.h"

#define VT_MAX_STEPS_PER_STEP 100000L /* CVODE steps within one communication step */

static vt_core *core(vt_instance *I) { return (vt_core *)I->data; }
static const vt_core *core_c(const vt_instance *I) { return (const vt_core *)I->data; }

double vt_input_time(const vt_core *c) { return c->inputs_changed ? c->t : c->t_in; }

void vt_init(void *m, const vt_model_def *def, void *data, vi_fmu_log_fn log, void *env)
{
    vt_instance *I = m;
    I->def = def;
    I->data = data;
    I->log = log;
    I->env = env;
    I->solver = NULL;
    I->msg[0] = '\0';
    vt_core *c = core(I);
    memset(c, 0, sizeof *c);
}

/* Back to the start; the solver (if any) is kept and restarted at initialization. */
void vt_reset(void *m)
{
    vt_instance *I = m;
    vi_solver *keep = I->solver;
    vt_init(m, I->def, I->data, I->log, I->env);
    I->solver = keep;
}

void vt_release(void *m)
{
    vt_instance *I = m;
    vi_solver_free(I->solver);
    I->solver = NULL;
}

void vt_changed(void *m) { core(m)->inputs_changed = 1; }

void vt_outputs(void *m, void *out)
{
    vt_instance *I = m;
    I->def->outputs(I->data, out);
}

void vt_setup_experiment(void *m, double start_time, int tolerance_defined, double tolerance)
{
    vt_core *c = core(m);
    c->t_start = start_time;
    c->tolerance = tolerance_defined ? tolerance : 0.0;
}

/* The rtol parameter is 0 (the experiment's tolerance) or in [VI_RTOL_MIN, VI_RTOL_MAX] (the table's
 * range says [0, VI_RTOL_MAX]). 0 or -1 with a message. */
static int check_rtol(const vt_model_def *def, const void *data, char *msg, size_t n)
{
    double r = def->rtol(data);
    if (r != 0.0 && !(r >= VI_RTOL_MIN && r <= VI_RTOL_MAX))
        VI_FAIL(msg, n, "rtol = %g: use 0 (the experiment's tolerance) or a value in [%g, %g]", r, VI_RTOL_MIN,
                VI_RTOL_MAX);
    return 0;
}

/* The relative tolerance the instance runs at, the contact FMU's rule (doc/model.md section 5, "The
 * tolerance rule"): the rtol parameter when set (> 0), else the experiment's tolerance when given, else
 * VI_RTOL_DEFAULT (the default experiment's declared tolerance). */
static double run_rtol(const vt_instance *I)
{
    double r = I->def->rtol(I->data), tolerance = core_c(I)->tolerance;
    return r > 0.0 ? r : tolerance > 0.0 ? tolerance : VI_RTOL_DEFAULT;
}

int vt_prepare(void *m)
{
    vt_instance *I = m;
    vt_core *c = core(I);
    if (c->tolerance > 0.0 && !(c->tolerance >= VI_RTOL_MIN && c->tolerance <= VI_RTOL_MAX))
        VI_FAIL(I->msg, sizeof I->msg, "relative tolerance (fmi2SetupExperiment) = %g: use a value in [%g, %g]",
                c->tolerance, VI_RTOL_MIN, VI_RTOL_MAX);
    if (check_rtol(I->def, I->data, I->msg, sizeof I->msg) < 0) return -1;
    if (I->def->check && I->def->check(I->data, I->msg, sizeof I->msg) < 0) return -1;
    c->t = c->t_in = c->t_start;
    c->inputs_changed = 0;
    memset(c->x, 0, sizeof c->x);
    I->def->start(I->data);
    c->solver_stale = 1;
    return 0;
}

/* The solver's right-hand side and Jacobian: the model's, on its block. */
static void rhs_cb(double t, const double *x, double *dx, void *user)
{
    const vt_instance *I = user;
    I->def->rhs(t, x, dx, I->data);
}

static void jac_cb(double t, const double *x, double *jac, void *user)
{
    const vt_instance *I = user;
    I->def->jac(t, x, jac, I->data);
}

/* Create the solver (allocates; never called from fmi2DoStep). 0 or -1. */
static int create_solver(vt_instance *I)
{
    const vt_model_def *def = I->def;
    const vt_core *c = core_c(I);
    double rtol = run_rtol(I);
    double atol[VT_MAX_STATES];
    def->scales(I->data, atol);
    for (int i = 0; i < def->n; i++) atol[i] *= rtol;
    vi_solver_config cfg = {
        .n = def->n, .nguards = 0, .rhs = rhs_cb, .guards = NULL, .jac = def->jac ? jac_cb : NULL, .user = I,
        .method = VI_METHOD_ADAMS, /* non-stiff, lightly damped oscillators */
        .rtol = rtol, .atol = atol, .max_step = 0.0, .ode = NULL, .log = I->log, .log_env = I->env,
    };
    vi_solver_free(I->solver);
    I->solver = vi_solver_create(&cfg, c->t, c->x);
    if (!I->solver)
        VI_FAIL(I->msg, sizeof I->msg, "the solver could not be created (see the log)");
    return 0;
}

int vt_initialize(void *m)
{
    vt_instance *I = m;
    if (vt_prepare(m) < 0) return -1;
    if (create_solver(I) < 0) return -1;
    core(I)->solver_stale = 0;
    /* a note, as the contact FMU's: an importer that passes the declared default most likely passes a default */
    double r = I->def->rtol(I->data), tolerance = core(I)->tolerance;
    if (r > 0.0 && tolerance > 0.0 && tolerance != VI_RTOL_DEFAULT && r != tolerance)
        I->log(I->env, VI_FMU_LOG_WARNING,
               "rtol = %g is used, not the experiment's tolerance %g (set rtol = 0 to use the experiment's)", r,
               tolerance);
    return 0;
}

int vt_advance(void *m, double t_end)
{
    vt_instance *I = m;
    vt_core *c = core(I);
    if (c->inputs_changed) { /* the held inputs start now; the right-hand side jumps here */
        c->t_in = c->t;
        c->inputs_changed = 0;
        c->solver_stale = 1;
    }
    if (c->solver_stale) {
        if (vi_solver_reset(I->solver, c->t, c->x) < 0) {
            vi_snprintf(I->msg, sizeof I->msg, "the solver could not restart at t = %.17g s", c->t);
            return VI_FMU_ERROR;
        }
        c->solver_stale = 0;
    }
    double t = c->t, x[VT_MAX_STATES], t0 = c->t, x0[VT_MAX_STATES];
    int fired[VI_SOLVER_MAX_GUARDS];
    long taken = 0;
    /* The solver may step past t_end and interpolate back; the next step restarts it when an input
     * changed, so no step integrates with inputs it was not given. */
    int rc = vi_solver_advance(I->solver, t_end, VT_MAX_STEPS_PER_STEP, &t, x, fired, &taken);
    if (rc != VI_SOLVER_REACHED && rc != VI_SOLVER_LIMIT) {
        vi_snprintf(I->msg, sizeof I->msg, "the integration from t = %.17g s to %.17g s failed (see the log)", c->t, t_end);
        c->solver_stale = 1; /* the state stays where the last step ended */
        return VI_FMU_ERROR;
    }
    memcpy(x0, c->x, sizeof x0);
    memcpy(c->x, x, sizeof(double) * (size_t)I->def->n);
    c->t = t;
    if (I->def->step_done) I->def->step_done(I->data, t0, x0);
    if (rc == VI_SOLVER_LIMIT) { /* a consistent point before t_end (doc/model.md section 7.1) */
        vi_snprintf(I->msg, sizeof I->msg, "work bound: %ld internal steps in one step, stopped at t = %.17g s",
                    VT_MAX_STEPS_PER_STEP, t);
        return VI_FMU_DISCARD;
    }
    return VI_FMU_OK;
}

double vt_time(const void *m) { return core_c(m)->t; }

void vt_terminate(void *m)
{
    vt_instance *I = m;
    if (!I->solver) return;
    vi_solver_stats st;
    vi_solver_statistics(I->solver, &st);
    I->log(I->env, VI_FMU_LOG_SOLVER, "%s statistics: %ld steps, %ld rhs evaluations, %ld restarts", st.method,
           st.steps, st.rhs_evals, st.resets);
}

void *vt_state(void *m) { return ((vt_instance *)m)->data; }

/* The running instance restarts from its block as a restored copy would: both continue alike. */
int vt_checkpoint(void *m)
{
    core(m)->solver_stale = 1;
    return 0;
}

int vt_restore(void *m, int running)
{
    vt_instance *I = m;
    if (!running) return 0; /* fmi2ExitInitializationMode creates the solver */
    if (running == VI_FMU_RUNNING_ME) return 0; /* the importer integrates */
    if (!I->solver && create_solver(I) < 0) return -1;
    core(I)->solver_stale = 1;
    return 0;
}

int vt_state_check(const void *state, int running, const vt_model_def *def, char *msg, size_t n)
{
    const vt_core *c = state;
    if (c->tolerance != 0.0 && !(c->tolerance >= VI_RTOL_MIN && c->tolerance <= VI_RTOL_MAX))
        VI_FAIL(msg, n, "tolerance = %g is neither 0 nor in [%g, %g]", c->tolerance, VI_RTOL_MIN, VI_RTOL_MAX);
    if (check_rtol(def, state, msg, n) < 0) return -1;
    if (def->check && def->check(state, msg, n) < 0) return -1;
    if (!running) return 0; /* before initialization only the settings matter */
    if (!isfinite(c->t) || !isfinite(c->t_in) || !isfinite(c->t_start) || c->t_in > c->t)
        VI_FAIL(msg, n, "time t = %g s, t_in = %g s, t_start = %g s: not finite or inputs set after t", c->t, c->t_in,
                c->t_start);
    for (int i = 0; i < def->n; i++)
        if (!isfinite(c->x[i])) VI_FAIL(msg, n, "state x[%d] = %g: not finite", i, c->x[i]);
    return 0;
}

const char *vt_message(const void *m) { return ((const vt_instance *)m)->msg; }
