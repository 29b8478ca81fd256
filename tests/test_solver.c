/* Unit tests of the solver interface (vi_solver.h) on small closed-form problems: the refusals of
 * vi_solver_create and of the state checks with their messages, events at exact times for every
 * method, the work bound, communication points inside the last step, restarts, checkpoints, the
 * statistics, and AUTO's stiffness tests driven one step at a time with a Jacobian the test sets. */
#define _POSIX_C_SOURCE 200809L /* dup, dup2, fileno */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "vi_solver.h"
#include "vi_sundials.h"

#define PI 3.14159265358979323846

/* ---- the log: every message kept (category and text) ------------------------------------------ */

static char log_text[16384];
static int log_errors, log_warnings;

static void capture(void *env, int category, const char *fmt, ...)
{
    (void)env;
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (category == VI_LOG_ERROR) log_errors++;
    if (category == VI_LOG_WARNING) log_warnings++;
    size_t used = strlen(log_text);
    snprintf(log_text + used, sizeof log_text - used, "%d|%s\n", category, line);
}

static void log_clear(void)
{
    log_text[0] = 0;
    log_errors = log_warnings = 0;
}

/* The log holds the line "category|text". */
static int logged(int category, const char *text)
{
    char line[1100];
    snprintf(line, sizeof line, "%d|%s\n", category, text);
    return strstr(log_text, line) != NULL;
}

/* The log holds a line "category|CVODE <function>: ...text..." (CVODE's own message, relayed). The
 * function is the API's in SUNDIALS 6 (CVode), the one that reports in SUNDIALS 7 (cvHandleFailure). */
static int cvode_said(int category, const char *text)
{
    char start[32];
    snprintf(start, sizeof start, "%d|CVODE ", category);
    for (const char *line = log_text; *line;) {
        const char *end = strchr(line, '\n'), *found = strstr(line, text);
        if (!end) end = line + strlen(line); /* a line cut at the end of the buffer */
        if (strncmp(line, start, strlen(start)) == 0 && found && found < end) return 1;
        line = *end ? end + 1 : end;
    }
    return 0;
}

/* ---- problems ------------------------------------------------------------------------------------ */

/* The harmonic oscillator x0'' = -x0 from (1, 0): x0 = cos t, x1 = -sin t. */
static void osc(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = x[1];
    dx[1] = -x[0];
}

static void osc_jac(double t, const double *x, double *j, void *u)
{
    (void)t, (void)x, (void)u;
    j[0] = 0.0, j[1] = 1.0, j[2] = -1.0, j[3] = 0.0;
}

/* g0 = x0 + 0.5 falls through 0 at 2 pi/3, g1 = x0 at pi/2, g2 = x1 + 2 never. */
static void osc_guards(double t, const double *x, double *g, void *u)
{
    (void)t, (void)u;
    g[0] = x[0] + 0.5;
    g[1] = x[0];
    g[2] = x[1] + 2.0;
}

/* g0 = -x0 rises through 0 at pi/2 and falls at 3 pi/2. */
static void rising_guard(double t, const double *x, double *g, void *u)
{
    (void)t, (void)u;
    g[0] = -x[0];
}

/* Guards that never cross: as many as never_ng says. */
static int never_ng = 1;
static void never(double t, const double *x, double *g, void *u)
{
    (void)t, (void)x, (void)u;
    for (int i = 0; i < never_ng; i++) g[i] = 1.0;
}

/* x' = -x for as many states as *u says. */
static void decay_n(double t, const double *x, double *dx, void *u)
{
    (void)t;
    for (int i = 0; i < *(const int *)u; i++) dx[i] = -x[i];
}

/* Three guards far from zero on the oscillator. */
static void osc_far(double t, const double *x, double *g, void *u)
{
    (void)t, (void)u;
    g[0] = x[0] + 2.0;
    g[1] = x[1] + 2.0;
    g[2] = 3.0 + t;
}

/* A guard that is identically zero, and one that never crosses. */
static void zero_guard(double t, const double *x, double *g, void *u)
{
    (void)t, (void)x, (void)u;
    g[0] = 0.0;
    g[1] = 1.0;
}

typedef struct {
    vi_ode ode;
    vi_solver_auto sw;
    double atol[VI_SOLVER_MAX_N];
    vi_solver_config cfg;
} rig;

/* The oscillator with the three guards (rtol 1e-10, atol 1e-12). */
static void rig_osc(rig *r, int method)
{
    memset(r, 0, sizeof *r);
    for (int i = 0; i < VI_SOLVER_MAX_N; i++) r->atol[i] = 1e-12;
    r->cfg = (vi_solver_config){.n = 2, .nguards = 3, .rhs = osc, .guards = osc_guards, .jac = osc_jac,
                                .method = method, .rtol = 1e-10, .atol = r->atol, .ode = &r->ode, .auto_choice = &r->sw,
                                .log = capture};
}

static const int METHODS[] = {VI_METHOD_BDF, VI_METHOD_ADAMS, VI_METHOD_DOP853, VI_METHOD_AUTO};
static const int CVODE_METHODS[] = {VI_METHOD_BDF, VI_METHOD_ADAMS};

static vi_solver *start(rig *r, double t0, const double *x0)
{
    log_clear();
    vi_solver *s = vi_solver_create(&r->cfg, t0, x0);
    cr_assert(s != NULL, "%s: %s", vi_solver_method_name(r->cfg.method), log_text);
    return s;
}

/* ---- names and refusals ------------------------------------------------------------------------- */

Test(solver, method_names)
{
    cr_assert_str_eq(vi_solver_method_name(VI_METHOD_BDF), "CVODE BDF");
    cr_assert_str_eq(vi_solver_method_name(VI_METHOD_ADAMS), "CVODE Adams");
    cr_assert_str_eq(vi_solver_method_name(VI_METHOD_DOP853), "Dormand-Prince 8(5,3)");
    cr_assert_str_eq(vi_solver_method_name(VI_METHOD_AUTO), "auto");
    cr_assert_str_eq(vi_solver_method_name(0), "unknown method");
    cr_assert_str_eq(vi_solver_method_name(5), "unknown method");
}

/* Sizes: 1..4 states and 0..16 guards; each limit exceeded alone is refused with the numbers. */
Test(solver, create_refuses_sizes_beyond_the_limits_naming_them)
{
    const struct { int n, ng, ok; } cases[] = {{0, 0, 0}, {1, 0, 1}, {4, 0, 1}, {5, 0, 0},
                                               {1, -1, 0}, {1, 16, 1}, {1, 17, 0}};
    for (size_t m = 0; m < sizeof METHODS / sizeof *METHODS; m++) {
        if (METHODS[m] == VI_METHOD_AUTO) continue; /* at most 2 states */
        for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
            rig r;
            rig_osc(&r, METHODS[m]);
            r.cfg.rhs = decay_n, r.cfg.guards = never, r.cfg.jac = NULL, r.cfg.user = &r.cfg.n;
            r.cfg.n = cases[k].n, r.cfg.nguards = cases[k].ng;
            never_ng = cases[k].ng;
            double x0[VI_SOLVER_MAX_N] = {1.0, 0.5, 0.25, 0.125};
            log_clear();
            vi_solver *s = vi_solver_create(&r.cfg, 0.0, x0);
            char want[200];
            snprintf(want, sizeof want, "vi_solver_create: %d states and %d guards exceed the limits 4 and 16",
                     cases[k].n, cases[k].ng);
            if (cases[k].ok) {
                cr_assert(s != NULL, "%s n %d ng %d refused: %s", vi_solver_method_name(METHODS[m]), cases[k].n,
                          cases[k].ng, log_text);
                cr_assert(log_errors == 0, "%s", log_text);
            } else {
                cr_assert(s == NULL, "n %d ng %d accepted", cases[k].n, cases[k].ng);
                cr_assert(logged(VI_LOG_ERROR, want), "n %d ng %d: %s", cases[k].n, cases[k].ng, log_text);
            }
            vi_solver_free(s);
        }
    }
}

Test(solver, create_refuses_unknown_methods)
{
    const int bad[] = {0, 5, -1};
    for (size_t k = 0; k < 3; k++) {
        rig r;
        rig_osc(&r, bad[k]);
        double x0[2] = {1.0, 0.0};
        log_clear();
        cr_assert(vi_solver_create(&r.cfg, 0.0, x0) == NULL);
        char want[100];
        snprintf(want, sizeof want, "vi_solver_create: unknown method %d", bad[k]);
        cr_assert(logged(VI_LOG_ERROR, want), "%s", log_text);
    }
    for (size_t m = 0; m < 4; m++) {
        rig r;
        rig_osc(&r, METHODS[m]);
        double x0[2] = {1.0, 0.0};
        vi_solver *s = start(&r, 0.0, x0);
        cr_assert(log_errors == 0 && log_warnings == 0, "%s", log_text);
        vi_solver_free(s);
    }
}

