"""Model Exchange runs of an FMU through fmpy's own integrator (CVode), with the FMU's log kept.

run_me(fmu_path, params, stop_time, ...) -> (result, messages): fmpy.simulate_fmu with
fmi_type='ModelExchange' on an instance whose logger records (status, category, text), with logEvents
on, so that every mode change is known with its exact time (compare_reference.fmu_events reads them).
"""
import ctypes

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, \
    fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE

calloc = ctypes.cdll.LoadLibrary(None).calloc
calloc.restype, calloc.argtypes = ctypes.c_void_p, [ctypes.c_size_t, ctypes.c_size_t]
free = ctypes.cdll.LoadLibrary(None).free
free.argtypes = [ctypes.c_void_p]


class MeInstance:
    """An FMU2Model whose logger records (status, category, message)."""

    def __init__(self, fmu_path, unzipdir=None, md=None, name="me"):
        self.md = md or read_model_description(str(fmu_path))
        self.unzipdir = unzipdir or extract(str(fmu_path))
        self.messages = []
        self.model = FMU2Model(guid=self.md.guid, unzipDirectory=self.unzipdir,
                               modelIdentifier=self.md.modelExchange.modelIdentifier, instanceName=name)
        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(self._log)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self.callbacks = cb
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}

    def _log(self, env, name, status, category, message):
        self.messages.append((status, category.decode(), message.decode().replace("%%", "%")))

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
    """compare_reference.Runner's interface (run(name, t, rtol, solver) -> (outputs on t, mode changes))
    for Model Exchange: fmpy's CVode integrates, output on the reference's grid."""

    def __init__(self, fmu_path, unzipdir=None):
        self.fmu_path, self.unzipdir = fmu_path, unzipdir or extract(str(fmu_path))
        self.md = read_model_description(str(fmu_path))

    def run(self, name, t, rtol, solver=None):
        from compare_reference import INTEGERS, REALS, SCENARIOS, fmu_events
        assert solver is None, "the importer integrates: the FMU's solver parameter plays no part"
        r, inst = run_me(self.fmu_path, SCENARIOS[name].full, float(t[-1]), rtol=rtol, output=REALS + INTEGERS,
                         output_interval=float(t[1] - t[0]), unzipdir=self.unzipdir, md=self.md)
        assert not inst.errors(), inst.errors()
        return {n: on_grid(r, t, n) for n in REALS + INTEGERS}, fmu_events(inst.messages)
