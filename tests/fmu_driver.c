/*
 * fmu_driver.c - drives an FMU binary through its fmi2* functions, as an importer would. Portable C:
 * the same source is built for Linux (dlopen) and, cross-compiled, for Windows (LoadLibrary) and
 * aarch64 Linux (tools/release.sh), where it runs under wine and qemu-user (tools/cross_test.sh).
 *
 *   fmu_driver <VibroImpact binary> <resources URI> [<LayerTest binary> <its GUID>]
 *       The checks for the memory checkers: built with AddressSanitizer + UndefinedBehaviorSanitizer
 *       (cmake -DVI_SANITIZE=ON) it runs against the sanitized VibroImpact.so; run under valgrind
 *       memcheck it runs against the normal one. Any report of either fails the test (tools/test.sh).
 *   fmu_driver run <VibroImpact binary> <case>
 *       Prints the record of one case (below) for comparison with another platform's binary; exits
 *       1 when a check inside the case fails.
 *   fmu_driver layer <LayerTest binary> <its GUID> <resources URI>
 *       Prints the value LayerTest read from the resources folder the URI names (-1: none read).
 *   fmu_driver companion <FMU binary> <its GUID> <input value>
 *       Prints the record of a run of any FMU on the generic layer (the vehicle-track companions):
 *       its first input (value reference 0) set to <input value>, rtol 1e-10, 1000 steps of 1e-4 s,
 *       every Real variable after each step.
 *   fmu_driver compare <record> <record> <tolerance>
 *       Compares two records line by line: trajectory lines ("~ <name> <t> <value>") within
 *       <tolerance> times the range of that variable in the first record (its largest magnitude if
 *       constant), every other line (statuses with their messages, counts) exactly. Prints the
 *       largest difference; exits 1 when they differ.
 *   fmu_driver cases
 *       Lists the cases.
 *
 * Checks (first form): instantiate; initialize a bouncing Hertz case and a yielding Johnson case;
 * step with events; read every variable; get, set, serialize and deserialize FMU states (also before
 * initialization and a corrupted one); refused calls and bad arguments; a failed initialization;
 * reset; many instances at once; Model Exchange for each law (forward Euler with its events, the
 * Jacobian, FMU states, refused calls); free. With LayerTest (the generic layer's test model, which reads
 * its resources folder) also: resource URIs percent-decoded, missing, or not local. The importer's
 * memory functions count blocks, so that a block the FMU forgets is reported even without a leak
 * checker.
 *
 * Cases (run):
 *   fig4b-<solver>   Fig. 4b (Johnson, Y = 6e8 Pa, a = 0.1 mm, f = 560 Hz) for 20 ms at rtol 1e-10,
 *   fig5a-<solver>   a Fig. 5a-like run (Hertz, f = 100 Hz) for 0.1 s, solver bdf, adams, dop853 or auto:
 *                    y after every communication step of 1e-5 s, the impact count at the end
 *   fig4b_100ms-<solver>  Fig. 4b for the paper's 0.1 s (see scenarios[] below)
 *   fig4b_thornton-<solver>, fig4b_hertz_damped-<solver>, fig4b_linear-<solver>
 *                    Fig. 4b's excitation for 20 ms with Thornton's law, damped Hertz and the linear
 *                    spring-dashpot
 *   cavity-<solver>  the two-sided case (upper_stop): an impact damper, a steel sphere in a cavity
 *                    20 mm high shaken at 1 mm, 50 Hz, damped Hertz (tests/driver_common.h), for
 *                    30 ms: y every 1e-5 s, the impact counts of both walls (each checked > 0)
 *   fig4b-me, fig5a-me, cavity-me    the same runs through Model Exchange, this driver integrating
 *                    (classical Runge-Kutta, fixed step 1e-6 s, events at the end of the step where an
 *                    event indicator changes sign): y every 1e-5 s, the event and impact counts
 *   refusals         bad parameter values, calls in the wrong order or with bad arguments, a missing
 *                    profile file: the status of every call and the messages logged
 *   rollback         per solver: a run from an FMU state, from its serialized copy and after
 *                    fmi2Reset equals the first run bit for bit (checked here, in this binary); y of
 *                    the first run
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DRIVER_NAME "fmu_driver"
#include "driver_common.h"
#include "fmi2Functions.h"
#include "vi_variables.h"

#define N_INSTANCES 24

static long live_blocks; /* allocateMemory minus freeMemory */
static int failures;

static void *allocate(size_t n, size_t size)
{
    void *p = calloc(n, size);
    if (p) live_blocks++;
    return p;
}

static void release(void *p)
{
    if (p) live_blocks--;
    free(p);
}

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env, (void)name, (void)status, (void)category, (void)message; /* errors are expected here */
}

static const fmi2CallbackFunctions callbacks = {logger, allocate, release, NULL, NULL};

/* The fmi2* functions of the loaded binary. */
static struct {
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2SetupExperimentTYPE *setup;
    fmi2EnterInitializationModeTYPE *enter_init;
    fmi2ExitInitializationModeTYPE *exit_init;
    fmi2TerminateTYPE *terminate;
    fmi2ResetTYPE *reset;
    fmi2GetRealTYPE *get_real;
    fmi2GetIntegerTYPE *get_integer;
    fmi2GetBooleanTYPE *get_boolean;
    fmi2GetStringTYPE *get_string;
    fmi2SetRealTYPE *set_real;
    fmi2SetIntegerTYPE *set_integer;
    fmi2SetBooleanTYPE *set_boolean;
    fmi2SetStringTYPE *set_string;
    fmi2SetRealInputDerivativesTYPE *set_derivatives;
    fmi2DoStepTYPE *do_step;
    fmi2GetFMUstateTYPE *get_state;
    fmi2SetFMUstateTYPE *set_state;
    fmi2FreeFMUstateTYPE *free_state;
    fmi2SerializedFMUstateSizeTYPE *state_size;
    fmi2SerializeFMUstateTYPE *serialize;
    fmi2DeSerializeFMUstateTYPE *deserialize;
    fmi2GetRealStatusTYPE *real_status;
    fmi2SetDebugLoggingTYPE *debug_logging;
    /* Model Exchange */
    fmi2EnterEventModeTYPE *enter_event;
    fmi2NewDiscreteStatesTYPE *new_discrete;
    fmi2EnterContinuousTimeModeTYPE *enter_ct;
    fmi2CompletedIntegratorStepTYPE *completed;
    fmi2SetTimeTYPE *set_time;
    fmi2SetContinuousStatesTYPE *set_states;
    fmi2GetContinuousStatesTYPE *get_states;
    fmi2GetDerivativesTYPE *get_derivatives;
    fmi2GetEventIndicatorsTYPE *get_indicators;
    fmi2GetNominalsOfContinuousStatesTYPE *get_nominals;
    fmi2GetDirectionalDerivativeTYPE *directional;
} F;

