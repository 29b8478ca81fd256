/* Unit tests of the FMI 2.0 and 3.0 faces of the generic layer (src/fmi/vi_fmi2.c, src/fmi/vi_fmi3.c) on the
 * layer with the stub model of tests/stub_model.h: what each face adds to the layer (the logger's
 * calling convention, the resource URI, instantiation's arguments, the status queries, the results
 * the importer reads back, the size arguments of FMI 3.0, the functions not provided). */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmi3Functions.h"
#include "vi_fmi_layer.h"

#include "stub_model.h"

/* What the importer's logger got: the last message and how many. */
typedef struct {
    int count;
    int status;
    char name[64], category[64], text[2048];
} logbook;

static void logger2(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                    fmi2String message, ...)
{
    logbook *b = env;
    b->count++;
    b->status = (int)status;
    snprintf(b->name, sizeof b->name, "%s", name ? name : "(null)");
    snprintf(b->category, sizeof b->category, "%s", category);
    snprintf(b->text, sizeof b->text, "%s", message); /* as given: the format, '%' escaped */
}
static void logger3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    logbook *b = env;
    b->count++;
    b->status = (int)status;
    snprintf(b->category, sizeof b->category, "%s", category);
    snprintf(b->text, sizeof b->text, "%s", message);
}

#define SAYS(b, st, ...)                                                                                    \
    do {                                                                                                    \
        cr_assert((b).status == (st), "status %d, expected %d: '%s'", (b).status, (int)(st), (b).text);      \
        const char *words_[] = {__VA_ARGS__};                                                               \
        for (size_t w_ = 0; w_ < sizeof words_ / sizeof words_[0]; w_++)                                    \
            cr_assert(strstr((b).text, words_[w_]), "'%s' lacks '%s'", (b).text, words_[w_]);              \
    } while (0)
/* Refused: fmi2Error / fmi3Error (the same value) and one error message more, naming the words. */
#define REFUSED(b, call, ...)                                                                               \
    do {                                                                                                    \
        int before_ = (b).count;                                                                            \
        int st_ = (int)(call);                                                                              \
        cr_assert(st_ == (int)fmi2Error, "%s: status %d", #call, st_);                                      \
        cr_assert((b).count == before_ + 1, "%s: %d messages", #call, (b).count - before_);                 \
        SAYS(b, fmi2Error, __VA_ARGS__);                                                                    \
        cr_assert(strcmp((b).category, "logStatusError") == 0, "category %s", (b).category);               \
    } while (0)

static fmi2CallbackFunctions callbacks(logbook *b)
{
    return (fmi2CallbackFunctions){.logger = logger2, .allocateMemory = counting_alloc, .freeMemory = counting_free,
                                   .componentEnvironment = b};
}
static fmi2Component inst2(logbook *b, fmi2Type type, const char *uri)
{
    fmi2CallbackFunctions cb = callbacks(b);
    return fmi2Instantiate("two", type, VI_GUID, uri, &cb, fmi2False, fmi2False);
}

/* ---- FMI 2.0 ---- */

Test(fmi2, the_logger_gets_the_instance_name_and_the_message_with_percent_escaped)
{
    logbook b = {0};
    fmi2Component c = inst2(&b, fmi2CoSimulation, NULL);
    cr_assert(c);
    fmi2String cats[] = {"100%"};
    cr_assert(fmi2SetDebugLogging(c, fmi2True, 1, cats) == fmi2Error);
    cr_assert(strcmp(b.text, "fmi2SetDebugLogging: unknown log category '100%%'") == 0, "'%s'", b.text);
    cr_assert(strcmp(b.name, "two") == 0 && strcmp(b.category, "logStatusError") == 0 && b.status == fmi2Error);
    fmi2String pct[] = {"%%d%"};
    cr_assert(fmi2SetDebugLogging(c, fmi2True, 1, pct) == fmi2Error);
    cr_assert(strcmp(b.text, "fmi2SetDebugLogging: unknown log category '%%%%d%%'") == 0, "'%s'", b.text);
    fmi2String calls[] = {"logFmi2Call"};
    cr_assert(fmi2SetDebugLogging(c, fmi2True, 1, calls) == fmi2OK);
    cr_assert(fmi2EnterInitializationMode(c) == fmi2OK);
    cr_assert(strcmp(b.text, "fmi2EnterInitializationMode") == 0 && strcmp(b.category, "logFmi2Call") == 0 &&
              b.status == fmi2OK, "'%s' %s", b.text, b.category);
    fmi2FreeInstance(c);
    cr_assert(strcmp(b.text, "fmi2FreeInstance") == 0);
}

/* The resources folder the model got from the URI (NULL: none). */
static const char *folder_of(const char *uri)
{
    logbook b = {0};
    resources_dir = (const char *)1;
    n_alloc = n_free = 0, fail_at = 0;
    fmi2Component c = inst2(&b, fmi2CoSimulation, uri);
    cr_assert(c, "%s: %s", uri, b.text);
    if (resources_dir) /* the path fits its block */
        cr_assert(strlen(resources_dir) + 1 <= block_size(resources_block), "%s: %zu bytes in a block of %zu", uri,
                  strlen(resources_dir) + 1, block_size(resources_block));
    fmi2FreeInstance(c);
    cr_assert(n_alloc == n_free, "%s: %d blocks allocated, %d freed", uri, n_alloc, n_free);
    return resources_dir;
}
#define FOLDER_IS(uri, want)                                                                               \
    do {                                                                                                   \
        const char *got_ = folder_of(uri);                                                                 \
        if (want) cr_assert(got_ && strcmp(got_, (want) ? (want) : "") == 0, "%s -> '%s'", uri, got_ ? got_ : "(none)"); \
        else cr_assert(got_ == NULL, "%s -> '%s'", uri, got_);                                             \
    } while (0)

Test(fmi2, resource_uris_give_the_local_folder)
{
    FOLDER_IS("file:///tmp/res", "/tmp/res");
    FOLDER_IS("file:/tmp/res", "/tmp/res");
    FOLDER_IS("file://localhost/tmp/res", "/tmp/res");
    FOLDER_IS("file:///", "/");
    FOLDER_IS("file:////x", "//x");
    FOLDER_IS("file://localhost//x", "//x");
    FOLDER_IS("file://host/tmp/res", (const char *)NULL);
    FOLDER_IS("file://localhost", (const char *)NULL);
    FOLDER_IS("file://localhostx/tmp", (const char *)NULL);
    FOLDER_IS("file://", (const char *)NULL);
    FOLDER_IS("file:tmp/res", (const char *)NULL);
    FOLDER_IS("file:", (const char *)NULL);
    FOLDER_IS("File:///tmp", (const char *)NULL);
    FOLDER_IS("fil:///tmp", (const char *)NULL);
    FOLDER_IS("http:///tmp", (const char *)NULL);
    FOLDER_IS("", (const char *)NULL);
    FOLDER_IS((const char *)NULL, (const char *)NULL);
}

Test(fmi2, resource_uris_are_percent_decoded_with_either_case)
{
    FOLDER_IS("file:///a%20b", "/a b");
    FOLDER_IS("file:///%41%5a%61%7A%30%39", "/AZaz09");
    FOLDER_IS("file:///%2f%2F%3a", "///:");
    FOLDER_IS("file:///%4a%4A%4f%4F%6a", "/JJOOj");
    FOLDER_IS("file:///x%", "/x%");
    FOLDER_IS("file:///x%4", "/x%4");
    FOLDER_IS("file:///x%zz", "/x%zz");
    FOLDER_IS("file:///x%g0%0g%G0%0G", "/x%g0%0g%G0%0G");
    FOLDER_IS("file:///x%/0%0/%:0%0:", "/x%/0%0/%:0%0:");
    FOLDER_IS("file:///x%`0%0`%@0%0@", "/x%`0%0`%@0%0@");
    FOLDER_IS("file:///%25%32", "/%2");
    FOLDER_IS("file:///%e9", "/\xe9");
    FOLDER_IS("file:///%09%0A", "/\t\n");
    dirty = 1; /* the path is terminated by the layer, not by a zeroed block */
    FOLDER_IS("file:///tmp/a%41", "/tmp/aA");
    FOLDER_IS("file://localhost/x", "/x");
    dirty = 0;
}

Test(fmi2, instantiation_without_memory_for_the_resource_path_goes_on_without_resources)
{
    logbook b = {0};
    n_alloc = n_free = 0, fail_at = 1;
    resources_dir = (const char *)1;
    fmi2Component c = inst2(&b, fmi2CoSimulation, "file:///tmp");
    fail_at = 0;
    cr_assert(c && resources_dir == NULL);
    fmi2FreeInstance(c);
    cr_assert(n_alloc == n_free + 1, "%d %d", n_alloc, n_free); /* the one that failed */
}

Test(fmi2, instantiation_needs_the_callbacks_with_a_logger)
{
    logbook b = {0};
    cr_assert(fmi2Instantiate("x", fmi2CoSimulation, VI_GUID, NULL, NULL, fmi2False, fmi2False) == NULL);
    fmi2CallbackFunctions cb = callbacks(&b);
    cb.logger = NULL;
    cr_assert(fmi2Instantiate("x", fmi2CoSimulation, VI_GUID, NULL, &cb, fmi2False, fmi2False) == NULL);
    cr_assert(b.count == 0);
}

/* canNotUseMemoryManagementFunctions="true" (the model descriptions): the importer may leave out the
 * memory functions, or one of them; the instance then uses the C library's for every block. */
Test(fmi2, instantiation_without_memory_functions_uses_the_fmus_own)
{
    for (int missing = 0; missing < 3; missing++) {
        logbook b = {0};
        fmi2CallbackFunctions cb = callbacks(&b);
        if (missing != 1) cb.allocateMemory = NULL;
        if (missing != 2) cb.freeMemory = NULL;
        n_alloc = n_free = 0;
        fmi2Component c = fmi2Instantiate("x", fmi2CoSimulation, VI_GUID, "file:///tmp", &cb, fmi2False, fmi2False);
        cr_assert(c != NULL, "missing %d: %s", missing, b.text);
        cr_assert(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) == fmi2OK);
        cr_assert(fmi2EnterInitializationMode(c) == fmi2OK && fmi2ExitInitializationMode(c) == fmi2OK);
        fmi2FreeInstance(c);
        cr_assert(n_alloc == 0 && n_free == 0 && b.count == 0, "missing %d: %d %d", missing, n_alloc, n_free);
    }
}

Test(fmi2, the_fmu_type_selects_the_interface)
{
    logbook b = {0};
    fmi2Component c = inst2(&b, fmi2ModelExchange, NULL);
    cr_assert(c && ((vi_fmi_instance *)c)->kind == VI_KIND_ME);
    fmi2FreeInstance(c);
    c = inst2(&b, fmi2CoSimulation, NULL);
    cr_assert(c && ((vi_fmi_instance *)c)->kind == VI_KIND_CS);
    fmi2FreeInstance(c);
    cr_assert(inst2(&b, (fmi2Type)2, NULL) == NULL);
    SAYS(b, fmi2Error, "fmi2Instantiate: CoreTest does not offer the interface type asked for (unknown type)");
    cr_assert(inst2(&b, (fmi2Type)-1, NULL) == NULL);
    SAYS(b, fmi2Error, "(unknown type)");
}

static fmi2Component running2(logbook *b)
{
    fmi2Component c = inst2(b, fmi2CoSimulation, NULL);
    cr_assert(c);
    cr_assert(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) == fmi2OK);
    cr_assert(fmi2EnterInitializationMode(c) == fmi2OK && fmi2ExitInitializationMode(c) == fmi2OK);
    return c;
}

