"""The OSC server (tactile_core.serve): its packet reader against python-osc's writer, the address
space, and every kind of bad message counted, never crashing the server."""

import math
import socket
import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
from pythonosc.osc_message_builder import OscMessageBuilder

from tactile_core.rendering.scene import Scene
from tactile_core.serve import Malformed, OscServer, read_packet

from .serve_support import ServerRig, levels_of, send_until_shown, wait_for


def message(address, *args):
    builder = OscMessageBuilder(address)
    for arg in args:
        builder.add_arg(arg)
    return builder.build()


def test_osc_reader_reads_what_python_osc_writes():
    m = message("/tactile/point/hand", 1.5, 2, "x", True, False, None, b"abc", 2**40)
    assert read_packet(m.dgram, 10) == (
        [("/tactile/point/hand", [1.5, 2, "x", True, False, None, b"abc", 2**40])],
        0,
    )
    b = OscMessageBuilder("/d")
    b.add_arg(0.1, "d")
    assert read_packet(b.build().dgram, 10) == ([("/d", [0.1])], 0)
    assert read_packet(message("/tactile/off").dgram, 10) == ([("/tactile/off", [])], 0)


def test_osc_reader_reads_bundles_in_order_up_to_a_bound():
    inner = OscBundleBuilder(IMMEDIATELY)
    inner.add_content(message("/b", 2))
    outer = OscBundleBuilder(IMMEDIATELY)
    outer.add_content(message("/a", 1))
    outer.add_content(inner.build())
    outer.add_content(message("/c", 3))
    data = outer.build().dgram
    assert read_packet(data, 10) == ([("/a", [1]), ("/b", [2]), ("/c", [3])], 0)
    assert read_packet(data, 1) == ([("/a", [1])], 2)


@pytest.mark.parametrize(
    "data, why",
    [
        (b"/abc", "NUL"),
        (b"/ab\x00\x00", "multiple of 4"),
        (b"abc\x00", "start with '/'"),
        (b"/a\xff\x00", "UTF-8"),
        (b"/a\x00\x00,f\x00\x00", "past the end"),
        (b"/a\x00\x00ff\x00\x00\x00\x00\x00\x00", "','"),
        (b"/a\x00\x00,q\x00\x00", "unknown type tag"),
        (b"/a\x00\x00,[\x00\x00", "not closed"),
        (b"/a\x00\x00,b\x00\x00\x00\x00\x00\x09abcd", "blob"),
        (b"#bundle\x00\x00\x00\x00\x00", "time tag"),
        (b"#bundle\x00" + bytes(8) + struct.pack(">i", 64) + b"/a\x00\x00", "does not fit"),
        (b"#bundle\x00" + bytes(8) + struct.pack(">i", -4) + b"/a\x00\x00", "does not fit"),
    ],
)
def test_osc_reader_refuses_what_is_not_osc(data, why):
    with pytest.raises(Malformed, match=why):
        read_packet(data, 10)


def test_osc_reader_refuses_deep_nesting():
    data = message("/a").dgram
    for _ in range(9):
        data = b"#bundle\x00" + bytes(8) + struct.pack(">i", len(data)) + data
    with pytest.raises(Malformed, match="nested"):
        read_packet(data, 10)


def test_osc_reader_finds_string_ends_without_walking_them():
    junk = b"/" + b"a" * 16000 + b"\x00" * 3  # 16,004 bytes, no type tags: one message
    assert read_packet(junk, 10)[0][0][0] == "/" + "a" * 16000


def test_serve_points_render_as_sent():
    with ServerRig() as rig:
        rig.send("/tactile/point", 1.2, 2.7)
        rig.taps.wait_levels(levels_of("AS", [(1.2, 2.7, 1.0)], 0.33, 0.7))
        rig.send("/tactile/point/left", 0.5, 0.5, 0.5)
        rig.taps.wait_levels(levels_of("AS", [(1.2, 2.7, 1.0), (0.5, 0.5, 0.5)], 0.33, 0.7))
        rig.send("/tactile/release", "")
        rig.taps.wait_levels(levels_of("AS", [(0.5, 0.5, 0.5)], 0.33, 0.7))
        rig.send("/tactile/point/7", 3.5, 3.5)
        rig.wait_count("points", 3)
        rig.send("/tactile/release", 7)  # an int id is the same id
        rig.send("/tactile/release")  # no id: all
        rig.taps.wait_levels(bytes(30))
        rig.wait_count("releases", 3)
        stats = rig.server.stats
        assert (stats.points, stats.releases, stats.problems) == (3, 3, 0)
        assert stats.last_sender.startswith("127.0.0.1:")


