/* Unit tests of the Model Exchange model (vi_me.h) without an FMU: the analytic partial derivatives
 * against central differences and closed forms in every mode of every law, the states, inputs and
 * derivatives the importer sees, the initialization's log, and the event iteration (guards, bands,
 * snapping, input changes, Zeno). Expected values come from the laws' closed forms (vi_contact.h)
 * or from differences of the model's own outputs, never from the code under test's results. */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "vi_me.h"

/* The last message of each log category, formatted. */
static char logged[8][1024];
static int n_logged[8];
static void capture(void *env, int category, const char *fmt, ...)
{
    (void)env;
    if (category < 0 || category >= 8) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(logged[category], sizeof logged[category], fmt, ap);
    va_end(ap);
    n_logged[category]++;
}
static void clear_log(void) { memset(logged, 0, sizeof logged), memset(n_logged, 0, sizeof n_logged); }

typedef void (*setter)(vi_parameters *p);

/* A Model Exchange instance of the defaults changed by `set`, initialized. */
static void start(vi_me *e, setter set)
{
    memset(e, 0, sizeof *e);
    clear_log();
    vi_sim_init(&e->s, capture, NULL);
    if (set) set(&e->s.d.par);
    cr_assert(vi_me_initialize(e) == 0, "%s", e->s.msg);
}

static void finish(vi_me *e) { vi_sim_free(&e->s); }

static void hertz(vi_parameters *p) { p->contact_model = VI_ContactModel_hertz; }
static void johnson(vi_parameters *p) { p->contact_model = VI_ContactModel_johnson; }
static void johnson_continuous(vi_parameters *p) { johnson(p), p->unloading = VI_Unloading_continuous; }
static void johnson_moving(vi_parameters *p) { johnson(p), p->moving_contact = 1; }
static void lepp(vi_parameters *p) { p->contact_model = VI_ContactModel_lepp; }


/* Put the instance into `mode` at indentation delta and velocity v (y = yC - delta), with the memory
 * that mode implies: Johnson plastic (fixed contact point) tracks delta_c = delta; unload and stick
 * hold delta_c = dc; LEPP plastic has delta_p = delta - delta_Y, LEPP elastic the permanent set dc. */
static void put(vi_me *e, int mode, double delta, double v, double dc)
{
    vi_model *M = &e->s.d.M;
    M->mode = mode;
    if (M->law == VI_ContactModel_johnson && !M->moving) {
        int plastic = mode == VI_Mode_plastic;
        M->yielded = plastic || mode == VI_Mode_unload || mode == VI_Mode_stick;
        M->U = M->yielded ? vi_johnson_unload_curve(&M->J, M->unloading, plastic ? delta : dc) : (vi_unload_curve){0};
    }
    if (M->law == VI_ContactModel_lepp) M->delta_p = mode == VI_Mode_plastic ? delta - M->J.delta_Y : dc;
    double x[2] = {vi_model_platform(M, e->s.d.t, NULL, NULL) - delta, v};
    vi_me_set_states(e, x);
    e->s.d.guard_band[0] = e->s.d.guard_band[1] = 0.0;
    e->s.d.step_t0 = e->s.d.t, e->s.d.step_v0 = v; /* a step starts here: F_mean is the force itself */
}

static double output(vi_me *e, int vr)
{
    const vi_outputs *out = vi_me_outputs_of(e, VI_OUT_ALL);
    const vi_variable *var = &vi_variable_table[vr];
    if (var->type == VI_Integer) return *(const int *)((const char *)out + var->offset);
    return *(const double *)((const char *)out + var->offset);
}

