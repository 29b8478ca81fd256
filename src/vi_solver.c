/* vi_solver.c - CVODE 6.4 wrapper; see vi_solver.h. */
#include "vi_solver.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

struct vi_solver {
    vi_solver_config cfg;
    double *atol_copy;
    SUNContext ctx;
    void *cvode;
    N_Vector x, atol;
    SUNMatrix A;
    SUNLinearSolver LS;
    vi_solver_stats before_reset; /* CVodeReInit zeroes CVODE's counters: the sums before it */
};

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

static int rhs_cb(sunrealtype t, N_Vector x, N_Vector dx, void *ud)
{
    vi_solver *s = ud;
    s->cfg.rhs(t, N_VGetArrayPointer(x), N_VGetArrayPointer(dx), s->cfg.user);
    return 0;
}

static int guard_cb(sunrealtype t, N_Vector x, sunrealtype *g, void *ud)
{
    vi_solver *s = ud;
    s->cfg.guards(t, N_VGetArrayPointer(x), g, s->cfg.user);
    return 0;
}

static int jac_cb(sunrealtype t, N_Vector x, N_Vector fx, SUNMatrix J, void *ud, N_Vector t1, N_Vector t2,
                  N_Vector t3)
{
    (void)fx, (void)t1, (void)t2, (void)t3;
    vi_solver *s = ud;
    int n = s->cfg.n;
    double j[VI_SOLVER_MAX_N * VI_SOLVER_MAX_N];
    s->cfg.jac(t, N_VGetArrayPointer(x), j, s->cfg.user);
    for (int r = 0; r < n; r++)
        for (int c = 0; c < n; c++) SM_ELEMENT_D(J, r, c) = j[r * n + c];
    return 0;
}

static void err_cb(int code, const char *module, const char *function, char *msg, void *ud)
{
    vi_solver *s = ud;
    s->cfg.log(s->cfg.log_env, code < 0 ? VI_LOG_ERROR : VI_LOG_WARNING, "%s %s: %s", module, function, msg);
}

static int configure(vi_solver *s, double t0, const double *x0)
{
    const vi_solver_config *c = &s->cfg;
    memcpy(N_VGetArrayPointer(s->x), x0, sizeof(double) * (size_t)c->n);
    memcpy(N_VGetArrayPointer(s->atol), c->atol, sizeof(double) * (size_t)c->n);
    CHECK(CVodeSetErrHandlerFn(s->cvode, err_cb, s));
    CHECK(CVodeInit(s->cvode, rhs_cb, t0, s->x));
    CHECK(CVodeSetUserData(s->cvode, s));
    CHECK(CVodeSVtolerances(s->cvode, c->rtol, s->atol));
    CHECK(CVodeSetLinearSolver(s->cvode, s->LS, s->A));
    if (c->jac) CHECK(CVodeSetJacFn(s->cvode, jac_cb));
    CHECK(CVodeSetMaxNumSteps(s->cvode, c->max_steps));
    if (c->max_step > 0.0) CHECK(CVodeSetMaxStep(s->cvode, c->max_step));
    if (c->nguards > 0) {
        int dir[VI_SOLVER_MAX_GUARDS];
        for (int i = 0; i < c->nguards; i++) dir[i] = -1;
        CHECK(CVodeRootInit(s->cvode, c->nguards, guard_cb));
        CHECK(CVodeSetRootDirection(s->cvode, dir));
        CHECK(CVodeSetNoInactiveRootWarn(s->cvode));
    }
    return 0;
}

