"""FMI-level behaviour the physics tests never reach: the status functions, the
state machine after failures, input values and derivatives, fmi2SetupExperiment's place, the stop
time, calculated parameters in initialization mode. Each test names the fault it catches."""
import ctypes

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (fmi2DoStepStatus, fmi2LastSuccessfulTime, fmi2PendingStatus, fmi2Status,
                       fmi2Terminated)

from conftest import effective, start

OK, DISCARD, ERROR = 0, 2, 3


def raw(s, fn, *args):
    """Call an FMI function and return its status instead of raising."""
    try:
        return getattr(s, fn)(s.component, *args)
    except FMICallException as e:
        return e.status


@pytest.fixture
def running(logged, vr):
    log = logged()
    s = log.instantiate()
    start(s, vr, dict(contact_model=1, a=1e-4, Y=1e9))  # Y: the force stays below F_Y (no validity note)
    yield log, s
    s.freeInstance()


def errors(log):
    return [m for st, _, m in log.messages if st == ERROR]


# ---- status functions ----

def test_get_status_has_nothing_pending(running):
    log, s = running
    v = fmi2Status(-1)
    assert raw(s, "fmi2GetStatus", fmi2DoStepStatus, ctypes.byref(v)) == DISCARD
    assert v.value == -1
    assert any(st == DISCARD and cat == "logStatusDiscard" and "fmi2GetStatus" in m for st, cat, m in log.messages)
    assert raw(s, "fmi2GetStatus", fmi2DoStepStatus, None) == ERROR


def test_last_successful_time_is_the_fmu_time(running, vr):
    _, s = running
    assert s.getRealStatus(fmi2LastSuccessfulTime) == 0.0
    s.doStep(0.0, 1e-3)
    s.doStep(1e-3, 5e-4)
    assert s.getRealStatus(fmi2LastSuccessfulTime) == 1e-3 + 5e-4
    v = ctypes.c_double(-1.0)
    assert raw(s, "fmi2GetRealStatus", fmi2DoStepStatus, ctypes.byref(v)) == DISCARD and v.value == -1.0
    assert raw(s, "fmi2GetRealStatus", fmi2LastSuccessfulTime, None) == ERROR


def test_boolean_status_never_asks_to_terminate(running):
    _, s = running
    v = ctypes.c_int(7)
    assert raw(s, "fmi2GetBooleanStatus", fmi2Terminated, ctypes.byref(v)) == OK and v.value == 0
    v = ctypes.c_int(7)
    assert raw(s, "fmi2GetBooleanStatus", fmi2PendingStatus, ctypes.byref(v)) == DISCARD and v.value == 7


def test_integer_and_string_status_have_nothing_to_report(running):
    _, s = running
    i = ctypes.c_int(7)
    assert raw(s, "fmi2GetIntegerStatus", fmi2DoStepStatus, ctypes.byref(i)) == DISCARD and i.value == 7
    p = ctypes.c_char_p(b"unchanged")
    assert raw(s, "fmi2GetStringStatus", fmi2PendingStatus, ctypes.byref(p)) == DISCARD and p.value == b"unchanged"


def test_status_functions_are_refused_before_initialization(logged):
    log = logged()
    s = log.instantiate()
    v = ctypes.c_double(-1.0)
    assert raw(s, "fmi2GetRealStatus", fmi2LastSuccessfulTime, ctypes.byref(v)) == ERROR
    assert any("fmi2GetRealStatus" in m and "not allowed" in m for m in errors(log))
    s.freeInstance()


def test_free_instance_of_null_does_nothing(running, logged, vr):
    """fmi2FreeInstance(NULL) returns without a crash and touches no instance: the running one steps
    on bit for bit as one that saw no such call, and says nothing."""
    log, s = running
    other = logged(name="other").instantiate()
    start(other, vr, dict(contact_model=1, a=1e-4, Y=1e9))
    s.fmi2FreeInstance(None)
    names = [vr[n] for n in ("y", "v", "F", "delta")]
    for k in range(50):
        s.doStep(k * 1e-4, 1e-4)
        other.doStep(k * 1e-4, 1e-4)
        assert s.getReal(names) == other.getReal(names), k
    assert log.messages == []
    other.freeInstance()


# ---- the state machine after failures ----

