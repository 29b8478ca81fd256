/* vi_run.c - one run of the contact model, shared by both drivers: set-up from the parameters, the
 * initial state, the outputs, the validity warnings and the checks of a saved run; see vi_run.h. */
#include "vi_run.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vi_check.h"
#include "vi_format.h"


void vi_run_init(vi_run *r, vi_run_data *d, vi_run_source src, vi_log_fn log, void *log_env)
{
    memset(r, 0, sizeof *r);
    memset(d, 0, sizeof *d);
    r->d = d;
    r->src = src;
    r->log = log;
    r->log_env = log_env;
    vi_run_bind_engine(r, &r->engine, 0);
}

void vi_run_set_resources(vi_run *r, const char *dir)
{
    vi_snprintf(r->resources, sizeof r->resources, "%s", dir ? dir : "");
}

void vi_run_reset(vi_run *r)
{
    char resources[VI_PATH_MAX];
    memcpy(resources, r->resources, sizeof resources);
    vi_run_free(r);
    vi_run_init(r, r->d, r->src, r->log, r->log_env);
    memcpy(r->resources, resources, sizeof resources);
}

void vi_run_free(vi_run *r)
{
    vi_profile_free(r->profile);
    r->profile = NULL;
    r->profile_key[0] = '\0';
}

/* The file a profile_file names: as given when absolute; else in the resources folder if it is
 * there, else relative to the working directory. 0, or -1 when the path does not fit. */
static int profile_path(const vi_run *r, const char *file, char *path, size_t n)
{
    int k;
    if (file[0] != '/' && r->resources[0]) {
        k = vi_snprintf(path, n, "%s/%s", r->resources, file);
        FILE *f = k > 0 && (size_t)k < n ? vi_profile_fopen(path) : NULL;
        if (f) {
            fclose(f);
            return 0;
        }
    }
    k = vi_snprintf(path, n, "%s", file);
    return k > 0 && (size_t)k < n ? 0 : -1;
}

/* Load (or keep, when file, R1, periodicity and interpolation are those it was built for) the profile of
 * the settings and hand it to the model with V and x0. Called after vi_model_setup and after a
 * restore: the profile pointer read from a saved state is never used. 0, or -1 (r->msg). */
static int attach_profile(vi_run *r)
{
    const vi_model_params *p = &r->set.model;
    const char *profile_file = r->set.profile_file;
    if (!profile_file[0]) {
        vi_profile_free(r->profile);
        r->profile = NULL;
        r->profile_key[0] = '\0';
        return vi_hybrid_set_rolling(&r->engine, NULL, p->V, p->x0, r->msg, sizeof r->msg);
    }
    char path[VI_PATH_MAX], key[sizeof r->profile_key];
    if (profile_path(r, profile_file, path, sizeof path) < 0)
        VI_FAIL(r->msg, sizeof r->msg, "profile_file '%.200s...': the path is too long", profile_file);
    if (!(p->R1 > 0.0))
        VI_FAIL(r->msg, sizeof r->msg, "profile_file: rolling needs a body radius R1 > 0 (R1 = %g m)", p->R1);
    vi_snprintf(key, sizeof key, "%s|%.17g|%d|%d", path, p->R1, p->profile_periodic != 0, p->profile_interpolation);
    if (!r->profile || strcmp(key, r->profile_key) != 0) {
        vi_profile_free(r->profile);
        r->profile_key[0] = '\0';
        r->profile = vi_profile_load_as(path, p->R1, p->profile_periodic, p->profile_interpolation, r->msg,
                                        sizeof r->msg);
        if (!r->profile) return -1;
        memcpy(r->profile_key, key, sizeof key);
    }
    return vi_hybrid_set_rolling(&r->engine, r->profile, p->V, p->x0, r->msg, sizeof r->msg);
}

/* Warn once per instance and cause when the simulation leaves the model's range of validity
 * (vi_model_validity). */
void vi_run_check_validity(vi_run *r)
{
    char text[400];
    const vi_model *model = vi_hybrid_model(&r->engine);
    r->validity_unchecked = 0;
    for (int cause; (cause = vi_model_validity(model, r->set.model.R1, r->d->t, r->d->x, r->warned_validity, text,
                                               sizeof text)) != 0;) { /* bounded: one more bit each time */
        r->warned_validity |= cause;
        r->log(r->log_env, VI_LOG_WARNING, "%s", text);
    }
    if (r->warned_validity & VI_INVALID_FORCE) return; /* warned once: the force need not be evaluated again */
    double F_max = fmax(r->d->F_peak, vi_model_force(model, r->d->t, r->d->x)); /* the step's so far, and now */
    if (model->ncontacts > 1) F_max = fmax(F_max, vi_model_force_upper(model, r->d->t, r->d->x)); /* the upper one's now */
    if (vi_model_force_validity(model, F_max, r->d->t, text, sizeof text)) {
        r->warned_validity |= VI_INVALID_FORCE;
        r->log(r->log_env, VI_LOG_WARNING, "%s", text);
    }
}


