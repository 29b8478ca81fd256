"""The numbers of README.md and doc/ that the code, the build or the committed reference data decide,
each with where it comes from: fmu-test/test_docs.py recomputes every one and fails when a page says
otherwise.

A Fact is (page, phrase, source): the phrase is the page's text around the number, with {n} where the
number stands (line breaks and runs of blanks count as one blank), and the number there must be what
the source computes, rounded to the digits the page shows. A TableFact names a cell instead: the
column by its header, the row by its first cell, and a pattern of the cell ({*} any text). Measured
numbers (times, errors of runs) are not here: their pages name the command that prints them.

Sources (all quick: a few FMU instances, the drivers' records, `nm`, `ctest -N`, one `vibroimpact
wplastic`), each computed once per session by a Sources object."""
import csv
import functools
import glob
import json
import math
import pathlib
import re
import shutil
import subprocess
import sys
from collections import namedtuple

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model, FMU2Slave, fmi2Real

ROOT = pathlib.Path(__file__).resolve().parent.parent
DBL_EPSILON = 2.0 ** -52

Fact = namedtuple("Fact", "page phrase source")
TableFact = namedtuple("TableFact", "page column row cell source")

WORDS = {w: i for i, w in enumerate("zero one two three four five six seven eight nine ten eleven twelve "
                                    "thirteen fourteen fifteen sixteen".split())}
NUMBER = r"(?P<n>[-+]?(?:\d{1,3}(?:,\d{3})+|\d+)(?:\.\d+)?(?:e[-+]?\d+)?|" + "|".join(WORDS) + ")"


def phrase_regex(phrase):
    """The phrase as a regex: {n} the number, {*} any text within a table cell, any whitespace one blank."""
    parts = re.split(r"(\{n\}|\{\*\})", phrase)
    out = []
    for p in parts:
        out.append(NUMBER if p == "{n}" else r"[^|]*?" if p == "{*}" else
                   r"\s+".join(re.escape(w) for w in p.split(" ")))
    return re.compile("".join(out), flags=re.I)


def parse(shown):
    """The number as the page shows it, and half a unit of its last digit (0 for a word)."""
    low = shown.lower()
    if low in WORDS:
        return float(WORDS[low]), 0.0
    mantissa, _, exponent = low.replace(",", "").partition("e")
    decimals = len(mantissa.partition(".")[2])
    return float(low.replace(",", "")), 0.5 * 10.0 ** (int(exponent or 0) - decimals)


def agrees(shown, value):
    """True when value, rounded to the digits shown, is the number shown."""
    x, half = parse(shown)
    return abs(value - x) <= half * (1 + 1e-9) + 1e-300


# ---- the sources -----------------------------------------------------------------------------------

INTEGER_OPTIONS = {"contact_model", "init", "unloading", "yield_formula", "solver"}


