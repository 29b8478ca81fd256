"""Model Exchange in every legal call order. In Continuous-Time Mode an importer may set the time, the
continuous states and the inputs in any order before it asks for derivatives, event indicators, outputs
or directional derivatives (FMI 2.0 section 3.2.3, FMI 3.0 section 3.2.2). Whatever the order, each
answer must be the one a fresh instance gives at the same (time, states, inputs): compared bit for bit,
with the reading itself done in each order too, in FMI 2.0 and FMI 3.0. The point is chosen so that every
read depends on each of the three: Hertz under the internal excitation, the mass in contact and moving,
so that a time, a state or an input left unapplied changes every answer (the negative control
test_a_call_left_out_changes_every_read)."""
import ctypes
import itertools
import math

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model
from fmpy.fmi3 import FMU3Model

from conftest import FMU, DEFAULTS, effective, with_solver
from vibroimpact.fmi3 import fmu3_path

NX = 3  # continuous states: y, v, W_damping

OUTPUTS = ("F", "delta", "y", "v", "yC", "F_mean", "k_contact")
READS = ("derivatives", "indicators", "outputs", "partials")
# Hertz, the mass pressed onto the platform (static start), then moved to another point of the contact; the
# platform shaken (yC = a (cos 2 pi f t - 1)), so that the contact at the new point depends on the time
A = 1e-5                                       # [m], a fifth of the static indentation (5.5e-5 m)
HERTZ = dict(contact_model=1, a=A)
T1, DY1, V1 = 1.3e-3, -2e-7, 0.011            # the new point: time [s], y - y0 [m], v [m/s]
YC_IN1, F_EXT1 = 3e-7, 1000.0                  # the new inputs [m], [N]


class Instance:
    """One Model Exchange instance of the FMI 2.0 or 3.0 FMU in Continuous-Time Mode, with the calls by
    name: set_time, set_states, set_inputs, and the four reads."""

    def __init__(self, version, md, unzipdir, params, inputs):
        self.version, self.md = version, md
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.nz = md.numberOfEventIndicators
        if version == 2:
            self.fmu = FMU2Model(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier="VibroImpact")
            self.fmu.instantiate(loggingOn=False)
            self.fmu.setupExperiment(startTime=0.0)
            self.fmu.enterInitializationMode()
            self._set_params(params)
            self.set_inputs(*inputs)
            self.fmu.exitInitializationMode()
            while True:
                more, terminate = self.fmu.newDiscreteStates()[:2]
                if not more or terminate:
                    break
        else:
            self.fmu = FMU3Model(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier="VibroImpact")
            self.fmu.instantiate()
            self.fmu.enterInitializationMode(startTime=0.0)
            self._set_params(params)
            self.set_inputs(*inputs)
            self.fmu.exitInitializationMode()
            while self.fmu.updateDiscreteStates()[0]:
                pass
        self.fmu.enterContinuousTimeMode()

    def _set_params(self, params):
        for name, value in with_solver(params).items():
            if self.version == 2:
                self.fmu.setInteger([self.vr[name]], [int(value)]) if isinstance(value, int) else \
                    self.fmu.setReal([self.vr[name]], [float(value)])
            else:
                self.fmu.setInt64([self.vr[name]], [int(value)]) if isinstance(value, int) else \
                    self.fmu.setFloat64([self.vr[name]], [float(value)])

    def _real(self, names):
        vrs = [self.vr[n] for n in names]
        return list(self.fmu.getReal(vrs) if self.version == 2 else self.fmu.getFloat64(vrs))

    def set_time(self, t):
        self.fmu.setTime(t)

    def set_states(self, x):
        x = list(x) + [0.0] * (NX - len(x))  # W_damping: 0 unless given
        self.fmu.setContinuousStates((ctypes.c_double * NX)(*x), NX)

    def set_inputs(self, yC_in, F_ext):
        vrs = [self.vr["yC_in"], self.vr["F_ext"]]
        (self.fmu.setReal if self.version == 2 else self.fmu.setFloat64)(vrs, [yC_in, F_ext])

    def apply(self, calls, t, x, u):
        """The calls of `calls` ("time", "states", "inputs") in that order, to the point t, x, u."""
        for call in calls:
            if call == "time":
                self.set_time(t)
            elif call == "states":
                self.set_states(x)
            else:
                self.set_inputs(*u)

    def states(self):
        x = (ctypes.c_double * NX)()
        self.fmu.getContinuousStates(x, NX)
        return list(x)

    def read(self, what):
        if what == "derivatives":
            dx = (ctypes.c_double * NX)()
            (self.fmu.getDerivatives if self.version == 2 else self.fmu.getContinuousStateDerivatives)(dx, NX)
            return list(dx)
        if what == "indicators":
            z = (ctypes.c_double * self.nz)()
            self.fmu.getEventIndicators(z, self.nz)
            return list(z)
        if what == "outputs":
            return self._real(OUTPUTS)
        unknowns = [self.vr[n] for n in ("der_y", "der_v", "F")]
        knowns = [self.vr[n] for n in ("y", "v", "yC_in", "F_ext")]
        out = []
        for k in knowns:  # one column of the Jacobian at a time
            if self.version == 2:
                out += list(self.fmu.getDirectionalDerivative(unknowns, [k], [1.0]))
            else:
                out += list(self.fmu.getDirectionalDerivative(unknowns, [k], [1.0], 3))
        return out

    def free(self):
        self.fmu.freeInstance()


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def fmu(request, tmp_path_factory):
    path = str(FMU if request.param == 2 else fmu3_path())
    md = read_model_description(path)
    return request.param, md, extract(path, unzipdir=str(tmp_path_factory.mktemp(f"order{request.param}")))


