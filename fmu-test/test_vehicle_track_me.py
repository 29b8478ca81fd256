"""The vehicle-track example in Model Exchange (examples/vehicle-track/me_master.py): the three FMUs
integrated together by one solver (SciPy's solve_ivp) against the monolithic reference, and with each
law of the guide to the laws against the co-simulation. (The companion FMUs' Model Exchange interface
alone: test_me_vehicle_track.py.)"""
from types import SimpleNamespace

import numpy as np
import pytest
from fmpy import read_model_description

from conftest import BUILD, FMU
from vibroimpact import laws_guide as G

# the example's modules, importable through pytest.ini's pythonpath
import me_master
import parameters
import reference
import roughness
from test_vehicle_track import needs_fmus, rough  # noqa: F401 (rough: the fixture, shared)

# ---- the coupled system ------------------------------------------------------------------------------

# Tolerance of the force against the reference, from the solver's relative tolerance: the positions
# carry a local error of about rtol |y| (|y| = 3.7 mm, the wheel's static position: the track's
# deflection under the wheel), and the Hertz force F = K delta^1.5 moves by 1.5 F / delta per metre
# of indentation (delta = 73.7 um at the static wheel load W): 1.5 rtol |y| / delta = 75 rtol of W
# per step. The local errors add up over the run: allow thirty of them. (Measured: 80 to 350 rtol at
# rtol 1e-8, examples/vehicle-track/README.md.)
RTOL = 1e-8
ACCUMULATION = 30.0


def force_tolerance(system, rtol=RTOL):
    """The bound on max |F - F_ref| / W at the solver tolerance rtol, from the static state."""
    y = abs(system.static_state()[reference.YW])
    delta = (system.W / system.K) ** (2.0 / 3.0)
    return ACCUMULATION * 1.5 * rtol * y / delta


def dissipation_tolerance(system, sol, T, rtol=RTOL):
    """The bound on |D - D_ref| / D_ref, D = int of sum c dv^2 over the dampers, from the force's: the
    damper velocities answer the dynamic force F - W, so a force error e W moves them by e W / |F - W|
    relative and D by twice that; e = force_tolerance, |F - W| its rms over the reference run. (The
    master's D takes no part in step size control; its error follows the force's.)"""
    t = np.linspace(0.0, T, 4001)
    dynamic = float(np.sqrt(np.mean((sol.force(t) - system.W) ** 2)))
    return 2.0 * force_tolerance(system, rtol) * system.W / dynamic


def force_error(r, sol, system):
    return float(np.max(np.abs(r["contact.F"] - sol.force(r["t"]))) / system.W)


@needs_fmus
def test_me_plan_sets_inputs_before_the_outputs_that_depend_on_them():
    """The evaluation order follows ModelStructure: in Model Exchange the contact force F depends on
    yC_in and vC_in at once and the suspension force on the wheel's position and velocity, so yC_in
    and vC_in are set before F is read and y_wheel, v_wheel before F_wheel; a dependency cycle is
    refused."""
    mds = {n: read_model_description(str(p)) for n, p in
           (("contact", FMU), ("track", BUILD / "Track.fmu"), ("vehicle", BUILD / "Vehicle.fmu"))}
    fmus = {n: SimpleNamespace(feedthrough=me_master.feedthrough(md)) for n, md in mds.items()}
    assert fmus["contact"].feedthrough["F"] >= {"yC_in", "vC_in"}
    order = me_master.plan(me_master.CONNECTIONS, fmus)
    at = {(c[2], c[3]): i for i, c in enumerate(order)}
    read = {(c[0], c[1]): i for i, c in enumerate(order)}
    assert max(at[("contact", "yC_in")], at[("contact", "vC_in")]) < read[("contact", "F")]
    assert max(at[("vehicle", "y_wheel")], at[("vehicle", "v_wheel")]) < read[("vehicle", "F_wheel")]
    fmus["track"].feedthrough["z_rail"] = {"F_contact"}  # a track whose rail followed the force at once
    with pytest.raises(RuntimeError, match="algebraic loop"):
        me_master.plan(me_master.CONNECTIONS, fmus)


@needs_fmus
def test_me_run_matches_the_reference(rough):
    """The three FMUs in one solver (DOP853, rtol 1e-8) rolling over the roughness: the force within
    force_tolerance (2.2e-5 of the wheel load) (the co-simulation's recommended coupling: 0.29 % at
    1e-5 s, test_vehicle_track.py), the impulse to rtol (ten times: it adds up over the run) and the
    work dissipated in the dampers within dissipation_tolerance (1.5e-4)."""
    path, T, system, sol = rough
    r = me_master.run(T, path, rtol=RTOL)
    assert r["time_events"] > 100  # the kinks of the rolling constraint over 27 ms of roughness
    assert force_error(r, sol, system) < force_tolerance(system)
    J_ref = sol.state(T)[reference.J, 0]
    assert abs(r["J"][-1] - J_ref) < 10 * RTOL * J_ref
    D_ref = sol.state(T)[reference.D, 0]
    assert abs(r["D"][-1] - D_ref) < dissipation_tolerance(system, sol, T) * D_ref


