"""The FMU says when a result leaves the model's range of validity (a contact radius
sqrt(R* delta) above 0.1 R*, i.e. delta > 0.01 R*; a contact force beyond the paper's limits of its
law: F_Y for Hertz, F_p = 650 F_Y for Johnson's eq. 3) and when options contradict each other, through
the logger (fmi2Warning, category logStatusWarning), once per instance, whatever the debug categories. Thresholds from closed forms:
the Hertz static indentation (W/K)^(2/3) and the Hertz impact indentation
(15 m v0^2/(16 E* sqrt(R*)))^(2/5); F_Y of eq. 5 (textbook) and the work along Johnson's virgin curve."""
import re

import numpy as np
import pytest
from fmpy import simulate_fmu
from scipy.optimize import brentq

from conftest import BUILD, DEFAULTS, effective, start
from vibroimpact.reference.closed_forms import load, virgin_work

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
    (dict(contact_model=1, yield_formula=2, P=1000.0), "yield_formula"),  # W below the printed F_Y
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


# ---- the force limits the paper states (section 2) --------------------------------------------------

HERTZ, JOHNSON, HERTZ_DAMPED = 1, 2, 4
LIMIT = {HERTZ: 1.0, HERTZ_DAMPED: 1.0, JOHNSON: 650.0}  # in F_Y: Hertz elastic, eq. 3 up to F_p ~ 650 F_Y


def force_warnings(inst):
    return [m for m in warnings(inst) if "the contact force reached" in m]


def in_F_Y(text):
    """The force a warning names, in units of F_Y ("... N = 1748 F_Y")."""
    return float(re.search(r" N = ([0-9.e+-]+) F_Y", text).group(1))


def yield_stress_for(ratio, params):
    """The Y at which the static load W = P + m g is `ratio` F_Y: F_Y grows as Y^3 (eq. 5)."""
    e = effective(params)
    return params.get("Y", DEFAULTS["Y"]) * (e["W"] / (ratio * e["F_Y"])) ** (1 / 3)


@pytest.mark.parametrize("law, moving", [(HERTZ, False), (HERTZ_DAMPED, False), (JOHNSON, False), (JOHNSON, True)])
@pytest.mark.parametrize("factor", [0.95, 1.05])
def test_a_static_force_beyond_the_law_s_limit_warns_once(logged, vr, law, moving, factor):
    """At rest under W = P + m g, with Y set so that W is 0.95 or 1.05 times the law's limit: one
    warning beyond it, naming W/F_Y (closed form), none below; 50 steps add none."""
    ratio = factor * LIMIT[law]
    params = dict(contact_model=law, moving_contact=moving, Y=yield_stress_for(ratio, {}))
    inst, s = run(logged, vr, params, steps=50)
    w = force_warnings(inst)
    if factor < 1:
        assert w == [], w
        return
    assert len(w) == 1 and w[0].startswith("t = 0 s: "), w
    assert in_F_Y(w[0]) == pytest.approx(ratio, rel=1e-3)
    assert f"F_p = 650 F_Y" in w[0] if law == JOHNSON else "Hertz's law" in w[0], w[0]


def impact_speed_for(ratio, e):
    """The approach speed at which an impact on Johnson's virgin curve (no load) turns at the force
    ratio F_Y: the kinetic energy is the work along eq. 3 to the indentation of that force."""
    dc = brentq(lambda d: float(load(e, d)) - ratio * e["F_Y"], e["delta_Y"], 1e3 * e["delta_Y"], xtol=1e-16)
    return np.sqrt(2 * virgin_work(e, dc) / e["m"])


@pytest.mark.parametrize("moving", [False, True])
@pytest.mark.parametrize("ratio", [600.0, 2250.0])
def test_an_impact_beyond_F_p_within_one_step_warns(logged, vr, ratio, moving):
    """Johnson, no load, an impact whose peak force is 600 or 2250 F_Y (closed form), the whole impact
    inside one communication step (force 0 at both ends; with a moving contact point no event marks
    the peak): the peak warns, naming its ratio."""
    params = dict(P=0.0, g=0.0, Y=1e8, init=2, moving_contact=moving)
    v0 = impact_speed_for(ratio, effective(params))
    inst, s = run(logged, vr, dict(params, v0=-v0), steps=1, h=0.05)
    assert s.getReal([vr["F"]])[0] == 0.0 and s.getInteger([vr["mode"]])[0] == 0  # over and gone
    w = force_warnings(inst)
    if ratio < 650:
        assert w == [], w
        return
    assert len(w) == 1 and 0 < float(re.match(r"t = (\S+) s", w[0]).group(1)) <= 0.05, w
    assert in_F_Y(w[0]) == pytest.approx(ratio, rel=1e-3)


@pytest.mark.parametrize("fmu", ["VibroImpact.fmu", "fmi3/VibroImpact.fmu"])
@pytest.mark.parametrize("kind", ["CoSimulation", "ModelExchange"])
def test_the_force_warning_is_the_same_in_every_interface(capfd, fmu, kind):
    """Johnson at rest at 1000 F_Y, through fmpy's default run: FMI 2.0 and 3.0, Co-Simulation and Model
    Exchange print the same warning."""
    Y = yield_stress_for(1000.0, {})
    e = effective(dict(Y=Y))
    simulate_fmu(str(BUILD / fmu), fmi_type=kind, start_values={"Y": Y}, stop_time=1e-3)
    out = [line for line in capfd.readouterr().out.splitlines() if "contact force reached" in line]
    assert len(out) == 1, (fmu, kind, out)
    assert out[0].endswith(f"t = 0 s: the contact force reached {e['W']:g} N = 1000 F_Y (F_Y = {e['F_Y']:g} N), "
                           "beyond F_p = 650 F_Y: Johnson's loading curve (paper eq. 3) holds for F_Y < F < F_p, a "
                           "plastic zone contained by elastic material (beyond, full plastic flow: contact_model = "
                           "lepp), so the results leave the model's range of validity"), out[0]
