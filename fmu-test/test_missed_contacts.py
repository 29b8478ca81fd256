"""No contact is passed over: a mass that reaches a surface is in contact with it, under every solver.

A sphere rattling in a narrow clearance (the upper stop 0.1 and 0.2 mm above the lower surface, the
platform shaken 1 mm at 50 Hz under gravity) leaves the upper surface by a release of the damped laws
(the force reaches zero while the indentation is still positive) and comes back after a flight of a
few micrometres. The onset guard after such a release must see that return: a mass that is inside
a surface while its contact is free feels no force there, the contact's elastic energy then counts a
compression nothing made, and the dissipated work falls below zero. Both are physically impossible,
so these checks need no reference: no sample has a free contact indented more than 5 um (the
largest indentation at which a release of these laws leaves the surface here is 1.1 um), and the
dissipated work never decreases by more than the tolerance of its integration (rtol times its
largest value: the damping's work is an integrated state).
"""
import numpy as np
import pytest
from fmpy import simulate_fmu

SPHERE = dict(R1=0.01, R2=0.0, m=0.03288, Y=1e9, P=0.0, g=9.81, init=2, a=1e-3, f=50.0, e_restitution=0.6)
LAWS = {"hertz_damped exact": dict(contact_model=4, damping_formula=1),
        "hertz_damped hunt_crossley": dict(contact_model=4, damping_formula=2),
        "linear": dict(contact_model=5)}
SOLVERS = {"bdf": 1, "adams": 2, "dop853": 3, "auto": 4}
FREE_INDENTATION_MAX = 5e-6  # m
RTOL = 1e-8


@pytest.mark.timeout(300)
@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("gap", [1e-4, 2e-4])
def test_a_mass_rattling_in_a_narrow_clearance_never_passes_into_a_surface(fmu_path, law, solver, gap):
    params = dict(SPHERE, upper_stop=True, gap=gap, solver=SOLVERS[solver], **LAWS[law])
    r = simulate_fmu(fmu_path, start_values=params, stop_time=0.05, output_interval=1e-5, relative_tolerance=RTOL,
                     output=["y", "yC", "delta", "mode", "mode_upper", "n_impacts_upper", "W_dissipated"])
    delta_upper = r["y"] - (r["yC"] + gap)
    inside_upper = (r["mode_upper"] == 0) & (delta_upper > FREE_INDENTATION_MAX)
    inside_lower = (r["mode"] == 0) & (r["delta"] > FREE_INDENTATION_MAX)
    assert r["n_impacts_upper"][-1] >= 5, "the scene must rattle against the upper surface"
    assert not inside_upper.any(), (
        f"the mass is {delta_upper[inside_upper].max():.3g} m inside the upper surface with its contact free, "
        f"first at t = {r['time'][inside_upper][0]:.6g} s")
    assert not inside_lower.any(), f"the mass is inside the lower surface with its contact free at t = {r['time'][inside_lower][0]:.6g} s"
    W = r["W_dissipated"]
    assert np.diff(W).min() >= -RTOL * W.max(), f"the dissipated work falls by {-np.diff(W).min():.3g} J, to {W.min():.3g} J"
