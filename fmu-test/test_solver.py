"""The solver layer seen from outside: every `solver` value selects its method and says
so, runs the same motion within its tolerance, honours max_step, and integrates past communication
points (small communication steps cost no extra internal steps)."""
import re

import numpy as np
import pytest

from conftest import start
from solvers import SOLVERS, each_solver

NAMES = {1: "CVODE BDF", 2: "CVODE Adams", 3: "Dormand-Prince 8(5,3)", 4: "auto"}


def statistics(log):
    """(steps, rhs evaluations) from the logSolver message at fmi2Terminate."""
    for _, _, m in log.messages:
        hit = re.search(r"statistics: (\d+) steps, (\d+) rhs evaluations", m)
        if hit:
            return int(hit.group(1)), int(hit.group(2))
    raise AssertionError("no statistics logged")


def run(logged, vr, params, h, n, tolerance=None):
    log = logged()
    s = log.instantiate(logging=True)
    s.setDebugLogging(True, ["logSolver"])
    start(s, vr, params, tolerance=tolerance)
    y = []
    for k in range(n):
        s.doStep(k * h, h)
        y.append(s.getReal([vr["y"]])[0])
    s.terminate()
    s.freeInstance()
    return log, np.array(y)


def test_default_is_auto(model_description):
    """The measurements of doc/speed.md favour auto across scenes (within 1.25 times the fastest)."""
    v = next(v for v in model_description.modelVariables if v.name == "solver")
    assert int(v.start) == SOLVERS["auto"]


@each_solver
def test_the_solver_is_the_one_selected_and_says_so(logged, vr, solver):
    log, _ = run(logged, vr, dict(contact_model=1, a=1e-4, solver=solver), 1e-4, 10)
    assert any(NAMES[solver] in m for _, _, m in log.messages), log.text()
    for other, name in NAMES.items():
        if other != solver:
            assert not any(name in m for _, _, m in log.messages)


def test_solvers_agree_within_tolerance(logged, vr):
    """Fig. 5c-like Hertz bouncing over 10 ms at rtol 1e-9: the three methods differ (they are
    different methods) but agree to well within 1e-6 of the motion, and so does auto."""
    ys = {sv: run(logged, vr, dict(contact_model=1, a=1e-4, solver=sv), 1e-5, 1000, 1e-9)[1] for sv in NAMES}
    swing = np.ptp(ys[1])
    assert not np.array_equal(ys[1], ys[2]) and not np.array_equal(ys[2], ys[3])
    for sv in (2, 3, 4):
        assert np.abs(ys[sv] - ys[1]).max() < 1e-6 * swing


@each_solver
def test_max_step_is_honoured(logged, vr, solver):
    """A static contact needs almost no steps; max_step = 1e-5 s forces at least 100 over 1 ms."""
    free, _ = run(logged, vr, dict(contact_model=1, solver=solver), 1e-3, 1)
    held, _ = run(logged, vr, dict(contact_model=1, solver=solver, max_step=1e-5), 1e-3, 1)
    assert statistics(free)[0] < 50
    assert statistics(held)[0] >= 100


@each_solver
def test_small_communication_steps_take_no_extra_internal_steps(logged, vr, solver):
    """Integration past communication points: the internal steps do not depend on how often the
    master samples (Hertz bouncing, 5 ms, one step of 5 ms against 5000 steps of 1 us)."""
    p = dict(contact_model=1, a=1e-4, solver=solver)
    coarse, yc = run(logged, vr, p, 5e-3, 1, 1e-8)
    fine, yf = run(logged, vr, p, 1e-6, 5000, 1e-8)
    steps_coarse, steps_fine = statistics(coarse)[0], statistics(fine)[0]
    assert steps_fine <= 1.05 * steps_coarse + 5, (steps_coarse, steps_fine)
    assert abs(yf[-1] - yc[-1]) < 1e-6 * 1e-4
