/* vi_contact_instance.c - one instance of the contact FMU: its FMI storage mapped onto the run and the
 * drivers; see vi_contact_instance.h. */
#include "vi_contact_instance.h"

#include <math.h>
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

vi_model_params vi_contact_model_params(const vi_parameters *p)
{
    return (vi_model_params){
        .m = p->m, .P = p->P, .g = p->g, .R1 = p->R1, .R2 = p->R2, .E1 = p->E1, .E2 = p->E2, .nu1 = p->nu1,
        .nu2 = p->nu2, .Y = p->Y, .theta_Y = p->theta_Y, .law = p->contact_model, .moving_contact = p->moving_contact,
        .unloading = p->unloading, .yield_formula = p->yield_formula, .init = p->init, .v0 = p->v0, .a = p->a,
        .f = p->f, .has_profile = p->profile_file[0] != '\0', .V = p->V, .x0 = p->x0,
        .profile_periodic = p->profile_periodic,
        .profile_interpolation = p->profile_interpolation == VI_ProfileInterpolation_cubic ? VI_PROFILE_CUBIC
                                                                                          : VI_PROFILE_LINEAR,
        .e_restitution = p->e_restitution, .damping_formula = p->damping_formula, .k_spring = p->k_spring,
        .upper_stop = p->upper_stop, .gap = p->gap};
}

double vi_contact_rtol(const vi_parameters *p, double tolerance)
{
    if (p->rtol > 0.0) return p->rtol;
    return tolerance > 0.0 ? tolerance : VI_RTOL_DEFAULT;
}

/* ---- the run's source: settings, the outputs' check (the inputs are read where they are stored) ---- */

/* The run's settings from the parameters and the experiment. The parameters lie in the ranges of the
 * variable table (rtol among them); left to check: the experiment's tolerance, rtol 0 or at least
 * VI_RTOL_MIN, and max_step 0 or at least VI_MAX_STEP_MIN. 0, or -1 (msg). */
static int settings(void *env, vi_run_settings *s, char *msg, size_t n)
{
    const vi_contact_data *d = &((const vi_contact *)env)->d;
    const vi_parameters *p = &d->par;
    if (d->tolerance > 0.0 && !(d->tolerance >= VI_RTOL_MIN && d->tolerance <= VI_RTOL_MAX))
        VI_FAIL(msg, n, "relative tolerance (the importer's: fmi2SetupExperiment, fmi3EnterInitializationMode) = %g: "
                "use a value in [%g, %g]",
                d->tolerance, VI_RTOL_MIN, VI_RTOL_MAX);
    if (!(p->rtol == 0.0 || p->rtol >= VI_RTOL_MIN))
        VI_FAIL(msg, n, "rtol = %g: use 0 (the experiment's tolerance) or a value in [%g, %g]", p->rtol,
                VI_RTOL_MIN, VI_RTOL_MAX);
    if (!(p->max_step == 0.0 || p->max_step >= VI_MAX_STEP_MIN))
        VI_FAIL(msg, n, "max_step = %g s: use 0 (no limit) or a step >= %g s", p->max_step,
                VI_MAX_STEP_MIN);
    *s = (vi_run_settings){.model = vi_contact_model_params(p), .t_start = d->t_start,
                           .rtol = vi_contact_rtol(p, d->tolerance), .rtol_given = p->rtol, .tolerance = d->tolerance,
                           .max_step = p->max_step, .method = p->solver, .velocity_input = p->velocity_input,
                           .profile_file = p->profile_file};
    return 0;
}


/* The run's values of `groups` into the table's outputs: group by group, only those asked for (a get
 * call asks for one or two). Returns out. */
static const vi_outputs *take_values(const vi_run_values *r, unsigned groups, vi_outputs *out)
{
    const vi_model_values *v = &r->model;
    for (unsigned left = groups & VI_OUT_ALL; left; left &= left - 1u) { /* bounded: one bit fewer each time */
        switch (left & (~left + 1u)) {
        case VI_OUT_STATE:
            out->delta = v->delta, out->v = v->v, out->contact = v->contact, out->mode = v->mode;
            out->n_impacts = v->n_impacts;
            out->delta_upper = v->delta_upper, out->mode_upper = v->mode_upper, out->n_impacts_upper = v->n_impacts_upper;
            break;
        case VI_OUT_PLATFORM: out->yC = v->yC, out->y = v->y; break;
        case VI_OUT_FORCE: out->F = v->F, out->F_peak = r->F_peak, out->F_upper = v->F_upper; break;
        case VI_OUT_MEMORY:
            out->delta_c = v->delta_c, out->delta_f = v->delta_f, out->delta_p = v->delta_p, out->Rbar = v->Rbar;
            out->W_plastic = v->W_plastic, out->E_contact = v->E_contact;
            out->W_damping = r->W_damping, out->W_dissipated = r->W_dissipated;
            break;
        case VI_OUT_CALCULATED:
            out->E_star = v->E_star, out->R_star = v->R_star, out->F_Y = v->F_Y, out->delta_Y = v->delta_Y;
            out->k_lin = v->k_lin, out->f_contact = v->f_contact;
            break;
        case VI_OUT_MEAN: out->F_mean = r->F_mean; break;
        case VI_OUT_STIFFNESS: out->k_contact = r->k_contact; break;
        default: out->der_y = r->der_y, out->der_v = r->der_v, out->der_W_damping = r->der_W_damping; /* DERIVATIVES */
        }
    }
    return out;
}

