"""The pattern editor's files: open and save a pattern (``"format": "tactile-pattern"``), import
a bHaptics ``.tact`` file as editable effects, export to ``.tact`` (the Designer's project form,
and with bHaptics' compiled frames too) and to WAV (the carriers an audio interface plays)."""

from __future__ import annotations

from pathlib import Path

from PySide6 import QtCore

from tactile_core.files import tact
from tactile_core.files.pattern import Pattern, PatternError, is_example
from tactile_core.files.tact import POSITION_GROUPS, POSITIONS, TactError, load_pattern
from tactile_core.files.wav import frame_levels, write_wav

from .. import dialogs

PATTERNS = ["Patterns (*.json)"]
TACT = ["bHaptics (*.tact)"]


def export_positions(target) -> dict:
    """``{group: position}``: the groups of ``target`` that name exactly one bHaptics device
    position a ``.tact`` file may hold (``front`` is ``VestFront``, ``back`` is ``VestBack``;
    ``left``, which a sleeve, a hand or a foot may be, is none): their effects are written to
    that position, in 0..1 of the group's actuators; everything else to ``VestFront`` over the
    whole array."""
    out = {}
    for group, _ in target.groups:
        names = [p for p in POSITIONS if group.lower() in (p.lower(), *POSITION_GROUPS.get(p, ()))]
        if len(names) == 1 and names[0] not in out.values():
            out[group] = names[0]
    return out


