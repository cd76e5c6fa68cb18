"""Render a shape's trace to tactor intensities: dense frames in batch, sparse on the live path."""

from __future__ import annotations

import functools

import numpy as np

from .._shared import validate as _validate
from .geometry import SNAP_REL, Grid, clamp
from .methods import METHODS, get_method
from .shapes import Shape

_DEFAULT_GRID = Grid()


def check_grid(grid) -> Grid:
    """Return ``grid`` if it is a :class:`Grid`; otherwise raise ``ValueError`` naming it."""
    if not isinstance(grid, Grid):
        raise ValueError(f"grid must be a Grid of at least 1 x 1, got {_validate.shown(grid)}")
    return grid


def check_shape(shape, method=None) -> Shape | None:
    """Return ``shape`` if it is a :class:`Shape` (or None for a method that needs none)."""
    if shape is None and method is not None and not method.needs_shape:
        return None
    if not isinstance(shape, Shape):
        raise ValueError(
            f"shape must be a Line, Circle, Square or Polyline, got {_validate.shown(shape)}"
        )
    return shape


@functools.lru_cache(maxsize=16)
def _cell_table(grid: Grid) -> np.ndarray:
    """Lookup from a clipped cell code to a slot of a sample's row of ``grid.size + 1``.

    Code ``(row + 1) * (cols + 2) + (col + 1)`` for ``col`` in [-1, cols] and ``row`` in
    [-1, rows]; cells outside the grid map to the spare slot ``grid.size``.
    """
    table = np.full((grid.rows + 2, grid.cols + 2), grid.size, dtype=np.intp)
    table[1:-1, 1:-1] = np.arange(grid.size).reshape(grid.shape)
    return table.reshape(-1)


def scatter(entries, n: int, grid: Grid) -> np.ndarray:
    """Write sparse tactor intensities into dense frames, dropping cells outside the grid.

    Parameters
    ----------
    entries : list of (cols, rows, values)
        Per entry, cell indices (float arrays of shape (n,)) and intensities (array of shape
        (n,) or a scalar). Entries naming the same cell in one sample add up.
    n : int
        Number of samples.
    grid : Grid

    Returns
    -------
    ndarray of float64, shape (n, rows, cols)
        A view into a buffer with one spare slot per sample (where cells outside the grid go).
    """
    table = _cell_table(grid)
    width = grid.cols + 2
    slots = grid.size + 1
    out = np.zeros((n, slots))
    base = np.arange(0, n * slots, slots, dtype=np.intp)
    flat = out.reshape(-1)
    for cols, rows, values in entries:
        if _inside(cols, grid.cols) and _inside(rows, grid.rows):
            index = (rows * grid.cols + cols).astype(np.intp)
        else:
            code = clamp(rows, -1.0, grid.rows) * width + clamp(cols, -1.0, grid.cols)
            code += width + 1.0
            index = table[code.astype(np.intp)]
        index += base
        flat[index] += values  # one index per sample within an entry: no repeats
    return out[:, : grid.size].reshape(n, grid.rows, grid.cols)


def _inside(index, size: int) -> bool:
    """True when every (float) cell index lies in ``[0, size)`` (vacuously for no samples)."""
    if np.ndim(index) == 0:
        return 0 <= index < size
    return index.size == 0 or (index.min() >= 0 and index.max() < size)


def render(shape, method, t, *, grid: Grid = _DEFAULT_GRID) -> np.ndarray:
    """Raw tactor intensities (before correction) of a shape traced to parameter(s) ``t``.

    Parameters
    ----------
    shape : Shape
        :class:`~tactile_core.Line`, :class:`~tactile_core.Circle`,
        :class:`~tactile_core.Square` or :class:`~tactile_core.Polyline`.
    method : str
        Closest tactor, midpoint, area sampling or interpolated midpoint (``"CT"``, ``"MM"``,
        ``"AS"``, ``"IM"``, paper 2.2-2.5), a peer method (``"EN"``, ``"PK"``, ``"RO"``,
        ``"GS"``), a plug-in, or a spec with parameters such as ``"RO:r=1.5"`` (see
        :mod:`tactile_core.rendering.methods`).
    t : float or array_like
        Trace parameter(s), finite and within [0, 1].
    grid : Grid, keyword-only
        The tactor grid; the paper's 5 x 6 array by default.

    Returns
    -------
    ndarray of float64, shape ``t.shape + (grid.rows, grid.cols)``
        Intensities in [0, 1] indexed ``[..., row, col]``, row 0 at the bottom. Tactors that
        would fall outside the grid are dropped (and, for AS, the area outside it is lost).

    Raises
    ------
    ValueError
        Naming ``method``, ``t``, ``grid`` or ``shape`` when one is invalid.

    Examples
    --------
    >>> import tactile_core as tc
    >>> f = tc.render(tc.Line((0.5, 1.84), (4.5, 4.16)), "AS", 0.5)
    >>> f[2:4, 2]  # the point (2.5, 3.0) sits on the edge between rows 2 and 3
    array([0.5, 0.5])
    """
    m = get_method(method)
    grid = check_grid(grid)
    shape = check_shape(shape, m)
    t = _validate.parameter_array(t)
    flat_t = t.reshape(-1)
    _check_size(flat_t.size, grid)
    x, y = shape.xy(flat_t)
    entries = m.sample(shape, x, y, flat_t, shape.snap_tol)
    return scatter(entries, flat_t.size, grid).reshape(t.shape + grid.shape)


