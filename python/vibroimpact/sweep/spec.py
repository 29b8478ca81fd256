"""What a sweep runs, worked out on the client: the FMU's interface (names -> value references and
types, enumeration item names), the --set / --grid / --loggrid options, the full product of the
grids, and the chains that the engine hands to the workers.

Nothing here talks to Dask or runs the FMU.
"""
import itertools
import math
import re
from dataclasses import dataclass, field

import numpy as np
from fmpy import read_model_description

from ..failure import CommandError

# The types a start value can have, as the worker sets them (fmi2SetReal/Integer/Boolean/String).
REAL, INTEGER, BOOLEAN, STRING = "Real", "Integer", "Boolean", "String"
_KIND = {"Real": REAL, "Integer": INTEGER, "Enumeration": INTEGER, "Boolean": BOOLEAN, "String": STRING}
_SETTABLE = {"parameter", "input"}
_TRUE, _FALSE = {"true", "1", "yes", "on"}, {"false", "0", "no", "off"}
# "name=value" pairs in a description: an enumeration declared as an Integer (as for libcosim) can keep
# its item names there, e.g. "contact law: hertz=1, johnson=2, lepp=3".
_ITEM_PAIR = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(-?\d+)")


class SpecError(CommandError, ValueError):
    """A sweep option that cannot be run (unknown name, bad value, bad grid): said before any run."""


@dataclass(frozen=True)
class Variable:
    name: str
    vr: int
    kind: str                # REAL, INTEGER, BOOLEAN or STRING
    causality: str
    variability: str
    start: object
    items: dict = field(default_factory=dict)   # enumeration item name -> value

    @property
    def tunable(self):
        return self.variability == "tunable" or self.causality == "input"


class Interface:
    """The FMU's variables by name, read from its modelDescription.xml."""

    def __init__(self, fmu_path):
        try:
            md = read_model_description(fmu_path)
        except Exception as e:   # not a zip, no modelDescription.xml, invalid XML
            raise SpecError(f"{fmu_path} is not an FMU that can be read ({e})") from None
        if md.fmiVersion != "2.0" or md.coSimulation is None:
            raise SpecError(f"{fmu_path} is an FMI {md.fmiVersion} "
                            f"{'Co-Simulation' if md.coSimulation else 'Model Exchange only'} FMU; the sweep runs "
                            "FMI 2.0 Co-Simulation FMUs (vibroimpact path prints the FMI 2.0 VibroImpact.fmu)")
        self.guid = md.guid
        self.model_identifier = md.coSimulation.modelIdentifier
        self.variables = {}
        for v in md.modelVariables:
            items = {}
            if v.declaredType is not None and getattr(v.declaredType, "items", None):
                items = {it.name: int(it.value) for it in v.declaredType.items}
            elif v.type == "Integer" and v.description:
                items = {k: int(x) for k, x in _ITEM_PAIR.findall(v.description)}
            self.variables[v.name] = Variable(v.name, v.valueReference, _KIND.get(v.type, REAL), v.causality,
                                              v.variability, v.start, items)

    def settable(self, name):
        v = self.variables.get(name)
        if v is None:
            close = [n for n in self.variables if n.lower() == name.lower()]
            hint = f" (did you mean {close[0]}?)" if close else ""
            raise SpecError(f"unknown variable '{name}'{hint}")
        if v.causality not in _SETTABLE:
            raise SpecError(f"'{name}' is a {v.causality}; only parameters and inputs can be set")
        return v

    def value(self, name, text):
        """A start value from its text: a number, an enumeration's item name, true/false, a string."""
        v = self.settable(name)
        s = str(text).strip()
        if v.kind == STRING:
            return s
        if v.kind == BOOLEAN:
            if s.lower() in _TRUE:
                return True
            if s.lower() in _FALSE:
                return False
            raise SpecError(f"{name} is a Boolean: give true or false, not '{s}'")
        if v.kind == INTEGER:
            if s in v.items:
                return v.items[s]
            try:
                x = float(s)
            except ValueError:
                names = ", ".join(f"{k}={i}" for k, i in v.items.items())
                raise SpecError(f"{name}: '{s}' is neither an integer nor an item name"
                                + (f" ({names})" if names else "")) from None
            if x != int(x):
                raise SpecError(f"{name} is an integer: '{s}' is not")
            return int(x)
        try:
            return float(s)
        except ValueError:
            raise SpecError(f"{name} is a real number: '{s}' is not") from None

    def start(self, name):
        """The FMU's declared start value (what applies when nothing sets it)."""
        v = self.variables[name]
        return None if v.start is None else self.value(name, v.start)


def _split(option, text):
    if "=" not in text:
        raise SpecError(f"{option} {text}: expected NAME=...")
    name, rest = text.split("=", 1)
    return name.strip(), rest.strip()


def parse_set(interface, text):
    """--set NAME=VALUE -> (name, value)."""
    name, value = _split("--set", text)
    return name, interface.value(name, value)


