/* Unit tests of the one-step integrator (vi_ode.h). Expected values come from the Butcher order
 * conditions (rooted trees, computed here), from closed-form solutions, and from the documented
 * behaviour (event rules, bounds, bit-exact restart); none is taken from the code's own output. */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_ode.h"

#define PI 3.14159265358979323846

/* ---------------------------------------------------------------------------------------------
 * Rooted trees up to order 8 and the order conditions sum_i w_i Phi_i(t) = 1/gamma(t)
 * ------------------------------------------------------------------------------------------- */
#define MAX_ORDER 8
#define MAX_TREES 256
#define NS VI_ODE_STAGES

typedef struct {
    int order, nch, ch[MAX_ORDER];
    long double gamma;
} tree;

static tree T[MAX_TREES];
static int n_trees;

/* Append all trees of order `ord` whose children (indices < limit, non-increasing) sum to rem. */
static void grow(int ord, int limit, int *ch, int nch, int rem, int max_idx)
{
    if (rem == 0) {
        cr_assert(n_trees < MAX_TREES);
        tree *t = &T[n_trees++];
        t->order = ord;
        t->nch = nch;
        t->gamma = ord;
        for (int i = 0; i < nch; i++) {
            t->ch[i] = ch[i];
            t->gamma *= T[ch[i]].gamma;
        }
        return;
    }
    for (int i = max_idx; i >= 0; i--) {
        if (i >= limit || T[i].order > rem) continue;
        ch[nch] = i;
        grow(ord, limit, ch, nch + 1, rem - T[i].order, i);
    }
}

static void make_trees(void)
{
    n_trees = 0;
    int ch[MAX_ORDER];
    for (int ord = 1; ord <= MAX_ORDER; ord++) {
        int limit = n_trees;
        grow(ord, limit, ch, 0, ord - 1, limit - 1);
    }
}

/* phi[t][i] = Phi_i(t) for all trees and stages; aphi[t][i] = sum_j a_ij Phi_j(t); the same with
 * |a_ij| (phi_abs, aphi_abs) is the scale of the rounding errors of the double coefficients. */
static long double phi[MAX_TREES][NS], aphi[MAX_TREES][NS], phi_abs[MAX_TREES][NS], aphi_abs[MAX_TREES][NS];

static void elementary_weights(const vi_ode_tableau *m)
{
    for (int t = 0; t < n_trees; t++) {
        for (int i = 0; i < NS; i++) {
            long double p = 1.0L, pa = 1.0L;
            for (int c = 0; c < T[t].nch; c++) p *= aphi[T[t].ch[c]][i], pa *= aphi_abs[T[t].ch[c]][i];
            phi[t][i] = p;
            phi_abs[t][i] = pa;
        }
        for (int i = 0; i < NS; i++) {
            long double s = 0.0L, sa = 0.0L;
            for (int j = 0; j < i; j++) {
                s += (long double)m->a[i][j] * phi[t][j];
                sa += fabsl((long double)m->a[i][j]) * phi_abs[t][j];
            }
            aphi[t][i] = s;
            aphi_abs[t][i] = sa;
        }
    }
}

/* Largest scaled residual of sum_i w_i Phi_i(t) = target(t) over trees with order in [lo, hi],
 * where target = theta^order / gamma (theta = 1 for the step) or 0 (zero = 1). */
static double residual(const long double *w, int lo, int hi, long double theta, int zero)
{
    double worst = 0.0;
    for (int t = 0; t < n_trees; t++) {
        if (T[t].order < lo || T[t].order > hi) continue;
        long double s = 0.0L, scale = 0.0L;
        for (int i = 0; i < NS; i++) {
            s += w[i] * phi[t][i];
            scale += fabsl(w[i]) * phi_abs[t][i];
        }
        long double target = zero ? 0.0L : powl(theta, T[t].order) / T[t].gamma;
        double r = (double)(fabsl(s - target) / (scale + fabsl(target)));
        if (r > worst) worst = r;
        if (getenv("VI_ODE_SHOW_RESIDUALS")) printf("order %d tree %d residual %.3g\n", T[t].order, t, r);
    }
    return worst;
}

Test(tableau, rooted_tree_counts)
{
    static const int count[MAX_ORDER + 1] = {0, 1, 1, 2, 4, 9, 20, 48, 115}; /* OEIS A000081 */
    make_trees();
    int per[MAX_ORDER + 1] = {0};
    for (int t = 0; t < n_trees; t++) per[T[t].order]++;
    for (int o = 1; o <= MAX_ORDER; o++) cr_assert_eq(per[o], count[o], "order %d: %d trees", o, per[o]);
    cr_assert_eq(n_trees, 200);
}

Test(tableau, nodes_are_row_sums_and_published_values)
{
    const vi_ode_tableau *m = vi_ode_method();
    for (int i = 0; i < NS; i++) {
        long double s = 0.0L, sa = 0.0L;
        for (int j = 0; j < i; j++) s += m->a[i][j], sa += fabs(m->a[i][j]);
        cr_assert(fabsl(s - m->c[i]) <= 2.0L * DBL_EPSILON * (sa + 1.0L), "stage %d: sum a = %.17Lg, c = %.17g", i, s,
                  m->c[i]);
    }
    double r6 = sqrt(6.0), c4 = (6.0 - r6) / 30.0;
    cr_assert(fabs(m->c[3] - c4) < 1e-16 && fabs(m->c[4] - (6.0 + r6) / 30.0) < 1e-16);
    cr_assert(fabs(m->c[2] - 2.0 * c4 / 3.0) < 1e-16 && fabs(m->c[1] - 4.0 * c4 / 9.0) < 1e-16);
    cr_assert(m->c[11] == 1.0 && m->c[12] == 1.0);
    for (int j = 0; j < NS; j++) cr_assert(m->a[12][j] == m->b[j], "stage 13 is f at the new point");
}

Test(tableau, the_sums_skip_only_zeros)
{
    const vi_ode_tableau *m = vi_ode_method();
    for (int i = 1; i < NS; i++)
        for (int j = 1; j < m->lo[i]; j++) cr_assert(m->a[i][j] == 0.0, "a[%d][%d] is skipped", i, j);
    for (int j = 1; j < m->lo[12]; j++) cr_assert(m->b[j] == 0.0 && m->e5[j] == 0.0 && m->e3[j] == 0.0);
    for (int j = 12; j < NS; j++) cr_assert(m->b[j] == 0.0 && m->e5[j] == 0.0 && m->e3[j] == 0.0);
    for (int r = 0; r < 4; r++)
        for (int j = 1; j < m->lo_d; j++) cr_assert(m->d[r][j] == 0.0, "d[%d][%d] is skipped", r, j);
}

Test(tableau, step_has_order_8_and_estimators_orders_5_and_3)
{
    const vi_ode_tableau *m = vi_ode_method();
    make_trees();
    elementary_weights(m);
    long double b[NS], e5[NS], e3[NS];
    for (int i = 0; i < NS; i++) b[i] = m->b[i], e5[i] = m->e5[i], e3[i] = m->e3[i];
    double rb = residual(b, 1, 8, 1.0L, 0);
    cr_assert(rb < 1e-14, "order conditions of b up to order 8: residual %g", rb);
    /* estimator e = b - bhat: bhat of order 5 (3), i.e. sum e Phi = 0 for trees up to order 5 (3) */
    double r5 = residual(e5, 1, 5, 1.0L, 1), r3 = residual(e3, 1, 3, 1.0L, 1);
    cr_assert(r5 < 1e-14 && r3 < 1e-14, "estimators: residuals %g %g", r5, r3);
    /* and not of a higher order (else the estimate would vanish too fast) */
    cr_assert(residual(e5, 6, 6, 1.0L, 1) > 1e-6 && residual(e3, 4, 4, 1.0L, 1) > 1e-6);
}

/* The continuous weights b_i(theta) of the dense output as documented in vi_ode.h. */
static void dense_weights(const vi_ode_tableau *m, long double th, long double *w)
{
    long double t1 = 1.0L - th;
    for (int i = 0; i < NS; i++) {
        long double q0 = m->b[i], q1 = (i == 0) - q0, q2 = q0 - (i == 12) - q1;
        long double q[7] = {q0, q1, q2, m->d[0][i], m->d[1][i], m->d[2][i], m->d[3][i]};
        w[i] = th * (q[0] + t1 * (q[1] + th * (q[2] + t1 * (q[3] + th * (q[4] + t1 * (q[5] + th * q[6]))))));
    }
}

Test(tableau, dense_output_has_order_7)
{
    const vi_ode_tableau *m = vi_ode_method();
    make_trees();
    elementary_weights(m);
    long double w[NS];
    /* a polynomial identity of degree <= 7 in theta that holds at theta = 0 and 8 more points */
    for (int k = 1; k <= 8; k++) {
        long double th = k / 8.0L;
        dense_weights(m, th, w);
        double r = residual(w, 1, 7, th, 0);
        cr_assert(r < 1e-14, "dense output at theta = %Lg: residual %g", th, r);
    }
    dense_weights(m, 0.5L, w);
    cr_assert(residual(w, 8, 8, 0.5L, 0) > 1e-8, "not of order 8 inside the step");
    dense_weights(m, 1.0L, w);
    for (int i = 0; i < NS; i++) cr_assert(fabsl(w[i] - m->b[i]) < 1e-14L, "theta = 1 gives the step");
}

/* ---------------------------------------------------------------------------------------------
 * Problems with closed-form solutions
 * ------------------------------------------------------------------------------------------- */

/* Harmonic oscillator x'' = -x: x = (x, v), x(t) = x0 cos t + v0 sin t. */
static void osc(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = x[1];
    dx[1] = -x[0];
}
static void osc_exact(double t, const double *x0, double *x)
{
    x[0] = x0[0] * cos(t) + x0[1] * sin(t);
    x[1] = -x0[0] * sin(t) + x0[1] * cos(t);
}

/* y' = -2 t y^2, y(0) = 1: y = 1/(1 + t^2). */
static void riccati(double t, const double *x, double *dx, void *u)
{
    (void)u;
    dx[0] = -2.0 * t * x[0] * x[0];
}
static void riccati_exact(double t, const double *x0, double *x)
{
    (void)x0;
    x[0] = 1.0 / (1.0 + t * t);
}

/* Forced oscillator x'' + x = cos 2t from rest: x = (cos t - cos 2t)/3. */
static void forced(double t, const double *x, double *dx, void *u)
{
    (void)u;
    dx[0] = x[1];
    dx[1] = -x[0] + cos(2.0 * t);
}
static void forced_exact(double t, const double *x0, double *x)
{
    (void)x0;
    x[0] = (cos(t) - cos(2.0 * t)) / 3.0;
    x[1] = (-sin(t) + 2.0 * sin(2.0 * t)) / 3.0;
}

/* Two oscillators of frequencies 1 and 2 (4 states: the integrator's wider component path). */
static void osc2(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = x[1], dx[1] = -x[0];
    dx[2] = x[3], dx[3] = -4.0 * x[2];
}
static void osc2_exact(double t, const double *x0, double *x)
{
    osc_exact(t, x0, x);
    x[2] = x0[2] * cos(2 * t) + 0.5 * x0[3] * sin(2 * t);
    x[3] = -2.0 * x0[2] * sin(2 * t) + x0[3] * cos(2 * t);
}

/* The oscillator and the Riccati equation side by side (3 states). */
static void osc_riccati(double t, const double *x, double *dx, void *u)
{
    osc(t, x, dx, u);
    riccati(t, x + 2, dx + 2, u);
}
static void osc_riccati_exact(double t, const double *x0, double *x)
{
    osc_exact(t, x0, x);
    riccati_exact(t, x0 + 2, x + 2);
}

#define NX VI_ODE_MAX_N

typedef struct {
    const char *name;
    int n;
    vi_ode_rhs_fn f;
    void (*exact)(double t, const double *x0, double *x);
    double x0[NX], T;
    int n_first;    /* fewest fixed steps over [0, T] in the order test (the asymptotic range starts there) */
    double h_dense; /* largest step of the dense-output test */
    int periodic;   /* the step count over a long run is a power of the tolerance */
} problem;

static const problem PROBLEMS[] = {
    {"oscillator", 2, osc, osc_exact, {1.0, 0.5}, 8.0, 8, 1.0, 1},
    {"riccati", 1, riccati, riccati_exact, {1.0}, 4.0, 16, 0.4, 0}, /* poles at +-i */
    {"forced", 2, forced, forced_exact, {0.0, 0.0}, 6.0, 8, 0.75, 1},
    {"two oscillators", 4, osc2, osc2_exact, {1.0, 0.5, 0.3, -0.2}, 8.0, 16, 0.5, 1},
    {"oscillator and riccati", 3, osc_riccati, osc_riccati_exact, {1.0, 0.5, 1.0}, 4.0, 16, 0.4, 0},
};
#define N_PROBLEMS (int)(sizeof PROBLEMS / sizeof PROBLEMS[0])

static vi_ode_problem make(const problem *pr, double rtol, double atol)
{
    vi_ode_problem p = {.n = pr->n, .rhs = pr->f, .rtol = rtol};
    for (int i = 0; i < pr->n; i++) p.atol[i] = atol;
    return p;
}

