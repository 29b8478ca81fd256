/*
 * fuzz_main.c - the libFuzzer harness of the FMU: decoding an input into calls (fuzz.h), the value
 * choosers, the watchdog, the logger's checks, the importer's memory functions, and the loop.
 *
 * Findings (each aborts, so that libFuzzer saves the input):
 *   - anything AddressSanitizer or UndefinedBehaviorSanitizer reports (the FMU is built with both);
 *   - a call that uses more than VI_FUZZ_CALL_SECONDS of CPU time (default 30 s), or that has not
 *     returned after VI_FUZZ_HANG_SECONDS of wall time (default 300 s; a watchdog thread);
 *   - a log message that is not well formed: NULL, empty, longer than FZ_MESSAGE_MAX, with a byte
 *     that starts no printable character (UTF-8, no control characters), from an unknown
 *     componentEnvironment; in FMI 2.0 also with a '%' that is not "%%" (the logger's message is a
 *     format) or naming another instance than the one called;
 *   - a status outside fmi2Status (fmi3Status), and the checks of calls_fmi2.c and calls_fmi3.c
 *     (OK where the standard's state machine or the variable's causality forbids the call, time
 *     after a step, ...);
 *   - blocks of the importer's memory still allocated after every instance was freed.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, nanosleep, mkdtemp, strnlen */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fuzz.h"

#define MODEL (&vi_fmu_this_model)
#define FZ_MESSAGE_MAX 4096  /* longest log message accepted as well formed */
#define FZ_CATEGORY_MAX 64
#define FZ_STRING_MAX 6000   /* the longest String value the harness passes, + 1 */
#define FZ_RECENT 24         /* calls remembered for a finding's report */

static fz_context ctx;
static const fz_call *by_code[128];
static const fz_interface *owner[128]; /* the interface of each code */
static int trace_on;

/* ---- reading the input ------------------------------------------------------------------------ */

uint8_t fz_u8(fz_reader *r)
{
    if (!r->n) return 0;
    r->n--;
    return *r->p++;
}

uint16_t fz_u16(fz_reader *r) { return (uint16_t)(fz_u8(r) | fz_u8(r) << 8); }

uint32_t fz_u32(fz_reader *r) { return (uint32_t)fz_u16(r) | (uint32_t)fz_u16(r) << 16; }

