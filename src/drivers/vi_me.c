/* vi_me.c - the contact model advanced by an importer's integrator (Model Exchange); see vi_me.h. */
#include "vi_me.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vi_check.h"

static double platform(const vi_model *model, double t) { return vi_model_platform(model, t, NULL, NULL); }

/* The model as the engine runs it (read only: the engine changes it). */
static inline const vi_model *model_of(const vi_me *e) { return vi_hybrid_model(&e->engine); }

/* The inputs from t on: their values (Model Exchange passes no derivatives: F_ext is held); yC_in at
 * the rate vC_in with velocity_input (vi_run_input_ramps), else at the rate estimated at the last
 * completed step. */
static void input_ramps(const vi_me *e, double t, vi_ramp *yC_in, vi_ramp *F_ext)
{
    vi_run_input_ramps(e->r, t, yC_in, F_ext);
    if (!e->r->set.velocity_input) yC_in->du = e->own->yC_in_rate;
    F_ext->du = 0.0;
}

/* Bring the model in step with the importer's time, states and inputs: delta = yC(t) - y. Setting the
 * time or the states only marks the model stale, and the setters of inputs store them only, so the
 * model catches up here, before anything is read: every answer is that of the last (t, y, v, inputs)
 * whatever the order they were set in. Inputs set in continuous-time mode act at once, as the
 * continuous functions of time FMI makes them: the mass stays where it is, and nothing is written
 * down (the integrator evaluates at trial points it may reject; the memory is written down at
 * completed steps and events); inputs set in event mode (d->inputs_changed, from the layer's
 * `changed`) wait for the event iteration, which applies them as a jump. */
static void sync(vi_me *e)
{
    vi_run_data *d = e->d;
    if (!e->active) return; /* before initialization: the run as prepared */
    vi_ramp yC_in, F_ext;
    input_ramps(e, d->t, &yC_in, &F_ext);
    int take = !d->inputs_changed && vi_hybrid_inputs_differ(&e->engine, d->t, yC_in, F_ext);
    if (!e->stale && !take) return;
    e->stale = 0;
    e->r->out_valid = 0;
    if (take) vi_hybrid_follow_inputs(&e->engine, d->t, d->x, yC_in, F_ext);
    d->x[0] = platform(model_of(e), d->t) - e->own->y_me; /* the importer holds y: delta follows from it */
}

/* A step completed or an event handled at the current time: the next step starts here. */
static void mark_step(vi_me *e)
{
    vi_run_data *d = e->d;
    d->step_t0 = d->t;
    d->step_v0 = d->x[1];
    e->own->step_u0 = vi_ramp_at(&model_of(e)->yC_in, d->t);
}

void vi_me_init(vi_me *e, vi_run *r, vi_me_data *d)
{
    memset(e, 0, sizeof *e);
    e->r = r, e->own = d;
    e->d = vi_run_attach(r, &e->engine, d, sizeof *d);
}

/* Bind the event engine to the integrated position y (Model Exchange) and start the driver's own state. */
static void start_driver(vi_me *e, int active)
{
    vi_run_bind_engine(e->r, &e->engine, active);
    e->active = active;
    e->stale = 1;
}

int vi_me_initialize(vi_me *e)
{
    vi_run *r = e->r;
    if (vi_run_prepare(r) < 0) return -1;
    vi_run_data *d = r->d;
    const vi_model *model = model_of(e);
    double rtol, atol[2];
    vi_ramp yC_in, F_ext;
    vi_run_tolerances(r, &rtol, atol); /* the scales of the initial state as prepared */
    d->initialized = 1;
    vi_run_warn_settings(r);
    e->own->yC_in_rate = 0.0;
    input_ramps(e, d->t, &yC_in, &F_ext);
    vi_hybrid_hold_inputs(&e->engine, yC_in, F_ext);
    mark_step(e);
    e->warned_rate = 0;
    e->own->y_me = platform(model, d->t) - d->x[0];
    e->active = 1;
    e->stale = 1;
    sync(e);
    vi_run_bind_engine(r, &e->engine, 1);
    vi_hybrid_start(&e->engine, rtol, atol, d->t, d->x); /* at the state as the importer holds it */
    double nominal[VI_ME_NSTATES];
    vi_me_nominals(e, nominal);
    r->log(r->log_env, VI_LOG_SOLVER, "Model Exchange: the importer integrates y, v and W_damping (nominals %g m, %g m/s, "
           "%g J); initial mode %d, delta = %.9g m, v = %.9g m/s", nominal[0], nominal[1], nominal[2], vi_model_mode(model),
           d->x[0], d->x[1]);
    return 0;
}

