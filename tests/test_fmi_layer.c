/* Unit tests of the generic FMI layer (src/fmi/vi_fmi_*.c) with a stub model that has no
 * physics but every hook, each of which can be told to fail or to answer a given value: the
 * life cycle and its argument checks, logging with categories, value access with its checks, the
 * FMU-state envelope, the Co-Simulation step checks and the Model Exchange calls. Two faces: a
 * plain one (FMI 2.0-like) and one with the FMI 3.0 extras (time, input derivatives and event
 * indicators as value references, Co-Simulation Event Mode, named enumerations). */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "vi_fmi_layer.h"

#include "stub_model.h"

/* What the face saw (the importer's logger environment points here): the last message and all. */
#define LOG_KEEP 16
typedef struct {
    int count;
    vi_status status;
    char category[32], text[VI_FMI_MESSAGE_MAX], name[64];
    vi_status all_status[LOG_KEEP];
    char all[LOG_KEEP][1024];
} record;

static void emit(const vi_fmi_instance *c, vi_status status, const char *category, const char *text)
{
    record *r = c->cb.env;
    if (r->count < LOG_KEEP) {
        r->all_status[r->count] = status;
        snprintf(r->all[r->count], sizeof r->all[0], "%s", text);
    }
    r->count++;
    r->status = status;
    snprintf(r->category, sizeof r->category, "%s", category);
    snprintf(r->text, sizeof r->text, "%s", text);
    snprintf(r->name, sizeof r->name, "%s", c->name);
}
static void any_logger(void) {}
static const vi_face face = {.call_category = "logTestCall", .emit = emit};
static const char *const face3_types[] = {"F64", "I32", "Bool", "Enum64", "Str"};
#define TIME_VR 1000u
#define DER_BASE 2000u
#define IND_BASE 3000u
static const vi_face face3 = {.call_category = "logTest3Call", .emit = emit, .named_enumerations = 1,
                              .type_names = face3_types, .has_time = 1, .time_vr = TIME_VR,
                              .has_input_derivatives = 1, .derivative_vr_base = DER_BASE, .cs_event_mode = 1,
                              .has_indicator_vrs = 1, .indicator_vr_base = IND_BASE};

static vi_fmi_instance *make_with(const vi_face *f, record *r, vi_kind kind, int logging_on)
{
    vi_callbacks cb = {.alloc = calloc, .free = free, .logger = any_logger, .env = r};
    vi_fmi_instance *c = vi_fmi_instantiate(f, &cb, "instantiate", "core", kind, VI_GUID, NULL, "", logging_on);
    cr_assert(c != NULL, "%s", r->text);
    return c;
}
static vi_fmi_instance *make(record *r, int logging_on) { return make_with(&face, r, VI_KIND_CS, logging_on); }

static double get_k(vi_fmi_instance *c)
{
    unsigned vr = VI_VR_k;
    double k = NAN;
    cr_assert(vi_fmi_get(c, "get", &vr, 1, VI_Real, &k, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    return k;
}

/* The last message: status, and every one of the words in its text. */
#define LAST_IS(r, st, ...)                                                                                  \
    do {                                                                                                     \
        cr_assert((r).status == (st), "status %d, expected %d: '%s'", (int)(r).status, (int)(st), (r).text);  \
        const char *words_[] = {__VA_ARGS__};                                                                \
        for (size_t w_ = 0; w_ < sizeof words_ / sizeof words_[0]; w_++)                                     \
            cr_assert(strstr((r).text, words_[w_]), "'%s' lacks '%s'", (r).text, words_[w_]);               \
    } while (0)
/* A call refused with an error message naming all the words, the count of messages one up. */
#define REFUSED(r, call, ...)                                                                                \
    do {                                                                                                     \
        int before_ = (r).count;                                                                             \
        cr_assert((call) == VI_STATUS_ERROR, "%s: not refused", #call);                                      \
        cr_assert((r).count == before_ + 1, "%s: %d messages", #call, (r).count - before_);                  \
        LAST_IS(r, VI_STATUS_ERROR, __VA_ARGS__);                                                            \
        cr_assert(strcmp((r).category, "logStatusError") == 0, "category %s", (r).category);                \
    } while (0)

Test(fmi_layer, a_value_outside_the_range_is_refused_at_set_time_and_nothing_changes)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    unsigned vr[2] = {VI_VR_u, VI_VR_k};
    const double bad[][2] = {{5.0, 0.0}, {5.0, -1.0}, {5.0, nextafter(10.0, 11.0)}, {5.0, 1e300}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        r.count = 0;
        cr_assert(vi_fmi_set(c, "set", vr, 2, VI_Real, bad[i], VI_ELEM_DOUBLE) == VI_STATUS_ERROR, "k = %g", bad[i][1]);
        cr_assert(r.count == 1 && r.status == VI_STATUS_ERROR, "%s", r.text);
        cr_assert(strstr(r.text, "set: k = ") && strstr(r.text, "0 < k <= 10") && strstr(r.text, "nothing was set"),
                  "%s", r.text);
        cr_assert(get_k(c) == 1.0 && c->state == VI_ST_INIT, "changed by a refused set");
        cr_assert(((stub *)c->model)->d.in.u == 0.0, "the other value of the call was set");
    }
    const double ok[][2] = {{5.0, 5e-324}, {5.0, 10.0}};
    for (size_t i = 0; i < 2; i++) {
        cr_assert(vi_fmi_set(c, "set", vr, 2, VI_Real, ok[i], VI_ELEM_DOUBLE) == VI_STATUS_OK);
        cr_assert(get_k(c) == ok[i][1]);
    }
    /* Integers: inclusive 1, exclusive 8 */
    unsigned vn = VI_VR_n;
    const int nbad[] = {0, 8, -5}, nok[] = {1, 7};
    for (int i = 0; i < 3; i++) {
        cr_assert(vi_fmi_set(c, "set", &vn, 1, VI_Integer, &nbad[i], VI_ELEM_INT) == VI_STATUS_ERROR, "n = %d", nbad[i]);
        cr_assert(strstr(r.text, "1 <= n < 8"), "%s", r.text);
    }
    for (int i = 0; i < 2; i++)
        cr_assert(vi_fmi_set(c, "set", &vn, 1, VI_Integer, &nok[i], VI_ELEM_INT) == VI_STATUS_OK, "n = %d", nok[i]);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, the_model_logging_with_an_unknown_category_reaches_the_importer_as_an_error)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    const int bad[] = {-1, VI_FMU_LOG_ERROR + 1, 1000000};
    for (int i = 0; i < 3; i++) {
        r.count = 0;
        s->log(s->env, bad[i], "message %d", 42);
        cr_assert(r.count == 2 && r.status == VI_STATUS_ERROR, "category %d: status %d", bad[i], (int)r.status);
        cr_assert(strcmp(r.text, "message 42") == 0, "category %d: '%s'", bad[i], r.text);
    }
    const char *warning[] = {"logStatusWarning"};
    cr_assert(vi_fmi_set_debug_logging(c, "logging", 1, 1, warning) == VI_STATUS_OK);
    r.count = 0;
    s->log(s->env, VI_FMU_LOG_WARNING, "fine");
    cr_assert(r.count == 1 && r.status == VI_STATUS_WARNING && strcmp(r.text, "fine") == 0, "%d %s", r.count, r.text);
    vi_fmi_free(c, "free");
}

/* A get call hands the model's outputs_of hook its own value references, once per call, and only
 * when it reads an output: the model computes what is read (lazy outputs). */
Test(fmi_layer, a_get_asks_the_model_for_the_outputs_it_reads)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    stub *s = c->model;
    get_k(c);
    cr_assert(s->outputs_calls == 0, "a parameter read computed outputs");
    unsigned vr[3] = {VI_VR_y, VI_VR_k, VI_VR_y};
    double v[3];
    cr_assert(vi_fmi_get(c, "get", vr, 3, VI_Real, v, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    cr_assert(s->outputs_calls == 1 && s->n_asked == 3 && memcmp(s->asked, vr, sizeof vr) == 0, "%d calls, %zu vrs",
              s->outputs_calls, s->n_asked);
    cr_assert(v[0] == 1.0 && v[1] == 1.0 && v[2] == 1.0);
    vi_fmi_free(c, "free");
}

/* ---- logging ---- */

Test(fmi_layer, the_model_logs_each_category_with_its_status_when_enabled_and_warnings_and_errors_always)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    static const struct {
        int cat;
        const char *name;
        vi_status status;
    } cats[] = {{VI_FMU_LOG_EVENTS, "logEvents", VI_STATUS_OK},
                {VI_FMU_LOG_SOLVER, "logSolver", VI_STATUS_OK},
                {VI_FMU_LOG_WARNING, "logStatusWarning", VI_STATUS_WARNING}};
    for (int i = 0; i < 3; i++) {
        int always = cats[i].status == VI_STATUS_WARNING; /* the user is expected to see a warning */
        r.count = 0;
        s->log(s->env, cats[i].cat, "m%d", i);
        cr_assert(r.count == always, "%s logged while disabled: %d", cats[i].name, r.count);
        r.count = 0;
        const char *one[] = {cats[i].name};
        cr_assert(vi_fmi_set_debug_logging(c, "logging", 1, 1, one) == VI_STATUS_OK);
        s->log(s->env, cats[i].cat, "m%d", i);
        cr_assert(r.count == 1 && r.status == cats[i].status && strcmp(r.category, cats[i].name) == 0, "%s: %d %d %s",
                  cats[i].name, r.count, (int)r.status, r.category);
        char want[8];
        snprintf(want, sizeof want, "m%d", i);
        cr_assert(strcmp(r.text, want) == 0, "'%s'", r.text);
        cr_assert(vi_fmi_set_debug_logging(c, "logging", 0, 1, one) == VI_STATUS_OK);
        s->log(s->env, cats[i].cat, "again");
        cr_assert(r.count == 1 + always, "%s logged after it was disabled", cats[i].name);
    }
    r.count = 0;
    s->log(s->env, VI_FMU_LOG_ERROR, "bad %s", "thing");
    cr_assert(r.count == 1 && r.status == VI_STATUS_ERROR && strcmp(r.category, "logStatusError") == 0 &&
              strcmp(r.text, "bad thing") == 0, "%d %s %s", r.count, r.category, r.text);
    /* logAll enables every category */
    const char *all[] = {"logAll"};
    cr_assert(vi_fmi_set_debug_logging(c, "logging", 1, 1, all) == VI_STATUS_OK);
    r.count = 0;
    s->log(s->env, VI_FMU_LOG_EVENTS, "ev");
    cr_assert(r.count == 1 && strcmp(r.category, "logEvents") == 0 && r.status == VI_STATUS_OK);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, without_a_logger_nothing_is_emitted)
{
    record r = {0};
    vi_callbacks cb = {.alloc = calloc, .free = free, .logger = NULL, .env = &r};
    vi_fmi_instance *c = vi_fmi_instantiate(&face, &cb, "instantiate", "core", VI_KIND_CS, VI_GUID, NULL, "", 1);
    cr_assert(c != NULL);
    stub *s = c->model;
    s->log(s->env, VI_FMU_LOG_ERROR, "bad");
    cr_assert(vi_fmi_exit_init(c, "exit") == VI_STATUS_ERROR);
    vi_fmi_free(c, "free");
    cr_assert(r.count == 0, "%d messages: %s", r.count, r.text);
}

Test(fmi_layer, control_characters_are_written_as_hex_escapes)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    vi_fmi_log(c, VI_STATUS_ERROR, VI_CAT_ERROR, "a\x01 ~\x7f\x1f%c", 0xe9);
    cr_assert(strcmp(r.text, "a\\x01 ~\\x7f\\x1f\\xe9") == 0, "'%s'", r.text);
    vi_fmi_log(c, VI_STATUS_ERROR, VI_CAT_ERROR, "plain");
    cr_assert(strcmp(r.text, "plain") == 0, "'%s'", r.text);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, warnings_and_discards_are_logged_whatever_is_enabled_debug_messages_only_when_enabled)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    vi_fmi_log(c, VI_STATUS_OK, VI_CAT_EVENTS, "e");
    cr_assert(r.count == 0);
    vi_fmi_log(c, VI_STATUS_WARNING, VI_CAT_WARNING, "w");
    cr_assert(r.count == 1 && r.status == VI_STATUS_WARNING && strcmp(r.category, "logStatusWarning") == 0);
    vi_fmi_log(c, VI_STATUS_DISCARD, VI_CAT_DISCARD, "d");
    cr_assert(r.count == 2 && r.status == VI_STATUS_DISCARD && strcmp(r.category, "logStatusDiscard") == 0);
    vi_fmi_free(c, "free");
}

/* `call` returns VI_STATUS_OK though the model logged notes in it: each reached the importer with status
 * Warning in logStatusWarning (every category is off), and nothing else was logged. */
