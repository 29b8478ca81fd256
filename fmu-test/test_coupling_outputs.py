"""Coupling outputs: F_mean, the contact force averaged over the last communication
step (its impulse divided by the step), and k_contact, the tangent contact stiffness dF/ddelta.
Expected values: closed forms (static load, the Hertz drop's impulse 2 m v0, the derivatives of the
contact laws of paper eqs. 2-4 and Fig. 3 computed here) and an independent quadrature of the force
sampled finely."""
import numpy as np
import pytest

from conftest import effective, start
from solvers import each_solver
from vibroimpact.reference.scenarios import SCENARIOS

HERTZ, JOHNSON, LEPP = 1, 2, 3


def instance(logged, vr, params, tolerance=None):
    s = logged().instantiate()
    start(s, vr, params, tolerance=tolerance)
    return s


def get(s, vr, *names):
    return s.getReal([vr[n] for n in names])


@each_solver
@pytest.mark.parametrize("law", [HERTZ, JOHNSON, LEPP])
def test_static_contact_mean_force_is_the_load(logged, vr, law, solver):
    """At rest under P + m g - F_ext. (The explicit one-step method lets the rounding residual of the
    static state ring up to its tolerance: rtol 1e-10 keeps that below the bound.)"""
    s = instance(logged, vr, dict(contact_model=law, solver=solver, F_ext=-500.0), tolerance=1e-10)
    W = effective({})["W"] + 500.0  # P + m g - F_ext
    # before any step: the force itself, to rounding (1.6e-16 measured)
    assert get(s, vr, "F_mean")[0] == pytest.approx(W, rel=1e-14)
    t = 0.0
    for h in (1e-7, 1e-5, 1e-3, 0.1):
        s.doStep(t, h)
        t += h
        assert get(s, vr, "F_mean")[0] == pytest.approx(W, rel=1e-9), h
    s.freeInstance()


@each_solver
@pytest.mark.parametrize("v0", [-0.1, -0.5])
def test_hertz_drop_in_one_long_step_gives_impulse_2_m_v0(logged, vr, v0, solver):
    """P = g = 0: the mass lands at v0, leaves at -v0 (restitution 1); the step spans the whole contact."""
    s = instance(logged, vr, dict(contact_model=HERTZ, init=2, P=0.0, g=0.0, v0=v0, solver=solver, rtol=1e-10))
    h = 0.01
    s.doStep(0.0, h)
    m = effective({})["m"]
    assert not s.getBoolean([vr["contact"]])[0]
    assert get(s, vr, "F_mean")[0] * h == pytest.approx(2 * m * -v0, rel=1e-8)
    s.freeInstance()


def quadrature_of_F(s, vr, t0, h, n):
    """Simpson's rule of F sampled at n + 1 points over [t0, t0 + h] (steps inside the interval)."""
    F = [get(s, vr, "F")[0]]
    for k in range(n):
        s.doStep(t0 + k * h / n, h / n)
        F.append(get(s, vr, "F")[0])
    F = np.array(F)
    return h / (3 * n) * (F[0] + F[-1] + 4 * F[1:-1:2].sum() + 2 * F[2:-1:2].sum())


@each_solver
@pytest.mark.parametrize("name, ramp", [("fig5a", 0.0), ("fig4a", 0.0), ("fig5a", 2e6)])
def test_mean_force_against_an_independent_quadrature(logged, vr, name, ramp, solver):
    """Two instances from the same state: one takes 1e-4 s steps and reports F_mean, the other samples F
    every 1e-7 s over the same steps. Fig. 5a stays in contact; Fig. 4a bounces, so most steps hold
    impacts; with `ramp` the external force F_ext rises at that rate [N/s] (given as its derivative).
    Both at rtol 1e-10; the quadrature's own error is far below the bound."""
    params = {**SCENARIOS[name].full, "solver": solver}
    coarse, fine = instance(logged, vr, params, 1e-10), instance(logged, vr, params, 1e-10)
    for s in (coarse, fine):
        s.setRealInputDerivatives([vr["F_ext"]], [1], [ramp])
    h, worst, scale = 1e-4, 0.0, effective({})["W"]
    for k in range(60):
        coarse.doStep(k * h, h)
        impulse = quadrature_of_F(fine, vr, k * h, h, 1000)
        worst = max(worst, abs(get(coarse, vr, "F_mean")[0] - impulse / h))
    assert worst < 1e-4 * scale
    coarse.freeInstance()
    fine.freeInstance()


