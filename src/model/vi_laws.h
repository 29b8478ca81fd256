/*
 * vi_laws.h - the contact laws beyond the paper's three: damped Hertz, the linear spring-dashpot and
 * Thornton's elastic-perfectly-plastic sphere. Pure functions with their partial derivatives; no solver,
 * no FMI. doc/model.md section 2 gives the laws to users; the independent reference is
 * python/vibroimpact/reference/laws.py.
 *
 * SI units: delta the indentation [m] (> 0: overlap), rate = d(delta)/dt [m/s] (> 0: approaching),
 * m the mass [kg], K = 4/3 E* sqrt(R*) [N/m^1.5], forces [N]. The force of a damped law never pulls:
 * F = max(0, f(delta, rate)); where f <= 0 or delta <= 0 the force and its partials are 0, and the bodies
 * separate where f falls through 0 while delta > 0 (vi_*_guard gives a function with the sign of f there).
 *
 *   damped Hertz, exact (Tsuji's form)   f = K delta^1.5 + alpha sqrt(m K) delta^(1/4) rate
 *       By similarity (delta = (m V^2/K)^(2/5) x) an impact at any speed V is x'' = -x^1.5 - alpha x^(1/4) x',
 *       x(0) = 0, x'(0) = 1: its restitution e(alpha) depends on alpha alone; vi_tsuji_alpha inverts it.
 *   damped Hertz, published forms        f = K delta^1.5 (1 + chi rate/V_i), V_i > 0 the approach speed at
 *       the onset of the contact; chi = 3(1 - e)/2 (Hunt-Crossley), 3(1 - e^2)/4 (Lankarani-Nikravesh),
 *       8(1 - e)/(5 e) (Flores). V_i <= 0 (a contact that starts at rest): f = K delta^1.5, undamped.
 *   linear spring-dashpot                f = k delta + c rate, c = 2 zeta sqrt(m k); with the clamp an
 *       impact has the restitution e = exp(-tan(b) (pi - 2 b)), b = asin(zeta) (zeta < 1), and
 *       e = exp(-2 g - 2 g exp(-g)/sinh(g)), zeta = cosh(g) (zeta >= 1); vi_linear_zeta inverts it.
 *   Thornton (J. Appl. Mech. 64, 1997)   Hertz up to delta_Y, then F = F_Y + pi p_Y R* (delta - delta_Y),
 *       p_Y = 3 F_Y/(2 pi R* delta_Y) the maximum Hertz pressure at yield (so the slope is continuous,
 *       1.5 F_Y/delta_Y). Unloading from (delta_c, F_c) is Hertzian, F = 4/3 E* sqrt(Rbar) (delta - delta_f)^1.5,
 *       a_p^2 = (2 F_c + F_Y)/(2 pi p_Y), Rbar = 4 E* a_p^3/(3 F_c), delta_r = (3 F_c/(4 E* sqrt(Rbar)))^(2/3),
 *       delta_f = delta_c - delta_r. Restitution for V > V_Y (1/2 m V_Y^2 = 2/5 F_Y delta_Y), r = V_Y/V:
 *       e = sqrt(6 sqrt(3)/5) sqrt(1 - r^2/6) (r/(r + 2 sqrt(6/5 - r^2/5)))^(1/4).
 */
#ifndef VI_LAWS_H
#define VI_LAWS_H

#include "vi_contact.h"

/* damping_formula: how a damped Hertz law damps */
enum { VI_DAMP_EXACT = 1, VI_DAMP_HUNT_CROSSLEY = 2, VI_DAMP_LANKARANI_NIKRAVESH = 3, VI_DAMP_FLORES = 4 };

/* A force and its partial derivatives. */
typedef struct {
    double F;        /* N */
    double dF_ddelta; /* N/m */
    double dF_drate;  /* N s/m */
} vi_law_force;
/* The second partials of a force: of dF/ddelta with respect to delta [N/m^2] and to the rate [N s/m^2]. */
typedef struct {
    double d2F_ddelta2, d2F_ddelta_drate;
} vi_law_curvature;
/* A guard with the sign of the unclamped force, and its partials (units of g per m and per m/s). */
typedef struct {
    double g, dg_ddelta, dg_drate;
} vi_law_guard;

/* The restitution of the dimensionless Tsuji impact, by a fixed-step integration (about 1e-12 accurate);
 * NaN for alpha above 1e8 (e = 1.25e-16), where the fixed steps are no longer stable, and for a NaN alpha. */
double vi_tsuji_restitution(double alpha);
/* alpha with vi_tsuji_restitution(alpha) = e to 1e-12 (relative), for e in (0, 1]. 0 on success; -1 when
 * e is outside (0, 1] or not finite, or below what the integration reaches (alpha untouched).
 * From e = VI_TSUJI_TABLE_E_MIN to 1 alpha comes from a table (below: vi_tsuji_alpha_solve):
 *     alpha = G(u) (1 - e)/sqrt(e),  u = ln(e/(1 - e)),
 * G smooth and bounded (1.1180 as e -> 0, 0.7118 as e -> 1), a Chebyshev series of degree
 * VI_TSUJI_TABLE_DEGREE on each of VI_TSUJI_TABLE_PIECES pieces of u of width VI_TSUJI_TABLE_WIDTH from
 * VI_TSUJI_TABLE_U_MIN; past the last piece (1 - e < 4.1e-8) G is its value at the end. tools/tsuji_table.c
 * writes the table (src/model/vi_tsuji_table.inc) from vi_tsuji_alpha_solve. */