double fz_raw_double(fz_reader *r)
{
    uint64_t bits = (uint64_t)fz_u32(r) | (uint64_t)fz_u32(r) << 32;
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

size_t fz_bytes(fz_reader *r, uint8_t *out, size_t n)
{
    size_t k = n < r->n ? n : r->n;
    memcpy(out, r->p, k);
    r->p += k, r->n -= k;
    return k;
}

/* ---- values ----------------------------------------------------------------------------------- */

double fz_real(fz_reader *r, double typical)
{
    uint8_t s = fz_u8(r);
    switch (s % 24) {
    case 0: return 0.0;
    case 1: return -0.0;
    case 2: return 1.0;
    case 3: return -1.0;
    case 4: return NAN;
    case 5: return INFINITY;
    case 6: return -INFINITY;
    case 7: return DBL_MAX;
    case 8: return -DBL_MAX;
    case 9: return DBL_TRUE_MIN;
    case 10: return DBL_MIN;
    case 11: return fz_raw_double(r);
    case 12: return typical;
    default: { /* typical times 2^(e/4) (1 + (e mod 4)/4), e in [-128, 127]: about 1e-10 to 1e10 */
        double base = typical != 0.0 && isfinite(typical) ? typical : 1.0;
        int e = (int8_t)fz_u8(r);
        double x = ldexp(base, e / 4) * (1.0 + (e & 3) / 4.0);
        return s >= 128 ? -x : x;
    }
    }
}

int fz_integer(fz_reader *r, const char *enumeration)
{
    uint8_t s = fz_u8(r);
    switch (s % 12) {
    case 0: case 1: case 2: case 3: case 4: return s % 12 - 1;
    case 5: return INT_MIN;
    case 6: return INT_MAX;
    case 7: return (int)fz_u32(r);
    default: { /* an item of the enumeration (any type when "none") */
        int n = 0;
        for (int i = 0; i < MODEL->n_enum_items; i++)
            n += strcmp(enumeration, "none") == 0 || strcmp(MODEL->enum_items[i].type, enumeration) == 0;
        if (!n) return fz_u8(r) % 8;
        int k = fz_u8(r) % n;
        for (int i = 0; i < MODEL->n_enum_items; i++)
            if ((strcmp(enumeration, "none") == 0 || strcmp(MODEL->enum_items[i].type, enumeration) == 0) && k-- == 0)
                return MODEL->enum_items[i].value;
        return 0;
    }
    }
}

int fz_boolean(fz_reader *r)
{
    static const int values[] = {0, 0, 0, 1, 1, 1, 2, -1};
    return values[fz_u8(r) % 8];
}

static char strings[FZ_ARRAY][FZ_STRING_MAX];

static const char *repeated(char *buf, char ch, size_t n)
{
    memset(buf, ch, n);
    buf[n] = '\0';
    return buf;
}

const char *fz_string(fz_reader *r, int which)
{
    char *buf = strings[(unsigned)which % FZ_ARRAY];
    uint8_t s = fz_u8(r);
    switch (s % 16) {
    case 0: return NULL;
    case 1: return "";
    case 2: return "p0.txt";
    case 3: return "p1.txt";
    case 4: snprintf(buf, FZ_STRING_MAX, "%s/p0.txt", ctx.resources); return buf;
    case 5: return "/nonexistent/profile.txt";
    case 6: return "../p0.txt";
    case 7: return repeated(buf, 'a', VI_STRING_SIZE - 1);
    case 8: return repeated(buf, 'b', VI_STRING_SIZE);
    case 9: return repeated(buf, 'c', FZ_STRING_MAX - 1);
    case 10: return "%s%n%d%%%";
    case 11: return "\x01\x1b[2J\x7f\xff";
    case 12: return "p0.txt\n";
    default: { /* raw bytes of the input */
        size_t n = fz_bytes(r, (uint8_t *)buf, fz_u8(r));
        buf[n] = '\0';
        return buf;
    }
    }
}

static int type_matches(const vi_variable *v, int type)
{
    if (type < 0) return 1;
    if (type == VI_Integer) return v->type == VI_Integer || v->type == VI_Enumeration;
    return (int)v->type == type;
}

fmi2ValueReference fz_vr(fz_reader *r, int type)
{
    uint8_t s = fz_u8(r);
    int n = MODEL->nvariables;
    if (s < 200 && type >= 0) {
        int count = 0;
        for (int i = 0; i < n; i++) count += type_matches(&MODEL->variables[i], type);
        if (count) {
            int k = s % count;
            for (int i = 0; i < n; i++)
                if (type_matches(&MODEL->variables[i], type) && k-- == 0) return (fmi2ValueReference)i;
        }
    }
    if (s < 240) return (fmi2ValueReference)(s % n);
    static const fmi2ValueReference beyond[] = {0, 1000, 0xFFFFFFFFu, 0x80000000u};
    return s % 4 == 0 ? (fmi2ValueReference)n : beyond[s % 4];
}

const vi_variable *fz_variable(fmi2ValueReference vr)
{
    return vr < (fmi2ValueReference)MODEL->nvariables ? &MODEL->variables[vr] : NULL;
}

/* ---- findings, tracing, the watchdog ----------------------------------------------------------- */

static char recent[FZ_RECENT][96];
static unsigned n_recent;

void fz_trace(const char *fmt, ...)
{
    if (!trace_on) return;
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

void fz_fail(const char *fmt, ...)
{
    fprintf(stderr, "\n==vi-fuzz== FINDING: ");
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n==vi-fuzz== the last calls (oldest first; VI_FUZZ_TRACE=1 shows arguments):\n");
    unsigned first = n_recent > FZ_RECENT ? n_recent - FZ_RECENT : 0;
    for (unsigned i = first; i < n_recent; i++) fprintf(stderr, "  %s\n", recent[i % FZ_RECENT]);
    abort();
}

fmi2Status fz_status(const char *call, fmi2Status s)
{
    if ((unsigned)s > (unsigned)fmi2Pending) fz_fail("%s returned %d, which is no fmi2Status", call, (int)s);
    return s;
}

void fz_finite(const char *call, const double *x, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i])) fz_fail("%s returned OK with element %zu = %g", call, i, x[i]);
}

