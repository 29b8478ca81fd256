"""Checked FMU state buffers: a serialized state carries a header (magic, version,
size, model, FMI state, stop time) and a checksum built on FNV-1a's round; every field is validated before a
state is used, and the first bad one is named. The tests alter states the way a broken file, a
wrong file or a memory fault would, and recompute the checksum themselves (an independent
implementation below) where they test the field checks behind it."""
import ctypes
import math
import struct

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from conftest import start
from test_layer import layer, layer_dir, layer_md, lvr  # noqa: F401 (fixtures)
from test_layer import start as layer_start

ERROR = 3
HEADER = struct.Struct("<IIQQIIdQ")  # magic, version, size, model, fmu_state, stop_time_defined, stop_time, checksum
CHECKSUM_AT = HEADER.size - 8


MASK = 0xFFFFFFFFFFFFFFFF


def fnv_round(h, w):
    """FNV-1a's round on a 64-bit word (xor, multiply by the FNV prime), then a xor-shift."""
    h = ((h ^ w) * 0x100000001B3) & MASK
    return h ^ (h >> 32)


def words_hash(data, h):
    """The documented checksum (src/fmi/vi_fmi2.c): four lanes over 32-byte blocks of little-endian
    words, folded with the length, then the tail bytes."""
    lanes = [fnv_round(h, k) for k in range(4)]
    n = len(data) - len(data) % 32
    for i in range(0, n, 32):
        for k in range(4):
            lanes[k] = fnv_round(lanes[k], int.from_bytes(data[i + 8 * k:i + 8 * k + 8], "little"))
    h = fnv_round(lanes[0], len(data))
    for k in range(1, 4):
        h = fnv_round(h, lanes[k])
    for b in data[n:]:
        h = fnv_round(h, b)
    return h


def fnv1a(data, h=0xCBF29CE484222325):
    """The checksum of a state: over the header (checksum field 0), then over the model's block."""
    return words_hash(data[HEADER.size:], words_hash(data[:HEADER.size], h))


def reseal(blob):
    """The same bytes with a correct checksum."""
    b = bytearray(blob)
    b[CHECKSUM_AT:CHECKSUM_AT + 8] = bytes(8)
    b[CHECKSUM_AT:CHECKSUM_AT + 8] = struct.pack("<Q", fnv1a(bytes(b)))
    return bytes(b)


def refused(log, s, blob, *words):
    n = len(log.messages)
    with pytest.raises(FMICallException):
        s.deSerializeFMUstate(blob)
    new = [m for st, _, m in log.messages[n:] if st == ERROR]
    assert new and all(w in new[-1] for w in words), new
    return new[-1]


@pytest.fixture
def blob_and_slave(logged, vr):
    """A serialized running state (Hertz, bouncing, 2 ms) and the instance (log, slave) it came from."""
    log = logged()
    s = log.instantiate()
    start(s, vr, dict(contact_model=1, a=1e-4))
    for k in range(20):
        s.doStep(k * 1e-4, 1e-4)
    blob = s.serializeFMUstate(s.getFMUstate())
    yield blob, log, s
    s.freeInstance()


def test_the_checksum_is_the_documented_fnv1a(blob_and_slave):
    blob, _, _ = blob_and_slave
    magic, version, size, model, fmu_state, _, _, check = HEADER.unpack_from(blob)
    assert (magic, size) == (0x554D4956, len(blob))
    assert reseal(blob) == blob  # the FMU's checksum is the documented one, over all bytes with the field as 0


