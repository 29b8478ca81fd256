"""The upper stop (upper_stop, gap: a second surface at yC + gap above the mass, moving with the
platform) against the closed form of a shaken cavity and the independent two-sided reference
(vibroimpact.reference.two_sided), in Co-Simulation and Model Exchange, FMI 2.0 and 3.0; its energy
balance, exact rollback, and the refusal of a clearance that is not positive.

The closed form (fmu-test/test_two_sided_reference.py): a sphere in a cavity shaken a (cos(2 pi f t) -
1), without gravity or load, with instantaneous impacts of restitution e, settles into two impacts per
cycle, one on each wall, half a period apart, at the free-flight speed u = (1+e)/(1-e) a w cos(phi),
gap = 2 a sin(phi) + (1+e)/(1-e) a pi cos(phi); a Hertz contact's finite duration moves it by under 1 %.
"""
import re

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from me_importer import Importer
from test_two_sided_reference import SPHERE, periodic_orbits
from vibroimpact import fmu as _fmu
from vibroimpact.reference import model as M
from vibroimpact.reference import two_sided as T

TRAJECTORY_TOL = 1e-5   # of the range of y: the FMU against the reference
OUTPUTS = ("y", "v", "F", "F_upper", "delta", "delta_upper", "mode", "mode_upper", "n_impacts", "n_impacts_upper",
           "E_contact", "W_dissipated")
CAVITY = dict(e=0.8, a=1e-3, f=50.0, gap=0.02)   # the steel sphere of SPHERE in a cavity 20 mm high at 50 Hz


class Slave:
    """An FMI 2.0 or 3.0 Co-Simulation instance of the contact FMU with the upper stop, started touching
    the lower surface (init = touching, v0) at the platform yC_in = y0, which then steps down to 0 (an
    input jump at t = 0: the mass stays, y0 above the lower surface). log: a vibroimpact.fmu.Messages
    that keeps the event log (logEvents) and what else the instance logs."""

    def __init__(self, path, params, y0=0.0, v0=0.0, log=None):
        md = read_model_description(path)
        self.fmi3 = md.fmiVersion.startswith("3")
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.kinds = {v.name: v.type for v in md.modelVariables}
        kind = FMU3Slave if self.fmi3 else FMU2Slave
        self.s = kind(guid=md.guid, unzipDirectory=extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName="upper")
        if log is None:
            self.s.instantiate()
        elif self.fmi3:
            self._log3 = lambda env, status, category, message: log.keep(status, category, message.decode())
            self.s.instantiate(loggingOn=True, logMessage=self._log3)
        else:
            self.s.instantiate(callbacks=log.callbacks, loggingOn=True)
        if log is not None:
            self.s.setDebugLogging(True, ["logEvents"])
        if self.fmi3:
            self.s.enterInitializationMode(startTime=0.0)
        else:
            self.s.setupExperiment(startTime=0.0)
            self.s.enterInitializationMode()
        for name, value in {"upper_stop": True, **params, "init": 2, "v0": v0, "yC_in": y0}.items():
            self.set(name, value)
        self.s.exitInitializationMode()
        self.set("yC_in", 0.0)
        self.t = 0.0

    def set(self, name, value):
        _fmu.set_value(self.s, self.vr[name], value, self.kinds[name])

    def get(self, name):
        vr, kind = [self.vr[name]], self.kinds[name]
        if kind in ("Real", "Float64"):
            return (self.s.getFloat64 if self.fmi3 else self.s.getReal)(vr)[0]
        if self.fmi3:
            return (self.s.getInt64 if kind == "Enumeration" else self.s.getInt32)(vr)[0]
        return self.s.getInteger(vr)[0]

    def step(self, h):
        self.s.doStep(self.t, h)
        self.t += h

    def run(self, t_end, h):
        """Step to t_end by h: the outputs at every communication point after the start."""
        out = {k: [] for k in ("t",) + OUTPUTS}
        for _ in range(int(round(t_end / h))):
            self.step(h)
            out["t"].append(self.t)
            for k in OUTPUTS:
                out[k].append(self.get(k))
        return {k: np.array(v) for k, v in out.items()}

    def close(self):
        self.s.terminate()
        self.s.freeInstance()


