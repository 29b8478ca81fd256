"""A short co-simulation master for the vehicle-track example (examples/vehicle-track), on fmpy's
FMU2Slave.

Three FMUs: the contact FMU (VibroImpact.fmu: the wheel and the wheel-rail contact), Track.fmu
(rail and sleeper) and Vehicle.fmu (the sprung mass on the primary suspension). Connections:

    Vehicle.F_wheel    -> VibroImpact.F_ext      suspension force on the wheel
    VibroImpact.y, v   -> Vehicle.y_wheel, v_wheel
    Track.z_rail       -> VibroImpact.yC_in      rail displacement under the wheel
    Track.v_rail       -> VibroImpact.vC_in      rail velocity (rail_motion "ramp": velocity_input = true)
    VibroImpact.F_mean -> Track.F_contact        (or F) the rail receives its negative

Schemes: Gauss-Seidel (the FMUs step one after the other within a communication step, each with
the newest outputs of the ones before it, in the order given) or Jacobi (all step with the
outputs of the last communication point, as libcosim's fixed-step algorithm does).

Rail motion (RAIL_MOTIONS: how the contact FMU sees the rail within a communication step):
    hold        yC_in held at the rail position the contact FMU is given, no rate: within the step
                the contact sees a rail at rest (velocity_input = false, no input derivative).
    ramp        the rail on a straight line at its velocity, given as the input vC_in with
                velocity_input = true: the FMU carries yC_in at vC_in through the step and takes the
                platform's rate from it wherever it needs it (damping, turning points, stick, mode
                choices). With the contact before the track the line starts at the rail position of
                the last communication point with the track's v_rail there (an extrapolation); with
                the track first, it joins the track's positions at both ends of the step (an
                interpolation: vC_in is the slope between them). The example's recommended coupling.
    derivative  the same straight line as the derivative of yC_in (fmi2SetRealInputDerivatives,
                order 1), velocity_input = false: for a master that sets input derivatives but does
                not connect vC_in. In Co-Simulation the FMU takes the platform's rate from the
                derivative then, so this gives the numbers of "ramp".

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
    ("track", "v_rail", "contact", "vC_in"),      # rail_motion "ramp"
    ("contact", "F_mean", "track", "F_contact"),  # or F
]
RAIL_MOTIONS = ("hold", "ramp", "derivative")
CONTACT_IN = ["yC_in", "F_ext", "vC_in"]
CONTACT_OUT = ["F", "F_mean", "y", "v", "yC", "delta"]
TRACK_OUT = ["z_rail", "v_rail", "E", "W_in", "W_dissipated"]
VEHICLE_OUT = ["F_wheel", "z_body", "v_body", "E", "W_in", "W_dissipated"]


class Slave:
    """One FMU: an FMU2Slave with preallocated value-reference arrays for its ports."""

    def __init__(self, path, name, start_values, t0=0.0, tolerance=None, log=None, events=True):
        """log: a vibroimpact.MessageLog that keeps what the instance logs, with logEvents on (events=False:
        off); None: fmpy's logger, which prints."""
        self.md = read_model_description(str(path))
        self.dir = extract(str(path), unzipdir=tempfile.mkdtemp(prefix=f"vt_{name}_"))
        self.vr, self.types = vifmu.variables(self.md)
        self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir,
                             modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        if log is None:
            self.fmu.instantiate()
        else:
            self.fmu.instantiate(callbacks=log.callbacks)
            if events:
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

    def step(self, t, h):
        """fmi2DoStep from t over h."""
        self.fmu.doStep(t, h)

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
            """The values, then (derivatives given) their first derivatives: setting a value clears
            its derivative."""
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


class Ports:
    """The three FMUs' ports: getters of the outputs (get_c, get_t, get_v; get_k: the contact's
    E_star and R_star) and setters of the inputs (set_c takes contact_inputs in that order, set_t
    F_contact, set_v y_wheel and v_wheel). C, T, V: objects with getter(names) and setter(names), as
    Slave."""

    def __init__(self, C, T, V, contact_outputs, contact_inputs):
        self.get_c, self.get_t, self.get_v = C.getter(contact_outputs), T.getter(TRACK_OUT), V.getter(VEHICLE_OUT)
        self.get_k = C.getter(["E_star", "R_star"])
        self.set_c = C.setter(contact_inputs)
        self.set_t, self.set_v = T.setter(["F_contact"]), V.setter(["y_wheel", "v_wheel"])

    def settle(self, contact_values):
        """Initialization mode: pass the outputs along the chain vehicle -> contact -> track ->
        contact -> vehicle three times, until they agree. contact_values(track, F_wheel): the values
        set_c takes, from the track's outputs (a dict: z_rail, v_rail) and the suspension force."""
        track = {"z_rail": 0.0, "v_rail": 0.0}
        for _ in range(3):
            self.set_c(contact_values(track, self.get_v()["F_wheel"]))
            self.set_t([self.get_c()["F"]])  # at the static start F_mean is F
            track = self.get_t()
            self.set_c(contact_values(track, self.get_v()["F_wheel"]))
            c = self.get_c()
            self.set_v([c["y"], c["v"]])

    def hertz_constant(self):
        """K [N/m^1.5] of the contact FMU: 4/3 E_star sqrt(R_star)."""
        k = self.get_k()
        return 4.0 / 3.0 * k["E_star"] * np.sqrt(k["R_star"])


