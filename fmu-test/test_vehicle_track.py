"""The vehicle-track example (examples/vehicle-track): the companion FMUs against closed forms, the
roughness profile against its spectrum, the monolithic reference against its own checks, and the
co-simulation (fmpy master and libcosim) against the reference."""
import math
import pathlib
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu
from scipy.linalg import expm

from conftest import BUILD, FMU, require_module

# the example's modules, importable through pytest.ini's pythonpath
import master
import parameters
import reference
import roughness

EXAMPLE = pathlib.Path(__file__).resolve().parent.parent / "examples" / "vehicle-track"

TRACK, VEHICLE = BUILD / "Track.fmu", BUILD / "Vehicle.fmu"
P_T, P_V = parameters.TRACK, parameters.VEHICLE
# The companion FMUs: every build of the tests makes them; missing ones fail (conftest.companion_fmus).
needs_fmus = pytest.mark.usefixtures("companion_fmus")


@pytest.fixture(scope="module", params=["Track", "Vehicle"])
def companion(request):
    path = BUILD / f"{request.param}.fmu"
    if not path.exists():
        pytest.fail(f"{path} is missing: build with cmake")
    return request.param, path


@needs_fmus
def test_companion_xml_matches_its_table_and_validates(companion):
    from test_interface import check_xml_matches_c_table
    name, path = companion
    check_xml_matches_c_table(read_model_description(str(path)), f"{name}_dump_variables")
    assert validate_fmu(str(path)) == []


def run_track(load, t_end, h, start_values=None):
    """Track.fmu driven by F_contact = load(t) (held over each step); outputs at every step."""
    t = np.arange(0.0, t_end + h / 2, h)
    sig = np.array([(tt, load(tt)) for tt in t], dtype=[("time", float), ("F_contact", float)])
    return simulate_fmu(str(TRACK), stop_time=t[-1], output_interval=h, input=sig, start_values=start_values or {},
                        output=["z_rail", "v_rail", "z_sleeper", "v_sleeper", "E", "W_dissipated", "W_in",
                                "k_static", "f1", "f2"])


def track_matrices(p):
    """x = (z_r, v_r, z_s, v_s): x' = A x + b F (written here from the equations of track.c's header)."""
    mr, ms, kp, cp, kb, cb = p["m_rail"], p["m_sleeper"], p["k_pad"], p["c_pad"], p["k_ballast"], p["c_ballast"]
    A = np.array([[0, 1, 0, 0],
                  [-kp / mr, -cp / mr, kp / mr, cp / mr],
                  [0, 0, 0, 1],
                  [kp / ms, cp / ms, -(kp + kb) / ms, -(cp + cb) / ms]])
    b = np.array([0, -1 / mr, 0, 0])
    return A, b


@needs_fmus
def test_track_static_deflection_and_frequencies():
    W = 66217.5
    r = run_track(lambda t: W, 0.01, 1e-4)
    kp, kb = P_T["k_pad"], P_T["k_ballast"]
    assert r["z_sleeper"][0] == pytest.approx(-W / kb, rel=1e-14)
    assert r["z_rail"][0] == pytest.approx(-W / kp - W / kb, rel=1e-14)
    # at rest it stays there
    assert np.max(np.abs(r["z_rail"] - r["z_rail"][0])) < 1e-12 * W / kb
    assert r["k_static"][0] == pytest.approx(1 / (1 / kp + 1 / kb), rel=1e-14)
    # undamped natural frequencies: the generalized eigenproblem K phi = w^2 M phi
    K = np.array([[kp, -kp], [-kp, kp + kb]])
    M = np.diag([P_T["m_rail"], P_T["m_sleeper"]])
    w = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real))
    assert r["f1"][0] == pytest.approx(w[0] / (2 * np.pi), rel=1e-12)
    assert r["f2"][0] == pytest.approx(w[1] / (2 * np.pi), rel=1e-12)