static double call_bound = 30.0, hang_bound = 300.0; /* seconds: CPU per call, wall before a hang */
static _Atomic long long call_started_ns;            /* wall clock at fz_begin, 0 between calls */
static const char *_Atomic current_call;
static struct timespec cpu_at_begin;
static double slowest;
static char slowest_call[96];

static long long now_ns(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

void fz_begin(const char *call)
{
    snprintf(recent[n_recent++ % FZ_RECENT], sizeof recent[0], "%s", call);
    atomic_store(&current_call, call);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu_at_begin);
    atomic_store(&call_started_ns, now_ns(CLOCK_MONOTONIC));
}

void fz_end(void)
{
    struct timespec now;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    atomic_store(&call_started_ns, 0);
    double cpu = (double)(now.tv_sec - cpu_at_begin.tv_sec) + 1e-9 * (double)(now.tv_nsec - cpu_at_begin.tv_nsec);
    const char *call = atomic_load(&current_call);
    if (cpu > slowest) {
        slowest = cpu;
        snprintf(slowest_call, sizeof slowest_call, "%s", call);
    }
    if (cpu > call_bound)
        fz_fail("%s used %.2f s of CPU time, more than the bound of %g s (VI_FUZZ_CALL_SECONDS)", call, cpu, call_bound);
}

static void *watchdog(void *arg)
{
    (void)arg;
    for (;;) {
        struct timespec pause = {0, 100000000};
        nanosleep(&pause, NULL);
        long long started = atomic_load(&call_started_ns);
        if (started && (double)(now_ns(CLOCK_MONOTONIC) - started) * 1e-9 > hang_bound) {
            fprintf(stderr, "\n==vi-fuzz== FINDING: %s has not returned after %g s (VI_FUZZ_HANG_SECONDS)\n",
                    atomic_load(&current_call), hang_bound);
            abort();
        }
    }
    return NULL;
}

/* ---- the importer's callbacks ---------------------------------------------------------------- */

static long live_blocks; /* blocks of the importer's memory the FMU holds */

static void *allocate(size_t n, size_t size)
{
    void *p = calloc(n, size);
    if (p) live_blocks++;
    return p;
}

static void release(void *p)
{
    if (p) live_blocks--;
    free(p);
}

/* The length of the UTF-8 sequence of a printable character at p (n bytes left), 0 if there is none
 * there: ASCII 0x20-0x7e, or a well-formed multi-byte sequence (no overlong forms, no surrogates,
 * at most U+10FFFF) of a character that is not a C1 control (U+0080-U+009F). */
static size_t printable_at(const unsigned char *p, size_t n)
{
    unsigned char c = p[0];
    if (c >= 0x20 && c <= 0x7e) return 1;
    size_t len = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
    if (!len || len > n) return 0;
    unsigned char lo = c == 0xe0 ? 0xa0 : c == 0xf0 ? 0x90 : 0x80, hi = c == 0xed ? 0x9f : c == 0xf4 ? 0x8f : 0xbf;
    if (p[1] < lo || p[1] > hi) return 0;
    for (size_t i = 2; i < len; i++)
        if (p[i] < 0x80 || p[i] > 0xbf) return 0;
    if (c == 0xc2 && p[1] <= 0x9f) return 0; /* C1 control */
    return len;
}

/* text: non-NULL, non-empty, at most max bytes before its NUL, printable characters only (UTF-8). */
static void check_text(const char *what, const char *name, const char *text, size_t max)
{
    if (!text) fz_fail("logger (%.80s): the %s is NULL", name, what);
    size_t n = strnlen(text, max + 1);
    if (n == 0) fz_fail("logger (%.80s): the %s is empty", name, what);
    if (n > max) fz_fail("logger (%.80s): the %s is longer than %zu bytes: %.200s...", name, what, max, text);
    const unsigned char *u = (const unsigned char *)text;
    for (size_t i = 0, k; i < n; i += k) {
        if ((k = printable_at(u + i, n - i)) > 0) continue;
        char shown[400];
        size_t j = 0;
        for (size_t m = 0; m < n && j + 5 < sizeof shown; m++) /* the text with other bytes escaped */
            j += u[m] < 0x20 || u[m] > 0x7e ? (size_t)snprintf(shown + j, sizeof shown - j, "\\x%02x", u[m])
                                             : (size_t)snprintf(shown + j, sizeof shown - j, "%c", u[m]);
        fz_fail("logger (%.80s): the %s has a byte that starts no printable character (0x%02x at %zu): %s", name,
                what, u[i], i, shown);
    }
}

