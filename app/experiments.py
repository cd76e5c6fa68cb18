"""The Experiments tab: an experimenter's console, and a separate window for the participant.

As in PsychoPy's split between the experimenter and the participant, the participant's window
(:class:`ParticipantWindow`, full screen on a second screen when there is one) shows only the
instructions, the response prompt, the rating box and the feedback; the console
(:class:`ExperimentsPanel`, the tuner's Experiments tab) shows the run: the participant id in
large type, the experiment, the progress, what the current trial plays, the array's health (rate,
late frames, link errors), where the results go, and an event log.

A run refuses to start while the array is disconnected. If the link drops during a run, the run
pauses with the array off, the console says so, and once the array is back the experimenter
presents the interrupted trial again (its row records how often it was presented). The tuning
scene is saved when a run starts and restored, paused, when it ends; a run never writes the
tuner's settings.
"""

from __future__ import annotations

import io
import time
from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.device.profile import default_profile
from tactile_core.experiments import RUNNERS, open_session
from tactile_core.experiments.analysis import analyze
from tactile_core.experiments.results import SESSION_FILE, check_participant
from tactile_core.experiments.runners import INTERVAL_GAP_S, INTERVAL_S
from tactile_core.experiments.tuning import save_correction
from tactile_core.rendering.methods import PAPER_METHODS
from tactile_core.rendering.scene import Scene

from .state import TunerState

TITLES = {
    "exp1": "Experiment 1: ratings of the four methods",
    "exp2": "Experiment 2: shortest line whose direction is felt (AS)",
    "exp3": "Experiment 3: circle or square, per method",
    "calibration": "Tactor calibration: detection threshold of every tactor",
    "correction": "Tune the correction by feel: measure mu and gamma",
}
KEYS = {
    "continue": "any letter key to go on",
    "prepare": "1-{n} to switch methods, a letter key to go on",
    "rating": "type 0-100, then Enter",
    "direction": "arrow keys",
    "shape": "C for circle, S for square",
    "detect": "Y (felt) or N (not felt); R to feel it again",
    "interval": "1 or 2 once both intervals have played; R to feel both again",
}
GAP_S = 0.8  # the array is off between a question's answer and the next stimulus
LINK_DOWN = ("disconnected", "stopped", "failed", "refused")
"""Stream states in which the array is not being driven."""


def _confirm(parent, title: str, text: str) -> bool:
    box = QtWidgets.QMessageBox(parent)
    box.setIcon(QtWidgets.QMessageBox.Icon.Question)
    box.setWindowTitle(title)
    box.setText(text)
    box.setStandardButtons(
        QtWidgets.QMessageBox.StandardButton.Yes | QtWidgets.QMessageBox.StandardButton.No
    )
    box.setDefaultButton(QtWidgets.QMessageBox.StandardButton.No)
    return box.exec() == QtWidgets.QMessageBox.StandardButton.Yes


class ParticipantWindow(QtWidgets.QWidget):
    """What the participant sees: the instructions and the response prompt, nothing else."""

    closed = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent, QtCore.Qt.WindowType.Window)
        self.setWindowTitle("tactile-tuner - participant")
        self.setObjectName("participant_window")
        layout = QtWidgets.QVBoxLayout(self)
        layout.setContentsMargins(60, 60, 60, 60)
        big = self.font()
        big.setPointSize(big.pointSize() + 12)
        self.prompt = QtWidgets.QLabel("")
        self.prompt.setObjectName("experiment_prompt")
        self.prompt.setWordWrap(True)
        self.prompt.setFont(big)
        self.prompt.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.keys_label = QtWidgets.QLabel("")
        self.keys_label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.rating_edit = QtWidgets.QLineEdit()
        self.rating_edit.setObjectName("rating")
        self.rating_edit.setFont(big)
        self.rating_edit.setMaximumWidth(220)
        self.rating_edit.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.rating_error = QtWidgets.QLabel("")
        self.rating_error.setObjectName("rating_error")
        self.rating_error.setStyleSheet("color: #c0392b;")
        self.rating_error.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.feedback = QtWidgets.QLabel("")
        self.feedback.setObjectName("experiment_feedback")
        self.feedback.setFont(big)
        self.feedback.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.countdown = QtWidgets.QLabel("")
        self.countdown.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        layout.addStretch(2)
        layout.addWidget(self.prompt)
        layout.addWidget(self.keys_label)
        row = QtWidgets.QHBoxLayout()
        row.addStretch(1)
        row.addWidget(self.rating_edit)
        row.addStretch(1)
        layout.addLayout(row)
        layout.addWidget(self.rating_error)
        layout.addWidget(self.feedback)
        layout.addWidget(self.countdown)
        layout.addStretch(3)
        self.rating_edit.setVisible(False)

    def show_on(self, screen_index: int | None) -> None:
        """Full screen on screen ``screen_index``, or an ordinary window for None."""
        screens = QtGui.QGuiApplication.screens()
        if screen_index is not None and 0 <= screen_index < len(screens):
            self.setScreen(screens[screen_index])
            self.setGeometry(screens[screen_index].geometry())
            self.showFullScreen()
        else:
            self.resize(900, 600)
            self.showNormal()
        self.raise_()
        self.activateWindow()

    def closeEvent(self, event) -> None:  # Qt override
        self.closed.emit()
        super().closeEvent(event)


