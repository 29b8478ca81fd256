/*
 * vi_model.h - the hybrid model of a mass pressed onto a vibrating platform (no solver, no FMI).
 *
 * The model is a body (vi_body: the mass, its load, its state y, v) on a platform, and a list of
 * contacts (vi_model_contact: each with its law, the law's parameters, its memory, its mode and its
 * guards): the lower contact, the body on the platform, and with upper_stop the upper contact, the
 * body under a second surface at yC + gap that moves with the platform. The force on the body is the
 * lower contact's less the upper one's; the outputs (F, mode, the memory) are the lower contact's,
 * the upper one's F_upper, delta_upper, mode_upper, n_impacts_upper, and E_contact both. The laws themselves are pure functions (vi_contact.h, vi_laws.h).
 *
 * Continuous state x = (delta, v): indentation delta = yC - y [m] and mass velocity v [m/s]
 * (the indentation, not y, is integrated: it stays exact when yC carries a large offset).
 *
 *   delta' = yC'(t) - v
 *   v'     = (F(delta, mode, memory) - W(t)) / m,     W(t) = P + m g - F_ext(t)  (net load down)
 *   yC(t)  = yC_in(t) + a (cos(phi(t)) - 1) + yb(x0 + V (t - t0)),   phi(t) = phi0 + 2 pi f (t - t_phi)
 *            (phi0 = 0, t_phi = t0 the start time; a and f are tunable: when f changes at t1 the
 *            phase goes on from phi(t1) at the new rate, so phi and yC stay continuous)
 *
 *            yb: rolling over a profile (paper Fig. 1b, vi_profile.h), 0 without one; x0 is the position
 *            on the profile at the start time t0, V the rolling speed. Where yb has a kink yC' jumps:
 *            vi_model_next_breakpoint gives the time, and the loop restarts there (vi_model_breakpoint).
 * Inputs are ramps over a communication step: u(t) = u + du (t - t_u) (du = 0: zero-order hold).
 *
 * Modes (output `mode`): 0 free, 1 elastic on the virgin curve (Hertz, Johnson and Thornton below
 * delta_Y, LEPP spring, the damped laws), 2 plastic (Johnson and Thornton virgin loading beyond
 * delta_Y; LEPP flow at F_Y; with a moving contact point: above delta_Y either way), 3 elastic
 * unload/reload (Johnson eq. 4, Thornton), 4 stick (Johnson paper unloading: Filippov sliding at a
 * turning point, F = F_hold = W + m yC''). The damped laws (hertz_damped, linear; vi_laws.h) have
 * modes 0 and 1 only, with a force that depends on delta' as well.
 *
 * Each mode of a contact has up to VI_CONTACT_NGUARDS guard functions g >= 0 (the model's
 * VI_NGUARDS are those of all its contacts, contact by contact); the mode is left when a guard falls
 * through zero (CVODE root direction -1 for all). vi_model.c defines each mode's guards once
 * (mode_guards: how each is measured and the surface of delta it belongs to), and the guard values,
 * the state check (vi_model_check), the events and the guard names all read that definition:
 *   0: g0 = s - delta                  contact (s = 0, delta_f or delta_p)
 *      g0 = max(-delta, -L g)          contact of a damped law (g: vi_*_guard, the sign of its force;
 *                                      L = delta_Y / g(delta_Y, 0): both branches lengths)
 *   1: g0 = delta - s                  separation
 *      g1 = delta_Y - delta            yield (Johnson), delta_p + delta_Y - delta (LEPP)
 *      g1 = g                          release of a damped law: its force reaches 0 while delta > 0
 *   2: g0 = delta'                     turning point (Johnson, LEPP)
 *      g0 = delta - delta_Y            back below yield (Johnson, moving contact point)
 *   3: g0 = delta - delta_f            separation
 *      g1 = delta_c - delta            reloading reaches delta_c
 *   4: g0 = F_load(delta_c) - F_hold   plastic loading resumes
 *      g1 = F_hold - F_unload(delta_c) unloading starts
 * At an event the state is snapped onto the surface that was reached, and the next mode is chosen
 * from the sign of the first nonzero of (position, rate, acceleration, jerk) relative to each
 * surface (vi_model_resolve). With delta' = 0 the acceleration of delta is (F_hold - F)/m and its
 * jerk F_hold'/m, F_hold' = -F_ext' + m yC''': a tie of the holding force with a force of the law
 * is broken by its rate. The stick guards are in force, not state, so they cannot be snapped: a
 * stick guard that fired counts as exactly zero in the choice that follows.
 */
