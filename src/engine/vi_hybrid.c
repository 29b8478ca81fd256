/* vi_hybrid.c - the hybrid automaton's event handling under both drivers; see vi_hybrid.h. */
#include "vi_hybrid.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "vi_check.h"
#include "vi_format.h"
#include "vi_solver.h" /* VI_RTOL_MIN, VI_RTOL_MAX: the tolerances a saved state may hold */

void vi_hybrid_bind(vi_hybrid *h, vi_model *model, vi_hybrid_state *st, int integrates_y, vi_log_fn log, void *log_env)
{
    *h = (vi_hybrid){.model = model, .st = st, .integrates_y = integrates_y, .log = log, .log_env = log_env};
}

int vi_hybrid_setup(vi_hybrid *h, const vi_model_params *p, double t0, char *msg, size_t n)
{
    return vi_model_setup(h->model, p, t0, msg, n);
}

int vi_hybrid_set_rolling(vi_hybrid *h, const vi_profile *profile, double V, double x0, char *msg, size_t n)
{
    return vi_model_set_rolling(h->model, profile, V, x0, msg, n);
}

void vi_hybrid_prepare(vi_hybrid *h, double t, vi_ramp yC_in, vi_ramp F_ext, int init, double v0, double x[2])
{
    vi_hybrid_hold_inputs(h, yC_in, F_ext);
    vi_model_initial_state(h->model, init, v0, t, x);
    memset(h->st, 0, sizeof *h->st);
    h->st->t_count = t;
}

void vi_hybrid_hold_inputs(vi_hybrid *h, vi_ramp yC_in, vi_ramp F_ext)
{
    h->model->yC_in = yC_in;
    h->model->F_ext = F_ext;
}

void vi_hybrid_follow_inputs(vi_hybrid *h, double t, double x[2], vi_ramp yC_in, vi_ramp F_ext)
{
    vi_model_set_inputs(h->model, t, x, yC_in, F_ext);
}

void vi_hybrid_write_down(vi_hybrid *h, double t, const double x[2])
{
    double copy[2] = {x[0], x[1]};
    vi_model_freeze(h->model, t, copy);
}

void vi_hybrid_start(vi_hybrid *h, double rtol, const double atol[2], double t, const double x[2])
{
    vi_hybrid_state *st = h->st;
    double atol_m = atol[0], atol_v = atol[1]; /* atol may point into st */
    memset(st, 0, sizeof *st);
    st->rtol = rtol;
    st->atol[0] = atol_m;
    st->atol[1] = atol_v;
    st->t_count = t;
    vi_hybrid_arm_at_zero(h, t, x);
}

static void add_change(const vi_model *model, double t, const double x[2], const double g0[VI_NGUARDS], double acc[VI_NGUARDS])
{
    double g[VI_NGUARDS];
    vi_model_guards(model, t, x, g);
    for (int i = 0; i < VI_NGUARDS; i++) acc[i] += fabs(g[i] - g0[i]);
}

/* How much each guard moves under rounding (one ulp of t with the integrated states fixed, and one
 * ulp of each integrated state: ulps[i]) and under a state error of the tolerance (rtol |q| + atol
 * in each integrated state q: tol[i]). The integrated position is delta or y = yC(t) - delta, whose
 * changes move delta the other way. */
static void guard_noise(const vi_hybrid *h, double t, const double x[2], double ulps[VI_NGUARDS], double tol[VI_NGUARDS])
{
    const vi_model *model = h->model;
    const vi_hybrid_state *st = h->st;
    double g0[VI_NGUARDS], t1 = nextafter(t, INFINITY), q = x[0], sign = 1.0, moved = 0.0;
    if (h->integrates_y) { /* y = yC(t) - delta; fixed y: delta moves with the platform over the ulp of t */
        double yC = vi_model_platform(model, t, NULL, NULL);
        q = yC - x[0], sign = -1.0, moved = vi_model_platform(model, t1, NULL, NULL) - yC;
    }
    vi_model_guards(model, t, x, g0);
    for (int i = 0; i < VI_NGUARDS; i++) ulps[i] = tol[i] = 0.0;
    add_change(model, t1, (const double[2]){x[0] + moved, x[1]}, g0, ulps);
    const double dq[2] = {nextafter(q, INFINITY) - q, st->rtol * fabs(q) + st->atol[0]};
    const double dv[2] = {nextafter(x[1], INFINITY) - x[1], st->rtol * fabs(x[1]) + st->atol[1]};
    for (int k = 0; k < 2; k++) {
        double *acc = k == 0 ? ulps : tol;
        add_change(model, t, (const double[2]){x[0] + sign * dq[k], x[1]}, g0, acc);
        add_change(model, t, (const double[2]){x[0], x[1] + dv[k]}, g0, acc);
    }
}

