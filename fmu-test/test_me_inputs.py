"""Model Exchange with inputs that move: an importer must set the inputs at t before every evaluation of
the derivatives and of the event indicators at t. The package's runner (vibroimpact.me.run_me with an
input, Me.euler_to with inputs) does; fmpy 0.3.32's own driver sets them in its event function only, so
that its right-hand side sees the inputs of the last event-function call (doc/coupling.md, importer
quirks).

The physics check: the paper's wheel under Hertz (Fig. 5c: a = 0.1 mm, f = 560 Hz) on a platform moved
through yC_in = a (cos(2 pi f t) - 1) follows the same motion as the FMU's internal harmonic excitation
`a` in Co-Simulation."""
import ctypes
import re

import numpy as np
import pytest
from fmpy import simulate_fmu

from vibroimpact.compare import fmu_events
from vibroimpact.me import Inputs, Me, MeInstance, run_me
from vibroimpact.reference.scenarios import SCENARIOS

FIG5C = SCENARIOS["fig5c"].full
A, F = FIG5C["a"], FIG5C["f"]
STOP = 0.02  # s: 11 periods, contact lost and found again in each


def y_c(t):
    """The platform of the internal excitation, m."""
    return A * (np.cos(2 * np.pi * F * t) - 1.0)


def table(dt=1e-6):
    """y_c as fmpy's structured input array."""
    t = np.arange(int(round(STOP / dt)) + 1) * dt
    return np.array(list(zip(t, y_c(t))), dtype=[("time", np.float64), ("yC_in", np.float64)])


class CallCheck:
    """fmpy's call logger that follows time (fmi2SetTime) and the value of one Real input (fmi2SetReal) and,
    at every fmi2GetDerivatives and fmi2GetEventIndicators, notes how far the input last set lies from
    `signal` at the time set last: `stale`, the evaluations with the input off by more than `tol`."""

    def __init__(self, vr, signal, tol):
        self.vr, self.signal, self.tol = vr, signal, tol
        self.t, self.u, self.evaluations, self.stale = None, None, 0, []

    def __call__(self, message):
        name = message.split("(", 1)[0]
        if name == "fmi2SetTime":
            self.t = float(re.search(r"time=([^,)]+)", message).group(1))
        elif name == "fmi2SetReal" and re.search(rf"vr=\[{self.vr}\],", message):
            self.u = float(re.search(r"value=\[([^\]]+)\]", message).group(1))
        elif name in ("fmi2GetDerivatives", "fmi2GetEventIndicators") and self.t is not None:
            self.evaluations += 1
            if self.u is None or abs(self.u - self.signal(self.t)) > self.tol:
                self.stale.append((name, self.t, self.u))


@pytest.fixture(scope="module")
def yc_vr(model_description):
    return next(v.valueReference for v in model_description.modelVariables if v.name == "yC_in")


def test_the_runner_sets_the_inputs_before_every_evaluation(fmu_path, yc_vr):
    check = CallCheck(yc_vr, y_c, 1e-18)
    run_me(fmu_path, dict(FIG5C, a=0.0), 2e-3, rtol=1e-8, output=("y",), output_interval=1e-4,
           input={"yC_in": y_c}, call_logger=check)
    assert check.evaluations > 100 and check.stale == []


def test_fmpys_driver_evaluates_the_derivatives_with_the_inputs_of_its_event_function(fmu_path, model_description,
                                                                                       yc_vr):
    """The quirk doc/coupling.md lists: fmpy 0.3.32's simulate_fmu(fmi_type='ModelExchange', input=...)
    calls fmi2GetDerivatives at times whose inputs it never set (it applies them in its root function)."""
    check = CallCheck(yc_vr, y_c, 1e-9)  # the table's interpolation error is below 2e-10 m
    inst = MeInstance(fmu_path, md=model_description, call_logger=check)
    model = inst.instantiate(categories=())
    try:
        simulate_fmu(fmu_path, fmi_type="ModelExchange", stop_time=2e-3, relative_tolerance=1e-6,
                     start_values=dict(FIG5C, a=0.0, rtol=1e-6), output=["y"], output_interval=1e-4,
                     fmu_instance=model, model_description=model_description, input=table())
    finally:
        model.freeInstance()
    derivatives = [s for s in check.stale if s[0] == "fmi2GetDerivatives"]
    assert len(derivatives) > 0.5 * check.evaluations / 2, (len(derivatives), check.evaluations)


