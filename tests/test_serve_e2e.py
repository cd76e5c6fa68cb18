"""``tactile serve`` end to end on loopback: an OSC client (python-osc) sends points, the server
streams into the emulator on a pseudo-terminal, and every frame the emulator received is checked
against rendering the points sent; the timeout release; a flood from a second process."""

import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
from pythonosc.udp_client import SimpleUDPClient

from tactile_core.device.link import open_link
from tactile_core.device.profile import default_profile
from tactile_core.rendering.scene import Scene
from tactile_core.serve import OscServer
from tactile_core.stream.streamer import Streamer

from .helpers import stop_with
from .serve_support import ServerRig, Taps, levels_of, send_until_shown, wait_for

CLI = [sys.executable, "-m", "tactile_core.cli"]
ZEROS = bytes(30)


def some_points(n, seed):
    """``n`` points (x, y, intensity) whose AS levels differ from the previous point's."""
    rng = np.random.default_rng(seed)
    points, last = [], ZEROS
    while len(points) < n:
        p = (float(rng.uniform(0, 5)), float(rng.uniform(0, 6)), float(rng.uniform(0.3, 1)))
        levels = levels_of("AS", [p], 0.33, 0.7)
        if levels not in (last, ZEROS):
            points.append(p)
            last = levels
    return points


def received_since(emulator, start):
    """Levels of the frames the emulator received from frame number ``start`` on."""
    return [row.tobytes() for row in emulator.log.arrays(start)[2]]


def send_each_and_wait(client, emulator, points):
    """Send the points one at a time, each once the previous one reached the emulator."""
    for x, y, a in points:
        want = levels_of("AS", [(x, y, a)], 0.33, 0.7)
        client.send_message("/tactile/point", [x, y, a])
        wait_for(lambda want=want: emulator.log.last() == want, what=f"point {(x, y)} at the array")


def assert_frames_follow(frames, points):
    """Every frame is all off (before the first point, if the stream was up before it, and
    after the release) or the rendering of the point sent last before it, and the points appear
    in the order sent, each of them."""
    expected = [levels_of("AS", [p], 0.33, 0.7) for p in points]
    runs = [frames[0]]
    for levels in frames[1:]:
        if levels != runs[-1]:
            runs.append(levels)
    if runs[0] == ZEROS:
        runs = runs[1:]
    assert runs == [*expected, ZEROS], (
        f"{len(runs)} runs of frames for {len(points)} points: "
        f"{[expected.index(r) if r in expected else r for r in runs]}"
    )


def test_serve_e2e_in_process_frames_at_the_emulator_match_the_points(emulator_thread):
    emulator, path = emulator_thread
    profile = default_profile()
    link = open_link(path, profile)
    streamer = Streamer(link, profile)
    server = OscServer(streamer, profile, scene=Scene(method="AS", mu=0.33, gamma=0.7),
                       port=0, timeout_s=10.0)  # fmt: skip
    points = some_points(25, seed=1)
    start = len(emulator.log)
    streamer.start()
    server.start()
    client = SimpleUDPClient(*server.address)
    try:
        send_each_and_wait(client, emulator, points)
        client.send_message("/tactile/release", [])
        wait_for(lambda: emulator.log.last() == ZEROS, what="the release at the array")
        stats = server.stop()
        streamer.stop()
    finally:
        client.close()
        server.stop()
        streamer.stop()
        link.close()
    assert (stats.points, stats.releases, stats.problems) == (25, 1, 0)
    assert_frames_follow(received_since(emulator, start), points)


