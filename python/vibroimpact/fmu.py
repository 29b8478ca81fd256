"""The helpers every script needs: where the FMU is, setting a value by its type, initializing an
instance, and collecting what the FMU logs.

fmpy is imported inside the functions that need it: the sweep's Dask scheduler imports this module
to read the task graph and needs nothing beyond the standard library.
"""
import os
import pathlib

ENV = "VI_FMU"          # environment variable: the FMU to use, overriding every other place
NAME = "VibroImpact.fmu"
PACKAGE = pathlib.Path(__file__).resolve().parent
CHECKOUT = PACKAGE.parent.parent   # the repository, when the package runs from a development checkout


def checkout_root():
    """The repository this package runs from (python/vibroimpact/ of a development checkout), or None
    when the package is installed from a wheel."""
    return CHECKOUT if (CHECKOUT / "CMakeLists.txt").is_file() and (CHECKOUT / "python" / "vibroimpact") == PACKAGE \
        else None


def fmu_path(required=True):
    """The path of VibroImpact.fmu: $VI_FMU when it is set; else the FMU installed inside this package
    (pip install .); else, in a development checkout, build/VibroImpact.fmu (what CMake builds).
    required: raise FileNotFoundError, saying how to get one, when that file does not exist."""
    if os.environ.get(ENV):
        path = pathlib.Path(os.environ[ENV]).resolve()
    elif (PACKAGE / NAME).is_file() or checkout_root() is None:
        path = PACKAGE / NAME
    else:
        path = checkout_root() / "build" / NAME
    if required and not path.is_file() and os.environ.get(ENV):
        raise FileNotFoundError(f"{ENV} names {path}, which is not a file: point {ENV} at an FMU, or unset it "
                                "to use the package's or the checkout's own")
    if required and not path.is_file():
        raise FileNotFoundError(f"{path} does not exist: build it (cmake -S . -B build && cmake --build build), "
                                f"install the package with pip install ., or set {ENV} to an FMU")
    return path


def build_dir():
    """The folder of fmu_path(): in a development checkout the CMake build folder, which also holds
    the other targets (Track.fmu, Vehicle.fmu, LayerTest.fmu, the table dumps, the benchmark programs)."""
    return fmu_path(required=False).parent


# ---- values --------------------------------------------------------------------------------------------

def kind_of(value):
    """The FMI type a Python value is set as: str String, bool Boolean, int Integer, anything else Real."""
    if isinstance(value, str):
        return "String"
    if isinstance(value, bool):
        return "Boolean"
    if isinstance(value, int):
        return "Integer"
    return "Real"


def set_value(slave, vr, value, kind=None):
    """fmi2Set<kind> of one value on an fmpy FMU2Slave. kind: the model description's type (Real,
    Integer, Enumeration, Boolean, String); None: from the Python type of value (kind_of)."""
    kind = kind or kind_of(value)
    if kind == "Real":
        slave.setReal([vr], [float(value)])
    elif kind in ("Integer", "Enumeration"):
        slave.setInteger([vr], [int(value)])
    elif kind == "Boolean":
        slave.setBoolean([vr], [bool(value)])
    elif kind == "String":
        slave.setString([vr], [str(value)])
    else:
        raise ValueError(f"no FMI 2.0 type {kind!r}")


def initialize(slave, vr, values, kinds=None, tolerance=None, start_time=0.0, stop_time=None):
    """An instantiated slave to the step-complete state: setupExperiment, the start values set in
    initialization mode, exitInitializationMode. vr: value reference by name; kinds: FMI type by name
    (missing names: from the Python type of the value)."""
    slave.setupExperiment(tolerance=tolerance, startTime=start_time, stopTime=stop_time)
    slave.enterInitializationMode()
    for name, value in values.items():
        set_value(slave, vr[name], value, (kinds or {}).get(name))
    slave.exitInitializationMode()


def variables(model_description):
    """(value reference by name, FMI type by name) of a model description read by fmpy."""
    return ({v.name: v.valueReference for v in model_description.modelVariables},
            {v.name: v.type for v in model_description.modelVariables})


# ---- log messages --------------------------------------------------------------------------------------

