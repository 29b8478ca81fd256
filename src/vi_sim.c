/* vi_sim.c - a simulation: inputs, initial state, and the event loop around the solver. */
#include "vi_sim.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "vi_check.h"
#include "vi_format.h"

_Static_assert((int)VI_Solver_bdf == (int)VI_METHOD_BDF && (int)VI_Solver_adams == (int)VI_METHOD_ADAMS &&
                   (int)VI_Solver_dop853 == (int)VI_METHOD_DOP853 && (int)VI_Solver_auto == (int)VI_METHOD_AUTO,
               "the solver enumeration is the solver layer's method number");

static void sim_rhs(double t, const double *x, double *dx, void *user)
{
    const vi_sim_data *d = user;
    vi_model_rhs(&d->M, t, x, dx);
}

/* The model's guards, each disarmed one shifted up by its band (re-arming: VI_GRAZE_TOL, VI_GRAZE_ULPS). */
static void sim_guards(double t, const double *x, double *g, void *user)
{
    const vi_sim_data *d = user;
    vi_model_guards(&d->M, t, x, g);
    for (int i = 0; i < VI_NGUARDS; i++) g[i] += d->guard_band[i];
}

static void sim_jac(double t, const double *x, double *j, void *user)
{
    const vi_sim_data *d = user;
    vi_model_jacobian(&d->M, t, x, j);
}

void vi_sim_init(vi_sim *s, vi_log_fn log, void *log_env)
{
    memset(s, 0, sizeof *s);
    s->log = log;
    s->log_env = log_env;
    vi_parameters_default(&s->d.par);
    vi_inputs_default(&s->d.in);
}

void vi_sim_set_resources(vi_sim *s, const char *dir)
{
    snprintf(s->resources, sizeof s->resources, "%s", dir ? dir : "");
}

void vi_sim_reset(vi_sim *s)
{
    char resources[VI_PATH_MAX];
    memcpy(resources, s->resources, sizeof resources);
    vi_sim_free(s);
    vi_sim_init(s, s->log, s->log_env);
    memcpy(s->resources, resources, sizeof resources);
}

void vi_sim_free(vi_sim *s)
{
    vi_solver_free(s->solver);
    s->solver = NULL;
    vi_profile_free(s->profile);
    s->profile = NULL;
    s->profile_key[0] = '\0';
}

/* The file a profile_file names: as given when absolute; else in the resources folder if it is
 * there, else relative to the working directory. 0, or -1 when the path does not fit. */
static int profile_path(const vi_sim *s, const char *file, char *path, size_t n)
{
    int k;
    if (file[0] != '/' && s->resources[0]) {
        k = snprintf(path, n, "%s/%s", s->resources, file);
        FILE *f = k > 0 && (size_t)k < n ? fopen(path, "r") : NULL;
        if (f) {
            fclose(f);
            return 0;
        }
    }
    k = snprintf(path, n, "%s", file);
    return k > 0 && (size_t)k < n ? 0 : -1;
}

/* Load (or keep, when file, R1 and periodicity are those it was built for) the profile of the
 * parameters and hand it to the model with V and x0. Called after vi_model_setup and after a
 * restore: the profile pointer read from a saved state is never used. 0, or -1 (s->msg). */
static int attach_profile(vi_sim *s)
{
    const vi_parameters *p = &s->d.par;
    vi_model *M = &s->d.M;
    if (!p->profile_file[0]) {
        vi_profile_free(s->profile);
        s->profile = NULL;
        s->profile_key[0] = '\0';
        return vi_model_set_rolling(M, NULL, p->V, p->x0, s->msg, sizeof s->msg);
    }
    char path[VI_PATH_MAX], key[sizeof s->profile_key];
    if (profile_path(s, p->profile_file, path, sizeof path) < 0)
        VI_FAIL(s->msg, sizeof s->msg, "profile_file '%.200s...': the path is too long", p->profile_file);
    if (!(p->R1 > 0.0))
        VI_FAIL(s->msg, sizeof s->msg, "profile_file: rolling needs a body radius R1 > 0 (R1 = %g m)", p->R1);
    snprintf(key, sizeof key, "%s|%.17g|%d", path, p->R1, p->profile_periodic != 0);
    if (!s->profile || strcmp(key, s->profile_key) != 0) {
        vi_profile_free(s->profile);
        s->profile_key[0] = '\0';
        s->profile = vi_profile_load(path, p->R1, p->profile_periodic, s->msg, sizeof s->msg);
        if (!s->profile) return -1;
        memcpy(s->profile_key, key, sizeof key);
    }
    return vi_model_set_rolling(M, s->profile, p->V, p->x0, s->msg, sizeof s->msg);
}

