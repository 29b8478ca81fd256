"""The vehicle-track example in Model Exchange (examples/vehicle-track/me_master.py): the companion
FMUs' Model Exchange interface against closed forms and an independent ODE, and the three FMUs
integrated together by one solver (SciPy's solve_ivp) against the monolithic reference."""
import math
from types import SimpleNamespace

import numpy as np
import pytest
from fmpy import read_model_description
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from conftest import BUILD, FMU

# the example's modules, importable through pytest.ini's pythonpath
import me_master
import parameters
import reference
import roughness
from test_vehicle_track import needs_fmus, track_matrices

P_T, P_V = parameters.TRACK, parameters.VEHICLE


def integrate(fmu_name, start_inputs, inputs, t_end, rtol=1e-10, outputs=(), n_out=201):
    """One companion FMU as Model Exchange: start_inputs (a dict) set in initialization mode, then
    inputs(t) before every evaluation, integrated by solve_ivp (DOP853); outputs on a grid."""
    f = me_master.MeFmu(BUILD / f"{fmu_name}.fmu", fmu_name.lower(), {}, rtol)
    try:
        setters = {k: f.setter(k) for k in start_inputs}

        def load(t, x):
            f.fmu.setTime(t)
            f.x[:] = x
            f.fmu.setContinuousStates(f.x, f.nx)
            for k, v in inputs(t).items():
                setters[k](v)

        for k, v in start_inputs.items():
            setters[k](v)
        f.fmu.exitInitializationMode()
        f.running = True
        f.event_iteration()
        x0 = f.states()

        def rhs(t, x):
            load(t, x)
            f.fmu.getDerivatives(f.dx, f.nx)
            return np.array(f.dx)

        sol = solve_ivp(rhs, (0.0, t_end), x0, method="DOP853", rtol=rtol, atol=rtol * f.nominals(),
                        dense_output=True)
        assert sol.success, sol.message
        t = np.linspace(0.0, t_end, n_out)
        out = {k: np.empty(n_out) for k in outputs}
        getters = {k: f.getter(k) for k in outputs}
        for i, ti in enumerate(t):
            load(ti, sol.sol(ti))
            for k, get in getters.items():
                out[k][i] = get()
        return t, out
    finally:
        f.free()


@needs_fmus
def test_companions_declare_model_exchange():
    for name, states in (("Track", ["z_rail", "v_rail", "z_sleeper", "v_sleeper", "W_in"]),
                         ("Vehicle", ["z_body", "v_body", "W_dissipated", "W_in"])):
        md = read_model_description(str(BUILD / f"{name}.fmu"))
        assert md.modelExchange is not None and md.modelExchange.modelIdentifier == name
        assert [d.variable.derivative.name for d in md.derivatives] == states
        assert md.numberOfContinuousStates == len(states) and md.numberOfEventIndicators == 0


@needs_fmus
def test_track_me_step_response_and_work():
    """Static under F0, then F1 from t = 0 on: x(t) = x1 + expm(A t) (x0 - x1) (track.c's equations
    as matrices, written in test_vehicle_track.py), and the work of the constant load, an ME state
    integrated by the importer, is -F1 (z_r(t) - z_r(0)); W_dissipated = W_in - (E - E(0)) grows to
    (F1 - F0)^2 / (2 k_static) as the track settles at its new static deflection."""
    F0, F1, T = 60e3, 70e3, 0.05
    t, out = integrate("Track", {"F_contact": F0}, lambda t: {"F_contact": F1}, T,
                       outputs=("z_rail", "v_sleeper", "W_in", "E", "W_dissipated"))
    A, b = track_matrices(P_T)
    x0, x1 = -np.linalg.solve(A, b * F0), -np.linalg.solve(A, b * F1)
    exact = np.array([x1 + expm(A * tt) @ (x0 - x1) for tt in t])
    assert np.max(np.abs(out["z_rail"] - exact[:, 0])) < 1e-8 * np.ptp(exact[:, 0])
    assert np.max(np.abs(out["v_sleeper"] - exact[:, 3])) < 1e-8 * np.ptp(exact[:, 3])
    work = -F1 * (exact[:, 0] - exact[0, 0])
    assert np.max(np.abs(out["W_in"] - work)) < 1e-8 * np.max(np.abs(work))
    assert np.all(np.diff(out["W_dissipated"]) > -1e-9)
    k_static = 1.0 / (1.0 / P_T["k_pad"] + 1.0 / P_T["k_ballast"])
    assert out["W_dissipated"][-1] == pytest.approx((F1 - F0) ** 2 / (2 * k_static), rel=1e-3)


