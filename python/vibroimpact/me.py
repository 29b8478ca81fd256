"""Model Exchange runs of an FMU: fmpy's own integrator, the package's own for runs with inputs, or raw
calls, with the FMU's log kept.

    run_me(fmu, params, stop_time, ...) -> (result, MeInstance)
        without inputs: fmpy.simulate_fmu(fmi_type='ModelExchange', solver='CVode') on an instance whose
        log is kept, with logEvents on, so that every mode change is known with its exact time
        (compare.fmu_events); with inputs: run_with_inputs, which sets the inputs at t before every
        evaluation of the derivatives and event indicators (fmpy 0.3.32's driver sets them in its event
        function only: its right-hand side sees the inputs of the last event-function call).
    run_with_inputs(inst, ...)  the package's own integrator (SciPy's solve_ivp, the FMU's event indicators
                                as its terminal events, the FMU's time events and the inputs' jumps as ends of
                                its intervals)
    Inputs                      the inputs as functions of time: fmpy's structured input array or a dict
                                name -> function of t
    MeRunner                    compare.Runner's interface for Model Exchange (compare(name, MeRunner(...)))
    Me(MeInstance)              the raw calls with plain lists: start, states, derivatives, indicators,
                                nominals, settle (the event iteration), euler_to (a fixed-step importer)
"""
import ctypes
import math

import numpy as np

from .compare import INTEGERS, REALS, fmu_events
from .fmu import Logged, MessageLog, fmu_path, set_value, set_values
from .reference.scenarios import SCENARIOS


class MeInstance(MessageLog):
    """An fmpy FMU2Model of an FMU with a MessageLog: `model`, `messages`, `vr`, `md`."""

    def __init__(self, fmu=None, unzipdir=None, md=None, name="me", call_logger=None):
        """call_logger: fmpy's fmiCallLogger, called with the text of each FMI call and its status."""
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Model
        super().__init__()
        fmu = str(fmu or fmu_path())
        self.md = md or read_model_description(fmu)
        self.unzipdir = unzipdir or extract(fmu)
        self.model = FMU2Model(guid=self.md.guid, unzipDirectory=self.unzipdir,
                               modelIdentifier=self.md.modelExchange.modelIdentifier, instanceName=name,
                               fmiCallLogger=call_logger)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}

    def instantiate(self, categories=("logEvents",)):
        """Instantiated with the given log categories on (warnings and errors are logged anyway)."""
        self.model.instantiate(callbacks=self.callbacks, loggingOn=False)
        if categories:
            self.model.setDebugLogging(True, list(categories))
        return self.model

    def errors(self):
        return [m for s, _, m in self.messages if s >= 3]


def run_me(fmu, params, stop_time, rtol=1e-10, output=("y", "v", "F", "mode"), output_interval=None,
           unzipdir=None, md=None, record_events=False, input=None, solver="CVode", step_size=None,
           step_finished=None, method="DOP853", call_logger=None):
    """-> (result, MeInstance) of one Model Exchange run from t = 0. The result is a structured array as
    fmpy's ('time' and the outputs, on the grid n output_interval; with record_events also before and
    after each event). The FMU's rtol is set to the importer's (its re-arming bands follow it), unless
    params give one.

    Without input: fmpy's driver (solver 'CVode' by default, its absolute tolerances rtol times the FMU's
    nominals; step_size and step_finished are fmpy's). With input (fmpy's structured input array, or a
    dict name -> function of t [s] of Real inputs): run_with_inputs, solve_ivp's `method`, which sets the
    inputs before every evaluation. call_logger: fmpy's fmiCallLogger of the instance."""
    from fmpy import simulate_fmu
    from fmpy.util import auto_interval
    inst = MeInstance(fmu, unzipdir, md, call_logger=call_logger)
    model = inst.instantiate()
    params = dict(params)
    if "rtol" in inst.vr and "rtol" not in params:
        params["rtol"] = min(max(rtol, 1e-14), 1e-2)
    try:
        if input is not None:
            r = run_with_inputs(inst, params, Inputs(input, inst.md), stop_time, rtol, output,
                                output_interval or auto_interval(stop_time), record_events, method)
        else:
            r = simulate_fmu(str(fmu or fmu_path()), fmi_type="ModelExchange", solver=solver, start_time=0.0,
                             stop_time=stop_time, relative_tolerance=rtol, start_values=params,
                             output=list(output), output_interval=output_interval, record_events=record_events,
                             fmu_instance=model, model_description=inst.md, step_size=step_size,
                             step_finished=step_finished)
    finally:
        model.freeInstance()
    return r, inst


