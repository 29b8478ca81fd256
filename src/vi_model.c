/* vi_model.c - hybrid model: modes, right-hand side, guards, events; equations in vi_model.h. */
#include "vi_model.h"

#include <math.h>
#include <stdio.h>

static int is_johnson_fixed(const vi_model *M) { return M->law == VI_ContactModel_johnson && !M->moving; }

/* Net load pressing the mass down, W(t) = P + m g - F_ext(t) [N]. */
static double net_load(const vi_model *M, double t) { return M->W0 - vi_ramp_at(&M->F_ext, t); }

#define CHECK(cond, ...)                                 \
    do {                                                 \
        if (!(cond)) {                                   \
            snprintf(msg, msg_size, __VA_ARGS__);        \
            return -1;                                   \
        }                                                \
    } while (0)

int vi_model_setup(vi_model *M, const vi_parameters *p, double t0, char *msg, size_t msg_size)
{
    CHECK(p->R1 > 0.0 || p->R2 > 0.0, "R1 = R2 = 0: two planes have no point contact; give a radius");

    M->law = p->contact_model;
    M->moving = p->moving_contact != 0;
    M->unloading = p->unloading == VI_Unloading_continuous ? VI_UNLOAD_CONTINUOUS : VI_UNLOAD_PAPER;
    M->m = p->m;
    M->W0 = p->P + p->m * p->g;
    M->J.E_star = vi_effective_modulus(p->E1, p->nu1, p->E2, p->nu2);
    M->J.R_star = vi_effective_radius(p->R1, p->R2);
    M->J.theta_Y = p->theta_Y;
    M->K = vi_hertz_constant(M->J.E_star, M->J.R_star);
    M->J.F_Y = vi_yield_force(p->yield_formula == VI_YieldFormula_printed ? VI_YIELD_PRINTED : VI_YIELD_TEXTBOOK,
                              p->theta_Y, p->Y, M->J.R_star, M->J.E_star);
    M->J.delta_Y = vi_hertz_indentation(M->K, M->J.F_Y);
    M->k_lin = M->J.F_Y / M->J.delta_Y;
    M->a = p->a;
    M->omega = 2.0 * VI_PI * p->f;
    M->t0 = t0;
    M->phi0 = 0.0;
    M->t_phi = t0;
    M->profile = NULL;
    M->V = M->x0 = 0.0;
    CHECK(isfinite(M->W0) && isfinite(M->K) && M->K > 0.0 && isfinite(M->J.F_Y) && M->J.F_Y > 0.0 &&
              M->J.delta_Y > 0.0 && isfinite(M->k_lin) && M->k_lin > 0.0,
          "the parameters give no finite positive contact stiffness or yield force (E* = %g Pa, R* = %g m, "
          "F_Y = %g N, delta_Y = %g m)", M->J.E_star, M->J.R_star, M->J.F_Y, M->J.delta_Y);
    return 0;
}

double vi_model_phase(const vi_model *M, double t) { return M->phi0 + M->omega * (t - M->t_phi); }

int vi_model_excitation_differs(const vi_model *M, double a, double f) { return a != M->a || 2.0 * VI_PI * f != M->omega; }

void vi_model_set_excitation(vi_model *M, double t, double x[2], double a, double f)
{
    double ph = vi_model_phase(M, t), c = cos(ph);
    x[0] += (a - M->a) * (c - 1.0); /* the platform moves, the mass does not */
    M->a = a;
    M->phi0 = fmod(ph, 2.0 * VI_PI);
    M->t_phi = t;
    M->omega = 2.0 * VI_PI * f;
}

/* ---- rolling over a profile ------------------------------------------------------------------ */

double vi_model_rolling_position(const vi_model *M, double t) { return M->x0 + M->V * (t - M->t0); }

int vi_model_set_rolling(vi_model *M, const vi_profile *profile, double V, double x0, char *msg, size_t n)
{
    if (profile && !vi_profile_periodic(profile) &&
        !(x0 >= vi_profile_x_first(profile) && x0 <= vi_profile_x_last(profile))) {
        snprintf(msg, n, "x0 = %g m lies outside the profile [%g, %g] m (set profile_periodic to repeat it)", x0,
                 vi_profile_x_first(profile), vi_profile_x_last(profile));
        return -1;
    }
    M->profile = profile;
    M->V = V;
    M->x0 = x0;
    return 0;
}

/* At most this many ulp steps round a breakpoint time past its kink (a few suffice). */
#define VI_BREAKPOINT_NUDGES 64

