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

vi_model_params vi_sim_model_params(const vi_parameters *p)
{
    return (vi_model_params){
        .m = p->m, .P = p->P, .g = p->g, .R1 = p->R1, .R2 = p->R2, .E1 = p->E1, .E2 = p->E2, .nu1 = p->nu1,
        .nu2 = p->nu2, .Y = p->Y, .theta_Y = p->theta_Y, .law = p->contact_model, .moving_contact = p->moving_contact,
        .unloading = p->unloading, .yield_formula = p->yield_formula, .init = p->init, .v0 = p->v0, .a = p->a,
        .f = p->f, .has_profile = p->profile_file[0] != '\0', .V = p->V, .x0 = p->x0,
        .profile_periodic = p->profile_periodic,
        .profile_interpolation = p->profile_interpolation == VI_ProfileInterpolation_cubic ? VI_PROFILE_CUBIC
                                                                                          : VI_PROFILE_LINEAR,
        .e_restitution = p->e_restitution,
        .damping_formula = p->damping_formula, .k_spring = p->k_spring};
}

static void sim_rhs(double t, const double *x, double *dx, void *user)
{
    const vi_sim *s = user;
    vi_model_rhs(&s->d.model, t, x, dx);
}

static void sim_guards(double t, const double *x, double *g, void *user)
{
    const vi_sim *s = user;
    vi_hybrid_guards(&s->engine, t, x, g);
}

static void sim_jac(double t, const double *x, double *j, void *user)
{
    const vi_sim *s = user;
    vi_model_jacobian(&s->d.model, t, x, j);
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
    vi_sim_data *d = &s->d;
    const vi_model *model = &d->model;
    double h = p->tb - p->ta, sum = 0.0, x[2];
    int onset = p->xa[0] == 0.0 && vi_model_damping_root_at_onset(model);
    for (int i = 0; i < VI_GAUSS_NODES && model->mode != VI_MODE_FREE; i++) {
        double u = gauss_t[i], u3 = u * u * u, t = p->ta + h * (onset ? u3 * u : u);
        if (vi_solver_piece_at(p, t, x, NULL) < 0) return -1;
        sum += gauss_w[i] * (onset ? 4.0 * u3 : 1.0) * vi_model_contact_power(model, t, x);
    }
    double spring = vi_model_contact_energy(model, p->xb, NULL) - vi_model_contact_energy(model, p->xa, NULL);
    d->W_damping += h * sum - spring;
    return 0;
}

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
    const vi_model *model = &s->d.model;
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
    e->t = t, e->x[0] = x[0], e->x[1] = x[1], e->mode = s->d.model.mode, e->valid = 1;
    e->g = vi_model_force_rate(&s->d.model, t, x, dx, &e->F);
}

/* Is the end point the point (t, x) in the current mode? */
static int at_peak_end(const vi_sim *s, double t, const double x[2])
{
    const vi_peak_point *e = &s->peak_end;
    return e->valid && e->t == t && e->x[0] == x[0] && e->x[1] == x[1] && e->mode == s->d.model.mode;
}

/* The largest force over a piece: at its ends, and inside where its rate changes sign from + to - (one
 * extremum per internal step: the solver's steps resolve the motion). The start is the end of the piece
 * before unless the model changed in between (an event, an input, a restart: peak_restart). */
static int piece_peak(vi_sim *s, const vi_solver_piece *p)
{
    vi_sim_data *d = &s->d;
    vi_peak_point *e = &s->peak_end;
    if (d->model.mode == VI_MODE_FREE) return 0; /* F = 0 */
    if (!at_peak_end(s, p->ta, p->xa)) peak_point(s, p->ta, p->xa, NULL);
    double Fa = e->F, ga = e->g;
    peak_point(s, p->tb, p->xb, p->dxb);
    double F_max = fmax(Fa, e->F);
    if (ga > 0.0 && e->g < 0.0 && peak_inside(s, p, Fa, ga, e->F, e->g, &F_max) < 0) return -1;
    d->F_peak = fmax(d->F_peak, F_max);
    return 0;
}

/* The model changed at the current point (an event, an input, a kink; changed: a restored state, a step's
 * start after inputs were set): its force raises F_peak, and the next piece starts from it. */
static void peak_restart(vi_sim *s, int changed)
{
    if (changed || !at_peak_end(s, s->d.t, s->d.x)) peak_point(s, s->d.t, s->d.x, NULL);
    s->d.F_peak = fmax(s->d.F_peak, s->peak_end.F);
}

