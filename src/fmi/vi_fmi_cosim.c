/*
 * vi_fmi_cosim.c - the FMI layer's Co-Simulation step: the checks of a communication step (its point,
 * size and the stop time) and the model's advance, to the end of the step or to its first event.
 */
#include "vi_fmi_layer_internal.h"

#include <float.h>
#include <math.h>

/* A step's current communication point may differ from the FMU's time by this many units of the
 * time resolution (DBL_EPSILON max(1 s, |t|)); a step must advance time by at least VI_MIN_STEP_ULPS. */
#define VI_TIME_MATCH_ULPS 1e3
#define VI_MIN_STEP_ULPS 16.0

static vi_status do_step(void *instance, const char *fn, double tc, double h, int *event)
{
    ENTER(VI_CALL_DO_STEP);
    double t = MODEL->time(c->model);
    double unit = DBL_EPSILON * (fabs(t) > 1.0 ? fabs(t) : 1.0); /* the resolution of time here, at least that at 1 s */
    double t_end = tc + h;
    /* Refused arguments leave the instance as it was (Error from fmi2DoStep and fmi3DoStep: "the step could
     * not be carried out at all"; the master may try another step). */
    if (!isfinite(tc))
        return vi_fmi_refuse(c, "%s: currentCommunicationPoint %g is not finite", fn, tc);
    if (!isfinite(h) || !(h > 0.0))
        return vi_fmi_refuse(c, "%s: the communication step size must be finite and positive (got %g)", fn, h);
    if (fabs(tc - t) > VI_TIME_MATCH_ULPS * unit)
        return vi_fmi_refuse(c, "%s: currentCommunicationPoint %.17g does not match the FMU's time %.17g", fn, tc, t);
    if (!(t_end - t >= VI_MIN_STEP_ULPS * unit))
        return vi_fmi_refuse(c, "%s: a step of %g s is too short to advance time at t = %.17g s: use at least %g s "
                                 "(%g units of the time resolution there); nothing was done",
                              fn, h, t, VI_MIN_STEP_ULPS * unit, VI_MIN_STEP_ULPS);
    if (c->stop_time_defined && t_end > c->stop_time + VI_TIME_MATCH_ULPS * unit)
        return vi_fmi_refuse(c, "%s: the step to %.17g passes the stop time %.17g", fn, t_end, c->stop_time);
    int rc = event && MODEL->advance_to_event ? MODEL->advance_to_event(c->model, t_end)
                                              : MODEL->advance(c->model, t_end);
    if (rc < 0) return vi_fmi_fail(c, fn);
    double t_now = MODEL->time(c->model);
    if ((rc == VI_FMU_OK && t_now != t_end) || (rc == VI_FMU_EVENT && !(event && t_now > t && t_now <= t_end))) {
        /* never OK for a step that did not happen */
        LOG_ERROR(c, "%s: the model stopped at t = %.17g s instead of %s %.17g s", fn, t_now,
                  rc == VI_FMU_EVENT ? "after the start and at most" : "", t_end);
        c->state = VI_ST_ERROR;
        return VI_STATUS_ERROR;
    }
    if (rc == VI_FMU_EVENT) {
        *event = 1;
        return done(c);
    }
    if (rc > 0) { /* stopped early at a consistent state: the last successful time tells where */
        vi_fmi_log(c, VI_STATUS_DISCARD, VI_CAT_DISCARD, "%s: %s", fn, MODEL->message(c->model));
        c->state = VI_ST_STEP_FAILED;
        return VI_STATUS_DISCARD;
    }
    return done(c);
}

vi_status vi_fmi_do_step(void *instance, const char *fn, double tc, double h) { return do_step(instance, fn, tc, h, NULL); }

vi_status vi_fmi_do_step_to_event(void *instance, const char *fn, double tc, double h, int *event)
{
    int stopped = 0;
    vi_status st = do_step(instance, fn, tc, h, &stopped);
    if (event) *event = stopped;
    return st;
}