def cs_run(path, params, t_end, h=1e-4, y0=0.0, v0=0.0):
    s = Slave(path, params, y0, v0)
    try:
        return s.run(t_end, h)
    finally:
        s.close()


def me_run(path, params, t_end, v0=0.0, rtol=1e-10):
    """Model Exchange (the independent importer), started touching the lower surface: the outputs at
    every step end."""
    imp = Importer(path, dict(params, init=2, v0=v0, upper_stop=True), rtol=rtol, max_step=1e-4)
    out = {k: [] for k in ("t",) + OUTPUTS}

    def record(i, t):
        out["t"].append(t)
        for k in OUTPUTS:
            out[k].append(i.real(k) if i.types[k] in ("Real", "Float64") else i.integer(k))
    imp.run(t_end, record)
    return {k: np.array(v) for k, v in out.items()}


def fmus():
    """The FMI 2.0 and 3.0 FMUs of the build."""
    return [p for p in (_fmu.fmu_path(), _fmu.fmu3_path(required=False)) if p]


def free_flight_speeds(r):
    """|v| of every free flight (both contacts free: without gravity or load v is constant), one per
    flight (a flight ends at the next contact onset), in order."""
    free = (r["mode"] == 0) & (r["mode_upper"] == 0)
    onsets = r["n_impacts"] + r["n_impacts_upper"]
    speeds, seen = [], set()
    for i in np.nonzero(free)[0]:
        if onsets[i] not in seen:
            seen.add(onsets[i])
            speeds.append(abs(r["v"][i]))
    return speeds


def assert_along(r, ref, what):
    span = np.ptp(ref.y)
    err = np.max(np.abs(r["y"] - ref.y)) / span
    assert err < TRAJECTORY_TOL, (what, err)
    F_scale = max(np.max(ref.F_lower), np.max(ref.F_upper))
    events = np.array([e[0] for e in ref.events] or [np.inf])
    away = np.min(np.abs(r["t"][:, None] - events[None, :]), axis=1) > 1e-9   # not at an event's instant
    assert np.max(np.abs(r["F_upper"] - ref.F_upper)[away]) < 1e-3 * F_scale, what   # the force's slope
    return err


@pytest.mark.timeout(600)
@pytest.mark.parametrize("path", fmus())
def test_a_shaken_cavity_settles_at_the_closed_form_speed(path):
    """Started on the closed form's stable orbit (phi < 0), the sphere keeps two impacts per cycle, one on
    each wall; its free-flight speed is within 1 % of u = (1+e)/(1-e) a w cos(phi), and within 1e-5 of the
    reference's; y along 0.4 s agrees with the reference to 1e-5 of its range."""
    c = CAVITY
    (phi, u, y0, v0), _ = periodic_orbits(c["e"], c["a"], c["f"], c["gap"])
    params = dict(SPHERE, e_restitution=c["e"], a=c["a"], f=c["f"], gap=c["gap"], rtol=1e-10)
    r = cs_run(path, params, 0.4, y0=y0, v0=v0)
    ref = T.simulate(dict(SPHERE, e_restitution=c["e"], a=c["a"], f=c["f"]), c["gap"], t_end=0.4, rtol=1e-10,
                     t_eval=r["t"], y0=y0, v0=v0)
    assert r["n_impacts"][-1] == r["n_impacts_upper"][-1] == round(0.4 * c["f"]), (r["n_impacts"][-1], r["n_impacts_upper"][-1])
    speeds = free_flight_speeds(r)
    assert speeds[-1] == pytest.approx(u, rel=1e-2), (speeds[-3:], u)
    assert speeds[-1] == pytest.approx(speeds[-2], rel=1e-4), speeds[-3:]   # settled
    separations = [(t, abs(v)) for t, side, kind, before, after, v in ref.events if after == M.FREE and before != M.FREE]
    assert len(separations) == 2 * round(0.4 * c["f"]), len(separations)
    for t, speed in separations:   # the FMU's speed in the flight that follows (constant: no gravity, no load)
        i = np.searchsorted(r["t"], t, side="right")
        if i < len(r["t"]):
            assert r["mode"][i] == r["mode_upper"][i] == 0
            assert abs(r["v"][i]) == pytest.approx(speed, rel=1e-5), (t, r["v"][i], speed)
    assert_along(r, ref, "cavity")


