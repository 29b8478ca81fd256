/* Unit tests of the event engine (vi_hybrid.h) on a Hertz model without a driver: the bands of a guard
 * at zero in either integrated coordinate in closed form, the same input signal changing nothing, the
 * Zeno rule's message, the event log's form, and the check of the engine's state. */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "vi_hybrid.h"
#include "vi_contact_instance.h" /* the defaults of the variable table (vi_parameters_default, vi_contact_model_params) */

static char last_line[512];
static int n_lines;

static void capture(void *env, int category, const char *fmt, ...)
{
    (void)env;
    if (category != VI_LOG_EVENTS) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(last_line, sizeof last_line, fmt, ap);
    va_end(ap);
    n_lines++;
}

/* A Hertz model touching a platform at yC_in = platform [m], in free flight moving up at 0.01 m/s
 * (delta = 0, the contact guard at zero); rtol 1e-6, atol 1e-9 m and 1e-6 m/s. */
static void touching(vi_model *model, vi_hybrid_state *st, vi_hybrid *h, int integrates_y, double platform, double x[2])
{
    vi_parameters p;
    vi_parameters_default(&p);
    p.contact_model = VI_ContactModel_hertz;
    vi_model_params mp = vi_contact_model_params(&p);
    char msg[256];
    memset(model, 0, sizeof *model);
    cr_assert(vi_model_setup(model, &mp, 0.0, msg, sizeof msg) == 0, "%s", msg);
    cr_assert(vi_model_set_rolling(model, NULL, 0.0, 0.0, msg, sizeof msg) == 0, "%s", msg);
    model->yC_in = (vi_ramp){platform, 0.0, 0.0};
    model->contact[0].mode = VI_MODE_FREE;
    x[0] = 0.0, x[1] = 0.01; /* delta' = yC' - v = -0.01: the mass leaves */
    vi_hybrid_bind(h, model, st, integrates_y, capture, NULL);
    vi_hybrid_start(h, 1e-6, (const double[2]){1e-9, 1e-6}, 0.0, x);
    n_lines = 0;
}

Test(hybrid, a_guard_at_zero_gets_the_band_of_the_coordinate_integrated)
{
    vi_model model;
    vi_hybrid_state st;
    vi_hybrid h;
    double x[2];
    /* delta integrated: the free contact guard -delta moves by atol under the tolerance and by the
     * smallest subnormal under one ulp of delta = 0 (the platform is still, v does not enter) */
    touching(&model, &st, &h, 0, 1.5, x);
    double band = 4.0 * 1e-9 + 256.0 * nextafter(0.0, 1.0) + DBL_MIN;
    cr_assert(st.band[0] == band && st.band[1] == 0.0, "band %.17g, closed form %.17g", st.band[0], band);
    /* y = yC - delta = 1.5 integrated: the guard moves by rtol |y| + atol under the tolerance and by
     * one ulp of y (2^-52 in [1, 2)) */
    touching(&model, &st, &h, 1, 1.5, x);
    band = 4.0 * (1e-6 * 1.5 + 1e-9) + 256.0 * 0x1p-52;
    cr_assert(fabs(st.band[0] - band) <= 1e-12 * band && st.band[1] == 0.0, "band %.17g, closed form %.17g",
              st.band[0], band);
    double g[VI_NGUARDS];
    vi_hybrid_guards(&h, 0.0, x, g);
    cr_assert(g[0] == st.band[0], "the integrator sees the guard lifted by its band: %g", g[0]);
}

Test(hybrid, the_same_input_signal_changes_nothing)
{
    vi_model model;
    vi_hybrid_state st;
    vi_hybrid h;
    double x[2];
    touching(&model, &st, &h, 0, 1.5, x);
    vi_model before = model;
    double x0[2] = {x[0], x[1]};
    cr_assert(vi_hybrid_input_jump(&h, 1e-3, x, (vi_ramp){1.5, 0.0, 1e-3}, model.F_ext, 0.0, 560.0) == 0);
    cr_assert(memcmp(&before, &model, sizeof model) == 0 && x[0] == x0[0] && x[1] == x0[1] && n_lines == 0);
    /* the platform up by 1 um onto the mass: delta jumps by 1 um, elastic, logged */
    cr_assert(vi_hybrid_input_jump(&h, 1e-3, x, (vi_ramp){1.5 + 1e-6, 0.0, 1e-3}, model.F_ext, 0.0, 560.0) == 1);
    cr_assert(x[0] == (1.5 + 1e-6) - 1.5 && x[1] == x0[1] && model.contact[0].mode == VI_MODE_ELASTIC, "delta %g mode %d", x[0],
              model.contact[0].mode);
    cr_assert(n_lines == 1 && strcmp(last_line, "event t=0.001 kind=input mode=0->1") == 0, "%s", last_line);
}

Test(hybrid, a_state_event_is_one_line_of_key_value_pairs)
{
    vi_model model;
    vi_hybrid_state st;
    vi_hybrid h;
    double x[2];
    touching(&model, &st, &h, 0, 1.5, x);
    x[0] = 1e-12, x[1] = -0.02; /* a located contact, coming down */
    int from = vi_hybrid_event(&h, 2e-3, x, 0, 1);
    double t, delta, v;
    int guard, a, b, end = 0;
    cr_assert(from == VI_MODE_FREE && model.contact[0].mode == VI_MODE_ELASTIC && x[0] == 0.0 && st.n_events == 1);
    cr_assert(sscanf(last_line, "event t=%lg kind=guard guard=%d mode=%d->%d delta=%lg v=%lg%n", &t, &guard, &a, &b,
                     &delta, &v, &end) == 6 && last_line[end] == '\0', "%s", last_line);
    cr_assert(t == 2e-3 && guard == 0 && a == 0 && b == 1 && delta == 0.0 && v == -0.02, "%s", last_line);
}

