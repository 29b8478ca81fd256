/* Unit tests of the early return of the simulation layer (vi_sim_advance_until): with the flag, an
 * advance ends at each change of mode, at the time an uninterrupted advance changes mode there, and
 * the run goes on as the uninterrupted one; without it, nothing changes. */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "test_run.h"

#define MAX_CHANGES 256

/* The mode changes an advance logs ("event t=... kind=guard guard=g mode=a->b ..."). */
typedef struct {
    int n;
    double t[MAX_CHANGES];
    int from[MAX_CHANGES], to[MAX_CHANGES];
} changes;

static void collect(void *env, int category, const char *fmt, ...)
{
    changes *c = env;
    char text[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    if (category == VI_LOG_ERROR) fprintf(stderr, "%s\n", text);
    double t;
    int g, a, b;
    if (category == VI_LOG_EVENTS && sscanf(text, "event t=%lg kind=guard guard=%d mode=%d->%d", &t, &g, &a, &b) == 4 &&
        a != b && c->n < MAX_CHANGES) {
        c->t[c->n] = t, c->from[c->n] = a, c->to[c->n] = b;
        c->n++;
    }
}

/* The paper's Fig. 4b (Johnson, Y = 6e8 Pa, a = 0.1 mm, 560 Hz): contact, yield, unloading,
 * separation and reloading, in 0.03 s. */
static void fig4b(test_run *s, changes *c, int solver)
{
    memset(c, 0, sizeof *c);
    test_run_init(s, collect, c);
    s->d.par.a = 1e-4;
    s->d.par.solver = solver;
    cr_assert(vi_sim_initialize(&s->s) == 0, "%s", s->r.msg);
}

#define T_END 0.03

Test(early_return, stops_at_every_mode_change_where_the_uninterrupted_run_changes_mode)
{
    static const int solvers[] = {VI_Solver_bdf, VI_Solver_adams, VI_Solver_dop853};
    for (int k = 0; k < 3; k++) {
        test_run ref, s;
        changes cref, c;
        fig4b(&ref, &cref, solvers[k]);
        cr_assert(vi_sim_advance(&ref.s, T_END) == VI_SIM_OK, "%s", ref.r.msg);
        cr_assert(cref.n >= 20, "solver %d: only %d mode changes in the reference run", solvers[k], cref.n);
        fig4b(&s, &c, solvers[k]);
        int stops = 0;
        for (int pass = 0; s.d.run.t < T_END && pass < 2 * MAX_CHANGES; pass++) {
            double t0 = s.d.run.t;
            int mode0 = s.d.run.model.contact[0].mode, n0 = c.n;
            int rc = vi_sim_advance_until(&s.s, T_END, 1);
            cr_assert(rc == VI_SIM_OK || rc == VI_SIM_EVENT, "solver %d: rc %d: %s", solvers[k], rc, s.r.msg);
            cr_assert(s.d.run.t > t0, "solver %d: no progress from t = %.17g s", solvers[k], t0);
            if (rc == VI_SIM_OK) {
                cr_assert(s.d.run.t == T_END && c.n == n0, "solver %d: OK but t = %.17g s, %d changes", solvers[k],
                          s.d.run.t, c.n - n0);
                continue;
            }
            /* exactly one mode change, and the advance ended at it with the new mode in force */
            cr_assert(c.n == n0 + 1, "solver %d: %d mode changes in one early-return advance", solvers[k], c.n - n0);
            cr_assert(c.from[n0] == mode0 && c.to[n0] == s.d.run.model.contact[0].mode && c.t[n0] == s.d.run.t,
                      "solver %d: stopped at t = %.17g s in mode %d, the change was %d -> %d at %.17g s", solvers[k],
                      s.d.run.t, s.d.run.model.contact[0].mode, c.from[n0], c.to[n0], c.t[n0]);
            stops++;
        }
        cr_assert(s.d.run.t == T_END, "solver %d: did not reach the end (t = %.17g s)", solvers[k], s.d.run.t);
        /* the same changes as the uninterrupted run, at the same times up to the solver's accuracy */
        cr_assert(stops == cref.n && c.n == cref.n, "solver %d: %d stops, %d changes; uninterrupted: %d",
                  solvers[k], stops, c.n, cref.n);
        for (int i = 0; i < c.n; i++) {
            cr_assert(c.from[i] == cref.from[i] && c.to[i] == cref.to[i], "solver %d: change %d is %d -> %d, "
                      "uninterrupted %d -> %d", solvers[k], i, c.from[i], c.to[i], cref.from[i], cref.to[i]);
            cr_assert(fabs(c.t[i] - cref.t[i]) <= 1e-7, "solver %d: change %d at %.17g s, uninterrupted at %.17g s",
                      solvers[k], i, c.t[i], cref.t[i]);
        }
        cr_assert(fabs(s.d.run.x[0] - ref.d.run.x[0]) <= 1e-4 * fabs(ref.d.run.x[0]) + 1e-9,
                  "solver %d: delta %.9g m at the end, uninterrupted %.9g m", solvers[k], s.d.run.x[0], ref.d.run.x[0]);
        test_run_free(&ref);
        test_run_free(&s);
    }
}

Test(early_return, without_the_flag_the_advance_is_the_plain_one)
{
    test_run a, b;
    changes ca, cb;
    fig4b(&a, &ca, VI_Solver_adams);
    fig4b(&b, &cb, VI_Solver_adams);
    for (int i = 1; i <= 30; i++) {
        cr_assert(vi_sim_advance(&a.s, 1e-3 * i) == VI_SIM_OK, "%s", a.r.msg);
        cr_assert(vi_sim_advance_until(&b.s, 1e-3 * i, 0) == VI_SIM_OK, "%s", b.r.msg);
        cr_assert(a.d.run.t == b.d.run.t && a.d.run.x[0] == b.d.run.x[0] && a.d.run.x[1] == b.d.run.x[1] && a.d.run.model.contact[0].mode == b.d.run.model.contact[0].mode);
    }
    cr_assert(ca.n == cb.n && ca.n >= 20);
    test_run_free(&a);
    test_run_free(&b);
}

Test(early_return, a_mode_change_by_an_input_at_the_start_is_not_a_stop)
{
    /* A mass resting on the platform (Hertz, static start); the platform input drops by 1 mm between
     * two advances, so the contact is lost at the instant the next advance starts (the mode is chosen
     * afresh there). Asked to stop at mode changes, that advance runs on to the landing. */
    test_run s;
    changes c;
    memset(&c, 0, sizeof c);
    test_run_init(&s, collect, &c);
    s.d.par.contact_model = VI_ContactModel_hertz;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    cr_assert(vi_sim_advance_until(&s.s, 1e-3, 1) == VI_SIM_OK && s.d.run.model.contact[0].mode == VI_Mode_elastic, "%s", s.r.msg);
    s.d.in.yC_in = -1e-3;
    s.d.run.inputs_changed = 1;
    int rc = vi_sim_advance_until(&s.s, 0.1, 1);
    cr_assert(rc == VI_SIM_EVENT, "rc %d: %s", rc, s.r.msg);
    /* free fall through 1 mm under (P + m g)/m = 108 m/s^2 takes sqrt(2e-3/108) s = 4.3 ms */
    double fall = sqrt(2e-3 / (40000.0 / 407.747 + 9.81));
    cr_assert(fabs(s.d.run.t - 1e-3 - fall) < 0.05 * fall, "stopped at t = %.17g s; the landing is at %.6g s", s.d.run.t,
              1e-3 + fall);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_elastic && c.n == 1 && c.from[0] == VI_Mode_free, "mode %d after the landing",
              s.d.run.model.contact[0].mode);
    test_run_free(&s);
}

