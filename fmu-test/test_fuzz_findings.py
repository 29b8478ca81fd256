"""Regression tests of what the libFuzzer harness (tests/fuzz) found. Each names the harness's check
it failed; the input that found it is in the seed corpus, tests/fuzz/corpus/VibroImpact/, so that
the fuzz test runs it again too."""
import math
import re
import unicodedata

import pytest
from fmpy.fmi1 import FMICallException

from conftest import Logged, start


def printable(text):
    """No control characters (C0, DEL, C1): what the harness's logger accepts."""
    return not any(unicodedata.category(ch) == "Cc" for ch in text)


def test_control_characters_of_the_instance_name_and_strings_are_escaped_in_messages(model_description, unzipdir, vr):
    """The harness's 'message ... has a byte that starts no printable character': the FMU copied the
    instance name (fmi2Instantiate's call log) and String values (a profile_file that cannot be
    read) into messages byte for byte, control characters and all (a terminal escape, a bell, a
    newline that splits a log line). They are shown escaped, and the message still names them."""
    log = Logged(model_description, unzipdir, name="a\x1b[2Jb\x07")
    s = log.instantiate(logging=True)
    s.setString([vr["profile_file"]], ["no\nsuch\x1bfile"])
    with pytest.raises(FMICallException):
        start(s, vr, dict(contact_model=1))
    texts = [m for _, _, m in log.messages]
    assert any("fmi2Instantiate" in m for m in texts) and any("profile_file" in m for m in texts), texts
    bad = [m for m in texts if not printable(m)]
    assert bad == [], bad
    assert any("a\\x1b[2Jb\\x07" in m for m in texts), texts  # the name, escaped
    assert any("no\\x0asuch\\x1bfile" in m for m in texts), texts
    s.freeInstance()


@pytest.mark.parametrize("when", ["initialization mode", "exit"])
def test_outputs_beyond_the_range_of_double_are_refused_not_nan(logged, vr, when):
    """The harness's 'fmi2GetReal gave NaN ... with fmi2OK': Johnson pre-loaded by P = 1e300 N starts
    at delta = 2.5e288 m, where the work along the virgin curve and the energy given back on
    unloading both overflow, and W_plastic = inf - inf = NaN was reported with fmi2OK (in
    initialization mode and after it). Such a state cannot be represented: initialization is
    refused, naming the output."""
    log = logged()
    s = log.instantiate()
    s.setupExperiment()
    s.enterInitializationMode()
    s.setReal([vr["P"]], [1e300])
    with pytest.raises(FMICallException):
        if when == "exit":
            s.exitInitializationMode()
        else:
            s.getReal([vr["W_plastic"]])
    assert any(re.search(r"W_plastic = -?nan at t = 0 s", m) for st, _, m in log.messages if st == 3), log.messages
    s.freeInstance()


def test_no_nan_output_with_ok_after_a_failed_initialization(logged, vr, model_description):
    """The harness's 'fmi2GetReal gave NaN ... with fmi2OK' again: after fmi2ExitInitializationMode
    failed, the instance is in the error state, where values may still be read, and outputs computed
    from the model that failed to initialize were NaN with fmi2OK (found as k_contact after a
    refused Poisson's ratio, which is now refused when set; here W_plastic after the load of
    1e300 N above). An output without a finite value is refused (fmi2Error naming it and the state);
    the others read as before."""
    log = logged()
    s = log.instantiate()
    s.setupExperiment()
    s.enterInitializationMode()
    s.setReal([vr["P"]], [1e300])
    with pytest.raises(FMICallException):
        s.exitInitializationMode()
    for v in model_description.modelVariables:
        if v.type != "Real":
            continue
        try:
            x = s.getReal([v.valueReference])[0]
        except FMICallException:
            continue
        assert x == x, f"{v.name} = NaN with fmi2OK"
    with pytest.raises(FMICallException):
        s.getReal([vr["W_plastic"]])
    # refused naming it: as no value (fmi2GetReal's check), or with the reason the initialization gives again
    assert re.match(r"fmi2GetReal: W_plastic = -?nan (has no value in state 'error'|at t = 0 s: the parameters)",
                    log.messages[-1][2]), log.messages
    assert s.getReal([vr["P"]]) == [1e300]  # a parameter reads as set
    s.freeInstance()


