"""What a renderer renders onto and what it renders: the checks of a grid or layout, a shape,
and whether a method renders on a layout (shared by :mod:`.rasterize` and :mod:`.trace`)."""

from __future__ import annotations

from .._shared import validate as _validate
from .geometry import Grid
from .layout import Layout
from .methods import get_method, layout_sampler
from .shapes import Shape


def check_grid(grid) -> Grid:
    """Return ``grid`` if it is a :class:`Grid`; otherwise raise ``ValueError`` naming it."""
    if not isinstance(grid, Grid):
        raise ValueError(f"grid must be a Grid of at least 1 x 1, got {_validate.shown(grid)}")
    return grid


def check_target(grid) -> Grid | Layout:
    """What to render onto: a :class:`Grid` (also for a grid's :class:`Layout`), or a layout
    that is not a grid; ``ValueError`` naming ``grid`` otherwise."""
    if isinstance(grid, Grid):
        return grid
    if isinstance(grid, Layout):
        return grid.grid if grid.grid is not None else grid
    raise ValueError(
        f"grid must be a Grid of at least 1 x 1 or a Layout, got {_validate.shown(grid)}"
    )


def check_renders(method, target) -> None:
    """``ValueError`` saying why, when ``method`` cannot render on ``target`` (a Grid or a
    Layout): the paper's four and grid-only plug-ins on a layout that is not a grid."""
    target = check_target(target)
    if isinstance(target, Layout):
        layout_sampler(get_method(method), target)


def frame_shape(target) -> tuple:
    """Shape of one frame on a Grid ``(rows, cols)`` or a Layout (``(size,)`` unless a grid)."""
    return target.shape if isinstance(target, Grid) else target.frame_shape


def target_size(target) -> int:
    """Tactors (actuators) of a Grid or Layout."""
    return target.size


def check_shape(shape, method=None) -> Shape | None:
    """Return ``shape`` if it is a :class:`Shape` (or None for a method that needs none)."""
    if shape is None and method is not None and not method.needs_shape:
        return None
    if not isinstance(shape, Shape):
        raise ValueError(
            f"shape must be a Line, Circle, Square or Polyline, got {_validate.shown(shape)}"
        )
    return shape