def process_allocator():
    """(calloc, free) as the process resolves them, for an FMI 2.0 instance's memory callbacks: those
    of the allocator loaded first, AddressSanitizer's when it is preloaded (LD_PRELOAD), so that it
    checks the FMU's blocks. fmpy's own calloc and free are looked up in the C library itself, past a
    preloaded allocator; on Windows they are the C runtime's."""
    import ctypes
    if os.name == "nt":
        from fmpy import calloc, free
        return calloc, free
    process = ctypes.CDLL(None)
    calloc, free = process.calloc, process.free
    calloc.argtypes, calloc.restype = [ctypes.c_size_t, ctypes.c_size_t], ctypes.c_void_p
    free.argtypes, free.restype = [ctypes.c_void_p], None
    return calloc, free


class MessageLog:
    """What an FMU instance logs: `callbacks` for FMU2Slave.instantiate, whose logger appends
    (status, category, message) to `messages` ('%%' unescaped). limit: keep at most that many;
    unique: skip a message text already kept."""

    def __init__(self, limit=None, unique=False):
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE, fmi2CallbackFunctions,
                               fmi2CallbackLoggerTYPE)
        self.messages, self.limit, self.unique = [], limit, unique
        calloc, free = process_allocator()
        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(self._log)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self.callbacks = cb   # referenced as long as the instance lives

    def _log(self, env, name, status, category, message):
        text = message.decode("utf-8", "replace").replace("%%", "%")
        if self.limit is not None and len(self.messages) >= self.limit:
            return
        if self.unique and any(m == text for _, _, m in self.messages):
            return
        self.messages.append((status, category.decode("utf-8", "replace"), text))

    def texts(self):
        return [m for _, _, m in self.messages]

    def text(self):
        return "\n".join(self.texts())


def simulate(what, fmu, **options):
    """fmpy.simulate_fmu(fmu, **options) (Co-Simulation) on an instance whose log is kept: when an FMI
    call fails, a failure.CommandError saying `what` failed, in the FMU's words. The instance is made
    here with a MessageLog's callbacks: fmpy's own `logger=` option installs the logger in a native
    proxy that all of fmpy's later default instances share, so that once this call's logger is gone,
    the next FMU that logs through fmpy's defaults would call freed memory."""
    import shutil

    import fmpy
    from fmpy import extract, read_model_description

    from .failure import fmu_refused
    fmu = str(fmu)
    md = read_model_description(fmu)
    unzipdir = extract(fmu)
    log = Logged(md, unzipdir, name="simulate")
    slave = log.instantiate()
    try:
        return fmpy.simulate_fmu(fmu, fmu_instance=slave, model_description=md, **options)
    except Exception as e:
        if not log.messages:
            raise
        raise fmu_refused(what, e, log.texts()) from e
    finally:
        slave.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)


def check_start(values, what, fmu=None, tolerance=None):
    """One co-simulation instance of the FMU (default fmu_path()) initialized with these start values
    (and tolerance), then freed: the check a command makes of its options before the long work. A
    failure.CommandError saying `what` was refused, in the FMU's words, when it refuses them."""
    from fmpy import extract, read_model_description

    from .failure import fmu_refused
    fmu = str(fmu or fmu_path())
    md = read_model_description(fmu)
    vr, kinds = variables(md)
    log = Logged(md, extract(fmu), name="check")
    try:
        slave = log.instantiate()
        try:
            initialize(slave, vr, values, kinds, tolerance=tolerance)
        finally:
            slave.freeInstance()
    except Exception as e:
        raise fmu_refused(what, e, log.texts()) from e


class Logged(MessageLog):
    """An FMU2Slave of an extracted FMU with a MessageLog: `slave`, `messages`."""

    def __init__(self, md, unzipdir, name="instance", guid=None):
        from fmpy.fmi2 import FMU2Slave
        super().__init__()
        self.slave = FMU2Slave(guid=guid or md.guid, unzipDirectory=unzipdir,
                               modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)

    def instantiate(self, logging=False):
        self.slave.instantiate(callbacks=self.callbacks, loggingOn=logging)
        return self.slave