@needs_fmus
def test_vehicle_me_follows_its_equations_and_balances_energy():
    """The wheel moves as y = a sin(w t) (set as values: in Model Exchange the wheel is where its
    inputs say now). The body against the same equation integrated here (vehicle.c's header:
    m_b z_b'' = -k (z_b - y) - c (v_b - v)), and E + W_dissipated - W_in = E(0), with W_dissipated
    and W_in two ME states integrated by the importer."""
    a, w, T = 2e-3, 2 * math.pi * 5.0, 0.5
    m, k, c, g = P_V["m_body"], P_V["k_susp"], P_V["c_susp"], P_V["g"]
    wheel = lambda t: {"y_wheel": a * math.sin(w * t), "v_wheel": a * w * math.cos(w * t)}  # noqa: E731
    t, out = integrate("Vehicle", wheel(0.0), wheel, T, outputs=("z_body", "F_wheel", "E", "W_in", "W_dissipated"))
    ode = solve_ivp(lambda tt, x: [x[1], -(k * (x[0] - a * math.sin(w * tt)) + c * (x[1] - a * w * math.cos(w * tt))) / m],
                    (0, T), [0.0, a * w], method="DOP853", rtol=1e-12, atol=1e-15, dense_output=True)
    z = ode.sol(t)[0]
    assert np.max(np.abs(out["z_body"] - z)) < 1e-8 * a
    F = -m * g + k * (z - a * np.sin(w * t)) + c * (ode.sol(t)[1] - a * w * np.cos(w * t))
    assert np.max(np.abs(out["F_wheel"] - F)) < 1e-6 * k * a
    balance = out["E"] + out["W_dissipated"] - out["W_in"] - out["E"][0]
    assert out["W_dissipated"][-1] > 1.0 and np.max(np.abs(out["W_in"])) > 100.0
    assert np.max(np.abs(balance)) < 1e-8 * np.max(np.abs(out["W_in"]))


# ---- the coupled system ------------------------------------------------------------------------------

# Tolerance of the force against the reference, from the solver's relative tolerance rtol: the
# positions carry a local error of about rtol |y|, |y| = 3.7 mm (the track's static deflection under
# the wheel), and the Hertz force moves by 1.5 F/delta per metre of indentation, delta = 73.7 um at
# the static load W: 1.5 rtol |y| / delta = 75 rtol of W per step; allow ten times that for the
# accumulation over the run. (Measured: 20 to 40 rtol at 1e-8, examples/vehicle-track/README.md.)
FORCE_PER_RTOL = 750.0
RTOL = 1e-8


def force_error(r, sol, system):
    return float(np.max(np.abs(r["contact.F"] - sol.force(r["t"]))) / system.W)


@pytest.fixture(scope="module")
def rough(tmp_path_factory):
    """The example's roughness in a file and the reference over the first 40 ms (the roughness
    starts after 13 ms)."""
    path = tmp_path_factory.mktemp("profile") / "profile.txt"
    roughness.write(path, *roughness.profile(**parameters.ROUGHNESS))
    T = 0.04
    system = reference.default_system(str(path), T)
    return path, T, system, reference.simulate(system, T, rtol=1e-10)


