/* Unit tests of the simulation layer (test_run.h) that need no FMU: the state-payload check
 * (doc/model.md section 7.6) names the first bad field; a valid state passes. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_format.h"
#include "test_run.h"

#include <stdarg.h>
#include <stdio.h>
#include <unistd.h> /* getpid */
static void quiet(void *env, int category, const char *fmt, ...) { (void)env; if (category != VI_LOG_ERROR) return; va_list ap; va_start(ap, fmt); vfprintf(stderr, fmt, ap); va_end(ap); fputc(10, stderr); }

/* A simulation of the defaults with a = 0.1 mm, run to 1 ms. (The solver points into s->d: a test_run
 * stays where it was initialized.) */
static void running(test_run *s)
{
    test_run_init(s, quiet, NULL);
    s->d.par.a = 1e-4;
    cr_assert(vi_sim_initialize(&s->s) == 0, "%s", s->r.msg);
    cr_assert(vi_sim_advance(&s->s, 1e-3) == VI_SIM_OK, "%s", s->r.msg);
}

/* A state as the FMU saves it (src/adapter/vi_fmu_contact.c): the FMI storage, the run's data and each driver's. */
typedef vi_contact_data state;
static state state_of(const test_run *s) { return s->d; }

/* The adapter's check of a state taken after initialization: of Co-Simulation (`surfaces`, with the
 * Model Exchange driver's data finite), or of Model Exchange. */
static int state_check(const state *st, int surfaces, char *msg, size_t n)
{
    return vi_contact_state_check(st, 1, !surfaces, msg, n);
}

/* The check refuses d and names `field` in its message. */
static void refused(const state *d, const char *field)
{
    char msg[256] = "";
    cr_assert(state_check(d, 1, msg, sizeof msg) < 0, "accepted a bad %s", field);
    cr_assert(strstr(msg, field) != NULL, "message '%s' does not name %s", msg, field);
}

Test(sim, data_check_accepts_states_the_fmu_produces)
{
    char msg[256];
    test_run s;
    test_run_init(&s, quiet, NULL);
    cr_assert(state_check(&s.d, 1, msg, sizeof msg) == 0, "defaults: %s", msg);
    test_run_free(&s);
    running(&s);
    cr_assert(state_check(&s.d, 1, msg, sizeof msg) == 0, "running: %s", msg);
    test_run_free(&s);
}

Test(sim, data_check_names_the_first_bad_field)
{
    test_run s;
    running(&s);
    state d;
#define CASE(stmt, field) d = state_of(&s), stmt, refused(&d, field)
    CASE(d.run.x[0] = NAN, "x[0]");
    CASE(d.run.x[1] = INFINITY, "x[1]");
    CASE(d.run.t = NAN, "t =");
    CASE(d.run.t = d.t_start - 1.0, "t =");
    CASE(d.t_start = INFINITY, "t_start");
    CASE(d.run.events.atol[1] = -1.0, "atol[1]");
    CASE(d.run.events.n_events = -1, "n_events");
    CASE(d.tolerance = 0.5, "tolerance");
    CASE(d.run.inputs_changed = 7, "inputs_changed");
    CASE(d.run.step_t0 = NAN, "step_t0");
    CASE(d.run.step_t0 = d.run.t + 1e-3, "step_t0");
    CASE(d.run.step_v0 = INFINITY, "step_v0");
    CASE(d.run.W_damping = NAN, "W_damping");
    CASE(d.run.F_peak = -1.0, "F_peak");
    CASE(d.run.events.band[0] = -1e-9, "guard band[0]");
    CASE(d.run.events.band[1] = NAN, "guard band[1]");
    CASE(d.me.y_me = NAN, "y_me");
    CASE(d.run.events.rtol = 0.5, "rtol = 0.5 is neither 0 nor in");
    CASE(d.run.events.rtol = 1e-3, "rtol = 0.001 is not the one of the settings");
    CASE(d.run.events.t_count = d.run.t + 1e-3, "t_count");
    CASE(d.run.events.zeno = VI_ZENO_EVENTS + 1, "zeno");
    CASE(d.run.events.zeno = -1, "zeno");
#undef CASE
    test_run_free(&s);
}

Test(sim, refuses_a_step_end_that_does_not_exceed_the_time)
{
    test_run s;
    running(&s);
    double t = s.d.run.t, x0 = s.d.run.x[0];
    cr_assert(vi_sim_advance(&s.s, t) == VI_SIM_ERROR);
    cr_assert(strstr(s.r.msg, "does not exceed") != NULL, "%s", s.r.msg);
    cr_assert(vi_sim_advance(&s.s, t - 1e-3) == VI_SIM_ERROR);
    cr_assert(vi_sim_advance(&s.s, NAN) == VI_SIM_ERROR);
    cr_assert(s.d.run.t == t && s.d.run.x[0] == x0, "a refused step changed the state");
    cr_assert(vi_sim_advance(&s.s, nextafter(t, INFINITY)) == VI_SIM_OK, "%s", s.r.msg); /* one ulp is a step */
    cr_assert(s.d.run.t == nextafter(t, INFINITY));
    cr_assert(vi_sim_advance(&s.s, t + 1e-3) == VI_SIM_OK, "%s", s.r.msg);
    test_run_free(&s);
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
        count = vi_hybrid_zeno_count(count, before, t);
        before = t;
        n++;
    }
    cr_assert(count >= VI_ZENO_EVENTS, "not detected after %d events", n);
    cr_assert(fabs(t - t_star) < 1e-12, "detected at %.17g, not at the accumulation point", t);
    count = 0, t = 0.05;
    for (int k = 0; k < 100000; k++, t += 1.0 / 3e7) count = vi_hybrid_zeno_count(count, t, t + 1.0 / 3e7);
    cr_assert(count == 0, "regular events counted as Zeno");
    cr_assert(vi_hybrid_zeno_count(5, 0.05, 0.06) == 0, "a gap resets the count");
}

/* The event count starts at zero and counts what happens: a mass thrown clear (no load) meets
 * nothing; a Hertz drop (P = g = 0, touching, moving in) rebounds elastically and leaves once (one
 * event, the separation), then flies on. */
Test(sim, event_count_starts_at_zero_and_counts_the_separation)
{
    double v0[] = {1.0, -0.1};
    long expect[] = {0, 1};
    for (int i = 0; i < 2; i++) {
        test_run s;
        test_run_init(&s, quiet, NULL);
        s.d.par.contact_model = VI_ContactModel_hertz;
        s.d.par.P = 0.0, s.d.par.g = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = v0[i];
        cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
        cr_assert(s.d.run.events.n_events == 0, "%ld events at the start", s.d.run.events.n_events);
        cr_assert(vi_sim_advance(&s.s, 0.01) == VI_SIM_OK, "%s", s.r.msg);
        cr_assert(s.d.run.events.n_events == expect[i] && s.d.run.model.contact[0].mode == VI_Mode_free, "v0 = %g: %ld events, mode %d", v0[i],
                  s.d.run.events.n_events, s.d.run.model.contact[0].mode);
        test_run_free(&s);
    }
}

/* Restoring the data of an instance not yet initialized (every solver): no solver until the next
 * initialization, so a step is refused; initialized again, the instance runs as before. */
Test(sim, restoring_data_from_before_initialization_leaves_no_solver)
{
    int solvers[] = {VI_Solver_bdf, VI_Solver_adams, VI_Solver_dop853};
    for (int i = 0; i < 3; i++) {
        test_run s, fresh;
        test_run_init(&s, quiet, NULL);
        s.d.par.solver = solvers[i];
        test_run_init(&fresh, quiet, NULL);
        fresh.d.par.solver = solvers[i];
        cr_assert(vi_sim_initialize(&s.s) == 0 && vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK, "%s", s.r.msg);
        double x_first = s.d.run.x[0];
        test_run_copy_data(&s, &fresh);
        cr_assert(vi_sim_restore(&s.s) == 0, "solver %d: %s", solvers[i], s.r.msg);
        cr_assert(vi_sim_advance(&s.s, 2e-3) == VI_SIM_ERROR && strstr(s.r.msg, "not initialized"), "solver %d: %s",
                  solvers[i], s.r.msg);
        cr_assert(vi_sim_initialize(&s.s) == 0 && vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK, "%s", s.r.msg);
        cr_assert(s.d.run.x[0] == x_first, "solver %d: the run differs", solvers[i]);
        test_run_free(&s), test_run_free(&fresh);
    }
}

/* A solver that cannot start fails the initialization (not the first step): the one-step method
 * evaluates the right-hand side at the start, and a load of 1e300 N on 1e-10 kg, touching (no
 * contact force yet), gives an acceleration beyond the doubles. */
