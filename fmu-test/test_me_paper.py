"""Model Exchange against the independent reference on every scenario of the paper.

fmpy integrates the FMU's states (y, v) itself (simulate_fmu with fmi_type='ModelExchange',
solver='CVode', at relative tolerance RTOL_ME; its absolute tolerances are RTOL_ME times the FMU's
nominals, the problem's length and velocity scales), and locates the events on the FMU's event
indicators. The criteria are those of test_paper.py for co-simulation, within each scenario's
predictable horizon: |y - y_ref| <= EPS_Y = 0.1 um, the force to 1e-3 and the plastic work to 1e-4 of
their maxima (3e-4 for `continuous`, test_paper.py says why), and the same sequence of mode changes, each within EVENT_DT = 1 us of the reference's.
"""
import numpy as np
import pytest

from vibroimpact.compare import EVENT_DT, compare
from vibroimpact.reference.generate import EPS_Y
from vibroimpact.reference.scenarios import SCENARIOS, STOP_TIME
from vibroimpact.me import MeRunner
from test_paper import F_REL, W_REL, W_REL_OF

RTOL_ME = 1e-11  # the tolerance of the reference trace, as test_paper.py runs co-simulation


@pytest.fixture(scope="module")
def compared_me(fmu_path, unzipdir):
    runner, cache = MeRunner(fmu_path, unzipdir), {}

    def get(name):
        if name not in cache:
            cache[name] = compare(name, runner, rtol=RTOL_ME)
        return cache[name]

    return get


@pytest.mark.parametrize("name", SCENARIOS)
def test_me_trajectory_within_horizon(name, compared_me):
    c = compared_me(name)
    assert (c["ref"]["time"] <= c["horizon"]).sum() > 100, "a horizon too short to compare"
    assert c["dy"] <= EPS_Y
    assert c["dF_rel"] <= F_REL
    assert c["dW_rel"] <= W_REL_OF.get(name, W_REL)


@pytest.mark.parametrize("name", SCENARIOS)
def test_me_event_sequence_within_horizon(name, compared_me):
    c = compared_me(name)
    assert c["events_fmu"] == c["events_ref"]
    assert c["event_dt"] <= EVENT_DT


@pytest.mark.parametrize("name", SCENARIOS)
def test_me_counts(name, compared_me):
    """To the end of the run: the counts of every kind of mode change where the reference is predictable
    to the end, else the impacts within 20 %."""
    c = compared_me(name)
    if c["horizon"] >= STOP_TIME:
        assert c["transitions"] == c["transitions_ref"]
        assert c["n_impacts"] == c["n_impacts_ref"]
    else:
        assert abs(c["n_impacts"] - c["n_impacts_ref"]) <= 0.2 * c["n_impacts_ref"]
    assert np.all(np.isfinite(c["fmu"]["y"]))
