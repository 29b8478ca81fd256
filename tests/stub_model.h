/*
 * stub_model.h - a model of the generic FMI layer (vi_fmu.h) with no physics, for the unit tests of
 * the layer (tests/test_fmi_layer.c: the layer; tests/test_faces.c: the FMI 2.0 and 3.0 faces on it). It has
 * every hook, Model Exchange too (2 states, 1 event indicator), each of which a test can tell to fail
 * or to answer a given value through the stub's fields; its one definition is in the test that
 * includes it.
 */
#ifndef STUB_MODEL_H
#define STUB_MODEL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_fmu.h"

#define VI_GUID "{core-test}"
#define VI_MODEL_IDENTIFIER "CoreTest"
#define VI_MODEL_DESCRIPTION "a stub model for the layer's unit tests"
#define VI_DEFAULT_EXPERIMENT {.start_s = 0.0, .stop_s = 1.0, .tolerance = 0.0, .step_s = 0.1}
#define VI_CAN_INTERPOLATE_INPUTS 1
#define VI_VARIABLES(X)                                                                                     \
    X(u, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "", 0, "", "an input")                      \
    X(k, Real, none, parameter, tunable, exact, 1.0, VI_ABOVE(0.0), VI_AT(10.0), "1/s", 0, "", "a rate")        \
    X(n, Integer, none, parameter, fixed, exact, 3, VI_AT(1), VI_BELOW(8), "", 0, "", "a count")                \
    X(y, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "", 0, "", "an output")              \
    X(p, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "", 0, "", "state 0")                \
    X(q, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "", 0, "", "state 1")                \
    X(der_p, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "", 0, "", "derivative of p")    \
    X(der_q, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "", 0, "", "derivative of q")    \
    X(b, Boolean, none, input, discrete, exact, 0, VI_NONE, VI_NONE, "", 0, "", "a switch")                     \
    X(label, String, none, parameter, fixed, exact, "abc", VI_NONE, VI_NONE, "", 0, "", "a label")              \
    X(w, Real, none, input, discrete, exact, 0.0, VI_NONE, VI_NONE, "", 0, "", "a discrete input")               \
    X(color, Integer, Color, parameter, tunable, exact, 2, VI_NONE, VI_NONE, "", 0, "", "a choice")
#define VI_ENUMERATIONS(E) E(Color, "a color") E(Shape, "a shape (no variable: its items are no colors)")
#define VI_ITEMS_Color(I) I(Color, red, 2) I(Color, blue, 5) I(Color, white, 2147483647) I(Color, black, -2147483647 - 1)
#define VI_ITEMS_Shape(I) I(Shape, round, 1) I(Shape, square, 6)
VI_TABLE_DECLARE
VI_TABLE_DEFINE

typedef struct {
    vi_parameters par;
    vi_inputs in, din;
    double t;
    double x[2];
    double pad[2]; /* the block a whole number of the hash's 32-byte rounds (the header has a tail) */
} data;
_Static_assert(sizeof(data) % 32 == 0, "the stub's block is a whole number of hash rounds");

/* What the hooks answer: set by a test between calls (fail_*: the hook returns -1). */
typedef struct {
    data d;
    vi_fmu_log_fn log;
    void *env;
    vi_outputs out;          /* what outputs_of hands the layer */
    int outputs_calls;       /* calls of outputs_of, and the value references of the last one */
    unsigned asked[8];
    size_t n_asked;
    int fail_prepare, fail_init, fail_me_init, fail_event, fail_checkpoint, fail_restore, fail_dd;
    int warn_notes;          /* every hook below marked NOTE logs a warning (a note the computation goes on
                                through) and counts it in notes */
    int notes;
    int prepare_calls, changed_calls, terminate_calls, reset_calls, checkpoint_calls, restore_calls, continuous_calls;
    int event_calls, release_calls;
    int restored_running;    /* `running` of the last restore */
    int nan_outputs;         /* y and the ME arrays get NaN */
    int advance_rc;          /* what advance returns, and where it leaves time (NAN: at t_end) */
    double advance_to;
    vi_fmu_event ev;         /* what event_update fills in (fields it leaves alone: -1) */
    int completed;           /* what completed_step answers */
    double setup_start, setup_tol;
    int setup_tol_defined, setup_calls;
} stub;

/* An allocator that counts: calloc and free that count the allocations asked for (n_alloc) and the
 * blocks freed (n_free; free(NULL) is not counted), fail the fail_at-th allocation (0: none), fill
 * each block with 0xab when dirty is set (an importer without calloc semantics), and keep the sizes
 * of the last 16 blocks (block_size: 0 for a block it does not know). */
