"""Write the FMI 2.0 or FMI 3.0 modelDescription.xml of a model on the generic FMI layer (src/fmi/vi_fmu.h)
from its variable table, the one source of both.

Run at build time by vi_add_fmu (cmake/vi_fmu.cmake), once per FMI version:

    python vi_model_description.py --fmi 2|3 --out OUT.xml [--time-vr VR --derivative-vr-base BASE
                                   --indicator-vr-base INDICATOR_BASE] --dump [EMULATOR...] DUMP
    python vi_model_description.py --markdown --out PAGE.md --dump DUMP   (the documentation's table)

DUMP is the model's <Name>_dump_variables (tests/dump_variables.c; run under EMULATOR when cross
compiling), which prints the model's table header (its variables with their dependencies and nominal
values, its enumerations, identity, default experiment) and what its vi_fmu_model says about Model
Exchange (states, derivatives, event indicators, directional derivatives). The output is not stamped
with a release: cmake/vi_fmu_stamp.py adds version, date, copyright and licence. The unstamped FMI 2.0
description of the contact model is the repository's top-level modelDescription.xml, which
fmu-test/test_interface.py compares with what the build packs; to write it again:

    python cmake/vi_model_description.py --fmi 2 --out modelDescription.xml --dump build/VibroImpact_dump_variables

and the documentation's variable table of the contact model, doc/variables.md, the same way (--markdown).

FMI 2.0: the variables in value-reference order (an enumerated Integer lists its items in its
description and declares their range as min and max, since some importers ignore Enumerations);
ModelStructure: every output and state derivative with the dependencies of the table's depends
column, and the initial unknowns (outputs, calculated parameters, state derivatives) depending on
every parameter and input (no dependencies attribute).
FMI 3.0: Real -> Float64 (unit and nominal through a Float64Type, as the FMI 3.0 Reference FMUs
declare them), Integer -> Int32, and Integer or Enumeration rows whose enum column names an
enumeration -> Enumeration; the independent variable `time` at VR (VI_FMI3_TIME_VR); when the model
interpolates its inputs, each Real input `u` of row r gets an input `der(u)` at BASE + r
(VI_FMI3_DERIVATIVE_VR_BASE), which the face maps onto the input's derivative; with Model Exchange the
event indicators are variables event_indicator_<i> at INDICATOR_BASE + i.
The capability flags are the layer's (src/fmi/vi_fmi2.c, src/fmi/vi_fmi3.c), written once here.
"""
import argparse
import re
import subprocess
import sys
from xml.sax.saxutils import quoteattr

# Every FMI 2.0 face: CVODE and the models allocate with malloc, so the importer's memory functions
# cannot be the only ones used (the layer takes its instance from them when given).
CO_SIMULATION_2 = dict(needsExecutionTool="false", canHandleVariableCommunicationStepSize="true",
                       maxOutputDerivativeOrder="0", canRunAsynchronuously="false",
                       canBeInstantiatedOnlyOncePerProcess="false", canNotUseMemoryManagementFunctions="true",
                       canGetAndSetFMUstate="true", canSerializeFMUstate="true", providesDirectionalDerivative="false")
MODEL_EXCHANGE_2 = dict(needsExecutionTool="false", completedIntegratorStepNotNeeded="false",
                        canBeInstantiatedOnlyOncePerProcess="false", canNotUseMemoryManagementFunctions="true",
                        canGetAndSetFMUstate="true", canSerializeFMUstate="true")
CO_SIMULATION_3 = dict(needsExecutionTool="false", canBeInstantiatedOnlyOncePerProcess="false",
                       canGetAndSetFMUState="true", canSerializeFMUState="true", providesDirectionalDerivatives="false",
                       providesAdjointDerivatives="false", canHandleVariableCommunicationStepSize="true",
                       maxOutputDerivativeOrder="0", providesIntermediateUpdate="false",
                       canReturnEarlyAfterIntermediateUpdate="false",
                       hasEventMode="true", providesEvaluateDiscreteStates="false")
