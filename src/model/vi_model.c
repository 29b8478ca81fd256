/* vi_model.c - hybrid model: modes, right-hand side, guards, events; equations in vi_model.h. */
#include "vi_model.h"

#include <math.h>
#include <stdio.h>

#include "vi_check.h"

#if defined(VI_VARIABLES_H) || defined(VI_TABLE_H) || defined(VI_FMU_H) || defined(VI_SOLVER_H)
#error "the model includes no FMI or solver header (its parameters: vi_model_params)"
#endif

/* Laws whose plastic memory is an unloading curve after the largest indentation (Johnson with a fixed
 * contact point, Thornton). */
static int is_johnson_fixed(const vi_model_contact *c)
{
    return (c->law == VI_LAW_JOHNSON && !c->moving) || c->law == VI_LAW_THORNTON;
}

/* Net load pressing the mass down, W(t) = P + m g - F_ext(t) [N]. */
static double net_load(const vi_model *model, double t) { return model->body.W0 - vi_ramp_at(&model->F_ext, t); }

/* The damped Hertz and linear laws' constants for a body of mass m [kg]; zero for the other laws. */
static int setup_damping(vi_model_contact *c, const vi_model_params *p, double m, char *msg, size_t n)
{
    c->damped = (vi_damped_hertz){0, 0.0, 0.0, 0.0};
    c->linear = (vi_linear_law){0.0, 0.0};
    if (c->law == VI_LAW_HERTZ_DAMPED &&
        vi_damped_hertz_setup(&c->damped, p->damping_formula, p->e_restitution, c->K, m) < 0)
        VI_FAIL(msg, n, "e_restitution = %g: no damping gives this restitution with damping_formula = %d (the exact "
                "damping reaches restitutions in [1e-9, 1])", p->e_restitution, p->damping_formula);
    if (c->law == VI_LAW_LINEAR && vi_linear_setup(&c->linear, p->k_spring, m, p->e_restitution) < 0)
        VI_FAIL(msg, n, "contact_model = linear needs k_spring > 0 N/m and e_restitution in (0, 1] (k_spring = %g, "
                "e_restitution = %g)", p->k_spring, p->e_restitution);
    return 0;
}

/* A contact's law and constants from the parameters (the law and material of both bodies). */
static void setup_contact(vi_model_contact *c, const vi_model_params *p)
{
    c->law = p->law;
    c->moving = p->moving_contact != 0 && p->law == VI_LAW_JOHNSON; /* only Johnson has a moving contact point */
    c->unloading = p->unloading == VI_UNLOAD_CONTINUOUS ? VI_UNLOAD_CONTINUOUS : VI_UNLOAD_PAPER;
    c->johnson.E_star = vi_effective_modulus(p->E1, p->nu1, p->E2, p->nu2);
    c->johnson.R_star = vi_effective_radius(p->R1, p->R2);
    c->johnson.theta_Y = p->theta_Y;
    c->K = vi_hertz_constant(c->johnson.E_star, c->johnson.R_star);
    c->johnson.F_Y = vi_yield_force(p->yield_formula == VI_YIELD_PRINTED ? VI_YIELD_PRINTED : VI_YIELD_TEXTBOOK,
                                    p->theta_Y, p->Y, c->johnson.R_star, c->johnson.E_star);
    c->johnson.delta_Y = vi_hertz_indentation(c->K, c->johnson.F_Y);
    c->k_lin = c->johnson.F_Y / c->johnson.delta_Y;
}

int vi_model_setup(vi_model *model, const vi_model_params *p, double t0, char *msg, size_t msg_size)
{
    if (!(p->R1 > 0.0 || p->R2 > 0.0))
        VI_FAIL(msg, msg_size, "R1 = R2 = 0: two planes have no point contact; give a radius");
    if (p->upper_stop && !(p->gap > 0.0 && isfinite(p->gap)))
        VI_FAIL(msg, msg_size, "gap = %g m: with upper_stop = true the clearance between the two surfaces must be "
                "finite and > 0", p->gap);

    model->body.m = p->m;
    model->body.W0 = p->P + p->m * p->g;
    model->a = p->a;
    model->omega = 2.0 * VI_PI * p->f;
    model->t0 = t0;
    model->phi0 = 0.0;
    model->t_phi = t0;
    model->profile = NULL;
    model->V = model->x0 = 0.0;
    model->ncontacts = p->upper_stop ? 2 : 1;
    for (int i = 0; i < VI_NCONTACTS; i++) model->contact[i] = (vi_model_contact){0};
    model->contact[VI_UPPER].upper = 1;
    model->contact[VI_UPPER].gap = p->upper_stop ? p->gap : 0.0;
    for (int i = 0; i < model->ncontacts; i++) {
        vi_model_contact *c = &model->contact[i];
        setup_contact(c, p);
        if (setup_damping(c, p, model->body.m, msg, msg_size) < 0) return -1;
        if (!(isfinite(model->body.W0) && isfinite(c->K) && c->K > 0.0 && isfinite(c->johnson.F_Y) && c->johnson.F_Y > 0.0 &&
              c->johnson.delta_Y > 0.0 && isfinite(c->k_lin) && c->k_lin > 0.0))
            VI_FAIL(msg, msg_size, "the parameters give no finite positive contact stiffness or yield force (E* = %g Pa, "
                    "R* = %g m, F_Y = %g N, delta_Y = %g m)", c->johnson.E_star, c->johnson.R_star, c->johnson.F_Y,
                    c->johnson.delta_Y);
    }
    return 0;
}

double vi_model_phase(const vi_model *model, double t) { return model->phi0 + model->omega * (t - model->t_phi); }

int vi_model_excitation_differs(const vi_model *model, double a, double f) { return a != model->a || 2.0 * VI_PI * f != model->omega; }

void vi_model_set_excitation(vi_model *model, double t, double x[2], double a, double f)
{
    double ph = vi_model_phase(model, t), c = cos(ph);
    x[0] += (a - model->a) * (c - 1.0); /* the platform moves, the mass does not */
    model->a = a;
    model->phi0 = fmod(ph, 2.0 * VI_PI);
    model->t_phi = t;
    model->omega = 2.0 * VI_PI * f;
}

void vi_model_set_inputs(vi_model *model, double t, double x[2], vi_ramp yC_in, vi_ramp F_ext)
{
    x[0] += vi_ramp_at(&yC_in, t) - vi_ramp_at(&model->yC_in, t); /* the platform moves, the mass does not */
    model->yC_in = yC_in;
    model->F_ext = F_ext;
}

/* ---- rolling over a profile ------------------------------------------------------------------ */

double vi_model_rolling_position(const vi_model *model, double t) { return model->x0 + model->V * (t - model->t0); }

int vi_model_set_rolling(vi_model *model, const vi_profile *profile, double V, double x0, char *msg, size_t n)
{
    if (profile && !vi_profile_periodic(profile) &&
        !(x0 >= vi_profile_x_first(profile) && x0 <= vi_profile_x_last(profile))) {
        vi_snprintf(msg, n, "x0 = %g m lies outside the profile [%g, %g] m (set profile_periodic to repeat it)", x0,
                    vi_profile_x_first(profile), vi_profile_x_last(profile));
        return -1;
    }
    model->profile = profile;
    model->V = V;
    model->x0 = x0;
    return 0;
}

/* At most this many ulp steps round a breakpoint time past its kink (a few suffice). */
#define VI_BREAKPOINT_NUDGES 64

double vi_model_next_breakpoint(const vi_model *model, double t)
{
    if (!model->profile || model->V == 0.0) return INFINITY;
    int dir = model->V > 0.0 ? 1 : -1;
    double xk = vi_profile_next_kink(model->profile, vi_model_rolling_position(model, t), dir);
    if (!isfinite(xk)) return INFINITY;
    double tk = model->t0 + (xk - model->x0) / model->V;
    for (int i = 0; i < VI_BREAKPOINT_NUDGES; i++) { /* position past the kink: the piece after it */
        double pos = vi_model_rolling_position(model, tk);
        if (dir > 0 ? pos >= xk : pos < xk) break;
        tk = nextafter(tk, INFINITY);
    }
    return tk > t ? tk : nextafter(t, INFINITY);
}

int vi_model_breakpoint(vi_model *model, double t, double x[2])
{
    vi_model_freeze(model, t, x);
    return vi_model_resolve(model, t, x);
}

double vi_model_rolling_limit(const vi_model *model, char *msg, size_t n)
{
    if (!model->profile || vi_profile_periodic(model->profile) || model->V == 0.0) return INFINITY;
    double end = model->V > 0.0 ? vi_profile_x_last(model->profile) : vi_profile_x_first(model->profile);
    double t = model->t0 + (end - model->x0) / model->V;
    vi_snprintf(msg, n, "t = %.17g s: the rolling position x0 + V (t - t_start) = %.17g m reaches the end of the profile "
                "(%s = %g m); the profile does not go on beyond it (set profile_periodic to repeat it)", t,
                vi_model_rolling_position(model, t), model->V > 0.0 ? "x_last" : "x_first", end);
    return t;
}

/* Platform position and its first three time derivatives at t: y[0..3] = yC, yC', yC'', yC'''. */
static void platform(const vi_model *model, double t, double y[4])
{
    double ph = vi_model_phase(model, t), c = cos(ph), s = sin(ph), aw = model->a * model->omega;
    y[0] = vi_ramp_at(&model->yC_in, t) + model->a * (c - 1.0);
    y[1] = model->yC_in.du - aw * s;
    y[2] = -aw * model->omega * c;
    y[3] = aw * model->omega * model->omega * s;
    if (model->profile) { /* yb(x0 + V (t - t0)): d/dt = V d/dx */
        double b[4], V = model->V;
        vi_profile_eval(model->profile, vi_model_rolling_position(model, t), b);
        y[0] += b[0], y[1] += V * b[1], y[2] += V * V * b[2], y[3] += V * V * V * b[3];
    }
}

double vi_model_platform(const vi_model *model, double t, double *dyC, double *ddyC)
{
    if (!dyC && !ddyC) { /* the position only: no sine, no derivatives of the profile */
        double yC = vi_ramp_at(&model->yC_in, t) + model->a * (cos(vi_model_phase(model, t)) - 1.0);
        if (model->profile) {
            double b[4];
            vi_profile_eval(model->profile, vi_model_rolling_position(model, t), b);
            yC += b[0];
        }
        return yC;
    }
    double y[4];
    platform(model, t, y);
    if (dyC) *dyC = y[1];
    if (ddyC) *ddyC = y[2];
    return y[0];
}

/* Force holding a sticking mass on the platform: F_hold = W(t) + m yC''(t). */
static double hold_force(const vi_model *model, double t)
{
    double y[4];
    platform(model, t, y);
    return net_load(model, t) + model->body.m * y[2];
}

/* Its rate F_hold' = W' + m yC''' = -F_ext' + m yC''' [N/s]: with delta' = 0 it is m delta''' plus
 * the force law's rate, so it breaks a tie of F_hold with a fixed force (next time derivative). */
static double hold_force_rate(const vi_model *model, double t)
{
    double y[4];
    platform(model, t, y);
    return -model->F_ext.du + model->body.m * y[3];
}

/* ---- the contact laws as the automaton uses them: one row of functions per law ---------------- */

/* What the automaton asks of a law's mode choice: the rates at (t, x) relative to the surfaces. */
typedef struct {
    double r;      /* delta' [m/s] */
    double F_hold; /* force holding the mass on the platform, W + m yC'' [N] */
    double j;      /* its rate [N/s] (the tie-breaker) */
    double m;      /* the body's mass [kg] */
    int snap;      /* SNAP_*: the stick guard an event put exactly on its surface */
} rates;