#ifndef VI_MODEL_H
#define VI_MODEL_H

#include <stddef.h>

#include "vi_contact.h"
#include "vi_laws.h"
#include "vi_profile.h"

#define VI_CONTACT_NGUARDS 2

/* Contact laws, modes (doc/model.md section 3) and initial states; the FMU's enumerations
 * ContactModel, Mode and Init have these values. */
enum { VI_LAW_HERTZ = 1, VI_LAW_JOHNSON = 2, VI_LAW_LEPP = 3, VI_LAW_HERTZ_DAMPED = 4, VI_LAW_LINEAR = 5, VI_LAW_THORNTON = 6 };
enum { VI_MODE_FREE = 0, VI_MODE_ELASTIC = 1, VI_MODE_PLASTIC = 2, VI_MODE_UNLOAD = 3, VI_MODE_STICK = 4 };
enum { VI_INIT_STATIC = 1, VI_INIT_TOUCHING = 2 };

/* The parameters the model is set up from. */
typedef struct {
    double m, P, g;             /* mass [kg], pressing load [N], gravity [m/s2] */
    double R1, R2, E1, E2;      /* radii [m] (0: plane), Young's moduli [Pa] */
    double nu1, nu2, Y, theta_Y; /* Poisson's ratios, yield stress [Pa], limiting mean pressure factor */
    int law;                    /* VI_LAW_* */
    int moving_contact;         /* Johnson with a moving contact point */
    int unloading;              /* VI_UNLOAD_* */
    int yield_formula;          /* VI_YIELD_* */
    int init;                   /* VI_INIT_* */
    double v0;                  /* initial velocity when touching [m/s] */
    double a, f;                /* harmonic excitation: amplitude [m], frequency [Hz] */
    int has_profile;            /* a profile is rolled over (vi_model_set_rolling) */
    double V, x0;               /* rolling speed [m/s], position on the profile at the start [m] */
    int profile_periodic;
    int profile_interpolation;  /* VI_PROFILE_LINEAR or VI_PROFILE_CUBIC (vi_profile.h) */
    double e_restitution;       /* damped Hertz, linear: restitution of an isolated impact, (0, 1] */
    int damping_formula;        /* damped Hertz: VI_DAMP_* (vi_laws.h) */
    double k_spring;            /* linear: spring stiffness [N/m] */
    int upper_stop;             /* a second surface at yC + gap above the mass (the upper contact) */
    double gap;                 /* its clearance [m], > 0 with upper_stop */
} vi_model_params;

/* The model's outputs and calculated parameters (doc/model.md section 5). */
typedef struct {
    double F, delta, y, v, yC;  /* N, m, m, m/s, m */
    int contact, mode, n_impacts;
    double delta_c, delta_f, delta_p, Rbar, W_plastic; /* m, m, m, m, J */
    double E_contact;           /* J (vi_model_contact_energy) */
    double E_star, R_star, F_Y, delta_Y, k_lin, f_contact; /* Pa, m, N, m, N/m, Hz */
    /* the upper contact (all 0 without one): its force on the mass (down) [N], indentation y - (yC +
     * gap) [m], mode, onsets, plastic work [J] (E_contact above is both contacts' energy) */
    double F_upper, delta_upper;
    int mode_upper, n_impacts_upper;
    double W_plastic_upper;
} vi_model_values;

/* An input over a communication step: value u + du (t - t). */
typedef struct {
    double u, du, t;
} vi_ramp;

/* The ramp's value at time t. */
static inline double vi_ramp_at(const vi_ramp *r, double t) { return r->u + r->du * (t - r->t); }

/* The body: a mass pressed down by a load. Its state is its position y [m] and velocity v [m/s]; the
 * model integrates it as x = (delta, v), delta = yC - y the lower contact's indentation (exact when
 * yC carries a large offset), and y = yC - delta. */
