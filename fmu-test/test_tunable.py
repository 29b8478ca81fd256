"""Tunable excitation: a and f may be set between steps; the change takes
effect at the start of the next step with the phase of the excitation continuous. Closed forms: with
the mass thrown clear of the platform (no load, v0 = 1 m/s) the output yC is the excitation alone,
yC = a (cos phi - 1) with the phase phi accumulating 2 pi f dt over each step."""
import numpy as np
import pytest
from fmpy import extract, read_model_description

from conftest import Logged, start

FLYING = dict(contact_model=1, P=0.0, g=0.0, init=2, v0=1.0, rtol=1e-10)


@pytest.fixture(scope="module")
def fmu(fmu_path):
    md = read_model_description(fmu_path)
    return md, extract(fmu_path), {v.name: v.valueReference for v in md.modelVariables}


def test_a_and_f_are_tunable_in_the_description(fmu):
    md, _, _ = fmu
    var = {v.name: v for v in md.modelVariables}
    assert var["a"].variability == "tunable" and var["f"].variability == "tunable"


def test_sweep_up_and_down_keeps_the_phase(fmu):
    """f changed at every communication point, up then down, and a twice: yC follows the closed form
    with the accumulated phase, never jumping when only f changes; the mass flies on untouched."""
    md, unzipdir, vr = fmu
    s = Logged(md, unzipdir).instantiate()
    a, f, h = 1e-4, 50.0, 1e-3
    start(s, vr, dict(FLYING, a=a, f=f))
    phase, t, yC_prev = 0.0, 0.0, 0.0
    for k in range(80):
        f_new = 50.0 + 10.0 * (k if k < 40 else 79 - k)
        a_new = 2e-4 if k == 20 else (1e-4 if k == 60 else a)
        if f_new != f:
            s.setReal([vr["f"]], [f_new])
        if a_new != a:
            s.setReal([vr["a"]], [a_new])
        v_before = s.getReal([vr["v"]])[0]
        if a_new == a and f_new != f:
            # only f changed at t: read the platform just after t (a step of eps), where the new f
            # already acts. With the phase kept, yC moves by at most a omega_new eps from yC(t); a phase
            # restarted as omega_new t would move it by about a |omega_new - omega| t (6e-9 m to 5e-7 m here).
            eps = 1e-12
            s.doStep(t, eps)
            yC_eps = s.getReal([vr["yC"]])[0]
            omega_new = 2 * np.pi * f_new
            # |yC'| <= a omega_new over a step of eps (to one ulp of t), plus rounding of yC
            assert abs(yC_eps - yC_prev) <= a * omega_new * (eps + np.spacing(t)) + 4 * np.spacing(a), k
            assert yC_eps == pytest.approx(a * (np.cos(phase + omega_new * eps) - 1.0), abs=1e-16), k
            s.doStep(t + eps, h - eps)
        else:
            s.doStep(t, h)
        f, a = f_new, a_new
        phase += 2 * np.pi * f * h
        t += h
        yC = s.getReal([vr["yC"]])[0]
        assert yC == pytest.approx(a * (np.cos(phase) - 1.0), abs=1e-16), k
        assert s.getReal([vr["v"]])[0] == v_before == 1.0  # free flight, no load: v stays 1 m/s
        yC_prev = yC


def test_amplitude_change_moves_the_platform_at_once(fmu):
    md, unzipdir, vr = fmu
    s = Logged(md, unzipdir).instantiate()
    start(s, vr, dict(FLYING, a=1e-4, f=100.0))
    s.doStep(0.0, 0.0031)
    y_before, d_before = s.getReal([vr["y"], vr["delta"]])
    s.setReal([vr["a"]], [3e-4])
    s.doStep(0.0031, 1e-9)
    y, d, yC = s.getReal([vr["y"], vr["delta"], vr["yC"]])
    assert y == pytest.approx(y_before + 1e-9, abs=1e-15)  # the mass flies on at 1 m/s
    # the platform moved by (a_new - a)(cos phi - 1) at once: yC = a_new (cos phi - 1) just after
    assert yC == pytest.approx(3e-4 * (np.cos(2 * np.pi * 100.0 * (0.0031 + 1e-9)) - 1.0), abs=1e-16)
    assert d == pytest.approx(yC - y, abs=1e-16) and abs(d - d_before) > 1e-5


def test_fixed_parameters_stay_fixed(fmu):
    md, unzipdir, vr = fmu
    s = Logged(md, unzipdir).instantiate()
    start(s, vr, FLYING)
    with pytest.raises(Exception):
        s.setReal([vr["m"]], [1.0])


def test_the_excitation_starts_at_the_start_time(fmu):
    """An experiment starting at t0 = 0.3721 s (208.4 periods of 560 Hz, not a whole number): the
    platform starts at rest there, yC = a (cos 2 pi f (t - t0) - 1), not at the phase of t = 0."""
    md, unzipdir, vr = fmu
    s = Logged(md, unzipdir).instantiate()
    a, f, t0, h = 1e-4, 560.0, 0.3721, 1e-4
    start(s, vr, dict(FLYING, a=a, f=f), start_time=t0)
    assert s.getReal([vr["yC"]]) == [0.0]
    t = t0
    for _ in range(5):
        s.doStep(t, h)
        t += h
        assert s.getReal([vr["yC"]])[0] == pytest.approx(a * (np.cos(2 * np.pi * f * (t - t0)) - 1.0), abs=1e-15)
    s.freeInstance()
