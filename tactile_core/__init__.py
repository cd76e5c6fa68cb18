"""tactile_core: rendering of moving points on low-resolution 2D vibrotactile arrays.

Implements the four rendering methods of "Bi-level and Anti-aliased Rendering Methods for a
Low-Resolution 2D Vibrotactile Array" (closest tactor, midpoint, area sampling, interpolated
midpoint), the threshold/gamma correction, quantisation to device levels, the trace clock, and
the data of the activation curves. numpy only: no Qt is imported here.

>>> import numpy as np
>>> import tactile_core as tc
>>> frames = tc.render(tc.Line((0.5, 1.84), (4.5, 4.16)), "AS", np.linspace(0, 1, 5))
>>> frames.shape
(5, 6, 5)
"""

from ._version import __version__
from .correction import correct, quantize
from .experiments import ORDERS, Staircase, pairwise_wilcoxon
from .geometry import PALM_ARRAY, ArraySpec, Grid
from .methods import METHOD_NAMES, METHODS, get_method
from .render import render, render_point, render_xy
from .shapes import Circle, Line, Polyline, Shape, Square, parse_shape, shape_from_dict
from .trace import LiveFrames, Sampling, Trace, render_frames

__all__ = [
    "METHODS",
    "METHOD_NAMES",
    "ORDERS",
    "PALM_ARRAY",
    "ArraySpec",
    "Circle",
    "Grid",
    "Line",
    "LiveFrames",
    "Polyline",
    "Sampling",
    "Shape",
    "Square",
    "Staircase",
    "Trace",
    "__version__",
    "correct",
    "get_method",
    "pairwise_wilcoxon",
    "parse_shape",
    "quantize",
    "render",
    "render_frames",
    "render_point",
    "render_xy",
    "shape_from_dict",
]
