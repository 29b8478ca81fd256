"""Valid ranges at the interface: every parameter with a valid range declares it as min/max in
modelDescription.xml, and fmi2SetReal/fmi2SetInteger refuse a value outside it (fmi2Error, an
Error-category message naming the variable, the value and the range) and change nothing: the instance
stays where it was and goes on with its old value. Values that are accepted but far outside the
model's validity (an amplitude a larger than R*, profile heights spanning more than R1) give one
validity warning each."""
import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from conftest import effective, start

ERROR, WARNING = 3, 1


def errors(inst):
    return [m for status, cat, m in inst.messages if status == ERROR and cat == "logStatusError"]


def ranged(md):
    """The Real and Integer parameters that declare a min or a max."""
    return [v for v in md.modelVariables if v.causality == "parameter" and v.type in ("Real", "Integer")
            and (v.min is not None or v.max is not None)]


def test_every_parameter_with_a_valid_range_declares_it(model_description):
    """The ranges of doc/model.md section 5: m, E, Y, theta_Y > 0; R >= 0; -1 < nu <= 0.5; f >= 0;
    rtol and max_step >= 0 (rtol 0 or in [1e-14, 1e-2], max_step 0 or at least 1e-12: the gaps are
    refused at initialization); enumerations their items. An exclusive
    bound is declared as the nearest double inside it."""
    var = {v.name: v for v in model_description.modelVariables}

    def bounds(name):
        v = var[name]
        return (None if v.min is None else float(v.min), None if v.max is None else float(v.max))

    tiny = math.nextafter(0.0, 1.0)
    for name in ("m", "E1", "E2", "Y", "theta_Y", "k_spring"):
        assert bounds(name) == (tiny, None), name
    for name in ("R1", "R2", "f", "max_step"):
        assert bounds(name) == (0.0, None), name
    assert bounds("rtol") == (0.0, 1e-2)
    for name in ("nu1", "nu2"):
        assert bounds(name) == (math.nextafter(-1.0, 0.0), 0.5), name
    assert bounds("contact_model") == (1, 6) and bounds("solver") == (1, 4) and bounds("init") == (1, 2)
    assert bounds("e_restitution") == (tiny, 1.0) and bounds("damping_formula") == (1, 4)
    for name in ("P", "g", "v0", "a", "V", "x0", "yC_in", "F_ext"):
        assert bounds(name) == (None, None), name
    for v in ranged(model_description):  # the start values lie inside
        lo, hi = bounds(v.name)
        assert (lo is None or float(v.start) >= lo) and (hi is None or float(v.start) <= hi), v.name


def outside_and_at(v):
    """(value just outside, value at the bound) for each declared bound of v."""
    cases = []
    for bound, direction in ((v.min, -1), (v.max, 1)):
        if bound is None:
            continue
        b = float(bound)
        if v.type == "Integer":
            cases.append((int(b) + direction, int(b)))
        else:
            cases.append((math.nextafter(b, direction * math.inf), b))
    return cases


def test_every_declared_bound_is_refused_just_outside_and_accepted_at_the_bound(model_description, logged, vr):
    for v in ranged(model_description):
        for out, at in outside_and_at(v):
            inst = logged()
            s = inst.instantiate()
            get, set_ = (s.getReal, s.setReal) if v.type == "Real" else (s.getInteger, s.setInteger)
            s.enterInitializationMode()
            before = get([v.valueReference])[0]
            with pytest.raises(FMICallException):
                set_([v.valueReference], [out])
            text = "\n".join(errors(inst))
            assert f"{v.name} = " in text and "fmi2Set" in text, (v.name, out, inst.messages)
            assert get([v.valueReference])[0] == before, v.name  # nothing was set
            set_([v.valueReference], [at])  # the bound itself is valid
            assert get([v.valueReference])[0] == at, v.name
            s.freeInstance()


@pytest.mark.parametrize("name, value, words", [
    ("m", 0.0, ["m = 0", "m > 0"]),
    ("m", -1.0, ["m = -1", "m > 0"]),
    ("nu1", -1.0, ["nu1 = -1", "-1 < nu1 <= 0.5"]),
    ("nu2", 0.7, ["nu2 = 0.7", "-1 < nu2 <= 0.5"]),
    ("rtol", 0.5, ["rtol = 0.5", "0 <= rtol <= 0.01"]),
    ("max_step", -1e-3, ["max_step = -0.001", "max_step >= 0", "at least 1e-12"]),
    ("contact_model", 7, ["contact_model = 7", "hertz=1, johnson=2, lepp=3"]),
    ("solver", 0, ["solver = 0", "bdf=1, adams=2, dop853=3, auto=4"]),
])
def test_the_message_names_the_variable_the_value_and_the_range(logged, vr, name, value, words):
    inst = logged()
    s = inst.instantiate()
    with pytest.raises(FMICallException):
        (s.setInteger if isinstance(value, int) else s.setReal)([vr[name]], [value])
    text = "\n".join(errors(inst))
    assert all(w in text for w in words), text


