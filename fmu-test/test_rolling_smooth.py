"""Rolling over the cubic spline through a profile's rows (profile_interpolation = cubic, doc/rolling.md).

With a = 0 the FMU's output yC is the rigid constraint yb(x0 + V t) itself. Its references are
computed here, independently of the FMU's code: for a gentle sinusoid h = A cos(2 pi x / L) (curvature
A (2 pi / L)^2 below 1/R1) the offset of the sinusoid itself along its normal, the contact point found
by scipy's brentq, to within the spline's interpolation error 5/384 dx^4 max|h''''|; for a rough
table the definition max over s of [h(s) + sqrt(R1^2 - (x - s)^2)] - R1 evaluated by search over
scipy's CubicSpline through the same rows (the body bridging troughs sharper than itself). Then: the
polyline and the spline agree on a densely sampled shape as closely as the polyline's error dx^2/8
max|h''| allows, and so does the force; a smooth spline has no kink, so Model Exchange meets no time
event and co-simulation no restart; the FMI 3.0 FMU gives the FMI 2.0 numbers; FMU states roll back
to the bit; an unknown value is refused naming the variable and its items.
"""
import numpy as np
import pytest
from fmpy import simulate_fmu
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq, minimize_scalar

from conftest import BUILD
from test_rolling import R1, ROUND, fmu, instance, platform_samples, state_round_trip, write  # noqa: F401 (fmu)
from vibroimpact.me import run_me

LINEAR, CUBIC = 1, 2
L, A = 0.05, 2e-5  # the corrugation of the benchmark: curvature A (2 pi / L)^2 = 0.32/m < 1/R1 = 2.1/m
K = 2 * np.pi / L


def sinusoid_offset(at):
    """yb of h = A cos(K x) at the positions `at`: the contact point s solves s - R1 h'/sqrt(1 + h'^2) = x
    (brentq; the shift is at most R1 A K = 1.2 mm), yb = h(s) + R1 (1/sqrt(1 + h'^2) - 1)."""
    out = []
    for x in np.atleast_1d(at):
        def centre(s):
            d = -A * K * np.sin(K * s)
            return s - R1 * d / np.sqrt(1 + d * d) - x
        s = brentq(centre, x - 2e-3, x + 2e-3, xtol=1e-16, rtol=4 * np.finfo(float).eps)
        d = -A * K * np.sin(K * s)
        w = 1 + d * d
        out.append(A * np.cos(K * s) - R1 * d * d / (np.sqrt(w) * (np.sqrt(w) + 1)))
    return np.array(out)


def corrugation(tmp_path, rows_per_wavelength, waves=4, name="corrugation.txt"):
    x = np.linspace(0.0, waves * L, waves * (rows_per_wavelength - 1) + 1)
    h = A * np.cos(K * x)
    h[-1] = h[0]
    return x, h, write(tmp_path / name, x, h)


@pytest.mark.parametrize("periodic", [True, False])
def test_the_spline_of_a_gentle_sinusoid_gives_its_offset(fmu, tmp_path, periodic):  # noqa: F811
    rows = 41  # dx = 1.25 mm: the spline within 5/384 dx^4 A K^4 = 1.6e-10 m of the sinusoid
    x, h, path = corrugation(tmp_path, rows)
    x0, V = (0.0, 1.0) if periodic else (0.5 * L, 0.5)
    t, yC = platform_samples(fmu, dict(profile_file=path, V=V, x0=x0, profile_periodic=periodic,
                                       profile_interpolation=CUBIC, contact_model=1), 0.3 if periodic else 0.2, 300)
    dx = L / (rows - 1)
    bound = 5 / 384 * dx ** 4 * A * K ** 4
    err = np.abs(yC - sinusoid_offset(x0 + V * t)).max()
    assert err <= bound + ROUND, (err, bound)
    # and the polyline through the same rows is further off: its error dx^2/8 A K^2 = 2e-8 m
    t, yL = platform_samples(fmu, dict(profile_file=path, V=V, x0=x0, profile_periodic=periodic, contact_model=1),
                             0.3 if periodic else 0.2, 300)
    assert np.abs(yL - sinusoid_offset(x0 + V * t)).max() > 20 * bound


def definition(spline, lo, hi, at):
    """max over s in [lo, hi], |s - at| <= R1, of spline(s) + sqrt(R1^2 - (at - s)^2) - R1: the best of a
    grid of 4001 points, refined by a bounded search around it and around the ends."""
    a, b = max(lo, at - R1), min(hi, at + R1)
    s = np.linspace(a, b, 4001)

    def g(u):
        return float(spline(u)) + np.sqrt(max(R1 * R1 - (at - u) ** 2, 0.0)) - R1
    vals = spline(s) + np.sqrt(np.maximum(R1 * R1 - (at - s) ** 2, 0.0)) - R1
    i = int(np.argmax(vals))
    best = max(g(a), g(b))
    r = minimize_scalar(lambda u: -g(u), bounds=(s[max(i - 1, 0)], s[min(i + 1, len(s) - 1)]), method="bounded",
                        options=dict(xatol=1e-14))
    return max(best, -r.fun, vals[i])


