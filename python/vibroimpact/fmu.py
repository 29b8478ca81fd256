"""Access to the FMU, FMI 2.0 and 3.0: where each build is, setting a value by its type (either
version), initializing an FMI 2.0 instance, and collecting what an instance logs. What only FMI 3.0
has (its initialization through Event Mode, steps that return early) is in vibroimpact.fmi3, built
on these.

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


def fmu3_path(required=True):
    """The FMI 3.0 VibroImpact.fmu: fmi3/VibroImpact.fmu beside the FMI 2.0 FMU of fmu_path() (in a
    development checkout build/fmi3/, in an installed package vibroimpact/fmi3/)."""
    path = fmu_path(required=False).parent / "fmi3" / NAME
    if required and not path.is_file():
        raise FileNotFoundError(f"{path} does not exist: build it (cmake -S . -B build && cmake --build build) "
                                f"or install the package with pip install .")
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


# the setter of each model-description type, by FMI version (an enumeration is an Integer in FMI 2.0, an
# Int64 in FMI 3.0)
SETTERS = {2: {"Real": ("setReal", float), "Integer": ("setInteger", int), "Enumeration": ("setInteger", int),
               "Boolean": ("setBoolean", bool), "String": ("setString", str)},
           3: {"Float64": ("setFloat64", float), "Int32": ("setInt32", int), "Int64": ("setInt64", int),
               "Enumeration": ("setInt64", int), "Boolean": ("setBoolean", bool), "String": ("setString", str)}}
FMI3_KIND = {"Real": "Float64", "Integer": "Enumeration"}  # kind_of's names as FMI 3.0 types


def set_value(instance, vr, value, kind=None):
    """fmi2Set<kind> or fmi3Set<kind> of one value on an fmpy instance (FMI 2.0 or 3.0). kind: the
    model description's type; None: from the Python type of value (kind_of; an int is an Integer in
    FMI 2.0 and an Enumeration, set as Int64, in FMI 3.0)."""
    version = 3 if hasattr(instance, "setFloat64") else 2
    kind = kind or kind_of(value)
    kind = FMI3_KIND.get(kind, kind) if version == 3 else kind
    if kind not in SETTERS[version]:
        raise ValueError(f"no FMI {version}.0 type {kind!r} in this FMU")
    method, convert = SETTERS[version][kind]
    getattr(instance, method)([vr], [convert(value)])


def set_values(instance, vr, values, kinds=None):
    """set_value of every start value: vr value reference by name, kinds FMI type by name (missing
    names: from the Python type of the value)."""
    for name, value in values.items():
        set_value(instance, vr[name], value, (kinds or {}).get(name))


def initialize(slave, vr, values, kinds=None, tolerance=None, start_time=0.0, stop_time=None):
    """An instantiated slave to the step-complete state: setupExperiment, the start values set in
    initialization mode, exitInitializationMode. vr: value reference by name; kinds: FMI type by name
    (missing names: from the Python type of the value)."""
    slave.setupExperiment(tolerance=tolerance, startTime=start_time, stopTime=stop_time)
    slave.enterInitializationMode()
    set_values(slave, vr, values, kinds)
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


WARNING = 1   # the status of a logged warning: fmi2Warning and fmi3Warning


class Messages:
    """What an FMU instance logged: `messages`, a list of (status, category, text). limit: keep at
    most that many; unique: skip a text already kept."""

    def __init__(self, limit=None, unique=False):
        self.messages, self.limit, self.unique = [], limit, unique

    def keep(self, status, category, text):
        """Keep one message: category as bytes (the C string), text as str."""
        if self.limit is not None and len(self.messages) >= self.limit:
            return
        if self.unique and any(m == text for _, _, m in self.messages):
            return
        self.messages.append((status, category.decode("utf-8", "replace"), text))

    def texts(self):
        return [m for _, _, m in self.messages]

    def text(self):
        return "\n".join(self.texts())

    def warnings(self):
        """The texts logged as warnings (status WARNING), each once, in the order logged."""
        return list(dict.fromkeys(m.strip() for s, _, m in self.messages if s == WARNING and m.strip()))


class Relay:
    """How every command passes on what the FMU warned in its runs: relay(run, texts) writes each
    text not yet relayed for that run to `stream` (default stderr) as one line
    'vibroimpact COMMAND: RUN: warning: TEXT' and keeps it in `by_run` (run -> [text]) for the
    command's own record of what ran."""

    def __init__(self, command, stream=None):
        self.command, self.stream, self.by_run = command, stream, {}

    def __call__(self, run, texts):
        import sys
        kept = self.by_run.setdefault(run, [])
        for text in texts:
            if text not in kept:
                kept.append(text)
                print(f"vibroimpact {self.command}: {run}: warning: {text}", file=self.stream or sys.stderr,
                      flush=True)

    def of(self, run):
        """The warnings relayed for run (none: [])."""
        return list(self.by_run.get(run, []))


