"""The FMU's interface: modelDescription.xml against the C variable table (the one source of truth),
fmpy's validator, and the binary's dependencies and exports."""
import pathlib
import subprocess

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
    for sv, (vr, name, typ, enum, caus, var, initial, start, unit, desc) in zip(md.modelVariables, variables):
        where = f"variable {name}"
        assert sv.name == name, where
        assert sv.valueReference == int(vr), where
        assert sv.type == TYPE_OF[typ], where
        assert sv.causality == caus, where
        assert sv.variability == var, where
        assert sv.description == desc, where
        assert (sv.declaredType.name if sv.declaredType else "none") == enum, where
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
    assert sorted(xml_enums) == sorted(enums)


def test_xml_matches_c_table(model_description):
    check_xml_matches_c_table(model_description, "VibroImpact_dump_variables")


def test_xml_at_top_level_is_the_packed_one(fmu_path):
    import zipfile
    with zipfile.ZipFile(fmu_path) as z:
        assert z.read("modelDescription.xml") == (ROOT / "modelDescription.xml").read_bytes()
        assert "binaries/linux64/VibroImpact.so" in z.namelist()


def test_fmpy_validate_finds_no_problem(fmu_path):
    assert validate_fmu(fmu_path) == []


def test_capabilities(model_description):
    cs = model_description.coSimulation
    assert cs.modelIdentifier == "VibroImpact"
    assert cs.canHandleVariableCommunicationStepSize and cs.canInterpolateInputs
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert model_description.defaultExperiment.tolerance is None  # else fmpy always overrides rtol


def test_binary_needs_only_libc_and_libm():
    out = subprocess.run(["readelf", "-d", str(BUILD / "VibroImpact.so")], check=True, capture_output=True,
                         text=True).stdout
    needed = sorted(line.split("[")[1].rstrip("]") for line in out.splitlines() if "(NEEDED)" in line)
    assert needed == ["libc.so.6", "libm.so.6"]


def test_binary_exports_exactly_the_fmi2_functions():
    out = subprocess.run(["nm", "-D", "--defined-only", str(BUILD / "VibroImpact.so")], check=True,
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
        "fmi2GetBooleanStatus", "fmi2GetStringStatus"}
    assert exported == expected
