/* Unit tests of the hybrid model (vi_model.h): initial states, mode choice, guards. Expected
 * values from closed forms (static equilibrium) and from the mode definitions of model.md. */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "vi_model.h"
#include "test_run.h"

/* The model set up from (and its option warnings of) the FMU's parameters, as the simulation does. */
static int setup_from_table(vi_model *M, const vi_parameters *p, double t0, char *msg, size_t n)
{
    vi_model_params mp = vi_contact_model_params(p);
    return vi_model_setup(M, &mp, t0, msg, n);
}

static int warnings_from_table(const vi_parameters *p, char *msg, size_t n)
{
    vi_model_params mp = vi_contact_model_params(p);
    return vi_model_option_warnings(&mp, msg, n);
}

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
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    return M;
}

/* What the ranges of the variable table cannot say: two planes (R1 = R2 = 0) have no contact. */
Test(model, rejects_two_planes)
{
    vi_parameters p;
    vi_parameters_default(&p);
    vi_model M;
    char msg[256];
    p.R1 = p.R2 = 0;
    cr_assert(setup_from_table(&M, &p, 0, msg, sizeof msg) < 0);
    cr_assert(strstr(msg, "R1 = R2 = 0") != NULL, "%s", msg);
    p.R2 = 1e-3;
    cr_assert(setup_from_table(&M, &p, 0, msg, sizeof msg) == 0, "%s", msg);
}

/* The variable table's ranges (src/adapter/vi_variables.h): the exclusive bounds are exactly the doubles
 * beyond them (m > 0: 5e-324 is in, 0 is out; -1 < nu <= 0.5), the inclusive ones contain their
 * bound, every start value lies in its range, and the range reads as written in model.md. */
static const vi_variable *var(const char *name)
{
    for (int vr = 0; vr < VI_NVARS; vr++)
        if (strcmp(vi_variable_table[vr].name, name) == 0) return &vi_variable_table[vr];
    cr_assert_fail("no variable %s", name);
    return NULL;
}

Test(table, ranges_of_the_contact_model)
{
    const struct { const char *name; double out, in; } edge[] = {
        {"m", 0.0, 5e-324},        {"m", -1.0, 1e300},          {"E1", 0.0, 5e-324},   {"E2", -0.0, 5e-324},
        {"Y", 0.0, 5e-324},        {"theta_Y", 0.0, 5e-324},    {"R1", -5e-324, 0.0},  {"R2", -5e-324, 0.0},
        {"nu1", -1.0, nextafter(-1.0, 0.0)}, {"nu2", -1.0, nextafter(-1.0, 0.0)},
        {"nu1", nextafter(0.5, 1.0), 0.5},   {"nu2", nextafter(0.5, 1.0), 0.5},
        {"f", -5e-324, 0.0},       {"max_step", -5e-324, 0.0},  {"rtol", -5e-324, 0.0},  {"rtol", 0.011, 1e-2},
        {"rtol", nextafter(1e-2, 1.0), 1e-2}, /* (0, 1e-14) is refused at initialization, as max_step's gap */
        {"m", NAN, 1.0},           {"nu1", NAN, 0.0},
    };
    for (size_t i = 0; i < sizeof edge / sizeof edge[0]; i++) {
        const vi_variable *v = var(edge[i].name);
        cr_assert(!vi_in_range(v, edge[i].out), "%s = %g accepted", edge[i].name, edge[i].out);
        cr_assert(vi_in_range(v, edge[i].in), "%s = %g refused", edge[i].name, edge[i].in);
    }
    const char *unbounded[] = {"P", "g", "v0", "a", "V", "x0", "yC_in", "F_ext"};
    for (size_t i = 0; i < sizeof unbounded / sizeof unbounded[0]; i++)
        cr_assert(vi_in_range(var(unbounded[i]), -1e300) && vi_in_range(var(unbounded[i]), 1e300), "%s", unbounded[i]);
    for (int vr = 0; vr < VI_NVARS; vr++) {
        const vi_variable *v = &vi_variable_table[vr];
        if (strcmp(v->initial, "exact") == 0 && v->type != VI_String)
            cr_assert(vi_in_range(v, v->start), "the start value of %s is outside its range", v->name);
    }
    const struct { const char *name, *text; } texts[] = {
        {"m", "m > 0"}, {"nu1", "-1 < nu1 <= 0.5"}, {"R1", "R1 >= 0"}, {"rtol", "0 <= rtol <= 0.01"}, {"a", ""}};
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        char text[128];
        vi_range_text(var(texts[i].name), text, sizeof text);
        cr_assert(strcmp(text, texts[i].text) == 0, "%s: '%s'", texts[i].name, text);
    }
}

Test(model, static_state_carries_the_load)
{
    int laws[] = {VI_ContactModel_hertz, VI_ContactModel_johnson, VI_ContactModel_lepp};
    for (int i = 0; i < 3; i++) {
        vi_model M = setup(laws[i], 0, VI_Unloading_paper, 40000.0, 9.81, 1e-4);
        double x[2];
        vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
        double W = 40000.0 + 407.747 * 9.81;
        cr_assert(M.contact[0].mode == VI_Mode_elastic, "law %d: mode %d", laws[i], M.contact[0].mode);
        cr_assert(fabs(vi_model_force(&M, 0.0, x) - W) <= 1e-12 * W, "law %d: F = %.17g", laws[i],
                  vi_model_force(&M, 0.0, x));
        cr_assert(x[1] == 0.0 && M.contact[0].n_impacts == 0);
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
    cr_assert(M.contact[0].mode == VI_Mode_elastic && x[0] == 0.0 && x[1] == -0.1);
    vi_model_initial_state(&M, VI_Init_touching, 0.1, 0.0, x); /* moving away */
    cr_assert(M.contact[0].mode == VI_Mode_free);
    vi_model_initial_state(&M, VI_Init_touching, 0.0, 0.0, x); /* at rest, no load */
    cr_assert(M.contact[0].mode == VI_Mode_free);
    M = setup(VI_ContactModel_hertz, 0, 1, 100.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_touching, 0.0, 0.0, x); /* at rest, pressed: acceleration decides */
    cr_assert(M.contact[0].mode == VI_Mode_elastic);
    cr_assert(M.contact[0].n_impacts == 0);
}

/* A damped law's start touching: moving in is a new contact that takes its rate as the approach speed
 * V_i; a start prepared again (the importer changed v0 in initialization mode) begins with none. */
Test(model, touching_state_of_a_damped_law_takes_its_approach_speed_anew)
{
    double x[2];
    vi_model M = setup(VI_ContactModel_hertz_damped, 0, 1, 0.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_touching, -0.1, 0.0, x);
    cr_assert(M.contact[0].mode == VI_Mode_elastic && M.contact[0].V_i == 0.1, "mode %d, V_i %g", M.contact[0].mode, M.contact[0].V_i);
    vi_model_initial_state(&M, VI_Init_touching, 0.1, 0.0, x);
    cr_assert(M.contact[0].mode == VI_Mode_free && M.contact[0].V_i == 0.0, "mode %d, V_i %g", M.contact[0].mode, M.contact[0].V_i);
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
        cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0);
        cr_assert(M.contact[0].johnson.F_Y < p.P + p.m * p.g);
        vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
        cr_assert(M.contact[0].yielded && M.contact[0].unload.delta_c == x[0] && x[0] > M.contact[0].johnson.delta_Y);
        /* paper: the unloading force F_Y k_c is below the load: stick; continuous: on the unloading curve */
        cr_assert(M.contact[0].mode == (variant == 1 ? VI_Mode_stick : VI_Mode_unload), "variant %d: mode %d", variant, M.contact[0].mode);
        cr_assert(fabs(vi_model_force(&M, 0.0, x) - (p.P + p.m * p.g)) <= 1e-9 * p.P);
    }
}

/* Loaded exactly to yield (W = F_Y, so delta = delta_Y: F_Y = K delta_Y^1.5): the material has not
 * yielded; no unloading curve is written down (paper eq. 4 holds up to delta_Y). */
Test(model, static_state_loaded_exactly_to_yield_has_not_yielded)
{
    vi_parameters p;
    vi_parameters_default(&p);
    p.g = 0.0;
    char msg[256];
    double x[2];
    for (int variant = 1; variant <= 2; variant++) {
        vi_model M = {0};
        p.unloading = variant;
        cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
        p.P = M.contact[0].johnson.F_Y;
        cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
        vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
        cr_assert(x[0] == M.contact[0].johnson.delta_Y, "variant %d: delta %.17g, delta_Y %.17g", variant, x[0], M.contact[0].johnson.delta_Y);
        cr_assert(!M.contact[0].yielded && M.contact[0].unload.delta_c == 0.0 && M.contact[0].mode == VI_Mode_elastic, "variant %d: yielded %d, mode %d",
                  variant, M.contact[0].yielded, M.contact[0].mode);
    }
}

Test(model, turning_point_chooses_plastic_stick_or_unload)
{
    vi_model M = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    double dc = 3.0 * M.contact[0].johnson.delta_Y;
    vi_unload_curve U = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, dc);
    double Fl = vi_johnson_load(&M.contact[0].johnson, dc), Fu = vi_unload_force(&U, dc);
    struct { double F_hold; int mode; } cases[] = {
        {1.01 * Fl, VI_Mode_plastic}, {0.5 * (Fl + Fu), VI_Mode_stick}, {0.99 * Fu, VI_Mode_unload}};
    for (int i = 0; i < 3; i++) {
        M.contact[0].yielded = 1;
        M.contact[0].unload = U;
        M.contact[0].mode = VI_Mode_plastic;
        M.F_ext = (vi_ramp){-cases[i].F_hold, 0.0, 0.0}; /* W = P + m g - F_ext = F_hold (a = 0) */
        double x[2] = {dc, 0.0};
        cr_assert(vi_model_resolve(&M, 0.0, x) == cases[i].mode, "case %d: mode %d", i, M.contact[0].mode);
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
                    x[0] = M.contact[0].johnson.delta_Y * (8.0 * rand() / RAND_MAX - 1.0);
                    x[1] = 0.2 * (2.0 * rand() / RAND_MAX - 1.0);
                    long n = M.contact[0].n_impacts;
                    int from = M.contact[0].mode, mode = vi_model_resolve(&M, t, x);
                    double gv[VI_NGUARDS];
                    vi_model_guards(&M, t, x, gv);
                    for (int j = 0; j < VI_NGUARDS; j++)
                        cr_assert(gv[j] >= 0.0, "law %d moving %d variant %d: mode %d guard %d = %g", law, moving,
                                  variant, mode, j, gv[j]);
                    cr_assert(M.contact[0].n_impacts == n + (from == VI_Mode_free && mode != VI_Mode_free));
                    cr_assert(vi_model_force(&M, t, x) >= 0.0);
                }
            }
}

/* ---- vi_model_check ----------------------------------------------------------------------------- */

static void log_nothing(void *env, int category, const char *fmt, ...) { (void)env, (void)category, (void)fmt; }

/* States written by the code itself pass: every communication point of bouncing runs of every law. */
Test(model_check, accepts_every_state_of_real_runs)
{
    struct { int law, moving, unloading, formula; double Y; } cases[] = {
        {1, 0, 1, 1, 6e8}, {2, 0, 1, 1, 6e8}, {2, 0, 2, 1, 6e8}, {2, 1, 1, 1, 6e8}, {3, 0, 1, 1, 6e8},
        {2, 0, 1, 2, 6e8}, {2, 0, 1, 1, 2e8}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        test_run s;
        test_run_init(&s, log_nothing, NULL);
        s.d.par.contact_model = cases[c].law;
        s.d.par.moving_contact = cases[c].moving;
        s.d.par.unloading = cases[c].unloading;
        s.d.par.yield_formula = cases[c].formula;
        s.d.par.Y = cases[c].Y;
        s.d.par.a = 1e-4;
        s.d.par.f = cases[c].Y < 3e8 ? 100.0 : 560.0;
        char msg[256];
        cr_assert(vi_model_check(&s.d.run.model, s.d.run.x, msg, sizeof msg) == 0, "never set up: %s", msg);
        cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
        int modes = 0;
        for (int k = 1; k <= 300; k++) {
            cr_assert(vi_sim_advance(&s.s, 1e-4 * k) == 0, "%s", s.r.msg);
            modes |= 1 << s.d.run.model.contact[0].mode;
            cr_assert(vi_model_check(&s.d.run.model, s.d.run.x, msg, sizeof msg) == 0, "case %zu t = %g: %s", c, s.d.run.t, msg);
        }
        cr_assert(modes & 1 << VI_Mode_elastic || modes & 1 << VI_Mode_unload || modes & 1 << VI_Mode_stick);
        test_run_free(&s);
    }
}

/* The random states of the resolver (input jumps) pass too. */
Test(model_check, accepts_resolved_random_states)
{
    srand(777);
    for (int law = 1; law <= 3; law++)
        for (int variant = 1; variant <= 2; variant++) {
            vi_model M = setup(law, 0, variant, 40000.0, 9.81, 1e-4);
            double x[2];
            char msg[256];
            vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
            for (int k = 0; k < 2000; k++) {
                double t = 1e-5 * k;
                vi_model_freeze(&M, t, x);
                x[0] = M.contact[0].johnson.delta_Y * (8.0 * rand() / RAND_MAX - 1.0);
                x[1] = 0.2 * (2.0 * rand() / RAND_MAX - 1.0);
                vi_model_resolve(&M, t, x);
                cr_assert(vi_model_check(&M, x, msg, sizeof msg) == 0, "law %d: %s", law, msg);
            }
        }
}

/* A model after a Johnson impact with yield: plastic memory and mode 3 or 0. */
static vi_model yielded_model(double x[2])
{
    vi_model M = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
    M.contact[0].mode = VI_Mode_plastic;
    M.contact[0].yielded = 1;
    x[0] = 3.0 * M.contact[0].johnson.delta_Y;
    x[1] = 1.0; /* moving away: unloads */
    vi_model_freeze(&M, 0.0, x);
    cr_assert(vi_model_resolve(&M, 0.0, x) == VI_Mode_unload);
    return M;
}

/* Spoil one field at a time; the check refuses and names it. */
static const char *spoil(vi_model *M, double x[2], int which)
{
    switch (which) {
    case 0: x[0] = NAN; return "state";
    case 1: M->contact[0].law = 7; return "contact law";
    case 2: M->contact[0].moving = 2; return "flag moving = 2 is not 0 or 1";
    case 3: M->contact[0].unloading = 0; return "unloading";
    case 4: M->contact[0].mode = 5; return "mode";
    case 5: M->body.m = -1.0; return "constant m";
    case 6: M->contact[0].K *= 1.0 + 1e-6; return "K";
    case 7: M->contact[0].johnson.delta_Y = INFINITY; return "delta_Y";
    case 8: M->contact[0].k_lin *= 2.0; return "k_lin";
    case 9: M->omega = -1.0; return "omega";
    case 10: M->yC_in.du = NAN; return "yC_in";
    case 11: M->contact[0].yielded = 3; return "yielded";
    case 12: M->contact[0].n_impacts = -1; return "n_impacts";
    case 13: M->contact[0].delta_p = 1e-6; return "delta_p";
    case 14: M->contact[0].unload.Rbar *= 1.001; return "Rbar";
    case 15: M->contact[0].unload.delta_f = M->contact[0].unload.delta_c * 1.5; return "delta_f";
    case 16: M->contact[0].unload.delta_c = 0.5 * M->contact[0].johnson.delta_Y; return "delta_c";
    case 17: M->contact[0].unload.Kbar = NAN; return "finite";
    case 18: M->contact[0].yielded = 0; return "yielded = 0";      /* memory left behind */
    case 19: M->contact[0].mode = VI_Mode_elastic; return "mode = 1"; /* virgin branch after yield */
    case 20: M->contact[0].mode = VI_Mode_free; return "mode 0 does not fit"; /* in contact at delta > delta_f */
    case 21: x[0] = M->contact[0].unload.delta_c * 1.01; return "mode 3 does not fit"; /* beyond delta_c while unloading */
    case 22: M->contact[0].mode = VI_Mode_stick; return "mode 4 does not fit"; /* stick off delta_c */
    case 23: M->contact[0].unloading = VI_UNLOAD_CONTINUOUS; M->contact[0].unload = vi_johnson_unload_curve(&M->contact[0].johnson, 2, M->contact[0].unload.delta_c);
             M->contact[0].mode = VI_Mode_stick; x[0] = M->contact[0].unload.delta_c; return "mode = 4"; /* stick needs paper unloading */
    case 24: M->contact[0].law = VI_ContactModel_hertz; return "yielded = 1 is impossible";
    case 26: M->contact[0].yielded = 0; M->contact[0].unload = (vi_unload_curve){0}; return "mode = 3"; /* unloading without memory */
    case 25: M->f_contact = NAN; return "f_contact";
    case 27: M->body.m = 0.0; return "constant m = 0 is not positive";
    case 28: M->contact[0].K = 0.0; return "constant K = 0 is not positive"; /* before its consistency with E*, R* */
    case 29: M->contact[0].johnson.delta_Y *= 1.0 + 1e-6; return "delta_Y = "; /* F_Y = K delta_Y^1.5 off: before k_lin's check */
    case 30: M->contact[0].delta_p = NAN; return "delta_p = nan is not finite";
    default: return NULL;
    }
}

Test(model_check, names_the_first_bad_field)
{
    double x0[2];
    char msg[256];
    vi_model ok = yielded_model(x0);
    cr_assert(vi_model_check(&ok, x0, msg, sizeof msg) == 0, "%s", msg);
    x0[0] = 0.5 * (ok.contact[0].unload.delta_c + ok.contact[0].unload.delta_f); /* inside the unloading branch */
    cr_assert(vi_model_check(&ok, x0, msg, sizeof msg) == 0, "%s", msg);
    for (int k = 0;; k++) {
        vi_model M = ok;
        double x[2] = {x0[0], x0[1]};
        const char *expect = spoil(&M, x, k);
        if (!expect) break;
        msg[0] = '\0';
        cr_assert(vi_model_check(&M, x, msg, sizeof msg) < 0, "spoiled %d (%s) accepted", k, expect);
        cr_assert(strstr(msg, expect) != NULL, "spoiled %d: expected '%s' in: %s", k, expect, msg);
    }
    /* memory left behind (yielded = 0): the message gives the curve's own delta_c and Rbar */
    vi_model M = ok;
    M.contact[0].yielded = 0;
    char expect[128];
    snprintf(expect, sizeof expect, "(delta_c = %g, Rbar = %g)", ok.contact[0].unload.delta_c, ok.contact[0].unload.Rbar);
    cr_assert(vi_model_check(&M, x0, msg, sizeof msg) < 0 && strstr(msg, expect), "expected '%s' in: %s", expect, msg);
}

/* A model never set up (law = 0: the state of an instance before initialization) holds no discrete
 * state: each of mode, yielded, n_impacts and delta_p set alone is refused. */
Test(model_check, never_set_up_has_no_discrete_state)
{
    double x[2] = {0.0, 0.0};
    char msg[256];
    for (int k = 0; k < 5; k++) {
        vi_model M;
        memset(&M, 0, sizeof M);
        if (k == 1) M.contact[0].mode = VI_Mode_elastic;
        if (k == 2) M.contact[0].yielded = 1;
        if (k == 3) M.contact[0].n_impacts = 1;
        if (k == 4) M.contact[0].delta_p = 1e-9;
        msg[0] = '\0';
        if (k == 0)
            cr_assert(vi_model_check(&M, x, msg, sizeof msg) == 0, "%s", msg);
        else
            cr_assert(vi_model_check(&M, x, msg, sizeof msg) < 0 && strstr(msg, "model not set up (law = 0)"),
                      "field %d: %s", k, msg);
    }
}

/* A model never set up (law 0: an instance before initialization, or a state restored from then) is
 * evaluated as Hertz with K = 0: no force and no memory, in contact or not; the state as it is. */
Test(model, never_set_up_is_hertz_without_stiffness)
{
    double x[2] = {1e-6, -0.5};
    for (int mode = VI_Mode_free; mode <= VI_Mode_elastic; mode++) {
        vi_model M;
        memset(&M, 0, sizeof M);
        M.contact[0].mode = mode;
        vi_model_values out;
        memset(&out, 0xab, sizeof out);
        vi_model_outputs(&M, 0.0, x, VI_OUT_STATE | VI_OUT_FORCE | VI_OUT_MEMORY, &out);
        cr_assert(out.delta == 1e-6 && out.v == -0.5 && out.contact == (mode != VI_Mode_free) && out.mode == mode,
                  "mode %d: state %g %g %d %d", mode, out.delta, out.v, out.contact, out.mode);
        cr_assert(out.F == 0.0 && out.delta_c == 0.0 && out.delta_f == 0.0 && out.delta_p == 0.0 && out.Rbar == 0.0 &&
                  out.W_plastic == 0.0, "mode %d: F %g, memory %g %g %g %g %g", mode, out.F, out.delta_c, out.delta_f,
                  out.delta_p, out.Rbar, out.W_plastic);
        cr_assert(vi_model_force(&M, 0.0, x) == 0.0);
    }
}

/* The tolerance on the guards: a state a rounding beyond its surface passes, 1e-5 of delta_Y does not. */
Test(model_check, guard_tolerance)
{
    vi_model M = setup(VI_ContactModel_hertz, 0, 1, 40000.0, 9.81, 0.0);
    double x[2];
    char msg[256];
    vi_model_initial_state(&M, VI_Init_touching, 0.0, 0.0, x);
    M.contact[0].mode = VI_Mode_free;
    x[0] = 1e-9 * M.contact[0].johnson.delta_Y; /* penetrating by a rounding error while free */
    cr_assert(vi_model_check(&M, x, msg, sizeof msg) == 0, "%s", msg);
    x[0] = 1e-5 * M.contact[0].johnson.delta_Y;
    cr_assert(vi_model_check(&M, x, msg, sizeof msg) < 0);
    M.contact[0].mode = VI_Mode_elastic; /* in contact at -1e-5 delta_Y: separated */
    x[0] = -1e-5 * M.contact[0].johnson.delta_Y;
    cr_assert(vi_model_check(&M, x, msg, sizeof msg) < 0);
}

