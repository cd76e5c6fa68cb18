"""Measure ``tactile serve``: OSC message -> frame at the array latency, and a flood.

    python tools/serve_bench.py latency [--messages 600] [--rate 300] [--lead-ms 0] [--realtime]
    python tools/serve_bench.py split [--messages 600] [--rate 300]
    python tools/serve_bench.py flood [--flood-rate 50000] [--seconds 2] [--tuner]
    python tools/serve_bench.py tuner [--messages 600] [--rate 300] [--lead-ms 0] [--realtime]
    python tools/serve_bench.py points [--methods RO,BA,PK,GS,EN] [--seconds 6] [--pythonpath DIR]

Three processes, as in use: the array (the emulator on a pseudo-terminal, in a child process
that reports the ``CLOCK_MONOTONIC`` time it received each frame), ``tactile serve`` streaming
into it, and this one sending OSC with python-osc's ``SimpleUDPClient`` (``time.perf_counter``
is ``CLOCK_MONOTONIC`` on Linux, so the times compare directly).

latency: points alternate between the corner tactors (CT: one tactor lit each), one every 20-40
ms at a random phase of the frame clock; the latency of a message is the time from just before
``sendto`` to the emulator's receipt of the first frame showing it.

split: the server and the stream in this process, so that a tap gives each frame's write time:
OSC -> write and OSC -> emulator side by side.

tuner: the same as latency, through the tuner (offscreen, its display running) instead of
``tactile serve``: its OSC server, turned on as the toggle does, in its stream process.

flood: a second process sends ``/tactile/point/flood`` at ``--flood-rate`` for ``--seconds``;
the server's counters (``--json``) and the frame intervals at the array before, during and
after the flood are printed.

points: 64 points (``--points``) held on a 255-actuator layout (a jittered 15 x 17 lattice, a
profile written for the run; the points anywhere on it and up to 1.5 pitches beyond), one
method at a time:
``tactile serve`` at 300 Hz into the emulator, a sender
refreshing every point every 20 ms (3,200 messages a second); the stream's late frames (sent
more than 1 ms after their deadline) and skipped deadlines, the timed frames the array played
late (after their time on its clock: the lead, 20 ms, covers a late write) and how long after
their time it played them (p99), and the cost of a frame of those
points in this process, one point at a time (``PointFrames.at_each``, what every frame did
before) and all at once (``at_many``). ``--pythonpath DIR`` runs the emulator and the server
from another checkout (the code before a change).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np

CLI = [sys.executable, "-m", "tactile_core.cli"]
EMULATOR = textwrap.dedent("""
    import signal, sys, threading
    import numpy as np
    from tactile_core.device.emulator import Emulator
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *a: stop.set())
    emulator = Emulator()
    print(emulator.open(), flush=True)
    emulator.run(stop.is_set)
    times, seqs, levels = emulator.log.arrays()
    np.savez(sys.argv[1], time=times, levels=levels)
    emulator.close()
""")
FLOOD = textwrap.dedent("""
    import socket, sys, time
    from pythonosc.osc_message_builder import OscMessageBuilder
    port, rate, seconds = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
    b = OscMessageBuilder("/tactile/point/flood"); b.add_arg(2.5); b.add_arg(3.0)
    data = b.build().dgram
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sent = 0
    start = time.perf_counter()
    print(start, flush=True)
    while (now := time.perf_counter() - start) < seconds:
        while sent < int(now * rate):
            try:
                sock.sendto(data, ("127.0.0.1", port))
            except OSError:
                pass
            sent += 1
    print(sent, time.perf_counter(), flush=True)
""")


SENDER = textwrap.dedent("""
    import random, sys, time
    from pythonosc.udp_client import SimpleUDPClient
    client = SimpleUDPClient("127.0.0.1", int(sys.argv[1]))
    rng = random.Random(1)
    sent = []
    for j in range(int(sys.argv[2])):
        time.sleep(rng.uniform(0.02, 0.04))
        t = time.perf_counter()
        client.send_message("/tactile/point", [0.5, 0.5] if j % 2 == 0 else [4.5, 5.5])
        sent.append(t)
    print(" ".join(map(repr, sent)), flush=True)
