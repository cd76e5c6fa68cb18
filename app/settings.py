"""What the tuner remembers between sessions (QSettings): the scene (and the ``.tact`` file of a
pattern it played), the pattern editor's pattern, the window's layout, the heatmap's view, the
curves' lanes, the Compare and Blind A/B method sets, the results folder, the Lab Streaming
Layer setting and the OSC server's address (never whether it was serving: another program
drives the array only when asked in this session). ``--no-restore`` ignores them; a run never
writes its trial scenes here."""

from __future__ import annotations

import json
from pathlib import Path

from PySide6 import QtGui

from tactile_core.files.pattern import is_example
from tactile_core.files.presets import (
    Preset,
    PresetError,
    builtin_presets,
    load_preset,
    preset_from_dict,
)

from .state import DEFAULT_SCENE
from .timeline.editor import restore_session as restore_editor
from .timeline.editor import resume_session as resume_editor
from .timeline.editor import save_session as save_editor
from .titles import same_tuning

START_PRESET = "exp1-line"
"""The built-in preset the tuner starts from without a last session (or with ``--no-restore``)."""


def start_preset() -> Preset:
    """The built-in Experiment 1 line, with its name and notes (the scene alone if the bundled
    file cannot be read)."""
    try:
        return load_preset(builtin_presets()[START_PRESET])
    except (KeyError, PresetError):
        return Preset(DEFAULT_SCENE, "Experiment 1 line")


def restored_preset(settings):
    """The last session's scene as a preset, or None (none saved, or damaged). A session that
    ended on a ``.tact`` pattern (a scene without a shape) comes back on the default shape with
    its tuning (method, mu, gamma, timing, frames); :func:`reopen_pattern` plays the pattern
    again."""
    text = settings.value("scene")
    if not text:
        return None
    try:
        data = json.loads(str(text))
        if isinstance(data, dict) and "shape" in data and data["shape"] is None:
            data["shape"] = DEFAULT_SCENE.shape.to_dict()  # as an older tuner saved a pattern
        return preset_from_dict(data, source="last session")
    except (ValueError, TypeError):
        return None  # a damaged setting: start from the default


def was_modified(settings) -> bool:
    """Whether the last session's scene differed from the preset it came from (its title had
    a star): the next start keeps the star, though it no longer knows that preset."""
    return _flag(settings, "modified")


def restored_profile(saved):
    """The device profile the last session ended on (``saved``, from :func:`restored_preset`),
    if it is still a known profile's name; else None (the default then)."""
    from tactile_core.device.profile import ProfileError, find_profile, profile_names

    name = getattr(saved, "device_profile", None)
    if not isinstance(name, str) or name not in profile_names():
        return None
    try:
        return find_profile(name)
    except ProfileError:
        return None  # its file is gone or damaged since


def reopen_pattern(window) -> None:
    """The last session played a ``.tact`` pattern or a pattern file: open it again, on the
    restored tuning; if the file is gone (or was never known), say so in the status bar (the
    tuning stays, on the default shape)."""
    settings = window.settings
    try:
        last = json.loads(str(settings.value("tact_pattern", "") or "null"))
        path, position = Path(last.get("path", "")), last.get("position")
    except (ValueError, TypeError, AttributeError):
        last = None  # none (or damaged)
    try:
        shapeless = json.loads(str(settings.value("scene", ""))).get("shape", 0) is None
    except (ValueError, TypeError, AttributeError):
        shapeless = False
    if last is None and not shapeless:
        return  # the last session played a shape
    kept = (f"{window.files.preset_name} with the last session's tuning (method, mu, gamma, "
            "timing)")  # fmt: skip
    if last is not None and last.get("kind") == "editor":  # the pattern editor's
        name = window.timeline.model.pattern.name or "untitled"
        said = (f"the last session's pattern again: {name}, from the pattern editor"
                if resume_editor(window.timeline, settings) else f"the pattern editor's {name} "
                f"does not play here: {kept}")  # fmt: skip
    elif last is not None and last.get("kind") == "pattern":  # a pattern file
        opened = path.is_file() and window.files.open_pattern_file(path)
        shown = f"the example {path.name}" if is_example(path) else path  # not a package path
        said = (f"the last session's pattern again: {shown}" if opened else
                f"the last session's pattern {path} no longer opens: {kept}")  # fmt: skip
    elif last is None:
        said = f"the last session's .tact pattern was not saved: {kept}"
    elif not path.is_file():
        said = f"the last session's .tact file {path} is gone: {kept}"
    elif window.files.import_tact_file(path, position, last.get("scale"), last.get("rotation")):
        said = f"the last session's pattern again: {position or 'every position'} of {path}"
    else:
        said = f"the last session's .tact file {path} no longer opens: {kept}"
    window.statusBar().showMessage(said, 20_000)


