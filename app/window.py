"""The tuner's main window: a shell that assembles the parts and wires them together.

The parts know the state (:mod:`.state`), the device controller (:mod:`.device`) and the core,
never each other: the Tune tab (:mod:`.tune`), Compare (:mod:`.compare`), Blind A/B
(:mod:`.blind`), the experiments console with the participant's window and guided tuning
(:mod:`.experiments`), the controls (:mod:`.controls`) and the device panel
(:mod:`.device_panel`) and the pattern editor (:mod:`.timeline`) in docks, the files
(:mod:`.files`), the menus (:mod:`.menus`) and the keys (:mod:`.keys`). This module connects
their signals, decides what a run or a blind test hides, and keeps the session's settings.
"""

from __future__ import annotations

from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.device.profile import default_profile
from tactile_core.rendering import placement
from tactile_core.rendering.methods import get_method

from . import dialogs
from . import settings as remembered
from .blind import BlindPanel
from .compare import CompareView
from .controls import ControlsPanel
from .device import DeviceController
from .device_panel import DevicePanel
from .experiments import ExperimentsPanel, GuidedTuning
from .files import FileActions
from .keys import KeyFilter, is_text_input
from .menus import build_menus
from .serve_panel import install_serve
from .state import TunerState
from .texts import (
    BLIND_FILES,
    DRAW_HELP,
    HIDDEN_BLIND,
    HIDDEN_EXPERIMENT,
    PROFILE_BLOCKED,
    RUN_FILES,
    value3,
)
from .timeline import install_timeline
from .titles import same_tuning, scene_name
from .tune import TuneWidget


