"""Model Exchange of the contact FMU where the importer does something unusual: a state it sets that
contradicts the mode, input jumps and tunable parameters at events (as co-simulation applies them),
non-finite values, and the nominals of its absolute tolerances."""
import math

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException

from vibroimpact.reference.scenarios import SCENARIOS
from vibroimpact.me import Me, MeInstance, run_me


@pytest.fixture
def me(fmu_path, unzipdir, model_description):
    made = []

    def make():
        inst = MeInstance(fmu_path, unzipdir, model_description)
        inst.instantiate(categories=("logEvents",))
        made.append(inst.model)
        return inst, Me(inst)

    yield make
    for f in made:
        f.freeInstance()


def guard_events(inst):
    """The state events the instance logged (logEvents), in order."""
    return [msg for _, _, msg in inst.messages if msg.startswith("event ") and "kind=guard" in msg]


def test_penetration_set_during_free_flight_is_caught_by_the_indicators(me):
    """The mass leaves the platform (touching start, moving up); the importer then sets a position
    1 um inside the platform. The free mode's contact indicator turns negative at once (an importer
    sees the sign change), and the event iteration takes the state as it is: elastic, with the Hertz
    force of that penetration."""
    inst, m = me()
    m.start(params=dict(contact_model=1, init=2, v0=0.01, a=0.0))
    assert m.integer("mode") == 0
    z0 = m.indicators()
    assert min(z0) > 0.0
    m.fmu.setTime(1e-4)
    y, v = m.states()[:2]
    yC = m.real("yC")
    m.set_states([yC - 1e-6, v])
    assert m.real("F") == 0.0 and m.indicators()[0] < 0.0  # flagged, not hidden
    m.fmu.enterEventMode()
    info = m.settle()
    assert m.integer("mode") == 1 and not info[3]  # the state as it is: no snap
    K = 4.0 / 3.0 * m.real("E_star") * math.sqrt(m.real("R_star"))
    # the state as set, to rounding (delta = yC - y of numbers near 5e-5 m: a few 1e-15 of 1e-6; 0 measured)
    assert m.real("delta") == pytest.approx(1e-6, rel=1e-13)
    assert m.real("F") == pytest.approx(K * 1e-6 ** 1.5, rel=1e-13)
    assert min(m.indicators()) > 0.0


def test_non_finite_states_are_refused(me):
    inst, m = me()
    m.start(params=dict(contact_model=1))
    x = m.states()
    with pytest.raises(FMICallException):
        m.set_states([float("nan"), 0.0])
    assert m.states() == x and any("state 0 (y) = nan is not finite" in e for e in inst.errors())


def test_nominals_are_the_problem_scales(me):
    """y is tens of micrometres: the nominals are the length and velocity scales co-simulation uses for
    its absolute tolerances (doc/model.md), so rtol x nominal is a sensible atol for an importer."""
    inst, m = me()
    m.start(params=dict(contact_model=1))
    L, V, _ = m.nominals()
    d_static = m.real("delta")
    assert L == pytest.approx(d_static, rel=1e-6)  # Hertz, static start: the static indentation
    k = 1.5 * 4.0 / 3.0 * m.real("E_star") * math.sqrt(m.real("R_star")) * math.sqrt(L)
    assert V == pytest.approx(L * math.sqrt(k / 407.747), rel=1e-6)


def test_tunable_amplitude_moves_the_platform_at_the_event(me):
    """A new a set in event mode acts in the event iteration, as at a co-simulation step: the platform
    moves by (a_new - a)(cos phi - 1), the mass stays, the indentation follows."""
    inst, m = me()
    m.start(params=dict(contact_model=1, a=1e-5, f=100.0))
    t = 1.3e-3
    m.fmu.setTime(t)
    m.fmu.completedIntegratorStep()
    y0, yC0, d0 = m.real("y"), m.real("yC"), m.real("delta")
    m.fmu.enterEventMode()
    m.set("a", 3e-5)
    assert m.real("yC") == yC0  # not before the event iteration
    m.settle()
    move = 2e-5 * (math.cos(2 * math.pi * 100.0 * t) - 1.0)
    assert m.real("yC") == pytest.approx(yC0 + move, abs=1e-18)
    assert m.real("y") == pytest.approx(y0, abs=1e-18) and m.real("delta") == pytest.approx(d0 + move, abs=1e-18)