#define OK_WITH_NOTES(r, s, call)                                                                              \
    do {                                                                                                       \
        int notes_ = (s)->notes, count_ = (r).count;                                                          \
        vi_status st_ = (call);                                                                                \
        cr_assert(st_ == VI_STATUS_OK, "%s returned %d: '%s'", #call, (int)st_, (r).text);                     \
        cr_assert((s)->notes > notes_ && (r).count - count_ == (s)->notes - notes_, "%s: %d notes, %d messages", \
                  #call, (s)->notes - notes_, (r).count - count_);                                              \
        cr_assert((r).status == VI_STATUS_WARNING && strcmp((r).category, "logStatusWarning") == 0 &&          \
                      strncmp((r).text, "note: ", 6) == 0,                                                    \
                  "%s: %d %s '%s'", #call, (int)(r).status, (r).category, (r).text);                            \
    } while (0)

/* A warning of the model is a note the computation goes on through (validity, tolerance, an option
 * ignored, a solver's remark): every importer shows it (status Warning, whatever is enabled), and the
 * call returns OK, since fmusim and PyFMI stop a run at any other status. Every call of a Co-Simulation
 * run that reaches a hook of the model. */
Test(fmi_layer, a_call_during_which_the_model_logged_a_note_returns_ok_in_co_simulation)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    s->warn_notes = 1;
    OK_WITH_NOTES(r, s, vi_fmi_setup_experiment(c, "setup", 1, 1e-6, 0.0, 0, 0.0));
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK); /* reaches no hook */
    double one = 1.0, y;
    unsigned u = VI_VR_u, vy = VI_VR_y;
    OK_WITH_NOTES(r, s, vi_fmi_get(c, "get", &vy, 1, VI_Real, &y, VI_ELEM_DOUBLE));
    OK_WITH_NOTES(r, s, vi_fmi_exit_init(c, "exit"));
    OK_WITH_NOTES(r, s, vi_fmi_set(c, "set", &u, 1, VI_Real, &one, VI_ELEM_DOUBLE));
    OK_WITH_NOTES(r, s, vi_fmi_do_step(c, "step", 0.0, 0.1));
    int event = -1;
    OK_WITH_NOTES(r, s, vi_fmi_do_step_to_event(c, "step", 0.1, 0.1, &event));
    cr_assert(event == 0);
    void *st = NULL;
    OK_WITH_NOTES(r, s, vi_fmi_get_fmu_state(c, "get", &st));
    OK_WITH_NOTES(r, s, vi_fmi_set_fmu_state(c, "set", st));
    cr_assert(vi_fmi_free_fmu_state(c, "free", &st) == VI_STATUS_OK);
    OK_WITH_NOTES(r, s, vi_fmi_terminate(c, "terminate"));
    vi_fmi_free(c, "free");
}

/* As above, every call of a Model Exchange run that reaches a hook of the model. */
Test(fmi_layer, a_call_during_which_the_model_logged_a_note_returns_ok_in_model_exchange)
{
    record r = {0};
    vi_fmi_instance *c = make_with(&face, &r, VI_KIND_ME, 0);
    stub *s = c->model;
    s->warn_notes = 1;
    OK_WITH_NOTES(r, s, vi_fmi_setup_experiment(c, "setup", 0, 0.0, 0.0, 0, 0.0));
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    OK_WITH_NOTES(r, s, vi_fmi_exit_init(c, "exit"));
    vi_fmu_event ev;
    OK_WITH_NOTES(r, s, vi_fmi_new_discrete_states(c, "nds", &ev));
    OK_WITH_NOTES(r, s, vi_fmi_enter_continuous_mode(c, "continuous"));
    OK_WITH_NOTES(r, s, vi_fmi_set_time(c, "time", 0.25));
    double x[2] = {0.25, 0.5}, dx[2], z[1];
    OK_WITH_NOTES(r, s, vi_fmi_set_states(c, "states", x, 2));
    OK_WITH_NOTES(r, s, vi_fmi_get_derivatives(c, "derivatives", dx, 2));
    OK_WITH_NOTES(r, s, vi_fmi_get_event_indicators(c, "indicators", z, 1));
    int enter = -1, terminate = -1;
    OK_WITH_NOTES(r, s, vi_fmi_completed_step(c, "completed", &enter, &terminate));
    cr_assert(enter == 0 && terminate == 0);
    unsigned unknown = VI_VR_der_q, known = VI_VR_p;
    double dk = 1.0, du;
    OK_WITH_NOTES(r, s, vi_fmi_directional_derivative(c, "dd", &unknown, 1, &known, 1, &dk, &du));
    cr_assert(du == -1.0);
    OK_WITH_NOTES(r, s, vi_fmi_terminate(c, "terminate"));
    vi_fmi_free(c, "free");
}

Test(fmi_layer, debug_logging_on_enables_exactly_the_categories_named)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    const char *events[] = {"logEvents"}, *solver[] = {"logSolver"};
    cr_assert(vi_fmi_set_debug_logging(c, "logging", 1, 0, NULL) == VI_STATUS_OK); /* all */
    cr_assert(vi_fmi_logs(c, VI_CAT_SOLVER) && vi_fmi_logs(c, VI_CAT_EVENTS));
    cr_assert(vi_fmi_set_debug_logging(c, "logging", 1, 1, events) == VI_STATUS_OK);
    cr_assert(vi_fmi_logs(c, VI_CAT_EVENTS) && !vi_fmi_logs(c, VI_CAT_SOLVER) && !vi_fmi_logs(c, VI_CAT_CALL));
    cr_assert(vi_fmi_set_debug_logging(c, "logging", 1, 1, solver) == VI_STATUS_OK);
    cr_assert(vi_fmi_logs(c, VI_CAT_SOLVER) && !vi_fmi_logs(c, VI_CAT_EVENTS));
    cr_assert(vi_fmi_set_debug_logging(c, "logging", 0, 0, NULL) == VI_STATUS_OK);
    cr_assert(!vi_fmi_logs(c, VI_CAT_SOLVER) && !vi_fmi_logs(c, VI_CAT_EVENTS));
    vi_fmi_free(c, "free");
}

Test(fmi_layer, calls_are_logged_in_the_call_category_only_when_it_or_logAll_is_enabled)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 1); /* every category */
    cr_assert(r.count == 1 && r.status == VI_STATUS_OK && strcmp(r.category, "logTestCall") == 0 &&
              strcmp(r.text, "instantiate: core") == 0, "%d '%s' '%s'", r.count, r.category, r.text);
    cr_assert(c->log_mask == (1u << VI_CAT_COUNT) - 1u, "mask %#x", c->log_mask);
    cr_assert(vi_fmi_enter_init(c, "enterInit") == VI_STATUS_OK);
    cr_assert(r.count == 2 && strcmp(r.text, "enterInit") == 0 && strcmp(r.category, "logTestCall") == 0);
    cr_assert(vi_fmi_set_debug_logging(c, "dbg", 0, 0, NULL) == VI_STATUS_OK && c->log_mask == 0u);
    cr_assert(r.count == 3 && strcmp(r.text, "dbg") == 0); /* logged on entry, before the mask changed */
    cr_assert(vi_fmi_exit_init(c, "exitInit") == VI_STATUS_OK);
    cr_assert(r.count == 3, "a call logged with logging off: %s", r.text);
    const char *calls[] = {"logTestCall"}, *all[] = {"logAll"};
    cr_assert(vi_fmi_set_debug_logging(c, "dbg", 1, 1, calls) == VI_STATUS_OK && c->log_mask == 1u << VI_CAT_CALL);
    cr_assert(vi_fmi_terminate(c, "term") == VI_STATUS_OK);
    cr_assert(r.count == 4 && strcmp(r.text, "term") == 0, "%d %s", r.count, r.text);
    cr_assert(vi_fmi_set_debug_logging(c, "dbg", 0, 1, calls) == VI_STATUS_OK && c->log_mask == 0u);
    cr_assert(r.count == 5 && strcmp(r.text, "dbg") == 0);
    cr_assert(vi_fmi_set_debug_logging(c, "dbg", 1, 1, all) == VI_STATUS_OK && c->log_mask == 1u << VI_CAT_ALL);
    cr_assert(r.count == 5);
    cr_assert(vi_fmi_reset(c, "rst") == VI_STATUS_OK);
    cr_assert(r.count == 6 && strcmp(r.text, "rst") == 0 && strcmp(r.category, "logTestCall") == 0, "%d %s", r.count,
              r.text);
    vi_fmi_free(c, "freeInst");
    cr_assert(r.count == 7 && strcmp(r.text, "freeInst") == 0, "%d %s", r.count, r.text);
}

Test(fmi_layer, a_call_category_disabled_is_not_logged_at_instantiation_and_free)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    cr_assert(c->log_mask == 0u && r.count == 0);
    vi_fmi_free(c, "free");
    cr_assert(r.count == 0);
}

Test(fmi_layer, each_log_category_name_sets_its_own_bit)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    const char *names[VI_CAT_COUNT] = {[VI_CAT_EVENTS] = "logEvents", [VI_CAT_SOLVER] = "logSolver",
                                       [VI_CAT_WARNING] = "logStatusWarning", [VI_CAT_DISCARD] = "logStatusDiscard",
                                       [VI_CAT_ERROR] = "logStatusError", [VI_CAT_CALL] = "logTestCall",
                                       [VI_CAT_ALL] = "logAll"};
    for (int k = 0; k < VI_CAT_COUNT; k++) {
        c->log_mask = 0;
        cr_assert(vi_fmi_set_debug_logging(c, "dbg", 1, 1, &names[k]) == VI_STATUS_OK, "%s", names[k]);
        cr_assert(c->log_mask == 1u << k, "%s: mask %#x", names[k], c->log_mask);
        c->log_mask = 0x7fu;
        cr_assert(vi_fmi_set_debug_logging(c, "dbg", 0, 1, &names[k]) == VI_STATUS_OK);
        cr_assert(c->log_mask == (0x7fu & ~(1u << k)), "%s off: mask %#x", names[k], c->log_mask);
    }
    c->log_mask = 0;
    const char *two[] = {"logSolver", "logStatusError"};
    cr_assert(vi_fmi_set_debug_logging(c, "dbg", 1, 2, two) == VI_STATUS_OK);
    cr_assert(c->log_mask == ((1u << VI_CAT_SOLVER) | (1u << VI_CAT_ERROR)), "mask %#x", c->log_mask);
    cr_assert(vi_fmi_set_debug_logging(c, "dbg", 1, 0, NULL) == VI_STATUS_OK && c->log_mask == 0x7fu);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, debug_logging_refuses_null_and_unknown_categories_and_changes_nothing)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    REFUSED(r, vi_fmi_set_debug_logging(c, "dbg", 1, 1, NULL), "dbg: categories is NULL");
    const char *bad[] = {"logEvents", "logNothing"}, *null[] = {NULL}, *near[] = {"logEvent"};
    REFUSED(r, vi_fmi_set_debug_logging(c, "dbg", 1, 2, bad), "dbg: unknown log category 'logNothing'");
    REFUSED(r, vi_fmi_set_debug_logging(c, "dbg", 1, 1, null), "dbg: unknown log category '(null)'");
    REFUSED(r, vi_fmi_set_debug_logging(c, "dbg", 1, 1, near), "unknown log category 'logEvent'");
    cr_assert(c->log_mask == 0u, "mask %#x", c->log_mask);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_call_in_a_state_it_is_not_allowed_in_is_refused_naming_the_state)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    REFUSED(r, vi_fmi_exit_init(c, "exitInit"), "exitInit: not allowed in state 'instantiated'");
    cr_assert(c->state == VI_ST_INSTANTIATED);
    static const struct { unsigned st; const char *name; } names[] = {
        {VI_ST_INIT, "initialization mode"}, {VI_ST_STEP_FAILED, "step failed"}, {VI_ST_TERMINATED, "terminated"},
        {VI_ST_ERROR, "error"}, {VI_ST_EVENT, "event mode"}, {VI_ST_CONTINUOUS, "continuous-time mode"},
        {VI_ST_FATAL, "fatal"}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        c->state = names[i].st;
        char want[64];
        snprintf(want, sizeof want, "not allowed in state '%s'", names[i].name);
        REFUSED(r, vi_fmi_enter_init(c, "enterInit"), want);
    }
    c->state = VI_ST_STEP_COMPLETE;
    REFUSED(r, vi_fmi_enter_init(c, "enterInit"), "state 'step complete'");
    cr_assert(vi_fmi_enter_init(NULL, "enterInit") == VI_STATUS_ERROR);
    vi_fmi_free(NULL, "free");
    vi_fmi_free(c, "free");
}

/* ---- life cycle ---- */

static vi_fmi_instance *instantiate_with(record *r, vi_callbacks cb, const char *name, vi_kind kind, const char *guid)
{
    cb.logger = any_logger, cb.env = r;
    return vi_fmi_instantiate(&face, &cb, "inst", name, kind, guid, "/res", "file:///res", 0);
}

Test(fmi_layer, instantiation_needs_both_memory_callbacks)
{
    record r = {0};
    vi_callbacks no_alloc = {.free = free}, no_free = {.alloc = calloc};
    cr_assert(instantiate_with(&r, no_alloc, "a", VI_KIND_CS, VI_GUID) == NULL);
    LAST_IS(r, VI_STATUS_ERROR, "inst: the callbacks allocateMemory and freeMemory are required");
    cr_assert(r.count == 1 && strcmp(r.name, "a") == 0, "%d %s", r.count, r.name);
    cr_assert(instantiate_with(&r, no_free, "b", VI_KIND_CS, VI_GUID) == NULL);
    cr_assert(r.count == 2 && strstr(r.text, "allocateMemory and freeMemory are required"));
}

Test(fmi_layer, instantiation_needs_a_name_a_known_interface_and_the_guid)
{
    record r = {0};
    vi_callbacks cb = {.alloc = calloc, .free = free};
    cr_assert(instantiate_with(&r, cb, NULL, VI_KIND_CS, VI_GUID) == NULL);
    LAST_IS(r, VI_STATUS_ERROR, "inst: instanceName must be a non-empty string");
    cr_assert(strcmp(r.name, "?") == 0, "%s", r.name);
    cr_assert(instantiate_with(&r, cb, "", VI_KIND_CS, VI_GUID) == NULL && r.count == 2);
    LAST_IS(r, VI_STATUS_ERROR, "instanceName must be a non-empty string");
    cr_assert(instantiate_with(&r, cb, "x", (vi_kind)7, VI_GUID) == NULL && r.count == 3);
    LAST_IS(r, VI_STATUS_ERROR, "inst: CoreTest does not offer the interface type asked for (unknown type)");
    cr_assert(instantiate_with(&r, cb, "x", VI_KIND_CS, NULL) == NULL && r.count == 4);
    LAST_IS(r, VI_STATUS_ERROR, "inst: GUID '(null)' does not match this FMU's '{core-test}'");
    cr_assert(instantiate_with(&r, cb, "x", VI_KIND_CS, "{core-test}x") == NULL && r.count == 5);
    LAST_IS(r, VI_STATUS_ERROR, "GUID '{core-test}x' does not match");
    vi_fmi_instance *c = instantiate_with(&r, cb, "me", VI_KIND_ME, VI_GUID);
    cr_assert(c != NULL && r.count == 5 && c->kind == VI_KIND_ME && c->state == VI_ST_INSTANTIATED, "%s", r.text);
    cr_assert(strcmp(resources_dir, "/res") == 0);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, every_allocation_of_instantiation_is_checked_and_nothing_leaks)
{
    record r = {0};
    vi_callbacks cb = {.alloc = counting_alloc, .free = counting_free};
    for (int k = 1; k <= 4; k++) {
        n_alloc = n_free = 0, fail_at = k, r.count = 0;
        cr_assert(instantiate_with(&r, cb, "x", VI_KIND_CS, VI_GUID) == NULL, "allocation %d", k);
        cr_assert(r.count == 1, "allocation %d: %d messages", k, r.count);
        LAST_IS(r, VI_STATUS_ERROR, "inst: out of memory");
        cr_assert(n_alloc == 4 && n_free == 3, "allocation %d: %d allocated, %d freed", k, n_alloc, n_free);
    }
    n_alloc = n_free = 0, fail_at = 0;
    vi_fmi_instance *c = instantiate_with(&r, cb, "name", VI_KIND_CS, VI_GUID);
    cr_assert(c != NULL && n_alloc == 4);
    /* each block has the size of what it holds */
    cr_assert(block_size(c) >= sizeof *c && block_size(c->name) >= 5 && block_size(c->model) >= sizeof(stub) &&
              block_size(c->outputs) >= sizeof(vi_outputs), "%zu %zu %zu %zu", block_size(c), block_size(c->name),
              block_size(c->model), block_size(c->outputs));
    cr_assert(strcmp(c->name, "name") == 0 && c->face == &face && c->cb.alloc == counting_alloc);
    stub *s = c->model;
    cr_assert(s->env == c && s->d.par.k == 1.0 && c->outputs != NULL, "the model was not initialized");
    vi_fmi_free(c, "free");
    cr_assert(n_free == 4 && s != NULL, "%d freed", n_free);
}