@needs_fmus
def test_track_step_response_matches_the_matrix_exponential():
    """A load step from the static state under F0 to F1: x(t) = x1 + expm(A t) (x0 - x1). (The
    error grows with the tolerance: 1e-5 of the swing at rtol 1e-8, 5000 steps.)"""
    F0, F1, h = 60e3, 70e3, 1e-5
    r = run_track(lambda t: F0 if t < h / 2 else F1, 0.05, h, {"rtol": 1e-10})
    A, b = track_matrices(P_T)
    x_static = lambda F: -np.linalg.solve(A, b * F)  # noqa: E731
    x0, x1 = x_static(F0), x_static(F1)
    assert r["z_rail"][0] == pytest.approx(x0[0], rel=1e-13)
    t = r["time"][1:] - h  # the new load acts from the end of the first step
    exact = np.array([x1 + expm(A * tt) @ (x0 - x1) for tt in t])
    swing = np.ptp(exact[:, 0])
    assert np.max(np.abs(r["z_rail"][1:] - exact[:, 0])) < 1e-6 * swing
    assert np.max(np.abs(r["v_sleeper"][1:] - exact[:, 3])) < 1e-6 * np.ptp(exact[:, 3])


@needs_fmus
def test_track_energy_balance():
    """Under a varying load the work the dampers dissipated (W_dissipated = W_in - (E - E(0)), with
    W_in the exact work of the held load) equals the integral of the damper power
    c_pad (v_r - v_s)^2 + c_ballast v_s^2 over the sampled velocities (trapezoid rule, 1e-5 s)."""
    r = run_track(lambda t: 66e3 + 20e3 * math.sin(2 * math.pi * 300 * t) + 10e3 * math.sin(2 * math.pi * 41 * t),
                  0.05, 1e-5)
    power = P_T["c_pad"] * (r["v_rail"] - r["v_sleeper"]) ** 2 + P_T["c_ballast"] * r["v_sleeper"] ** 2
    dissipated = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(r["time"]))])
    assert dissipated[-1] > 1.0  # the dampers work
    assert np.max(np.abs(r["W_dissipated"] - dissipated)) < 1e-3 * dissipated[-1]
    # W_in is the work of the held load: -F (z_r(end) - z_r(start)) summed over the steps
    F = np.array([66e3 + 20e3 * math.sin(2 * math.pi * 300 * t) + 10e3 * math.sin(2 * math.pi * 41 * t)
                  for t in r["time"][:-1]])
    assert r["W_in"][-1] == pytest.approx(np.sum(-F * np.diff(r["z_rail"])), rel=1e-9)


def run_vehicle(y_wheel, v_wheel, t_end, h, start_values=None):
    t = np.arange(0.0, t_end + h / 2, h)
    sig = np.array([(tt, y_wheel(tt), v_wheel(tt)) for tt in t],
                   dtype=[("time", float), ("y_wheel", float), ("v_wheel", float)])
    return simulate_fmu(str(VEHICLE), stop_time=t[-1], output_interval=h, input=sig, start_values=start_values or {},
                        output=["F_wheel", "z_body", "v_body", "E", "W_dissipated", "W_in", "f_body"])


@needs_fmus
def test_vehicle_static_start_and_free_vibration():
    """The body starts on the wheel under m g; a sudden wheel drop d then gives the damped
    oscillator z'' + 2 zeta w z' + w^2 z = w^2 d from z = 0 (closed form). (At rtol 1e-8 the error
    after 5000 steps is 5e-5 of d.)"""
    m, k, c, g = P_V["m_body"], P_V["k_susp"], P_V["c_susp"], P_V["g"]
    d, h = -1e-3, 1e-4
    r = run_vehicle(lambda t: 0.0 if t < h / 2 else d, lambda t: 0.0, 0.5, h, {"rtol": 1e-10})
    assert r["F_wheel"][0] == pytest.approx(-m * g, rel=1e-15)
    assert r["z_body"][0] == 0.0
    w, zeta = math.sqrt(k / m), c / (2 * math.sqrt(k * m))
    wd = w * math.sqrt(1 - zeta ** 2)
    t = r["time"][1:] - h
    z = d + np.exp(-zeta * w * t) * (-d * np.cos(wd * t) - d * zeta * w / wd * np.sin(wd * t))
    assert np.max(np.abs(r["z_body"][1:] - z)) < 1e-6 * abs(d)
    assert r["f_body"][0] == pytest.approx(w / (2 * math.pi), rel=1e-14)


