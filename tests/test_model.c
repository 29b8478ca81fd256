/* Unit tests of the hybrid model (vi_model.h): initial states, mode choice, guards. Expected
 * values from closed forms (static equilibrium) and from the mode definitions of model.md. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>

#include "vi_model.h"

static vi_model setup(int law, int moving, int unloading, double P, double g, double a)
{
    vi_parameters p;
    vi_parameters_default(&p);
    p.contact_model = law;
    p.moving_contact = moving;
    p.unloading = unloading;
    p.P = P;
    p.g = g;
    p.a = a;
    vi_model M = {0};
    char msg[256];
    cr_assert(vi_model_setup(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    return M;
}

Test(model, rejects_bad_parameters)
{
    vi_parameters p;
    vi_parameters_default(&p);
    vi_model M;
    char msg[256];
    p.m = -1;
    cr_assert(vi_model_setup(&M, &p, 0, msg, sizeof msg) < 0);
    cr_assert(strstr(msg, "mass") != NULL, "%s", msg);
    vi_parameters_default(&p);
    p.R1 = p.R2 = 0;
    cr_assert(vi_model_setup(&M, &p, 0, msg, sizeof msg) < 0);
    vi_parameters_default(&p);
    p.Y = NAN;
    cr_assert(vi_model_setup(&M, &p, 0, msg, sizeof msg) < 0);
    vi_parameters_default(&p);
    p.contact_model = 7;
    cr_assert(vi_model_setup(&M, &p, 0, msg, sizeof msg) < 0);
    vi_parameters_default(&p);
    p.nu1 = 0.7;
    cr_assert(vi_model_setup(&M, &p, 0, msg, sizeof msg) < 0);
}

Test(model, static_state_carries_the_load)
{
    int laws[] = {VI_ContactModel_hertz, VI_ContactModel_johnson, VI_ContactModel_lepp};
    for (int i = 0; i < 3; i++) {
        vi_model M = setup(laws[i], 0, VI_Unloading_paper, 40000.0, 9.81, 1e-4);
        double x[2];
        vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
        double W = 40000.0 + 407.747 * 9.81;
        cr_assert(M.mode == VI_Mode_elastic, "law %d: mode %d", laws[i], M.mode);
        cr_assert(fabs(vi_model_force(&M, 0.0, x) - W) <= 1e-12 * W, "law %d: F = %.17g", laws[i],
                  vi_model_force(&M, 0.0, x));
        cr_assert(x[1] == 0.0 && M.n_impacts == 0);
        double dx[2];
        vi_model_rhs(&M, 0.0, x, dx);
        cr_assert(fabs(dx[1]) < 1e-12 * W / 407.747);
    }
}

Test(model, touching_state_mode_from_rate_and_acceleration)
{
    double x[2];
    vi_model M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_touching, -0.1, 0.0, x); /* moving into the platform */
    cr_assert(M.mode == VI_Mode_elastic && x[0] == 0.0 && x[1] == -0.1);
    vi_model_initial_state(&M, VI_Init_touching, 0.1, 0.0, x); /* moving away */
    cr_assert(M.mode == VI_Mode_free);
    vi_model_initial_state(&M, VI_Init_touching, 0.0, 0.0, x); /* at rest, no load */
    cr_assert(M.mode == VI_Mode_free);
    M = setup(VI_ContactModel_hertz, 0, 1, 100.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_touching, 0.0, 0.0, x); /* at rest, pressed: acceleration decides */
    cr_assert(M.mode == VI_Mode_elastic);
    cr_assert(M.n_impacts == 0);
}

Test(model, plastically_preloaded_static_state)
{
    /* printed yield formula, Y = 6e8: F_Y = 27 kN < W = 44 kN */
    vi_parameters p;
    vi_parameters_default(&p);
    p.yield_formula = VI_YieldFormula_printed;
    char msg[256];
    double x[2];
    for (int variant = 1; variant <= 2; variant++) {
        vi_model M = {0};
        p.unloading = variant;
        cr_assert(vi_model_setup(&M, &p, 0.0, msg, sizeof msg) == 0);
        cr_assert(M.J.F_Y < p.P + p.m * p.g);
        vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
        cr_assert(M.yielded && M.U.delta_c == x[0] && x[0] > M.J.delta_Y);
        /* paper: the unloading force F_Y k_c is below the load: stick; continuous: on the unloading curve */
        cr_assert(M.mode == (variant == 1 ? VI_Mode_stick : VI_Mode_unload), "variant %d: mode %d", variant, M.mode);
        cr_assert(fabs(vi_model_force(&M, 0.0, x) - (p.P + p.m * p.g)) <= 1e-9 * p.P);
    }
}

Test(model, turning_point_chooses_plastic_stick_or_unload)
{
    vi_model M = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    double dc = 3.0 * M.J.delta_Y;
    vi_unload_curve U = vi_johnson_unload_curve(&M.J, VI_UNLOAD_PAPER, dc);
    double Fl = vi_johnson_load(&M.J, dc), Fu = vi_unload_force(&U, dc);
    struct { double F_hold; int mode; } cases[] = {
        {1.01 * Fl, VI_Mode_plastic}, {0.5 * (Fl + Fu), VI_Mode_stick}, {0.99 * Fu, VI_Mode_unload}};
    for (int i = 0; i < 3; i++) {
        M.yielded = 1;
        M.U = U;
        M.mode = VI_Mode_plastic;
        M.F_ext = (vi_ramp){-cases[i].F_hold, 0.0, 0.0}; /* W = P + m g - F_ext = F_hold (a = 0) */
        double x[2] = {dc, 0.0};
        cr_assert(vi_model_resolve(&M, 0.0, x) == cases[i].mode, "case %d: mode %d", i, M.mode);
    }
}

/* Property: whatever the state, the chosen mode has no guard below zero (so CVODE cannot miss the
 * next switch), and contact onsets are counted. */
Test(model, resolved_mode_has_nonnegative_guards)
{
    srand(12345);
    for (int law = 1; law <= 3; law++)
        for (int moving = 0; moving <= 1; moving++)
            for (int variant = 1; variant <= 2; variant++) {
                vi_model M = setup(law, moving, variant, 40000.0, 9.81, 1e-4);
                double x[2];
                vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
                for (int k = 0; k < 2000; k++) {
                    double t = 1e-5 * k;
                    vi_model_freeze(&M, t, x); /* then jump, as an input change does */
                    x[0] = M.J.delta_Y * (8.0 * rand() / RAND_MAX - 1.0);
                    x[1] = 0.2 * (2.0 * rand() / RAND_MAX - 1.0);
                    long n = M.n_impacts;
                    int from = M.mode, mode = vi_model_resolve(&M, t, x);
                    double gv[VI_NGUARDS];
                    vi_model_guards(&M, t, x, gv);
                    for (int j = 0; j < VI_NGUARDS; j++)
                        cr_assert(gv[j] >= 0.0, "law %d moving %d variant %d: mode %d guard %d = %g", law, moving,
                                  variant, mode, j, gv[j]);
                    cr_assert(M.n_impacts == n + (from == VI_Mode_free && mode != VI_Mode_free));
                    cr_assert(vi_model_force(&M, t, x) >= 0.0);
                }
            }
}