Test(fmi_layer, a_resources_failure_is_reported_and_frees_the_instance)
{
    record r = {0};
    vi_callbacks cb = {.alloc = counting_alloc, .free = counting_free};
    n_alloc = n_free = 0, fail_at = 0, fail_resources = 1;
    vi_fmi_instance *c = instantiate_with(&r, cb, "x", VI_KIND_CS, VI_GUID);
    fail_resources = 0;
    cr_assert(c == NULL && r.count == 1);
    LAST_IS(r, VI_STATUS_ERROR, "inst: resources 'file:///res': the stub says no");
    cr_assert(n_alloc == 4 && n_free == 4, "%d allocated, %d freed", n_alloc, n_free);
}

Test(fmi_layer, free_releases_the_model_and_every_block)
{
    record r = {0};
    vi_callbacks cb = {.alloc = counting_alloc, .free = counting_free};
    n_alloc = n_free = 0, fail_at = 0;
    vi_fmi_instance *c = instantiate_with(&r, cb, "x", VI_KIND_CS, VI_GUID);
    cr_assert(c);
    int before = releases;
    vi_fmi_free(c, "free");
    cr_assert(n_free == 4 && releases == before + 1, "%d blocks freed, %d releases", n_free, releases - before);
}

Test(fmi_layer, setup_experiment_takes_a_tolerance_strictly_between_0_and_1)
{
    record r = {0};
    const double bad[] = {0.0, 1.0, -1e-3, 2.0, NAN, INFINITY}, good[] = {5e-324, 0.5, 0x1.fffffffffffffp-1};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        vi_fmi_instance *c = make(&r, 0);
        REFUSED(r, vi_fmi_setup_experiment(c, "setup", 1, bad[i], 0.0, 0, 0.0), "setup: need a finite start time",
                "a tolerance in (0, 1)");
        stub *s = c->model;
        cr_assert(s->setup_calls == 0);
        vi_fmi_free(c, "free");
    }
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
        vi_fmi_instance *c = make(&r, 0);
        cr_assert(vi_fmi_setup_experiment(c, "setup", 1, good[i], 0.0, 0, 0.0) == VI_STATUS_OK, "%g", good[i]);
        stub *s = c->model;
        cr_assert(s->setup_calls == 1 && s->setup_tol_defined == 1 && s->setup_tol == good[i]);
        vi_fmi_free(c, "free");
    }
    /* no tolerance given: its value does not matter */
    vi_fmi_instance *c = make(&r, 0);
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, 0.0, 0, 0.0) == VI_STATUS_OK);
    cr_assert(((stub *)c->model)->setup_tol_defined == 0);
    vi_fmi_free(c, "free");
    c = make(&r, 0);
    cr_assert(vi_fmi_setup_experiment(c, "setup", 7, 0.25, 0.0, 0, 0.0) == VI_STATUS_OK);
    cr_assert(((stub *)c->model)->setup_tol_defined == 1, "tolerance_defined passed as %d",
              ((stub *)c->model)->setup_tol_defined);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, setup_experiment_needs_a_finite_start_and_a_stop_not_before_it)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    REFUSED(r, vi_fmi_setup_experiment(c, "setup", 0, 0.0, NAN, 0, 0.0), "start nan");
    REFUSED(r, vi_fmi_setup_experiment(c, "setup", 0, 0.0, INFINITY, 0, 0.0), "start inf");
    REFUSED(r, vi_fmi_setup_experiment(c, "setup", 1, 0.125, 2.0, 1, nextafter(2.0, 0.0)),
            "(got start 2, tolerance 0.125, stop 2)");
    REFUSED(r, vi_fmi_setup_experiment(c, "setup", 0, 0.0, 2.0, 1, NAN), "stop nan");
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, 2.0, 0, 1.0) == VI_STATUS_OK); /* no stop time */
    cr_assert(c->stop_time_defined == 0);
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, 2.0, 5, 2.0) == VI_STATUS_OK);
    stub *s = c->model;
    cr_assert(c->stop_time_defined == 1 && c->stop_time == 2.0 && s->setup_start == 2.0 && s->d.t == 2.0);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, initialization_of_each_interface_and_its_failures)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && c->state == VI_ST_INIT && c->initialized == 0);
    ((stub *)c->model)->fail_init = 1;
    REFUSED(r, vi_fmi_exit_init(c, "exitInit"), "exitInit: the stub says no");
    cr_assert(c->state == VI_ST_ERROR && c->initialized == 0);
    vi_fmi_free(c, "free");

    c = make(&r, 0);
    ((stub *)c->model)->fail_me_init = 1; /* not the Co-Simulation hook */
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    cr_assert(c->state == VI_ST_STEP_COMPLETE && c->initialized == 1);
    vi_fmi_free(c, "free");

    c = make_with(&face, &r, VI_KIND_ME, 0);
    ((stub *)c->model)->fail_me_init = 1;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    REFUSED(r, vi_fmi_exit_init(c, "exitInit"), "exitInit: the stub says no");
    cr_assert(c->state == VI_ST_ERROR && c->initialized == 0);
    vi_fmi_free(c, "free");

    c = make_with(&face, &r, VI_KIND_ME, 0);
    ((stub *)c->model)->fail_init = 1; /* not the Model Exchange hook */
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, 3.0, 0, 0.0) == VI_STATUS_OK);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    c->event_passes = 5, c->t_committed = -1.0;
    cr_assert(vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    cr_assert(c->state == VI_ST_EVENT && c->initialized == 1 && c->event_passes == 0 && c->t_committed == 3.0,
              "state %u, initialized %d, passes %d, t_committed %g", c->state, c->initialized, c->event_passes,
              c->t_committed);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, terminate_and_reset)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, 0.0, 1, 5.0) == VI_STATUS_OK);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    cr_assert(vi_fmi_terminate(c, "term") == VI_STATUS_OK && c->state == VI_ST_TERMINATED && s->terminate_calls == 1);
    s->d.par.k = 7.0;
    cr_assert(vi_fmi_reset(c, "reset") == VI_STATUS_OK);
    cr_assert(c->state == VI_ST_INSTANTIATED && c->stop_time_defined == 0 && c->initialized == 0 &&
              s->reset_calls == 1 && s->d.par.k == 1.0);
    vi_fmi_free(c, "free");
    c = make(&r, 0);
    s = c->model;
    REFUSED(r, vi_fmi_terminate(c, "term"), "term: not allowed in state 'instantiated'");
    cr_assert(s->terminate_calls == 0 && c->state == VI_ST_INSTANTIATED);
    vi_fmi_free(c, "free");
}

/* ---- values ---- */

