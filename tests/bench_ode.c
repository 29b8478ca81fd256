/* bench_ode: cost of the one-step integrator (vi_ode.h) for 2 states.
 *
 * Part 1 prints, for a harmonic oscillator and a Hertz contact oscillator on a harmonic platform,
 * the nanoseconds per accepted step, the rhs evaluations per step, the nanoseconds of those rhs
 * evaluations alone (timed separately, at times spread over the run) and the share of the step
 * spent outside them; with and without dense output and guards.
 * Part 2 runs the FMU's model (vi_model.h) on the paper's Fig. 4b (Johnson, Y = 6e8 Pa) and Fig. 5a
 * (Hertz, 100 Hz) over 40 ms with outputs every 1e-5 s by dense interpolation and the model's
 * events, and prints per rtol the CPU time, steps, events, rhs evaluations and the largest
 * deviation of the mass position y from a run at rtol 1e-13, relative to the range of y.
 * Times are the minimum of several repeats (the machine is shared; the minimum is the least
 * disturbed run).
 *
 *   build/bench_ode [repeats]          (built with the project; not a test: it asserts nothing) */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "vi_model.h"
#include "vi_ode.h"
#include "vi_contact_instance.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void osc(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = x[1];
    dx[1] = -x[0];
}

/* Hertz contact: x = (delta [m], v [m/s]), the paper's Hertz data (K = 1.12e11 N/m^1.5 order,
 * m = 407.7 kg, W = 40 kN), platform a cos(2 pi f t). */
typedef struct {
    double K, m, W, a, w;
} hertz;

static void hertz_rhs(double t, const double *x, double *dx, void *u)
{
    const hertz *H = u;
    double d = x[0], F = d > 0.0 ? H->K * d * sqrt(d) : 0.0;
    dx[0] = -H->a * H->w * sin(H->w * t) - x[1];
    dx[1] = (F - H->W) / H->m;
}

static void hertz_guards(double t, const double *x, double *g, void *u)
{
    (void)t, (void)u;
    g[0] = x[0];     /* separation */
    g[1] = -x[1];    /* a turning point, as a second guard */
}

typedef struct {
    const char *name;
    vi_ode_problem p;
    double x0[2], T;
    int dense_per_step; /* vi_ode_dense calls per step (outputs at communication points) */
} cas;

static double run(cas *c, vi_ode_stats *st)
{
    vi_ode s;
    if (vi_ode_init(&s, &c->p, 0.0, c->x0, 0.0, 0u) != VI_ODE_OK) exit(1);
    double t0 = now(), x[2];
    while (s.t < c->T) {
        int r = vi_ode_step(&s, &c->p, c->T);
        if (r < 0) {
            fprintf(stderr, "%s: %s at t = %g\n", c->name, vi_ode_status_text(r), s.t);
            exit(1);
        }
        for (int k = 1; k <= c->dense_per_step; k++)
            vi_ode_dense(&s, &c->p, s.t_old + (s.t - s.t_old) * k / (c->dense_per_step + 1), x, NULL);
        if (r == VI_ODE_EVENT) vi_ode_restart(&s, &c->p, s.ev_t, s.ev_x, s.h, s.ev_fired);
    }
    *st = s.st;
    return now() - t0;
}

/* ---- Part 2: the FMU's model ---- */
#define COMM_STEP 1e-5
#define T_END 0.04
#define N_COMM 4000

static void model_rhs(double t, const double *x, double *dx, void *u) { vi_model_rhs(u, t, x, dx); }
static void model_guards(double t, const double *x, double *g, void *u) { vi_model_guards(u, t, x, g); }

typedef struct {
    long steps, events, rhs_evals, dense_builds;
} model_stats;

