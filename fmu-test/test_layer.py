"""The generic FMI 2.0 layer (src/fmi/vi_fmu.h, src/fmi/vi_fmi2.c) on LayerTest, its smallest model
(tests/layer_fmu: x' = -k x + u, advanced by its closed form), so that what the layer does is
tested apart from any physics: table against XML, String and tunable parameters, input
derivatives, fmi2Discard and the recovery the standard describes, the error state, the resources
folder."""
import math
import pathlib
import shutil

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2LastSuccessfulTime, fmi2Terminated
from fmpy.validation import validate_fmu

from conftest import BUILD, Logged
from test_interface import check_xml_matches_c_table

LAYER = BUILD / "LayerTest.fmu"
DISCARD, ERROR = 2, 3


@pytest.fixture(scope="module")
def layer_md():
    if not LAYER.exists():
        pytest.fail(f"{LAYER} is missing: build with cmake")
    return read_model_description(str(LAYER))


@pytest.fixture(scope="module")
def layer_dir(tmp_path_factory):
    return extract(str(LAYER), unzipdir=str(tmp_path_factory.mktemp("layer")))


@pytest.fixture(scope="module")
def lvr(layer_md):
    return {v.name: v.valueReference for v in layer_md.modelVariables}


@pytest.fixture
def layer(layer_md, layer_dir):
    made = []

    def make(unzipdir=None, **params):
        log = Logged(layer_md, unzipdir or layer_dir)
        s = log.instantiate()
        made.append(s)
        return log, s

    yield make
    for s in made:
        s.freeInstance()


def start(s, lvr, start_time=0.0, **params):
    s.setupExperiment(startTime=start_time)
    s.enterInitializationMode()
    for name, value in params.items():
        s.setReal([lvr[name]], [float(value)])
    s.exitInitializationMode()


def x_of(s, lvr):
    return s.getReal([lvr["x"]])[0]


def logged_with(log, status, category, *words):
    return any(st == status and cat == category and all(w in m for w in words) for st, cat, m in log.messages)


def test_layer_xml_matches_its_table_and_validates(layer_md):
    check_xml_matches_c_table(layer_md, "LayerTest_dump_variables")
    assert validate_fmu(str(LAYER)) == []


def test_closed_form_steps(layer, lvr):
    _, s = layer()
    start(s, lvr, k=2.0, x0=3.0)
    for n in range(10):
        s.doStep(n * 0.1, 0.1)
    assert x_of(s, lvr) == pytest.approx(3.0 * math.exp(-2.0), rel=1e-12)
    assert s.getInteger([lvr["steps"]]) == [10]


def test_input_value_resets_its_derivative_and_a_derivative_alone_is_applied(layer, lvr):
    """x' = -x + u(t): a ramp u = 1 + 2 t over the first step, a value alone (hold) over the second,
    a derivative alone (ramp from the held value) over the third."""
    _, s = layer()
    start(s, lvr)

    def ref(x0, u, du, h):  # x' = -x + u + du t on [0, h]
        A = u - du
        return A + du * h + (x0 - A) * math.exp(-h)

    s.setReal([lvr["u"]], [1.0])
    s.setRealInputDerivatives([lvr["u"]], [1], [2.0])
    s.doStep(0.0, 0.5)
    x1 = ref(1.0, 1.0, 2.0, 0.5)
    assert x_of(s, lvr) == pytest.approx(x1, rel=1e-12)
    s.setReal([lvr["u"]], [4.0])  # a new value: zero-order hold, the derivative is gone
    s.doStep(0.5, 0.5)
    x2 = ref(x1, 4.0, 0.0, 0.5)
    assert x_of(s, lvr) == pytest.approx(x2, rel=1e-12)
    s.setRealInputDerivatives([lvr["u"]], [1], [-3.0])  # only the derivative changes
    s.doStep(1.0, 0.5)
    assert x_of(s, lvr) == pytest.approx(ref(x2, 4.0, -3.0, 0.5), rel=1e-12)


def test_der_x_is_the_derivative_with_the_input_in_force(layer, lvr):
    """der_x = -k x + u(t), with u(t) the input on the step's ramp: at the end of a step along
    u = 1 + 2 t, u = 2 (not the ramp's start value 1)."""
    _, s = layer()
    start(s, lvr, k=2.0)
    s.setReal([lvr["u"]], [1.0])
    s.setRealInputDerivatives([lvr["u"]], [1], [2.0])
    s.doStep(0.0, 0.5)
    x = x_of(s, lvr)
    assert s.getReal([lvr["der_x"]])[0] == pytest.approx(-2.0 * x + 2.0, rel=1e-12)


def test_string_parameter_start_value_and_length(layer, lvr):
    _, s = layer()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    assert s.getString([lvr["label"]]) == [b"start"]
    assert s.getInteger([lvr["label_length"]]) == [5]
    s.setString([lvr["label"]], ["é" * 10])  # bytes, not characters, count
    assert s.getInteger([lvr["label_length"]]) == [20]
    s.exitInitializationMode()