/* Warn once per instance and cause when the simulation leaves the model's range of validity
 * (vi_model_validity). */
void vi_sim_check_validity(vi_sim *s)
{
    char text[400];
    s->validity_unchecked = 0;
    for (int cause; (cause = vi_model_validity(&s->d.M, s->d.par.R1, s->d.t, s->d.x, s->warned_validity, text,
                                               sizeof text)) != 0;) { /* bounded: one more bit each time */
        s->warned_validity |= cause;
        s->log(s->log_env, VI_LOG_WARNING, "%s", text);
    }
}

static void set_input_ramps(vi_model *M, const vi_sim_data *d, double t)
{
    M->yC_in = (vi_ramp){d->in.yC_in, d->din.yC_in, t};
    M->F_ext = (vi_ramp){d->in.F_ext, d->din.F_ext, t};
}

static double rtol_of(const vi_sim_data *d) { return d->tolerance > 0.0 ? d->tolerance : d->par.rtol; }
static void arm_guards_at_zero(vi_sim_data *d);

/* Are the outputs and calculated parameters at the current state finite? -1 (s->msg, naming the
 * first that is not) when the parameters and inputs lead to values beyond the range of double (a
 * Johnson load of 1e300 N: the plastic work is inf - inf), which are refused rather than reported. */
static int outputs_finite(vi_sim *s)
{
    vi_outputs out;
    s->out_valid = 0;
    vi_sim_outputs(s, &out);
    for (int vr = 0; vr < VI_NVARS; vr++) {
        const vi_variable *v = &vi_variable_table[vr];
        double x;
        if (v->group != VI_GROUP_OUTPUTS || v->type != VI_Real) continue;
        memcpy(&x, (const char *)&out + v->offset, sizeof x);
        if (!isfinite(x)) {
            snprintf(s->msg, sizeof s->msg, "%s = %g at t = %.17g s: the parameters and inputs lead to values beyond the "
                     "range of double", v->name, x, s->d.t);
            return -1;
        }
    }
    return 0;
}

int vi_sim_prepare(vi_sim *s)
{
    vi_sim_data *d = &s->d;
    const vi_parameters *p = &d->par;
    s->out_valid = 0;
    /* The parameters lie in the ranges of the variable table (rtol among them); left to check: the
     * experiment's tolerance, and max_step between 0 and VI_MAX_STEP_MIN. */
    if (d->tolerance > 0.0 && !(d->tolerance >= VI_RTOL_MIN && d->tolerance <= VI_RTOL_MAX))
        VI_FAIL(s->msg, sizeof s->msg, "relative tolerance (the importer's: fmi2SetupExperiment, fmi3EnterInitializationMode) = %g: "
                "use a value in [%g, %g]",
                d->tolerance, VI_RTOL_MIN, VI_RTOL_MAX);
    if (!(p->max_step == 0.0 || p->max_step >= VI_MAX_STEP_MIN))
        VI_FAIL(s->msg, sizeof s->msg, "max_step = %g s: use 0 (no limit) or a step >= %g s", p->max_step,
                VI_MAX_STEP_MIN);
    if (vi_model_setup(&d->M, p, d->t_start, s->msg, sizeof s->msg) < 0) return -1;
    if (attach_profile(s) < 0) return -1;
    d->t = d->t_start;
    set_input_ramps(&d->M, d, d->t);
    d->inputs_changed = 0;
    vi_model_initial_state(&d->M, p->init, p->v0, d->t, d->x);
    d->n_events = 0;
    d->step_t0 = d->t;
    d->step_v0 = d->x[1];
    memset(d->guard_band, 0, sizeof d->guard_band);
    return outputs_finite(s);
}

/* (Re)create the solver with the tolerances stored in s->d: starting at the current state, or
 * (resume) continuing the continuation in s->d as it is. */
