"""Write the FMI 3.0 modelDescription.xml of a model on the generic FMI layer (include/vi_fmu.h).

Run at build time by vi_add_fmu(... FMI_VERSIONS 3) (cmake/vi_fmu.cmake):

    python vi_fmi3_description.py --fmi2 modelDescription.xml --time-vr VR --derivative-vr-base BASE
                                  --indicator-vr-base INDICATOR_BASE --out OUT.xml --dump [EMULATOR...] DUMP

DUMP is the model's <Name>_dump_variables (tests/dump_variables.c; run under EMULATOR when cross
compiling), which prints the variable table, the one source of truth for the variables. From it
come every variable (name, value reference, type, causality, variability, initial, start, min,
max, unit, description), the Enumeration types with their items, the instantiationToken (the table's GUID)
and the lists of ModelStructure. What the table does not hold comes from the model's FMI 2.0
description (as stamped with the release by cmake/vi_fmu_stamp.py), which the FMI 2.0 tests check
against the same table: the model's name, description, version, generation date, copyright and
licence, the unit definitions, the default experiment, the log categories' descriptions, the
descriptions of enumeration types, the nominal values, Model Exchange (its capabilities, the state
derivatives, the number of event indicators), and which variables each unknown depends on.

Types: Real -> Float64 (its unit and nominal value through a Float64Type), Boolean -> Boolean,
String -> String, Integer -> Int32, and Integer or Enumeration rows whose enum column names an
enumeration -> Enumeration of that type (read and written as Int64 through the FMI 3.0 API).
FMI 3.0 also asks for the independent variable: `time`, with the value reference VR that the face
answers to (VI_FMI3_TIME_VR in cmake/vi_fmu.cmake, given to both). When the FMI 2.0 description
has Model Exchange, so has this one, and FMI 3.0 lists the event indicators as variables:
event_indicator_<i> at value reference INDICATOR_BASE + i (VI_FMI3_INDICATOR_VR_BASE). FMI 3.0 has no call for input
derivatives: when the FMI 2.0 description says canInterpolateInputs="true", each Real input `u` of
row r gets an input `der(u)` (derivative="r") at value reference BASE + r
(VI_FMI3_DERIVATIVE_VR_BASE), which the face maps onto the input's derivative. The capabilities are those of
the FMI 3.0 face (src/vi_fmi3.c), written once here.
"""
import argparse
import subprocess
import sys
import xml.etree.ElementTree as ET
from xml.sax.saxutils import quoteattr

# The FMI 3.0 face's Co-Simulation capabilities (src/vi_fmi3.c implements exactly these).
CO_SIMULATION = dict(
    needsExecutionTool="false",
    canBeInstantiatedOnlyOncePerProcess="false",
    canGetAndSetFMUState="true",
    canSerializeFMUState="true",
    providesDirectionalDerivatives="false",
    providesAdjointDerivatives="false",
    canHandleVariableCommunicationStepSize="true",
    maxOutputDerivativeOrder="0",
    providesIntermediateUpdate="false",
    mightReturnEarlyFromDoStep="true",
    canReturnEarlyAfterIntermediateUpdate="false",
    hasEventMode="true",
    providesEvaluateDiscreteStates="false",
)

# ... and Model Exchange capabilities (with those the FMI 2.0 description states: directional
# derivatives, completed integrator step).
MODEL_EXCHANGE = dict(
    needsExecutionTool="false",
    canBeInstantiatedOnlyOncePerProcess="false",
    canGetAndSetFMUState="true",
    canSerializeFMUState="true",
    providesAdjointDerivatives="false",
    providesEvaluateDiscreteStates="false",
)

# The log category of FMI calls is named after the version; every other category keeps its name.
CALL_CATEGORY = {"logFmi2Call": "logFmi3Call"}


def fail(msg):
    sys.exit(f"vi_fmi3_description.py: {msg}")


