/*
 * fuzz.h - the libFuzzer harness of the FMU (tests/fuzz/README.md): what its parts share.
 *
 * An input is a sequence of calls. Each call starts with an opcode byte: bit 7 picks the instance
 * slot (two slots), bits 0-6 the call kind (fz_call.code); the kind's own arguments follow, read
 * with the fz_* readers below (an exhausted input reads as zeros). The kinds of one interface of
 * the FMU (FMI 2.0 common and Co-Simulation: calls_fmi2.c) form one table; codes are fixed, so that
 * the seed corpus keeps its meaning when kinds are added:
 *     0-39    FMI 2.0, common functions and Co-Simulation (calls_fmi2.c)
 *     40-59   FMI 2.0 Model Exchange (calls_fmi2me.c)
 *     60-99   FMI 3.0 (calls_fmi3.c)
 *     100-127 the harness itself (profile files; fuzz_main.c)
 * A code that no table has, or whose functions the FMU binary lacks, is skipped.
 *
 * Every FMU call goes through fz_begin/fz_end (the watchdog: a call running longer than a bound is
 * a finding) and every message through the logger's checks (fuzz_main.c); a finding prints what
 * happened and aborts, so that libFuzzer saves the input. VI_FUZZ_TRACE=1 prints every call.
 *
 * Each calls_<interface>.c defines one fz_interface (fz_fmi2, fz_fmi2me, fz_fmi3); fuzz_main.c lists
 * them as weak references, so that a binary holds the interfaces linked into it (tests/fuzz/fuzz.cmake:
 * fuzz_<FMU> links both faces, FMI 2.0 and FMI 3.0, fuzz_<FMU>_fmi3 the FMI 3.0 face only). A slot
 * holds an instance of one FMI version; a call of another version's interface on it is skipped,
 * except an instantiation, which first frees the instance through its own version's functions.
 */
#ifndef VI_FUZZ_H
#define VI_FUZZ_H

#include <stddef.h>
#include <stdint.h>

#include "fmi2Functions.h"
#include "vi_fmu.h"

#define FZ_SLOTS 2          /* instances alive at once */
#define FZ_STATES 3         /* FMU state handles per slot */
#define FZ_BUFFERS 3        /* serialized states shared by the slots */
#define FZ_MAX_CALLS 96     /* calls per input: bounds the work of one input */
#define FZ_NAME_SIZE 6000   /* longest instance name the harness passes, + 1 */
#define FZ_ARRAY 6          /* the most value references in one fmi2Get/fmi2Set */
/* Passes of the Model Exchange event iteration in a row that ask for another before the FMU stops
 * the run with an error (doc/model-exchange.md, "Events"): one more that returns OK is a finding. */
#define FZ_EVENT_PASS_BOUND 100

/* ---- reading the input ---- */
typedef struct {
    const uint8_t *p;
    size_t n;
} fz_reader;
uint8_t fz_u8(fz_reader *r);
uint16_t fz_u16(fz_reader *r);
uint32_t fz_u32(fz_reader *r);
double fz_raw_double(fz_reader *r);
/* Up to n bytes of the input into out (fewer when it ends); returns how many. */
size_t fz_bytes(fz_reader *r, uint8_t *out, size_t n);

/* ---- values ---- */
/* A Real: special values (0, -0, +-1, NaN, +-inf, extremes, subnormals), raw bits, or `typical`
 * (a variable's start value; 1 when it is 0) scaled by a power of two and maybe negated. */
double fz_real(fz_reader *r, double typical);
/* An Integer: small values, extremes, raw bits, or an item of `enumeration` ("none": any item). */
int fz_integer(fz_reader *r, const char *enumeration);
int fz_boolean(fz_reader *r);
/* A String (NULL possible): names of the profile files the harness writes, paths, long and
 * unterminated-looking strings, control characters, format directives, raw bytes. Valid until the
 * next call of fz_string with the same `which` (0..FZ_ARRAY-1). */
const char *fz_string(fz_reader *r, int which);
/* A value reference: mostly one of a variable of `type` (a vi_type; -1: any variable), sometimes
 * one past the table or far beyond it. */
fmi2ValueReference fz_vr(fz_reader *r, int type);
/* The variable with value reference vr, or NULL. */
const vi_variable *fz_variable(fmi2ValueReference vr);

