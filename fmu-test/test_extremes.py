"""Extreme parameters: each case runs in a subprocess with a time limit, so that a
hang fails fast. Expected values are closed forms written here (static equilibrium, Hertz)."""
import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import RUN_SOLVER, effective, with_solver

RUNNER = r"""
import json, sys
from fmpy import read_model_description, extract
from vibroimpact.fmu import Logged, initialize
fmu, params, steps, h = sys.argv[1], json.loads(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
md = read_model_description(fmu)
vr = {v.name: v.valueReference for v in md.modelVariables}
L = Logged(md, extract(fmu))
s = L.instantiate()
out = {"ok": True, "messages": []}
try:
    initialize(s, vr, params)
    t = 0.0
    for k in range(steps):
        s.doStep(t, h)
        t += h
    names = ["F", "delta", "v", "mode", "y"]
    out.update({n: s.getReal([vr[n]])[0] for n in ["F", "delta", "v", "y", "delta_Y", "F_Y"]})
    out["mode"] = s.getInteger([vr["mode"]])[0]
except Exception as e:
    out["ok"] = False
    out["error"] = str(e)
out["messages"] = [m for _, _, m in L.messages]
print(json.dumps(out))
"""


def run(fmu_path, params, steps=0, h=1e-4, timeout=30):
    """Initialize (and step) in a subprocess; a hang is a failure after `timeout` seconds."""
    try:
        p = subprocess.run([sys.executable, "-c", RUNNER, fmu_path, json.dumps(with_solver(params)),
                            str(steps), str(h)], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{params}: no answer within {timeout} s (hang)")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


# Loads far below F_Y (load/F_Y under 1e-154): the static start still returns, on the closed form.
@pytest.mark.parametrize("params", [
    {"P": 1e-200, "g": 0.0},
    {"P": 1e-200, "g": 0.0, "contact_model": 1},
    {"P": 1e-200, "g": 0.0, "contact_model": 3},
    {"R1": 1e85},
    {"m": 5e-324, "P": 0.0},
    {"P": 1e-300, "g": 0.0},
], ids=["johnson_P1e-200", "hertz_P1e-200", "lepp_P1e-200", "R1_1e85", "m_5e-324", "P1e-300"])
def test_static_start_at_tiny_loads_returns(fmu_path, params):
    r = run(fmu_path, params)
    assert r["ok"], r
    W = params.get("P", 40000.0) + params.get("m", 407.747) * params.get("g", 9.81)
    assert r["mode"] == 1 and r["v"] == 0.0
    if W > 1e-290:  # the force is a normal number
        assert r["F"] == pytest.approx(W, rel=1e-12)
    e = effective(params)
    # Hertz (and Johnson below yield) closed form, by logarithms: delta = (W/K)^(2/3)
    if params.get("contact_model", 2) != 3:
        assert r["delta"] == pytest.approx(np.exp(2 / 3 * (np.log(W) - np.log(e["K"]))), rel=1e-12)


# ---- absolute tolerances from the active law's own scales ------------------------------------
def outputs(fmu_path, params, stop=0.02, h=1e-4):
    from fmpy import simulate_fmu
    return simulate_fmu(fmu_path, start_values=params, stop_time=stop, output_interval=h,
                        output=["y", "v", "F", "delta", "mode"])


def test_hertz_does_not_depend_on_Y(fmu_path):
    """Y plays no role in Hertz: runs with Y = 6e8 and Y = 1e4 are the same bit for bit (the length
    scale came from delta_Y(Y) before: 5e-16 m at Y = 1e4)."""
    base = dict(contact_model=1, a=1e-4, f=560.0, rtol=1e-10)
    a, b = outputs(fmu_path, {**base, "Y": 6e8}), outputs(fmu_path, {**base, "Y": 1e4})
    for n in ("y", "v", "F", "mode"):
        assert np.array_equal(a[n], b[n]), n
    assert a["mode"].min() == 0 and a["mode"].max() == 1  # it bounces: the run exercises events


@pytest.mark.parametrize("law", [1, 2, 3])
def test_static_start_ignores_v0(fmu_path, law):
    """A static start does not use v0: v0 = 1e-100 gives the run of v0 = 0 bit for bit (it shrank the
    scale to the Hertz impact indentation at 1e-100 m/s and exhausted the step limit)."""
    base = dict(contact_model=law, a=1e-4, f=560.0)
    a, b = outputs(fmu_path, {**base, "v0": 0.0}), outputs(fmu_path, {**base, "v0": 1e-100})
    for n in ("y", "v", "F", "mode"):
        assert np.array_equal(a[n], b[n]), n


@pytest.mark.parametrize("law", [1, 2, 3])
def test_negligible_amplitude_keeps_the_static_state(fmu_path, law):
    """a = 1e-300 gave zero error weights (CV_ILL_INPUT). The platform does not move: the force
    stays at the load (closed form) to the tolerance, and the run equals a = 0 to rounding."""
    W = 40000.0 + 407.747 * 9.81
    r = outputs(fmu_path, dict(contact_model=law, a=1e-300))
    z = outputs(fmu_path, dict(contact_model=law, a=0.0))
    assert np.all(r["mode"] == 1)
    # CVODE (bdf, adams) keeps rest to rounding: the right-hand side at the static state is zero to a
    # few ulps of W, and so is every step (measured 3 ulps). The explicit one-step method's error-free
    # steps grow to its stability limit on the contact oscillation, where rounding grows until the error
    # control holds it: rest to the tolerance (rtol 1e-6; the force 1.5 times the indentation's error,
    # with a factor 10 of global over local error, as in test_hertz). auto runs the explicit method until
    # its steps are held by that stability limit, then BDF.
    tol = 1.5e-5 if RUN_SOLVER in (3, 4) else 16 * np.finfo(float).eps
    assert np.abs(r["F"] - W).max() <= tol * W
    assert np.abs(r["y"] - z["y"]).max() <= 1e-20


def test_tiny_load_with_excitation_runs(fmu_path):
    """P = 1e-200, g = 0 under an excitation: initialization never returned, and the static
    indentation (2e-141 m) would have made the tolerances vanish. The platform starts accelerating
    downwards at a omega^2 while nothing holds the mass down: it flies."""
    r = run(fmu_path, {"P": 1e-200, "g": 0.0, "a": 1e-4}, steps=200)
    assert r["ok"], r
    assert r["mode"] == 0  # flying: weightless, thrown off by the platform
