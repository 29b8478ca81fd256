/*
 * vi_contact_instance.h - one instance of the contact FMU: its FMI storage (the parameters and inputs
 * as the importer set them, the experiment) beside the run's data and each driver's (together what an
 * FMU state holds), the run over them and both drivers over the run; and the mapping of the FMI
 * storage onto the run: its settings and inputs from the variable table's structs, its values into
 * the table's outputs, the checks of a saved block. The FMI adapter (src/adapter/vi_fmu_contact.c) maps the
 * layer's hooks onto an instance; the C tests use one without the layer. The run and the drivers
 * know no FMI: the variable table (vi_variables.h) is known here and in the adapter only.
 */
#ifndef VI_CONTACT_INSTANCE_H
#define VI_CONTACT_INSTANCE_H

#include "vi_me.h"
#include "vi_sim.h"
#include "vi_variables.h"

/* The plain data of an instance, what an FMU state holds. */
typedef struct {
    vi_parameters par;
    vi_inputs in;        /* input values as last set */
    vi_inputs din;       /* their time derivatives (order 1); setting a value resets its derivative */
    double t_start;      /* the experiment's start [s] */
    double tolerance;    /* the importer's (fmi2SetupExperiment, fmi3EnterInitializationMode), 0 when not
                            defined (then par.rtol counts) */
    vi_run_data run;
    vi_sim_data cs;
    vi_me_data me;
} vi_contact_data;

/* An instance: its data, the run over it and the two drivers over the run (Co-Simulation s, Model
 * Exchange e; e.active says whether Model Exchange runs). It stays where it was initialized. */
typedef struct {
    vi_contact_data d;
    vi_run r;
    vi_sim s;
    vi_me e;
    vi_outputs out; /* the outputs as the variable table holds them (vi_contact_outputs_of) */
} vi_contact;

/* The model's parameters (vi_model.h) from the FMU's. */
vi_model_params vi_contact_model_params(const vi_parameters *p);
/* The relative tolerance the simulation runs at: rtol when set (> 0), else the experiment's tolerance
 * when given, else VI_RTOL_DEFAULT (doc/model.md section 5). */
double vi_contact_rtol(const vi_parameters *p, double tolerance);

/* The defaults of the variable table; the run and both drivers bound to the data; no solver yet. */
void vi_contact_init(vi_contact *c, vi_log_fn log, void *log_env);
/* Back to the defaults; frees the solver; keeps the resources folder and the logger. */
void vi_contact_reset(vi_contact *c);
void vi_contact_free(vi_contact *c);
/* The outputs of `groups` (VI_OUT_*, vi_model.h) at the current time in the variable table's struct:
 * Co-Simulation's run, or Model Exchange's (with the states' derivatives) when it runs or they are
 * asked for. */
const vi_outputs *vi_contact_outputs_of(vi_contact *c, unsigned groups);
/* Is d a block this FMU could have saved (doc/model.md section 7.6)? Before initialization (running
 * 0) only the settings exist, which the FMI layer checks; after it, the experiment, the run's fields,
 * the driver's (Model Exchange with model_exchange nonzero, else Co-Simulation, whose block keeps the
 * other driver's data finite) and the model's. 0, or -1 naming the first bad field in msg. */
int vi_contact_state_check(const vi_contact_data *d, int running, int model_exchange, char *msg, size_t n);

#endif
