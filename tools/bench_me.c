/* bench_me - the cost of the Model Exchange calls of an FMU binary, without Python (dlopen).
 *
 *   vi_bench_me FMU.so GUID N [vr=value ...]
 *
 * vr=value sets a start value before initialization as in bench_driver ("r12=6e8" Real, "i13=2"
 * Integer, "b14=1" Boolean). After initialization and the initial event iteration, in continuous-time
 * mode at the initial state, each of the following is timed N times in a loop (CPU time, the least of
 * five loops counts: the least disturbed on a shared machine) and printed in nanoseconds per call:
 *   derivatives   fmi2SetTime + fmi2SetContinuousStates + fmi2GetDerivatives, the evaluation an
 *                 importer's integrator makes (time and states moved by a little each call)
 *   indicators    fmi2SetTime + fmi2SetContinuousStates + fmi2GetEventIndicators
 *   event_state   a state event: fmi2SetContinuousStates with the first state 1 nm beyond the surface of the
 *                 first event indicator, fmi2EnterEventMode, fmi2NewDiscreteStates until settled,
 *                 fmi2EnterContinuousTimeMode; the next call crosses back (for the contact FMU: the
 *                 contact is lost, then made again, each event choosing the mode afresh)
 *   event_none    the same event iteration where nothing is due (a step event)
 * The first state and indicator are taken as they are (contact FMU: y and the contact or separation
 * guard of the mode at the start). Exit status 1 when a call fails or the events did not alternate.
 * Time moves forward by 1 us at each state event (events at one instant would be Zeno). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fmi2Functions.h"

#define MAX_SETS 64
#define MAX_N 16
#define LOOPS 5

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env, (void)name, (void)category;
    if (status >= fmi2Warning) fprintf(stderr, "FMU: %s\n", message);
}

#define LOAD(var, name)                                                  \
    var = (name##TYPE *)dlsym(lib, #name);                               \
    if (!var) {                                                          \
        fprintf(stderr, "missing %s\n", #name);                          \
        return 1;                                                        \
    }
#define CHECK(call)                                                      \
    do {                                                                 \
        if ((call) > fmi2Warning) {                                      \
            fprintf(stderr, "failed: %s\n", #call);                      \
            return 1;                                                    \
        }                                                                \
    } while (0)

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: %s FMU.so GUID N [vr=value ...]\n", argv[0]);
        return 2;
    }
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "%s\n", dlerror());
        return 1;
    }
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2SetupExperimentTYPE *setup;
    fmi2EnterInitializationModeTYPE *enter_init;
    fmi2ExitInitializationModeTYPE *exit_init;
    fmi2SetRealTYPE *set_real;
    fmi2SetIntegerTYPE *set_integer;
    fmi2SetBooleanTYPE *set_boolean;
    fmi2NewDiscreteStatesTYPE *new_discrete;
    fmi2EnterEventModeTYPE *enter_event;
    fmi2EnterContinuousTimeModeTYPE *enter_ct;
    fmi2SetTimeTYPE *set_time;
    fmi2SetContinuousStatesTYPE *set_states;
    fmi2GetContinuousStatesTYPE *get_states;
    fmi2GetDerivativesTYPE *get_derivatives;
    fmi2GetEventIndicatorsTYPE *get_indicators;
    LOAD(instantiate, fmi2Instantiate) LOAD(free_instance, fmi2FreeInstance) LOAD(setup, fmi2SetupExperiment)
    LOAD(enter_init, fmi2EnterInitializationMode) LOAD(exit_init, fmi2ExitInitializationMode)
    LOAD(set_real, fmi2SetReal) LOAD(set_integer, fmi2SetInteger) LOAD(set_boolean, fmi2SetBoolean)
    LOAD(new_discrete, fmi2NewDiscreteStates) LOAD(enter_event, fmi2EnterEventMode)
    LOAD(enter_ct, fmi2EnterContinuousTimeMode) LOAD(set_time, fmi2SetTime) LOAD(set_states, fmi2SetContinuousStates)
    LOAD(get_states, fmi2GetContinuousStates) LOAD(get_derivatives, fmi2GetDerivatives)
    LOAD(get_indicators, fmi2GetEventIndicators)

    long n = atol(argv[3]);
    fmi2CallbackFunctions cb = {.logger = logger, .allocateMemory = calloc, .freeMemory = free};
    fmi2Component c = instantiate("bench", fmi2ModelExchange, argv[2], "", &cb, fmi2False, fmi2False);
    if (!c || n < 1) return 1;
    CHECK(setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK(enter_init(c));
    for (int i = 4; i < argc; i++) {
        char type;
        unsigned vr;
        double value;
        if (sscanf(argv[i], "%c%u=%lf", &type, &vr, &value) != 3) return fprintf(stderr, "bad %s\n", argv[i]), 2;
        fmi2ValueReference r = vr;
        fmi2Integer k = (fmi2Integer)value;
        fmi2Boolean b = value != 0.0;
        if (type == 'r') CHECK(set_real(c, &r, 1, &value));
        else if (type == 'i') CHECK(set_integer(c, &r, 1, &k));
        else CHECK(set_boolean(c, &r, 1, &b));
    }
    CHECK(exit_init(c));
    fmi2EventInfo info = {.newDiscreteStatesNeeded = fmi2True};
    for (int k = 0; k < 100 && info.newDiscreteStatesNeeded; k++) CHECK(new_discrete(c, &info));
    CHECK(enter_ct(c));

    double x0[MAX_N], x[MAX_N], dx[MAX_N], z[MAX_N], t0 = 1e-9;
    const size_t nx = 3, nz = 4; /* the contact FMU (y, v, W_damping; two guards per contact); a model with other sizes fails the calls below */
    CHECK(set_time(c, t0));
    CHECK(get_states(c, x0, nx));
    double best[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
    double sink = 0.0, xa[MAX_N], xb[MAX_N];
    /* two states 1 nm on either side of the first indicator's surface (the indicator is linear in the
     * first state near it: the zero from the slope over 1e-3 of the state), for events that alternate */
    double z0[MAX_N], z1[MAX_N], hx = 1e-3 * fmax(fabs(x0[0]), 1e-12);
    CHECK(get_indicators(c, z0, nz));
    memcpy(x, x0, sizeof x);
    x[0] += hx;
    CHECK(set_states(c, x, nx));
    CHECK(get_indicators(c, z1, nz));
    double slope = (z1[0] - z0[0]) / hx, x_zero = x0[0] - z0[0] / slope;
    memcpy(xa, x0, sizeof xa), memcpy(xb, x0, sizeof xb);
    xa[0] = x_zero + 1e-9 * (slope > 0 ? -1.0 : 1.0); /* the indicator below zero */
    xb[0] = x_zero - 1e-9 * (slope > 0 ? -1.0 : 1.0); /* and above: back across at the next event */
    CHECK(set_states(c, x0, nx));
    int crossed = 1;
    double tc = t0; /* time only goes forward past events */
    for (int loop = 0; loop < LOOPS; loop++) {
        double start = cpu_now();
        for (long k = 0; k < n; k++) {
            x[0] = x0[0] * (1.0 + 1e-9 * (double)(k & 7)), x[1] = x0[1];
            CHECK(set_time(c, tc + 1e-12 * (double)(k & 7)));
            CHECK(set_states(c, x, nx));
            CHECK(get_derivatives(c, dx, nx));
            sink += dx[1];
        }
        best[0] = fmin(best[0], (cpu_now() - start) / (double)n);
        start = cpu_now();
        for (long k = 0; k < n; k++) {
            x[0] = x0[0] * (1.0 + 1e-9 * (double)(k & 7)), x[1] = x0[1];
            CHECK(set_time(c, tc + 1e-12 * (double)(k & 7)));
            CHECK(set_states(c, x, nx));
            CHECK(get_indicators(c, z, nz));
            sink += z[0];
        }
        best[1] = fmin(best[1], (cpu_now() - start) / (double)n);
        start = cpu_now();
        for (long k = 0; k < n; k++) { /* the state crosses the surface, the event iteration takes it */
            tc += 1e-6; /* events 1 us apart: no accumulation */
            CHECK(set_time(c, tc));
            CHECK(set_states(c, (k & 1) ? xb : xa, nx));
            CHECK(enter_event(c));
            info.newDiscreteStatesNeeded = fmi2True;
            for (int p = 0; p < 100 && info.newDiscreteStatesNeeded; p++) CHECK(new_discrete(c, &info));
            CHECK(enter_ct(c));
        }
        best[2] = fmin(best[2], (cpu_now() - start) / (double)n);
        CHECK(set_states(c, xa, nx));
        CHECK(get_indicators(c, z, nz));
        crossed &= (n % 2 == 0) == (z[0] <= 0.0); /* an even number of events: back in the first mode */
        start = cpu_now();
        for (long k = 0; k < n; k++) { /* nothing due: a step event */
            CHECK(enter_event(c));
            info.newDiscreteStatesNeeded = fmi2True;
            for (int p = 0; p < 100 && info.newDiscreteStatesNeeded; p++) CHECK(new_discrete(c, &info));
            CHECK(enter_ct(c));
        }
        best[3] = fmin(best[3], (cpu_now() - start) / (double)n);
        CHECK(set_states(c, x0, nx));
    }
    free_instance(c);
    printf("derivatives_ns %.1f indicators_ns %.1f event_state_ns %.1f event_none_ns %.1f crossed %d finite %d\n",
           1e9 * best[0], 1e9 * best[1], 1e9 * best[2], 1e9 * best[3], crossed, sink == sink);
    return crossed ? 0 : 1;
}
