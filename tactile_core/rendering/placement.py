"""What goes on a layout: which methods render on it and which one a scene gets, a shape that
fits it, and a path drawn round a wrap.

A device profile's actuators sit on a grid (the paper's palm array, a 3 x 3 grid) or anywhere
(:class:`~tactile_core.rendering.layout.Layout`: a belt, a sleeve, a vest panel). Coordinates are
layout units (pitches) either way. The command line, the scripting API, the OSC server and the
tuner all ask here, so a scene on a belt gets the same method wherever it is made.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ._grid import Grid
from ._targets import check_renders
from .layout import Layout
from .methods import method_names
from .shapes import Circle, Line, Square

FALLBACK = "BA"
"""The method a scene falls back to on a layout its method cannot render on: barycentric
weights, AS's weights generalised to actuators anywhere."""

SHAPE_METHOD = "IM"
"""The method a shape gets on a grid when none is chosen: the paper's interpolated midpoint, the
anti-aliased method with the fewest tactors lit."""

POINT_METHOD = "AS"
"""The method free points get on a grid when none is chosen: area sampling (MM and IM follow a
stroke, which a free point does not have)."""

LAYOUT_SETS = ("BA", "RO", "GS", "EN")
"""Compare's and Blind A/B's methods on a layout that is not a grid, when theirs cannot render
there: the smooth method and the peer methods of other systems."""

PALM = Grid()
PALM_SHAPES = {
    "line": Line((0.5, 1.84), (4.5, 4.16)),
    "circle": Circle((2.5, 3.0), 2.0),
    "square": Square((2.5, 3.5), 4.0),
}
"""The shape box's defaults on the paper's palm array (the Experiment 1 line)."""


def default_method(layout: Layout, *, free_points: bool = False) -> str:
    """The method a scene gets on ``layout`` when none is chosen.

    Parameters
    ----------
    layout : Layout
        Where it plays (a :class:`Grid` is one).
    free_points : bool
        For points another program or the user drives (no shape) rather than a traced shape.

    Returns
    -------
    str
        :data:`SHAPE_METHOD` (IM) for a shape on a grid, :data:`POINT_METHOD` (AS) for free
        points on a grid, :data:`FALLBACK` (BA) on a layout that is not a grid.

    Examples
    --------
    >>> default_method(Grid()), default_method(Grid(), free_points=True)
    ('IM', 'AS')
    """
    if not layout.is_grid:
        return FALLBACK
    return POINT_METHOD if free_points else SHAPE_METHOD


def refusal(method, layout: Layout) -> str:
    """Why ``method`` (a spec) cannot render on ``layout``, or "" when it can."""
    if layout.is_grid:
        return ""
    try:
        check_renders(method, layout)
    except ValueError as exc:
        return str(exc)
    return ""


def fallback_note(method: str, layout: Layout) -> str:
    """The status line when a scene's ``method`` plays BA instead on ``layout`` (the full
    reason is the method's tooltip)."""
    return (f"playing {FALLBACK} instead of {method}, which needs a grid (this layout: "
            f"{layout.describe()}; {', '.join(methods_for(layout))} render on it)")  # fmt: skip


def methods_for(layout: Layout) -> list[str]:
    """The registered methods that render on ``layout`` (all of them on a grid)."""
    return [name for name in method_names() if not refusal(name, layout)]


def restricted(methods, layout: Layout) -> tuple[list[str], list[str]]:
    """A method set for ``layout``: ``methods`` without those that cannot render there, made up
    from :data:`LAYOUT_SETS` to four when fewer than two are left; and the specs left out."""
    kept = [m for m in methods if not refusal(m, layout)]
    dropped = [m for m in methods if m not in kept]
    if len(kept) < 2:
        kept += [m for m in LAYOUT_SETS if m not in kept][: 4 - len(kept)]
    return kept, dropped


def restriction_note(dropped, methods, layout: Layout, doing: str) -> str:
    """What :func:`restricted` left out, for the note under a method set ("" for nothing)."""
    if not dropped:
        return ""
    return (f"{' '.join(dropped)} cannot render on this layout ({layout.describe()}): {doing} "
            f"{' '.join(methods)}; the paper's four need a grid")  # fmt: skip


