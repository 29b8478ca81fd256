/*
 * order.c - the Model Exchange call-order property of the harness (fuzz.h, fz_call_order), for both
 * FMI versions: each gives its functions in an fz_me_face (calls_fmi2me.c, calls_fmi3.c).
 *
 * FMI 2.0 (section 3.2.3) and FMI 3.0 let an importer in Continuous-Time Mode set the time, the
 * continuous states and the continuous inputs in any order before it asks for derivatives, event
 * indicators or outputs. So at one point of a run the harness takes an FMU state S, makes the sets
 * of order A (final values only) and asks the three getters (in an order of their own); then, each
 * time from S restored, order A again and order B (another order of the same final values, with up
 * to FZ_DECOYS earlier sets of other values, and the getters in another order). Two properties:
 *   - "call-order": order B gives the statuses and bits of order A, both from S restored;
 *   - "restore": S restored gives back the continuous states read when it was taken, and order A
 *     after the restore the statuses and bits it gave before.
 * A set that is not fmi2OK/fmi3OK ends the check without a finding. VI_FUZZ_OFF (fuzz.h) can leave
 * either property out.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"

#define MODEL (&vi_fmu_this_model)
#define FZ_ME_MAX 16   /* states, indicators and continuous inputs the check handles */
#define FZ_OUT_MAX 64  /* Real outputs compared */
#define FZ_DECOYS 3    /* the most sets of other values in order B */
#define FZ_ACTIONS (2 + FZ_ME_MAX + FZ_DECOYS)

enum { SET_TIME, SET_STATES, SET_INPUT };

typedef struct {
    int kind;     /* SET_* */
    int input;    /* SET_INPUT: which continuous input */
    int decoy;    /* 1: a value other than the final one */
    double t, u;  /* SET_TIME, SET_INPUT */
    double x[FZ_ME_MAX];
} action;

typedef struct {
    int status[3];
    double value[3][FZ_OUT_MAX];
} answers;

typedef struct {
    unsigned input_vr[FZ_ME_MAX], output_vr[FZ_OUT_MAX];
    size_t n_inputs, n_outputs, nx, nz;
} variables;

/* The continuous Real inputs (settable in Continuous-Time Mode) and the Real outputs of the model. */
static void find_variables(variables *v)
{
    v->n_inputs = v->n_outputs = 0;
    v->nx = (size_t)MODEL->n_states, v->nz = (size_t)MODEL->n_indicators;
    for (int i = 0; i < MODEL->nvariables; i++) {
        const vi_variable *w = &MODEL->variables[i];
        if (w->type != VI_Real) continue;
        if (strcmp(w->causality, "input") == 0 && strcmp(w->variability, "continuous") == 0 && v->n_inputs < FZ_ME_MAX)
            v->input_vr[v->n_inputs++] = (unsigned)i;
        if (strcmp(w->causality, "output") == 0 && v->n_outputs < FZ_OUT_MAX) v->output_vr[v->n_outputs++] = (unsigned)i;
    }
}

/* A shuffle of a[0..n) by bytes of the input (Fisher-Yates). */
static void shuffle(fz_reader *r, void *base, size_t n, size_t size)
{
    unsigned char tmp[sizeof(action)], *a = base;
    for (size_t i = n; i > 1; i--) {
        size_t j = fz_u8(r) % i;
        memcpy(tmp, a + (i - 1) * size, size);
        memcpy(a + (i - 1) * size, a + j * size, size);
        memcpy(a + j * size, tmp, size);
    }
}

/* A state near x (x scaled by 1 + k/1024, k a signed byte) or any value fz_real gives. */
static void near_states(fz_reader *r, const double *x0, double *x, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        uint8_t how = fz_u8(r);
        x[i] = how < 192 ? x0[i] * (1.0 + (int8_t)fz_u8(r) / 1024.0) : fz_real(r, x0[i] != 0.0 ? x0[i] : 1e-4);
    }
}