Test(fmi2, status_queries_answer_the_last_successful_time_and_terminated_only)
{
    logbook b = {0};
    fmi2Component c = inst2(&b, fmi2CoSimulation, NULL);
    fmi2Status st;
    fmi2Real t = -1.0;
    REFUSED(b, fmi2GetStatus(c, fmi2DoStepStatus, &st), "fmi2GetStatus: not allowed in state 'instantiated'");
    REFUSED(b, fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t), "fmi2GetRealStatus: not allowed");
    fmi2FreeInstance(c);
    c = running2(&b);
    stub *s = ((vi_fmi_instance *)c)->model;
    s->advance_rc = VI_FMU_DISCARD, s->advance_to = 0.125;
    cr_assert(fmi2DoStep(c, 0.0, 0.5, fmi2True) == fmi2Discard);
    cr_assert(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t) == fmi2OK && t == 0.125);
    fmi2Boolean term = fmi2True;
    cr_assert(fmi2GetBooleanStatus(c, fmi2Terminated, &term) == fmi2OK && term == fmi2False);
    int before = b.count;
    cr_assert(fmi2GetStatus(c, fmi2DoStepStatus, &st) == fmi2Discard && b.count == before + 1);
    SAYS(b, fmi2Discard, "fmi2GetStatus: no status of kind 0 (fmi2DoStep runs synchronously)");
    cr_assert(strcmp(b.category, "logStatusDiscard") == 0);
    cr_assert(fmi2GetRealStatus(c, fmi2Terminated, &t) == fmi2Discard && t == 0.125);
    SAYS(b, fmi2Discard, "fmi2GetRealStatus: no status of kind 3");
    fmi2Integer i = 0;
    cr_assert(fmi2GetIntegerStatus(c, fmi2PendingStatus, &i) == fmi2Discard);
    SAYS(b, fmi2Discard, "fmi2GetIntegerStatus: no status of kind 1");
    cr_assert(fmi2GetBooleanStatus(c, fmi2LastSuccessfulTime, &term) == fmi2Discard);
    SAYS(b, fmi2Discard, "fmi2GetBooleanStatus: no status of kind 2");
    fmi2String str = NULL;
    cr_assert(fmi2GetStringStatus(c, fmi2PendingStatus, &str) == fmi2Discard);
    SAYS(b, fmi2Discard, "fmi2GetStringStatus: no status of kind 1");
    REFUSED(b, fmi2GetRealStatus(c, fmi2LastSuccessfulTime, NULL), "fmi2GetRealStatus: value is NULL");
    REFUSED(b, fmi2GetBooleanStatus(c, fmi2Terminated, NULL), "fmi2GetBooleanStatus: value is NULL");
    REFUSED(b, fmi2GetStatus(c, fmi2DoStepStatus, NULL), "fmi2GetStatus: value is NULL");
    REFUSED(b, fmi2GetIntegerStatus(c, fmi2PendingStatus, NULL), "fmi2GetIntegerStatus: value is NULL");
    REFUSED(b, fmi2GetStringStatus(c, fmi2PendingStatus, NULL), "fmi2GetStringStatus: value is NULL");
    /* in the error state: the last status queries only */
    ((vi_fmi_instance *)c)->state = VI_ST_ERROR;
    cr_assert(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t) == fmi2OK);
    cr_assert(fmi2GetBooleanStatus(c, fmi2Terminated, &term) == fmi2OK);
    REFUSED(b, fmi2GetStatus(c, fmi2DoStepStatus, &st), "fmi2GetStatus: not allowed in state 'error'");
    REFUSED(b, fmi2GetIntegerStatus(c, fmi2PendingStatus, &i), "fmi2GetIntegerStatus: not allowed in state 'error'");
    REFUSED(b, fmi2GetStringStatus(c, fmi2PendingStatus, &str), "fmi2GetStringStatus: not allowed in state 'error'");
    fmi2FreeInstance(c);
    cr_assert(fmi2GetRealStatus(NULL, fmi2LastSuccessfulTime, &t) == fmi2Error);
    cr_assert(fmi2GetStatus(NULL, fmi2DoStepStatus, &st) == fmi2Error);
}

Test(fmi2, output_derivatives_and_cancel_step_are_not_provided)
{
    logbook b = {0};
    fmi2Component c = running2(&b);
    fmi2ValueReference vr = VI_VR_y;
    fmi2Integer order = 1;
    fmi2Real v;
    REFUSED(b, fmi2GetRealOutputDerivatives(c, &vr, 1, &order, &v),
            "fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder=0)");
    REFUSED(b, fmi2CancelStep(c), "fmi2CancelStep: fmi2DoStep is synchronous; there is nothing to cancel");
    cr_assert(((vi_fmi_instance *)c)->state == VI_ST_STEP_COMPLETE);
    cr_assert(fmi2GetRealOutputDerivatives(NULL, &vr, 1, &order, &v) == fmi2Error);
    cr_assert(fmi2CancelStep(NULL) == fmi2Error);
    fmi2FreeInstance(c);
    c = inst2(&b, fmi2CoSimulation, NULL);
    REFUSED(b, fmi2GetRealOutputDerivatives(c, &vr, 1, &order, &v), "not allowed in state 'instantiated'");
    fmi2FreeInstance(c);
}