def point():
    """The new point: time, states (the mass DY1 from its rest on the platform under P + m g, moving at V1)
    and inputs."""
    e = effective(DEFAULTS)
    y_rest = -((DEFAULTS["P"] + DEFAULTS["m"] * DEFAULTS["g"]) / e["K"]) ** (2.0 / 3.0)
    return T1, [y_rest + DY1, V1], (YC_IN1, F_EXT1)


def fresh_reads(fmu, reads):
    """A fresh instance, started with the new inputs, set to the new point once: the reads in `reads` order."""
    version, md, unzipdir = fmu
    b = Instance(version, md, unzipdir, HERTZ, (YC_IN1, F_EXT1))
    t1, x1, _ = point()
    b.set_time(t1)
    b.set_states(x1)
    out = {r: b.read(r) for r in reads}
    b.free()
    return out


def test_the_point_is_an_elastic_contact_with_the_closed_form_force(fmu):
    """The reference point itself: Hertz, elastic, der(v) = (K delta^1.5 - P - m g + F_ext) / m, with delta
    the static indentation under P + m g - F_ext plus the mass's move down and the platform's move at T1."""
    version, md, unzipdir = fmu
    b = Instance(version, md, unzipdir, HERTZ, (YC_IN1, F_EXT1))
    y0 = b.states()[0]
    e = effective(DEFAULTS)
    W = DEFAULTS["P"] + DEFAULTS["m"] * DEFAULTS["g"]
    delta0 = ((W - F_EXT1) / e["K"]) ** (2.0 / 3.0)  # the static start: at rest under W - F_ext
    b.set_time(T1)
    b.set_states([y0 + DY1, V1])
    yC = A * (math.cos(2 * math.pi * DEFAULTS["f"] * T1) - 1)  # the platform's move from its start
    delta = delta0 - DY1 + yC  # the mass moved by DY1, the platform by yC (from yC_in)
    assert delta > 0 and abs(yC) > 0.1 * delta0  # in contact, and the time matters
    F = e["K"] * delta ** 1.5
    dv = b.read("derivatives")[1]
    assert dv == pytest.approx((F - W + F_EXT1) / DEFAULTS["m"], rel=1e-6)
    b.free()