def parse_grid(interface, text, log=False):
    """--grid NAME=START:STOP:N (linear) or --loggrid (logarithmic) -> (name, values)."""
    option = "--loggrid" if log else "--grid"
    name, rest = _split(option, text)
    parts = rest.split(":")
    if len(parts) != 3:
        raise SpecError(f"{option} {text}: expected NAME=START:STOP:N")
    try:
        a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise SpecError(f"{option} {text}: START and STOP are numbers, N an integer") from None
    v = interface.settable(name)
    if v.kind != REAL:
        raise SpecError(f"{option} {name}: only Real variables can be gridded ({name} is {v.kind}); "
                        "use one sweep per value of it")
    if n < 1 or not (math.isfinite(a) and math.isfinite(b)):
        raise SpecError(f"{option} {text}: need finite START, STOP and N >= 1")
    if log:
        if a <= 0 or b <= 0:
            raise SpecError(f"{option} {text}: a logarithmic grid needs START, STOP > 0")
        values = np.geomspace(a, b, n) if n > 1 else np.array([a])
    else:
        values = np.linspace(a, b, n) if n > 1 else np.array([a])
    return name, [float(x) for x in values]


@dataclass
class Sweep:
    """A parsed sweep: fixed start values, grids (in the order given), times, direction."""
    fixed: dict                  # name -> value (after --set)
    grids: list                  # [(name, [values])], the first is the continuation parameter
    stop_time: float
    step: float
    transient: float = 0.0
    direction: str = None        # None (independent points), "up" or "down"
    log_axes: tuple = ()         # names of the --loggrid variables (for the plots)
    title: str = ""              # how the figures name the sweep (e.g. the --set options as given)

    @property
    def names(self):
        return [n for n, _ in self.grids]

    def points(self):
        """Every point of the full product, first grid outermost: [(index, {name: value})]."""
        if not self.grids:
            return [(0, {})]
        combos = itertools.product(*[vals for _, vals in self.grids])
        return [(i, dict(zip(self.names, c))) for i, c in enumerate(combos)]


def check(sweep, interface):
    """Refuse what cannot run, before any worker starts."""
    for name in list(sweep.fixed) + sweep.names:
        interface.settable(name)
    seen = set()
    for name in sweep.names:
        if name in seen:
            raise SpecError(f"'{name}' is gridded twice")
        if name in sweep.fixed:
            raise SpecError(f"'{name}' is both --set and gridded")
        seen.add(name)
    for label, x in (("--stop-time", sweep.stop_time), ("--step", sweep.step)):
        if not (math.isfinite(x) and x > 0):
            raise SpecError(f"{label} must be a finite positive number (got {x})")
    if not (math.isfinite(sweep.transient) and 0 <= sweep.transient < sweep.stop_time):
        raise SpecError(f"--transient must lie in [0, stop time) (got {sweep.transient})")
    if sweep.step > sweep.stop_time:
        raise SpecError(f"--step {sweep.step} is longer than the stop time {sweep.stop_time}")
    if sweep.direction is not None:
        if sweep.direction not in ("up", "down"):
            raise SpecError("--sweep-direction is up or down")
        if not sweep.grids:
            raise SpecError("--sweep-direction needs a --grid or --loggrid to continue along")
        first = interface.variables[sweep.names[0]]
        if not first.tunable:
            tunable = [n for n, v in interface.variables.items() if v.variability == "tunable"]
            raise SpecError(
                f"a continuation sweep changes its first grid variable, '{first.name}', on a running instance, "
                f"so it must be tunable; this FMU declares it {first.variability}"
                + (f" (tunable: {', '.join(tunable)})" if tunable else " (it has no tunable parameter)"))


def value_entries(interface, values):
    """{name: value} -> [(name, vr, kind, value)], the plain data a worker sets."""
    return [(n, interface.variables[n].vr, interface.variables[n].kind, x) for n, x in values.items()]


def corners(sweep):
    """[{name: value}]: every combination of each grid's first and last value ([{}] without grids)."""
    names = sweep.names
    ends = [sorted({vals[0], vals[-1]}) for _, vals in sweep.grids]
    return [dict(zip(names, c)) for c in itertools.product(*ends)]


def chains(sweep, interface):
    """The work units: [(point indices, fixed start values, [per-point values])].

    Independent sweep: one chain per point. Continuation: one chain per combination of the other
    grids, running along the first grid in the sweep direction (values ascending for up, descending
    for down). Values are (name, vr, kind, value) tuples, plain data for the workers.
    """
    def entries(values):
        return value_entries(interface, values)

    points = sweep.points()
    fixed = entries(sweep.fixed)
    if sweep.direction is None:
        return [([i], fixed, [entries(v)]) for i, v in points]
    first = sweep.names[0]
    groups = {}
    for i, v in points:
        key = tuple((n, x) for n, x in v.items() if n != first)
        groups.setdefault(key, []).append((i, v))
    out = []
    for key, members in groups.items():
        members.sort(key=lambda iv: iv[1][first], reverse=(sweep.direction == "down"))
        out.append(([i for i, _ in members], fixed + entries(dict(key)),
                    [entries({first: v[first]}) for _, v in members]))
    return out
