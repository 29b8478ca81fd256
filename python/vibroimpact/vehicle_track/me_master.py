"""The vehicle-track system without coupling error: the three FMUs (VibroImpact.fmu, Track.fmu,
Vehicle.fmu) imported as Model Exchange and integrated together by one solver, SciPy's solve_ivp
(examples/vehicle-track/me_master.py runs it against the example's monolithic reference).

A short master over fmpy's Model Exchange API (FMU2Model). It stacks the FMUs' continuous states
(contact: y, v, W_damping; track: z_rail, v_rail, z_sleeper, v_sleeper; vehicle: z_body, v_body, W_dissipated)
and two integrals of its own for the bookkeeping: the impulse J of the contact force (the mean force
over any interval) and the work D dissipated in the three dampers (from the FMUs' velocities and
the dampers' start values in the companion FMUs). The integrals ride along without error control of their own: the
solver's tolerance acts on the FMUs' states, as it would in an importer that has no bookkeeping.

The couplings are algebraic connections: before each evaluation of the derivatives or of the event
indicators, every connected input is set from the other FMU's output at the same time and state, in
an order that respects direct feedthrough (the outputs' dependencies in ModelStructure): an output is
read only after the inputs it depends on are set. For this system the order is

    contact y, v     -> vehicle y_wheel, v_wheel
    vehicle F_wheel  -> contact F_ext        (F_wheel depends on y_wheel, v_wheel at once)
    track z_rail     -> contact yC_in
    track v_rail     -> contact vC_in        (v_rail is a state of the track)
    contact F        -> track F_contact      (in Model Exchange F depends on yC_in and vC_in at once)

The contact FMU gets the rail's velocity as well as its position (velocity_input = true, set when
vC_in is connected): Model Exchange passes values only, and the rate of yC_in is what its damping,
turning points and mode choices need (doc/model-exchange.md, "The platform's rate"). The track
receives the contact force itself: with one solver there is no step to average over. Both sides of
every port see the same values at the same time, so the couplings create no energy.

Events: the contact FMU's event indicators are solve_ivp's terminal events, and the FMUs' next time
event (a kink of the rolling constraint) ends the integration interval, as does SPAN. At the end of
every interval the master sets the state there (just past the crossing of a state event) and calls
fmi2CompletedIntegratorStep; at an event (state, time, or asked for) it takes the three FMUs through
fmi2EnterEventMode, fmi2NewDiscreteStates (passes over all three, the connections set again after
each, until none asks for another; bounded) and fmi2EnterContinuousTimeMode, reads their states back
and restarts the integrator there.
"""
import ctypes
import math
import pathlib
import shutil
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model
from scipy.integrate import solve_ivp

from .. import fmu as vifmu
from . import master, parameters

# (from FMU, output, to FMU, input). The order here is not the evaluation order: plan() sorts it.
CONNECTIONS = [
    ("vehicle", "F_wheel", "contact", "F_ext"),
    ("contact", "y", "vehicle", "y_wheel"),
    ("contact", "v", "vehicle", "v_wheel"),
    ("track", "z_rail", "contact", "yC_in"),
    ("track", "v_rail", "contact", "vC_in"),
    ("contact", "F", "track", "F_contact"),
]
FMUS = ("contact", "track", "vehicle")   # the order of the stacked states
# The master's own integrals, after the FMUs' states: the impulse J [N s] and the dampers' work D [J].
# Their nominal magnitude (absolute tolerance = rtol times it) is so large that they take no part in
# the step size control.
QUADRATURES = ("J", "D")
QUADRATURE_NOMINAL = 1e30
SPAN = 1e-3                               # s: the longest integration interval (a completed step at least this often)
MAX_EVENT_PASSES = 100                    # passes of fmi2NewDiscreteStates over the three FMUs at one event
RECORDED = {"contact": ["F", "y", "v", "delta", "yC"], "track": ["z_rail", "v_rail", "z_sleeper", "v_sleeper", "E"],
            "vehicle": ["F_wheel", "z_body", "v_body", "E", "W_dissipated"]}


