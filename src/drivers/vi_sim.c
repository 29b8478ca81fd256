/* vi_sim.c - the Co-Simulation driver: the event loop around the solver over a run (vi_run.h). */
#include "vi_sim.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "vi_check.h"
#include "vi_format.h"

/* The model as the engine runs it (read only: the engine changes it). */
static inline const vi_model *model_of(const vi_sim *s) { return vi_hybrid_model(&s->engine); }

static void sim_rhs(double t, const double *x, double *dx, void *user)
{
    const vi_sim *s = user;
    vi_model_rhs(model_of(s), t, x, dx);
}

static void sim_guards(double t, const double *x, double *g, void *user)
{
    const vi_sim *s = user;
    vi_hybrid_guards(&s->engine, t, x, g);
}

static void sim_jac(double t, const double *x, double *j, void *user)
{
    const vi_sim *s = user;
    vi_model_jacobian(model_of(s), t, x, j);
}

/* ---- along the solution: the damping's work and the largest force -------------------------------- */

/* Gauss-Legendre quadrature on [0, 1], 4 nodes (exact for polynomials of degree 7): nodes and weights. The
 * damping's work of every damped law in a drop and under Fig. 4b's excitation is that of 64 x 8 nodes to
 * 8e-11 at rtol 1e-9 and 2e-9 at rtol 1e-6 (measured), far below the motion's own error. */
#define VI_GAUSS_NODES 4
static const double gauss_t[VI_GAUSS_NODES] = {0.069431844202973714, 0.33000947820757187, 0.66999052179242813,
                                               0.93056815579702623};
static const double gauss_w[VI_GAUSS_NODES] = {0.17392742256872679, 0.32607257743127321, 0.32607257743127321,
                                               0.17392742256872679};

/* The damping's work over a piece of the solution (a damped law): the work of the force, integral of F
 * delta' dt (Gauss-Legendre on the interpolant; 0 when free), less the change of the spring part's energy
 * E_contact (closed form: no quadrature over the kink of F_spring where delta crosses 0). Where Tsuji's
 * damping delta^(1/4) delta' grows as (t - ta)^(1/4) from a contact's onset (delta = 0 exactly at ta:
 * the event puts it there), the piece is integrated in u with t = ta + h u^4, which makes it a
 * polynomial (hertz_damped, exact: 1e-11 of the work instead of 7e-9 at rtol 1e-9). */
static int piece_damping(vi_sim *s, const vi_solver_piece *p)
{
    vi_run_data *d = s->d;
    const vi_model *model = model_of(s);
    double h = p->tb - p->ta, sum = 0.0, x[2];
    int onset = vi_model_damping_onset(model, p->xa);
    for (int i = 0; i < VI_GAUSS_NODES && vi_model_touching(model); i++) {
        double u = gauss_t[i], u3 = u * u * u, t = p->ta + h * (onset ? u3 * u : u);
        if (vi_solver_piece_at(p, t, x, NULL) < 0) return -1;
        sum += gauss_w[i] * (onset ? 4.0 * u3 : 1.0) * vi_model_contact_power(model, t, x);
    }
    double spring = vi_model_contact_energy(model, p->xb, NULL) - vi_model_contact_energy(model, p->xa, NULL);
    d->W_damping += h * sum - spring;
    return 0;
}

/* fmax(a, b) without a call into libm (on x86-64 fmax is one): b where they are equal (+0 and -0 too), the
 * other where one is NaN, as glibc's. */
static inline double larger(double a, double b) { return a > b || b != b ? a : b; }

/* The force's maximum inside a piece: at most this many evaluations of the interpolant, until the estimate
 * moves by less than this fraction of the piece (F is flat there: its error is of the move's square). */
#define VI_PEAK_ITERS 8
#define VI_PEAK_MOVE 1e-7

