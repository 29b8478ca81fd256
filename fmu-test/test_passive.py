"""Laws that make no energy (doc/model.md section 2): with Johnson's continuous unloading an impact
rebounds with a restitution of at most 1 at every speed, and paper unloading (as printed), which
rebounds faster than it came below 1.36 times the yield speed, says so once per instance with the
values. Impact speeds are in units of the yield speed v_Y, from the Hertz energy at delta_Y:
1/2 m v_Y^2 = 2/5 F_Y delta_Y; the expected values come from the closed forms
(vibroimpact.reference.closed_forms), not from the C code."""
import re

import numpy as np
import pytest
from fmpy import simulate_fmu
from scipy.optimize import brentq

from conftest import effective, start
from vibroimpact.reference.closed_forms import w_plastic_closed_form

JOHNSON, PAPER, CONTINUOUS = 2, 1, 2
WARNING = 1  # fmi2Warning
NO_LOAD = dict(P=0.0, g=0.0)


def yield_speed(e):
    return np.sqrt(2 * 0.4 * e["F_Y"] * e["delta_Y"] / e["m"])


def turning_point(e, v0, variant):
    """delta_c of an impact at v0 without load (its kinetic energy is the virgin work to delta_c), and
    (work taken, W_plastic) there."""
    W = 0.5 * e["m"] * v0 ** 2
    dc = brentq(lambda d: w_plastic_closed_form(e, d, variant)[0] - W, e["delta_Y"], 1e3 * e["delta_Y"],
                xtol=1e-18, rtol=1e-15)
    return dc, w_plastic_closed_form(e, dc, variant)


@pytest.mark.parametrize("ratio", [1.01, 1.1, 1.36, 1.92, 3.0, 5.0, 7.9, 8.0, 10.0, 30.0, 100.0])
def test_continuous_unloading_rebounds_at_most_as_fast_as_it_came(fmu_path, ratio):
    """e <= 1 from 1.01 to 100 v_Y (it was 1.154 at 1.92 v_Y): 1 to the integration's accuracy while the
    curve gives back the whole loading work (delta_c below 4.61 delta_Y, impacts below 7.95 v_Y), then
    sqrt(1 - W_plastic/W) of the closed form (0.9667 at 10 v_Y, 0.6592 at 100 v_Y)."""
    e = effective(NO_LOAD)
    v0 = -ratio * yield_speed(e)
    dc, (W, Wp) = turning_point(e, v0, CONTINUOUS)
    assert dc < 0.01 * e["R_star"]  # inside the range of validity
    r = simulate_fmu(fmu_path, start_values=dict(NO_LOAD, contact_model=JOHNSON, unloading=CONTINUOUS, init=2, v0=v0,
                                                 rtol=1e-10),
                     stop_time=0.01, output_interval=1e-5, output=["v", "mode", "delta_c", "W_plastic"])
    assert r["mode"][-1] == 0 and r["delta_c"][-1] == pytest.approx(dc, rel=1e-6)
    restitution = r["v"][-1] / -v0
    assert restitution <= 1 + 1e-7
    assert restitution == pytest.approx(np.sqrt(1 - Wp / W), abs=1e-6)
    assert r["W_plastic"][-1] >= -1e-9 * W and r["W_plastic"][-1] == pytest.approx(Wp, abs=1e-7 * W)


def energy_warnings(inst):
    return [m for status, cat, m in inst.messages if status == WARNING and "unloading = paper" in m]


def number(text, name):
    m = re.search(name + r" = (-?[0-9.e+-]+)", text)
    assert m, (name, text)
    return float(m.group(1))


@pytest.mark.parametrize("ratio, warns", [(1.2, True), (1.34, True), (1.38, False), (3.0, False)])
def test_paper_unloading_says_when_it_makes_energy(logged, vr, ratio, warns):
    """An impact at 1.2 v_Y with paper unloading rebounds faster than it came: one warning names delta_c,
    the work taken and the energy given back (the closed form's); none above 1.36 v_Y."""
    e = effective(NO_LOAD)
    v0 = -ratio * yield_speed(e)
    dc, (W, Wp) = turning_point(e, v0, PAPER)
    assert (Wp < 0) == warns
    inst = logged()
    s = inst.instantiate(logging=False)
    start(s, vr, dict(NO_LOAD, contact_model=JOHNSON, unloading=PAPER, init=2, v0=v0, rtol=1e-10))
    for k in range(200):
        s.doStep(k * 5e-5, 5e-5)
    w = energy_warnings(inst)
    assert s.getReal([vr["delta_c"]])[0] == pytest.approx(dc, rel=1e-6)
    if not warns:
        assert w == [], w
        return
    assert len(w) == 1, w
    assert number(w[0], "delta_c") == pytest.approx(dc, rel=1e-5)
    assert re.search(r"took ([0-9.e+-]+) J", w[0]) and float(re.search(r"took ([0-9.e+-]+) J", w[0]).group(1)) \
        == pytest.approx(W, rel=1e-5)
    assert float(re.search(r"gives back ([0-9.e+-]+) J", w[0]).group(1)) == pytest.approx(W - Wp, rel=1e-5)
    assert number(w[0], "W_plastic") == pytest.approx(Wp, rel=1e-4)
    assert w[0].endswith("unloading = continuous does not"), w[0]  # whole, not cut


def test_paper_unloading_warns_once_per_instance(logged, vr):
    """F_ext presses the wheel into the platform slowly to 1.2 F_Y, releases it to 0.5 F_Y, presses to
    1.5 F_Y and releases: turning points below 1.2527 delta_Y (F_load there is 1.69 F_Y), each with an
    unloading curve that gives back more than the loading took; one warning."""
    e = effective(NO_LOAD)
    inst = logged()
    s = inst.instantiate(logging=False)
    start(s, vr, dict(NO_LOAD, contact_model=JOHNSON, unloading=PAPER, rtol=1e-10))
    h, legs = 1e-4, [(0.0, -1.2), (-1.2, -0.5), (-0.5, -1.5), (-1.5, 0.0)]
    turning_points, t = [], 0.0
    for f0, f1 in legs:  # each leg over 0.05 s
        for k in range(500):
            s.setReal([vr["F_ext"]], [(f0 + (f1 - f0) * (k + 1) / 500) * e["F_Y"]])
            s.doStep(t, h)
            t += h
            dc = s.getReal([vr["delta_c"]])[0]
            if dc > 0 and (not turning_points or dc > turning_points[-1]) and s.getInteger([vr["mode"]])[0] != 2:
                turning_points.append(dc)  # a new turning point committed
    assert len(turning_points) >= 2 and turning_points[-1] < 1.2527 * e["delta_Y"], turning_points
    assert all(w_plastic_closed_form(e, dc, PAPER)[1] < 0 for dc in turning_points)
    assert len(energy_warnings(inst)) == 1, energy_warnings(inst)


@pytest.mark.parametrize("kind", ["CoSimulation", "ModelExchange"])
def test_fmpy_shows_the_energy_warning(fmu_path, capfd, kind):
    """fmpy with its defaults prints the warning, in Co-Simulation and Model Exchange."""
    e = effective(NO_LOAD)
    simulate_fmu(fmu_path, fmi_type=kind, stop_time=0.01, output_interval=1e-4,
                 start_values=dict(NO_LOAD, contact_model=JOHNSON, unloading=PAPER, init=2, v0=-1.2 * yield_speed(e)))
    out = capfd.readouterr().out
    assert out.count("returns more energy than the contact took") == 1, out
