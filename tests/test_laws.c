/* Unit tests of the damped, linear and Thornton laws (vi_laws.h). Expected values come from closed forms
 * (the damped oscillator, Hunt and Crossley's chi, Thornton 1997), finite differences, and the independent
 * Python reference (python/vibroimpact/reference/laws.py: tsuji_alpha, a SciPy integration with event
 * location, itself checked against closed forms by fmu-test/test_laws_reference.py). */
#include <criterion/criterion.h>
#include <math.h>

#include "vi_laws.h"

#define REL(a, b, tol) cr_assert(isfinite(a) && fabs((a) - (b)) <= (tol) * fabs(b), \
                                 "%s = %.17g, expected %.17g (rel. tol. %g)", #a, (double)(a), (double)(b), (double)(tol))
#define ABS(a, b, tol) cr_assert(isfinite(a) && fabs((a) - (b)) <= (tol), \
                                 "%s = %.17g, expected %.17g (abs. tol. %g)", #a, (double)(a), (double)(b), (double)(tol))

/* (e, alpha) from the Python reference's tsuji_alpha (SciPy DOP853, rtol 1e-13, brentq) */
static const double tsuji_table[][2] = {
    {0.999, 0.0007122630628739804}, {0.95, 0.0368911658466214}, {0.8, 0.1662630515845944},
    {0.5, 0.5708136787826432},      {0.2, 1.6351178366201555},  {0.05, 4.349926308107589},
    {0.01, 10.748648632670589},     {1e-4, 111.71148251333622}, {1e-6, 1118.0196602826152},
    {1e-9, 35355.33840076893},
};
#define N_TSUJI (sizeof tsuji_table / sizeof tsuji_table[0])

Test(tsuji, restitution_matches_the_independent_integration)
{
    cr_assert(vi_tsuji_restitution(0.0) == 1.0);
    /* the reference's absolute tolerance (1e-15 on the rebound speed) bounds the comparison */
    for (size_t i = 0; i < N_TSUJI; i++) ABS(vi_tsuji_restitution(tsuji_table[i][1]), tsuji_table[i][0], 1e-12);
}

/* (alpha, e) from the Python reference's tsuji_restitution, at alphas whose separation falls within the
 * first thousandth of a step of the rebound phase: the located root is near the step's start */
static const double tsuji_early_root[][2] = {{0.58226408105695104, 0.4940129830664174},
                                             {0.71298435460243237, 0.4323441581340238}};

Test(tsuji, restitution_located_at_the_start_of_a_rebound_step)
{
    for (size_t i = 0; i < sizeof tsuji_early_root / sizeof tsuji_early_root[0]; i++)
        ABS(vi_tsuji_restitution(tsuji_early_root[i][0]), tsuji_early_root[i][1], 1e-12);
}

/* The Python reference's tsuji_restitution(1e8) and tsuji_alpha(1e-15) (at this end the fixed steps' error,
 * 1e-23 absolute, is 1e-7 of e); beyond alpha = 1e8 the steps are not stable (at 2e8 they gave 4e23) and the
 * restitution is NaN, which the search for alpha refuses. */
Test(tsuji, restitution_up_to_alpha_1e8_then_nan)
{
    REL(vi_tsuji_restitution(1e8), 1.2500000000010567e-16, 1e-6);
    const double beyond[] = {1.0000001e8, 2e8, 1e12, INFINITY, NAN};
    for (size_t i = 0; i < sizeof beyond / sizeof beyond[0]; i++)
        cr_assert(isnan(vi_tsuji_restitution(beyond[i])), "alpha = %g", beyond[i]);
    double alpha = 42.0;
    cr_assert(vi_tsuji_alpha(1e-15, &alpha) == 0);
    REL(alpha, 35355339.05932617, 1e-7);
    cr_assert(vi_tsuji_alpha(2e-16, &alpha) == -1);
}

