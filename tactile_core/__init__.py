"""tactile_core: rendering of moving points on low-resolution 2D vibrotactile arrays.

Implements the four rendering methods of "Bi-level and Anti-aliased Rendering Methods for a
Low-Resolution 2D Vibrotactile Array" (closest tactor, midpoint, area sampling, interpolated
midpoint), the threshold/gamma correction, quantisation to device levels, the trace clock, and
the data of the activation curves. numpy only: no Qt is imported here.

The package is layered; each layer imports only those above it in this list::

    _shared      argument checks, atomic files, bounded JSON, bundled assets
    rendering    geometry, shapes, methods, correction, trace, scene, curves, percept
    device       profiles, wire format, links, streamer, emulator, recorder
    live         driven by other programs: the OSC server, LSL outlets
    files        presets, exports
    experiments  the paper's three experiments, analysis, tuning the correction by feel
    bench, cli   the ``tactile`` command and its benchmarks; ``script`` (``tc.open_array``)

``tc.Pattern`` (with ``tc.Effect``, ``tc.Dots``, ``tc.Dot``) composes effects on a time line
(:mod:`tactile_core.files.pattern`); like ``tc.open_array`` it is imported when first used.

``docs/architecture.md`` draws the layers and the one-way flow of a frame.

>>> import numpy as np
>>> import tactile_core as tc
>>> frames = tc.render(tc.Line((0.5, 1.84), (4.5, 4.16)), "AS", np.linspace(0, 1, 5))
>>> frames.shape
(5, 6, 5)
"""

from ._version import __version__
from .experiments import ORDERS, Staircase, pairwise_wilcoxon
from .rendering.correction import correct, quantize
from .rendering.geometry import PALM_ARRAY, ArraySpec, Grid
from .rendering.methods import METHOD_NAMES, METHODS, get_method
from .rendering.rasterize import render, render_point, render_xy
from .rendering.shapes import (
    Circle,
    Line,
    Polyline,
    Shape,
    Square,
    TimedPath,
    parse_shape,
    shape_from_dict,
)
from .rendering.trace import LiveFrames, Sampling, Trace, render_frames

__all__ = [
    "METHODS",
    "METHOD_NAMES",
    "ORDERS",
    "PALM_ARRAY",
    "ArraySpec",
    "Circle",
    "Dot",
    "Dots",
    "Effect",
    "Grid",
    "Line",
    "LiveFrames",
    "Pattern",
    "Polyline",
    "Sampling",
    "Shape",
    "Square",
    "Staircase",
    "TimedPath",
    "Trace",
    "__version__",
    "correct",
    "get_method",
    "open_array",
    "pairwise_wilcoxon",
    "parse_shape",
    "quantize",
    "render",
    "render_frames",
    "render_point",
    "render_xy",
    "shape_from_dict",
]


_PATTERNS = ("Dot", "Dots", "Effect", "Pattern")
"""Patterns (:mod:`tactile_core.files.pattern`), imported when first asked for."""


def __getattr__(name: str):
    if name == "open_array":  # the scripting API, imported when first asked for
        from .script import open_array

        return open_array
    if name in _PATTERNS:
        from .files import pattern

        return getattr(pattern, name)
    raise AttributeError(f"module 'tactile_core' has no attribute {name!r}")