class PortEnergy:
    """The work the coupling creates at the two ports (the module docstring), summed as the FMUs
    step: e_rail at the rail, e_susp at the suspension [J]."""

    def __init__(self, K, z_rail):
        self.K = K
        self.e_rail = self.e_susp = 0.0
        self.platform_end = z_rail  # where the contact's platform input path ended

    def hertz(self, delta):
        """The Hertz energy 2/5 K delta^2.5 [J]."""
        return 0.4 * self.K * max(delta, 0.0) ** 2.5

    def contact(self, before, after, z_rail, slope, F_ext, dt):
        """The contact FMU stepped over dt from the outputs `before` to `after`, its platform input
        starting at z_rail with the slope given, under F_ext."""
        self.e_rail += self.hertz(before["delta"] + z_rail - self.platform_end) - self.hertz(before["delta"])
        self.e_rail += slope * after["F_mean"] * dt
        self.e_susp += F_ext * (after["y"] - before["y"])
        self.platform_end = z_rail + slope * dt

    def track(self, W_in_before, W_in_after):
        self.e_rail += W_in_after - W_in_before

    def vehicle(self, E_before, after_set, after_step):
        """The vehicle's energy jumped from E_before when the wheel position it holds was replaced
        (outputs after_set), then it stepped (outputs after_step)."""
        self.e_susp += after_set["E"] - E_before
        self.e_susp += after_step["W_in"] - after_set["W_in"]


class Record:
    """The arrays run() returns, on the grid t_n = n step: the FMUs' outputs ('contact.F', ...), the
    force handed to the track ('F_to_track') and the energy the coupling created ('E_coupling', the
    sum of 'E_rail_port' and 'E_susp_port')."""

    def __init__(self, n_steps, c, t_out, v_out):
        names = [f"contact.{n}" for n in c] + [f"track.{n}" for n in t_out] + [f"vehicle.{n}" for n in v_out]
        self.rec = {k: np.empty(n_steps + 1) for k in names + ["F_to_track", "E_coupling", "E_rail_port", "E_susp_port"]}

    def put(self, i, c, t_out, v_out, handed, energy, F_mean=None):
        """Row i; F_mean: the contact's mean force over the step when not its own output's."""
        for prefix, outs in (("contact", c), ("track", t_out), ("vehicle", v_out)):
            for k, v in outs.items():
                self.rec[f"{prefix}.{k}"][i] = v
        if F_mean is not None:
            self.rec["contact.F_mean"][i] = F_mean
        self.rec["F_to_track"][i] = handed
        self.rec["E_rail_port"][i], self.rec["E_susp_port"][i] = energy.e_rail, energy.e_susp
        self.rec["E_coupling"][i] = energy.e_rail + energy.e_susp

    def result(self, step, K, **more):
        rows = len(self.rec["F_to_track"])
        return dict(self.rec, t=np.arange(rows) * step, K=K, **more)


def steps_of(step, stop_time, max_steps=10 ** 7):
    """The number of communication steps of size step to stop_time (a multiple of it)."""
    n_steps = int(round(stop_time / step))
    if n_steps > max_steps or abs(n_steps * step - stop_time) > 1e-9 * stop_time:
        raise ValueError(f"stop_time {stop_time} is not a multiple of the step {step} (or too many steps)")
    return n_steps


def with_mean(c):
    """Contact outputs with F_mean (F where the FMU has none)."""
    if "F_mean" not in c:
        c["F_mean"] = c["F"]
    return c