@needs_fmus
def test_vehicle_wheel_inputs_feed_through_and_energy_balances():
    """F_wheel depends on the wheel inputs at once (declared in ModelStructure). A wheel at rest
    that starts to move at constant velocity is followed exactly by the held position and velocity
    (y + v (t - t_set)), so E + W_dissipated - W_in stays at its start value while the damper
    works on the body's transient."""
    md = read_model_description(str(VEHICLE))
    deps = {u.variable.name: sorted(d.name for d in (u.dependencies or [])) for u in md.outputs}
    # the inputs at once (and, in Model Exchange, the states z_body, v_body)
    assert deps["F_wheel"] == ["v_body", "v_wheel", "y_wheel", "z_body"] and deps["z_body"] == ["z_body"]
    v, h = 0.01, 1e-3
    r = run_vehicle(lambda t: v * max(t - h, 0.0), lambda t: v if t > h / 2 else 0.0, 1.0, h, {"rtol": 1e-8})
    balance = r["E"] + r["W_dissipated"] - r["W_in"] - r["E"][0]
    assert r["W_dissipated"][-1] > 0.1
    # the wheel's rise moves 560 J through W_in (lifting the sprung weight): the balance holds to
    # 1e-7 of that (1e-5 of the dissipated work) at rtol 1e-8
    assert np.max(np.abs(balance)) < 1e-7 * np.max(np.abs(r["W_in"]))


def test_roughness_has_its_spectrum_and_is_seeded():
    x, h = roughness.profile(**parameters.ROUGHNESS)
    x2, h2 = roughness.profile(**parameters.ROUGHNESS)
    assert np.array_equal(h, h2)
    assert np.all(h[x <= 1.0] == 0.0)  # the wheel starts on a flat rail
    # the sinusoids carry the band levels exactly (mean square of a sinusoid: amplitude^2 / 2) ...
    k, amp, _, of_band = roughness.components(parameters.ROUGHNESS["level_db"], parameters.ROUGHNESS["seed"])
    for lam, level in roughness.ISO3095_LIMIT_DB.items():
        band = of_band == lam
        edges = 2 * np.pi / (lam * roughness.BAND_HALF_WIDTH), 2 * np.pi * roughness.BAND_HALF_WIDTH / lam
        assert np.all((k[band] >= edges[0]) & (k[band] <= edges[1]))
        if lam >= 0.01:
            expected = 1e-6 * 10 ** ((level + parameters.ROUGHNESS["level_db"]) / 20)
            assert np.sqrt(np.sum(amp[band] ** 2) / 2) == pytest.approx(expected, rel=1e-12), lam
        else:
            assert not band.any()
    # ... and the written profile shows them: one-third octave band levels of the sampled profile
    # within 3 dB for the bands with many wavelengths in the 4.7 m (10 cm and shorter)
    rough = x > 1.3
    levels = roughness.band_levels(x[rough], h[rough], lo=0.01, hi=0.1)
    for lam, level in levels.items():
        assert abs(level - (roughness.ISO3095_LIMIT_DB[lam] + parameters.ROUGHNESS["level_db"])) < 3.0, lam


def test_reference_rolling_constraint_is_the_definition():
    """yb(x) = max over |s - x| <= R of [h(s) + sqrt(R^2 - (x - s)^2)] - R, by brute force on a
    dense sampling of the piecewise-linear profile, against the exact vertex/segment evaluation."""
    x, h = roughness.profile(**parameters.ROUGHNESS)
    R = parameters.WHEEL["R1"]
    P = reference.Profile(x, h, R)
    for xx in np.random.default_rng(2).uniform(1.2, 4.0, 15):
        # a dense sampling of s that contains every vertex in reach (where a maximum often is)
        s = np.union1d(np.linspace(xx - R, xx + R, 400001), x[np.abs(x - xx) < R])
        brute = np.max(np.interp(s, x, h) + np.sqrt(np.maximum(R * R - (xx - s) ** 2, 0.0))) - R
        # the sampled maximum is a lower bound, short of a maximum inside a segment by at most
        # (spacing)^2 / (2 R) = 6e-12 m
        assert 0.0 <= P(xx)[0] - brute < 1e-11


