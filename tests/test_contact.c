/* Unit tests of the contact laws (vi_contact.h). Expected values come from closed forms, from the
 * paper's data, or from a Hertz reference case computed independently from Hertz's impact formulas
 * (Johnson, Contact Mechanics, 1985, chapter 11: delta_max = (15 m v^2/(16 E* sqrt(R*)))^(2/5),
 * F_max = K delta_max^(3/2)): a steel sphere R = 10 mm (32.88 g) on a steel half-space, E* = 115.4 GPa,
 * K = 1.538e10 N/m^1.5; v = 0.1 m/s: delta_max = 3.721 um, F_max = 110.4 N; p0 = 1.6 GPa at yield:
 * delta_Y = 4.744 um, F_Y = 159.0 N. */
#include <criterion/criterion.h>
#include <math.h>

#include "vi_contact.h"

#define REL(a, b, tol) cr_assert(isfinite(a) && fabs((a) - (b)) <= (tol) * fabs(b), \
                                 "%s = %.17g, expected %.17g (rel. tol. %g)", #a, (double)(a), (double)(b), (double)(tol))

static const double E_steel = 2.1e11, nu_steel = 0.3;

Test(effective, radius_eq1)
{
    REL(vi_effective_radius(0.475, 0.0), 0.475, 1e-15);      /* sphere on a plane */
    REL(vi_effective_radius(0.0, 0.475), 0.475, 1e-15);
    REL(vi_effective_radius(0.5, 0.5), 0.25, 1e-15);         /* two equal spheres */
    REL(vi_effective_radius(0.3, 0.6), 0.2, 1e-15);          /* 1/R* = 1/0.3 + 1/0.6 = 5 */
    cr_assert(vi_effective_radius(0.0, 0.0) == 0.0);
}

Test(effective, modulus_eq1)
{
    /* equal materials: E* = E / (2 (1 - nu^2)) */
    REL(vi_effective_modulus(E_steel, nu_steel, E_steel, nu_steel), E_steel / (2.0 * 0.91), 1e-15);
    /* the Hertz reference case above */
    REL(vi_effective_modulus(210e9, 0.3, 210e9, 0.3), 115.4e9, 1e-3);
    /* a rigid second body: E* = E1/(1 - nu1^2) */
    REL(vi_effective_modulus(E_steel, nu_steel, 1e300, 0.0), E_steel / 0.91, 1e-12);
}

Test(hertz, reference_impact_case)
{
    double Es = vi_effective_modulus(210e9, 0.3, 210e9, 0.3), K = vi_hertz_constant(Es, 0.01);
    REL(K, 1.538e10, 1e-3);
    REL(vi_hertz_force(K, 3.721e-6), 110.4, 1e-3);
    REL(vi_hertz_force(K, 23.48e-6), 1750.0, 1e-3);
    cr_assert(vi_hertz_force(K, 0.0) == 0.0 && vi_hertz_force(K, -1e-6) == 0.0);
}

Test(hertz, stiffness_and_energy_are_derivative_and_integral)
{
    double K = 1.0e11, d = 3e-5, h = 1e-9;
    double dF = (vi_hertz_force(K, d + h) - vi_hertz_force(K, d - h)) / (2 * h);
    REL(vi_hertz_stiffness(K, d), dF, 1e-7);
    double dU = (vi_hertz_energy(K, d + h) - vi_hertz_energy(K, d - h)) / (2 * h);
    REL(vi_hertz_force(K, d), dU, 1e-7);
}

Test(hertz, static_indentation)
{
    /* paper data, g = 0: W = P = 40 kN, m = 407.747 kg; linearised resonance 267.19 Hz (model.md) */
    double Es = vi_effective_modulus(E_steel, nu_steel, E_steel, nu_steel), K = vi_hertz_constant(Es, 0.475);
    double W = 40000.0, d = vi_hertz_indentation(K, W);
    REL(K * pow(d, 1.5), W, 1e-14);
    double f = sqrt(vi_hertz_stiffness(K, d) / 407.747) / (2 * VI_PI);
    cr_assert(fabs(f - 267.19) < 0.005, "f = %.6f Hz", f);
    cr_assert(vi_hertz_indentation(K, 0.0) == 0.0);
}

Test(yield, textbook_formula_reference_case)
{
    /* yield when the maximum Hertz pressure p0 = 1.5 p_mean reaches 1.6 GPa */
    double Es = vi_effective_modulus(210e9, 0.3, 210e9, 0.3), K = vi_hertz_constant(Es, 0.01);
    double FY = vi_yield_force(VI_YIELD_TEXTBOOK, 1.0, 1.6e9 / 1.5, 0.01, Es);
    REL(FY, 159.0, 1e-3);
    REL(vi_hertz_indentation(K, FY), 4.744e-6, 1e-3);
}