/* In stick delta' = 0 exactly; with the stick Jacobian (d delta'/dv = 0) the Newton iteration keeps
 * delta on delta_c bit for bit (with the free-motion Jacobian it drifted by 1e-6 relative). */
Test(model, stick_keeps_delta_exactly_on_delta_c)
{
    test_run s;
    test_run_init(&s, log_nothing, NULL);
    s.d.par.Y = 2e8; /* the 'stick' scenario */
    s.d.par.a = 1e-4;
    s.d.par.f = 100.0;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    int sticking = 0, touching = 0;
    for (int k = 1; k <= 500; k++) {
        cr_assert(vi_sim_advance(&s.s, 1e-4 * k) == 0, "%s", s.r.msg);
        const vi_model *M = &s.d.run.model;
        double t = s.d.run.t, *x = s.d.run.x, j[4], fd[4];
        vi_model_jacobian(M, t, x, j);
        /* the right-hand side's own derivatives, by central differences of relative step 1e-6 */
        for (int c = 0; c < 2; c++) {
            double h = 1e-6 * fmax(fabs(x[c]), c == 0 ? M->contact[0].johnson.delta_Y : 1e-3), xp[2] = {x[0], x[1]},
                   xm[2] = {x[0], x[1]}, fp[2], fm[2];
            xp[c] += h, xm[c] -= h;
            vi_model_rhs(M, t, xp, fp);
            vi_model_rhs(M, t, xm, fm);
            fd[c] = (fp[0] - fm[0]) / (2 * h), fd[2 + c] = (fp[1] - fm[1]) / (2 * h);
        }
        if (M->contact[0].mode == VI_Mode_free) continue;
        if (M->contact[0].mode != VI_Mode_stick) {
            /* other contact modes: d delta'/dv = -1, d v'/d delta = k/m (the difference's truncation
             * error is about (h/delta)^2 = 1e-12 relative, its rounding eps |v'| / (h k/m) about 1e-10) */
            touching++;
            cr_assert(j[0] == 0.0 && j[1] == -1.0 && j[3] == 0.0, "t = %g", t);
            cr_assert(fd[0] == 0.0 && fabs(fd[1] + 1.0) <= 1e-6 && fd[3] == 0.0, "t = %g: %g %g %g", t, fd[0], fd[1], fd[3]);
            cr_assert(fabs(j[2] - fd[2]) <= 1e-8 * fabs(j[2]), "t = %g mode %d: %g vs %g", t, M->contact[0].mode, j[2], fd[2]);
            continue;
        }
        sticking++;
        /* stick: delta' = 0 and v' = yC'' do not depend on the state, so the Jacobian is zero */
        for (int i = 0; i < 4; i++)
            cr_assert(j[i] == 0.0 && fd[i] == 0.0, "t = %g: J[%d] = %g, difference %g", t, i, j[i], fd[i]);
        cr_assert(x[0] == M->contact[0].unload.delta_c, "t = %g: delta - delta_c = %g", t, x[0] - M->contact[0].unload.delta_c);
    }
    cr_assert(sticking > 50 && touching > 50, "%d samples in stick, %d in other contact modes", sticking, touching);
    test_run_free(&s);
}

/* The static state at extreme loads comes from a closed form or a bounded solve,
 * never an ulp-by-ulp walk (which took 2^52 steps for load/F_Y below 1e-154). Expected indentation
 * from logarithms: d = exp(2/3 (ln W - ln K)) (Hertz, and Johnson below yield). */
Test(model, static_state_at_extreme_loads, .timeout = 20)
{
    const double loads[] = {4.9e-323, 1e-310, 1e-300, 1e-200, 1e-155, 1e-100, 1e-20, 1.0, 4e4, 1e12, 1e30, 1e100};
    for (int law = 1; law <= 3; law++)
        for (size_t i = 0; i < sizeof loads / sizeof loads[0]; i++) {
            double W = loads[i], x[2];
            vi_model M = setup(law, 0, VI_Unloading_paper, W, 0.0, 0.0);
            vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
            if (law == VI_ContactModel_lepp && W < M.contact[0].johnson.F_Y) /* linear: W/k_lin, 0 where that underflows */
                cr_assert(x[0] == W / M.contact[0].k_lin, "law %d W %g: delta = %g", law, W, x[0]);
            else
                cr_assert(x[0] > 0.0 && isfinite(x[0]), "law %d W %g: delta = %g", law, W, x[0]);
            cr_assert(M.contact[0].mode != VI_Mode_free, "law %d W %g: mode %d", law, W, M.contact[0].mode);
            if (W < M.contact[0].johnson.F_Y && law != VI_ContactModel_lepp) {
                double expect = exp(2.0 / 3.0 * (log(W) - log(M.contact[0].K)));
                cr_assert(fabs(x[0] - expect) <= 1e-13 * expect, "law %d W %g: %.17g vs %.17g", law, W, x[0], expect);
            }
            if (W >= 1e-290 && !(law == VI_ContactModel_lepp && W > M.contact[0].johnson.F_Y)) { /* the load is carried (LEPP beyond F_Y flows) */
                double F = vi_model_force(&M, 0.0, x);
                cr_assert(fabs(F - W) <= 1e-12 * W, "law %d W %g: F = %.17g", law, W, F);
            }
        }
}

/* The same for extreme parameters: R1 = 1e85 (load/F_Y ~ 1e-170) and m = 5e-324. */
Test(model, static_state_with_extreme_parameters, .timeout = 20)
{
    vi_parameters p;
    vi_parameters_default(&p);
    p.R1 = 1e85;
    vi_model M = {0};
    char msg[256];
    double x[2];
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
    double W = p.P + p.m * p.g;
    cr_assert(fabs(vi_model_force(&M, 0.0, x) - W) <= 1e-12 * W);
    vi_parameters_default(&p);
    p.m = 5e-324;
    p.P = 0.0;
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
    cr_assert(x[0] > 0.0 && M.contact[0].mode == VI_Mode_elastic, "delta %g mode %d", x[0], M.contact[0].mode);
}

/* The tolerance scales come from the active law: closed forms per case. */
Test(model, scales_from_the_active_law)
{
    double x[2], L, V;
    /* Hertz, static: L = the static indentation, whatever Y is (Y plays no role in Hertz) */
    for (int k = 0; k < 2; k++) {
        vi_parameters p;
        vi_parameters_default(&p);
        p.contact_model = VI_ContactModel_hertz;
        p.Y = k ? 1e4 : 6e8;
        p.a = 1e-300;
        vi_model M = {0};
        char msg[256];
        cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0);
        vi_model_initial_state(&M, VI_Init_static, 1e-100, 0.0, x);
        vi_model_scales(&M, x, &L, &V);
        double dW = pow((p.P + p.m * p.g) / M.contact[0].K, 2.0 / 3.0);
        cr_assert(fabs(L - dW) <= 1e-14 * dW, "Y = %g: L = %g vs %g", p.Y, L, dW);
        double w = sqrt(1.5 * M.contact[0].K * sqrt(dW) / p.m);
        cr_assert(fabs(V - dW * w) <= 1e-14 * dW * w, "V = %g", V);
    }
    /* Johnson and LEPP: the larger of delta_Y and the static indentation */
    for (int law = 2; law <= 3; law++) {
        vi_model M = setup(law, 0, 1, 40000.0, 9.81, 1e-300);
        vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
        vi_model_scales(&M, x, &L, &V);
        cr_assert(L == fmax(M.contact[0].johnson.delta_Y, x[0]), "law %d: L = %g", law, L);
    }
    /* a load however light (1e-4 N, at rest): its own static indentation, not a fallback */
    {
        vi_model M = setup(VI_ContactModel_hertz, 0, 1, 1e-4, 0.0, 0.0);
        vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
        vi_model_scales(&M, x, &L, &V);
        double dW = pow(1e-4 / M.contact[0].K, 2.0 / 3.0);
        cr_assert(fabs(L - dW) <= 1e-14 * dW, "L = %g vs %g", L, dW);
    }
    /* a drop (no load): the impact indentation at v0; Hertz closed form */
    vi_model M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_touching, -0.3, 0.0, x);
    vi_model_scales(&M, x, &L, &V);
    double dv = pow(15.0 * M.body.m * 0.09 / (16.0 * M.contact[0].johnson.E_star * sqrt(M.contact[0].johnson.R_star)), 0.4);
    cr_assert(fabs(L - dv) <= 1e-14 * dv);
    /* a drop however slow (1e-4 m/s): its own impact indentation, not a fallback */
    M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_touching, -1e-4, 0.0, x);
    vi_model_scales(&M, x, &L, &V);
    dv = pow(15.0 * M.body.m * 1e-8 / (16.0 * M.contact[0].johnson.E_star * sqrt(M.contact[0].johnson.R_star)), 0.4);
    cr_assert(fabs(L - dv) <= 1e-14 * dv, "L = %g vs %g", L, dv);
    /* a LEPP drop (no load): the larger of delta_Y and the linear spring's impact indentation
     * v sqrt(m / k_lin) (energy: m v^2 / 2 = k_lin d^2 / 2) */
    M = setup(VI_ContactModel_lepp, 0, 1, 0.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_touching, -30.0, 0.0, x);
    vi_model_scales(&M, x, &L, &V);
    dv = 30.0 * sqrt(M.body.m / M.contact[0].k_lin);
    cr_assert(dv > M.contact[0].johnson.delta_Y && fabs(L - dv) <= 1e-14 * dv, "L = %.17g, impact %.17g, delta_Y %g", L, dv, M.contact[0].johnson.delta_Y);
    /* no load, no speed: the excitation's speed; nothing at all: 1e-6 R* */
    M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 1e-4);
    vi_model_initial_state(&M, VI_Init_touching, 0.0, 0.0, x);
    vi_model_scales(&M, x, &L, &V);
    double va = 1e-4 * 2.0 * VI_PI * 560.0;
    dv = pow(15.0 * M.body.m * va * va / (16.0 * M.contact[0].johnson.E_star * sqrt(M.contact[0].johnson.R_star)), 0.4);
    cr_assert(fabs(L - dv) <= 1e-14 * dv);
    M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    vi_model_initial_state(&M, VI_Init_touching, 0.0, 0.0, x);
    vi_model_scales(&M, x, &L, &V);
    cr_assert(L == VI_SCALE_FALLBACK * M.contact[0].johnson.R_star && V > 0.0);
    /* extremes: finite and positive */
    double loads[] = {1e-200, 4.9e-323, 1e100};
    for (int i = 0; i < 3; i++)
        for (int law = 1; law <= 3; law++) {
            M = setup(law, 0, 1, loads[i], 0.0, 1e-300);
            vi_model_initial_state(&M, VI_Init_static, 1e-100, 0.0, x);
            vi_model_scales(&M, x, &L, &V);
            cr_assert(L > 0.0 && isfinite(L) && V > 0.0 && isfinite(V), "law %d W %g: %g %g", law, loads[i], L, V);
        }
}

/* LEPP: a state exactly on the yield surface (delta = delta_p + delta_Y) has not flowed: resolving it
 * leaves delta_p and delta as they are, to the bit (recomputing delta_p = delta - delta_Y would round:
 * here 1e-20 m beside delta_Y = 5.6e-5 m), in whichever mode the rates choose. */
Test(model, lepp_on_its_yield_surface_keeps_its_permanent_set)
{
    for (int k = 0; k < 2; k++) {
        vi_model M = setup(VI_ContactModel_lepp, 0, 1, k ? 40000.0 : 0.0, 0.0, 0.0);
        M.contact[0].delta_p = 1e-20;
        double x[2] = {M.contact[0].delta_p + M.contact[0].johnson.delta_Y, k ? 0.0 : -1.0}, d = x[0];
        cr_assert((d - M.contact[0].johnson.delta_Y) != M.contact[0].delta_p, "delta_p is recovered exactly: the test would not tell");
        vi_model_resolve(&M, 0.0, x);
        cr_assert(M.contact[0].delta_p == 1e-20 && x[0] == d && M.contact[0].mode != VI_Mode_free, "k %d: delta_p %.17g, delta %.17g, mode %d",
                  k, M.contact[0].delta_p, x[0], M.contact[0].mode);
    }
}

/* LEPP: freezing a plastic state writes down delta_p = delta - delta_Y and puts delta exactly on the
 * new yield surface delta_p + delta_Y (the sum may round away from the delta it came from). */
Test(model, lepp_freeze_puts_delta_on_the_yield_surface)
{
    vi_model M = setup(VI_ContactModel_lepp, 0, 1, 0.0, 0.0, 0.0);
    int differs = 0;
    for (int k = 1; k <= 200; k++) {
        double d = M.contact[0].johnson.delta_Y * (1.0 + k / 7.0) + k * 1e-19, x[2] = {d, 0.0};
        M.contact[0].mode = VI_Mode_plastic, M.contact[0].delta_p = 0.0;
        vi_model_freeze(&M, 0.0, x);
        cr_assert(M.contact[0].delta_p == d - M.contact[0].johnson.delta_Y && x[0] == M.contact[0].delta_p + M.contact[0].johnson.delta_Y && x[1] == 0.0, "k %d: %.17g %.17g",
                  k, x[0], M.contact[0].delta_p);
        differs += x[0] != d;
    }
    cr_assert(differs > 0, "no delta rounded: the test would not tell");
}

/* Ties (position, rate and force difference all zero) are broken by the next time
 * derivative, F_hold' = -F_ext' + m yC'''. Exact ties built with P equal to a force of the band. */
Test(model, stick_band_ties_broken_by_the_rate_of_the_holding_force)
{
    vi_model M = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    double dc = 3.0 * M.contact[0].johnson.delta_Y;
    vi_unload_curve U = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, dc);
    double F_load = vi_johnson_load(&M.contact[0].johnson, dc), F_unload = vi_unload_force(&U, dc);
    struct { double P, dF_ext; int mode; } cases[] = {
        {F_load, -1.0, VI_Mode_plastic},  /* on the load limit, the load grows: loading resumes */
        {F_load, +1.0, VI_Mode_stick},    /* on the load limit, the load falls: into the band */
        {F_load, 0.0, VI_Mode_stick},     /* a tie in every derivative: stays */
        {F_unload, +1.0, VI_Mode_unload}, /* on the unload limit, the load falls: unloading starts */
        {F_unload, -1.0, VI_Mode_stick},  /* on the unload limit, the load grows: into the band */
        {F_load, -1e-6, VI_Mode_plastic}, /* the same for rates of any size, however small */
        {F_unload, +1e-6, VI_Mode_unload},
    };
    for (int i = 0; i < 7; i++) {
        M.body.W0 = cases[i].P; /* g = 0, a = 0: F_hold = W = P at the ramp's time */
        M.F_ext = (vi_ramp){0.0, cases[i].dF_ext, 0.5};
        M.contact[0].yielded = 1, M.contact[0].unload = U, M.contact[0].mode = VI_Mode_stick;
        double x[2] = {dc, 0.0};
        cr_assert(vi_model_resolve(&M, 0.5, x) == cases[i].mode, "case %d: mode %d", i, M.contact[0].mode);
    }
}

/* A stick guard that fires is on its surface even though the located root leaves it slightly on the
 * near side: the mass starts loading at the quarter period where F_hold = W - m a w^2 cos(w t)
 * rises through F_load = W (it stayed in stick a whole period before). */
Test(model, fired_stick_guard_counts_as_on_its_surface)
{
    vi_model M = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 1e-5);
    double dc = 3.0 * M.contact[0].johnson.delta_Y;
    vi_unload_curve U = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, dc);
    M.body.W0 = vi_johnson_load(&M.contact[0].johnson, dc);
    double w = M.omega, tq = 0.25 * 2.0 * VI_PI / w;
    for (int k = -3; k <= 3; k++) {
        double t = tq + k * 1e-16; /* the root as a solver locates it, on either side */
        M.contact[0].yielded = 1, M.contact[0].unload = U, M.contact[0].mode = VI_Mode_stick;
        double x[2] = {dc, 0.0}, g[VI_NGUARDS];
        vi_model_freeze(&M, t, x);
        vi_model_guards(&M, t, x, g);
        cr_assert(fabs(g[0]) < 1e-9 * M.body.W0, "k %d: g0 = %g", k, g[0]);
        cr_assert(vi_model_event(&M, t, x, 0) == VI_Mode_plastic, "k %d: mode %d", k, M.contact[0].mode);
    }
}

/* The validity thresholds (vi_model.h): delta > 0.01 R* (contact radius sqrt(R* delta) > 0.1 R*),
 * |a| > R*, a profile whose heights span more than R1; each cause once (skip). */
Test(model, validity_threshold)
{
    vi_model M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    double x[2] = {0.0, 0.0}, limit = 0.01 * M.contact[0].johnson.R_star, R1 = 0.475;
    char msg[400];
    M.contact[0].mode = VI_Mode_elastic;
    x[0] = limit * (1.0 - 1e-12);
    cr_assert(vi_model_validity(&M, R1, 0.0, x, 0, msg, sizeof msg) == 0);
    x[0] = limit * (1.0 + 1e-12);
    cr_assert(vi_model_validity(&M, R1, 1.5, x, 0, msg, sizeof msg) == VI_INVALID_INDENTATION);
    cr_assert(strstr(msg, "t = 1.5 s") && strstr(msg, "0.01 R*"), "%s", msg);
    cr_assert(vi_model_validity(&M, R1, 1.5, x, VI_INVALID_INDENTATION, msg, sizeof msg) == 0);
    M.contact[0].mode = VI_Mode_free; /* apart: no contact radius */
    cr_assert(vi_model_validity(&M, R1, 0.0, x, 0, msg, sizeof msg) == 0);
    /* the amplitude against R* (= R1 = 0.475 m here, R2 = 0), either sign */
    M.a = -M.contact[0].johnson.R_star;
    cr_assert(vi_model_validity(&M, R1, 0.0, x, 0, msg, sizeof msg) == 0);
    M.a = nextafter(-M.contact[0].johnson.R_star, -INFINITY);
    cr_assert(vi_model_validity(&M, R1, 2.0, x, 0, msg, sizeof msg) == VI_INVALID_AMPLITUDE);
    cr_assert(strstr(msg, "t = 2 s") && strstr(msg, "a = -0.475 m") && strstr(msg, "R* = 0.475 m"), "%s", msg);
    cr_assert(vi_model_validity(&M, R1, 2.0, x, VI_INVALID_AMPLITUDE, msg, sizeof msg) == 0);
    M.a = 0.0;
    vi_parameters p;
    vi_parameters_default(&p);
    cr_assert(warnings_from_table(&p, msg, sizeof msg) == 0 && msg[0] == '\0');
    p.contact_model = VI_ContactModel_lepp, p.moving_contact = 1, p.unloading = 2, p.v0 = 1.0;
    cr_assert(warnings_from_table(&p, msg, sizeof msg) == 3, "%s", msg);
    cr_assert(strstr(msg, "moving_contact") && strstr(msg, "unloading") && strstr(msg, "v0"), "%s", msg);
    char tiny[8]; /* truncated, never overrun */
    cr_assert(warnings_from_table(&p, tiny, sizeof tiny) == 3 && strlen(tiny) == 7);
    /* the yield formula is ignored by Hertz only: every law with the default, Johnson and LEPP printed */
    int laws[] = {VI_ContactModel_hertz, VI_ContactModel_johnson, VI_ContactModel_lepp};
    for (int i = 0; i < 3; i++) {
        vi_parameters_default(&p);
        p.contact_model = laws[i];
        cr_assert(warnings_from_table(&p, msg, sizeof msg) == 0, "law %d: %s", laws[i], msg);
        p.yield_formula = VI_YieldFormula_printed;
        cr_assert(warnings_from_table(&p, msg, sizeof msg) == (laws[i] == VI_ContactModel_hertz), "%s", msg);
    }
}

/* A profile whose heights span more than R1 is accepted (its slopes are gentle) and out of validity. */
Test(model, validity_of_the_profile_heights)
{
    const double x[] = {0.0, 50.0, 100.0}, h_ok[] = {0.0, 0.4, 0.0}, h_tall[] = {0.0, 0.5, 0.0};
    char msg[400];
    for (int tall = 0; tall < 2; tall++) {
        vi_profile *p = vi_profile_create(x, tall ? h_tall : h_ok, 3, 0.475, 0, "test", msg, sizeof msg);
        cr_assert(p != NULL, "%s", msg);
        cr_assert(vi_profile_height_span(p) == (tall ? 0.5 : 0.4));
        vi_model M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
        cr_assert(vi_model_set_rolling(&M, p, 1.0, 10.0, msg, sizeof msg) == 0, "%s", msg);
        double s[2] = {0.0, 0.0};
        int cause = vi_model_validity(&M, 0.475, 0.0, s, 0, msg, sizeof msg);
        cr_assert(cause == (tall ? VI_INVALID_PROFILE : 0), "tall %d: %d %s", tall, cause, msg);
        if (tall) cr_assert(strstr(msg, "span 0.5 m") && strstr(msg, "R1 = 0.475 m"), "%s", msg);
        vi_profile_free(p);
    }
}

/* ---- tunable excitation ------------------------------------------------------------------------- */

