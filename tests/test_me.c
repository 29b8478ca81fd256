/* Unit tests of the Model Exchange model (test_run.h) without an FMU: the analytic partial derivatives
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
#include <unistd.h> /* getpid */

#include "test_run.h"

/* The last message of each log category, formatted. */
static char logged[8][1024];
static int n_logged[8];
static char history[4096]; /* every message of the events category, one per line */
static void capture(void *env, int category, const char *fmt, ...)
{
    (void)env;
    if (category < 0 || category >= 8) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(logged[category], sizeof logged[category], fmt, ap);
    va_end(ap);
    n_logged[category]++;
    if (category == VI_LOG_EVENTS && strlen(history) + strlen(logged[category]) + 2 < sizeof history)
        strcat(strcat(history, logged[category]), "\n");
}
static void clear_log(void) { memset(logged, 0, sizeof logged), memset(n_logged, 0, sizeof n_logged), history[0] = 0; }

typedef void (*setter)(vi_parameters *p);

/* The partial derivative of the unknown with value reference `unknown` with respect to the known
 * `known` (the row and column of vi_me_jacobian, mapped here as the FMU adapter maps them). */
static double vi_me_partial(test_run *e, int unknown, int known)
{
    static const int rows[VI_NVARS] = {
        [VI_VR_der_y] = VI_ME_DER_Y + 1, [VI_VR_der_v] = VI_ME_DER_V + 1, [VI_VR_F] = VI_ME_F + 1,
        [VI_VR_F_mean] = VI_ME_F_MEAN + 1, [VI_VR_delta] = VI_ME_DELTA + 1, [VI_VR_y] = VI_ME_Y + 1,
        [VI_VR_v] = VI_ME_V + 1, [VI_VR_yC] = VI_ME_YC + 1, [VI_VR_k_contact] = VI_ME_K_CONTACT + 1,
        [VI_VR_delta_c] = VI_ME_DELTA_C + 1, [VI_VR_delta_f] = VI_ME_DELTA_F + 1, [VI_VR_Rbar] = VI_ME_RBAR + 1,
        [VI_VR_delta_p] = VI_ME_DELTA_P + 1, [VI_VR_W_plastic] = VI_ME_W_PLASTIC + 1}; /* 0: none */
    vi_me_partials J[VI_ME_N_UNKNOWNS];
    vi_me_jacobian(&e->e, J);
    if (unknown < 0 || unknown >= VI_NVARS || rows[unknown] == 0) return 0.0;
    const vi_me_partials *row = &J[rows[unknown] - 1];
    return known == VI_VR_y ? row->y : known == VI_VR_v ? row->v : known == VI_VR_yC_in ? row->yC_in
         : known == VI_VR_F_ext ? row->F_ext : 0.0;
}

/* A Model Exchange instance of the defaults changed by `set`, initialized. */
static void start(test_run *e, setter set)
{
    memset(e, 0, sizeof *e);
    clear_log();
    test_run_init(e, capture, NULL);
    if (set) set(&e->d.par);
    cr_assert(vi_me_initialize(&e->e) == 0, "%s", e->r.msg);
}

static void finish(test_run *e) { test_run_free(e); }

static void hertz(vi_parameters *p) { p->contact_model = VI_ContactModel_hertz; }
static void johnson(vi_parameters *p) { p->contact_model = VI_ContactModel_johnson; }
static void johnson_continuous(vi_parameters *p) { johnson(p), p->unloading = VI_Unloading_continuous; }
static void johnson_moving(vi_parameters *p) { johnson(p), p->moving_contact = 1; }
static void lepp(vi_parameters *p) { p->contact_model = VI_ContactModel_lepp; }


/* Put the instance into `mode` at indentation delta and velocity v (y = yC - delta), with the memory
 * that mode implies: Johnson plastic (fixed contact point) tracks delta_c = delta beyond the memory
 * written down (at PLASTIC_WRITTEN delta: the outputs are smooth around delta); unload and stick hold
 * delta_c = dc; LEPP plastic has delta_p = delta - delta_Y beyond the set written down (PLASTIC_WRITTEN
 * delta - delta_Y), LEPP elastic the permanent set dc. */
#define PLASTIC_WRITTEN 0.999
static void put(test_run *e, int mode, double delta, double v, double dc)
{
    vi_model *M = &e->d.run.model;
    M->contact[0].mode = mode;
    if (M->contact[0].law == VI_ContactModel_johnson && !M->contact[0].moving) {
        int plastic = mode == VI_Mode_plastic;
        M->contact[0].yielded = plastic || mode == VI_Mode_unload || mode == VI_Mode_stick;
        double written = plastic ? PLASTIC_WRITTEN * delta : dc;
        M->contact[0].unload = M->contact[0].yielded ? vi_johnson_unload_curve(&M->contact[0].johnson, M->contact[0].unloading, written) : (vi_unload_curve){0};
    }
    if (M->contact[0].law == VI_ContactModel_lepp) M->contact[0].delta_p = mode == VI_Mode_plastic ? PLASTIC_WRITTEN * delta - M->contact[0].johnson.delta_Y : dc;
    double x[VI_ME_NSTATES] = {vi_model_platform(M, e->d.run.t, NULL, NULL) - delta, v};
    vi_me_set_states(&e->e, x);
    vi_contact_outputs_of(e, 0); /* a read: the model catches up with the states set */
    e->d.run.events.band[0] = e->d.run.events.band[1] = 0.0;
    e->d.run.step_t0 = e->d.run.t, e->d.run.step_v0 = v; /* a step starts here: F_mean is the force itself */
}

static double output(test_run *e, int vr)
{
    const vi_outputs *out = vi_contact_outputs_of(e, VI_OUT_ALL);
    const vi_variable *var = &vi_variable_table[vr];
    if (var->type == VI_Integer) return *(const int *)((const char *)out + var->offset);
    return *(const double *)((const char *)out + var->offset);
}

/* Change one known (the state y or v, the input yC_in or F_ext, set in continuous time) by h. */
static void nudge(test_run *e, int known, double h)
{
    double x[VI_ME_NSTATES];
    vi_me_get_states(&e->e, x);
    switch (known) {
    case VI_VR_y: x[0] += h; vi_me_set_states(&e->e, x); break;
    case VI_VR_v: x[1] += h; vi_me_set_states(&e->e, x); break;
    case VI_VR_yC_in: e->d.in.yC_in += h; vi_me_set_time(&e->e, e->d.run.t); break;
    case VI_VR_F_ext: e->d.in.F_ext += h; vi_me_set_time(&e->e, e->d.run.t); break;
    }
}

static const int knowns[] = {VI_VR_y, VI_VR_v, VI_VR_yC_in, VI_VR_F_ext};
static const int unknowns[] = {VI_VR_der_y, VI_VR_der_v, VI_VR_F, VI_VR_F_mean, VI_VR_delta, VI_VR_y, VI_VR_v,
                               VI_VR_yC, VI_VR_k_contact, VI_VR_delta_c, VI_VR_delta_f, VI_VR_Rbar, VI_VR_delta_p,
                               VI_VR_W_plastic, VI_VR_E_star, VI_VR_F_Y};

/* Every partial derivative of every unknown at the current point against central differences of the
 * outputs (steps of 1e-5 of the problem's scales; the point must be smooth within them). */
static void partials_match_differences(test_run *e, const char *where)
{
    vi_contact_data d0 = e->d;
    double y0 = e->d.me.y_me, nominal[VI_ME_NSTATES];
    vi_me_nominals(&e->e, nominal);
    double scale[] = {nominal[0], nominal[1], nominal[0], 1e4};
    for (int j = 0; j < 4; j++) {
        double h = 1e-5 * scale[j];
        for (size_t i = 0; i < sizeof unknowns / sizeof *unknowns; i++) {
            int u = unknowns[i];
            e->d = d0, e->d.me.y_me = y0, e->r.out_valid = 0;
            double J = vi_me_partial(e, u, knowns[j]), f0 = output(e, u);
            nudge(e, knowns[j], h);
            double fp = output(e, u);
            e->d = d0, e->d.me.y_me = y0, e->r.out_valid = 0;
            nudge(e, knowns[j], -h);
            double fm = output(e, u);
            e->d = d0, e->d.me.y_me = y0, e->r.out_valid = 0;
            double fd = (fp - fm) / (2.0 * h), tol = 1e-6 * (fabs(J) + fabs(fd)) + 1e-12 * fabs(f0) / scale[j];
            if (fd == 0.0) tol = 0.0; /* the output does not move: its partial is exactly zero */
            cr_assert(fabs(J - fd) <= tol, "%s (mode %d): d%s/d%s = %.10g, central difference %.10g", where,
                      e->d.run.model.contact[0].mode, vi_variable_table[u].name, vi_variable_table[knowns[j]].name, J, fd);
        }
    }
}

