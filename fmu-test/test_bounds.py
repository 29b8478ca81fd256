"""Valid ranges and bounded work (issue 9 items 3 and 8): tolerances and max_step outside their
documented ranges are refused at initialization with a message naming them and the range."""
import pytest
from fmpy.fmi1 import FMICallException

from conftest import start

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


@pytest.mark.parametrize("rtol", [0.5, 0.011, 1e-15, 0.0])
def test_rtol_outside_its_range_is_refused(logged, vr, rtol):
    refused(logged, vr, ["rtol", "1e-14", "0.01"], dict(rtol=rtol))


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
