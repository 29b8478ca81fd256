/* vi_laws.c - damped Hertz, linear spring-dashpot, Thornton; equations in vi_laws.h. */
#include "vi_laws.h"

#include <float.h>
#include <math.h>

/* ---- a bracketed root search -------------------------------------------------------------------- */

/* Illinois false position on [lo, hi] with fn(lo) and fn(hi) of opposite signs: stops when the bracket
 * is below tol (absolute) or after VI_ROOT_MAX_ITER iterations (it converges superlinearly: about 10). */
#define VI_ROOT_MAX_ITER 200

typedef double (*vi_root_fn)(double x, const void *ctx);

static double root_bracketed(vi_root_fn fn, const void *ctx, double lo, double hi, double tol)
{
    double flo = fn(lo, ctx), fhi = fn(hi, ctx);
    int side = 0; /* which end stayed last time: halve its value (Illinois) */
    for (int it = 0; it < VI_ROOT_MAX_ITER && hi - lo > tol; it++) {
        double x = (lo * fhi - hi * flo) / (fhi - flo);
        if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
        double fx = fn(x, ctx);
        if (fx == 0.0) return x;
        if ((fx < 0.0) == (flo < 0.0)) {
            lo = x, flo = fx;
            if (side == -1) fhi *= 0.5;
            side = -1;
        } else {
            hi = x, fhi = fx;
            if (side == 1) flo *= 0.5;
            side = 1;
        }
    }
    return fabs(flo) < fabs(fhi) ? lo : hi;
}

/* Expands hi (doubling, at most VI_BRACKET_MAX_DOUBLINGS times) until fn(hi) < 0, for fn positive at 0
 * and decreasing. Returns hi, or a negative value when no sign change was found. */
#define VI_BRACKET_MAX_DOUBLINGS 60

static double bracket_up(vi_root_fn fn, const void *ctx, double hi)
{
    for (int i = 0; i < VI_BRACKET_MAX_DOUBLINGS; i++, hi *= 2.0)
        if (fn(hi, ctx) < 0.0) return hi;
    return -1.0;
}

/* ---- Tsuji's damped Hertz: the dimensionless impact ----------------------------------------------- */

/* x'' = -x^1.5 - alpha x^(1/4) x' from x = 0, x' = 1, in two phases that keep classical RK4 at its order
 * where x^(1/4) is not smooth (x -> 0):
 *  1. in the time sigma = tau^(1/4) (x ~ tau = sigma^4 at the start): VI_TSUJI_STEPS steps span sigma in
 *     [0, VI_TSUJI_SIGMA_MAX] (every impact ends by tau = 3.22, alpha = 0: sigma = 1.34), until the force
 *     vanishes or, rebounding, x falls below VI_TSUJI_SWITCH times its peak;
 *  2. then with s = x^(1/4) as the independent variable: dv/ds = -4 s^9/v - 4 alpha s^4, smooth, with
 *     v < 0 bounded away from 0, down to where the force vanishes, s^5 + alpha v = 0 (before s = 0), in
 *     VI_TSUJI_REBOUND_STEPS steps. */
#define VI_TSUJI_STEPS 3000
#define VI_TSUJI_SIGMA_MAX 1.4142135623730951 /* tau = 4 */
#define VI_TSUJI_SWITCH 0.5
#define VI_TSUJI_REBOUND_STEPS 1000
#define VI_TSUJI_LOCATE_TOL 1e-15             /* the separation's position within a step, in steps */
#define VI_TSUJI_ALPHA_MAX 1e8                /* e = 1.25e-16; from about 1.6e8 on the steps are unstable */

typedef struct {
    double x, v; /* dimensionless indentation and its rate d/dtau */
} tsuji_state;

static tsuji_state tsuji_rate(double alpha, double sigma, tsuji_state s)
{
    double x = s.x > 0.0 ? s.x : 0.0, dtau = 4.0 * sigma * sigma * sigma;
    tsuji_state d = {dtau * s.v, dtau * (-x * sqrt(x) - alpha * sqrt(sqrt(x)) * s.v)};
    return d;
}

