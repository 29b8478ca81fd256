"""The independent reference of the two-sided contact (vibroimpact.reference.two_sided: a mass between
the platform and a second surface at yC + gap) against a closed form, a mirror image and the one-sided
reference.

The closed form: a sphere in a cavity shaken a (cos(2 pi f t) - 1), without gravity or load, with
instantaneous impacts of restitution e, has a periodic motion of two impacts per cycle, one on each
wall, half a period apart, each at the free-flight speed u = (1+e)/(1-e) a w cos(phi), where the phase
phi solves gap = 2 a sin(phi) + (1+e)/(1-e) a pi cos(phi) (between impacts the sphere covers u pi/w
while the cavity moves by -2 a sin(phi)). The finite contact time of a Hertz contact shifts it by
about the ratio of the contact time to the half period."""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from vibroimpact.reference import model as M
from vibroimpact.reference import two_sided as T

# a steel sphere of radius 10 mm (32.88 g) between two steel planes, no gravity, no load
SPHERE = dict(m=0.03288, P=0.0, g=0.0, R1=0.01, R2=0.0, contact_model=M.HERTZ_DAMPED, init=M.TOUCHING)


def periodic_orbits(e, a, f, gap):
    """[(phi, u, y0, v0)] of the closed form's two-impact orbits: the phase, the free-flight speed and
    the orbit's state at t = 0 (in flight up from the lower wall it left at w t1 = phi - pi/2)."""
    w, r = 2 * math.pi * f, (1 + e) / (1 - e)
    gap_of = lambda phi: 2 * a * math.sin(phi) + r * a * math.pi * math.cos(phi) - gap
    orbits = []
    for lo, hi in ((-math.pi / 2, 0.0), (0.0, math.pi / 2)):
        phi = brentq(gap_of, lo, hi, xtol=1e-15)
        u, t1 = r * a * w * math.cos(phi), (phi - math.pi / 2) / w
        orbits.append((phi, u, a * (math.cos(w * t1) - 1) - u * t1, u))
    return orbits


@pytest.mark.timeout(300)
@pytest.mark.parametrize("e, gap", [(0.8, 0.02), (0.6, 0.01)])
def test_a_shaken_cavity_settles_into_the_closed_form_orbit(e, gap):
    """Started on the closed form's orbit of phi < 0 (the other one, phi > 0, decays: checked below),
    the sphere keeps two impacts per cycle, alternating walls half a period apart, at a free-flight
    speed within 1 % of u (the contact time, about 60 us against the half period of 10 ms)."""
    a, f = 1e-3, 50.0
    (phi, u, y0, v0), _ = periodic_orbits(e, a, f, gap)
    r = T.simulate(dict(SPHERE, e_restitution=e, a=a, f=f), gap, t_end=0.4, rtol=1e-9, y0=y0, v0=v0)
    lower, upper = (np.array(r.impacts[s]) for s in (T.LOWER, T.UPPER))
    assert len(lower) == len(upper) == round(0.4 * f), (lower, upper)
    half, t1 = 0.5 / f, (phi - math.pi / 2) / (2 * math.pi * f)  # the closed form's impacts on the lower wall
    assert np.all(np.abs(lower - t1 - np.round((lower - t1) * f) / f) < 0.02 * half), lower
    assert np.all(np.abs(lower - upper - half) < 0.02 * half), lower - upper  # the upper wall first: in flight up
    for side in (T.LOWER, T.UPPER):
        speeds = r.free_flight_speeds(side)
        assert speeds[-1] == pytest.approx(u, rel=1e-2), (side, speeds[-3:], u)
        assert speeds[-1] == pytest.approx(speeds[-2], rel=1e-5), speeds[-3:]  # settled


