"""The FMU says when a result leaves the model's range of validity (a contact radius
sqrt(R* delta) above 0.1 R*, i.e. delta > 0.01 R*) and when options contradict each other, through
the logger (fmi2Warning, category logStatusWarning), once per instance, whatever the debug categories. Thresholds from closed forms:
the Hertz static indentation (W/K)^(2/3) and the Hertz impact indentation
(15 m v0^2/(16 E* sqrt(R*)))^(2/5)."""
import numpy as np
import pytest

from conftest import effective, start

WARNING = 1  # fmi2Warning


def warnings(inst):
    return [m for status, cat, m in inst.messages if status == WARNING and cat == "logStatusWarning"]


def run(logged, vr, params, steps=0, h=1e-5):
    inst = logged()
    s = inst.instantiate(logging=False)
    s.setDebugLogging(True, ["logStatusWarning"])
    start(s, vr, params)
    t = 0.0
    for _ in range(steps):
        s.doStep(t, h)
        t += h
    return inst, s


@pytest.mark.parametrize("law", [1, 2, 3])
def test_huge_load_warns_once(logged, vr, law):
    """P = 1e12 N: the static indentation exceeds the radius (it was reported with fmi2OK, silently)."""
    e = effective(dict(P=1e12))
    assert (e["W"] / e["K"]) ** (2 / 3) > 0.01 * e["R_star"]  # closed form: far outside
    inst, s = run(logged, vr, dict(contact_model=law, P=1e12, a=1e-4), steps=50)
    w = [m for m in warnings(inst) if "0.01 R*" in m]
    assert len(w) == 1, inst.messages
    if law != 3:  # LEPP starts at delta_Y beyond F_Y and flows there, to hundreds of metres
        assert "t = 0 s" in w[0]


def test_default_run_does_not_warn(logged, vr):
    inst, s = run(logged, vr, dict(a=1e-4), steps=200)
    assert warnings(inst) == []


@pytest.mark.parametrize("v0, warn", [(-10.0, False), (-30.0, True)])
def test_impact_deeper_than_the_threshold_warns(logged, vr, v0, warn):
    """Hertz drop: the peak indentation passes 0.01 R* for |v0| above 18 m/s (closed form)."""
    e = effective(dict(P=0.0, g=0.0))
    d_max = (15 * e["m"] * v0 ** 2 / (16 * e["E_star"] * np.sqrt(e["R_star"]))) ** 0.4
    assert (d_max > 0.01 * e["R_star"]) == warn
    inst, s = run(logged, vr, dict(contact_model=1, P=0.0, g=0.0, init=2, v0=v0), steps=300)
    w = [m for m in warnings(inst) if "0.01 R*" in m]
    assert len(w) == (1 if warn else 0), w


@pytest.mark.parametrize("params, name", [
    (dict(contact_model=1, moving_contact=True), "moving_contact"),
    (dict(contact_model=3, moving_contact=True), "moving_contact"),
    (dict(contact_model=1, unloading=2), "unloading"),
    (dict(contact_model=2, moving_contact=True, unloading=2), "unloading"),
    (dict(contact_model=1, yield_formula=2), "yield_formula"),
    (dict(v0=0.5), "v0"),
    (dict(V=3.0), "profile_file"),
    (dict(profile_periodic=True), "profile_file"),
])
def test_contradicting_options_warn(logged, vr, params, name):
    inst, s = run(logged, vr, params, steps=3)
    w = warnings(inst)
    assert len(w) == 1 and name in w[0] and "ignored" in w[0], w


def test_warnings_reach_the_logger_with_every_category_off(logged, vr):
    """The user should see a warning: with logging off (fmpy's default) the warnings are still logged, with
    status fmi2Warning. They are notes the run goes on through, so the call that logged them returns fmi2OK
    (fmusim and PyFMI stop a run at any other status)."""
    inst = logged()
    s = inst.instantiate(logging=False)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.setInteger([vr["contact_model"]], [1])
    s.setBoolean([vr["moving_contact"]], [True])
    s.setReal([vr["a"]], [1.0])  # larger than R* = 0.475 m
    status = s._functions["fmi2ExitInitializationMode"](s.component)  # fmpy's wrapper hides a warning
    assert status == 0  # fmi2OK
    w = warnings(inst)
    assert len(w) == 2 and "moving_contact" in w[0] and "exceeds R*" in w[1], w
    assert raw_step(s, 0.0, 1e-5) == 0


def raw_step(s, t, h):
    return s._functions["fmi2DoStep"](s.component, t, h, 1)


def test_fmpy_default_run_shows_the_amplitude_warning(fmu_path, capfd):
    """fmpy.simulate_fmu with its defaults (no debug logging) prints the warning of an amplitude larger
    than R*, in FMI 2.0 Co-Simulation and Model Exchange."""
    from fmpy import simulate_fmu
    for kind in ("CoSimulation", "ModelExchange"):
        simulate_fmu(fmu_path, fmi_type=kind, start_values={"a": 1.0}, stop_time=1e-3)
        out = capfd.readouterr().out
        assert "[WARNING]" in out and "a = 1 m exceeds R* = 0.475 m" in out, (kind, out)


def test_debug_logging_enables_exactly_the_categories_named(logged, vr):
    """fmi2SetDebugLogging(true, [c]) after (true, []) leaves only c on: no event messages afterwards."""
    inst = logged()
    s = inst.instantiate(logging=False)
    s.setDebugLogging(True, [])  # all
    s.setDebugLogging(True, ["logStatusWarning"])  # exactly this one
    del inst.messages[:]  # the call itself was logged while every category was on
    start(s, vr, dict(a=1e-4))
    for k in range(100):
        s.doStep(k * 1e-5, 1e-5)
    assert not [m for status, cat, m in inst.messages if cat in ("logEvents", "logSolver", "logFmi2Call")]
    inst2 = logged()
    s2 = inst2.instantiate(logging=False)
    s2.setDebugLogging(True, ["logEvents"])
    start(s2, vr, dict(a=1e-4))
    for k in range(100):
        s2.doStep(k * 1e-5, 1e-5)
    assert [m for status, cat, m in inst2.messages if cat == "logEvents"]  # the control: events do happen
