"""The FMU's interface: modelDescription.xml (generated from the C variable table, the one source of
truth) against that table, the checked-in descriptions against what the build packs, fmpy's validator,
the capability flags, and the binary's dependencies and exports."""
import pathlib
import subprocess
import sys

import pytest

from fmpy.validation import validate_fmu

from conftest import BUILD, ROOT

TYPE_OF = {"Real": "Real", "Integer": "Integer", "Boolean": "Boolean", "Enumeration": "Enumeration", "String": "String"}


def c_table(dump="VibroImpact_dump_variables"):
    out = subprocess.run([str(BUILD / dump)], check=True, capture_output=True, text=True).stdout
    rows = [line.split("\t") for line in out.splitlines()]
    guid = next(r[1] for r in rows if r[0] == "guid")
    variables = [r[1:] for r in rows if r[0] == "var"]
    enums = [(r[1], r[2], int(r[3])) for r in rows if r[0] == "enum"]
    return guid, variables, enums


def check_xml_matches_c_table(md, dump):
    """modelDescription.xml (read by fmpy) against the C table printed by the model's dump tool."""
    guid, variables, enums = c_table(dump)
    assert md.guid == guid
    assert len(md.modelVariables) == len(variables)
    for sv, (vr, name, typ, enum, caus, var, initial, start, lo, hi, unit, desc) in zip(md.modelVariables, variables):
        where = f"variable {name}"
        assert sv.name == name, where
        assert sv.valueReference == int(vr), where
        assert sv.type == TYPE_OF[typ], where
        assert sv.causality == caus, where
        assert sv.variability == var, where
        assert sv.description == desc, where
        if typ == "Enumeration":
            assert sv.declaredType is not None and sv.declaredType.name == enum, where
        else:
            assert sv.declaredType is None, where
        if typ == "Integer" and enum != "none":  # an enumerated option as an Integer (libcosim sees it)
            values = [value for t, _, value in enums if t == enum]
            assert (int(sv.min), int(sv.max)) == (min(values), max(values)), where
        elif typ in ("Real", "Integer"):  # the table's range, as the inclusive bounds FMI declares
            assert (None if sv.min is None else float(sv.min)) == (float(lo) if lo else None), where + " min"
            assert (None if sv.max is None else float(sv.max)) == (float(hi) if hi else None), where + " max"
        if typ == "Real":
            assert (sv.unit or "") == unit, where
        if initial == "exact" and typ == "String":
            assert sv.start == start, where
        elif initial == "exact":
            expected = float(start)
            got = {"true": 1.0, "false": 0.0}.get(sv.start, None) if typ == "Boolean" else float(sv.start)
            assert got == expected, where
        else:
            assert sv.start is None and sv.initial == "calculated", where
    xml_enums = [(t.name, i.name, int(i.value)) for t in md.typeDefinitions for i in t.items]
    declared = {v[3] for v in variables if v[2] == "Enumeration"}
    assert sorted(xml_enums) == sorted(e for e in enums if e[0] in declared)


def test_xml_matches_c_table(model_description):
    check_xml_matches_c_table(model_description, "VibroImpact_dump_variables")


# The attributes the build stamps into the root element (cmake/vi_fmu_stamp.py; fmu-test/test_release.py);
# generationTool too where the FMU carries SUNDIALS (which one: fmu-test/test_sundials.py).
RELEASE_ATTRIBUTES = r'\s+(?:version|generationDateAndTime|copyright|license|generationTool)="[^"]*"'
# The checked-in FMI 2.0 descriptions, where users and scripts read them: the generator's output.
CHECKED_IN = {"VibroImpact": "modelDescription.xml", "LayerTest": "tests/layer_fmu/modelDescription.xml",
              "Track": "examples/vehicle-track/track/modelDescription.xml",
              "Vehicle": "examples/vehicle-track/vehicle/modelDescription.xml"}


@pytest.mark.parametrize("name", sorted(CHECKED_IN))
def test_checked_in_description_is_the_packed_one(name):
    """The packed description is the generated one with the release stamped into its root element; the
    checked-in file is the generated one as it is."""
    import re
    import zipfile
    place = CHECKED_IN[name]
    with zipfile.ZipFile(BUILD / f"{name}.fmu") as z:
        packed = z.read("modelDescription.xml").decode("utf-8")
        assert f"binaries/linux64/{name}.so" in z.namelist()
    root = re.search(r"<fmiModelDescription[^>]*>", packed)
    unstamped = packed[:root.start()] + re.sub(RELEASE_ATTRIBUTES, "", root.group(0)) + packed[root.end():]
    assert len(re.findall(RELEASE_ATTRIBUTES, root.group(0))) == 5
    written = (ROOT / place).read_text(encoding="utf-8")
    written = re.sub(r'\s+generationTool="[^"]*"', "", written, count=1)
    assert unstamped == written, (
        f"{place} is not what the build generates from the table: write it again with\n  python "
        f"cmake/vi_model_description.py --fmi 2 --out {place} --dump build/{name}_dump_variables")