@pytest.fixture(scope="module")
def harmonic_reference():
    exc, T = (20e-6, 600.0), 0.03
    system = reference.default_system(None, T, excitation=exc)
    return exc, T, system, reference.simulate(system, T, rtol=1e-10)


def test_reference_restarts_on_the_side_an_event_leads_to(monkeypatch):
    """The reference locates a contact loss or onset with brentq and restarts there; delta at the
    located time is zero to rounding and can keep the old sign (it did with another BLAS kernel:
    the same loss was found again and again at one instant, 10^7 times). Here every located time is
    moved back to where delta still has the old sign: the run must meet the same ten events, at the
    same times within 1e-8 s (the restarts change the steps after them; the Model Exchange run is held
    to the same agreement with the reference, test_vehicle_track_me.py)."""
    exc, T = (300e-6, 300.0), 0.02
    system = reference.default_system(None, T, excitation=exc)
    plain = reference.simulate(system, T, rtol=1e-8, max_steps=200)  # 11 pieces between events

    def late_side(f, a, b, **kw):
        r = reference_brentq(f, a, b, **kw)
        for _ in range(64):  # back to the old side of the crossing
            if (f(r) > 0.0) == (f(a) > 0.0):
                return r
            r = max(a, np.nextafter(r, -np.inf))
        return a

    reference_brentq = reference.brentq
    monkeypatch.setattr(reference, "brentq", late_side)
    moved = reference.simulate(system, T, rtol=1e-8, max_steps=200)
    assert len(plain.events) == len(moved.events) == 10
    assert [k for _, k in moved.events] == [k for _, k in plain.events]
    assert np.max(np.abs(np.array([t for t, _ in moved.events]) - [t for t, _ in plain.events])) < 1e-8


def test_reference_energy_balance_and_convergence(harmonic_reference):
    exc, T, system, sol = harmonic_reference
    t = np.linspace(0, T, 301)
    assert np.max(np.abs(sol.energy_residual(t))) < 1e-6 * sol.state(T)[reference.D, 0]
    loose = reference.simulate(system, T, rtol=1e-7)
    assert np.max(np.abs(loose.force(t) - sol.force(t))) < 1e-5 * system.W


def assert_contact_has(*names):
    """The contact FMU's variables the coupling uses (F_mean and rolling): this FMU always has them."""
    md = read_model_description(str(FMU))
    have = {v.name for v in md.modelVariables}
    assert set(names) <= have, f"the contact FMU lacks {sorted(set(names) - have)}"


@pytest.fixture(scope="module")
def rough(tmp_path_factory):
    """The example's roughness profile in a file, and the reference over the first 40 ms (the
    roughness starts after 13 ms)."""
    path = tmp_path_factory.mktemp("profile") / "profile.txt"
    roughness.write(path, *roughness.profile(**parameters.ROUGHNESS))
    T = 0.04
    system = reference.default_system(str(path), T)
    return path, T, system, reference.simulate(system, T, rtol=1e-10)


@needs_fmus
def test_coupled_run_matches_the_reference(rough):
    """The recommended coupling (Gauss-Seidel vehicle -> contact -> track, the rail extrapolated
    with its velocity, F_mean to the track) at 1e-5 s against the monolithic reference, rolling
    over the roughness: measured 0.29 % and 0.19 % of the wheel load; the end-of-step force F and
    a held rail give 20 % and more (examples/vehicle-track/README.md)."""
    assert_contact_has("F_mean", "profile_file", "V", "x0")
    path, T, system, sol = rough
    h = 1e-5
    r = master.run(h, T, "gauss-seidel", ("vehicle", "contact", "track"), "F_mean", "ramp", profile=path)
    assert np.max(np.abs(r["contact.F"] - sol.force(r["t"]))) < 0.01 * system.W
    assert np.max(np.abs(r["contact.F_mean"][1:] - sol.mean_force(r["t"]))) < 0.01 * system.W
    # the track got the wheel's impulse, step by step: momentum is kept
    J_ref = sol.state(T)[reference.J, 0]
    assert abs(np.sum(r["F_to_track"][1:]) * h - J_ref) < 1e-4 * J_ref


