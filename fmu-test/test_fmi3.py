"""The FMI 3.0 FMU (build/fmi3/VibroImpact.fmu, doc/fmi3.md): the same model as the FMI 2.0 FMU, and
what only FMI 3.0 offers.

- Without early return it is the FMI 2.0 FMU: the same outputs, bit for bit, on the same steps, for
  every solver; and it follows the independent reference (vibroimpact.reference) within each
  scenario's horizon as tightly as test_paper.py asks of the FMI 2.0 FMU.
- With earlyReturnAllowed, fmi3DoStep returns at every change of mode (contact, separation, yield,
  turning point, stick entry and exit) with lastSuccessfulTime at the event: the stops are the mode
  changes the reference lists (same sequence, times within EVENT_DT = 1 us, within the horizon),
  and exactly the mode changes the FMU itself logs; with Event Mode too, eventHandlingNeeded marks
  the same stops and the importer passes through fmi3EnterEventMode, fmi3UpdateDiscreteStates and
  fmi3EnterStepMode with the same result.
- The tolerance given to fmi3EnterInitializationMode acts as FMI 2.0's fmi2SetupExperiment's; the
  input derivatives der(yC_in), der(F_ext) act as fmi2SetRealInputDerivatives.
- Enumerations by item name, the independent variable time, the data types, the calls of Event Mode
  in the states where they are refused; the layer's test model and the vehicle-track companions
  built for FMI 3.0 behave as their FMI 2.0 builds; fmi-sim (a second importer) runs the FMU.
- Model Exchange: fmpy integrates the FMI 3.0 interface to the FMI 2.0 one's numbers, bit for bit;
  event indicators are also variables; the directional derivative is FMI 2.0's.
"""
import csv
import ctypes
import json
import math
import os
import pathlib
import shutil
import subprocess

import fmpy
import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException

from conftest import BUILD, FMU, with_solver
from solvers import each_solver
from vibroimpact import fmi3
from vibroimpact.compare import EVENT_DT, INTEGERS, REALS, SCENARIOS, Runner, compare, fmu_events, read_events
from vibroimpact.reference.generate import DATA, EPS_Y
from vibroimpact.reference.scenarios import STOP_TIME

OK, DISCARD, ERROR = fmi3.OK, fmi3.DISCARD, fmi3.ERROR
RTOL = 1e-11  # the reference's tolerance (vibroimpact.compare.RTOL_FMU)
SUMMARY = json.loads((DATA / "summary.json").read_text())
FMU3 = BUILD / "fmi3" / "VibroImpact.fmu"


@pytest.fixture(scope="module")
def md3():
    if not FMU3.exists():
        pytest.fail(f"{FMU3} is missing: build with cmake --build build")
    return read_model_description(str(FMU3))


@pytest.fixture(scope="module")
def dir3(md3, tmp_path_factory):
    return extract(str(FMU3), unzipdir=str(tmp_path_factory.mktemp("fmi3")))


@pytest.fixture(scope="module")
def vr3(md3):
    return {v.name: v.valueReference for v in md3.modelVariables}


@pytest.fixture(scope="module")
def kinds3(md3):
    return {v.name: v.type for v in md3.modelVariables}


@pytest.fixture
def logged3(md3, dir3):
    made = []

    def make(**kw):
        made.append(fmi3.Logged(md3, dir3, **kw))
        return made[-1]

    yield make


def raw(s, fn, *args):
    """Call an FMI 3.0 function and return its status instead of raising."""
    try:
        return getattr(s, fn)(s.component, *args)
    except FMICallException as e:
        return e.status


def errors(log):
    return [m for st, _, m in log.messages if st == ERROR]


class Runner3:
    """Runner (vibroimpact.compare) for the FMI 3.0 FMU: the scenarios on the reference's sample grid,
    one fmi3DoStep per sample, the mode changes from logEvents."""

    def __init__(self, md, unzipdir, vr, kinds):
        self.md, self.unzipdir, self.vr, self.kinds = md, unzipdir, vr, kinds

    def run(self, name, t, rtol=RTOL, solver=None):
        log = fmi3.Logged(self.md, self.unzipdir, name=name)
        s, vr = log.instantiate(logging=True), self.vr
        s.setDebugLogging(True, ["logEvents"])
        params = {**SCENARIOS[name].full, **({} if solver is None else {"solver": solver})}
        fmi3.initialize(s, vr, params, kinds=self.kinds, tolerance=rtol, start_time=float(t[0]), stop_time=float(t[-1]))
        reals = [vr[n] for n in REALS]
        out = np.empty((len(t), len(REALS) + len(INTEGERS)))
        for k in range(len(t)):
            if k:
                s.doStep(t[k - 1], t[k] - t[k - 1])
            out[k] = s.getFloat64(reals) + s.getInt64([vr["mode"]]) + s.getInt32([vr["n_impacts"]])
        s.terminate()
        s.freeInstance()
        return dict(zip(REALS + INTEGERS, out.T)), fmu_events(log.messages)


# ---- the same model as the FMI 2.0 FMU ------------------------------------------------------------------

SAME_AS_FMI2 = ["fig4b", "fig4c", "fig5c", "fig6b", "stick", "printed"]