MODEL_EXCHANGE_3 = dict(needsExecutionTool="false", canBeInstantiatedOnlyOncePerProcess="false",
                        canGetAndSetFMUState="true", canSerializeFMUState="true", providesAdjointDerivatives="false",
                        providesEvaluateDiscreteStates="false", needsCompletedIntegratorStep="true")

# The layer's log categories (VI_CAT_* in src/fmi/vi_fmi_layer.h, in that order); the call category is
# named after the version.
LOG_CATEGORIES = [
    ("logEvents", "every event of the model: changes of its mode, state and time events"),
    ("logSolver", "solver settings and statistics"),
    ("logStatusWarning", "warnings"),
    ("logStatusDiscard", "steps that stopped early (Discard; always logged)"),
    ("logStatusError", "errors (always logged)"),
    ("logFmi{v}Call", "every FMI function call"),
    ("logAll", "all of the above"),
]

# The SI base units of every unit symbol a table may use (exponents of kg, m, s).
UNITS = {"m": dict(m=1), "kg": dict(kg=1), "s": dict(s=1), "N": dict(kg=1, m=1, s=-2), "Pa": dict(kg=1, m=-1, s=-2),
         "J": dict(kg=1, m=2, s=-2), "W": dict(kg=1, m=2, s=-3), "Hz": dict(s=-1), "1/s": dict(s=-1),
         "m/s": dict(m=1, s=-1), "m/s2": dict(m=1, s=-2), "N/m": dict(kg=1, s=-2), "N.s/m": dict(kg=1, s=-1),
         "N/s": dict(kg=1, m=1, s=-3)}

GENERATED = "<!-- Generated by cmake/vi_model_description.py from the model's variable table: do not edit. -->"
# Before ModelStructure: what its dependencies mean for each interface.
STRUCTURE_NOTE = ["    <!-- Dependencies as Model Exchange has them: an output or state derivative moves at once with",
                  "         these inputs and states (in some mode). In Co-Simulation an input set at a communication",
                  "         point acts from the next step on: no output changes before it. Initially every unknown",
                  "         depends on every parameter and input. -->"]


def fail(msg):
    sys.exit(f"vi_model_description.py: {msg}")


def run_dump(command):
    run = subprocess.run(command, stdout=subprocess.PIPE, universal_newlines=True, encoding="utf-8")
    if run.returncode != 0:
        fail(f"{' '.join(command)} failed with exit code {run.returncode}")
    return run.stdout


def parse_variable(cols):
    vr, name, typ, enum, caus, var, init, start, lo, hi, unit, desc = cols[:12]
    return dict(vr=int(vr), name=name, type=typ, enum=enum, causality=caus, variability=var, initial=init,
                start=start, min=lo or None, max=hi or None, unit=unit, description=desc, nominal=None, depends=None)


def parse_dump(text, where):
    """The dump as a dict: guid, model, description, experiment, interpolates, early_return, me (n_states,
    n_indicators, directional), states [(state vr, derivative vr)], variables (dicts by row), enum_types,
    items."""
    t = dict(states=[], variables=[], enum_types={}, items={}, me=(0, 0, False), interpolates=False, early_return=False)
    nominal, depends, ranges = {}, {}, {}
    for line in text.splitlines():
        cols = line.split("\t")
        kind, rest = cols[0], cols[1:]
        if kind == "guid":
            t["guid"] = rest[0]
        elif kind == "model":
            t["model"], t["description"] = rest[0], rest[1]
        elif kind == "experiment":
            t["experiment"] = dict(startTime=rest[0], stopTime=rest[1], tolerance=rest[2] or None, stepSize=rest[3])
        elif kind == "interpolates_inputs":
            t["interpolates"] = rest[0] == "1"
        elif kind == "early_return":
            t["early_return"] = rest[0] == "1"
        elif kind == "model_exchange":
            t["me"] = (int(rest[0]), int(rest[1]), rest[2] == "1")
        elif kind == "state":
            t["states"].append((int(rest[0]), int(rest[1])))
        elif kind == "var":
            t["variables"].append(parse_variable(rest))
        elif kind == "nominal":
            nominal[int(rest[0])] = rest[1]
        elif kind == "range":
            ranges[int(rest[0])] = rest[1]
        elif kind == "depends":
            depends[int(rest[0])] = rest[1].split()
        elif kind == "enumtype":
            t["enum_types"][rest[0]] = rest[1]
        elif kind == "enum":
            t["items"].setdefault(rest[0], []).append((rest[1], int(rest[2])))
    if "guid" not in t or "model" not in t or not t["variables"]:
        fail(f"{where}: no guid, model or variables (is it the output of <Name>_dump_variables?)")
    for vr, v in enumerate(t["variables"]):
        if v["vr"] != vr:
            fail(f"{where}: value reference {v['vr']} in row {vr}")
        v["nominal"], v["depends"], v["range"] = nominal.get(vr), depends.get(vr, []), ranges.get(vr, "")
    check_table(t, where)
    return t