""")


def first_showing(times, levels, sent):
    """Per message: time to the first frame from its send time on that shows its tactor."""
    lit = (levels[:, 0] > 0, levels[:, 29] > 0)  # channel 0 = tactor (0, 0); 29 = (4, 5)
    out = []
    for j, t in enumerate(sent):
        after = np.flatnonzero((times >= t) & lit[j % 2])
        if len(after):
            out.append(times[after[0]] - t)
    return np.array(out) * 1e3


def describe(lat, what):
    p50, p99 = np.percentile(lat, 50), np.percentile(lat, 99)
    return (f"{what}: p50 {p50:.2f} ms, p99 {p99:.2f} ms, max {lat.max():.2f} ms, "
            f"mean {lat.mean():.2f} ms ({len(lat)} messages)")  # fmt: skip


def latency_split(args) -> None:
    """The server and the stream in this process (a tap gives each frame's write time), the
    emulator and the sender in their own: OSC -> write, and write -> emulator."""
    from tactile_core.device.link import open_link
    from tactile_core.device.profile import default_profile
    from tactile_core.rendering.scene import Scene
    from tactile_core.serve import OscServer
    from tactile_core.stream.streamer import Streamer

    with tempfile.TemporaryDirectory() as folder:
        record = Path(folder) / "frames.npz"
        emulator = subprocess.Popen([sys.executable, "-c", EMULATOR, str(record)],
                                    stdout=subprocess.PIPE, text=True)  # fmt: skip
        profile = default_profile()
        link = open_link(emulator.stdout.readline().strip(), profile)
        written = []
        streamer = Streamer(link, profile, taps=[lambda t, s, lv: written.append((t, lv))])
        server = OscServer(streamer, profile, scene=Scene(method="CT", rate_hz=args.rate),
                           port=0, timeout_s=60.0)  # fmt: skip
        streamer.start()
        server.start()
        time.sleep(1.0)
        out = subprocess.run([sys.executable, "-c", SENDER, str(server.address[1]),
                              str(args.messages)], capture_output=True, text=True)  # fmt: skip
        time.sleep(0.2)
        server.stop()
        streamer.stop()
        link.close()
        emulator.send_signal(signal.SIGINT)
        emulator.communicate(timeout=30)
        with np.load(record) as data:
            times, levels = data["time"], data["levels"]
    sent = [float(x) for x in out.stdout.split()]
    w_times = np.array([t for t, _ in written])
    w_levels = np.array([np.frombuffer(lv, dtype=np.uint8) for _, lv in written])
    print(f"OSC message -> frame, {args.rate:g} Hz, frames for now, server in-process:")
    print("  " + describe(first_showing(w_times, w_levels, sent), "to the write"))
    print("  " + describe(first_showing(times, levels, sent), "to the emulator"))


class Rig:
    """The emulator and ``tactile serve`` as child processes."""

    def __init__(self, folder: Path, serve_args: list[str]):
        self.record = folder / "frames.npz"
        self.summary = folder / "serve.json"
        self.emulator = subprocess.Popen([sys.executable, "-c", EMULATOR, str(self.record)],
                                         stdout=subprocess.PIPE, text=True)  # fmt: skip
        path = self.emulator.stdout.readline().strip()
        self.serve = subprocess.Popen(
            [*CLI, "serve", "--device", path, "--osc-port", "0", "--status-s", "0",
             "--json", str(self.summary), *serve_args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        first = self.serve.stdout.readline().strip()
        if not first.startswith("osc://"):
            self.emulator.kill()
            raise SystemExit(f"tactile serve did not start: {self.serve.communicate()[1]}")
        self.port = int(first.rsplit(":", 1)[1])
        time.sleep(1.0)  # the hello exchange and the first frames
        self.pid = self.serve.pid

    def wait(self, seconds: float) -> None:
        time.sleep(seconds)

    def output_of(self, proc, timeout_s: float) -> str:
        return proc.communicate(timeout=timeout_s)[0]

    def finish(self):
        self.serve.send_signal(signal.SIGINT)
        self.serve.communicate(timeout=30)
        self.emulator.send_signal(signal.SIGINT)
        self.emulator.communicate(timeout=30)
        with np.load(self.record) as data:
            times, levels = data["time"], data["levels"]
        return times, levels, json.loads(self.summary.read_text())["serve"]


def latency(args) -> None:
    from pythonosc.udp_client import SimpleUDPClient

    with tempfile.TemporaryDirectory() as folder:
        rig = Rig(Path(folder), ["--method", "CT", "--rate", str(args.rate), "--timeout-ms",
                                 "60000", "--lead-ms", str(args.lead_ms)]
                  + (["--realtime"] if args.realtime else []))  # fmt: skip
        client = SimpleUDPClient("127.0.0.1", rig.port)
        rng = random.Random(1)
        sent = []
        for j in range(args.messages):
            x, y = (0.5, 0.5) if j % 2 == 0 else (4.5, 5.5)
            time.sleep(rng.uniform(0.02, 0.04))
            t = time.perf_counter()
            client.send_message("/tactile/point", [x, y])
            sent.append(t)
        time.sleep(0.2)
        times, levels, served = rig.finish()
    lat = first_showing(times, levels, sent)
    print(f"OSC message -> frame at the emulator (its time to play, for a timed frame), "
          f"tactile serve at {args.rate:g} Hz, lead {args.lead_ms:g} ms"
          f"{', real-time priority' if args.realtime else ''}:")  # fmt: skip
    print("  " + describe(lat, f"{len(sent)} sent"))
    print(f"  server: {served['messages']} messages, {served['points']} points, "
          f"{served['problems']} problems")  # fmt: skip


class TunerRig:
    """The emulator as a child process and the tuner (offscreen, its display running) streaming
    into it, its OSC server turned on as the toggle does; the same interface as :class:`Rig`."""

    def __init__(self, folder: Path, *, method="CT", rate=300.0, lead_ms=0.0, realtime=False):
        os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
        from PySide6 import QtCore, QtWidgets

        from tactile_tuner.window import MainWindow

        settings = QtCore.QSettings  # the bench's own settings, never the user's
        settings.setDefaultFormat(settings.Format.IniFormat)
        settings.setPath(settings.Format.IniFormat, settings.Scope.UserScope, str(folder))
        self.record = folder / "frames.npz"
        self.emulator = subprocess.Popen([sys.executable, "-c", EMULATOR, str(self.record)],
                                         stdout=subprocess.PIPE, text=True)  # fmt: skip
        path = self.emulator.stdout.readline().strip()
        self.app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
        self.win = win = MainWindow(restore=False, realtime=realtime)
        win.resize(1280, 720)
        win.show()
        win.device.set_lead(lead_ms)
        win.device.connect_device(path)
        win.state.update(method=method, rate_hz=rate)
        self.pump(lambda: win.device.stats.frames > 300, 30)
        win.serve.port = 0
        win.serve.set_serving(True)
        self.pump(lambda: win.serve.serving == "on", 30)
        self.port = win.serve.address[1]
        self.pid = win.device.streamer._proc.pid  # the stream process, where the server is
        self.display_hz = 0.0

    def pump(self, until, timeout_s: float) -> None:
        """Run the Qt event loop (the display timer, the stream's events) until ``until()``."""
        deadline = time.monotonic() + timeout_s
        while not until():
            if time.monotonic() > deadline:
                raise SystemExit("the tuner did not get there in time")
            self.app.processEvents()
            time.sleep(0.002)

    def wait(self, seconds: float) -> None:
        end = time.monotonic() + seconds
        self.pump(lambda: time.monotonic() > end, seconds + 5)

    def output_of(self, proc, timeout_s: float) -> str:
        self.pump(lambda: proc.poll() is not None, timeout_s)
        return proc.stdout.read()

    def finish(self):
        self.display_hz = self.win.tune.display.display_rate()[0]
        served = self.win.serve.stats.to_dict()
        self.win.close()
        self.emulator.send_signal(signal.SIGINT)
        self.emulator.communicate(timeout=30)
        with np.load(self.record) as data:
            return data["time"], data["levels"], served


def latency_tuner(args) -> None:
    """OSC message -> frame at the emulator through the tuner's server (in its stream process)."""
    with tempfile.TemporaryDirectory() as folder:
        rig = TunerRig(Path(folder), rate=args.rate, lead_ms=args.lead_ms, realtime=args.realtime)
        command = [sys.executable, "-c", SENDER, str(rig.port), str(args.messages)]
        sender = subprocess.Popen(command, stdout=subprocess.PIPE, text=True)
        out = rig.output_of(sender, 60 + args.messages * 0.05)
        rig.wait(0.2)
        times, levels, served = rig.finish()
    sent = [float(x) for x in out.split()]
    print(f"OSC message -> frame at the emulator (its time to play, for a timed frame), "
          f"the tuner's server at {args.rate:g} Hz, lead {args.lead_ms:g} ms"
          f"{', real-time priority' if args.realtime else ''}:")  # fmt: skip
    print("  " + describe(first_showing(times, levels, sent), f"{len(sent)} sent"))
    print(f"  server: {served['messages']} messages, {served['points']} points, "
          f"{served['problems']} problems; the tuner's display at "
          f"{rig.display_hz:.0f} Hz")  # fmt: skip


def intervals(times, start, end, period):
    inside = times[(times >= start) & (times < end)]
    errors = np.abs(np.diff(inside) - period) * 1e3
    if not len(errors):
        return "no frames"
    return (f"{len(inside)} frames, |interval - {period * 1e3:.2f} ms| p50 "
            f"{np.percentile(errors, 50):.3f} ms, p99 {np.percentile(errors, 99):.3f} ms, "
            f"max {errors.max():.3f} ms")  # fmt: skip


def cpu_s(pid: int) -> float:
    """User + system CPU seconds of process ``pid`` (Linux), or NaN."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return float("nan")
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def flood(args) -> None:
    with tempfile.TemporaryDirectory() as folder:
        if args.tuner:
            rig = TunerRig(Path(folder), method="AS")
        else:
            rig = Rig(Path(folder), ["--rate", "300", "--lead-ms", "0"])
        idle0, t0 = cpu_s(rig.pid), time.perf_counter()
        rig.wait(args.seconds)
        idle = (cpu_s(rig.pid) - idle0) / (time.perf_counter() - t0)
        busy0 = cpu_s(rig.pid)
        proc = subprocess.Popen([sys.executable, "-c", FLOOD, str(rig.port), str(args.flood_rate),
                                 str(args.seconds)], stdout=subprocess.PIPE, text=True)  # fmt: skip
        out = rig.output_of(proc, args.seconds + 60)
        busy = (cpu_s(rig.pid) - busy0) / args.seconds
        first, last = out.splitlines()
        start = float(first)
        sent, end = int(last.split()[0]), float(last.split()[1])
        rig.wait(args.seconds)
        times, _, served = rig.finish()
    who = "the tuner's stream process" if args.tuner else "tactile serve"
    print(f"flood: {sent} messages in {end - start:.2f} s ({sent / (end - start):,.0f}/s) "
          f"from a second process")  # fmt: skip
    print(f"  server: {served['datagrams']} datagrams read, {served['kernel_dropped']} dropped by "
          f"the system (buffer full), {served['flood_dropped']} dropped over the rate limit, "
          f"{served['points']} points applied, {served['errors']} errors")  # fmt: skip
    print(f"  {who}'s CPU: {idle:.0%} of a core before, {busy:.0%} during the flood")
    period = 1 / 300
    print(f"  frames at the array before: {intervals(times, start - args.seconds, start, period)}")
    print(f"  frames at the array during: {intervals(times, start, end, period)}")
    print(f"  frames at the array after:  {intervals(times, end, end + args.seconds, period)}")


POINTS_SENDER = textwrap.dedent("""
    import random, sys, time
    from pythonosc.udp_client import SimpleUDPClient
    client = SimpleUDPClient("127.0.0.1", int(sys.argv[1]))
    rng = random.Random(2)
    points = [(rng.uniform(-1.5, 16.5), rng.uniform(-1.5, 18.5)) for _ in range(64)]
    points = points[: int(sys.argv[3])]
    end = time.perf_counter() + float(sys.argv[2])
    k = 0
    while time.perf_counter() < end:  # every point every 20 ms, moving a little
        for i, (x, y) in enumerate(points):
            client.send_message(f"/tactile/point/p{i}", [x + 0.3 * (k % 7) / 7, y, 0.8])
        k += 1
        time.sleep(0.02)
""")


def jittered_profile(path: Path) -> None:
    """A device profile of 255 actuators on a jittered 15 x 17 lattice (pitch units)."""
    rng = random.Random(255)
    actuators = [[round(c + 0.5 + rng.uniform(-0.2, 0.2), 4),
                  round(r + 0.5 + rng.uniform(-0.2, 0.2), 4)]
                 for r in range(17) for c in range(15)]  # fmt: skip
    path.write_text(json.dumps({
        "format": "tactile-device-profile", "version": 1, "name": "jitter-255",
        "pitch_mm": 10.0, "levels": 23, "baud": 3_000_000,
        "layout": {"units": "pitch", "actuators": actuators},
    }))  # fmt: skip


def frame_cost_us(profile_path: Path, method: str, n: int) -> tuple[float, float]:
    """Median us of a frame of the sender's ``n`` points, one at a time and all at once."""
    from tactile_core.device.profile import load_profile
    from tactile_core.rendering.points import FreePoints
    from tactile_core.rendering.scene import Scene

    target = load_profile(str(profile_path)).layout
    rng = random.Random(2)
    points = FreePoints(timeout_s=None)
    for i in range(64):
        x, y = rng.uniform(-1.5, 16.5), rng.uniform(-1.5, 18.5)
        if i < n:
            points.set(f"p{i}", x, y, 0.8)
    live = Scene(method=method, mu=0.33, gamma=0.7, source=points).live(target, 300.0)
    table = points.points
    out = []
    for at in (live.at_each, live.at_many):
        times = []
        for _ in range(300):
            t = time.perf_counter()
            at(table, 0.0)
            times.append(time.perf_counter() - t)
        out.append(float(np.median(times)) * 1e6)
    return out[0], out[1]


def many_points(args) -> None:
    env = dict(os.environ, PYTHONPATH=args.pythonpath) if args.pythonpath else None
    with tempfile.TemporaryDirectory() as folder:
        profile = Path(folder) / "jitter-255.json"
        jittered_profile(profile)
        print(f"{args.points} points on 255 actuators, tactile serve at 300 Hz for "
              f"{args.seconds:g} s"
              f"{', real-time priority' if args.realtime else ''}"
              f"{' (code from ' + args.pythonpath + ')' if args.pythonpath else ''}:")  # fmt: skip
        print(
            "| method | frames | written > 1 ms late | skipped | played late at the array | "
            "played p99 ms after its time | one at a time us/frame | all at once us/frame |"
        )
        for method in args.methods.split(","):
            summary = Path(folder) / f"{method}.json"
            played = Path(folder) / f"{method}-array.json"
            emulator = subprocess.Popen([*CLI, "emulate", "--profile", str(profile),
                                         "--json", str(played)], env=env,
                                        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                        text=True)  # fmt: skip
            path = emulator.stdout.readline().strip()
            serve = subprocess.Popen(
                [*CLI, "serve", "--device", path, "--profile", str(profile), "--method", method,
                 "--osc-port", "0", "--status-s", "0", "--json", str(summary),
                 "--seconds", str(args.seconds + 1.0), *(["--realtime"] if args.realtime else [])],
                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
            )  # fmt: skip
            port = serve.stdout.readline().strip().rsplit(":", 1)[1]
            time.sleep(0.5)
            subprocess.run([sys.executable, "-c", POINTS_SENDER, port, str(args.seconds),
                            str(args.points)])  # fmt: skip
            serve.communicate(timeout=60)
            emulator.send_signal(signal.SIGINT)
            emulator.communicate(timeout=30)
            stream = json.loads(summary.read_text())["stream"]
            array = json.loads(played.read_text())
            each, many = frame_cost_us(profile, method, args.points)
            print(f"| {method} | {stream['frames']} | {stream['late']} | {stream['skipped']} | "
                  f"{array['timed_late']} | {array['play_lag_p99_ms']:.2f} | "
                  f"{each:.0f} | {many:.0f} |")  # fmt: skip


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="what", required=True)
    lat = sub.add_parser("latency")
    lat.add_argument("--messages", type=int, default=600)
    lat.add_argument("--rate", type=float, default=300.0)
    lat.add_argument("--lead-ms", type=float, default=0.0)
    lat.add_argument("--realtime", action="store_true", help="tactile serve --realtime")
    split = sub.add_parser("split")
    split.add_argument("--messages", type=int, default=600)
    split.add_argument("--rate", type=float, default=300.0)
    tuner = sub.add_parser("tuner")
    tuner.add_argument("--messages", type=int, default=600)
    tuner.add_argument("--rate", type=float, default=300.0)
    tuner.add_argument("--lead-ms", type=float, default=0.0)
    tuner.add_argument("--realtime", action="store_true", help="the stream's --realtime")
    fl = sub.add_parser("flood")
    fl.add_argument("--flood-rate", type=float, default=50_000.0)
    fl.add_argument("--seconds", type=float, default=2.0)
    fl.add_argument("--tuner", action="store_true", help="through the tuner's server")
    pts = sub.add_parser("points")
    pts.add_argument("--methods", default="RO,BA,PK,GS,EN")
    pts.add_argument("--seconds", type=float, default=6.0)
    pts.add_argument("--pythonpath", default=None, help="run the code of this checkout")
    pts.add_argument("--realtime", action="store_true", help="tactile serve --realtime")
    pts.add_argument("--points", type=int, default=64, help="points held (1 to 64)")
    args = p.parse_args(argv)
    commands = {"latency": latency, "split": latency_split, "flood": flood, "tuner": latency_tuner,
                "points": many_points}  # fmt: skip
    commands[args.what](args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