Test(fmi_layer, get_and_set_refuse_a_null_array_of_either_kind_but_not_an_empty_call)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    unsigned vr = VI_VR_k;
    double v = 2.0;
    REFUSED(r, vi_fmi_get(c, "get", NULL, 1, VI_Real, &v, VI_ELEM_DOUBLE), "get: NULL array");
    REFUSED(r, vi_fmi_get(c, "get", &vr, 1, VI_Real, NULL, VI_ELEM_DOUBLE), "get: NULL array");
    REFUSED(r, vi_fmi_set(c, "set", NULL, 1, VI_Real, &v, VI_ELEM_DOUBLE), "set: NULL array");
    REFUSED(r, vi_fmi_set(c, "set", &vr, 1, VI_Real, NULL, VI_ELEM_DOUBLE), "set: NULL array");
    cr_assert(vi_fmi_get(c, "get", NULL, 0, VI_Real, NULL, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    cr_assert(vi_fmi_set(c, "set", NULL, 0, VI_Real, NULL, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    cr_assert(get_k(c) == 1.0);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, get_refuses_unknown_references_and_other_types_naming_the_type)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    unsigned vr = VI_NVARS;
    double v;
    int k;
    REFUSED(r, vi_fmi_get(c, "get", &vr, 1, VI_Real, &v, VI_ELEM_DOUBLE), "get: unknown value reference 12");
    vr = TIME_VR; /* the plain face has no time variable */
    REFUSED(r, vi_fmi_get(c, "get", &vr, 1, VI_Real, &v, VI_ELEM_DOUBLE), "unknown value reference 1000");
    vr = VI_VR_k;
    REFUSED(r, vi_fmi_get(c, "get", &vr, 1, VI_Integer, &k, VI_ELEM_INT), "get: value reference 1 (k) is of type Real");
    vr = VI_VR_b;
    REFUSED(r, vi_fmi_get(c, "get", &vr, 1, VI_Real, &v, VI_ELEM_DOUBLE), "(b) is of type Boolean");
    vr = VI_VR_n;
    REFUSED(r, vi_fmi_get(c, "get", &vr, 1, VI_Real, &v, VI_ELEM_DOUBLE), "(n) is of type Integer");
    vr = VI_VR_label;
    REFUSED(r, vi_fmi_get(c, "get", &vr, 1, VI_Real, &v, VI_ELEM_DOUBLE), "(label) is of type String");
    vr = VI_VR_color; /* an enumeration is read as an Integer by the plain face */
    cr_assert(vi_fmi_get(c, "get", &vr, 1, VI_Integer, &k, VI_ELEM_INT) == VI_STATUS_OK && k == 2);
    REFUSED(r, vi_fmi_get(c, "get", &vr, 1, VI_Real, &v, VI_ELEM_DOUBLE), "(color) is of type Integer");
    vi_fmi_free(c, "free");

    c = make_with(&face3, &r, VI_KIND_CS, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    REFUSED(r, vi_fmi_get(c, "get3", &vr, 1, VI_Integer, &k, VI_ELEM_INT), "get3: value reference 11 (color) is of type Enum64");
    int64_t k64 = 0;
    cr_assert(vi_fmi_get(c, "get3", &vr, 1, VI_Enumeration, &k64, VI_ELEM_INT64) == VI_STATUS_OK && k64 == 2);
    vr = VI_VR_n;
    REFUSED(r, vi_fmi_get(c, "get3", &vr, 1, VI_Enumeration, &k64, VI_ELEM_INT64), "(n) is of type I32");
    vr = VI_VR_k;
    REFUSED(r, vi_fmi_get(c, "get3", &vr, 1, VI_Boolean, &k, VI_ELEM_BOOL), "(k) is of type F64");
    vi_fmi_free(c, "free");
}

Test(fmi_layer, get_reads_each_type_into_its_element_kind)
{
    record r = {0};
    vi_fmi_instance *c = make_with(&face3, &r, VI_KIND_CS, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    stub *s = c->model;
    s->d.in.b = 1, s->d.par.n = 6;
    unsigned vb = VI_VR_b, vn = VI_VR_n, vl = VI_VR_label, vk = VI_VR_k;
    bool b = false;
    int bi = 0, n = 0;
    const char *str = NULL;
    cr_assert(vi_fmi_get(c, "get", &vb, 1, VI_Boolean, &b, VI_ELEM_BOOL) == VI_STATUS_OK && b == true);
    cr_assert(vi_fmi_get(c, "get", &vb, 1, VI_Boolean, &bi, VI_ELEM_INT) == VI_STATUS_OK && bi == 1);
    cr_assert(vi_fmi_get(c, "get", &vn, 1, VI_Integer, &n, VI_ELEM_INT) == VI_STATUS_OK && n == 6);
    cr_assert(vi_fmi_get(c, "get", &vl, 1, VI_String, &str, VI_ELEM_STRING) == VI_STATUS_OK);
    cr_assert(str == s->d.par.label && strcmp(str, "abc") == 0);
    double two[2] = {0, 0};
    unsigned vr2[2] = {VI_VR_k, VI_VR_u};
    s->d.in.u = -3.5;
    cr_assert(vi_fmi_get(c, "get", vr2, 2, VI_Real, two, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    cr_assert(two[0] == 1.0 && two[1] == -3.5);
    /* outputs after the first (their offsets in vi_outputs are not 0) */
    unsigned outs[3] = {VI_VR_q, VI_VR_der_q, VI_VR_p};
    double o[3] = {0, 0, 0};
    s->d.par.k = 2.0;
    cr_assert(vi_fmi_get(c, "get", outs, 3, VI_Real, o, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    cr_assert(o[0] == -0.25 && o[1] == -1.0 && o[2] == 0.5, "%g %g %g", o[0], o[1], o[2]);
    (void)vk;
    vi_fmi_free(c, "free");
}

Test(fmi_layer, outputs_are_computed_from_the_initial_state_in_initialization_mode_and_after_a_failed_one)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    unsigned vy = VI_VR_y;
    double y = 0;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    cr_assert(vi_fmi_get(c, "get", &vy, 1, VI_Real, &y, VI_ELEM_DOUBLE) == VI_STATUS_OK && y == 1.0);
    cr_assert(s->prepare_calls == 1);
    get_k(c); /* a parameter: nothing prepared */
    cr_assert(s->prepare_calls == 1);
    s->fail_prepare = 1;
    REFUSED(r, vi_fmi_get(c, "get", &vy, 1, VI_Real, &y, VI_ELEM_DOUBLE), "get: the stub says no");
    s->fail_init = 1;
    cr_assert(vi_fmi_exit_init(c, "exit") == VI_STATUS_ERROR && c->state == VI_ST_ERROR);
    REFUSED(r, vi_fmi_get(c, "get", &vy, 1, VI_Real, &y, VI_ELEM_DOUBLE), "get: the stub says no");
    cr_assert(s->prepare_calls == 3);
    vi_fmi_free(c, "free");

    c = make(&r, 0);
    s = c->model;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    s->fail_prepare = 1; /* running: no prepare */
    cr_assert(vi_fmi_get(c, "get", &vy, 1, VI_Real, &y, VI_ELEM_DOUBLE) == VI_STATUS_OK && y == 1.0);
    c->state = VI_ST_ERROR; /* the error state of an initialized instance */
    cr_assert(vi_fmi_get(c, "get", &vy, 1, VI_Real, &y, VI_ELEM_DOUBLE) == VI_STATUS_OK && y == 1.0);
    cr_assert(s->prepare_calls == 0);
    s->nan_outputs = 1;
    REFUSED(r, vi_fmi_get(c, "get", &vy, 1, VI_Real, &y, VI_ELEM_DOUBLE), "get: y = nan has no value in state 'error'");
    vi_fmi_free(c, "free");
}

Test(fmi_layer, the_face_variables_time_input_derivatives_and_indicators_are_read)
{
    record r = {0};
    vi_fmi_instance *c = make_with(&face3, &r, VI_KIND_ME, 0);
    stub *s = c->model;
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, 1.5, 0, 0.0) == VI_STATUS_OK);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    s->d.din.u = 0.75;
    s->d.x[0] = 3.0;
    unsigned vr[4] = {TIME_VR, DER_BASE + VI_VR_u, IND_BASE, VI_VR_y};
    double v[4] = {0};
    cr_assert(vi_fmi_get(c, "get", vr, 4, VI_Real, v, VI_ELEM_DOUBLE) == VI_STATUS_OK, "%s", r.text);
    cr_assert(v[0] == 1.5 && v[1] == 0.75 && v[2] == 2.0 && v[3] == 1.0, "%g %g %g %g", v[0], v[1], v[2], v[3]);
    cr_assert(s->prepare_calls == 1 && s->outputs_calls == 1, "prepared %d times, outputs %d", s->prepare_calls,
              s->outputs_calls);
    /* not the derivative of an input, beyond the indicators, between the bases, as another type */
    const unsigned bad[] = {DER_BASE + VI_VR_k, DER_BASE + VI_NVARS, IND_BASE + 1, TIME_VR + 1, DER_BASE - 1};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char want[64];
        snprintf(want, sizeof want, "get: unknown value reference %u", bad[i]);
        REFUSED(r, vi_fmi_get(c, "get", &bad[i], 1, VI_Real, v, VI_ELEM_DOUBLE), want);
    }
    int k;
    REFUSED(r, vi_fmi_get(c, "get", &vr[0], 1, VI_Integer, &k, VI_ELEM_INT), "unknown value reference 1000");
    s->fail_prepare = 1;
    REFUSED(r, vi_fmi_get(c, "get", &vr[0], 1, VI_Real, v, VI_ELEM_DOUBLE), "get: the stub says no");
    REFUSED(r, vi_fmi_get(c, "get", &vr[2], 1, VI_Real, v, VI_ELEM_DOUBLE), "get: the stub says no");
    s->fail_prepare = 0;
    /* the face's references are never set */
    REFUSED(r, vi_fmi_set(c, "set", &vr[0], 1, VI_Real, v, VI_ELEM_DOUBLE), "set: time is the independent variable");
    REFUSED(r, vi_fmi_set(c, "set", &vr[2], 1, VI_Real, v, VI_ELEM_DOUBLE),
            "set: value reference 3000 is an event indicator: it cannot be set");
    vi_fmi_free(c, "free");

    /* Co-Simulation declares the indicators too: they read as the model's */
    c = make_with(&face3, &r, VI_KIND_CS, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    v[0] = NAN;
    cr_assert(vi_fmi_get(c, "get", &vr[2], 1, VI_Real, v, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    stub *cs = c->model;
    cr_assert(v[0] == cs->d.x[0] - 1.0, "indicator %g, the stub's %g", v[0], cs->d.x[0] - 1.0);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, input_derivatives_set_as_variables_in_the_order_given)
{
    record r = {0};
    vi_fmi_instance *c = make_with(&face3, &r, VI_KIND_CS, 0);
    stub *s = c->model;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    unsigned vr[2] = {DER_BASE + VI_VR_u, VI_VR_u};
    double v[2] = {4.0, 2.0};
    cr_assert(vi_fmi_set(c, "set", vr, 2, VI_Real, v, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    cr_assert(s->d.in.u == 2.0 && s->d.din.u == 0.0, "a value set after its derivative resets it");
    cr_assert(s->changed_calls == 2, "%d", s->changed_calls);
    unsigned vr2[2] = {VI_VR_u, DER_BASE + VI_VR_u};
    double v2[2] = {3.0, 5.0};
    cr_assert(vi_fmi_set(c, "set", vr2, 2, VI_Real, v2, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    cr_assert(s->d.in.u == 3.0 && s->d.din.u == 5.0 && s->changed_calls == 4);
    double bad[2] = {1.0, INFINITY};
    REFUSED(r, vi_fmi_set(c, "set", vr2, 2, VI_Real, bad, VI_ELEM_DOUBLE), "set: the derivative of u must be finite");
    cr_assert(s->d.in.u == 3.0 && s->d.din.u == 5.0 && s->changed_calls == 4);
    unsigned vk = DER_BASE + VI_VR_k;
    REFUSED(r, vi_fmi_set(c, "set", &vk, 1, VI_Real, v, VI_ELEM_DOUBLE), "set: unknown value reference 2001");
    vi_fmi_free(c, "free");
}

Test(fmi_layer, what_may_be_set_in_each_state)
{
    record r = {0};
    vi_fmi_instance *c = make_with(&face, &r, VI_KIND_ME, 0);
    stub *s = c->model;
    unsigned vk = VI_VR_k, vn = VI_VR_n, vu = VI_VR_u, vb = VI_VR_b, vy = VI_VR_y, vw = VI_VR_w, vl = VI_VR_label;
    double x = 2.0;
    int one = 1, four = 4;
    /* instantiated and initialization mode: parameters and inputs, no change announced */
    cr_assert(vi_fmi_set(c, "set", &vn, 1, VI_Integer, &four, VI_ELEM_INT) == VI_STATUS_OK && s->d.par.n == 4);
    cr_assert(s->changed_calls == 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    cr_assert(vi_fmi_set(c, "set", &vk, 1, VI_Real, &x, VI_ELEM_DOUBLE) == VI_STATUS_OK && s->d.par.k == 2.0);
    cr_assert(s->changed_calls == 0, "a parameter set in initialization mode was announced");
    cr_assert(vi_fmi_set(c, "set", &vu, 1, VI_Real, &x, VI_ELEM_DOUBLE) == VI_STATUS_OK && s->changed_calls == 1);
    REFUSED(r, vi_fmi_set(c, "set", &vy, 1, VI_Real, &x, VI_ELEM_DOUBLE), "set: y is an output and cannot be set");
    cr_assert(vi_fmi_exit_init(c, "exit") == VI_STATUS_OK && c->state == VI_ST_EVENT);
    /* event mode: tunable parameters and inputs, announced; fixed ones not */
    int five = 5;
    REFUSED(r, vi_fmi_set(c, "set", &vn, 1, VI_Integer, &five, VI_ELEM_INT),
            "set: n is a fixed parameter: set it before the end of initialization mode");
    const char *lab = "new";
    REFUSED(r, vi_fmi_set(c, "set", &vl, 1, VI_String, &lab, VI_ELEM_STRING), "set: label is a fixed parameter");
    cr_assert(s->d.par.n == 4);
    x = 3.0;
    cr_assert(vi_fmi_set(c, "set", &vk, 1, VI_Real, &x, VI_ELEM_DOUBLE) == VI_STATUS_OK && s->d.par.k == 3.0);
    cr_assert(s->changed_calls == 2, "%d", s->changed_calls);
    cr_assert(vi_fmi_set(c, "set", &vb, 1, VI_Boolean, &one, VI_ELEM_INT) == VI_STATUS_OK && s->changed_calls == 3);
    /* continuous-time mode: continuous inputs only, not announced, the derivative reset */
    cr_assert(vi_fmi_enter_continuous_mode(c, "cont") == VI_STATUS_OK && c->state == VI_ST_CONTINUOUS);
    s->d.din.u = 9.0;
    cr_assert(vi_fmi_set(c, "set", &vu, 1, VI_Real, &x, VI_ELEM_DOUBLE) == VI_STATUS_OK && s->d.in.u == 3.0);
    cr_assert(s->changed_calls == 3 && s->d.din.u == 0.0, "%d %g", s->changed_calls, s->d.din.u);
    REFUSED(r, vi_fmi_set(c, "set", &vk, 1, VI_Real, &x, VI_ELEM_DOUBLE),
            "set: k cannot be set in continuous-time mode (only continuous inputs can)");
    REFUSED(r, vi_fmi_set(c, "set", &vw, 1, VI_Real, &x, VI_ELEM_DOUBLE), "set: w cannot be set in continuous-time");
    vi_fmi_free(c, "free");

    /* Co-Simulation: a tunable parameter between steps is announced */
    c = make(&r, 0);
    s = c->model;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    int blue = 5;
    unsigned vc = VI_VR_color;
    cr_assert(vi_fmi_set(c, "set", &vc, 1, VI_Integer, &blue, VI_ELEM_INT) == VI_STATUS_OK && s->d.par.color == 5);
    cr_assert(s->changed_calls == 1);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, values_are_checked_before_any_is_stored)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    unsigned vr[2] = {VI_VR_u, VI_VR_k};
    double nan2[2] = {1.0, NAN};
    REFUSED(r, vi_fmi_set(c, "set", vr, 2, VI_Real, nan2, VI_ELEM_DOUBLE), "set: k must be finite");
    cr_assert(s->d.in.u == 0.0);
    /* Booleans: any nonzero value is stored as 1 */
    unsigned vb = VI_VR_b;
    int seven = 7, zero = 0;
    cr_assert(vi_fmi_set(c, "set", &vb, 1, VI_Boolean, &seven, VI_ELEM_INT) == VI_STATUS_OK && s->d.in.b == 1);
    cr_assert(vi_fmi_set(c, "set", &vb, 1, VI_Boolean, &zero, VI_ELEM_INT) == VI_STATUS_OK && s->d.in.b == 0);
    /* enumerations: items only */
    unsigned vc = VI_VR_color;
    const int items_bad[] = {3, 0, -2, 6, 1}, items_ok[] = {5, 2}; /* 1 and 6: items of another type */
    for (int i = 0; i < 5; i++)
        REFUSED(r, vi_fmi_set(c, "set", &vc, 1, VI_Integer, &items_bad[i], VI_ELEM_INT),
                "is not one of its items red=2, blue=5, white=2147483647, black=-2147483648; nothing was set");
    for (int i = 0; i < 2; i++)
        cr_assert(vi_fmi_set(c, "set", &vc, 1, VI_Integer, &items_ok[i], VI_ELEM_INT) == VI_STATUS_OK &&
                  s->d.par.color == items_ok[i]);
    /* items at the ends of int; 64-bit values beyond them refused (not converted) */
    const int64_t ends[] = {INT32_MAX, INT32_MIN}, beyond[] = {(int64_t)INT32_MAX + 1, (int64_t)INT32_MIN - 1,
                                                               (int64_t)INT32_MAX + 2};
    for (int i = 0; i < 2; i++)
        cr_assert(vi_fmi_set(c, "set", &vc, 1, VI_Integer, &ends[i], VI_ELEM_INT64) == VI_STATUS_OK &&
                  s->d.par.color == ends[i], "%lld", (long long)ends[i]);
    REFUSED(r, vi_fmi_set(c, "set", &vc, 1, VI_Integer, &beyond[0], VI_ELEM_INT64), "set: color = 2147483648 is not one");
    REFUSED(r, vi_fmi_set(c, "set", &vc, 1, VI_Integer, &beyond[1], VI_ELEM_INT64), "set: color = -2147483649 is not one");
    REFUSED(r, vi_fmi_set(c, "set", &vc, 1, VI_Integer, &beyond[2], VI_ELEM_INT64), "set: color = 2147483649 is not one");
    /* Strings: not NULL, at most VI_STRING_SIZE - 1 characters */
    unsigned vl = VI_VR_label;
    const char *null = NULL;
    REFUSED(r, vi_fmi_set(c, "set", &vl, 1, VI_String, &null, VI_ELEM_STRING), "set: the value of label is NULL");
    static char longest[VI_STRING_SIZE + 1];
    memset(longest, 'a', VI_STRING_SIZE);
    longest[VI_STRING_SIZE] = '\0';
    const char *too_long = longest;
    REFUSED(r, vi_fmi_set(c, "set", &vl, 1, VI_String, &too_long, VI_ELEM_STRING),
            "set: the value of label is longer than 1023 characters");
    cr_assert(strcmp(s->d.par.label, "abc") == 0);
    longest[VI_STRING_SIZE - 1] = '\0';
    cr_assert(vi_fmi_set(c, "set", &vl, 1, VI_String, &too_long, VI_ELEM_STRING) == VI_STATUS_OK);
    cr_assert(strlen(s->d.par.label) == VI_STRING_SIZE - 1);
    /* a value set from the instance's own string */
    const char *own = s->d.par.label + 1000;
    cr_assert(vi_fmi_set(c, "set", &vl, 1, VI_String, &own, VI_ELEM_STRING) == VI_STATUS_OK);
    cr_assert(strlen(s->d.par.label) == 23);
    /* 64-bit and C bool arrays */
    int64_t n64 = 5;
    unsigned vn = VI_VR_n;
    cr_assert(vi_fmi_set(c, "set", &vn, 1, VI_Integer, &n64, VI_ELEM_INT64) == VI_STATUS_OK && s->d.par.n == 5);
    bool t = true;
    cr_assert(vi_fmi_set(c, "set", &vb, 1, VI_Boolean, &t, VI_ELEM_BOOL) == VI_STATUS_OK && s->d.in.b == 1);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, input_derivatives_need_every_array_order_1_a_finite_value_and_an_input)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    unsigned vr = VI_VR_u;
    int order = 1;
    double v = 0.5;
    REFUSED(r, vi_fmi_set_input_derivatives(c, "der", NULL, 1, &order, &v), "der: NULL array");
    REFUSED(r, vi_fmi_set_input_derivatives(c, "der", &vr, 1, NULL, &v), "der: NULL array");
    REFUSED(r, vi_fmi_set_input_derivatives(c, "der", &vr, 1, &order, NULL), "der: NULL array");
    cr_assert(vi_fmi_set_input_derivatives(c, "der", NULL, 0, NULL, NULL) == VI_STATUS_OK);
    int two = 2, zero = 0;
    REFUSED(r, vi_fmi_set_input_derivatives(c, "der", &vr, 1, &two, &v), "der: u order 2 = 0.5: only finite first");
    REFUSED(r, vi_fmi_set_input_derivatives(c, "der", &vr, 1, &zero, &v), "der: u order 0 = 0.5");
    double inf = INFINITY;
    REFUSED(r, vi_fmi_set_input_derivatives(c, "der", &vr, 1, &order, &inf), "der: u order 1 = inf");
    unsigned vk = VI_VR_k, vx = 99;
    REFUSED(r, vi_fmi_set_input_derivatives(c, "der", &vk, 1, &order, &v), "der: k order 1 = 0.5");
    REFUSED(r, vi_fmi_set_input_derivatives(c, "der", &vx, 1, &order, &v), "der: unknown value reference 99");
    cr_assert(s->d.din.u == 0.0 && s->changed_calls == 0);
    cr_assert(vi_fmi_set_input_derivatives(c, "der", &vr, 1, &order, &v) == VI_STATUS_OK);
    cr_assert(s->d.din.u == 0.5 && s->changed_calls == 1);
    vi_fmi_free(c, "free");
}

/* ---- FMU state ---- */

/* The envelope's header as its format is documented (src/fmi/vi_fmi_fmu_state.c). */
typedef struct {
    uint32_t magic, version;
    uint64_t size, model;
    uint32_t fmu_state, stop_time_defined;
    double stop_time;
    uint64_t checksum;
} header;
#define SAVED_SIZE (sizeof(header) + sizeof(data))

/* The documented hash, written again from its description: FNV-1a's xor-multiply round on 64-bit
 * words, each followed by h ^= h >> 32, in four lanes started from h with the lane numbers, the
 * lanes folded in after the word count, then the tail bytes one by one. */
static uint64_t round64(uint64_t h, uint64_t w)
{
    h ^= w;
    h *= UINT64_C(1099511628211);
    return h ^ (h >> 32);
}
static uint64_t doc_hash(uint64_t h, const void *data_, size_t n)
{
    const unsigned char *p = data_;
    uint64_t lane[4];
    for (unsigned k = 0; k < 4; k++) lane[k] = round64(h, k);
    size_t blocks = n / 32;
    for (size_t b = 0; b < blocks; b++)
        for (unsigned k = 0; k < 4; k++) {
            uint64_t w;
            memcpy(&w, p + 32 * b + 8 * k, 8);
            lane[k] = round64(lane[k], w);
        }
    uint64_t out = round64(lane[0], n);
    for (unsigned k = 1; k < 4; k++) out = round64(out, lane[k]);
    for (size_t i = 32 * blocks; i < n; i++) out = round64(out, p[i]);
    return out;
}
#define OFFSET_BASIS UINT64_C(14695981039346656037)
static uint64_t doc_checksum(const void *saved)
{
    header h;
    memcpy(&h, saved, sizeof h);
    h.checksum = 0;
    return doc_hash(doc_hash(OFFSET_BASIS, &h, sizeof h), (const char *)saved + sizeof h, sizeof(data));
}
/* Recompute the checksum after a test altered a header field. */
static void reseal(void *saved) { ((header *)saved)->checksum = doc_checksum(saved); }

Test(fmi_layer, the_hash_of_the_state_envelope_is_the_documented_one)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    void *st = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &st) == VI_STATUS_OK && st);
    header h;
    memcpy(&h, st, sizeof h);
    cr_assert(h.magic == 0x554d4956u && h.version == 4u && h.size == SAVED_SIZE, "%#x %u %llu", h.magic, h.version,
              (unsigned long long)h.size);
    cr_assert(h.model == doc_hash(OFFSET_BASIS, VI_GUID, strlen(VI_GUID)), "model id %#llx",
              (unsigned long long)h.model);
    cr_assert(h.fmu_state == VI_ST_INSTANTIATED && h.stop_time_defined == 0);
    cr_assert(h.checksum == doc_checksum(st), "checksum %#llx, documented %#llx", (unsigned long long)h.checksum,
              (unsigned long long)doc_checksum(st));
    cr_assert(memcmp((char *)st + sizeof h, c->model, sizeof(data)) == 0, "the payload is the model's block");
    size_t size = 0;
    cr_assert(vi_fmi_fmu_state_size(c, "size", st, &size) == VI_STATUS_OK && size == SAVED_SIZE);
    cr_assert(vi_fmi_free_fmu_state(c, "free", &st) == VI_STATUS_OK && st == NULL);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_state_restores_the_model_block_the_fmi_state_and_the_stop_time)
{
    record r = {0};
    vi_fmi_instance *c = make_with(&face, &r, VI_KIND_ME, 0);
    stub *s = c->model;
    void *before = NULL, *after = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &before) == VI_STATUS_OK && s->checkpoint_calls == 0);
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, 2.0, 1, 9.0) == VI_STATUS_OK);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    cr_assert(vi_fmi_get_fmu_state(c, "get", &after) == VI_STATUS_OK && s->checkpoint_calls == 1);
    void *same = after;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &after) == VI_STATUS_OK && after == same, "a given state is reused");
    /* back to the instantiated state: not running */
    c->event_passes = 3;
    cr_assert(vi_fmi_set_fmu_state(c, "set", before) == VI_STATUS_OK);
    cr_assert(c->state == VI_ST_INSTANTIATED && c->stop_time_defined == 0 && c->stop_time == 0.0 && c->initialized == 0 &&
              c->event_passes == 0 && s->restored_running == 0 && s->d.t == 0.0 && c->t_committed == 0.0);
    /* and to the running one (Model Exchange) */
    cr_assert(vi_fmi_set_fmu_state(c, "set", after) == VI_STATUS_OK);
    cr_assert(c->state == VI_ST_EVENT && c->stop_time_defined == 1 && c->stop_time == 9.0 && c->initialized == 1 &&
              s->restored_running == VI_FMU_RUNNING_ME && s->d.t == 2.0 && c->t_committed == 2.0);
    s->fail_restore = 1;
    REFUSED(r, vi_fmi_set_fmu_state(c, "set", before), "set: the stub says no");
    cr_assert(c->state == VI_ST_ERROR);
    s->fail_restore = 0;
    /* a state taken in the error state after initialization is a running one */
    void *err = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &err) == VI_STATUS_OK && s->checkpoint_calls == 2);
    cr_assert(vi_fmi_set_fmu_state(c, "set", err) == VI_STATUS_OK && s->restored_running == VI_FMU_RUNNING_ME &&
              c->initialized == 1);
    vi_fmi_free_fmu_state(c, "free", &before);
    vi_fmi_free_fmu_state(c, "free", &after);
    vi_fmi_free_fmu_state(c, "free", &err);
    vi_fmi_free(c, "free");

    c = make(&r, 0);
    s = c->model;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    void *init_st = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &init_st) == VI_STATUS_OK && s->checkpoint_calls == 0);
    cr_assert(vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    s->fail_checkpoint = 1;
    void *none = NULL;
    REFUSED(r, vi_fmi_get_fmu_state(c, "get", &none), "get: the stub says no");
    cr_assert(c->state == VI_ST_ERROR && none == NULL);
    s->fail_checkpoint = 0;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &none) == VI_STATUS_OK);
    cr_assert(vi_fmi_set_fmu_state(c, "set", none) == VI_STATUS_OK && s->restored_running == VI_FMU_RUNNING_CS);
    cr_assert(vi_fmi_set_fmu_state(c, "set", init_st) == VI_STATUS_OK && c->state == VI_ST_INIT &&
              s->restored_running == 0 && c->initialized == 0);
    REFUSED(r, vi_fmi_get_fmu_state(c, "get", NULL), "get: FMUstate is NULL");
    vi_fmi_free_fmu_state(c, "free", &none);
    vi_fmi_free_fmu_state(c, "free", &init_st);
    cr_assert(vi_fmi_free_fmu_state(c, "free", NULL) == VI_STATUS_OK);
    cr_assert(vi_fmi_free_fmu_state(c, "free", &none) == VI_STATUS_OK && none == NULL);
    vi_fmi_free(c, "free");
}

