"""What a renderer renders onto and what it renders: the checks of a layout (a grid is one), a
shape, and whether a method renders on a layout (shared by :mod:`.rasterize` and :mod:`.trace`)."""

from __future__ import annotations

from .._shared import validate as _validate
from .layout import Layout, check_layout
from .methods import get_method, layout_sampler
from .shapes import Shape


def check_target(grid) -> Layout:
    """What to render onto: a :class:`~tactile_core.rendering.geometry.Grid` or any other
    :class:`Layout`; ``ValueError`` naming ``grid`` otherwise."""
    return check_layout(grid, "grid")


def check_renders(method, target) -> None:
    """``ValueError`` saying why, when ``method`` cannot render on ``target``: the paper's four
    and grid-only plug-ins on a layout that is not a grid."""
    target = check_target(target)
    if not target.is_grid:
        layout_sampler(get_method(method), target)


def check_shape(shape, method=None) -> Shape | None:
    """Return ``shape`` if it is a :class:`Shape` (or None for a method that needs none)."""
    if shape is None and method is not None and not method.needs_shape:
        return None
    if not isinstance(shape, Shape):
        raise ValueError(
            f"shape must be a Line, Circle, Square or Polyline, got {_validate.shown(shape)}"
        )
    return shape
