"""The shape: line, circle or square, and its coordinates in grid units; for an imported
``.tact`` pattern, what it plays and bHaptics' play-time options (scale and rotation)."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

import tactile_core as tc
from tactile_core.files.pattern import Pattern, PatternCue
from tactile_core.files.tact import TactPattern
from tactile_core.rendering import placement

from ..texts import count, tip
from ._common import SceneGroupWidget, spin_box

SHAPES = ("line", "circle", "square")
FIELDS = {
    "line": ("x0", "y0", "x1", "y1"),
    "circle": ("centre x", "centre y", "radius"),
    "square": ("centre x", "centre y", "edge"),
}


class ShapeWidget(SceneGroupWidget):
    """A drop-down of the shapes and, per shape, a page of its coordinates."""

    def __init__(self, state, parent=None):
        super().__init__("Shape (grid units)", state, parent)
        v = QtWidgets.QVBoxLayout(self)
        self.shape_combo = QtWidgets.QComboBox()
        self.shape_combo.addItems([s.capitalize() for s in SHAPES])
        v.addWidget(self.shape_combo)
        self.shape_stack = QtWidgets.QStackedWidget()
        self.shape_fields = {}
        for kind in SHAPES:
            page = QtWidgets.QWidget()
            form = QtWidgets.QFormLayout(page)
            form.setContentsMargins(0, 0, 0, 0)
            fields = []
            for label in FIELDS[kind]:
                lo = 0.0 if label in ("radius", "edge") else -10.0
                spin = spin_box(lo, 20.0, 0.05, 3)
                spin.setToolTip(tip(
                    f"{label} in grid units (paper 2.1): 1 unit = one tactor pitch (18 mm on the "
                    "palm array); tactors sit at the cells' centres, x + 0.5, y + 0.5"
                ))  # fmt: skip
                spin.valueChanged.connect(self._on_shape_fields_changed)
                form.addRow(label, spin)
                fields.append(spin)
            self.shape_fields[kind] = fields
            self.shape_stack.addWidget(page)
        # What the scene plays when it is none of the shapes (a path or a .tact pattern): shown,
        # not chosen (picking a shape above replaces it)
        self.shape_combo.addItem("Other")
        self.shape_combo.model().item(len(SHAPES)).setEnabled(False)
        self.other_label = QtWidgets.QLabel()
        self.other_label.setObjectName("other-content")
        self.other_label.setWordWrap(True)
        self.other_label.setTextFormat(QtCore.Qt.TextFormat.PlainText)  # a file's name, as is
        self.other_label.setAlignment(QtCore.Qt.AlignmentFlag.AlignTop)
        other = QtWidgets.QWidget()
        column = QtWidgets.QVBoxLayout(other)
        column.setContentsMargins(0, 0, 0, 0)
        column.addWidget(self.other_label)
        self.tact_options = self._tact_options_box()
        column.addWidget(self.tact_options)
        column.addStretch(1)
        self.shape_stack.addWidget(other)
        self.shape_combo.currentIndexChanged.connect(self._on_shape_combo_changed)
        v.addWidget(self.shape_stack)
        state.scene_changed.connect(self.refresh)
        state.layout_changed.connect(self._on_state_layout_changed)
        self._on_state_layout_changed(state.layout)
        self.refresh()

    def _tact_options_box(self) -> QtWidgets.QGroupBox:
        """bHaptics' ScaleOption and RotationOption for an imported pattern (docs/tact.md)."""
        box = QtWidgets.QGroupBox("bHaptics options")
        box.setObjectName("tact-options")
        form = QtWidgets.QFormLayout(box)
        self.tact_fields = {
            "intensity": spin_box(0.0, 10.0, 0.1, 2, " x"),
            "duration": spin_box(0.05, 10.0, 0.1, 2, " x"),
            "angle": spin_box(-360.0, 360.0, 15.0, 1, " deg"),
            "offset": spin_box(-1.0, 1.0, 0.05, 2),
        }
        tips = {
            "intensity": "ScaleOption intensity: every intensity of the file times this",
            "duration": "ScaleOption duration: every time of the file times this (2 = half as "
            "fast)",
            "angle": "RotationOption angle round the body (vest files): 90 turns the pattern a "
            "quarter turn to the wearer's left, 180 swaps front and back",
            "offset": "RotationOption vertical offset (vest files), in panel heights: 0.25 moves "
            "the pattern a quarter of the panel up",
        }
        labels = {"intensity": "intensity", "duration": "duration", "angle": "rotation",
                  "offset": "offset up"}  # fmt: skip
        for key, field in self.tact_fields.items():
            field.setToolTip(tip(tips[key]))
            field.valueChanged.connect(self._on_tact_options_changed)
            form.addRow(labels[key], field)
        return box

    def _on_tact_options_changed(self, _value=None) -> None:
        source = self.state.scene.source
        if self._updating or not isinstance(source, TactPattern):
            return
        f = {key: field.value() for key, field in self.tact_fields.items()}
        try:
            scale, rotation = (f["intensity"], f["duration"]), (f["angle"], f["offset"])
            position = source.position if source.named else None
            pattern = TactPattern(source.file, position, scale, rotation)
        except ValueError as exc:
            self.state.error_raised.emit(str(exc))
            return
        self.state.update(source=pattern, epoch=self.state.scene.epoch + 1, playing=True)

    def _on_state_layout_changed(self, layout) -> None:
        grid = layout.is_grid
        self.setTitle("Shape (grid units)" if grid else "Shape (layout units: pitches)")
        if layout.wrap is not None:
            self.setToolTip(tip(
                f"{layout.wrap.axis} wraps round at {layout.wrap.circumference:g}: a shape may "
                "cross the seam, and coordinates past it come back on the other side"
            ))  # fmt: skip
        else:
            self.setToolTip("")

    def _on_shape_combo_changed(self, index: int) -> None:
        if self._updating or index >= len(SHAPES):
            return
        kind = SHAPES[index]
        scene = self.state.scene
        # Defaults that fit the layout (the paper's on the palm array).
        defaults = placement.shape_defaults(self.state.layout)
        if (
            scene.shape is None
            or scene.source is not None
            or type(scene.shape).__name__.lower() != kind
        ):
            self.state.update(shape=defaults[kind])

    def _on_shape_fields_changed(self, _value=None) -> None:
        if self._updating or self.shape_combo.currentIndex() >= len(SHAPES):
            return
        kind = SHAPES[self.shape_combo.currentIndex()]
        values = [f.value() for f in self.shape_fields[kind]]
        try:
            if kind == "line":
                shape = tc.Line(values[0:2], values[2:4])
            elif kind == "circle":
                shape = tc.Circle(values[0:2], values[2])
            else:
                shape = tc.Square(values[0:2], values[2])
        except ValueError as exc:
            self.state.error_raised.emit(str(exc))
            return
        self.state.update(shape=shape)

    def set_draw_mode(self, on: bool) -> None:
        """A free point has no shape to edit while draw mode is on."""
        self.shape_combo.setEnabled(not on)
        self.shape_stack.setEnabled(not on)

    def _show(self, scene) -> None:
        shape = scene.shape
        kind = type(shape).__name__.lower()
        if kind not in SHAPES:
            self.shape_combo.setCurrentIndex(len(SHAPES))
            self.shape_stack.setCurrentIndex(len(SHAPES))
            self.other_label.setText(describe_content(scene, self.state.layout))
            source = scene.source
            self.tact_options.setVisible(isinstance(source, TactPattern))
            if isinstance(source, TactPattern):
                values = {
                    "intensity": source.scale.intensity,
                    "duration": source.scale.duration,
                    "angle": source.rotation.angle_deg,
                    "offset": source.rotation.offset_y,
                }
                for key, field in self.tact_fields.items():
                    field.setValue(values[key])
            return
        self.shape_combo.setCurrentIndex(SHAPES.index(kind))
        self.shape_stack.setCurrentIndex(SHAPES.index(kind))
        if kind == "line":
            values = (*shape.p0, *shape.p1)
        elif kind == "circle":
            values = (*shape.center, shape.radius)
        else:
            values = (*shape.center, shape.edge)
        for field, value in zip(self.shape_fields[kind], values):
            field.setValue(value)


