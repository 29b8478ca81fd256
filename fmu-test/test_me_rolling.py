"""Rolling over a profile (paper Fig. 1b) in Model Exchange: the platform yC the FMU gives fmpy's
integrator is the rigid constraint of the independent reference (reference/profile_ref.py), the
kinks of yb (the body bridging a trough) are time events the importer meets exactly, the dynamics
over a corrugation follow the linearised closed form, Model Exchange follows co-simulation over a
profile with kinks, and the end of a non-periodic table ends the run (terminateSimulation) with its
time and position."""
import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import effective
from vibroimpact.me import run_me
from test_rolling import R1, ROUND, write

from vibroimpact.reference import profile as profile_ref

LAM, A = 0.05, 3e-4  # curvature 4.7/m > 1/R1: the body bridges every trough, yb has a kink there


def sharp_sinusoid(tmp_path):
    x = np.linspace(0.0, 0.5, 2001)
    h = A * np.cos(2 * np.pi * x / LAM)
    return x, h, write(tmp_path / "sharp.txt", x, h)


def test_platform_is_the_rigid_constraint_and_kinks_are_time_events(fmu_path, tmp_path):
    x, h, path = sharp_sinusoid(tmp_path)
    V, x0, stop = 1.0, 0.05, 0.4
    r, inst = run_me(fmu_path, dict(profile_file=path, V=V, x0=x0, contact_model=1, a=0.0), stop, rtol=1e-8,
                     output=("yC", "y"), output_interval=1e-3, record_events=True)
    assert not inst.errors()
    pos = x0 + V * r["time"]
    assert np.abs(r["yC"] - profile_ref.yb(x, h, R1, pos)).max() <= 1e-12 * A + ROUND
    # the troughs, where the body touches two points (the reference's definition, searched)
    troughs = [LAM / 2 + k * LAM for k in range(1, 9)]
    for p in troughs:
        s = profile_ref.contact_points(x, h, R1, p)
        assert s.min() < p - 1e-3 and s.max() > p + 1e-3
    event_times = r["time"][1:][np.diff(r["time"]) == 0.0]  # the recorder samples an event twice
    for p in troughs:
        t_kink = (p - x0) / V
        assert np.min(np.abs(event_times - t_kink)) <= 1e-12, t_kink


def test_model_exchange_follows_co_simulation_over_the_kinks(fmu_path, tmp_path):
    """Hertz, static start, 1 m/s over the troughs: the mass leaves the profile at every crest and lands
    again (10 impacts in 0.12 s); ME (fmpy CVode) and CS at rtol 1e-10 stay within 1e-9 m of each other
    (measured 5.5e-11 m; later the bouncing makes every difference grow)."""
    x, h, path = sharp_sinusoid(tmp_path)
    p = dict(profile_file=path, V=1.0, x0=0.05, contact_model=1, a=0.0)
    r, inst = run_me(fmu_path, p, 0.12, rtol=1e-10, output=("y", "mode", "n_impacts"), output_interval=1e-4)
    c = simulate_fmu(str(fmu_path), fmi_type="CoSimulation", stop_time=0.12, start_values={**p, "rtol": 1e-10},
                     output=["y", "mode", "n_impacts"], output_interval=1e-4)
    assert c["n_impacts"][-1] >= 8 and r["n_impacts"][-1] == c["n_impacts"][-1]
    assert np.abs(r["y"] - c["y"]).max() <= 1e-9


def test_corrugation_dynamics_against_the_linearised_closed_form(fmu_path, tmp_path):
    """As test_rolling.py's co-simulation test: Hertz, static start on a crest, passing frequency 0.3 x
    the contact resonance over a 1 um corrugation: delta - delta_s = A W^2/(w_c^2 - W^2)
    (cos w_c t - cos W t), within 2 % of its range."""
    lam, amp0 = 0.05, 1e-6
    x = np.linspace(0.0, 2.0, 4001)
    path = write(tmp_path / "corrugation.txt", x, amp0 * np.cos(2 * np.pi * x / lam))
    e = effective(dict(g=9.81))
    d_s = (e["W"] / e["K"]) ** (2 / 3)
    w_c = np.sqrt(1.5 * e["K"] * np.sqrt(d_s) / e["m"])
    V = 0.3 * w_c * lam / (2 * np.pi)
    W = 2 * np.pi * V / lam
    r, inst = run_me(fmu_path, dict(profile_file=path, V=V, x0=0.0, contact_model=1), 0.03, rtol=1e-10,
                     output=("delta",), output_interval=1e-5)
    amp = amp0 * W ** 2 / (w_c ** 2 - W ** 2)
    lin = amp * (np.cos(w_c * r["time"]) - np.cos(W * r["time"]))
    assert np.abs(r["delta"] - d_s - lin).max() <= 0.02 * 2 * amp


def test_end_of_the_table_ends_the_run_with_time_and_position(fmu_path, tmp_path):
    x = np.linspace(0.0, 0.1, 11)
    path = write(tmp_path / "short.txt", x, np.zeros_like(x))
    r, inst = run_me(fmu_path, dict(profile_file=path, V=2.0, x0=0.02, contact_model=1), 0.1, rtol=1e-8,
                     output=("y",), output_interval=1e-3)
    # fmpy stops at the event that asks to terminate (its last sample is the output point before it)
    assert 0.039 - 1e-12 <= r["time"][-1] <= 0.04
    text = "\n".join(m for _, _, m in inst.messages)
    assert "t = 0.04" in text and "x_last = 0.1 m" in text