void vi_me_set_time(vi_me *e, double t)
{
    e->d->t = t;
    e->stale = 1;
}

void vi_me_get_states(vi_me *e, double x[VI_ME_NSTATES])
{
    const vi_run_data *d = e->d;
    x[0] = e->active ? e->own->y_me : platform(model_of(e), d->t) - d->x[0]; /* before: the initial state prepared */
    x[1] = d->x[1];
    x[2] = d->W_damping;
}

void vi_me_set_states(vi_me *e, const double x[VI_ME_NSTATES])
{
    e->own->y_me = x[0];
    e->d->x[1] = x[1];
    e->d->W_damping = x[2];
    e->stale = 1;
}

void vi_me_derivatives(vi_me *e, double dx[VI_ME_NSTATES])
{
    sync(e);
    const vi_run_data *d = e->d;
    double r[2];
    vi_model_rhs(model_of(e), d->t, d->x, r);
    dx[0] = d->x[1];
    dx[1] = r[1];
    dx[2] = vi_model_damping_power(model_of(e), d->t, d->x).P;
}

void vi_me_indicators(vi_me *e, double z[VI_ME_NINDICATORS])
{
    sync(e);
    vi_hybrid_guards(&e->engine, e->d->t, e->d->x, z);
}

void vi_me_nominals(const vi_me *e, double nominal[VI_ME_NSTATES])
{
    const vi_hybrid_state *h = vi_hybrid_state_of(&e->engine);
    for (int i = 0; i < 2; i++) nominal[i] = e->active && h->atol[i] > 0.0 ? h->atol[i] / h->rtol : 1.0;
    nominal[2] = e->active && h->atol[1] > 0.0 ? model_of(e)->body.m * nominal[1] * nominal[1] : 1.0; /* m V^2 [J] */
}

/* The end of a non-periodic profile at or before t: 1 with the reason in msg. */
static int past_profile_end(const vi_model *model, double t, char *msg, size_t n)
{
    return t >= vi_model_rolling_limit(model, msg, n);
}

/* The time events of one pass, in x (a copy of the state): inputs and tunable a, f set in event mode
 * (an input jump), and a kink of the profile passed since the last step. */
static void time_events(vi_me *e, double x[2])
{
    vi_run_data *d = e->d;
    double t = d->t;
    double a, f;
    vi_run_excitation(e->r, &a, &f);
    if (d->inputs_changed || vi_model_excitation_differs(model_of(e), a, f)) {
        vi_ramp yC_in, F_ext;
        vi_hybrid_inputs(&e->engine, &yC_in, &F_ext);
        if (d->inputs_changed) input_ramps(e, t, &yC_in, &F_ext);
        d->inputs_changed = 0;
        vi_hybrid_input_jump(&e->engine, t, x, yC_in, F_ext, a, f);
    }
    if (vi_model_next_breakpoint(model_of(e), d->step_t0) <= t) vi_hybrid_kink(&e->engine, t, x);
}

/* The first guard at or below zero, as a state event. Returns the guard, or -1 when none fired; *from:
 * the mode it belonged to. */
static int state_event(vi_me *e, double x[2], int *from)
{
    vi_run_data *d = e->d;
    int located, fired = vi_hybrid_fired(&e->engine, d->t, x, &located);
    if (fired < 0) return -1;
    *from = vi_hybrid_event(&e->engine, d->t, x, fired, located);
    return fired;
}

/* Take x (the state after the pass) as the importer's: y moves only when x moved. */
static void take_state(vi_me *e, const double x[2], vi_me_event *ev)
{
    vi_run_data *d = e->d;
    if (x[0] != d->x[0] || x[1] != d->x[1]) { /* snapped, frozen onto the platform, or a new a */
        ev->states_changed = 1;
        e->own->y_me = platform(model_of(e), d->t) - x[0];
        d->x[1] = x[1];
    }
    d->x[0] = platform(model_of(e), d->t) - e->own->y_me;
}