@each_solver
@pytest.mark.parametrize("name", SAME_AS_FMI2)
def test_without_early_return_it_is_the_fmi2_fmu_bit_for_bit(name, solver, md3, dir3, vr3, kinds3, unzipdir):
    from vibroimpact.compare import read_trace
    t = read_trace(name)["time"][:1500]  # 30 ms on the reference grid
    out2, ev2 = Runner(FMU, unzipdir).run(name, t, RTOL, solver)
    out3, ev3 = Runner3(md3, dir3, vr3, kinds3).run(name, t, RTOL, solver)
    for k in REALS + INTEGERS:
        assert np.array_equal(out3[k], out2[k]), k
    assert ev3 == ev2 and len(ev3) > 5


@pytest.mark.parametrize("name", SCENARIOS)
def test_follows_the_reference_within_the_horizon(name, md3, dir3, vr3, kinds3):
    """As test_paper.py asks of the FMI 2.0 FMU (default solver)."""
    c = compare(name, Runner3(md3, dir3, vr3, kinds3))
    assert c["dy"] <= EPS_Y
    assert c["dF_rel"] <= 1e-3 and c["dW_rel"] <= 1e-4
    assert c["events_fmu"] == c["events_ref"] and c["event_dt"] <= EVENT_DT


# ---- early return ----------------------------------------------------------------------------------------

def early_return_run(logged3, vr3, kinds3, name, event_mode, step, solver=None, rtol=RTOL):
    """The scenario stepped on a grid of `step` with early return (and Event Mode): ([(t, mode before,
    mode after)] of the stops, the mode changes the FMU logged, its final y)."""
    log = logged3()
    s = log.instantiate(event_mode=event_mode, early_return=True, logging=True)
    s.setDebugLogging(True, ["logEvents"])
    params = {**SCENARIOS[name].full, **({} if solver is None else {"solver": solver})}
    fmi3.initialize(s, vr3, params, kinds=kinds3, tolerance=rtol, stop_time=STOP_TIME, event_mode=event_mode)
    mode0 = s.getInt64([vr3["mode"]])[0]
    events, samples = fmi3.run_to_events(s, 0.0, STOP_TIME, step, sample=lambda t: (t, s.getInt64([vr3["mode"]])[0]))
    stops, before, at = [], mode0, set(events)
    for t, mode in samples:
        if t in at:
            stops.append((t, before, mode))
        before = mode
    y = s.getFloat64([vr3["y"]])[0]
    s.terminate()
    s.freeInstance()
    return stops, fmu_events(log.messages), y


@pytest.mark.parametrize("event_mode", [False, True], ids=["early_return", "early_return+event_mode"])
@pytest.mark.parametrize("name", SCENARIOS)
def test_stops_at_the_reference_mode_changes(name, event_mode, logged3, vr3, kinds3):
    stops, logged, _ = early_return_run(logged3, vr3, kinds3, name, event_mode, step=1e-3)
    # every stop is a mode change the FMU logged, at the very time it logged it, and every logged
    # change is a stop
    assert stops == logged
    assert all(before != after for _, before, after in stops)
    h = SUMMARY[name]["horizon"]
    ref = [e for e in read_events(name) if e[0] <= h - EVENT_DT]
    got = [e for e in stops if e[0] <= h - EVENT_DT]
    assert [e[1:] for e in got] == [e[1:] for e in ref]
    assert max((abs(a[0] - b[0]) for a, b in zip(got, ref)), default=0.0) <= EVENT_DT
    if name != "fig5a":  # Hertz at 100 Hz never loses the contact
        assert len(got) >= 10


@each_solver
def test_stops_do_not_change_the_run(solver, logged3, vr3, kinds3):
    """Returning at every event leaves the trajectory as without (to the solver's tolerance), for
    every solver; Event Mode changes nothing more (bit for bit); one long step returns once per
    event, where many short ones do."""
    name = "fig4b"
    params = {**SCENARIOS[name].full, "solver": solver}
    stops, _, y = early_return_run(logged3, vr3, kinds3, name, False, step=1e-3, solver=solver)
    stops_ev, _, y_ev = early_return_run(logged3, vr3, kinds3, name, True, step=1e-3, solver=solver)
    assert stops_ev == stops and y_ev == y
    long_stops, _, _ = early_return_run(logged3, vr3, kinds3, name, False, step=STOP_TIME, solver=solver)
    h = SUMMARY[name]["horizon"]
    within = [e for e in stops if e[0] <= h - EVENT_DT]
    assert [e[1:] for e in long_stops[:len(within)]] == [e[1:] for e in within]
    assert max(abs(a[0] - b[0]) for a, b in zip(long_stops, within)) <= 0.1 * EVENT_DT
    t_end = math.floor(h * 1e3) / 1e3  # a grid point within the horizon
    s = logged3().instantiate()
    fmi3.initialize(s, vr3, params, kinds=kinds3, tolerance=RTOL)
    for k in range(round(t_end * 1e3)):
        s.doStep(1e-3 * k, 1e-3 * (k + 1) - 1e-3 * k)
    y_plain = s.getFloat64([vr3["y"]])[0]
    s.freeInstance()
    s = logged3().instantiate(early_return=True)
    fmi3.initialize(s, vr3, params, kinds=kinds3, tolerance=RTOL)
    fmi3.run_to_events(s, 0.0, t_end, 1e-3)
    assert abs(s.getFloat64([vr3["y"]])[0] - y_plain) <= 1e-3 * EPS_Y
    s.freeInstance()