Test(yield, mean_pressure_at_yield)
{
    /* textbook: F_Y/(pi a^2) = theta_Y Y with the Hertz radius a^2 = R* delta_Y;
     * printed (eq. 5, no factor pi): the mean pressure is pi^(-1/3) theta_Y Y (0.75 Y for theta_Y = 1.1) */
    double Es = vi_effective_modulus(E_steel, nu_steel, E_steel, nu_steel), R = 0.475, K = vi_hertz_constant(Es, R);
    double th = 1.1, Y = 6e8;
    double F1 = vi_yield_force(VI_YIELD_TEXTBOOK, th, Y, R, Es), d1 = vi_hertz_indentation(K, F1);
    REL(F1 / (VI_PI * R * d1), th * Y, 1e-13);
    double F2 = vi_yield_force(VI_YIELD_PRINTED, th, Y, R, Es), d2 = vi_hertz_indentation(K, F2);
    REL(F2 / (VI_PI * R * d2), th * Y / cbrt(VI_PI), 1e-13);
    REL(F2 / (VI_PI * R * d2) / Y, 0.7505, 1e-3);
    /* paper: "for 1 GPa F_Y is 1.95 times greater than for 0.8 GPa" (ratio (1/0.8)^3) */
    REL(vi_yield_force(VI_YIELD_PRINTED, th, 1e9, R, Es) / vi_yield_force(VI_YIELD_PRINTED, th, 8e8, R, Es), 1.953125, 1e-13);
}

/* A Johnson virgin curve with the paper's data (Y = 6e8 Pa, textbook yield). */
static vi_johnson paper_johnson(void)
{
    vi_johnson J;
    J.E_star = vi_effective_modulus(E_steel, nu_steel, E_steel, nu_steel);
    J.R_star = 0.475;
    J.theta_Y = 1.1;
    J.F_Y = vi_yield_force(VI_YIELD_TEXTBOOK, J.theta_Y, 6e8, J.R_star, J.E_star);
    J.delta_Y = vi_hertz_indentation(vi_hertz_constant(J.E_star, J.R_star), J.F_Y);
    return J;
}

Test(johnson, loading_continuous_at_yield_with_slope_jump)
{
    vi_johnson J = paper_johnson();
    double dY = J.delta_Y, FY = J.F_Y, h = 1e-7 * dY;
    REL(vi_johnson_load(&J, dY * (1 - 1e-12)), FY, 1e-11);
    REL(vi_johnson_load(&J, dY * (1 + 1e-12)), FY, 1e-11);
    double below = (vi_johnson_load(&J, dY) - vi_johnson_load(&J, dY - h)) / h / (FY / dY);
    double above = (vi_johnson_load(&J, dY + h) - vi_johnson_load(&J, dY)) / h / (FY / dY);
    REL(below, 1.5, 1e-6);
    REL(above, 2.0 * (1.0 + 1.0 / (3.0 * 1.1)), 1e-6);
    /* eq. 3 at delta = 2 delta_Y: k = 3, F = 3 F_Y (1 + ln 3/3.3) (4.00 F_Y to three digits) */
    REL(vi_johnson_load(&J, 2 * dY), 3.0 * FY * (1.0 + log(3.0) / 3.3), 1e-14);
    REL(vi_johnson_load(&J, 2 * dY) / FY, 4.00, 2e-3);
}

Test(johnson, below_yield_is_the_hertz_curve_down_to_tiny_indentations)
{
    /* eq. 2: below delta_Y the virgin curve is Hertz, F = K delta^1.5 with K = F_Y/delta_Y^1.5,
     * however small the indentation (a ringing contact far below yield lives there) */
    vi_johnson J = paper_johnson();
    double K = J.F_Y / pow(J.delta_Y, 1.5), s[] = {1e-9, 1e-6, 2e-4, 0.3, 1.0};
    for (unsigned i = 0; i < sizeof s / sizeof s[0]; i++) {
        double d = s[i] * J.delta_Y;
        REL(vi_johnson_load(&J, d), K * pow(d, 1.5), 1e-13);
        REL(vi_johnson_load_stiffness(&J, d), 1.5 * K * sqrt(d), 1e-13);
        REL(vi_johnson_load_work(&J, d), 0.4 * K * pow(d, 2.5), 1e-13);
    }
    cr_assert(vi_johnson_load(&J, 0.0) == 0.0 && vi_johnson_load(&J, -1e-9) == 0.0);
    cr_assert(vi_johnson_load_stiffness(&J, 0.0) == 0.0 && vi_johnson_load_work(&J, -1e-9) == 0.0);
}

