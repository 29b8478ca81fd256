/* vi_run.c - one run of the contact model, shared by both drivers: set-up from the parameters, the
 * initial state, the outputs, the validity warnings and the checks of a saved run; see vi_run.h. */
#include "vi_run.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vi_check.h"
#include "vi_format.h"


_Static_assert((int)VI_Solver_bdf == (int)VI_METHOD_BDF && (int)VI_Solver_adams == (int)VI_METHOD_ADAMS &&
                   (int)VI_Solver_dop853 == (int)VI_METHOD_DOP853 && (int)VI_Solver_auto == (int)VI_METHOD_AUTO,
               "the solver enumeration is the solver layer's method number");
_Static_assert((int)VI_ContactModel_hertz == (int)VI_LAW_HERTZ && (int)VI_ContactModel_johnson == (int)VI_LAW_JOHNSON &&
                   (int)VI_ContactModel_lepp == (int)VI_LAW_LEPP &&
                   (int)VI_ContactModel_hertz_damped == (int)VI_LAW_HERTZ_DAMPED &&
                   (int)VI_ContactModel_linear == (int)VI_LAW_LINEAR && (int)VI_ContactModel_thornton == (int)VI_LAW_THORNTON &&
                   (int)VI_DampingFormula_exact == (int)VI_DAMP_EXACT &&
                   (int)VI_DampingFormula_hunt_crossley == (int)VI_DAMP_HUNT_CROSSLEY &&
                   (int)VI_DampingFormula_lankarani_nikravesh == (int)VI_DAMP_LANKARANI_NIKRAVESH &&
                   (int)VI_DampingFormula_flores == (int)VI_DAMP_FLORES && (int)VI_Init_static == (int)VI_INIT_STATIC &&
                   (int)VI_Init_touching == (int)VI_INIT_TOUCHING && (int)VI_Unloading_paper == (int)VI_UNLOAD_PAPER &&
                   (int)VI_Unloading_continuous == (int)VI_UNLOAD_CONTINUOUS &&
                   (int)VI_YieldFormula_textbook == (int)VI_YIELD_TEXTBOOK &&
                   (int)VI_YieldFormula_printed == (int)VI_YIELD_PRINTED,
               "the enumerations of the variable table are the model's numbers");
_Static_assert((int)VI_Mode_free == (int)VI_MODE_FREE && (int)VI_Mode_elastic == (int)VI_MODE_ELASTIC &&
                   (int)VI_Mode_plastic == (int)VI_MODE_PLASTIC && (int)VI_Mode_unload == (int)VI_MODE_UNLOAD &&
                   (int)VI_Mode_stick == (int)VI_MODE_STICK,
               "the Mode enumeration is the model's mode");

vi_model_params vi_run_model_params(const vi_parameters *p)
{
    return (vi_model_params){
        .m = p->m, .P = p->P, .g = p->g, .R1 = p->R1, .R2 = p->R2, .E1 = p->E1, .E2 = p->E2, .nu1 = p->nu1,
        .nu2 = p->nu2, .Y = p->Y, .theta_Y = p->theta_Y, .law = p->contact_model, .moving_contact = p->moving_contact,
        .unloading = p->unloading, .yield_formula = p->yield_formula, .init = p->init, .v0 = p->v0, .a = p->a,
        .f = p->f, .has_profile = p->profile_file[0] != '\0', .V = p->V, .x0 = p->x0,
        .profile_periodic = p->profile_periodic, .e_restitution = p->e_restitution,
        .damping_formula = p->damping_formula, .k_spring = p->k_spring};
}