def test_do_step_results_and_event_mode_protocol(logged3, vr3, kinds3):
    log = logged3()
    s = log.instantiate(event_mode=True, early_return=True)
    s.enterInitializationMode(tolerance=1e-8)
    s.setFloat64([vr3["a"]], [1e-4])
    s.exitInitializationMode()
    # Event Mode after initialization: no step until fmi3EnterStepMode
    assert fmi3.do_step(s, 0.0, 1e-3)[0] == ERROR
    assert any("fmi3DoStep" in m and "event mode" in m for m in errors(log))
    assert s.updateDiscreteStates() == (False, False, False, False, False, 0.0)
    s.enterStepMode()
    assert raw(s, "fmi3EnterStepMode") == ERROR and raw(s, "fmi3UpdateDiscreteStates", *[None] * 6) == ERROR
    status, handling, terminate, early, last = fmi3.do_step(s, 0.0, 1e-3)
    assert (status, handling, terminate, early) == (OK, True, False, True)
    assert 3.19e-4 < last < 3.21e-4  # the first separation (reference: 3.1995e-4 s)
    # in Event Mode the outputs are those just after the event: out of contact, no force
    s.enterEventMode()
    assert s.getInt64([vr3["mode"]]) == [0] and s.getBoolean([vr3["contact"]]) == [False]
    assert s.getFloat64([vr3["F"], vr3["time"]]) == [0.0, last]
    # tunables may be set there, fixed parameters not
    s.setFloat64([vr3["f"]], [600.0])
    assert raw(s, "fmi3SetFloat64", (ctypes.c_uint * 1)(vr3["m"]), 1, (ctypes.c_double * 1)(1.0), 1) == ERROR
    assert any("m is a fixed parameter" in m for m in errors(log))
    assert raw(s, "fmi3EnterEventMode") == ERROR
    fmi3.update_discrete_states(s)
    s.enterStepMode()
    # a step that meets no event goes to its end: no early return, no event handling
    status, handling, _, early, last2 = fmi3.do_step(s, last, 1e-5)
    assert (status, handling, early, last2) == (OK, False, False, last + 1e-5)
    s.terminate()
    s.freeInstance()


def test_event_mode_is_refused_when_not_asked_for_and_steps_go_to_their_end(logged3, vr3, kinds3):
    log = logged3()
    s = log.instantiate(event_mode=True, early_return=False)
    fmi3.initialize(s, vr3, dict(a=1e-4), event_mode=True)
    status, handling, _, early, last = fmi3.do_step(s, 0.0, 1e-3)  # contains the separation at 0.32 ms
    assert (status, handling, early, last) == (OK, False, False, 1e-3)
    s.freeInstance()
    log = logged3()
    s = log.instantiate(early_return=True)
    fmi3.initialize(s, vr3, dict(a=1e-4))
    assert raw(s, "fmi3EnterEventMode") == ERROR
    assert any("eventModeUsed = false" in m for m in errors(log))
    status, handling, _, early, last = fmi3.do_step(s, 0.0, 1e-3)
    assert (status, handling, early) == (OK, False, True) and last < 1e-3
    s.freeInstance()


def test_a_state_taken_in_event_mode_restores_event_mode(logged3, vr3, kinds3):
    log = logged3()
    s = log.instantiate(event_mode=True, early_return=True)
    fmi3.initialize(s, vr3, dict(a=1e-4), event_mode=True)
    last = fmi3.do_step(s, 0.0, 1e-3)[4]
    s.enterEventMode()
    state = s.getFMUState()
    s.enterStepMode()
    t2 = fmi3.do_step(s, last, 1e-3)[4]
    y2 = s.getFloat64([vr3["y"]])
    s.setFMUState(state)
    assert fmi3.do_step(s, last, 1e-3)[0] == ERROR  # back in Event Mode
    s.enterStepMode()
    assert fmi3.do_step(s, last, 1e-3)[4] == t2 and s.getFloat64([vr3["y"]]) == y2
    s.freeFMUState(state)
    s.freeInstance()


# ---- the tolerance of fmi3EnterInitializationMode --------------------------------------------------------

def test_tolerance_acts_as_fmi2_setup_experiment(logged3, vr3, kinds3, logged, vr):
    from conftest import start

    def run3(tolerance):
        s = logged3().instantiate()
        fmi3.initialize(s, vr3, with_solver(dict(a=1e-4, contact_model=1)), kinds=kinds3, tolerance=tolerance)
        for k in range(1, 101):
            s.doStep(1e-4 * (k - 1), 1e-4)
        y = s.getFloat64([vr3["y"], vr3["v"]])
        s.freeInstance()
        return y

    def run2(tolerance):
        s = logged().instantiate()
        start(s, vr, dict(a=1e-4, contact_model=1), tolerance=tolerance)
        for k in range(1, 101):
            s.doStep(1e-4 * (k - 1), 1e-4)
        y = s.getReal([vr["y"], vr["v"]])
        s.freeInstance()
        return y

    for tol in (1e-4, 1e-9):
        assert run3(tol) == run2(tol)
    assert run3(1e-4) != run3(1e-9) and run3(None) == run2(None)
    log = logged3()
    s = log.instantiate()
    s.enterInitializationMode(tolerance=0.5)
    assert raw(s, "fmi3ExitInitializationMode") == ERROR
    assert any("fmi3EnterInitializationMode" in m and "0.5" in m for m in errors(log))
    s.freeInstance()
    log = logged3()
    s = log.instantiate()
    assert raw(s, "fmi3EnterInitializationMode", True, 2.0, 0.0, False, 0.0) == ERROR
    assert raw(s, "fmi3EnterInitializationMode", False, 0.0, 0.0, True, -1.0) == ERROR
    assert any("tolerance in (0, 1)" in m for m in errors(log))
    s.enterInitializationMode()  # nothing changed: the instance is still instantiated
    s.freeInstance()