static double max_err(const double *a, const double *b, int n)
{
    double e = 0.0;
    for (int i = 0; i < n; i++) e = fmax(e, fabs(a[i] - b[i]));
    return e;
}

/* Integrate to pr->T (steps bounded); return the largest max-norm error at the step points and the
 * number of steps. */
static double run(const problem *pr, vi_ode_problem *p, long *steps)
{
    vi_ode s;
    double e = 0.0, xe[NX];
    cr_assert_eq(vi_ode_init(&s, p, 0.0, pr->x0, 0.0, 0u), VI_ODE_OK);
    for (long k = 0; s.t < pr->T; k++) {
        cr_assert(k < 1000000, "too many steps");
        int r = vi_ode_step(&s, p, pr->T);
        cr_assert_eq(r, VI_ODE_OK, "%s: %s at t = %g", pr->name, vi_ode_status_text(r), s.t);
        pr->exact(s.t, pr->x0, xe);
        e = fmax(e, max_err(s.x, xe, pr->n));
    }
    cr_assert(s.t == pr->T, "ends exactly at t_stop");
    if (steps) *steps = s.st.accepted;
    return e;
}

/* Least-squares slope of log y against log x. */
static double slope(const double *x, const double *y, int n)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int i = 0; i < n; i++) {
        double lx = log(x[i]), ly = log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

Test(order, global_error_falls_like_h8_with_fixed_steps)
{
    for (int k = 0; k < N_PROBLEMS; k++) {
        const problem *pr = &PROBLEMS[k];
        double e[5];
        int checked = 0;
        for (int j = 0; j < 5; j++) {
            vi_ode_problem p = make(pr, 1e-6, 1e-6);
            p.h_fixed = pr->T / (pr->n_first << j);
            e[j] = run(pr, &p, NULL);
        }
        for (int j = 0; j + 1 < 5; j++) {
            double ord = log2(e[j] / e[j + 1]);
            cr_log_info("%s: %d steps: error %.3e, observed order %.2f", pr->name, pr->n_first << j, e[j], ord);
            if (e[j + 1] < 5e-15) continue; /* rounding */
            checked++;
            cr_assert(ord >= 7.5 && ord <= 9.5, "%s: order %.2f from %d to %d steps", pr->name, ord,
                      pr->n_first << j, pr->n_first << (j + 1));
        }
        cr_assert(checked >= 2, "%s: order seen over %d halvings only", pr->name, checked);
    }
}

/* One fixed step of size h from the exact solution at t0: the state after it. */
static void one_step(const problem *pr, double t0, double h, vi_ode *s, vi_ode_problem *p)
{
    double x0[NX];
    pr->exact(t0, pr->x0, x0);
    *p = make(pr, 1e-6, 1e-6);
    p->h_fixed = h;
    cr_assert_eq(vi_ode_init(s, p, t0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(s, p, INFINITY), VI_ODE_OK);
    cr_assert(s->t == t0 + h);
}

Test(estimate, embedded_estimate_behaves_like_h8)
{
    /* err = err5^2 / sqrt(err5^2 + 0.01 err3^2) with err5 ~ h^6, err3 ~ h^4: ~ h^8 for small h */
    for (int k = 0; k < N_PROBLEMS; k++) {
        const problem *pr = &PROBLEMS[k];
        double hs[4], es[4];
        for (int j = 0; j < 4; j++) {
            vi_ode s;
            vi_ode_problem p;
            hs[j] = 0.2 / (1 << j);
            one_step(pr, 0.3, hs[j], &s, &p);
            es[j] = s.err;
            cr_assert(es[j] > 0.0);
        }
        double sl = slope(hs, es, 4);
        cr_log_info("%s: estimate %.3e .. %.3e, slope %.2f", pr->name, es[0], es[3], sl);
        cr_assert(sl > 7.5 && sl < 8.5, "%s: estimate slope %.2f", pr->name, sl);
    }
}

Test(estimate, error_proportional_to_tolerance_and_steps_like_tol_minus_one_eighth)
{
    for (int k = 0; k < N_PROBLEMS; k++) {
        problem pr = PROBLEMS[k];
        /* the oscillators over many periods (the step count is not dominated by the start); the
         * Riccati solution grows ever smoother, its step count is not a power of tol: error only */
        int periodic = pr.periodic;
        if (periodic) pr.T = 50.0;
        double tol[9], err[9], steps[9];
        for (int j = 0; j < 9; j++) {
            tol[j] = pow(10.0, -4.0 - j);
            vi_ode_problem p = make(&pr, tol[j], tol[j]);
            long ns;
            err[j] = run(&pr, &p, &ns);
            steps[j] = (double)ns;
            cr_log_info("%s: tol %.0e error %.2e (ratio %.2f) steps %ld", pr.name, tol[j], err[j], err[j] / tol[j], ns);
            cr_assert(err[j] < 30.0 * tol[j] && err[j] > 1e-2 * tol[j], "%s: tol %g error %g", pr.name, tol[j], err[j]);
        }
        double se = slope(tol, err, 9), ss = slope(tol, steps, 9);
        cr_log_info("%s: error ~ tol^%.3f, steps ~ tol^%.3f", pr.name, se, ss);
        cr_assert(se > 0.9 && se < 1.1, "%s: error ~ tol^%.3f", pr.name, se);
        if (periodic) cr_assert(ss > -0.14 && ss < -0.11, "%s: steps ~ tol^%.3f (expected -1/8)", pr.name, ss);
    }
}

Test(dense, local_error_of_order_7_inside_exact_at_ends)
{
    for (int k = 0; k < N_PROBLEMS; k++) {
        const problem *pr = &PROBLEMS[k];
        double hs[3], e_mid[3], e_end[3], e_der[3];
        for (int j = 0; j < 3; j++) {
            vi_ode s;
            vi_ode_problem p;
            double t0 = 1.0, h = hs[j] = pr->h_dense / (1 << j), x[NX], dx[NX], xe[NX], xe2[NX], f[NX];
            one_step(pr, t0, h, &s, &p);
            /* the ends, exactly */
            cr_assert_eq(vi_ode_dense(&s, &p, t0, x, dx), VI_ODE_OK);
            cr_assert(memcmp(x, s.x_old, sizeof(double) * (size_t)pr->n) == 0);
            pr->f(t0, s.x_old, f, NULL);
            cr_assert(max_err(dx, f, pr->n) <= 1e-12 * (1.0 + fabs(f[0]) + fabs(f[pr->n - 1])), "x'(t0) = f");
            cr_assert_eq(vi_ode_dense(&s, &p, s.t, x, dx), VI_ODE_OK);
            cr_assert(memcmp(x, s.x, sizeof(double) * (size_t)pr->n) == 0);
            pr->f(s.t, s.x, f, NULL);
            cr_assert(max_err(dx, f, pr->n) <= 1e-12 * (1.0 + fabs(f[0]) + fabs(f[pr->n - 1])), "x'(t1) = f");
            /* inside: worst of a few points; the end: the step's own local error */
            e_mid[j] = e_der[j] = 0.0;
            for (int i = 1; i <= 4; i++) {
                double t = t0 + h * (i / 5.0);
                cr_assert_eq(vi_ode_dense(&s, &p, t, x, dx), VI_ODE_OK);
                pr->exact(t, pr->x0, xe);
                e_mid[j] = fmax(e_mid[j], max_err(x, xe, pr->n));
                double d = 1e-6; /* the exact derivative by central differences of the exact solution */
                pr->exact(t + d, pr->x0, xe2);
                pr->exact(t - d, pr->x0, xe);
                for (int c = 0; c < pr->n; c++) e_der[j] = fmax(e_der[j], fabs(dx[c] - (xe2[c] - xe[c]) / (2 * d)));
            }
            pr->exact(s.t, pr->x0, xe);
            e_end[j] = max_err(s.x, xe, pr->n);
        }
        cr_assert(e_mid[2] > 1e-13 && e_end[2] > 5e-15, "%s: errors %g %g above rounding", pr->name, e_mid[2], e_end[2]);
        double sm = slope(hs, e_mid, 3), se = slope(hs, e_end, 3);
        cr_log_info("%s: dense local error %.2e .. %.2e slope %.2f; step end slope %.2f; derivative error %.2e .. %.2e",
                    pr->name, e_mid[0], e_mid[2], sm, se, e_der[0], e_der[2]);
        cr_assert(sm > 7.5 && sm < 8.7, "%s: dense output local error ~ h^%.2f (order 7: h^8)", pr->name, sm);
        cr_assert(se > 8.3, "%s: step local error ~ h^%.2f (order 8: h^9)", pr->name, se);
        cr_assert(e_der[2] < 1e-7 && e_der[2] < 1e-3 * e_der[0], "%s: derivative of the interpolant", pr->name);
    }
}

/* ---------------------------------------------------------------------------------------------
 * Events
 * ------------------------------------------------------------------------------------------- */
typedef struct {
    int kind;
    double tau;
    double t_min, t_max; /* range of the times the guards were evaluated at (set t_min = INFINITY) */
} gctx;

enum { G_X, G_MULTI, G_TWO_ROOTS, G_JUMP, G_FLAT, G_TINY, G_NAN, G_LOPSIDED };

static void guards(double t, const double *x, double *g, void *u)
{
    gctx *c = u;
    c->t_min = fmin(c->t_min, t);
    c->t_max = fmax(c->t_max, t);
    switch (c->kind) {
    case G_X: g[0] = x[0]; break;
    case G_MULTI: g[0] = x[0], g[1] = 2.0 * x[0], g[2] = x[0] + 0.5, g[3] = x[0] - 0.2; break;
    case G_TWO_ROOTS: g[0] = (t - 0.9) * (t - 1.1); break;
    case G_JUMP: g[0] = t < c->tau ? 1.0 : -1.0; break;
    case G_FLAT: g[0] = pow(c->tau - t, 5); break;
    case G_TINY: g[0] = 1e-300 * (c->tau - t); break;
    case G_NAN: g[0] = fabs(t - c->tau) < 0.05 ? NAN : c->tau - t; break;
    case G_LOPSIDED: g[0] = t < c->tau ? 1e300 : -1e-300; break;
    }
}

/* The oscillator with rhs user data NULL and guards with context c. */
static void osc_u(double t, const double *x, double *dx, void *u)
{
    (void)u;
    osc(t, x, dx, NULL);
}

static vi_ode_problem event_problem(gctx *c, int ng, double h_fixed, double rtol)
{
    vi_ode_problem p = {.n = 2, .ng = ng, .rhs = osc_u, .guards = guards, .user = c, .rtol = rtol,
                        .atol = {rtol, rtol}, .h_fixed = h_fixed};
    return p;
}

/* Step until an event or t_end (bounded); returns the status of the last step. */
static int until_event(vi_ode *s, vi_ode_problem *p, double t_end)
{
    for (int k = 0; k < 100000; k++) {
        int r = vi_ode_step(s, p, t_end);
        if (r != VI_ODE_OK || s->t >= t_end) return r;
    }
    cr_assert_fail("no end");
    return -1;
}

/* The event's bracket: a few ulps wide, guard > 0 at its left end and <= 0 at ev_t (dense output). */
static void check_bracket(vi_ode *s, vi_ode_problem *p, int guard)
{
    double x[2], g[VI_ODE_MAX_G];
    cr_assert(s->ev_t > s->t_old && s->ev_t <= s->t, "event inside the step");
    cr_assert(s->ev_t - s->ev_t_lo <= DBL_EPSILON * fabs(s->ev_t), "bracket %g wide at %g",
              s->ev_t - s->ev_t_lo, s->ev_t);
    cr_assert_eq(vi_ode_dense(s, p, s->ev_t_lo, x, NULL), VI_ODE_OK);
    p->guards(s->ev_t_lo, x, g, p->user);
    cr_assert(g[guard] > 0.0, "guard > 0 at the left end of the bracket");
    p->guards(s->ev_t, s->ev_x, g, p->user);
    cr_assert(g[guard] <= 0.0, "guard <= 0 at the event");
}

Test(events, oscillator_zero_crossings_at_pi_half_plus_2_pi_k)
{
    /* fixed steps of 0.05 (solution error ~1e-16): the event times to ~1e-16 relative; adaptive
     * steps at rtol 1e-9: to the solution's accuracy, the bracket on the interpolant still 1-2 ulps */
    struct {
        double h_fixed, rtol, tol;
    } runs[] = {{0.05, 1e-6, 2e-15}, {0.0, 1e-9, 1e-8}};
    for (int m = 0; m < 2; m++) {
        gctx c = {G_X, 0, INFINITY, -INFINITY};
        vi_ode_problem p = event_problem(&c, 1, runs[m].h_fixed, runs[m].rtol);
        vi_ode s;
        double x0[2] = {1.0, 0.0};
        cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
        for (int k = 0; k < 4; k++) {
            cr_assert_eq(until_event(&s, &p, 100.0), VI_ODE_EVENT);
            double exact = PI / 2 + 2 * PI * k;
            cr_log_info("event %d at %.17g, exact %.17g, rel. error %.2e", k, s.ev_t, exact, (s.ev_t - exact) / exact);
            cr_assert(fabs(s.ev_t - exact) <= runs[m].tol * exact, "event %d at %.17g, exact %.17g", k, s.ev_t, exact);
            cr_assert_eq(s.ev_fired, 1u);
            if (m == 0)
                cr_assert(fabs(s.ev_x[0]) <= 4 * DBL_EPSILON * exact && fabs(s.ev_x[1] + 1.0) < 1e-14, "x = %g",
                          s.ev_x[0]);
            check_bracket(&s, &p, 0);
            cr_assert_eq(vi_ode_step(&s, &p, 100.0), VI_ODE_ERR_ARGS, "no step past a pending event");
            /* the mode does not change: restart there, the guard that fired held until it moved away */
            cr_assert_eq(vi_ode_restart(&s, &p, s.ev_t, s.ev_x, 0.0, s.ev_fired), VI_ODE_OK);
        }
        cr_assert_eq(s.st.events, 4);
    }
}

Test(events, two_roots_inside_one_step_need_interior_samples)
{
    gctx c = {G_TWO_ROOTS, 0, INFINITY, -INFINITY};
    vi_ode_problem p = event_problem(&c, 1, 2.0, 1e-6); /* one step [0, 2], g > 0 at both ends */
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 2.0), VI_ODE_OK, "without samples the dip below zero is not seen");
    p.guard_samples = 3; /* samples at 0.5, 1, 1.5: g(1) < 0 */
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 2.0), VI_ODE_EVENT);
    cr_assert(fabs(s.ev_t - 0.9) <= 2 * DBL_EPSILON, "first root 0.9: %.17g", s.ev_t);
    cr_assert(c.t_min == 0.0 && c.t_max == 2.0, "guards evaluated inside the step only: [%g, %g]", c.t_min, c.t_max);
    check_bracket(&s, &p, 0);
    cr_assert_eq(s.st.dense_builds, 1, "dense output built once per step");
}

