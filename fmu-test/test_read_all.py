"""Every variable a model description declares can be read, in every interface the FMU offers and in
each state where the standard allows reading (initialization mode, between steps or in continuous time,
in event mode, after termination): the importers that read all variables after initialization (the
Reference FMUs' fmusim does) must be able to run every interface."""
import ctypes
import math

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

from conftest import FMU
from vibroimpact.fmi3 import fmu3_path, run_to_events

PARAMS = dict(contact_model=2, a=1e-4)  # Johnson, shaken: contact, memory and events all in use


def getters(fmu, version):
    if version == 2:
        return {"Real": fmu.getReal, "Integer": fmu.getInteger, "Enumeration": fmu.getInteger,
                "Boolean": fmu.getBoolean, "String": fmu.getString}
    return {"Float64": fmu.getFloat64, "Int32": fmu.getInt32, "Int64": fmu.getInt64,
            "Enumeration": fmu.getInt64, "Boolean": fmu.getBoolean, "String": fmu.getString}


def declared(v):
    """The start value a model description declares, as the getter of its type returns it."""
    if v.type in ("Real", "Float64"):
        return float(v.start)
    if v.type == "Boolean":
        return v.start in ("true", "1")
    if v.type == "String":
        return v.start
    return int(v.start)


def read_every_variable(fmu, md, version):
    """Each declared variable read alone with the getter of its type (fmpy raises on any status but OK):
    {name: value}. Checked: every Real finite; each the same as when all variables of its type are read
    in one call, as fmusim reads them (a value that depended on the other references asked for, or on
    a read before, would differ); every parameter what was set (PARAMS) or else its declared start."""
    get = getters(fmu, version)
    values = {v.name: get[v.type]([v.valueReference])[0] for v in md.modelVariables}
    for v in md.modelVariables:
        if v.type in ("Real", "Float64"):
            assert math.isfinite(values[v.name]), (v.name, values[v.name])
    for kind in {v.type for v in md.modelVariables}:
        of_kind = [v for v in md.modelVariables if v.type == kind]
        together = get[kind]([v.valueReference for v in of_kind])
        assert {v.name: values[v.name] for v in of_kind} == dict(zip([v.name for v in of_kind], together)), kind
    parameters = {v.name: PARAMS.get(v.name, declared(v)) for v in md.modelVariables if v.causality == "parameter"}
    text = {n: x.decode() if isinstance(x, bytes) else x for n, x in values.items()}  # fmpy's FMI 2.0 Strings: bytes
    assert parameters and {n: text[n] for n in parameters} == parameters
    return values


def set_params(fmu, md, version):
    vr = {v.name: v for v in md.modelVariables}
    for name, value in PARAMS.items():
        v = vr[name]
        if isinstance(value, int):
            (fmu.setInteger if version == 2 else fmu.setInt64)([v.valueReference], [value])
        else:
            (fmu.setReal if version == 2 else fmu.setFloat64)([v.valueReference], [value])


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    out = {}
    for version, path in ((2, str(FMU)), (3, str(fmu3_path()))):
        out[version] = (read_model_description(path), extract(path, unzipdir=str(tmp_path_factory.mktemp(f"all{version}"))))
    return out


def test_fmi2_co_simulation_reads_all(fmus):
    md, unzipdir = fmus[2]
    s = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier="VibroImpact")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    set_params(s, md, 2)
    read_every_variable(s, md, 2)
    s.exitInitializationMode()
    read_every_variable(s, md, 2)
    for k in range(20):
        s.doStep(k * 1e-4, 1e-4)
    read_every_variable(s, md, 2)
    s.terminate()
    read_every_variable(s, md, 2)
    s.freeInstance()


@pytest.mark.parametrize("event_mode", [False, True], ids=["step", "event-mode"])
def test_fmi3_co_simulation_reads_all(fmus, event_mode):
    """The event indicators (causality local, <EventIndicator>) included: in Co-Simulation they are the
    guards of the current mode, as in Model Exchange."""
    md, unzipdir = fmus[3]
    s = FMU3Slave(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier="VibroImpact")
    s.instantiate(eventModeUsed=event_mode, earlyReturnAllowed=event_mode)
    s.enterInitializationMode(startTime=0.0)
    set_params(s, md, 3)
    read_every_variable(s, md, 3)
    s.exitInitializationMode()
    if event_mode:
        read_every_variable(s, md, 3)
        while s.updateDiscreteStates()[0]:
            pass
        s.enterStepMode()
    read_every_variable(s, md, 3)
    events, _ = run_to_events(s, 0.0, 5e-3, 1e-4, sample=lambda t: read_every_variable(s, md, 3))
    assert not event_mode or events  # early returns at contact events, read after each
    values = read_every_variable(s, md, 3)
    assert values["event_indicator_0"] > 0.0  # inside the mode, as after any completed step
    s.terminate()
    read_every_variable(s, md, 3)
    s.freeInstance()


@pytest.mark.parametrize("version", [2, 3], ids=["fmi2", "fmi3"])
def test_model_exchange_reads_all(fmus, version):
    md, unzipdir = fmus[version]
    kind = FMU2Model if version == 2 else FMU3Model
    m = kind(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier="VibroImpact")
    m.instantiate()
    if version == 2:
        m.setupExperiment(startTime=0.0)
        m.enterInitializationMode()
    else:
        m.enterInitializationMode(startTime=0.0)
    set_params(m, md, version)
    read_every_variable(m, md, version)
    m.exitInitializationMode()
    read_every_variable(m, md, version)  # event mode
    for _ in range(100):  # the event iteration (the FMU settles in one pass)
        more = m.newDiscreteStates()[0] if version == 2 else m.updateDiscreteStates()[0]
        if not more:
            break
    m.enterContinuousTimeMode()
    n = len(md.derivatives)
    x = (ctypes.c_double * n)()
    m.getContinuousStates(x, n)
    m.setTime(1e-4)
    m.setContinuousStates(x, n)
    read_every_variable(m, md, version)
    m.terminate()
    read_every_variable(m, md, version)
    m.freeInstance()