@needs_fmus
def test_me_plan_sets_inputs_before_the_outputs_that_depend_on_them():
    """The evaluation order follows ModelStructure: in Model Exchange the contact force F depends on
    yC_in at once and the suspension force on the wheel's position and velocity, so yC_in is set
    before F is read and y_wheel, v_wheel before F_wheel; a dependency cycle is refused."""
    mds = {n: read_model_description(str(p)) for n, p in
           (("contact", FMU), ("track", BUILD / "Track.fmu"), ("vehicle", BUILD / "Vehicle.fmu"))}
    fmus = {n: SimpleNamespace(feedthrough=me_master.feedthrough(md)) for n, md in mds.items()}
    assert fmus["contact"].feedthrough["F"] >= {"yC_in"}
    order = me_master.plan(me_master.CONNECTIONS, fmus)
    at = {(c[2], c[3]): i for i, c in enumerate(order)}
    read = {(c[0], c[1]): i for i, c in enumerate(order)}
    assert at[("contact", "yC_in")] < read[("contact", "F")]
    assert max(at[("vehicle", "y_wheel")], at[("vehicle", "v_wheel")]) < read[("vehicle", "F_wheel")]
    fmus["track"].feedthrough["z_rail"] = {"F_contact"}  # a track whose rail followed the force at once
    with pytest.raises(RuntimeError, match="algebraic loop"):
        me_master.plan(me_master.CONNECTIONS, fmus)


@needs_fmus
def test_me_run_matches_the_reference(rough):
    """The three FMUs in one solver (DOP853, rtol 1e-8) rolling over the roughness: the force within
    FORCE_PER_RTOL rtol of the wheel load (the co-simulation's recommended coupling: 0.29 % at
    1e-5 s, test_vehicle_track.py), the impulse to rtol, and no energy created at the ports (both
    sides of each port see the same values: what is left is rounding)."""
    path, T, system, sol = rough
    r = me_master.run(T, RTOL, profile=path)
    assert r["time_events"] > 100  # the kinks of the rolling constraint over 27 ms of roughness
    assert force_error(r, sol, system) < FORCE_PER_RTOL * RTOL
    J_ref = sol.state(T)[reference.J, 0]
    assert abs(r["J"][-1] - J_ref) < 10 * RTOL * J_ref
    D_ref = sol.state(T)[reference.D, 0]
    assert abs(r["E_coupling"][-1]) < 1e-9 * D_ref
    D = r["track.W_dissipated"][-1] + r["vehicle.W_dissipated"][-1]
    assert abs(D - D_ref) < 100 * RTOL * D_ref


@needs_fmus
def test_me_run_meets_the_contact_losses_and_onsets():
    """The contact FMU's internal harmonic (a = 300 um at 300 Hz) lifts the wheel off the rail five
    times in 20 ms: the state events (onsets the FMU takes two or three events for, a few
    nanoseconds apart, merged) are the reference's contact changes, and the force stays within
    FORCE_PER_RTOL rtol of the wheel load."""
    exc, T = (300e-6, 300.0), 0.02
    system = reference.default_system(None, T, excitation=exc)
    sol = reference.simulate(system, T, rtol=1e-10)
    r = me_master.run(T, RTOL, excitation=exc)
    ref_times = np.unique(np.round([t for t, _ in sol.events], 9))
    me_times = r["state_events"][np.concatenate([[True], np.diff(r["state_events"]) > 1e-6])]
    assert len(ref_times) == 10 and len(me_times) == len(ref_times)
    assert np.max(np.abs(me_times - ref_times)) < 1e-8
    assert force_error(r, sol, system) < FORCE_PER_RTOL * RTOL


@needs_fmus
@pytest.mark.parametrize("broken", ["rail not connected", "F_mean to the track"])
def test_me_run_fails_on_a_broken_coupling(rough, broken):
    """The same check fails when a coupling is broken: the contact FMU not told where the rail is,
    or the track handed the co-simulation's F_mean (in Model Exchange a mean since the last
    completed integrator step, not the force of now)."""
    path, T, system, sol = rough
    C = me_master.CONNECTIONS
    conns = {"rail not connected": [c for c in C if c[3] != "yC_in"],
             "F_mean to the track": [c if c[3] != "F_contact" else ("contact", "F_mean", "track", "F_contact")
                                     for c in C]}[broken]
    r = me_master.run(T, RTOL, profile=path, connections=conns)
    assert force_error(r, sol, system) > 100 * FORCE_PER_RTOL * RTOL