def mirror_params(law):
    return dict(m=0.03288, P=0.0, R1=0.01, R2=0.0, contact_model=law, Y=1e9, a=0.0, gap=0.005, rtol=1e-10)


@pytest.mark.timeout(600)
@pytest.mark.parametrize("law", [M.JOHNSON, M.LEPP, M.HERTZ_DAMPED])
def test_a_mass_falls_up_onto_the_upper_surface(law):
    """Under g = -9.81 the mass, started at rest on the lower surface, falls up through the gap of 5 mm
    onto the upper surface and bounces there: y against the reference to 1e-5 of its range (Co-Simulation
    and Model Exchange, FMI 2.0 and 3.0); the same motion as a fall onto the lower surface mirrored (the
    upper contact's force that of the lower one); and the energy balance kinetic + E_contact +
    W_dissipated + m g (y - y0) = 0 (the platform does not move) to 1e-6 of the energy exchanged."""
    p = mirror_params(law)
    up = dict(p, g=-9.81)
    t_end = 0.15
    for path in fmus():
        runs = {"cs": cs_run(path, up, t_end), "me": me_run(path, up, t_end)}
        for kind, r in runs.items():
            ref = T.simulate({k: v for k, v in up.items() if k not in ("gap", "rtol")}, p["gap"], t_end=t_end,
                             rtol=1e-10, t_eval=r["t"], y0=0.0, v0=0.0)
            assert r["n_impacts_upper"][-1] >= 2 and r["n_impacts"][-1] == 0, (kind, r["n_impacts_upper"][-1])
            assert r["n_impacts_upper"][-1] == len(ref.impacts[T.UPPER]), kind
            assert_along(r, ref, (path, kind))
            kinetic = 0.5 * p["m"] * r["v"] ** 2
            balance = kinetic + r["E_contact"] + r["W_dissipated"] + p["m"] * -9.81 * r["y"]
            exchanged = np.max(kinetic)
            assert np.max(np.abs(balance)) < 1e-6 * exchanged, (path, kind, np.max(np.abs(balance)) / exchanged)
    # the mirror image: a fall onto the lower surface from the top of the gap (CS, FMI 2.0)
    path = _fmu.fmu_path()
    r_up = cs_run(path, up, t_end)
    r_down = cs_run(path, dict(p, g=9.81), t_end, y0=p["gap"])
    assert np.max(np.abs(r_up["y"] - (p["gap"] - r_down["y"]))) < TRAJECTORY_TOL * p["gap"]
    assert np.max(np.abs(r_up["F_upper"] - r_down["F"])) < 1e-3 * np.max(r_down["F"])


@pytest.mark.timeout(600)
def test_a_paper_scene_with_an_upper_stop_the_mass_reaches():
    """The paper's Johnson scene (the platform at a = 20 um, 560 Hz, the mass of 407.7 kg pressed by 40 kN)
    with an upper surface 4 um above the mass's start: the mass bounces into it; y against the reference to
    1e-5 of its range in Co-Simulation and Model Exchange."""
    p = dict(a=2e-5, f=560.0, gap=4e-6, rtol=1e-10)
    t_end = 0.01
    for path in fmus():
        for kind, r in (("cs", cs_run(path, p, t_end, h=2e-5)), ("me", me_run(path, p, t_end))):
            ref = T.simulate(dict(a=2e-5, f=560.0, init=M.TOUCHING), p["gap"], t_end=t_end, rtol=1e-10,
                             t_eval=r["t"], y0=0.0, v0=0.0)
            assert r["n_impacts_upper"][-1] >= 1 and r["n_impacts_upper"][-1] == len(ref.impacts[T.UPPER]), kind
            assert_along(r, ref, (path, kind))