def hertz_k(K, d):
    return 1.5 * K * np.sqrt(np.maximum(d, 0.0))


def johnson_load_k(e, theta_Y, d):
    """d/ddelta of eq. 3, F = F_Y k (1 + ln k/(3 theta_Y)), k = 2 delta/delta_Y - 1."""
    k = 2 * d / e["delta_Y"] - 1
    return e["F_Y"] * 2 / e["delta_Y"] * (1 + (np.log(k) + 1) / (3 * theta_Y))


EXPECTED_MODES = {"fig4b": {0, 1, 2, 3}, "fig5b": {0, 1}, "fig6a_30um": {1, 2}, "stick": {2, 3, 4}}


@each_solver
@pytest.mark.parametrize("name", EXPECTED_MODES)
def test_contact_stiffness_is_the_slope_of_the_law(logged, vr, name, solver):
    p = {**SCENARIOS[name].full, "solver": solver}
    e = effective(p)
    s = instance(logged, vr, p)
    names = ("delta", "k_contact", "delta_c", "delta_f", "delta_p", "Rbar")
    seen = set()
    for k in range(2000):
        s.doStep(k * 2e-5, 2e-5)
        d, kc, dc, df, dp, Rbar = get(s, vr, *names)
        mode = s.getInteger([vr["mode"]])[0]
        seen.add(mode)
        law = p["contact_model"]
        if mode == 0:
            expected = 0.0
        elif law == HERTZ or (law == JOHNSON and mode == 1):
            expected = hertz_k(e["K"], d)
        elif law == JOHNSON and mode == 2:
            expected = johnson_load_k(e, p["theta_Y"], d)
        elif law == JOHNSON:  # unloading curve (mode 3), or at delta_c when sticking (mode 4)
            Kbar = 4 / 3 * e["E_star"] * np.sqrt(Rbar)
            expected = hertz_k(Kbar, (dc if mode == 4 else d) - df)
        else:  # LEPP: the spring, or perfectly plastic flow
            expected = e["k_lin"] if mode == 1 else 0.0
        # the same formula at the same state: rounding only (1.8e-15 measured over 32000 samples, every solver)
        assert kc == pytest.approx(expected, rel=1e-13, abs=1e-300), (k, mode)
    assert seen >= EXPECTED_MODES[name], seen
    s.freeInstance()


@each_solver
def test_reading_the_derivatives_in_co_simulation_changes_nothing(logged, vr, solver):
    """der_y and der_v are outputs of a Co-Simulation instance too. Reading them after every step, with
    both inputs given as ramps (their derivatives set), leaves the run bit for bit what it is without
    the reads; der_y is v, der_v the mass's acceleration (F - P + F_ext)/m - g, both at the step's end."""
    params = {**SCENARIOS["fig5a"].full, "solver": solver}
    reading, plain = instance(logged, vr, params), instance(logged, vr, params)
    names = ("y", "v", "F", "delta", "F_mean")
    m, P, g = (params[n] for n in ("m", "P", "g"))
    rows = {id(reading): [], id(plain): []}
    for k in range(200):
        for s in (reading, plain):
            s.setReal([vr["yC_in"], vr["F_ext"]], [1e-3 * k * 1e-5, 50.0 * k * 1e-5])
            s.setRealInputDerivatives([vr["yC_in"], vr["F_ext"]], [1, 1], [1e-3, 50.0])
            s.doStep(k * 1e-5, 1e-5)
            rows[id(s)].append(get(s, vr, *names))
        der_y, der_v = get(reading, vr, "der_y", "der_v")
        v, F = rows[id(reading)][-1][1:3]
        assert der_y == v
        F_ext = 50.0 * (k + 1) * 1e-5
        # rounding only: 1.4e-14 m/s^2 measured (der_v near 0 at rest: an absolute floor)
        assert der_v == pytest.approx((F - P + F_ext) / m - g, rel=1e-12, abs=1e-12)
    assert rows[id(reading)] == rows[id(plain)]
    for s in (reading, plain):
        s.freeInstance()