/* The same 1 ms later, where the mean force covers a step of its own (F_mean = m (v - v0)/h + ...;
 * the step starts at put's time, which is not 0 after the first point of a test). */
static void partials_match_differences_now_and_later(test_run *e, const char *where)
{
    partials_match_differences(e, where);
    vi_me_set_time(&e->e, e->d.run.t + 1e-3);
    partials_match_differences(e, where);
}

Test(me_jacobian, partials_of_hertz_in_free_flight_and_contact)
{
    test_run e;
    start(&e, hertz);
    const vi_model *M = &e.d.run.model;
    double d = 0.7 * vi_hertz_indentation(M->contact[0].K, M->body.W0);
    put(&e, VI_Mode_free, -d, 0.01, 0.0);
    partials_match_differences_now_and_later(&e, "hertz free");
    put(&e, VI_Mode_elastic, d, 0.01, 0.0);
    partials_match_differences_now_and_later(&e, "hertz elastic");
    put(&e, VI_Mode_elastic, 3.0 * M->contact[0].johnson.delta_Y, 0.01, 0.0); /* Hertz has no yield: the same law beyond delta_Y */
    partials_match_differences_now_and_later(&e, "hertz elastic beyond delta_Y");
    finish(&e);
}

Test(me_jacobian, partials_of_johnson_in_every_mode)
{
    setter laws[] = {johnson, johnson_continuous};
    for (int l = 0; l < 2; l++) {
        test_run e;
        start(&e, laws[l]);
        double dY = e.d.run.model.contact[0].johnson.delta_Y;
        put(&e, VI_Mode_elastic, 0.6 * dY, -0.01, 0.0);
        partials_match_differences_now_and_later(&e, "johnson elastic");
        /* continuous unloading returns the whole loading work below 4.61 delta_Y: W_plastic is 0 to rounding
         * there and its difference quotient noise (test_contact.c checks the curve's rates on both sides) */
        put(&e, VI_Mode_plastic, (l == 0 ? 1.7 : 5.0) * dY, -0.01, 0.0);
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
    test_run e;
    start(&e, johnson_moving);
    double dY = e.d.run.model.contact[0].johnson.delta_Y;
    put(&e, VI_Mode_elastic, 0.6 * dY, -0.01, 0.0);
    partials_match_differences_now_and_later(&e, "moving elastic");
    put(&e, VI_Mode_plastic, 1.7 * dY, -0.01, 0.0);
    partials_match_differences_now_and_later(&e, "moving plastic");
    finish(&e);
}

Test(me_jacobian, partials_of_lepp_in_every_mode)
{
    test_run e;
    start(&e, lepp);
    double dY = e.d.run.model.contact[0].johnson.delta_Y;
    put(&e, VI_Mode_elastic, 0.6 * dY, -0.01, 0.2 * dY);
    partials_match_differences_now_and_later(&e, "lepp elastic");
    put(&e, VI_Mode_plastic, 1.7 * dY, -0.01, 0.0);
    partials_match_differences_now_and_later(&e, "lepp plastic");
    put(&e, VI_Mode_free, 0.1 * dY, 0.01, 0.2 * dY);
    partials_match_differences_now_and_later(&e, "lepp free");
    finish(&e);
}

/* d(k_contact)/d(yC_in) = dk/ddelta, the second derivative of the force law (closed forms). */
static double stiffness_rate(test_run *e) { return vi_me_partial(e, VI_VR_k_contact, VI_VR_yC_in); }

Test(me_jacobian, stiffness_rate_at_the_ends_of_each_branch)
{
    test_run e;
    start(&e, hertz);
    double K = e.d.run.model.contact[0].K, dY = e.d.run.model.contact[0].johnson.delta_Y;
    put(&e, VI_Mode_elastic, 0.0, 0.0, 0.0); /* touching: F = K d^1.5 has F'' = 0.75 K/sqrt(d) -> its limit 0 is reported */
    cr_assert(stiffness_rate(&e) == 0.0, "hertz at delta = 0: %g", stiffness_rate(&e));
    put(&e, VI_Mode_elastic, -1e-9, 0.0, 0.0); /* a state beyond the contact surface before its event */
    cr_assert(stiffness_rate(&e) == 0.0, "hertz at delta < 0: %g", stiffness_rate(&e));
    put(&e, VI_Mode_elastic, 4.0 * dY, 0.0, 0.0);
    cr_assert(fabs(stiffness_rate(&e) - 0.75 * K / sqrt(4.0 * dY)) <= 1e-14 * 0.75 * K / sqrt(dY), "hertz beyond delta_Y");
    finish(&e);

    start(&e, johnson);
    const vi_johnson *J = &e.d.run.model.contact[0].johnson;
    put(&e, VI_Mode_elastic, 0.0, 0.0, 0.0);
    cr_assert(stiffness_rate(&e) == 0.0, "johnson at delta = 0: %g", stiffness_rate(&e));
    put(&e, VI_Mode_elastic, -1e-9, 0.0, 0.0);
    cr_assert(stiffness_rate(&e) == 0.0, "johnson at delta < 0: %g", stiffness_rate(&e));
    put(&e, VI_Mode_elastic, 1e-4 * J->delta_Y, 0.0, 0.0); /* just touching: F'' = 0.75 F_Y/(dY^2 sqrt(d/dY)) */
    double touching = 0.75 * J->F_Y / (J->delta_Y * J->delta_Y * sqrt(e.d.run.x[0] / J->delta_Y));
    cr_assert(fabs(stiffness_rate(&e) - touching) <= 1e-12 * touching, "johnson at 1e-4 delta_Y: %.17g, closed form %.17g",
              stiffness_rate(&e), touching);
    /* on the yield surface, still elastic: the elastic branch F = F_Y (d/dY)^1.5, F'' = 0.75 F_Y/dY^2 */
    put(&e, VI_Mode_elastic, J->delta_Y, 0.0, 0.0);
    double elastic = 0.75 * J->F_Y / (J->delta_Y * J->delta_Y);
    cr_assert(fabs(stiffness_rate(&e) - elastic) <= 1e-14 * elastic, "johnson at delta_Y: %.17g, closed form %.17g",
              stiffness_rate(&e), elastic);
    /* unloading at and below delta_f (the force is 0 there) */
    put(&e, VI_Mode_unload, 0.0, 0.0, 2.0 * dY);
    double df = e.d.run.model.contact[0].unload.delta_f;
    put(&e, VI_Mode_unload, df, 0.0, 2.0 * dY);
    cr_assert(e.d.run.x[0] == df, "delta %.17g is not delta_f %.17g", e.d.run.x[0], df);
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
    test_run e;
    start(&e, hertz);
    double K = e.d.run.model.contact[0].K, m = e.d.run.model.body.m, d = e.d.run.x[0];
    /* the platform rises by d/2 in continuous time: the stiffness is that at 1.5 d */
    e.d.in.yC_in = 0.5 * d;
    double k = 1.5 * K * sqrt(1.5 * d);
    cr_assert(fabs(vi_me_partial(&e, VI_VR_der_v, VI_VR_y) + k / m) <= 1e-12 * k / m, "der_v/y = %.17g, closed form %.17g",
              vi_me_partial(&e, VI_VR_der_v, VI_VR_y), -k / m);
    finish(&e);
}

Test(me_jacobian, partials_with_respect_to_parameters_are_zero)
{
    test_run e;
    start(&e, johnson);
    for (size_t i = 0; i < sizeof unknowns / sizeof *unknowns; i++) {
        cr_assert(vi_me_partial(&e, unknowns[i], VI_VR_m) == 0.0, "%s", vi_variable_table[unknowns[i]].name);
        cr_assert(vi_me_partial(&e, unknowns[i], VI_VR_k_contact) == 0.0, "%s", vi_variable_table[unknowns[i]].name);
    }
    finish(&e);
}

/* ---- the event iteration ----------------------------------------------------------------------- */

static void hertz_on_a_raised_platform(vi_parameters *p) { hertz(p), p->init = VI_Init_touching, p->v0 = 0.01; }

/* The platform at yC_in = 1.5 m (a = 0: it does not move), the mass at y, v, in `mode`. */
static void at(test_run *e, int mode, double y, double v)
{
    e->d.run.model.contact[0].mode = mode;
    double x[VI_ME_NSTATES] = {y, v};
    vi_me_set_states(&e->e, x);
    e->d.run.events.band[0] = e->d.run.events.band[1] = 0.0;
}

static vi_me_event update(test_run *e)
{
    vi_me_event ev;
    memset(&ev, 0x55, sizeof ev); /* every field is written */
    cr_assert(vi_me_event_update(&e->e, &ev) == 0, "%s", e->r.msg);
    return ev;
}

static void raised(test_run *e)
{
    memset(e, 0, sizeof *e);
    clear_log();
    test_run_init(e, capture, NULL);
    hertz_on_a_raised_platform(&e->d.par);
    e->d.in.yC_in = 1.5;
    cr_assert(vi_me_initialize(&e->e) == 0, "%s", e->r.msg);
}

Test(me_events, a_grazing_contact_is_snapped_and_its_guard_lifted_by_its_band)
{
    test_run e;
    raised(&e);
    /* free flight moving up, 0.1 um into the platform: within the band of the contact guard
     * (4 (rtol |y| + atol) = 6e-6 m): a located crossing, put onto the surface; the mass moves away,
     * the mode stays free, and the guard is lifted by the band until it has moved away */
    double y = 1.5 - 1e-7, v = 0.02, rtol = vi_contact_rtol(&e.d.par, e.d.tolerance); /* (the start had v0 = 0.01) */
    at(&e, VI_Mode_free, y, v);
    long events = e.d.run.events.n_events;
    clear_log();
    vi_me_event ev = update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_free && e.d.run.events.n_events == events + 1, "mode %d, %ld events", e.d.run.model.contact[0].mode, e.d.run.events.n_events);
    cr_assert(ev.states_changed == 1 && ev.another_pass == 0 && ev.terminate == 0 && ev.next_time_defined == 0);
    double x[VI_ME_NSTATES];
    vi_me_get_states(&e.e, x);
    cr_assert(x[0] == 1.5 && x[1] == v && e.d.run.x[0] == 0.0, "snapped to y = %.17g, delta = %g", x[0], e.d.run.x[0]);
    /* band, at the state snapped onto the surface (y = 1.5): 4 times the guard's change under
     * rtol |y| + atol, 256 times its change under one ulp of y (2^-52 for y in [1, 2); the platform
     * does not move and the guard does not depend on v) */
    double band = 4.0 * (rtol * x[0] + e.d.run.events.atol[0]) + 256.0 * 0x1p-52;
    cr_assert(fabs(e.d.run.events.band[0] - band) <= 1e-12 * band, "band %.17g, closed form %.17g", e.d.run.events.band[0], band);
    cr_assert(e.d.run.events.band[1] == 0.0, "the inactive guard has no band: %g", e.d.run.events.band[1]);
    double z[VI_ME_NINDICATORS];
    vi_me_indicators(&e.e, z);
    cr_assert(z[0] == e.d.run.events.band[0] && z[1] == 1.0, "indicators %g %g", z[0], z[1]);
    cr_assert(e.d.run.step_t0 == e.d.run.t && e.d.run.step_v0 == v, "the mean force starts anew at the event");
    char expected[256];
    snprintf(expected, sizeof expected, "event t=%.17g kind=guard guard=0 mode=0->0 delta=%.9g v=%.9g", 0.0, 0.0, v);
    cr_assert(strcmp(logged[VI_LOG_EVENTS], expected) == 0, "logged '%s'", logged[VI_LOG_EVENTS]);
    /* an update within the band fires nothing: the guard is disarmed */
    double xb[VI_ME_NSTATES] = {1.5 - 0.5 * band, v};
    vi_me_set_states(&e.e, xb);
    ev = update(&e);
    cr_assert(e.d.run.events.n_events == events + 1 && ev.states_changed == 0, "a disarmed guard fired: %ld events", e.d.run.events.n_events);
    /* a completed step re-arms it once it is above its band, not before */
    cr_assert(vi_me_completed_step(&e.e) == 0);
    cr_assert(e.d.run.events.band[0] > 0.0, "re-armed within its band");
    double xa[VI_ME_NSTATES] = {1.5 + 1.5 * band, v};
    vi_me_set_states(&e.e, xa);
    cr_assert(vi_me_completed_step(&e.e) == 0);
    cr_assert(e.d.run.events.band[0] == 0.0, "not re-armed above its band: %g", e.d.run.events.band[0]);
    /* exactly at its band it stays disarmed (1e-5 m above the platform: the guard is y - 1.5 exactly) */
    double xe[VI_ME_NSTATES] = {1.5 + 1e-5, v};
    vi_me_set_states(&e.e, xe);
    double G = xe[0] - 1.5;
    e.d.run.events.band[0] = G;
    cr_assert(vi_me_completed_step(&e.e) == 0);
    cr_assert(e.d.run.events.band[0] == G, "re-armed at its band");
    e.d.run.events.band[0] = nextafter(G, 0.0);
    cr_assert(vi_me_completed_step(&e.e) == 0);
    cr_assert(e.d.run.events.band[0] == 0.0, "not re-armed an ulp above its band");
    /* a platform input set in continuous time since the last call counts: it drops 1 mm away */
    vi_me_set_states(&e.e, xb);
    e.d.run.events.band[0] = band;
    e.d.in.yC_in = 1.5 - 1e-3;
    cr_assert(vi_me_completed_step(&e.e) == 0);
    cr_assert(e.d.run.events.band[0] == 0.0, "not re-armed after the platform moved away: %g", e.d.run.events.band[0]);
    finish(&e);
}

