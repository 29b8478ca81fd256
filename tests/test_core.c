/* Unit tests of the generic FMI layer's core (src/vi_fmi_core.c) with a stub model that has no
 * physics: the range check of the variable table at set time, and the logger handed to the model
 * with a category the layer does not know. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_fmi_core.h"

#define VI_GUID "{core-test}"
#define VI_MODEL_IDENTIFIER "CoreTest"
#define VI_VARIABLES(X)                                                                                     \
    X(u, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "", "an input")                      \
    X(k, Real, none, parameter, tunable, exact, 1.0, VI_ABOVE(0.0), VI_AT(10.0), "1/s", "a rate")        \
    X(n, Integer, none, parameter, fixed, exact, 3, VI_AT(1), VI_BELOW(8), "", "a count")                \
    X(y, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "", "an output")
#define VI_ENUMERATIONS(E)
VI_TABLE_DECLARE
VI_TABLE_DEFINE

typedef struct {
    vi_parameters par;
    vi_inputs in, din;
    double t;
} data;

typedef struct {
    data d;
    vi_fmu_log_fn log;
    void *env;
} stub;

static void init(void *m, vi_fmu_log_fn log, void *env)
{
    stub *s = m;
    vi_parameters_default(&s->d.par);
    vi_inputs_default(&s->d.in);
    s->log = log, s->env = env;
}
static void reset(void *m) { init(m, ((stub *)m)->log, ((stub *)m)->env); }
static void release(void *m) { (void)m; }
static void changed(void *m) { (void)m; }
static void outputs(void *m, void *out) { ((vi_outputs *)out)->y = ((stub *)m)->d.par.k; }
static void setup_experiment(void *m, double t0, int td, double tol) { (void)td, (void)tol, ((stub *)m)->d.t = t0; }
static int prepare(void *m) { return (void)m, 0; }
static int advance(void *m, double t_end) { return ((stub *)m)->d.t = t_end, 0; }
static double time_of(const void *m) { return ((const stub *)m)->d.t; }
static void *state(void *m) { return &((stub *)m)->d; }
static const char *message(const void *m) { return (void)m, ""; }

const vi_fmu_model vi_fmu_this_model = {
    VI_FMU_TABLE_FIELDS(stub, data), .init = init, .reset = reset, .release = release, .changed = changed,
    .outputs = outputs, .setup_experiment = setup_experiment, .prepare = prepare, .initialize = prepare,
    .advance = advance, .time = time_of, .state = state, .message = message,
};

/* What the face saw last (the importer's logger environment points here). */
typedef struct {
    int count;
    vi_status status;
    char category[32], text[1024];
} record;

static void emit(const vi_core *c, vi_status status, const char *category, const char *text)
{
    record *r = c->cb.env;
    r->count++;
    r->status = status;
    snprintf(r->category, sizeof r->category, "%s", category);
    snprintf(r->text, sizeof r->text, "%s", text);
}
static void any_logger(void) {}
static const vi_face face = {.call_category = "logTestCall", .emit = emit};

static vi_core *make(record *r, int logging_on)
{
    vi_callbacks cb = {.alloc = calloc, .free = free, .logger = any_logger, .env = r};
    vi_core *c = vi_core_instantiate(&face, &cb, "instantiate", "core", VI_KIND_CS, VI_GUID, NULL, "", logging_on);
    cr_assert(c != NULL, "%s", r->text);
    return c;
}

static double get_k(vi_core *c)
{
    unsigned vr = VI_VR_k;
    double k = NAN;
    cr_assert(vi_core_get(c, "get", &vr, 1, VI_Real, &k, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    return k;
}

Test(core, a_value_outside_the_range_is_refused_at_set_time_and_nothing_changes)
{
    record r = {0};
    vi_core *c = make(&r, 0);
    cr_assert(vi_core_enter_init(c, "enter") == VI_STATUS_OK);
    unsigned vr[2] = {VI_VR_u, VI_VR_k};
    const double bad[][2] = {{5.0, 0.0}, {5.0, -1.0}, {5.0, nextafter(10.0, 11.0)}, {5.0, 1e300}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        r.count = 0;
        cr_assert(vi_core_set(c, "set", vr, 2, VI_Real, bad[i], VI_ELEM_DOUBLE) == VI_STATUS_ERROR, "k = %g", bad[i][1]);
        cr_assert(r.count == 1 && r.status == VI_STATUS_ERROR, "%s", r.text);
        cr_assert(strstr(r.text, "set: k = ") && strstr(r.text, "0 < k <= 10") && strstr(r.text, "nothing was set"),
                  "%s", r.text);
        cr_assert(get_k(c) == 1.0 && c->state == VI_ST_INIT, "changed by a refused set");
        cr_assert(((stub *)c->model)->d.in.u == 0.0, "the other value of the call was set");
    }
    const double ok[][2] = {{5.0, 5e-324}, {5.0, 10.0}};
    for (size_t i = 0; i < 2; i++) {
        cr_assert(vi_core_set(c, "set", vr, 2, VI_Real, ok[i], VI_ELEM_DOUBLE) == VI_STATUS_OK);
        cr_assert(get_k(c) == ok[i][1]);
    }
    /* Integers: inclusive 1, exclusive 8 */
    unsigned vn = VI_VR_n;
    const int nbad[] = {0, 8, -5}, nok[] = {1, 7};
    for (int i = 0; i < 3; i++) {
        cr_assert(vi_core_set(c, "set", &vn, 1, VI_Integer, &nbad[i], VI_ELEM_INT) == VI_STATUS_ERROR, "n = %d", nbad[i]);
        cr_assert(strstr(r.text, "1 <= n < 8"), "%s", r.text);
    }
    for (int i = 0; i < 2; i++)
        cr_assert(vi_core_set(c, "set", &vn, 1, VI_Integer, &nok[i], VI_ELEM_INT) == VI_STATUS_OK, "n = %d", nok[i]);
    vi_core_free(c, "free");
}

Test(core, the_model_logging_with_an_unknown_category_reaches_the_importer_as_an_error)
{
    record r = {0};
    vi_core *c = make(&r, 0);
    stub *s = c->model;
    const int bad[] = {-1, VI_FMU_LOG_ERROR + 1, 1000000};
    for (int i = 0; i < 3; i++) {
        r.count = 0;
        s->log(s->env, bad[i], "message %d", 42);
        cr_assert(r.count == 2 && r.status == VI_STATUS_ERROR, "category %d: status %d", bad[i], (int)r.status);
        cr_assert(strcmp(r.text, "message 42") == 0, "category %d: '%s'", bad[i], r.text);
    }
    const char *warning[] = {"logStatusWarning"};
    cr_assert(vi_core_set_debug_logging(c, "logging", 1, 1, warning) == VI_STATUS_OK);
    r.count = 0;
    s->log(s->env, VI_FMU_LOG_WARNING, "fine");
    cr_assert(r.count == 1 && r.status == VI_STATUS_WARNING && strcmp(r.text, "fine") == 0, "%d %s", r.count, r.text);
    vi_core_free(c, "free");
}
