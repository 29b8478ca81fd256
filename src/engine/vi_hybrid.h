/*
 * vi_hybrid.h - the hybrid automaton's event handling, one engine under both drivers: Co-Simulation
 * (vi_sim.c, which integrates between events with its own solver) and Model Exchange (vi_me.c,
 * where the importer integrates). The engine owns the rules: the guards as the integrator sees them
 * (shifted by bands), their noise, arming and re-arming, input jumps, kinks of the rolling profile,
 * state events, the Zeno rule and the event log. It works on the model (vi_model.h) and its own
 * state; the drivers only decide when to call it and who integrates.
 *
 * Bands. After an event that keeps the mode (grazing) the guard that fired sits at zero, and
 * integration error or rounding alone could take it below zero again and again. It is disarmed:
 * shifted up by a band until it has moved above that band, VI_GRAZE_TOL times its change under a
 * state error of the tolerance (rtol |q| + atol per integrated state q) plus VI_GRAZE_ULPS times
 * its change under one ulp of t and of each integrated state. A guard of a mode just entered (or of
 * a state just changed from outside) that starts at zero up to rounding gets the same band: the mode
 * was chosen because the motion goes inside, and a mode left tangentially (stick exit, where the
 * rate of delta is zero) would otherwise see its guard cross back and forth within the integration
 * error. A real crossing is found at most the band late, and the state is snapped onto the surface.
 *
 * The integrated states q are those the integrator holds: (delta, v) in Co-Simulation, (y, v) with
 * delta = yC(t) - y in Model Exchange (vi_hybrid_bind's integrates_y), so the noise is that of the numbers
 * actually integrated.
 *
 * The engine owns the model's state and its own: nothing outside this header and the model writes
 * them (the functions under "the engine's state" below set up, restore and feed them).
 *
 * The event log (category VI_LOG_EVENTS) has one line per event and contact, key=value pairs
 * separated by single spaces (doc/using.md, "The event log"):
 *   event t=<s> kind=start mode=<m> delta=<m> v=<m/s>[ contact=<c>]
 *   event t=<s> kind=guard guard=<g> mode=<a>-><b> delta=<m> v=<m/s>[ contact=<c>]
 *   event t=<s> kind=input mode=<a>-><b>[ contact=<c>]
 *   event t=<s> kind=kink mode=<a>-><b>[ contact=<c>]
 * t with 17 significant digits; input and kink lines only for a contact whose mode changed. The
 * engine is sized by the model's contacts: VI_NGUARDS guards and bands, VI_CONTACT_NGUARDS per
 * contact; guard g belongs to contact g / VI_CONTACT_NGUARDS. A line's mode and delta are its
 * contact's (its own indentation); with an upper contact every line ends in contact=lower or
 * contact=upper, and a start logs one line per contact; with one contact there is no such field.
 */
#ifndef VI_HYBRID_H
#define VI_HYBRID_H

#include "vi_model.h"
#include "vi_log.h"

#define VI_GRAZE_TOL 4.0
#define VI_GRAZE_ULPS 256.0
/* Zeno: VI_ZENO_EVENTS consecutive state events, each within VI_ZENO_ULPS units in the last place of
 * t after the one before, are events accumulating at one instant. (Regular events, however many,
 * are a matter of the drivers' work bounds.) */
#define VI_ZENO_EVENTS 64
#define VI_ZENO_ULPS 1024.0

/* The engine's part of an FMU state (plain data). */
typedef struct {
    double rtol, atol[2]; /* the integrator's tolerances (relative; atol of delta or y [m] and of v [m/s]) */
    double band[VI_NGUARDS]; /* > 0: the guard is disarmed and shifted up by this (its unit) */
    double t_count;          /* time [s] the Zeno count runs from: the last state event, or a count start */
    int zeno;                /* consecutive state events each within VI_ZENO_ULPS of the one before */
    long n_events;           /* state events so far */
} vi_hybrid_state;

/* The engine of one driver: its model and state (both inside the driver's data, which never moves),
 * and what it logs through. Not part of an FMU state. */
typedef struct {
    vi_model *model;
    vi_hybrid_state *st;
    int integrates_y; /* Model Exchange: the integrator holds y = yC(t) - delta, not delta */
    vi_log_fn log;
    void *log_env;
} vi_hybrid;

