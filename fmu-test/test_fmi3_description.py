"""The FMI 3.0 model descriptions (generated at build time by cmake/vi_model_description.py from each
model's variable table, as the FMI 2.0 ones are): fmpy validates them, and they say what the FMI 2.0
descriptions say, variable by variable, translated into FMI 3.0 (types, Enumeration items, units,
start values, bounds, ModelStructure, categories), for the contact FMU, the layer's test model and
the vehicle-track example's companions."""
import datetime
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile

import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu, validate_model_description

from conftest import BUILD, ROOT

GENERATOR = ROOT / "cmake" / "vi_model_description.py"
TIME_VR = 2147483647  # VI_FMI3_TIME_VR in cmake/vi_fmu.cmake
DER_BASE = 1073741824  # VI_FMI3_DERIVATIVE_VR_BASE
INDICATOR_BASE = 1610612736  # VI_FMI3_INDICATOR_VR_BASE
MODELS = {"VibroImpact": ROOT / "modelDescription.xml", "LayerTest": ROOT / "tests/layer_fmu/modelDescription.xml",
          "Track": ROOT / "examples/vehicle-track/track/modelDescription.xml",
          "Vehicle": ROOT / "examples/vehicle-track/vehicle/modelDescription.xml"}


def fmu3(name):
    path = BUILD / "fmi3" / f"{name}.fmu"
    if not path.exists():
        pytest.fail(f"{path} is missing: build with cmake --build build")
    return path


@pytest.fixture(scope="module", params=sorted(MODELS))
def pair(request):
    """(name, FMI 2.0 description, FMI 3.0 description) of one model."""
    name = request.param
    return name, read_model_description(str(BUILD / f"{name}.fmu")), read_model_description(str(fmu3(name)))


def enum_items_in_description(text):
    """The "name=value" items the FMI 2.0 description appends to an enumerated Integer's description."""
    m = re.search(r": ((?:\w+=-?\d+)(?:, \w+=-?\d+)*)$", text or "")
    return [(n, int(k)) for n, k in (p.split("=") for p in m.group(1).split(", "))] if m else None


@pytest.mark.parametrize("name", sorted(MODELS))
def test_fmpy_validates_the_fmu(name):
    assert validate_fmu(str(fmu3(name))) == []
    md = read_model_description(str(fmu3(name)), validate=True)
    assert validate_model_description(md, validate_variable_names=True, validate_model_structure=True) == []
    assert md.fmiVersion == "3.0"


def test_identity_capabilities_and_experiment(pair):
    name, md2, md3 = pair
    assert md3.guid == md2.guid  # fmpy reads instantiationToken into guid
    assert md3.modelName == md2.modelName and md3.coSimulation.modelIdentifier == name
    assert (md3.modelExchange is None) == (md2.modelExchange is None) and md3.scheduledExecution is None
    if md3.modelExchange is not None:
        me2, me3 = md2.modelExchange, md3.modelExchange
        assert me3.modelIdentifier == name and me3.canGetAndSetFMUstate and me3.canSerializeFMUstate
        with zipfile.ZipFile(fmu3(name)) as z:  # fmpy 0.3 reads no FMI 3.0 capability names it does not know
            xml3 = ET.fromstring(z.read("modelDescription.xml")).find("ModelExchange")
        assert xml3.get("providesDirectionalDerivatives") == str(me2.providesDirectionalDerivative).lower()
        assert xml3.get("needsCompletedIntegratorStep") == str(me2.needsCompletedIntegratorStep).lower()
    cs = md3.coSimulation
    assert cs.hasEventMode and cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    # only the contact model ends a step at its events (advance_to_event); the others never return early
    assert cs.mightReturnEarlyFromDoStep == (name == "VibroImpact")
    assert cs.canHandleVariableCommunicationStepSize and not cs.providesIntermediateUpdate
    assert not cs.providesDirectionalDerivative and cs.maxOutputDerivativeOrder == 0
    for a in ("startTime", "stopTime", "stepSize", "tolerance"):
        assert getattr(md3.defaultExperiment, a) == getattr(md2.defaultExperiment, a), a
    assert [c.name for c in md3.logCategories] == [c.name.replace("logFmi2Call", "logFmi3Call")
                                                   for c in md2.logCategories]
    # FMI 3.0 also declares s, the unit of the independent variable time
    assert {u.name for u in md3.unitDefinitions} == {u.name for u in md2.unitDefinitions} | {"s"}