static void load(const char *path)
{
    lib_close();
    if (!lib_open(path)) exit(2);
#define SYM(field, name)                                                  \
    do {                                                                  \
        *(void **)&F.field = lib_symbol(name);                            \
        if (!F.field) {                                                   \
            fprintf(stderr, "fmu_driver: %s is not exported\n", name);    \
            exit(2);                                                      \
        }                                                                 \
    } while (0)
    SYM(instantiate, "fmi2Instantiate");
    SYM(free_instance, "fmi2FreeInstance");
    SYM(setup, "fmi2SetupExperiment");
    SYM(enter_init, "fmi2EnterInitializationMode");
    SYM(exit_init, "fmi2ExitInitializationMode");
    SYM(terminate, "fmi2Terminate");
    SYM(reset, "fmi2Reset");
    SYM(get_real, "fmi2GetReal");
    SYM(get_integer, "fmi2GetInteger");
    SYM(get_boolean, "fmi2GetBoolean");
    SYM(get_string, "fmi2GetString");
    SYM(set_real, "fmi2SetReal");
    SYM(set_integer, "fmi2SetInteger");
    SYM(set_boolean, "fmi2SetBoolean");
    SYM(set_string, "fmi2SetString");
    SYM(set_derivatives, "fmi2SetRealInputDerivatives");
    SYM(do_step, "fmi2DoStep");
    SYM(get_state, "fmi2GetFMUstate");
    SYM(set_state, "fmi2SetFMUstate");
    SYM(free_state, "fmi2FreeFMUstate");
    SYM(state_size, "fmi2SerializedFMUstateSize");
    SYM(serialize, "fmi2SerializeFMUstate");
    SYM(deserialize, "fmi2DeSerializeFMUstate");
    SYM(real_status, "fmi2GetRealStatus");
    SYM(debug_logging, "fmi2SetDebugLogging");
    SYM(enter_event, "fmi2EnterEventMode");
    SYM(new_discrete, "fmi2NewDiscreteStates");
    SYM(enter_ct, "fmi2EnterContinuousTimeMode");
    SYM(completed, "fmi2CompletedIntegratorStep");
    SYM(set_time, "fmi2SetTime");
    SYM(set_states, "fmi2SetContinuousStates");
    SYM(get_states, "fmi2GetContinuousStates");
    SYM(get_derivatives, "fmi2GetDerivatives");
    SYM(get_indicators, "fmi2GetEventIndicators");
    SYM(get_nominals, "fmi2GetNominalsOfContinuousStates");
    SYM(directional, "fmi2GetDirectionalDerivative");
#undef SYM
}

#define EXPECT(cond)                                                             \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "fmu_driver:%d: failed: %s\n", __LINE__, #cond);     \
            failures++;                                                          \
        }                                                                        \
    } while (0)

static fmi2Component instantiate(const char *name, const char *resources)
{
    fmi2Component c = F.instantiate(name, fmi2CoSimulation, VI_GUID, resources, &callbacks, fmi2False, fmi2False);
    EXPECT(c != NULL);
    return c;
}

/* Set parameters (reals, then the law) and initialize at t = 0. */
static fmi2Status initialize(fmi2Component c, int law, double a, double Y)
{
    const fmi2ValueReference vr[] = {VI_VR_a, VI_VR_Y};
    const fmi2Real v[] = {a, Y};
    const fmi2ValueReference law_vr = VI_VR_contact_model;
    const fmi2Integer law_v = law;
    EXPECT(F.setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) == fmi2OK);
    EXPECT(F.enter_init(c) == fmi2OK);
    EXPECT(F.set_real(c, vr, 2, v) == fmi2OK);
    EXPECT(F.set_integer(c, &law_vr, 1, &law_v) == fmi2OK);
    return F.exit_init(c);
}

/* Every variable of every type once. */
static void read_all(fmi2Component c)
{
    for (fmi2ValueReference vr = 0; vr < VI_NVARS; vr++) {
        fmi2Real r;
        fmi2Integer i;
        fmi2Boolean b;
        fmi2String s;
        fmi2Status st = F.get_real(c, &vr, 1, &r);
        if (st != fmi2OK) st = F.get_integer(c, &vr, 1, &i);
        if (st != fmi2OK) st = F.get_boolean(c, &vr, 1, &b);
        if (st != fmi2OK) st = F.get_string(c, &vr, 1, &s);
        EXPECT(st == fmi2OK);
    }
}

static void steps(fmi2Component c, double *t, int n, double h)
{
    for (int k = 0; k < n; k++, *t += h) EXPECT(F.do_step(c, *t, h, fmi2True) == fmi2OK);
}

/* FMU states: get, serialize, deserialize, set, a corrupted copy refused. */
static void states(fmi2Component c, double *t)
{
    fmi2FMUstate s = NULL, back = NULL;
    size_t n = 0;
    EXPECT(F.get_state(c, &s) == fmi2OK);
    EXPECT(F.get_state(c, &s) == fmi2OK); /* reuses the block */
    EXPECT(F.state_size(c, s, &n) == fmi2OK && n > 0);
    fmi2Byte *bytes = malloc(n);
    EXPECT(F.serialize(c, s, bytes, n) == fmi2OK);
    EXPECT(F.deserialize(c, bytes, n, &back) == fmi2OK);
    EXPECT(F.deserialize(c, bytes, n, &back) == fmi2OK); /* into the existing block */
    bytes[n / 2] ^= 0x10;
    fmi2FMUstate bad = NULL;
    EXPECT(F.deserialize(c, bytes, n, &bad) == fmi2Error && bad == NULL);
    EXPECT(F.deserialize(c, bytes, n - 1, &bad) == fmi2Error && bad == NULL);
    free(bytes);
    double t0 = *t;
    steps(c, t, 20, 1e-4);
    EXPECT(F.set_state(c, back) == fmi2OK);
    *t = t0;
    steps(c, t, 20, 1e-4);
    EXPECT(F.free_state(c, &s) == fmi2OK && s == NULL);
    EXPECT(F.free_state(c, &back) == fmi2OK && back == NULL);
}

/* Calls that must be refused, without harm. */
static void refusals(fmi2Component c, double t)
{
    const fmi2ValueReference unknown = 100000, m = VI_VR_m, file = VI_VR_profile_file, y = VI_VR_yC_in;
    fmi2Real r = 1.0;
    fmi2String long_string;
    static char text[VI_STRING_SIZE + 8];
    memset(text, 'x', sizeof text - 1);
    long_string = text;
    const fmi2Integer order = 2;
    EXPECT(F.get_real(c, &unknown, 1, &r) == fmi2Error);
    EXPECT(F.set_real(c, &m, 1, &r) == fmi2Error);             /* fixed after initialization */
    EXPECT(F.set_string(c, &file, 1, &long_string) == fmi2Error);
    EXPECT(F.set_derivatives(c, &y, 1, &order, &r) == fmi2Error); /* order 2 */
    EXPECT(F.do_step(c, t, 5e-324, fmi2True) == fmi2Error);
    EXPECT(F.do_step(c, t + 1.0, 1e-4, fmi2True) == fmi2Error);
    EXPECT(F.do_step(c, t, -1.0, fmi2True) == fmi2Error);
    EXPECT(F.set_state(c, NULL) == fmi2Error);
    fmi2String categories[] = {"logEvents", "logNothing"};
    EXPECT(F.debug_logging(c, fmi2True, 2, categories) == fmi2Error);
    EXPECT(F.debug_logging(c, fmi2True, 1, categories) == fmi2OK);
}

/* LayerTest through the generic calls only, with resource URIs of every kind. */
/* The event iteration of Model Exchange, then continuous-time mode again. */
static void event_iteration(fmi2Component c)
{
    fmi2EventInfo info = {.newDiscreteStatesNeeded = fmi2True};
    for (int k = 0; k < 20 && info.newDiscreteStatesNeeded && !info.terminateSimulation; k++)
        EXPECT(F.new_discrete(c, &info) == fmi2OK);
    EXPECT(F.enter_ct(c) == fmi2OK);
}