static int create_solver(vi_sim *s, int resume)
{
    vi_sim_data *d = &s->d;
    vi_solver_free(s->solver);
    vi_solver_config cfg = {
        .n = 2, .nguards = VI_NGUARDS, .rhs = sim_rhs, .guards = sim_guards, .jac = sim_jac, .user = d,
        .method = d->par.solver, .rtol = rtol_of(d), .atol = d->atol, .max_step = d->par.max_step,
        .ode = &d->ode, .sw = &d->sw, .log = s->log, .log_env = s->log_env};
    s->solver = resume ? vi_solver_resume(&cfg, d->t, d->x) : vi_solver_create(&cfg, d->t, d->x);
    s->solver_stale = 0;
    if (!s->solver)
        VI_FAIL(s->msg, sizeof s->msg, "could not create the solver");
    return 0;
}

int vi_sim_initialize(vi_sim *s)
{
    if (vi_sim_prepare(s) < 0) return -1;
    vi_sim_data *d = &s->d;
    double L, V, rtol = rtol_of(d);
    vi_model_scales(&d->M, d->x, &L, &V);
    d->atol[0] = rtol * L;
    d->atol[1] = rtol * V;
    d->initialized = 1;
    arm_guards_at_zero(d);
    memset(&d->ode, 0, sizeof d->ode);
    memset(&d->sw, 0, sizeof d->sw);
    if (create_solver(s, 0) < 0) return -1;
    char text[400];
    if (vi_model_option_warnings(&d->par, text, sizeof text) > 0) s->log(s->log_env, VI_LOG_WARNING, "%s", text);
    vi_sim_check_validity(s);
    return 0;
}

void vi_sim_log_solver(const vi_sim *s)
{
    const vi_sim_data *d = &s->d;
    double rtol = rtol_of(d);
    s->log(s->log_env, VI_LOG_SOLVER, "%s, rtol %g, atol %g m and %g m/s (scales %g m, %g m/s)",
           vi_solver_method_name(d->par.solver), rtol, d->atol[0], d->atol[1], d->atol[0] / rtol, d->atol[1] / rtol);
}

int vi_sim_checkpoint(vi_sim *s)
{
    if (!s->d.initialized || !s->solver) return 0;
    if (vi_solver_checkpoint(s->solver, s->d.t, s->d.x) < 0)
        VI_FAIL(s->msg, sizeof s->msg, "could not restart the solver at t = %.17g s", s->d.t);
    s->solver_stale = 0;
    return 0;
}

static int restore(vi_sim *s, int with_solver)
{
    s->out_valid = 0;
    s->validity_unchecked = 1;
    if (!s->d.initialized || !with_solver) { /* before initialization (no solver until then), or Model Exchange */
        vi_solver_free(s->solver);
        s->solver = NULL;
        if (!s->d.initialized) return 0;
    }
    if (attach_profile(s) < 0) return -1; /* the restored model's profile pointer is replaced by ours */
    return with_solver ? create_solver(s, 1) : 0;
}

int vi_sim_restore(vi_sim *s) { return restore(s, 1); }
int vi_sim_restore_without_solver(vi_sim *s) { return restore(s, 0); }

/* New input values (and tunable a, f) take effect at time t: the platform may jump (the mass does
 * not), the force may step; the mode is then chosen afresh from the new state. An input that
 * continues its previous ramp (held, or the same slope) changes nothing and does not restart the
 * solver. */
static void apply_inputs(vi_sim *s)
{
    vi_sim_data *d = &s->d;
    vi_model *M = &d->M;
    double t = d->t;
    d->inputs_changed = 0;
    vi_ramp y_old = M->yC_in, f_old = M->F_ext;
    double y_old_t = vi_ramp_at(&y_old, t), f_old_t = vi_ramp_at(&f_old, t);
    if (d->in.yC_in == y_old_t && d->din.yC_in == y_old.du && d->in.F_ext == f_old_t && d->din.F_ext == f_old.du &&
        !vi_model_excitation_differs(M, d->par.a, d->par.f))
        return; /* the same signal: nothing happens */
    vi_model_freeze(M, t, d->x);
    int mode = M->mode;
    d->x[0] += d->in.yC_in - y_old_t; /* delta jumps with the platform */
    set_input_ramps(M, d, t);
    vi_model_set_excitation(M, t, d->x, d->par.a, d->par.f);
    if (vi_model_resolve(M, t, d->x) != mode) {
        s->log(s->log_env, VI_LOG_EVENTS, "t = %.17g s: input change, mode %d -> %d", t, mode, M->mode);
        memset(d->guard_band, 0, sizeof d->guard_band);
    }
    arm_guards_at_zero(d);
    s->solver_stale = 1;
    vi_sim_check_validity(s); /* a new amplitude */
}