# ---- values ----------------------------------------------------------------------------------------------

def test_enumerations_by_item_name(md3, logged3, vr3, kinds3):
    """The options are Enumerations: fmpy sets them by value from the item names of the description,
    and a run with contact_model = hertz is the FMI 2.0 run with contact_model = 1."""
    hertz = fmi3.enumeration_value(md3, "contact_model", "hertz")
    dop853 = fmi3.enumeration_value(md3, "solver", "dop853")
    assert (hertz, dop853) == (1, 3)
    items = {i.name: int(i.value) for i in next(v for v in md3.modelVariables if v.name == "mode").declaredType.items}
    assert items == dict(free=0, elastic=1, plastic=2, unload=3, stick=4)
    kw = dict(stop_time=0.01, output_interval=1e-4, output=["y", "mode", "n_impacts"])
    r3 = fmpy.simulate_fmu(str(FMU3), start_values=dict(contact_model=hertz, a=1e-4, solver=dop853), **kw)
    r2 = fmpy.simulate_fmu(str(FMU), start_values=dict(contact_model=1, a=1e-4, solver=3), **kw)
    for k in ("time", "y", "mode", "n_impacts"):
        assert np.array_equal(r3[k], r2[k]), k
    assert set(r3["mode"]) == {items["free"], items["elastic"]}


def test_input_derivatives_are_variables_and_act_as_in_fmi2(logged3, vr3, kinds3, logged, vr):
    """der(yC_in) set after yC_in moves the platform input on that slope over the step, as
    fmi2SetRealInputDerivatives does (bit for bit); setting yC_in again resets it to 0."""
    from conftest import start

    def slope(t):
        return 0.02 * math.cos(2 * math.pi * 300 * t)

    s2 = logged().instantiate()
    start(s2, vr, dict(contact_model=1))
    s3 = logged3().instantiate()
    fmi3.initialize(s3, vr3, with_solver(dict(contact_model=1)), kinds=kinds3)
    y_in, h = 0.0, 1e-4
    for k in range(200):
        t = k * h
        s2.setReal([vr["yC_in"]], [y_in])
        s2.setRealInputDerivatives([vr["yC_in"]], [1], [slope(t)])
        s3.setFloat64([vr3["yC_in"], vr3["der(yC_in)"]], [y_in, slope(t)])
        assert s3.getFloat64([vr3["der(yC_in)"]]) == [slope(t)]
        s2.doStep(t, h)
        s3.doStep(t, h)
        y_in += slope(t) * h
        assert s3.getFloat64([vr3["y"], vr3["yC"], vr3["F"]]) == s2.getReal([vr["y"], vr["yC"], vr["F"]])
    assert abs(s3.getFloat64([vr3["yC"]])[0] - y_in) < 1e-15  # the platform followed the ramps
    s3.setFloat64([vr3["der(yC_in)"]], [1.0])
    s3.setFloat64([vr3["yC_in"]], [y_in])  # a value after its derivative resets it
    assert s3.getFloat64([vr3["der(yC_in)"]]) == [0.0]
    nan = (ctypes.c_double * 1)(math.nan)
    assert raw(s3, "fmi3SetFloat64", (ctypes.c_uint * 1)(vr3["der(F_ext)"]), 1, nan, 1) == ERROR
    s2.freeInstance()
    s3.freeInstance()