def test_doc_variables_md_is_the_generated_table(tmp_path):
    """doc/variables.md, the documentation's variable table with the dependencies, is what the generator
    writes from the table today."""
    (tmp_path / "doc").mkdir()  # the same --out as the command the page names, in a folder of its own
    subprocess.run([sys.executable, str(ROOT / "cmake" / "vi_model_description.py"), "--markdown", "--out",
                    "doc/variables.md", "--dump", str(BUILD / "VibroImpact_dump_variables")], check=True, cwd=tmp_path,
                   capture_output=True)
    generated = (tmp_path / "doc" / "variables.md").read_text(encoding="utf-8")
    assert (ROOT / "doc" / "variables.md").read_text(encoding="utf-8") == generated, (
        "doc/variables.md is not what the build's table gives: write it again with\n  python "
        "cmake/vi_model_description.py --markdown --out doc/variables.md --dump build/VibroImpact_dump_variables")


@pytest.mark.parametrize("name", sorted(CHECKED_IN))
def test_fmpy_validate_finds_no_problem(name):
    """Every FMI 2.0 FMU of the build, its variable names and ModelStructure included."""
    from fmpy import read_model_description
    from fmpy.validation import validate_model_description
    path = str(BUILD / f"{name}.fmu")
    assert validate_fmu(path) == []
    md = read_model_description(path, validate=True)
    assert validate_model_description(md, validate_variable_names=True, validate_model_structure=True) == []


def test_capabilities(model_description):
    cs, me = model_description.coSimulation, model_description.modelExchange
    assert cs.modelIdentifier == me.modelIdentifier == "VibroImpact"
    assert cs.canHandleVariableCommunicationStepSize and cs.canInterpolateInputs
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate and me.canGetAndSetFMUstate and me.canSerializeFMUstate
    # CVODE and the model allocate with malloc: the importer's memory functions are not the only ones used
    assert cs.canNotUseMemoryManagementFunctions and me.canNotUseMemoryManagementFunctions
    assert me.providesDirectionalDerivative and not cs.providesDirectionalDerivative
    assert not me.completedIntegratorStepNotNeeded and cs.maxOutputDerivativeOrder == 0
    assert not cs.canRunAsynchronuously and not cs.canBeInstantiatedOnlyOncePerProcess
    # the tolerance of rtol = 0; an rtol the user sets wins over whatever an importer passes (test_solver)
    assert float(model_description.defaultExperiment.tolerance) == 1e-6


@pytest.mark.parametrize("name", ["VibroImpact", "LayerTest"])  # every FMU built by vi_add_fmu
def test_binary_needs_only_libc_and_libm(name):
    out = subprocess.run(["readelf", "-d", str(BUILD / f"{name}.so")], check=True, capture_output=True,
                         text=True).stdout
    needed = sorted(line.split("[")[1].rstrip("]") for line in out.splitlines() if "(NEEDED)" in line)
    assert needed == ["libc.so.6", "libm.so.6"]


@pytest.mark.parametrize("name", ["VibroImpact", "LayerTest"])
def test_binary_exports_exactly_the_fmi2_functions(name):
    out = subprocess.run(["nm", "-D", "--defined-only", str(BUILD / f"{name}.so")], check=True,
                         capture_output=True, text=True).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.split()[1] in "TtDdBbRr"}
    expected = {
        "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate", "fmi2FreeInstance",
        "fmi2SetupExperiment", "fmi2EnterInitializationMode", "fmi2ExitInitializationMode", "fmi2Terminate",
        "fmi2Reset", "fmi2GetReal", "fmi2GetInteger", "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal",
        "fmi2SetInteger", "fmi2SetBoolean", "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate",
        "fmi2FreeFMUstate", "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
        "fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives",
        "fmi2DoStep", "fmi2CancelStep", "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
        "fmi2GetBooleanStatus", "fmi2GetStringStatus",
        "fmi2EnterEventMode", "fmi2NewDiscreteStates", "fmi2EnterContinuousTimeMode", "fmi2CompletedIntegratorStep",
        "fmi2SetTime", "fmi2SetContinuousStates", "fmi2GetDerivatives", "fmi2GetEventIndicators",
        "fmi2GetContinuousStates", "fmi2GetNominalsOfContinuousStates"}
    assert exported == expected


def check_model_structure(md):
    """Outputs: every output, with the dependencies it declares; Derivatives: the derivative of every
    state (Model Exchange); InitialUnknowns: every output, calculated parameter and state derivative."""
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    assert [u.variable for u in md.outputs] == outputs
    derivatives = [v for v in md.modelVariables if v.derivative is not None]
    assert [u.variable for u in md.derivatives] == derivatives
    unknowns = [v for v in md.modelVariables if v.causality in ("output", "calculatedParameter") or v in derivatives]
    assert [u.variable for u in md.initialUnknowns] == unknowns  # in the order of the variables
    known = {v.name for v in md.modelVariables if v.causality == "input"} | {v.derivative.name for v in derivatives}
    for u in md.outputs + md.derivatives:  # dependencies on inputs and states only
        assert all(d.name in known for d in u.dependencies or []), u.variable.name


