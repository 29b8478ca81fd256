"""The guide to the laws (vibroimpact laws, doc/choosing.md): its drop rows against closed forms and the
independent reference, and the page's table cells that do not depend on the machine (peak force,
restitution, events of the 1 m/s drop) against a rerun of the command's code."""
import math
import pathlib
import subprocess
import sys

import numpy as np
import pytest

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
    the rerun's rows of hertz and johnson (laws_guide.vt_agreement)."""
    rows, _ = vt_rows
    rerun = {line for line in G.agreement_markdown(list(rows.values())).splitlines()[2:]}
    page = set((ROOT / "doc" / "choosing.md").read_text().splitlines())
    assert len(rerun) == 2 and rerun <= page, rerun