vi_solver *vi_solver_create(const vi_solver_config *cfg, double t0, const double *x0)
{
    if (cfg->n < 1 || cfg->n > VI_SOLVER_MAX_N || cfg->nguards < 0 || cfg->nguards > VI_SOLVER_MAX_GUARDS) {
        cfg->log(cfg->log_env, VI_LOG_ERROR, "vi_solver_create: %d states and %d guards exceed the limits %d and %d",
                 cfg->n, cfg->nguards, VI_SOLVER_MAX_N, VI_SOLVER_MAX_GUARDS);
        return NULL;
    }
    vi_solver *s = calloc(1, sizeof *s);
    if (!s) {
        cfg->log(cfg->log_env, VI_LOG_ERROR, "out of memory creating the solver");
        return NULL;
    }
    s->cfg = *cfg;
    s->atol_copy = malloc(sizeof(double) * (size_t)cfg->n);
    if (check_ptr(s, s->atol_copy, "malloc") < 0) goto fail;
    memcpy(s->atol_copy, cfg->atol, sizeof(double) * (size_t)cfg->n);
    s->cfg.atol = s->atol_copy;
    if (check_flag(s, SUNContext_Create(NULL, &s->ctx), "SUNContext_Create") < 0) goto fail;
    s->cvode = CVodeCreate(cfg->adams ? CV_ADAMS : CV_BDF, s->ctx);
    if (check_ptr(s, s->cvode, "CVodeCreate") < 0) goto fail;
    s->x = N_VNew_Serial(cfg->n, s->ctx);
    if (check_ptr(s, s->x, "N_VNew_Serial") < 0) goto fail;
    s->atol = N_VNew_Serial(cfg->n, s->ctx);
    if (check_ptr(s, s->atol, "N_VNew_Serial") < 0) goto fail;
    s->A = SUNDenseMatrix(cfg->n, cfg->n, s->ctx);
    if (check_ptr(s, s->A, "SUNDenseMatrix") < 0) goto fail;
    s->LS = SUNLinSol_Dense(s->x, s->A, s->ctx);
    if (check_ptr(s, s->LS, "SUNLinSol_Dense") < 0) goto fail;
    if (configure(s, t0, x0) < 0) goto fail;
    return s;
fail:
    vi_solver_free(s);
    return NULL;
}

int vi_solver_reset(vi_solver *s, double t0, const double *x0)
{
    memcpy(N_VGetArrayPointer(s->x), x0, sizeof(double) * (size_t)s->cfg.n);
    vi_solver_statistics(s, &s->before_reset);
    s->before_reset.resets++;
    CHECK(CVodeReInit(s->cvode, t0, s->x));
    return 0;
}

int vi_solver_advance(vi_solver *s, double tout, double *t, double *x, int *fired)
{
    sunrealtype tret = *t;
    CHECK(CVodeSetStopTime(s->cvode, tout));
    int flag = CVode(s->cvode, tout, s->x, &tret, CV_NORMAL);
    CHECK(flag);
    *t = tret;
    memcpy(x, N_VGetArrayPointer(s->x), sizeof(double) * (size_t)s->cfg.n);
    if (flag == CV_ROOT_RETURN) {
        CHECK(CVodeGetRootInfo(s->cvode, fired));
        return VI_SOLVER_EVENT;
    }
    *t = tout;
    return VI_SOLVER_REACHED;
}

/* CVODE's counters since the last (re)initialisation. */
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

void vi_solver_statistics(const vi_solver *s, vi_solver_stats *st)
{
    vi_solver_stats c;
    current_counters(s, &c);
    const vi_solver_stats *b = &s->before_reset;
    st->steps = b->steps + c.steps;
    st->rhs_evals = b->rhs_evals + c.rhs_evals;
    st->jac_evals = b->jac_evals + c.jac_evals;
    st->nonlin_iters = b->nonlin_iters + c.nonlin_iters;
    st->nonlin_fails = b->nonlin_fails + c.nonlin_fails;
    st->err_test_fails = b->err_test_fails + c.err_test_fails;
    st->guard_evals = b->guard_evals + c.guard_evals;
    st->resets = b->resets;
}

void vi_solver_free(vi_solver *s)
{
    if (!s) return;
    if (s->cvode) CVodeFree(&s->cvode);
    if (s->LS) SUNLinSolFree(s->LS);
    if (s->A) SUNMatDestroy(s->A);
    if (s->x) N_VDestroy(s->x);
    if (s->atol) N_VDestroy(s->atol);
    if (s->ctx) SUNContext_Free(&s->ctx);
    free(s->atol_copy);
    free(s);
}
