"""The grid of tactors: ``cols`` x ``rows`` unit cells, a tactor at each centre; a kind of
:class:`~tactile_core.rendering.layout.Layout`.

Re-exported by :mod:`.geometry`, where it has always been found.
"""

from __future__ import annotations

import functools

import numpy as np

from .._shared import validate as _validate
from .layout import Layout

MAX_GRID = 1024
"""Most columns or rows of a grid."""


class Grid(Layout):
    """A grid of ``cols`` x ``rows`` tactors, one per unit cell: a :class:`Layout` whose
    actuators sit at the cell centres ``(col + 0.5, row + 0.5)`` in row-major order, named
    ``"r{row}c{col}"``, and on which the paper's methods render (:attr:`is_grid`).

    Parameters
    ----------
    cols, rows : int
        Number of columns (along x) and rows (along y), each from 1 to 1024. The default is the
        paper's palm array, 5 columns by 6 rows.

    Notes
    -----
    Immutable and hashable like every layout; two grids are equal when their columns and rows
    are. The positions and names of a large grid are made only when asked for.

    Examples
    --------
    >>> Grid().shape
    (6, 5)
    >>> Grid(cols=2, rows=3).center(1, 2)
    (1.5, 2.5)
    >>> Grid(2, 3).frame_shape, Grid(2, 3).positions[:2], Grid(2, 3).is_grid
    ((3, 2), ((0.5, 0.5), (1.5, 0.5)), True)
    """

    def __init__(self, cols: int = 5, rows: int = 6):
        for name, value in (("cols", cols), ("rows", rows)):
            try:
                checked = _validate.integer(f"grid {name}", value, 1, MAX_GRID)
            except ValueError:
                raise ValueError(
                    f"grid must be at least 1 x 1 and at most {MAX_GRID} x {MAX_GRID}: grid "
                    f"{name} must be an integer from 1 to {MAX_GRID}, got {_validate.shown(value)}"
                ) from None
            object.__setattr__(self, name, checked)

    def __setattr__(self, name, value):
        raise AttributeError(f"Grid is immutable: cannot set {name!r}")

    def __delattr__(self, name):
        raise AttributeError(f"Grid is immutable: cannot delete {name!r}")

    def __eq__(self, other):
        if type(other) is not Grid:
            return NotImplemented
        return (self.cols, self.rows) == (other.cols, other.rows)

    def __hash__(self):
        return hash((Grid, self.cols, self.rows))

    def __repr__(self):
        return f"Grid(cols={self.cols}, rows={self.rows})"

    def __reduce__(self):
        return (Grid, (self.cols, self.rows))

    # --- the Layout interface -------------------------------------------------------------------

    wrap = None
    groups = ()

    @property
    def positions(self) -> tuple:
        """The tactor centres ``((col + 0.5, row + 0.5), ...)`` in row-major order."""
        return _positions(self.cols, self.rows)

    @property
    def names(self) -> tuple:
        """``("r0c0", "r0c1", ...)``: each tactor's :meth:`cell_name`."""
        return _names(self.cols, self.rows)

    @property
    def xy(self) -> np.ndarray:
        """``(size, 2)`` float64: the tactor centres (read-only)."""
        return _xy(self.cols, self.rows)

    @property
    def size(self) -> int:
        """Number of tactors, ``rows * cols``."""
        return self.rows * self.cols

    @property
    def is_grid(self) -> bool:
        """True: the paper's methods render here."""
        return True

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)``: the shape of one frame."""
        return (self.rows, self.cols)

    @property
    def frame_shape(self) -> tuple[int, int]:
        """``(rows, cols)``, as :attr:`shape`."""
        return (self.rows, self.cols)

    @property
    def wire_shape(self) -> tuple[int, int]:
        """``(cols, rows)``, as the wire format's info announces a grid."""
        return (self.cols, self.rows)

    def bounds(self, margin: float = 0.5) -> tuple[float, float, float, float]:
        """``(0, cols, 0, rows)``: the cells (``margin`` is half a cell by construction)."""
        return (0.0, float(self.cols), 0.0, float(self.rows))

    def describe(self) -> str:
        """``"5 x 6 grid"``."""
        return f"{self.cols} x {self.rows} grid"

    # --- cells ---------------------------------------------------------------------------------

    def center(self, col: int, row: int) -> tuple[float, float]:
        """Coordinates ``(x, y)`` of the tactor of cell ``(col, row)``, in grid units."""
        return (col + 0.5, row + 0.5)

    def flat(self, col: int, row: int) -> int:
        """Flat index ``row * cols + col`` of cell ``(col, row)`` (the default channel)."""
        return row * self.cols + col

    def cell(self, flat: int) -> tuple[int, int]:
        """``(col, row)`` of the cell with flat index ``flat``."""
        row, col = divmod(flat, self.cols)
        return (col, row)

    def cell_name(self, flat: int) -> str:
        """A short label such as ``"r2c4"`` (row 2, column 4) used in files and plots."""
        col, row = self.cell(flat)
        return f"r{row}c{col}"


@functools.lru_cache(maxsize=16)
def _xy(cols: int, rows: int) -> np.ndarray:
    x, y = np.meshgrid(np.arange(cols) + 0.5, np.arange(rows) + 0.5)
    xy = np.stack([x.ravel(), y.ravel()], axis=1)
    xy.flags.writeable = False
    return xy


@functools.lru_cache(maxsize=16)
def _positions(cols: int, rows: int) -> tuple:
    return tuple(map(tuple, _xy(cols, rows).tolist()))


@functools.lru_cache(maxsize=16)
def _names(cols: int, rows: int) -> tuple:
    return tuple(f"r{row}c{col}" for row in range(rows) for col in range(cols))
