/*
 * vt_companion.h - what the companion models of the vehicle-track example (track/, vehicle/)
 * share: a small ODE system x' = f(t, x; parameters, inputs), advanced over each communication
 * step by the repository's CVODE wrapper (src/solvers/vi_solver.h), as a model of the generic FMI
 * layer (src/fmi/vi_fmu.h). A model folder holds only its physics: its variable table, one
 * vt_model_def (right-hand side, Jacobian, parameter check, initial state, tolerance scales,
 * outputs) and VT_DEFINE_FMU. This file turns that into the layer's hooks.
 *
 * Inputs are held over a step (zero-order hold); a model may extrapolate them in time from the
 * time they were set (vt_input_time). When an input changed, the solver restarts at the start of
 * the next step, since the right-hand side jumps there.
 */
#ifndef VT_COMPANION_H
#define VT_COMPANION_H

#include <stddef.h>

#include "vi_fmu.h"
#include "vi_solver.h"

#define VT_MAX_STATES VI_SOLVER_MAX_N
#define VT_TWO_PI 6.28318530717958647692
/* m: the absolute tolerance of displacements is rtol times this (a micrometre: the wheel-rail
 * contact's indentation is tens of micrometres), velocities and energies follow from it. */
#define VT_LENGTH_SCALE 1e-6

/* The part of a model's plain-data block (its FMU state) that this file manages. A model's block
 * starts with it: typedef struct { vt_core core; vi_parameters par; vi_inputs in, din; ... }. */
typedef struct {
    double t_start;        /* s, from fmi2SetupExperiment */
    double tolerance;      /* from fmi2SetupExperiment, 0 = none */
    double t;              /* s, current time */
    double t_in;           /* s, when the inputs were last set (they are held from then on) */
    int inputs_changed;    /* an input was set since the last step */
    int solver_stale;      /* the state changed outside the solver: restart before advancing */
    double x[VT_MAX_STATES];
    /* Model Exchange: the last completed step of the importer (for step_done) */
    double t_step, x_step[VT_MAX_STATES];
} vt_core;

typedef struct {
    int n; /* number of states, <= VT_MAX_STATES */
    /* Optional (NULL: none). Check what the ranges of the variable table cannot say (the layer
     * refuses a value outside its range when it is set): 0, or -1 with a message naming the
     * variables and what is allowed. */
    int (*check)(const void *data, char *msg, size_t n);
    /* The initial state (core.x) from the parameters and the inputs at core.t. */
    void (*start)(void *data);
    /* The rtol parameter: 0 = the experiment's tolerance (VI_RTOL_DEFAULT without one); set, it wins
     * over the experiment's (the contact FMU's rule, doc/model.md section 5). */
    double (*rtol)(const void *data);
    /* Absolute tolerance of each state divided by the relative tolerance (the model's own scales). */
    void (*scales)(const void *data, double *scale);
    /* x' = f(t, x) and, optionally, its Jacobian (row-major n x n). */
    void (*rhs)(double t, const double *x, double *dx, const void *data);
    void (*jac)(double t, const double *x, double *jac, const void *data);
    /* Outputs and calculated parameters at core.t into *out (a vi_outputs). */
    void (*outputs)(const void *data, void *out);
    /* Optional: after a step from (t0, x0) to core.t, core.x (e.g. sums that follow exactly from
     * the held inputs and the states at the step's ends; in Model Exchange a step is the importer's
     * completed step and the inputs are those at its end). */
    void (*step_done)(void *data, double t0, const double *x0);
} vt_model_def;

/* The layer's instance of a companion model; VT_DEFINE_FMU puts the model's plain-data block
 * (starting with vt_core) right after it and points `data` at it. */
typedef struct {
    const vt_model_def *def;
    void *data;
    vi_solver *solver;
    vi_fmu_log_fn log;
    void *env;
    char msg[256];
} vt_instance;

/* The time the held inputs refer to: now when they were set since the last step. */
double vt_input_time(const vt_core *c);

/* The generic hooks (vt_companion.c). */
void vt_init(void *m, const vt_model_def *def, void *data, vi_fmu_log_fn log, void *env);
void vt_reset(void *m); /* the model's defaults are applied after it (VT_DEFINE_FMU) */
void vt_release(void *m);
void vt_changed(void *m);
void vt_outputs(void *m, void *out);
void vt_setup_experiment(void *m, double start_time, int tolerance_defined, double tolerance);
int vt_prepare(void *m);
int vt_initialize(void *m);
int vt_advance(void *m, double t_end);
double vt_time(const void *m);
void vt_terminate(void *m);
void *vt_state(void *m);
int vt_checkpoint(void *m);
int vt_restore(void *m, int running);
int vt_state_check(const void *state, int running, const vt_model_def *def, char *msg, size_t n);
const char *vt_message(const void *m);

