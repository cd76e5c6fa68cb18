"""Interpolated-midpoint method (IM), paper section 2.5: MM's tactors, interpolated.

On a stroke with major axis x, the point's x lies between the column centres
``x_k = floor(x - 0.5) + 0.5`` and ``x_k + 1``. MM's tactor of column ``k`` gets intensity
``x_k+1 - x`` and MM's tactor of column ``k + 1`` gets the rest, so intensities move linearly
along the major axis and always sum to 1 (y-major strokes likewise, axes swapped). Between a
line's end and the centre of its end column the end tactor holds 1 (there is no column beyond
to share with).

**Hand-overs between strokes.** The paper states the rule between two column centres of one
stroke. A shape of several strokes (a circle's four octant arcs, a square's edges, a polygon's
sides) also needs a rule where one stroke hands over to the next; applying the stroke rule up to
the junction makes IM jump there (on the Experiment 3 circle a tactor went 1 -> 0 and its
neighbour 0 -> 1 at each 45-degree point). Along the trace, IM therefore has *keyframes*, moments
where one of MM's tactors has everything:

- each tactor centre a stroke passes on its major axis: MM's tactor of that column (row);
- a junction whose column (row) has no centre on the stroke before or after it (a *partial*
  column, e.g. a square's corner between tactor centres): MM's tactor of that partial column,
  which is the tactor of the cell containing the junction.

Between two keyframes of one stroke the paper's rule applies. Across a junction, from the
outgoing stroke's last keyframe to the incoming stroke's first, intensity moves linearly in
``t`` (proportional to arc length for every shape here) from one keyframe's tactor to the
next's. So IM is continuous along every shape, its tactors are MM's, at most two are lit, and
raw intensities sum to 1. A shape of zero length lights the cell of its point, as MM does.
"""

from __future__ import annotations

import bisect
import itertools
import math

import numpy as np

from ..geometry import SNAP_REL, Pieces, cell_floor, cell_split, cell_split1, clamp
from ._cells import PAIR, ZIP, Cells, CellTable, Indexed, stack_points
from .midpoint import lookup, on_stroke, tactor_of_cell, to_cells

NAME = "IM"
TITLE = "interpolated midpoint"
BILEVEL = False
NEEDS_SHAPE = True
MAX_TACTORS = 2

_T_TOL = SNAP_REL
"""Snap tolerance for positions measured in ``t`` (within [0, 1]): 64 ulps of 1."""


class Keyframes:
    """IM's keyframes of one shape and the hand-over segments between them.

    Parameters
    ----------
    keyframes : list of (t, (col, row), runs)
        In trace order, ``t`` in [0, 1]; ``runs`` is the set of strokes (indices into the
        shape's runs) the keyframe lies on as a centre or an open end (empty for a junction).
    closed : bool
        Wrap around: the segment after the last keyframe leads to the first.

    Attributes
    ----------
    t : ndarray of float64, shape (n,)
        Keyframe parameters, ascending; a closed shape's table starts with its last keyframe
        minus 1 and ends with its first plus 1, so every ``t`` in [0, 1] has a segment.
    cols, rows : ndarray of float64, shape (n,)
        Each keyframe's tactor.
    handover : ndarray of bool, shape (n - 1,)
        True for a segment across a junction (linear in ``t``), False within one stroke (the
        paper's rule).
    """

    def __init__(self, keyframes: list, closed: bool):
        if closed:
            (t_last, cell_last, runs_last), (t_first, cell_first, runs_first) = (
                keyframes[-1],
                keyframes[0],
            )
            keyframes = [
                (t_last - 1.0, cell_last, runs_last),
                *keyframes,
                (t_first + 1.0, cell_first, runs_first),
            ]
        self.t = np.array([k[0] for k in keyframes])
        self.cols = np.array([float(k[1][0]) for k in keyframes])
        self.rows = np.array([float(k[1][1]) for k in keyframes])
        self.handover = np.array([not (k0[2] & k1[2]) for k0, k1 in itertools.pairwise(keyframes)])
        self.any_handover = bool(self.handover.any())
        # Per segment: its start, its end and its width, gathered in one take.
        self._segments = np.stack([self.t[:-1], self.t[1:], self.t[1:] - self.t[:-1]])
        self._steps = bool((self._segments[2] > 0.0).all())
        self._pieces = Pieces(self.t, len(self.handover) - 1)
        self._t1 = self.t.tolist()
        self._cells1 = [k[1] for k in keyframes]
        self._handover1 = self.handover.tolist()

    def segment(self, t):
        """Segment index of each ``t`` (array) and its share ``w`` of the later keyframe."""
        j = self._pieces.of(t)
        t0, t1, width = self._segments.take(j, axis=1)
        d0 = np.subtract(t, t0, out=t0)
        if self._steps:  # every segment has a length (always, once keyframes are merged)
            w = d0 / width
        else:
            with np.errstate(divide="ignore", invalid="ignore"):
                w = np.where(width > 0.0, d0 / width, 0.0)
        # Within _T_TOL of the segment's end w is 1, of its start 0. (Before the start or past
        # the end, which the segment's choice rules out, the clip below gives the same.)
        t1 -= t
        np.putmask(w, t1 <= _T_TOL, 1.0)
        np.putmask(w, d0 <= _T_TOL, 0.0)
        np.maximum(w, 0.0, out=w)
        return j, np.minimum(w, 1.0, out=w)

    def handover1(self, t: float) -> tuple | None:
        """Scalar: the lit ``(col, row, value)`` if ``t`` is in a hand-over, else None."""
        j = min(max(bisect.bisect_right(self._t1, t) - 1, 0), len(self._handover1) - 1)
        if not self._handover1[j]:
            return None
        t0, t1 = self._t1[j], self._t1[j + 1]
        if abs(t - t0) <= _T_TOL or t1 <= t0:
            w = 0.0
        elif abs(t1 - t) <= _T_TOL:
            w = 1.0
        else:
            w = min(max((t - t0) / (t1 - t0), 0.0), 1.0)
        (c0, r0), (c1, r1) = self._cells1[j], self._cells1[j + 1]
        if (c0, r0) == (c1, r1):
            return ((c0, r0, 1.0),)
        return tuple((c, r, v) for c, r, v in ((c0, r0, 1.0 - w), (c1, r1, w)) if v > 0.0)