static tsuji_state tsuji_rk4(double alpha, double sigma, tsuji_state s, double h)
{
    tsuji_state k1 = tsuji_rate(alpha, sigma, s);
    tsuji_state s2 = {s.x + 0.5 * h * k1.x, s.v + 0.5 * h * k1.v};
    tsuji_state k2 = tsuji_rate(alpha, sigma + 0.5 * h, s2);
    tsuji_state s3 = {s.x + 0.5 * h * k2.x, s.v + 0.5 * h * k2.v};
    tsuji_state k3 = tsuji_rate(alpha, sigma + 0.5 * h, s3);
    tsuji_state s4 = {s.x + h * k3.x, s.v + h * k3.v};
    tsuji_state k4 = tsuji_rate(alpha, sigma + h, s4);
    tsuji_state out = {s.x + h / 6.0 * (k1.x + 2.0 * k2.x + 2.0 * k3.x + k4.x),
                       s.v + h / 6.0 * (k1.v + 2.0 * k2.v + 2.0 * k3.v + k4.v)};
    return out;
}

/* x^(5/4) + alpha v: the force over x^(1/4); falls through 0 at separation */
static double tsuji_guard(double alpha, tsuji_state s)
{
    double x = s.x > 0.0 ? s.x : 0.0;
    return x * sqrt(sqrt(x)) + alpha * s.v;
}

typedef struct {
    double alpha, sigma, h;
    tsuji_state s;
} tsuji_step;

/* the guard after a fraction theta of the step */
static double tsuji_partial_step_guard(double theta, const void *ctx)
{
    const tsuji_step *st = ctx;
    return tsuji_guard(st->alpha, tsuji_rk4(st->alpha, st->sigma, st->s, theta * st->h));
}

/* phase 2: dv/ds, and one RK4 step of length h (< 0) from (s, v) */
static double tsuji_rebound_rate(double alpha, double s, double v)
{
    double s4 = s * s * s * s;
    return -4.0 * s4 * s4 * s / v - 4.0 * alpha * s4;
}