def test_serve_e2e_subprocess_into_the_emulator_ends_all_off(emulator_thread):
    emulator, path = emulator_thread
    serve = subprocess.Popen(
        [*CLI, "serve", "--device", path, "--osc-port", "0", "--method", "AS", "--mu", "0.33",
         "--gamma", "0.7", "--timeout-ms", "10000", "--lead-ms", "0", "--status-s", "0"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        first = serve.stdout.readline().strip()
        assert first.startswith("osc://127.0.0.1:"), serve.stderr.read()
        port = int(first.rsplit(":", 1)[1])
        points = some_points(15, seed=2)
        client = SimpleUDPClient("127.0.0.1", port)
        start = len(emulator.log)
        send_each_and_wait(client, emulator, points)
        client.close()
    except BaseException:
        stop_with(serve, signal.SIGKILL)
        raise
    out, err = stop_with(serve, signal.SIGINT, 20)  # Ctrl-C while the last point is lit
    assert serve.returncode == 0, err
    assert "15 point updates" in out  # the summary
    # the emulator's thread logs the all-off when it reads it, maybe after the server left
    wait_for(lambda: emulator.log.last() == ZEROS, what="the all-off frame at the array")
    frames = received_since(emulator, start)
    assert frames[-1] == ZEROS  # the way out: all off
    assert_frames_follow(frames, points)


def test_serve_e2e_point_not_refreshed_goes_off_at_the_array(emulator_thread):
    emulator, path = emulator_thread
    profile = default_profile()
    link = open_link(path, profile)
    taps = Taps()
    streamer = Streamer(link, profile, taps=[taps])
    server = OscServer(streamer, profile, scene=Scene(method="AS", mu=0.33, gamma=0.7), port=0)
    streamer.start()
    server.start()
    client = SimpleUDPClient(*server.address)
    try:
        want = levels_of("AS", [(2.5, 3.5, 1.0)], 0.33, 0.7)
        send = lambda: client.send_message("/tactile/point/crashing-sender", [2.5, 3.5])  # noqa: E731
        lit = send_until_shown(send, taps, want)  # then never again
        off = taps.wait_levels(ZEROS, after=lit)
        wait_for(lambda: emulator.log.last() == ZEROS, what="all off at the array")
        wait_for(lambda: server.stats.timed_out >= 1, what="the timeout counted")
        assert server.running and server.stats.active_points == 0
        assert all(f[2] == want for f in taps.frames[lit:off])  # lit until released, no flicker
    finally:
        client.close()
        server.stop()
        streamer.stop()
        link.close()


FLOOD = textwrap.dedent("""
    import socket, sys, time
    from pythonosc.osc_message_builder import OscMessageBuilder
    port, rate, seconds = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
    b = OscMessageBuilder("/tactile/point/flood"); b.add_arg(2.5); b.add_arg(3.0)
    data = b.build().dgram
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sent = failed = 0
    start = time.perf_counter()
    while True:
        now = time.perf_counter() - start
        if now >= seconds:
            break
        while sent + failed < int(now * rate):
            try:
                sock.sendto(data, ("127.0.0.1", port)); sent += 1
            except OSError:
                failed += 1
    print(sent, failed, time.perf_counter() - start, flush=True)
""")


def test_serve_flood_from_a_second_process_is_counted_and_the_server_lives():
    # A limit of 2,000 messages/s: a sender a loaded machine slows to a tenth of its 50,000/s
    # still floods it (at the default 10,000/s it might not, and nothing would be dropped).
    with ServerRig(max_rate_hz=2_000.0) as rig:
        first_frames = len(rig.taps.frames)
        port = str(rig.server.address[1])
        flood = subprocess.run([sys.executable, "-c", FLOOD, port, "50000", "1.5"],
                               capture_output=True, text=True, timeout=60)  # fmt: skip
        assert flood.returncode == 0, flood.stderr
        sent, _failed, seconds = flood.stdout.split()
        sent = int(sent)
        assert sent > 2 * 2_000 * 1.5  # it flooded (its rate is reported, not asserted)
        # The socket's buffer may still be full: the system drops what does not fit, an off
        # too. Repeat it until one is read; then one more, read after everything else, carries
        # the system's final count of dropped datagrams.
        offs = 0
        while rig.server.stats.controls == 0:
            assert offs < 100, "no /tactile/off got through"
            rig.send("/tactile/off")
            offs += 1
            time.sleep(0.05)
        done = rig.server.stats.controls + 1
        rig.send("/tactile/off")
        rig.wait_count("controls", done)
        s = rig.server.stats
        assert rig.server.running and s.errors == 0 and s.malformed == 0
        assert s.datagrams + s.kernel_dropped == sent + offs + 1  # every datagram accounted for
        assert s.points + s.flood_dropped == s.datagrams - s.controls
        assert s.flood_dropped + s.kernel_dropped > 0  # more than the server reads
        assert len(rig.taps.frames) > first_frames  # the frame clock went on
        rig.send("/tactile/point", 1.5, 1.5)
        rig.taps.wait_levels(levels_of("AS", [(1.5, 1.5, 1.0)], 0.33, 0.7))
        assert rig.streamer.stats.state == "streaming"
    print(f"flood: {sent} sent in {float(seconds):.2f} s; {s.line()}")


def test_serve_subprocess_sigterm_and_bad_options():
    out = subprocess.run([*CLI, "serve", "--device", "sim", "--method", "IM"],
                         capture_output=True, text=True, timeout=60)  # fmt: skip
    assert out.returncode == 2 and "needs a shape" in out.stderr
    serve = subprocess.Popen([*CLI, "serve", "--device", "sim", "--osc-port", "0",
                              "--status-s", "0.1"], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert serve.stdout.readline().startswith("osc://127.0.0.1:")
        for line in serve.stderr:  # the periodic status line
            if line.startswith("osc 127.0.0.1:"):
                assert "0 messages (0/s); 0 points, playing points" in line
                break
    except BaseException:
        stop_with(serve, signal.SIGKILL)
        raise
    out, err = stop_with(serve, signal.SIGTERM, 20)
    assert serve.returncode == 0, err
    assert "stopped: all off" in out


def test_serve_busy_port_is_said_before_the_device_is_touched():
    import socket

    busy = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    busy.bind(("127.0.0.1", 0))
    device = socket.socket()  # a device on a TCP port: opening it would connect here
    device.bind(("127.0.0.1", 0))
    device.listen(1)
    device.settimeout(0)
    try:
        out = subprocess.run(
            [*CLI, "serve", "--device", f"socket://127.0.0.1:{device.getsockname()[1]}",
             "--osc-port", str(busy.getsockname()[1]), "--seconds", "1"],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip
        assert out.returncode == 1 and out.stdout == ""
        assert f"cannot listen on 127.0.0.1:{busy.getsockname()[1]}" in out.stderr
        assert "--osc-port 0 takes any free port" in out.stderr
        assert "identifying" not in out.stderr  # the stream never started
        try:
            device.accept()
            raise AssertionError("tactile serve opened the device before checking the port")
        except BlockingIOError:
            pass
    finally:
        busy.close()
        device.close()


def test_serve_cli_takes_the_bracketed_ipv6_host_it_prints():
    out = subprocess.run([*CLI, "serve", "--device", "sim", "--host", "[not-ipv6]"],
                         capture_output=True, text=True, timeout=60)  # fmt: skip
    assert out.returncode == 2 and "::1 or [::1]" in out.stderr
    out = subprocess.run(
        [*CLI, "serve", "--device", "sim", "--host", "[::1]", "--osc-port", "0",
         "--seconds", "0.3", "--status-s", "0"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    if "Cannot assign" in out.stderr or "not supported" in out.stderr:
        return  # no IPv6 loopback on this machine: the host was taken, the address was not
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("osc://[::1]:")
