/* vt_companion_me.c - Model Exchange of the vehicle-track companion models (vt_companion.h): the
 * importer integrates the model's x' = f(t, x) with the inputs as they are set. */
#include <string.h>

#include "vt_companion.h"

static vt_core *core(void *m) { return (vt_core *)((vt_instance *)m)->data; }

int vt_me_initialize(void *m)
{
    if (vt_prepare(m) < 0) return -1;
    vt_core *c = core(m);
    c->t_step = c->t;
    memcpy(c->x_step, c->x, sizeof c->x_step);
    return 0;
}

/* The inputs hold from now: they are taken as they are at every time the importer sets. */
void vt_me_set_time(void *m, double t)
{
    vt_core *c = core(m);
    c->t = c->t_in = t;
}

void vt_me_get_states(void *m, double x[])
{
    const vt_instance *I = m;
    memcpy(x, core(m)->x, sizeof(double) * (size_t)I->def->n);
}

void vt_me_set_states(void *m, const double x[])
{
    const vt_instance *I = m;
    memcpy(core(m)->x, x, sizeof(double) * (size_t)I->def->n);
}

void vt_me_derivatives(void *m, double dx[])
{
    const vt_instance *I = m;
    const vt_core *c = core(m);
    I->def->rhs(c->t, c->x, dx, I->data);
}

void vt_me_nominals(const void *m, double nominal[])
{
    const vt_instance *I = m;
    I->def->scales(I->data, nominal);
}

/* No events of their own: inputs set in event mode simply hold from now. */
int vt_me_event_update(void *m, vi_fmu_event *ev)
{
    (void)ev;
    vt_me_enter_continuous(m);
    return 0;
}

void vt_me_enter_continuous(void *m)
{
    vt_core *c = core(m);
    c->inputs_changed = 0;
    c->t_in = c->t;
}

int vt_me_completed_step(void *m)
{
    const vt_instance *I = m;
    vt_core *c = core(m);
    if (I->def->step_done) I->def->step_done(I->data, c->t_step, c->x_step);
    c->t_step = c->t;
    memcpy(c->x_step, c->x, sizeof c->x_step);
    return 0;
}
