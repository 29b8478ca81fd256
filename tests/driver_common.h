/*
 * driver_common.h - what tests/fmu_driver.c (FMI 2.0) and tests/fmu3_driver.c (FMI 3.0) share: the
 * loading of the FMU binary on every platform, and the cases they run on every platform's binary for
 * tools/cross_test.sh (the paper's scenarios, the solvers, the settings of the records, the
 * Runge-Kutta step of Model Exchange). Each driver defines DRIVER_NAME (its messages' prefix) first.
 */
#ifndef DRIVER_COMMON_H
#define DRIVER_COMMON_H

#ifdef _WIN32
#include <windows.h>
#else
#include <dlfcn.h>
#endif
#include <stdio.h>

#include "vi_variables.h"

/* The loaded binary: dlopen where there is one, LoadLibrary on Windows. */
#ifdef _WIN32
static HMODULE lib;

static int lib_open(const char *path)
{
    char native[MAX_PATH];
    if (snprintf(native, sizeof native, "%s", path) >= (int)sizeof native) return 0;
    for (char *p = native; *p; p++)
        if (*p == '/') *p = '\\';
    lib = LoadLibraryA(native);
    if (!lib) fprintf(stderr, DRIVER_NAME ": cannot load %s (error %lu)\n", path, (unsigned long)GetLastError());
    return lib != NULL;
}

static void *lib_symbol(const char *name)
{
    union {
        FARPROC f;
        void *p;
    } u = {.f = GetProcAddress(lib, name)};
    return u.p;
}

static void lib_close(void)
{
    if (lib) FreeLibrary(lib);
    lib = NULL;
}
#else
static void *lib;

static int lib_open(const char *path)
{
    lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) fprintf(stderr, DRIVER_NAME ": %s\n", dlerror());
    return lib != NULL;
}

static void *lib_symbol(const char *name) { return dlsym(lib, name); }

static void lib_close(void)
{
    if (lib) dlclose(lib);
    lib = NULL;
}
#endif

#define RTOL_CASES 1e-10 /* relative tolerance of the trajectory cases */
#define H_CASES 1e-5     /* s, communication step of the trajectory cases (and the recording interval) */
#define ME_NX 3          /* continuous states of VibroImpact: y, v, W_damping (modelDescription.xml, Derivatives) */
#define ME_NZ 4          /* its event indicators (numberOfEventIndicators): two per contact */
#define ME_H 1e-6        /* s, the fixed step of the drivers' classical Runge-Kutta method (Model Exchange) */
#define ME_EVENT_PASSES 100 /* bound of the event iteration (fmi2NewDiscreteStates, fmi3UpdateDiscreteStates) */

/* The paper's scenarios (the parameters that differ from the model description's start values), and
 * the two-sided one (two_sided: the impact damper's settings below as well). */
typedef struct {
    const char *name;
    int law;
    double a, f, Y;  /* m, Hz, Pa */
    double t_stop;   /* s */
    int two_sided;   /* upper_stop = true with the settings of two_sided_reals and two_sided_enums */
} scenario;

/* A parameter's value by its value reference. */
typedef struct {
    unsigned vr;
    double value;
} setting;

/* The two-sided case, an impact damper: a steel sphere (R = 5 mm, 4.1103 g) in a cavity 20 mm high
 * (upper_stop, gap) shaken a (cos(2 pi f t) - 1), a = 1 mm, f = 50 Hz, without gravity or load, damped
 * Hertz (exact damping, e = 0.8), started touching the lower wall at 2 m/s up, for 30 ms: it hits
 * the upper wall at 9 ms and the lower one at 19 ms (the run checks that n_impacts and
 * n_impacts_upper are > 0). 30 ms, not longer: CVODE's BDF and Adams on aarch64 (whose SUNDIALS
 * fuses multiplications and additions) leave an impact at a speed that differs within their error,
 * and each flight carries the difference into y, which grows with time (to 8e-7 of the range of y
 * after 0.1 s, beyond the cross test's 1e-7). */