static int time_scale_check(vi_run *r);

int vi_run_prepare(vi_run *r)
{
    vi_run_data *d = r->d;
    r->out_valid = 0;
    if (r->src.settings(r->src.env, &r->set, r->msg, sizeof r->msg) < 0) return -1;
    const vi_run_settings *p = &r->set;
    if (vi_hybrid_setup(&r->engine, &p->model, p->t_start, r->msg, sizeof r->msg) < 0) return -1;
    if (attach_profile(r) < 0) return -1;
    d->t = p->t_start;
    vi_ramp yC_in, F_ext;
    vi_run_input_ramps(r, d->t, &yC_in, &F_ext);
    d->inputs_changed = 0;
    vi_hybrid_prepare(&r->engine, d->t, yC_in, F_ext, p->model.init, p->model.v0, d->x);
    d->step_t0 = d->t;
    d->step_v0 = d->x[1];
    d->W_damping = 0.0;
    d->F_peak = vi_model_force(vi_hybrid_model(&r->engine), d->t, d->x);
    if (time_scale_check(r) < 0) return -1;
    r->out_valid = 0;
    return r->src.outputs_check(r->src.env, r->msg, sizeof r->msg);
}

void vi_run_tolerances(const vi_run *r, double *rtol, double atol[2])
{
    double L, V;
    *rtol = r->set.rtol;
    vi_model_scales(vi_hybrid_model(&r->engine), r->d->x, &L, &V);
    atol[0] = *rtol * L;
    atol[1] = *rtol * V;
}

void vi_run_bind_engine(const vi_run *r, vi_hybrid *engine, int integrates_y)
{
    vi_hybrid_bind(engine, &r->d->model, &r->d->events, integrates_y, r->log, r->log_env);
}

vi_run_data *vi_run_attach(const vi_run *r, vi_hybrid *engine, void *own, size_t own_size)
{
    memset(own, 0, own_size);
    vi_run_bind_engine(r, engine, 0);
    return r->d;
}

void vi_run_warn_settings(vi_run *r)
{
    const vi_run_settings *p = &r->set;
    char text[400];
    if (vi_model_option_warnings(&p->model, text, sizeof text) > 0) r->log(r->log_env, VI_LOG_WARNING, "%s", text);
    /* an importer that passes the declared default experiment's tolerance most likely passes a default */
    if (p->rtol_given > 0.0 && p->tolerance > 0.0 && p->tolerance != VI_RTOL_DEFAULT && p->rtol_given != p->tolerance)
        r->log(r->log_env, VI_LOG_WARNING, "rtol = %g is used, not the experiment's tolerance %g (set rtol = 0 to use the "
               "experiment's)", p->rtol_given, p->tolerance);
    vi_run_check_validity(r);
}

int vi_run_restore(vi_run *r)
{
    r->out_valid = 0;
    r->validity_unchecked = 1;
    if (r->src.settings(r->src.env, &r->set, r->msg, sizeof r->msg) < 0) return -1;
    if (!r->d->initialized) return 0; /* before initialization: no model set up yet */
    return attach_profile(r); /* the restored model's profile pointer is replaced by ours */
}

/* ---- the contact's time scale ----------------------------------------------------------------- */

double vi_run_time_scale(const vi_run *r, double *k_out, char *note, size_t n)
{
    const vi_model *model = vi_hybrid_model(&r->engine);
    const vi_model_contact *c = vi_model_lower(model);
    double m = model->body.m, at = r->d->x[0], T;
    double k = c->mode == VI_MODE_FREE ? 0.0 : vi_run_contact_stiffness(model, r->d->t, r->d->x);
    const char *where = "at the indentation";
    if (k > 0.0 && isfinite(k)) {
        T = sqrt(m) / sqrt(k);
    } else {
        double L, V;
        vi_model_scales(model, r->d->x, &L, &V);
        T = L / V, at = L, where = "at the indentation scale";
        k = sqrt(m) * (V / L), k *= k; /* m (V/L)^2 without overflow for a tiny m */
    }
    const vi_johnson *J = &c->johnson;
    if (c->law == VI_LAW_LINEAR)
        vi_snprintf(note, n, "sqrt(m/k) = %.3g s (m = %g kg, k = k_spring = %g N/m)", T, m, k);
    else
        vi_snprintf(note, n, "sqrt(m/k) = %.3g s (m = %g kg, k = %.3g N/m, the law's stiffness %s %.3g m, from E* = %g Pa "
                    "and R* = %g m)", T, m, k, where, at, J->E_star, J->R_star);
    *k_out = k;
    return T;
}

/* Refuse at initialization what double precision cannot integrate: a contact whose rate k/m = 1/T^2
 * overflows (the Jacobian's entry, the contact frequency f_contact), naming m and the smallest mass
 * with that stiffness. */