void fz_check_message(const fz_slot *s, int status, const char *category, const char *message, int format)
{
    int known = 0;
    for (int i = 0; i < FZ_SLOTS; i++) known |= s == &ctx.slot[i];
    if (!known) fz_fail("logger: the instance environment %p is none the importer gave", (const void *)s);
    const char *name = s->expected_name;
    if ((unsigned)status > (unsigned)fmi2Pending) fz_fail("logger (%.80s): status %d is no status", name, status);
    check_text("category", name, category, FZ_CATEGORY_MAX);
    check_text("message", name, message, FZ_MESSAGE_MAX);
    if (format)
        for (const char *p = message; *p; p++) /* a format without arguments: only "%%" */
            if (*p == '%' && *++p != '%')
                fz_fail("logger (%.80s): a '%%' that is not \"%%%%\" in the message (a format): %.300s", name, message);
    fz_trace("    log %d %s: %s", status, category, message);
}

/* FMI 2.0's logger: the message is a format, and the instance is named. */
static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    fz_slot *s = env;
    int known = 0;
    for (int i = 0; i < FZ_SLOTS; i++) known |= s == &ctx.slot[i];
    if (!known) fz_fail("logger: componentEnvironment %p is none the importer gave", env);
    if (!name) fz_fail("logger: the instance name is NULL (instance '%.80s')", s->expected_name);
    if (strcmp(name, s->expected_name) != 0)
        fz_fail("logger: the message names instance '%.80s', the call was to '%.80s'", name, s->expected_name);
    fz_check_message(s, (int)status, category, message, 1);
}

fmi2CallbackFunctions fz_callbacks(fz_slot *s)
{
    return (fmi2CallbackFunctions){logger, allocate, release, NULL, s};
}

void fz_expect_name(fz_slot *s, const char *name) { s->expected_name = name ? name : "?"; }

/* ---- serialized FMU states: the documented checksum (src/fmi/vi_fmi_fmu_state.c), written again ---------- */

static uint64_t round_(uint64_t h, uint64_t w)
{
    h = (h ^ w) * 0x100000001b3u;
    return h ^ (h >> 32);
}

static uint64_t words_hash(uint64_t h, const uint8_t *p, size_t n)
{
    uint64_t lane[4], w;
    for (int k = 0; k < 4; k++) lane[k] = round_(h, (uint64_t)k);
    size_t i = 0;
    for (; i + 32 <= n; i += 32)
        for (int k = 0; k < 4; k++) {
            memcpy(&w, p + i + 8 * (size_t)k, 8);
            lane[k] = round_(lane[k], w);
        }
    h = round_(lane[0], (uint64_t)n);
    for (int k = 1; k < 4; k++) h = round_(h, lane[k]);
    for (; i < n; i++) h = round_(h, p[i]);
    return h;
}

/* The header: magic, version (4 bytes each), size, model (8 each), fmu_state at 24 (4), stop time
 * defined (4), stop time (8), checksum at 40 (8). */
enum { HEADER = 48, FMU_STATE_AT = 24, CHECKSUM_AT = 40 };

void fz_reseal(uint8_t *p, size_t n)
{
    if (n < HEADER) return;
    uint8_t head[HEADER];
    memcpy(head, p, HEADER);
    memset(head + CHECKSUM_AT, 0, 8);
    uint64_t h = words_hash(words_hash(0xcbf29ce484222325u, head, HEADER), p + HEADER, n - HEADER);
    memcpy(p + CHECKSUM_AT, &h, 8);
}

