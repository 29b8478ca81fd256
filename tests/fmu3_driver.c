/*
 * fmu3_driver.c - drives the FMI 3.0 build of the FMU (build/fmi3/VibroImpact.so) through its fmi3*
 * functions, as an importer would, for the memory checkers (as tests/fmu_driver.c does for the
 * FMI 2.0 build): under AddressSanitizer + UndefinedBehaviorSanitizer (cmake -DVI_SANITIZE=ON)
 * against the sanitized binary, else under valgrind memcheck. Any report fails the test.
 *
 *   fmu3_driver <path to the FMI 3.0 VibroImpact.so> <resources folder path>
 *   fmu3_driver run <FMI 3.0 VibroImpact binary> <case>
 *       Prints the record of one case for comparison with another platform's binary (tools/cross_test.sh
 *       compares them with `fmu_driver compare`); exits 1 when a check inside the case fails.
 *   fmu3_driver cases
 *       Lists the cases.
 *
 * Portable C like tests/fmu_driver.c: built for Windows and aarch64 Linux too (tools/release.sh).
 *
 * What it does: instantiate with and without early return and Event Mode; initialize with a
 * tolerance; step with early returns through Event Mode; read every variable through its type and
 * time; get, set, serialize and deserialize FMU states (also in Event Mode and a corrupted one);
 * refused calls and bad arguments; a failed initialization; reset; many instances at once; free.
 * FMI 3.0 has no memory callbacks: the FMU allocates with malloc, so leaks are the checkers' to find.
 *
 * Cases (run), each at rtol 1e-10 and recorded every 1e-5 s like fmu_driver's:
 *   cs-fig4b-<solver>, cs-fig5a-<solver>   Co-Simulation with early return and Event Mode: y at every
 *                    communication point, the time of every early return (its number as the
 *                    abscissa), the counts of early returns and impacts
 *   cs-cavity-<solver>   the same for the two-sided case (upper_stop: the impact damper of
 *                    tests/driver_common.h, 30 ms), also the upper wall's impact count (both checked > 0)
 *   me-fig4b, me-fig5a, me-cavity   Model Exchange, this driver integrating as fmu_driver's fig4b-me,
 *                    fig5a-me and cavity-me (classical Runge-Kutta, fixed step 1e-6 s, events at the end
 *                    of a step where an event indicator changes sign): y, the event and impact counts
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DRIVER_NAME "fmu3_driver"
#include "driver_common.h"
#include "fmi3Functions.h"
#include "vi_variables.h"

#define N_INSTANCES 16
#define TIME_VR 2147483647u /* VI_FMI3_TIME_VR of cmake/vi_fmu.cmake */

static int failures;

static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    (void)env, (void)status, (void)category, (void)message; /* errors are expected here */
}

/* The fmi3* functions of the loaded binary. */
static struct {
    fmi3InstantiateCoSimulationTYPE *instantiate;
    fmi3InstantiateModelExchangeTYPE *instantiate_me;
    fmi3FreeInstanceTYPE *free_instance;
    fmi3EnterInitializationModeTYPE *enter_init;
    fmi3ExitInitializationModeTYPE *exit_init;
    fmi3EnterEventModeTYPE *enter_event;
    fmi3UpdateDiscreteStatesTYPE *update;
    fmi3EnterStepModeTYPE *enter_step;
    fmi3TerminateTYPE *terminate;
    fmi3ResetTYPE *reset;
    fmi3GetFloat64TYPE *get_float64;
    fmi3GetInt32TYPE *get_int32;
    fmi3GetInt64TYPE *get_int64;
    fmi3GetBooleanTYPE *get_boolean;
    fmi3GetStringTYPE *get_string;
    fmi3SetFloat64TYPE *set_float64;
    fmi3SetInt64TYPE *set_int64;
    fmi3SetBooleanTYPE *set_boolean;
    fmi3SetStringTYPE *set_string;
    fmi3DoStepTYPE *do_step;
    fmi3GetFMUStateTYPE *get_state;
    fmi3SetFMUStateTYPE *set_state;
    fmi3FreeFMUStateTYPE *free_state;
    fmi3SerializedFMUStateSizeTYPE *state_size;
    fmi3SerializeFMUStateTYPE *serialize;
    fmi3DeserializeFMUStateTYPE *deserialize;
    fmi3SetDebugLoggingTYPE *debug_logging;
    /* Model Exchange */
    fmi3SetTimeTYPE *set_time;
    fmi3SetContinuousStatesTYPE *set_states;
    fmi3GetContinuousStatesTYPE *get_states;
    fmi3GetContinuousStateDerivativesTYPE *get_derivatives;
    fmi3GetEventIndicatorsTYPE *get_indicators;
    fmi3CompletedIntegratorStepTYPE *completed_step;
    fmi3EnterContinuousTimeModeTYPE *enter_continuous;
} F;