Test(events, first_guard_wins_and_ties_fire_together)
{
    gctx c = {G_MULTI, 0, INFINITY, -INFINITY};
    /* g0 = x, g1 = 2x (same root), g2 = x + 1/2, g3 = x - 1/5 on x = cos t */
    struct {
        double t;
        unsigned fired;
    } expect[] = {{acos(0.2), 8u}, {PI / 2, 3u}, {2 * PI / 3, 4u}, {2 * PI + acos(0.2), 8u}, {5 * PI / 2, 3u}};
    for (int fixed = 0; fixed < 2; fixed++) {
        vi_ode_problem p = event_problem(&c, 4, fixed ? 0.8 : 0.0, 1e-12); /* fixed: several roots in a step */
        vi_ode s;
        double x0[2] = {1.0, 0.0};
        cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
        for (int k = 0; k < 5; k++) {
            long iters = s.st.root_iters;
            cr_assert_eq(until_event(&s, &p, 100.0), VI_ODE_EVENT);
            /* smooth guards: the Illinois steps converge fast (a bisection alone needs ~50) */
            cr_assert(s.st.root_iters - iters <= 20, "event %d: %ld root iterations", k, s.st.root_iters - iters);
            cr_assert(fabs(s.ev_t - expect[k].t) < (fixed ? 1e-6 : 1e-10), "event %d at %.15g, expected %.15g", k,
                      s.ev_t, expect[k].t);
            cr_assert_eq(s.ev_fired, expect[k].fired, "event %d: fired %#x, expected %#x", k, s.ev_fired,
                         expect[k].fired);
            for (int i = 0; i < 4; i++)
                if (s.ev_fired & (1u << i)) check_bracket(&s, &p, i);
            cr_assert_eq(vi_ode_restart(&s, &p, s.ev_t, s.ev_x, 0.0, s.ev_fired), VI_ODE_OK);
        }
    }
}

Test(events, guard_zero_at_start_fires_only_after_being_positive)
{
    gctx c = {G_X, 0, INFINITY, -INFINITY};
    vi_ode_problem p = event_problem(&c, 1, 0.0, 1e-12);
    vi_ode s;
    double up[2] = {0.0, 1.0}, down[2] = {0.0, -1.0}; /* x = sin t, x = -sin t: g = 0 at the start */
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, up, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(s.armed, 0u, "g = 0 does not arm");
    cr_assert_eq(until_event(&s, &p, 100.0), VI_ODE_EVENT);
    cr_assert(fabs(s.ev_t - PI) < 1e-10, "sin t falls through 0 at pi: %.17g", s.ev_t);
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, down, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(until_event(&s, &p, 100.0), VI_ODE_EVENT);
    cr_assert(fabs(s.ev_t - 2 * PI) < 1e-10, "-sin t falls through 0 at 2 pi: %.17g", s.ev_t);
}

Test(events, hold_keeps_a_guard_sitting_at_zero_from_firing_again)
{
    gctx c = {G_X, 0, INFINITY, -INFINITY};
    vi_ode_problem p = event_problem(&c, 1, 0.0, 1e-12);
    vi_ode s;
    double x0[2] = {1e-20, -1.0}; /* g barely positive, moving down */
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(until_event(&s, &p, 100.0), VI_ODE_EVENT);
    cr_assert(s.ev_t < 1e-15, "an armed guard fires at once: %g", s.ev_t);
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 1u), VI_ODE_OK);
    cr_assert_eq(until_event(&s, &p, 100.0), VI_ODE_EVENT);
    cr_assert(fabs(s.ev_t - 2 * PI) < 1e-9, "held: fires after it rose above 0 and fell back, %.17g", s.ev_t);
    /* arm_eps: a guard arms only above its threshold */
    double low[2] = {0.3, 0.0};
    p.arm_eps[0] = 0.5;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, low, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(until_event(&s, &p, 20.0), VI_ODE_OK, "0.3 cos t never exceeds 0.5: never armed");
    p.arm_eps[0] = 0.2;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, low, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(until_event(&s, &p, 20.0), VI_ODE_EVENT);
    cr_assert(fabs(s.ev_t - PI / 2) < 1e-9);
}

Test(events, root_search_is_bounded_and_exact_for_hard_guards)
{
    int kinds[] = {G_JUMP, G_FLAT, G_TINY};
    double taus[] = {0.7, 0.3, 0.123456789};
    for (int k = 0; k < 3; k++) {
        for (int j = 0; j < 3; j++) {
            gctx c = {kinds[k], taus[j], INFINITY, -INFINITY};
            vi_ode_problem p = event_problem(&c, 1, 1.0, 1e-6); /* one step [0, 1] */
            vi_ode s;
            double x0[2] = {1.0, 0.0};
            cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
            cr_assert_eq(vi_ode_step(&s, &p, 1.0), VI_ODE_EVENT, "kind %d tau %g", kinds[k], taus[j]);
            cr_log_info("kind %d tau %.9g: %ld iterations, error %.2e", kinds[k], taus[j], s.st.root_iters,
                        s.ev_t - taus[j]);
            cr_assert(s.ev_t >= taus[j] && s.ev_t - taus[j] <= DBL_EPSILON * taus[j], "kind %d: %.17g vs %.17g",
                      kinds[k], s.ev_t, taus[j]);
            cr_assert(s.st.root_iters <= 3 * 53, "kind %d: %ld iterations", kinds[k], s.st.root_iters);
        }
    }
}

/* A root the bracket cannot close on within VI_ODE_MAX_ROOT_ITERS guard evaluations: a jump from
 * 1e300 to -1e-300 (the linear estimate lands beside the right end, so only the bisection of every
 * third evaluation halves the bracket) at t = 1e-250 in the step [0, 1], about 880 halvings from eps of
 * it. The step fails with VI_ODE_ERR_ROOT after exactly that many evaluations and leaves the state as
 * it was; the same jump at 0.3 is found within eps. */
Test(events, root_search_gives_up_after_its_bound)
{
    gctx c = {G_LOPSIDED, 1e-250, INFINITY, -INFINITY};
    vi_ode_problem p = event_problem(&c, 1, 1.0, 1e-6); /* one step [0, 1] */
    vi_ode s, before;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    before = s;
    cr_assert_eq(vi_ode_step(&s, &p, 1.0), VI_ODE_ERR_ROOT);
    cr_assert(s.st.root_iters == VI_ODE_MAX_ROOT_ITERS, "%ld guard evaluations", s.st.root_iters);
    s.st = before.st;
    s.sp[1 - s.cur] = before.sp[1 - before.cur];
    cr_assert(memcmp(&s, &before, sizeof s) == 0, "state unchanged by a failed step");
    c.tau = 0.3;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 1.0), VI_ODE_EVENT);
    cr_assert(s.ev_t >= 0.3 && s.ev_t - 0.3 <= DBL_EPSILON * 0.3 && s.st.root_iters <= 3 * 53, "%.17g after %ld",
              s.ev_t, s.st.root_iters);
}

/* The root search stops at the first bracket no wider than eps max(|a|, |b|), the bound included: a
 * jump one ulp below 1 is bracketed by [1 - 2^-52, 1], exactly eps wide, and the event is at 1 (within
 * 2 ulps, as vi_ode.h says), not searched to the ulp below. */
Test(events, root_search_stops_at_a_bracket_of_exactly_its_tolerance)
{
    gctx c = {G_JUMP, 1.0 - 0x1p-53, INFINITY, -INFINITY};
    vi_ode_problem p = event_problem(&c, 1, 2.0, 1e-6); /* one step [0, 2] */
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 2.0), VI_ODE_EVENT);
    cr_assert(s.ev_t == 1.0 && s.ev_t_lo == 1.0 - 0x1p-52, "[%.17g, %.17g]", s.ev_t_lo, s.ev_t);
}

/* A proposed step shorter than 16 ulps of t (t + h might round to t) is raised to 16 eps |t|: from
 * t = 1.03 with a first step of 1e-20 s, the step ends at 1.03 + 16 eps 1.03 (16.48 ulps of 1.03,
 * rounded to 16). */
Test(state, a_step_under_16_ulps_of_t_is_raised_to_16_eps_t)
{
    gctx c = {G_X, 0.0, INFINITY, -INFINITY};
    vi_ode_problem p = event_problem(&c, 0, 0.0, 1e-6);
    vi_ode s;
    double x0[2] = {1.0, 0.0}, t0 = 1.03;
    cr_assert_eq(vi_ode_init(&s, &p, t0, x0, 1e-20, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 2.0), VI_ODE_OK);
    cr_assert(s.t == t0 + 16.0 * DBL_EPSILON * t0, "t = t0 + %.17g eps t0", (s.t - t0) / (DBL_EPSILON * t0));
}

Test(events, nonfinite_guard_fails_and_leaves_the_state)
{
    gctx c = {G_NAN, 0.7, INFINITY, -INFINITY};
    vi_ode_problem p = event_problem(&c, 1, 0.25, 1e-6);
    vi_ode s, before;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 10.0), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 10.0), VI_ODE_OK);
    before = s;
    cr_assert_eq(vi_ode_step(&s, &p, 10.0), VI_ODE_ERR_NONFINITE, "the root search meets NaN near 0.7");
    s.st = before.st;                          /* the statistics count the work */
    s.sp[1 - s.cur] = before.sp[1 - before.cur]; /* the scratch half holds the failed attempt */
    cr_assert(memcmp(&s, &before, sizeof s) == 0, "state unchanged by a failed step");
}

/* With h_fixed the proposed size s.h is h_fixed after every step (the error control is off, even where
 * it would propose a longer step: here 100 steps of 1e-4 on a problem solved to 1e-6) */
Test(order, a_fixed_step_proposes_its_own_size)
{
    problem pr = PROBLEMS[0];
    vi_ode_problem p = make(&pr, 1e-6, 1e-6);
    p.h_fixed = 1e-4;
    vi_ode s;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 0.0, 0u), VI_ODE_OK);
    cr_assert(s.h == p.h_fixed, "first proposal %g", s.h);
    for (int k = 0; k < 100; k++) {
        cr_assert_eq(vi_ode_step(&s, &p, pr.T), VI_ODE_OK);
        cr_assert(s.h == p.h_fixed, "step %d: proposal %g", k, s.h);
    }
}

Test(order, time_does_not_drift_over_many_steps)
{
    /* 10^4 fixed steps: t + h is rounded each step; the step must span exactly [t, fl(t + h)] or the
     * solution drifts in phase by ~1e4 roundings of t (~3e-11 here) */
    problem pr = PROBLEMS[0];
    pr.T = 100.0;
    vi_ode_problem p = make(&pr, 1e-6, 1e-6);
    p.h_fixed = 0.01;
    vi_ode s;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 0.0, 0u), VI_ODE_OK);
    for (long k = 0; s.t < pr.T; k++) {
        cr_assert(k < 20000);
        cr_assert_eq(vi_ode_step(&s, &p, pr.T), VI_ODE_OK);
    }
    double xe[2];
    pr.exact(pr.T, pr.x0, xe);
    cr_log_info("error after 10^4 steps: %.2e", max_err(s.x, xe, 2));
    cr_assert(max_err(s.x, xe, 2) < 2e-12, "error %g after 10^4 steps", max_err(s.x, xe, 2));
}