@pytest.mark.timeout(300)
def test_rollback_with_the_upper_stop_is_exact():
    """A state taken in flight and set back: the steps that follow, across impacts on both walls, give
    the same outputs bit for bit (FMI 2.0 Co-Simulation, also through a serialized state)."""
    c = CAVITY
    (phi, u, y0, v0), _ = periodic_orbits(c["e"], c["a"], c["f"], c["gap"])
    params = dict(SPHERE, e_restitution=c["e"], a=c["a"], f=c["f"], gap=c["gap"])
    s = Slave(_fmu.fmu_path(), params, y0, v0)
    try:
        s.run(0.013, 1e-3)
        state, t_state = s.s.getFMUstate(), s.t
        blob = s.s.serializeFMUstate(state)
        first = s.run(0.04, 1e-3)
        assert first["n_impacts"][-1] >= 2 and first["n_impacts_upper"][-1] >= 2
        for again in (state, s.s.deSerializeFMUstate(blob)):
            s.s.setFMUstate(again)
            s.t = t_state
            second = s.run(0.04, 1e-3)
            for k in OUTPUTS:
                assert np.array_equal(first[k], second[k]), k
    finally:
        s.close()


def test_a_clearance_that_is_not_positive_is_refused(fmu_path):
    """upper_stop = true with gap = 0 fails the initialization, naming gap and its range; a negative gap
    is refused when set (below its minimum 0)."""
    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    log = _fmu.MessageLog()
    s = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu_path), modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName="gap")
    s.instantiate(callbacks=log.callbacks, loggingOn=True)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.setBoolean([vr["upper_stop"]], [True])
    with pytest.raises(Exception):
        s.setReal([vr["gap"]], [-1e-3])
    with pytest.raises(Exception):
        s.exitInitializationMode()
    assert any("gap = 0 m" in m and "> 0" in m for m in log.texts()), log.texts()
    s.freeInstance()


def test_without_the_upper_stop_its_outputs_are_zero(fmu_path):
    """upper_stop = false (the default): F_upper, delta_upper, mode_upper and n_impacts_upper stay 0."""
    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu_path), modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName="plain")
    s.instantiate()
    _fmu.initialize(s, vr, dict(a=2e-5, f=560.0))
    for k in range(50):
        s.doStep(k * 1e-4, 1e-4)
        assert s.getReal([vr["F_upper"], vr["delta_upper"]]) == [0.0, 0.0]
        assert s.getInteger([vr["mode_upper"], vr["n_impacts_upper"]]) == [0, 0]
    s.terminate()
    s.freeInstance()


@pytest.mark.timeout(300)
@pytest.mark.parametrize("law", [M.LEPP, M.HERTZ_DAMPED])
def test_model_exchange_partials_of_the_upper_contact(fmu_path, law):
    """In Model Exchange, pressed into the upper surface (the mass fallen up under g = -9.81, mode_upper
    elastic): the directional derivatives of F_upper, delta_upper, F, der_v and E_contact with respect to
    the states y and v are central differences of the outputs (to 1e-6 of their scale); F, the lower
    contact's force, is 0 with its partials."""
    imp = Importer(fmu_path, dict(mirror_params(law), g=-9.81, init=2, upper_stop=True), rtol=1e-10, max_step=1e-5)
    imp.run(0.031935)   # the onset is at 0.0319275 s; the contact lasts about 80 us
    assert imp.integer("mode_upper") == 1 and imp.integer("mode") == 0
    f, names = imp.model, ["F_upper", "delta_upper", "F", "der_v", "E_contact"]
    refs = [imp.vr[n] for n in names]
    x0 = imp._states()
    f0 = np.array(f.getReal(refs))
    for i, (known, h) in enumerate((("y", 1e-10), ("v", 1e-6))):
        J = np.array(f.getDirectionalDerivative(refs, [imp.vr[known]], [1.0]))
        side = []
        for s in (1.0, -1.0):
            x = x0.copy()
            x[i] += s * h
            imp._at(imp.t, x)
            side.append(np.array(f.getReal(refs)))
        imp._at(imp.t, x0)
        fd = (side[0] - side[1]) / (2 * h)
        scale = np.abs(J) + np.abs(fd) + 1e-9 * np.abs(f0) / h
        assert np.all(np.abs(J - fd) <= 1e-6 * scale), (known, dict(zip(names, J)), dict(zip(names, fd)))
        assert J[2] == 0.0 and f0[2] == 0.0
    assert f.getDirectionalDerivative([imp.vr["delta_upper"]], [imp.vr["y"]], [1.0])[0] == 1.0


