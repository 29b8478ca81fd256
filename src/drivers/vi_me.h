/*
 * vi_me.h - the Model Exchange driver: a run of the contact model (vi_run.h) advanced by somebody
 * else's integrator, the model as an ODE with events. It shares the run (model, event engine,
 * outputs, validity warnings) with the Co-Simulation driver (vi_sim.h) and has no solver of its own.
 * Nothing here knows FMI; src/adapter/vi_fmu_contact.c maps the FMI layer's hooks onto these functions.
 *
 * States (the importer integrates them):  y [m], the mass position, v [m/s], its velocity, and W_damping
 * [J], the damping's work (VI_ME_NSTATES below):
 *     y' = v,      v' = (F(delta, mode, memory) - W(t)) / m        (in stick: v' = yC''(t))
 *     W_damping' = (F - F_spring(delta)) delta'                    (vi_model_damping_power)
 * with delta = yC(t) - y (vi_model.h: the platform yC includes the input yC_in, the harmonic
 * excitation and the rolling profile). The position y, not the indentation, is the state, so that
 * the derivatives need the input yC_in only through its value (Model Exchange passes no input
 * derivatives): a new yC_in moves the platform while the mass stays where it is. The model keeps
 * delta in the run's state (x[0]) in step with y.
 *
 * The plastic memory needs no state of its own: while it changes (Johnson loading beyond delta_Y,
 * LEPP flow) it equals delta (delta_c = delta, delta_p = delta - delta_Y) beyond what was written
 * down, and it is written down when that mode is left (vi_model_freeze).
 *
 * Event indicators: the VI_NGUARDS guards of the contacts' current modes, VI_CONTACT_NGUARDS per
 * contact (vi_model.h: contact, separation,
 * yield, Johnson turning point, stick entry and exit, LEPP flow start and end), each > 0 inside the
 * mode; a guard that starts at zero after an event is lifted by its rounding noise and a guard that
 * fired without a change of mode (grazing) by its band (vi_hybrid.h, the event engine both drivers
 * share), until it has moved away; both come back to the plain guard at a completed step.
 *
 * The platform's rate. Model Exchange passes input values only, yet the rate of delta (the turning
 * points, stick, the damping, every choice of mode) needs the rate of yC_in. With velocity_input it is
 * the input vC_in. Without, it is estimated at each completed step from yC_in's change over that step
 * (vi_me_data.yC_in_rate) and used, until the next completed step, by the event indicators and the mode
 * choices alike (one notion: a guard cannot fire again at once because the choice saw another rate);
 * a new estimate that puts a guard below zero asks for an event. While it is an estimate, the plastic
 * memory is written down at completed steps. F_ext is held at its value.
 */
#ifndef VI_ME_H
#define VI_ME_H

#include "vi_run.h"

/* The third state, W_damping [J]: the damping's work, W_damping' = vi_model_damping_power (0 for laws that
 * do not damp), so that W_dissipated = W_plastic + W_damping. F_peak is F: the FMU does not see inside
 * the importer's steps (only its trial points, some of them rejected), and the importer reads F at every
 * point it needs. */
#define VI_ME_NSTATES 3
#define VI_ME_NINDICATORS VI_NGUARDS

/* The driver's part of an FMU state (plain data). */
typedef struct {
    double y_me;       /* the mass position y [m] the importer integrates (delta = yC(t) - y), kept as given so
                          that a restored state gives it back bit for bit */
    double step_u0;    /* yC_in [m] at the run's step_t0 */
    double yC_in_rate; /* without velocity_input: the rate of yC_in [m/s] the model runs, estimated at
                          completed steps (above) */
} vi_me_data;

/* The Model Exchange driver over a run; the states are own->y_me, the run's x[1] (v) and W_damping. */
typedef struct {
    vi_run *r;       /* the run it drives (model, outputs, message) */
    vi_run_data *d;  /* r->d: the run's data */
    vi_me_data *own; /* the driver's data */
    vi_hybrid engine; /* the event engine over the run, for the importer's integrator (y integrated) */
    int active; /* initialized for Model Exchange */
    int stale;  /* time or states set since the model last caught up with them */
    int warned_rate; /* the estimated rate of yC_in was warned of (once per instance) */
} vi_me;

/* What one pass of the event iteration did. */
typedef struct {
    int another_pass, terminate, states_changed, next_time_defined;
    double next_time;
} vi_me_event;

/* Bind the driver to a run and to its own data (zeroed). */
void vi_me_init(vi_me *e, vi_run *r, vi_me_data *d);
/* vi_run_prepare (the initial state), then start the engine for the importer's integrator: 0 or -1
 * (the run's msg). No solver is made. */