def step_input(t_jump, jump, stop):
    dt = np.dtype([("time", np.float64), ("yC_in", np.float64)])
    return np.array([(0.0, 0.0), (t_jump, 0.0), (t_jump, jump), (stop, jump)], dtype=dt)


def test_input_jump_during_plastic_loading_acts_as_in_co_simulation(fmu_path, unzipdir, model_description):
    """Johnson (Fig. 4b): the platform drops by 2 um while the contact loads plastically. Co-simulation
    applies a new yC_in at the step after its communication point (memory written down at the old
    indentation, then the jump, then the mode chosen); fmpy's Model Exchange loop meets the jump as an
    input event and sets it in event mode. Both unload from the same delta_c (2 um above the new
    indentation), reload onto the virgin curve and go on alike."""
    from conftest import Logged, start
    p, t_jump, jump, stop, h = SCENARIOS["fig4b"].full, 1.6e-3, -2e-6, 4e-3, 1e-4
    r, inst = run_me(fmu_path, p, stop, rtol=1e-11, output=("y", "delta_c", "mode"), output_interval=h,
                     input=step_input(t_jump, jump, stop))
    assert not inst.errors()
    log = Logged(model_description, unzipdir)
    s = log.instantiate(logging=True)
    s.setDebugLogging(True, ["logEvents"])
    vr = {v.name: v.valueReference for v in model_description.modelVariables}
    start(s, vr, p, tolerance=1e-11)
    y, dc = [], []
    for k in range(int(round(stop / h)) + 1):
        if k:
            s.doStep((k - 1) * h, h)
        if abs(k * h - t_jump) < h / 2:
            s.setReal([vr["yC_in"]], [jump])
        y.append(s.getReal([vr["y"]])[0])
        dc.append(s.getReal([vr["delta_c"]])[0])
    s.freeInstance()
    cs_modes = [m for m in log.text().splitlines() if "kind=input mode=2->3" in m]
    me_modes = [m for _, _, m in inst.messages if "kind=input mode=2->3" in m]
    assert len(cs_modes) == len(me_modes) == 1  # unloading after the jump
    assert np.abs(r["delta_c"] - dc).max() <= 1e-12
    assert np.abs(r["y"] - y).max() <= 1e-10


def test_inputs_set_after_the_last_event_pass_act_in_continuous_time(me):
    """A master sets the inputs again after the last pass of its event iteration (they follow other
    FMUs' states): from fmi2EnterContinuousTimeMode on they act as continuous-time inputs do."""
    inst, m = me()
    m.start(params=dict(contact_model=1))
    m.fmu.setTime(1e-4)
    m.fmu.completedIntegratorStep()
    m.fmu.enterEventMode()
    m.settle()
    d0 = m.real("delta")
    m.set("yC_in", 1e-7)
    m.fmu.enterContinuousTimeMode()
    assert m.real("delta") == pytest.approx(d0 + 1e-7, abs=1e-18)
    m.set("yC_in", 2e-7)  # and go on following the input in continuous time
    assert m.real("delta") == pytest.approx(d0 + 2e-7, abs=1e-18)


def test_state_from_before_initialization_gives_the_initial_states_again(me):
    """A state taken when instantiated and set while integrating: in initialization mode the states
    are those of the start the parameters give (as in a fresh instance), not the importer's last."""
    inst, m = me()
    before = m.fmu.getFMUstate()
    m.fmu.setupExperiment()
    m.fmu.enterInitializationMode()
    initial = m.states()
    m.fmu.exitInitializationMode()
    m.settle()
    m.fmu.enterContinuousTimeMode()
    m.fmu.setTime(1e-3)
    m.set_states([initial[0] / 3, 0.01])
    assert m.states()[:2] == [initial[0] / 3, 0.01]
    m.fmu.setFMUstate(before)
    m.fmu.setupExperiment()
    m.fmu.enterInitializationMode()
    assert m.states() == initial and initial[0] < 0.0 and initial[1] == 0.0  # the static start
    m.fmu.freeFMUstate(before)