def restore_window(window) -> None:
    """Put back the last session's layout and choices on ``window`` (a ``MainWindow``)."""
    settings = window.settings
    geometry = settings.value("geometry")
    if geometry is not None:
        window.restoreGeometry(geometry)
    window_state = settings.value("windowState")
    if window_state is not None:
        window.restoreState(window_state)
    mode = settings.value("view_mode")
    if mode and (mode != "predicted" or window.state.layout.is_grid):  # grids only
        window.state.set_view_mode(str(mode))
    lanes = str(settings.value("lanes", "false")).lower() == "true"
    window.tune.lanes_check.setChecked(lanes)
    for chooser, key in ((window.compare.chooser, "compare_methods"),
                         (window.blind.chooser, "blind_methods")):  # fmt: skip
        methods = str(settings.value(key, "")).split()
        if any(chooser.check(m) for m in methods):
            continue  # for a grid, and this layout is not one: its own set, as its note says
        if methods and methods != chooser.methods and not chooser.apply(methods):
            chooser.refuse("")  # a method gone since (a plug-in): the default, silently
    said = restore_editor(window.timeline, settings)
    if said:
        window.statusBar().showMessage(said, 10_000)
    folder = settings.value("results_folder")
    if folder:
        window.experiments.setup.folder_edit.setText(str(folder))
    restore_serve(settings, window.serve)


def _flag(settings, key: str) -> bool:
    return str(settings.value(key, "false")).lower() == "true"


def restore_serve(settings, live) -> None:
    """The OSC server's host and port and the LSL setting (opening the outlets if it was on)."""
    host = str(settings.value("osc_host", "") or "").strip()
    if host:
        live.host = host
    try:
        live.port = min(max(int(settings.value("osc_port", live.port)), 0), 65535)
    except (TypeError, ValueError):
        pass  # a damaged setting: the default port
    if _flag(settings, "lsl_markers"):
        live.set_lsl(True, _flag(settings, "lsl_levels"))
    else:
        live.lsl_levels = _flag(settings, "lsl_levels")
        live.changed.emit()


def save_window(window) -> None:
    """Remember ``window``'s scene, layout and choices for the next start. During a run the
    tuning scene saved when it started is remembered, never a trial's."""
    settings = window.settings
    scene = window.experiments.saved_scene or window.state.scene
    files = window.files
    pattern = files.pattern_file(scene.source) if scene.shape is None else None
    if pattern is None and window.timeline.owns_scene() and scene is window.state.scene:
        pattern = {"kind": "editor"}  # the editor's pattern (kept below), and how it played
    if scene.shape is None:  # a pattern (or points another program drove): a preset holds a
        scene = scene.replace(shape=DEFAULT_SCENE.shape, source=None)  # shape; the tuning stays
    preset = Preset(scene, files.preset_name, files.preset_notes, window.device.profile.name,
                    window.device.lead_ms)  # fmt: skip
    settings.setValue("scene", json.dumps(preset.to_dict()))
    came = files.preset_scene  # the title's star: the next start shows it again
    live = window.experiments.saved_scene or window.state.scene
    settings.setValue("modified", files.modified_at_start
                      or (came is not None and not same_tuning(live, came)))  # fmt: skip
    settings.setValue("tact_pattern", json.dumps(pattern) if pattern else "")
    settings.setValue("geometry", window.saveGeometry())
    settings.setValue("windowState", window.saveState())
    settings.setValue("view_mode", window.state.view_mode)
    settings.setValue("lanes", window.tune.lanes_check.isChecked())
    settings.setValue("compare_methods", " ".join(window.compare.chosen_methods))
    settings.setValue("blind_methods", " ".join(window.blind.chosen_methods))
    settings.setValue("results_folder", window.experiments.setup.folder_edit.text())
    save_editor(window.timeline, settings)
    live = window.serve
    settings.setValue("osc_host", live.host)
    settings.setValue("osc_port", live.port)
    settings.setValue("lsl_markers", live.lsl_markers)
    settings.setValue("lsl_levels", live.lsl_levels)
    settings.sync()


TITLE_GUESS_PX = 32
"""A title bar's height, for a window the window manager has not framed yet (before it is
shown its frame is unknown: Qt reports the window's own rectangle as its frame)."""


def fit_window(window, keep_size: bool = False) -> None:
    """Keep the window on its screen and no larger than it, its frame included (a saved size
    from a larger screen, or the default, is shrunk to fit); ``keep_size``: a size asked for
    (``--size``) is kept, only the position is fitted. A window that fits is not moved: Qt
    places a window by its frame but, before the window manager has framed it, reports the
    window's own place, so moving it there put it a title bar lower at every start.

    Parameters
    ----------
    window : QMainWindow
    keep_size : bool
    """
    screen = window.screen() or QtGui.QGuiApplication.primaryScreen()
    if screen is None:
        return
    area = screen.availableGeometry()
    frame, inner = window.frameGeometry(), window.geometry()
    if frame != inner:  # framed: its margins as they are
        left, top = inner.x() - frame.x(), inner.y() - frame.y()
        right, bottom = frame.right() - inner.right(), frame.bottom() - inner.bottom()
    else:  # not framed yet: room for a title bar
        left, top, right, bottom = 0, TITLE_GUESS_PX, 0, 0
    w = min(inner.width(), area.width() - left - right)
    h = min(inner.height(), area.height() - top - bottom)
    if (w, h) != (inner.width(), inner.height()) and not keep_size:
        window.resize(w, h)
    w, h = window.width(), window.height()
    # within the area; one larger than it (a size asked for) from its top left corner
    x = max(min(inner.x(), area.right() - right - w + 1), area.left() + left)
    y = max(min(inner.y(), area.bottom() - bottom - h + 1), area.top() + top)
    if (x, y) != (inner.x(), inner.y()):
        window.move(x - left, y - top)  # (Qt moves a window by its frame)
