/* vi_contact.c - contact laws; equations in vi_contact.h. */
#include "vi_contact.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

double vi_effective_radius(double R1, double R2)
{
    double curvature = (R1 > 0.0 ? 1.0 / R1 : 0.0) + (R2 > 0.0 ? 1.0 / R2 : 0.0);
    return curvature > 0.0 ? 1.0 / curvature : 0.0;
}

double vi_effective_modulus(double E1, double nu1, double E2, double nu2)
{
    return 1.0 / ((1.0 - nu1 * nu1) / E1 + (1.0 - nu2 * nu2) / E2);
}

double vi_hertz_constant(double E_star, double R_star) { return 4.0 / 3.0 * E_star * sqrt(R_star); }

double vi_yield_force(int formula, double theta_Y, double Y, double R_star, double E_star)
{
    double pY = theta_Y * Y;
    double c = formula == VI_YIELD_PRINTED ? 1.0 : VI_PI;
    double q = 0.75 * VI_PI;
    return c * q * q * pY * pY * pY * R_star * R_star / (E_star * E_star);
}

double vi_hertz_force(double K, double delta) { return delta > 0.0 ? K * delta * sqrt(delta) : 0.0; }
double vi_hertz_stiffness(double K, double delta) { return delta > 0.0 ? 1.5 * K * sqrt(delta) : 0.0; }
double vi_hertz_energy(double K, double delta) { return delta > 0.0 ? 0.4 * K * delta * delta * sqrt(delta) : 0.0; }
/* (F/S)^(2/3) for F, S > 0 without underflow: F/S is not squared before the root, and when F/S
 * itself leaves the normal range (F denormal, S large) both are rooted first. */
static double ratio_two_thirds(double F, double S)
{
    double q = F / S, r = q >= DBL_MIN ? cbrt(q) : cbrt(F) / cbrt(S);
    return r * r;
}

double vi_hertz_indentation(double K, double F) { return F > 0.0 ? ratio_two_thirds(F, K) : 0.0; }

/* k = 2 delta/delta_Y - 1, the ratio of the contact area to the area at yield. */
static double area_ratio(const vi_johnson *J, double delta) { return 2.0 * delta / J->delta_Y - 1.0; }

double vi_johnson_load(const vi_johnson *J, double delta)
{
    if (delta <= J->delta_Y) {
        double s = delta / J->delta_Y;
        return s > 0.0 ? J->F_Y * s * sqrt(s) : 0.0;
    }
    double k = area_ratio(J, delta);
    return J->F_Y * k * (1.0 + log(k) / (3.0 * J->theta_Y));
}

double vi_johnson_load_stiffness(const vi_johnson *J, double delta)
{
    if (delta <= J->delta_Y) {
        double s = delta / J->delta_Y;
        return s > 0.0 ? 1.5 * J->F_Y / J->delta_Y * sqrt(s) : 0.0;
    }
    double k = area_ratio(J, delta);
    return 2.0 * J->F_Y / J->delta_Y * (1.0 + (log(k) + 1.0) / (3.0 * J->theta_Y));
}

double vi_johnson_load_work(const vi_johnson *J, double delta)
{
    double hertz_part = 0.4 * J->F_Y * J->delta_Y; /* integral of Hertz from 0 to delta_Y */
    if (delta <= J->delta_Y) {
        double s = delta / J->delta_Y;
        return s > 0.0 ? hertz_part * s * s * sqrt(s) : 0.0;
    }
    /* ddelta = delta_Y/2 dk; antiderivative of k + k ln k/(3 theta) is k^2/2 + (k^2 ln k/2 - k^2/4)/(3 theta) */
    double k = area_ratio(J, delta), th3 = 3.0 * J->theta_Y;
    double prim = 0.5 * (k * k - 1.0) + (0.5 * k * k * log(k) - 0.25 * (k * k - 1.0)) / th3;
    return hertz_part + 0.5 * J->F_Y * J->delta_Y * prim;
}

/* The Newton iteration of vi_johnson_load_indentation stops when a step is below VI_NEWTON_ULPS ulps
 * of k (it converges quadratically: a few iterations), after VI_NEWTON_MAX_ITER at most. */
#define VI_NEWTON_ULPS 4.0
#define VI_NEWTON_MAX_ITER 100

double vi_johnson_load_indentation(const vi_johnson *J, double F)
{
    if (F <= J->F_Y) return F > 0.0 ? J->delta_Y * ratio_two_thirds(F, J->F_Y) : 0.0;
    /* Solve k (1 + ln k/(3 theta)) = w for k >= 1. The left side is increasing and convex, so Newton
     * from k = w (where the residual is >= 0) decreases monotonically onto the root. */
    double w = F / J->F_Y, th3 = 3.0 * J->theta_Y, k = w;
    for (int it = 0; it < VI_NEWTON_MAX_ITER; it++) {
        double r = k * (1.0 + log(k) / th3) - w;
        double step = r / (1.0 + (log(k) + 1.0) / th3);
        k -= step;
        if (fabs(step) <= VI_NEWTON_ULPS * DBL_EPSILON * k) break;
    }
    return 0.5 * J->delta_Y * (k + 1.0);
}