class Inputs:
    """Real inputs of an FMU as functions of time: `names`, values(t, after) -> their values at t, and
    `jumps`, the times where one jumps (then values(t, after=False) is the value before, after=True the
    value after).

    source: fmpy's structured input array (a 'time' field, nondecreasing, and a field per input; a time
    given twice is a jump; linear in between, held beyond the ends), or a dict name -> function of t [s]
    (continuous: no jumps)."""

    def __init__(self, source, md):
        real = {v.name for v in md.modelVariables if v.causality == "input" and v.type == "Real"}
        if isinstance(source, dict):
            self.names, self._functions, self.jumps = list(source), list(source.values()), []
        else:
            self.names = [n for n in source.dtype.names if n != "time"]
            self._t = np.asarray(source["time"], dtype=float)
            self._v = [np.asarray(source[n], dtype=float) for n in self.names]
            self._functions = None
            if np.any(np.diff(self._t) < 0):
                raise ValueError("the input table's times decrease")
            self.jumps = sorted(set(self._t[1:][np.diff(self._t) == 0]))
        unknown = [n for n in self.names if n not in real]
        if unknown:
            raise ValueError(f"{', '.join(unknown)}: not a Real input of the FMU (its Real inputs: {sorted(real)})")

    def values(self, t, after=False):
        if self._functions is not None:
            return [float(f(t)) for f in self._functions]
        T = self._t
        i = min(max(int(np.searchsorted(T, t, side="right" if after else "left")), 1), len(T) - 1)
        span = T[i] - T[i - 1]
        w = min(max((t - T[i - 1]) / span, 0.0), 1.0) if span > 0 else 1.0
        return [float(v[i - 1] + w * (v[i] - v[i - 1])) for v in self._v]

    def next_jump(self, t):
        """The first jump after t (inf: none)."""
        return next((tj for tj in self.jumps if tj > t), math.inf)


class InputDriven:
    """One FMU2Model in continuous-time mode with its inputs set at t before every evaluation: rhs(t, x),
    indicators(t, x) (cached for the same t and x) and solve_ivp's event functions; the interface
    vehicle_track.me_master.interval integrates."""

    def __init__(self, inst, inputs):
        f = inst.model
        self.inst, self.f, self.inputs, self.md = inst, f, inputs, inst.md
        self.nx, self.nz = self.md.numberOfContinuousStates, self.md.numberOfEventIndicators
        self._vr = (ctypes.c_uint * len(inputs.names))(*[inst.vr[n] for n in inputs.names])
        self._u = (ctypes.c_double * len(inputs.names))()
        self._x, self._dx = (ctypes.c_double * self.nx)(), (ctypes.c_double * self.nx)()
        self._z = (ctypes.c_double * max(self.nz, 1))()
        self._z_key, self._z_value = None, None

    def set_inputs(self, t, after=False):
        self._u[:] = self.inputs.values(t, after)
        self.f.fmi2SetReal(self.f.component, self._vr, len(self._u), self._u)

    def load(self, t, x):
        self.f.fmi2SetTime(self.f.component, t)
        self.set_inputs(t)
        self._x[:] = x
        self.f.fmi2SetContinuousStates(self.f.component, self._x, self.nx)

    def rhs(self, t, x):
        self.load(t, x)
        self.f.fmi2GetDerivatives(self.f.component, self._dx, self.nx)
        return np.array(self._dx)

    def indicators(self, t, x):
        key = (t, np.asarray(x).tobytes())
        if key != self._z_key:
            self.load(t, x)
            self.f.fmi2GetEventIndicators(self.f.component, self._z, self.nz)
            self._z_key, self._z_value = key, np.array(self._z[:self.nz])
        return self._z_value

    def event_functions(self):
        def make(k):
            def g(t, x):
                return self.indicators(t, x)[k]
            g.terminal = True
            return g
        return [make(k) for k in range(self.nz)]

    def reason(self):
        """The FMU's last message (why it asks to terminate)."""
        return self.inst.texts()[-1] if self.inst.messages else "no message logged"

    def states(self):
        self.f.getContinuousStates(self._x, self.nx)
        return np.array(self._x)

    def nominals(self):
        self.f.getNominalsOfContinuousStates(self._x, self.nx)
        return np.array(self._x)

    def event_iteration(self, t, initial=False, max_passes=100):
        """Event mode at t with the inputs after any jump there, fmi2NewDiscreteStates until no pass is
        asked for, continuous-time mode. -> the next time event (inf: none). Raises when the FMU asks to
        terminate (its reason in the message: a run that stops is never returned as a result)."""
        if not initial:
            self.f.enterEventMode()
        self.set_inputs(t, after=True)
        for _ in range(max_passes):  # bounded
            needed, terminate, _nominals, _changed, defined, t_next = self.f.newDiscreteStates()
            if terminate:
                raise RuntimeError(f"the FMU asks to terminate at t = {t!r} s: {self.reason()}")
            if not needed:
                break
        else:
            raise RuntimeError(f"the event iteration does not settle in {max_passes} passes at t = {t!r} s")
        self.f.enterContinuousTimeMode()
        self._z_key = None  # a new mode: new indicators at the same time and state
        return t_next if defined else math.inf


