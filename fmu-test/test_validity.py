"""The FMU says when a result leaves the model's range of validity (a contact radius
sqrt(R* delta) above 0.1 R*, i.e. delta > 0.01 R*) and when options contradict each other, through
the logger (fmi2Warning, category logStatusWarning), once per instance. Thresholds from closed forms:
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


def test_warnings_are_not_logged_when_the_category_is_off(logged, vr):
    inst = logged()
    s = inst.instantiate(logging=False)
    start(s, vr, dict(contact_model=1, moving_contact=True, P=1e12))
    assert warnings(inst) == []