def test_types_time_and_bad_values(logged3, vr3):
    log = logged3()
    s = log.instantiate()
    one = lambda *v: (ctypes.c_uint * len(v))(*v)  # noqa: E731
    s.enterInitializationMode(startTime=0.25)
    assert s.getFloat64([vr3["time"]]) == [0.25]
    # each value through its type: Int32 n_impacts, Int64 the enumerations, Boolean, String
    assert s.getInt32([vr3["n_impacts"]]) == [0] and s.getInt64([vr3["contact_model"]]) == [2]
    s.setBoolean([vr3["moving_contact"]], [True])
    assert s.getBoolean([vr3["moving_contact"]]) == [True]
    s.setString([vr3["profile_file"]], [""])
    cases = {  # call -> (arguments, words of the message)
        "fmi3GetInt32": ((one(vr3["contact_model"]), 1, (ctypes.c_int32 * 1)(), 1), "Enumeration (Int64)"),
        "fmi3GetInt64": ((one(vr3["m"]), 1, (ctypes.c_int64 * 1)(), 1), "is of type Float64"),
        "fmi3SetInt64": ((one(vr3["solver"]), 1, (ctypes.c_int64 * 1)(2 ** 40), 1), "is not one of its items"),
        "fmi3SetFloat64": ((one(vr3["time"]), 1, (ctypes.c_double * 1)(1.0), 1), "independent variable"),
        "fmi3GetFloat64": ((one(vr3["m"], vr3["P"]), 2, (ctypes.c_double * 2)(), 1), "nValues = 1"),
        "fmi3GetFloat32": ((one(vr3["m"]), 1, (ctypes.c_float * 1)(), 1), "not a Float32 variable"),
        "fmi3GetUInt8": ((one(0), 1, (ctypes.c_uint8 * 1)(), 1), "not a UInt8 variable"),
        "fmi3GetClock": ((one(0), 1, (ctypes.c_bool * 1)()), "not a Clock variable"),
    }
    for fn, (args, words) in cases.items():
        n = len(errors(log))
        assert raw(s, fn, *args) == ERROR, fn
        assert len(errors(log)) == n + 1 and words in errors(log)[-1], (fn, errors(log)[-1])
    nan = (ctypes.c_double * 1)(math.nan)
    assert raw(s, "fmi3SetFloat64", one(vr3["a"]), 1, nan, 1) == ERROR
    assert raw(s, "fmi3SetString", one(vr3["profile_file"]), 1, (ctypes.c_char_p * 1)(b"x" * 5000), 1) == ERROR
    assert s.getFloat64([vr3["a"]]) == [0.0]
    # not an item, outside the range: refused at once, as in FMI 2.0, naming what is allowed
    assert raw(s, "fmi3SetInt64", one(vr3["contact_model"]), 1, (ctypes.c_int64 * 1)(9), 1) == ERROR
    assert "hertz=1, johnson=2, lepp=3" in errors(log)[-1]
    assert raw(s, "fmi3SetFloat64", one(vr3["nu1"]), 1, (ctypes.c_double * 1)(0.7), 1) == ERROR
    assert "nu1" in errors(log)[-1] and "range" in errors(log)[-1]
    s.exitInitializationMode()
    s.freeInstance()


def test_value_references_not_in_the_description_are_refused(md3, logged3, vr3):
    """Around every block of value references the description uses (the table, time, der(u) and
    the event indicators), each one it does not list is refused by fmi3GetFloat64 and fmi3SetFloat64
    as unknown, and each Float64 it lists is read (the indicators in Model Exchange only)."""
    log = logged3()
    s = log.instantiate()
    fmi3.initialize(s, vr3, {})
    listed = {v.valueReference: v for v in md3.modelVariables}
    der, ind = vr3["der(yC_in)"], md3.eventIndicators and md3.eventIndicators[0].variable.valueReference
    candidates = set(range(0, max(r for r in listed if r < der) + 3)) | {vr3["time"] - 1, vr3["time"]}
    candidates |= set(range(der - 1, der + len(listed) + 2))
    candidates |= set(range(ind - 1, ind + 4)) if ind else set()
    d = (ctypes.c_double * 1)(0.0)
    for r in sorted(candidates):
        one = (ctypes.c_uint * 1)(r)
        if r in listed:
            if listed[r].type == "Float64" and not listed[r].name.startswith("event_indicator_"):  # ME only
                assert raw(s, "fmi3GetFloat64", one, 1, d, 1) == OK, listed[r].name
            continue
        del log.messages[:]
        assert raw(s, "fmi3GetFloat64", one, 1, d, 1) == ERROR, r
        assert raw(s, "fmi3SetFloat64", one, 1, d, 1) == ERROR, r
        assert errors(log) == [f"fmi3GetFloat64: unknown value reference {r}",
                               f"fmi3SetFloat64: unknown value reference {r}"], r
    s.freeInstance()


def test_other_functions_are_refused(logged3, vr3):
    log = logged3()
    s = log.instantiate()
    with pytest.raises(Exception):
        logged3(token="{00000000-0000-0000-0000-000000000000}").instantiate()
    fmi3.initialize(s, vr3, {})
    d = (ctypes.c_double * 1)()
    for fn, args in {"fmi3GetDirectionalDerivative": (None, 0, None, 0, None, 0, d, 0),
                     "fmi3GetAdjointDerivative": (None, 0, None, 0, None, 0, d, 0),
                     "fmi3GetOutputDerivatives": (None, 0, None, d, 0), "fmi3EnterConfigurationMode": (),
                     "fmi3EvaluateDiscreteStates": (), "fmi3SetTime": (0.0,),
                     "fmi3GetNumberOfContinuousStates": (ctypes.byref(ctypes.c_size_t()),),
                     "fmi3GetEventIndicators": (d, 2)}.items():
        assert raw(s, fn, *args) == ERROR, fn
    assert all("not provided" in m or "Model Exchange" in m or "not allowed in state" in m for m in errors(log)), errors(log)
    s.freeInstance()