/* Model Exchange: each law under excitation integrated by forward Euler (the events at the end of the
 * steps that cross), every variable read, the Jacobian, FMU states in continuous-time mode, refused
 * calls. */
static void model_exchange(const char *resources)
{
    for (int law = 1; law <= 3; law++) {
        fmi2Component c = F.instantiate("me", fmi2ModelExchange, VI_GUID, resources, &callbacks, fmi2False, fmi2False);
        EXPECT(c != NULL);
        if (!c) continue;
        EXPECT(initialize(c, law, 1e-4, 6e8) == fmi2OK);
        event_iteration(c);
        double x[ME_NX], dx[ME_NX], z[ME_NZ], z_old[ME_NZ], nominal[ME_NX], t = 0.0, h = 1e-7;
        EXPECT(F.get_states(c, x, ME_NX) == fmi2OK && F.get_nominals(c, nominal, ME_NX) == fmi2OK);
        EXPECT(F.get_indicators(c, z_old, ME_NZ) == fmi2OK);
        int events = 0;
        for (int k = 0; k < 30000; k++) { /* 3 ms */
            EXPECT(F.get_derivatives(c, dx, ME_NX) == fmi2OK);
            t += h;
            for (int i = 0; i < ME_NX; i++) x[i] += h * dx[i];
            EXPECT(F.set_time(c, t) == fmi2OK && F.set_states(c, x, ME_NX) == fmi2OK);
            EXPECT(F.get_indicators(c, z, ME_NZ) == fmi2OK);
            fmi2Boolean enter = fmi2False, terminate = fmi2False;
            EXPECT(F.completed(c, fmi2True, &enter, &terminate) == fmi2OK);
            int crossed = 0;
            for (int i = 0; i < ME_NZ; i++) crossed |= (z[i] > 0) != (z_old[i] > 0);
            if (crossed || enter) {
                EXPECT(F.enter_event(c) == fmi2OK);
                event_iteration(c);
                EXPECT(F.get_states(c, x, ME_NX) == fmi2OK && F.get_indicators(c, z, ME_NZ) == fmi2OK);
                events++;
            }
            for (int i = 0; i < ME_NZ; i++) z_old[i] = z[i];
        }
        EXPECT(events > 0);
        read_all(c);
        const fmi2ValueReference unknown[] = {VI_VR_der_y, VI_VR_der_v, VI_VR_F}, known[] = {VI_VR_y};
        const fmi2Real seed[] = {1.0};
        fmi2Real j[3];
        EXPECT(F.directional(c, unknown, 3, known, 1, seed, j) == fmi2OK);
        fmi2FMUstate s = NULL, back = NULL;
        size_t n = 0;
        EXPECT(F.get_state(c, &s) == fmi2OK && F.state_size(c, s, &n) == fmi2OK);
        fmi2Byte *bytes = malloc(n);
        EXPECT(F.serialize(c, s, bytes, n) == fmi2OK && F.deserialize(c, bytes, n, &back) == fmi2OK);
        free(bytes);
        EXPECT(F.set_state(c, back) == fmi2OK);
        EXPECT(F.free_state(c, &s) == fmi2OK && F.free_state(c, &back) == fmi2OK);
        const double bad[ME_NX] = {NAN, 0.0, 0.0};
        fmi2EventInfo info;
        EXPECT(F.set_states(c, bad, ME_NX) == fmi2Error && F.set_states(c, x, ME_NX + 1) == fmi2Error);
        EXPECT(F.new_discrete(c, &info) == fmi2Error && F.set_time(c, t - 1e-3) == fmi2Error);
        EXPECT(F.do_step(c, t, 1e-4, fmi2True) == fmi2Error);
        EXPECT(F.terminate(c) == fmi2OK);
        F.free_instance(c);
    }
}

static void layer_test(const char *path, const char *guid)
{
    load(path);
    static const char *const uris[] = {"file:///tmp/%41b%2fc%7e%7E%zz/resources", "file:/tmp/resources",
                                       "file://localhost/tmp/resources", "file://otherhost/tmp", "http://x/y",
                                       "", NULL};
    for (size_t i = 0; i < sizeof uris / sizeof uris[0]; i++) {
        fmi2Component c = F.instantiate("layer", fmi2CoSimulation, guid, uris[i], &callbacks, fmi2False, fmi2False);
        EXPECT(c != NULL);
        if (!c) continue;
        EXPECT(F.setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) == fmi2OK);
        EXPECT(F.enter_init(c) == fmi2OK);
        EXPECT(F.exit_init(c) == fmi2OK);
        double t = 0.0;
        steps(c, &t, 10, 0.01);
        fmi2FMUstate s = NULL;
        EXPECT(F.get_state(c, &s) == fmi2OK);
        steps(c, &t, 10, 0.01);
        EXPECT(F.set_state(c, s) == fmi2OK);
        EXPECT(F.free_state(c, &s) == fmi2OK);
        F.free_instance(c);
    }
}

/* The checks for the memory checkers (the first form of the command line). */
static int check_binary(int argc, char **argv)
{
    load(argv[1]);
    const char *resources = argv[2];

    /* One instance through its whole life, twice (fmi2Reset in between). */
    fmi2Component c = instantiate("driver", resources);
    for (int round = 0; round < 2; round++) {
        EXPECT(initialize(c, VI_ContactModel_hertz, 1e-4, 6e8) == fmi2OK);
        const fmi2ValueReference y = VI_VR_yC_in;
        const fmi2Integer one = 1;
        const fmi2Real slope = 1e-3, value = 1e-7;
        double t = 0.0;
        steps(c, &t, 50, 1e-4);
        EXPECT(F.set_real(c, &y, 1, &value) == fmi2OK);
        EXPECT(F.set_derivatives(c, &y, 1, &one, &slope) == fmi2OK);
        steps(c, &t, 50, 1e-4);
        read_all(c);
        const fmi2ValueReference n_vr = VI_VR_n_impacts;
        fmi2Integer impacts = 0;
        EXPECT(F.get_integer(c, &n_vr, 1, &impacts) == fmi2OK && impacts > 0); /* events happened */
        states(c, &t);
        refusals(c, t);
        fmi2Real last;
        EXPECT(F.real_status(c, fmi2LastSuccessfulTime, &last) == fmi2OK && fabs(last - t) < 1e-12);
        EXPECT(F.terminate(c) == fmi2OK);
        EXPECT(F.reset(c) == fmi2OK);
    }

    /* A state taken before initialization, restored into a running instance. */
    fmi2FMUstate early = NULL;
    EXPECT(F.get_state(c, &early) == fmi2OK);
    EXPECT(initialize(c, VI_ContactModel_johnson, 1e-4, 2e8) == fmi2OK);
    double t = 0.0;
    steps(c, &t, 30, 1e-4);
    EXPECT(F.set_state(c, early) == fmi2OK);
    EXPECT(initialize(c, VI_ContactModel_lepp, 1e-4, 6e8) == fmi2OK);
    t = 0.0;
    steps(c, &t, 30, 1e-4);
    read_all(c);
    EXPECT(F.free_state(c, &early) == fmi2OK);

    /* A failed initialization (Y = 1e300 is in its range, but the yield force overflows), then reset. */
    EXPECT(F.reset(c) == fmi2OK);
    EXPECT(initialize(c, VI_ContactModel_johnson, 1e-4, 1e300) == fmi2Error);
    EXPECT(F.do_step(c, 0.0, 1e-4, fmi2True) == fmi2Error);
    EXPECT(F.reset(c) == fmi2OK);
    F.free_instance(c);
    F.free_instance(NULL);

    /* Many instances at once, interleaved, each with its own law. */
    fmi2Component many[N_INSTANCES];
    char name[32];
    for (int i = 0; i < N_INSTANCES; i++) {
        snprintf(name, sizeof name, "instance %d", i);
        many[i] = instantiate(name, resources);
        EXPECT(initialize(many[i], 1 + i % 3, 1e-4, 6e8) == fmi2OK);
    }
    for (int k = 0; k < 20; k++)
        for (int i = 0; i < N_INSTANCES; i++) EXPECT(F.do_step(many[i], k * 1e-4, 1e-4, fmi2True) == fmi2OK);
    for (int i = 0; i < N_INSTANCES; i++) F.free_instance(many[i]);

    /* Instantiation refused: no leak either. */
    EXPECT(F.instantiate("bad", fmi2CoSimulation, "{wrong}", resources, &callbacks, fmi2False, fmi2False) == NULL);
    EXPECT(F.instantiate("bad", (fmi2Type)7, VI_GUID, resources, &callbacks, fmi2False, fmi2False) == NULL);

    model_exchange(resources);

    if (argc == 5) layer_test(argv[3], argv[4]);

    EXPECT(live_blocks == 0);
    lib_close();
    if (failures) fprintf(stderr, "fmu_driver: %d checks failed, %ld blocks not freed\n", failures, live_blocks);
    else printf("fmu_driver: all checks passed\n");
    return failures ? 1 : 0;
}