def test_serve_method_and_correction_change_the_points_and_refuse_shape_methods():
    with ServerRig() as rig:
        rig.send("/tactile/method", "CT")
        rig.send("/tactile/mu", 0.0)
        rig.send("/tactile/gamma", 2.0)
        rig.wait_count("controls", 3)
        assert (rig.server.scene.method, rig.server.scene.mu, rig.server.scene.gamma) == (
            "CT", 0.0, 2.0
        )  # fmt: skip
        rig.send("/tactile/point", 1.2, 2.7, 0.5)
        rig.taps.wait_levels(levels_of("CT", [(1.2, 2.7, 0.5)], 0.0, 2.0))
        rig.send("/tactile/method", "IM")
        rig.wait_count("refused", 1)
        assert "needs a shape" in rig.server.stats.last_problem
        rig.send("/tactile/method", "XX")
        rig.send("/tactile/mu", 1.5)
        rig.send("/tactile/gamma", 0)
        rig.wait_count("out_of_range", 2)
        assert rig.server.stats.refused == 2
        assert rig.server.scene.method == "CT" and rig.server.scene.mu == 0.0


def test_serve_reports_only_what_a_sender_set_whenever_the_owner_scene_lands():
    # The tuner's scene reaches the server down a pipe and may land before or after a sender's
    # messages; a sender's change is reported as the fields its message set (never the
    # owner's mu or gamma: reporting those would undo the owner's change in the tuner).
    changes = []
    with ServerRig(on_tuning=changes.append) as rig:  # scene AS, mu 0.33, gamma 0.7
        rig.send("/tactile/gamma", 2.0)
        rig.wait_count("controls", 1)
        rig.server.set_scene(Scene(method="GS", mu=0.5, gamma=0.7))  # the owner's, late
        rig.send("/tactile/method", "RO")
        rig.wait_count("controls", 2)
        rig.send("/tactile/mu", 0.5)  # what the points' scene already has: nothing to report
        rig.wait_count("controls", 3)
        assert changes == [{"gamma": 2.0}, {"method": "RO"}]
        scene = rig.server.scene
        assert (scene.method, scene.mu, scene.gamma) == ("RO", 0.5, 0.7)


def test_serve_takes_a_32_bit_mu_and_gamma_as_the_decimal_the_sender_wrote():
    # python-osc sends 0.33 as the float32 0.33000001311302185, which the markers recorded
    with ServerRig() as rig:
        rig.send("/tactile/mu", 0.33)
        rig.send("/tactile/gamma", 0.7)
        rig.wait_count("controls", 2)
        assert (rig.server.scene.mu, rig.server.scene.gamma) == (0.33, 0.7)
        exact = OscMessageBuilder("/tactile/mu")
        exact.add_arg(0.1, "d")  # a 64-bit argument is taken as it is
        rig.client.send(exact.build())
        rig.wait_count("controls", 3)
        assert rig.server.scene.mu == 0.1


@pytest.mark.parametrize(
    "sent, taken",
    [(0.33000001311302185, 0.33), (0.699999988079071, 0.7), (0.10000000149011612, 0.1),
     (2.5, 2.5), (0.3333333432674408, 0.33333334), (0.1, 0.1), (1 / 3, 1 / 3),
     (math.inf, math.inf), (1e300, 1e300)],
)  # fmt: skip
def test_serve_decimal32_by_hand(sent, taken):
    from tactile_core.serve._osc_addresses import decimal32

    assert decimal32(sent) == taken


@settings(max_examples=300, derandomize=True, database=None)
@given(st.floats(width=32, allow_nan=False, allow_infinity=False))
def test_serve_decimal32_is_the_same_32_bit_float(x):
    from tactile_core.serve._osc_addresses import decimal32

    y = decimal32(x)
    assert struct.pack(">f", y) == struct.pack(">f", x)
    assert len(repr(abs(y)).split("e")[0].replace(".", "").strip("0")) <= 9


