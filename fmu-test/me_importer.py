"""An independent Model Exchange importer for the tests: Dormand-Prince 8(5,3) from SciPy, stepped by
hand, with every input set at the evaluation's time before each call of fmi2GetDerivatives and
fmi2GetEventIndicators (as a multibody or vehicle-track master does), the event indicators watched
for a fall through zero at every step and their crossing located on the step's dense output, then
the event iteration. It shares no code with the FMU's own drivers or the package's ME helpers, so
that a test compares the FMU with an importer it was not written against."""
import ctypes
import math

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model
from fmpy.fmi3 import FMU3Model
from scipy.integrate import DOP853
from scipy.optimize import brentq
from vibroimpact.fmu import MessageLog, Messages

MAX_STEPS = 2_000_000   # a run that needs more is a failure of the test, not a hang
MAX_PASSES = 100        # event iteration passes at one instant


class Stopped(Exception):
    """The FMU asked to terminate, or an FMI call failed: the message says where."""


class Importer:
    """One ME run of an FMI 2.0 or 3.0 FMU: params {name: value}, inputs {name: function of t}; messages
    keeps what the FMU logged."""

    def __init__(self, fmu, params=None, inputs=None, rtol=1e-8, tolerance=None, max_step=1e-5):
        md = read_model_description(fmu)
        self.fmi3 = md.fmiVersion.startswith("3")
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.types = {v.name: v.type for v in md.modelVariables}
        self.nx, self.nz = md.numberOfContinuousStates, md.numberOfEventIndicators
        self.inputs = dict(inputs or {})
        self.rtol, self.max_step = rtol, max_step   # max_step [s]: no crossing of an indicator is stepped over
        self.events = []            # (t, indicator or None for a step event)
        self.messages = Messages()
        kind = FMU3Model if self.fmi3 else FMU2Model
        self.model = kind(guid=md.guid, unzipDirectory=extract(fmu), modelIdentifier=md.modelExchange.modelIdentifier,
                          instanceName="me")
        self.t = 0.0
        f = self.model
        if self.fmi3:
            f.instantiate(logMessage=self._log3)
            f.enterInitializationMode(tolerance=tolerance or rtol, startTime=0.0)
        else:
            self._log2 = MessageLog()
            self.messages = self._log2
            f.instantiate(callbacks=self._log2.callbacks, loggingOn=False)
            f.setupExperiment(tolerance=tolerance or rtol, startTime=0.0)
            f.enterInitializationMode()
        for name, value in (params or {}).items():
            self._set(name, value)
        self._set_inputs(0.0)
        f.exitInitializationMode()
        self._iterate()
        f.enterContinuousTimeMode()
        self.x = self._states()

    def _log3(self, env, status, category, message):
        self.messages.keep(status, category, message.decode("utf-8", "replace"))

    def _set(self, name, value):
        vr, kind = [self.vr[name]], self.types[name]
        if kind in ("Real", "Float64"):
            (self.model.setFloat64 if self.fmi3 else self.model.setReal)(vr, [float(value)])
        elif kind == "Boolean":
            self.model.setBoolean(vr, [bool(value)])
        elif self.fmi3:
            (self.model.setInt64 if kind == "Enumeration" else self.model.setInt32)(vr, [int(value)])
        else:
            self.model.setInteger(vr, [int(value)])

    def _set_inputs(self, t):
        for name, fn in self.inputs.items():
            self._set(name, fn(t))

    def _array(self, fn, n):
        a = (ctypes.c_double * max(n, 1))()
        fn(a, n)
        return np.array(a[:n])

    def _states(self):
        return self._array(self.model.getContinuousStates, self.nx)

    def _at(self, t, x):
        f = self.model
        f.setTime(t)
        self._set_inputs(t)
        f.setContinuousStates((ctypes.c_double * self.nx)(*x), self.nx)

    def derivatives(self, t, x):
        self._at(t, x)
        get = self.model.getContinuousStateDerivatives if self.fmi3 else self.model.getDerivatives
        return self._array(get, self.nx)

    def indicators(self, t, x):
        self._at(t, x)
        return self._array(self.model.getEventIndicators, self.nz)

    def _iterate(self):
        for _ in range(MAX_PASSES):
            info = self.model.updateDiscreteStates() if self.fmi3 else self.model.newDiscreteStates()
            if info[1]:
                raise Stopped(f"the FMU terminated at t = {self.t!r}")
            if not info[0]:
                return
        raise Stopped(f"the event iteration did not settle at t = {self.t!r}")

    def real(self, name):
        return (self.model.getFloat64 if self.fmi3 else self.model.getReal)([self.vr[name]])[0]

    def integer(self, name):
        if self.fmi3:
            return (self.model.getInt64 if self.types[name] == "Enumeration" else self.model.getInt32)([self.vr[name]])[0]
        return self.model.getInteger([self.vr[name]])[0]

    def _crossing(self, sol, t0, t1, z0):
        """The first indicator falling through zero inside (t0, t1] on the dense output: (time just past
        it, index), or None."""
        z1 = self.indicators(t1, sol(t1))
        first = None
        for i in range(self.nz):
            if z0[i] > 0.0 and z1[i] <= 0.0:
                g = (lambda s, i=i: self.indicators(s, sol(s))[i])
                tc = brentq(g, t0, t1, xtol=1e-16 * max(1.0, abs(t1)), rtol=4 * np.finfo(float).eps)
                if first is None or tc < first[0]:
                    first = (tc, i)
        if first is None:
            return None
        tc, i = first
        for _ in range(64):  # the first representable time past the crossing
            if self.indicators(tc, sol(tc))[i] <= 0.0 or tc >= t1:
                break
            tc = min(np.nextafter(tc, math.inf) + 1e-15 * abs(tc), t1)
        return tc, i

    def run(self, t_end, record=None):
        """Integrate to t_end; record(self, t) is called at each accepted step end and event."""
        atol = self.rtol * np.array(self._nominals())
        solver = DOP853(self.derivatives, self.t, self.x, t_end, rtol=self.rtol, atol=atol, max_step=self.max_step)
        z0 = self.indicators(self.t, self.x)
        for _ in range(MAX_STEPS):
            if self.t >= t_end:
                return
            t_prev = self.t
            solver.step()
            if solver.status == "failed":
                raise Stopped(f"the integrator failed at t = {solver.t!r}")
            hit = self._crossing(solver.dense_output(), t_prev, solver.t, z0)
            t = hit[0] if hit else solver.t
            x = solver.dense_output()(t) if hit else solver.y
            self._at(t, x)
            self.t, self.x = t, x
            enter, terminate = self.model.completedIntegratorStep()[:2]
            if terminate:
                raise Stopped(f"the FMU terminated at t = {t!r}")
            if hit or enter:
                self.events.append((t, hit[1] if hit else None))
                self.model.enterEventMode()
                self._iterate()
                self.model.enterContinuousTimeMode()
                self.x = self._states()
                solver = DOP853(self.derivatives, self.t, self.x, t_end, rtol=self.rtol, atol=atol, max_step=self.max_step)
            if record:
                self._at(self.t, self.x)  # the integrator's last evaluation may lie ahead
                record(self, self.t)
            z0 = self.indicators(self.t, self.x)
        raise Stopped(f"more than {MAX_STEPS} steps before t = {t_end}")

    def _nominals(self):
        return list(self._array(self.model.getNominalsOfContinuousStates, self.nx))