/* ---- records for comparing platforms ------------------------------------------------------------ */

#define ROLLBACK_STEPS 1000  /* steps of 1e-5 s run from the state at 10 ms (to 20 ms: one more impact) */
#define LOG_SIZE 4096        /* characters of the messages kept per call */
#define LAYER_VR_resource_value 10 /* tests/layer_fmu/layer_variables.h: the row of resource_value */

static const char *const status_names[] = {"OK", "Warning", "Discard", "Error", "Fatal", "Pending"};

static const char *status_name(fmi2Status st)
{
    return (unsigned)st < sizeof status_names / sizeof status_names[0] ? status_names[st] : "?";
}

/* What the FMU logged since the last call of print_status (warnings and errors: logging is off). */
static char logged[LOG_SIZE];

static void record_logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                          fmi2String message, ...)
{
    (void)env, (void)name;
    char text[LOG_SIZE];
    va_list ap;
    va_start(ap, message);
    vsnprintf(text, sizeof text, message, ap); /* the message is a format (FMI 2.0, 2.1.5) */
    va_end(ap);
    size_t n = strlen(logged);
    snprintf(logged + n, sizeof logged - n, " [%s %s] ", status_name(status), category ? category : "");
    strncat(logged, text, sizeof logged - strlen(logged) - 1);
}

static const fmi2CallbackFunctions record_callbacks = {record_logger, allocate, release, NULL, NULL};

/* One exact line: the label, the status of the call and what was logged during it. */
static void print_status(const char *label, fmi2Status st)
{
    printf("= %s: %s%s\n", label, status_name(st), logged);
    logged[0] = '\0';
}

static fmi2Component new_instance(void)
{
    logged[0] = '\0';
    return F.instantiate("driver", fmi2CoSimulation, VI_GUID, NULL, &record_callbacks, fmi2False, fmi2False);
}

static fmi2Status set_real_value(fmi2Component c, fmi2ValueReference vr, double value)
{
    return F.set_real(c, &vr, 1, &value);
}

static fmi2Status set_integer_value(fmi2Component c, fmi2ValueReference vr, int value)
{
    const fmi2Integer v = value;
    return F.set_integer(c, &vr, 1, &v);
}

static double get_real_value(fmi2Component c, fmi2ValueReference vr)
{
    fmi2Real v = NAN;
    EXPECT(F.get_real(c, &vr, 1, &v) == fmi2OK);
    return v;
}

static int get_integer_value(fmi2Component c, fmi2ValueReference vr)
{
    fmi2Integer v = -1;
    EXPECT(F.get_integer(c, &vr, 1, &v) == fmi2OK);
    return (int)v;
}

/* The scenarios, solvers and record settings: tests/driver_common.h. */

/* The two-sided case's settings (upper_stop = true and the impact damper's parameters); fmi2OK or
 * the first failure. */
static fmi2Status set_two_sided(fmi2Component c)
{
    const fmi2ValueReference upper_stop = VI_VR_upper_stop;
    const fmi2Boolean on = fmi2True;
    fmi2Status st = F.set_boolean(c, &upper_stop, 1, &on);
    for (size_t i = 0; i < N_TWO_SIDED_REALS && st == fmi2OK; i++)
        st = set_real_value(c, two_sided_reals[i].vr, two_sided_reals[i].value);
    for (size_t i = 0; i < N_TWO_SIDED_ENUMS && st == fmi2OK; i++)
        st = set_integer_value(c, two_sided_enums[i].vr, (int)two_sided_enums[i].value);
    return st;
}

/* The two-sided case's record line: the upper contact's impacts; both walls must have been hit. */
static void print_two_sided(fmi2Component c, const scenario *sc)
{
    if (!sc->two_sided) return;
    int lower = get_integer_value(c, VI_VR_n_impacts), upper = get_integer_value(c, VI_VR_n_impacts_upper);
    printf("= n_impacts_upper %d\n", upper);
    EXPECT(lower > 0 && upper > 0);
}

/* Instantiate and initialize one scenario with one solver at RTOL_CASES; NULL on failure. */
static fmi2Component start_scenario(const scenario *sc, int solver)
{
    fmi2Component c = new_instance();
    EXPECT(c != NULL);
    if (!c) return NULL;
    fmi2Status st = F.setup(c, fmi2True, RTOL_CASES, 0.0, fmi2False, 0.0);
    if (st == fmi2OK) st = F.enter_init(c);
    if (st == fmi2OK) st = set_integer_value(c, VI_VR_contact_model, sc->law);
    if (st == fmi2OK) st = set_integer_value(c, VI_VR_solver, solver);
    if (st == fmi2OK) st = set_real_value(c, VI_VR_a, sc->a);
    if (st == fmi2OK) st = set_real_value(c, VI_VR_f, sc->f);
    if (st == fmi2OK) st = set_real_value(c, VI_VR_Y, sc->Y);
    if (st == fmi2OK && sc->two_sided) st = set_two_sided(c);
    if (st == fmi2OK) st = F.exit_init(c);
    if (st != fmi2OK) {
        fprintf(stderr, "fmu_driver: %s did not initialize:%s\n", sc->name, logged);
        failures++;
        F.free_instance(c);
        return NULL;
    }
    return c;
}

/* Steps k0 .. k0 + n - 1 of H_CASES; y and F after each into ys[2 n] (when given); 0, or -1 when a step
 * fails. */
