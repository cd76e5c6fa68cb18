"""The pattern editor's controller: every edit an undoable command on the model, effects added
from what the tuner has (the scene, a drawing, tactors picked on the heatmap, a Tactile Brush
stroke), and the pattern played and scrubbed through the tuner's own stream."""

from __future__ import annotations

import json
import time
from pathlib import Path

from PySide6 import QtCore, QtGui

from tactile_core.files.pattern import Dot, Dots, Effect, Pattern, PatternCue, is_example
from tactile_core.rendering import placement
from tactile_core.rendering.shapes import path_from_samples

from .model import BIG_STEP_S, KEEP, SNAP_S, TimelineModel, snap

DOT_S = 0.2
"""How long the dots of a set picked on the heatmap play, in seconds."""
MAX_SESSION_CHARS = 1_000_000
"""The longest pattern (as JSON) the editor keeps in the session's settings for the next start;
a longer one comes back from its file, if it has one."""


def _tactor_name(layout, index: int) -> str:
    """A tactor as the heatmap names it: ``(col,row)`` on a grid, its name on a layout."""
    if layout.is_grid:
        return f"({index % layout.cols},{index // layout.cols})"
    return layout.names[index]


def pattern_of(source) -> Pattern | None:
    """The pattern a scene's source plays (a pattern, or a moment of one), or None."""
    if isinstance(source, PatternCue):
        return source.pattern
    return source if isinstance(source, Pattern) else None


class EditCommand(QtGui.QUndoCommand):
    """One edit on the undo stack: the model's pattern, selection (and, for another pattern
    opened, its file) after it, and before it for the undo. Edits of one key held down are
    merged into one command by :meth:`TimelineEditor.push` (Qt's own ``mergeWith``, which
    deletes the merged command under PySide's wrapper, crashed the interpreter)."""

    def __init__(self, model: TimelineModel, edit):
        super().__init__(edit.text)
        self.model = model
        self.before = (model.pattern, model.selected, KEEP if edit.path == KEEP else model.path)
        self.after = (edit.pattern, edit.selected, edit.path)
        self.key = edit.merge

    def redo(self) -> None:  # Qt override
        self.model.apply(*self.after)

    def undo(self) -> None:  # Qt override
        self.model.apply(*self.before)