/* The table (vi_tsuji_alpha) and the root search (vi_tsuji_alpha_solve) alike. */
Test(tsuji, alpha_inverts_to_1e_12)
{
    int (*const inverse[])(double, double *) = {vi_tsuji_alpha, vi_tsuji_alpha_solve};
    for (int f = 0; f < 2; f++) {
        for (size_t i = 0; i < N_TSUJI; i++) {
            double e = tsuji_table[i][0], alpha = -1.0;
            cr_assert(inverse[f](e, &alpha) == 0, "e = %g", e);
            REL(alpha, tsuji_table[i][1], 1e-8);
            ABS(vi_tsuji_restitution(alpha), e, 1e-12);
        }
        double alpha = -1.0;
        cr_assert(inverse[f](1.0, &alpha) == 0 && alpha == 0.0);
    }
}

/* The table (vi_laws.h) against the integration it was made from: alpha's restitution by
 * vi_tsuji_restitution is e to TABLE_RTOL (relative) at the ends of the table and of every piece, just
 * inside and outside them, and at e drawn at random, uniformly in u = ln(e/(1 - e)) across the table
 * and uniformly in e. The worst of 20,000 such draws: 9.0e-14. */
#define TABLE_RTOL 1e-12
#define TABLE_DRAWS 300

static double table_e_of_u(double u) { return 1.0 / (1.0 + exp(-u)); }

/* a draw in [0, 1) from a fixed-seed linear congruential generator (Knuth's MMIX constants) */
static double uniform01(unsigned long long *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) * 0x1.0p-53;
}

static void check_table_at(double e)
{
    double alpha = -1.0;
    cr_assert(vi_tsuji_alpha(e, &alpha) == 0 && alpha >= 0.0, "e = %.17g", e);
    double r = vi_tsuji_restitution(alpha);
    cr_assert(fabs(r - e) <= TABLE_RTOL * e, "e = %.17g: alpha = %.17g gives %.17g (rel. %.2e)", e, alpha, r,
              r / e - 1.0);
}

Test(tsuji, table_gives_the_integrations_restitution)
{
    const double u_max = VI_TSUJI_TABLE_U_MIN + VI_TSUJI_TABLE_PIECES * VI_TSUJI_TABLE_WIDTH;
    for (int i = 0; i <= VI_TSUJI_TABLE_PIECES; i++) {
        double e = table_e_of_u(VI_TSUJI_TABLE_U_MIN + i * VI_TSUJI_TABLE_WIDTH);
        check_table_at(e);
        check_table_at(e * (1.0 + 1e-12));
        check_table_at(e * (1.0 - 1e-12));
    }
    const double ends[] = {VI_TSUJI_TABLE_E_MIN, nextafter(VI_TSUJI_TABLE_E_MIN, 1.0), 1e-9, 0.5, 1.0 - 1e-9,
                           1.0 - 1e-12, 1.0 - 0x1.0p-53, nextafter(table_e_of_u(u_max), 1.0)};
    for (size_t i = 0; i < sizeof ends / sizeof ends[0]; i++) check_table_at(ends[i]);
    unsigned long long state = 41;
    for (int i = 0; i < TABLE_DRAWS; i++) {
        check_table_at(table_e_of_u(VI_TSUJI_TABLE_U_MIN + (u_max - VI_TSUJI_TABLE_U_MIN) * uniform01(&state)));
        check_table_at(VI_TSUJI_TABLE_E_MIN + (1.0 - VI_TSUJI_TABLE_E_MIN) * uniform01(&state));
    }
    double alpha = -1.0;
    cr_assert(vi_tsuji_alpha(1.0, &alpha) == 0 && alpha == 0.0);
}

/* The table's alpha against the root search's (closer to e = 1 the integration's error, 5e-13 on e,
 * dominates alpha's relative error: the test above compares restitutions there), and below the table
 * the root search itself. */
Test(tsuji, table_matches_the_root_search)
{
    const double es[] = {2e-9, 1e-6, 0.01, 0.3, 0.6, 0.9, 0.99, 0.999};
    for (size_t i = 0; i < sizeof es / sizeof es[0]; i++) {
        double a = -1.0, b = -2.0;
        cr_assert(vi_tsuji_alpha(es[i], &a) == 0 && vi_tsuji_alpha_solve(es[i], &b) == 0);
        REL(a, b, 1e-11);
    }
    double a = -1.0, b = -2.0, below = 0.5 * VI_TSUJI_TABLE_E_MIN;
    cr_assert(vi_tsuji_alpha(below, &a) == 0 && vi_tsuji_alpha_solve(below, &b) == 0 && a == b);
}

