"""The vehicle-track co-simulation on the FMI 3.0 builds of the three FMUs (build/fmi3/), with early
return: the contact FMU returns at every contact loss and onset, the other FMUs step to that
instant, and the run goes on from there.

Gauss-Seidel contact -> track -> vehicle on the communication points t_n = n step:
- the contact FMU steps first, from t to the next point, its rail input extrapolated with the rail
  velocity (der(yC_in) = v_rail, the FMI 3.0 form of fmi2SetRealInputDerivatives; rail_motion
  "hold" sets none) and the suspension force of t held; with early return (earlyReturnAllowed) it
  stops at the first change of its mode inside the step, at the time it located;
- the track then steps to the same instant with the contact's force over that sub-step (F_mean:
  its impulse divided by the sub-step, or F), and the vehicle with the wheel's y and v there;
- the next sub-step starts at that instant and ends at the next communication point (or earlier,
  at the next event; a rest shorter than 1e-9 step joins the following step).
Records at the communication points what master.run records, so that the study's metrics apply:
the contact's outputs at the point, except F_mean and the force handed to the track, which are
the impulse of the whole step (summed over its sub-steps) divided by the step; and the energy the
coupling creates at the two ports (master.py explains the bookkeeping), summed over the sub-steps.
Also returns the times of the early returns ('events').
"""
import ctypes
import pathlib
import shutil
import tempfile

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

import master
import parameters
from vibroimpact import fmi3


