"""Shared helpers for the FMU-level tests: the FMU of this checkout, the solver to run every test with,
and the closed forms and FMU helpers of the vibroimpact package under the names the tests use."""
import importlib
import json
import locale
import os
import pathlib

import fmpy
import fmpy.fmi2
import fmpy.simulation
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


# The tests VI_SOLVER reaches: those that start a run without a solver of their own (with_solver below, also
# through fmpy.simulate_fmu) and those of modules that read SOLVER or RUN_SOLVER themselves. The default pass
# writes their node ids with --solver-tests-out FILE; tools/test.sh's VI_SOLVER loop runs only those
# (--solver-tests-from FILE): in every other test the solver is the test's own or the FMU's default, and the
# default pass ran it already.
_SOLVER_TESTS, _RUNNING = set(), [None]


def with_solver(params):
    if "solver" not in (params or {}) and _RUNNING[0]:
        _SOLVER_TESTS.add(_RUNNING[0])
    return params if SOLVER is None or "solver" in (params or {}) else {**(params or {}), "solver": SOLVER}


_simulate_fmu = fmpy.simulate_fmu


def _simulate_with_solver(filename, *args, start_values=None, **kw):
    if pathlib.Path(str(filename)).name != FMU.name:  # the companion FMUs have their own solvers
        return _simulate_fmu(filename, *args, start_values=start_values, **kw)
    return _simulate_fmu(filename, *args, start_values=with_solver(start_values or {}), **kw)


fmpy.simulate_fmu = _simulate_with_solver

# fmpy.simulate_fmu and an instance made without callbacks allocate through fmpy's calloc and free,
# the C library's own: here the process's, so that a preloaded AddressSanitizer checks those blocks too
# (tools/test.sh's sanitized run; the same functions otherwise).
fmpy.simulation.calloc, fmpy.simulation.free = _fmu.process_allocator()
fmpy.fmi2.defaultCallbacks.allocateMemory = fmpy.fmi2.fmi2CallbackAllocateMemoryTYPE(fmpy.simulation.calloc)
fmpy.fmi2.defaultCallbacks.freeMemory = fmpy.fmi2.fmi2CallbackFreeMemoryTYPE(fmpy.simulation.free)


# --locale NAME runs the tests in that locale: set for the whole process (LC_ALL) before any FMU is loaded,
# as an importer in a German modelling tool would (tools/test.sh runs its sanitized part in de_DE.UTF-8).
def pytest_addoption(parser):
    parser.addoption("--locale", default=None, metavar="NAME",
                     help="set LC_ALL to NAME before any FMU is loaded (e.g. de_DE.UTF-8: decimal point ',')")
    parser.addoption("--solver-tests-out", default=None, metavar="FILE",
                     help="write the node ids of the tests VI_SOLVER reaches (JSON) to FILE")
    parser.addoption("--solver-tests-from", default=None, metavar="FILE",
                     help="run only the tests FILE names (written by --solver-tests-out)")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    _RUNNING[0] = item.nodeid
    module = getattr(item, "module", None)
    if module is not None and ("SOLVER" in vars(module) or "RUN_SOLVER" in vars(module)):
        _SOLVER_TESTS.add(item.nodeid)  # the module reads the solver under test itself
    yield
    _RUNNING[0] = None


def pytest_collection_modifyitems(config, items):
    path = config.getoption("--solver-tests-from", default=None)
    if not path:
        return
    try:
        wanted = set(json.loads(pathlib.Path(path).read_text()))
    except (OSError, ValueError) as e:
        raise pytest.UsageError(f"--solver-tests-from {path}: {e} (write it with a run given --solver-tests-out)")
    keep = [i for i in items if i.nodeid in wanted]
    config.hook.pytest_deselected(items=[i for i in items if i.nodeid not in wanted])
    items[:] = keep


def pytest_sessionfinish(session):
    path = session.config.getoption("--solver-tests-out", default=None)
    if path:
        pathlib.Path(path).write_text(json.dumps(sorted(_SOLVER_TESTS), indent=0))


def pytest_configure(config):
    name = config.getoption("--locale", default=None)
    if name:
        try:
            locale.setlocale(locale.LC_ALL, name)
        except locale.Error:
            raise pytest.UsageError(f"--locale {name}: the locale is missing (Debian: the package locales, then "
                                    f"localedef -i {name.split('.')[0]} -f UTF-8 {name}; tools/setup.sh --test does both)")


def pytest_report_header(config):
    if config.getoption("--locale", default=None):
        return f"locale: {locale.setlocale(locale.LC_NUMERIC)} (decimal point '{locale.localeconv()['decimal_point']}')"


@pytest.fixture(scope="session")
def fmu_path():
    if not FMU.exists():
        pytest.fail(f"{FMU} is missing: build it with cmake -S . -B build && cmake --build build")
    return str(FMU)


def require_module(name):
    """The Python module `name` of pyproject.toml's test extra; a missing one fails the test with how to
    install it (never a skip)."""
    try:
        return importlib.import_module(name)
    except ImportError as e:
        pytest.fail(f"{name} is not installed ({e}): tools/setup.sh installs it (pyproject.toml's test extra)")


@pytest.fixture(scope="session")
def companion_fmus():
    """The vehicle-track example's Track.fmu and Vehicle.fmu, which every build of the tests makes next
    to the FMU under test (CMakeLists.txt); missing ones fail the test."""
    paths = [BUILD / "Track.fmu", BUILD / "Vehicle.fmu"]
    missing = [str(p) for p in paths if not p.exists()]
    if missing:
        pytest.fail(f"{', '.join(missing)} missing: build with cmake -S . -B build && cmake --build build")
    return paths


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