def test_the_upper_contact_is_checked_against_the_range_of_validity(fmu_path):
    """Hertz's law beyond F_Y on the upper surface (the mass falls up 5 mm under g = -9.81: about 380 N
    against F_Y = 38 N) is warned about as on the lower one (Co-Simulation: at the communication points,
    every 10 us here); the same fall without the upper stop touches nothing and warns of nothing."""
    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    for upper, warned in ((True, True), (False, False)):
        log = _fmu.MessageLog()
        s = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu_path), modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName="validity")
        s.instantiate(callbacks=log.callbacks, loggingOn=True)
        _fmu.initialize(s, vr, dict(mirror_params(M.HERTZ), g=-9.81, init=2, upper_stop=upper,
                                    gap=mirror_params(M.HERTZ)["gap"] if upper else 0.0))
        for k in range(3300):
            s.doStep(k * 1e-5, 1e-5)
        assert any("the contact force reached" in m and "F_Y" in m for m in log.texts()) == warned, log.texts()
        s.terminate()
        s.freeInstance()


@pytest.mark.timeout(600)
def test_stick_on_the_upper_surface():
    """Johnson (paper unloading, Y = 200 MPa) pressed up onto the upper surface by P = -40 kN, g = -9.81
    (the mass starts a picometre below it), the platform shaken a = -0.3 mm at 100 Hz: the contact
    sticks (mode_upper 4) as the lower one does from a pre-loaded start, and the mass also reaches the
    lower surface. The stick samples and y against the reference (y to 1e-5 of its range), in
    Co-Simulation and Model Exchange, FMI 2.0 and 3.0."""
    base = dict(P=-40000.0, g=-9.81, a=-3e-4, f=100.0, Y=2e8)
    gap, t_end = 1e-12, 0.03
    for path in fmus():
        for kind, r in (("cs", cs_run(path, dict(base, gap=gap, rtol=1e-10), t_end, h=1e-5)),
                        ("me", me_run(path, dict(base, gap=gap), t_end))):
            ref = T.simulate(dict(base, init=M.TOUCHING), gap, t_end=t_end, rtol=1e-10, t_eval=r["t"], y0=0.0, v0=0.0)
            stick, ref_stick = r["mode_upper"] == 4, ref.mode_upper == 4
            assert ref_stick.sum() > (100 if kind == "cs" else 10) and abs(int(stick.sum()) - int(ref_stick.sum())) <= 2, (kind, stick.sum(), ref_stick.sum())
            assert r["n_impacts"][-1] >= 1 and r["n_impacts"][-1] == len(ref.impacts[T.LOWER]), kind
            assert_along(r, ref, (path, kind))


@pytest.mark.timeout(300)
def test_model_exchange_rollback_with_the_upper_stop_is_exact(fmu_path):
    """Model Exchange: a state taken between impacts on both walls (the cavity started at the lower wall
    at the closed form's speed) and set back gives the same states, modes and counts along the same
    steps of the importer, bit for bit."""
    c = CAVITY
    params = dict(SPHERE, e_restitution=c["e"], a=c["a"], f=c["f"], gap=c["gap"], init=2, upper_stop=True)
    (phi, u, y0, v0), _ = periodic_orbits(c["e"], c["a"], c["f"], c["gap"])
    imp = Importer(fmu_path, dict(params, v0=u), rtol=1e-9, max_step=1e-4)
    imp.run(0.013)
    state, t0, x0 = imp.model.getFMUstate(), imp.t, imp.x.copy()
    counts = (imp.integer("n_impacts"), imp.integer("n_impacts_upper"))

    def record_run():
        out = []
        imp.run(0.05, lambda i, t: out.append((t, *i._states(), i.integer("mode"), i.integer("mode_upper"),
                                               i.integer("n_impacts"), i.integer("n_impacts_upper"))))
        return out
    first = record_run()
    assert first[-1][-2] > counts[0] and first[-1][-1] > counts[1], (first[-1], counts)  # both walls hit
    imp.model.setFMUstate(state)
    imp.t, imp.x = t0, x0
    assert record_run() == first