def test_a_rough_spline_is_rolled_over_as_its_definition_says(fmu, tmp_path):  # noqa: F811
    """Random rows every 5 mm of up to 0.3 mm: the spline's troughs curve up to about 30/m, sharper than
    the body (1/R1 = 2.1/m), which bridges them; its ends are corners the body rolls round."""
    rng = np.random.default_rng(41)
    x = np.linspace(0.0, 0.3, 61)
    h = 3e-4 * rng.random(len(x))
    path = write(tmp_path / "rough.txt", x, h)
    spline = CubicSpline(x, h, bc_type="not-a-knot")
    assert (spline(x, 2) * R1 > 1).any()  # troughs sharper than the body
    t, yC = platform_samples(fmu, dict(profile_file=path, V=1.0, x0=0.0, profile_interpolation=CUBIC, contact_model=1),
                             0.3, 150)
    ref = np.array([definition(spline, x[0], x[-1], p) for p in t])
    assert np.abs(yC - ref).max() <= 1e-12 * np.ptp(h) + ROUND


def test_the_polyline_and_the_spline_agree_on_a_densely_sampled_shape(fmu, tmp_path):  # noqa: F811
    """2001 rows per wavelength (dx = 25 um): the polyline is within dx^2/8 A K^2 = 2.5e-11 m of the
    sinusoid, the spline much closer; their yb differ by no more than that, and the wheel rolled over
    them at 30 m/s (Hertz, 20 ms) feels the same peak force to 1e-4."""
    x, h, path = corrugation(tmp_path, 2001, waves=2)
    dx = L / 2000
    base = dict(profile_file=path, V=30.0, profile_periodic=True, contact_model=1, rtol=1e-8)
    t, yL = platform_samples(fmu, base, 0.02, 200)
    t, yS = platform_samples(fmu, {**base, "profile_interpolation": CUBIC}, 0.02, 200)
    assert np.abs(yL - yS).max() <= dx ** 2 / 8 * A * K ** 2 + ROUND
    peaks = []
    for interpolation in (LINEAR, CUBIC):
        r = simulate_fmu(str(BUILD / "VibroImpact.fmu"), stop_time=0.02, output_interval=1e-3, output=["F_peak"],
                         start_values={**base, "profile_interpolation": interpolation})
        peaks.append(r["F_peak"].max())
    assert abs(peaks[1] / peaks[0] - 1) <= 1e-4, peaks


def test_a_smooth_spline_has_no_time_event_in_model_exchange(fmu_path, tmp_path):
    """The polyline of the sampled corrugation has a kink at its concave rows, each a time event for the
    importer; the spline through the same rows has none, and Model Exchange runs without events,
    following the sinusoid's offset."""
    x, h, path = corrugation(tmp_path, 101)
    p = dict(profile_file=path, V=1.0, x0=0.0, profile_periodic=True, contact_model=1, a=0.0)
    events = {}
    for interpolation in (LINEAR, CUBIC):
        r, inst = run_me(fmu_path, {**p, "profile_interpolation": interpolation}, 0.05, rtol=1e-8,
                         output=("yC",), output_interval=1e-3, record_events=True)
        assert not inst.errors()
        events[interpolation] = int(np.sum(np.diff(r["time"]) == 0.0))
    assert events[LINEAR] >= 20 and events[CUBIC] == 0, events
    assert np.abs(r["yC"] - sinusoid_offset(r["time"])).max() <= 5 / 384 * (L / 100) ** 4 * A * K ** 4 + ROUND


def test_fmi3_gives_the_fmi2_numbers(tmp_path):
    x, h, path = corrugation(tmp_path, 201)
    start = dict(profile_file=path, V=30.0, profile_periodic=True, contact_model=1, profile_interpolation=CUBIC,
                 rtol=1e-8)
    for kind in ("CoSimulation", "ModelExchange"):
        kw = dict(fmi_type=kind, stop_time=0.01, output_interval=1e-4, relative_tolerance=1e-8,
                  output=["y", "yC", "F"], start_values=start)
        r2 = simulate_fmu(str(BUILD / "VibroImpact.fmu"), **kw)
        r3 = simulate_fmu(str(BUILD / "fmi3" / "VibroImpact.fmu"), **kw)
        for k in ("time", "y", "yC", "F"):
            assert np.array_equal(r3[k], r2[k]), (kind, k)


def test_fmu_state_with_a_spline(fmu, tmp_path):  # noqa: F811
    """As test_rolling.py's test with the polyline: a state taken while rolling, set back in the same
    instance and deserialized in a fresh one gives the platform to the bit, the mass and the force to
    the solver's tolerance."""
    x, h, path = corrugation(tmp_path, 101, waves=1)
    state_round_trip(fmu, dict(profile_file=path, V=5.0, profile_periodic=True, contact_model=1,
                               profile_interpolation=CUBIC, rtol=1e-10), A)


def test_an_unknown_interpolation_is_refused_naming_its_items(fmu):  # noqa: F811
    md, unzipdir, vr = fmu
    inst, s, init = instance(fmu, {}, logging=True)
    with pytest.raises(Exception):
        s.setInteger([vr["profile_interpolation"]], [3])
    assert any("profile_interpolation = 3 is not one of its items" in m and "linear=1" in m and "cubic=2" in m
               for _, _, m in inst.messages), inst.messages
    s.freeInstance()
