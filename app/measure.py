"""The Array menu's "Measure the motors...": ``tactile measure`` run from the tuner.

The dialog runs the command in a child process (the core's procedure, unchanged) on the device
the tuner streams to, which the tuner lets go of meanwhile (the simulated array's run needs the
simulated sensor, ``sim``); it shows the command's lines, asks for the sensor to be moved when
the command asks, and offers to use the profile it wrote.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from PySide6 import QtCore, QtWidgets

from tactile_core.device.profile import user_profiles_dir

PROMPT = "put the sensor on tactor"


class MeasureDialog(QtWidgets.QDialog):
    """Measure the motors of the tuner's device with a sensor on an audio input.

    Parameters
    ----------
    device : DeviceController
        The tuner's device: its URL and profile; its link is let go of while measuring.
    files : FileActions
        Uses the written profile when asked.
    """

    def __init__(self, device, files, parent=None):
        super().__init__(parent)
        self.setWindowTitle("Measure the motors")
        self.setObjectName("measure_dialog")
        self.device, self.files = device, files
        self.result: dict | None = None
        self._url: str | None = None
        self.process = QtCore.QProcess(self)
        self.process.readyReadStandardError.connect(self._on_process_stderr)
        self.process.finished.connect(self._on_process_finished)
        form = QtWidgets.QFormLayout()
        self.input_edit = QtWidgets.QLineEdit("sim" if device.simulated else "audio:?channel=1")
        self.input_edit.setToolTip(
            "audio:NAME?channel=N (the sensor's audio input, channel from 1), or sim: the "
            "simulated sensor on the simulated array"
        )
        form.addRow("Sensor input", self.input_edit)
        self.tactors_edit = QtWidgets.QLineEdit("all")
        self.tactors_edit.setToolTip("all, or names and indices: r0c0,r2c3")
        form.addRow("Tactors", self.tactors_edit)
        self.quick_check = QtWidgets.QCheckBox("quick (8 s a tactor instead of 14 s)")
        form.addRow("", self.quick_check)
        name = f"{device.profile.name}-measured.json"
        self.out_edit = QtWidgets.QLineEdit(str(user_profiles_dir() / name))
        form.addRow("Write the profile to", self.out_edit)
        self.log_view = QtWidgets.QPlainTextEdit(readOnly=True)
        self.log_view.setObjectName("measure_log")
        self.log_view.setMinimumSize(560, 220)
        self.measure_button = QtWidgets.QPushButton("Measure")
        self.next_button = QtWidgets.QPushButton("Sensor in place: go on")
        self.use_button = QtWidgets.QPushButton("Use the measured profile")
        self.stop_button = QtWidgets.QPushButton("Stop")
        for button in (self.next_button, self.use_button, self.stop_button):
            button.setEnabled(False)
        self.measure_button.clicked.connect(self.start)
        self.next_button.clicked.connect(self._on_next_button_clicked)
        self.use_button.clicked.connect(self._on_use_button_clicked)
        self.stop_button.clicked.connect(self.stop)
        buttons = QtWidgets.QHBoxLayout()
        for button in (self.measure_button, self.next_button, self.stop_button, self.use_button):
            buttons.addWidget(button)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(form)
        layout.addWidget(self.log_view)
        layout.addLayout(buttons)

    def arguments(self) -> list[str]:
        """The ``tactile measure`` command line of the dialog's fields."""
        profile = self.device.profile
        args = ["measure", "--input", self.input_edit.text().strip(), "--device",
                self.device.url or "sim", "--profile", profile.path or profile.name,
                "--tactors", self.tactors_edit.text().strip() or "all", "--json"]  # fmt: skip
        if self.quick_check.isChecked():
            args.append("--quick")
        if self.out_edit.text().strip():
            args += ["--out", self.out_edit.text().strip()]
        return args

    def start(self) -> None:
        """Let go of the device and run the command."""
        if self.process.state() != QtCore.QProcess.ProcessState.NotRunning:
            return
        out = self.out_edit.text().strip()
        if out:
            Path(out).parent.mkdir(parents=True, exist_ok=True)
        self._url = self.device.url
        self.device.disconnect_device()  # the command opens the device itself
        self.result = None
        self.log_view.clear()
        self.measure_button.setEnabled(False)
        self.use_button.setEnabled(False)
        self.stop_button.setEnabled(True)
        self.process.start(sys.executable, ["-m", "tactile_core.cli", *self.arguments()])

    def stop(self) -> None:
        """End the command (the array goes all off)."""
        if self.process.state() != QtCore.QProcess.ProcessState.NotRunning:
            self.process.terminate()

    def _log(self, text: str) -> None:
        self.log_view.appendPlainText(text)

    def _on_process_stderr(self) -> None:
        text = bytes(self.process.readAllStandardError()).decode("utf-8", "replace")
        for line in text.splitlines():
            self._log(line)
            if line.startswith(PROMPT):
                self.next_button.setEnabled(True)

    def _on_next_button_clicked(self) -> None:
        self.next_button.setEnabled(False)
        self.process.write(b"\n")

    def _on_process_finished(self, code: int, status) -> None:
        out = bytes(self.process.readAllStandardOutput()).decode("utf-8", "replace").strip()
        try:
            self.result = json.loads(out.splitlines()[-1]) if out else None
        except (json.JSONDecodeError, IndexError):
            self.result = None
        if self.result is not None:
            r = self.result
            self._log(f"median over {len(r['tactors'])} tactors: spin-up {r['tau_up_ms']} ms, "
                      f"run-down {r['tau_down_ms']} ms, delay {r['delay_ms']} ms")  # fmt: skip
        written = (
            code == 0 and self.out_edit.text().strip() and Path(self.out_edit.text()).is_file()
        )
        self._log(
            f"finished (exit {code})" + (f"; wrote {self.out_edit.text()}" if written else "")
        )
        self.use_button.setEnabled(bool(written))
        self.measure_button.setEnabled(True)
        self.next_button.setEnabled(False)
        self.stop_button.setEnabled(False)
        if self._url is not None:
            self.device.connect_device(self._url)

    def _on_use_button_clicked(self) -> None:
        self.files.use_profile(self.out_edit.text().strip())
        self.accept()

    def closeEvent(self, event) -> None:
        self.stop()
        self.process.waitForFinished(5000)
        super().closeEvent(event)


def show_measure_dialog(window) -> MeasureDialog:
    """Open the dialog for ``window``'s device (kept on the window while open)."""
    dialog = MeasureDialog(window.device, window.files, window)
    window.measure_dialog = dialog
    dialog.show()
    return dialog