def read_table(command):
    """The dump: guid, variables (dicts) in value-reference order, enumeration items by type."""
    guid, variables, items = None, [], {}
    run = subprocess.run(command, stdout=subprocess.PIPE, universal_newlines=True, encoding="utf-8")
    if run.returncode != 0:
        fail(f"{' '.join(command)} failed with exit code {run.returncode}")
    path = command[-1]
    for line in run.stdout.splitlines():
        cols = line.split("\t")
        if cols[0] == "guid":
            guid = cols[1]
        elif cols[0] == "var":
            vr, name, typ, enum, caus, var, init, start, lo, hi, unit, desc = cols[1:13]
            variables.append(dict(vr=int(vr), name=name, type=typ, enum=enum, causality=caus, variability=var,
                                  initial=init, start=start, min=lo or None, max=hi or None, unit=unit,
                                  description=desc))
        elif cols[0] == "enum":
            items.setdefault(cols[1], []).append((cols[2], int(cols[3])))
    if guid is None or not variables:
        fail(f"{path}: no guid or no variables (is it the output of <Name>_dump_variables?)")
    for i, v in enumerate(variables):
        if v["vr"] != i:
            fail(f"{path}: value reference {v['vr']} in row {i}")
        if v["enum"] != "none":
            if v["enum"] not in items:
                fail(f"{v['name']}: enumeration {v['enum']} has no items")
            # the dump appends the items to an Integer's description, as the FMI 2.0 XML does
            suffix = ": " + ", ".join(f"{n}={k}" for n, k in items[v["enum"]])
            if v["description"].endswith(suffix):
                v["description"] = v["description"][: -len(suffix)]
    return guid, variables, items


def number(text):
    """A start value as the shortest text that reads back as the same double (integers plain)."""
    x = float(text)
    return str(int(x)) if x.is_integer() and abs(x) < 2**53 else repr(x)