class Sources:
    """What the facts are computed from: the FMU under test and its build folder (drivers, FMI 3.0 FMU),
    the C sources' #defines, the committed reference data, and the package's commands."""

    def __init__(self, fmu, build):
        self.fmu, self.build = pathlib.Path(fmu), pathlib.Path(build)

    @functools.cached_property
    def md(self):
        return read_model_description(str(self.fmu))

    @functools.cached_property
    def unzipdir(self):
        return extract(str(self.fmu))

    def start(self, name):
        return float(next(v.start for v in self.md.modelVariables if v.name == name))

    def nominal(self, name):
        return float(next(v.nominal for v in self.md.modelVariables if v.name == name))

    def instance(self, cls, params):
        """An instance of cls (FMU2Slave, FMU2Model) initialized with these parameters; -> (it, value references)."""
        vr = {v.name: v.valueReference for v in self.md.modelVariables}
        s = cls(guid=self.md.guid, unzipDirectory=self.unzipdir, modelIdentifier=self.md.coSimulation.modelIdentifier,
                instanceName="doc")
        s.instantiate()
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
        for k, v in params.items():
            (s.setInteger if k in INTEGER_OPTIONS else s.setReal)([vr[k]], [v])
        s.exitInitializationMode()
        return s, vr

    @functools.lru_cache(maxsize=None)
    def initial(self, name, **params):
        """A Real variable of a Co-Simulation instance right after initialization with these parameters."""
        s, vr = self.instance(FMU2Slave, params)
        try:
            return s.getReal([vr[name]])[0]
        finally:
            s.terminate()
            s.freeInstance()

    @functools.lru_cache(maxsize=None)
    def nominals(self, contact_model):
        """fmi2GetNominalsOfContinuousStates of a Model Exchange instance at the static start."""
        m, _ = self.instance(FMU2Model, {"contact_model": contact_model})
        try:
            x = (fmi2Real * 3)()
            m.getNominalsOfContinuousStates(x, 3)
            return list(x)
        finally:
            m.freeInstance()

    @functools.cached_property
    def fmu3(self):
        path = self.build / "fmi3" / self.fmu.name
        assert path.is_file(), f"{path}: the FMI 3.0 FMU is missing: build it (cmake --build build)"
        return path

    def vr3(self, name):
        return next(v.valueReference for v in read_model_description(str(self.fmu3)).modelVariables if v.name == name)

    def exports(self, library, prefix):
        nm = shutil.which("nm")
        assert nm, "nm not found: install binutils (apt-get install binutils; ./tools/setup.sh installs gcc with it)"
        out = subprocess.run([nm, "-D", "--defined-only", str(library)], capture_output=True, text=True, check=True)
        return sum(1 for line in out.stdout.splitlines() if line.split()[-1].startswith(prefix))

    @functools.cached_property
    def defines(self):
        """#define NAME value of every C file and header under src/ whose value is a number."""
        found = {}
        for path in sorted(glob.glob(str(ROOT / "src" / "*" / "*.[ch]"))):
            for m in re.finditer(r"^#define (VI_\w+) ([0-9][0-9.e+-]*)L?\b", pathlib.Path(path).read_text(), re.M):
                found[m.group(1)] = float(m.group(2))
        return found

    def define(self, name):
        assert name in self.defines, f"no #define {name} in src/: the page names a constant that is gone"
        return self.defines[name]

    @functools.cached_property
    def reference(self):
        """The committed reference's summary.json, with each scenario's mode changes within its horizon."""
        found = [p for top in ("python", "fmu-test") for p in (ROOT / top).glob("**/reference/data/summary.json")]
        assert len(found) == 1, found
        summary = json.loads(found[0].read_text())
        for name, s in summary.items():
            with open(found[0].parent / f"{name}.events.csv", newline="") as f:
                s["changes_in_horizon"] = sum(float(e["time"]) <= s["horizon"] for e in csv.DictReader(f))
        return summary

    def driver(self, name, *args):
        exe = self.build / name
        assert exe.is_file(), f"{exe} is missing: build the tests (cmake --build build)"
        return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=60, check=True).stdout

    def driver_define(self, source, name):
        m = re.search(rf"^#define {name} (\d+)", (ROOT / "tests" / source).read_text(), re.M)
        assert m, f"no #define {name} in tests/{source}"
        return float(m.group(1))

    def driver_result(self, name, library, case, pattern):
        m = re.search(pattern, self.driver(name, "run", library, case), re.M)
        assert m, f"{name} run {case}: no line matching {pattern}"
        return float(m.group(1))

    @functools.cached_property
    def ctest_commands(self):
        ctest = shutil.which("ctest")
        assert ctest, "ctest not found: install cmake (./tools/setup.sh)"
        out = subprocess.run([ctest, "--test-dir", str(self.build), "--show-only=json-v1"], capture_output=True,
                             text=True, timeout=60, check=True)
        return {t["name"]: t.get("command", []) for t in json.loads(out.stdout)["tests"]}

    def fuzz_seconds(self, target):
        command = self.ctest_commands.get(f"fuzz_{target}")
        assert command, f"no ctest test fuzz_{target} in {self.build}: configure with clang's libFuzzer (./tools/setup.sh)"
        return float(next(a for a in command if a.startswith("-max_total_time=")).split("=")[1])

    @functools.lru_cache(maxsize=None)
    def wplastic(self, *args):
        run = subprocess.run([sys.executable, "-m", "vibroimpact", "wplastic", *args], capture_output=True, text=True,
                             timeout=60)
        assert run.returncode == 0, run.stderr
        return run.stdout

    def wplastic_number(self, args, pattern):
        m = re.search(pattern, self.wplastic(*args))
        assert m, f"vibroimpact wplastic {' '.join(args)} prints nothing matching {pattern}:\n{self.wplastic(*args)}"
        return float(m.group(1))

    def state_bits(self):
        """Bits of a serialized FMU state of a bouncing Hertz run after 2 ms (the FMU's default solver)."""
        s, _ = self.instance(FMU2Slave, {"contact_model": 1, "a": 1e-4})
        try:
            for k in range(20):
                s.doStep(k * 1e-4, 1e-4)
            return 8 * len(s.serializeFMUstate(s.getFMUstate()))
        finally:
            s.freeInstance()

    def pytest_timeout(self):
        return float(re.search(r"^timeout = (\d+)", (ROOT / "pytest.ini").read_text(), re.M).group(1))

    def mutant_share(self):
        """The equivalents list's entries over the mutants tools/mutate.py --list names, in per cent."""
        run = subprocess.run([sys.executable, str(ROOT / "tools" / "mutate.py"), "--list"], capture_output=True,
                             text=True, timeout=120)
        assert run.returncode == 0, run.stderr
        return 100.0 * self.equivalents() / len(run.stdout.splitlines())

    def equivalents(self):
        lines = (ROOT / "tools" / "mutants-equivalent.txt").read_text().splitlines()
        return sum(1 for line in lines if line.strip() and not line.startswith("#"))