static const setting two_sided_reals[] = {
    {VI_VR_m, 4.1103e-3}, {VI_VR_R1, 5e-3}, {VI_VR_R2, 0.0}, {VI_VR_P, 0.0}, {VI_VR_g, 0.0},
    {VI_VR_e_restitution, 0.8}, {VI_VR_gap, 0.02}, {VI_VR_v0, 2.0},
};
static const setting two_sided_enums[] = {
    {VI_VR_damping_formula, VI_DampingFormula_exact}, {VI_VR_init, VI_Init_touching},
};
#define N_TWO_SIDED_REALS (sizeof two_sided_reals / sizeof two_sided_reals[0])
#define N_TWO_SIDED_ENUMS (sizeof two_sided_enums / sizeof two_sided_enums[0])

/* Fig. 4b bounces chaotically: a difference in the last bit (another C library's pow or cos, another
 * compiler's SUNDIALS) grows about tenfold every 5 ms, so platforms agree to 1e-7 of the range of y
 * for the first 20 ms (6 impacts, every mode) but not over the paper's 0.1 s (fig4b_100ms shows how
 * far they part). */
static const scenario scenarios[] = {
    {"fig4b", VI_ContactModel_johnson, 1e-4, 560.0, 6e8, 0.02, 0},
    {"fig5a", VI_ContactModel_hertz, 1e-4, 100.0, 6e8, 0.1, 0},
    {"cavity", VI_ContactModel_hertz_damped, 1e-3, 50.0, 6e8, 0.03, 1}, /* the two-sided case above */
    {"fig4b_100ms", VI_ContactModel_johnson, 1e-4, 560.0, 6e8, 0.1, 0},
    /* the laws beyond the paper's, under Fig. 4b's excitation (their other parameters at their defaults) */
    {"fig4b_thornton", VI_ContactModel_thornton, 1e-4, 560.0, 6e8, 0.02, 0},
    {"fig4b_hertz_damped", VI_ContactModel_hertz_damped, 1e-4, 560.0, 6e8, 0.02, 0},
    {"fig4b_linear", VI_ContactModel_linear, 1e-4, 560.0, 6e8, 0.02, 0},
};
static const char *const solver_names[] = {"bdf", "adams", "dop853", "auto"};
static const int solver_values[] = {VI_Solver_bdf, VI_Solver_adams, VI_Solver_dop853, VI_Solver_auto};
#define N_SCENARIOS (sizeof scenarios / sizeof scenarios[0])
#define N_SOLVERS (sizeof solver_values / sizeof solver_values[0])
#define N_ME_SCENARIOS 3 /* fig4b, fig5a, cavity: also through Model Exchange (and FMI 3.0's early return) */

/* x' at (t, x) into dx through the FMU's Model Exchange calls; 0, or -1 when a call fails. */
typedef int derivatives_fn(void *instance, double t, const double *x, double *dx);

/* One classical Runge-Kutta step of the states x from t to t1 = t + ME_H; 0, or -1 when a call of
 * f fails (x is then undefined). */
static int rk4_step(derivatives_fn *f, void *instance, double t, double t1, double x[ME_NX])
{
    double k1[ME_NX], k2[ME_NX], k3[ME_NX], k4[ME_NX], xs[ME_NX];
    int rc = f(instance, t, x, k1);
    for (int i = 0; i < ME_NX; i++) xs[i] = x[i] + 0.5 * ME_H * k1[i];
    rc = rc < 0 ? rc : f(instance, t + 0.5 * ME_H, xs, k2);
    for (int i = 0; i < ME_NX; i++) xs[i] = x[i] + 0.5 * ME_H * k2[i];
    rc = rc < 0 ? rc : f(instance, t + 0.5 * ME_H, xs, k3);
    for (int i = 0; i < ME_NX; i++) xs[i] = x[i] + ME_H * k3[i];
    rc = rc < 0 ? rc : f(instance, t1, xs, k4);
    for (int i = 0; i < ME_NX; i++) x[i] += ME_H / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    return rc;
}

#endif
