/*
 * vi_ode.h - a high-order explicit one-step integrator with dense output and event location, for
 * small non-stiff systems x' = f(t, x) (n <= VI_ODE_MAX_N) with guard functions g(t, x).
 *
 * METHOD
 *   Dormand-Prince 8(5,3) ("DOP853") of Hairer and Wanner: an explicit Runge-Kutta method of
 *   order 8 with 12 stages, first-same-as-last (the 13th stage, f at the new point, is the first
 *   stage of the next step), two embedded error estimators of orders 5 and 3 combined into one
 *   estimate that behaves like h^8, and a continuous extension (dense output) of order 7 that needs
 *   3 more stages per step. Sources: E. Hairer, S.P. Norsett, G. Wanner, Solving Ordinary
 *   Differential Equations I, 2nd ed., Springer 1993: II.5 (the 8(5,3) construction after
 *   Dormand and Prince), II.6 (dense output), II.4 (step size control, starting step size), II.10
 *   (the combined error estimate). The coefficients are the numbers the authors published with
 *   the method (the coefficient set of DOP853, 1993); they are typed in here as numbers only, and
 *   tests/test_ode.c checks every one of them against the Butcher order conditions (all 200 rooted
 *   trees up to order 8 for the step, order 7 at 8 points for the dense output, orders 5 and 3 for
 *   the estimators, the nodes against the row sums), so a mistyped digit fails the tests. The code
 *   is written for this project; no third-party code is used.
 *
 * DESIGN
 *   vi_ode_problem describes the problem (function pointers, tolerances, options); the caller owns
 *   it and passes it to every call. vi_ode holds the integrator's complete state as PLAIN DATA: no
 *   pointers, no allocation, fixed-size arrays, every byte written by vi_ode_init (components
 *   beyond n are zero and stay zero). A byte copy of a vi_ode (memcpy, or inside an FMU state)
 *   continued with the same problem reproduces the same steps, events and results bit for bit.
 *   Nothing here allocates, and no function keeps static or global state. Every loop is bounded:
 *   rejected attempts per step (VI_ODE_MAX_REJECTS), root-finder iterations
 *   (VI_ODE_MAX_ROOT_ITERS), guard samples (VI_ODE_MAX_SAMPLES).
 *
 * USE
 *   vi_ode_problem p = {.n = 2, .ng = 2, .rhs = f, .guards = g, .user = model, .rtol = 1e-8,
 *                       .atol = {1e-12, 1e-9}, .max_step = 0, .guard_samples = 2};
 *   vi_ode s;
 *   if (vi_ode_init(&s, &p, t0, x0, 0.0, 0u) < 0) ...        // f(t0,x0), g(t0,x0), the first h
 *   for (long k = 0; k < k_max; k++) {
 *       int r = vi_ode_step(&s, &p, t_stop);                 // one accepted step, never past t_stop
 *       if (r < 0) ... failure (vi_ode_status_text(r)); s.t, s.x: the last good point
 *       ... outputs at t_c in [s.t_old, s.t] (before s.ev_t after an event):
 *           vi_ode_dense(&s, &p, t_c, xc, NULL)
 *       if (r == VI_ODE_EVENT) {                             // the earliest falling guard crossing
 *           ... apply the event at (s.ev_t, s.ev_x) for the guards in the bit mask s.ev_fired
 *           vi_ode_restart(&s, &p, s.ev_t, x_after, 0.0, hold); // see RE-ARMING
 *       } else if (s.t == t_stop) break;
 *   }
 *
 * STEPS
 *   vi_ode_step takes one accepted step from s.t of the proposed size s.h, limited by max_step
 *   and never passing t_stop: when t_stop - s.t <= 1.01 h (and <= max_step) the step ends exactly
 *   at t_stop (s.t == t_stop bit for bit afterwards). A step spans exactly [t, fl(t + h)] (h is
 *   taken as the difference of the rounded times), so time does not drift by roundings, and its
 *   length never exceeds max_step. Rejected attempts shrink h; the step is refused with
 *   VI_ODE_ERR_HMIN when h falls below max(p->h_min, 16 eps |t|) (step size underflow), with
 *   VI_ODE_ERR_NONFINITE when the rhs stays non-finite (NaN, Inf) although h was shrunk, and with
 *   VI_ODE_ERR_REJECTS after VI_ODE_MAX_REJECTS rejected attempts. On any failure the state is
 *   left as it was (t, x, h, guards, the last step and its dense output; the statistics count the
 *   work, and the scratch half sp[1 - cur] holds the failed attempt), so the caller can report
 *   s.t as the last successful time.
 *   Error control: per component sc_i = atol_i + rtol max(|x_i(t)|, |x_i(t+h)|), err5 and err3 the
 *   RMS norms of the two estimators scaled by sc; err = err5^2 / sqrt(err5^2 + 0.01 err3^2) (HNW
 *   II.10); the step is accepted when err <= 1; the next h is h min(5, max(0.2, 0.9 err^(-1/8))),
 *   not larger than h after a rejection (a step shortened to reach t_stop keeps the earlier
 *   proposal when that was larger). A rejected attempt is retried with h max(0.04, 0.9 err^(-1/8))
 *   (0.2 h when it was not finite), except in the first step after vi_ode_init/vi_ode_restart once
 *   two attempts have been rejected in a row with the error falling slower than h^8: where the
 *   solution is not smooth at the start (a contact beginning there: a force growing like a power
 *   3/2 of the indentation leaves an error like h^(5/2)), the two errors show the order
 *   q = ln(err1/err2) / ln(h1/h2) < 8, and the next attempt takes h (0.25/err)^(1/q) (q at least 1;
 *   between 0.04 h and 0.9 h). p->h_fixed > 0 turns the control off: every step has size
 *   h_fixed (or ends at t_stop) and is accepted (for convergence tests and diagnostics).
 *   The first step size: h0 > 0 given to vi_ode_init/vi_ode_restart, else Hairer's estimate (HNW
 *   II.4, one extra rhs evaluation); both limited by max_step.
 *   Stability: with p->h_rho_max > 0 every step (the first included) is also at most
 *   h_rho_max / rho, rho = p->spectral_radius(t, x) at its start (no bound where rho is 0 or NaN;
 *   never below the shortest step, 16 eps |t| or h_min). The error estimate alone does not keep an
 *   explicit method stable: at an equilibrium the solution does not move, every step's estimate
 *   is near 0 however far h rho lies beyond the stability domain, and the rounding-sized
 *   deviations grow by |R(h lambda)| per step until they reach the tolerance, in one step when h
 *   rho is large (a contact at rest whose absolute tolerances are large: motion from rest). A bound
 *   inside the stability domain keeps the deviations from growing, so a rest stays at rest. At an
 *   exact rest (f = 0 at the step's start) a step is first tried without the bound: when all its
 *   stages come out exactly 0 it is exact (there is no deviation to grow) and taken; otherwise the
 *   step is retried within the bound (the trial counts in st.rejected, not in the step-size
 *   control).
 *   Cost: 12 rhs evaluations per accepted step (11 per rejected attempt), 3 more for the dense
 *   output of a step when it is used (built lazily, once per step, on the first vi_ode_dense call
 *   or event search that needs it; deterministic, so it does not matter when), 1 guard evaluation
 *   per step end plus guard_samples per step, plus those of a root search.
 *
 * DENSE OUTPUT
 *   vi_ode_dense(s, p, t, x, dx) gives the interpolant of order 7 (local error O(h^8)) on the last
 *   accepted step [s.t_old, s.t] and, when dx != NULL, its time derivative (equal to f at both
 *   ends). At t == s.t_old and t == s.t it returns s.x_old and s.x exactly. Outside the step it
 *   returns VI_ODE_ERR_ARGS. Whether or when the dense output is built has no influence on the
 *   steps taken.
 *
 * EVENTS (guards, direction, sampling, root finding)
 *   The model's guards are >= 0 inside a mode; an event is a FALLING crossing: guard i goes from
 *   g_i > 0 to g_i <= 0. Only ARMED guards fire (see RE-ARMING). After each accepted step [t0, t1]
 *   the guards are evaluated at t1 (their values at t0 are kept from the previous step end or the
 *   restart) and, when p->guard_samples = m > 0, at the m interior points t0 + j (t1 - t0)/(m + 1)
 *   of the dense output (this builds the dense output for every step). The sub-intervals are
 *   scanned in time order; the first one in which an armed guard goes from > 0 at its left end to
 *   <= 0 at its right end is searched for the root. A guard that dips below zero and comes back
 *   between two neighbouring sample points is not seen (with m = 0: within one step); choose m
 *   (or max_step) for the double crossings that matter.
 *   The root search works on all candidate guards (armed and > 0 at the sub-interval's left end)
 *   at once: the bracket [a, b] always has all of them > 0 at a and at least one <= 0 at b. New
 *   points come from the Illinois variant of regula falsi on the guard whose linear root estimate
 *   is earliest, kept strictly inside the bracket, with a bisection whenever two iterations did
 *   not halve the bracket (so the width halves at least every third iteration); the search stops
 *   when b - a <= eps max(|a|, |b|) (1 or 2 ulps of t), after at most VI_ODE_MAX_ROOT_ITERS guard
 *   evaluations (VI_ODE_ERR_ROOT otherwise, which the bisections rule out). The event is
 *       s.ev_t = b      the first point found with a guard <= 0 (s.ev_t - s.ev_t_lo = b - a),
 *       s.ev_x          the dense output at b (s.x when b == s.t),
 *       s.ev_fired      bit i for every candidate guard with g_i(b) <= 0: all guards whose root lies
 *                       in the final bracket fire together (exact ties fire together).
 *   A guard never fires at the step's start (it must be > 0 there). Guard values that are not
 *   finite stop the step with VI_ODE_ERR_NONFINITE.
 *   After VI_ODE_EVENT the state holds the whole step [t_old, t] (t lies beyond ev_t unless
 *   ev_t == t) and its dense output, so outputs before ev_t can still be interpolated; the caller
 *   applies the event and restarts with vi_ode_restart (or vi_ode_init) at ev_t, from ev_x or the
 *   state after the event's jump (x0 may point into the state, e.g. s.ev_x). vi_ode_step refuses
 *   to continue (VI_ODE_ERR_ARGS) until then: the rest of the step lies beyond an event.
 *
 * RE-ARMING
 *   At vi_ode_init/vi_ode_restart guard i is armed when g_i(t0, x0) > p->arm_eps[i] and bit i of
 *   `hold` is clear. A guard that is not armed becomes armed at the first guard evaluation point
 *   (step end or interior sample, in time order) where g_i > arm_eps[i]; only then can it fire.
 *   So a guard that is exactly 0 (or negative) at a restart never fires before it has been
 *   positive; and after an event that leaves the mode unchanged, passing hold = s.ev_fired keeps
 *   the guards that just fired from firing again at once while they sit at (or within rounding
 *   of) zero: they fire again only after they have risen above arm_eps (default 0: any positive
 *   value) and fallen back. s.armed shows the current arming (bit i: guard i armed).
 *
 * STATISTICS
 *   s.st: attempts (accepted + rejected), accepted, rejected, rhs_evals (every rhs call, including
 *   the start, the first-step estimate and dense stages), guard_evals (every guards call),
 *   dense_builds, root_iters (guard evaluations inside root searches), events. vi_ode_init clears
 *   them, vi_ode_restart keeps adding.
 */
