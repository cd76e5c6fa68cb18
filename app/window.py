"""The tuner's main window."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

import tactile_core as tc
from tactile_core.device.profile import ProfileError, find_profile, load_profile
from tactile_core.files import export
from tactile_core.files.presets import (
    Preset,
    PresetError,
    builtin_presets,
    load_preset,
    preset_from_dict,
    save_preset,
)
from tactile_core.rendering.curves import activation_curves
from tactile_core.rendering.methods import get_method
from tactile_core.rendering.percept import felt_magnitude, predict
from tactile_core.rendering.rasterize import point_entries

from . import dialogs
from .compare import BlindPanel, CompareView
from .device import DeviceController
from .experiments import ExperimentsPanel, TuningResultDialog
from .panels import DRAW_HELP, ControlsPanel, DevicePanel
from .state import TunerState
from .views import CorrectionView, CurvesView, ElidedLabel, HeatmapView, cell_colors

DISPLAY_HZ = 60
HIDDEN_BLIND = (
    "Blind A/B in progress: the display is hidden so that it does not give the method away. "
    "Reveal in the Blind A/B tab to see it again."
)
HIDDEN_EXPERIMENT = (
    "An experiment is running: the display is hidden so that it does not give the stimulus away."
)


def _same_tuning(a, b) -> bool:
    """Whether two scenes are the same tuning (playing state and restarts aside)."""
    return a.replace(playing=True, epoch=0) == b.replace(playing=True, epoch=0)


def is_text_input(widget) -> bool:
    """True for a widget that takes typed text (a field, a spin box, an editable drop-down)."""
    if isinstance(
        widget,
        (QtWidgets.QLineEdit, QtWidgets.QAbstractSpinBox, QtWidgets.QTextEdit,
         QtWidgets.QPlainTextEdit),
    ):  # fmt: skip
        return True
    return isinstance(widget, QtWidgets.QComboBox) and widget.isEditable()


class _KeyFilter(QtCore.QObject):
    """Application-wide keys.

    - **Esc** turns everything off from anywhere in the window, even with the cursor in a text
      box; but with a menu, a drop-down or a dialog open, Esc is theirs (it closes them).
    - **Space** and **1-8** (play/pause, methods) act unless a text input has the focus, so
      typing ``COM2`` or ``0.35`` never switches the method. **Enter** in a field commits its
      value and gives the keys back to the window.
    - During an experiment the run owns the keyboard.
    """

    def __init__(self, window):
        super().__init__(window)
        self.window = window

    def eventFilter(self, obj, event):
        if event.type() != QtCore.QEvent.Type.KeyPress or event.isAutoRepeat():
            return False
        app = QtWidgets.QApplication
        if app.activePopupWidget() is not None or app.activeModalWidget() is not None:
            return False  # a menu, a drop-down list or a dialog: Esc closes it, nothing more
        active = app.activeWindow()
        ours = (self.window, self.window.experiments.participant_window)
        if active is not None and active not in ours:
            return False  # another window: its keys are its own
        if not isinstance(obj, QtWidgets.QWidget) or obj.window() not in ours:
            return False  # the event on its way to a widget's parent: act on it once
        key = event.key()
        if key == QtCore.Qt.Key.Key_Escape:
            self.window.all_off()
            if self.window.experiments.running:
                self.window.experiments.pause()
            return False
        if self.window.experiments.running:
            # A run owns the keyboard (its rating box takes digits and Enter itself).
            return self.window.experiments.handle_key(event)
        focus = app.focusWidget()
        if is_text_input(focus):
            if key in (QtCore.Qt.Key.Key_Return, QtCore.Qt.Key.Key_Enter):
                # Let the field commit its value first, then give the keys back.
                QtCore.QTimer.singleShot(0, self.window.return_focus)
            return False
        if key == QtCore.Qt.Key.Key_Space:
            self.window.toggle_play()
            return True
        if QtCore.Qt.Key.Key_1 <= key <= QtCore.Qt.Key.Key_8:
            return self.window.press_number(key - QtCore.Qt.Key.Key_1 + 1)
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
        self._pulse = None  # (scene before, held) while a tactor is pulsed from the heatmap
        self._scrub_s = None  # trace time the cursor was dragged to (while paused)
        self._preset_scene = (
            preset.scene if preset is not None else getattr(self, "_restored_preset_scene", None)
        )

        # Tune tab ----------------------------------------------------------------------------
        grid = self.device.profile.grid
        self.heatmap = HeatmapView(grid.cols, grid.rows, title="Array")
        self.heatmap.setObjectName("heatmap")
        self.curves = CurvesView()
        self.lanes_check = QtWidgets.QCheckBox("one lane per tactor")
        self.lanes_check.setObjectName("lanes")
        self.lanes_check.setToolTip(
            "Activation curves in lanes, one row per tactor labelled (col,row): the sequence of a "
            "bi-level method, whose curves all sit at 1, can be read (the paper's Figure 3)"
        )
        self.lanes_check.toggled.connect(self.curves.set_lanes)
        curves_box = QtWidgets.QWidget()
        box = QtWidgets.QVBoxLayout(curves_box)
        box.setContentsMargins(0, 0, 0, 0)
        bar = QtWidgets.QHBoxLayout()
        hint = ElidedLabel("drag the cursor to scrub; hover for values; dashed: raw")
        hint.setObjectName("curves_hint")
        hint.setToolTip(
            "Solid curves are corrected, dashed ones raw. Pause, then drag the dashed cursor to "
            "show any instant of the trace on the heatmap; hover a curve or a heatmap cell to "
            "read its tactor and value"
        )
        hint.setAlignment(QtCore.Qt.AlignmentFlag.AlignRight | QtCore.Qt.AlignmentFlag.AlignVCenter)
        bar.addWidget(self.lanes_check)
        bar.addWidget(hint, 1)
        box.addLayout(bar)
        box.addWidget(self.curves, 1)
        self.correction = CorrectionView()
        right = QtWidgets.QSplitter(QtCore.Qt.Orientation.Vertical)
        right.addWidget(curves_box)
        right.addWidget(self.correction)
        right.setSizes([600, 360])
        tune = QtWidgets.QSplitter(QtCore.Qt.Orientation.Horizontal)
        tune.addWidget(self.heatmap)
        tune.addWidget(right)
        tune.setStretchFactor(0, 0)
        tune.setStretchFactor(1, 1)
        self.tune_split = tune
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

        # Docks -------------------------------------------------------------------------------
        self.controls = ControlsPanel(self.state)
        scroll = QtWidgets.QScrollArea()
        scroll.setWidget(self.controls)
        scroll.setWidgetResizable(True)
        # Never sideways: the controls are laid out for the dock's width and scroll vertically.
        scroll.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        scroll.setMinimumWidth(self.controls.minimumSizeHint().width() + 18)
        self.controls_scroll = scroll
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
        self.device_dock = dock
        self._pulse_timer = QtCore.QTimer(self)
        self._pulse_timer.setSingleShot(True)
        self._pulse_timer.timeout.connect(lambda: self._end_pulse(restore=True))

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
        # The predicted view has its own curves and path: switching the mode redraws them.
        self.state.view_mode_changed.connect(
            lambda _: self._on_state_scene_changed_deferred(self.state.scene)
        )
        self.state.show_levels_changed.connect(self.heatmap.set_show_values)
        self.state.error_raised.connect(self.show_error)
        self.device.error_raised.connect(self.show_error)
        self.device.connection_changed.connect(self._on_device_connection_changed)
        self.controls.all_off_requested.connect(self.all_off)
        self.controls.draw_mode_toggled.connect(self.set_draw_mode)
        self.device_panel.profile_requested.connect(self._on_profile_requested)
        self.heatmap.point_drawn.connect(self._on_heatmap_point_drawn)
        self.heatmap.draw_released.connect(self._on_heatmap_draw_released)
        self.heatmap.cell_hovered.connect(self.curves.highlight)
        self.curves.curve_hovered.connect(self.heatmap.highlight)
        self.heatmap.cell_clicked.connect(self.pulse_cell)
        self.curves.scrubbed.connect(self._on_curves_scrubbed)
        self.device.status_changed.connect(self._on_device_status_changed)
        self.state.playing_changed.connect(self._on_state_playing_changed)
        self.state.scene_changed.connect(lambda _: self._update_title())
        self.blind.blind_changed.connect(self._on_blind_changed)
        self.experiments.running_changed.connect(self._on_experiments_running_changed)
        self.device.status_changed.connect(self.experiments.on_device_status)
        self.experiments.error_raised.connect(self.show_error)
        self.experiments.correction_measured.connect(self._on_correction_measured)
        self.experiments.save_profile_requested = self.save_calibrated_profile
        self._key_filter = _KeyFilter(self)
        QtWidgets.QApplication.instance().installEventFilter(self._key_filter)

        self._on_state_scene_changed(self.state.scene)
        self._update_title()
        screen = QtGui.QGuiApplication.primaryScreen()
        if screen is not None:  # a default that fits; a saved size replaces it below
            area = screen.availableGeometry()
            self.resize(min(1400, round(area.width() * 0.92)), min(900, round(area.height() * 0.9)))
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
        menu.addSeparator()
        menu.addAction("Tune the correction by feel...", self.start_tuning)
        self.view_menu = menu = self.menuBar().addMenu("&View")
        self._dock_actions = []
        for dock in self.findChildren(QtWidgets.QDockWidget):
            action = dock.toggleViewAction()
            action.setText(f"{dock.windowTitle()} panel")
            menu.addAction(action)
            self._dock_actions.append(action)
        lanes = menu.addAction("Activation curves in lanes")
        lanes.setCheckable(True)
        lanes.toggled.connect(self.lanes_check.setChecked)
        self.lanes_check.toggled.connect(lanes.setChecked)
        menu.addSeparator()
        menu.addAction("Reset layout", self.reset_layout)

    # --- actions -----------------------------------------------------------------------------

    def all_off(self) -> None:
        """Everything off now (Esc, the button, the menu)."""
        self._end_pulse(restore=True)
        self.device.all_off()
        self.statusBar().showMessage("all off (Space plays again)")

    def _on_state_playing_changed(self, playing: bool) -> None:
        if playing:
            self._scrub_s = None
            self.statusBar().showMessage("playing", 2000)

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
        self._fit_heatmap()

    def fit_to_screen(self) -> None:
        """Keep the window on its screen and no larger than it (a saved size from a larger
        screen, or the default, is shrunk to fit)."""
        screen = self.screen() or QtGui.QGuiApplication.primaryScreen()
        if screen is None:
            return
        area = screen.availableGeometry()
        frame = self.frameGeometry()
        w = min(self.width(), area.width() - (frame.width() - self.width()))
        h = min(self.height(), area.height() - (frame.height() - self.height()))
        if (w, h) != (self.width(), self.height()):
            self.resize(w, h)
        geometry = self.frameGeometry()
        x = min(max(geometry.x(), area.left()), area.right() - geometry.width() + 1)
        y = min(max(geometry.y(), area.top()), area.bottom() - geometry.height() + 1)
        self.move(x, y)

    def _fit_heatmap(self) -> None:
        """Give the heatmap the width at which its square cells fill its height."""
        total = sum(self.tune_split.sizes())
        if total <= 0:
            return
        want = self.heatmap.preferred_width(self.tune_split.height())
        right = self.tune_split.widget(1).minimumSizeHint().width()
        want = min(max(want, 220), round(total * 0.55), total - right)
        self.tune_split.setSizes([want, total - want])

    def resizeEvent(self, event) -> None:  # Qt override
        super().resizeEvent(event)
        QtCore.QTimer.singleShot(0, self._fit_heatmap)

    def _update_title(self) -> None:
        """``tactile-tuner - preset[*] - method, mu, gamma``: current, with a star once the
        scene differs from the preset it came from."""
        scene = self.state.scene
        modified = self._preset_scene is not None and not _same_tuning(scene, self._preset_scene)
        name = self.preset_name + (" *" if modified else "")
        self.setWindowTitle(
            f"tactile-tuner - {name} - {scene.method}, mu {scene.mu:.2f}, gamma {scene.gamma:.2f}"
        )

    def _on_device_status_changed(self, stats) -> None:
        """A lost device is obvious: a banner over the tabs and the heatmap marked."""
        lost = stats.state in ("disconnected", "failed", "refused") or (
            stats.state == "stopped" and not self.device.simulated
        )
        if lost:
            self.banner.setText(f"Device not streaming ({stats.state}): {stats.status}")
        self.banner.setVisible(lost)
        self.heatmap.set_streaming(not lost, f"not streaming: {stats.state}")

    # --- pulses and scrubbing ------------------------------------------------------------------

    def pulse_cell(self, col: int, row: int, hold: bool = False) -> None:
        """Play one tactor alone at full drive: a 0.3 s pulse, or held (Shift+click) until the
        next click, Space or Esc. The scene before it comes back afterwards."""
        if self.experiments.running or self.blind.active or self.heatmap.drawing:
            return
        held = self._pulse is not None and self._pulse[1]
        self._end_pulse(restore=True)
        if held:
            return  # a click releases a held tactor
        centre = (col + 0.5, row + 0.5)
        backup = self.state.scene
        self._pulse = (backup, hold)
        self.state.set_scene(backup.replace(
            shape=tc.Line(centre, centre), method="CT", mu=0.0, gamma=1.0, gain=1.0,
            duration_s=0.3, pause_s=0.0, repeat=hold, playing=True, epoch=backup.epoch + 1,
        ))  # fmt: skip
        what = "holding" if hold else "pulsing"
        self.statusBar().showMessage(
            f"{what} tactor ({col},{row})" + (": click again or press Esc to release" if hold
                                              else ""), 4000)  # fmt: skip
        if not hold:
            self._pulse_timer.start(400)

    def _end_pulse(self, restore: bool) -> None:
        if self._pulse is None:
            return
        backup, _ = self._pulse
        self._pulse = None
        self._pulse_timer.stop()
        if restore:
            self.state.set_scene(backup.replace(epoch=self.state.scene.epoch + 1))

    def _on_curves_scrubbed(self, time_s: float) -> None:
        """The cursor dragged: the array pauses; the views show the trace at that time."""
        if self.state.scene.playing:
            self.state.update(playing=False)
        self._scrub_s = max(0.0, float(time_s))

    def toggle_play(self) -> None:
        """Play or pause the trace (Space)."""
        if self._pulse is not None:
            self._end_pulse(restore=True)
            return
        self.state.update(playing=not self.state.scene.playing)

    def press_number(self, key: int) -> bool:
        """Number keys: the method, or in blind A/B the shuffled method behind the key; True if
        the key meant something."""
        if self.blind.mapping and not self.blind.revealed:
            if key > len(self.blind.mapping):
                return False
            self.blind.select_key(key)
            return True
        names = self.controls.method_names()
        if key > len(names):
            return False
        name = names[key - 1]
        if self.heatmap.drawing and get_method(name).needs_shape:
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

    # --- tuning the correction by feel ----------------------------------------------------------

    def start_tuning(self) -> None:
        """Guide the experimenter to the tuning procedure (the Experiments tab, set up)."""
        self.tabs.setCurrentWidget(self.experiments)
        self.experiments.prepare_tuning()

    def _on_correction_measured(self, result, preset_path) -> None:
        self.tuning_dialog = dialog = TuningResultDialog(result, preset_path, self)
        dialog.applied.connect(lambda: self.apply_correction(result.mu, result.gamma))
        dialog.save_requested.connect(lambda: self.apply_correction(result.mu, result.gamma))
        dialog.save_requested.connect(self._on_save_preset)
        dialog.setAttribute(QtCore.Qt.WidgetAttribute.WA_DeleteOnClose)
        dialog.open()

    def apply_correction(self, mu: float, gamma: float) -> None:
        """Set the tuner's mu and gamma (a measured correction)."""
        self.state.update(mu=mu, gamma=gamma)
        self.statusBar().showMessage(f"applied the measured correction: mu {mu:.3f}, "
                                     f"gamma {gamma:.3f}", 8000)  # fmt: skip

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
        self._preset_scene = preset.scene
        self._update_title()
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
        path = dialogs.open_path(self, "presets", "Open preset", ["Presets (*.json)"])
        if path:
            self.load_preset_file(path)

    def _on_save_preset(self) -> None:
        name = f"{dialogs.tuning_tag(self.state.scene)}-{dialogs.today()}.json"
        path = dialogs.save_path(self, "presets", "Save preset", name, ["Presets (*.json)"])
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
        scene = self.state.scene
        kind = type(scene.shape).__name__.lower() if scene.shape is not None else "none"
        name = f"curves-{kind}-{dialogs.tuning_tag(scene)}-{dialogs.today()}.csv"
        path = dialogs.save_path(self, "exports", "Export activation curves", name,
                                 ["CSV (*.csv)", "PNG (*.png)", "SVG (*.svg)"])  # fmt: skip
        if path:
            self.export_curves(path)

    def _on_export_lut(self) -> None:
        scene = self.state.scene
        levels = self.device.profile.levels
        name = f"lut-mu{scene.mu:.2f}-gamma{scene.gamma:.2f}-{levels}levels.h"
        path = dialogs.save_path(self, "exports", "Export correction table", name,
                                 ["C header (*.h)", "CSV (*.csv)"])  # fmt: skip
        if path:
            self.export_lut(path)

    def _on_profile_requested(self) -> None:
        path = dialogs.open_path(self, "profiles", "Device profile", ["Profiles (*.json)"])
        if path:
            try:
                self.device.set_profile(load_profile(path))
            except ProfileError as exc:
                self.show_error(str(exc))

    # --- draw mode and blind A/B -----------------------------------------------------------

    def set_draw_mode(self, on: bool) -> None:
        """Drag on the heatmap to move a free point (CT and AS only). Leaving draw mode puts back
        the whole scene it changed (shape, method, pause, playing)."""
        on = bool(on)
        if on == self.heatmap.drawing:
            return
        if on:
            self._end_pulse(restore=True)
            self._draw_backup = self.state.scene
            changes = {"pause_s": 0.0, "playing": False}
            if get_method(self.state.scene.method).needs_shape:
                changes["method"] = "AS"
                self.statusBar().showMessage(f"draw mode uses AS: {DRAW_HELP}", 10_000)
            centre = (self.heatmap.cols / 2, self.heatmap.rows / 2)
            self.heatmap.set_drawing(True)
            self.state.update(shape=tc.Line(centre, centre), **changes)
            self.curves.clear_curves()  # a free point has no trace to plot
        else:
            self.heatmap.set_drawing(False)
            backup, self._draw_backup = self._draw_backup, None
            if backup is not None:
                self.state.set_scene(backup.replace(epoch=self.state.scene.epoch + 1))
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
        # Tuning measures thresholds on raw drive, as the calibration does.
        if running and runner is not None and runner.experiment in ("calibration", "correction"):
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
        self.correction.set_params(scene.mu, scene.gamma, profile.levels, profile.response,
                                   profile.drive_for if scene.felt_domain else None)  # fmt: skip
        if scene.shape is None:
            return
        if self.heatmap.drawing or self._pulse is not None:
            # A free point or a pulsed tactor has no trace worth plotting: no curves, no frames
            self.curves.clear_curves()
            self.heatmap.set_cell_frames({})
            self.heatmap.set_outline(None)
            return
        if self.state.view_mode == "predicted":
            self._show_predicted(scene)
            return
        self.heatmap.set_path(None)
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
            self.curves.plotItem.setTitle(
                f"{scene.method} activation, mu {scene.mu:.2f}, gamma {scene.gamma:.2f}"
            )

    def _show_predicted(self, scene) -> None:
        """The predicted view: the felt centroid's path on the heatmap, the felt intensity over
        time in the curves view, the ripple and centroid error in its title."""
        try:
            percept = predict(scene.shape, scene.method, scene.mu, scene.gamma,
                              grid=self.device.profile.grid, samples=400)  # fmt: skip
        except ValueError as exc:
            self.show_error(f"no prediction: {exc}")
            return
        times = percept.t * scene.duration_s
        if scene.direction == "reverse":
            times = times[::-1]
        self._curves = None
        self.heatmap.set_cell_frames({})
        self.heatmap.set_outline(scene.shape.outline())
        self.heatmap.set_path(percept.centroid)
        self.curves.set_series(times, percept.felt, scene.duration_s + scene.pause_s,
                               "felt intensity M")  # fmt: skip
        if not self.blind.active:
            self.curves.plotItem.setTitle(
                f"{scene.method}: ripple {percept.ripple:.2f}, off {percept.mean_error_mm:.1f} "
                f"mm (max {percept.max_error_mm:.1f})"
            )

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
        elif trace is not None and self._scrub_s is not None and not scene.playing:
            phase = min(self._scrub_s, trace.period_s)  # scrubbing: where the cursor was left
            t = trace.parameter1(phase)
        mode = self.state.view_mode
        if self._scrub_s is not None and mode in ("sent", "felt") and not scene.playing:
            mode = "corrected"  # the array is paused while scrubbing: show what it would get
        grid = self.device.profile.grid
        labels = None
        if mode in ("raw", "corrected", "predicted"):
            values = np.zeros(grid.size)
            if t is not None:
                sample1 = get_method(scene.method).sample1
                try:
                    entries = point_entries(scene.shape, sample1, t, grid.cols, grid.rows)
                except ValueError as exc:  # only a plug-in raises here (it is checked first)
                    self._plugin_failed(scene, exc)
                    return
                for i, v in entries:
                    values[i] = v
                if mode != "raw":
                    values = tc.correct(values, scene.mu, scene.gamma, gain=scene.gain)
                if mode == "predicted":
                    values = felt_magnitude(values, scene.mu, 1.0 / (2.0 * scene.gamma))
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

    def _plugin_failed(self, scene, exc) -> None:
        """A plug-in method failed while playing: say so, list it as unavailable, and go back
        to AS with the array paused (all off)."""
        from tactile_core.rendering.methods import mark_unavailable

        mark_unavailable(scene.method, str(exc))
        self.show_error(f"{exc}; the plug-in is listed as unavailable, back to AS (paused)")
        self.state.update(method="AS", playing=False)
        self.state.plugins_changed.emit()

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
        self._restored_preset_scene = preset.scene
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
        self.lanes_check.setChecked(str(self.settings.value("lanes", "false")).lower() == "true")

    def save_settings(self) -> None:
        """Remember the scene and the window layout for the next start. During a run the
        tuning scene saved when it started is remembered, never a trial's."""
        scene = self.experiments.saved_scene or self.state.scene
        preset = Preset(scene, self.preset_name, self.preset_notes, self.device.profile.name)
        self.settings.setValue("scene", json.dumps(preset.to_dict()))
        self.settings.setValue("geometry", self.saveGeometry())
        self.settings.setValue("windowState", self.saveState())
        self.settings.setValue("view_mode", self.state.view_mode)
        self.settings.setValue("lanes", self.lanes_check.isChecked())
        self.settings.sync()

    def closeEvent(self, event) -> None:  # Qt override
        self.display_timer.stop()
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