/* Hertz, thrown up from a touching start; at t = 1e-4 s the flight is replaced (as a restored state
 * would) by one that is `gap` above the platform coming down at 0.05 m/s, its contact guard armed
 * (no band left from the start). The first early-return advance from there: its mode changes and
 * where it stopped. */
static void land_after_gap(double gap, changes *c, double *t0, double *t, int *mode)
{
    test_run s;
    memset(c, 0, sizeof *c);
    test_run_init(&s, collect, c);
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.init = VI_Init_touching;
    s.d.par.v0 = 0.05;
    s.d.par.solver = VI_Solver_adams; /* CVODE restarts at the restored state: the landing falls in the advance */
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    cr_assert(vi_sim_advance(&s.s, 1e-4) == VI_SIM_OK && s.d.run.model.contact[0].mode == VI_Mode_free, "%s", s.r.msg);
    s.d.run.x[0] = -gap;
    s.d.run.x[1] = -0.05;
    s.d.run.events.band[0] = 0.0;
    cr_assert(vi_sim_restore(&s.s) == 0, "%s", s.r.msg);
    memset(c, 0, sizeof *c);
    *t0 = s.d.run.t;
    cr_assert(vi_sim_advance_until(&s.s, 0.1, 1) == VI_SIM_EVENT, "%s", s.r.msg);
    *t = s.d.run.t;
    *mode = s.d.run.model.contact[0].mode;
    test_run_free(&s);
}