def _mm_cell(strokes, stroke: int, major: int) -> tuple[int, int]:
    """``(col, row)`` of MM's tactor of major cell ``major`` of stroke ``stroke``."""
    params = strokes.rows1[stroke]
    minor = tactor_of_cell(strokes, params, float(major))
    col, row = to_cells(params[0] == 0, major, int(minor))
    return int(col), int(row)


def build_keyframes(shape) -> Keyframes | None:
    """IM's keyframes of ``shape``, or None when it has no hand-over between strokes."""
    strokes = shape.strokes
    runs = strokes.runs()
    tol = strokes.tol
    if len(runs) < 2 or all(r.u_in == r.u_out for r in runs):
        return None  # one stroke (the paper's rule alone), or a point
    keyframes = []  # (t, cell, runs)
    partial_in, partial_out = [], []
    for index, run in enumerate(runs):
        lo, hi = min(run.u_in, run.u_out) - tol, max(run.u_in, run.u_out) + tol
        # Only the stroke's first and last centres matter: between them the paper's rule
        # applies, whatever the stroke's length.
        c_lo, c_hi = math.ceil(lo - 0.5) + 0.5, math.floor(hi - 0.5) + 0.5
        if c_lo <= c_hi:
            ends = (c_lo, c_hi) if run.u_out >= run.u_in else (c_hi, c_lo)
            for c in ends[: 1 if c_lo == c_hi else 2]:
                cell = _mm_cell(strokes, run.stroke, math.floor(c))
                keyframes.append((run.t_at(c), cell, frozenset({index})))
        for u, partial in ((run.u_in, partial_in), (run.u_out, partial_out)):
            centre = int(cell_floor(u, tol)) + 0.5  # of the column the stroke ends in
            partial.append(not lo <= centre <= hi)
    junctions = [(i, i + 1) for i in range(len(runs) - 1)]
    if shape.closed:
        junctions.append((len(runs) - 1, 0))
    for i, j in junctions:
        if partial_out[i]:
            cell = _mm_cell(strokes, runs[i].stroke, int(cell_floor(runs[i].u_out, tol)))
        elif partial_in[j]:
            cell = _mm_cell(strokes, runs[j].stroke, int(cell_floor(runs[j].u_in, tol)))
        else:
            continue
        keyframes.append((runs[i].t_out, cell, frozenset()))
    if shape.closed:
        keyframes = [(t % 1.0, cell, on) for t, cell, on in keyframes]
    else:  # the ends: the stroke's rule applies up to them from the stroke's own keyframes
        first, last = runs[0], runs[-1]
        cell = _mm_cell(strokes, first.stroke, int(cell_floor(first.u_in, tol)))
        keyframes.append((0.0, cell, frozenset({0})))
        cell = _mm_cell(strokes, last.stroke, int(cell_floor(last.u_out, tol)))
        keyframes.append((1.0, cell, frozenset({len(runs) - 1})))
    keyframes.sort(key=lambda k: k[0])
    merged = []
    for t, cell, on in keyframes:
        # Keyframes at one place (a junction on a tactor centre, a line's end on one) light the
        # same tactor: keep one, on every stroke it belongs to.
        if merged and abs(t - merged[-1][0]) <= _T_TOL:
            merged[-1] = (merged[-1][0], merged[-1][1], merged[-1][2] | on)
        else:
            merged.append((t, cell, on))
    keys = Keyframes(merged, shape.closed)
    return keys if keys.any_handover else None