void vi_hybrid_bind(vi_hybrid *h, vi_model *model, vi_hybrid_state *st, int integrates_y, vi_log_fn log, void *log_env);

/* ---- the engine's state ---------------------------------------------------------------------------
 * The model (its constants, inputs, mode and memory) and the engine's own state (vi_hybrid_state)
 * change only through the functions of this header: the run sets them up and restores them, the
 * drivers set inputs and call the events. Everyone reads them through the views below. */

/* The model as the engine runs it, and the engine's state: read-only views. */
static inline const vi_model *vi_hybrid_model(const vi_hybrid *h) { return h->model; }
static inline const vi_hybrid_state *vi_hybrid_state_of(const vi_hybrid *h) { return h->st; }
/* The lower contact's mode (VI_MODE_*, the output `mode`), and the state events so far. */
static inline int vi_hybrid_mode(const vi_hybrid *h) { return vi_model_mode(h->model); }
static inline long vi_hybrid_event_count(const vi_hybrid *h) { return h->st->n_events; }
/* Every contact's mode as one number, mode + 8 mode_upper (VI_MODE_* < 8): two are equal exactly when
 * each contact's mode is (the lower contact's mode alone without an upper contact). */
static inline int vi_hybrid_modes(const vi_hybrid *h)
{
    int modes = 0;
    for (int i = h->model->ncontacts - 1; i >= 0; i--) modes = 8 * modes + h->model->contact[i].mode;
    return modes;
}
/* The inputs the model runs, as ramps. */
static inline void vi_hybrid_inputs(const vi_hybrid *h, vi_ramp *yC_in, vi_ramp *F_ext)
{
    *yC_in = h->model->yC_in;
    *F_ext = h->model->F_ext;
}
/* Set the model up from its parameters at the start time t0 (vi_model_setup): 0, or -1 with msg. */
int vi_hybrid_setup(vi_hybrid *h, const vi_model_params *p, double t0, char *msg, size_t n);
/* Roll over profile (NULL: none) at speed V from x0 (vi_model_set_rolling): at set-up, and after a
 * restore, which never trusts the profile pointer of a saved state. 0, or -1 with msg. */
int vi_hybrid_set_rolling(vi_hybrid *h, const vi_profile *profile, double V, double x0, char *msg, size_t n);
/* The initial state at t: the inputs run these ramps, the model starts (vi_model_initial_state: mode,
 * memory, f_contact, and the state x), and the engine's own state is cleared (no event yet, the Zeno
 * count from t; the tolerances come with vi_hybrid_start). */
void vi_hybrid_prepare(vi_hybrid *h, double t, vi_ramp yC_in, vi_ramp F_ext, int init, double v0, double x[2]);
/* The inputs run these ramps, taken as they are: the state and the mode stay (Model Exchange restates
 * the initial inputs at the rates it runs). */
void vi_hybrid_hold_inputs(vi_hybrid *h, vi_ramp yC_in, vi_ramp F_ext);
/* Continuous-time inputs (Model Exchange): from t on the inputs run these ramps, delta moves with the
 * platform while the mass stays (vi_model_set_inputs); nothing is written down and no mode chosen
 * (the event indicators flag a jump that contradicts the mode). */
void vi_hybrid_follow_inputs(vi_hybrid *h, double t, double x[2], vi_ramp yC_in, vi_ramp F_ext);
/* Write down the memory that tracks the state at (t, x) (vi_model_freeze on a copy of x: the state
 * is the integrator's and stays as it is). */
void vi_hybrid_write_down(vi_hybrid *h, double t, const double x[2]);

/* A simulation starts at (t, x) with these tolerances: no event yet, guards at zero armed. */
void vi_hybrid_start(vi_hybrid *h, double rtol, const double atol[2], double t, const double x[2]);
/* Log the initial mode and state (t, x) (kind=start). */
void vi_hybrid_log_start(const vi_hybrid *h, double t, const double x[2]);
/* The Zeno count starts afresh at t (Co-Simulation: each advance). */
static inline void vi_hybrid_count_from(vi_hybrid *h, double t)
{
    h->st->zeno = 0;
    h->st->t_count = t;
}