/* Model Exchange (vt_companion_me.c): the importer integrates x' = f(t, x) with the inputs as they
 * are set (no hold, no extrapolation); no event indicators, no directional derivatives. */
int vt_me_initialize(void *m);
void vt_me_set_time(void *m, double t);
void vt_me_get_states(void *m, double x[]);
void vt_me_set_states(void *m, const double x[]);
void vt_me_derivatives(void *m, double dx[]);
void vt_me_nominals(const void *m, double nominal[]);
int vt_me_event_update(void *m, vi_fmu_event *ev);
int vt_me_completed_step(void *m);
void vt_me_enter_continuous(void *m);

/* In the model's file, after its table (VI_TABLE_DEFINE) and its vt_model_def DEF whose block
 * type is DATA (with members par, in and din): the one model of this FMU binary, Co-Simulation and
 * Model Exchange. N is the number of states (a constant, = DEF.n), STATE_VRS and DERIVATIVE_VRS
 * arrays of N value references: the states (outputs) and their derivatives (locals), in state order. */
#define VT_DEFINE_FMU(DEF, DATA, N, STATE_VRS, DERIVATIVE_VRS)                                    \
    typedef struct {                                                                              \
        vt_instance head;                                                                         \
        DATA data;                                                                                \
    } vt_instance_##DATA;                                                                         \
    static void vt_defaults_##DATA(void *m)                                                       \
    {                                                                                             \
        DATA *d = vt_state(m);                                                                    \
        vi_parameters_default(&d->par);                                                           \
        vi_inputs_default(&d->in);                                                                \
    }                                                                                             \
    static void vt_init_##DATA(void *m, vi_fmu_log_fn log, void *env)                             \
    {                                                                                             \
        vt_init(m, &(DEF), &((vt_instance_##DATA *)m)->data, log, env);                           \
        vt_defaults_##DATA(m);                                                                    \
    }                                                                                             \
    static void vt_reset_##DATA(void *m)                                                          \
    {                                                                                             \
        vt_reset(m);                                                                              \
        vt_defaults_##DATA(m);                                                                    \
    }                                                                                             \
    static int vt_check_##DATA(const void *s, int running, char *msg, size_t n)                    \
    {                                                                                             \
        return vt_state_check(s, running, &(DEF), msg, n);                                        \
    }                                                                                             \
    const vi_fmu_model vi_fmu_this_model = {                                                       \
        VI_FMU_TABLE_FIELDS(vt_instance_##DATA, DATA),                                             \
        .init = vt_init_##DATA,                                                                    \
        .reset = vt_reset_##DATA,                                                                  \
        .release = vt_release,                                                                     \
        .changed = vt_changed,                                                                     \
        .outputs = vt_outputs,                                                                     \
        .setup_experiment = vt_setup_experiment,                                                   \
        .prepare = vt_prepare,                                                                     \
        .initialize = vt_initialize,                                                               \
        .advance = vt_advance,                                                                     \
        .time = vt_time,                                                                           \
        .terminate = vt_terminate,                                                                 \
        .state = vt_state,                                                                         \
        .checkpoint = vt_checkpoint,                                                               \
        .restore = vt_restore,                                                                     \
        .state_check = vt_check_##DATA,                                                            \
        .message = vt_message,                                                                     \
        .n_states = (N),                                                                           \
        .n_indicators = 0,                                                                         \
        .state_vrs = (STATE_VRS),                                                                  \
        .derivative_vrs = (DERIVATIVE_VRS),                                                        \
        .me_initialize = vt_me_initialize,                                                         \
        .set_time = vt_me_set_time,                                                                \
        .get_states = vt_me_get_states,                                                            \
        .set_states = vt_me_set_states,                                                            \
        .derivatives = vt_me_derivatives,                                                          \
        .nominals = vt_me_nominals,                                                                \
        .event_update = vt_me_event_update,                                                        \
        .completed_step = vt_me_completed_step,                                                    \
        .enter_continuous = vt_me_enter_continuous,                                                \
    }

#endif