class MeFmu:
    """One FMU as an fmpy FMU2Model, in initialization mode after construction."""

    def __init__(self, path, name, start_values, tolerance):
        self.name = name
        self.md = read_model_description(str(path))
        if self.md.modelExchange is None:
            raise RuntimeError(f"{path} offers no Model Exchange")
        self.dir = extract(str(path), unzipdir=tempfile.mkdtemp(prefix=f"vt_me_{name}_"))
        self.vr, self.types = vifmu.variables(self.md)
        self.log = vifmu.MessageLog(limit=200)
        self.fmu = FMU2Model(guid=self.md.guid, unzipDirectory=self.dir,
                             modelIdentifier=self.md.modelExchange.modelIdentifier, instanceName=name)
        self.fmu.instantiate(callbacks=self.log.callbacks)
        self.running = False
        self.fmu.setupExperiment(tolerance=tolerance, startTime=0.0)
        for k, val in start_values.items():
            vifmu.set_value(self.fmu, self.vr[k], val, self.types[k])
        self.fmu.enterInitializationMode()
        self.nx, self.nz = self.md.numberOfContinuousStates, self.md.numberOfEventIndicators
        self.x, self.dx = (ctypes.c_double * self.nx)(), (ctypes.c_double * self.nx)()
        self.z = (ctypes.c_double * max(self.nz, 1))()
        self.feedthrough = feedthrough(self.md)
        self.next_event = math.inf

    def getter(self, name):
        vr, buf, fmu = (ctypes.c_uint * 1)(self.vr[name]), (ctypes.c_double * 1)(), self.fmu

        def get():
            fmu.fmi2GetReal(fmu.component, vr, 1, buf)
            return buf[0]
        return get

    def setter(self, name):
        vr, buf, fmu = (ctypes.c_uint * 1)(self.vr[name]), (ctypes.c_double * 1)(), self.fmu

        def set_(value):
            buf[0] = value
            fmu.fmi2SetReal(fmu.component, vr, 1, buf)
        return set_

    def states(self):
        self.fmu.getContinuousStates(self.x, self.nx)
        return np.array(self.x)

    def nominals(self):
        self.fmu.getNominalsOfContinuousStates(self.x, self.nx)
        return np.array(self.x)

    def new_discrete_states(self):
        """One pass of fmi2NewDiscreteStates (event mode): -> (another pass needed, states changed);
        sets next_event."""
        needed, terminate, _nominals, changed, defined, t_next = self.fmu.newDiscreteStates()
        if terminate:
            raise RuntimeError(f"{self.name} asks to terminate: {self.log.text()[-500:]}")
        self.next_event = t_next if defined else math.inf
        return needed, changed

    def free(self):
        try:
            if self.running:
                self.fmu.terminate()
        except Exception:  # an instance in the error state cannot terminate; it is freed all the same
            pass
        finally:
            self.fmu.freeInstance()
            shutil.rmtree(self.dir, ignore_errors=True)


def feedthrough(md):
    """The inputs each output depends on at once (direct feedthrough), from ModelStructure: name ->
    set of input names."""
    inputs = {v.name for v in md.modelVariables if v.causality == "input"}
    return {u.variable.name: {d.name for d in (u.dependencies or []) if d.name in inputs} for u in md.outputs}


def plan(connections, fmus):
    """The connections in an evaluation order in which every output is read after the connected
    inputs it depends on (ModelStructure) were set; fmus: name -> object with `feedthrough`
    (feedthrough()). Raises on an algebraic loop."""
    connected = {(c[2], c[3]) for c in connections}
    pending, done, order = list(connections), set(), []
    for _ in range(len(connections)):  # bounded: one connection per pass
        ready = [c for c in pending if all((c[0], i) in done for i in fmus[c[0]].feedthrough.get(c[1], ())
                                           if (c[0], i) in connected)]
        if not ready:
            raise RuntimeError(f"algebraic loop among {pending}: every output depends on an input not yet set")
        order.append(ready[0])
        pending.remove(ready[0])
        done.add((ready[0][2], ready[0][3]))
    return order