Test(sim, a_solver_that_cannot_start_fails_the_initialization)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.solver = VI_Solver_dop853;
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 1e300, s.d.par.m = 1e-10, s.d.par.init = VI_Init_touching, s.d.par.v0 = 1.0;
    cr_assert(vi_sim_initialize(&s.s) < 0, "initialized");
    cr_assert(strstr(s.r.msg, "could not create the solver at t = 0 s: no first step from the initial state (the load's "
                            "acceleration (P + m g - F_ext)/m = inf m/s2); the contact's time scale sqrt(m/k) = "), "%s", s.r.msg);
    cr_assert(strstr(s.r.msg, "; raise m, or lower P or the contact's stiffness"), "%s", s.r.msg);
    test_run_free(&s);
}

/* With the one-step method the solver's continuation is part of the state and checked field by field. */
Test(sim, data_check_names_bad_fields_of_the_one_step_continuation)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.solver = VI_Solver_dop853;
    s.d.par.a = 1e-4;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    cr_assert(vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK, "%s", s.r.msg);
    char msg[256];
    cr_assert(state_check(&s.d, 1, msg, sizeof msg) == 0, "%s", msg);
    state d;
#define CASE(stmt, field) d = state_of(&s), stmt, refused(&d, field)
    CASE(d.cs.ode.event_pending = 2, "ode.event_pending");
    CASE(d.cs.ode.event_pending = -1, "ode.event_pending");
    CASE(d.cs.ode.have_step = 2, "ode.have_step");
    CASE(d.cs.ode.cur = 2, "ode.cur");
    CASE(d.cs.ode.h = 0.0, "ode.h");
    CASE(d.cs.ode.t = NAN, "ode.t");
    CASE(d.cs.ode.x[0] = NAN, "ode.x[0]");
    CASE(d.cs.ode.f[1] = INFINITY, "ode.f[1]");
    CASE(d.cs.ode.g[1] = NAN, "ode.g[1]");
    CASE(d.cs.ode.t_old = d.run.t + 1e-9, "does not span t"); /* the last step ends before the time */
    CASE((d.cs.ode.have_step = 0, d.cs.ode.t = d.run.t + 1e-9), "a restart must be at t"); /* no step: at the time */
#undef CASE
    test_run_free(&s);
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

/* ---- solver = auto ------------------------------------------------------------------------------ */

/* A light mass (1e-7 kg) resting under the default Hertz load on a platform moving with a = 0.1 mm at
 * 560 Hz: the contact rings at about 10 MHz, the motion follows the platform (the mass's inertia moves
 * delta by about 1e-13 m). */
static void light_mass(test_run *s, int solver)
{
    test_run_init(s, quiet, NULL);
    s->d.par.solver = solver;
    s->d.par.contact_model = VI_ContactModel_hertz;
    s->d.par.m = 1e-7;
    s->d.par.a = 1e-4;
    cr_assert(vi_sim_initialize(&s->s) == 0, "%s", s->r.msg);
}

/* auto finds the stiff contact stiff within its first steps and hands it to BDF: the platform is
 * followed (y = yC - delta_static) at a few thousand right-hand sides, where the one-step method alone
 * needs about 3 million for 10 ms. */
Test(sim, auto_hands_a_stiff_contact_to_bdf)
{
    test_run s;
    light_mass(&s, VI_Solver_auto);
    double delta_static = s.d.run.x[0], worst = 0.0;
    for (int k = 1; k <= 100; k++) {
        cr_assert(vi_sim_advance(&s.s, 1e-4 * k) == VI_SIM_OK, "%s", s.r.msg);
        vi_outputs out;
        test_run_outputs(&s, &out);
        worst = fmax(worst, fabs(out.y - (out.yC - delta_static)));
    }
    vi_solver_stats st;
    vi_sim_statistics(&s.s, &st);
    cr_assert(worst < 1e-10, "y departs from yC - delta_static by %g m", worst);
    cr_assert(st.switches == 1 && s.d.cs.auto_choice.bdf == 1, "%ld hand-overs, bdf %d", st.switches, s.d.cs.auto_choice.bdf);
    cr_assert(st.rhs_evals < 5000, "%ld rhs evaluations", st.rhs_evals);
    test_run_free(&s);
}

/* In contact the light mass is stiff (BDF); pulled off the platform by an upward force of twice its
 * load it flies free (no stiffness at all) and auto hands back to the one-step method. The Hertz
 * contact is elastic and the net force F_ext - W = W constant, so from the rest at t1 (elastic energy
 * 2/5 W delta_static) the energy balance 1/2 m v^2 = 2/5 W delta_static + W (y - y1) holds in flight,
 * and y - y1 follows the parabola W/m (t - t1)^2 / 2 to within the short release. */
Test(sim, auto_hands_back_when_the_mass_flies_free)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.solver = VI_Solver_auto;
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.m = 1e-7;
    s.d.par.P = 1e-3;
    s.d.par.g = 0.0;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    double W = 1e-3, m = 1e-7, delta_static = s.d.run.x[0];
    cr_assert(vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK, "%s", s.r.msg);
    cr_assert(s.d.cs.auto_choice.bdf == 1, "not handed to BDF in contact");
    vi_outputs out;
    test_run_outputs(&s, &out);
    double y1 = out.y;
    s.d.in.F_ext = 2.0 * W;
    s.d.run.inputs_changed = 1;
    for (int k = 1; k <= 10; k++) {
        double t = 1e-3 + 1e-4 * k, tau = t - 1e-3;
        cr_assert(vi_sim_advance(&s.s, t) == VI_SIM_OK, "%s", s.r.msg);
        test_run_outputs(&s, &out);
        double kinetic = 0.5 * m * out.v * out.v, work = 0.4 * W * delta_static + W * (out.y - y1);
        cr_assert(fabs(kinetic - work) <= 1e-6 * work, "t = %g: 1/2 m v^2 = %.9g, work %.9g", t, kinetic, work);
        cr_assert(fabs(out.y - y1 - 0.5 * W / m * tau * tau) <= 1e-2 * 0.5 * W / m * tau * tau, "t = %g: y - y1 = %g", t,
                  out.y - y1);
    }
    vi_solver_stats st;
    vi_sim_statistics(&s.s, &st);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_free && s.d.cs.auto_choice.bdf == 0 && st.switches == 2, "mode %d, bdf %d, %ld hand-overs",
              s.d.run.model.contact[0].mode, s.d.cs.auto_choice.bdf, st.switches);
    test_run_free(&s);
}

/* A state taken from a running auto instance (vi_sim_checkpoint, then a byte copy of the data, as the
 * FMU does) and restored in another instance continues bit for bit like the original: taken while
 * the one-step method runs (before the hand-over, which both then make at the same step) and while
 * BDF runs. */
Test(sim, auto_restored_state_continues_bit_for_bit)
{
    const double taken_at[] = {3e-7, 1e-3};
    for (int i = 0; i < 2; i++) {
        test_run a, b;
        light_mass(&a, VI_Solver_auto);
        cr_assert(vi_sim_advance(&a.s, taken_at[i]) == VI_SIM_OK, "%s", a.r.msg);
        cr_assert(a.d.cs.auto_choice.bdf == i, "state %d taken with bdf = %d", i, a.d.cs.auto_choice.bdf);
        cr_assert(vi_sim_checkpoint(&a.s) == 0, "%s", a.r.msg);
        test_run_init(&b, quiet, NULL);
        test_run_copy_data(&b, &a);
        cr_assert(vi_sim_restore(&b.s) == 0, "%s", b.r.msg);
        for (int k = 1; k <= 30; k++) {
            double t = taken_at[i] + 1e-4 * k;
            cr_assert(vi_sim_advance(&a.s, t) == VI_SIM_OK && vi_sim_advance(&b.s, t) == VI_SIM_OK, "%s %s", a.r.msg, b.r.msg);
            cr_assert(memcmp(a.d.run.x, b.d.run.x, sizeof a.d.run.x) == 0, "state %d, t = %g: %.17g %.17g vs %.17g %.17g", i, t,
                      a.d.run.x[0], a.d.run.x[1], b.d.run.x[0], b.d.run.x[1]);
        }
        cr_assert(memcmp(&a.d.cs.auto_choice, &b.d.cs.auto_choice, sizeof a.d.cs.auto_choice) == 0 && a.d.cs.auto_choice.switches == 1);
        test_run_free(&a), test_run_free(&b);
    }
}

/* The data check names bad fields of auto's choice; while BDF runs the one-step continuation is not
 * used (a hand-over back restarts it) and not checked. */
