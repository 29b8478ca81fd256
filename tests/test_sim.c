/* Unit tests of the simulation layer (vi_sim.h) that need no FMU: the state-payload check
 * (doc/model.md section 7.6) names the first bad field; a valid state passes. */
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
    CASE(d.atol[1] = -1.0, "atol[1]");
    CASE(d.n_events = -1, "n_events");
    CASE(d.tolerance = 0.5, "tolerance");
    CASE(d.inputs_changed = 7, "inputs_changed");
    CASE(d.step_t0 = NAN, "step_t0");
    CASE(d.step_t0 = d.t + 1e-3, "step_t0");
    CASE(d.step_v0 = INFINITY, "step_v0");
    CASE(d.guard_band[0] = -1e-9, "guard_band[0]");
    CASE(d.guard_band[1] = NAN, "guard_band[1]");
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

/* Events accumulating geometrically at t* = 0.05 s (a bouncing ball with restitution 1/2: the gaps
 * halve) reach the Zeno count once the gaps fall to rounding; regular events at 30 MHz never do. */
Test(sim, zeno_rule_counts_accumulation_not_frequency)
{
    double t_star = 0.05, gap = 1e-6, t = t_star - 2.0 * gap, before = t;
    int count = 0, n = 0;
    while (count < VI_ZENO_EVENTS && n < 1000) {
        t = fmin(t + gap, t_star);
        gap *= 0.5;
        count = vi_sim_zeno_count(count, before, t);
        before = t;
        n++;
    }
    cr_assert(count >= VI_ZENO_EVENTS, "not detected after %d events", n);
    cr_assert(fabs(t - t_star) < 1e-12, "detected at %.17g, not at the accumulation point", t);
    count = 0, t = 0.05;
    for (int k = 0; k < 100000; k++, t += 1.0 / 3e7) count = vi_sim_zeno_count(count, t, t + 1.0 / 3e7);
    cr_assert(count == 0, "regular events counted as Zeno");
    cr_assert(vi_sim_zeno_count(5, 0.05, 0.06) == 0, "a gap resets the count");
}

/* The event count starts at zero and counts what happens: a mass thrown clear (no load) meets
 * nothing; a Hertz drop (P = g = 0, touching, moving in) rebounds elastically and leaves once (one
 * event, the separation), then flies on. */
Test(sim, event_count_starts_at_zero_and_counts_the_separation)
{
    double v0[] = {1.0, -0.1};
    long expect[] = {0, 1};
    for (int i = 0; i < 2; i++) {
        vi_sim s;
        vi_sim_init(&s, quiet, NULL);
        s.d.par.contact_model = VI_ContactModel_hertz;
        s.d.par.P = 0.0, s.d.par.g = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = v0[i];
        cr_assert(vi_sim_initialize(&s) == 0, "%s", s.msg);
        cr_assert(s.d.n_events == 0, "%ld events at the start", s.d.n_events);
        cr_assert(vi_sim_advance(&s, 0.01) == VI_SIM_OK, "%s", s.msg);
        cr_assert(s.d.n_events == expect[i] && s.d.M.mode == VI_Mode_free, "v0 = %g: %ld events, mode %d", v0[i],
                  s.d.n_events, s.d.M.mode);
        vi_sim_free(&s);
    }
}

/* Restoring the data of an instance not yet initialized (every solver): no solver until the next
 * initialization, so a step is refused; initialized again, the instance runs as before. */
Test(sim, restoring_data_from_before_initialization_leaves_no_solver)
{
    int solvers[] = {VI_Solver_bdf, VI_Solver_adams, VI_Solver_dop853};
    for (int i = 0; i < 3; i++) {
        vi_sim s, fresh;
        vi_sim_init(&s, quiet, NULL);
        s.d.par.solver = solvers[i];
        vi_sim_init(&fresh, quiet, NULL);
        fresh.d.par.solver = solvers[i];
        cr_assert(vi_sim_initialize(&s) == 0 && vi_sim_advance(&s, 1e-3) == VI_SIM_OK, "%s", s.msg);
        double x_first = s.d.x[0];
        s.d = fresh.d;
        cr_assert(vi_sim_restore(&s) == 0, "solver %d: %s", solvers[i], s.msg);
        cr_assert(vi_sim_advance(&s, 2e-3) == VI_SIM_ERROR && strstr(s.msg, "not initialized"), "solver %d: %s",
                  solvers[i], s.msg);
        cr_assert(vi_sim_initialize(&s) == 0 && vi_sim_advance(&s, 1e-3) == VI_SIM_OK, "%s", s.msg);
        cr_assert(s.d.x[0] == x_first, "solver %d: the run differs", solvers[i]);
        vi_sim_free(&s), vi_sim_free(&fresh);
    }
}

