/*
 * fmu_driver.c - drives the FMU binary through its fmi2* functions, as an importer would, for the
 * memory checkers: built with AddressSanitizer + UndefinedBehaviorSanitizer (cmake -DVI_SANITIZE=ON)
 * it runs against the sanitized VibroImpact.so; run under valgrind memcheck it runs against the
 * normal one. Any report of either fails the test (tools/test.sh).
 *
 *   fmu_driver <path to VibroImpact.so> <resources folder URI> [<path to LayerTest.so> <its GUID>]
 *
 * What it does: instantiate; initialize a bouncing Hertz case and a yielding Johnson case; step with
 * events; read every variable; get, set, serialize and deserialize FMU states (also before
 * initialization and a corrupted one); refused calls and bad arguments; a failed initialization;
 * reset; many instances at once; free. With LayerTest (the generic layer's test model, which reads
 * its resources folder) also: resource URIs percent-decoded, missing, or not local. The importer's
 * memory functions count blocks, so that a block the FMU forgets is reported even without a leak
 * checker.
 */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
} F;

static void *lib;

static void load(const char *path)
{
    if (lib) dlclose(lib);
    lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "fmu_driver: %s\n", dlerror());
        exit(2);
    }
#define SYM(field, name)                                                  \
    do {                                                                  \
        *(void **)&F.field = dlsym(lib, name);                            \
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

int main(int argc, char **argv)
{
    if (argc != 3 && argc != 5) {
        fprintf(stderr, "usage: fmu_driver <VibroImpact.so> <resources URI> [<LayerTest.so> <its GUID>]\n");
        return 2;
    }
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

    if (argc == 5) layer_test(argv[3], argv[4]);

    EXPECT(live_blocks == 0);
    dlclose(lib);
    if (failures) fprintf(stderr, "fmu_driver: %d checks failed, %ld blocks not freed\n", failures, live_blocks);
    else printf("fmu_driver: all checks passed\n");
    return failures ? 1 : 0;
}