Test(sim, data_check_names_bad_fields_of_the_auto_choice)
{
    test_run s;
    light_mass(&s, VI_Solver_auto);
    cr_assert(vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK && s.d.cs.auto_choice.bdf == 1, "%s", s.r.msg);
    char msg[256];
    cr_assert(state_check(&s.d, 1, msg, sizeof msg) == 0, "%s", msg);
    state d;
#define CASE(stmt, field) d = state_of(&s), stmt, refused(&d, field)
    CASE(d.cs.auto_choice.bdf = 2, "auto_choice.bdf");
    CASE(d.cs.auto_choice.pending = -1, "auto_choice.pending");
    CASE(d.cs.auto_choice.stiff = VI_AUTO_STIFF_STEPS + 1, "auto_choice.stiff");
    CASE(d.cs.auto_choice.calm = -1, "auto_choice.calm");
    CASE(d.cs.auto_choice.steps = -1, "auto_choice.steps");
    CASE(d.cs.auto_choice.switches = -1, "auto_choice.switches");
    CASE((d.cs.auto_choice.bdf = 0, d.cs.ode.t = NAN), "ode.t");
#undef CASE
    d = state_of(&s);
    d.cs.ode.t = NAN;
    cr_assert(state_check(&d, 1, msg, sizeof msg) == 0, "%s", msg);
    test_run_free(&s);
}

static void jac_2(double t, const double *x, double *j, void *u)
{
    (void)t, (void)x, (void)u;
    j[0] = j[1] = j[2] = j[3] = 0.0;
}

/* auto is made for at most 2 states with a Jacobian and the caller's choice block. */
Test(solver, auto_needs_two_states_a_jacobian_and_its_choice)
{
    vi_ode ode;
    vi_solver_auto sw;
    double atol[3] = {1e-9, 1e-9, 1e-9}, x0[3] = {0.0, 0.0, 0.0};
    vi_solver_config ok = {.n = 2, .rhs = nan_after_half, .jac = jac_2, .method = VI_METHOD_AUTO, .rtol = 1e-6,
                           .atol = atol, .ode = &ode, .auto_choice = &sw, .log = quiet};
    vi_solver *s = vi_solver_create(&ok, 0.0, x0);
    cr_assert(s != NULL);
    vi_solver_free(s);
    vi_solver_config bad = ok;
    bad.n = 3;
    cr_assert(vi_solver_create(&bad, 0.0, x0) == NULL);
    bad = ok, bad.jac = NULL;
    cr_assert(vi_solver_create(&bad, 0.0, x0) == NULL);
    bad = ok, bad.auto_choice = NULL;
    cr_assert(vi_solver_create(&bad, 0.0, x0) == NULL);
}

/* ---- lazy outputs ------------------------------------------------------------------------------- */

/* Reading a group of outputs computes that group only: y (the platform group) leaves the force, the
 * plastic work and the rest untouched; every group read alone equals the same group read with all
 * the others; a step makes every group new. (Johnson, yielded: W_plastic takes a logarithm.) */
Test(sim, outputs_are_computed_per_group_when_read)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.a = 1e-4;
    s.d.par.Y = 2e8; /* yields at the first impact */
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    cr_assert(vi_sim_advance(&s.s, 2e-3) == VI_SIM_OK, "%s", s.r.msg);
    vi_outputs part, all;
    s.out.W_plastic = s.out.F = s.out.F_mean = s.out.k_contact = s.out.E_star = -12345.0;
    part = *vi_contact_outputs_of(&s, VI_OUT_PLATFORM);
    cr_assert(s.r.out_valid == VI_OUT_PLATFORM, "groups computed: %#x", s.r.out_valid);
    cr_assert(part.W_plastic == -12345.0 && part.F == -12345.0 && part.F_mean == -12345.0 &&
              part.k_contact == -12345.0 && part.E_star == -12345.0, "a group nobody read was computed");
    unsigned groups[] = {VI_OUT_STATE, VI_OUT_FORCE, VI_OUT_MEMORY, VI_OUT_CALCULATED, VI_OUT_MEAN, VI_OUT_STIFFNESS};
    for (int step = 0; step < 2; step++) {
        vi_outputs one[6];
        for (int i = 0; i < 6; i++) {
            s.r.out_valid = 0;
            one[i] = *vi_contact_outputs_of(&s, groups[i]);
        }
        s.r.out_valid = 0;
        test_run_outputs(&s, &all);
        cr_assert(all.W_plastic > 0.0 && all.delta_c > 0.0, "no plastic memory: %g", all.W_plastic);
        cr_assert(one[0].delta == all.delta && one[0].v == all.v && one[0].mode == all.mode && one[0].n_impacts == all.n_impacts);
        cr_assert(one[1].F == all.F && one[2].W_plastic == all.W_plastic && one[2].Rbar == all.Rbar &&
                  one[3].E_star == all.E_star && one[4].F_mean == all.F_mean && one[5].k_contact == all.k_contact);
        cr_assert(part.y == all.y && part.yC == all.yC, "y read alone %g, with all %g", part.y, all.y);
        double W_before = all.W_plastic, y_before = all.y;
        cr_assert(vi_sim_advance(&s.s, 4e-3 + 2e-3 * step) == VI_SIM_OK, "%s", s.r.msg);
        cr_assert(s.r.out_valid == 0, "outputs kept over a step: %#x", s.r.out_valid);
        part = *vi_contact_outputs_of(&s, VI_OUT_PLATFORM | VI_OUT_MEMORY);
        cr_assert(part.y != y_before && part.W_plastic >= W_before, "y %g -> %g, W %g -> %g", y_before, part.y, W_before,
                  part.W_plastic);
    }
    test_run_free(&s);
}

/* Warnings of the range of validity after a restore: every cause is checked at the next
 * communication point (a restored state may carry an amplitude this instance never warned of); in
 * between, a communication point tests the indentation only. */
static int warnings;
static void count_warnings(void *env, int category, const char *fmt, ...)
{
    (void)env, (void)fmt;
    if (category == VI_LOG_WARNING) warnings++;
}

Test(sim, a_restored_state_is_checked_for_every_cause_of_validity)
{
    test_run a, b;
    test_run_init(&a, count_warnings, NULL);
    a.d.par.contact_model = VI_ContactModel_hertz;
    a.d.par.a = 0.5; /* more than R* = 0.2375 m: outside the range of validity */
    warnings = 0;
    cr_assert(vi_sim_initialize(&a.s) == 0, "%s", a.r.msg);
    cr_assert(warnings == 1 && (a.r.warned_validity & VI_INVALID_AMPLITUDE), "%d warnings", warnings);
    test_run_init(&b, count_warnings, NULL);
    b.d.par.contact_model = VI_ContactModel_hertz;
    cr_assert(vi_sim_initialize(&b.s) == 0 && vi_sim_advance(&b.s, 1e-4) == VI_SIM_OK, "%s", b.r.msg);
    cr_assert(warnings == 1 && b.r.warned_validity == 0);
    cr_assert(vi_sim_checkpoint(&a.s) == 0);
    test_run_copy_data(&b, &a);
    cr_assert(vi_sim_restore(&b.s) == 0, "%s", b.r.msg);
    cr_assert(vi_sim_advance(&b.s, b.d.run.t + 1e-6) == VI_SIM_OK, "%s", b.r.msg);
    cr_assert(warnings == 2 && (b.r.warned_validity & VI_INVALID_AMPLITUDE), "%d warnings, bits %d", warnings,
              b.r.warned_validity);
    test_run_free(&a), test_run_free(&b);
}

/* A profile file of two points at height 0. */
static void write_flat_profile(const char *path)
{
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL, "%s", path);
    fputs("0 0\n1 0\n", f);
    fclose(f);
}

/* A profile needs a body of positive radius: with R1 = 0 (the variable table's range refuses it at
 * the FMI level; test_run's callers may set it) the initialization fails naming R1, before the table
 * is read; any positive radius will do. */
Test(sim, a_profile_needs_a_positive_body_radius)
{
    char path[64];
    snprintf(path, sizeof path, "/tmp/vi_test_sim_profile_%d.txt", (int)getpid());
    write_flat_profile(path);
    test_run s;
    test_run_init(&s, quiet, NULL);
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "%s", path);
    s.d.par.V = 1.0, s.d.par.x0 = 0.5, s.d.par.R1 = 0.0, s.d.par.R2 = 0.1; /* R* from R2 alone */
    int rc = vi_sim_initialize(&s.s);
    cr_assert(rc < 0 && strstr(s.r.msg, "rolling needs a body radius R1 > 0 (R1 = 0 m)"), "%s", s.r.msg);
    test_run_free(&s);
    test_run_init(&s, quiet, NULL); /* a small wheel (0.1 mm) rolls like any other */
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "%s", path);
    s.d.par.V = 1.0, s.d.par.x0 = 0.5, s.d.par.R1 = 1e-4;
    rc = vi_sim_initialize(&s.s);
    remove(path);
    cr_assert(rc == 0 && s.d.run.model.profile != NULL, "%s", s.r.msg);
    test_run_free(&s);
}

/* A relative profile_file of one character, not in the resources folder, is read from the working
 * directory (the shortest name is a name like any other). */