def test_a_refused_value_in_a_call_sets_none_of_the_others(logged, vr):
    s = logged().instantiate()
    s.enterInitializationMode()
    with pytest.raises(FMICallException):
        s.setReal([vr["m"], vr["nu1"]], [500.0, -1.0])
    assert s.getReal([vr["m"], vr["nu1"]]) == [407.747, 0.3]


FLYING = dict(contact_model=1, P=0.0, g=0.0, init=2, v0=1.0, a=1e-4, f=100.0)


def test_negative_frequency_while_running_is_refused_and_the_run_goes_on_with_the_old_one(logged, vr):
    """f = -1 set between steps: fmi2SetReal refuses it (rather than accepting it and letting the next
    fmi2DoStep fail and end the instance); f keeps its value and the run continues exactly like a run
    in which nobody tried."""
    inst, ref = logged(), logged()
    s, r = inst.instantiate(), ref.instantiate()
    start(s, vr, FLYING)
    start(r, vr, FLYING)
    h = 1e-3
    for k in range(3):
        s.doStep(k * h, h)
        r.doStep(k * h, h)
    with pytest.raises(FMICallException) as e:
        s.setReal([vr["f"]], [-1.0])
    assert e.value.status == ERROR
    text = "\n".join(errors(inst))
    assert "f = -1" in text and "f >= 0" in text, inst.messages
    assert s.getReal([vr["f"]]) == [100.0]
    names = ["yC", "y", "v", "delta"]
    for k in range(3, 8):
        s.doStep(k * h, h)  # fmpy raises unless fmi2OK
        r.doStep(k * h, h)
        assert s.getReal([vr[n] for n in names]) == r.getReal([vr[n] for n in names]), k
    s.setReal([vr["f"]], [0.0])  # the bound itself is valid while running too
    s.doStep(8 * h, h)


def test_non_finite_values_are_still_refused(logged, vr):
    s = logged().instantiate()
    for name in ("a", "m", "P"):
        for bad in (math.nan, math.inf, -math.inf):
            with pytest.raises(FMICallException):
                s.setReal([vr[name]], [bad])


def validity_warnings(inst):
    return [m for status, cat, m in inst.messages if status == WARNING and cat == "logStatusWarning"
            and "range of validity" in m]


def run_steps(s, n, t=0.0, h=1e-4):
    """n steps of h from t; the time reached."""
    for k in range(n):
        s.doStep(t + k * h, h)
    return t + n * h


def test_an_amplitude_of_kilometres_warns_once(logged, vr):
    """|a| > R* (0.475 m with the defaults): accepted, one validity warning naming a and R*, however
    long the run and whatever a is tuned to next."""
    R = effective({})["R_star"]
    inst = logged()
    s = inst.instantiate()
    s.setDebugLogging(True, ["logStatusWarning"])
    start(s, vr, dict(a=1e3))
    t = run_steps(s, 20)
    s.setReal([vr["a"]], [2e3])
    run_steps(s, 5, t)
    w = [m for m in validity_warnings(inst) if "amplitude" in m]
    assert len(w) == 1, inst.messages
    assert "a = 1000 m" in w[0] and f"R* = {R:g} m" in w[0], w[0]


def test_an_amplitude_tuned_beyond_R_star_warns_once_when_it_takes_effect(logged, vr):
    inst = logged()
    s = inst.instantiate()
    s.setDebugLogging(True, ["logStatusWarning"])
    start(s, vr, dict(FLYING, a=1e-4))
    t = run_steps(s, 5)
    assert validity_warnings(inst) == []
    s.setReal([vr["a"]], [-0.5])  # |a| > R* = 0.475 m
    t = run_steps(s, 5, t)
    s.setReal([vr["a"]], [-0.6])
    run_steps(s, 5, t)
    w = [m for m in validity_warnings(inst) if "amplitude" in m]
    assert len(w) == 1 and "a = -0.5 m" in w[0], inst.messages


@pytest.mark.parametrize("height, warn", [(0.4, False), (0.475, False), (0.5, True)])
def test_profile_heights_spanning_more_than_R1_warn_once(logged, vr, tmp_path, height, warn):
    """A hill 100 m long rolled over by the wheel of R1 = 0.475 m: gentle slopes (the wheel can roll
    over it), heights spanning 0.4 m (inside), exactly R1 (sin(pi/2) = 1: not more) or 0.5 m (more
    than R1)."""
    table = tmp_path / "hill.txt"
    x = np.linspace(0.0, 100.0, 11)
    h = height * np.sin(np.pi * x / 100.0)
    table.write_text("".join(f"{float(a)!r} {float(b)!r}\n" for a, b in zip(x, h)))
    inst = logged()
    s = inst.instantiate()
    s.setDebugLogging(True, ["logStatusWarning"])
    start(s, vr, dict(profile_file=str(table), V=10.0, x0=10.0))
    run_steps(s, 20)
    w = [m for m in validity_warnings(inst) if "profile" in m]
    assert len(w) == (1 if warn else 0), inst.messages
    if warn:
        assert "R1 = 0.475 m" in w[0], w[0]