Test(early_return, a_mode_change_within_the_time_resolution_of_the_start_is_taken_in_the_advance)
{
    changes c;
    double t0, t, unit = VI_EARLY_RETURN_UNITS * DBL_EPSILON; /* at t = 1e-4 s: 2.3e-13 s */
    int mode;
    /* 1e-13 m above: the landing is about 2e-12 s later, a stop */
    land_after_gap(1e-13, &c, &t0, &t, &mode);
    cr_assert(mode == VI_Mode_elastic && c.n == 1 && t > t0 + unit, "t - t0 = %g s, mode %d", t - t0, mode);
    /* 1e-15 m above: the landing, about 2e-14 s later, is the instant the advance started; it runs on
     * to the separation */
    land_after_gap(1e-15, &c, &t0, &t, &mode);
    cr_assert(c.n == 2 && c.to[0] == VI_Mode_elastic && c.t[0] - t0 <= unit, "%d changes, the first %g s after the start",
              c.n, c.n ? c.t[0] - t0 : 0.0);
    cr_assert(mode == VI_Mode_free && t - t0 > 1e-3, "stopped %g s after the start in mode %d", t - t0, mode);
}

/* Rolled without load (P = 0, g = 0) down a V-shaped trough at 1 m/s: the mass follows the platform
 * down touching it without force; at the kink (t = 10 ms) the platform turns up, and the contact
 * begins there, by the kink and not by an event. The early return stops at the kink. */
Test(early_return, stops_at_a_kink_of_the_profile_that_changes_the_mode)
{
    char path[64];
    snprintf(path, sizeof path, "/tmp/vi_early_return_v_%d.txt", (int)getpid());
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL);
    fprintf(f, "-10 1e-3\n0 0\n10 1e-3\n");
    fclose(f);
    test_run s;
    changes c;
    memset(&c, 0, sizeof c);
    test_run_init(&s, collect, &c);
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 0.0, s.d.par.g = 0.0;
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "%s", path);
    s.d.par.V = 1.0, s.d.par.x0 = -0.01;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_free);
    int rc = vi_sim_advance_until(&s.s, 0.1, 1);
    remove(path);
    cr_assert(rc == VI_SIM_EVENT, "rc %d: %s", rc, s.r.msg);
    cr_assert(fabs(s.d.run.t - 0.01) <= 1e-12 && s.d.run.model.contact[0].mode == VI_Mode_elastic && c.n == 0,
              "stopped at t = %.17g s in mode %d after %d event mode changes", s.d.run.t, s.d.run.model.contact[0].mode, c.n);
    test_run_free(&s);
}
