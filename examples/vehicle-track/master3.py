"""The vehicle-track co-simulation on the FMI 3.0 builds of the three FMUs (build/fmi3/), with early
return: the contact FMU returns at every contact loss and onset, the other FMUs step to that
instant, and the run goes on from there.

Gauss-Seidel contact -> track -> vehicle on the communication points t_n = n step:
- the contact FMU steps first, from t to the next point, its rail input extrapolated with the rail
  velocity and the suspension force of t held; with early return (earlyReturnAllowed) it stops at
  the first change of its mode inside the step, at the time it located. rail_motion as in
  master.py: "ramp" passes the rail velocity as vC_in with velocity_input = true (the FMU carries
  yC_in at vC_in and takes the platform's rate from it), "derivative" as der(yC_in) (the FMI 3.0
  form of fmi2SetRealInputDerivatives), "hold" neither;
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

from vibroimpact.vehicle_track import master
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


class EarlyReturnCoupling(master.Coupling):
    """run()'s communication steps: contact, track, vehicle, in sub-steps that end where the contact
    FMU returns early; the track's and the vehicle's halves and the energy bookkeeping are
    master.Coupling's."""

    def __init__(self, slaves, ports, energy, force, rail_motion, max_substeps):
        super().__init__(slaves, ports, energy, force, rail_motion)
        self.max_substeps = max_substeps
        self.events, self.substeps = [], 0

    def substep(self, t, h):
        """One sub-step from t, at most h long. Returns the time reached (None: t + h, no early
        return) and the impulses of the contact's force and of the force handed to the track."""
        self.substeps += 1
        if self.substeps > self.max_substeps:
            raise RuntimeError(f"more than {self.max_substeps} sub-steps")
        before = self.c
        value, slope = self.rail(h, None, self.t_out, False)
        F_ext = self.v_out["F_wheel"]
        self.p.set_c([value, slope if self.rail_motion == "derivative" else 0.0, slope, F_ext])
        t_end, early = self.C.step(t, h)
        dt = t_end - t
        self.c = master.with_mean(self.p.get_c())
        if early:
            self.events.append(t_end)
        self.energy.contact(before, self.c, value, slope, F_ext, dt)
        self.track(t, dt, self.c)
        self.vehicle(t, dt, self.c)
        return (t_end if early else None), self.c["F_mean"] * dt, self.handed * dt

    def step(self, t, t_next, step):
        """From t to t_next. Returns the time reached and the impulses [N s] of the contact's force
        and of the force handed to the track."""
        impulse_c = impulse_handed = 0.0
        while t_next - t > 1e-9 * step:  # bounded by max_substeps; a rest shorter than that joins the next step
            t_early, j_c, j_handed = self.substep(t, t_next - t)
            t = t_next if t_early is None else t_early
            impulse_c += j_c
            impulse_handed += j_handed
        return t, impulse_c, impulse_handed


def run(step, stop_time=parameters.STOP_TIME, force="F_mean", rail_motion="ramp", early_return=True, profile=None,
        excitation=None, build=None, rtol=1e-8, max_substeps=10 ** 7):
    """Co-simulate (module docstring). Returns a dict of arrays on the grid t_n = n step as master.run,
    and 'events': the times where the contact FMU returned early."""
    if rail_motion not in master.RAIL_MOTIONS:
        raise ValueError(f"rail_motion = {rail_motion!r}: one of {', '.join(master.RAIL_MOTIONS)}")
    build = pathlib.Path(build or master.build_dir()) / "fmi3"
    n_steps = master.steps_of(step, stop_time)
    velocity = rail_motion == "ramp"
    sv_c = dict(master.contact_start_values(profile, excitation), rtol=rtol, velocity_input=velocity)
    slaves = {}
    try:
        C = slaves["contact"] = Slave3(build / "VibroImpact.fmu", "contact", sv_c, early_return)
        T = slaves["track"] = Slave3(build / "Track.fmu", "track", {"rtol": rtol})
        V = slaves["vehicle"] = Slave3(build / "Vehicle.fmu", "vehicle", {"rtol": rtol})
        ports = master.Ports(C, T, V, [n for n in master.CONTACT_OUT if C.has(n)],
                             ["yC_in", "der(yC_in)", "vC_in", "F_ext"])  # the derivative after its value
        ports.settle(lambda track, F_wheel: [track["z_rail"], 0.0, track["v_rail"] if velocity else 0.0, F_wheel])
        for s in slaves.values():
            s.start()
        K = ports.hertz_constant()
        energy = master.PortEnergy(K, ports.get_t()["z_rail"])
        cpl = EarlyReturnCoupling(slaves, ports, energy, force, rail_motion, max_substeps)
        rec = master.Record(n_steps, cpl.c, cpl.t_out, cpl.v_out)
        rec.put(0, cpl.c, cpl.t_out, cpl.v_out, cpl.c[force], energy)
        t = 0.0
        for n in range(n_steps):  # bounded: every sub-step ends at an event or at t_{n+1}
            t, impulse_c, impulse_handed = cpl.step(t, (n + 1) * step, step)
            rec.put(n + 1, cpl.c, cpl.t_out, cpl.v_out, impulse_handed / step, energy, F_mean=impulse_c / step)
        return rec.result(step, K, events=np.array(cpl.events))
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
    ap.add_argument("--rail-motion", choices=master.RAIL_MOTIONS, default="ramp")
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