Test(sim, a_one_character_profile_file_is_read_from_the_working_directory)
{
    char dir[] = "/tmp/vi_test_sim_XXXXXX";
    cr_assert(mkdtemp(dir) != NULL && chdir(dir) == 0);
    write_flat_profile("p");
    test_run s;
    test_run_init(&s, quiet, NULL);
    vi_run_set_resources(&s.r, "/nonexistent/resources");
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "p");
    s.d.par.V = 1.0, s.d.par.x0 = 0.5;
    int rc = vi_sim_initialize(&s.s);
    remove("p");
    cr_assert(chdir("/") == 0 && rmdir(dir) == 0);
    cr_assert(rc == 0 && s.d.run.model.profile != NULL, "%s", s.r.msg);
    test_run_free(&s);
}

/* A resources folder of one character, the root (file:///), is looked in like any other: a relative
 * profile_file "tmp/<dir>/p" is the file /tmp/<dir>/p, whatever the working directory. */
Test(sim, a_root_resources_folder_is_looked_in)
{
    char dir[] = "/tmp/vi_test_sim_XXXXXX", path[64];
    cr_assert(mkdtemp(dir) != NULL && chdir(dir) == 0); /* no tmp/ here */
    snprintf(path, sizeof path, "%s/p", dir);
    write_flat_profile(path);
    test_run s;
    test_run_init(&s, quiet, NULL);
    vi_run_set_resources(&s.r, "/");
    snprintf(s.d.par.profile_file, sizeof s.d.par.profile_file, "%s", path + 1);
    s.d.par.V = 1.0, s.d.par.x0 = 0.5;
    int rc = vi_sim_initialize(&s.s);
    remove(path);
    cr_assert(chdir("/") == 0 && rmdir(dir) == 0);
    cr_assert(rc == 0 && s.d.run.model.profile != NULL, "%s", s.r.msg);
    test_run_free(&s);
}

/* ---- the state-payload check, rule by rule ------------------------------------------------------ */

/* The check refuses d with exactly the message fmt (printf-formatted with the spoiled values). */
static void refused_as(const state *d, int surfaces, const char *fmt, ...) VI_PRINTF_FORMAT(3, 4);
static void refused_as(const state *d, int surfaces, const char *fmt, ...)
{
    char expect[512], msg[512] = "";
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(expect, sizeof expect, fmt, ap);
    va_end(ap);
    int rc = surfaces ? state_check(d, 1, msg, sizeof msg) : state_check(d, 0, msg, sizeof msg);
    cr_assert(rc == -1, "accepted (rc %d); expected: %s", rc, expect);
    cr_assert(strcmp(msg, expect) == 0, "expected '%s', got '%s'", expect, msg);
}

static void passes(const state *d, int surfaces, const char *what)
{
    char msg[512] = "";
    int rc = surfaces ? state_check(d, 1, msg, sizeof msg) : state_check(d, 0, msg, sizeof msg);
    cr_assert(rc == 0, "%s: rc %d: %s", what, rc, msg);
}

/* Each rule of the payload broken alone (values at and just beyond its bounds), with its message;
 * the values a rule allows, at its bounds, pass. */
Test(sim, data_check_each_rule_alone_with_its_message)
{
    test_run s;
    running(&s);
    const state ok = state_of(&s);
    state d;
    passes(&ok, 1, "running");
    d = ok, d.run.inputs_changed = 1;
    passes(&d, 1, "inputs changed");
    d = ok, d.run.inputs_changed = 2;
    refused_as(&d, 1, "inputs_changed = 2 is not 0 or 1");
    d = ok, d.run.inputs_changed = -1;
    refused_as(&d, 1, "inputs_changed = -1 is not 0 or 1");
    d = ok, d.t_start = INFINITY;
    refused_as(&d, 1, "t_start = inf is not finite");
    d = ok, d.t_start = NAN;
    refused_as(&d, 1, "t_start = nan is not finite");
    double tolerances_in[] = {0.0, 1e-14, 1e-2}, tolerances_out[] = {nextafter(1e-14, 0.0), nextafter(1e-2, 1.0), -1e-3,
                                                                      NAN};
    for (int i = 0; i < 3; i++) {
        d = ok, d.tolerance = tolerances_in[i];
        d.run.events.rtol = vi_contact_rtol(&d.par, d.tolerance); /* the tolerance the simulation then runs at */
        passes(&d, 1, "tolerance in range");
    }
    for (int i = 0; i < 4; i++) {
        d = ok, d.tolerance = tolerances_out[i];
        refused_as(&d, 1, "tolerance = %g is neither 0 nor in [1e-14, 0.01]", tolerances_out[i]);
    }
    d = ok, d.run.t = NAN;
    refused_as(&d, 1, "t = nan is not finite or before t_start = 0");
    d = ok, d.run.t = -1e-300;
    refused_as(&d, 1, "t = -1e-300 is not finite or before t_start = 0");
    d = ok, d.t_start = d.run.step_t0 = d.run.t; /* at the start itself */
    passes(&d, 1, "t = t_start");
    d = ok, d.run.x[0] = NAN;
    refused_as(&d, 1, "x[0] = nan is not finite");
    d = ok, d.run.x[1] = -INFINITY;
    refused_as(&d, 1, "x[1] = -inf is not finite");
    for (int i = 0; i < 2; i++) {
        double bad[] = {NAN, INFINITY, -1e-300};
        for (int k = 0; k < 3; k++) {
            d = ok, d.run.events.atol[i] = bad[k];
            refused_as(&d, 1, "atol[%d] = %g is not finite and >= 0", i, bad[k]);
        }
        d = ok, d.run.events.atol[i] = 0.0;
        passes(&d, 1, "atol = 0");
    }
    d = ok, d.run.events.n_events = -1;
    refused_as(&d, 1, "n_events = -1 is negative");
    d = ok, d.run.events.n_events = 0;
    passes(&d, 1, "no events");
    d = ok, d.run.initialized = 2;
    refused_as(&d, 1, "initialized = 2 is not 0 or 1");
    d = ok, d.run.initialized = -1;
    refused_as(&d, 1, "initialized = -1 is not 0 or 1");
    d = ok, d.run.step_t0 = NAN;
    refused_as(&d, 1, "step_t0 = nan, step_v0 = %g: not finite or after t", ok.run.step_v0);
    d = ok, d.run.step_t0 = nextafter(ok.run.t, INFINITY);
    refused_as(&d, 1, "step_t0 = %g, step_v0 = %g: not finite or after t", d.run.step_t0, ok.run.step_v0);
    d = ok, d.run.step_v0 = NAN;
    refused_as(&d, 1, "step_t0 = %g, step_v0 = nan: not finite or after t", ok.run.step_t0);
    d = ok, d.run.step_t0 = ok.run.t;
    passes(&d, 1, "a step of zero length");
    const double bad_peak[] = {NAN, INFINITY, -5e-324};
    for (int k = 0; k < 3; k++) {
        d = ok, d.run.F_peak = bad_peak[k];
        refused_as(&d, 1, "W_damping = %g, F_peak = %g: not finite, or F_peak < 0", ok.run.W_damping, bad_peak[k]);
        d = ok, d.run.W_damping = k == 2 ? NAN : bad_peak[k];
        refused_as(&d, 1, "W_damping = %g, F_peak = %g: not finite, or F_peak < 0", d.run.W_damping, ok.run.F_peak);
    }
    d = ok, d.run.F_peak = 0.0, d.run.W_damping = -1.0; /* Model Exchange: the importer's state, of any sign */
    passes(&d, 1, "no force yet, a negative damping work");
    for (int i = 0; i < VI_NGUARDS; i++) {
        double bad[] = {NAN, INFINITY, -1e-300};
        for (int k = 0; k < 3; k++) {
            d = ok, d.run.events.band[i] = bad[k];
            refused_as(&d, 1, "guard band[%d] = %g is not finite and >= 0", i, bad[k]);
        }
        d = ok, d.run.events.band[i] = 1e-12; /* a disarmed guard's band is tiny */
        passes(&d, 1, "a small band");
    }
    /* the model's own check follows */
    d = ok, d.run.model.contact[0].mode = 9;
    refused_as(&d, 1, "mode = 9 is not in 0..4");
    test_run_free(&s);
}

/* The one-step continuation is checked only where it is in use: a co-simulation state of the one-step
 * method (dop853, or auto while not on BDF); never for a CVODE method (BDF, Adams), never between
 * events (Model Exchange), never before initialization. */
