"""A scenario through the FMI 3.0 FMU's Co-Simulation interface (fmpy's FMU3Slave), plain or with
early return and Event Mode: where it stops and how long it takes (`vibroimpact fmi3` tabulates
these against the reference; doc/fmi3.md).
"""
import time

from . import fmi3
from .failure import fmu_refused
from .reference.scenarios import SCENARIOS, STOP_TIME


def run(md, unzipdir, name, step, rtol, early_return, event_mode, warned=None):
    """-> ([(t, mode before, mode after)] of the stops, wall time [s]); a CommandError with what the
    FMU logged when an FMI call fails. warned: called with (name, the FMU's warnings) when it logged
    any (a fmu.Relay)."""
    log = fmi3.Logged(md, unzipdir, name=name)
    try:
        out = _run(md, log, name, step, rtol, early_return, event_mode)
    except Exception as e:
        raise fmu_refused(f"the FMI 3.0 FMU on {name} at --rtol {rtol:g}", e, log.texts()) from e
    if warned is not None and log.warnings():
        warned(name, log.warnings())
    return out


def _run(md, log, name, step, rtol, early_return, event_mode):
    vr = {v.name: v.valueReference for v in md.modelVariables}
    kinds = {v.name: v.type for v in md.modelVariables}
    s = log.instantiate(event_mode=event_mode, early_return=early_return)
    t0 = time.perf_counter()
    fmi3.initialize(s, vr, SCENARIOS[name].full, kinds=kinds, tolerance=rtol, stop_time=STOP_TIME,
                    event_mode=event_mode)
    if step is None:   # only the initialization: the options are checked before the long work
        s.terminate()
        s.freeInstance()
        return [], 0.0
    mode = s.getInt64([vr["mode"]])[0]
    stops = []
    if early_return:
        events, samples = fmi3.run_to_events(s, 0.0, STOP_TIME, step, sample=lambda t: (t, s.getInt64([vr["mode"]])[0]))
        at = set(events)
        for t, m in samples:
            if t in at:
                stops.append((t, mode, m))
            mode = m
    else:
        n = round(STOP_TIME / step)
        for k in range(n):
            s.doStep(k * step, (k + 1) * step - k * step)
    wall = time.perf_counter() - t0
    s.terminate()
    s.freeInstance()
    return stops, wall