static double tsuji_rebound_rk4(double alpha, double s, double v, double h)
{
    double k1 = tsuji_rebound_rate(alpha, s, v);
    double k2 = tsuji_rebound_rate(alpha, s + 0.5 * h, v + 0.5 * h * k1);
    double k3 = tsuji_rebound_rate(alpha, s + 0.5 * h, v + 0.5 * h * k2);
    double k4 = tsuji_rebound_rate(alpha, s + h, v + h * k3);
    return v + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

typedef struct {
    double alpha, s, v, h;
} tsuji_rebound_step;

static double tsuji_rebound_partial_guard(double theta, const void *ctx)
{
    const tsuji_rebound_step *st = ctx;
    double s = st->s + theta * st->h, s2 = s * s;
    return s2 * s2 * s + st->alpha * tsuji_rebound_rk4(st->alpha, st->s, st->v, theta * st->h);
}

/* phase 2 from x > 0, v < 0: the speed where the force vanishes */
static double tsuji_rebound(double alpha, tsuji_state start)
{
    double s = sqrt(sqrt(start.x)), v = start.v, h = -s / VI_TSUJI_REBOUND_STEPS;
    for (int i = 0; i < VI_TSUJI_REBOUND_STEPS; i++, s += h) {
        double next = tsuji_rebound_rk4(alpha, s, v, h), s1 = s + h, s12 = s1 * s1;
        if (s12 * s12 * s1 + alpha * next < 0.0) {
            tsuji_rebound_step st = {alpha, s, v, h};
            double theta = root_bracketed(tsuji_rebound_partial_guard, &st, 0.0, 1.0, VI_TSUJI_LOCATE_TOL);
            return -tsuji_rebound_rk4(alpha, s, v, theta * h);
        }
        v = next;
    }
    return -v; /* not reached: at s = 0 the guard is alpha v < 0 */
}

double vi_tsuji_restitution(double alpha)
{
    if (!(alpha <= VI_TSUJI_ALPHA_MAX)) return NAN;
    if (!(alpha > 0.0)) return 1.0;
    const double h = VI_TSUJI_SIGMA_MAX / VI_TSUJI_STEPS;
    tsuji_state s = {0.0, 1.0};
    double x_peak = 0.0;
    for (int i = 0; i < VI_TSUJI_STEPS; i++) {
        double sigma = i * h;
        tsuji_state next = tsuji_rk4(alpha, sigma, s, h);
        if (next.v < 0.0 && tsuji_guard(alpha, next) < 0.0) {
            tsuji_step st = {alpha, sigma, h, s};
            double theta = root_bracketed(tsuji_partial_step_guard, &st, 0.0, 1.0, VI_TSUJI_LOCATE_TOL);
            return -tsuji_rk4(alpha, sigma, s, theta * h).v;
        }
        if (next.v < 0.0 && next.x < VI_TSUJI_SWITCH * x_peak) return tsuji_rebound(alpha, next);
        x_peak = fmax(x_peak, next.x);
        s = next;
    }
    return -s.v; /* not reached: every impact ends within the span */
}

static double tsuji_residual(double alpha, const void *ctx)
{
    return vi_tsuji_restitution(alpha) - *(const double *)ctx;
}

/* alpha is found to VI_TSUJI_ALPHA_TOL (relative; |d ln e/d ln alpha| <= 2 keeps e within twice it), and
 * the result is accepted when its restitution is e to VI_TSUJI_E_RTOL (relative). The doubling search
 * for an upper bound finds none past VI_TSUJI_ALPHA_MAX (the restitution is NaN there): e below
 * e(2^26) = 2.8e-16 is refused. */
#define VI_TSUJI_ALPHA_TOL 1e-14
#define VI_TSUJI_E_RTOL 1e-10

int vi_tsuji_alpha_solve(double e, double *alpha)
{
    if (!(e > 0.0 && e <= 1.0)) return -1;
    if (e == 1.0) {
        *alpha = 0.0;
        return 0;
    }
    double hi = bracket_up(tsuji_residual, &e, 1.0);
    if (hi < 0.0) return -1;
    double a = root_bracketed(tsuji_residual, &e, 0.0, hi, VI_TSUJI_ALPHA_TOL * hi);
    if (!(fabs(vi_tsuji_restitution(a) / e - 1.0) <= VI_TSUJI_E_RTOL)) return -1;
    *alpha = a;
    return 0;
}

/* the table of vi_laws.h: vi_tsuji_table[piece][k], the Chebyshev coefficients of G on the piece */
#include "vi_tsuji_table.inc"
_Static_assert(sizeof vi_tsuji_table == sizeof(double) * VI_TSUJI_TABLE_PIECES * (VI_TSUJI_TABLE_DEGREE + 1),
               "src/model/vi_tsuji_table.inc does not match the table's shape in vi_laws.h");

/* G(u) = sum_k c_k T_k(x), x in [-1, 1] across the piece of u (Clenshaw's recurrence) */
static double tsuji_table_G(double u)
{
    double pos = (u - VI_TSUJI_TABLE_U_MIN) / VI_TSUJI_TABLE_WIDTH;
    int i = pos < VI_TSUJI_TABLE_PIECES - 1 ? (int)pos : VI_TSUJI_TABLE_PIECES - 1;
    double x = 2.0 * (pos - i) - 1.0, b1 = 0.0, b2 = 0.0;
    if (x > 1.0) x = 1.0; /* past the last piece: its end */
    const double *c = vi_tsuji_table[i];
    for (int k = VI_TSUJI_TABLE_DEGREE; k > 0; k--) {
        double b = 2.0 * x * b1 - b2 + c[k];
        b2 = b1, b1 = b;
    }
    return x * b1 - b2 + c[0];
}

int vi_tsuji_alpha(double e, double *alpha)
{
    if (!(e >= VI_TSUJI_TABLE_E_MIN && e <= 1.0)) return vi_tsuji_alpha_solve(e, alpha);
    double u = log(e / (1.0 - e)); /* +infinity at e = 1: alpha = 0 */
    *alpha = tsuji_table_G(u) * (1.0 - e) / sqrt(e);
    return 0;
}

/* ---- damped Hertz -------------------------------------------------------------------------------- */

double vi_damping_chi(int formula, double e)
{
    switch (formula) {
    case VI_DAMP_HUNT_CROSSLEY: return 1.5 * (1.0 - e);
    case VI_DAMP_LANKARANI_NIKRAVESH: return 0.75 * (1.0 - e * e);
    case VI_DAMP_FLORES: return 1.6 * (1.0 - e) / e;
    default: return 0.0;
    }
}

/* chi (1 + e_a) - ln((1 + chi)/(1 - chi e_a)): positive at e_a = 0, falling to -infinity at 1/chi */
static double hunt_crossley_residual(double ea, const void *ctx)
{
    double chi = *(const double *)ctx;
    return chi * (1.0 + ea) - log((1.0 + chi) / (1.0 - chi * ea));
}

#define VI_RESTITUTION_TOL 1e-15

double vi_damping_restitution(double chi)
{
    if (!(chi > 0.0)) return 1.0;
    double hi = fmin(1.0, 1.0 / chi);
    if (hunt_crossley_residual(hi, &chi) >= 0.0) hi = nextafter(hi, 0.0); /* e_a = 1/chi: the logarithm's pole */
    if (hunt_crossley_residual(hi, &chi) >= 0.0) return hi;
    return root_bracketed(hunt_crossley_residual, &chi, 0.0, hi, VI_RESTITUTION_TOL);
}

int vi_damped_hertz_setup(vi_damped_hertz *D, int formula, double e, double K, double m)
{
    if (!(e > 0.0 && e <= 1.0) || formula < VI_DAMP_EXACT || formula > VI_DAMP_FLORES) return -1;
    vi_damped_hertz out = {formula, K, 0.0, vi_damping_chi(formula, e)};
    if (formula == VI_DAMP_EXACT) {
        double alpha;
        if (vi_tsuji_alpha(e, &alpha) != 0) return -1;
        out.alpha_c = alpha * sqrt(m * K);
    }
    *D = out;
    return 0;
}

/* the published forms' damping factor chi/V_i [s/m]: 0 for a contact that started at rest */
static double damping_per_speed(const vi_damped_hertz *D, double V_i) { return V_i > 0.0 ? D->chi / V_i : 0.0; }

vi_law_force vi_damped_hertz_force(const vi_damped_hertz *D, double delta, double rate, double V_i)
{
    vi_law_force out = {0.0, 0.0, 0.0};
    if (!(delta > 0.0)) return out;
    double sq = sqrt(delta), hertz = D->K * delta * sq;
    if (D->formula == VI_DAMP_EXACT) {
        double q = sqrt(sq); /* delta^(1/4) */
        out.F = hertz + D->alpha_c * q * rate;
        out.dF_ddelta = 1.5 * D->K * sq + 0.25 * D->alpha_c * rate * q / delta;
        out.dF_drate = D->alpha_c * q;
    } else {
        double b = damping_per_speed(D, V_i);
        out.F = hertz * (1.0 + b * rate);
        out.dF_ddelta = 1.5 * D->K * sq * (1.0 + b * rate);
        out.dF_drate = hertz * b;
    }
    if (!(out.F > 0.0)) out.F = out.dF_ddelta = out.dF_drate = 0.0;
    return out;
}

vi_law_curvature vi_damped_hertz_curvature(const vi_damped_hertz *D, double delta, double rate, double V_i)
{
    vi_law_curvature out = {0.0, 0.0};
    if (!(vi_damped_hertz_force(D, delta, rate, V_i).F > 0.0)) return out;
    double sq = sqrt(delta);
    if (D->formula == VI_DAMP_EXACT) {
        double q = sqrt(sq) / delta; /* delta^(-3/4) */
        out.d2F_ddelta2 = 0.75 * D->K / sq - 0.1875 * D->alpha_c * rate * q / delta;
        out.d2F_ddelta_drate = 0.25 * D->alpha_c * q;
    } else {
        double b = damping_per_speed(D, V_i);
        out.d2F_ddelta2 = 0.75 * D->K / sq * (1.0 + b * rate);
        out.d2F_ddelta_drate = 1.5 * D->K * sq * b;
    }
    return out;
}

vi_law_guard vi_damped_hertz_guard(const vi_damped_hertz *D, double delta, double rate, double V_i)
{
    if (D->formula == VI_DAMP_EXACT) {
        double d = delta > 0.0 ? delta : 0.0, q = sqrt(sqrt(d));
        return (vi_law_guard){D->K * d * q + D->alpha_c * rate, 1.25 * D->K * q, D->alpha_c};
    }
    double b = damping_per_speed(D, V_i);
    return (vi_law_guard){1.0 + b * rate, 0.0, b};
}

/* ---- linear spring-dashpot ----------------------------------------------------------------------- */

/* below VI_ZETA_CRITICAL_BAND of critical damping, the overdamped form is evaluated at its limit
 * (gamma -> 0: e -> exp(-2), omega t_c -> 2), where acosh loses its digits */
#define VI_ZETA_CRITICAL_BAND 1e-12

double vi_linear_restitution(double zeta)
{
    if (!(zeta > 0.0)) return 1.0;
    if (zeta < 1.0) {
        double b = asin(zeta);
        return exp(-tan(b) * (VI_PI - 2.0 * b));
    }
    if (zeta - 1.0 < VI_ZETA_CRITICAL_BAND) return exp(-2.0);
    double g = acosh(zeta);
    return exp(-2.0 * g - 2.0 * g * exp(-g) / sinh(g));
}

double vi_linear_contact_time(double zeta)
{
    if (!(zeta > 0.0)) return VI_PI;
    if (zeta < 1.0) {
        double b = asin(zeta);
        return (VI_PI - 2.0 * b) / cos(b);
    }
    if (zeta - 1.0 < VI_ZETA_CRITICAL_BAND) return 2.0;
    double g = acosh(zeta);
    return 2.0 * g / sinh(g);
}

static double linear_residual(double zeta, const void *ctx)
{
    return vi_linear_restitution(zeta) - *(const double *)ctx;
}

#define VI_ZETA_TOL 1e-15

int vi_linear_zeta(double e, double *zeta)
{
    if (!(e > 0.0 && e <= 1.0)) return -1;
    if (e == 1.0) {
        *zeta = 0.0;
        return 0;
    }
    /* e(zeta) < exp(-2 acosh(zeta)) < 1/zeta^2 above critical damping, and e(1) = exp(-2) */
    double hi = fmax(1.0, 1.0 / sqrt(e));
    *zeta = root_bracketed(linear_residual, &e, 0.0, hi, VI_ZETA_TOL * hi);
    return 0;
}

int vi_linear_setup(vi_linear_law *L, double k, double m, double e)
{
    double zeta;
    if (!(k > 0.0 && m > 0.0) || vi_linear_zeta(e, &zeta) != 0) return -1;
    L->k = k;
    L->c = 2.0 * zeta * sqrt(m * k);
    return 0;
}

vi_law_force vi_linear_force(const vi_linear_law *L, double delta, double rate)
{
    vi_law_force out = {0.0, 0.0, 0.0};
    double f = L->k * delta + L->c * rate;
    if (delta > 0.0 && f > 0.0) out = (vi_law_force){f, L->k, L->c};
    return out;
}

vi_law_guard vi_linear_guard(const vi_linear_law *L, double delta, double rate)
{
    return (vi_law_guard){L->k * delta + L->c * rate, L->k, L->c};
}

/* ---- Thornton ------------------------------------------------------------------------------------- */

/* the slope of the plastic branch, pi p_Y R* = 1.5 F_Y/delta_Y [N/m] */
static double thornton_slope(const vi_johnson *J) { return 1.5 * J->F_Y / J->delta_Y; }

double vi_thornton_load(const vi_johnson *J, double delta)
{
    if (delta <= J->delta_Y) {
        double s = delta / J->delta_Y;
        return s > 0.0 ? J->F_Y * s * sqrt(s) : 0.0;
    }
    return J->F_Y + thornton_slope(J) * (delta - J->delta_Y);
}

double vi_thornton_load_stiffness(const vi_johnson *J, double delta)
{
    if (delta <= J->delta_Y) {
        double s = delta / J->delta_Y;
        return s > 0.0 ? thornton_slope(J) * sqrt(s) : 0.0;
    }
    return thornton_slope(J);
}

double vi_thornton_load_work(const vi_johnson *J, double delta)
{
    double hertz_part = 0.4 * J->F_Y * J->delta_Y; /* integral of Hertz from 0 to delta_Y */
    if (delta <= J->delta_Y) {
        double s = delta / J->delta_Y;
        return s > 0.0 ? hertz_part * s * s * sqrt(s) : 0.0;
    }
    double d = delta - J->delta_Y;
    return hertz_part + J->F_Y * d + 0.5 * thornton_slope(J) * d * d;
}

double vi_thornton_load_indentation(const vi_johnson *J, double F)
{
    if (F <= J->F_Y) return F > 0.0 ? J->delta_Y * cbrt((F / J->F_Y) * (F / J->F_Y)) : 0.0;
    return J->delta_Y + (F - J->F_Y) / thornton_slope(J);
}

double vi_thornton_load_stiffness_rate(const vi_johnson *J, double delta)
{
    return delta <= J->delta_Y && delta > 0.0 ? 0.75 * J->F_Y / (J->delta_Y * sqrt(delta * J->delta_Y)) : 0.0;
}

vi_unload_curve vi_thornton_unload_curve(const vi_johnson *J, double delta_c)
{
    vi_unload_curve U;
    U.delta_c = delta_c;
    if (delta_c <= J->delta_Y) {
        U.Rbar = J->R_star;
        U.delta_r = delta_c;
    } else {
        /* a_p^2 = (2 F_c + F_Y)/(2 pi p_Y) with 2 pi p_Y = 3 F_Y/(R* delta_Y) and F_c on the line: R* delta_c */
        double F_c = vi_thornton_load(J, delta_c), ap2 = J->R_star * delta_c;
        U.Rbar = 4.0 * J->E_star * ap2 * sqrt(ap2) / (3.0 * F_c);
        U.delta_r = ap2 / U.Rbar; /* Hertz: a^2 = Rbar delta_r */
    }
    U.delta_f = delta_c - U.delta_r;
    U.Kbar = vi_hertz_constant(J->E_star, U.Rbar);
    return U;
}

vi_unload_rates vi_thornton_unload_rates(const vi_johnson *J, double delta_c)
{
    if (delta_c <= J->delta_Y) return (vi_unload_rates){0.0, 1.0};
    vi_unload_curve U = vi_thornton_unload_curve(J, delta_c);
    double s = thornton_slope(J) / vi_thornton_load(J, delta_c); /* dF_c/F_c per m */
    vi_unload_rates r;
    r.Rbar = U.Rbar * (1.5 / delta_c - s);
    r.delta_r = U.delta_r * (s - 0.5 / delta_c);
    return r;
}