/* The guards as the integrator sees them: the model's, each disarmed one shifted up by its band
 * (inline: the integrators evaluate it at every step). */
static inline void vi_hybrid_guards(const vi_hybrid *h, double t, const double x[2], double g[VI_NGUARDS])
{
    vi_model_guards(h->model, t, x, g);
    for (int i = 0; i < VI_NGUARDS; i++) g[i] += h->st->band[i];
}
/* Disarmed guards that have moved above their band are armed again (inline: the drivers ask at every
 * step, and most steps have no band). */
void vi_hybrid_rearm_banded(vi_hybrid *h, double t, const double x[2]);
static inline void vi_hybrid_rearm(vi_hybrid *h, double t, const double x[2])
{
    int any = 0;
    for (int i = 0; i < VI_NGUARDS; i++) any |= h->st->band[i] > 0.0;
    if (any) vi_hybrid_rearm_banded(h, t, x);
}
/* Guards at zero up to rounding, not disarmed, get their band (see above). */
void vi_hybrid_arm_at_zero(vi_hybrid *h, double t, const double x[2]);

/* The first guard at or below zero as the integrator sees it at (t, x), -1 when none; *located: it
 * lies within its band of zero (a crossing the integrator located, to be snapped onto its surface)
 * rather than clearly beyond (a state stepped or set past the surface). */
int vi_hybrid_fired(const vi_hybrid *h, double t, const double x[2], int *located);
/* Is a guard (as the integrator sees it) strictly below zero at (t, x)? */
int vi_hybrid_due(const vi_hybrid *h, double t, const double x[2]);

/* Do these inputs (ramps) differ from those the model runs, in their values at t or their rates?
 * (inline: Model Exchange asks at every evaluation) */
static inline int vi_hybrid_inputs_differ(const vi_hybrid *h, double t, vi_ramp yC_in, vi_ramp F_ext)
{
    const vi_model *model = h->model;
    return yC_in.du != model->yC_in.du || F_ext.du != model->F_ext.du ||
           vi_ramp_at(&yC_in, t) != vi_ramp_at(&model->yC_in, t) || vi_ramp_at(&F_ext, t) != vi_ramp_at(&model->F_ext, t);
}
/* An input jump at t (inputs and the tunable excitation): when they differ from what the model runs,
 * take them, move the platform with a new a, choose the mode afresh, log a change of mode, reset and
 * arm the bands, and return 1; else 0 (the same signal: nothing happens). */
int vi_hybrid_input_jump(vi_hybrid *h, double t, double x[2], vi_ramp yC_in, vi_ramp F_ext, double a, double f);
/* A kink of the rolling profile at t (the platform velocity jumps): choose the mode afresh, log a
 * change, reset and arm the bands. */
void vi_hybrid_kink(vi_hybrid *h, double t, double x[2]);
/* A state event at t: guard `fired` of its contact's current mode reached zero. located: snap onto
 * its surface (vi_model_event); else choose the modes of the state as it is (freeze,
 * vi_model_resolve). The mode is chosen with the inputs' ramps the guards see (one notion of the
 * platform's rate: a guard cannot fire again at the same instant because the choice saw another
 * rate). Counts and logs the event; a change of the contact's mode resets its bands, grazing
 * disarms the guard that fired. Returns the contact's mode before. The driver then arms the guards
 * at zero (vi_hybrid_arm_at_zero) at the state as its integrator holds it. */
int vi_hybrid_event(vi_hybrid *h, double t, double x[2], int fired, int located);
/* After a state event at t on guard `fired` of mode `from`: do events accumulate (the Zeno rule)?
 * Then 1, with the message in msg naming the time, the guard and its mode. */
int vi_hybrid_zeno(const vi_hybrid *h, double t, int fired, int from, char *msg, size_t n);
/* The Zeno rule alone: the count after one more state event at t, the one before at t_before. */
int vi_hybrid_zeno_count(int count, double t_before, double t);

/* Is st a state this engine could have produced? 0, or -1 with the first bad field in msg. */
int vi_hybrid_check(const vi_hybrid_state *st, double t, char *msg, size_t n);

#endif