static fmi2Component events2(logbook *b)
{
    fmi2Component c = inst2(b, fmi2ModelExchange, NULL);
    cr_assert(c);
    cr_assert(fmi2SetupExperiment(c, fmi2False, 0.0, 1.0, fmi2False, 0.0) == fmi2OK);
    cr_assert(fmi2EnterInitializationMode(c) == fmi2OK && fmi2ExitInitializationMode(c) == fmi2OK);
    return c;
}

Test(fmi2, the_event_info_carries_each_field_of_the_pass)
{
    logbook b = {0};
    fmi2Component c = events2(&b);
    stub *s = ((vi_fmi_instance *)c)->model;
    REFUSED(b, fmi2NewDiscreteStates(c, NULL), "fmi2NewDiscreteStates: fmi2EventInfo is NULL");
    static const vi_fmu_event cases[] = {
        {.another_pass = 1}, {.terminate = 1}, {.nominals_changed = 1}, {.states_changed = 1},
        {.next_time_defined = 1, .next_time = 2.5}, {.next_time = 4.0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        s->ev = cases[i];
        fmi2EventInfo e;
        memset(&e, 0x55, sizeof e);
        /* the reason for terminating is logged as a warning: the call says so */
        cr_assert(fmi2NewDiscreteStates(c, &e) == (cases[i].terminate ? fmi2Warning : fmi2OK), "case %zu", i);
        cr_assert(e.newDiscreteStatesNeeded == (cases[i].another_pass ? fmi2True : fmi2False), "case %zu", i);
        cr_assert(e.terminateSimulation == (cases[i].terminate ? fmi2True : fmi2False), "case %zu", i);
        cr_assert(e.nominalsOfContinuousStatesChanged == (cases[i].nominals_changed ? fmi2True : fmi2False));
        cr_assert(e.valuesOfContinuousStatesChanged == (cases[i].states_changed ? fmi2True : fmi2False));
        cr_assert(e.nextEventTimeDefined == (cases[i].next_time_defined ? fmi2True : fmi2False));
        cr_assert(e.nextEventTime == (cases[i].next_time_defined ? cases[i].next_time : 0.0), "case %zu: %g", i,
                  e.nextEventTime);
    }
    s->fail_event = 1;
    fmi2EventInfo e;
    memset(&e, 0x55, sizeof e);
    fmi2EventInfo untouched = e;
    REFUSED(b, fmi2NewDiscreteStates(c, &e), "fmi2NewDiscreteStates: the stub says no");
    cr_assert(memcmp(&e, &untouched, sizeof e) == 0, "the event info was written after a failure");
    fmi2FreeInstance(c);
}

Test(fmi2, a_completed_integrator_step_writes_both_results_or_neither)
{
    logbook b = {0};
    fmi2Component c = events2(&b);
    stub *s = ((vi_fmi_instance *)c)->model;
    cr_assert(fmi2EnterContinuousTimeMode(c) == fmi2OK);
    fmi2Boolean enter = 7, term = 7;
    REFUSED(b, fmi2CompletedIntegratorStep(c, fmi2True, NULL, &term), "fmi2CompletedIntegratorStep: NULL argument");
    REFUSED(b, fmi2CompletedIntegratorStep(c, fmi2True, &enter, NULL), "fmi2CompletedIntegratorStep: NULL argument");
    cr_assert(enter == 7 && term == 7);
    s->completed = 1;
    cr_assert(fmi2CompletedIntegratorStep(c, fmi2True, &enter, &term) == fmi2OK && enter == fmi2True &&
              term == fmi2False);
    s->completed = 0;
    term = 7;
    cr_assert(fmi2CompletedIntegratorStep(c, fmi2True, &enter, &term) == fmi2OK && enter == fmi2False &&
              term == fmi2False);
    ((vi_fmi_instance *)c)->state = VI_ST_EVENT;
    enter = term = 7;
    REFUSED(b, fmi2CompletedIntegratorStep(c, fmi2True, &enter, &term), "not allowed in state 'event mode'");
    cr_assert(enter == 7 && term == 7);
    fmi2FreeInstance(c);
}

Test(fmi2, each_model_exchange_and_state_function_reaches_the_layer_under_its_own_name)
{
    logbook b = {0};
    fmi2Component c = events2(&b);
    fmi2Real x[2] = {1.0, 2.0}, nan2[2] = {NAN, 0.0};
    REFUSED(b, fmi2SetContinuousStates(c, nan2, 2), "fmi2SetContinuousStates: not allowed in state 'event mode'");
    REFUSED(b, fmi2GetDerivatives(c, x, 1), "fmi2GetDerivatives: 1 derivatives given");
    REFUSED(b, fmi2GetEventIndicators(c, x, 2), "fmi2GetEventIndicators: 2 event indicators given");
    REFUSED(b, fmi2GetContinuousStates(c, x, 3), "fmi2GetContinuousStates: 3 states given");
    REFUSED(b, fmi2GetNominalsOfContinuousStates(c, x, 1), "fmi2GetNominalsOfContinuousStates: 1 nominals");
    REFUSED(b, fmi2SetTime(c, NAN), "fmi2SetTime: time nan is not finite");
    cr_assert(fmi2GetNominalsOfContinuousStates(c, x, 2) == fmi2OK && x[0] == 1.0 && x[1] == 2.0);
    cr_assert(fmi2EnterContinuousTimeMode(c) == fmi2OK);
    REFUSED(b, fmi2EnterContinuousTimeMode(c), "fmi2EnterContinuousTimeMode: not allowed");
    REFUSED(b, fmi2SetContinuousStates(c, nan2, 2), "fmi2SetContinuousStates: state 0 (p) = nan");
    cr_assert(fmi2SetTime(c, 1.5) == fmi2OK && fmi2SetContinuousStates(c, x, 2) == fmi2OK);
    cr_assert(fmi2GetContinuousStates(c, x, 2) == fmi2OK && x[0] == 1.0 && x[1] == 2.0);
    cr_assert(fmi2GetDerivatives(c, x, 2) == fmi2OK && x[0] == 2.0 && x[1] == -1.0);
    cr_assert(fmi2GetEventIndicators(c, x, 1) == fmi2OK && x[0] == 0.0);
    cr_assert(fmi2EnterEventMode(c) == fmi2OK);
    REFUSED(b, fmi2SetTime(c, 2.0), "fmi2SetTime: t = 2 s in event mode");
    fmi2ValueReference unk = VI_VR_der_p, kn = VI_VR_q;
    fmi2Real seed = 2.0, out = 0.0;
    cr_assert(fmi2GetDirectionalDerivative(c, &unk, 1, &kn, 1, &seed, &out) == fmi2OK && out == 2.0);
    REFUSED(b, fmi2GetDirectionalDerivative(c, &unk, 1, &kn, 1, &seed, NULL), "fmi2GetDirectionalDerivative: NULL array");
    fmi2FMUstate st = NULL;
    REFUSED(b, fmi2GetFMUstate(c, NULL), "fmi2GetFMUstate: FMUstate is NULL");
    cr_assert(fmi2GetFMUstate(c, &st) == fmi2OK);
    size_t size = 0;
    cr_assert(fmi2SerializedFMUstateSize(c, st, &size) == fmi2OK && size > sizeof(data));
    REFUSED(b, fmi2SerializedFMUstateSize(c, st, NULL), "fmi2SerializedFMUstateSize: size is NULL");
    fmi2Byte *bytes = malloc(size);
    REFUSED(b, fmi2SerializeFMUstate(c, st, bytes, size - 1), "fmi2SerializeFMUstate: need a buffer");
    cr_assert(fmi2SerializeFMUstate(c, st, bytes, size) == fmi2OK);
    fmi2FMUstate back = NULL;
    REFUSED(b, fmi2DeSerializeFMUstate(c, bytes, size - 1, &back), "fmi2DeSerializeFMUstate: invalid FMU state");
    cr_assert(fmi2DeSerializeFMUstate(c, bytes, size, &back) == fmi2OK && memcmp(back, st, size) == 0);
    REFUSED(b, fmi2SetFMUstate(c, NULL), "fmi2SetFMUstate: invalid FMU state: the state is NULL");
    cr_assert(fmi2SetFMUstate(c, back) == fmi2OK);
    cr_assert(fmi2FreeFMUstate(c, &back) == fmi2OK && back == NULL);
    cr_assert(fmi2FreeFMUstate(c, &st) == fmi2OK);
    free(bytes);
    cr_assert(fmi2Terminate(c) == fmi2OK && ((vi_fmi_instance *)c)->state == VI_ST_TERMINATED);
    REFUSED(b, fmi2Terminate(c), "fmi2Terminate: not allowed in state 'terminated'");
    cr_assert(fmi2Reset(c) == fmi2OK && ((vi_fmi_instance *)c)->state == VI_ST_INSTANTIATED);
    REFUSED(b, fmi2ExitInitializationMode(c), "fmi2ExitInitializationMode: not allowed");
    REFUSED(b, fmi2SetupExperiment(c, fmi2True, 0.0, 0.0, fmi2False, 0.0), "fmi2SetupExperiment: need a finite start");
    REFUSED(b, fmi2DoStep(c, 0.0, 1.0, fmi2True), "fmi2DoStep: not allowed");
    REFUSED(b, fmi2NewDiscreteStates(c, &(fmi2EventInfo){0}), "fmi2NewDiscreteStates: not allowed");
    REFUSED(b, fmi2EnterEventMode(c), "fmi2EnterEventMode: not allowed");
    fmi2FreeInstance(c);
}

Test(fmi2, each_value_and_step_function_reaches_the_layer_under_its_own_name)
{
    logbook b = {0};
    fmi2Component c = running2(&b);
    fmi2ValueReference unk = VI_VR_der_p, kn = VI_VR_q;
    fmi2Real seed = 2.0, out = 0.0;
    fmi2ValueReference vk = VI_VR_k, vn = VI_VR_n, vb = VI_VR_b, vl = VI_VR_label, vu = VI_VR_u;
    fmi2Real k = 0;
    fmi2Integer n = 0, bo = 0, order = 1;
    fmi2String l = NULL;
    cr_assert(fmi2GetReal(c, &vk, 1, &k) == fmi2OK && k == 1.0);
    cr_assert(fmi2GetInteger(c, &vn, 1, &n) == fmi2OK && n == 3);
    cr_assert(fmi2GetBoolean(c, &vb, 1, &bo) == fmi2OK && bo == 0);
    cr_assert(fmi2GetString(c, &vl, 1, &l) == fmi2OK && strcmp(l, "abc") == 0);
    REFUSED(b, fmi2GetReal(c, &vn, 1, &k), "fmi2GetReal: value reference 2 (n) is of type Integer");
    REFUSED(b, fmi2GetInteger(c, &vk, 1, &n), "fmi2GetInteger: value reference 1 (k) is of type Real");
    REFUSED(b, fmi2GetBoolean(c, &vk, 1, &bo), "fmi2GetBoolean: value reference 1");
    REFUSED(b, fmi2GetString(c, &vk, 1, &l), "fmi2GetString: value reference 1");
    REFUSED(b, fmi2SetReal(c, &vn, 1, &k), "fmi2SetReal: value reference 2");
    REFUSED(b, fmi2SetInteger(c, &vn, 1, &(fmi2Integer){9}), "fmi2SetInteger: n is a fixed parameter");
    REFUSED(b, fmi2SetBoolean(c, &vk, 1, &bo), "fmi2SetBoolean: value reference 1");
    REFUSED(b, fmi2SetString(c, &vl, 1, &l), "fmi2SetString: label is a fixed parameter");
    bo = 3;
    cr_assert(fmi2SetBoolean(c, &vb, 1, &bo) == fmi2OK && fmi2GetBoolean(c, &vb, 1, &n) == fmi2OK && n == 1);
    REFUSED(b, fmi2SetRealInputDerivatives(c, &vu, 1, &(fmi2Integer){2}, &k), "fmi2SetRealInputDerivatives: u order 2");
    cr_assert(fmi2SetRealInputDerivatives(c, &vu, 1, &order, &(fmi2Real){0.5}) == fmi2OK);
    REFUSED(b, fmi2DoStep(c, 1.0, 1.0, fmi2True), "fmi2DoStep: currentCommunicationPoint");
    cr_assert(fmi2DoStep(c, 0.0, 1.0, fmi2False) == fmi2OK);
    REFUSED(b, fmi2GetDirectionalDerivative(c, &unk, 1, &kn, 1, &seed, &out),
            "fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative=false in Co-Simulation)");
    fmi2FreeInstance(c);
    cr_assert(strcmp(fmi2GetTypesPlatform(), "default") == 0 && strcmp(fmi2GetVersion(), "2.0") == 0);
}

/* `call` returns OK (fmi2OK and fmi3OK are 0) though the model logged a note in it, which the importer got
 * with status Warning (fmi2Warning and fmi3Warning are 1) in logStatusWarning. */
#define NOTED_OK(b, s, call)                                                                                 \
    do {                                                                                                     \
        int notes_ = (s)->notes;                                                                            \
        int st_ = (int)(call);                                                                              \
        cr_assert(st_ == 0 && (s)->notes > notes_, "%s: status %d, %d notes", #call, st_, (s)->notes - notes_); \
        SAYS(b, 1, "note: ");                                                                               \
        cr_assert(strcmp((b).category, "logStatusWarning") == 0, "%s: %s", #call, (b).category);              \
    } while (0)

/* A warning of the model (a note the computation goes on through) reaches the logger as fmi2Warning while
 * the call returns fmi2OK: importers such as fmusim and PyFMI stop a run at any other status. */
Test(fmi2, a_note_of_the_model_is_logged_as_a_warning_and_the_call_returns_ok)
{
    logbook b = {0};
    fmi2Component c = inst2(&b, fmi2CoSimulation, NULL);
    stub *s = ((vi_fmi_instance *)c)->model;
    s->warn_notes = 1;
    NOTED_OK(b, s, fmi2SetupExperiment(c, fmi2True, 1e-6, 0.0, fmi2False, 0.0));
    cr_assert(fmi2EnterInitializationMode(c) == fmi2OK);
    NOTED_OK(b, s, fmi2ExitInitializationMode(c));
    NOTED_OK(b, s, fmi2DoStep(c, 0.0, 0.5, fmi2True));
    NOTED_OK(b, s, fmi2Terminate(c));
    fmi2FreeInstance(c);
    c = inst2(&b, fmi2ModelExchange, NULL);
    s = ((vi_fmi_instance *)c)->model;
    s->warn_notes = 1;
    cr_assert(fmi2EnterInitializationMode(c) == fmi2OK);
    NOTED_OK(b, s, fmi2ExitInitializationMode(c));
    fmi2EventInfo info;
    NOTED_OK(b, s, fmi2NewDiscreteStates(c, &info));
    cr_assert(!info.terminateSimulation);
    NOTED_OK(b, s, fmi2EnterContinuousTimeMode(c));
    double dx[2], z[1];
    NOTED_OK(b, s, fmi2GetDerivatives(c, dx, 2));
    NOTED_OK(b, s, fmi2GetEventIndicators(c, z, 1));
    fmi2Boolean enter = fmi2True, term = fmi2True;
    NOTED_OK(b, s, fmi2CompletedIntegratorStep(c, fmi2True, &enter, &term));
    cr_assert(!enter && !term);
    fmi2FreeInstance(c);
}

/* ---- FMI 3.0 ---- */

#define TIME3 VI_FMI3_TIME_VR
static fmi3Instance cs3(logbook *b, bool event_mode, bool early_return)
{
    fmi3Instance c = fmi3InstantiateCoSimulation("three", VI_GUID, NULL, false, false, event_mode, early_return, NULL,
                                                 0, b, logger3, NULL);
    cr_assert(c, "%s", b->text);
    return c;
}
static fmi3Instance running3(logbook *b, bool event_mode, bool early_return)
{
    fmi3Instance c = cs3(b, event_mode, early_return);
    cr_assert(fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0) == fmi3OK);
    cr_assert(fmi3ExitInitializationMode(c) == fmi3OK, "%s", b->text);
    return c;
}
static fmi3Instance me3(logbook *b)
{
    fmi3Instance c = fmi3InstantiateModelExchange("three", VI_GUID, NULL, false, false, b, logger3);
    cr_assert(c, "%s", b->text);
    cr_assert(fmi3EnterInitializationMode(c, false, 0.0, 1.0, false, 0.0) == fmi3OK);
    cr_assert(fmi3ExitInitializationMode(c) == fmi3OK);
    return c;
}

Test(fmi3, the_logger_gets_the_message_as_it_is_and_instantiation_its_arguments)
{
    logbook b = {0};
    fmi3Instance c = fmi3InstantiateCoSimulation("three", VI_GUID, "", false, true, false, false, NULL, 0, &b,
                                                 logger3, NULL);
    cr_assert(c && b.count == 1 && strcmp(b.text, "fmi3InstantiateCoSimulation: three") == 0 &&
              strcmp(b.category, "logFmi3Call") == 0, "%d '%s'", b.count, b.text);
    cr_assert(((vi_fmi_instance *)c)->face_options == 0u && resources_dir == NULL);
    fmi3String cats[] = {"100%"};
    cr_assert(fmi3SetDebugLogging(c, true, 1, cats) == fmi3Error);
    cr_assert(strcmp(b.text, "fmi3SetDebugLogging: unknown log category '100%'") == 0, "'%s'", b.text);
    fmi3FreeInstance(c);
    cr_assert(strcmp(b.text, "fmi3FreeInstance") == 0);
    c = fmi3InstantiateCoSimulation("three", VI_GUID, "/res/", false, false, true, false, NULL, 0, &b, logger3, NULL);
    cr_assert(c && ((vi_fmi_instance *)c)->face_options == 1u && resources_dir && strcmp(resources_dir, "/res/") == 0);
    fmi3FreeInstance(c);
    c = fmi3InstantiateCoSimulation("three", VI_GUID, NULL, false, false, false, true, NULL, 0, &b, logger3, NULL);
    cr_assert(c && ((vi_fmi_instance *)c)->face_options == 2u && resources_dir == NULL);
    fmi3FreeInstance(c);
    c = fmi3InstantiateModelExchange("three", VI_GUID, "/r", false, false, &b, logger3);
    cr_assert(c && ((vi_fmi_instance *)c)->kind == VI_KIND_ME && ((vi_fmi_instance *)c)->face_options == 0u &&
              strcmp(resources_dir, "/r") == 0);
    fmi3FreeInstance(c);
    int before = b.count;
    cr_assert(fmi3InstantiateCoSimulation("three", "{other}", NULL, false, false, false, false, NULL, 0, &b, logger3,
                                          NULL) == NULL);
    cr_assert(b.count == before + 1);
    SAYS(b, fmi3Error, "fmi3InstantiateCoSimulation: GUID '{other}' does not match");
    cr_assert(fmi3InstantiateScheduledExecution("s", VI_GUID, NULL, false, false, &b, logger3, NULL, NULL, NULL) == NULL);
    cr_assert(b.count == before + 2 && strcmp(b.category, "logStatusError") == 0);
    SAYS(b, fmi3Error, "fmi3InstantiateScheduledExecution: this FMU offers Co-Simulation and Model Exchange, "
                              "not Scheduled Execution");
    cr_assert(fmi3InstantiateScheduledExecution("s", VI_GUID, NULL, false, false, &b, NULL, NULL, NULL, NULL) == NULL);
    cr_assert(strcmp(fmi3GetVersion(), "3.0") == 0);
}

Test(fmi3, initialization_mode_is_entered_only_with_valid_settings_and_left_into_the_right_mode)
{
    logbook b = {0};
    fmi3Instance c = cs3(&b, false, false);
    REFUSED(b, fmi3EnterInitializationMode(c, true, 1.0, 0.0, false, 0.0), "fmi3EnterInitializationMode: need a finite");
    cr_assert(((vi_fmi_instance *)c)->state == VI_ST_INSTANTIATED);
    cr_assert(fmi3EnterInitializationMode(c, true, 0.5, 2.0, true, 3.0) == fmi3OK);
    cr_assert(((vi_fmi_instance *)c)->state == VI_ST_INIT && ((vi_fmi_instance *)c)->stop_time == 3.0);
    REFUSED(b, fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            "fmi3EnterInitializationMode: not allowed in state 'initialization mode'");
    cr_assert(fmi3ExitInitializationMode(c) == fmi3OK && ((vi_fmi_instance *)c)->state == VI_ST_STEP_COMPLETE);
    REFUSED(b, fmi3EnterEventMode(c), "fmi3EnterEventMode: the instance was created with eventModeUsed = false");
    cr_assert(((vi_fmi_instance *)c)->state == VI_ST_STEP_COMPLETE);
    REFUSED(b, fmi3ExitInitializationMode(c), "fmi3ExitInitializationMode: not allowed in state 'step complete'");
    fmi3FreeInstance(c);
    c = cs3(&b, false, false);
    REFUSED(b, fmi3EnterEventMode(c), "fmi3EnterEventMode: not allowed in state 'instantiated'");
    fmi3FreeInstance(c);
    c = running3(&b, true, false);
    cr_assert(((vi_fmi_instance *)c)->state == VI_ST_EVENT);
    REFUSED(b, fmi3EnterEventMode(c), "fmi3EnterEventMode: not allowed in state 'event mode'");
    cr_assert(fmi3EnterStepMode(c) == fmi3OK && ((vi_fmi_instance *)c)->state == VI_ST_STEP_COMPLETE);
    cr_assert(fmi3EnterEventMode(c) == fmi3OK && ((vi_fmi_instance *)c)->state == VI_ST_EVENT);
    fmi3FreeInstance(c);
    c = cs3(&b, true, false);
    stub *s = ((vi_fmi_instance *)c)->model;
    s->fail_init = 1;
    cr_assert(fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0) == fmi3OK);
    REFUSED(b, fmi3ExitInitializationMode(c), "fmi3ExitInitializationMode: the stub says no");
    cr_assert(((vi_fmi_instance *)c)->state == VI_ST_ERROR);
    fmi3FreeInstance(c);
    c = me3(&b);
    cr_assert(((vi_fmi_instance *)c)->state == VI_ST_EVENT);
    cr_assert(fmi3EnterContinuousTimeMode(c) == fmi3OK && fmi3EnterEventMode(c) == fmi3OK);
    fmi3FreeInstance(c);
    cr_assert(fmi3EnterEventMode(NULL) == fmi3Error && fmi3ExitInitializationMode(NULL) == fmi3Error);
}

/* As in FMI 2.0: a note of the model is logged as fmi3Warning, the call returns fmi3OK, also where the face
 * makes one call of two of the layer's (initialization mode entered with the experiment's settings, left
 * into Event Mode). */
Test(fmi3, a_note_of_the_model_is_logged_as_a_warning_and_the_call_returns_ok)
{
    logbook b = {0};
    fmi3Instance c = cs3(&b, true, true);
    stub *s = ((vi_fmi_instance *)c)->model;
    s->warn_notes = 1;
    NOTED_OK(b, s, fmi3EnterInitializationMode(c, true, 1e-6, 0.0, false, 0.0));
    NOTED_OK(b, s, fmi3ExitInitializationMode(c));
    cr_assert(fmi3EnterStepMode(c) == fmi3OK);
    bool ehn, term, early;
    double last;
    NOTED_OK(b, s, fmi3DoStep(c, 0.0, 0.5, true, &ehn, &term, &early, &last));
    cr_assert(!early && last == 0.5);
    NOTED_OK(b, s, fmi3Terminate(c));
    fmi3FreeInstance(c);
    c = fmi3InstantiateModelExchange("three", VI_GUID, NULL, false, false, &b, logger3);
    s = ((vi_fmi_instance *)c)->model;
    s->warn_notes = 1;
    NOTED_OK(b, s, fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0));
    NOTED_OK(b, s, fmi3ExitInitializationMode(c));
    bool need, nominals, values, next_defined;
    double next;
    NOTED_OK(b, s, fmi3UpdateDiscreteStates(c, &need, &term, &nominals, &values, &next_defined, &next));
    cr_assert(!term);
    NOTED_OK(b, s, fmi3EnterContinuousTimeMode(c));
    double dx[2], z[1];
    NOTED_OK(b, s, fmi3GetContinuousStateDerivatives(c, dx, 2));
    NOTED_OK(b, s, fmi3GetEventIndicators(c, z, 1));
    bool enter = true;
    term = true;
    NOTED_OK(b, s, fmi3CompletedIntegratorStep(c, true, &enter, &term));
    cr_assert(!enter && !term);
    fmi3FreeInstance(c);
}

