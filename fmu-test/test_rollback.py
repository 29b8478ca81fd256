"""Exact rollback: for every solver, a run continued from a saved FMU
state is bit for bit the run that continues without the save: get state at t, run to t2 -> A; set
the state, run to t2 again -> B; A == B. The same for a serialized state restored into a fresh
instance, and for fmi2Reset followed by the same run. Fig. 4b (chaotic bouncing, Johnson) at the
default tolerance: any difference in the continuation grows to a different trajectory."""
import numpy as np
import pytest

from conftest import start
from solvers import each_solver

H = 1e-5          # communication step [s]
T_SAVE = 0.01     # s
N_AFTER = 2000    # steps after the save: 20 ms, beyond the first impacts after the save
NAMES = ("y", "v", "F", "delta", "W_plastic", "F_mean")


def fig4b(solver):
    from vibroimpact.reference.scenarios import SCENARIOS
    return {**SCENARIOS["fig4b"].full, "solver": solver}


def run(s, vr, t0, n):
    out = []
    for k in range(n):
        s.doStep(t0 + k * H, H)
        out.append(s.getReal([vr[x] for x in NAMES]) + s.getInteger([vr["n_impacts"], vr["mode"]]))
    return np.array(out)


@each_solver
def test_set_state_continues_bit_for_bit(logged, vr, solver):
    s = logged().instantiate()
    start(s, vr, fig4b(solver))
    n_save = round(T_SAVE / H)
    run(s, vr, 0.0, n_save)
    state = s.getFMUstate()
    a = run(s, vr, T_SAVE, N_AFTER)
    s.setFMUstate(state)
    b = run(s, vr, T_SAVE, N_AFTER)
    assert a[-1, -2] > a[0, -2], "no impact after the save: the test would prove little"
    np.testing.assert_array_equal(a, b)

    blob = s.serializeFMUstate(state)
    s.freeFMUstate(state)
    fresh = logged().instantiate()
    start(fresh, vr, fig4b(solver))
    fresh.setFMUstate(fresh.deSerializeFMUstate(blob))
    np.testing.assert_array_equal(run(fresh, vr, T_SAVE, N_AFTER), a)
    s.freeInstance()
    fresh.freeInstance()


@each_solver
def test_state_taken_between_every_step_changes_nothing_in_repeat(logged, vr, solver):
    """Saving the state at every step (a master ready to roll back) gives the same run every time."""
    def taking_states():
        s = logged().instantiate()
        start(s, vr, fig4b(solver))
        out = []
        for k in range(1500):
            state = s.getFMUstate()
            s.freeFMUstate(state)
            s.doStep(k * H, H)
            out.append(s.getReal([vr["y"], vr["F"]]))
        s.freeInstance()
        return np.array(out)
    np.testing.assert_array_equal(taking_states(), taking_states())


@each_solver
def test_reset_and_the_same_run_are_bit_for_bit(logged, vr, solver):
    s = logged().instantiate()
    start(s, vr, fig4b(solver))
    a = run(s, vr, 0.0, 3000)
    s.reset()
    start(s, vr, fig4b(solver))
    b = run(s, vr, 0.0, 3000)
    np.testing.assert_array_equal(a, b)
    s.freeInstance()

