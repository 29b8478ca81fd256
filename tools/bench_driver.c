/* bench_driver - runs the FMU binary directly (dlopen, no Python in the loop) for `vibroimpact bench`.
 *
 *   vi_bench_driver FMU.so GUID T_STOP H REPEATS TOL --vrs Y,V,F,DELTA,MODE,N_IMPACTS [--out FILE]
 *                   [--reads VR,VR,...] [--checkpoint] [--budget S] [vr=value ...]
 *
 * --vrs: the value references of y, v, F, delta (Reals), mode and n_impacts (Integers)
 * (vibroimpact/bench.py reads them from modelDescription.xml). --reads: the Real outputs read after every
 * step (default: y; "--reads ''" reads nothing). --checkpoint: fmi2GetFMUstate before every step (a
 * master ready to roll back). --budget S: no further repeat once the runs have taken S s of CPU.
 * vr=value sets a start value before initialization: "r12=6e8" (Real), "i13=2" (Integer or
 * enumeration), "b14=1" (Boolean), "s46=/path/profile.txt" (String). TOL > 0 goes to fmi2SetupExperiment (0: the FMU's rtol counts).
 * The run: instantiate, set up, initialize, then fmi2DoStep with communication step H up to T_STOP,
 * reading the --reads outputs after each step, then free. It is repeated
 * REPEATS times; the minimum CPU time (the least disturbed run on a shared machine) is printed as
 *   cpu_s <min CPU seconds of the whole run> step_us <min CPU per fmi2DoStep, loop only, us>
 *   init_s <min CPU seconds from fmi2Instantiate to the end of fmi2ExitInitializationMode>
 *   heap_bytes <heap in use after initialization minus before instantiation> steps <n>
 *   impacts <n_impacts at the end> rhs <rhs evaluations the FMU reports at fmi2Terminate (logSolver)>
 *   discard_at <fmi2LastSuccessfulTime when a step returned fmi2Discard (the run stops there), else nan>
 *   solver_steps, rejected, guard_evals, restarts <the solver's accepted internal steps, rejected attempts (error
 *   test failures), guard evaluations and restarts, from the same statistics; -1 when not reported>
 * --out FILE writes, for the first run, the samples (t, y, v, F, delta, mode) as doubles.
 * Exit status 1 when a call fails (printed). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <malloc.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fmi2Functions.h"

#define MAX_SETS 64
#define MAX_READS 64

/* "a,b,c" -> vr[], returns the count */
static int parse_vrs(const char *text, fmi2ValueReference *vr, int max)
{
    int n = 0;
    for (const char *p = text; *p && n < max; n++) {
        char *end;
        vr[n] = (fmi2ValueReference)strtoul(p, &end, 10);
        if (end == p) return -1;
        p = *end == ',' ? end + 1 : end;
    }
    return n;
}

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static long rhs_evals = -1, solver_steps = -1, rejected = -1, guard_evals = -1, restarts = -1;

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env, (void)name;
    if (status >= fmi2Discard) fprintf(stderr, "[%s] %s\n", category, message);
    /* "... statistics: N steps, M rhs evaluations, J Jacobian evaluations, I nonlinear iterations, F nonlinear
     * failures, E error test failures, G guard evaluations, R restarts, V events" */
    const char *stats = strstr(message, "statistics: ");
    long c[9];
    if (stats && sscanf(stats, "statistics: %ld steps, %ld rhs evaluations, %ld Jacobian evaluations, %ld nonlinear "
                        "iterations, %ld nonlinear failures, %ld error test failures, %ld guard evaluations, %ld restarts",
                        &c[0], &c[1], &c[2], &c[3], &c[4], &c[5], &c[6], &c[7]) == 8)
        solver_steps = c[0], rhs_evals = c[1], rejected = c[5], guard_evals = c[6], restarts = c[7];
}

#define LOAD(name) fmi2##name##TYPE *name = (fmi2##name##TYPE *)dlsym(lib, "fmi2" #name)