Test(tsuji, refuses_what_it_cannot_invert)
{
    double alpha = 42.0;
    const double bad[] = {0.0, -0.5, 1.0000001, NAN, INFINITY, 1e-300};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        cr_assert(vi_tsuji_alpha(bad[i], &alpha) == -1, "e = %g accepted", bad[i]);
        cr_assert(vi_tsuji_alpha_solve(bad[i], &alpha) == -1, "e = %g accepted", bad[i]);
        cr_assert(alpha == 42.0);
    }
}

/* central finite differences of the force of D at (delta, rate) */
static void check_partials(const vi_damped_hertz *D, double delta, double rate, double V_i)
{
    vi_law_force f = vi_damped_hertz_force(D, delta, rate, V_i);
    double hd = 1e-6 * delta, hr = 1e-6 * fabs(rate);
    double dd = (vi_damped_hertz_force(D, delta + hd, rate, V_i).F - vi_damped_hertz_force(D, delta - hd, rate, V_i).F) / (2 * hd);
    double dr = (vi_damped_hertz_force(D, delta, rate + hr, V_i).F - vi_damped_hertz_force(D, delta, rate - hr, V_i).F) / (2 * hr);
    REL(f.dF_ddelta, dd, 1e-7);
    REL(f.dF_drate, dr, 1e-7);
}

Test(damped_hertz, exact_force_and_partials)
{
    double K = 1.538e10, m = 0.03288, e = 0.5;
    vi_damped_hertz D;
    cr_assert(vi_damped_hertz_setup(&D, VI_DAMP_EXACT, e, K, m) == 0);
    REL(D.alpha_c, 0.5708136787826432 * sqrt(m * K), 1e-9);
    double delta = 1e-5, rate = 0.4;
    vi_law_force f = vi_damped_hertz_force(&D, delta, rate, 0.0);
    REL(f.F, K * pow(delta, 1.5) + D.alpha_c * pow(delta, 0.25) * rate, 1e-14);
    check_partials(&D, delta, rate, 0.0);
    check_partials(&D, delta, -0.1, 0.0); /* rebounding, force still positive */
    cr_assert(vi_damped_hertz_force(&D, delta, -0.1, 0.0).F > 0.0);
}

Test(damped_hertz, published_forms_chi_and_partials)
{
    /* chi = 3(1-e)/2, 3(1-e^2)/4, 8(1-e)/(5e) */
    REL(vi_damping_chi(VI_DAMP_HUNT_CROSSLEY, 0.6), 0.6, 1e-15);
    REL(vi_damping_chi(VI_DAMP_LANKARANI_NIKRAVESH, 0.6), 0.48, 1e-15);
    REL(vi_damping_chi(VI_DAMP_FLORES, 0.5), 1.6, 1e-15);
    cr_assert(vi_damping_chi(VI_DAMP_EXACT, 0.5) == 0.0);
    double K = 2e10, delta = 2e-5, V_i = 0.8;
    for (int formula = VI_DAMP_HUNT_CROSSLEY; formula <= VI_DAMP_FLORES; formula++) {
        vi_damped_hertz D;
        cr_assert(vi_damped_hertz_setup(&D, formula, 0.7, K, 1.0) == 0);
        double chi = vi_damping_chi(formula, 0.7);
        REL(vi_damped_hertz_force(&D, delta, 0.3, V_i).F, K * pow(delta, 1.5) * (1 + chi * 0.3 / V_i), 1e-14);
        check_partials(&D, delta, 0.3, V_i);
        check_partials(&D, delta, -0.2, V_i);
        /* a contact that started at rest is undamped: Hertz */
        vi_law_force h = vi_damped_hertz_force(&D, delta, -0.2, 0.0);
        REL(h.F, vi_hertz_force(K, delta), 1e-15);
        cr_assert(h.dF_drate == 0.0 && vi_damped_hertz_guard(&D, delta, -5.0, 0.0).g > 0.0);
    }
}