typedef struct {
    double m;  /* mass [kg] */
    double W0; /* the load's constant part P + m g [N] (W(t) = W0 - F_ext(t)) */
} vi_body;

/* One contact of the body with a surface: its law with the law's constants, its memory and its mode.
 * Each mode has VI_CONTACT_NGUARDS guards (vi_model.c, mode_guards), the contact's; the model's
 * guard i belongs to contact i / VI_CONTACT_NGUARDS. The lower contact's indentation is the state's
 * delta = x[0] and its rate yC' - v; the upper contact's (its surface at yC + gap, moving with the
 * platform) is delta_u = y - yC - gap = -gap - delta and its rate v - yC' = -delta'. In its own
 * indentation and rate each contact is the one-sided contact: its law, surfaces, snapping and mode
 * choice; its holding force in stick is that of the lower contact with the sign turned
 * (-(W + m yC'')). vi_model.c's per-contact functions (contact_force, contact_stiffness,
 * contact_guards, resolve) take the contact and the state. */
typedef struct {
    /* the law and its constants, from the parameters (vi_model_setup) */
    int law;       /* VI_LAW_* */
    int upper;     /* the upper contact: indentation -gap - delta, rate -delta' */
    double gap;    /* the upper contact's clearance [m] (0 for the lower contact) */
    int moving;    /* Johnson with a moving contact point */
    int unloading; /* VI_UNLOAD_PAPER or VI_UNLOAD_CONTINUOUS */
    double K;      /* Hertz constant [N/m^1.5] */
    vi_johnson johnson;  /* E*, R*, theta_Y, F_Y, delta_Y */
    double k_lin;  /* F_Y/delta_Y [N/m] */
    vi_damped_hertz damped;  /* damped Hertz: K, alpha sqrt(m K) or chi */
    vi_linear_law linear;    /* linear spring-dashpot: k, c */

    /* discrete state */
    int mode;          /* VI_MODE_* */
    int yielded;       /* Johnson, fixed contact point: plastic memory exists */
    vi_unload_curve unload; /* Johnson memory: delta_c, Rbar, delta_r, delta_f (valid when yielded) */
    double delta_p;    /* LEPP permanent set [m] (in mode 2 it is delta - delta_Y) */
    double V_i;        /* damped Hertz, published forms: approach speed at the onset of this contact [m/s]
                        * (0: a contact present at a static start, undamped until it ends) */
    long n_impacts;    /* contact onsets */
} vi_model_contact;

/* The contacts of the model, in its list: the lower contact, delta = yC - y (contact 0), and with
 * upper_stop the upper contact (contact 1). The engine (vi_hybrid.h), the solver's guards and Model
 * Exchange's event indicators are sized by the list's capacity: VI_CONTACT_NGUARDS guards per contact;
 * the guards of a contact the model does not use are 1 (never fire). */
#define VI_NCONTACTS 2
#define VI_LOWER 0
#define VI_UPPER 1

typedef struct {
    vi_body body;
    /* the platform, from the parameters (vi_model_setup) */
    double a, omega, t0; /* harmonic excitation: amplitude [m], 2 pi f [rad/s]; start time [s] */
    double phi0, t_phi;  /* phase reference: phi(t) = phi0 + omega (t - t_phi) [rad, s] (state: tunable f) */
    double f_contact;    /* linearised contact resonance at the initial static load [Hz] (initial state) */
    double V, x0;        /* rolling speed [m/s] and position on the profile at t0 [m] */
    /* The profile (owned by the simulation, not the model). A pointer inside the FMU state: never
     * trusted from a saved state; the simulation attaches its own after setup and after every
     * restore (vi_model_set_rolling). NULL: no profile, yb = 0. */
    const vi_profile *profile;

    /* inputs */
    vi_ramp yC_in, F_ext;

    /* the contacts: the body against the platform's surfaces, the first ncontacts in use (1, or 2
     * with upper_stop); the others all zero */
    int ncontacts;
    vi_model_contact contact[VI_NCONTACTS];
} vi_model;

