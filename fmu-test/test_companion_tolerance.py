"""The vehicle-track example's companions, Track.fmu and Vehicle.fmu, follow the contact FMU's tolerance
rule (doc/model.md section 5, "The tolerance rule"): they declare the same default experiment tolerance,
`rtol = 0` (the default) runs at the experiment's tolerance (the declared 1e-6 without one), and an `rtol`
set wins over any experiment's tolerance (PyFMI passes 1e-4), with a note naming both. Checked from the
model descriptions of both FMI versions and from runs: a run at one tolerance is the same, bit for bit,
however that tolerance was given, and the track's step response is as accurate as the tolerance it ran
at says (against the matrix exponential)."""
import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from scipy.linalg import expm

from conftest import BUILD, FMU
from vibroimpact.fmu import MessageLog, fmu3_path

import parameters  # the example's, through pytest.ini's pythonpath

pytestmark = pytest.mark.usefixtures("companion_fmus")
COMPANIONS = ("Track", "Vehicle")
WARNING = 1  # fmi2Warning
F0, F1, H, STEPS = 60e3, 70e3, 1e-5, 5000  # N, N, s: a load step on the track, 50 ms


def variable(md, name):
    return next(v for v in md.modelVariables if v.name == name)


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("name", COMPANIONS)
def test_the_descriptions_declare_the_contact_fmus_tolerance_and_rtol(name, version):
    folder = BUILD if version == 2 else fmu3_path().parent
    md = read_model_description(str(folder / f"{name}.fmu"))
    contact = read_model_description(str(FMU if version == 2 else fmu3_path()))
    assert float(md.defaultExperiment.tolerance) == float(contact.defaultExperiment.tolerance) == 1e-6
    mine, theirs = variable(md, "rtol"), variable(contact, "rtol")
    assert float(mine.start) == 0.0 and float(mine.min) == 0.0 and float(mine.max) == float(theirs.max)
    assert mine.description == theirs.description


class Run:
    """One Co-Simulation run of a companion: setupExperiment(tolerance), rtol (None: not set), the first
    input stepping from its start to `after` at the end of the first step; the first output at each
    step, and the messages."""

    def __init__(self, name, tolerance, rtol, first_input, before, after, output):
        path = BUILD / f"{name}.fmu"
        md = read_model_description(str(path))
        vr = {v.name: v.valueReference for v in md.modelVariables}
        self.log = MessageLog()
        s = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        s.instantiate(callbacks=self.log.callbacks)
        try:
            s.setupExperiment(tolerance=tolerance, startTime=0.0)
            s.enterInitializationMode()
            if rtol is not None:
                s.setReal([vr["rtol"]], [rtol])
            s.setReal([vr[first_input]], [before])
            s.exitInitializationMode()
            self.y = [s.getReal([vr[output]])[0]]
            s.setReal([vr[first_input]], [after])
            for k in range(STEPS):
                s.doStep(k * H, H)
                self.y.append(s.getReal([vr[output]])[0])
            s.terminate()
        finally:
            s.freeInstance()
        self.y = np.array(self.y)

    def notes(self):
        return [m for status, _, m in self.log.messages if status == WARNING]


def run(name, tolerance, rtol):
    if name == "Track":
        return Run(name, tolerance, rtol, "F_contact", F0, F1, "z_rail")
    return Run(name, tolerance, rtol, "y_wheel", 0.0, -1e-3, "z_body")


@pytest.mark.parametrize("name", COMPANIONS)
def test_a_set_rtol_wins_and_rtol_0_runs_at_the_experiments_tolerance(name):
    """The same tolerance, however given, gives the same run bit for bit; the other one another run."""
    tight = run(name, 1e-10, None)
    assert np.array_equal(run(name, 1e-4, 1e-10).y, tight.y)  # PyFMI's 1e-4 does not loosen a set rtol
    loose = run(name, 1e-4, 0.0)
    assert np.array_equal(run(name, 1e-10, 1e-4).y, loose.y)
    assert not np.array_equal(loose.y, tight.y)
    assert np.array_equal(run(name, None, None).y, run(name, 1e-6, None).y)  # none given: the declared 1e-6


def test_the_track_is_as_accurate_as_the_tolerance_it_ran_at():
    """The step response from the static state under F0 to F1, x1 + expm(A t) (x0 - x1): within 1e-7 of
    its swing at rtol 1e-10 set under an experiment's 1e-4, and beyond 1e-5 of it at the experiment's 1e-4
    with rtol 0 (it ran at 1e-4 indeed: 4.8e-5 measured)."""
    from test_vehicle_track import track_matrices
    A, b = track_matrices(parameters.TRACK)
    x0, x1 = (-np.linalg.solve(A, b * F) for F in (F0, F1))
    step, e, exact = expm(A * H), x0 - x1, []
    for _ in range(STEPS + 1):  # the load F1 acts from t = 0: x(k H) = x1 + expm(A H)^k (x0 - x1)
        exact.append((x1 + e)[0])
        e = step @ e
    exact = np.array(exact)
    swing = np.ptp(exact)
    assert np.abs(run("Track", 1e-4, 1e-10).y - exact).max() < 1e-7 * swing
    assert np.abs(run("Track", 1e-4, 0.0).y - exact).max() > 1e-5 * swing


@pytest.mark.parametrize("name", COMPANIONS)
def test_a_set_rtol_and_another_tolerance_give_one_note(name):
    """Logged with status Warning, naming both, while every call returned OK (fmpy raises otherwise); none
    when the tolerance given is the declared default (fmpy passes it when given none) or equal to rtol."""
    r = run(name, 1e-4, 1e-10)
    assert r.notes() == ["rtol = 1e-10 is used, not the experiment's tolerance 0.0001 (set rtol = 0 to use the "
                         "experiment's)"]
    assert run(name, 1e-6, 1e-10).notes() == [] and run(name, 1e-10, 1e-10).notes() == []