Test(damped_hertz, clamped_at_zero_where_the_guard_falls_through_zero)
{
    double K = 2e10, m = 1.0, delta = 1e-5;
    vi_damped_hertz D[2];
    cr_assert(vi_damped_hertz_setup(&D[0], VI_DAMP_EXACT, 0.3, K, m) == 0);
    cr_assert(vi_damped_hertz_setup(&D[1], VI_DAMP_FLORES, 0.3, K, m) == 0);
    for (int i = 0; i < 2; i++) {
        /* the rate at which f = 0: exact K delta^1.5 + alpha_c delta^(1/4) r = 0; Flores 1 + chi r/V_i = 0 */
        double V_i = 1.0;
        double r0 = i == 0 ? -K * pow(delta, 1.25) / D[0].alpha_c : -V_i / D[1].chi;
        ABS(vi_damped_hertz_guard(&D[i], delta, r0, V_i).g, 0.0, 1e-9 * fabs(vi_damped_hertz_guard(&D[i], delta, 0.0, V_i).g));
        vi_law_force below = vi_damped_hertz_force(&D[i], delta, 1.01 * r0, V_i);
        cr_assert(below.F == 0.0 && below.dF_ddelta == 0.0 && below.dF_drate == 0.0);
        cr_assert(vi_damped_hertz_guard(&D[i], delta, 1.01 * r0, V_i).g < 0.0);
        cr_assert(vi_damped_hertz_force(&D[i], delta, 0.99 * r0, V_i).F > 0.0);
        cr_assert(vi_damped_hertz_guard(&D[i], delta, 0.99 * r0, V_i).g > 0.0);
        vi_law_force apart = vi_damped_hertz_force(&D[i], -1e-9, 1.0, V_i);
        cr_assert(apart.F == 0.0 && apart.dF_ddelta == 0.0 && apart.dF_drate == 0.0);
    }
    vi_damped_hertz untouched = D[0];
    cr_assert(vi_damped_hertz_setup(&untouched, VI_DAMP_EXACT, 1.5, K, m) == -1);
    cr_assert(vi_damped_hertz_setup(&untouched, 7, 0.5, K, m) == -1);
    cr_assert(untouched.alpha_c == D[0].alpha_c);
}

/* The damped oscillator x'' + 2 zeta x' + x = 0, x(0) = 0, x'(0) = 1 (time in 1/omega), in its textbook
 * solution: position, velocity and acceleration at t. */
static void oscillator(double zeta, double t, double *x, double *v, double *a)
{
    if (zeta < 1.0) {
        double wd = sqrt(1 - zeta * zeta), ex = exp(-zeta * t);
        *x = ex * sin(wd * t) / wd;
        *v = ex * (cos(wd * t) - zeta / wd * sin(wd * t));
    } else {
        double s = sqrt(zeta * zeta - 1), r1 = -zeta + s, r2 = -zeta - s;
        *x = (exp(r1 * t) - exp(r2 * t)) / (r1 - r2);
        *v = (r1 * exp(r1 * t) - r2 * exp(r2 * t)) / (r1 - r2);
    }
    *a = -*x - 2 * zeta * *v;
}

Test(linear, restitution_is_the_oscillator_at_zero_force)
{
    const double zetas[] = {0.01, 0.2, 0.5, 0.707, 0.9, 0.999, 1.001, 1.5, 4.0};
    for (size_t i = 0; i < sizeof zetas / sizeof zetas[0]; i++) {
        double z = zetas[i], tc = vi_linear_contact_time(z), x, v, a;
        oscillator(z, tc, &x, &v, &a);
        ABS(a, 0.0, 1e-12);         /* the force k x + c x' is zero: separation */
        cr_assert(x > 0.0 && v < 0); /* before the overlap closes */
        REL(vi_linear_restitution(z), -v, 1e-12);
    }
    cr_assert(vi_linear_restitution(0.0) == 1.0);
    REL(vi_linear_contact_time(0.0), VI_PI, 1e-15);
    REL(vi_linear_restitution(1.0), exp(-2.0), 1e-15);
    REL(vi_linear_contact_time(1.0), 2.0, 1e-15);
    /* continuous across critical damping */
    REL(vi_linear_restitution(1.0 - 1e-9), exp(-2.0), 1e-6);
    REL(vi_linear_restitution(1.0 + 1e-9), exp(-2.0), 1e-6);
}