#ifndef VI_ODE_H
#define VI_ODE_H

#include <stddef.h>

#define VI_ODE_MAX_N 4           /* states */
#define VI_ODE_MAX_G 16          /* guards (bit masks are unsigned int) */
#define VI_ODE_MAX_SAMPLES 8     /* interior guard samples per step */
#define VI_ODE_MAX_REJECTS 64    /* rejected attempts within one vi_ode_step */
#define VI_ODE_MAX_ROOT_ITERS 300 /* guard evaluations in one root search */
#define VI_ODE_STAGES 16         /* 12 for the step, the 13th is f at the end, 3 for the dense output */
#define VI_ODE_ORDER 8

/* Status values returned by the functions below. */
enum {
    VI_ODE_OK = 0,             /* step accepted, no event in it */
    VI_ODE_EVENT = 1,          /* step accepted, an event located in it: s.ev_* */
    VI_ODE_ERR_ARGS = -1,      /* invalid problem, state or call */
    VI_ODE_ERR_HMIN = -2,      /* step size underflow: h < max(h_min, 16 eps |t|) */
    VI_ODE_ERR_NONFINITE = -3, /* rhs (after step reductions) or guards not finite */
    VI_ODE_ERR_REJECTS = -4,   /* VI_ODE_MAX_REJECTS rejected attempts in one step */
    VI_ODE_ERR_ROOT = -5       /* root search exceeded VI_ODE_MAX_ROOT_ITERS */
};

