/* layer_model.c - LayerTest (see layer_variables.h): the model hooks of the generic FMI layer. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "layer_variables.h"
#include "vi_check.h"
#include "vi_fmu.h"

VI_TABLE_DEFINE

/* Everything saved in an FMU state: plain data. */
typedef struct {
    vi_parameters par;
    vi_inputs in, din;
    int inputs_changed;
    double t_start, t, x;
    double k, u, du, t_u; /* active rate and input ramp */
    long steps;
    double k_initial;
    double checkpoint_time; /* written by the checkpoint hook */
    /* Model Exchange */
    int model_exchange; /* initialized for an importer's integrator: the input acts as it is set */
    long events;
    int above;      /* x > x_event at the last event */
    int time_event; /* the time event at t_event happened */
} layer_data;

typedef struct {
    layer_data d;
    double resource_value; /* read once at instantiation: not part of the state */
    vi_fmu_log_fn log;
    void *env;
    char msg[256];
} layer;

static void init(void *m, vi_fmu_log_fn log, void *env)
{
    layer *L = m;
    memset(&L->d, 0, sizeof L->d);
    vi_parameters_default(&L->d.par);
    vi_inputs_default(&L->d.in);
    L->log = log;
    L->env = env;
}

static void reset(void *m)
{
    layer *L = m;
    init(m, L->log, L->env);
}

static void release(void *m) { (void)m; }

static int set_resources(void *m, const char *dir)
{
    layer *L = m;
    char path[2048];
    L->resource_value = -1.0;
    if (!dir || vi_snprintf(path, sizeof path, "%s/value.txt", dir) >= (int)sizeof path) return 0;
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char text[64], *end = text; /* read in the C syntax whatever the process's locale (fscanf follows it) */
    if (fgets(text, sizeof text, f)) L->resource_value = vi_strtod(text, &end);
    if (end == text) L->resource_value = -1.0;
    fclose(f);
    return 0;
}

static void changed(void *m) { ((layer *)m)->d.inputs_changed = 1; }

static void outputs(void *m, void *out)
{
    const layer *L = m;
    vi_outputs *o = out;
    o->x = L->d.x;
    o->steps = (int)L->d.steps;
    o->label_length = (int)strlen(L->d.par.label);
    o->resource_value = L->resource_value;
    o->k_initial = L->d.k_initial;
    o->checkpoint_time = L->d.checkpoint_time;
    o->events = (int)L->d.events;
    /* the input in force now: as set (Model Exchange), or on the step's ramp (Co-Simulation) */
    const layer_data *d = &L->d;
    double u = d->model_exchange ? d->in.u : d->u + d->du * (d->t - d->t_u);
    o->der_x = -d->k * d->x + u;
}

static void setup_experiment(void *m, double start_time, int tolerance_defined, double tolerance)
{
    (void)tolerance_defined, (void)tolerance;
    ((layer *)m)->d.t_start = start_time;
}

static int prepare(void *m)
{
    layer *L = m;
    layer_data *d = &L->d;
    d->t = d->t_start;
    d->x = d->par.x0;
    d->k = d->k_initial = d->par.k;
    d->u = d->in.u, d->du = d->din.u, d->t_u = d->t;
    d->inputs_changed = 0;
    d->steps = 0;
    d->events = 0;
    d->above = d->x > d->par.x_event;
    d->time_event = 0;
    return 0;
}

static int initialize(void *m) { return prepare(m); }

static int me_initialize(void *m)
{
    ((layer *)m)->d.model_exchange = 1;
    return prepare(m);
}

/* x' = -k x + u + du (t - t_u) from (t0, x0) to t1, exactly. */
static double solve(const layer_data *d, double t0, double x0, double t1)
{
    double B = d->du / d->k, tau0 = t0 - d->t_u, tau1 = t1 - d->t_u;
    double A = (d->u - B) / d->k; /* x_p(tau) = A + B tau */
    return A + B * tau1 + (x0 - A - B * tau0) * exp(-d->k * (t1 - t0));
}

static int advance(void *m, double t_end)
{
    layer *L = m;
    layer_data *d = &L->d;
    if (d->inputs_changed) { /* new input ramp and tunable k (> 0: the layer checks its range) from now on */
        d->u = d->in.u, d->du = d->din.u, d->t_u = d->t, d->k = d->par.k;
        d->inputs_changed = 0;
    }
    if (d->par.fail_at > d->t && d->par.fail_at < t_end) {
        vi_snprintf(L->msg, sizeof L->msg, "failed at fail_at = %g s", d->par.fail_at);
        return VI_FMU_ERROR;
    }
    int stop = d->par.discard_at > d->t && d->par.discard_at < t_end;
    double t1 = stop ? d->par.discard_at : t_end;
    d->x = solve(d, d->t, d->x, t1);
    d->t = t1;
    d->steps++;
    if (stop) {
        vi_snprintf(L->msg, sizeof L->msg, "stopped at t = %.17g s (discard_at)", d->t);
        return VI_FMU_DISCARD;
    }
    return VI_FMU_OK;
}