# ---- closed forms of the defaults -----------------------------------------------------------------------

def static_load(s):
    return s.start("P") + s.start("m") * s.start("g")


def johnson_slope_above_yield(s):
    """Eq. 3's slope at delta_Y in units of F_Y/delta_Y: 2 (1 + 1/(3 theta_Y))."""
    return 2.0 * (1.0 + 1.0 / (3.0 * s.start("theta_Y")))


def platform_acceleration(s, a=1e-4, f=560.0):
    return a * (2 * math.pi * f) ** 2


# ---- the facts --------------------------------------------------------------------------------------------

def F_Y(**params):
    return lambda s: s.initial("F_Y", **params)


def released(e, law="exact"):
    """The percentage of an isolated impact's energy a damped law's spring part holds at its release, from
    the independent reference (vibroimpact.reference.laws)."""
    def source(_sources):
        from vibroimpact.reference.laws import released_fraction
        return 100.0 * released_fraction(law, e)
    return source


def f_contact(**params):
    return lambda s: s.initial("f_contact", **params)


def define(name, scale=1.0, offset=0.0):
    return lambda s: s.define(name) * scale + offset


def horizon_ms(name):
    return lambda s: s.reference[name]["horizon"] * 1e3


def wplastic(pattern, *args):
    return lambda s: s.wplastic_number(args, pattern)