Test(me_events, a_grazing_turning_point_gets_the_band_of_the_velocity)
{
    /* Johnson loading plastically (P = 3e5 N: the load is above the force at 1.2 delta_Y), the rate
     * of delta 1e-8 m/s below zero: within the band of the turning-point guard delta' = yC' - v; the
     * holding force exceeds the load: it stays plastic, v is snapped onto yC' = 0, and the guard gets
     * the band of v there: 4 (rtol 0 + atol_v) + 256 ulp(0) */
    test_run e;
    memset(&e, 0, sizeof e);
    test_run_init(&e, capture, NULL);
    e.d.par.P = 3e5;
    cr_assert(vi_me_initialize(&e.e) == 0, "%s", e.r.msg);
    double dY = e.d.run.model.contact[0].johnson.delta_Y, v = 1e-8, rtol = vi_contact_rtol(&e.d.par, e.d.tolerance);
    put(&e, VI_Mode_plastic, 1.2 * dY, v, 0.0);
    vi_me_event ev = update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_plastic && e.d.run.x[1] == 0.0 && ev.states_changed == 1, "mode %d, v %g",
              e.d.run.model.contact[0].mode, e.d.run.x[1]);
    double band = 4.0 * (rtol * 0.0 + e.d.run.events.atol[1]) + 256.0 * nextafter(0.0, INFINITY);
    cr_assert(fabs(e.d.run.events.band[0] - band) <= 1e-12 * band, "band %.17g, closed form %.17g", e.d.run.events.band[0], band);
    finish(&e);
}