void vi_run_init(vi_run *r, vi_run_data *d, vi_log_fn log, void *log_env)
{
    memset(r, 0, sizeof *r);
    memset(d, 0, sizeof *d);
    r->d = d;
    r->log = log;
    r->log_env = log_env;
    vi_parameters_default(&d->par);
    vi_inputs_default(&d->in);
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
    vi_run_init(r, r->d, r->log, r->log_env);
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

/* Load (or keep, when file, R1 and periodicity are those it was built for) the profile of the
 * parameters and hand it to the model with V and x0. Called after vi_model_setup and after a
 * restore: the profile pointer read from a saved state is never used. 0, or -1 (r->msg). */
static int attach_profile(vi_run *r)
{
    const vi_parameters *p = &r->d->par;
    vi_model *model = &r->d->model;
    if (!p->profile_file[0]) {
        vi_profile_free(r->profile);
        r->profile = NULL;
        r->profile_key[0] = '\0';
        return vi_model_set_rolling(model, NULL, p->V, p->x0, r->msg, sizeof r->msg);
    }
    char path[VI_PATH_MAX], key[sizeof r->profile_key];
    if (profile_path(r, p->profile_file, path, sizeof path) < 0)
        VI_FAIL(r->msg, sizeof r->msg, "profile_file '%.200s...': the path is too long", p->profile_file);
    if (!(p->R1 > 0.0))
        VI_FAIL(r->msg, sizeof r->msg, "profile_file: rolling needs a body radius R1 > 0 (R1 = %g m)", p->R1);
    vi_snprintf(key, sizeof key, "%s|%.17g|%d", path, p->R1, p->profile_periodic != 0);
    if (!r->profile || strcmp(key, r->profile_key) != 0) {
        vi_profile_free(r->profile);
        r->profile_key[0] = '\0';
        r->profile = vi_profile_load(path, p->R1, p->profile_periodic, r->msg, sizeof r->msg);
        if (!r->profile) return -1;
        memcpy(r->profile_key, key, sizeof key);
    }
    return vi_model_set_rolling(model, r->profile, p->V, p->x0, r->msg, sizeof r->msg);
}

/* Warn once per instance and cause when the simulation leaves the model's range of validity
 * (vi_model_validity). */
void vi_run_check_validity(vi_run *r)
{
    char text[400];
    r->validity_unchecked = 0;
    for (int cause; (cause = vi_model_validity(&r->d->model, r->d->par.R1, r->d->t, r->d->x, r->warned_validity, text,
                                               sizeof text)) != 0;) { /* bounded: one more bit each time */
        r->warned_validity |= cause;
        r->log(r->log_env, VI_LOG_WARNING, "%s", text);
    }
    if (r->warned_validity & VI_INVALID_FORCE) return; /* warned once: the force need not be evaluated again */
    double F_max = fmax(r->d->F_peak, vi_model_force(&r->d->model, r->d->t, r->d->x)); /* the step's so far, and now */
    if (vi_model_force_validity(&r->d->model, F_max, r->d->t, text, sizeof text)) {
        r->warned_validity |= VI_INVALID_FORCE;
        r->log(r->log_env, VI_LOG_WARNING, "%s", text);
    }
}

void vi_run_input_ramps(const vi_run_data *d, double t, vi_ramp *yC_in, vi_ramp *F_ext)
{
    *yC_in = (vi_ramp){d->in.yC_in, d->par.velocity_input ? d->in.vC_in : d->din.yC_in, t};
    *F_ext = (vi_ramp){d->in.F_ext, d->din.F_ext, t};
}

static void set_input_ramps(vi_model *model, const vi_run_data *d, double t)
{
    vi_run_input_ramps(d, t, &model->yC_in, &model->F_ext);
}

double vi_run_rtol(const vi_run_data *d)
{
    if (d->par.rtol > 0.0) return d->par.rtol;
    return d->tolerance > 0.0 ? d->tolerance : VI_RTOL_DEFAULT;
}

/* Are the outputs and calculated parameters at the current state finite? -1 (r->msg, naming the
 * first that is not) when the parameters and inputs lead to values beyond the range of double (a
 * Johnson load of 1e300 N: the plastic work is inf - inf), which are refused rather than reported. */
static int outputs_finite(vi_run *r)
{
    r->out_valid = 0;
    vi_outputs out = *vi_run_outputs_of(r, VI_OUT_ALL);
    for (int vr = 0; vr < VI_NVARS; vr++) {
        const vi_variable *v = &vi_variable_table[vr];
        double x;
        if (v->group != VI_GROUP_OUTPUTS || v->type != VI_Real) continue;
        memcpy(&x, (const char *)&out + v->offset, sizeof x);
        if (!isfinite(x)) {
            vi_snprintf(r->msg, sizeof r->msg, "%s = %g at t = %.17g s: the parameters and inputs lead to values beyond the "
                        "range of double", v->name, x, r->d->t);
            return -1;
        }
    }
    return 0;
}

static int time_scale_check(vi_run *r);

int vi_run_prepare(vi_run *r)
{
    vi_run_data *d = r->d;
    const vi_parameters *p = &d->par;
    r->out_valid = 0;
    /* The parameters lie in the ranges of the variable table (rtol among them); left to check: the
     * experiment's tolerance, and max_step between 0 and VI_MAX_STEP_MIN. */
    if (d->tolerance > 0.0 && !(d->tolerance >= VI_RTOL_MIN && d->tolerance <= VI_RTOL_MAX))
        VI_FAIL(r->msg, sizeof r->msg, "relative tolerance (the importer's: fmi2SetupExperiment, fmi3EnterInitializationMode) = %g: "
                "use a value in [%g, %g]",
                d->tolerance, VI_RTOL_MIN, VI_RTOL_MAX);
    if (!(p->rtol == 0.0 || p->rtol >= VI_RTOL_MIN))
        VI_FAIL(r->msg, sizeof r->msg, "rtol = %g: use 0 (the experiment's tolerance) or a value in [%g, %g]", p->rtol,
                VI_RTOL_MIN, VI_RTOL_MAX);
    if (!(p->max_step == 0.0 || p->max_step >= VI_MAX_STEP_MIN))
        VI_FAIL(r->msg, sizeof r->msg, "max_step = %g s: use 0 (no limit) or a step >= %g s", p->max_step,
                VI_MAX_STEP_MIN);
    vi_model_params model_params = vi_run_model_params(p);
    if (vi_model_setup(&d->model, &model_params, d->t_start, r->msg, sizeof r->msg) < 0) return -1;
    if (attach_profile(r) < 0) return -1;
    d->t = d->t_start;
    set_input_ramps(&d->model, d, d->t);
    d->inputs_changed = 0;
    vi_model_initial_state(&d->model, p->init, p->v0, d->t, d->x);
    d->step_t0 = d->t;
    d->step_v0 = d->x[1];
    d->W_damping = 0.0;
    d->F_peak = vi_model_force(&d->model, d->t, d->x);
    memset(&d->events, 0, sizeof d->events);
    d->events.t_count = d->t;
    if (time_scale_check(r) < 0) return -1;
    return outputs_finite(r);
}

void vi_run_tolerances(const vi_run *r, double *rtol, double atol[2])
{
    double L, V;
    *rtol = vi_run_rtol(r->d);
    vi_model_scales(&r->d->model, r->d->x, &L, &V);
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
    const vi_run_data *d = r->d;
    char text[400];
    vi_model_params model_params = vi_run_model_params(&d->par);
    if (vi_model_option_warnings(&model_params, text, sizeof text) > 0) r->log(r->log_env, VI_LOG_WARNING, "%s", text);
    /* an importer that passes the declared default experiment's tolerance most likely passes a default */
    if (d->par.rtol > 0.0 && d->tolerance > 0.0 && d->tolerance != VI_RTOL_DEFAULT && d->par.rtol != d->tolerance)
        r->log(r->log_env, VI_LOG_WARNING, "rtol = %g is used, not the experiment's tolerance %g (set rtol = 0 to use the "
               "experiment's)", d->par.rtol, d->tolerance);
    vi_run_check_validity(r);
}

int vi_run_restore(vi_run *r)
{
    r->out_valid = 0;
    r->validity_unchecked = 1;
    if (!r->d->initialized) return 0; /* before initialization: no model set up yet */
    return attach_profile(r); /* the restored model's profile pointer is replaced by ours */
}

/* ---- the contact's time scale ----------------------------------------------------------------- */

double vi_run_time_scale(const vi_run *r, double *k_out, char *note, size_t n)
{
    const vi_model *model = &r->d->model;
    double k = model->mode == VI_MODE_FREE ? 0.0 : vi_run_contact_stiffness(model, r->d->t, r->d->x), at = r->d->x[0], T;
    const char *where = "at the indentation";
    if (k > 0.0 && isfinite(k)) {
        T = sqrt(model->m) / sqrt(k);
    } else {
        double L, V;
        vi_model_scales(model, r->d->x, &L, &V);
        T = L / V, at = L, where = "at the indentation scale";
        k = sqrt(model->m) * (V / L), k *= k; /* m (V/L)^2 without overflow for a tiny m */
    }
    const vi_johnson *J = &model->johnson;
    if (model->law == VI_LAW_LINEAR)
        vi_snprintf(note, n, "sqrt(m/k) = %.3g s (m = %g kg, k = k_spring = %g N/m)", T, model->m, k);
    else
        vi_snprintf(note, n, "sqrt(m/k) = %.3g s (m = %g kg, k = %.3g N/m, the law's stiffness %s %.3g m, from E* = %g Pa "
                    "and R* = %g m)", T, model->m, k, where, at, J->E_star, J->R_star);
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
            "smaller mass cannot be integrated in double precision", r->d->model.m, note, k / DBL_MAX * 2.0);
}