/* Change one known (the state y or v, the input yC_in or F_ext, set in continuous time) by h. */
static void nudge(vi_me *e, int known, double h)
{
    double x[2];
    vi_me_get_states(e, x);
    switch (known) {
    case VI_VR_y: x[0] += h; vi_me_set_states(e, x); break;
    case VI_VR_v: x[1] += h; vi_me_set_states(e, x); break;
    case VI_VR_yC_in: e->s.d.in.yC_in += h; vi_me_set_time(e, e->s.d.t); break;
    case VI_VR_F_ext: e->s.d.in.F_ext += h; vi_me_set_time(e, e->s.d.t); break;
    }
}

static const int knowns[] = {VI_VR_y, VI_VR_v, VI_VR_yC_in, VI_VR_F_ext};
static const int unknowns[] = {VI_VR_der_y, VI_VR_der_v, VI_VR_F, VI_VR_F_mean, VI_VR_delta, VI_VR_y, VI_VR_v,
                               VI_VR_yC, VI_VR_k_contact, VI_VR_delta_c, VI_VR_delta_f, VI_VR_Rbar, VI_VR_delta_p,
                               VI_VR_W_plastic, VI_VR_E_star, VI_VR_F_Y};

/* Every partial derivative of every unknown at the current point against central differences of the
 * outputs (steps of 1e-5 of the problem's scales; the point must be smooth within them). */
static void partials_match_differences(vi_me *e, const char *where)
{
    vi_sim_data d0 = e->s.d;
    double y0 = e->y, nominal[2];
    vi_me_nominals(e, nominal);
    double scale[] = {nominal[0], nominal[1], nominal[0], 1e4};
    for (int j = 0; j < 4; j++) {
        double h = 1e-5 * scale[j];
        for (size_t i = 0; i < sizeof unknowns / sizeof *unknowns; i++) {
            int u = unknowns[i];
            e->s.d = d0, e->y = y0, e->s.out_valid = 0;
            double J = vi_me_partial(e, u, knowns[j]), f0 = output(e, u);
            nudge(e, knowns[j], h);
            double fp = output(e, u);
            e->s.d = d0, e->y = y0, e->s.out_valid = 0;
            nudge(e, knowns[j], -h);
            double fm = output(e, u);
            e->s.d = d0, e->y = y0, e->s.out_valid = 0;
            double fd = (fp - fm) / (2.0 * h), tol = 1e-6 * (fabs(J) + fabs(fd)) + 1e-12 * fabs(f0) / scale[j];
            if (fd == 0.0) tol = 0.0; /* the output does not move: its partial is exactly zero */
            cr_assert(fabs(J - fd) <= tol, "%s (mode %d): d%s/d%s = %.10g, central difference %.10g", where,
                      e->s.d.M.mode, vi_variable_table[u].name, vi_variable_table[knowns[j]].name, J, fd);
        }
    }
}

/* The same 1 ms later, where the mean force covers a step of its own (F_mean = m (v - v0)/h + ...;
 * the step starts at put's time, which is not 0 after the first point of a test). */
static void partials_match_differences_now_and_later(vi_me *e, const char *where)
{
    partials_match_differences(e, where);
    vi_me_set_time(e, e->s.d.t + 1e-3);
    partials_match_differences(e, where);
}

Test(me_jacobian, partials_of_hertz_in_free_flight_and_contact)
{
    vi_me e;
    start(&e, hertz);
    const vi_model *M = &e.s.d.M;
    double d = 0.7 * vi_hertz_indentation(M->K, M->W0);
    put(&e, VI_Mode_free, -d, 0.01, 0.0);
    partials_match_differences_now_and_later(&e, "hertz free");
    put(&e, VI_Mode_elastic, d, 0.01, 0.0);
    partials_match_differences_now_and_later(&e, "hertz elastic");
    put(&e, VI_Mode_elastic, 3.0 * M->J.delta_Y, 0.01, 0.0); /* Hertz has no yield: the same law beyond delta_Y */
    partials_match_differences_now_and_later(&e, "hertz elastic beyond delta_Y");
    finish(&e);
}

