/*
 * vi_solver.h - one interface over the integrators of a small dense ODE system with guards:
 * SUNDIALS CVODE 6.4 (BDF or Adams-Moulton, Newton iteration, dense linear solver) and a built-in
 * explicit one-step method (added behind the same calls).
 *
 * Lifecycle: vi_solver_create -> (vi_solver_reset | vi_solver_advance)* -> vi_solver_free.
 * The solver integrates x' = rhs(t, x) and stops at the first zero of any guard g_i(t, x) crossed
 * from positive to negative (root direction -1), or returns the state at tout.
 *
 * Integration past output points: vi_solver_advance sets no stop time. The solver keeps its step
 * size and order, may step beyond tout, and returns x(tout) from its interpolant (CVODE:
 * CVodeGetDky inside CVode's CV_NORMAL mode); guards are checked between the last output point and
 * tout on that interpolant. The next call continues from the solver's own internal state, so a
 * call whose tout lies inside the last internal step takes no new step. The caller restarts the
 * solver (vi_solver_reset) only when the problem changes: after an event, an input jump, or when a
 * state is taken (vi_sim_checkpoint).
 *
 * Every SUNDIALS call is checked by one helper that logs the failing call through cfg->log.
 */
#ifndef VI_SOLVER_H
#define VI_SOLVER_H

/* Sizes this wrapper is made for: small dense systems. */
#define VI_SOLVER_MAX_N 4
#define VI_SOLVER_MAX_GUARDS 16

typedef void (*vi_log_fn)(void *env, int category, const char *fmt, ...);
enum { VI_LOG_EVENTS, VI_LOG_SOLVER, VI_LOG_WARNING, VI_LOG_ERROR };

typedef void (*vi_rhs_fn)(double t, const double *x, double *dx, void *user);
typedef void (*vi_guard_fn)(double t, const double *x, double *g, void *user);
typedef void (*vi_jac_fn)(double t, const double *x, double *jac_row_major, void *user);

/* Integration methods (the values of the FMU's `solver` enumeration). */
enum { VI_METHOD_BDF = 1, VI_METHOD_ADAMS = 2 };

typedef struct {
    int n, nguards; /* at most VI_SOLVER_MAX_N and VI_SOLVER_MAX_GUARDS */
    vi_rhs_fn rhs;
    vi_guard_fn guards;
    vi_jac_fn jac;      /* NULL: difference quotients */
    void *user;         /* passed to rhs, guards, jac */
    int method;         /* VI_METHOD_* */
    double rtol;
    const double *atol; /* n absolute tolerances */
    double max_step;    /* 0: none */
    vi_log_fn log;
    void *log_env;
} vi_solver_config;

typedef struct {
    long steps, rhs_evals, jac_evals, nonlin_iters, nonlin_fails, err_test_fails, guard_evals, resets;
} vi_solver_stats;

enum { VI_SOLVER_REACHED = 0, VI_SOLVER_EVENT = 1, VI_SOLVER_LIMIT = 2, VI_SOLVER_FAILED = -1 };

typedef struct vi_solver vi_solver;

/* NULL on failure (logged). Copies the configuration; cfg->atol must hold n values. */
vi_solver *vi_solver_create(const vi_solver_config *cfg, double t0, const double *x0);
/* Cold restart from (t0, x0): the next advance starts a new integration there. 0 or VI_SOLVER_FAILED. */
int vi_solver_reset(vi_solver *s, double t0, const double *x0);
/* Integrate towards tout > *t taking at most max_steps internal steps (*taken: how many it took).
 *   VI_SOLVER_REACHED: *t = tout and x = x(tout) (interpolated when the solver stepped beyond tout);
 *   VI_SOLVER_EVENT:   *t and x hold the first guard zero in (*t, tout]; fired[i] != 0 for the
 *                      guards that crossed; the caller resets the solver before going on;
 *   VI_SOLVER_LIMIT:   max_steps taken: *t and x hold the solver's last internal step (< tout),
 *                      a consistent point the solver can continue from;
 *   VI_SOLVER_FAILED:  logged. */
int vi_solver_advance(vi_solver *s, double tout, long max_steps, double *t, double *x, int *fired, long *taken);
/* Cumulative counters since vi_solver_create. */
void vi_solver_statistics(const vi_solver *s, vi_solver_stats *st);
void vi_solver_free(vi_solver *s);

#endif
