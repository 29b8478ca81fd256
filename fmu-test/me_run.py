"""Model Exchange runs of an FMU through fmpy's own integrator (CVode), with the FMU's log kept.

run_me(fmu_path, params, stop_time, ...) -> (result, messages): fmpy.simulate_fmu with
fmi_type='ModelExchange' on an instance whose logger records (status, category, text), with logEvents
on, so that every mode change is known with its exact time (vibroimpact.compare.fmu_events reads them).
"""
import ctypes

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model

from vibroimpact.compare import INTEGERS, REALS, fmu_events
from vibroimpact.fmu import MessageLog
from vibroimpact.reference.scenarios import SCENARIOS


class MeInstance(MessageLog):
    """An FMU2Model whose logger records (status, category, message) in `messages`."""

    def __init__(self, fmu_path, unzipdir=None, md=None, name="me"):
        super().__init__()
        self.md = md or read_model_description(str(fmu_path))
        self.unzipdir = unzipdir or extract(str(fmu_path))
        self.model = FMU2Model(guid=self.md.guid, unzipDirectory=self.unzipdir,
                               modelIdentifier=self.md.modelExchange.modelIdentifier, instanceName=name)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}

    def instantiate(self, categories=("logEvents",)):
        self.model.instantiate(callbacks=self.callbacks, loggingOn=False)
        if categories:
            self.model.setDebugLogging(True, list(categories))
        return self.model

    def errors(self):
        return [m for s, _, m in self.messages if s >= 3]


def run_me(fmu_path, params, stop_time, rtol=1e-10, output=("y", "v", "F", "mode"), output_interval=None,
           unzipdir=None, md=None, record_events=False, input=None, solver="CVode", step_size=None):
    """-> (fmpy result, MeInstance) of one Model Exchange run from t = 0."""
    inst = MeInstance(fmu_path, unzipdir, md)
    fmu = inst.instantiate()
    try:
        r = simulate_fmu(str(fmu_path), fmi_type="ModelExchange", solver=solver, start_time=0.0, stop_time=stop_time,
                         relative_tolerance=rtol, start_values=dict(params), output=list(output),
                         output_interval=output_interval, record_events=record_events, fmu_instance=fmu,
                         model_description=inst.md, input=input, step_size=step_size)
    finally:
        fmu.freeInstance()
    return r, inst


def on_grid(result, t, name):
    """The result's `name` at the times t (the recorder's regular points agree with t to rounding)."""
    return np.interp(t, result["time"], result[name])


class MeRunner:
    """vibroimpact.compare.Runner's interface (run(name, t, rtol, solver) -> (outputs on t, mode changes))
    for Model Exchange: fmpy's CVode integrates, output on the reference's grid."""

    def __init__(self, fmu_path, unzipdir=None):
        self.fmu_path, self.unzipdir = fmu_path, unzipdir or extract(str(fmu_path))
        self.md = read_model_description(str(fmu_path))

    def run(self, name, t, rtol, solver=None):
        assert solver is None, "the importer integrates: the FMU's solver parameter plays no part"
        r, inst = run_me(self.fmu_path, SCENARIOS[name].full, float(t[-1]), rtol=rtol, output=REALS + INTEGERS,
                         output_interval=float(t[1] - t[0]), unzipdir=self.unzipdir, md=self.md)
        assert not inst.errors(), inst.errors()
        return {n: on_grid(r, t, n) for n in REALS + INTEGERS}, fmu_events(inst.messages)


class Me:
    """Raw Model Exchange calls on an MeInstance with plain lists (fmpy raises FMICallException on an
    error or fatal status)."""

    def __init__(self, inst):
        self.inst, self.fmu, self.vr = inst, inst.model, inst.vr
        self.nx = inst.md.numberOfContinuousStates
        self.nz = inst.md.numberOfEventIndicators
        self.t = 0.0

    def start(self, params=None, start_time=0.0, tolerance=None):
        """Instantiated -> continuous-time mode after the initial event iteration; -> its event info."""
        f = self.fmu
        f.setupExperiment(tolerance=tolerance, startTime=start_time)
        f.enterInitializationMode()
        for name, value in (params or {}).items():
            self.set(name, value)
        f.exitInitializationMode()
        self.t = start_time
        info = self.settle()
        f.enterContinuousTimeMode()
        return info

    def settle(self):
        while True:
            info = self.fmu.newDiscreteStates()
            if not info[0] or info[1]:
                return info

    def set(self, name, value):
        v = next(v for v in self.inst.md.modelVariables if v.name == name)
        if v.type == "Real":
            self.fmu.setReal([v.valueReference], [float(value)])
        elif v.type == "Boolean":
            self.fmu.setBoolean([v.valueReference], [bool(value)])
        elif v.type == "String":
            self.fmu.setString([v.valueReference], [value])
        else:
            self.fmu.setInteger([v.valueReference], [int(value)])

    def real(self, name):
        return self.fmu.getReal([self.vr[name]])[0]

    def integer(self, name):
        return self.fmu.getInteger([self.vr[name]])[0]

    def _array(self, fn, n):
        a = (ctypes.c_double * max(n, 1))()
        fn(a, n)
        return list(a)[:n]

    def states(self):
        return self._array(self.fmu.getContinuousStates, self.nx)

    def set_states(self, x, n=None):
        self.fmu.setContinuousStates((ctypes.c_double * max(len(x), 1))(*x), len(x) if n is None else n)

    def derivatives(self):
        return self._array(self.fmu.getDerivatives, self.nx)

    def indicators(self):
        return self._array(self.fmu.getEventIndicators, self.nz)

    def nominals(self):
        return self._array(self.fmu.getNominalsOfContinuousStates, self.nx)

    def euler_to(self, t_end, h):
        """Forward Euler in continuous-time mode from the FMU's state to t_end with steps h, stopping at
        the first step whose event indicators changed sign; -> (time reached, crossed)."""
        t, x, z = self.t, self.states(), self.indicators()
        while t < t_end - 1e-15:
            dx = self.derivatives()
            t = min(t + h, t_end)
            x = [a + h * b for a, b in zip(x, dx)]
            self.fmu.setTime(t)
            self.set_states(x)
            self.t = t
            z_new = self.indicators()
            if any((a > 0) != (b > 0) for a, b in zip(z, z_new)):
                return t, True
            enter, _ = self.fmu.completedIntegratorStep()
            z = z_new
            if enter:
                return t, True
        return t, False