Test(me_jacobian, partials_of_johnson_in_every_mode)
{
    setter laws[] = {johnson, johnson_continuous};
    for (int l = 0; l < 2; l++) {
        vi_me e;
        start(&e, laws[l]);
        double dY = e.s.d.M.J.delta_Y;
        put(&e, VI_Mode_elastic, 0.6 * dY, -0.01, 0.0);
        partials_match_differences_now_and_later(&e, "johnson elastic");
        put(&e, VI_Mode_plastic, 1.7 * dY, -0.01, 0.0);
        partials_match_differences_now_and_later(&e, "johnson plastic");
        put(&e, VI_Mode_unload, 1.6 * dY, 0.01, 1.8 * dY);
        partials_match_differences_now_and_later(&e, "johnson unload");
        if (l == 0) {
            put(&e, VI_Mode_stick, 1.8 * dY, 0.0, 1.8 * dY);
            partials_match_differences_now_and_later(&e, "johnson stick");
        }
        put(&e, VI_Mode_free, -0.5 * dY, 0.01, 1.8 * dY);
        partials_match_differences_now_and_later(&e, "johnson free");
        finish(&e);
    }
}

Test(me_jacobian, partials_of_johnson_with_a_moving_contact_point)
{
    vi_me e;
    start(&e, johnson_moving);
    double dY = e.s.d.M.J.delta_Y;
    put(&e, VI_Mode_elastic, 0.6 * dY, -0.01, 0.0);
    partials_match_differences_now_and_later(&e, "moving elastic");
    put(&e, VI_Mode_plastic, 1.7 * dY, -0.01, 0.0);
    partials_match_differences_now_and_later(&e, "moving plastic");
    finish(&e);
}

Test(me_jacobian, partials_of_lepp_in_every_mode)
{
    vi_me e;
    start(&e, lepp);
    double dY = e.s.d.M.J.delta_Y;
    put(&e, VI_Mode_elastic, 0.6 * dY, -0.01, 0.2 * dY);
    partials_match_differences_now_and_later(&e, "lepp elastic");
    put(&e, VI_Mode_plastic, 1.7 * dY, -0.01, 0.0);
    partials_match_differences_now_and_later(&e, "lepp plastic");
    put(&e, VI_Mode_free, 0.1 * dY, 0.01, 0.2 * dY);
    partials_match_differences_now_and_later(&e, "lepp free");
    finish(&e);
}

/* d(k_contact)/d(yC_in) = dk/ddelta, the second derivative of the force law (closed forms). */
static double stiffness_rate(vi_me *e) { return vi_me_partial(e, VI_VR_k_contact, VI_VR_yC_in); }