def fits(shape, layout: Layout) -> bool:
    """Whether ``shape`` lies on ``layout``: its outline within the layout's extent (a grid's
    cells, or the actuators and half a pitch round them), a quarter of a pitch to spare; along
    a wrap anything fits."""
    if shape is None:
        return True
    x0, x1, y0, y1 = layout.bounds()
    pts = np.asarray(shape.outline(), dtype=float)
    inside = [(pts[:, 0] >= x0 - 0.25) & (pts[:, 0] <= x1 + 0.25),
              (pts[:, 1] >= y0 - 0.25) & (pts[:, 1] <= y1 + 0.25)]  # fmt: skip
    if layout.wrap is not None:
        inside[layout.wrap.index] = True
    return bool(np.all(inside[0] & inside[1]))


def shape_defaults(layout: Layout) -> dict:
    """A line, a circle and a square that fit ``layout``: the palm array's own on the palm
    array; round a wrap, the line goes once round (crossing the seam, from one end of the other
    axis to the other: a helix on a sleeve); elsewhere, centred on the actuators."""
    if layout == PALM:
        return dict(PALM_SHAPES)
    xy = layout.xy
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    centre = (lo + hi) / 2
    x0, x1, y0, y1 = layout.bounds()  # half a pitch round the actuators: never empty
    small = min(x1 - x0, y1 - y0)
    if layout.wrap is not None:
        c = layout.wrap.circumference
        if layout.wrap.axis == "x":
            line = Line((0.0, float(lo[1])), (c, float(hi[1])))
        else:
            line = Line((float(lo[0]), 0.0), (float(hi[0]), c))
    else:
        line = Line(tuple(map(float, lo)), tuple(map(float, hi)))
    point = tuple(map(float, centre))
    return {
        "line": line,
        "circle": Circle(point, round(0.4 * small, 3)),
        "square": Square(point, round(0.8 * small, 3)),
    }


def default_shape(layout: Layout):
    """The shape a scene gets on a layout its shape does not fit: the line (round a wrap) or
    the circle (elsewhere) of :func:`shape_defaults`."""
    shapes = shape_defaults(layout)
    if layout == PALM or layout.wrap is not None:
        return shapes["line"]
    xy = layout.xy
    flat = np.ptp(xy[:, 0]) == 0 or np.ptp(xy[:, 1]) == 0  # actuators in a row: the line
    return shapes["line"] if flat else shapes["circle"]


def unrolled(points, layout: Layout) -> tuple[np.ndarray, np.ndarray]:
    """A path ``(n, 2)`` as drawn on the unrolled strip of a wrapped layout: cut where it
    crosses the seam (a gap, NaN, between the two ends of the strip) and each piece taken into
    one turn ``[0, circumference]``. Unchanged on a layout without a wrap.

    Examples
    --------
    >>> from tactile_core.rendering.layout import Wrap
    >>> belt = Layout([(k, 0.0) for k in range(8)], wrap=Wrap("x", 8.0))
    >>> x, y = unrolled([(6.0, 0.0), (10.0, 0.0)], belt)
    >>> x.tolist()
    [6.0, 8.0, nan, 0.0, 2.0]
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if layout.wrap is None or len(pts) == 0:
        return pts[:, 0].copy(), pts[:, 1].copy()
    c, k = layout.wrap.circumference, layout.wrap.index
    pieces, piece = [], [pts[0]]
    for p, q in itertools.pairwise(pts):
        a, b = p[k], q[k]
        # the seams crossed: going up, in (a, b]; going down, in [b, a) (a point on a seam ends
        # the turn it comes from)
        if b > a:
            seams = np.arange(math.floor(a / c) + 1, math.floor(b / c) + 1) * c
        else:
            seams = np.arange(math.ceil(b / c), math.ceil(a / c))[::-1] * c
        for at in seams:
            cut = p + (q - p) * ((at - a) / (b - a))
            cut[k] = at  # exactly on the seam
            pieces.append([*piece, cut])
            piece = [cut]
        piece.append(q)
    pieces.append(piece)
    xs, ys = [], []
    for piece in pieces:
        arr = np.array(piece)
        if len(pieces) > 1 and np.ptp(arr, axis=0).max() == 0.0:
            continue  # the end of a path that stops on the seam: nothing to draw past it
        middle = (arr[:, k].min() + arr[:, k].max()) / 2
        arr[:, k] -= c * math.floor(middle / c)  # the turn this piece lies on
        if xs:
            xs.append(np.nan)
            ys.append(np.nan)
        xs += arr[:, 0].tolist()
        ys += arr[:, 1].tolist()
    return np.array(xs), np.array(ys)
