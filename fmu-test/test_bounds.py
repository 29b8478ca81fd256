"""Valid ranges and bounded work: tolerances and max_step outside their
documented ranges are refused at initialization with a message naming them and the range."""
import re

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from conftest import start, with_solver
from solvers import SOLVERS, each_solver

ERROR = 3


def refused(logged, vr, words, params=None, tolerance=None):
    log = logged()
    s = log.instantiate()
    with pytest.raises(FMICallException):
        start(s, vr, params, tolerance=tolerance)
    text = log.text()
    assert all(w in text for w in words), text
    s.freeInstance()


def accepted(logged, vr, params=None, tolerance=None):
    s = logged().instantiate()
    start(s, vr, {"a": 1e-5, **(params or {})}, tolerance=tolerance)
    s.doStep(0.0, 1e-3)
    s.freeInstance()


@pytest.mark.parametrize("rtol", [0.5, 0.011, 1e-15, -1e-9])
def test_rtol_outside_its_range_is_refused(logged, vr, rtol):
    """rtol is 0 (the experiment's tolerance) or in [1e-14, 1e-2]."""
    refused(logged, vr, ["rtol", "1e-14" if 0 < rtol < 1e-14 else "0", "0.01"], dict(rtol=rtol))


@pytest.mark.parametrize("tol", [0.5, 1e-15])
def test_experiment_tolerance_outside_the_range_is_refused(logged, vr, tol):
    refused(logged, vr, ["fmi2SetupExperiment", "1e-14", "0.01"], tolerance=tol)


@pytest.mark.parametrize("rtol", [1e-2, 1e-14])
def test_rtol_at_the_ends_of_its_range_runs(logged, vr, rtol):
    accepted(logged, vr, dict(rtol=rtol))


@pytest.mark.parametrize("max_step", [-1e-3, 1e-13, 5e-324])
def test_max_step_outside_its_range_is_refused(logged, vr, max_step):
    refused(logged, vr, ["max_step", "1e-12"], dict(max_step=max_step))


@pytest.mark.parametrize("max_step", [0.0, 1e-12, 1e300])
def test_max_step_in_its_range_runs(logged, vr, max_step):
    s = logged().instantiate()
    start(s, vr, dict(a=1e-5, max_step=max_step))
    s.doStep(0.0, 1e-9 if max_step == 1e-12 else 1e-3)
    s.freeInstance()


# ---- bounded work per step, no false chattering --------------------------------------------------
# Each case runs in a subprocess with a time limit: a hang fails fast instead of stalling the suite.

RUNNER = r'''
import json
from ctypes import byref, c_double
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from vibroimpact.fmu import Logged, fmu_path, initialize
from vibroimpact.reference.scenarios import SCENARIOS
FMU = fmu_path()
md = read_model_description(str(FMU))
vr = {{v.name: v.valueReference for v in md.modelVariables}}
log = Logged(md, extract(str(FMU)))
s = log.instantiate()
params = {params!r}
if "scenario" in params:
    params = {{**SCENARIOS[params.pop("scenario")].full, **params}}
initialize(s, vr, params, tolerance={tolerance!r})
t, status = 0.0, "ok"
try:
    for h in {steps!r}:
        s.doStep(t, h)
        t += h
except FMICallException as e:
    status = "discard" if e.status == 2 else "error"
last = c_double()
s.fmi2GetRealStatus(s.component, 2, byref(last))  # fmi2LastSuccessfulTime
names = ["y", "v", "F", "delta", "delta_f"]
out = dict(zip(names, s.getReal([vr[n] for n in names])))
messages = [m for st, _, m in log.messages if st != 1]  # warnings (fmi2Warning, validity) apart
warnings = [m for st, _, m in log.messages if st == 1]
events = None
if status != "error":  # the statistics of fmi2Terminate: the events of the whole run
    s.setDebugLogging(True, ["logSolver"])
    s.terminate()
    stats = [m for _, _, m in log.messages[len(messages):] if "statistics" in m]
    events = int(stats[0].split(" events")[0].rsplit(" ", 1)[-1]) if stats else None
print(json.dumps(dict(status=status, last=last.value, t=t, messages=messages, warnings=warnings, events=events,
                      n_impacts=s.getInteger([vr["n_impacts"]])[0], mode=s.getInteger([vr["mode"]])[0], **out)))
'''


