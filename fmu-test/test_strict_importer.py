"""A master that stops at any status but OK, as fmusim and PyFMI's Co-Simulation driver do, runs every
scenario of the guide to the laws (vibroimpact.laws_guide, doc/choosing.md: the drops, the paper's
excitation, the rolling wheel and the vehicle-track example, each with every law and option) and every
paper scenario (vibroimpact.reference.scenarios) to its end: FMI 2.0 and 3.0 Co-Simulation, fmpy's Model
Exchange driver, the vehicle-track example's co-simulation and Model Exchange masters, and a run given
both the experiment's tolerance and `rtol`. The notes the FMU logs on the way (a result outside the range
of validity, an option's accuracy, `rtol` against the tolerance) still reach the logger with status
Warning: they are notes the computation goes on through, not results that are wrong.

The strict instances are fmpy's FMU2Slave, FMU3Slave and FMU2Model with a call logger (fmpy's
fmiCallLogger, which sees each call's status) that raises at any status but OK."""
import pathlib
import tempfile

import fmpy
import fmpy.fmi2
import fmpy.fmi3
import numpy as np
import pytest
from fmpy import extract, read_model_description

from vibroimpact import fmu as vifmu
from vibroimpact import laws_guide as G
from vibroimpact import rolling
from vibroimpact.me import run_me
from vibroimpact.reference.scenarios import SCENARIOS
from vibroimpact.vehicle_track import master as vt_master
from vibroimpact.vehicle_track import me_master as vt_me
from vibroimpact.vehicle_track import parameters as vt_parameters
from vibroimpact.vehicle_track import roughness

WARNING = 1  # fmi2Warning, fmi3Warning
NOT_OK = ("WARNING", "DISCARD", "ERROR", "FATAL", "PENDING")


class NotOk(Exception):
    """A call returned a status other than OK: the run stops here, as in fmusim and PyFMI."""


def _stop_at_any_status_but_ok(message):
    """fmpy's call logger: 'fmi2DoStep(...) -> WARNING' raises NotOk."""
    if message.rsplit(" -> ", 1)[-1] in NOT_OK:
        raise NotOk(message[:400])


def strict(cls):
    """fmpy's instance class `cls` whose every call raises NotOk at a status other than OK (under the same
    name: fmpy finds the FMI version's functions by the class name)."""
    def __init__(self, **kw):
        cls.__init__(self, fmiCallLogger=_stop_at_any_status_but_ok, **kw)
    return type(cls.__name__, (cls,), {"__init__": __init__})


StrictSlave2, StrictSlave3, StrictModel2 = strict(fmpy.fmi2.FMU2Slave), strict(fmpy.fmi3.FMU3Slave), \
    strict(fmpy.fmi2.FMU2Model)


class Fmu:
    """An extracted FMU (either version) and its model description."""

    def __init__(self, path):
        self.path = str(path)
        self.md = read_model_description(self.path)
        self.dir = extract(self.path)


@pytest.fixture(scope="module")
def fmus(fmu_path):
    return {2: Fmu(fmu_path), 3: Fmu(vifmu.fmu3_path())}


def cs_run(f, version, params, stop, tolerance, interval=1e-5):
    """One Co-Simulation run by fmpy.simulate_fmu on a strict instance: (result, messages)."""
    if version == 2:
        log = vifmu.MessageLog()
        s = StrictSlave2(guid=f.md.guid, unzipDirectory=f.dir, modelIdentifier=f.md.coSimulation.modelIdentifier,
                         instanceName="strict")
        s.instantiate(callbacks=log.callbacks)
    else:
        log = vifmu.Messages()
        s = StrictSlave3(guid=f.md.guid, unzipDirectory=f.dir, modelIdentifier=f.md.coSimulation.modelIdentifier,
                         instanceName="strict")
        s.instantiate(logMessage=lambda env, status, category, message: log.keep(status, category,
                                                                                 message.decode()))
    try:
        r = fmpy.simulate_fmu(f.path, fmi_type="CoSimulation", fmu_instance=s, model_description=f.md,
                              start_values=params, stop_time=stop,
                              relative_tolerance=tolerance, output_interval=interval, output=["y"])
    finally:
        s.freeInstance()
    return r, log.messages


def notes(messages):
    return [m for status, _, m in messages if status == WARNING]


def guide_runs():
    """(scene, variant, parameters, stop time, output interval) of every row of doc/choosing.md but the
    vehicle-track ones."""
    profile = pathlib.Path(tempfile.mkdtemp(prefix="strict_")) / "corrugation.txt"
    rolling.corrugation(profile)
    runs = []
    for scene, (params, stop, _) in G.scenes(profile.resolve()).items():
        for variant, options in G.VARIANTS.items():
            p = dict(params, **options)
            if variant == "linear":
                p["k_spring"] = G.k_spring_for(scene)
            runs.append((scene, variant, p, stop, G.INTERVAL if stop <= G.STOP["drop"] else 1e-5))
    return runs


GUIDE = guide_runs()
GUIDE_IDS = [f"{scene}-{variant}" for scene, variant, *_ in GUIDE]


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("scene, variant, params, stop, interval", GUIDE, ids=GUIDE_IDS)
def test_every_scene_of_the_guide_runs_to_its_end_in_co_simulation(fmus, version, scene, variant, params, stop,
                                                                    interval):
    """Each scene with each law at the guide's tolerance: every call OK, the result to the stop time."""
    r, messages = cs_run(fmus[version], version, params, stop, G.RTOL, interval)
    assert r["time"][-1] == pytest.approx(stop, abs=1e-12)