static void load(const char *path)
{
    if (!lib_open(path)) exit(2);
#define SYM(field, name)                                                  \
    do {                                                                  \
        *(void **)&F.field = lib_symbol(name);                            \
        if (!F.field) {                                                   \
            fprintf(stderr, "fmu3_driver: %s is not exported\n", name);   \
            exit(2);                                                      \
        }                                                                 \
    } while (0)
    SYM(instantiate, "fmi3InstantiateCoSimulation");
    SYM(instantiate_me, "fmi3InstantiateModelExchange");
    SYM(free_instance, "fmi3FreeInstance");
    SYM(enter_init, "fmi3EnterInitializationMode");
    SYM(exit_init, "fmi3ExitInitializationMode");
    SYM(enter_event, "fmi3EnterEventMode");
    SYM(update, "fmi3UpdateDiscreteStates");
    SYM(enter_step, "fmi3EnterStepMode");
    SYM(terminate, "fmi3Terminate");
    SYM(reset, "fmi3Reset");
    SYM(get_float64, "fmi3GetFloat64");
    SYM(get_int32, "fmi3GetInt32");
    SYM(get_int64, "fmi3GetInt64");
    SYM(get_boolean, "fmi3GetBoolean");
    SYM(get_string, "fmi3GetString");
    SYM(set_float64, "fmi3SetFloat64");
    SYM(set_int64, "fmi3SetInt64");
    SYM(set_boolean, "fmi3SetBoolean");
    SYM(set_string, "fmi3SetString");
    SYM(do_step, "fmi3DoStep");
    SYM(get_state, "fmi3GetFMUState");
    SYM(set_state, "fmi3SetFMUState");
    SYM(free_state, "fmi3FreeFMUState");
    SYM(state_size, "fmi3SerializedFMUStateSize");
    SYM(serialize, "fmi3SerializeFMUState");
    SYM(deserialize, "fmi3DeserializeFMUState");
    SYM(debug_logging, "fmi3SetDebugLogging");
    SYM(set_time, "fmi3SetTime");
    SYM(set_states, "fmi3SetContinuousStates");
    SYM(get_states, "fmi3GetContinuousStates");
    SYM(get_derivatives, "fmi3GetContinuousStateDerivatives");
    SYM(get_indicators, "fmi3GetEventIndicators");
    SYM(completed_step, "fmi3CompletedIntegratorStep");
    SYM(enter_continuous, "fmi3EnterContinuousTimeMode");
#undef SYM
}

#define EXPECT(cond)                                                             \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "fmu3_driver:%d: failed: %s\n", __LINE__, #cond);    \
            failures++;                                                          \
        }                                                                        \
    } while (0)

static fmi3Instance instantiate(const char *name, const char *resources, int event_mode, int early_return)
{
    fmi3Instance c = F.instantiate(name, VI_GUID, resources, fmi3False, fmi3False, event_mode, early_return, NULL, 0,
                                   NULL, logger, NULL);
    EXPECT(c != NULL);
    return c;
}

/* Event Mode: one pass of the event iteration, then Step Mode. */
static void event_iteration(fmi3Instance c)
{
    fmi3Boolean more = fmi3True, terminate, nominals, values, next_defined;
    fmi3Float64 next;
    EXPECT(F.update(c, &more, &terminate, &nominals, &values, &next_defined, &next) == fmi3OK && !more);
    EXPECT(F.enter_step(c) == fmi3OK);
}

