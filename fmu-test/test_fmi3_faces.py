"""The same robustness tests against both faces of the layer, FMI 2.0 (build/VibroImpact.fmu) and
FMI 3.0 (build/fmi3/VibroImpact.fmu): rollback and serialized states continue bit for bit, altered
or foreign states are refused with the reason, bad calls and bad values are refused with a message
naming the variable and leave the instance usable, and no function crashes on a NULL instance.
Both faces share one layer (src/fmi/vi_fmi_*.c), so these tests hold the FMI 3.0 face to everything
the FMI 2.0 one was tested for; the FMI 2.0 suites (test_fmi.py, test_state.py, test_rollback.py,
test_status.py) go further on the FMI 2.0 face alone."""
import ctypes
import math

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2LastSuccessfulTime

from conftest import BUILD
from solvers import each_solver
from vibroimpact import fmi3
from vibroimpact.fmu import MessageLog, set_value

OK, DISCARD, ERROR = 0, 2, 3


class Face:
    """One instance of the FMI 2.0 or FMI 3.0 build of a model behind the same calls."""

    def __init__(self, version, model, name="instance"):
        self.version, self.model = version, model
        path = BUILD / ("" if version == 2 else "fmi3") / f"{model}.fmu"
        self.md = read_model_description(str(path))
        self.dir = _extracted(path)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.kinds = {v.name: v.type for v in self.md.modelVariables}
        if version == 2:
            self.log = MessageLog()
            self.s = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir, modelIdentifier=model, instanceName=name)
            self.s.instantiate(callbacks=self.log.callbacks)
        else:
            self.log = fmi3.Logged(self.md, self.dir, name=name)
            self.log.instantiate()
            self.s = self.log.slave
        self.fn = lambda base: f"fmi{version}{base}" if version == 3 else f"fmi2{base.replace('State', 'state')}"

    @property
    def messages(self):
        return self.log.messages

    def errors(self):
        return [m for st, _, m in self.messages if st == ERROR]

    def raw(self, base, *args):
        """fmi<v><base> on this instance; its status (fmpy raises on errors)."""
        try:
            return getattr(self.s, self.fn(base.replace("DeserializeFMUState", "DeSerializeFMUState")
                                           if self.version == 2 else base))(self.s.component, *args)
        except FMICallException as e:
            return e.status

    def init(self, params, tolerance=None, stop_time=None):
        if self.version == 2:
            self.s.setupExperiment(tolerance=tolerance, startTime=0.0, stopTime=stop_time)
            self.s.enterInitializationMode()
            for name, value in params.items():
                set_value(self.s, self.vr[name], value, self.kinds[name])
            self.s.exitInitializationMode()
        else:
            fmi3.initialize(self.s, self.vr, params, kinds=self.kinds, tolerance=tolerance, stop_time=stop_time)

    def step(self, t, h):
        if self.version == 3:
            return fmi3.do_step(self.s, t, h)[0]
        try:
            self.s.doStep(t, h)
            return OK
        except FMICallException as e:
            return e.status

    def reals(self, *names):
        get = self.s.getReal if self.version == 2 else self.s.getFloat64
        return get([self.vr[n] for n in names])

    def set_real(self, name, value):
        vr, v = (ctypes.c_uint * 1)(self.vr[name]), (ctypes.c_double * 1)(value)
        return self.raw("SetReal", vr, 1, v) if self.version == 2 else self.raw("SetFloat64", vr, 1, v, 1)

    def mode(self):
        return (self.s.getInteger if self.version == 2 else self.s.getInt64)([self.vr["mode"]])[0]

    def get_state(self):
        return self.s.getFMUstate() if self.version == 2 else self.s.getFMUState()

    def set_state(self, state):
        return self.s.setFMUstate(state) if self.version == 2 else self.s.setFMUState(state)

    def free_state(self, state):
        return self.s.freeFMUstate(state) if self.version == 2 else self.s.freeFMUState(state)

    def serialize(self, state):
        return self.s.serializeFMUstate(state) if self.version == 2 else self.s.serializeFMUState(state)

    def deserialize(self, blob):
        """The state, or the status when it was refused."""
        try:
            return self.s.deSerializeFMUstate(blob) if self.version == 2 else self.s.deserializeFMUState(blob)
        except FMICallException as e:
            return e.status

    def free(self):
        self.s.freeInstance()


_EXTRACTED = {}


def _extracted(path):
    if path not in _EXTRACTED:
        _EXTRACTED[path] = extract(str(path))
    return _EXTRACTED[path]


each_face = pytest.mark.parametrize("version", [2, 3], ids=["fmi2", "fmi3"])
FIG4B = dict(contact_model=2, Y=6e8, a=1e-4)  # Johnson: yield, unloading, separations
H = 2e-5


@pytest.fixture
def faces():
    made = []

    def make(version, model="VibroImpact", **kw):
        made.append(Face(version, model, **kw))
        return made[-1]

    yield make
    for f in made:
        f.free()


def run(f, t0, n):
    out = []
    for k in range(n):
        assert f.step(t0 + k * H, H) == OK
        out.append(f.reals("y", "v", "F", "W_plastic") + [f.mode()])
    return np.array(out)


