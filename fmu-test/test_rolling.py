"""Rolling over an irregular surface (paper Fig. 1b) through the FMU.

With a = 0 and yC_in = 0 the FMU's output yC is the rigid constraint yb(x0 + V t) itself, so the
FMU's yb is sampled at every communication point and compared with the independent reference
vibroimpact.reference.profile (the definition evaluated by search, no geometry worked out) and
with closed forms: a gentle sinusoid is followed exactly at its crests; a sinusoid whose curvature
exceeds 1/R1 bridges its troughs (the body touches two points there); a step becomes the circular
ramp around its upper corner; a narrow bump is swept as the circle around its apex. Then: the
dynamics over a corrugation against the linearised closed form, bad files refused at
initialization with file and line, the end of a table, periodic tables, the resources folder, and
FMU states with a profile.
"""
import shutil
import zipfile

import numpy as np
import pytest
from fmpy import extract, read_model_description

from conftest import Logged, effective, start
from solvers import each_solver
from vibroimpact.reference import profile as profile_ref

R1 = 0.475
# absolute rounding of yb: the reference's sqrt(R1^2 - d^2) - R1 carries a few ulps of R1
ROUND = 8 * np.finfo(float).eps * R1


def write(path, x, h):
    with open(path, "w") as f:
        f.write("# x [m]  h [m]\n")
        for a, b in zip(x, h):
            f.write(f"{float(a)!r} {float(b)!r}\n")
    return str(path)


@pytest.fixture(scope="module")
def fmu(fmu_path):
    md = read_model_description(fmu_path)
    return md, extract(fmu_path), {v.name: v.valueReference for v in md.modelVariables}


def instance(fmu, params, logging=False, tolerance=None):
    """An initialized instance (start() runs fmi2ExitInitializationMode), with its logger."""
    md, unzipdir, vr = fmu
    inst = Logged(md, unzipdir)
    s = inst.instantiate(logging=logging)
    if logging:
        s.setDebugLogging(True, ["logStatusWarning", "logStatusError"])
    return inst, s, lambda: start(s, vr, params, tolerance=tolerance)


def platform_samples(fmu, params, t_end, n):
    """yC at n + 1 equally spaced communication points (the FMU initialized with params)."""
    md, unzipdir, vr = fmu
    inst, s, init = instance(fmu, params)
    init()
    h, out = t_end / n, []
    for k in range(n + 1):
        if k:
            s.doStep((k - 1) * h, h)
        out.append(s.getReal([vr["yC"]])[0])
    s.terminate()
    s.freeInstance()
    return np.linspace(0.0, t_end, n + 1), np.array(out)


def rolled(fmu, tmp_path, x, h, V, x0, t_end, n=400, periodic=False, law=1):
    path = write(tmp_path / "profile.txt", x, h)
    params = dict(profile_file=path, V=V, x0=x0, contact_model=law, profile_periodic=periodic)
    return platform_samples(fmu, params, t_end, n)


def test_gentle_sinusoid_followed_at_its_crests(fmu, tmp_path):
    lam, A = 0.05, 2e-5  # curvature A (2 pi/lam)^2 = 0.32/m < 1/R1 = 2.1/m
    x = np.linspace(0.0, 0.5, 1001)
    h = A * np.cos(2 * np.pi * x / lam)
    t, yC = rolled(fmu, tmp_path, x, h, V=1.0, x0=0.05, t_end=0.4, n=400)
    pos = 0.05 + t
    ref = profile_ref.yb(x, h, R1, pos)
    assert np.abs(yC - ref).max() <= 1e-12 * A + ROUND
    crest = np.isclose(np.mod(pos + 1e-12, lam), 0.0, atol=1e-9)
    assert crest.sum() >= 7
    assert np.abs(yC[crest] - A).max() <= 1e-15  # the body sits on each crest exactly
    assert np.all(yC >= np.interp(pos, x, h) - 1e-15)  # never below the surface


def test_sharp_sinusoid_bridges_its_troughs(fmu, tmp_path):
    lam, A = 0.05, 3e-4  # curvature 4.7/m > 1/R1: the body cannot reach the bottom
    x = np.linspace(0.0, 0.5, 2001)
    h = A * np.cos(2 * np.pi * x / lam)
    t, yC = rolled(fmu, tmp_path, x, h, V=1.0, x0=0.05, t_end=0.4, n=400)
    pos = 0.05 + t
    assert np.abs(yC - profile_ref.yb(x, h, R1, pos)).max() <= 1e-12 * A + ROUND
    trough = np.isclose(np.mod(pos - lam / 2 + 1e-12, lam), 0.0, atol=1e-9)
    assert trough.sum() >= 7
    assert np.all(yC[trough] > -A + 0.1 * A)  # bridged: far above the bottom
    # over a trough the body rests on two points, symmetric about it (the definition, searched)
    s = profile_ref.contact_points(x, h, R1, 0.1 + lam / 2)
    assert s.min() < 0.1 + lam / 2 - 1e-3 and s.max() > 0.1 + lam / 2 + 1e-3