Test(fmi3, every_variable_is_a_scalar)
{
    logbook b = {0};
    fmi3Instance c = running3(&b, false, false);
    fmi3ValueReference vk = VI_VR_k, vn = VI_VR_n, vc = VI_VR_color, vb = VI_VR_b, vl = VI_VR_label;
    double k[2] = {0, 0};
    int n[2];
    int64_t e[2];
    bool bo[2];
    fmi3String l[2];
    REFUSED(b, fmi3GetFloat64(c, &vk, 1, k, 2), "fmi3GetFloat64: nValues = 2 must equal nValueReferences = 1");
    REFUSED(b, fmi3GetFloat64(c, &vk, 1, k, 0), "fmi3GetFloat64: nValues = 0 must equal nValueReferences = 1");
    REFUSED(b, fmi3SetFloat64(c, &vk, 1, k, 2), "fmi3SetFloat64: nValues = 2");
    REFUSED(b, fmi3GetInt32(c, &vn, 1, n, 2), "fmi3GetInt32: nValues = 2");
    REFUSED(b, fmi3SetInt32(c, &vn, 1, n, 0), "fmi3SetInt32: nValues = 0");
    REFUSED(b, fmi3GetInt64(c, &vc, 1, e, 2), "fmi3GetInt64: nValues = 2");
    REFUSED(b, fmi3SetInt64(c, &vc, 1, e, 2), "fmi3SetInt64: nValues = 2");
    REFUSED(b, fmi3GetBoolean(c, &vb, 1, bo, 2), "fmi3GetBoolean: nValues = 2");
    REFUSED(b, fmi3SetBoolean(c, &vb, 1, bo, 2), "fmi3SetBoolean: nValues = 2");
    REFUSED(b, fmi3GetString(c, &vl, 1, l, 2), "fmi3GetString: nValues = 2");
    REFUSED(b, fmi3SetString(c, &vl, 1, l, 2), "fmi3SetString: nValues = 2");
    cr_assert(fmi3GetFloat64(c, &vk, 1, k, 1) == fmi3OK && k[0] == 1.0);
    cr_assert(fmi3GetInt32(c, &vn, 1, n, 1) == fmi3OK && n[0] == 3);
    cr_assert(fmi3GetInt64(c, &vc, 1, e, 1) == fmi3OK && e[0] == 2);
    e[0] = 5;
    cr_assert(fmi3SetInt64(c, &vc, 1, e, 1) == fmi3OK && fmi3GetInt64(c, &vc, 1, e + 1, 1) == fmi3OK && e[1] == 5);
    bo[0] = true;
    cr_assert(fmi3SetBoolean(c, &vb, 1, bo, 1) == fmi3OK && fmi3GetBoolean(c, &vb, 1, bo + 1, 1) == fmi3OK && bo[1]);
    cr_assert(fmi3GetString(c, &vl, 1, l, 1) == fmi3OK && strcmp(l[0], "abc") == 0);
    REFUSED(b, fmi3SetString(c, &vl, 1, l, 1), "fmi3SetString: label is a fixed parameter");
    REFUSED(b, fmi3SetInt32(c, &vn, 1, n, 1), "fmi3SetInt32: n is a fixed parameter");
    REFUSED(b, fmi3GetInt32(c, &vc, 1, n, 1), "fmi3GetInt32: value reference 11 (color) is of type Enumeration (Int64)");
    REFUSED(b, fmi3GetFloat64(c, &vn, 1, k, 1), "fmi3GetFloat64: value reference 2 (n) is of type Int32");
    k[0] = 2.0;
    cr_assert(fmi3SetFloat64(c, &vk, 1, k, 1) == fmi3OK && fmi3GetFloat64(c, &vk, 1, k + 1, 1) == fmi3OK && k[1] == 2.0);
    fmi3ValueReference vt = TIME3;
    cr_assert(fmi3GetFloat64(c, &vt, 1, k, 1) == fmi3OK && k[0] == 0.0);
    /* the state check comes first */
    fmi3FreeInstance(c);
    c = cs3(&b, false, false);
    REFUSED(b, fmi3GetFloat64(c, &vk, 1, k, 2), "fmi3GetFloat64: not allowed in state 'instantiated'");
    ((vi_fmi_instance *)c)->state = VI_ST_STEP_FAILED;
    REFUSED(b, fmi3SetInt32(c, &vn, 1, n, 2), "fmi3SetInt32: not allowed in state 'step failed'");
    REFUSED(b, fmi3SetFloat64(c, &vk, 1, k, 2), "fmi3SetFloat64: not allowed in state 'step failed'");
    fmi3FreeInstance(c);
    cr_assert(fmi3GetFloat64(NULL, &vk, 1, k, 2) == fmi3Error);
}