/* The lower contact (the body on the platform): the contact whose mode, force and memory are the
 * outputs. */
static inline const vi_model_contact *vi_model_lower(const vi_model *model) { return &model->contact[VI_LOWER]; }
/* The mode of the lower contact (the output `mode`). */
static inline int vi_model_mode(const vi_model *model) { return model->contact[VI_LOWER].mode; }

/* The model's guards: VI_CONTACT_NGUARDS per contact. */
#define VI_NGUARDS (VI_CONTACT_NGUARDS * VI_NCONTACTS)

/* Derive the constants from the parameters. Each parameter lies in its range of the variable table
 * (finite, m > 0, -1 < nu <= 0.5, enumerations one of their items, ...: the FMI layer refuses any
 * other value when it is set); what the table cannot say is checked here: at least one radius > 0,
 * and a finite positive contact stiffness and yield force. Returns 0, or -1 with a message in msg. */
int vi_model_setup(vi_model *model, const vi_model_params *p, double t0, char *msg, size_t msg_size);

/* The excitation's parameters changed at time t (tunable a and f, finite, f >= 0 as the variable
 * table says): the phase phi stays continuous (a new f turns on from phi(t) at the new rate); a new
 * a moves the platform by (a_new - a)(cos(phi(t)) - 1), and delta jumps with it while the mass does
 * not move, as for a jump of yC_in. Call between vi_model_freeze and vi_model_resolve (the rate of
 * delta changes). */
void vi_model_set_excitation(vi_model *model, double t, double x[2], double a, double f);
/* The inputs run these ramps from time t on: delta jumps with the platform's position yC_in while the
 * mass does not move. Call between vi_model_freeze and vi_model_resolve, as for the excitation. */
void vi_model_set_inputs(vi_model *model, double t, double x[2], vi_ramp yC_in, vi_ramp F_ext);
/* Do (a, f) differ from the excitation the model runs? */
int vi_model_excitation_differs(const vi_model *model, double a, double f);
/* The excitation's phase phi(t) [rad]. */
double vi_model_phase(const vi_model *model, double t);

/* Roll over profile (NULL: none) at speed V [m/s] from position x0 [m] at t0 (both finite). Returns 0,
 * or -1 with a message when x0 lies outside a non-periodic profile. */
int vi_model_set_rolling(vi_model *model, const vi_profile *profile, double V, double x0, char *msg, size_t n);
/* Position on the profile at time t [m]. */
double vi_model_rolling_position(const vi_model *model, double t);
/* The first time after t at which the platform velocity jumps (the rolling position
 * passes a kink of yb); INFINITY if none. The time is rounded so that the position there is past the
 * kink, so that yC' there is the value after the jump. */
double vi_model_next_breakpoint(const vi_model *model, double t);
/* At a breakpoint (time t): the rate of delta jumped with the platform velocity; choose the mode
 * afresh (freeze, then resolve). Returns the mode. */
int vi_model_breakpoint(vi_model *model, double t, double x[2]);
/* The last time a non-periodic profile covers (the rolling position reaches its end); INFINITY
 * without a profile, with a periodic one, or with V = 0. When it is finite, msg says why the motion
 * cannot go past it. */
double vi_model_rolling_limit(const vi_model *model, char *msg, size_t n);

/* Platform position yC(t) [m]; its first and second derivatives when the pointers are not NULL. */
double vi_model_platform(const vi_model *model, double t, double *dyC, double *ddyC);

/* Initial state at time t0 (parameters init, v0) on the virgin curve; sets the mode and f_contact,
 * the linearised resonance at the static load W(t0) (unloading stiffness when pre-loaded plastically). */
void vi_model_initial_state(vi_model *model, int init, double v0, double t0, double x[2]);

/* Does the law need the platform's rate beyond the tie-breaks of a mode choice (a rate guard: the
 * turning point of a plastic motion, stick; a force that depends on delta')? Hertz and Johnson with a
 * moving contact point do not. */