int vi_me_event_update(vi_me *e, vi_me_event *ev)
{
    vi_run_data *d = e->d;
    memset(ev, 0, sizeof *ev);
    sync(e);
    double t = d->t, x[2] = {d->x[0], d->x[1]};
    if (past_profile_end(model_of(e), t, e->r->msg, sizeof e->r->msg)) {
        ev->terminate = 1;
        return 0;
    }
    time_events(e, x);
    int from = vi_hybrid_mode(&e->engine), fired = state_event(e, x, &from);
    take_state(e, x, ev);
    vi_hybrid_arm_at_zero(&e->engine, t, d->x); /* at the state as the importer holds it */
    ev->another_pass = vi_hybrid_due(&e->engine, t, d->x);
    mark_step(e);
    vi_run_check_validity(e->r);
    if (fired >= 0 && vi_hybrid_zeno(&e->engine, t, fired, from, e->r->msg, sizeof e->r->msg)) ev->terminate = 1;
    char why[8];
    double next = fmin(vi_model_next_breakpoint(model_of(e), t), vi_model_rolling_limit(model_of(e), why, sizeof why));
    if (isfinite(next) && next > t) ev->next_time_defined = 1, ev->next_time = next;
    e->r->out_valid = 0;
    return 0;
}

void vi_me_enter_continuous(vi_me *e)
{
    e->d->inputs_changed = 0;
    sync(e);
}

/* The rate of yC_in over the step that just completed becomes the rate the model runs until the next
 * completed step (without velocity_input): one notion of the platform's rate for the event indicators
 * and the mode choices. Its first change while the law needs the rate is warned of once. */
static void estimate_rate(vi_me *e)
{
    vi_run_data *d = e->d;
    double h = d->t - d->step_t0;
    if (e->r->set.velocity_input || !(h > 0.0)) return;
    e->own->yC_in_rate = (vi_ramp_at(&model_of(e)->yC_in, d->t) - e->own->step_u0) / h;
    if (e->own->yC_in_rate != 0.0 && !e->warned_rate && vi_model_uses_rate(model_of(e))) {
        e->warned_rate = 1;
        e->r->log(e->r->log_env, VI_LOG_WARNING, "t = %.17g s: yC_in moves (%g m/s) and velocity_input = false: Model "
                 "Exchange passes no input derivatives, so the platform's rate is estimated from yC_in's change over "
                 "each completed step, and turning points, damping and mode choices lag by a step; set velocity_input "
                 "= true and connect the platform's velocity to vC_in for exact results", d->t, e->own->yC_in_rate);
    }
    sync(e); /* the new rate acts from now on (a continuous-time input) */
}

/* While the platform's rate is an estimate (yC_in moves, velocity_input = false), a plastic motion may
 * go on past its turning point for up to a step: its memory is written down at each completed step,
 * so that delta_c and the permanent set never decrease (the memory outputs are never below what was
 * written down). With a known rate the motion stays plastic only while delta grows. The state stays
 * the importer's (vi_hybrid_write_down works on a copy). */
static void write_down(vi_me *e)
{
    vi_run_data *d = e->d;
    if (vi_hybrid_mode(&e->engine) != VI_MODE_PLASTIC || e->r->set.velocity_input || e->own->yC_in_rate == 0.0) return;
    vi_hybrid_write_down(&e->engine, d->t, d->x);
}

int vi_me_completed_step(vi_me *e)
{
    vi_run_data *d = e->d;
    char why[8];
    sync(e);
    if (vi_model_next_breakpoint(model_of(e), d->step_t0) <= d->t || past_profile_end(model_of(e), d->t, why, sizeof why))
        return 1; /* a time event was stepped over: handle it here */
    estimate_rate(e);
    write_down(e);
    if (vi_hybrid_due(&e->engine, d->t, d->x)) return 1; /* the new rate put a guard below zero */
    vi_hybrid_rearm(&e->engine, d->t, d->x);
    mark_step(e);
    vi_run_check_validity(e->r);
    return 0;
}

const vi_run_values *vi_me_outputs_of(vi_me *e, unsigned groups)
{
    vi_run *run = e->r;
    const vi_run_data *d = run->d;
    sync(e);
    const vi_run_values *out = vi_run_outputs_of(run, groups);
    if (e->active && (groups & VI_OUT_FORCE)) run->out.F_peak = run->out.model.F; /* the importer's steps are not seen */
    if (e->active && (groups & VI_OUT_PLATFORM)) run->out.model.y = e->own->y_me; /* the state as set, not yC - delta */
    if ((groups & VI_OUT_DERIVATIVES) && !(run->out_valid & VI_OUT_DERIVATIVES)) {
        double r[2];
        vi_model_rhs(model_of(e), d->t, d->x, r);
        run->out.der_y = d->x[1];
        run->out.der_v = r[1];
        run->out.der_W_damping = vi_model_damping_power(model_of(e), d->t, d->x).P;
        run->out_valid |= VI_OUT_DERIVATIVES;
    }
    return out;
}


