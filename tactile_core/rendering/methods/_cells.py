"""The batch form of the built-in methods: candidate cells per axis and one array of values.

The method protocol's ``sample`` returns one ``(cols, rows, values)`` entry per tactor it may
light; the renderer then pays a few numpy calls per entry. The built-in methods with several
entries (AS, EN, PK, RO, GS, VRCH) also define ``sample_cells``, which returns a :class:`Cells`:
the candidate columns and rows of every point as two small 2-D arrays, the ``(column, row)``
pairs that make up the candidates, and their values as one ``(k, n)`` array, so that the
renderer scatters all of them in a handful of calls whatever their number. Methods whose
candidates are a whole block of cells around each point (AS, EN, RO, GS, VRCH) return a
:class:`Block` instead: the block's first cell and its values, no candidate arrays at all (the
renderer finds the block's cells from small per-grid tables). IM, whose tactors come from a
per-shape table of cells, returns :class:`Indexed`: entries of that :class:`CellTable`, whose
flat indices the renderer keeps per grid. Their ``sample`` is
:meth:`Cells.entries` (:meth:`Block.entries`) of it, so both forms give the same numbers.
Plug-ins are never asked for this form (their output goes through the protocol's checks).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Cells(NamedTuple):
    """Candidate tactors of ``n`` points and their intensities.

    Attributes
    ----------
    cols : ndarray of float64, shape (a, n)
        Candidate columns of each point (whole numbers, possibly outside the grid).
    rows : ndarray of float64, shape (b, n)
        Candidate rows of each point.
    values : ndarray of float64, shape (k, n)
        Intensity of each candidate, in [0, 1].
    pairs : (ndarray of intp, ndarray of intp), None or ``ZIP``
        ``(col_index, row_index)``, each of length ``k``: candidate ``i`` is
        ``(cols[col_index[i]], rows[row_index[i]])``. None: the pairs of every column with
        every row, rows outer, candidate ``i`` being ``(cols[i % a], rows[i // a])``: all of
        them (``k = a * b``), or the first ``k`` when ``values`` has fewer rows (the pairs
        left out lie beyond the method's reach). :data:`ZIP`: candidate ``i`` is
        ``(cols[i], rows[i])`` (``k = a = b``).
    add : bool
        Candidates of one point may name the same tactor; their values add up, in order.
        Otherwise no two candidates of one point name the same tactor inside the grid, and the
        renderer may write them rather than add them up (cells outside the grid are dropped).
    """

    cols: np.ndarray
    rows: np.ndarray
    values: np.ndarray | float
    pairs: tuple | str | None = None
    add: bool = False

    def selectors(self) -> tuple[np.ndarray, np.ndarray]:
        """``(col_index, row_index)`` of every candidate (see :attr:`pairs`)."""
        if self.pairs is ZIP:
            return np.arange(len(self.cols)), np.arange(len(self.rows))
        if self.pairs is not None:
            return self.pairs
        a, b = len(self.cols), len(self.rows)
        k = a * b if np.ndim(self.values) != 2 else len(self.values)
        return np.tile(np.arange(a), b)[:k], np.repeat(np.arange(b), a)[:k]

    def entries(self) -> list:
        """The protocol's form: ``[(cols, rows, values), ...]``, one entry per candidate."""
        col_index, row_index = self.selectors()
        if np.ndim(self.values) == 0:
            values = [self.values] * len(col_index)
        else:
            values = self.values.reshape(len(col_index), -1)
        return [
            (self.cols[i], self.rows[j], values[k])
            for k, (i, j) in enumerate(zip(col_index.tolist(), row_index.tolist()))
        ]


class Block(NamedTuple):
    """Candidate tactors of ``n`` points that make up a block of ``width x height`` cells
    around each point, and their intensities.

    Attributes
    ----------
    origin : ndarray of float64, shape (2, n)
        The block's lower-left cell of each point: column (``origin[0]``) and row (whole
        numbers, possibly outside the grid). With ``flip``, twice that plus a flag (0 or 1)
        that reverses the order of the block's two columns (rows).
    values : ndarray of float64, shape (k, n)
        Intensity of the block's first ``k`` cells (the others are off), in [0, 1], rows outer:
        value ``j * width + i`` is cell ``(origin[0] + i, origin[1] + j)`` (with ``flip``,
        ``i`` and ``j`` reversed where the flags say). No two name one tactor, so the renderer
        writes them (cells outside the grid are dropped).
    width, height : int
        The block's size in columns and rows (2 x 2 with ``flip``).
    flip : bool
        ``origin`` carries the flags: a 2 x 2 block whose first cell per axis is the one the
        method chose (PK's nearest tactor), so that the cell left out comes last.
    """

    origin: np.ndarray
    values: np.ndarray
    width: int
    height: int
    flip: bool = False

    def cells(self) -> Cells:
        """The same candidates as :class:`Cells` (every column with every row, rows outer)."""
        cols = np.arange(self.width, dtype=np.float64)[:, None]
        rows = np.arange(self.height, dtype=np.float64)[:, None]
        if not self.flip:
            return Cells(self.origin[0] + cols, self.origin[1] + rows, self.values)
        first = np.floor(self.origin / 2.0)
        flag = self.origin - 2.0 * first
        cols = first[0] + np.abs(cols - flag[0])  # i, or 1 - i where flagged
        rows = first[1] + np.abs(rows - flag[1])
        return Cells(cols, rows, self.values)

    def entries(self) -> list:
        """The protocol's form: ``[(cols, rows, values), ...]``, one entry per cell."""
        return self.cells().entries()


class CellTable:
    """Cells a method picks its tactors from, built once (per shape), with their flat indices
    per grid kept for the renderer.

    Parameters
    ----------
    cols, rows : array_like of float
        Each entry's cell (whole numbers, possibly outside the grid).
    """

    def __init__(self, cols, rows):
        self.cols = np.array(cols, dtype=np.float64)
        self.rows = np.array(rows, dtype=np.float64)
        self.cols.flags.writeable = self.rows.flags.writeable = False
        self.flat_parts: dict = {}  # grid -> flat index of each entry, negative off the grid

    def __len__(self) -> int:
        return len(self.cols)


class Indexed(NamedTuple):
    """Candidate tactors of ``n`` points as entries of a :class:`CellTable`, and their
    intensities.

    Attributes
    ----------
    picks : ndarray of intp, shape (k, n)
        Each candidate's entry of ``table``.
    table : CellTable
    values : ndarray of float64, shape (k, n)
        Intensity of each candidate, in [0, 1]. No two candidates of one point name one tactor
        inside the grid, so the renderer writes them (cells outside the grid are dropped).
    """

    picks: np.ndarray
    table: CellTable
    values: np.ndarray

    def cells(self) -> Cells:
        """The same candidates as :class:`Cells` (column ``i`` with row ``i``)."""
        table = self.table
        return Cells(table.cols.take(self.picks), table.rows.take(self.picks), self.values, ZIP)

    def entries(self) -> list:
        """The protocol's form: ``[(cols, rows, values), ...]``, one entry per candidate."""
        return self.cells().entries()


ZIP = "zip"
""":attr:`Cells.pairs` for candidates given column by row (``(cols[i], rows[i])``)."""


PAIR = np.array([[0.0], [1.0]])
"""Offsets 0 and 1 as a column, to broadcast against ``(n,)`` rows."""
PAIR.flags.writeable = False


def outer(op, rows: np.ndarray, cols: np.ndarray, out: np.ndarray) -> np.ndarray:
    """``op(rows[i // a], cols[i % a])`` for the first ``k`` pairs of a row and a column, rows
    outer (the order of :attr:`Cells.pairs` None), into ``out`` (``(k, n)``).

    Parameters
    ----------
    op : numpy ufunc
        A binary ufunc such as ``np.multiply`` or ``np.add``.
    rows : ndarray, shape (b, n)
    cols : ndarray, shape (a, n)
    out : ndarray, shape (k, n)
        ``k <= a * b``.

    Returns
    -------
    ndarray
        ``out``.
    """
    a, n = cols.shape
    if len(out) == a * len(rows):  # every pair: one broadcast operation
        op(rows[:, None, :], cols[None, :, :], out=out.reshape(len(rows), a, n))
        return out
    full, rest = divmod(len(out), a)
    op(rows[:full, None, :], cols[None, :, :], out=out[: full * a].reshape(full, a, n))
    if rest:
        op(rows[full], cols[:rest], out=out[full * a :])
    return out


def stack_points(x, y) -> np.ndarray:
    """Points as the batch form takes them: one ``(2, n)`` array, x then y."""
    return np.stack([np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)])