/* A piece of the solution the solver passed (vi_solver.h, PIECES). */
static int sim_piece(const vi_solver_piece *p, void *user)
{
    vi_sim *s = user;
    if (vi_model_damps(&s->d.model) && piece_damping(s, p) < 0) return -1;
    return piece_peak(s, p);
}

void vi_sim_init(vi_sim *s, vi_log_fn log, void *log_env)
{
    memset(s, 0, sizeof *s);
    s->log = log;
    s->log_env = log_env;
    vi_hybrid_bind(&s->engine, &s->d.model, &s->d.events, 0, log, log_env);
    vi_parameters_default(&s->d.par);
    vi_inputs_default(&s->d.in);
}

void vi_sim_set_resources(vi_sim *s, const char *dir)
{
    vi_snprintf(s->resources, sizeof s->resources, "%s", dir ? dir : "");
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
        k = vi_snprintf(path, n, "%s/%s", s->resources, file);
        FILE *f = k > 0 && (size_t)k < n ? vi_profile_fopen(path) : NULL;
        if (f) {
            fclose(f);
            return 0;
        }
    }
    k = vi_snprintf(path, n, "%s", file);
    return k > 0 && (size_t)k < n ? 0 : -1;
}

/* Load (or keep, when file, R1, periodicity and interpolation are those it was built for) the profile of the
 * parameters and hand it to the model with V and x0. Called after vi_model_setup and after a
 * restore: the profile pointer read from a saved state is never used. 0, or -1 (s->msg). */
static int attach_profile(vi_sim *s)
{
    const vi_parameters *p = &s->d.par;
    vi_model *model = &s->d.model;
    if (!p->profile_file[0]) {
        vi_profile_free(s->profile);
        s->profile = NULL;
        s->profile_key[0] = '\0';
        return vi_model_set_rolling(model, NULL, p->V, p->x0, s->msg, sizeof s->msg);
    }
    char path[VI_PATH_MAX], key[sizeof s->profile_key];
    if (profile_path(s, p->profile_file, path, sizeof path) < 0)
        VI_FAIL(s->msg, sizeof s->msg, "profile_file '%.200s...': the path is too long", p->profile_file);
    if (!(p->R1 > 0.0))
        VI_FAIL(s->msg, sizeof s->msg, "profile_file: rolling needs a body radius R1 > 0 (R1 = %g m)", p->R1);
    int interpolation = vi_sim_model_params(p).profile_interpolation;
    vi_snprintf(key, sizeof key, "%s|%.17g|%d|%d", path, p->R1, p->profile_periodic != 0, interpolation);
    if (!s->profile || strcmp(key, s->profile_key) != 0) {
        vi_profile_free(s->profile);
        s->profile_key[0] = '\0';
        s->profile = vi_profile_load_as(path, p->R1, p->profile_periodic, interpolation, s->msg, sizeof s->msg);
        if (!s->profile) return -1;
        memcpy(s->profile_key, key, sizeof key);
    }
    return vi_model_set_rolling(model, s->profile, p->V, p->x0, s->msg, sizeof s->msg);
}

/* Warn once per instance and cause when the simulation leaves the model's range of validity
 * (vi_model_validity). */
void vi_sim_check_validity(vi_sim *s)
{
    char text[400];
    s->validity_unchecked = 0;
    for (int cause; (cause = vi_model_validity(&s->d.model, s->d.par.R1, s->d.t, s->d.x, s->warned_validity, text,
                                               sizeof text)) != 0;) { /* bounded: one more bit each time */
        s->warned_validity |= cause;
        s->log(s->log_env, VI_LOG_WARNING, "%s", text);
    }
    if (s->warned_validity & VI_INVALID_FORCE) return; /* warned once: the force need not be evaluated again */
    double F_max = fmax(s->d.F_peak, vi_model_force(&s->d.model, s->d.t, s->d.x)); /* the step's so far, and now */
    if (vi_model_force_validity(&s->d.model, F_max, s->d.t, text, sizeof text)) {
        s->warned_validity |= VI_INVALID_FORCE;
        s->log(s->log_env, VI_LOG_WARNING, "%s", text);
    }
}