int vi_me_checkpoint(vi_me *e)
{
    sync(e); /* the memory stays as written down: a saved state changes nothing that follows */
    return 0;
}

int vi_me_restore(vi_me *e, int running)
{
    if (vi_run_restore(e->r) < 0) return -1;
    start_driver(e, running);
    return 0;
}

/* Every field of the driver's data finite. */
static int me_data_check(const vi_me_data *d, char *msg, size_t n)
{
    if (!isfinite(d->y_me)) VI_FAIL(msg, n, "y_me = %g is not finite", d->y_me);
    if (!isfinite(d->step_u0) || !isfinite(d->yC_in_rate))
        VI_FAIL(msg, n, "step_u0 = %g, yC_in_rate = %g: not finite", d->step_u0, d->yC_in_rate);
    return 0;
}

int vi_me_data_check(const vi_run_data *r, const vi_me_data *d, double t_start, double rtol, char *msg, size_t n)
{
    if (vi_run_data_check(r, t_start, rtol, msg, n) < 0 || me_data_check(d, msg, n) < 0) return -1;
    return vi_run_data_check_model(r, 0, msg, n);
}

int vi_me_data_finite(const vi_me_data *d, char *msg, size_t n) { return me_data_check(d, msg, n); }

/* ---- the Jacobian ---------------------------------------------------------------------------- */

/* An unknown's partials with respect to delta, v, F_ext and yC (directly, not through delta), mapped
 * onto the knowns: delta = yC(t) - y, yC = yC_in + ... (vC_in: set by the caller) */
static vi_me_partials through_delta(double a_d, double a_v, double a_F, double a_yC)
{
    return (vi_me_partials){.y = -a_d, .v = a_v, .yC_in = a_d + a_yC, .F_ext = a_F, .vC_in = 0.0};
}

/* The rows of the energy outputs and of the damping's power: W_dissipated = W_plastic + W_damping (the
 * state's column is the layer's; with an upper contact also its plastic work, whose rate in delta is
 * minus that in its own indentation -gap - delta), E_contact (both contacts'), and F_peak = F. */
static void energy_rows(vi_me *e, vi_me_partials jac[VI_ME_N_UNKNOWNS])
{
    const vi_run_data *d = e->d;
    const vi_model *model = model_of(e);
    double dE;
    vi_model_contact_energy(model, d->x, &dE);
    vi_model_power P = vi_model_damping_power(model, d->t, d->x);
    vi_memory_rates up;
    vi_model_memory_rates(model, VI_UPPER, d->x, &up); /* all 0 without an upper contact */
    jac[VI_ME_DER_W] = through_delta(P.dP_ddelta, -P.dP_drate, 0.0, 0.0); /* delta' = yC' - v */
    if (e->r->set.velocity_input) jac[VI_ME_DER_W].vC_in = P.dP_drate;
    jac[VI_ME_W_DISSIPATED] = jac[VI_ME_W_PLASTIC];
    if (model->ncontacts > 1) jac[VI_ME_W_DISSIPATED].y += up.W_plastic, jac[VI_ME_W_DISSIPATED].yC_in -= up.W_plastic;
    jac[VI_ME_E_CONTACT] = through_delta(dE, 0.0, 0.0, 0.0);
    jac[VI_ME_F_PEAK] = jac[VI_ME_F];
}

/* The rows of the upper contact (force F_upper(delta_u, r_u) with delta_u = -gap - delta, r_u = v - yC';
 * in stick -F_hold), F's row with the lower contact's slopes alone (without an upper contact the
 * model's stiffness and damping are the lower contact's, as vi_me_jacobian writes them), and
 * k_contact's (the sum of both contacts' stiffnesses, each in its own indentation and rate; in the
 * lower contact's stick its stiffness at delta_c alone, a constant). */
