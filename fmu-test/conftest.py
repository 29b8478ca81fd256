"""Shared helpers for the FMU-level tests: where the FMU is, closed-form physics, and an FMU2Slave
with a logger that records what the FMU says."""
import os
import pathlib

import fmpy
import numpy as np
import pytest
from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)

ROOT = pathlib.Path(__file__).resolve().parent.parent
BUILD = pathlib.Path(os.environ.get("VI_BUILD_DIR", ROOT / "build"))
FMU = BUILD / "VibroImpact.fmu"

# VI_SOLVER=<value of the `solver` enumeration> runs the whole suite with that solver: start() and
# fmpy.simulate_fmu (wrapped here, before the test modules import it) set it unless a test sets its own.
SOLVER = int(os.environ["VI_SOLVER"]) if os.environ.get("VI_SOLVER") else None


def with_solver(params):
    return params if SOLVER is None or "solver" in (params or {}) else {**(params or {}), "solver": SOLVER}


_simulate_fmu = fmpy.simulate_fmu


def _simulate_with_solver(filename, *args, start_values=None, **kw):
    """Only FMUs that have a `solver` parameter get it (not the vehicle-track example's Track and Vehicle)."""
    if SOLVER is not None and any(v.name == "solver" for v in read_model_description(filename).modelVariables):
        start_values = with_solver(start_values or {})
    return _simulate_fmu(filename, *args, start_values=start_values or {}, **kw)


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


class Logged:
    """FMU2Slave whose logger records (status, category, message)."""

    def __init__(self, md, unzipdir, name="instance", guid=None):
        self.messages = []
        self.slave = FMU2Slave(guid=guid or md.guid, unzipDirectory=unzipdir,
                               modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(self._log)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self.callbacks = cb

    def _log(self, env, name, status, category, message):
        self.messages.append((status, category.decode(), message.decode().replace("%%", "%")))

    def instantiate(self, logging=False):
        self.slave.instantiate(callbacks=self.callbacks, loggingOn=logging)
        return self.slave

    def text(self):
        return "\n".join(m for _, _, m in self.messages)


@pytest.fixture
def logged(model_description, unzipdir):
    made = []

    def make(**kw):
        made.append(Logged(model_description, unzipdir, **kw))
        return made[-1]

    yield make


def start(slave, vr, params=None, tolerance=None, start_time=0.0, stop_time=None):
    """Instantiated slave -> step-complete state with the given parameters."""
    slave.setupExperiment(tolerance=tolerance, startTime=start_time, stopTime=stop_time)
    slave.enterInitializationMode()
    for name, value in with_solver(params or {}).items():
        if isinstance(value, str):
            slave.setString([vr[name]], [value])
        elif isinstance(value, bool):
            slave.setBoolean([vr[name]], [value])
        elif isinstance(value, int):
            slave.setInteger([vr[name]], [value])
        else:
            slave.setReal([vr[name]], [float(value)])
    slave.exitInitializationMode()


# ---- closed forms (model.md, paper eq. 1, 2, 5) -------------------------------------------------
DEFAULTS = dict(m=407.747, P=40000.0, g=9.81, R1=0.475, R2=0.0, E1=2.1e11, E2=2.1e11, nu1=0.3, nu2=0.3,
                Y=6e8, theta_Y=1.1)


def effective(p):
    q = {**DEFAULTS, **p}
    curv = sum(1 / r for r in (q["R1"], q["R2"]) if r > 0)
    R = 1 / curv
    E = 1 / ((1 - q["nu1"] ** 2) / q["E1"] + (1 - q["nu2"] ** 2) / q["E2"])
    K = 4 / 3 * E * np.sqrt(R)
    FY = np.pi * (3 * np.pi / 4) ** 2 * (q["theta_Y"] * q["Y"]) ** 3 * R ** 2 / E ** 2
    dY = (FY / K) ** (2 / 3)
    return dict(E_star=E, R_star=R, K=K, F_Y=FY, delta_Y=dY, k_lin=FY / dY, W=q["P"] + q["m"] * q["g"], m=q["m"])