def test_tunable_parameter_takes_effect_at_the_next_step(layer, lvr):
    log, s = layer()
    start(s, lvr)
    s.doStep(0.0, 0.5)
    x1 = x_of(s, lvr)
    s.setReal([lvr["k"]], [3.0])  # tunable: allowed between steps
    assert x_of(s, lvr) == x1  # nothing happens before the next step
    assert s.getReal([lvr["k_initial"]]) == [1.0]
    s.doStep(0.5, 0.5)
    assert x_of(s, lvr) == pytest.approx(x1 * math.exp(-1.5), rel=1e-12)
    with pytest.raises(FMICallException):
        s.setReal([lvr["x0"]], [5.0])  # fixed: refused after initialization
    assert logged_with(log, ERROR, "logStatusError", "x0", "fixed parameter")


def test_discard_last_successful_time_and_recovery_through_a_saved_state(layer, lvr):
    """fmi2Discard (FMI 2.0, fmi2DoStep): the step stopped early; the master reads
    fmi2LastSuccessfulTime, may read values there, may not step on, and redoes the step from a
    state saved at its start (fmi2SetFMUstate) with smaller steps."""
    log, s = layer()
    start(s, lvr, discard_at=0.25)
    saved = s.getFMUstate()
    with pytest.raises(FMICallException) as e:
        s.doStep(0.0, 0.5)
    assert e.value.status == DISCARD
    assert logged_with(log, DISCARD, "logStatusDiscard", "fmi2DoStep", "0.25")
    assert s.getRealStatus(fmi2LastSuccessfulTime) == 0.25
    assert s.getBooleanStatus(fmi2Terminated) == 0  # the FMU does not ask to end the run
    assert x_of(s, lvr) == pytest.approx(math.exp(-0.25), rel=1e-12)  # values at the last successful time
    with pytest.raises(FMICallException) as e:
        s.doStep(0.25, 0.25)
    assert e.value.status == ERROR
    assert logged_with(log, ERROR, "logStatusError", "fmi2DoStep", "not allowed", "step failed")
    s.setFMUstate(saved)  # back to t = 0, step complete
    s.doStep(0.0, 0.25)
    s.doStep(0.25, 0.25)
    assert x_of(s, lvr) == pytest.approx(math.exp(-0.5), rel=1e-12)
    s.freeFMUstate(saved)


def test_discarded_instance_may_terminate_or_reset(layer, lvr):
    _, s = layer()
    start(s, lvr, discard_at=0.25)
    with pytest.raises(FMICallException):
        s.doStep(0.0, 0.5)
    s.terminate()
    s.reset()
    start(s, lvr)
    s.doStep(0.0, 0.5)
    assert x_of(s, lvr) == pytest.approx(math.exp(-0.5), rel=1e-12)


def test_failed_step_puts_the_instance_in_the_error_state(layer, lvr):
    log, s = layer()
    start(s, lvr, fail_at=0.25)
    with pytest.raises(FMICallException) as e:
        s.doStep(0.0, 0.5)
    assert e.value.status == ERROR
    assert logged_with(log, ERROR, "logStatusError", "fmi2DoStep", "fail_at")
    for call in (lambda: s.doStep(0.0, 0.1), lambda: s.setReal([lvr["u"]], [1.0]), lambda: s.terminate()):
        with pytest.raises(FMICallException):
            call()
    assert logged_with(log, ERROR, "logStatusError", "not allowed", "state 'error'")
    s.reset()
    start(s, lvr)
    s.doStep(0.0, 0.5)


def test_resources_folder_reaches_the_model_decoded(layer, lvr, tmp_path):
    _, s = layer()
    start(s, lvr)
    assert s.getReal([lvr["resource_value"]]) == [0.125]
    odd = tmp_path / "dir with space %41"  # percent-encoded twice over in the URI
    shutil.copytree(pathlib.Path(s.unzipDirectory), odd)
    _, t = layer(unzipdir=str(odd))
    start(t, lvr)
    assert t.getReal([lvr["resource_value"]]) == [0.125]


def test_state_taken_after_a_discard_restores_step_failed(layer, lvr):
    log, s = layer()
    start(s, lvr, discard_at=0.25)
    with pytest.raises(FMICallException):
        s.doStep(0.0, 0.5)
    failed = s.getFMUstate()
    s.reset()
    start(s, lvr)
    s.setFMUstate(failed)
    assert s.getRealStatus(fmi2LastSuccessfulTime) == 0.25
    with pytest.raises(FMICallException):
        s.doStep(0.25, 0.25)
    assert logged_with(log, ERROR, "logStatusError", "fmi2DoStep", "step failed")


def test_layer_model_structure_is_honest(layer_md, layer, lvr):
    from test_interface import check_declared_independence, check_model_structure
    check_model_structure(layer_md)

    def make_running():
        _, s = layer()
        start(s, lvr)
        s.doStep(0.0, 0.5)
        return s, 0.5, 0.25

    check_declared_independence(layer_md, make_running, {"u": 2.0})