def test_reset_gives_the_initial_states_again(me):
    """After a run, fmi2Reset: in the next initialization mode the states, indicators and outputs are
    those of a fresh instance (the start the parameters give), not the last run's."""
    names = ("y", "v", "F", "delta", "yC")

    def initial(m):
        m.fmu.setupExperiment()
        m.fmu.enterInitializationMode()
        return m.states(), m.indicators(), [m.real(n) for n in names]

    _, fresh = me()
    expected = initial(fresh)
    _, m = me()
    m.start()
    m.fmu.setTime(1e-3)
    m.set_states([expected[0][0] / 3, 0.01])
    m.fmu.enterEventMode()
    m.settle()
    m.fmu.reset()
    assert initial(m) == expected and expected[0][0] < 0.0  # the static start, below the platform


def test_fmu_state_gives_back_the_states_bit_for_bit_far_from_the_platform(me):
    """An FMU state taken in continuous-time mode gives back the importer's states to the bit, also
    where the platform is far from the mass (yC = -1e6 m, y = 0.1 m: delta = yC - y carries 19 fewer
    bits of y than y itself); a second state with other states set in between changes nothing."""
    inst, m = me()
    m.start(params=dict(contact_model=1, init=2, v0=0.0, a=0.0, yC_in=-1e6))
    m.fmu.setTime(1e-4)
    x = [0.1 + 2.0 ** -40, 1e-3 / 3.0, 1.0 / 3.0]  # bits below the ulp of 1e6 (1.2e-10); W_damping
    m.set_states(x)
    m.fmu.enterEventMode()
    m.settle()  # the state as it is: free flight
    m.fmu.enterContinuousTimeMode()
    assert m.integer("mode") == 0 and m.states() == x
    saved = m.fmu.getFMUstate()
    m.set_states([0.2, 0.0, 0.0])
    m.fmu.setFMUstate(saved)
    assert m.states() == x  # exactly
    m.fmu.freeFMUstate(saved)


def test_initial_state_is_logged(fmu_path, unzipdir, model_description):
    """logSolver at fmi2ExitInitializationMode in Model Exchange: the nominals the importer gets and
    the initial mode and state, here a touching start moving up at v0 (delta = 0, free flight)."""
    import re
    inst = MeInstance(fmu_path, unzipdir, model_description)
    inst.instantiate(categories=("logSolver",))
    m = Me(inst)
    m.start(params=dict(contact_model=1, init=2, v0=0.0125, a=0.0))
    msg = next(t for _, cat, t in inst.messages if cat == "logSolver" and "initial mode" in t)
    got = re.fullmatch(r"Model Exchange: the importer integrates y, v and W_damping \(nominals (\S+) m, (\S+) m/s, "
                       r"(\S+) J\); initial mode (\d+), delta = (\S+) m, v = (\S+) m/s", msg).groups()
    assert [float(x) for x in got[:3]] == pytest.approx(m.nominals(), rel=1e-5)
    assert (int(got[3]), float(got[4]), float(got[5])) == (0, 0.0, 0.0125) == (m.integer("mode"), 0.0, m.states()[1])
    inst.model.freeInstance()


