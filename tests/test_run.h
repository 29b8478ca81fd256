/* An instance of the contact FMU without the FMI layer (vi_contact_instance.h), for the C tests and
 * benchmarks: t.d its data (the FMI storage par, in, din, t_start, tolerance; the run's data t.d.run;
 * the drivers' t.d.cs and t.d.me: together what an FMU state copies), t.r the run, t.s the
 * Co-Simulation driver and t.e the Model Exchange driver. A test_run stays where it was initialized. */
#ifndef VI_TEST_RUN_H
#define VI_TEST_RUN_H

#include "vi_contact_instance.h"

typedef vi_contact test_run;

/* The defaults of the variable table, no solver. */
static inline void test_run_init(test_run *t, vi_log_fn log, void *log_env) { vi_contact_init(t, log, log_env); }
static inline void test_run_free(test_run *t) { vi_contact_free(t); }
/* Back to the defaults (fmi2Reset), keeping the resources folder. */
static inline void test_run_reset(test_run *t) { vi_contact_reset(t); }
/* Every output and calculated parameter at the current time. */
static inline void test_run_outputs(test_run *t, vi_outputs *out) { *out = *vi_contact_outputs_of(t, VI_OUT_ALL); }
/* The data of `from` into `to` (what an FMU state copies). */
static inline void test_run_copy_data(test_run *to, const test_run *from) { to->d = from->d; }

#endif
