"""GUI responsiveness: the tuner's display refresh while it streams at 300 Hz.

Run by ``tactile bench --part gui`` or ``tactile-tuner --bench`` (it needs Qt, so it lives
with the GUI, registered under the entry point group ``tactile.bench``).
"""

from __future__ import annotations

import contextlib
import os
import tempfile
import time

import numpy as np


@contextlib.contextmanager
def _offscreen_app():
    """A QApplication (offscreen unless a display is set) whose settings go to a temporary
    folder, so a benchmark never touches the user's last session."""
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from PySide6 import QtCore, QtWidgets

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    with tempfile.TemporaryDirectory() as tmpdir:
        QtCore.QCoreApplication.setOrganizationName("tactile-tuner-bench")
        QtCore.QSettings.setDefaultFormat(QtCore.QSettings.Format.IniFormat)
        QtCore.QSettings.setPath(
            QtCore.QSettings.Format.IniFormat, QtCore.QSettings.Scope.UserScope, tmpdir
        )
        yield app, tmpdir


RECEIVERS = {
    "array": "standing in for the array's own processor, which never waits for the host: at "
    "real-time priority on the GUI's core (it preempts the GUI, and leaves the stream's core to "
    "the stream), on a local TCP port (`--socket --realtime`: loopback delivers each write in "
    "the writer's context, where a pseudo-terminal hands the bytes to a kernel worker that "
    "waits whenever the GUI paints)",
    "ordinary": "an ordinary process on a pseudo-terminal (a third process on the two cores)",
}
"""How the benchmark's ``tactile emulate`` receives (see :func:`gui_table`)."""


def _emulator(tmpdir, rate_hz: float, name: str, receiver: str):
    """``tactile emulate`` for a row, receiving as ``receiver`` says (:data:`RECEIVERS`)."""
    from tactile_core.bench import EmulatorProcess
    from tactile_core.stream.process import own_core

    if receiver == "ordinary":
        return EmulatorProcess(tmpdir, rate_hz, name)
    cores = own_core()
    return EmulatorProcess(
        tmpdir, rate_hz, name, realtime=True, cpus=None if cores is None else cores[1], socket=True
    )


def _cli_row(tmpdir, seconds: float, rate_hz: float, receiver: str, realtime: bool) -> list:
    """The same measurement for ``tactile stream`` (no GUI), the yardstick of the tuner's."""
    import subprocess
    import sys

    from tactile_core.bench import GAMMA, MU

    emu = _emulator(tmpdir, rate_hz, f"gui-cli-{receiver}-{realtime}", receiver)
    proc = subprocess.run(
        [sys.executable, "-m", "tactile_core.cli", "stream", "--device", emu.path,
         "--shape", "circle:2.5,3,2", "--method", "AS", "--mu", str(MU), "--gamma", str(GAMMA),
         "--rate", str(rate_hz), "--filter", "box", "--dither", "--seconds", str(seconds + 0.5),
         *(["--realtime"] if realtime else [])],
        capture_output=True, text=True, timeout=seconds + 60,
    )  # fmt: skip
    report, log = emu.finish()
    received = log[:-1, 0]
    received = received[received >= received[-1] - seconds]
    err = np.abs(np.diff(received) - 1.0 / rate_hz) * 1e3
    sender = proc.stdout.split("interval error:")[1].split("\n")[0].strip()
    p50, p99 = (float(x.split()[1]) for x in sender.split(","))
    return [
        "`tactile stream --realtime`, no GUI" if realtime else
        "`tactile stream`, no GUI (the yardstick)",
        "-",
        "-",
        f"{(len(received) - 1) / (received[-1] - received[0]):.1f}",
        f"{p50:.3f} / {p99:.3f}",
        f"{np.percentile(err, 50):.3f} / {np.percentile(err, 99):.3f}",
        "-",
        "-",
        f"{report['seq_gaps'] + report['bad_frames']['crc']}",
    ]  # fmt: skip


