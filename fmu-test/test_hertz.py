"""Hertz contact end to end through fmpy: drop test, static equilibrium, calculated parameters,
contact resonance. Expected values are closed forms (the Hertz impact, doc/model.md) or the paper's."""
import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import RUN_SOLVER, effective, start

HERTZ = 1


def drop(fmu_path, v0, rtol=1e-10, stop=0.006, step=2e-6):
    params = dict(contact_model=HERTZ, init=2, P=0.0, g=0.0, v0=v0, rtol=rtol)
    return simulate_fmu(fmu_path, start_values=params, stop_time=stop, output_interval=step,
                        output=["delta", "v", "F", "mode", "n_impacts", "contact"])


def peak(t, y):
    """Maximum of sampled y refined by the parabola through the three samples around it."""
    i = int(np.argmax(y))
    y0, y1, y2 = y[i - 1], y[i], y[i + 1]
    return y1 + (y0 - y2) ** 2 / (8 * (2 * y1 - y0 - y2))


@pytest.mark.parametrize("v0", [-0.1, -0.5])
def test_drop_restitution_and_peak_indentation(fmu_path, v0):
    r = drop(fmu_path, v0)
    e = effective(dict(P=0.0, g=0.0))
    # after separation the mass flies off freely (P = g = 0) at the rebound velocity
    assert r["mode"][-1] == 0 and not r["contact"][-1]
    restitution = r["v"][-1] / -v0
    assert abs(restitution - 1.0) < 1e-6
    dmax = (15 * e["m"] * v0 ** 2 / (16 * e["E_star"] * np.sqrt(e["R_star"]))) ** 0.4
    assert abs(peak(r["time"], r["delta"]) / dmax - 1.0) < 1e-6
    # contact duration of the Hertz impact, 2 delta_max/v0 * int_0^1 dx/sqrt(1 - x^2.5) = 2.9433 delta_max/v0,
    # to the sampling step
    t_contact = r["time"][r["contact"].astype(bool)]
    assert abs((t_contact[-1] - t_contact[0]) - 2.9433 * dmax / -v0) < 3 * 2e-6
    assert r["n_impacts"][-1] == 0  # a contact present at the start is not counted


def test_static_equilibrium_stays_put(fmu_path):
    r = simulate_fmu(fmu_path, start_values=dict(contact_model=HERTZ), stop_time=0.1, output_interval=1e-3,
                     output=["delta", "v", "F", "y", "mode", "n_impacts"])
    e = effective({})
    d0 = (e["W"] / e["K"]) ** (2 / 3)
    # CVODE keeps rest to rounding; the explicit one-step method's error-free steps grow to its
    # stability limit on the contact oscillation, where rounding grows until the error control holds it:
    # rest to the tolerance (rtol 1e-6; delta 2e-6 relative measured, F 1.5 times that); auto runs the
    # explicit method until its steps are held by that stability limit, then BDF
    tol = 1e-5 if RUN_SOLVER in (3, 4) else 1e-12
    assert np.all(np.abs(r["delta"] / d0 - 1) < tol)
    assert np.all(np.abs(r["F"] / e["W"] - 1) < 1.5 * tol)
    assert np.all(np.abs(r["v"]) < tol)
    assert np.all(r["mode"] == 1) and r["n_impacts"][-1] == 0


def test_calculated_parameters(logged, vr):
    for params in [{}, dict(R2=0.3, E2=7e10, nu2=0.33, Y=4e8, theta_Y=1.2)]:
        s = logged().instantiate()
        start(s, vr, dict(contact_model=HERTZ, **params))
        e = effective(params)
        for name in ["E_star", "R_star", "F_Y", "delta_Y", "k_lin"]:
            assert s.getReal([vr[name]])[0] == pytest.approx(e[name], rel=1e-13), name
        s.terminate()
        s.freeInstance()


def test_contact_resonance_of_the_paper(logged, vr):
    s = logged().instantiate()
    start(s, vr, dict(contact_model=HERTZ, g=0.0))
    assert abs(s.getReal([vr["f_contact"]])[0] - 267.19) < 0.005
    s.terminate()
    s.freeInstance()


def test_contact_resonance_matches_free_oscillation(fmu_path):
    """A small platform step (0.1 % of the static indentation) rings at f_contact."""
    e = effective(dict(g=0.0))
    d0 = (e["W"] / e["K"]) ** (2 / 3)
    f0 = np.sqrt(1.5 * e["W"] / d0 / e["m"]) / (2 * np.pi)
    inp = np.array([(0.0, 0.0), (0.001, 0.0), (0.001, 1e-3 * d0), (0.1, 1e-3 * d0)],
                   dtype=[("time", float), ("yC_in", float)])
    r = simulate_fmu(fmu_path, start_values=dict(contact_model=HERTZ, g=0.0, rtol=1e-9), stop_time=0.05,
                     output_interval=1e-5, input=inp, output=["delta"])
    x = r["delta"][r["time"] > 0.0011] - np.mean(r["delta"][r["time"] > 0.0011])
    crossings = np.where(np.diff(np.sign(x)) > 0)[0]
    period = np.mean(np.diff(r["time"][crossings]))
    assert abs(1 / period / f0 - 1) < 2e-3


def test_mass_rides_the_platform_below_separation(fmu_path):
    """a = 1e-6 m at 560 Hz: far below the static indentation d0, the contact never opens and the force
    swings around the static load W. Linearised about d0 (stiffness k = 1.5 W/d0, w0^2 = k/m,
    r = w/w0), from rest with yC = a (cos wt - 1): F - W = A (cos wt - cos w0 t), A = k a r^2/(r^2 - 1).
    The part of F at the excitation frequency is A; the Hertz law's curvature, neglected there, adds
    to it only at third order, (a r^2/(r^2 - 1)/d0)^2 ~ 2e-3 relative (it shifts the free part's
    frequency instead)."""
    r = simulate_fmu(fmu_path, start_values=dict(contact_model=HERTZ, a=1e-6), stop_time=0.05,
                     output_interval=1e-5, output=["F", "contact", "yC", "y"])
    e = effective({})
    assert np.all(r["contact"])
    assert abs(np.mean(r["F"]) / e["W"] - 1) < 0.02
    assert np.min(r["yC"]) == pytest.approx(-2e-6, rel=1e-3)
    d0 = (e["W"] / e["K"]) ** (2 / 3)
    k, w = 1.5 * e["W"] / d0, 2 * np.pi * 560.0
    w0 = np.sqrt(k / e["m"])
    r2 = (w / w0) ** 2
    A = k * 1e-6 * r2 / (r2 - 1)
    t = r["time"]
    linear = A * (np.cos(w * t) - np.cos(w0 * t))

    def at_w(x):  # the cos and sin coefficients at w over the run (28 periods; the same sampling)
        return [float(2 * np.trapezoid(x * c(w * t), t) / t[-1]) for c in (np.cos, np.sin)]

    (c, s), (c_lin, s_lin) = at_w(r["F"] - e["W"]), at_w(linear)
    assert abs(c - c_lin) < 5e-3 * A and abs(s - s_lin) < 5e-3 * A, (c / A, c_lin / A, s / A, s_lin / A)