Test(hybrid, events_accumulating_at_one_instant_stop_at_the_64th)
{
    vi_model model;
    vi_hybrid_state st;
    vi_hybrid h;
    double x[2];
    char msg[512] = "";
    touching(&model, &st, &h, 0, 1.5, x);
    for (int i = 1; i <= VI_ZENO_EVENTS; i++) {
        model.contact[0].mode = VI_MODE_FREE, x[0] = 1e-12, x[1] = -0.02;
        int from = vi_hybrid_event(&h, 0.0, x, 0, 1);
        cr_assert(vi_hybrid_zeno(&h, 0.0, 0, from, msg, sizeof msg) == (i == VI_ZENO_EVENTS), "event %d", i);
    }
    char expect[512];
    snprintf(expect, sizeof expect, "events accumulate at t = 0 s (Zeno): %d events each within %g ulps of time of the "
             "one before, the last on guard 0 of mode 0 (contact); stopped there. Each mode chosen was left again at "
             "once: the motion the guards see leaves it. Where the platform moves through yC_in, pass its velocity "
             "(velocity_input = true, vC_in); else tighten rtol", VI_ZENO_EVENTS, VI_ZENO_ULPS);
    cr_assert(strcmp(msg, expect) == 0, "%s", msg);
    vi_hybrid_count_from(&h, 1.0);
    cr_assert(st.zeno == 0 && st.t_count == 1.0);
}

Test(hybrid, check_names_the_first_bad_field)
{
    vi_model model;
    vi_hybrid_state st, bad;
    vi_hybrid h;
    double x[2];
    char msg[256];
    touching(&model, &st, &h, 0, 1.5, x);
    cr_assert(vi_hybrid_check(&st, 0.0, msg, sizeof msg) == 0, "%s", msg);
    bad = st, bad.rtol = 0.5;
    cr_assert(vi_hybrid_check(&bad, 0.0, msg, sizeof msg) < 0 && strstr(msg, "rtol = 0.5") != NULL, "%s", msg);
    bad = st, bad.atol[1] = NAN;
    cr_assert(vi_hybrid_check(&bad, 0.0, msg, sizeof msg) < 0 && strstr(msg, "atol[1]") != NULL, "%s", msg);
    bad = st, bad.band[1] = -1e-300;
    cr_assert(vi_hybrid_check(&bad, 0.0, msg, sizeof msg) < 0 && strstr(msg, "guard band[1]") != NULL, "%s", msg);
    bad = st, bad.t_count = 1e-3;
    cr_assert(vi_hybrid_check(&bad, 0.0, msg, sizeof msg) < 0 && strstr(msg, "t_count") != NULL, "%s", msg);
    bad = st, bad.zeno = VI_ZENO_EVENTS + 1;
    cr_assert(vi_hybrid_check(&bad, 0.0, msg, sizeof msg) < 0 && strstr(msg, "zeno = 65") != NULL, "%s", msg);
    bad = st, bad.n_events = -1;
    cr_assert(vi_hybrid_check(&bad, 0.0, msg, sizeof msg) < 0 && strstr(msg, "n_events = -1") != NULL, "%s", msg);
}

/* The guards by name, as vi_model.h lists them, for a law of each kind: the Zeno message names them. */
Test(hybrid, the_guards_are_named_as_the_model_lists_them)
{
    static const struct { int law, moving; const char *names[5][VI_NGUARDS]; } cases[] = {
        {VI_ContactModel_hertz, 0, {{"contact", "none"}, {"separation", "none"}}},
        {VI_ContactModel_johnson, 0, {{"contact", "none"}, {"separation", "yield"}, {"the turning point (delta' = 0)", "none"},
                                      {"separation", "reloading to delta_c"},
                                      {"the end of stick (plastic loading)", "the end of stick (unloading)"}}},
        {VI_ContactModel_johnson, 1, {{"contact", "none"}, {"separation", "yield"}, {"back below yield", "none"}}},
        {VI_ContactModel_lepp, 0, {{"contact", "none"}, {"separation", "yield"}, {"the turning point (delta' = 0)", "none"}}},
        {VI_ContactModel_hertz_damped, 0, {{"contact", "none"}, {"separation", "release (the damped force reaches 0)"}}},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        vi_parameters p;
        vi_parameters_default(&p);
        p.contact_model = cases[k].law, p.moving_contact = cases[k].moving;
        vi_model_params mp = vi_contact_model_params(&p);
        vi_model model;
        char msg[256];
        memset(&model, 0, sizeof model);
        cr_assert(vi_model_setup(&model, &mp, 0.0, msg, sizeof msg) == 0, "%s", msg);
        for (int mode = 0; mode < 5; mode++)
            for (int g = 0; g < VI_NGUARDS; g++) {
                const char *want = cases[k].names[mode][g] ? cases[k].names[mode][g] : "none";
                if (!cases[k].names[mode][0]) continue; /* a mode the law does not have */
                cr_assert(strcmp(vi_model_guard_name(&model, mode, g), want) == 0, "law %d, mode %d, guard %d: %s",
                          cases[k].law, mode, g, vi_model_guard_name(&model, mode, g));
            }
    }
}
