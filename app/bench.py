"""GUI responsiveness: the tuner's display refresh while it streams at 300 Hz.

Run by ``tactile bench --part gui`` (it needs Qt, so it lives in ``app``).
"""

from __future__ import annotations

import os
import tempfile
import time

import numpy as np


def gui_table(seconds: float = 10.0, rate_hz: float = 300.0):
    """Rows: display refresh and stream statistics with the tuner running, per situation."""
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from PySide6 import QtCore, QtWidgets

    import tactile_core as tc
    from tactile_core.bench import GAMMA, MU, Table, _EmulatorProcess

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    rows = []
    with tempfile.TemporaryDirectory() as tmpdir:
        QtCore.QCoreApplication.setOrganizationName("tactile-tuner-bench")
        QtCore.QSettings.setDefaultFormat(QtCore.QSettings.Format.IniFormat)
        QtCore.QSettings.setPath(
            QtCore.QSettings.Format.IniFormat, QtCore.QSettings.Scope.UserScope, tmpdir
        )
        from .window import MainWindow

        situations = (
            ("Tune tab", True),
            ("Compare tab (4 heatmaps, 4 plots)", True),
            ("Tune tab, mu slider dragged", True),
            ("Tune tab, stream as a thread of the GUI", False),
            ("Tune tab, mu slider dragged, stream as a thread", False),
        )
        for situation, process in situations:
            emu = _EmulatorProcess(tmpdir, rate_hz, f"gui-{len(rows)}")
            window = MainWindow(device_url=emu.path, restore=False, process=process)
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
                spin = window.controls.mu_spin
                drag.timeout.connect(lambda v=values, spin=spin: spin.setValue(next(v)))
                drag.start(33)
            loop = QtCore.QEventLoop()
            QtCore.QTimer.singleShot(500, loop.quit)  # settle
            loop.exec()
            window._display_times.clear()
            start = time.perf_counter()
            loop = QtCore.QEventLoop()
            QtCore.QTimer.singleShot(round(seconds * 1000), loop.quit)
            loop.exec()
            drag.stop()
            ticks = np.array([t for t in window._display_times if t >= start])
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
        "'as a thread' (the streamer in the GUI's process, sharing its interpreter lock)."
    )
    return Table("The tuner while streaming", headers, rows, notes)