double vi_model_next_breakpoint(const vi_model *M, double t)
{
    if (!M->profile || M->V == 0.0) return INFINITY;
    int dir = M->V > 0.0 ? 1 : -1;
    double xk = vi_profile_next_kink(M->profile, vi_model_rolling_position(M, t), dir);
    if (!isfinite(xk)) return INFINITY;
    double tk = M->t0 + (xk - M->x0) / M->V;
    for (int i = 0; i < VI_BREAKPOINT_NUDGES; i++) { /* position past the kink: the piece after it */
        double pos = vi_model_rolling_position(M, tk);
        if (dir > 0 ? pos >= xk : pos < xk) break;
        tk = nextafter(tk, INFINITY);
    }
    return tk > t ? tk : nextafter(t, INFINITY);
}

int vi_model_breakpoint(vi_model *M, double t, double x[2])
{
    vi_model_freeze(M, t, x);
    return vi_model_resolve(M, t, x);
}

double vi_model_rolling_limit(const vi_model *M, char *msg, size_t n)
{
    if (!M->profile || vi_profile_periodic(M->profile) || M->V == 0.0) return INFINITY;
    double end = M->V > 0.0 ? vi_profile_x_last(M->profile) : vi_profile_x_first(M->profile);
    double t = M->t0 + (end - M->x0) / M->V;
    snprintf(msg, n, "t = %.17g s: the rolling position x0 + V (t - t_start) = %.17g m reaches the end of the profile "
             "(%s = %g m); the profile does not go on beyond it (set profile_periodic to repeat it)", t,
             vi_model_rolling_position(M, t), M->V > 0.0 ? "x_last" : "x_first", end);
    return t;
}

/* Platform position and its first three time derivatives at t: y[0..3] = yC, yC', yC'', yC'''. */
static void platform(const vi_model *M, double t, double y[4])
{
    double ph = vi_model_phase(M, t), c = cos(ph), s = sin(ph), aw = M->a * M->omega;
    y[0] = vi_ramp_at(&M->yC_in, t) + M->a * (c - 1.0);
    y[1] = M->yC_in.du - aw * s;
    y[2] = -aw * M->omega * c;
    y[3] = aw * M->omega * M->omega * s;
    if (M->profile) { /* yb(x0 + V (t - t0)): d/dt = V d/dx */
        double b[4], V = M->V;
        vi_profile_eval(M->profile, vi_model_rolling_position(M, t), b);
        y[0] += b[0], y[1] += V * b[1], y[2] += V * V * b[2], y[3] += V * V * V * b[3];
    }
}

double vi_model_platform(const vi_model *M, double t, double *dyC, double *ddyC)
{
    double y[4];
    platform(M, t, y);
    if (dyC) *dyC = y[1];
    if (ddyC) *ddyC = y[2];
    return y[0];
}

/* Force holding a sticking mass on the platform: F_hold = W(t) + m yC''(t). */
static double hold_force(const vi_model *M, double t)
{
    double y[4];
    platform(M, t, y);
    return net_load(M, t) + M->m * y[2];
}

/* Its rate F_hold' = W' + m yC''' = -F_ext' + m yC''' [N/s]: with delta' = 0 it is m delta''' plus
 * the force law's rate, so it breaks a tie of F_hold with a fixed force (next time derivative). */
static double hold_force_rate(const vi_model *M, double t)
{
    double y[4];
    platform(M, t, y);
    return -M->F_ext.du + M->m * y[3];
}

double vi_model_force(const vi_model *M, double t, const double x[2])
{
    double d = x[0];
    switch (M->mode) {
    case VI_Mode_elastic:
        if (M->law == VI_ContactModel_lepp) return d > M->delta_p ? M->k_lin * (d - M->delta_p) : 0.0;
        if (M->law == VI_ContactModel_johnson) return vi_johnson_load(&M->J, d);
        return vi_hertz_force(M->K, d);
    case VI_Mode_plastic:
        return M->law == VI_ContactModel_lepp ? M->J.F_Y : vi_johnson_load(&M->J, d);
    case VI_Mode_unload:
        return vi_unload_force(&M->U, d);
    case VI_Mode_stick:
        return hold_force(M, t);
    default:
        return 0.0;
    }
}

void vi_model_rhs(const vi_model *M, double t, const double x[2], double dx[2])
{
    double dyC, ddyC;
    vi_model_platform(M, t, &dyC, &ddyC);
    if (M->mode == VI_Mode_stick) { /* Filippov sliding on delta = delta_c: the mass moves with the platform */
        dx[0] = 0.0;
        dx[1] = ddyC;
        return;
    }
    dx[0] = dyC - x[1];
    dx[1] = (vi_model_force(M, t, x) - net_load(M, t)) / M->m;
}

