"""ModelStructure (generated from the table's depends column) against measured feedthrough.

Scenarios that together reach all five modes and the three laws run in Model Exchange (fmpy's
CVode). At the first completed step in each mode, with the instance in continuous-time mode and an
FMU state taken, and again 1e-6 s later (fmi2SetTime inside the step, where the
mean force covers a step of its own), each known (the inputs yC_in and F_ext, the states y and v) is moved by
+-1e-3 of its scale alone, and every output and state derivative is read again: a value that
changes depends on that known. An output or derivative must not move with a known it is declared
independent of, at any point; and every declared dependency must be seen at some point (the
declaration is the union over the modes, no wider).
"""
import ctypes

import pytest

from vibroimpact.reference.scenarios import SCENARIOS

STEP_REL = 1e-3
# scenario -> modes it reaches within 0.02 s (as in test_me_jacobian.py: all five modes, every law)
CASES = {"fig5c": [0, 1], "fig4b": [0, 1, 2, 3], "stick": [2, 3, 4], "continuous": [0, 1, 2, 3], "fig4c": [0, 1, 2],
         "fig6a": [0, 1, 2]}
KNOWNS = ["yC_in", "F_ext", "y", "v"]


def unknowns(md):
    """The outputs and state derivatives with their declared dependencies (names)."""
    return {u.variable.name: {d.name for d in u.dependencies} for u in md.outputs + md.derivatives}


class Point:
    """Reads and moves one Model Exchange instance at its current point."""

    def __init__(self, fmu, md):
        self.fmu, self.md = fmu, md
        self.vars = {v.name: v for v in md.modelVariables}

    def read(self, names):
        get = {"Real": self.fmu.getReal, "Integer": self.fmu.getInteger, "Enumeration": self.fmu.getInteger,
               "Boolean": self.fmu.getBoolean}
        return {n: get[self.vars[n].type]([self.vars[n].valueReference])[0] for n in names}

    def states(self):
        x = (ctypes.c_double * 2)()
        self.fmu.getContinuousStates(x, 2)
        return list(x)

    def move(self, known, delta):
        if known in ("y", "v"):
            x = self.states()
            x[0 if known == "y" else 1] += delta
            self.fmu.setContinuousStates((ctypes.c_double * 2)(*x), 2)
        else:
            vr = self.vars[known].valueReference
            self.fmu.setReal([vr], [self.fmu.getReal([vr])[0] + delta])

    def feedthrough(self, names):
        """{(unknown, known)} of the pairs where moving the known alone moves the unknown."""
        fmu = self.fmu
        x = (ctypes.c_double * 2)()
        fmu.getNominalsOfContinuousStates(x, 2)
        scale = {"y": x[0], "v": x[1], "yC_in": x[0], "F_ext": 1e4}
        state = fmu.getFMUstate()
        base = self.read(names)
        moved = set()
        for known in KNOWNS:
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
        point, seen = Point(fmu, md), set()

        def step_finished(time, recorder):
            mode = point.read(["mode"])["mode"]
            if mode in seen or time <= 0.0:
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
            return len(seen) < len(modes)

        simulate_fmu(str(fmu_path), fmi_type="ModelExchange", solver="CVode", stop_time=0.02,
                     relative_tolerance=1e-9, start_values=SCENARIOS[name].full, output_interval=1e-5,
                     fmu_instance=fmu, model_description=md, step_finished=step_finished, output=["y"])
        fmu.freeInstance()
        assert seen == set(modes), (name, seen)
    never = sorted((n, k) for n, ks in declared.items() for k in ks if (n, k) not in measured)
    assert not never, f"declared dependencies never measured in any mode: {never}"