/* ---- re-arming of guards after events that keep the mode ----------------------------------- */

/* The noise of the guards at (t, x): how much each moves under rounding (one ulp of t and of each
 * state; ulps[i]) and under a state error of the integration tolerance (rtol |x_k| + atol_k in each
 * state; tol[i]). */
static void guard_noise(const vi_sim_data *d, double ulps[VI_NGUARDS], double tol[VI_NGUARDS])
{
    const vi_model *M = &d->M;
    double g0[VI_NGUARDS], g[VI_NGUARDS], y[2] = {d->x[0], d->x[1]}, rtol = rtol_of(d);
    vi_model_guards(M, d->t, y, g0);
    vi_model_guards(M, nextafter(d->t, INFINITY), y, g);
    for (int i = 0; i < VI_NGUARDS; i++) ulps[i] = fabs(g[i] - g0[i]), tol[i] = 0.0;
    for (int k = 0; k < 2; k++) {
        y[k] = nextafter(d->x[k], INFINITY);
        vi_model_guards(M, d->t, y, g);
        for (int i = 0; i < VI_NGUARDS; i++) ulps[i] += fabs(g[i] - g0[i]);
        y[k] = d->x[k] + (rtol * fabs(d->x[k]) + d->atol[k]);
        vi_model_guards(M, d->t, y, g);
        for (int i = 0; i < VI_NGUARDS; i++) tol[i] += fabs(g[i] - g0[i]);
        y[k] = d->x[k];
    }
}

/* A disarmed guard is armed again once it lies above its band. */
static void rearm_guards(vi_sim_data *d)
{
    int any = 0;
    for (int i = 0; i < VI_NGUARDS; i++) any |= d->guard_band[i] > 0.0;
    if (!any) return;
    double g[VI_NGUARDS];
    vi_model_guards(&d->M, d->t, d->x, g);
    for (int i = 0; i < VI_NGUARDS; i++)
        if (d->guard_band[i] > 0.0 && g[i] > d->guard_band[i]) d->guard_band[i] = 0.0;
}

/* The guards of a mode just entered (or of a state just changed from outside) that start at zero,
 * up to rounding, the state snapped onto their surface: shifted up by their rounding noise, so that
 * they count as positive from the start (the mode was chosen because the motion goes inside) and a
 * crossing back, however soon, is found. (A guard that starts at zero would otherwise wait until it
 * has been seen positive, and a short excursion within one step would be missed.) */
static void arm_guards_at_zero(vi_sim_data *d)
{
    double g[VI_NGUARDS], ulps[VI_NGUARDS], tol[VI_NGUARDS];
    vi_model_guards(&d->M, d->t, d->x, g);
    guard_noise(d, ulps, tol);
    for (int i = 0; i < VI_NGUARDS; i++) {
        double noise = VI_GRAZE_ULPS * ulps[i] + DBL_MIN;
        if (d->guard_band[i] == 0.0 && fabs(g[i]) <= noise) d->guard_band[i] = noise;
    }
}

/* ---- the loop ------------------------------------------------------------------------------- */

int vi_sim_zeno_count(int count, double t_before, double t)
{
    double ulp = nextafter(fabs(t), INFINITY) - fabs(t);
    return t - t_before <= VI_ZENO_ULPS * ulp ? count + 1 : 0;
}

/* End the advance early (doc/model.md section 7.1): the state at d->t is consistent and usable. */
static int discard(vi_sim *s, const char *fmt, ...) VI_PRINTF_FORMAT(2, 3);
static int discard(vi_sim *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->msg, sizeof s->msg, fmt, ap);
    va_end(ap);
    return VI_SIM_DISCARD;
}

/* One event at d->t: guard `fired` of the current mode reached zero. When the mode stays, that guard
 * sits at zero and is disarmed (band) until it has moved away. */