Test(fmi3, types_the_fmu_has_no_variable_of_refuse_any_reference)
{
    logbook b = {0};
    fmi3Instance c = running3(&b, false, false);
    fmi3ValueReference vr[2] = {7, 8};
    float f[2];
    uint8_t u8[2];
    size_t sizes[2];
    fmi3Binary bin[2];
    REFUSED(b, fmi3GetFloat32(c, vr, 2, f, 2), "fmi3GetFloat32: value reference 7 is not a Float32 variable: this FMU has none");
    REFUSED(b, fmi3SetFloat32(c, vr, 2, f, 2), "fmi3SetFloat32: value reference 7 is not a Float32 variable");
    REFUSED(b, fmi3GetUInt8(c, vr + 1, 1, u8, 1), "fmi3GetUInt8: value reference 8 is not a UInt8 variable");
    REFUSED(b, fmi3GetBinary(c, vr, 1, sizes, bin, 1), "fmi3GetBinary: value reference 7 is not a Binary variable");
    REFUSED(b, fmi3SetInt8(c, NULL, 1, NULL, 1), "fmi3SetInt8: value reference 0 is not a Int8 variable");
    cr_assert(fmi3GetFloat32(c, NULL, 0, NULL, 0) == fmi3OK && fmi3SetBinary(c, NULL, 0, NULL, NULL, 0) == fmi3OK);
    cr_assert(fmi3GetClock(c, NULL, 0, NULL) == fmi3OK);
    fmi3FreeInstance(c);
    c = cs3(&b, false, false);
    REFUSED(b, fmi3GetFloat32(c, NULL, 0, NULL, 0), "fmi3GetFloat32: not allowed in state 'instantiated'");
    fmi3FreeInstance(c);
    cr_assert(fmi3GetFloat32(NULL, NULL, 0, NULL, 0) == fmi3Error);
}