def test_model_structure_declares_the_model_exchange_dependencies(model_description):
    """The force follows the indentation yC - y at once: in Model Exchange F depends directly on the input
    yC_in and the state y, and on v through the damped laws' rate, and on the platform's velocity vC_in there
    when velocity_input is true; the discrete outputs depend on nothing continuous (the Jacobian test in
    test_me_jacobian.py checks every declared pair against the FMU's partial derivatives)."""
    check_model_structure(model_description)
    deps = {u.variable.name: sorted(d.name for d in u.dependencies) for u in model_description.outputs}
    assert deps["F"] == ["F_ext", "v", "vC_in", "y", "yC_in"] and deps["y"] == ["y"] and deps["v"] == ["v"]
    assert deps["mode"] == deps["contact"] == deps["n_impacts"] == []
    der = {u.variable.name: sorted(d.name for d in u.dependencies) for u in model_description.derivatives}
    assert der == {"der_y": ["v"], "der_v": ["F_ext", "v", "vC_in", "y", "yC_in"], "der_W_damping": ["v", "vC_in", "y", "yC_in"]}
    assert deps["F_peak"] == deps["F"] and deps["E_contact"] == ["y", "yC_in"]
    assert deps["W_dissipated"] == ["W_damping", "y", "yC_in"]


def read_all(s, md, variables):
    values = []
    for v in variables:
        get = {"Real": s.getReal, "Integer": s.getInteger, "Enumeration": s.getInteger, "Boolean": s.getBoolean}
        values.append(get[v.type]([v.valueReference])[0])
    return values


def check_declared_independence(md, make_running, changes):
    """For each input: setting it (value and derivative) at a communication point leaves every output
    that does not declare a dependency on it unchanged until the next fmi2DoStep, and the next step
    does feel it (so the check is not vacuous). make_running() -> (instance, time, step); the caller
    frees the instances."""
    outputs = [u.variable for u in md.outputs]
    for name, value in changes.items():
        inp = next(v for v in md.modelVariables if v.name == name)
        # no dependencies attribute (None) means: depends on every input
        free = [u.variable for u in md.outputs if u.dependencies is not None and inp not in u.dependencies]
        assert free, name
        s, t, h = make_running()
        before = read_all(s, md, free)
        s.setReal([inp.valueReference], [value])
        s.setRealInputDerivatives([inp.valueReference], [1], [value / h])
        assert read_all(s, md, free) == before, name
        s.doStep(t, h)
        changed = read_all(s, md, outputs)
        s, t, h = make_running()
        s.doStep(t, h)
        assert read_all(s, md, outputs) != changed, name


def test_outputs_do_not_change_before_the_next_step(model_description, logged, vr):
    from conftest import start

    made = []

    def make_running():
        made.append(logged().instantiate())
        start(made[-1], vr, dict(contact_model=1, a=1e-4))
        for k in range(20):
            made[-1].doStep(k * 1e-4, 1e-4)
        return made[-1], 20e-4, 1e-4

    check_declared_independence(model_description, make_running, {"yC_in": 1e-6, "F_ext": 1e3})
    for s in made:
        s.freeInstance()


def test_doc_model_md_describes_every_variable(model_description):
    """doc/model.md is the user's reference for the interface: every variable of modelDescription.xml
    appears in a table row of its section 5, with its default where it has one."""
    text = (ROOT / "doc" / "model.md").read_text()
    section = text[text.index("## 5. FMI interface"):text.index("## 6.")]
    rows = [line for line in section.splitlines() if line.startswith("| `")]
    for sv in model_description.modelVariables:
        named = [r for r in rows if f"`{sv.name}`" in r.split("|")[1]] + \
                [line for line in section.splitlines() if f"`{sv.name}`" in line and sv.causality == "calculatedParameter"]
        assert named, f"{sv.name} is not described in doc/model.md section 5"
        if sv.causality in ("parameter", "input") and sv.type in ("Real", "Integer") and len(named[0].split("|")) > 4:
            cells = [c.strip() for c in named[0].split("|")]
            names = [n.strip("` ") for n in cells[1].split(",")]
            defaults = [d.strip() for d in cells[3].split(",")]
            if len(defaults) == 1:  # one default for every name of the row (`E1`, `E2` | Pa | 2.1e11)
                defaults *= len(names)
            assert len(defaults) == len(names), f"{sv.name}: {len(names)} names, {len(defaults)} defaults"
            assert float(defaults[names.index(sv.name)]) == float(sv.start), f"default of {sv.name}"