/* ---- the watchdog and findings ---- */
void fz_begin(const char *call);
void fz_end(void);
/* A finding: print it (and the calls so far with VI_FUZZ_TRACE=1) and abort. */
void fz_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));
void fz_trace(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Is status one of the fmi2Status values? (A finding otherwise.) */
fmi2Status fz_status(const char *call, fmi2Status s);

/* ---- instances ---- */
/* The FMI states of the state machines, as bits (a mask: the states the instance may be in, after
 * a call whose outcome leaves it open). The bits are those the FMU records in its FMU states
 * (src/fmi/vi_fmi_layer.h VI_ST_*). FMI 2.0 Co-Simulation has the first six (FZ_ANY); FMI 3.0 names
 * step complete "Step Mode" and step failed "Step Discarded", and adds Event Mode (Co-Simulation with
 * eventModeUsed, Model Exchange) and Continuous-Time Mode (Model Exchange): FZ_ANY3. */
enum {
    FZ_INSTANTIATED = 1 << 0,
    FZ_INIT = 1 << 1,
    FZ_STEP_COMPLETE = 1 << 2,
    FZ_STEP_FAILED = 1 << 3,
    FZ_TERMINATED = 1 << 4,
    FZ_ERROR = 1 << 5,
    FZ_ANY = (1 << 6) - 1,
    FZ_EVENT = 1 << 7,
    FZ_CONTINUOUS = 1 << 8,
    FZ_ANY3 = FZ_ANY | FZ_EVENT | FZ_CONTINUOUS,
};

typedef struct {
    void *handle; /* fmi2FMUstate, NULL when free */
    unsigned mask; /* the FMI states the instance may have been in when it was taken */
    double t;     /* its communication time */
} fz_saved;

/* The energy property of an undriven run (energy.c). */
typedef struct {
    int off;          /* the run was driven, or its past is unknown (a restored state): no check */
    double tolerance; /* the experiment's relative tolerance (0: none given) */
} fz_energy;

typedef struct fz_slot {
    void *c;                   /* fmi2Component, NULL when the slot is empty */
    int fmu_type;              /* fmi2CoSimulation or fmi2ModelExchange */
    char name[FZ_NAME_SIZE];   /* the name it was instantiated with */
    const char *expected_name; /* what the logger must be told (name, or "?" for a NULL name) */
    unsigned mask;             /* FZ_* states it may be in (Co-Simulation) */
    double t;                  /* the importer's communication time */
    double start_time;         /* of fmi2SetupExperiment */
    fz_saved saved[FZ_STATES];
    int logging;               /* debug logging on (every category) */
    int version;               /* the FMI version of the functions that made c (2 or 3) */
    unsigned options;          /* FMI 3.0 Co-Simulation: FZ_EVENT_MODE_USED | FZ_EARLY_RETURN_ALLOWED */
    fz_energy energy;
} fz_slot;

enum { FZ_EVENT_MODE_USED = 1u << 0, FZ_EARLY_RETURN_ALLOWED = 1u << 1 };

typedef struct {
    uint8_t *data;
    size_t n;
} fz_buffer;

typedef struct {
    fz_slot slot[FZ_SLOTS];
    fz_buffer buffer[FZ_BUFFERS];
    char resources[256]; /* a folder the harness writes profile files into */
    char resources_uri[300];
} fz_context;

/* The callbacks every instance gets (componentEnvironment: its slot). */
fmi2CallbackFunctions fz_callbacks(fz_slot *s);
/* Set a slot's expected logger name before fmi2Instantiate. */
void fz_expect_name(fz_slot *s, const char *name);
/* The checks of a log message for slot s (status, category, text; format: the message is a printf
 * format, as in FMI 2.0, so that a '%' must be "%%"); a finding when one fails. */
void fz_check_message(const fz_slot *s, int status, const char *category, const char *message, int format);

/* ---- serialized FMU states (both versions have one format, src/fmi/vi_fmi_fmu_state.c) ---- */
/* Seal p (n bytes) again with the documented checksum (FNV-1a's round over 64-bit words in four
 * lanes over the 48-byte header, its checksum at 40 taken as 0, then the model's block). */
void fz_reseal(uint8_t *p, size_t n);
/* A copy of b (malloc) altered by up to three edits read from r (bit flips, bytes, doubles,
 * truncation, extension), maybe sealed again; *n: its length. */
uint8_t *fz_corrupted(fz_reader *r, const fz_buffer *b, size_t *n);
/* The FMI state a (maybe altered) serialized state records (its header's fmu_state field), when that
 * is one of the FZ_ANY3 bits; FZ_ANY3 otherwise. */
unsigned fz_recorded_mask(const uint8_t *p, size_t n);

/* ---- FMI 2.0 outcomes (calls_fmi2.c), shared with Model Exchange (calls_fmi2me.c) ---- */
/* fmi2OK or fmi2Warning from a call allowed in the states `allowed` only, while the instance may be
 * in none of them, is a finding; then the instance is in `next` (0: those of its states that allow
 * the call). fmi2Error: refused with the state unchanged, or the instance is in Error now. */
void fz_outcome2(fz_slot *s, const char *call, unsigned allowed, fmi2Status st, unsigned next);
/* The mask of a call for the slot's interface: `cs` for Co-Simulation, `me` for Model Exchange. */
unsigned fz_by_type(const fz_slot *s, unsigned cs, unsigned me);
/* Is every element of x finite? Else a finding naming the call and the element. */
void fz_finite(const char *call, const double *x, size_t n);

/* ---- the Model Exchange call-order property (order.c) ----
 * In Continuous-Time Mode an importer sets time, continuous states and continuous inputs in any
 * order before it asks for derivatives, event indicators or outputs; two orders that end at the
 * same (time, states, inputs) must give the same answers bit for bit. fz_call_order takes an FMU
 * state, brings the instance to one point in order A (the final values only), then, from the
 * restored state, in order A again (the same answers, or restoring the state is not exact) and in
 * order B (other orders of the sets and of the getters, with earlier sets of other values, decoys,
 * in between). Each interface gives its functions; each returns the call's status (0: OK) and
 * checks its outcome against the state machine. order.c says what is compared. */
typedef struct {
    const char *name[3]; /* of the getters: derivatives, event indicators, Real outputs */
    int (*set_time)(fz_slot *s, double t);
    int (*set_states)(fz_slot *s, const double *x, size_t n);
    int (*set_reals)(fz_slot *s, const unsigned *vr, size_t n, const double *x);
    int (*get_states)(fz_slot *s, double *x, size_t n);
    int (*derivatives)(fz_slot *s, double *dx, size_t n);
    int (*indicators)(fz_slot *s, double *z, size_t n);
    int (*get_reals)(fz_slot *s, const unsigned *vr, size_t n, double *x);
    int (*save)(fz_slot *s, void **state);
    int (*restore)(fz_slot *s, void *state, unsigned mask);
    void (*drop)(fz_slot *s, void **state);
} fz_me_face;
/* The property at the slot's current point (skipped unless the instance may be in Continuous-Time
 * Mode at a known time); reads its choices from r. */
void fz_call_order(fz_slot *s, fz_reader *r, const fz_me_face *f);
/* Is the property `name` left out? The environment variable VI_FUZZ_OFF lists the ones to leave
 * out, comma-separated ("call-order", "restore": order.c), for a campaign while a known failure of
 * one is being fixed. */
int fz_off(const char *name);

/* ---- call kinds ---- */
/* What a call does to an undriven run (energy.c): drives it or makes its past unknown (0), leaves
 * it undriven (reads, steps), or leaves it undriven while the instance has not started (sets and
 * mode changes in Instantiated and Initialization Mode). */
enum { FZ_RUN_DRIVES = 0, FZ_RUN_KEEPS = 1, FZ_RUN_STARTS = 2 };

typedef struct {
    uint8_t code;
    const char *name;
    /* Run the call on slot s (or both slots of ctx); read the arguments from r. */
    void (*run)(fz_context *ctx, fz_slot *s, fz_reader *r);
    int instantiates; /* makes a new instance in the slot (frees the one there first) */
    int energy;       /* FZ_RUN_* */
} fz_call;

/* ---- the energy property of an undriven run (energy.c) ----
 * In a Co-Simulation run with no excitation (a = 0, constant inputs) kinetic + elastic energy never
 * grows beyond the tolerance: kinetic + E_contact + W_dissipated + W0 y is constant. */
#define FZ_ENERGY_VALUES 15
/* Read n Reals (0: OK): each interface's fmi2GetReal or fmi3GetFloat64. */
typedef int (*fz_get_reals)(fz_slot *s, const unsigned *vr, size_t n, double *x);
/* Read one Integer or enumeration (0: OK): fmi2GetInteger or fmi3GetInt64. */
typedef int (*fz_get_int)(fz_slot *s, unsigned vr, long *value);
/* After every call on slot s (the dispatcher): a new instance starts a run, and a call that drives
 * the run (fz_call.energy) ends its checks. */
void fz_energy_after_call(fz_slot *s, const fz_call *call, unsigned mask_before);
/* The experiment's tolerance, as fmi2SetupExperiment or fmi3EnterInitializationMode accepted it. */
void fz_energy_tolerance(fz_slot *s, int defined, double tolerance);
/* The values the check needs, before or after a step; 0 when the slot's run is not checked (driven,
 * not Co-Simulation, not in Step Mode, a != 0 or V != 0, a value unread or not finite). */
int fz_energy_read(fz_slot *s, fz_get_reals get, fz_get_int get_int, double x[FZ_ENERGY_VALUES]);
/* The check of the step [t, t + h] from the values before (a) and after (b) it; a finding when the
 * balance grew beyond the tolerance. */
void fz_energy_check(const fz_slot *s, const double a[FZ_ENERGY_VALUES], const double b[FZ_ENERGY_VALUES],
                     double t, double h);

typedef struct {
    const char *name;
    int (*available)(void);   /* are the interface's functions in this binary? */
    const fz_call *calls;
    size_t ncalls;
    void (*release)(fz_context *ctx, fz_slot *s); /* free the slot's instance of this version, if any */
    int fmi_version; /* of its functions (2 or 3); 0: the harness's own kinds, for any slot */
} fz_interface;

#endif