/* A mass thrown up and away (no load, v0 = 1 m/s): the platform's position is the excitation alone. */
static void flying(test_run *s, double a, double f)
{
    test_run_init(s, log_nothing, NULL);
    s->d.par.contact_model = VI_ContactModel_hertz;
    s->d.par.P = 0.0, s->d.par.g = 0.0, s->d.par.init = VI_Init_touching, s->d.par.v0 = 1.0;
    s->d.par.a = a, s->d.par.f = f;
    s->d.par.rtol = 1e-9; /* the free-flight comparison below is at 1e-6: well above the global error */
    cr_assert(vi_sim_initialize(&s->s) == 0, "%s", s->r.msg);
}

Test(excitation, frequency_change_keeps_phase_and_position_continuous)
{
    test_run s;
    flying(&s, 1e-4, 100.0);
    double t1 = 0.0123, t2 = 0.02;
    cr_assert(vi_sim_advance(&s.s, t1) == 0, "%s", s.r.msg);
    double y_before = vi_model_platform(&s.d.run.model, t1, NULL, NULL), v_mass = s.d.run.x[1], y_mass = y_before - s.d.run.x[0];
    s.d.par.f = 250.0;
    s.d.run.inputs_changed = 1;
    cr_assert(vi_sim_advance(&s.s, t2) == 0, "%s", s.r.msg);
    double ph1 = 2.0 * VI_PI * 100.0 * t1; /* closed form: the phase at t1, then 250 Hz */
    cr_assert(fabs(vi_model_phase(&s.d.run.model, t1) - fmod(ph1, 2.0 * VI_PI)) < 1e-14);
    cr_assert(fabs(vi_model_platform(&s.d.run.model, t1, NULL, NULL) - y_before) <= 1e-18, "yC jumped");
    double expect = 1e-4 * (cos(ph1 + 2.0 * VI_PI * 250.0 * (t2 - t1)) - 1.0);
    cr_assert(fabs(vi_model_platform(&s.d.run.model, t2, NULL, NULL) - expect) <= 1e-17, "%g vs %g",
              vi_model_platform(&s.d.run.model, t2, NULL, NULL), expect);
    /* free flight: the mass never felt the change (y = y1 + v1 (t - t1), no load) */
    double y2 = vi_model_platform(&s.d.run.model, t2, NULL, NULL) - s.d.run.x[0];
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_free && s.d.run.x[1] == v_mass, "the mass got a kick");
    cr_assert(fabs(y2 - (y_mass + v_mass * (t2 - t1))) <= 1e-6 * y2, "%.17g", y2);
    test_run_free(&s);
}

Test(excitation, amplitude_change_moves_the_platform_not_the_mass)
{
    test_run s;
    flying(&s, 1e-4, 100.0);
    double t1 = 0.0031;
    cr_assert(vi_sim_advance(&s.s, t1) == 0, "%s", s.r.msg);
    double d_before = s.d.run.x[0], y_mass = vi_model_platform(&s.d.run.model, t1, NULL, NULL) - d_before;
    s.d.par.a = 3e-4;
    s.d.run.inputs_changed = 1;
    cr_assert(vi_sim_advance(&s.s, t1 + 1e-3) == 0, "%s", s.r.msg);
    double c = cos(2.0 * VI_PI * 100.0 * t1);
    /* apply the change alone: redo it on a copy at t1 */
    test_run r;
    flying(&r, 1e-4, 100.0);
    cr_assert(vi_sim_advance(&r.s, t1) == 0);
    vi_model_set_excitation(&r.d.run.model, t1, r.d.run.x, 3e-4, 100.0); /* at t1 itself, as the loop does next step */
    cr_assert(fabs(r.d.run.x[0] - (d_before + 2e-4 * (c - 1.0))) <= 1e-18, "delta jumps by da (cos - 1)");
    cr_assert(fabs(vi_model_platform(&r.d.run.model, t1, NULL, NULL) - r.d.run.x[0] - y_mass) <= 1e-18, "the mass moved");
    cr_assert(fabs(vi_model_platform(&r.d.run.model, t1, NULL, NULL) - 3e-4 * (c - 1.0)) <= 1e-18);
    test_run_free(&s);
    test_run_free(&r);
}

/* Up and down sweeps by changes at communication points: the platform follows the closed-form
 * accumulated phase phi = sum f_k 2 pi dt_k at every point. */
Test(excitation, sweep_up_and_down_follows_the_accumulated_phase)
{
    test_run s;
    flying(&s, 1e-4, 50.0);
    double t = 0.0, phase = 0.0, f = 50.0, h = 1e-3;
    for (int k = 0; k < 60; k++) {
        double f_next = k < 30 ? 50.0 + 10.0 * k : 50.0 + 10.0 * (59 - k); /* up, then down */
        if (f_next != f) s.d.par.f = f_next, s.d.run.inputs_changed = 1, f = f_next;
        cr_assert(vi_sim_advance(&s.s, t + h) == 0, "%s", s.r.msg);
        phase += 2.0 * VI_PI * f * h;
        t += h;
        double expect = 1e-4 * (cos(phase) - 1.0), dyC, yC = vi_model_platform(&s.d.run.model, t, &dyC, NULL);
        cr_assert(fabs(yC - expect) <= 1e-13 * 1e-4, "k %d: %g vs %g (%g)", k, yC, expect, yC - expect);
        cr_assert(fabs(dyC + 1e-4 * 2.0 * VI_PI * f * sin(phase)) <= 1e-12, "k %d: velocity", k);
    }
    test_run_free(&s);
}

/* ---- rolling over a profile --------------------------------------------------------------------- */

/* A V-shaped trough of slope s0 with its bottom at x = 0 on [-10, 10] m, written to a file:
 * yb = s0 |x| + R1 (sqrt(1 + s0^2) - 1). */
static const char *v_trough_file(double s0)
{
    static char path[64];
    snprintf(path, sizeof path, "/tmp/vi_model_test_v_%d.txt", (int)getpid());
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL);
    fprintf(f, "-10 %.17g\n0 0\n10 %.17g\n", 10.0 * s0, 10.0 * s0);
    fclose(f);
    return path;
}

/* A simulation of the defaults rolled over the trough (parameters profile_file, V, x0). */
static void rolling_sim(test_run *s, double s0, double V, double x0, double rtol)
{
    test_run_init(s, log_nothing, NULL);
    s->d.par.contact_model = VI_ContactModel_hertz;
    s->d.par.solver = VI_Solver_adams; /* an implicit method keeps a static rest to rounding */
    s->d.par.rtol = rtol;
    snprintf(s->d.par.profile_file, sizeof s->d.par.profile_file, "%s", v_trough_file(s0));
    s->d.par.V = V, s->d.par.x0 = x0;
    cr_assert(vi_sim_initialize(&s->s) == 0, "%s", s->r.msg);
}

/* Rolling at V = 0 over a profile with a kink behind (and ahead of) the start: no breakpoint ever,
 * the static state stays as it is (to rounding). */
Test(rolling, no_breakpoint_at_zero_speed, .timeout = 10)
{
    for (int k = 0; k < 2; k++) {
        test_run s;
        rolling_sim(&s, 1e-4, 0.0, k ? -0.5 : 0.5, 1e-8);
        cr_assert(vi_model_next_breakpoint(&s.d.run.model, s.d.run.t) == INFINITY);
        double x0 = s.d.run.x[0];
        cr_assert(vi_sim_advance(&s.s, 0.01) == VI_SIM_OK && s.d.run.t == 0.01, "%s", s.r.msg);
        cr_assert(fabs(s.d.run.x[0] - x0) <= 1e-9 * x0 && fabs(s.d.run.x[1]) <= 1e-12 && s.d.run.events.n_events == 0,
                  "delta %g -> %g, v %g, %ld events", x0, s.d.run.x[0], s.d.run.x[1], (long)s.d.run.events.n_events);
        test_run_free(&s);
    }
}

/* Static start on Hertz, rolled at V over the trough's kink: before it the mass rides the platform
 * down uniformly (delta stays static); the kink turns the platform velocity by 2 s0 V, and the
 * contact rings with amplitude 2 s0 V / omega_c (linearised, omega_c = 2 pi f_contact). The loop
 * stops at the kink (doc/model.md section 6) and restarts there. */
Test(rolling, kink_is_a_breakpoint_and_rings_the_contact)
{
    for (int dir = -1; dir <= 1; dir += 2) {
        double s0 = 1e-4, V = 1.0 * dir, x0 = -0.01 * dir, tk = 0.01; /* the kink at x = 0, t = 10 ms */
        test_run s;
        rolling_sim(&s, s0, V, x0, 1e-10);
        double ds = s.d.run.x[0], w = 2.0 * VI_PI * s.d.run.model.f_contact;
        cr_assert(fabs(s.d.run.x[1] - (-s0 * V * dir)) <= 1e-18, "v0 %g", s.d.run.x[1]); /* yC' = -s0 |V| before the kink */
        double bp = vi_model_next_breakpoint(&s.d.run.model, 0.0);
        double xk = vi_profile_next_kink(s.d.run.model.profile, -dir, dir), pos = vi_model_rolling_position(&s.d.run.model, bp);
        cr_assert(fabs(xk) < 1e-14 && fabs(bp - tk) <= 1e-14 && (dir > 0 ? pos >= xk : pos < xk),
                  "breakpoint %.17g: position %g, kink %g", bp, pos, xk);
        double L, Vs;
        vi_model_scales(&s.d.run.model, s.d.run.x, &L, &Vs);
        s.d.run.events.atol[0] = 1e-10 * L, s.d.run.events.atol[1] = 1e-10 * Vs;
        s.d.run.initialized = 1; /* set up by hand: the solver starts from this state */
        cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
        double before = 0.0, after = 0.0;
        for (int k = 1; k <= 400; k++) {
            double t = 5e-5 * k;
            cr_assert(vi_sim_advance(&s.s, t) == 0, "%s", s.r.msg);
            if (t < tk) before = fmax(before, fabs(s.d.run.x[0] - ds));
            else after = fmax(after, fabs(s.d.run.x[0] - ds));
        }
        double amp = 2.0 * s0 * fabs(V) / w;
        cr_assert(before <= 1e-6 * amp, "dir %d: delta moved before the kink by %g", dir, before);
        cr_assert(fabs(after - amp) <= 0.01 * amp, "dir %d: ringing %g vs %g", dir, after, amp);
        test_run_free(&s);
    }
    remove(v_trough_file(1e-4));
}

Test(rolling, the_profile_ends)
{
    test_run s;
    rolling_sim(&s, 1e-4, 1000.0, 9.0, 1e-6); /* x in [-10, 10]: the end at t = 1 ms */
    cr_assert(vi_sim_advance(&s.s, 5e-4) == VI_SIM_OK, "%s", s.r.msg);
    cr_assert(vi_sim_advance(&s.s, 2e-3) == VI_SIM_DISCARD);
    cr_assert(fabs(s.d.run.t - 1e-3) < 1e-15 && strstr(s.r.msg, "t = 0.001") && strstr(s.r.msg, "x_last = 10 m"), "t %g: %s",
              s.d.run.t, s.r.msg);
    test_run_free(&s);
    /* a step that ends exactly where the profile ends is complete: x_last is on the profile */
    rolling_sim(&s, 1e-4, 1000.0, 9.0, 1e-6);
    char why[400];
    double end = vi_model_rolling_limit(&s.d.run.model, why, sizeof why);
    cr_assert(vi_sim_advance(&s.s, end) == VI_SIM_OK, "%s", s.r.msg);
    cr_assert(s.d.run.t == end && vi_model_rolling_position(&s.d.run.model, s.d.run.t) == 10.0);
    cr_assert(vi_sim_advance(&s.s, end + 1e-6) == VI_SIM_DISCARD && s.d.run.t == end);
    test_run_free(&s);
    test_run_init(&s, log_nothing, NULL); /* x0 outside the table */
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "%s", v_trough_file(1e-4));
    s.d.par.V = 1.0, s.d.par.x0 = 11.0;
    cr_assert(vi_sim_initialize(&s.s) < 0);
    cr_assert(strstr(s.r.msg, "x0 = 11 m lies outside the profile [-10, 10] m"), "%s", s.r.msg);
    test_run_free(&s);
    remove(v_trough_file(1e-4));
}

/* The end of the table in the direction of travel, however slow: t_end = t0 + (x_end - x0)/V. */
Test(rolling, the_profile_ends_ahead_for_slow_rolling_too)
{
    double x[] = {-10.0, 0.0, 10.0}, h[] = {1e-3, 0.0, 1e-3};
    char msg[512];
    vi_profile *prof = vi_profile_create(x, h, 3, 0.475, 0, "trough", msg, sizeof msg);
    cr_assert(prof != NULL, "%s", msg);
    vi_model M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    double V[] = {1e-5, 2.0, -1e-5, -2.0}, expect[] = {1e5, 0.5, 1.9e6, 9.5};
    for (int i = 0; i < 4; i++) {
        cr_assert(vi_model_set_rolling(&M, prof, V[i], 9.0, msg, sizeof msg) == 0, "%s", msg);
        double t = vi_model_rolling_limit(&M, msg, sizeof msg);
        cr_assert(fabs(t - expect[i]) <= 1e-12 * expect[i], "V = %g: t = %.17g", V[i], t);
        cr_assert(strstr(msg, V[i] > 0 ? "x_last = 10 m" : "x_first = -10 m"), "%s", msg);
    }
    cr_assert(vi_model_set_rolling(&M, prof, 0.0, 9.0, msg, sizeof msg) == 0);
    cr_assert(vi_model_rolling_limit(&M, msg, sizeof msg) == INFINITY); /* standing still: never */
    vi_profile_free(prof);
}

/* A restored state carries a profile pointer that is never used: restore attaches the instance's own
 * (here: a fresh instance with the same parameters, and a saved pointer spoiled on purpose). */
Test(rolling, restore_reattaches_the_profile)
{
    test_run a, b;
    rolling_sim(&a, 1e-4, 1.0, -0.01, 1e-8);
    rolling_sim(&b, 1e-4, 1.0, -0.01, 1e-8);
    cr_assert(vi_sim_advance(&a.s, 5e-3) == 0);
    cr_assert(vi_sim_checkpoint(&a.s) == 0);
    test_run_copy_data(&b, &a);
    b.d.run.model.profile = (const vi_profile *)(uintptr_t)0x1; /* garbage: must not be followed */
    char msg[256];
    cr_assert(vi_contact_state_check(&b.d, 1, 0, msg, sizeof msg) == 0, "%s", msg);
    cr_assert(vi_sim_restore(&b.s) == 0, "%s", b.r.msg);
    cr_assert(b.d.run.model.profile == b.r.profile && b.r.profile != a.r.profile);
    cr_assert(vi_sim_advance(&a.s, 0.02) == 0 && vi_sim_advance(&b.s, 0.02) == 0);
    cr_assert(a.d.run.x[0] == b.d.run.x[0] && a.d.run.x[1] == b.d.run.x[1], "restored run differs");
    test_run_free(&a), test_run_free(&b);
    remove(v_trough_file(1e-4));
}

/* The holding force of a sticking mass includes the profile's curvature: F_hold = W + m V^2 yb''. */
Test(rolling, platform_derivatives_follow_the_profile)
{
    double x[] = {-1.0, 0.0, 1e-9, 1.0}, h[] = {0.0, 0.0, 0.01, 0.01}; /* a step: a circular ramp */
    char msg[256];
    vi_profile *prof = vi_profile_create(x, h, 4, 0.475, 0, "step", msg, sizeof msg);
    vi_model M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    cr_assert(vi_model_set_rolling(&M, prof, 3.0, -0.05, msg, sizeof msg) == 0);
    double t = 0.004, d = -0.05 + 3.0 * t - 1e-9, R = 0.475, dyC, ddyC; /* on the ramp */
    double yC = vi_model_platform(&M, t, &dyC, &ddyC);
    cr_assert(fabs(yC - (0.01 - d * d / (R + sqrt(R * R - d * d)))) <= 1e-15);
    cr_assert(fabs(dyC - 3.0 * (-d / sqrt(R * R - d * d))) <= 1e-12);
    cr_assert(fabs(ddyC - 9.0 * (-R * R / pow(R * R - d * d, 1.5))) <= 1e-9);
    vi_profile_free(prof);
}

/* Johnson with a moving contact point has no memory: free, elastic and plastic are its only modes,
 * and the check refuses unloading and stick for it by that rule (naming the law and moving = 1),
 * before any rule of those modes' surfaces. */
Test(model_check, moving_contact_has_no_unloading_or_stick)
{
    vi_model M = setup(VI_ContactModel_johnson, 1, VI_Unloading_paper, 40000.0, 9.81, 0.0);
    double x[2];
    char msg[256];
    vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
    cr_assert(vi_model_check(&M, x, msg, sizeof msg) == 0, "%s", msg);
    for (int mode = VI_Mode_unload; mode <= VI_Mode_stick; mode++) {
        vi_model B = M;
        B.contact[0].mode = mode;
        msg[0] = '\0';
        cr_assert(vi_model_check(&B, x, msg, sizeof msg) < 0, "mode %d accepted", mode);
        char expect[96];
        snprintf(expect, sizeof expect, "mode = %d is impossible for contact_model johnson (moving 1", mode);
        cr_assert(strstr(msg, expect) != NULL, "expected '%s' in: %s", expect, msg);
    }
}

/* ---- vi_model_check, rule by rule: each rule broken alone, refused with its whole message ---------- */

/* The check refuses (M, x) with exactly the message `fmt` (printf-formatted with the spoiled values). */
static void refused_with(const vi_model *M, const double x[2], int surfaces, const char *fmt, ...)
{
    char expect[512], msg[512] = "";
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(expect, sizeof expect, fmt, ap);
    va_end(ap);
    int rc = surfaces ? vi_model_check(M, x, msg, sizeof msg) : vi_model_check_between_events(M, x, msg, sizeof msg);
    cr_assert(rc == -1, "accepted (rc %d); expected: %s", rc, expect);
    cr_assert(strcmp(msg, expect) == 0, "expected '%s', got '%s'", expect, msg);
}

static void accepted_as(const vi_model *M, const double x[2], const char *what)
{
    char msg[512] = "";
    int rc = vi_model_check(M, x, msg, sizeof msg);
    cr_assert(rc == 0, "%s: rc %d: %s", what, rc, msg);
}

/* Johnson with a fixed contact point after a yielding impact: unloading at delta between delta_f and
 * delta_c (the state of yielded_model, for any unloading variant and parameters). */
static vi_model unloading_model(const vi_parameters *p, double x[2])
{
    vi_model M = {0};
    char msg[256];
    cr_assert(setup_from_table(&M, p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, M.contact[0].unloading, 3.0 * M.contact[0].johnson.delta_Y);
    M.contact[0].yielded = 1;
    M.contact[0].mode = VI_Mode_unload;
    x[0] = 0.5 * (M.contact[0].unload.delta_f + M.contact[0].unload.delta_c);
    x[1] = 1.0;
    accepted_as(&M, x, "unloading model");
    return M;
}

static vi_model default_unloading_model(double x[2])
{
    vi_parameters p;
    vi_parameters_default(&p);
    return unloading_model(&p, x);
}

/* Each constant: not finite (every one of the 17, by name and value), and for those that must be
 * positive, 0 (the bound itself) refused as not positive, before any consistency rule. */
Test(model_check, every_constant_must_be_finite_and_the_positive_ones_positive)
{
    double x0[2];
    vi_model ok = default_unloading_model(x0);
    struct { const char *name; size_t offset; int positive; } c[] = {
        {"m", offsetof(vi_model, body.m), 1},           {"W0", offsetof(vi_model, body.W0), 0},
        {"K", offsetof(vi_model, contact[0].K), 1},           {"E_star", offsetof(vi_model, contact[0].johnson.E_star), 1},
        {"R_star", offsetof(vi_model, contact[0].johnson.R_star), 1}, {"theta_Y", offsetof(vi_model, contact[0].johnson.theta_Y), 1},
        {"F_Y", offsetof(vi_model, contact[0].johnson.F_Y), 1},     {"delta_Y", offsetof(vi_model, contact[0].johnson.delta_Y), 1},
        {"k_lin", offsetof(vi_model, contact[0].k_lin), 1},   {"a", offsetof(vi_model, a), 0},
        {"omega", offsetof(vi_model, omega), 0},   {"t0", offsetof(vi_model, t0), 0},
        {"phi0", offsetof(vi_model, phi0), 0},     {"t_phi", offsetof(vi_model, t_phi), 0},
        {"V", offsetof(vi_model, V), 0},           {"x0", offsetof(vi_model, x0), 0},
        {"f_contact", offsetof(vi_model, f_contact), 0}};
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        double bad[] = {NAN, INFINITY, -INFINITY};
        for (int k = 0; k < 3; k++) {
            vi_model M = ok;
            memcpy((char *)&M + c[i].offset, &bad[k], sizeof bad[k]);
            refused_with(&M, x0, 1, "model constant %s = %g is not finite", c[i].name, bad[k]);
        }
        vi_model M = ok;
        double zero = 0.0;
        memcpy((char *)&M + c[i].offset, &zero, sizeof zero);
        if (c[i].positive)
            refused_with(&M, x0, 1, "model constant %s = 0 is not positive", c[i].name);
        else
            accepted_as(&M, x0, c[i].name); /* 0 is a value of its own (no excitation, start at 0, ...) */
    }
    /* the free constants take either sign (omega and f_contact excepted: below) */
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        if (c[i].positive || strcmp(c[i].name, "omega") == 0 || strcmp(c[i].name, "f_contact") == 0) continue;
        vi_model M = ok;
        double negative = -1e-4;
        memcpy((char *)&M + c[i].offset, &negative, sizeof negative);
        accepted_as(&M, x0, c[i].name);
    }
    /* a mass and a yield angle far below 1 are masses and angles like any other */
    vi_model M = ok;
    M.body.m = 1e-4;
    accepted_as(&M, x0, "m = 1e-4 kg");
    M = ok;
    M.contact[0].johnson.theta_Y = 1e-4;
    accepted_as(&M, x0, "theta_Y = 1e-4");
    /* negative: omega and f_contact (0 and small values pass) */
    M = ok;
    M.omega = -1e-300;
    refused_with(&M, x0, 1, "model constant omega = -1e-300 is negative");
    M.omega = 1e-4;
    accepted_as(&M, x0, "omega = 1e-4 rad/s");
    M = ok;
    M.f_contact = -1e-300;
    refused_with(&M, x0, 1, "model constant f_contact = -1e-300 is negative");
    M.f_contact = 1e-4;
    accepted_as(&M, x0, "f_contact = 1e-4 Hz");
    /* every non-positive value of a positive constant, not only 0 */
    M = ok;
    M.contact[0].johnson.R_star = -0.2;
    refused_with(&M, x0, 1, "model constant R_star = -0.2 is not positive");
}