# ---- Model Exchange ------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["fig4b", "fig5c", "fig6b", "stick"])
def test_model_exchange_is_the_fmi2_one(name):
    """fmpy integrates the FMI 3.0 and the FMI 2.0 Model Exchange interfaces (its CVode, its event
    handling) to the same numbers, bit for bit, events included."""
    kw = dict(fmi_type="ModelExchange", stop_time=0.02, output_interval=1e-4, relative_tolerance=1e-8,
              output=["y", "v", "F", "mode", "n_impacts"])
    r2 = fmpy.simulate_fmu(str(FMU), start_values=dict(SCENARIOS[name].full), **kw)
    r3 = fmpy.simulate_fmu(str(FMU3), start_values=dict(SCENARIOS[name].full), **kw)
    for k in ("time", "y", "v", "F", "mode", "n_impacts"):
        assert np.array_equal(r3[k], r2[k]), k
    assert len(set(r3["mode"])) >= 2


def test_model_exchange_calls(md3, dir3, vr3):
    """The FMI 3.0 Model Exchange functions on the core's: counts as the model description's, event
    indicators also as variables, the directional derivative as FMI 2.0's, the interfaces apart."""
    from fmpy.fmi2 import FMU2Model
    from fmpy.fmi3 import FMU3Model
    msgs = []
    m3 = FMU3Model(guid=md3.guid, unzipDirectory=dir3, modelIdentifier="VibroImpact", instanceName="me3")
    m3.instantiate(logMessage=lambda env, st, cat, m: msgs.append((st, m.decode())))
    m3.enterInitializationMode(tolerance=1e-8)
    m3.setFloat64([vr3["a"]], [1e-4])
    m3.exitInitializationMode()
    fmi3.update_discrete_states(m3)
    m3.enterContinuousTimeMode()
    assert m3.getNumberOfContinuousStates() == len(md3.derivatives) == 3
    assert m3.getNumberOfEventIndicators() == len(md3.eventIndicators) == 4  # two per contact
    m3.setTime(1e-4)
    z = (ctypes.c_double * 4)()
    m3.getEventIndicators(z, 4)
    assert m3.getFloat64([u.variable.valueReference for u in md3.eventIndicators]) == list(z)
    assert raw(m3, "fmi3SetFloat64", (ctypes.c_uint * 1)(md3.eventIndicators[0].variable.valueReference), 1,
               (ctypes.c_double * 1)(1.0), 1) == ERROR
    assert raw(m3, "fmi3DoStep", 0.0, 1e-4, True, *[ctypes.byref(ctypes.c_bool()) for _ in range(3)],
               ctypes.byref(ctypes.c_double())) == ERROR
    states = [vr3["y"], vr3["v"]]
    seeds = [1.0, 0.0]
    der = [u.variable.valueReference for u in md3.derivatives]
    J3 = m3.getDirectionalDerivative(der, states, seeds)
    md2 = read_model_description(str(FMU))
    m2 = FMU2Model(guid=md2.guid, unzipDirectory=extract(str(FMU)), modelIdentifier="VibroImpact", instanceName="me2")
    m2.instantiate()
    m2.setupExperiment(tolerance=1e-8)
    m2.enterInitializationMode()
    m2.setReal([vr3["a"]], [1e-4])
    m2.exitInitializationMode()
    while m2.newDiscreteStates()[0]:
        pass
    m2.enterContinuousTimeMode()
    m2.setTime(1e-4)
    assert m2.getDirectionalDerivative(der, states, seeds) == J3
    assert J3 != [0.0, 0.0]
    m2.freeInstance()
    m3.freeInstance()


def test_model_exchange_event_update_and_directional_derivative_arguments(md3, dir3, vr3, tmp_path):
    """fmi3UpdateDiscreteStates writes all six results: over a profile whose kinks are time events
    (troughs at LAM/2 + k LAM, test_me_rolling), the next kink's time (x - x0)/V, and without one
    no next event time. fmi3GetDirectionalDerivative refuses nSeed != nKnowns and
    nSensitivity != nUnknowns, each alone."""
    from fmpy.fmi3 import FMU3Model
    from test_me_rolling import LAM, sharp_sinusoid
    _, _, path = sharp_sinusoid(tmp_path)
    V, x0 = 1.0, 0.05
    msgs = []

    def update(m):
        flags, t = [ctypes.c_bool(True) for _ in range(5)], ctypes.c_double(-1.0)
        assert raw(m, "fmi3UpdateDiscreteStates", *[ctypes.byref(b) for b in flags], ctypes.byref(t)) == OK
        return [b.value for b in flags], t.value

    for profile in (True, False):
        m = FMU3Model(guid=md3.guid, unzipDirectory=dir3, modelIdentifier="VibroImpact", instanceName="me3")
        m.instantiate(logMessage=lambda env, st, cat, text: msgs.append((st, text.decode())))
        m.enterInitializationMode(tolerance=1e-8)
        if profile:
            m.setString([vr3["profile_file"]], [str(path)])
            m.setFloat64([vr3["V"], vr3["x0"], vr3["a"]], [V, x0, 0.0])
        m.exitInitializationMode()
        flags, t = update(m)
        if profile:
            assert flags == [False, False, False, False, True]
            assert t == pytest.approx((LAM / 2 + LAM - x0) / V, abs=1e-12)
        else:
            assert (flags, t) == ([False] * 5, 0.0)
        m.enterContinuousTimeMode()
        if profile:  # past the first kink without stopping: the next one
            m.setTime(0.03)
            m.enterEventMode()
            assert update(m) == ([False, False, False, False, True],
                                 pytest.approx((LAM / 2 + 2 * LAM - x0) / V, abs=1e-12))
            m.enterContinuousTimeMode()
        der, states = [u.variable.valueReference for u in md3.derivatives], [vr3["y"], vr3["v"]]
        assert len(m.getDirectionalDerivative(der, states, [1.0, 0.0])) == 3
        d, u, k = (ctypes.c_double * 2)(1.0, 0.0), (ctypes.c_uint * 2)(*der[:2]), (ctypes.c_uint * 2)(*states)
        for n_seed, n_sens in ((1, 2), (2, 1)):
            del msgs[:]
            assert raw(m, "fmi3GetDirectionalDerivative", u, 2, k, 2, d, n_seed, d, n_sens) == ERROR
            assert [text for st, text in msgs if st == ERROR] == [
                f"fmi3GetDirectionalDerivative: nSeed = {n_seed} and nSensitivity = {n_sens} must equal nKnowns = 2 "
                "and nUnknowns = 2 (every variable is a scalar)"]
        m.freeInstance()


