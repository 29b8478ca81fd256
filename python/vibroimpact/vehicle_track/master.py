"""A short co-simulation master for the vehicle-track example (examples/vehicle-track), on fmpy's
FMU2Slave.

Three FMUs: the contact FMU (VibroImpact.fmu: the wheel and the wheel-rail contact), Track.fmu
(rail and sleeper) and Vehicle.fmu (the sprung mass on the primary suspension). Connections:

    Vehicle.F_wheel    -> VibroImpact.F_ext      suspension force on the wheel
    VibroImpact.y, v   -> Vehicle.y_wheel, v_wheel
    Track.z_rail       -> VibroImpact.yC_in      rail displacement under the wheel
    VibroImpact.F_mean -> Track.F_contact        (or F) the rail receives its negative

Schemes: Gauss-Seidel (the FMUs step one after the other within a communication step, each with
the newest outputs of the ones before it, in the order given) or Jacobi (all step with the
outputs of the last communication point, as libcosim's fixed-step algorithm does).

Initialization: every FMU starts in static equilibrium under its inputs at the end of
initialization, so the master passes the outputs around in initialization mode until they
agree (three passes along the chain vehicle -> contact -> track -> contact -> vehicle).

Energy bookkeeping: at each port the master adds up the work the coupling creates, which is zero
in the monolithic system: at the rail, the work the rail motion does on the contact (from the
jump of yC_in, through the Hertz energy 2/5 K delta^2.5, and from its slope times the impulse)
plus the work the handed force does on the rail (Track.W_in); at the suspension, the work of
F_ext on the wheel (F_ext times the wheel's displacement) plus Vehicle.W_in and the jump of the
vehicle's energy when the wheel position it holds is replaced.
"""
import ctypes
import pathlib
import shutil
import tempfile

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from .. import fmu as vifmu
from . import parameters

# (from FMU, output, to FMU, input): what run() passes; OspSystemStructure.xml states the same.
CONNECTIONS = [
    ("vehicle", "F_wheel", "contact", "F_ext"),
    ("contact", "y", "vehicle", "y_wheel"),
    ("contact", "v", "vehicle", "v_wheel"),
    ("track", "z_rail", "contact", "yC_in"),
    ("contact", "F_mean", "track", "F_contact"),  # or F
]
CONTACT_OUT = ["F", "F_mean", "y", "v", "yC", "delta"]
TRACK_OUT = ["z_rail", "v_rail", "E", "W_in", "W_dissipated"]
VEHICLE_OUT = ["F_wheel", "z_body", "v_body", "E", "W_in", "W_dissipated"]


class Slave:
    """One FMU: an FMU2Slave with preallocated value-reference arrays for its ports."""

    def __init__(self, path, name, start_values, t0=0.0, tolerance=None, log=None):
        """log: a vibroimpact.MessageLog that keeps what the instance logs, with logEvents on."""
        self.md = read_model_description(str(path))
        self.dir = extract(str(path), unzipdir=tempfile.mkdtemp(prefix=f"vt_{name}_"))
        self.vr, self.types = vifmu.variables(self.md)
        self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir,
                             modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        if log is None:
            self.fmu.instantiate()
        else:
            self.fmu.instantiate(callbacks=log.callbacks)
            self.fmu.setDebugLogging(True, ["logEvents"])
        self.fmu.setupExperiment(tolerance=tolerance, startTime=t0)
        for k, val in start_values.items():
            self.set_start(k, val)
        self.fmu.enterInitializationMode()
        self.running = False

    def start(self):
        self.fmu.exitInitializationMode()
        self.running = True

    def has(self, name):
        return name in self.vr

    def set_start(self, name, value):
        vifmu.set_value(self.fmu, self.vr[name], value, self.types[name])

    def getter(self, names):
        vr = (ctypes.c_uint * len(names))(*[self.vr[n] for n in names])
        buf = (ctypes.c_double * len(names))()
        fmu, n = self.fmu, len(names)

        def get():
            fmu.fmi2GetReal(fmu.component, vr, n, buf)
            return dict(zip(names, buf))
        return get

    def setter(self, names):
        vr = (ctypes.c_uint * len(names))(*[self.vr[n] for n in names])
        buf = (ctypes.c_double * len(names))()
        order = (ctypes.c_int * len(names))(*([1] * len(names)))
        fmu, n = self.fmu, len(names)

        def set_(values, derivatives=None):
            buf[:] = values
            fmu.fmi2SetReal(fmu.component, vr, n, buf)
            if derivatives is not None:
                buf[:] = derivatives
                fmu.fmi2SetRealInputDerivatives(fmu.component, vr, n, order, buf)
        return set_

    def free(self):
        try:
            if self.running:
                self.fmu.terminate()
        finally:
            self.fmu.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