double vi_model_stiffness_over_mass(const vi_model *M, double t, const double x[2])
{
    (void)t;
    double d = x[0], k = 0.0;
    switch (M->mode) {
    case VI_Mode_elastic:
        k = M->law == VI_ContactModel_lepp      ? (d > M->delta_p ? M->k_lin : 0.0)
            : M->law == VI_ContactModel_johnson ? vi_johnson_load_stiffness(&M->J, d)
                                                : vi_hertz_stiffness(M->K, d);
        break;
    case VI_Mode_plastic: k = M->law == VI_ContactModel_lepp ? 0.0 : vi_johnson_load_stiffness(&M->J, d); break;
    case VI_Mode_unload: k = vi_unload_stiffness(&M->U, d); break;
    default: break;
    }
    return k / M->m;
}

void vi_model_jacobian(const vi_model *M, double t, const double x[2], double j[4])
{
    int stick = M->mode == VI_Mode_stick;
    j[0] = 0.0, j[1] = stick ? 0.0 : -1.0;
    j[2] = vi_model_stiffness_over_mass(M, t, x), j[3] = 0.0; /* 0 in stick */
}

/* Indentation at which the bodies touch: 0, the permanent set delta_f (Johnson) or delta_p (LEPP). */
static double contact_surface(const vi_model *M)
{
    if (M->law == VI_ContactModel_lepp) return M->delta_p;
    if (is_johnson_fixed(M) && M->yielded) return M->U.delta_f;
    return 0.0;
}

/* Indentation at which the virgin elastic branch yields (mode 1 -> 2); +inf for Hertz. */
static double yield_surface(const vi_model *M)
{
    if (M->law == VI_ContactModel_lepp) return M->delta_p + M->J.delta_Y;
    if (M->law == VI_ContactModel_johnson) return M->J.delta_Y;
    return INFINITY;
}

void vi_model_guards(const vi_model *M, double t, const double x[2], double g[VI_NGUARDS])
{
    double d = x[0], dyC;
    g[0] = g[1] = 1.0; /* inactive */
    switch (M->mode) {
    case VI_Mode_free: g[0] = contact_surface(M) - d; break;
    case VI_Mode_elastic:
        g[0] = d - contact_surface(M);
        if (M->law != VI_ContactModel_hertz) g[1] = yield_surface(M) - d;
        break;
    case VI_Mode_plastic:
        if (M->moving && M->law == VI_ContactModel_johnson) {
            g[0] = d - M->J.delta_Y;
        } else {
            vi_model_platform(M, t, &dyC, NULL);
            g[0] = dyC - x[1]; /* delta' */
        }
        break;
    case VI_Mode_unload:
        g[0] = d - M->U.delta_f;
        g[1] = M->U.delta_c - d;
        break;
    case VI_Mode_stick: {
        double F_hold = hold_force(M, t);
        g[0] = vi_johnson_load(&M->J, M->U.delta_c) - F_hold;
        g[1] = F_hold - vi_unload_force(&M->U, M->U.delta_c);
        break;
    }
    default: break;
    }
}

/* LEPP plastic flow to x[0]: the permanent set follows, delta_p = delta - delta_Y; x[0] is then
 * rounded onto the yield surface so that its guard is exactly zero, never an ulp below. */
static void lepp_flow_to(vi_model *M, double x[2])
{
    M->delta_p = x[0] - M->J.delta_Y;
    x[0] = yield_surface(M);
}

void vi_model_freeze(vi_model *M, double t, double x[2])
{
    if (M->mode == VI_Mode_plastic && is_johnson_fixed(M))
        M->U = vi_johnson_unload_curve(&M->J, M->unloading, x[0]);
    else if (M->mode == VI_Mode_plastic && M->law == VI_ContactModel_lepp)
        lepp_flow_to(M, x);
    else if (M->mode == VI_Mode_stick)
        vi_model_platform(M, t, &x[1], NULL);
}

/* The sign of the first nonzero of (position, rate, acceleration, jerk) relative to a surface is
 * positive. With delta' = 0 the acceleration of delta is (F_hold - F)/m and its jerk F_hold'/m (F
 * fixed on the surface), so callers pass force differences and F_hold' for the last two. */
static int ahead(double pos, double rate, double acc, double jerk)
{
    return pos > 0.0 || (pos == 0.0 && (rate > 0.0 || (rate == 0.0 && (acc > 0.0 || (acc == 0.0 && jerk > 0.0)))));
}

/* Which stick guard an event put exactly on its surface: its force difference counts as 0, so that
 * the next derivative decides (the guard's value at the located root is only nearly 0). */