@pytest.mark.timeout(600)
@pytest.mark.parametrize("scene, variant, params, stop, interval", GUIDE, ids=GUIDE_IDS)
def test_every_scene_of_the_guide_runs_to_its_end_in_fmpys_model_exchange(fmu_path, scene, variant, params, stop,
                                                                         interval):
    """The same rows through fmpy's Model Exchange driver (its CVode), the instance strict."""
    r, inst = run_me(fmu_path, params, stop, rtol=G.RTOL, output=("y",), output_interval=1e-5,
                     call_logger=_stop_at_any_status_but_ok)
    assert r["time"][-1] == pytest.approx(stop, abs=1e-12) and not inst.errors()


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("name", list(SCENARIOS))
def test_every_paper_scenario_runs_to_its_end_in_co_simulation(fmus, version, name):
    """The paper's scenarios (Figs. 4-6, the LEPP ones included, and those beyond the paper) to 0.1 s,
    without the experiment's tolerance (the FMU's default)."""
    r, _ = cs_run(fmus[version], version, SCENARIOS[name].full, 0.1, None)
    assert r["time"][-1] == pytest.approx(0.1, abs=1e-12)


@pytest.mark.timeout(600)
@pytest.mark.parametrize("name", list(SCENARIOS))
def test_every_paper_scenario_runs_to_its_end_in_fmpys_model_exchange(fmu_path, name):
    r, inst = run_me(fmu_path, SCENARIOS[name].full, 0.1, rtol=1e-8, output=("y",), output_interval=1e-4,
                     call_logger=_stop_at_any_status_but_ok)
    assert r["time"][-1] == pytest.approx(0.1, abs=1e-12) and not inst.errors()


@pytest.mark.parametrize("version", [2, 3])
def test_a_run_given_the_tolerance_and_rtol_runs_and_says_which_it_uses(fmus, version):
    """The experiment's tolerance 1e-7 and rtol = 1e-9: rtol wins (doc/model.md section 5), the run goes on
    to its end, and the note saying so reaches the logger as a warning."""
    r, messages = cs_run(fmus[version], version, dict(SCENARIOS["fig4b"].full, rtol=1e-9), 0.1, 1e-7)
    assert r["time"][-1] == pytest.approx(0.1, abs=1e-12)
    assert any("rtol = 1e-09 is used, not the experiment's tolerance 1e-07" in m for m in notes(messages)), messages


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("scene, variant, words", [
    ("fig4b", "lepp", "exceeds 0.01 R*"),                # LEPP flows on to a contact radius beyond 0.1 R*
    ("drop_3", "lepp", "exceeds 0.01 R*"),
    ("drop_1", "hunt_crossley", "damping_formula = 2 gives an isolated impact the restitution"),
])
def test_the_notes_still_reach_the_logger_as_warnings(fmus, version, scene, variant, words):
    """The runs an importer that stops at a warning status ended early (the LEPP scene at 0.0495 s of
    0.05 s): they run to their end, and the note is logged with status Warning, once."""
    _, _, params, stop, interval = next(g for g in GUIDE if g[:2] == (scene, variant))
    r, messages = cs_run(fmus[version], version, params, stop, G.RTOL, interval)
    assert r["time"][-1] == pytest.approx(stop, abs=1e-12)
    assert len([m for m in notes(messages) if words in m]) == 1, messages


@pytest.fixture(scope="module")
def rough(tmp_path_factory, companion_fmus):
    path = tmp_path_factory.mktemp("strict_vt") / "roughness.txt"
    roughness.write(path, *roughness.profile(**vt_parameters.ROUGHNESS))
    return path.resolve()


@pytest.mark.timeout(300)
@pytest.mark.parametrize("variant", list(G.VARIANTS))
def test_the_vehicle_track_scene_runs_to_its_end_in_co_simulation(fmu_path, rough, monkeypatch, variant):
    """The guide's vehicle-track co-simulation (the example's recommended master) with every FMU strict."""
    monkeypatch.setattr(vt_master, "FMU2Slave", StrictSlave2)
    p = dict(profile_file=str(rough), x0=G.VT_X0, **G.VARIANTS[variant])
    if variant == "linear":
        p["k_spring"] = G.k_spring_for("vehicle_track")
    rec = G._vt_cs(fmu_path, p, G.STOP["vehicle_track"])
    assert rec["t"][-1] == pytest.approx(G.STOP["vehicle_track"], abs=1e-12)
    assert np.isfinite(rec["contact.F"]).all()


# The strict Model Exchange master runs the guide's whole scene (0.03 s) for every law but the two whose
# force follows the rate of indentation: the master stopped johnson_continuous and thornton at 11.5 ms and
# lepp at 20.7 ms with the Zeno rule before the rail's velocity reached the contact FMU (vC_in). The damped
# laws run the first 10 ms [s]: there the solver takes 5 times hertz's evaluations (doc/choosing.md), and
# the strict call logger, which formats every FMI call, multiplies the cost by 5: 2 minutes per damped law
# for the whole scene.
VT_ME_STRICT_STOP = {"hertz_damped": 0.01, "linear": 0.01}


@pytest.mark.timeout(600)
@pytest.mark.parametrize("variant", list(G.VARIANTS))
def test_the_vehicle_track_scene_runs_to_its_end_in_model_exchange(fmu_path, rough, monkeypatch, variant):
    """The guide's vehicle-track Model Exchange master (the three FMUs in one solver, the rail's velocity
    in vC_in) with every FMU strict, to VT_ME_STRICT_STOP."""
    monkeypatch.setattr(vt_me, "FMU2Model", StrictModel2)
    p = dict(profile_file=str(rough), x0=G.VT_X0, **G.VARIANTS[variant])
    if variant == "linear":
        p["k_spring"] = G.k_spring_for("vehicle_track")
    G._vt_me_run(fmu_path, p, VT_ME_STRICT_STOP.get(variant, G.STOP["vehicle_track"]))