/* A solver that cannot start fails the initialization (not the first step): the one-step method
 * evaluates the right-hand side at the start, and a load of 1e300 N on 1e-10 kg, touching (no
 * contact force yet), gives an acceleration beyond the doubles. */
Test(sim, a_solver_that_cannot_start_fails_the_initialization)
{
    vi_sim s;
    vi_sim_init(&s, quiet, NULL);
    s.d.par.solver = VI_Solver_dop853;
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 1e300, s.d.par.m = 1e-10, s.d.par.init = VI_Init_touching, s.d.par.v0 = 1.0;
    cr_assert(vi_sim_initialize(&s) < 0, "initialized");
    cr_assert(strstr(s.msg, "could not create the solver"), "%s", s.msg);
    vi_sim_free(&s);
}

/* With the one-step method the solver's continuation is part of the state and checked field by field. */
Test(sim, data_check_names_bad_fields_of_the_one_step_continuation)
{
    vi_sim s;
    vi_sim_init(&s, quiet, NULL);
    s.d.par.solver = VI_Solver_dop853;
    s.d.par.a = 1e-4;
    cr_assert(vi_sim_initialize(&s) == 0, "%s", s.msg);
    cr_assert(vi_sim_advance(&s, 1e-3) == VI_SIM_OK, "%s", s.msg);
    char msg[256];
    cr_assert(vi_sim_data_check(&s.d, msg, sizeof msg) == 0, "%s", msg);
    vi_sim_data d;
#define CASE(stmt, field) d = s.d, stmt, refused(&d, field)
    CASE(d.ode.event_pending = 2, "ode.event_pending");
    CASE(d.ode.event_pending = -1, "ode.event_pending");
    CASE(d.ode.have_step = 2, "ode.have_step");
    CASE(d.ode.cur = 2, "ode.cur");
    CASE(d.ode.h = 0.0, "ode.h");
    CASE(d.ode.t = NAN, "ode.t");
    CASE(d.ode.x[0] = NAN, "ode.x[0]");
    CASE(d.ode.f[1] = INFINITY, "ode.f[1]");
    CASE(d.ode.g[1] = NAN, "ode.g[1]");
#undef CASE
    vi_sim_free(&s);
}

/* ---- the solver interface (vi_solver.h) ------------------------------------------------------ */

static void nan_after_half(double t, const double *x, double *dx, void *u)
{
    (void)x, (void)u;
    dx[0] = t < 0.5 ? 1.0 : NAN;
    dx[1] = 0.0;
}

/* The one-step method: a right-hand side that turns non-finite fails the advance (vi_ode_step
 * refuses the step), never a success and never the work bound, which would tell the caller to go on
 * from there. (CVODE instead approaches t = 0.5 in ever shorter successful steps.) */
Test(solver, a_right_hand_side_turning_non_finite_fails_the_one_step_advance)
{
    vi_ode ode;
    double atol[2] = {1e-9, 1e-9}, x0[2] = {0.0, 0.0}, x[2], t = 0.0;
    vi_solver_config cfg = {.n = 2, .rhs = nan_after_half, .method = VI_METHOD_DOP853, .rtol = 1e-6, .atol = atol,
                            .ode = &ode, .log = quiet};
    vi_solver *s = vi_solver_create(&cfg, 0.0, x0);
    cr_assert(s != NULL);
    int fired[1];
    long taken = 0;
    int rc = vi_solver_advance(s, 1.0, 1000, &t, x, fired, &taken);
    cr_assert(rc == VI_SOLVER_FAILED, "rc %d at t = %g after %ld steps", rc, t, taken);
    vi_solver_free(s);
}