def test_model_exchange_euler_importer_overshooting_yield_keeps_a_finite_memory(fmu_path):
    """The harness's 'fmi2GetEventIndicators returned fmi2OK with element 0 = NaN': an explicit-Euler
    importer (Johnson, a = 0.21 mm at 560 Hz, steps of 0.1 ms, then 1 ms) meets the events late; at
    one the state lay far beyond the plastic mode's surface, and the memory written down there was
    the unloading curve of that state's indentation, below yield: area ratio < 0, Rbar = NaN, and
    every indicator NaN from then on with fmi2OK (a state taken then was refused when set back). The
    memory is the largest indentation reached, never below yield: the indicators stay finite and a
    state taken on the way is accepted back."""
    from vibroimpact.me import Me, MeInstance

    inst = MeInstance(fmu_path)
    inst.instantiate(categories=())
    me = Me(inst)
    me.start(dict(a=0.000213623046875))
    saved = None
    t, z = 0.0, me.indicators()
    for k in range(32):
        h = 1e-4 if k < 16 else 1e-3
        x, dx = me.states(), me.derivatives()
        t += h
        me.fmu.setTime(t)
        me.set_states([a + h * b for a, b in zip(x, dx)])
        enter, _ = me.fmu.completedIntegratorStep()
        z_new = me.indicators()
        if enter or any((a > 0) != (b > 0) for a, b in zip(z, z_new)):
            me.fmu.enterEventMode()
            me.settle()
            me.fmu.enterContinuousTimeMode()
            z_new = me.indicators()
        assert all(v == v for v in z_new), (k, t, z_new)
        z = z_new
        if k == 20:
            saved = me.fmu.getFMUstate()
    me.fmu.setFMUstate(saved)
    assert all(v == v for v in me.indicators())
    me.fmu.freeFMUstate(saved)
    me.fmu.freeInstance()


# Findings whose calls ran for minutes (or crashed) run in a child interpreter with a time limit:
# ISOLATED's prologue makes the instance `s` of the FMU argv[1], with `md`, `vr`, `log` and the
# further arguments `args`; each script goes on from there.
ISOLATED = r"""
import sys, time
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from vibroimpact.fmu import Logged
fmu, args = sys.argv[1], sys.argv[2:]
md = read_model_description(fmu)
vr = {v.name: v.valueReference for v in md.modelVariables}
log = Logged(md, extract(fmu))
s = log.instantiate()
"""


def isolated(script, fmu_path, *args, what, seconds=60):
    """Run ISOLATED + script in a child interpreter; its stdout. Fails the test, naming `what`, when
    the child has not finished within `seconds` or exits with an error."""
    import subprocess
    import sys
    try:
        p = subprocess.run([sys.executable, "-c", ISOLATED + script, fmu_path, *map(str, args)],
                           capture_output=True, text=True, timeout=seconds)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{what} did not return within {seconds} s")
    assert p.returncode == 0, (p.returncode, p.stderr[-2000:])
    return p.stdout


STEP_AFTER_HUGE_FORCE = r"""
s.setupExperiment()
s.enterInitializationMode()
s.setInteger([vr["solver"]], [int(args[0])])
s.exitInitializationMode()
s.doStep(0.0, 0.01)
s.setReal([vr["F_ext"]], [1.7976931348623157e308])
t0 = time.process_time()
try:
    s.doStep(0.01, 1.0)
    status = "ok"
except FMICallException as e:
    status = "discard" if e.status == 2 else "error"
print(status, time.process_time() - t0, log.messages[-1][2] if log.messages else "")
"""


@pytest.mark.parametrize("solver", [1, 2, 3, 4], ids=["bdf", "adams", "dop853", "auto"])
def test_a_step_under_a_force_beyond_what_can_be_integrated_fails_at_once(fmu_path, solver):
    """The harness's watchdog ('fmi2DoStep used more than 30 s of CPU time'): under an input force of
    1.8e308 N, CVODE's first step size came out 0, then NaN, and CVODE 6.4 went on evaluating the
    right-hand side at t = NaN inside one call: minutes of CPU time in one fmi2DoStep (more than
    100 s without the sanitizers). A time or derivative that is not finite now fails the right-hand
    side, and CVODE the step after its limit of such failures: fmi2Error at once, naming where
    (dop853 failed at once before)."""
    out = isolated(STEP_AFTER_HUGE_FORCE, fmu_path, solver, what="fmi2DoStep")
    status, cpu, message = out.split(" ", 2)
    assert status == "error" and float(cpu) < 5.0, out
    assert "the solver failed near t = 0.01" in message, message