class TuningResultDialog(QtWidgets.QDialog):
    """The result of tuning the correction by feel: mu and gamma with their intervals, and
    *Apply* (to the tuner now) and *Save as preset...*; without a correction, why not."""

    applied = QtCore.Signal()
    save_requested = QtCore.Signal()

    def __init__(self, result, preset_path=None, parent=None):
        super().__init__(parent)
        self.setWindowTitle("Correction measured" if result.ok else "No correction")
        self.setObjectName("tuning_result")
        layout = QtWidgets.QVBoxLayout(self)
        text = QtWidgets.QPlainTextEdit(result.summary())
        text.setReadOnly(True)
        text.setFont(QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont))
        text.setMinimumSize(520, 220)
        layout.addWidget(text)
        if preset_path is not None:
            where = QtWidgets.QLabel(f"Kept in {preset_path.parent} (correction.json and "
                                     f"{preset_path.name}).")  # fmt: skip
            where.setWordWrap(True)
            layout.addWidget(where)
        buttons = QtWidgets.QDialogButtonBox()
        self.apply_button = buttons.addButton(
            "Apply", QtWidgets.QDialogButtonBox.ButtonRole.AcceptRole
        )
        self.save_button = buttons.addButton(
            "Save as preset...", QtWidgets.QDialogButtonBox.ButtonRole.ActionRole
        )
        buttons.addButton(QtWidgets.QDialogButtonBox.StandardButton.Close)
        for b in (self.apply_button, self.save_button):
            b.setEnabled(result.ok)
        self.apply_button.setToolTip("Set the tuner's mu and gamma to the measured ones")
        self.apply_button.clicked.connect(self.applied)
        self.apply_button.clicked.connect(self.accept)
        self.save_button.clicked.connect(self.save_requested)
        buttons.rejected.connect(self.reject)
        layout.addWidget(buttons)