/* Where the cubic through (a, Fa) and (b, Fb) with slopes ga > 0 > gb (Hermite) has its maximum in (a, b). */
static double hermite_peak(double a, double b, double Fa, double Fb, double ga, double gb)
{
    double h = b - a, dF = (Fb - Fa) / h;
    /* H'(a + s h) = ga + s (6 dF - 4 ga - 2 gb) + s^2 (3 ga + 3 gb - 6 dF): its root in (0, 1) where H' falls */
    double c2 = 3.0 * (ga + gb) - 6.0 * dF, c1 = 6.0 * dF - 4.0 * ga - 2.0 * gb, c0 = ga, s;
    if (fabs(c2) <= 1e-12 * (fabs(c1) + fabs(c0))) {
        s = -c0 / c1;
    } else {
        double disc = sqrt(fmax(c1 * c1 - 4.0 * c2 * c0, 0.0)), q = -0.5 * (c1 + (c1 >= 0.0 ? disc : -disc));
        double r1 = q / c2, r2 = q != 0.0 ? c0 / q : r1; /* the root where 2 c2 s + c1 < 0 (H' falling) */
        s = 2.0 * c2 * r1 + c1 < 0.0 && r1 > 0.0 && r1 < 1.0 ? r1 : r2;
    }
    return s > 0.0 && s < 1.0 ? a + s * h : a + 0.5 * h;
}

/* The largest force inside a piece whose force rate falls from ga > 0 at ta to gb < 0 at tb: the
 * maximum of the cubic (Hermite) through the force and its rate at the ends of the bracket, the force
 * and its rate evaluated there on the interpolant, the bracket narrowed to the side where the rate
 * changes sign, until the estimate stops moving; the largest force seen into *F_max. */
static int peak_inside(vi_sim *s, const vi_solver_piece *p, double Fa, double ga, double Fb, double gb, double *F_max)
{
    const vi_model *model = model_of(s);
    double a = p->ta, b = p->tb, x[2], dx[2], last = a, move = VI_PEAK_MOVE * (p->tb - p->ta);
    for (int i = 0; i < VI_PEAK_ITERS; i++) {
        double t = hermite_peak(a, b, Fa, Fb, ga, gb), F;
        if (vi_solver_piece_at(p, t, x, dx) < 0) return -1;
        double g = vi_model_force_rate(model, t, x, dx, &F);
        *F_max = fmax(*F_max, F);
        if (fabs(t - last) <= move || g == 0.0) break;
        last = t;
        if (g > 0.0) a = t, Fa = F, ga = g;
        else b = t, Fb = F, gb = g;
    }
    return 0;
}

/* The force and its rate at (t, x) in the current mode (dx = x' there, NULL: the right-hand side's), into
 * the simulation's end point (the start of the next piece). */
static void peak_point(vi_sim *s, double t, const double x[2], const double dx[2])
{
    vi_peak_point *e = &s->peak_end;
    e->t = t, e->x[0] = x[0], e->x[1] = x[1], e->mode = vi_hybrid_mode(&s->engine), e->valid = 1;
    e->g = vi_model_force_rate(model_of(s), t, x, dx, &e->F);
}

/* Is the end point the point (t, x) in the current mode? */
static int at_peak_end(const vi_sim *s, double t, const double x[2])
{
    const vi_peak_point *e = &s->peak_end;
    return e->valid && e->t == t && e->x[0] == x[0] && e->x[1] == x[1] && e->mode == vi_hybrid_mode(&s->engine);
}

/* The largest force over a piece: at its ends, and inside where its rate changes sign from + to - (one
 * extremum per internal step: the solver's steps resolve the motion). The start is the end of the piece
 * before unless the model changed in between (an event, an input, a restart: peak_restart). */
static int piece_peak(vi_sim *s, const vi_solver_piece *p)
{
    vi_run_data *d = s->d;
    vi_peak_point *e = &s->peak_end;
    if (vi_hybrid_mode(&s->engine) == VI_MODE_FREE) return 0; /* F = 0 */
    if (!at_peak_end(s, p->ta, p->xa)) peak_point(s, p->ta, p->xa, NULL);
    double Fa = e->F, ga = e->g;
    peak_point(s, p->tb, p->xb, p->dxb);
    double F_max = larger(Fa, e->F);
    if (ga > 0.0 && e->g < 0.0 && peak_inside(s, p, Fa, ga, e->F, e->g, &F_max) < 0) return -1;
    d->F_peak = larger(d->F_peak, F_max);
    return 0;
}

/* The model changed at the current point (an event, an input, a kink; changed: a restored state, a step's
 * start after inputs were set): its force raises F_peak (from the value given), and the next piece starts
 * from it. */
static void peak_restart_from(vi_sim *s, int changed, double F_peak)
{
    if (changed || !at_peak_end(s, s->d->t, s->d->x)) peak_point(s, s->d->t, s->d->x, NULL);
    s->d->F_peak = larger(F_peak, s->peak_end.F);
}

static void peak_restart(vi_sim *s, int changed) { peak_restart_from(s, changed, s->d->F_peak); }