Test(sim, data_check_looks_at_the_one_step_continuation_only_where_it_is_used)
{
    int solvers[] = {VI_Solver_bdf, VI_Solver_adams, VI_Solver_dop853};
    for (int i = 0; i < 3; i++) {
        test_run s;
        test_run_init(&s, quiet, NULL);
        s.d.par.solver = solvers[i];
        s.d.par.a = 1e-4;
        cr_assert(vi_sim_initialize(&s.s) == 0 && vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK, "%s", s.r.msg);
        state d = state_of(&s);
        d.cs.ode.h = 0.0;
        d.cs.ode.t = NAN;
        if (solvers[i] == VI_Solver_dop853) {
            char msg[512] = "";
            cr_assert(state_check(&d, 1, msg, sizeof msg) == -1 && strstr(msg, "ode."), "%s", msg);
        } else {
            passes(&d, 1, "a CVODE state ignores the one-step continuation");
        }
        passes(&d, 0, "between events");
        d.run.initialized = 0;
        passes(&d, 1, "before initialization");
        test_run_free(&s);
    }
}

/* ---- what the log messages of the loop report ----------------------------------------------------- */

static char logged[16][1024];
static int n_logged, log_category;
static void capture(void *env, int category, const char *fmt, ...)
{
    (void)env;
    if (category != log_category || n_logged >= 16) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(logged[n_logged++], sizeof logged[0], fmt, ap);
    va_end(ap);
}

/* A Hertz drop (P = g = 0, touching, moving in at 0.1 m/s) separates once, after the Hertz contact
 * time t_c = 2 (delta_max/v0) sqrt(pi) Gamma(7/5)/Gamma(9/10), delta_max = (15 m v0^2/(16 E* sqrt(R*)))^(2/5),
 * at delta = 0 (snapped onto the contact surface) and v = +v0 (elastic: the energy comes back). The
 * event's log line says so, value by value; the solver line (logged by the co-simulation driver after the
 * set-up) gives atol = rtol (delta_max, delta_max w). */
Test(sim, event_and_solver_log_lines_report_the_values)
{
    test_run s;
    n_logged = 0, log_category = VI_LOG_SOLVER;
    test_run_init(&s, capture, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 0.0, s.d.par.g = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = -0.1;
    s.d.par.solver = VI_Solver_dop853;
    s.d.par.rtol = 1e-10;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    cr_assert(n_logged == 0, "the set-up logs nothing of a solver the driver may not use");
    vi_sim_log_solver(&s.s);
    const vi_model *M = &s.d.run.model;
    double v0 = 0.1, dmax = pow(15.0 * M->body.m * v0 * v0 / (16.0 * M->contact[0].johnson.E_star * sqrt(M->contact[0].johnson.R_star)), 0.4);
    double w = sqrt(1.5 * M->contact[0].K * sqrt(dmax) / M->body.m); /* the virgin stiffness at delta_max over m */
    cr_assert(n_logged == 1, "%d solver lines", n_logged);
    const char *name = vi_solver_method_name(VI_Solver_dop853), *rest = logged[0] + strlen(name);
    double rtol, atol0, atol1, L, V;
    cr_assert(strncmp(logged[0], name, strlen(name)) == 0, "%s", logged[0]);
    cr_assert(sscanf(rest, ", rtol %lg, atol %lg m and %lg m/s (scales %lg m, %lg m/s)", &rtol, &atol0, &atol1, &L, &V) == 5,
              "%s", logged[0]);
    cr_assert(rtol == 1e-10, "%s", logged[0]);
    cr_assert(fabs(L - dmax) <= 1e-5 * dmax && fabs(V - dmax * w) <= 1e-5 * dmax * w, "%s (%g m, %g m/s)", logged[0], dmax,
              dmax * w);
    cr_assert(fabs(atol0 - 1e-10 * dmax) <= 1e-5 * 1e-10 * dmax && fabs(atol1 - 1e-10 * dmax * w) <= 1e-5 * 1e-10 * dmax * w,
              "%s", logged[0]);
    n_logged = 0, log_category = VI_LOG_EVENTS;
    cr_assert(vi_sim_advance(&s.s, 0.01) == VI_SIM_OK, "%s", s.r.msg); /* t_c = 2.2 ms */
    cr_assert(n_logged == 1, "%d event lines, %ld events, mode %d, t %g", n_logged, s.d.run.events.n_events, s.d.run.model.contact[0].mode, s.d.run.t);
    double t, delta, v;
    int guard, from, to, end = 0;
    cr_assert(sscanf(logged[0], "event t=%lg kind=guard guard=%d mode=%d->%d delta=%lg v=%lg%n", &t, &guard, &from, &to,
                     &delta, &v, &end) == 6 && logged[0][end] == '\0', "%s", logged[0]);
    double tc = 2.0 * dmax / v0 * sqrt(VI_PI) * tgamma(1.4) / tgamma(0.9);
    cr_assert(fabs(t - tc) <= 1e-6 * tc, "%s: t_c = %.9g s", logged[0], tc);
    cr_assert(guard == 0 && from == VI_Mode_elastic && to == VI_Mode_free, "%s", logged[0]);
    cr_assert(delta == 0.0 && fabs(v - v0) <= 1e-7, "%s", logged[0]);
    test_run_free(&s);
}

/* A solver failure names the time and the state it stopped at: a mass of 1e-10 kg flying free at
 * 1 m/s, then pushed by F_ext = -1e300 N (an acceleration beyond the doubles). */
Test(sim, solver_failure_message_gives_the_state)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.solver = VI_Solver_dop853;
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.m = 1e-10, s.d.par.P = 0.0, s.d.par.g = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = 1.0;
    cr_assert(vi_sim_initialize(&s.s) == 0 && vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK, "%s", s.r.msg);
    cr_assert(fabs(s.d.run.x[0] + 1e-3) <= 1e-12 && s.d.run.x[1] == 1.0, "%g %g", s.d.run.x[0], s.d.run.x[1]);
    s.d.in.F_ext = -1e300;
    s.d.run.inputs_changed = 1;
    cr_assert(vi_sim_advance(&s.s, 2e-3) == VI_SIM_ERROR, "%s", s.r.msg);
    char expect[512];
    snprintf(expect, sizeof expect, "the solver failed near t = %.17g s (mode 0, delta = %g m, v = %g m/s)", s.d.run.t,
             s.d.run.x[0], s.d.run.x[1]);
    cr_assert(strncmp(s.r.msg, expect, strlen(expect)) == 0 && strstr(s.r.msg, "; the contact's time scale sqrt(m/k) = "),
              "expected '%s' and the time scale, got '%s'", expect, s.r.msg);
    cr_assert(s.d.run.t >= 1e-3 && s.d.run.t < 2e-3 && s.d.run.x[0] < 0.0 && s.d.run.x[1] != s.d.run.x[0], "%s", s.r.msg);
    test_run_free(&s);
}

/* ---- guard bands across a change of mode ------------------------------------------------------ */

/* The band of a contact guard (+-delta) armed at delta = 0 (up to rounding): VI_GRAZE_TOL times its
 * change under the state error atol of delta, VI_GRAZE_ULPS times its change over one ulp of delta
 * (the smallest subnormal), plus DBL_MIN. */
static double band_at_contact(const test_run *s)
{
    return VI_GRAZE_TOL * s->d.run.events.atol[0] + VI_GRAZE_ULPS * nextafter(0.0, 1.0) + DBL_MIN;
}

/* An event that changes the mode arms the new mode's guards afresh: a band the old mode's guard had
 * (here set by hand on the contact guard of a Hertz drop) does not carry over to the free flight,
 * whose contact guard starts at zero (delta snapped onto the surface) with the band of its rounding. */
Test(sim, a_mode_change_at_an_event_arms_the_new_guards_afresh)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 0.0, s.d.par.g = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = -0.1;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_elastic);
    s.d.run.events.band[0] = 1e-9; /* the separation comes 1e-9 m late: the band is part of the guard */
    cr_assert(vi_sim_advance_until(&s.s, 0.01, 1) == VI_SIM_EVENT, "%s", s.r.msg);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_free && s.d.run.x[0] == 0.0, "mode %d delta %g", s.d.run.model.contact[0].mode, s.d.run.x[0]);
    cr_assert(s.d.run.events.band[0] == band_at_contact(&s) && s.d.run.events.band[1] == 0.0, "bands %g %g", s.d.run.events.band[0],
              s.d.run.events.band[1]);
    test_run_free(&s);
}

/* The same for an input change that changes the mode: a Hertz mass at rest under its load; the
 * platform drops by exactly the static indentation (delta = 0) while F_ext = 2 W pulls the mass up:
 * free, its contact guard at zero with the band of its rounding, not the band of 1 m left on the
 * elastic mode's guard (which would hide every later contact); the change is logged. The mass is set at rest exactly, so
 * that the force alone decides the mode (delta = 0, delta' = 0, F_hold = -W < 0: free). */