class MainWindow(QtWidgets.QMainWindow):
    """Heatmap, activation curves and correction curve beside the controls and the device.

    Parameters
    ----------
    device_url : str, optional
        Connect to this device at start-up; the simulated array otherwise.
    profile : DeviceProfile, optional
        The array (else the last session's profile if still known, else the palm array).
    preset : Preset, optional
        Start from this preset (else the last session's scene, else the built-in Experiment 1
        line with its notes).
    restore : bool
        Restore the last session's scene and window layout (QSettings).
    process : bool
        Stream from a child process (default; see :class:`app.device.DeviceController`).
    realtime : bool
        Ask for real-time priority for the stream's output thread.
    remember : bool
        Save the scene and window layout for the next start when the window closes (False for
        ``--screenshot``, which shows the session and must not change it).

    Attributes
    ----------
    state : TunerState
    device : DeviceController
    tune : TuneWidget
        The Tune tab (heatmap, curves, correction curve).
    compare : CompareView
    blind : BlindPanel
    experiments : ExperimentsPanel
        The Experiments tab (with the participant's window).
    controls : ControlsPanel
    device_panel : DevicePanel
    files : FileActions
        Presets, exports and profiles.
    guided : GuidedTuning
        The result of tuning the correction by feel.
    serve : ServeController
        Driven by another program (OSC), and LSL markers (:mod:`.serve`).
    """

    def __init__(
        self,
        device_url=None,
        profile=None,
        preset=None,
        restore=True,
        process=True,
        realtime=True,
        remember=True,
    ):
        super().__init__()
        self.remember = bool(remember)
        self.setWindowTitle("tactile-tuner")
        self.settings = QtCore.QSettings()
        self.last_error = ""
        self.confirm = lambda title, text: dialogs.confirm(self, title, text)
        """Asks yes or no before a run or unsaved ratings are given up (tests answer it)."""
        self._ask_before_closing = True
        saved = remembered.restored_preset(self.settings) if restore else None
        start = preset or saved or remembered.start_preset()
        profile = profile or remembered.restored_profile(saved) or default_profile()
        self.state = TunerState(start.scene, layout=profile.layout)
        if start.device_profile != profile.name:
            self.state.fit_scene()  # a scene made for another array: its shape may lie off this
        self.device = DeviceController(self.state, profile, process=process, realtime=realtime,
                                       lead_ms=start.lead_ms)  # fmt: skip
        self.files = FileActions(self.state, self.device, self)
        self.files.set_preset(start)
        self.files.preset_scene = self.state.scene  # as it plays here: no star for a fitting
        self.files.modified_at_start = saved is not None and remembered.was_modified(self.settings)

        # The tabs --------------------------------------------------------------------------
        self.tune = TuneWidget(self.state, self.device)
        self.compare = CompareView(self.state, motors=lambda: self.device.profile.motor)
        self.blind = BlindPanel(self.state)
        self.experiments = ExperimentsPanel(
            self.state,
            lambda: self.device.profile,
            lambda: self.device.stats,
            lambda: self.device.description,
        )
        self.guided = GuidedTuning(self.state, self)
        self.tabs = QtWidgets.QTabWidget()
        self.tabs.addTab(self.tune, "Tune")
        self.tabs.addTab(self.compare, "Compare")
        self.tabs.addTab(self.blind, "Blind A/B")
        self.tabs.addTab(self.experiments, "Experiments")
        self.banner = QtWidgets.QLabel()
        self.banner.setObjectName("device_banner")
        self.banner.setWordWrap(True)
        self.banner.setStyleSheet(
            "background: #c0392b; color: white; font-weight: bold; padding: 6px;"
        )
        self.banner.setVisible(False)
        central = QtWidgets.QWidget()
        column = QtWidgets.QVBoxLayout(central)
        column.setContentsMargins(0, 0, 0, 0)
        column.setSpacing(0)
        column.addWidget(self.banner)
        column.addWidget(self.tabs, 1)
        self.setCentralWidget(central)

        # The docks -------------------------------------------------------------------------
        self.controls = ControlsPanel(self.state)
        scroll = QtWidgets.QScrollArea()
        scroll.setWidget(self.controls)
        scroll.setWidgetResizable(True)
        # Never sideways: the controls are laid out for the dock's width and scroll vertically.
        scroll.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        scroll.setMinimumWidth(self.controls.minimumSizeHint().width() + 18)
        self.controls_scroll = scroll
        self.controls_dock = self._dock("Controls", "controls_dock", scroll,
                                        QtCore.Qt.DockWidgetArea.LeftDockWidgetArea)  # fmt: skip
        self.device_panel = DevicePanel(self.device)
        self.device_dock = self._dock("Device", "device_dock", self.device_panel,
                                      QtCore.Qt.DockWidgetArea.BottomDockWidgetArea)  # fmt: skip

        self.view_menu, self._method_actions = build_menus(
            self,
            self.files,
            toggle_play=self.toggle_play,
            all_off=self.all_off,
            restart=self.state.restart,
            start_tuning=self.start_tuning,
            reset_layout=self.reset_layout,
            lanes_check=self.tune.lanes_check,
        )
        self._connect_parts()
        self.serve = install_serve(self)
        self.statusBar().showMessage(self.state.last_message or "ready")  # e.g. BA for AS
        self._key_filter = KeyFilter(
            self,
            windows=lambda: (self, self.experiments.participant_window),
            on_escape=self.all_off,
            run_active=lambda: self.experiments.running,
            on_run_key=self.experiments.handle_key,
            on_space=self.toggle_play,
            on_number=self.press_number,
            on_return=self.return_focus,
            run_only=lambda: (self.experiments.participant_window,),
        )
        QtWidgets.QApplication.instance().installEventFilter(self._key_filter)
        self.timeline = install_timeline(self)  # the pattern editor (a dock)

        self.tune.refresh()
        self._update_title()
        screen = QtGui.QGuiApplication.primaryScreen()
        if screen is not None:  # a default that fits; a saved size replaces it below
            area = screen.availableGeometry()
            self.resize(min(1400, round(area.width() * 0.92)), min(900, round(area.height() * 0.9)))
        self.controls.set_profile(self.device.profile)
        self.tune.display.start()

        if restore:
            remembered.restore_window(self)
            if preset is None:
                remembered.reopen_pattern(self)
        if device_url:
            self.device.connect_device(device_url)

    def _dock(self, title, name, widget, area) -> QtWidgets.QDockWidget:
        dock = QtWidgets.QDockWidget(title, self)
        dock.setObjectName(name)
        dock.setWidget(widget)
        self.addDockWidget(area, dock)
        return dock

    def _connect_parts(self) -> None:
        """The parts' signals to one another (through the shell) and to the window."""
        status = self.statusBar().showMessage
        state, device, tune, gestures = self.state, self.device, self.tune, self.tune.gestures
        files = self.files
        state.error_raised.connect(self.show_error)
        state.message_posted.connect(status)
        state.playing_changed.connect(self._on_state_playing_changed)
        state.scene_changed.connect(lambda _: self._update_title())
        device.error_raised.connect(self.show_error)
        device.connection_changed.connect(self._on_device_connection_changed)
        device.status_changed.connect(self._on_device_status_changed)
        device.status_changed.connect(self.experiments.on_device_status)
        tune.error_raised.connect(self.show_error)
        tune.display.frame_shown.connect(self._on_display_frame_shown)
        gestures.can_pulse = lambda: not (self.experiments.running or self.blind.session.active)
        gestures.draw_mode_changed.connect(self.controls.set_draw_mode)
        gestures.message_posted.connect(status)
        self.controls.all_off_requested.connect(self.all_off)
        self.controls.draw_mode_toggled.connect(gestures.set_draw_mode)
        self.device_panel.profile_requested.connect(self.files.ask_open_profile)
        self.device_panel.profile_chosen.connect(self.files.use_profile)
        self.files.profile_blocked = self._profile_blocked
        self.files.curves = lambda: tune.shown_curves
        blind = self.blind.session
        self.files.blocked = lambda: (
            BLIND_FILES if blind.active else RUN_FILES if self.experiments.running else ""
        )
        self.files.before_load = lambda: gestures.set_draw_mode(False)
        self.files.follow_drawing(gestures)
        self.files.error_raised.connect(self.show_error)
        self.files.message_posted.connect(status)
        self.files.preset_changed.connect(self._update_title)
        self.files.preset_changed.connect(self._show_preset)
        self.controls.preset.notes_edited.connect(lambda text: setattr(files, "preset_notes",
                                                                       text))  # fmt: skip
        self._show_preset()
        self.blind.blind_changed.connect(self._on_blind_changed)
        self.experiments.running_changed.connect(self._on_experiments_running_changed)
        self.experiments.error_raised.connect(self.show_error)
        self.experiments.correction_measured.connect(self.guided.show_result)
        self.experiments.profile_save_requested.connect(self.save_calibrated_profile)
        self.guided.message_posted.connect(status)
        self.guided.save_preset_requested.connect(self.files.ask_save_preset)

    # --- commands that span the parts ------------------------------------------------------------

    def all_off(self) -> None:
        """Everything off now (Esc, the button, the menu)."""
        self.tune.gestures.end_pulse(restore=False)  # (the tuning goes out paused below)
        self.device.all_off()
        if self.experiments.running:  # Space is the run's, not play/pause
            self.experiments.pause()  # (the menu's All off said so, and did not pause it)
            self.statusBar().showMessage("all off: the run is paused (Enter or Present again "
                                         "resumes it)")  # fmt: skip
        else:
            self.statusBar().showMessage("all off (Space plays again)")

    def toggle_play(self) -> None:
        """Play or pause the trace (Space); a pulsed tactor is let go first."""
        if self.tune.gestures.pulsing:
            self.tune.gestures.end_pulse()
            return
        # A held (scrubbed) instant plays the trace again; otherwise play or pause.
        self.state.update(playing=self.state.held or not self.state.scene.playing)

    def press_number(self, key: int) -> bool:
        """Number keys: the method, or in blind A/B the shuffled method behind the key; True if
        the key meant something."""
        if self.blind.session.active:
            if key > len(self.blind.session.mapping):
                return False
            self.blind.select_key(key)
            return True
        names = self.controls.method_names()
        if key > len(names):
            return False
        name = names[key - 1]
        why = placement.refusal(name, self.state.layout)
        if why:
            self.show_error(why)
            return True
        if self.tune.heatmap.drawing and get_method(name).needs_shape:
            self.show_error(f"{name} is not available in draw mode: {DRAW_HELP}")
            return True
        self.state.update(method=name)
        return True

    def return_focus(self) -> None:
        """Give the keyboard back to the window (after Enter in a field)."""
        focus = QtWidgets.QApplication.focusWidget()
        if focus is not None and is_text_input(focus):
            focus.clearFocus()
        self.tabs.setFocus()

    def show_error(self, message: str) -> None:
        """Tell the user what went wrong, without stopping anything."""
        self.last_error = message
        self.statusBar().showMessage(message, 10_000)
        box = QtWidgets.QMessageBox(self)
        box.setIcon(QtWidgets.QMessageBox.Icon.Warning)
        box.setWindowTitle("tactile-tuner")
        box.setText(message)
        box.setAttribute(QtCore.Qt.WidgetAttribute.WA_DeleteOnClose)
        box.open()  # not modal to the event loop: streaming and display keep running

    def _profile_blocked(self) -> str:
        """Why the device profile may not change now ("" when it may)."""
        if self.experiments.running:
            return PROFILE_BLOCKED.format("during an experiment run")
        if self.blind.session.active or self.blind.session.unsaved:
            return PROFILE_BLOCKED.format("while a Blind A/B session is on or unsaved")
        return ""

    def start_tuning(self) -> None:
        """Guide the experimenter to the tuning procedure (the Experiments tab, set up)."""
        if self.experiments.running:  # (it rewrote the console of the run going on)
            self.statusBar().showMessage("a run is going on: Stop it first to tune by feel", 8000)
            return
        self.tabs.setCurrentWidget(self.experiments)
        self.experiments.prepare_tuning()

    def save_calibrated_profile(self, path) -> bool:
        """Save the device profile with the last calibration run's offsets and gains, and use
        it."""
        return self.files.save_calibrated_profile(path, self.experiments.last_calibration)

    # --- what the parts show -------------------------------------------------------------------

    def _on_state_playing_changed(self, playing: bool) -> None:
        if playing:
            self.statusBar().showMessage("playing", 2000)

    def _on_display_frame_shown(self, scene, start_s, rate_hz, phase_s) -> None:
        if self.tabs.currentWidget() is self.compare:
            self.compare.tick(scene, start_s, rate_hz, phase_s)

    def _update_tune_page(self) -> None:
        """The tune tab's views, or why they are hidden (a run, a blind test)."""
        running = self.experiments.running
        if running or self.blind.session.active:
            self.tune.hide_views(HIDDEN_EXPERIMENT if running else HIDDEN_BLIND)
        else:
            self.tune.show_views()

    def _on_blind_changed(self, blind: bool) -> None:
        if blind:  # draw mode would switch to AS and say so
            self.tune.gestures.set_draw_mode(False)
        self.controls.playback.draw_check.setEnabled(not blind)
        for action in self._method_actions:
            action.setEnabled(not blind)
        self._update_title()
        self._update_tune_page()
        self.tune.set_method_hidden(blind)
        self.tabs.setTabEnabled(1, not blind)
        self.controls.set_method_hidden(blind)
        self.device_panel.set_status_visible(not blind)

    def _on_experiments_running_changed(self, running: bool) -> None:
        """A run hides everything that shows the stimulus (participants see the screen). A
        calibration run measures raw drive, so a calibrated profile is set aside meanwhile."""
        runner = self.experiments.runner
        # Tuning measures thresholds on raw drive, as the calibration does.
        if running and runner is not None and runner.experiment in ("calibration", "correction"):
            if self.device.profile.calibrated:
                self._profile_before_calibration = self.device.profile
                self.device.set_profile(self.device.profile.without_calibration())
        elif not running and getattr(self, "_profile_before_calibration", None) is not None:
            self.device.set_profile(self._profile_before_calibration)
            self._profile_before_calibration = None
        self._update_tune_page()
        self.tabs.setTabEnabled(0, not running)
        self.tabs.setTabEnabled(1, not running)
        self.tabs.setTabEnabled(2, not running)
        self.device_panel.set_run_locked(running)
        # The controls show the stimulus (a line's ends give its direction away): hide them.
        self.controls_dock.setVisible(not running)
        self.device_panel.set_status_visible(not running)

    def _on_device_connection_changed(self, description: str) -> None:
        self.statusBar().showMessage(f"streaming to {description}", 5000)
        self.controls.set_profile(self.device.profile)

    def _on_device_status_changed(self, stats) -> None:
        """A lost device is obvious: a banner over the tabs and the heatmap marked."""
        lost = stats.state in ("disconnected", "failed", "refused") or (
            stats.state == "stopped" and not self.device.simulated
        )
        if lost:
            self.banner.setText(f"Device not streaming ({stats.state}): {stats.status}")
        self.banner.setVisible(lost)
        self.tune.heatmap.set_streaming(not lost, f"not streaming: {stats.state}")

    def _show_preset(self) -> None:
        self.controls.preset.show_preset(self.files.preset_name, self.files.preset_notes)

    def _update_title(self) -> None:
        """``tactile-tuner - name[*] - method, mu, gamma``: what plays (:func:`.titles.scene_name`),
        with a star once the scene differs from the preset it came from."""
        if self.blind.session.active:  # the method, and whether it is the preset's, stay hidden
            self.setWindowTitle("tactile-tuner - Blind A/B (the method is hidden)")
            return
        scene, files = self.state.scene, self.files
        came_from = files.preset_scene
        modified = files.modified_at_start or (came_from is not None
                                               and not same_tuning(scene, came_from))  # fmt: skip
        name = scene_name(scene, came_from, files.preset_name) + (" *" if modified else "")
        self.setWindowTitle(
            f"tactile-tuner - {name} - {scene.method}, mu {value3(scene.mu)}, "
            f"gamma {value3(scene.gamma)}"
        )

    # --- layout ----------------------------------------------------------------------------------

    def reset_layout(self) -> None:
        """The docks where they start: controls on the left, device below; all shown."""
        areas = QtCore.Qt.DockWidgetArea
        for dock, area in ((self.controls_dock, areas.LeftDockWidgetArea),
                           (self.device_dock, areas.BottomDockWidgetArea)):  # fmt: skip
            dock.setFloating(False)
            self.addDockWidget(area, dock)
            dock.show()
        self.resizeDocks([self.controls_dock], [self.controls_scroll.minimumWidth()],
                         QtCore.Qt.Orientation.Horizontal)  # fmt: skip
        self.tune.fit_heatmap()

    def fit_to_screen(self, keep_size: bool = False) -> None:
        """Keep the window on its screen and no larger than it (:func:`.settings.fit_window`);
        ``keep_size``: a size asked for (``--size``) is kept, only the position is fitted."""
        remembered.fit_window(self, keep_size)

    def resizeEvent(self, event) -> None:  # Qt override
        super().resizeEvent(event)
        QtCore.QTimer.singleShot(0, self.tune.fit_heatmap)

    # --- settings --------------------------------------------------------------------------------

    def save_settings(self) -> None:
        """Remember the scene and the window layout for the next start (:mod:`.settings`);
        nothing for a window made with ``remember=False`` (a screenshot)."""
        if self.remember:
            remembered.save_window(self)

    def close_now(self) -> None:
        """Close without asking (a signal: Ctrl-C in the terminal, SIGTERM, SIGHUP)."""
        self._ask_before_closing = False
        self.close()

    def _may_close(self) -> bool:
        """Whether to close: asks first while a run is on or ratings are unsaved."""
        reasons = []
        if self.experiments.running:
            reasons.append("An experiment is running: it stops (every answer so far is on "
                           "disk, and Start resumes it).")  # fmt: skip
        if self.blind.session.unsaved:
            reasons.append("The Blind A/B ratings are not saved" + (
                f"; they are autosaved in\n{self.blind.session.autosave_path}"
                if self.blind.session.autosave_path else "."))  # fmt: skip
        if not reasons or not self._ask_before_closing:
            return True
        return self.confirm("Quit tactile-tuner", "\n\n".join([*reasons, "Quit anyway?"]))

    def closeEvent(self, event) -> None:  # Qt override
        if not self._may_close():
            event.ignore()
            return
        self.tune.display.stop()
        for box in self.findChildren(QtWidgets.QMessageBox):
            box.close()
        self.device.shutdown()  # all off first
        self.experiments.stop()  # a run: its file closed, the participant released
        self.experiments.participant_window.hide()
        try:
            self.save_settings()
        finally:
            QtWidgets.QApplication.instance().removeEventFilter(self._key_filter)
            super().closeEvent(event)