Test(me_events, a_state_beyond_the_band_takes_the_mode_of_the_state_as_it_is)
{
    test_run e;
    raised(&e);
    /* 10 um into the platform, moving down, beyond the band (6e-6 m): no located crossing but a state
     * the importer stepped to: elastic at the state as it is, not snapped */
    at(&e, VI_Mode_free, 1.5 - 1e-5, -0.01);
    cr_assert(vi_contact_outputs_of(&e, VI_OUT_ALL)->mode == VI_Mode_free);
    vi_me_event ev = update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_elastic && e.d.run.model.contact[0].n_impacts == 1, "mode %d", e.d.run.model.contact[0].mode);
    const vi_outputs *out = vi_contact_outputs_of(&e, VI_OUT_STATE); /* not those read before the event */
    cr_assert(out->mode == VI_Mode_elastic && out->n_impacts == 1 && out->contact == 1, "output mode %d", out->mode);
    cr_assert(ev.states_changed == 0 && e.d.run.x[0] == 1.5 - (1.5 - 1e-5), "delta %.17g", e.d.run.x[0]);
    cr_assert(e.d.run.events.band[0] == 0.0 && e.d.run.events.band[1] == 0.0, "a mode entered with its guards away from 0");
    finish(&e);
}

Test(me_events, guards_are_armed_at_zero_up_to_their_rounding_noise_and_no_further)
{
    test_run e;
    raised(&e);
    /* the touching start moving up: free flight with the contact guard at 0, lifted by its noise and
     * the band of the tolerance (those of Model Exchange, not the simulation's noise alone) */
    double y0 = 1.5, band0 = 256.0 * 0x1p-52 + 4.0 * (vi_contact_rtol(&e.d.par, e.d.tolerance) * y0 + e.d.run.events.atol[0]);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_free && e.d.me.y_me == y0);
    cr_assert(fabs(e.d.run.events.band[0] - band0) <= 1e-12 * band0, "initial band %.17g, closed form %.17g",
              e.d.run.events.band[0], band0);
    /* free flight 256 ulps of y above the platform: the contact guard equals its noise, 256 times its
     * change under one ulp of y (2^-52): lifted; 257 ulps: not */
    double rtol = vi_contact_rtol(&e.d.par, e.d.tolerance);
    for (int k = 256; k <= 257; k++) {
        double y = 1.5 + k * 0x1p-52;
        at(&e, VI_Mode_free, y, 0.01);
        vi_me_event ev = update(&e);
        cr_assert(ev.states_changed == 0 && e.d.run.model.contact[0].mode == VI_Mode_free);
        double band = k == 256 ? 256.0 * 0x1p-52 + 4.0 * (rtol * y + e.d.run.events.atol[0]) : 0.0;
        cr_assert(fabs(e.d.run.events.band[0] - band) <= 1e-12 * band, "%d ulps: band %.17g, closed form %.17g", k,
                  e.d.run.events.band[0], band);
        cr_assert(e.d.run.events.band[1] == 0.0);
    }
    /* a guard already lifted keeps its band */
    at(&e, VI_Mode_free, 1.5, 0.01);
    e.d.run.events.band[0] = 1e-9;
    update(&e);
    cr_assert(e.d.run.events.band[0] == 1e-9, "band %g", e.d.run.events.band[0]);
    finish(&e);
}

static void preloaded_stick(vi_parameters *p) { p->P = 3e5; }

Test(me_events, a_guard_exactly_at_zero_without_noise_is_lifted_by_the_least_normal_double)
{
    /* Johnson, paper unloading, P = 3e5 N: the static start is plastically pre-loaded and sticks with
     * F_hold = W = F_load(delta_c) exactly (no excitation: the stick guards do not move with t, y or v) */
    test_run e;
    start(&e, preloaded_stick);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_stick);
    double z[VI_ME_NINDICATORS], W = e.d.run.model.body.W0;
    vi_me_indicators(&e.e, z);
    cr_assert(vi_johnson_load(&e.d.run.model.contact[0].johnson, e.d.run.model.contact[0].unload.delta_c) == W, "not exactly on the load surface");
    cr_assert(z[0] == DBL_MIN, "load guard %g", z[0]);
    double g1 = W - vi_unload_force(&e.d.run.model.contact[0].unload, e.d.run.model.contact[0].unload.delta_c);
    cr_assert(z[1] == g1, "unload guard %.17g, closed form %.17g", z[1], g1);
    finish(&e);
}

Test(me_events, an_input_jump_onto_the_contact_surface_is_an_event_of_the_new_mode)
{
    /* free flight moving down; the platform input jumps (set in event mode) to the mass: delta = 0
     * exactly with delta' > 0: the mode becomes elastic, logged as an input event; its contact guard,
     * at zero, is armed with a band of its own (the bands of the mode left do not apply), so no state
     * event follows in the same pass */
    test_run e;
    raised(&e);
    at(&e, VI_Mode_free, 1.5 + 1e-6, -0.01);
    long events = e.d.run.events.n_events;
    clear_log();
    e.d.in.yC_in = 1.5 + 1e-6;
    e.d.run.inputs_changed = 1;
    e.d.run.events.band[0] = 1.0; /* a band of free flight: not the elastic guard's */
    vi_me_event ev = update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_elastic && e.d.run.x[0] == 0.0, "mode %d, delta %g", e.d.run.model.contact[0].mode, e.d.run.x[0]);
    cr_assert(e.d.run.events.n_events == events, "%ld state events", e.d.run.events.n_events - events);
    cr_assert(e.d.run.inputs_changed == 0 && ev.another_pass == 0 && ev.terminate == 0);
    double x[VI_ME_NSTATES];
    vi_me_get_states(&e.e, x);
    cr_assert(x[0] == 1.5 + 1e-6 && x[1] == -0.01);
    cr_assert(n_logged[VI_LOG_EVENTS] == 1, "%d event messages", n_logged[VI_LOG_EVENTS]);
    char expected[256];
    snprintf(expected, sizeof expected, "event t=%.17g kind=input mode=0->1", 0.0);
    cr_assert(strcmp(logged[VI_LOG_EVENTS], expected) == 0, "logged '%s'", logged[VI_LOG_EVENTS]);
    cr_assert(e.d.run.events.band[0] > 0.0 && e.d.run.events.band[0] < 1e-4, "the new mode's guard at 0 is armed afresh: %g",
              e.d.run.events.band[0]);
    finish(&e);
}

Test(me_events, an_input_change_in_event_mode_is_logged_when_it_changes_the_mode)
{
    test_run e;
    raised(&e);
    at(&e, VI_Mode_free, 1.5 + 1e-3, -0.01);
    clear_log();
    e.d.in.yC_in = 1.5 + 2e-3; /* into the mass: contact */
    e.d.run.inputs_changed = 1;
    update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_elastic && e.d.run.model.yC_in.u == 1.5 + 2e-3 && e.d.run.model.yC_in.du == 0.0);
    char expected[256];
    snprintf(expected, sizeof expected, "event t=%.17g kind=input mode=0->1", 0.0);
    cr_assert(strcmp(logged[VI_LOG_EVENTS], expected) == 0, "logged '%s'", logged[VI_LOG_EVENTS]);
    double x[VI_ME_NSTATES];
    vi_me_get_states(&e.e, x);
    cr_assert(x[0] == 1.5 + 1e-3 && fabs(e.d.run.x[0] - 1e-3) <= 1e-15, "the mass stays: y %.17g, delta %g", x[0], e.d.run.x[0]);
    /* a force input that leaves the mode: nothing logged */
    clear_log();
    e.d.in.F_ext = 10.0;
    e.d.run.inputs_changed = 1;
    update(&e);
    cr_assert(e.d.run.model.F_ext.u == 10.0 && e.d.run.model.F_ext.t == e.d.run.t && n_logged[VI_LOG_EVENTS] == 0, "logged '%s'",
              logged[VI_LOG_EVENTS]);
    finish(&e);
}

static void late_start(vi_parameters *p) { hertz(p), p->init = VI_Init_touching, p->v0 = 0.01; }