/* The band of guard i at (t, x) (see vi_hybrid.h). */
static double band_of(const double ulps[VI_NGUARDS], const double tol[VI_NGUARDS], int i)
{
    return VI_GRAZE_TOL * tol[i] + VI_GRAZE_ULPS * ulps[i] + DBL_MIN;
}

void vi_hybrid_rearm_banded(vi_hybrid *h, double t, const double x[2])
{
    double *band = h->st->band, g[VI_NGUARDS];
    vi_model_guards(h->model, t, x, g);
    for (int i = 0; i < VI_NGUARDS; i++)
        if (band[i] > 0.0 && g[i] > band[i]) band[i] = 0.0;
}

/* The event log's field naming contact i, with a space before it: " contact=lower" or " contact=upper"
 * in a model with an upper contact; none in a model with one contact (its lines as they always were). */
static const char *contact_field(const vi_model *model, int i)
{
    if (model->ncontacts < 2) return "";
    return i == VI_LOWER ? " contact=lower" : " contact=upper";
}

void vi_hybrid_log_start(const vi_hybrid *h, double t, const double x[2])
{
    const vi_model *model = h->model;
    for (int i = 0; i < model->ncontacts; i++)
        h->log(h->log_env, VI_LOG_EVENTS, "event t=%.17g kind=start mode=%d delta=%.9g v=%.9g%s", t,
               model->contact[i].mode, vi_model_contact_indentation(model, i, x), x[1], contact_field(model, i));
}

void vi_hybrid_arm_at_zero(vi_hybrid *h, double t, const double x[2])
{
    double g[VI_NGUARDS], ulps[VI_NGUARDS], tol[VI_NGUARDS];
    vi_model_guards(h->model, t, x, g);
    guard_noise(h, t, x, ulps, tol);
    for (int i = 0; i < VI_NGUARDS; i++)
        if (h->st->band[i] == 0.0 && fabs(g[i]) <= VI_GRAZE_ULPS * ulps[i] + DBL_MIN) h->st->band[i] = band_of(ulps, tol, i);
}

int vi_hybrid_fired(const vi_hybrid *h, double t, const double x[2], int *located)
{
    double g[VI_NGUARDS], ulps[VI_NGUARDS], tol[VI_NGUARDS];
    vi_model_guards(h->model, t, x, g);
    for (int i = 0; i < VI_NGUARDS; i++) {
        if (g[i] + h->st->band[i] > 0.0) continue;
        guard_noise(h, t, x, ulps, tol);
        *located = fabs(g[i]) <= band_of(ulps, tol, i);
        return i;
    }
    return -1;
}

int vi_hybrid_due(const vi_hybrid *h, double t, const double x[2])
{
    double g[VI_NGUARDS];
    vi_hybrid_guards(h, t, x, g);
    int due = 0;
    for (int i = 0; i < VI_NGUARDS; i++) due |= g[i] < 0.0;
    return due;
}

/* ---- inputs and kinks ------------------------------------------------------------------------- */

/* The inputs act from t on: the memory is written down at the state before, then delta jumps with the
 * platform (the mass does not move). */
static void take_inputs(vi_hybrid *h, double t, double x[2], vi_ramp yC_in, vi_ramp F_ext)
{
    vi_model_freeze(h->model, t, x);
    vi_model_set_inputs(h->model, t, x, yC_in, F_ext);
}

/* The modes of the model's contacts into from (before an input jump or a kink). */
static void modes_of(const vi_model *model, int from[VI_NCONTACTS])
{
    for (int i = 0; i < VI_NCONTACTS; i++) from[i] = model->contact[i].mode;
}

/* The modes were `from` before an input jump or a kink (kind): log each contact's mode that changed
 * and, when one did, reset the bands; then arm the guards at zero. */
static void mode_chosen(vi_hybrid *h, const char *kind, const int from[VI_NCONTACTS], double t, const double x[2])
{
    const vi_model *model = h->model;
    int changed = 0;
    for (int i = 0; i < model->ncontacts; i++) {
        int to = model->contact[i].mode;
        if (to == from[i]) continue;
        h->log(h->log_env, VI_LOG_EVENTS, "event t=%.17g kind=%s mode=%d->%d%s", t, kind, from[i], to,
               contact_field(model, i));
        changed = 1;
    }
    if (changed) memset(h->st->band, 0, sizeof h->st->band);
    vi_hybrid_arm_at_zero(h, t, x);
}

int vi_hybrid_input_jump(vi_hybrid *h, double t, double x[2], vi_ramp yC_in, vi_ramp F_ext, double a, double f)
{
    vi_model *model = h->model;
    int from[VI_NCONTACTS];
    modes_of(model, from);
    if (!vi_hybrid_inputs_differ(h, t, yC_in, F_ext) && !vi_model_excitation_differs(model, a, f)) return 0;
    take_inputs(h, t, x, yC_in, F_ext);
    vi_model_set_excitation(model, t, x, a, f); /* a new a moves the platform (delta with it), the mass stays */
    vi_model_resolve(model, t, x);
    mode_chosen(h, "input", from, t, x);
    return 1;
}

