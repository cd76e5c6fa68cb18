"""A drawing kept as the scene's shape: what draw mode drew, replayed at the pace it was drawn
(File -> Keep the drawing as the shape)."""

from __future__ import annotations

import time

from tactile_core.rendering.shapes import path_from_samples


class KeepsDrawing:
    """The part of :class:`~app.files.FileActions` that records draw mode's drag and keeps it
    as the shape. It uses the host's ``state``, ``before_load``, ``drawing_changed``,
    ``error_raised`` and ``message_posted``; :meth:`init_drawing` sets it up."""

    def init_drawing(self) -> None:
        """No drawing, out of draw mode."""
        self._stroke: list = []
        """The last drawing in draw mode: ``(seconds, x, y)`` per point drawn (none outside
        draw mode)."""
        self._stroke_done = True
        self._drawing = False  # in draw mode

    def follow_drawing(self, gestures) -> None:
        """Record what is drawn in ``gestures``' draw mode (a
        :class:`~app.tune.gestures.HeatmapGestures`), for :meth:`keep_drawing`."""
        gestures.heatmap.point_drawn.connect(self.record_drawn_point)
        gestures.heatmap.draw_released.connect(self.end_drawn_stroke)
        gestures.draw_mode_changed.connect(self.set_draw_mode)

    @property
    def can_keep_drawing(self) -> bool:
        """In draw mode with a path drawn (two points or more): :meth:`keep_drawing` keeps it."""
        return self._drawing and len(self._stroke) >= 2

    def set_draw_mode(self, on: bool) -> None:
        """Draw mode began or ended: either way, no drawing yet (one from an earlier draw mode
        would replace whatever scene plays since: a preset, a ``.tact`` file)."""
        self._drawing = bool(on)
        self._stroke, self._stroke_done = [], True
        self.drawing_changed.emit(self.can_keep_drawing)

    def record_drawn_point(self, x: float, y: float) -> None:
        """Draw mode moved the point to ``(x, y)``: add it to the drawing (a new drawing starts
        after the pointer was released)."""
        if not self._drawing:
            return
        before = self.can_keep_drawing
        if self._stroke_done:
            self._stroke, self._stroke_done = [], False
        self._stroke.append((time.perf_counter(), float(x), float(y)))
        if self.can_keep_drawing != before:
            self.drawing_changed.emit(self.can_keep_drawing)

    def end_drawn_stroke(self) -> None:
        """The pointer was released: the drawing is complete."""
        self._stroke_done = True

    def keep_drawing(self) -> bool:
        """Leave draw mode with the last drawing as the scene's shape: a time-keyed path that
        replays it at the pace it was drawn (save it as a preset, export it as ``.tact``).
        Only in draw mode, with a path drawn (:attr:`can_keep_drawing`)."""
        if not self._drawing:
            self.error_raised.emit("draw a path first: turn on draw mode and drag on the heatmap")
            return False
        try:
            shape = path_from_samples([s for s, _, _ in self._stroke],
                                      [(x, y) for _, x, y in self._stroke])  # fmt: skip
        except ValueError:
            self.error_raised.emit("draw a path first: turn on draw mode and drag on the heatmap")
            return False
        self.before_load()
        scene = self.state.scene
        self.state.set_scene(scene.replace(shape=shape, duration_s=shape.duration_s, source=None,
                                           epoch=scene.epoch + 1, playing=True))  # fmt: skip
        self.message_posted.emit(f"the drawing is the shape: {len(shape.points)} points over "
                                 f"{shape.duration_s:.2f} s", 10_000)  # fmt: skip
        return True