Test(linear, zeta_inverts_and_setup_gives_c)
{
    const double es[] = {1e-300, 1e-6, 0.05, 0.135, 0.2, 0.5, 0.9, 0.95, 0.999999};
    for (size_t i = 0; i < sizeof es / sizeof es[0]; i++) {
        double z = -1.0;
        cr_assert(vi_linear_zeta(es[i], &z) == 0);
        REL(vi_linear_restitution(z), es[i], 1e-13);
    }
    double z = -1.0;
    cr_assert(vi_linear_zeta(1.0, &z) == 0 && z == 0.0);
    cr_assert(vi_linear_zeta(0.0, &z) == -1 && vi_linear_zeta(NAN, &z) == -1 && vi_linear_zeta(1.5, &z) == -1);
    /* the range (0, 1] at its ends: the double just above 1 and just above 0 */
    cr_assert(vi_linear_zeta(nextafter(1.0, 2.0), &z) == -1 && vi_linear_zeta(-0.0, &z) == -1);
    cr_assert(vi_linear_zeta(nextafter(0.0, 1.0), &z) == 0 && z > 1.0);
    vi_linear_law L = {0, 0};
    double k = 1e7, m = 2.0;
    cr_assert(vi_linear_setup(&L, k, m, 0.6) == 0);
    cr_assert(vi_linear_zeta(0.6, &z) == 0);
    REL(L.c, 2 * z * sqrt(m * k), 1e-15);
    cr_assert(vi_linear_setup(&L, 0.0, m, 0.6) == -1 && vi_linear_setup(&L, k, m, 0.0) == -1);
    /* force, partials, clamp */
    vi_law_force f = vi_linear_force(&L, 1e-4, 0.3);
    REL(f.F, k * 1e-4 + L.c * 0.3, 1e-15);
    cr_assert(f.dF_ddelta == k && f.dF_drate == L.c);
    double r0 = -k * 1e-4 / L.c;
    cr_assert(vi_linear_force(&L, 1e-4, 1.001 * r0).F == 0.0 && vi_linear_force(&L, 1e-4, 1.001 * r0).dF_drate == 0.0);
    cr_assert(vi_linear_guard(&L, 1e-4, 1.001 * r0).g < 0.0 && vi_linear_guard(&L, 1e-4, 0.999 * r0).g > 0.0);
    cr_assert(vi_linear_force(&L, -1e-6, 1.0).F == 0.0);
}

/* the steel case of the literature (Johnson's Hertz case): E* = 115.4 GPa, R* = 10 mm, p_Y = 1.6 GPa the
 * maximum pressure at yield: delta_Y = (pi p_Y/(2 E*))^2 R* = 4.744 um, F_Y = 159.0 N */
static vi_johnson steel(void)
{
    double E = 115.4e9, R = 0.01, pY = 1.6e9, q = VI_PI * pY / (2 * E);
    vi_johnson J = {E, R, 1.1, 0.0, q * q * R};
    J.F_Y = vi_hertz_force(vi_hertz_constant(E, R), J.delta_Y);
    return J;
}