def gui_table(seconds: float = 10.0, rate_hz: float = 300.0, receiver: str = "array"):
    """Rows: display refresh and stream statistics with the tuner running, per situation.

    ``receiver``: how ``tactile emulate`` receives (:data:`RECEIVERS`): ``"array"`` (the
    default) at real-time priority on the stream's core, as an array's own processor that
    never waits for the host; ``"ordinary"`` as an ordinary third process on the two cores,
    waiting whenever the GUI paints.
    """
    from PySide6 import QtCore

    import tactile_core as tc
    from tactile_core.bench import GAMMA, MU, Table

    rows = []
    with _offscreen_app() as (app, tmpdir):
        rows.append(_cli_row(tmpdir, seconds, rate_hz, receiver, realtime=False))
        rows.append(_cli_row(tmpdir, seconds, rate_hz, receiver, realtime=True))
        from .window import MainWindow

        situations = (
            ("Tune tab", True, True),
            ("Compare tab (4 heatmaps, 4 plots)", True, True),
            ("Tune tab, mu slider dragged", True, True),
            ("Tune tab, mu slider dragged, without real-time priority", True, False),
            ("Tune tab, stream as a thread of the GUI", False, False),
            ("Tune tab, mu slider dragged, stream as a thread", False, False),
        )
        for situation, process, realtime in situations:
            emu = _emulator(tmpdir, rate_hz, f"gui-{receiver}-{len(rows)}", receiver)
            window = MainWindow(
                device_url=emu.path, restore=False, process=process, realtime=realtime
            )
            window.resize(1400, 900)
            window.show()
            scene = window.state.scene.replace(
                shape=tc.Circle((2.5, 3.0), 2.0), method="AS", mu=MU, gamma=GAMMA, rate_hz=rate_hz
            )
            window.state.set_scene(scene)
            if situation.startswith("Compare"):
                window.tabs.setCurrentWidget(window.compare)
            drag = QtCore.QTimer()
            if "dragged" in situation:
                values = iter(
                    np.tile(np.r_[np.linspace(0.2, 0.6, 30), np.linspace(0.6, 0.2, 30)], 1000)
                )
                spin = window.controls.correction.mu_spin
                drag.timeout.connect(lambda v=values, spin=spin: spin.setValue(next(v)))
                drag.start(33)
            loop = QtCore.QEventLoop()
            QtCore.QTimer.singleShot(500, loop.quit)  # settle
            loop.exec()
            window.tune.display.tick_times.clear()
            start = time.perf_counter()
            loop = QtCore.QEventLoop()
            QtCore.QTimer.singleShot(round(seconds * 1000), loop.quit)
            loop.exec()
            drag.stop()
            ticks = np.array([t for t in window.tune.display.tick_times if t >= start])
            stats = window.device.stats
            window.close()
            report, log = emu.finish()
            received = log[:-1, 0]
            received = received[received >= received[-1] - seconds]
            received_hz = (len(received) - 1) / (received[-1] - received[0])
            err = np.abs(np.diff(received) - 1.0 / rate_hz) * 1e3
            interval = np.diff(ticks) * 1e3
            rows.append(
                [
                    situation,
                    f"{(len(ticks) - 1) / (ticks[-1] - ticks[0]):.1f}",
                    f"{np.percentile(interval, 99):.1f}",
                    f"{received_hz:.1f}",
                    f"{stats.interval_error_p50_ms:.3f} / {stats.interval_error_p99_ms:.3f}",
                    f"{np.percentile(err, 50):.3f} / {np.percentile(err, 99):.3f}",
                    f"{stats.late}",
                    f"{stats.skipped}",
                    f"{report['seq_gaps'] + report['bad_frames']['crc']}",
                ]
            )
    app.processEvents()
    headers = [
        "situation",
        "display Hz",
        "display p99 interval ms",
        "received Hz",
        "sender interval err p50 / p99 ms",
        "emulator interval err p50 / p99 ms",
        "late > 1 ms",
        "skipped",
        "lost",
    ]
    notes = (
        f"The tuner offscreen, streaming the Experiment 1 circle (AS, box S=4, dithered) at "
        f"{rate_hz:g} Hz into `tactile emulate` for {seconds:g} s per row; the display timer asks "
        "for 60 Hz. 'mu slider dragged': the mu box changes 30 times a second, so 30 new scenes "
        "a second reach the streamer. The stream runs in its own process unless the row says "
        "'as a thread' (the streamer in the GUI's process, sharing its interpreter lock). "
        "Sender: intervals between writes in the streaming process; emulator: between receipts "
        f"in `tactile emulate`, {RECEIVERS[receiver]}. The tuner asks for real-time priority "
        "for the stream by default (SCHED_FIFO 10; `--no-realtime` does not). The "
        "emulator is a format 2 array without scheduled frames (`--plain`), so what it receives "
        "is the host's own timing: what an array that cannot schedule gets. The stream process "
        "runs on a core of its own (the GUI on the other)."
    )
    title = "The tuner while streaming"
    if receiver != "array":
        title += f" ({receiver} receiver)"
    return Table(title, headers, rows, notes)