class MessageLog(Messages):
    """Messages of an FMI 2.0 instance: `callbacks` for FMU2Slave/FMU2Model.instantiate, whose logger
    keeps what the instance logs (its message is a format string: '%%' unescaped)."""

    def __init__(self, limit=None, unique=False):
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE, fmi2CallbackFunctions,
                               fmi2CallbackLoggerTYPE)
        super().__init__(limit, unique)
        calloc, free = process_allocator()
        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(self._log)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self.callbacks = cb   # referenced as long as the instance lives

    def _log(self, env, name, status, category, message):
        self.keep(status, category, message.decode("utf-8", "replace").replace("%%", "%"))


def logged_instance(md, unzipdir, interface="CoSimulation", name="instance"):
    """(instance, log) for fmpy.simulate_fmu(fmu_instance=instance): an fmpy instance of the extracted
    FMU (FMI 2.0 or 3.0, `interface` CoSimulation or ModelExchange), instantiated with a logger that
    keeps what it logs in log (Messages; its warnings for a Relay). The caller frees the instance."""
    cs = interface == "CoSimulation"
    identifier = (md.coSimulation if cs else md.modelExchange).modelIdentifier
    if md.fmiVersion == "2.0":
        from fmpy.fmi2 import FMU2Model, FMU2Slave
        log = MessageLog()
        instance = (FMU2Slave if cs else FMU2Model)(guid=md.guid, unzipDirectory=unzipdir,
                                                     modelIdentifier=identifier, instanceName=name)
        instance.instantiate(callbacks=log.callbacks)
        return instance, log
    from fmpy.fmi3 import FMU3Model, FMU3Slave
    log = Messages()
    instance = (FMU3Slave if cs else FMU3Model)(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=identifier,
                                                instanceName=name)
    instance.instantiate(logMessage=lambda env, status, category, text: log.keep(status, category,
                                                                                  text.decode("utf-8", "replace")))
    return instance, log


def simulate(what, fmu, warned=None, **options):
    """fmpy.simulate_fmu(fmu, **options) (Co-Simulation) on an instance whose log is kept: when an FMI
    call fails, a failure.CommandError saying `what` failed, in the FMU's words. warned: called with
    the warnings the FMU logged (Messages.warnings) in a run that succeeded, when it logged any (for
    example lambda texts: relay(run, texts) of a Relay; a failed run's CommandError holds them).
    The instance is made here with a MessageLog's callbacks: fmpy's own `logger=` option installs the
    logger in a native proxy that all of fmpy's later default instances share, so that once this
    call's logger is gone, the next FMU that logs through fmpy's defaults would call freed memory."""
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
        result = fmpy.simulate_fmu(fmu, fmu_instance=slave, model_description=md, **options)
    except Exception as e:
        if not log.messages:
            raise
        raise fmu_refused(what, e, log.texts()) from e
    finally:
        slave.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)
    if warned is not None and log.warnings():
        warned(log.warnings())
    return result


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