def test_calls_refused_after_a_failed_initialization(logged, vr):
    log = logged()
    s = log.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.setReal([vr["R1"]], [0.0])  # in its range, but with R2 = 0 two planes: refused at initialization
    with pytest.raises(FMICallException):
        s.exitInitializationMode()
    assert any("fmi2ExitInitializationMode" in m and "R1 = R2 = 0" in m for m in errors(log))
    for name, call in (("fmi2DoStep", lambda: s.doStep(0.0, 1e-4)),
                       ("fmi2ExitInitializationMode", s.exitInitializationMode),
                       ("fmi2EnterInitializationMode", s.enterInitializationMode),
                       ("fmi2SetReal", lambda: s.setReal([vr["m"]], [1.0])),
                       ("fmi2Terminate", s.terminate)):
        with pytest.raises(FMICallException):
            call()
        assert any(name in m and "not allowed in state 'error'" in m for m in errors(log)), name
    s.reset()  # the way out
    start(s, vr)
    s.doStep(0.0, 1e-4)
    s.freeInstance()


def test_set_fmu_state_with_null_or_foreign_pointer_is_refused(running):
    log, s = running
    assert raw(s, "fmi2SetFMUstate", None) == ERROR
    junk = ctypes.create_string_buffer(b"\x00" * 64)
    assert raw(s, "fmi2SetFMUstate", ctypes.cast(junk, ctypes.c_void_p)) == ERROR
    assert any("fmi2SetFMUstate" in m and "magic" in m for m in errors(log))
    s.doStep(0.0, 1e-4)


def test_setup_experiment_only_when_instantiated(logged, vr):
    log = logged()
    s = log.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    with pytest.raises(FMICallException):
        s.setupExperiment(startTime=1.0)
    s.exitInitializationMode()
    with pytest.raises(FMICallException):
        s.setupExperiment(startTime=1.0)
    assert sum("fmi2SetupExperiment" in m and "not allowed" in m for m in errors(log)) == 2
    s.doStep(0.0, 1e-4)  # time still starts at 0
    s.freeInstance()


@pytest.mark.parametrize("tolerance, start, stop", [
    (0.0, 0.0, None), (1.0, 0.0, None), (-1e-6, 0.0, None), (float("nan"), 0.0, None),
    (None, float("inf"), None), (None, float("nan"), None), (None, 1.0, 1.0 - 1e-12)])