enum { SNAP_NONE = -1, SNAP_LOAD = 0, SNAP_UNLOAD = 1 };

static int resolve(vi_model *M, double t, double x[2], int snap)
{
    double dyC, d = x[0], F_hold = hold_force(M, t), j = hold_force_rate(M, t);
    vi_model_platform(M, t, &dyC, NULL);
    double r = dyC - x[1];
    int mode = VI_Mode_free;
    switch (M->law) {
    case VI_ContactModel_hertz: mode = ahead(d, r, F_hold, j) ? VI_Mode_elastic : VI_Mode_free; break;
    case VI_ContactModel_lepp:
        if (ahead(d - M->delta_p, r, F_hold, j)) {
            if (d > yield_surface(M)) lepp_flow_to(M, x); /* pushed beyond yield: it flowed */
            mode = ahead(x[0] - yield_surface(M), r, F_hold - M->J.F_Y, j) ? VI_Mode_plastic : VI_Mode_elastic;
        }
        break;
    case VI_ContactModel_johnson:
        if (!M->yielded || M->moving) {
            if (!ahead(d, r, F_hold, j)) break;
            mode = ahead(d - M->J.delta_Y, r, F_hold - M->J.F_Y, j) ? VI_Mode_plastic : VI_Mode_elastic;
            if (mode == VI_Mode_elastic || M->moving) break;
            M->yielded = 1;
            M->U = vi_johnson_unload_curve(&M->J, M->unloading, d > M->J.delta_Y ? d : M->J.delta_Y);
        }
        if (d > M->U.delta_c) M->U = vi_johnson_unload_curve(&M->J, M->unloading, d); /* pushed deeper */
        {
            double F_load = vi_johnson_load(&M->J, M->U.delta_c), F_unload = vi_unload_force(&M->U, d);
            double dF_load = snap == SNAP_LOAD ? 0.0 : F_hold - F_load;
            double dF_unload = snap == SNAP_UNLOAD ? 0.0 : F_hold - F_unload;
            if (ahead(d - M->U.delta_c, r, dF_load, j))
                mode = VI_Mode_plastic;
            else if (d == M->U.delta_c && r == 0.0 && ahead(0.0, 0.0, dF_unload, j) && M->unloading == VI_UNLOAD_PAPER)
                mode = VI_Mode_stick; /* F_unload < F_hold <= F_load: neither branch is consistent */
            else if (ahead(d - M->U.delta_f, r, dF_unload, j))
                mode = VI_Mode_unload;
        }
        break;
    default: break;
    }
    if (M->mode == VI_Mode_free && mode != VI_Mode_free) M->n_impacts++;
    M->mode = mode;
    return mode;
}

int vi_model_resolve(vi_model *M, double t, double x[2]) { return resolve(M, t, x, SNAP_NONE); }

int vi_model_event(vi_model *M, double t, double x[2], int fired)
{
    vi_model_freeze(M, t, x);
    switch (M->mode) {
    case VI_Mode_free: x[0] = contact_surface(M); break;
    case VI_Mode_elastic: x[0] = fired == 0 ? contact_surface(M) : yield_surface(M); break;
    case VI_Mode_plastic:
        if (M->moving && M->law == VI_ContactModel_johnson) x[0] = M->J.delta_Y;
        else vi_model_platform(M, t, &x[1], NULL); /* turning point: delta' = 0 */
        break;
    case VI_Mode_unload: x[0] = fired == 0 ? M->U.delta_f : M->U.delta_c; break;
    case VI_Mode_stick: x[0] = M->U.delta_c; return resolve(M, t, x, fired == 0 ? SNAP_LOAD : SNAP_UNLOAD);
    default: break;
    }
    return vi_model_resolve(M, t, x);
}

/* Linearised contact stiffness at the static load W [N/m]. */
static double static_stiffness(const vi_model *M, double W)
{
    if (W <= 0.0) return 0.0;
    switch (M->law) {
    case VI_ContactModel_hertz: return vi_hertz_stiffness(M->K, vi_hertz_indentation(M->K, W));
    case VI_ContactModel_lepp: return M->k_lin;
    default: {
        double d = vi_johnson_load_indentation(&M->J, W);
        if (M->moving || d <= M->J.delta_Y) return vi_johnson_load_stiffness(&M->J, d);
        vi_unload_curve U = vi_johnson_unload_curve(&M->J, M->unloading, d); /* small oscillations unload */
        return vi_unload_stiffness(&U, d);
    }
    }
}