class Coupled:
    """The stacked system: x' = f(t, x) over the FMUs' states and the master's integrals, and the
    FMUs' event indicators, with the connections set before each evaluation."""

    def __init__(self, fmus, connections, sort=True):
        self.fmus = fmus
        self.list = [fmus[n] for n in FMUS]
        self.slices, k = {}, 0
        for f in self.list:
            self.slices[f.name] = slice(k, k + f.nx)
            k += f.nx
        self.nq = k
        self.n = k + len(QUADRATURES)
        order = plan(connections, fmus) if sort else list(connections)
        self.links = [(fmus[a].getter(o), fmus[b].setter(i)) for a, o, b, i in order]
        c, tr, ve = fmus["contact"], fmus["track"], fmus["vehicle"]
        self.get_F, self.get_v = c.getter("F"), c.getter("v")
        self.get_v_rail, self.get_v_sleeper, self.get_v_body = tr.getter("v_rail"), tr.getter("v_sleeper"), \
            ve.getter("v_body")
        pt, pv = parameters.start_values(tr.md), parameters.start_values(ve.md)
        self.dampers = pt["c_pad"], pt["c_ballast"], pv["c_susp"]
        self.indicator_fmus = [f for f in self.list if f.nz > 0]
        self.nz = sum(f.nz for f in self.indicator_fmus)
        self.evaluations = 0
        self._z_key, self._z = None, None
        self._xbuf = {f.name: (ctypes.c_double * f.nx)() for f in self.list}

    def propagate(self):
        for get, set_ in self.links:
            set_(get())

    def load(self, t, X):
        """Time and states into every FMU, then the connections in order."""
        for f in self.list:
            buf = self._xbuf[f.name]
            buf[:] = X[self.slices[f.name]]
            f.fmu.fmi2SetTime(f.fmu.component, t)
            f.fmu.fmi2SetContinuousStates(f.fmu.component, buf, f.nx)
        self.propagate()

    def rhs(self, t, X):
        self.evaluations += 1
        self.load(t, X)
        dX = np.empty(self.n)
        for f in self.list:
            f.fmu.fmi2GetDerivatives(f.fmu.component, f.dx, f.nx)
            dX[self.slices[f.name]] = f.dx
        c_pad, c_ballast, c_susp = self.dampers
        vr, vs, F = self.get_v_rail(), self.get_v_sleeper(), self.get_F()
        dv_susp = self.get_v_body() - self.get_v()
        dX[self.nq:] = (F, c_pad * (vr - vs) ** 2 + c_ballast * vs ** 2 + c_susp * dv_susp ** 2)
        return dX

    def indicators(self, t, X):
        key = (t, X.tobytes())
        if key != self._z_key:
            self.load(t, X)
            z = []
            for f in self.indicator_fmus:
                f.fmu.fmi2GetEventIndicators(f.fmu.component, f.z, f.nz)
                z.extend(f.z[:f.nz])
            self._z_key, self._z = key, np.array(z)
        return self._z

    def event_functions(self):
        def make(k):
            def g(t, X):
                return self.indicators(t, X)[k]
            g.terminal = True
            return g
        return [make(k) for k in range(self.nz)]

    def event_iteration(self, initial=False):
        """Every FMU in event mode (after initialization they are in it already), passes of
        fmi2NewDiscreteStates over all of them with the connections set again after each, until
        none asks for another, then continuous-time mode. -> whether a continuous state changed."""
        if not initial:
            for f in self.list:
                f.fmu.enterEventMode()
        changed = False
        for _ in range(MAX_EVENT_PASSES):  # bounded
            again = False
            for f in self.list:
                needed, moved = f.new_discrete_states()
                again |= needed
                changed |= moved
            self.propagate()
            if not again:
                break
        else:
            raise RuntimeError(f"the event iteration does not settle in {MAX_EVENT_PASSES} passes")
        for f in self.list:
            f.fmu.enterContinuousTimeMode()
        self._z_key = None  # the same time and states, but a new mode: new indicators
        return changed

    def states(self):
        return np.concatenate([f.states() for f in self.list])

    def nominals(self):
        return np.concatenate([f.nominals() for f in self.list] + [np.full(len(QUADRATURES), QUADRATURE_NOMINAL)])