class Coupling:
    """run()'s communication steps over the three FMUs (Slave), with the energy bookkeeping; c,
    t_out, v_out: the newest outputs, handed: the force last handed to the track."""

    def __init__(self, slaves, ports, energy, force, rail_motion):
        """rail_motion: one of RAIL_MOTIONS (the module docstring); the contact FMU's inputs in
        ports.set_c are CONTACT_IN."""
        self.C, self.T, self.V = slaves["contact"], slaves["track"], slaves["vehicle"]
        self.p, self.energy, self.force, self.rail_motion = ports, energy, force, rail_motion
        self.c, self.t_out, self.v_out = with_mean(ports.get_c()), ports.get_t(), ports.get_v()
        self.handed = self.c[force]

    def rail(self, step, old, track, track_stepped):
        """The rail's path over the step the contact FMU is given: (its position at t [m], its slope
        [m/s]); track_stepped: the track's outputs are those of t + step already."""
        if self.rail_motion == "hold":
            return track["z_rail"], 0.0
        if track_stepped:  # interpolate between the track's positions at both ends of the step
            return old["track"]["z_rail"], (track["z_rail"] - old["track"]["z_rail"]) / step
        return track["z_rail"], track["v_rail"]  # extrapolate with the rail velocity

    def contact(self, t, step, old, track, vehicle, track_stepped):
        """Step the contact FMU with the track's and the vehicle's outputs given; track_stepped:
        the track's are those of t + step already."""
        value, slope = self.rail(step, old, track, track_stepped)
        F_ext = vehicle["F_wheel"]
        # vC_in is the slope ("ramp": the FMU's platform rate; otherwise not read)
        self.p.set_c([value, F_ext, slope], [slope, 0.0, 0.0] if self.rail_motion == "derivative" else None)
        self.C.step(t, step)
        self.c = with_mean(self.p.get_c())
        self.energy.contact(old["contact"], self.c, value, slope, F_ext, step)
        return self.c

    def track(self, t, step, contact):
        self.handed = contact[self.force]
        self.p.set_t([self.handed])
        w0 = self.t_out["W_in"]
        self.T.step(t, step)
        self.t_out = self.p.get_t()
        self.energy.track(w0, self.t_out["W_in"])
        return self.t_out

    def vehicle(self, t, step, contact):
        E_before = self.p.get_v()["E"]
        self.p.set_v([contact["y"], contact["v"]])
        after_set = self.p.get_v()
        self.V.step(t, step)
        self.v_out = self.p.get_v()
        self.energy.vehicle(E_before, after_set, self.v_out)
        return self.v_out

    def step(self, t, step, seq, gauss_seidel):
        """The FMUs step from t in the order seq, each with the newest outputs of the ones before it
        (gauss_seidel) or all with those of t (Jacobi)."""
        old = {"contact": self.c, "track": self.t_out, "vehicle": self.v_out}
        new = {}

        def latest(name):
            return new[name] if gauss_seidel and name in new else old[name]
        for name in seq:
            if name == "contact":
                new[name] = self.contact(t, step, old, latest("track"), latest("vehicle"), "track" in new)
            elif name == "track":
                new[name] = self.track(t, step, latest("contact"))
            else:
                new[name] = self.vehicle(t, step, latest("contact"))


def run(step, stop_time=parameters.STOP_TIME, scheme="gauss-seidel", order=("vehicle", "contact", "track"),
        force="F_mean", rail_motion="hold", profile=None, excitation=None, build=None, rtol=1e-8,
        max_steps=10 ** 7, contact=None, contact_log=None, record=(), contact_events=True):
    """Co-simulate with a fixed communication step. Returns a dict of arrays on the grid
    t_n = n step (n = 0 .. N): contact outputs, track and vehicle outputs, the force handed to the
    track, and the cumulative energy the coupling created ('E_coupling'); Record says which. contact:
    start values of the contact FMU that replace the example's (contact_start_values); contact_log:
    a vibroimpact.MessageLog that keeps the contact FMU's log, its events included unless
    contact_events is false; record: more of the contact FMU's outputs to record (beside CONTACT_OUT)."""
    if rail_motion not in RAIL_MOTIONS:
        raise ValueError(f"rail_motion = {rail_motion!r}: one of {', '.join(RAIL_MOTIONS)}")
    build = pathlib.Path(build or build_dir())
    n_steps = steps_of(step, stop_time, max_steps)
    velocity = rail_motion == "ramp"
    sv_c = dict(contact_start_values(profile, excitation, contact), rtol=rtol, velocity_input=velocity)
    slaves = {}
    try:
        C = slaves["contact"] = Slave(build / "VibroImpact.fmu", "contact", sv_c, log=contact_log,
                                          events=contact_events)
        slaves["track"] = Slave(build / "Track.fmu", "track", {"rtol": rtol})
        slaves["vehicle"] = Slave(build / "Vehicle.fmu", "vehicle", {"rtol": rtol})
        if force == "F_mean" and not C.has("F_mean"):
            raise RuntimeError("this VibroImpact.fmu has no output F_mean")
        ports = Ports(C, slaves["track"], slaves["vehicle"], [n for n in CONTACT_OUT + list(record) if C.has(n)],
                      CONTACT_IN)
        ports.settle(lambda track, F_wheel: [track["z_rail"], F_wheel, track["v_rail"] if velocity else 0.0])
        for s in slaves.values():
            s.start()
        K = ports.hertz_constant()
        energy = PortEnergy(K, ports.get_t()["z_rail"])
        cpl = Coupling(slaves, ports, energy, force, rail_motion)
        rec = Record(n_steps, cpl.c, cpl.t_out, cpl.v_out)
        rec.put(0, cpl.c, cpl.t_out, cpl.v_out, cpl.handed, energy)
        seq = list(order) if scheme == "gauss-seidel" else ["vehicle", "contact", "track"]
        for n in range(n_steps):  # bounded
            cpl.step(n * step, step, seq, scheme == "gauss-seidel")
            rec.put(n + 1, cpl.c, cpl.t_out, cpl.v_out, cpl.handed, energy)
        return rec.result(step, K)
    finally:
        for s in slaves.values():
            s.free()