/* Indentation at rest under W > 0 on the Johnson virgin curve, with F(d) >= W where rounding allows,
 * so that a pre-loaded start does not see a spurious push into the material. The inverse is
 * accurate to a few ulps; at most VI_STATIC_NUDGES steps of 1, 2, 4, ... ulps close the gap. When F
 * cannot reach W (its value is denormal: loads below about 1e-300 N), d stays within 2^16 ulps. */
#define VI_STATIC_NUDGES 16
static double johnson_static_indentation(const vi_johnson *J, double W)
{
    double d = vi_johnson_load_indentation(J, W), step = nextafter(d, INFINITY) - d;
    for (int i = 0; i < VI_STATIC_NUDGES && vi_johnson_load(J, d) < W; i++, step *= 2.0) d += step;
    return d;
}

void vi_model_initial_state(vi_model *M, int init, double v0, double t0, double x[2])
{
    M->f_contact = sqrt(static_stiffness(M, net_load(M, t0)) / M->m) / (2.0 * VI_PI);
    M->mode = VI_Mode_free;
    M->yielded = 0;
    M->U = (vi_unload_curve){0};
    M->delta_p = 0.0;
    x[0] = 0.0;
    x[1] = v0;
    if (init == VI_Init_static) {
        double W = net_load(M, t0), d = 0.0;
        if (W > 0.0) {
            if (M->law == VI_ContactModel_hertz) d = vi_hertz_indentation(M->K, W);
            else if (M->law == VI_ContactModel_johnson) d = johnson_static_indentation(&M->J, W);
            else d = W <= M->J.F_Y ? W / M->k_lin : M->J.delta_Y; /* beyond F_Y: flows from the start */
        }
        if (is_johnson_fixed(M) && d > M->J.delta_Y) { /* plastically pre-loaded */
            M->yielded = 1;
            M->U = vi_johnson_unload_curve(&M->J, M->unloading, d);
        }
        x[0] = d;
        vi_model_platform(M, t0, &x[1], NULL);
    }
    vi_model_resolve(M, t0, x);
    M->n_impacts = 0;
}

/* Tangent stiffness of the virgin curve at delta > 0 [N/m]. */
static double virgin_stiffness(const vi_model *M, double d)
{
    if (M->law == VI_ContactModel_lepp) return M->k_lin;
    if (M->law == VI_ContactModel_johnson) return vi_johnson_load_stiffness(&M->J, d);
    return vi_hertz_stiffness(M->K, d);
}

void vi_model_scales(const vi_model *M, const double x0[2], double *L, double *V)
{
    double W = net_load(M, M->t0), dyC, l = 0.0;
    vi_model_platform(M, M->t0, &dyC, NULL);
    if (W > 0.0) {
        double dW = M->law == VI_ContactModel_hertz     ? vi_hertz_indentation(M->K, W)
                    : M->law == VI_ContactModel_johnson ? vi_johnson_load_indentation(&M->J, W)
                                                        : fmin(W / M->k_lin, M->J.delta_Y);
        l = fmax(l, dW);
    }
    if (M->law != VI_ContactModel_hertz) l = fmax(l, M->J.delta_Y);
    double v = fabs(dyC - x0[1]);
    if (!(l > 0.0 || v > 0.0)) /* only the excitation moves anything: harmonic and rolling */
        v = fabs(M->a) * M->omega + (M->profile ? fabs(M->V) * vi_profile_max_slope(M->profile) : 0.0);
    if (v > 0.0 && isfinite(v)) {
        double dv = M->law == VI_ContactModel_lepp
                        ? v * sqrt(M->m) / sqrt(M->k_lin)
                        : pow(15.0 * M->m * v * v / (16.0 * M->J.E_star * sqrt(M->J.R_star)), 0.4);
        if (isfinite(dv)) l = fmax(l, dv);
    }
    if (!(l > 0.0)) l = VI_SCALE_FALLBACK * M->J.R_star;
    *L = l;
    *V = l * (sqrt(virgin_stiffness(M, l)) / sqrt(M->m));
}

/* ---- validity ------------------------------------------------------------------------------ */