/* A piece of the solution the solver passed (vi_solver.h, PIECES). */
static int sim_piece(const vi_solver_piece *p, void *user)
{
    vi_sim *s = user;
    if (vi_model_damps(model_of(s)) && piece_damping(s, p) < 0) return -1;
    return piece_peak(s, p);
}

void vi_sim_init(vi_sim *s, vi_run *r, vi_sim_data *d)
{
    memset(s, 0, sizeof *s);
    s->r = r, s->own = d;
    s->d = vi_run_attach(r, &s->engine, d, sizeof *d);
    s->log = r->log;
    s->log_env = r->log_env;
}

void vi_sim_free(vi_sim *s)
{
    vi_solver_free(s->solver);
    s->solver = NULL;
}

static void append_cause(vi_sim *s, double h_comm);

/* (Re)create the solver with the tolerances stored in s->d: starting at the current state, or
 * (resume) continuing the continuation in s->d as it is. */
static int create_solver(vi_sim *s, int resume)
{
    vi_run_data *d = s->d;
    vi_solver_free(s->solver);
    vi_solver_config cfg = {
        .n = 2, .nguards = VI_NGUARDS, .rhs = sim_rhs, .guards = sim_guards, .jac = sim_jac, .user = s,
        .method = s->r->set.method, .rtol = vi_hybrid_state_of(&s->engine)->rtol,
        .atol = vi_hybrid_state_of(&s->engine)->atol, .max_step = s->r->set.max_step,
        .ode = &s->own->ode, .auto_choice = &s->own->auto_choice, .piece = sim_piece, .log = vi_sim_solver_log, .log_env = s};
    s->solver = resume ? vi_solver_resume(&cfg, d->t, d->x) : vi_solver_create(&cfg, d->t, d->x);
    s->solver_stale = 0;
    if (!s->solver) { /* the configuration is valid: the first step failed, a rate beyond the doubles */
        const vi_model *model = model_of(s);
        vi_snprintf(s->r->msg, sizeof s->r->msg, "could not create the solver at t = %.17g s: no first step from the initial "
                    "state (the load's acceleration (P + m g - F_ext)/m = %g m/s2)", d->t,
                    (model->body.W0 - vi_ramp_at(&model->F_ext, d->t)) / model->body.m);
        append_cause(s, 0.0);
        size_t used = strlen(s->r->msg);
        vi_snprintf(s->r->msg + used, sizeof s->r->msg - used, "; raise m, or lower P or the contact's stiffness");
        return -1;
    }
    return 0;
}

int vi_sim_initialize(vi_sim *s)
{
    if (vi_run_prepare(s->r) < 0) return -1;
    vi_run_data *d = s->d;
    double rtol, atol[2];
    vi_run_tolerances(s->r, &rtol, atol);
    vi_hybrid_start(&s->engine, rtol, atol, d->t, d->x);
    d->initialized = 1;
    memset(&s->own->ode, 0, sizeof s->own->ode);
    memset(&s->own->auto_choice, 0, sizeof s->own->auto_choice);
    if (create_solver(s, 0) < 0) return -1;
    vi_run_warn_settings(s->r);
    vi_sim_report_warnings(s); /* of the solver's creation */
    return 0;
}

void vi_sim_log_solver(const vi_sim *s)
{
    const vi_hybrid_state *e = vi_hybrid_state_of(&s->engine);
    s->log(s->log_env, VI_LOG_SOLVER, "%s, rtol %g, atol %g m and %g m/s (scales %g m, %g m/s)",
           vi_solver_method_name(s->r->set.method), e->rtol, e->atol[0], e->atol[1], e->atol[0] / e->rtol,
           e->atol[1] / e->rtol);
}

int vi_sim_checkpoint(vi_sim *s)
{
    if (!s->d->initialized || !s->solver) return 0;
    if (vi_solver_checkpoint(s->solver, s->d->t, s->d->x) < 0)
        VI_FAIL(s->r->msg, sizeof s->r->msg, "could not restart the solver at t = %.17g s", s->d->t);
    s->solver_stale = 0;
    return 0;
}

int vi_sim_restore(vi_sim *s)
{
    s->peak_end.valid = 0;
    if (!s->d->initialized) { /* before initialization: no solver until then */
        vi_run_restore(s->r);
        vi_solver_free(s->solver);
        s->solver = NULL;
        return 0;
    }
    if (vi_run_restore(s->r) < 0) return -1;
    return create_solver(s, 1);
}