Test(me_jacobian, stiffness_rate_at_the_ends_of_each_branch)
{
    vi_me e;
    start(&e, hertz);
    double K = e.s.d.M.K, dY = e.s.d.M.J.delta_Y;
    put(&e, VI_Mode_elastic, 0.0, 0.0, 0.0); /* touching: F = K d^1.5 has F'' = 0.75 K/sqrt(d) -> its limit 0 is reported */
    cr_assert(stiffness_rate(&e) == 0.0, "hertz at delta = 0: %g", stiffness_rate(&e));
    put(&e, VI_Mode_elastic, -1e-9, 0.0, 0.0); /* a state beyond the contact surface before its event */
    cr_assert(stiffness_rate(&e) == 0.0, "hertz at delta < 0: %g", stiffness_rate(&e));
    put(&e, VI_Mode_elastic, 4.0 * dY, 0.0, 0.0);
    cr_assert(fabs(stiffness_rate(&e) - 0.75 * K / sqrt(4.0 * dY)) <= 1e-14 * 0.75 * K / sqrt(dY), "hertz beyond delta_Y");
    finish(&e);

    start(&e, johnson);
    const vi_johnson *J = &e.s.d.M.J;
    put(&e, VI_Mode_elastic, 0.0, 0.0, 0.0);
    cr_assert(stiffness_rate(&e) == 0.0, "johnson at delta = 0: %g", stiffness_rate(&e));
    put(&e, VI_Mode_elastic, -1e-9, 0.0, 0.0);
    cr_assert(stiffness_rate(&e) == 0.0, "johnson at delta < 0: %g", stiffness_rate(&e));
    put(&e, VI_Mode_elastic, 1e-4 * J->delta_Y, 0.0, 0.0); /* just touching: F'' = 0.75 F_Y/(dY^2 sqrt(d/dY)) */
    double touching = 0.75 * J->F_Y / (J->delta_Y * J->delta_Y * sqrt(e.s.d.x[0] / J->delta_Y));
    cr_assert(fabs(stiffness_rate(&e) - touching) <= 1e-12 * touching, "johnson at 1e-4 delta_Y: %.17g, closed form %.17g",
              stiffness_rate(&e), touching);
    /* on the yield surface, still elastic: the elastic branch F = F_Y (d/dY)^1.5, F'' = 0.75 F_Y/dY^2 */
    put(&e, VI_Mode_elastic, J->delta_Y, 0.0, 0.0);
    double elastic = 0.75 * J->F_Y / (J->delta_Y * J->delta_Y);
    cr_assert(fabs(stiffness_rate(&e) - elastic) <= 1e-14 * elastic, "johnson at delta_Y: %.17g, closed form %.17g",
              stiffness_rate(&e), elastic);
    /* unloading at and below delta_f (the force is 0 there) */
    put(&e, VI_Mode_unload, 0.0, 0.0, 2.0 * dY);
    double df = e.s.d.M.U.delta_f;
    put(&e, VI_Mode_unload, df, 0.0, 2.0 * dY);
    cr_assert(e.s.d.x[0] == df, "delta %.17g is not delta_f %.17g", e.s.d.x[0], df);
    cr_assert(stiffness_rate(&e) == 0.0, "unload at delta_f: %g", stiffness_rate(&e));
    put(&e, VI_Mode_unload, 0.5 * df, 0.0, 2.0 * dY);
    cr_assert(stiffness_rate(&e) == 0.0, "unload below delta_f: %g", stiffness_rate(&e));
    /* in stick the reported stiffness is that at delta_c: it does not move with delta */
    put(&e, VI_Mode_stick, 2.0 * dY, 0.0, 2.0 * dY);
    cr_assert(stiffness_rate(&e) == 0.0 && vi_me_partial(&e, VI_VR_k_contact, VI_VR_y) == 0.0, "stick");
    finish(&e);
}

Test(me_jacobian, partials_are_those_of_inputs_set_since_the_last_call)
{
    vi_me e;
    start(&e, hertz);
    double K = e.s.d.M.K, m = e.s.d.M.m, d = e.s.d.x[0];
    /* the platform rises by d/2 in continuous time: the stiffness is that at 1.5 d */
    e.s.d.in.yC_in = 0.5 * d;
    double k = 1.5 * K * sqrt(1.5 * d);
    cr_assert(fabs(vi_me_partial(&e, VI_VR_der_v, VI_VR_y) + k / m) <= 1e-12 * k / m, "der_v/y = %.17g, closed form %.17g",
              vi_me_partial(&e, VI_VR_der_v, VI_VR_y), -k / m);
    finish(&e);
}

Test(me_jacobian, partials_with_respect_to_parameters_are_zero)
{
    vi_me e;
    start(&e, johnson);
    for (size_t i = 0; i < sizeof unknowns / sizeof *unknowns; i++) {
        cr_assert(vi_me_partial(&e, unknowns[i], VI_VR_m) == 0.0, "%s", vi_variable_table[unknowns[i]].name);
        cr_assert(vi_me_partial(&e, unknowns[i], VI_VR_k_contact) == 0.0, "%s", vi_variable_table[unknowns[i]].name);
    }
    finish(&e);
}
