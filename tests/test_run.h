/* A run of the contact model with both drivers and their data, held as the FMU adapter
 * (src/vi_fmu_contact.c) holds them, for the C tests and benchmarks that are no FMU: t.d is the run's
 * data, t.cs and t.me the drivers' (together what an FMU state copies), t.r the run, t.s the
 * Co-Simulation driver and t.e the Model Exchange driver. A test_run stays where it was initialized. */
#ifndef VI_TEST_RUN_H
#define VI_TEST_RUN_H

#include "vi_me.h"
#include "vi_sim.h"

typedef struct {
    vi_run_data d;
    vi_sim_data cs;
    vi_me_data me;
    vi_run r;
    vi_sim s;
    vi_me e;
} test_run;

/* The defaults of the variable table, no solver. */
static inline void test_run_init(test_run *t, vi_log_fn log, void *log_env)
{
    vi_run_init(&t->r, &t->d, log, log_env);
    vi_sim_init(&t->s, &t->r, &t->cs);
    vi_me_init(&t->e, &t->r, &t->me);
}

static inline void test_run_free(test_run *t)
{
    vi_sim_free(&t->s);
    vi_run_free(&t->r);
}

/* Back to the defaults (fmi2Reset), keeping the resources folder. */
static inline void test_run_reset(test_run *t)
{
    vi_sim_free(&t->s);
    vi_run_reset(&t->r);
    vi_sim_init(&t->s, &t->r, &t->cs);
    vi_me_init(&t->e, &t->r, &t->me);
}

/* Every output and calculated parameter of the run at its current time. */
static inline void test_run_outputs(test_run *t, vi_outputs *out) { *out = *vi_run_outputs_of(&t->r, VI_OUT_ALL); }

/* The data of `from` into `to` (what an FMU state copies). */
static inline void test_run_copy_data(test_run *to, const test_run *from)
{
    to->d = from->d;
    to->cs = from->cs;
    to->me = from->me;
}

#endif