def past_crossing(dense, t_event, z_before, coupled, k, t_limit, max_tries=64):
    """The first time at or after t_event (a root located on the dense output) where indicator k
    has left the sign it had at the start of the interval, and the state there; bounded search in
    growing steps of ulps, never beyond t_limit."""
    t = t_event
    for i in range(max_tries):  # bounded
        X = dense(t)
        if (coupled.indicators(t, X)[k] > 0.0) != (z_before > 0.0) or t >= t_limit:
            return t, X
        t = min(t_event + 2.0 ** i * math.ulp(t_event), t_limit)
    raise RuntimeError(f"indicator {k} does not change sign within {max_tries} tries after t = {t_event!r} s")


class Recording:
    """run()'s record: the recorded outputs (RECORDED) and the master's integrals on the grid
    t = n dt_out, from the integrator's dense output. The integrals restart from zero in each
    interval (rtol acts on what the interval adds, not on the total): offset keeps what the earlier
    intervals added."""

    def __init__(self, sys_, stop_time, dt_out):
        self.sys = sys_
        self.grid = np.arange(int(round(stop_time / dt_out)) + 1) * dt_out
        self.grid[-1] = stop_time
        self.rec = {f"{n}.{o}": np.full(len(self.grid), np.nan) for n, outs in RECORDED.items() for o in outs}
        self.rec.update({q: np.full(len(self.grid), np.nan) for q in QUADRATURES})
        self.getters = {f"{n}.{o}": sys_.fmus[n].getter(o) for n, outs in RECORDED.items() for o in outs}
        self.offset = np.zeros(len(QUADRATURES))
        self.n = 0  # rows recorded

    def put(self, t, X):
        self.sys.load(t, X)
        for key, get in self.getters.items():
            self.rec[key][self.n] = get()
        for j, q in enumerate(QUADRATURES):
            self.rec[q][self.n] = self.offset[j] + X[self.sys.nq + j]
        self.n += 1

    def restart_integrals(self, X):
        """At the start of an interval: the integrals in X go to the offset, X's restart from zero."""
        self.offset += X[self.sys.nq:]
        X[self.sys.nq:] = 0.0

    def upto(self, dense, t_new, X_new):
        """The grid points up to t_new, from the dense output (X_new at t_new itself)."""
        grid = self.grid
        while self.n < len(grid) and grid[self.n] <= t_new:
            self.put(grid[self.n], dense(grid[self.n]) if grid[self.n] < t_new else X_new)


def start(build, sv_c, rtol, connections, sort, fmus):
    """The three FMUs instantiated into fmus (a dict, so that the caller frees them), brought to their
    common static start and into continuous-time mode. Returns the Coupled system."""
    fmus["contact"] = MeFmu(build / "VibroImpact.fmu", "contact", sv_c, rtol)
    fmus["track"] = MeFmu(build / "Track.fmu", "track", {}, rtol)
    fmus["vehicle"] = MeFmu(build / "Vehicle.fmu", "vehicle", {}, rtol)
    sys_ = Coupled(fmus, connections, sort)
    # initialization mode: every FMU takes its static state under its inputs; pass the outputs
    # along the connections until they agree (the chain is three deep)
    for _ in range(3):
        sys_.propagate()
    for f in fmus.values():
        f.fmu.exitInitializationMode()
        f.running = True
    sys_.event_iteration(initial=True)
    return sys_