class TimelineEditor(QtCore.QObject):
    """Edits the :class:`TimelineModel` through a ``QUndoStack`` and plays its pattern.

    The pattern plays as the scene's source, through the stream like any pattern
    (:class:`~tactile_core.files.pattern.PatternCue`: from the playhead, or held at it while
    scrubbed), so the heatmap, the curves and the array follow it. While the scene plays the
    editor's pattern, an edit takes effect at once (playing on from the playhead, or held
    there), and the playhead follows the stream; at the pattern's end it stops there. A
    pattern opened from the File menu is opened here too (Undo gives the one before back).

    Parameters
    ----------
    state : TunerState
    heatmap : HeatmapView
        Its drags in draw mode are recorded (:meth:`add_from_drawing`), its clicks pick
        tactors while :attr:`picking`.
    clock : callable
        Seconds, for the times of a drawing (``time.perf_counter``; tests inject one).
    """

    refused = QtCore.Signal(str)
    """An edit refused, saying why (the pattern's own message): shown under the panel."""
    error_raised = QtCore.Signal(str)
    """A file that could not be read or written."""
    message_posted = QtCore.Signal(str, int)
    picking_changed = QtCore.Signal(bool)

    def __init__(self, state, heatmap, parent=None, *, clock=time.perf_counter):
        super().__init__(parent)
        self.state = state
        self.heatmap = heatmap
        self.clock = clock
        self.model = TimelineModel()
        self.undo_stack = QtGui.QUndoStack(self)
        self.before_play = lambda: None
        """Called before the editor takes the scene (the window leaves draw mode)."""
        self.file_of = lambda source: None
        """Where a pattern the scene plays was opened from (``FileActions.pattern_file``)."""
        self.picking = False
        self.picked: list[int] = []
        self.drawing = None
        """The last drawing done in draw mode, ``(seconds, x, y)`` per point, or None."""
        self._stroke: list = []
        self._stroke_done = True
        scene = state.scene
        self.shape_scene = scene if scene.shape is not None else None
        """The last scene that played a shape (what *Add from the scene* adds)."""
        self._before = self.model.pattern
        self._why: dict = {}  # (pattern, why it does not play) by (id, layout, method)
        self.model.connect("pattern", self._on_model_pattern)
        state.scene_changed.connect(self._on_state_scene_changed)
        heatmap.point_drawn.connect(self._on_heatmap_point_drawn)
        heatmap.draw_released.connect(self._on_heatmap_draw_released)
        heatmap.cell_clicked.connect(self._on_heatmap_cell_clicked)
        heatmap.actuator_clicked.connect(self._on_heatmap_actuator_clicked)

    # --- edits ---------------------------------------------------------------------------------

    def push(self, make) -> bool:
        """Apply the edit ``make()`` returns as a command on the undo stack; False (and
        :attr:`refused`) when the pattern refuses it, or when it would no longer play on this
        array although it did."""
        try:
            edit = make()
            self._check(edit.pattern)
        except ValueError as exc:
            self.refused.emit(str(exc))
            self.message_posted.emit(f"not changed: {exc}", 10_000)
            return False
        stack = self.undo_stack
        top = stack.command(stack.index() - 1) if stack.index() > 0 else None
        if (
            edit.merge is not None
            and isinstance(top, EditCommand)
            and top.key == edit.merge
            and stack.index() == stack.count()
            and stack.cleanIndex() != stack.index()
        ):
            top.after = (edit.pattern, edit.selected, edit.path)  # one more step of a held key
            self.model.apply(*top.after)
            return True
        stack.push(EditCommand(self.model, edit))
        return True

    def why_not(self, pattern: Pattern) -> str:
        """Why ``pattern`` does not play on the array with the scene's method ("" when it does:
        :meth:`Pattern.check`); the last few answers are kept, as an edit asks of the pattern
        before it and after it (a check of 10,000 effects takes a quarter of a second)."""
        key = (id(pattern), self.state.layout, self.state.scene.method)
        kept = self._why.get(key)
        if kept is not None and kept[0] is pattern:
            return kept[1]
        try:
            pattern.check(self.state.layout, self.state.scene.method)
            why = ""
        except ValueError as exc:
            why = str(exc)
        if len(self._why) >= 4:
            self._why.pop(next(iter(self._why)))
        self._why[key] = (pattern, why)
        return why

    def _check(self, pattern: Pattern) -> None:
        """``ValueError`` if ``pattern`` does not play on the array while the edited one did."""
        if not pattern.effects:
            return
        why = self.why_not(pattern)
        if why and not (self.model.pattern.effects and self.why_not(self.model.pattern)):
            raise ValueError(why)  # (a pattern that did not play here either may be edited)

    def _selected(self) -> int | None:
        if self.model.selected is None:
            self.message_posted.emit("select an effect first (click it, or Tab)", 5000)
        return self.model.selected

    def delete_selected(self) -> bool:
        """Delete the selected effect."""
        i = self._selected()
        return i is not None and self.push(lambda: self.model.delete(i))

    def duplicate_selected(self) -> bool:
        """A copy of the selected effect right after it."""
        i = self._selected()
        return i is not None and self.push(lambda: self.model.duplicate(i))

    def nudge(self, steps: int = 0, tracks: int = 0, big: bool = False) -> bool:
        """Move the selected effect by ``steps`` grid steps (of :data:`BIG_STEP_S` with
        ``big``) and ``tracks`` tracks."""
        i = self._selected()
        step = (BIG_STEP_S if big else self.model.grid_s or SNAP_S) * steps
        return i is not None and self.push(lambda: self.model.nudge(i, step, tracks))

    def stretch(self, steps: int, big: bool = False) -> bool:
        """Lengthen (shorten, for negative ``steps``) the selected effect's play."""
        i = self._selected()
        step = (BIG_STEP_S if big else self.model.grid_s or SNAP_S) * steps
        return i is not None and self.push(lambda: self.model.stretch(i, step))

    def select_next(self, step: int) -> bool:
        """Select the next (``step`` 1) or previous (-1) effect in time order; False past
        either end."""
        index = self.model.neighbour(step)
        if index is None:
            return False
        self.model.select(index)
        return True

    # --- effects from what the tuner has ----------------------------------------------------

    def _placed(self, content, duration_s, text: str, **fields) -> bool:
        """Add ``content`` at the playhead (on the grid), on the lowest free track."""
        start = snap(self.model.playhead_s, self.model.grid_s)

        def make():
            effect = Effect(content, start_s=start, duration_s=duration_s, **fields)
            track = self.model.free_track(effect.start_s, effect.end_s)
            return self.model.add(effect.replace(track=track), text)

        return self.push(make)

    def add_from_scene(self) -> bool:
        """Add the last shape the scene played, with its method and duration."""
        scene = self.shape_scene
        if scene is None:
            self.refused.emit("no shape has played yet: pick one in the Shape controls")
            return False
        return self._placed(scene.shape, scene.duration_s, "Add the scene's shape",
                            method=scene.method)  # fmt: skip

    def add_from_drawing(self) -> bool:
        """Add the last drawing (draw mode's last drag) as a time-keyed path at its own pace,
        rendered by the scene's method."""
        if self.drawing is None:
            self.refused.emit("draw first: tick draw mode and drag on the heatmap")
            return False
        try:
            path = path_from_samples([s for s, _, _ in self.drawing],
                                     [(x, y) for _, x, y in self.drawing])  # fmt: skip
        except ValueError as exc:
            self.refused.emit(f"the drawing is not a path: {exc}")
            return False
        return self._placed(path, None, "Add the drawing")

    def set_picking(self, on: bool) -> None:
        """Pick tactors on the heatmap (a click picks one, a second click drops it) instead of
        pulsing them; :meth:`add_dots` adds them."""
        on = bool(on)
        if on != self.picking:
            self.picking = on
            self.picked = [] if on else self.picked
            self.picking_changed.emit(on)
            if on:
                self.message_posted.emit("click tactors on the heatmap to pick them, then "
                                         "Add > Dots: the tactors picked", 10_000)  # fmt: skip

    def add_dots(self) -> bool:
        """Add the tactors picked as a set of dots, together, for :data:`DOT_S`; picking ends."""
        picked = list(self.picked)
        if not picked:
            self.refused.emit("pick tactors first: Add > Pick tactors, then click them on the "
                              "heatmap")  # fmt: skip
            return False
        dots = Dots([Dot(i, 1.0, 0.0, DOT_S) for i in picked])
        added = self._placed(dots, DOT_S, f"Add {len(picked)} dots")
        if added:
            self.set_picking(False)
        return added

    def add_brush(self) -> bool:
        """Add a Tactile Brush stroke (``TB``) along the last shape played (the layout's default
        shape if none), over its duration."""
        scene = self.shape_scene
        shape = scene.shape if scene is not None else placement.default_shape(self.state.layout)
        duration = scene.duration_s if scene is not None else 1.0
        return self._placed(shape, duration, "Add a Tactile Brush stroke", method="TB")

    def _on_heatmap_point_drawn(self, x: float, y: float) -> None:
        if not self.heatmap.drawing:
            return
        if self._stroke_done:
            self._stroke, self._stroke_done = [], False
        x, y = self.heatmap.clamp(x, y)
        self._stroke.append((self.clock(), x, y))

    def _on_heatmap_draw_released(self) -> None:
        self._stroke_done = True
        if len(self._stroke) >= 2:
            self.drawing = list(self._stroke)

    def _on_heatmap_cell_clicked(self, col: int, row: int, _shift: bool) -> None:
        self._pick(row * self.state.layout.cols + col)

    def _on_heatmap_actuator_clicked(self, index: int, _shift: bool) -> None:
        self._pick(index)

    def _pick(self, index: int) -> None:
        if not self.picking:
            return
        if index in self.picked:
            self.picked.remove(index)
        else:
            self.picked.append(index)
        names = ", ".join(_tactor_name(self.state.layout, i) for i in self.picked) or "none"
        self.message_posted.emit(f"tactors picked: {names}", 10_000)

    # --- playing -------------------------------------------------------------------------------

    def owns_scene(self) -> bool:
        """Whether the scene plays the editor's pattern (from a moment of it, or as opened)."""
        pattern = pattern_of(self.state.scene.source)
        return pattern is not None and pattern is self.model.pattern

    def _playable(self) -> bool:
        pattern = self.model.pattern
        if not pattern.effects:
            self.refused.emit("the pattern has no effects to play: add one first")
            return False
        why = self.why_not(pattern)
        if why:
            self.refused.emit(f"the pattern does not play on this array: {why}")
        return not why

    def _take(self, cue: PatternCue, playing: bool) -> bool:
        self.before_play()
        scene = self.state.scene
        return self.state.update(shape=None, source=cue, playing=playing,
                                 epoch=scene.epoch + 1)  # fmt: skip

    def play(self) -> bool:
        """Play the pattern from the playhead (from its start when the playhead is at its
        end)."""
        if not self._playable():
            return False
        start = self.model.playhead_s
        if start >= self.model.pattern.duration_s - 1e-9:
            start = 0.0
            self.model.set_playhead(0.0)
        return self._take(PatternCue(self.model.pattern, start), True)

    def toggle_play(self) -> None:
        """Space in the editor: pause or play the editor's pattern (as Space does any scene);
        play it from the playhead if the scene plays something else."""
        if self.owns_scene():
            self.state.update(playing=self.state.held or not self.state.scene.playing)
        else:
            self.play()

    def seek(self, time_s: float) -> None:
        """Scrub: the playhead to ``time_s``; the heatmap and the array show that frame of the
        pattern (held, as the curves' cursor holds a trace) until it plays again."""
        self.model.set_playhead(min(max(float(time_s), 0.0), 3600.0))
        if self.model.pattern.effects and self._playable():
            self._take(PatternCue(self.model.pattern, self.model.playhead_s, hold=True), True)

    def _on_model_pattern(self) -> None:
        """An edit, undo or redo: the scene follows when it played the pattern before it."""
        before, self._before = self._before, self.model.pattern
        if pattern_of(self.state.scene.source) is not before:
            return
        pattern, scene = self.model.pattern, self.state.scene
        if not pattern.effects or self.why_not(pattern):
            self.state.update(source=None, playing=False)
            return
        held = scene.source.hold if isinstance(scene.source, PatternCue) else False
        moving = scene.playing and not held
        cue = PatternCue(pattern, min(self.model.playhead_s, pattern.duration_s), hold=not moving)
        self.state.update(source=cue, playing=scene.playing)

    def on_frame_shown(self, scene, start_s, rate_hz, phase_s) -> None:
        """The display showed a frame: the playhead follows a playing pattern of the editor's,
        which stops at the end (held there, paused: Space plays it from the start)."""
        source = scene.source
        if phase_s is None or pattern_of(source) is not self.model.pattern or not scene.playing:
            return
        if isinstance(source, PatternCue) and source.hold:
            return
        self.model.set_playhead(phase_s)
        end = self.model.pattern.duration_s
        if phase_s >= end:  # (a pattern opened from a file too: its buttons said Pause at end)
            self.state.update(source=PatternCue(self.model.pattern, end, hold=True),
                              playing=False)  # fmt: skip

    def _on_state_scene_changed(self, scene) -> None:
        if scene.shape is not None and not self.heatmap.drawing:
            self.shape_scene = scene
        source = scene.source
        if isinstance(source, Pattern) and source == self.model.pattern:
            if source is not self.model.pattern:  # the same pattern again: this one's object
                self.model.apply(source, self.model.selected)
        elif isinstance(source, Pattern):  # File > Open pattern... (or Example patterns)
            path = (self.file_of(source) or {}).get("path")
            path = None if path is None else Path(path)
            bundled = path is not None and is_example(path)
            self.open_pattern(source, None if bundled else path,
                              f"Open {source.name or 'the pattern'}")  # fmt: skip
            if bundled:  # an example as it comes: nothing to save; Save asks where
                self.undo_stack.setClean()

    def open_pattern(self, pattern: Pattern, path, text: str) -> None:
        """Edit ``pattern`` (from the file ``path``, or None) instead, as an undoable step;
        the stack counts it as saved when it came from a file."""
        self.undo_stack.push(EditCommand(self.model, self.model.replace_all(pattern, text, path)))
        self.model.set_playhead(0.0)
        if path is not None:
            self.undo_stack.setClean()