/* The law (an Enumeration, Int64), a and Y, a tolerance; initialized at t = 0 (in Event Mode when
 * the instance uses it, left to Step Mode here). */
static fmi3Status initialize(fmi3Instance c, int law, double a, double Y, int event_mode)
{
    const fmi3ValueReference vr[] = {VI_VR_a, VI_VR_Y}, law_vr = VI_VR_contact_model;
    const fmi3Float64 v[] = {a, Y};
    const fmi3Int64 law_v = law;
    EXPECT(F.enter_init(c, fmi3True, 1e-7, 0.0, fmi3False, 0.0) == fmi3OK);
    EXPECT(F.set_float64(c, vr, 2, v, 2) == fmi3OK);
    if (F.set_int64(c, &law_vr, 1, &law_v, 1) != fmi3OK) return fmi3Error; /* not an item: refused at once */
    fmi3Status st = F.exit_init(c);
    if (st == fmi3OK && event_mode) event_iteration(c);
    return st;
}

/* Every variable through its type once, and time. */
static void read_all(fmi3Instance c)
{
    for (fmi3ValueReference vr = 0; vr < VI_NVARS; vr++) {
        fmi3Float64 r;
        fmi3Int32 i;
        fmi3Int64 e;
        fmi3Boolean b;
        fmi3String s;
        fmi3Status st = F.get_float64(c, &vr, 1, &r, 1);
        if (st != fmi3OK) st = F.get_int32(c, &vr, 1, &i, 1);
        if (st != fmi3OK) st = F.get_int64(c, &vr, 1, &e, 1);
        if (st != fmi3OK) st = F.get_boolean(c, &vr, 1, &b, 1);
        if (st != fmi3OK) st = F.get_string(c, &vr, 1, &s, 1);
        EXPECT(st == fmi3OK);
    }
    const fmi3ValueReference time_vr = TIME_VR;
    fmi3Float64 t;
    EXPECT(F.get_float64(c, &time_vr, 1, &t, 1) == fmi3OK && isfinite(t));
}

/* Steps of h to t + n h; with early return, stops at the events (through Event Mode when used).
 * Returns the number of early returns. */
static int steps(fmi3Instance c, double *t, int n, double h)
{
    int early_returns = 0;
    double end = *t + n * h;
    for (int k = 0; k < 100 * n && *t < end; k++) {
        fmi3Boolean handling, terminate, early;
        fmi3Float64 last;
        double step = fmin(h, end - *t);
        EXPECT(F.do_step(c, *t, step, fmi3True, &handling, &terminate, &early, &last) == fmi3OK);
        EXPECT(last > *t && last <= *t + step);
        early_returns += early;
        *t = early ? last : *t + step;
        if (handling) {
            EXPECT(F.enter_event(c) == fmi3OK);
            event_iteration(c);
        }
    }
    return early_returns;
}

/* FMU states: get, serialize, deserialize, set, a corrupted copy refused. */
static void states(fmi3Instance c, double *t)
{
    fmi3FMUState s = NULL, back = NULL;
    size_t n = 0;
    EXPECT(F.get_state(c, &s) == fmi3OK);
    EXPECT(F.get_state(c, &s) == fmi3OK); /* reuses the block */
    EXPECT(F.state_size(c, s, &n) == fmi3OK && n > 0);
    fmi3Byte *bytes = malloc(n);
    EXPECT(F.serialize(c, s, bytes, n) == fmi3OK);
    EXPECT(F.deserialize(c, bytes, n, &back) == fmi3OK);
    EXPECT(F.deserialize(c, bytes, n, &back) == fmi3OK); /* into the existing block */
    bytes[n / 2] ^= 0x10;
    fmi3FMUState bad = NULL;
    EXPECT(F.deserialize(c, bytes, n, &bad) == fmi3Error && bad == NULL);
    EXPECT(F.deserialize(c, bytes, n - 1, &bad) == fmi3Error && bad == NULL);
    free(bytes);
    double t0 = *t;
    steps(c, t, 20, 1e-4);
    EXPECT(F.set_state(c, back) == fmi3OK);
    *t = t0;
    steps(c, t, 20, 1e-4);
    EXPECT(F.free_state(c, &s) == fmi3OK && s == NULL);
    EXPECT(F.free_state(c, &back) == fmi3OK && back == NULL);
}