typedef struct {
    const char *name;
    /* force [N] and stiffness dF/ddelta [N/m] in the elastic and the plastic mode at indentation d */
    double (*elastic_force)(const vi_model_contact *c, double d);
    double (*elastic_stiffness)(const vi_model_contact *c, double d);
    double (*plastic_force)(const vi_model_contact *c, double d); /* NULL: the law never yields */
    double (*plastic_stiffness)(const vi_model_contact *c, double d);
    /* their rates d(stiffness)/d(delta) [N/m^2] (Model Exchange's Jacobian) */
    double (*elastic_stiffness_rate)(const vi_model_contact *c, double d);
    double (*plastic_stiffness_rate)(const vi_model_contact *c, double d);
    /* the rates d/d(delta) of the memory outputs in the current mode at indentation d */
    void (*memory_rates)(const vi_model_contact *c, double d, vi_memory_rates *r);
    /* the indentation at which the bodies touch, and at which the elastic branch yields (INFINITY:
     * never) */
    double (*contact_surface)(const vi_model_contact *c);
    double (*yield_surface)(const vi_model_contact *c);
    /* the lowest indentation the plastic mode may have (vi_model_check) */
    double (*plastic_floor)(const vi_model_contact *c);
    /* write down the memory a plastic motion leaves at x (mode plastic; may round x onto a surface);
     * NULL: nothing to write down */
    void (*freeze_plastic)(vi_model_contact *c, double x[2]);
    /* the mode consistent with x and the rates (vi_model_resolve); may update the memory */
    int (*choose)(vi_model_contact *c, double x[2], const rates *q);
    /* may the law (with its flags and memory) be in this mode? */
    int (*mode_allowed)(const vi_model_contact *c, int mode);
    /* at rest under the load W > 0: indentation on the virgin curve, and the stiffness of small
     * oscillations there */
    double (*static_indentation)(const vi_model_contact *c, double W);
    double (*static_stiffness)(const vi_model_contact *c, double W);
    /* the virgin curve's stiffness at d > 0, and the impact indentation at approach speed v > 0 */
    double (*virgin_stiffness)(const vi_model_contact *c, double d);
    double (*impact_indentation)(const vi_model_contact *c, double m, double v); /* m: the body's mass [kg] */
    /* the memory outputs (delta_c, delta_f, delta_p, Rbar, W_plastic) at indentation d */
    void (*memory_outputs)(const vi_model_contact *c, double d, vi_model_values *out);
    /* the elastic energy [J] held at indentation d in the elastic and the plastic mode (vi_model_contact_energy) */
    double (*elastic_energy)(const vi_model_contact *c, double d);
    double (*plastic_energy)(const vi_model_contact *c, double d);
    int permanent_set; /* the memory is the permanent set delta_p (else delta_p stays 0) */
    /* Laws with an unloading curve (Johnson fixed, Thornton): the virgin curve's inverse and work, the
     * unloading curve after delta_c and its rates with delta_c; may_stick: the unloading curve can lie
     * below the loading force at delta_c (stick possible) */
    double (*virgin_indentation)(const vi_model_contact *c, double F);
    double (*virgin_work)(const vi_model_contact *c, double d);
    vi_unload_curve (*unload_curve)(const vi_model_contact *c, double delta_c);
    vi_unload_rates (*unload_rates)(const vi_model_contact *c, double delta_c);
    int may_stick;
    /* Laws whose force depends on the rate r = delta' (damped Hertz, linear), NULL otherwise: force and
     * partials in mode elastic, second partials, and the guard with the sign of the unclamped force
     * (mode elastic is left where it falls through 0, mode free entered again where it rises while
     * delta > 0) */
    vi_law_force (*rate_force)(const vi_model_contact *c, double d, double r);
    vi_law_curvature (*rate_curvature)(const vi_model_contact *c, double d, double r);
    vi_law_guard (*force_guard)(const vi_model_contact *c, double d, double r);
} law_fns;

static const law_fns *law(const vi_model_contact *c);
static int below_written(const vi_model_contact *c, double d);

/* The sign of the first nonzero of (position, rate, acceleration, jerk) relative to a surface is
 * positive. With delta' = 0 the acceleration of delta is (F_hold - F)/m and its jerk F_hold'/m (F
 * fixed on the surface), so callers pass force differences and F_hold' for the last two. */
static int ahead(double pos, double rate, double acc, double jerk)
{
    return pos > 0.0 || (pos == 0.0 && (rate > 0.0 || (rate == 0.0 && (acc > 0.0 || (acc == 0.0 && jerk > 0.0)))));
}

/* Which stick guard an event put exactly on its surface: its force difference counts as 0, so that
 * the next derivative decides (the guard's value at the located root is only nearly 0). */
enum { SNAP_NONE = -1, SNAP_LOAD = 0, SNAP_UNLOAD = 1, SNAP_RELEASE = 2 /* the damped laws' force guard */ };

/* Hertz and Johnson share the impact indentation (15 m v^2/(16 E* sqrt(R*)))^(2/5). */
static double hertz_impact(const vi_model_contact *c, double m, double v)
{
    return pow(15.0 * m * v * v / (16.0 * c->johnson.E_star * sqrt(c->johnson.R_star)), 0.4);
}
static double zero_surface(const vi_model_contact *c) { return (void)c, 0.0; }
static void no_memory(const vi_model_contact *c, double d, vi_model_values *out) { (void)c, (void)d, (void)out; }
static double no_rate(const vi_model_contact *c, double d) { return (void)c, (void)d, 0.0; }
static void no_memory_rates(const vi_model_contact *c, double d, vi_memory_rates *r)
{
    (void)c, (void)d;
    *r = (vi_memory_rates){0.0, 0.0, 0.0, 0.0, 0.0};
}

/* Hertz (eq. 2): elastic only. */
static double hertz_force(const vi_model_contact *c, double d) { return vi_hertz_force(c->K, d); }
static double hertz_stiffness(const vi_model_contact *c, double d) { return vi_hertz_stiffness(c->K, d); }
static double hertz_stiffness_rate(const vi_model_contact *c, double d) { return vi_hertz_stiffness_rate(c->K, d); }
static double hertz_no_yield(const vi_model_contact *c) { return (void)c, INFINITY; }
static double hertz_energy(const vi_model_contact *c, double d) { return vi_hertz_energy(c->K, d); }
static int hertz_choose(vi_model_contact *c, double x[2], const rates *q)
{
    (void)c;
    return ahead(x[0], q->r, q->F_hold, q->j) ? VI_MODE_ELASTIC : VI_MODE_FREE;
}
static int hertz_modes(const vi_model_contact *c, int mode) { return (void)c, mode == VI_MODE_FREE || mode == VI_MODE_ELASTIC; }
static double hertz_static_indentation(const vi_model_contact *c, double W) { return vi_hertz_indentation(c->K, W); }
static double hertz_static_stiffness(const vi_model_contact *c, double W)
{
    return vi_hertz_stiffness(c->K, vi_hertz_indentation(c->K, W));
}

/* Johnson (eqs. 3, 4): the virgin curve, with a fixed contact point the unloading memory U. */
static double johnson_load(const vi_model_contact *c, double d) { return vi_johnson_load(&c->johnson, d); }
static double johnson_load_stiffness(const vi_model_contact *c, double d) { return vi_johnson_load_stiffness(&c->johnson, d); }
static double johnson_load_stiffness_rate(const vi_model_contact *c, double d) { return vi_johnson_load_stiffness_rate(&c->johnson, d); }
static double johnson_contact(const vi_model_contact *c) { return is_johnson_fixed(c) && c->yielded ? c->unload.delta_f : 0.0; }
static double johnson_yield(const vi_model_contact *c) { return c->johnson.delta_Y; }
static double johnson_plastic_floor(const vi_model_contact *c) { return c->moving ? c->johnson.delta_Y : c->unload.delta_c; }
/* The memory is the largest indentation reached, never below yield: a state an importer hands over
 * may lie below it (a step that went far past the turning point), and the unloading curve of an
 * indentation below delta_Y / 2 does not exist (area ratio < 0). */
static void johnson_freeze(vi_model_contact *c, double x[2])
{
    double dc = fmax(x[0], c->yielded ? fmax(c->unload.delta_c, c->johnson.delta_Y) : c->johnson.delta_Y);
    if (is_johnson_fixed(c)) c->unload = law(c)->unload_curve(c, dc);
}
static int johnson_choose(vi_model_contact *c, double x[2], const rates *q)
{
    double d = x[0], r = q->r, F_hold = q->F_hold, j = q->j;
    int mode = VI_MODE_FREE;
    if (!c->yielded || c->moving) { /* the surfaces of the guards: contact 0 (no memory), yield delta_Y */
        if (!ahead(d - law(c)->contact_surface(c), r, F_hold, j)) return VI_MODE_FREE;
        mode = ahead(d - law(c)->yield_surface(c), r, F_hold - c->johnson.F_Y, j) ? VI_MODE_PLASTIC : VI_MODE_ELASTIC;
        if (mode == VI_MODE_ELASTIC || c->moving) return mode;
        c->yielded = 1;
        c->unload = law(c)->unload_curve(c, d > c->johnson.delta_Y ? d : c->johnson.delta_Y);
    }
    if (d > c->unload.delta_c) c->unload = law(c)->unload_curve(c, d); /* pushed deeper */
    double F_load = law(c)->plastic_force(c, c->unload.delta_c), F_unload = vi_unload_force(&c->unload, d);
    double dF_load = q->snap == SNAP_LOAD ? 0.0 : F_hold - F_load;
    double dF_unload = q->snap == SNAP_UNLOAD ? 0.0 : F_hold - F_unload;
    if (ahead(d - c->unload.delta_c, r, dF_load, j)) return VI_MODE_PLASTIC;
    if (d == c->unload.delta_c && r == 0.0 && ahead(0.0, 0.0, dF_unload, j) && law(c)->may_stick &&
        c->unloading == VI_UNLOAD_PAPER)
        return VI_MODE_STICK; /* F_unload < F_hold <= F_load: neither branch is consistent */
    if (ahead(d - c->unload.delta_f, r, dF_unload, j)) return VI_MODE_UNLOAD;
    return mode;
}
static int johnson_modes(const vi_model_contact *c, int mode)
{
    if (!is_johnson_fixed(c)) return mode >= VI_MODE_FREE && mode <= VI_MODE_PLASTIC;
    if (!c->yielded) return mode == VI_MODE_FREE || mode == VI_MODE_ELASTIC;
    return mode == VI_MODE_FREE || mode == VI_MODE_PLASTIC || mode == VI_MODE_UNLOAD ||
           (mode == VI_MODE_STICK && law(c)->may_stick && c->unloading == VI_UNLOAD_PAPER);
}
/* Indentation at rest under W > 0 on the Johnson virgin curve, with F(d) >= W where rounding allows,
 * so that a pre-loaded start does not see a spurious push into the material. The inverse is
 * accurate to a few ulps; at most VI_STATIC_NUDGES steps of 1, 2, 4, ... ulps close the gap. When F
 * cannot reach W (its value is denormal: loads below about 1e-300 N), d stays within 2^16 ulps. */
#define VI_STATIC_NUDGES 16
static double johnson_static_indentation(const vi_model_contact *c, double W)
{
    const law_fns *L = law(c);
    double d = L->virgin_indentation(c, W), step = nextafter(d, INFINITY) - d;
    for (int i = 0; i < VI_STATIC_NUDGES && L->plastic_force(c, d) < W; i++, step *= 2.0) d += step;
    return d;
}
static double johnson_static_stiffness(const vi_model_contact *c, double W)
{
    const law_fns *L = law(c);
    double d = L->virgin_indentation(c, W);
    if (!is_johnson_fixed(c) || d <= c->johnson.delta_Y) return L->plastic_stiffness(c, d);
    vi_unload_curve U = L->unload_curve(c, d); /* small oscillations unload */
    return vi_unload_stiffness(&U, d);
}
static void johnson_memory(const vi_model_contact *c, double d, vi_model_values *out)
{
    if (!is_johnson_fixed(c) || !c->yielded) return;
    vi_unload_curve U = c->unload; /* while loading plastically: the curve of the deepest point so far */
    if (c->mode == VI_MODE_PLASTIC && d > U.delta_c) U = law(c)->unload_curve(c, d);
    out->delta_c = U.delta_c;
    out->delta_f = U.delta_f;
    out->Rbar = U.Rbar;
    /* dissipated = work along the virgin curve - energy the unloading curve gives back */
    out->W_plastic = law(c)->virgin_work(c, U.delta_c) - vi_unload_energy(&U, U.delta_c);
}
/* While Johnson (fixed contact point) loads plastically beyond the memory written down, delta_c = d and
 * the unloading curve moves with it: W_plastic = load work(delta_c) - 0.4 Kbar delta_r^2.5, Kbar =
 * 4/3 E* sqrt(Rbar). */