Test(fmi3, directional_derivative_sizes_must_equal_the_numbers_of_knowns_and_unknowns)
{
    logbook b = {0};
    fmi3Instance c = me3(&b);
    fmi3ValueReference unk[2] = {VI_VR_der_p, VI_VR_der_q}, kn[2] = {VI_VR_q, VI_VR_p};
    double seed[2] = {1.0, 2.0}, out[2] = {0, 0};
    REFUSED(b, fmi3GetDirectionalDerivative(c, unk, 2, kn, 2, seed, 1, out, 2),
            "fmi3GetDirectionalDerivative: nSeed = 1 and nSensitivity = 2 must equal nKnowns = 2 and nUnknowns = 2");
    REFUSED(b, fmi3GetDirectionalDerivative(c, unk, 2, kn, 2, seed, 2, out, 1),
            "nSeed = 2 and nSensitivity = 1 must equal nKnowns = 2 and nUnknowns = 2");
    REFUSED(b, fmi3GetDirectionalDerivative(c, unk, 2, kn, 1, seed, 2, out, 2), "nSeed = 2 and nSensitivity = 2 must equal nKnowns = 1");
    REFUSED(b, fmi3GetDirectionalDerivative(c, unk, 1, kn, 2, seed, 2, out, 2), "and nUnknowns = 1");
    cr_assert(out[0] == 0.0 && out[1] == 0.0);
    cr_assert(fmi3GetDirectionalDerivative(c, unk, 2, kn, 2, seed, 2, out, 2) == fmi3OK);
    cr_assert(out[0] == 1.0 && out[1] == -2.0, "%g %g", out[0], out[1]);
    cr_assert(fmi3GetDirectionalDerivative(c, unk, 1, kn, 2, seed, 2, out, 1) == fmi3OK && out[0] == 1.0);
    REFUSED(b, fmi3GetAdjointDerivative(c, unk, 2, kn, 2, seed, 2, out, 2),
            "fmi3GetAdjointDerivative: not provided (providesAdjointDerivatives = false)");
    fmi3FreeInstance(c);
    c = cs3(&b, false, false);
    REFUSED(b, fmi3GetDirectionalDerivative(c, unk, 2, kn, 2, seed, 1, out, 2),
            "fmi3GetDirectionalDerivative: not allowed in state 'instantiated'");
    fmi3FreeInstance(c);
    cr_assert(fmi3GetDirectionalDerivative(NULL, unk, 2, kn, 2, seed, 1, out, 2) == fmi3Error);
}