/* ---------------------------------------------------------------------------------------------
 * Plain-data state, limits, failures, accounting
 * ------------------------------------------------------------------------------------------- */

/* Drive a forced oscillator with guards through steps, events and restarts (`dense`: also query
 * the dense output between steps). Returns the number of events. */
static int drive(vi_ode *s, vi_ode_problem *p, int steps, int dense)
{
    int events = 0;
    for (int k = 0; k < steps; k++) {
        int r = vi_ode_step(s, p, 1e3);
        cr_assert(r >= 0, "%s", vi_ode_status_text(r));
        if (dense) {
            double x[2], dx[2];
            cr_assert_eq(vi_ode_dense(s, p, s->t_old + 0.37 * (s->t - s->t_old), x, dx), VI_ODE_OK);
        }
        if (r == VI_ODE_EVENT) {
            double x[2] = {s->ev_x[0], -0.9 * s->ev_x[1]}; /* a jump at the event */
            cr_assert_eq(vi_ode_restart(s, p, s->ev_t, x, 0.0, s->ev_fired), VI_ODE_OK);
            events++;
        }
    }
    return events;
}

static void forced_u(double t, const double *x, double *dx, void *u)
{
    (void)u;
    forced(t, x, dx, NULL);
}

Test(state, copy_continues_bit_for_bit_and_dense_requests_do_not_matter)
{
    gctx c = {G_MULTI, 0, INFINITY, -INFINITY};
    vi_ode_problem p = {.n = 2, .ng = 4, .rhs = forced_u, .guards = guards, .user = &c, .rtol = 1e-9,
                        .atol = {1e-12, 1e-12}, .guard_samples = 2};
    vi_ode a, b, d;
    double x0[2] = {0.5, 0.0};
    cr_assert_eq(vi_ode_init(&a, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert(drive(&a, &p, 40, 0) > 0);
    memcpy(&b, &a, sizeof a);
    memcpy(&d, &a, sizeof a);
    int ea = drive(&a, &p, 200, 0), eb = drive(&b, &p, 200, 0), ed = drive(&d, &p, 200, 1);
    cr_assert(ea > 3 && ea == eb && ea == ed, "events %d %d %d", ea, eb, ed);
    cr_assert(memcmp(&a, &b, sizeof a) == 0, "a byte copy continues identically");
    /* with dense requests only the statistics differ (guard_samples > 0: dense is built anyway) */
    cr_assert(a.t == d.t && a.h == d.h && memcmp(a.x, d.x, sizeof a.x) == 0 && memcmp(a.sp, d.sp, sizeof a.sp) == 0);
    p.guard_samples = 0; /* now dense output is built on demand only */
    cr_assert_eq(vi_ode_init(&a, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    memcpy(&d, &a, sizeof a);
    drive(&a, &p, 200, 0);
    drive(&d, &p, 200, 1);
    cr_assert(d.st.dense_builds > a.st.dense_builds);
    cr_assert(a.t == d.t && a.h == d.h && memcmp(a.x, d.x, sizeof a.x) == 0 && memcmp(a.g, d.g, sizeof a.g) == 0);
}

Test(state, max_step_and_t_stop_are_respected)
{
    problem pr = PROBLEMS[0];
    vi_ode_problem p = make(&pr, 1e-6, 1e-6);
    p.max_step = 0.01;
    vi_ode s;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 0.0, 0u), VI_ODE_OK);
    cr_assert(s.h <= 0.01);
    double t_stop = 1.0 / 3.0;
    long k;
    for (k = 0; s.t < t_stop; k++) {
        cr_assert(k < 1000);
        cr_assert_eq(vi_ode_step(&s, &p, t_stop), VI_ODE_OK);
        cr_assert(s.t - s.t_old <= 0.01, "step %g > max_step", s.t - s.t_old);
        cr_assert(s.t <= t_stop);
    }
    cr_assert(s.t == t_stop, "t_stop reached exactly");
    cr_assert(k >= 34 && k <= 35, "%ld steps of at most 0.01 over 1/3", k);
    cr_assert_eq(vi_ode_step(&s, &p, t_stop), VI_ODE_ERR_ARGS, "t_stop must lie ahead");
    p.max_step = 1e-4; /* a small max_step */
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 1.0), VI_ODE_OK);
    cr_assert(s.t == 1e-4 && s.h == 1e-4, "t = %g, proposal %g", s.t, s.h);
    /* a large step stops at t_stop too */
    p.max_step = 0.0;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 1e-9), VI_ODE_OK);
    cr_assert(s.t == 1e-9);
}

static void blowup(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = x[0] * x[0]; /* x = 1/(1 - t) */
}

static void nan_after(double t, const double *x, double *dx, void *u)
{
    (void)u;
    dx[0] = t > 0.5 ? NAN : -x[0];
}

static void stiff(double t, const double *x, double *dx, void *u)
{
    (void)u;
    dx[0] = -1e6 * (x[0] - cos(t));
}

Test(failures, reported_never_a_hang_and_the_state_is_kept)
{
    vi_ode_problem p = {.n = 1, .rhs = blowup, .rtol = 1e-8, .atol = {1e-8}};
    vi_ode s, before;
    double x0[1] = {1.0};
    int r = VI_ODE_OK;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    for (int k = 0; k < 100000 && r == VI_ODE_OK; k++) {
        before = s;
        r = vi_ode_step(&s, &p, 2.0);
    }
    cr_assert(r == VI_ODE_ERR_HMIN || r == VI_ODE_ERR_NONFINITE, "blow-up at t = 1: %s", vi_ode_status_text(r));
    /* the numerical solution's own singularity lies within about rtol of t = 1 */
    cr_assert(fabs(s.t - 1.0) < 1e-6 && s.x[0] > 1e6, "stopped at the singularity: t = %.17g, x = %g", s.t, s.x[0]);
    s.st = before.st;
    s.sp[1 - s.cur] = before.sp[1 - before.cur];
    cr_assert(memcmp(&s, &before, sizeof s) == 0, "state unchanged by the failed step");

    p.rhs = nan_after;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    r = VI_ODE_OK;
    for (int k = 0; k < 100000 && r == VI_ODE_OK; k++) r = vi_ode_step(&s, &p, 2.0);
    cr_assert_eq(r, VI_ODE_ERR_NONFINITE, "%s", vi_ode_status_text(r));
    cr_assert(s.t <= 0.5 && s.t > 0.49, "t = %g", s.t);
    cr_assert(s.st.rejected <= VI_ODE_MAX_REJECTS);

    p.rhs = stiff; /* needs h ~ 3e-6: below h_min */
    p.h_min = 1e-3;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 1e-2, 0u), VI_ODE_OK);
    r = VI_ODE_OK;
    for (int k = 0; k < 100000 && r == VI_ODE_OK; k++) r = vi_ode_step(&s, &p, 2.0);
    cr_assert_eq(r, VI_ODE_ERR_HMIN, "%s", vi_ode_status_text(r));

    /* a fixed step that meets NaN fails at once */
    p.rhs = nan_after;
    p.h_min = 0.0;
    p.h_fixed = 0.3;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 2.0), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 2.0), VI_ODE_ERR_NONFINITE);
    cr_assert(s.t == 0.3);
    /* not finite at the start: refused, and the state is left as it was (a continuation that an FMU
     * state may still copy), by a restart too */
    vi_ode kept = s;
    cr_assert_eq(vi_ode_init(&s, &p, 0.7, x0, 0.0, 0u), VI_ODE_ERR_NONFINITE);
    cr_assert(memcmp(&s, &kept, sizeof s) == 0, "a failed vi_ode_init changed the state");
    cr_assert_eq(vi_ode_restart(&s, &p, 0.7, x0, 0.0, 0u), VI_ODE_ERR_NONFINITE);
    cr_assert(memcmp(&s, &kept, sizeof s) == 0, "a failed vi_ode_restart changed the state");
}

/* A derivative too large for the tolerances' scale: Hairer's estimate of the first step comes out
 * 0 (the norm of f overflows), which was kept as the continuation's step size (a state no step or
 * FMU state check accepts). */
static void huge_after(double t, const double *x, double *dx, void *u)
{
    (void)x, (void)u;
    dx[0] = t >= 1.0 ? 1.7e305 : -1.0;
}

Test(failures, a_first_step_that_comes_out_zero_is_refused_and_the_state_is_kept)
{
    vi_ode_problem p = {.n = 1, .rhs = huge_after, .rtol = 1e-8, .atol = {1e-12}};
    double x0[1] = {1.0};
    vi_ode s;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 0.5), VI_ODE_OK);
    vi_ode kept = s;
    cr_assert_eq(vi_ode_restart(&s, &p, 1.0, x0, 0.0, 0u), VI_ODE_ERR_HMIN);
    cr_assert(memcmp(&s, &kept, sizeof s) == 0, "a failed vi_ode_restart changed the state");
    cr_assert(s.h > 0.0);
}

Test(failures, invalid_problems_and_calls)
{
    char msg[128];
    vi_ode_problem ok = {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}};
    cr_assert_eq(vi_ode_check(&ok, msg, sizeof msg), VI_ODE_OK);
    struct {
        const char *field;
        vi_ode_problem p;
    } bad[] = {
        {"n", {.n = 0, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6}}},
        {"n", {.n = VI_ODE_MAX_N + 1, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6, 1e-6, 1e-6}}},
        {"rhs", {.n = 2, .rtol = 1e-6, .atol = {1e-6, 1e-6}}},
        {"guards", {.n = 2, .ng = 1, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}}},
        {"ng", {.n = 2, .ng = VI_ODE_MAX_G + 1, .rhs = osc_u, .guards = guards, .rtol = 1e-6, .atol = {1e-6, 1e-6}}},
        {"rtol", {.n = 2, .rhs = osc_u, .rtol = 0.0, .atol = {1e-6, 1e-6}}},
        {"rtol", {.n = 2, .rhs = osc_u, .rtol = NAN, .atol = {1e-6, 1e-6}}},
        {"rtol", {.n = 2, .rhs = osc_u, .rtol = 1.0, .atol = {1e-6, 1e-6}}},
        {"atol", {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 0.0}}},
        {"max_step", {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}, .max_step = -1}},
        {"h_min", {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}, .h_min = INFINITY}},
        {"h_fixed", {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}, .h_fixed = -1}},
        {"guard_samples",
         {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}, .guard_samples = VI_ODE_MAX_SAMPLES + 1}},
        {"arm_eps", {.n = 2, .ng = 1, .rhs = osc_u, .guards = guards, .rtol = 1e-6, .atol = {1e-6, 1e-6}, .arm_eps = {-1}}},
        {"h_rho_max", {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}, .h_rho_max = -1}},
        {"spectral_radius", {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}, .h_rho_max = 5}},
    };
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        msg[0] = 0;
        cr_assert_eq(vi_ode_check(&bad[i].p, msg, sizeof msg), VI_ODE_ERR_ARGS, "%s", bad[i].field);
        cr_assert(strstr(msg, bad[i].field) == msg, "message names %s: %s", bad[i].field, msg);
        cr_assert_eq(vi_ode_init(&s, &bad[i].p, 0.0, x0, 0.0, 0u), VI_ODE_ERR_ARGS);
    }
    double xnan[2] = {NAN, 0.0};
    cr_assert_eq(vi_ode_init(&s, &ok, 0.0, xnan, 0.0, 0u), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_init(&s, &ok, INFINITY, x0, 0.0, 0u), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_init(&s, &ok, 0.0, x0, -1.0, 0u), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_init(&s, &ok, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    double x[2];
    cr_assert_eq(vi_ode_dense(&s, &ok, 0.0, x, NULL), VI_ODE_ERR_ARGS, "no step yet");
    cr_assert_eq(vi_ode_step(&s, &ok, NAN), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_step(&s, &ok, 1.0), VI_ODE_OK);
    cr_assert_eq(vi_ode_dense(&s, &ok, s.t * (1 + 1e-15), x, NULL), VI_ODE_ERR_ARGS, "beyond the step");
    cr_assert_eq(vi_ode_dense(&s, &ok, -1e-300, x, NULL), VI_ODE_ERR_ARGS, "before the step");
    vi_ode_problem other = ok;
    other.n = 1;
    cr_assert_eq(vi_ode_step(&s, &other, 1.0), VI_ODE_ERR_ARGS, "state made for another problem");
    gctx c = {G_X, 0, INFINITY, -INFINITY};
    other = ok;
    other.ng = 1, other.guards = guards, other.user = &c;
    cr_assert_eq(vi_ode_step(&s, &other, 1.0), VI_ODE_ERR_ARGS, "state made for another number of guards");
    for (int st = -6; st <= 2; st++) cr_assert(vi_ode_status_text(st) != NULL);
    cr_assert(strcmp(vi_ode_status_text(VI_ODE_ERR_HMIN), vi_ode_status_text(VI_ODE_ERR_ROOT)) != 0);
}

static long rhs_calls;
static void counted(double t, const double *x, double *dx, void *u)
{
    (void)u;
    rhs_calls++;
    osc(t, x, dx, NULL);
}

Test(state, statistics_count_the_work)
{
    vi_ode_problem p = {.n = 2, .rhs = counted, .rtol = 1e-10, .atol = {1e-10, 1e-10}};
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    rhs_calls = 0;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(s.st.rhs_evals, 2, "f(t0) and the first-step estimate");
    for (int k = 0; k < 50; k++) cr_assert_eq(vi_ode_step(&s, &p, 1e3), VI_ODE_OK);
    cr_assert_eq(s.st.attempts, s.st.accepted + s.st.rejected);
    cr_assert_eq(s.st.accepted, 50);
    cr_assert_eq(s.st.rhs_evals, 2 + 12 * s.st.accepted + 11 * s.st.rejected, "12 per step, 11 per rejection");
    double x[2];
    cr_assert_eq(vi_ode_dense(&s, &p, s.t_old, x, NULL), VI_ODE_OK);
    cr_assert_eq(vi_ode_dense(&s, &p, s.t, x, NULL), VI_ODE_OK);
    cr_assert_eq(s.st.dense_builds, 1);
    cr_assert_eq(s.st.rhs_evals, 2 + 12 * s.st.accepted + 11 * s.st.rejected + 3, "3 for the dense output, once");
    cr_assert_eq(s.st.rhs_evals, rhs_calls);
    vi_ode_stats before = s.st;
    cr_assert_eq(vi_ode_restart(&s, &p, s.t, s.x, s.h, 0u), VI_ODE_OK);
    cr_assert(s.st.attempts == before.attempts && s.st.accepted == before.accepted &&
              s.st.rejected == before.rejected && s.st.guard_evals == before.guard_evals &&
              s.st.dense_builds == before.dense_builds && s.st.root_iters == before.root_iters &&
              s.st.events == before.events, "restart keeps the statistics");
    cr_assert_eq(s.st.rhs_evals, before.rhs_evals + 1, "h0 given: f(t0) only");
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.5, 0u), VI_ODE_OK);
    cr_assert(s.st.accepted == 0 && s.h == 0.5, "init clears the statistics; h0 used");
}