int vi_model_validity(const vi_model *M, double R1, double t, const double x[2], int skip, char *msg, size_t n)
{
    double R = M->J.R_star, limit = VI_VALIDITY_RADIUS * VI_VALIDITY_RADIUS * R;
    double d = fmax(M->mode == VI_Mode_free ? 0.0 : x[0], M->yielded ? M->U.delta_c : 0.0);
    if (!(skip & VI_INVALID_INDENTATION) && d > limit) {
        snprintf(msg, n, "t = %.17g s: the indentation %g m exceeds %g R* = %g m (contact radius sqrt(R* delta) = %g m "
                 "> %g R*): the contact laws (paper eqs. 2-4) assume a contact radius small against R*, so the "
                 "results leave the model's range of validity", t, d, VI_VALIDITY_RADIUS * VI_VALIDITY_RADIUS, limit,
                 sqrt(R * d), VI_VALIDITY_RADIUS);
        return VI_INVALID_INDENTATION;
    }
    if (!(skip & VI_INVALID_AMPLITUDE) && fabs(M->a) > R) {
        snprintf(msg, n, "t = %.17g s: the excitation amplitude a = %g m exceeds R* = %g m: the contact laws (paper "
                 "eqs. 2-4) describe a local contact, with every displacement small against R*, so the results "
                 "leave the model's range of validity", t, M->a, R);
        return VI_INVALID_AMPLITUDE;
    }
    double span = M->profile ? vi_profile_height_span(M->profile) : 0.0;
    if (!(skip & VI_INVALID_PROFILE) && span > R1) {
        snprintf(msg, n, "t = %.17g s: the heights of profile_file span %g m, more than the rolling radius R1 = %g m: "
                 "rolling over a profile (paper Fig. 1b) assumes a roughness small against the wheel, so the results "
                 "leave the model's range of validity", t, span, R1);
        return VI_INVALID_PROFILE;
    }
    return 0;
}

int vi_model_option_warnings(const vi_parameters *p, char *msg, size_t n)
{
    int count = 0, johnson = p->contact_model == VI_ContactModel_johnson;
    size_t used = 0;
    msg[0] = '\0';
#define OPTION(cond, text)                                                               \
    if (cond) {                                                                          \
        int k = snprintf(msg + used, used < n ? n - used : 0, "%s" text, count ? "; " : ""); \
        used += k > 0 ? (size_t)k : 0;                                                   \
        count++;                                                                         \
    }
    OPTION(p->moving_contact && !johnson, "moving_contact = true is ignored: only the Johnson law has a moving contact point")
    OPTION(p->unloading == VI_Unloading_continuous && !(johnson && !p->moving_contact),
           "unloading = continuous is ignored: only Johnson with a fixed contact point unloads on eq. 4")
    OPTION(p->yield_formula == VI_YieldFormula_printed && p->contact_model == VI_ContactModel_hertz,
           "yield_formula = printed is ignored by the Hertz law (it changes only the calculated F_Y, delta_Y)")
    OPTION(p->v0 != 0.0 && p->init == VI_Init_static, "v0 is ignored by a static start (init = static)")
    OPTION(!p->profile_file[0] && (p->V != 0.0 || p->x0 != 0.0 || p->profile_periodic),
           "V, x0 and profile_periodic are ignored without a profile_file")
#undef OPTION
    return count;
}

/* ---- validity of a saved model (doc/model.md section 7.6) ---------------------------------- */

#define BAD(...) return snprintf(msg, n, __VA_ARGS__), -1

/* a and b agree to rel relative to the larger (both finite). */
static int close_rel(double a, double b, double rel) { return fabs(a - b) <= rel * fmax(fabs(a), fabs(b)); }

#define CONSISTENCY_TOL 1e-9

static int check_constants(const vi_model *M, char *msg, size_t n)
{
    const struct { const char *name; double value; int positive; } c[] = {
        {"m", M->m, 1},           {"W0", M->W0, 0},         {"K", M->K, 1},
        {"E_star", M->J.E_star, 1}, {"R_star", M->J.R_star, 1}, {"theta_Y", M->J.theta_Y, 1},
        {"F_Y", M->J.F_Y, 1},     {"delta_Y", M->J.delta_Y, 1}, {"k_lin", M->k_lin, 1},
        {"a", M->a, 0},           {"omega", M->omega, 0},   {"t0", M->t0, 0},
        {"phi0", M->phi0, 0},     {"t_phi", M->t_phi, 0},   {"V", M->V, 0},
        {"x0", M->x0, 0},
        {"f_contact", M->f_contact, 0}};
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        if (!isfinite(c[i].value)) BAD("model constant %s = %g is not finite", c[i].name, c[i].value);
        if (c[i].positive && !(c[i].value > 0.0)) BAD("model constant %s = %g is not positive", c[i].name, c[i].value);
    }
    if (M->omega < 0.0) BAD("model constant omega = %g is negative", M->omega);
    if (M->f_contact < 0.0) BAD("model constant f_contact = %g is negative", M->f_contact);
    if (!close_rel(M->K, vi_hertz_constant(M->J.E_star, M->J.R_star), CONSISTENCY_TOL))
        BAD("model constant K = %g does not match 4/3 E* sqrt(R*)", M->K);
    if (!close_rel(M->J.F_Y, vi_hertz_force(M->K, M->J.delta_Y), CONSISTENCY_TOL))
        BAD("model constant delta_Y = %g does not match F_Y = K delta_Y^1.5", M->J.delta_Y);
    if (!close_rel(M->k_lin, M->J.F_Y / M->J.delta_Y, CONSISTENCY_TOL))
        BAD("model constant k_lin = %g does not match F_Y/delta_Y", M->k_lin);
    const vi_ramp *r[2] = {&M->yC_in, &M->F_ext};
    const char *rn[2] = {"yC_in", "F_ext"};
    for (int i = 0; i < 2; i++)
        if (!isfinite(r[i]->u) || !isfinite(r[i]->du) || !isfinite(r[i]->t))
            BAD("model input ramp %s (%g, %g, %g) is not finite", rn[i], r[i]->u, r[i]->du, r[i]->t);
    return 0;
}