Test(fmi3, update_discrete_states_checks_each_result_pointer_and_fills_every_result)
{
    logbook b = {0};
    fmi3Instance c = me3(&b);
    stub *s = ((vi_fmi_instance *)c)->model;
    bool r[5];
    double next = -1.0;
    for (int k = 0; k < 6; k++) {
        bool *p[5] = {&r[0], &r[1], &r[2], &r[3], &r[4]};
        double *pn = &next;
        if (k < 5) p[k] = NULL;
        else pn = NULL;
        REFUSED(b, fmi3UpdateDiscreteStates(c, p[0], p[1], p[2], p[3], p[4], pn), "fmi3UpdateDiscreteStates: NULL argument");
    }
    cr_assert(s->event_calls == 0);
    static const vi_fmu_event cases[] = {
        {.another_pass = 1}, {.terminate = 1}, {.nominals_changed = 1}, {.states_changed = 1},
        {.next_time_defined = 1, .next_time = 2.5}, {.next_time = 4.0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        s->ev = cases[i];
        memset(r, 1, sizeof r);
        next = -1.0;
        cr_assert(fmi3UpdateDiscreteStates(c, &r[0], &r[1], &r[2], &r[3], &r[4], &next) ==
                      (cases[i].terminate ? fmi3Warning : fmi3OK), "case %zu", i);
        cr_assert(r[0] == (cases[i].another_pass != 0) && r[1] == (cases[i].terminate != 0) &&
                  r[2] == (cases[i].nominals_changed != 0) && r[3] == (cases[i].states_changed != 0) &&
                  r[4] == (cases[i].next_time_defined != 0), "case %zu: %d %d %d %d %d", i, r[0], r[1], r[2], r[3], r[4]);
        cr_assert(next == (cases[i].next_time_defined ? cases[i].next_time : 0.0), "case %zu: %g", i, next);
    }
    s->fail_event = 1;
    memset(r, 1, sizeof r);
    next = -1.0;
    REFUSED(b, fmi3UpdateDiscreteStates(c, &r[0], &r[1], &r[2], &r[3], &r[4], &next), "fmi3UpdateDiscreteStates: the stub says no");
    cr_assert(r[0] && r[1] && r[2] && r[3] && r[4] && next == -1.0, "results written after a failure");
    fmi3FreeInstance(c);

    /* Co-Simulation Event Mode: nothing to update */
    c = running3(&b, true, false);
    memset(r, 1, sizeof r);
    next = -1.0;
    cr_assert(fmi3UpdateDiscreteStates(c, &r[0], &r[1], &r[2], &r[3], &r[4], &next) == fmi3OK);
    cr_assert(!r[0] && !r[1] && !r[2] && !r[3] && !r[4] && next == 0.0);
    cr_assert(((stub *)((vi_fmi_instance *)c)->model)->event_calls == 0);
    cr_assert(fmi3EnterStepMode(c) == fmi3OK);
    REFUSED(b, fmi3UpdateDiscreteStates(c, &r[0], &r[1], &r[2], &r[3], &r[4], &next),
            "fmi3UpdateDiscreteStates: not allowed in state 'step complete'");
    REFUSED(b, fmi3EvaluateDiscreteStates(c), "fmi3EvaluateDiscreteStates: not allowed in state 'step complete'");
    fmi3FreeInstance(c);
    c = running3(&b, true, false);
    REFUSED(b, fmi3EvaluateDiscreteStates(c), "fmi3EvaluateDiscreteStates: not provided (providesEvaluateDiscreteStates = false)");
    fmi3FreeInstance(c);
}

Test(fmi3, a_completed_integrator_step_and_the_model_exchange_counts)
{
    logbook b = {0};
    fmi3Instance c = me3(&b);
    stub *s = ((vi_fmi_instance *)c)->model;
    size_t n = 0;
    cr_assert(fmi3GetNumberOfContinuousStates(c, &n) == fmi3OK && n == 2);
    cr_assert(fmi3GetNumberOfEventIndicators(c, &n) == fmi3OK && n == 1);
    REFUSED(b, fmi3GetNumberOfEventIndicators(c, NULL), "fmi3GetNumberOfEventIndicators: NULL argument");
    REFUSED(b, fmi3GetNumberOfContinuousStates(c, NULL), "fmi3GetNumberOfContinuousStates: NULL argument");
    cr_assert(fmi3EnterContinuousTimeMode(c) == fmi3OK);
    bool enter = false, term = true;
    REFUSED(b, fmi3CompletedIntegratorStep(c, true, NULL, &term), "fmi3CompletedIntegratorStep: NULL argument");
    REFUSED(b, fmi3CompletedIntegratorStep(c, true, &enter, NULL), "fmi3CompletedIntegratorStep: NULL argument");
    s->completed = 1;
    cr_assert(fmi3CompletedIntegratorStep(c, true, &enter, &term) == fmi3OK && enter && !term);
    s->completed = 0;
    term = true;
    cr_assert(fmi3CompletedIntegratorStep(c, true, &enter, &term) == fmi3OK && !enter && !term);
    double x[2] = {3.0, 4.0};
    cr_assert(fmi3SetTime(c, 2.0) == fmi3OK && fmi3SetContinuousStates(c, x, 2) == fmi3OK);
    cr_assert(fmi3GetContinuousStates(c, x, 2) == fmi3OK && x[0] == 3.0 && x[1] == 4.0);
    cr_assert(fmi3GetContinuousStateDerivatives(c, x, 2) == fmi3OK && x[0] == 4.0 && x[1] == -3.0);
    cr_assert(fmi3GetEventIndicators(c, x, 1) == fmi3OK && x[0] == 2.0);
    cr_assert(fmi3GetNominalsOfContinuousStates(c, x, 2) == fmi3OK && x[1] == 2.0);
    REFUSED(b, fmi3SetTime(c, 0.5), "fmi3SetTime: t = 0.5 s lies before");
    REFUSED(b, fmi3SetContinuousStates(c, x, 1), "fmi3SetContinuousStates: 1 states given");
    REFUSED(b, fmi3GetContinuousStateDerivatives(c, x, 1), "fmi3GetContinuousStateDerivatives: 1 derivatives");
    REFUSED(b, fmi3GetEventIndicators(c, x, 0), "fmi3GetEventIndicators: 0 event indicators");
    REFUSED(b, fmi3GetContinuousStates(c, x, 1), "fmi3GetContinuousStates: 1 states");
    REFUSED(b, fmi3GetNominalsOfContinuousStates(c, x, 1), "fmi3GetNominalsOfContinuousStates: 1 nominals");
    fmi3FreeInstance(c);
    c = cs3(&b, false, false);
    cr_assert(fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0) == fmi3OK);
    REFUSED(b, fmi3GetNumberOfContinuousStates(c, &n), "fmi3GetNumberOfContinuousStates: a Model Exchange function");
    REFUSED(b, fmi3GetNumberOfEventIndicators(c, &n), "fmi3GetNumberOfEventIndicators: a Model Exchange function");
    fmi3FreeInstance(c);
    c = fmi3InstantiateModelExchange("three", VI_GUID, NULL, false, false, &b, logger3);
    REFUSED(b, fmi3GetNumberOfContinuousStates(c, &n), "fmi3GetNumberOfContinuousStates: not allowed in state 'instantiated'");
    fmi3FreeInstance(c);
    cr_assert(fmi3GetNumberOfContinuousStates(NULL, &n) == fmi3Error);
}