Test(sim, a_mode_change_at_an_input_change_arms_the_new_guards_afresh)
{
    test_run s;
    test_run_init(&s, capture, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    cr_assert(vi_sim_initialize(&s.s) == 0 && vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK, "%s", s.r.msg);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_elastic && s.d.run.x[0] > 0.0);
    s.d.run.events.band[0] = 1.0;
    s.d.run.x[1] = 0.0; /* at rest exactly (the solver leaves a velocity of rounding size) */
    s.d.in.yC_in = -s.d.run.x[0];
    s.d.in.F_ext = 2.0 * s.d.run.model.body.W0;
    s.d.run.inputs_changed = 1;
    n_logged = 0, log_category = VI_LOG_EVENTS;
    cr_assert(vi_sim_advance(&s.s, 1e-3 + 1e-6) == VI_SIM_OK, "%s", s.r.msg);
    cr_assert(n_logged == 1 && strcmp(logged[0], "event t=0.001 kind=input mode=1->0") == 0, "%d: %s", n_logged,
              logged[0]);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_free && s.d.run.x[0] < 0.0, "mode %d delta %g", s.d.run.model.contact[0].mode, s.d.run.x[0]);
    cr_assert(s.d.run.events.band[0] == band_at_contact(&s) && s.d.run.events.band[1] == 0.0, "bands %g %g", s.d.run.events.band[0],
              s.d.run.events.band[1]);
    test_run_free(&s);
}

/* The importer's tolerance (0: none, par.rtol counts) lies in [1e-14, 0.01], both ends included; one
 * ulp beyond either end is refused with the message naming the range. */
Test(sim, experiment_tolerance_at_and_beyond_its_bounds)
{
    double in[] = {0.0, 1e-14, 1e-2}, out[] = {nextafter(1e-14, 0.0), nextafter(1e-2, 1.0), 5e-324};
    for (int i = 0; i < 3; i++) {
        test_run s;
        test_run_init(&s, quiet, NULL);
        s.d.tolerance = in[i];
        cr_assert(vi_run_prepare(&s.r) == 0, "tolerance %g: %s", in[i], s.r.msg);
        test_run_free(&s);
    }
    for (int i = 0; i < 3; i++) {
        test_run s;
        test_run_init(&s, quiet, NULL);
        s.d.tolerance = out[i];
        cr_assert(vi_run_prepare(&s.r) == -1, "tolerance %g accepted", out[i]);
        char expect[256];
        snprintf(expect, sizeof expect, "relative tolerance (the importer's: fmi2SetupExperiment, fmi3EnterInitializationMode) "
                 "= %g: use a value in [1e-14, 0.01]", out[i]);
        cr_assert(strcmp(s.r.msg, expect) == 0, "expected '%s', got '%s'", expect, s.r.msg);
        test_run_free(&s);
    }
}

/* Johnson pre-loaded by P = 1e300 N starts at an indentation where the plastic work is inf - inf: the
 * initialization is refused naming that output and the start time (here 0.5 s); P = 1e30 N is fine. */
Test(sim, initialization_refuses_outputs_beyond_the_doubles)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.P = 1e300;
    s.d.t_start = 0.5;
    cr_assert(vi_run_prepare(&s.r) == -1, "accepted");
    cr_assert(strncmp(s.r.msg, "W_plastic = ", 12) == 0 && isnan(atof(s.r.msg + 12)) &&
              strstr(s.r.msg, " at t = 0.5 s: the parameters and inputs lead to values beyond the range of double") != NULL,
              "%s", s.r.msg);
    test_run_free(&s);
    test_run_init(&s, quiet, NULL);
    s.d.par.P = 1e30;
    cr_assert(vi_run_prepare(&s.r) == 0, "%s", s.r.msg);
    vi_outputs out;
    test_run_outputs(&s, &out);
    cr_assert(isfinite(out.W_plastic) && out.W_plastic > 0.0, "W_plastic %g", out.W_plastic);
    test_run_free(&s);
}

/* F_mean is the impulse of the contact force over the last step divided by it: zero in free flight
 * under gravity and a linearly growing pull F_ext (whose mean over the step is its midpoint value),
 * and the force itself before any step. */
Test(sim, mean_force_is_zero_in_free_flight_under_a_ramp)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = 10.0;
    s.d.par.solver = VI_Solver_dop853, s.d.par.rtol = 1e-10; /* a polynomial motion: integrated to rounding */
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    vi_outputs out;
    test_run_outputs(&s, &out);
    cr_assert(out.F_mean == 0.0 && out.F == 0.0, "before any step: %g", out.F_mean);
    cr_assert(vi_sim_advance(&s.s, 1e-3) == VI_SIM_OK, "%s", s.r.msg);
    test_run_outputs(&s, &out);
    double W = s.d.run.model.body.W0;
    cr_assert(fabs(out.F_mean) <= 1e-9 * W, "gravity only: F_mean %g", out.F_mean);
    s.d.in.F_ext = 100.0, s.d.din.F_ext = 2e4; /* 100 N growing at 20 kN/s */
    s.d.run.inputs_changed = 1;
    for (int k = 2; k <= 4; k++) {
        cr_assert(vi_sim_advance(&s.s, 1e-3 * k) == VI_SIM_OK, "%s", s.r.msg);
        s.r.out_valid = 0;
        test_run_outputs(&s, &out);
        cr_assert(s.d.run.model.contact[0].mode == VI_Mode_free && fabs(out.F_mean) <= 1e-9 * W, "step %d: F_mean %g", k, out.F_mean);
    }
    test_run_free(&s);
}

/* k_contact is dF/ddelta of the mode: Hertz 1.5 K sqrt(delta); a sticking mass is held at delta_c
 * between the branches and would unload on the unloading curve: 1.5 Kbar sqrt(delta_c - delta_f). */
Test(sim, contact_stiffness_of_the_mode)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    double d = s.d.run.x[0], k = 1.5 * s.d.run.model.contact[0].K * sqrt(d);
    const vi_outputs *out = vi_contact_outputs_of(&s, VI_OUT_STIFFNESS);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_elastic && fabs(out->k_contact - k) <= 1e-12 * k, "%g vs %g", out->k_contact, k);
    test_run_free(&s);
    test_run_init(&s, quiet, NULL);
    s.d.par.yield_formula = VI_YieldFormula_printed; /* F_Y below the load: plastically pre-loaded, stick */
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    const vi_unload_curve *U = &s.d.run.model.contact[0].unload;
    k = 1.5 * U->Kbar * sqrt(U->delta_c - U->delta_f);
    out = vi_contact_outputs_of(&s, VI_OUT_STIFFNESS);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_stick && fabs(out->k_contact - k) <= 1e-12 * k, "mode %d: %g vs %g", s.d.run.model.contact[0].mode,
              out->k_contact, k);
    test_run_free(&s);
}

/* A restore replaces everything derived from the old state: the outputs read before are not served
 * again, whichever driver restores the run (Model Exchange: the run alone); with the solver
 * (co-simulation) the run goes on; before any initialization the statistics are zero. */
Test(sim, restore_replaces_outputs_and_solver)
{
    test_run a, b;
    running(&a);
    running(&b);
    cr_assert(vi_sim_advance(&b.s, 3e-3) == VI_SIM_OK, "%s", b.r.msg);
    vi_outputs before, expect;
    test_run_outputs(&b, &before);
    test_run_outputs(&a, &expect);
    cr_assert(before.y != expect.y && before.delta != expect.delta);
    cr_assert(vi_sim_checkpoint(&a.s) == 0, "%s", a.r.msg);
    test_run_copy_data(&b, &a);
    cr_assert(vi_me_restore(&b.e, 1) == 0, "%s", b.r.msg); /* the run alone, as Model Exchange restores it */
    const vi_model_values *v = &vi_run_outputs_of(&b.r, VI_OUT_ALL)->model;
    cr_assert(v->y == expect.y && v->delta == expect.delta && v->F == expect.F, "outputs of the old state");
    b.e.active = 0; /* a Co-Simulation instance again */
    vi_solver_stats st, zero;
    memset(&zero, 0, sizeof zero);
    cr_assert(vi_sim_restore(&b.s) == 0 && b.s.solver != NULL, "%s", b.r.msg);
    cr_assert(vi_sim_advance(&a.s, 2e-3) == VI_SIM_OK && vi_sim_advance(&b.s, 2e-3) == VI_SIM_OK, "%s", b.r.msg);
    cr_assert(a.d.run.x[0] == b.d.run.x[0] && a.d.run.x[1] == b.d.run.x[1], "the restored run differs");
    vi_sim_statistics(&b.s, &st);
    cr_assert(st.rhs_evals > 0);
    test_run_free(&a), test_run_free(&b);
    test_run_init(&a, quiet, NULL);
    memset(&st, 0xff, sizeof st);
    vi_sim_statistics(&a.s, &st);
    cr_assert(memcmp(&st, &zero, sizeof st) == 0, "statistics before initialization");
    cr_assert(vi_sim_checkpoint(&a.s) == 0, "%s", a.r.msg); /* nothing to keep yet */
}

