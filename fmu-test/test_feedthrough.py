"""ModelStructure (generated from the table's depends column) against measured feedthrough.

The contact model: scenarios that together reach all five modes and the three laws run in Model
Exchange (fmpy's CVode). At the first completed step in each mode, with the instance in
continuous-time mode and an FMU state taken, and again 1e-6 s later (fmi2SetTime inside the step,
where the mean force covers a step of its own), each known (the inputs yC_in and F_ext, the states y
and v) is moved by +-1e-3 of its scale alone, and every output and state derivative is read again: a
value that changes depends on that known. An output or derivative must not move with a known it is
declared independent of, at any point; and every declared dependency must be seen at some point (the
declaration is the union over the modes, no wider). The layer's test model and the vehicle-track
companions (linear, one mode) are measured the same way, 1 ms after a point where no state or input
is zero.
"""
import ctypes

import pytest

from conftest import BUILD
from vibroimpact.reference.scenarios import SCENARIOS

STEP_REL = 1e-3
# scenario -> modes it reaches within 0.02 s (as in test_me_jacobian.py: all five modes, every law)
CASES = {"fig5c": [0, 1], "fig4b": [0, 1, 2, 3], "stick": [2, 3, 4], "continuous": [0, 1, 2, 3], "fig4c": [0, 1, 2],
         "fig6a": [0, 1, 2], "damped": [0, 1], "damped_velocity": [0, 1],
         # the upper stop: (mode, mode_upper) pairs, the mass pressed up onto the upper surface
         "upper_stick": [(0, 1), (0, 2), (0, 3), (0, 4)], "upper_damped": [(0, 1)]}
# cases that are no scenario of the table: the damped Hertz law (its force depends on v) under Fig. 4b's excitation,
# and with the platform's rate taken from vC_in (the force then depends on it)
EXTRA = {"damped": dict(contact_model=4, e_restitution=0.6, Y=6e8, a=1e-4, f=560.0),
         "damped_velocity": dict(contact_model=4, e_restitution=0.6, Y=6e8, a=1e-4, f=560.0, velocity_input=True),
         "upper_stick": dict(upper_stop=True, gap=1e-12, init=2, P=-40000.0, g=-9.81, a=-3e-4, f=100.0, Y=2e8),
         "upper_damped": dict(upper_stop=True, gap=1e-12, init=2, P=-40000.0, g=-9.81, a=1e-4, f=560.0, contact_model=4,
                              e_restitution=0.6, velocity_input=True)}


def modes_of(point):
    """(mode, mode_upper) at the point."""
    r = point.read(["mode", "mode_upper"])
    return r["mode"], r["mode_upper"]


def unknowns(md):
    """The outputs and state derivatives with their declared dependencies (names)."""
    return {u.variable.name: {d.name for d in u.dependencies} for u in md.outputs + md.derivatives}


class Point:
    """Reads and moves one Model Exchange instance at its current point. Knowns: the continuous Real
    inputs (moved by STEP_REL times input_scale[name]) and the continuous states (by STEP_REL times
    their nominals)."""

    def __init__(self, fmu, md, input_scale):
        self.fmu, self.md, self.input_scale = fmu, md, input_scale
        self.vars = {v.name: v for v in md.modelVariables}
        self.state_names = [u.variable.derivative.name for u in md.derivatives]
        self.knowns = [v.name for v in md.modelVariables if v.causality == "input" and v.type == "Real"
                       and v.variability == "continuous"] + self.state_names

    def read(self, names):
        get = {"Real": self.fmu.getReal, "Integer": self.fmu.getInteger, "Enumeration": self.fmu.getInteger,
               "Boolean": self.fmu.getBoolean}
        return {n: get[self.vars[n].type]([self.vars[n].valueReference])[0] for n in names}

    def array(self, call):
        n = len(self.state_names)
        x = (ctypes.c_double * n)()
        call(x, n)
        return list(x)

    def move(self, known, delta):
        if known in self.state_names:
            x = self.array(self.fmu.getContinuousStates)
            x[self.state_names.index(known)] += delta
            self.fmu.setContinuousStates((ctypes.c_double * len(x))(*x), len(x))
        else:
            vr = self.vars[known].valueReference
            self.fmu.setReal([vr], [self.fmu.getReal([vr])[0] + delta])

    def feedthrough(self, names):
        """{(unknown, known)} of the pairs where moving the known alone moves the unknown."""
        fmu = self.fmu
        scale = dict(zip(self.state_names, self.array(fmu.getNominalsOfContinuousStates)), **self.input_scale)
        state = fmu.getFMUstate()
        base = self.read(names)
        moved = set()
        for known in self.knowns:
            for sign in (1.0, -1.0):
                self.move(known, sign * STEP_REL * scale[known])
                now = self.read(names)
                moved |= {(n, known) for n in names if now[n] != base[n]}
                fmu.setFMUstate(state)
        fmu.freeFMUstate(state)
        return moved