/* The contact radius a [m] of the continuous unloading curve after delta_c, and da/d(delta_c) [1] when
 * da is not NULL (vi_contact.h): eq. 3's area, a_c^2 = R* (2 delta_c - delta_Y), or the passive bound
 * a_W = (1 + VI_PASSIVE_ULPS DBL_EPSILON) 3 F_c^2/(10 E* W_c) where it is larger (W_c the virgin work to delta_c,
 * dW_c/d(delta_c) = F_c, so d ln a_W = 2 F_c'/F_c - F_c/W_c). */
static double continuous_radius(const vi_johnson *J, double delta_c, double F_c, double *da)
{
    double W_c = vi_johnson_load_work(J, delta_c);
    double a_c = sqrt(J->R_star * (2.0 * delta_c - J->delta_Y));
    double a_W = (1.0 + VI_PASSIVE_ULPS * DBL_EPSILON) * 0.3 * F_c * F_c / (J->E_star * W_c);
    if (a_W > a_c) {
        if (da) *da = a_W * (2.0 * vi_johnson_load_stiffness(J, delta_c) / F_c - F_c / W_c);
        return a_W;
    }
    if (da) *da = J->R_star / a_c;
    return a_c;
}

vi_unload_curve vi_johnson_unload_curve(const vi_johnson *J, int variant, double delta_c)
{
    vi_unload_curve U;
    U.delta_c = delta_c;
    if (variant == VI_UNLOAD_CONTINUOUS) { /* the Hertz curve of radius a through (delta_c, F_c) */
        double F_c = vi_johnson_load(J, delta_c), a = continuous_radius(J, delta_c, F_c, NULL);
        U.Rbar = 4.0 * J->E_star * a * a * a / (3.0 * F_c);
        U.delta_r = 3.0 * F_c / (4.0 * J->E_star * a);
    } else {
        double sk = sqrt(area_ratio(J, delta_c));
        U.Rbar = J->R_star * sk;
        U.delta_r = J->delta_Y * sk;
    }
    U.delta_f = delta_c - U.delta_r;
    U.Kbar = vi_hertz_constant(J->E_star, U.Rbar);
    return U;
}

double vi_unload_force(const vi_unload_curve *U, double delta) { return vi_hertz_force(U->Kbar, delta - U->delta_f); }
double vi_unload_stiffness(const vi_unload_curve *U, double delta) { return vi_hertz_stiffness(U->Kbar, delta - U->delta_f); }
double vi_unload_energy(const vi_unload_curve *U, double delta) { return vi_hertz_energy(U->Kbar, delta - U->delta_f); }

double vi_hertz_stiffness_rate(double K, double delta) { return delta > 0.0 ? 0.75 * K / sqrt(delta) : 0.0; }

double vi_johnson_load_stiffness_rate(const vi_johnson *J, double delta)
{
    double s = delta / J->delta_Y;
    if (delta <= J->delta_Y) return s > 0.0 ? 0.75 * J->F_Y / (J->delta_Y * J->delta_Y * sqrt(s)) : 0.0;
    /* eq. 3: F'' = 4 F_Y / (3 theta_Y k delta_Y^2), k = 2 delta/delta_Y - 1 */
    return 4.0 * J->F_Y / (3.0 * J->theta_Y * (2.0 * s - 1.0) * J->delta_Y * J->delta_Y);
}

double vi_unload_stiffness_rate(const vi_unload_curve *U, double delta)
{
    return vi_hertz_stiffness_rate(U->Kbar, delta - U->delta_f);
}

vi_unload_rates vi_johnson_unload_rates(const vi_johnson *J, int variant, double delta_c)
{
    vi_unload_rates r;
    if (variant == VI_UNLOAD_CONTINUOUS) { /* a from continuous_radius, F_c the load at delta_c */
        double F = vi_johnson_load(J, delta_c), dF = vi_johnson_load_stiffness(J, delta_c), da;
        double a = continuous_radius(J, delta_c, F, &da);
        r.Rbar = 4.0 * J->E_star / 3.0 * (3.0 * a * a * da / F - a * a * a * dF / (F * F)); /* Rbar = 4 E* a^3/(3 F) */
        r.delta_r = 3.0 / (4.0 * J->E_star) * (dF / a - F * da / (a * a));                 /* delta_r = 3 F/(4 E* a) */
    } else { /* Rbar = R* sqrt(k_c), delta_r = delta_Y sqrt(k_c), k_c = 2 delta_c/delta_Y - 1 */
        double sk = sqrt(area_ratio(J, delta_c));
        r.Rbar = J->R_star / (J->delta_Y * sk);
        r.delta_r = 1.0 / sk;
    }
    return r;
}