static void apply_event(vi_sim *s, int fired)
{
    vi_sim_data *d = &s->d;
    int from = d->M.mode;
    vi_model_event(&d->M, d->t, d->x, fired);
    d->n_events++;
    s->log(s->log_env, VI_LOG_EVENTS, "t = %.17g s: guard %d of mode %d, mode %d -> %d, delta = %.9g m, v = %.9g m/s",
           d->t, fired, from, from, d->M.mode, d->x[0], d->x[1]);
    vi_sim_check_validity(s);
    if (d->M.mode != from) {
        memset(d->guard_band, 0, sizeof d->guard_band);
        arm_guards_at_zero(d);
        return;
    }
    rearm_guards(d);
    double ulps[VI_NGUARDS], tol[VI_NGUARDS];
    guard_noise(d, ulps, tol);
    d->guard_band[fired] = VI_GRAZE_TOL * tol[fired] + VI_GRAZE_ULPS * ulps[fired] + DBL_MIN;
}

/* A kink of the rolling profile at d->t (doc/model.md section 6): the platform velocity jumps, so the rate of
 * delta does; the mode is chosen afresh (as after an input jump) and the solver restarts. */
static int apply_breakpoint(vi_sim *s)
{
    vi_sim_data *d = &s->d;
    int from = d->M.mode;
    if (vi_model_breakpoint(&d->M, d->t, d->x) != from) {
        s->log(s->log_env, VI_LOG_EVENTS, "t = %.17g s: profile kink, mode %d -> %d", d->t, from, d->M.mode);
        memset(d->guard_band, 0, sizeof d->guard_band);
    }
    arm_guards_at_zero(d);
    return vi_solver_reset(s->solver, d->t, d->x);
}

/* Early return: does the advance end here, after an event or a profile kink that may have switched
 * the mode from mode_before? Only when asked, the mode changed, and the time lies beyond the instant
 * the advance started (more than VI_EARLY_RETURN_UNITS units of the time resolution after it): mode
 * changes at that instant are taken in the same advance, so every early return makes a step an
 * importer can take with its other FMUs, and events accumulating at one instant still meet the
 * Zeno rule. */
static int stop_here(const vi_sim *s, int stop_at_mode_change, int mode_before)
{
    double unit = DBL_EPSILON * fmax(1.0, fabs(s->d.t));
    return stop_at_mode_change && s->d.M.mode != mode_before && s->d.t - s->d.step_t0 > VI_EARLY_RETURN_UNITS * unit;
}

int vi_sim_advance(vi_sim *s, double t_end) { return vi_sim_advance_until(s, t_end, 0); }