def contact_start_values(profile=None, excitation=None, contact=None):
    """Start values of the contact FMU for the example: the wheel of parameters.WHEEL, Hertz;
    rolling over `profile` (a file) or an internal harmonic excitation (a [m], f [Hz]); `contact`
    (a dict) replaces or adds values (another law)."""
    sv = dict(parameters.WHEEL, **(contact or {}))
    if profile:
        sv["profile_file"] = str(profile)
    else:
        sv.pop("V"), sv.pop("x0")
    if excitation:
        sv["a"], sv["f"] = excitation
    return sv


def build_dir():
    """The folder with the three FMUs: that of vibroimpact.fmu_path() (build/ of the checkout)."""
    return vifmu.build_dir()


def run(step, stop_time=parameters.STOP_TIME, scheme="gauss-seidel", order=("vehicle", "contact", "track"),
        force="F_mean", rail_motion="hold", profile=None, excitation=None, build=None, rtol=1e-8,
        max_steps=10 ** 7, contact=None, contact_log=None, record=()):
    """Co-simulate with a fixed communication step. Returns a dict of arrays on the grid
    t_n = n step (n = 0 .. N): contact outputs, track and vehicle outputs, the force handed to the
    track, and the cumulative energy the coupling created ('E_coupling'). contact: start values of
    the contact FMU that replace the example's (contact_start_values); contact_log: a
    vibroimpact.MessageLog that keeps the contact FMU's log, its events included; record: more of the
    contact FMU's outputs to record (beside CONTACT_OUT)."""
    build = pathlib.Path(build or build_dir())
    n_steps = int(round(stop_time / step))
    if n_steps > max_steps or abs(n_steps * step - stop_time) > 1e-9 * stop_time:
        raise ValueError(f"stop_time {stop_time} is not a multiple of the step {step} (or too many steps)")
    sv_c = contact_start_values(profile, excitation, contact)
    sv_c["rtol"] = rtol
    slaves = {}
    try:
        C = slaves["contact"] = Slave(build / "VibroImpact.fmu", "contact", sv_c, log=contact_log)
        T = slaves["track"] = Slave(build / "Track.fmu", "track", {"rtol": rtol})
        V = slaves["vehicle"] = Slave(build / "Vehicle.fmu", "vehicle", {"rtol": rtol})
        if force == "F_mean" and not C.has("F_mean"):
            raise RuntimeError("this VibroImpact.fmu has no output F_mean")
        c_out = [n for n in CONTACT_OUT + list(record) if C.has(n)]
        get_c, get_t, get_v = C.getter(c_out), T.getter(TRACK_OUT), V.getter(VEHICLE_OUT)
        get_k = C.getter(["E_star", "R_star"])
        set_c = C.setter(["yC_in", "F_ext"])
        set_t, set_v = T.setter(["F_contact"]), V.setter(["y_wheel", "v_wheel"])
        ramp = rail_motion == "ramp"

        # initialization: pass the outputs along the chain until they agree
        for _ in range(3):
            set_c([0.0 if _ == 0 else t_out["z_rail"], get_v()["F_wheel"]])
            c = get_c()
            set_t([c["F"]])  # at the static start F_mean is F
            t_out = get_t()
            set_c([t_out["z_rail"], get_v()["F_wheel"]])
            c = get_c()
            set_v([c["y"], c["v"]])
        for s in slaves.values():
            s.start()
        kk = get_k()
        K = 4.0 / 3.0 * kk["E_star"] * np.sqrt(kk["R_star"])

        def U(delta):
            return 0.4 * K * max(delta, 0.0) ** 2.5

        c, t_out, v_out = get_c(), get_t(), get_v()
        if "F_mean" not in c:
            c["F_mean"] = c["F"]
        rec = {k: np.empty(n_steps + 1) for k in
               [f"contact.{n}" for n in c] + [f"track.{n}" for n in t_out] + [f"vehicle.{n}" for n in v_out]
               + ["F_to_track", "E_coupling", "E_rail_port", "E_susp_port"]}

        def record(i, handed, e_rail, e_susp):
            for k2, v2 in c.items():
                rec[f"contact.{k2}"][i] = v2
            for k2, v2 in t_out.items():
                rec[f"track.{k2}"][i] = v2
            for k2, v2 in v_out.items():
                rec[f"vehicle.{k2}"][i] = v2
            rec["F_to_track"][i] = handed
            rec["E_rail_port"][i], rec["E_susp_port"][i] = e_rail, e_susp
            rec["E_coupling"][i] = e_rail + e_susp

        e_rail = e_susp = 0.0
        platform_end = t_out["z_rail"]  # where the contact's platform input path ended
        record(0, c[force], 0.0, 0.0)
        seq = list(order) if scheme == "gauss-seidel" else ["vehicle", "contact", "track"]
        for n in range(n_steps):  # bounded
            t = n * step
            old_c, old_t, old_v = c, t_out, v_out
            new = {}

            def latest(name):
                if scheme == "gauss-seidel" and name in new:
                    return new[name]
                return {"contact": old_c, "track": old_t, "vehicle": old_v}[name]

            handed = None
            for name in seq:
                if name == "contact":
                    tr, ve = latest("track"), latest("vehicle")
                    if ramp and "track" in new:     # track already at t_{n+1}: interpolate
                        value, slope = old_t["z_rail"], (tr["z_rail"] - old_t["z_rail"]) / step
                    elif ramp:                      # extrapolate with the rail velocity
                        value, slope = tr["z_rail"], tr["v_rail"]
                    else:
                        value, slope = tr["z_rail"], 0.0
                    F_ext = ve["F_wheel"]
                    e_rail += U(old_c["delta"] + value - platform_end) - U(old_c["delta"])
                    set_c([value, F_ext], [slope, 0.0] if ramp else None)
                    y0 = old_c["y"]
                    C.fmu.doStep(t, step)
                    c = get_c()
                    if "F_mean" not in c:
                        c["F_mean"] = c["F"]
                    new["contact"] = c
                    e_rail += slope * c["F_mean"] * step
                    e_susp += F_ext * (c["y"] - y0)
                    platform_end = value + slope * step
                elif name == "track":
                    handed = latest("contact")[force]
                    set_t([handed])
                    w0 = old_t["W_in"]
                    T.fmu.doStep(t, step)
                    t_out = get_t()
                    new["track"] = t_out
                    e_rail += t_out["W_in"] - w0
                else:
                    cc = latest("contact")
                    E_before = get_v()["E"]
                    set_v([cc["y"], cc["v"]])
                    e_susp += get_v()["E"] - E_before
                    w0 = get_v()["W_in"]
                    V.fmu.doStep(t, step)
                    v_out = get_v()
                    new["vehicle"] = v_out
                    e_susp += v_out["W_in"] - w0
            record(n + 1, handed, e_rail, e_susp)
        rec["t"] = np.arange(n_steps + 1) * step
        rec["K"] = K
        return rec
    finally:
        for s in slaves.values():
            s.free()