def test_null_result_pointers_are_refused_one_at_a_time(md3, dir3, logged3, vr3):
    """fmi3DoStep, fmi3UpdateDiscreteStates, fmi3CompletedIntegratorStep and the Model Exchange
    counts with each result pointer NULL alone: refused with "NULL argument", the others untouched,
    the instance going on."""
    from fmpy.fmi3 import FMU3Model

    log = logged3()
    s = log.instantiate()
    fmi3.initialize(s, vr3, {})
    msgs = []
    for k in range(4):
        flags, t = [ctypes.c_bool(True) for _ in range(3)], ctypes.c_double(-1.0)
        ptrs = [ctypes.byref(f) for f in flags] + [ctypes.byref(t)]
        ptrs[k] = None
        del log.messages[:]
        assert raw(s, "fmi3DoStep", 0.0, 1e-4, True, *ptrs) == ERROR, k
        assert errors(log) == ["fmi3DoStep: NULL argument"], k
        assert [f.value for f in flags] == [True] * 3 and t.value == -1.0
    s.doStep(0.0, 1e-4)
    s.freeInstance()
    m = FMU3Model(guid=md3.guid, unzipDirectory=dir3, modelIdentifier="VibroImpact", instanceName="me3")
    m.instantiate(logMessage=lambda env, st, cat, text: msgs.append((st, text.decode())))
    m.enterInitializationMode()
    m.exitInitializationMode()
    for k in range(6):
        flags, t = [ctypes.c_bool(True) for _ in range(5)], ctypes.c_double(-1.0)
        ptrs = [ctypes.byref(f) for f in flags] + [ctypes.byref(t)]
        ptrs[k] = None
        del msgs[:]
        assert raw(m, "fmi3UpdateDiscreteStates", *ptrs) == ERROR, k
        assert [text for st, text in msgs if st == ERROR] == ["fmi3UpdateDiscreteStates: NULL argument"], k
        assert [f.value for f in flags] == [True] * 5 and t.value == -1.0
    fmi3.update_discrete_states(m)
    m.enterContinuousTimeMode()
    for k in range(2):
        flags = [ctypes.c_bool(True) for _ in range(2)]
        ptrs = [ctypes.byref(f) for f in flags]
        ptrs[k] = None
        del msgs[:]
        assert raw(m, "fmi3CompletedIntegratorStep", True, *ptrs) == ERROR, k
        assert [text for st, text in msgs if st == ERROR] == ["fmi3CompletedIntegratorStep: NULL argument"], k
        assert [f.value for f in flags] == [True] * 2
    for fn in ("fmi3GetNumberOfContinuousStates", "fmi3GetNumberOfEventIndicators"):
        del msgs[:]
        assert raw(m, fn, None) == ERROR and [text for st, text in msgs if st == ERROR] == [f"{fn}: NULL argument"]
    assert m.completedIntegratorStep() == (False, False)
    m.freeInstance()


# ---- the other models on the layer, built for FMI 3.0 --------------------------------------------------

@pytest.mark.parametrize("name,signal,value", [("Track", "F_contact", 5e4), ("Vehicle", "y_wheel", -1e-4),
                                               ("LayerTest", "u", 0.5)])
def test_companion_and_layer_models_match_their_fmi2_builds(name, signal, value):
    """The input steps at 5 ms; every output follows it in both builds alike, with or without early
    return and Event Mode (the models have no events), and in Model Exchange."""
    md = read_model_description(str(BUILD / f"{name}.fmu"))
    outputs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    steps = np.array([(0.0, 0.0), (0.005, value)], dtype=[("time", np.float64), (signal, np.float64)])
    kw = dict(stop_time=0.02, output_interval=1e-4, output=outputs, input=steps, start_values={})
    r2 = fmpy.simulate_fmu(str(BUILD / f"{name}.fmu"), **kw)
    r3 = fmpy.simulate_fmu(str(BUILD / "fmi3" / f"{name}.fmu"), **kw)
    r3e = fmpy.simulate_fmu(str(BUILD / "fmi3" / f"{name}.fmu"), early_return_allowed=True, use_event_mode=True, **kw)
    for k in ["time"] + outputs:
        assert np.array_equal(r3[k], r2[k]), k
    moved = [k for k in outputs if np.ptp(r2[k]) > 0]
    assert moved, "the input step moved no output"
    for k in outputs:  # fmpy records Event Mode's extra samples: compare at the common times
        assert np.array_equal(np.interp(r2["time"], r3e["time"], r3e[k]), r2[k]), k
    if md.modelExchange:  # and their Model Exchange interfaces, integrated by fmpy's CVode
        r2 = fmpy.simulate_fmu(str(BUILD / f"{name}.fmu"), fmi_type="ModelExchange", **kw)
        r3 = fmpy.simulate_fmu(str(BUILD / "fmi3" / f"{name}.fmu"), fmi_type="ModelExchange", **kw)
        for k in ["time"] + outputs:
            assert np.array_equal(r3[k], r2[k]), k


