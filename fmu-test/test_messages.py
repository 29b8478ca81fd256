"""What the FMU's log says matches what it did: the solver statistics at fmi2Terminate name the
method that ran (the one-step method's were labelled "CVODE statistics")."""
import pytest

from conftest import start

NAMES = {1: "CVODE BDF", 2: "CVODE Adams", 3: "Dormand-Prince 8(5,3)"}


@pytest.mark.parametrize("solver", [1, 2, 3])
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
