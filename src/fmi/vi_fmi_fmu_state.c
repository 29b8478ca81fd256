/*
 * vi_fmi_fmu_state.c - the FMI layer's FMU states: the checked envelope around the model's plain-data
 * block (header, checksum, the table's values, the model's own check), its serialization, and the
 * calls that take, restore, free, size, serialize and deserialize one.
 */
#include "vi_fmi_layer_internal.h"

#include <math.h>
#include <string.h>

/* An FMU state: this header, then MODEL->state_size bytes of the model's plain data. It is taken
 * and restored in every FMI state but fatal; restoring puts the instance into the FMI state the
 * state was taken in. Serialized, it is the same bytes (for the same build of the FMU). Before a
 * state is used (set, serialized, deserialized) every part is checked: header, checksum, the
 * table's values, and the model's own fields (state_check hook); the first bad part is named. */
#define VI_STATE_MAGIC 0x554d4956u /* "VIMU" */
#define VI_STATE_VERSION 4u

typedef struct {
    uint32_t magic, version;
    uint64_t size;              /* bytes in all, this header included */
    uint64_t model;             /* hash (below) of the model's GUID: a state of another model is refused */
    uint32_t fmu_state;         /* the FMI state it was taken in (one VI_ST_* bit) */
    uint32_t stop_time_defined; /* the setup's stop time */
    double stop_time;
    uint64_t checksum;          /* hash (below) of all bytes, this field taken as 0 */
} vi_saved_state;

static size_t saved_size(void) { return sizeof(vi_saved_state) + MODEL->state_size; }
static void *payload(const vi_saved_state *s) { return (char *)s + sizeof *s; }

/* The hash behind model_id and checksum: the multiply-xor round of FNV-1a (Fowler, Noll, Vo: xor,
 * then multiply by the 64-bit FNV prime) applied to 64-bit words instead of bytes, each followed by
 * a xor-shift so that high bits feed back into low ones, in four interleaved lanes, the lanes and
 * the tail bytes folded in at the end. It is not FNV-1a itself (which goes byte by byte): a state of
 * a few kB costs a fraction of a microsecond. Every round is a bijection of its lane and of its
 * word, so any change of a single word (a single bit flip, say) changes the result. Start with
 * h = VI_FNV_OFFSET. */
#define VI_FNV_OFFSET 0xcbf29ce484222325u
#define VI_FNV_PRIME 0x100000001b3u
#define VI_HASH_LANES 4
static uint64_t hash_round(uint64_t h, uint64_t w)
{
    h = (h ^ w) * VI_FNV_PRIME;
    return h ^ (h >> 32);
}

static uint64_t state_hash(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    uint64_t lane[VI_HASH_LANES], w;
    for (int k = 0; k < VI_HASH_LANES; k++) lane[k] = hash_round(h, (uint64_t)k);
    size_t i = 0;
    for (; i + 8 * VI_HASH_LANES <= n; i += 8 * VI_HASH_LANES)
        for (int k = 0; k < VI_HASH_LANES; k++) {
            memcpy(&w, p + i + 8 * (size_t)k, sizeof w);
            lane[k] = hash_round(lane[k], w);
        }
    h = hash_round(lane[0], (uint64_t)n);
    for (int k = 1; k < VI_HASH_LANES; k++) h = hash_round(h, lane[k]);
    for (; i < n; i++) h = hash_round(h, p[i]);
    return h;
}

static uint64_t model_id(void) { return state_hash(VI_FNV_OFFSET, MODEL->guid, strlen(MODEL->guid)); }

static uint64_t checksum(const vi_saved_state *s)
{
    vi_saved_state head = *s;
    head.checksum = 0;
    return state_hash(state_hash(VI_FNV_OFFSET, &head, sizeof head), payload(s), MODEL->state_size);
}

/* The table's values in a saved block: what the setters guarantee (finite Reals inside their
 * ranges, Integers inside theirs, enumerations items of their type, Booleans 0 or 1, terminated
 * Strings). 0, or -1 with the first bad one. */