def test_serve_shape_plays_once_then_back_to_points():
    scenes = []  # every scene the server swaps in, in order
    with ServerRig(on_scene=scenes.append) as rig:
        rig.send("/tactile/shape", "line:0.5,0.5,4.5,0.5", 0.2)
        wait_for(lambda: len(scenes) >= 2, what="the shape, then back to points")
        assert scenes[0].shape.spec == "line:0.5,0.5,4.5,0.5" and not scenes[0].repeat
        assert scenes[0].marker == "osc-shape" and scenes[1].source is rig.server.points
        lit = [f for f in rig.taps.frames if any(f[2])]
        assert lit and all(f[2][5:] == bytes(25) for f in lit)  # the bottom row only
        rig.send("/tactile/shape", "circle:2.5,3,2", 30.0)
        wait_for(lambda: len(scenes) >= 3, what="the second shape")
        assert rig.server.stats.playing == "circle:2.5,3,2"
        rig.send("/tactile/off")  # ends the shape at once
        wait_for(lambda: len(scenes) >= 4, what="off")
        assert scenes[3].source is rig.server.points and rig.server.stats.playing == "points"
        rig.send("/tactile/shape", "blob:1", 1.0)
        rig.send("/tactile/shape", "circle:2.5,3,2")
        rig.send("/tactile/shape", "circle:2.5,3,2", -1.0)
        rig.send("/tactile/shape", "circle:2.5,3,2", math.nan)
        rig.wait_count("non_finite", 1)
        s = rig.server.stats
        assert (s.shapes, s.refused, s.wrong_type, s.out_of_range) == (2, 1, 1, 1)


def test_serve_point_not_refreshed_is_released():
    with ServerRig(timeout_s=0.05) as rig:
        want = levels_of("AS", [(2.5, 3.5, 1.0)], 0.33, 0.7)
        lit = send_until_shown(lambda: rig.send("/tactile/point", 2.5, 3.5), rig.taps, want)
        off = rig.taps.wait_levels(bytes(30), after=lit)
        rig.wait_count("timed_out", 1)
        assert rig.server.stats.active_points == 0 and rig.server.running
        # no frame between still lit: the sender went quiet, the array went off
        assert all(f[2] == bytes(30) for f in rig.taps.frames[off : off + 10])


def test_serve_counts_every_kind_of_bad_message_and_goes_on():
    with ServerRig() as rig:
        sock = rig.client._sock
        for junk in (b"garbage", b"", b"\x00" * 8, b"/a\x00\x00,q\x00\x00"):
            sock.sendto(junk, rig.server.address)
        rig.send("/tactile/nothing", 1)
        rig.send("/other", 1)
        rig.send("/tactile/point/", 1.0, 1.0)
        rig.send("/tactile/point", "a", 1.0)
        rig.send("/tactile/point", 1.0)
        rig.send("/tactile/point", True, 1.0)
        rig.send("/tactile/release", 1.5)
        rig.send("/tactile/method", 3)
        rig.send("/tactile/point", math.nan, 1.0)
        rig.send("/tactile/point", 1.0, -math.inf)
        rig.send("/tactile/mu", math.inf)
        rig.send("/tactile/point", 1.0, 1.0, 2.0)
        rig.send("/tactile/point", 1e9, 1.0)
        rig.send("/tactile/point/" + "x" * 70, 1.0, 1.0)
        rig.wait_count("out_of_range", 3)
        s = rig.server.stats
        assert (s.malformed, s.unknown, s.wrong_type, s.non_finite) == (4, 3, 5, 3)
        assert s.points == 0 and s.errors == 0
        rig.send("/tactile/point", 1.5, 1.5)  # alive and well
        rig.taps.wait_levels(levels_of("AS", [(1.5, 1.5, 1.0)], 0.33, 0.7))
        assert "out of range" in s.line() and "malformed" in s.summary()


def test_serve_flood_guard_drops_unread_but_always_reads_off():
    with ServerRig(max_rate_hz=100.0) as rig:  # a bucket of 5 messages
        sock = rig.client._sock
        point = message("/tactile/point", 1.5, 1.5).dgram
        for _ in range(200):
            sock.sendto(point, rig.server.address)
        sock.sendto(message("/tactile/off").dgram, rig.server.address)
        rig.wait_count("controls", 1)
        s = rig.server.stats
        assert s.flood_dropped > 0
        assert s.datagrams + s.kernel_dropped == 201
        assert s.points + s.flood_dropped == s.datagrams - 1


def test_serve_listens_on_loopback_and_warns_beyond_it():
    with ServerRig() as rig:
        assert rig.server.address[0] == "127.0.0.1" and rig.warnings == []
    rig = ServerRig()
    rig.server.host = "0.0.0.0"
    with rig:
        assert rig.warnings and "beyond this machine" in rig.warnings[0]


def test_serve_port_in_use_says_where():
    with ServerRig() as rig:
        other = OscServer(rig.streamer, scene=Scene(method="AS"), port=rig.server.address[1])
        with pytest.raises(OSError, match=f"127.0.0.1:{rig.server.address[1]}"):
            other.start()