/* K = 4/3 E* sqrt(R*), F_Y = K delta_Y^1.5 and k_lin = F_Y/delta_Y hold to 1e-9 relative: 2e-9 off is
 * refused (naming the constant), 0.5e-9 off passes. */
Test(model_check, constants_consistent_to_1e_9)
{
    double x0[2];
    vi_model ok = default_unloading_model(x0);
    vi_model M = ok;
    M.contact[0].K = ok.contact[0].K * (1.0 + 2e-9);
    refused_with(&M, x0, 1, "model constant K = %g does not match 4/3 E* sqrt(R*)", M.contact[0].K);
    M.contact[0].K = ok.contact[0].K * (1.0 + 0.5e-9);
    accepted_as(&M, x0, "K 0.5e-9 off");
    M = ok;
    M.contact[0].johnson.F_Y = ok.contact[0].johnson.F_Y * (1.0 - 2e-9);
    refused_with(&M, x0, 1, "model constant delta_Y = %g does not match F_Y = K delta_Y^1.5", M.contact[0].johnson.delta_Y);
    M.contact[0].johnson.F_Y = ok.contact[0].johnson.F_Y * (1.0 - 0.5e-9);
    M.contact[0].k_lin = M.contact[0].johnson.F_Y / M.contact[0].johnson.delta_Y;
    accepted_as(&M, x0, "F_Y 0.5e-9 off");
    M = ok;
    M.contact[0].k_lin = ok.contact[0].k_lin * (1.0 + 2e-9);
    refused_with(&M, x0, 1, "model constant k_lin = %g does not match F_Y/delta_Y", M.contact[0].k_lin);
    M.contact[0].k_lin = ok.contact[0].k_lin * (1.0 - 0.5e-9);
    accepted_as(&M, x0, "k_lin 0.5e-9 off");
}

/* The bound of "to 1e-9 relative" itself: |k_lin - F_Y/delta_Y| = 1e-9 max(...) exactly passes. With
 * delta_Y = 1 m, F_Y = 999999999 N and k_lin = 1e9 N/m the difference is 1 N/m and 1e-9 k_lin rounds to
 * 1 exactly (a Hertz model built around these numbers: K = F_Y, R* = 1 m, E* = 3/4 K). */
Test(model_check, consistency_bound_is_inclusive)
{
    vi_model M = {0};
    M.contact[0].law = VI_ContactModel_hertz, M.contact[0].unloading = VI_UNLOAD_PAPER, M.body.m = 1.0;
    M.contact[0].johnson.R_star = 1.0, M.contact[0].johnson.E_star = 0.75 * 999999999.0, M.contact[0].johnson.theta_Y = 1.0;
    M.contact[0].johnson.delta_Y = 1.0, M.contact[0].johnson.F_Y = 999999999.0, M.contact[0].K = 999999999.0;
    M.contact[0].k_lin = 1e9;
    M.ncontacts = 1, M.contact[VI_UPPER].upper = 1; /* the lower contact alone */
    double x[2] = {0.0, 0.0};
    cr_assert(fabs(M.contact[0].k_lin - M.contact[0].johnson.F_Y / M.contact[0].johnson.delta_Y) == 1e-9 * fmax(M.contact[0].k_lin, M.contact[0].johnson.F_Y / M.contact[0].johnson.delta_Y));
    accepted_as(&M, x, "k_lin exactly 1e-9 off");
    M.contact[0].k_lin = nextafter(1e9, INFINITY);
    refused_with(&M, x, 1, "model constant k_lin = %g does not match F_Y/delta_Y", M.contact[0].k_lin);
}

/* The input ramps: each of value, rate and time of yC_in and F_ext non-finite alone. */
Test(model_check, input_ramps_must_be_finite)
{
    double x0[2];
    vi_model ok = default_unloading_model(x0);
    ok.yC_in = (vi_ramp){1e-3, -2e-3, 0.5};
    ok.F_ext = (vi_ramp){7.0, 3.0, 0.25};
    accepted_as(&ok, x0, "finite ramps");
    const char *names[2] = {"yC_in", "F_ext"};
    for (int r = 0; r < 2; r++)
        for (int field = 0; field < 3; field++) {
            vi_model M = ok;
            vi_ramp *ramp = r ? &M.F_ext : &M.yC_in;
            double *v = field == 0 ? &ramp->u : field == 1 ? &ramp->du : &ramp->t;
            *v = field == 1 ? -INFINITY : NAN;
            refused_with(&M, x0, 1, "model input ramp %s (%g, %g, %g) is not finite", names[r], ramp->u, ramp->du,
                         ramp->t);
        }
}

/* The state, the enumerations and the flags, each refused alone with its message. */
Test(model_check, state_enumerations_and_flags)
{
    double x0[2];
    vi_model ok = default_unloading_model(x0);
    double x[2] = {x0[0], INFINITY};
    refused_with(&ok, x, 1, "state (delta %g, v inf) is not finite", x0[0]);
    x[0] = NAN, x[1] = 0.25;
    refused_with(&ok, x, 1, "state (delta nan, v 0.25) is not finite");
    int laws[] = {-1, 0x7fffffff, 7};
    for (int i = 0; i < 3; i++) {
        vi_model M = ok;
        M.contact[0].law = laws[i];
        refused_with(&M, x0, 1, "contact law = %d is not one of 1 (hertz) ... 6 (thornton)", laws[i]);
    }
    int flags[] = {-1, 2};
    for (int i = 0; i < 2; i++) {
        vi_model M = ok;
        M.contact[0].moving = flags[i];
        refused_with(&M, x0, 1, "model flag moving = %d is not 0 or 1", flags[i]);
        M = ok;
        M.contact[0].yielded = flags[i];
        refused_with(&M, x0, 1, "model flag yielded = %d is not 0 or 1", flags[i]);
    }
    int unloading[] = {0, 3};
    for (int i = 0; i < 2; i++) {
        vi_model M = ok;
        M.contact[0].unloading = unloading[i];
        refused_with(&M, x0, 1, "unloading = %d is not paper (1) or continuous (2)", unloading[i]);
    }
    int modes[] = {-1, 5};
    for (int i = 0; i < 2; i++) {
        vi_model M = ok;
        M.contact[0].mode = modes[i];
        refused_with(&M, x0, 1, "mode = %d is not in 0..4", modes[i]);
    }
    vi_model M = ok;
    M.contact[0].n_impacts = -1;
    refused_with(&M, x0, 1, "n_impacts = -1 is negative");
    M.contact[0].n_impacts = 0;
    accepted_as(&M, x0, "no impact yet");
}

/* delta_p: finite for every law; LEPP's permanent set is >= 0 (0 and any positive set pass), the other
 * laws have none. */
Test(model_check, permanent_set_of_each_law)
{
    double x[2] = {0.0, 1.0};
    vi_model L = setup(VI_ContactModel_lepp, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    L.contact[0].mode = VI_Mode_free;
    double sets[] = {0.0, 5e-4, 0.5};
    for (int i = 0; i < 3; i++) {
        L.contact[0].delta_p = sets[i];
        accepted_as(&L, x, "LEPP permanent set >= 0");
    }
    L.contact[0].delta_p = -1e-9;
    refused_with(&L, x, 1, "delta_p = -1e-09 is impossible for contact_model lepp");
    L.contact[0].delta_p = NAN;
    refused_with(&L, x, 1, "delta_p = nan is not finite");
    L.contact[0].delta_p = INFINITY;
    refused_with(&L, x, 1, "delta_p = inf is not finite");
    int laws[] = {VI_ContactModel_hertz, VI_ContactModel_johnson};
    const char *names[] = {"hertz", "johnson"};
    for (int i = 0; i < 2; i++) {
        vi_model M = setup(laws[i], 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
        M.contact[0].mode = VI_Mode_free;
        accepted_as(&M, x, names[i]);
        M.contact[0].delta_p = 1e-6;
        refused_with(&M, x, 1, "delta_p = 1e-06 is impossible for contact_model %s", names[i]);
        M.contact[0].delta_p = -1e-3;
        refused_with(&M, x, 1, "delta_p = -0.001 is impossible for contact_model %s", names[i]);
        M.contact[0].delta_p = -INFINITY;
        refused_with(&M, x, 1, "delta_p = -inf is not finite");
    }
}

/* Without yield the unloading curve is all zero: each of its five values alone is refused (the
 * message gives delta_c and Rbar); with yield it exists for Johnson with a fixed contact point only. */
Test(model_check, unloading_curve_only_after_yield_and_only_for_fixed_johnson)
{
    double x[2] = {0.0, 1.0};
    vi_model M0 = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    M0.contact[0].mode = VI_Mode_free;
    accepted_as(&M0, x, "virgin");
    for (int i = 0; i < 5; i++) {
        vi_model M = M0;
        double *u[5] = {&M.contact[0].unload.delta_c, &M.contact[0].unload.Rbar, &M.contact[0].unload.delta_r, &M.contact[0].unload.delta_f, &M.contact[0].unload.Kbar};
        *u[i] = 1e-5 * (i + 1);
        refused_with(&M, x, 1, "unloading curve (delta_c = %g, Rbar = %g) present although yielded = 0", M.contact[0].unload.delta_c,
                     M.contact[0].unload.Rbar);
    }
    double x0[2];
    vi_model ok = default_unloading_model(x0);
    vi_model M = ok;
    M.contact[0].law = VI_ContactModel_lepp;
    refused_with(&M, x0, 1, "yielded = 1 is impossible for contact_model lepp (moving 0)");
    M = ok;
    M.contact[0].law = VI_ContactModel_hertz;
    refused_with(&M, x0, 1, "yielded = 1 is impossible for contact_model hertz (moving 0)");
    M = ok;
    M.contact[0].moving = 1;
    refused_with(&M, x0, 1, "yielded = 1 is impossible for contact_model johnson (moving 1)");
}

/* A yielded memory: every value finite (each alone, the message lists all five), delta_c >= delta_Y
 * (to 1e-9: the bound passes, one ulp below does not), Rbar > 0, delta_f <= delta_c, and the curve the
 * one of delta_c to 1e-9 (each value 2e-9 off refused, 0.5e-9 off passes). */
Test(model_check, yielded_memory_rules)
{
    double x0[2];
    for (int variant = VI_UNLOAD_PAPER; variant <= VI_UNLOAD_CONTINUOUS; variant++) {
        vi_parameters p;
        vi_parameters_default(&p);
        p.unloading = variant;
        vi_model ok = unloading_model(&p, x0);
        const vi_unload_curve U = ok.contact[0].unload;
        for (int i = 0; i < 5; i++) {
            vi_model M = ok;
            double *u[5] = {&M.contact[0].unload.delta_c, &M.contact[0].unload.Rbar, &M.contact[0].unload.delta_r, &M.contact[0].unload.delta_f, &M.contact[0].unload.Kbar};
            *u[i] = i % 2 ? INFINITY : NAN;
            refused_with(&M, x0, 1, "unloading curve: a value (delta_c %g, Rbar %g, delta_r %g, delta_f %g, Kbar %g) is "
                         "not finite", M.contact[0].unload.delta_c, M.contact[0].unload.Rbar, M.contact[0].unload.delta_r, M.contact[0].unload.delta_f, M.contact[0].unload.Kbar);
        }
        /* delta_c at the bound delta_Y (1 - 1e-9), with its own curve */
        vi_model M = ok;
        double dc = ok.contact[0].johnson.delta_Y * (1.0 - 1e-9);
        M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, variant, dc);
        double xb[2] = {0.5 * (M.contact[0].unload.delta_f + dc), 1.0};
        accepted_as(&M, xb, "delta_c at its lower bound");
        M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, variant, nextafter(dc, 0.0));
        refused_with(&M, xb, 1, "delta_c = %g is below delta_Y = %g", M.contact[0].unload.delta_c, M.contact[0].johnson.delta_Y);
        /* Rbar */
        double rbar[] = {0.0, -U.Rbar};
        for (int i = 0; i < 2; i++) {
            M = ok;
            M.contact[0].unload.Rbar = rbar[i];
            refused_with(&M, x0, 1, "Rbar = %g is not positive", rbar[i]);
        }
        /* delta_f: above delta_c by one ulp (the order rule), at delta_c (the curve rule) */
        M = ok;
        M.contact[0].unload.delta_f = nextafter(U.delta_c, INFINITY);
        refused_with(&M, x0, 1, "delta_f = %g is above delta_c = %g", M.contact[0].unload.delta_f, U.delta_c);
        M.contact[0].unload.delta_f = U.delta_c;
        refused_with(&M, x0, 1, "delta_f = %g does not belong to delta_c (%g)", U.delta_c, U.delta_f);
        /* the curve of delta_c, value by value */
        M = ok;
        M.contact[0].unload.Rbar = U.Rbar * (1.0 + 2e-9);
        refused_with(&M, x0, 1, "Rbar = %g does not belong to delta_c (%g)", M.contact[0].unload.Rbar, U.Rbar);
        M.contact[0].unload.Rbar = U.Rbar * (1.0 - 0.5e-9);
        accepted_as(&M, x0, "Rbar 0.5e-9 off");
        M = ok;
        M.contact[0].unload.delta_r = U.delta_r * (1.0 - 2e-9);
        refused_with(&M, x0, 1, "delta_r = %g does not belong to delta_c (%g)", M.contact[0].unload.delta_r, U.delta_r);
        M.contact[0].unload.delta_r = U.delta_r * (1.0 + 0.5e-9);
        accepted_as(&M, x0, "delta_r 0.5e-9 off");
        M = ok;
        M.contact[0].unload.delta_f = U.delta_f - 2e-9 * U.delta_c;
        refused_with(&M, x0, 1, "delta_f = %g does not belong to delta_c (%g)", M.contact[0].unload.delta_f, U.delta_f);
        M.contact[0].unload.delta_f = U.delta_f + 0.5e-9 * U.delta_c;
        accepted_as(&M, x0, "delta_f 0.5e-9 delta_c off");
        /* delta_f exactly 1e-9 delta_c off passes and one ulp further does not: a delta_c near the model's
         * whose 1e-9 delta_c is a double of 20 significant bits, a whole number of ulps of delta_f */
        int e;
        double frac = frexp(1e-9 * U.delta_c, &e), tol = 0.0;
        for (int j = 0; j < 64 && tol == 0.0; j++) {
            double want = ldexp(round(ldexp(frac, 20)) + j, e - 20), c = want / 1e-9;
            for (int k = 0; k < 8 && 1e-9 * c != want; k++) c = nextafter(c, 1e-9 * c < want ? INFINITY : 0.0);
            if (1e-9 * c == want) dc = c, tol = want;
        }
        cr_assert(tol > 0.0, "no delta_c with a short 1e-9 delta_c near %g", U.delta_c);
        M = ok;
        M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, variant, dc);
        double df = M.contact[0].unload.delta_f, xf[2] = {0.5 * (df + dc), 1.0};
        M.contact[0].unload.delta_f = df + tol;
        cr_assert(M.contact[0].unload.delta_f - df == tol, "delta_f %.17g + %.17g is not exact", df, tol);
        accepted_as(&M, xf, "delta_f 1e-9 delta_c off");
        M.contact[0].unload.delta_f = nextafter(df + tol, INFINITY);
        refused_with(&M, xf, 1, "delta_f = %g does not belong to delta_c (%g)", M.contact[0].unload.delta_f, df);
        M = ok;
        M.contact[0].unload.Kbar = U.Kbar * (1.0 + 2e-9);
        refused_with(&M, x0, 1, "Kbar = %g does not belong to Rbar (%g)", M.contact[0].unload.Kbar, U.Kbar);
        M.contact[0].unload.Kbar = U.Kbar * (1.0 - 0.5e-9);
        accepted_as(&M, x0, "Kbar 0.5e-9 off");
    }
    /* a small body: Rbar far below 1 mm is a radius like any other */
    vi_parameters p;
    vi_parameters_default(&p);
    p.R1 = 1e-4;
    vi_model M = unloading_model(&p, x0);
    cr_assert(M.contact[0].unload.Rbar < 1e-3, "Rbar %g", M.contact[0].unload.Rbar);
}

/* The mode against the state: each length guard of each mode a clear distance (0.5 delta_Y or more)
 * beyond its surface, refused naming the mode, delta, the distance, the surface and the tolerance
 * 1e-6 max(delta_Y, |delta|, delta_c); between events (Model Exchange) the same states pass. */