class ExperimentsPanel(QtWidgets.QWidget):
    """The experimenter's console: sets up, starts, watches and analyses the runs.

    Parameters
    ----------
    state : TunerState
        The tuner's state; a run plays each trial's scene through it.
    profile : callable
        The device profile the run plays on (recorded in the session).
    stats : callable, optional
        The stream's :class:`~tactile_core.device.streamer.StreamStats` now.
    device : callable, optional
        A one-line description of the link ("simulated array", a port).
    """

    running_changed = QtCore.Signal(bool)
    error_raised = QtCore.Signal(str)
    calibration_done = QtCore.Signal(object)
    """``(offset, gain, threshold)`` lists when a calibration run finishes."""
    correction_measured = QtCore.Signal(object, object)
    """``(TuningResult, preset path or None)`` when a tuning run finishes, with or without a
    correction (``result.ok``)."""
    _analysis_done = QtCore.Signal(object, str)
    _analysis_progress = QtCore.Signal(float, str)

    def __init__(self, state: TunerState, profile=None, stats=None, device=None, parent=None):
        super().__init__(parent)
        self.state = state
        self.profile = profile or default_profile
        self.stats = stats
        self.device = device or (lambda: "simulated array")
        self.confirm = lambda title, text: _confirm(self, title, text)
        """Asks the experimenter yes or no (tests answer it themselves)."""
        self.runner = None
        self.saved_scene: Scene | None = None
        """The tuning scene while a run plays its own (restored, paused, when it ends)."""
        self.trial_started = 0.0
        self._health0 = None
        self._presentations = 0
        self._paused = False
        self._link_lost = False
        self.last_calibration = None
        self.participant_window = ParticipantWindow()
        self.participant_window.closed.connect(self._on_participant_window_closed)
        # The participant's widgets, under the names the console drives them by.
        pw = self.participant_window
        self.prompt, self.keys_label, self.feedback = pw.prompt, pw.keys_label, pw.feedback
        self.rating_edit, self.countdown = pw.rating_edit, pw.countdown
        self.rating_edit.returnPressed.connect(self._on_rating_return_pressed)

        layout = QtWidgets.QHBoxLayout(self)
        left = QtWidgets.QVBoxLayout()
        layout.addLayout(left, 2)
        setup = QtWidgets.QGroupBox("Session")
        form = QtWidgets.QFormLayout(setup)
        self.experiment_combo = QtWidgets.QComboBox()
        for key, title in TITLES.items():
            self.experiment_combo.addItem(title, key)
        self.participant_edit = QtWidgets.QLineEdit()
        self.participant_edit.setObjectName("participant")
        self.participant_edit.setPlaceholderText("required: letters, digits, _ . -")
        self.participant_edit.setToolTip(
            "The participant's id (it names the folder of their results); no default, so that "
            "nobody resumes someone else's session by accident"
        )
        folder_row = QtWidgets.QHBoxLayout()
        self.folder_edit = QtWidgets.QLineEdit(str(Path.home() / "tactile-results"))
        browse = QtWidgets.QPushButton("Browse...")
        browse.clicked.connect(self._on_browse_clicked)
        folder_row.addWidget(self.folder_edit)
        folder_row.addWidget(browse)
        self.seed_spin = QtWidgets.QSpinBox()
        self.seed_spin.setRange(0, 2**31 - 1)
        self.seed_spin.setToolTip("Seeds the orders and every random choice of the session")
        self.emphasis_spin = QtWidgets.QDoubleSpinBox()
        self.emphasis_spin.setRange(0.0, 0.9)
        self.emphasis_spin.setSingleStep(0.1)
        self.emphasis_spin.setToolTip(
            "Experiment 3: slow the point down near corners (0 = the paper; 4.3 suggests it)"
        )
        self.screen_combo = QtWidgets.QComboBox()
        self.screen_combo.setObjectName("participant_screen")
        self.screen_combo.setToolTip(
            "Where the participant's window goes: full screen on a screen, or a window"
        )
        self._fill_screens()
        # Long titles elide rather than widen the tab past a 1280-pixel screen.
        for combo in (self.experiment_combo, self.screen_combo):
            combo.setSizeAdjustPolicy(
                QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon
            )
            combo.setMinimumContentsLength(18)
        self.experiment_combo.setToolTip("The paper's experiment to run (Section 5)")
        form.addRow("experiment", self.experiment_combo)
        form.addRow("participant id", self.participant_edit)
        form.addRow("results folder", folder_row)
        form.addRow("seed", self.seed_spin)
        form.addRow("corner emphasis (Exp. 3)", self.emphasis_spin)
        from .compare import MethodSetEdit

        self.methods_edit = MethodSetEdit(PAPER_METHODS, 2, 8, label=None)
        self.methods_edit.setToolTip(
            "The methods Experiments 1 and 3 compare: the paper's four by default (in the "
            "paper's 12 orders); any other set of 2-8 is ordered by a balanced Latin square"
        )
        form.addRow("methods (Exp. 1, 3)", self.methods_edit)
        form.addRow("participant window", self.screen_combo)
        buttons = QtWidgets.QHBoxLayout()
        self.start_button = QtWidgets.QPushButton("Start / resume")
        self.start_button.setObjectName("experiment_start")
        self.stop_button = QtWidgets.QPushButton("Stop")
        self.resume_button = QtWidgets.QPushButton("Present again")
        self.resume_button.setToolTip("After a pause or a lost link: present the trial again")
        self.resume_button.setEnabled(False)
        for b in (self.start_button, self.stop_button, self.resume_button):
            buttons.addWidget(b)
        form.addRow(buttons)
        left.addWidget(setup)

        run = QtWidgets.QGroupBox("Run")
        v = QtWidgets.QVBoxLayout(run)
        huge = self.font()
        huge.setPointSize(huge.pointSize() + 14)
        huge.setBold(True)
        self.participant_label = QtWidgets.QLabel("no participant")
        self.participant_label.setObjectName("participant_label")
        self.participant_label.setFont(huge)
        self.run_label = QtWidgets.QLabel("Set up a session and press Start.")
        self.run_label.setObjectName("run_label")
        self.run_label.setWordWrap(True)
        self.progress = QtWidgets.QProgressBar()
        self.health_label = QtWidgets.QLabel("")
        self.health_label.setObjectName("health_label")
        self.health_label.setWordWrap(True)
        self.path_label = QtWidgets.QLabel("")
        self.path_label.setWordWrap(True)
        self.path_label.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
        self.log = QtWidgets.QPlainTextEdit()
        self.log.setObjectName("experiment_log")
        self.log.setReadOnly(True)
        self.log.setMaximumBlockCount(500)
        self.log.setPlaceholderText("events of the run")
        for w in (self.participant_label, self.run_label, self.progress, self.health_label,
                  self.path_label):  # fmt: skip
            v.addWidget(w)
        v.addWidget(self.log, 1)
        left.addWidget(run, 1)

        right = QtWidgets.QGroupBox("Analysis")
        r = QtWidgets.QVBoxLayout(right)
        row = QtWidgets.QHBoxLayout()
        self.analyze_button = QtWidgets.QPushButton("Analyze results folder")
        self.paper_rounding_check = QtWidgets.QCheckBox("paper's rounding of p")
        self.paper_rounding_check.setToolTip(
            "Round each p to three decimals before x 6, as the paper's tables did"
        )
        self.save_profile_button = QtWidgets.QPushButton("Save calibrated profile...")
        self.save_profile_button.setEnabled(False)
        for w in (self.analyze_button, self.save_profile_button):
            row.addWidget(w)
        row.addStretch(1)
        r.addLayout(row)
        r.addWidget(self.paper_rounding_check)
        self.analysis_progress = QtWidgets.QProgressBar()
        self.analysis_progress.setVisible(False)
        r.addWidget(self.analysis_progress)
        self.output = QtWidgets.QPlainTextEdit()
        self.output.setReadOnly(True)
        self.output.setPlaceholderText("analysis output")
        self.output.setLineWrapMode(QtWidgets.QPlainTextEdit.LineWrapMode.NoWrap)
        self.output.setFont(
            QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont)
        )
        self.figures = QtWidgets.QTabWidget()
        self.figures.setObjectName("analysis_figures")
        split = QtWidgets.QSplitter(QtCore.Qt.Orientation.Vertical)
        split.addWidget(self.output)
        split.addWidget(self.figures)
        r.addWidget(split, 1)
        layout.addWidget(right, 3)

        self.start_button.clicked.connect(self.start)
        self.stop_button.clicked.connect(self.stop)
        self.resume_button.clicked.connect(self.present_again)
        self.analyze_button.clicked.connect(self.run_analysis)
        self.save_profile_button.clicked.connect(self._on_save_profile_clicked)
        self._analysis_done.connect(self._on_analysis_done)
        self._analysis_progress.connect(self._on_analysis_progress)
        self._analysis_thread = None
        self.limit_timer = QtCore.QTimer(self)
        self.limit_timer.setSingleShot(True)
        self.limit_timer.timeout.connect(lambda: self.submit(None))
        self.tick_timer = QtCore.QTimer(self)
        self.tick_timer.timeout.connect(self._on_tick_timer_timeout)
        self.gap_timer = QtCore.QTimer(self)
        self.gap_timer.setSingleShot(True)
        self.gap_timer.timeout.connect(self._present)
        # Two-interval trials: interval 1, a gap, interval 2, then the question.
        self.interval_timer = QtCore.QTimer(self)
        self.interval_timer.setSingleShot(True)
        self.interval_timer.timeout.connect(self._next_interval)
        self._steps: list = []
        self.last_tuning = None
        self.health_timer = QtCore.QTimer(self)
        self.health_timer.timeout.connect(self._on_health_timer_timeout)
        self.health_timer.start(500)

    # --- session ------------------------------------------------------------------------------

    def prepare_tuning(self) -> None:
        """Set the console up for tuning the correction by feel, and say what comes."""
        from tactile_core.experiments.tuning import TuningPlan

        self.experiment_combo.setCurrentIndex(self.experiment_combo.findData("correction"))
        plan = TuningPlan()
        trials = 5 * plan.threshold_trials + 2 * plan.gamma_trials + plan.corner_trials
        self.run_label.setText(
            f"Tune by feel: type the id, then Start. {trials} trials (about "
            f"{round(trials * 3.2 / 60)} min): mu, then gamma. Esc pauses, array off."
        )
        self.participant_edit.setFocus()

    @property
    def running(self) -> bool:
        """True while a runner is active."""
        return self.runner is not None

    def _fill_screens(self) -> None:
        self.screen_combo.clear()
        self.screen_combo.addItem("a window (this screen)", None)
        for i, screen in enumerate(QtGui.QGuiApplication.screens()):
            size = screen.geometry()
            self.screen_combo.addItem(
                f"full screen on {screen.name() or f'screen {i + 1}'} "
                f"({size.width()} x {size.height()})",
                i,
            )
        if len(QtGui.QGuiApplication.screens()) > 1:  # a second screen: the participant's
            self.screen_combo.setCurrentIndex(self.screen_combo.count() - 1)

    def log_event(self, text: str) -> None:
        """Add a timestamped line to the console's event log."""
        self.log.appendPlainText(f"{time.strftime('%H:%M:%S')}  {text}")

    def _device_state(self) -> str:
        return "" if self.stats is None else self.stats().state

    def start(self) -> bool:
        """Open (or resume) the session and start the selected experiment; False (and a
        message) if it cannot start."""
        if self.runner is not None:
            return False
        kind = self.experiment_combo.currentData()
        pid = self.participant_edit.text()
        try:
            pid = check_participant(pid)
        except ValueError as exc:
            self.error_raised.emit(str(exc))
            return False
        state = self._device_state()
        if state in LINK_DOWN:
            self.error_raised.emit(
                f"the array is not connected ({state}: {self.stats().status}); connect it, or "
                f"choose the simulated array, before starting"
            )
            return False
        folder = Path(self.folder_edit.text().strip() or ".")
        existing = folder / f"participant-{pid}" / SESSION_FILE
        title = TITLES[kind]
        if existing.exists():
            question = (
                f"Participant {pid} already has results in {existing.parent}.\n\n"
                f"Resume {title} for {pid}?"
            )
        else:
            question = f"Start {title} for a new participant, {pid}?"
        if not self.confirm("Start the run", question):
            return False
        try:
            profile = self.profile()
            session = open_session(folder, pid, seed=self.seed_spin.value(),
                                   device_profile=profile.name)  # fmt: skip
            methods = self.methods_edit.methods
            recorded = session.parameters.get(f"{kind}_methods")
            if kind in ("exp1", "exp3") and recorded and list(methods) == list(PAPER_METHODS):
                # Resuming a participant who ran another set, with the console at its default:
                # resume their set (another set typed in is refused, naming both).
                methods = None
                self.methods_edit.apply(recorded)
                self.log_event(f"resuming {kind} on the participant's methods: "
                               f"{' '.join(recorded)}")  # fmt: skip
            if kind == "exp3":
                runner = RUNNERS[kind](session, emphasis=self.emphasis_spin.value(),
                                       methods=methods, profile=profile)  # fmt: skip
            elif kind == "exp1":
                runner = RUNNERS[kind](session, methods=methods, profile=profile)
            else:
                runner = RUNNERS[kind](session, profile=profile)
        except (ValueError, OSError) as exc:
            self.error_raised.emit(str(exc))
            return False
        self.runner = runner
        self.saved_scene = self.state.scene
        self._link_lost = False
        self.participant_label.setText(f"participant {pid}")
        self.path_label.setText(f"results: {runner.path}")
        self.log_event(f"started {title} for {pid} on {self.device()} ({runner.done} done)")
        if runner.recovered:
            self.log_event(f"resumed after a crash: {runner.recovered}; that trial comes again")
        self.feedback.setText("")
        self.participant_window.rating_error.setText("")
        self.participant_window.show_on(self.screen_combo.currentData())
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
        runner, self.runner = self.runner, None
        runner.close()
        self.log_event(f"stopped at {runner.done} of {runner.total}; start again to resume")
        self.run_label.setText("Stopped. Start again with the same participant to resume.")
        self.prompt.setText("Please wait.")
        self.rating_edit.setVisible(False)
        self._end_run()

    def _end_run(self) -> None:
        """Back to the tuning scene, paused (the participant's hand may still be on the array),
        and the participant's window closed."""
        saved, self.saved_scene = self.saved_scene, None
        if saved is not None:
            self.state.set_scene(saved.replace(playing=False, epoch=self.state.scene.epoch + 1))
        self.participant_window.hide()
        self.resume_button.setEnabled(False)
        self.running_changed.emit(False)

    def _stop_timers(self) -> None:
        for timer in (self.limit_timer, self.tick_timer, self.gap_timer, self.interval_timer):
            timer.stop()
        self._steps = []
        self.countdown.setText("")

    # --- two-interval trials ------------------------------------------------------------------

    @property
    def intervals_playing(self) -> bool:
        """True while the intervals of a two-interval trial are being played."""
        return bool(self._steps) or self.interval_timer.isActive()

    def _play_intervals(self, trial) -> None:
        """Play interval 1, a silent gap, interval 2; then ask (the participant's window shows
        which interval is playing, in large type)."""
        one, two = trial.intervals
        self._steps = [(one, INTERVAL_S, "1"), (None, INTERVAL_GAP_S, ""), (two, INTERVAL_S, "2"),
                       (None, 0.0, None)]  # fmt: skip
        self._next_interval()

    def _next_interval(self) -> None:
        if not self._steps:
            return
        scene, seconds, label = self._steps.pop(0)
        self._play(scene)
        if label is None:  # both played: the question
            self.countdown.setText("")
            self.prompt.setText(self.runner.current.prompt if self.runner and
                                self.runner.current else "")  # fmt: skip
            self.trial_started = time.monotonic()
            return
        self.countdown.setText(f"interval {label}" if label else "")
        self.interval_timer.start(round(seconds * 1000))

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
        self.resume_button.setEnabled(False)
        done, total = runner.progress()
        self.progress.setRange(0, max(total, 1))
        self.progress.setValue(done)
        info = ", ".join(f"{k} {v}" for k, v in trial.info.items())
        self.run_label.setText(
            f"{TITLES[runner.experiment]}: trial {done + 1} of {total}, {trial.stage} "
            f"{trial.index} ({trial.kind}{': ' + info if info else ''})"
        )
        self.prompt.setText(trial.prompt)
        self.keys_label.setText(f"keys: {KEYS[trial.kind].format(n=len(trial.options))}")
        self.rating_edit.setVisible(trial.kind == "rating")
        self.participant_window.rating_error.setText("")
        if trial.kind == "rating":
            self.rating_edit.clear()
            self.rating_edit.setFocus()
        if trial.kind == "interval":
            self.prompt.setText("Feel both intervals.")
            self._play_intervals(trial)
        else:
            self._play(trial.scene)
        self._presentations += 1
        if self._presentations > 1:
            self.log_event(f"trial {trial.stage} {trial.index} presented again "
                           f"({self._presentations} times)")  # fmt: skip
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
        return {"late_frames": stats.late, "skipped_frames": stats.skipped,
                "link_errors": stats.errors}  # fmt: skip

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
        if self.intervals_playing:
            return False  # both intervals first
        trial = runner.current
        rt = time.monotonic() - self.trial_started
        health = {"presentations": self._presentations}
        now, before = self._health_counts(), self._health0
        if now is not None and before is not None:
            health.update({key: now[key] - before[key] for key in now})
        try:
            feedback = runner.answer(answer, rt_s=rt, health=health)
        except OSError as exc:  # the disk: the runner stays on this trial; a retry records it
            self.feedback.setText("Please wait.")
            self.log_event(f"could not record the answer ({exc}); the trial stays: retry")
            self.error_raised.emit(f"could not record the answer: {exc}")
            return False
        except ValueError as exc:
            self.participant_window.rating_error.setText(str(exc))
            return False
        self._presentations = 0
        self._stop_timers()
        self.feedback.setText(feedback)
        if trial.kind in ("direction", "shape", "detect", "interval"):
            self._play(None)  # silence before the next stimulus
            self.gap_timer.start(round(GAP_S * 1000))
        else:
            self._present()
        return True

    def select_key(self, key: int) -> bool:
        """Experiment 1 preparation stage: play the method behind key 1-N."""
        runner = self.runner
        if runner is None or runner.current is None or runner.current.kind != "prepare":
            return False
        self._play(runner.select(key))
        return True

    def replay(self) -> None:
        """Play the current trial's stimulus again (calibration: R), or both its intervals."""
        trial = self.runner.current if self.runner else None
        if trial is None or self._paused:
            return
        if trial.kind == "interval":
            self.interval_timer.stop()
            self._play_intervals(trial)
        elif trial.scene is not None:
            self._play(trial.scene)

    def pause(self, why: str = "paused (Esc)") -> None:
        """The array off; the trial is presented again when the run resumes."""
        if self.runner is None:
            return
        self._paused = True
        self._stop_timers()
        self._play(None)
        self.gap_timer.stop()
        self.prompt.setText("Paused. Please wait.")
        self.rating_edit.setVisible(False)
        self.resume_button.setEnabled(not self._link_lost)
        trial = self.runner.current
        where = f" at trial {trial.stage} {trial.index}" if trial else ""
        self.log_event(f"{why}{where}; the array is off")

    def present_again(self) -> None:
        """Resume after a pause: the current trial, from its beginning."""
        if self.runner is None or not self._paused:
            return
        if self._link_lost:
            self.error_raised.emit("the array is still disconnected")
            return
        self._present()

    def on_device_status(self, stats) -> None:
        """The stream's state changed: a lost link pauses the run; its return is logged."""
        if self.runner is None:
            return
        if stats.state in LINK_DOWN and not self._link_lost:
            self._link_lost = True
            self.pause(f"link lost ({stats.status})")
        elif stats.state in ("streaming", "paused", "idle") and self._link_lost:
            self._link_lost = False
            self.resume_button.setEnabled(True)
            self.log_event("the array is back: press Present again (or Enter)")

    def _on_health_timer_timeout(self) -> None:
        if self.stats is None:
            return
        s = self.stats()
        link = f"{self.device()}: {s.state}"
        self.health_label.setText(
            f"{link} | {s.achieved_rate_hz:.0f} Hz | late {s.late}, skipped {s.skipped}, "
            f"link errors {s.errors}"
        )
        self.health_label.setStyleSheet("color: #c0392b;" if s.state in LINK_DOWN else "")

    def _on_participant_window_closed(self) -> None:
        if self.runner is not None and not self._paused:
            self.pause("the participant's window was closed")

    def _on_rating_return_pressed(self) -> None:
        text = self.rating_edit.text().strip()
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or not 0 <= value <= 100:
            self.participant_window.rating_error.setText(
                f"A rating is a whole number from 0 to 100; {text or 'nothing'} is not one."
            )
            self.rating_edit.selectAll()
            return
        self.submit(value)

    def handle_key(self, event) -> bool:
        """Keys while running; True if the key was used."""
        runner = self.runner
        if runner is None or runner.current is None:
            return False
        key = event.key()
        k = QtCore.Qt.Key
        if self._paused:
            if key in (k.Key_Return, k.Key_Enter):
                self.present_again()
                return True
            return False
        kind = runner.current.kind
        if kind == "rating":
            return False  # the rating box takes digits and Enter itself
        if kind == "prepare" and k.Key_1 <= key < k.Key_1 + len(runner.current.options):
            return self.select_key(key - k.Key_1 + 1)
        if kind in ("continue", "prepare") and k.Key_A <= key <= k.Key_Z:
            return self.submit("continue")
        if kind == "direction":
            arrows = {k.Key_Up: "up", k.Key_Down: "down", k.Key_Left: "left", k.Key_Right: "right"}
            if key in arrows:
                return self.submit(arrows[key])
        if kind == "shape" and key in (k.Key_C, k.Key_S):
            return self.submit("circle" if key == k.Key_C else "square")
        if kind == "interval":
            if key in (k.Key_1, k.Key_2):
                return self.submit("1" if key == k.Key_1 else "2")
            if key == k.Key_R:
                self.replay()
                return True
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
        self.prompt.setText("Thank you. This part is finished.")
        self.keys_label.setText("")
        self.rating_edit.setVisible(False)
        self.run_label.setText(f"Finished. Results are in {runner.session.folder}.")
        self.progress.setValue(self.progress.maximum())
        self.log_event(f"finished {runner.experiment}: {runner.done} answers in {runner.path}")
        if runner.experiment == "correction":
            self._finish_tuning(runner)
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
        self._end_run()

    def _finish_tuning(self, runner) -> None:
        """Keep the measured correction (record and preset in the participant's folder), or
        say why there is none; the window offers to apply it."""
        result = runner.result()
        preset = None
        if result.ok:
            try:
                _, preset = save_correction(runner, result)
            except (OSError, ValueError) as exc:
                self.error_raised.emit(f"could not save the correction: {exc}")
            self.last_calibration = runner.calibration()
            self.save_profile_button.setEnabled(True)
            self.log_event(f"correction: mu {result.mu:.3f}, gamma {result.gamma:.3f} "
                           f"({result.trials} trials); saved {preset}")  # fmt: skip
            self.run_label.setText(f"Finished: mu {result.mu:.3f}, gamma {result.gamma:.3f}.")
        else:
            self.log_event(f"no correction: {result.message}")
            self.run_label.setText("Finished without a correction (see the log).")
        self.last_tuning = result
        self.correction_measured.emit(result, preset)

    # --- analysis and profiles -----------------------------------------------------------------

    def run_analysis(self, wait: bool = False) -> bool:
        """Run ``tactile analyze`` on the results folder in the background; its tables go to
        the output (fixed-width), its figures to tabs. ``wait`` blocks until it is done (for
        tests and scripts); returns whether it succeeded (True at once when not waiting)."""
        if self._analysis_thread is not None and self._analysis_thread.is_alive():
            return False
        import threading

        folder = self.folder_edit.text().strip()
        rounding = self.paper_rounding_check.isChecked()
        self.output.setPlainText(f"analysing {folder} ...")
        self.analysis_progress.setRange(0, 100)
        self.analysis_progress.setValue(0)
        self.analysis_progress.setVisible(True)
        self.analyze_button.setEnabled(False)
        self._analysis_result = None

        def work():
            buffer = io.StringIO()
            try:
                result = analyze(
                    folder,
                    out=lambda s="": buffer.write(f"{s}\n"),
                    paper_rounding=rounding,
                    progress=lambda f, what: self._analysis_progress.emit(f, what),
                )
            except (ValueError, OSError) as exc:
                self._analysis_done.emit(None, str(exc))
                return
            self._analysis_done.emit(result, buffer.getvalue())

        self._analysis_thread = threading.Thread(target=work, name="analyze", daemon=True)
        self._analysis_thread.start()
        if wait:
            deadline = time.monotonic() + 120
            while self._analysis_result is None and time.monotonic() < deadline:
                QtWidgets.QApplication.processEvents(
                    QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 50
                )
            return bool(self._analysis_result)
        return True

    def _on_analysis_progress(self, fraction: float, what: str) -> None:
        self.analysis_progress.setValue(round(fraction * 100))
        self.analysis_progress.setFormat(f"{what} %p%")

    def _on_analysis_done(self, result, text: str) -> None:
        self.analysis_progress.setVisible(False)
        self.analyze_button.setEnabled(True)
        if result is None:
            self.output.setPlainText(text)
            self.error_raised.emit(text)
            self._analysis_result = False
            return
        self.output.setPlainText(text)
        while self.figures.count():
            widget = self.figures.widget(0)
            self.figures.removeTab(0)
            widget.deleteLater()
        for path in result.get("figures", []):
            label = QtWidgets.QLabel()
            label.setPixmap(QtGui.QPixmap(path))
            label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
            scroll = QtWidgets.QScrollArea()
            scroll.setWidget(label)
            scroll.setWidgetResizable(True)
            self.figures.addTab(scroll, Path(path).stem)
        self._analysis_result = True

    def _on_browse_clicked(self) -> None:
        from . import dialogs

        folder = dialogs.folder_path(self, "results", "Results folder", self.folder_edit.text())
        if folder:
            self.folder_edit.setText(str(folder))

    def _on_save_profile_clicked(self) -> None:
        from . import dialogs

        pid = dialogs.safe_name(self.participant_edit.text() or "participant")
        name = f"{self.profile().name}-calibrated-{pid}-{dialogs.today()}.json"
        path = dialogs.save_path(self, "profiles", "Save calibrated profile", name,
                                 ["Profiles (*.json)"])  # fmt: skip
        if path:
            self.save_profile_requested(path)

    def save_profile_requested(self, path) -> None:  # replaced by the window
        """Hook: the window saves the profile with the last calibration."""