static int check_memory(const vi_model *M, char *msg, size_t n)
{
    if (M->yielded != 0 && M->yielded != 1) BAD("model flag yielded = %d is not 0 or 1", M->yielded);
    if (M->n_impacts < 0) BAD("n_impacts = %ld is negative", M->n_impacts);
    if (!isfinite(M->delta_p)) BAD("delta_p = %g is not finite", M->delta_p);
    if (M->law == VI_ContactModel_lepp ? M->delta_p < 0.0 : M->delta_p != 0.0)
        BAD("delta_p = %g is impossible for contact_model %d", M->delta_p, M->law);
    const vi_unload_curve *U = &M->U;
    const double u[5] = {U->delta_c, U->Rbar, U->delta_r, U->delta_f, U->Kbar};
    if (!M->yielded) {
        for (int i = 0; i < 5; i++)
            if (u[i] != 0.0) BAD("unloading curve (delta_c = %g, Rbar = %g) present although yielded = 0", u[0], u[1]);
        return 0;
    }
    if (!is_johnson_fixed(M)) BAD("yielded = 1 is impossible for contact_model %d (moving %d)", M->law, M->moving);
    for (int i = 0; i < 5; i++)
        if (!isfinite(u[i])) BAD("unloading curve: a value (delta_c %g, Rbar %g, delta_r %g, delta_f %g, Kbar %g) is not "
                                 "finite", u[0], u[1], u[2], u[3], u[4]);
    if (!(U->delta_c >= M->J.delta_Y * (1.0 - CONSISTENCY_TOL)))
        BAD("delta_c = %g is below delta_Y = %g", U->delta_c, M->J.delta_Y);
    if (!(U->Rbar > 0.0)) BAD("Rbar = %g is not positive", U->Rbar);
    if (!(U->delta_f <= U->delta_c)) BAD("delta_f = %g is above delta_c = %g", U->delta_f, U->delta_c);
    vi_unload_curve E = vi_johnson_unload_curve(&M->J, M->unloading, U->delta_c);
    if (!close_rel(U->Rbar, E.Rbar, CONSISTENCY_TOL)) BAD("Rbar = %g does not belong to delta_c (%g)", U->Rbar, E.Rbar);
    if (!close_rel(U->delta_r, E.delta_r, CONSISTENCY_TOL))
        BAD("delta_r = %g does not belong to delta_c (%g)", U->delta_r, E.delta_r);
    if (!(fabs(U->delta_f - E.delta_f) <= CONSISTENCY_TOL * U->delta_c))
        BAD("delta_f = %g does not belong to delta_c (%g)", U->delta_f, E.delta_f);
    if (!close_rel(U->Kbar, E.Kbar, CONSISTENCY_TOL)) BAD("Kbar = %g does not belong to Rbar (%g)", U->Kbar, E.Kbar);
    return 0;
}