Test(fmi3, do_step_results_with_and_without_early_return)
{
    logbook b = {0};
    fmi3Instance c = running3(&b, true, true);
    bool ehn = true, term = true, early = false;
    double last = -1.0;
    REFUSED(b, fmi3DoStep(c, 0.0, 1.0, false, &ehn, &term, &early, &last), "fmi3DoStep: not allowed in state 'event mode'");
    cr_assert(fmi3EnterStepMode(c) == fmi3OK);
    for (int k = 0; k < 4; k++) {
        bool *p[3] = {&ehn, &term, &early};
        double *pl = &last;
        if (k < 3) p[k] = NULL;
        else pl = NULL;
        REFUSED(b, fmi3DoStep(c, 0.0, 1.0, false, p[0], p[1], p[2], pl), "fmi3DoStep: NULL argument");
    }
    cr_assert(fmi3DoStep(NULL, 0.0, 1.0, false, &ehn, &term, &early, &last) == fmi3Error);
    ((vi_fmi_instance *)c)->state = VI_ST_STEP_FAILED; /* the state is checked before the arguments */
    REFUSED(b, fmi3DoStep(c, 0.0, 1.0, false, NULL, &term, &early, &last), "fmi3DoStep: not allowed in state 'step failed'");
    ((vi_fmi_instance *)c)->state = VI_ST_STEP_COMPLETE;
    stub *s = ((vi_fmi_instance *)c)->model;
    /* an event inside the step */
    s->advance_rc = VI_FMU_EVENT, s->advance_to = 0.25;
    cr_assert(fmi3DoStep(c, 0.0, 1.0, false, &ehn, &term, &early, &last) == fmi3OK, "%s", b.text);
    cr_assert(ehn && !term && early && last == 0.25);
    /* an event at the end of the step: no early return, but the event is handled */
    s->advance_to = 1.0;
    term = true;
    cr_assert(fmi3DoStep(c, 0.25, 0.75, false, &ehn, &term, &early, &last) == fmi3OK);
    cr_assert(ehn && !term && !early && last == 1.0);
    /* no event */
    s->advance_rc = VI_FMU_OK, s->advance_to = NAN;
    cr_assert(fmi3DoStep(c, 1.0, 1.0, false, &ehn, &term, &early, &last) == fmi3OK);
    cr_assert(!ehn && !early && last == 2.0);
    /* a discard: where the step stopped */
    s->advance_rc = VI_FMU_DISCARD, s->advance_to = 2.5;
    cr_assert(fmi3DoStep(c, 2.0, 1.0, false, &ehn, &term, &early, &last) == fmi3Discard);
    cr_assert(last == 2.5 && !early && !ehn);
    fmi3FreeInstance(c);

    /* early return without event mode: no event handling asked for */
    c = running3(&b, false, true);
    s = ((vi_fmi_instance *)c)->model;
    s->advance_rc = VI_FMU_EVENT, s->advance_to = 0.5;
    cr_assert(fmi3DoStep(c, 0.0, 1.0, false, &ehn, &term, &early, &last) == fmi3OK);
    cr_assert(!ehn && early && last == 0.5);
    fmi3FreeInstance(c);

    /* without early return the step goes to its end through advance: an event there is the model's error */
    c = running3(&b, true, false);
    cr_assert(fmi3EnterStepMode(c) == fmi3OK);
    s = ((vi_fmi_instance *)c)->model;
    cr_assert(fmi3DoStep(c, 0.0, 1.0, false, &ehn, &term, &early, &last) == fmi3OK && !ehn && !early && last == 1.0);
    s->advance_rc = VI_FMU_EVENT, s->advance_to = 1.5;
    REFUSED(b, fmi3DoStep(c, 1.0, 1.0, false, &ehn, &term, &early, &last), "fmi3DoStep: the model stopped at t = 1.5 s");
    fmi3FreeInstance(c);
}

Test(fmi3, functions_not_provided_are_refused_after_the_state_check)
{
    logbook b = {0};
    fmi3Instance c = running3(&b, false, false);
    size_t n;
    fmi3ValueReference vr = 0;
    double d;
    uint64_t u;
    fmi3IntervalQualifier q;
    int32_t order = 1;
    REFUSED(b, fmi3GetNumberOfVariableDependencies(c, 0, &n), "fmi3GetNumberOfVariableDependencies: not provided (providesPerElementDependencies = false");
    REFUSED(b, fmi3GetVariableDependencies(c, 0, NULL, NULL, NULL, NULL, 0), "fmi3GetVariableDependencies: not provided");
    REFUSED(b, fmi3EnterConfigurationMode(c), "fmi3EnterConfigurationMode: not provided (the FMU has no structural parameters)");
    REFUSED(b, fmi3ExitConfigurationMode(c), "fmi3ExitConfigurationMode: not provided");
    REFUSED(b, fmi3GetIntervalDecimal(c, &vr, 1, &d, &q), "fmi3GetIntervalDecimal: not provided (the FMU has no clocks)");
    REFUSED(b, fmi3GetIntervalFraction(c, &vr, 1, &u, &u, &q), "fmi3GetIntervalFraction: not provided");
    REFUSED(b, fmi3GetShiftDecimal(c, &vr, 1, &d), "fmi3GetShiftDecimal: not provided");
    REFUSED(b, fmi3GetShiftFraction(c, &vr, 1, &u, &u), "fmi3GetShiftFraction: not provided");
    REFUSED(b, fmi3SetIntervalDecimal(c, &vr, 1, &d), "fmi3SetIntervalDecimal: not provided");
    REFUSED(b, fmi3SetIntervalFraction(c, &vr, 1, &u, &u), "fmi3SetIntervalFraction: not provided");
    REFUSED(b, fmi3SetShiftDecimal(c, &vr, 1, &d), "fmi3SetShiftDecimal: not provided");
    REFUSED(b, fmi3SetShiftFraction(c, &vr, 1, &u, &u), "fmi3SetShiftFraction: not provided");
    REFUSED(b, fmi3ActivateModelPartition(c, 0, 0.0), "fmi3ActivateModelPartition: not provided (no Scheduled Execution)");
    REFUSED(b, fmi3GetOutputDerivatives(c, &vr, 1, &order, &d, 1), "fmi3GetOutputDerivatives: not provided (maxOutputDerivativeOrder = 0)");
    cr_assert(fmi3Terminate(c) == fmi3OK);
    REFUSED(b, fmi3GetOutputDerivatives(c, &vr, 1, &order, &d, 1), "fmi3GetOutputDerivatives: not provided");
    ((vi_fmi_instance *)c)->state = VI_ST_FATAL;
    REFUSED(b, fmi3EnterConfigurationMode(c), "fmi3EnterConfigurationMode: not allowed in state 'fatal'");
    ((vi_fmi_instance *)c)->state = VI_ST_TERMINATED;
    cr_assert(fmi3Reset(c) == fmi3OK);
    REFUSED(b, fmi3GetOutputDerivatives(c, &vr, 1, &order, &d, 1), "fmi3GetOutputDerivatives: not allowed in state 'instantiated'");
    fmi3FreeInstance(c);
    cr_assert(fmi3EnterConfigurationMode(NULL) == fmi3Error);
}

Test(fmi3, fmu_states_go_through_the_core_under_the_fmi3_names)
{
    logbook b = {0};
    fmi3Instance c = running3(&b, false, false);
    fmi3FMUState st = NULL, back = NULL;
    REFUSED(b, fmi3GetFMUState(c, NULL), "fmi3GetFMUState: FMUstate is NULL");
    cr_assert(fmi3GetFMUState(c, &st) == fmi3OK);
    size_t size = 0;
    REFUSED(b, fmi3SerializedFMUStateSize(c, st, NULL), "fmi3SerializedFMUStateSize: size is NULL");
    cr_assert(fmi3SerializedFMUStateSize(c, st, &size) == fmi3OK);
    uint8_t *bytes = malloc(size);
    REFUSED(b, fmi3SerializeFMUState(c, st, bytes, size - 1), "fmi3SerializeFMUState: need a buffer");
    cr_assert(fmi3SerializeFMUState(c, st, bytes, size) == fmi3OK);
    REFUSED(b, fmi3DeserializeFMUState(c, bytes, 3, &back), "fmi3DeserializeFMUState: invalid FMU state: size 3");
    cr_assert(fmi3DeserializeFMUState(c, bytes, size, &back) == fmi3OK);
    REFUSED(b, fmi3SetFMUState(c, NULL), "fmi3SetFMUState: invalid FMU state: the state is NULL");
    cr_assert(fmi3SetFMUState(c, back) == fmi3OK);
    cr_assert(fmi3FreeFMUState(c, &back) == fmi3OK && back == NULL && fmi3FreeFMUState(c, &st) == fmi3OK);
    free(bytes);
    fmi3FreeInstance(c);
}