/* A saved state of c with one header field changed (resealed), refused with the given reason. */
static void refused_state(record *r, vi_fmi_instance *c, void (*alter)(void *), int seal, const char *why)
{
    void *st = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &st) == VI_STATUS_OK);
    alter(st);
    if (seal) reseal(st);
    unsigned state = c->state;
    char want[400];
    snprintf(want, sizeof want, "set: invalid FMU state: %s", why);
    REFUSED(*r, vi_fmi_set_fmu_state(c, "set", st), want);
    cr_assert(c->state == state);
    size_t size = 0;
    snprintf(want, sizeof want, "size: invalid FMU state: %s", why);
    REFUSED(*r, vi_fmi_fmu_state_size(c, "size", st, &size), want);
    unsigned char bytes[SAVED_SIZE];
    snprintf(want, sizeof want, "ser: invalid FMU state: %s", why);
    REFUSED(*r, vi_fmi_serialize(c, "ser", st, bytes, sizeof bytes), want);
    memcpy(bytes, st, sizeof bytes);
    void *back = NULL;
    snprintf(want, sizeof want, "des: invalid FMU state: %s", why);
    REFUSED(*r, vi_fmi_deserialize(c, "des", bytes, sizeof bytes, &back), want);
    cr_assert(back == NULL);
    vi_fmi_free_fmu_state(c, "free", &st);
}
static void bad_magic(void *s) { ((header *)s)->magic ^= 1u; }
static void bad_version(void *s) { ((header *)s)->version = 3u; }
static void bad_model(void *s) { ((header *)s)->model ^= 1u; }
static void bad_size(void *s) { ((header *)s)->size -= 8u; }
static void bad_payload(void *s) { ((unsigned char *)s)[sizeof(header) + sizeof(data) - 1] ^= 1u; }
static void no_state(void *s) { ((header *)s)->fmu_state = 0u; }
static void two_states(void *s) { ((header *)s)->fmu_state = VI_ST_INIT | VI_ST_INSTANTIATED; }
static void fatal_state(void *s) { ((header *)s)->fmu_state = VI_ST_FATAL; }
static void beyond_state(void *s) { ((header *)s)->fmu_state = 1u << 9; }
static void step_state(void *s) { ((header *)s)->fmu_state = VI_ST_STEP_COMPLETE; }
static void failed_state(void *s) { ((header *)s)->fmu_state = VI_ST_STEP_FAILED; }
static void event_state(void *s) { ((header *)s)->fmu_state = VI_ST_EVENT; }
static void continuous_state(void *s) { ((header *)s)->fmu_state = VI_ST_CONTINUOUS; }
static void stop_flag(void *s) { ((header *)s)->stop_time_defined = 2u; }
static void stop_nan(void *s) { ((header *)s)->stop_time_defined = 1u, ((header *)s)->stop_time = NAN; }
static void stop_inf(void *s) { ((header *)s)->stop_time_defined = 1u, ((header *)s)->stop_time = -INFINITY; }

Test(fmi_layer, every_part_of_a_state_is_checked_before_it_is_used)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    refused_state(&r, c, bad_magic, 0, "not an FMU state of this layer (magic number)");
    refused_state(&r, c, bad_version, 0, "an FMU state of another layer version");
    refused_state(&r, c, bad_model, 0, "an FMU state of another model (GUID)");
    refused_state(&r, c, bad_payload, 0, "checksum mismatch: the state was altered");
    refused_state(&r, c, no_state, 1, "field fmu_state = 0 is not an FMI state");
    refused_state(&r, c, two_states, 1, "field fmu_state = 3 is not an FMI state");
    refused_state(&r, c, fatal_state, 1, "field fmu_state = 64 is not an FMI state");
    refused_state(&r, c, beyond_state, 1, "field fmu_state = 512 is not an FMI state");
    refused_state(&r, c, event_state, 1, "taken in state 'event mode', which an instance of this interface never is in");
    refused_state(&r, c, continuous_state, 1, "taken in state 'continuous-time mode', which");
    refused_state(&r, c, stop_flag, 1, "field stop_time is not finite");
    refused_state(&r, c, stop_nan, 1, "field stop_time is not finite");
    refused_state(&r, c, stop_inf, 1, "field stop_time is not finite");
    vi_fmi_free(c, "free");

    c = make_with(&face, &r, VI_KIND_ME, 0);
    refused_state(&r, c, step_state, 1, "taken in state 'step complete', which an instance of this interface never");
    refused_state(&r, c, failed_state, 1, "taken in state 'step failed'");
    vi_fmi_free(c, "free");

    /* Co-Simulation with Event Mode: states taken there are fine */
    c = make_with(&face3, &r, VI_KIND_CS, 0);
    void *st = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &st) == VI_STATUS_OK);
    event_state(st), reseal(st);
    cr_assert(vi_fmi_set_fmu_state(c, "set", st) == VI_STATUS_OK && c->state == VI_ST_EVENT, "%s", r.text);
    vi_fmi_free_fmu_state(c, "free", &st);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_state_with_a_bad_size_is_refused)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    void *st = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &st) == VI_STATUS_OK);
    bad_size(st), reseal(st);
    char want[200];
    snprintf(want, sizeof want, "set: invalid FMU state: size %zu bytes: a state of this build of CoreTest has %zu",
             SAVED_SIZE - 8, SAVED_SIZE);
    REFUSED(r, vi_fmi_set_fmu_state(c, "set", st), want);
    vi_fmi_free_fmu_state(c, "free", &st);
    cr_assert(vi_fmi_set_fmu_state(c, "set", NULL) == VI_STATUS_ERROR);
    LAST_IS(r, VI_STATUS_ERROR, "set: invalid FMU state: the state is NULL");
    size_t size = 0;
    REFUSED(r, vi_fmi_fmu_state_size(c, "size", NULL, &size), "size: invalid FMU state: the state is NULL");
    cr_assert(size == 0);
    vi_fmi_free(c, "free");
}

