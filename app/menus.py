"""The tuner's menu bar: File, Array, View and Help."""

from __future__ import annotations

from PySide6 import QtGui, QtWidgets

from tactile_core.device.profile import profile_names
from tactile_core.files.pattern import example_patterns
from tactile_core.files.presets import builtin_presets

from . import help as help_dialogs
from .measure import show_measure_dialog


def build_menus(window, files, *, toggle_play, all_off, restart, start_tuning, reset_layout,
                lanes_check) -> tuple[QtWidgets.QMenu, list]:  # fmt: skip
    """Fill ``window``'s menu bar; returns the View menu and the File actions that would show
    or change the method (disabled while Blind A/B hides it).

    Parameters
    ----------
    window : QMainWindow
        Its menu bar gets the menus; its docks get a show/hide action each in the View menu.
    files : FileActions
        Presets and exports.
    toggle_play, all_off, restart, start_tuning, reset_layout : callable
        The Array and View menus' actions.
    lanes_check : QCheckBox
        The curves' lanes, mirrored by a checkable View action.
    """
    bar = window.menuBar()
    menu = bar.addMenu("&File")
    keys = QtGui.QKeySequence.StandardKey
    method_actions = [
        menu.addAction("Open preset...", files.ask_open_preset, keys.Open),
        menu.addAction("Save preset as...", files.ask_save_preset, keys.Save),
    ]
    builtins = menu.addMenu("Built-in presets")
    for stem, path in builtin_presets().items():
        builtins.addAction(stem, lambda p=path: files.load_preset_file(p))
    method_actions.append(builtins.menuAction())
    menu.addSeparator()
    method_actions.append(
        menu.addAction("Export activation curves (CSV, PNG, SVG)...", files.ask_export_curves)
    )
    menu.addAction("Export correction table (CSV, C header)...", files.ask_export_lut)
    menu.addSeparator()
    menu.addAction("Open pattern...", files.ask_open_pattern)
    examples = menu.addMenu("Example patterns")
    for stem, path in example_patterns().items():
        examples.addAction(stem, lambda p=path: files.open_pattern_file(p))
    menu.addAction("Import .tact...", files.ask_import_tact)
    menu.addAction("Export .tact...", files.ask_export_tact)
    keep = menu.addAction("Keep the drawing as the shape", files.keep_drawing)
    keep.setStatusTip(
        "In draw mode, after a drag: leave draw mode with the path drawn as the shape"
    )
    keep.setEnabled(files.can_keep_drawing)  # only in draw mode, with a drawing
    files.drawing_changed.connect(keep.setEnabled)
    menu.addSeparator()
    # Ctrl+Q on every platform (the standard key is empty on some, e.g. Windows, offscreen).
    menu.addAction("Quit", window.close, QtGui.QKeySequence("Ctrl+Q"))
    menu = bar.addMenu("&Array")
    menu.addAction("Play / pause\tSpace", toggle_play)
    menu.addAction("All off\tEsc", all_off)
    menu.addAction("Restart trace", restart)
    profiles = menu.addMenu("Device profile")
    profiles.setObjectName("profiles_menu")
    profiles.aboutToShow.connect(lambda: _fill_profiles(profiles, files))
    _fill_profiles(profiles, files)
    menu.addSeparator()
    menu.addAction("Tune the correction by feel...", start_tuning)
    menu.addAction("Measure the motors...", lambda: show_measure_dialog(window))
    view = bar.addMenu("&View")
    for dock in window.findChildren(QtWidgets.QDockWidget):
        action = dock.toggleViewAction()
        action.setText(f"{dock.windowTitle()} panel")
        view.addAction(action)
    lanes = view.addAction("Activation curves in lanes")
    lanes.setCheckable(True)
    lanes.toggled.connect(lanes_check.setChecked)
    lanes_check.toggled.connect(lanes.setChecked)
    view.addSeparator()
    view.addAction("Reset layout", reset_layout)
    menu = bar.addMenu("&Help")
    menu.addAction("Keyboard shortcuts", lambda: help_dialogs.show_shortcuts(window),
                   keys.HelpContents)  # fmt: skip
    menu.addAction("About tactile-tuner", lambda: help_dialogs.show_about(window))
    return view, method_actions


def _fill_profiles(menu: QtWidgets.QMenu, files) -> None:
    """The known device profiles by name, the one in use ticked, and one from a file."""
    menu.clear()
    current = files.device.profile.name
    for name in profile_names():
        action = menu.addAction(name, lambda n=name: files.use_profile(n))
        action.setCheckable(True)
        action.setChecked(name == current)
    menu.addSeparator()
    menu.addAction("From a file...", files.ask_open_profile)
