/* Unit tests of the simulation layer (vi_sim.h) that need no FMU: the state-payload check of
 * contract C3 names the first bad field; a valid state passes. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "vi_sim.h"

#include <stdarg.h>
#include <stdio.h>
static void quiet(void *env, int category, const char *fmt, ...) { (void)env; if (category != VI_LOG_ERROR) return; va_list ap; va_start(ap, fmt); vfprintf(stderr, fmt, ap); va_end(ap); fputc(10, stderr); }

/* A simulation of the defaults with a = 0.1 mm, run to 1 ms. (The solver points into s->d: a vi_sim
 * stays where it was initialized.) */
static void running(vi_sim *s)
{
    vi_sim_init(s, quiet, NULL);
    s->d.par.a = 1e-4;
    cr_assert(vi_sim_initialize(s) == 0, "%s", s->msg);
    cr_assert(vi_sim_advance(s, 1e-3) == VI_SIM_OK, "%s", s->msg);
}

/* The check refuses d and names `field` in its message. */
static void refused(const vi_sim_data *d, const char *field)
{
    char msg[256] = "";
    cr_assert(vi_sim_data_check(d, msg, sizeof msg) < 0, "accepted a bad %s", field);
    cr_assert(strstr(msg, field) != NULL, "message '%s' does not name %s", msg, field);
}

Test(sim, data_check_accepts_states_the_fmu_produces)
{
    char msg[256];
    vi_sim s;
    vi_sim_init(&s, quiet, NULL);
    cr_assert(vi_sim_data_check(&s.d, msg, sizeof msg) == 0, "defaults: %s", msg);
    vi_sim_free(&s);
    running(&s);
    cr_assert(vi_sim_data_check(&s.d, msg, sizeof msg) == 0, "running: %s", msg);
    vi_sim_free(&s);
}

Test(sim, data_check_names_the_first_bad_field)
{
    vi_sim s;
    running(&s);
    vi_sim_data d;
#define CASE(stmt, field) d = s.d, stmt, refused(&d, field)
    CASE(d.x[0] = NAN, "x[0]");
    CASE(d.x[1] = INFINITY, "x[1]");
    CASE(d.t = NAN, "t =");
    CASE(d.t = d.t_start - 1.0, "t =");
    CASE(d.t_start = INFINITY, "t_start");
    CASE(d.in.yC_in = NAN, "yC_in");
    CASE(d.din.F_ext = INFINITY, "derivative of F_ext");
    CASE(d.par.m = NAN, "m =");
    CASE(d.par.contact_model = 9, "contact_model");
    CASE(d.par.solver = 0, "solver");
    CASE(d.par.moving_contact = 2, "moving_contact");
    CASE(d.atol[1] = -1.0, "atol[1]");
    CASE(d.n_events = -1, "n_events");
    CASE(d.tolerance = 0.5, "tolerance");
    CASE(d.inputs_changed = 7, "inputs_changed");
#undef CASE
    vi_sim_free(&s);
}

Test(sim, refuses_a_step_end_that_does_not_exceed_the_time)
{
    vi_sim s;
    running(&s);
    double t = s.d.t, x0 = s.d.x[0];
    cr_assert(vi_sim_advance(&s, t) == VI_SIM_ERROR);
    cr_assert(strstr(s.msg, "does not exceed") != NULL, "%s", s.msg);
    cr_assert(vi_sim_advance(&s, t - 1e-3) == VI_SIM_ERROR);
    cr_assert(vi_sim_advance(&s, NAN) == VI_SIM_ERROR);
    cr_assert(s.d.t == t && s.d.x[0] == x0, "a refused step changed the state");
    cr_assert(vi_sim_advance(&s, nextafter(t, INFINITY)) == VI_SIM_OK, "%s", s.msg); /* one ulp is a step */
    cr_assert(s.d.t == nextafter(t, INFINITY));
    cr_assert(vi_sim_advance(&s, t + 1e-3) == VI_SIM_OK, "%s", s.msg);
    vi_sim_free(&s);
}