def keyframes_of(shape) -> Keyframes | None:
    """The shape's IM keyframes, built once and kept with its strokes."""
    strokes = shape.strokes
    try:
        return strokes.im_keyframes
    except AttributeError:
        strokes.im_keyframes = build_keyframes(shape)
        return strokes.im_keyframes


def _stroke_cells(shape, xy, t, tol):
    """The paper's rule on each point's own stroke: ``(cols, rows, values)``, each ``(2, n)``."""
    strokes = shape.strokes
    table = lookup(strokes)
    params, xmajor, u, ids = on_stroke(strokes, xy[0], xy[1], t, 9 if table is None else 5)
    k, w = cell_split(u - 0.5, tol)  # w: share of cell k + 1
    pair = k + PAIR  # major cells k and k + 1, shape (2, n)
    # Between a stroke's end and its end cell's centre, the end tactor keeps everything:
    # w = 1 before the first centre (k < first), w = 0 after the last (k + 1 > last).
    np.putmask(w, k < params[3], 1.0)
    np.putmask(w, pair[1] > params[4], 0.0)
    if table is not None:
        cols, rows = table.cells(pair, ids)
    else:
        cols, rows = to_cells(xmajor, pair, tactor_of_cell(strokes, params, pair))
    values = np.empty((2, len(w)))
    np.subtract(1.0, w, out=values[0])
    values[1] = w
    return cols, rows, values


_INT_PAIR = PAIR.astype(np.intp)


def sample(shape, x, y, t, tol):
    """Tactors lit at the points ``(x, y) = shape.f(t)``.

    Parameters
    ----------
    shape : Shape
        The traced shape; its strokes select the tactors.
    x, y : ndarray of float64, shape (n,)
        Points of the trace in grid units.
    t : ndarray of float64, shape (n,)
        Their trace parameters.
    tol : float
        The shape's snap tolerance.

    Returns
    -------
    list of (cols, rows, values)
        Two entries: MM's tactors around each point and their intensities (in a hand-over
        both entries may name one tactor; the caller adds them up).
    """
    return sample_cells(shape, stack_points(x, y), t, tol).entries()


def sample_cells(shape, xy, t, tol):
    """:func:`sample` in the renderer's batch form, for the points ``xy`` (``(2, n)``): two
    candidates per point, entries of the shape's :class:`PieceTable` (:class:`~._cells.Indexed`);
    for a shape whose strokes span too many cells to tabulate, :class:`~._cells.Cells` added up
    (in a hand-over both may name one tactor)."""
    table = piece_table(shape)
    if table is not None:
        return table.sample(xy, t, tol)
    cols, rows, values = _stroke_cells(shape, xy, t, tol)
    keys = keyframes_of(shape)
    if keys is not None:
        j, w = keys.segment(t)
        across = keys.handover.take(j)
        if across.any():
            ends = j + _INT_PAIR
            np.copyto(cols, keys.cols.take(ends), where=across)
            np.copyto(rows, keys.rows.take(ends), where=across)
            np.copyto(values[1], w, where=across)
            np.subtract(1.0, w, out=values[0], where=across)
    return Cells(cols, rows, values, ZIP, add=True)