def test_serve_refuses_a_shape_method_at_the_start():
    from tactile_core.device.link import SimulatedArray
    from tactile_core.stream.streamer import Streamer

    with pytest.raises(ValueError, match="needs a shape"):
        OscServer(Streamer(SimulatedArray()), scene=Scene(method="IM"))


def test_serve_stop_leaves_the_stream_idle():
    with ServerRig() as rig:
        rig.send("/tactile/point", 1.5, 1.5)
        rig.wait_count("points", 1)
        stats = rig.server.stop()
        assert rig.streamer.scene is None and stats.points == 1
        rig.taps.wait_levels(bytes(30), after=len(rig.taps.frames))


def test_serve_socket_error_paths_do_not_stop_the_receiver(monkeypatch):
    with ServerRig() as rig:
        real = rig.server._handle

        def broken(address, args, now):
            if address == "/tactile/off":
                raise RuntimeError("boom")
            return real(address, args, now)

        monkeypatch.setattr(rig.server, "_handle", broken)
        rig.send("/tactile/off")
        rig.wait_count("errors", 1)
        assert "boom" in rig.server.stats.last_problem
        rig.send("/tactile/point", 1.5, 1.5)
        rig.wait_count("points", 1)


def test_serve_reads_ipv6_loopback_when_asked():
    if not socket.has_ipv6:
        pytest.skip("no IPv6 on this machine")
    rig = ServerRig()
    rig.server.host = "::1"
    try:
        rig.streamer.start()
        rig.server.start()
    except OSError as exc:  # IPv6 compiled in but not configured here
        rig.streamer.stop()
        pytest.skip(f"no IPv6 loopback: {exc}")
    try:
        assert rig.server.address[0] == "::1" and rig.warnings == []
    finally:
        rig.server.stop()
        rig.streamer.stop()


@pytest.mark.parametrize(
    "host, local",
    [("127.0.0.1", True), ("127.8.9.10", True), ("::1", True), ("::ffff:127.0.0.1", True),
     ("fe80::1%lo", False), ("0.0.0.0", False), ("::", False), ("192.168.1.5", False),
     ("::ffff:192.168.1.5", False)],
)  # fmt: skip
def test_serve_warns_exactly_for_addresses_beyond_this_machine(host, local):
    # IPv4 loopback written as IPv6 drew the "beyond this machine" warning (Python < 3.13)
    from tactile_core.serve._osc_server import _loopback

    assert _loopback(host) is local


def test_serve_on_a_local_stream_and_refused_by_the_stream_process():
    from pythonosc.udp_client import SimpleUDPClient

    from tactile_core.stream.process import open_stream

    from .serve_support import Taps

    stream = open_stream(None, process=False)
    taps = Taps()
    stream.taps.append(taps)
    server = OscServer(stream, scene=Scene(method="AS", mu=0.33, gamma=0.7), port=0).start()
    client = SimpleUDPClient(*server.address)
    try:
        assert server.on_onset in stream.on_onset  # shapes timed from their first frame
        client.send_message("/tactile/point", [1.2, 2.7])
        taps.wait_levels(levels_of("AS", [(1.2, 2.7, 1.0)], 0.33, 0.7))
    finally:
        client.close()
        server.stop()
        stream.stop()
    child = open_stream(None, process=True)
    try:
        with pytest.raises(TypeError, match="process=False"):
            OscServer(child, scene=Scene(method="AS"), port=0).start()
    finally:
        child.stop()


def test_serve_restarts_after_stop_like_a_toggle():
    with ServerRig() as rig:
        first = rig.server.stop()
        assert not rig.server.running and rig.server.stats.elapsed_s == first.elapsed_s
        rig.server.start()
        rig.client.close()
        from pythonosc.udp_client import SimpleUDPClient

        rig.client = SimpleUDPClient(*rig.server.address)
        rig.send("/tactile/point", 1.5, 1.5)
        rig.taps.wait_levels(levels_of("AS", [(1.5, 1.5, 1.0)], 0.33, 0.7))
        assert rig.server.running and rig.server.stats.points == 1


def test_serve_listens_on_bracketed_ipv6_as_it_prints_it():
    from tactile_core.serve import listen_host

    assert listen_host("[::1]") == "::1" and listen_host(" 127.0.0.1 ") == "127.0.0.1"
    for bad in ("[localhost]", "", "[]"):
        with pytest.raises(ValueError, match=r"::1 or \[::1\]"):
            listen_host(bad)
    if not socket.has_ipv6:
        return
    rig = ServerRig()
    rig.server.host = "[::1]"  # what the server prints on its first line: osc://[::1]:PORT
    try:
        rig.streamer.start()
        rig.server.start()
    except OSError as exc:
        rig.streamer.stop()
        assert "Name or service" not in str(exc)  # refused as a name before
        pytest.skip(f"no IPv6 loopback: {exc}")
    try:
        assert rig.server.address[0] == "::1" and rig.server.stats.address.startswith("[::1]:")
    finally:
        rig.server.stop()
        rig.streamer.stop()


