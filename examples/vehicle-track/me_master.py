"""The vehicle-track system without coupling error: the three FMUs imported as Model Exchange and
integrated together by one solver.

    python3 me_master.py [--stop-time T] [--rtol R ...] [--method DOP853] [--out results] [--no-cosim]

A short master over fmpy's Model Exchange API (FMU2Model): the states of the contact FMU (wheel y, v),
Track.fmu (rail and sleeper) and Vehicle.fmu (sprung mass, its damper work) are stacked into one
vector and handed to SciPy's solve_ivp; the contact FMU's event indicators are solve_ivp's events
(terminal: the master then runs the event iteration of all three FMUs and restarts the integrator),
its next event time (the kinks of the rolling profile) ends the integration span. The connections
are algebraic, evaluated at every call of the right-hand side in the order that has no loop:

    Track.z_rail       -> VibroImpact.yC_in      (the rail's state)
    VibroImpact.y, v   -> Vehicle.y_wheel, v_wheel (the wheel's states)
    Vehicle.F_wheel    -> VibroImpact.F_ext
    VibroImpact.F      -> Track.F_contact        (the force now, not a step's mean)

The master also integrates three quadratures for the bookkeeping: the contact force's impulse J (mean
forces over any interval), the work dissipated in the three dampers D, and the work the roughness does
on the system WR = integral of F dyb/dt (with the rigid rolling constraint of reference.py, which the
FMU's agrees with to 1e-12 m). The energy balance E(t) + D(t) - WR(t) - E(0), E the stored energy of
reference.System, shows what the integration gives away: there is no coupling to create energy.

main() runs the monolithic reference (reference.py), this master, and the study's co-simulation
couplings at 1e-5 s and 1e-6 s (master.py), and prints the comparison table of the README
(errors against the reference, energy, CPU time).
"""
import argparse
import ctypes
import pathlib
import shutil
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model
from scipy.integrate import solve_ivp

import master
import parameters
import reference
import roughness
import vibroimpact

HERE = pathlib.Path(__file__).resolve().parent
MAX_EVENT_PASSES = 20   # global event iteration: passes over the three FMUs at one event
MAX_SEGMENTS = 10 ** 6  # integration spans (between events, time events and completed steps)


class Model:
    """One FMU as Model Exchange: an FMU2Model with ctypes buffers for its states, derivatives,
    event indicators and ports."""

    def __init__(self, path, name, start_values):
        self.md = read_model_description(str(path))
        self.dir = extract(str(path), unzipdir=tempfile.mkdtemp(prefix=f"vt_me_{name}_"))
        self.vr, self.types = vibroimpact.fmu.variables(self.md)
        self.log = vibroimpact.fmu.MessageLog()
        self.fmu = FMU2Model(guid=self.md.guid, unzipDirectory=self.dir,
                             modelIdentifier=self.md.modelExchange.modelIdentifier, instanceName=name)
        self.fmu.instantiate(callbacks=self.log.callbacks)
        self.nx, self.nz = self.md.numberOfContinuousStates, self.md.numberOfEventIndicators
        self.x = (ctypes.c_double * self.nx)()
        self.dx = (ctypes.c_double * self.nx)()
        self.z = (ctypes.c_double * max(self.nz, 1))()
        self.fmu.setupExperiment(startTime=0.0)
        for k, v in start_values.items():
            vibroimpact.set_value(self.fmu, self.vr[k], v, self.types[k])
        self.fmu.enterInitializationMode()

    def port(self, names):
        """(get, set) of Real variables by name, through preallocated arrays."""
        vr = (ctypes.c_uint * len(names))(*[self.vr[n] for n in names])
        buf = (ctypes.c_double * len(names))()
        f, n = self.fmu, len(names)

        def get():
            f.fmi2GetReal(f.component, vr, n, buf)
            return list(buf)

        def set_(values):
            buf[:] = values
            f.fmi2SetReal(f.component, vr, n, buf)
        return get, set_

    def set_states(self, t, x):
        self.fmu.fmi2SetTime(self.fmu.component, t)
        self.x[:] = x
        self.fmu.fmi2SetContinuousStates(self.fmu.component, self.x, self.nx)

    def states(self):
        self.fmu.getContinuousStates(self.x, self.nx)
        return list(self.x)

    def derivatives(self):
        self.fmu.fmi2GetDerivatives(self.fmu.component, self.dx, self.nx)
        return list(self.dx)

    def indicators(self):
        self.fmu.fmi2GetEventIndicators(self.fmu.component, self.z, self.nz)
        return list(self.z)[:self.nz]

    def nominals(self):
        n = (ctypes.c_double * self.nx)()
        self.fmu.getNominalsOfContinuousStates(n, self.nx)
        return list(n)

    def free(self):
        try:
            self.fmu.terminate()
        except Exception:  # an instance in the error state cannot terminate; it is freed all the same
            pass
        self.fmu.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