/* New input values (and tunable a, f) take effect at the current time as an input jump
 * (vi_hybrid_input_jump); an input that continues its previous ramp (held, or the same slope)
 * changes nothing and does not restart the solver. */
static void apply_inputs(vi_sim *s)
{
    vi_run_data *d = s->d;
    double t = d->t;
    vi_ramp yC_in, F_ext;
    double a, f;
    vi_run_input_ramps(s->r, t, &yC_in, &F_ext);
    vi_run_excitation(s->r, &a, &f);
    d->inputs_changed = 0;
    if (!vi_hybrid_input_jump(&s->engine, t, d->x, yC_in, F_ext, a, f)) return;
    s->solver_stale = 1;
    vi_run_check_validity(s->r); /* a new amplitude */
}

/* ---- messages: what the contact's time scale says of a failure; the solver's warnings ------------ */

/* A time scale shorter than this many units of the time resolution DBL_EPSILON |t| cannot be resolved
 * by steps at t (a contact needs many steps, each at least a unit). */
#define VI_RESOLVED_UNITS 1e3

/* What to change: raise m or soften the contact. */
static const char *remedy(const vi_model *model)
{
    return vi_model_lower(model)->law == VI_LAW_LINEAR ? "raise m or lower k_spring" : "raise m or soften the contact (E1, E2, R1, R2)";
}

/* Append to s->r->msg what the contact's time scale says: whether it is too short for the time resolution
 * at t, or for the work bound over a communication step of h_comm [s] (0: none known), and what to
 * change. Every failure message ends with it. */
