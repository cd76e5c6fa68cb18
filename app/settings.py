"""What the tuner remembers between sessions (QSettings): the scene, the window's layout, the
heatmap's view, the curves' lanes, the Compare and Blind A/B method sets and the results folder.
``--no-restore`` ignores them; a run never writes its trial scenes here."""

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
    if mode and (mode != "predicted" or window.state.layout.grid is not None):  # grids only
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
    settings.sync()
