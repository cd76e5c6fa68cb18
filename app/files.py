"""The tuner's files: presets (open, save, built-in), exports (curves, correction table),
bHaptics ``.tact`` files (import, export, a drawing kept as the shape), patterns (open one and
play it), and device profiles (load one, save a calibrated one)."""

from __future__ import annotations

from pathlib import Path

from PySide6 import QtCore

from tactile_core.device.profile import (
    ProfileError,
    find_profile,
    load_profile,
    profile_names,
)
from tactile_core.files import export, tact
from tactile_core.files.pattern import Pattern, PatternCue, PatternError, profiles_playing
from tactile_core.files.presets import MAX_NAME_CHARS, Preset, PresetError, load_preset, save_preset
from tactile_core.files.tact import TactError, load_pattern, path_of_scene, write_tact
from tactile_core.rendering.shapes import TimedPath

from . import dialogs
from .drawing import KeepsDrawing
from .texts import count, value3
from .titles import source_kind
from .views import cell_colors


def _plays_on(names, blocked: str) -> str:
    """What a refusal adds to say where a pattern plays: the profiles and how to choose one
    (or why the profile may not change now); nothing when it plays on none."""
    if not names:
        return ""
    how = blocked or ("choose it in the device dock's profile box (or the Array menu's Device "
                      "profile), then open the pattern again")  # fmt: skip
    return f". It plays on the device profile {' or '.join(names)}: {how}"


