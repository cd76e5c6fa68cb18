"""The experimenter's console (the Experiments tab): set a run up, start it, watch it."""

from __future__ import annotations

import time
from pathlib import Path

from PySide6 import QtCore, QtWidgets

from tactile_core.device.profile import default_profile
from tactile_core.experiments import RUNNERS, open_session
from tactile_core.experiments.results import SESSION_FILE, check_participant
from tactile_core.rendering.methods import PAPER_METHODS
from tactile_core.rendering.scene import Scene

from .. import dialogs
from ..state import TunerState
from ..texts import value3
from .analysis import AnalysisWidget
from .guided import keep_correction, tuning_intro
from .participant import ParticipantWindow
from .session import TITLES, SessionWidget
from .trials import LINK_DOWN, TrialPresenter


class ExperimentsPanel(QtWidgets.QWidget):
    """The experimenter's console: sets up, starts, watches and analyses the runs.

    The participant's window (:attr:`participant_window`) shows what the participant needs;
    :attr:`trials` presents the trials; :attr:`analysis` analyses the results folder. The
    console shows the participant id in large type, the run's progress and current trial, the
    array's health, where the results go, and an event log.

    Parameters
    ----------
    state : TunerState
        The tuner's state; a run plays each trial's scene through it.
    profile : callable
        The device profile the run plays on (recorded in the session).
    stats : callable, optional
        The stream's :class:`~tactile_core.stream.streamer.StreamStats` now.
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
    profile_save_requested = QtCore.Signal(object)
    """A path to save the device profile to, with the last calibration's offsets and gains."""

    def __init__(self, state: TunerState, profile=None, stats=None, device=None, parent=None):
        super().__init__(parent)
        self.state = state
        self.profile = profile or default_profile
        self.stats = stats
        self.device = device or (lambda: "simulated array")
        self.confirm = lambda title, text: dialogs.confirm(self, title, text)
        """Asks the experimenter yes or no (tests answer it themselves)."""
        self.saved_scene: Scene | None = None
        """The tuning scene while a run plays its own (restored, paused, when it ends)."""
        self.last_calibration = None
        self.last_tuning = None
        self.participant_window = ParticipantWindow()
        self.trials = TrialPresenter(state, self.participant_window, self._health_counts, self)

        layout = QtWidgets.QHBoxLayout(self)
        column = QtWidgets.QWidget()
        left = QtWidgets.QVBoxLayout(column)
        left.setContentsMargins(0, 0, 0, 0)
        self.setup = SessionWidget()
        left.addWidget(self.setup)
        left.addWidget(self._run_box(), 1)
        layout.addWidget(self._scrolled(column), 2)
        self.analysis = AnalysisWidget(lambda: self.setup.folder_edit.text().strip(), self)
        layout.addWidget(self.analysis, 3)

        self.setup.start_button.clicked.connect(self.start)
        self.setup.stop_button.clicked.connect(self.stop)
        self.setup.resume_button.clicked.connect(self.trials.present_again)
        self.analysis.save_profile_button.clicked.connect(self._on_save_profile_clicked)
        self.analysis.error_raised.connect(self.error_raised)
        self.trials.trial_presented.connect(self._on_trials_trial_presented)
        self.trials.event_logged.connect(self.log_event)
        self.trials.error_raised.connect(self.error_raised)
        self.trials.resumable_changed.connect(self.setup.resume_button.setEnabled)
        self.trials.finished.connect(self._on_trials_finished)
        self.health_timer = QtCore.QTimer(self)
        self.health_timer.timeout.connect(self._on_health_timer_timeout)
        self.health_timer.start(500)
        state.layout_changed.connect(self._on_state_layout_changed)
        self._on_state_layout_changed(state.layout)

    def _on_state_layout_changed(self, layout) -> None:
        """The paper's experiments (and tuning by feel) run on a grid: on another layout Start
        is off and the run box says why; the analysis still works."""
        grid = layout.is_grid
        why = ("" if grid else f"The paper's experiments and tuning by feel need a grid profile "
               f"such as palm-5x6; this profile is a layout ({layout.describe()}). The analysis "
               "of a results folder works on any profile.")  # fmt: skip
        self.setup.start_button.setEnabled(grid)
        self.setup.start_button.setToolTip(why)
        if not self.running:
            self.run_label.setText(why or "Set up a session and press Start.")

    @staticmethod
    def _scrolled(column: QtWidgets.QWidget) -> QtWidgets.QScrollArea:
        """The set-up and the run in a column that scrolls up and down, never sideways: the
        tab's least height was theirs (531 px), and with the device dock, the menus and a
        title bar the window was taller than a 1280 x 720 screen."""
        scroll = QtWidgets.QScrollArea()
        scroll.setWidget(column)
        scroll.setWidgetResizable(True)
        scroll.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
        scroll.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        bar = scroll.style().pixelMetric(QtWidgets.QStyle.PixelMetric.PM_ScrollBarExtent)
        scroll.setMinimumWidth(column.minimumSizeHint().width() + bar)
        return scroll

    def _run_box(self) -> QtWidgets.QGroupBox:
        """The run as it goes: participant, trial, progress, health, results path, log."""
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
        return run

    # --- the run, for the window ---------------------------------------------------------------

    @property
    def runner(self):
        """The run's runner (None when no run is active)."""
        return self.trials.runner

    @property
    def running(self) -> bool:
        """True while a runner is active."""
        return self.trials.runner is not None

    def pause(self, why: str = "paused (Esc)") -> None:
        """The array off; the trial is presented again when the run resumes."""
        self.trials.pause(why)

    def handle_key(self, event) -> bool:
        """Keys while running; True if the key was used."""
        return self.trials.handle_key(event)

    def on_device_status(self, stats) -> None:
        """The stream's state changed: a lost link pauses the run; its return is logged."""
        self.trials.on_device_status(stats)

    def prepare_tuning(self) -> None:
        """Set the console up for tuning the correction by feel, and say what comes."""
        self.setup.select("correction")
        self.run_label.setText(tuning_intro())
        self.setup.participant_edit.setFocus()

    # --- session -------------------------------------------------------------------------------

    def log_event(self, text: str) -> None:
        """Add a timestamped line to the console's event log."""
        self.log.appendPlainText(f"{time.strftime('%H:%M:%S')}  {text}")

    def _device_state(self) -> str:
        return "" if self.stats is None else self.stats().state

    def _health_counts(self) -> dict | None:
        """The stream's counters now (for the per-trial health columns)."""
        if self.stats is None:
            return None
        stats = self.stats()
        return {"late_frames": stats.late, "skipped_frames": stats.skipped,
                "link_errors": stats.errors}  # fmt: skip

    def start(self) -> bool:
        """Open (or resume) the session and start the selected experiment; False (and a
        message) if it cannot start."""
        if self.running:
            return False
        setup = self.setup
        kind = setup.experiment
        try:
            pid = check_participant(setup.participant_edit.text())
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
        text = setup.folder_edit.text().strip()
        if not text:  # (it wrote into whatever folder the tuner was started in)
            self.error_raised.emit("the results folder is empty: name the folder the "
                                   "participants' results go to")  # fmt: skip
            return False
        folder = Path(text).expanduser().absolute()  # "~/res" is the home's, not a "~" folder
        existing = folder / f"participant-{pid}"
        title = TITLES[kind]
        if (existing / f"{kind}.csv").exists():  # the runner's results file
            question = (
                f"Participant {pid} already has results of this experiment in {existing}.\n\n"
                f"Resume {title} for {pid}?"
            )
        elif (existing / SESSION_FILE).exists():
            question = (
                f"Participant {pid} has a session in {existing}, without results of this "
                f"experiment.\n\nStart {title} for {pid}?"
            )
        else:
            question = f"Start {title} for a new participant, {pid}?\n\nResults go to {existing}."
        if not self.confirm("Start the run", question):
            return False
        try:
            runner = self._open_runner(kind, folder, pid)
        except OSError as exc:  # (it said only "[Errno 28] No space left on device")
            where = exc.filename or folder
            self.error_raised.emit(f"could not start: {where}: {exc.strerror or exc}; free "
                                   "space there, or choose another results folder")  # fmt: skip
            return False
        except ValueError as exc:
            self.error_raised.emit(str(exc))
            return False
        self.trials.begin(runner)
        self.saved_scene = self.state.scene
        self.state.lock(self.trials)  # the trials alone set the stimulus until the run ends
        self.participant_label.setText(f"participant {pid}")
        self.path_label.setText(f"results: {runner.path}")
        self.log_event(f"started {title} for {pid} on {self.device()} ({runner.done} done)")
        if runner.recovered:
            self.log_event(f"resumed after a crash: {runner.recovered}; that trial comes again")
        self.participant_window.show_on(setup.screen_combo.currentData())
        self.setup.set_running(True)
        self.running_changed.emit(True)
        self.trials.present()
        return True

    def _open_runner(self, kind: str, folder: Path, pid: str):
        """The runner of experiment ``kind`` on the participant's session (opened or
        resumed)."""
        profile = self.profile()
        setup = self.setup
        session = open_session(folder, pid, seed=setup.seed_spin.value(),
                               device_profile=profile.name)  # fmt: skip
        if session.seed != setup.seed_spin.value():  # a resumed session keeps its own
            self.log_event(f"the participant's session has seed {session.seed}, not "
                           f"{setup.seed_spin.value()}: it keeps its own")  # fmt: skip
            setup.seed_spin.setValue(session.seed)
        methods = setup.methods_edit.methods
        recorded = session.parameters.get(f"{kind}_methods")
        if kind in ("exp1", "exp3") and recorded and list(methods) == list(PAPER_METHODS):
            # Resuming a participant who ran another set, with the console at its default:
            # resume their set (another set typed in is refused, naming both).
            methods = None
            setup.methods_edit.apply(recorded)
            self.log_event(f"resuming {kind} on the participant's methods: "
                           f"{' '.join(recorded)}")  # fmt: skip
        if kind == "exp3":
            return RUNNERS[kind](session, emphasis=setup.emphasis_spin.value(),
                                 methods=methods, profile=profile)  # fmt: skip
        if kind == "exp1":
            return RUNNERS[kind](session, methods=methods, profile=profile)
        return RUNNERS[kind](session, profile=profile)

    def stop(self) -> None:
        """Stop the run (everything answered so far is on disk) and turn the array off."""
        if not self.running:
            return
        runner = self.trials.stop()
        runner.close()
        self.log_event(f"stopped at {runner.done} of {runner.total}; start again to resume")
        self.run_label.setText("Stopped. Start again with the same participant to resume.")
        self._end_run()

    def _end_run(self, finished: bool = False) -> None:
        """Back to the tuning scene, paused (the participant's hand may still be on the array).
        The participant's window closes, or after the last trial says the part is finished
        (until the next run or the experimenter closes it)."""
        saved, self.saved_scene = self.saved_scene, None
        self.state.unlock(self.trials)
        if saved is not None:
            self.state.set_scene(saved.replace(playing=False, epoch=self.state.scene.epoch + 1))
        if not finished:
            self.participant_window.hide()
        self.setup.resume_button.setEnabled(False)
        self.setup.set_running(False)
        self.running_changed.emit(False)

    def _on_trials_trial_presented(self, trial) -> None:
        runner = self.trials.runner
        done, total = runner.progress()
        self.progress.setRange(0, max(total, 1))
        self.progress.setValue(done)
        info = ", ".join(f"{k} {v}" for k, v in trial.info.items())
        self.run_label.setText(
            f"{TITLES[runner.experiment]}: trial {done + 1} of {total}, {trial.stage} "
            f"{trial.index} ({trial.kind}{': ' + info if info else ''})"
        )

    def _on_trials_finished(self) -> None:
        runner = self.trials.runner
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
                self.analysis.save_profile_button.setEnabled(True)
                self.calibration_done.emit(self.last_calibration)
        runner.close()
        self.trials.release()
        self._end_run(finished=True)

    def _finish_tuning(self, runner) -> None:
        """Keep the measured correction (record and preset in the participant's folder), or
        say why there is none; the window offers to apply it."""
        result = runner.result()
        preset = None
        if result.ok:
            preset, error = keep_correction(runner, result)
            if error:
                self.error_raised.emit(error)
            self.last_calibration = runner.calibration()
            self.analysis.save_profile_button.setEnabled(True)
            mu, gamma = value3(result.mu), value3(result.gamma)
            self.log_event(f"correction: mu {mu}, gamma {gamma} ({result.trials} trials); "
                           f"saved {preset}")  # fmt: skip
            self.run_label.setText(f"Finished: mu {mu}, gamma {gamma}.")
        else:
            self.log_event(f"no correction: {result.message}")
            self.run_label.setText("Finished without a correction (see the log).")
        self.last_tuning = result
        self.correction_measured.emit(result, preset)

    # --- health and files ----------------------------------------------------------------------

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

    def _on_save_profile_clicked(self) -> None:
        pid = dialogs.safe_name(self.setup.participant_edit.text() or "participant")
        name = f"{self.profile().name}-calibrated-{pid}-{dialogs.today()}.json"
        path = dialogs.save_path(self, "profiles", "Save calibrated profile", name,
                                 ["Profiles (*.json)"])  # fmt: skip
        if path:
            self.profile_save_requested.emit(path)