def check_table(t, where):
    """Enumerations have items, states are rows, dependencies name inputs and states of outputs and
    state derivatives; strips the items the dump appends to an enumerated Integer's description."""
    by_name = {v["name"]: v for v in t["variables"]}
    state_vrs = {s for s, _ in t["states"]}
    derivative_vrs = {d for _, d in t["states"]}
    if len(t["states"]) != t["me"][0] or any(vr >= len(t["variables"]) for vr in state_vrs | derivative_vrs):
        fail(f"{where}: the states and derivatives are not {t['me'][0]} rows of the table")
    for v in t["variables"]:
        if v["enum"] != "none":
            if v["enum"] not in t["items"]:
                fail(f"{v['name']}: enumeration {v['enum']} has no items")
            suffix = ": " + ", ".join(f"{n}={k}" for n, k in t["items"][v["enum"]])
            v["plain_description"] = v["description"][: -len(suffix)] if v["description"].endswith(suffix) \
                else v["description"]
        else:
            v["plain_description"] = v["description"]
        unknown = v["causality"] == "output" or v["vr"] in derivative_vrs
        if v["depends"] and not unknown:
            fail(f"{v['name']}: only outputs and state derivatives declare dependencies (depends column)")
        for d in v["depends"]:
            if d not in by_name or not (by_name[d]["causality"] == "input" or by_name[d]["vr"] in state_vrs):
                fail(f"{v['name']}: depends on {d!r}, which is no input or continuous state of the table")
        if v["unit"] and v["unit"] not in UNITS:
            fail(f"{v['name']}: unit {v['unit']!r} is not in UNITS of cmake/vi_model_description.py")


def read_table(command):
    """The dump of command: (guid, variables, enumeration items by type), as cmake/vi_fmu_doc.py reads it."""
    t = parse_dump(run_dump(command), command[-1])
    for v in t["variables"]:
        v["description"] = v["plain_description"]
    return t["guid"], t["variables"], t["items"]


def number(text):
    """A number as the shortest text that reads back as the same double (integers plain, 1e-5 not 1e-05)."""
    x = float(text)
    return str(int(x)) if x.is_integer() and abs(x) < 2**53 else re.sub(r"e([+-])0(?=\d)", r"e\1", repr(x))


def attrs(**kw):
    return "".join(f" {k}={quoteattr(str(v))}" for k, v in kw.items() if v is not None)


def units_used(t):
    """The unit symbols of the table in the order of first use (and s, the unit of time, in FMI 3.0)."""
    seen = []
    for v in t["variables"]:
        if v["unit"] and v["unit"] not in seen:
            seen.append(v["unit"])
    return seen


def unit_definitions(units):
    out = ["  <UnitDefinitions>"]
    for u in units:
        base = "".join(f" {k}={quoteattr(str(e))}" for k, e in sorted(UNITS[u].items()))
        out.append(f"    <Unit{attrs(name=u)}><BaseUnit{base}/></Unit>")
    return out + ["  </UnitDefinitions>"] if units else []