@pytest.fixture(scope="module")
def internal(fmu_path):
    """The Co-Simulation run with the internal excitation: y on the 10 us grid and its mode changes."""
    from vibroimpact.fmu import simulate
    return simulate("the internal excitation", fmu_path, start_values=dict(FIG5C, rtol=1e-10), stop_time=STOP,
                    output_interval=1e-5, output=["y", "mode"])


@pytest.mark.parametrize("kind", ["function", "table"])
def test_hertz_on_a_moving_platform_follows_the_input(fmu_path, internal, kind):
    """Hertz (no rate in the force) under yC_in = a (cos(2 pi f t) - 1), given as a function of t or as
    fmpy's table at 1 us (linear between its points: 2e-10 m off the cosine at most), against the internal
    excitation: y within 2e-9 m (1.7e-5 of its 117 um swing; measured 1.2e-9 with the table) and the same
    contact losses and impacts."""
    source = {"yC_in": y_c} if kind == "function" else table()
    r, inst = run_me(fmu_path, dict(FIG5C, a=0.0), STOP, rtol=1e-10, output=("y", "mode"), output_interval=1e-5,
                     input=source)
    assert not inst.errors()
    assert r["time"][-1] == pytest.approx(STOP, abs=1e-12)
    y = np.interp(internal["time"], r["time"], r["y"])
    assert np.abs(y - internal["y"]).max() < 2e-9, np.abs(y - internal["y"]).max()
    changes = np.count_nonzero(np.diff(internal["mode"]))
    assert changes >= 20 and np.count_nonzero(np.diff(r["mode"])) == changes
    assert len(fmu_events(inst.messages)) >= changes


def fmpys_driver(fmu_path, model_description, rtol):
    """fmpy's own Model Exchange run of the table at rtol: its result."""
    inst = MeInstance(fmu_path, md=model_description)
    model = inst.instantiate(categories=())
    try:
        return simulate_fmu(fmu_path, fmi_type="ModelExchange", stop_time=STOP, relative_tolerance=rtol,
                            start_values=dict(FIG5C, a=0.0, rtol=rtol), output=["y"], output_interval=1e-5,
                            fmu_instance=model, model_description=model_description, input=table())
    finally:
        model.freeInstance()


def test_fmpys_driver_is_off_or_gives_up_as_coupling_md_says(fmu_path, model_description, internal):
    """doc/coupling.md's numbers for the same case through fmpy's driver: 5.6 um off the internal
    excitation at rtol = 1e-6 (the package's runner: within 1e-8 m there), and at 1e-10 its CVode stops
    within the first 0.1 ms ("mxstep steps taken before reaching tout")."""
    r = fmpys_driver(fmu_path, model_description, 1e-6)
    error = np.abs(np.interp(internal["time"], r["time"], r["y"]) - internal["y"]).max()
    assert 5e-6 < error < 6e-6, error
    with pytest.raises(RuntimeError, match="mxstep") as failure:
        fmpys_driver(fmu_path, model_description, 1e-10)
    # fmpy's CVode prints t with the process's decimal point (',' in de_DE.UTF-8: tools/test.sh's sanitized pass)
    assert float(re.search(r"At t = (\S+),", str(failure.value)).group(1).replace(",", ".")) < 1e-4
    own, _ = run_me(fmu_path, dict(FIG5C, a=0.0), STOP, rtol=1e-6, output=("y",), output_interval=1e-5,
                    input=table())
    assert np.abs(np.interp(internal["time"], own["time"], own["y"]) - internal["y"]).max() < 1e-8


def test_a_time_given_twice_in_a_table_is_a_jump(model_description):
    """fmpy's table convention: a time given twice is a jump; values before it are the first row's,
    values at and after it the second's; linear in between; held beyond the ends."""
    src = np.array([(0.0, 0.0), (1.0, 1.0), (1.0, 5.0), (2.0, 7.0)], dtype=[("time", float), ("F_ext", float)])
    u = Inputs(src, model_description)
    assert u.jumps == [1.0] and u.next_jump(0.5) == 1.0 and u.next_jump(1.0) == np.inf
    assert u.values(0.5) == [0.5] and u.values(1.0) == [1.0] and u.values(1.0, after=True) == [5.0]
    assert u.values(1.5, after=True) == [6.0] and u.values(3.0) == [7.0] and u.values(-1.0) == [0.0]
    with pytest.raises(ValueError, match="a: not a Real input"):
        Inputs({"a": lambda t: 0.0}, model_description)