static int run_steps(fmi2Component c, long k0, long n, double *ys)
{
    for (long k = k0; k < k0 + n; k++) {
        fmi2Status st = F.do_step(c, k * H_CASES, H_CASES, fmi2True);
        if (st != fmi2OK) {
            fprintf(stderr, "fmu_driver: step %ld: %s%s\n", k, status_name(st), logged);
            failures++;
            return -1;
        }
        if (ys) {
            ys[2 * (k - k0)] = get_real_value(c, VI_VR_y);
            ys[2 * (k - k0) + 1] = get_real_value(c, VI_VR_F);
        }
    }
    return 0;
}

static void case_trajectory(const scenario *sc, size_t solver)
{
    fmi2Component c = start_scenario(sc, solver_values[solver]);
    if (!c) return;
    const long n = lround(sc->t_stop / H_CASES);
    printf("# %s, solver %s, rtol %g, %ld steps of %g s: t y\n", sc->name, solver_names[solver], RTOL_CASES, n,
           H_CASES);
    for (long k = 0; k < n; k++) {
        if (run_steps(c, k, 1, NULL) < 0) break;
        printf("~ y %.17g %.17g\n", (k + 1) * H_CASES, get_real_value(c, VI_VR_y));
    }
    printf("= n_impacts %d\n", get_integer_value(c, VI_VR_n_impacts));
    print_two_sided(c, sc);
    F.free_instance(c);
}

/* A parameter value outside its range, set in initialization mode. */
typedef struct {
    const char *label;
    fmi2ValueReference vr;
    int is_integer;
    double value;
} bad_value;

static void case_refusals(void)
{
    static const bad_value bad[] = {
        {"m = -1", VI_VR_m, 0, -1.0},
        {"m = NaN", VI_VR_m, 0, NAN},
        {"P = inf", VI_VR_P, 0, INFINITY},
        {"E1 = 0", VI_VR_E1, 0, 0.0},
        {"nu2 = 0.6", VI_VR_nu2, 0, 0.6},
        {"Y = -6e8", VI_VR_Y, 0, -6e8},
        {"theta_Y = 0", VI_VR_theta_Y, 0, 0.0},
        {"R1 = 0 and R2 = 0", VI_VR_R1, 0, 0.0}, /* R2 starts at 0: two planes */
        {"f = -1", VI_VR_f, 0, -1.0},
        {"rtol = 1e-15", VI_VR_rtol, 0, 1e-15}, /* 0 is the experiment's tolerance; (0, 1e-14) is refused */
        {"max_step = -1e-3", VI_VR_max_step, 0, -1e-3},
        {"contact_model = 7", VI_VR_contact_model, 1, 7},
        {"unloading = 0", VI_VR_unloading, 1, 0},
        {"solver = 5", VI_VR_solver, 1, 5},
        {"init = 3", VI_VR_init, 1, 3},
    };
    char label[128];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        fmi2Component c = new_instance();
        EXPECT(c != NULL);
        if (!c) continue;
        EXPECT(F.setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) == fmi2OK);
        EXPECT(F.enter_init(c) == fmi2OK);
        fmi2Status set = bad[i].is_integer ? set_integer_value(c, bad[i].vr, (int)bad[i].value)
                                           : set_real_value(c, bad[i].vr, bad[i].value);
        snprintf(label, sizeof label, "set %s", bad[i].label);
        print_status(label, set);
        fmi2Status init = F.exit_init(c);
        snprintf(label, sizeof label, "fmi2ExitInitializationMode after %s", bad[i].label);
        print_status(label, init);
        EXPECT(set != fmi2OK || init != fmi2OK); /* refused at one of the two */
        fmi2Status step = F.do_step(c, 0.0, 1e-4, fmi2True);
        snprintf(label, sizeof label, "fmi2DoStep after %s", bad[i].label);
        print_status(label, step);
        EXPECT(init == fmi2OK || step == fmi2Error);
        F.free_instance(c);
    }

    /* Calls in the wrong order or with bad arguments. */
    fmi2Component c = new_instance();
    EXPECT(c != NULL);
    if (!c) return;
    const fmi2ValueReference m = VI_VR_m, unknown = 100000, y_in = VI_VR_yC_in, file = VI_VR_profile_file;
    fmi2Real r = 1.0;
    fmi2FMUstate state = NULL;
    print_status("fmi2DoStep before initialization", F.do_step(c, 0.0, 1e-4, fmi2True));
    print_status("fmi2ExitInitializationMode before fmi2EnterInitializationMode", F.exit_init(c));
    print_status("fmi2Terminate before initialization", F.terminate(c));
    print_status("fmi2SetupExperiment", F.setup(c, fmi2True, 1e-8, 0.0, fmi2True, 1e-3));
    print_status("fmi2EnterInitializationMode", F.enter_init(c));
    print_status("fmi2EnterInitializationMode again", F.enter_init(c));
    print_status("fmi2SetupExperiment in initialization mode", F.setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    print_status("fmi2GetReal of an unknown value reference", F.get_real(c, &unknown, 1, &r));
    print_status("fmi2ExitInitializationMode", F.exit_init(c));
    print_status("fmi2SetReal of the fixed parameter m after initialization", F.set_real(c, &m, 1, &r));
    const fmi2String name = "profile.txt";
    print_status("fmi2SetString of the fixed profile_file after initialization", F.set_string(c, &file, 1, &name));
    const fmi2Integer order = 2;
    print_status("fmi2SetRealInputDerivatives of order 2", F.set_derivatives(c, &y_in, 1, &order, &r));
    print_status("fmi2DoStep from the wrong time", F.do_step(c, 0.5, 1e-4, fmi2True));
    print_status("fmi2DoStep of -1 s", F.do_step(c, 0.0, -1.0, fmi2True));
    print_status("fmi2DoStep of 5e-324 s", F.do_step(c, 0.0, 5e-324, fmi2True));
    print_status("fmi2DoStep of NaN s", F.do_step(c, 0.0, NAN, fmi2True));
    print_status("fmi2DoStep past the stop time", F.do_step(c, 0.0, 2e-3, fmi2True));
    print_status("fmi2DoStep", F.do_step(c, 0.0, 1e-4, fmi2True));
    print_status("fmi2SetFMUstate of NULL", F.set_state(c, NULL));
    const fmi2Byte garbage[64] = {1, 2, 3};
    print_status("fmi2DeSerializeFMUstate of 64 bytes of garbage", F.deserialize(c, garbage, sizeof garbage, &state));
    EXPECT(state == NULL);
    fmi2Real last = NAN;
    print_status("fmi2GetRealStatus(fmi2LastSuccessfulTime)", F.real_status(c, fmi2LastSuccessfulTime, &last));
    printf("= last successful time %.17g\n", last);
    print_status("fmi2Terminate", F.terminate(c));
    print_status("fmi2DoStep after fmi2Terminate", F.do_step(c, 1e-4, 1e-4, fmi2True));
    print_status("fmi2Reset", F.reset(c));
    print_status("fmi2DoStep after fmi2Reset", F.do_step(c, 0.0, 1e-4, fmi2True));

    /* A profile file that is not there. */
    const fmi2String missing = "no-such-profile.txt";
    print_status("fmi2EnterInitializationMode", F.enter_init(c));
    print_status("fmi2SetString profile_file = no-such-profile.txt", F.set_string(c, &file, 1, &missing));
    print_status("fmi2ExitInitializationMode with a missing profile", F.exit_init(c));
    print_status("fmi2Reset", F.reset(c));
    F.free_instance(c);

    logged[0] = '\0';
    fmi2Component other =
        F.instantiate("driver", fmi2CoSimulation, "{wrong}", NULL, &record_callbacks, fmi2False, fmi2False);
    printf("= fmi2Instantiate with a wrong GUID: %s%s\n", other ? "an instance" : "NULL", logged);
    EXPECT(other == NULL);
    logged[0] = '\0';
    other = F.instantiate("driver", fmi2ModelExchange, VI_GUID, NULL, &record_callbacks, fmi2False, fmi2False);
    printf("= fmi2Instantiate for Model Exchange: %s%s\n", other ? "an instance" : "NULL", logged);
    logged[0] = '\0';
    if (other) F.free_instance(other);
}

