/* vi_solver.c - the solver interface (vi_solver.h): SUNDIALS CVODE (BDF, Adams; SUNDIALS 6.4 or 7.x:
 * vi_sundials.h), the built-in one-step method (vi_ode.h, Dormand-Prince 8(5,3)), and AUTO switching
 * between the one-step method and BDF. */
#include "vi_solver.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_check.h"
#include "vi_sundials.h"

struct vi_solver {
    vi_solver_config cfg; /* cfg.atol: the caller's, read only while the solver is created */
    /* the one-step method: the problem (the continuation is *cfg.ode) */
    vi_ode_problem ode_problem;
    long ode_resets;
    /* CVODE */
    SUNContext ctx;
    void *cvode;
    N_Vector x, atol, dky;
    SUNMatrix A;
    SUNLinearSolver LS;
    int fresh;                    /* no step since the last (re)initialisation */
    double t0;                    /* time of the last (re)initialisation */
    double tn;                    /* CVODE's internal time: the end of its last step */
    int root_pending;             /* a guard zero was found in the last step, at troot <= tn ... */
    double troot, xroot[VI_SOLVER_MAX_N];
    int rootsfound[VI_SOLVER_MAX_GUARDS]; /* ... for these guards; not reported yet */
    vi_solver_stats before_reset; /* CVodeReInit zeroes CVODE's counters: the sums before it */
    /* the pieces (vi_solver.h, PIECES): the solution is handed over up to tq, where it is xq */
    double tq, xq[VI_SOLVER_MAX_N];
    int piece_of_ode;             /* the piece being handed over is the one-step method's */
};

#if defined(SUNDIALS_ENABLE_PYTHON)
/* A SUNDIALS built for its Python module (the sundials4py wheel's static libraries) calls, when it
 * frees an object, a function of that module to free the Python callbacks the object holds. Nothing
 * here attaches Python callbacks (the pointer it passes is NULL): these free nothing. */
void SUNContextFunctionTable_Destroy(void *ptr);
void SUNLoggerFunctionTable_Destroy(void *ptr);
void SUNLinearSolverFunctionTable_Destroy(void *ptr);
void SUNNonlinearSolverFunctionTable_Destroy(void *ptr);
void SUNDomEigEstimatorFunctionTable_Destroy(void *ptr);
void SUNStepperFunctionTable_Destroy(void *ptr);
void cvode_user_supplied_fn_table_destroy(void *ptr);
void SUNContextFunctionTable_Destroy(void *ptr) { (void)ptr; }
void SUNLoggerFunctionTable_Destroy(void *ptr) { (void)ptr; }
void SUNLinearSolverFunctionTable_Destroy(void *ptr) { (void)ptr; }
void SUNNonlinearSolverFunctionTable_Destroy(void *ptr) { (void)ptr; }
void SUNDomEigEstimatorFunctionTable_Destroy(void *ptr) { (void)ptr; }
void SUNStepperFunctionTable_Destroy(void *ptr) { (void)ptr; }
void cvode_user_supplied_fn_table_destroy(void *ptr) { (void)ptr; }
#endif

/* Returned by the methods' advance loops under AUTO: the other method takes over here. */
enum { HANDOVER = 100 };

const char *vi_solver_method_name(int method)
{
    switch (method) {
    case VI_METHOD_BDF: return "CVODE BDF";
    case VI_METHOD_ADAMS: return "CVODE Adams";
    case VI_METHOD_DOP853: return "Dormand-Prince 8(5,3)";
    case VI_METHOD_AUTO: return "auto";
    default: return "unknown method";
    }
}

