"""The Tune tab: the live heatmap, the activation curves and the correction curve.

:class:`TuneWidget` lays the views out and redraws the scene's plots; :class:`FrameDisplay`
shows the array's current frame at about 60 Hz; :class:`HeatmapGestures` turns clicks and drags
on the plots into scenes (pulse a tactor, draw a free point, scrub the trace).
"""

from .display import DISPLAY_HZ, FrameDisplay
from .gestures import HeatmapGestures
from .widget import TuneWidget

__all__ = ["DISPLAY_HZ", "FrameDisplay", "HeatmapGestures", "TuneWidget"]