static int n_alloc, n_free, fail_at, dirty;
static struct {
    const void *p;
    size_t size;
} blocks[16];
static void *counting_alloc(size_t n, size_t size)
{
    if (++n_alloc == fail_at) return NULL;
    void *p = calloc(n, size);
    if (p && dirty) memset(p, 0xab, n * size);
    blocks[n_alloc % 16].p = p, blocks[n_alloc % 16].size = n * size;
    return p;
}
static size_t block_size(const void *p)
{
    for (int i = 0; i < 16; i++)
        if (blocks[i].p == p) return blocks[i].size;
    return 0;
}
static void counting_free(void *p)
{
    if (p) n_free++;
    free(p);
}

/* set_resources fails (global: it is called during instantiation), and the folder it was given last
 * (NULL: none). */
static int fail_resources;
static const char *resources_dir, *resources_block; /* a copy of the folder, and the block it came in */
static char resources_copy[1024];

/* A note of the hook `what` when warn_notes is set. */
#define NOTE(s, what) \
    ((s)->warn_notes ? (void)((s)->notes++, (s)->log((s)->env, VI_FMU_LOG_WARNING, "note: %s", what)) : (void)0)

static void init(void *m, vi_fmu_log_fn log, void *env)
{
    stub *s = m;
    vi_parameters_default(&s->d.par);
    vi_inputs_default(&s->d.in);
    memset(&s->d.din, 0, sizeof s->d.din);
    s->d.x[0] = 0.5, s->d.x[1] = -0.25;
    s->advance_to = NAN;
    s->log = log, s->env = env;
}
static void reset(void *m) { ((stub *)m)->reset_calls++, init(m, ((stub *)m)->log, ((stub *)m)->env); }
static int releases; /* calls of release (global: the instance is freed right after) */
static void release(void *m) { ((stub *)m)->release_calls++, releases++; }
static int set_resources(void *m, const char *dir)
{
    (void)m;
    resources_dir = dir ? resources_copy : NULL;
    resources_block = dir;
    if (dir) snprintf(resources_copy, sizeof resources_copy, "%s", dir);
    return fail_resources ? -1 : 0;
}
static void changed(void *m) { ((stub *)m)->changed_calls++, NOTE((stub *)m, "changed"); }
static void outputs(void *m, void *out)
{
    stub *s = m;
    vi_outputs *o = out;
    o->y = s->nan_outputs ? NAN : s->d.par.k;
    o->p = s->d.x[0], o->q = s->d.x[1], o->der_p = s->d.x[1], o->der_q = -s->d.par.k * s->d.x[0];
}
static const void *outputs_of(void *m, const unsigned vr[], size_t nvr)
{
    stub *s = m;
    s->outputs_calls++;
    NOTE(s, "outputs_of");
    s->n_asked = nvr < 8 ? nvr : 8;
    memcpy(s->asked, vr, s->n_asked * sizeof *vr);
    outputs(m, &s->out);
    return &s->out;
}
static void setup_experiment(void *m, double t0, int td, double tol)
{
    stub *s = m;
    s->setup_calls++, s->setup_start = t0, s->setup_tol_defined = td, s->setup_tol = tol;
    NOTE(s, "setup_experiment");
    s->d.t = t0;
}
static int prepare(void *m) { stub *s = m; return NOTE(s, "prepare"), s->prepare_calls++, s->fail_prepare ? -1 : 0; }
static int initialize(void *m)
{
    stub *s = m;
    NOTE(s, "initialize");
    return s->fail_init ? -1 : 0;
}
static int me_initialize(void *m) { return NOTE((stub *)m, "me_initialize"), ((stub *)m)->fail_me_init ? -1 : 0; }
static int advance(void *m, double t_end)
{
    stub *s = m;
    s->d.t = isnan(s->advance_to) ? t_end : s->advance_to;
    NOTE(s, "advance");
    return s->advance_rc;
}
static int to_event_calls; /* calls of advance_to_event */
static int advance_to_event(void *m, double t_end) { return to_event_calls++, advance(m, t_end); }
static double time_of(const void *m) { return ((const stub *)m)->d.t; }
static void terminate(void *m) { ((stub *)m)->terminate_calls++, NOTE((stub *)m, "terminate"); }
static void *state(void *m) { return &((stub *)m)->d; }
static int checkpoint(void *m)
{
    stub *s = m;
    return NOTE(s, "checkpoint"), s->checkpoint_calls++, s->fail_checkpoint ? -1 : 0;
}
static int restore(void *m, int running)
{
    stub *s = m;
    s->restore_calls++, s->restored_running = running;
    NOTE(s, "restore");
    return s->fail_restore ? -1 : 0;
}
/* The model's own check of a saved block: x[0] = 666 is bad (with a reason), 777 bad without one. */
static int state_check(const void *block, int running, char *msg, size_t n)
{
    (void)running;
    const data *d = block;
    if (d->x[0] == 777.0) return -1;
    if (d->x[0] == 666.0) return snprintf(msg, n, "x[0] = 666 is bad"), -1;
    return 0;
}
static const char *message(const void *m) { return (void)m, "the stub says no"; }
static void set_time(void *m, double t) { ((stub *)m)->d.t = t, NOTE((stub *)m, "set_time"); }
static void get_states(void *m, double x[])
{
    stub *s = m;
    x[0] = s->d.x[0], x[1] = s->nan_outputs ? NAN : s->d.x[1];
}
static void set_states(void *m, const double x[])
{
    ((stub *)m)->d.x[0] = x[0], ((stub *)m)->d.x[1] = x[1];
    NOTE((stub *)m, "set_states");
}
static void derivatives(void *m, double dx[])
{
    stub *s = m;
    dx[0] = s->d.x[1], dx[1] = s->nan_outputs ? NAN : -s->d.par.k * s->d.x[0];
    NOTE(s, "derivatives");
}
static void indicators(void *m, double z[])
{
    stub *s = m;
    z[0] = s->nan_outputs ? NAN : s->d.x[0] - 1.0;
    NOTE(s, "indicators");
}
static void nominals(const void *m, double nominal[]) { (void)m, nominal[0] = 1.0, nominal[1] = 2.0; }
static int event_update(void *m, vi_fmu_event *ev)
{
    stub *s = m;
    s->event_calls++;
    NOTE(s, "event_update");
    if (s->fail_event) return -1;
    *ev = s->ev;
    return 0;
}
static int completed_step(void *m) { return NOTE((stub *)m, "completed_step"), ((stub *)m)->completed; }
static void enter_continuous(void *m) { ((stub *)m)->continuous_calls++, NOTE((stub *)m, "enter_continuous"); }
/* J: d(der_p)/dq = 1, d(der_q)/dp = -k, dy/du = 2, every other partial 0. */
static int directional_derivative(void *m, const unsigned unknown[], size_t nu, const unsigned known[], size_t nk,
                                  const double dknown[], double dunknown[])
{
    stub *s = m;
    NOTE(s, "directional_derivative");
    if (s->fail_dd) return -1;
    for (size_t i = 0; i < nu; i++) {
        dunknown[i] = 0.0;
        for (size_t j = 0; j < nk; j++) {
            double J = unknown[i] == VI_VR_der_p && known[j] == VI_VR_q   ? 1.0
                       : unknown[i] == VI_VR_der_q && known[j] == VI_VR_p ? -s->d.par.k
                       : unknown[i] == VI_VR_y && known[j] == VI_VR_u     ? 2.0
                                                                          : 0.0;
            dunknown[i] += J * dknown[j];
        }
    }
    return 0;
}