static void append_cause(vi_sim *s, double h_comm)
{
    char note[300];
    double k, T = vi_run_time_scale(s->r, &k, note, sizeof note), t = s->d->t, unit = DBL_EPSILON * fabs(t);
    int unresolved = T < VI_RESOLVED_UNITS * unit, too_many = h_comm > (double)VI_MAX_STEPS_PER_ADVANCE * T;
    int late = T < VI_RESOLVED_UNITS * DBL_EPSILON * fabs(s->r->set.t_start); /* the start time alone is too late */
    size_t used = strlen(s->r->msg);
    used += (size_t)vi_snprintf(s->r->msg + used, sizeof s->r->msg - used, "; the contact's time scale %s", note);
    if (used < sizeof s->r->msg && unresolved)
        used += (size_t)vi_snprintf(s->r->msg + used, sizeof s->r->msg - used, " is only %.3g units of the time resolution "
                                    "%.3g s at t = %.17g s, too short for the solver's steps there", T / unit, unit, t);
    if (used < sizeof s->r->msg && too_many)
        used += (size_t)vi_snprintf(s->r->msg + used, sizeof s->r->msg - used, "%s %.3g times shorter than the communication "
                                    "step %g s, more than the %ld internal steps one step may take",
                                    unresolved ? " and" : " is", h_comm / T, h_comm, VI_MAX_STEPS_PER_ADVANCE);
    char shorter[80] = "";
    if (too_many)
        vi_snprintf(shorter, sizeof shorter, ", or use communication steps below %.3g s", (double)VI_MAX_STEPS_PER_ADVANCE * T);
    if (used < sizeof s->r->msg && (unresolved || too_many))
        vi_snprintf(s->r->msg + used, sizeof s->r->msg - used, ": %s%s%s", remedy(model_of(s)),
                    late ? ", or start the run nearer t = 0" : "", shorter);
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* Is the text at p a number (a digit, or a sign or point before one)? (Reads past p[0] only when it is
 * not the terminator.) */
static int number_at(const char *p)
{
    return is_digit(p[0]) || ((p[0] == '-' || p[0] == '+' || p[0] == '.') && is_digit(p[1]));
}

/* The text after the number at p: [+-] digits and points, an exponent. */
static const char *skip_number(const char *p)
{
    if (*p == '-' || *p == '+') p++;
    while (is_digit(*p) || *p == '.') p++;
    if (*p != 'e' && *p != 'E') return p;
    const char *e = p + 1 + (p[1] == '-' || p[1] == '+');
    if (!is_digit(*e)) return p;
    while (is_digit(*e)) e++;
    return e;
}

/* Are two texts of at most VI_RELAY_KIND_MAX bytes the same but for their numbers? */
static int same_kind(const char *a, const char *b)
{
    for (int i = 0; i < VI_RELAY_KIND_MAX; i++) { /* bounded: each pass moves both by a byte or a number */
        if (number_at(a) && number_at(b)) {
            a = skip_number(a), b = skip_number(b);
            continue;
        }
        if (*a != *b) return 0;
        if (!*a) return 1;
        a++, b++;
    }
    return 1;
}

void vi_sim_solver_log(void *env, int category, const char *fmt, ...)
{
    vi_sim *s = env;
    char text[600], kind[VI_RELAY_KIND_MAX];
    va_list ap;
    va_start(ap, fmt);
    vi_vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    if (category != VI_LOG_WARNING) {
        s->log(s->log_env, category, "%s", text);
        return;
    }
    vi_relay *r = &s->relay;
    vi_snprintf(kind, sizeof kind, "%s", text);
    for (int i = 0; i < r->kinds; i++)
        if (same_kind(r->kind[i], kind)) {
            r->repeats[i]++;
            r->unreported = 1;
            return;
        }
    if (r->kinds == VI_RELAY_KINDS) {
        r->others++;
        r->unreported = 1;
        return;
    }
    memcpy(r->kind[r->kinds++], kind, sizeof kind);
    char note[300], units[160] = "";
    double k, T = vi_run_time_scale(s->r, &k, note, sizeof note), unit = DBL_EPSILON * fabs(s->d->t);
    if (unit > 0.0)
        vi_snprintf(units, sizeof units, " is %.3g units of the time resolution at t = %.17g s%s", T / unit, s->d->t,
                    T < VI_RESOLVED_UNITS * unit ? ", too few for the solver's steps: the likely cause" : "");
    s->log(s->log_env, VI_LOG_WARNING, "%s (the contact's time scale %s%s; further warnings like this one are counted, "
           "not repeated)", text, note, units);
}

void vi_sim_report_warnings(vi_sim *s)
{
    vi_relay *r = &s->relay;
    if (!r->unreported) return;
    r->unreported = 0;
    for (int i = 0; i < r->kinds; i++)
        if (r->repeats[i] > 0) {
            s->log(s->log_env, VI_LOG_WARNING, "%ld more solver warnings like \"%s\" by t = %.17g s (counted, not relayed)",
                   r->repeats[i], r->kind[i], s->d->t);
            r->repeats[i] = 0;
        }
    if (r->others > 0)
        s->log(s->log_env, VI_LOG_WARNING, "%ld more solver warnings of other kinds by t = %.17g s (counted, not relayed)",
               r->others, s->d->t);
    r->others = 0;
}

/* ---- the loop ------------------------------------------------------------------------------- */

/* End the advance early (doc/model.md section 7.1): the state at d->t is consistent and usable. */
static int discard(vi_sim *s, const char *fmt, ...) VI_PRINTF_FORMAT(2, 3);
static int discard(vi_sim *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vi_vsnprintf(s->r->msg, sizeof s->r->msg, fmt, ap);
    va_end(ap);
    return VI_SIM_DISCARD;
}

/* Early return: does the advance end here, after an event or a profile kink that may have switched
 * a contact's mode from modes_before (vi_hybrid_modes)? Only when asked, a mode changed, and the time
 * lies beyond the instant the advance started (more than VI_EARLY_RETURN_UNITS units of the time
 * resolution after it): mode changes at that instant are taken in the same advance, so every early
 * return makes a step an importer can take with its other FMUs, and events accumulating at one
 * instant still meet the Zeno rule. */
static int stop_here(const vi_sim *s, int stop_at_mode_change, int modes_before)
{
    double unit = DBL_EPSILON * fmax(1.0, fabs(s->d->t));
    return stop_at_mode_change && vi_hybrid_modes(&s->engine) != modes_before && s->d->t - s->d->step_t0 > VI_EARLY_RETURN_UNITS * unit;
}

/* One advance in progress. */
typedef struct {
    double t_end, limit, target; /* the step's end, the end of a non-periodic profile, the nearer */
    long steps_left, events, kinks;
    int stop_at_mode_change;
} advance_run;

/* How a pass of the loop ended, besides the VI_SIM_* results that end the advance. */
enum { PASS_MORE = 100, PASS_END, PASS_STOPPED };

static int solver_failed(vi_sim *s)
{
    const vi_run_data *d = s->d;
    vi_snprintf(s->r->msg, sizeof s->r->msg, "the solver failed near t = %.17g s (mode %d, delta = %g m, v = %g m/s)", d->t,
                vi_hybrid_mode(&s->engine), d->x[0], d->x[1]);
    append_cause(s, s->advance_end - d->step_t0);
    return VI_SIM_ERROR;
}

/* The start of an advance to t_end: refuse what cannot run, take the inputs, re-arm, restart a stale
 * solver. VI_SIM_OK or VI_SIM_ERROR (s->r->msg). */
static int begin_advance(vi_sim *s, double t_end)
{
    vi_run_data *d = s->d;
    if (!s->solver) VI_FAIL(s->r->msg, sizeof s->r->msg, "the simulation is not initialized");
    if (!(t_end > d->t))
        VI_FAIL(s->r->msg, sizeof s->r->msg, "the step end %.17g s does not exceed the current time %.17g s in floating point",
                t_end, d->t);
    s->r->out_valid = 0;
    d->step_t0 = d->t;
    d->step_v0 = d->x[1];
    vi_hybrid_count_from(&s->engine, d->t);
    int changed = d->inputs_changed || s->solver_stale;
    if (d->inputs_changed) apply_inputs(s);
    vi_hybrid_rearm(&s->engine, d->t, d->x);
    peak_restart_from(s, changed, 0.0); /* F_peak: the force now, and the step's pieces raise it */
    if (s->solver_stale) {
        if (vi_solver_reset(s->solver, d->t, d->x) < 0) return solver_failed(s);
        s->solver_stale = 0;
    }
    return VI_SIM_OK;
}

/* A state event the solver located (fired: its guard flags): apply it, restart the solver, and end
 * the advance on the Zeno rule or the work bound on events. */
static int state_event(vi_sim *s, advance_run *run, const int fired[])
{
    vi_run_data *d = s->d;
    int g = 0;
    while (g < VI_NGUARDS - 1 && fired[g] == 0) g++;
    int from = vi_hybrid_event(&s->engine, d->t, d->x, g, 1);
    peak_restart(s, 1);
    vi_hybrid_arm_at_zero(&s->engine, d->t, d->x);
    vi_run_check_validity(s->r);
    if (vi_solver_reset(s->solver, d->t, d->x) < 0) return solver_failed(s);
    if (vi_hybrid_zeno(&s->engine, d->t, g, from, s->r->msg, sizeof s->r->msg)) return VI_SIM_DISCARD;
    if (++run->events >= VI_MAX_EVENTS_PER_ADVANCE && d->t < run->t_end) {
        discard(s, "work bound: %ld events in one step, stopped at t = %.17g s (mode %d); continue from there or use "
                   "smaller communication steps", VI_MAX_EVENTS_PER_ADVANCE, d->t, vi_hybrid_mode(&s->engine));
        append_cause(s, run->t_end - d->step_t0);
        return VI_SIM_DISCARD;
    }
    return PASS_MORE;
}

/* One pass of the loop: integrate to the next kink of the profile or the target, or to an event. */
static int advance_pass(vi_sim *s, advance_run *run)
{
    vi_run_data *d = s->d;
    int modes_before = vi_hybrid_modes(&s->engine), rc = VI_SOLVER_REACHED, fired[VI_SOLVER_MAX_GUARDS];
    double bp = model_of(s)->profile ? vi_model_next_breakpoint(model_of(s), d->t) : INFINITY;
    double stop = bp < run->target ? bp : run->target;
    long taken = 0;
    if ((stop == bp || run->kinks) && stop - d->t <= VI_BREAKPOINT_ULPS * DBL_EPSILON * fabs(stop)) {
        d->t = stop; /* a kink, or the end after one, within rounding of now: too close for the solver */
        if (vi_solver_reset(s->solver, d->t, d->x) < 0) return solver_failed(s);
    } else {
        rc = vi_solver_advance(s->solver, stop, run->steps_left, &d->t, d->x, fired, &taken);
    }
    run->steps_left -= taken;
    if (rc == VI_SOLVER_FAILED) return solver_failed(s);
    if (rc == VI_SOLVER_LIMIT) {
        discard(s, "work bound: %ld internal steps in one step, stopped at t = %.17g s (mode %d); continue from there "
                   "or use smaller communication steps; its internal steps averaged %.3g s", VI_MAX_STEPS_PER_ADVANCE,
                d->t, vi_hybrid_mode(&s->engine), (d->t - d->step_t0) / (double)VI_MAX_STEPS_PER_ADVANCE);
        append_cause(s, run->t_end - d->step_t0);
        return VI_SIM_DISCARD;
    }
    int pass = PASS_MORE;
    if (rc == VI_SOLVER_REACHED && stop == bp) {
        run->kinks++;
        vi_hybrid_kink(&s->engine, d->t, d->x); /* the rate of delta jumped: the solver restarts */
        peak_restart(s, 1);
        if (vi_solver_reset(s->solver, d->t, d->x) < 0) return solver_failed(s);
    } else if (rc != VI_SOLVER_REACHED) {
        pass = state_event(s, run, fired);
    }
    if (pass != PASS_MORE) return pass;
    if (stop_here(s, run->stop_at_mode_change, modes_before)) return PASS_STOPPED;
    return rc == VI_SOLVER_REACHED && d->t >= run->target ? PASS_END : PASS_MORE;
}

int vi_sim_advance(vi_sim *s, double t_end) { return vi_sim_advance_until(s, t_end, 0); }

/* The end of an advance with result rc: the solver's warnings counted in it reported. */
static int reported(vi_sim *s, int rc)
{
    vi_sim_report_warnings(s);
    return rc;
}

int vi_sim_advance_until(vi_sim *s, double t_end, int stop_at_mode_change)
{
    vi_run_data *d = s->d;
    s->advance_end = t_end;
    if (begin_advance(s, t_end) != VI_SIM_OK) return reported(s, VI_SIM_ERROR);
    char why[400]; /* written only where a profile ends */
    advance_run run = {.t_end = t_end, .steps_left = VI_MAX_STEPS_PER_ADVANCE, .stop_at_mode_change = stop_at_mode_change};
    run.limit = model_of(s)->profile ? vi_model_rolling_limit(model_of(s), why, sizeof why) : INFINITY;
    run.target = run.limit < t_end ? run.limit : t_end;
    int pass = PASS_MORE;
    /* bounded: every pass is an event (bounded below) or a kink of the profile (finitely many in the
     * distance |V| (t_end - t) rolled) */
    while (pass == PASS_MORE && d->t < run.target) pass = advance_pass(s, &run);
    if (pass != PASS_MORE && pass != PASS_END && pass != PASS_STOPPED) return reported(s, pass);
    vi_sim_report_warnings(s);
    if (!isfinite(d->x[0]) || !isfinite(d->x[1]))
        VI_FAIL(s->r->msg, sizeof s->r->msg, "the state is not finite at t = %.17g s", d->t);
    /* at a communication point only the indentation can newly leave the range (a changes in
     * apply_inputs, which checks; the profile is fixed), unless a state was restored since */
    if (s->r->validity_unchecked ||
        (!(s->r->warned_validity & VI_INVALID_INDENTATION) && vi_model_indentation_invalid(model_of(s), d->x)) ||
        (!(s->r->warned_validity & VI_INVALID_FORCE) &&
         fmax(d->F_peak, vi_model_force_upper(model_of(s), d->t, d->x)) > vi_model_force_limit(model_of(s))))
        vi_run_check_validity(s->r);
    if (pass == PASS_STOPPED) return VI_SIM_EVENT;
    if (t_end > run.limit) return discard(s, "%s", why); /* the end of the profile: nothing beyond it */
    d->t = t_end;
    return VI_SIM_OK;
}

/* ---- validity of a state payload (doc/model.md section 7.6) --------------------------------- */

int vi_sim_data_check(const vi_run_data *r, const vi_sim_data *d, const vi_run_settings *set, char *msg, size_t n)
{
    if (vi_run_data_check(r, set->t_start, set->rtol, msg, n) < 0) return -1;
    /* the solver's continuation */
    int solver = r->initialized, method = set->method;
    if (solver && method == VI_METHOD_AUTO && vi_solver_auto_check(&d->auto_choice, msg, n) < 0) return -1;
    int one_step = method == VI_METHOD_DOP853 || (method == VI_METHOD_AUTO && !d->auto_choice.bdf);
    if (solver && one_step && vi_solver_ode_check(&d->ode, 2, VI_NGUARDS, r->t, msg, n) < 0) return -1;
    return vi_run_data_check_model(r, 1, msg, n);
}

void vi_sim_statistics(const vi_sim *s, vi_solver_stats *st)
{
    if (s->solver) vi_solver_statistics(s->solver, st);
    else memset(st, 0, sizeof *st);
}
