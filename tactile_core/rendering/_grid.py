"""The grid of tactors: ``cols`` x ``rows`` unit cells, a tactor at each centre.

Re-exported by :mod:`.geometry`, where it has always been found; it lives here so that
:mod:`.layout` and :mod:`.geometry` can both build on it.
"""

from __future__ import annotations

from dataclasses import dataclass

from .._shared import validate as _validate

MAX_GRID = 1024
"""Most columns or rows of a grid."""


@dataclass(frozen=True)
class Grid:
    """A grid of ``cols`` x ``rows`` tactors, one per unit cell.

    Parameters
    ----------
    cols, rows : int
        Number of columns (along x) and rows (along y), each from 1 to 1024. The default is the
        paper's palm array, 5 columns by 6 rows.

    Examples
    --------
    >>> Grid().shape
    (6, 5)
    >>> Grid(cols=2, rows=3).center(1, 2)
    (1.5, 2.5)
    """

    cols: int = 5
    rows: int = 6

    def __post_init__(self):
        for name in ("cols", "rows"):
            value = getattr(self, name)
            try:
                checked = _validate.integer(f"grid {name}", value, 1, MAX_GRID)
            except ValueError:
                raise ValueError(
                    f"grid must be at least 1 x 1 and at most {MAX_GRID} x {MAX_GRID}: grid "
                    f"{name} must be an integer from 1 to {MAX_GRID}, got {_validate.shown(value)}"
                ) from None
            object.__setattr__(self, name, checked)

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)``: the shape of one frame."""
        return (self.rows, self.cols)

    @property
    def size(self) -> int:
        """Number of tactors, ``rows * cols``."""
        return self.rows * self.cols

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