def in_subprocess(params, steps, tolerance=None, timeout=60):
    import json
    import subprocess
    import sys
    code = RUNNER.format(params=with_solver(params), steps=list(steps), tolerance=tolerance)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


WORK_BOUND = re.compile(r"fmi2DoStep: work bound: (\d+) (internal steps|events) in one step, stopped at "
                        r"t = (\S+) s \(mode \d\); continue from there or use smaller communication steps"
                        r"(?:; its internal steps averaged \S+ s)?; the contact's time scale sqrt\(m/k\) = .*")


def assert_work_bound(r, kind=None):
    """The step's only message is the work bound's, at the time the FMU got to (fmi2LastSuccessfulTime);
    not the Zeno rule's ('events accumulate ...'). A bound on events stops at the event it names: the
    run (that one step) counts exactly that many (the solver statistics)."""
    assert len(r["messages"]) == 1, r["messages"]
    m = WORK_BOUND.fullmatch(r["messages"][0])
    assert m and float(m.group(3)) == r["last"], (r["last"], r["messages"])
    assert kind is None or m.group(2) == kind, r["messages"]
    if m.group(2) == "events":
        assert r["events"] == int(m.group(1)), (r["events"], r["messages"])


@each_solver
def test_huge_step_is_bounded_and_discarded_where_it_got(solver):
    """Fig. 4b with one step of 1e6 s (ran 92 s before failing): fmi2Discard after the documented work
    bound, fmi2LastSuccessfulTime is where the FMU got, the message names that time, and the state
    there is consistent (a free mass is not inside the platform: no contact was missed on the way)."""
    r = in_subprocess(dict(scenario="fig4b", solver=solver), [1e6])
    assert r["status"] == "discard"
    assert 0.0 < r["last"] < 1e6
    assert_work_bound(r)
    assert all(np.isfinite([r["y"], r["F"], r["delta"]]))
    assert r["mode"] != 0 or r["delta"] <= r["delta_f"] + 1e-9, r


def test_thousands_of_regular_impacts_in_one_step():
    """Hertz under a = 0.1 mm at 2 kHz (one impact per excitation period) over 2 s in one step: 4000
    impacts, 8000 events, no error."""
    r = in_subprocess(dict(contact_model=1, a=1e-4, f=2000.0), [2.0])
    assert r["status"] == "ok", r["messages"]
    assert abs(r["n_impacts"] - 4000) <= 1


def test_contact_at_tens_of_megahertz_is_not_chattering():
    """m = 1e-7 kg without load on a platform vibrating at 30 MHz: the platform's acceleration a (2 pi
    f)^2 = 3.6e5 m/s^2 throws the mass off, and it hits the platform again, every period: 600 impacts
    in 20 us, each with its onset and its separation only (Hertz), 2 events per impact. Small steps
    run; a long step ends at the work bound, not at the Zeno rule."""
    p = dict(contact_model=1, m=1e-7, P=0.0, a=1e-11, f=3e7)
    small = in_subprocess(p, [1e-6] * 20)
    assert small["status"] == "ok" and abs(small["n_impacts"] - 600) <= 1, small
    assert small["events"] <= 2 * (small["n_impacts"] + 1), small
    long = in_subprocess(p, [1e-2])
    assert long["status"] == "discard"
    assert_work_bound(long)
    assert 0.0 < long["last"] < 1e-2


@each_solver
def test_work_bound_on_internal_steps_stops_on_the_trajectory(solver):
    """A mass thrown up at 100 m/s, no load but gravity, max_step = 1 us: one step of 2 s meets the
    bound of 1e6 internal steps near 1 s; the state there is the closed form of the throw,
    y = v0 t - g t^2/2, v = v0 - g t (relative 1e-9)."""
    v0, g = 100.0, 9.81
    r = in_subprocess(dict(contact_model=1, P=0.0, g=g, init=2, v0=v0, max_step=1e-6, solver=solver), [2.0])
    assert r["status"] == "discard"
    assert_work_bound(r, "internal steps")
    t = r["last"]
    assert 0.5 < t < 2.0
    assert r["y"] == pytest.approx(v0 * t - 0.5 * g * t * t, rel=1e-9)
    assert r["v"] == pytest.approx(v0 - g * t, rel=1e-9)


