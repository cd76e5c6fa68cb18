"""The firmware's parser and PWM tables (firmware/src/protocol.c, pwm.c), compiled for the host
with gcc and driven through ctypes with the same test vectors as the Python receiver."""

import ctypes

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tactile_core.device.wire import crc16

from . import wire_vectors as wv
from .firmware_support import build, require
from .test_wire import check_vector

REASONS = ("cobs", "short", "crc", "type", "length", "range")


@pytest.fixture(scope="module")
def shim(tmp_path_factory):
    require("host")
    path = build("host", tmp_path_factory.mktemp("firmware-host"))
    lib = ctypes.CDLL(str(path))
    lib.shim_feed.argtypes = [ctypes.c_char_p, ctypes.c_size_t]
    lib.shim_advance.argtypes = [ctypes.c_uint32]
    lib.shim_replies.argtypes = [ctypes.c_void_p, ctypes.c_size_t]  # written: not c_char_p
    lib.shim_replies.restype = ctypes.c_size_t
    lib.shim_crc16.argtypes = [ctypes.c_char_p, ctypes.c_size_t]
    lib.shim_crc16.restype = ctypes.c_uint16
    lib.shim_cobs_encode.argtypes = [ctypes.c_char_p, ctypes.c_size_t, ctypes.c_void_p]
    lib.shim_levels.argtypes = [ctypes.c_void_p]
    lib.shim_pwm_table.argtypes = [ctypes.c_char_p, ctypes.c_void_p]
    lib.shim_cobs_encode.restype = ctypes.c_size_t
    return lib


def run_c(lib, vector):
    lib.shim_reset()
    applied, replies = [], b""
    levels = ctypes.create_string_buffer(30)
    for kind, arg in vector["steps"]:
        if kind == "feed":
            for i in range(len(arg)):  # byte by byte, as the UART delivers them
                if lib.shim_feed(arg[i : i + 1], 1):
                    lib.shim_levels(levels)
                    applied.append(list(levels.raw))
        elif lib.shim_advance(arg):  # a timed frame came due (one per step in the vectors)
            lib.shim_levels(levels)
            applied.append(list(levels.raw))
        out = ctypes.create_string_buffer(4096)
        n = lib.shim_replies(out, 4096)
        replies += out.raw[:n]
    counters = (ctypes.c_uint32 * 12)()
    lib.shim_counters(counters)
    lib.shim_levels(levels)
    return (
        applied,
        list(levels.raw),
        replies,
        {
            "frames_applied": counters[0],
            "dropped": counters[1],
            "watchdog_trips": counters[2],
            "dropped_by": {r: counters[3 + i] for i, r in enumerate(REASONS) if counters[3 + i]},
        },
    )


@pytest.mark.parametrize("vector", wv.VECTORS, ids=[v["name"] for v in wv.VECTORS])
def test_firmware_parser_meets_the_vectors(shim, vector):
    applied, levels, replies, counters = run_c(shim, vector)
    # The C shim reports applied levels without their sequence numbers; take them from the
    # vector, which the Python receiver checks.
    seqs = [s for s, _ in vector["applied"]]
    check_vector(vector, list(zip(seqs, applied)), levels, replies, counters)
    assert len(applied) == len(vector["applied"])


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=400))
def test_firmware_crc16_and_cobs_match_the_host(shim, data):
    from cobs import cobs

    assert shim.shim_crc16(data, len(data)) == crc16(data)
    out = ctypes.create_string_buffer(len(data) + len(data) // 254 + 2)
    n = shim.shim_cobs_encode(data, len(data), out)
    assert out.raw[:n] == cobs.encode(data) + b"\x00"


@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(0, 22), min_size=30, max_size=30))
def test_firmware_pwm_table_gives_each_channel_its_duty(shim, levels):
    table = ctypes.create_string_buffer(22 * 4)
    shim.shim_pwm_table(bytes(levels), table)
    slots = np.frombuffer(table.raw, dtype=np.uint8).reshape(22, 4)  # slot, port
    for channel, level in enumerate(levels):
        port, bit = divmod(channel, 8)  # the README's pin map: 8 channels per port, A C L K
        on = (slots[:, port] >> bit) & 1
        assert on.sum() == level  # duty = level / 22 of the period
        assert (on[:level] == 1).all()  # on from the start of the period
    assert not (slots[:, 3] & 0xC0).any()  # PORTK bits 6 and 7 are not channels
