/*
 * energy.c - the energy property of an undriven Co-Simulation run, for both FMI versions (fuzz.h).
 *
 * With no excitation (a = 0, the platform and the inputs constant) no work is done on the mass but
 * that of its constant load W0 = P + m g - F_ext, so that the balance
 *     B = 1/2 m v^2 + E_contact + W_dissipated + W0 y        (y up, the load's potential W0 y)
 * stays constant (doc/numerics.md, "Energy and negative plastic work"; W_dissipated holds what the
 * contact dissipated, and what paper unloading returns, with its sign). A step that lets B grow by
 * more than FZ_ENERGY_TOL rtol of the energy moved in the step, beyond the rounding of B's terms,
 * made energy: a solver that turns rest into motion (an explicit method outside its stability
 * domain) or feeds an undriven run. A finding.
 *
 * Checked on each fmi2DoStep and fmi3DoStep (the Co-Simulation kinds, not the master's, which sets
 * inputs in Event Mode) of an instance whose run has been undriven since its start: after the
 * instantiation only calls that do not drive it (fz_call.energy: FZ_RUN_KEEPS; FZ_RUN_STARTS while
 * the instance may be instantiated or initializing only, where its parameters and inputs are set).
 * Any other call (inputs, tunable parameters or input derivatives set after the start, an FMU state
 * restored, Event Mode, a reset) ends the checks until the next instantiation. A step is checked
 * only when a, V, the platform yC, P, m, g and F_ext read the same before and after it.
 *
 * Beyond rtol of the energy moved, B may also grow by the energy of a state error of the absolute
 * tolerances (doc/numerics.md, "Tolerances"): errors rtol L in delta and rtol V in v, with
 * V = L sqrt(k(L)/m), change B about a rest by 1/2 k(L) (rtol L)^2 + 1/2 m (rtol V)^2 =
 * rtol^2 k(L) L^2. A run resting far below L (a mass so light that its static indentation is 1e-171 m
 * against delta_Y) may move by that much and no more. The laws with a yield limit (johnson, lepp,
 * thornton) have L >= delta_Y and k(L) L^2 >= F_Y delta_Y, read from the FMU; for the others no lower
 * bound of L is known from outside and nothing is allowed.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "vi_model.h"

/* B may grow by FZ_ENERGY_TOL rtol of the energy moved in a step (the integration's own error is
 * of the order of rtol of it) plus 64 ulps of the terms of B. */
#define FZ_ENERGY_TOL 1000.0

/* What is read before and after a step. */
enum { E_M, E_P, E_G, E_A, E_V, E_RTOL, E_FEXT, E_YC, E_Y, E_VEL, E_EC, E_WD, E_FY, E_DY, E_LAW, E_N };
static const char *const names[E_N] = {"m", "P", "g", "a", "V", "rtol", "F_ext", "yC", "y", "v", "E_contact",
                                       "W_dissipated", "F_Y", "delta_Y", "contact_model"};

static unsigned vr_of(const char *name)
{
    for (int i = 0; i < vi_fmu_this_model.nvariables; i++)
        if (strcmp(vi_fmu_this_model.variables[i].name, name) == 0) return (unsigned)i;
    fz_fail("energy check: the FMU has no variable %s", name);
}

void fz_energy_after_call(fz_slot *s, const fz_call *call, unsigned mask_before)
{
    if (call->instantiates) s->energy = (fz_energy){0, 0.0};
    else if (call->energy == FZ_RUN_KEEPS) return;
    else if (call->energy == FZ_RUN_STARTS && !(mask_before & ~(unsigned)(FZ_INSTANTIATED | FZ_INIT))) return;
    else s->energy.off = 1;
}

void fz_energy_tolerance(fz_slot *s, int defined, double tolerance) { s->energy.tolerance = defined ? tolerance : 0.0; }

int fz_energy_read(fz_slot *s, fz_get_reals get, fz_get_int get_int, double x[FZ_ENERGY_VALUES])
{
    static unsigned vr[E_N];
    if (!vr[E_N - 1])
        for (int i = 0; i < E_N; i++) vr[i] = vr_of(names[i]);
    if (s->energy.off || !s->c || s->fmu_type != fmi2CoSimulation || s->mask != FZ_STEP_COMPLETE) return 0;
    long law = 0;
    if (get(s, vr, E_LAW, x) != 0 || get_int(s, vr[E_LAW], &law) != 0) return 0; /* the Reals come first */
    x[E_LAW] = (double)law;
    for (int i = 0; i < E_N; i++)
        if (!isfinite(x[i])) return 0;
    return x[E_A] == 0.0 && x[E_V] == 0.0;
}

/* B and the magnitude of its terms (*terms). */
static double balance(const double x[FZ_ENERGY_VALUES], double *terms)
{
    double W0 = x[E_P] + x[E_M] * x[E_G] - x[E_FEXT], kinetic = 0.5 * x[E_M] * x[E_VEL] * x[E_VEL];
    *terms = fabs(kinetic) + fabs(x[E_EC]) + fabs(x[E_WD]) + fabs(W0 * x[E_Y]);
    return kinetic + x[E_EC] + x[E_WD] + W0 * x[E_Y];
}

void fz_energy_check(const fz_slot *s, const double a[FZ_ENERGY_VALUES], const double b[FZ_ENERGY_VALUES],
                     double t, double h)
{
    static const int same[] = {E_M, E_P, E_G, E_A, E_V, E_RTOL, E_FEXT, E_YC};
    for (size_t i = 0; i < sizeof same / sizeof same[0]; i++)
        if (a[same[i]] != b[same[i]]) return; /* driven after all (or the platform moved): no check */
    double rtol = a[E_RTOL] > 0.0 ? a[E_RTOL] : s->energy.tolerance > 0.0 ? s->energy.tolerance : 1e-6;
    double terms_a, terms_b, Ba = balance(a, &terms_a), Bb = balance(b, &terms_b);
    double W0 = a[E_P] + a[E_M] * a[E_G] - a[E_FEXT];
    double moved = 0.5 * a[E_M] * (a[E_VEL] * a[E_VEL] + b[E_VEL] * b[E_VEL]) + fabs(a[E_EC]) + fabs(b[E_EC]) +
                   fabs(b[E_WD] - a[E_WD]) + fabs(W0 * (b[E_Y] - a[E_Y]));
    int yields = a[E_LAW] == VI_LAW_JOHNSON || a[E_LAW] == VI_LAW_LEPP || a[E_LAW] == VI_LAW_THORNTON;
    double absolute = yields ? rtol * rtol * a[E_FY] * a[E_DY] : 0.0;
    double tol = FZ_ENERGY_TOL * (rtol * moved + absolute) + 64.0 * DBL_EPSILON * (terms_a + terms_b);
    if (isfinite(Bb - Ba) && Bb - Ba > tol)
        fz_fail("energy: an undriven run (a = 0, constant inputs) gained %.6g J in the step [%.17g, %.17g + %.17g] s "
                "(allowed %.3g J: %g times rtol of the %.6g J moved and rtol^2 F_Y delta_Y = %.3g J, rtol %g, and the rounding): kinetic + E_contact + "
                "W_dissipated + W0 y went from %.17g to %.17g J; v %.9g -> %.9g m/s, y %.9g -> %.9g m, m %g kg, "
                "W0 %g N", Bb - Ba, t, t, h, tol, FZ_ENERGY_TOL, moved, absolute, rtol, Ba, Bb, a[E_VEL], b[E_VEL], a[E_Y],
                b[E_Y], a[E_M], W0);
}
