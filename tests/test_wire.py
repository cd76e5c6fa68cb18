"""The wire format: CRC-8 and COBS vectors worked by hand, round trips, and bad frames."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tactile_core.wire import (
    REASONS,
    FrameError,
    FrameReader,
    crc8,
    decode_frame,
    encode_frame,
    frame_length,
)


def crc8_bitwise(data):
    """Reference CRC-8 (poly 0x07, init 0, no reflection, no xor), one bit at a time."""
    crc = 0
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = ((crc << 1) ^ 0x07) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc


def test_crc8_vectors_worked_by_hand():
    # 0x01: seven shifts to 0x80, the eighth shifts out the top bit and xors 0x07.
    assert crc8(b"\x01") == 0x07
    # 0x80: the top bit goes at once (0x07), then 0x0E, 0x1C, 0x38, 0x70, 0xE0, 0xC7, 0x89.
    assert crc8(b"\x80") == 0x89
    # 0x46 ('F'): 0x8C, 0x1F, 0x3E, 0x7C, 0xF8, 0xF7, 0xE9, 0xD5.
    assert crc8(b"\x46") == 0xD5
    # then 0x00: 0xAD, 0x5D, 0xBA, 0x73, 0xE6, 0xCB, 0x91, 0x25; and 0x00 again -> 0xFB.
    assert crc8(b"\x46\x00") == 0x25
    assert crc8(b"\x46\x00\x00") == 0xFB
    assert crc8(b"") == 0x00


def test_crc8_catalogue_check_value():
    # CRC-8/SMBUS (poly 0x07, init 0, refin/refout false, xorout 0): check = 0xF4.
    assert crc8(b"123456789") == 0xF4


@given(st.binary(max_size=300))
def test_crc8_table_matches_bitwise_reference(data):
    assert crc8(data) == crc8_bitwise(data)


def test_empty_frame_encoded_by_hand():
    # payload 46 00 00 FB (type, seq 0, N 0, CRC): COBS splits at the zeros:
    # [46] -> 02 46, [] -> 01, [FB] -> 02 FB; then the delimiter.
    assert encode_frame(0, []) == bytes.fromhex("02 46 01 02 FB 00")


def test_two_channel_frame_encoded_by_hand():
    # payload 46 00 02 00 16 + CRC; COBS: [46] -> 02 46, [02] -> 02 02, [16 CRC] -> 03 16 CRC.
    crc = crc8_bitwise(bytes.fromhex("46 00 02 00 16"))
    assert encode_frame(0, [0, 22]) == bytes.fromhex(f"02 46 02 02 03 16 {crc:02x} 00")


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


def test_palm_frame_is_36_bytes_on_the_wire():
    assert len(encode_frame(7, [3] * 30)) == 36 == frame_length(30)
    assert len(encode_frame(7, [0] * 30)) == 36  # zeros are stuffed, never grow a frame


def test_sequence_number_wraps():
    assert decode_frame(encode_frame(256 + 5, [1, 2])[:-1])[0] == 5
    assert decode_frame(encode_frame(255, [1, 2])[:-1])[0] == 255


@given(st.integers(0, 255), st.lists(st.integers(0, 22), max_size=60))
def test_round_trip(seq, levels):
    wire = encode_frame(seq, levels)
    assert wire.count(0) == 1 and wire.endswith(b"\x00")
    got_seq, got = decode_frame(wire[:-1], channels=len(levels), levels=23)
    assert got_seq == seq and list(got) == levels


def corrupt_payload(payload):
    from cobs import cobs

    return cobs.encode(bytes(payload))


@pytest.mark.parametrize(
    ("payload", "kwargs", "reason"),
    [
        (b"\x46\x00\x02\x01\x02" + bytes([crc8(b"\x46\x00\x02\x01\x02") ^ 1]), {}, "crc"),
        (
            b"\x46\x00\x02\x01\x02" + bytes([crc8(b"\x46\x00\x02\x01\x02")]),
            {"channels": 30},
            "length",
        ),
        (b"\x46\x00\x05\x01\x02" + bytes([crc8(b"\x46\x00\x05\x01\x02")]), {}, "length"),
        (b"\x46\x00\x02\x01\x17" + bytes([crc8(b"\x46\x00\x02\x01\x17")]), {"levels": 23}, "range"),
        (b"\x47\x00\x02\x01\x02" + bytes([crc8(b"\x47\x00\x02\x01\x02")]), {}, "type"),
        (b"\x46\x00", {}, "short"),
    ],
)
def test_bad_frames_are_rejected_with_their_reason(payload, kwargs, reason):
    with pytest.raises(FrameError) as info:
        decode_frame(corrupt_payload(payload), **kwargs)
    assert info.value.reason == reason


def test_bad_cobs_is_rejected():
    with pytest.raises(FrameError) as info:
        decode_frame(b"\x05\x46\x00")  # claims 4 bytes follow, only 2 do
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
    reader = FrameReader(channels=30, levels=23, max_length=512)
    assert reader.feed(b"\x01" * 100_000) == []
    assert len(reader._buffer) == 0
    frames = reader.feed(b"\x00" + encode_frame(1, [0] * 30))
    assert [s for s, _ in frames] == [1]
    assert reader.errors["length"] == 1


@given(st.binary(max_size=2000))
def test_reader_never_crashes_on_random_bytes(data):
    reader = FrameReader(channels=30, levels=23)
    frames = reader.feed(data)
    assert all(len(levels) == 30 and max(levels, default=0) < 23 for _, levels in frames)
    # and a good frame after the noise still decodes
    frames = reader.feed(b"\x00" + encode_frame(9, [5] * 30))
    assert frames[-1][0] == 9