/* A state whose model block was changed behind the setters' back: refused, naming the value. */
static void refused_values(record *r, void (*alter)(stub *), const char *why)
{
    vi_fmi_instance *c = make(r, 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    stub *s = c->model;
    alter(s);
    void *st = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &st) == VI_STATUS_OK);
    char want[300];
    snprintf(want, sizeof want, "set: invalid FMU state: %s", why);
    REFUSED(*r, vi_fmi_set_fmu_state(c, "set", st), want);
    vi_fmi_free_fmu_state(c, "free", &st);
    vi_fmi_free(c, "free");
}
static void k_nan(stub *s) { s->d.par.k = NAN; }
static void k_zero(stub *s) { s->d.par.k = 0.0; }
static void k_above(stub *s) { s->d.par.k = 10.5; }
static void u_inf(stub *s) { s->d.in.u = INFINITY; }
static void du_nan(stub *s) { s->d.din.u = NAN; }
static void dw_inf(stub *s) { s->d.din.w = -INFINITY; }
static void label_open(stub *s) { memset(s->d.par.label, 'z', VI_STRING_SIZE); }
static void b_two(stub *s) { s->d.in.b = 2; }
static void b_minus(stub *s) { s->d.in.b = -1; }
static void n_eight(stub *s) { s->d.par.n = 8; }
static void n_zero(stub *s) { s->d.par.n = 0; }
static void color_three(stub *s) { s->d.par.color = 3; }
static void model_bad(stub *s) { s->d.x[0] = 666.0; }
/* two bad parts: the first (the table's values before the model's own check) is named */
static void k_zero_model_bad(stub *s) { s->d.par.k = 0.0, s->d.x[0] = 666.0; }
static void n_eight_model_bad(stub *s) { s->d.par.n = 8, s->d.x[0] = 666.0; }
static void color_model_bad(stub *s) { s->d.par.color = 4, s->d.x[0] = 666.0; }
static void model_mute(stub *s) { s->d.x[0] = 777.0; }

Test(fmi_layer, the_table_values_and_the_model_fields_of_a_state_are_checked)
{
    record r = {0};
    refused_values(&r, k_nan, "k = nan is not finite");
    refused_values(&r, k_zero, "k = 0 is outside its range 0 < k <= 10 (a rate)");
    refused_values(&r, k_above, "k = 10.5 is outside its range");
    refused_values(&r, u_inf, "u = inf is not finite");
    refused_values(&r, du_nan, "the derivative of u = nan is not finite");
    refused_values(&r, dw_inf, "the derivative of w = -inf is not finite");
    refused_values(&r, label_open, "label is not a terminated string");
    refused_values(&r, b_two, "b = 2 is not a Boolean");
    refused_values(&r, b_minus, "b = -1 is not a Boolean");
    refused_values(&r, n_eight, "n = 8 is outside its range 1 <= n < 8");
    refused_values(&r, n_zero, "n = 0 is outside its range");
    refused_values(&r, color_three, "color = 3 is not one of its items red=2, blue=5, white=2147483647, black=-2147483648");
    refused_values(&r, model_bad, "x[0] = 666 is bad");
    refused_values(&r, model_mute, "invalid field");
    refused_values(&r, k_zero_model_bad, "k = 0 is outside its range");
    refused_values(&r, n_eight_model_bad, "n = 8 is outside its range");
    refused_values(&r, color_model_bad, "color = 4 is not one of its items");
    /* values at their bounds are fine */
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    s->d.par.k = 10.0, s->d.par.n = 7, s->d.in.b = 1, s->d.par.color = 5;
    void *st = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &st) == VI_STATUS_OK);
    cr_assert(vi_fmi_set_fmu_state(c, "set", st) == VI_STATUS_OK, "%s", r.text);
    s->d.par.n = 1;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &st) == VI_STATUS_OK);
    cr_assert(vi_fmi_set_fmu_state(c, "set", st) == VI_STATUS_OK, "%s", r.text);
    vi_fmi_free_fmu_state(c, "free", &st);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, serialization_round_trip_and_its_size_checks)
{
    record r = {0};
    vi_callbacks cb = {.alloc = counting_alloc, .free = counting_free, .logger = any_logger, .env = &r};
    n_alloc = n_free = 0, fail_at = 0;
    vi_fmi_instance *c = vi_fmi_instantiate(&face, &cb, "inst", "x", VI_KIND_CS, VI_GUID, NULL, "", 0);
    cr_assert(c);
    stub *s = c->model;
    s->d.par.k = 4.0;
    void *st = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &st) == VI_STATUS_OK);
    unsigned char bytes[SAVED_SIZE + 8];
    char want[200];
    snprintf(want, sizeof want, "ser: need a buffer of %zu bytes (got %zu)", SAVED_SIZE, SAVED_SIZE - 1);
    REFUSED(r, vi_fmi_serialize(c, "ser", st, bytes, SAVED_SIZE - 1), want);
    REFUSED(r, vi_fmi_serialize(c, "ser", st, NULL, SAVED_SIZE), "ser: need a buffer of");
    cr_assert(vi_fmi_serialize(c, "ser", st, bytes, SAVED_SIZE) == VI_STATUS_OK);
    cr_assert(memcmp(bytes, st, SAVED_SIZE) == 0);
    cr_assert(vi_fmi_serialize(c, "ser", st, bytes, SAVED_SIZE + 8) == VI_STATUS_OK);
    REFUSED(r, vi_fmi_fmu_state_size(c, "size", st, NULL), "size: size is NULL");
    void *back = NULL;
    REFUSED(r, vi_fmi_deserialize(c, "des", NULL, SAVED_SIZE, &back), "des: NULL argument");
    REFUSED(r, vi_fmi_deserialize(c, "des", bytes, SAVED_SIZE, NULL), "des: NULL argument");
    int allocated = n_alloc; /* sizes beyond the bounds: refused before anything is allocated or copied */
    snprintf(want, sizeof want, "des: invalid FMU state: size %zu bytes: a state of this build of CoreTest has %zu",
             SAVED_SIZE + 1, SAVED_SIZE);
    REFUSED(r, vi_fmi_deserialize(c, "des", bytes, SAVED_SIZE + 1, &back), want);
    snprintf(want, sizeof want, "des: invalid FMU state: size %zu bytes", sizeof(header) - 1);
    REFUSED(r, vi_fmi_deserialize(c, "des", bytes, sizeof(header) - 1, &back), want);
    cr_assert(n_alloc == allocated, "%d blocks allocated for a size beyond the bounds", n_alloc - allocated);
    int freed = n_free;
    snprintf(want, sizeof want, "des: invalid FMU state: size %zu bytes", SAVED_SIZE - 1);
    REFUSED(r, vi_fmi_deserialize(c, "des", bytes, SAVED_SIZE - 1, &back), want);
    snprintf(want, sizeof want, "des: invalid FMU state: size %zu bytes", sizeof(header));
    REFUSED(r, vi_fmi_deserialize(c, "des", bytes, sizeof(header), &back), want);
    cr_assert(back == NULL && n_alloc - allocated == 2 && n_free - freed == 2, "a refused state leaked");
    cr_assert(vi_fmi_deserialize(c, "des", bytes, SAVED_SIZE, &back) == VI_STATUS_OK && back != NULL);
    cr_assert(memcmp(back, st, SAVED_SIZE) == 0);
    /* into a state the importer has: overwritten in place */
    s->d.par.k = 6.0;
    void *other = NULL;
    cr_assert(vi_fmi_get_fmu_state(c, "get", &other) == VI_STATUS_OK);
    void *kept = other;
    allocated = n_alloc, freed = n_free;
    cr_assert(vi_fmi_deserialize(c, "des", bytes, SAVED_SIZE, &other) == VI_STATUS_OK && other == kept);
    cr_assert(memcmp(other, st, SAVED_SIZE) == 0 && n_alloc - allocated == 1 && n_free - freed == 1);
    cr_assert(vi_fmi_set_fmu_state(c, "set", other) == VI_STATUS_OK && s->d.par.k == 4.0);
    fail_at = n_alloc + 1;
    void *oom = NULL;
    REFUSED(r, vi_fmi_deserialize(c, "des", bytes, SAVED_SIZE, &oom), "des: out of memory");
    fail_at = n_alloc + 1;
    REFUSED(r, vi_fmi_get_fmu_state(c, "get", &oom), "get: out of memory");
    fail_at = 0;
    vi_fmi_free_fmu_state(c, "free", &st);
    vi_fmi_free_fmu_state(c, "free", &back);
    vi_fmi_free_fmu_state(c, "free", &other);
    vi_fmi_free(c, "free");
    cr_assert(n_alloc - 2 == n_free, "%d allocated, %d freed", n_alloc, n_free);
}

/* ---- Co-Simulation steps ---- */

static vi_fmi_instance *running_cs(record *r, const vi_face *f, double start, int stop_defined, double stop)
{
    vi_fmi_instance *c = make_with(f, r, VI_KIND_CS, 0);
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, start, stop_defined, stop) == VI_STATUS_OK, "%s", r->text);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    return c;
}

Test(fmi_layer, a_step_needs_a_finite_positive_size)
{
    record r = {0};
    vi_fmi_instance *c = running_cs(&r, &face, 0.0, 0, 0.0);
    const double bad[] = {0.0, -1e-3, NAN, INFINITY};
    for (int i = 0; i < 4; i++)
        REFUSED(r, vi_fmi_do_step(c, "step", 0.0, bad[i]), "step: the communication step size must be finite and positive");
    REFUSED(r, vi_fmi_do_step(c, "step", NAN, 1e-3), "step: currentCommunicationPoint nan is not finite");
    REFUSED(r, vi_fmi_do_step(c, "step", -INFINITY, 1e-3), "step: currentCommunicationPoint -inf is not finite");
    cr_assert(c->state == VI_ST_STEP_COMPLETE && ((stub *)c->model)->d.t == 0.0);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, the_communication_point_may_differ_from_the_time_by_1000_units_of_its_resolution)
{
    record r = {0};
    const double t0[] = {0.0, 0.5, 4.0, -4.0};
    for (int i = 0; i < 4; i++) {
        double unit = DBL_EPSILON * (fabs(t0[i]) > 1.0 ? fabs(t0[i]) : 1.0);
        vi_fmi_instance *c = running_cs(&r, &face, t0[i], 0, 0.0);
        stub *s = c->model;
        REFUSED(r, vi_fmi_do_step(c, "step", t0[i] + 1001 * unit, 1.0), "step: currentCommunicationPoint",
                "does not match the FMU's time");
        REFUSED(r, vi_fmi_do_step(c, "step", t0[i] - 1001 * unit, 1.0), "does not match");
        cr_assert(s->d.t == t0[i]);
        cr_assert(vi_fmi_do_step(c, "step", t0[i] + 1000 * unit, 1.0) == VI_STATUS_OK, "t0 %g: %s", t0[i], r.text);
        cr_assert(s->d.t == t0[i] + 1000 * unit + 1.0);
        vi_fmi_free(c, "free");
        c = running_cs(&r, &face, t0[i], 0, 0.0);
        cr_assert(vi_fmi_do_step(c, "step", t0[i] - 1000 * unit, 1.0) == VI_STATUS_OK, "t0 %g: %s", t0[i], r.text);
        vi_fmi_free(c, "free");
    }
}

/* Between 1 s and 1.01 s the resolution is |t| DBL_EPSILON, not DBL_EPSILON: at t = 1.005 s the
 * point may differ by 1000 * 1.005 ulps of 1 s. */
