"""The pattern editor's time line: tracks as rows, effects as blocks on a time axis, a ruler
with the playhead. Drag a block to move it (start and track), its right edge to resize it,
the ruler to scrub; the keys do the same (Tab, arrows, Delete, Space)."""

from __future__ import annotations

import math

from PySide6 import QtCore, QtGui, QtWidgets

from .model import describe

RULER_PX = 24
"""Height of the ruler at the top of the view."""
TRACK_PX = 30
"""Height of a track."""
LEFT_PX = 30
"""Room before 0 s for the tracks' numbers."""
EDGE_PX = 6
"""A press this close to a block's right edge resizes it."""
MIN_SPAN_S = 2.0
"""The least time the view spans when fitted."""
KIND_COLORS = {"shape": "#2478b4", "dots": "#de9c00", "tact": "#00a070", "brush": "#8a48c8"}
"""The blocks' colours by what they play: a shape, dots, a ``.tact`` effect, a TB stroke."""
PLAYHEAD_COLOR = "#e53935"
Key = QtCore.Qt.Key

STRETCH_KEYS = {Key.Key_BracketRight: 1, Key.Key_BracketLeft: -1, Key.Key_BraceRight: 1,
                Key.Key_BraceLeft: -1}  # fmt: skip
"""] / [ lengthen / shorten the selected effect by 10 ms (} / {, Shift: 100 ms)."""
Mod = QtCore.Qt.KeyboardModifier


def kind_of(effect) -> str:
    """The colour key of an effect (:data:`KIND_COLORS`)."""
    return "brush" if effect.kind == "shape" and effect.method == "TB" else effect.kind


def tick_step(pixels_per_s: float) -> float:
    """Seconds between labelled ticks: 1, 2 or 5 times a power of ten, at least 60 px apart."""
    raw = 60.0 / max(pixels_per_s, 1e-9)
    power = 10.0 ** math.floor(math.log10(raw))
    return next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= raw)


class BlockItem(QtWidgets.QGraphicsRectItem):
    """One effect drawn as a block from its start to the end of its last play (a line at each
    repeat), labelled with its name or what it plays."""

    def __init__(self, view):
        super().__init__()
        self.view = view
        self.index = -1
        self.effect = None
        self.label = ""
        self.selected = False
        self.setAcceptHoverEvents(True)

    def show(self, index: int, effect, rect: QtCore.QRectF, selected: bool) -> None:
        """Draw effect ``index`` in ``rect``."""
        self.index, self.effect, self.selected = index, effect, selected
        name = effect.name or describe(effect)
        repeat = f" x{effect.repeat}" if effect.repeat > 1 else ""
        self.label = f"{index + 1}  {name}{repeat}"
        self.setToolTip(f"effect {index + 1}: {describe(effect)}, {effect.start_s:g} s + "
                        f"{effect.duration_s:g} s{repeat} on track {effect.track + 1}")  # fmt: skip
        self.setRect(rect)
        self.update()

    def paint(self, painter, option, widget=None) -> None:  # Qt override
        rect = self.rect()
        color = QtGui.QColor(KIND_COLORS[kind_of(self.effect)])
        fill = QtGui.QColor(color)
        fill.setAlpha(200 if self.selected else 150)
        if rect.width() < 2 * EDGE_PX and not self.selected:  # a sliver: no label, no edge
            painter.fillRect(rect.adjusted(0, 1, 0, -1), fill)  # (10,000 blocks in view)
            return
        palette = self.view.palette()
        painter.setBrush(fill)
        edge = palette.color(QtGui.QPalette.ColorRole.Highlight) if self.selected else color
        painter.setPen(QtGui.QPen(edge.darker(130) if not self.selected else edge,
                                  3 if self.selected else 1))  # fmt: skip
        painter.drawRoundedRect(rect.adjusted(1, 1, -1, -1), 4, 4)
        effect = self.effect
        if effect.repeat > 1:
            painter.setPen(QtGui.QPen(QtGui.QColor(255, 255, 255, 150), 1,
                                      QtCore.Qt.PenStyle.DashLine))  # fmt: skip
            play = rect.width() / effect.repeat
            for r in range(1, effect.repeat):
                x = rect.left() + r * play
                painter.drawLine(QtCore.QPointF(x, rect.top() + 3),
                                 QtCore.QPointF(x, rect.bottom() - 3))  # fmt: skip
        painter.setPen(QtGui.QColor("white"))
        text_rect = rect.adjusted(5, 0, -EDGE_PX, 0)
        text = painter.fontMetrics().elidedText(self.label, QtCore.Qt.TextElideMode.ElideRight,
                                                int(max(text_rect.width(), 0)))  # fmt: skip
        painter.drawText(text_rect, QtCore.Qt.AlignmentFlag.AlignVCenter, text)

    def hoverMoveEvent(self, event) -> None:  # Qt override
        near = event.pos().x() >= self.rect().right() - EDGE_PX
        shape = QtCore.Qt.CursorShape
        self.setCursor(shape.SizeHorCursor if near else shape.OpenHandCursor)