static void johnson_memory_rates(const vi_model_contact *c, double d, vi_memory_rates *r)
{
    if (!is_johnson_fixed(c) || c->mode != VI_MODE_PLASTIC || below_written(c, d)) {
        no_memory_rates(c, d, r);
        return;
    }
    vi_unload_curve U = law(c)->unload_curve(c, d);
    vi_unload_rates u = law(c)->unload_rates(c, d);
    double dK = 2.0 / 3.0 * c->johnson.E_star * u.Rbar / sqrt(U.Rbar), dr = U.delta_r;
    r->delta_c = 1.0;
    r->delta_f = 1.0 - u.delta_r;
    r->delta_p = 0.0;
    r->Rbar = u.Rbar;
    r->W_plastic = law(c)->plastic_force(c, d) - 0.4 * dK * dr * dr * sqrt(dr) - U.Kbar * dr * sqrt(dr) * u.delta_r;
}

/* The energy held while loading on the virgin curve beyond delta_Y: the unloading curve of delta_c = d
 * gives it back (with a moving contact point the virgin curve itself does). */
static double johnson_plastic_energy(const vi_model_contact *c, double d)
{
    if (!is_johnson_fixed(c)) return law(c)->virgin_work(c, d);
    vi_unload_curve U = law(c)->unload_curve(c, d);
    return vi_unload_energy(&U, d);
}

static double johnson_indentation(const vi_model_contact *c, double F) { return vi_johnson_load_indentation(&c->johnson, F); }
static double johnson_work(const vi_model_contact *c, double d) { return vi_johnson_load_work(&c->johnson, d); }
static vi_unload_curve johnson_unload(const vi_model_contact *c, double dc) { return vi_johnson_unload_curve(&c->johnson, c->unloading, dc); }
static vi_unload_rates johnson_unload_rates(const vi_model_contact *c, double dc) { return vi_johnson_unload_rates(&c->johnson, c->unloading, dc); }
/* Paper unloading as printed returns more energy than the loading took after a small plastic excursion
 * (eq. 3 is stiffer than Hertz above delta_Y; W_plastic < 0 for delta_c < 1.2527 delta_Y at theta_Y = 1.1).
 * Returns 1, with the values in msg, when the unloading curve in memory does (not while delta_c moves). */
static int johnson_makes_energy(const vi_model_contact *c, double t, char *msg, size_t n)
{
    if (c->law != VI_LAW_JOHNSON || c->moving || c->unloading != VI_UNLOAD_PAPER || !c->yielded ||
        c->mode == VI_MODE_PLASTIC)
        return 0;
    const vi_unload_curve *U = &c->unload;
    double taken = vi_johnson_load_work(&c->johnson, U->delta_c), returned = vi_unload_energy(U, U->delta_c);
    if (!(returned > taken)) return 0;
    vi_snprintf(msg, n, "t = %.17g s: unloading = paper returns more energy than the contact took: loading to "
                "delta_c = %g m (%.5g delta_Y) took %g J, its unloading curve (eq. 4 as printed) gives back %g J "
                "(W_plastic = %g J), a rebound faster than the impact, as below 1.2527 delta_Y; unloading = "
                "continuous does not", t, U->delta_c, U->delta_c / c->johnson.delta_Y, taken, returned,
                taken - returned);
    return 1;
}

/* Thornton (vi_laws.h): Johnson's automaton with Thornton's virgin and unloading curves; the unloading
 * curve meets the loading force at delta_c, so there is no stick. */
static double thornton_load(const vi_model_contact *c, double d) { return vi_thornton_load(&c->johnson, d); }
static double thornton_load_stiffness(const vi_model_contact *c, double d) { return vi_thornton_load_stiffness(&c->johnson, d); }
static double thornton_load_stiffness_rate(const vi_model_contact *c, double d) { return vi_thornton_load_stiffness_rate(&c->johnson, d); }
static double thornton_indentation(const vi_model_contact *c, double F) { return vi_thornton_load_indentation(&c->johnson, F); }
static double thornton_work(const vi_model_contact *c, double d) { return vi_thornton_load_work(&c->johnson, d); }
static vi_unload_curve thornton_unload(const vi_model_contact *c, double dc) { return vi_thornton_unload_curve(&c->johnson, dc); }
static vi_unload_rates thornton_unload_rates(const vi_model_contact *c, double dc) { return vi_thornton_unload_rates(&c->johnson, dc); }

/* Damped Hertz and the linear spring-dashpot (vi_laws.h): modes free and elastic, the force a function
 * of delta and its rate; the rate-free part (the spring) serves the static state and the scales. */
static vi_law_force damped_force(const vi_model_contact *c, double d, double r) { return vi_damped_hertz_force(&c->damped, d, r, c->V_i); }
static vi_law_curvature damped_curvature(const vi_model_contact *c, double d, double r) { return vi_damped_hertz_curvature(&c->damped, d, r, c->V_i); }
static vi_law_guard damped_guard(const vi_model_contact *c, double d, double r) { return vi_damped_hertz_guard(&c->damped, d, r, c->V_i); }
static vi_law_force linear_force(const vi_model_contact *c, double d, double r) { return vi_linear_force(&c->linear, d, r); }
static vi_law_curvature linear_curvature(const vi_model_contact *c, double d, double r) { return (void)c, (void)d, (void)r, (vi_law_curvature){0.0, 0.0}; }
static vi_law_guard linear_guard(const vi_model_contact *c, double d, double r) { return vi_linear_guard(&c->linear, d, r); }
static double spring_force(const vi_model_contact *c, double d) { return d > 0.0 ? c->linear.k * d : 0.0; }
static double spring_stiffness(const vi_model_contact *c, double d) { return d > 0.0 ? c->linear.k : 0.0; }
static double spring_static_indentation(const vi_model_contact *c, double W) { return W / c->linear.k; }
static double spring_static_stiffness(const vi_model_contact *c, double W) { return (void)W, c->linear.k; }
static double spring_virgin_stiffness(const vi_model_contact *c, double d) { return (void)d, c->linear.k; }
static double spring_impact(const vi_model_contact *c, double m, double v) { return v * sqrt(m) / sqrt(c->linear.k); }
static double spring_energy(const vi_model_contact *c, double d) { return d > 0.0 ? 0.5 * c->linear.k * d * d : 0.0; }
/* Leaving the free mode where the force guard g is well inside its positive side (more than half the
 * size of its terms; at a resumed contact it is about 0) is a new contact, through delta = 0. */
#define VI_ONSET_GUARD_FRACTION 0.5
static int new_contact(const vi_model_contact *c, double d, double r)
{
    vi_law_guard g = law(c)->force_guard(c, d, r);
    return d <= 0.0 || g.g > VI_ONSET_GUARD_FRACTION * (fabs(g.g - g.dg_drate * r) + fabs(g.dg_drate * r));
}

/* In contact while delta > 0 and the unclamped force is positive: the side of delta = 0, then that of
 * the guard g (with F = 0 on its surface, delta'' = F_hold/m: g' = g_d r + g_r F_hold/m). A new contact
 * takes its approach speed as V_i. */
static int damped_choose(vi_model_contact *c, double x[2], const rates *q)
{
    double d = x[0], r = q->r;
    if (!ahead(d, r, q->F_hold, q->j)) return VI_MODE_FREE;
    vi_law_guard g = law(c)->force_guard(c, d, r);
    double g0 = q->snap == SNAP_RELEASE ? 0.0 : g.g;
    if (!ahead(g0, g.dg_ddelta * r + g.dg_drate * q->F_hold / q->m, 0.0, 0.0)) return VI_MODE_FREE;
    if (c->mode == VI_MODE_FREE && new_contact(c, d, r)) c->V_i = r > 0.0 ? r : 0.0;
    return VI_MODE_ELASTIC;
}

/* Linear elastic-perfectly plastic (paper Fig. 3): a spring k_lin from the permanent set delta_p,
 * flowing at F_Y. */
static double lepp_force(const vi_model_contact *c, double d) { return d > c->delta_p ? c->k_lin * (d - c->delta_p) : 0.0; }
static double lepp_stiffness(const vi_model_contact *c, double d) { return d > c->delta_p ? c->k_lin : 0.0; }
static double lepp_flow_force(const vi_model_contact *c, double d) { return (void)d, c->johnson.F_Y; }
static double lepp_flow_stiffness(const vi_model_contact *c, double d) { return (void)c, (void)d, 0.0; }
static double lepp_contact(const vi_model_contact *c) { return c->delta_p; }
static double lepp_yield(const vi_model_contact *c) { return c->delta_p + c->johnson.delta_Y; }
/* Plastic flow to x[0]: the permanent set follows, delta_p = delta - delta_Y; x[0] is then rounded
 * onto the yield surface so that its guard is exactly zero, never an ulp below. The permanent set
 * never decreases: a state below the yield surface (an importer's step past the turning point) leaves
 * it and x as they are. */
static void lepp_flow_to(vi_model_contact *c, double x[2])
{
    if (!(x[0] - c->johnson.delta_Y >= c->delta_p)) return;
    c->delta_p = x[0] - c->johnson.delta_Y;
    x[0] = lepp_yield(c);
}
static int lepp_choose(vi_model_contact *c, double x[2], const rates *q)
{
    if (!ahead(x[0] - lepp_contact(c), q->r, q->F_hold, q->j)) return VI_MODE_FREE;
    if (x[0] > lepp_yield(c)) lepp_flow_to(c, x); /* pushed beyond yield: it flowed */
    return ahead(x[0] - lepp_yield(c), q->r, q->F_hold - c->johnson.F_Y, q->j) ? VI_MODE_PLASTIC : VI_MODE_ELASTIC;
}
static int lepp_modes(const vi_model_contact *c, int mode) { return (void)c, mode >= VI_MODE_FREE && mode <= VI_MODE_PLASTIC; }
static double lepp_energy(const vi_model_contact *c, double d)
{
    double s = d - c->delta_p;
    return s > 0.0 ? 0.5 * c->k_lin * s * s : 0.0;
}
static double lepp_flow_energy(const vi_model_contact *c, double d) { return (void)d, 0.5 * c->johnson.F_Y * c->johnson.delta_Y; }
static double lepp_static_indentation(const vi_model_contact *c, double W)
{
    return W <= c->johnson.F_Y ? W / c->k_lin : c->johnson.delta_Y; /* beyond F_Y: flows from the start */
}
static double lepp_static_stiffness(const vi_model_contact *c, double W) { return (void)W, c->k_lin; }
static double lepp_virgin_stiffness(const vi_model_contact *c, double d) { return (void)d, c->k_lin; }
static double lepp_impact(const vi_model_contact *c, double m, double v) { return v * sqrt(m) / sqrt(c->k_lin); }
static void lepp_memory(const vi_model_contact *c, double d, vi_model_values *out)
{
    out->delta_p = c->mode == VI_MODE_PLASTIC ? fmax(d - c->johnson.delta_Y, c->delta_p) : c->delta_p;
    out->W_plastic = c->johnson.F_Y * out->delta_p;
}
/* While LEPP flows beyond the set written down, delta_p = d - delta_Y and W_plastic = F_Y delta_p. */
static void lepp_memory_rates(const vi_model_contact *c, double d, vi_memory_rates *r)
{
    no_memory_rates(c, d, r);
    if (c->mode == VI_MODE_PLASTIC && !below_written(c, d))
        r->delta_p = 1.0, r->W_plastic = c->johnson.F_Y;
}