class PieceTable:
    """Everything IM's batch path needs about a shape, per piece of the trace: the pieces
    where neither the stroke nor the keyframe segment changes, so one lookup of ``t`` finds
    both (the strokes' and the keyframes' lookups agree with it: both take a point at a break
    into the later piece).

    Per piece, ``params`` holds the stroke's ``axis, lo, hi, first, last`` (as
    :class:`~tactile_core.rendering.shapes.Strokes`), its offset into MM's table of cells
    (:func:`~.midpoint.lookup`), and the segment's hand-over flag, ``t0``, ``t1``, width and the
    two keyframes' entries of ``cells`` (MM's cells, then the keyframes', then one cell off every
    grid). A hand-over between two keyframes on one tactor lights it at 1 from the first entry
    (``t1`` and the width infinite, so ``w = 0``) and sends the second nowhere.
    """

    def __init__(self, shape, table, keys: Keyframes | None):
        strokes = shape.strokes
        points = {0.0}
        for run in strokes.runs():
            points.update((run.t_in % 1.0, run.t_out % 1.0))
        if keys is not None:
            points.update(v for v in keys.t.tolist() if 0.0 < v < 1.0)
        points = sorted(v for v in points if 0.0 <= v < 1.0)
        ends = [*points[1:], 1.0]
        base = len(table.cols)
        cols, rows = [*table.cols.tolist()], [*table.rows.tolist()]
        if keys is not None:
            cols += keys.cols.tolist()
            rows += keys.rows.tolist()
        nowhere = len(cols)
        self.cells = CellTable([*cols, -1.0], [*rows, -1.0])
        columns = []
        for start, end in zip(points, ends):
            mid = 0.5 * (start + end)
            stroke = strokes.locate1(mid)
            row = strokes.rows1[stroke]
            column = [*row[:5], float(table.offset[stroke]), 0.0, 0.0, np.inf, np.inf, 0.0, 0.0]
            if keys is not None:
                j = min(max(bisect.bisect_right(keys._t1, mid) - 1, 0), len(keys._handover1) - 1)
                t0, t1 = keys._t1[j], keys._t1[j + 1]
                same = keys._cells1[j] == keys._cells1[j + 1]
                if keys._handover1[j]:
                    column[6:] = [1.0, t0, np.inf if same else t1,
                                  np.inf if same or t1 <= t0 else t1 - t0,
                                  base + j, nowhere if same else base + j + 1]  # fmt: skip
            columns.append(column)
        self.params = np.array(columns, dtype=np.float64).T.copy()
        self.params.flags.writeable = False
        self.pieces = Pieces(points, len(points) - 1) if len(points) > 1 else None
        self.any_handover = bool(self.params[6].any())

    def sample(self, xy, t, tol) -> Indexed:
        """The candidates of the points ``xy`` at ``t`` (see :func:`sample_cells`)."""
        if self.pieces is None:
            p = self.params  # one piece: its column broadcasts
        else:
            p = self.params.take(self.pieces.of(t), axis=1)
        u = clamp(np.where(p[0] == 0.0, xy[0], xy[1]), p[1], p[2])
        k, w = cell_split(u - 0.5, tol)  # w: share of cell k + 1
        # Between a stroke's end and its end cell's centre, the end tactor keeps everything:
        # w = 1 before the first centre (k < first), w = 0 after the last (k + 1 > last).
        np.putmask(w, k < p[3], 1.0)
        np.putmask(w, k >= p[4], 0.0)
        picks = np.empty((2, len(w)))
        np.add(k, p[5], out=picks[0])  # MM's cells of major cells k and k + 1
        np.add(picks[0], 1.0, out=picks[1])
        if self.any_handover:
            across = p[6] != 0.0
            if across.any():
                d0 = t - p[7]
                h = d0 / p[9]
                # Within _T_TOL of the segment's end w is 1, of its start 0.
                np.putmask(h, p[8] - t <= _T_TOL, 1.0)
                np.putmask(h, d0 <= _T_TOL, 0.0)
                np.copyto(w, clamp(h, 0.0, 1.0), where=across)
                np.copyto(picks, p[10:12], where=across)
        values = np.empty((2, len(w)))
        np.subtract(1.0, w, out=values[0])
        values[1] = w
        return Indexed(picks.astype(np.intp), self.cells, values)


def piece_table(shape) -> PieceTable | None:
    """The shape's :class:`PieceTable`, built once and kept with its strokes; None when its
    strokes span too many cells for MM's table (:data:`~.midpoint.MAX_LOOKUP`)."""
    strokes = shape.strokes
    try:
        return strokes.im_pieces
    except AttributeError:
        table = lookup(strokes)
        strokes.im_pieces = None if table is None else PieceTable(shape, table, keyframes_of(shape))
        return strokes.im_pieces


def sample1(shape, x, y, t, tol):
    """Scalar :func:`sample`: ``(col, row, value)`` tuples with nonzero intensity."""
    keys = keyframes_of(shape)
    if keys is not None:
        lit = keys.handover1(t)
        if lit is not None:
            return lit
    strokes = shape.strokes
    row = strokes.rows1[strokes.locate1(t)]
    axis, lo, hi, first, last = row[:5]
    u = min(max(x if axis == 0 else y, lo), hi)
    k, w = cell_split1(u - 0.5, tol)
    if k < first:
        w = 1.0
    if k + 1 > last:
        w = 0.0
    out = []
    for m, value in ((k, 1.0 - w), (k + 1, w)):
        if value > 0.0:
            n = math.floor(strokes.minor1(row, min(max(m + 0.5, lo), hi)) + tol)
            out.append((m, n, value) if axis == 0 else (n, m, value))
    return tuple(out)
