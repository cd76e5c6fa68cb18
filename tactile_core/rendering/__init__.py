"""Rendering: from a shape to the intensities of the tactors, frame by frame.

The data flow of the paper, one module per step::

    shapes (f(t)) -> trace (time -> t) -> methods (CT, MM, AS, IM, peers) -> correction (mu, gamma)
                  -> quantisation (device levels)

``geometry`` holds the grid, ``rasterize`` evaluates a method at many points (batch) or one
(the live path), ``scene`` bundles everything that decides a frame into one immutable snapshot,
``curves`` gives the activation curves of the paper's Figures 3 and 4, ``motor`` the motors'
first-order lag, ``percept`` predicts what a method feels like for a range of participants and
``jumps`` measures how abruptly a method switches a tactor. numpy only; nothing here knows of
devices, files or Qt (a device profile hands its motor model in as a value).
"""

from .correction import Dither, correct, quantize
from .curves import ActivationCurves, activation_curves
from .geometry import PALM_ARRAY, ArraySpec, Grid
from .jumps import largest_jump
from .methods import METHOD_NAMES, METHODS, get_method
from .motor import MotorResponse
from .percept import Participant, Percept, felt_magnitude, participant_grid, predict, predict_range
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
    "MotorResponse",
    "Participant",
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
    "largest_jump",
    "parse_shape",
    "participant_grid",
    "predict",
    "predict_range",
    "quantize",
    "render",
    "render_frames",
    "render_point",
    "render_xy",
    "shape_from_dict",
]