static const law_fns laws[] = {
    [VI_LAW_HERTZ] = {
        .name = "hertz", .elastic_force = hertz_force, .elastic_stiffness = hertz_stiffness,
        .elastic_stiffness_rate = hertz_stiffness_rate, .plastic_stiffness_rate = no_rate, .memory_rates = no_memory_rates,
        .contact_surface = zero_surface, .yield_surface = hertz_no_yield, .plastic_floor = hertz_no_yield,
        .choose = hertz_choose, .mode_allowed = hertz_modes, .static_indentation = hertz_static_indentation,
        .static_stiffness = hertz_static_stiffness, .virgin_stiffness = hertz_stiffness,
        .impact_indentation = hertz_impact, .memory_outputs = no_memory, .elastic_energy = hertz_energy},
    [VI_LAW_JOHNSON] = {
        .name = "johnson", .elastic_force = johnson_load, .elastic_stiffness = johnson_load_stiffness,
        .plastic_force = johnson_load, .plastic_stiffness = johnson_load_stiffness, .contact_surface = johnson_contact,
        .elastic_stiffness_rate = johnson_load_stiffness_rate, .plastic_stiffness_rate = johnson_load_stiffness_rate,
        .memory_rates = johnson_memory_rates,
        .yield_surface = johnson_yield, .plastic_floor = johnson_plastic_floor, .freeze_plastic = johnson_freeze,
        .choose = johnson_choose, .mode_allowed = johnson_modes, .static_indentation = johnson_static_indentation,
        .static_stiffness = johnson_static_stiffness, .virgin_stiffness = johnson_load_stiffness,
        .impact_indentation = hertz_impact, .memory_outputs = johnson_memory, .virgin_indentation = johnson_indentation,
        .virgin_work = johnson_work, .unload_curve = johnson_unload, .unload_rates = johnson_unload_rates, .may_stick = 1,
        .elastic_energy = johnson_work, .plastic_energy = johnson_plastic_energy},
    [VI_LAW_LEPP] = {
        .name = "lepp", .elastic_force = lepp_force, .elastic_stiffness = lepp_stiffness,
        .plastic_force = lepp_flow_force, .plastic_stiffness = lepp_flow_stiffness, .contact_surface = lepp_contact,
        .elastic_stiffness_rate = no_rate, .plastic_stiffness_rate = no_rate, .memory_rates = lepp_memory_rates,
        .yield_surface = lepp_yield, .plastic_floor = lepp_yield, .freeze_plastic = lepp_flow_to,
        .choose = lepp_choose, .mode_allowed = lepp_modes, .static_indentation = lepp_static_indentation,
        .static_stiffness = lepp_static_stiffness, .virgin_stiffness = lepp_virgin_stiffness,
        .impact_indentation = lepp_impact, .memory_outputs = lepp_memory, .permanent_set = 1,
        .elastic_energy = lepp_energy, .plastic_energy = lepp_flow_energy},
    [VI_LAW_HERTZ_DAMPED] = {
        .name = "hertz_damped", .elastic_force = hertz_force, .elastic_stiffness = hertz_stiffness,
        .elastic_stiffness_rate = hertz_stiffness_rate, .plastic_stiffness_rate = no_rate, .memory_rates = no_memory_rates,
        .contact_surface = zero_surface, .yield_surface = hertz_no_yield, .plastic_floor = hertz_no_yield,
        .choose = damped_choose, .mode_allowed = hertz_modes, .static_indentation = hertz_static_indentation,
        .static_stiffness = hertz_static_stiffness, .virgin_stiffness = hertz_stiffness,
        .impact_indentation = hertz_impact, .memory_outputs = no_memory, .rate_force = damped_force,
        .rate_curvature = damped_curvature, .force_guard = damped_guard, .elastic_energy = hertz_energy},
    [VI_LAW_LINEAR] = {
        .name = "linear", .elastic_force = spring_force, .elastic_stiffness = spring_stiffness,
        .elastic_stiffness_rate = no_rate, .plastic_stiffness_rate = no_rate, .memory_rates = no_memory_rates,
        .contact_surface = zero_surface, .yield_surface = hertz_no_yield, .plastic_floor = hertz_no_yield,
        .choose = damped_choose, .mode_allowed = hertz_modes, .static_indentation = spring_static_indentation,
        .static_stiffness = spring_static_stiffness, .virgin_stiffness = spring_virgin_stiffness,
        .impact_indentation = spring_impact, .memory_outputs = no_memory, .rate_force = linear_force,
        .rate_curvature = linear_curvature, .force_guard = linear_guard, .elastic_energy = spring_energy},
    [VI_LAW_THORNTON] = {
        .name = "thornton", .elastic_force = thornton_load, .elastic_stiffness = thornton_load_stiffness,
        .plastic_force = thornton_load, .plastic_stiffness = thornton_load_stiffness, .contact_surface = johnson_contact,
        .elastic_stiffness_rate = thornton_load_stiffness_rate, .plastic_stiffness_rate = thornton_load_stiffness_rate,
        .memory_rates = johnson_memory_rates,
        .yield_surface = johnson_yield, .plastic_floor = johnson_plastic_floor, .freeze_plastic = johnson_freeze,
        .choose = johnson_choose, .mode_allowed = johnson_modes, .static_indentation = johnson_static_indentation,
        .static_stiffness = johnson_static_stiffness, .virgin_stiffness = thornton_load_stiffness,
        .impact_indentation = hertz_impact, .memory_outputs = johnson_memory, .virgin_indentation = thornton_indentation,
        .virgin_work = thornton_work, .unload_curve = thornton_unload, .unload_rates = thornton_unload_rates,
        .elastic_energy = thornton_work, .plastic_energy = johnson_plastic_energy},
};

/* The row of model's law (set up, or checked to be one of the three). */
/* A model not set up yet (law 0: an instance before initialization, or a state restored from
 * then) has no contact force and no memory: it is evaluated as Hertz with K = 0. */
static const law_fns *law(const vi_model_contact *c) { return &laws[c->law == 0 ? VI_LAW_HERTZ : c->law]; }

/* Johnson with a moving contact point leaves the plastic mode when it falls back below delta_Y;
 * every other plastic motion ends at a turning point (delta' = 0). */
static int plastic_ends_at_yield(const vi_model_contact *c) { return c->law == VI_LAW_JOHNSON && c->moving; }

/* ---- force, right-hand side, guards, events ------------------------------------------------------ */

int vi_model_uses_rate(const vi_model *model)
{
    int uses = 0;
    for (int i = 0; i < model->ncontacts; i++) {
        const vi_model_contact *c = &model->contact[i];
        uses |= c->law != VI_LAW_HERTZ && !plastic_ends_at_yield(c);
    }
    return uses;
}

/* The rate r = delta' = yC'(t) - v. */
static double indentation_rate(const vi_model *model, double t, const double x[2])
{
    double dyC;
    vi_model_platform(model, t, &dyC, NULL);
    return dyC - x[1];
}

/* Contact c's own indentation and rate: the lower contact's delta = x[0] and delta'; the upper
 * contact's -gap - delta and -delta'. side: +1 lower, -1 upper (the sign of its rate and its force on
 * the body). */
static double side(const vi_model_contact *c) { return c->upper ? -1.0 : 1.0; }
static double contact_indentation(const vi_model_contact *c, const double x[2]) { return c->upper ? -c->gap - x[0] : x[0]; }
static double contact_rate(const vi_model *model, const vi_model_contact *c, double t, const double x[2])
{
    double r = indentation_rate(model, t, x);
    return c->upper ? -r : r;
}
/* Put the state's delta where contact c's indentation is d. */
static void put_indentation(const vi_model_contact *c, double x[2], double d) { x[0] = c->upper ? -c->gap - d : d; }

/* The law's mode choice and plastic write-down on contact c's own indentation d (the upper contact:
 * on a copy, written back where the law moved it onto a surface; d is exactly the surface an event
 * snapped onto, which -gap - delta may miss by rounding). */
static int law_choose(vi_model_contact *c, double x[2], double d, const rates *q)
{
    if (!c->upper) return law(c)->choose(c, x, q);
    double xc[2] = {d, x[1]};
    int mode = law(c)->choose(c, xc, q);
    if (xc[0] != d) put_indentation(c, x, xc[0]);
    return mode;
}
static void law_freeze(vi_model_contact *c, double x[2])
{
    if (!c->upper) {
        law(c)->freeze_plastic(c, x);
        return;
    }
    double xc[2] = {contact_indentation(c, x), x[1]}, d = xc[0];
    law(c)->freeze_plastic(c, xc);
    if (xc[0] != d) put_indentation(c, x, xc[0]);
}

/* Is any contact in stick (the mass moves with the platform)? */
static int any_stick(const vi_model *model)
{
    int stick = 0;
    for (int i = 0; i < model->ncontacts; i++) stick |= model->contact[i].mode == VI_MODE_STICK;
    return stick;
}

/* Force and partials of contact c's rate-dependent law in mode elastic at (t, x); all zero in any other
 * case. */
static vi_law_force rate_force(const vi_model *model, const vi_model_contact *c, double t, const double x[2])
{
    const law_fns *L = law(c);
    if (c->mode != VI_MODE_ELASTIC || !L->rate_force) return (vi_law_force){0.0, 0.0, 0.0};
    return L->rate_force(c, contact_indentation(c, x), contact_rate(model, c, t, x));
}

/* Contact c's force [N] at (t, x) in its mode. */
static double contact_force(const vi_model *model, const vi_model_contact *c, double t, const double x[2])
{
    double d = contact_indentation(c, x);
    if (law(c)->rate_force) return rate_force(model, c, t, x).F;
    switch (c->mode) {
    case VI_MODE_ELASTIC: return law(c)->elastic_force(c, d);
    case VI_MODE_PLASTIC: return law(c)->plastic_force(c, d);
    case VI_MODE_UNLOAD: return vi_unload_force(&c->unload, d);
    case VI_MODE_STICK: return side(c) * hold_force(model, t);
    default: return 0.0;
    }
}

double vi_model_force(const vi_model *model, double t, const double x[2])
{
    return contact_force(model, vi_model_lower(model), t, x);
}

double vi_model_force_upper(const vi_model *model, double t, const double x[2])
{
    return model->ncontacts > 1 ? contact_force(model, &model->contact[VI_UPPER], t, x) : 0.0;
}

/* The contacts' force on the body [N], upwards: the lower contact's, less those of the others. */
static double body_force(const vi_model *model, double t, const double x[2])
{
    double F = contact_force(model, &model->contact[0], t, x);
    for (int i = 1; i < model->ncontacts; i++) F -= contact_force(model, &model->contact[i], t, x);
    return F;
}

void vi_model_rhs(const vi_model *model, double t, const double x[2], double dx[2])
{
    double dyC, ddyC;
    vi_model_platform(model, t, &dyC, &ddyC);
    if (any_stick(model)) { /* Filippov sliding on delta = delta_c: the mass moves with the platform */
        dx[0] = 0.0;
        dx[1] = ddyC;
        return;
    }
    dx[0] = dyC - x[1];
    dx[1] = (body_force(model, t, x) - net_load(model, t)) / model->body.m;
}

/* Contact c's stiffness dF/d(delta) [N/m] at (t, x) in its mode (0 free and in stick). */
static double contact_stiffness(const vi_model *model, const vi_model_contact *c, double t, const double x[2])
{
    if (law(c)->rate_force) return rate_force(model, c, t, x).dF_ddelta;
    double d = contact_indentation(c, x);
    switch (c->mode) {
    case VI_MODE_ELASTIC: return law(c)->elastic_stiffness(c, d);
    case VI_MODE_PLASTIC: return law(c)->plastic_stiffness(c, d);
    case VI_MODE_UNLOAD: return vi_unload_stiffness(&c->unload, d);
    default: return 0.0;
    }
}

