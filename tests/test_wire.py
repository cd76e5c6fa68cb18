"""Wire format 2: CRC-16 and COBS worked by hand, every message type, bad messages, and the
shared test vectors run against the Python receiver (the firmware's C parser runs them in
test_firmware.py)."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tactile_core.device.array import ArrayModel
from tactile_core.device.wire import (
    REASONS,
    ClockReply,
    Frame,
    FrameReader,
    Hello,
    Info,
    MessageError,
    MessageReader,
    Query,
    Status,
    Timed,
    clock_diff,
    crc16,
    decode_frame,
    decode_message,
    encode_clock,
    encode_clock_reply,
    encode_frame,
    encode_hello,
    encode_info,
    encode_query,
    encode_status,
    encode_timed,
    frame_length,
    level_bits,
    pack_levels,
    unpack_levels,
)

from . import wire_vectors as wv


def test_crc16_check_value_and_vectors_worked_by_hand():
    assert crc16(b"123456789") == 0x29B1  # CRC-16/CCITT-FALSE's catalogue check value
    assert crc16(b"") == 0xFFFF  # the initial value, nothing shifted through
    # 0x00 then: 0xFFFF ^ 0x0000 = 0xFFFF; eight shifts, each with the top bit set at first:
    # the reference computed bit by bit.
    assert crc16(b"\x00") == wv.crc16_bitwise(b"\x00") == 0xE1F0


@given(st.binary(max_size=300))
def test_crc16_table_matches_bitwise_reference(data):
    assert crc16(data) == wv.crc16_bitwise(data)


def test_hello_encoded_by_hand():
    # payload 48 00 + CRC 99 6A; COBS: [48] -> 02 48, [99 6A] -> 03 99 6A; then the delimiter.
    assert wv.crc16_bitwise(b"\x48\x00") == 0x996A
    assert encode_hello(0) == bytes.fromhex("02 48 03 99 6a 00") == wv.hello(0)


def test_two_channel_frame_encoded_by_hand():
    # payload 46 00 02 00 16 + CRC D1 76: COBS [46] -> 02 46, [02] -> 02 02, [16 D1 76] -> 04 ...
    assert wv.crc16_bitwise(bytes.fromhex("46 00 02 00 16")) == 0xD176
    assert encode_frame(0, [0, 22]) == bytes.fromhex("02 46 02 02 04 16 d1 76 00")


def test_every_message_type_matches_the_independent_encoder():
    assert encode_frame(7, wv.RAMP) == wv.frame(7, wv.RAMP)
    assert encode_query(200) == wv.query(200)
    info = Info(3, 2, 5, 6, 23, 250, 303, "palm-5x6", features=1, queue=24)
    assert encode_info(info) == wv.info(3)
    plain = {**wv.PALM, "features": 0}  # a format 2 array without the extension
    assert encode_info(Info(3, 2, 5, 6, 23, 250, 303, "palm-5x6")) == wv.info(3, plain)
    assert decode_message(wv.info(3, plain)[:-1]) == Info(3, 2, 5, 6, 23, 250, 303, "palm-5x6")
    assert decode_message(wv.info(3)[:-1]).scheduled
    assert encode_status(Status(4, 70000, 3, 2)) == wv.status(4, 70000, 3, 2)
    assert encode_timed(9, 2**32 - 1, wv.RAMP, bits=5) == wv.timed(9, 2**32 - 1, wv.RAMP)
    assert encode_clock(11) == wv.clock(11)
    reply = ClockReply(12, 2**31 + 5, 7, 1, 2, 3)
    assert encode_clock_reply(reply) == wv.clock_reply(12, 2**31 + 5, 7, 1, 2, 3)
    assert decode_message(wv.clock_reply(12, 2**31 + 5, 7, 1, 2, 3)[:-1]) == reply
    assert decode_message(wv.timed(9, 70, wv.RAMP)[:-1], levels=23) == Timed(9, 70, bytes(wv.RAMP))


def test_timed_frame_encoded_by_hand():
    # levels 0, 22 at 5 bits: 00000 10110 + 000000 padding = 0000 0101 1000 0000 = 05 80
    # payload 54 01 | 00 00 13 88 (5000 us) | 02 | 05 80, CRC 7D 07
    # COBS: [54 01] 00 [] 00 [13 88 02 05 80 7D 07] -> 03 54 01 01 08 13 88 02 05 80 7d 07
    assert wv.packed([0, 22]) == bytes.fromhex("05 80")
    assert wv.crc16_bitwise(bytes.fromhex("54 01 00 00 13 88 02 05 80")) == 0x7D07
    expected = bytes.fromhex("03 54 01 01 08 13 88 02 05 80 7d 07 00")
    assert encode_timed(1, 5000, [0, 22], bits=5) == expected


def test_levels_pack_into_as_few_bits_as_the_levels_need():
    assert [level_bits(n) for n in (2, 3, 4, 5, 23, 32, 33, 256)] == [1, 2, 2, 3, 5, 5, 6, 8]
    assert pack_levels(bytes(wv.RAMP), 5) == wv.packed(wv.RAMP)  # 150 bits in 19 bytes
    assert len(wv.packed(wv.RAMP)) == 19
    assert unpack_levels(wv.packed(wv.RAMP), 30, 5) == bytes(wv.RAMP)
    assert frame_length(30, timed=True, bits=5) == 30  # 28 payload bytes, COBS code, delimiter
    with pytest.raises(ValueError, match="does not fit"):
        pack_levels(bytes([32]), 5)


def test_the_wrapping_clock_difference():
    assert clock_diff(10, 5) == 5 and clock_diff(5, 10) == -5
    assert clock_diff(3, 2**32 - 3) == 6  # just past the wrap is ahead
    assert clock_diff(2**32 - 3, 3) == -6
    assert clock_diff(2**31 - 1, 0) == 2**31 - 1 and clock_diff(2**31, 0) == -(2**31)


def test_cobs_vectors_from_the_cobs_description():
    from cobs import cobs

    vectors = {
        "00": "01 01",
        "00 00": "01 01 01",
        "11 22 00 33": "03 11 22 02 33",
        "11 22 33 44": "05 11 22 33 44",
        "11 00 00 00": "02 11 01 01 01",
    }
    for raw, encoded in vectors.items():
        assert cobs.encode(bytes.fromhex(raw)) == bytes.fromhex(encoded)
        assert wv.cobs_encode(bytes.fromhex(raw)) == bytes.fromhex(encoded)


def test_palm_frame_is_37_bytes_on_the_wire():
    # 'F', seq, N, 30 levels, 2 CRC bytes = 35; COBS adds one; the delimiter one more.
    assert len(encode_frame(7, [3] * 30)) == 37 == frame_length(30)
    assert len(encode_frame(7, [0] * 30)) == 37  # zeros are stuffed, never grow a frame
    assert pytest.approx(311.35, abs=0.01) == 115200 / 10 / 37  # frames a second, 8N1


def test_sequence_number_wraps():
    assert decode_frame(encode_frame(256 + 5, [1, 2])[:-1])[0] == 5
    assert decode_frame(encode_frame(255, [1, 2])[:-1])[0] == 255


@given(st.integers(0, 255), st.lists(st.integers(0, 22), max_size=60))
def test_frame_round_trip(seq, levels):
    wire = encode_frame(seq, levels)
    assert wire.count(0) == 1 and wire.endswith(b"\x00")
    assert decode_message(wire[:-1], channels=len(levels), levels=23) == Frame(seq, bytes(levels))


@given(
    st.integers(0, 255),
    st.integers(1, 64),
    st.integers(1, 64),
    st.integers(2, 255),
    st.integers(0, 65535),
    st.integers(0, 65535),
    st.text(st.characters(min_codepoint=32, max_codepoint=126), max_size=64),
    st.integers(0, 2**32 - 1),
    st.integers(0, 2**32 - 1),
    st.integers(0, 65535),
)
def test_info_status_hello_query_round_trip(seq, cols, rows, levels, wd, pwm, name, f, d, t):
    info = Info(seq, 2, cols, rows, levels, wd, pwm, name)
    assert decode_message(encode_info(info)[:-1]) == info
    assert decode_message(encode_status(Status(seq, f, d, t))[:-1]) == Status(seq, f, d, t)
    assert decode_message(encode_hello(seq)[:-1]) == Hello(seq)
    assert decode_message(encode_query(seq)[:-1]) == Query(seq)


def _sealed(body):
    from cobs import cobs

    crc = wv.crc16_bitwise(body)
    return cobs.encode(body + bytes((crc >> 8, crc & 0xFF)))


@pytest.mark.parametrize(
    ("payload", "kwargs", "reason"),
    [
        (b"\x46\x00\x02\x01\x02" + b"\x00\x00", {}, "crc"),
        (None, {"channels": 30}, "length"),
        (b"\x46\x00\x05\x01\x02", {}, "length"),
        (b"\x46\x00\x02\x01\x17", {"levels": 23}, "range"),
        (b"\x47\x00\x02\x01\x02", {}, "type"),
        (b"\x49\x00\x03\x05\x06\x17\x00\xfa\x01\x2f\x00", {}, "range"),  # an info of version 3
        (b"\x51\x00\x00", {}, "length"),
    ],
)
def test_bad_messages_are_rejected_with_their_reason(payload, kwargs, reason):
    from cobs import cobs

    if payload is None:
        message = encode_frame(0, [1, 2])[:-1]
    elif reason == "crc":
        message = cobs.encode(payload)
    else:
        message = _sealed(payload)
    with pytest.raises(MessageError) as info:
        decode_message(message, **kwargs)
    assert info.value.reason == reason


def test_short_and_bad_cobs_are_rejected():
    from cobs import cobs

    with pytest.raises(MessageError) as info:
        decode_message(cobs.encode(b"\x46\x00"))
    assert info.value.reason == "short"
    with pytest.raises(MessageError) as info:
        decode_message(b"\x05\x46\x00")  # claims 4 bytes follow, only 2 do
    assert info.value.reason == "cobs"


def test_reader_splits_a_stream_and_resynchronises_after_garbage():
    reader = FrameReader(channels=2, levels=23)
    good = [encode_frame(i, [i, 22 - i]) for i in range(3)]
    stream = b"garbage\xff\x13" + b"\x00" + good[0] + good[1][:4] + b"\x00" + good[2]
    frames = []
    for i in range(0, len(stream), 3):  # arrives in small pieces
        frames += reader.feed(stream[i : i + 3])
    assert [seq for seq, _ in frames] == [0, 2]
    assert reader.bad == 2  # the garbage, and the truncated frame 1
    assert sum(reader.errors[r] for r in REASONS) == 2


def test_reader_drops_runaway_garbage_without_growing():
    reader = FrameReader(channels=30, levels=23)
    assert reader.feed(b"\x01" * 100_000) == []
    assert len(reader._buffer) == 0
    frames = reader.feed(b"\x00" + encode_frame(1, [0] * 30))
    assert [s for s, _ in frames] == [1]
    assert reader.errors["length"] == 1


@given(st.binary(max_size=2000))
def test_reader_never_crashes_on_random_bytes(data):
    reader = MessageReader(channels=30, levels=23)
    for msg in reader.feed(data):
        if isinstance(msg, Frame):
            assert len(msg.levels) == 30 and max(msg.levels, default=0) < 23
    frames = reader.feed(b"\x00" + encode_frame(9, [5] * 30))
    assert frames[-1] == Frame(9, bytes([5] * 30))


# --- the shared vectors against the Python receiver ------------------------------------------


def run_model(vector):
    model = ArrayModel()
    now_ms, applied, replies = 0, [], b""
    for kind, arg in vector["steps"]:
        if kind == "feed":
            out, frames = model.receive(arg, now_ms / 1000)
            replies += out
            applied += [(f.seq, list(f.levels)) for f in frames]
        else:
            now_ms += arg
            applied += [(f.seq, list(f.levels)) for f in model.advance(now_ms / 1000)]
            model.watchdog(now_ms / 1000)
    counters = {
        "frames_applied": model.frames_applied,
        "dropped": model.dropped,
        "watchdog_trips": model.watchdog_trips,
        "dropped_by": {k: v for k, v in model.reader.errors.items() if v},
    }
    return applied, list(model.levels), replies, counters


def check_vector(vector, applied, levels, replies, counters):
    assert applied == [(s, list(lv)) for s, lv in vector["applied"]]
    assert levels == vector["levels"]
    assert replies == vector["replies"], (replies.hex(" "), vector["replies"].hex(" "))
    assert counters["frames_applied"] == vector["frames_applied"]
    assert counters["watchdog_trips"] == vector["watchdog_trips"]
    if vector["dropped"] is None:
        assert counters["dropped"] >= 1
    else:
        assert counters["dropped"] == vector["dropped"]
        assert counters["dropped_by"] == vector["dropped_by"]


@pytest.mark.parametrize("vector", wv.VECTORS, ids=[v["name"] for v in wv.VECTORS])
def test_python_receiver_meets_the_vectors(vector):
    check_vector(vector, *run_model(vector))


@given(st.binary(max_size=600), st.integers(0, 255))
def test_a_corrupted_frame_never_changes_the_levels(noise, seq):
    model = ArrayModel()
    model.receive(encode_frame(1, wv.RAMP), 0.0)
    _, frames = model.receive(b"\x00" + noise + b"\x00", 0.0)
    for f in frames:  # noise that happens to be a valid frame is applied, as it should be
        assert len(f.levels) == 30
    if not frames:
        assert list(model.levels) == wv.RAMP


def test_readme_lists_the_test_vectors():
    from pathlib import Path

    readme = (Path(__file__).resolve().parent.parent / "docs" / "device.md").read_text()
    for data in (
        wv.hello(0),
        wv.query(5),
        wv.frame(0, [0, 22]),
        wv.info(0),
        wv.status(5, 0, 0, 0),
        wv.timed(1, 5000, [0, 22]),
        wv.clock(2),
        wv.clock_reply(2, 7000, 7100, 0, 0, 1),
    ):
        assert data.hex(" ") in readme, data.hex(" ")
    ramp = wv.frame(1, wv.RAMP).hex(" ")
    assert ramp[:18] in readme and ramp[-30:] in readme