int vi_sim_advance_until(vi_sim *s, double t_end, int stop_at_mode_change)
{
    vi_sim_data *d = &s->d;
    if (!s->solver) {
        snprintf(s->msg, sizeof s->msg, "the simulation is not initialized");
        return VI_SIM_ERROR;
    }
    if (!(t_end > d->t)) {
        snprintf(s->msg, sizeof s->msg, "the step end %.17g s does not exceed the current time %.17g s in floating point",
                 t_end, d->t);
        return VI_SIM_ERROR;
    }
    s->out_valid = 0;
    d->step_t0 = d->t;
    d->step_v0 = d->x[1];
    if (d->inputs_changed) apply_inputs(s);
    rearm_guards(d);
    if (s->solver_stale) {
        if (vi_solver_reset(s->solver, d->t, d->x) < 0) goto fail;
        s->solver_stale = 0;
    }
    long steps_left = VI_MAX_STEPS_PER_ADVANCE, events = 0, kinks = 0;
    int zeno = 0, stopped = 0; /* stopped: at a mode change, asked for by stop_at_mode_change */
    int fired[VI_SOLVER_MAX_GUARDS];
    char why[400]; /* rolling: a non-periodic profile ends at `limit` */
    double limit = d->M.profile ? vi_model_rolling_limit(&d->M, why, sizeof why) : INFINITY;
    double target = limit < t_end ? limit : t_end;
    /* bounded: every pass is an event (bounded below) or a kink of the profile (finitely many in the
     * distance |V| (t_end - t) rolled) */
    while (d->t < target) {
        long taken = 0;
        int mode_before = d->M.mode;
        double t_before = d->t, bp = d->M.profile ? vi_model_next_breakpoint(&d->M, d->t) : INFINITY;
        double stop = bp < target ? bp : target;
        int rc = VI_SOLVER_REACHED;
        if ((stop == bp || kinks) && stop - d->t <= VI_BREAKPOINT_ULPS * DBL_EPSILON * fabs(stop)) {
            d->t = stop; /* a kink, or the end after one, within rounding of now: too close for the solver */
            if (vi_solver_reset(s->solver, d->t, d->x) < 0) goto fail;
        } else
            rc = vi_solver_advance(s->solver, stop, steps_left, &d->t, d->x, fired, &taken);
        steps_left -= taken;
        if (rc == VI_SOLVER_FAILED) goto fail;
        if (rc == VI_SOLVER_REACHED) {
            if (stop == bp) {
                kinks++;
                if (apply_breakpoint(s) < 0) goto fail;
            }
            if ((stopped = stop_here(s, stop_at_mode_change, mode_before))) break;
            if (d->t >= target) break;
            continue;
        }
        if (rc == VI_SOLVER_LIMIT)
            return discard(s, "work bound: %ld internal steps in one step, stopped at t = %.17g s (mode %d); "
                              "continue from there or use smaller communication steps",
                           VI_MAX_STEPS_PER_ADVANCE, d->t, d->M.mode);
        int g = 0;
        while (g < VI_NGUARDS - 1 && fired[g] == 0) g++;
        apply_event(s, g);
        if (vi_solver_reset(s->solver, d->t, d->x) < 0) goto fail;
        zeno = vi_sim_zeno_count(zeno, t_before, d->t);
        if (zeno >= VI_ZENO_EVENTS)
            return discard(s, "events accumulate at t = %.17g s (Zeno): %d events each within %g ulps of time of the "
                              "one before, the last on guard %d of mode %d; stopped there",
                           d->t, VI_ZENO_EVENTS, VI_ZENO_ULPS, g, d->M.mode);
        if (++events >= VI_MAX_EVENTS_PER_ADVANCE && d->t < t_end)
            return discard(s, "work bound: %ld events in one step, stopped at t = %.17g s (mode %d); "
                              "continue from there or use smaller communication steps",
                           VI_MAX_EVENTS_PER_ADVANCE, d->t, d->M.mode);
        if ((stopped = stop_here(s, stop_at_mode_change, mode_before))) break;
    }
    if (!isfinite(d->x[0]) || !isfinite(d->x[1])) {
        snprintf(s->msg, sizeof s->msg, "the state is not finite at t = %.17g s", d->t);
        return VI_SIM_ERROR;
    }
    /* at a communication point only the indentation can newly leave the range (a changes in
     * apply_inputs, which checks; the profile is fixed), unless a state was restored since */
    if (s->validity_unchecked ||
        (!(s->warned_validity & VI_INVALID_INDENTATION) && vi_model_indentation_invalid(&d->M, d->x)))
        vi_sim_check_validity(s);
    if (stopped) return VI_SIM_EVENT;
    if (t_end > limit) return discard(s, "%s", why); /* the end of the profile: nothing beyond it */
    d->t = t_end;
    return VI_SIM_OK;
fail:
    snprintf(s->msg, sizeof s->msg, "the solver failed near t = %.17g s (mode %d, delta = %g m, v = %g m/s)", d->t,
             d->M.mode, d->x[0], d->x[1]);
    return VI_SIM_ERROR;
}

/* ---- outputs -------------------------------------------------------------------------------- */

/* Tangent contact stiffness dF/ddelta [N/m] (0 out of contact). A sticking mass is held at delta_c
 * between the two branches; small unloading would follow the unloading curve, so its stiffness. */
static double contact_stiffness(const vi_model *M, double t, const double x[2])
{
    if (M->mode == VI_Mode_stick) return vi_unload_stiffness(&M->U, M->U.delta_c);
    return M->m * vi_model_stiffness_over_mass(M, t, x);
}

/* The contact force averaged over the last step [t0, t]: the impulse over the step divided by it,
 * from the momentum balance m v' = F - W(t), W = P + m g - F_ext(t) (F_ext linear over the step, so
 * its mean is its midpoint value). Before any step: the force itself. */
static double mean_force(const vi_sim_data *d)
{
    const vi_model *M = &d->M;
    double h = d->t - d->step_t0;
    if (!(h > 0.0)) return vi_model_force(M, d->t, d->x);
    double W_mean = M->W0 - vi_ramp_at(&M->F_ext, d->step_t0 + 0.5 * h);
    return M->m * (d->x[1] - d->step_v0) / h + W_mean;
}

