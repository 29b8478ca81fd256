"""The guide to the laws (vibroimpact laws, doc/choosing.md): its drop rows against closed forms and the
independent reference, its two-wall scenes (the upper stop) against the closed form of a shaken cavity and
the free fall onto a descending lid, and the page's table cells that do not depend on the machine (peak
force, restitution, events of the 1 m/s drop; the vehicle-track and two-wall rows) against a rerun of the
command's code."""
import math
import pathlib
import subprocess
import sys

import numpy as np
import pytest

from test_two_sided_reference import periodic_orbits
from vibroimpact import laws_guide as G
from vibroimpact.reference import laws as L
from vibroimpact.reference.closed_forms import effective

ROOT = pathlib.Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def drop_rows(tmp_path_factory, fmu_path):
    rows = G.run(tmp_path_factory.mktemp("laws"), fmu_path, only_scenes=["drop_1"], repeat=1)
    return {r["variant"]: r for r in rows}


@pytest.mark.timeout(300)
def test_drop_rows_against_closed_forms(drop_rows):
    """1 m/s: hertz rebounds at 1 with Johnson's peak force 1750 N; exact damping and linear at 0.6;
    Hunt-Crossley at its closed relation; Thornton at his closed form (r = V_Y/V)."""
    assert drop_rows["hertz"]["restitution"] == pytest.approx(1.0, abs=1e-6)
    assert drop_rows["hertz"]["F_max_N"] == pytest.approx(1750.0, rel=1e-3)
    for v in ("hertz_damped", "linear"):
        assert drop_rows[v]["restitution"] == pytest.approx(G.E_DAMPED, abs=1e-6)
        assert drop_rows[v]["W_dissipated_J"] == pytest.approx(0.5 * G.SPHERE["m"] * (1 - G.E_DAMPED ** 2), rel=1e-5)
    expected = L.hc_restitution_closed_form(L.chi(L.HUNT_CROSSLEY, G.E_DAMPED))
    assert drop_rows["hunt_crossley"]["restitution"] == pytest.approx(expected, abs=1e-6)
    e = effective(G.SPHERE)
    VY = math.sqrt(0.8 * e["F_Y"] * e["delta_Y"] / G.SPHERE["m"])
    assert drop_rows["thornton"]["restitution"] == pytest.approx(L.thornton_restitution(VY), abs=1e-5)
    assert all(r["events"] >= 1 and r["cpu_cs_s_per_s"] > 0 for r in drop_rows.values())