@pytest.mark.parametrize("inside", [True, False])
def test_crossing_within_the_graze_band_is_put_onto_the_surface(me, inside):
    """At t = 1e5 s one ulp of time moves the platform (560 Hz, 0.1 mm) by ~2e-12 m: an importer
    cannot locate a crossing better. The band the event update takes as "on the surface" is
    VI_GRAZE_TOL (4) times the change of the guard under a state error of the tolerance plus
    VI_GRAZE_ULPS (256) times its change under one ulp of t and y (src/drivers/vi_sim.h); here the ulps
    term dominates. A penetration of a quarter of that band is snapped onto the surface (delta = 0,
    states changed); four times the band is taken as it is (elastic at that delta)."""
    inst, m = me()
    t0, a, f, rtol, v = 1e5, 1e-4, 560.0, 1e-8, 0.05
    m.start(params=dict(contact_model=1, init=2, v0=v, a=a, f=f, rtol=rtol), start_time=t0)
    t = t0 + 1e-3
    m.fmu.setTime(t)
    yC = m.real("yC")
    assert yC == pytest.approx(a * (math.cos(2 * math.pi * f * (t - t0)) - 1), rel=1e-6)
    m.set_states([yC + 1e-6, v])  # free flight, 1 um above: any band of the start is re-armed
    assert m.fmu.completedIntegratorStep()[0] is False
    speed = abs(a * 2 * math.pi * f * math.sin(2 * math.pi * f * (t - t0)))
    tol = rtol * abs(yC) + rtol * m.nominals()[0]  # rtol |y| + atol, atol = rtol * nominal
    ulps = speed * math.ulp(t) + math.ulp(yC)
    assert 256 * ulps > 4 * 4 * tol
    band = 4 * tol + 256 * ulps
    pen = band / 4 if inside else 4 * band
    m.set_states([yC - pen, -v])
    assert m.indicators()[0] < 0.0
    m.fmu.enterEventMode()
    info = m.fmu.newDiscreteStates()
    assert m.integer("mode") == 1
    if inside:
        assert (info[3], m.real("delta"), m.states()[0]) == (True, 0.0, yC)
    else:
        assert info[3] is False and m.real("delta") == pytest.approx(pen, rel=1e-6)


def test_bands_of_a_mode_left_do_not_shift_the_next_modes_indicators(me):
    """A touching start moving up: free flight with its contact guard at zero, lifted by a band (the
    indicator is positive at delta = 0). A 1 um penetration set then is an impact; in the elastic
    mode, away from both its surfaces, the indicators are its guards as they are: delta (Hertz has
    no yield surface: the second is inactive, 1; the upper contact's two, not in use, are 1)."""
    inst, m = me()
    m.start(params=dict(contact_model=1, init=2, v0=0.05, a=0.0))
    assert m.integer("mode") == 0 and m.real("delta") == 0.0
    z = m.indicators()
    assert 0.0 < z[0] < 1e-9 and z[1] == 1.0
    m.fmu.setTime(1e-6)
    m.set_states([m.states()[0] - 1e-6, -0.05])
    m.fmu.enterEventMode()
    m.settle()
    delta = m.real("delta")
    assert m.integer("mode") == 1 and delta == pytest.approx(1e-6, rel=1e-13)  # to rounding, as above
    assert m.indicators() == [delta, 1.0, 1.0, 1.0]


@pytest.mark.parametrize("law", [1, 2, 3])
def test_contact_left_under_a_falling_input_is_one_event(fmu_path, unzipdir, model_description, law):
    """The platform input yC_in drops at 1000 m/s^2 from t = 1 ms (a dipped joint), faster than the
    load can pull the mass after it (P/m + g = 108 m/s^2): the contact is left while the mass still
    moves down. With the platform's velocity passed (velocity_input, vC_in) the separation is one located
    event, mode 1 -> 0, where the platform falls faster than the mass (yC_in' < v < 0), not a same-mode
    event followed by a second one picoseconds later."""
    inputs = {"yC_in": lambda t: 0.0 if t < 1e-3 else -500.0 * (t - 1e-3) ** 2,
              "vC_in": lambda t: 0.0 if t < 1e-3 else -1000.0 * (t - 1e-3)}
    r, inst = run_me(fmu_path, dict(contact_model=law, velocity_input=True), 3e-3, rtol=1e-8, input=inputs,
                     unzipdir=unzipdir, md=model_description)
    assert not inst.errors()
    events = guard_events(inst)
    assert len(events) == 1 and "mode=1->0" in events[0], events
    fields = dict(word.split("=", 1) for word in events[0].split()[1:])
    t_sep, v_sep = float(fields["t"]), float(fields["v"])
    assert 1e-3 < t_sep < 2e-3
    assert -1000.0 * (t_sep - 1e-3) < v_sep < 0.0