#define VI_TSUJI_TABLE_U_MIN (-21.0)  /* e = 7.58e-10 */
#define VI_TSUJI_TABLE_WIDTH 2.0
#define VI_TSUJI_TABLE_PIECES 19      /* up to u = 17: 1 - e = 4.14e-8 */
#define VI_TSUJI_TABLE_DEGREE 16
#define VI_TSUJI_TABLE_E_MIN 7.582560422162385e-10 /* 1/(1 + exp(21)) */
int vi_tsuji_alpha(double e, double *alpha);
/* The same by integration: a root search on vi_tsuji_restitution (milliseconds of CPU), alpha to 1e-14
 * (relative above alpha = 1, absolute below). */
int vi_tsuji_alpha_solve(double e, double *alpha);
/* The factor chi of a published form (VI_DAMP_HUNT_CROSSLEY ... VI_DAMP_FLORES) for e in (0, 1]; 0 for
 * any other formula. */
double vi_damping_chi(int formula, double e);

/* The restitution the published form with factor chi > 0 really gives (at every speed): the root e_a of
 * Hunt and Crossley's energy relation chi (1 + e_a) = ln((1 + chi)/(1 - chi e_a)); 1 for chi <= 0. */
double vi_damping_restitution(double chi);

/* A damped Hertz contact, set up once from its parameters. */
typedef struct {
    int formula;    /* VI_DAMP_* */
    double K;       /* N/m^1.5 */
    double alpha_c; /* exact: alpha sqrt(m K) [N s/m^(5/4)]; 0 otherwise */
    double chi;     /* published forms: chi [1]; 0 otherwise */
} vi_damped_hertz;

/* 0 on success; -1 when e is outside (0, 1] or the formula unknown (D untouched). */
int vi_damped_hertz_setup(vi_damped_hertz *D, int formula, double e, double K, double m);
/* Force and partials at (delta, rate); V_i [m/s] the approach speed at the onset (published forms). */
vi_law_force vi_damped_hertz_force(const vi_damped_hertz *D, double delta, double rate, double V_i);
vi_law_curvature vi_damped_hertz_curvature(const vi_damped_hertz *D, double delta, double rate, double V_i);
/* Has the sign of f for delta > 0 and stays finite as delta -> 0 (exact: K delta^(5/4) + alpha_c rate
 * [N/m^(1/4)]; published forms: 1 + chi rate/V_i [1]; undamped: 1). */
vi_law_guard vi_damped_hertz_guard(const vi_damped_hertz *D, double delta, double rate, double V_i);

/* The clamped linear spring-dashpot's restitution for a damping ratio zeta >= 0, its contact time
 * times omega = sqrt(k/m), and the inverse: zeta with restitution e in (0, 1] to 1e-14 (0 on success,
 * -1 when e is outside (0, 1]). */
double vi_linear_restitution(double zeta);
double vi_linear_contact_time(double zeta);
int vi_linear_zeta(double e, double *zeta);

typedef struct {
    double k; /* N/m */
    double c; /* N s/m */
} vi_linear_law;

/* 0 on success; -1 when e is outside (0, 1], k or m not > 0 (L untouched). */
int vi_linear_setup(vi_linear_law *L, double k, double m, double e);
vi_law_force vi_linear_force(const vi_linear_law *L, double delta, double rate);
vi_law_guard vi_linear_guard(const vi_linear_law *L, double delta, double rate); /* f [N] */

/* Thornton's law on the yield limit and elastic constants of J (E_star, R_star, F_Y, delta_Y; theta_Y is
 * not used): the virgin curve, its stiffness, its work from 0, its inverse, and the unloading curve after
 * a maximum indentation delta_c (vi_unload_force and friends of vi_contact.h evaluate it; delta_c <=
 * delta_Y gives the Hertz curve). */
double vi_thornton_load(const vi_johnson *J, double delta);
double vi_thornton_load_stiffness(const vi_johnson *J, double delta);
double vi_thornton_load_work(const vi_johnson *J, double delta);
double vi_thornton_load_indentation(const vi_johnson *J, double F);
double vi_thornton_load_stiffness_rate(const vi_johnson *J, double delta); /* d2F/ddelta2 [N/m^2] */
/* Above yield a_p^2 = R* delta_c (it follows from the equations above), so Rbar = 4 E* (R* delta_c)^1.5/(3 F_c)
 * and delta_r = R* delta_c/Rbar. */
vi_unload_curve vi_thornton_unload_curve(const vi_johnson *J, double delta_c);
/* d/d(delta_c) of Rbar and delta_r (vi_contact.h). */
vi_unload_rates vi_thornton_unload_rates(const vi_johnson *J, double delta_c);

#endif
