"""Non-finite and negative arguments of the stepping calls, on VibroImpact itself, in Co-Simulation and
Model Exchange, FMI 2.0 and 3.0: a communication step size of +inf, -inf, NaN or below zero and a
communication point that is not finite (fmi2DoStep, fmi3DoStep); a time that is not finite
(fmi2SetTime, fmi3SetTime) and continuous states that are not finite (fmi2SetContinuousStates,
fmi3SetContinuousStates). Each is refused with Error (an argument no step can have: the step "could not
be carried out at all", not Discard) and a message that names the argument and its value; the instance
is left as it was (time, states, outputs bit for bit) and goes on: the next good call works and gives
what an instance never given the bad one gives."""
import ctypes
import math

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave, fmi3Boolean, fmi3Float64

from conftest import FMU, with_solver
from vibroimpact.fmi3 import fmu3_path
from vibroimpact.fmu import MessageLog, Messages

ERROR = 3  # fmi2Error, fmi3Error
OUTPUTS = ("y", "v", "F", "delta", "yC", "E_contact")
PARAMS = dict(contact_model=1, a=1e-5)  # Hertz on the shaken platform: the state moves with every step
INF, NAN = float("inf"), float("nan")
NX = 3  # y, v, W_damping


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def fmu(request, tmp_path_factory):
    path = str(FMU if request.param == 2 else fmu3_path())
    md = read_model_description(path)
    return request.param, md, extract(path, unzipdir=str(tmp_path_factory.mktemp(f"bad{request.param}")))


class Instance:
    """One instance of either version and interface, initialized with PARAMS (and VI_SOLVER's solver),
    whose raw calls return their status and whose logger keeps the messages."""

    def __init__(self, fmu, interface):
        self.version, md, unzipdir = fmu
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.ints = {v.name for v in md.modelVariables if v.type in ("Integer", "Int32", "Int64", "Enumeration")}
        kind = {(2, "cs"): FMU2Slave, (2, "me"): FMU2Model, (3, "cs"): FMU3Slave, (3, "me"): FMU3Model}
        self.f = kind[self.version, interface](guid=md.guid, unzipDirectory=unzipdir, modelIdentifier="VibroImpact")
        if self.version == 2:
            self.log = MessageLog()
            self.f.instantiate(callbacks=self.log.callbacks)
            self.f.setupExperiment(startTime=0.0)
            self.f.enterInitializationMode()
        else:
            self.log = Messages()
            self._logger = lambda env, status, category, message: self.log.keep(
                status, category, message.decode("utf-8", "replace"))
            self.f.instantiate(logMessage=self._logger)
            self.f.enterInitializationMode(startTime=0.0)
        for name, value in with_solver(PARAMS).items():
            if name in self.ints:
                (self.f.setInteger if self.version == 2 else self.f.setInt64)([self.vr[name]], [int(value)])
            else:
                (self.f.setReal if self.version == 2 else self.f.setFloat64)([self.vr[name]], [float(value)])
        self.f.exitInitializationMode()
        if interface == "me":
            while (self.f.newDiscreteStates()[0] if self.version == 2 else self.f.updateDiscreteStates()[0]):
                pass
            self.f.enterContinuousTimeMode()

    def do_step(self, t, h):
        if self.version == 2:
            return self._status(lambda: self.f.fmi2DoStep(self.f.component, t, h, 1))
        event, terminate, early, last = fmi3Boolean(), fmi3Boolean(), fmi3Boolean(), fmi3Float64()
        return self._status(lambda: self.f.fmi3DoStep(self.f.component, t, h, fmi3Boolean(True), ctypes.byref(event),
                                                        ctypes.byref(terminate), ctypes.byref(early), ctypes.byref(last)))

    def set_time(self, t):
        return self._status(lambda: getattr(self.f, f"fmi{self.version}SetTime")(self.f.component, t))

    def set_states(self, x):
        return self._status(lambda: getattr(self.f, f"fmi{self.version}SetContinuousStates")(
            self.f.component, (ctypes.c_double * NX)(*x), NX))

    @staticmethod
    def _status(call):
        try:
            return call()
        except FMICallException as e:
            return e.status

    def outputs(self):
        vrs = [self.vr[n] for n in OUTPUTS]
        return list(self.f.getReal(vrs) if self.version == 2 else self.f.getFloat64(vrs))

    def states(self):
        x = (ctypes.c_double * NX)()
        self.f.getContinuousStates(x, NX)
        return list(x)

    def derivatives(self):
        dx = (ctypes.c_double * NX)()
        (self.f.getDerivatives if self.version == 2 else self.f.getContinuousStateDerivatives)(dx, NX)
        return list(dx)

    def errors(self):
        return [m for status, _, m in self.log.messages if status == ERROR]

    def free(self):
        self.f.freeInstance()