def _latencies(report, log, marks) -> np.ndarray:
    """Milliseconds from each change to the first received frame showing it (changes that a
    later change overtook before any frame showed them are left out)."""
    received = report["started_monotonic"] + log[:, 0]
    out = []
    for k, (when, channel) in enumerate(marks):
        after = np.flatnonzero((received >= when) & (log[:, 2 + channel] > 0))
        next_change = marks[k + 1][0] if k + 1 < len(marks) else np.inf
        if len(after) and received[after[0]] < next_change:
            out.append(received[after[0]] - when)
    return np.array(out) * 1e3


def gui_latency_table(rate_hz: float = 300.0, changes: int = 30):
    """Parameter change in the tuner to the first changed frame on the wire (via the process)."""
    from PySide6 import QtCore

    import tactile_core as tc
    from tactile_core.bench import EmulatorProcess, Table

    rows = []
    with _offscreen_app() as (app, tmpdir):
        from .window import MainWindow

        for process in (True, False):
            emu = EmulatorProcess(tmpdir, rate_hz, f"latency-{process}")
            window = MainWindow(device_url=emu.path, restore=False, process=process)
            window.resize(1400, 900)
            window.show()
            corners = (tc.Line((0.5, 0.5), (0.5, 0.5)), tc.Line((4.5, 5.5), (4.5, 5.5)))
            window.state.update(shape=corners[0], method="CT", rate_hz=rate_hz, dither=False)
            marks = []
            rng = np.random.default_rng(2)

            loop = QtCore.QEventLoop()

            def change(i, marks=marks, window=window, corners=corners, loop=loop, rng=rng):
                # Each change schedules the next, ~70 ms later at a random phase of the frame,
                # so that a busy moment of the GUI cannot fire two at once.
                if i == changes:
                    QtCore.QTimer.singleShot(300, loop.quit)
                    return
                target = corners[(i + 1) % 2]
                marks.append((time.monotonic(), 29 if target is corners[1] else 0))
                window.state.update(shape=target)
                delay = 70 + int(rng.uniform(0, 1000.0 / rate_hz))
                QtCore.QTimer.singleShot(delay, lambda: change(i + 1))

            QtCore.QTimer.singleShot(400, lambda change=change: change(0))
            loop.exec()
            window.close()
            report, log = emu.finish()
            lat = _latencies(report, log, marks)
            target_ms = 1000.0 / rate_hz + 1.0
            rows.append(
                [
                    "own process" if process else "thread of the GUI",
                    f"{len(lat)} / {changes}",
                    f"{np.median(lat):.2f}",
                    f"{lat.max():.2f}",
                    f"{target_ms:.2f}",
                    f"{(lat <= target_ms).mean() * 100:.0f}",
                ]
            )
    app.processEvents()
    return Table(
        "Parameter change in the tuner to the wire",
        ["stream", "changes seen", "median ms", "max ms", "target ms", "% within target"],
        rows,
        f"The tuner streaming at {rate_hz:g} Hz into `tactile emulate`; the shape is switched "
        f"{changes} times through the tuner's state (as a control does) at random phases; "
        "latency from the change to the emulator's receipt of the first frame of the new shape.",
    )


def run(quick: bool = False, out=print) -> list:
    """The GUI's benchmark tables (``tactile bench --part gui`` and ``tactile-tuner --bench``),
    printed as Markdown; returns them."""
    seconds = 3.0 if quick else 10.0
    tables = [gui_table(seconds), gui_table(seconds, receiver="ordinary"), gui_latency_table()]
    for table in tables:
        out(table.markdown())
        out("")
    return tables
