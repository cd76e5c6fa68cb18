"""What a datagram may cost the OSC server (issue 31, F1): bounds checked before a datagram is
read, the rate limit charged by cost and shared among senders, and status lines that stay short
whatever a sender sends. Counts and a frozen clock, never a duration."""

import struct

import pytest
from pythonosc.osc_message_builder import OscMessageBuilder
from pythonosc.udp_client import SimpleUDPClient

from tactile_core.serve import Malformed, read_packet
from tactile_core.serve._osc_wire import MAX_ARGUMENTS, MAX_DATAGRAM_BYTES

from .serve_support import ServerRig, wait_for


def message(address, *args):
    builder = OscMessageBuilder(address)
    for arg in args:
        builder.add_arg(arg)
    return builder.build().dgram


def frozen():
    """A clock that never moves: token buckets never fill again, points never age."""
    return lambda: 1000.0


def test_osc_reader_refuses_more_type_tags_than_the_bound_before_reading_them():
    assert len(read_packet(message("/a", *range(MAX_ARGUMENTS)), 1)[0][0][1]) == MAX_ARGUMENTS
    with pytest.raises(Malformed, match=f"more than {MAX_ARGUMENTS} type tags"):
        read_packet(message("/a", *range(MAX_ARGUMENTS + 1)), 1)
    brackets = b"/tactile/point\x00\x00" + b"," + b"[" * 16_000 + b"\x00" * 3  # issue 31's junk
    with pytest.raises(Malformed, match="type tags"):
        read_packet(brackets, 10)


def test_osc_reader_refuses_a_datagram_over_the_size_bound():
    junk = b"/" + b"a" * MAX_DATAGRAM_BYTES + b"\x00" * 3
    with pytest.raises(Malformed, match=f"at most {MAX_DATAGRAM_BYTES}"):
        read_packet(junk, 10)


def test_serve_never_reads_a_datagram_over_the_size_bound():
    with ServerRig() as rig:
        sock = rig.client._sock
        brackets = b"/tactile/point\x00\x00" + b"," + b"[" * 65_000 + b"\x00" * 3  # 64 KB
        for _ in range(3):
            sock.sendto(brackets, rig.server.address)
        rig.send("/tactile/point", 1.5, 1.5)
        rig.wait_count("points", 1)
        s = rig.server.stats
        assert (s.too_large, s.malformed, s.messages) == (3, 0, 1)
        assert "longer than 16384 bytes" in s.last_problem


def test_serve_charges_a_datagram_by_its_bytes_not_as_one_message():
    # 200 units a second, a bucket of 10; the clock never moves, so it never fills again
    with ServerRig(max_rate_hz=200.0, clock=frozen()) as rig:
        sock = rig.client._sock
        big = message("/tactile/nothing", "x" * 8000)  # 8 KB: 126 units, one message
        for _ in range(10):  # the old limit counted these as 10 messages: all read
            sock.sendto(big, rig.server.address)
        rig.wait_count("datagrams", 10)
        s = rig.server.stats
        assert (s.unknown, s.flood_dropped) == (1, 9)  # the first leaves a debt of 116 units


def test_serve_charges_a_shape_for_its_points_and_bounds_them_before_parsing():
    spec = "polyline:" + ",".join(["0.5,0.5,4.5,5.5"] * 75)  # 150 points
    too_many = "polyline:" + ",".join(["0.5,0.5,4.5,5.5"] * 129)  # 258 points: over 256
    with ServerRig(max_rate_hz=2000.0, clock=frozen()) as rig:  # a bucket of 100 units
        rig.send("/tactile/shape", too_many, 1.0)
        rig.wait_count("out_of_range", 1)
        assert (
            rig.server.stats.shapes == 0 and "at most 256 points" in rig.server.stats.last_problem
        )
        rig.send("/tactile/shape", spec, 1.0)  # 19 units of bytes, 10 + 150 for the shape
        rig.wait_count("shapes", 1)
        rig.send("/tactile/point", 1.5, 1.5)  # the sender is in debt: dropped unread
        rig.wait_count("datagrams", 3)
        assert (rig.server.stats.points, rig.server.stats.flood_dropped) == (0, 1)


def test_serve_reads_a_datagrams_costly_messages_only_within_one_bucket():
    with ServerRig(max_rate_hz=2000.0, clock=frozen()) as rig:  # a bucket of 100 units
        bundle = b"#bundle\x00" + bytes(8)
        for k in range(40):  # 40 scene changes of 10 units each, and 40 x 16 bytes: 10 units
            element = message("/tactile/mu", 0.1 + 0.01 * (k % 2))
            bundle += struct.pack(">i", len(element)) + element
        rig.client._sock.sendto(bundle, rig.server.address)
        rig.wait_count("datagrams", 1)
        wait_for(lambda: rig.server.stats.controls + rig.server.stats.flood_dropped == 40)
        s = rig.server.stats
        # 90 units left after the bytes; messages are read while that stays above -10
        assert (s.controls, s.flood_dropped) == (11, 29)


def test_serve_a_flooding_sender_leaves_another_senders_points_alone():
    with ServerRig(max_rate_hz=200.0, clock=frozen()) as rig:  # two senders: 100/s each
        flood = message("/tactile/point/flood", 2.5, 3.0)
        for _ in range(50):
            rig.client._sock.sendto(flood, rig.server.address)
        rig.wait_count("datagrams", 50)
        assert rig.server.stats.flood_dropped > 0
        held = SimpleUDPClient(*rig.server.address)  # another socket: another sender
        try:
            for k in range(3):
                held.send_message("/tactile/point/held", [1.5, 1.5 + k])
            rig.wait_count("datagrams", 53)
        finally:
            held._sock.close()
        assert "held" in rig.server.points.points  # the old shared bucket dropped it
        assert rig.server.points.points["held"].y == 3.5


def test_serve_flood_of_offs_costs_the_output_thread_no_new_scenes():
    with ServerRig() as rig:
        swaps = []
        real = rig.streamer.set_scene
        rig.streamer.set_scene = lambda scene: swaps.append(scene) or real(scene)
        for _ in range(200):
            rig.send("/tactile/off")
        rig.wait_count("controls", 200)
        assert swaps == []  # nothing to turn off: the points' scene plays already
        rig.send("/tactile/mu", 0.5)
        rig.send("/tactile/mu", 0.5)  # the same again
        rig.wait_count("controls", 202)
        assert len(swaps) == 1 and swaps[0].mu == 0.5


def test_serve_status_line_stays_short_while_a_long_shape_plays():
    spec = "polyline:" + ",".join(
        f"{0.5 + (k % 40) / 10:.6f},{0.5 + k / 50:.6f}" for k in range(250)
    )
    with ServerRig() as rig:
        rig.send("/tactile/shape", spec, 30.0)
        rig.wait_count("shapes", 1)
        s = rig.server.stats
        assert s.playing.startswith("polyline:0.5,0.5,0.6,0.52,") and "(250 points)" in s.playing
        assert len(s.line()) < 300 and len(s.summary()) < 1000  # the spec is 5,500 characters
        rig.send("/tactile/method", "X" * 5000)
        rig.wait_count("refused", 1)
        assert len(rig.server.stats.last_problem) <= 160 and len(rig.server.stats.line()) < 400
