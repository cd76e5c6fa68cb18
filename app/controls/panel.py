"""The controls dock: the scene's boxes, one above the other."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

from tactile_core.rendering.methods import PAPER_METHODS

from ..state import TunerState
from ..widgets import guard_wheel
from .correction import CorrectionWidget
from .method import MethodWidget
from .playback import PlaybackWidget
from .preset import PresetWidget
from .shape import ShapeWidget
from .trace import TraceWidget


class ControlsPanel(QtWidgets.QWidget):
    """Widgets that write to :class:`TunerState` and follow it, in five boxes.

    Attributes
    ----------
    playback : PlaybackWidget
        Play/pause, restart, all off, the view mode, values in cells, draw mode.
    method : MethodWidget
        The method (keys 1-4, the others, a parameter).
    correction : CorrectionWidget
        mu and gamma, on drive or on felt amplitude; motor-aware drive.
    shape : ShapeWidget
        The shape and its coordinates.
    trace : TraceWidget
        Timing and frames.
    preset : PresetWidget
        The preset's name and notes.
    """

    draw_mode_toggled = QtCore.Signal(bool)
    all_off_requested = QtCore.Signal()

    def __init__(self, state: TunerState, parent=None):
        super().__init__(parent)
        self.state = state
        layout = QtWidgets.QVBoxLayout(self)
        self.playback = PlaybackWidget(state)
        self.method = MethodWidget(state)
        self.correction = CorrectionWidget(state)
        self.shape = ShapeWidget(state)
        self.trace = TraceWidget(state)
        self.preset = PresetWidget()
        for box in (self.playback, self.method, self.correction, self.shape, self.trace,
                    self.preset):  # fmt: skip
            layout.addWidget(box)
        layout.addStretch(1)
        guard_wheel(self)  # the dock scrolls under the wheel; a value changes once clicked
        self.playback.draw_mode_toggled.connect(self.draw_mode_toggled)
        self.playback.all_off_requested.connect(self.all_off_requested)

    def method_names(self) -> list[str]:
        """The methods of the number keys, in key order (key 1 first): the paper's four."""
        return list(PAPER_METHODS)

    def set_felt_available(self, available: bool) -> None:
        """'felt' (the view and the correction's domain) needs the device profile's motor
        response curve; without one the view falls back to 'sent'."""
        self.playback.set_felt_available(available)
        if not available and self.state.view_mode == "felt":
            self.state.set_view_mode("sent")
        self.correction.set_felt_available(available)

    def set_profile(self, profile) -> None:
        """What the device profile knows of its motors: their response curve (the 'felt'
        view and domain), their time constants (motor-aware drive)."""
        self.set_felt_available(profile.response is not None)
        motors = profile.motor.describe() if profile.motor is not None else ""
        self.correction.set_motor_available(profile.motor is not None, motors)

    def set_draw_mode(self, on: bool) -> None:
        """Reflect draw mode: MM and IM are unavailable on free points, the shape is not
        edited."""
        self.method.set_draw_mode(on)
        self.shape.set_draw_mode(on)
        self.playback.set_draw_mode(on)

    def set_method_hidden(self, hidden: bool) -> None:
        """Blind A/B testing: hide which method is selected (and its parameter)."""
        self.method.set_method_hidden(hidden)
