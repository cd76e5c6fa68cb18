"""The tuner's main window."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

import tactile_core as tc
from tactile_core import export
from tactile_core.curves import activation_curves
from tactile_core.device import ProfileError, find_profile, load_profile
from tactile_core.methods import METHODS
from tactile_core.presets import (
    Preset,
    PresetError,
    builtin_presets,
    load_preset,
    preset_from_dict,
    save_preset,
)
from tactile_core.render import point_entries

from .compare import BlindPanel, CompareView
from .device import DeviceController
from .experiments import ExperimentsPanel
from .panels import DRAW_HELP, ControlsPanel, DevicePanel
from .state import TunerState
from .views import CorrectionView, CurvesView, HeatmapView, cell_colors

DISPLAY_HZ = 60
HIDDEN_BLIND = (
    "Blind A/B in progress: the display is hidden so that it does not give the method away. "
    "Reveal in the Blind A/B tab to see it again."
)
HIDDEN_EXPERIMENT = (
    "An experiment is running: the display is hidden so that it does not give the stimulus away."
)


class _KeyFilter(QtCore.QObject):
    """Application-wide keys: Esc always turns everything off; Space and 1-4 act unless a
    text field has the focus (so typing a number into a box still works)."""

    def __init__(self, window):
        super().__init__(window)
        self.window = window

    def eventFilter(self, obj, event):
        if event.type() != QtCore.QEvent.Type.KeyPress or event.isAutoRepeat():
            return False
        active = QtWidgets.QApplication.activeWindow()
        ours = (self.window, self.window.experiments.participant_window)
        if active is not None and active not in ours:
            return False  # a dialog or another window: its keys are its own
        key = event.key()
        if key == QtCore.Qt.Key.Key_Escape:
            self.window.all_off()
            if self.window.experiments.running:
                self.window.experiments.pause()
            return False  # dialogs still see Esc
        if self.window.experiments.running:
            # A run owns the keyboard (its rating box takes digits and Enter itself).
            return self.window.experiments.handle_key(event)
        focus = QtWidgets.QApplication.focusWidget()
        typing = isinstance(
            focus,
            (
                QtWidgets.QLineEdit,
                QtWidgets.QAbstractSpinBox,
                QtWidgets.QTextEdit,
                QtWidgets.QPlainTextEdit,
            ),
        )
        if typing:
            return False
        if key == QtCore.Qt.Key.Key_Space:
            self.window.toggle_play()
            return True
        if QtCore.Qt.Key.Key_1 <= key <= QtCore.Qt.Key.Key_4:
            self.window.press_number(key - QtCore.Qt.Key.Key_1 + 1)
            return True
        return False


class MainWindow(QtWidgets.QMainWindow):
    """Heatmap, activation curves and correction curve beside the controls and the device.

    Parameters
    ----------
    device_url : str, optional
        Connect to this device at start-up; the simulated array otherwise.
    profile : DeviceProfile, optional
    preset : Preset, optional
        Start from this preset (else the last session's scene, else the Experiment 1 line).
    restore : bool
        Restore the last session's scene and window layout (QSettings).
    process : bool
        Stream from a child process (default; see :class:`app.device.DeviceController`).
    realtime : bool
        Ask for real-time priority for the stream's output thread.
    """

    def __init__(
        self, device_url=None, profile=None, preset=None, restore=True, process=True, realtime=False
    ):
        super().__init__()
        self.setWindowTitle("tactile-tuner")
        self.settings = QtCore.QSettings()
        self.last_error = ""
        self.preset_name = "Experiment 1 line"
        self.preset_notes = ""
        scene = None
        if restore:
            scene = self._restored_scene()
        if preset is not None:
            scene = preset.scene
            self.preset_name, self.preset_notes = preset.name, preset.notes
        self.state = TunerState(scene)
        self.device = DeviceController(self.state, profile, process=process, realtime=realtime)
        self._trace_cache = (None, None)
        self._display_times: list[float] = []
        self._draw_backup = None

        # Tune tab ----------------------------------------------------------------------------
        grid = self.device.profile.grid
        self.heatmap = HeatmapView(grid.cols, grid.rows, title="Array")
        self.heatmap.setObjectName("heatmap")
        self.curves = CurvesView()
        self.correction = CorrectionView()
        right = QtWidgets.QSplitter(QtCore.Qt.Orientation.Vertical)
        right.addWidget(self.curves)
        right.addWidget(self.correction)
        tune = QtWidgets.QSplitter(QtCore.Qt.Orientation.Horizontal)
        tune.addWidget(self.heatmap)
        tune.addWidget(right)
        tune.setSizes([420, 560])
        self.hidden_label = QtWidgets.QLabel(HIDDEN_BLIND)
        self.hidden_label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.hidden_label.setWordWrap(True)
        self.tune_stack = QtWidgets.QStackedWidget()
        self.tune_stack.addWidget(tune)
        self.tune_stack.addWidget(self.hidden_label)

        self.compare = CompareView(self.state)
        self.blind = BlindPanel(self.state)
        self.experiments = ExperimentsPanel(
            self.state,
            lambda: self.device.profile,
            lambda: self.device.stats,
            lambda: self.device.description,
        )
        self.tabs = QtWidgets.QTabWidget()
        self.tabs.addTab(self.tune_stack, "Tune")
        self.tabs.addTab(self.compare, "Compare")
        self.tabs.addTab(self.blind, "Blind A/B")
        self.tabs.addTab(self.experiments, "Experiments")
        self.setCentralWidget(self.tabs)

        # Docks -------------------------------------------------------------------------------
        self.controls = ControlsPanel(self.state)
        scroll = QtWidgets.QScrollArea()
        scroll.setWidget(self.controls)
        scroll.setWidgetResizable(True)
        dock = QtWidgets.QDockWidget("Controls", self)
        dock.setObjectName("controls_dock")
        dock.setWidget(scroll)
        self.addDockWidget(QtCore.Qt.DockWidgetArea.LeftDockWidgetArea, dock)
        self.controls_dock = dock
        self.device_panel = DevicePanel(self.device)
        dock = QtWidgets.QDockWidget("Device", self)
        dock.setObjectName("device_dock")
        dock.setWidget(self.device_panel)
        self.addDockWidget(QtCore.Qt.DockWidgetArea.BottomDockWidgetArea, dock)

        self._build_menu()
        self.statusBar().showMessage("ready")

        # Wiring ------------------------------------------------------------------------------
        # Scene changes arrive up to ~100 times a second while a slider is dragged: the array
        # gets each one at once (DeviceController), the views are rebuilt at most every 50 ms.
        self._views_timer = QtCore.QTimer(self)
        self._views_timer.setSingleShot(True)
        self._views_timer.setInterval(50)
        self._views_timer.timeout.connect(lambda: self._on_state_scene_changed(self.state.scene))
        self.state.scene_changed.connect(self._on_state_scene_changed_deferred)
        self.state.show_levels_changed.connect(self.heatmap.set_show_values)
        self.state.error_raised.connect(self.show_error)
        self.device.error_raised.connect(self.show_error)
        self.device.connection_changed.connect(self._on_device_connection_changed)
        self.controls.all_off_requested.connect(self.all_off)
        self.controls.draw_mode_toggled.connect(self.set_draw_mode)
        self.device_panel.profile_requested.connect(self._on_profile_requested)
        self.heatmap.point_drawn.connect(self._on_heatmap_point_drawn)
        self.heatmap.draw_released.connect(self._on_heatmap_draw_released)
        self.blind.blind_changed.connect(self._on_blind_changed)
        self.experiments.running_changed.connect(self._on_experiments_running_changed)
        self.device.status_changed.connect(self.experiments.on_device_status)
        self.experiments.error_raised.connect(self.show_error)
        self.experiments.save_profile_requested = self.save_calibrated_profile
        self._key_filter = _KeyFilter(self)
        QtWidgets.QApplication.instance().installEventFilter(self._key_filter)

        self._on_state_scene_changed(self.state.scene)
        self.controls.set_felt_available(self.device.profile.response is not None)
        self.display_timer = QtCore.QTimer(self)
        self.display_timer.setTimerType(QtCore.Qt.TimerType.PreciseTimer)
        self.display_timer.timeout.connect(self._on_display_timer_timeout)
        self.display_timer.start(round(1000 / DISPLAY_HZ))

        if restore:
            self._restore_layout()
        if device_url:
            self.device.connect_device(device_url)

    # --- menus -------------------------------------------------------------------------------

    def _build_menu(self) -> None:
        menu = self.menuBar().addMenu("&File")
        menu.addAction("Open preset...", self._on_open_preset, QtGui.QKeySequence.StandardKey.Open)
        menu.addAction(
            "Save preset as...", self._on_save_preset, QtGui.QKeySequence.StandardKey.Save
        )
        builtins = menu.addMenu("Built-in presets")
        for stem, path in builtin_presets().items():
            builtins.addAction(stem, lambda p=path: self.load_preset_file(p))
        menu.addSeparator()
        menu.addAction("Export activation curves (CSV, PNG, SVG)...", self._on_export_curves)
        menu.addAction("Export correction table (CSV, C header)...", self._on_export_lut)
        menu.addSeparator()
        menu.addAction("Quit", self.close, QtGui.QKeySequence.StandardKey.Quit)
        menu = self.menuBar().addMenu("&Array")
        menu.addAction("Play / pause\tSpace", self.toggle_play)
        menu.addAction("All off\tEsc", self.all_off)
        menu.addAction("Restart trace", self.state.restart)

    # --- actions -----------------------------------------------------------------------------

    def all_off(self) -> None:
        """Everything off now (Esc, the button, the menu)."""
        self.device.all_off()
        self.statusBar().showMessage("all off")

    def toggle_play(self) -> None:
        """Play or pause the trace (Space)."""
        self.state.update(playing=not self.state.scene.playing)

    def press_number(self, key: int) -> None:
        """Keys 1-4: the method, or in blind A/B the shuffled method behind the key."""
        if self.blind.mapping and not self.blind.revealed:
            self.blind.select_key(key)
            return
        name = list(METHODS)[key - 1]
        if self.heatmap.drawing and METHODS[name].needs_shape:
            self.show_error(f"{name} is not available in draw mode: {DRAW_HELP}")
            return
        self.state.update(method=name)

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

    # --- presets -----------------------------------------------------------------------------

    def load_preset_file(self, path) -> bool:
        """Load a preset; on any problem show it and change nothing."""
        try:
            preset = load_preset(path)
        except PresetError as exc:
            self.show_error(str(exc))
            return False
        if preset.device_profile != self.device.profile.name:
            try:  # by name among the bundled and the user's profiles, never a path
                self.device.set_profile(find_profile(preset.device_profile))
            except ProfileError as exc:
                self.statusBar().showMessage(
                    f"kept profile {self.device.profile.name}: {exc}", 10_000
                )
        self.set_draw_mode(False)
        self.state.set_scene(preset.scene.replace(epoch=self.state.scene.epoch + 1))
        self.preset_name, self.preset_notes = preset.name, preset.notes
        self.setWindowTitle(f"tactile-tuner - {preset.name}")
        self.statusBar().showMessage(f"loaded preset {preset.name}", 5000)
        return True

    def save_preset_file(self, path, name=None, notes=None) -> bool:
        """Save the current scene as a preset (atomically)."""
        path = Path(path)
        preset = Preset(
            self.state.scene.replace(playing=True),
            name=name or path.stem,
            notes=self.preset_notes if notes is None else notes,
            device_profile=self.device.profile.name,
        )
        try:
            save_preset(preset, path)
        except (OSError, ValueError) as exc:  # ValueError: a path refused before writing
            self.show_error(f"could not save {path}: {exc}")
            return False
        self.statusBar().showMessage(f"saved preset to {path}", 5000)
        return True

    def _on_open_preset(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Open preset", "", "Presets (*.json)")
        if path:
            self.load_preset_file(path)

    def _on_save_preset(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, "Save preset", "preset.json", "Presets (*.json)"
        )
        if path:
            self.save_preset_file(path)

    # --- exports -----------------------------------------------------------------------------

    def export_curves(self, path) -> bool:
        """Activation curves of the current scene to .csv, .png or .svg."""
        path = Path(path)
        scene = self.state.scene
        curves = self._curves
        try:
            if path.suffix.lower() == ".csv":
                export.write_curves_csv(path, curves)
            elif path.suffix.lower() in (".png", ".svg"):
                title = f"{scene.method} on {scene.shape.spec}, mu = {scene.mu:g}, "
                title += f"gamma = {scene.gamma:g}"
                export.plot_curves(path, curves, title=title, colors=cell_colors(curves.cells))
            else:
                self.show_error(f"curves export must end in .csv, .png or .svg, got {path.name}")
                return False
        except (OSError, ValueError) as exc:  # ValueError: a path refused before writing
            self.show_error(f"could not write {path}: {exc}")
            return False
        self.statusBar().showMessage(f"exported curves to {path}", 5000)
        return True

    def export_lut(self, path) -> bool:
        """The correction as a 256-entry table: .csv, or a C header (.h)."""
        path = Path(path)
        scene, levels = self.state.scene, self.device.profile.levels
        try:
            if path.suffix.lower() == ".csv":
                export.write_lut_csv(path, scene.mu, scene.gamma, levels)
            elif path.suffix.lower() == ".h":
                export.write_lut_header(path, scene.mu, scene.gamma, levels)
            else:
                self.show_error(f"table export must end in .csv or .h, got {path.name}")
                return False
        except (OSError, ValueError) as exc:  # ValueError: a path refused before writing
            self.show_error(f"could not write {path}: {exc}")
            return False
        self.statusBar().showMessage(f"exported correction table to {path}", 5000)
        return True

    def _on_export_curves(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, "Export activation curves", "curves.csv", "CSV (*.csv);;PNG (*.png);;SVG (*.svg)"
        )
        if path:
            self.export_curves(path)

    def _on_export_lut(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, "Export correction table", "tactile_lut.h", "C header (*.h);;CSV (*.csv)"
        )
        if path:
            self.export_lut(path)

    def _on_profile_requested(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self, "Device profile", "", "Profiles (*.json)"
        )
        if path:
            try:
                self.device.set_profile(load_profile(path))
            except ProfileError as exc:
                self.show_error(str(exc))

    # --- draw mode and blind A/B -----------------------------------------------------------

    def set_draw_mode(self, on: bool) -> None:
        """Drag on the heatmap to move a free point (CT and AS only)."""
        on = bool(on)
        if on == self.heatmap.drawing:
            return
        if on:
            self._draw_backup = self.state.scene
            changes = {"pause_s": 0.0, "playing": False}
            if METHODS[self.state.scene.method].needs_shape:
                changes["method"] = "AS"
                self.statusBar().showMessage(f"draw mode uses AS: {DRAW_HELP}", 10_000)
            centre = (self.heatmap.cols / 2, self.heatmap.rows / 2)
            self.state.update(shape=tc.Line(centre, centre), **changes)
        else:
            backup = self._draw_backup
            if backup is not None:
                self.state.update(
                    shape=backup.shape, pause_s=backup.pause_s, playing=backup.playing
                )
        self.heatmap.set_drawing(on)
        self.controls.set_draw_mode(on)

    def _on_heatmap_point_drawn(self, x: float, y: float) -> None:
        x = min(max(x, 0.0), float(self.heatmap.cols))
        y = min(max(y, 0.0), float(self.heatmap.rows))
        self.state.update(shape=tc.Line((x, y), (x, y)), playing=True)

    def _on_heatmap_draw_released(self) -> None:
        self.state.update(playing=False)

    def _on_experiments_running_changed(self, running: bool) -> None:
        """A run hides everything that shows the stimulus (participants see the screen). A
        calibration run measures raw drive, so a calibrated profile is set aside meanwhile."""
        runner = self.experiments.runner
        if running and runner is not None and runner.experiment == "calibration":
            if self.device.profile.calibrated:
                self._profile_before_calibration = self.device.profile
                self.device.set_profile(self.device.profile.without_calibration())
        elif not running and getattr(self, "_profile_before_calibration", None) is not None:
            self.device.set_profile(self._profile_before_calibration)
            self._profile_before_calibration = None
        self.hidden_label.setText(HIDDEN_EXPERIMENT if running else HIDDEN_BLIND)
        self.tune_stack.setCurrentIndex(1 if running or self.blind.active else 0)
        self.tabs.setTabEnabled(0, not running)
        self.tabs.setTabEnabled(1, not running)
        self.tabs.setTabEnabled(2, not running)
        # The controls show the stimulus (a line's ends give its direction away): hide them.
        self.controls_dock.setVisible(not running)
        self.device_panel.status_label.setVisible(not running)

    def save_calibrated_profile(self, path) -> bool:
        """Save the device profile with the last calibration run's offsets and gains, and use
        it."""
        calibration = self.experiments.last_calibration
        if calibration is None:
            self.show_error("no calibration has finished yet")
            return False
        try:
            profile = self.device.profile.with_calibration(*calibration)
            profile.save(path)
        except (ValueError, OSError) as exc:
            self.show_error(f"could not save the calibrated profile: {exc}")
            return False
        self.device.set_profile(load_profile(path))
        self.statusBar().showMessage(f"calibrated profile saved to {path} and in use", 10_000)
        return True

    def _on_blind_changed(self, blind: bool) -> None:
        self.tune_stack.setCurrentIndex(1 if blind else 0)
        self.tabs.setTabEnabled(1, not blind)
        self.controls.set_method_hidden(blind)
        self.device_panel.status_label.setVisible(not blind)

    # --- views -------------------------------------------------------------------------------

    def _on_state_scene_changed_deferred(self, _scene) -> None:
        if not self._views_timer.isActive():
            self._views_timer.start()

    def _on_state_scene_changed(self, scene) -> None:
        profile = self.device.profile
        self.correction.set_params(scene.mu, scene.gamma, profile.levels, profile.response)
        if scene.shape is None:
            return
        curves = activation_curves(
            scene.shape,
            scene.method,
            duration_s=scene.duration_s,
            direction=scene.direction,
            mu=scene.mu,
            gamma=scene.gamma,
            samples=400,
        )
        self._curves = curves
        colors = cell_colors(curves.cells)
        self.curves.set_curves(curves, colors, scene.duration_s + scene.pause_s)
        self.heatmap.set_cell_frames(colors)
        self.heatmap.set_outline(None if self.heatmap.drawing else scene.shape.outline())
        if not self.blind.active:
            self.curves.plotItem.setTitle(f"{scene.method} activation: solid corrected, dashed raw")

    def _on_device_connection_changed(self, description: str) -> None:
        self.statusBar().showMessage(f"streaming to {description}", 5000)
        self.controls.set_felt_available(self.device.profile.response is not None)

    def _trace(self, scene):
        cached_scene, trace = self._trace_cache
        if cached_scene is not scene:
            trace = scene.trace() if scene.shape is not None else None
            self._trace_cache = (scene, trace)
        return trace

    def _on_display_timer_timeout(self) -> None:
        now = time.perf_counter()
        self._display_times.append(now)
        if len(self._display_times) > 4096:
            del self._display_times[:2048]
        scene = self.state.scene
        _, trace_time = self.device.streamer.last_frame
        trace = self._trace(scene)
        t = phase = None
        if trace is not None and trace_time is not None and scene.playing:
            t = trace.parameter1(trace_time)
            phase = math.fmod(trace_time, trace.period_s) if trace.repeat else trace_time
        mode = self.state.view_mode
        grid = self.device.profile.grid
        labels = None
        if mode in ("raw", "corrected"):
            values = np.zeros(grid.size)
            if t is not None:
                sample1 = METHODS[scene.method].sample1
                for i, v in point_entries(scene.shape, sample1, t, grid.cols, grid.rows):
                    values[i] = v
                if mode == "corrected":
                    values = tc.correct(values, scene.mu, scene.gamma, gain=scene.gain)
            values = values.reshape(grid.shape)
            if self.state.show_levels:
                labels = np.char.mod("%.2f", values)
        else:
            values = self.device.sent()
            if mode == "felt":
                felt = self.device.felt()
                values = felt if felt is not None else values
                if self.state.show_levels:
                    labels = np.char.mod("%.2f", values)
            elif self.state.show_levels:
                labels = self.device.sent_levels()
        if not self.blind.active:
            self.heatmap.set_frame(values, labels)
            point = None if t is None or self.heatmap.drawing else scene.shape.point(t)
            if self.heatmap.drawing and scene.playing and scene.shape is not None:
                point = scene.shape.point(0.0)
            self.heatmap.set_point(point)
            self.curves.set_cursor(phase)
            if self.tabs.currentWidget() is self.compare:
                self.compare.tick(scene, t, phase)

    def display_rate(self) -> tuple[float, float]:
        """Achieved display refresh rate (Hz) and p99 interval (ms) over the last second."""
        times = np.array(self._display_times)
        times = times[times > times[-1] - 1.0] if len(times) else times
        if len(times) < 3:
            return 0.0, 0.0
        intervals = np.diff(times)
        return 1.0 / intervals.mean(), float(np.percentile(intervals, 99) * 1e3)

    # --- settings ----------------------------------------------------------------------------

    def _restored_scene(self):
        text = self.settings.value("scene")
        if not text:
            return None
        try:
            preset = preset_from_dict(json.loads(str(text)), source="last session")
        except (ValueError, TypeError):
            return None  # a damaged setting: start from the default
        self.preset_name, self.preset_notes = preset.name, preset.notes
        return preset.scene

    def _restore_layout(self) -> None:
        geometry = self.settings.value("geometry")
        if geometry is not None:
            self.restoreGeometry(geometry)
        window_state = self.settings.value("windowState")
        if window_state is not None:
            self.restoreState(window_state)
        mode = self.settings.value("view_mode")
        if mode:
            self.state.set_view_mode(str(mode))

    def save_settings(self) -> None:
        """Remember the scene and the window layout for the next start. During a run the
        tuning scene saved when it started is remembered, never a trial's."""
        scene = self.experiments.saved_scene or self.state.scene
        preset = Preset(scene, self.preset_name, self.preset_notes, self.device.profile.name)
        self.settings.setValue("scene", json.dumps(preset.to_dict()))
        self.settings.setValue("geometry", self.saveGeometry())
        self.settings.setValue("windowState", self.saveState())
        self.settings.setValue("view_mode", self.state.view_mode)
        self.settings.sync()

    def closeEvent(self, event) -> None:  # Qt override
        self.display_timer.stop()
        self.device.shutdown()  # all off first
        self.experiments.stop()  # a run: its file closed, the participant released
        self.experiments.participant_window.hide()
        try:
            self.save_settings()
        finally:
            QtWidgets.QApplication.instance().removeEventFilter(self._key_filter)
            super().closeEvent(event)