class TimelineView(QtWidgets.QGraphicsView):
    """The tracks and effects of a :class:`~.model.TimelineModel`, edited through a
    :class:`~.editor.TimelineEditor` (each drag or key one undoable command).

    Mouse: click a block to select it, drag it to move it (snapped to the model's grid, 10 ms;
    up or down to another track), drag its right edge to resize one play, click or drag the
    ruler to scrub; Ctrl+wheel zooms. Keys: Tab / Shift+Tab (or Ctrl+Right / Ctrl+Left) select
    the next or previous effect in time; the arrows move it by 10 ms (Shift: 100 ms) or a
    track; Alt+Right / Alt+Left (or ] / [) lengthen or shorten it; Home / End scrub to the start
    or the end; Delete removes it, Ctrl+D duplicates it; Space plays or pauses.
    """

    takes_space = True
    """Space is this view's (play or pause the pattern), not the window's (:mod:`..keys`)."""

    def __init__(self, editor, parent=None):
        super().__init__(parent)
        self.setObjectName("timeline_view")
        self.editor = editor
        self.model = editor.model
        self.setScene(QtWidgets.QGraphicsScene(self))
        self.setFocusPolicy(QtCore.Qt.FocusPolicy.StrongFocus)
        self.setAlignment(QtCore.Qt.AlignmentFlag.AlignLeft | QtCore.Qt.AlignmentFlag.AlignTop)
        self.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing)
        self.setViewportUpdateMode(QtWidgets.QGraphicsView.ViewportUpdateMode.FullViewportUpdate)
        self.setMinimumHeight(RULER_PX + 3 * TRACK_PX + 4)
        self.setAccessibleName("Pattern time line")
        self.pixels_per_s = 100.0
        self._span_s = MIN_SPAN_S
        self._zoomed = False
        self._blocks: list[BlockItem] = []
        self._drag = None  # (block, "move" or "resize", scene x, scene y) while dragging
        self._scrubbing = False
        self.model.connect("pattern", self._on_model_pattern)
        self.model.connect("selection", self._on_model_selection)
        self.model.connect("playhead", self.viewport().update)
        self._on_model_pattern()

    # --- geometry ------------------------------------------------------------------------------

    def x_of(self, time_s: float) -> float:
        """The scene's x of ``time_s``."""
        return LEFT_PX + time_s * self.pixels_per_s

    def time_at(self, view_x: float) -> float:
        """The time at the viewport's x ``view_x``, in seconds (0 at least)."""
        x = self.mapToScene(QtCore.QPoint(round(view_x), 0)).x()
        return max((x - LEFT_PX) / self.pixels_per_s, 0.0)

    def block_rect(self, effect) -> QtCore.QRectF:
        """Where an effect's block goes, in scene coordinates."""
        x0, x1 = self.x_of(effect.start_s), self.x_of(effect.end_s)
        top = RULER_PX + effect.track * TRACK_PX + 2
        return QtCore.QRectF(x0, top, max(x1 - x0, 3.0), TRACK_PX - 4)

    def block(self, index: int) -> BlockItem:
        """The block of effect ``index``."""
        return self._blocks[index]

    def _fit(self) -> None:
        """Pixels per second so that the pattern (at least :data:`MIN_SPAN_S`) fits across."""
        duration = self.model.pattern.duration_s
        if not self._zoomed and (duration > self._span_s * 0.95 or duration < self._span_s / 2):
            self._span_s = max(MIN_SPAN_S, duration * 1.15)
        width = max(self.viewport().width() - LEFT_PX - 12, 100)
        self.pixels_per_s = width / self._span_s

    def _layout(self) -> None:
        """Every block in its place (the items made once and reused), the scene's extent."""
        effects = self.model.pattern.effects
        scene = self.scene()
        while len(self._blocks) < len(effects):
            item = BlockItem(self)
            scene.addItem(item)
            self._blocks.append(item)
        while len(self._blocks) > len(effects):
            scene.removeItem(self._blocks.pop())
        for i, (item, effect) in enumerate(zip(self._blocks, effects)):
            item.show(i, effect, self.block_rect(effect), i == self.model.selected)
        tracks = max((e.track for e in effects), default=-1) + 2  # and an empty one to drag to
        end = max(self.model.pattern.duration_s, self._span_s)  # (fitted: no scroll bar)
        height = RULER_PX + max(tracks, 3) * TRACK_PX
        scene.setSceneRect(0, 0, self.x_of(end) + 8, height)
        self.viewport().update()

    def resizeEvent(self, event) -> None:  # Qt override
        super().resizeEvent(event)
        self._fit()
        self._layout()

    def _on_model_pattern(self) -> None:
        self._fit()
        self._layout()

    def _on_model_selection(self) -> None:
        for i, item in enumerate(self._blocks):
            item.selected = i == self.model.selected
            item.update()
        if self.model.selected is not None:
            self.ensureVisible(self._blocks[self.model.selected].rect(), 20, 10)

    def wheelEvent(self, event) -> None:  # Qt override
        if event.modifiers() & Mod.ControlModifier:
            factor = 1.25 if event.angleDelta().y() > 0 else 0.8
            self._span_s = min(max(self._span_s / factor, 0.05), 3600.0)
            self._zoomed = True
            self._fit()
            self._layout()
            event.accept()
            return
        super().wheelEvent(event)

    # --- painting ------------------------------------------------------------------------------

    def drawBackground(self, painter, rect) -> None:  # Qt override
        palette = self.palette()
        role = QtGui.QPalette.ColorRole
        painter.fillRect(rect, palette.color(role.Base))
        scene = self.sceneRect()
        tracks = int((scene.height() - RULER_PX) // TRACK_PX)
        painter.setPen(palette.color(role.Text))
        for t in range(tracks):
            top = RULER_PX + t * TRACK_PX
            if t % 2:
                painter.fillRect(QtCore.QRectF(0, top, scene.width(), TRACK_PX),
                                 palette.color(role.AlternateBase))  # fmt: skip
            painter.drawText(QtCore.QRectF(0, top, LEFT_PX - 4, TRACK_PX),
                             QtCore.Qt.AlignmentFlag.AlignCenter, str(t + 1))  # fmt: skip
        grid = QtGui.QColor(palette.color(role.Text))
        grid.setAlpha(40)
        painter.setPen(grid)
        step = tick_step(self.pixels_per_s)
        for k in range(int(scene.width() / (step * self.pixels_per_s)) + 2):
            x = self.x_of(k * step)
            painter.drawLine(QtCore.QPointF(x, RULER_PX), QtCore.QPointF(x, scene.height()))

    def drawForeground(self, painter, rect) -> None:  # Qt override
        """The ruler at the top of the viewport (it stays there while the tracks scroll) and
        the playhead over everything."""
        palette = self.palette()
        role = QtGui.QPalette.ColorRole
        painter.save()
        painter.resetTransform()
        width = self.viewport().width()
        painter.fillRect(QtCore.QRectF(0, 0, width, RULER_PX), palette.color(role.Window))
        painter.setPen(palette.color(role.WindowText))
        step = tick_step(self.pixels_per_s)
        left, right = self.time_at(0), self.time_at(width)
        k = math.floor(left / step)
        while k * step <= right:
            x = self.mapFromScene(QtCore.QPointF(self.x_of(k * step), 0)).x()
            painter.drawLine(QtCore.QPointF(x, RULER_PX - 6), QtCore.QPointF(x, RULER_PX))
            painter.drawText(QtCore.QPointF(x + 3, RULER_PX - 8), f"{k * step:g}")
            k += 1
        painter.drawText(QtCore.QPointF(4, RULER_PX - 8), "s")
        x = self.mapFromScene(QtCore.QPointF(self.x_of(self.model.playhead_s), 0)).x()
        red = QtGui.QColor(PLAYHEAD_COLOR)
        painter.setPen(QtGui.QPen(red, 2))
        painter.drawLine(QtCore.QPointF(x, 0), QtCore.QPointF(x, self.viewport().height()))
        painter.setBrush(red)
        painter.drawPolygon(QtGui.QPolygonF([QtCore.QPointF(x - 6, 0), QtCore.QPointF(x + 6, 0),
                                             QtCore.QPointF(x, 9)]))  # fmt: skip
        painter.restore()

    # --- the mouse -----------------------------------------------------------------------------

    def mousePressEvent(self, event) -> None:  # Qt override
        if event.button() != QtCore.Qt.MouseButton.LeftButton:
            super().mousePressEvent(event)
            return
        self.setFocus()
        pos = event.position()
        if pos.y() < RULER_PX:
            self._scrubbing = True
            self.editor.seek(self.time_at(pos.x()))
            return
        where = self.mapToScene(pos.toPoint())
        item = next((b for b in self._blocks if b.rect().contains(where)), None)
        if item is None:
            self.model.select(None)
            return
        self.model.select(item.index)
        mode = "resize" if where.x() >= item.rect().right() - EDGE_PX else "move"
        self._drag = (item, mode, where.x(), where.y())

    def mouseMoveEvent(self, event) -> None:  # Qt override
        pos = event.position()
        if self._scrubbing:
            self.editor.seek(self.time_at(pos.x()))
            return
        if self._drag is None:
            super().mouseMoveEvent(event)
            return
        item, mode, x0, y0 = self._drag
        where = self.mapToScene(pos.toPoint())
        effect = self._dragged(item, mode, where.x() - x0, where.y() - y0)
        if effect is not None:
            item.setRect(self.block_rect(effect))  # a preview: the edit is made on release

    def mouseReleaseEvent(self, event) -> None:  # Qt override
        if self._scrubbing:
            self._scrubbing = False
            return
        if self._drag is None:
            super().mouseReleaseEvent(event)
            return
        item, mode, x0, y0 = self._drag
        self._drag = None
        where = self.mapToScene(event.position().toPoint())
        dx, dy = where.x() - x0, where.y() - y0
        effect, i = item.effect, item.index
        if mode == "move":
            start, track = self._moved_to(effect, dx, dy)
            if (start, track) != (effect.start_s, effect.track):
                self.editor.push(lambda: self.model.move(i, start, track))
        else:
            duration = self._resized_to(effect, dx)
            if duration != effect.duration_s:
                self.editor.push(lambda: self.model.resize(i, duration))
        self._layout()  # (a refused edit: the block goes back)

    def _moved_to(self, effect, dx: float, dy: float) -> tuple[float, int]:
        """Where a move by ``(dx, dy)`` scene pixels puts an effect: its start (snapped, not
        before 0) and track."""
        grid = self.model.grid_s
        start = effect.start_s + dx / self.pixels_per_s
        start = max(round(round(start / grid) * grid, 9) if grid > 0 else start, 0.0)
        track = min(max(effect.track + round(dy / TRACK_PX), 0), 999)
        return start, track

    def _resized_to(self, effect, dx: float) -> float:
        """One play's duration after the block's end moved by ``dx`` scene pixels (snapped,
        one grid step at least)."""
        grid = self.model.grid_s or 1e-3
        span = effect.end_s - effect.start_s + dx / self.pixels_per_s
        duration = span / effect.repeat
        return max(round(round(duration / grid) * grid, 9), grid)

    def _dragged(self, item, mode, dx, dy):
        effect = item.effect
        try:
            if mode == "move":
                start, track = self._moved_to(effect, dx, dy)
                return effect.replace(start_s=start, track=track)
            return effect.replace(duration_s=self._resized_to(effect, dx), envelope=())
        except ValueError:
            return None

    # --- the keys ------------------------------------------------------------------------------

    def focusNextPrevChild(self, forward: bool) -> bool:  # Qt override: Tab selects effects
        if self.editor.select_next(1 if forward else -1):
            return True
        return super().focusNextPrevChild(forward)  # past the last (first): on to the next field

    def keyPressEvent(self, event) -> None:  # Qt override
        key, mods = event.key(), event.modifiers()
        big = bool(mods & Mod.ShiftModifier)
        editor = self.editor
        if key == Key.Key_Space:
            editor.toggle_play()
        elif key in (Key.Key_Left, Key.Key_Right):
            sign = 1 if key == Key.Key_Right else -1
            if mods & Mod.ControlModifier:
                editor.select_next(sign)
            elif mods & Mod.AltModifier:
                editor.stretch(sign, big)
            else:
                editor.nudge(steps=sign, big=big)
        elif key in STRETCH_KEYS:  # as Alt+arrows, which some window managers take for their own
            editor.stretch(STRETCH_KEYS[key], big or key in (Key.Key_BraceRight, Key.Key_BraceLeft))
        elif key in (Key.Key_Up, Key.Key_Down):
            editor.nudge(tracks=-1 if key == Key.Key_Up else 1)
        elif key in (Key.Key_Delete, Key.Key_Backspace):
            editor.delete_selected()
        elif key == Key.Key_D and mods & Mod.ControlModifier:
            editor.duplicate_selected()
        elif key == Key.Key_Home:
            editor.seek(0.0)
        elif key == Key.Key_End:
            editor.seek(self.model.pattern.duration_s)
        else:
            super().keyPressEvent(event)
            return
        event.accept()