static double later(fz_reader *r, double t)
{
    static const double dt[] = {0.0, 1e-12, 1e-9, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2};
    return t + dt[fz_u8(r) % 8];
}

static int run_set(fz_slot *s, const fz_me_face *f, const variables *v, const action *a)
{
    switch (a->kind) {
    case SET_TIME: fz_trace("    order: set time %.17g%s", a->t, a->decoy ? " (decoy)" : ""); return f->set_time(s, a->t);
    case SET_STATES:
        fz_trace("    order: set states %.17g %.17g%s", a->x[0], v->nx > 1 ? a->x[1] : 0.0, a->decoy ? " (decoy)" : "");
        return f->set_states(s, a->x, v->nx);
    default:
        fz_trace("    order: set input vr %u = %.17g%s", v->input_vr[a->input], a->u, a->decoy ? " (decoy)" : "");
        return f->set_reals(s, &v->input_vr[a->input], 1, &a->u);
    }
}

/* The sets of one order, then the getters in the order `getters`; 0 when a set was not OK. */
static int run(fz_slot *s, const fz_me_face *f, const variables *v, const action *a, size_t n, const int getters[3],
               answers *out)
{
    for (size_t i = 0; i < n; i++)
        if (run_set(s, f, v, &a[i]) != 0) return 0;
    memset(out, 0, sizeof *out);
    for (int k = 0; k < 3; k++) {
        int g = getters[k];
        double *x = out->value[g];
        out->status[g] = g == 0 ? f->derivatives(s, x, v->nx)
                         : g == 1 ? f->indicators(s, x, v->nz)
                                  : f->get_reals(s, v->output_vr, v->n_outputs, x);
    }
    return 1;
}

/* The same statuses, and with OK the same bits, or a finding naming what differs. */
static void compare(const fz_me_face *f, const variables *v, const answers *a, const answers *b, const char *what,
                    const char *first)
{
    static const char *const kinds[] = {"derivative", "event indicator", "output"};
    for (int g = 0; g < 3; g++) {
        size_t n = g == 0 ? v->nx : g == 1 ? v->nz : v->n_outputs;
        if (a->status[g] != b->status[g])
            fz_fail("%s: %s returned %d after %s and %d after %s", what, f->name[g], a->status[g], first, b->status[g],
                    what);
        if (a->status[g] != 0) continue;
        for (size_t i = 0; i < n; i++)
            if (memcmp(&a->value[g][i], &b->value[g][i], sizeof(double)) != 0)
                fz_fail("%s: %s %zu%s%s is %.17g after %s and %.17g after %s (same time, states and inputs)", what,
                        kinds[g], i, g == 2 ? ", vr " : "", g == 2 ? MODEL->variables[v->output_vr[i]].name : "",
                        a->value[g][i], first, b->value[g][i], what);
    }
}

/* Order A: the final values in an order of the input. Order B: the same, shuffled again, with decoys
 * (other values of a kind, each moved before the final set of its kind). Returns the lengths. */