def interval(sys_, t, X, t_end, h, method, rtol, atol, events):
    """Integrate from t to t_end or to the first state event. Returns the time and state reached
    (just past the crossing at a state event), whether one ended it, the dense output, and the
    step size to start the next interval with."""
    z0 = sys_.indicators(t, X).copy()
    sol = solve_ivp(sys_.rhs, (t, t_end), X, method=method, rtol=rtol, atol=atol, events=events,
                    dense_output=True, first_step=None if h is None else min(h, t_end - t))
    if sol.status < 0:
        raise RuntimeError(f"solve_ivp at t = {t} s: {sol.message}")
    state_event = sol.status == 1
    if state_event:  # a terminal state event: the earliest indicator that crossed
        k = min((te[0], k) for k, te in enumerate(sol.t_events) if len(te))[1]
        t_new, X_new = past_crossing(sol.sol, sol.t_events[k][0], z0[k], sys_, k, t_end)
    else:
        t_new, X_new = t_end, sol.y[:, -1]
    steps = np.diff(sol.sol.ts)
    return t_new, X_new, state_event, sol.sol, float(steps[-2:].max()) if len(steps) else h


def complete_step(sys_, t, X, event_due):
    """The step is complete at (t, X): fmi2CompletedIntegratorStep for every FMU, then the event
    iteration when an event is due (event_due) or an FMU asks for one. Moves the FMUs' states in X
    when the iteration changed them."""
    sys_.load(t, X)
    asked = False
    for f in sys_.list:
        enter, terminate = f.fmu.completedIntegratorStep()
        if terminate:
            raise RuntimeError(f"{f.name} asks to terminate at t = {t} s: {f.log.text()[-500:]}")
        asked |= enter
    if (event_due or asked) and sys_.event_iteration():
        X[:sys_.nq] = sys_.states()


def run(stop_time=parameters.STOP_TIME, profile=None, excitation=None, rtol=1e-8, method="DOP853", build=None,
        dt_out=1e-5, span=SPAN, connections=CONNECTIONS, sort=True, max_intervals=10 ** 6, contact=None):
    """Integrate the coupled system from the static start to stop_time. Returns a dict of arrays on
    the grid t = n dt_out (the integrator's dense output there): 'contact.F', 'track.z_rail', ...
    (RECORDED), the master's integrals 'J' and 'D', the times of the state events ('state_events'),
    counts ('evaluations', 'time_events', 'intervals') and 'cpu_s', the CPU time of the run (the
    FMUs included: they run in this process). contact: start values of the contact FMU that replace
    the example's (master.contact_start_values); velocity_input is true when the connections pass
    vC_in, unless contact sets it."""
    build = pathlib.Path(build or master.build_dir())
    cpu0 = time.process_time()
    sv_c = master.contact_start_values(profile, excitation, contact)
    sv_c.setdefault("velocity_input", any(c[2:] == ("contact", "vC_in") for c in connections))
    fmus = {}
    try:
        sys_ = start(build, sv_c, rtol, connections, sort, fmus)
        X = np.concatenate([sys_.states(), np.zeros(len(QUADRATURES))])
        atol, events = rtol * sys_.nominals(), sys_.event_functions()
        rec = Recording(sys_, stop_time, dt_out)
        rec.put(0.0, X)
        t, h, n_time, state_events = 0.0, None, 0, []
        for intervals in range(1, max_intervals + 1):  # bounded
            if t >= stop_time:
                break
            t_next = min(f.next_event for f in sys_.list)
            rec.restart_integrals(X)
            t_new, X_new, state_event, dense, h = interval(sys_, t, X, min(stop_time, t_next, t + span), h,
                                                           method, rtol, atol, events)
            if state_event:
                state_events.append(t_new)
            rec.upto(dense, t_new, X_new)
            t, X = t_new, np.array(X_new)
            n_time += t >= t_next
            complete_step(sys_, t, X, state_event or t >= t_next)
        else:
            raise RuntimeError(f"more than {max_intervals} integration intervals")
        return dict(rec.rec, t=rec.grid, evaluations=sys_.evaluations, state_events=np.array(state_events),
                    time_events=n_time, n_time_events=n_time, intervals=intervals, cpu_s=time.process_time() - cpu0)
    except Exception as e:
        logs = "; ".join(f"{n}: {f.log.text()[-300:]}" for n, f in fmus.items() if f.log.messages)
        raise RuntimeError(f"{e}" + (f" (FMU log: {logs})" if logs else "")) from e
    finally:
        for f in fmus.values():
            f.free()