/* Calls that must be refused, without harm. */
static void refusals(fmi3Instance c, double t)
{
    const fmi3ValueReference unknown = 100000, m = VI_VR_m, file = VI_VR_profile_file, law = VI_VR_contact_model;
    const fmi3ValueReference two[] = {VI_VR_m, VI_VR_P}, time_vr = TIME_VR;
    fmi3Float64 r = 1.0, pair[2];
    fmi3Int32 i32;
    const fmi3Int64 huge = (fmi3Int64)1 << 40;
    static char text[VI_STRING_SIZE + 8];
    memset(text, 'x', sizeof text - 1);
    fmi3String long_string = text;
    fmi3Boolean handling, terminate, early, more, nominals, values, defined;
    fmi3Float64 last, next;
    EXPECT(F.get_float64(c, &unknown, 1, &r, 1) == fmi3Error);
    EXPECT(F.get_float64(c, two, 2, pair, 1) == fmi3Error);    /* nValues */
    EXPECT(F.set_float64(c, &m, 1, &r, 1) == fmi3Error);        /* fixed after initialization */
    EXPECT(F.set_float64(c, &time_vr, 1, &r, 1) == fmi3Error);  /* the independent variable */
    EXPECT(F.get_int32(c, &law, 1, &i32, 1) == fmi3Error);      /* an Enumeration: Int64 */
    EXPECT(F.set_int64(c, &law, 1, &huge, 1) == fmi3Error);
    EXPECT(F.set_string(c, &file, 1, &long_string, 1) == fmi3Error);
    EXPECT(F.do_step(c, t, 5e-324, fmi3True, &handling, &terminate, &early, &last) == fmi3Error);
    EXPECT(F.do_step(c, t + 1.0, 1e-4, fmi3True, &handling, &terminate, &early, &last) == fmi3Error);
    EXPECT(F.do_step(c, t, 1e-4, fmi3True, NULL, &terminate, &early, &last) == fmi3Error);
    EXPECT(F.update(c, &more, &terminate, &nominals, &values, &defined, &next) == fmi3Error); /* Step Mode */
    EXPECT(F.enter_step(c) == fmi3Error);
    EXPECT(F.set_state(c, NULL) == fmi3Error);
    fmi3String categories[] = {"logEvents", "logNothing"};
    EXPECT(F.debug_logging(c, fmi3True, 2, categories) == fmi3Error);
    EXPECT(F.debug_logging(c, fmi3True, 1, categories) == fmi3OK);
}

/* ---- cases: records for comparison across platforms ------------------------------------------------ */

#define EARLY_PER_STEP 100 /* bound of the early returns inside one communication step */

static void case_logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    (void)env, (void)category;
    if (status > fmi3Warning) fprintf(stderr, "fmu3_driver: FMU: %s\n", message);
}

/* The two-sided case's settings (upper_stop = true and the impact damper's parameters); fmi3OK or
 * the first failure. */
static fmi3Status set_two_sided(fmi3Instance c)
{
    const fmi3ValueReference upper_stop = VI_VR_upper_stop;
    const fmi3Boolean on = fmi3True;
    fmi3Status st = F.set_boolean(c, &upper_stop, 1, &on, 1);
    for (size_t i = 0; i < N_TWO_SIDED_REALS && st == fmi3OK; i++) {
        const fmi3ValueReference vr = two_sided_reals[i].vr;
        const fmi3Float64 v = two_sided_reals[i].value;
        st = F.set_float64(c, &vr, 1, &v, 1);
    }
    for (size_t i = 0; i < N_TWO_SIDED_ENUMS && st == fmi3OK; i++) {
        const fmi3ValueReference vr = two_sided_enums[i].vr;
        const fmi3Int64 v = (fmi3Int64)two_sided_enums[i].value;
        st = F.set_int64(c, &vr, 1, &v, 1);
    }
    return st;
}