uint8_t *fz_corrupted(fz_reader *r, const fz_buffer *b, size_t *n)
{
    size_t cap = b->n + 256;
    uint8_t *p = malloc(cap);
    memcpy(p, b->data, b->n);
    *n = b->n;
    uint8_t edits = fz_u8(r);
    for (int e = 0; e < edits % 4; e++) {
        uint8_t kind = fz_u8(r);
        uint16_t at = fz_u16(r);
        switch (kind % 5) {
        case 0: if (*n) p[at % *n] ^= (uint8_t)(1u << (kind >> 5)); break;
        case 1: if (*n) p[at % *n] = fz_u8(r); break;
        case 2:
            if (*n >= 8) {
                double x = fz_real(r, 1.0);
                memcpy(p + ((at % (*n - 7)) & ~(size_t)7), &x, 8);
            }
            break;
        case 3: *n = at % (*n + 1); break;
        default: {
            size_t k = fz_u8(r);
            if (*n + k <= cap) memset(p + *n, kind, k), *n += k;
        }
        }
    }
    if (edits & 0x80) fz_reseal(p, *n);
    fz_trace("    %d edits, %zu bytes%s", edits % 4, *n, edits & 0x80 ? ", sealed again" : "");
    return p;
}

unsigned fz_recorded_mask(const uint8_t *p, size_t n)
{
    uint32_t m;
    if (n < HEADER) return FZ_ANY3;
    memcpy(&m, p + FMU_STATE_AT, 4);
    return m && !(m & (m - 1)) && (m & FZ_ANY3) ? m : FZ_ANY3;
}

/* ---- the harness's own kinds (codes 100-127): profile files in the resources folder (p0.txt, p1.txt) */

static void k_profile(fz_context *ctx, fz_slot *s, fz_reader *r)
{
    (void)s;
    uint8_t k = fz_u8(r);
    char path[512];
    snprintf(path, sizeof path, "%s/p%d.txt", ctx->resources, k & 1);
    FILE *f = fopen(path, "wb");
    if (!f) fz_fail("cannot write %s", path);
    if (k & 2) { /* raw bytes */
        uint8_t raw[4096];
        fwrite(raw, 1, fz_bytes(r, raw, fz_u16(r) % sizeof raw), f);
    } else { /* rows x h: x from x0 by dx (maybe jittered), h = amplitude times a byte */
        int rows = 1 + fz_u8(r) % 64;
        double x = fz_real(r, 0.0), dx = fz_real(r, 0.01), amp = fz_real(r, 1e-3);
        for (int i = 0; i < rows; i++) {
            uint8_t b = fz_u8(r);
            if (b == 255) fprintf(f, "# comment\n\n");
            fprintf(f, "%.17g %.17g\n", x, amp * ((int8_t)b / 128.0));
            x += k & 4 ? dx * (1.0 + (b & 7) / 8.0) : dx;
        }
        if (k & 8) fprintf(f, "%.17g %.17g", x, 0.0); /* no final newline */
    }
    fclose(f);
}

static int always(void) { return 1; }
static void nothing(fz_context *c, fz_slot *s) { (void)c, (void)s; }
static const fz_call harness_calls[] = {{100, "write a profile file", k_profile, 0, FZ_RUN_KEEPS}};
static const fz_interface fz_harness = {"the harness", always, harness_calls, 1, nothing, 0};

/* The interfaces linked into this binary (each calls_*.c defines one; weak: absent ones are NULL). */
extern const fz_interface fz_fmi2 __attribute__((weak));
extern const fz_interface fz_fmi2me __attribute__((weak));
extern const fz_interface fz_fmi3 __attribute__((weak));
static const fz_interface *const interfaces[] = {&fz_harness, &fz_fmi2, &fz_fmi2me, &fz_fmi3};
#define N_INTERFACES (sizeof interfaces / sizeof interfaces[0])

/* ---- set-up, the loop, the end ---------------------------------------------------------------- */

static void remove_resources(void)
{
    char path[512];
    for (int i = 0; i < 2; i++) {
        snprintf(path, sizeof path, "%s/p%d.txt", ctx.resources, i);
        unlink(path);
    }
    rmdir(ctx.resources);
    if (slowest > 0.0) fprintf(stderr, "==vi-fuzz== slowest call: %s, %.3f s of CPU time\n", slowest_call, slowest);
}

