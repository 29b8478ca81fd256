/*
 * track.c - the Track FMU of the vehicle-track example: a rail mass on a rail pad on a sleeper
 * mass on ballast, loaded by the wheel-rail contact force. Coordinates up positive, measured from
 * the track at rest under its own weight (gravity on rail and sleeper is balanced there and drops
 * out). The contact force on the wheel F = F_contact (input) acts on the rail as -F:
 *
 *   m_rail    z_r'' = -F - F_pad,                      F_pad = k_pad (z_r - z_s) + c_pad (v_r - v_s)
 *   m_sleeper z_s'' = F_pad - k_ballast z_s - c_ballast v_s
 *
 * States x = (z_r, v_r, z_s, v_s). The work of the input, W_in = integral of -F v_r dt, is exact
 * from the states: F is held over a step, so a step adds -F (z_r(end) - z_r(start)). The stored
 * energy E (kinetic + elastic) depends on the states only, so the work dissipated in the dampers
 * (the integral of c_pad (v_r - v_s)^2 + c_ballast v_s^2) is W_dissipated = W_in - (E - E(0)).
 * Start: at rest under the initial input, z_s = -F/k_ballast, z_r = z_s - F/k_pad.
 */
#include <math.h>
#include <stdio.h>

#include "track_variables.h"
#include "vt_companion.h"

VI_TABLE_DEFINE

typedef struct {
    vt_core core;
    vi_parameters par;
    vi_inputs in, din;
    double W_in; /* J, work of the input force on the rail so far */
    double E0;   /* J, stored energy at the start */
} track_data;

enum { ZR, VR, ZS, VS, N_TRACK };

/* Kinetic energy of rail and sleeper and elastic energy of pad and ballast [J]. */
static double energy(const track_data *d)
{
    const vi_parameters *p = &d->par;
    const double *x = d->core.x;
    double s = x[ZR] - x[ZS];
    return 0.5 * (p->m_rail * x[VR] * x[VR] + p->m_sleeper * x[VS] * x[VS] + p->k_pad * s * s +
                  p->k_ballast * x[ZS] * x[ZS]);
}

static void start(void *data)
{
    track_data *d = data;
    double F = d->in.F_contact;
    d->core.x[ZS] = -F / d->par.k_ballast;
    d->core.x[ZR] = d->core.x[ZS] - F / d->par.k_pad;
    d->W_in = 0.0;
    d->E0 = energy(d);
}

static void step_done(void *data, double t0, const double *x0)
{
    (void)t0;
    track_data *d = data;
    d->W_in += -d->in.F_contact * (d->core.x[ZR] - x0[ZR]);
}

static double rtol(const void *data) { return ((const track_data *)data)->par.rtol; }

static double k_static(const vi_parameters *p) { return 1.0 / (1.0 / p->k_pad + 1.0 / p->k_ballast); }

/* Undamped natural circular frequencies: det(K - w^2 M) = 0,
 * m_r m_s w^4 - (k_pad m_s + (k_pad + k_ballast) m_r) w^2 + k_pad k_ballast = 0. */
static void omegas(const vi_parameters *p, double *w1, double *w2)
{
    double a = p->m_rail * p->m_sleeper, b = p->k_pad * p->m_sleeper + (p->k_pad + p->k_ballast) * p->m_rail;
    double c = p->k_pad * p->k_ballast, disc = sqrt(b * b - 4.0 * a * c);
    *w1 = sqrt(2.0 * c / (b + disc)); /* the smaller root, without cancellation */
    *w2 = sqrt((b + disc) / (2.0 * a));
}

/* Absolute tolerance scales: VT_LENGTH_SCALE for the displacements, that times the upper natural
 * frequency for the velocities. */
static void scales(const void *data, double *s)
{
    const vi_parameters *p = &((const track_data *)data)->par;
    double w1, w2;
    omegas(p, &w1, &w2);
    s[ZR] = s[ZS] = VT_LENGTH_SCALE;
    s[VR] = s[VS] = VT_LENGTH_SCALE * w2;
}

static void rhs(double t, const double *x, double *dx, const void *data)
{
    (void)t;
    const track_data *d = data;
    const vi_parameters *p = &d->par;
    double F = d->in.F_contact;
    double dv = x[VR] - x[VS];
    double F_pad = p->k_pad * (x[ZR] - x[ZS]) + p->c_pad * dv;
    dx[ZR] = x[VR];
    dx[VR] = (-F - F_pad) / p->m_rail;
    dx[ZS] = x[VS];
    dx[VS] = (F_pad - p->k_ballast * x[ZS] - p->c_ballast * x[VS]) / p->m_sleeper;
}

static void jac(double t, const double *x, double *J, const void *data)
{
    (void)t, (void)x;
    const vi_parameters *p = &((const track_data *)data)->par;
    const int n = N_TRACK;
    for (int i = 0; i < n * n; i++) J[i] = 0.0;
    J[ZR * n + VR] = 1.0;
    J[VR * n + ZR] = -p->k_pad / p->m_rail;
    J[VR * n + VR] = -p->c_pad / p->m_rail;
    J[VR * n + ZS] = p->k_pad / p->m_rail;
    J[VR * n + VS] = p->c_pad / p->m_rail;
    J[ZS * n + VS] = 1.0;
    J[VS * n + ZR] = p->k_pad / p->m_sleeper;
    J[VS * n + VR] = p->c_pad / p->m_sleeper;
    J[VS * n + ZS] = -(p->k_pad + p->k_ballast) / p->m_sleeper;
    J[VS * n + VS] = -(p->c_pad + p->c_ballast) / p->m_sleeper;
}

static void outputs(const void *data, void *out)
{
    const track_data *d = data;
    const vi_parameters *p = &d->par;
    const double *x = d->core.x;
    vi_outputs *o = out;
    o->z_rail = x[ZR];
    o->v_rail = x[VR];
    o->z_sleeper = x[ZS];
    o->v_sleeper = x[VS];
    o->E = energy(d);
    o->W_dissipated = d->W_in - (o->E - d->E0);
    o->W_in = d->W_in;
    o->k_static = k_static(p);
    double w1, w2;
    omegas(p, &w1, &w2);
    o->f1 = w1 / VT_TWO_PI;
    o->f2 = w2 / VT_TWO_PI;
    double dx[N_TRACK];
    rhs(d->core.t, x, dx, d);
    o->der_z_rail = dx[ZR], o->der_v_rail = dx[VR], o->der_z_sleeper = dx[ZS], o->der_v_sleeper = dx[VS];
}

static const vt_model_def track_def = {
    .n = N_TRACK,
    .start = start,
    .rtol = rtol,
    .scales = scales,
    .rhs = rhs,
    .jac = jac,
    .outputs = outputs,
    .step_done = step_done,
};

/* Model Exchange: the states and their derivatives, in the order of x. */
static const unsigned state_vrs[N_TRACK] = {VI_VR_z_rail, VI_VR_v_rail, VI_VR_z_sleeper, VI_VR_v_sleeper};
static const unsigned derivative_vrs[N_TRACK] = {VI_VR_der_z_rail, VI_VR_der_v_rail, VI_VR_der_z_sleeper, VI_VR_der_v_sleeper};

VT_DEFINE_FMU(track_def, track_data, N_TRACK, state_vrs, derivative_vrs);