static int check_values(const void *block, char *msg, size_t n)
{
    for (int vr = 0; vr < MODEL->nvariables; vr++) {
        const vi_variable *v = &MODEL->variables[vr];
        if (v->group == VI_GROUP_OUTPUTS) continue;
        const char *p = (const char *)vi_fmi_group_in(block, v->group) + v->offset;
        double x, dx;
        int k;
        switch (v->type) {
        case VI_Real:
            memcpy(&x, p, sizeof x);
            if (!isfinite(x)) VI_FAIL(msg, n, "%s = %g is not finite", v->name, x);
            if (vi_fmi_check_range(v, x, msg, n) < 0) return -1;
            if (v->group != VI_GROUP_INPUTS) break;
            memcpy(&dx, (const char *)vi_fmi_group_in(block, VI_GROUP_INPUT_DERIVATIVES) + v->offset, sizeof dx);
            if (!isfinite(dx)) VI_FAIL(msg, n, "the derivative of %s = %g is not finite", v->name, dx);
            break;
        case VI_String:
            if (!memchr(p, '\0', VI_STRING_SIZE)) VI_FAIL(msg, n, "%s is not a terminated string", v->name);
            break;
        default:
            memcpy(&k, p, sizeof k);
            if (v->type == VI_Boolean && k != 0 && k != 1)
                VI_FAIL(msg, n, "%s = %d is not a Boolean", v->name, k);
            if (v->type != VI_Boolean && vi_fmi_check_range(v, k, msg, n) < 0) return -1;
        }
    }
    return 0;
}

/* Was the saved FMI state after initialization? Then VI_FMU_RUNNING_CS or _ME (the instance's interface). */
static int saved_running(const vi_fmi_instance *c, const vi_saved_state *s)
{
    if (!(s->fmu_state & (VI_ST_RUNNING | VI_ST_ERROR))) return 0;
    return c->kind == VI_KIND_ME ? VI_FMU_RUNNING_ME : VI_FMU_RUNNING_CS;
}

/* The states an instance of this kind can be in. */
static unsigned kind_states(const vi_fmi_instance *c)
{
    unsigned common = VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_TERMINATED | VI_ST_ERROR;
    return common | (c->kind == VI_KIND_ME ? VI_ST_EVENT | VI_ST_CONTINUOUS
                                           : VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED |
                                                 (c->face->cs_event_mode ? VI_ST_EVENT : 0u));
}

/* Is s (aligned, at least a header) a state of this FMU that may be used? Logs the first reason
 * why not. `size`: the bytes the caller has. */
static int check_saved(vi_fmi_instance *c, const char *fn, const vi_saved_state *s, size_t size)
{
    char why[320] = "";
    if (!s) vi_snprintf(why, sizeof why, "the state is NULL");
    else if (s->magic != VI_STATE_MAGIC) vi_snprintf(why, sizeof why, "not an FMU state of this layer (magic number)");
    else if (s->version != VI_STATE_VERSION) vi_snprintf(why, sizeof why, "an FMU state of another layer version");
    else if (s->model != model_id()) vi_snprintf(why, sizeof why, "an FMU state of another model (GUID)");
    else if (s->size != saved_size() || size != saved_size())
        vi_snprintf(why, sizeof why, "size %zu bytes: a state of this build of %s has %zu", size, MODEL->model_identifier,
                    saved_size());
    else if (s->checksum != checksum(s)) vi_snprintf(why, sizeof why, "checksum mismatch: the state was altered");
    else if (!(s->fmu_state & VI_ST_ANY_BUT_FATAL) || (s->fmu_state & (s->fmu_state - 1u)))
        vi_snprintf(why, sizeof why, "field fmu_state = %u is not an FMI state", (unsigned)s->fmu_state);
    else if (!(s->fmu_state & kind_states(c)))
        vi_snprintf(why, sizeof why, "taken in state '%s', which an instance of this interface never is in",
                    vi_fmi_state_name(s->fmu_state));
    else if (s->stop_time_defined > 1u || (s->stop_time_defined && !isfinite(s->stop_time)))
        vi_snprintf(why, sizeof why, "field stop_time is not finite");
    else if (check_values(payload(s), why, sizeof why) < 0 ||
             (MODEL->state_check && MODEL->state_check(payload(s), saved_running(c, s), why, sizeof why) < 0)) {
        if (!why[0]) vi_snprintf(why, sizeof why, "invalid field");
    }
    if (why[0]) LOG_ERROR(c, "%s: invalid FMU state: %s", fn, why);
    return why[0] == '\0';
}