Test(johnson, work_is_the_integral_of_the_load)
{
    /* composite Simpson with 20000 panels: an independent quadrature of eq. 2/3 */
    vi_johnson J = paper_johnson();
    double d = 7.3 * J.delta_Y;
    int n = 20000;
    double h1 = J.delta_Y / n, s1 = 0, h2 = (d - J.delta_Y) / n, s2 = 0;
    for (int i = 0; i <= n; i++) {
        double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        s1 += w * vi_johnson_load(&J, i * h1);
        s2 += w * vi_johnson_load(&J, J.delta_Y + i * h2);
    }
    REL(vi_johnson_load_work(&J, d), (s1 * h1 + s2 * h2) / 3.0, 1e-9);
    REL(vi_johnson_load_work(&J, J.delta_Y), 0.4 * J.F_Y * J.delta_Y, 1e-14);
}

Test(johnson, indentation_inverts_the_load)
{
    vi_johnson J = paper_johnson();
    double Fs[] = {0.3 * J.F_Y, J.F_Y, 1.0001 * J.F_Y, 2.5 * J.F_Y, 40 * J.F_Y, 600 * J.F_Y};
    for (unsigned i = 0; i < sizeof Fs / sizeof Fs[0]; i++)
        REL(vi_johnson_load(&J, vi_johnson_load_indentation(&J, Fs[i])), Fs[i], 1e-13);
}

Test(johnson, paper_unloading_drop_at_turning_point)
{
    vi_johnson J = paper_johnson();
    double kc_values[] = {1.5, 3.0, 7.0, 40.0};
    for (int i = 0; i < 4; i++) {
        double kc = kc_values[i], dc = 0.5 * J.delta_Y * (kc + 1.0);
        vi_unload_curve U = vi_johnson_unload_curve(&J, VI_UNLOAD_PAPER, dc);
        REL(U.Rbar, J.R_star * sqrt(kc), 1e-14);
        REL(U.delta_r, J.delta_Y * sqrt(kc), 1e-14);
        REL(U.delta_f, dc - J.delta_Y * sqrt(kc), 1e-13);
        /* F_unload(delta_c) = F_Y k_c, below the loading force by F_Y k_c ln(k_c)/(3 theta_Y) */
        REL(vi_unload_force(&U, dc), J.F_Y * kc, 1e-13);
        REL(vi_johnson_load(&J, dc) - vi_unload_force(&U, dc), J.F_Y * kc * log(kc) / 3.3, 1e-9);
        cr_assert(vi_unload_force(&U, U.delta_f) == 0.0);
    }
}

Test(johnson, continuous_unloading_matches_force_and_radius)
{
    vi_johnson J = paper_johnson();
    double ratios[] = {1.2, 2.0, 5.0, 30.0};
    for (int i = 0; i < 4; i++) {
        double dc = ratios[i] * J.delta_Y;
        vi_unload_curve U = vi_johnson_unload_curve(&J, VI_UNLOAD_CONTINUOUS, dc);
        REL(vi_unload_force(&U, dc), vi_johnson_load(&J, dc), 1e-13);
        /* Hertz contact radius on the unloading curve, Rbar delta_r, equals a_c^2 = R* (2 delta_c - delta_Y) */
        REL(U.Rbar * U.delta_r, J.R_star * (2 * dc - J.delta_Y), 1e-13);
    }
    /* at delta_c = delta_Y both variants are the Hertz curve */
    vi_unload_curve P = vi_johnson_unload_curve(&J, VI_UNLOAD_PAPER, J.delta_Y);
    vi_unload_curve C = vi_johnson_unload_curve(&J, VI_UNLOAD_CONTINUOUS, J.delta_Y);
    REL(P.Rbar, J.R_star, 1e-14);
    REL(C.Rbar, J.R_star, 1e-13);
    cr_assert(fabs(C.delta_f) < 1e-12 * J.delta_Y);
    /* model.md: continuous unloading gives delta_f < 0 for delta_c < 5 delta_Y */
    cr_assert(vi_johnson_unload_curve(&J, VI_UNLOAD_CONTINUOUS, 3 * J.delta_Y).delta_f < 0.0);
    cr_assert(vi_johnson_unload_curve(&J, VI_UNLOAD_CONTINUOUS, 6 * J.delta_Y).delta_f > 0.0);
}

Test(johnson, unloading_energy_is_the_integral)
{
    vi_johnson J = paper_johnson();
    vi_unload_curve U = vi_johnson_unload_curve(&J, VI_UNLOAD_PAPER, 4 * J.delta_Y);
    REL(vi_unload_energy(&U, U.delta_c), 0.4 * vi_unload_force(&U, U.delta_c) * U.delta_r, 1e-14);
}

