/*
 * vi_solver.h - a small wrapper around SUNDIALS CVODE 6.4 for a dense ODE system with rootfinding.
 *
 * Lifecycle: vi_solver_create -> (vi_solver_reset | vi_solver_advance)* -> vi_solver_free.
 * The solver integrates x' = rhs(t, x) and stops at the first zero of any guard g_i(t, x) crossed
 * from positive to negative (root direction -1), or at tout, which it never passes (the stop time
 * is set before every advance: SUNDIALS 6.4 forgets it once reached). After an event the caller
 * changes the model and calls vi_solver_reset (CVodeReInit, a cold restart).
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

typedef struct {
    int n, nguards; /* at most VI_SOLVER_MAX_N and VI_SOLVER_MAX_GUARDS */
    vi_rhs_fn rhs;
    vi_guard_fn guards;
    vi_jac_fn jac;      /* NULL: difference quotients */
    void *user;         /* passed to rhs, guards, jac */
    int adams;          /* 0: BDF, 1: Adams-Moulton (both with Newton iteration and a dense solver) */
    double rtol;
    const double *atol; /* n absolute tolerances */
    double max_step;    /* 0: none */
    long max_steps;     /* per advance */
    vi_log_fn log;
    void *log_env;
} vi_solver_config;

typedef struct {
    long steps, rhs_evals, jac_evals, nonlin_iters, nonlin_fails, err_test_fails, guard_evals, resets;
} vi_solver_stats;

enum { VI_SOLVER_REACHED = 0, VI_SOLVER_EVENT = 1, VI_SOLVER_FAILED = -1 };

typedef struct vi_solver vi_solver;

/* NULL on failure (logged). Copies the configuration; cfg->atol must hold n values. */
vi_solver *vi_solver_create(const vi_solver_config *cfg, double t0, const double *x0);
/* Restart from (t0, x0). 0 or VI_SOLVER_FAILED. */
int vi_solver_reset(vi_solver *s, double t0, const double *x0);
/* Integrate towards tout. On VI_SOLVER_EVENT, *t and x hold the event and fired[i] is nonzero for
 * the guards that crossed; on VI_SOLVER_REACHED, *t == tout. */
int vi_solver_advance(vi_solver *s, double tout, double *t, double *x, int *fired);
void vi_solver_statistics(const vi_solver *s, vi_solver_stats *st);
void vi_solver_free(vi_solver *s);

#endif