/* A contact beginning at t = 0: x0 the indentation, x1 its rate, x1' = -x0^(3/2) (Hertz, unit
 * constants). The solution carries t^(7/2) and t^(5/2) terms, so the first step's error falls like
 * h^(5/2), not h^8: after two rejected attempts the step size follows the order the two errors show,
 * h (0.25/err)^(1/q), and the first step is accepted after at most 4 rejected attempts; the rule of
 * h^8 (0.9 err^(-1/8), at least 0.2 h, as for a smooth solution) needs 7 from the same start. */
static void onset_rhs(double t, const double *x, double *dx, void *user)
{
    (void)t, (void)user;
    double d = x[0] > 0.0 ? x[0] : 0.0;
    dx[0] = x[1];
    dx[1] = -d * sqrt(d);
}

Test(state, a_rejection_at_a_start_that_is_not_smooth_follows_the_order_of_the_errors)
{
    vi_ode_problem p = {.n = 2, .rhs = onset_rhs, .rtol = 1e-10, .atol = {1e-12, 1e-12}};
    vi_ode s;
    double x0[2] = {0.0, 1.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 1.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 10.0), VI_ODE_OK);
    cr_log_info("first step %g after %d rejected attempts", s.t, s.rejected_last);
    cr_assert(s.rejected_last >= 2 && s.rejected_last <= 4, "%d rejected attempts", s.rejected_last);
    /* the accepted step is within the tolerance: x1(t) = 1 - (2/5) t^(5/2) + (6/175) t^5 + O(t^(15/2)) */
    double t = s.t, exact = 1.0 - 0.4 * pow(t, 2.5) + 6.0 / 175.0 * pow(t, 5.0);
    cr_assert(fabs(s.x[1] - exact) <= 1e-12 + 1e-10 + pow(t, 7.5), "x1 %.17g against %.17g at t %g", s.x[1], exact, t);
}

Test(state, a_rejected_attempt_costs_eleven_evaluations)
{
    /* A first step of 0.5 given at rtol 1e-10 is rejected (and then some): f(t0) at the start, 12
     * evaluations per accepted step, 11 per rejected attempt (f at its end is not evaluated). */
    vi_ode_problem p = {.n = 2, .rhs = counted, .rtol = 1e-10, .atol = {1e-10, 1e-10}};
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    rhs_calls = 0;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.5, 0u), VI_ODE_OK);
    for (int k = 0; k < 10; k++) cr_assert_eq(vi_ode_step(&s, &p, 1e3), VI_ODE_OK);
    cr_assert(s.st.rejected > 0 && s.st.accepted == 10, "rejected %ld", s.st.rejected);
    cr_assert_eq(s.st.rhs_evals, 1 + 12 * s.st.accepted + 11 * s.st.rejected);
    cr_assert_eq(s.st.rhs_evals, rhs_calls);
}

Test(events, root_at_the_step_end_and_bracket_never_moved_right)
{
    /* g = 1 before tau, -1 from tau on, tau = the step end: every probe lands left of the root */
    gctx c = {G_JUMP, 1.0, INFINITY, -INFINITY};
    vi_ode_problem p = event_problem(&c, 1, 1.0, 1e-6);
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 5.0), VI_ODE_EVENT);
    cr_assert(s.ev_t == 1.0 && s.ev_fired == 1u, "at the step end: %.17g, fired %#x", s.ev_t, s.ev_fired);
    cr_assert(memcmp(s.ev_x, s.x, sizeof(double) * 2) == 0, "the state at the step end, exactly");
    cr_assert(s.ev_t_lo < 1.0 && s.ev_t - s.ev_t_lo <= DBL_EPSILON);
}

Test(state, initial_step_is_hairers_estimate)
{
    /* HNW I, II.4: d0 = ||x0||, d1 = ||f0||, h0 = 0.01 d0/d1 (1e-6 if either < 1e-5),
     * d2 = ||f(t0 + h0, x0 + h0 f0) - f0|| / h0, h1 = (0.01 / max(d1, d2))^(1/8)
     * (max(1e-6, 1e-3 h0) if that max <= 1e-15), h = min(100 h0, h1); norms RMS with
     * sc = atol + rtol |x0|. Oscillator x0 = (1, 0), rtol = atol = 1e-6: sc = (2e-6, 1e-6),
     * d0 = 1/(2e-6 sqrt 2), f0 = (0, -1): d1 = 1/(1e-6 sqrt 2), h0 = 0.005; f1 = (-0.005, -1):
     * d2 = 1/(2e-6 sqrt 2); h1 = (0.01 1e-6 sqrt 2)^(1/8). */
    vi_ode_problem p = {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}};
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    double h1 = pow(0.01 * 1e-6 * sqrt(2.0), 1.0 / 8.0);
    cr_assert(fabs(s.h - fmin(0.5, h1)) < 1e-12 * h1, "h = %.17g, expected %.17g", s.h, h1);
    /* f = 0: d1 = d2 = 0, so h0 = 1e-6 and h1 = max(1e-6, 1e-9) */
    problem zero = PROBLEMS[0];
    vi_ode_problem pz = make(&zero, 1e-6, 1e-6);
    pz.rhs = blowup; /* x' = x^2 at x = 0: f = 0 */
    double z[2] = {0.0, 0.0};
    pz.n = 1;
    cr_assert_eq(vi_ode_init(&s, &pz, 0.0, z, 0.0, 0u), VI_ODE_OK);
    cr_assert(s.h == 1e-6, "h = %g", s.h);
    /* limited by max_step; a given h0 is used */
    p.max_step = 0.01;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert(s.h == 0.01);
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.003, 0u), VI_ODE_OK);
    cr_assert(s.h == 0.003);
    /* however small: a given h0, and max_step over the estimate and over a given h0 */
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 1e-4, 0u), VI_ODE_OK);
    cr_assert(s.h == 1e-4, "h = %g", s.h);
    p.max_step = 1e-5;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert(s.h == 1e-5, "h = %g", s.h);
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.003, 0u), VI_ODE_OK);
    cr_assert(s.h == 1e-5, "h = %g", s.h);
}

static void decay(double t, const double *x, double *dx, void *u)
{
    (void)t;
    dx[0] = -*(const double *)u * x[0];
}

Test(state, initial_step_on_both_sides_of_the_1e_minus_5_thresholds)
{
    /* x' = -k x, atol = 1, rtol = 1e-10 (sc = 1 + 1e-10 x0): d0 = x0/sc, d1 = k d0. HNW II.4: h0 = 1e-6
     * when d0 or d1 < 1e-5, else 0.01 d0/d1; d2 = k d1 (linear), h = min(100 h0, h1). Each threshold
     * from just above and just below, the other norm far from its own. */
    double cases[][2] = {{1.005e-5, 1000.0}, {0.995e-5, 1000.0}, {1.0, 1.005e-5}, {1.0, 0.995e-5}};
    for (int i = 0; i < 4; i++) {
        double y0 = cases[i][0], k = cases[i][1];
        vi_ode_problem p = {.n = 1, .rhs = decay, .user = &k, .rtol = 1e-10, .atol = {1.0}};
        double sc = 1.0 + 1e-10 * y0, d0 = y0 / sc, d1 = k * d0;
        double h0 = d0 < 1e-5 || d1 < 1e-5 ? 1e-6 : 0.01 * d0 / d1;
        double expect = fmin(100.0 * h0, pow(0.01 / fmax(d1, k * d1), 1.0 / 8.0));
        cr_assert((h0 == 1e-6) == (i % 2 == 1)); /* the cases are what they say */
        vi_ode s;
        double x0[1] = {y0};
        cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
        cr_assert(fabs(s.h - expect) <= 1e-9 * expect, "case %d: h = %.17g, expected %.17g", i, s.h, expect);
    }
}

static void decay_then_nan(double t, const double *x, double *dx, void *u)
{
    dx[0] = t == 0.0 ? -*(const double *)u * x[0] : NAN;
}

Test(state, initial_step_is_h0_when_f_at_the_trial_point_is_not_finite)
{
    /* HNW II.4's difference quotient needs f(t0 + h0, x0 + h0 f0); when that is not finite the
     * estimate stops at h0 = 0.01 d0/d1 (x' = -1000 x from 1, atol 1, rtol 1e-10: h0 = 1e-5; the
     * full estimate with d2 ignored would be min(100 h0, (0.01/d1)^(1/8)) = 1e-3). */
    double k = 1000.0;
    vi_ode_problem p = {.n = 1, .rhs = decay_then_nan, .user = &k, .rtol = 1e-10, .atol = {1.0}};
    vi_ode s;
    double x0[1] = {1.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    double sc = 1.0 + 1e-10, d0 = 1.0 / sc, d1 = k * d0;
    cr_assert(fabs(s.h - 0.01 * d0 / d1) <= 1e-15, "h = %.17g", s.h);
    cr_assert(s.st.rhs_evals == 2);
}

static void one_until_half(double t, const double *x, double *dx, void *u)
{
    (void)x, (void)u;
    dx[0] = t < 0.5 ? 1.0 : NAN;
}

Test(state, initial_step_trial_point_is_within_max_step)
{
    /* x' = 1 from 100, atol = rtol = 1e-14 (sc = 1.01e-12): d0 = 100/sc, d1 = 1/sc, so h0 = 0.01 d0/d1
     * = 1, limited to max_step = 0.1 before f is tried at t0 + h0 (finite there; NaN from 0.5 on):
     * d2 = 0, h = min(100 h0, (0.01/d1)^(1/8)) = (0.01 sc)^(1/8) = 0.0178, under max_step. */
    vi_ode_problem p = {.n = 1, .rhs = one_until_half, .rtol = 1e-14, .atol = {1e-14}, .max_step = 0.1};
    vi_ode s;
    double x0[1] = {100.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    double sc = 1e-14 + 1e-14 * 100.0, expect = pow(0.01 * sc, 1.0 / 8.0);
    cr_assert(fabs(s.h - expect) <= 1e-12 * expect, "h = %.17g, expected %.17g", s.h, expect);
}

static void constant_rate(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)x;
    dx[0] = *(const double *)u;
}

Test(state, initial_step_on_both_sides_of_the_1e_minus_15_threshold)
{
    /* x' = c from 0, atol 1, rtol 1e-10 (sc = 1): d0 = 0, so h0 = 1e-6; dm = max(d1, d2) = c (f is
     * constant: d2 = 0). Above 1e-15, h1 = (0.01/c)^(1/8) (about 42) and h = 100 h0 = 1e-4; at or
     * below it, h1 = max(1e-6, 1e-3 h0) = 1e-6. */
    const double cs[] = {1.005e-15, 1e-15, 0.995e-15};
    const double want[] = {1e-4, 1e-6, 1e-6};
    for (int i = 0; i < 3; i++) {
        double c = cs[i];
        vi_ode_problem p = {.n = 1, .rhs = constant_rate, .user = &c, .rtol = 1e-10, .atol = {1.0}};
        vi_ode s;
        double x0[1] = {0.0};
        cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
        cr_assert(fabs(s.h - want[i]) <= 1e-15 * want[i], "c = %g: h = %.17g", c, s.h);
    }
}

static void decay_one(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = -x[0];
}

Test(state, an_attempt_with_an_error_just_above_one_is_rejected)
{
    /* The error estimate of a step of size h from x = 1 of x' = -x, measured with fixed steps (which
     * are accepted whatever their error and report it), is bisected to h with err in (1.002, 1.008);
     * an adaptive step tried with that h is rejected and costs 11 evaluations. */
    vi_ode_problem fx = {.n = 1, .rhs = decay_one, .rtol = 1e-6, .atol = {1e-6}, .h_fixed = 0.1};
    vi_ode s;
    double x0[1] = {1.0}, lo = 0.01, hi = 2.0, h = 0.0, err = 0.0;
    for (int k = 0; k < 200; k++) {
        h = 0.5 * (lo + hi);
        fx.h_fixed = h;
        cr_assert_eq(vi_ode_init(&s, &fx, 0.0, x0, 0.0, 0u), VI_ODE_OK);
        cr_assert_eq(vi_ode_step(&s, &fx, INFINITY), VI_ODE_OK);
        err = s.err;
        if (err > 1.002 && err < 1.008) break;
        if (err <= 1.002) lo = h;
        else hi = h;
    }
    cr_assert(err > 1.002 && err < 1.008, "err %.17g at h %.17g", err, h);
    vi_ode_problem p = fx;
    p.h_fixed = 0.0;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, h, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_OK);
    cr_assert(s.st.rejected == 1 && s.t < h && s.err <= 1.0, "rejected %ld, t %.17g of %.17g", s.st.rejected, s.t, h);
    cr_assert(s.st.rhs_evals == 1 + 11 + 12 && s.f[0] == -s.x[0], "%ld evaluations", s.st.rhs_evals);
}