class Slave3:
    """One FMU of FMI 3.0: an FMU3Slave in initialization mode, with preallocated port arrays."""

    def __init__(self, path, name, start_values, early_return=False, tolerance=None):
        self.md = read_model_description(str(path))
        self.dir = extract(str(path), unzipdir=tempfile.mkdtemp(prefix=f"vt3_{name}_"))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.types = {v.name: v.type for v in self.md.modelVariables}
        self.fmu = FMU3Slave(guid=self.md.guid, unzipDirectory=self.dir,
                             modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(earlyReturnAllowed=early_return, logMessage=lambda *a: None)
        self.fmu.enterInitializationMode(tolerance=tolerance)
        for k, val in start_values.items():
            fmi3.set_value(self.fmu, self.vr[k], val, self.types[k])
        self.running = False

    def start(self):
        self.fmu.exitInitializationMode()
        self.running = True

    def has(self, name):
        return name in self.vr

    def getter(self, names):
        vr = (ctypes.c_uint * len(names))(*[self.vr[n] for n in names])
        buf = (ctypes.c_double * len(names))()
        fmu, n = self.fmu, len(names)

        def get():
            fmu.fmi3GetFloat64(fmu.component, vr, n, buf, n)
            return dict(zip(names, buf))
        return get

    def setter(self, names):
        vr = (ctypes.c_uint * len(names))(*[self.vr[n] for n in names])
        buf = (ctypes.c_double * len(names))()
        fmu, n = self.fmu, len(names)

        def set_(values):
            buf[:] = values
            fmu.fmi3SetFloat64(fmu.component, vr, n, buf, n)
        return set_

    def step(self, t, h):
        """-> (the time reached, whether it returned early)."""
        status, _, _, early, last = fmi3.do_step(self.fmu, t, h)
        if status != fmi3.OK:
            raise RuntimeError(f"{self.fmu.instanceName}: fmi3DoStep from {t!r} s over {h!r} s: status {status}")
        return (last if early else t + h), early

    def free(self):
        try:
            if self.running:
                self.fmu.terminate()
        finally:
            self.fmu.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


def run(step, stop_time=parameters.STOP_TIME, force="F_mean", rail_motion="ramp", early_return=True, profile=None,
        excitation=None, build=None, rtol=1e-8, max_substeps=10 ** 7):
    """Co-simulate (module docstring). Returns a dict of arrays on the grid t_n = n step as master.run,
    and 'events': the times where the contact FMU returned early."""
    build = pathlib.Path(build or master.build_dir()) / "fmi3"
    n_steps = int(round(stop_time / step))
    if abs(n_steps * step - stop_time) > 1e-9 * stop_time:
        raise ValueError(f"stop_time {stop_time} is not a multiple of the step {step}")
    sv_c = master.contact_start_values(profile, excitation)
    sv_c["rtol"] = rtol
    slaves = {}
    try:
        C = slaves["contact"] = Slave3(build / "VibroImpact.fmu", "contact", sv_c, early_return)
        T = slaves["track"] = Slave3(build / "Track.fmu", "track", {"rtol": rtol})
        V = slaves["vehicle"] = Slave3(build / "Vehicle.fmu", "vehicle", {"rtol": rtol})
        c_out = [n for n in master.CONTACT_OUT if C.has(n)]
        get_c, get_t, get_v = C.getter(c_out), T.getter(master.TRACK_OUT), V.getter(master.VEHICLE_OUT)
        get_k = C.getter(["E_star", "R_star"])
        set_c = C.setter(["yC_in", "der(yC_in)", "F_ext"])  # the derivative after its value
        set_t, set_v = T.setter(["F_contact"]), V.setter(["y_wheel", "v_wheel"])
        ramp = rail_motion == "ramp"

        # initialization: pass the outputs along the chain until they agree (as master.run)
        t_out = {"z_rail": 0.0}
        for _ in range(3):
            set_c([t_out["z_rail"], 0.0, get_v()["F_wheel"]])
            set_t([get_c()["F"]])
            t_out = get_t()
            set_c([t_out["z_rail"], 0.0, get_v()["F_wheel"]])
            c = get_c()
            set_v([c["y"], c["v"]])
        for s in slaves.values():
            s.start()
        kk = get_k()
        K = 4.0 / 3.0 * kk["E_star"] * np.sqrt(kk["R_star"])

        def U(delta):
            return 0.4 * K * max(delta, 0.0) ** 2.5

        c, t_out, v_out = get_c(), get_t(), get_v()
        rec = {k: np.empty(n_steps + 1) for k in
               [f"contact.{n}" for n in c] + [f"track.{n}" for n in t_out] + [f"vehicle.{n}" for n in v_out]
               + ["F_to_track", "E_coupling", "E_rail_port", "E_susp_port"]}

        def record(i, mean, handed, e_rail, e_susp):
            for k2, v2 in c.items():
                rec[f"contact.{k2}"][i] = v2
            rec["contact.F_mean"][i] = mean
            for k2, v2 in t_out.items():
                rec[f"track.{k2}"][i] = v2
            for k2, v2 in v_out.items():
                rec[f"vehicle.{k2}"][i] = v2
            rec["F_to_track"][i] = handed
            rec["E_rail_port"][i], rec["E_susp_port"][i] = e_rail, e_susp
            rec["E_coupling"][i] = e_rail + e_susp

        e_rail = e_susp = 0.0
        platform_end = t_out["z_rail"]  # where the contact's platform input path ended
        record(0, c["F_mean"], c[force], 0.0, 0.0)
        events, t, substeps = [], 0.0, 0
        for n in range(n_steps):  # bounded: every sub-step ends at an event or at t_{n+1}
            t_next = (n + 1) * step
            impulse_c = impulse_handed = 0.0
            while t_next - t > 1e-9 * step:  # a rest shorter than that joins the next step
                substeps += 1
                if substeps > max_substeps:
                    raise RuntimeError(f"more than {max_substeps} sub-steps")
                value, slope = t_out["z_rail"], (t_out["v_rail"] if ramp else 0.0)
                F_ext, y0 = v_out["F_wheel"], c["y"]
                e_rail += U(c["delta"] + value - platform_end) - U(c["delta"])
                set_c([value, slope, F_ext])
                t_end, early = C.step(t, t_next - t)
                dt = t_end - t
                c = get_c()
                if early:
                    events.append(t_end)
                e_rail += slope * c["F_mean"] * dt
                e_susp += F_ext * (c["y"] - y0)
                platform_end = value + slope * dt
                impulse_c += c["F_mean"] * dt
                handed = c[force]
                set_t([handed])
                w0 = t_out["W_in"]
                T.step(t, dt)
                t_out = get_t()
                e_rail += t_out["W_in"] - w0
                impulse_handed += handed * dt
                E_before = v_out["E"]
                set_v([c["y"], c["v"]])
                after_set = get_v()
                e_susp += after_set["E"] - E_before
                V.step(t, dt)
                v_out = get_v()
                e_susp += v_out["W_in"] - after_set["W_in"]
                t = t_end if early else t_next
            record(n + 1, impulse_c / step, impulse_handed / step, e_rail, e_susp)
        rec["t"] = np.arange(n_steps + 1) * step
        rec["K"] = K
        rec["events"] = np.array(events)
        return rec
    finally:
        for s in slaves.values():
            s.free()


def main():
    import argparse
    import time
    ap = argparse.ArgumentParser(description="FMI 3.0 master with early return for the vehicle-track example")
    ap.add_argument("--step", type=float, default=1e-5)
    ap.add_argument("--stop-time", type=float, default=parameters.STOP_TIME)
    ap.add_argument("--force", choices=["F", "F_mean"], default="F_mean")
    ap.add_argument("--rail-motion", choices=["hold", "ramp"], default="ramp")
    ap.add_argument("--no-early-return", action="store_true")
    ap.add_argument("--profile")
    ap.add_argument("--excitation", type=float, nargs=2, metavar=("A", "F"))
    a = ap.parse_args()
    t0 = time.time()
    r = run(a.step, a.stop_time, a.force, a.rail_motion, not a.no_early_return, a.profile, a.excitation)
    F = r["contact.F"]
    print(f"{time.time() - t0:.1f} s: {len(r['events'])} early returns, F {F.min():.0f} .. {F.max():.0f} N, "
          f"energy created by the coupling {r['E_coupling'][-1]:.3e} J")


if __name__ == "__main__":
    main()