Test(thornton, loading_curve)
{
    vi_johnson J = steel();
    REL(J.delta_Y, 4.744e-6, 1e-3);
    REL(J.F_Y, 159.0, 2e-3);
    /* F/F_Y = 1 + 1.5 (delta/delta_Y - 1) above yield, Hertz below */
    const double ratio[] = {2, 5, 10, 20, 50, 100}, expected[] = {2.5, 7.0, 14.5, 29.5, 74.5, 149.5};
    for (int i = 0; i < 6; i++) REL(vi_thornton_load(&J, ratio[i] * J.delta_Y) / J.F_Y, expected[i], 1e-13);
    REL(vi_thornton_load(&J, 0.5 * J.delta_Y), J.F_Y * pow(0.5, 1.5), 1e-14);
    cr_assert(vi_thornton_load(&J, 0.0) == 0.0 && vi_thornton_load(&J, -1e-6) == 0.0);
    /* slope continuous at yield: pi p_Y R* = 1.5 F_Y/delta_Y */
    REL(vi_thornton_load_stiffness(&J, J.delta_Y * (1 - 1e-12)), VI_PI * 1.6e9 * 0.01, 1e-6);
    REL(vi_thornton_load_stiffness(&J, J.delta_Y * (1 + 1e-12)), VI_PI * 1.6e9 * 0.01, 1e-6);
    for (double s = 0.3; s < 40; s *= 2.1) {
        double d = s * J.delta_Y, h = 1e-7 * d;
        REL(vi_thornton_load_stiffness(&J, d), (vi_thornton_load(&J, d + h) - vi_thornton_load(&J, d - h)) / (2 * h), 1e-7);
        REL(vi_thornton_load_indentation(&J, vi_thornton_load(&J, d)), d, 1e-13);
        /* work: Simpson's rule of the load curve, exact for the parabola above yield */
        int n = 2000;
        double sum = 0.0, step = d / n;
        for (int k = 0; k <= n; k++) {
            double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
            sum += w * vi_thornton_load(&J, k * step);
        }
        REL(vi_thornton_load_work(&J, d), sum * step / 3.0, 1e-6);
    }
}

Test(thornton, unloading_at_turning_points)
{
    vi_johnson J = steel();
    /* below yield: the Hertz curve */
    vi_unload_curve U = vi_thornton_unload_curve(&J, 0.7 * J.delta_Y);
    REL(U.Rbar, J.R_star, 1e-15);
    cr_assert(U.delta_f == 0.0);
    /* at yield the plastic curve meets Hertz: Rbar = R*, delta_f = 0 */
    U = vi_thornton_unload_curve(&J, J.delta_Y * (1 + 1e-12));
    REL(U.Rbar, J.R_star, 1e-9);
    ABS(U.delta_f, 0.0, 1e-9 * J.delta_Y);
    for (double s = 1.5; s < 100; s *= 3) {
        double dc = s * J.delta_Y, Fc = vi_thornton_load(&J, dc);
        U = vi_thornton_unload_curve(&J, dc);
        REL(vi_unload_force(&U, dc), Fc, 1e-12); /* force continuous at the turning point */
        /* the contact radius of the unloading Hertz curve at delta_c is a_p: a_p^2 = Rbar delta_r */
        double pY = 3 * J.F_Y / (2 * VI_PI * J.R_star * J.delta_Y);
        REL(U.Rbar * U.delta_r, (2 * Fc + J.F_Y) / (2 * VI_PI * pY), 1e-12);
        cr_assert(U.Rbar > J.R_star && U.delta_f > 0 && U.delta_f < dc);
    }
}

/* Thornton's closed form for r = V_Y/V */
static double thornton_e(double r)
{
    return sqrt(6 * sqrt(3.0) / 5) * sqrt(1 - r * r / 6) * pow(r / (r + 2 * sqrt(6.0 / 5 - r * r / 5)), 0.25);
}

Test(thornton, restitution_closed_form)
{
    /* literature values of the closed form: r = 0.5: 0.931, 0.2: 0.773, 0.1: 0.659, 0.01: 0.374 */
    ABS(thornton_e(0.5), 0.931, 6e-4);
    ABS(thornton_e(0.2), 0.773, 6e-4);
    ABS(thornton_e(0.1), 0.659, 6e-4);
    ABS(thornton_e(0.01), 0.374, 6e-4);
    ABS(thornton_e(1.0), 1.0, 1e-15);
    /* An impact that turns at delta_c: 1/2 m V^2 is the loading work, the rebound's 1/2 m V'^2 the elastic
     * energy of the unloading curve, 1/2 m V_Y^2 = 2/5 F_Y delta_Y: e = sqrt(U/W), r = sqrt(W_Y/W). */
    vi_johnson J = steel();
    for (double s = 1.0001; s < 200; s *= 1.7) {
        double dc = s * J.delta_Y, W = vi_thornton_load_work(&J, dc);
        vi_unload_curve U = vi_thornton_unload_curve(&J, dc);
        double e = sqrt(vi_unload_energy(&U, dc) / W), r = sqrt(0.4 * J.F_Y * J.delta_Y / W);
        REL(e, thornton_e(r), 1e-12);
    }
}