def test_checkpoint_hook_runs_before_a_running_state_is_copied(layer, lvr):
    _, s = layer()
    s.setupExperiment(startTime=0.0)
    early = s.getFMUstate()  # not running: no checkpoint
    s.enterInitializationMode()
    s.exitInitializationMode()
    assert s.getReal([lvr["checkpoint_time"]]) == [0.0]
    s.doStep(0.0, 0.5)
    state = s.getFMUstate()
    assert s.getReal([lvr["checkpoint_time"]]) == [0.5]
    s.doStep(0.5, 0.25)
    s.setFMUstate(state)
    assert s.getReal([lvr["checkpoint_time"]]) == [0.5]  # the copy holds what the checkpoint wrote
    s.setFMUstate(early)
    s.enterInitializationMode()
    assert s.getReal([lvr["checkpoint_time"]]) == [0.0]


def raw_layer(layer_md, layer_dir, uri, callbacks=None):
    """A LayerTest instance made with fmi2Instantiate directly (any resource URI); (log, slave)."""
    import ctypes
    log = Logged(layer_md, layer_dir)
    s = log.slave
    s.component = s.fmi2Instantiate(b"raw", 1, layer_md.guid.encode(), uri,
                                    ctypes.byref(callbacks or log.callbacks), 0, 0)
    return log, s


@pytest.mark.parametrize("name, uri_name", [
    ("09AF-afJOjo", "%30%39%41%46%2d%61%66%4A%4F%6a%6f"),  # hex digits 0 9 A F a f, at their bounds
    ("plain", "plain")])
def test_resource_uri_percent_decoding(layer_md, layer_dir, lvr, tmp_path, name, uri_name):
    shutil.copytree(pathlib.Path(layer_dir), tmp_path / name)
    for uri in (f"file://{tmp_path}/{uri_name}/resources", f"file:{tmp_path}/{uri_name}/resources",
                f"file://localhost{tmp_path}/{uri_name}/resources"):
        _, s = raw_layer(layer_md, layer_dir, uri.encode())
        assert s.component
        start(s, lvr)
        assert s.getReal([lvr["resource_value"]]) == [0.125], uri
        s.freeInstance()


@pytest.mark.parametrize("uri", [None, b"", b"http://example.org/resources", b"file://otherhost/tmp/resources",
                                 b"file:relative/resources", b"file:///nonexistent%zz/resources"])
def test_resource_uri_that_names_no_local_folder(layer_md, layer_dir, lvr, uri):
    _, s = raw_layer(layer_md, layer_dir, uri)
    assert s.component  # the model decides: LayerTest reads nothing
    start(s, lvr)
    assert s.getReal([lvr["resource_value"]]) == [-1.0]
    s.freeInstance()


def test_resource_uri_with_another_host_is_not_read_as_a_local_path(layer_md, layer_dir, lvr, tmp_path):
    """file://host/p names p on another host: refused even when //host/p would be a local folder (on
    POSIX "//tmp/x" is "/tmp/x"), where file:///host/p is read."""
    shutil.copytree(pathlib.Path(layer_dir), tmp_path / "copy")
    local = (tmp_path / "copy" / "resources").as_posix()
    assert local.startswith("/") and not local.startswith("//")
    for uri, value in ((f"file://{local}", 0.125), (f"file:/{local}", -1.0)):  # file:/// + p, file:// + p
        _, s = raw_layer(layer_md, layer_dir, uri.encode())
        start(s, lvr)
        assert s.getReal([lvr["resource_value"]]) == [value], uri
        s.freeInstance()


def test_importer_out_of_memory_is_refused(layer_md, layer_dir, lvr):
    """The importer's allocateMemory may return NULL: every allocation is checked."""
    from fmpy import calloc
    from fmpy.fmi2 import fmi2CallbackAllocateMemoryTYPE
    fail = {"on": False}

    def allocate(n, size):
        return None if fail["on"] else calloc(n, size)

    log = Logged(layer_md, layer_dir)
    log.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(allocate)
    fail["on"] = True
    _, s = raw_layer(layer_md, layer_dir, b"file:///tmp", callbacks=log.callbacks)
    assert not s.component
    assert any("out of memory" in m for _, _, m in log.messages)
    fail["on"] = False
    _, s = raw_layer(layer_md, layer_dir, b"file:///tmp", callbacks=log.callbacks)
    start(s, lvr)
    blob = s.serializeFMUstate(s.getFMUstate())
    fail["on"] = True
    for call in (s.getFMUstate, lambda: s.deSerializeFMUstate(blob)):
        with pytest.raises(FMICallException):
            call()
    fail["on"] = False
    assert sum("out of memory" in m for _, _, m in log.messages) == 3
    s.doStep(0.0, 0.5)
    s.freeInstance()