class System:
    """The three FMUs as one ODE with events: X = (contact y, v | track z_r, v_r, z_s, v_s | vehicle
    z_b, v_b, W_d | J, D, WR)."""

    def __init__(self, profile, excitation=None, rtol=1e-10, build=None, stop_time=parameters.STOP_TIME):
        build = pathlib.Path(build or master.build_dir())
        sv = master.contact_start_values(profile, excitation)
        sv["rtol"] = rtol  # the contact FMU's re-arming bands follow the integrator's tolerance
        self.C = Model(build / "VibroImpact.fmu", "contact", sv)
        self.T = Model(build / "Track.fmu", "track", {})
        self.V = Model(build / "Vehicle.fmu", "vehicle", {})
        self.models = (self.C, self.T, self.V)
        self.ref = reference.default_system(profile, stop_time, excitation)  # the roughness work only
        tr, ve = parameters.TRACK, parameters.VEHICLE
        self.c_pad, self.c_ballast, self.c_susp = tr["c_pad"], tr["c_ballast"], ve["c_susp"]
        self.get_c, self.set_c = self.C.port(["yC_in", "F_ext"])
        self.get_cf = self.C.port(["F", "y", "v"])[0]
        self.get_t = self.T.port(["z_rail", "v_rail", "v_sleeper"])[0]
        self.set_t = self.T.port(["F_contact"])[1]
        self.get_v = self.V.port(["F_wheel", "v_body"])[0]
        self.set_v = self.V.port(["y_wheel", "v_wheel"])[1]
        self.cache_key, self.cache = None, None
        self.n_rhs = 0
        # initialization: pass the outputs along the chain until they agree (static equilibria)
        z_rail = 0.0
        for _ in range(3):
            self.set_c([z_rail, self.get_v()[0]])
            F, y, v = self.get_cf()
            self.set_t([F])
            z_rail = self.get_t()[0]
            self.set_c([z_rail, self.get_v()[0]])
            F, y, v = self.get_cf()
            self.set_v([y, v])
        for m in self.models:
            m.fmu.exitInitializationMode()
        self.t_next = self.event_iteration(initial=True)
        x = self.C.states() + self.T.states() + self.V.states()
        self.X0 = np.array(x + [0.0, 0.0, 0.0])
        self.nominal = np.array(self.C.nominals() + self.T.nominals() + self.V.nominals() + [1e4 * 1e-6, 1e-3, 1e-3])

    def connect(self, t, X):
        """Set time and states of the three FMUs and their inputs: -> (F, y_w, v_w, z_r, v_r, v_s, v_b)."""
        key = (t, X.tobytes())
        if key == self.cache_key:
            return self.cache
        C, T, V = self.C, self.T, self.V
        C.set_states(t, X[0:2])
        T.set_states(t, X[2:6])
        V.set_states(t, X[6:9])
        z_r, v_r, v_s = self.get_t()
        self.set_v([X[0], X[1]])
        F_wheel, v_b = self.get_v()
        self.set_c([z_r, F_wheel])
        F = self.get_cf()[0]
        self.set_t([F])
        self.cache_key, self.cache = key, (F, X[0], X[1], z_r, v_r, v_s, v_b)
        return self.cache

    def rhs(self, t, X):
        self.n_rhs += 1
        F, y_w, v_w, z_r, v_r, v_s, v_b = self.connect(t, X)
        power = self.c_susp * (v_b - v_w) ** 2 + self.c_pad * (v_r - v_s) ** 2 + self.c_ballast * v_s ** 2
        return np.array(self.C.derivatives() + self.T.derivatives() + self.V.derivatives()
                        + [F, power, F * self.ref.yb(t)[1]])

    def indicator(self, i):
        def z(t, X):
            self.connect(t, X)
            return self.C.indicators()[i]
        z.terminal, z.direction = True, 0
        return z

    def event_iteration(self, initial=False):
        """All three FMUs in event mode, fmi2NewDiscreteStates until none asks for another pass (the inputs
        set again after every pass), then continuous-time mode. -> the next time event (inf: none)."""
        if not initial:
            for m in self.models:
                m.fmu.enterEventMode()
        t_next = np.inf
        for _ in range(MAX_EVENT_PASSES):
            again = False
            for m in self.models:
                needed, terminate, _, _, defined, t_ev = m.fmu.newDiscreteStates()
                if terminate:
                    raise RuntimeError(f"{m.fmu.instanceName}: terminateSimulation: {m.log.text()[-300:]}")
                again |= needed
                if defined:
                    t_next = min(t_next, t_ev)
            z_r = self.get_t()[0]
            F, y, v = self.get_cf()
            self.set_v([y, v])
            self.set_c([z_r, self.get_v()[0]])
            self.set_t([self.get_cf()[0]])
            if not again:
                break
        else:
            raise RuntimeError("the event iteration does not settle")
        for m in self.models:
            m.fmu.enterContinuousTimeMode()
        return t_next

    def completed(self, t, X):
        self.connect(t, X)
        for m in self.models:
            enter, terminate = m.fmu.completedIntegratorStep()
            if terminate:
                raise RuntimeError(f"{m.fmu.instanceName} asks to terminate")
            if enter:
                return True
        return False

    def free(self):
        for m in self.models:
            m.free()


