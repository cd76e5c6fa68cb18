"""Render a shape's trace to tactor intensities: dense frames in batch, sparse on the live path."""

from __future__ import annotations

import functools

import numpy as np

from .._shared import validate as _validate
from ._targets import check_renders as check_renders
from ._targets import check_shape, check_target
from .geometry import SNAP_REL, Grid
from .layout import Layout
from .methods import METHODS, ZIP, Block, Indexed, get_method, layout_sampler, outer
from .shapes import Shape

_DEFAULT_GRID = Grid()


_OFF_GRID = -(1 << 40)
"""A row or column part of a flat index for cells outside the grid: any index holding one is
negative, and is sent to the spare slot at the end of the buffer."""


@functools.lru_cache(maxsize=16)
def _index_tables(grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """Per axis, from a cell plus one (clipped to the table) to its part of a flat index.

    Columns map to ``col`` and rows to ``row * cols``; cells outside the grid (entries 0 and
    ``size + 1`` once clipped) to :data:`_OFF_GRID`.
    """
    cols = np.full(grid.cols + 2, _OFF_GRID, dtype=np.intp)
    rows = np.full(grid.rows + 2, _OFF_GRID, dtype=np.intp)
    cols[1:-1] = np.arange(grid.cols)
    rows[1:-1] = np.arange(grid.rows) * grid.cols
    cols.flags.writeable = rows.flags.writeable = False
    return cols, rows


def _index_part(cells, table: np.ndarray, *, bounded: bool = False):
    """Index parts (:func:`_index_tables`) of cells given as whole floats.

    ``bounded``: the cells are known to lie within a few cells of ``[-MAX_COORD, MAX_COORD]``
    (a built-in method's, from checked coordinates), so they convert to integers as they are;
    otherwise (a plug-in's, any magnitude) they are clipped first.
    """
    if np.ndim(cells) == 0:
        return table[int(min(max(cells + 1.0, 0.0), len(table) - 1.0))]
    if bounded:
        index = cells.astype(np.intp)
    else:
        index = np.clip(cells, -1.0, len(table) - 2.0).astype(np.intp)
    index += 1
    return table.take(index, mode="clip")


@functools.lru_cache(maxsize=4)
def _offsets(n: int, size: int) -> np.ndarray:
    """Each sample's offset into the frames' flat buffer (read-only, kept for a few sizes)."""
    out = np.arange(0, n * size, size, dtype=np.intp)
    out.flags.writeable = False
    return out


def _new_buffer(n: int, grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """Zeroed frames as one flat buffer with a spare slot at its end (where cells outside the
    grid go), and each sample's offset into it."""
    return np.zeros(n * grid.size + 1), np.arange(0, n * grid.size, grid.size, dtype=np.intp)


def _frames(flat: np.ndarray, n: int, grid: Grid) -> np.ndarray:
    return flat[:-1].reshape(n, grid.rows, grid.cols)


def scatter(entries, n: int, grid: Grid) -> np.ndarray:
    """Write sparse tactor intensities into dense frames, dropping cells outside the grid.

    Parameters
    ----------
    entries : list of (cols, rows, values)
        Per entry, cell indices (whole floats, arrays of shape (n,) or scalars) and intensities
        (array of shape (n,) or a scalar). Entries naming the same cell in one sample add up.
    n : int
        Number of samples.
    grid : Grid

    Returns
    -------
    ndarray of float64, shape (n, rows, cols)
    """
    col_table, row_table = _index_tables(grid)
    flat, base = _new_buffer(n, grid)
    for cols, rows, values in entries:
        index = _index_part(rows, row_table) + base
        index += _index_part(cols, col_table)
        np.maximum(index, -1, out=index)  # off the grid: the spare slot
        flat[index] += values  # one index per sample within an entry: no repeats
    return _frames(flat, n, grid)


def scatter_cells(cells, n: int, grid: Grid) -> np.ndarray:
    """:func:`scatter` for the batch form of the built-in methods (:mod:`.methods._cells`):
    every candidate in one pass. Candidates of one sample never name one tactor twice, so they
    are written, not added. A :class:`~.methods._cells.Block` goes through
    :func:`_scatter_block`."""
    if type(cells) is Block:
        return _scatter_block(cells, n, grid)
    if type(cells) is Indexed:
        return _scatter_indexed(cells, n, grid)
    col_table, row_table = _index_tables(grid)
    flat, base = _new_buffer(n, grid)
    cols = _index_part(cells.cols, col_table, bounded=True)
    rows = _index_part(cells.rows, row_table, bounded=True)
    rows += base
    if cells.pairs is None:
        k = len(cells.values) if np.ndim(cells.values) == 2 else len(rows) * len(cols)
        index = outer(np.add, rows, cols, np.empty((k, n), dtype=np.intp))
    elif cells.pairs is ZIP:
        index = rows
        index += cols
    else:
        col_index, row_index = cells.pairs
        index = rows.take(row_index, axis=0)
        index += cols.take(col_index, axis=0)
    np.maximum(index, -1, out=index)
    values = cells.values
    if np.ndim(values) == 0:
        flat[index] = values
    elif cells.add:
        values = values.reshape(index.shape)
        flat[index[0]] = values[0]
        for k in range(1, len(index)):
            flat[index[k]] += values[k]
    else:
        flat[index] = values.reshape(index.shape)
    return _frames(flat, n, grid)


@functools.lru_cache(maxsize=64)
def _block_tables(grid: Grid, width: int, height: int, flip: bool = False):
    """Per axis, from a block's first cell plus the block's size (clipped to the table) to
    the index parts (:func:`_index_tables`) of the block's cells along that axis.

    Columns: ``table[i, c + width]`` is the part of column ``c + i``, for ``c`` in
    ``[-width, cols]``; beyond that range every cell of the block is outside the grid, and so
    are the table's first and last entries, where the clipped lookups land. With ``flip``
    (2 x 2 blocks), ``table[i, 2 (c + 2) + f]`` is the part of column ``c + (i xor f)``.
    """
    out = []
    for size, step, span in ((grid.cols, 1, width), (grid.rows, grid.cols, height)):
        if flip:
            m = np.arange(2 * (size + span + 1))
            first = (m // 2 - span)[None, :] + (np.arange(span)[:, None] ^ (m % 2)[None, :])
        else:
            first = np.arange(-span, size + 1)[None, :] + np.arange(span)[:, None]  # cells
        table = np.where((first >= 0) & (first < size), first * step, _OFF_GRID)
        table = np.ascontiguousarray(table, dtype=np.intp)
        table.flags.writeable = False
        out.append(table)
    return out[0], out[1]


def _scatter_block(block: Block, n: int, grid: Grid) -> np.ndarray:
    """:func:`scatter_cells` for a :class:`~.methods._cells.Block`: each axis's index parts
    from one lookup of the block's first cell, then every cell in one write."""
    width, height = block.width, block.height
    col_table, row_table = _block_tables(grid, width, height, block.flip)
    first = block.origin.astype(np.intp)
    if width == height:
        first += 2 * width if block.flip else width
    else:
        first[0] += width
        first[1] += height
    cols = col_table.take(first[0], axis=1, mode="clip")
    rows = row_table.take(first[1], axis=1, mode="clip")
    rows += _offsets(n, grid.size)
    index = outer(np.add, rows, cols, np.empty((len(block.values), n), dtype=np.intp))
    np.maximum(index, -1, out=index)
    del first, cols, rows  # (the frames are allocated last: a smaller peak of memory)
    flat = np.zeros(n * grid.size + 1)
    flat[index] = block.values
    return _frames(flat, n, grid)


def _scatter_indexed(cells: Indexed, n: int, grid: Grid) -> np.ndarray:
    """:func:`scatter_cells` for :class:`~.methods._cells.Indexed`: the table's flat indices
    for this grid (computed once per table and grid), one lookup, every candidate in one
    write."""
    table = cells.table
    parts = table.flat_parts.get(grid)
    if parts is None:
        col_table, row_table = _index_tables(grid)
        parts = _index_part(table.cols, col_table) + _index_part(table.rows, row_table)
        parts.flags.writeable = False  # (negative, far below -n * size, off the grid)
        table.flat_parts[grid] = parts
    index = parts.take(cells.picks)
    index += _offsets(n, grid.size)
    np.maximum(index, -1, out=index)  # (off the grid: the spare slot)
    flat = np.zeros(n * grid.size + 1)
    flat[index] = cells.values
    return _frames(flat, n, grid)


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
    grid : Grid or Layout, keyword-only
        The tactor grid; the paper's 5 x 6 array by default. A
        :class:`~tactile_core.rendering.layout.Layout` renders on actuators anywhere, with
        the methods that work there (EN, PK, RO, GS, VRCH, BA; the paper's four need a grid).

    Returns
    -------
    ndarray of float64, shape ``t.shape + (grid.rows, grid.cols)``
        Intensities in [0, 1] indexed ``[..., row, col]``, row 0 at the bottom. Tactors that
        would fall outside the grid are dropped (and, for AS, the area outside it is lost).
        On a layout that is not a grid, ``t.shape + (layout.size,)`` in actuator order. For a
        shape with an intensity envelope (a :class:`~tactile_core.rendering.shapes.TimedPath`)
        the method's intensities are multiplied by ``shape.intensity(t)``.

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
    m = METHODS.get(method) if type(method) is str else None
    if m is not None and type(grid) is Grid and isinstance(shape, Shape):
        # The common case, checked cheaply: a registered method by its name, a float or an
        # array of float64. Anything else (or a t out of range) takes the checks below.
        if type(t) is float:
            if 0.0 <= t <= 1.0:
                return _render_valid(shape, m, np.array(t), grid)
        elif type(t) is np.ndarray and t.dtype is _FLOAT64 and t.size:
            if t.size <= _POINTWISE:
                ok = all(0.0 <= v <= 1.0 for v in t.flat)
            else:
                ok = t.min() >= 0.0 and t.max() <= 1.0  # (False for NaN)
            if ok and t.size * grid.size <= MAX_VALUES:
                return _render_valid(shape, m, t, grid)
    m = get_method(method)
    grid = check_target(grid)
    shape = check_shape(shape, m)
    t = _validate.parameter_array(t)
    _check_size(t.size, grid)
    if not grid.is_grid:
        return _render_layout(shape, m, t, grid)
    return _render_valid(shape, m, t, grid)


def _render_layout(shape, m, t: np.ndarray, layout: Layout) -> np.ndarray:
    """:func:`render` on a layout that is not a grid: ``t.shape + (size,)``."""
    flat_t = t.reshape(-1)
    frames = _enveloped(shape, flat_t, layout_sampler(m, layout).frames_of(shape, flat_t))
    return frames.reshape((*t.shape, layout.size))


def _enveloped(shape, flat_t: np.ndarray, frames: np.ndarray) -> np.ndarray:
    """``frames`` (one per sample of ``flat_t``) times the shape's intensity envelope, for a
    shape that has one (a time-keyed path); before the correction, so 0 stays 0."""
    if shape is None or not shape.has_envelope:
        return frames
    scale = shape.intensity(flat_t).reshape((-1,) + (1,) * (frames.ndim - 1))
    frames *= scale
    return frames


_FLOAT64 = np.dtype(np.float64)

_POINTWISE = 8
"""Up to this many samples, built-in methods render point by point with their scalar samplers
(a few microseconds a point, where the array path costs tens of microseconds of set-up)."""


def _render_valid(shape, m, t: np.ndarray, grid: Grid) -> np.ndarray:
    """:func:`render` on checked arguments (``t`` a float64 array within [0, 1])."""
    n = t.size
    flat_t = t.reshape(-1)
    if n <= _POINTWISE and not m.plugin:
        frames = _render_points(shape, m, flat_t.tolist(), grid)
        if frames is not None:
            return _enveloped(shape, flat_t, frames.reshape((n, *grid.shape))).reshape(
                t.shape + grid.shape
            )
    if m.sample_cells is not None:
        xy = shape.xy_rows(flat_t)
    else:
        xy = shape.xy(flat_t)
    frames = _sample_and_scatter(m, shape, xy, flat_t, shape.snap_tol, grid)
    return _enveloped(shape, flat_t, frames).reshape(t.shape + grid.shape)


def _sample_and_scatter(m, shape, xy, t, tol, grid: Grid) -> np.ndarray:
    """Frames ``(n, rows, cols)`` of the points ``xy`` (``(2, n)``: x then y): through a
    built-in method's batch form where it has one, else the protocol's entries."""
    n = len(xy[0])
    if m.sample_cells is not None:
        return scatter_cells(m.sample_cells(shape, xy, t, tol), n, grid)
    return scatter(m.sample(shape, xy[0], xy[1], t, tol), n, grid)


def _render_points(shape, m, ts: list, grid: Grid) -> np.ndarray | None:
    """Frames of a few points from a built-in method's scalar sampler, or None if a decision
    there lies within rounding of its edge (where only the array path decides as it always
    has: see ``Method.sample1_exact``)."""
    sample1 = m.sample1_exact
    ncols, nrows, size = grid.cols, grid.rows, grid.size
    out = np.zeros(len(ts) * size)
    point, tol = shape.point, shape.snap_tol
    base = 0
    for t in ts:
        x, y = point(t)
        lit = sample1(shape, x, y, t, tol)
        if lit is None:
            return None
        for c, r, v in lit:
            if 0 <= c < ncols and 0 <= r < nrows:
                out[base + r * ncols + c] += v
        base += size
    return out


MAX_VALUES = 200_000_000
"""Most intensities one call returns (1.6 GB of float64)."""


def _check_size(n: int, grid: Grid) -> None:
    if n * grid.size > MAX_VALUES:
        raise ValueError(
            f"t holds {n} samples of {grid.size} tactors: more than {MAX_VALUES:.0e} values in "
            f"one call; render in chunks"
        )


def free_method(method):
    """The :class:`~.methods.Method` for ``method`` if it renders free points (needs no shape);
    ``ValueError`` naming the methods that do otherwise."""
    m = get_method(method)
    if m.needs_shape:
        free = ", ".join(n for n, k in METHODS.items() if not k.needs_shape)
        raise ValueError(
            f"method {m.name} needs a shape (it picks its tactors from the shape's strokes); "
            f"free points work with {free}"
        )
    return m


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
    grid : Grid or Layout, keyword-only

    Returns
    -------
    ndarray of float64, shape ``broadcast(x, y).shape + (grid.rows, grid.cols)``
        (``+ (layout.size,)`` on a layout that is not a grid)
    """
    m = free_method(method)
    grid = check_target(grid)
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
    if x.size and max(np.abs(x).max(), np.abs(y).max()) > _validate.MAX_COORD:
        raise ValueError(
            f"x and y must be coordinates within {_validate.MAX_COORD:g} grid units of the origin, "
            f"got {max(np.abs(x).max(), np.abs(y).max()):g}"
        )
    x, y = x.reshape(-1), y.reshape(-1)
    _check_size(x.size, grid)
    tol = SNAP_REL * np.maximum(np.maximum(np.abs(x), np.abs(y)), 1.0)
    if not grid.is_grid:
        return layout_sampler(m, grid).frames(x, y, tol).reshape((*shape, grid.size))
    frames = _sample_and_scatter(m, None, np.stack([x, y]), None, tol, grid)
    return frames.reshape(shape + grid.shape)


def render_point(shape, method, t: float, grid: Grid = _DEFAULT_GRID) -> tuple:
    """Live path: the lit tactors at one parameter value, with plain Python arithmetic.

    Touches only the active tactors (at most four) and allocates no arrays: about 10x
    cheaper than :func:`render` on a single ``t``. Arguments are checked as in :func:`render`.

    Returns
    -------
    tuple of (int, float)
        ``(flat index, raw intensity)`` of each lit tactor inside the grid, flat index =
        ``row * cols + col`` (on a layout that is not a grid: the actuator index).
    """
    m = get_method(method)
    grid = check_target(grid)
    shape = check_shape(shape, m)
    if not 0.0 <= t <= 1.0:
        raise ValueError(f"t must be finite and within [0, 1], got {_validate.shown(t)}")
    if not grid.is_grid:
        return layout_entries(shape, layout_sampler(m, grid), float(t))
    return point_entries(shape, m.sample1, float(t), grid.cols, grid.rows)


def point_entries(shape, sample1, t: float, ncols: int, nrows: int) -> tuple:
    """Unchecked core of :func:`render_point` for callers that validated once up front."""
    x, y = shape.point(t)
    lit = tuple(
        (r * ncols + c, v)
        for c, r, v in sample1(shape, x, y, t, shape.snap_tol)
        if v > 0.0 and 0 <= c < ncols and 0 <= r < nrows
    )
    if shape.has_envelope:
        k = shape.intensity1(t)
        return tuple((i, v * k) for i, v in lit if v * k > 0.0)
    return lit


def layout_entries(shape, sampler, t: float) -> tuple:
    """:func:`point_entries` on a layout that is not a grid, for a
    :class:`~.methods.LayoutSampler`: ``((actuator, raw intensity), ...)`` of the lit
    actuators, the envelope applied."""
    k = shape.intensity1(t) if shape.has_envelope else 1.0
    return tuple((i, v * k) for i, v in sampler.entries_of(shape, t) if v * k > 0.0)