const vi_outputs *vi_sim_outputs_of(vi_sim *s, unsigned groups)
{
    unsigned need = groups & (VI_OUT_ALL & ~VI_OUT_DERIVATIVES) & ~s->out_valid;
    if (need) {
        const vi_sim_data *d = &s->d;
        vi_model_outputs(&d->M, d->t, d->x, need, &s->out);
        if (need & VI_OUT_MEAN) s->out.F_mean = mean_force(d);
        if (need & VI_OUT_STIFFNESS) s->out.k_contact = contact_stiffness(&d->M, d->t, d->x);
        s->out_valid |= need;
    }
    return &s->out;
}

void vi_sim_outputs(vi_sim *s, vi_outputs *out) { *out = *vi_sim_outputs_of(s, VI_OUT_ALL); }

/* ---- validity of a state payload (doc/model.md section 7.6) --------------------------------- */


static int data_check(const vi_sim_data *d, int surfaces, char *msg, size_t n)
{
    if (d->inputs_changed != 0 && d->inputs_changed != 1)
        VI_FAIL(msg, n, "inputs_changed = %d is not 0 or 1", d->inputs_changed);
    if (!isfinite(d->t_start)) VI_FAIL(msg, n, "t_start = %g is not finite", d->t_start);
    if (d->tolerance != 0.0 && !(d->tolerance >= VI_RTOL_MIN && d->tolerance <= VI_RTOL_MAX))
        VI_FAIL(msg, n, "tolerance = %g is neither 0 nor in [%g, %g]", d->tolerance, VI_RTOL_MIN, VI_RTOL_MAX);
    if (!isfinite(d->t) || d->t < d->t_start)
        VI_FAIL(msg, n, "t = %g is not finite or before t_start = %g", d->t, d->t_start);
    for (int i = 0; i < 2; i++) {
        if (!isfinite(d->x[i])) VI_FAIL(msg, n, "x[%d] = %g is not finite", i, d->x[i]);
        if (!(d->atol[i] >= 0.0 && isfinite(d->atol[i])))
            VI_FAIL(msg, n, "atol[%d] = %g is not finite and >= 0", i, d->atol[i]);
    }
    if (d->n_events < 0) VI_FAIL(msg, n, "n_events = %ld is negative", d->n_events);
    if (d->initialized != 0 && d->initialized != 1) VI_FAIL(msg, n, "initialized = %d is not 0 or 1", d->initialized);
    if (!isfinite(d->step_t0) || d->step_t0 > d->t || !isfinite(d->step_v0))
        VI_FAIL(msg, n, "step_t0 = %g, step_v0 = %g: not finite or after t", d->step_t0, d->step_v0);
    for (int i = 0; i < VI_NGUARDS; i++)
        if (!(d->guard_band[i] >= 0.0 && isfinite(d->guard_band[i])))
            VI_FAIL(msg, n, "guard_band[%d] = %g is not finite and >= 0", i, d->guard_band[i]);
    /* the solver's continuation (co-simulation; Model Exchange states, between events, have none in use) */
    int solver = d->initialized && surfaces;
    if (solver && d->par.solver == VI_Solver_auto && vi_solver_auto_check(&d->sw, msg, n) < 0) return -1;
    int one_step = d->par.solver == VI_Solver_dop853 || (d->par.solver == VI_Solver_auto && !d->sw.bdf);
    if (solver && one_step && vi_solver_ode_check(&d->ode, 2, VI_NGUARDS, d->t, msg, n) < 0) return -1;
    return surfaces ? vi_model_check(&d->M, d->x, msg, n) : vi_model_check_between_events(&d->M, d->x, msg, n);
}

int vi_sim_data_check(const vi_sim_data *d, char *msg, size_t n) { return data_check(d, 1, msg, n); }
int vi_sim_data_check_between_events(const vi_sim_data *d, char *msg, size_t n) { return data_check(d, 0, msg, n); }

void vi_sim_statistics(const vi_sim *s, vi_solver_stats *st)
{
    if (s->solver) vi_solver_statistics(s->solver, st);
    else memset(st, 0, sizeof *st);
}