@needs_fmus
def test_me_run_meets_the_contact_losses_and_onsets():
    """The contact FMU's internal harmonic (a = 300 um at 300 Hz) lifts the wheel off the rail five
    times in 20 ms: the state events (onsets the FMU takes two or three events for, a few
    nanoseconds apart, merged) are the reference's contact changes, and the force stays within
    force_tolerance."""
    exc, T = (300e-6, 300.0), 0.02
    system = reference.default_system(None, T, excitation=exc)
    sol = reference.simulate(system, T, rtol=1e-10)
    r = me_master.run(T, excitation=exc, rtol=RTOL)
    ref_times = np.unique(np.round([t for t, _ in sol.events], 9))
    me_times = r["state_events"][np.concatenate([[True], np.diff(r["state_events"]) > 1e-6])]
    assert len(ref_times) == 10 and len(me_times) == len(ref_times)
    assert np.max(np.abs(me_times - ref_times)) < 1e-8
    assert force_error(r, sol, system) < force_tolerance(system)


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
    r = me_master.run(T, path, rtol=RTOL, connections=conns)
    assert force_error(r, sol, system) > 100 * force_tolerance(system)


# ---- every law of the guide: the Model Exchange master against its co-simulation --------------------

FLOOR = 5e-4        # W: the runs' own errors: Model Exchange's mean force at rtol 1e-8 is 1e-4 W from the
                    # monolithic reference over 0.15 s, the co-simulation's at 1e-6 s 2e-4 W
                    # (examples/vehicle-track/README.md); here 4.8e-5 to 2.5e-4 W apart
FIRST_ORDER = 0.7   # at least first order in the step: halving it takes 0.7 of the difference at most
AT_MOST = 0.05      # W: the largest difference at 1e-6 s (measured 0.029, johnson)


@pytest.fixture(scope="module")
def guide_scene(tmp_path_factory):
    """The guide's vehicle-track roughness in a file."""
    path = tmp_path_factory.mktemp("guide_vt") / "roughness.txt"
    roughness.write(path, *roughness.profile(**parameters.ROUGHNESS))
    return str(path.resolve())


@needs_fmus
@pytest.mark.timeout(600)
@pytest.mark.parametrize("variant", list(G.VARIANTS))
def test_me_master_agrees_with_the_co_simulation_for_every_law(fmu_path, guide_scene, variant):
    """Each law of the guide (vibroimpact laws) in its vehicle-track scene (0.03 s from x0 = 1 m): the
    Model Exchange master (DOP853, rtol 1e-8, the rail's velocity in vC_in) runs to the end, and the
    recommended co-simulation (GS ramp, F_mean) approaches it as the step shrinks
    (laws_guide.vt_agreement: the mean force over 10 us, an impulse, so that a force that jumps, as the
    paper's Johnson unloading does at a turning point, weighs by how long it lasts).

    Measured at 1e-6 s (units of W, doc/choosing.md): 4.8e-5 to 2.5e-4 for hertz, hunt_crossley,
    thornton, lepp, johnson_moving and johnson_continuous, the runs' own errors (FLOOR); 7.9e-3
    (hertz_damped), 8.6e-3 (linear) and 2.9e-2 (johnson), halved or nearly from 2e-6 s (1.6e-2,
    1.7e-2, 4.7e-2): first order in the step. The co-simulation holds vC_in over a step, so a damping
    force lags the rail's velocity; and where the rail's position is re-set below its extrapolation at
    a communication point, Johnson unloads for a few nanoseconds with the paper's force drop. Without
    vC_in in the Model Exchange master six laws differ by 0.09 to 145 W."""
    p = dict(profile_file=guide_scene, x0=G.VT_X0, **G.VARIANTS[variant])
    if variant == "linear":
        p["k_spring"] = G.k_spring_for("vehicle_track")
    d = G.vt_agreement(fmu_path, p, G.STOP["vehicle_track"])
    fine, coarse = (d[f"me_vs_cs_{h:g}"] for h in sorted(G.AGREEMENT_STEPS))
    assert fine <= max(FLOOR, FIRST_ORDER * coarse), d
    assert fine < AT_MOST, d
