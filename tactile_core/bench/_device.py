"""Tables 3 and 4, the device link: streaming into ``tactile emulate`` on a pseudo-terminal
(idle and with another core busy), and how long a scene change takes to reach the wire."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from ..rendering.shapes import Line
from ._common import GAMMA, MU, SCENES, Table


class EmulatorProcess:
    """``tactile emulate`` in a subprocess, for the device benchmark. ``plain``: a format 2
    array without scheduled frames, so that what it receives shows the host's own timing.
    ``realtime``: it receives at real-time priority (``--realtime``), ``cpus``: it runs on
    those cores only, and ``socket``: on a local TCP port (``--socket``, no kernel worker
    between the host's write and its read), as the array's own processor would never wait
    for the host's."""

    def __init__(self, tmpdir, rate_hz, name, plain: bool = True, realtime: bool = False,
                 cpus=None, socket: bool = False):  # fmt: skip
        import os
        import subprocess
        import sys

        self.report = Path(tmpdir) / f"{name}.json"
        self.log = Path(tmpdir) / f"{name}.csv"
        cmd = [sys.executable, "-m", "tactile_core.cli", "emulate", "--rate", str(rate_hz)]
        cmd += ["--json", str(self.report), "--log", str(self.log)]
        cmd += ["--plain"] if plain else []
        cmd += ["--realtime"] if realtime else []
        cmd += ["--socket"] if socket else []
        self.proc = subprocess.Popen(
            cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True
        )
        if cpus is not None:
            try:
                os.sched_setaffinity(self.proc.pid, cpus)
            except (AttributeError, OSError):
                pass
        self.path = self.proc.stdout.readline().strip()

    def finish(self):
        import signal

        self.proc.send_signal(signal.SIGINT)
        self.proc.communicate(timeout=30)
        report = json.loads(self.report.read_text())
        rows = self.log.read_text().splitlines()[1:]
        log = np.array([[float(v) for v in r.split(",")] for r in rows]).reshape(len(rows), -1)
        return report, log


class _Busy:
    """Another process keeping one core busy (``with _Busy(): ...``)."""

    def __enter__(self):
        import subprocess
        import sys

        self.proc = subprocess.Popen([sys.executable, "-c", "while True: pass"])
        return self

    def __exit__(self, *exc):
        self.proc.kill()
        self.proc.wait()


def device_tables(rates=(100, 200, 300), seconds: float = 10.0, changes: int = 30):
    """Tables 3 and 4: streaming into the emulator, and parameter-change latency."""
    import contextlib
    import tempfile

    from ..device.link import SerialLink
    from ..rendering.scene import Scene
    from ..stream.streamer import Streamer

    rows = []
    latency_rows = []
    with tempfile.TemporaryDirectory() as tmpdir:
        for load in ("idle", "other core busy"):
            busy = _Busy() if load != "idle" else contextlib.nullcontext()
            with busy:
                for rate in rates:
                    emu = EmulatorProcess(tmpdir, rate, f"{load[:4]}-{rate}")
                    link = SerialLink(emu.path)
                    scene = Scene(SCENES["circle"], "AS", MU, GAMMA, rate_hz=rate)
                    streamer = Streamer(link, scene=scene)
                    streamer.start()
                    time.sleep(seconds)
                    stats = streamer.stop()
                    link.close()
                    report, log = emu.finish()
                    lost = stats.frames - report["frames"] + report["seq_gaps"]
                    # Receiver side, without the final all-off frame (sent at once on stop,
                    # off the deadline grid).
                    received = log[:-1, 0]
                    received_hz = (len(received) - 1) / (received[-1] - received[0])
                    err = np.abs(np.diff(received) - 1.0 / rate) * 1e3
                    rows.append(
                        [
                            load,
                            f"{rate}",
                            f"{received_hz:.2f}",
                            f"{100 * received_hz / rate:.2f}",
                            f"{stats.interval_error_p50_ms:.3f} / "
                            f"{stats.interval_error_p99_ms:.3f}",
                            f"{np.percentile(err, 50):.3f} / {np.percentile(err, 99):.3f}",
                            f"{err.max():.1f}",
                            f"{stats.late}",
                            f"{stats.skipped}",
                            f"{max(lost, 0)}",
                        ]
                    )
        for rate in rates:
            emu = EmulatorProcess(tmpdir, rate, f"latency-{rate}")
            link = SerialLink(emu.path)
            corner_a = Line((0.5, 0.5), (0.5, 0.5))  # lights channel 0 only
            corner_b = Line((4.5, 5.5), (4.5, 5.5))  # lights channel 29 only
            scene = Scene(corner_a, "CT", rate_hz=rate, dither=False)
            streamer = Streamer(link, scene=scene)
            streamer.start()
            rng = np.random.default_rng(1)
            marks = []
            time.sleep(0.3)
            for i in range(changes):
                time.sleep(0.05 + rng.uniform(0, 1.0 / rate))  # a random phase of the frame
                target = corner_b if i % 2 == 0 else corner_a
                marks.append((time.monotonic(), 29 if target is corner_b else 0))
                streamer.set_scene(scene.replace(shape=target))
            time.sleep(0.1)
            streamer.stop()
            link.close()
            report, log = emu.finish()
            received = report["started_monotonic"] + log[:, 0]
            latencies = []
            for k, (when, channel) in enumerate(marks):
                after = np.flatnonzero((received >= when) & (log[:, 2 + channel] > 0))
                next_change = marks[k + 1][0] if k + 1 < len(marks) else np.inf
                if len(after) and received[after[0]] < next_change:  # not overtaken
                    latencies.append(received[after[0]] - when)
            lat = np.array(latencies) * 1e3
            period_ms = 1e3 / rate
            latency_rows.append(
                [
                    f"{rate}",
                    f"{len(lat)} / {changes}",
                    f"{np.median(lat):.2f}",
                    f"{lat.max():.2f}",
                    f"{period_ms + 1:.2f}",
                    f"{(lat <= period_ms + 1).mean() * 100:.0f}",
                ]
            )
    headers = [
        "load",
        "rate Hz",
        "received Hz",
        "% of requested",
        "sender interval err p50 / p99 ms",
        "emulator interval err p50 / p99 ms",
        "emulator max err ms",
        "late > 1 ms",
        "skipped",
        "lost",
    ]
    notes = (
        f"{seconds:g} s of the Experiment 1 circle (AS, box S=4, dithered) per row, streamed by "
        "`Streamer` through pyserial into `tactile emulate` on a pseudo-terminal (a separate "
        "process). Interval error: |interval between successive frames - period|, at the sender "
        "(after each write) and at the emulator (on receipt). Lost: frames written but not "
        "decoded, plus gaps in the sequence numbers. `other core busy`: a second process "
        "spinning `while True: pass` for the whole run."
    )
    stream_table = Table("Streaming into the emulator", headers, rows, notes)
    latency_table = Table(
        "Parameter change to the wire",
        ["rate Hz", "changes seen", "median ms", "max ms", "target ms", "% within target"],
        latency_rows,
        f"{changes} scene changes at random phases of the frame; latency from `set_scene` "
        "to the emulator's receipt of the first frame of the new scene (both on the monotonic "
        "clock). Target: one frame period + 1 ms.",
    )
    return stream_table, latency_table