def test_a_fixed_step_importer_sets_the_inputs_before_every_evaluation(fmu_path, model_description, yc_vr):
    """Me.euler_to with inputs: the same protocol, and the FMU's platform yC is the input's at the end."""
    check = CallCheck(yc_vr, y_c, 1e-18)
    inst = MeInstance(fmu_path, md=model_description, call_logger=check)
    inst.instantiate(categories=())
    m = Me(inst)
    try:
        m.start(params=dict(FIG5C, a=0.0))
        t, _ = m.euler_to(2e-4, 1e-6, inputs={"yC_in": y_c})
        assert check.evaluations > 100 and check.stale == []
        assert m.real("yC") == pytest.approx(y_c(t), abs=1e-18)
    finally:
        m.fmu.freeInstance()


def test_a_run_the_fmu_ends_raises_with_its_reason_and_events_are_recorded(fmu_path, tmp_path):
    """The wheel rolls off the end of a non-periodic table at t = 0.04 s (x0 = 0.02 m, V = 2 m/s, last
    x = 0.1 m) under a constant F_ext given as an input: the FMU asks to terminate there, and the runner
    raises with the FMU's reason instead of returning a result that stops short. With record_events
    (Fig. 5c's wheel on the moving platform), rows before and after each contact loss and onset."""
    from test_rolling import write
    x = np.linspace(0.0, 0.1, 11)
    path = write(tmp_path / "short.txt", x, np.zeros_like(x))
    p = dict(profile_file=path, V=2.0, x0=0.02, contact_model=1)
    with pytest.raises(RuntimeError, match=r"asks to terminate at t = 0\.04.*x_last = 0\.1 m"):
        run_me(fmu_path, p, 0.1, rtol=1e-8, output=("y",), output_interval=1e-3, input={"F_ext": lambda t: 0.0})
    r, inst = run_me(fmu_path, dict(FIG5C, a=0.0), 5e-3, rtol=1e-8, output=("y", "mode"), output_interval=1e-3,
                     record_events=True, input={"yC_in": y_c})
    events = [e[0] for e in fmu_events(inst.messages) if e[0] > 0.0]
    off_grid = r["time"][np.abs(r["time"] - np.round(r["time"] / 1e-3) * 1e-3) > 1e-12]
    assert len(events) >= 2 and len(off_grid) == 2 * len(events), (events, off_grid)
    assert np.allclose(off_grid[::2], events, rtol=0, atol=1e-15) and np.all(np.diff(r["time"]) >= 0)


def test_the_output_y_is_the_state_the_importer_set(fmu_path):
    """In Model Exchange y is a state: the output y is the value the importer set, bit for bit, whatever
    the inputs (computed as yC - delta with delta = yC - y it could differ by an ulp, and moved with yC_in
    although no input may move a state)."""
    inst = MeInstance(fmu_path)
    inst.instantiate()
    m, vr = inst.model, inst.vr
    m.setupExperiment(startTime=0.0)
    m.setReal([vr["a"], vr["f"]], [1e-4, 560.0])  # the platform moves: yC = yC_in + a (cos(2 pi f t) - 1)
    m.enterInitializationMode()
    m.exitInitializationMode()
    m.enterContinuousTimeMode()
    n = len(inst.md.derivatives)
    rng = np.random.default_rng(7)
    for t, y, yc in zip(rng.uniform(0.0, 1e-2, 400), rng.uniform(-2e-4, 2e-4, 400), rng.uniform(-1e-4, 1e-4, 400)):
        m.setTime(t)
        x = (ctypes.c_double * n)()
        m.getContinuousStates(x, n)
        assert inst.md.derivatives[0].variable.derivative.name == "y"
        x[0] = y
        m.setContinuousStates(x, n)
        m.setReal([vr["yC_in"]], [yc])
        assert m.getReal([vr["y"]])[0] == y, (t, y, yc)
    m.terminate()
    m.freeInstance()
