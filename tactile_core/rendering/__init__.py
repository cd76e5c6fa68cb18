"""Rendering: from a shape to the intensities of the tactors, frame by frame.

The data flow of the paper, one module per step::

    shapes (f(t)) -> trace (time -> t) -> methods (CT, MM, AS, IM, peers) -> correction (mu, gamma)
                  -> quantisation (device levels)

``geometry`` holds the grid, ``rasterize`` evaluates a method at many points (batch) or one
(the live path), ``scene`` bundles everything that decides a frame into one immutable snapshot,
``curves`` gives the activation curves of the paper's Figures 3 and 4 and ``percept`` predicts
what a method feels like. numpy only; nothing here knows of devices, files or Qt.
"""

from .correction import Dither, correct, quantize
from .curves import ActivationCurves, activation_curves
from .geometry import PALM_ARRAY, ArraySpec, Grid
from .methods import METHOD_NAMES, METHODS, get_method
from .percept import Percept, felt_magnitude, predict
from .rasterize import render, render_point, render_xy
from .scene import PAPER_PIPELINE, Pipeline, Scene
from .shapes import Circle, Line, Polyline, Shape, Square, parse_shape, shape_from_dict
from .trace import LiveFrames, Sampling, Trace, render_frames

__all__ = [
    "METHODS",
    "METHOD_NAMES",
    "PALM_ARRAY",
    "PAPER_PIPELINE",
    "ActivationCurves",
    "ArraySpec",
    "Circle",
    "Dither",
    "Grid",
    "Line",
    "LiveFrames",
    "Percept",
    "Pipeline",
    "Polyline",
    "Sampling",
    "Scene",
    "Shape",
    "Square",
    "Trace",
    "activation_curves",
    "correct",
    "felt_magnitude",
    "get_method",
    "parse_shape",
    "predict",
    "quantize",
    "render",
    "render_frames",
    "render_point",
    "render_xy",
    "shape_from_dict",
]