def run(stop_time=parameters.STOP_TIME, profile=None, excitation=None, rtol=1e-10, method="DOP853",
        grid=1e-6, span=1e-3, build=None):
    """Integrate the three FMUs together. Returns the samples on the grid t = k grid (k = 0 .. N): the
    stacked states, the contact force, the impulse, and the counts of events and right-hand sides."""
    s = System(profile, excitation, rtol, build, stop_time)
    try:
        atol = rtol * s.nominal
        events = [s.indicator(i) for i in range(s.C.nz)]
        n = int(round(stop_time / grid))
        tg = np.arange(n + 1) * grid
        Xg = np.empty((n + 1, len(s.X0)))
        Fg = np.empty(n + 1)
        t, X, k = 0.0, s.X0.copy(), 0
        event_times, n_time_events = [], 0
        start = time.process_time()
        for _ in range(MAX_SEGMENTS):  # bounded: every span ends at an event, a time event or span later
            if t >= stop_time:
                break
            t_end = min(stop_time, t + span, s.t_next)
            sol = solve_ivp(s.rhs, (t, t_end), X, method=method, rtol=rtol, atol=atol, events=events,
                            dense_output=True)
            if sol.status < 0:
                raise RuntimeError(f"solve_ivp: {sol.message} at t = {sol.t[-1]}")
            t1 = sol.t[-1]
            while k <= n and tg[k] <= t1:  # samples of this span (time never goes back past its start)
                Xg[k] = sol.sol(tg[k])
                Fg[k] = s.connect(tg[k], Xg[k])[0]
                k += 1
            t, X = t1, sol.y[:, -1].copy()
            if sol.status == 1:  # a state event: located by solve_ivp, handled by the FMUs
                s.connect(t, X)
                s.t_next = s.event_iteration()
                event_times.append(t)
            elif t >= s.t_next or s.completed(t, X):  # a time event (a kink of the profile), or asked for
                s.connect(t, X)
                s.t_next = s.event_iteration()
                n_time_events += 1
            X[:9] = s.C.states() + s.T.states() + s.V.states()  # the event may have moved a state
        else:
            raise RuntimeError("too many spans")
        cpu = time.process_time() - start
        return dict(t=tg, X=Xg, F=Fg, cpu=cpu, n_rhs=s.n_rhs, n_events=len(event_times), event_times=event_times,
                    n_time_events=n_time_events,
                    contact_messages=s.C.log.texts())
    finally:
        s.free()