int vi_model_uses_rate(const vi_model *model);
/* Contact force [N] in the current mode (the lower contact's). */
double vi_model_force(const vi_model *model, double t, const double x[2]);
/* The upper contact's force on the mass [N], down positive; 0 without an upper contact. */
double vi_model_force_upper(const vi_model *model, double t, const double x[2]);
void vi_model_rhs(const vi_model *model, double t, const double x[2], double dx[2]);
/* Contact i's stiffness dF_i/d(delta_i) [N/m] and damping dF_i/d(delta_i') [N s/m] in its own
 * indentation and rate at (t, x) in its mode (0 free, in stick, and for a contact not in use). */
void vi_model_contact_slopes(const vi_model *model, int i, double t, const double x[2], double *k, double *c);
/* Is a contact in stick (the mass moves with the platform: delta' = 0, v' = yC'')? */
int vi_model_sticks(const vi_model *model);
/* d(v')/d(delta): the only nonzero state derivative of the right-hand side besides d(delta')/dv = -1. */
double vi_model_stiffness_over_mass(const vi_model *model, double t, const double x[2]);
/* Contact i's d(stiffness)/d(delta_i) [N/m^2] in its own indentation delta_i (the lower contact's
 * delta; the upper one's -gap - delta): the second derivative of its force in its mode (0 where it is
 * linear or constant, in stick, whose stiffness is that at delta_c, and for a contact not in use). */
double vi_model_stiffness_rate(const vi_model *model, int i, double t, const double x[2], double *per_rate);
/* dF/d(delta') [N s/m] of a law that damps (damped Hertz, linear spring-dashpot) in contact; else 0.
 * per_rate above: d(stiffness_i)/d(delta_i') [N s/m^2] for those laws, else 0. */
double vi_model_damping(const vi_model *model, double t, const double x[2]);
/* The rates d/d(delta_i) [1, except W_plastic: N] of contact i's memory outputs at x in its mode, in
 * its own indentation delta_i: nonzero only while the memory tracks delta_i (Johnson loading
 * plastically with a fixed contact point: delta_c = delta_i; LEPP flowing: delta_p = delta_i -
 * delta_Y); all 0 for a contact not in use. */
typedef struct {
    double delta_c, delta_f, delta_p, Rbar, W_plastic;
} vi_memory_rates;
void vi_model_memory_rates(const vi_model *model, int i, const double x[2], vi_memory_rates *r);
/* ENERGY. Along a motion, 1/2 m v^2 + E_contact + W_plastic + W_damping = the work of the platform,
 * integral of F yC' dt, plus the work of the net load, -integral of W(t) v dt: the power F delta' the
 * bodies put into the contact is the rate of E_contact + W_plastic + W_damping.
 * The elastic energy the contact holds at x in the current mode [J]: the work of the current branch's
 * force from its contact surface to delta (free: 0; elastic: the virgin curve's work, Hertz 0.4 K
 * delta^2.5 (Johnson and Thornton below delta_Y), LEPP 0.5 k_lin (delta - delta_p)^2; plastic: the
 * unloading curve of delta_c = delta, 0.4 Kbar delta_r^2.5 (moving contact point: the virgin curve's
 * work), LEPP 0.5 F_Y delta_Y; unload and stick: the unloading curve's, 0.4 Kbar (delta - delta_f)^2.5
 * at delta or delta_c). The damped laws (hertz_damped, linear) hold the energy of their spring part,
 * F_spring = K delta^1.5 or k_spring delta, 0.4 K delta^2.5 or 0.5 k_spring delta^2, while the bodies
 * overlap (delta > 0), in either mode: after a release (the force reached 0 at delta > 0) the spring
 * still holds its energy, and gives it to the damping while delta falls to 0, or keeps it when the
 * contact resumes. With an upper contact E_contact is the sum of both contacts' (the upper one's in
 * its own indentation -gap - delta). per_delta (when not NULL): d(E_contact)/d(delta) [N] in the
 * current modes. */
double vi_model_contact_energy(const vi_model *model, const double x[2], double *per_delta);
/* The damping's power of a damped law at (t, x) [W], the rate of W_damping: the power of the force
 * beyond its spring part, P = (F - F_spring(delta)) delta' (elastic: F_damping delta' >= 0; free at
 * delta > 0, after a release: -F_spring delta' >= 0, delta falling); 0 for the other laws; with its
 * partials d/d(delta) [N/s] and d/d(delta') [N]. */