Test(fmi_layer, the_time_resolution_grows_with_t_just_above_1_s)
{
    record r = {0};
    vi_fmi_instance *c = running_cs(&r, &face, 1.005, 0, 0.0);
    cr_assert(vi_fmi_do_step(c, "step", 1.005 + 1003 * DBL_EPSILON, 1.0) == VI_STATUS_OK, "%s", r.text);
    vi_fmi_free(c, "free");
    c = running_cs(&r, &face, 1.005, 0, 0.0);
    REFUSED(r, vi_fmi_do_step(c, "step", 1.005 + 1006 * DBL_EPSILON, 1.0), "does not match the FMU's time");
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_step_advances_time_by_at_least_16_units_of_its_resolution)
{
    record r = {0};
    const double t0[] = {0.0, 0.5, 4.0, -4.0};
    for (int i = 0; i < 4; i++) {
        double unit = DBL_EPSILON * (fabs(t0[i]) > 1.0 ? fabs(t0[i]) : 1.0);
        vi_fmi_instance *c = running_cs(&r, &face, t0[i], 0, 0.0);
        stub *s = c->model;
        double h = 16 * unit;
        /* refused: a step that ends 15 units after the time */
        REFUSED(r, vi_fmi_do_step(c, "step", t0[i], 15 * unit), "step: a step of", "is too short to advance time",
                "(16 units of the time resolution there); nothing was done");
        cr_assert(s->d.t == t0[i]);
        char want[120];
        snprintf(want, sizeof want, "use at least %g s", h);
        REFUSED(r, vi_fmi_do_step(c, "step", t0[i], nextafter(t0[i] + h, -INFINITY) - t0[i]), want);
        cr_assert(vi_fmi_do_step(c, "step", t0[i], h) == VI_STATUS_OK, "t0 %g: %s", t0[i], r.text);
        cr_assert(s->d.t == t0[i] + h);
        vi_fmi_free(c, "free");
    }
    /* the communication point behind the time by 8 units: the step is counted from the time */
    vi_fmi_instance *c = running_cs(&r, &face, 0.0, 0, 0.0);
    REFUSED(r, vi_fmi_do_step(c, "step", -8 * DBL_EPSILON, 23 * DBL_EPSILON), "is too short");
    cr_assert(vi_fmi_do_step(c, "step", -8 * DBL_EPSILON, 24 * DBL_EPSILON) == VI_STATUS_OK, "%s", r.text);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_step_may_pass_the_stop_time_by_1000_units_of_the_resolution)
{
    record r = {0};
    const double stop[] = {1.0, 0.25};
    for (int i = 0; i < 2; i++) {
        vi_fmi_instance *c = running_cs(&r, &face, 0.0, 1, stop[i]);
        REFUSED(r, vi_fmi_do_step(c, "step", 0.0, stop[i] + 1001 * DBL_EPSILON), "step: the step to",
                "passes the stop time");
        cr_assert(vi_fmi_do_step(c, "step", 0.0, stop[i] + 1000 * DBL_EPSILON) == VI_STATUS_OK, "%s", r.text);
        vi_fmi_free(c, "free");
    }
    /* with no stop time, any end */
    vi_fmi_instance *c = running_cs(&r, &face, 0.0, 0, 0.0);
    c->stop_time = 0.5; /* not defined: ignored */
    cr_assert(vi_fmi_do_step(c, "step", 0.0, 1.0) == VI_STATUS_OK);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, what_the_model_answers_to_a_step)
{
    record r = {0};
    vi_fmi_instance *c = running_cs(&r, &face, 0.0, 0, 0.0);
    stub *s = c->model;
    s->advance_rc = VI_FMU_ERROR;
    REFUSED(r, vi_fmi_do_step(c, "step", 0.0, 0.5), "step: the stub says no");
    cr_assert(c->state == VI_ST_ERROR);
    vi_fmi_free(c, "free");

    /* a discard: stopped early, the message logged whatever is enabled */
    c = running_cs(&r, &face, 0.0, 0, 0.0);
    s = c->model;
    s->advance_rc = VI_FMU_DISCARD, s->advance_to = 0.25;
    int before = r.count;
    cr_assert(vi_fmi_do_step(c, "step", 0.0, 0.5) == VI_STATUS_DISCARD);
    cr_assert(r.count == before + 1 && strcmp(r.category, "logStatusDiscard") == 0);
    LAST_IS(r, VI_STATUS_DISCARD, "step: the stub says no");
    cr_assert(c->state == VI_ST_STEP_FAILED && vi_fmi_time(c) == 0.25);
    vi_fmi_free(c, "free");

    /* OK at another time than the end: an error of the model */
    c = running_cs(&r, &face, 0.0, 0, 0.0);
    s = c->model;
    s->advance_to = 0.25;
    REFUSED(r, vi_fmi_do_step(c, "step", 0.0, 0.5), "step: the model stopped at t = 0.25 s instead of  0.5 s");
    cr_assert(c->state == VI_ST_ERROR);
    vi_fmi_free(c, "free");

    /* an event where none may be reported */
    c = running_cs(&r, &face, 0.0, 0, 0.0);
    s = c->model;
    s->advance_rc = VI_FMU_EVENT, s->advance_to = 0.25;
    REFUSED(r, vi_fmi_do_step(c, "step", 0.0, 0.5),
            "step: the model stopped at t = 0.25 s instead of after the start and at most 0.5 s");
    cr_assert(c->state == VI_ST_ERROR);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_step_to_the_first_event_ends_inside_the_step)
{
    record r = {0};
    const double at[] = {0.25, 0.5}, bad_at[] = {1.0, 0.5000000001, 0.75};
    for (int i = 0; i < 2; i++) {
        vi_fmi_instance *c = running_cs(&r, &face3, 1.0, 0, 0.0);
        stub *s = c->model;
        s->advance_rc = VI_FMU_EVENT, s->advance_to = 1.0 + at[i];
        int event = -1;
        cr_assert(vi_fmi_do_step_to_event(c, "step", 1.0, 0.5, &event) == VI_STATUS_OK, "%s", r.text);
        cr_assert(event == 1 && vi_fmi_time(c) == 1.0 + at[i] && c->state == VI_ST_STEP_COMPLETE);
        vi_fmi_free(c, "free");
    }
    for (int i = 0; i < 3; i++) {
        vi_fmi_instance *c = running_cs(&r, &face3, 0.5, 0, 0.0);
        stub *s = c->model;
        s->advance_rc = VI_FMU_EVENT, s->advance_to = bad_at[i] == 0.5 ? 0.5 : bad_at[i] + 0.5;
        int event = -1;
        cr_assert(vi_fmi_do_step_to_event(c, "step", 0.5, 0.5, &event) == VI_STATUS_ERROR, "event at %g",
                  s->advance_to);
        LAST_IS(r, VI_STATUS_ERROR, "step: the model stopped at t =", "instead of after the start and at most 1 s");
        cr_assert(event == 0 && c->state == VI_ST_ERROR);
        vi_fmi_free(c, "free");
    }
    /* no event: to the end; a plain step never asks for events */
    vi_fmi_instance *c = running_cs(&r, &face3, 0.0, 0, 0.0);
    int event = -1, calls = to_event_calls;
    cr_assert(vi_fmi_do_step_to_event(c, "step", 0.0, 0.5, &event) == VI_STATUS_OK && event == 0);
    cr_assert(to_event_calls == calls + 1);
    cr_assert(vi_fmi_do_step_to_event(c, "step", 0.5, 0.5, NULL) == VI_STATUS_OK && vi_fmi_time(c) == 1.0);
    cr_assert(vi_fmi_do_step(c, "step", 1.0, 0.5) == VI_STATUS_OK && to_event_calls == calls + 2, "%d",
              to_event_calls - calls);
    vi_fmi_free(c, "free");
}

/* ---- Model Exchange ---- */

static vi_fmi_instance *me_in_event_mode(record *r, const vi_face *f, double start)
{
    vi_fmi_instance *c = make_with(f, r, VI_KIND_ME, 0);
    cr_assert(vi_fmi_setup_experiment(c, "setup", 0, 0.0, start, 0, 0.0) == VI_STATUS_OK);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    cr_assert(c->state == VI_ST_EVENT);
    return c;
}

Test(fmi_layer, model_exchange_calls_on_a_co_simulation_instance_are_refused)
{
    record r = {0};
    vi_fmi_instance *c = running_cs(&r, &face3, 0.0, 0, 0.0);
    double x[2];
    vi_fmu_event ev;
    int a, b;
    c->state = VI_ST_EVENT;
    REFUSED(r, vi_fmi_new_discrete_states(c, "nds", &ev), "nds: a Model Exchange function; this instance is a Co-Simulation one");
    REFUSED(r, vi_fmi_enter_continuous_mode(c, "ecm"), "ecm: a Model Exchange function");
    REFUSED(r, vi_fmi_set_time(c, "st", 0.0), "st: a Model Exchange function");
    REFUSED(r, vi_fmi_get_derivatives(c, "gd", x, 2), "gd: a Model Exchange function");
    REFUSED(r, vi_fmi_get_states(c, "gs", x, 2), "gs: a Model Exchange function");
    REFUSED(r, vi_fmi_get_event_indicators(c, "gi", x, 1), "gi: a Model Exchange function");
    REFUSED(r, vi_fmi_get_nominals(c, "gn", x, 2), "gn: a Model Exchange function");
    cr_assert(vi_fmi_enter_step_mode(c, "esm") == VI_STATUS_OK && c->state == VI_ST_STEP_COMPLETE);
    REFUSED(r, vi_fmi_set_states(c, "ss", x, 2), "ss: not allowed in state 'step complete'");
    c->state = VI_ST_CONTINUOUS;
    REFUSED(r, vi_fmi_completed_step(c, "cs", &a, &b), "cs: a Model Exchange function");
    REFUSED(r, vi_fmi_set_states(c, "ss", x, 2), "ss: a Model Exchange function");
    vi_fmi_free(c, "free");
    c = me_in_event_mode(&r, &face3, 0.0);
    REFUSED(r, vi_fmi_enter_step_mode(c, "esm"), "esm: only for Co-Simulation");
    cr_assert(c->state == VI_ST_EVENT);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, co_simulation_enters_event_mode_from_step_mode_only_with_a_face_that_has_it)
{
    record r = {0};
    vi_fmi_instance *c = running_cs(&r, &face, 0.0, 0, 0.0);
    REFUSED(r, vi_fmi_enter_event_mode(c, "eem"), "eem: not allowed in state 'step complete'");
    cr_assert(c->state == VI_ST_STEP_COMPLETE);
    vi_fmi_free(c, "free");
    c = running_cs(&r, &face3, 0.0, 0, 0.0);
    cr_assert(vi_fmi_enter_event_mode(c, "eem") == VI_STATUS_OK && c->state == VI_ST_EVENT);
    REFUSED(r, vi_fmi_enter_event_mode(c, "eem"), "eem: not allowed in state 'event mode'");
    cr_assert(c->state == VI_ST_EVENT);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, event_mode_keeps_the_pass_count_of_an_event_iteration_and_commits_the_time)
{
    record r = {0};
    vi_fmi_instance *c = me_in_event_mode(&r, &face, 0.0);
    stub *s = c->model;
    vi_fmu_event ev;
    s->ev = (vi_fmu_event){.another_pass = 1};
    for (int i = 1; i <= 3; i++) cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK && c->event_passes == i);
    cr_assert(vi_fmi_enter_event_mode(c, "eem") == VI_STATUS_OK && c->event_passes == 3,
              "re-entering event mode during an event iteration restarted its count");
    cr_assert(vi_fmi_enter_continuous_mode(c, "ecm") == VI_STATUS_OK && c->event_passes == 0 &&
              c->state == VI_ST_CONTINUOUS && s->continuous_calls == 1);
    cr_assert(vi_fmi_set_time(c, "st", 0.5) == VI_STATUS_OK);
    c->event_passes = 4;
    cr_assert(vi_fmi_enter_event_mode(c, "eem") == VI_STATUS_OK && c->event_passes == 0 && c->state == VI_ST_EVENT);
    cr_assert(c->t_committed == 0.5);
    REFUSED(r, vi_fmi_set_time(c, "st", 0.25), "st: t = 0.25 s lies before the last event or completed integrator step (0.5 s)");
    vi_fmi_free(c, "free");
}

Test(fmi_layer, the_event_iteration_stops_after_100_passes_in_a_row_asking_for_another)
{
    record r = {0};
    vi_fmi_instance *c = me_in_event_mode(&r, &face, 2.0);
    stub *s = c->model;
    vi_fmu_event ev;
    s->ev = (vi_fmu_event){.another_pass = 1};
    for (int i = 1; i < VI_MAX_EVENT_PASSES; i++)
        cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK, "pass %d", i);
    cr_assert(c->event_passes == 99 && c->state == VI_ST_EVENT);
    REFUSED(r, vi_fmi_new_discrete_states(c, "nds", &ev),
            "nds: the discrete states do not settle at t = 2 s: 100 passes of the event iteration in a row");
    cr_assert(c->state == VI_ST_ERROR);
    vi_fmi_free(c, "free");
    /* a pass that settles restarts the count */
    c = me_in_event_mode(&r, &face, 2.0);
    s = c->model;
    s->ev = (vi_fmu_event){.another_pass = 1};
    for (int i = 1; i < VI_MAX_EVENT_PASSES; i++) cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK);
    s->ev.another_pass = 0;
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK && c->event_passes == 0);
    s->ev.another_pass = 1;
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK && c->event_passes == 1);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_pass_of_the_event_iteration_reports_what_the_model_filled_in)
{
    record r = {0};
    vi_fmi_instance *c = me_in_event_mode(&r, &face, 1.0);
    stub *s = c->model;
    vi_fmu_event ev;
    REFUSED(r, vi_fmi_new_discrete_states(c, "nds", NULL), "nds: fmi2EventInfo is NULL");
    cr_assert(s->event_calls == 0);
    s->ev = (vi_fmu_event){.states_changed = 1, .nominals_changed = 1, .next_time_defined = 1, .next_time = 1.5};
    memset(&ev, 0xff, sizeof ev);
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK);
    cr_assert(ev.another_pass == 0 && ev.terminate == 0 && ev.states_changed == 1 && ev.nominals_changed == 1 &&
              ev.next_time_defined == 1 && ev.next_time == 1.5);
    /* a time event not after now is none */
    s->ev.next_time = 1.0;
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK && ev.next_time_defined == 0);
    s->ev.next_time = 0.5;
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK && ev.next_time_defined == 0);
    s->ev.next_time = nextafter(1.0, 2.0);
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK && ev.next_time_defined == 1);
    /* the model asks to terminate (the run ends before the time asked for: a result not right): its reason
     * is logged as a warning though warnings are off, and the call returns a warning; the next call starts
     * afresh */
    s->ev = (vi_fmu_event){.terminate = 1};
    int before = r.count;
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_WARNING && ev.terminate == 1);
    cr_assert(r.count == before + 1 && strcmp(r.category, "logStatusWarning") == 0);
    LAST_IS(r, VI_STATUS_WARNING, "nds: terminateSimulation: the stub says no");
    cr_assert(strcmp(r.text, "nds: terminateSimulation: the stub says no") == 0, "'%s'", r.text);
    s->ev = (vi_fmu_event){0};
    before = r.count;
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK && r.count == before);
    /* the pass commits its time */
    c->t_committed = 0.0;
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_OK && c->t_committed == 1.0);
    s->fail_event = 1;
    REFUSED(r, vi_fmi_new_discrete_states(c, "nds", &ev), "nds: the stub says no");
    cr_assert(c->state == VI_ST_ERROR);
    vi_fmi_free(c, "free");
    /* without a logger, no terminate message; the status still says that the run ends early */
    vi_callbacks cb = {.alloc = calloc, .free = free, .logger = NULL, .env = &r};
    c = vi_fmi_instantiate(&face, &cb, "inst", "x", VI_KIND_ME, VI_GUID, NULL, "", 0);
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    ((stub *)c->model)->ev = (vi_fmu_event){.terminate = 1};
    before = r.count;
    cr_assert(vi_fmi_new_discrete_states(c, "nds", &ev) == VI_STATUS_WARNING && r.count == before);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_completed_integrator_step_commits_the_time_and_passes_the_models_request)
{
    record r = {0};
    vi_fmi_instance *c = me_in_event_mode(&r, &face, 0.0);
    stub *s = c->model;
    cr_assert(vi_fmi_enter_continuous_mode(c, "ecm") == VI_STATUS_OK);
    int enter = -1, term = -1;
    REFUSED(r, vi_fmi_completed_step(c, "cis", NULL, &term), "cis: NULL argument");
    REFUSED(r, vi_fmi_completed_step(c, "cis", &enter, NULL), "cis: NULL argument");
    cr_assert(vi_fmi_set_time(c, "st", 0.75) == VI_STATUS_OK);
    s->completed = 1;
    term = 5;
    cr_assert(vi_fmi_completed_step(c, "cis", &enter, &term) == VI_STATUS_OK && enter == 1 && term == 0);
    cr_assert(c->t_committed == 0.75);
    s->completed = 0;
    cr_assert(vi_fmi_completed_step(c, "cis", &enter, &term) == VI_STATUS_OK && enter == 0);
    s->completed = 3;
    cr_assert(vi_fmi_completed_step(c, "cis", &enter, &term) == VI_STATUS_OK && enter == 1);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, time_goes_forward_in_continuous_time_mode_and_stays_in_event_mode)
{
    record r = {0};
    vi_fmi_instance *c = me_in_event_mode(&r, &face, 1.0);
    stub *s = c->model;
    REFUSED(r, vi_fmi_set_time(c, "st", NAN), "st: time nan is not finite");
    REFUSED(r, vi_fmi_set_time(c, "st", INFINITY), "st: time inf is not finite");
    REFUSED(r, vi_fmi_set_time(c, "st", 2.0), "st: t = 2 s in event mode, whose time is 1 s");
    cr_assert(vi_fmi_set_time(c, "st", 1.0) == VI_STATUS_OK && s->d.t == 1.0);
    cr_assert(vi_fmi_enter_continuous_mode(c, "ecm") == VI_STATUS_OK);
    REFUSED(r, vi_fmi_set_time(c, "st", nextafter(1.0, 0.0)), "lies before the last event");
    cr_assert(vi_fmi_set_time(c, "st", 1.0) == VI_STATUS_OK);
    cr_assert(vi_fmi_set_time(c, "st", 3.0) == VI_STATUS_OK && s->d.t == 3.0);
    cr_assert(vi_fmi_set_time(c, "st", 2.0) == VI_STATUS_OK && s->d.t == 2.0, "back within the step");
    vi_fmi_free(c, "free");
}

