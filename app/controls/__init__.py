"""The controls dock: widgets that write the scene to the state and show the state's values.

:class:`ControlsPanel` stacks six boxes, each listening to the state on its own: playback and
view, the method, the correction, the shape, the trace and its frames, and the preset's notes.
"""

from .correction import GAMMA_MAX, GAMMA_MIN, CorrectionWidget, gamma_to_slider, slider_to_gamma
from .method import METHOD_TIPS, MethodWidget
from .panel import ControlsPanel
from .playback import PlaybackWidget
from .preset import PresetWidget
from .shape import ShapeWidget
from .trace import TraceWidget

__all__ = [
    "GAMMA_MAX",
    "GAMMA_MIN",
    "METHOD_TIPS",
    "ControlsPanel",
    "CorrectionWidget",
    "MethodWidget",
    "PlaybackWidget",
    "PresetWidget",
    "ShapeWidget",
    "TraceWidget",
    "gamma_to_slider",
    "slider_to_gamma",
]
