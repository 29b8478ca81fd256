"""Shared helpers for the FMU-level tests: the FMU of this checkout, the solver to run every test with,
and the closed forms and FMU helpers of the vibroimpact package under the names the tests use."""
import os
import pathlib

import fmpy
import pytest
from fmpy import extract, read_model_description

from vibroimpact import fmu as _fmu
from vibroimpact.fmu import Logged  # noqa: F401  (used by the tests)
from vibroimpact.reference.closed_forms import DEFAULTS, effective  # noqa: F401  (used by the tests)

ROOT = pathlib.Path(__file__).resolve().parent.parent
# The FMU under test is this checkout's build/VibroImpact.fmu unless VI_FMU names another one; set here,
# so that the package's code and the commands the tests start (vibroimpact sweep) use the same.
os.environ.setdefault(_fmu.ENV, str(ROOT / "build" / _fmu.NAME))
FMU = _fmu.fmu_path(required=False)
BUILD = _fmu.build_dir()

# VI_SOLVER=<value of the `solver` enumeration> runs the whole suite with that solver: start() and
# fmpy.simulate_fmu (wrapped here, before the test modules import it) set it unless a test sets its own.
SOLVER = int(os.environ["VI_SOLVER"]) if os.environ.get("VI_SOLVER") else None


def _default_solver():
    """The `solver` an FMU run gets when nothing sets it: the model description's start value."""
    if not FMU.exists():
        return None
    return int(next(v.start for v in read_model_description(str(FMU)).modelVariables if v.name == "solver"))


DEFAULT_SOLVER = _default_solver()
# the solver of a run that sets none: VI_SOLVER's, else the FMU's default
RUN_SOLVER = SOLVER if SOLVER is not None else DEFAULT_SOLVER


def with_solver(params):
    return params if SOLVER is None or "solver" in (params or {}) else {**(params or {}), "solver": SOLVER}


_simulate_fmu = fmpy.simulate_fmu


def _simulate_with_solver(filename, *args, start_values=None, **kw):
    if pathlib.Path(str(filename)).name != FMU.name:  # the companion FMUs have their own solvers
        return _simulate_fmu(filename, *args, start_values=start_values, **kw)
    return _simulate_fmu(filename, *args, start_values=with_solver(start_values or {}), **kw)


fmpy.simulate_fmu = _simulate_with_solver


@pytest.fixture(scope="session")
def fmu_path():
    if not FMU.exists():
        pytest.fail(f"{FMU} is missing: build it with cmake -S . -B build && cmake --build build")
    return str(FMU)


@pytest.fixture(scope="session")
def model_description(fmu_path):
    return read_model_description(fmu_path)


@pytest.fixture(scope="session")
def unzipdir(fmu_path, tmp_path_factory):
    return extract(fmu_path, unzipdir=str(tmp_path_factory.mktemp("fmu")))


@pytest.fixture(scope="session")
def vr(model_description):
    """Value reference by variable name."""
    return {v.name: v.valueReference for v in model_description.modelVariables}


@pytest.fixture
def logged(model_description, unzipdir):
    made = []

    def make(**kw):
        made.append(Logged(model_description, unzipdir, **kw))
        return made[-1]

    yield make


def start(slave, vr, params=None, tolerance=None, start_time=0.0, stop_time=None):
    """Instantiated slave -> step-complete state with the given parameters (and VI_SOLVER's solver)."""
    _fmu.initialize(slave, vr, with_solver(params or {}), tolerance=tolerance, start_time=start_time,
                    stop_time=stop_time)