/* The scenario's parameters set in Initialization Mode (tolerance RTOL_CASES); fmi3OK or the first
 * failure. solver < 0: Model Exchange (no solver). */
static fmi3Status setup_scenario(fmi3Instance c, const scenario *sc, int solver)
{
    const fmi3ValueReference real_vr[] = {VI_VR_a, VI_VR_f, VI_VR_Y};
    const fmi3Float64 real_v[] = {sc->a, sc->f, sc->Y};
    const fmi3ValueReference law_vr = VI_VR_contact_model, solver_vr = VI_VR_solver;
    const fmi3Int64 law_v = sc->law, solver_v = solver;
    fmi3Status st = F.enter_init(c, fmi3True, RTOL_CASES, 0.0, fmi3False, 0.0);
    if (st == fmi3OK) st = F.set_float64(c, real_vr, 3, real_v, 3);
    if (st == fmi3OK) st = F.set_int64(c, &law_vr, 1, &law_v, 1);
    if (st == fmi3OK && solver >= 0) st = F.set_int64(c, &solver_vr, 1, &solver_v, 1);
    if (st == fmi3OK && sc->two_sided) st = set_two_sided(c);
    if (st == fmi3OK) st = F.exit_init(c);
    return st;
}

static double get_y(fmi3Instance c)
{
    const fmi3ValueReference vr = VI_VR_y;
    fmi3Float64 y = NAN;
    EXPECT(F.get_float64(c, &vr, 1, &y, 1) == fmi3OK);
    return y;
}

static int get_impacts(fmi3Instance c)
{
    const fmi3ValueReference vr = VI_VR_n_impacts;
    fmi3Int32 n = -1;
    EXPECT(F.get_int32(c, &vr, 1, &n, 1) == fmi3OK);
    return (int)n;
}

/* The two-sided case's record line: the upper contact's impacts; both walls must have been hit. */
static void print_two_sided(fmi3Instance c, const scenario *sc)
{
    if (!sc->two_sided) return;
    const fmi3ValueReference vr = VI_VR_n_impacts_upper;
    fmi3Int32 upper = -1;
    EXPECT(F.get_int32(c, &vr, 1, &upper, 1) == fmi3OK);
    printf("= n_impacts_upper %d\n", (int)upper);
    EXPECT(get_impacts(c) > 0 && upper > 0);
}

/* The event iteration of Event Mode; 0, or -1. */
static int update_discrete(fmi3Instance c, long *passes)
{
    fmi3Boolean more = fmi3True, terminate, nominals, values, next_defined;
    fmi3Float64 next;
    for (int k = 0; k < ME_EVENT_PASSES && more; k++, (*passes)++)
        if (F.update(c, &more, &terminate, &nominals, &values, &next_defined, &next) != fmi3OK) return -1;
    return more || terminate ? -1 : 0;
}

/* One communication step of H_CASES from t, through every early return inside it (Event Mode at
 * each); the times of the early returns printed. 0, or -1. */
static int cs_step(fmi3Instance c, double t, long *early_returns, long *passes)
{
    const double end = t + H_CASES;
    for (int k = 0; k < EARLY_PER_STEP && t < end; k++) {
        fmi3Boolean handling, terminate, early;
        fmi3Float64 last;
        if (F.do_step(c, t, end - t, fmi3True, &handling, &terminate, &early, &last) != fmi3OK) return -1;
        if (early) printf("~ t_early %ld %.17g\n", ++*early_returns, last);
        t = early ? last : end;
        if (handling && (F.enter_event(c) != fmi3OK || update_discrete(c, passes) < 0 || F.enter_step(c) != fmi3OK))
            return -1;
    }
    return t < end ? -1 : 0;
}