static void upper_rows(vi_me *e, vi_me_partials jac[VI_ME_N_UNKNOWNS])
{
    const vi_run_data *d = e->d;
    const vi_model *model = model_of(e);
    jac[VI_ME_F_UPPER] = jac[VI_ME_DELTA_UPPER] = through_delta(0.0, 0.0, 0.0, 0.0);
    if (model->ncontacts < 2) return;
    double k, c, k_up, c_up, k_rate_up, k_per_rate_up;
    vi_model_contact_slopes(model, VI_LOWER, d->t, d->x, &k, &c);
    vi_model_contact_slopes(model, VI_UPPER, d->t, d->x, &k_up, &c_up);
    jac[VI_ME_F] = through_delta(k, -c, vi_model_mode(model) == VI_MODE_STICK ? -1.0 : 0.0, 0.0);
    jac[VI_ME_F_UPPER] = through_delta(-k_up, c_up, model->contact[VI_UPPER].mode == VI_MODE_STICK ? 1.0 : 0.0, 0.0);
    jac[VI_ME_DELTA_UPPER] = through_delta(-1.0, 0.0, 0.0, 0.0);
    if (e->r->set.velocity_input) jac[VI_ME_F].vC_in = c, jac[VI_ME_F_UPPER].vC_in = -c_up;
    if (vi_model_mode(model) == VI_MODE_STICK) return;
    k_rate_up = vi_model_stiffness_rate(model, VI_UPPER, d->t, d->x, &k_per_rate_up); /* d/d(delta_u), d/d(r_u) */
    vi_me_partials *K = &jac[VI_ME_K_CONTACT]; /* d(delta_u)/d(delta) = -1, d(r_u)/dv = 1, d(r_u)/d(vC_in) = -1 */
    K->y += k_rate_up, K->yC_in -= k_rate_up, K->v += k_per_rate_up;
    if (e->r->set.velocity_input) K->vC_in -= k_per_rate_up;
}

void vi_me_jacobian(vi_me *e, vi_me_partials jac[VI_ME_N_UNKNOWNS])
{
    sync(e);
    const vi_run_data *d = e->d;
    const vi_model *model = model_of(e);
    double m = model->body.m, h = d->t - d->step_t0;
    int stick = vi_model_sticks(model);
    double k = stick ? 0.0 : m * vi_model_stiffness_over_mass(model, d->t, d->x); /* dF/ddelta */
    double c = vi_model_damping(model, d->t, d->x), k_per_rate;                 /* dF/ddelta' (delta' = yC' - v) */
    double k_rate = vi_model_stiffness_rate(model, VI_LOWER, d->t, d->x, &k_per_rate);
    vi_memory_rates mem;
    vi_model_memory_rates(model, VI_LOWER, d->x, &mem);
    jac[VI_ME_DER_Y] = through_delta(0.0, 1.0, 0.0, 0.0);
    jac[VI_ME_DER_V] = through_delta(k / m, -c / m, stick ? 0.0 : 1.0 / m, 0.0); /* (F - F_upper - W0 + F_ext)/m; stick: yC'' */
    jac[VI_ME_F] = through_delta(k, -c, stick ? -1.0 : 0.0, 0.0);                /* stick: F_hold = W0 - F_ext + m yC'' */
    jac[VI_ME_F_MEAN] = h > 0.0 ? through_delta(0.0, m / h, -1.0, 0.0)        /* m (v - v0)/h + W0 - F_ext */
                              : jac[VI_ME_F];                                 /* F - F_upper */
    jac[VI_ME_DELTA] = through_delta(1.0, 0.0, 0.0, 0.0);
    jac[VI_ME_Y] = through_delta(-1.0, 0.0, 0.0, 1.0);
    jac[VI_ME_V] = through_delta(0.0, 1.0, 0.0, 0.0);
    jac[VI_ME_YC] = through_delta(0.0, 0.0, 0.0, 1.0);
    jac[VI_ME_K_CONTACT] = through_delta(k_rate, -k_per_rate, 0.0, 0.0);
    jac[VI_ME_DELTA_C] = through_delta(mem.delta_c, 0.0, 0.0, 0.0);
    jac[VI_ME_DELTA_F] = through_delta(mem.delta_f, 0.0, 0.0, 0.0);
    jac[VI_ME_RBAR] = through_delta(mem.Rbar, 0.0, 0.0, 0.0);
    jac[VI_ME_DELTA_P] = through_delta(mem.delta_p, 0.0, 0.0, 0.0);
    jac[VI_ME_W_PLASTIC] = through_delta(mem.W_plastic, 0.0, 0.0, 0.0);
    if (e->r->set.velocity_input) { /* vC_in is the platform's rate in delta' = yC' - v: the partials of -v */
        jac[VI_ME_DER_V].vC_in = c / m;
        jac[VI_ME_F].vC_in = c;
        if (h <= 0.0) jac[VI_ME_F_MEAN].vC_in = c;
        jac[VI_ME_K_CONTACT].vC_in = k_per_rate;
    }
    upper_rows(e, jac);
    energy_rows(e, jac);
}