int vi_me_initialize(vi_me *e);
void vi_me_set_time(vi_me *e, double t);
/* x = (y, v, W_damping). */
void vi_me_get_states(vi_me *e, double x[VI_ME_NSTATES]);
void vi_me_set_states(vi_me *e, const double x[VI_ME_NSTATES]);
void vi_me_derivatives(vi_me *e, double dx[VI_ME_NSTATES]);
void vi_me_indicators(vi_me *e, double z[VI_ME_NINDICATORS]);
/* The scales of the problem (vi_model_scales: L [m], V [m/s]) once initialized, 1 before. */
void vi_me_nominals(const vi_me *e, double nominal[VI_ME_NSTATES]);
/* One pass of the event iteration at the current time: tunable a, f and inputs set in event mode
 * (as an input change of co-simulation: freeze, move the platform, choose the mode); a kink of the
 * rolling profile passed (time event); the first guard at or below zero (a guard within its band
 * of zero is snapped onto its surface, vi_model_event; one clearly beyond is a state the importer
 * set or stepped to: the mode is chosen for the state as it is, vi_model_resolve). another_pass
 * when a guard of the new mode is still below zero. At the end of a non-periodic profile, and when
 * events accumulate at one instant (VI_ZENO_EVENTS state events each within VI_ZENO_ULPS of the one
 * before): terminate (the run's msg says why). 0, or -1 (the run's msg). */
int vi_me_event_update(vi_me *e, vi_me_event *ev);
/* Continuous-time mode begins: inputs set after the last event-iteration pass act from now on as
 * continuous-time inputs do (at once; the event indicators flag a jump that contradicts the mode). */
void vi_me_enter_continuous(vi_me *e);
/* A completed step of the importer: re-arm guards that moved away, start the mean force anew.
 * 1 when an event is due now (a kink or the profile's end was stepped over), else 0. */
int vi_me_completed_step(vi_me *e);
/* The outputs of `groups` (VI_OUT_*, vi_model.h; VI_OUT_DERIVATIVES: der_y, der_v, der_W_damping) at
 * the current time, states and inputs, as vi_run_outputs_of; the mean force is the one since the
 * last event or completed step. */
const vi_run_values *vi_me_outputs_of(vi_me *e, unsigned groups);
/* Make the run's data hold the current (t, delta, v) and memory before it is copied (FMU state), and
 * take the run back from a restored state (vi_run_restore; `running`: a state taken after
 * initialization, into an instance of Model Exchange). 0 or -1 (the run's msg). */
int vi_me_checkpoint(vi_me *e);
int vi_me_restore(vi_me *e, int running);
/* Is (r, d) a state of Model Exchange this FMU could have produced (doc/model.md section 7.6), with the
 * start time and relative tolerance of its settings? The
 * run's fields (vi_run_data_check), the driver's, then the model's part between events
 * (vi_model_check_between_events: the importer's states may lie beyond the mode's surfaces until
 * the next event). 0, or -1 naming the first bad field in msg. */
int vi_me_data_check(const vi_run_data *r, const vi_me_data *d, double t_start, double rtol, char *msg, size_t n);
/* The driver's fields alone: finite. 0 or -1 (msg). */
int vi_me_data_finite(const vi_me_data *d, char *msg, size_t n);

/* The partial derivatives of one unknown with respect to the knowns: the states y [m], v [m/s] and
 * the inputs yC_in [m], F_ext [N], vC_in [m/s] (nonzero only with velocity_input). */
typedef struct {
    double y, v, yC_in, F_ext, vC_in;
} vi_me_partials;
/* The unknowns: the derivatives of the states and the outputs that move with the states and inputs
 * (every other output and the calculated parameters have zero partials). */
enum {
    VI_ME_DER_Y, VI_ME_DER_V, VI_ME_F, VI_ME_F_MEAN, VI_ME_DELTA, VI_ME_Y, VI_ME_V, VI_ME_YC, VI_ME_K_CONTACT,
    VI_ME_DELTA_C, VI_ME_DELTA_F, VI_ME_RBAR, VI_ME_DELTA_P, VI_ME_W_PLASTIC,
    VI_ME_DER_W, VI_ME_W_DISSIPATED, VI_ME_E_CONTACT, VI_ME_F_PEAK, /* W_dissipated: its W_damping column is 1 */
    VI_ME_F_UPPER, VI_ME_DELTA_UPPER, /* the upper contact's force and indentation (0 without one) */
    VI_ME_N_UNKNOWNS
};
/* The Jacobian at the current point, analytic, in the current mode: jac[unknown]. */
void vi_me_jacobian(vi_me *e, vi_me_partials jac[VI_ME_N_UNKNOWNS]);

#endif