PAPER_Y = {"Y": 6e8}
FACTS = [
    # README.md
    Fact("README.md", "motion is predictable for its first {n} ms only", horizon_ms("fig4b")),
    Fact("README.md", "German locale), {n} s of fuzzing",
         lambda s: s.fuzz_seconds("VibroImpact") + s.fuzz_seconds("VibroImpact_fmi3")),
    # doc/model.md
    Fact("doc/model.md", "(about {n} times the contact resonance", lambda s: 560.0 / s.initial("f_contact", g=0.0)),
    Fact("doc/model.md", "the contact resonance, {n} Hz with `g = 0`", f_contact(g=0.0)),
    Fact("doc/model.md", "(slope {n} against 1.5 in units of `F_Y/delta_Y`)", johnson_slope_above_yield),
    Fact("doc/model.md", "exceeds `0.01 R*` ({n} mm for the paper's wheel)", lambda s: 10.0 * s.start("R1")),
    Fact("doc/model.md", "({n} internal solver steps or", define("VI_MAX_STEPS_PER_ADVANCE")),
    Fact("doc/model.md", "steps or {n} events in one step", define("VI_MAX_EVENTS_PER_ADVANCE")),
    Fact("doc/model.md", "(Zeno: {n} consecutive events", define("VI_ZENO_EVENTS")),
    Fact("doc/model.md", "each within {n} units in the last place of `t`", define("VI_ZENO_ULPS")),
    Fact("doc/model.md", "after {n} steps in a row held by the explicit method's stability", define("VI_AUTO_STIFF_STEPS")),
    Fact("doc/model.md", "spectral radius above {n}, BDF takes over", define("VI_AUTO_STIFF_HRHO")),
    Fact("doc/model.md", "spectral radius below {n} for 6 steps", define("VI_AUTO_NONSTIFF_HRHO")),
    Fact("doc/model.md", "spectral radius below 1 for {n} steps", define("VI_AUTO_CALM_STEPS")),
    Fact("doc/model.md", "in an isolated impact {n} % of the impact energy", released(0.5)),
    Fact("doc/model.md", "energy at `e_restitution = 0.5`, {n} % at 0.3", released(0.3)),
    Fact("doc/model.md", "% at 0.3, {n} % at 0.7", released(0.7)),
    Fact("doc/model.md", "% at 0.7, {n} % at 0.9", released(0.9)),
    Fact("doc/model.md", "while the overlap falls to 0 ({n} % at `e = 0.5`)", released(0.5, "linear")),
    Fact("doc/model.md", "by Gauss-Legendre quadrature with {n} nodes", define("VI_GAUSS_NODES")),
    Fact("doc/model.md", "than 1e-7 of the step (at most {n} evaluations)", define("VI_PEAK_ITERS")),
    Fact("doc/model.md", "estimate moves by less than {n} of the step", define("VI_PEAK_MOVE")),
    # doc/numerics.md
    Fact("doc/numerics.md", "(slope {n} against 1.5 in units of `F_Y/delta_Y`)", johnson_slope_above_yield),
    Fact("doc/numerics.md", "held above a band of {n} times its tolerance-sized noise", define("VI_GRAZE_TOL")),
    Fact("doc/numerics.md", "{n} consecutive events, each within 1024 units", define("VI_ZENO_EVENTS")),
    Fact("doc/numerics.md", "consecutive events, each within {n} units in the last place", define("VI_ZENO_ULPS")),
    Fact("doc/numerics.md", "paper unloading: `W_plastic < 0` for `delta_c < {n} delta_Y`",
         wplastic(r"paper: W_plastic < 0 for delta_c < ([0-9.]+) delta_Y")),
    Fact("doc/numerics.md", "(impacts below {n} times the yield speed", wplastic(r"paper: .*impacts below ([0-9.]+) v_Y")),
    Fact("doc/numerics.md", "at worst `{n} F_Y delta_Y` (`-0.09751 J`", wplastic(r"paper: .*= (-[0-9.]+) F_Y delta_Y")),
    Fact("doc/numerics.md", "(`{n} J` with the data of Fig. 4b", wplastic(r"paper: .*most negative (-[0-9.]+) J")),
    Fact("doc/numerics.md", "with the data of Fig. 4b, at `delta_c = {n} delta_Y`)",
         wplastic(r"paper: .*at delta_c = ([0-9.]+) delta_Y")),
    Fact("doc/numerics.md", "at `delta_c = 1.129 delta_Y`); restitution up to {n};",
         wplastic(r"paper: .*restitution up to ([0-9.]+)")),
    Fact("doc/numerics.md", "`W_plastic < 0` for `delta_c < {n} delta_Y`, at worst `-1.3655",
         wplastic(r"radius-continuous: W_plastic < 0 for delta_c < ([0-9.]+) delta_Y")),
    Fact("doc/numerics.md", "at worst `{n} F_Y delta_Y` (`-10.01 J`", wplastic(r"radius-continuous: .*= (-[0-9.]+) F_Y delta_Y")),
    Fact("doc/numerics.md", "(`{n} J` with Fig. 4b's data", wplastic(r"radius-continuous: .*most negative (-[0-9.]+) J")),
    Fact("doc/numerics.md", "`{n} J` at `Y = 2e9 Pa`",
         wplastic(r"radius-continuous: .*most negative (-[0-9.]+) J", "--Y", "2e9")),
    Fact("doc/numerics.md", "restitution up to {n}. Continuous unloading", wplastic(r"radius-continuous: .*restitution up to ([0-9.]+)")),
    Fact("doc/model.md", "gives back more than the loading took for `delta_c < {n} delta_Y`",
         wplastic(r"radius-continuous: W_plastic < 0 for delta_c < ([0-9.]+) delta_Y")),
    Fact("doc/model.md", "`delta_c < 4.6100 delta_Y`: up to `{n} F_Y delta_Y` more",
         lambda s: -s.wplastic_number((), r"radius-continuous: .*= (-[0-9.]+) F_Y delta_Y")),
    Fact("doc/model.md", "a rebound up to {n} times", wplastic(r"radius-continuous: .*restitution up to ([0-9.]+)")),
    Fact("doc/model.md", "faster than the impact (at {n} times the yield speed", wplastic(r"radius-continuous: .*\(at ([0-9.]+) v_Y\)")),
    Fact("doc/model.md", "(`a_c >= a_W`: `delta_c >= {n} delta_Y`",
         wplastic(r"radius-continuous: W_plastic < 0 for delta_c < ([0-9.]+) delta_Y")),
    Fact("doc/model.md", "impacts above {n} `v_Y`) the unloading", wplastic(r"radius-continuous: .*impacts below ([0-9.]+) v_Y")),
    Fact("doc/model.md", "(`a_W` is taken {n} units of rounding larger", define("VI_PASSIVE_ULPS")),
    Fact("doc/model.md", "negative for `{n} < delta_c/delta_Y < 4.990`", wplastic(r"continuous: .*delta_f < 0 for ([0-9.]+) <")),
    Fact("doc/model.md", "< delta_c/delta_Y < {n}`", wplastic(r"continuous: .*< delta_c/delta_Y < ([0-9.]+)")),
    Fact("doc/model.md", "(`theta_Y = 1.1`; impacts of {n} to 8.76 `v_Y`)", wplastic(r"continuous: .*\(impacts ([0-9.]+) to")),
    Fact("doc/model.md", "impacts of 6.67 to {n} `v_Y`)", wplastic(r"continuous: .*\(impacts [0-9.]+ to ([0-9.]+) v_Y")),
    Fact("doc/model.md", "a turning point below `delta_c = {n} delta_Y`",
         wplastic(r"paper: W_plastic < 0 for delta_c < ([0-9.]+) delta_Y")),
    Fact("doc/model.md", "(impacts below {n} `v_Y`)", wplastic(r"paper: .*impacts below ([0-9.]+) v_Y")),
    Fact("doc/model.md", "restitution up to {n} and a negative", wplastic(r"paper: .*restitution up to ([0-9.]+)")),
    Fact("doc/model.md", "loading to `delta_c` took (`delta_c < {n} delta_Y`, section 2)",
         wplastic(r"paper: W_plastic < 0 for delta_c < ([0-9.]+) delta_Y")),
    # doc/using.md
    Fact("doc/using.md", "String parameters (up to {n} bytes)", define("VI_STRING_SIZE", offset=-1)),
    Fact("doc/using.md", "a String longer than {n} bytes", define("VI_STRING_SIZE", offset=-1)),
    Fact("doc/using.md", "by at least {n} units of the time resolution", define("VI_MIN_STEP_ULPS")),
    Fact("doc/using.md", "`16 DBL_EPSILON max(1 s, |t|)`, {n} s near t = 0",
         lambda s: s.define("VI_MIN_STEP_ULPS") * DBL_EPSILON),
    Fact("doc/using.md", "s near t = 0, {n} s at t = 1e17 s", lambda s: s.define("VI_MIN_STEP_ULPS") * DBL_EPSILON * 1e17),
    Fact("doc/using.md", "declares the tolerance {n}.", lambda s: float(s.md.defaultExperiment.tolerance)),
    Fact("doc/using.md", "The default experiment runs {n} s", lambda s: float(s.md.defaultExperiment.stopTime)),
    Fact("doc/using.md", "with a {n} ms communication step", lambda s: float(s.md.defaultExperiment.stepSize) * 1e3),
    # doc/model-exchange.md
    Fact("doc/model-exchange.md", "at the paper's load {n} m (the static indentation)", lambda s: s.nominals(1)[0]),
    Fact("doc/model-exchange.md", "(the static indentation) and {n} m/s for Hertz", lambda s: s.nominals(1)[1]),
    Fact("doc/model-exchange.md", "{n} m (`delta_Y`) and 0.16 m/s for Johnson", lambda s: s.nominals(2)[0]),
    Fact("doc/model-exchange.md", "(`delta_Y`) and {n} m/s for Johnson", lambda s: s.nominals(2)[1]),
    Fact("doc/model-exchange.md", "`modelDescription.xml` declares {n} m, 0.1 m/s and 1 J", lambda s: s.nominal("y")),
    Fact("doc/model-exchange.md", "declares 1e-5 m, {n} m/s and 1 J", lambda s: s.nominal("v")),
    Fact("doc/model-exchange.md", "declares 1e-5 m, 0.1 m/s and {n} J", lambda s: s.nominal("W_damping")),
    Fact("doc/model-exchange.md", "event indicators | {n}: the guards of the current mode",
         lambda s: s.md.numberOfEventIndicators),
    Fact("doc/model-exchange.md", "still below zero; {n} such passes in a row", define("VI_MAX_EVENT_PASSES")),
    Fact("doc/model-exchange.md", "and {n} state events each within 1024 ulps", define("VI_ZENO_EVENTS")),
    Fact("doc/model-exchange.md", "state events each within {n} ulps", define("VI_ZENO_ULPS")),
    Fact("doc/model-exchange.md", "(its rounding noise plus {n} times its change", define("VI_GRAZE_TOL")),
    Fact("doc/model-exchange.md", "the reference on all {n} scenarios", lambda s: len(s.reference)),
    # doc/fmi3.md
    Fact("doc/fmi3.md", "the independent variable `time` (value reference {n})", lambda s: s.vr3("time")),
    Fact("doc/fmi3.md", "(value references {n} + row)", lambda s: s.vr3("der(yC_in)") - s.vr3("yC_in")),
    Fact("doc/fmi3.md", "(value references {n} + i)", lambda s: s.vr3("event_indicator_0")),
    Fact("doc/fmi3.md", "(within {n} units of the time resolution", define("VI_EARLY_RETURN_UNITS")),
    Fact("doc/fmi3.md", "`DBL_EPSILON max(1 s, |t|)`, {n} s below 1 s)",
         lambda s: s.define("VI_EARLY_RETURN_UNITS") * DBL_EPSILON),
    # doc/platforms.md
    Fact("doc/platforms.md", "(the {n} `fmi2*` functions of both interfaces",
         lambda s: s.exports(s.build / f"{s.fmu.stem}.so", "fmi2")),
    Fact("doc/platforms.md", "the {n} `fmi3*` functions)", lambda s: s.exports(s.build / "fmi3" / f"{s.fmu.stem}.so", "fmi3")),
    Fact("doc/platforms.md", "refused calls, {n} instances at once", lambda s: s.driver_define("fmu_driver.c", "N_INSTANCES")),
    Fact("doc/platforms.md", "the status of every call and every message logged ({n} lines)",
         lambda s: len(s.driver("fmu_driver", "run", s.build / f"{s.fmu.stem}.so", "refusals").splitlines())),
    Fact("doc/platforms.md", "| refusals | {n} of 77 lines equal |",
         lambda s: len(s.driver("fmu_driver", "run", s.build / f"{s.fmu.stem}.so", "refusals").splitlines())),
    Fact("doc/platforms.md", "({n} early returns in fig4b",
         lambda s: s.driver_result("fmu3_driver", s.build / "fmi3" / f"{s.fmu.stem}.so", "cs-fig4b-auto",
                                   r"^= (\d+) early returns")),
    Fact("doc/platforms.md", "Over the first 20 ms ({n} impacts, every mode of the automaton)",
         lambda s: s.driver_result("fmu_driver", s.build / f"{s.fmu.stem}.so", "fig4b-auto", r"^= n_impacts (\d+)")),
    Fact("doc/platforms.md", "(the {n} scenarios of the paper against the independent reference",
         lambda s: len(s.reference)),
    # doc/rolling.md
    Fact("doc/rolling.md", "At most {n} million rows", define("VI_PROFILE_ROWS_MAX", scale=1e-6)),
    Fact("doc/rolling.md", "lines of at most {n} characters", define("VI_PROFILE_LINE_MAX", offset=-2)),
    # doc/scenarios.md
    Fact("doc/scenarios.md", "`F_Y` is {n} kN and the largest force", lambda s: s.initial("F_Y", Y=1e9) / 1e3),
    Fact("doc/scenarios.md", "With eq. 5 as printed, `F_Y` is {n} kN",
         lambda s: s.initial("F_Y", Y=1e9, yield_formula=2) / 1e3),
    Fact("doc/scenarios.md", "the platform's {n} mm.", lambda s: 2e3 * 1e-4),
    Fact("doc/scenarios.md", "That resonance is {n} Hz with `g = 0`", f_contact(g=0.0)),
    Fact("doc/scenarios.md", "and {n} Hz linearised at `P + m g`", f_contact()),
    Fact("doc/scenarios.md", "so at the static load it rises from {n} Hz", f_contact()),
    Fact("doc/scenarios.md", "and only its first {n} ms are predictable", horizon_ms("fig4b")),
    Fact("doc/scenarios.md", "(chaotic beyond {n} ms)", horizon_ms("fig4c")),
    Fact("doc/scenarios.md", "up to `a (2 pi f)^2 = {n} m/s^2`", platform_acceleration),
    Fact("doc/scenarios.md", "The LEPP force is capped at `F_Y = {n} kN`", lambda s: s.initial("F_Y", **PAPER_Y) / 1e3),
    Fact("doc/scenarios.md", "`(F_Y - P - m g)/m` is only {n} m/s^2",
         lambda s: (s.initial("F_Y", **PAPER_Y) - static_load(s)) / s.start("m")),
    Fact("doc/scenarios.md", "with the printed yield formula, `F_Y` = {n} kN",
         lambda s: s.initial("F_Y", Y=6e8, yield_formula=2) / 1e3),
    Fact("doc/scenarios.md", "is below the static load of {n} kN", lambda s: static_load(s) / 1e3),
    Fact("doc/scenarios.md", "`P = 40 kN = 10 m g` (`m = {n} kg`", lambda s: s.start("m")),
    Fact("doc/scenarios.md", "which is 0.1 % of `a`. The bouncing Johnson cases are chaotic: {n} ms for `fig4b`",
         horizon_ms("fig4b")),
    Fact("doc/scenarios.md", "{n} ms for `fig4c`", horizon_ms("fig4c")),
    Fact("doc/scenarios.md", "{n} ms for `continuous`", horizon_ms("continuous")),
    Fact("doc/scenarios.md", "and {n} ms for `printed`", horizon_ms("printed")),
    Fact("doc/scenarios.md", "regains contact once per excitation period: {n} impacts in 56 periods",
         lambda s: s.reference["fig4a"]["n_impacts"]),
    Fact("doc/scenarios.md", "It makes {n} impacts with forces up to", lambda s: s.reference["fig4b"]["n_impacts"]),
    Fact("doc/scenarios.md", "The mass flies up to 9 mm, {n} impacts", lambda s: s.reference["fig5b"]["n_impacts"]),
    Fact("doc/scenarios.md", "continuous unloading, {n} impacts", lambda s: s.reference["continuous"]["n_impacts"]),
    # doc/sweeps.md
    Fact("doc/sweeps.md", "The dotted line is `f_contact = {n} Hz`", f_contact()),
    Fact("doc/sweeps.md", "peaks within 1 Hz of `sqrt(k/m)/(2 pi)`, which is {n} Hz", f_contact()),
    Fact("doc/sweeps.md", "(1.8 ms at {n} Hz)", f_contact()),
    Fact("doc/sweeps.md", "larger than the static indentation ({n} µm)", lambda s: -1e6 * s.initial("y", contact_model=1)),
    Fact("doc/sweeps.md", "the mass's `(P + m g)/m = {n} m/s^2`", lambda s: static_load(s) / s.start("m")),
    Fact("doc/sweeps.md", "(at {n} Hz for a rigid contact)",
         lambda s: math.sqrt(static_load(s) / s.start("m") / 1e-4) / (2 * math.pi)),
    Fact("doc/sweeps.md", "The first impacts yield (`F_Y = {n} kN`", lambda s: s.initial("F_Y", **PAPER_Y) / 1e3),
    # doc/speed.md
    Fact("doc/speed.md", "with {n}, 0.8 times the nearest point", define("VI_AUTO_STIFF_HRHO")),
    Fact("doc/speed.md", "{n} such steps in a row mean the step is held by stability", define("VI_AUTO_STIFF_STEPS")),
    Fact("doc/speed.md", "While BDF runs, once it has taken {n} steps", define("VI_AUTO_BDF_MIN_STEPS")),
    Fact("doc/speed.md", "{n} steps in a row with `h rho < 1`", define("VI_AUTO_CALM_STEPS")),
    Fact("doc/speed.md", "steps in a row with `h rho < {n}`", define("VI_AUTO_NONSTIFF_HRHO")),
    Fact("doc/speed.md", "The explicit method's steps never exceed `h rho = {n}`", define("VI_SOLVER_STABLE_HRHO")),
    Fact("doc/speed.md", "is handed over at `t = 8 x 5.4/rho`, {n} s",
         lambda s: s.define("VI_AUTO_STIFF_STEPS") * s.define("VI_SOLVER_STABLE_HRHO") /
         (2 * math.pi * s.initial("f_contact", R1=1000.0, m=1e-5))),
    Fact("doc/numerics.md", "Its steps are bounded by its stability: `h rho <= {n}`", define("VI_SOLVER_STABLE_HRHO")),
    Fact("doc/numerics.md", "(the paper's contact, `rho` = {n}/s", lambda s: 2 * math.pi * s.initial("f_contact")),
    Fact("doc/numerics.md", "`rho` = 1706/s: {n} steps per second)",
         lambda s: 2 * math.pi * s.initial("f_contact") / s.define("VI_SOLVER_STABLE_HRHO")),
    Fact("doc/numerics.md", "(absolute tolerances from `delta_Y`, {n} m", lambda s: s.initial("delta_Y", R1=1000.0, m=1e-5)),
    Fact("doc/numerics.md", "against a resting indentation of {n} m", lambda s: s.initial("delta", R1=1000.0, m=1e-5)),
    # doc/testing.md
    Fact("doc/testing.md", "(`pytest.ini`: {n} s unless a test says otherwise", lambda s: s.pytest_timeout()),
    Fact("doc/testing.md", "the static indentation with the paper's {n} Hz", f_contact(g=0.0)),
    Fact("doc/testing.md", "`f_contact` = {n} Hz, also from free ringing", f_contact(g=0.0)),
    Fact("doc/testing.md", "(same sequence, within 1 us, all {n} scenarios)", lambda s: len(s.reference)),
    Fact("doc/testing.md", "ctest runs fuzz_VibroImpact for {n} s", lambda s: s.fuzz_seconds("VibroImpact")),
    Fact("doc/testing.md", "and fuzz_VibroImpact_fmi3 for {n} s", lambda s: s.fuzz_seconds("VibroImpact_fmi3")),
    Fact("doc/testing.md", "All {n} single-bit flips of a serialized state (Hertz, bouncing, after 2 ms)",
         lambda s: s.state_bits()),
    Fact("doc/testing.md", "`tools/mutants-equivalent.txt` holds {n} entries", lambda s: s.equivalents()),
    Fact("doc/testing.md", "(about {n} % of the mutants `tools/mutate.py --list` names)", lambda s: s.mutant_share()),
    Fact("doc/testing.md", "reset, {n} instances at once, and LayerTest's", lambda s: s.driver_define("fmu_driver.c", "N_INSTANCES")),
    Fact("doc/testing.md", "reset, {n} interleaved instances", lambda s: s.driver_define("fmu3_driver.c", "N_INSTANCES")),
    Fact("doc/testing.md", "{n} refusals with their messages equal",
         lambda s: len(s.driver("fmu_driver", "run", s.build / f"{s.fmu.stem}.so", "refusals").splitlines())),
]