H = 1e-4  # [s], a good communication step


@pytest.mark.parametrize("tc, h, names", [
    (0.0, INF, ("communication step size", "inf")), (0.0, -INF, ("communication step size", "-inf")),
    (0.0, NAN, ("communication step size", "nan")), (0.0, -1e-3, ("communication step size", "-0.001")),
    (INF, H, ("currentCommunicationPoint", "inf")), (NAN, H, ("currentCommunicationPoint", "nan")),
    (-INF, H, ("currentCommunicationPoint", "-inf"))],
    ids=["h=inf", "h=-inf", "h=nan", "h<0", "tc=inf", "tc=nan", "tc=-inf"])
def test_a_bad_step_is_refused_and_the_instance_goes_on(fmu, tc, h, names):
    version = fmu[0]
    s, fresh = Instance(fmu, "cs"), Instance(fmu, "cs")
    assert s.do_step(0.0, H) == 0 and fresh.do_step(0.0, H) == 0
    before = s.outputs()
    tc = H if tc == 0.0 else tc  # at the instance's time
    assert s.do_step(tc, h) == ERROR
    errors = s.errors()
    assert len(errors) == 1 and f"fmi{version}DoStep" in errors[0] and all(n in errors[0] for n in names), errors
    assert s.outputs() == before  # nothing was done
    assert s.do_step(H, H) == 0 and fresh.do_step(H, H) == 0
    assert s.outputs() == fresh.outputs()  # and goes on as if it had never been asked
    assert len(s.errors()) == 1
    s.free()
    fresh.free()


@pytest.mark.parametrize("t", [INF, -INF, NAN], ids=["inf", "-inf", "nan"])
def test_a_time_that_is_not_finite_is_refused(fmu, t):
    version = fmu[0]
    m = Instance(fmu, "me")
    assert m.set_time(2e-4) == 0
    x, dx, out = m.states(), m.derivatives(), m.outputs()
    assert m.set_time(t) == ERROR
    errors = m.errors()
    assert len(errors) == 1 and f"fmi{version}SetTime" in errors[0] and f"time {t:g} is not finite" in errors[0], errors
    assert (m.states(), m.derivatives(), m.outputs()) == (x, dx, out)  # still at t = 2e-4 s
    assert m.set_time(3e-4) == 0 and m.derivatives() != dx  # the platform moved: the time was taken
    m.free()


@pytest.mark.parametrize("i, value", [(0, INF), (1, NAN), (2, -INF), (0, NAN)])
def test_states_that_are_not_finite_are_refused(fmu, i, value):
    version = fmu[0]
    m = Instance(fmu, "me")
    assert m.set_time(1e-4) == 0
    x, dx = m.states(), m.derivatives()
    bad = list(x)
    bad[i] = value
    assert m.set_states(bad) == ERROR
    errors = m.errors()
    name = ("y", "v", "W_damping")[i]
    assert len(errors) == 1 and f"fmi{version}SetContinuousStates" in errors[0] and \
        f"state {i} ({name}) = {value:g} is not finite; nothing was set" in errors[0], errors
    assert m.states() == x and m.derivatives() == dx
    moved = list(x)
    moved[0] -= 1e-7  # a good set then works: the mass 0.1 um lower, the contact force up
    assert m.set_states(moved) == 0 and m.states() == moved and m.derivatives()[1] > dx[1]
    assert all(math.isfinite(v) for v in m.outputs()) and np.all(np.isfinite(m.derivatives()))
    m.free()