/* The value references of the states and of their derivatives, each array followed by that of the
 * parameter k: a loop that ran one element too far would take k for a state or a derivative. */
static const struct {
    unsigned vrs[2], after;
} states_k = {{VI_VR_p, VI_VR_q}, VI_VR_k}, derivatives_k = {{VI_VR_der_p, VI_VR_der_q}, VI_VR_k};

/* The layer reads the stub's rows from here: the table, then a row past it that looks like a Real input
 * (u's storage), so that a read beyond nvariables shows as a variable that should not be there
 * (out-of-bounds reads of the table itself land past AddressSanitizer's red zone). */
static const struct {
    vi_variable rows[VI_NVARS];
    vi_variable beyond;
} stub_rows = {{VI_VARIABLES(VI_ROW_)},
               VI_ROW_(u, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "", 0, "", "not a variable")};

const vi_fmu_model vi_fmu_this_model = {
    VI_FMU_ROWS_FIELDS(stub, data, stub_rows.rows), .init = init, .reset = reset, .release = release,
    .set_resources = set_resources, .changed = changed, .outputs = outputs, .outputs_of = outputs_of,
    .setup_experiment = setup_experiment, .prepare = prepare, .initialize = initialize, .advance = advance,
    .advance_to_event = advance_to_event,
    .time = time_of, .terminate = terminate, .state = state, .checkpoint = checkpoint, .restore = restore,
    .state_check = state_check, .message = message, .n_states = 2, .n_indicators = 1, .state_vrs = states_k.vrs,
    .derivative_vrs = derivatives_k.vrs, .me_initialize = me_initialize, .set_time = set_time,
    .get_states = get_states, .set_states = set_states, .derivatives = derivatives, .indicators = indicators,
    .nominals = nominals, .event_update = event_update, .completed_step = completed_step,
    .enter_continuous = enter_continuous, .directional_derivative = directional_derivative,
};

#endif