def test_serve_status_line_names_the_last_refused_message_and_why():
    with ServerRig() as rig:
        rig.send("/tactile/method", "MM")
        rig.wait_count("refused", 1)
        line = rig.server.stats.line()
        assert "1 refused; last: /tactile/method MM: method MM needs a shape" in line


class ReplyCatcher:
    """python-osc's own server as the client that asks for replies, as a patch does."""

    def __init__(self):
        import threading

        from pythonosc.dispatcher import Dispatcher
        from pythonosc.osc_server import ThreadingOSCUDPServer

        self.got = []
        dispatcher = Dispatcher()
        dispatcher.set_default_handler(lambda address, *args: self.got.append((address, args)))
        self.server = ThreadingOSCUDPServer(("127.0.0.1", 0), dispatcher)
        self.port = self.server.server_address[1]
        threading.Thread(target=self.server.serve_forever, daemon=True).start()

    def sendto(self, dgram, address):  # from the listening socket: replies come back here
        self.server.socket.sendto(dgram, address)

    def close(self):
        self.server.shutdown()
        self.server.server_close()


def test_serve_replies_errors_and_state_where_the_sender_asked():
    catcher = ReplyCatcher()
    try:
        with ServerRig() as rig:
            rig.send("/tactile/mu", 2.0)  # nobody asked: no reply
            rig.wait_count("out_of_range", 1)
            rig.send("/tactile/reply", catcher.port)  # a patch's [udpreceive PORT]
            rig.send("/tactile/mu", 2.0)
            rig.send("/tactile/point", 1.5, 1.5)
            rig.send("/tactile/state")
            wait_for(lambda: len(catcher.got) >= 2, what="two replies")
            (error, why), (state, values) = catcher.got[:2]
            assert (error, why[:2]) == ("/tactile/error", ("/tactile/mu", "out of range"))
            assert "mu" in why[2] and "[0, 1]" in why[2]
            assert state == "/tactile/state"
            assert values == ("AS", pytest.approx(0.33), pytest.approx(0.7), 1, "points")
            s = rig.server.stats
            assert (s.replies, s.queries, s.out_of_range) == (2, 2, 2)
    finally:
        catcher.close()


def test_serve_answers_a_query_where_it_came_from_and_never_a_reply():
    catcher = ReplyCatcher()
    try:
        with ServerRig(reply_port=catcher.port) as rig:  # tactile serve --reply-port
            catcher.sendto(message("/tactile/state").dgram, rig.server.address)
            rig.send("/tactile/method", "MM")  # another socket: its host at the reply port
            wait_for(lambda: len(catcher.got) >= 2, what="two replies")
            assert catcher.got[0][0] == "/tactile/state"
            why = rig.server.stats.last_problem
            assert catcher.got[1] == ("/tactile/error", ("/tactile/method", "refused", why))
            for echo in ("/tactile/error", "/tactile/state"):  # another server's replies
                rig.send(echo, "x", "y")
            rig.wait_count("datagrams", 4)
            wait_for(lambda: rig.server.stats.unknown + rig.server.stats.wrong_type == 2)
            assert rig.server.stats.replies == 2  # no ping-pong between two servers
    finally:
        catcher.close()


def test_serve_replies_are_rate_limited_and_never_wait():
    frozen = lambda: 1000.0  # noqa: E731 -- the reply bucket never fills again
    with ServerRig(reply_port=9, clock=frozen, max_rate_hz=1e6) as rig:  # 9: nobody listens
        bad = message("/tactile/mu", 5.0).dgram
        for _ in range(60):
            rig.client._sock.sendto(bad, rig.server.address)
        rig.wait_count("out_of_range", 60)
        # a refusal is counted before its reply is: wait for all 60 to be sent or dropped
        stats = lambda: rig.server.stats  # noqa: E731
        wait_for(lambda: stats().replies + stats().replies_dropped >= 60, what="60 replies")
        s = stats()
        assert (s.replies, s.replies_dropped) == (20, 40)  # a burst of 20, then none
        rig.send("/tactile/point", 1.5, 1.5)  # the receiver went on
        rig.wait_count("points", 1)