static void make_orders(fz_reader *r, const variables *v, double t0, const double *x0, action *a, size_t *na,
                        action *b, size_t *nb)
{
    uint8_t which = fz_u8(r);
    size_t n = 0;
    if (which & 1) a[n++] = (action){.kind = SET_TIME, .t = later(r, t0)};
    if (which & 2) a[n] = (action){.kind = SET_STATES}, near_states(r, x0, a[n].x, v->nx), n++;
    for (size_t i = 0; i < v->n_inputs; i++)
        if (which >> (2 + i % 6) & 1) {
            const vi_variable *w = &MODEL->variables[v->input_vr[i]];
            a[n++] = (action){.kind = SET_INPUT, .input = (int)i, .u = fz_real(r, w->start != 0.0 ? w->start : 1e-4)};
        }
    *na = n;
    shuffle(r, a, n, sizeof *a);
    memcpy(b, a, n * sizeof *a);
    size_t decoys = n ? fz_u8(r) % (FZ_DECOYS + 1) : 0;
    for (size_t k = 0; k < decoys; k++) {
        action d = a[fz_u8(r) % n];
        d.decoy = 1;
        if (d.kind == SET_TIME) d.t = later(r, t0);
        else if (d.kind == SET_STATES) near_states(r, x0, d.x, v->nx);
        else d.u = fz_real(r, d.u);
        b[n + k] = d;
    }
    *nb = n + decoys;
    shuffle(r, b, *nb, sizeof *b);
    for (size_t i = 0; i < *nb; i++) /* a decoy after the final set of its kind goes before it */
        for (size_t j = 0; j < i; j++)
            if (b[i].decoy && !b[j].decoy && b[i].kind == b[j].kind && b[i].input == b[j].input) {
                action tmp = b[i];
                b[i] = b[j], b[j] = tmp;
            }
}

/* Restore S (taken at states x0): 0 when it was fmi2OK/fmi3OK; the states must then be x0's bits. */
static int restore(fz_slot *s, const fz_me_face *f, const variables *v, void *saved, unsigned mask,
                   const double *x0)
{
    if (f->restore(s, saved, mask) != 0) return -1;
    double x[FZ_ME_MAX];
    if (!fz_off("restore") && f->get_states(s, x, v->nx) == 0 && memcmp(x, x0, v->nx * sizeof *x) != 0)
        for (size_t i = 0; i < v->nx; i++)
            if (memcmp(&x[i], &x0[i], sizeof *x) != 0)
                fz_fail("restore: the FMU state gives back state %zu = %.17g, taken at %.17g", i, x[i], x0[i]);
    return 0;
}

static void getter_order(fz_reader *r, int g[3])
{
    g[0] = 0, g[1] = 1, g[2] = 2;
    shuffle(r, g, 3, sizeof g[0]);
}

void fz_call_order(fz_slot *s, fz_reader *r, const fz_me_face *f)
{
    variables v;
    find_variables(&v);
    if (!s->c || s->fmu_type != fmi2ModelExchange || !(s->mask & FZ_CONTINUOUS) || isnan(s->t) || v.nx == 0 ||
        v.nx > FZ_ME_MAX || v.nz > FZ_ME_MAX)
        return;
    if (fz_off("call-order") && fz_off("restore")) return;
    double x0[FZ_ME_MAX], t0 = s->t;
    if (f->get_states(s, x0, v.nx) != 0) return;
    action a[FZ_ACTIONS], b[FZ_ACTIONS];
    size_t na, nb;
    make_orders(r, &v, t0, x0, a, &na, b, &nb);
    int ga[3], gb[3];
    getter_order(r, ga);
    getter_order(r, gb);
    unsigned mask = s->mask;
    void *saved = NULL;
    if (f->save(s, &saved) != 0) return;
    answers first, again, other;
    fz_trace("    order A, then from the saved state order A again and order B (%zu sets, %zu with decoys)", na, nb);
    int done = run(s, f, &v, a, na, ga, &first) && restore(s, f, &v, saved, mask, x0) == 0 &&
               run(s, f, &v, a, na, ga, &again) && restore(s, f, &v, saved, mask, x0) == 0 &&
               run(s, f, &v, b, nb, gb, &other);
    if (done) {
        if (!fz_off("restore")) compare(f, &v, &first, &again, "restore: order A from the restored FMU state", "order A");
        if (!fz_off("call-order")) compare(f, &v, &again, &other, "call order: order B", "order A (both from the FMU state)");
        for (size_t i = 0; i < na; i++)
            if (a[i].kind == SET_TIME) s->t = a[i].t;
    } else {
        s->t = restore(s, f, &v, saved, mask, x0) == 0 ? t0 : NAN; /* NAN: unknown */
    }
    f->drop(s, &saved);
}