@pytest.mark.parametrize("order", list(itertools.permutations(("time", "states", "inputs"))),
                         ids=lambda o: "-".join(o))
@pytest.mark.parametrize("first", READS)
def test_every_order_of_setting_gives_the_fresh_instance_answer(fmu, order, first):
    """Set the time, the states and the inputs in `order`, then read `first` before the other reads:
    each read equals a fresh instance's at the same point, bit for bit."""
    version, md, unzipdir = fmu
    a = Instance(version, md, unzipdir, HERTZ, (0.0, 0.0))
    t1, x1, u1 = point()
    a.read("derivatives")  # evaluated once at the old point, so that a stale value would be at hand
    a.read("outputs")
    a.apply(order, t1, x1, u1)
    reads = (first,) + tuple(r for r in READS if r != first)
    got = {r: a.read(r) for r in reads}
    a.free()
    want = fresh_reads(fmu, reads)
    for r in reads:
        assert np.array_equal(got[r], want[r]), (r, got[r], want[r])


@pytest.mark.parametrize("first", READS)
def test_inputs_set_again_after_a_read_count(fmu, first):
    """The measured failure: F_ext raised by 1000 N after the states were set and the derivatives read:
    der(v) must rise by 1000 N / m at once, in every read."""
    version, md, unzipdir = fmu
    a = Instance(version, md, unzipdir, HERTZ, (YC_IN1, 0.0))
    t1, x1, _ = point()
    a.set_time(t1)
    a.set_states(x1)
    before = a.read("derivatives")[1]
    a.set_inputs(YC_IN1, F_EXT1)
    reads = (first,) + tuple(r for r in READS if r != first)
    got = {r: a.read(r) for r in reads}
    a.free()
    assert got["derivatives"][1] - before == pytest.approx(F_EXT1 / DEFAULTS["m"], rel=1e-9)
    want = fresh_reads(fmu, reads)
    for r in reads:
        assert np.array_equal(got[r], want[r]), (r, got[r], want[r])


def test_reads_repeated_in_any_order_agree(fmu):
    """The reads do not change the instance: all 24 orders of the four reads give the same values."""
    version, md, unzipdir = fmu
    a = Instance(version, md, unzipdir, HERTZ, (0.0, 0.0))
    t1, x1, u1 = point()
    a.set_inputs(*u1)
    a.set_time(t1)
    a.set_states(x1)
    first = {r: a.read(r) for r in READS}
    for perm in itertools.permutations(READS):
        for r in perm:
            assert np.array_equal(a.read(r), first[r]), (perm, r)
    assert all(math.isfinite(v) for r in READS for v in first[r])
    a.free()


@pytest.mark.parametrize("left_out", ("time", "states", "inputs"))
def test_a_call_left_out_changes_every_read(fmu, left_out):
    """The negative control of the tests above: an importer that reads before it has set the time (or
    the states, or the inputs) gets other derivatives, indicators, outputs and partials than the fresh
    instance at the point, so a call the FMU applied late or not at all would fail them."""
    version, md, unzipdir = fmu
    a = Instance(version, md, unzipdir, HERTZ, (0.0, 0.0))
    t1, x1, u1 = point()
    a.read("derivatives")
    a.apply([c for c in ("time", "states", "inputs") if c != left_out], t1, x1, u1)
    got = {r: a.read(r) for r in READS}
    a.free()
    want = fresh_reads(fmu, READS)
    for r in READS:
        assert not np.array_equal(got[r], want[r]), (left_out, r, got[r])
    if left_out == "time":  # every output under test moves with the time (F_mean too)
        outputs = dict(zip(OUTPUTS, got["outputs"]))
        fresh = dict(zip(OUTPUTS, want["outputs"]))
        assert [n for n in OUTPUTS if outputs[n] == fresh[n]] == ["y", "v"]  # the states, which were set
