"""The generic layer's Model Exchange part (src/fmi/vi_fmi_model_exchange.c, src/fmi/vi_fmi2.c) on LayerTest, apart from
any physics: x' = -k x + u integrated by the importer, a state event where x crosses x_event (x jumps
by `jump`), a time event at t_event, and a switch that keeps the event iteration from settling.
The state machine (every Model Exchange call refused in the states the standard does not allow it
in, with a message naming the call and the state), non-finite and wrongly sized arguments, time
moving back, FMU states, tunable parameters at events, the directional derivative."""
import ctypes
import math

import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException

from conftest import BUILD
from vibroimpact.me import Me, MeInstance

LAYER = BUILD / "LayerTest.fmu"


@pytest.fixture(scope="module")
def layer_md():
    return read_model_description(str(LAYER))


@pytest.fixture(scope="module")
def layer_dir(tmp_path_factory):
    return extract(str(LAYER), unzipdir=str(tmp_path_factory.mktemp("layer_me")))


@pytest.fixture
def me(layer_md, layer_dir):
    made = []

    def make(kind="me"):
        inst = MeInstance(LAYER, layer_dir, layer_md)
        if kind == "cs":  # the same binary as Co-Simulation
            from conftest import Logged
            log = Logged(layer_md, layer_dir)
            s = log.instantiate()
            made.append(s)
            return log, s
        inst.instantiate(categories=())
        made.append(inst.model)
        return inst, Me(inst)

    yield make
    for f in made:
        f.freeInstance()


def test_fmpy_integrates_the_decay_and_finds_the_state_event(layer_md):
    """x' = -x from 1: x crosses 0.5 at ln 2 and jumps to 0.75 there (x_event 0.5, jump 0.25), then
    decays again: x(1) = 0.75 exp(-(1 - ln 2))."""
    r = simulate_fmu(str(LAYER), fmi_type="ModelExchange", solver="CVode", stop_time=1.0, relative_tolerance=1e-10,
                     start_values=dict(x_event=0.5, jump=0.25), output=["x", "events"], output_interval=0.01)
    assert r["events"][-1] == 1
    assert r["x"][-1] == pytest.approx(0.75 * math.exp(-(1.0 - math.log(2.0))), rel=1e-7)


def test_time_event_is_announced_and_met(layer_md):
    r = simulate_fmu(str(LAYER), fmi_type="ModelExchange", solver="CVode", stop_time=1.0, relative_tolerance=1e-10,
                     start_values=dict(t_event=0.3337), output=["x", "events"], output_interval=0.1, record_events=True)
    t_events = [t for t, n in zip(r["time"], r["events"]) if n == 1]
    assert r["events"][-1] == 1 and t_events[0] == 0.3337  # met exactly: nextEventTime


def test_event_iteration_that_never_settles_is_stopped_with_a_message(me):
    """The same number of passes whether or not the importer calls fmi2EnterEventMode again between
    them (allowed in event mode): that does not start the count afresh."""
    stopped_after = []
    for reenter in (False, True):
        inst, m = me()
        m.fmu.setupExperiment(startTime=0.0)
        m.fmu.enterInitializationMode()
        m.set("chatter", True)
        m.fmu.exitInitializationMode()
        passes = 0
        with pytest.raises(FMICallException):
            for passes in range(1000):  # bounded here too: the FMU must stop first
                if reenter:
                    m.fmu.enterEventMode()
                assert m.fmu.newDiscreteStates()[0]
        assert passes < 1000 and any("do not settle" in e for e in inst.errors()), inst.errors()
        with pytest.raises(FMICallException):  # the error state
            m.fmu.enterContinuousTimeMode()
        stopped_after.append(passes)
    assert stopped_after[0] == stopped_after[1]


@pytest.mark.parametrize("call", ["setTime", "setContinuousStates", "getDerivatives", "enterEventMode",
                                  "newDiscreteStates", "enterContinuousTimeMode", "completedIntegratorStep"])
def test_model_exchange_calls_refused_before_initialization(me, call):
    inst, m = me()
    args = {"setTime": (0.0,), "setContinuousStates": None, "getDerivatives": None}.get(call, ())
    with pytest.raises(FMICallException):
        if call == "setContinuousStates":
            m.set_states([1.0])
        elif call == "getDerivatives":
            m.derivatives()
        else:
            getattr(m.fmu, call)(*args)
    assert any(f"fmi2{call[0].upper()}{call[1:]}: not allowed in state 'instantiated'" in e for e in inst.errors()), \
        inst.errors()