def log_categories(version):
    out = ["  <LogCategories>"]
    for name, desc in LOG_CATEGORIES:
        out.append(f"    <Category{attrs(name=name.format(v=version), description=desc)}/>")
    return out + ["  </LogCategories>"]


def experiment(t):
    e = {k: (number(v) if v is not None else None) for k, v in t["experiment"].items()}
    return [f"  <DefaultExperiment{attrs(**e)}/>"]


def initial_of(v):
    """The initial attribute FMI lets a variable declare (outputs, calculated parameters, locals)."""
    return v["initial"] if v["causality"] in ("output", "calculatedParameter", "local") else None


def initial_unknowns(t):
    """Outputs, calculated parameters and (with Model Exchange) state derivatives that are calculated."""
    derivatives = {d for _, d in t["states"]}
    return [v for v in t["variables"] if v["initial"] in ("calculated", "approx")
            and (v["causality"] in ("output", "calculatedParameter") or v["vr"] in derivatives)]


# ---- FMI 2.0 --------------------------------------------------------------------------------------------

def fmi2_header(t):
    root = dict(fmiVersion="2.0", modelName=t["model"], guid=t["guid"], description=t["description"],
                generationTool="VibroImpact cmake/vi_model_description.py", variableNamingConvention="structured",
                numberOfEventIndicators=str(t["me"][1] if t["me"][0] else 0))  # Model Exchange only
    out = ['<?xml version="1.0" encoding="UTF-8"?>', GENERATED,
           "<!-- FMI's min and max are inclusive: an exclusive bound of the table is declared as the nearest",
           '     double inside it, so min="5e-324" (the smallest positive double) says "> 0" exactly. -->',
           f"<fmiModelDescription{attrs(**root)}>"]
    n_states, _, directional = t["me"]
    if n_states:
        me = dict(modelIdentifier=t["model"], **MODEL_EXCHANGE_2,
                  providesDirectionalDerivative="true" if directional else "false")
        out.append(f"  <ModelExchange{attrs(**me)}/>")
    cs = dict(modelIdentifier=t["model"], **CO_SIMULATION_2, canInterpolateInputs="true" if t["interpolates"] else "false")
    out.append(f"  <CoSimulation{attrs(**cs)}/>")
    out += unit_definitions(units_used(t))
    declared = [e for e in t["items"] if any(v["type"] == "Enumeration" and v["enum"] == e for v in t["variables"])]
    if declared:
        out.append("  <TypeDefinitions>")
        for e in declared:
            out.append(f"    <SimpleType{attrs(name=e, description=t['enum_types'].get(e))}>")
            out.append("      <Enumeration>")
            out += [f"        <Item{attrs(name=n, value=k)}/>" for n, k in t["items"][e]]
            out.append("      </Enumeration>")
            out.append("    </SimpleType>")
        out.append("  </TypeDefinitions>")
    return out + log_categories(2) + experiment(t)


def fmi2_type_element(t, v, derivative_of):
    """The type element of a ScalarVariable (<Real unit=... min=... start=.../>)."""
    a = {}
    if v["type"] == "Enumeration":
        a["declaredType"] = v["enum"]
    if v["type"] == "Real" and v["unit"]:
        a["unit"] = v["unit"]
    if v["type"] == "Real" and v["nominal"]:
        a["nominal"] = number(v["nominal"])
    if v["type"] == "Integer" and v["enum"] != "none":
        values = [k for _, k in t["items"][v["enum"]]]
        a["min"], a["max"] = str(min(values)), str(max(values))
    elif v["type"] in ("Real", "Integer"):
        a["min"], a["max"] = (v[b] and number(v[b]) for b in ("min", "max"))
    if v["vr"] in derivative_of:
        a["derivative"] = str(derivative_of[v["vr"]] + 1)
    if v["initial"] == "exact":
        if v["type"] == "String":
            a["start"] = v["start"]
        elif v["type"] == "Boolean":
            a["start"] = "true" if float(v["start"]) else "false"
        else:
            a["start"] = number(v["start"])
    return f"<{v['type']}{attrs(**a)}/>"


