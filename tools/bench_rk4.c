/* bench_rk4 - what a master without event location would get: the FMU's model (vi_model.h)
 * integrated by the classical fixed-step Runge-Kutta method of order 4, the guards looked at only
 * at the ends of the steps. When a guard is found below zero there, the event is applied at that
 * step end (state snapped onto the surface, mode chosen afresh), late by up to one step.
 *
 *   vi_bench_rk4 T_STOP H_COMM H_RK4 REPEATS OUT [name=value ...]
 *   vi_bench_rk4 --rhs-cost N [name=value ...]
 *
 * --rhs-cost: nanoseconds per evaluation of the model's right-hand side alone (vi_model_rhs), the
 * minimum over 5 rounds of N evaluations at states along one RK4 run of 10 ms (the contact modes and
 * free flight the run visits), for the "limit" of `vibroimpact bench` (rhs evaluations x their cost).
 * name=value sets a parameter of the variable table (Reals, Integers, Booleans by name). Outputs y,
 * v, F, delta, mode at every communication point (H_COMM a multiple of H_RK4) go to OUT as doubles
 * (t, y, v, F, delta, mode), as tools/bench_driver.c writes them. Prints
 *   cpu_s <min CPU seconds over REPEATS runs> steps <RK4 steps> events <events applied>
 * Part of `vibroimpact bench`; not a test. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vi_model.h"
#include "vi_contact_instance.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int set_parameter(vi_parameters *p, const char *arg)
{
    char name[64];
    double value;
    if (sscanf(arg, "%63[^=]=%lf", name, &value) != 2) return -1;
    for (int vr = 0; vr < VI_NVARS; vr++) {
        const vi_variable *v = &vi_variable_table[vr];
        if (v->group != VI_GROUP_PARAMETERS || strcmp(v->name, name) != 0) continue;
        char *field = (char *)p + v->offset;
        if (v->type == VI_Real) *(double *)field = value;
        else *(int *)field = (int)value;
        return 0;
    }
    return -1;
}

static void rk4_step(const vi_model *M, double t, double h, double x[2])
{
    double k1[2], k2[2], k3[2], k4[2], y[2];
    vi_model_rhs(M, t, x, k1);
    for (int i = 0; i < 2; i++) y[i] = x[i] + 0.5 * h * k1[i];
    vi_model_rhs(M, t + 0.5 * h, y, k2);
    for (int i = 0; i < 2; i++) y[i] = x[i] + 0.5 * h * k2[i];
    vi_model_rhs(M, t + 0.5 * h, y, k3);
    for (int i = 0; i < 2; i++) y[i] = x[i] + h * k3[i];
    vi_model_rhs(M, t + h, y, k4);
    for (int i = 0; i < 2; i++) x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
}

/* States (t, x, mode) along 10 ms of an RK4 run, then N evaluations of the rhs over them. */
static int rhs_cost(long n, const vi_parameters *par)
{
    enum { NS = 1000 };
    static double ts[NS], xs[NS][2];
    static int modes[NS];
    vi_model M = {0};
    char msg[256];
    vi_model_params mp = vi_contact_model_params(par);
    if (vi_model_setup(&M, &mp, 0.0, msg, sizeof msg) < 0) {
        fprintf(stderr, "%s\n", msg);
        return 1;
    }
    double x[2], h = 1e-8;
    vi_model_initial_state(&M, par->init, par->v0, 0.0, x);
    for (long k = 0; k < 1000000; k++) {
        double g[VI_NGUARDS];
        rk4_step(&M, k * h, h, x);
        vi_model_guards(&M, (k + 1) * h, x, g);
        for (int i = 0; i < VI_NGUARDS; i++)
            if (g[i] < 0.0) {
                vi_model_event(&M, (k + 1) * h, x, i);
                break;
            }
        if (k % 1000 == 0) ts[k / 1000] = (k + 1) * h, xs[k / 1000][0] = x[0], xs[k / 1000][1] = x[1], modes[k / 1000] = M.contact[0].mode;
    }
    double best = INFINITY, sink = 0.0;
    for (int round = 0; round < 5; round++) {
        double c0 = cpu_now();
        for (long k = 0; k < n; k++) {
            double dx[2];
            M.contact[0].mode = modes[k % NS];
            vi_model_rhs(&M, ts[k % NS], xs[k % NS], dx);
            sink += dx[1];
        }
        double c1 = cpu_now();
        if (c1 - c0 < best) best = c1 - c0;
    }
    printf("rhs_ns %.6g (checksum %g)\n", 1e9 * best / (double)n, sink);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && !strcmp(argv[1], "--rhs-cost")) {
        vi_parameters par;
        vi_parameters_default(&par);
        for (int i = 3; i < argc; i++)
            if (set_parameter(&par, argv[i]) < 0) return 2;
        return rhs_cost(atol(argv[2]), &par);
    }
    if (argc < 6) {
        fprintf(stderr, "usage: %s T_STOP H_COMM H_RK4 REPEATS OUT [name=value ...]\n", argv[0]);
        return 2;
    }
    double t_stop = atof(argv[1]), h_comm = atof(argv[2]), h = atof(argv[3]);
    int repeats = atoi(argv[4]);
    long per_comm = (long)floor(h_comm / h + 0.5), n_comm = (long)floor(t_stop / h_comm + 0.5);
    vi_parameters par;
    vi_parameters_default(&par);
    for (int i = 6; i < argc; i++)
        if (set_parameter(&par, argv[i]) < 0) {
            fprintf(stderr, "unknown parameter %s\n", argv[i]);
            return 2;
        }
    double best = INFINITY;
    long events = 0;
    for (int rep = 0; rep < repeats; rep++) {
        FILE *out = rep == 0 ? fopen(argv[5], "wb") : NULL;
        double c0 = cpu_now(), x[2];
        vi_model M = {0};
        char msg[256];
        vi_model_params mp = vi_contact_model_params(&par);
        if (vi_model_setup(&M, &mp, 0.0, msg, sizeof msg) < 0) {
            fprintf(stderr, "%s\n", msg);
            return 1;
        }
        M.yC_in = M.F_ext = (vi_ramp){0.0, 0.0, 0.0};
        vi_model_initial_state(&M, par.init, par.v0, 0.0, x);
        events = 0;
        for (long k = 0; k < n_comm; k++) {
            for (long j = 0; j < per_comm; j++) {
                double t = (double)(k * per_comm + j) * h;
                rk4_step(&M, t, h, x);
                double g[VI_NGUARDS];
                vi_model_guards(&M, t + h, x, g);
                for (int i = 0; i < VI_NGUARDS; i++)
                    if (g[i] < 0.0) { /* found late, applied here */
                        vi_model_event(&M, t + h, x, i);
                        events++;
                        break;
                    }
            }
            if (out) {
                double tc = (double)(k + 1) * h_comm, yC = vi_model_platform(&M, tc, NULL, NULL);
                double row[6] = {tc, yC - x[0], x[1], vi_model_force(&M, tc, x), x[0], M.contact[0].mode};
                fwrite(row, sizeof row, 1, out);
            }
        }
        double c1 = cpu_now();
        if (out) fclose(out);
        if (c1 - c0 < best) best = c1 - c0;
    }
    printf("cpu_s %.9g steps %ld events %ld\n", best, n_comm * per_comm, events);
    return 0;
}