class PatternFiles(QtCore.QObject):
    """Reads and writes the editor's pattern; problems become :attr:`error_raised` messages and
    nothing changes (files are written atomically by the core).

    Parameters
    ----------
    editor : TimelineEditor
    device : DeviceController
        The profile in use: its layout (groups, ``.tact`` positions), levels and carriers.
    parent : QWidget
        The dialogs' parent.
    """

    saved = QtCore.Signal(object, object)
    """A pattern was saved: ``(pattern, path)``."""

    def __init__(self, editor, device, parent):
        super().__init__(parent)
        self.editor = editor
        self.device = device

    @property
    def model(self):
        return self.editor.model

    def _fail(self, text: str) -> bool:
        self.editor.error_raised.emit(text)
        return False

    def _done(self, text: str) -> bool:
        self.editor.message_posted.emit(text, 8000)
        return True

    # --- the pattern file ----------------------------------------------------------------------

    def open_file(self, path) -> bool:
        """Edit the pattern of ``path`` (an undoable step); a pattern that does not play on
        this array opens all the same, and the status line says why it does not."""
        try:
            pattern = Pattern.load(path)
        except PatternError as exc:
            return self._fail(str(exc))
        self.editor.open_pattern(pattern, Path(path), f"Open {Path(path).name}")
        layout = self.device.profile.layout
        try:
            pattern.check(layout, self.editor.state.scene.method)
            note = ""
        except ValueError as exc:
            note = f"; it does not play on {self.device.profile.name}: {exc}"
        n = len(pattern.effects)
        return self._done(f"editing {Path(path).name}: {n} effect{'' if n == 1 else 's'}{note}")

    def save_file(self, path=None) -> bool:
        """Save the pattern to ``path`` (None: the file it came from); the undo stack is clean
        after it. A pattern without a name is given its file's (an undoable edit)."""
        path = self.model.path if path is None else Path(path)
        if path is None:
            return self._fail("the pattern has no file yet: Save as... first")
        if is_example(path):  # the installed package's own copy: every next user's example
            return self._fail(f"{path.name} is a bundled example: Save as... a file of your own")
        if not self.model.pattern.name:  # named for its file, by the file and everywhere
            self.editor.push(lambda: self.model.change_pattern(name=path.stem))
        try:
            written = self.model.pattern.save(path)
        except (OSError, ValueError) as exc:
            return self._fail(f"could not save {path}: {exc}")
        self.model.set_path(Path(written))
        self.editor.undo_stack.setClean()
        self.saved.emit(self.model.pattern, Path(written))
        return self._done(f"saved the pattern to {written}")

    def import_tact(self, path) -> bool:
        """Import a ``.tact`` file's effects as the pattern (each effect at its time on its
        track): every device position on the profile's group for it, or the first over the
        whole array (:meth:`Pattern.from_tact`)."""
        layout = self.device.profile.layout
        try:
            placed = load_pattern(path).placement(layout)
            groups = {p.position: p.group for p in placed if p.group is not None}
            pattern = Pattern.from_tact(path, groups=groups or None)
        except (TactError, ValueError) as exc:
            return self._fail(str(exc))
        self.editor.open_pattern(pattern, None, f"Import {Path(path).name}")
        where = ", ".join(f"{p} on {g}" for p, g in groups.items()) or "over the whole array"
        n = len(pattern.effects)
        return self._done(f"imported {n} effect{'' if n == 1 else 's'} of {Path(path).name} "
                          f"({where}) as editable effects")  # fmt: skip

    # --- exports -------------------------------------------------------------------------------

    def export_tact(self, path, compiled: bool = False) -> bool:
        """The pattern as bHaptics' Designer project (and, ``compiled``, its compiled frames
        every 20 ms as rendered with the scene's method), each group that names a device
        position on it (:func:`export_positions`)."""
        layout, scene = self.device.profile.layout, self.editor.state.scene
        positions = export_positions(layout)
        loose = [k for k, e in enumerate(self.model.pattern.effects) if e.group not in positions]
        if loose and "VestFront" in positions.values():  # where the rest would go is a group's
            k = loose[0]
            group = self.model.pattern.effects[k].group
            what = "every actuator" if group is None else f"the group {group}"
            places = ", ".join(f"{g} as {p}" for g, p in positions.items())
            return self._fail(f"could not export {Path(path).name}: effect {k + 1} plays on "
                              f"{what}, but a .tact file holds each group here as a device "
                              f"position ({places}): choose its group in the properties "
                              f"({' or '.join(positions)}), then export again")  # fmt: skip
        options = dict(positions=positions,
                       name=Path(path).stem[: tact.MAX_NAME_CHARS] or "pattern")  # fmt: skip
        if compiled:
            options["compiled"] = scene.method
        try:
            written = self.model.pattern.save_tact(path, layout, **options)
        except (OSError, ValueError) as exc:
            return self._fail(f"could not export {path}: {exc}")
        form = "project and compiled frames" if compiled else "project"
        return self._done(f"exported the pattern to {written} (bHaptics {form})")

    def export_wav(self, path) -> bool:
        """The pattern's carriers as the audio transport would play them: its frames at the
        scene's method, correction and rate, calibrated and quantised to the profile's levels,
        one channel per actuator (:func:`~tactile_core.files.wav.write_wav`)."""
        profile, scene = self.device.profile, self.editor.state.scene
        pattern = self.model.pattern
        try:
            if not pattern.effects:
                raise ValueError("the pattern has no effects to play")
            _, frames = pattern.frames(scene.method, profile.layout, rate_hz=scene.rate_hz,
                                       mu=scene.mu, gamma=scene.gamma, gain=scene.gain)  # fmt: skip
            write_wav(path, frame_levels(frames, profile), scene.rate_hz, profile)
        except (OSError, ValueError) as exc:
            return self._fail(f"could not export {path}: {exc}")
        return self._done(f"exported the pattern's carriers to {path} ({profile.channels} "
                          f"channels, {len(frames)} frames at {scene.rate_hz:g} Hz)")  # fmt: skip

    # --- dialogs -------------------------------------------------------------------------------

    def _name(self, suffix: str) -> str:
        stem = self.model.path.stem if self.model.path else self.model.pattern.name or "pattern"
        return dialogs.safe_name(stem) + suffix

    def ask_open(self) -> None:
        """Ask for a pattern file and edit it."""
        path = dialogs.open_path(self.parent(), "patterns", "Open pattern", PATTERNS)
        if path:
            self.open_file(path)

    def ask_save(self) -> None:
        """Save to the pattern's file, or ask where (Save as)."""
        if self.model.path is None:
            self.ask_save_as()
        else:
            self.save_file()

    def ask_save_as(self) -> None:
        """Ask where to save the pattern, and save it."""
        path = dialogs.save_path(self.parent(), "patterns", "Save pattern as",
                                 self._name(".json"), PATTERNS)  # fmt: skip
        if path:
            self.save_file(path)

    def ask_import_tact(self) -> None:
        """Ask for a ``.tact`` file and import its effects."""
        path = dialogs.open_path(self.parent(), "tact", "Import bHaptics .tact as effects", TACT)
        if path:
            self.import_tact(path)

    def ask_export_tact(self, compiled: bool = False) -> None:
        """Ask where to export the pattern as ``.tact``, and export it."""
        name = dialogs.unused_name("tact", self._name(".tact"))
        path = dialogs.save_path(self.parent(), "tact", "Export the pattern as .tact", name, TACT)
        if path:
            self.export_tact(path, compiled)

    def ask_export_wav(self) -> None:
        """Ask where to export the pattern as WAV, and export it."""
        path = dialogs.save_path(self.parent(), "exports", "Export the pattern as WAV",
                                 self._name(".wav"), ["WAV (*.wav)"])  # fmt: skip
        if path:
            self.export_wav(path)
