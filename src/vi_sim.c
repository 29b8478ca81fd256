/* vi_sim.c - a simulation: inputs, initial state, and the event loop around the solver. */
#include "vi_sim.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Consecutive events within one step before the step is refused as chattering (Zeno). */
#define VI_MAX_EVENTS_PER_STEP 100000L
#define VI_MAX_STEPS_PER_ADVANCE 500000L

static void sim_rhs(double t, const double *x, double *dx, void *user) { vi_model_rhs(user, t, x, dx); }
static void sim_guards(double t, const double *x, double *g, void *user) { vi_model_guards(user, t, x, g); }
static void sim_jac(double t, const double *x, double *j, void *user)
{
    vi_model_jacobian(user, t, x, j);
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

/* Load (or keep, when file, R1 and periodicity are those it was built for) the profile and hand it
 * to the model with V and x0. Called after vi_model_setup and after a restore: a profile pointer
 * read from a saved state is never used. 0, or -1 (s->msg). */
static int attach_profile(vi_sim *s, const char *file, double V, double x0, int periodic)
{
    vi_model *M = &s->d.M;
    double R1 = s->d.par.R1;
    if (!file || !file[0]) {
        vi_profile_free(s->profile);
        s->profile = NULL;
        s->profile_key[0] = '\0';
        return vi_model_set_rolling(M, NULL, V, x0, s->msg, sizeof s->msg);
    }
    char path[VI_PATH_MAX], key[sizeof s->profile_key];
    if (profile_path(s, file, path, sizeof path) < 0) {
        snprintf(s->msg, sizeof s->msg, "profile_file '%.200s...': the path is too long", file);
        return -1;
    }
    if (!(R1 > 0.0)) {
        snprintf(s->msg, sizeof s->msg, "profile_file: rolling needs a body radius R1 > 0 (R1 = %g m)", R1);
        return -1;
    }
    snprintf(key, sizeof key, "%s|%.17g|%d", path, R1, periodic != 0);
    if (!s->profile || strcmp(key, s->profile_key) != 0) {
        vi_profile_free(s->profile);
        s->profile_key[0] = '\0';
        s->profile = vi_profile_load(path, R1, periodic, s->msg, sizeof s->msg);
        if (!s->profile) return -1;
        memcpy(s->profile_key, key, sizeof key);
    }
    return vi_model_set_rolling(M, s->profile, V, x0, s->msg, sizeof s->msg);
}

static void set_input_ramps(vi_model *M, const vi_sim_data *d, double t)
{
    M->yC_in = (vi_ramp){d->in.yC_in, d->din.yC_in, t};
    M->F_ext = (vi_ramp){d->in.F_ext, d->din.F_ext, t};
}

static double rtol_of(const vi_sim_data *d) { return d->tolerance > 0.0 ? d->tolerance : d->par.rtol; }

int vi_sim_prepare(vi_sim *s)
{
    vi_sim_data *d = &s->d;
    const vi_parameters *p = &d->par;
    double rtol = rtol_of(d);
    if (!(rtol >= 1e-14 && rtol < 1.0)) {
        snprintf(s->msg, sizeof s->msg, "relative tolerance %g: use a value in [1e-14, 1)", rtol);
        return -1;
    }
    if (!(p->max_step >= 0.0 && isfinite(p->max_step))) {
        snprintf(s->msg, sizeof s->msg, "max_step = %g s: use 0 (none) or a positive step", p->max_step);
        return -1;
    }
    if (p->solver != VI_Solver_bdf && p->solver != VI_Solver_adams) {
        snprintf(s->msg, sizeof s->msg, "solver = %d: use bdf (1) or adams (2)", p->solver);
        return -1;
    }
    if (!isfinite(d->in.yC_in) || !isfinite(d->in.F_ext)) {
        snprintf(s->msg, sizeof s->msg, "the inputs yC_in and F_ext must be finite");
        return -1;
    }
    if (vi_model_setup(&d->M, p, d->t_start, s->msg, sizeof s->msg) < 0) return -1;
    if (attach_profile(s, "", 0.0, 0.0, 0) < 0) return -1; /* TODO(M): profile_file, V, x0, profile_periodic */
    d->t = d->t_start;
    set_input_ramps(&d->M, d, d->t);
    d->inputs_changed = 0;
    vi_model_initial_state(&d->M, p->init, p->v0, d->t, d->x);
    d->n_events = 0;
    return 0;
}

/* (Re)create the solver at the current state with the tolerances stored in s->d. */
static int create_solver(vi_sim *s)
{
    vi_sim_data *d = &s->d;
    vi_solver_free(s->solver);
    vi_solver_config cfg = {
        .n = 2, .nguards = VI_NGUARDS, .rhs = sim_rhs, .guards = sim_guards, .jac = sim_jac, .user = &d->M,
        .adams = d->par.solver == VI_Solver_adams, .rtol = rtol_of(d), .atol = d->atol,
        .max_step = d->par.max_step, .max_steps = VI_MAX_STEPS_PER_ADVANCE, .log = s->log, .log_env = s->log_env};
    s->solver = vi_solver_create(&cfg, d->t, d->x);
    s->solver_stale = 0;
    if (!s->solver) {
        snprintf(s->msg, sizeof s->msg, "could not create the CVODE solver");
        return -1;
    }
    return 0;
}

/* Warn once per instance when the contact leaves the model's range of validity (contract C6). */
static void check_validity(vi_sim *s)
{
    char text[400];
    if (!s->warned_validity && vi_model_validity(&s->d.M, s->d.t, s->d.x, text, sizeof text)) {
        s->warned_validity = 1;
        s->log(s->log_env, VI_LOG_WARNING, "%s", text);
    }
}

int vi_sim_initialize(vi_sim *s)
{
    if (vi_sim_prepare(s) < 0) return -1;
    vi_sim_data *d = &s->d;
    double L, V, rtol = rtol_of(d);
    vi_model_scales(&d->M, d->x, &L, &V);
    d->atol[0] = rtol * L;
    d->atol[1] = rtol * V;
    if (create_solver(s) < 0) return -1;
    char text[400];
    if (vi_model_option_warnings(&d->par, text, sizeof text) > 0) s->log(s->log_env, VI_LOG_WARNING, "%s", text);
    check_validity(s);
    s->log(s->log_env, VI_LOG_SOLVER, "CVODE %s, rtol %g, atol %g m and %g m/s (scales %g m, %g m/s)",
           d->par.solver == VI_Solver_adams ? "Adams" : "BDF", rtol, d->atol[0], d->atol[1], L, V);
    return 0;
}

int vi_sim_restore(vi_sim *s) { return create_solver(s); }

/* New input values (and tunable a, f) take effect at time t: the platform may jump (the mass does
 * not), the force may step; the mode is then chosen afresh from the new state. 0, or -1 (s->msg). */
static int apply_inputs(vi_sim *s)
{
    vi_sim_data *d = &s->d;
    vi_model *M = &d->M;
    double t = d->t;
    d->inputs_changed = 0;
    vi_ramp y_old = M->yC_in, f_old = M->F_ext;
    double y_old_t = vi_ramp_at(&y_old, t), f_old_t = vi_ramp_at(&f_old, t);
    if (d->in.yC_in == y_old_t && d->din.yC_in == y_old.du && d->in.F_ext == f_old_t && d->din.F_ext == f_old.du &&
        !vi_model_excitation_differs(M, d->par.a, d->par.f))
        return 0; /* the same signal: nothing happens */
    vi_model_freeze(M, t, d->x);
    int mode = M->mode;
    d->x[0] += d->in.yC_in - y_old_t; /* delta jumps with the platform */
    set_input_ramps(M, d, t);
    if (vi_model_set_excitation(M, t, d->x, d->par.a, d->par.f, s->msg, sizeof s->msg) < 0) return -1;
    if (vi_model_resolve(M, t, d->x) != mode)
        s->log(s->log_env, VI_LOG_EVENTS, "t = %.17g s: input change, mode %d -> %d", t, mode, M->mode);
    s->solver_stale = 1;
    return 0;
}

int vi_sim_advance(vi_sim *s, double t_end)
{
    vi_sim_data *d = &s->d;
    if (d->inputs_changed && apply_inputs(s) < 0) return -1;
    if (s->solver_stale) {
        if (vi_solver_reset(s->solver, d->t, d->x) < 0) goto fail;
        s->solver_stale = 0;
    }
    long events = 0;
    int fired[VI_NGUARDS];
    char why[400]; /* rolling: the profile ends at `limit` (contract C10 for the kinks below) */
    double limit = vi_model_rolling_limit(&d->M, why, sizeof why), target = fmin(t_end, limit);
    while (d->t < target) {
        double bp = vi_model_next_breakpoint(&d->M, d->t), stop = fmin(target, bp);
        int rc = vi_solver_advance(s->solver, stop, &d->t, d->x, fired);
        if (rc == VI_SOLVER_FAILED) goto fail;
        if (rc == VI_SOLVER_REACHED) {
            if (stop == bp) { /* the platform velocity jumps: choose the mode afresh, restart */
                int from = d->M.mode;
                if (vi_model_breakpoint(&d->M, d->t, d->x) != from)
                    s->log(s->log_env, VI_LOG_EVENTS, "t = %.17g s: profile kink, mode %d -> %d", d->t, from, d->M.mode);
                if (vi_solver_reset(s->solver, d->t, d->x) < 0) goto fail;
            }
            if (d->t >= target) break;
            continue;
        }
        int g = 0;
        while (g < VI_NGUARDS - 1 && fired[g] == 0) g++;
        int from = d->M.mode;
        vi_model_event(&d->M, d->t, d->x, g);
        d->n_events++;
        check_validity(s);
        s->log(s->log_env, VI_LOG_EVENTS, "t = %.17g s: guard %d of mode %d, mode %d -> %d, delta = %.9g m, v = %.9g m/s",
               d->t, g, from, from, d->M.mode, d->x[0], d->x[1]);
        if (++events > VI_MAX_EVENTS_PER_STEP) {
            snprintf(s->msg, sizeof s->msg, "more than %ld events in one step near t = %.17g s (chattering)",
                     VI_MAX_EVENTS_PER_STEP, d->t);
            return -1;
        }
        if (vi_solver_reset(s->solver, d->t, d->x) < 0) goto fail;
    }
    if (t_end > limit) { /* reached the end of the profile: nothing beyond it */
        snprintf(s->msg, sizeof s->msg, "%s", why);
        return -1;
    }
    d->t = t_end;
    if (!isfinite(d->x[0]) || !isfinite(d->x[1])) {
        snprintf(s->msg, sizeof s->msg, "the state is not finite at t = %.17g s", d->t);
        return -1;
    }
    check_validity(s);
    return 0;
fail:
    snprintf(s->msg, sizeof s->msg, "CVODE failed near t = %.17g s (mode %d, delta = %g m, v = %g m/s)", d->t,
             d->M.mode, d->x[0], d->x[1]);
    return -1;
}

void vi_sim_outputs(const vi_sim *s, vi_outputs *out)
{
    vi_model_calculated(&s->d.M, out);
    vi_model_outputs(&s->d.M, s->d.t, s->d.x, out);
}

void vi_sim_statistics(const vi_sim *s, vi_solver_stats *st)
{
    if (s->solver) vi_solver_statistics(s->solver, st);
    else memset(st, 0, sizeof *st);
}