Test(model_check, each_surface_of_each_mode)
{
    double x0[2];
    vi_model Y = default_unloading_model(x0); /* Johnson, yielded, delta_c = 3 delta_Y */
    const double dY = Y.contact[0].johnson.delta_Y, dc = Y.contact[0].unload.delta_c, df = Y.contact[0].unload.delta_f;
    cr_assert(df > 0.5 * dY, "delta_f %g", df);
    vi_model H = setup(VI_ContactModel_hertz, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    vi_model J = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    vi_model Jm = setup(VI_ContactModel_johnson, 1, VI_Unloading_paper, 0.0, 0.0, 0.0);
    vi_model L = setup(VI_ContactModel_lepp, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    L.contact[0].delta_p = 2.0 * dY; /* the laws share delta_Y (same E*, R*, Y) */
    cr_assert(H.contact[0].johnson.delta_Y == dY && L.contact[0].johnson.delta_Y == dY);
    struct { vi_model *M; int mode; double d, beyond; int surface; } c[] = {
        {&H, VI_Mode_free, 0.5 * dY, 0.5 * dY, 0},             /* free, in contact */
        {&L, VI_Mode_elastic, 1.5 * dY, 0.5 * dY, 0},          /* LEPP elastic, off the permanent set */
        {&J, VI_Mode_elastic, 2.5 * dY, 1.5 * dY, 1},          /* elastic beyond yield */
        {&L, VI_Mode_elastic, 3.5 * dY, 0.5 * dY, 1},          /* LEPP elastic beyond delta_p + delta_Y */
        {&Y, VI_Mode_plastic, 2.0 * dY, 1.0 * dY, 0},          /* plastic below delta_c */
        {&Jm, VI_Mode_plastic, 0.5 * dY, 0.5 * dY, 0},         /* moving: plastic below delta_Y */
        {&L, VI_Mode_plastic, 2.5 * dY, 0.5 * dY, 0},          /* LEPP plastic below delta_p + delta_Y */
        {&Y, VI_Mode_unload, df - 0.5 * dY, 0.5 * dY, 0},      /* unloading beyond separation */
        {&Y, VI_Mode_unload, dc + 0.5 * dY, 0.5 * dY, 1},      /* unloading beyond delta_c */
        {&Y, VI_Mode_stick, dc - 0.5 * dY, 0.5 * dY, 0},       /* stick off delta_c, below */
        {&Y, VI_Mode_stick, dc + 0.5 * dY, 0.5 * dY, 1},       /* stick off delta_c, above */
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        vi_model M = *c[i].M;
        M.contact[0].mode = c[i].mode;
        double x[2] = {c[i].d, 0.125};
        double tol = 1e-6 * fmax(fmax(dY, fabs(c[i].d)), fabs(M.contact[0].unload.delta_c));
        char expect[512];
        snprintf(expect, sizeof expect, "mode %d does not fit the state: delta = %.17g m lies %g m beyond its surface %d "
                 "(tolerance %g m)", c[i].mode, c[i].d, c[i].beyond, c[i].surface, tol);
        char msg[512] = "";
        cr_assert(vi_model_check(&M, x, msg, sizeof msg) == -1, "case %zu accepted", i);
        /* the distance is printed with %g: compare all but its last digits through the parts around it */
        char head[256];
        snprintf(head, sizeof head, "mode %d does not fit the state: delta = %.17g m lies ", c[i].mode, c[i].d);
        char tail[128];
        snprintf(tail, sizeof tail, " m beyond its surface %d (tolerance %g m)", c[i].surface, tol);
        cr_assert(strncmp(msg, head, strlen(head)) == 0 && strstr(msg, tail) != NULL, "case %zu: expected '%s', got '%s'",
                  i, expect, msg);
        double printed = atof(msg + strlen(head));
        cr_assert(fabs(printed - c[i].beyond) <= 1e-5 * c[i].beyond, "case %zu: distance %g vs %g", i, printed,
                  c[i].beyond);
        msg[0] = '\0';
        cr_assert(vi_model_check_between_events(&M, x, msg, sizeof msg) == 0, "case %zu between events: %s", i, msg);
    }
}

/* The tolerance of the length guards is inclusive: free Hertz at delta = 1e-6 delta_Y (exactly the
 * tolerance below the contact surface) passes, one ulp deeper does not. */
Test(model_check, guard_tolerance_bound_is_inclusive)
{
    vi_model M = setup(VI_ContactModel_hertz, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    M.contact[0].mode = VI_Mode_free;
    double tol = VI_CHECK_GUARD_TOL * M.contact[0].johnson.delta_Y, x[2] = {tol, -1.0};
    accepted_as(&M, x, "at the tolerance");
    x[0] = nextafter(tol, INFINITY);
    char msg[512] = "";
    cr_assert(vi_model_check(&M, x, msg, sizeof msg) == -1 && strstr(msg, "mode 0 does not fit"), "%s", msg);
}

/* The breakpoint is the first time at which the rolling position lies on the piece after the kink:
 * at the kink itself going forward (the piece to the right starts there), strictly beyond it going
 * backward. Trough with its kink at x = 0; x0 = -+0.5 m, V = +-1 m/s: the kink is reached at t = 0.5 s,
 * where x0 + V t is exactly 0. Forward: 0.5 s; backward: one ulp later (position -1e-16 m). */
Test(rolling, breakpoint_lies_on_the_piece_after_the_kink)
{
    double x[] = {-10.0, 0.0, 10.0}, h[] = {1e-3, 0.0, 1e-3};
    char msg[512];
    vi_profile *prof = vi_profile_create(x, h, 3, 0.475, 0, "trough", msg, sizeof msg);
    cr_assert(prof != NULL, "%s", msg);
    vi_model M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    for (int dir = -1; dir <= 1; dir += 2) {
        cr_assert(vi_model_set_rolling(&M, prof, dir, -0.5 * dir, msg, sizeof msg) == 0, "%s", msg);
        cr_assert(vi_profile_next_kink(prof, -0.5 * dir, dir) == 0.0);
        cr_assert(vi_model_rolling_position(&M, 0.5) == 0.0);
        double tk = vi_model_next_breakpoint(&M, 0.0), expect = dir > 0 ? 0.5 : nextafter(0.5, 1.0);
        cr_assert(tk == expect, "V = %d: breakpoint %.17g, expected %.17g", dir, tk, expect);
        cr_assert(dir > 0 ? vi_model_rolling_position(&M, tk) == 0.0 : vi_model_rolling_position(&M, tk) < 0.0);
    }
    vi_profile_free(prof);
}

/* Each ignored option alone gives its one warning (exact text), and the option where it is used gives
 * none: moving_contact (Johnson uses it), continuous unloading (Johnson with a fixed contact point
 * uses it), the printed yield formula (all but Hertz), v0 (a touching start), the rolling parameters
 * V, x0, profile_periodic (each alone; with a profile_file they are used). Two at once are joined. */
Test(model, each_ignored_option_warns_alone)
{
    const char *moving = "moving_contact = true is ignored: only the Johnson law has a moving contact point",
               *unloading = "unloading = continuous is ignored: only Johnson with a fixed contact point unloads on eq. 4",
               *printed = "yield_formula = printed is ignored by the laws without yield (it changes only the calculated F_Y, delta_Y)",
               *v0 = "v0 is ignored by a static start (init = static)",
               *rolling = "V, x0 and profile_periodic are ignored without a profile_file";
    struct { int law, moving, unloading, formula, init; double v0, V, x0; int periodic; const char *file, *expect; } c[] = {
        {VI_ContactModel_hertz, 1, 1, 1, 1, 0.0, 0.0, 0.0, 0, "", moving},
        {VI_ContactModel_lepp, 1, 1, 1, 1, 0.0, 0.0, 0.0, 0, "", moving},
        {VI_ContactModel_johnson, 1, 1, 1, 1, 0.0, 0.0, 0.0, 0, "", ""},
        {VI_ContactModel_johnson, 0, 2, 1, 1, 0.0, 0.0, 0.0, 0, "", ""},
        {VI_ContactModel_hertz, 0, 2, 1, 1, 0.0, 0.0, 0.0, 0, "", unloading},
        {VI_ContactModel_lepp, 0, 2, 1, 1, 0.0, 0.0, 0.0, 0, "", unloading},
        {VI_ContactModel_johnson, 1, 2, 1, 1, 0.0, 0.0, 0.0, 0, "", unloading},
        {VI_ContactModel_hertz, 0, 1, 2, 1, 0.0, 0.0, 0.0, 0, "", printed},
        {VI_ContactModel_lepp, 0, 1, 2, 1, 0.0, 0.0, 0.0, 0, "", ""},
        {VI_ContactModel_johnson, 0, 1, 1, 1, 1e-4, 0.0, 0.0, 0, "", v0},
        {VI_ContactModel_johnson, 0, 1, 1, 1, -2.0, 0.0, 0.0, 0, "", v0},
        {VI_ContactModel_johnson, 0, 1, 1, 2, 1e-4, 0.0, 0.0, 0, "", ""},
        {VI_ContactModel_johnson, 0, 1, 1, 1, 0.0, 1e-4, 0.0, 0, "", rolling},
        {VI_ContactModel_johnson, 0, 1, 1, 1, 0.0, 0.0, 1e-4, 0, "", rolling},
        {VI_ContactModel_johnson, 0, 1, 1, 1, 0.0, -5.0, -5.0, 0, "", rolling},
        {VI_ContactModel_johnson, 0, 1, 1, 1, 0.0, 0.0, 0.0, 1, "", rolling},
        {VI_ContactModel_johnson, 0, 1, 1, 1, 0.0, 1e-4, 1e-4, 1, "road.txt", ""},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        vi_parameters p;
        vi_parameters_default(&p);
        p.contact_model = c[i].law, p.moving_contact = c[i].moving, p.unloading = c[i].unloading;
        p.yield_formula = c[i].formula, p.init = c[i].init, p.v0 = c[i].v0, p.V = c[i].V, p.x0 = c[i].x0;
        p.profile_periodic = c[i].periodic;
        snprintf(p.profile_file, sizeof p.profile_file, "%s", c[i].file);
        char msg[512];
        memset(msg, 'x', sizeof msg);
        int count = warnings_from_table(&p, msg, sizeof msg);
        cr_assert(count == (c[i].expect[0] != '\0') && strcmp(msg, c[i].expect) == 0, "case %zu: %d '%s'", i, count, msg);
    }
    vi_parameters p;
    vi_parameters_default(&p);
    p.contact_model = VI_ContactModel_hertz, p.yield_formula = VI_YieldFormula_printed, p.V = 1.0;
    char msg[512], expect[512];
    snprintf(expect, sizeof expect, "%s; %s", printed, rolling);
    cr_assert(warnings_from_table(&p, msg, sizeof msg) == 2 && strcmp(msg, expect) == 0, "%s", msg);
}

/* profile_interpolation = cubic without a profile_file warns alone, with one it is used (no warning), and
 * linear (the default) never warns. */
Test(model, cubic_interpolation_without_a_profile_warns)
{
    const char *files[] = {"", "road.txt", ""};
    int interpolation[] = {VI_ProfileInterpolation_cubic, VI_ProfileInterpolation_cubic, VI_ProfileInterpolation_linear};
    const char *expect[] = {"profile_interpolation = cubic is ignored without a profile_file", "", ""};
    for (int i = 0; i < 3; i++) {
        vi_parameters p;
        vi_parameters_default(&p);
        p.profile_interpolation = interpolation[i];
        snprintf(p.profile_file, sizeof p.profile_file, "%s", files[i]);
        char msg[512];
        memset(msg, 'x', sizeof msg);
        int count = warnings_from_table(&p, msg, sizeof msg);
        cr_assert(count == (expect[i][0] != '\0') && strcmp(msg, expect[i]) == 0, "case %d: %d '%s'", i, count, msg);
    }
}

/* The setup refuses parameters whose load or stiffness leave the doubles, naming E*, R*, F_Y, delta_Y:
 * an infinite load, a yield indentation beyond the doubles (k_lin = 0). First only the load is infinite (P + m g = 1e308 + 1e300 kg 1e10 m/s^2), every stiffness is fine. A
 * soft (E1 = E2 = 1e-6 Pa), weak (Y = 1e-10 Pa) material has stiffnesses and a yield force far below
 * 1 and is accepted like any other. */
Test(model, setup_refuses_values_beyond_the_doubles_and_accepts_tiny_stiffnesses)
{
    vi_parameters p;
    vi_parameters_default(&p);
    p.P = 1e308, p.m = 1e300, p.g = 1e10;
    vi_model M = {0};
    char msg[512], expect[512];
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == -1);
    cr_assert(isinf(M.body.W0) && isfinite(M.contact[0].K) && M.contact[0].K > 0.0 && isfinite(M.contact[0].k_lin) && M.contact[0].johnson.F_Y > 0.0);
    snprintf(expect, sizeof expect, "the parameters give no finite positive contact stiffness or yield force (E* = %g Pa, "
             "R* = %g m, F_Y = %g N, delta_Y = %g m)", M.contact[0].johnson.E_star, M.contact[0].johnson.R_star, M.contact[0].johnson.F_Y, M.contact[0].johnson.delta_Y);
    cr_assert(strcmp(msg, expect) == 0, "expected '%s', got '%s'", expect, msg);
    cr_assert(p.R2 == 0.0 && fabs(M.contact[0].johnson.R_star - p.R1) <= 1e-15 * p.R1, "R* %g", M.contact[0].johnson.R_star); /* against a plane: R* = R1 */
    /* a yield force so far above the stiffness that delta_Y = (F_Y/K)^(2/3) overflows: k_lin = F_Y/delta_Y
     * is 0 (E* = 1e-120 Pa, theta_Y Y = 1e-15 Pa: F_Y about 1e194 N, K about 1e-120) */
    vi_parameters_default(&p);
    p.E1 = p.E2 = 2e-120, p.nu1 = p.nu2 = 0.0, p.theta_Y = 1e-15, p.Y = 1.0;
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == -1, "accepted: k_lin %g", M.contact[0].k_lin);
    cr_assert(isfinite(M.contact[0].johnson.F_Y) && M.contact[0].johnson.F_Y > 0.0 && M.contact[0].K > 0.0 && isinf(M.contact[0].johnson.delta_Y) && M.contact[0].k_lin == 0.0, "F_Y %g K %g", M.contact[0].johnson.F_Y,
              M.contact[0].K);
    snprintf(expect, sizeof expect, "the parameters give no finite positive contact stiffness or yield force (E* = 1e-120 Pa, "
             "R* = %g m, F_Y = %g N, delta_Y = inf m)", M.contact[0].johnson.R_star, M.contact[0].johnson.F_Y);
    cr_assert(strcmp(msg, expect) == 0, "expected '%s', got '%s'", expect, msg);
    vi_parameters_default(&p);
    p.E1 = p.E2 = 1e-6, p.Y = 1e-10;
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    cr_assert(M.contact[0].K < 1e-3 && M.contact[0].johnson.F_Y < 1e-3 && M.contact[0].k_lin < 1e-3, "K %g F_Y %g k_lin %g", M.contact[0].K, M.contact[0].johnson.F_Y, M.contact[0].k_lin);
}

/* The height of the attached profile at x = 5 m (trough of slope s0: about 5 s0). */
static double profile_height_at_5(const test_run *s)
{
    double y[4];
    cr_assert(s->d.run.model.profile == s->r.profile && s->r.profile != NULL);
    vi_profile_eval(s->r.profile, 5.0, y);
    return y[0];
}

/* The profile is read once and kept while file, R1 and periodicity stay those it was built for (a
 * restore of such a state reads no file, even if the file changed meanwhile); a new R1 or periodicity
 * reads the file again. Without a profile_file, or with one that cannot be read, there is none, and
 * the simulation owns none (nor the name of one). */
Test(rolling, profile_kept_for_the_same_file_radius_and_periodicity)
{
    test_run s;
    rolling_sim(&s, 1e-4, 1.0, -0.01, 1e-8);
    cr_assert(fabs(profile_height_at_5(&s) - 5e-4) <= 1e-6, "%g", profile_height_at_5(&s));
    v_trough_file(2e-4); /* the file changes on disk */
    cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
    cr_assert(fabs(profile_height_at_5(&s) - 5e-4) <= 1e-6, "reloaded: %g", profile_height_at_5(&s));
    s.d.par.profile_periodic = 1; /* another periodicity: read again */
    cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
    cr_assert(fabs(profile_height_at_5(&s) - 1e-3) <= 1e-6 && vi_profile_periodic(s.r.profile), "%g", profile_height_at_5(&s));
    v_trough_file(3e-4);
    s.d.par.profile_periodic = 2; /* periodic as well (any nonzero value): the same profile */
    cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
    cr_assert(fabs(profile_height_at_5(&s) - 1e-3) <= 1e-6, "reloaded: %g", profile_height_at_5(&s));
    s.d.par.R1 = 0.4; /* another radius: read again */
    cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
    cr_assert(fabs(profile_height_at_5(&s) - 1.5e-3) <= 1e-6, "%g", profile_height_at_5(&s));
    char file[sizeof s.d.par.profile_file];
    memcpy(file, s.d.par.profile_file, sizeof file);
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "%.64s.missing", file); /* no such file: no profile */
    cr_assert(vi_sim_restore(&s.s) == -1 && strstr(s.r.msg, ".missing"), "%s", s.r.msg);
    cr_assert(s.r.profile == NULL && s.r.profile_key[0] == '\0');
    memcpy(s.d.par.profile_file, file, sizeof file);
    cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
    cr_assert(fabs(profile_height_at_5(&s) - 1.5e-3) <= 1e-6, "%g", profile_height_at_5(&s));
    s.d.par.profile_file[0] = '\0'; /* none: the model rolls over nothing, the profile is released */
    cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
    cr_assert(s.d.run.model.profile == NULL && s.r.profile == NULL && s.r.profile_key[0] == '\0');
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "%s", v_trough_file(1e-4)); /* and back */
    cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
    cr_assert(fabs(profile_height_at_5(&s) - 5e-4) <= 1e-6, "%g", profile_height_at_5(&s));
    test_run_free(&s);
    cr_assert(s.r.profile == NULL);
    remove(v_trough_file(1e-4));
}

/* The validity messages, value by value, and the bounds themselves: delta = 0.01 R* exactly, |a| = R*
 * exactly and heights spanning exactly R1 are valid. The indentation is delta in contact, or the
 * largest one delta_c when that is larger (unloading after yield), and 0 in free flight, whatever
 * the radius; a velocity is no indentation. */
Test(model, validity_messages_and_bounds)
{
    vi_parameters p;
    vi_parameters_default(&p);
    p.contact_model = VI_ContactModel_hertz;
    p.R1 = 0.05; /* R* = 0.05 m: the limit 5e-4 m lies below 1e-3 m */
    vi_model M = {0};
    char msg[512], expect[512];
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    const double R = M.contact[0].johnson.R_star, limit = 0.01 * R;
    M.contact[0].mode = VI_Mode_free;
    double x[2] = {2.0 * limit, 1.0};
    cr_assert(vi_model_validity(&M, 1e-4, 0.0, x, 0, msg, sizeof msg) == 0, "free: %s", msg);
    cr_assert(!vi_model_indentation_invalid(&M, x));
    M.contact[0].mode = VI_Mode_elastic;
    x[0] = 1e-5; /* in contact, moving at 1 m/s */
    cr_assert(vi_model_validity(&M, 1e-4, 0.0, x, 0, msg, sizeof msg) == 0, "elastic: %s", msg);
    cr_assert(!vi_model_indentation_invalid(&M, x));
    x[0] = 0.1 * 0.1 * R;
    cr_assert(vi_model_validity(&M, 1e-4, 0.0, x, 0, msg, sizeof msg) == 0, "at the limit: %s", msg);
    cr_assert(!vi_model_indentation_invalid(&M, x));
    x[0] = 2.0 * limit;
    cr_assert(vi_model_indentation_invalid(&M, x));
    cr_assert(vi_model_validity(&M, 1e-4, 0.25, x, 0, msg, sizeof msg) == VI_INVALID_INDENTATION);
    snprintf(expect, sizeof expect, "t = 0.25 s: the indentation %g m exceeds 0.01 R* = %g m (contact radius sqrt(R* delta) "
             "= %g m > 0.1 R*): the contact laws (paper eqs. 2-4) assume a contact radius small against R*, so the "
             "results leave the model's range of validity", 2.0 * limit, limit, sqrt(2.0) * 0.1 * R);
    cr_assert(strcmp(msg, expect) == 0, "expected '%s', got '%s'", expect, msg);
    /* after yield: delta_c counts while unloading below it */
    vi_model J = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    const double lj = 0.01 * J.contact[0].johnson.R_star;
    J.contact[0].yielded = 1, J.contact[0].mode = VI_Mode_unload;
    J.contact[0].unload = vi_johnson_unload_curve(&J.contact[0].johnson, VI_UNLOAD_PAPER, 1.5 * lj);
    double xj[2] = {0.5 * lj, 0.0};
    cr_assert(vi_model_indentation_invalid(&J, xj));
    cr_assert(vi_model_validity(&J, 0.475, 1.0, xj, 0, msg, sizeof msg) == VI_INVALID_INDENTATION);
    snprintf(expect, sizeof expect, "t = 1 s: the indentation %g m exceeds", 1.5 * lj);
    cr_assert(strncmp(msg, expect, strlen(expect)) == 0, "expected '%s...', got '%s'", expect, msg);
    /* the amplitude: |a| = R* is valid, either sign */
    x[0] = 0.0;
    M.a = R;
    cr_assert(vi_model_validity(&M, 1e-4, 0.0, x, 0, msg, sizeof msg) == 0, "a = R*: %s", msg);
    M.a = -2.0 * R;
    cr_assert(vi_model_validity(&M, 1e-4, 3.0, x, 0, msg, sizeof msg) == VI_INVALID_AMPLITUDE);
    snprintf(expect, sizeof expect, "t = 3 s: the excitation amplitude a = %g m exceeds R* = %g m: the contact laws (paper "
             "eqs. 2-4) describe a local contact, with every displacement small against R*, so the results leave the "
             "model's range of validity", -2.0 * R, R);
    cr_assert(strcmp(msg, expect) == 0, "expected '%s', got '%s'", expect, msg);
    /* the heights: spanning exactly R1 is valid */
    M.a = 0.0;
    const double xs[] = {0.0, 50.0, 100.0}, hs[] = {0.0, 0.475, 0.0};
    vi_profile *prof = vi_profile_create(xs, hs, 3, 0.475, 0, "hill", msg, sizeof msg);
    cr_assert(prof != NULL, "%s", msg);
    cr_assert(vi_profile_height_span(prof) == 0.475);
    cr_assert(vi_model_set_rolling(&M, prof, 1.0, 10.0, msg, sizeof msg) == 0, "%s", msg);
    cr_assert(vi_model_validity(&M, 0.475, 0.0, x, 0, msg, sizeof msg) == 0, "span = R1: %s", msg);
    cr_assert(vi_model_validity(&M, 0.25, 4.0, x, 0, msg, sizeof msg) == VI_INVALID_PROFILE);
    snprintf(expect, sizeof expect, "t = 4 s: the heights of profile_file span 0.475 m, more than the rolling radius R1 = "
             "0.25 m: rolling over a profile (paper Fig. 1b) assumes a roughness small against the wheel, so the results "
             "leave the model's range of validity");
    cr_assert(strcmp(msg, expect) == 0, "expected '%s', got '%s'", expect, msg);
    vi_profile_free(prof);
}

/* The force limits of the paper (section 2): F_Y for Hertz and damped Hertz, 650 F_Y for Johnson (fixed or
 * moving contact point), none for the others; at the limit valid, one ulp above it named with its ratio;
 * the longest message (17 digits of t, the widest numbers) fits the simulation's 400-byte buffer. */
Test(model, force_limits_of_the_paper)
{
    const int laws[] = {VI_ContactModel_hertz, VI_ContactModel_hertz_damped, VI_ContactModel_johnson,
                        VI_ContactModel_johnson, VI_ContactModel_lepp, VI_ContactModel_linear, VI_ContactModel_thornton};
    const double ratio[] = {1.0, 1.0, 650.0, 650.0, INFINITY, INFINITY, INFINITY};
    for (int i = 0; i < 7; i++) {
        vi_model M = setup(laws[i], i == 3, VI_Unloading_paper, 40000.0, 9.81, 0.0);
        double F_Y = M.contact[0].johnson.F_Y, limit = vi_model_force_limit(&M);
        char msg[512], expect[128];
        cr_assert(limit == ratio[i] * F_Y, "law %d: %g", laws[i], limit);
        cr_assert(vi_model_force_validity(&M, limit, 1.0, msg, sizeof msg) == 0, "law %d at the limit: %s", laws[i], msg);
        if (!isfinite(limit)) {
            cr_assert(vi_model_force_validity(&M, 1e308, 1.0, msg, sizeof msg) == 0, "law %d: %s", laws[i], msg);
            continue;
        }
        double F = nextafter(limit, INFINITY);
        cr_assert(vi_model_force_validity(&M, F, 0.25, msg, sizeof msg) == VI_INVALID_FORCE, "law %d", laws[i]);
        snprintf(expect, sizeof expect, "t = 0.25 s: the contact force reached %g N = %.4g F_Y (F_Y = %g N)", F, F / F_Y, F_Y);
        cr_assert(strncmp(msg, expect, strlen(expect)) == 0, "expected '%s...', got '%s'", expect, msg);
        cr_assert(strstr(msg, ratio[i] > 1.0 ? "beyond F_p = 650 F_Y: Johnson's loading curve (paper eq. 3)"
                                             : "Hertz's law (paper eq. 2) assumes purely elastic strains"), "%s", msg);
        int n = vi_model_force_validity(&M, -1.2345678901234567e-300, 0.0, msg, sizeof msg);
        cr_assert(n == 0, "a negative force is no excess");
        M.contact[0].johnson.F_Y = -1.2345678901234567e-300; /* the widest %g and %.4g numbers */
        cr_assert(vi_model_force_validity(&M, 1.2345678901234567e+300, 0.0010207383440245387, msg, sizeof msg) ==
                  VI_INVALID_FORCE);
        cr_assert(strlen(msg) < 400, "%zu bytes: %s", strlen(msg), msg);
    }
}

