"""What a worker runs: one chain of points on one FMU instance (fmpy's FMU2Slave), the statistics
computed on the fly, and the Poincare samples.

The sweep ships this module to the Dask workers (engine.package_zip), so a worker needs only fmpy and
numpy, not this repository. It imports nothing from the package but vibroimpact.fmu, and returns
plain data (dicts, lists, floats) so that the client can read it without the worker's classes.

Time grid of a point. With P = 1/f the excitation period (f read from the FMU after its start
values are set), the communication step is h = P / ceil(P / step), the largest step not above
--step that divides the period; a point runs the smallest whole number of periods that covers
--stop-time, so every Poincare sample (phase 0 of the excitation, once per period) falls exactly on
a communication point and a continuation sweep's next point starts at phase 0 too. Communication
points are t_start + i h, computed from i (no accumulated sum). With f <= 0 there is no period: the
step is --step, the run ends at the first step at or past --stop-time, and there are no Poincare
samples.

Statistics over the samples at the communication points in [t_start + transient, t_end]:
  F_max, F_min, delta_max   extremes of the sampled F and delta (a step that resolves the contact
                            time resolves the peaks: the sampling error is about (pi h / t_contact)^2 / 2)
  sep_max                   largest sampled gap between the surfaces out of contact
                            (delta_f + delta_p - delta, i.e. above the dent's bottom)
  contact_fraction          share of the samples in contact (mode != 0)
  F_mean                    exact time average of the contact force from the momentum balance
                            m v' = F - (P + m g - F_ext):  F_mean = P + m g - F_ext + m (v(t_end) - v(t0)) / (t_end - t0)
  n_impacts, W_plastic      increments of the FMU's counters over the window (exact)
"""
import ctypes
import math
import os
import threading

import numpy as np

from ..fmu import MessageLog, set_value

STATS = ["F_max", "F_min", "F_mean", "delta_max", "sep_max", "contact_fraction", "n_impacts", "W_plastic"]
# what a step reads: Reals, then Integers (mode and n_impacts; an enumeration is read as an integer)
REALS = ["F", "delta", "v", "delta_f", "delta_p", "W_plastic"]
INTS = ["mode", "n_impacts"]
LOAD = ["P", "m", "g", "F_ext", "f"]
OUTPUT_NAMES = REALS + INTS + LOAD
_F, _DELTA, _V, _DF, _DP, _W = range(len(REALS))
_MODE, _NIMP = range(len(INTS))
CHUNK = 1024            # samples reduced at a time: memory per point is bounded whatever the stop time
PERIOD_REL_EPS = 1e-9   # slack when counting steps per period and periods per stop time
FMI_WARNING, FMI_DISCARD = 1, 2
WARN_CATEGORIES = ["logStatusWarning", "logStatusError"]
MAX_MESSAGES = 8        # messages kept per point (the FMU says each warning once per instance)


class PointFailed(Exception):
    pass


def time_grid(f, step, stop_time):
    """(h, steps per period or 0, number of steps) for one point; see the module docstring."""
    if not (math.isfinite(f) and f > 0):
        return step, 0, max(1, math.ceil(stop_time / step - PERIOD_REL_EPS))
    period = 1.0 / f
    per = max(1, math.ceil(period / step - PERIOD_REL_EPS))
    periods = max(1, math.ceil(stop_time / period - PERIOD_REL_EPS))
    return period / per, per, per * periods