def test_calls_refused_in_event_and_continuous_time_mode(me):
    inst, m = me()
    m.fmu.setupExperiment(startTime=0.0)
    m.fmu.enterInitializationMode()
    m.fmu.exitInitializationMode()  # event mode
    do_step = m.fmu.dll.fmi2DoStep
    do_step.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_int]
    do_step.restype = ctypes.c_int
    assert do_step(m.fmu.component, 0.0, 0.1, 1) == 3
    for call in (lambda: m.set_states([1.0]), m.fmu.completedIntegratorStep):
        with pytest.raises(FMICallException):
            call()
    assert any("fmi2SetContinuousStates: not allowed in state 'event mode'" in e for e in inst.errors())
    assert any("fmi2CompletedIntegratorStep: not allowed in state 'event mode'" in e for e in inst.errors())
    assert any("fmi2DoStep: not allowed in state 'event mode'" in e for e in inst.errors())
    m.settle()
    m.fmu.enterContinuousTimeMode()
    for call in (m.fmu.newDiscreteStates, m.fmu.enterContinuousTimeMode, lambda: m.set("t_event", 1.0),
                 lambda: m.set("chatter", True)):
        with pytest.raises(FMICallException):
            call()
    text = "\n".join(inst.errors())
    assert "fmi2NewDiscreteStates: not allowed in state 'continuous-time mode'" in text
    assert "fmi2EnterContinuousTimeMode: not allowed in state 'continuous-time mode'" in text
    assert "fmi2SetBoolean: not allowed in state 'continuous-time mode'" in text
    assert "t_event cannot be set in continuous-time mode" in text
    m.set("u", 2.0)  # a continuous input can be set: it acts at once
    assert m.derivatives() == [pytest.approx(-1.0 + 2.0)]
    m.fmu.terminate()
    for call in (lambda: m.fmu.setTime(1.0), m.fmu.enterEventMode, lambda: m.set_states([1.0])):
        with pytest.raises(FMICallException):
            call()
    assert "fmi2SetTime: not allowed in state 'terminated'" in "\n".join(inst.errors())


def test_model_exchange_calls_refused_on_a_co_simulation_instance(me):
    log, s = me("cs")
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    set_time, enter_event = s.dll.fmi2SetTime, s.dll.fmi2EnterEventMode
    set_time.argtypes, set_time.restype = [ctypes.c_void_p, ctypes.c_double], ctypes.c_int
    enter_event.argtypes, enter_event.restype = [ctypes.c_void_p], ctypes.c_int
    assert set_time(s.component, 0.5) == 3 and enter_event(s.component) == 3
    assert "fmi2SetTime: not allowed in state 'step complete'" in log.text()
    with pytest.raises(FMICallException):
        s.getDirectionalDerivative([0], [0], [1.0])
    assert "not provided (providesDirectionalDerivative=false in Co-Simulation)" in log.text()


def test_non_finite_time_and_states_are_refused_and_change_nothing(me):
    inst, m = me()
    m.start()
    m.fmu.setTime(0.1)
    m.set_states([0.5])
    for bad in (float("nan"), float("inf"), -float("inf")):
        with pytest.raises(FMICallException):
            m.fmu.setTime(bad)
        with pytest.raises(FMICallException):
            m.set_states([bad])
    assert m.states() == [0.5] and m.derivatives() == [pytest.approx(-0.5)]
    text = "\n".join(inst.errors())
    assert "fmi2SetTime: time nan is not finite" in text and "state 0 (x) = inf is not finite" in text
    with pytest.raises(FMICallException):
        m.set_states([0.5, 0.5], n=2)  # one state, not two
    assert "2 states given; LayerTest has 1" in "\n".join(inst.errors())
    m.fmu.setTime(0.2)  # still usable
    m.fmu.completedIntegratorStep()


def test_null_arguments_are_refused_and_change_nothing(me, layer_md):
    """Each pointer argument of the Model Exchange calls NULL, alone: refused naming it, nothing
    written; with arrays of length 0 where the model has states, the length is refused."""
    inst, m = me()
    m.start()
    m.fmu.setTime(0.1)
    m.set_states([0.5])
    dll = ctypes.CDLL(m.fmu.dll._name)
    b = ctypes.c_int(7)
    nx, nz = layer_md.numberOfContinuousStates, layer_md.numberOfEventIndicators
    calls = [("fmi2CompletedIntegratorStep", (1, None, ctypes.byref(b)), "NULL argument"),
             ("fmi2CompletedIntegratorStep", (1, ctypes.byref(b), None), "NULL argument")]
    for fn, n in (("fmi2GetDerivatives", nx), ("fmi2GetContinuousStates", nx), ("fmi2SetContinuousStates", nx),
                  ("fmi2GetNominalsOfContinuousStates", nx), ("fmi2GetEventIndicators", nz)):
        calls += [(fn, (None, ctypes.c_size_t(n)), "the array is NULL"),
                  (fn, ((ctypes.c_double * 4)(), ctypes.c_size_t(0)), "0 ")]
    for fn, args, words in calls:
        f = getattr(dll, fn)
        f.restype = ctypes.c_int
        del inst.messages[:]
        assert f(ctypes.c_void_p(m.fmu.component), *args) == 3, (fn, args)
        assert inst.errors() and inst.errors()[0].startswith(f"{fn}: {words}"), (fn, inst.errors())
    assert b.value == 7
    assert m.states() == [0.5]
    m.fmu.enterEventMode()
    f = dll.fmi2NewDiscreteStates
    f.restype = ctypes.c_int
    del inst.messages[:]
    assert f(ctypes.c_void_p(m.fmu.component), None) == 3
    assert inst.errors() == ["fmi2NewDiscreteStates: fmi2EventInfo is NULL"]
    m.settle()
    m.fmu.enterContinuousTimeMode()
    assert m.fmu.completedIntegratorStep() == (False, False)