static void case_cs(const scenario *sc, size_t solver)
{
    fmi3Instance c = F.instantiate("case", VI_GUID, NULL, fmi3False, fmi3False, fmi3True, fmi3True, NULL, 0, NULL,
                                   case_logger, NULL);
    EXPECT(c != NULL);
    if (!c) return;
    long passes = 0, early_returns = 0;
    if (setup_scenario(c, sc, solver_values[solver]) != fmi3OK || update_discrete(c, &passes) < 0 ||
        F.enter_step(c) != fmi3OK) {
        fprintf(stderr, "fmu3_driver: %s did not initialize\n", sc->name);
        failures++;
        F.free_instance(c);
        return;
    }
    const long n = lround(sc->t_stop / H_CASES);
    printf("# %s, Co-Simulation with early return and Event Mode, solver %s, rtol %g, %ld steps of %g s\n",
           sc->name, solver_names[solver], RTOL_CASES, n, H_CASES);
    for (long k = 0; k < n; k++) {
        if (cs_step(c, k * H_CASES, &early_returns, &passes) < 0) {
            fprintf(stderr, "fmu3_driver: %s: step %ld failed\n", sc->name, k);
            failures++;
            break;
        }
        printf("~ y %.17g %.17g\n", (k + 1) * H_CASES, get_y(c));
    }
    printf("= %ld early returns, n_impacts %d\n", early_returns, get_impacts(c));
    print_two_sided(c, sc);
    F.free_instance(c);
}

/* x' at (t, x) into dx; 0, or -1 (derivatives_fn). */
static int me_derivatives(void *c, double t, const double *x, double *dx)
{
    return F.set_time(c, t) == fmi3OK && F.set_states(c, x, ME_NX) == fmi3OK &&
                   F.get_derivatives(c, dx, ME_NX) == fmi3OK
               ? 0
               : -1;
}

/* Event Mode's iteration, then Continuous-Time Mode; the states and indicators after it. 0, or -1. */
static int me_event(fmi3Instance c, double *x, double *z, long *passes)
{
    return update_discrete(c, passes) == 0 && F.enter_continuous(c) == fmi3OK &&
                   F.get_states(c, x, ME_NX) == fmi3OK && F.get_indicators(c, z, ME_NZ) == fmi3OK
               ? 0
               : -1;
}

/* One classical Runge-Kutta step from t to t1 (ME_H apart), then the event check at t1; 1 when an
 * event was handled, 0 when none, -1 on failure. */
static int me_step(fmi3Instance c, double t, double t1, double *x, double *z, long *passes)
{
    double z1[ME_NZ];
    int rc = rk4_step(me_derivatives, c, t, t1, x);
    fmi3Boolean enter = fmi3False, stop = fmi3False;
    if (rc < 0 || F.set_time(c, t1) != fmi3OK || F.set_states(c, x, ME_NX) != fmi3OK ||
        F.completed_step(c, fmi3True, &enter, &stop) != fmi3OK || F.get_indicators(c, z1, ME_NZ) != fmi3OK || stop)
        return -1;
    int crossed = 0;
    for (int i = 0; i < ME_NZ; i++) crossed |= (z[i] > 0.0) != (z1[i] > 0.0);
    memcpy(z, z1, sizeof z1);
    if (!crossed && !enter) return 0;
    return F.enter_event(c) == fmi3OK && me_event(c, x, z, passes) == 0 ? 1 : -1;
}