/* ---- outputs -------------------------------------------------------------------------------- */

/* Tangent contact stiffness: a sticking mass is held at delta_c between the two branches; small
 * unloading would follow the unloading curve, so its stiffness. */
double vi_run_contact_stiffness(const vi_model *model, double t, const double x[2])
{
    if (model->mode == VI_Mode_stick) return vi_unload_stiffness(&model->unload, model->unload.delta_c);
    return model->m * vi_model_stiffness_over_mass(model, t, x);
}

/* The contact force averaged over the last step [t0, t]: the impulse over the step divided by it,
 * from the momentum balance m v' = F - W(t), W = P + m g - F_ext(t) (F_ext linear over the step, so
 * its mean is its midpoint value). Before any step: the force itself. */
static double mean_force(const vi_run_data *d)
{
    const vi_model *model = &d->model;
    double h = d->t - d->step_t0;
    if (!(h > 0.0)) return vi_model_force(model, d->t, d->x);
    double W_mean = model->W0 - vi_ramp_at(&model->F_ext, d->step_t0 + 0.5 * h);
    return model->m * (d->x[1] - d->step_v0) / h + W_mean;
}

/* The model's values of the groups VI_OUT_STATE ... VI_OUT_CALCULATED into the FMU's outputs. */
static void take_values(const vi_model_values *v, unsigned groups, vi_outputs *out)
{
    if (groups & VI_OUT_STATE) {
        out->delta = v->delta, out->v = v->v, out->contact = v->contact, out->mode = v->mode;
        out->n_impacts = v->n_impacts;
    }
    if (groups & VI_OUT_PLATFORM) out->yC = v->yC, out->y = v->y;
    if (groups & VI_OUT_FORCE) out->F = v->F;
    if (groups & VI_OUT_MEMORY) {
        out->delta_c = v->delta_c, out->delta_f = v->delta_f, out->delta_p = v->delta_p, out->Rbar = v->Rbar;
        out->W_plastic = v->W_plastic, out->E_contact = v->E_contact;
    }
    if (groups & VI_OUT_CALCULATED) {
        out->E_star = v->E_star, out->R_star = v->R_star, out->F_Y = v->F_Y, out->delta_Y = v->delta_Y;
        out->k_lin = v->k_lin, out->f_contact = v->f_contact;
    }
}

