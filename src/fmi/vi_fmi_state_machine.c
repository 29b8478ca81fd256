/*
 * vi_fmi_state_machine.c - the FMI layer's state machine: in which FMI states each call is allowed,
 * and the entry every call of the layer passes through (vi_fmi_layer.h).
 */
#include "vi_fmi_layer_internal.h"

#define ST_READABLE (VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED | VI_ST_ERROR | \
                     VI_ST_EVENT | VI_ST_CONTINUOUS)
#define ST_ME_READABLE (VI_ST_INIT | VI_ST_EVENT | VI_ST_CONTINUOUS | VI_ST_TERMINATED | VI_ST_ERROR)

/* In which FMI states each call is allowed: the state machines of FMI 2.0 (sections 3.2.3 and 4.2.4) and
 * FMI 3.0 (which adds Event Mode to Co-Simulation). */
const unsigned vi_fmi_allowed[VI_CALL_COUNT] = {
    [VI_CALL_SET_DEBUG_LOGGING] = VI_ST_ANY_BUT_FATAL,
    [VI_CALL_SETUP_EXPERIMENT] = VI_ST_INSTANTIATED,
    [VI_CALL_ENTER_INIT] = VI_ST_INSTANTIATED,
    [VI_CALL_EXIT_INIT] = VI_ST_INIT,
    [VI_CALL_TERMINATE] = VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_EVENT | VI_ST_CONTINUOUS,
    [VI_CALL_RESET] = VI_ST_ANY_BUT_FATAL,
    [VI_CALL_GET] = ST_READABLE,
    [VI_CALL_SET_REAL] = VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_EVENT | VI_ST_CONTINUOUS,
    [VI_CALL_SET_DISCRETE] = VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_EVENT,
    [VI_CALL_FMU_STATE] = VI_ST_ANY_BUT_FATAL,
    [VI_CALL_DIRECTIONAL_DERIVATIVE] = ST_READABLE,
    [VI_CALL_SET_INPUT_DERIVATIVES] = VI_ST_INSTANTIATED | VI_ST_INIT | VI_ST_STEP_COMPLETE,
    [VI_CALL_GET_OUTPUT_DERIVATIVES] = VI_ST_INIT | VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED |
                                       VI_ST_ERROR,
    [VI_CALL_DO_STEP] = VI_ST_STEP_COMPLETE,
    [VI_CALL_CANCEL_STEP] = VI_ST_ANY_BUT_FATAL,
    [VI_CALL_GET_STATUS] = VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED,
    [VI_CALL_GET_LAST_STATUS] = VI_ST_STEP_COMPLETE | VI_ST_STEP_FAILED | VI_ST_TERMINATED | VI_ST_ERROR,
    [VI_CALL_ENTER_EVENT_MODE] = VI_ST_EVENT | VI_ST_CONTINUOUS | VI_ST_STEP_COMPLETE,
    [VI_CALL_NEW_DISCRETE_STATES] = VI_ST_EVENT,
    [VI_CALL_ENTER_CONTINUOUS_MODE] = VI_ST_EVENT,
    [VI_CALL_COMPLETED_STEP] = VI_ST_CONTINUOUS,
    [VI_CALL_SET_TIME] = VI_ST_EVENT | VI_ST_CONTINUOUS,
    [VI_CALL_SET_STATES] = VI_ST_CONTINUOUS,
    [VI_CALL_GET_DERIVATIVES] = VI_ST_EVENT | VI_ST_CONTINUOUS | VI_ST_TERMINATED | VI_ST_ERROR,
    [VI_CALL_GET_EVENT_INDICATORS] = ST_ME_READABLE,
    [VI_CALL_GET_STATES] = ST_ME_READABLE,
    [VI_CALL_GET_NOMINALS] = VI_ST_INSTANTIATED | VI_ST_EVENT | VI_ST_CONTINUOUS | VI_ST_TERMINATED | VI_ST_ERROR,
    [VI_CALL_ENTER_STEP_MODE] = VI_ST_EVENT,
};

const char *vi_fmi_state_name(unsigned s)
{
    switch (s) {
    case VI_ST_INSTANTIATED: return "instantiated";
    case VI_ST_INIT: return "initialization mode";
    case VI_ST_STEP_COMPLETE: return "step complete";
    case VI_ST_STEP_FAILED: return "step failed";
    case VI_ST_TERMINATED: return "terminated";
    case VI_ST_ERROR: return "error";
    case VI_ST_EVENT: return "event mode";
    case VI_ST_CONTINUOUS: return "continuous-time mode";
    default: return "fatal";
    }
}

vi_fmi_instance *vi_fmi_enter(void *instance, vi_call call, const char *fn)
{
    vi_fmi_instance *c = instance;
    if (!c) return NULL;
    if (!(c->state & vi_fmi_allowed[call])) {
        LOG_ERROR(c, "%s: not allowed in state '%s'", fn, vi_fmi_state_name(c->state));
        return NULL;
    }
    if (vi_fmi_logs(c, VI_CAT_CALL)) vi_fmi_log(c, VI_STATUS_OK, VI_CAT_CALL, "%s", fn);
    c->result_warning = 0;
    return c;
}

vi_status vi_fmi_fail(vi_fmi_instance *c, const char *fn)
{
    LOG_ERROR(c, "%s: %s", fn, MODEL->message(c->model));
    c->state = VI_ST_ERROR;
    return VI_STATUS_ERROR;
}