class Recorder:
    """The outputs at the grid n dt and, with events=True, before and after each event: result()."""

    def __init__(self, inst, names, stop_time, dt, events):
        kinds = {v.name: v.type for v in inst.md.modelVariables}
        dtypes = {"Real": np.float64, "Integer": np.int32, "Enumeration": np.int32, "Boolean": np.bool_}
        self.f, self.names, self.events = inst.model, list(names), events
        self.getters = [(getattr(self.f, f"get{'Integer' if kinds[n] == 'Enumeration' else kinds[n]}"),
                         inst.vr[n]) for n in self.names]
        self.dtype = [("time", np.float64)] + [(n, dtypes[kinds[n]]) for n in self.names]
        self.grid = np.arange(int(math.floor(stop_time / dt + 1e-9)) + 1) * dt
        if self.grid[-1] < stop_time * (1 - 1e-12):
            self.grid = np.append(self.grid, stop_time)
        self.rows, self.n = [], 0

    def next_point(self, t):
        """The first grid point after t (where an importer completes an integrator step at the latest)."""
        k = int(np.searchsorted(self.grid, t, side="right"))
        return self.grid[k] if k < len(self.grid) else math.inf

    def put(self, t):
        self.rows.append((t, *(get([vr])[0] for get, vr in self.getters)))

    def at_event(self, t):
        """Before and after an event at t (the FMU's state as it is): a row when events are recorded."""
        if self.events:
            self.put(t)

    def upto(self, system, dense, t_new, x_new):
        """The grid points up to t_new (the state there from the dense output; x_new at t_new)."""
        while self.n < len(self.grid) and self.grid[self.n] <= t_new:
            t = self.grid[self.n]
            system.load(t, dense(t) if t < t_new else x_new)
            self.put(t)
            self.n += 1

    def result(self):
        return np.array(self.rows, dtype=self.dtype)


def _initialize(system, params, rtol):
    """Instantiated -> continuous-time mode at t = 0 with the start values and the inputs at 0."""
    f, kinds = system.f, {v.name: v.type for v in system.md.modelVariables}
    f.setupExperiment(tolerance=rtol, startTime=0.0)
    f.enterInitializationMode()
    set_values(f, system.inst.vr, params, kinds)
    system.set_inputs(0.0, after=True)
    f.exitInitializationMode()
    return system.event_iteration(0.0, initial=True)