@pytest.mark.timeout(300)
def test_model_exchange_mean_force_at_a_step_end_is_the_net_force():
    """Model Exchange, after each completed integrator step (a step of no length: the mean is the force
    itself): F_mean is the net contact force F - F_upper, also while the mass is pressed into the upper
    surface (the mass fallen up under g = -9.81 onto it, Hertz), FMI 2.0 and 3.0."""
    for path in fmus():
        imp = Importer(str(path), dict(mirror_params(M.HERTZ), g=-9.81, init=2, upper_stop=True), rtol=1e-10,
                       max_step=1e-5)
        pressed = []

        def record(i, t):
            F, F_upper, F_mean = i.real("F"), i.real("F_upper"), i.real("F_mean")
            assert F_mean == F - F_upper, (path, t, F_mean, F, F_upper)
            if F_upper > 0.0:
                pressed.append(t)
        imp.run(0.0321, record)
        assert len(pressed) >= 3, (path, pressed)


# the event log's lines (doc/using.md, "The event log"); with the upper stop each ends in its contact
EVENT_LINE = re.compile(r"event t=(?P<t>\S+) kind=(?P<kind>start|guard|input|kink)(?: guard=(?P<guard>\d))? "
                        r"mode=(?:(?P<start>\d)|(?P<before>\d)->(?P<after>\d))(?: delta=(?P<delta>\S+) v=(?P<v>\S+))?"
                        r"(?: contact=(?P<contact>lower|upper))?")


def event_lines(log):
    lines = [m for _, cat, m in log.messages if cat == "logEvents" and m.startswith("event ")]
    matches = [EVENT_LINE.fullmatch(m) for m in lines]
    assert all(matches), [m for m, k in zip(lines, matches) if not k]
    return matches


@pytest.mark.timeout(300)
@pytest.mark.parametrize("path", fmus(), ids=["fmi2", "fmi3"][:len(fmus())])
def test_the_event_log_names_each_contact(path):
    """With the upper stop every event line ends in contact=lower or contact=upper and gives that
    contact's mode and indentation: the cavity (both walls hit) logs one start line per contact (the
    lower one at delta = 0, the upper one at -gap), its guard lines hold guards 0, 1 (lower) and 2, 3
    (upper), every contact onset is at its own surface (delta = 0) and their counts are n_impacts and
    n_impacts_upper; then a jump of yC_in that pushes the upper surface 0.1 um into the free mass logs
    the upper contact's switch to elastic (kind=input mode=0->1 contact=upper). Without the upper stop
    the lines of a fall onto the platform carry no contact field (the one-sided log as it always was)."""
    c = CAVITY
    (phi, u, y0, v0), _ = periodic_orbits(c["e"], c["a"], c["f"], c["gap"])
    params = dict(SPHERE, e_restitution=c["e"], a=c["a"], f=c["f"], gap=c["gap"], rtol=1e-10)
    log = _fmu.MessageLog() if "fmi3" not in str(path) else _fmu.Messages()
    s = Slave(str(path), params, y0, v0, log=log)
    try:
        s.run(0.06, 1e-4)
        while s.get("mode") or s.get("mode_upper"):   # into a free flight
            s.step(1e-4)
        counts = {"lower": s.get("n_impacts"), "upper": s.get("n_impacts_upper")}
        lines = event_lines(log)
        assert counts["lower"] >= 2 and counts["upper"] >= 2, counts
        assert all(m["contact"] for m in lines), [m.string for m in lines if not m["contact"]]
        starts = [(m["contact"], float(m["delta"])) for m in lines if m["kind"] == "start"]
        assert starts == [("lower", 0.0), ("upper", -c["gap"])], starts
        guards = [m for m in lines if m["kind"] == "guard"]
        assert all((int(m["guard"]) >= 2) == (m["contact"] == "upper") for m in guards), [m.string for m in guards]
        for side in ("lower", "upper"):
            onsets = [m for m in guards if m["contact"] == side and m["before"] == "0" and m["after"] != "0"]
            assert len(onsets) == counts[side] and all(float(m["delta"]) == 0.0 for m in onsets), (side, counts)
        # the upper surface jumps 0.1 um into the mass: yC_in moves the platform by the difference
        yC = s.get("yC")
        s.set("yC_in", s.get("yC_in") + (s.get("y") - c["gap"] - 1e-7) - yC)
        s.step(1e-6)
        jumps = [m for m in event_lines(log)[len(lines):] if m["kind"] == "input"]
        assert [(m["before"], m["after"], m["contact"]) for m in jumps] == [("0", "1", "upper")], [m.string for m in jumps]
    finally:
        s.close()
    # the one-sided FMU's lines: no contact field
    log = _fmu.MessageLog() if "fmi3" not in str(path) else _fmu.Messages()
    s = Slave(str(path), dict(params, upper_stop=False, gap=0.0, g=9.81), 1e-3, 0.0, log=log)   # falls onto the platform
    try:
        s.run(0.05, 1e-4)
        lines = event_lines(log)
        assert s.get("n_impacts") >= 1 and lines and not any(m["contact"] for m in lines), [m.string for m in lines]
    finally:
        s.close()