def test_no_input_rate_before_the_start(me):
    """The inputs have no rate before the experiment starts: an instance started at t = 1 s with the
    platform input at -0.01 m, whose importer then puts the mass onto the platform's surface (delta =
    0, at rest) at that same instant and asks for an event, keeps the contact (the load presses the
    mass in). A rate counted from yC_in = 0 at t = 0 would have the platform falling at 0.01 m/s,
    away from the mass, and end the contact."""
    inst, m = me()
    m.start(params=dict(contact_model=1, yC_in=-0.01), start_time=1.0)
    assert m.integer("mode") == 1
    yc = -0.01 - m.real("delta")
    m.set("yC_in", yc)
    m.set_states([yc, 0.0])
    assert m.real("delta") == 0.0 and m.indicators()[0] == 0.0
    m.fmu.enterEventMode()
    m.settle()
    assert m.integer("mode") == 1
    assert not [msg for _, _, msg in inst.messages if "mode=1->0" in msg]


def test_first_step_rate_counts_from_the_inputs_at_the_start(me):
    """The mean input rate a state event chooses the mode with runs from the inputs at the start: the
    platform set 1 cm high at the start (yC_in = 0.01 m) falls 5 um in the importer's first step of
    0.1 ms, a mean rate of -0.05 m/s, while the mass moves at -0.01 m/s: it stays behind, and the
    contact found at delta = 0 ends there (one event, mode 1 -> 0). Counted from yC_in = 0 at t = 0
    instead, the platform would seem to rise at 100 m/s and keep the contact."""
    inst, m = me()
    m.start(params=dict(contact_model=1, yC_in=0.01))
    assert m.integer("mode") == 1
    t1, yc1 = 1e-4, 0.01 - 5e-6
    m.fmu.setTime(t1)
    m.set_states([yc1, -0.01])  # on the platform's new position: delta = 0
    m.set("yC_in", yc1)
    assert m.real("delta") == 0.0
    enter, terminate = m.fmu.completedIntegratorStep()
    assert not terminate
    m.fmu.enterEventMode()
    m.settle()
    events = guard_events(inst)
    assert len(events) == 1 and "mode=1->0" in events[0], events
    assert m.integer("mode") == 0


def test_an_event_without_a_change_keeps_the_step_rate(me):
    """An event iteration at the end of a step that changes nothing leaves the input rate of that step
    in place: as in the test above, the platform falls at a mean -0.05 m/s over the first step of
    0.1 ms, but the importer first completes the step with the mass 0.1 um inside the platform and
    iterates an event there (nothing fires), then sets the mass onto the surface at the same instant
    (delta = 0, moving at -0.01 m/s) and iterates again: the contact ends (one event, mode 1 -> 0).
    With the rate taken from the first iteration's instant instead, the platform would seem at rest
    and keep the mass."""
    inst, m = me()
    m.start(params=dict(contact_model=1, yC_in=0.01))
    assert m.integer("mode") == 1
    t1, yc1 = 1e-4, 0.01 - 5e-6
    m.fmu.setTime(t1)
    m.set("yC_in", yc1)
    m.set_states([yc1 - 1e-7, -0.01])  # delta = 0.1 um: no guard at zero
    enter, terminate = m.fmu.completedIntegratorStep()
    assert not terminate
    m.fmu.enterEventMode()
    m.settle()
    assert m.integer("mode") == 1 and not guard_events(inst)
    m.fmu.enterContinuousTimeMode()
    m.set_states([yc1, -0.01])  # on the surface: delta = 0
    assert m.real("delta") == 0.0
    m.fmu.enterEventMode()
    m.settle()
    events = guard_events(inst)
    assert len(events) == 1 and "mode=1->0" in events[0], events
    assert m.integer("mode") == 0