/* ---- Model Exchange: this driver as the importer's integrator ------------------------------------- */


static struct {
    fmi2SetTimeTYPE *set_time;
    fmi2SetContinuousStatesTYPE *set_states;
    fmi2GetContinuousStatesTYPE *get_states;
    fmi2GetDerivativesTYPE *get_derivatives;
    fmi2GetEventIndicatorsTYPE *get_indicators;
    fmi2CompletedIntegratorStepTYPE *completed_step;
    fmi2EnterEventModeTYPE *enter_event_mode;
    fmi2NewDiscreteStatesTYPE *new_discrete_states;
    fmi2EnterContinuousTimeModeTYPE *enter_continuous;
} M;

static void load_me(void)
{
#define SYM(field, name)                                                  \
    do {                                                                  \
        *(void **)&M.field = lib_symbol(name);                            \
        if (!M.field) {                                                   \
            fprintf(stderr, "fmu_driver: %s is not exported\n", name);    \
            exit(2);                                                      \
        }                                                                 \
    } while (0)
    SYM(set_time, "fmi2SetTime");
    SYM(set_states, "fmi2SetContinuousStates");
    SYM(get_states, "fmi2GetContinuousStates");
    SYM(get_derivatives, "fmi2GetDerivatives");
    SYM(get_indicators, "fmi2GetEventIndicators");
    SYM(completed_step, "fmi2CompletedIntegratorStep");
    SYM(enter_event_mode, "fmi2EnterEventMode");
    SYM(new_discrete_states, "fmi2NewDiscreteStates");
    SYM(enter_continuous, "fmi2EnterContinuousTimeMode");
#undef SYM
}

/* Event mode until the discrete states settle, then continuous-time mode; the states and indicators
 * after it. 0, or -1 (counted as a failure). */
static int me_event_iteration(fmi2Component c, double *x, double *z, long *passes)
{
    fmi2EventInfo ev = {.newDiscreteStatesNeeded = fmi2True};
    for (int k = 0; k < ME_EVENT_PASSES && ev.newDiscreteStatesNeeded; k++, (*passes)++)
        if (M.new_discrete_states(c, &ev) != fmi2OK) return failures++, -1;
    EXPECT(!ev.newDiscreteStatesNeeded && !ev.terminateSimulation && !ev.nextEventTimeDefined);
    if (M.enter_continuous(c) != fmi2OK || M.get_states(c, x, ME_NX) != fmi2OK ||
        M.get_indicators(c, z, ME_NZ) != fmi2OK)
        return failures++, -1;
    return 0;
}

/* x' at (t, x) into dx; 0, or -1 (derivatives_fn). */
static int me_derivatives(void *c, double t, const double *x, double *dx)
{
    return M.set_time(c, t) == fmi2OK && M.set_states(c, x, ME_NX) == fmi2OK &&
                   M.get_derivatives(c, dx, ME_NX) == fmi2OK
               ? 0
               : -1;
}

/* A scenario through Model Exchange: classical Runge-Kutta with the fixed step ME_H, an event where
 * an indicator changes sign over a step or the FMU asks for one (no root location: the event is
 * handled at the end of that step); y after every 1e-5 s, the event count. */
static void case_model_exchange(const scenario *sc)
{
    load_me();
    logged[0] = '\0';
    fmi2Component c = F.instantiate("me", fmi2ModelExchange, VI_GUID, NULL, &record_callbacks, fmi2False, fmi2False);
    EXPECT(c != NULL);
    if (!c) return;
    fmi2Status st = F.setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    if (st == fmi2OK) st = F.enter_init(c);
    if (st == fmi2OK) st = set_integer_value(c, VI_VR_contact_model, sc->law);
    if (st == fmi2OK) st = set_real_value(c, VI_VR_a, sc->a);
    if (st == fmi2OK) st = set_real_value(c, VI_VR_f, sc->f);
    if (st == fmi2OK) st = set_real_value(c, VI_VR_Y, sc->Y);
    if (st == fmi2OK && sc->two_sided) st = set_two_sided(c);
    if (st == fmi2OK) st = F.exit_init(c);
    double x[ME_NX], z[ME_NZ];
    long events = 0, passes = 0;
    if (st != fmi2OK || me_event_iteration(c, x, z, &passes) < 0) {
        fprintf(stderr, "fmu_driver: %s (Model Exchange) did not initialize:%s\n", sc->name, logged);
        failures++;
        F.free_instance(c);
        return;
    }
    const long n = lround(sc->t_stop / ME_H), every = lround(H_CASES / ME_H);
    printf("# %s, Model Exchange, classical Runge-Kutta, %ld steps of %g s: t y\n", sc->name, n, ME_H);
    for (long k = 0; k < n; k++) {
        const double t = k * ME_H, t1 = (k + 1) * ME_H;
        double z1[ME_NZ];
        int rc = rk4_step(me_derivatives, c, t, t1, x);
        fmi2Boolean enter = fmi2False, stop = fmi2False;
        if (rc == 0 && M.set_time(c, t1) == fmi2OK && M.set_states(c, x, ME_NX) == fmi2OK &&
            M.completed_step(c, fmi2True, &enter, &stop) == fmi2OK && M.get_indicators(c, z1, ME_NZ) == fmi2OK) {
            int crossed = 0;
            for (int i = 0; i < ME_NZ; i++) crossed |= (z[i] > 0.0) != (z1[i] > 0.0);
            memcpy(z, z1, sizeof z);
            if ((crossed || enter) && (M.enter_event_mode(c) != fmi2OK || me_event_iteration(c, x, z, &passes) < 0))
                rc = -1;
            events += crossed || enter;
        } else {
            rc = -1;
        }
        if (rc < 0 || stop) {
            fprintf(stderr, "fmu_driver: %s (Model Exchange) stopped at t = %g:%s\n", sc->name, t1, logged);
            failures++;
            break;
        }
        if ((k + 1) % every == 0) printf("~ y %.17g %.17g\n", (double)((k + 1) / every) * H_CASES, x[0]);
    }
    printf("= Model Exchange: %ld events, %ld passes of fmi2NewDiscreteStates, n_impacts %d\n", events, passes,
           get_integer_value(c, VI_VR_n_impacts));
    print_two_sided(c, sc);
    F.free_instance(c);
}

/* n steps' y and F equal bit for bit (NaN included). */
static int identical(const double *a, const double *b, long n)
{
    return memcmp(a, b, 2 * (size_t)n * sizeof *a) == 0;
}