Test(me_events, events_accumulating_at_one_instant_terminate_at_the_64th)
{
    test_run e;
    memset(&e, 0, sizeof e);
    test_run_init(&e, capture, NULL);
    late_start(&e.d.par);
    e.d.t_start = 10.0; /* the count starts at the start time, not at 0 */
    e.d.in.yC_in = 1.5;
    cr_assert(vi_me_initialize(&e.e) == 0, "%s", e.r.msg);
    for (int i = 1; i <= VI_ZENO_EVENTS; i++) {
        at(&e, VI_Mode_free, 1.5 - 1e-5, -0.01); /* beyond the contact surface: an event each time */
        vi_me_event ev = update(&e);
        cr_assert(ev.terminate == (i == VI_ZENO_EVENTS), "event %d: terminate %d", i, ev.terminate);
    }
    char expected[512];
    snprintf(expected, sizeof expected, "events accumulate at t = %.17g s (Zeno): %d events each within %g ulps of time "
             "of the one before, the last on guard 0 of mode 0 (contact); stopped there. Each mode chosen was left again "
             "at once: the motion the guards see leaves it. Where the platform moves through yC_in, pass its velocity "
             "(velocity_input = true, vC_in); else tighten rtol", 10.0, VI_ZENO_EVENTS, VI_ZENO_ULPS);
    cr_assert(strcmp(e.r.msg, expected) == 0, "message '%s'", e.r.msg);
    /* later, at t = 20 s: the first event there is far from the last one (t = 10 s) and counts 0, the
     * next 64 count 1 ... 64 */
    vi_me_set_time(&e.e, 20.0);
    for (int i = 0; i <= VI_ZENO_EVENTS; i++) {
        at(&e, VI_Mode_free, 1.5 - 1e-5, -0.01);
        vi_me_event ev = update(&e);
        cr_assert(ev.terminate == (i == VI_ZENO_EVENTS), "event %d at 20 s: terminate %d", i, ev.terminate);
    }
    finish(&e);
}

/* ---- initialization, states, inputs ------------------------------------------------------------- */

static void hertz_raised_with_rates(vi_parameters *p) { hertz(p); }

Test(me_states, initialization_logs_the_scales_and_the_initial_state_in_closed_form)
{
    test_run e;
    memset(&e, 0, sizeof e);
    clear_log();
    test_run_init(&e, capture, NULL);
    hertz_raised_with_rates(&e.d.par);
    e.d.in.yC_in = 0.25, e.d.in.F_ext = 100.0;
    e.d.run.events.zeno = 50, e.d.run.events.band[0] = e.d.run.events.band[1] = 1.0; /* left from an earlier run */
    cr_assert(vi_me_initialize(&e.e) == 0, "%s", e.r.msg);
    const vi_model *M = &e.d.run.model;
    /* Hertz at rest under W = P + m g - F_ext: delta = (W/K)^(2/3) = L, V = L sqrt(1.5 K sqrt(L)/m) */
    double E = 1.0 / (2.0 * (1.0 - 0.09) / 2.1e11), K = 4.0 / 3.0 * E * sqrt(0.475);
    double W = 40000.0 + 407.747 * 9.81 - 100.0, L = pow(W / K, 2.0 / 3.0), V = L * sqrt(1.5 * K * sqrt(L) / 407.747);
    double nl, nv, nw, delta, v;
    int mode, n = 0;
    const char *text = strstr(logged[VI_LOG_SOLVER], "Model Exchange");
    cr_assert(text != NULL, "logged '%s'", logged[VI_LOG_SOLVER]);
    cr_assert(sscanf(text, "Model Exchange: the importer integrates y, v and W_damping (nominals %lg m, %lg m/s, %lg J); "
                           "initial mode %d, delta = %lg m, v = %lg m/s%n", &nl, &nv, &nw, &mode, &delta, &v, &n) == 6 && n > 0,
              "logged '%s'", text);
    cr_assert(fabs(nl - L) <= 1e-5 * L && fabs(nv - V) <= 1e-5 * V, "nominals %g %g, closed form %g %g", nl, nv, L, V);
    cr_assert(fabs(nw - 407.747 * V * V) <= 1e-5 * nw, "nominal %g, closed form m V^2 = %g", nw, 407.747 * V * V);
    cr_assert(mode == VI_Mode_elastic && fabs(delta - L) <= 1e-8 * L && v == 0.0, "mode %d, delta %.9g, v %g", mode, delta, v);
    double x[VI_ME_NSTATES], z[VI_ME_NINDICATORS], dx[VI_ME_NSTATES], nominal[VI_ME_NSTATES];
    vi_me_get_states(&e.e, x);
    cr_assert(fabs(x[0] - (0.25 - L)) <= 1e-15 && x[1] == 0.0, "y = %.17g, closed form %.17g", x[0], 0.25 - L);
    vi_me_nominals(&e.e, nominal);
    cr_assert(fabs(nominal[0] - L) <= 1e-12 * L && fabs(nominal[1] - V) <= 1e-12 * V, "nominals %g %g", nominal[0], nominal[1]);
    vi_me_indicators(&e.e, z); /* the guards, no band */
    cr_assert(z[0] == e.d.run.x[0] && z[1] == 1.0, "indicators %g %g", z[0], z[1]);
    vi_me_derivatives(&e.e, dx);
    cr_assert(dx[0] == 0.0 && fabs(dx[1]) <= 1e-9, "at rest: %g %g", dx[0], dx[1]);
    cr_assert(M->F_ext.u == 100.0 && vi_contact_outputs_of(&e, VI_OUT_ALL)->yC == 0.25);
    /* the Zeno count starts afresh */
    at(&e, VI_Mode_free, 0.25 - 1e-5, -0.01);
    for (int i = 1; i < VI_ZENO_EVENTS; i++) {
        at(&e, VI_Mode_free, 0.25 - 1e-5, -0.01);
        cr_assert(update(&e).terminate == 0, "terminated at event %d", i);
    }
    finish(&e);
}

Test(me_states, inputs_are_held_at_their_values_from_the_initialization)
{
    /* input rates set before (as for co-simulation): Model Exchange passes values only */
    test_run e;
    memset(&e, 0, sizeof e);
    test_run_init(&e, capture, NULL);
    hertz(&e.d.par);
    e.d.in.yC_in = 0.25, e.d.in.F_ext = 100.0;
    e.d.din.yC_in = 1.0, e.d.din.F_ext = 1e3;
    cr_assert(vi_me_initialize(&e.e) == 0, "%s", e.r.msg);
    const vi_model *M = &e.d.run.model;
    double dx[VI_ME_NSTATES], dx1[VI_ME_NSTATES];
    vi_me_derivatives(&e.e, dx);
    vi_me_set_time(&e.e, 1e-3); /* 1 ms later neither the platform nor the force has moved */
    vi_me_derivatives(&e.e, dx1);
    cr_assert(M->yC_in.du == 0.0 && M->F_ext.du == 0.0 && dx1[0] == dx[0] && dx1[1] == dx[1], "the inputs moved");
    cr_assert(M->yC_in.u == 0.25 && M->F_ext.u == 100.0 && vi_contact_outputs_of(&e, VI_OUT_ALL)->yC == 0.25);
    finish(&e);
}

Test(me_states, initialization_fails_with_the_simulation)
{
    test_run e;
    memset(&e, 0, sizeof e);
    test_run_init(&e, capture, NULL);
    e.d.par.R1 = 0.0; /* two planes */
    cr_assert(vi_me_initialize(&e.e) == -1);
    cr_assert(e.e.active == 0 && strstr(e.r.msg, "radius") != NULL, "%s", e.r.msg);
    finish(&e);
}

Test(me_states, a_sync_without_a_change_of_input_leaves_the_model_as_it_is)
{
    test_run e;
    start(&e, johnson);
    vi_model M0 = e.d.run.model;
    vi_me_set_time(&e.e, 1e-3);
    double dx[VI_ME_NSTATES];
    vi_me_derivatives(&e.e, dx);
    cr_assert(memcmp(&M0, &e.d.run.model, sizeof M0) == 0, "the model changed (input ramps restarted?)");
    cr_assert(e.d.run.t == 1e-3);
    finish(&e);
}