void vi_model_contact_slopes(const vi_model *model, int i, double t, const double x[2], double *k, double *c)
{
    *k = *c = 0.0;
    if (i < 0 || i >= model->ncontacts) return;
    *k = contact_stiffness(model, &model->contact[i], t, x);
    *c = rate_force(model, &model->contact[i], t, x).dF_drate;
}

int vi_model_sticks(const vi_model *model) { return any_stick(model); }

double vi_model_stiffness_over_mass(const vi_model *model, double t, const double x[2])
{
    double k = contact_stiffness(model, &model->contact[0], t, x);
    for (int i = 1; i < model->ncontacts; i++) k += contact_stiffness(model, &model->contact[i], t, x);
    return k / model->body.m;
}

double vi_model_damping(const vi_model *model, double t, const double x[2])
{
    double c = rate_force(model, &model->contact[0], t, x).dF_drate;
    for (int i = 1; i < model->ncontacts; i++) c += rate_force(model, &model->contact[i], t, x).dF_drate;
    return c;
}

double vi_model_stiffness_rate(const vi_model *model, int i, double t, const double x[2], double *per_rate)
{
    *per_rate = 0.0;
    if (i < 0 || i >= model->ncontacts) return 0.0;
    const vi_model_contact *c = &model->contact[i];
    double d = contact_indentation(c, x);
    if (law(c)->rate_force) {
        if (c->mode != VI_MODE_ELASTIC) return 0.0;
        vi_law_curvature k = law(c)->rate_curvature(c, d, contact_rate(model, c, t, x));
        *per_rate = k.d2F_ddelta_drate;
        return k.d2F_ddelta2;
    }
    switch (c->mode) {
    case VI_MODE_ELASTIC: return law(c)->elastic_stiffness_rate(c, d);
    case VI_MODE_PLASTIC: return law(c)->plastic_stiffness_rate(c, d);
    case VI_MODE_UNLOAD: return vi_unload_stiffness_rate(&c->unload, d);
    default: return 0.0; /* free; stick, whose stiffness is that at delta_c */
    }
}

void vi_model_memory_rates(const vi_model *model, int i, const double x[2], vi_memory_rates *r)
{
    if (i < 0 || i >= model->ncontacts) {
        *r = (vi_memory_rates){0.0, 0.0, 0.0, 0.0, 0.0};
        return;
    }
    const vi_model_contact *c = &model->contact[i];
    law(c)->memory_rates(c, contact_indentation(c, x), r);
}

/* ---- energy (vi_model.h, ENERGY) --------------------------------------------------------------------- */

/* A plastic state below the memory written down (Model Exchange: an importer's state past a turning
 * point it has not located yet): delta below delta_c (Johnson and Thornton with a fixed contact point)
 * or below the LEPP yield surface. */
static int below_written(const vi_model_contact *c, double d)
{
    if (is_johnson_fixed(c)) return c->yielded && d < c->unload.delta_c;
    return law(c)->permanent_set && d < lepp_yield(c);
}

/* Contact c's elastic energy at its indentation d [J], and dE/dd into *k (per_delta: wanted). */
static double contact_energy(const vi_model_contact *c, double d, int per_delta, double *k_out)
{
    const law_fns *L = law(c);
    double E = 0.0, k = 0.0;
    vi_memory_rates r;
    if (L->rate_force) { /* the spring part, while the bodies overlap */
        E = L->elastic_energy(c, d), k = L->elastic_force(c, d);
    } else {
        switch (c->mode) {
        case VI_MODE_ELASTIC: E = L->elastic_energy(c, d), k = L->elastic_force(c, d); break;
        case VI_MODE_PLASTIC:
            if (below_written(c, d)) { /* past a turning point not located yet: as unloading from the memory */
                E = L->elastic_energy(c, d), k = L->elastic_force(c, d);
                if (is_johnson_fixed(c)) E = vi_unload_energy(&c->unload, d), k = vi_unload_force(&c->unload, d);
                break;
            }
            E = L->plastic_energy(c, d);
            if (per_delta) L->memory_rates(c, d, &r), k = L->plastic_force(c, d) - r.W_plastic;
            break;
        case VI_MODE_UNLOAD: E = vi_unload_energy(&c->unload, d), k = vi_unload_force(&c->unload, d); break;
        case VI_MODE_STICK: E = vi_unload_energy(&c->unload, c->unload.delta_c); break;
        default: break;
        }
    }
    *k_out = k;
    return E;
}

double vi_model_contact_energy(const vi_model *model, const double x[2], double *per_delta)
{
    double k, E = contact_energy(vi_model_lower(model), x[0], per_delta != NULL, &k);
    if (model->ncontacts > 1) { /* the upper contact: d(delta_u)/d(delta) = -1 */
        const vi_model_contact *c = &model->contact[VI_UPPER];
        double ku;
        E += contact_energy(c, contact_indentation(c, x), per_delta != NULL, &ku);
        k -= ku;
    }
    if (per_delta) *per_delta = k;
    return E;
}

/* The power the body puts into contact c at (t, x) [W]: its force times its indentation's rate. */
static double contact_power(const vi_model *model, const vi_model_contact *c, double t, const double x[2])
{
    if (c->mode == VI_MODE_FREE) return 0.0;
    double r = contact_rate(model, c, t, x);
    if (law(c)->rate_force)
        return c->mode == VI_MODE_ELASTIC ? law(c)->rate_force(c, contact_indentation(c, x), r).F * r : 0.0;
    return contact_force(model, c, t, x) * r;
}

double vi_model_contact_power(const vi_model *model, double t, const double x[2])
{
    double P = contact_power(model, vi_model_lower(model), t, x);
    if (model->ncontacts > 1) P += contact_power(model, &model->contact[VI_UPPER], t, x);
    return P;
}

int vi_model_touching(const vi_model *model)
{
    int touching = 0;
    for (int i = 0; i < model->ncontacts; i++) touching |= model->contact[i].mode != VI_MODE_FREE;
    return touching;
}

int vi_model_damps(const vi_model *model)
{
    int damps = 0;
    for (int i = 0; i < model->ncontacts; i++) damps |= law(&model->contact[i])->rate_force != NULL;
    return damps;
}

int vi_model_damping_root_at_onset(const vi_model *model)
{
    const vi_model_contact *c = vi_model_lower(model);
    return c->law == VI_LAW_HERTZ_DAMPED && c->damped.formula == VI_DAMP_EXACT;
}

int vi_model_damping_onset(const vi_model *model, const double x[2])
{
    int onset = x[0] == 0.0;
    if (model->ncontacts > 1) onset |= contact_indentation(&model->contact[VI_UPPER], x) == 0.0;
    return onset && vi_model_damping_root_at_onset(model);
}

/* Contact c's damping power at (t, x) with its partials in its own indentation and rate. */
static vi_model_power contact_damping_power(const vi_model *model, const vi_model_contact *c, double t, const double x[2])
{
    const law_fns *L = law(c);
    if (!L->rate_force) return (vi_model_power){0.0, 0.0, 0.0};
    double d = contact_indentation(c, x), r = contact_rate(model, c, t, x);
    double Fs = L->elastic_force(c, d), ks = L->elastic_stiffness(c, d);
    vi_law_force F = rate_force(model, c, t, x); /* 0 when free */
    return (vi_model_power){(F.F - Fs) * r, (F.dF_ddelta - ks) * r, F.dF_drate * r + F.F - Fs};
}

vi_model_power vi_model_damping_power(const vi_model *model, double t, const double x[2])
{
    vi_model_power P = contact_damping_power(model, vi_model_lower(model), t, x);
    if (model->ncontacts > 1) { /* the upper contact's indentation and rate are -delta and -delta' (plus -gap) */
        vi_model_power U = contact_damping_power(model, &model->contact[VI_UPPER], t, x);
        P.P += U.P, P.dP_ddelta -= U.dP_ddelta, P.dP_drate -= U.dP_drate;
    }
    return P;
}

double vi_model_force_rate(const vi_model *model, double t, const double x[2], const double dx[2], double *F)
{
    const vi_model_contact *c = vi_model_lower(model);
    const law_fns *L = law(c);
    double d = x[0], k = 0.0;
    *F = 0.0;
    if (c->mode == VI_MODE_FREE) return 0.0;
    if (c->mode == VI_MODE_STICK) return *F = hold_force(model, t), hold_force_rate(model, t);
    if (L->rate_force) { /* dF/dt = F_delta r + F_r r', r' = yC'' - v' */
        double y[4];
        platform(model, t, y);
        double r = y[1] - x[1];
        vi_law_force f = L->rate_force(c, d, r);
        *F = f.F;
        return f.dF_ddelta * r + f.dF_drate * (y[2] - (dx ? dx[1] : (f.F - net_load(model, t)) / model->body.m));
    }
    switch (c->mode) {
    case VI_MODE_ELASTIC: *F = L->elastic_force(c, d), k = L->elastic_stiffness(c, d); break;
    case VI_MODE_PLASTIC: *F = L->plastic_force(c, d), k = L->plastic_stiffness(c, d); break;
    default: *F = vi_unload_force(&c->unload, d), k = vi_unload_stiffness(&c->unload, d); break;
    }
    return k * (dx ? dx[0] : indentation_rate(model, t, x));
}

void vi_model_jacobian(const vi_model *model, double t, const double x[2], double j[4])
{
    int stick = any_stick(model);
    j[0] = 0.0, j[1] = stick ? 0.0 : -1.0;
    j[2] = vi_model_stiffness_over_mass(model, t, x); /* 0 in stick */
    j[3] = -vi_model_damping(model, t, x) / model->body.m; /* d(delta')/dv = -1 */
}

/* ---- the guards: one definition per mode (vi_model.h lists them), read by the guard values, the
 * state check, the events and the names ------------------------------------------------------------ */

/* How a guard is measured. A position guard is the distance of delta from a surface; the others vanish
 * with a rate or a force, and the state check holds their mode to a surface of delta all the same. */
typedef enum {
    GUARD_NONE,         /* not used: the value 1 */
    GUARD_ABOVE,        /* delta - surface: the mode lies above the surface */
    GUARD_BELOW,        /* surface - delta: the mode lies below it */
    GUARD_TURN,         /* delta' = yC' - v, a plastic motion's turning point; the mode lies above the surface */
    GUARD_ONSET,        /* damped laws, free: max(-delta, -g) (g the force guard); no surface to check */
    GUARD_RELEASE,      /* damped laws, elastic: the force guard g; no surface to check */
    GUARD_STICK_LOAD,   /* F_load(delta_c) - F_hold; the mode lies on the surface delta_c (above it) */
    GUARD_STICK_UNLOAD, /* F_hold - F_unload(delta_c); on the surface delta_c (below it) */
} guard_kind;

typedef struct {
    guard_kind kind;
    double surface; /* the surface of delta [m] an event snaps onto and the state check measures from */
    const char *name;
} guard_def;