/* auto needs at most 2 states, a Jacobian and its choice block: each lack alone is refused and named. */
Test(solver, auto_refusals_name_what_is_missing)
{
    const struct { int n, jac, sw; const char *want; } cases[] = {
        {3, 1, 1, "got 3 states"},
        {2, 0, 1, "got 2 states, no Jacobian"},
        {2, 1, 0, "got 2 states, no auto_choice"},
        {3, 0, 0, "got 3 states, no Jacobian, no auto_choice"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        rig r;
        rig_osc(&r, VI_METHOD_AUTO);
        r.cfg.n = cases[k].n;
        if (!cases[k].jac) r.cfg.jac = NULL;
        if (!cases[k].sw) r.cfg.auto_choice = NULL;
        double x0[3] = {1.0, 0.0, 0.0};
        log_clear();
        cr_assert(vi_solver_create(&r.cfg, 0.0, x0) == NULL, "case %zu accepted", k);
        char want[200];
        snprintf(want, sizeof want, "vi_solver_create: auto needs at most 2 states, a Jacobian and its choice (cfg->auto_choice); %s",
                 cases[k].want);
        cr_assert(logged(VI_LOG_ERROR, want), "%s", log_text);
    }
}

/* The one-step method (alone or under auto) needs the caller's continuation and a problem vi_ode accepts. */
Test(solver, one_step_method_needs_its_continuation_and_a_valid_problem)
{
    const int methods[] = {VI_METHOD_DOP853, VI_METHOD_AUTO};
    for (int m = 0; m < 2; m++) {
        rig r;
        rig_osc(&r, methods[m]);
        double x0[2] = {1.0, 0.0};
        r.cfg.ode = NULL;
        log_clear();
        cr_assert(vi_solver_create(&r.cfg, 0.0, x0) == NULL);
        cr_assert(logged(VI_LOG_ERROR, "one-step method: no continuation given"), "%s", log_text);
        rig_osc(&r, methods[m]);
        r.cfg.rtol = 0.0; /* CVODE takes it (pure absolute control), vi_ode does not */
        log_clear();
        cr_assert(vi_solver_create(&r.cfg, 0.0, x0) == NULL);
        cr_assert(logged(VI_LOG_ERROR, "one-step method: rtol must be in (0, 1) (got 0)"), "%s", log_text);
    }
}

/* A SUNDIALS call that fails is logged with the call and CVODE's name and number of its flag, next
 * to CVODE's own message (an error). */
Test(solver, a_failing_sundials_call_is_logged_with_its_name_and_flag)
{
    rig r;
    rig_osc(&r, VI_METHOD_BDF);
    r.cfg.rtol = -1.0;
    double x0[2] = {1.0, 0.0};
    log_clear();
    cr_assert(vi_solver_create(&r.cfg, 0.0, x0) == NULL);
    cr_assert(logged(VI_LOG_ERROR, "SUNDIALS call CVodeSVtolerances(s->cvode, c->rtol, s->atol) failed: CV_ILL_INPUT (-22)"),
              "%s", log_text);
    cr_assert(strstr(log_text, "3|CVODE CVodeSVtolerances: ") != NULL, "%s", log_text);
}

/* CVODE's warnings reach the log as warnings, and nothing is printed: at t = 1e15 s, where a double
 * resolves 0.125 s, CVODE's first steps on the oscillator are below that (t + h = t). SUNDIALS 7's
 * logger prints CVODE's warnings on stdout unless they are taken from it, which 7.0 to 7.7 cannot:
 * there they are dropped (vi_sundials.h). */
Test(solver, a_cvode_warning_is_logged_and_nothing_is_printed)
{
    for (size_t m = 0; m < 2; m++) {
        rig r;
        rig_osc(&r, CVODE_METHODS[m]);
        double t0 = 1e15, x0[2] = {1.0, 0.0}, x[2], t = t0;
        int fired[3];
        long taken;
        FILE *out = tmpfile();
        cr_assert(out != NULL);
        fflush(stdout);
        int saved = dup(1);
        cr_assert(saved >= 0 && dup2(fileno(out), 1) == 1);
        vi_solver *s = start(&r, t0, x0);
        cr_assert(s != NULL, "%s", log_text);
        vi_solver_advance(s, t0 + 1.0, 20, &t, x, fired, &taken); /* the outcome is not the point */
        fflush(stdout);
        cr_assert(dup2(saved, 1) == 1);
        close(saved);
        long printed = fseek(out, 0, SEEK_END) == 0 ? ftell(out) : -1;
        fclose(out);
        cr_assert(printed == 0, "%s: %ld bytes printed on stdout", vi_solver_method_name(CVODE_METHODS[m]), printed);
        int relayed = VI_SUNDIALS_7 && !VI_SUNLOGGER_CALLBACKS ? 0 : 1;
        cr_assert(cvode_said(VI_LOG_WARNING, "are such that t + h = t on the next step") == relayed, "%s", log_text);
        vi_solver_free(s);
    }
}

static void nan_x0(double t, const double *x, double *dx, void *u)
{
    osc(t, x, dx, u);
    dx[0] = NAN;
}

static void inf_x1(double t, const double *x, double *dx, void *u)
{
    osc(t, x, dx, u);
    dx[1] = -INFINITY;
}

/* A derivative that is not finite in any one component fails CVODE's first step (a recoverable
 * failure of the right-hand side at the start), logged with the flag. */
Test(solver, a_non_finite_derivative_in_any_component_fails_cvode)
{
    const vi_rhs_fn bad[] = {nan_x0, inf_x1};
    for (size_t m = 0; m < 2; m++)
        for (int k = 0; k < 2; k++) {
            rig r;
            rig_osc(&r, CVODE_METHODS[m]);
            r.cfg.rhs = bad[k];
            r.cfg.jac = NULL;
            double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
            int fired[3];
            long taken;
            vi_solver *s = start(&r, 0.0, x0);
            cr_assert(vi_solver_advance(s, 1.0, 100, &t, x, fired, &taken) == VI_SOLVER_FAILED);
            cr_assert(logged(VI_LOG_ERROR, "SUNDIALS call flag failed: CV_FIRST_RHSFUNC_ERR (-9)"), "%s", log_text);
            vi_solver_free(s);
        }
}

/* ---- events ------------------------------------------------------------------------------------ */

/* Every method stops at the first falling zero, pi/2 (guard 1; guard 0 falls later, guard 2 never),
 * with x there, and flags guard 1 only. */
Test(solver, every_method_stops_at_the_first_falling_guard_zero)
{
    for (size_t m = 0; m < 4; m++) {
        rig r;
        rig_osc(&r, METHODS[m]);
        double x0[2] = {1.0, 0.0}, x[2] = {NAN, NAN}, t = 0.0;
        int fired[3] = {7, 7, 7};
        long taken = 12345;
        vi_solver *s = start(&r, 0.0, x0);
        int rc = vi_solver_advance(s, 3.0, 100000, &t, x, fired, &taken);
        const char *name = vi_solver_method_name(METHODS[m]);
        cr_assert(rc == VI_SOLVER_EVENT, "%s: rc %d", name, rc);
        cr_assert(fabs(t - PI / 2) < 1e-8, "%s: t = %.17g", name, t);
        cr_assert(fabs(x[0]) < 1e-8 && fabs(x[1] + 1.0) < 1e-8, "%s: x = %g %g", name, x[0], x[1]);
        cr_assert(fired[0] == 0 && fired[1] != 0 && fired[2] == 0, "%s: fired %d %d %d", name, fired[0], fired[1],
                  fired[2]);
        vi_solver_stats st;
        vi_solver_statistics(s, &st);
        cr_assert(taken > 0 && taken < 1000, "%s: taken %ld", name, taken);
        if (METHODS[m] != VI_METHOD_AUTO) cr_assert(taken == st.steps, "%s: taken %ld, %ld steps", name, taken, st.steps);
        vi_solver_free(s);
    }
}

/* Only falling crossings are events: -cos t rises through 0 at pi/2 and falls at 3 pi/2. */
Test(solver, a_rising_guard_is_no_event)
{
    for (size_t m = 0; m < 4; m++) {
        rig r;
        rig_osc(&r, METHODS[m]);
        r.cfg.nguards = 1, r.cfg.guards = rising_guard;
        double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
        int fired[1] = {0};
        long taken;
        vi_solver *s = start(&r, 0.0, x0);
        int rc = vi_solver_advance(s, 6.0, 100000, &t, x, fired, &taken);
        cr_assert(rc == VI_SOLVER_EVENT && fabs(t - 1.5 * PI) < 1e-8 && fired[0] != 0, "%s: rc %d t %.17g",
                  vi_solver_method_name(METHODS[m]), rc, t);
        vi_solver_free(s);
    }
}

/* An event found beyond the communication point is held and reported by the call whose tout is
 * exactly its time (one-step method: the continuation holds ev_t). */
Test(solver, one_step_event_exactly_at_the_communication_point_is_reported)
{
    rig r;
    rig_osc(&r, VI_METHOD_DOP853);
    double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
    int fired[3];
    long taken;
    vi_solver *s = start(&r, 0.0, x0);
    cr_assert(vi_solver_advance(s, 1.5707, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED && t == 1.5707);
    cr_assert(r.ode.event_pending, "the step over 1.5707 did not reach pi/2 (t = %.17g)", r.ode.t);
    double te = r.ode.ev_t;
    cr_assert(fabs(te - PI / 2) < 1e-9);
    memset(fired, 0, sizeof fired);
    int rc = vi_solver_advance(s, te, 100000, &t, x, fired, &taken);
    cr_assert(rc == VI_SOLVER_EVENT && t == te && taken == 0, "rc %d t %.17g (event at %.17g)", rc, t, te);
    cr_assert(x[0] == r.ode.ev_x[0] && x[1] == r.ode.ev_x[1] && fired[1] == 1 && fired[0] == 0);
    vi_solver_free(s);
}

/* The same for CVODE: a root in the step over tout is held; a call to exactly its time reports it.
 * (Two solvers driven alike take the same steps: the first finds the time, the second asks for it.) */
Test(solver, cvode_event_exactly_at_the_communication_point_is_reported)
{
    for (size_t m = 0; m < 2; m++) {
        rig ra, rb;
        rig_osc(&ra, CVODE_METHODS[m]);
        rig_osc(&rb, CVODE_METHODS[m]);
        double x0[2] = {1.0, 0.0}, x[2], t = 0.0, tb = 0.0, xb[2];
        int fired[3];
        long taken;
        vi_solver *a = start(&ra, 0.0, x0), *b = start(&rb, 0.0, x0);
        const double before = PI / 2 - 1e-9;
        cr_assert(vi_solver_advance(a, before, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
        cr_assert(vi_solver_advance(b, before, 100000, &tb, xb, fired, &taken) == VI_SOLVER_REACHED);
        cr_assert(vi_solver_advance(a, 3.0, 100000, &t, x, fired, &taken) == VI_SOLVER_EVENT);
        cr_assert(taken == 0, "the root was not held: %ld steps", taken);
        double te = t;
        int rc = vi_solver_advance(b, te, 100000, &tb, xb, fired, &taken);
        cr_assert(rc == VI_SOLVER_EVENT && tb == te && taken == 0 && xb[0] == x[0] && xb[1] == x[1], "rc %d t %.17g",
                  rc, tb);
        vi_solver_free(a), vi_solver_free(b);
    }
}

/* A restart drops a root held beyond the last communication point: from the restart the guard
 * crosses only pi/2 later. */
Test(solver, a_restart_drops_a_held_root)
{
    for (size_t m = 0; m < 2; m++) {
        rig r;
        rig_osc(&r, CVODE_METHODS[m]);
        double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
        int fired[3];
        long taken;
        vi_solver *s = start(&r, 0.0, x0);
        const double before = PI / 2 - 1e-9;
        cr_assert(vi_solver_advance(s, before, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
        cr_assert(vi_solver_reset(s, before, x0) == 0);
        int rc = vi_solver_advance(s, before + 1.0, 100000, &t, x, fired, &taken);
        cr_assert(rc == VI_SOLVER_REACHED && t == before + 1.0, "rc %d at %.17g", rc, t);
        cr_assert(fabs(x[0] - cos(1.0)) < 1e-8 && fabs(x[1] + sin(1.0)) < 1e-8);
        rc = vi_solver_advance(s, before + 3.0, 100000, &t, x, fired, &taken);
        cr_assert(rc == VI_SOLVER_EVENT && fabs(t - before - PI / 2) < 1e-8, "rc %d at %.17g", rc, t);
        vi_solver_free(s);
    }
}

/* A guard that is identically zero is no event and gives no warning (CVODE's inactive-root warning
 * is off). */
Test(solver, a_guard_identically_zero_is_quiet)
{
    for (size_t m = 0; m < 4; m++) {
        rig r;
        rig_osc(&r, METHODS[m]);
        r.cfg.nguards = 2, r.cfg.guards = zero_guard;
        double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
        int fired[2];
        long taken;
        vi_solver *s = start(&r, 0.0, x0);
        int rc = vi_solver_advance(s, 2.0, 100000, &t, x, fired, &taken);
        cr_assert(rc == VI_SOLVER_REACHED, "%s: rc %d", vi_solver_method_name(METHODS[m]), rc);
        cr_assert(log_text[0] == 0, "%s: %s", vi_solver_method_name(METHODS[m]), log_text);
        vi_solver_free(s);
    }
}

/* ---- communication points, the work bound, restarts ---------------------------------------------- */

/* Closer to the start than CVODE can begin an integration (4 eps of time), x(tout) is the start
 * state, without a step: at a creation and after a restart; at exactly 4 eps too; beyond (at 4.5
 * eps, and 8 ulps at 1.99 where 4 eps |t| is 7.96 ulps) CVODE takes its step. */
Test(solver, a_communication_point_within_4_eps_of_a_start_is_the_start_state)
{
    const double eps = DBL_EPSILON;
    const struct { double t0, tout; int steps; } cases[] = {
        {1.0, 1.0 + eps, 0},
        {1.0, 1.0 + 2 * eps, 0},
        {-1.0, -1.0 + 4 * eps, 0},
        {-1.0, -1.0 + 4.5 * eps, 1},
        {1.99 - 8 * eps, 1.99, 1},
    };
    for (size_t m = 0; m < 2; m++)
        for (size_t k = 0; k < sizeof cases / sizeof *cases; k++)
            for (int restart = 0; restart < 2; restart++) {
                rig r;
                rig_osc(&r, CVODE_METHODS[m]);
                double x0[2] = {0.6, 0.8}, x[2] = {NAN, NAN}, t;
                int fired[3];
                long taken;
                vi_solver *s = start(&r, restart ? 0.0 : cases[k].t0, x0);
                if (restart) {
                    cr_assert(vi_solver_advance(s, 0.5, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
                    cr_assert(vi_solver_reset(s, cases[k].t0, x0) == 0);
                    x[0] = x[1] = NAN;
                }
                t = cases[k].t0;
                int rc = vi_solver_advance(s, cases[k].tout, 100, &t, x, fired, &taken);
                cr_assert(rc == VI_SOLVER_REACHED && t == cases[k].tout, "case %zu: rc %d %s", k, rc, log_text);
                cr_assert(cases[k].steps ? taken >= 1 : taken == 0, "case %zu restart %d: %ld steps", k, restart, taken);
                if (!cases[k].steps) cr_assert(x[0] == x0[0] && x[1] == x0[1], "x %.17g %.17g", x[0], x[1]);
                else cr_assert(fabs(x[0] - x0[0]) < 1e-12 && fabs(x[1] - x0[1]) < 1e-12);
                /* and from there on as usual */
                rc = vi_solver_advance(s, cases[k].t0 + 1.0, 100000, &t, x, fired, &taken);
                cr_assert(rc == VI_SOLVER_REACHED, "rc %d %s", rc, log_text);
                double c = cos(1.0), sn = sin(1.0);
                cr_assert(fabs(x[0] - (0.6 * c + 0.8 * sn)) < 1e-8 && fabs(x[1] - (0.8 * c - 0.6 * sn)) < 1e-8);
                vi_solver_free(s);
            }
}

/* The work bound: max_steps steps, then the last internal step (*t < tout) with its state; with 0
 * steps allowed, the point of the last restart. Reaching it is no error: nothing is logged (CVODE's
 * own "too much work" message is not passed on). */
Test(solver, the_work_bound_returns_the_last_internal_step)
{
    for (size_t m = 0; m < 4; m++) {
        rig r;
        rig_osc(&r, METHODS[m]);
        double x0[2] = {1.0, 0.0}, x[2] = {NAN, NAN}, t = 0.0;
        int fired[3];
        long taken = 99;
        const char *name = vi_solver_method_name(METHODS[m]);
        vi_solver *s = start(&r, 0.0, x0);
        for (int k = 1; k <= 3; k++) {
            double before = t;
            x[0] = x[1] = NAN;
            int rc = vi_solver_advance(s, 1.0, 1, &t, x, fired, &taken);
            cr_assert(rc == VI_SOLVER_LIMIT && taken == 1 && t > before && t < 1.0, "%s: rc %d taken %ld t %g", name, rc,
                      taken, t);
            cr_assert(fabs(x[0] - cos(t)) < 1e-9 && fabs(x[1] + sin(t)) < 1e-9, "%s: x(%g) = %g %g", name, t, x[0], x[1]);
            if (METHODS[m] == VI_METHOD_DOP853 || METHODS[m] == VI_METHOD_AUTO)
                cr_assert(t == r.ode.t && x[0] == r.ode.x[0] && x[1] == r.ode.x[1]);
        }
        cr_assert(log_errors == 0 && log_warnings == 0, "%s: %s", name, log_text);
        double x1[2] = {0.0, 1.0};
        cr_assert(vi_solver_reset(s, 0.25, x1) == 0);
        x[0] = x[1] = NAN;
        int rc = vi_solver_advance(s, 1.0, 0, &t, x, fired, &taken);
        cr_assert(rc == VI_SOLVER_LIMIT && taken == 0 && t == 0.25 && x[0] == 0.0 && x[1] == 1.0, "%s: rc %d t %g", name,
                  rc, t);
        vi_solver_free(s);
    }
}

/* A communication point inside (or at the end of) the last internal step takes no step: two solvers
 * driven alike, one step at a time and then to the end of the second step, agree bit for bit. */
Test(solver, a_point_inside_the_last_step_takes_no_step)
{
    for (size_t m = 0; m < 4; m++) {
        rig ra, rb;
        rig_osc(&ra, METHODS[m]);
        rig_osc(&rb, METHODS[m]);
        const char *name = vi_solver_method_name(METHODS[m]);
        double x0[2] = {1.0, 0.0}, xa[2], xb[2], ta = 0.0, tb = 0.0;
        int fired[3];
        long taken;
        vi_solver *a = start(&ra, 0.0, x0), *b = start(&rb, 0.0, x0);
        cr_assert(vi_solver_advance(a, 1.0, 1, &ta, xa, fired, &taken) == VI_SOLVER_LIMIT);
        double t1 = ta;
        cr_assert(vi_solver_advance(a, 1.0, 1, &ta, xa, fired, &taken) == VI_SOLVER_LIMIT);
        double t2 = ta;
        cr_assert(vi_solver_advance(b, 1.0, 1, &tb, xb, fired, &taken) == VI_SOLVER_LIMIT && tb == t1);
        int rc = vi_solver_advance(b, 0.5 * (t1 + t2), 5, &tb, xb, fired, &taken);
        cr_assert(rc == VI_SOLVER_REACHED && taken == 1, "%s: rc %d taken %ld", name, rc, taken);
        double tm = 0.5 * (t1 + t2);
        cr_assert(fabs(xb[0] - cos(tm)) < 1e-9 && fabs(xb[1] + sin(tm)) < 1e-9);
        rc = vi_solver_advance(b, t2, 5, &tb, xb, fired, &taken);
        cr_assert(rc == VI_SOLVER_REACHED && taken == 0 && tb == t2, "%s: rc %d taken %ld", name, rc, taken);
        cr_assert(xb[0] == xa[0] && xb[1] == xa[1], "%s: %.17g %.17g vs %.17g %.17g", name, xb[0], xb[1], xa[0], xa[1]);
        vi_solver_free(a), vi_solver_free(b);
    }
}

/* The end of a step exactly at tout: the one-step method's steps do not depend on tout, so a second
 * solver asked for the end of the first step reaches it with that one step. */
Test(solver, one_step_tout_at_a_step_end_takes_that_step_only)
{
    rig ra, rb;
    rig_osc(&ra, VI_METHOD_DOP853);
    rig_osc(&rb, VI_METHOD_DOP853);
    double x0[2] = {1.0, 0.0}, xa[2], xb[2], ta = 0.0, tb = 0.0;
    int fired[3];
    long taken;
    vi_solver *a = start(&ra, 0.0, x0), *b = start(&rb, 0.0, x0);
    cr_assert(vi_solver_advance(a, 1.0, 1, &ta, xa, fired, &taken) == VI_SOLVER_LIMIT);
    int rc = vi_solver_advance(b, ta, 5, &tb, xb, fired, &taken);
    cr_assert(rc == VI_SOLVER_REACHED && taken == 1 && tb == ta && xb[0] == xa[0] && xb[1] == xa[1], "rc %d taken %ld",
              rc, taken);
    vi_solver_free(a), vi_solver_free(b);
}

/* The one-step method through the interface is vi_ode with the configuration's problem and
 * VI_SOLVER_GUARD_SAMPLES interior samples: creation, each step and a restart leave the
 * continuation byte for byte as vi_ode_init, vi_ode_step and vi_ode_restart do. */
Test(solver, the_one_step_method_is_vi_ode_with_the_configured_problem)
{
    rig r;
    rig_osc(&r, VI_METHOD_DOP853);
    r.cfg.rtol = 1e-7, r.cfg.max_step = 0.3;
    r.atol[0] = 1e-9, r.atol[1] = 2e-9;
    double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
    r.cfg.guards = osc_far;
    vi_ode_problem p = {.n = 2, .ng = 3, .rhs = osc, .guards = osc_far, .user = NULL, .rtol = 1e-7,
                        .atol = {1e-9, 2e-9}, .max_step = 0.3, .guard_samples = VI_SOLVER_GUARD_SAMPLES};
    vi_ode ref;
    memset(&ref, 0xA5, sizeof ref);
    cr_assert(vi_ode_init(&ref, &p, 0.0, x0, 0.0, 0u) == VI_ODE_OK);
    vi_solver *s = start(&r, 0.0, x0);
    r.atol[0] = r.atol[1] = NAN; /* the configuration was copied */
    cr_assert(memcmp(&r.ode, &ref, sizeof ref) == 0, "creation differs from vi_ode_init");
    int fired[3];
    long taken;
    for (int k = 0; k < 6; k++) {
        cr_assert(vi_solver_advance(s, 100.0, 1, &t, x, fired, &taken) == VI_SOLVER_LIMIT);
        cr_assert(vi_ode_step(&ref, &p, INFINITY) == VI_ODE_OK);
        cr_assert(memcmp(&r.ode, &ref, sizeof ref) == 0, "step %d differs", k);
        cr_assert(ref.t - ref.t_old <= 0.3);
    }
    double x1[2] = {0.5, -0.5};
    cr_assert(vi_solver_reset(s, t, x1) == 0);
    cr_assert(vi_ode_restart(&ref, &p, t, x1, 0.0, 0u) == VI_ODE_OK);
    cr_assert(memcmp(&r.ode, &ref, sizeof ref) == 0, "restart differs");
    /* the guard evaluations: one at each restart, then an end and 2 samples per step */
    vi_solver_stats st;
    vi_solver_statistics(s, &st);
    cr_assert(st.guard_evals == 2 + 6 * (1 + VI_SOLVER_GUARD_SAMPLES), "%ld", st.guard_evals);
    vi_solver_free(s);
}

/* A restart of the one-step method at a state it cannot start from fails with the time. */
Test(solver, a_one_step_restart_that_fails_is_logged_with_the_time)
{
    rig r;
    rig_osc(&r, VI_METHOD_DOP853);
    double x0[2] = {1.0, 0.0}, bad[2] = {NAN, 0.0};
    vi_solver *s = start(&r, 0.0, x0);
    cr_assert(vi_solver_reset(s, 0.75, bad) == VI_SOLVER_FAILED);
    cr_assert(logged(VI_LOG_ERROR, "vi_ode_restart failed at t = 0.75 s: invalid problem, state or call"), "%s",
              log_text);
    vi_solver_free(s);
}

static void nan_after_half(double t, const double *x, double *dx, void *u)
{
    (void)x, (void)u;
    dx[0] = t < 0.5 ? 1.0 : NAN;
    dx[1] = 0.0;
}

/* The one-step method's failure is logged with the time it got to. */
Test(solver, a_one_step_failure_is_logged_with_the_last_good_time)
{
    rig r;
    rig_osc(&r, VI_METHOD_DOP853);
    r.cfg.rhs = nan_after_half, r.cfg.nguards = 0;
    double x0[2] = {0.0, 0.0}, x[2], t = 0.0;
    int fired[1];
    long taken;
    vi_solver *s = start(&r, 0.0, x0);
    cr_assert(vi_solver_advance(s, 1.0, 1000, &t, x, fired, &taken) == VI_SOLVER_FAILED);
    char want[200];
    snprintf(want, sizeof want, "vi_ode_step failed at t = %.17g s: right-hand side or guards not finite", r.ode.t);
    cr_assert(r.ode.t < 0.5 && r.ode.t > 0.49, "%.17g", r.ode.t);
    cr_assert(logged(VI_LOG_ERROR, want), "%s", log_text);
    vi_solver_free(s);
}

/* ---- checks of saved states -------------------------------------------------------------------- */

/* vi_solver_ode_check: each field bad alone is refused naming it; the ends of the rules pass. */
Test(solver, the_continuation_check_names_each_bad_field)
{
    vi_ode_problem p = {.n = 2, .ng = 2, .rhs = osc, .guards = zero_guard, .rtol = 1e-8, .atol = {1e-9, 1e-9}};
    double x0[2] = {1.0, 0.0};
    vi_ode good;
    cr_assert(vi_ode_init(&good, &p, 0.0, x0, 0.0, 0u) == VI_ODE_OK);
    cr_assert(vi_ode_step(&good, &p, INFINITY) == VI_ODE_OK);
    const double t = good.t; /* the caller's time: the end of the step */
    char msg[200];
    cr_assert(vi_solver_ode_check(&good, 2, 2, t, msg, sizeof msg) == 0, "%s", msg);
    vi_ode o;
#define BAD(stmt, n, ng, text)                                                                         \
    do {                                                                                               \
        o = good;                                                                                      \
        stmt;                                                                                          \
        msg[0] = 0;                                                                                    \
        cr_assert(vi_solver_ode_check(&o, n, ng, t, msg, sizeof msg) == -1, "accepted: %s", #stmt);   \
        cr_assert(strstr(msg, text) != NULL, "%s: '%s'", #stmt, msg);                                  \
    } while (0)
#define OK(stmt, tt)                                                                                   \
    do {                                                                                               \
        o = good;                                                                                      \
        stmt;                                                                                          \
        cr_assert(vi_solver_ode_check(&o, 2, 2, tt, msg, sizeof msg) == 0, "%s: %s", #stmt, msg);      \
    } while (0)
    BAD((void)0, 3, 2, "ode: made for 2 states and 2 guards, not 3 and 2");
    BAD((void)0, 2, 1, "ode: made for 2 states and 2 guards, not 2 and 1");
    BAD(o.t = NAN, 2, 2, "ode.t = nan is not finite");
    BAD(o.t = INFINITY, 2, 2, "ode.t = inf is not finite");
    BAD(o.t = nextafter(t, 0.0), 2, 2, "is not finite or before t");
    BAD(o.h = 0.0, 2, 2, "ode.h = 0 is not finite and positive");
    BAD(o.h = -1.0, 2, 2, "ode.h = -1 is not");
    BAD(o.h = INFINITY, 2, 2, "ode.h = inf is not");
    BAD(o.event_pending = 2, 2, 2, "ode.event_pending = 2");
    BAD(o.event_pending = -1, 2, 2, "ode.event_pending = -1");
    BAD(o.have_step = 2, 2, 2, "ode.have_step = 2");
    BAD(o.have_step = -1, 2, 2, "ode.have_step = -1");
    BAD(o.cur = 2, 2, 2, "ode.cur = 2");
    BAD(o.cur = -1, 2, 2, "ode.cur = -1");
    BAD(o.t_old = nextafter(t, INFINITY), 2, 2, "ode: the last step [");
    BAD((o.have_step = 0, o.t = t + 1.0), 2, 2, "a restart must be at t");
    BAD(o.x[0] = NAN, 2, 2, "ode.x[0] or ode.f[0] is not finite");
    BAD(o.x[1] = INFINITY, 2, 2, "ode.x[1] or ode.f[1] is not finite");
    BAD(o.f[0] = -INFINITY, 2, 2, "ode.x[0] or ode.f[0]");
    BAD(o.f[1] = NAN, 2, 2, "ode.x[1] or ode.f[1]");
    BAD(o.g[0] = NAN, 2, 2, "ode.g[0] is not finite");
    BAD(o.g[1] = INFINITY, 2, 2, "ode.g[1] is not finite");
    /* the ends of the rules */
    OK(o.event_pending = 1, t);
    OK(o.have_step = 0, o.t);
    OK(o.cur = 1 - o.cur, t);
    OK(o.h = DBL_MIN, t);
    OK(o.t_old = t, t);
    OK((void)0, good.t_old);                /* a time at the start of the last step */
    OK(o.x[2] = NAN, t);                     /* beyond n */
    OK((o.f[2] = NAN, o.g[2] = NAN), t);     /* beyond n and ng */
    cr_assert(vi_solver_ode_check(&good, 2, 2, nextafter(good.t_old, -INFINITY), msg, sizeof msg) == -1);
#undef BAD
#undef OK
}

/* vi_solver_auto_check: the ranges' ends pass, one beyond each is refused with its message. */
Test(solver, the_auto_choice_check_takes_its_ranges_and_names_each_bad_field)
{
    char msg[200];
    vi_solver_auto ok = {0}, a;
    cr_assert(vi_solver_auto_check(&ok, msg, sizeof msg) == 0);
    vi_solver_auto top = {.bdf = 1, .pending = 1, .stiff = VI_AUTO_STIFF_STEPS, .calm = VI_AUTO_CALM_STEPS,
                          .steps = VI_AUTO_BDF_MIN_STEPS, .switches = 1000000};
    cr_assert(vi_solver_auto_check(&top, msg, sizeof msg) == 0, "%s", msg);
#define BAD(stmt, text)                                                                                \
    do {                                                                                               \
        a = ok;                                                                                        \
        stmt;                                                                                          \
        msg[0] = 0;                                                                                    \
        cr_assert(vi_solver_auto_check(&a, msg, sizeof msg) == -1, "accepted: %s", #stmt);            \
        cr_assert_str_eq(msg, text);                                                                   \
    } while (0)
    BAD(a.bdf = 2, "auto_choice.bdf = 2 is not 0 or 1");
    BAD(a.bdf = -1, "auto_choice.bdf = -1 is not 0 or 1");
    BAD(a.pending = 2, "auto_choice.pending = 2 is not 0 or 1");
    BAD(a.pending = -1, "auto_choice.pending = -1 is not 0 or 1");
    BAD(a.stiff = -1, "auto_choice.stiff = -1 is not in [0, 8]");
    BAD(a.stiff = 9, "auto_choice.stiff = 9 is not in [0, 8]");
    BAD(a.calm = -1, "auto_choice.calm = -1 is not in [0, 6]");
    BAD(a.calm = 7, "auto_choice.calm = 7 is not in [0, 6]");
    BAD(a.steps = -1, "auto_choice.steps = -1 is not in [0, 10]");
    BAD(a.steps = 11, "auto_choice.steps = 11 is not in [0, 10]");
    BAD(a.switches = -1, "auto_choice.switches = -1 is negative");
#undef BAD
}

/* Resuming the one-step method checks the continuation and says why it refuses it; auto checks it
 * only when the one-step method runs. */
Test(solver, resume_refuses_an_inconsistent_continuation)
{
    rig r;
    rig_osc(&r, VI_METHOD_DOP853);
    double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
    int fired[3];
    long taken;
    vi_solver *s = start(&r, 0.0, x0);
    cr_assert(vi_solver_advance(s, 0.5, 1000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
    vi_solver_free(s);
    r.ode.h = 0.0;
    log_clear();
    cr_assert(vi_solver_resume(&r.cfg, 0.5, x) == NULL);
    cr_assert(logged(VI_LOG_ERROR, "one-step method: the saved continuation is inconsistent: ode.h = 0 is not finite and "
                                   "positive"),
              "%s", log_text);

    rig_osc(&r, VI_METHOD_AUTO);
    s = start(&r, 0.0, x0);
    t = 0.0;
    cr_assert(vi_solver_advance(s, 0.5, 1000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
    vi_solver_free(s);
    r.ode.h = 0.0;
    log_clear();
    cr_assert(vi_solver_resume(&r.cfg, 0.5, x) == NULL);
    cr_assert(strstr(log_text, "the saved continuation is inconsistent: ode.h = 0") != NULL, "%s", log_text);
    r.sw.bdf = 1; /* BDF runs: the continuation is not used */
    log_clear();
    s = vi_solver_resume(&r.cfg, 0.5, x);
    cr_assert(s != NULL && log_text[0] == 0, "%s", log_text);
    vi_solver_free(s);
}

/* A state taken at a communication point (checkpoint, then a byte copy of the continuation and the
 * choice) and resumed in a new solver continues bit for bit like the original, for every method. */
Test(solver, a_resumed_state_continues_bit_for_bit)
{
    for (size_t m = 0; m < 4; m++) {
        rig ra, rb;
        rig_osc(&ra, METHODS[m]);
        double x0[2] = {1.0, 0.0}, xa[2], xb[2], ta = 0.0, tb;
        int fired[3];
        long taken;
        vi_solver *a = start(&ra, 0.0, x0);
        cr_assert(vi_solver_advance(a, 0.7, 100000, &ta, xa, fired, &taken) == VI_SOLVER_REACHED);
        cr_assert(vi_solver_checkpoint(a, ta, xa) == 0);
        rb = ra;
        rb.cfg.ode = &rb.ode, rb.cfg.auto_choice = &rb.sw, rb.cfg.atol = rb.atol;
        log_clear();
        vi_solver *b = vi_solver_resume(&rb.cfg, ta, xa);
        cr_assert(b != NULL, "%s: %s", vi_solver_method_name(METHODS[m]), log_text);
        tb = ta, xb[0] = xa[0], xb[1] = xa[1];
        for (int k = 1; k <= 5; k++) {
            double tout = 0.7 + 0.2 * k;
            int rca = vi_solver_advance(a, tout, 100000, &ta, xa, fired, &taken);
            int rcb = vi_solver_advance(b, tout, 100000, &tb, xb, fired, &taken);
            cr_assert(rca == rcb && ta == tb && xa[0] == xb[0] && xa[1] == xb[1], "%s, k %d: %.17g vs %.17g",
                      vi_solver_method_name(METHODS[m]), k, xa[0], xb[0]);
            if (rca == VI_SOLVER_EVENT) {
                cr_assert(vi_solver_reset(a, ta, xa) == 0 && vi_solver_reset(b, tb, xb) == 0);
                k--;
            }
        }
        vi_solver_free(a), vi_solver_free(b);
    }
}

/* ---- statistics, restarts and checkpoints -------------------------------------------------------- */

/* A stiff linear system (eigenvalues -1 and -1000) driven through its transient. */
static void stiff_lin(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = -1000.0 * x[0] + 999.0 * x[1];
    dx[1] = -x[1];
}

static long jac_calls;
static void stiff_jac(double t, const double *x, double *j, void *u)
{
    (void)t, (void)x, (void)u;
    jac_calls++;
    j[0] = -1000.0, j[1] = 999.0, j[2] = 0.0, j[3] = -1.0;
}

/* Van der Pol's oscillator with mu = 1000 (stiff, with sharp turns: every counter of CVODE moves). */
static const double VDP_MU = 1000.0;
static void vdp(double t, const double *x, double *dx, void *u)
{
    (void)t, (void)u;
    dx[0] = x[1];
    dx[1] = VDP_MU * (1.0 - x[0] * x[0]) * x[1] - x[0];
}

static void vdp_jac(double t, const double *x, double *j, void *u)
{
    (void)t, (void)u;
    jac_calls++;
    j[0] = 0.0, j[1] = 1.0, j[2] = -2.0 * VDP_MU * x[0] * x[1] - 1.0, j[3] = VDP_MU * (1.0 - x[0] * x[0]);
}

/* CVODE's counters add up over restarts: a run restarted at t = 1000 counts what the run up to 1000
 * did plus what a new solver started there does; restarts counted. */
Test(solver, cvode_statistics_add_up_over_restarts)
{
    for (size_t m = 0; m < 2; m++) {
        for (int with_jac = 0; with_jac < 2; with_jac++) {
            rig ra, rb;
            rig_osc(&ra, CVODE_METHODS[m]);
            never_ng = 1;
            ra.cfg.rhs = vdp, ra.cfg.nguards = 1, ra.cfg.guards = never, ra.cfg.jac = with_jac ? vdp_jac : NULL;
            ra.cfg.rtol = 1e-6, ra.atol[0] = ra.atol[1] = 1e-8;
            rb = ra;
            rb.cfg.ode = &rb.ode, rb.cfg.auto_choice = &rb.sw, rb.cfg.atol = rb.atol;
            double x0[2] = {2.0, 0.0}, x[2], t = 0.0, xb[2], tb = 1000.0;
            int fired[1];
            long taken, sum = 0;
            vi_solver *a = start(&ra, 0.0, x0);
            for (int k = 1; k <= 4; k++) {
                cr_assert(vi_solver_advance(a, 250.0 * k, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
                sum += taken;
            }
            vi_solver_stats s1, s2, sb, sa;
            vi_solver_statistics(a, &s1);
            cr_assert(s1.steps == sum && s1.resets == 0, "%ld steps, %ld taken", s1.steps, sum);
            cr_assert(vi_solver_reset(a, 1000.0, x) == 0);
            vi_solver_statistics(a, &s2);
            cr_assert(s2.resets == 1 && s2.steps == s1.steps && s2.rhs_evals == s1.rhs_evals);
            jac_calls = 0;
            vi_solver *b = start(&rb, 1000.0, x);
            for (int k = 1; k <= 4; k++) {
                cr_assert(vi_solver_advance(a, 1000.0 + 250.0 * k, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
                cr_assert(vi_solver_advance(b, 1000.0 + 250.0 * k, 100000, &tb, xb, fired, &taken) == VI_SOLVER_REACHED);
                cr_assert(x[0] == xb[0] && x[1] == xb[1]);
            }
            vi_solver_statistics(a, &sa);
            vi_solver_statistics(b, &sb);
            cr_assert_str_eq(sa.method, vi_solver_method_name(CVODE_METHODS[m]));
            cr_assert(sa.resets == 1 && sb.resets == 0);
            cr_assert(sa.steps == s1.steps + sb.steps && sa.rhs_evals == s1.rhs_evals + sb.rhs_evals &&
                      sa.jac_evals == s1.jac_evals + sb.jac_evals && sa.nonlin_iters == s1.nonlin_iters + sb.nonlin_iters &&
                      sa.nonlin_fails == s1.nonlin_fails + sb.nonlin_fails &&
                      sa.err_test_fails == s1.err_test_fails + sb.err_test_fails &&
                      sa.guard_evals == s1.guard_evals + sb.guard_evals && sa.switches == 0,
                      "steps %ld = %ld + %ld, rhs %ld = %ld + %ld", sa.steps, s1.steps, sb.steps, sa.rhs_evals, s1.rhs_evals,
                      sb.rhs_evals);
            /* every counter of the first part is used (a sum cannot hide) */
            cr_assert(s1.steps > 0 && s1.rhs_evals > 0 && s1.nonlin_iters > 0 && s1.guard_evals > 0 && s1.jac_evals > 0 &&
                          s1.err_test_fails > 0 && s1.nonlin_fails > 0 && sb.nonlin_fails > 0,
                      "jac %ld, error test failures %ld, convergence failures %ld and %ld", s1.jac_evals, s1.err_test_fails,
                      s1.nonlin_fails, sb.nonlin_fails);
            if (with_jac) cr_assert(jac_calls == sa.jac_evals - s1.jac_evals + sb.jac_evals, "%ld calls, %ld + %ld", jac_calls, sa.jac_evals - s1.jac_evals, sb.jac_evals);
            vi_solver_free(a), vi_solver_free(b);
        }
    }
}

/* The analytic Jacobian is what CVODE uses, entry for entry: a run with it does the work of a run
 * with difference quotients (exact here to rounding, the system being linear) to within a few
 * percent, and calls it once per evaluation. (A Jacobian transposed or with a column missing makes
 * the Newton iteration diverge at these step sizes.) */
Test(solver, the_jacobian_is_passed_to_cvode)
{
    rig ra, rb;
    rig_osc(&ra, VI_METHOD_BDF);
    ra.cfg.rhs = stiff_lin, ra.cfg.nguards = 0, ra.cfg.jac = stiff_jac, ra.cfg.rtol = 1e-6;
    ra.atol[0] = ra.atol[1] = 1e-8;
    rb = ra;
    rb.cfg.atol = rb.atol, rb.cfg.jac = NULL;
    double x0[2] = {0.0, 1.0}, xa[2], xb[2], ta = 0.0, tb = 0.0;
    int fired[1];
    long taken;
    jac_calls = 0;
    vi_solver *a = start(&ra, 0.0, x0), *b = start(&rb, 0.0, x0);
    cr_assert(vi_solver_advance(a, 2.0, 100000, &ta, xa, fired, &taken) == VI_SOLVER_REACHED);
    cr_assert(vi_solver_advance(b, 2.0, 100000, &tb, xb, fired, &taken) == VI_SOLVER_REACHED);
    vi_solver_stats sa, sb;
    vi_solver_statistics(a, &sa);
    vi_solver_statistics(b, &sb);
    cr_assert(jac_calls == sa.jac_evals && jac_calls > 0, "%ld calls, %ld evaluations", jac_calls, sa.jac_evals);
    cr_assert(sa.steps <= 1.05 * sb.steps && sa.nonlin_iters <= 1.05 * sb.nonlin_iters &&
                  sa.nonlin_fails <= sb.nonlin_fails + 2,
              "steps %ld vs %ld, iterations %ld vs %ld, failures %ld vs %ld", sa.steps, sb.steps, sa.nonlin_iters,
              sb.nonlin_iters, sa.nonlin_fails, sb.nonlin_fails);
    cr_assert(fabs(xa[0] - exp(-2.0)) < 1e-5 && fabs(xa[1] - exp(-2.0)) < 1e-5);
    vi_solver_free(a), vi_solver_free(b);
}

/* max_step bounds CVODE's steps: at most 1e-3 s (the limit of the rule's other side), so at least
 * 100 steps over 0.1 s where the oscillator needs a handful. */
Test(solver, max_step_bounds_cvode_steps)
{
    for (size_t m = 0; m < 2; m++) {
        rig r;
        rig_osc(&r, CVODE_METHODS[m]);
        r.cfg.rtol = 1e-4, r.atol[0] = r.atol[1] = 1e-6, r.cfg.max_step = 1e-3;
        double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
        int fired[3];
        long taken;
        vi_solver *s = start(&r, 0.0, x0);
        cr_assert(vi_solver_advance(s, 0.1, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
        cr_assert(taken >= 100, "%ld steps", taken);
        vi_solver_free(s);
        r.cfg.max_step = 0.0;
        s = start(&r, 0.0, x0);
        t = 0.0;
        cr_assert(vi_solver_advance(s, 0.1, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
        cr_assert(taken < 50, "%ld steps", taken);
        vi_solver_free(s);
    }
}

/* The one-step method's statistics are its continuation's counters; restarts are counted, the one
 * at creation not. */
Test(solver, one_step_statistics_are_the_continuations_counters)
{
    const int methods[] = {VI_METHOD_DOP853, VI_METHOD_AUTO};
    for (int m = 0; m < 2; m++) {
        rig r;
        rig_osc(&r, methods[m]);
        never_ng = 1;
        r.cfg.rhs = stiff_lin, r.cfg.nguards = 1, r.cfg.guards = never, r.cfg.rtol = 1e-6; /* held by stability: rejections */
        double x0[2] = {0.0, 1.0}, x[2], t = 0.0;
        int fired[3];
        long taken;
        vi_solver *s = start(&r, 0.0, x0);
        vi_solver_stats st;
        vi_solver_statistics(s, &st);
        cr_assert(st.resets == 0 && st.steps == 0, "%ld resets", st.resets);
        cr_assert(vi_solver_advance(s, 0.5, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
        cr_assert(vi_solver_reset(s, 0.5, x) == 0);
        cr_assert(vi_solver_advance(s, 1.0, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
        cr_assert(vi_solver_reset(s, t, x) == 0);
        memset(&st, 0x55, sizeof st); /* every field is written */
        vi_solver_statistics(s, &st);
        const vi_ode_stats *o = &r.ode.st;
        cr_assert(st.steps == o->accepted && st.rhs_evals == o->rhs_evals && st.err_test_fails == o->rejected &&
                      st.guard_evals == o->guard_evals && st.resets == 2 && st.jac_evals == 0 && st.nonlin_iters == 0 &&
                      st.nonlin_fails == 0 && st.switches == 0,
                  "steps %ld/%ld rhs %ld/%ld rejected %ld/%ld guards %ld/%ld resets %ld", st.steps, o->accepted,
                  st.rhs_evals, o->rhs_evals, st.err_test_fails, o->rejected, st.guard_evals, o->guard_evals, st.resets);
        cr_assert(o->accepted > 0 && o->rejected > 0 && o->rhs_evals > 0 && o->guard_evals > 0, "rejected %ld", o->rejected);
        cr_assert_str_eq(st.method, vi_solver_method_name(methods[m]));
        vi_solver_free(s);
    }
}

/* A checkpoint restarts CVODE (counted as a restart) and leaves the one-step method alone. */
Test(solver, a_checkpoint_restarts_cvode_only)
{
    for (size_t m = 0; m < 4; m++) {
        rig r;
        rig_osc(&r, METHODS[m]);
        double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
        int fired[3];
        long taken;
        vi_solver *s = start(&r, 0.0, x0);
        cr_assert(vi_solver_advance(s, 0.5, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
        vi_ode before = r.ode;
        cr_assert(vi_solver_checkpoint(s, t, x) == 0);
        vi_solver_stats st;
        vi_solver_statistics(s, &st);
        int cvode = METHODS[m] == VI_METHOD_BDF || METHODS[m] == VI_METHOD_ADAMS;
        cr_assert(st.resets == cvode, "%s: %ld resets", vi_solver_method_name(METHODS[m]), st.resets);
        if (!cvode) cr_assert(memcmp(&before, &r.ode, sizeof before) == 0);
        vi_solver_free(s);
    }
}

/* vi_solver_create copies the configuration: the caller's atol array may change (or go) after it,
 * and a restart still takes the tolerances given at creation. Two solvers, one whose caller's array
 * is set to 1 m after creation, restarted and advanced alike, end at the same state bit for bit. */
Test(solver, a_restart_keeps_the_tolerances_given_at_creation)
{
    for (size_t m = 0; m < 4; m++) {
        rig r, kept;
        rig_osc(&r, METHODS[m]);
        rig_osc(&kept, METHODS[m]);
        double x0[2] = {1.0, 0.0}, x[2][2], t[2] = {0.0, 0.0};
        int fired[3];
        long taken;
        vi_solver *s[2] = {start(&r, 0.0, x0), start(&kept, 0.0, x0)};
        for (int i = 0; i < VI_SOLVER_MAX_N; i++) r.atol[i] = 1.0;
        for (int k = 0; k < 2; k++) {
            cr_assert(vi_solver_reset(s[k], 0.0, x0) == 0);
            cr_assert(vi_solver_advance(s[k], 1.5, 100000, &t[k], x[k], fired, &taken) == VI_SOLVER_REACHED);
            vi_solver_free(s[k]);
        }
        cr_assert(t[0] == t[1] && x[0][0] == x[1][0] && x[0][1] == x[1][1],
                  "%s: (%.17g, %.17g) after the caller's atol changed, (%.17g, %.17g) without",
                  vi_solver_method_name(METHODS[m]), x[0][0], x[0][1], x[1][0], x[1][1]);
    }
}

/* ---- auto ----------------------------------------------------------------------------------------- */

/* x0' = 1, x1' = -k (x1 - 1) from (1, 1): x0 = 1 + t, x1 = 1, both exact for either method. The
 * Jacobian the stiffness tests see is set by the test (J; consistent with the right-hand side,
 * diag(0, -k), while BDF runs). atol 1e3 and max_step 0.5 make every step of the one-step method
 * 0.5 s exactly (Hairer's first step exceeds it, the error is nil), so h rho is exact. */
static double J[4], K;
static void lin(double t, const double *x, double *dx, void *u)
{
    (void)t;
    dx[0] = 1.0;
    if (*(const int *)u == 2) dx[1] = -K * (x[1] - 1.0);
}

static void jac_set(double t, const double *x, double *j, void *u)
{
    (void)t, (void)x, (void)u;
    memcpy(j, J, sizeof J);
}

static void set_j(double a, double b, double c, double d) { J[0] = a, J[1] = b, J[2] = c, J[3] = d; }

static vi_solver *auto_rig(rig *r, int n)
{
    memset(r, 0, sizeof *r);
    for (int i = 0; i < VI_SOLVER_MAX_N; i++) r->atol[i] = 1e3;
    r->cfg = (vi_solver_config){.n = n, .nguards = 0, .rhs = lin, .guards = never, .jac = jac_set,
                                .method = VI_METHOD_AUTO, .rtol = 1e-3, .atol = r->atol, .max_step = 0.5,
                                .ode = &r->ode, .auto_choice = &r->sw, .log = capture};
    r->cfg.user = &r->cfg.n;
    K = 0.0;
    set_j(0.0, 0.0, 0.0, 0.0);
    double x0[2] = {1.0, 1.0};
    return start(r, 0.0, x0);
}

/* One step (the work bound 1) from t, checked against x0 = 1 + t. */
static void one(vi_solver *s, rig *r, double *t)
{
    double x[2] = {NAN, NAN};
    int fired[1];
    long taken;
    double before = *t;
    int rc = vi_solver_advance(s, 1e6, 1, t, x, fired, &taken);
    cr_assert(rc == VI_SOLVER_LIMIT && taken == 1 && *t > before, "rc %d taken %ld: %s", rc, taken, log_text);
    cr_assert(fabs(x[0] - (1.0 + *t)) <= 1e-9 * (1.0 + *t), "x0(%.17g) = %.17g", *t, x[0]);
    if (r->cfg.n == 2) cr_assert(fabs(x[1] - 1.0) < 1e-12, "x1 = %.17g", x[1]);
    if (!r->sw.bdf) cr_assert(r->ode.t - r->ode.t_old == 0.5, "step %.17g", r->ode.t - r->ode.t_old);
}

/* The spectral radius of the Jacobian at the end of each step decides a step: h rho > 4.8 counts
 * as held by stability, else calm. Real pairs (rho = |tr|/2 + sqrt(tr^2/4 - det)) and complex
 * pairs (rho = sqrt(det)) just below (9.5: h rho = 4.75) and above (9.75: 4.875); a single
 * state (rho = |J|); exactly 4.8 is not above. */
Test(solver, auto_spectral_radius_decides_each_step)
{
    const struct { int n; double j[4]; int stiff; } cases[] = {
        {2, {-9.0, 7.0, 0.5, -2.5}, 0},   /* eigenvalues -9.5, -2 */
        {2, {-9.0, 7.0, 0.75, -2.75}, 1}, /* -9.75, -2 */
        {2, {-2.5, 0.5, 7.0, -9.0}, 0},   /* the transpose */
        {2, {0.5, 2.0, -45.25, -0.5}, 0}, /* +-9.5 i */
        {2, {0.5, 2.0, -47.65625, -0.5}, 1}, /* +-9.75 i */
        {2, {-9.6, 0.0, 0.0, -9.6}, 0},   /* a double eigenvalue: h rho = 4.8 */
        {2, {-9.61, 0.0, 0.0, -9.59}, 1}, /* nearly double: rho = 9.61, not sqrt(det) = 9.59999 */
        {1, {-9.5, 100.0, 100.0, 100.0}, 0}, /* one state: only J[0] is its Jacobian */
        {1, {9.75, 0, 0, 0}, 1},
        {1, {-9.6, 0, 0, 0}, 0},
        {1, {nextafter(-9.6, -INFINITY), 0, 0, 0}, 1},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        rig r;
        vi_solver *s = auto_rig(&r, cases[k].n);
        double t = 0.0;
        one(s, &r, &t);
        cr_assert(r.sw.calm == 1 && r.sw.stiff == 0, "case %zu: calm %d stiff %d", k, r.sw.calm, r.sw.stiff);
        memcpy(J, cases[k].j, sizeof J);
        one(s, &r, &t);
        if (cases[k].stiff)
            cr_assert(r.sw.stiff == 1 && r.sw.calm == 0, "case %zu: not stiff (calm %d)", k, r.sw.calm);
        else
            cr_assert(r.sw.stiff == 0 && r.sw.calm == 2, "case %zu: stiff (stiff %d calm %d)", k, r.sw.stiff, r.sw.calm);
        vi_solver_free(s);
    }
}

static const double STIFF[4] = {-10.0, 0.0, 0.0, -10.0}, CALM[4] = {-9.6, 0.0, 0.0, -9.6};

static void steps_of(vi_solver *s, rig *r, double *t, const double *j, int count)
{
    memcpy(J, j, sizeof J);
    for (int k = 0; k < count; k++) one(s, r, t);
}

/* Eight steps in a row held by stability make the problem stiff; fewer than six calm steps in
 * between do not clear their count, six do, and a stiff step clears the calm count. The hand-over
 * comes with the next call, from the end of the last step, logged. */
Test(solver, auto_hands_over_after_eight_stiff_steps_in_a_row)
{
    rig r;
    vi_solver *s = auto_rig(&r, 2);
    double t = 0.0;
    steps_of(s, &r, &t, STIFF, 5);
    cr_assert(r.sw.stiff == 5 && r.sw.calm == 0 && !r.sw.pending);
    steps_of(s, &r, &t, CALM, 5);
    cr_assert(r.sw.stiff == 5 && r.sw.calm == 5, "stiff %d calm %d", r.sw.stiff, r.sw.calm);
    steps_of(s, &r, &t, STIFF, 1);
    cr_assert(r.sw.stiff == 6 && r.sw.calm == 0);
    steps_of(s, &r, &t, CALM, 6);
    cr_assert(r.sw.stiff == 0 && r.sw.calm == 6, "stiff %d calm %d", r.sw.stiff, r.sw.calm);
    steps_of(s, &r, &t, CALM, 2);
    cr_assert(r.sw.stiff == 0 && r.sw.calm == 6);
    steps_of(s, &r, &t, STIFF, 7);
    cr_assert(r.sw.stiff == 7 && !r.sw.pending);
    steps_of(s, &r, &t, CALM, 1);
    cr_assert(r.sw.stiff == 7 && r.sw.calm == 1 && !r.sw.pending);
    steps_of(s, &r, &t, STIFF, 1);
    cr_assert(r.sw.stiff == 8 && r.sw.calm == 0 && r.sw.pending && !r.sw.bdf && r.sw.switches == 0);
    char want[300];
    snprintf(want, sizeof want,
             "t = %.17g s: stiff (8 steps in a row held by stability, h rho > 4.8): CVODE BDF takes over", t);
    log_clear();
    K = 1e8, set_j(0.0, 0.0, 0.0, -1e8);
    one(s, &r, &t);
    cr_assert(r.sw.bdf == 1 && r.sw.pending == 0 && r.sw.stiff == 0 && r.sw.calm == 0 && r.sw.steps == 1 &&
                  r.sw.switches == 1,
              "bdf %d pending %d stiff %d calm %d steps %ld", r.sw.bdf, r.sw.pending, r.sw.stiff, r.sw.calm, r.sw.steps);
    cr_assert(logged(VI_LOG_SOLVER, want), "%s\nwanted %s", log_text, want);
    vi_solver_stats st;
    vi_solver_statistics(s, &st);
    cr_assert(st.switches == 1 && st.resets == 0 && st.steps == 29, "switches %ld resets %ld steps %ld", st.switches,
              st.resets, st.steps);
    vi_solver_free(s);
}

/* Under BDF the first 10 steps are not tested; then 6 steps in a row with h rho < 1 hand back (a
 * step above clears the count), from the end of BDF's last step, logged; a restart clears BDF's
 * counts. */
Test(solver, auto_hands_back_after_six_calm_bdf_steps)
{
    rig r;
    vi_solver *s = auto_rig(&r, 2);
    double t = 0.0;
    steps_of(s, &r, &t, STIFF, 8);
    K = 1e8, set_j(0.0, 0.0, 0.0, -1e8);
    for (int k = 1; k <= 12; k++) {
        one(s, &r, &t);
        cr_assert(r.sw.bdf && r.sw.steps == (k < 10 ? k : 10) && r.sw.calm == 0, "step %d: steps %ld calm %d", k,
                  r.sw.steps, r.sw.calm);
    }
    K = 0.0, set_j(0.0, 0.0, 0.0, 0.0);
    for (int k = 1; k <= 3; k++) one(s, &r, &t);
    cr_assert(r.sw.calm == 3 && r.sw.steps == 10);
    double x[2] = {1.0 + t, 1.0};
    cr_assert(vi_solver_reset(s, t, x) == 0);
    cr_assert(r.sw.bdf && r.sw.calm == 0 && r.sw.steps == 0 && r.sw.switches == 1);
    for (int k = 1; k <= 9; k++) one(s, &r, &t);
    cr_assert(r.sw.calm == 0 && r.sw.steps == 9);
    for (int k = 1; k <= 5; k++) one(s, &r, &t);
    cr_assert(r.sw.calm == 5 && !r.sw.pending, "calm %d", r.sw.calm);
    K = 1e8, set_j(0.0, 0.0, 0.0, -1e8);
    one(s, &r, &t);
    cr_assert(r.sw.calm == 0);
    K = 0.0, set_j(0.0, 0.0, 0.0, 0.0);
    for (int k = 1; k <= 5; k++) one(s, &r, &t);
    cr_assert(r.sw.calm == 5 && !r.sw.pending);
    one(s, &r, &t);
    cr_assert(r.sw.calm == 6 && r.sw.pending && r.sw.bdf);
    char want[300];
    snprintf(want, sizeof want,
             "t = %.17g s: not stiff (6 BDF steps in a row with h rho < 1): Dormand-Prince 8(5,3) takes over", t);
    log_clear();
    one(s, &r, &t);
    cr_assert(!r.sw.bdf && r.sw.switches == 2 && !r.sw.pending && r.sw.calm == 1 && r.sw.steps == 0, "bdf %d calm %d",
              r.sw.bdf, r.sw.calm);
    cr_assert(logged(VI_LOG_SOLVER, want), "%s\nwanted %s", log_text, want);
    vi_solver_stats st;
    vi_solver_statistics(s, &st);
    cr_assert(st.switches == 2 && st.resets == 1, "%ld %ld", st.switches, st.resets);
    vi_solver_free(s);
}

/* A hand-over asked for at the end of an advance is made by the next restart: BDF starts there. */
Test(solver, auto_restart_makes_a_pending_hand_over)
{
    rig r;
    vi_solver *s = auto_rig(&r, 2);
    double t = 0.0;
    steps_of(s, &r, &t, STIFF, 8);
    cr_assert(r.sw.pending && !r.sw.bdf);
    double x[2] = {1.0 + t, 1.0};
    log_clear();
    cr_assert(vi_solver_reset(s, t, x) == 0);
    char want[300];
    snprintf(want, sizeof want,
             "t = %.17g s: stiff (8 steps in a row held by stability, h rho > 4.8): CVODE BDF takes over", t);
    cr_assert(logged(VI_LOG_SOLVER, want), "%s", log_text);
    cr_assert(r.sw.bdf && !r.sw.pending && r.sw.switches == 1 && r.sw.stiff == 0);
    vi_solver_stats st;
    vi_solver_statistics(s, &st);
    cr_assert(st.resets == 1 && st.steps == 8, "resets %ld steps %ld", st.resets, st.steps);
    cr_assert(vi_solver_checkpoint(s, t, x) == 0);
    vi_solver_statistics(s, &st);
    cr_assert(st.resets == 2, "a checkpoint under BDF restarts it: %ld", st.resets);
    K = 1e8, set_j(0.0, 0.0, 0.0, -1e8);
    one(s, &r, &t);
    cr_assert(r.sw.steps == 1);
    vi_solver_free(s);
}

/* A new auto solver starts with the one-step method and clears the caller's choice block. */
Test(solver, auto_creation_clears_the_choice)
{
    rig r;
    rig_osc(&r, VI_METHOD_AUTO);
    r.sw = (vi_solver_auto){.bdf = 1, .pending = 1, .stiff = 3, .calm = 2, .steps = 4, .switches = 9};
    double x0[2] = {1.0, 0.0};
    vi_solver *s = start(&r, 0.0, x0);
    cr_assert(r.sw.bdf == 0 && r.sw.pending == 0 && r.sw.stiff == 0 && r.sw.calm == 0 && r.sw.steps == 0 &&
                  r.sw.switches == 0,
              "bdf %d pending %d stiff %d calm %d steps %ld switches %ld", r.sw.bdf, r.sw.pending, r.sw.stiff, r.sw.calm,
              r.sw.steps, r.sw.switches);
    cr_assert(r.ode.t == 0.0 && r.ode.x[0] == 1.0 && !r.ode.have_step);
    vi_solver_free(s);
}

static void nan_from_half(double t, const double *x, double *dx, void *u)
{
    (void)x;
    dx[0] = t < 0.5 ? 1.0 : NAN;
    if (*(const int *)u == 2) dx[1] = 0.0;
}

/* When the one-step method fails under auto, the failure is logged (not as an error) with the time
 * it got to, and BDF takes over from there at once (and fails in turn, at the same place). */
Test(solver, auto_hands_a_failure_of_the_one_step_method_to_bdf)
{
    rig r;
    memset(&r, 0, sizeof r);
    r.atol[0] = r.atol[1] = 1e-9;
    r.cfg = (vi_solver_config){.n = 2, .rhs = nan_from_half, .jac = jac_set, .method = VI_METHOD_AUTO, .rtol = 1e-6,
                               .atol = r.atol, .ode = &r.ode, .auto_choice = &r.sw, .log = capture};
    r.cfg.user = &r.cfg.n;
    set_j(0.0, 0.0, 0.0, 0.0);
    double x0[2] = {0.0, 0.0}, x[2], t = 0.0;
    int fired[1];
    long taken;
    vi_solver *s = start(&r, 0.0, x0);
    int rc = vi_solver_advance(s, 1.0, 300, &t, x, fired, &taken);
    char want[300];
    snprintf(want, sizeof want, "t = %.17g s: Dormand-Prince 8(5,3) failed (right-hand side or guards not finite)", r.ode.t);
    cr_assert(r.ode.t > 0.49 && r.ode.t < 0.5, "%.17g", r.ode.t);
    cr_assert(logged(VI_LOG_SOLVER, want), "%s\nwanted %s", log_text, want);
    cr_assert(r.sw.bdf == 1 && r.sw.switches == 1, "bdf %d switches %ld", r.sw.bdf, r.sw.switches);
    /* BDF starts an ulp before 0.5, where the derivative turns NaN, and fails there in turn */
    cr_assert(rc == VI_SOLVER_FAILED, "rc %d", rc);
    cr_assert(logged(VI_LOG_ERROR, "SUNDIALS call flag failed: CV_REPTD_RHSFUNC_ERR (-10)"), "%s", log_text);
    cr_assert(cvode_said(VI_LOG_ERROR, "At t = 0.5 repeated recoverable right-hand side function errors."), "%s",
              log_text);
    vi_solver_free(s);
}

/* ---- memory ------------------------------------------------------------------------------------- */

#ifdef VI_TEST_WRAP
/* Built with the linker's --wrap for the allocator and SUNDIALS's constructors (CMakeLists.txt): the
 * solver's and SUNDIALS's (static) calls come here. live_blocks counts their blocks not yet freed;
 * fail(name, k) makes the k-th next call of that name (0: the next) fail as on a lack of memory. */
void *__real_malloc(size_t size);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *p, size_t size);
void __real_free(void *p);
int __real_SUNContext_Create(VI_SUN_COMM comm, SUNContext *ctx);
void *__real_CVodeCreate(int lmm, SUNContext ctx);
N_Vector __real_N_VNew_Serial(sunindextype n, SUNContext ctx);
int __real_N_VEnableFusedOps_Serial(N_Vector v, sunbooleantype tf);
SUNMatrix __real_SUNDenseMatrix(sunindextype m, sunindextype n, SUNContext ctx);
SUNLinearSolver __real_SUNLinSol_Dense(N_Vector y, SUNMatrix a, SUNContext ctx);

static long live_blocks;
static const char *fail_name;
static int fail_skip;

static void fail(const char *name, int k) { fail_name = name, fail_skip = k; }

static int failing(const char *name)
{
    if (!fail_name || strcmp(fail_name, name) != 0 || fail_skip-- > 0) return 0;
    fail_name = NULL;
    return 1;
}

void *__wrap_malloc(size_t size);
void *__wrap_malloc(size_t size)
{
    void *p = failing("malloc") ? NULL : __real_malloc(size);
    live_blocks += p != NULL;
    return p;
}
void *__wrap_calloc(size_t count, size_t size);
void *__wrap_calloc(size_t count, size_t size)
{
    void *p = failing("calloc") ? NULL : __real_calloc(count, size);
    live_blocks += p != NULL;
    return p;
}
void *__wrap_realloc(void *q, size_t size);
void *__wrap_realloc(void *q, size_t size)
{
    void *p = __real_realloc(q, size);
    live_blocks += !q && p;
    return p;
}
void __wrap_free(void *p);
void __wrap_free(void *p)
{
    live_blocks -= p != NULL;
    __real_free(p);
}
int __wrap_SUNContext_Create(VI_SUN_COMM comm, SUNContext *ctx);
int __wrap_SUNContext_Create(VI_SUN_COMM comm, SUNContext *ctx)
{
    return failing("SUNContext_Create") ? -1 : __real_SUNContext_Create(comm, ctx);
}
void *__wrap_CVodeCreate(int lmm, SUNContext ctx);
void *__wrap_CVodeCreate(int lmm, SUNContext ctx) { return failing("CVodeCreate") ? NULL : __real_CVodeCreate(lmm, ctx); }
N_Vector __wrap_N_VNew_Serial(sunindextype n, SUNContext ctx);
N_Vector __wrap_N_VNew_Serial(sunindextype n, SUNContext ctx)
{
    return failing("N_VNew_Serial") ? NULL : __real_N_VNew_Serial(n, ctx);
}
int __wrap_N_VEnableFusedOps_Serial(N_Vector v, sunbooleantype tf);
int __wrap_N_VEnableFusedOps_Serial(N_Vector v, sunbooleantype tf)
{
    return failing("N_VEnableFusedOps_Serial") ? -1 : __real_N_VEnableFusedOps_Serial(v, tf);
}
SUNMatrix __wrap_SUNDenseMatrix(sunindextype m, sunindextype n, SUNContext ctx);
SUNMatrix __wrap_SUNDenseMatrix(sunindextype m, sunindextype n, SUNContext ctx)
{
    return failing("SUNDenseMatrix") ? NULL : __real_SUNDenseMatrix(m, n, ctx);
}
SUNLinearSolver __wrap_SUNLinSol_Dense(N_Vector y, SUNMatrix a, SUNContext ctx);
SUNLinearSolver __wrap_SUNLinSol_Dense(N_Vector y, SUNMatrix a, SUNContext ctx)
{
    return failing("SUNLinSol_Dense") ? NULL : __real_SUNLinSol_Dense(y, a, ctx);
}

static void run_and_free(int method)
{
    rig r;
    rig_osc(&r, method);
    double x0[2] = {1.0, 0.0}, x[2], t = 0.0;
    int fired[3];
    long taken, before = live_blocks;
    vi_solver *s = start(&r, 0.0, x0);
    if (method != VI_METHOD_DOP853) cr_assert(live_blocks > before + 5, "the allocations are not counted");
    cr_assert(vi_solver_advance(s, 0.5, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
    cr_assert(vi_solver_reset(s, t, x) == 0);
    cr_assert(vi_solver_advance(s, 1.0, 100000, &t, x, fired, &taken) == VI_SOLVER_REACHED);
    vi_solver_free(s);
}

/* A solver of every method gives back every block it and SUNDIALS allocated (CVODE's memory,
 * vectors, matrix, linear solver, context), and so does a creation that fails in a SUNDIALS call
 * (whose flag's name SUNDIALS allocates). */
Test(solver, every_allocation_is_given_back)
{
    vi_solver_free(NULL);
    for (size_t m = 0; m < 4; m++) {
        long before = live_blocks;
        run_and_free(METHODS[m]);
        cr_assert(live_blocks == before, "%s: %ld blocks left", vi_solver_method_name(METHODS[m]), live_blocks - before);
    }
    rig r;
    rig_osc(&r, VI_METHOD_BDF);
    r.cfg.rtol = -1.0; /* CVodeSVtolerances fails */
    double x0[2] = {1.0, 0.0};
    long before = live_blocks;
    log_clear();
    cr_assert(vi_solver_create(&r.cfg, 0.0, x0) == NULL);
    cr_assert(strstr(log_text, "CV_ILL_INPUT") != NULL, "%s", log_text);
    cr_assert(live_blocks == before, "failed creation: %ld blocks left", live_blocks - before);
}

/* A creation that runs out of memory at any allocation fails, says which call failed, and gives
 * back what it had. */
Test(solver, creation_out_of_memory_fails_cleanly_at_every_allocation)
{
    const struct { const char *call; int k; const char *want; } cases[] = {
        {"calloc", 0, "out of memory creating the solver"},
        {"SUNContext_Create", 0, "SUNDIALS call SUNContext_Create failed: "},
        {"CVodeCreate", 0, "SUNDIALS call CVodeCreate returned NULL"},
        {"N_VNew_Serial", 0, "SUNDIALS call N_VNew_Serial returned NULL"},
        {"N_VNew_Serial", 1, "SUNDIALS call N_VNew_Serial returned NULL"},
        {"N_VNew_Serial", 2, "SUNDIALS call N_VNew_Serial returned NULL"},
        {"N_VEnableFusedOps_Serial", 0, "SUNDIALS call N_VEnableFusedOps_Serial failed: "},
        {"N_VEnableFusedOps_Serial", 1, "SUNDIALS call N_VEnableFusedOps_Serial failed: "},
        {"SUNDenseMatrix", 0, "SUNDIALS call SUNDenseMatrix returned NULL"},
        {"SUNLinSol_Dense", 0, "SUNDIALS call SUNLinSol_Dense returned NULL"},
    };
    for (size_t m = 0; m < 4; m++)
        for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
            if (METHODS[m] == VI_METHOD_DOP853 && k > 0) break; /* no CVODE */
            rig r;
            rig_osc(&r, METHODS[m]);
            double x0[2] = {1.0, 0.0};
            long before = live_blocks;
            log_clear();
            fail(cases[k].call, cases[k].k);
            vi_solver *s = vi_solver_create(&r.cfg, 0.0, x0);
            cr_assert(fail_name == NULL, "%s: %s not called", vi_solver_method_name(METHODS[m]), cases[k].call);
            cr_assert(s == NULL, "%s: created without %s", vi_solver_method_name(METHODS[m]), cases[k].call);
            cr_assert(log_errors == 1 && strstr(log_text, cases[k].want) != NULL, "%s, %s %d: %s",
                      vi_solver_method_name(METHODS[m]), cases[k].call, cases[k].k, log_text);
            cr_assert(live_blocks == before, "%s, %s: %ld blocks left", vi_solver_method_name(METHODS[m]), cases[k].call,
                      live_blocks - before);
        }
}
#endif

/* ---- pieces (vi_solver.h, PIECES) ----------------------------------------------------------------- */

/* What the piece callback saw: the pieces' ends, the largest error of the interpolant and of its
 * derivative against the oscillator's closed form at three inside points and at the end, and the
 * integral of x0^2 (Gauss-Legendre, 4 nodes, on each piece). */
static struct {
    int n, fail_at;
    double ta[4096], tb[4096], err, derr, integral;
} pieces;

static int record_piece(const vi_solver_piece *p, void *u)
{
    (void)u;
    static const double gt[4] = {0.069431844202973714, 0.33000947820757187, 0.66999052179242813, 0.93056815579702623};
    static const double gw[4] = {0.17392742256872679, 0.32607257743127321, 0.32607257743127321, 0.17392742256872679};
    if (pieces.n == pieces.fail_at) return -1;
    cr_assert(pieces.n < 4096 && p->tb > p->ta, "piece %d: [%.17g, %.17g]", pieces.n, p->ta, p->tb);
    pieces.ta[pieces.n] = p->ta, pieces.tb[pieces.n] = p->tb;
    pieces.n++;
    double x[2], dx[2], y[2];
    for (int i = 0; i < 4; i++) {
        double t = p->ta + gt[i] * (p->tb - p->ta);
        cr_assert(vi_solver_piece_at(p, t, x, dx) == 0 && vi_solver_piece_at(p, t, y, NULL) == 0);
        cr_assert(x[0] == y[0] && x[1] == y[1], "the derivative changes the value");
        pieces.err = fmax(pieces.err, fmax(fabs(x[0] - cos(t)), fabs(x[1] + sin(t))));
        pieces.derr = fmax(pieces.derr, fmax(fabs(dx[0] + sin(t)), fabs(dx[1] + cos(t))));
        pieces.integral += (p->tb - p->ta) * gw[i] * x[0] * x[0];
    }
    cr_assert(vi_solver_piece_at(p, p->ta, x, NULL) == 0 && x[0] == p->xa[0] && x[1] == p->xa[1]);
    cr_assert(vi_solver_piece_at(p, p->tb, x, NULL) == 0 && x[0] == p->xb[0] && x[1] == p->xb[1]);
    pieces.derr = fmax(pieces.derr, fmax(fabs(p->dxb[0] + sin(p->tb)), fabs(p->dxb[1] + cos(p->tb))));
    return 0;
}

/* The oscillator from (1, 0) at t = 0 with the piece recorder, which refuses piece fail_at (-1: none). */
static vi_solver *start_pieces(rig *r, int method, int fail_at)
{
    rig_osc(r, method);
    r->cfg.piece = record_piece;
    memset(&pieces, 0, sizeof pieces);
    pieces.fail_at = fail_at;
    return start(r, 0.0, (const double[2]){1.0, 0.0});
}

/* The oscillator to t = 3 through communication points 0.37 apart, the events at pi/2 and 2 pi/3 restarting it:
 * the pieces follow each other without gap from 0 to 3 (the event's time ends one and starts the
 * next), their interpolant is the solution (its derivative to 1e-4: CVODE's polynomial differentiated is off
 * by 6e-6 here), and the integral of cos^2 over them is t/2 + sin(2 t)/4. */
Test(solver, pieces_cover_every_advance_without_gap_with_the_interpolant)
{
    for (size_t m = 0; m < 4; m++) {
        rig r;
        vi_solver *s = start_pieces(&r, METHODS[m], -1);
        double x[2], t = 0.0, tout = 0.0, t_event = NAN;
        int fired[3];
        long taken;
        const char *name = vi_solver_method_name(METHODS[m]);
        for (int k = 0; k < 100 && t < 3.0; k++) {
            tout = fmin(3.0, tout + (t >= tout ? 0.37 : 0.0));
            int rc = vi_solver_advance(s, tout, 100000, &t, x, fired, &taken);
            cr_assert(rc == VI_SOLVER_REACHED || rc == VI_SOLVER_EVENT, "%s: rc %d", name, rc);
            cr_assert(pieces.tb[pieces.n - 1] == t, "%s: the last piece ends at %.17g, not at %.17g", name,
                      pieces.tb[pieces.n - 1], t);
            if (rc == VI_SOLVER_EVENT) {
                t_event = isnan(t_event) ? t : t_event; /* pi/2, then 2 pi/3 */
                cr_assert(vi_solver_reset(s, t, x) == 0);
            }
        }
        cr_assert(fabs(t_event - PI / 2) < 1e-8, "%s: event at %.17g", name, t_event);
        cr_assert(pieces.ta[0] == 0.0 && pieces.n > 8, "%s: %d pieces", name, pieces.n);
        for (int i = 1; i < pieces.n; i++)
            cr_assert(pieces.ta[i] == pieces.tb[i - 1], "%s: piece %d starts at %.17g, the one before ends at %.17g", name,
                      i, pieces.ta[i], pieces.tb[i - 1]);
        cr_assert(pieces.err < 1e-8 && pieces.derr < 1e-4, "%s: interpolant off by %g, its derivative by %g", name,
                  pieces.err, pieces.derr);
        double exact = 1.5 + sin(6.0) / 4.0;
        cr_assert(fabs(pieces.integral - exact) < 1e-8, "%s: integral %.17g, closed form %.17g", name, pieces.integral,
                  exact);
        vi_solver_free(s);
    }
}

/* A piece the caller refuses fails the advance, with every method. */
Test(solver, a_refused_piece_fails_the_advance)
{
    for (size_t m = 0; m < 4; m++) {
        rig r;
        vi_solver *s = start_pieces(&r, METHODS[m], 2);
        double x[2], t = 0.0;
        int fired[3];
        long taken;
        int rc = VI_SOLVER_REACHED;
        for (int k = 1; k <= 10 && rc == VI_SOLVER_REACHED; k++)
            rc = vi_solver_advance(s, 0.1 * k, 100000, &t, x, fired, &taken);
        cr_assert(rc == VI_SOLVER_FAILED && pieces.n == 2, "%s: rc %d after %d pieces", vi_solver_method_name(METHODS[m]),
                  rc, pieces.n);
        vi_solver_free(s);
    }
}