@needs_fmus
@pytest.mark.parametrize("order", [("vehicle", "contact", "track"), ("vehicle", "track", "contact")])
def test_the_rail_velocity_as_vc_in_or_as_the_derivative_gives_the_same_numbers(rough, order):
    """rail_motion "ramp" (vC_in with velocity_input) and "derivative" (the derivative of yC_in) move the
    contact FMU's platform on the same straight line, extrapolated (contact first) or interpolated
    (track first), and give it the same rate: the same numbers, bit for bit, and the same energy
    bookkeeping (doc/model.md: vC_in carries yC_in through the step)."""
    path, _, _, _ = rough
    h, T = 1e-5, 0.02
    r = {m: master.run(h, T, "gauss-seidel", order, "F_mean", m, profile=path) for m in ("ramp", "derivative", "hold")}
    for key in ("contact.F", "contact.F_mean", "contact.y", "track.z_rail", "E_coupling"):
        assert np.array_equal(r["ramp"][key], r["derivative"][key]), key
    assert not np.array_equal(r["ramp"]["contact.F"], r["hold"]["contact.F"])


@needs_fmus
@pytest.mark.libcosim
@pytest.mark.parametrize("rail_motion", ["ramp", "hold"])
def test_libcosim_and_the_fmpy_master_agree(rough, rail_motion):
    """libcosim from OspSystemStructure.xml (the rail's velocity in vC_in, or without: "hold") and
    master.py with the same (Jacobi) scheme and rail motion."""
    require_module("libcosimpy")
    assert_contact_has("F_mean", "profile_file", "V", "x0", "vC_in")
    import cosim
    path, _, system, _ = rough
    h, T = 5e-6, 0.03
    rc = cosim.run(h, T, "F_mean", profile=path, rail_motion=rail_motion)
    rm = master.run(h, T, "jacobi", force="F_mean", rail_motion=rail_motion, profile=path)
    # The same scheme on the same FMUs: the importers differ only in how values travel (rounding), and
    # a multistep solver's step sequence reacts to that at its tolerance (rtol 1e-6), far below the
    # coupling error (about 1 % of W at this step): agreement to a tenth of the tolerance.
    tol = 0.1 * 1e-6
    assert np.max(np.abs(rc["contact.F"][1:] - rm["contact.F"][1:])) < tol * system.W
    assert np.max(np.abs(rc["track.z_rail"][1:] - rm["track.z_rail"][1:])) < 1e-12
    assert np.max(np.abs(rc["vehicle.F_wheel"][1:] - rm["vehicle.F_wheel"][1:])) < tol * system.W


def test_osp_file_agrees_with_parameters_and_the_master():
    root = ET.parse(EXAMPLE / "OspSystemStructure.xml").getroot()
    ns = {"o": "http://opensimulationplatform.com/MSMI/OSPSystemStructure"}
    values = {}
    for sim in root.iterfind("o:Simulators/o:Simulator", ns):
        for iv in sim.iterfind("o:InitialValues/o:InitialValue", ns):
            (v,) = list(iv)
            values[(sim.get("name"), iv.get("variable"))] = v.get("value")
    for name, value in parameters.WHEEL.items():
        assert float(values[("contact", name)]) == value, name
    # the coupling inputs start at the reference's static state
    system = reference.System()
    x = system.static_state()
    assert float(values[("contact", "yC_in")]) == pytest.approx(x[reference.ZR], rel=1e-12)
    assert float(values[("contact", "F_ext")]) == pytest.approx(-P_V["m_body"] * P_V["g"], rel=1e-12)
    assert float(values[("track", "F_contact")]) == pytest.approx(system.W, rel=1e-12)
    assert float(values[("vehicle", "y_wheel")]) == pytest.approx(x[reference.YW], rel=1e-12)
    assert values[("contact", "velocity_input")] == "true"  # the rail's velocity in vC_in (connected below)
    cons = [tuple(x for v in c.iterfind("o:Variable", ns) for x in (v.get("simulator"), v.get("name")))
            for c in root.iterfind("o:Connections/o:VariableConnection", ns)]
    assert sorted(cons) == sorted(master.CONNECTIONS)