def test_time_goes_back_within_a_step_never_before_it(me):
    """An integrator evaluates at earlier times within its current step (root location), never before
    its last completed step or event."""
    inst, m = me()
    m.start()
    m.fmu.setTime(0.2)
    m.fmu.completedIntegratorStep()
    m.fmu.setTime(0.3)
    m.fmu.setTime(0.25)  # back, within the step since 0.2
    m.fmu.setTime(0.2)
    with pytest.raises(FMICallException):
        m.fmu.setTime(0.19)
    assert any("t = 0.19000000000000000 s lies before the last event or completed integrator step" in e or
               "lies before the last event or completed integrator step (0.20000000000000001 s)" in e
               for e in inst.errors()), inst.errors()
    m.fmu.setTime(0.25)
    m.fmu.enterEventMode()
    with pytest.raises(FMICallException):
        m.fmu.setTime(0.3)  # time does not move in event mode
    m.fmu.setTime(0.25)


def test_time_never_goes_back_before_the_start(me):
    """Right after fmi2ExitInitializationMode (start time 1 s), before any event iteration, a time
    before the start is refused as time going back, naming the start."""
    inst, m = me()
    m.fmu.setupExperiment(startTime=1.0)
    m.fmu.enterInitializationMode()
    m.fmu.exitInitializationMode()
    with pytest.raises(FMICallException):
        m.fmu.setTime(0.5)
    assert inst.errors() == ["fmi2SetTime: t = 0.5 s lies before the last event or completed integrator step (1 s); "
                             "time goes back only within the current step (restore an FMU state to go further)"]
    m.settle()
    m.fmu.enterContinuousTimeMode()
    m.fmu.setTime(1.5)


def test_fmu_state_in_event_and_continuous_time_mode(me):
    inst, m = me()
    m.start()
    m.fmu.setTime(0.1)
    m.set_states([0.9])
    s = m.fmu.getFMUstate()
    ser = m.fmu.serializeFMUstate(s)
    m.fmu.setTime(0.2)
    m.set_states([0.3])
    m.fmu.enterEventMode()
    m.fmu.setFMUstate(m.fmu.deSerializeFMUstate(ser))
    assert m.states() == [0.9] and m.derivatives() == [pytest.approx(-0.9)]
    m.set_states([0.8])  # continuous-time mode again, as it was taken
    bad = bytearray(ser)
    bad[-8] ^= 1
    with pytest.raises(FMICallException):
        m.fmu.deSerializeFMUstate(bytes(bad))
    assert any("checksum" in e for e in inst.errors())


def test_tunable_parameter_acts_at_the_next_event(me):
    inst, m = me()
    m.start()
    m.fmu.setTime(0.1)
    m.set_states([1.0])
    m.fmu.completedIntegratorStep()
    m.fmu.enterEventMode()
    m.set("k", 3.0)
    assert m.derivatives() == [pytest.approx(-1.0)]  # not before the event iteration
    m.settle()
    assert m.derivatives() == [pytest.approx(-3.0)]


def test_directional_derivative(me):
    inst, m = me()
    m.start(params=dict(k=2.0))
    vr = m.vr
    assert m.fmu.getDirectionalDerivative([vr["der_x"], vr["x"]], [vr["x"]], [1.0]) == [-2.0, 1.0]
    assert m.fmu.getDirectionalDerivative([vr["der_x"]], [vr["u"]], [3.0]) == [3.0]
    with pytest.raises(FMICallException):
        m.fmu.getDirectionalDerivative([vr["der_x"]], [vr["k"]], [1.0])  # a parameter is no known
    assert any("known k is neither a state nor an input" in e for e in inst.errors())


def test_euler_importer_meets_the_state_event_late_and_the_fmu_takes_the_state_as_it_is(me):
    """A fixed-step importer detects the crossing at the end of the step that made it: the event
    iteration applies the jump to the state it is given."""
    inst, m = me()
    m.start(params=dict(x_event=0.5, jump=0.25))
    t, crossed = m.euler_to(1.0, 0.01)
    assert crossed and 0.68 < t < 0.72
    x_before = m.states()[0]
    m.fmu.enterEventMode()
    info = m.settle()
    assert info[3] and m.states()[0] == pytest.approx(x_before + 0.25) and m.integer("events") == 1