static void case_me(const scenario *sc)
{
    fmi3Instance c = F.instantiate_me("me", VI_GUID, NULL, fmi3False, fmi3False, NULL, case_logger);
    EXPECT(c != NULL);
    if (!c) return;
    double x[ME_NX], z[ME_NZ];
    long events = 0, passes = 0;
    if (setup_scenario(c, sc, -1) != fmi3OK || me_event(c, x, z, &passes) < 0) {
        fprintf(stderr, "fmu3_driver: %s (Model Exchange) did not initialize\n", sc->name);
        failures++;
        F.free_instance(c);
        return;
    }
    const long n = lround(sc->t_stop / ME_H), every = lround(H_CASES / ME_H);
    printf("# %s, Model Exchange, classical Runge-Kutta, %ld steps of %g s: t y\n", sc->name, n, ME_H);
    for (long k = 0; k < n; k++) {
        int rc = me_step(c, k * ME_H, (k + 1) * ME_H, x, z, &passes);
        if (rc < 0) {
            fprintf(stderr, "fmu3_driver: %s (Model Exchange) stopped at t = %g\n", sc->name, (k + 1) * ME_H);
            failures++;
            break;
        }
        events += rc;
        if ((k + 1) % every == 0) printf("~ y %.17g %.17g\n", (double)((k + 1) / every) * H_CASES, x[0]);
    }
    printf("= Model Exchange: %ld events, %ld passes of fmi3UpdateDiscreteStates, n_impacts %d\n", events, passes,
           get_impacts(c));
    print_two_sided(c, sc);
    F.free_instance(c);
}

static int list_cases(void)
{
    for (size_t i = 0; i < N_ME_SCENARIOS; i++)
        for (size_t s = 0; s < N_SOLVERS; s++) printf("cs-%s-%s\n", scenarios[i].name, solver_names[s]);
    for (size_t i = 0; i < N_ME_SCENARIOS; i++) printf("me-%s\n", scenarios[i].name);
    return 0;
}