def save_session(editor, settings) -> None:
    """Remember ``editor``'s pattern (its JSON, up to :data:`MAX_SESSION_CHARS`), its file,
    whether it has unsaved edits, the playhead and the effect selected, for the next start."""
    model = editor.model
    text = json.dumps(model.pattern.to_dict())
    settings.setValue("editor_pattern", text if len(text) <= MAX_SESSION_CHARS else "")
    settings.setValue("editor_path", str(model.path) if model.path is not None else "")
    settings.setValue("editor_modified", not editor.undo_stack.isClean())
    settings.setValue("editor_at", json.dumps([model.playhead_s, model.selected]))
    scene = editor.state.scene
    settings.setValue("editor_scene", json.dumps([editor.state.held, scene.playing]))


def restore_session(editor, settings) -> str:
    """Put back the last session's pattern in ``editor`` (not as an undoable step; with its
    unsaved edits still unsaved), its playhead and selection; returns what the status line
    says of it ("" for none)."""
    text = str(settings.value("editor_pattern", "") or "")
    path = str(settings.value("editor_path", "") or "") or None
    try:
        if text:
            pattern = Pattern.from_dict(json.loads(text), "the last session's pattern")
        elif path is not None:
            pattern = Pattern.load(path)
        else:
            return ""
    except (ValueError, TypeError, OSError) as exc:
        return f"the pattern editor starts empty: {exc}"
    editor.model.apply(pattern, None, None if path is None else Path(path))
    editor.undo_stack.clear()
    try:  # where it was: the playhead, the effect selected
        playhead, selected = json.loads(str(settings.value("editor_at", "") or "[0, null]"))
        editor.model.set_playhead(playhead)
        editor.model.select(selected)
    except (ValueError, TypeError):
        pass  # (damaged: at the start, nothing selected)
    if str(settings.value("editor_modified", "false")).lower() == "true":
        editor.undo_stack.resetClean()  # its edits are still not saved
    return ""


def resume_session(editor, settings) -> bool:
    """The last session ended with the scene playing the editor's pattern: the scene plays it
    again as it was left (held at the playhead, paused there, or playing from it); False if
    it does not play on this array."""
    try:
        held, playing = json.loads(str(settings.value("editor_scene", "") or "[false, true]"))
    except (ValueError, TypeError):
        held, playing = False, True
    if not held and playing:
        return editor.play()
    if not editor._playable():
        return False
    cue = PatternCue(editor.model.pattern, editor.model.playhead_s, hold=True)
    return editor._take(cue, bool(playing))