@pytest.mark.timeout(300)
def test_the_other_orbit_of_the_closed_form_decays():
    """The orbit of phi > 0 is unstable: started on it, the sphere leaves it within a few cycles (its
    speeds spread by more than 10 % of u), so the test above checks the one a cavity settles into."""
    a, f, gap, e = 1e-3, 50.0, 0.02, 0.8
    _, (phi, u, y0, v0) = periodic_orbits(e, a, f, gap)
    r = T.simulate(dict(SPHERE, e_restitution=e, a=a, f=f), gap, t_end=0.3, rtol=1e-9, y0=y0, v0=v0)
    speeds = r.free_flight_speeds(T.LOWER) + r.free_flight_speeds(T.UPPER)
    assert max(abs(s - u) for s in speeds) > 0.1 * u, (speeds, u)


@pytest.mark.timeout(300)
@pytest.mark.parametrize("law", [M.JOHNSON, M.HERTZ_DAMPED, M.LEPP])
def test_the_upper_contact_is_the_lower_one_mirrored(law):
    """A mass falling onto the lower surface under g, and the same mass falling up onto the upper
    surface under -g from the mirrored start: the same motion mirrored about the middle of the gap,
    with the same force on each side (plastic memory and damping included), to the integration's
    tolerance."""
    gap, drop = 0.02, 0.005
    p = dict(m=0.03288, P=0.0, R1=0.01, R2=0.0, contact_model=law, Y=1e9, init=M.TOUCHING)
    t = np.linspace(0.0, 0.15, 1501)
    down = T.simulate(dict(p, g=9.81), gap, t_end=0.15, rtol=1e-10, t_eval=t, y0=drop)
    up = T.simulate(dict(p, g=-9.81), gap, t_end=0.15, rtol=1e-10, t_eval=t, y0=gap - drop)
    assert len(down.impacts[T.LOWER]) >= 2 and not down.impacts[T.UPPER], down.impacts
    assert len(up.impacts[T.UPPER]) == len(down.impacts[T.LOWER]) and not up.impacts[T.LOWER], up.impacts
    assert np.allclose(up.y, gap - down.y, rtol=0.0, atol=1e-9), np.max(np.abs(up.y - (gap - down.y)))
    assert np.allclose(up.impacts[T.UPPER], down.impacts[T.LOWER], rtol=0.0, atol=1e-9)
    # A sample just after a contact's beginning sees the force rise at up to about 1e7 N/s (hertz_damped's
    # damping at the impact speed), so the impact times' difference (5e-11 s at rtol 1e-10) moves it by up
    # to 1.6e-6 of the largest force: 1e-5 of it leaves a margin of 6.
    F_scale = np.max(down.F_lower)
    assert np.allclose(up.F_upper, down.F_lower, rtol=0.0, atol=1e-5 * F_scale), \
        np.max(np.abs(up.F_upper - down.F_lower)) / F_scale
    assert np.all(up.F_lower == 0.0) and np.all(down.F_upper == 0.0)


@pytest.mark.timeout(300)
def test_an_upper_surface_out_of_reach_changes_nothing():
    """The paper's Johnson scene (bouncing on the harmonic platform, a = 20 um at 560 Hz) with an upper
    surface 10 mm above, which the mass never reaches: the one-sided reference's motion."""
    p = dict(a=2e-5, f=560.0)
    t = np.linspace(0.0, 0.02, 401)
    one = M.simulate(p, 0.02, rtol=1e-10, t_eval=t)
    two = T.simulate(p, 0.01, t_end=0.02, rtol=1e-10, t_eval=t)
    assert one.n_impacts_total >= 3 and len(two.impacts[T.LOWER]) == one.n_impacts_total and not two.impacts[T.UPPER]
    assert np.allclose(two.y, one.y, rtol=0.0, atol=1e-10), np.max(np.abs(two.y - one.y))
    assert np.allclose(two.F_lower, one.F, rtol=0.0, atol=1e-6 * np.max(one.F))


def test_a_clearance_that_is_not_positive_is_refused():
    for gap in (0.0, -1e-3, float("nan")):
        with pytest.raises(ValueError, match="gap"):
            T.contacts({}, gap)