def test_every_single_bit_flip_is_refused(blob_and_slave):
    blob, log, s = blob_and_slave
    accepted = []
    for bit in range(8 * len(blob)):
        b = bytearray(blob)
        b[bit // 8] ^= 1 << (bit % 8)
        try:
            s.freeFMUstate(s.deSerializeFMUstate(bytes(b)))
            accepted.append(bit)
        except FMICallException:
            pass
    assert accepted == [], f"{len(accepted)} of {8 * len(blob)} flips accepted"
    assert any("checksum" in m for _, _, m in log.messages)
    s.freeFMUstate(s.deSerializeFMUstate(blob))  # the intact state still is


def test_wrong_size_version_and_model_are_refused(blob_and_slave, layer_blob):
    blob, log, s = blob_and_slave
    refused(log, s, blob[:-1], "size")
    refused(log, s, blob + b"\0", "size")
    refused(log, s, blob[:10], "size")
    v = bytearray(blob)
    v[4] += 1
    refused(log, s, reseal(v), "version")
    refused(log, s, layer_blob, "another model")


def test_header_fields_are_validated(blob_and_slave):
    blob, log, s = blob_and_slave
    head = list(HEADER.unpack_from(blob))
    assert head[5:7] == [0, 0.0]  # taken without a stop time
    for field, value, words in ((4, 0xFF, "fmu_state = 255"), (4, 0, "fmu_state = 0"), (5, 2, "stop_time"),
                                (6, math.nan, "stop_time"), (5, 1, None)):
        h = head.copy()
        h[field] = value
        if field == 6:
            h[5] = 1
        b = reseal(HEADER.pack(*h) + blob[HEADER.size:])
        if words:
            refused(log, s, b, words)
        else:
            # a valid header: a stop time defined at 0 s is accepted, restored, and binds the next step
            state = s.deSerializeFMUstate(b)
            s.setFMUstate(state)
            s.freeFMUstate(state)
            n = len(log.messages)
            with pytest.raises(FMICallException):
                s.doStep(2e-3, 1e-4)
            new = [m for st, _, m in log.messages[n:] if st == ERROR]
            assert new == ["fmi2DoStep: the step to 0.0020999999999999999 passes the stop time 0"], new


def find_double(blob, x):
    at = blob.find(struct.pack("<d", x), HEADER.size)
    assert at > 0
    return at


def test_non_finite_parameter_and_bad_boolean_and_unterminated_string_are_named(logged, vr):
    log = logged()
    s = log.instantiate()
    s.setReal([vr["m"]], [407.7471234])  # a value that occurs once in the state
    s.setBoolean([vr["moving_contact"]], [True])
    s.setString([vr["profile_file"]], ["p" * 16])
    blob = s.serializeFMUstate(s.getFMUstate())
    at = find_double(blob, 407.7471234)
    b = bytearray(blob)
    b[at:at + 8] = struct.pack("<d", math.nan)
    refused(log, s, reseal(b), "m = nan is not finite")
    b = bytearray(blob)
    b[at:at + 8] = struct.pack("<d", math.inf)
    refused(log, s, reseal(b), "m = inf")
    at = blob.find(b"p" * 16)
    b = bytearray(blob)
    b[at:at + 1024] = b"q" * 1024
    refused(log, s, reseal(b), "profile_file", "terminated")
    s.freeInstance()


def test_non_finite_input_derivative_is_named(logged, vr):
    """An input's derivative (fmi2SetRealInputDerivatives) is part of the state and checked like a value."""
    log = logged()
    s = log.instantiate()
    start(s, vr, dict(contact_model=1))
    s.setRealInputDerivatives([vr["yC_in"]], [1], [0.0123456789])  # a value that occurs once in the state
    blob = s.serializeFMUstate(s.getFMUstate())
    at = find_double(blob, 0.0123456789)
    b = bytearray(blob)
    b[at:at + 8] = struct.pack("<d", math.nan)
    refused(log, s, reseal(b), "derivative of yC_in = nan is not finite")
    s.freeInstance()


def test_enumerations_out_of_their_items_are_named(logged, vr):
    """fmi2SetInteger refuses a value that is not an item (test_ranges.py), so a state holding one
    is corruption."""
    log = logged()
    s = log.instantiate()
    blobs = []
    for law in (1, 3):
        s.reset()
        start(s, vr, dict(contact_model=law))
        blobs.append(bytearray(s.serializeFMUstate(s.getFMUstate())))
    first = next(i for i in range(HEADER.size, len(blobs[0])) if blobs[0][i] != blobs[1][i])
    blobs[0][first] = 7  # contact_model: the first field in which the two states differ
    refused(log, s, reseal(blobs[0]), "contact_model = 7")
    s.freeInstance()


def test_set_fmu_state_refuses_a_state_altered_in_memory_and_the_instance_goes_on(blob_and_slave, vr):
    blob, log, s = blob_and_slave
    state = s.deSerializeFMUstate(blob)
    addr = state.value + HEADER.size + 100
    ctypes.memset(addr, ctypes.c_ubyte.from_address(addr).value ^ 0x10, 1)
    with pytest.raises(FMICallException):
        s.setFMUstate(state)
    assert any(st == ERROR and "fmi2SetFMUstate" in m and "checksum" in m for st, _, m in log.messages)
    s.doStep(20e-4, 1e-4)  # refused before anything was overwritten: the instance goes on
    assert np.isfinite(s.getReal([vr["y"]])[0])
    s.freeFMUstate(state)


# ---- the model's own fields (state_check hook), on LayerTest whose layout is known ----

@pytest.fixture
def layer_blob(layer, lvr):
    _, s = layer()
    layer_start(s, lvr)
    s.doStep(0.0, 0.5)
    return s.serializeFMUstate(s.getFMUstate())


def test_model_fields_checked_by_the_model_hook(layer, lvr, layer_blob):
    log, s = layer()
    layer_start(s, lvr)
    at = find_double(layer_blob, 0.5)  # t, the first 0.5 after the parameters and inputs
    b = bytearray(layer_blob)
    b[at:at + 8] = struct.pack("<d", math.nan)
    refused(log, s, reseal(b), "t = nan")
    at = find_double(layer_blob, math.exp(-0.5))  # x
    b = bytearray(layer_blob)
    b[at:at + 8] = struct.pack("<d", math.inf)
    refused(log, s, reseal(b), "x = inf")
    s.setFMUstate(s.deSerializeFMUstate(layer_blob))
    assert s.getReal([lvr["x"]])[0] == pytest.approx(math.exp(-0.5), rel=1e-15)