/* The guards of `mode` for contact c's law and memory (any mode, also one the law does not have). */
static void mode_guards(const vi_model_contact *c, int mode, guard_def g[VI_CONTACT_NGUARDS])
{
    const law_fns *L = law(c);
    g[0] = g[1] = (guard_def){GUARD_NONE, INFINITY, "none"};
    switch (mode) {
    case VI_MODE_FREE: g[0] = (guard_def){L->force_guard ? GUARD_ONSET : GUARD_BELOW, L->contact_surface(c), "contact"}; break;
    case VI_MODE_ELASTIC: {
        double yield = L->yield_surface(c);
        g[0] = (guard_def){GUARD_ABOVE, L->contact_surface(c), "separation"};
        if (L->force_guard) g[1] = (guard_def){GUARD_RELEASE, yield, "release (the damped force reaches 0)"};
        else if (isfinite(yield)) g[1] = (guard_def){GUARD_BELOW, yield, "yield"};
        break;
    }
    case VI_MODE_PLASTIC:
        if (plastic_ends_at_yield(c)) g[0] = (guard_def){GUARD_ABOVE, L->yield_surface(c), "back below yield"};
        else g[0] = (guard_def){GUARD_TURN, L->plastic_floor(c), "the turning point (delta' = 0)"};
        break;
    case VI_MODE_UNLOAD:
        g[0] = (guard_def){GUARD_ABOVE, c->unload.delta_f, "separation"};
        g[1] = (guard_def){GUARD_BELOW, c->unload.delta_c, "reloading to delta_c"};
        break;
    case VI_MODE_STICK:
        g[0] = (guard_def){GUARD_STICK_LOAD, c->unload.delta_c, "the end of stick (plastic loading)"};
        g[1] = (guard_def){GUARD_STICK_UNLOAD, c->unload.delta_c, "the end of stick (unloading)"};
        break;
    default: break;
    }
}

/* The guard's time-free part, the signed distance of delta from its surface on the mode's side;
 * INFINITY for a guard with no surface to check. */
static double guard_distance(const guard_def *g, double d)
{
    switch (g->kind) {
    case GUARD_ABOVE:
    case GUARD_TURN:
    case GUARD_STICK_LOAD: return d - g->surface;
    case GUARD_BELOW:
    case GUARD_STICK_UNLOAD: return g->surface - d;
    default: return INFINITY;
    }
}

/* The length per unit of contact c's force guard: its value at rest at the yield indentation delta_Y
 * taken as delta_Y (1 where that is no finite positive number). The onset guard max(-delta, -L g)
 * (GUARD_ONSET) is then a length on both branches, so that its band (vi_hybrid.h), set where the force
 * guard's branch reaches zero at a release, is a band of the indentation where the next contact
 * crosses on the other branch: a band in the force guard's own units (newtons, or 1 for the
 * dimensionless guard) would hide a whole flight of a few micrometres. */
static double guard_length(const vi_model_contact *c)
{
    double d = c->johnson.delta_Y, L = d / fabs(law(c)->force_guard(c, d, 0.0).g);
    return isfinite(L) && L > 0.0 ? L : 1.0;
}

/* Contact c's guards in its mode at (t, x) into g[0 .. VI_CONTACT_NGUARDS - 1]. */
static void contact_guards(const vi_model *model, const vi_model_contact *c, double t, const double x[2], double *g)
{
    guard_def def[VI_CONTACT_NGUARDS];
    double d = contact_indentation(c, x), F_hold = 0.0;
    mode_guards(c, c->mode, def);
    if (def[0].kind == GUARD_STICK_LOAD) F_hold = side(c) * hold_force(model, t); /* both stick guards: once */
    for (int i = 0; i < VI_CONTACT_NGUARDS; i++) {
        switch (def[i].kind) {
        case GUARD_ABOVE:
        case GUARD_BELOW: g[i] = guard_distance(&def[i], d); break;
        case GUARD_TURN: g[i] = contact_rate(model, c, t, x); break;
        case GUARD_ONSET: g[i] = fmax(-d, -guard_length(c) * law(c)->force_guard(c, d, contact_rate(model, c, t, x)).g); break;
        case GUARD_RELEASE: g[i] = law(c)->force_guard(c, d, contact_rate(model, c, t, x)).g; break;
        case GUARD_STICK_LOAD: g[i] = vi_johnson_load(&c->johnson, def[i].surface) - F_hold; break;
        case GUARD_STICK_UNLOAD: g[i] = F_hold - vi_unload_force(&c->unload, def[i].surface); break;
        default: g[i] = 1.0; break; /* inactive */
        }
    }
}

void vi_model_guards(const vi_model *model, double t, const double x[2], double g[VI_NGUARDS])
{
    for (int i = 0; i < model->ncontacts; i++) contact_guards(model, &model->contact[i], t, x, g + i * VI_CONTACT_NGUARDS);
    for (int i = model->ncontacts * VI_CONTACT_NGUARDS; i < VI_NGUARDS; i++) g[i] = 1.0; /* contacts not in use */
}

const char *vi_model_guard_name(const vi_model *model, int mode, int guard)
{
    guard_def def[VI_CONTACT_NGUARDS];
    if (guard < 0 || guard >= model->ncontacts * VI_CONTACT_NGUARDS) return "none"; /* also a contact not in use */
    mode_guards(&model->contact[guard / VI_CONTACT_NGUARDS], mode, def);
    return def[guard % VI_CONTACT_NGUARDS].name;
}

int vi_model_guard_mode(const vi_model *model, int guard) { return model->contact[guard / VI_CONTACT_NGUARDS].mode; }

double vi_model_contact_indentation(const vi_model *model, int i, const double x[2])
{
    return contact_indentation(&model->contact[i], x);
}

void vi_model_freeze(vi_model *model, double t, double x[2])
{
    for (int i = 0; i < model->ncontacts; i++) {
        vi_model_contact *c = &model->contact[i];
        if (c->mode == VI_MODE_PLASTIC && law(c)->freeze_plastic) law_freeze(c, x);
        else if (c->mode == VI_MODE_STICK) vi_model_platform(model, t, &x[1], NULL);
    }
}

/* Choose contact c's mode at (t, x) with its indentation d (snap: the stick guard an event put on its
 * surface); a contact onset counts an impact. Returns the mode. */
static int resolve_at(vi_model *model, vi_model_contact *c, double t, double x[2], double d, int snap)
{
    double dyC, s = side(c);
    vi_model_platform(model, t, &dyC, NULL);
    rates q = {.r = s * (dyC - x[1]), .F_hold = s * hold_force(model, t), .j = s * hold_force_rate(model, t),
               .m = model->body.m, .snap = snap};
    int mode = law_choose(c, x, d, &q);
    if (c->mode == VI_MODE_FREE && mode != VI_MODE_FREE) c->n_impacts++;
    c->mode = mode;
    return mode;
}
static int resolve(vi_model *model, vi_model_contact *c, double t, double x[2], int snap)
{
    return resolve_at(model, c, t, x, contact_indentation(c, x), snap);
}

int vi_model_resolve(vi_model *model, double t, double x[2])
{
    for (int i = 0; i < model->ncontacts; i++) resolve(model, &model->contact[i], t, x, SNAP_NONE);
    return vi_model_mode(model);
}

/* At most this many ulp steps of v put the force guard on the side of the mode chosen (one or two do). */
#define VI_GUARD_NUDGES 64

/* A damped law's event: free, delta reached 0 (snapped onto 0: a new contact) or the force guard rose
 * again while delta > 0 (the state stays); in contact, the force guard fell through 0 while delta > 0:
 * the rate is put onto the guard's surface (g is linear in it), then on the side of the mode chosen,
 * so that the new mode starts with its guards >= 0. */
static int damped_event(vi_model *model, vi_model_contact *c, double t, double x[2])
{
    const law_fns *L = law(c);
    double s = side(c);
    if (c->mode == VI_MODE_FREE) {
        if (new_contact(c, contact_indentation(c, x), contact_rate(model, c, t, x))) put_indentation(c, x, 0.0); /* onto 0 */
        return resolve(model, c, t, x, SNAP_NONE);
    }
    vi_law_guard g = L->force_guard(c, contact_indentation(c, x), contact_rate(model, c, t, x));
    if (g.dg_drate > 0.0) x[1] += s * (g.g / g.dg_drate); /* r = s (yC' - v): a larger s v lowers g */
    int mode = resolve(model, c, t, x, SNAP_RELEASE);
    for (int i = 0; i < VI_GUARD_NUDGES; i++) {
        double gv = L->force_guard(c, contact_indentation(c, x), contact_rate(model, c, t, x)).g;
        if (mode == VI_MODE_ELASTIC ? gv >= 0.0 : gv <= 0.0) break;
        x[1] = nextafter(x[1], (mode == VI_MODE_ELASTIC) == (s > 0.0) ? -INFINITY : INFINITY);
    }
    return mode;
}

int vi_model_event(vi_model *model, double t, double x[2], int fired)
{
    guard_def def[VI_CONTACT_NGUARDS];
    vi_model_contact *c = &model->contact[fired / VI_CONTACT_NGUARDS];
    int local = fired % VI_CONTACT_NGUARDS;
    vi_model_freeze(model, t, x);
    mode_guards(c, c->mode, def);
    const guard_def *g = &def[local == 0 || def[1].kind == GUARD_NONE ? 0 : 1]; /* a mode with one guard: that one */
    switch (g->kind) {
    case GUARD_ABOVE:
    case GUARD_BELOW: put_indentation(c, x, g->surface); return resolve_at(model, c, t, x, g->surface, SNAP_NONE);
    case GUARD_TURN: vi_model_platform(model, t, &x[1], NULL); break; /* turning point: delta' = 0 */
    case GUARD_ONSET:
    case GUARD_RELEASE: return damped_event(model, c, t, x);
    case GUARD_STICK_LOAD:
    case GUARD_STICK_UNLOAD:
        put_indentation(c, x, g->surface);
        return resolve_at(model, c, t, x, g->surface, g->kind == GUARD_STICK_LOAD ? SNAP_LOAD : SNAP_UNLOAD);
    default: break;
    }
    return resolve(model, c, t, x, SNAP_NONE);
}

/* Contact c without memory, free (before the initial state). */
static void clear_contact(vi_model_contact *c)
{
    c->mode = VI_MODE_FREE;
    c->yielded = 0;
    c->unload = (vi_unload_curve){0};
    c->delta_p = 0.0;
    c->V_i = 0.0;
}

void vi_model_initial_state(vi_model *model, int init, double v0, double t0, double x[2])
{
    vi_model_contact *c = &model->contact[VI_LOWER];
    double W0 = net_load(model, t0);
    model->f_contact = sqrt(W0 > 0.0 ? law(c)->static_stiffness(c, W0) / model->body.m : 0.0) / (2.0 * VI_PI);
    for (int i = 0; i < model->ncontacts; i++) clear_contact(&model->contact[i]);
    x[0] = 0.0;
    x[1] = v0;
    if (init == VI_INIT_STATIC) { /* at rest on the lower contact */
        double d = W0 > 0.0 ? law(c)->static_indentation(c, W0) : 0.0;
        if (is_johnson_fixed(c) && d > c->johnson.delta_Y) { /* plastically pre-loaded */
            c->yielded = 1;
            c->unload = law(c)->unload_curve(c, d);
        }
        x[0] = d;
        vi_model_platform(model, t0, &x[1], NULL);
    }
    vi_model_resolve(model, t0, x);
    for (int i = 0; i < model->ncontacts; i++) model->contact[i].n_impacts = 0;
}

void vi_model_scales(const vi_model *model, const double x0[2], double *L, double *V)
{
    const vi_model_contact *c = vi_model_lower(model);
    double W = net_load(model, model->t0), dyC, l = 0.0;
    vi_model_platform(model, model->t0, &dyC, NULL);
    if (W > 0.0) l = fmax(l, law(c)->static_indentation(c, W));
    if (isfinite(law(c)->yield_surface(c))) l = fmax(l, c->johnson.delta_Y);
    double v = fabs(dyC - x0[1]);
    if (!(l > 0.0 || v > 0.0)) /* only the excitation moves anything: harmonic and rolling */
        v = fabs(model->a) * model->omega + (model->profile ? fabs(model->V) * vi_profile_max_slope(model->profile) : 0.0);
    if (v > 0.0 && isfinite(v)) {
        double dv = law(c)->impact_indentation(c, model->body.m, v);
        if (isfinite(dv)) l = fmax(l, dv);
    }
    if (!(l > 0.0)) l = VI_SCALE_FALLBACK * c->johnson.R_star;
    *L = l;
    *V = l * (sqrt(law(c)->virgin_stiffness(c, l)) / sqrt(model->body.m));
}