def run_with_inputs(inst, params, inputs, stop_time, rtol, output, output_interval, record_events=False,
                    method="DOP853", max_intervals=10 ** 6):
    """Integrate the instantiated MeInstance from t = 0 to stop_time with the Inputs set at t before every
    evaluation of the derivatives and of the event indicators: solve_ivp (`method`, rtol, atol = rtol times
    the FMU's nominals) over intervals that end at a state event (located on the dense output, the state
    taken just past the crossing), a time event of the FMU, a jump of the inputs, an output point or the
    stop time; after each, fmi2CompletedIntegratorStep and, at an event, the event iteration. -> fmpy's
    kind of result."""
    from .vehicle_track.me_master import interval
    system = InputDriven(inst, inputs)
    t_event = _initialize(system, params, rtol)
    rec = Recorder(inst, output, stop_time, output_interval, record_events)
    x = system.states()
    rec.upto(system, None, 0.0, x)
    atol, events = rtol * system.nominals(), system.event_functions()
    t, h = 0.0, None
    for _ in range(max_intervals):  # bounded
        if t >= stop_time:
            return rec.result()
        t_start, t_end = t, min(stop_time, t_event, inputs.next_jump(t), rec.next_point(t))
        t, x, state_event, dense, h = interval(system, t, x, t_end, h, method, rtol, atol, events)
        h = h if h and h > 0 else None  # an interval of a few ulps: solve_ivp chooses the next first step
        rec.upto(system, dense, t, x)
        system.load(t, x)
        enter, terminate = system.f.completedIntegratorStep()
        if terminate:
            raise RuntimeError(f"the FMU asks to terminate at t = {t!r} s: {system.reason()}")
        if state_event or enter or t >= min(t_event, inputs.next_jump(t_start)):
            rec.at_event(t)
            t_event = system.event_iteration(t)
            x = system.states()
            rec.at_event(t)
    raise RuntimeError(f"more than {max_intervals} integration intervals")


def on_grid(result, t, name):
    """The result's `name` at the times t (the recorder's regular points agree with t to rounding)."""
    return np.interp(t, result["time"], result[name])


class MeRunner:
    """compare.Runner's interface (run(name, t, rtol, solver) -> (outputs on t, mode changes)) for
    Model Exchange: fmpy's CVode integrates, output on the reference's grid."""

    def __init__(self, fmu=None, unzipdir=None):
        from fmpy import extract, read_model_description
        self.fmu = str(fmu or fmu_path())
        self.unzipdir = unzipdir or extract(self.fmu)
        self.md = read_model_description(self.fmu)

    def run(self, name, t, rtol, solver=None):
        r, inst = run_me(self.fmu, SCENARIOS[name].full, float(t[-1]), rtol=rtol, output=REALS + INTEGERS,
                         output_interval=float(t[1] - t[0]), unzipdir=self.unzipdir, md=self.md)
        if inst.errors():
            raise RuntimeError("; ".join(inst.errors()))
        return {n: on_grid(r, t, n) for n in REALS + INTEGERS}, fmu_events(inst.messages)


class Me:
    """The raw Model Exchange calls on an instantiated MeInstance, with plain lists (fmpy raises
    FMICallException on an error status)."""

    def __init__(self, inst):
        self.inst, self.fmu, self.vr = inst, inst.model, inst.vr
        self.types = {v.name: v.type for v in inst.md.modelVariables}
        self.nx = inst.md.numberOfContinuousStates
        self.nz = inst.md.numberOfEventIndicators
        self.t = 0.0

    def start(self, params=None, start_time=0.0, tolerance=None):
        """Instantiated -> continuous-time mode after the initial event iteration; -> its last event info."""
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
        """fmi2NewDiscreteStates until no further pass is asked for (or termination): its last info."""
        while True:
            info = self.fmu.newDiscreteStates()
            if not info[0] or info[1]:
                return info

    def set(self, name, value):
        set_value(self.fmu, self.vr[name], value, self.types[name])

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
        """Sets the states x; fewer values than states set the first ones, the others keep theirs (the
        contact FMU's y and v, its W_damping unchanged). n: the count passed instead of len(x)."""
        if n is None and len(x) < self.nx:
            x = list(x) + self.states()[len(x):]
        self.fmu.setContinuousStates((ctypes.c_double * max(len(x), 1))(*x), len(x) if n is None else n)

    def derivatives(self):
        return self._array(self.fmu.getDerivatives, self.nx)

    def indicators(self):
        return self._array(self.fmu.getEventIndicators, self.nz)

    def nominals(self):
        return self._array(self.fmu.getNominalsOfContinuousStates, self.nx)

    def set_inputs(self, inputs, t):
        """The inputs (an Inputs, or a dict name -> function of t [s]) at t; None: nothing."""
        if inputs is None:
            return
        inputs = Inputs(inputs, self.inst.md) if isinstance(inputs, dict) else inputs
        for name, value in zip(inputs.names, inputs.values(t)):
            self.set(name, value)

    def euler_to(self, t_end, h, inputs=None):
        """Forward Euler in continuous-time mode from the FMU's state to t_end with steps h, stopping at
        the first step whose event indicators changed sign or after which the FMU asks for an event;
        -> (time reached, whether it stopped for an event). inputs (an Inputs, or a dict name -> function
        of t [s]): set at t before every evaluation of the derivatives and of the event indicators."""
        inputs = Inputs(inputs, self.inst.md) if isinstance(inputs, dict) else inputs
        t, x = self.t, self.states()
        self.set_inputs(inputs, t)
        z = self.indicators()
        while t < t_end - 1e-15:
            dx = self.derivatives()
            dt = min(h, t_end - t)
            t = min(t + h, t_end)
            x = [a + dt * b for a, b in zip(x, dx)]
            self.fmu.setTime(t)
            self.set_inputs(inputs, t)
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