def test_layer_discard_and_failure_map_to_fmi3(tmp_path):
    md = read_model_description(str(BUILD / "fmi3" / "LayerTest.fmu"))
    d = extract(str(BUILD / "fmi3" / "LayerTest.fmu"), unzipdir=str(tmp_path / "l"))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    log = fmi3.Logged(md, d)
    s = log.instantiate(early_return=True)
    fmi3.initialize(s, vr, dict(discard_at=0.35), kinds={"discard_at": "Float64"})
    with open(os.path.join(d, "resources", "value.txt")) as f:  # read by the model through resourcePath
        assert s.getFloat64([vr["resource_value"]])[0] == float(f.read())
    assert fmi3.do_step(s, 0.0, 0.25)[0] == OK
    status, handling, terminate, early, last = fmi3.do_step(s, 0.25, 0.25)
    assert (status, handling, terminate, early, last) == (DISCARD, False, False, False, 0.35)
    assert fmi3.do_step(s, 0.35, 0.1)[0] == ERROR  # Step Discarded: no more steps
    s.terminate()
    s.freeInstance()
    log = fmi3.Logged(md, d)
    s = log.instantiate()
    fmi3.initialize(s, vr, dict(fail_at=0.1), kinds={"fail_at": "Float64"})
    assert fmi3.do_step(s, 0.0, 0.25)[0] == ERROR
    assert raw(s, "fmi3Terminate") == ERROR  # the error state
    s.reset()
    fmi3.initialize(s, vr, {})
    assert fmi3.do_step(s, 0.0, 0.25)[0] == OK
    s.freeInstance()


# ---- a second importer: fmi-sim ------------------------------------------------------------------------

FMI_SIM = shutil.which("fmi-sim") or shutil.which(os.path.expanduser("~/.cargo/bin/fmi-sim"))


def fmi_sim(tmp_path, *options):
    if not FMI_SIM:
        pytest.fail("fmi-sim is not installed (tools/setup.sh installs it with cargo)")
    out = tmp_path / "out.csv"
    run = subprocess.run([FMI_SIM, "--model", str(FMU3), "-o", str(out), "co-simulation", "-s", "0", "-f", "0.01",
                          "--init-values", "a=0.0001", *options], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr[-2000:]
    with open(out) as f:
        return list(csv.DictReader(f))


def test_fmi_sim_runs_it_as_fmpy_does(tmp_path, logged3, vr3):
    rows = fmi_sim(tmp_path)
    t = [float(r["time"]) for r in rows]
    assert len(t) > 50 and t[-1] == pytest.approx(0.01)
    s = logged3().instantiate()
    fmi3.initialize(s, vr3, dict(a=1e-4))
    for k, r in enumerate(rows):
        if k:
            s.doStep(t[k - 1], t[k] - t[k - 1])
        assert float(r["y"]) == s.getFloat64([vr3["y"]])[0], t[k]
    s.freeInstance()


def test_fmi_sim_returns_early_at_the_events(tmp_path, logged3, vr3):
    rows = fmi_sim(tmp_path, "--early-return-allowed", "--event-mode-used")
    t = sorted({float(r["time"]) for r in rows})
    s = logged3().instantiate(early_return=True)
    fmi3.initialize(s, vr3, dict(a=1e-4))
    events, _ = fmi3.run_to_events(s, 0.0, 0.01, 1e-4)
    s.freeInstance()
    assert len(events) >= 8 and set(events) <= set(t)


def test_scheduled_execution_is_refused_with_and_without_a_logger(dir3):
    """fmi3InstantiateScheduledExecution gives no instance: the FMU offers Co-Simulation and Model
    Exchange only. It says why through the logger it is given (an error naming the kinds offered), and
    without a logger it returns NULL as well, calling nothing."""
    so = next(pathlib.Path(dir3, "binaries").glob("*/VibroImpact.so"))
    lib = ctypes.CDLL(str(so))
    log_type = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_char_p)
    f = lib.fmi3InstantiateScheduledExecution
    f.restype = ctypes.c_void_p
    f.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p, ctypes.c_bool, ctypes.c_bool, ctypes.c_void_p,
                  log_type, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    seen = []
    logger = log_type(lambda env, status, category, message: seen.append((status, category, message)))
    token = read_model_description(str(FMU3)).instantiationToken.encode()
    assert f(b"se", token, None, False, False, None, logger, None, None, None) is None
    assert seen == [(ERROR, b"logStatusError", b"fmi3InstantiateScheduledExecution: this FMU offers Co-Simulation and "
                                               b"Model Exchange, not Scheduled Execution")], seen
    assert f(b"se", token, None, False, False, None, log_type(), None, None, None) is None