int main(int argc, char **argv)
{
    if (argc < 7) {
        fprintf(stderr, "usage: %s FMU.so GUID T_STOP H REPEATS TOL --vrs Y,V,F,DELTA,MODE [--out FILE] "
                        "[--reads VR,...] [vr=value ...]\n", argv[0]);
        return 2;
    }
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 2;
    }
    LOAD(Instantiate); LOAD(SetupExperiment); LOAD(EnterInitializationMode); LOAD(ExitInitializationMode);
    LOAD(SetReal); LOAD(SetInteger); LOAD(SetBoolean); LOAD(GetReal); LOAD(GetInteger); LOAD(DoStep);
    LOAD(FreeInstance); LOAD(Terminate); LOAD(SetDebugLogging); LOAD(GetFMUstate); LOAD(FreeFMUstate);
    LOAD(GetRealStatus); LOAD(SetString);
    const char *guid = argv[2], *out_path = NULL;
    double t_stop = atof(argv[3]), h = atof(argv[4]), tol = atof(argv[6]);
    int repeats = atoi(argv[5]), nreads = -1, nvrs = 0, nsets = 0, checkpoint = 0;
    double budget = INFINITY, spent = 0.0;
    fmi2ValueReference vrs[6], reads[MAX_READS];
    char set_type[MAX_SETS];
    fmi2ValueReference set_vr[MAX_SETS];
    double set_value[MAX_SETS];
    const char *set_text[MAX_SETS];
    for (int i = 7; i < argc; i++) {
        if (!strcmp(argv[i], "--out") && i + 1 < argc) out_path = argv[++i];
        else if (!strcmp(argv[i], "--reads") && i + 1 < argc) nreads = parse_vrs(argv[++i], reads, MAX_READS);
        else if (!strcmp(argv[i], "--vrs") && i + 1 < argc) nvrs = parse_vrs(argv[++i], vrs, 6);
        else if (!strcmp(argv[i], "--checkpoint")) checkpoint = 1;
        else if (!strcmp(argv[i], "--budget") && i + 1 < argc) budget = atof(argv[++i]);
        else if (nsets < MAX_SETS && argv[i][0] == 's' && sscanf(argv[i], "s%u=", &set_vr[nsets]) == 1 && strchr(argv[i], '='))
            set_type[nsets] = 's', set_text[nsets] = strchr(argv[i], '=') + 1, nsets++;
        else if (nsets < MAX_SETS && sscanf(argv[i], "%c%u=%lf", &set_type[nsets], &set_vr[nsets], &set_value[nsets]) == 3)
            nsets++;
        else {
            fprintf(stderr, "bad argument %s\n", argv[i]);
            return 2;
        }
    }
    if (nvrs != 6) {
        fprintf(stderr, "--vrs Y,V,F,DELTA,MODE,N_IMPACTS is required\n");
        return 2;
    }
    if (nreads < 0) nreads = 1, reads[0] = vrs[0];
    long n = (long)floor(t_stop / h + 0.5);
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    double best = INFINITY, best_loop = INFINITY, best_init = INFINITY;
    long heap = 0;
    fmi2Integer impacts = 0;
    double discard_at = NAN; /* fmi2LastSuccessfulTime after an fmi2Discard (the work bound) */
    for (int rep = 0; rep < repeats && spent < budget; rep++) {
        FILE *out = rep == 0 && out_path ? fopen(out_path, "wb") : NULL;
        size_t heap0 = mallinfo2().uordblks;
        double c0 = cpu_now();
        fmi2Component c = Instantiate("bench", fmi2CoSimulation, guid, "file:///tmp", &cb, fmi2False, fmi2False);
        if (!c || SetupExperiment(c, tol > 0, tol, 0.0, fmi2True, t_stop * (1 + 1e-12)) > fmi2Warning ||
            EnterInitializationMode(c) > fmi2Warning) {
            fprintf(stderr, "instantiation failed\n");
            return 1;
        }
        for (int i = 0; i < nsets; i++) {
            fmi2Status st;
            if (set_type[i] == 'r') st = SetReal(c, &set_vr[i], 1, &set_value[i]);
            else if (set_type[i] == 's') st = SetString(c, &set_vr[i], 1, &set_text[i]);
            else {
                fmi2Integer k = (fmi2Integer)set_value[i];
                st = set_type[i] == 'b' ? SetBoolean(c, &set_vr[i], 1, &k) : SetInteger(c, &set_vr[i], 1, &k);
            }
            if (st > fmi2Warning) return 1;
        }
        if (ExitInitializationMode(c) > fmi2Warning) return 1;
        if (cpu_now() - c0 < best_init) best_init = cpu_now() - c0;
        fmi2String categories[] = {"logSolver"};
        if (rep == 0) SetDebugLogging(c, fmi2True, 1, categories);
        heap = (long)(mallinfo2().uordblks - heap0);
        double l0 = cpu_now(), r[MAX_READS];
        fmi2Integer mode = 0;
        fmi2FMUstate state = NULL;
        for (long k = 0; k < n; k++) {
            if (checkpoint && GetFMUstate(c, &state) != fmi2OK) return 1;
            fmi2Status st = DoStep(c, k * h, h, fmi2True);
            if (st == fmi2Discard) {
                GetRealStatus(c, fmi2LastSuccessfulTime, &discard_at);
                break;
            }
            if (st != fmi2OK) {
                fprintf(stderr, "fmi2DoStep at t = %.17g returned %d\n", k * h, (int)st);
                return 1;
            }
            if (nreads > 0) GetReal(c, reads, (size_t)nreads, r);
            if (out) {
                GetReal(c, vrs, 4, r);
                GetInteger(c, &vrs[4], 1, &mode);
                double row[6] = {(k + 1) * h, r[0], r[1], r[2], r[3], mode};
                fwrite(row, sizeof row, 1, out);
            }
        }
        double l1 = cpu_now();
        if (state) FreeFMUstate(c, &state);
        GetInteger(c, &vrs[5], 1, &impacts);
        Terminate(c);
        FreeInstance(c);
        double c1 = cpu_now();
        if (out) fclose(out);
        if (c1 - c0 < best) best = c1 - c0;
        spent += c1 - c0;
        if (l1 - l0 < best_loop) best_loop = l1 - l0;
    }
    printf("cpu_s %.9g step_us %.6g init_s %.9g heap_bytes %ld steps %ld impacts %d rhs %ld discard_at %.17g "
           "solver_steps %ld rejected %ld guard_evals %ld restarts %ld\n", best, 1e6 * best_loop / (double)n, best_init,
           heap, n, (int)impacts, rhs_evals, discard_at, solver_steps, rejected, guard_evals, restarts);
    dlclose(lib);
    return 0;
}