void vi_sim_input_ramps(const vi_sim_data *d, double t, vi_ramp *yC_in, vi_ramp *F_ext)
{
    *yC_in = (vi_ramp){d->in.yC_in, d->par.velocity_input ? d->in.vC_in : d->din.yC_in, t};
    *F_ext = (vi_ramp){d->in.F_ext, d->din.F_ext, t};
}

static void set_input_ramps(vi_model *model, const vi_sim_data *d, double t)
{
    vi_sim_input_ramps(d, t, &model->yC_in, &model->F_ext);
}

double vi_sim_rtol(const vi_sim_data *d)
{
    if (d->par.rtol > 0.0) return d->par.rtol;
    return d->tolerance > 0.0 ? d->tolerance : VI_RTOL_DEFAULT;
}

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
            vi_snprintf(s->msg, sizeof s->msg, "%s = %g at t = %.17g s: the parameters and inputs lead to values beyond the "
                        "range of double", v->name, x, s->d.t);
            return -1;
        }
    }
    return 0;
}

static int time_scale_check(vi_sim *s);
static void append_cause(vi_sim *s, double h_comm);

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
    if (!(p->rtol == 0.0 || p->rtol >= VI_RTOL_MIN))
        VI_FAIL(s->msg, sizeof s->msg, "rtol = %g: use 0 (the experiment's tolerance) or a value in [%g, %g]", p->rtol,
                VI_RTOL_MIN, VI_RTOL_MAX);
    if (!(p->max_step == 0.0 || p->max_step >= VI_MAX_STEP_MIN))
        VI_FAIL(s->msg, sizeof s->msg, "max_step = %g s: use 0 (no limit) or a step >= %g s", p->max_step,
                VI_MAX_STEP_MIN);
    vi_model_params model_params = vi_sim_model_params(p);
    if (vi_model_setup(&d->model, &model_params, d->t_start, s->msg, sizeof s->msg) < 0) return -1;
    if (attach_profile(s) < 0) return -1;
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
    if (time_scale_check(s) < 0) return -1;
    return outputs_finite(s);
}

/* (Re)create the solver with the tolerances stored in s->d: starting at the current state, or
 * (resume) continuing the continuation in s->d as it is. */
static int create_solver(vi_sim *s, int resume)
{
    vi_sim_data *d = &s->d;
    vi_solver_free(s->solver);
    vi_solver_config cfg = {
        .n = 2, .nguards = VI_NGUARDS, .rhs = sim_rhs, .guards = sim_guards, .jac = sim_jac, .user = s,
        .method = d->par.solver, .rtol = d->events.rtol, .atol = d->events.atol, .max_step = d->par.max_step,
        .ode = &d->ode, .auto_choice = &d->auto_choice, .piece = sim_piece, .log = vi_sim_solver_log, .log_env = s};
    s->solver = resume ? vi_solver_resume(&cfg, d->t, d->x) : vi_solver_create(&cfg, d->t, d->x);
    s->solver_stale = 0;
    if (!s->solver) { /* the configuration is valid: the first step failed, a rate beyond the doubles */
        const vi_model *model = &d->model;
        vi_snprintf(s->msg, sizeof s->msg, "could not create the solver at t = %.17g s: no first step from the initial "
                    "state (the load's acceleration (P + m g - F_ext)/m = %g m/s2)", d->t,
                    (model->W0 - vi_ramp_at(&model->F_ext, d->t)) / model->m);
        append_cause(s, 0.0);
        size_t used = strlen(s->msg);
        vi_snprintf(s->msg + used, sizeof s->msg - used, "; raise m, or lower P or the contact's stiffness");
        return -1;
    }
    return 0;
}

int vi_sim_initialize(vi_sim *s)
{
    if (vi_sim_prepare(s) < 0) return -1;
    vi_sim_data *d = &s->d;
    double L, V, rtol = vi_sim_rtol(d);
    vi_model_scales(&d->model, d->x, &L, &V);
    vi_hybrid_start(&s->engine, rtol, (const double[2]){rtol * L, rtol * V}, d->t, d->x);
    d->initialized = 1;
    memset(&d->ode, 0, sizeof d->ode);
    memset(&d->auto_choice, 0, sizeof d->auto_choice);
    if (create_solver(s, 0) < 0) return -1;
    char text[400];
    vi_model_params model_params = vi_sim_model_params(&d->par);
    if (vi_model_option_warnings(&model_params, text, sizeof text) > 0) s->log(s->log_env, VI_LOG_WARNING, "%s", text);
    /* an importer that passes the declared default experiment's tolerance most likely passes a default */
    if (d->par.rtol > 0.0 && d->tolerance > 0.0 && d->tolerance != VI_RTOL_DEFAULT && d->par.rtol != d->tolerance)
        s->log(s->log_env, VI_LOG_WARNING, "rtol = %g is used, not the experiment's tolerance %g (set rtol = 0 to use the "
               "experiment's)", d->par.rtol, d->tolerance);
    vi_sim_check_validity(s);
    vi_sim_report_warnings(s); /* of the solver's creation */
    return 0;
}

