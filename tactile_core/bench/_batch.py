"""Table 1a, what batch rendering costs: ``render`` per frame for every method and shape,
next to two straightforward area samplings as yardsticks."""

from __future__ import annotations

import time

import numpy as np

from ..rendering.geometry import Grid
from ..rendering.methods import METHOD_NAMES
from ._common import SCENES, Table, best_time


def dense_area_sampling(shape, t, grid: Grid) -> np.ndarray:
    """The textbook vectorised AS: the box's overlap with every cell, broadcast over frames.

    For each frame and each cell, the overlap of ``[px - 0.5, px + 0.5]`` with
    ``[col, col + 1]`` times the same in y: the yardstick the issue quotes (~0.25 us/frame).
    """
    x, y = shape.xy(t)
    cols = np.arange(grid.cols, dtype=np.float64)
    rows = np.arange(grid.rows, dtype=np.float64)
    wx = np.minimum(x[:, None] + 0.5, cols + 1) - np.maximum(x[:, None] - 0.5, cols)
    wy = np.minimum(y[:, None] + 0.5, rows + 1) - np.maximum(y[:, None] - 0.5, rows)
    return np.maximum(wy, 0.0)[:, :, None] * np.maximum(wx, 0.0)[:, None, :]


def naive_area_sampling(shape, t, grid: Grid) -> np.ndarray:
    """A leaner straightforward AS: only the four overlapped corners, masked fancy indexing.

    Plain ``floor`` (no float-noise snapping), boolean masks to drop cells outside the grid,
    and fancy-index assignment per corner: a stricter yardstick than :func:`dense_area_sampling`.
    """
    x, y = shape.xy(t)
    a, b = x - 0.5, y - 0.5
    c, r = np.floor(a), np.floor(b)
    fx, fy = a - c, b - r
    out = np.zeros((len(t), grid.rows, grid.cols))
    sample = np.arange(len(t))
    for dc, dr, w in (
        (0, 0, (1 - fx) * (1 - fy)),
        (1, 0, fx * (1 - fy)),
        (0, 1, (1 - fx) * fy),
        (1, 1, fx * fy),
    ):
        cc, rr = (c + dc).astype(int), (r + dr).astype(int)
        ok = (cc >= 0) & (cc < grid.cols) & (rr >= 0) & (rr < grid.rows)
        out[sample[ok], rr[ok], cc[ok]] = w[ok]
    return out


def batch_table(sizes=(2000, 100_000), grid: Grid | None = None) -> Table:
    """Table 1a: batch cost per frame of ``render`` for every method and shape."""
    from ..rendering.rasterize import render

    grid = grid or Grid()
    rows = []
    for name, shape in SCENES.items():
        for method in ("dense AS", "corner AS", *METHOD_NAMES):
            row = [name, method]
            for n in sizes:
                t = np.linspace(0.0, 1.0, n)
                if method == "dense AS":
                    seconds = best_time(lambda t=t, s=shape: dense_area_sampling(s, t, grid))
                elif method == "corner AS":
                    seconds = best_time(lambda t=t, s=shape: naive_area_sampling(s, t, grid))
                else:
                    seconds = best_time(lambda t=t, s=shape, m=method: render(s, m, t, grid=grid))
                row.append(f"{seconds / n * 1e6:.3f}")
            rows.append(row)
    headers = ["shape", "method", *(f"us/frame @ {n:,}" for n in sizes)]
    notes = (
        "Yardsticks on the same shape: `dense AS` is the textbook vectorised area sampling "
        "(the box's overlap with every cell, broadcast over all frames); `corner AS` a leaner "
        "straightforward one (the four overlapped cells, masked fancy indexing)."
    )
    return Table("Batch rendering cost (render, raw intensities)", headers, rows, notes)


BUILT_IN = ("CT", "MM", "AS", "IM", "EN", "PK", "RO", "GS", "VRCH")
"""The built-in methods, in the order of the ratio table's columns."""


def _interleaved(fns, *, repeat: int, number: int) -> list[float]:
    """Seconds per call of each of ``fns``, timed in turn (A, B, A, B ...) ``repeat`` times
    with ``number`` calls each: the minimum per function, so a disturbance that hits one
    turn does not tilt the comparison."""
    best = [float("inf")] * len(fns)
    for _ in range(repeat):
        for i, fn in enumerate(fns):
            t0 = time.perf_counter()
            for _ in range(number):
                fn()
            best[i] = min(best[i], (time.perf_counter() - t0) / number)
    return best


def ratio_table(samples: int = 2000, repeat: int = 40, grid: Grid | None = None) -> Table:
    """Batch ``render`` of every built-in method against ``corner AS`` on the same shape.

    Each cell is ``min(render) / min(corner AS)`` over ``repeat`` turns of the two, timed
    interleaved (A, B, A, B ...) with enough calls a turn for ~3 ms. First a 32 MB block is
    allocated and freed: glibc then keeps freed memory up to that size instead of returning it
    to the system (it adapts that threshold to the largest block freed, as the 100,000-sample
    rows of :func:`batch_table` do), so no call pays page faults that depend on which
    allocations happened to come before it.
    """
    from ..rendering.rasterize import render

    grid = grid or Grid()
    np.ones(4_000_000).sum()  # settle the allocator (see above)
    t = np.linspace(0.0, 1.0, samples)
    rows = []
    for name, shape in SCENES.items():
        row = [name]
        corner = lambda s=shape: naive_area_sampling(s, t, grid)  # noqa: E731
        per_call = best_time(corner, repeat=3, min_s=0.01)
        number = max(1, int(0.003 / per_call))
        floor_s = float("inf")
        for method in BUILT_IN:
            fn = lambda s=shape, m=method: render(s, m, t, grid=grid)  # noqa: E731
            fn()  # set-up (strokes, keyframes, tables) outside the timing
            mine, floor = _interleaved([fn, corner], repeat=repeat, number=number)
            floor_s = min(floor_s, floor)
            row.append(f"{mine / floor:.2f}")
        row.append(f"{floor_s / samples * 1e6:.3f}")
        rows.append(row)
    notes = (
        f"`render(shape, method, t)` at {samples:,} samples against `corner AS` on the same "
        f"shape and t: the minimum over {repeat} turns of each, timed interleaved (A, B, A, "
        "B ...), after a 32 MB allocation that settles the C library's allocator. Below 1: "
        "cheaper than the straightforward vectorised area sampling. Last column: corner AS "
        "itself, the fastest of its turns."
    )
    headers = ["shape", *BUILT_IN, "corner AS us/frame"]
    return Table("Batch render against corner AS", headers, rows, notes)