static int state_check(const void *state, int running, char *msg, size_t n)
{
    const layer_data *d = state;
    if (!isfinite(d->t_start)) VI_FAIL(msg, n, "t_start = %g is not finite", d->t_start);
    if (d->inputs_changed != 0 && d->inputs_changed != 1)
        VI_FAIL(msg, n, "inputs_changed = %d is not 0 or 1", d->inputs_changed);
    if (d->model_exchange != 0 && d->model_exchange != 1)
        VI_FAIL(msg, n, "model_exchange = %d is not 0 or 1", d->model_exchange);
    if (!running) return 0; /* the rest is computed at initialization */
    if (!(isfinite(d->t) && d->t >= d->t_start)) VI_FAIL(msg, n, "t = %g is not finite or before t_start", d->t);
    if (!isfinite(d->x)) VI_FAIL(msg, n, "x = %g is not finite", d->x);
    if (!(d->k > 0.0 && isfinite(d->k))) VI_FAIL(msg, n, "k = %g is not finite and positive", d->k);
    if (!isfinite(d->u) || !isfinite(d->du) || !isfinite(d->t_u)) VI_FAIL(msg, n, "the input ramp is not finite");
    if (d->steps < 0) VI_FAIL(msg, n, "steps = %ld is negative", d->steps);
    if (d->events < 0 || (d->above != 0 && d->above != 1) || (d->time_event != 0 && d->time_event != 1))
        VI_FAIL(msg, n, "events = %ld, above = %d, time_event = %d: not a count and two flags", d->events, d->above,
                d->time_event);
    return 0;
}

static int checkpoint(void *m)
{
    layer_data *d = &((layer *)m)->d;
    d->checkpoint_time = d->t;
    return 0;
}

static double time_of(const void *m) { return ((const layer *)m)->d.t; }
static void *state(void *m) { return &((layer *)m)->d; }
static const char *message(const void *m) { return ((const layer *)m)->msg; }

/* ---- Model Exchange: x' = -k x + u with the input as set ---- */

static const unsigned state_vrs[1] = {VI_VR_x}, derivative_vrs[1] = {VI_VR_der_x};

static void set_time(void *m, double t) { ((layer *)m)->d.t = t; }
static void get_states(void *m, double x[]) { x[0] = ((layer *)m)->d.x; }
static void set_states(void *m, const double x[]) { ((layer *)m)->d.x = x[0]; }
static void derivatives(void *m, double dx[])
{
    const layer_data *d = &((layer *)m)->d;
    dx[0] = -d->k * d->x + d->in.u;
}
static void indicators(void *m, double z[])
{
    const layer_data *d = &((layer *)m)->d;
    z[0] = d->x - d->par.x_event;
}
static void nominals(const void *m, double nominal[]) { (void)m, nominal[0] = 1.0; }

static int event_update(void *m, vi_fmu_event *ev)
{
    layer *L = m;
    layer_data *d = &L->d;
    d->k = d->par.k; /* tunable: from this event on */
    d->u = d->in.u, d->du = 0.0, d->t_u = d->t;
    d->inputs_changed = 0;
    if ((d->x > d->par.x_event) != d->above) { /* a state event */
        d->events++;
        d->x += d->par.jump;
        ev->states_changed = d->par.jump != 0.0;
        L->log(L->env, VI_FMU_LOG_EVENTS, "t = %.17g s: x crossed x_event", d->t);
    }
    d->above = d->x > d->par.x_event;
    if (d->par.t_event > 0.0 && !d->time_event && d->t >= d->par.t_event) {
        d->events++;
        d->time_event = 1;
        L->log(L->env, VI_FMU_LOG_EVENTS, "t = %.17g s: time event", d->t);
    }
    ev->next_time_defined = d->par.t_event > d->t && !d->time_event;
    ev->next_time = d->par.t_event;
    ev->another_pass = d->par.chatter;
    return 0;
}

/* An event is due when the time event was stepped over. */
static int completed_step(void *m)
{
    const layer_data *d = &((layer *)m)->d;
    return d->par.t_event > 0.0 && !d->time_event && d->t >= d->par.t_event;
}

static int directional_derivative(void *m, const unsigned unknown[], size_t n_unknown, const unsigned known[],
                                  size_t n_known, const double dknown[], double dunknown[])
{
    const layer_data *d = &((layer *)m)->d;
    for (size_t i = 0; i < n_unknown; i++) {
        dunknown[i] = 0.0;
        for (size_t j = 0; j < n_known; j++) {
            double p = 0.0;
            if (unknown[i] == VI_VR_der_x) p = known[j] == VI_VR_x ? -d->k : known[j] == VI_VR_u ? 1.0 : 0.0;
            if (unknown[i] == VI_VR_x) p = known[j] == VI_VR_x;
            dunknown[i] += p * dknown[j];
        }
    }
    return 0;
}

const vi_fmu_model vi_fmu_this_model = {
    VI_FMU_TABLE_FIELDS(layer, layer_data),
    .init = init,
    .reset = reset,
    .release = release,
    .set_resources = set_resources,
    .changed = changed,
    .outputs = outputs,
    .setup_experiment = setup_experiment,
    .prepare = prepare,
    .initialize = initialize,
    .advance = advance,
    .time = time_of,
    .state = state,
    .checkpoint = checkpoint,
    .state_check = state_check,
    .message = message,
    .n_states = 1,
    .n_indicators = 1,
    .state_vrs = state_vrs,
    .derivative_vrs = derivative_vrs,
    .me_initialize = me_initialize,
    .set_time = set_time,
    .get_states = get_states,
    .set_states = set_states,
    .derivatives = derivatives,
    .indicators = indicators,
    .nominals = nominals,
    .event_update = event_update,
    .completed_step = completed_step,
    .directional_derivative = directional_derivative,
};
