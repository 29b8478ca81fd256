/*
 * vi_fmu_contact.c - the contact model as a model of the generic FMI layer (vi_fmu.h): an instance
 * (vi_contact_instance.h) holds the FMI storage and one run of the model (vi_run.h) under two
 * drivers, Co-Simulation on vi_sim (its own solver) and Model Exchange on vi_me (the importer's); an
 * instance uses one of them. The FMI calls and their checks live in the layer (src/fmi/vi_fmi_*.c and
 * the faces vi_fmi2.c, vi_fmi3.c); this file maps the layer's hooks and value references onto the
 * instance, its drivers and the model.
 */
#include <stddef.h>

#include "vi_contact_instance.h"
#include "vi_fmu.h"

_Static_assert((int)VI_FMU_LOG_EVENTS == (int)VI_LOG_EVENTS && (int)VI_FMU_LOG_SOLVER == (int)VI_LOG_SOLVER &&
                   (int)VI_FMU_LOG_WARNING == (int)VI_LOG_WARNING && (int)VI_FMU_LOG_ERROR == (int)VI_LOG_ERROR,
               "vi_sim logs with the layer's categories");
_Static_assert((int)VI_FMU_OK == (int)VI_SIM_OK && (int)VI_FMU_DISCARD == (int)VI_SIM_DISCARD &&
                   (int)VI_FMU_ERROR == (int)VI_SIM_ERROR && (int)VI_FMU_EVENT == (int)VI_SIM_EVENT,
               "vi_sim's results are the layer's");

/* One instance of the FMU, in Co-Simulation or in Model Exchange (vi_contact_instance.h): its data
 * (the FMI storage, the run's and each driver's), the run over it and both drivers over the run;
 * `e.active` says whether Model Exchange runs. */
typedef vi_contact contact_instance;

static void init(void *m, vi_fmu_log_fn log, void *env) { vi_contact_init(m, log, env); }
static void reset(void *m) { vi_contact_reset(m); }
static void release(void *m) { vi_contact_free(m); }

static vi_run *run_of(void *m) { return &((contact_instance *)m)->r; }
static vi_sim *sim_of(void *m) { return &((contact_instance *)m)->s; }
static vi_me *me_of(void *m) { return &((contact_instance *)m)->e; }

static int set_resources(void *m, const char *dir)
{
    vi_run_set_resources(run_of(m), dir);
    return 0;
}

static void changed(void *m) { ((contact_instance *)m)->d.run.inputs_changed = 1; }
static void outputs(void *m, void *out) { *(vi_outputs *)out = *vi_contact_outputs_of(m, VI_OUT_ALL); }

/* The group of outputs (VI_OUT_*) of each variable by value reference (0: no output or calculated
 * parameter). */
static const unsigned char output_groups[VI_NVARS] = {
    [VI_VR_delta] = VI_OUT_STATE, [VI_VR_v] = VI_OUT_STATE, [VI_VR_contact] = VI_OUT_STATE,
    [VI_VR_mode] = VI_OUT_STATE, [VI_VR_n_impacts] = VI_OUT_STATE, [VI_VR_yC] = VI_OUT_PLATFORM,
    [VI_VR_y] = VI_OUT_PLATFORM, [VI_VR_F] = VI_OUT_FORCE, [VI_VR_delta_c] = VI_OUT_MEMORY,
    [VI_VR_delta_f] = VI_OUT_MEMORY, [VI_VR_delta_p] = VI_OUT_MEMORY, [VI_VR_Rbar] = VI_OUT_MEMORY,
    [VI_VR_W_plastic] = VI_OUT_MEMORY, [VI_VR_E_star] = VI_OUT_CALCULATED, [VI_VR_R_star] = VI_OUT_CALCULATED,
    [VI_VR_F_Y] = VI_OUT_CALCULATED, [VI_VR_delta_Y] = VI_OUT_CALCULATED, [VI_VR_k_lin] = VI_OUT_CALCULATED,
    [VI_VR_f_contact] = VI_OUT_CALCULATED, [VI_VR_F_mean] = VI_OUT_MEAN, [VI_VR_k_contact] = VI_OUT_STIFFNESS,
    [VI_VR_der_y] = VI_OUT_DERIVATIVES, [VI_VR_der_v] = VI_OUT_DERIVATIVES,
    [VI_VR_W_dissipated] = VI_OUT_MEMORY, [VI_VR_E_contact] = VI_OUT_MEMORY, [VI_VR_F_peak] = VI_OUT_FORCE,
    [VI_VR_W_damping] = VI_OUT_MEMORY, [VI_VR_der_W_damping] = VI_OUT_DERIVATIVES,
    [VI_VR_F_upper] = VI_OUT_FORCE, [VI_VR_delta_upper] = VI_OUT_STATE, [VI_VR_mode_upper] = VI_OUT_STATE,
    [VI_VR_n_impacts_upper] = VI_OUT_STATE};