/* One run: y at the N_COMM + 1 communication points into y_out; returns the CPU time. */
static double model_run(const vi_parameters *par, double rtol, int samples, double *y_out, model_stats *ms)
{
    vi_model M;
    char msg[256];
    vi_model_params mp = vi_contact_model_params(par);
    if (vi_model_setup(&M, &mp, 0.0, msg, sizeof msg) < 0) {
        fprintf(stderr, "model: %s\n", msg);
        exit(1);
    }
    double x[2], L, V;
    vi_model_initial_state(&M, par->init, par->v0, 0.0, x);
    vi_model_scales(&M, x, &L, &V);
    vi_ode_problem p = {.n = 2, .ng = VI_NGUARDS, .rhs = model_rhs, .guards = model_guards, .user = &M,
                        .rtol = rtol, .atol = {rtol * L, rtol * V}, .guard_samples = samples};
    vi_ode s;
    double t0 = now();
    if (vi_ode_init(&s, &p, 0.0, x, 0.0, 0u) != VI_ODE_OK) exit(1);
    y_out[0] = vi_model_platform(&M, 0.0, NULL, NULL) - x[0];
    int next = 1; /* next communication point */
    long events = 0;
    while (next <= N_COMM) {
        int r = vi_ode_step(&s, &p, T_END);
        if (r < 0) {
            fprintf(stderr, "model: %s at t = %g\n", vi_ode_status_text(r), s.t);
            exit(1);
        }
        double t_valid = r == VI_ODE_EVENT ? s.ev_t : s.t;
        for (; next <= N_COMM && next * COMM_STEP <= t_valid; next++) {
            double tc = next * COMM_STEP, xc[2];
            vi_ode_dense(&s, &p, tc, xc, NULL);
            y_out[next] = vi_model_platform(&M, tc, NULL, NULL) - xc[0];
        }
        if (r == VI_ODE_EVENT) {
            int g = 0;
            while (!(s.ev_fired & (1u << g))) g++;
            int mode = M.contact[0].mode;
            double xe[2] = {s.ev_x[0], s.ev_x[1]};
            vi_model_event(&M, s.ev_t, xe, g);
            vi_ode_restart(&s, &p, s.ev_t, xe, 0.0, M.contact[0].mode == mode ? s.ev_fired : 0u);
            events++;
        }
    }
    double cpu = now() - t0;
    *ms = (model_stats){s.st.accepted, events, s.st.rhs_evals, s.st.dense_builds};
    return cpu;
}

static void model_part(int repeats)
{
    static double y_ref[N_COMM + 1], y[N_COMM + 1];
    struct {
        const char *name;
        int law;
        double Y, f;
    } figs[] = {{"Fig. 4b (Johnson, Y = 6e8 Pa, 560 Hz)", VI_ContactModel_johnson, 6e8, 560.0},
                {"Fig. 5a (Hertz, 100 Hz)", VI_ContactModel_hertz, 6e8, 100.0}};
    printf("\nThe FMU's model, 40 ms, outputs every 1e-5 s by dense interpolation, events located:\n");
    printf("%-40s %7s %7s %7s %7s %9s %9s %10s %11s\n", "scenario", "rtol", "samples", "steps", "events", "rhs",
           "rhs/step", "CPU [ms]", "error/range");
    for (size_t k = 0; k < sizeof figs / sizeof figs[0]; k++) {
        vi_parameters par;
        vi_parameters_default(&par);
        par.contact_model = figs[k].law;
        par.Y = figs[k].Y;
        par.f = figs[k].f;
        par.a = 1e-4;
        par.init = 1;
        model_stats ms;
        model_run(&par, 1e-13, 2, y_ref, &ms);
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i <= N_COMM; i++) lo = fmin(lo, y_ref[i]), hi = fmax(hi, y_ref[i]);
        double rtols[] = {1e-6, 1e-8, 1e-10};
        for (int samples = 0; samples <= 2; samples += 2)
            for (size_t j = 0; j < sizeof rtols / sizeof rtols[0]; j++) {
                double best = INFINITY;
                for (int r = 0; r < repeats; r++) best = fmin(best, model_run(&par, rtols[j], samples, y, &ms));
                double err = 0.0;
                for (int i = 0; i <= N_COMM; i++) err = fmax(err, fabs(y[i] - y_ref[i]));
                printf("%-40s %7.0e %7d %7ld %7ld %9ld %9.2f %10.3f %11.2e\n", figs[k].name, rtols[j], samples, ms.steps,
                       ms.events, ms.rhs_evals, (double)ms.rhs_evals / ms.steps, 1e3 * best, err / (hi - lo));
            }
    }
}