static void rate_one(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)x, (void)u;
    dx[0] = 1.0;
}

Test(failures, a_state_whose_proposed_step_is_zero_is_refused)
{
    /* h = 0 is not a state vi_ode leaves: vi_ode_step refuses it as an invalid call (not as a step
     * size underflow, which the step loop would report). */
    vi_ode_problem p = {.n = 1, .rhs = rate_one, .rtol = 1e-8, .atol = {1e-9}};
    vi_ode s;
    double x0[1] = {0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    s.h = 0.0;
    cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_ERR_ARGS);
    s.h = -1.0;
    cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_ERR_ARGS);
}

/* A refusal with no message buffer (NULL, of any size, or a size of 0) writes nothing. */
Test(failures, a_refusal_without_a_message_buffer_writes_nothing)
{
    vi_ode_problem p = {.n = 0, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6}};
    cr_assert_eq(vi_ode_check(&p, NULL, 100), VI_ODE_ERR_ARGS);
    char msg[8] = "unset";
    cr_assert_eq(vi_ode_check(&p, msg, 0), VI_ODE_ERR_ARGS);
    cr_assert_str_eq(msg, "unset");
    cr_assert_eq(vi_ode_check(&p, msg, sizeof msg), VI_ODE_ERR_ARGS);
    cr_assert_str_eq(msg, "n must ");
}

/* x' = 1 from 0 (x = t), one fixed step [0, 1]; the guard T - x^3 records where it is evaluated and
 * its value there. */
static double cubic_root_T;
static double cubic_evals[VI_ODE_MAX_ROOT_ITERS + 8], cubic_values[VI_ODE_MAX_ROOT_ITERS + 8];
/* the guard: 0: T - x^3 (concave), 1: T - t (exactly 0 at a dyadic T), 2: (1 - x)^3 - (1 - T)^3 (convex) */
static int n_cubic_evals, cubic_linear_in_t;
static void unit_rate(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)x, (void)u;
    dx[0] = 1.0;
}
static void cubic_guard(double t, const double *x, double *g, void *u)
{
    (void)u;
    double y = 1.0 - x[0], yT = 1.0 - cubic_root_T;
    g[0] = cubic_linear_in_t == 1 ? cubic_root_T - t
         : cubic_linear_in_t == 2 ? y * y * y - yT * yT * yT
                                  : cubic_root_T - x[0] * x[0] * x[0];
    if (n_cubic_evals < (int)(sizeof cubic_evals / sizeof *cubic_evals))
        cubic_evals[n_cubic_evals] = t, cubic_values[n_cubic_evals++] = g[0];
}

Test(events, root_search_halves_the_bracket_every_third_evaluation_and_bisects_within_two_tolerances)
{
    /* The rules of the root search (vi_ode.h, EVENTS), checked on the bracket the test rebuilds from
     * the points the guard was evaluated at (g <= 0: the new right end, else the new left end): the
     * width halves at least every third evaluation, and once it is within two tolerances (eps of the
     * larger end) the next evaluation is its midpoint (which closes a bracket of 2 ulps). */
    vi_ode_problem p = {.n = 1, .ng = 1, .rhs = unit_rate, .guards = cubic_guard, .rtol = 1e-8, .atol = {1e-9},
                        .h_fixed = 1.0};
    for (int k = 1; k < 200; k++) {
        cubic_root_T = k / 200.0 + 1e-3 * sin(k);
        vi_ode s;
        double x0[1] = {0.0};
        n_cubic_evals = 0;
        cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
        cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_EVENT);
        cr_assert(n_cubic_evals == 2 + s.st.root_iters && cubic_evals[0] == 0.0 && cubic_evals[1] == 1.0);
        double a = 0.0, b = 1.0, w[VI_ODE_MAX_ROOT_ITERS + 8];
        for (int i = 2; i < n_cubic_evals; i++) {
            double tm = cubic_evals[i], tol = DBL_EPSILON * fmax(fabs(a), fabs(b));
            cr_assert(b - a > tol && tm > a && tm < b, "T %.17g, evaluation %d at %.17g outside (%.17g, %.17g)",
                      cubic_root_T, i, tm, a, b);
            if (b - a <= 2.0 * tol) {
                cr_assert(tm == a + 0.5 * (b - a), "T %.17g: bracket [%.17g, %.17g] within two tolerances, evaluation %d at %.17g",
                          cubic_root_T, a, b, i, tm);
            }
            if (cubic_values[i] <= 0.0) b = tm;
            else a = tm;
            w[i] = b - a;
            if (i >= 4) cr_assert(w[i] <= 0.5 * (i == 4 ? 1.0 : w[i - 3]), "T %.17g: width %g after %d, %g three before",
                                  cubic_root_T, w[i], i, i == 4 ? 1.0 : w[i - 3]);
        }
        cr_assert(s.ev_t == b && s.ev_t_lo == a && b - a <= DBL_EPSILON * b, "T %.17g", cubic_root_T);
    }
}

Test(events, root_search_points_are_the_illinois_method_with_its_bisections)
{
    /* Every evaluation point of the search, recomputed from the rules of vi_ode.h (EVENTS) on the
     * values the guard returned: regula falsi on the weighted end values, the Illinois rule (an end
     * kept twice in a row has its weight halved; an end that moves gets weight 1), a bisection when
     * the last two evaluations did not halve the bracket, and the point kept a tolerance inside the
     * bracket (its midpoint within two tolerances). */
    vi_ode_problem p = {.n = 1, .ng = 1, .rhs = unit_rate, .guards = cubic_guard, .rtol = 1e-8, .atol = {1e-9},
                        .h_fixed = 1.0};
    long halvings = 0, bisections = 0;
    for (int k = 1; k < 200 + 63 + 99; k++) {
        /* T - x^3 with roots T^(1/3) (regula falsi keeps its right end), then T - t with dyadic roots
         * T = j/64 (an end value exactly 0), then the convex (1 - x)^3 - (1 - T)^3 (it keeps its left end) */
        cubic_linear_in_t = k < 200 ? 0 : k < 263 ? 1 : 2;
        cubic_root_T = k < 200 ? k / 200.0 + 1e-3 * sin(k) : k < 263 ? (k - 199) / 64.0 : (k - 262) / 100.0 + 1e-3 * sin(k);
        vi_ode s;
        double x0[1] = {0.0};
        n_cubic_evals = 0;
        cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
        cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_EVENT);
        double a = 0.0, b = 1.0, ga = cubic_values[0], gb = cubic_values[1], wa = 1.0, wb = 1.0;
        double w1 = INFINITY, w2 = INFINITY;
        int side = 0;
        for (int i = 2; i < n_cubic_evals; i++) {
            double tol = fmax(DBL_EPSILON * fmax(fabs(a), fabs(b)), DBL_MIN), tm;
            if (b - a > 0.5 * w2) {
                tm = a + 0.5 * (b - a);
                bisections++;
            } else {
                tm = a + (b - a) * (wa * ga / (wa * ga - wb * gb));
            }
            if (b - a <= 2.0 * tol) tm = a + 0.5 * (b - a);
            else if (tm < a + tol) tm = a + tol;
            else if (tm > b - tol) tm = b - tol;
            cr_assert(cubic_evals[i] == tm, "T %.17g, evaluation %d at %.17g, expected %.17g", cubic_root_T, i,
                      cubic_evals[i], tm);
            w2 = w1, w1 = b - a;
            if (cubic_values[i] <= 0.0) {
                b = tm, gb = cubic_values[i], wb = 1.0;
                if (side == -1) wa *= 0.5, halvings++;
                side = -1;
            } else {
                a = tm, ga = cubic_values[i], wa = 1.0;
                if (side == 1) wb *= 0.5, halvings++;
                side = 1;
            }
        }
    }
    cubic_linear_in_t = 0;
    cr_assert(halvings > 100 && bisections > 50, "the cases use both rules: %ld halvings, %ld bisections", halvings,
              bisections);
}

Test(state, a_restart_after_an_event_keeps_every_counter)
{
    /* One fixed step [0, 1] with an event located in it: every counter has moved; a restart adds its
     * own work (f and the guards at the restart point) and keeps the rest. The proposed step of a
     * fixed-step problem is h_fixed. */
    vi_ode_problem p = {.n = 1, .ng = 1, .rhs = unit_rate, .guards = cubic_guard, .rtol = 1e-8, .atol = {1e-9},
                        .h_fixed = 1.0};
    cubic_linear_in_t = 0, cubic_root_T = 0.3;
    vi_ode s;
    double x0[1] = {0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_EVENT);
    cr_assert(s.h == 1.0, "proposed %.17g", s.h);
    vi_ode_stats b = s.st;
    cr_assert(b.attempts == 1 && b.accepted == 1 && b.root_iters > 0 && b.dense_builds == 1 && b.events == 1);
    cr_assert_eq(vi_ode_restart(&s, &p, s.ev_t, s.ev_x, 0.0, 1u), VI_ODE_OK);
    cr_assert(s.st.attempts == b.attempts && s.st.accepted == b.accepted && s.st.rejected == b.rejected &&
              s.st.rhs_evals == b.rhs_evals + 1 && s.st.guard_evals == b.guard_evals + 1 &&
              s.st.dense_builds == b.dense_builds && s.st.root_iters == b.root_iters && s.st.events == b.events);
}

static double arm_t1;
static void bump_guard(double t, const double *x, double *g, void *u)
{
    (void)x, (void)u;
    g[0] = 0.5 - (t - arm_t1) * (t - arm_t1); /* 0.5 exactly at arm_t1, below elsewhere */
}

Test(events, a_guard_that_only_reaches_its_arming_threshold_stays_unarmed)
{
    /* arm_eps = 0.5: g = 0.5 - (t - t1)^2 touches 0.5 at t1 and falls below 0 after; with steps of 1
     * from 0 the guard is evaluated exactly at t1 = 1 (a step end) or t1 = 0 (the start). Never above
     * the threshold, it never arms and never fires; with arm_eps just below 0.5 it fires at t1 + sqrt(0.5). */
    vi_ode_problem p = {.n = 1, .ng = 1, .rhs = unit_rate, .guards = bump_guard, .rtol = 1e-8, .atol = {1e-9},
                        .h_fixed = 1.0, .arm_eps = {0.5}};
    const double t1s[] = {1.0, 0.0};
    for (int k = 0; k < 2; k++) {
        arm_t1 = t1s[k];
        for (int below = 0; below < 2; below++) {
            p.arm_eps[0] = below ? nextafter(0.5, 0.0) : 0.5;
            vi_ode s;
            double x0[1] = {0.0};
            cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
            int r = VI_ODE_OK;
            for (int j = 0; j < 4 && r == VI_ODE_OK; j++) r = vi_ode_step(&s, &p, INFINITY);
            if (!below) {
                cr_assert(r == VI_ODE_OK && s.armed == 0u, "t1 = %g: armed at 0.5 exactly", arm_t1);
            } else {
                cr_assert(r == VI_ODE_EVENT && fabs(s.ev_t - arm_t1 - sqrt(0.5)) < 1e-12, "t1 = %g: r %d at %.17g", arm_t1,
                          r, s.ev_t);
            }
        }
    }
}

static long calls_until_nan;
static void nan_on_one_call(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = --calls_until_nan == 0 ? NAN : -x[0];
}