/* Radii of any size count, however small or large: a 0.5 mm sphere on a plane, and a 2 km radius
 * (curvature below 1e-3/m) with a plane. */
Test(effective, radius_of_any_size)
{
    REL(vi_effective_radius(5e-4, 0.0), 5e-4, 1e-15);
    REL(vi_effective_radius(0.0, 5e-4), 5e-4, 1e-15);
    REL(vi_effective_radius(5e-4, 5e-4), 2.5e-4, 1e-15);
    REL(vi_effective_radius(2000.0, 0.0), 2000.0, 1e-15);
    REL(vi_effective_radius(0.0, 2000.0), 2000.0, 1e-15);
}

/* Without contact (delta <= 0) the Hertz force, stiffness and energy are 0; a load of 0.5 mN (or none)
 * gives the closed-form indentation (F/K)^(2/3) (or 0), also a load so small that F/K is denormal. */
Test(hertz, no_contact_and_small_loads)
{
    double K = 1.538e10;
    for (double d = -1e-3; d <= 0.0; d += 5e-4) {
        cr_assert(vi_hertz_force(K, d) == 0.0 && vi_hertz_stiffness(K, d) == 0.0 && vi_hertz_energy(K, d) == 0.0,
                  "delta = %g: %g %g %g", d, vi_hertz_force(K, d), vi_hertz_stiffness(K, d), vi_hertz_energy(K, d));
        cr_assert(vi_hertz_indentation(K, d) == 0.0);
    }
    REL(vi_hertz_indentation(K, 5e-4), pow(5e-4 / K, 2.0 / 3.0), 1e-14);
    REL(vi_hertz_indentation(K, 1e-300), exp(2.0 / 3.0 * (log(1e-300) - log(K))), 1e-13); /* F/K below DBL_MIN */
    REL(vi_hertz_indentation(1e10, 4.9e-324), exp(2.0 / 3.0 * (log(4.9e-324) - log(1e10))), 1e-12);
}

/* Above yield the loading stiffness is the derivative of eq. 3, 2 F_Y/delta_Y (1 + (ln k + 1)/(3 theta_Y)):
 * against the closed form and a central difference of the load. Below yield, loads of 0.5 mN or none
 * are inverted by the Hertz curve (delta_Y (F/F_Y)^(2/3), or 0). */
Test(johnson, stiffness_above_yield_is_the_derivative_of_the_load)
{
    vi_johnson J = paper_johnson();
    double ratios[] = {1.01, 1.7, 3.0, 12.0, 150.0};
    for (int i = 0; i < 5; i++) {
        double d = ratios[i] * J.delta_Y, k = 2.0 * ratios[i] - 1.0, e = 1e-6 * J.delta_Y;
        REL(vi_johnson_load_stiffness(&J, d), 2.0 * J.F_Y / J.delta_Y * (1.0 + (log(k) + 1.0) / (3.0 * J.theta_Y)), 1e-13);
        REL(vi_johnson_load_stiffness(&J, d), (vi_johnson_load(&J, d + e) - vi_johnson_load(&J, d - e)) / (2.0 * e), 1e-6);
    }
    REL(vi_johnson_load_indentation(&J, 5e-4), J.delta_Y * pow(5e-4 / J.F_Y, 2.0 / 3.0), 1e-14);
    cr_assert(vi_johnson_load_indentation(&J, 0.0) == 0.0 && vi_johnson_load_indentation(&J, -1.0) == 0.0);
}

/* The unloading curve carries the indentation it starts from; its stiffness is 1.5 Kbar sqrt(delta -
 * delta_f) (the derivative of the force), 0 below delta_f. */
Test(johnson, unloading_curve_stiffness_and_start)
{
    vi_johnson J = paper_johnson();
    for (int variant = VI_UNLOAD_PAPER; variant <= VI_UNLOAD_CONTINUOUS; variant++) {
        double dc = 7.0 * J.delta_Y;
        vi_unload_curve U = vi_johnson_unload_curve(&J, variant, dc);
        cr_assert(U.delta_c == dc);
        cr_assert(U.delta_f > 0.0);
        double d = U.delta_f + 0.5 * U.delta_r, e = 1e-6 * U.delta_r;
        REL(vi_unload_stiffness(&U, d), 1.5 * U.Kbar * sqrt(d - U.delta_f), 1e-14);
        REL(vi_unload_stiffness(&U, d), (vi_unload_force(&U, d + e) - vi_unload_force(&U, d - e)) / (2.0 * e), 1e-8);
        cr_assert(vi_unload_stiffness(&U, 0.5 * U.delta_f) == 0.0);
    }
}
