/*
 * vi_solver.h - one interface over the integrators of a small dense ODE system with guards:
 * SUNDIALS CVODE 6.4 (BDF or Adams-Moulton, Newton iteration, dense linear solver), the built-in
 * explicit one-step method Dormand-Prince 8(5,3) with dense output (vi_ode.h), and `auto`: the
 * one-step method while the problem is not stiff, CVODE BDF while it is (AUTO below).
 *
 * Where the integrator's state lives:
 *   CVODE keeps its history (Nordsieck array, order, step size) inside its own memory. It cannot be
 *   copied out, so a state taken for later (vi_solver_checkpoint) restarts CVODE at that point:
 *   the running solver and a copy restored later (vi_solver_resume) both continue with a cold
 *   start from the same data, bit for bit alike.
 *   The one-step method keeps its whole continuation (time, step size, last step with its stages,
 *   guard values and arming) in a plain-data vi_ode that the caller owns (cfg->ode, inside the FMU
 *   state): a checkpoint costs nothing and a restored copy continues exactly where it was.
 *
 * Lifecycle: vi_solver_create -> (vi_solver_reset | vi_solver_advance)* -> vi_solver_free.
 * The solver integrates x' = rhs(t, x) and stops at the first zero of any guard g_i(t, x) crossed
 * from positive to negative (root direction -1), or returns the state at tout.
 *
 * Integration past output points: vi_solver_advance sets no stop time. The solver keeps its step
 * size and order, may step beyond tout, and returns x(tout) from its interpolant (CVODE: driven
 * one internal step at a time in CV_ONE_STEP mode, x(tout) from CVodeGetDky; the guards are
 * checked by CVODE over each whole step, and a root found beyond tout is held until the calls
 * reach it). The next call continues from the solver's own internal state, so a call whose tout
 * lies inside the last internal step takes no new step. The caller restarts the
 * solver (vi_solver_reset) only when the problem changes: after an event, an input jump, or when a
 * state is taken (vi_sim_checkpoint).
 *
 * AUTO (VI_METHOD_AUTO, systems of at most 2 states with a Jacobian)
 *   The one-step method tests every accepted step for stiffness (Hairer & Wanner, Solving ODEs II,
 *   IV.2: a step held by stability, not accuracy, has h rho at the boundary of the method's
 *   stability domain): h rho, h the step and rho the spectral radius of the Jacobian at its end,
 *   against VI_AUTO_STIFF_HRHO. VI_AUTO_STIFF_STEPS such steps in a row (VI_AUTO_CALM_STEPS steps
 *   below it in a row clear the count) make the problem stiff: CVODE BDF takes over from the end of
 *   the last step. The one-step method's steps are bounded by VI_SOLVER_STABLE_HRHO (above
 *   VI_AUTO_STIFF_HRHO), so that a stiff problem is seen before it leaves the stability domain
 *   (at a rest, whose error estimate allows any step, it would at the first step). While BDF
 *   runs, once it has taken VI_AUTO_BDF_MIN_STEPS steps since it started (its first steps are
 *   short), VI_AUTO_CALM_STEPS steps in a row whose h rho lies below
 *   VI_AUTO_NONSTIFF_HRHO (BDF's own step resolves the fastest motion: an explicit method is stable
 *   there) hand back to the one-step method from the end of BDF's last step. When the one-step
 *   method fails (a step size underflow, too many rejected steps, a right-hand side that is not
 *   finite) BDF takes over at its last point at once. A hand-over waits
 *   until the running method is asked for a step beyond its last one, or happens at a restart
 *   (vi_solver_reset, after an event). Events are located by whichever method runs.
 *   Which method runs and the counts are plain data the caller owns (cfg->auto_choice, inside the FMU
 *   state), next to the one-step method's continuation (cfg->ode): a checkpoint costs nothing while
 *   the one-step method runs and restarts BDF (as for CVODE alone) while BDF runs, so a restored
 *   copy continues bit for bit like the original.
 *
 * Every SUNDIALS call that sets up or advances CVODE is checked by one helper that logs the failing
 * call through cfg->log. The counter queries of vi_solver_statistics (CVodeGetNum*) are not: on
 * the live CVODE memory with its linear solver attached they cannot fail (they fail only for a
 * NULL memory or linear solver), and a statistic is no reason to fail a run.
 */
#ifndef VI_SOLVER_H
#define VI_SOLVER_H

#include <stddef.h>

#include "vi_ode.h"
#include "vi_log.h"

