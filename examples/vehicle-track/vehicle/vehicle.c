/*
 * vehicle.c - the Vehicle FMU of the vehicle-track example: the sprung mass above one wheel on
 * the primary suspension. The wheel is the contact FMU's mass; this FMU takes its position and
 * velocity and gives the suspension force on it. Up positive; z_b is measured so that z_b = y_w
 * when the spring carries the static load m_b g:
 *
 *   F_wheel = -m_b g + k (z_b - y_w) + c (v_b - v_w)      (force on the wheel)
 *   m_b z_b'' = -k (z_b - y_w) - c (v_b - v_w)             (gravity balanced by the spring preload)
 *
 * Over a step the wheel moves at the velocity it was given: y_w(t) = y_wheel + v_wheel (t - t_in),
 * v_w = v_wheel, from the time t_in the inputs were set (a first-order hold that needs no input
 * derivatives, so every importer gets the same). States x = (z_b, v_b, W_dissipated): the last
 * integrates the damper power c (v_b - v_w)^2. The work the wheel motion does on the vehicle,
 * W_in = integral of -F_wheel v_w dt, is exact from the states: v_w is held over a step and the
 * impulse of F_wheel follows from the body's momentum, -m_b (v_b(end) - v_b(start)) - m_b g h.
 * Then E + W_dissipated - W_in stays at its initial value within a step, E = 1/2 m_b v_b^2 +
 * 1/2 k (z_b - y_w)^2 + m_b g y_w (a new y_wheel at a communication point moves E by the jump of
 * the spring and weight terms). Start: the spring at its static load and the body moving with the
 * wheel, z_b = y_wheel, v_b = v_wheel.
 */
#include <math.h>
#include <stdio.h>

#include "vehicle_variables.h"
#include "vt_companion.h"

VI_TABLE_DEFINE

typedef struct {
    vt_core core;
    vi_parameters par;
    vi_inputs in, din;
    double W_in; /* J, work of the wheel motion on the vehicle so far */
} vehicle_data;

enum { ZB, VB, WD, N_VEHICLE };

/* The wheel's position and velocity at t, from the held inputs. */
static void wheel(const vehicle_data *d, double t, double *y, double *v)
{
    *v = d->in.v_wheel;
    *y = d->in.y_wheel + d->in.v_wheel * (t - vt_input_time(&d->core));
}

static void start(void *data)
{
    vehicle_data *d = data;
    d->core.x[ZB] = d->in.y_wheel;
    d->core.x[VB] = d->in.v_wheel;
    d->W_in = 0.0;
}

static void step_done(void *data, double t0, const double *x0)
{
    vehicle_data *d = data;
    const vi_parameters *p = &d->par;
    double impulse = -p->m_body * (d->core.x[VB] - x0[VB]) - p->m_body * p->g * (d->core.t - t0);
    d->W_in += -impulse * d->in.v_wheel;
}

static double rtol(const void *data) { return ((const vehicle_data *)data)->par.rtol; }

/* Absolute tolerance scales: VT_LENGTH_SCALE, that times the natural frequency, and the spring's
 * elastic energy at that length. */
static void scales(const void *data, double *s)
{
    const vi_parameters *p = &((const vehicle_data *)data)->par;
    s[ZB] = VT_LENGTH_SCALE;
    s[VB] = VT_LENGTH_SCALE * sqrt(p->k_susp / p->m_body);
    s[WD] = 0.5 * p->k_susp * VT_LENGTH_SCALE * VT_LENGTH_SCALE;
}

static double force_on_wheel(const vehicle_data *d, double t, const double *x)
{
    const vi_parameters *p = &d->par;
    double yw, vw;
    wheel(d, t, &yw, &vw);
    return -p->m_body * p->g + p->k_susp * (x[ZB] - yw) + p->c_susp * (x[VB] - vw);
}

static void rhs(double t, const double *x, double *dx, const void *data)
{
    const vehicle_data *d = data;
    const vi_parameters *p = &d->par;
    double F = force_on_wheel(d, t, x), dv = x[VB] - d->in.v_wheel;
    dx[ZB] = x[VB];
    dx[VB] = -(F + p->m_body * p->g) / p->m_body;
    dx[WD] = p->c_susp * dv * dv;
}

static void jac(double t, const double *x, double *J, const void *data)
{
    (void)t;
    const vehicle_data *d = data;
    const vi_parameters *p = &d->par;
    const int n = N_VEHICLE;
    for (int i = 0; i < n * n; i++) J[i] = 0.0;
    double vw = d->in.v_wheel;
    J[ZB * n + VB] = 1.0;
    J[VB * n + ZB] = -p->k_susp / p->m_body;
    J[VB * n + VB] = -p->c_susp / p->m_body;
    J[WD * n + VB] = 2.0 * p->c_susp * (x[VB] - vw);
}

static void outputs(const void *data, void *out)
{
    const vehicle_data *d = data;
    const vi_parameters *p = &d->par;
    const double *x = d->core.x;
    vi_outputs *o = out;
    double yw, vw;
    wheel(d, d->core.t, &yw, &vw);
    o->F_wheel = force_on_wheel(d, d->core.t, x);
    o->z_body = x[ZB];
    o->v_body = x[VB];
    double s = x[ZB] - yw;
    o->E = 0.5 * (p->m_body * x[VB] * x[VB] + p->k_susp * s * s) + p->m_body * p->g * yw;
    o->W_dissipated = x[WD];
    o->W_in = d->W_in;
    o->f_body = sqrt(p->k_susp / p->m_body) / VT_TWO_PI;
    double dx[N_VEHICLE];
    rhs(d->core.t, x, dx, d);
    o->der_z_body = dx[ZB], o->der_v_body = dx[VB], o->der_W_dissipated = dx[WD];
}

static const vt_model_def vehicle_def = {
    .n = N_VEHICLE,
    .start = start,
    .rtol = rtol,
    .scales = scales,
    .rhs = rhs,
    .jac = jac,
    .outputs = outputs,
    .step_done = step_done,
};

/* Model Exchange: the states and their derivatives, in the order of x. */
static const unsigned state_vrs[N_VEHICLE] = {VI_VR_z_body, VI_VR_v_body, VI_VR_W_dissipated};
static const unsigned derivative_vrs[N_VEHICLE] = {VI_VR_der_z_body, VI_VR_der_v_body, VI_VR_der_W_dissipated};

VT_DEFINE_FMU(vehicle_def, vehicle_data, N_VEHICLE, state_vrs, derivative_vrs);