def fmi2_variables(t):
    derivative_of = {d: s for s, d in t["states"]}
    out = ["  <ModelVariables>"]
    for v in t["variables"]:
        a = dict(name=v["name"], valueReference=v["vr"], description=v["description"] or None,
                 causality=v["causality"], variability=v["variability"], initial=initial_of(v))
        out.append(f"    <!-- {v['vr'] + 1} --><ScalarVariable{attrs(**a)}>")
        out.append(f"      {fmi2_type_element(t, v, derivative_of)}")
        out.append("    </ScalarVariable>")
    return out + ["  </ModelVariables>"]


def fmi2_structure(t):
    """ModelStructure by index (row + 1)."""
    by_name = {v["name"]: v for v in t["variables"]}

    def unknown(v, with_dependencies=True):
        deps = " ".join(str(i) for i in sorted(by_name[d]["vr"] + 1 for d in v["depends"]))
        return f"      <Unknown{attrs(index=v['vr'] + 1, dependencies=deps if with_dependencies else None)}/>"
    outputs = [v for v in t["variables"] if v["causality"] == "output"]
    out = ["  <ModelStructure>"] + STRUCTURE_NOTE
    if outputs:
        out += ["    <Outputs>"] + [unknown(v) for v in outputs] + ["    </Outputs>"]
    if t["states"]:
        out += ["    <Derivatives>"] + [unknown(t["variables"][d]) for _, d in t["states"]] + ["    </Derivatives>"]
    initial = initial_unknowns(t)
    if initial:
        out += ["    <InitialUnknowns>"] + [unknown(v, False) for v in initial] + ["    </InitialUnknowns>"]
    return out + ["  </ModelStructure>"]


def fmi2(t):
    return fmi2_header(t) + fmi2_variables(t) + fmi2_structure(t) + ["</fmiModelDescription>"]


# ---- FMI 3.0 --------------------------------------------------------------------------------------------

def float_type(v):
    """(name, unit, nominal) of the Float64Type of the Real row v, or None."""
    unit, nominal = v["unit"] or None, v["nominal"] and number(v["nominal"])
    if nominal:
        return (f"{unit} (nominal {nominal})" if unit else f"nominal {nominal}"), unit, nominal
    return (unit, unit, None) if unit else None


def rate_unit(t, v):
    """The unit of der(v), v's unit per second, where the table uses that unit."""
    rate = v["unit"] + "/s" if v["unit"] else None
    return rate if rate in units_used(t) else None


def fmi3_header(t, args):
    root = dict(fmiVersion="3.0", modelName=t["model"], description=t["description"].replace("fmi2", "fmi3"),
                generationTool="VibroImpact cmake/vi_model_description.py", instantiationToken=t["guid"],
                variableNamingConvention="structured")
    out = ['<?xml version="1.0" encoding="UTF-8"?>', GENERATED, f"<fmiModelDescription{attrs(**root)}>"]
    n_states, _, directional = t["me"]
    if n_states:
        me = dict(modelIdentifier=t["model"], **MODEL_EXCHANGE_3,
                  providesDirectionalDerivatives="true" if directional else "false")
        out.append(f"  <ModelExchange{attrs(**me)}/>")
    cs = dict(modelIdentifier=t["model"], **CO_SIMULATION_3,
              mightReturnEarlyFromDoStep="true" if t["early_return"] else "false")  # at the model's events
    out.append(f"  <CoSimulation{attrs(**cs)}/>")
    units = units_used(t)
    out += unit_definitions(units + (["s"] if "s" not in units else []))
    reals = [v for v in t["variables"] if v["type"] == "Real"]
    types = sorted({float_type(v) for v in reals if float_type(v)} | {("s", "s", None)}
                   | {(r, r, None) for r in (rate_unit(t, v) for v in reals if v["causality"] == "input") if r})
    out.append("  <TypeDefinitions>")
    out += [f"    <Float64Type{attrs(name=n, unit=u, nominal=k)}/>" for n, u, k in types]
    for e, its in t["items"].items():
        out.append(f"    <EnumerationType{attrs(name=e, description=t['enum_types'].get(e))}>")
        out += [f"      <Item{attrs(name=n, value=k)}/>" for n, k in its]
        out.append("    </EnumerationType>")
    out.append("  </TypeDefinitions>")
    return out + log_categories(3) + experiment(t)