typedef struct {
    double P, dP_ddelta, dP_drate;
} vi_model_power;
/* With an upper contact: the sum of both contacts' powers, the partials in the lower contact's delta and delta'. */
vi_model_power vi_model_damping_power(const vi_model *model, double t, const double x[2]);
/* The power the bodies put into the contact at (t, x) [W]: F delta', the rate of E_contact + W_plastic +
 * W_damping (with an upper contact the sum of both contacts', each its force times its own rate). */
double vi_model_contact_power(const vi_model *model, double t, const double x[2]);
/* Is any contact not free? */
int vi_model_touching(const vi_model *model);
/* Does a contact of hertz_damped, exact (vi_model_damping_root_at_onset) sit exactly at its onset
 * (indentation 0) at x? */
int vi_model_damping_onset(const vi_model *model, const double x[2]);
/* Does the law damp (hertz_damped, linear: W_damping grows)? */
int vi_model_damps(const vi_model *model);
/* Does its damping's power grow as (t - t_onset)^(1/4) from a contact's onset (Tsuji's delta^(1/4)
 * delta'^2: hertz_damped, exact)? */
int vi_model_damping_root_at_onset(const vi_model *model);
/* dF/dt along the motion at (t, x) [N/s]: stiffness times delta' (and, for the damped laws, dF/d(delta')
 * times delta''); in stick the rate of F_hold; 0 when free. Zero where F has an extremum in time. dx: the
 * motion's x' = (delta', v') at (t, x) (a solver's interpolant), NULL: from the right-hand side. The
 * force itself (vi_model_force) into *F, from the same evaluation of the law. */
double vi_model_force_rate(const vi_model *model, double t, const double x[2], const double dx[2], double *F);

/* Jacobian of vi_model_rhs, row major: d(delta', v')/d(delta, v). In stick both rows are zero
 * (delta' = 0, v' = yC''), so that a Newton iteration keeps delta exactly on delta_c. */
void vi_model_jacobian(const vi_model *model, double t, const double x[2], double j[4]);
void vi_model_guards(const vi_model *model, double t, const double x[2], double g[VI_NGUARDS]);
/* What guard `guard` (of the model's VI_NGUARDS) watches in `mode` of its contact, in words
 * ("separation", "the turning point", ...; "none" for a guard the mode does not use). */
const char *vi_model_guard_name(const vi_model *model, int mode, int guard);
/* The mode of the contact guard `guard` belongs to. */
int vi_model_guard_mode(const vi_model *model, int guard);
/* Contact i's own indentation at x [m]: the lower contact's delta, the upper one's -gap - delta. */
double vi_model_contact_indentation(const vi_model *model, int i, const double x[2]);

/* The memory outputs never fall below the memory written down: while loading plastically delta_c is
 * max(delta, delta_c written), the LEPP set max(delta - delta_Y, delta_p written) (an importer's state may
 * lie past a turning point it has not located yet).
 * Write down the memory that tracks the state (delta_c while Johnson loads plastically, delta_p
 * while LEPP flows) and put a sticking mass exactly on the platform's velocity. Call it before the
 * state is changed from outside (an input jump) and before vi_model_resolve. */
void vi_model_freeze(vi_model *model, double t, double x[2]);
/* Apply the event: guard `fired` of the current mode reached zero at time t. Freezes, snaps x onto
 * the surface, and chooses the next mode. Returns the new mode. */
int vi_model_event(vi_model *model, double t, double x[2], int fired);
/* Choose the mode consistent with (delta, rate, acceleration) at an arbitrary state, e.g. after an
 * input jump (freeze first); updates the memory if the state lies beyond it and counts a contact
 * onset. Returns the new mode. */
int vi_model_resolve(vi_model *model, double t, double x[2]);