def scenario_rows(page, column, cell, source):
    return [TableFact(page, column, f"{name}", cell, functools.partial(source, name=name))
            for name in ("fig4a", "fig4b", "fig4c", "fig5a", "fig5b", "fig5c", "fig6a", "fig6b", "fig6c", "fig6a_30um",
                         "fig6b_30um", "fig6c_30um", "stick", "continuous", "printed")]


TABLE_FACTS = (
    scenario_rows("doc/scenarios.md", "horizon [ms]", "{n}", lambda s, name: s.reference[name]["horizon"] * 1e3)
    + scenario_rows("doc/scenarios.md", "mode changes compared", "{n} (same)",
                    lambda s, name: s.reference[name]["changes_in_horizon"])
    + scenario_rows("doc/scenarios.md", "impacts FMU / ref (0.1 s)", "{*} / {n}",
                    lambda s, name: s.reference[name]["n_impacts"])
    + scenario_rows("doc/fmi3.md", "reference changes within the horizon", "{n}",
                    lambda s, name: s.reference[name]["changes_in_horizon"])
)


# ---- reading the pages -------------------------------------------------------------------------------------

def page_text(page):
    return re.sub(r"\s+", " ", (ROOT / page).read_text())


def table_cells(page, column, row):
    """The cells of the column in every row whose first cell is row (backticks ignored), over the page's tables."""
    cells, header = [], None
    for line in (ROOT / page).read_text().splitlines():
        if not line.startswith("|"):
            header = None
            continue
        cols = [c.strip() for c in line.strip().strip("|").split("|")]
        if header is None:
            header = cols
        elif column in header and cols[0].strip("`") == row and len(cols) == len(header):
            cells.append(cols[header.index(column)])
    return cells