static void case_rollback(void)
{
    const scenario *sc = &scenarios[0];
    const long k0 = 1000, n = ROLLBACK_STEPS;
    double *first = malloc(4 * (size_t)n * sizeof *first);
    if (!first) exit(2);
    double *again = first + 2 * n;
    for (size_t s = 0; s < N_SOLVERS; s++) {
        fmi2Component c = start_scenario(sc, solver_values[s]);
        if (!c) continue;
        fmi2FMUstate state = NULL, copy = NULL;
        size_t size = 0;
        run_steps(c, 0, k0, NULL);
        EXPECT(F.get_state(c, &state) == fmi2OK);
        EXPECT(F.state_size(c, state, &size) == fmi2OK && size > 0);
        fmi2Byte *bytes = malloc(size ? size : 1);
        if (!bytes) exit(2);
        EXPECT(F.serialize(c, state, bytes, size) == fmi2OK);
        run_steps(c, k0, n, first);

        EXPECT(F.set_state(c, state) == fmi2OK);
        run_steps(c, k0, n, again);
        int from_state = identical(first, again, n);

        EXPECT(F.deserialize(c, bytes, size, &copy) == fmi2OK);
        EXPECT(F.set_state(c, copy) == fmi2OK);
        run_steps(c, k0, n, again);
        int from_bytes = identical(first, again, n);

        /* fmi2Reset, the same initialization, the same calls */
        EXPECT(F.reset(c) == fmi2OK);
        EXPECT(F.setup(c, fmi2True, RTOL_CASES, 0.0, fmi2False, 0.0) == fmi2OK);
        EXPECT(F.enter_init(c) == fmi2OK);
        EXPECT(set_integer_value(c, VI_VR_contact_model, sc->law) == fmi2OK);
        EXPECT(set_integer_value(c, VI_VR_solver, solver_values[s]) == fmi2OK);
        EXPECT(set_real_value(c, VI_VR_a, sc->a) == fmi2OK);
        EXPECT(set_real_value(c, VI_VR_f, sc->f) == fmi2OK);
        EXPECT(set_real_value(c, VI_VR_Y, sc->Y) == fmi2OK);
        EXPECT(F.exit_init(c) == fmi2OK);
        run_steps(c, 0, k0, NULL);
        fmi2FMUstate taken = NULL;
        EXPECT(F.get_state(c, &taken) == fmi2OK && F.free_state(c, &taken) == fmi2OK);
        run_steps(c, k0, n, again);
        int after_reset = identical(first, again, n);

        EXPECT(from_state && from_bytes && after_reset);
        printf("= rollback %s: from the state %s, from its serialized copy %s, after fmi2Reset %s\n",
               solver_names[s], from_state ? "identical" : "DIFFERENT", from_bytes ? "identical" : "DIFFERENT",
               after_reset ? "identical" : "DIFFERENT");
        printf("# %s, solver %s: y over the %ld steps run from the state at t = %g s\n", sc->name, solver_names[s], n,
               k0 * H_CASES);
        for (long k = 0; k < n; k++) printf("~ y %.17g %.17g\n", (k0 + k + 1) * H_CASES, first[2 * k]);
        free(bytes);
        EXPECT(F.free_state(c, &state) == fmi2OK);
        EXPECT(F.free_state(c, &copy) == fmi2OK);
        F.free_instance(c);
    }
    free(first);
}

static int list_cases(void)
{
    for (size_t i = 0; i < N_SCENARIOS; i++)
        for (size_t s = 0; s < N_SOLVERS; s++) printf("%s-%s\n", scenarios[i].name, solver_names[s]);
    for (size_t i = 0; i < N_ME_SCENARIOS; i++) printf("%s-me\n", scenarios[i].name);
    printf("refusals\nrollback\n");
    return 0;
}

static int run_case(const char *path, const char *name)
{
    load(path);
    int found = 0;
    if (strcmp(name, "refusals") == 0) {
        case_refusals();
        found = 1;
    } else if (strcmp(name, "rollback") == 0) {
        case_rollback();
        found = 1;
    }
    for (size_t i = 0; i < N_ME_SCENARIOS && !found; i++) {
        char full[64];
        snprintf(full, sizeof full, "%s-me", scenarios[i].name);
        if (strcmp(name, full) == 0) {
            case_model_exchange(&scenarios[i]);
            found = 1;
        }
    }
    for (size_t i = 0; i < N_SCENARIOS && !found; i++)
        for (size_t s = 0; s < N_SOLVERS && !found; s++) {
            char full[64];
            snprintf(full, sizeof full, "%s-%s", scenarios[i].name, solver_names[s]);
            if (strcmp(name, full) == 0) {
                case_trajectory(&scenarios[i], s);
                found = 1;
            }
        }
    if (!found) {
        fprintf(stderr, "fmu_driver: no case '%s' (fmu_driver cases lists them)\n", name);
        return 2;
    }
    EXPECT(live_blocks == 0);
    lib_close();
    fflush(stdout);
    if (failures) fprintf(stderr, "fmu_driver: %s: %d checks failed\n", name, failures);
    return failures ? 1 : 0;
}

static int layer_resource(const char *path, const char *guid, const char *uri)
{
    load(path);
    fmi2Component c = F.instantiate("layer", fmi2CoSimulation, guid, uri, &record_callbacks, fmi2False, fmi2False);
    if (!c) {
        fprintf(stderr, "fmu_driver: LayerTest refused %s:%s\n", uri, logged);
        return 1;
    }
    const fmi2ValueReference vr = LAYER_VR_resource_value;
    fmi2Real value = NAN;
    EXPECT(F.setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) == fmi2OK);
    EXPECT(F.enter_init(c) == fmi2OK);
    EXPECT(F.exit_init(c) == fmi2OK);
    EXPECT(F.get_real(c, &vr, 1, &value) == fmi2OK);
    printf("%.17g\n", value);
    F.free_instance(c);
    lib_close();
    return failures ? 1 : 0;
}

/* Any FMU on the generic layer (the vehicle-track companions): default parameters, tolerance
 * RTOL_CASES, the Real with value reference 0 (their first input) set to `input` after
 * initialization, COMPANION_STEPS steps of COMPANION_H; every Real variable after each step. */
#define COMPANION_STEPS 1000
#define COMPANION_H 1e-4 /* s */
#define VR_SCAN 256      /* value references tried */

static int run_companion(const char *path, const char *guid, double input)
{
    load(path);
    fmi2Component c = F.instantiate("companion", fmi2CoSimulation, guid, NULL, &record_callbacks, fmi2False,
                                    fmi2False);
    if (!c) {
        fprintf(stderr, "fmu_driver: %s refused the instance:%s\n", path, logged);
        return 1;
    }
    EXPECT(F.setup(c, fmi2True, RTOL_CASES, 0.0, fmi2False, 0.0) == fmi2OK);
    EXPECT(F.enter_init(c) == fmi2OK);
    EXPECT(F.exit_init(c) == fmi2OK);
    fmi2ValueReference reals[VR_SCAN];
    size_t n = 0;
    for (fmi2ValueReference vr = 0; vr < VR_SCAN; vr++) {
        fmi2Real v;
        if (F.get_real(c, &vr, 1, &v) == fmi2OK) reals[n++] = vr;
    }
    logged[0] = '\0';
    const fmi2ValueReference in = 0;
    EXPECT(n > 0 && reals[0] == 0 && F.set_real(c, &in, 1, &input) == fmi2OK);
    printf("# %s: %zu Real variables, rtol %g, input (value reference 0) %g, %d steps of %g s\n", path, n,
           RTOL_CASES, input, COMPANION_STEPS, COMPANION_H);
    for (long k = 0; k < COMPANION_STEPS; k++) {
        fmi2Status st = F.do_step(c, k * COMPANION_H, COMPANION_H, fmi2True);
        if (st != fmi2OK) {
            print_status("fmi2DoStep", st);
            failures++;
            break;
        }
        for (size_t i = 0; i < n; i++) {
            fmi2Real v = NAN;
            EXPECT(F.get_real(c, &reals[i], 1, &v) == fmi2OK);
            printf("~ vr%u %.17g %.17g\n", (unsigned)reals[i], (k + 1) * COMPANION_H, v);
        }
    }
    F.free_instance(c);
    EXPECT(live_blocks == 0);
    lib_close();
    return failures ? 1 : 0;
}

