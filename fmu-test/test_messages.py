"""What the FMU's log says matches what it did: the solver statistics at fmi2Terminate name the
method that ran (the one-step method's were labelled "CVODE statistics") and count the restarts an
input jump causes. Messages name their cause: a flood of solver warnings is relayed once a kind and
counted; a failure names the contact's time scale sqrt(m/k) with m and the stiffness, and what to
change; a mass too small for double precision is refused at initialization with the smallest mass,
the same in FMI 2.0 and 3.0, Co-Simulation and Model Exchange."""
import math
import re
import sys

import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2LastSuccessfulTime

from conftest import BUILD, start
from solvers import each_solver
from vibroimpact import fmi3

NAMES = {1: "CVODE BDF", 2: "CVODE Adams", 3: "Dormand-Prince 8(5,3)", 4: "auto"}


@pytest.mark.parametrize("solver", [1, 2, 3, 4])
def test_solver_statistics_name_the_method_that_ran(logged, vr, solver):
    inst = logged()
    s = inst.instantiate()
    s.setDebugLogging(True, ["logSolver"])
    start(s, vr, dict(a=1e-4, solver=solver))
    for k in range(5):
        s.doStep(k * 1e-4, 1e-4)
    s.terminate()
    stats = [m for _, cat, m in inst.messages if cat == "logSolver" and "statistics" in m]
    assert len(stats) == 1, inst.messages
    assert stats[0].startswith(f"{NAMES[solver]} statistics: "), stats[0]
    steps = int(stats[0].split(": ")[1].split(" steps")[0])
    assert steps > 0, stats[0]


def statistic(text, name):
    """The count before `name` in the statistics message ("..., 3 restarts, ...")."""
    return int(text.split(f" {name}")[0].rsplit(" ", 1)[-1])


@each_solver
@pytest.mark.parametrize("jumps", [0, 1, 3])
def test_each_input_jump_restarts_the_solver_once(logged, vr, solver, jumps):
    """A mass thrown clear of the platform (no load, v0 = 1 m/s: no event in 3 ms), yC_in moved
    between steps `jumps` times: the statistics count that many restarts and no event."""
    inst = logged()
    s = inst.instantiate()
    s.setDebugLogging(True, ["logSolver"])
    start(s, vr, dict(contact_model=1, P=0.0, g=0.0, init=2, v0=1.0, solver=solver))
    t = 0.0
    for k in range(30):
        if k in (10, 20, 25)[:jumps]:
            s.setReal([vr["yC_in"]], [1e-6 * (k + 1)])
        s.doStep(t, 1e-4)
        t += 1e-4
    s.terminate()
    stats = [m for _, cat, m in inst.messages if cat == "logSolver" and "statistics" in m]
    assert len(stats) == 1 and statistic(stats[0], "events") == 0, inst.messages
    assert statistic(stats[0], "restarts") == jumps, stats[0]


@pytest.mark.parametrize("solver", [1, 2, 3, 4])
def test_model_exchange_logs_nothing_of_a_solver_it_does_not_use(solver):
    """In Model Exchange the importer integrates: with logSolver on, neither the set-up nor the statistics
    name one of the FMU's own methods; the statistics count the events handled (a shaken Hertz contact,
    stepped to its first event and through it: one)."""
    from vibroimpact.me import Me, MeInstance
    inst = MeInstance()
    inst.instantiate(categories=("logSolver",))
    m = Me(inst)
    m.start(dict(contact_model=1, a=1e-4, solver=solver))
    t, event = m.euler_to(5e-3, 1e-6)  # until the contact is left: an event is due
    assert event, t
    m.fmu.enterEventMode()
    m.settle()
    inst.model.terminate()
    texts = [t for _, cat, t in inst.messages if cat == "logSolver"]
    inst.model.freeInstance()
    assert not [t for t in texts if any(name in t for name in NAMES.values())], texts
    stats = [t for t in texts if "statistics" in t]
    assert len(stats) == 1 and stats[0].startswith("Model Exchange statistics: "), texts
    assert statistic(stats[0], "events") == 1


# ---- messages that name the cause ---------------------------------------------------------------------

EPS = sys.float_info.epsilon
WARNING = 1
# a linear spring of 1e30 N/m under the paper's mass: a contact time scale sqrt(m/k) of 2e-14 s, 91 units of
# the time resolution at t = 1 s; shaken, the mass bounces and the solver's steps cannot resolve its impacts
STIFF = dict(contact_model=5, k_spring=1e30, a=1e-4, solver=4)
T_STIFF = math.sqrt(407.747 / 1e30)


@pytest.fixture(scope="module")
def fmi3_parts(tmp_path_factory):
    path = BUILD / "fmi3" / "VibroImpact.fmu"
    md = read_model_description(str(path))
    return md, extract(str(path), unzipdir=str(tmp_path_factory.mktemp("fmi3"))), \
        {v.name: v.valueReference for v in md.modelVariables}, {v.name: v.type for v in md.modelVariables}