# ---- FMU states ------------------------------------------------------------------------------------------

@each_solver
@each_face
def test_rollback_and_serialized_states_continue_bit_for_bit(version, solver, faces):
    f = faces(version)
    f.init({**FIG4B, "solver": solver})
    run(f, 0.0, 250)
    state = f.get_state()
    a = run(f, 250 * H, 500)
    f.set_state(state)
    b = run(f, 250 * H, 500)
    assert len(set(a[:, -1])) >= 3, "too few modes after the save to prove much"
    np.testing.assert_array_equal(a, b)
    blob = f.serialize(state)
    f.free_state(state)
    fresh = faces(version)
    fresh.init({**FIG4B, "solver": solver})
    fresh.set_state(fresh.deserialize(blob))
    np.testing.assert_array_equal(run(fresh, 250 * H, 500), a)


def test_a_state_moves_between_the_faces(faces):
    """One core, one state format: a state serialized by one face continues bit for bit in the
    other; a state taken in FMI 3.0's Event Mode is refused by the FMI 2.0 face, which has none."""
    f2, f3 = faces(2), faces(3)
    f2.init(FIG4B)
    f3.init(FIG4B)
    run(f2, 0.0, 100)
    blob = f2.serialize(f2.get_state())
    a = run(f2, 100 * H, 300)
    f3.set_state(f3.deserialize(blob))
    np.testing.assert_array_equal(run(f3, 100 * H, 300), a)
    log = fmi3.Logged(f3.md, f3.dir)
    s = log.instantiate(event_mode=True)
    fmi3.initialize(s, f3.vr, FIG4B, kinds=f3.kinds)  # Event Mode after initialization
    event_blob = s.serializeFMUState(s.getFMUState())
    s.freeInstance()
    assert f2.deserialize(event_blob) == ERROR
    assert "event mode" in f2.errors()[-1] and "never is in" in f2.errors()[-1]


@each_face
def test_altered_truncated_and_foreign_states_are_refused(version, faces):
    f = faces(version)
    f.init(FIG4B)
    run(f, 0.0, 100)
    blob = f.serialize(f.get_state())
    flipped = []
    for byte in range(0, len(blob), 7):  # a bit flip in every 7th byte (test_state.py flips every bit)
        b = bytearray(blob)
        b[byte] ^= 1 << (byte % 8)
        got = f.deserialize(bytes(b))
        if got != ERROR:
            flipped.append(byte)
            f.free_state(got)
    assert flipped == []
    assert any("checksum" in m for m in f.errors())
    assert f.deserialize(blob[:-1]) == ERROR and "size" in f.errors()[-1]
    other = faces(version, "LayerTest")
    other.init({})
    assert f.deserialize(other.serialize(other.get_state())) == ERROR and "another model" in f.errors()[-1]
    assert f.raw("SetFMUState", None) == ERROR and "NULL" in f.errors()[-1]
    f.set_state(f.deserialize(blob))  # the intact state still is accepted, and the instance goes on
    assert f.step(100 * H, H) == OK


# ---- bad calls and bad values ----------------------------------------------------------------------------

@each_face
def test_calls_in_the_wrong_state_are_refused_and_change_nothing(version, faces):
    """Each call refused in a state it is not allowed in leaves the instance as it was: the values
    read before and after are the same, and the run that follows is bit for bit that of an instance
    that got no refused call."""
    f, plain = faces(version), faces(version, name="plain")
    assert f.step(0.0, H) == ERROR and "not allowed in state 'instantiated'" in f.errors()[-1]
    assert f.raw("Terminate") == ERROR
    f.init(FIG4B)
    plain.init(FIG4B)
    np.testing.assert_array_equal(run(f, 0.0, 100), run(plain, 0.0, 100))
    before = f.reals("y", "v", "F", "W_plastic")
    assert f.raw("EnterInitializationMode", *([] if version == 2 else [False, 0.0, 0.0, False, 0.0])) == ERROR
    assert f.raw("ExitInitializationMode") == ERROR
    assert f.reals("y", "v", "F", "W_plastic") == before
    np.testing.assert_array_equal(run(f, 100 * H, 100), run(plain, 100 * H, 100))
    at_end = f.reals("y", "v", "F", "W_plastic")
    f.s.terminate()
    assert f.step(200 * H, H) == ERROR and "terminated" in f.errors()[-1]
    assert f.raw("Terminate") == ERROR
    assert f.reals("y", "v", "F", "W_plastic") == at_end
    f.s.reset()
    f.init(FIG4B)
    assert f.step(0.0, H) == OK