/* Rolling from a start time t0 = 2 s (position x0 at t0): the kink at x = 0 of the trough is reached
 * at t0 + (0 - x0)/V, the end of the table at t0 + (x_end - x0)/V (closed forms: x0 = -+1 m, V = +-0.5
 * m/s: 4 s and 24 s). Standing still (V = 0) there is no breakpoint; slow rolling (1 mm/s) has one. */
Test(rolling, breakpoints_and_end_from_a_start_time_not_zero)
{
    double x[] = {-10.0, 0.0, 10.0}, h[] = {1e-3, 0.0, 1e-3};
    char msg[512];
    vi_profile *prof = vi_profile_create(x, h, 3, 0.475, 0, "trough", msg, sizeof msg);
    cr_assert(prof != NULL, "%s", msg);
    vi_parameters p;
    vi_parameters_default(&p);
    vi_model M = {0};
    cr_assert(setup_from_table(&M, &p, 2.0, msg, sizeof msg) == 0, "%s", msg);
    for (int dir = -1; dir <= 1; dir += 2) {
        cr_assert(vi_model_set_rolling(&M, prof, 0.5 * dir, -1.0 * dir, msg, sizeof msg) == 0, "%s", msg);
        double tk = vi_model_next_breakpoint(&M, 2.0), expect = dir > 0 ? 4.0 : nextafter(4.0, 5.0);
        cr_assert(tk == expect, "V = %g: breakpoint %.17g", 0.5 * dir, tk);
        double end = vi_model_rolling_limit(&M, msg, sizeof msg);
        cr_assert(fabs(end - 24.0) <= 1e-14 * 24.0, "V = %g: end %.17g", 0.5 * dir, end);
        cr_assert(strstr(msg, dir > 0 ? "(x_last = 10 m)" : "(x_first = -10 m)"), "%s", msg);
    }
    cr_assert(vi_model_set_rolling(&M, prof, 0.0, -1.0, msg, sizeof msg) == 0, "%s", msg);
    cr_assert(vi_model_next_breakpoint(&M, 2.0) == INFINITY);
    cr_assert(vi_model_set_rolling(&M, prof, 1e-3, -1.0, msg, sizeof msg) == 0, "%s", msg);
    double tk = vi_model_next_breakpoint(&M, 2.0);
    cr_assert(fabs(tk - 1002.0) <= 1e-9, "%.17g", tk);
    /* the start position: the ends of the table are on it, one ulp beyond is not (unless periodic) */
    cr_assert(vi_model_set_rolling(&M, prof, 1.0, -10.0, msg, sizeof msg) == 0, "%s", msg);
    cr_assert(vi_model_set_rolling(&M, prof, 1.0, 10.0, msg, sizeof msg) == 0, "%s", msg);
    double beyond[] = {nextafter(-10.0, -11.0), nextafter(10.0, 11.0)};
    for (int i = 0; i < 2; i++) {
        M.x0 = 0.25;
        cr_assert(vi_model_set_rolling(&M, prof, 1.0, beyond[i], msg, sizeof msg) == -1);
        char expect[256];
        snprintf(expect, sizeof expect, "x0 = %g m lies outside the profile [-10, 10] m (set profile_periodic to repeat it)",
                 beyond[i]);
        cr_assert(strcmp(msg, expect) == 0 && M.x0 == 0.25, "expected '%s', got '%s'", expect, msg);
    }
    vi_profile_free(prof);
    prof = vi_profile_create(x, h, 3, 0.475, 1, "trough", msg, sizeof msg);
    cr_assert(prof != NULL, "%s", msg);
    cr_assert(vi_model_set_rolling(&M, prof, 1.0, 25.0, msg, sizeof msg) == 0 && M.x0 == 25.0 && M.V == 1.0, "%s", msg);
    cr_assert(vi_model_set_rolling(&M, NULL, -2.0, 1e6, msg, sizeof msg) == 0 && M.profile == NULL && M.x0 == 1e6 &&
              M.V == -2.0);
    vi_profile_free(prof);
}

static char kink_line[256];
static void capture_events(void *env, int category, const char *fmt, ...)
{
    (void)env;
    if (category != VI_LOG_EVENTS) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(kink_line, sizeof kink_line, fmt, ap);
    va_end(ap);
}

/* A mass without load riding the trough's slope at the platform's own velocity (free, delta = 0) is
 * met by the platform at the kink (t = 10 ms: its velocity turns by 2 s0 V upward): the kink changes
 * the mode to elastic, the loop stops there when asked, says so in the log, and arms the new mode's
 * guards afresh (delta lies within rounding of 0: no band, or the band of its rounding), whatever band
 * the free mode's guard had. */
Test(rolling, a_kink_that_changes_the_mode)
{
    const double s0 = 1e-4, V = 1.0;
    test_run s;
    test_run_init(&s, capture_events, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 0.0, s.d.par.g = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = -s0 * V;
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "%s", v_trough_file(s0));
    s.d.par.V = V, s.d.par.x0 = -0.01;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    double dyC;
    vi_model_platform(&s.d.run.model, 0.0, &dyC, NULL);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_free && dyC == -s0 * V, "mode %d, yC' = %.17g", s.d.run.model.contact[0].mode, dyC);
    s.d.run.events.band[0] = 1.0;
    kink_line[0] = '\0';
    cr_assert(vi_sim_advance_until(&s.s, 0.02, 1) == VI_SIM_EVENT, "%s", s.r.msg);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_elastic && fabs(s.d.run.t - 0.01) <= 1e-15 && fabs(s.d.run.x[0]) <= 1e-12,
              "mode %d t %.17g delta %g", s.d.run.model.contact[0].mode, s.d.run.t, s.d.run.x[0]);
    double t;
    int from, to;
    cr_assert(sscanf(kink_line, "event t=%lg kind=kink mode=%d->%d", &t, &from, &to) == 3 && t == s.d.run.t &&
              from == VI_Mode_free && to == VI_Mode_elastic, "%s", kink_line);
    cr_assert(s.d.run.events.band[0] < 1e-300 && s.d.run.events.band[1] == 0.0, "bands %g %g", s.d.run.events.band[0],
              s.d.run.events.band[1]);
    test_run_free(&s);
    remove(v_trough_file(s0));
}

/* The outputs of each law in its modes, group by group, against closed forms: the state as it is,
 * the platform yC = yC_in + a (cos(w t) - 1) and y = yC - delta, the force of the mode, the memory
 * (Johnson with a fixed contact point: the unloading curve of delta_c, or of delta while plastic, and
 * W_plastic = the virgin curve's work to delta_c minus the unloading curve's energy; LEPP: delta_p, or
 * delta - delta_Y while plastic, and W_plastic = F_Y delta_p; none otherwise: Rbar = R*), and the
 * calculated parameters. */
Test(model, outputs_of_each_law_and_mode)
{
    vi_model J = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 1e-4);
    const double dY = J.contact[0].johnson.delta_Y, t = 1.25e-4, w = J.omega;
    J.yC_in = (vi_ramp){2e-5, 0.0, 0.0};
    J.f_contact = 123.0;
    J.contact[0].n_impacts = 7;
    const double yC = 2e-5 + 1e-4 * (cos(w * t) - 1.0);
    /* Johnson, yielded, unloading at delta between delta_f and delta_c */
    vi_model M = J;
    M.contact[0].yielded = 1, M.contact[0].mode = VI_Mode_unload;
    M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, 3.0 * dY);
    double x[2] = {0.5 * (M.contact[0].unload.delta_f + M.contact[0].unload.delta_c), -0.5};
    vi_model_values out;
    memset(&out, 0, sizeof out);
    vi_model_outputs(&M, t, x, VI_OUT_STATE | VI_OUT_PLATFORM | VI_OUT_FORCE | VI_OUT_MEMORY | VI_OUT_CALCULATED, &out);
    cr_assert(out.delta == x[0] && out.v == -0.5 && out.contact == 1 && out.mode == VI_Mode_unload && out.n_impacts == 7);
    cr_assert(fabs(out.yC - yC) <= 1e-18 && fabs(out.y - (yC - x[0])) <= 1e-18, "yC %.17g vs %.17g", out.yC, yC);
    double Fu = M.contact[0].unload.Kbar * pow(x[0] - M.contact[0].unload.delta_f, 1.5);
    cr_assert(fabs(out.F - Fu) <= 1e-12 * Fu, "F %g vs %g", out.F, Fu);
    double W = vi_johnson_load_work(&M.contact[0].johnson, 3.0 * dY) - vi_unload_energy(&M.contact[0].unload, 3.0 * dY);
    cr_assert(out.delta_c == 3.0 * dY && out.delta_f == M.contact[0].unload.delta_f && out.Rbar == M.contact[0].unload.Rbar && out.delta_p == 0.0 &&
              fabs(out.W_plastic - W) <= 1e-12 * W && W > 0.0, "memory %g %g %g %g", out.delta_c, out.delta_f, out.Rbar,
              out.W_plastic);
    cr_assert(out.E_star == M.contact[0].johnson.E_star && out.R_star == M.contact[0].johnson.R_star && out.F_Y == M.contact[0].johnson.F_Y && out.delta_Y == dY &&
              out.k_lin == M.contact[0].k_lin && out.f_contact == 123.0);
    /* plastic at 4 delta_Y: the memory is that of delta itself */
    M.contact[0].mode = VI_Mode_plastic;
    x[0] = 4.0 * dY;
    vi_model_outputs(&M, t, x, VI_OUT_FORCE | VI_OUT_MEMORY, &out);
    vi_unload_curve U4 = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, 4.0 * dY);
    cr_assert(out.delta_c == 4.0 * dY && out.delta_f == U4.delta_f && out.Rbar == U4.Rbar, "%g %g", out.delta_c, out.Rbar);
    cr_assert(fabs(out.F - vi_johnson_load(&M.contact[0].johnson, 4.0 * dY)) <= 1e-12 * out.F);
    /* stick: the holding force W + m yC'' (no load here: m yC'') */
    M.contact[0].mode = VI_Mode_stick;
    x[0] = 3.0 * dY;
    vi_model_outputs(&M, t, x, VI_OUT_FORCE, &out);
    double hold = -M.body.m * 1e-4 * w * w * cos(w * t);
    cr_assert(fabs(out.F - hold) <= 1e-12 * fabs(hold), "F %g vs %g", out.F, hold);
    /* Johnson not yielded, and moving: no memory, Rbar = R*; free: no contact, no force */
    vi_model V = J;
    V.contact[0].mode = VI_Mode_free;
    double xf[2] = {-1e-3, 2.0};
    out.delta_c = out.delta_f = out.delta_p = out.W_plastic = out.Rbar = -1.0;
    vi_model_outputs(&V, t, xf, VI_OUT_STATE | VI_OUT_FORCE | VI_OUT_MEMORY, &out);
    cr_assert(out.contact == 0 && out.mode == 0 && out.F == 0.0 && out.delta_c == 0.0 && out.delta_f == 0.0 &&
              out.delta_p == 0.0 && out.W_plastic == 0.0 && out.Rbar == J.contact[0].johnson.R_star);
    vi_model Mv = setup(VI_ContactModel_johnson, 1, VI_Unloading_paper, 0.0, 0.0, 0.0);
    Mv.contact[0].mode = VI_Mode_plastic;
    double xm[2] = {2.0 * dY, 0.0};
    vi_model_outputs(&Mv, 0.0, xm, VI_OUT_MEMORY, &out);
    cr_assert(out.delta_c == 0.0 && out.W_plastic == 0.0 && out.Rbar == Mv.contact[0].johnson.R_star);
    /* LEPP: elastic from the permanent set, plastic at F_Y with delta_p = delta - delta_Y */
    vi_model L = setup(VI_ContactModel_lepp, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    L.contact[0].delta_p = 0.5 * dY, L.contact[0].mode = VI_Mode_elastic;
    double xl[2] = {1.25 * dY, 0.0};
    vi_model_outputs(&L, 0.0, xl, VI_OUT_FORCE | VI_OUT_MEMORY, &out);
    cr_assert(fabs(out.F - L.contact[0].k_lin * 0.75 * dY) <= 1e-12 * out.F && out.delta_p == 0.5 * dY &&
              fabs(out.W_plastic - L.contact[0].johnson.F_Y * 0.5 * dY) <= 1e-12 * out.W_plastic && out.delta_c == 0.0 &&
              out.Rbar == L.contact[0].johnson.R_star, "F %g W %g", out.F, out.W_plastic);
    L.contact[0].mode = VI_Mode_plastic;
    xl[0] = 2.5 * dY;
    vi_model_outputs(&L, 0.0, xl, VI_OUT_FORCE | VI_OUT_MEMORY, &out);
    cr_assert(out.F == L.contact[0].johnson.F_Y && fabs(out.delta_p - 1.5 * dY) <= 1e-15 * dY &&
              fabs(out.W_plastic - L.contact[0].johnson.F_Y * 1.5 * dY) <= 1e-12 * out.W_plastic, "F %g delta_p %g", out.F, out.delta_p);
    /* Hertz: K delta^1.5 */
    vi_model H = setup(VI_ContactModel_hertz, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    H.contact[0].mode = VI_Mode_elastic;
    double xh[2] = {3.0 * dY, 0.0};
    vi_model_outputs(&H, 0.0, xh, VI_OUT_FORCE | VI_OUT_MEMORY, &out);
    cr_assert(fabs(out.F - H.contact[0].K * pow(3.0 * dY, 1.5)) <= 1e-12 * out.F && out.W_plastic == 0.0 && out.delta_p == 0.0);
}

/* The initial state starts from nothing, whatever the model held before (a re-initialization): no
 * memory, no permanent set, no impacts, the mode chosen afresh. f_contact = sqrt(k/m)/(2 pi) with k the
 * stiffness of small oscillations at the static load W (0 without a load pressing). */
Test(model, initial_state_starts_from_nothing)
{
    int laws[] = {VI_ContactModel_hertz, VI_ContactModel_johnson, VI_ContactModel_lepp};
    for (int i = 0; i < 3; i++) {
        for (int init = VI_Init_static; init <= VI_Init_touching; init++) {
            vi_model M = setup(laws[i], 0, VI_Unloading_paper, 40000.0, 9.81, 0.0);
            M.contact[0].mode = VI_Mode_stick, M.contact[0].yielded = 1, M.contact[0].delta_p = 1e-6, M.contact[0].n_impacts = 5;
            M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, 3.0 * M.contact[0].johnson.delta_Y);
            double x[2] = {1.0, 1.0};
            vi_model_initial_state(&M, init, init == VI_Init_static ? 0.0 : 2.0, 0.0, x);
            double W = M.body.W0, d = init == VI_Init_static ? (laws[i] == VI_ContactModel_lepp ? W / M.contact[0].k_lin
                                                                                          : pow(W / M.contact[0].K, 2.0 / 3.0))
                                                        : 0.0;
            if (laws[i] == VI_ContactModel_johnson && init == VI_Init_static)
                d = vi_johnson_load_indentation(&M.contact[0].johnson, W); /* below yield here: the Hertz branch */
            cr_assert(M.contact[0].yielded == 0 && M.contact[0].delta_p == 0.0 && M.contact[0].n_impacts == 0 && M.contact[0].unload.delta_c == 0.0 && M.contact[0].unload.Rbar == 0.0 &&
                      M.contact[0].unload.delta_r == 0.0 && M.contact[0].unload.delta_f == 0.0 && M.contact[0].unload.Kbar == 0.0, "law %d init %d", laws[i], init);
            cr_assert(fabs(x[0] - d) <= 1e-12 * d, "law %d init %d: delta %.17g vs %.17g", laws[i], init, x[0], d);
            cr_assert(init == VI_Init_static ? x[1] == 0.0 && M.contact[0].mode == VI_Mode_elastic : x[1] == 2.0 && M.contact[0].mode == VI_Mode_free,
                      "law %d init %d: v %g mode %d", laws[i], init, x[1], M.contact[0].mode);
            double k = laws[i] == VI_ContactModel_lepp ? M.contact[0].k_lin : 1.5 * M.contact[0].K * sqrt(pow(W / M.contact[0].K, 2.0 / 3.0));
            double f = sqrt(k / M.body.m) / (2.0 * VI_PI);
            cr_assert(fabs(M.f_contact - f) <= 1e-9 * f, "law %d: f_contact %.17g vs %.17g", laws[i], M.f_contact, f);
        }
        /* no load pressing (W = 0, and W < 0: pulled up): no static indentation, no resonance */
        double loads[][2] = {{0.0, 0.0}, {-100.0, 0.0}};
        for (int k = 0; k < 2; k++) {
            vi_model M = setup(laws[i], 0, VI_Unloading_paper, loads[k][0], loads[k][1], 0.0);
            double x[2];
            vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
            cr_assert(x[0] == 0.0 && M.f_contact == 0.0 && M.contact[0].mode == VI_Mode_free, "law %d W %g: delta %g f %g mode %d", laws[i],
                      M.body.W0, x[0], M.f_contact, M.contact[0].mode);
        }
        /* a tiny load presses all the same */
        vi_model M = setup(laws[i], 0, VI_Unloading_paper, 1e-4, 0.0, 0.0);
        double x[2];
        vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
        cr_assert(x[0] > 0.0 && M.f_contact > 0.0, "law %d: delta %g f %g", laws[i], x[0], M.f_contact);
    }
    /* beyond yield (W = 1e7 N > F_Y): Johnson with a fixed contact point starts yielded; LEPP flows
     * from the start (delta_Y, no memory); Johnson moving has none either */
    vi_model J = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 1e7, 0.0, 0.0);
    vi_model Jm = setup(VI_ContactModel_johnson, 1, VI_Unloading_paper, 1e7, 0.0, 0.0);
    vi_model L = setup(VI_ContactModel_lepp, 0, VI_Unloading_paper, 1e7, 0.0, 0.0);
    double x[2];
    vi_model_initial_state(&J, VI_Init_static, 0.0, 0.0, x);
    cr_assert(J.contact[0].yielded == 1 && J.contact[0].unload.delta_c == x[0] && x[0] > J.contact[0].johnson.delta_Y);
    vi_model_initial_state(&Jm, VI_Init_static, 0.0, 0.0, x);
    cr_assert(Jm.contact[0].yielded == 0 && Jm.contact[0].unload.delta_c == 0.0 && x[0] > Jm.contact[0].johnson.delta_Y);
    vi_model_initial_state(&L, VI_Init_static, 0.0, 0.0, x);
    cr_assert(L.contact[0].yielded == 0 && L.contact[0].unload.delta_c == 0.0 && x[0] == L.contact[0].johnson.delta_Y && L.contact[0].delta_p == 0.0, "%g", x[0]);
    /* small oscillations there: on the unloading curve of the static indentation (fixed contact point),
     * on the virgin curve (moving) */
    double d = vi_johnson_load_indentation(&J.contact[0].johnson, 1e7);
    vi_unload_curve U = vi_johnson_unload_curve(&J.contact[0].johnson, VI_UNLOAD_PAPER, d);
    double k = 1.5 * U.Kbar * sqrt(d - U.delta_f), f = sqrt(k / J.body.m) / (2.0 * VI_PI);
    cr_assert(fabs(J.f_contact - f) <= 1e-9 * f, "fixed: f_contact %.17g vs %.17g", J.f_contact, f);
    k = vi_johnson_load_stiffness(&Jm.contact[0].johnson, d), f = sqrt(k / Jm.body.m) / (2.0 * VI_PI);
    cr_assert(fabs(Jm.f_contact - f) <= 1e-9 * f, "moving: f_contact %.17g vs %.17g", Jm.f_contact, f);
}

/* Without load and speed the scales come from what the excitation moves: a w plus |V| times the
 * profile's largest slope (a flat stretch between slopes 1e-4 at rest: 0 + 2 m/s 1e-4 = 2e-4 m/s,
 * either direction of rolling; with a = 1e-6 m at 560 Hz as well, their sum); the length is the Hertz
 * impact indentation at that speed. */
Test(rolling, scales_from_the_rolling_speed)
{
    double x[] = {-10.0, 0.0, 1.0, 11.0}, h[] = {1e-3, 0.0, 0.0, 1e-3};
    char msg[512];
    vi_profile *prof = vi_profile_create(x, h, 4, 0.475, 0, "dip", msg, sizeof msg);
    cr_assert(prof != NULL, "%s", msg);
    cr_assert(fabs(vi_profile_max_slope(prof) - 1e-4) <= 1e-15, "%.17g", vi_profile_max_slope(prof));
    for (int k = 0; k < 3; k++) {
        double a = k == 2 ? 1e-6 : 0.0, V = k == 1 ? -2.0 : 2.0;
        vi_model M = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, a);
        cr_assert(vi_model_set_rolling(&M, prof, V, 0.5, msg, sizeof msg) == 0, "%s", msg);
        double s[2], L, Vs;
        vi_model_initial_state(&M, VI_Init_touching, 0.0, 0.0, s);
        vi_model_scales(&M, s, &L, &Vs);
        double v = a * 2.0 * VI_PI * 560.0 + 2.0 * vi_profile_max_slope(prof);
        double dv = pow(15.0 * M.body.m * v * v / (16.0 * M.contact[0].johnson.E_star * sqrt(M.contact[0].johnson.R_star)), 0.4);
        cr_assert(fabs(L - dv) <= 1e-14 * dv, "case %d: L = %.17g vs %.17g", k, L, dv);
    }
    vi_profile_free(prof);
}