const vi_outputs *vi_run_outputs_of(vi_run *r, unsigned groups)
{
    unsigned need = groups & (VI_OUT_ALL & ~VI_OUT_DERIVATIVES) & ~r->out_valid;
    if (need) {
        const vi_run_data *d = r->d;
        vi_model_values values;
        vi_model_outputs(&d->model, d->t, d->x, need, &values);
        take_values(&values, need, &r->out);
        if (need & VI_OUT_MEMORY) r->out.W_damping = d->W_damping, r->out.W_dissipated = r->out.W_plastic + d->W_damping;
        if (need & VI_OUT_FORCE) r->out.F_peak = fmax(d->F_peak, r->out.F);
        if (need & VI_OUT_MEAN) r->out.F_mean = mean_force(d);
        if (need & VI_OUT_STIFFNESS) r->out.k_contact = vi_run_contact_stiffness(&d->model, d->t, d->x);
        r->out_valid |= need;
    }
    return &r->out;
}

/* ---- validity of a state payload (doc/model.md section 7.6) --------------------------------- */

int vi_run_data_check(const vi_run_data *d, char *msg, size_t n)
{
    if (d->inputs_changed != 0 && d->inputs_changed != 1)
        VI_FAIL(msg, n, "inputs_changed = %d is not 0 or 1", d->inputs_changed);
    if (!isfinite(d->t_start)) VI_FAIL(msg, n, "t_start = %g is not finite", d->t_start);
    if (d->tolerance != 0.0 && !(d->tolerance >= VI_RTOL_MIN && d->tolerance <= VI_RTOL_MAX))
        VI_FAIL(msg, n, "tolerance = %g is neither 0 nor in [%g, %g]", d->tolerance, VI_RTOL_MIN, VI_RTOL_MAX);
    if (!isfinite(d->t) || d->t < d->t_start)
        VI_FAIL(msg, n, "t = %g is not finite or before t_start = %g", d->t, d->t_start);
    for (int i = 0; i < 2; i++)
        if (!isfinite(d->x[i])) VI_FAIL(msg, n, "x[%d] = %g is not finite", i, d->x[i]);
    if (d->initialized != 0 && d->initialized != 1) VI_FAIL(msg, n, "initialized = %d is not 0 or 1", d->initialized);
    if (!isfinite(d->step_t0) || d->step_t0 > d->t || !isfinite(d->step_v0))
        VI_FAIL(msg, n, "step_t0 = %g, step_v0 = %g: not finite or after t", d->step_t0, d->step_v0);
    if (!isfinite(d->W_damping) || !(d->F_peak >= 0.0 && isfinite(d->F_peak)))
        VI_FAIL(msg, n, "W_damping = %g, F_peak = %g: not finite, or F_peak < 0", d->W_damping, d->F_peak);
    if (vi_hybrid_check(&d->events, d->t, msg, n) < 0) return -1;
    if (d->initialized && d->events.rtol != vi_run_rtol(d))
        VI_FAIL(msg, n, "rtol = %g is not the one of the settings, %g", d->events.rtol, vi_run_rtol(d));
    return 0;
}

int vi_run_data_check_model(const vi_run_data *d, int surfaces, char *msg, size_t n)
{
    return surfaces ? vi_model_check(&d->model, d->x, msg, n) : vi_model_check_between_events(&d->model, d->x, msg, n);
}