/* dx = f(t, x); g[0..ng-1] = guards at (t, x). Same signatures as the CVODE wrapper's. */
typedef void (*vi_ode_rhs_fn)(double t, const double *x, double *dx, void *user);
typedef void (*vi_ode_guard_fn)(double t, const double *x, double *g, void *user);

typedef struct {
    int n;                        /* states, 1..VI_ODE_MAX_N */
    int ng;                       /* guards, 0..VI_ODE_MAX_G */
    vi_ode_rhs_fn rhs;            /* required */
    vi_ode_guard_fn guards;       /* required when ng > 0 */
    void *user;                   /* passed to rhs and guards */
    double rtol;                  /* relative tolerance, 0 < rtol < 1 */
    double atol[VI_ODE_MAX_N];    /* absolute tolerances, > 0 */
    double max_step;              /* largest step [time units]; 0: none */
    double h_min;                 /* smallest step before VI_ODE_ERR_HMIN; 0: only 16 eps |t| */
    double h_fixed;               /* > 0: fixed step size without error control; 0: adaptive */
    int guard_samples;            /* interior guard samples per step, 0..VI_ODE_MAX_SAMPLES */
    double arm_eps[VI_ODE_MAX_G]; /* a guard arms when g > arm_eps (>= 0; 0: when g > 0) */
    /* the stability bound (STEPS): spectral_radius(t, x, rho_env) the spectral radius of the Jacobian
     * of f at (t, x); h_rho_max > 0 bounds every step by h rho(start of the step) <= h_rho_max (0: no
     * bound, spectral_radius may be NULL) */
    double (*spectral_radius)(double t, const double *x, void *rho_env);
    void *rho_env;
    double h_rho_max;
} vi_ode_problem;