/* Length L [m] and velocity V [m/s] scales of the active law in this scene, for the absolute
 * tolerances (rtol L, rtol V), from the initial state x0 at t0. L is the largest indentation the
 * law's own loads and speeds produce:
 *   d_W      the static indentation under W(t0) = P + m g - F_ext on the law's virgin curve (W > 0);
 *   delta_Y  for Johnson and LEPP only (Hertz has no yield: Y plays no role there);
 *   d_v      the impact indentation at the initial approach speed v = |yC'(t0) - v(t0)| (or, when
 *            neither a load nor that speed gives a scale, at the excitation's speed |a| 2 pi f):
 *            Hertz and Johnson (15 m v^2/(16 E* sqrt(R*)))^(2/5), LEPP v sqrt(m/k_lin);
 *   VI_SCALE_FALLBACK R* when all of these are 0 (no load, no speed, no excitation).
 * The largest, not the smallest, so that a negligible load, speed or amplitude (P = 1e-200,
 * v0 = 1e-100, a = 1e-300) cannot shrink the tolerances to nothing; vibrations much smaller than L
 * are then resolved to rtol L (tighten rtol for them). V = L sqrt(k(L)/m), k the law's virgin
 * stiffness at L (computed without overflow for tiny m). Both are finite and > 0. */
#define VI_SCALE_FALLBACK 1e-6
void vi_model_scales(const vi_model *model, const double x0[2], double *L, double *V);

/* Range of validity. The contact laws (eqs. 2-4) describe the local contact of bodies whose radii
 * are large against the contact and against every displacement of the problem (half-space, small
 * slopes). Four causes, each a bit of the result (the last is a law that makes energy):
 *   VI_INVALID_INDENTATION  the Hertz contact radius sqrt(R* delta) exceeds VI_VALIDITY_RADIUS R*,
 *                           i.e. the indentation delta (or the largest one, delta_c) exceeds
 *                           VI_VALIDITY_RADIUS^2 R*;
 *   VI_INVALID_AMPLITUDE    the excitation amplitude |a| exceeds R*: the platform moves by more than
 *                           the radius of curvature of the contact (above the contact resonance the
 *                           indentation swings by about a, a hundred times the first limit);
 *   VI_INVALID_PROFILE      the profile's heights span more than the rolling radius R1 (paper
 *                           Fig. 1b: a wheel rolling over a roughness small against it);
 *   VI_INVALID_ENERGY       Johnson's paper unloading (as printed) returns more energy than the
 *                           loading to delta_c took (W_plastic < 0: delta_c < 1.2527 delta_Y).
 * Returns the bit of the first cause that is not in `skip`, with a message naming the time, the
 * value and the limit; 0 when there is none. The simulation checks at initialization, at events,
 * at communication points and after a change of a, and warns once per cause and instance
 * (logStatusWarning). */
#define VI_VALIDITY_RADIUS 0.1
enum { VI_INVALID_INDENTATION = 1, VI_INVALID_AMPLITUDE = 2, VI_INVALID_PROFILE = 4, VI_INVALID_ENERGY = 8,
       VI_INVALID_FORCE = 16 };
int vi_model_validity(const vi_model *model, double R1, double t, const double x[2], int skip, char *msg, size_t n);
/* The one cause that depends on the state alone: is the indentation beyond its limit at x? (The
 * others change only with a, the profile and the plastic memory, which changes at events.) */
int vi_model_indentation_invalid(const vi_model *model, const double x[2]);
/* The force limits the paper states (section 2), VI_INVALID_FORCE: Hertz's law (eq. 2, hertz and
 * hertz_damped) holds while the strains are purely elastic, F <= F_Y; Johnson's elastic-plastic
 * loading (eq. 3) for F_Y < F < F_p, F_p about VI_JOHNSON_FP F_Y (contained plastic flow; beyond it
 * the flow is fully plastic). vi_model_force_limit: the law's limit [N] (INFINITY: none);
 * vi_model_force_validity: VI_INVALID_FORCE with a message naming the time, the largest force F_max
 * [N] and the limit when F_max exceeds it, else 0. */
#define VI_JOHNSON_FP 650.0
double vi_model_force_limit(const vi_model *model);
int vi_model_force_validity(const vi_model *model, double F_max, double t, char *msg, size_t n);

/* Options that contradict each other or are ignored: moving_contact, continuous
 * unloading, the printed yield formula or damping_formula where the law does not use them, v0 with a
 * static start, the rolling parameters without a profile; and a published damping form whose
 * restitution misses e_restitution by more than 0.01 (it names the restitution it gives).
 * Returns how many there are; msg lists them (one warning at initialization). */