/* ---- validity ------------------------------------------------------------------------------ */

/* The indentation the range of validity looks at: contact c's own in contact, or its largest one
 * delta_c. */
static double contact_validity_indentation(const vi_model_contact *c, const double x[2])
{
    double d = c->mode == VI_MODE_FREE ? 0.0 : contact_indentation(c, x), dc = c->yielded ? c->unload.delta_c : 0.0;
    return dc > d || d != d ? dc : d; /* fmax */
}
/* The larger of the contacts' (the same material on both sides). */
static double validity_indentation(const vi_model *model, const double x[2])
{
    double d = contact_validity_indentation(vi_model_lower(model), x);
    if (model->ncontacts > 1) d = fmax(d, contact_validity_indentation(&model->contact[VI_UPPER], x));
    return d;
}

int vi_model_indentation_invalid(const vi_model *model, const double x[2])
{
    const vi_model_contact *c = vi_model_lower(model);
    return validity_indentation(model, x) > VI_VALIDITY_RADIUS * VI_VALIDITY_RADIUS * c->johnson.R_star;
}

int vi_model_validity(const vi_model *model, double R1, double t, const double x[2], int skip, char *msg, size_t n)
{
    const vi_model_contact *c = vi_model_lower(model);
    double R = c->johnson.R_star, limit = VI_VALIDITY_RADIUS * VI_VALIDITY_RADIUS * R, d = validity_indentation(model, x);
    if (!(skip & VI_INVALID_INDENTATION) && d > limit) {
        vi_snprintf(msg, n, "t = %.17g s: the indentation %g m exceeds %g R* = %g m (contact radius sqrt(R* delta) = %g m "
                    "> %g R*): the contact laws (paper eqs. 2-4) assume a contact radius small against R*, so the "
                    "results leave the model's range of validity", t, d, VI_VALIDITY_RADIUS * VI_VALIDITY_RADIUS, limit,
                    sqrt(R * d), VI_VALIDITY_RADIUS);
        return VI_INVALID_INDENTATION;
    }
    if (!(skip & VI_INVALID_AMPLITUDE) && fabs(model->a) > R) {
        vi_snprintf(msg, n, "t = %.17g s: the excitation amplitude a = %g m exceeds R* = %g m: the contact laws (paper "
                    "eqs. 2-4) describe a local contact, with every displacement small against R*, so the results "
                    "leave the model's range of validity", t, model->a, R);
        return VI_INVALID_AMPLITUDE;
    }
    if (!(skip & VI_INVALID_ENERGY) && johnson_makes_energy(c, t, msg, n)) return VI_INVALID_ENERGY;
    double span = model->profile ? vi_profile_height_span(model->profile) : 0.0;
    if (!(skip & VI_INVALID_PROFILE) && span > R1) {
        vi_snprintf(msg, n, "t = %.17g s: the heights of profile_file span %g m, more than the rolling radius R1 = %g m: "
                    "rolling over a profile (paper Fig. 1b) assumes a roughness small against the wheel, so the results "
                    "leave the model's range of validity", t, span, R1);
        return VI_INVALID_PROFILE;
    }
    return 0;
}

double vi_model_force_limit(const vi_model *model)
{
    const vi_model_contact *c = vi_model_lower(model);
    switch (c->law) {
    case VI_LAW_HERTZ:
    case VI_LAW_HERTZ_DAMPED: return c->johnson.F_Y;
    case VI_LAW_JOHNSON: return VI_JOHNSON_FP * c->johnson.F_Y;
    default: return INFINITY;
    }
}

int vi_model_force_validity(const vi_model *model, double F_max, double t, char *msg, size_t n)
{
    const vi_model_contact *c = vi_model_lower(model);
    double F_Y = c->johnson.F_Y, limit = vi_model_force_limit(model);
    if (!(F_max > limit)) return 0;
    if (c->law == VI_LAW_JOHNSON)
        vi_snprintf(msg, n, "t = %.17g s: the contact force reached %g N = %.4g F_Y (F_Y = %g N), beyond F_p = %g F_Y: "
                    "Johnson's loading curve (paper eq. 3) holds for F_Y < F < F_p, a plastic zone contained by elastic "
                    "material (beyond, full plastic flow: contact_model = lepp), so the results leave the model's range "
                    "of validity", t, F_max, F_max / F_Y, F_Y, VI_JOHNSON_FP);
    else
        vi_snprintf(msg, n, "t = %.17g s: the contact force reached %g N = %.4g F_Y (F_Y = %g N): Hertz's law "
                    "(paper eq. 2) assumes purely elastic strains, which end at F_Y (contact_model = johnson or "
                    "thornton follow the yield), so the results leave the model's range of validity",
                    t, F_max, F_max / F_Y, F_Y);
    return VI_INVALID_FORCE;
}

/* A published damping form whose restitution misses e_restitution by more than this is named in a warning. */
#define VI_PUBLISHED_E_TOL 0.01

int vi_model_option_warnings(const vi_model_params *p, char *msg, size_t n)
{
    int count = 0, johnson = p->law == VI_LAW_JOHNSON;
    size_t used = 0;
    msg[0] = '\0';
#define OPTION(cond, text)                                                               \
    if (cond) {                                                                          \
        int k = vi_snprintf(msg + used, used < n ? n - used : 0, "%s" text, count ? "; " : ""); \
        used += k > 0 ? (size_t)k : 0;                                                   \
        count++;                                                                         \
    }
    OPTION(p->moving_contact && !johnson, "moving_contact = true is ignored: only the Johnson law has a moving contact point")
    OPTION(p->unloading == VI_UNLOAD_CONTINUOUS && !(johnson && !p->moving_contact),
           "unloading = continuous is ignored: only Johnson with a fixed contact point unloads on eq. 4")
    OPTION(p->yield_formula == VI_YIELD_PRINTED &&
               (p->law == VI_LAW_HERTZ || p->law == VI_LAW_HERTZ_DAMPED || p->law == VI_LAW_LINEAR),
           "yield_formula = printed is ignored by the laws without yield (it changes only the calculated F_Y, delta_Y)")
    OPTION(p->damping_formula != VI_DAMP_EXACT && p->law != VI_LAW_HERTZ_DAMPED,
           "damping_formula is ignored: only contact_model = hertz_damped damps by a formula")
    if (p->law == VI_LAW_HERTZ_DAMPED && p->damping_formula != VI_DAMP_EXACT) {
        double ea = vi_damping_restitution(vi_damping_chi(p->damping_formula, p->e_restitution));
        if (fabs(ea - p->e_restitution) > VI_PUBLISHED_E_TOL) {
            int k = vi_snprintf(msg + used, used < n ? n - used : 0, "%sdamping_formula = %d gives an isolated impact "
                                "the restitution %.4f, not e_restitution = %g (its formula holds near e = 1; "
                                "damping_formula = exact gives e_restitution at every speed)", count ? "; " : "",
                                p->damping_formula, ea, p->e_restitution);
            used += k > 0 ? (size_t)k : 0;
            count++;
        }
    }
    OPTION(p->v0 != 0.0 && p->init == VI_INIT_STATIC, "v0 is ignored by a static start (init = static)")
    OPTION(!p->has_profile && (p->V != 0.0 || p->x0 != 0.0 || p->profile_periodic),
           "V, x0 and profile_periodic are ignored without a profile_file")
    OPTION(!p->has_profile && p->profile_interpolation == VI_PROFILE_CUBIC,
           "profile_interpolation = cubic is ignored without a profile_file")
#undef OPTION
    return count;
}

/* ---- validity of a saved model (doc/model.md section 7.6) ---------------------------------- */


/* a and b agree to rel relative to the larger (both finite). */
static int close_rel(double a, double b, double rel) { return fabs(a - b) <= rel * fmax(fabs(a), fabs(b)); }

#define CONSISTENCY_TOL 1e-9

/* A list of named constants: each finite, and > 0 where `positive`. */
typedef struct {
    const char *name;
    double value;
    int positive;
} named_constant;

static int check_named(const named_constant *c, size_t count, char *msg, size_t n)
{
    for (size_t i = 0; i < count; i++) {
        if (!isfinite(c[i].value)) VI_FAIL(msg, n, "model constant %s = %g is not finite", c[i].name, c[i].value);
        if (c[i].positive && !(c[i].value > 0.0))
            VI_FAIL(msg, n, "model constant %s = %g is not positive", c[i].name, c[i].value);
    }
    return 0;
}

/* Contact c's constants: finite, positive, and consistent with each other. */
static int check_contact_constants(const vi_model_contact *c, char *msg, size_t n)
{
    const vi_johnson *J = &c->johnson;
    const named_constant k[] = {{"K", c->K, 1},        {"E_star", J->E_star, 1},   {"R_star", J->R_star, 1},
                                {"theta_Y", J->theta_Y, 1}, {"F_Y", J->F_Y, 1}, {"delta_Y", J->delta_Y, 1},
                                {"k_lin", c->k_lin, 1}};
    if (check_named(k, sizeof k / sizeof k[0], msg, n) < 0) return -1;
    if (!close_rel(c->K, vi_hertz_constant(J->E_star, J->R_star), CONSISTENCY_TOL))
        VI_FAIL(msg, n, "model constant K = %g does not match 4/3 E* sqrt(R*)", c->K);
    if (!close_rel(J->F_Y, vi_hertz_force(c->K, J->delta_Y), CONSISTENCY_TOL))
        VI_FAIL(msg, n, "model constant delta_Y = %g does not match F_Y = K delta_Y^1.5", J->delta_Y);
    if (!close_rel(c->k_lin, J->F_Y / J->delta_Y, CONSISTENCY_TOL))
        VI_FAIL(msg, n, "model constant k_lin = %g does not match F_Y/delta_Y", c->k_lin);
    return 0;
}

/* The body's, the contacts' and the platform's constants, and the inputs' ramps. */
static int check_constants(const vi_model *model, char *msg, size_t n)
{
    const named_constant body[] = {{"m", model->body.m, 1}, {"W0", model->body.W0, 0}};
    const named_constant platform[] = {{"a", model->a, 0},         {"omega", model->omega, 0}, {"t0", model->t0, 0},
                                       {"phi0", model->phi0, 0},   {"t_phi", model->t_phi, 0}, {"V", model->V, 0},
                                       {"x0", model->x0, 0},       {"f_contact", model->f_contact, 0}};
    if (check_named(body, sizeof body / sizeof body[0], msg, n) < 0) return -1;
    for (int i = 0; i < model->ncontacts; i++)
        if (check_contact_constants(&model->contact[i], msg, n) < 0) return -1;
    if (check_named(platform, sizeof platform / sizeof platform[0], msg, n) < 0) return -1;
    if (model->omega < 0.0) VI_FAIL(msg, n, "model constant omega = %g is negative", model->omega);
    if (model->f_contact < 0.0) VI_FAIL(msg, n, "model constant f_contact = %g is negative", model->f_contact);
    const vi_ramp *r[2] = {&model->yC_in, &model->F_ext};
    const char *rn[2] = {"yC_in", "F_ext"};
    for (int i = 0; i < 2; i++)
        if (!isfinite(r[i]->u) || !isfinite(r[i]->du) || !isfinite(r[i]->t))
            VI_FAIL(msg, n, "model input ramp %s (%g, %g, %g) is not finite", rn[i], r[i]->u, r[i]->du, r[i]->t);
    return 0;
}