MAX_VALUES = 200_000_000
"""Most intensities one call returns (1.6 GB of float64)."""


def _check_size(n: int, grid: Grid) -> None:
    if n * grid.size > MAX_VALUES:
        raise ValueError(
            f"t holds {n} samples of {grid.size} tactors: more than {MAX_VALUES:.0e} values in "
            f"one call; render in chunks"
        )


def render_xy(method, x, y, *, grid: Grid = _DEFAULT_GRID) -> np.ndarray:
    """Render free points (no shape) with a method that needs none (CT or AS).

    The paper notes (2.1) that CT and AS apply when the stimulus position comes from something
    other than an equation, such as a touchpad; MM and IM select tactors from the shape's
    strokes and raise ``ValueError`` here.

    Parameters
    ----------
    method : str
        A method that needs no shape: CT, AS, EN, PK, RO, GS (or a spec such as ``"RO:r=1.5"``).
    x, y : float or array_like
        Finite coordinates in grid units, broadcast together.
    grid : Grid, keyword-only

    Returns
    -------
    ndarray of float64, shape ``broadcast(x, y).shape + (grid.rows, grid.cols)``
    """
    m = get_method(method)
    if m.needs_shape:
        free = ", ".join(n for n, k in METHODS.items() if not k.needs_shape)
        raise ValueError(
            f"method {m.name} needs a shape (it picks its tactors from the shape's strokes); "
            f"free points work with {free}"
        )
    grid = check_grid(grid)
    try:
        if isinstance(x, (str, bytes)) or isinstance(y, (str, bytes)):
            raise TypeError
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
    except (TypeError, ValueError, OverflowError):
        raise ValueError(
            f"x and y must be finite coordinates (numbers or arrays of them), got "
            f"{_validate.shown(x)} and {_validate.shown(y)}"
        ) from None
    shape = x.shape
    if not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise ValueError("x and y must be finite coordinates")
    x, y = x.reshape(-1), y.reshape(-1)
    _check_size(x.size, grid)
    tol = SNAP_REL * np.maximum(np.maximum(np.abs(x), np.abs(y)), 1.0)
    entries = m.sample(None, x, y, None, tol)
    return scatter(entries, x.size, grid).reshape(shape + grid.shape)


def render_point(shape, method, t: float, grid: Grid = _DEFAULT_GRID) -> tuple:
    """Live path: the lit tactors at one parameter value, with plain Python arithmetic.

    Touches only the active tactors (at most four) and allocates no arrays: about 10x
    cheaper than :func:`render` on a single ``t``. Arguments are checked as in :func:`render`.

    Returns
    -------
    tuple of (int, float)
        ``(flat index, raw intensity)`` of each lit tactor inside the grid, flat index =
        ``row * cols + col``.
    """
    m = get_method(method)
    grid = check_grid(grid)
    shape = check_shape(shape, m)
    if not 0.0 <= t <= 1.0:
        raise ValueError(f"t must be finite and within [0, 1], got {_validate.shown(t)}")
    return point_entries(shape, m.sample1, float(t), grid.cols, grid.rows)


def point_entries(shape, sample1, t: float, ncols: int, nrows: int) -> tuple:
    """Unchecked core of :func:`render_point` for callers that validated once up front."""
    x, y = shape.point(t)
    return tuple(
        (r * ncols + c, v)
        for c, r, v in sample1(shape, x, y, t, shape.snap_tol)
        if v > 0.0 and 0 <= c < ncols and 0 <= r < nrows
    )