Test(failures, a_step_whose_end_derivative_is_not_finite_is_rejected)
{
    /* x' = -x with h0 = 0.1 given: vi_ode_init calls f once; the first attempt evaluates stages 2..12
     * (11 calls) and then f at its end, the 13th call, which returns NaN here. That attempt is
     * rejected (as non-finite: h shrinks by 0.2) and the step taken with h = 0.02, f finite at its end. */
    vi_ode_problem p = {.n = 1, .rhs = nan_on_one_call, .rtol = 1e-8, .atol = {1e-9}};
    vi_ode s;
    double x0[1] = {1.0};
    calls_until_nan = 13;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.1, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_OK);
    cr_assert(s.st.rejected == 1 && s.st.accepted == 1, "rejected %ld", s.st.rejected);
    cr_assert(s.t == 0.1 * 0.2 && isfinite(s.f[0]), "t %.17g f %g", s.t, s.f[0]);
    cr_assert(fabs(s.x[0] - exp(-s.t)) < 1e-12 && s.f[0] == -s.x[0]);
}

Test(failures, each_refusal_of_a_problem_says_the_rule_and_the_value)
{
    /* One rule broken at a time, the message compared whole: the rule and the value given (longer than
     * 60 lines for its table: twenty refusals, a row each, and the change that makes each). */
    const vi_ode_problem ok = {.n = 2, .ng = 1, .rhs = osc_u, .guards = guards, .rtol = 1e-6, .atol = {1e-6, 1e-6}};
    char msg[128];
    cr_assert_eq(vi_ode_check(NULL, msg, sizeof msg), VI_ODE_ERR_ARGS);
    cr_assert_str_eq(msg, "no problem given (got 0)");
    struct {
        vi_ode_problem p;
        const char *want;
    } cases[] = {
        {ok, "n must be in 1..VI_ODE_MAX_N (got 0)"},
        {ok, "n must be in 1..VI_ODE_MAX_N (got 5)"},
        {ok, "ng must be in 0..VI_ODE_MAX_G (got -1)"},
        {ok, "ng must be in 0..VI_ODE_MAX_G (got 17)"},
        {ok, "rhs is NULL (got 0)"},
        {ok, "guards is NULL while ng > 0 (got 1)"},
        {ok, "rtol must be in (0, 1) (got 0)"},
        {ok, "rtol must be in (0, 1) (got 1)"},
        {ok, "atol[i] must be finite and > 0 (got -2)"},
        {ok, "atol[i] must be finite and > 0 (got inf)"},
        {ok, "max_step must be finite and >= 0 (got -1)"},
        {ok, "max_step must be finite and >= 0 (got inf)"},
        {ok, "h_min must be finite and >= 0 (got -0.5)"},
        {ok, "h_min must be finite and >= 0 (got nan)"},
        {ok, "h_fixed must be finite and >= 0 (got -3)"},
        {ok, "h_fixed must be finite and >= 0 (got inf)"},
        {ok, "guard_samples must be in 0..VI_ODE_MAX_SAMPLES (got -1)"},
        {ok, "guard_samples must be in 0..VI_ODE_MAX_SAMPLES (got 9)"},
        {ok, "arm_eps[i] must be finite and >= 0 (got -0.25)"},
        {ok, "arm_eps[i] must be finite and >= 0 (got inf)"},
    };
    int k = 0;
    cases[k++].p.n = 0;
    cases[k++].p.n = VI_ODE_MAX_N + 1;
    cases[k++].p.ng = -1;
    cases[k++].p.ng = VI_ODE_MAX_G + 1;
    cases[k++].p.rhs = NULL;
    cases[k++].p.guards = NULL;
    cases[k++].p.rtol = 0.0;
    cases[k++].p.rtol = 1.0;
    cases[k++].p.atol[0] = -2.0;
    cases[k++].p.atol[1] = INFINITY;
    cases[k++].p.max_step = -1.0;
    cases[k++].p.max_step = INFINITY;
    cases[k++].p.h_min = -0.5;
    cases[k++].p.h_min = NAN;
    cases[k++].p.h_fixed = -3.0;
    cases[k++].p.h_fixed = INFINITY;
    cases[k++].p.guard_samples = -1;
    cases[k++].p.guard_samples = VI_ODE_MAX_SAMPLES + 1;
    cases[k++].p.arm_eps[0] = -0.25;
    cases[k++].p.arm_eps[0] = INFINITY;
    cr_assert(k == (int)(sizeof cases / sizeof *cases));
    for (int i = 0; i < k; i++) {
        msg[0] = 0;
        cr_assert_eq(vi_ode_check(&cases[i].p, msg, sizeof msg), VI_ODE_ERR_ARGS, "%s", cases[i].want);
        cr_assert_str_eq(msg, cases[i].want);
    }
    /* the ends of the rules */
    vi_ode_problem e = ok;
    e.n = 1, e.ng = 0, e.guards = NULL, e.rtol = 1e-300, e.guard_samples = VI_ODE_MAX_SAMPLES;
    cr_assert_eq(vi_ode_check(&e, msg, sizeof msg), VI_ODE_OK, "%s", msg);
    e = ok;
    e.n = VI_ODE_MAX_N, e.atol[2] = e.atol[3] = 1e-300, e.ng = VI_ODE_MAX_G, e.rtol = nextafter(1.0, 0.0);
    cr_assert_eq(vi_ode_check(&e, msg, sizeof msg), VI_ODE_OK, "%s", msg);
}

static void huge_rate(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)x, (void)u;
    dx[0] = 1e306;
}

Test(failures, a_step_that_overflows_the_state_is_rejected)
{
    /* x' = 1e306 from 0 with h0 = 1000 given: x(1000) and x(200) overflow (the error estimate, scaled
     * by rtol |x1| = inf, comes out 0 and finite), so both attempts are rejected and the step is taken
     * with h = 40, x = 4e307. */
    vi_ode_problem p = {.n = 1, .rhs = huge_rate, .rtol = 1e-3, .atol = {1.0}};
    vi_ode s;
    double x0[1] = {0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 1000.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_OK);
    cr_assert(s.st.rejected == 2 && s.t == 1000.0 * 0.2 * 0.2, "rejected %ld, t %.17g", s.st.rejected, s.t);
    cr_assert(isfinite(s.x[0]) && fabs(s.x[0] - 4e307) <= 1e-12 * 4e307, "x %g", s.x[0]);
}

Test(state, max_step_bounds_fixed_steps_and_a_tightened_problem)
{
    /* max_step holds over h_fixed (0.3 fixed, 0.1 at most: steps of 0.1) and over a step size
     * proposed under a looser problem (a state started without max_step, stepped with 0.05). */
    vi_ode_problem p = {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}, .h_fixed = 0.3, .max_step = 0.1};
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    for (int k = 0; k < 3; k++) {
        cr_assert_eq(vi_ode_step(&s, &p, INFINITY), VI_ODE_OK);
        cr_assert(s.t - s.t_old <= 0.1 && s.t - s.t_old >= 0.1 * (1 - 1e-15), "step %d: %.17g", k, s.t - s.t_old);
    }
    vi_ode_problem loose = {.n = 2, .rhs = osc_u, .rtol = 1e-6, .atol = {1e-6, 1e-6}};
    cr_assert_eq(vi_ode_init(&s, &loose, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &loose, INFINITY), VI_ODE_OK);
    cr_assert(s.h > 0.05, "proposed %g", s.h);
    loose.max_step = 0.05;
    cr_assert_eq(vi_ode_step(&s, &loose, INFINITY), VI_ODE_OK);
    cr_assert(s.t - s.t_old <= 0.05, "step %.17g", s.t - s.t_old);
}

Test(failures, a_retry_at_exactly_h_min_is_taken)
{
    /* The first attempt (h0 = 0.1 given) fails on a NaN stage and h shrinks by FAC_MIN = 0.2; the
     * retry is made when h is not below h_min (h_min = 0.02 exactly: the step is taken) and refused
     * when it is (h_min one ulp above: VI_ODE_ERR_NONFINITE, the state kept). */
    for (int above = 0; above < 2; above++) {
        vi_ode_problem p = {.n = 1, .rhs = nan_on_one_call, .rtol = 1e-8, .atol = {1e-9}};
        p.h_min = above ? nextafter(0.1 * 0.2, 1.0) : 0.1 * 0.2;
        vi_ode s;
        double x0[1] = {1.0};
        calls_until_nan = 2; /* the second stage of the first attempt */
        cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.1, 0u), VI_ODE_OK);
        int r = vi_ode_step(&s, &p, INFINITY);
        if (above) {
            cr_assert(r == VI_ODE_ERR_NONFINITE && s.t == 0.0 && s.st.rejected == 1, "r %d", r);
        } else {
            cr_assert(r == VI_ODE_OK && s.t == 0.1 * 0.2 && s.st.rejected == 1, "r %d t %.17g", r, s.t);
        }
    }
}

Test(state, step_size_control_rules)
{
    problem pr = PROBLEMS[0];
    vi_ode_problem p = make(&pr, 1e-8, 1e-8);
    vi_ode s;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 0.0, 0u), VI_ODE_OK);
    double x_prev[2] = {s.x[0], s.x[1]}, t_prev = s.t;
    for (int k = 0; k < 5; k++) {
        cr_assert_eq(vi_ode_step(&s, &p, 100.0), VI_ODE_OK);
        cr_assert(s.t_old == t_prev && memcmp(s.x_old, x_prev, sizeof x_prev) == 0, "[t_old, t] is the last step");
        t_prev = s.t, x_prev[0] = s.x[0], x_prev[1] = s.x[1];
        cr_assert(s.err <= 1.0);
        if (s.rejected_last == 0)
            cr_assert(fabs(s.h / (s.t - s.t_old) - fmin(5.0, fmax(0.2, 0.9 / pow(s.err, 0.125)))) < 1e-12,
                      "h_new = h min(5, max(0.2, 0.9 err^-1/8))");
    }
    /* growth by at most 5 per step; none right after a rejection */
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 1e-6, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 100.0), VI_ODE_OK);
    cr_assert(s.rejected_last == 0 && s.h == 5.0 * (s.t - s.t_old), "h grows by 5: %g after %g", s.h, s.t - s.t_old);
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 3.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 100.0), VI_ODE_OK);
    cr_assert(s.rejected_last > 0 && s.h <= s.t - s.t_old, "after %d rejections h %g <= %g", s.rejected_last, s.h,
              s.t - s.t_old);
    cr_assert_eq(s.st.rejected, s.rejected_last);
    /* a step shortened to reach t_stop keeps the proposal */
    double h = s.h;
    cr_assert_eq(vi_ode_step(&s, &p, s.t + 0.1 * h), VI_ODE_OK);
    cr_assert(s.h >= h, "proposal %g kept after a short step to t_stop (was %g)", s.h, h);
    /* a tiny fixed step */
    p.h_fixed = 1e-4;
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, pr.x0, 0.0, 0u), VI_ODE_OK);
    cr_assert(s.h == 1e-4);
    int k = 0;
    for (; s.t < 1e-3 && k < 100; k++) cr_assert_eq(vi_ode_step(&s, &p, 1e-3), VI_ODE_OK);
    cr_assert_eq(k, 10, "%d fixed steps of 1e-4 over 1e-3", k);
    cr_assert(s.t == 1e-3);
}

/* f jumps right after t = 0: the first stage (f = 0) disagrees with all others (f = 1e60) for every h,
 * so the scaled error estimate stays ~1e4 however small h gets; h_min = 16 eps |t| = 0 at t = 0 */
static void kink(double t, const double *x, double *dx, void *u)
{
    (void)x, (void)u;
    dx[0] = t > 0.0 ? 1e60 : 0.0;
}

Test(failures, rejections_are_bounded)
{
    vi_ode_problem p = {.n = 1, .rhs = kink, .rtol = 1e-6, .atol = {1e-6}};
    vi_ode s;
    double x0[1] = {0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 1e-3, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 1.0), VI_ODE_ERR_REJECTS);
    cr_assert_eq(s.st.rejected, VI_ODE_MAX_REJECTS);
    cr_assert(s.t == 0.0 && s.h == 1e-3, "state unchanged");
}

Test(failures, check_bounds_and_null_arguments)
{
    gctx c = {G_X, 0, INFINITY, -INFINITY};
    vi_ode_problem p = {.n = 2, .ng = 1, .rhs = osc_u, .guards = guards, .user = &c, .rtol = 1e-6,
                        .atol = {1e-6, 1e-6}, .guard_samples = VI_ODE_MAX_SAMPLES};
    p.arm_eps[1] = -1.0; /* beyond ng: not looked at */
    cr_assert_eq(vi_ode_check(&p, NULL, 0), VI_ODE_OK);
    p.atol[2] = -1.0;    /* beyond n: not looked at */
    cr_assert_eq(vi_ode_check(&p, NULL, 0), VI_ODE_OK);
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(NULL, &p, 0.0, x0, 0.0, 0u), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_restart(NULL, &p, 0.0, x0, 0.0, 0u), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_init(&s, NULL, 0.0, x0, 0.0, 0u), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, NULL, 0.0, 0u), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_check(NULL, NULL, 0), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(NULL, &p, 1.0), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_step(&s, NULL, 1.0), VI_ODE_ERR_ARGS);
    double x[2];
    cr_assert_eq(vi_ode_step(&s, &p, 1.0), VI_ODE_OK);
    cr_assert_eq(vi_ode_dense(&s, &p, s.t, NULL, NULL), VI_ODE_ERR_ARGS);
    cr_assert_eq(vi_ode_dense(NULL, &p, s.t, x, NULL), VI_ODE_ERR_ARGS);
}