def test_step_becomes_the_circular_ramp(fmu, tmp_path):
    H, c = 5e-3, 1e-9
    x, h = np.array([-1.0, 0.0, c, 1.0]), np.array([0.0, 0.0, H, H])
    t, yC = rolled(fmu, tmp_path, x, h, V=2.0, x0=-0.2, t_end=0.2, n=400)
    d = -0.2 + 2.0 * t - c
    ramp = np.where(d >= 0, H, np.maximum(0.0, H - d ** 2 / (R1 + np.sqrt(np.maximum(R1 ** 2 - d ** 2, 0)))))
    assert np.abs(yC - ramp).max() <= 1e-12 * H + ROUND


def test_narrow_bump_swept_as_a_circle(fmu, tmp_path):
    H, w = 2e-4, 1e-6
    x, h = np.array([-1.0, -w, 0.0, w, 1.0]), np.array([0.0, 0.0, H, 0.0, 0.0])
    t, yC = rolled(fmu, tmp_path, x, h, V=1.0, x0=-0.05, t_end=0.1, n=400)
    d = -0.05 + t
    circle = np.maximum(0.0, H - d ** 2 / (R1 + np.sqrt(R1 ** 2 - d ** 2)))
    half = np.sqrt(R1 ** 2 - (R1 - H) ** 2)
    away = np.abs(np.abs(d) - half) > 2 * w
    assert np.abs(yC - circle)[away].max() <= 1e-12 * H + ROUND
    assert np.abs(yC - profile_ref.yb(x, h, R1, d)).max() <= 1e-12 * H + ROUND


def test_periodic_table_repeats(fmu, tmp_path):
    lam, A = 0.05, 3e-4
    x = np.linspace(0.0, lam, 101)
    h = A * np.cos(2 * np.pi * x / lam)
    h[-1] = h[0]
    t, yC = rolled(fmu, tmp_path, x, h, V=-1.5, x0=0.01, t_end=0.2, n=200, periodic=True)
    assert np.abs(yC - profile_ref.yb(x, h, R1, 0.01 - 1.5 * t, periodic=True)).max() <= 1e-12 * A + ROUND


def test_corrugation_dynamics_against_the_linearised_closed_form(fmu, tmp_path):
    """Hertz, static start on a crest, rolling at a passing frequency 0.3 x the contact resonance over
    a 1 um corrugation (yb = h to 0.4 %): delta - delta_s = A W^2/(w_c^2 - W^2) (cos w_c t - cos W t),
    W = 2 pi V/lam, w_c = 2 pi f_contact; the contact force follows with the contact stiffness."""
    md, unzipdir, vr = fmu
    lam, A = 0.05, 1e-6
    x = np.linspace(0.0, 2.0, 4001)
    h = A * np.cos(2 * np.pi * x / lam)
    path = write(tmp_path / "corrugation.txt", x, h)
    e = effective(dict(g=9.81))
    d_s = (e["W"] / e["K"]) ** (2 / 3)
    k_c = 1.5 * e["K"] * np.sqrt(d_s)
    w_c = np.sqrt(k_c / e["m"])
    V = 0.3 * w_c * lam / (2 * np.pi)
    inst, s, init = instance(fmu, dict(profile_file=path, V=V, x0=0.0, contact_model=1, rtol=1e-10))
    init()
    W = 2 * np.pi * V / lam
    hstep, worst = 1e-5, 0.0
    amp = A * W ** 2 / (w_c ** 2 - W ** 2)
    for k in range(1, 3001):
        s.doStep((k - 1) * hstep, hstep)
        t = k * hstep
        delta = s.getReal([vr["delta"]])[0]
        lin = amp * (np.cos(w_c * t) - np.cos(W * t))
        worst = max(worst, abs(delta - d_s - lin))
    assert worst <= 0.02 * 2 * amp, (worst, amp)


@pytest.mark.parametrize("text, expect", [
    (None, "cannot open"),
    ("0 0\n1 0\n0.5 0\n", "line 3"),
    ("0 0\n1 nan\n", "line 2"),
    ("0 0\n", "one data row (line 1)"),
    ("0 0\n1 x\n", "line 2"),
])
def test_bad_files_are_refused_at_initialization(fmu, tmp_path, text, expect):
    path = tmp_path / "bad.txt"
    if text is not None:
        path.write_text(text)
    inst, s, init = instance(fmu, dict(profile_file=str(path), V=1.0), logging=True)
    with pytest.raises(Exception):
        init()
    assert any(str(path) in m and expect in m for m in inst.text().splitlines()), inst.text()