def test_the_independent_variable_is_time(pair):
    _, md2, md3 = pair
    time = md3.modelVariables[0]
    assert (time.name, time.causality, time.variability, time.type, time.valueReference) == \
        ("time", "independent", "continuous", "Float64", TIME_VR)
    assert time.start is None
    assert TIME_VR not in {v.valueReference for v in md2.modelVariables}


def test_every_variable_as_in_fmi2(pair):
    name, md2, md3 = pair
    v3s = md3.modelVariables[1:1 + len(md2.modelVariables)]
    assert [v.name for v in v3s] == [v.name for v in md2.modelVariables]
    for v2, v3 in zip(md2.modelVariables, v3s):
        what = f"{name}.{v2.name}"
        for a in ("valueReference", "causality", "variability"):
            assert getattr(v3, a) == getattr(v2, a), (what, a)
        assert v3.initial == v2.initial or (v2.initial is None and v3.initial in (None, "exact")), what
        items2 = enum_items_in_description(v2.description) if v2.type == "Integer" else None
        if v2.type == "Enumeration":
            items2 = [(i.name, int(i.value)) for i in v2.declaredType.items]
        if items2:  # an option or `mode`: an FMI 3.0 Enumeration with the same items, named
            assert v3.type == "Enumeration", what
            assert [(i.name, int(i.value)) for i in v3.declaredType.items] == items2, what
            assert v2.description.startswith(v3.description), what
            if v2.min is not None:
                assert (int(v2.min), int(v2.max)) == (min(k for _, k in items2), max(k for _, k in items2)), what
        else:
            assert v3.type == {"Real": "Float64", "Integer": "Int32"}.get(v2.type, v2.type), what
            assert v3.description == v2.description, what
        if v2.type == "Real":
            assert (v3.declaredType.unit if v3.declaredType else None) == v2.unit, what
            assert (v3.declaredType.nominal if v3.declaredType else None) == v2.nominal, what
        if v2.type in ("Real", "Integer") and not items2:
            for b in ("min", "max"):
                assert (getattr(v3, b) is None) == (getattr(v2, b) is None), (what, b)
                if getattr(v2, b) is not None:
                    assert float(getattr(v3, b)) == float(getattr(v2, b)), (what, b)
        if v2.start is None:
            assert v3.start is None, what
        elif v2.type == "Real":
            assert float(v3.start) == float(v2.start), what
        elif v2.type == "Boolean":
            assert str(v3.start).lower() == str(v2.start).lower(), what
        else:
            assert str(v3.start) == str(v2.start), what


def test_every_real_input_has_its_derivative_after_the_table(pair):
    """FMI 3.0 has no fmi3SetInputDerivatives: der(u) of each Real input u (what fmi2SetRealInputDerivatives
    sets in FMI 2.0, canInterpolateInputs) is an input variable of its own."""
    name, md2, md3 = pair
    inputs = [v for v in md2.modelVariables if v.causality == "input" and v.type == "Real"]
    ders = [v for v in md3.modelVariables if v.name.startswith("der(")]
    if not md2.coSimulation.canInterpolateInputs:  # the companions hold their inputs their own way
        inputs = []
    assert [d.name for d in ders] == [f"der({v.name})" for v in inputs]
    for d, v in zip(ders, inputs):
        assert (d.causality, d.variability, d.type, d.start) == ("input", "continuous", "Float64", "0"), name
        assert d.derivative.name == v.name and d.valueReference == DER_BASE + v.valueReference
        if d.declaredType:
            assert d.declaredType.unit == f"{v.unit}/s"