/* A mass flying off a Hertz contact at 1 m/s (no load), 1 ms after it left: free, delta = -1 mm. */
static void flying_off(test_run *s)
{
    test_run_init(s, quiet, NULL);
    s->d.par.contact_model = VI_ContactModel_hertz;
    s->d.par.P = 0.0, s->d.par.g = 0.0, s->d.par.init = VI_Init_touching, s->d.par.v0 = 1.0;
    cr_assert(vi_sim_initialize(&s->s) == 0 && vi_sim_advance(&s->s, 1e-3) == VI_SIM_OK, "%s", s->r.msg);
    cr_assert(s->d.run.model.contact[0].mode == VI_Mode_free && fabs(s->d.run.x[0] + 1e-3) <= 1e-12, "delta %g", s->d.run.x[0]);
}

/* A disarmed guard (band > 0) is armed again (band 0) at the start of a step once it lies above its
 * band, and only then: a mass flying off (contact guard 1 mm and growing, the other guard inactive at
 * 1) with bands set by hand on one guard or the other. */
Test(sim, a_guard_is_rearmed_once_above_its_band)
{
    test_run s;
    flying_off(&s);
    struct { double band[2], after[2]; } c[] = {
        {{1e-300, 0.0}, {0.0, 0.0}}, /* contact guard far above a tiny band: armed */
        {{1.0, 0.0}, {1.0, 0.0}},    /* below its band of 1 m: stays disarmed */
        {{0.0, 0.5}, {0.0, 0.0}},    /* the inactive guard (1) above its band: armed */
        {{1.0, 0.5}, {1.0, 0.0}},    /* each guard on its own */
    };
    for (int i = 0; i < 4; i++) {
        s.d.run.events.band[0] = c[i].band[0], s.d.run.events.band[1] = c[i].band[1];
        cr_assert(vi_sim_advance(&s.s, s.d.run.t + 1e-4) == VI_SIM_OK, "%s", s.r.msg);
        cr_assert(s.d.run.events.band[0] == c[i].after[0] && s.d.run.events.band[1] == c[i].after[1], "case %d: bands %g %g", i,
                  s.d.run.events.band[0], s.d.run.events.band[1]);
    }
    test_run_free(&s);
}

/* A step of a few ulps of time (32 ulps of t, within the 64 ulps that count as "at" a profile's kink)
 * without a profile is integrated like any other: a mass flying off at 1 m/s moves by the step. */
Test(sim, a_step_of_a_few_ulps_is_integrated)
{
    test_run s;
    flying_off(&s);
    double t0 = s.d.run.t, d0 = s.d.run.x[0], t1 = t0 + 32.0 * DBL_EPSILON * t0, ulp = DBL_EPSILON * fabs(d0);
    cr_assert(t1 - t0 <= VI_BREAKPOINT_ULPS * DBL_EPSILON * t1);
    cr_assert(vi_sim_advance(&s.s, t1) == VI_SIM_OK && s.d.run.t == t1, "%s", s.r.msg);
    cr_assert(fabs(s.d.run.x[0] - (d0 - (t1 - t0))) <= 4.0 * ulp, "delta %.17g -> %.17g over %g s", d0, s.d.run.x[0], t1 - t0);
    test_run_free(&s);
}

/* An input set again to what its ramp already gives (the same value at this time and the same slope,
 * and a and f unchanged) changes nothing and does not restart the solver; each of the six (yC_in, its
 * slope, F_ext, its slope, a, f) changed alone restarts it once. A mass flying free (no load), a = 0.1
 * mm at 100 Hz, yC_in ramping at 1 mm/s. */
static void same_inputs_again(test_run *s)
{
    s->d.in.yC_in = vi_ramp_at(&s->d.run.model.yC_in, s->d.run.t), s->d.din.yC_in = s->d.run.model.yC_in.du;
    s->d.in.F_ext = vi_ramp_at(&s->d.run.model.F_ext, s->d.run.t), s->d.din.F_ext = s->d.run.model.F_ext.du;
    s->d.run.inputs_changed = 1;
}

Test(sim, only_a_changed_input_restarts_the_solver)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 0.0, s.d.par.g = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = 1.0;
    s.d.par.a = 1e-4, s.d.par.f = 100.0;
    s.d.din.yC_in = 1e-3;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    double t = 0.0;
    vi_solver_stats st;
    cr_assert(vi_sim_advance(&s.s, t += 1e-3) == VI_SIM_OK, "%s", s.r.msg);
    for (int k = 0; k < 6; k++) {
        vi_sim_statistics(&s.s, &st);
        long resets = st.resets;
        same_inputs_again(&s);
        cr_assert(vi_sim_advance(&s.s, t += 1e-3) == VI_SIM_OK, "%s", s.r.msg);
        vi_sim_statistics(&s.s, &st);
        cr_assert(st.resets == resets, "k %d: restarted for an unchanged input (%ld -> %ld)", k, resets, st.resets);
        same_inputs_again(&s);
        switch (k) {
        case 0: s.d.in.yC_in += 1e-9; break;
        case 1: s.d.din.yC_in = 2e-3; break;
        case 2: s.d.in.F_ext = -1e-3; break;
        case 3: s.d.din.F_ext = -1e-3; break;
        case 4: s.d.par.a = 2e-4; break;
        case 5: s.d.par.f = 101.0; break;
        }
        cr_assert(vi_sim_advance(&s.s, t += 1e-3) == VI_SIM_OK, "%s", s.r.msg);
        vi_sim_statistics(&s.s, &st);
        cr_assert(st.resets == resets + 1, "k %d: %ld -> %ld restarts", k, resets, st.resets);
    }
    test_run_free(&s);
}

/* The Zeno rule's bound: an event VI_ZENO_ULPS ulps of time after the one before counts (the count
 * grows by one), one ulp more does not (the count starts again); the ulp is that of the later time,
 * negative times alike. */
Test(sim, zeno_count_at_its_bound)
{
    double ulp = nextafter(1.0, 2.0) - 1.0; /* of times in [1, 2) */
    cr_assert(vi_hybrid_zeno_count(5, 1.0, 1.0 + VI_ZENO_ULPS * ulp) == 6);
    cr_assert(vi_hybrid_zeno_count(5, 1.0, 1.0 + (VI_ZENO_ULPS + 1.0) * ulp) == 0);
    cr_assert(vi_hybrid_zeno_count(0, -1.5 - VI_ZENO_ULPS * ulp, -1.5) == 1);
    cr_assert(vi_hybrid_zeno_count(0, -1.5 - (VI_ZENO_ULPS + 1.0) * ulp, -1.5) == 0);
    cr_assert(vi_hybrid_zeno_count(63, 1.0, 1.0) == 64);
}

/* A reset goes back to the defaults and frees the solver, keeping the resources folder and the logger;
 * no folder (NULL) is the empty one. */
Test(sim, reset_keeps_the_resources_folder)
{
    test_run s;
    running(&s);
    vi_run_set_resources(&s.r, "/opt/fmu/resources");
    s.d.par.m = 3.0;
    test_run_reset(&s);
    cr_assert(strcmp(s.r.resources, "/opt/fmu/resources") == 0, "'%s'", s.r.resources);
    cr_assert(s.s.solver == NULL && s.d.par.m != 3.0 && s.d.run.initialized == 0 && s.r.log == quiet);
    vi_run_set_resources(&s.r, NULL);
    cr_assert(s.r.resources[0] == '\0');
    test_run_free(&s);
}

/* The outputs right after the initialization are those of the initial state (the check of their
 * finiteness computes them all; none is left from before): a static Hertz start. */
Test(sim, outputs_after_initialization_are_those_of_the_initial_state)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    vi_outputs out;
    test_run_outputs(&s, &out);
    double W = s.d.run.model.body.W0, d = pow(W / s.d.run.model.contact[0].K, 2.0 / 3.0);
    cr_assert(out.delta == s.d.run.x[0] && fabs(out.delta - d) <= 1e-12 * d && out.v == 0.0 && out.mode == VI_Mode_elastic &&
              out.contact == 1 && fabs(out.F - W) <= 1e-12 * W, "delta %g v %g mode %d F %g", out.delta, out.v, out.mode, out.F);
    test_run_free(&s);
}

/* Preparing again (as every read in initialization mode does, after parameters were set) drops the
 * outputs computed before: the static force follows a load that changed in between. */
Test(sim, preparing_again_drops_the_outputs_computed_before)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    cr_assert(vi_run_prepare(&s.r) == 0, "%s", s.r.msg);
    double W = s.d.run.model.body.W0;
    cr_assert(fabs(vi_contact_outputs_of(&s, VI_OUT_FORCE)->F - W) <= 1e-12 * W);
    s.d.par.P *= 2.0;
    cr_assert(vi_run_prepare(&s.r) == 0, "%s", s.r.msg);
    double W2 = s.d.run.model.body.W0, F2 = vi_contact_outputs_of(&s, VI_OUT_FORCE)->F;
    cr_assert(W2 > 1.5 * W && fabs(F2 - W2) <= 1e-12 * W2, "F = %g after the load went from %g to %g", F2, W, W2);
    test_run_free(&s);
}