/* At the end of a non-periodic profile the loop does not run; inputs that put delta beyond the
 * doubles there (the platform thrown to +1.7e308 m, then to -1.7e308 m: delta = -inf) end the step in
 * an error naming the time, not in a state reported as valid. */
Test(rolling, a_state_beyond_the_doubles_at_the_end_of_the_profile_is_an_error)
{
    test_run s;
    rolling_sim(&s, 1e-4, 1000.0, 9.0, 1e-6); /* the end at t = 1 ms */
    char why[400];
    double end = vi_model_rolling_limit(&s.d.run.model, why, sizeof why);
    cr_assert(vi_sim_advance(&s.s, end) == VI_SIM_OK, "%s", s.r.msg);
    s.d.in.yC_in = 1.7e308;
    s.d.run.inputs_changed = 1;
    cr_assert(vi_sim_advance(&s.s, end + 1e-6) == VI_SIM_DISCARD && s.d.run.t == end, "%s", s.r.msg);
    s.d.in.yC_in = -1.7e308;
    s.d.run.inputs_changed = 1;
    int rc = vi_sim_advance(&s.s, end + 1e-6);
    char expect[128];
    snprintf(expect, sizeof expect, "the state is not finite at t = %.17g s", end);
    cr_assert(rc == VI_SIM_ERROR && strcmp(s.r.msg, expect) == 0 && isinf(s.d.run.x[0]), "rc %d: %s", rc, s.r.msg);
    test_run_free(&s);
    rolling_sim(&s, 1e-4, 1000.0, 9.0, 1e-6); /* the velocity alone (set by hand: no input reaches it) */
    cr_assert(vi_sim_advance(&s.s, end) == VI_SIM_OK, "%s", s.r.msg);
    s.d.run.x[1] = NAN;
    rc = vi_sim_advance(&s.s, end + 1e-6);
    cr_assert(rc == VI_SIM_ERROR && strcmp(s.r.msg, expect) == 0, "rc %d: %s", rc, s.r.msg);
    test_run_free(&s);
    remove(v_trough_file(1e-4));
}

/* A step that ends a few ulps before a kink: the next step starts within rounding of the kink, too
 * close for the solver to step there; the kink is taken at once and the contact rings as usual (the
 * ringing amplitude 2 s0 V / omega_c, linearised, as in kink_is_a_breakpoint_and_rings_the_contact). */
Test(rolling, a_kink_within_rounding_of_the_step_start)
{
    const double s0 = 1e-4, V = 1.0;
    test_run s;
    rolling_sim(&s, s0, V, -0.01, 1e-10);
    double tk = vi_model_next_breakpoint(&s.d.run.model, 0.0), ds = s.d.run.x[0], w = 2.0 * VI_PI * s.d.run.model.f_contact;
    double t1 = nextafter(nextafter(nextafter(tk, 0.0), 0.0), 0.0);
    cr_assert(vi_sim_advance(&s.s, t1) == VI_SIM_OK, "%s", s.r.msg);
    double after = 0.0;
    for (int k = 1; k <= 200; k++) {
        cr_assert(vi_sim_advance(&s.s, tk + 5e-5 * k) == VI_SIM_OK, "k %d: %s", k, s.r.msg);
        after = fmax(after, fabs(s.d.run.x[0] - ds));
    }
    double amp = 2.0 * s0 * V / w;
    cr_assert(fabs(after - amp) <= 0.02 * amp, "ringing %g vs %g", after, amp);
    test_run_free(&s);
    remove(v_trough_file(s0));
}

/* The guards of each mode against their closed forms (inactive ones at 1): free: contact - delta
 * (Johnson after yield: delta_f; LEPP: delta_p); elastic: delta - contact and yield - delta (Hertz
 * never yields); plastic: delta' = yC' - v, or delta - delta_Y for Johnson with a moving contact
 * point; unloading: delta - delta_f, delta_c - delta; stick: F_load(delta_c) - F_hold and
 * F_hold - F_unload(delta_c), with F_hold = W + m yC''. Platform: a = 0.1 mm at 560 Hz, t = 0.1 ms. */
Test(model, guards_of_each_mode)
{
    const double t = 1e-4, P = 40000.0;
    vi_model H = setup(VI_ContactModel_hertz, 0, VI_Unloading_paper, P, 0.0, 1e-4);
    vi_model Y = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, P, 0.0, 1e-4);
    vi_model Jm = setup(VI_ContactModel_johnson, 1, VI_Unloading_paper, P, 0.0, 1e-4);
    vi_model L = setup(VI_ContactModel_lepp, 0, VI_Unloading_paper, P, 0.0, 1e-4);
    const double dY = H.contact[0].johnson.delta_Y, w = H.omega, dyC = -1e-4 * w * sin(w * t), ddyC = -1e-4 * w * w * cos(w * t);
    Y.contact[0].yielded = 1, Y.contact[0].unload = vi_johnson_unload_curve(&Y.contact[0].johnson, VI_UNLOAD_PAPER, 3.0 * dY);
    L.contact[0].delta_p = 0.5 * dY;
    const double d = 2.0 * dY, v = 0.3, df = Y.contact[0].unload.delta_f, dc = Y.contact[0].unload.delta_c;
    const double F_hold = P + Y.body.m * ddyC;
    struct { vi_model *M; int mode; double g0, g1; } c[] = {
        {&H, VI_Mode_free, -d, 1.0},
        {&Y, VI_Mode_free, df - d, 1.0},
        {&L, VI_Mode_free, 0.5 * dY - d, 1.0},
        {&H, VI_Mode_elastic, d, 1.0},
        {&Jm, VI_Mode_elastic, d, dY - d},
        {&L, VI_Mode_elastic, d - 0.5 * dY, 1.5 * dY - d},
        {&Y, VI_Mode_plastic, dyC - v, 1.0},
        {&L, VI_Mode_plastic, dyC - v, 1.0},
        {&Jm, VI_Mode_plastic, d - dY, 1.0},
        {&Y, VI_Mode_unload, d - df, dc - d},
        {&Y, VI_Mode_stick, vi_johnson_load(&Y.contact[0].johnson, dc) - F_hold, F_hold - vi_unload_force(&Y.contact[0].unload, dc)},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        vi_model M = *c[i].M;
        M.contact[0].mode = c[i].mode;
        double x[2] = {d, v}, g[VI_NGUARDS];
        vi_model_guards(&M, t, x, g);
        for (int k = 0; k < 2; k++) {
            double e = k ? c[i].g1 : c[i].g0;
            cr_assert(fabs(g[k] - e) <= 1e-12 * fmax(fabs(e), dY * 1e-3), "case %zu guard %d: %.17g vs %.17g", i, k, g[k],
                      e);
        }
    }
}

/* The right-hand side: delta' = yC' - v and v' = (F - W(t))/m, W = P + m g - F_ext(t); sticking, the
 * mass moves with the platform (delta' = 0, v' = yC''); the Jacobian's d v'/d delta is the mode's
 * stiffness over m (0 free and sticking). */
Test(model, right_hand_side_of_each_mode)
{
    const double t = 1e-4, P = 40000.0;
    vi_model H = setup(VI_ContactModel_hertz, 0, VI_Unloading_paper, P, 9.81, 1e-4);
    H.F_ext = (vi_ramp){100.0, 2e4, 0.0}; /* F_ext(t) = 100 N + 20 kN/s t */
    const double dY = H.contact[0].johnson.delta_Y, w = H.omega, m = H.body.m, dyC = -1e-4 * w * sin(w * t), ddyC = -1e-4 * w * w * cos(w * t);
    const double W = P + m * 9.81 - (100.0 + 2e4 * t), d = 2.0 * dY, v = 0.3;
    double x[2] = {d, v}, dx[2], j[4];
    H.contact[0].mode = VI_Mode_free;
    vi_model_rhs(&H, t, x, dx);
    vi_model_jacobian(&H, t, x, j);
    cr_assert(fabs(dx[0] - (dyC - v)) <= 1e-15 && fabs(dx[1] + W / m) <= 1e-12 * W / m, "free: %g %g", dx[0], dx[1]);
    cr_assert(j[0] == 0.0 && j[1] == -1.0 && j[2] == 0.0 && j[3] == 0.0);
    H.contact[0].mode = VI_Mode_elastic;
    vi_model_rhs(&H, t, x, dx);
    vi_model_jacobian(&H, t, x, j);
    double F = H.contact[0].K * pow(d, 1.5);
    cr_assert(fabs(dx[0] - (dyC - v)) <= 1e-15 && fabs(dx[1] - (F - W) / m) <= 1e-12 * F / m, "elastic: %g", dx[1]);
    cr_assert(j[1] == -1.0 && fabs(j[2] - 1.5 * H.contact[0].K * sqrt(d) / m) <= 1e-12 * j[2], "jacobian %g", j[2]);
    vi_model Y = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, P, 9.81, 1e-4);
    Y.contact[0].yielded = 1, Y.contact[0].unload = vi_johnson_unload_curve(&Y.contact[0].johnson, VI_UNLOAD_PAPER, 3.0 * dY), Y.contact[0].mode = VI_Mode_stick;
    x[0] = Y.contact[0].unload.delta_c;
    vi_model_rhs(&Y, t, x, dx);
    vi_model_jacobian(&Y, t, x, j);
    cr_assert(dx[0] == 0.0 && fabs(dx[1] - ddyC) <= 1e-12 * fabs(ddyC), "stick: %g %g", dx[0], dx[1]);
    cr_assert(j[0] == 0.0 && j[1] == 0.0 && j[2] == 0.0 && j[3] == 0.0);
    Y.contact[0].mode = VI_Mode_unload;
    x[0] = 0.5 * (Y.contact[0].unload.delta_f + Y.contact[0].unload.delta_c);
    vi_model_jacobian(&Y, t, x, j);
    double k = 1.5 * Y.contact[0].unload.Kbar * sqrt(x[0] - Y.contact[0].unload.delta_f);
    cr_assert(j[1] == -1.0 && fabs(j[2] - k / m) <= 1e-12 * k / m, "unloading stiffness %g vs %g", j[2] * m, k);
    vi_model L = setup(VI_ContactModel_lepp, 0, VI_Unloading_paper, P, 9.81, 1e-4);
    L.contact[0].mode = VI_Mode_plastic;
    x[0] = 2.0 * dY;
    vi_model_rhs(&L, t, x, dx);
    vi_model_jacobian(&L, t, x, j);
    double WL = P + m * 9.81;
    cr_assert(fabs(dx[1] - (L.contact[0].johnson.F_Y - WL) / m) <= 1e-12 * WL / m && j[2] == 0.0, "LEPP plastic: %g %g", dx[1], j[2]);
    /* LEPP elastic from its permanent set: no stiffness at delta_p itself (no force there), k_lin beyond */
    L.contact[0].mode = VI_Mode_elastic, L.contact[0].delta_p = 0.5 * dY;
    x[0] = 0.5 * dY;
    vi_model_jacobian(&L, t, x, j);
    cr_assert(j[2] == 0.0 && vi_model_force(&L, t, x) == 0.0, "at delta_p: %g", j[2]);
    x[0] = nextafter(0.5 * dY, 1.0);
    vi_model_jacobian(&L, t, x, j);
    cr_assert(j[2] == L.contact[0].k_lin / m, "beyond delta_p: %g", j[2]);
}

/* An event puts the state exactly onto the surface of the guard that fired and chooses the mode from
 * there (no platform motion, no load: the velocity decides; v < 0 moves into the platform). */
Test(model, event_snaps_onto_the_fired_surface)
{
    vi_model H = setup(VI_ContactModel_hertz, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    vi_model J = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    vi_model Jm = setup(VI_ContactModel_johnson, 1, VI_Unloading_paper, 0.0, 0.0, 0.0);
    vi_model L = setup(VI_ContactModel_lepp, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    vi_model Y = J;
    const double dY = H.contact[0].johnson.delta_Y;
    L.contact[0].delta_p = 0.5 * dY;
    Y.contact[0].yielded = 1, Y.contact[0].unload = vi_johnson_unload_curve(&Y.contact[0].johnson, VI_UNLOAD_PAPER, 3.0 * dY);
    const double df = Y.contact[0].unload.delta_f, dc = Y.contact[0].unload.delta_c;
    struct { vi_model *M; int mode, fired; double d, v, snapped; int after; } c[] = {
        {&H, VI_Mode_free, 0, 1e-12, -0.1, 0.0, VI_Mode_elastic},
        {&H, VI_Mode_elastic, 0, -1e-12, 0.1, 0.0, VI_Mode_free},
        {&L, VI_Mode_elastic, 0, 0.5 * dY - 1e-15, 0.1, 0.5 * dY, VI_Mode_free},
        {&L, VI_Mode_elastic, 1, 1.5 * dY + 1e-15, -0.1, 1.5 * dY, VI_Mode_plastic},
        {&J, VI_Mode_elastic, 1, dY * (1.0 + 1e-12), -0.1, dY, VI_Mode_plastic},
        {&Jm, VI_Mode_plastic, 0, dY * (1.0 - 1e-12), 0.1, dY, VI_Mode_elastic},
        {&Y, VI_Mode_unload, 0, df - 1e-15, 0.1, df, VI_Mode_free},
        {&Y, VI_Mode_unload, 1, dc + 1e-15, -0.1, dc, VI_Mode_plastic},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        vi_model M = *c[i].M;
        M.contact[0].mode = c[i].mode;
        double x[2] = {c[i].d, c[i].v};
        int mode = vi_model_event(&M, 0.0, x, c[i].fired);
        cr_assert(x[0] == c[i].snapped && x[1] == c[i].v && mode == c[i].after && M.contact[0].mode == mode,
                  "case %zu: delta %.17g (surface %.17g), v %g, mode %d", i, x[0], c[i].snapped, x[1], mode);
    }
    /* the turning point of a plastic motion (fixed contact point): delta' = 0 (v = yC' = 0), the
     * memory written down at delta, then unloading (no load holds it) */
    vi_model M = Y;
    M.contact[0].mode = VI_Mode_plastic;
    double x[2] = {4.0 * dY, 1e-9};
    cr_assert(vi_model_event(&M, 0.0, x, 0) == VI_Mode_unload && x[1] == 0.0 && x[0] == 4.0 * dY && M.contact[0].unload.delta_c == 4.0 * dY,
              "mode %d v %g delta_c %g", M.contact[0].mode, x[1], M.contact[0].unload.delta_c);
}

/* Hertz with Tsuji's exact damping of restitution e, a 10 g ball on steel, no load and no platform
 * motion (the rate alone decides). */
static vi_model damped_ball(double e)
{
    vi_parameters p;
    vi_parameters_default(&p);
    p.contact_model = VI_ContactModel_hertz_damped;
    p.damping_formula = VI_DAMP_EXACT;
    p.e_restitution = e;
    p.P = p.g = p.a = 0.0;
    p.m = 0.01;
    vi_model M = {0};
    char msg[256];
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    return M;
}

/* A damped law's force guard fired in contact (delta > 0, g = K delta^(5/4) + alpha_c r < 0, r = yC' - v;
 * no load): the event puts the rate onto the guard's surface, r = -K delta^(5/4)/alpha_c (vi_laws.h),
 * then an ulp or two onto its free side, and the mass leaves, however weak the damping (e close to 1:
 * alpha_c, the guard's slope in r, below 1e-3). */
Test(model, damped_event_puts_the_rate_onto_the_force_guard)
{
    const double es[] = {0.5, 0.99999999}, ds[] = {1e-12, 3.3e-9, 1e-6}, past[] = {2.0, 1.0 + 1e-9};
    for (size_t i = 0; i < sizeof es / sizeof es[0]; i++) {
        const vi_model M0 = damped_ball(es[i]);
        const double K = M0.contact[0].damped.K, ac = M0.contact[0].damped.alpha_c;
        if (i == 1) cr_assert(ac < 1e-3, "alpha_c = %g", ac);
        for (size_t j = 0; j < sizeof ds / sizeof ds[0] * 2; j++) {
            vi_model M = M0;
            M.contact[0].mode = VI_Mode_elastic;
            const double d = ds[j / 2], r_surface = -K * d * sqrt(sqrt(d)) / ac;
            double x[2] = {d, -past[j % 2] * r_surface}; /* r = -v beyond the surface: g < 0 */
            cr_assert(vi_model_event(&M, 0.0, x, 1) == VI_Mode_free && x[0] == d, "e = %.9g: mode %d", es[i], M.contact[0].mode);
            const double ulp = nextafter(fabs(r_surface), INFINITY) - fabs(r_surface);
            cr_assert(fabs(-x[1] - r_surface) <= 4.0 * ulp, "e = %.9g, delta = %g: r = %.17g, on the surface %.17g",
                      es[i], d, -x[1], r_surface);
            /* on the free side of the guard, as the model computes it (no platform motion: r = -v) */
            const double g = vi_damped_hertz_guard(&M.contact[0].damped, x[0], -x[1], M.contact[0].V_i).g;
            cr_assert(g <= 0.0, "e = %.9g, delta = %g: the guard %g after the event is on the contact side", es[i], d, g);
        }
    }
}

/* A damped law's free mode left at delta > 0 (no load, no platform motion, r = -v): where the force
 * guard g = K delta^(5/4) + alpha_c r has just risen through 0 (g = 1e-9 of its terms), the contact
 * resumes: delta is kept and so is the approach speed V_i of the impact before; where g is all of
 * its terms (r > 0, moving in) the contact is new and takes r as V_i, also where g is far below 1. */
Test(model, damped_contact_resumed_keeps_delta_and_the_approach_speed)
{
    const vi_model M0 = damped_ball(0.5);
    const double K = M0.contact[0].damped.K, ac = M0.contact[0].damped.alpha_c, ds[] = {1e-12, 3.3e-9, 1e-6};
    for (size_t j = 0; j < sizeof ds / sizeof ds[0]; j++) {
        const double d = ds[j], r_surface = -K * d * sqrt(sqrt(d)) / ac;
        vi_model M = M0;
        M.contact[0].mode = VI_Mode_free, M.contact[0].V_i = 0.3;
        double x[2] = {d, -r_surface * (1.0 - 1e-9)}; /* r = -v just inside the contact side: g > 0 */
        cr_assert(vi_model_event(&M, 0.0, x, 1) == VI_Mode_elastic && x[0] == d && M.contact[0].V_i == 0.3,
                  "delta = %g: mode %d, delta %g, V_i %g", d, M.contact[0].mode, x[0], M.contact[0].V_i);
        M = M0;
        M.contact[0].mode = VI_Mode_free, M.contact[0].V_i = 0.3;
        const double r_in = 1e-3 / ac, g = K * d * sqrt(sqrt(d)) + 1e-3; /* moving in slowly */
        double in[2] = {d, -r_in};
        cr_assert(vi_model_resolve(&M, 0.0, in) == VI_Mode_elastic && M.contact[0].V_i == r_in,
                  "delta = %g, g = %g: mode %d, V_i %g (r = %g)", d, g, M.contact[0].mode, M.contact[0].V_i, r_in);
    }
}

/* Johnson's mode choice (fixed contact point, no load, no platform motion: the velocity decides) and
 * the memory it writes: below yield elastic; beyond it plastic, yielded, with the unloading curve of
 * delta; pushed beyond delta_c, the curve of the new delta; between delta_f and delta_c unloading
 * (moving in or out), below delta_f free; at a turning point on delta_c with the holding force between
 * the branches stick for the paper's curve, never for the continuous one (no gap between them). */
Test(model, johnson_mode_choice_and_memory)
{
    vi_model J = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    const double dY = J.contact[0].johnson.delta_Y;
    struct { int yielded; double d, v; int mode, yielded_after; double dc_after; } c[] = {
        {0, 0.5, -0.1, VI_Mode_elastic, 0, 0.0},
        {0, 0.5, 0.1, VI_Mode_elastic, 0, 0.0},
        {0, 2.0, -0.1, VI_Mode_plastic, 1, 2.0},
        {1, 4.0, -0.1, VI_Mode_plastic, 1, 4.0},
        {1, 2.5, -0.1, VI_Mode_unload, 1, 3.0},
        {1, 2.5, 0.1, VI_Mode_unload, 1, 3.0},
        {1, 0.5, 0.1, VI_Mode_free, 1, 3.0},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        vi_model M = J;
        M.contact[0].mode = VI_Mode_free;
        if (c[i].yielded) M.contact[0].yielded = 1, M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, 3.0 * dY);
        double x[2] = {c[i].d * dY, c[i].v};
        int mode = vi_model_resolve(&M, 0.0, x);
        cr_assert(mode == c[i].mode && M.contact[0].yielded == c[i].yielded_after && M.contact[0].unload.delta_c == c[i].dc_after * dY,
                  "case %zu: mode %d yielded %d delta_c %g delta_Y", i, mode, M.contact[0].yielded, M.contact[0].unload.delta_c / dY);
        if (M.contact[0].yielded) {
            vi_unload_curve U = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, M.contact[0].unload.delta_c);
            cr_assert(M.contact[0].unload.Rbar == U.Rbar && M.contact[0].unload.delta_f == U.delta_f, "case %zu: not the curve of delta_c", i);
        }
    }
    for (int variant = VI_UNLOAD_PAPER; variant <= VI_UNLOAD_CONTINUOUS; variant++) {
        vi_model M = setup(VI_ContactModel_johnson, 0, variant, 0.0, 0.0, 0.0);
        double dc = 3.0 * dY;
        M.contact[0].yielded = 1, M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, variant, dc), M.contact[0].mode = VI_Mode_plastic;
        double Fl = vi_johnson_load(&M.contact[0].johnson, dc), Fu = vi_unload_force(&M.contact[0].unload, dc);
        M.F_ext = (vi_ramp){-(variant == VI_UNLOAD_PAPER ? 0.5 * (Fl + Fu) : 0.99 * Fl), 0.0, 0.0};
        double x[2] = {dc, 0.0};
        int expect = variant == VI_UNLOAD_PAPER ? VI_Mode_stick : VI_Mode_unload;
        cr_assert(vi_model_resolve(&M, 0.0, x) == expect, "variant %d: mode %d (F_unload %g, F_load %g)", variant, M.contact[0].mode,
                  Fu, Fl);
    }
}