def energy_residual(r, system):
    """E(t) + D(t) - WR(t) - E(0) [J] of a run, E the stored energy of reference.System."""
    R = reference
    X = r["X"]
    x = np.zeros((len(r["t"]), R.N_STATE))
    x[:, R.YW], x[:, R.VW] = X[:, 0], X[:, 1]
    x[:, R.ZR], x[:, R.VR], x[:, R.ZS], x[:, R.VS] = X[:, 2], X[:, 3], X[:, 4], X[:, 5]
    x[:, R.ZB], x[:, R.VB] = X[:, 6], X[:, 7]
    E = np.array([system.energy(t, xx) for t, xx in zip(r["t"], x)])
    return E + X[:, 10] - X[:, 11] - E[0]


def compare(r, sol, system, mean_step=1e-5):
    """Errors against the reference (W: the static wheel load)."""
    t, W = r["t"], system.W
    F_ref = sol.force(t)
    every = int(round(mean_step / (t[1] - t[0])))
    tm = t[::every]
    Fm = np.diff(r["X"][::every, 9]) / np.diff(tm)
    D_ref = sol.state(t[-1])[reference.D, 0]
    res = energy_residual(r, system)
    return {"force_error": float(np.max(np.abs(r["F"] - F_ref)) / W),
            "mean_force_error": float(np.max(np.abs(Fm - sol.mean_force(tm))) / W),
            "y_error_m": float(np.max(np.abs(r["X"][:, 0] - sol.state(t)[reference.YW]))),
            "energy_residual_J": float(np.max(np.abs(res))),
            "energy_residual_rel": float(np.max(np.abs(res)) / D_ref)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stop-time", type=float, default=parameters.STOP_TIME)
    ap.add_argument("--rtol", type=float, nargs="+", default=[1e-8, 1e-10], help="the one solver's tolerances")
    ap.add_argument("--method", default="DOP853", help="solve_ivp's method (DOP853, RK45, Radau, BDF, LSODA)")
    ap.add_argument("--out", default=str(HERE / "results"))
    ap.add_argument("--no-cosim", action="store_true", help="leave out the co-simulation runs")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    profile = out / "profile.txt"
    roughness.write(profile, *roughness.profile(**parameters.ROUGHNESS))
    system = reference.default_system(profile, a.stop_time)
    start = time.process_time()
    sol = reference.simulate(system, a.stop_time, rtol=1e-10)
    cpu_ref = time.process_time() - start
    D_ref = sol.state(a.stop_time)[reference.D, 0]
    rows = []
    for rtol in a.rtol:
        r = run(a.stop_time, profile, rtol=rtol, method=a.method)
        m = compare(r, sol, system)
        rows.append((f"Model Exchange, one solver ({a.method}, rtol {rtol:g})", m["force_error"],
                     m["mean_force_error"], f"{m['energy_residual_rel']:.1e} (balance)", r["cpu"]))
        print(f"ME rtol {rtol:g}: state events at {', '.join(f'{t:.9f}' for t in r['event_times'])} s "
              f"(reference: {', '.join(f'{t:.9f}' for t, _ in sol.events)} s), {r['n_time_events']} time events, "
              f"{r['n_rhs']} right-hand sides; y within {m['y_error_m']:.1e} m; energy balance "
              f"{m['energy_residual_J']:.1e} J")
    if not a.no_cosim:
        import study
        for label, scheme, order, rail, force in study.COUPLINGS:
            if label not in ("GS hold, F_mean", "GS ramp, F_mean"):
                continue
            for h in (1e-5, 1e-6):
                start = time.process_time()
                rc = master.run(h, a.stop_time, scheme, order, force, rail, profile)
                cpu = time.process_time() - start
                mc = study.metrics(rc, sol, system)
                rows.append((f"{label}, step {h:g} s", mc["force_error"], mc["mean_force_error"],
                             f"{mc['energy_created_rel']:+.1e} (coupling)", cpu))
    lines = ["| run | force error max abs(F - F_ref) / W | mean-force error (1e-5 s) / W | energy / dissipated "
             "| CPU [s] |", "|---|---|---|---|---|"]
    lines.append(f"| monolithic reference (DOP853, rtol 1e-10) | 0 | 0 | "
                 f"{np.abs(sol.energy_residual(np.linspace(0, a.stop_time, 2001))).max() / D_ref:.1e} (balance) "
                 f"| {cpu_ref:.1f} |")
    lines += [f"| {lab} | {fe:.2g} | {mfe:.2g} | {en} | {cpu:.1f} |" for lab, fe, mfe, en, cpu in rows]
    text = "\n".join(lines) + "\n"
    (out / "model_exchange.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