/* Only the groups of outputs the get call reads (reading y computes no force and no plastic work). */
static const void *outputs_of(void *m, const unsigned vr[], size_t nvr)
{
    unsigned groups = 0;
    for (size_t i = 0; i < nvr; i++) groups |= vr[i] < VI_NVARS ? output_groups[vr[i]] : 0u;
    return vi_contact_outputs_of(m, groups);
}

static void setup_experiment(void *m, double start_time, int tolerance_defined, double tolerance)
{
    vi_contact_data *d = &((contact_instance *)m)->d;
    d->t_start = start_time;
    d->tolerance = tolerance_defined ? tolerance : 0.0;
}

static int prepare(void *m) { return vi_run_prepare(run_of(m)); }

static int initialize(void *m)
{
    vi_sim *s = sim_of(m);
    if (vi_sim_initialize(s) < 0) return -1;
    vi_sim_log_solver(s);
    vi_hybrid_log_start(&s->engine, s->d->t, s->d->x);
    return 0;
}

static int advance(void *m, double t_end) { return vi_sim_advance(sim_of(m), t_end); }
static int advance_to_event(void *m, double t_end) { return vi_sim_advance_until(sim_of(m), t_end, 1); }
static double time_of(const void *m) { return ((const contact_instance *)m)->d.run.t; }

/* The statistics of the solver that ran; Model Exchange's solver is the importer's: its events only. */
static void terminate(void *m)
{
    const contact_instance *inst = m;
    const vi_sim *s = &inst->s;
    if (inst->e.active) {
        s->log(s->log_env, VI_LOG_SOLVER, "Model Exchange statistics: %ld events", vi_hybrid_event_count(&inst->r.engine));
        return;
    }
    vi_solver_stats st;
    vi_sim_statistics(s, &st);
    s->log(s->log_env, VI_LOG_SOLVER,
           "%s statistics: %ld steps, %ld rhs evaluations, %ld Jacobian evaluations, %ld nonlinear iterations, "
           "%ld nonlinear failures, %ld error test failures, %ld guard evaluations, %ld restarts, %ld events",
           st.method ? st.method : "solver", st.steps, st.rhs_evals, st.jac_evals, st.nonlin_iters, st.nonlin_fails, st.err_test_fails, st.guard_evals,
           st.resets, vi_hybrid_event_count(&inst->r.engine));
}

static void *state(void *m) { return &((contact_instance *)m)->d; }

/* A state saved before initialization needs no solver: fmi2ExitInitializationMode creates one. */
static int restore(void *m, int running)
{
    if (!running) return me_of(m)->active = 0;
    return running == VI_FMU_RUNNING_ME ? vi_me_restore(me_of(m), 1) : vi_sim_restore(sim_of(m));
}

/* A state taken from a running instance is its complete continuation (doc/model.md section 7.5). */
static int checkpoint(void *m) { return me_of(m)->active ? vi_me_checkpoint(me_of(m)) : vi_sim_checkpoint(sim_of(m)); }

/* Every field of a saved block (doc/model.md section 7.6); before initialization only the settings exist. */
static int state_check(const void *state, int running, char *msg, size_t n)
{
    return vi_contact_state_check(state, running, running == VI_FMU_RUNNING_ME, msg, n);
}

static const char *message(const void *m) { return ((const contact_instance *)m)->r.msg; }

/* ---- Model Exchange ---- */

static const unsigned state_vrs[VI_ME_NSTATES] = {VI_VR_y, VI_VR_v, VI_VR_W_damping};
static const unsigned derivative_vrs[VI_ME_NSTATES] = {VI_VR_der_y, VI_VR_der_v, VI_VR_der_W_damping};

static int me_initialize(void *m) { return vi_me_initialize(me_of(m)); }
static void set_time(void *m, double t) { vi_me_set_time(me_of(m), t); }
static void get_states(void *m, double x[]) { vi_me_get_states(me_of(m), x); }
static void set_states(void *m, const double x[]) { vi_me_set_states(me_of(m), x); }
static void derivatives(void *m, double dx[]) { vi_me_derivatives(me_of(m), dx); }
static void indicators(void *m, double z[]) { vi_me_indicators(me_of(m), z); }
static void nominals(const void *m, double nominal[]) { vi_me_nominals(&((const contact_instance *)m)->e, nominal); }
static int completed_step(void *m) { return vi_me_completed_step(me_of(m)); }
static void enter_continuous(void *m) { vi_me_enter_continuous(me_of(m)); }