def describe_content(scene, target) -> str:
    """What a scene plays when it is not a line, circle or square, in words."""
    shape, source = scene.shape, scene.source
    pick = " Pick a shape above to replace it."
    if shape is not None:
        points = len(getattr(shape, "points", ()))
        if isinstance(shape, tc.TimedPath):
            return (f"A time-keyed path of {points} points over {shape.duration_s:g} s "
                    f"(drawn or imported).{pick}")  # fmt: skip
        return f"A {type(shape).__name__.lower()} of {points} points.{pick}"
    if isinstance(source, PatternCue):  # a pattern from a moment of it (the editor's)
        source = source.pattern
    if isinstance(source, Pattern):  # a pattern file
        effects, tracks = count(len(source.effects), "effect"), count(len(source.tracks), "track")
        return (f"The pattern {source.name or 'untitled'}: {effects} on {tracks} over "
                f"{source.duration_s:g} s.{pick}")  # fmt: skip
    if isinstance(source, TactPattern):
        paths, dots = len(source.paths(target)), len(source.dots(target))
        return (f"The .tact pattern {source.name or 'untitled'}, {source.describe(target)}: "
                f"{count(paths, 'path')} and {count(dots, 'dot')} over "
                f"{source.duration_on(target):g} s.{pick}")  # fmt: skip
    if source is not None:
        return "Free points sent by another program (OSC or a script)."
    return "Nothing: the array is off."