@pytest.mark.parametrize("solver", [1, 2, 3, 4], ids=["bdf", "adams", "dop853", "auto"])
def test_a_mass_resting_far_below_the_tolerance_moves_only_within_it(logged, vr, solver):
    """The harness's 'energy: an undriven run ... gained 9.6e-33 J' (FMI 3.0): Johnson with
    m = 4.6e-246 kg and P = 0 rests at delta = 5.6e-171 m, while the absolute tolerance of delta is
    rtol times a length of at least delta_Y (doc/numerics.md, "Tolerances": a negligible load does
    not shrink the tolerances). In a step of 1 us auto's BDF moved the mass by 8.7e-18 m, within that
    tolerance, and the harness weighed the contact energy of the move against the energy moved alone
    (none): a finding of the check, which now also allows the energy of an error of the absolute
    tolerances, rtol^2 F_Y delta_Y. Every solver keeps the rest to within the tolerance, in
    position and in energy, or refuses the step (dop853: its stable steps are 1e-86 s)."""
    log = logged()
    s = log.instantiate()
    start(s, vr, dict(m=4.5767114683872232e-246, P=0.0, solver=solver))
    names = ["y", "v", "E_contact", "W_dissipated", "F_Y", "delta_Y", "m", "g"]
    before = dict(zip(names, s.getReal([vr[n] for n in names])))
    try:
        s.doStep(0.0, 1e-6)
    except FMICallException:
        assert solver == 3 and "work bound" in log.messages[-1][2], log.messages[-3:]
        return
    after = dict(zip(names, s.getReal([vr[n] for n in names])))
    rtol = 1e-6

    def balance(x):
        return 0.5 * x["m"] * x["v"] ** 2 + x["E_contact"] + x["W_dissipated"] + x["m"] * x["g"] * x["y"]

    assert abs(after["y"] - before["y"]) <= rtol * before["delta_Y"], (before, after)
    assert balance(after) - balance(before) <= rtol**2 * before["F_Y"] * before["delta_Y"], (before, after)
    s.freeInstance()

OUTPUTS_AFTER_REFUSED_TOLERANCE = r"""
s.setupExperiment(tolerance=2.2250738585072014e-308)
s.enterInitializationMode()
try:
    s.exitInitializationMode()
    print("initialized")
except FMICallException:
    pass
outputs = [v for v in md.modelVariables if v.type == "Real" and v.causality in ("output", "calculatedParameter")]
for v in outputs:
    try:
        print(v.name, s.getReal([v.valueReference])[0])
    except FMICallException:
        print(v.name, "refused:", log.messages[-1][2])
"""


def test_outputs_after_an_initialization_that_failed_before_the_model_was_set_up(fmu_path):
    """The harness's AddressSanitizer report 'SEGV on unknown address 0x0' in vi_sim_outputs: the
    tolerance of fmi2SetupExperiment (2.2e-308, outside [1e-14, 1e-2]) failed
    fmi2ExitInitializationMode before the model's law was set up, and fmi2GetReal of an output in
    the error state then called the outputs of a law that is none (a NULL function pointer): a crash
    of the importer. Outputs in the error state of an initialization that never succeeded are
    computed as in initialization mode, which fails again with the reason: every output read is
    refused, naming it."""
    out = isolated(OUTPUTS_AFTER_REFUSED_TOLERANCE, fmu_path, what="fmi2GetReal in the error state")
    lines = out.splitlines()
    assert "initialized" not in lines and len(lines) > 10, out
    for line in lines:
        assert "refused:" in line and "relative tolerance" in line and "use a value in [1e-14, 0.01]" in line, line


def test_model_exchange_arrays_with_no_value_are_refused_after_a_failed_initialization(fmu_path):
    """The harness's 'fmi2GetDerivatives returned fmi2OK with element 0 = NaN': a Model Exchange
    instance (LEPP, a = F_ext = 1.8e308) whose fmi2ExitInitializationMode failed (v = NaN) still
    answered fmi2GetContinuousStates and fmi2GetDerivatives in the error state, with NaN and fmi2OK.
    An array with an element that is not finite is refused, naming it and the state."""
    from vibroimpact.me import Me, MeInstance

    inst = MeInstance(fmu_path)
    inst.instantiate(categories=())
    me = Me(inst)
    me.fmu.setupExperiment()
    me.fmu.enterInitializationMode()
    for name, value in dict(contact_model=3, a=1.7976931348623157e308, F_ext=1.7976931348623157e308).items():
        me.set(name, value)
    with pytest.raises(FMICallException):
        me.fmu.exitInitializationMode()
    for name, call in (("states", "fmi2GetContinuousStates"), ("derivatives", "fmi2GetDerivatives"),
                       ("indicators", "fmi2GetEventIndicators"), ("nominals", "fmi2GetNominalsOfContinuousStates")):
        try:
            values = getattr(me, name)()
        except FMICallException:
            assert re.match(rf"{call}: element \d = -?nan has no value in state 'error'", inst.messages[-1][2]), \
                inst.messages[-1]
            continue
        assert all(math.isfinite(v) for v in values), (name, values)
    me.fmu.freeInstance()


PERIODIC_PROFILE_OF_SUBNORMAL_PERIOD = r"""
s.setupExperiment()
s.enterInitializationMode()
s.setString([vr["profile_file"]], [args[0]])
s.setBoolean([vr["profile_periodic"]], [True])
try:
    s.exitInitializationMode()
    print("initialized")
except FMICallException:
    print("refused:", log.messages[-1][2])
"""