@pytest.mark.timeout(300)
@pytest.mark.parametrize("event_mode", [False, True])
def test_fmi3_returns_early_at_each_contacts_mode_change(event_mode):
    """FMI 3.0 Co-Simulation with early return (with and without Event Mode): a step ends at every
    change of mode of either contact, so the cavity started at the lower wall at 2 m/s up (its walls
    hit in turn, an onset and a separation each) returns early as often as its two contacts switch:
    2 (n_impacts + n_impacts_upper) times, at the times the event log gives."""
    from vibroimpact import fmi3 as _fmi3
    path = _fmu.fmu3_path(required=False)
    if not path.is_file():
        pytest.skip("no FMI 3.0 build")
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    kinds = {v.name: v.type for v in md.modelVariables}
    inst = _fmi3.Logged(md, extract(str(path)), name="early")
    s = inst.instantiate(event_mode=event_mode, early_return=True, logging=True)
    s.setDebugLogging(True, ["logEvents"])
    params = dict(SPHERE, e_restitution=CAVITY["e"], a=CAVITY["a"], f=CAVITY["f"], gap=CAVITY["gap"], init=2, v0=2.0,
                  upper_stop=True)
    _fmi3.initialize(s, vr, params, kinds=kinds, tolerance=1e-10, event_mode=event_mode)
    times, _ = _fmi3.run_to_events(s, 0.0, 0.1, 1e-3)
    lower, upper = s.getInt32([vr["n_impacts"]])[0], s.getInt32([vr["n_impacts_upper"]])[0]
    switches = [float(m["t"]) for m in event_lines(inst) if m["kind"] == "guard" and m["before"] != m["after"]]
    s.terminate()
    s.freeInstance()
    assert lower > 0 and upper > 0, (lower, upper)
    assert len(times) == len(switches) == 2 * (lower + upper), (times, switches, lower, upper)
    assert times == switches


def test_fmu_events_keeps_the_mode_changes_of_the_contact_asked_for():
    """compare.fmu_events reads one contact's mode changes: the lower one's by default (the lines that name
    contact=lower, and a one-sided run's, which name none), the upper one's when asked; a mode number of
    one contact never enters the other's list."""
    from vibroimpact.compare import fmu_events
    log = [(0, "logEvents", "event t=0 kind=start mode=0 delta=0 v=2 contact=lower"),
           (0, "logEvents", "event t=0.25 kind=guard guard=2 mode=0->1 delta=0 v=2 contact=upper"),
           (0, "logEvents", "event t=0.5 kind=guard guard=3 mode=1->0 delta=1e-06 v=-2 contact=upper"),
           (0, "logEvents", "event t=0.75 kind=guard guard=0 mode=0->1 delta=0 v=-2 contact=lower"),
           (0, "logEvents", "event t=1 kind=guard guard=1 mode=1->1 delta=0 v=-2 contact=lower")]
    assert fmu_events(log) == [(0.75, 0, 1)]  # before: the upper contact's two changes too
    assert fmu_events(log, "upper") == [(0.25, 0, 1), (0.5, 1, 0)]
    one_sided = [(0, "logEvents", "event t=0.75 kind=guard guard=0 mode=0->1 delta=0 v=-2")]
    assert fmu_events(one_sided) == [(0.75, 0, 1)] and fmu_events(one_sided, "upper") == []