Test(me_states, continuous_inputs_act_at_once_each_alone)
{
    test_run e;
    start(&e, hertz);
    double y = e.d.me.y_me, t = 2e-3;
    vi_me_set_time(&e.e, t);
    /* the force alone */
    e.d.in.F_ext = 50.0;
    const vi_outputs *out = vi_contact_outputs_of(&e, VI_OUT_ALL);
    cr_assert(e.d.run.model.F_ext.u == 50.0 && e.d.run.model.F_ext.du == 0.0 && e.d.run.model.F_ext.t == t, "F_ext ramp");
    double F = out->F, W = e.d.run.model.body.W0 - 50.0;
    cr_assert(fabs(out->der_v - (F - W) / e.d.run.model.body.m) <= 1e-12 * W / e.d.run.model.body.m, "der_v %g", out->der_v);
    /* the platform alone: the mass stays, delta moves with the platform */
    e.d.in.yC_in = 1e-6;
    out = vi_contact_outputs_of(&e, VI_OUT_ALL);
    cr_assert(e.d.run.model.yC_in.u == 1e-6 && e.d.run.model.yC_in.du == 0.0 && e.d.run.model.yC_in.t == t && e.d.me.y_me == y);
    cr_assert(out->delta == 1e-6 - y && out->yC == 1e-6, "delta %.17g, closed form %.17g", out->delta, 1e-6 - y);
    /* a ramp restored from co-simulation (a rate, the same value): Model Exchange holds the value */
    e.d.run.model.yC_in.du = 1.0;
    vi_me_set_time(&e.e, t);
    vi_contact_outputs_of(&e, 0);
    cr_assert(e.d.run.model.yC_in.du == 0.0 && e.d.run.model.yC_in.u == 1e-6, "yC_in ramp kept its rate");
    e.d.run.model.F_ext.du = 1.0;
    vi_me_set_time(&e.e, t);
    vi_contact_outputs_of(&e, 0);
    cr_assert(e.d.run.model.F_ext.du == 0.0 && e.d.run.model.F_ext.u == 50.0, "F_ext ramp kept its rate");
    finish(&e);
}

/* A plastic motion at 1.7 delta_Y of `law` (memory written down at 1.2 delta_Y where it started to
 * flow), the platform moved through yC_in without its velocity: an evaluation at a trial point 1 us on
 * (the platform 0.2 delta_Y up) writes nothing down; a completed step there (the rate of yC_in is then an
 * estimate) does, and then the platform dropping back (in continuous time) leaves the memory outputs
 * where they were: they never decrease. */
static void memory_is_written_at_completed_steps(setter law)
{
    test_run e;
    start(&e, law);
    vi_model *M = &e.d.run.model;
    int johnson_law = M->contact[0].law == VI_ContactModel_johnson;
    double dY = M->contact[0].johnson.delta_Y, d = 1.7 * dY;
    put(&e, VI_Mode_plastic, d, -0.01, 0.0);
    d = e.d.run.x[0];
    if (johnson_law) M->contact[0].unload = vi_johnson_unload_curve(&M->contact[0].johnson, M->contact[0].unloading, 1.2 * dY);
    else M->contact[0].delta_p = 0.2 * dY;
    e.d.in.yC_in = 0.2 * dY; /* a trial point */
    vi_me_set_time(&e.e, 1e-6);
    d = vi_contact_outputs_of(&e, VI_OUT_ALL)->delta;
    cr_assert(johnson_law ? M->contact[0].unload.delta_c == 1.2 * dY : M->contact[0].delta_p == 0.2 * dY, "a trial point wrote the memory down");
    cr_assert(vi_me_completed_step(&e.e) == 0);
    cr_assert(johnson_law ? M->contact[0].unload.delta_c == d : M->contact[0].delta_p == d - dY, "the completed step at %.17g wrote nothing", d);
    const vi_outputs *out = vi_contact_outputs_of(&e, VI_OUT_ALL);
    double dc = out->delta_c, dp = out->delta_p, W = out->W_plastic;
    e.d.in.yC_in = -0.2 * dY;
    vi_me_set_time(&e.e, 2e-6);
    out = vi_contact_outputs_of(&e, VI_OUT_ALL);
    cr_assert(out->delta_c == dc && out->delta_p == dp && out->W_plastic == W, "the memory outputs moved back");
    finish(&e);
}

Test(me_states, the_plastic_memory_is_written_down_at_completed_steps_and_never_decreases)
{
    memory_is_written_at_completed_steps(johnson);
    memory_is_written_at_completed_steps(lepp);
}

Test(me_states, co_simulation_outputs_are_the_simulations_own)
{
    /* an instance not initialized for Model Exchange (co-simulation): reading outputs through the
     * Model Exchange functions neither moves the state nor restarts the output cache */
    test_run e;
    memset(&e, 0, sizeof e);
    test_run_init(&e, capture, NULL);
    hertz(&e.d.par);
    cr_assert(vi_sim_initialize(&e.s) == 0, "%s", e.r.msg);
    double d = e.d.run.x[0], x[VI_ME_NSTATES];
    cr_assert(d > 0.0);
    vi_me_get_states(&e.e, x); /* before: the initial state prepared, y = yC - delta */
    cr_assert(x[0] == -d && x[1] == 0.0, "y %.17g", x[0]);
    const vi_outputs *out = vi_contact_outputs_of(&e, VI_OUT_STATE);
    cr_assert(out->delta == d && e.d.run.x[0] == d, "delta %g", out->delta);
    cr_assert(e.r.out_valid & VI_OUT_STATE);
    vi_me_set_time(&e.e, 0.0);
    cr_assert(e.r.out_valid & VI_OUT_STATE, "the cache was cleared");
    finish(&e);
}

Test(me_states, states_set_are_those_read_and_the_outputs_follow)
{
    test_run e;
    start(&e, hertz);
    const vi_outputs *out = vi_contact_outputs_of(&e, VI_OUT_ALL);
    double K = e.d.run.model.contact[0].K, m = e.d.run.model.body.m, W = e.d.run.model.body.W0;
    double x[VI_ME_NSTATES] = {-3e-5, -0.02}, r[VI_ME_NSTATES], dx[VI_ME_NSTATES];
    vi_me_set_states(&e.e, x);
    vi_me_get_states(&e.e, r);
    cr_assert(r[0] == x[0] && r[1] == x[1], "states %g %g", r[0], r[1]);
    out = vi_contact_outputs_of(&e, VI_OUT_ALL); /* not the cached outputs of before */
    cr_assert(out->delta == 3e-5 && out->v == -0.02 && out->y == -3e-5, "delta %g v %g", out->delta, out->v);
    double F = K * 3e-5 * sqrt(3e-5);
    cr_assert(fabs(out->F - F) <= 1e-12 * F, "F %g, closed form %g", out->F, F);
    cr_assert(out->der_y == -0.02 && fabs(out->der_v - (F - W) / m) <= 1e-12 * W / m, "der %g %g", out->der_y, out->der_v);
    vi_me_derivatives(&e.e, dx);
    cr_assert(dx[0] == -0.02 && dx[1] == out->der_v, "derivatives %g %g", dx[0], dx[1]);
    /* the derivatives group is recomputed after a change of state */
    x[1] = 0.03;
    vi_me_set_states(&e.e, x);
    cr_assert(vi_contact_outputs_of(&e, VI_OUT_DERIVATIVES)->der_y == 0.03);
    finish(&e);
}

/* ---- time events: kinks of a rolling profile and its end ----------------------------------------- */