class Window:
    """Running statistics over the samples at or after index i0 (chunks of rows at a time)."""

    def __init__(self, i0, per):
        self.i0, self.per = i0, per
        self.F_max = self.delta_max = self.sep_max = -math.inf
        self.F_min = math.inf
        self.n = self.n_contact = 0
        self.first = None       # (v, W_plastic, n_impacts) at i0
        self.last = None        # the same at the last sample
        self.poincare = []      # (i, delta, v)

    def add(self, i_first, reals, ints):
        """Rows i_first .. i_first + len(reals) - 1."""
        idx = np.arange(i_first, i_first + len(reals))
        keep = idx >= self.i0
        if not keep.any():
            return
        r, k, idx = reals[keep], ints[keep], idx[keep]
        if self.first is None:
            self.first = (float(r[0, _V]), float(r[0, _W]), int(k[0, _NIMP]))
        self.last = (float(r[-1, _V]), float(r[-1, _W]), int(k[-1, _NIMP]))
        self.F_max = max(self.F_max, float(r[:, _F].max()))
        self.F_min = min(self.F_min, float(r[:, _F].min()))
        self.delta_max = max(self.delta_max, float(r[:, _DELTA].max()))
        free = k[:, _MODE] == 0
        gap = np.where(free, r[:, _DF] + r[:, _DP] - r[:, _DELTA], 0.0)
        self.sep_max = max(self.sep_max, float(gap.max()))
        self.n += len(r)
        self.n_contact += int((~free).sum())
        if self.per:
            on = idx % self.per == 0
            self.poincare += [(int(i), float(d), float(v)) for i, d, v in zip(idx[on], r[on, _DELTA], r[on, _V])]

    def result(self, h, load):
        P, m, g, F_ext = load
        t_window = (self.n - 1) * h
        v0, W0, n0 = self.first
        v1, W1, n1 = self.last
        return dict(F_max=self.F_max, F_min=self.F_min,
                    F_mean=float(P + m * g - F_ext + m * (v1 - v0) / t_window),
                    delta_max=self.delta_max, sep_max=self.sep_max,
                    contact_fraction=self.n_contact / self.n, n_impacts=n1 - n0, W_plastic=float(W1 - W0))


class Instance:
    """One FMU instance with a logger that keeps what the FMU says, and fast value access."""

    def __init__(self, slave, vrs):
        self.slave = slave
        self.log = MessageLog(limit=MAX_MESSAGES, unique=True)   # referenced as long as the instance lives
        slave.instantiate(callbacks=self.log.callbacks, loggingOn=False)
        slave.setDebugLogging(True, WARN_CATEGORIES)
        fn = slave._functions   # raw ctypes functions: no fmpy wrapper in the stepping loop
        self._do_step, self._get_real, self._get_int = fn["fmi2DoStep"], fn["fmi2GetReal"], fn["fmi2GetInteger"]
        self.vr_real = (ctypes.c_uint * len(REALS))(*[vrs[n] for n in REALS])
        self.vr_int = (ctypes.c_uint * len(INTS))(*[vrs[n] for n in INTS])
        self.vr_load = [vrs[n] for n in LOAD]
        self.reals = np.zeros((CHUNK, len(REALS)))
        self.ints = np.zeros((CHUNK, len(INTS)), dtype=np.int32)
        dptr, iptr = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_int)
        self._real_rows = [ctypes.cast(self.reals.ctypes.data + j * self.reals.strides[0], dptr) for j in range(CHUNK)]
        self._int_rows = [ctypes.cast(self.ints.ctypes.data + j * self.ints.strides[0], iptr) for j in range(CHUNK)]
        self.t = 0.0

    @property
    def messages(self):
        """What the FMU logged since the last clear_messages(), each text once."""
        return self.log.texts()

    def clear_messages(self):
        self.log.messages.clear()

    def error(self, what):
        return "; ".join(self.messages) or what

    def set(self, values):
        for _, vr, kind, x in values:
            set_value(self.slave, vr, x, kind)

    def start(self, values):
        s = self.slave
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
        self.set(values)
        s.exitInitializationMode()
        self.t = 0.0

    def load(self):
        return self.slave.getReal(self.vr_load)

    def read(self, j):
        comp = self.slave.component
        self._get_real(comp, self.vr_real, len(REALS), self._real_rows[j])
        self._get_int(comp, self.vr_int, len(INTS), self._int_rows[j])

    def run(self, h, n_steps, window):
        """n_steps communication steps of size h from self.t, reading every output into the window."""
        comp, t0 = self.slave.component, self.t
        self.read(0)
        window.add(0, self.reals[:1], self.ints[:1])
        i = 0
        while i < n_steps:                      # bounded: i grows by at least one per pass
            rows = min(CHUNK, n_steps - i)
            for j in range(rows):
                i += 1
                tc = t0 + (i - 1) * h
                status = self._do_step(comp, ctypes.c_double(tc), ctypes.c_double(t0 + i * h - tc), 1)
                if status > FMI_WARNING:
                    kind = "discarded" if status == FMI_DISCARD else "failed"
                    raise PointFailed(self.error(f"fmi2DoStep {kind} at t = {tc:.9g} s"))
                self.read(j)
            window.add(i - rows + 1, self.reals[:rows], self.ints[:rows])
        self.t = t0 + n_steps * h

    def free(self):
        s = self.slave
        try:
            s.fmi2Terminate(s.component)
        except Exception:
            pass                                # an instance in the error state may refuse; free it anyway
        s.fmi2FreeInstance(s.component)         # not FMU2Slave.freeInstance: that also unloads the library
        s.component = None