static int time_scale_check(vi_run *r)
{
    char note[300];
    double k, T = vi_run_time_scale(r, &k, note, sizeof note), rate = 1.0 / T;
    if (isfinite(rate * rate)) return 0;
    VI_FAIL(r->msg, sizeof r->msg, "m = %g kg is too small for the contact: its time scale %s makes the rate k/m = "
            "1/T^2 overflow double; use m >= %.3g kg with this contact: the motion of a "
            "smaller mass cannot be integrated in double precision", vi_hybrid_model(&r->engine)->body.m, note, k / DBL_MAX * 2.0);
}


/* ---- outputs -------------------------------------------------------------------------------- */

/* Tangent contact stiffness: a sticking mass is held at delta_c between the two branches; small
 * unloading would follow the unloading curve, so its stiffness. */
double vi_run_contact_stiffness(const vi_model *model, double t, const double x[2])
{
    const vi_model_contact *c = vi_model_lower(model);
    if (c->mode == VI_MODE_STICK) return vi_unload_stiffness(&c->unload, c->unload.delta_c);
    return model->body.m * vi_model_stiffness_over_mass(model, t, x);
}

/* The contact force averaged over the last step [t0, t]: the impulse over the step divided by it,
 * from the momentum balance m v' = F - W(t), W = P + m g - F_ext(t) (F_ext linear over the step, so
 * its mean is its midpoint value). Before any step: the net contact force itself, F - F_upper. */
static double mean_force(const vi_run *r)
{
    const vi_run_data *d = r->d;
    const vi_model *model = vi_hybrid_model(&r->engine);
    double h = d->t - d->step_t0;
    if (!(h > 0.0)) return vi_model_force(model, d->t, d->x) - vi_model_force_upper(model, d->t, d->x);
    double W_mean = model->body.W0 - vi_ramp_at(&model->F_ext, d->step_t0 + 0.5 * h);
    return model->body.m * (d->x[1] - d->step_v0) / h + W_mean;
}

void vi_run_compute_outputs(vi_run *r, unsigned need)
{
    const vi_run_data *d = r->d;
    const vi_model *model = vi_hybrid_model(&r->engine);
    if (need == VI_OUT_PLATFORM) { /* y alone, an importer's usual read: vi_model_outputs' platform group */
        r->out.model.yC = vi_model_platform(model, d->t, NULL, NULL);
        r->out.model.y = r->out.model.yC - d->x[0];
        r->out_valid |= need;
        return;
    }
    vi_model_outputs(model, d->t, d->x, need, &r->out.model);
    if (need & VI_OUT_MEMORY) { /* both contacts' plastic work */
        double W_plastic = r->out.model.W_plastic;
        if (model->ncontacts > 1) W_plastic += r->out.model.W_plastic_upper;
        r->out.W_damping = d->W_damping, r->out.W_dissipated = W_plastic + d->W_damping;
    }
    if (need & VI_OUT_FORCE) r->out.F_peak = fmax(d->F_peak, r->out.model.F);
    if (need & VI_OUT_MEAN) r->out.F_mean = mean_force(r);
    if (need & VI_OUT_STIFFNESS) r->out.k_contact = vi_run_contact_stiffness(model, d->t, d->x);
    r->out_valid |= need;
}

/* ---- validity of a state payload (doc/model.md section 7.6) --------------------------------- */

int vi_run_data_check(const vi_run_data *d, double t_start, double rtol, char *msg, size_t n)
{
    if (d->inputs_changed != 0 && d->inputs_changed != 1)
        VI_FAIL(msg, n, "inputs_changed = %d is not 0 or 1", d->inputs_changed);
    if (!isfinite(d->t) || d->t < t_start)
        VI_FAIL(msg, n, "t = %g is not finite or before t_start = %g", d->t, t_start);
    for (int i = 0; i < 2; i++)
        if (!isfinite(d->x[i])) VI_FAIL(msg, n, "x[%d] = %g is not finite", i, d->x[i]);
    if (d->initialized != 0 && d->initialized != 1) VI_FAIL(msg, n, "initialized = %d is not 0 or 1", d->initialized);
    if (!isfinite(d->step_t0) || d->step_t0 > d->t || !isfinite(d->step_v0))
        VI_FAIL(msg, n, "step_t0 = %g, step_v0 = %g: not finite or after t", d->step_t0, d->step_v0);
    if (!isfinite(d->W_damping) || !(d->F_peak >= 0.0 && isfinite(d->F_peak)))
        VI_FAIL(msg, n, "W_damping = %g, F_peak = %g: not finite, or F_peak < 0", d->W_damping, d->F_peak);
    if (vi_hybrid_check(&d->events, d->t, msg, n) < 0) return -1;
    if (d->initialized && d->events.rtol != rtol)
        VI_FAIL(msg, n, "rtol = %g is not the one of the settings, %g", d->events.rtol, rtol);
    return 0;
}

int vi_run_data_check_model(const vi_run_data *d, int surfaces, char *msg, size_t n)
{
    return surfaces ? vi_model_check(&d->model, d->x, msg, n) : vi_model_check_between_events(&d->model, d->x, msg, n);
}
