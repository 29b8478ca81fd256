"""What the FMU's log says matches what it did: the solver statistics at fmi2Terminate name the
method that ran (the one-step method's were labelled "CVODE statistics") and count the restarts an
input jump causes."""
import pytest

from conftest import start
from solvers import each_solver

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
