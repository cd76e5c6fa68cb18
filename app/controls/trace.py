"""The trace and its frames: timing, frame rate, filter, dithering, emphasis and intensity."""

from __future__ import annotations

from PySide6 import QtWidgets

import tactile_core as tc

from ..texts import tip
from ._common import SceneGroupWidget, spin_box

DURATION_RANGE_S = (0.1, 60.0)
"""What the duration box sets (a pattern's own duration is shown whatever it is)."""
OWN_TIMING = (
    "The pattern sets its own timing (each effect's start, duration and repeats): duration, "
    "pause, direction and corner emphasis are a shape's trace. Pick a shape to set them."
)
DIRECTIONS = ("forward", "reverse")
TURNS = (" (counter-clockwise)", " (clockwise)")
"""Which way forward and reverse turn, said for the shapes that turn one way (a circle, a
square); a line or a path has no turn to name."""


def direction_texts(shape) -> list[str]:
    """The direction box's items for ``shape``: ``forward (counter-clockwise)`` for a circle or
    a square, plain ``forward`` for any other shape (or a pattern, None)."""
    turns = isinstance(shape, (tc.Circle, tc.Square))
    return [d + (t if turns else "") for d, t in zip(DIRECTIONS, TURNS)]


class TraceWidget(SceneGroupWidget):
    """How the point runs along the shape (duration, pause, direction, corner emphasis) and how
    its frames are made (rate, filter, sub-samples, dithering, master intensity)."""

    def __init__(self, state, parent=None):
        super().__init__("Trace and frames", state, parent)
        form = QtWidgets.QFormLayout(self)
        self.duration_spin = spin_box(*DURATION_RANGE_S, 0.1, 2, " s")
        self.pause_spin = spin_box(0.0, 30.0, 0.1, 2, " s")
        self.direction_combo = QtWidgets.QComboBox()
        self.direction_combo.addItems(direction_texts(state.scene.shape))
        self.rate_spin = spin_box(10.0, 1000.0, 10.0, 0, " Hz")
        self.filter_combo = QtWidgets.QComboBox()
        self.filter_combo.addItems(["point", "box"])
        self.subsamples_spin = QtWidgets.QSpinBox()
        self.subsamples_spin.setRange(1, 64)
        self.subsamples_spin.setKeyboardTracking(False)
        self.dither_check = QtWidgets.QCheckBox("temporal dithering")
        tips = {
            self.duration_spin: "Trace duration in seconds, t from 0 to 1 (paper 3.4.2: 2 s).",
            self.pause_spin: "Seconds off between traces (paper 3.4.2 and 3.4.3: 0.5 s; "
            "Experiment 3 retraces continuously: 0).",
            self.direction_combo: "Forward follows f(t): counter-clockwise for circles and "
            "squares (paper 3.4.2, 3.4.4); reverse runs t from 1 to 0.",
            self.rate_spin: "Frames a second sent to the array, 10-1000 Hz (capped at what the "
            "link carries: 311 at 115200 baud). Not the PWM carrier, about 300 Hz on the "
            "paper's array (3.3).",
            self.filter_combo: "point: each frame is the trace at the middle of its interval "
            "(the paper's pipeline). box: the average of S sub-samples over the interval.",
            self.subsamples_spin: "Sub-samples S of the box filter, 1-64.",
            self.dither_check: "Error feedback per tactor, so averages finer than the device's "
            "23 levels go out; off: plain rounding (the paper's pipeline).",
        }
        self.emphasis_spin = spin_box(0.0, 0.9, 0.1, 2)
        tips[self.emphasis_spin] = (
            "Corner emphasis 0-0.9 (beyond the paper; its 4.3 suggests it): the point slows near "
            "corners; 0.5 doubles the dwell; 0 = constant speed"
        )
        for widget, text in tips.items():
            widget.setToolTip(tip(text))
        self._timing_tips = {
            w: tips[w]
            for w in (self.duration_spin, self.pause_spin, self.direction_combo, self.emphasis_spin)
        }
        """The trace's timing boxes and their tooltips: a pattern's own timing replaces them."""
        self.gain_spin = spin_box(0.0, 1.0, 0.05, 2)
        self.gain_spin.setToolTip(tip(
            "Master intensity 0-1 (beyond the paper): scales the part above the threshold, "
            "mu + gain (1 - mu) I^gamma, so no lit tactor drops below mu"
        ))  # fmt: skip
        form.addRow("duration", self.duration_spin)
        form.addRow("pause", self.pause_spin)
        form.addRow("direction", self.direction_combo)
        form.addRow("frame rate", self.rate_spin)
        form.addRow("filter", self.filter_combo)
        form.addRow("box sub-samples", self.subsamples_spin)
        form.addRow("", self.dither_check)
        form.addRow("corner emphasis", self.emphasis_spin)
        form.addRow("master intensity", self.gain_spin)
        self.duration_spin.valueChanged.connect(lambda v: self._set(duration_s=v))
        self.pause_spin.valueChanged.connect(lambda v: self._set(pause_s=v))
        self.direction_combo.currentIndexChanged.connect(
            lambda i: self._set(direction=DIRECTIONS[i])
        )
        self.rate_spin.valueChanged.connect(lambda v: self._set(rate_hz=v))
        self.filter_combo.currentTextChanged.connect(lambda t: self._set(filter=t))
        self.subsamples_spin.valueChanged.connect(lambda v: self._set(subsamples=v))
        self.dither_check.toggled.connect(lambda on: self._set(dither=on))
        self.emphasis_spin.valueChanged.connect(lambda v: self._set(emphasis=v))
        self.gain_spin.valueChanged.connect(lambda v: self._set(gain=v))
        state.scene_changed.connect(self.refresh)
        self.refresh()

    def _show(self, scene) -> None:
        own = scene.source is not None and hasattr(scene.source, "duration_on")
        for widget, text in self._timing_tips.items():  # a pattern: its own timing, not these
            widget.setEnabled(not own)
            widget.setToolTip(tip(OWN_TIMING if own else text))
        if own:
            duration_s = scene.source.duration_on(self.state.layout)
            lo, hi = DURATION_RANGE_S
            self.duration_spin.setRange(min(lo, duration_s), max(hi, duration_s))
            self.duration_spin.setValue(duration_s)
        else:
            self.duration_spin.setRange(*DURATION_RANGE_S)
            self.duration_spin.setValue(scene.duration_s)
        self.pause_spin.setValue(scene.pause_s)
        for i, text in enumerate(direction_texts(scene.shape)):
            self.direction_combo.setItemText(i, text)
        self.direction_combo.setCurrentIndex(0 if scene.direction == "forward" else 1)
        self.rate_spin.setValue(scene.rate_hz)
        self.filter_combo.setCurrentText(scene.filter)
        self.subsamples_spin.setValue(scene.subsamples)
        self.subsamples_spin.setEnabled(scene.filter == "box")
        self.dither_check.setChecked(scene.dither)
        self.emphasis_spin.setValue(scene.emphasis)
        self.gain_spin.setValue(scene.gain)