static int run_case(const char *path, const char *name)
{
    load(path);
    int found = 0;
    char full[64];
    for (size_t i = 0; i < N_ME_SCENARIOS && !found; i++) {
        snprintf(full, sizeof full, "me-%s", scenarios[i].name);
        if (strcmp(name, full) == 0) case_me(&scenarios[i]), found = 1;
        for (size_t s = 0; s < N_SOLVERS && !found; s++) {
            snprintf(full, sizeof full, "cs-%s-%s", scenarios[i].name, solver_names[s]);
            if (strcmp(name, full) == 0) case_cs(&scenarios[i], s), found = 1;
        }
    }
    lib_close();
    if (!found) {
        fprintf(stderr, "fmu3_driver: no case '%s' (fmu3_driver cases lists them)\n", name);
        return 2;
    }
    fflush(stdout);
    if (failures) fprintf(stderr, "fmu3_driver: %s: %d checks failed\n", name, failures);
    return failures ? 1 : 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "cases") == 0) return list_cases();
    if (argc == 4 && strcmp(argv[1], "run") == 0) return run_case(argv[2], argv[3]);
    if (argc != 3) {
        fprintf(stderr, "usage: fmu3_driver <VibroImpact binary of FMI 3.0> <resources folder>\n"
                        "       fmu3_driver run <VibroImpact binary of FMI 3.0> <case>\n"
                        "       fmu3_driver cases\n");
        return 2;
    }
    load(argv[1]);
    const char *resources = argv[2];

    /* One instance through its whole life, twice (fmi3Reset in between), for each pair of options. */
    for (int options = 0; options < 4; options++) {
        int event_mode = options & 1, early_return = options >> 1 & 1;
        fmi3Instance c = instantiate("driver", resources, event_mode, early_return);
        for (int round = 0; round < 2; round++) {
            EXPECT(initialize(c, VI_ContactModel_hertz, 1e-4, 6e8, event_mode) == fmi3OK);
            double t = 0.0;
            int stops = steps(c, &t, 50, 1e-4);
            EXPECT(early_return ? stops > 0 : stops == 0);
            read_all(c);
            const fmi3ValueReference n_vr = VI_VR_n_impacts;
            fmi3Int32 impacts = 0;
            EXPECT(F.get_int32(c, &n_vr, 1, &impacts, 1) == fmi3OK && impacts > 0); /* events happened */
            if (event_mode) { /* a state taken in Event Mode restores Event Mode */
                fmi3FMUState in_event = NULL;
                double t0 = t;
                EXPECT(F.enter_event(c) == fmi3OK);
                EXPECT(F.get_state(c, &in_event) == fmi3OK);
                event_iteration(c);
                steps(c, &t, 10, 1e-4);
                EXPECT(F.set_state(c, in_event) == fmi3OK);
                t = t0;
                event_iteration(c);
                EXPECT(F.free_state(c, &in_event) == fmi3OK);
            }
            states(c, &t);
            refusals(c, t);
            EXPECT(F.terminate(c) == fmi3OK);
            EXPECT(F.reset(c) == fmi3OK);
        }
        F.free_instance(c);
    }

    /* A state taken before initialization, restored into a running instance; a failed initialization. */
    fmi3Instance c = instantiate("driver", resources, 0, 1);
    fmi3FMUState before = NULL;
    EXPECT(F.get_state(c, &before) == fmi3OK);
    EXPECT(initialize(c, VI_ContactModel_johnson, 1e-4, 2e8, 0) == fmi3OK);
    double t = 0.0;
    steps(c, &t, 30, 1e-4);
    EXPECT(F.set_state(c, before) == fmi3OK);
    EXPECT(initialize(c, VI_ContactModel_lepp, 1e-4, 6e8, 0) == fmi3OK);
    t = 0.0;
    steps(c, &t, 30, 1e-4);
    read_all(c);
    EXPECT(F.free_state(c, &before) == fmi3OK);
    EXPECT(F.reset(c) == fmi3OK);
    EXPECT(initialize(c, 7, 1e-4, 6e8, 0) == fmi3Error); /* contact_model = 7 refused */
    fmi3Boolean handling, terminate, early;
    fmi3Float64 last;
    EXPECT(F.do_step(c, 0.0, 1e-4, fmi3True, &handling, &terminate, &early, &last) == fmi3Error);
    EXPECT(F.reset(c) == fmi3OK);
    const fmi3ValueReference m_vr = VI_VR_m;
    const fmi3Float64 negative = -1.0;
    EXPECT(F.enter_init(c, fmi3False, 0.0, 0.0, fmi3False, 0.0) == fmi3OK);
    EXPECT(F.set_float64(c, &m_vr, 1, &negative, 1) == fmi3Error); /* outside its range */
    EXPECT(F.exit_init(c) == fmi3OK);
    EXPECT(F.reset(c) == fmi3OK);
    F.free_instance(c);
    F.free_instance(NULL);

    /* Many instances at once, interleaved, each with its own law and options. */
    fmi3Instance many[N_INSTANCES];
    double times[N_INSTANCES];
    char name[32];
    for (int i = 0; i < N_INSTANCES; i++) {
        snprintf(name, sizeof name, "instance %d", i);
        many[i] = instantiate(name, i % 2 ? NULL : resources, 0, i % 2);
        EXPECT(initialize(many[i], 1 + i % 3, 1e-4, 6e8, 0) == fmi3OK);
        times[i] = 0.0;
    }
    for (int k = 0; k < 20; k++)
        for (int i = 0; i < N_INSTANCES; i++) steps(many[i], &times[i], 1, 1e-4);
    for (int i = 0; i < N_INSTANCES; i++) F.free_instance(many[i]);

    /* Instantiation refused: no leak either. */
    EXPECT(F.instantiate("bad", "{wrong}", resources, fmi3False, fmi3False, fmi3False, fmi3False, NULL, 0, NULL,
                         logger, NULL) == NULL);
    EXPECT(F.instantiate("", VI_GUID, resources, fmi3False, fmi3False, fmi3False, fmi3False, NULL, 0, NULL, logger,
                         NULL) == NULL);
    EXPECT(F.instantiate_me("me", "{wrong}", resources, fmi3False, fmi3False, NULL, logger) == NULL);
    fmi3Instance me = F.instantiate_me("me", VI_GUID, resources, fmi3False, fmi3False, NULL, logger);
    EXPECT(me != NULL); /* its calls are driven by fmu-test/test_fmi3.py; here: created and freed */
    F.free_instance(me);

    lib_close();
    if (failures) fprintf(stderr, "fmu3_driver: %d checks failed\n", failures);
    else printf("fmu3_driver: all checks passed\n");
    return failures ? 1 : 0;
}