class FMUFiles:
    """The FMU extracted once in a directory, and one fmpy FMU2Slave per thread (fmpy's constructor
    changes the working directory while it loads the library, hence the lock)."""

    def __init__(self, unzipdir, guid, model_identifier, vrs):
        self.unzipdir, self.guid, self.model_identifier, self.vrs = unzipdir, guid, model_identifier, vrs
        self._lock = threading.Lock()
        self._local = threading.local()

    def slave(self):
        s = getattr(self._local, "slave", None)
        if s is None:
            from fmpy.fmi2 import FMU2Slave
            with self._lock:
                s = FMU2Slave(guid=self.guid, unzipDirectory=self.unzipdir, modelIdentifier=self.model_identifier,
                              instanceName=f"sweep-{os.getpid()}-{threading.get_ident()}")
            self._local.slave = s
        return s


def _nan_stats():
    return {k: math.nan for k in STATS}


def run_chain(files, fixed, per_point, timing, progress=None):
    """Run the points of one chain in order on one instance; return one result dict per point.

    fixed: start values of the chain [(name, vr, kind, value)]; per_point: the values of each point.
    The first point (and any point after a failure, on a fresh instance) sets fixed + its own values
    in initialization mode; the next points set their own values (tunable) at the communication
    point where the previous one ended, and continue from its state. progress(k) is called after
    each point."""
    stop_time, step, transient = timing["stop_time"], timing["step"], timing["transient"]
    results, inst, restart_note = [], None, ""
    for k, values in enumerate(per_point):
        res = dict(_nan_stats(), status="error", message="", poincare=[])
        try:
            if inst is None:
                inst = Instance(files.slave(), files.vrs)
                inst.start(fixed + values)
            else:
                inst.set(values)
            P, m, g, F_ext, f = inst.load()
            h, per, n_steps = time_grid(f, step, stop_time)
            i0 = min(n_steps, max(0, math.ceil(transient / h - PERIOD_REL_EPS)))
            if i0 >= n_steps:
                raise PointFailed(f"the transient {transient} s leaves no sample before the end of the run")
            w = Window(i0, per)
            t_start = inst.t
            inst.run(h, n_steps, w)
            res.update(w.result(h, (P, m, g, F_ext)))
            res.update(status="ok", t_start=t_start, h=h,
                       poincare=[(t_start + i * h, d, v) for i, d, v in w.poincare])
            res["message"] = "; ".join(filter(None, [restart_note] + inst.messages))
            inst.clear_messages()
        except Exception as e:  # the FMU's own words when it gave any, else the exception
            text = inst.error(str(e)) if inst is not None and inst.messages else (str(e) or repr(e))
            res.update(_nan_stats(), status="error", message=text, poincare=[])
            if inst is not None:
                inst.free()
            inst = None
            restart_note = "continuation restarted from the initial state after the previous point failed" \
                if len(per_point) > 1 else ""
        else:
            restart_note = ""
        results.append(res)
        if progress is not None:
            progress(k)
    if inst is not None:
        inst.free()
    return results