def fmi3_variable(v, derivative_of):
    element = "Enumeration" if v["enum"] != "none" else {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean",
                                                          "String": "String"}[v["type"]]
    a = dict(name=v["name"], valueReference=v["vr"], description=v["plain_description"] or None,
             causality=v["causality"], variability=v["variability"], initial=initial_of(v))
    if element == "Enumeration":
        a["declaredType"] = v["enum"]
    if element in ("Float64", "Int32"):
        a["min"], a["max"] = (v[b] and number(v[b]) for b in ("min", "max"))
    if element == "Float64" and float_type(v):
        a["declaredType"] = float_type(v)[0]
    if element == "Float64" and v["vr"] in derivative_of:
        a["derivative"] = derivative_of[v["vr"]]
    given = v["initial"] == "exact" and v["causality"] in ("parameter", "input", "local")
    if element == "String":
        start = f"<Start{attrs(value=v['start'])}/>" if given else ""
        return f"    <String{attrs(**a)}>{start}</String>" if start else f"    <String{attrs(**a)}/>"
    if given:
        a["start"] = ("true" if float(v["start"]) else "false") if element == "Boolean" else number(v["start"])
    return f"    <{element}{attrs(**a)}/>"


def fmi3_variables(t, args):
    n_vars, n_indicators = len(t["variables"]), t["me"][1]
    bases = sorted([(args.time_vr, 1), (args.derivative_vr_base, n_vars), (args.indicator_vr_base, 1000)])
    if bases[0][0] < n_vars or any(b + n > c for (b, n), (c, _) in zip(bases, bases[1:])):
        fail("--time-vr, --derivative-vr-base, --indicator-vr-base overlap each other or the table's rows")
    derivative_of = {d: s for s, d in t["states"]}
    time = attrs(name="time", valueReference=args.time_vr, description="simulation time", causality="independent",
                 variability="continuous", declaredType="s")
    out = ["  <ModelVariables>", f"    <Float64{time}/>"]
    out += [fmi3_variable(v, derivative_of) for v in t["variables"]]
    for v in t["variables"]:  # the derivatives of the Real inputs, when the model uses them
        if v["type"] == "Real" and v["causality"] == "input" and t["interpolates"]:
            a = dict(name=f"der({v['name']})", valueReference=args.derivative_vr_base + v["vr"],
                     description=f"time derivative of {v['name']}: the input moves on this slope over the next "
                                 f"step (set it after {v['name']}, whose setting resets it to 0)",
                     causality="input", variability="continuous", declaredType=rate_unit(t, v), derivative=v["vr"],
                     start="0")
            out.append(f"    <Float64{attrs(**a)}/>")
    for i in range(n_indicators if t["me"][0] else 0):  # FMI 3.0 lists the event indicators as variables
        a = dict(name=f"event_indicator_{i}", valueReference=args.indicator_vr_base + i,
                 description=f"event indicator {i} of the hybrid automaton (fmi3GetEventIndicators): the mode "
                             f"changes where it crosses zero", causality="local", variability="continuous",
                 initial="calculated")
        out.append(f"    <Float64{attrs(**a)}/>")
    return out + ["  </ModelVariables>"]


def fmi3_structure(t, args):
    """ModelStructure by value reference."""
    by_name = {v["name"]: v for v in t["variables"]}

    def unknown(element, v, with_dependencies=True):
        deps = " ".join(str(d) for d in sorted(by_name[n]["vr"] for n in v["depends"]))
        return f"    <{element}{attrs(valueReference=v['vr'], dependencies=deps if with_dependencies else None)}/>"
    out = ["  <ModelStructure>"] + STRUCTURE_NOTE
    out += [unknown("Output", v) for v in t["variables"] if v["causality"] == "output"]
    out += [unknown("ContinuousStateDerivative", t["variables"][d]) for _, d in t["states"]]
    out += [unknown("InitialUnknown", v, False) for v in initial_unknowns(t)]
    out += [f"    <EventIndicator{attrs(valueReference=args.indicator_vr_base + i)}/>"
            for i in range(t["me"][1] if t["me"][0] else 0)]
    return out + ["  </ModelStructure>"]