@each_face
def test_bad_values_are_refused_naming_the_variable(version, faces):
    f = faces(version)
    f.init(FIG4B, stop_time=0.01)
    assert f.set_real("F_ext", math.nan) == ERROR and "F_ext must be finite" in f.errors()[-1]
    assert f.set_real("m", 1.0) == ERROR and "m is a fixed parameter" in f.errors()[-1]
    assert f.set_real("F", 1.0) == ERROR and "F is an output" in f.errors()[-1]
    assert f.set_real("contact_model", 1.0) == ERROR and "contact_model" in f.errors()[-1]
    vr = (ctypes.c_uint * 1)(9999)
    d = (ctypes.c_double * 1)()
    assert f.raw(*(("GetReal", vr, 1, d) if version == 2 else ("GetFloat64", vr, 1, d, 1))) == ERROR
    assert "unknown value reference 9999" in f.errors()[-1]
    s = (ctypes.c_char_p * 1)(b"x" * 2000)
    svr = (ctypes.c_uint * 1)(f.vr["profile_file"])
    f.s.terminate(), f.s.reset()
    assert f.raw(*(("SetString", svr, 1, s) if version == 2 else ("SetString", svr, 1, s, 1))) == ERROR
    assert "profile_file is longer than 1023" in f.errors()[-1]
    f.init(FIG4B, stop_time=0.01)
    for t, h, words in [(0.0, -H, "finite and positive"), (0.0, math.inf, "finite and positive"),
                        (1e-3, H, "does not match"), (0.0, 1e-20, "too short"), (0.0, 0.02, "stop time")]:
        assert f.step(t, h) == ERROR and words in f.errors()[-1], (t, h)
    assert f.reals("F_ext") == [0.0]
    assert f.step(0.0, H) == OK  # every refusal left the instance as it was


@each_face
def test_a_failed_initialization_and_a_discarded_step(version, faces, tmp_path):
    f = faces(version)
    f.s.enterInitializationMode()
    assert f.set_real("m", -1.0) == ERROR and "m = -1 is outside its range" in f.errors()[-1]
    f.set_real("max_step", 1e-13)  # in its range, but no step the solver can take: refused at initialization
    assert f.raw("ExitInitializationMode") == ERROR and "max_step" in f.errors()[-1]
    assert f.step(0.0, H) == ERROR  # the error state
    f.s.reset()
    profile = tmp_path / "p.txt"
    profile.write_text("0 0\n0.01 0\n")
    f.init(dict(profile_file=str(profile), V=1.0))  # rolls off the profile's end at 10 ms
    assert f.step(0.0, 5e-3) == OK
    assert f.step(5e-3, 1e-2) == DISCARD
    assert any(st == DISCARD for st, _, _ in f.messages)
    t = f.s.getRealStatus(fmi2LastSuccessfulTime) if version == 2 else f.reals("time")[0]
    assert t == pytest.approx(1e-2, abs=1e-15)
    assert f.step(t, H) == ERROR  # step failed / step discarded: no more steps
    f.s.terminate()


@each_face
def test_every_function_refuses_a_null_instance(version, faces):
    f = faces(version)
    f.init(FIG4B)
    dll = ctypes.CDLL(f.s.dll._name)  # fresh function objects, without fmpy's argument types
    d, p, z = ctypes.c_double(), ctypes.c_void_p(), ctypes.c_size_t()
    b = ctypes.c_bool()
    vr = (ctypes.c_uint * 1)(0)
    common = {"SetDebugLogging": (0, z, None), "ExitInitializationMode": (), "Terminate": (), "Reset": (),
              "GetFMUState": (ctypes.byref(p),), "SetFMUState": (None,), "FreeFMUState": (ctypes.byref(p),)}
    if version == 2:
        calls = {**{f"fmi2{k.replace('State', 'state')}": v for k, v in common.items()},
                 "fmi2GetReal": (vr, 1, ctypes.byref(d)), "fmi2SetReal": (vr, 1, ctypes.byref(d)),
                 "fmi2DoStep": (ctypes.c_double(0), ctypes.c_double(H), 1)}
    else:
        calls = {**{f"fmi3{k}": v for k, v in common.items()},
                 "fmi3EnterInitializationMode": (0, ctypes.c_double(0), ctypes.c_double(0), 0, ctypes.c_double(0)),
                 "fmi3GetFloat64": (vr, 1, ctypes.byref(d), 1), "fmi3SetFloat64": (vr, 1, ctypes.byref(d), 1),
                 "fmi3GetInt64": (vr, 1, ctypes.byref(d), 1), "fmi3GetFloat32": (vr, 1, ctypes.byref(d), 1),
                 "fmi3EnterEventMode": (), "fmi3EnterStepMode": (), "fmi3EvaluateDiscreteStates": (),
                 "fmi3UpdateDiscreteStates": tuple(ctypes.byref(b) for _ in range(5)) + (ctypes.byref(d),),
                 "fmi3DoStep": (ctypes.c_double(0), ctypes.c_double(H), 1, ctypes.byref(b), ctypes.byref(b),
                                ctypes.byref(b), ctypes.byref(d)),
                 "fmi3SerializedFMUStateSize": (None, ctypes.byref(z)), "fmi3GetClock": (vr, 1, ctypes.byref(b))}
    for name, args in calls.items():
        fn = getattr(dll, name)
        fn.restype = ctypes.c_int
        assert fn(None, *args) == ERROR, name
    dll[f"fmi{version}FreeInstance"](None)
    assert f.step(0.0, H) == OK  # the real instance is untouched