typedef struct {
    long attempts, accepted, rejected, rhs_evals, guard_evals, dense_builds, root_iters, events;
} vi_ode_stats;

/* One step [t0, t1] and what its dense output needs (internal; see vi_ode.sp). */
typedef struct {
    double t0, t1, x0[VI_ODE_MAX_N], x1[VI_ODE_MAX_N];
    double k[VI_ODE_STAGES][VI_ODE_MAX_N]; /* stages (12: f(t1, x1); 13..15 once dense_ready) */
    double q[7][VI_ODE_MAX_N];             /* dense-output coefficients (once dense_ready) */
    int dense_ready, pad_;
} vi_ode_span;

/* The integrator's state: plain data, copyable byte for byte (no pointers; every byte is written
 * by vi_ode_init first). Read the documented fields; change them only through the functions. */
typedef struct {
    double t, x[VI_ODE_MAX_N];        /* current point */
    double f[VI_ODE_MAX_N];           /* f(t, x): the first stage of the next step */
    double h;                         /* proposed size of the next step */
    double err;                       /* error estimate of the last accepted step (<= 1 adaptive) */
    double t_old, x_old[VI_ODE_MAX_N]; /* start of the last accepted step [t_old, t] */
    double g[VI_ODE_MAX_G];           /* guard values at t */
    double ev_t, ev_t_lo, ev_x[VI_ODE_MAX_N]; /* the event (valid when event_pending) */
    vi_ode_stats st;
    vi_ode_span sp[2];                /* the last accepted step is sp[cur]; the next is worked on in
                                         sp[1 - cur] and committed by flipping cur */
    unsigned int armed;               /* bit i: guard i is armed */
    unsigned int ev_fired;            /* bit i: guard i fired at ev_t */
    int n, ng;                        /* sizes the state was made for (checked on every call) */
    int cur;                          /* index of the last accepted step in sp */
    int have_step;                    /* a step has been accepted since the (re)start */
    int event_pending;                /* the last step ended in an event: vi_ode_init/restart next */
    int rejected_last;                /* rejected attempts in the last vi_ode_step */
} vi_ode;

