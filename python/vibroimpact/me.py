"""Model Exchange runs of an FMU: fmpy's own integrator, or raw calls, with the FMU's log kept.

    run_me(fmu, params, stop_time, ...) -> (fmpy result, MeInstance)
        fmpy.simulate_fmu(fmi_type='ModelExchange', solver='CVode') on an instance whose log is kept,
        with logEvents on, so that every mode change is known with its exact time (compare.fmu_events).
    MeRunner                    compare.Runner's interface for Model Exchange (compare(name, MeRunner(...)))
    Me(MeInstance)              the raw calls with plain lists: start, states, derivatives, indicators,
                                nominals, settle (the event iteration), euler_to (a fixed-step importer)
"""
import ctypes

import numpy as np

from .compare import INTEGERS, REALS, fmu_events
from .fmu import MessageLog, fmu_path, set_value
from .reference.scenarios import SCENARIOS


class MeInstance(MessageLog):
    """An fmpy FMU2Model of an FMU with a MessageLog: `model`, `messages`, `vr`, `md`."""

    def __init__(self, fmu=None, unzipdir=None, md=None, name="me"):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Model
        super().__init__()
        fmu = str(fmu or fmu_path())
        self.md = md or read_model_description(fmu)
        self.unzipdir = unzipdir or extract(fmu)
        self.model = FMU2Model(guid=self.md.guid, unzipDirectory=self.unzipdir,
                               modelIdentifier=self.md.modelExchange.modelIdentifier, instanceName=name)
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
           step_finished=None):
    """-> (fmpy result, MeInstance) of one Model Exchange run from t = 0 (fmpy's CVode by default;
    its absolute tolerances are rtol times the FMU's nominals). The FMU's rtol is set to the
    importer's (its re-arming bands follow it), unless params give one."""
    from fmpy import simulate_fmu
    inst = MeInstance(fmu, unzipdir, md)
    model = inst.instantiate()
    params = dict(params)
    if "rtol" in inst.vr and "rtol" not in params:
        params["rtol"] = min(max(rtol, 1e-14), 1e-2)
    try:
        r = simulate_fmu(str(fmu or fmu_path()), fmi_type="ModelExchange", solver=solver, start_time=0.0,
                         stop_time=stop_time, relative_tolerance=rtol, start_values=params, output=list(output),
                         output_interval=output_interval, record_events=record_events, fmu_instance=model,
                         model_description=inst.md, input=input, step_size=step_size, step_finished=step_finished)
    finally:
        model.freeInstance()
    return r, inst


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

    def euler_to(self, t_end, h):
        """Forward Euler in continuous-time mode from the FMU's state to t_end with steps h, stopping at
        the first step whose event indicators changed sign or after which the FMU asks for an event;
        -> (time reached, whether it stopped for an event)."""
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


# ---- cost: Model Exchange in fmpy against co-simulation -------------------------------------------------

COST_SCENARIOS = ("fig5c", "fig4a", "fig6b", "stick")
ADAMS = 2  # the co-simulation side of the cost comparison: the FMU's own CVODE (Adams)
COST_RTOLS = (1e-6, 1e-8, 1e-10)


def cost(names=COST_SCENARIOS, rtols=COST_RTOLS, fmu=None, repeat=3):
    """Rows (scenario, interface, rtol, max |y - y_ref| within the horizon [m], CPU seconds, mode changes as
    the reference's) of fmpy runs on the reference grid (20 us output): Model Exchange with fmpy's CVode
    (BDF, atol = rtol x the FMU's nominals) and Co-Simulation with the FMU's own CVODE, each the best of
    `repeat` runs."""
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
                        r = simulate_fmu(fmu, fmi_type="CoSimulation", stop_time=float(t[-1]),
                                         start_values={**SCENARIOS[name].full, "rtol": rtol, "solver": ADAMS},
                                         output_interval=float(t[1] - t[0]), output=["y", "mode"], model_description=md)
                        events = None
                    cpu = time.process_time() - start
                    best = cpu if best is None else min(best, cpu)
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
