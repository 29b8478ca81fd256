"""What only FMI 3.0 has, on the FMU access of vibroimpact.fmu: initializing an instance (through
Event Mode when it uses it), a step that reports instead of raising, and a loop that follows the
FMU's early returns to its events. fmu3_path and set_value (either version) come from vibroimpact.fmu.

The FMI 3.0 FMU is the same model as the FMI 2.0 one (doc/fmi3.md): Float64, Int32, Boolean,
String variables and the options and `mode` as Enumerations (read and written as Int64); a
Co-Simulation step may return early at a change of the model's mode.
"""
import ctypes

from .fmu import Messages, fmu3_path, set_value, set_values

__all__ = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "Logged", "do_step", "enumeration_value", "fmu3_path",
           "initialize", "run_to_events", "set_value", "update_discrete_states"]

OK, WARNING, DISCARD, ERROR, FATAL = range(5)


def enumeration_value(model_description, name, item):
    """The value of the item named `item` of the Enumeration variable `name`."""
    v = next(v for v in model_description.modelVariables if v.name == name)
    return int(next(i.value for i in v.declaredType.items if i.name == item))


def initialize(slave, vr, values, kinds=None, tolerance=None, start_time=0.0, stop_time=None, event_mode=False):
    """An instantiated FMU3Slave to Step Mode: fmi3EnterInitializationMode (tolerance, start and stop
    time), the start values, fmi3ExitInitializationMode, and, for an instance that uses Event Mode
    (event_mode=True), the event iteration and fmi3EnterStepMode. kinds: FMI 3.0 type by name."""
    slave.enterInitializationMode(tolerance=tolerance, startTime=start_time, stopTime=stop_time)
    set_values(slave, vr, values, kinds)
    slave.exitInitializationMode()
    if event_mode:
        update_discrete_states(slave)
        slave.enterStepMode()


def update_discrete_states(slave):
    """fmi3UpdateDiscreteStates until it asks for no more (the FMU's answer is at most one pass)."""
    for _ in range(100):
        if not slave.updateDiscreteStates()[0]:
            return
    raise RuntimeError("fmi3UpdateDiscreteStates asked for more than 100 passes")


class Logged(Messages):
    """An FMU3Slave of an extracted FMU whose logger keeps what it logs in `messages`.
    instantiate(event_mode, early_return, logging) creates the instance."""

    def __init__(self, md, unzipdir, name="instance", token=None):
        from fmpy.fmi3 import FMU3Slave
        super().__init__()
        self.slave = FMU3Slave(guid=token or md.guid, unzipDirectory=unzipdir,
                               modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)

    def _log(self, env, status, category, message):
        self.keep(status, category, message.decode("utf-8", "replace"))

    def instantiate(self, event_mode=False, early_return=False, logging=False):
        self.slave.instantiate(loggingOn=logging, eventModeUsed=event_mode, earlyReturnAllowed=early_return,
                               logMessage=self._log)
        return self.slave


# ---- stepping ------------------------------------------------------------------------------------------

def do_step(slave, t, h):
    """fmi3DoStep from t over h without raising: (status, eventHandlingNeeded, terminateSimulation,
    earlyReturn, lastSuccessfulTime)."""
    from fmpy.fmi3 import fmi3Boolean, fmi3Float64
    event, terminate, early, last = fmi3Boolean(), fmi3Boolean(), fmi3Boolean(), fmi3Float64()
    fn = slave._functions["fmi3DoStep"]  # the raw function: fmpy's doStep raises on fmi3Discard
    status = fn(slave.component, t, h, fmi3Boolean(True), ctypes.byref(event), ctypes.byref(terminate),
                ctypes.byref(early), ctypes.byref(last))
    return status, event.value, terminate.value, early.value, last.value


def run_to_events(slave, t_start, t_end, step, sample=None, max_steps=10 ** 7):
    """Step an initialized instance (created with earlyReturnAllowed) from t_start to t_end on the
    grid t_start + k step, each step ending at the next grid point or earlier where the FMU returns
    early (a grid point closer than 1e-9 step after an early return is skipped). Returns (event
    times, samples): the lastSuccessfulTime of every step that ended at an event (early return, or
    eventHandlingNeeded), and sample(t) after every step (None: no samples). When a step asks for
    event handling (an instance with eventModeUsed) the loop passes through Event Mode there."""
    events, samples, t, k = [], [], t_start, 0
    for _ in range(max_steps):
        if t >= t_end:
            return events, samples
        t_next = min(t_start + (k + 1) * step, t_end)
        while t_next - t <= 1e-9 * step and t_next < t_end:  # bounded: the grid passes t
            k += 1
            t_next = min(t_start + (k + 1) * step, t_end)
        status, handling, _, early, last = do_step(slave, t, t_next - t)
        if status > WARNING:  # a warning was logged (the logger has it); the step was done
            raise RuntimeError(f"fmi3DoStep from t = {t!r} s returned status {status}")
        if early or handling:
            events.append(last)
        if handling:
            slave.enterEventMode()
            update_discrete_states(slave)
            slave.enterStepMode()
        if early:
            t = last
        else:
            t, k = t_next, k + 1
        if sample is not None:
            samples.append(sample(t))
    raise RuntimeError(f"more than {max_steps} steps")