# ---- cost: Model Exchange in fmpy against co-simulation -------------------------------------------------

COST_SCENARIOS = ("fig5c", "fig4a", "fig6b", "stick")
ADAMS = 2  # the co-simulation side of the cost comparison: the FMU's own CVODE (Adams)
COST_RTOLS = (1e-6, 1e-8, 1e-10)


def cost(names=COST_SCENARIOS, rtols=COST_RTOLS, fmu=None, repeat=3, warned=None):
    """Rows (scenario, interface, rtol, max |y - y_ref| within the horizon [m], CPU seconds, mode changes as
    the reference's) of fmpy runs on the reference grid (20 us output): Model Exchange with fmpy's CVode
    (BDF, atol = rtol x the FMU's nominals) and Co-Simulation with the FMU's own CVODE, each the best of
    `repeat` runs. warned: called with ('SCENARIO ME' or 'SCENARIO CS', the FMU's warnings) when it logged
    any in a run (a fmu.Relay)."""
    import time

    from fmpy import extract, read_model_description, simulate_fmu

    from .compare import SUMMARY, EVENT_DT, read_events, read_trace
    fmu = str(fmu or fmu_path())
    md, unzipdir = read_model_description(fmu), extract(fmu)
    rows = []
    for name in names:
        ref, h = read_trace(name), SUMMARY[name]["horizon"]
        t = ref["time"]
        within = t <= h
        ref_events = [e[1:] for e in read_events(name) if e[0] <= h - EVENT_DT]
        for rtol in rtols:
            for kind in ("ME", "CS"):
                best = None
                for _ in range(repeat):
                    start = time.process_time()
                    if kind == "ME":
                        r, inst = run_me(fmu, SCENARIOS[name].full, float(t[-1]), rtol=rtol, output=("y", "mode"),
                                         output_interval=float(t[1] - t[0]), unzipdir=unzipdir, md=md)
                        events = [e[1:] for e in fmu_events(inst.messages) if e[0] <= h - EVENT_DT]
                    else:
                        inst = Logged(md, unzipdir, name="cs")
                        slave = inst.instantiate()
                        try:
                            r = simulate_fmu(fmu, fmi_type="CoSimulation", stop_time=float(t[-1]),
                                             start_values={**SCENARIOS[name].full, "rtol": rtol, "solver": ADAMS},
                                             output_interval=float(t[1] - t[0]), output=["y", "mode"],
                                             model_description=md, fmu_instance=slave)
                        finally:
                            slave.freeInstance()
                        events = None
                    cpu = time.process_time() - start
                    best = cpu if best is None else min(best, cpu)
                    if warned is not None and inst.warnings():
                        warned(f"{name} {kind}", inst.warnings())
                y = on_grid(r, t, "y")
                err = float(np.abs(y - ref["y"])[within].max())
                same = "" if events is None else ("same" if events == ref_events else "DIFFERENT")
                rows.append((name, kind, rtol, err, best, same))
    return rows


def call_cost(n=20000, fmu=None):
    """Seconds per derivative evaluation as fmpy's integrator makes it (fmi2SetTime,
    fmi2SetContinuousStates, fmi2GetDerivatives through ctypes), the best of three loops of n."""
    import time
    inst = MeInstance(fmu)
    inst.instantiate(categories=())
    m = Me(inst)
    m.start(params=dict(contact_model=1))
    x = (ctypes.c_double * m.nx)(*m.states())
    dx = (ctypes.c_double * m.nx)()
    best = float("inf")
    for _ in range(3):
        start = time.process_time()
        for k in range(n):
            m.fmu.setTime(1e-9 * (k & 7))
            m.fmu.setContinuousStates(x, m.nx)
            m.fmu.getDerivatives(dx, m.nx)
        best = min(best, (time.process_time() - start) / n)
    m.fmu.freeInstance()
    return best