def attrs(**kw):
    return "".join(f" {k}={quoteattr(str(v))}" for k, v in kw.items() if v is not None)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmi2", required=True, help="the model's FMI 2.0 modelDescription.xml")
    ap.add_argument("--time-vr", required=True, type=int, help="value reference of the independent variable time")
    ap.add_argument("--derivative-vr-base", required=True, type=int,
                    help="value reference of der(u) for the Real input u in row 0 (row r: base + r)")
    ap.add_argument("--indicator-vr-base", required=True, type=int,
                    help="value reference of the first event indicator (Model Exchange; indicator i: base + i)")
    ap.add_argument("--out", required=True, help="the FMI 3.0 modelDescription.xml to write")
    ap.add_argument("--dump", required=True, nargs="+", help="the command that prints the table")
    args = ap.parse_args()

    guid, variables, items = read_table(args.dump)
    md2 = ET.parse(args.fmi2).getroot()
    if md2.get("guid") != guid:
        fail(f"{args.fmi2}: guid {md2.get('guid')} is not the table's {guid}")
    cs2 = md2.find("CoSimulation")
    if cs2 is None:
        fail(f"{args.fmi2}: no CoSimulation element")
    sv2 = md2.findall("ModelVariables/ScalarVariable")
    if [s.get("name") for s in sv2] != [v["name"] for v in variables]:
        fail(f"{args.fmi2}: its variables are not the table's (run the FMI 2.0 interface tests)")
    vr_of_index = {i + 1: int(s.get("valueReference")) for i, s in enumerate(sv2)}

    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           "<!-- Generated by cmake/vi_fmi3_description.py from the variable table and the FMI 2.0",
           "     description of the same model: do not edit. -->"]
    root = dict(fmiVersion="3.0", modelName=md2.get("modelName"),
                description=md2.get("description") and md2.get("description").replace("fmi2", "fmi3"),
                version=md2.get("version"), author=md2.get("author"), copyright=md2.get("copyright"),
                license=md2.get("license"), generationTool="VibroImpact cmake/vi_fmi3_description.py",
                generationDateAndTime=md2.get("generationDateAndTime"),
                instantiationToken=guid, variableNamingConvention=md2.get("variableNamingConvention"))
    out.append(f"<fmiModelDescription{attrs(**root)}>")
    me2 = md2.find("ModelExchange")
    if me2 is not None:  # the model offers Model Exchange (the layer's ME hooks)
        needs_step = "true" if me2.get("completedIntegratorStepNotNeeded", "false") == "false" else "false"
        me = attrs(modelIdentifier=me2.get("modelIdentifier"), **MODEL_EXCHANGE,
                   providesDirectionalDerivatives=me2.get("providesDirectionalDerivative", "false"),
                   needsCompletedIntegratorStep=needs_step)
        out.append(f"  <ModelExchange{me}/>")
    out.append(f"  <CoSimulation{attrs(modelIdentifier=cs2.get('modelIdentifier'), **CO_SIMULATION)}/>")

    units = md2.find("UnitDefinitions")
    unit_names = {u.get("name") for u in md2.findall("UnitDefinitions/Unit")}
    if units is not None and len(units):
        out.append("  <UnitDefinitions>")
        for u in units:
            out.append("    " + ET.tostring(u, encoding="unicode").strip())
        out.append("  </UnitDefinitions>")

    # Units and nominal values reach the variables through Float64Types, one per unit (named as the
    # unit) and one per unit and nominal value (as the FMI 3.0 Reference FMUs declare them; some
    # importers read no unit or nominal attribute on a variable itself). The unit of der(u) is u's
    # unit per second where the model defines that unit.
    rate_of = {v["name"]: v["unit"] + "/s" for v in variables if v["type"] == "Real" and v["causality"] == "input"
               and v["unit"] and v["unit"] + "/s" in unit_names}
    nominal_of = {v["name"]: s[0].get("nominal") for v, s in zip(variables, sv2)
                  if v["type"] == "Real" and len(s) and s[0].get("nominal")}

    def float_type(v):
        """(name, unit, nominal) of the Float64Type of the Real row v, or None."""
        unit, nominal = v["unit"] or None, nominal_of.get(v["name"])
        if nominal:
            return (f"{unit} (nominal {nominal})" if unit else f"nominal {nominal}"), unit, nominal
        return (unit, unit, None) if unit else None
    float_types = sorted({float_type(v) for v in variables if v["type"] == "Real" and float_type(v)}
                         | {(u, u, None) for u in rate_of.values()}
                         | ({("s", "s", None)} if "s" in unit_names else set()))
    enum_desc = {s.get("name"): s.get("description") for s in md2.findall("TypeDefinitions/SimpleType")}
    if items or float_types:
        out.append("  <TypeDefinitions>")
        for name, unit, nominal in float_types:
            out.append(f"    <Float64Type{attrs(name=name, unit=unit, nominal=nominal)}/>")
        for t, its in items.items():
            out.append(f"    <EnumerationType{attrs(name=t, description=enum_desc.get(t))}>")
            for n, k in its:
                out.append(f"      <Item{attrs(name=n, value=k)}/>")
            out.append("    </EnumerationType>")
        out.append("  </TypeDefinitions>")

    cats = md2.findall("LogCategories/Category")
    if cats:
        out.append("  <LogCategories>")
        for c in cats:
            name = CALL_CATEGORY.get(c.get("name"), c.get("name"))
            desc = c.get("description")
            out.append(f"    <Category{attrs(name=name, description=desc and desc.replace('fmi2', 'fmi3'))}/>")
        out.append("  </LogCategories>")

    de = md2.find("DefaultExperiment")
    if de is not None:
        out.append(f"  <DefaultExperiment{attrs(**de.attrib)}/>")

    out.append("  <ModelVariables>")
    bases = sorted([(args.time_vr, 1), (args.derivative_vr_base, len(variables)), (args.indicator_vr_base, 1000)])
    if bases[0][0] < len(variables) or any(b + n > c for (b, n), (c, _) in zip(bases, bases[1:])):
        fail(f"--time-vr, --derivative-vr-base, --indicator-vr-base overlap each other or the table's rows")
    time = attrs(name="time", valueReference=args.time_vr, description="simulation time", causality="independent",
                 variability="continuous", declaredType="s" if "s" in unit_names else None)
    out.append(f"    <Float64{time}/>")
    for v, s in zip(variables, sv2):
        t2 = s[0] if len(s) else None  # the FMI 2.0 type element (bounds)
        enum = v["enum"] if v["enum"] != "none" else None
        element = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String",
                   "Enumeration": "Enumeration"}[v["type"]]
        if enum:
            element = "Enumeration"
        given = v["initial"] == "exact" and v["causality"] in ("parameter", "input")
        a = dict(name=v["name"], valueReference=v["vr"], description=v["description"] or None,
                 causality=v["causality"], variability=v["variability"],
                 initial=v["initial"] if v["causality"] in ("output", "calculatedParameter", "local") else None)
        if element == "Enumeration":
            a["declaredType"] = enum
        if element in ("Float64", "Int32"):
            a["min"], a["max"] = (v[b] and number(v[b]) for b in ("min", "max"))
        if element == "Float64" and float_type(v):
            a["declaredType"] = float_type(v)[0]
        if element == "Float64" and t2 is not None and t2.get("derivative"):
            a["derivative"] = vr_of_index[int(t2.get("derivative"))]
        if element == "String":
            if given:
                out.append(f"    <String{attrs(**a)}><Start{attrs(value=v['start'])}/></String>")
            else:
                out.append(f"    <String{attrs(**a)}/>")
            continue
        if given:
            a["start"] = ("true" if float(v["start"]) else "false") if element == "Boolean" else number(v["start"])
        out.append(f"    <{element}{attrs(**a)}/>")
    for v in variables:  # the derivatives of the Real inputs, when the model uses them
        if v["type"] == "Real" and v["causality"] == "input" and cs2.get("canInterpolateInputs") == "true":
            a = dict(name=f"der({v['name']})", valueReference=args.derivative_vr_base + v["vr"],
                     description=f"time derivative of {v['name']}: the input moves on this slope over the next "
                                 f"step (set it after {v['name']}, whose setting resets it to 0)",
                     causality="input", variability="continuous", declaredType=rate_of.get(v["name"]), derivative=v["vr"],
                     start="0")
            out.append(f"    <Float64{attrs(**a)}/>")
    n_indicators = int(md2.get("numberOfEventIndicators", "0")) if me2 is not None else 0
    for i in range(n_indicators):  # Model Exchange: FMI 3.0 lists the event indicators as variables
        a = dict(name=f"event_indicator_{i}", valueReference=args.indicator_vr_base + i,
                 description=f"event indicator {i} of the hybrid automaton (fmi3GetEventIndicators): the mode "
                             f"changes where it crosses zero", causality="local", variability="continuous",
                 initial="calculated")
        out.append(f"    <Float64{attrs(**a)}/>")
    out.append("  </ModelVariables>")

    # ModelStructure: the lists follow from the table (outputs; initially the outputs, calculated
    # parameters and state derivatives that are calculated); the dependencies of each come from the FMI 2.0 description, translated from its
    # indices to value references.
    deps2 = {}
    for kind in ("Outputs", "Derivatives", "InitialUnknowns"):
        for u in md2.findall(f"ModelStructure/{kind}/Unknown"):
            deps2[(kind, vr_of_index[int(u.get("index"))])] = u
    outputs = [v["vr"] for v in variables if v["causality"] == "output"]
    derivatives = {int(s.get("valueReference")) for s in sv2 if len(s) and s[0].get("derivative")}
    initial = [v["vr"] for v in variables if v["initial"] in ("calculated", "approx")
               and (v["causality"] in ("output", "calculatedParameter") or v["vr"] in derivatives)]
    for kind, vrs in (("Outputs", outputs), ("InitialUnknowns", initial)):
        listed = sorted(vr for k, vr in deps2 if k == kind)
        if listed != sorted(vrs):
            fail(f"{args.fmi2}: ModelStructure/{kind} lists value references {listed}, the table gives {vrs}")

    def unknown(element, kind, vr):
        u = deps2[(kind, vr)]
        d = u.get("dependencies")
        a = dict(valueReference=vr)
        if d is not None:
            a["dependencies"] = " ".join(str(vr_of_index[int(i)]) for i in d.split())
            if u.get("dependenciesKind") is not None:
                a["dependenciesKind"] = u.get("dependenciesKind")
        return f"    <{element}{attrs(**a)}/>"

    state_derivatives = [vr for k, vr in deps2 if k == "Derivatives"]  # in the FMI 2.0 order
    if sorted(state_derivatives) != sorted(derivatives & set(state_derivatives)) or \
            (me2 is not None and sorted(state_derivatives) != sorted(derivatives)):
        fail(f"{args.fmi2}: ModelStructure/Derivatives {state_derivatives} are not the variables with a derivative "
             f"attribute {sorted(derivatives)}")
    out.append("  <ModelStructure>")
    out += [unknown("Output", "Outputs", vr) for vr in outputs]
    out += [unknown("ContinuousStateDerivative", "Derivatives", vr) for vr in state_derivatives]
    out += [unknown("InitialUnknown", "InitialUnknowns", vr) for vr in initial
            if me2 is not None or vr not in derivatives]
    out += [f"    <EventIndicator{attrs(valueReference=args.indicator_vr_base + i)}/>" for i in range(n_indicators)]
    out.append("  </ModelStructure>")
    out.append("</fmiModelDescription>")
    text = "\n".join(out) + "\n"
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(text)


if __name__ == "__main__":
    main()