void vi_hybrid_kink(vi_hybrid *h, double t, double x[2])
{
    int from[VI_NCONTACTS];
    modes_of(h->model, from);
    vi_model_breakpoint(h->model, t, x);
    mode_chosen(h, "kink", from, t, x);
}

/* ---- state events ----------------------------------------------------------------------------- */

/* Choose the mode after guard `fired` reached zero, with the rates the guards see. */
static void choose(vi_model *model, double t, double x[2], int fired, int located)
{
    if (located) {
        vi_model_event(model, t, x, fired);
    } else {
        vi_model_freeze(model, t, x);
        vi_model_resolve(model, t, x);
    }
}

/* The bands of the guards of the contact guard `fired` belongs to are cleared (its mode changed). */
static void clear_bands(vi_hybrid_state *st, int fired)
{
    int first = fired / VI_CONTACT_NGUARDS * VI_CONTACT_NGUARDS;
    for (int i = first; i < first + VI_CONTACT_NGUARDS; i++) st->band[i] = 0.0;
}

int vi_hybrid_event(vi_hybrid *h, double t, double x[2], int fired, int located)
{
    vi_model *model = h->model;
    vi_hybrid_state *st = h->st;
    int from = vi_model_guard_mode(model, fired);
    choose(model, t, x, fired, located);
    st->n_events++;
    st->zeno = vi_hybrid_zeno_count(st->zeno, st->t_count, t);
    st->t_count = t;
    int to = vi_model_guard_mode(model, fired), contact = fired / VI_CONTACT_NGUARDS;
    h->log(h->log_env, VI_LOG_EVENTS, "event t=%.17g kind=guard guard=%d mode=%d->%d delta=%.9g v=%.9g%s", t, fired,
           from, to, vi_model_contact_indentation(model, contact, x), x[1], contact_field(model, contact));
    if (to != from) {
        clear_bands(st, fired);
    } else {
        double ulps[VI_NGUARDS], tol[VI_NGUARDS];
        vi_hybrid_rearm(h, t, x);
        guard_noise(h, t, x, ulps, tol);
        st->band[fired] = band_of(ulps, tol, fired); /* grazing: disarmed */
    }
    return from;
}

int vi_hybrid_zeno_count(int count, double t_before, double t)
{
    double ulp = nextafter(fabs(t), INFINITY) - fabs(t);
    return t - t_before <= VI_ZENO_ULPS * ulp ? count + 1 : 0;
}

int vi_hybrid_zeno(const vi_hybrid *h, double t, int fired, int from, char *msg, size_t n)
{
    if (h->st->zeno < VI_ZENO_EVENTS) return 0;
    vi_snprintf(msg, n, "events accumulate at t = %.17g s (Zeno): %d events each within %g ulps of time of the one "
                "before, the last on guard %d of mode %d (%s); stopped there. Each mode chosen was left again at once: "
                "the motion the guards see leaves it. Where the platform moves through yC_in, pass its velocity "
                "(velocity_input = true, vC_in); else tighten rtol", t, VI_ZENO_EVENTS, VI_ZENO_ULPS, fired, from,
                vi_model_guard_name(h->model, from, fired));
    return 1;
}

int vi_hybrid_check(const vi_hybrid_state *st, double t, char *msg, size_t n)
{
    if (!(st->rtol == 0.0 || (st->rtol >= VI_RTOL_MIN && st->rtol <= VI_RTOL_MAX)))
        VI_FAIL(msg, n, "rtol = %g is neither 0 nor in [%g, %g]", st->rtol, VI_RTOL_MIN, VI_RTOL_MAX);
    for (int i = 0; i < 2; i++)
        if (!(st->atol[i] >= 0.0 && isfinite(st->atol[i])))
            VI_FAIL(msg, n, "atol[%d] = %g is not finite and >= 0", i, st->atol[i]);
    for (int i = 0; i < VI_NGUARDS; i++)
        if (!(st->band[i] >= 0.0 && isfinite(st->band[i])))
            VI_FAIL(msg, n, "guard band[%d] = %g is not finite and >= 0", i, st->band[i]);
    if (!isfinite(st->t_count) || st->t_count > t)
        VI_FAIL(msg, n, "t_count = %g is not finite or after t = %g", st->t_count, t);
    if (st->zeno < 0 || st->zeno > VI_ZENO_EVENTS)
        VI_FAIL(msg, n, "zeno = %d is not in 0..%d", st->zeno, VI_ZENO_EVENTS);
    if (st->n_events < 0) VI_FAIL(msg, n, "n_events = %ld is negative", st->n_events);
    return 0;
}