/* A stick guard that fired at the load limit leaves the tie to F_hold' = -F_ext' + m yC''' with yC''' =
 * a w^3 sin(w t): against a rate of F_ext of half that jerk force the mass loads on (plastic), against
 * one and a half times it stays (stick); the rate's magnitude, not its sign alone, decides. */
Test(model, tie_at_the_load_limit_broken_by_the_jerk_against_the_load_rate)
{
    const double t = 1e-4;
    for (int k = 0; k < 2; k++) {
        vi_model M = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 1e-5);
        const double w = M.omega, s = sin(w * t), c = cos(w * t), dc = 3.0 * M.contact[0].johnson.delta_Y;
        cr_assert(s > 0.3);
        M.contact[0].yielded = 1, M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, dc), M.contact[0].mode = VI_Mode_stick;
        M.body.W0 = vi_johnson_load(&M.contact[0].johnson, dc) + M.body.m * 1e-5 * w * w * c; /* F_hold(t) = F_load(delta_c) */
        double jerk = M.body.m * 1e-5 * w * w * w * s;
        M.F_ext = (vi_ramp){0.0, (k ? 1.5 : 0.5) * jerk, t};
        double x[2] = {dc, 0.0};
        int mode = vi_model_event(&M, t, x, 0);
        cr_assert(mode == (k ? VI_Mode_stick : VI_Mode_plastic), "F_ext' = %g m a w^3 sin: mode %d", k ? 1.5 : 0.5, mode);
    }
}

/* Rolling, the jerk of the platform is V^3 yb''' (here on the circular ramp of a step, V = 3 m/s): a
 * tie at the load limit is broken by F_hold' = -F_ext' + m V^3 yb''' against a rate of F_ext of nine
 * tenths of that jerk force (loads on if it is positive, stays otherwise). */
Test(rolling, tie_at_the_load_limit_broken_by_the_profile_jerk)
{
    double xs[] = {-1.0, 0.0, 1e-9, 1.0}, hs[] = {0.0, 0.0, 0.01, 0.01};
    char msg[256];
    vi_profile *prof = vi_profile_create(xs, hs, 4, 0.475, 0, "step", msg, sizeof msg);
    cr_assert(prof != NULL, "%s", msg);
    vi_model M = setup(VI_ContactModel_johnson, 0, VI_Unloading_paper, 0.0, 0.0, 0.0);
    cr_assert(vi_model_set_rolling(&M, prof, 3.0, -0.05, msg, sizeof msg) == 0, "%s", msg);
    const double t = 0.004, V = 3.0, dc = 3.0 * M.contact[0].johnson.delta_Y;
    double b[4];
    vi_profile_eval(prof, vi_model_rolling_position(&M, t), b);
    cr_assert(fabs(b[3]) > 1.0, "yb''' = %g", b[3]);
    M.contact[0].yielded = 1, M.contact[0].unload = vi_johnson_unload_curve(&M.contact[0].johnson, VI_UNLOAD_PAPER, dc), M.contact[0].mode = VI_Mode_stick;
    M.body.W0 = vi_johnson_load(&M.contact[0].johnson, dc) - M.body.m * V * V * b[2]; /* F_hold(t) = F_load(delta_c) */
    M.F_ext = (vi_ramp){0.0, 0.9 * M.body.m * V * V * V * b[3], t};
    double x[2] = {dc, 0.0};
    int mode = vi_model_event(&M, t, x, 0);
    cr_assert(mode == (b[3] > 0.0 ? VI_Mode_plastic : VI_Mode_stick), "yb''' = %g: mode %d", b[3], mode);
    vi_profile_free(prof);
}

/* ---- energy (vi_model.h, ENERGY) ---------------------------------------------------------------- */

/* A model of the law in the mode given at x = (d, r): yielded with delta_c = dc where the mode needs
 * the Johnson or Thornton memory (plastic, unload, stick); the permanent set dp for LEPP. */
static vi_model in_mode(int law, int moving, int unloading, int mode, double dc, double dp)
{
    vi_model M = setup(law, moving, unloading, 0.0, 0.0, 0.0);
    M.contact[0].mode = mode;
    M.contact[0].delta_p = law == VI_ContactModel_lepp ? dp : 0.0;
    if ((law == VI_ContactModel_johnson && !moving) || law == VI_ContactModel_thornton) {
        int memory = mode == VI_Mode_plastic || mode == VI_Mode_unload || mode == VI_Mode_stick;
        M.contact[0].yielded = memory;
        if (memory)
            M.contact[0].unload = law == VI_ContactModel_thornton ? vi_thornton_unload_curve(&M.contact[0].johnson, dc)
                                                       : vi_johnson_unload_curve(&M.contact[0].johnson, unloading, dc);
    }
    return M;
}

/* E_contact in closed form for each law and mode, its rate d/d(delta) against a central difference
 * (the memory following delta where the mode moves it, as in plastic loading), and that rate equal
 * to the force wherever the force is the branch's own (elastic, unload): the work of that force. In
 * plastic loading E_contact + W_plastic is the virgin curve's work (its energy is what the unloading
 * curve of delta_c = delta gives back). The plastic cases load beyond the memory written down a little
 * before (at 2.99 delta_Y), so that the central differences stay on the loading side. */
Test(energy, contact_energy_is_the_work_of_the_branch_force)
{
    vi_model H = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    double dY = H.contact[0].johnson.delta_Y, FY = H.contact[0].johnson.F_Y, K = H.contact[0].K;
    struct { int law, moving, unloading, mode; double d, dc, dp, closed; } c[] = {
        {VI_ContactModel_hertz, 0, 1, VI_Mode_elastic, 2.0 * dY, 0, 0, 0.4 * K * pow(2.0 * dY, 2.5)},
        {VI_ContactModel_hertz, 0, 1, VI_Mode_free, -dY, 0, 0, 0.0},
        {VI_ContactModel_johnson, 0, 1, VI_Mode_elastic, 0.5 * dY, 0, 0, 0.4 * K * pow(0.5 * dY, 2.5)},
        {VI_ContactModel_johnson, 0, 1, VI_Mode_plastic, 3.0 * dY, 2.99 * dY, 0, NAN},
        {VI_ContactModel_johnson, 0, 2, VI_Mode_plastic, 3.0 * dY, 2.99 * dY, 0, NAN},
        {VI_ContactModel_johnson, 0, 1, VI_Mode_unload, 2.5 * dY, 3.0 * dY, 0, NAN},
        {VI_ContactModel_johnson, 0, 1, VI_Mode_stick, 3.0 * dY, 3.0 * dY, 0, NAN},
        {VI_ContactModel_johnson, 1, 1, VI_Mode_plastic, 3.0 * dY, 0, 0, NAN},
        {VI_ContactModel_thornton, 0, 1, VI_Mode_plastic, 3.0 * dY, 2.99 * dY, 0, NAN},
        {VI_ContactModel_thornton, 0, 1, VI_Mode_unload, 2.5 * dY, 3.0 * dY, 0, NAN},
        {VI_ContactModel_lepp, 0, 1, VI_Mode_elastic, 1.5 * dY, 0, dY, 0.5 * FY / dY * 0.25 * dY * dY},
        {VI_ContactModel_lepp, 0, 1, VI_Mode_plastic, 3.0 * dY, 0, 1.99 * dY, 0.5 * FY * dY},
        {VI_ContactModel_hertz_damped, 0, 1, VI_Mode_elastic, 2.0 * dY, 0, 0, 0.4 * K * pow(2.0 * dY, 2.5)},
        {VI_ContactModel_hertz_damped, 0, 1, VI_Mode_free, 2.0 * dY, 0, 0, 0.4 * K * pow(2.0 * dY, 2.5)},
        {VI_ContactModel_linear, 0, 1, VI_Mode_free, 2.0 * dY, 0, 0, 0.5 * 1.2e9 * 4.0 * dY * dY},
        {VI_ContactModel_linear, 0, 1, VI_Mode_free, -dY, 0, 0, 0.0},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        vi_model M = in_mode(c[i].law, c[i].moving, c[i].unloading, c[i].mode, c[i].dc, c[i].dp);
        double x[2] = {c[i].d, 0.0}, k, h = 1e-6 * dY;
        double E = vi_model_contact_energy(&M, x, &k);
        if (!isnan(c[i].closed))
            cr_assert(fabs(E - c[i].closed) <= 1e-12 * fabs(c[i].closed), "case %zu: %.17g, closed form %.17g", i, E,
                      c[i].closed);
        double xp[2] = {c[i].d + h, 0.0}, xm[2] = {c[i].d - h, 0.0};
        double fd = (vi_model_contact_energy(&M, xp, NULL) - vi_model_contact_energy(&M, xm, NULL)) / (2.0 * h);
        cr_assert(fabs(k - fd) <= 1e-6 * (fabs(k) + FY), "case %zu: rate %.17g, difference %.17g", i, k, fd);
        if (c[i].mode == VI_Mode_elastic || c[i].mode == VI_Mode_unload || (c[i].moving && c[i].mode == VI_Mode_plastic))
            cr_assert(fabs(k - vi_model_force(&M, 0.0, x)) <= 1e-12 * fabs(k), "case %zu: the rate is not the force", i);
        if (c[i].mode == VI_Mode_plastic && !c[i].moving && c[i].law != VI_ContactModel_lepp) {
            vi_model_values out;
            vi_model_outputs(&M, 0.0, x, VI_OUT_MEMORY, &out);
            double work = c[i].law == VI_ContactModel_thornton ? vi_thornton_load_work(&M.contact[0].johnson, c[i].d)
                                                                : vi_johnson_load_work(&M.contact[0].johnson, c[i].d);
            cr_assert(fabs(out.E_contact + out.W_plastic - work) <= 1e-12 * work, "case %zu: %.17g + %.17g != %.17g", i,
                      out.E_contact, out.W_plastic, work);
            cr_assert(out.E_contact == E);
        }
    }
}

/* The damping's power: (F - F_spring) delta' with F = max(0, f); Tsuji's form gives alpha sqrt(m K)
 * delta^(1/4) delta'^2, the linear law c delta'^2, both >= 0; free at delta > 0 (after a release)
 * -F_spring delta' (delta falls: >= 0); 0 apart and for every law without damping. Its partials against
 * central differences. */
Test(energy, damping_power_is_the_force_beyond_the_spring_times_the_rate)
{
    vi_model Md = setup(VI_ContactModel_hertz_damped, 0, 1, 0.0, 0.0, 0.0);
    vi_model Ml = setup(VI_ContactModel_linear, 0, 1, 0.0, 0.0, 0.0);
    double d = 2e-5, r[2] = {0.3, -0.2};
    for (int k = 0; k < 2; k++) {
        double x[2] = {d, -r[k]}; /* yC' = 0: delta' = -v */
        Md.contact[0].mode = Ml.contact[0].mode = VI_Mode_elastic;
        vi_model_power Pd = vi_model_damping_power(&Md, 0.0, x), Pl = vi_model_damping_power(&Ml, 0.0, x);
        double want_d = Md.contact[0].damped.alpha_c * pow(d, 0.25) * r[k] * r[k], want_l = Ml.contact[0].linear.c * r[k] * r[k];
        if (vi_damped_hertz_force(&Md.contact[0].damped, d, r[k], 0.0).F > 0.0)
            cr_assert(fabs(Pd.P - want_d) <= 1e-12 * want_d, "Tsuji %.17g, closed form %.17g", Pd.P, want_d);
        if (vi_linear_force(&Ml.contact[0].linear, d, r[k]).F > 0.0)
            cr_assert(fabs(Pl.P - want_l) <= 1e-12 * want_l, "linear %.17g, closed form %.17g", Pl.P, want_l);
        const vi_model *models[2] = {&Md, &Ml};
        for (int j = 0; j < 2; j++) {
            const vi_model *M = models[j];
            vi_model_power P = vi_model_damping_power(M, 0.0, x);
            double hd = 1e-7 * d, hr = 1e-7;
            double xp[2] = {d + hd, x[1]}, xm[2] = {d - hd, x[1]}, vp[2] = {d, x[1] - hr}, vm[2] = {d, x[1] + hr};
            double fd_d = (vi_model_damping_power(M, 0.0, xp).P - vi_model_damping_power(M, 0.0, xm).P) / (2.0 * hd);
            double fd_r = (vi_model_damping_power(M, 0.0, vp).P - vi_model_damping_power(M, 0.0, vm).P) / (2.0 * hr);
            cr_assert(P.P >= 0.0, "law %d rate %g: power %g", j, r[k], P.P);
            cr_assert(fabs(P.dP_ddelta - fd_d) <= 1e-5 * (fabs(fd_d) + fabs(P.P) / d), "law %d: %g %g", j, P.dP_ddelta, fd_d);
            cr_assert(fabs(P.dP_drate - fd_r) <= 1e-5 * (fabs(fd_r) + fabs(P.P) / fabs(r[k])), "law %d: %g %g", j,
                      P.dP_drate, fd_r);
        }
    }
    double away[2] = {d, 0.2}; /* free, still overlapping, delta falling at 0.2 m/s */
    Md.contact[0].mode = Ml.contact[0].mode = VI_Mode_free;
    double Fs = Md.contact[0].K * pow(d, 1.5);
    cr_assert(fabs(vi_model_damping_power(&Md, 0.0, away).P - 0.2 * Fs) <= 1e-12 * 0.2 * Fs);
    cr_assert(fabs(vi_model_damping_power(&Ml, 0.0, away).P - 0.2 * Ml.contact[0].linear.k * d) <= 1e-12 * 0.2 * Ml.contact[0].linear.k * d);
    double apart[2] = {-d, 0.2};
    cr_assert(vi_model_damping_power(&Md, 0.0, apart).P == 0.0 && vi_model_damping_power(&Ml, 0.0, apart).P == 0.0);
    cr_assert(vi_model_damps(&Md) && vi_model_damps(&Ml));
    for (int law = VI_ContactModel_hertz; law <= VI_ContactModel_thornton; law++) {
        if (law == VI_ContactModel_hertz_damped || law == VI_ContactModel_linear) continue;
        vi_model M = setup(law, 0, 1, 0.0, 0.0, 0.0);
        M.contact[0].mode = VI_Mode_elastic;
        double x[2] = {d, -0.3};
        cr_assert(!vi_model_damps(&M) && vi_model_damping_power(&M, 0.0, x).P == 0.0, "law %d", law);
    }
}

/* dF/dt along the motion against a central difference in time along x' (vi_model_rhs), in each mode of
 * each kind of law, under the harmonic excitation and a ramp of F_ext; the force it gives is
 * vi_model_force's. With x' from an interpolant (dx) the same within the difference's error. */
Test(energy, force_rate_is_the_time_derivative_of_the_force)
{
    vi_model H = setup(VI_ContactModel_hertz, 0, 1, 0.0, 0.0, 0.0);
    double dY = H.contact[0].johnson.delta_Y;
    struct { int law, unloading, mode; double d, dc, v; } c[] = {
        {VI_ContactModel_hertz, 1, VI_Mode_elastic, 2.0 * dY, 0, -0.1},
        {VI_ContactModel_johnson, 1, VI_Mode_plastic, 3.0 * dY, 3.0 * dY, -0.1},
        {VI_ContactModel_johnson, 1, VI_Mode_unload, 2.5 * dY, 3.0 * dY, 0.1},
        {VI_ContactModel_johnson, 1, VI_Mode_stick, 3.0 * dY, 3.0 * dY, 0.0},
        {VI_ContactModel_thornton, 1, VI_Mode_plastic, 3.0 * dY, 3.0 * dY, -0.1},
        {VI_ContactModel_lepp, 1, VI_Mode_elastic, 0.5 * dY, 0, 0.1},
        {VI_ContactModel_hertz_damped, 1, VI_Mode_elastic, 2.0 * dY, 0, -0.1},
        {VI_ContactModel_linear, 1, VI_Mode_elastic, 2.0 * dY, 0, 0.05},
        {VI_ContactModel_hertz, 1, VI_Mode_free, -dY, 0, 0.1},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        vi_model M = in_mode(c[i].law, 0, c[i].unloading, c[i].mode, c[i].dc, 0.0);
        M.a = 1e-5, M.omega = 2.0 * VI_PI * 560.0;
        M.F_ext = (vi_ramp){-1e3, 2e6, 0.0};
        double t = 1e-4, x[2] = {c[i].d, c[i].v}, dx[2], F, h = 1e-9;
        vi_model_rhs(&M, t, x, dx);
        double g = vi_model_force_rate(&M, t, x, NULL, &F), g_dx = vi_model_force_rate(&M, t, x, dx, &F);
        double xp[2] = {x[0] + h * dx[0], x[1] + h * dx[1]}, xm[2] = {x[0] - h * dx[0], x[1] - h * dx[1]};
        double fd = (vi_model_force(&M, t + h, xp) - vi_model_force(&M, t - h, xm)) / (2.0 * h);
        double scale = fabs(fd) + 1e-6 * H.contact[0].johnson.F_Y / 1e-3;
        cr_assert(F == vi_model_force(&M, t, x), "case %zu: F %.17g, %.17g", i, F, vi_model_force(&M, t, x));
        cr_assert(fabs(g - fd) <= 1e-5 * scale, "case %zu: rate %.17g, difference %.17g", i, g, fd);
        cr_assert(fabs(g_dx - g) <= 1e-9 * scale, "case %zu: with x' given %.17g, %.17g", i, g_dx, g);
    }
}

/* The upper stop needs a clearance > 0, and sets up a second contact at -gap - delta. */
Test(model, an_upper_stop_needs_a_positive_gap)
{
    vi_parameters p;
    vi_parameters_default(&p);
    p.upper_stop = 1, p.gap = 0.0;
    vi_model M;
    char msg[256];
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) < 0 && strstr(msg, "gap = 0 m") != NULL, "%s", msg);
    p.gap = 1e-3;
    cr_assert(setup_from_table(&M, &p, 0.0, msg, sizeof msg) == 0, "%s", msg);
    cr_assert(M.ncontacts == 2 && M.contact[VI_UPPER].upper == 1 && M.contact[VI_UPPER].gap == 1e-3);
    cr_assert(M.contact[VI_UPPER].K == M.contact[VI_LOWER].K, "the same law and material on both sides");
}

/* A saved model: one or two contacts, and a contact not in use blank in every field. */
Test(model_check, the_upper_contact_not_in_use_is_blank)
{
    double x0[2];
    vi_model ok = default_unloading_model(x0);
    accepted_as(&ok, x0, "the lower contact alone");
    vi_model bad = ok;
    bad.contact[VI_UPPER].johnson.F_Y = 1.0;
    refused_with(&bad, x0, 1, "the upper contact is not in use but has a state (law 0, mode 0, gap 0 m)");
    bad = ok, bad.contact[VI_UPPER].n_impacts = 1;
    refused_with(&bad, x0, 1, "the upper contact is not in use but has a state (law 0, mode 0, gap 0 m)");
    bad = ok, bad.ncontacts = 3;
    refused_with(&bad, x0, 1, "ncontacts = 3 is not 1 or 2");
    bad = ok, bad.contact[VI_UPPER].upper = 0;
    refused_with(&bad, x0, 1, "the contacts' sides (lower 0, upper 0) are not lower and upper");
}

/* A contact not in use (the upper one without the upper stop, or an index outside the model's contacts) has
 * no stiffness rate, slopes or memory rates, whatever its slot holds: here a copy of the loaded lower
 * contact. */
Test(model, a_contact_not_in_use_gives_zeros_whatever_its_slot_holds)
{
    vi_model M = setup(VI_ContactModel_hertz, 0, VI_Unloading_paper, 40000.0, 9.81, 1e-4);
    double x[2];
    vi_model_initial_state(&M, VI_Init_static, 0.0, 0.0, x);
    cr_assert(M.ncontacts == 1 && M.contact[VI_LOWER].mode == VI_Mode_elastic);
    double per_rate = 1.0, k = 1.0, c = 1.0;
    cr_assert(vi_model_stiffness_rate(&M, VI_LOWER, 0.0, x, &per_rate) != 0.0); /* Hertz: F'' != 0 at delta > 0 */
    M.contact[VI_UPPER] = M.contact[VI_LOWER];
    int unused[] = {VI_UPPER, -1, VI_NCONTACTS};
    for (int j = 0; j < 3; j++) {
        per_rate = k = c = 1.0;
        cr_assert(vi_model_stiffness_rate(&M, unused[j], 0.0, x, &per_rate) == 0.0 && per_rate == 0.0, "i = %d", unused[j]);
        vi_model_contact_slopes(&M, unused[j], 0.0, x, &k, &c);
        cr_assert(k == 0.0 && c == 0.0, "i = %d: k = %g, c = %g", unused[j], k, c);
        vi_memory_rates r = {1.0, 1.0, 1.0, 1.0, 1.0};
        vi_model_memory_rates(&M, unused[j], x, &r);
        cr_assert(r.delta_c == 0.0 && r.delta_f == 0.0 && r.delta_p == 0.0 && r.Rbar == 0.0 && r.W_plastic == 0.0,
                  "i = %d", unused[j]);
    }
}