static int event_update(void *m, vi_fmu_event *ev)
{
    vi_me_event e;
    if (vi_me_event_update(me_of(m), &e) < 0) return -1;
    *ev = (vi_fmu_event){.another_pass = e.another_pass, .terminate = e.terminate, .states_changed = e.states_changed,
                         .next_time_defined = e.next_time_defined, .next_time = e.next_time};
    return 0;
}

/* The Jacobian's index sets in value references: the row of vi_me_jacobian of an unknown (-1: its
 * partials are zero), and the column of a known. */
static int jacobian_row(unsigned vr)
{
    switch (vr) {
    case VI_VR_der_y: return VI_ME_DER_Y;
    case VI_VR_der_v: return VI_ME_DER_V;
    case VI_VR_F: return VI_ME_F;
    case VI_VR_F_mean: return VI_ME_F_MEAN;
    case VI_VR_delta: return VI_ME_DELTA;
    case VI_VR_y: return VI_ME_Y;
    case VI_VR_v: return VI_ME_V;
    case VI_VR_yC: return VI_ME_YC;
    case VI_VR_k_contact: return VI_ME_K_CONTACT;
    case VI_VR_delta_c: return VI_ME_DELTA_C;
    case VI_VR_delta_f: return VI_ME_DELTA_F;
    case VI_VR_Rbar: return VI_ME_RBAR;
    case VI_VR_delta_p: return VI_ME_DELTA_P;
    case VI_VR_W_plastic: return VI_ME_W_PLASTIC;
    case VI_VR_der_W_damping: return VI_ME_DER_W;
    case VI_VR_W_dissipated: return VI_ME_W_DISSIPATED;
    case VI_VR_E_contact: return VI_ME_E_CONTACT;
    case VI_VR_F_peak: return VI_ME_F_PEAK;
    case VI_VR_F_upper: return VI_ME_F_UPPER;
    case VI_VR_delta_upper: return VI_ME_DELTA_UPPER;
    default: return -1;
    }
}

static double jacobian_entry(const vi_me_partials *row, unsigned known)
{
    switch (known) {
    case VI_VR_y: return row->y;
    case VI_VR_v: return row->v;
    case VI_VR_yC_in: return row->yC_in;
    case VI_VR_F_ext: return row->F_ext;
    case VI_VR_vC_in: return row->vC_in;
    default: return 0.0;
    }
}

/* The partial of an unknown with respect to the state W_damping: 1 for W_dissipated (= W_plastic +
 * W_damping), W_damping itself and nothing else. */
static double damping_column(unsigned unknown)
{
    return unknown == VI_VR_W_dissipated || unknown == VI_VR_W_damping ? 1.0 : 0.0;
}

static int directional_derivative(void *m, const unsigned unknown[], size_t n_unknown, const unsigned known[],
                                  size_t n_known, const double dknown[], double dunknown[])
{
    vi_me_partials jac[VI_ME_N_UNKNOWNS];
    vi_me_jacobian(me_of(m), jac);
    for (size_t i = 0; i < n_unknown; i++) {
        int row = jacobian_row(unknown[i]);
        dunknown[i] = 0.0;
        for (size_t j = 0; j < n_known && row >= 0; j++)
            if (dknown[j] != 0.0) dunknown[i] += jacobian_entry(&jac[row], known[j]) * dknown[j];
        for (size_t j = 0; j < n_known; j++)
            if (known[j] == VI_VR_W_damping && dknown[j] != 0.0) dunknown[i] += damping_column(unknown[i]) * dknown[j];
    }
    return 0;
}

const vi_fmu_model vi_fmu_this_model = {
    VI_FMU_TABLE_FIELDS(contact_instance, vi_contact_data),
    .init = init,
    .reset = reset,
    .release = release,
    .set_resources = set_resources,
    .changed = changed,
    .outputs = outputs,
    .outputs_of = outputs_of,
    .setup_experiment = setup_experiment,
    .prepare = prepare,
    .initialize = initialize,
    .advance = advance,
    .advance_to_event = advance_to_event,
    .time = time_of,
    .terminate = terminate,
    .state = state,
    .checkpoint = checkpoint,
    .restore = restore,
    .state_check = state_check,
    .message = message,
    .n_states = VI_ME_NSTATES,
    .n_indicators = VI_ME_NINDICATORS,
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
    .enter_continuous = enter_continuous,
    .directional_derivative = directional_derivative,
};
