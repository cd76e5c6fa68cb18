"""Barycentric method (BA): this project's smooth method for actuators anywhere.

On any layout (:class:`~tactile_core.rendering.layout.Layout`) the point's weights are its
barycentric coordinates in the Delaunay triangle of actuators that holds it, bilinear in a
rectangle of four actuators (where the triangulation is not unique), linear between neighbours
of a collinear layout (a belt); beyond the actuators' hull the weights of the nearest boundary
point fade out over one pitch (:mod:`._tessellation`). The weights sum to 1 inside the hull and
change continuously everywhere, also across a wrap's seam.

On a grid those rules give exactly AS's area weights (paper 2.4) everywhere, the edge falloff
included, so on a grid BA renders with AS's samplers; the tests check that the layout path
computes the same numbers from the tessellation of the grid's tactor centres. BA is driven with
the set correction, as AS is.
"""

from __future__ import annotations

from .area import sample, sample1, sample_cells

NAME = "BA"
TITLE = "barycentric, any layout (AS on a grid)"
BILEVEL = False
NEEDS_SHAPE = False
MAX_TACTORS = 4

__all__ = ["MAX_TACTORS", "NAME", "TITLE", "sample", "sample1", "sample_cells"]
