/*
 * vi_fmi_instance.c - the FMI layer's instance life cycle: instantiation with its checks, freeing,
 * debug logging, experiment setup, initialization, termination and reset.
 */
#include "vi_fmi_layer_internal.h"

#include <math.h>
#include <string.h>

vi_status vi_fmi_set_debug_logging(void *instance, const char *fn, int on, size_t n, const char *const categories[])
{
    ENTER(VI_CALL_SET_DEBUG_LOGGING);
    if (n > 0 && !categories) return vi_fmi_refuse(c, "%s: categories is NULL", fn);
    unsigned mask = 0;
    for (size_t i = 0; i < n; i++) {
        int k = 0;
        while (k < VI_CAT_COUNT && (!categories[i] || strcmp(categories[i], vi_fmi_category_name(c, k)) != 0)) k++;
        if (k == VI_CAT_COUNT)
            return vi_fmi_refuse(c, "%s: unknown log category '%s'", fn, categories[i] ? categories[i] : "(null)");
        mask |= 1u << k;
    }
    if (n == 0) mask = (1u << VI_CAT_COUNT) - 1u;
    c->log_mask = on ? mask : c->log_mask & ~mask; /* on: exactly the categories named */
    return done(c);
}

vi_fmi_instance *vi_fmi_instantiate(const vi_face *face, const vi_callbacks *cb, const char *fn, const char *name,
                             vi_kind kind, const char *guid, const char *resource_dir, const char *resource_label,
                             int logging_on)
{
    vi_fmi_instance tmp = {.face = face, .cb = *cb, .name = (char *)(name ? name : "?")};
    if (!cb->alloc || !cb->free) {
        LOG_ERROR(&tmp, "%s: the callbacks allocateMemory and freeMemory are required", fn);
        return NULL;
    }
    if (!name || !*name) {
        LOG_ERROR(&tmp, "%s: instanceName must be a non-empty string", fn);
        return NULL;
    }
    if (kind != VI_KIND_CS && !(kind == VI_KIND_ME && MODEL->n_states > 0)) {
        LOG_ERROR(&tmp, "%s: %s does not offer the interface type asked for (%s)", fn, MODEL->model_identifier,
                  kind == VI_KIND_ME ? "Model Exchange" : "unknown type");
        return NULL;
    }
    if (!guid || strcmp(guid, MODEL->guid) != 0) {
        LOG_ERROR(&tmp, "%s: GUID '%s' does not match this FMU's '%s'", fn, guid ? guid : "(null)", MODEL->guid);
        return NULL;
    }
    vi_fmi_instance *c = cb->alloc(1, sizeof *c);
    char *copy = cb->alloc(strlen(name) + 1, 1);
    void *model = cb->alloc(1, MODEL->instance_size);
    void *outputs = cb->alloc(1, MODEL->outputs_size);
    if (!c || !copy || !model || !outputs) {
        LOG_ERROR(&tmp, "%s: out of memory", fn);
        void *blocks[] = {c, copy, model, outputs};
        for (int i = 0; i < 4; i++)
            if (blocks[i]) cb->free(blocks[i]);
        return NULL;
    }
    memset(c, 0, sizeof *c);
    memset(model, 0, MODEL->instance_size);
    strcpy(copy, name);
    c->face = face;
    c->cb = *cb;
    c->kind = kind;
    c->model = model;
    c->outputs = outputs;
    c->name = copy;
    c->state = VI_ST_INSTANTIATED;
    c->log_mask = logging_on ? (1u << VI_CAT_COUNT) - 1u : 0u;
    MODEL->init(c->model, vi_fmi_model_log, c);
    if (MODEL->set_resources && MODEL->set_resources(c->model, resource_dir) < 0) {
        LOG_ERROR(c, "%s: resources '%s': %s", fn, resource_label ? resource_label : "(null)", MODEL->message(c->model));
        vi_fmi_free(c, fn);
        return NULL;
    }
    if (vi_fmi_logs(c, VI_CAT_CALL)) vi_fmi_log(c, VI_STATUS_OK, VI_CAT_CALL, "%s: %s", fn, name);
    return c;
}

void vi_fmi_free(vi_fmi_instance *c, const char *fn)
{
    if (!c) return;
    if (vi_fmi_logs(c, VI_CAT_CALL)) vi_fmi_log(c, VI_STATUS_OK, VI_CAT_CALL, "%s", fn);
    MODEL->release(c->model);
    void (*release)(void *) = c->cb.free;
    release(c->outputs);
    release(c->model);
    release(c->name);
    release(c);
}

vi_status vi_fmi_setup_experiment(void *instance, const char *fn, int tolerance_defined, double tolerance,
                                   double start, int stop_defined, double stop)
{
    ENTER(VI_CALL_SETUP_EXPERIMENT);
    if (!isfinite(start) || (tolerance_defined && !(tolerance > 0.0 && tolerance < 1.0)) ||
        (stop_defined && !(stop >= start)))
        return vi_fmi_refuse(c, "%s: need a finite start time, a tolerance in (0, 1) and stop time >= start time (got "
                                 "start %g, tolerance %g, stop %g)", fn, start, tolerance, stop);
    MODEL->setup_experiment(c->model, start, tolerance_defined != 0, tolerance);
    c->stop_time_defined = stop_defined != 0;
    c->stop_time = stop;
    return done(c);
}

vi_status vi_fmi_enter_init(void *instance, const char *fn)
{
    ENTER(VI_CALL_ENTER_INIT);
    c->state = VI_ST_INIT;
    return done(c);
}

vi_status vi_fmi_exit_init(void *instance, const char *fn)
{
    ENTER(VI_CALL_EXIT_INIT);
    if (c->kind == VI_KIND_ME) {
        if (MODEL->me_initialize(c->model) < 0) return vi_fmi_fail(c, fn);
        c->initialized = 1;
        c->state = VI_ST_EVENT; /* the importer runs the initial event iteration */
        c->t_committed = MODEL->time(c->model);
        c->event_passes = 0;
        return done(c);
    }
    if (MODEL->initialize(c->model) < 0) return vi_fmi_fail(c, fn);
    c->initialized = 1;
    c->state = VI_ST_STEP_COMPLETE;
    return done(c);
}

vi_status vi_fmi_terminate(void *instance, const char *fn)
{
    ENTER(VI_CALL_TERMINATE);
    if (MODEL->terminate) MODEL->terminate(c->model);
    c->state = VI_ST_TERMINATED;
    return done(c);
}

vi_status vi_fmi_reset(void *instance, const char *fn)
{
    ENTER(VI_CALL_RESET);
    MODEL->reset(c->model);
    c->stop_time_defined = 0;
    c->initialized = 0;
    c->state = VI_ST_INSTANTIATED;
    return done(c);
}

double vi_fmi_time(const vi_fmi_instance *c) { return MODEL->time(c->model); }