/* ---- comparing two records ------------------------------------------------------------------------ */

#define LINE_MAX_CHARS 8192
#define MAX_NAMES 64 /* variables with trajectory lines in one record */
#define NAME_SIZE 32

typedef struct {
    FILE *f;
    long line_no;
    char line[LINE_MAX_CHARS];
} record;

/* The next line without its line end (wine's programs write CR LF); 0 at the end. */
static int next_line(record *r)
{
    if (!fgets(r->line, sizeof r->line, r->f)) return 0;
    r->line_no++;
    r->line[strcspn(r->line, "\r\n")] = '\0';
    return 1;
}

/* A trajectory line "~ <name> <t> <value>": 1, or 0 for another kind of line. */
static int trajectory_line(const char *line, char name[NAME_SIZE], double *t, double *v)
{
    return sscanf(line, "~ %31s %lf %lf", name, t, v) == 3;
}

/* What a difference in one variable is measured against: the range of its values in the reference
 * record, or the largest magnitude for a constant. */
typedef struct {
    int n;
    char name[MAX_NAMES][NAME_SIZE];
    double lo[MAX_NAMES], hi[MAX_NAMES], big[MAX_NAMES], max_d[MAX_NAMES];
} scales;

static int name_index(scales *sc, const char *name)
{
    for (int i = 0; i < sc->n; i++)
        if (strcmp(sc->name[i], name) == 0) return i;
    if (sc->n == MAX_NAMES) return -1;
    snprintf(sc->name[sc->n], NAME_SIZE, "%s", name);
    sc->lo[sc->n] = INFINITY, sc->hi[sc->n] = -INFINITY, sc->big[sc->n] = 0.0, sc->max_d[sc->n] = 0.0;
    return sc->n++;
}

static double scale_of(const scales *sc, int i)
{
    return sc->hi[i] > sc->lo[i] ? sc->hi[i] - sc->lo[i] : sc->big[i];
}

static int compare_records(const char *path_a, const char *path_b, double tol)
{
    static scales sc; /* large: not on the stack */
    record a = {.f = fopen(path_a, "r")}, b = {.f = fopen(path_b, "r")};
    if (!a.f || !b.f) {
        fprintf(stderr, "fmu_driver: cannot open %s\n", !a.f ? path_a : path_b);
        return 2;
    }
    char name[NAME_SIZE], name_b[NAME_SIZE];
    double ta, va, tb, vb;
    while (next_line(&a)) { /* the scales, from the first record */
        if (!trajectory_line(a.line, name, &ta, &va)) continue;
        int i = name_index(&sc, name);
        if (i < 0) {
            fprintf(stderr, "compare: more than %d variables in %s\n", MAX_NAMES, path_a);
            return 2;
        }
        sc.lo[i] = fmin(sc.lo[i], va), sc.hi[i] = fmax(sc.hi[i], va), sc.big[i] = fmax(sc.big[i], fabs(va));
    }
    rewind(a.f);
    a.line_no = 0;
    long n_points = 0, n_exact = 0, n_exact_differ = 0, mismatches = 0;
    for (;;) { /* bounded by the records' lengths */
        int more_a = next_line(&a), more_b = next_line(&b);
        if (!more_a || !more_b) {
            if (more_a || more_b) {
                fprintf(stderr, "compare: %s ends at line %ld, the other goes on\n", more_a ? path_b : path_a,
                        more_a ? b.line_no : a.line_no);
                mismatches++;
            }
            break;
        }
        if (trajectory_line(a.line, name, &ta, &va)) {
            if (!trajectory_line(b.line, name_b, &tb, &vb) || strcmp(name, name_b) != 0 || ta != tb) {
                fprintf(stderr, "compare: line %ld: '%s' against '%s'\n", a.line_no, a.line, b.line);
                mismatches++;
                continue;
            }
            n_points++;
            int i = name_index(&sc, name);
            double d = fabs(va - vb), scale = scale_of(&sc, i);
            if (d > sc.max_d[i] || isnan(d)) sc.max_d[i] = d; /* NaN counts as a difference */
            if (!(d <= tol * scale)) {
                if (mismatches < 10)
                    fprintf(stderr, "compare: %s at t = %.17g: %.17g against %.17g (%.3g of its scale %.3g)\n", name,
                            ta, va, vb, d / scale, scale);
                mismatches++;
            }
        } else if (a.line[0] != '#') {
            n_exact++;
            if (strcmp(a.line, b.line) != 0) {
                fprintf(stderr, "compare: line %ld differs:\n  %s\n  %s\n", a.line_no, a.line, b.line);
                n_exact_differ++;
                mismatches++;
            }
        }
    }
    fclose(a.f), fclose(b.f);
    int worst = -1;
    double worst_rel = -1.0;
    for (int i = 0; i < sc.n; i++) {
        double scale = scale_of(&sc, i), rel = scale > 0 ? sc.max_d[i] / scale : (sc.max_d[i] > 0 ? INFINITY : 0.0);
        if (rel > worst_rel || isnan(rel)) worst = i, worst_rel = rel;
    }
    if (worst >= 0 && worst_rel > 0)
        printf("%ld points of %d variable(s): max difference %.2g of the range of %s (%.2g of %.3g; allowed %g)",
               n_points, sc.n, worst_rel, sc.name[worst], sc.max_d[worst], scale_of(&sc, worst), tol);
    else if (worst >= 0)
        printf("%ld points of %d variable(s): equal bit for bit", n_points, sc.n);
    if (n_exact) printf("%s%ld of %ld exact lines equal", worst >= 0 ? "; " : "", n_exact - n_exact_differ, n_exact);
    printf("%s\n", mismatches ? ": DIFFERENCES" : "");
    return mismatches ? 1 : 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "cases") == 0) return list_cases();
    if (argc == 4 && strcmp(argv[1], "run") == 0) return run_case(argv[2], argv[3]);
    if (argc == 5 && strcmp(argv[1], "layer") == 0) return layer_resource(argv[2], argv[3], argv[4]);
    if (argc == 5 && strcmp(argv[1], "companion") == 0) return run_companion(argv[2], argv[3], atof(argv[4]));
    if (argc == 5 && strcmp(argv[1], "compare") == 0) return compare_records(argv[2], argv[3], atof(argv[4]));
    if (argc == 3 || argc == 5) return check_binary(argc, argv);
    fprintf(stderr, "usage: fmu_driver <VibroImpact binary> <resources URI> [<LayerTest binary> <its GUID>]\n"
                    "       fmu_driver run <VibroImpact binary> <case>\n"
                    "       fmu_driver layer <LayerTest binary> <its GUID> <resources URI>\n"
                    "       fmu_driver companion <FMU binary> <its GUID> <input value>\n"
                    "       fmu_driver compare <record> <record> <tolerance>\n"
                    "       fmu_driver cases\n");
    return 2;
}