def stiff_step(version, logged, vr, fmi3_parts):
    """STIFF started at t = 1 s, one communication step of 0.1 ms: (status, the warnings, the other messages)."""
    if version == 2:
        inst = logged()
        s = inst.instantiate()
        start(s, vr, STIFF, start_time=1.0)
        status = s._functions["fmi2DoStep"](s.component, 1.0, 1e-4, 1)
    else:
        md, unzipdir, vr3, kinds = fmi3_parts
        inst = fmi3.Logged(md, unzipdir)
        s = inst.instantiate()
        fmi3.initialize(s, vr3, STIFF, kinds=kinds, start_time=1.0)
        status = fmi3.do_step(s, 1.0, 1e-4)[0]
    warnings = [m for st, _, m in inst.messages if st == WARNING]
    return status, warnings, [m for st, _, m in inst.messages if st != WARNING]


@pytest.mark.timeout(600)  # two steps of 1e6 internal steps each (30 s on a loaded machine, more when sanitized)
def test_a_flood_of_solver_warnings_is_counted_not_repeated(logged, vr, fmi3_parts):
    """The stiff spring relayed 733,335 solver warnings in one step (99,803 in the issue's run): now the
    first of each kind, with the time scale that causes them (closed form), and one count per kind at the
    end of the step; the work bound ends the step naming k_spring and the time scale. FMI 2.0 and 3.0
    log the same warnings, and the same step message after their function names."""
    runs = [stiff_step(version, logged, vr, fmi3_parts) for version in (2, 3)]
    status, warnings, others = runs[0]
    assert status == 2 and len(others) == 1 and others[0].startswith("fmi2DoStep: work bound: "), others  # Discard
    first = [w for w in warnings if "(counted, not relayed)" not in w]
    counts = [int(w.split(" ")[0]) for w in warnings if w.endswith("(counted, not relayed)")]
    assert 1 <= len(first) <= 4 and len(counts) <= len(first) + 1, warnings
    assert len(first) + sum(counts) > 1000, warnings  # the flood is there, counted
    units = T_STIFF / EPS
    for w in first:
        assert f"sqrt(m/k) = {T_STIFF:.3g} s (m = 407.747 kg, k = k_spring = 1e+30 N/m) is {units:.3g} units of the " \
               "time resolution at t = 1 s, too few for the solver's steps: the likely cause" in w, w
    assert f"sqrt(m/k) = {T_STIFF:.3g} s (m = 407.747 kg, k = k_spring = 1e+30 N/m) is only {units:.3g} units of the " \
           "time resolution" in others[0] and "raise m or lower k_spring" in others[0], others[0]
    assert runs[1][0] == 2 and runs[1][1] == warnings, runs[1][1]
    assert runs[1][2] == ["fmi3DoStep" + others[0][len("fmi2DoStep"):]], runs[1][2]


def test_an_explicit_method_at_its_work_bound_names_the_mass(logged, vr):
    """m = 1e-100 kg shaken under dop853: the work bound's message names m, the stiffness and the time
    scale (sqrt(m/k) with the k it names), the mean internal step (the time reached over the 1e6 steps)
    and says to raise m."""
    inst = logged()
    s = inst.instantiate()
    start(s, vr, dict(m=1e-100, a=1e-4, solver=3))
    assert s._functions["fmi2DoStep"](s.component, 0.0, 1e-4, 1) == 2
    message = inst.messages[-1][2]
    m = re.search(r"sqrt\(m/k\) = (\S+) s \(m = 1e-100 kg, k = (\S+) N/m, the law's stiffness at the indentation", message)
    assert m and float(m.group(1)) == pytest.approx(math.sqrt(1e-100 / float(m.group(2))), rel=2e-3), message
    assert "times shorter than the communication step 0.0001 s" in message and ": raise m or soften the contact" \
        in message, message
    mean = float(re.search(r"its internal steps averaged (\S+) s", message).group(1))
    last = s.getRealStatus(fmi2LastSuccessfulTime)
    assert mean == pytest.approx(last / 1e6, rel=2e-3), (message, last)


def smallest_mass(message):
    return float(re.search(r"use m >= (\S+) kg", message).group(1))


@pytest.mark.parametrize("fmu", ["VibroImpact.fmu", "fmi3/VibroImpact.fmu"])
@pytest.mark.parametrize("kind", ["CoSimulation", "ModelExchange"])
def test_a_mass_too_small_for_double_is_refused_naming_m(capfd, fmu, kind):
    """m = 1e-300 kg (the contact's rate k/m beyond the doubles) is refused at initialization naming m and
    the smallest mass; that mass is accepted, a quarter of it refused: the range the message states is
    the one enforced. The same message in FMI 2.0 and 3.0, Co-Simulation and Model Exchange."""
    def init(m):
        try:
            simulate_fmu(str(BUILD / fmu), fmi_type=kind, start_values={"m": m}, stop_time=1e-6)
        except (FMICallException, Exception) as e:  # fmpy raises on the refusal
            return str(e), capfd.readouterr().out
        return None, capfd.readouterr().out
    _, out = init(1e-300)
    refusal = [line for line in out.splitlines() if "is too small for the contact" in line]
    assert len(refusal) == 1 and "m = 1e-300 kg is too small for the contact: its time scale sqrt(m/k) = " in refusal[0]
    assert "makes the rate k/m = 1/T^2 overflow double; use m >= " in refusal[0], refusal
    m_min = smallest_mass(refusal[0])
    assert "too small for the contact" not in init(m_min)[1]
    assert "too small for the contact" in init(m_min / 4)[1]