Test(me_events, kinks_and_the_end_of_the_profile_are_time_events)
{
    /* Hertz without load on a V-shaped profile rolled at 1 m/s from x = -0.01 m: the platform falls
     * until the kink at x = 0 (t = 0.01 s), then rises into the mass; the table ends at x = 10 m */
    char path[64];
    snprintf(path, sizeof path, "/tmp/vi_test_me_profile_%d.txt", (int)getpid());
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL);
    fprintf(f, "-10 1e-3\n0 0\n10 1e-3\n");
    fclose(f);
    test_run e;
    memset(&e, 0, sizeof e);
    clear_log();
    test_run_init(&e, capture, NULL);
    hertz(&e.d.par);
    e.d.par.P = 0.0, e.d.par.g = 0.0;
    snprintf(e.d.par.profile_file, sizeof e.d.par.profile_file, "%s", path);
    e.d.par.V = 1.0, e.d.par.x0 = -0.01;
    int rc = vi_me_initialize(&e.e);
    remove(path);
    cr_assert(rc == 0, "%s", e.r.msg);
    const vi_model *M = &e.d.run.model;
    char why[512];
    double tk = vi_model_next_breakpoint(M, 0.0), end = vi_model_rolling_limit(M, why, sizeof why);
    cr_assert(fabs(tk - 0.01) <= 1e-15 && fabs(end - 10.01) <= 1e-12, "kink at %.17g s, end at %.17g s", tk, end);
    vi_me_event ev = update(&e);
    cr_assert(ev.next_time_defined == 1 && ev.next_time == tk && ev.terminate == 0, "next time %d %.17g", ev.next_time_defined,
              ev.next_time);
    /* the mass follows the platform down to the kink (touching, at its velocity) */
    double dyC, v = -1e-4;
    vi_model_platform(M, tk, &dyC, NULL);
    cr_assert(fabs(dyC + v) <= 1e-15, "platform velocity after the kink %g", dyC);
    vi_me_set_time(&e.e, nextafter(tk, 0.0));
    cr_assert(vi_me_completed_step(&e.e) == 0, "an event before the kink");
    vi_me_set_time(&e.e, tk);
    double x[VI_ME_NSTATES] = {vi_model_platform(M, tk, NULL, NULL), v};
    vi_me_set_states(&e.e, x);
    cr_assert(vi_me_completed_step(&e.e) == 1, "the kink was stepped onto: an event is due");
    clear_log();
    ev = update(&e);
    cr_assert(M->contact[0].mode == VI_Mode_elastic && ev.terminate == 0, "mode %d after the kink", M->contact[0].mode);
    char expected[128];
    snprintf(expected, sizeof expected, "event t=%.17g kind=kink mode=0->1\n", tk);
    cr_assert(strncmp(history, expected, strlen(expected)) == 0, "logged '%s'", history);
    cr_assert(ev.next_time_defined == 1 && ev.next_time == end, "next time %d %.17g", ev.next_time_defined, ev.next_time);
    cr_assert(vi_me_completed_step(&e.e) == 0, "the kink is behind");
    /* the end of the table: an event due when stepped onto, and the run terminates there */
    vi_me_set_time(&e.e, nextafter(end, 0.0));
    cr_assert(vi_me_completed_step(&e.e) == 0, "an event before the end");
    vi_me_set_time(&e.e, end);
    cr_assert(vi_me_completed_step(&e.e) == 1, "the end was stepped onto: an event is due");
    ev = update(&e);
    cr_assert(ev.terminate == 1 && strstr(e.r.msg, "reaches the end of the profile") != NULL, "terminate %d: %s", ev.terminate,
              e.r.msg);
    cr_assert(ev.next_time_defined == 0 && ev.another_pass == 0 && ev.states_changed == 0);
    finish(&e);
}

Test(me_states, checkpoint_and_restore_carry_the_state_y)
{
    test_run e;
    start(&e, johnson);
    double dY = e.d.run.model.contact[0].johnson.delta_Y;
    put(&e, VI_Mode_plastic, 1.5 * dY, -0.01, 0.0);
    e.d.run.model.contact[0].unload = vi_johnson_unload_curve(&e.d.run.model.contact[0].johnson, e.d.run.model.contact[0].unloading, 1.2 * dY); /* as where it started to flow */
    vi_me_set_time(&e.e, 1e-3);
    cr_assert(vi_me_checkpoint(&e.e) == 0, "%s", e.r.msg);
    /* taking a state changes nothing that follows: the memory stays where it was written down, and the
     * output delta_c is the indentation reached (delta_c = delta while loading) */
    cr_assert(e.d.run.model.contact[0].unload.delta_c == 1.2 * dY, "delta_c %.17g written down at %.17g", e.d.run.model.contact[0].unload.delta_c, 1.2 * dY);
    cr_assert(vi_contact_outputs_of(&e, VI_OUT_ALL)->delta_c == e.d.run.x[0]);
    vi_contact_data saved = e.d;
    double y = e.d.me.y_me;
    double x[VI_ME_NSTATES] = {y + 1e-6, 0.02};
    vi_me_set_states(&e.e, x);
    e.d.run.events.zeno = 7;
    e.d = saved;
    cr_assert(vi_me_restore(&e.e, 1) == 0, "%s", e.r.msg);
    cr_assert(e.e.active == 1 && e.d.run.events.zeno == 0 && e.d.me.y_me == y, "restored y %.17g, saved %.17g", e.d.me.y_me, y);
    vi_me_get_states(&e.e, x);
    cr_assert(x[0] == y && x[1] == -0.01);
    /* a state from before initialization: not running, the states are the initial ones prepared */
    cr_assert(vi_me_restore(&e.e, 0) == 0, "%s", e.r.msg);
    cr_assert(e.e.active == 0);
    finish(&e);
}

Test(me_states, nominals_are_one_before_initialization)
{
    test_run e;
    memset(&e, 0, sizeof e);
    test_run_init(&e, capture, NULL);
    double nominal[VI_ME_NSTATES];
    vi_me_nominals(&e.e, nominal);
    cr_assert(nominal[0] == 1.0 && nominal[1] == 1.0, "%g %g", nominal[0], nominal[1]);
    /* the importer's tolerance wins over rtol: nominal = atol / tolerance */
    e.d.tolerance = 1e-4;
    cr_assert(vi_me_initialize(&e.e) == 0, "%s", e.r.msg);
    vi_me_nominals(&e.e, nominal);
    cr_assert(fabs(nominal[0] - e.d.run.events.atol[0] / 1e-4) <= 1e-15 * nominal[0], "%g", nominal[0]);
    e.d.run.events.atol[1] = 0.0; /* no scale: 1 */
    vi_me_nominals(&e.e, nominal);
    cr_assert(nominal[1] == 1.0, "%g", nominal[1]);
    finish(&e);
}

static void hertz_dop853(vi_parameters *p) { hertz(p), p->solver = VI_Solver_dop853; }

Test(me_states, a_checkpoint_makes_the_saved_state_whole)
{
    /* Model Exchange makes no solver (the importer integrates): the Co-Simulation driver's data stays
     * as it was bound, and a saved state is the run's and the driver's */
    test_run e;
    start(&e, hertz_dop853);
    cr_assert(e.s.solver == NULL, "Model Exchange made a solver");
    vi_me_set_time(&e.e, 1e-3);
    char msg[512];
    /* an input set in continuous time since the last call is taken before the copy */
    e.d.in.yC_in = 1e-6;
    double y = e.d.me.y_me;
    cr_assert(vi_me_checkpoint(&e.e) == 0, "%s", e.r.msg);
    cr_assert(vi_contact_state_check(&e.d, 1, 1, msg, sizeof msg) == 0, "%s", msg);
    cr_assert(e.d.run.x[0] == 1e-6 - y, "delta %.17g, closed form %.17g", e.d.run.x[0], 1e-6 - y);
    cr_assert(e.s.solver == NULL && e.d.cs.ode.h == 0.0, "Model Exchange made or ran a solver");
    /* a state where the force overflows: nothing is restarted, the state is saved as it is */
    double x[VI_ME_NSTATES] = {-1e200, 0.0};
    vi_me_set_states(&e.e, x);
    cr_assert(vi_me_checkpoint(&e.e) == 0, "%s", e.r.msg);
    cr_assert(e.d.me.y_me == -1e200);
    /* a state naming a profile that cannot be loaded is refused; the instance stays as it was */
    snprintf(e.d.par.profile_file, sizeof e.d.par.profile_file, "/nonexistent/vi_test_me_profile.txt");
    e.d.par.V = 1.0;
    cr_assert(vi_me_restore(&e.e, 0) == -1);
    cr_assert(e.e.active == 1 && e.d.me.y_me == x[0], "the instance changed");
    finish(&e);
}