/* The mode is allowed for the law and the memory, and no time-free guard is clearly negative. */
static int check_mode(const vi_model *M, const double x[2], char *msg, size_t n)
{
    int mode = M->mode, ok;
    switch (M->law) {
    case VI_ContactModel_hertz: ok = mode == VI_Mode_free || mode == VI_Mode_elastic; break;
    case VI_ContactModel_lepp: ok = mode >= VI_Mode_free && mode <= VI_Mode_plastic; break;
    default:
        if (M->moving) ok = mode >= VI_Mode_free && mode <= VI_Mode_plastic;
        else if (!M->yielded) ok = mode == VI_Mode_free || mode == VI_Mode_elastic;
        else ok = mode == VI_Mode_free || mode == VI_Mode_plastic || mode == VI_Mode_unload ||
                  (mode == VI_Mode_stick && M->unloading == VI_UNLOAD_PAPER);
    }
    if (!ok) BAD("mode = %d is impossible for contact_model %d (moving %d, unloading %d, yielded %d)", mode, M->law,
                 M->moving, M->unloading, M->yielded);
    double d = x[0], tol = VI_CHECK_GUARD_TOL * fmax(fmax(M->J.delta_Y, fabs(d)), fabs(M->U.delta_c));
    double g[2] = {INFINITY, INFINITY};
    switch (mode) {
    case VI_Mode_free: g[0] = contact_surface(M) - d; break;
    case VI_Mode_elastic: g[0] = d - contact_surface(M), g[1] = yield_surface(M) - d; break;
    case VI_Mode_plastic:
        g[0] = M->law == VI_ContactModel_lepp ? d - yield_surface(M)
               : M->moving                    ? d - M->J.delta_Y
                                              : d - M->U.delta_c;
        break;
    case VI_Mode_unload: g[0] = d - M->U.delta_f, g[1] = M->U.delta_c - d; break;
    default: g[0] = d - M->U.delta_c, g[1] = M->U.delta_c - d; break; /* stick: on delta_c */
    }
    for (int i = 0; i < 2; i++)
        if (g[i] < -tol)
            BAD("mode %d does not fit the state: delta = %.17g m lies %g m beyond its surface %d (tolerance %g m)", mode,
                d, -g[i], i, tol);
    return 0;
}

int vi_model_check(const vi_model *M, const double x[2], char *msg, size_t n)
{
    if (!isfinite(x[0]) || !isfinite(x[1])) BAD("state (delta %g, v %g) is not finite", x[0], x[1]);
    if (M->law == 0) { /* never set up */
        if (M->mode != 0 || M->yielded != 0 || M->n_impacts != 0 || M->delta_p != 0.0)
            BAD("model not set up (law = 0) but with a discrete state (mode %d)", M->mode);
        return 0;
    }
    if (M->law < VI_ContactModel_hertz || M->law > VI_ContactModel_lepp)
        BAD("contact law = %d is not hertz (1), johnson (2) or lepp (3)", M->law);
    if (M->moving != 0 && M->moving != 1) BAD("model flag moving = %d is not 0 or 1", M->moving);
    if (M->unloading != VI_UNLOAD_PAPER && M->unloading != VI_UNLOAD_CONTINUOUS)
        BAD("unloading = %d is not paper (1) or continuous (2)", M->unloading);
    if (M->mode < VI_Mode_free || M->mode > VI_Mode_stick) BAD("mode = %d is not in 0..4", M->mode);
    if (check_constants(M, msg, n) < 0 || check_memory(M, msg, n) < 0) return -1;
    return check_mode(M, x, msg, n);
}
#undef BAD

void vi_model_calculated(const vi_model *M, vi_outputs *out)
{
    out->E_star = M->J.E_star;
    out->R_star = M->J.R_star;
    out->F_Y = M->J.F_Y;
    out->delta_Y = M->J.delta_Y;
    out->k_lin = M->k_lin;
    out->f_contact = M->f_contact;
}

void vi_model_outputs(const vi_model *M, double t, const double x[2], vi_outputs *out)
{
    double d = x[0];
    out->yC = vi_model_platform(M, t, NULL, NULL);
    out->F = vi_model_force(M, t, x);
    out->delta = d;
    out->y = out->yC - d;
    out->v = x[1];
    out->contact = M->mode != VI_Mode_free;
    out->mode = M->mode;
    out->n_impacts = (int)M->n_impacts;
    out->delta_c = out->delta_f = out->delta_p = out->W_plastic = 0.0;
    out->Rbar = M->J.R_star;
    if (is_johnson_fixed(M) && M->yielded) {
        vi_unload_curve U = M->mode == VI_Mode_plastic ? vi_johnson_unload_curve(&M->J, M->unloading, d) : M->U;
        out->delta_c = U.delta_c;
        out->delta_f = U.delta_f;
        out->Rbar = U.Rbar;
        /* dissipated = work along the virgin curve - energy the unloading curve gives back */
        out->W_plastic = vi_johnson_load_work(&M->J, U.delta_c) - vi_unload_energy(&U, U.delta_c);
    } else if (M->law == VI_ContactModel_lepp) {
        out->delta_p = M->mode == VI_Mode_plastic ? d - M->J.delta_Y : M->delta_p;
        out->W_plastic = M->J.F_Y * out->delta_p;
    }
}