/* The relative tolerances the solvers are used with (the models' parameter rtol declares this range;
 * the tolerance of fmi2SetupExperiment is checked against it at initialization): above VI_RTOL_MAX
 * the error is of the order of the motion itself; below VI_RTOL_MIN the tolerance is under the
 * rounding of a double state. A maximum step is 0 (no limit) or at least VI_MAX_STEP_MIN. */
#define VI_RTOL_MIN 1e-14
#define VI_RTOL_MAX 1e-2
#define VI_RTOL_DEFAULT 1e-6 /* without rtol and without the experiment's tolerance */
#define VI_MAX_STEP_MIN 1e-12 /* s */

/* Sizes this wrapper is made for: small dense systems. */
#define VI_SOLVER_MAX_N 4
#define VI_SOLVER_MAX_GUARDS 16

typedef void (*vi_rhs_fn)(double t, const double *x, double *dx, void *user);
typedef void (*vi_guard_fn)(double t, const double *x, double *g, void *user);
typedef void (*vi_jac_fn)(double t, const double *x, double *jac_row_major, void *user);

/* PIECES (for the caller's quadratures and extrema along the solution). With cfg->piece set, every
 * vi_solver_advance hands the caller the solution it passed as consecutive pieces [ta, tb]: from the
 * last (re)start, or the point the last advance returned, up to the point this advance returns (tout,
 * the event, the last step). A piece lies inside one internal step, so no event and no restart lies
 * inside it, and x(t) there is the step's interpolant (vi_solver_piece_at): the one-step method's
 * dense output (order 7), CVODE's interpolating polynomial (CVodeGetDky). A piece is handed over
 * before the solver leaves its step: the call of cfg->piece is the only time its interior can be
 * read. The pieces do not change the steps taken (the dense output is built when it is first read,
 * and building it changes nothing). cfg->piece returns 0, or -1 to fail the advance. */
typedef struct vi_solver vi_solver;
typedef struct {
    double ta, tb;         /* the piece [s] */
    const double *xa, *xb; /* the solution at its ends */
    const double *dxb;     /* x'(tb): the interpolant's derivative (at the end of a step of the one-step
                              method, the right-hand side there) */
    vi_solver *solver;     /* the solver that made it (for vi_solver_piece_at) */
} vi_solver_piece;
typedef int (*vi_piece_fn)(const vi_solver_piece *piece, void *user);

/* Integration methods (the values of the FMU's `solver` enumeration). */
enum { VI_METHOD_BDF = 1, VI_METHOD_ADAMS = 2, VI_METHOD_DOP853 = 3, VI_METHOD_AUTO = 4 };
/* Its name for messages: "CVODE BDF", "CVODE Adams", "Dormand-Prince 8(5,3)", "auto"; "unknown method" else. */
const char *vi_solver_method_name(int method);

/* AUTO's stiffness tests (see AUTO above). VI_AUTO_STIFF_HRHO is 0.8 times the nearest point of the
 * boundary of DOP853's stability domain to the origin (5.96, on the imaginary axis; 6.39 on the
 * negative real axis): the undamped oscillation of a stiff contact puts the eigenvalues on the
 * imaginary axis. Hairer's test counts 15 steps with rho estimated from two stages; rho from the
 * Jacobian is exact, and 8 steps in a row near the boundary are a step size held by stability. */
#define VI_AUTO_STIFF_HRHO 4.8
#define VI_AUTO_STIFF_STEPS 8
#define VI_AUTO_CALM_STEPS 6
#define VI_AUTO_NONSTIFF_HRHO 1.0
#define VI_AUTO_BDF_MIN_STEPS 10

/* The one-step method's steps are at most VI_SOLVER_STABLE_HRHO / rho, rho the spectral radius of the
 * Jacobian at the step's start (vi_ode.h, STEPS): 0.9 times the nearest point of the boundary of
 * DOP853's stability domain (5.96), where |R(h lambda)| <= 0.72 on the imaginary axis. Above
 * VI_AUTO_STIFF_HRHO, so that AUTO counts the steps this bound holds as stiff. */
#define VI_SOLVER_STABLE_HRHO 5.4

/* Interior guard samples per step of the one-step method (see vi_ode.h, EVENTS): a guard that dips
 * below zero and back within one step is seen when it is below zero at a sample. */
#define VI_SOLVER_GUARD_SAMPLES 2

