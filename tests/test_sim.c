/* Unit tests of the simulation layer (vi_sim.h) that need no FMU: the state-payload check of
 * contract C3 names the first bad field; a valid state passes. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "vi_sim.h"

static void quiet(void *env, int category, const char *fmt, ...) { (void)env, (void)category, (void)fmt; }

static vi_sim running(void)
{
    vi_sim s;
    vi_sim_init(&s, quiet, NULL);
    s.d.par.a = 1e-4;
    cr_assert(vi_sim_initialize(&s) == 0, "%s", s.msg);
    cr_assert(vi_sim_advance(&s, 1e-3) == VI_SIM_OK, "%s", s.msg);
    return s;
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
    s = running();
    cr_assert(vi_sim_data_check(&s.d, msg, sizeof msg) == 0, "running: %s", msg);
    vi_sim_free(&s);
}

Test(sim, data_check_names_the_first_bad_field)
{
    vi_sim s = running();
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
