/*
 * vi_contact.h - contact laws of hard spheres: pure functions, no solver, no FMI.
 *
 * Equation numbers refer to Kowalska 2002, the paper the model follows (doc/model.md section 2).
 * SI units throughout: lengths in m, forces in N, moduli and stresses in Pa, energies in J.
 * delta is the indentation (relative approach), positive when the bodies overlap.
 *
 *   (1) effective properties  1/R* = 1/R1 + 1/R2 (R = 0: plane),
 *                             1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2
 *   (2) Hertz                 F = K delta^(3/2),  K = 4/3 E* sqrt(R*)
 *   (3) Johnson loading       F = F_Y k [1 + ln(k)/(3 theta_Y)],  k = 2 delta/delta_Y - 1  (delta > delta_Y)
 *   (4) Johnson unloading     F = 4/3 E* sqrt(Rbar) (delta - delta_f)^(3/2)  (Rbar, delta_f below)
 *   (5) yield force           F_Y = c (3 pi/4)^2 (theta_Y Y)^3 R*^2 / E*^2,
 *                             c = pi (textbook: mean Hertz pressure theta_Y Y at yield) or 1 (as printed)
 *       yield indentation     delta_Y = (F_Y/K)^(2/3)
 *   Linear elastic-perfectly plastic (paper Fig. 3): F = k_lin (delta - delta_p) in [0, F_Y], k_lin = F_Y/delta_Y.
 */
#ifndef VI_CONTACT_H
#define VI_CONTACT_H

#define VI_PI 3.14159265358979323846

/* (1) R* from two radii; a radius of 0 is a plane. Both 0 gives 0 (no curvature: invalid). */
double vi_effective_radius(double R1, double R2);
/* (1) E* from two Young's moduli and Poisson's ratios. */
double vi_effective_modulus(double E1, double nu1, double E2, double nu2);
/* (2) Hertz constant K = 4/3 E* sqrt(R*) [N/m^1.5]. */
double vi_hertz_constant(double E_star, double R_star);

enum { VI_YIELD_TEXTBOOK = 1, VI_YIELD_PRINTED = 2 };
/* (5) yield force; formula is VI_YIELD_TEXTBOOK or VI_YIELD_PRINTED. */
double vi_yield_force(int formula, double theta_Y, double Y, double R_star, double E_star);

/* (2) Hertz force, stiffness dF/ddelta, stored energy, and the indentation under a force F >= 0.
 * Zero (force, stiffness, energy) for delta <= 0. */
double vi_hertz_force(double K, double delta);
double vi_hertz_stiffness(double K, double delta);
double vi_hertz_energy(double K, double delta);
double vi_hertz_indentation(double K, double F);
/* d(stiffness)/d(delta) = F'' [N/m^2]: 3/4 K delta^(-1/2) (0 for delta <= 0). */
double vi_hertz_stiffness_rate(double K, double delta);

/* The virgin (first-loading) curve of Johnson's model: Hertz up to delta_Y, eq. (3) beyond. */
typedef struct {
    double E_star, R_star, theta_Y; /* Pa, m, 1 */
    double F_Y, delta_Y;            /* N, m */
} vi_johnson;

double vi_johnson_load(const vi_johnson *J, double delta);           /* F [N] */
double vi_johnson_load_stiffness(const vi_johnson *J, double delta); /* dF/ddelta [N/m] */
double vi_johnson_load_work(const vi_johnson *J, double delta);      /* integral of F from 0 [J] */
double vi_johnson_load_indentation(const vi_johnson *J, double F);   /* inverse of vi_johnson_load */
double vi_johnson_load_stiffness_rate(const vi_johnson *J, double delta); /* d2F/ddelta2 [N/m^2] */

/* The elastic unloading/reloading curve (4) after a maximum indentation delta_c >= delta_Y. */
enum { VI_UNLOAD_PAPER = 1, VI_UNLOAD_CONTINUOUS = 2 };
typedef struct {
    double delta_c;  /* maximum indentation [m] */
    double Rbar;     /* effective radius after plastic deformation [m] */
    double delta_r;  /* recovered indentation delta_c - delta_f [m] */
    double delta_f;  /* indentation where the force vanishes (permanent set) [m] */
    double Kbar;     /* 4/3 E* sqrt(Rbar) [N/m^1.5] */
} vi_unload_curve;

/* paper:      Rbar = R* sqrt(k_c), delta_r = delta_Y sqrt(k_c), k_c = 2 delta_c/delta_Y - 1 (as printed;
 *             returns more energy than the loading took for delta_c < 1.2527 delta_Y at theta_Y = 1.1)
 * continuous: the Hertz curve through the turning point (force continuous, F_c = vi_johnson_load(delta_c))
 *             with contact radius a:  Rbar = 4 E* a^3/(3 F_c), delta_r = 3 F_c/(4 E* a), and
 *               a = max(a_c, a_W),  a_c^2 = R* (2 delta_c - delta_Y)       (eq. 3's contact area)
 *                                   a_W = (1 + VI_PASSIVE_ULPS DBL_EPSILON) 3 F_c^2/(10 E* W_c)
 *             with W_c = vi_johnson_load_work(delta_c). The curve returns the energy
 *             2/5 F_c delta_r = 3 F_c^2/(10 E* a) <= W_c/(1 + VI_PASSIVE_ULPS DBL_EPSILON): no
 *             load-unload cycle returns more than it took (passive), W_plastic = W_c - 2/5 F_c delta_r
 *             >= 0. Where a_c >= a_W (at theta_Y = 1.1: delta_c >= 4.6100 delta_Y) it is the force- and
 *             radius-continuous curve; below, eq. 3 (stiffer than Hertz above delta_Y) would make that
 *             curve return more than the loading took, and the larger radius a_W returns the loading
 *             work (restitution 1). */
#define VI_PASSIVE_ULPS 64 /* the margin of a_W in units of rounding: returned <= taken in floating point too */
vi_unload_curve vi_johnson_unload_curve(const vi_johnson *J, int variant, double delta_c);
double vi_unload_force(const vi_unload_curve *U, double delta);
double vi_unload_stiffness(const vi_unload_curve *U, double delta);
double vi_unload_energy(const vi_unload_curve *U, double delta); /* elastic energy stored at delta [J] */
double vi_unload_stiffness_rate(const vi_unload_curve *U, double delta); /* d2F/ddelta2 [N/m^2] */
/* How the unloading curve moves with delta_c: d/d(delta_c) of Rbar [1] and of delta_r [1]. */
typedef struct {
    double Rbar, delta_r;
} vi_unload_rates;
vi_unload_rates vi_johnson_unload_rates(const vi_johnson *J, int variant, double delta_c);

#endif
