"""The Experiments tab: the paper's experiments and the calibration, run from the keyboard."""

from __future__ import annotations

import io
import time
from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.device import default_profile
from tactile_core.experiments import RUNNERS, open_session
from tactile_core.experiments.analysis import analyze
from tactile_core.scene import Scene

from .state import TunerState

TITLES = {
    "exp1": "Experiment 1: ratings of the four methods",
    "exp2": "Experiment 2: shortest line whose direction is felt (AS)",
    "exp3": "Experiment 3: circle or square, per method",
    "calibration": "Tactor calibration: detection threshold of every tactor",
}
KEYS = {
    "continue": "any letter key to go on",
    "prepare": "1-4 to switch methods, a letter key to go on",
    "rating": "type 0-100, then Enter",
    "direction": "arrow keys",
    "shape": "C for circle, S for square",
    "detect": "Y (felt) or N (not felt); R to feel it again",
}
GAP_S = 0.8  # the array is off between a question's answer and the next stimulus


class ExperimentsPanel(QtWidgets.QWidget):
    """Runs an experiment runner against the array, driven from the keyboard.

    The screen never shows the stimulus (the views are hidden while a run is active); the
    array plays each trial's scene through the tuner's state, so it reaches a device or the
    simulated array like any other scene.
    """

    running_changed = QtCore.Signal(bool)
    error_raised = QtCore.Signal(str)
    calibration_done = QtCore.Signal(object)
    """``(offset, gain, threshold)`` lists when a calibration run finishes."""

    def __init__(self, state: TunerState, profile=None, stats=None, parent=None):
        super().__init__(parent)
        self.state = state
        self.profile = profile or default_profile
        """Callable: the device profile the run plays on (recorded in the session)."""
        self.stats = stats
        """Callable: the stream's :class:`StreamStats` now (None: no health recorded)."""
        self._health0 = None
        self.runner = None
        self.trial_started = 0.0
        self._paused = False
        layout = QtWidgets.QVBoxLayout(self)

        setup = QtWidgets.QGroupBox("Session")
        form = QtWidgets.QFormLayout(setup)
        self.experiment_combo = QtWidgets.QComboBox()
        for key, title in TITLES.items():
            self.experiment_combo.addItem(title, key)
        self.participant_edit = QtWidgets.QLineEdit("P01")
        self.participant_edit.setObjectName("participant")
        folder_row = QtWidgets.QHBoxLayout()
        self.folder_edit = QtWidgets.QLineEdit(str(Path.home() / "tactile-results"))
        browse = QtWidgets.QPushButton("Browse...")
        browse.clicked.connect(self._on_browse_clicked)
        folder_row.addWidget(self.folder_edit)
        folder_row.addWidget(browse)
        self.seed_spin = QtWidgets.QSpinBox()
        self.seed_spin.setRange(0, 2**31 - 1)
        self.emphasis_spin = QtWidgets.QDoubleSpinBox()
        self.emphasis_spin.setRange(0.0, 0.9)
        self.emphasis_spin.setSingleStep(0.1)
        self.emphasis_spin.setToolTip(
            "Experiment 3: slow the point down near corners (0 = the paper)"
        )
        form.addRow("experiment", self.experiment_combo)
        form.addRow("participant id", self.participant_edit)
        form.addRow("results folder", folder_row)
        form.addRow("seed", self.seed_spin)
        form.addRow("corner emphasis (Exp. 3)", self.emphasis_spin)
        buttons = QtWidgets.QHBoxLayout()
        self.start_button = QtWidgets.QPushButton("Start / resume")
        self.start_button.setObjectName("experiment_start")
        self.stop_button = QtWidgets.QPushButton("Stop")
        self.analyze_button = QtWidgets.QPushButton("Analyze results folder")
        self.save_profile_button = QtWidgets.QPushButton("Save calibrated profile...")
        self.save_profile_button.setEnabled(False)
        for b in (
            self.start_button,
            self.stop_button,
            self.analyze_button,
            self.save_profile_button,
        ):
            buttons.addWidget(b)
        form.addRow(buttons)
        layout.addWidget(setup)

        run = QtWidgets.QGroupBox("Run")
        v = QtWidgets.QVBoxLayout(run)
        self.prompt = QtWidgets.QLabel("Set up a session and press Start.")
        self.prompt.setObjectName("experiment_prompt")
        self.prompt.setWordWrap(True)
        font = self.prompt.font()
        font.setPointSize(font.pointSize() + 8)
        self.prompt.setFont(font)
        self.keys_label = QtWidgets.QLabel("")
        self.rating_edit = QtWidgets.QLineEdit()
        self.rating_edit.setObjectName("rating")
        self.rating_edit.setValidator(QtGui.QIntValidator(0, 100, self))
        self.rating_edit.setMaximumWidth(120)
        self.rating_edit.returnPressed.connect(self._on_rating_return_pressed)
        self.feedback = QtWidgets.QLabel("")
        self.feedback.setObjectName("experiment_feedback")
        self.feedback.setFont(font)
        self.progress = QtWidgets.QProgressBar()
        self.countdown = QtWidgets.QLabel("")
        for w in (
            self.prompt,
            self.keys_label,
            self.rating_edit,
            self.feedback,
            self.countdown,
            self.progress,
        ):
            v.addWidget(w)
        self.output = QtWidgets.QPlainTextEdit()
        self.output.setReadOnly(True)
        self.output.setPlaceholderText("analysis output")
        v.addWidget(self.output)
        layout.addWidget(run, 1)

        self.start_button.clicked.connect(self.start)
        self.stop_button.clicked.connect(self.stop)
        self.analyze_button.clicked.connect(self.run_analysis)
        self.save_profile_button.clicked.connect(self._on_save_profile_clicked)
        self.limit_timer = QtCore.QTimer(self)
        self.limit_timer.setSingleShot(True)
        self.limit_timer.timeout.connect(lambda: self.submit(None))
        self.tick_timer = QtCore.QTimer(self)
        self.tick_timer.timeout.connect(self._on_tick_timer_timeout)
        self.gap_timer = QtCore.QTimer(self)
        self.gap_timer.setSingleShot(True)
        self.gap_timer.timeout.connect(self._present)
        self.rating_edit.setVisible(False)
        self.last_calibration = None

    # --- session ------------------------------------------------------------------------------

    @property
    def running(self) -> bool:
        """True while a runner is active."""
        return self.runner is not None

    def start(self) -> bool:
        """Open (or resume) the session and start the selected experiment."""
        if self.runner is not None:
            return False
        kind = self.experiment_combo.currentData()
        try:
            profile = self.profile()
            session = open_session(
                self.folder_edit.text().strip() or ".",
                self.participant_edit.text().strip(),
                seed=self.seed_spin.value(),
                device_profile=profile.name,
            )
            if kind == "exp3":
                runner = RUNNERS[kind](
                    session, emphasis=self.emphasis_spin.value(), profile=profile
                )
            else:
                runner = RUNNERS[kind](session, profile=profile)
        except (ValueError, OSError) as exc:
            self.error_raised.emit(str(exc))
            return False
        self.runner = runner
        self.output.clear()
        self.feedback.setText("")
        self.running_changed.emit(True)
        if runner.finished:
            self._finish()
        else:
            self._present()
        return True

    def stop(self) -> None:
        """Stop the run (everything answered so far is on disk) and turn the array off."""
        if self.runner is None:
            return
        self._stop_timers()
        self.runner.close()
        self.runner = None
        self.state.set_scene(self.state.scene.replace(playing=False))
        self.prompt.setText("Stopped. Start again with the same participant to resume.")
        self.rating_edit.setVisible(False)
        self.running_changed.emit(False)

    def _stop_timers(self) -> None:
        for timer in (self.limit_timer, self.tick_timer, self.gap_timer):
            timer.stop()
        self.countdown.setText("")

    # --- trials -------------------------------------------------------------------------------

    def _play(self, scene: Scene | None) -> None:
        current = self.state.scene
        if scene is None:
            self.state.set_scene(current.replace(playing=False))
        else:
            self.state.set_scene(scene.replace(epoch=current.epoch + 1))

    def _present(self) -> None:
        runner = self.runner
        if runner is None:
            return
        trial = runner.current
        if trial is None:
            self._finish()
            return
        self._paused = False
        done, total = runner.progress()
        self.progress.setRange(0, max(total, 1))
        self.progress.setValue(done)
        self.prompt.setText(trial.prompt)
        self.keys_label.setText(f"keys: {KEYS[trial.kind]}")
        self.rating_edit.setVisible(trial.kind == "rating")
        if trial.kind == "rating":
            self.rating_edit.clear()
            self.rating_edit.setFocus()
        self._play(trial.scene)
        self.trial_started = time.monotonic()
        self._health0 = self._health_counts()
        if trial.time_limit_s:
            self.limit_timer.start(round(trial.time_limit_s * 1000))
            self.tick_timer.start(250)
            self._on_tick_timer_timeout()

    def _health_counts(self) -> dict | None:
        """The stream's counters now (for the per-trial health columns)."""
        if self.stats is None:
            return None
        stats = self.stats()
        return {
            "late_frames": stats.late,
            "skipped_frames": stats.skipped,
            "link_errors": stats.errors,
        }

    def _on_tick_timer_timeout(self) -> None:
        trial = self.runner.current if self.runner else None
        if trial is None or not trial.time_limit_s:
            self.countdown.setText("")
            return
        left = trial.time_limit_s - (time.monotonic() - self.trial_started)
        self.countdown.setText(f"{max(left, 0):.0f} s left")

    def submit(self, answer) -> bool:
        """Answer the current trial (the UI's keys call this); False if not accepted."""
        runner = self.runner
        if runner is None or runner.current is None or self.gap_timer.isActive() or self._paused:
            return False
        trial = runner.current
        rt = time.monotonic() - self.trial_started
        health = None
        now, before = self._health_counts(), self._health0
        if now is not None and before is not None:
            health = {key: now[key] - before[key] for key in now}
        try:
            feedback = runner.answer(answer, rt_s=rt, health=health)
        except (ValueError, OSError) as exc:
            self.feedback.setText(str(exc))
            return False
        self._stop_timers()
        self.feedback.setText(feedback)
        if trial.kind in ("direction", "shape", "detect"):
            self._play(None)  # silence before the next stimulus
            self.gap_timer.start(round(GAP_S * 1000))
        else:
            self._present()
        return True

    def select_key(self, key: int) -> bool:
        """Experiment 1 preparation stage: play the method behind key 1-4."""
        runner = self.runner
        if runner is None or runner.current is None or runner.current.kind != "prepare":
            return False
        self._play(runner.select(key))
        return True

    def replay(self) -> None:
        """Play the current trial's stimulus again (calibration: R)."""
        if self.runner and self.runner.current and self.runner.current.scene is not None:
            self._play(self.runner.current.scene)

    def pause(self) -> None:
        """Esc during a run: the array is off; Start resumes the same trial."""
        self._paused = True
        self._stop_timers()
        self.prompt.setText("Paused (all off). Press Enter to present the same trial again.")

    def _on_rating_return_pressed(self) -> None:
        text = self.rating_edit.text().strip()
        if text:
            self.submit(int(text))

    def handle_key(self, event) -> bool:
        """Keys while running; True if the key was used."""
        runner = self.runner
        if runner is None or runner.current is None:
            return False
        key = event.key()
        k = QtCore.Qt.Key
        if self._paused:
            if key in (k.Key_Return, k.Key_Enter):
                self._present()
                return True
            return False
        kind = runner.current.kind
        if kind == "prepare" and k.Key_1 <= key <= k.Key_4:
            return self.select_key(key - k.Key_1 + 1)
        if kind in ("continue", "prepare") and k.Key_A <= key <= k.Key_Z:
            return self.submit("continue")
        if kind == "direction":
            arrows = {k.Key_Up: "up", k.Key_Down: "down", k.Key_Left: "left", k.Key_Right: "right"}
            if key in arrows:
                return self.submit(arrows[key])
        if kind == "shape" and key in (k.Key_C, k.Key_S):
            return self.submit("circle" if key == k.Key_C else "square")
        if kind == "detect":
            if key in (k.Key_Y, k.Key_N):
                return self.submit("yes" if key == k.Key_Y else "no")
            if key == k.Key_R:
                self.replay()
                return True
        return False

    def _finish(self) -> None:
        runner = self.runner
        self._stop_timers()
        self.state.set_scene(self.state.scene.replace(playing=False))
        folder = runner.session.folder
        self.prompt.setText(f"Finished. Results are in {folder}.")
        self.keys_label.setText("")
        self.rating_edit.setVisible(False)
        self.progress.setValue(self.progress.maximum())
        if runner.experiment == "calibration":
            try:
                self.last_calibration = runner.calibration()
            except ValueError as exc:
                self.error_raised.emit(str(exc))
            else:
                self.save_profile_button.setEnabled(True)
                self.calibration_done.emit(self.last_calibration)
        runner.close()
        self.runner = None
        self.running_changed.emit(False)

    # --- analysis and profiles -----------------------------------------------------------------

    def run_analysis(self) -> bool:
        """Run ``tactile analyze`` on the results folder and show its output."""
        buffer = io.StringIO()
        try:
            analyze(self.folder_edit.text().strip(), out=lambda s="": buffer.write(f"{s}\n"))
        except (ValueError, OSError) as exc:
            self.error_raised.emit(str(exc))
            return False
        self.output.setPlainText(buffer.getvalue())
        return True

    def _on_browse_clicked(self) -> None:
        folder = QtWidgets.QFileDialog.getExistingDirectory(
            self, "Results folder", self.folder_edit.text()
        )
        if folder:
            self.folder_edit.setText(folder)

    def _on_save_profile_clicked(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, "Save calibrated profile", "calibrated.json", "Profiles (*.json)"
        )
        if path:
            self.save_profile_requested(path)

    def save_profile_requested(self, path) -> None:  # replaced by the window
        """Hook: the window saves the profile with the last calibration."""