/* Are the outputs and calculated parameters at the prepared state finite? -1 (msg, naming the first
 * that is not) when the parameters and inputs lead to values beyond the range of double (a Johnson
 * load of 1e300 N: the plastic work is inf - inf), which are refused rather than reported. */
static int outputs_check(void *env, char *msg, size_t n)
{
    vi_contact *c = env;
    take_values(vi_run_outputs_of(&c->r, VI_OUT_ALL), VI_OUT_ALL & ~VI_OUT_DERIVATIVES, &c->out);
    for (int vr = 0; vr < VI_NVARS; vr++) {
        const vi_variable *v = &vi_variable_table[vr];
        double x;
        if (v->group != VI_GROUP_OUTPUTS || v->type != VI_Real) continue;
        memcpy(&x, (const char *)&c->out + v->offset, sizeof x);
        if (!isfinite(x)) {
            vi_snprintf(msg, n, "%s = %g at t = %.17g s: the parameters and inputs lead to values beyond the "
                        "range of double", v->name, x, c->d.run.t);
            return -1;
        }
    }
    return 0;
}

/* ---- life cycle, outputs, checks ------------------------------------------------------------------ */

void vi_contact_init(vi_contact *c, vi_log_fn log, void *log_env)
{
    memset(c, 0, sizeof *c);
    vi_parameters_default(&c->d.par);
    vi_inputs_default(&c->d.in);
    const vi_contact_data *d = &c->d;
    vi_run_inputs in = {.yC_in = &d->in.yC_in, .yC_in_rate = &d->din.yC_in, .F_ext = &d->in.F_ext,
                        .F_ext_rate = &d->din.F_ext, .vC_in = &d->in.vC_in, .a = &d->par.a, .f = &d->par.f};
    vi_run_source src = {.settings = settings, .inputs = in, .outputs_check = outputs_check, .env = c};
    vi_run_init(&c->r, &c->d.run, src, log, log_env);
    vi_sim_init(&c->s, &c->r, &c->d.cs);
    vi_me_init(&c->e, &c->r, &c->d.me);
}

void vi_contact_reset(vi_contact *c)
{
    vi_sim_free(&c->s);
    vi_run_reset(&c->r);
    memset(&c->d, 0, sizeof c->d);
    memset(&c->out, 0, sizeof c->out);
    vi_parameters_default(&c->d.par);
    vi_inputs_default(&c->d.in);
    vi_sim_init(&c->s, &c->r, &c->d.cs);
    vi_me_init(&c->e, &c->r, &c->d.me);
}

void vi_contact_free(vi_contact *c)
{
    vi_sim_free(&c->s);
    vi_run_free(&c->r);
}

const vi_outputs *vi_contact_outputs_of(vi_contact *c, unsigned groups)
{
    const vi_run_values *v = !c->e.active && !(groups & VI_OUT_DERIVATIVES) ? vi_run_outputs_of(&c->r, groups)
                                                                            : vi_me_outputs_of(&c->e, groups);
    return take_values(v, groups, &c->out);
}

int vi_contact_state_check(const vi_contact_data *d, int running, int model_exchange, char *msg, size_t n)
{
    if (!running) return 0;
    if (!isfinite(d->t_start)) VI_FAIL(msg, n, "t_start = %g is not finite", d->t_start);
    if (d->tolerance != 0.0 && !(d->tolerance >= VI_RTOL_MIN && d->tolerance <= VI_RTOL_MAX))
        VI_FAIL(msg, n, "tolerance = %g is neither 0 nor in [%g, %g]", d->tolerance, VI_RTOL_MIN, VI_RTOL_MAX);
    vi_run_settings set = {.t_start = d->t_start, .rtol = vi_contact_rtol(&d->par, d->tolerance), .method = d->par.solver};
    if (model_exchange) return vi_me_data_check(&d->run, &d->me, set.t_start, set.rtol, msg, n);
    return vi_sim_data_check(&d->run, &d->cs, &set, msg, n) < 0 ? -1 : vi_me_data_finite(&d->me, msg, n);
}