void vi_sim_log_solver(const vi_sim *s)
{
    const vi_hybrid_state *e = &s->d.events;
    s->log(s->log_env, VI_LOG_SOLVER, "%s, rtol %g, atol %g m and %g m/s (scales %g m, %g m/s)",
           vi_solver_method_name(s->d.par.solver), e->rtol, e->atol[0], e->atol[1], e->atol[0] / e->rtol,
           e->atol[1] / e->rtol);
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
    s->peak_end.valid = 0;
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

/* New input values (and tunable a, f) take effect at the current time as an input jump
 * (vi_hybrid_input_jump); an input that continues its previous ramp (held, or the same slope)
 * changes nothing and does not restart the solver. */
static void apply_inputs(vi_sim *s)
{
    vi_sim_data *d = &s->d;
    double t = d->t;
    vi_ramp yC_in, F_ext;
    vi_sim_input_ramps(d, t, &yC_in, &F_ext);
    d->inputs_changed = 0;
    if (!vi_hybrid_input_jump(&s->engine, t, d->x, yC_in, F_ext, d->par.a, d->par.f)) return;
    s->solver_stale = 1;
    vi_sim_check_validity(s); /* a new amplitude */
}

/* ---- messages: what the contact's time scale says of a failure; the solver's warnings ------------ */

static double contact_stiffness(const vi_model *model, double t, const double x[2]);

/* A time scale shorter than this many units of the time resolution DBL_EPSILON |t| cannot be resolved
 * by steps at t (a contact needs many steps, each at least a unit). */
#define VI_RESOLVED_UNITS 1e3

/* The contact's time scale T = sqrt(m/k) [s] at the current state, k the tangent stiffness there (out
 * of contact: the law's at the indentation scale of vi_model_scales), with m, k and what sets k in
 * `note`; *k_out = k [N/m]. */
static double time_scale(const vi_sim *s, double *k_out, char *note, size_t n)
{
    const vi_model *model = &s->d.model;
    double k = model->mode == VI_MODE_FREE ? 0.0 : contact_stiffness(model, s->d.t, s->d.x), at = s->d.x[0], T;
    const char *where = "at the indentation";
    if (k > 0.0 && isfinite(k)) {
        T = sqrt(model->m) / sqrt(k);
    } else {
        double L, V;
        vi_model_scales(model, s->d.x, &L, &V);
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

/* What to change: raise m or soften the contact. */
static const char *remedy(const vi_model *model)
{
    return model->law == VI_LAW_LINEAR ? "raise m or lower k_spring" : "raise m or soften the contact (E1, E2, R1, R2)";
}

/* Append to s->msg what the contact's time scale says: whether it is too short for the time resolution
 * at t, or for the work bound over a communication step of h_comm [s] (0: none known), and what to
 * change. Every failure message ends with it. */
static void append_cause(vi_sim *s, double h_comm)
{
    char note[300];
    double k, T = time_scale(s, &k, note, sizeof note), t = s->d.t, unit = DBL_EPSILON * fabs(t);
    int unresolved = T < VI_RESOLVED_UNITS * unit, too_many = h_comm > (double)VI_MAX_STEPS_PER_ADVANCE * T;
    int late = T < VI_RESOLVED_UNITS * DBL_EPSILON * fabs(s->d.t_start); /* the start time alone is too late */
    size_t used = strlen(s->msg);
    used += (size_t)vi_snprintf(s->msg + used, sizeof s->msg - used, "; the contact's time scale %s", note);
    if (used < sizeof s->msg && unresolved)
        used += (size_t)vi_snprintf(s->msg + used, sizeof s->msg - used, " is only %.3g units of the time resolution "
                                    "%.3g s at t = %.17g s, too short for the solver's steps there", T / unit, unit, t);
    if (used < sizeof s->msg && too_many)
        used += (size_t)vi_snprintf(s->msg + used, sizeof s->msg - used, "%s %.3g times shorter than the communication "
                                    "step %g s, more than the %ld internal steps one step may take",
                                    unresolved ? " and" : " is", h_comm / T, h_comm, VI_MAX_STEPS_PER_ADVANCE);
    char shorter[80] = "";
    if (too_many)
        vi_snprintf(shorter, sizeof shorter, ", or use communication steps below %.3g s", (double)VI_MAX_STEPS_PER_ADVANCE * T);
    if (used < sizeof s->msg && (unresolved || too_many))
        vi_snprintf(s->msg + used, sizeof s->msg - used, ": %s%s%s", remedy(&s->d.model),
                    late ? ", or start the run nearer t = 0" : "", shorter);
}

/* Refuse at initialization what double precision cannot integrate: a contact whose rate k/m = 1/T^2
 * overflows (the Jacobian's entry, the contact frequency f_contact), naming m and the smallest mass
 * with that stiffness. */
static int time_scale_check(vi_sim *s)
{
    char note[300];
    double k, T = time_scale(s, &k, note, sizeof note), rate = 1.0 / T;
    if (isfinite(rate * rate)) return 0;
    VI_FAIL(s->msg, sizeof s->msg, "m = %g kg is too small for the contact: its time scale %s makes the rate k/m = "
            "1/T^2 overflow double; use m >= %.3g kg with this contact: the motion of a "
            "smaller mass cannot be integrated in double precision", s->d.model.m, note, k / DBL_MAX * 2.0);
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
            return;
        }
    if (r->kinds == VI_RELAY_KINDS) {
        r->others++;
        return;
    }
    memcpy(r->kind[r->kinds++], kind, sizeof kind);
    char note[300], units[160] = "";
    double k, T = time_scale(s, &k, note, sizeof note), unit = DBL_EPSILON * fabs(s->d.t);
    if (unit > 0.0)
        vi_snprintf(units, sizeof units, " is %.3g units of the time resolution at t = %.17g s%s", T / unit, s->d.t,
                    T < VI_RESOLVED_UNITS * unit ? ", too few for the solver's steps: the likely cause" : "");
    s->log(s->log_env, VI_LOG_WARNING, "%s (the contact's time scale %s%s; further warnings like this one are counted, "
           "not repeated)", text, note, units);
}

void vi_sim_report_warnings(vi_sim *s)
{
    vi_relay *r = &s->relay;
    for (int i = 0; i < r->kinds; i++)
        if (r->repeats[i] > 0) {
            s->log(s->log_env, VI_LOG_WARNING, "%ld more solver warnings like \"%s\" by t = %.17g s (counted, not relayed)",
                   r->repeats[i], r->kind[i], s->d.t);
            r->repeats[i] = 0;
        }
    if (r->others > 0)
        s->log(s->log_env, VI_LOG_WARNING, "%ld more solver warnings of other kinds by t = %.17g s (counted, not relayed)",
               r->others, s->d.t);
    r->others = 0;
}

/* ---- the loop ------------------------------------------------------------------------------- */

/* End the advance early (doc/model.md section 7.1): the state at d->t is consistent and usable. */
static int discard(vi_sim *s, const char *fmt, ...) VI_PRINTF_FORMAT(2, 3);
static int discard(vi_sim *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vi_vsnprintf(s->msg, sizeof s->msg, fmt, ap);
    va_end(ap);
    return VI_SIM_DISCARD;
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
    return stop_at_mode_change && s->d.model.mode != mode_before && s->d.t - s->d.step_t0 > VI_EARLY_RETURN_UNITS * unit;
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
    const vi_sim_data *d = &s->d;
    vi_snprintf(s->msg, sizeof s->msg, "the solver failed near t = %.17g s (mode %d, delta = %g m, v = %g m/s)", d->t,
                d->model.mode, d->x[0], d->x[1]);
    append_cause(s, s->advance_end - d->step_t0);
    return VI_SIM_ERROR;
}

/* The start of an advance to t_end: refuse what cannot run, take the inputs, re-arm, restart a stale
 * solver. VI_SIM_OK or VI_SIM_ERROR (s->msg). */
static int begin_advance(vi_sim *s, double t_end)
{
    vi_sim_data *d = &s->d;
    if (!s->solver) VI_FAIL(s->msg, sizeof s->msg, "the simulation is not initialized");
    if (!(t_end > d->t))
        VI_FAIL(s->msg, sizeof s->msg, "the step end %.17g s does not exceed the current time %.17g s in floating point",
                t_end, d->t);
    s->out_valid = 0;
    d->step_t0 = d->t;
    d->step_v0 = d->x[1];
    vi_hybrid_count_from(&s->engine, d->t);
    int changed = d->inputs_changed || s->solver_stale;
    if (d->inputs_changed) apply_inputs(s);
    vi_hybrid_rearm(&s->engine, d->t, d->x);
    d->F_peak = 0.0; /* the force now and the step's pieces raise it */
    peak_restart(s, changed);
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
    vi_sim_data *d = &s->d;
    int g = 0;
    while (g < VI_NGUARDS - 1 && fired[g] == 0) g++;
    int from = vi_hybrid_event(&s->engine, d->t, d->x, g, 1);
    peak_restart(s, 1);
    vi_hybrid_arm_at_zero(&s->engine, d->t, d->x);
    vi_sim_check_validity(s);
    if (vi_solver_reset(s->solver, d->t, d->x) < 0) return solver_failed(s);
    if (vi_hybrid_zeno(&s->engine, d->t, g, from, s->msg, sizeof s->msg)) return VI_SIM_DISCARD;
    if (++run->events >= VI_MAX_EVENTS_PER_ADVANCE && d->t < run->t_end) {
        discard(s, "work bound: %ld events in one step, stopped at t = %.17g s (mode %d); continue from there or use "
                   "smaller communication steps", VI_MAX_EVENTS_PER_ADVANCE, d->t, d->model.mode);
        append_cause(s, run->t_end - d->step_t0);
        return VI_SIM_DISCARD;
    }
    return PASS_MORE;
}

/* One pass of the loop: integrate to the next kink of the profile or the target, or to an event. */
static int advance_pass(vi_sim *s, advance_run *run)
{
    vi_sim_data *d = &s->d;
    int mode_before = d->model.mode, rc = VI_SOLVER_REACHED, fired[VI_SOLVER_MAX_GUARDS];
    double bp = d->model.profile ? vi_model_next_breakpoint(&d->model, d->t) : INFINITY;
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
                d->t, d->model.mode, (d->t - d->step_t0) / (double)VI_MAX_STEPS_PER_ADVANCE);
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
    if (stop_here(s, run->stop_at_mode_change, mode_before)) return PASS_STOPPED;
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
    vi_sim_data *d = &s->d;
    s->advance_end = t_end;
    if (begin_advance(s, t_end) != VI_SIM_OK) return reported(s, VI_SIM_ERROR);
    char why[400]; /* written only where a profile ends */
    advance_run run = {.t_end = t_end, .steps_left = VI_MAX_STEPS_PER_ADVANCE, .stop_at_mode_change = stop_at_mode_change};
    run.limit = d->model.profile ? vi_model_rolling_limit(&d->model, why, sizeof why) : INFINITY;
    run.target = run.limit < t_end ? run.limit : t_end;
    int pass = PASS_MORE;
    /* bounded: every pass is an event (bounded below) or a kink of the profile (finitely many in the
     * distance |V| (t_end - t) rolled) */
    while (pass == PASS_MORE && d->t < run.target) pass = advance_pass(s, &run);
    if (pass != PASS_MORE && pass != PASS_END && pass != PASS_STOPPED) return reported(s, pass);
    vi_sim_report_warnings(s);
    if (!isfinite(d->x[0]) || !isfinite(d->x[1]))
        VI_FAIL(s->msg, sizeof s->msg, "the state is not finite at t = %.17g s", d->t);
    /* at a communication point only the indentation can newly leave the range (a changes in
     * apply_inputs, which checks; the profile is fixed), unless a state was restored since */
    if (s->validity_unchecked ||
        (!(s->warned_validity & VI_INVALID_INDENTATION) && vi_model_indentation_invalid(&d->model, d->x)) ||
        (!(s->warned_validity & VI_INVALID_FORCE) && d->F_peak > vi_model_force_limit(&d->model)))
        vi_sim_check_validity(s);
    if (pass == PASS_STOPPED) return VI_SIM_EVENT;
    if (t_end > run.limit) return discard(s, "%s", why); /* the end of the profile: nothing beyond it */
    d->t = t_end;
    return VI_SIM_OK;
}

/* ---- outputs -------------------------------------------------------------------------------- */

/* Tangent contact stiffness dF/ddelta [N/m] (0 out of contact). A sticking mass is held at delta_c
 * between the two branches; small unloading would follow the unloading curve, so its stiffness. */
static double contact_stiffness(const vi_model *model, double t, const double x[2])
{
    if (model->mode == VI_Mode_stick) return vi_unload_stiffness(&model->unload, model->unload.delta_c);
    return model->m * vi_model_stiffness_over_mass(model, t, x);
}

/* The contact force averaged over the last step [t0, t]: the impulse over the step divided by it,
 * from the momentum balance m v' = F - W(t), W = P + m g - F_ext(t) (F_ext linear over the step, so
 * its mean is its midpoint value). Before any step: the force itself. */
static double mean_force(const vi_sim_data *d)
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

const vi_outputs *vi_sim_outputs_of(vi_sim *s, unsigned groups)
{
    unsigned need = groups & (VI_OUT_ALL & ~VI_OUT_DERIVATIVES) & ~s->out_valid;
    if (need) {
        const vi_sim_data *d = &s->d;
        vi_model_values values;
        vi_model_outputs(&d->model, d->t, d->x, need, &values);
        take_values(&values, need, &s->out);
        if (need & VI_OUT_MEMORY) s->out.W_damping = d->W_damping, s->out.W_dissipated = s->out.W_plastic + d->W_damping;
        if (need & VI_OUT_FORCE) s->out.F_peak = fmax(d->F_peak, s->out.F);
        if (need & VI_OUT_MEAN) s->out.F_mean = mean_force(d);
        if (need & VI_OUT_STIFFNESS) s->out.k_contact = contact_stiffness(&d->model, d->t, d->x);
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
    for (int i = 0; i < 2; i++)
        if (!isfinite(d->x[i])) VI_FAIL(msg, n, "x[%d] = %g is not finite", i, d->x[i]);
    if (!isfinite(d->y_me)) VI_FAIL(msg, n, "y_me = %g is not finite", d->y_me);
    if (d->initialized != 0 && d->initialized != 1) VI_FAIL(msg, n, "initialized = %d is not 0 or 1", d->initialized);
    if (!isfinite(d->step_t0) || d->step_t0 > d->t || !isfinite(d->step_v0))
        VI_FAIL(msg, n, "step_t0 = %g, step_v0 = %g: not finite or after t", d->step_t0, d->step_v0);
    if (!isfinite(d->step_u0) || !isfinite(d->yC_in_rate))
        VI_FAIL(msg, n, "step_u0 = %g, yC_in_rate = %g: not finite", d->step_u0, d->yC_in_rate);
    if (!isfinite(d->W_damping) || !(d->F_peak >= 0.0 && isfinite(d->F_peak)))
        VI_FAIL(msg, n, "W_damping = %g, F_peak = %g: not finite, or F_peak < 0", d->W_damping, d->F_peak);
    if (vi_hybrid_check(&d->events, d->t, msg, n) < 0) return -1;
    if (d->initialized && d->events.rtol != vi_sim_rtol(d))
        VI_FAIL(msg, n, "rtol = %g is not the one of the settings, %g", d->events.rtol, vi_sim_rtol(d));
    /* the solver's continuation (co-simulation; Model Exchange states, between events, have none in use) */
    int solver = d->initialized && surfaces;
    if (solver && d->par.solver == VI_Solver_auto && vi_solver_auto_check(&d->auto_choice, msg, n) < 0) return -1;
    int one_step = d->par.solver == VI_Solver_dop853 || (d->par.solver == VI_Solver_auto && !d->auto_choice.bdf);
    if (solver && one_step && vi_solver_ode_check(&d->ode, 2, VI_NGUARDS, d->t, msg, n) < 0) return -1;
    return surfaces ? vi_model_check(&d->model, d->x, msg, n) : vi_model_check_between_events(&d->model, d->x, msg, n);
}

int vi_sim_data_check(const vi_sim_data *d, char *msg, size_t n) { return data_check(d, 1, msg, n); }
int vi_sim_data_check_between_events(const vi_sim_data *d, char *msg, size_t n) { return data_check(d, 0, msg, n); }

void vi_sim_statistics(const vi_sim *s, vi_solver_stats *st)
{
    if (s->solver) vi_solver_statistics(s->solver, st);
    else memset(st, 0, sizeof *st);
}