def test_model_structure_as_in_fmi2(pair):
    name, md2, md3 = pair
    deps = lambda u: None if u.dependencies is None else sorted(d.name for d in u.dependencies)  # noqa: E731
    assert [(u.variable.name, deps(u)) for u in md3.outputs] == [(u.variable.name, deps(u)) for u in md2.outputs]
    assert [u.variable.name for u in md3.initialUnknowns] == [u.variable.name for u in md2.initialUnknowns]
    assert [(u.variable.name, deps(u)) for u in md3.derivatives] == [(u.variable.name, deps(u)) for u in md2.derivatives]
    assert [u.variable.derivative.name for u in md3.derivatives] == [u.variable.derivative.name for u in md2.derivatives]
    # FMI 3.0 lists the event indicators as variables
    n = md2.numberOfEventIndicators if md2.modelExchange else 0
    assert [(u.variable.name, u.variable.valueReference) for u in md3.eventIndicators] == \
        [(f"event_indicator_{i}", INDICATOR_BASE + i) for i in range(n)]
    for u in md3.eventIndicators:
        assert (u.variable.causality, u.variable.variability, u.variable.type) == ("local", "continuous", "Float64")


def generate(tmp_path, version, dump_text):
    """Run the generator on a dump given as text (printed by cat); the completed process."""
    dump = tmp_path / "dump.txt"
    dump.write_text(dump_text)
    fmi3 = ["--time-vr", str(TIME_VR), "--derivative-vr-base", str(DER_BASE), "--indicator-vr-base", str(INDICATOR_BASE)]
    return subprocess.run([sys.executable, str(GENERATOR), "--fmi", version, *(fmi3 if version == "3" else []),
                           "--out", str(tmp_path / "out.xml"), "--dump", "cat", str(dump)], capture_output=True, text=True)


def test_the_generator_refuses_a_table_it_cannot_describe(tmp_path):
    """The table is the one source: a dependency on something that is no input or state, on a name that
    is no variable, or a dependency of a parameter, and a unit without base units stop the build with
    a message naming the variable, instead of giving a description of something else."""
    dump = subprocess.run([str(BUILD / "VibroImpact_dump_variables")], check=True, capture_output=True,
                          text=True).stdout
    vr = {line.split("\t")[2]: line.split("\t")[1] for line in dump.splitlines() if line.startswith("var\t")}
    cases = {"F": dump.replace(f"depends\t{vr['F']}\tyC_in F_ext y v vC_in\n", f"depends\t{vr['F']}\tyC_in m y\n"),
             "delta": dump.replace(f"depends\t{vr['delta']}\tyC_in y\n", f"depends\t{vr['delta']}\tyC_in z\n"),
             "m": dump.replace("\nenumtype", f"\ndepends\t{vr['m']}\ty\nenumtype", 1),
             "W_plastic": dump.replace('\tJ\tplastic work', '\tfurlong\tplastic work')}
    for what, text in cases.items():
        assert text != dump, what
        for version in ("2", "3"):
            run = generate(tmp_path, version, text)
            assert run.returncode != 0, what
            assert run.stderr.startswith(f"vi_model_description.py: {what}:"), (what, run.stderr)


@pytest.mark.parametrize("version", ["2", "3"])
def test_the_packed_description_is_the_generated_one_stamped(tmp_path, version):
    dump = subprocess.run([str(BUILD / "VibroImpact_dump_variables")], check=True, capture_output=True,
                          text=True).stdout
    assert generate(tmp_path, version, dump).returncode == 0
    stamped = tmp_path / "stamped.xml"
    packed = tmp_path / "packed"
    shutil.unpack_archive(str(fmu3("VibroImpact") if version == "3" else BUILD / "VibroImpact.fmu"), str(packed), "zip")
    root = ET.parse(packed / "modelDescription.xml").getroot()
    epoch = int(datetime.datetime.strptime(root.get("generationDateAndTime"), "%Y-%m-%dT%H:%M:%S%z").timestamp())
    stamp = [sys.executable, str(ROOT / "cmake" / "vi_fmu_stamp.py"), "--xml", str(tmp_path / "out.xml"),
             "--version", root.get("version"), "--license", str(ROOT / "LICENSE"), "--out", str(stamped),
             f"--source-date-epoch={epoch}", f"--generation-tool={root.get('generationTool')}"]
    subprocess.run(stamp, check=True, env={"PATH": os.environ["PATH"]})  # no SOURCE_DATE_EPOCH of the caller
    assert (packed / "modelDescription.xml").read_text() == stamped.read_text()