def test_work_bound_on_events_stops_at_the_event_it_names():
    """The 30 MHz contact with the one-step method (long steps between events): a step of 10 ms meets
    the bound on events before that on internal steps, after exactly the number of events it names."""
    r = in_subprocess(dict(contact_model=1, m=1e-7, P=0.0, a=1e-11, f=3e7, solver=3), [1e-2])
    assert r["status"] == "discard"
    assert_work_bound(r, "events")
    assert 0.0 < r["last"] < 1e-2


# The runs below last 0.1 s in steps of 0.1 ms. Chattering is a pair of guards firing one after the other
# again and again, microseconds or less apart, thousands of times; an impact's own events are few:
# its onset, the changes of mode while in contact, its separation.
RUN_S, RUN_STEPS = 0.1, [1e-4] * 1000


def assert_events_per_contact(r, at_most):
    """The run ended OK and its events (fmi2Terminate's count) number at most `at_most` per contact:
    per impact (n_impacts) and for the contact the run may start in."""
    assert r["status"] == "ok", r["messages"][-3:]
    assert r["events"] is not None and r["events"] <= at_most * (r["n_impacts"] + 1), (r["events"], r["n_impacts"])


@each_solver
@pytest.mark.parametrize("tolerance", [None, 1e-3, 1e-8])
def test_grazing_with_poissons_ratio_near_minus_one(tolerance, solver):
    """Fig. 4b with nu1 = nu2 = -0.999999: the mass grazes the permanent set (reaches it with a rate of
    1e-5 of its speed); no event may fire again and again ('chattering'). Johnson with a fixed
    contact point: a contact has its onset, yield, the turning point (unloading or stick), the end of
    stick, a reload past delta_c with its turning point, and the separation: at most 8 events per
    contact (4.4 measured at most, dop853 at rtol 1e-3). After the end of stick the unloading mode's reload guard starts
    at zero; its band (vi_hybrid.h: VI_GRAZE_TOL times its change under a state error of the
    tolerance) keeps the state error of dop853 at rtol 1e-3 from firing it again and again."""
    r = in_subprocess(dict(scenario="fig4b", nu1=-0.999999, nu2=-0.999999, solver=solver), RUN_STEPS, tolerance)
    assert_events_per_contact(r, 8)


@pytest.mark.parametrize("law", [1, 2, 3])
@pytest.mark.parametrize("tolerance", [1e-2, 1e-6, 1e-10])
def test_tangential_touch_of_a_floating_mass(law, tolerance):
    """No load, the mass at rest touching the platform, which swings down and comes back to touch it
    tangentially (zero relative speed) once per period: at most one contact per period of the
    excitation (f = 560 Hz: 56 in the run), and with no speed to yield, each contact has only its
    onset and its separation: at most 2 events per contact (1.9 measured at most, and 29 contacts)."""
    f = 560.0
    p = dict(contact_model=law, init=2, v0=0.0, P=0.0, g=0.0, a=1e-4, f=f)
    r = in_subprocess(p, RUN_STEPS, tolerance)
    assert r["n_impacts"] <= f * RUN_S + 1, r["n_impacts"]
    assert_events_per_contact(r, 2)


@pytest.mark.parametrize("tolerance", [1e-2, 1e-3])
def test_moving_contact_at_loose_tolerance(tolerance):
    """Fig. 4c (Johnson, moving contact point: no memory) at loose tolerances: a contact has its onset,
    yield, the return below yield and the separation, twice yield and return when the excitation
    pushes again within one contact: at most 6 events per contact (3.75 measured at most)."""
    r = in_subprocess(dict(scenario="fig4c"), RUN_STEPS, tolerance)
    assert_events_per_contact(r, 6)