def test_setup_experiment_refuses_what_no_experiment_can_have(logged, vr, tolerance, start, stop):
    """A tolerance outside (0, 1) (its ends included), a start time that is not finite, a stop time
    before the start: refused by fmi2SetupExperiment itself, naming the three conditions and the
    values; a valid call then sets the experiment (stop = start is valid)."""
    log = logged()
    s = log.instantiate()
    args = (tolerance is not None, ctypes.c_double(tolerance or 0.0), ctypes.c_double(start), stop is not None,
            ctypes.c_double(stop or 0.0))
    assert raw(s, "fmi2SetupExperiment", *args) == ERROR
    assert len(errors(log)) == 1 and errors(log)[0].startswith(
        "fmi2SetupExperiment: need a finite start time, a tolerance in (0, 1) and stop time >= start time (got "
        "start "), errors(log)
    s.setupExperiment(tolerance=1e-6, startTime=1.0, stopTime=1.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    assert s.getRealStatus(fmi2LastSuccessfulTime) == 1.0
    s.freeInstance()


def test_stop_time_is_enforced(logged, vr):
    log = logged()
    s = log.instantiate()
    start(s, vr, stop_time=1e-3)
    s.doStep(0.0, 5e-4)
    with pytest.raises(FMICallException):
        s.doStep(5e-4, 1e-3)
    assert any("stop time" in m for m in errors(log))
    s.doStep(5e-4, 5e-4)  # up to the stop time exactly
    s.freeInstance()


# ---- inputs: values and derivatives (platform displacement yC_in; the output yC is what is applied) ----

def test_input_derivative_alone_is_applied(running, vr):
    _, s = running
    s.setRealInputDerivatives([vr["yC_in"]], [1], [2e-3])  # m/s, the value stays 0
    s.doStep(0.0, 1e-3)
    yC_internal = 1e-4 * (np.cos(2 * np.pi * 560 * 1e-3) - 1)
    assert s.getReal([vr["yC"]])[0] == pytest.approx(2e-3 * 1e-3 + yC_internal, rel=1e-12, abs=1e-18)


def test_input_value_resets_its_derivative(running, vr):
    _, s = running
    s.setReal([vr["yC_in"]], [1e-6])
    s.setRealInputDerivatives([vr["yC_in"]], [1], [2e-3])
    s.doStep(0.0, 1e-3)
    s.setReal([vr["yC_in"]], [5e-6])  # a new value alone: held, no slope
    s.doStep(1e-3, 1e-3)
    yC_internal = 1e-4 * (np.cos(2 * np.pi * 560 * 2e-3) - 1)
    assert s.getReal([vr["yC"]])[0] == pytest.approx(5e-6 + yC_internal, rel=1e-12, abs=1e-18)


# ---- calculated parameters in initialization mode ----

def test_output_derivatives_are_not_provided(logged, vr):
    """maxOutputDerivativeOrder = 0: fmi2GetRealOutputDerivatives is refused with one message saying
    so where the call is allowed, and with one saying the state where it is not."""
    log = logged()
    s = log.instantiate()
    d, order = (ctypes.c_double * 1)(-1.0), (ctypes.c_int * 1)(1)
    y = (ctypes.c_uint * 1)(vr["y"])
    assert raw(s, "fmi2GetRealOutputDerivatives", y, 1, order, d) == ERROR  # instantiated: not allowed
    assert errors(log) == ["fmi2GetRealOutputDerivatives: not allowed in state 'instantiated'"]
    start(s, vr)
    assert raw(s, "fmi2GetRealOutputDerivatives", y, 1, order, d) == ERROR
    assert errors(log)[1:] == ["fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder=0)"]
    assert d[0] == -1.0
    s.doStep(0.0, 1e-4)  # a refusal, not a failure
    s.freeInstance()


def test_calculated_parameters_in_initialization_mode(logged, vr):
    """Read between fmi2EnterInitializationMode and fmi2ExitInitializationMode: the closed forms of
    paper eqs. 1, 2, 5 (conftest.effective), not 0."""
    s = logged().instantiate()
    params = dict(P=30000.0, R2=0.9, E2=1.2e11, nu2=0.28, Y=7e8)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.setReal([vr[k] for k in params], list(params.values()))
    e = effective(params)
    names = ["E_star", "R_star", "F_Y", "delta_Y", "k_lin", "f_contact"]
    got = dict(zip(names, s.getReal([vr[n] for n in names])))
    for n in names[:-1]:
        assert got[n] == pytest.approx(e[n], rel=1e-12), n
    # linearised resonance at the static load W on the Hertz curve F = K delta^1.5 (below yield)
    assert e["W"] < e["F_Y"]
    k = 1.5 * e["K"] ** (2 / 3) * e["W"] ** (1 / 3)
    assert got["f_contact"] == pytest.approx(np.sqrt(k / e["m"]) / (2 * np.pi), rel=1e-9)
    s.exitInitializationMode()
    assert s.getReal([vr[n] for n in names]) == [got[n] for n in names]
    s.freeInstance()


def test_every_function_refuses_a_null_instance(running):
    """No importer should pass NULL, but none may crash the FMU by doing so."""
    _, s = running
    d, i, p = ctypes.c_double(), ctypes.c_int(), ctypes.c_void_p()
    vr = (ctypes.c_uint * 1)(0)
    dll = ctypes.CDLL(s.dll._name)  # fresh function objects, without fmpy's argument types
    calls = {
        "fmi2SetDebugLogging": (0, ctypes.c_size_t(0), None),
        "fmi2SetupExperiment": (0, ctypes.c_double(0), ctypes.c_double(0), 0, ctypes.c_double(0)),
        "fmi2EnterInitializationMode": (), "fmi2ExitInitializationMode": (), "fmi2Terminate": (),
        "fmi2Reset": (), "fmi2GetReal": (vr, 1, ctypes.byref(d)), "fmi2SetReal": (vr, 1, ctypes.byref(d)),
        "fmi2GetInteger": (vr, 1, ctypes.byref(i)), "fmi2SetInteger": (vr, 1, ctypes.byref(i)),
        "fmi2GetBoolean": (vr, 1, ctypes.byref(i)), "fmi2SetBoolean": (vr, 1, ctypes.byref(i)),
        "fmi2GetString": (vr, 1, ctypes.byref(p)), "fmi2SetString": (vr, 1, ctypes.byref(p)),
        "fmi2GetFMUstate": (ctypes.byref(p),), "fmi2SetFMUstate": (None,), "fmi2FreeFMUstate": (ctypes.byref(p),),
        "fmi2DoStep": (ctypes.c_double(0), ctypes.c_double(1e-4), 1), "fmi2CancelStep": (),
        "fmi2GetRealStatus": (fmi2LastSuccessfulTime, ctypes.byref(d)),
        "fmi2GetBooleanStatus": (fmi2Terminated, ctypes.byref(i)),
        "fmi2GetStatus": (fmi2DoStepStatus, ctypes.byref(i)),
        "fmi2GetIntegerStatus": (fmi2DoStepStatus, ctypes.byref(i)),
        "fmi2GetStringStatus": (fmi2DoStepStatus, ctypes.byref(p)),
        "fmi2SetRealInputDerivatives": (vr, 1, ctypes.byref(i), ctypes.byref(d)),
        "fmi2GetRealOutputDerivatives": (vr, 1, ctypes.byref(i), ctypes.byref(d)),
        "fmi2GetDirectionalDerivative": (vr, 1, vr, 1, ctypes.byref(d), ctypes.byref(d)),
        "fmi2SerializedFMUstateSize": (None, ctypes.byref(p)), "fmi2SerializeFMUstate": (None, None, 0),
        "fmi2DeSerializeFMUstate": (None, 0, ctypes.byref(p)),
    }
    for name, args in calls.items():
        fn = getattr(dll, name)
        fn.restype = ctypes.c_int
        assert fn(None, *args) == ERROR, name
    s.doStep(0.0, 1e-4)  # the real instance is untouched


def test_null_arrays_are_refused(running, vr):
    """Each array argument NULL with nvr = 1, the others valid: refused with "NULL array", nothing
    read or written, the instance going on; with nvr = 0 NULL arrays are no error."""
    log, s = running
    d, i, p = ctypes.c_double(0.0), ctypes.c_int(1), ctypes.c_char_p(b"")
    one = (ctypes.c_uint * 1)(vr["a"])
    ref = {"Real": ((ctypes.c_uint * 1)(vr["a"]), ctypes.byref(d)),
           "Integer": ((ctypes.c_uint * 1)(vr["n_impacts"]), ctypes.byref(i)),
           "Boolean": ((ctypes.c_uint * 1)(vr["contact"]), ctypes.byref(i)),
           "String": ((ctypes.c_uint * 1)(vr["profile_file"]), ctypes.byref(p))}
    calls = []
    for kind, (r, value) in ref.items():
        calls += [(f"fmi2Get{kind}", (None, 1, value)), (f"fmi2Get{kind}", (r, 1, None))]
    ins = {"Real": ((ctypes.c_uint * 1)(vr["yC_in"]), ctypes.byref(d)),
           "Integer": ((ctypes.c_uint * 1)(vr["solver"]), ctypes.byref(i)),
           "Boolean": ((ctypes.c_uint * 1)(vr["moving_contact"]), ctypes.byref(i)),
           "String": ((ctypes.c_uint * 1)(vr["profile_file"]), ctypes.byref(p))}
    for kind, (r, value) in ins.items():
        calls += [(f"fmi2Set{kind}", (None, 1, value)), (f"fmi2Set{kind}", (r, 1, None))]
    order = (ctypes.c_int * 1)(1)
    calls += [("fmi2SetRealInputDerivatives", args) for args in
              ((None, 1, order, ctypes.byref(d)), (one, 1, None, ctypes.byref(d)), (one, 1, order, None))]
    for fn, args in calls:
        del log.messages[:]
        assert raw(s, fn, *args) == ERROR, (fn, args)
        assert errors(log) == [f"{fn}: NULL array"], fn
    for fn in ("fmi2GetReal", "fmi2SetReal", "fmi2GetInteger", "fmi2SetInteger", "fmi2GetBoolean", "fmi2SetBoolean",
               "fmi2GetString", "fmi2SetString"):
        assert raw(s, fn, None, 0, None) == OK, fn
    assert raw(s, "fmi2SetRealInputDerivatives", None, 0, None, None) == OK
    s.doStep(0.0, 1e-4)
    a, f, yC = s.getReal([vr["a"], vr["f"], vr["yC"]])
    assert (a, f) == (1e-4, 560.0) and yC == pytest.approx(a * (np.cos(2 * np.pi * f * 1e-4) - 1), rel=1e-12)


def test_debug_logging_with_null_categories_is_refused(running):
    log, s = running
    assert raw(s, "fmi2SetDebugLogging", 1, 2, None) == ERROR
    assert any("fmi2SetDebugLogging" in m and "NULL" in m for m in errors(log))


def test_serialize_refuses_a_state_altered_in_memory(running):
    log, s = running
    state = s.getFMUstate()
    addr = state.value + 60
    ctypes.memset(addr, ctypes.c_ubyte.from_address(addr).value ^ 1, 1)
    buf = ctypes.create_string_buffer(1 << 16)
    n = ctypes.c_size_t()
    assert raw(s, "fmi2SerializedFMUstateSize", state, ctypes.byref(n)) == ERROR
    assert raw(s, "fmi2SerializeFMUstate", state, buf, len(buf)) == ERROR
    assert sum("checksum" in m for m in errors(log)) == 2
    assert raw(s, "fmi2DeSerializeFMUstate", None, 100, ctypes.byref(ctypes.c_void_p())) == ERROR
    s.freeFMUstate(state)