def test_choosing_md_quotes_the_command(drop_rows):
    """doc/choosing.md's rows of the 1 m/s drop have the peak force, restitution, dissipated work and
    event count a rerun gives (the CPU columns depend on the machine and are not compared)."""
    page = {}
    for line in (ROOT / "doc" / "choosing.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 10 and cells[0] == "drop_1":
            page[cells[1]] = cells[2:7]
    rerun = {}
    for line in G.markdown(list(drop_rows.values())).splitlines()[2:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        rerun[cells[1]] = cells[2:7]
    assert page.keys() == rerun.keys()
    # the work an elastic law "dissipates" is the solver's error: equal within 1e-5 of the impact's
    # kinetic energy, whichever solver runs; the other cells as printed
    noise_J = 1e-5 * 0.5 * G.SPHERE["m"] * 1.0 ** 2
    for variant, cells in page.items():
        other = rerun[variant]
        assert cells[:2] + cells[3:] == other[:2] + other[3:], variant
        if cells[2] or other[2]:
            assert float(cells[2]) == pytest.approx(float(other[2]), rel=1e-3, abs=noise_J), variant


def test_the_command_is_registered():
    r = subprocess.run([sys.executable, "-m", "vibroimpact", "laws", "--help"], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0 and "doc/choosing.md" in r.stdout


@pytest.fixture(scope="module")
def vt_rows(tmp_path_factory, fmu_path, companion_fmus):
    out = tmp_path_factory.mktemp("laws_vt")
    rows = G.run(out, fmu_path, only_scenes=["vehicle_track"], variants=["hertz", "johnson"], repeat=1)
    return {r["variant"]: r for r in rows}, out / "roughness.txt"


@pytest.mark.timeout(300)
def test_vehicle_track_rows_against_the_monolithic_reference(vt_rows):
    """The vehicle-track scene with hertz, the example's recommended co-simulation, against the example's
    independent monolithic reference (SciPy, from the equations) over the same stretch of rail: peak force
    to 1 % of the static wheel load W (the example measures 0.36 % W at this communication step), the
    wheel's peak-to-peak motion over the second half to 0.1 um; johnson dissipates plastic work; both
    ran in Co-Simulation and Model Exchange."""
    import reference
    rows, rough = vt_rows
    stop = G.STOP["vehicle_track"]
    profile = reference.Profile.from_file(rough, reference.parameters.WHEEL["R1"])
    system = reference.System(wheel={"x0": G.VT_X0}, profile=profile, t_end=stop)
    sol = reference.simulate(system, stop, rtol=1e-10)
    t = np.linspace(0.0, stop, int(round(stop / G.TIMED_INTERVAL)) + 1)
    assert rows["hertz"]["F_max_N"] == pytest.approx(float(sol.force(t).max()), abs=0.01 * system.W)
    y = sol.state(t[t >= stop / 2])[reference.YW]
    assert rows["hertz"]["y_pp_um"] == pytest.approx(float(np.ptp(y)) * 1e6, abs=0.1)
    assert rows["hertz"]["W_dissipated_J"] == 0.0
    assert rows["johnson"]["W_dissipated_J"] > 0.0
    for r in rows.values():
        assert r["events"] >= 1 and r["cpu_cs_s_per_s"] > 0 and r["cpu_me_s_per_s"] > 0


def test_choosing_md_quotes_the_vehicle_track_rows(vt_rows):
    """doc/choosing.md's vehicle-track rows of hertz and johnson have the peak force, dissipated work,
    response and event count a rerun gives."""
    rows, _ = vt_rows
    page = {}
    for line in (ROOT / "doc" / "choosing.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 10 and cells[0] == "vehicle_track" and cells[1] in rows:
            page[cells[1]] = cells[2:7]
    rerun = {}
    for line in G.markdown(list(rows.values())).splitlines()[2:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        rerun[cells[1]] = cells[2:7]
    assert set(rerun) == {"hertz", "johnson"} and page == rerun


def test_choosing_md_quotes_the_vehicle_track_agreement(vt_rows):
    """doc/choosing.md's table of the vehicle-track Model Exchange master against its co-simulation has
    the rerun's rows of hertz and johnson (laws_guide.vt_agreement) within 10 %: each number is the
    largest difference of two integrations near their tolerance, which moves with the step sequence of
    the master's SciPy integrator (hertz's 8.7e-05 and 7.5e-05 were 8.9e-05 and 7.7e-05 with another
    SciPy and NumPy build)."""
    rows, _ = vt_rows

    def table(text):
        out = {}
        for line in text.splitlines():
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) == 1 + len(G.AGREEMENT_STEPS) and cells[0] in rows:
                try:
                    out[cells[0]] = [float(c) for c in cells[1:]]
                except ValueError:
                    continue
        return out
    rerun = table(G.agreement_markdown(list(rows.values())))
    page = table((ROOT / "doc" / "choosing.md").read_text().split("**The Model Exchange master and the co-simulation agree**")[1])
    assert set(rerun) == {"hertz", "johnson"} and set(rerun) <= set(page), (rerun, page)
    for variant, numbers in rerun.items():
        assert np.allclose(page[variant], numbers, rtol=0.1, atol=0.0), (variant, page[variant], numbers)


@pytest.fixture(scope="module")
def wall_rows(tmp_path_factory, fmu_path):
    """Both two-wall scenes with every variant: {(scene, variant): row}."""
    rows = G.run(tmp_path_factory.mktemp("laws_walls"), fmu_path, only_scenes=list(G.WALL_SCENES), repeat=1)
    return {(r["scene"], r["variant"]): r for r in rows}


@pytest.mark.timeout(300)
def test_the_wall_scenes_give_every_variant_finite_numbers(wall_rows):
    """impact_damper and clearance, each with every variant: finite peak force, dissipated work, response,
    costs and wall quantities; every variant hits both walls in both scenes; no law gives energy back
    (the work dissipated, over the run and per cycle, is not negative beyond rounding)."""
    assert set(wall_rows) == {(s, v) for s in G.WALL_SCENES for v in G.VARIANTS}
    for key, r in wall_rows.items():
        numbers = [r[k] for k in ("F_max_N", "W_dissipated_J", "y_pp_um", "cpu_cs_s_per_s", "cpu_me_s_per_s",
                                  "speed_m_s", "impacts_lower_per_cycle", "impacts_upper_per_cycle", "F_lower_N",
                                  "F_upper_N", "W_cycle_J")]
        assert all(math.isfinite(x) for x in numbers), (key, numbers)
        assert r["events"] > 0 and r["cpu_cs_s_per_s"] > 0 and r["cpu_me_s_per_s"] > 0, key
        assert r["impacts_lower_per_cycle"] > 0 and r["impacts_upper_per_cycle"] > 0, key
        assert r["F_lower_N"] > 0 and r["F_upper_N"] > 0, key
        assert r["W_dissipated_J"] > -1e-12 and r["W_cycle_J"] > -1e-12, key
    text = G.markdown(list(wall_rows.values())) + G.walls_markdown(list(wall_rows.values()))
    assert "nan" not in text.lower() and "inf" not in text.lower()


@pytest.mark.timeout(300)
def test_the_impact_damper_settles_at_the_closed_form(wall_rows):
    """With restitution e exact (hertz_damped, linear: e = 0.6) the sphere thrown up at 1.5 m/s settles into
    the closed form's motion (test_two_sided_reference.periodic_orbits): one impact per cycle on each wall,
    the speed it leaves a wall with within 1 % of u = (1+e)/(1-e) a w cos(phi) (the contact time, about
    60 us, against the half period of 10 ms), and each cycle dissipates the closed form's 4 m u^2 (1-e)/(1+e)
    within 2 % (u squared); an elastic law dissipates nothing."""
    p = dict(G.SPHERE, **G.SHAKEN, **G.WALLS["impact_damper"])
    (phi, u, _, _), _ = periodic_orbits(G.E_DAMPED, p["a"], p["f"], p["gap"])
    assert G.cavity_orbit(G.E_DAMPED, p["a"], p["f"], p["gap"]) == pytest.approx((phi, u), rel=1e-12)
    for variant in ("hertz_damped", "linear"):
        r = wall_rows["impact_damper", variant]
        assert r["impacts_lower_per_cycle"] == r["impacts_upper_per_cycle"] == 1.0, variant
        assert r["speed_m_s"] == pytest.approx(u, rel=1e-2), variant
        assert r["speed_closed_form"] == pytest.approx(r["speed_m_s"] / u, rel=1e-12)
        e = G.E_DAMPED
        assert r["W_cycle_J"] == pytest.approx(4 * p["m"] * u * u * (1 - e) / (1 + e), rel=2e-2), variant
        assert r["F_lower_N"] == pytest.approx(r["F_upper_N"], rel=1e-2), variant   # the two walls alike
    assert wall_rows["impact_damper", "hertz"]["W_cycle_J"] == 0.0


@pytest.mark.timeout(300)
def test_the_clearance_starts_with_a_free_fall_onto_the_lid(wall_rows):
    """At rest on the lower flank when the platform starts down at a w^2 = 10 g, the sphere falls freely
    (y = -g t^2/2) until the upper flank, a (cos(w t) - 1) + gap, comes down onto it: the first onset on the
    upper wall, whatever the law, is that free fall's (to 1e-9 s); then it rattles, both flanks hit."""
    from scipy.optimize import brentq
    p = dict(G.SPHERE, **G.SHAKEN, **G.WALLS["clearance"])
    w = 2 * math.pi * p["f"]
    assert p["a"] * w * w > p["g"]
    lid = lambda t: p["a"] * (math.cos(w * t) - 1) + p["gap"] + 0.5 * p["g"] * t * t
    t1 = brentq(lid, 1e-9, 0.5 / p["f"], xtol=1e-15)
    for variant in G.VARIANTS:
        r = wall_rows["clearance", variant]
        assert r["first_upper_s"] == pytest.approx(t1, abs=1e-9), variant
        assert r["impacts_lower_per_cycle"] >= 1 and r["impacts_upper_per_cycle"] >= 1, variant
    assert wall_rows["clearance", "hertz"]["W_cycle_J"] == 0.0
    assert wall_rows["clearance", "hertz_damped"]["W_cycle_J"] > 0.0


def page_rows(scenes):
    """doc/choosing.md's main table rows of `scenes`: {(scene, variant): the machine-independent cells}."""
    page = {}
    for line in (ROOT / "doc" / "choosing.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 10 and cells[0] in scenes:
            page[cells[0], cells[1]] = cells[2:7]
    return page


def test_choosing_md_quotes_the_wall_scenes(wall_rows):
    """doc/choosing.md's rows of impact_damper and clearance have the peak force, dissipated work,
    response and event count a rerun gives, and its table of what each wall sees is the rerun's."""
    rows = list(wall_rows.values())
    rerun = {}
    for line in G.markdown(rows).splitlines()[2:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        rerun[cells[0], cells[1]] = cells[2:7]
    page = page_rows(G.WALL_SCENES)
    assert page.keys() == rerun.keys()
    for key, cells in page.items():
        assert all(map(same_cell, cells, rerun[key])), (key, cells, rerun[key])
    walls = {tuple(c.strip() for c in line.strip().strip("|").split("|"))
             for line in G.walls_markdown(rows).splitlines()[2:]}
    on_page = {}
    for line in (ROOT / "doc" / "choosing.md").read_text().splitlines():
        cells = tuple(c.strip() for c in line.strip().strip("|").split("|"))
        if len(cells) == 9 and cells[0] in G.WALL_SCENES:
            on_page[cells[:2]] = cells
    assert len(walls) == len(rows) and {c[:2] for c in walls} == on_page.keys()
    for cells in walls:
        assert all(map(same_cell, on_page[cells[:2]], cells)), (on_page[cells[:2]], cells)


def same_cell(a, b):
    """Two table cells agree: the same text, or both a work an elastic law "dissipates" (the solver's
    rounding, below 1e-9 in J or mJ), which differs with the machine's arithmetic."""
    try:
        return a == b or (abs(float(a)) < 1e-9 and abs(float(b)) < 1e-9)
    except ValueError:
        return False


def test_an_unknown_scene_is_refused_before_the_wall_figure_is_written(tmp_path):
    """--scenes impact_damper nosuch: exit 2 naming nosuch and the two-wall scenes, every file of a
    finished run (laws_walls.png too) as it was."""
    out = tmp_path / "laws"
    out.mkdir()
    files = ("laws.csv", "laws.md", "laws.png", "laws_walls.png")
    for name in files:
        (out / name).write_text(f"finished {name}\n")
    r = subprocess.run([sys.executable, "-m", "vibroimpact", "laws", "--out", "laws", "--scenes", "impact_damper",
                        "nosuch"], capture_output=True, text=True, timeout=60, cwd=tmp_path)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    last = r.stderr.strip().splitlines()[-1]
    assert "unknown scene nosuch" in last and "impact_damper" in last and "clearance" in last, last
    assert sorted(p.name for p in out.iterdir()) == sorted(files)
    for name in files:
        assert (out / name).read_text() == f"finished {name}\n"