/* The one check for SUNDIALS return flags: logs the failing call and returns VI_SOLVER_FAILED. */
static int check_flag(const vi_solver *s, int flag, const char *call)
{
    if (flag >= 0) return 0;
    char *name = CVodeGetReturnFlagName(flag); /* malloc'ed by SUNDIALS */
    s->cfg.log(s->cfg.log_env, VI_LOG_ERROR, "SUNDIALS call %s failed: %s (%d)", call, name ? name : "?", flag);
    free(name);
    return VI_SOLVER_FAILED;
}
#define CHECK(call) \
    do { if (check_flag(s, (call), #call) < 0) return VI_SOLVER_FAILED; } while (0)
static int check_ptr(const vi_solver *s, const void *p, const char *call)
{
    if (p) return 0;
    s->cfg.log(s->cfg.log_env, VI_LOG_ERROR, "SUNDIALS call %s returned NULL", call);
    return VI_SOLVER_FAILED;
}

/* Callbacks: the serial vectors' data are read directly (NV_DATA_S), no operation-table call.
 * A time or a derivative that is not finite is a recoverable failure of the right-hand side: CVODE
 * retries with a smaller step and fails the step after its limit of such failures. (Taken as it
 * was, a step size that had become NaN, under a force of 1e308 N, kept CVODE 6.4 in its step loop
 * for minutes.) */
static int rhs_cb(sunrealtype t, N_Vector x, N_Vector dx, void *ud)
{
    const vi_solver *s = ud;
    double *d = NV_DATA_S(dx);
    s->cfg.rhs(t, NV_DATA_S(x), d, s->cfg.user);
    int finite = isfinite(t);
    for (int i = 0; i < s->cfg.n; i++) finite &= isfinite(d[i]) != 0;
    return finite ? 0 : 1;
}

static int guard_cb(sunrealtype t, N_Vector x, sunrealtype *g, void *ud)
{
    const vi_solver *s = ud;
    s->cfg.guards(t, NV_DATA_S(x), g, s->cfg.user);
    return 0;
}

static int jac_cb(sunrealtype t, N_Vector x, N_Vector fx, SUNMatrix J, void *ud, N_Vector t1, N_Vector t2,
                  N_Vector t3)
{
    (void)fx, (void)t1, (void)t2, (void)t3;
    const vi_solver *s = ud;
    int n = s->cfg.n;
    double j[VI_SOLVER_MAX_N * VI_SOLVER_MAX_N];
    s->cfg.jac(t, NV_DATA_S(x), j, s->cfg.user);
    for (int r = 0; r < n; r++)
        for (int c = 0; c < n; c++) SM_ELEMENT_D(J, r, c) = j[r * n + c];
    return 0;
}

/* CVODE's own messages: an error for a negative code, else a warning. The work limit is not an error
 * here: vi_solver_advance reports it. */
static void relay(const vi_solver *s, int code, const char *module, const char *function, const char *msg)
{
    if (code == CV_TOO_MUCH_WORK) return;
    s->cfg.log(s->cfg.log_env, code < 0 ? VI_LOG_ERROR : VI_LOG_WARNING, "%s %s: %s", module, function, msg);
}

#if VI_SUNDIALS_7
/* SUNDIALS 7 names no module: CVODE for CVODE's functions (CVode*, and cv* inside), SUNDIALS for the
 * shared ones. */
static const char *module_of(const char *function)
{
    return function && (strncmp(function, "CVode", 5) == 0 || strncmp(function, "cv", 2) == 0) ? "CVODE" : "SUNDIALS";
}

/* The context's error handler (the only one: SUNDIALS' own, which prints to stderr, is removed). */
static void err_cb(int line, const char *function, const char *file, const char *msg, SUNErrCode code, void *ud,
                   SUNContext ctx)
{
    (void)line, (void)file, (void)ctx;
    relay(ud, code, module_of(function), function ? function : "?", msg ? msg : SUNGetErrMsg(code));
}

#if VI_SUNLOGGER_CALLBACKS
/* The logger's messages: CVODE's warnings (the errors come through err_cb; nothing is printed). */
static SUNErrCode log_cb(SUNLogger logger, SUNLogLevel level, const char *prefix, int rank, const char *scope,
                         const char *label, const char *payload, void *ud)
{
    (void)logger, (void)prefix, (void)rank, (void)scope;
    if (level == SUN_LOGLEVEL_WARNING && payload) relay(ud, CV_WARNING, module_of(label), label ? label : "?", payload);
    return SUN_SUCCESS;
}

static SUNErrCode flush_cb(SUNLogger logger, SUNLogLevel level, void *ud)
{
    (void)logger, (void)level, (void)ud;
    return SUN_SUCCESS;
}
#endif

/* SUNDIALS 7: CVODE's errors to err_cb, its warnings to log_cb (7.8 on). Before 7.8 a logger's only
 * outputs are files (CVODE's warnings go to stdout): the context has none, and CVODE's warnings are
 * dropped (a SUNDIALS logging at debug level, 4, needs one: its own, as it is). */
static int route_messages(vi_solver *s)
{
    CHECK(SUNContext_ClearErrHandlers(s->ctx));
    CHECK(SUNContext_PushErrHandler(s->ctx, err_cb, s));
#if VI_SUNLOGGER_CALLBACKS
    SUNLogger logger = NULL;
    CHECK(SUNContext_GetLogger(s->ctx, &logger));
    if (logger) CHECK(SUNLogger_SetQueueAndFlushMsgFns(logger, log_cb, flush_cb, s));
#elif SUNDIALS_LOGGING_LEVEL < 4
    CHECK(SUNContext_SetLogger(s->ctx, NULL));
#endif
    return 0;
}
#else
/* SUNDIALS 6: the integrator's handler takes CVODE's errors and warnings. */
static void err_cb(int code, const char *module, const char *function, char *msg, void *ud)
{
    relay(ud, code, module, function, msg);
}
#endif

static int configure(vi_solver *s, double t0, const double *x0)
{
    const vi_solver_config *c = &s->cfg;
    memcpy(NV_DATA_S(s->x), x0, sizeof(double) * (size_t)c->n);
    memcpy(NV_DATA_S(s->atol), c->atol, sizeof(double) * (size_t)c->n);
#if !VI_SUNDIALS_7
    CHECK(CVodeSetErrHandlerFn(s->cvode, err_cb, s));
#endif
    CHECK(CVodeInit(s->cvode, rhs_cb, t0, s->x));
    CHECK(CVodeSetUserData(s->cvode, s));
    CHECK(CVodeSVtolerances(s->cvode, c->rtol, s->atol));
    CHECK(CVodeSetLinearSolver(s->cvode, s->LS, s->A));
    if (c->jac) CHECK(CVodeSetJacFn(s->cvode, jac_cb));
    if (c->max_step > 0.0) CHECK(CVodeSetMaxStep(s->cvode, c->max_step));
    if (c->nguards > 0) {
        int dir[VI_SOLVER_MAX_GUARDS];
        for (int i = 0; i < c->nguards; i++) dir[i] = -1;
        CHECK(CVodeRootInit(s->cvode, c->nguards, guard_cb));
        CHECK(CVodeSetRootDirection(s->cvode, dir));
        CHECK(CVodeSetNoInactiveRootWarn(s->cvode));
    }
    s->fresh = 1;
    s->t0 = t0;
    return 0;
}

/* ---- the one-step method ---------------------------------------------------------------------- */

/* A failure of the one-step method at t (a failed call leaves the continuation as it was). */
static int ode_fail_at(const vi_solver *s, int status, const char *call, double t)
{
    s->cfg.log(s->cfg.log_env, VI_LOG_ERROR, "%s failed at t = %.17g s: %s", call, t, vi_ode_status_text(status));
    return VI_SOLVER_FAILED;
}

static int ode_fail(const vi_solver *s, int status, const char *call)
{
    return ode_fail_at(s, status, call, s->cfg.ode->t);
}

static double spectral_radius(const vi_solver *s, double t, const double *x);
static double ode_spectral_radius(double t, const double *x, void *env) { return spectral_radius(env, t, x); }

/* The one-step method's problem; with a Jacobian of at most 2 states its steps are bounded by
 * stability (VI_SOLVER_STABLE_HRHO). */
static int ode_setup(vi_solver *s)
{
    const vi_solver_config *c = &s->cfg;
    vi_ode_problem *p = &s->ode_problem;
    int bounded = c->jac && c->n <= 2;
    *p = (vi_ode_problem){.n = c->n, .ng = c->nguards, .rhs = c->rhs, .guards = c->guards, .user = c->user,
                          .rtol = c->rtol, .max_step = c->max_step, .guard_samples = VI_SOLVER_GUARD_SAMPLES,
                          .spectral_radius = bounded ? ode_spectral_radius : NULL, .rho_env = s,
                          .h_rho_max = bounded ? VI_SOLVER_STABLE_HRHO : 0.0};
    memcpy(p->atol, c->atol, sizeof(double) * (size_t)c->n);
    char msg[256];
    if (!c->ode || vi_ode_check(p, msg, sizeof msg) < 0) {
        c->log(c->log_env, VI_LOG_ERROR, "one-step method: %s", c->ode ? msg : "no continuation given");
        return VI_SOLVER_FAILED;
    }
    return 0;
}

int vi_solver_ode_check(const vi_ode *o, int n, int nguards, double t, char *msg, size_t size)
{
    if (o->n != n || o->ng != nguards)
        VI_FAIL(msg, size, "ode: made for %d states and %d guards, not %d and %d", o->n, o->ng, n, nguards);
    if (!isfinite(o->t) || o->t < t) VI_FAIL(msg, size, "ode.t = %g is not finite or before t = %g", o->t, t);
    if (!(o->h > 0.0 && isfinite(o->h))) VI_FAIL(msg, size, "ode.h = %g is not finite and positive", o->h);
    if (o->event_pending != 0 && o->event_pending != 1) VI_FAIL(msg, size, "ode.event_pending = %d", o->event_pending);
    if (o->have_step != 0 && o->have_step != 1) VI_FAIL(msg, size, "ode.have_step = %d", o->have_step);
    if (o->cur != 0 && o->cur != 1) VI_FAIL(msg, size, "ode.cur = %d", o->cur);
    if (o->have_step && !(o->t_old <= t))
        VI_FAIL(msg, size, "ode: the last step [%g, %g] does not span t = %g", o->t_old, o->t, t);
    if (!o->have_step && o->t != t) VI_FAIL(msg, size, "ode.t = %g: a restart must be at t = %g", o->t, t);
    for (int i = 0; i < n; i++)
        if (!isfinite(o->x[i]) || !isfinite(o->f[i])) VI_FAIL(msg, size, "ode.x[%d] or ode.f[%d] is not finite", i, i);
    for (int i = 0; i < nguards; i++)
        if (!isfinite(o->g[i])) VI_FAIL(msg, size, "ode.g[%d] is not finite", i);
    return 0;
}

static int ode_valid(const vi_solver *s, double t0)
{
    char msg[160];
    if (vi_solver_ode_check(s->cfg.ode, s->cfg.n, s->cfg.nguards, t0, msg, sizeof msg) == 0) return 1;
    s->cfg.log(s->cfg.log_env, VI_LOG_ERROR, "one-step method: the saved continuation is inconsistent: %s", msg);
    return 0;
}

/* ---- AUTO: the stiffness tests ----------------------------------------------------------------- */

/* The spectral radius of the Jacobian at (t, x) (at most 2 states: from its trace and determinant). */
static double spectral_radius(const vi_solver *s, double t, const double *x)
{
    double j[VI_SOLVER_MAX_N * VI_SOLVER_MAX_N];
    s->cfg.jac(t, x, j, s->cfg.user);
    if (s->cfg.n == 1) return fabs(j[0]);
    double tr = 0.5 * (j[0] + j[3]), det = j[0] * j[3] - j[1] * j[2], disc = tr * tr - det;
    return disc >= 0.0 ? fabs(tr) + sqrt(disc) : sqrt(det); /* a complex pair: |lambda|^2 = det */
}

/* After an accepted step of the one-step method: was it held by stability? */
static void test_one_step(const vi_solver *s, const vi_ode *o)
{
    vi_solver_auto *a = s->cfg.auto_choice;
    double h_rho = (o->t - o->t_old) * spectral_radius(s, o->t, o->x);
    if (h_rho > VI_AUTO_STIFF_HRHO) {
        a->calm = 0;
        if (++a->stiff >= VI_AUTO_STIFF_STEPS) a->stiff = VI_AUTO_STIFF_STEPS, a->pending = 1;
    } else if (a->calm < VI_AUTO_CALM_STEPS && ++a->calm == VI_AUTO_CALM_STEPS) {
        a->stiff = 0;
    }
}

/* After a step of BDF (x at its end): does its step resolve the fastest motion? */
static int test_bdf(vi_solver *s, const double *x)
{
    vi_solver_auto *a = s->cfg.auto_choice;
    if (a->steps < VI_AUTO_BDF_MIN_STEPS) a->steps++;
    if (a->steps < VI_AUTO_BDF_MIN_STEPS) return 0;
    double h;
    CHECK(CVodeGetLastStep(s->cvode, &h));
    if (!(h * spectral_radius(s, s->tn, x) < VI_AUTO_NONSTIFF_HRHO)) a->calm = 0;
    else if (a->calm < VI_AUTO_CALM_STEPS && ++a->calm == VI_AUTO_CALM_STEPS) a->pending = 1;
    return 0;
}

/* Flip AUTO to the other method (it starts at t). */
static void hand_over(const vi_solver *s, double t)
{
    vi_solver_auto *a = s->cfg.auto_choice;
    a->bdf = !a->bdf;
    a->pending = a->stiff = a->calm = 0;
    a->steps = 0;
    a->switches++;
    if (a->bdf)
        s->cfg.log(s->cfg.log_env, VI_LOG_SOLVER, "t = %.17g s: stiff (%d steps in a row held by stability, h rho > %g): "
                   "CVODE BDF takes over", t, VI_AUTO_STIFF_STEPS, VI_AUTO_STIFF_HRHO);
    else
        s->cfg.log(s->cfg.log_env, VI_LOG_SOLVER, "t = %.17g s: not stiff (%d BDF steps in a row with h rho < %g): "
                   "Dormand-Prince 8(5,3) takes over", t, VI_AUTO_CALM_STEPS, VI_AUTO_NONSTIFF_HRHO);
}

int vi_solver_auto_check(const vi_solver_auto *a, char *msg, size_t size)
{
#define AUTO_BAD(...) do { vi_snprintf(msg, size, __VA_ARGS__); return -1; } while (0)
    if (a->bdf != 0 && a->bdf != 1) AUTO_BAD("auto_choice.bdf = %d is not 0 or 1", a->bdf);
    if (a->pending != 0 && a->pending != 1) AUTO_BAD("auto_choice.pending = %d is not 0 or 1", a->pending);
    if (a->stiff < 0 || a->stiff > VI_AUTO_STIFF_STEPS) AUTO_BAD("auto_choice.stiff = %d is not in [0, %d]", a->stiff, VI_AUTO_STIFF_STEPS);
    if (a->calm < 0 || a->calm > VI_AUTO_CALM_STEPS) AUTO_BAD("auto_choice.calm = %d is not in [0, %d]", a->calm, VI_AUTO_CALM_STEPS);
    if (a->steps < 0 || a->steps > VI_AUTO_BDF_MIN_STEPS) AUTO_BAD("auto_choice.steps = %ld is not in [0, %d]", a->steps, VI_AUTO_BDF_MIN_STEPS);
    if (a->switches < 0) AUTO_BAD("auto_choice.switches = %ld is negative", a->switches);
    return 0;
#undef AUTO_BAD
}

/* ---- the pieces ---------------------------------------------------------------------------------- */

/* The pieces start anew at (t0, x0): a (re)start, a resumed state. */
static void pieces_from(vi_solver *s, double t0, const double *x0)
{
    s->tq = t0;
    memcpy(s->xq, x0, sizeof(double) * (size_t)s->cfg.n);
}

/* x'(t) on the piece p: the one-step method's f at the end of its step, else the interpolant's (CVODE: its
 * derivative alone). */
static int piece_derivative(vi_solver *s, const vi_solver_piece *p, double t, double *dx)
{
    size_t bytes = sizeof(double) * (size_t)s->cfg.n;
    if (s->piece_of_ode && t == s->cfg.ode->t) {
        memcpy(dx, s->cfg.ode->f, bytes);
        return 0;
    }
    if (!s->piece_of_ode && !s->fresh) {
        CHECK(CVodeGetDky(s->cvode, t, 1, s->dky));
        memcpy(dx, NV_DATA_S(s->dky), bytes);
        return 0;
    }
    double x[VI_SOLVER_MAX_N];
    return vi_solver_piece_at(p, t, x, dx);
}

/* Hand over the piece [tq, tb] of the current step (of_ode: the one-step method's), where x(tb) = xb and
 * x'(tb) = dxb (NULL: piece_derivative). */
static int cover(vi_solver *s, int of_ode, double tb, const double *xb, const double *dxb)
{
    if (!(tb > s->tq)) return 0;
    if (s->cfg.piece) {
        double dx[VI_SOLVER_MAX_N];
        s->piece_of_ode = of_ode;
        vi_solver_piece p = {.ta = s->tq, .tb = tb, .xa = s->xq, .xb = xb, .dxb = dxb ? dxb : dx, .solver = s};
        if (!dxb && piece_derivative(s, &p, tb, dx) < 0) return VI_SOLVER_FAILED;
        if (s->cfg.piece(&p, s->cfg.user) < 0) return VI_SOLVER_FAILED;
    }
    pieces_from(s, tb, xb);
    return 0;
}

int vi_solver_piece_at(const vi_solver_piece *piece, double t, double *x, double *dx)
{
    vi_solver *s = piece->solver;
    size_t bytes = sizeof(double) * (size_t)s->cfg.n;
    if (!dx && (t == piece->ta || t == piece->tb)) {
        memcpy(x, t == piece->ta ? piece->xa : piece->xb, bytes);
        return 0;
    }
    if (s->piece_of_ode) {
        int r = vi_ode_dense(s->cfg.ode, &s->ode_problem, t, x, dx);
        return r < 0 ? ode_fail_at(s, r, "vi_ode_dense", t) : 0;
    }
    if (s->fresh) { /* no step yet: a piece of a few ulps of time at the start point, x' from the rhs */
        memcpy(x, piece->xa, bytes);
        if (dx) s->cfg.rhs(t, x, dx, s->cfg.user);
        return 0;
    }
    CHECK(CVodeGetDky(s->cvode, t, 0, s->dky));
    memcpy(x, NV_DATA_S(s->dky), bytes);
    if (dx) {
        CHECK(CVodeGetDky(s->cvode, t, 1, s->dky));
        memcpy(dx, NV_DATA_S(s->dky), bytes);
    }
    return 0;
}

static int ode_advance(vi_solver *s, double tout, long max_steps, double *t, double *x, int *fired, long *taken)
{
    vi_ode *o = s->cfg.ode;
    const vi_ode_problem *p = &s->ode_problem;
    int n = s->cfg.n;
    for (;;) { /* bounded: every pass takes a step, at most max_steps */
        if (o->event_pending && o->ev_t <= tout) {
            *t = o->ev_t;
            memcpy(x, o->ev_x, sizeof(double) * (size_t)n);
            for (int i = 0; i < s->cfg.nguards; i++) fired[i] = (o->ev_fired >> i) & 1u;
            return cover(s, 1, *t, x, NULL) < 0 ? VI_SOLVER_FAILED : VI_SOLVER_EVENT;
        }
        if (tout <= o->t) { /* inside the last step: its interpolant (and its derivative for the piece) */
            double dx[VI_SOLVER_MAX_N], *pdx = s->cfg.piece ? dx : NULL;
            int r = o->have_step ? vi_ode_dense(o, p, tout, x, pdx) : VI_ODE_ERR_ARGS;
            if (r < 0) return ode_fail(s, r, "vi_ode_dense");
            *t = tout;
            return cover(s, 1, tout, x, pdx) < 0 ? VI_SOLVER_FAILED : VI_SOLVER_REACHED;
        }
        if (cover(s, 1, o->t, o->x, NULL) < 0) return VI_SOLVER_FAILED; /* the rest of the step, before it is left */
        if (*taken >= max_steps) {
            *t = o->t;
            memcpy(x, o->x, sizeof(double) * (size_t)n);
            return VI_SOLVER_LIMIT;
        }
        if (s->cfg.method == VI_METHOD_AUTO && s->cfg.auto_choice->pending) return HANDOVER;
        int r = vi_ode_step(o, p, INFINITY);
        if (r < 0 && s->cfg.method == VI_METHOD_AUTO) { /* the state is as before the step: BDF tries from there */
            s->cfg.log(s->cfg.log_env, VI_LOG_SOLVER, "t = %.17g s: Dormand-Prince 8(5,3) failed (%s)", o->t,
                       vi_ode_status_text(r));
            s->cfg.auto_choice->pending = 1;
            return HANDOVER;
        }
        if (r < 0) return ode_fail(s, r, "vi_ode_step");
        ++*taken;
        if (s->cfg.method == VI_METHOD_AUTO) test_one_step(s, o);
    }
}

/* ---- creation, common to both ----------------------------------------------------------------- */

/* 0 when cfg is within the limits and names a method with what it needs, else -1 with a message. */
static int check_config(const vi_solver_config *cfg)
{
    if (cfg->n < 1 || cfg->n > VI_SOLVER_MAX_N || cfg->n > VI_ODE_MAX_N || cfg->nguards < 0 ||
        cfg->nguards > VI_SOLVER_MAX_GUARDS || cfg->nguards > VI_ODE_MAX_G) {
        cfg->log(cfg->log_env, VI_LOG_ERROR, "vi_solver_create: %d states and %d guards exceed the limits %d and %d",
                 cfg->n, cfg->nguards, VI_SOLVER_MAX_N, VI_SOLVER_MAX_GUARDS);
        return -1;
    }
    if (cfg->method != VI_METHOD_BDF && cfg->method != VI_METHOD_ADAMS && cfg->method != VI_METHOD_DOP853 &&
        cfg->method != VI_METHOD_AUTO) {
        cfg->log(cfg->log_env, VI_LOG_ERROR, "vi_solver_create: unknown method %d", cfg->method);
        return -1;
    }
    if (cfg->method == VI_METHOD_AUTO && (cfg->n > 2 || !cfg->jac || !cfg->auto_choice)) {
        cfg->log(cfg->log_env, VI_LOG_ERROR, "vi_solver_create: auto needs at most 2 states, a Jacobian and its "
                 "choice (cfg->auto_choice); got %d states%s%s", cfg->n, cfg->jac ? "" : ", no Jacobian",
                 cfg->auto_choice ? "" : ", no auto_choice");
        return -1;
    }
    return 0;
}

/* CVODE's context, integrator, vectors and dense linear solver; 0 or -1 with a message. */
static int create_cvode(vi_solver *s)
{
    const vi_solver_config *cfg = &s->cfg;
    if (check_flag(s, SUNContext_Create(VI_SUN_COMM_NULL, &s->ctx), "SUNContext_Create") < 0) return -1;
#if VI_SUNDIALS_7
    if (route_messages(s) < 0) return -1;
#endif
    s->cvode = CVodeCreate(cfg->method == VI_METHOD_ADAMS ? CV_ADAMS : CV_BDF, s->ctx); /* AUTO: BDF */
    if (check_ptr(s, s->cvode, "CVodeCreate") < 0) return -1;
    s->x = N_VNew_Serial(cfg->n, s->ctx);
    if (check_ptr(s, s->x, "N_VNew_Serial") < 0) return -1;
    /* the fused vector operations (one loop for a linear combination, as CVodeGetDky's interpolation
     * into dky needs) for x, the vectors CVODE clones from it, and dky: a communication point inside
     * the last internal step costs a third of the unfused sequence of vector calls */
    if (check_flag(s, N_VEnableFusedOps_Serial(s->x, SUNTRUE), "N_VEnableFusedOps_Serial") < 0) return -1;
    s->atol = N_VNew_Serial(cfg->n, s->ctx);
    if (check_ptr(s, s->atol, "N_VNew_Serial") < 0) return -1;
    s->dky = N_VNew_Serial(cfg->n, s->ctx);
    if (check_ptr(s, s->dky, "N_VNew_Serial") < 0) return -1;
    if (check_flag(s, N_VEnableFusedOps_Serial(s->dky, SUNTRUE), "N_VEnableFusedOps_Serial") < 0) return -1;
    s->A = SUNDenseMatrix(cfg->n, cfg->n, s->ctx);
    if (check_ptr(s, s->A, "SUNDenseMatrix") < 0) return -1;
    s->LS = SUNLinSol_Dense(s->x, s->A, s->ctx);
    if (check_ptr(s, s->LS, "SUNLinSol_Dense") < 0) return -1;
    return 0;
}

static vi_solver *create(const vi_solver_config *cfg, double t0, const double *x0, int resume)
{
    if (check_config(cfg) < 0) return NULL;
    vi_solver *s = calloc(1, sizeof *s);
    if (!s) {
        cfg->log(cfg->log_env, VI_LOG_ERROR, "out of memory creating the solver");
        return NULL;
    }
    s->cfg = *cfg;
    pieces_from(s, t0, x0);
    if (cfg->method == VI_METHOD_DOP853) {
        if (ode_setup(s) < 0) goto fail;
        if (resume ? !ode_valid(s, t0) : vi_solver_reset(s, t0, x0) < 0) goto fail;
        s->ode_resets = 0;
        return s;
    }
    if (create_cvode(s) < 0) goto fail;
    if (configure(s, t0, x0) < 0) goto fail;
    if (cfg->method == VI_METHOD_AUTO) { /* the one-step method first; resumed: the method the choice names */
        if (ode_setup(s) < 0) goto fail;
        if (!resume) *cfg->auto_choice = (vi_solver_auto){0};
        if (resume ? !cfg->auto_choice->bdf && !ode_valid(s, t0) : vi_solver_reset(s, t0, x0) < 0) goto fail;
        s->ode_resets = 0;
    }
    return s;
fail:
    vi_solver_free(s);
    return NULL;
}

vi_solver *vi_solver_create(const vi_solver_config *cfg, double t0, const double *x0)
{
    return create(cfg, t0, x0, 0);
}

vi_solver *vi_solver_resume(const vi_solver_config *cfg, double t0, const double *x0)
{
    return create(cfg, t0, x0, 1);
}

int vi_solver_checkpoint(vi_solver *s, double t0, const double *x0)
{
    int one_step = s->cfg.method == VI_METHOD_DOP853 || (s->cfg.method == VI_METHOD_AUTO && !s->cfg.auto_choice->bdf);
    return one_step ? 0 : vi_solver_reset(s, t0, x0);
}

/* Restart the one-step method, or CVODE, at (t0, x0). */
static int ode_restart(vi_solver *s, double t0, const double *x0)
{
    pieces_from(s, t0, x0);
    int r = vi_ode_restart(s->cfg.ode, &s->ode_problem, t0, x0, 0.0, 0u);
    return r < 0 ? ode_fail_at(s, r, "vi_ode_restart", t0) : 0;
}

static void cvode_counters(const vi_solver *s, vi_solver_stats *st);

static int cvode_restart(vi_solver *s, double t0, const double *x0)
{
    pieces_from(s, t0, x0);
    memcpy(NV_DATA_S(s->x), x0, sizeof(double) * (size_t)s->cfg.n);
    cvode_counters(s, &s->before_reset);
    CHECK(CVodeReInit(s->cvode, t0, s->x));
    s->fresh = 1;
    s->t0 = s->tn = t0;
    s->root_pending = 0;
    if (s->cfg.method == VI_METHOD_AUTO) s->cfg.auto_choice->steps = 0, s->cfg.auto_choice->calm = 0;
    return 0;
}

int vi_solver_reset(vi_solver *s, double t0, const double *x0)
{
    vi_solver_auto *a = s->cfg.method == VI_METHOD_AUTO ? s->cfg.auto_choice : NULL;
    if (a && a->pending) hand_over(s, t0);
    if (s->cfg.method == VI_METHOD_DOP853 || (a && !a->bdf)) {
        s->ode_resets++;
        return ode_restart(s, t0, x0);
    }
    s->before_reset.resets++;
    return cvode_restart(s, t0, x0);
}

/* CVODE is driven one internal step at a time (CV_ONE_STEP): a communication point inside the last
 * step costs one interpolation (CVodeGetDky), no call into the integrator and no root check of its
 * own; CVODE checks the guards once per step over the whole step. A root found in a step is held
 * until the output points before it have been served. */
static int cvode_advance(vi_solver *s, double tout, long max_steps, double *t, double *x, int *fired, long *taken)
{
    size_t bytes = sizeof(double) * (size_t)s->cfg.n;
    if (s->fresh && tout - s->t0 <= 4.0 * DBL_EPSILON * fmax(fabs(s->t0), fabs(tout))) {
        /* closer than CVODE can start an integration: x(tout) = x(t0) to within a few ulps of time.
         * The solver stays at t0 and the next call integrates from there. */
        memcpy(x, NV_DATA_S(s->x), bytes);
        *t = tout;
        return cover(s, 0, tout, x, NULL) < 0 ? VI_SOLVER_FAILED : VI_SOLVER_REACHED;
    }
    for (;;) { /* bounded: every pass takes a step, at most max_steps */
        if (s->root_pending && s->troot <= tout) {
            s->root_pending = 0;
            *t = s->troot;
            memcpy(x, s->xroot, bytes);
            memcpy(fired, s->rootsfound, sizeof(int) * (size_t)s->cfg.nguards);
            return cover(s, 0, *t, x, NULL) < 0 ? VI_SOLVER_FAILED : VI_SOLVER_EVENT;
        }
        if (!s->fresh && tout <= s->tn) {
            CHECK(CVodeGetDky(s->cvode, tout, 0, s->dky));
            memcpy(x, NV_DATA_S(s->dky), bytes);
            *t = tout;
            return cover(s, 0, tout, x, NULL) < 0 ? VI_SOLVER_FAILED : VI_SOLVER_REACHED;
        }
        /* the rest of the last step, before it is left (s->x holds x(tn): no root is pending here) */
        if (!s->fresh && cover(s, 0, s->tn, NV_DATA_S(s->x), NULL) < 0) return VI_SOLVER_FAILED;
        if (*taken >= max_steps) { /* s->x holds x(tn): no root is pending in a completed step */
            *t = s->tn;
            memcpy(x, NV_DATA_S(s->x), bytes);
            return VI_SOLVER_LIMIT;
        }
        if (s->cfg.method == VI_METHOD_AUTO && s->cfg.auto_choice->pending) return HANDOVER; /* s->x holds x(tn) */
        sunrealtype tret;
        int flag = CVode(s->cvode, tout, s->x, &tret, CV_ONE_STEP);
        CHECK(flag);
        CHECK(CVodeGetCurrentTime(s->cvode, &s->tn));
        s->fresh = 0;
        ++*taken;
        if (flag == CV_ROOT_RETURN) {
            s->root_pending = 1;
            s->troot = tret;
            memcpy(s->xroot, NV_DATA_S(s->x), bytes);
            CHECK(CVodeGetRootInfo(s->cvode, s->rootsfound));
        }
        if (s->cfg.method == VI_METHOD_AUTO && test_bdf(s, NV_DATA_S(s->x)) < 0) return VI_SOLVER_FAILED;
    }
}

int vi_solver_advance(vi_solver *s, double tout, long max_steps, double *t, double *x, int *fired, long *taken)
{
    *taken = 0;
    if (s->cfg.method == VI_METHOD_DOP853) return ode_advance(s, tout, max_steps, t, x, fired, taken);
    if (s->cfg.method != VI_METHOD_AUTO) return cvode_advance(s, tout, max_steps, t, x, fired, taken);
    /* AUTO: bounded, a hand-over is asked for only after steps taken since the one before (at most
     * max_steps of them) */
    for (long pass = 0; pass <= max_steps + 1; pass++) {
        int r = s->cfg.auto_choice->bdf ? cvode_advance(s, tout, max_steps, t, x, fired, taken)
                               : ode_advance(s, tout, max_steps, t, x, fired, taken);
        if (r != HANDOVER) return r;
        const vi_ode *o = s->cfg.ode;
        double t0 = s->cfg.auto_choice->bdf ? s->tn : o->t, x0[VI_SOLVER_MAX_N];
        memcpy(x0, s->cfg.auto_choice->bdf ? NV_DATA_S(s->x) : o->x, sizeof(double) * (size_t)s->cfg.n);
        hand_over(s, t0);
        if ((s->cfg.auto_choice->bdf ? cvode_restart(s, t0, x0) : ode_restart(s, t0, x0)) < 0) return VI_SOLVER_FAILED;
    }
    return VI_SOLVER_FAILED;
}

/* CVODE's counters since the last (re)initialisation. Their return values are not checked: they fail
 * only for a NULL CVODE memory or linear solver, and both exist for the solver's whole life. */
static void current_counters(const vi_solver *s, vi_solver_stats *st)
{
    memset(st, 0, sizeof *st);
    CVodeGetNumSteps(s->cvode, &st->steps);
    CVodeGetNumRhsEvals(s->cvode, &st->rhs_evals);
    CVodeGetNumJacEvals(s->cvode, &st->jac_evals);
    CVodeGetNumNonlinSolvIters(s->cvode, &st->nonlin_iters);
    CVodeGetNumNonlinSolvConvFails(s->cvode, &st->nonlin_fails);
    CVodeGetNumErrTestFails(s->cvode, &st->err_test_fails);
    CVodeGetNumGEvals(s->cvode, &st->guard_evals);
}

/* CVODE's counters since vi_solver_create (the sums before its restarts included). */
static void cvode_counters(const vi_solver *s, vi_solver_stats *st)
{
    vi_solver_stats c;
    current_counters(s, &c);
    const vi_solver_stats *b = &s->before_reset;
    *st = (vi_solver_stats){.steps = b->steps + c.steps, .rhs_evals = b->rhs_evals + c.rhs_evals,
                            .jac_evals = b->jac_evals + c.jac_evals, .nonlin_iters = b->nonlin_iters + c.nonlin_iters,
                            .nonlin_fails = b->nonlin_fails + c.nonlin_fails,
                            .err_test_fails = b->err_test_fails + c.err_test_fails,
                            .guard_evals = b->guard_evals + c.guard_evals, .resets = b->resets};
}

void vi_solver_statistics(const vi_solver *s, vi_solver_stats *st)
{
    memset(st, 0, sizeof *st);
    if (s->cfg.method != VI_METHOD_DOP853) cvode_counters(s, st);
    if (s->cfg.method == VI_METHOD_DOP853 || s->cfg.method == VI_METHOD_AUTO) {
        const vi_ode_stats *o = &s->cfg.ode->st;
        st->steps += o->accepted;
        st->rhs_evals += o->rhs_evals;
        st->err_test_fails += o->rejected;
        st->guard_evals += o->guard_evals;
        st->resets += s->ode_resets;
    }
    if (s->cfg.method == VI_METHOD_AUTO) st->switches = s->cfg.auto_choice->switches;
    st->method = vi_solver_method_name(s->cfg.method);
}

void vi_solver_free(vi_solver *s)
{
    if (!s) return;
    if (s->cvode) CVodeFree(&s->cvode);
    if (s->LS) SUNLinSolFree(s->LS);
    if (s->A) SUNMatDestroy(s->A);
    if (s->x) N_VDestroy(s->x);
    if (s->atol) N_VDestroy(s->atol);
    if (s->dky) N_VDestroy(s->dky);
    if (s->ctx) SUNContext_Free(&s->ctx);
    free(s);
}