Test(damped_hertz, second_partials_and_guard_partials)
{
    double K = 2e10, delta = 2e-5, V_i = 0.8;
    for (int formula = VI_DAMP_EXACT; formula <= VI_DAMP_FLORES; formula++) {
        vi_damped_hertz D;
        cr_assert(vi_damped_hertz_setup(&D, formula, 0.7, K, 1.0) == 0);
        for (double rate = -0.1; rate < 0.5; rate += 0.4) {
            double hd = 1e-6 * delta, hr = 1e-6;
            vi_law_curvature c = vi_damped_hertz_curvature(&D, delta, rate, V_i);
            REL(c.d2F_ddelta2, (vi_damped_hertz_force(&D, delta + hd, rate, V_i).dF_ddelta -
                                vi_damped_hertz_force(&D, delta - hd, rate, V_i).dF_ddelta) / (2 * hd), 1e-6);
            REL(c.d2F_ddelta_drate, (vi_damped_hertz_force(&D, delta, rate + hr, V_i).dF_ddelta -
                                     vi_damped_hertz_force(&D, delta, rate - hr, V_i).dF_ddelta) / (2 * hr), 1e-6);
            vi_law_guard g = vi_damped_hertz_guard(&D, delta, rate, V_i);
            double gd = (vi_damped_hertz_guard(&D, delta + hd, rate, V_i).g - vi_damped_hertz_guard(&D, delta - hd, rate, V_i).g) / (2 * hd);
            double gr = (vi_damped_hertz_guard(&D, delta, rate + hr, V_i).g - vi_damped_hertz_guard(&D, delta, rate - hr, V_i).g) / (2 * hr);
            ABS(g.dg_ddelta, gd, 1e-6 * fabs(gd) + 1e-12);
            ABS(g.dg_drate, gr, 1e-6 * fabs(gr) + 1e-12);
        }
    }
}

Test(thornton, stiffness_rate_and_unload_rates)
{
    vi_johnson J = steel();
    for (double s = 0.3; s < 40; s *= 2.3) {
        double d = s * J.delta_Y, h = 1e-6 * d;
        ABS(vi_thornton_load_stiffness_rate(&J, d),
            (vi_thornton_load_stiffness(&J, d + h) - vi_thornton_load_stiffness(&J, d - h)) / (2 * h),
            1e-6 * J.F_Y / (J.delta_Y * J.delta_Y));
        if (s < 1.0) continue;
        vi_unload_rates r = vi_thornton_unload_rates(&J, d);
        vi_unload_curve a = vi_thornton_unload_curve(&J, d + h), b = vi_thornton_unload_curve(&J, d - h);
        REL(r.Rbar, (a.Rbar - b.Rbar) / (2 * h), 1e-6);
        REL(r.delta_r, (a.delta_r - b.delta_r) / (2 * h), 1e-6);
    }
}

Test(damped_hertz, restitution_of_the_published_forms)
{
    /* the Python reference's integration of F = K delta^1.5 (1 + chi delta'/V_i) (python -m
     * vibroimpact.reference.laws): e = 0.3 -> 0.5813, 0.6842, 0.2562; e = 0.9 -> 0.9090, 0.9132, 0.8939 */
    const double e[2] = {0.3, 0.9}, expected[2][3] = {{0.5813, 0.6842, 0.2562}, {0.9090, 0.9132, 0.8939}};
    for (int i = 0; i < 2; i++)
        for (int f = 0; f < 3; f++)
            ABS(vi_damping_restitution(vi_damping_chi(VI_DAMP_HUNT_CROSSLEY + f, e[i])), expected[i][f], 5e-5);
    cr_assert(vi_damping_restitution(0.0) == 1.0);
    double r = vi_damping_restitution(1e3); /* heavy damping: e_a -> 0 */
    cr_assert(r >= 0.0 && r < 1e-2);
}