static void nan_in_dense_stage(double t, const double *x, double *dx, void *u)
{
    (void)u;
    dx[0] = fabs(t - 0.1) < 0.005 ? NAN : -x[0]; /* only the dense-output stage at c = 0.1 of [0, 1] */
}

Test(failures, nonfinite_dense_stage_is_reported)
{
    vi_ode_problem p = {.n = 1, .rhs = nan_in_dense_stage, .rtol = 1e-6, .atol = {1e-6}, .h_fixed = 1.0};
    vi_ode s;
    double x0[1] = {1.0}, x[1] = {42.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 2.0), VI_ODE_OK, "the step's own stages avoid t = 0.1");
    cr_assert_eq(vi_ode_dense(&s, &p, 0.5, x, NULL), VI_ODE_ERR_NONFINITE);
    cr_assert(x[0] == 42.0, "nothing written");
    cr_assert_eq(s.sp[s.cur].dense_ready, 0);
}

static void positive_guard(double t, const double *x, double *g, void *u)
{
    (void)t, (void)u;
    g[0] = 1.0 + x[0] * x[0]; /* never crosses: only the search's interior samples build the dense output */
}

/* The same NaN at the dense stage c = 0.1, met by the event search's interior guard samples (which
 * build the dense output): the step fails as not finite and the state stays at its start. */
Test(failures, nonfinite_dense_stage_fails_the_event_search)
{
    vi_ode_problem p = {.n = 1, .ng = 1, .rhs = nan_in_dense_stage, .guards = positive_guard, .rtol = 1e-6,
                        .atol = {1e-6}, .h_fixed = 1.0, .guard_samples = 1};
    vi_ode s;
    double x0[1] = {1.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &p, 2.0), VI_ODE_ERR_NONFINITE);
    cr_assert(s.t == 0.0 && s.x[0] == 1.0, "t = %g, x = %g", s.t, s.x[0]);
}

Test(state, initial_step_of_a_nonlinear_problem)
{
    /* y' = -2 t y^2 at t0 = 0.5, y0 = 0.8, rtol = 1e-6, atol = 1e-8: the formulas of HNW II.4 */
    vi_ode_problem p = {.n = 1, .rhs = riccati, .rtol = 1e-6, .atol = {1e-8}};
    vi_ode s;
    double t0 = 0.5, y0 = 0.8, sc = 1e-8 + 1e-6 * y0;
    double f0 = -2 * t0 * y0 * y0, d0 = y0 / sc, d1 = fabs(f0) / sc;
    double h0 = 0.01 * d0 / d1, y1 = y0 + h0 * f0, f1 = -2 * (t0 + h0) * y1 * y1;
    double d2 = fabs(f1 - f0) / h0 / sc, h1 = pow(0.01 / fmax(d1, d2), 1.0 / 8.0);
    double expect = fmin(100 * h0, h1);
    double x0[1] = {y0};
    cr_assert_eq(vi_ode_init(&s, &p, t0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert(fabs(s.h - expect) <= 1e-13 * expect, "h = %.17g, expected %.17g", s.h, expect);
}

static void sixteen(double t, const double *x, double *g, void *u)
{
    (void)t, (void)u;
    for (int i = 0; i < VI_ODE_MAX_G; i++) g[i] = x[0] + 0.1 * i; /* all cross cos t = -0.1 i */
}

static void still(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)x, (void)u;
    dx[0] = 0.0;
}

Test(state, sixteen_guards_and_a_constant_solution)
{
    vi_ode_problem p = {.n = 2, .ng = VI_ODE_MAX_G, .rhs = osc_u, .guards = sixteen, .rtol = 1e-10,
                        .atol = {1e-10, 1e-10}};
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(s.armed, 0xffffu);
    for (int i = 0; i < 10; i++) { /* guards 0..9 fire one after the other at acos(-0.1 i) */
        cr_assert_eq(until_event(&s, &p, 10.0), VI_ODE_EVENT);
        cr_assert_eq(s.ev_fired, 1u << i, "event %d fired %#x", i, s.ev_fired);
        cr_assert(fabs(s.ev_t - acos(-0.1 * i)) < 1e-9);
        cr_assert_eq(vi_ode_restart(&s, &p, s.ev_t, s.ev_x, 0.0, s.ev_fired), VI_ODE_OK);
    }
    /* f = 0: the error estimate is exactly 0, the step grows by the largest factor */
    vi_ode_problem q = {.n = 1, .rhs = still, .rtol = 1e-6, .atol = {1e-6}};
    double z[1] = {3.0};
    cr_assert_eq(vi_ode_init(&s, &q, 0.0, z, 0.01, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &q, 100.0), VI_ODE_OK);
    cr_assert(s.err == 0.0 && s.h == 0.05 && s.x[0] == 3.0, "err %g, h %g", s.err, s.h);
}

/* One step of the tableau as in a textbook (all stages, full sums, the published error formula):
 * an independent implementation to compare the module's step with. */
static void textbook_step(vi_ode_rhs_fn f, int n, double t, const double *x, double h, const double *atol,
                          double rtol, double *x1, double *err)
{
    const vi_ode_tableau *m = vi_ode_method();
    double k[VI_ODE_STAGES][NX], y[NX], e5[NX], e3[NX];
    for (int i = 0; i < 12; i++) {
        for (int c = 0; c < n; c++) {
            y[c] = x[c];
            for (int j = 0; j < i; j++) y[c] += h * m->a[i][j] * k[j][c];
        }
        f(t + m->c[i] * h, y, k[i], NULL);
    }
    double s5 = 0.0, s3 = 0.0;
    for (int c = 0; c < n; c++) {
        x1[c] = x[c], e5[c] = e3[c] = 0.0;
        for (int j = 0; j < 12; j++) {
            x1[c] += h * m->b[j] * k[j][c];
            e5[c] += h * m->e5[j] * k[j][c];
            e3[c] += h * m->e3[j] * k[j][c];
        }
        double sc = atol[c] + rtol * fmax(fabs(x[c]), fabs(x1[c]));
        s5 += (e5[c] / sc) * (e5[c] / sc) / n;
        s3 += (e3[c] / sc) * (e3[c] / sc) / n;
    }
    *err = s5 / sqrt(s5 + 0.01 * s3); /* ||e5||^2 / sqrt(||e5||^2 + 0.01 ||e3||^2), RMS norms */
}

Test(order, step_agrees_with_a_textbook_implementation_of_the_tableau)
{
    for (int k = 0; k < N_PROBLEMS; k++) {
        const problem *pr = &PROBLEMS[k];
        vi_ode_problem p = make(pr, 1e-7, 1e-9);
        p.h_fixed = 0.3;
        vi_ode s;
        double x0[NX], x1[NX], err, t0 = 0.7;
        pr->exact(t0, pr->x0, x0);
        cr_assert_eq(vi_ode_init(&s, &p, t0, x0, 0.0, 0u), VI_ODE_OK);
        cr_assert_eq(vi_ode_step(&s, &p, 10.0), VI_ODE_OK);
        textbook_step(pr->f, pr->n, t0, x0, s.t - t0, p.atol, p.rtol, x1, &err);
        for (int c = 0; c < pr->n; c++)
            cr_assert(fabs(s.x[c] - x1[c]) <= 1e-14 * (fabs(x1[c]) + 1.0), "%s: x[%d] %.17g vs %.17g", pr->name, c,
                      s.x[c], x1[c]);
        /* the estimators cancel to O(h^6) and O(h^4): roundings of the stages show at ~1e-7 */
        cr_assert(fabs(s.err - err) <= 1e-5 * err, "%s: err %.17g vs %.17g", pr->name, s.err, err);
    }
}

Test(state, a_step_below_the_rounding_of_t_advances_by_16_ulps_or_fails)
{
    /* At t = 1e17 one ulp is 16 s: a proposed step of 1 us would be h = 0 (t + h == t); the
     * shortest step taken is 16 eps |t|. */
    vi_ode_problem q = {.n = 1, .rhs = still, .rtol = 1e-6, .atol = {1e-6}};
    vi_ode s;
    double z[1] = {3.0}, t0 = 1e17, h_min = 16.0 * DBL_EPSILON * t0;
    cr_assert_eq(vi_ode_init(&s, &q, t0, z, 1e-6, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &q, INFINITY), VI_ODE_OK);
    double ulp = nextafter(t0, INFINITY) - t0; /* 16 s: t0 + h_min rounds to the time grid */
    cr_assert(s.t - t0 >= h_min - ulp && s.t - t0 <= 2.0 * h_min, "t - t0 = %g, h_min %g", s.t - t0, h_min);
    double t1 = s.t;
    cr_assert_eq(vi_ode_step(&s, &q, INFINITY), VI_ODE_OK);
    cr_assert(s.t > t1 && s.x[0] == 3.0);
    /* a fixed step that rounds to nothing cannot advance: step size underflow, state kept */
    q.h_fixed = 1.0;
    cr_assert_eq(vi_ode_init(&s, &q, t0, z, 0.0, 0u), VI_ODE_OK);
    cr_assert_eq(vi_ode_step(&s, &q, INFINITY), VI_ODE_ERR_HMIN);
    cr_assert(s.t == t0 && s.x[0] == 3.0);
}

/* A stiff undamped oscillator x'' = -w^2 (x - 1), w = 1e7 rad/s, started 1e-12 off its rest at x = 1
 * with absolute tolerances far above that motion (as a contact at rest with a law whose length
 * scale is much larger than its indentation): rho = w. */
#define REST_W 1e7
static void rest_osc(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = x[1];
    dx[1] = -REST_W * REST_W * (x[0] - 1.0);
}
static double rest_rho(double t, const double *x, void *env) { return (void)t, (void)x, (void)env, REST_W; }

/* The largest |x - 1| (scaled by w for v: the oscillation's amplitude) over 1e-4 s (160 periods). */
static double rest_amplitude(vi_ode_problem *p, double *h_rho)
{
    vi_ode s;
    double x0[2] = {1.0 + 1e-12, 0.0}, amp = 0.0;
    *h_rho = 0.0;
    cr_assert_eq(vi_ode_init(&s, p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    for (long k = 0; k < 100000 && s.t < 1e-4; k++) {
        cr_assert_eq(vi_ode_step(&s, p, 1e-4), VI_ODE_OK);
        amp = fmax(amp, hypot(s.x[0] - 1.0, s.x[1] / REST_W));
        *h_rho = fmax(*h_rho, (s.t - s.t_old) * REST_W);
    }
    cr_assert(s.t == 1e-4);
    return amp;
}

Test(stability, steps_bounded_by_h_rho_max_keep_a_rest_at_rest)
{
    /* Without the bound the first step (Hairer's estimate: the state hardly moves) lies far outside
     * the stability domain, and the 1e-12 deviation grows towards the tolerance (1e-3); with
     * h rho <= 5.4 it never grows (|R| <= 1 on the imaginary axis up to 5.96). */
    vi_ode_problem p = {.n = 2, .rhs = rest_osc, .rtol = 1e-6, .atol = {1e-3, 1e-3 * REST_W}};
    double h_rho, free_amp = rest_amplitude(&p, &h_rho);
    cr_assert(free_amp > 1e-9 && h_rho > 6.0, "unbounded: amplitude %g, h rho up to %g", free_amp, h_rho);
    p.spectral_radius = rest_rho;
    p.h_rho_max = 5.4;
    double amp = rest_amplitude(&p, &h_rho);
    cr_assert(amp <= 1e-12 * (1.0 + 1e-3), "bounded: the amplitude grew to %g", amp);
    cr_assert(h_rho <= 5.4 * (1.0 + 1e-12), "h rho %g", h_rho);
}

Test(stability, an_exact_rest_is_not_held_to_the_bound)
{
    /* Started exactly at rest every stage is 0: the steps grow as the error estimate allows (factor 5
     * per step), the state stays exact, and no step is rejected. */
    vi_ode_problem p = {.n = 2, .rhs = rest_osc, .rtol = 1e-6, .atol = {1e-3, 1e-3 * REST_W},
                        .spectral_radius = rest_rho, .h_rho_max = 5.4};
    vi_ode s;
    double x0[2] = {1.0, 0.0};
    cr_assert_eq(vi_ode_init(&s, &p, 0.0, x0, 0.0, 0u), VI_ODE_OK);
    for (int k = 0; k < 100 && s.t < 1.0; k++) cr_assert_eq(vi_ode_step(&s, &p, 1.0), VI_ODE_OK);
    cr_assert(s.t == 1.0 && s.x[0] == 1.0 && s.x[1] == 0.0, "t %g, x %.17g %.17g", s.t, s.x[0], s.x[1]);
    cr_assert(s.st.accepted < 40 && s.st.rejected == 0, "%ld steps, %ld rejected", s.st.accepted, s.st.rejected);
}