def test_a_periodic_profile_whose_period_is_subnormal_is_refused_at_once(fmu_path, tmp_path):
    """The harness's watchdog ('fmi2ExitInitializationMode has not returned after 300 s'): a profile
    file the harness wrote, 43 rows 4.9e-324 m apart (subnormal abscissae, heights 0 or 4.9e-324 m),
    read as periodic: the wheel of radius R1 = 0.475 m spans about 1e321 periods, and building the
    rigid-constraint envelope over them did not end. Initialization is refused, naming the period and
    R1, in well under a second."""
    tiny = 4.9406564584124654e-324
    rows = [f"{k * tiny!r} {(tiny if k % 3 else 0.0)!r}" for k in range(43)]
    path = tmp_path / "p0.txt"
    path.write_text("\n".join(rows) + "\n")
    out = isolated(PERIODIC_PROFILE_OF_SUBNORMAL_PERIOD, fmu_path, path, what="fmi2ExitInitializationMode")
    assert re.search(r"refused: .*profile_file .*the period \S+ m is too short for R1 = 0\.475 m", out), out


def test_co_simulation_functions_are_refused_on_a_model_exchange_instance(fmu_path):
    """The harness's 'fmi2SetRealInputDerivatives returned 0 for a Model Exchange instance ... FMI 2.0
    allows it in none only': a Model Exchange instance accepted the Co-Simulation functions that
    its state allowed (input derivatives in initialization mode, the status of the last step once
    terminated). FMI 2.0's Model Exchange state machine (section 3.2.3) has none of them: each is
    refused, naming the function and the interface."""
    import ctypes

    from vibroimpact.me import Me, MeInstance

    inst = MeInstance(fmu_path)
    inst.instantiate(categories=())
    me = Me(inst)
    dll, c = me.fmu.dll, me.fmu.component
    set_derivatives, real_status, boolean_status = (dll.fmi2SetRealInputDerivatives, dll.fmi2GetRealStatus,
                                                    dll.fmi2GetBooleanStatus)
    set_derivatives.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_uint), ctypes.c_size_t,
                                ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_double)]
    real_status.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.POINTER(ctypes.c_double)]
    boolean_status.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.POINTER(ctypes.c_int)]
    set_derivatives.restype = real_status.restype = boolean_status.restype = ctypes.c_int
    vr, order, value = (ctypes.c_uint * 1)(me.vr["yC_in"]), (ctypes.c_int * 1)(1), (ctypes.c_double * 1)(1e-3)
    me.fmu.setupExperiment()
    me.fmu.enterInitializationMode()
    for n in (0, 1):
        assert set_derivatives(c, vr, n, order, value) == 3  # fmi2Error
        assert "fmi2SetRealInputDerivatives" in inst.messages[-1][2] and "Model Exchange" in inst.messages[-1][2]
    me.fmu.exitInitializationMode()
    me.fmu.terminate()
    time, done = ctypes.c_double(-1.0), ctypes.c_int(-1)
    assert real_status(c, 2, ctypes.byref(time)) == 3 and time.value == -1.0  # fmi2LastSuccessfulTime
    assert "fmi2GetRealStatus" in inst.messages[-1][2] and "Model Exchange" in inst.messages[-1][2]
    assert boolean_status(c, 3, ctypes.byref(done)) == 3 and done.value == -1  # fmi2Terminated
    assert "fmi2GetBooleanStatus" in inst.messages[-1][2] and "Model Exchange" in inst.messages[-1][2]
    me.fmu.freeInstance()


def test_a_directional_derivative_that_overflows_is_refused(fmu_path):
    """The harness's 'fmi2GetDirectionalDerivative returned OK with element 0 = inf': a seed of
    1.8e308 along y times the slope of the acceleration (the contact stiffness over the mass)
    overflowed, and the infinite derivative was returned with fmi2OK. A directional derivative that is not a finite number is refused, naming the unknown
    and the known; a seed of 1 along the same direction still gives a finite, nonzero answer."""
    from vibroimpact.me import Me, MeInstance

    inst = MeInstance(fmu_path)
    inst.instantiate(categories=())
    me = Me(inst)
    me.fmu.setupExperiment()
    me.fmu.enterInitializationMode()
    me.fmu.exitInitializationMode()
    me.settle()
    me.fmu.enterContinuousTimeMode()
    unknown, known = [me.vr["der_v"]], [me.vr["y"]]
    slope = me.fmu.getDirectionalDerivative(unknown, known, [1.0])[0]
    assert math.isfinite(slope) and abs(slope) > 1.0, slope
    with pytest.raises(FMICallException):
        me.fmu.getDirectionalDerivative(unknown, known, [1.7976931348623157e308])
    assert re.search(r"fmi2GetDirectionalDerivative: .*der_v.* not finite", inst.messages[-1][2]), inst.messages[-1]
    me.fmu.freeInstance()