Test(fmi_layer, model_exchange_arrays_have_the_models_lengths_and_finite_values)
{
    record r = {0};
    vi_fmi_instance *c = me_in_event_mode(&r, &face, 0.0);
    stub *s = c->model;
    cr_assert(vi_fmi_enter_continuous_mode(c, "ecm") == VI_STATUS_OK);
    double x[3] = {0, 0, 0};
    REFUSED(r, vi_fmi_set_states(c, "ss", x, 1), "ss: 1 states given; CoreTest has 2");
    REFUSED(r, vi_fmi_set_states(c, "ss", x, 3), "ss: 3 states given; CoreTest has 2");
    REFUSED(r, vi_fmi_set_states(c, "ss", NULL, 2), "ss: the array is NULL");
    REFUSED(r, vi_fmi_get_states(c, "gs", x, 1), "gs: 1 states given");
    REFUSED(r, vi_fmi_get_derivatives(c, "gd", x, 3), "gd: 3 derivatives given; CoreTest has 2");
    REFUSED(r, vi_fmi_get_derivatives(c, "gd", NULL, 2), "gd: the array is NULL");
    REFUSED(r, vi_fmi_get_event_indicators(c, "gi", x, 2), "gi: 2 event indicators given; CoreTest has 1");
    REFUSED(r, vi_fmi_get_event_indicators(c, "gi", x, 0), "gi: 0 event indicators given; CoreTest has 1");
    REFUSED(r, vi_fmi_get_event_indicators(c, "gi", NULL, 1), "gi: the array is NULL");
    REFUSED(r, vi_fmi_get_nominals(c, "gn", x, 1), "gn: 1 nominals given");
    REFUSED(r, vi_fmi_get_nominals(c, "gn", NULL, 2), "gn: the array is NULL");
    double bad[2] = {1.0, NAN};
    REFUSED(r, vi_fmi_set_states(c, "ss", bad, 2), "ss: state 1 (q) = nan is not finite; nothing was set");
    bad[0] = -INFINITY, bad[1] = 0.0;
    REFUSED(r, vi_fmi_set_states(c, "ss", bad, 2), "ss: state 0 (p) = -inf is not finite");
    cr_assert(s->d.x[0] == 0.5 && s->d.x[1] == -0.25);
    double good[3] = {2.0, 3.0, NAN}; /* only the first n elements are read */
    cr_assert(vi_fmi_set_states(c, "ss", good, 2) == VI_STATUS_OK && s->d.x[0] == 2.0 && s->d.x[1] == 3.0);
    cr_assert(vi_fmi_get_states(c, "gs", x, 2) == VI_STATUS_OK && x[0] == 2.0 && x[1] == 3.0);
    cr_assert(vi_fmi_get_derivatives(c, "gd", x, 2) == VI_STATUS_OK && x[0] == 3.0 && x[1] == -2.0);
    cr_assert(vi_fmi_get_event_indicators(c, "gi", x, 1) == VI_STATUS_OK && x[0] == 1.0);
    cr_assert(vi_fmi_get_nominals(c, "gn", x, 2) == VI_STATUS_OK && x[0] == 1.0 && x[1] == 2.0);
    s->nan_outputs = 1;
    REFUSED(r, vi_fmi_get_states(c, "gs", x, 2), "gs: element 1 = nan has no value in state 'continuous-time mode'");
    REFUSED(r, vi_fmi_get_derivatives(c, "gd", x, 2), "gd: element 1 = nan has no value");
    REFUSED(r, vi_fmi_get_event_indicators(c, "gi", x, 1), "gi: element 0 = nan has no value");
    vi_fmi_free(c, "free");
}

Test(fmi_layer, states_and_indicators_in_initialization_mode_come_from_the_prepared_model)
{
    record r = {0};
    vi_fmi_instance *c = make_with(&face, &r, VI_KIND_ME, 0);
    stub *s = c->model;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK);
    double x[2];
    cr_assert(vi_fmi_get_states(c, "gs", x, 2) == VI_STATUS_OK && s->prepare_calls == 1);
    cr_assert(vi_fmi_get_event_indicators(c, "gi", x, 1) == VI_STATUS_OK && s->prepare_calls == 2);
    unsigned dd_unk = VI_VR_der_q, dd_kn = VI_VR_p;
    double dd_seed = 1.0, dd_out = 0.0;
    cr_assert(vi_fmi_directional_derivative(c, "dd", &dd_unk, 1, &dd_kn, 1, &dd_seed, &dd_out) == VI_STATUS_OK);
    cr_assert(dd_out == -1.0 && s->prepare_calls == 3, "%g, prepared %d times", dd_out, s->prepare_calls);
    s->fail_prepare = 1;
    REFUSED(r, vi_fmi_get_states(c, "gs", x, 2), "gs: the stub says no");
    REFUSED(r, vi_fmi_get_event_indicators(c, "gi", x, 1), "gi: the stub says no");
    unsigned unk = VI_VR_der_p, kn = VI_VR_q;
    double seed = 1.0, out = 0.0;
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", &unk, 1, &kn, 1, &seed, &out), "dd: the stub says no");
    s->fail_prepare = 0;
    cr_assert(vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    s->fail_prepare = 1; /* after initialization: not prepared again */
    cr_assert(vi_fmi_get_states(c, "gs", x, 2) == VI_STATUS_OK);
    cr_assert(vi_fmi_get_event_indicators(c, "gi", x, 1) == VI_STATUS_OK);
    cr_assert(vi_fmi_directional_derivative(c, "dd", &unk, 1, &kn, 1, &seed, &out) == VI_STATUS_OK && out == 1.0);
    cr_assert(s->prepare_calls == 6, "%d", s->prepare_calls);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, directional_derivatives_check_every_array_and_reference)
{
    record r = {0};
    vi_fmi_instance *c = running_cs(&r, &face, 0.0, 0, 0.0);
    unsigned unk[2] = {VI_VR_der_p, VI_VR_der_q}, kn[2] = {VI_VR_q, VI_VR_p};
    double seed[2] = {1.0, 1.0}, out[2] = {0, 0};
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, kn, 2, seed, out),
            "dd: not provided (providesDirectionalDerivative=false in Co-Simulation)");
    vi_fmi_free(c, "free");
    c = me_in_event_mode(&r, &face, 0.0);
    stub *s = c->model;
    s->d.par.k = 4.0;
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", NULL, 2, kn, 2, seed, out), "dd: NULL array");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, kn, 2, seed, NULL), "dd: NULL array");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, NULL, 2, seed, out), "dd: NULL array");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, kn, 2, NULL, out), "dd: NULL array");
    cr_assert(vi_fmi_directional_derivative(c, "dd", NULL, 0, NULL, 0, NULL, NULL) == VI_STATUS_OK);
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 1, NULL, 1, seed, out), "dd: NULL array");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 1, kn, 1, NULL, out), "dd: NULL array");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", NULL, 1, kn, 1, seed, out), "dd: NULL array");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 1, kn, 1, seed, NULL), "dd: NULL array");
    cr_assert(vi_fmi_directional_derivative(c, "dd", unk, 2, NULL, 0, NULL, out) == VI_STATUS_OK);
    cr_assert(out[0] == 0.0 && out[1] == 0.0);
    cr_assert(vi_fmi_directional_derivative(c, "dd", NULL, 0, kn, 2, seed, NULL) == VI_STATUS_OK);
    unsigned bad_unk[2] = {VI_VR_der_p, VI_VR_k}, bad_kn[2] = {VI_VR_q, VI_VR_y}, param[1] = {VI_VR_k};
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", bad_unk, 2, kn, 2, seed, out),
            "dd: unknown k is neither a state derivative nor an output");
    unsigned in_unk[1] = {VI_VR_u};
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", in_unk, 1, kn, 2, seed, out), "dd: unknown u is neither");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, bad_kn, 2, seed, out),
            "dd: known y is neither a state nor an input");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, param, 1, seed, out), "dd: known k is neither");
    unsigned beyond[1] = {VI_NVARS};
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", beyond, 1, kn, 2, seed, out), "dd: unknown value reference 12");
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, beyond, 1, seed, out), "dd: unknown value reference 12");
    unsigned vb[1] = {VI_VR_b};
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", vb, 1, kn, 2, seed, out), "(b) is of type Boolean");
    double nan_seed[2] = {1.0, NAN};
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, kn, 2, nan_seed, out), "dd: the seed of p is not finite");
    /* J dknown: d(der_p)/dq = 1, d(der_q)/dp = -k; dy/du = 2 */
    double seed2[2] = {3.0, 0.5};
    cr_assert(vi_fmi_directional_derivative(c, "dd", unk, 2, kn, 2, seed2, out) == VI_STATUS_OK, "%s", r.text);
    cr_assert(out[0] == 3.0 && out[1] == -2.0, "%g %g", out[0], out[1]);
    unsigned vy = VI_VR_y, vu = VI_VR_u;
    cr_assert(vi_fmi_directional_derivative(c, "dd", &vy, 1, &vu, 1, seed2, out) == VI_STATUS_OK && out[0] == 6.0);
    s->fail_dd = 1;
    REFUSED(r, vi_fmi_directional_derivative(c, "dd", unk, 2, kn, 2, seed2, out), "dd: the stub says no");
    vi_fmi_free(c, "free");
}

/* An importer whose allocateMemory does not zero the block (calloc semantics are required, but the
 * layer does not rely on them): the instance and the model start zeroed all the same. */
Test(fmi_layer, the_instance_and_the_model_start_zeroed_whatever_the_allocator_gives)
{
    record r = {0};
    dirty = 1;
    vi_callbacks cb = {.alloc = counting_alloc, .free = counting_free, .logger = any_logger, .env = &r};
    vi_fmi_instance *c = vi_fmi_instantiate(&face, &cb, "inst", "x", VI_KIND_ME, VI_GUID, NULL, "", 0);
    cr_assert(c);
    cr_assert(c->stop_time_defined == 0 && c->stop_time == 0.0 && c->face_options == 0u && c->initialized == 0 &&
              c->t_committed == 0.0 && c->event_passes == 0, "the instance was not zeroed");
    stub *s = c->model;
    cr_assert(s->prepare_calls == 0 && s->fail_prepare == 0 && s->outputs_calls == 0 && s->d.t == 0.0 &&
              s->completed == 0, "the model's block was not zeroed");
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    vi_fmi_free(c, "free");
}

Test(fmi_layer, setting_a_parameter_or_a_boolean_input_leaves_the_input_derivatives_alone)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    stub *s = c->model;
    cr_assert(vi_fmi_enter_init(c, "enter") == VI_STATUS_OK && vi_fmi_exit_init(c, "exit") == VI_STATUS_OK);
    unsigned vu = VI_VR_u, vw = VI_VR_w, vk = VI_VR_k, vb = VI_VR_b, vc = VI_VR_color;
    int order = 1, one = 1, blue = 5;
    double du = 5.0, x = 2.0;
    cr_assert(vi_fmi_set_input_derivatives(c, "der", &vu, 1, &order, &du) == VI_STATUS_OK);
    cr_assert(vi_fmi_set_input_derivatives(c, "der", &vw, 1, &order, &du) == VI_STATUS_OK);
    s->d.din.b = 7;
    cr_assert(vi_fmi_set(c, "set", &vk, 1, VI_Real, &x, VI_ELEM_DOUBLE) == VI_STATUS_OK); /* k: the first parameter */
    cr_assert(vi_fmi_set(c, "set", &vb, 1, VI_Boolean, &one, VI_ELEM_INT) == VI_STATUS_OK);
    cr_assert(vi_fmi_set(c, "set", &vc, 1, VI_Integer, &blue, VI_ELEM_INT) == VI_STATUS_OK);
    cr_assert(s->d.din.u == 5.0 && s->d.din.w == 5.0 && s->d.din.b == 7, "%g %g %d", s->d.din.u, s->d.din.w, s->d.din.b);
    cr_assert(vi_fmi_set(c, "set", &vw, 1, VI_Real, &x, VI_ELEM_DOUBLE) == VI_STATUS_OK);
    cr_assert(s->d.din.u == 5.0 && s->d.din.w == 0.0, "a Real input's own derivative is reset, no other");
    vi_fmi_free(c, "free");
}

Test(fmi_layer, a_long_message_is_cut_to_1023_characters)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    static char longer[1500];
    memset(longer, 'm', sizeof longer - 1);
    vi_fmi_log(c, VI_STATUS_ERROR, VI_CAT_ERROR, "%s", longer);
    cr_assert(strlen(r.text) == 1023 && r.text[0] == 'm', "%zu", strlen(r.text));
    vi_fmi_free(c, "free");
}

/* A refused value is printed in as few digits as read back as it: 1e23 (whose 16 digits are
 * 9.999999999999999e+22) and the double after 10 (17 digits). */
Test(fmi_layer, a_refused_value_is_printed_in_the_fewest_digits_that_read_back_as_it)
{
    record r = {0};
    vi_fmi_instance *c = make(&r, 0);
    unsigned vk = VI_VR_k;
    const double x[] = {1e23, nextafter(10.0, 11.0), -0.1};
    const char *text[] = {"set: k = 1e+23 is outside its range 0 < k <= 10 (a rate); nothing was set",
                          "set: k = 10.000000000000002 is outside", "set: k = -0.1 is outside"};
    for (int i = 0; i < 3; i++) {
        REFUSED(r, vi_fmi_set(c, "set", &vk, 1, VI_Real, &x[i], VI_ELEM_DOUBLE), text[i]);
    }
    cr_assert(strcmp(r.text, "set: k = -0.1 is outside its range 0 < k <= 10 (a rate); nothing was set") == 0, "%s",
              r.text);
    vi_fmi_free(c, "free");
}