int vi_model_option_warnings(const vi_model_params *p, char *msg, size_t n);

/* Is model (with the state x) a model this code could have produced (doc/model.md section 7.6)? Checks, and names in
 * msg the first bad field of:
 *  - enumerations and flags: law, moving, unloading, mode (allowed for the law), yielded;
 *  - constants: finite, m, K, E*, R*, theta_Y, F_Y, delta_Y, k_lin > 0, omega >= 0, and consistent with
 *    each other (K = 4/3 E* sqrt(R*), F_Y = K delta_Y^1.5, k_lin = F_Y/delta_Y to 1e-9 relative);
 *  - inputs: the ramps finite;
 *  - memory: yielded only for Johnson with a fixed contact point; then the unloading curve U is the
 *    one of delta_c (recomputed, 1e-9 relative), delta_c >= delta_Y, Rbar > 0, delta_f <= delta_c;
 *    without yield U is all zero; delta_p finite, >= 0 for LEPP and 0 otherwise; n_impacts >= 0;
 *  - mode against state, from what does not depend on the time (the signature carries none): the
 *    length guards of the mode (contact, separation, yield, reloading to delta_c) and the memory a
 *    mode implies (plastic: delta >= delta_c, or delta >= delta_p + delta_Y for LEPP; stick: delta =
 *    delta_c, paper unloading) may not be below -VI_CHECK_GUARD_TOL times the length scale
 *    max(delta_Y, |delta|, delta_c). Guards are >= 0 inside a mode and events snap the state onto
 *    their surface, so a state this code wrote misses by rounding only; 1e-6 leaves room for the
 *    solver's root location and flags a mode that does not belong to the state. The guards in
 *    velocity and force (turning point, stick limits) need the time and are not checked here.
 * A model never set up (law 0, as vi_sim_init leaves it) is valid when its discrete state is zero.
 * Returns 0, or -1 with the message. Touches nothing (pointers in model are not followed). */
#define VI_CHECK_GUARD_TOL 1e-6
int vi_model_check(const vi_model *model, const double x[2], char *msg, size_t n);
/* vi_model_check without the mode against the state: a state an outside integrator may hold (Model
 * Exchange), which lies beyond its mode's surfaces between a crossing and the event that follows. */
int vi_model_check_between_events(const vi_model *model, const double x[2], char *msg, size_t n);

/* Derived parameters (E_star ... f_contact) and outputs at (t, x). */
void vi_model_calculated(const vi_model *model, vi_model_values *out);
/* Groups of outputs computed together: a reader of y needs the platform position (a cosine), not the
 * force law or the plastic work (a logarithm). The simulation layer adds VI_OUT_MEAN (F_mean) and
 * VI_OUT_STIFFNESS (k_contact); Model Exchange VI_OUT_DERIVATIVES (der_y, der_v). */
enum {
    VI_OUT_STATE = 1u << 0,       /* delta, v, contact, mode, n_impacts: the state as it is */
    VI_OUT_PLATFORM = 1u << 1,    /* yC and y = yC - delta */
    VI_OUT_FORCE = 1u << 2,       /* F (+ F_peak) */
    VI_OUT_MEMORY = 1u << 3,      /* delta_c, delta_f, delta_p, Rbar, W_plastic, E_contact (+ W_dissipated) */
    VI_OUT_CALCULATED = 1u << 4,  /* E_star, R_star, F_Y, delta_Y, k_lin, f_contact */
    VI_OUT_MEAN = 1u << 5,        /* F_mean */
    VI_OUT_STIFFNESS = 1u << 6,   /* k_contact */
    VI_OUT_DERIVATIVES = 1u << 7, /* der_y, der_v */
    VI_OUT_ALL = (1u << 8) - 1u
};
/* The outputs of the groups VI_OUT_STATE ... VI_OUT_CALCULATED named in `groups` at (t, x) into *out;
 * the other fields of *out are left as they are. */
void vi_model_outputs(const vi_model *model, double t, const double x[2], unsigned groups, vi_model_values *out);

#endif