/* A guard within rounding of zero (here delta = 1e-310 m in contact, far below the rounding noise of
 * the contact guard) when an input changes gets the band of a guard at zero (band_at_contact). */
Test(sim, a_guard_within_rounding_of_zero_gets_the_band_of_its_noise)
{
    test_run s;
    test_run_init(&s, quiet, NULL);
    s.d.par.contact_model = VI_ContactModel_hertz;
    s.d.par.P = 0.0, s.d.par.g = 0.0, s.d.par.init = VI_Init_touching, s.d.par.v0 = -0.1;
    cr_assert(vi_sim_initialize(&s.s) == 0, "%s", s.r.msg);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_elastic && s.d.run.events.band[0] == band_at_contact(&s), "band %g", s.d.run.events.band[0]);
    s.d.run.events.band[0] = 0.0;
    s.d.run.x[0] = 1e-310;
    s.d.in.F_ext = 1.0;
    s.d.run.inputs_changed = 1;
    cr_assert(vi_sim_advance(&s.s, 1e-9) == VI_SIM_OK, "%s", s.r.msg);
    cr_assert(s.d.run.model.contact[0].mode == VI_Mode_elastic && s.d.run.events.band[0] == band_at_contact(&s) && s.d.run.events.band[1] == 0.0,
              "bands %g %g", s.d.run.events.band[0], s.d.run.events.band[1]);
    /* the bound: a guard exactly at its rounding noise (VI_GRAZE_ULPS times its change over one ulp of
     * delta, plus DBL_MIN) counts as zero, one ulp above it does not */
    const double noise = VI_GRAZE_ULPS * nextafter(0.0, 1.0) + DBL_MIN, at[2] = {noise, nextafter(noise, 1.0)};
    for (int k = 0; k < 2; k++) {
        s.d.run.events.band[0] = 0.0;
        s.d.run.x[0] = at[k];
        s.d.in.F_ext += 1.0;
        s.d.run.inputs_changed = 1;
        cr_assert(vi_sim_advance(&s.s, s.d.run.t + 1e-9) == VI_SIM_OK, "%s", s.r.msg);
        cr_assert(s.d.run.events.band[0] == (k ? 0.0 : band_at_contact(&s)), "delta %g: band %g", at[k], s.d.run.events.band[0]);
    }
    test_run_free(&s);
}

/* ---- the solver's warnings: relayed once a kind, counted exactly ----------------------------------- */

#define KIND_A "CVODE CVode: Internal t = %.17g and h = %g are such that t + h = t on the next step."

/* 1005 warnings of one kind (numbers of every form: 1, 1.0000000000000002, 1e-18, -3.5E+07), 3 of a
 * second, one each of two more (four kinds are remembered), 5 of further kinds (two ending in a cut
 * number): the first of each remembered kind is relayed with the contact's time scale, the report
 * gives 1004 and 2 more and 5 of other kinds, a report with nothing new says nothing, and a kind seen before is only
 * counted in the next. */
Test(sim, solver_warnings_are_relayed_once_a_kind_and_counted_exactly)
{
    test_run s;
    n_logged = 0, log_category = VI_LOG_WARNING;
    test_run_init(&s, capture, NULL);
    cr_assert(vi_sim_initialize(&s.s) == 0 && n_logged == 0, "%s", s.r.msg);
    for (int i = 0; i < 1000; i++) vi_sim_solver_log(&s.s, VI_LOG_WARNING, KIND_A, 1.0 + i * DBL_EPSILON, i * 1e-18);
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "The above warning has been issued 10 times.");
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, KIND_A, -3.5e7, -3.5e7);
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "The above warning has been issued 11 times.");
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "The above warning has been issued 12 times.");
    for (int i = 0; i < 4; i++) vi_sim_solver_log(&s.s, VI_LOG_WARNING, KIND_A, 2.0, 5e-300);
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "kind C");
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "kind D at t = 1");
    for (int i = 0; i < 3; i++) vi_sim_solver_log(&s.s, VI_LOG_WARNING, "kind %c", 'E' + i);
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "kind D at t = 1e"); /* numbers cut at the end: other kinds */
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "kind D at t = -");
    cr_assert(n_logged == 4, "%d relayed", n_logged);
    cr_assert(strncmp(logged[0], "CVODE CVode: Internal t = 1 and h = 0 are such that t + h = t on the next step. (the "
                      "contact's time scale sqrt(m/k) = ", 106) == 0, "%s", logged[0]);
    cr_assert(strstr(logged[0], "further warnings like this one are counted, not repeated)"), "%s", logged[0]);
    cr_assert(strncmp(logged[1], "The above warning has been issued 10 times. (", 45) == 0, "%s", logged[1]);
    cr_assert(strncmp(logged[2], "kind C (", 8) == 0 && strncmp(logged[3], "kind D at t = 1 (", 17) == 0, "%s", logged[3]);
    vi_sim_report_warnings(&s.s);
    cr_assert(n_logged == 7, "%d", n_logged);
    cr_assert(strcmp(logged[4], "1004 more solver warnings like \"CVODE CVode: Internal t = 1 and h = 0 are such that "
                     "t + h = t on the next step.\" by t = 0 s (counted, not relayed)") == 0, "%s", logged[4]);
    cr_assert(strcmp(logged[5], "2 more solver warnings like \"The above warning has been issued 10 times.\" by t = 0 s "
                     "(counted, not relayed)") == 0, "%s", logged[5]);
    cr_assert(strcmp(logged[6], "5 more solver warnings of other kinds by t = 0 s (counted, not relayed)") == 0, "%s",
              logged[6]);
    vi_sim_report_warnings(&s.s);
    cr_assert(n_logged == 7, "a second report repeats: %s", logged[7]);
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "kind D at t = 2.5e-3");
    cr_assert(n_logged == 7, "a kind seen before relayed again: %s", logged[7]);
    cr_assert(vi_sim_advance(&s.s, 1e-4) == VI_SIM_OK, "%s", s.r.msg); /* every advance ends with a report */
    cr_assert(n_logged == 8 && strncmp(logged[7], "1 more solver warnings like \"kind D at t = 1\" by t = 0.0001 s", 60) == 0,
              "%d: %s", n_logged, logged[7]);
    test_run_free(&s);
}

/* A run initialized with its warnings captured (nothing logged yet): the relay's tests below. */
static void relay_run(test_run *s)
{
    n_logged = 0, log_category = VI_LOG_WARNING;
    test_run_init(s, capture, NULL);
    cr_assert(vi_sim_initialize(&s->s) == 0 && n_logged == 0, "%s", s->r.msg);
}

/* With every kind remembered, a warning of another kind alone is still reported, counted among the others. */
Test(sim, solver_warnings_of_other_kinds_alone_are_reported)
{
    test_run s;
    relay_run(&s);
    for (int i = 0; i < VI_RELAY_KINDS; i++) vi_sim_solver_log(&s.s, VI_LOG_WARNING, "kind %c", 'A' + i);
    vi_sim_report_warnings(&s.s);
    cr_assert(n_logged == VI_RELAY_KINDS, "%d: %s", n_logged, logged[n_logged - 1]);
    vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", "another kind");
    vi_sim_report_warnings(&s.s);
    cr_assert(n_logged == VI_RELAY_KINDS + 1 &&
              strcmp(logged[VI_RELAY_KINDS], "1 more solver warnings of other kinds by t = 0 s (counted, not relayed)") == 0,
              "%d: %s", n_logged, logged[n_logged - 1]);
    test_run_free(&s);
}

/* A number in a warning may start with a sign or a point before its digit ("+2", "-3", ".5"): the
 * warnings that differ from the first only there are of its kind, counted, not relayed. */
Test(sim, solver_warnings_numbers_may_start_with_a_sign_or_a_point)
{
    test_run s;
    relay_run(&s);
    const char *texts[] = {"step at t = 1 s", "step at t = +2 s", "step at t = -3 s", "step at t = .5 s"};
    for (int i = 0; i < 4; i++) vi_sim_solver_log(&s.s, VI_LOG_WARNING, "%s", texts[i]);
    cr_assert(n_logged == 1, "%d relayed, the last: %s", n_logged, logged[n_logged - 1]);
    vi_sim_report_warnings(&s.s);
    cr_assert(n_logged == 2 && strcmp(logged[1], "3 more solver warnings like \"step at t = 1 s\" by t = 0 s (counted, not "
                                                 "relayed)") == 0, "%d: %s", n_logged, logged[n_logged - 1]);
    test_run_free(&s);
}