/* AUTO's choice: plain data owned by the caller (zeroed or as vi_solver_* left it). */
typedef struct {
    int bdf;        /* 1 while CVODE BDF runs (the problem was found stiff), 0 while the one-step method does */
    int pending;    /* the running method's test asks for the other: hand over before the next step */
    int stiff;      /* one-step method: steps in a row with h rho > VI_AUTO_STIFF_HRHO */
    int calm;       /* steps in a row below the running method's threshold */
    long steps;     /* BDF: steps since it last (re)started */
    long switches;  /* hand-overs so far */
} vi_solver_auto;

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
    vi_ode *ode;        /* VI_METHOD_DOP853, AUTO: the continuation, owned by the caller (plain data) */
    vi_solver_auto *auto_choice; /* VI_METHOD_AUTO: which method runs, owned by the caller (plain data) */
    vi_piece_fn piece;  /* NULL, or called for every piece of the solution passed (PIECES above) */
    vi_log_fn log;
    void *log_env;
} vi_solver_config;

typedef struct {
    const char *method; /* the method that ran (vi_solver_method_name) */
    long steps, rhs_evals, jac_evals, nonlin_iters, nonlin_fails, err_test_fails, guard_evals, resets;
    long switches; /* AUTO: hand-overs between the one-step method and BDF */
} vi_solver_stats;

enum { VI_SOLVER_REACHED = 0, VI_SOLVER_EVENT = 1, VI_SOLVER_LIMIT = 2, VI_SOLVER_FAILED = -1 };

/* x(t) (n values) on a piece handed to cfg->piece, for ta <= t <= tb (its ends exactly: xa, xb), and
 * when dx != NULL the interpolant's derivative x'(t). 0, or VI_SOLVER_FAILED (logged). */
int vi_solver_piece_at(const vi_solver_piece *piece, double t, double *x, double *dx);

/* NULL on failure (logged). Copies the configuration; cfg->atol must hold n values while it runs (the
 * tolerances are copied into the integrators). Starts at (t0, x0). */
vi_solver *vi_solver_create(const vi_solver_config *cfg, double t0, const double *x0);
/* As vi_solver_create, but continuing a saved state: the one-step method continues from *cfg->ode as
 * it is (checked); CVODE starts at (t0, x0) as after vi_solver_checkpoint; AUTO continues with the
 * method *cfg->auto_choice names. */
vi_solver *vi_solver_resume(const vi_solver_config *cfg, double t0, const double *x0);
/* Make (t0, x0), the caller's current point, a point from which vi_solver_resume continues exactly as
 * this solver will: CVODE (and AUTO while BDF runs) restarts there; the one-step method has nothing
 * to do. 0 or FAILED. */
int vi_solver_checkpoint(vi_solver *s, double t0, const double *x0);
/* Cold restart from (t0, x0): the next advance starts a new integration there (AUTO: with the other
 * method when a hand-over is pending). 0 or VI_SOLVER_FAILED. */
int vi_solver_reset(vi_solver *s, double t0, const double *x0);
/* Integrate towards tout > *t taking at most max_steps internal steps (*taken: how many it took).
 *   VI_SOLVER_REACHED: *t = tout and x = x(tout) (interpolated when the solver stepped beyond tout);
 *   VI_SOLVER_EVENT:   *t and x hold the first guard zero in (*t, tout]; fired[i] != 0 for the
 *                      guards that crossed; the caller resets the solver before going on;
 *   VI_SOLVER_LIMIT:   max_steps taken: *t and x hold the solver's last internal step (< tout),
 *                      a consistent point the solver can continue from;
 *   VI_SOLVER_FAILED:  logged. */
int vi_solver_advance(vi_solver *s, double tout, long max_steps, double *t, double *x, int *fired, long *taken);
/* Cumulative counters since vi_solver_create, and the method's name. (The one-step method has no
 * Jacobian and no nonlinear iteration: those stay 0; its rejected steps count as error test failures.) */
void vi_solver_statistics(const vi_solver *s, vi_solver_stats *st);
/* Is *o a continuation of the one-step method for n states and nguards guards whose current point
 * is at or after t (a state restored from outside may hold anything)? 0, or -1 with the first bad
 * field in msg. */
int vi_solver_ode_check(const vi_ode *o, int n, int nguards, double t, char *msg, size_t size);
/* Is *a a choice AUTO could have left (flags 0 or 1, counts in range)? 0, or -1 naming the field. */
int vi_solver_auto_check(const vi_solver_auto *a, char *msg, size_t size);
void vi_solver_free(vi_solver *s);

#endif