vi_status vi_fmi_get_fmu_state(void *instance, const char *fn, void **state)
{
    ENTER(VI_CALL_FMU_STATE);
    if (!state) return vi_fmi_refuse(c, "%s: FMUstate is NULL", fn);
    if ((c->state & VI_ST_RUNNING) && MODEL->checkpoint && MODEL->checkpoint(c->model) != 0)
        return vi_fmi_fail(c, fn);
    vi_saved_state *s = *state ? *state : c->cb.alloc(1, saved_size());
    if (!s) return vi_fmi_refuse(c, "%s: out of memory", fn);
    *s = (vi_saved_state){.magic = VI_STATE_MAGIC, .version = VI_STATE_VERSION, .size = saved_size(),
                          .model = model_id(), .fmu_state = (uint32_t)c->state,
                          .stop_time_defined = (uint32_t)c->stop_time_defined, .stop_time = c->stop_time};
    memcpy(payload(s), MODEL->state(c->model), MODEL->state_size);
    s->checksum = checksum(s);
    *state = s;
    return done(c);
}

vi_status vi_fmi_set_fmu_state(void *instance, const char *fn, const void *state)
{
    ENTER(VI_CALL_FMU_STATE);
    const vi_saved_state *s = state;
    if (!check_saved(c, fn, s, s ? s->size : 0)) return VI_STATUS_ERROR;
    memcpy(MODEL->state(c->model), payload(s), MODEL->state_size);
    c->stop_time_defined = (int)s->stop_time_defined;
    c->stop_time = s->stop_time;
    c->state = s->fmu_state;
    c->event_passes = 0;
    c->initialized = saved_running(c, s) != 0;
    if (MODEL->restore && MODEL->restore(c->model, saved_running(c, s)) != 0) return vi_fmi_fail(c, fn);
    c->t_committed = MODEL->time(c->model);
    return done(c);
}

vi_status vi_fmi_free_fmu_state(void *instance, const char *fn, void **state)
{
    ENTER(VI_CALL_FMU_STATE);
    if (state && *state) {
        c->cb.free(*state);
        *state = NULL;
    }
    return done(c);
}

vi_status vi_fmi_fmu_state_size(void *instance, const char *fn, const void *state, size_t *size)
{
    ENTER(VI_CALL_FMU_STATE);
    if (!size) return vi_fmi_refuse(c, "%s: size is NULL", fn);
    const vi_saved_state *s = state;
    if (!check_saved(c, fn, s, s ? s->size : 0)) return VI_STATUS_ERROR;
    *size = saved_size();
    return done(c);
}

vi_status vi_fmi_serialize(void *instance, const char *fn, const void *state, unsigned char *bytes, size_t size)
{
    ENTER(VI_CALL_FMU_STATE);
    if (!bytes || size < saved_size())
        return vi_fmi_refuse(c, "%s: need a buffer of %zu bytes (got %zu)", fn, saved_size(), size);
    const vi_saved_state *s = state;
    if (!check_saved(c, fn, s, s ? s->size : 0)) return VI_STATUS_ERROR;
    memcpy(bytes, state, saved_size());
    return done(c);
}

vi_status vi_fmi_deserialize(void *instance, const char *fn, const unsigned char *bytes, size_t size, void **state)
{
    ENTER(VI_CALL_FMU_STATE);
    if (!bytes || !state) return vi_fmi_refuse(c, "%s: NULL argument", fn);
    if (size < sizeof(vi_saved_state) || size > saved_size())
        return vi_fmi_refuse(c, "%s: invalid FMU state: size %zu bytes: a state of this build of %s has %zu", fn, size,
                              MODEL->model_identifier, saved_size());
    vi_saved_state *s = c->cb.alloc(1, saved_size()); /* aligned, checked before it replaces anything */
    if (!s) return vi_fmi_refuse(c, "%s: out of memory", fn);
    memcpy(s, bytes, size);
    if (!check_saved(c, fn, s, size)) {
        c->cb.free(s);
        return VI_STATUS_ERROR;
    }
    if (*state) {
        memcpy(*state, s, saved_size());
        c->cb.free(s);
    } else {
        *state = s;
    }
    return done(c);
}