static int check_memory(const vi_model_contact *c, char *msg, size_t n)
{
    if (c->yielded != 0 && c->yielded != 1) VI_FAIL(msg, n, "model flag yielded = %d is not 0 or 1", c->yielded);
    if (c->n_impacts < 0) VI_FAIL(msg, n, "n_impacts = %ld is negative", c->n_impacts);
    if (!isfinite(c->delta_p)) VI_FAIL(msg, n, "delta_p = %g is not finite", c->delta_p);
    if (!(c->V_i >= 0.0 && isfinite(c->V_i))) VI_FAIL(msg, n, "V_i = %g is not finite and >= 0", c->V_i);
    const double dc[5] = {c->damped.alpha_c, c->damped.chi, c->damped.K, c->linear.k, c->linear.c};
    for (int i = 0; i < 5; i++)
        if (!(dc[i] >= 0.0 && isfinite(dc[i])))
            VI_FAIL(msg, n, "a damping constant (alpha_c %g, chi %g, K %g, k %g, c %g) is not finite and >= 0", dc[0], dc[1],
                    dc[2], dc[3], dc[4]);
    if (law(c)->permanent_set ? c->delta_p < 0.0 : c->delta_p != 0.0)
        VI_FAIL(msg, n, "delta_p = %g is impossible for contact_model %s", c->delta_p, law(c)->name);
    const vi_unload_curve *U = &c->unload;
    const double u[5] = {U->delta_c, U->Rbar, U->delta_r, U->delta_f, U->Kbar};
    if (!c->yielded) {
        for (int i = 0; i < 5; i++)
            if (u[i] != 0.0)
                VI_FAIL(msg, n, "unloading curve (delta_c = %g, Rbar = %g) present although yielded = 0", u[0], u[1]);
        return 0;
    }
    if (!is_johnson_fixed(c))
        VI_FAIL(msg, n, "yielded = 1 is impossible for contact_model %s (moving %d)", law(c)->name, c->moving);
    for (int i = 0; i < 5; i++)
        if (!isfinite(u[i]))
            VI_FAIL(msg, n, "unloading curve: a value (delta_c %g, Rbar %g, delta_r %g, delta_f %g, Kbar %g) is not "
                    "finite", u[0], u[1], u[2], u[3], u[4]);
    if (!(U->delta_c >= c->johnson.delta_Y * (1.0 - CONSISTENCY_TOL)))
        VI_FAIL(msg, n, "delta_c = %g is below delta_Y = %g", U->delta_c, c->johnson.delta_Y);
    if (!(U->Rbar > 0.0)) VI_FAIL(msg, n, "Rbar = %g is not positive", U->Rbar);
    if (!(U->delta_f <= U->delta_c)) VI_FAIL(msg, n, "delta_f = %g is above delta_c = %g", U->delta_f, U->delta_c);
    vi_unload_curve E = law(c)->unload_curve(c, U->delta_c);
    if (!close_rel(U->Rbar, E.Rbar, CONSISTENCY_TOL))
        VI_FAIL(msg, n, "Rbar = %g does not belong to delta_c (%g)", U->Rbar, E.Rbar);
    if (!close_rel(U->delta_r, E.delta_r, CONSISTENCY_TOL))
        VI_FAIL(msg, n, "delta_r = %g does not belong to delta_c (%g)", U->delta_r, E.delta_r);
    if (!(fabs(U->delta_f - E.delta_f) <= CONSISTENCY_TOL * U->delta_c))
        VI_FAIL(msg, n, "delta_f = %g does not belong to delta_c (%g)", U->delta_f, E.delta_f);
    if (!close_rel(U->Kbar, E.Kbar, CONSISTENCY_TOL))
        VI_FAIL(msg, n, "Kbar = %g does not belong to Rbar (%g)", U->Kbar, E.Kbar);
    return 0;
}

/* The mode is allowed for the law and the memory, and (surfaces) no guard's distance from its surface
 * (mode_guards) is clearly negative. */
static int check_mode(const vi_model_contact *c, const double x[2], int surfaces, char *msg, size_t n)
{
    const law_fns *L = law(c);
    int mode = c->mode;
    if (!L->mode_allowed(c, mode))
        VI_FAIL(msg, n, "mode = %d is impossible for contact_model %s (moving %d, unloading %d, yielded %d)", mode,
                L->name, c->moving, c->unloading, c->yielded);
    if (!surfaces) return 0;
    double d = contact_indentation(c, x), tol = VI_CHECK_GUARD_TOL * fmax(fmax(c->johnson.delta_Y, fabs(d)), fabs(c->unload.delta_c));
    guard_def def[VI_CONTACT_NGUARDS];
    mode_guards(c, mode, def);
    for (int i = 0; i < VI_CONTACT_NGUARDS; i++) {
        double g = guard_distance(&def[i], d);
        if (g < -tol)
            VI_FAIL(msg, n, "mode %d does not fit the state: delta = %.17g m lies %g m beyond its surface %d "
                    "(tolerance %g m)", mode, d, -g, i, tol);
    }
    return 0;
}

/* Contact c's enumerations and flags. */
static int check_flags(const vi_model_contact *c, char *msg, size_t n)
{
    if (c->law < VI_LAW_HERTZ || c->law > VI_LAW_THORNTON)
        VI_FAIL(msg, n, "contact law = %d is not one of %d (hertz) ... %d (thornton)", c->law, VI_LAW_HERTZ,
                VI_LAW_THORNTON);
    if (c->moving != 0 && c->moving != 1) VI_FAIL(msg, n, "model flag moving = %d is not 0 or 1", c->moving);
    if (c->unloading != VI_UNLOAD_PAPER && c->unloading != VI_UNLOAD_CONTINUOUS)
        VI_FAIL(msg, n, "unloading = %d is not paper (%d) or continuous (%d)", c->unloading, VI_UNLOAD_PAPER,
                VI_UNLOAD_CONTINUOUS);
    if (c->mode < VI_MODE_FREE || c->mode > VI_MODE_STICK)
        VI_FAIL(msg, n, "mode = %d is not in %d..%d", c->mode, VI_MODE_FREE, VI_MODE_STICK);
    return 0;
}

/* A model never set up (law 0): every contact without a discrete state. */
static int check_not_set_up(const vi_model *model, char *msg, size_t n)
{
    for (int i = 0; i < VI_NCONTACTS; i++) {
        const vi_model_contact *c = &model->contact[i];
        if (c->mode != 0 || c->yielded != 0 || c->n_impacts != 0 || c->delta_p != 0.0)
            VI_FAIL(msg, n, "model not set up (law = 0) but with a discrete state (mode %d)", c->mode);
    }
    return 0;
}

/* A contact not in use: every field zero (its side aside). */
static int contact_blank(const vi_model_contact *c)
{
    const vi_unload_curve *U = &c->unload;
    const vi_johnson *J = &c->johnson;
    const double d[] = {c->gap, c->K, J->E_star, J->R_star, J->theta_Y, J->F_Y, J->delta_Y, c->k_lin,
                        c->damped.alpha_c, c->damped.chi, c->damped.K, c->linear.k, c->linear.c, U->delta_c,
                        U->Rbar, U->delta_r, U->delta_f, U->Kbar, c->delta_p, c->V_i};
    int blank = c->law == 0 && c->moving == 0 && c->unloading == 0 && c->mode == 0 && c->yielded == 0 &&
                c->n_impacts == 0 && c->damped.formula == 0;
    for (size_t i = 0; i < sizeof d / sizeof d[0]; i++) blank &= d[i] == 0.0;
    return blank;
}

/* The list of contacts: one or two in use, the upper one with its clearance > 0, the others zero. */
static int check_list(const vi_model *model, char *msg, size_t n)
{
    if (model->ncontacts != 1 && model->ncontacts != 2) VI_FAIL(msg, n, "ncontacts = %d is not 1 or 2", model->ncontacts);
    const vi_model_contact *lower = &model->contact[VI_LOWER], *upper = &model->contact[VI_UPPER];
    if (lower->upper != 0 || lower->gap != 0.0 || upper->upper != 1)
        VI_FAIL(msg, n, "the contacts' sides (lower %d, upper %d) are not lower and upper", lower->upper, upper->upper);
    if (model->ncontacts == 2 && !(upper->gap > 0.0 && isfinite(upper->gap)))
        VI_FAIL(msg, n, "gap = %g m of the upper contact is not finite and > 0", upper->gap);
    if (model->ncontacts == 1 && !contact_blank(upper))
        VI_FAIL(msg, n, "the upper contact is not in use but has a state (law %d, mode %d, gap %g m)", upper->law,
                upper->mode, upper->gap);
    return 0;
}

static int check(const vi_model *model, const double x[2], int surfaces, char *msg, size_t n)
{
    if (!isfinite(x[0]) || !isfinite(x[1])) VI_FAIL(msg, n, "state (delta %g, v %g) is not finite", x[0], x[1]);
    if (vi_model_lower(model)->law == 0) return check_not_set_up(model, msg, n); /* never set up */
    if (check_list(model, msg, n) < 0) return -1;
    for (int i = 0; i < model->ncontacts; i++)
        if (check_flags(&model->contact[i], msg, n) < 0) return -1;
    if (check_constants(model, msg, n) < 0) return -1;
    for (int i = 0; i < model->ncontacts; i++)
        if (check_memory(&model->contact[i], msg, n) < 0) return -1;
    for (int i = 0; i < model->ncontacts; i++)
        if (check_mode(&model->contact[i], x, surfaces, msg, n) < 0) return -1;
    return 0;
}

int vi_model_check(const vi_model *model, const double x[2], char *msg, size_t n) { return check(model, x, 1, msg, n); }
int vi_model_check_between_events(const vi_model *model, const double x[2], char *msg, size_t n)
{
    return check(model, x, 0, msg, n);
}

void vi_model_calculated(const vi_model *model, vi_model_values *out)
{
    const vi_model_contact *c = vi_model_lower(model);
    out->E_star = c->johnson.E_star;
    out->R_star = c->johnson.R_star;
    out->F_Y = c->johnson.F_Y;
    out->delta_Y = c->johnson.delta_Y;
    out->k_lin = c->k_lin;
    out->f_contact = model->f_contact;
}

/* The upper contact's outputs of `groups` (all 0 without an upper contact). */
static void upper_outputs(const vi_model *model, double t, const double x[2], unsigned groups, vi_model_values *out)
{
    const vi_model_contact *c = &model->contact[VI_UPPER];
    int on = model->ncontacts > 1;
    if (groups & VI_OUT_STATE) {
        out->delta_upper = on ? contact_indentation(c, x) : 0.0;
        out->mode_upper = on ? c->mode : VI_MODE_FREE;
        out->n_impacts_upper = on ? (int)c->n_impacts : 0;
    }
    if (groups & VI_OUT_FORCE) out->F_upper = on ? contact_force(model, c, t, x) : 0.0;
    if (groups & VI_OUT_MEMORY) {
        vi_model_values m = {.W_plastic = 0.0};
        if (on) law(c)->memory_outputs(c, contact_indentation(c, x), &m);
        out->W_plastic_upper = m.W_plastic;
    }
}

void vi_model_outputs(const vi_model *model, double t, const double x[2], unsigned groups, vi_model_values *out)
{
    const vi_model_contact *c = vi_model_lower(model);
    double d = x[0];
    if (groups & VI_OUT_STATE) {
        out->delta = d;
        out->v = x[1];
        out->contact = c->mode != VI_MODE_FREE;
        out->mode = c->mode;
        out->n_impacts = (int)c->n_impacts;
    }
    if (groups & VI_OUT_PLATFORM) {
        out->yC = vi_model_platform(model, t, NULL, NULL);
        out->y = out->yC - d;
    }
    if (groups & VI_OUT_FORCE) out->F = vi_model_force(model, t, x);
    if (groups & VI_OUT_CALCULATED) vi_model_calculated(model, out);
    upper_outputs(model, t, x, groups, out);
    if (!(groups & VI_OUT_MEMORY)) return;
    out->delta_c = out->delta_f = out->delta_p = out->W_plastic = 0.0;
    out->Rbar = c->johnson.R_star;
    law(c)->memory_outputs(c, d, out);
    out->E_contact = vi_model_contact_energy(model, x, NULL);
}
