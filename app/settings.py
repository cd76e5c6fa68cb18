"""What the tuner remembers between sessions (QSettings): the scene, the window's layout, the
heatmap's view, the curves' lanes, the Compare and Blind A/B method sets, the results folder,
the Lab Streaming Layer setting and the OSC server's address (never whether it was serving: another
program drives the array only when asked in this session). ``--no-restore`` ignores them; a run
never writes its trial scenes here."""

from __future__ import annotations

import json

from tactile_core.files.presets import Preset, preset_from_dict


def restored_preset(settings):
    """The last session's scene as a preset, or None (none saved, or damaged)."""
    text = settings.value("scene")
    if not text:
        return None
    try:
        return preset_from_dict(json.loads(str(text)), source="last session")
    except (ValueError, TypeError):
        return None  # a damaged setting: start from the default


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
    folder = settings.value("results_folder")
    if folder:
        window.experiments.setup.folder_edit.setText(str(folder))
    restore_live(settings, window.serve)


def _flag(settings, key: str) -> bool:
    return str(settings.value(key, "false")).lower() == "true"


def restore_live(settings, live) -> None:
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
    preset = Preset(scene, files.preset_name, files.preset_notes, window.device.profile.name,
                    window.device.lead_ms)  # fmt: skip
    settings.setValue("scene", json.dumps(preset.to_dict()))
    settings.setValue("geometry", window.saveGeometry())
    settings.setValue("windowState", window.saveState())
    settings.setValue("view_mode", window.state.view_mode)
    settings.setValue("lanes", window.tune.lanes_check.isChecked())
    settings.setValue("compare_methods", " ".join(window.compare.chosen_methods))
    settings.setValue("blind_methods", " ".join(window.blind.chosen_methods))
    settings.setValue("results_folder", window.experiments.setup.folder_edit.text())
    live = window.serve
    settings.setValue("osc_host", live.host)
    settings.setValue("osc_port", live.port)
    settings.setValue("lsl_markers", live.lsl_markers)
    settings.setValue("lsl_levels", live.lsl_levels)
    settings.sync()