class FileActions(QtCore.QObject, KeepsDrawing):
    """Reads and writes the tuner's files; the File menu and the device panel call it.

    It remembers which preset the scene came from (:attr:`preset_name`, :attr:`preset_notes`,
    :attr:`preset_scene`), for the window's title and the next save. Problems become
    :attr:`error_raised` messages; a file is never half-written (the core writes atomically).

    Parameters
    ----------
    state : TunerState
    device : DeviceController
        The profile in use (its name goes into presets; its levels into tables).
    parent : QWidget
        The dialogs' parent (the main window).
    """

    error_raised = QtCore.Signal(str)
    message_posted = QtCore.Signal(str, int)
    """A status line and how long to show it (ms)."""
    preset_changed = QtCore.Signal()
    """The scene's preset changed: a preset or a ``.tact`` file replaced the scene, or the
    scene was saved as a preset (its name is now :attr:`preset_name`)."""
    drawing_changed = QtCore.Signal(bool)
    """Whether there is a drawing to keep as the shape (:meth:`keep_drawing`): in draw mode,
    once a drag has drawn a path."""

    def __init__(self, state, device, parent):
        super().__init__(parent)
        self.state = state
        self.device = device
        self.preset_name = "Experiment 1 line"
        self.preset_notes = ""
        self.preset_scene = state.scene
        """The scene of the preset (or last session) the tuning came from: at first the scene
        the window starts from (the Experiment 1 line unless a preset is set), so that the
        title's "modified" star shows from the first change."""
        self.curves = lambda: None
        """The activation curves on show (the window connects the tune tab's)."""
        self.before_load = lambda: None
        """Called before a preset replaces the scene (the window leaves draw mode)."""
        self.blocked = lambda: ""
        """Why presets and curve exports are refused now ("" when they are not): they would
        name the method Blind A/B hides."""
        self.confirm = lambda title, text: dialogs.confirm(parent, title, text)
        """Asks yes or no before a file is replaced (tests answer it)."""
        self.profile_blocked = lambda: ""
        """Why the device profile may not change now ("" when it may): a blind session or a
        run depends on its layout."""
        self._imported: set[Path] = set()
        """The ``.tact`` files imported in this session (an export never overwrites one)."""
        self._pattern_file = (None, None)
        """The pattern imported last and where it came from (its file and position)."""
        self.init_drawing()

    def _refused(self) -> bool:
        reason = self.blocked()
        if reason:
            self.error_raised.emit(reason)
        return bool(reason)

    @property
    def preset_scene(self):
        """The scene of the preset (pattern, ``.tact`` file) the scene came from: the title
        has a star while the scene differs from it."""
        return self._preset_scene

    @preset_scene.setter
    def preset_scene(self, scene) -> None:
        self._preset_scene = scene
        self.modified_at_start = False  # a new origin: the last session's star is over

    def set_preset(self, preset) -> None:
        """Remember ``preset`` as where the scene came from."""
        self.preset_name, self.preset_notes = preset.name, preset.notes
        self.preset_scene = preset.scene

    # --- presets -------------------------------------------------------------------------------

    def load_preset_file(self, path) -> bool:
        """Load a preset; on any problem show it and change nothing."""
        if self._refused():
            return False
        try:
            preset = load_preset(path)
        except PresetError as exc:
            self.error_raised.emit(str(exc))
            return False
        switched = ""
        if preset.device_profile != self.device.profile.name:
            try:  # by name among the bundled and the user's profiles, never a path
                self.device.set_profile(find_profile(preset.device_profile))
                switched = f" on its device profile {preset.device_profile}"
            except ProfileError as exc:
                self.message_posted.emit(f"kept profile {self.device.profile.name}: {exc}", 10_000)
        self.device.set_lead(preset.lead_ms)
        self.before_load()
        self.state.last_message = ""  # what follows is this preset's, on this layout
        self.state.set_scene(preset.scene.replace(epoch=self.state.scene.epoch + 1))
        self.set_preset(preset)
        self.preset_changed.emit()
        changes = self._changes()
        self.message_posted.emit(f"loaded preset {preset.name}{switched}{changes}",
                                 10_000 if changes or switched else 5000)  # fmt: skip
        return True

    def save_preset_file(self, path, name=None, notes=None) -> bool:
        """Save the current scene as a preset (atomically)."""
        if self._refused():
            return False
        path = Path(path)
        if self.state.scene.shape is None:
            kind = source_kind(self.state.scene.source)
            self.error_raised.emit(f"could not save {path}: a preset holds a shape, and this "
                                   f"scene plays {kind} (keep its file, or pick a "
                                   "shape)")  # fmt: skip
            return False
        preset = Preset(
            self.state.scene.replace(playing=True),
            name=name or path.stem[:MAX_NAME_CHARS],
            notes=self.preset_notes if notes is None else notes,
            device_profile=self.device.profile.name,
            lead_ms=self.device.lead_ms,
        )
        try:
            save_preset(preset, path)
        except (OSError, ValueError) as exc:  # ValueError: a path refused before writing
            self.error_raised.emit(f"could not save {path}: {exc}")
            return False
        self.set_preset(preset)  # the scene is this preset now: its name, no "modified" star
        self.preset_changed.emit()
        self.message_posted.emit(f"saved preset to {path}", 5000)
        return True

    def ask_open_preset(self) -> None:
        """Ask for a preset and load it."""
        path = dialogs.open_path(self.parent(), "presets", "Open preset", ["Presets (*.json)"])
        if path:
            self.load_preset_file(path)

    def ask_save_preset(self) -> None:
        """Ask where to save the scene as a preset, and save it."""
        name = f"{dialogs.tuning_tag(self.state.scene)}-{dialogs.today()}.json"
        path = dialogs.save_path(self.parent(), "presets", "Save preset", name,
                                 ["Presets (*.json)"])  # fmt: skip
        if path:
            self.save_preset_file(path)

    # --- exports -------------------------------------------------------------------------------

    def export_curves(self, path) -> bool:
        """Activation curves of the current scene to .csv, .png or .svg."""
        if self._refused():
            return False
        path = Path(path)
        scene = self.state.scene
        curves = self.curves()
        if curves is None:
            self.error_raised.emit("no activation curves on show to export (the curves view's "
                                   "title says why)")  # fmt: skip
            return False
        try:
            if path.suffix.lower() == ".csv":
                export.write_curves_csv(path, curves)
            elif path.suffix.lower() in (".png", ".svg"):
                what = scene.shape.spec if scene.shape is not None else self.preset_name
                title = f"{scene.method} on {what}, mu = {value3(scene.mu)}, "
                title += f"gamma = {value3(scene.gamma)}"
                export.plot_curves(path, curves, title=title, colors=cell_colors(curves.cells))
            else:
                self.error_raised.emit(
                    f"curves export must end in .csv, .png or .svg, got {path.name}"
                )
                return False
        except (OSError, ValueError) as exc:  # ValueError: a path refused before writing
            self.error_raised.emit(f"could not write {path}: {exc}")
            return False
        self.message_posted.emit(f"exported curves to {path}", 5000)
        return True

    def export_lut(self, path) -> bool:
        """The correction as a 256-entry table: .csv, or a C header (.h)."""
        path = Path(path)
        scene, profile = self.state.scene, self.device.profile
        # as the stream sends it: the master intensity, and on felt amplitude the motors'
        # inverse response (the table used to hold the correction alone)
        stages = dict(gain=scene.gain, drive_for=profile.drive_for
                      if scene.felt_domain and profile.response is not None else None)  # fmt: skip
        try:
            if path.suffix.lower() == ".csv":
                export.write_lut_csv(path, scene.mu, scene.gamma, profile.levels, **stages)
            elif path.suffix.lower() == ".h":
                export.write_lut_header(path, scene.mu, scene.gamma, profile.levels, **stages)
            else:
                self.error_raised.emit(f"table export must end in .csv or .h, got {path.name}")
                return False
        except (OSError, ValueError) as exc:  # ValueError: a path refused before writing
            self.error_raised.emit(f"could not write {path}: {exc}")
            return False
        self.message_posted.emit(f"exported correction table to {path}", 5000)
        return True

    def ask_export_curves(self) -> None:
        """Ask where to export the activation curves (CSV, PNG or SVG), and export them."""
        scene = self.state.scene
        kind = type(scene.shape).__name__.lower() if scene.shape is not None else "pattern"
        name = f"curves-{kind}-{dialogs.tuning_tag(scene)}-{dialogs.today()}.csv"
        path = dialogs.save_path(self.parent(), "exports", "Export activation curves", name,
                                 ["CSV (*.csv)", "PNG (*.png)", "SVG (*.svg)"])  # fmt: skip
        if path:
            self.export_curves(path)

    def ask_export_lut(self) -> None:
        """Ask where to export the correction table (CSV or C header), and export it."""
        scene = self.state.scene
        levels = self.device.profile.levels
        name = f"lut-mu{value3(scene.mu)}-gamma{value3(scene.gamma)}-{levels}levels.h"
        path = dialogs.save_path(self.parent(), "exports", "Export correction table", name,
                                 ["C header (*.h)", "CSV (*.csv)"])  # fmt: skip
        if path:
            self.export_lut(path)

    # --- bHaptics .tact files ---------------------------------------------------------------------

    def import_tact_file(self, path, position=None, scale=None, rotation=None) -> bool:
        """Import a ``.tact`` file onto the current array: every position on the array's group
        for it (``VestFront`` on ``front``, ...), or one. A single path over the whole array
        becomes the scene's shape (a time-keyed path, over its own duration); anything more
        (several paths, dots, several positions, bHaptics' scale or rotation) plays as the
        scene's pattern: the heatmap draws its paths, the curves view its actuators over its
        duration."""
        if self._refused():
            return False
        try:
            pattern = load_pattern(path, position, scale=scale, rotation=rotation)
        except (TactError, ValueError) as exc:
            self.error_raised.emit(str(exc))
            return False
        target = self.device.profile.layout
        paths, dots = pattern.paths(target), pattern.dots(target)
        if not paths and not dots:
            self.error_raised.emit(f"{path}: no paths or dots to play")
            return False
        self.before_load()
        self._imported.add(Path(path).resolve())
        scene = self.state.scene.replace(epoch=self.state.scene.epoch + 1, playing=True)
        (whole, *more) = pattern.placement(target)
        plain = pattern.scale.identity and pattern.rotation.identity
        if len(paths) == 1 and not dots and not more and whole.index is None and plain:
            (shape,) = paths
            start = shape.times_s[0]
            shape = TimedPath(shape.points, [s - start for s in shape.times_s], shape.intensities,
                              shape.pattern, shape.fade)  # fmt: skip
            scene = scene.replace(shape=shape, duration_s=shape.duration_s, source=None)
            what = "its path is the shape"
        else:
            scene = scene.replace(shape=None, source=pattern)
            self._pattern_file = (pattern, {"path": str(Path(path).absolute()),
                                            "position": position})  # fmt: skip
            what = (f"{count(len(paths), 'path')} and {count(len(dots), 'dot')} play as a "
                    f"pattern of {pattern.duration_on(target):g} s "
                    "(Restart replays it)")  # fmt: skip
        self.state.set_scene(scene)
        self.preset_name, self.preset_notes, self.preset_scene = Path(path).stem, "", scene
        self.preset_changed.emit()
        left_out = pattern.skipped_on(target)
        skipped = f"; not played: {', '.join(left_out)}" if left_out else ""
        notes = "".join(f"; {note}" for note in pattern.notes)  # what plays otherwise than asked
        self.message_posted.emit(f"imported {pattern.describe(target)} of {Path(path).name}: "
                                 f"{what}{skipped}{notes}", 10_000)  # fmt: skip
        return True

    # --- patterns ---------------------------------------------------------------------------------

    def open_pattern_file(self, path, *, example: bool = False) -> bool:
        """Open a pattern file (``docs/patterns.md``) and play it as the scene's frame source,
        from its start: checked against the current array (the groups it names, its dots'
        actuators) and method first; on any problem show it and change nothing.

        A pattern that does not play on the array's profile but on other known profiles: an
        ``example`` (File -> Example patterns) switches to the first of them, the default
        profile first, as a preset switches to its own, and says so; for another file the
        message names them and how to choose one (a pattern does not say which array it is for,
        and the array connected is the user's)."""
        if self._refused():
            return False
        try:
            pattern = Pattern.load(path)
            if not pattern.effects:
                raise PatternError(f"{path}: the pattern has no effects to play")
        except PatternError as exc:
            self.error_raised.emit(str(exc))
            return False
        here, switched = self.device.profile.name, ""
        try:
            pattern.check(self.device.profile.layout, self.state.scene.method)
        except ValueError as exc:  # what does not play on this array, by field
            elsewhere = [name for name in profiles_playing(pattern) if name != here]
            blocked = self.profile_blocked()
            if not elsewhere or not example or blocked:
                self.error_raised.emit(f"{path}: {exc}" + _plays_on(elsewhere, blocked))
                return False
            self.before_load()
            self.state.last_message = ""
            self.device.set_profile(find_profile(elsewhere[0]))
            switched = f" on the device profile {elsewhere[0]} (it does not play on {here})"
            try:
                pattern.check(self.device.profile.layout, self.state.scene.method)
            except ValueError as exc:
                self.error_raised.emit(f"{path}: {exc}")
                return False
        self.before_load()
        scene = self.state.scene.replace(shape=None, source=pattern, playing=True,
                                         epoch=self.state.scene.epoch + 1)  # fmt: skip
        self._pattern_file = (pattern, {"path": str(Path(path).absolute()), "kind": "pattern"})
        self.state.set_scene(scene)
        self.preset_name = pattern.name or Path(path).stem
        self.preset_notes, self.preset_scene = pattern.notes, scene
        self.preset_changed.emit()
        what = f"{count(len(pattern.effects), 'effect')} over {pattern.duration_s:g} s"
        self.message_posted.emit(f"opened the pattern {Path(path).name}{switched}: {what} "
                                 f"(Restart replays it){self._changes()}", 10_000)  # fmt: skip
        return True

    def ask_open_pattern(self) -> None:
        """Ask for a pattern file and play it."""
        path = dialogs.open_path(self.parent(), "patterns", "Open pattern",
                                 ["Patterns (*.json)"])  # fmt: skip
        if path:
            self.open_pattern_file(path)

    def pattern_saved(self, pattern, path) -> None:
        """The pattern editor saved ``pattern`` to ``path``: while the scene plays it, the scene
        came from that file (the title's name, no star; the next start opens it)."""
        source = self.state.scene.source
        if (source.pattern if isinstance(source, PatternCue) else source) != pattern:
            return
        self._pattern_file = (pattern, {"path": str(Path(path).absolute()), "kind": "pattern"})
        self.preset_name, self.preset_notes = pattern.name or Path(path).stem, pattern.notes
        self.preset_scene = self.state.scene.replace(source=pattern)
        self.preset_changed.emit()

    def pattern_file(self, source) -> dict | None:
        """``{"path", "position", ["scale", "rotation"]}`` of the ``.tact`` file a scene's
        ``source`` was imported from (with the options it plays with), ``{"path", "kind":
        "pattern"}`` of a pattern file it was opened from, or None (neither)."""
        pattern, where = self._pattern_file
        if isinstance(pattern, Pattern):  # a pattern file (or a moment of it: a cue)
            source = source.pattern if isinstance(source, PatternCue) else source
            return dict(where) if source is not None and source is pattern else None
        if source is None or pattern is None or getattr(source, "file", None) is not pattern.file:
            return None
        out = dict(where)
        if not source.scale.identity:
            out["scale"] = [source.scale.intensity, source.scale.duration]
        if not source.rotation.identity:
            out["rotation"] = [source.rotation.angle_deg, source.rotation.offset_y]
        return out

    def export_tact_file(self, path) -> bool:
        """The scene's trace (its shape over its duration) as a ``.tact`` file, in 0..1 of the
        current array's actuators. A ``.tact`` file imported in this session is never
        overwritten (its other positions, paths and dots would be lost)."""
        path = Path(path)
        if path.resolve() in self._imported:
            self.error_raised.emit(f"could not export {path}: it is the .tact file this "
                                   "session imported; export to another name")  # fmt: skip
            return False
        try:
            written = write_tact(path, path_of_scene(self.state.scene), self.device.profile.layout,
                                 name=path.stem[: tact.MAX_NAME_CHARS])  # fmt: skip
        except (OSError, ValueError) as exc:
            self.error_raised.emit(f"could not export {path}: {exc}")
            return False
        self.message_posted.emit(f"exported the trace to {written}", 5000)
        return True

    def ask_import_tact(self) -> None:
        """Ask for a ``.tact`` file and import it."""
        path = dialogs.open_path(self.parent(), "tact", "Import bHaptics .tact",
                                 ["bHaptics (*.tact)"])  # fmt: skip
        if path:
            self.import_tact_file(path)

    def ask_export_tact(self) -> None:
        """Ask where to export the scene's trace as ``.tact``, and export it."""
        # Never the imported file's own name: a new one beside it.
        name = dialogs.unused_name("tact", f"{self.preset_name or 'trace'}-export.tact")
        path = dialogs.save_path(self.parent(), "tact", "Export bHaptics .tact", name,
                                 ["bHaptics (*.tact)"], confirm_overwrite=False)  # fmt: skip
        # The file this session imported is refused before anything is asked (Qt asked to
        # replace it, and the export then refused); another file is replaced once confirmed.
        if path and (path.resolve() in self._imported or not path.exists() or self.confirm(
                "Export bHaptics .tact", f"{path}\nalready exists.\n\nReplace it?")):  # fmt: skip
            self.export_tact_file(path)

    # --- device profiles -------------------------------------------------------------------------

    def use_profile(self, name_or_path) -> bool:
        """Use a device profile: a known one by name (bundled or the user's), or a file. The
        views and the scene follow its layout (:meth:`TunerState.set_layout`)."""
        reason = self.profile_blocked()
        if reason:
            self.error_raised.emit(reason)
            return False
        try:
            known = str(name_or_path) in profile_names()
            profile = find_profile(name_or_path) if known else load_profile(name_or_path)
        except ProfileError as exc:
            self.error_raised.emit(str(exc))
            return False
        self.before_load()
        self.state.last_message = ""
        self.device.set_profile(profile)
        self.message_posted.emit(
            f"device profile {profile.name}: {profile.layout.describe()}" + self._changes(), 10_000
        )
        return True

    def _changes(self) -> str:
        """What the state changed to fit the layout (a method, a shape), as a sentence."""
        return f". {self.state.last_message}" if self.state.last_message else ""

    def ask_open_profile(self) -> None:
        """Ask for a device profile and use it."""
        if self.profile_blocked():
            self.error_raised.emit(self.profile_blocked())
            return
        path = dialogs.open_path(self.parent(), "profiles", "Device profile",
                                 ["Profiles (*.json)"])  # fmt: skip
        if path:
            self.use_profile(path)

    def save_calibrated_profile(self, path, calibration) -> bool:
        """Save the device profile with a calibration's offsets and gains (and thresholds),
        and use it."""
        if calibration is None:
            self.error_raised.emit("no calibration has finished yet")
            return False
        try:
            profile = self.device.profile.with_calibration(*calibration)
            profile.save(path)
        except (ValueError, OSError) as exc:
            self.error_raised.emit(f"could not save the calibrated profile: {exc}")
            return False
        self.device.set_profile(load_profile(path))
        self.message_posted.emit(f"calibrated profile saved to {path} and in use", 10_000)
        return True