int fz_off(const char *name)
{
    const char *list = getenv("VI_FUZZ_OFF");
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)) != NULL; p += n)
        if ((p == list || p[-1] == ',') && (p[n] == '\0' || p[n] == ',')) return 1;
    return 0;
}

static double env_seconds(const char *name, double fallback)
{
    const char *v = getenv(name);
    double x = v ? strtod(v, NULL) : fallback;
    return x > 0.0 ? x : fallback;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    trace_on = getenv("VI_FUZZ_TRACE") && strcmp(getenv("VI_FUZZ_TRACE"), "0") != 0;
    call_bound = env_seconds("VI_FUZZ_CALL_SECONDS", call_bound);
    hang_bound = env_seconds("VI_FUZZ_HANG_SECONDS", hang_bound);
    snprintf(ctx.resources, sizeof ctx.resources, "%s/vi-fuzz-XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    if (!mkdtemp(ctx.resources)) {
        perror("vi-fuzz: mkdtemp");
        exit(2);
    }
    snprintf(ctx.resources_uri, sizeof ctx.resources_uri, "file://%s", ctx.resources);
    atexit(remove_resources);
    for (size_t k = 0; k < N_INTERFACES; k++) {
        const fz_interface *in = interfaces[k];
        if (!in) continue;
        if (!in->available()) {
            fprintf(stderr, "==vi-fuzz== %s: not in this FMU binary, its calls are skipped\n", in->name);
            continue;
        }
        for (size_t i = 0; i < in->ncalls; i++) {
            const fz_call *c = &in->calls[i];
            if (c->code > 127 || by_code[c->code]) {
                fprintf(stderr, "vi-fuzz: call code %u of %s is taken twice\n", c->code, c->name);
                exit(2);
            }
            by_code[c->code] = c;
            owner[c->code] = in;
        }
    }
    pthread_t t;
    if (pthread_create(&t, NULL, watchdog, NULL) != 0 || pthread_detach(t) != 0) {
        fprintf(stderr, "vi-fuzz: no watchdog thread\n");
        exit(2);
    }
    return 0;
}

/* Free the slot's instance (and its FMU states) through the functions of its FMI version. */
static void release_slot(fz_slot *s)
{
    for (size_t k = 0; k < N_INTERFACES; k++)
        if (interfaces[k] && interfaces[k]->fmi_version == s->version && interfaces[k]->available())
            interfaces[k]->release(&ctx, s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r = {data, size};
    for (int i = 0; i < FZ_SLOTS; i++) {
        memset(&ctx.slot[i], 0, sizeof ctx.slot[i]);
        fz_expect_name(&ctx.slot[i], NULL);
    }
    n_recent = 0;
    fz_trace("---- input of %zu bytes", size);
    for (int k = 0; k < FZ_MAX_CALLS && r.n > 0; k++) {
        uint8_t op = fz_u8(&r);
        const fz_call *call = by_code[op & 127];
        if (!call) continue;
        fz_slot *s = &ctx.slot[op >> 7];
        int version = owner[op & 127]->fmi_version;
        if (s->c && version && version != s->version) { /* an instance of the other FMI version */
            if (!call->instantiates) {
                fz_trace("[%d] slot %d: %s skipped: the slot holds an FMI %d.0 instance", k, op >> 7, call->name,
                         s->version);
                continue;
            }
            release_slot(s);
        }
        fz_trace("[%d] slot %d: %s", k, op >> 7, call->name);
        unsigned mask_before = s->mask;
        call->run(&ctx, s, &r);
        fz_energy_after_call(s, call, mask_before);
    }
    for (int i = 0; i < FZ_SLOTS; i++) release_slot(&ctx.slot[i]);
    for (int i = 0; i < FZ_BUFFERS; i++) {
        free(ctx.buffer[i].data);
        ctx.buffer[i] = (fz_buffer){NULL, 0};
    }
    if (live_blocks != 0) {
        long n = live_blocks;
        live_blocks = 0;
        fz_fail("%ld blocks of the importer's memory are still held after every instance was freed", n);
    }
    return 0;
}