def fmi3(t, args):
    return fmi3_header(t, args) + fmi3_variables(t, args) + fmi3_structure(t, args) + ["</fmiModelDescription>"]


# ---- the documentation's variable table -----------------------------------------------------------------

def cell(text):
    return str(text).replace("|", "\\|")


def markdown(t, command):
    """The variables and the ModelStructure of the table as a Markdown page."""
    out = [f"# The variables of {t['model']}", "",
           "Generated from the model's variable table, as its model descriptions are, by", "", f"    {command}", "",
           "(`fmu-test/test_interface.py` fails when this page is not what that command writes). The value",
           "reference of a variable is its row; FMI 3.0 adds `time`, the inputs' derivatives `der(<input>)`",
           "and the event indicators ([fmi3.md](fmi3.md)). What each variable does: [model.md](model.md),",
           "section 5.", "",
           "| value reference | name | type | causality | variability | start | range | unit | description |",
           "|---|---|---|---|---|---|---|---|---|"]
    for v in t["variables"]:
        start = "" if v["initial"] != "exact" else (f'"{v["start"]}"' if v["type"] == "String" else
                                                    ("true" if float(v["start"]) else "false") if v["type"] == "Boolean"
                                                    else number(v["start"]))
        cells = [v["vr"], f"`{v['name']}`", v["type"], v["causality"], v["variability"], start, v["range"], v["unit"],
                 v["description"]]
        out.append("| " + " | ".join(cell(c) for c in cells) + " |")
    out += ["", "## Dependencies (ModelStructure)", "",
            "In Model Exchange each output and state derivative moves at once with the inputs and continuous",
            "states listed (in some mode of the model), and with no other (`fmu-test/test_feedthrough.py`",
            "measures it); initially every unknown depends on every parameter and input. In Co-Simulation an",
            "input set at a communication point acts from the next step on: no output changes before it.", "",
            "| output or derivative | depends on |", "|---|---|"]
    derivatives = {d for _, d in t["states"]}
    for v in t["variables"]:
        if v["causality"] == "output" or v["vr"] in derivatives:
            out.append(f"| `{v['name']}` | " + (", ".join(f"`{d}`" for d in v["depends"]) or "nothing") + " |")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmi", choices=("2", "3"), help="the FMI version of the description")
    ap.add_argument("--markdown", action="store_true", help="write the documentation's variable table instead")
    ap.add_argument("--out", required=True, help="the modelDescription.xml to write")
    ap.add_argument("--time-vr", type=int, help="FMI 3.0: value reference of the independent variable time")
    ap.add_argument("--derivative-vr-base", type=int,
                    help="FMI 3.0: value reference of der(u) for the Real input u in row 0 (row r: base + r)")
    ap.add_argument("--indicator-vr-base", type=int,
                    help="FMI 3.0: value reference of the first event indicator (indicator i: base + i)")
    ap.add_argument("--dump", required=True, nargs="+", help="the command that prints the table")
    args = ap.parse_args()
    if (args.fmi is None) == (not args.markdown):
        fail("give one of --fmi 2, --fmi 3 and --markdown")
    t = parse_dump(run_dump(args.dump), args.dump[-1])
    if args.fmi == "3" and None in (args.time_vr, args.derivative_vr_base, args.indicator_vr_base):
        fail("--fmi 3 needs --time-vr, --derivative-vr-base and --indicator-vr-base")
    if args.markdown:
        lines = markdown(t, f"python cmake/vi_model_description.py --markdown --out {args.out} --dump "
                            f"build/{t['model']}_dump_variables")
    else:
        lines = fmi2(t) if args.fmi == "2" else fmi3(t, args)
    with open(args.out, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