/* 0 when the problem is valid; else VI_ODE_ERR_ARGS and a message naming the bad field in msg
 * (when msg != NULL). */
int vi_ode_check(const vi_ode_problem *p, char *msg, size_t msg_size);

/* Start at (t0, x0): clears the whole state (statistics too), evaluates f(t0, x0) and the guards,
 * arms the guards (see RE-ARMING; hold: bit mask of guards that start unarmed), and sets the first
 * step size (h0 > 0: this; else Hairer's estimate; both limited by max_step; h_fixed when set).
 * There is no step yet (no dense output). Returns VI_ODE_OK, VI_ODE_ERR_ARGS (invalid problem, x0
 * or t0 not finite, h0 < 0), VI_ODE_ERR_NONFINITE (f or g not finite at the start) or
 * VI_ODE_ERR_HMIN (the first step size is not positive: f too large for the tolerances' scale);
 * on any error *s is left as it was. */
int vi_ode_init(vi_ode *s, const vi_ode_problem *p, double t0, const double *x0, double h0,
                unsigned int hold);
/* vi_ode_init that keeps (adds up) the statistics of s: for restarts after events or input jumps.
 * s must hold an initialized state (or be zeroed). */
int vi_ode_restart(vi_ode *s, const vi_ode_problem *p, double t0, const double *x0, double h0,
                   unsigned int hold);

/* One accepted step towards t_stop (> s->t; INFINITY for none), then the event search in it.
 * VI_ODE_OK or VI_ODE_EVENT, or a failure (< 0) with the state unchanged. */
int vi_ode_step(vi_ode *s, const vi_ode_problem *p, double t_stop);

/* Dense output at t in [s->t_old, s->t]: x (n values) and, when dx != NULL, x'(t) from the
 * interpolant. Builds the dense output on first use in a step (3 rhs evaluations). VI_ODE_OK,
 * VI_ODE_ERR_ARGS (no step yet, t outside the step) or VI_ODE_ERR_NONFINITE (a dense stage). */
int vi_ode_dense(vi_ode *s, const vi_ode_problem *p, double t, double *x, double *dx);

/* A short text for a status value. */
const char *vi_ode_status_text(int status);

/* The coefficients of the method (for the tests that check them against the order conditions).
 * Stage i (0-based) is evaluated at t + c[i] h from x + h sum_j a[i][j] k[j]; the step is
 * x + h sum b[i] k[i]; the estimators are h sum e5[i] k[i] and h sum e3[i] k[i]; the dense output
 * at theta in [0, 1] (theta1 = 1 - theta) is
 *   x0 + theta (q0 + theta1 (q1 + theta (q2 + theta1 (q3 + theta (q4 + theta1 (q5 + theta q6))))))
 * with q0 = x1 - x0, q1 = h k[0] - q0, q2 = q0 - h k[12] - q1, q(3+r) = h sum_j d[r][j] k[j]. */
typedef struct {
    const double *c;                   /* [VI_ODE_STAGES] */
    const double (*a)[VI_ODE_STAGES];  /* [VI_ODE_STAGES][VI_ODE_STAGES], lower triangular */
    const double *b, *e5, *e3;         /* [VI_ODE_STAGES], zero beyond stage 12 */
    const double (*d)[VI_ODE_STAGES];  /* [4][VI_ODE_STAGES] */
    const int *lo;                     /* the sums use a[i][0] and a[i][lo[i] .. i-1] only; b, e5, e3
                                          columns 0 and lo[12] .. 11; d columns 0 and lo_d .. 15 */
    int lo_d;
} vi_ode_tableau;
const vi_ode_tableau *vi_ode_method(void);

#endif