int main(int argc, char **argv)
{
    int repeats = argc > 1 ? atoi(argv[1]) : 5;
    if (repeats < 1) repeats = 1;
    /* K for steel R = 0.475 m: 4/3 E* sqrt(R), E* = 115.4 GPa */
    hertz H = {4.0 / 3.0 * 115.4e9 * sqrt(0.475), 407.747, 40000.0, 1e-6, 2 * 3.14159265358979323846 * 100.0};
    double d0 = pow(H.W / H.K, 2.0 / 3.0);
    cas cases[] = {
        {"oscillator, rtol 1e-8", {.n = 2, .rhs = osc, .rtol = 1e-8, .atol = {1e-10, 1e-10}}, {1, 0}, 2000.0, 0},
        {"oscillator, rtol 1e-8, dense 1/step", {.n = 2, .rhs = osc, .rtol = 1e-8, .atol = {1e-10, 1e-10}}, {1, 0},
         2000.0, 1},
        {"hertz, rtol 1e-8", {.n = 2, .rhs = hertz_rhs, .user = &H, .rtol = 1e-8, .atol = {1e-14, 1e-9}},
         {d0 * 1.5, 0}, 2.0, 0},
        {"hertz, rtol 1e-8, 2 guards", {.n = 2, .ng = 2, .rhs = hertz_rhs, .guards = hertz_guards, .user = &H,
          .rtol = 1e-8, .atol = {1e-14, 1e-9}}, {d0 * 1.5, 0}, 2.0, 0},
        {"hertz, rtol 1e-8, 2 guards, 2 samples, dense 2/step", {.n = 2, .ng = 2, .rhs = hertz_rhs,
          .guards = hertz_guards, .user = &H, .rtol = 1e-8, .atol = {1e-14, 1e-9}, .guard_samples = 2},
         {d0 * 1.5, 0}, 2.0, 2},
    };
    printf("%-52s %9s %9s %9s %9s %9s %8s\n", "case (2 states)", "steps", "ns/step", "rhs/step", "ns/rhs",
           "rhs ns/st", "other %");
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        cas *c = &cases[i];
        vi_ode_stats st = {0};
        double best = INFINITY;
        for (int r = 0; r < repeats; r++) best = fmin(best, run(c, &st));
        /* the same number of rhs evaluations alone, at points along the trajectory */
        long n_rhs = st.rhs_evals;
        double x[2] = {c->x0[0], c->x0[1]}, dx[2], sink = 0.0, best_rhs = INFINITY;
        for (int r = 0; r < repeats; r++) {
            double t0 = now();
            for (long k = 0; k < n_rhs; k++) {
                c->p.rhs(c->T * ((double)k / n_rhs), x, dx, c->p.user); /* t over the run's span */
                x[1] += 1e-30 * dx[1]; /* keep the calls dependent */
                sink += dx[0];
            }
            best_rhs = fmin(best_rhs, now() - t0);
        }
        double ns_step = 1e9 * best / st.accepted, ns_rhs = 1e9 * best_rhs / n_rhs;
        double rhs_per_step = (double)n_rhs / st.accepted;
        printf("%-52s %9ld %9.1f %9.2f %9.2f %9.1f %7.0f%%%s\n", c->name, st.accepted, ns_step, rhs_per_step, ns_rhs,
               ns_rhs * rhs_per_step, 100.0 * (1.0 - ns_rhs * rhs_per_step / ns_step), sink == 12345.0 ? " " : "");
    }
    model_part(repeats);
    return 0;
}
