"""The vehicle-track companion FMUs (Track, Vehicle) in Model Exchange: fmpy integrates their states
and meets the input steps as input events; the closed forms of test_vehicle_track.py hold (the
track's step response through the matrix exponential, the vehicle's damped oscillation after a
wheel drop)."""
import math

import numpy as np
import pytest
from fmpy import simulate_fmu
from scipy.linalg import expm

from test_vehicle_track import P_T, P_V, TRACK, VEHICLE, needs_fmus, track_matrices

T_STEP = 1e-3  # s, when the input steps


def step(name, before, after, stop):
    return np.array([(0.0, before), (T_STEP, before), (T_STEP, after), (stop, after)],
                    dtype=[("time", float), (name, float)])


@needs_fmus
def test_track_step_response_in_model_exchange():
    F0, F1, stop = 60e3, 70e3, 0.05
    r = simulate_fmu(str(TRACK), fmi_type="ModelExchange", solver="CVode", stop_time=stop, relative_tolerance=1e-10, start_values={},
                     output_interval=1e-5, input=step("F_contact", F0, F1, stop),
                     output=["z_rail", "v_rail", "z_sleeper", "v_sleeper", "der_v_rail"])
    A, b = track_matrices(P_T)
    x_static = lambda F: -np.linalg.solve(A, b * F)  # noqa: E731
    x0, x1 = x_static(F0), x_static(F1)
    before, after = r["time"] < T_STEP, r["time"] > T_STEP
    assert np.abs(r["z_rail"][before] - x0[0]).max() < 1e-12 * abs(x0[0])  # at rest under F0
    exact = np.array([x1 + expm(A * (t - T_STEP)) @ (x0 - x1) for t in r["time"][after]])
    assert np.abs(r["z_rail"][after] - exact[:, 0]).max() < 1e-6 * np.ptp(exact[:, 0])
    assert np.abs(r["v_sleeper"][after] - exact[:, 3]).max() < 1e-6 * np.ptp(exact[:, 3])
    dv = np.array([(A @ x + b * F1)[1] for x in exact])  # the derivative the FMU reports
    assert np.abs(r["der_v_rail"][after] - dv).max() < 1e-5 * np.ptp(dv)


@needs_fmus
def test_vehicle_wheel_drop_in_model_exchange():
    m, k, c, g = P_V["m_body"], P_V["k_susp"], P_V["c_susp"], P_V["g"]
    d, stop = -1e-3, 0.5
    r = simulate_fmu(str(VEHICLE), fmi_type="ModelExchange", solver="CVode", stop_time=stop, relative_tolerance=1e-10, start_values={},
                     output_interval=1e-4, input=step("y_wheel", 0.0, d, stop), output=["F_wheel", "z_body", "E",
                                                                                         "W_dissipated"])
    assert r["F_wheel"][0] == pytest.approx(-m * g, rel=1e-15)
    w, zeta = math.sqrt(k / m), c / (2 * math.sqrt(k * m))
    wd = w * math.sqrt(1 - zeta ** 2)
    after = r["time"] > T_STEP
    t = r["time"][after] - T_STEP
    z = d + np.exp(-zeta * w * t) * (-d * np.cos(wd * t) - d * zeta * w / wd * np.sin(wd * t))
    assert np.abs(r["z_body"][after] - z).max() < 1e-6 * abs(d)
    # the dissipated work (a state in both interfaces) closes the energy balance after the drop
    # (E jumps with the wheel at T_STEP; no work is done by a wheel at rest afterwards)
    balance = r["E"][after] + r["W_dissipated"][after]
    assert np.abs(balance - balance[0]).max() < 1e-6 * 0.5 * k * d * d