@pytest.mark.timeout(600)
def test_model_structure_is_the_measured_feedthrough(fmu_path, unzipdir, model_description):
    from fmpy import simulate_fmu
    from fmpy.fmi2 import FMU2Model

    md = model_description
    declared = unknowns(md)
    names = sorted(declared)
    measured = set()
    for name, modes in CASES.items():
        fmu = FMU2Model(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.modelExchange.modelIdentifier,
                        instanceName=name)
        fmu.instantiate()
        point, seen = Point(fmu, md, {"yC_in": 1e-5, "F_ext": 1e4, "vC_in": 0.1}), set()
        want = {m if isinstance(m, tuple) else (m, 0) for m in modes}

        def step_finished(time, recorder):
            mode = modes_of(point)
            if mode in seen or mode not in want or time <= 0.0:
                return True
            seen.add(mode)
            here = point.feedthrough(names)
            state = fmu.getFMUstate()
            fmu.setTime(time + 1e-6)  # inside an integrator step: the mean force covers a step of its own
            here |= point.feedthrough(names)
            fmu.setFMUstate(state)
            fmu.freeFMUstate(state)
            undeclared = sorted((n, k) for n, k in here if k not in declared[n])
            assert not undeclared, f"{name}, mode {mode}: moved by a known declared independent: {undeclared}"
            measured.update(here)
            return len(seen) < len(want)

        simulate_fmu(str(fmu_path), fmi_type="ModelExchange", solver="CVode", stop_time=0.02,
                     relative_tolerance=1e-9, start_values=EXTRA.get(name) or SCENARIOS[name].full, output_interval=1e-5,
                     fmu_instance=fmu, model_description=md, step_finished=step_finished, output=["y"])
        fmu.freeInstance()
        assert seen == want, (name, seen)
    never = sorted((n, k) for n, ks in declared.items() for k in ks if (n, k) not in measured)
    assert not never, f"declared dependencies never measured in any mode: {never}"


# Inputs and states of each companion model set to values none of which is zero, and the scale of
# each input (its size in the example).
COMPANIONS = {"LayerTest": ({"u": 0.7, "x": 1.3}, {"u": 1.0}),
              "Track": ({"F_contact": -4e4, "z_rail": -2e-4, "v_rail": 3e-3, "z_sleeper": -1e-4, "v_sleeper": 1e-3},
                        {"F_contact": 1e4}),
              "Vehicle": ({"y_wheel": 1e-4, "v_wheel": 2e-3, "z_body": -3e-4, "v_body": 1e-3, "W_dissipated": 5.0},
                          {"y_wheel": 1e-4, "v_wheel": 1e-2})}


@pytest.mark.parametrize("name", sorted(COMPANIONS))
def test_model_structure_of_the_other_models_is_the_measured_feedthrough(name, tmp_path):
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Model

    path = str(BUILD / f"{name}.fmu")
    md = read_model_description(path)
    fmu = FMU2Model(guid=md.guid, unzipDirectory=extract(path, unzipdir=str(tmp_path / "fmu")),
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName=name)
    fmu.instantiate()
    values, input_scale = COMPANIONS[name]
    point = Point(fmu, md, input_scale)
    assert sorted(values) == sorted(point.knowns), point.knowns  # every known is moved from a value of its own
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.newDiscreteStates()
    fmu.enterContinuousTimeMode()
    for known, value in values.items():
        point.move(known, value - (point.read([known])[known] if known not in point.state_names else
                                   point.array(fmu.getContinuousStates)[point.state_names.index(known)]))
    fmu.setTime(1e-3)  # after the inputs' time: the vehicle's wheel has moved on at v_wheel since
    declared = unknowns(md)
    measured = point.feedthrough(sorted(declared))
    fmu.terminate()
    fmu.freeInstance()
    undeclared = sorted((n, k) for n, k in measured if k not in declared[n])
    assert not undeclared, f"{name}: moved by a known declared independent: {undeclared}"
    never = sorted((n, k) for n, ks in declared.items() for k in ks if (n, k) not in measured)
    assert not never, f"{name}: declared dependencies not measured: {never}"