def test_end_of_the_table_is_refused_with_time_and_position(fmu, tmp_path):
    md, unzipdir, vr = fmu
    x = np.linspace(0.0, 0.1, 11)
    path = write(tmp_path / "short.txt", x, np.zeros_like(x))
    inst, s, init = instance(fmu, dict(profile_file=path, V=2.0, x0=0.02), logging=True)
    init()
    s.doStep(0.0, 0.03)  # to x = 0.08 m
    with pytest.raises(Exception):
        s.doStep(0.03, 0.03)  # the end, x = 0.1 m, at t = 0.04 s
    assert "t = 0.04" in inst.text() and "x_last = 0.1 m" in inst.text()


def test_x0_outside_the_table_is_refused(fmu, tmp_path):
    x = np.linspace(0.0, 0.1, 11)
    path = write(tmp_path / "short.txt", x, np.zeros_like(x))
    inst, s, init = instance(fmu, dict(profile_file=path, V=1.0, x0=0.5), logging=True)
    with pytest.raises(Exception):
        init()
    assert "x0 = 0.5 m lies outside the profile" in inst.text()


def test_relative_path_from_resources_then_working_directory(fmu_path, tmp_path, monkeypatch):
    """A relative profile_file is looked up in the FMU's resources folder first, then in the working
    directory: an FMU carrying resources/rail.txt (a step up) and a different rail.txt (flat) in
    the working directory: the resources win; without resources/rail.txt the working directory."""
    x = np.array([0.0, 0.05, 0.05 + 1e-9, 1.0])
    up = tmp_path / "fmu_with_resources.fmu"
    shutil.copy(fmu_path, up)
    with zipfile.ZipFile(up, "a") as z:
        z.writestr("resources/rail.txt", "".join(f"{float(a)!r} {float(b)!r}\n" for a, b in zip(x, [0, 0, 1e-3, 1e-3])))
    work = tmp_path / "work"
    work.mkdir()
    write(work / "rail.txt", [0.0, 1.0], [2e-3, 2e-3])
    monkeypatch.chdir(work)
    for fmu_file, expect in ((up, 1e-3), (fmu_path, 2e-3)):
        md = read_model_description(str(fmu_file))
        f = (md, extract(str(fmu_file)), {v.name: v.valueReference for v in md.modelVariables})
        t, yC = platform_samples(f, dict(profile_file="rail.txt", V=1.0, x0=0.5), 0.1, 10)
        assert yC[-1] == pytest.approx(expect, abs=1e-15)


@each_solver
def test_fmu_state_with_a_profile(fmu, tmp_path, solver):
    """Get the state while rolling, run on; set it back, run again; and the serialized state in a fresh
    instance with the same parameters: the platform (the profile, reattached from the instance's own
    copy, never from the saved pointer) is the same to the bit, the mass to the solver's tolerance
    (a restored run restarts the solver)."""
    lam, A = 0.05, 2e-5
    x = np.linspace(0.0, lam, 101)
    h = A * np.cos(2 * np.pi * x / lam)
    h[-1] = h[0]
    params = dict(profile_file=write(tmp_path / "p.txt", x, h), V=5.0, profile_periodic=True, contact_model=1,
                  rtol=1e-10, solver=solver)  # kinks fall on communication points (t = 5 ms among them)
    state_round_trip(fmu, params, A)


def state_round_trip(fmu, params, A):
    """The run from 5 ms after a state taken there, set back in the same instance and deserialized in a
    fresh one with the same parameters: the platform yC to the bit, y within 1e-6 A and F within 1e-6 of
    the static load of the original run's."""
    md, unzipdir, vr = fmu
    names = [vr[n] for n in ("yC", "y", "v", "F")]

    def run(s, t0, n, hs=1e-4):
        out = []
        for k in range(n):
            s.doStep(t0 + k * hs, hs)
            out.append(s.getReal(names))
        return np.array(out)

    inst, s, init = instance(fmu, params)
    init()
    run(s, 0.0, 50)
    state = s.getFMUstate()
    a = run(s, 0.005, 100)
    s.setFMUstate(state)
    b = run(s, 0.005, 100)
    blob = s.serializeFMUstate(state)
    inst2, s2, init2 = instance(fmu, params)
    init2()
    s2.setFMUstate(s2.deSerializeFMUstate(blob))
    c = run(s2, 0.005, 100)
    assert np.ptp(a[:, 0]) > A  # it rolls
    e = effective({})
    for other in (b, c):
        assert np.array_equal(other[:, 0], a[:, 0])
        assert np.abs(other[:, 1] - a[:, 1]).max() <= 1e-6 * A
        assert np.abs(other[:, 3] - a[:, 3]).max() <= 1e-6 * e["W"]