Test(me_events, the_band_counts_one_ulp_of_y_upwards)
{
    /* LEPP touching its permanent set delta_p = 2^-14 m exactly (y = -2^-14: the platform at 0), moving
     * in: the contact guard delta - delta_p is 0 and fires, the state stays elastic (grazing). One ulp of
     * y upwards is 2^-67 (the next double towards 0), which moves delta to 2^-14 - 2^-67 exactly: the
     * guard moves by 2^-67 (downwards delta would round back to 2^-14, a move of 0) */
    test_run e;
    start(&e, lepp);
    double d = 0x1p-14, rtol = vi_contact_rtol(&e.d.par, e.d.tolerance);
    put(&e, VI_Mode_elastic, d, -0.01, d);
    cr_assert(e.d.me.y_me == -d && e.d.run.x[0] == d && e.d.run.model.contact[0].delta_p == d);
    update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_elastic);
    double band = 4.0 * (rtol * d + e.d.run.events.atol[0]) + 256.0 * 0x1p-67;
    cr_assert(fabs(e.d.run.events.band[0] - band) <= 1e-11 * band, "band %.17g, closed form %.17g", e.d.run.events.band[0], band);
    finish(&e);
}

Test(me_events, the_band_counts_one_ulp_of_v_upwards)
{
    /* Johnson loading plastically on a slope rolled at 1 m/s: the platform velocity is -2^-7 m/s exactly
     * (a straight profile, no excitation: it does not move with t). The mass at v = -2^-7: the turning-
     * point guard yC' - v is 0 and fires; the holding force exceeds the load: it stays plastic. One ulp
     * of v upwards is 2^-60 (towards 0): the guard moves by 2^-60 */
    char path[64];
    snprintf(path, sizeof path, "/tmp/vi_test_me_slope_%d.txt", (int)getpid());
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL);
    fprintf(f, "0 0\n8 -0.0625\n");
    fclose(f);
    test_run e;
    memset(&e, 0, sizeof e);
    test_run_init(&e, capture, NULL);
    e.d.par.P = 3e5;
    snprintf(e.d.par.profile_file, sizeof e.d.par.profile_file, "%s", path);
    e.d.par.V = 1.0, e.d.par.x0 = 1.0;
    int rc = vi_me_initialize(&e.e);
    remove(path);
    cr_assert(rc == 0, "%s", e.r.msg);
    double dyC, v = -0x1p-7, rtol = vi_contact_rtol(&e.d.par, e.d.tolerance);
    vi_model_platform(&e.d.run.model, 0.0, &dyC, NULL);
    cr_assert(dyC == v, "platform velocity %.17g", dyC);
    put(&e, VI_Mode_plastic, 1.2 * e.d.run.model.contact[0].johnson.delta_Y, v, 0.0);
    update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_plastic);
    double band = 4.0 * (rtol * -v + e.d.run.events.atol[1]) + 256.0 * 0x1p-60;
    cr_assert(fabs(e.d.run.events.band[0] - band) <= 5e-11 * band, "band %.17g, closed form %.17g", e.d.run.events.band[0], band);
    finish(&e);
}

Test(me_states, a_completed_step_starts_the_mean_force_anew)
{
    test_run e;
    start(&e, hertz);
    double x[VI_ME_NSTATES] = {e.d.me.y_me, 0.02};
    vi_me_set_states(&e.e, x);
    vi_me_set_time(&e.e, 1e-3);
    double m = e.d.run.model.body.m, W = e.d.run.model.body.W0;
    /* over the step from 0: F_mean = m (v - v0)/h + W with v0 = 0 */
    double Fm = vi_contact_outputs_of(&e, VI_OUT_MEAN)->F_mean;
    cr_assert(fabs(Fm - (m * 0.02 / 1e-3 + W)) <= 1e-12 * W, "F_mean %.17g", Fm);
    cr_assert(vi_me_completed_step(&e.e) == 0);
    cr_assert(e.d.run.step_t0 == 1e-3 && e.d.run.step_v0 == 0.02, "step start %g %g", e.d.run.step_t0, e.d.run.step_v0);
    vi_me_set_time(&e.e, 2e-3);
    x[1] = 0.03;
    vi_me_set_states(&e.e, x);
    Fm = vi_contact_outputs_of(&e, VI_OUT_MEAN)->F_mean;
    cr_assert(fabs(Fm - (m * 0.01 / 1e-3 + W)) <= 1e-12 * W, "F_mean %.17g", Fm);
    finish(&e);
}

Test(me_states, inputs_set_after_the_last_event_pass_act_when_continuous_time_begins)
{
    test_run e;
    start(&e, hertz);
    double y = e.d.me.y_me;
    e.d.in.yC_in = 2e-6;
    e.d.run.inputs_changed = 1; /* set in event mode: they wait for the event iteration ... */
    vi_me_set_time(&e.e, 0.0);
    cr_assert(e.d.run.model.yC_in.u == 0.0, "taken in event mode");
    vi_me_enter_continuous(&e.e); /* ... or act at once when continuous time begins */
    cr_assert(e.d.run.inputs_changed == 0 && e.d.run.model.yC_in.u == 2e-6 && e.d.run.x[0] == 2e-6 - y, "delta %g", e.d.run.x[0]);
    finish(&e);
}

Test(me_events, an_input_set_in_continuous_time_is_taken_by_the_event_iteration)
{
    test_run e;
    raised(&e);
    at(&e, VI_Mode_free, 1.5 + 1e-3, -0.01);
    e.d.in.yC_in = 1.5 + 2e-3; /* into the mass, set in continuous time (no call since) */
    vi_me_event ev = update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_elastic && e.d.run.model.yC_in.u == 1.5 + 2e-3, "mode %d", e.d.run.model.contact[0].mode);
    cr_assert(ev.states_changed == 0 && fabs(e.d.run.x[0] - 1e-3) <= 1e-15, "delta %g", e.d.run.x[0]);
    finish(&e);
}

Test(me_events, a_stick_guard_that_fires_exactly_at_zero_is_lifted_by_the_least_normal_double)
{
    /* the pre-loaded stick start with F_hold = F_load(delta_c) exactly (no excitation): with its band
     * cleared the load guard fires at 0; the holding force does not exceed the load (no rate to break
     * the tie): it stays in stick, the guard lifted by DBL_MIN (its noise and tolerance band are 0) */
    test_run e;
    start(&e, preloaded_stick);
    e.d.run.events.band[0] = 0.0;
    long events = e.d.run.events.n_events;
    vi_me_event ev = update(&e);
    cr_assert(e.d.run.model.contact[0].mode == VI_Mode_stick && e.d.run.events.n_events == events + 1, "mode %d", e.d.run.model.contact[0].mode);
    cr_assert(e.d.run.events.band[0] == DBL_MIN && ev.another_pass == 0, "band %g, another pass %d", e.d.run.events.band[0],
              ev.another_pass);
    finish(&e);
}

Test(me_states, each_call_writes_its_arrays_and_nothing_beyond)
{
    /* (dop853 restarted at 1 ms: the simulation's data after the bands is not all zero) */
    test_run e;
    start(&e, hertz_dop853);
    vi_me_set_time(&e.e, 1e-3);
    cr_assert(vi_me_checkpoint(&e.e) == 0, "%s", e.r.msg);
    double a[VI_ME_NSTATES + 1], z[VI_ME_NINDICATORS + 1];
    a[VI_ME_NSTATES] = z[VI_ME_NINDICATORS] = 12345.0;
    vi_me_indicators(&e.e, z);
    vi_me_nominals(&e.e, a);
    cr_assert(z[VI_ME_NINDICATORS] == 12345.0 && a[VI_ME_NSTATES] == 12345.0, "written beyond the arrays");
    vi_me_derivatives(&e.e, a);
    vi_me_get_states(&e.e, a);
    cr_assert(a[VI_ME_NSTATES] == 12345.0, "written beyond the states");
    finish(&e);
}
