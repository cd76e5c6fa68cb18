"""bHaptics' coordinates on this array: a file's 0..1 motor places (y downward) mapped onto the
extent of the actuator centres, and back; a playback type's fade."""

from __future__ import annotations

from ..rendering.rasterize import check_target


def layout_box(target) -> tuple[float, float, float, float]:
    """``(x0, x1, y0, y1)``: the extent of the actuator centres of a Grid or Layout, in layout
    units (a grid's ``(0.5, cols - 0.5, 0.5, rows - 0.5)``)."""
    xy = check_target(target).xy
    return (float(xy[:, 0].min()), float(xy[:, 0].max()), float(xy[:, 1].min()),
            float(xy[:, 1].max()))  # fmt: skip


def unit_to_layout(x: float, y: float, box) -> tuple[float, float]:
    """bHaptics' ``(x, y)`` (0..1, y downward) to layout units in ``box`` (:func:`layout_box`)."""
    x0, x1, y0, y1 = box
    return (x0 + x * (x1 - x0), y1 - y * (y1 - y0))


def layout_to_unit(x: float, y: float, box) -> tuple[float, float]:
    """Layout units back to bHaptics' 0..1 (y downward), clipped to [0, 1]; an axis of zero
    extent gives 0.5."""
    x0, x1, y0, y1 = box
    u = (x - x0) / (x1 - x0) if x1 > x0 else 0.5
    v = (y1 - y) / (y1 - y0) if y1 > y0 else 0.5
    return (min(max(u, 0.0), 1.0), min(max(v, 0.0), 1.0))


def fade1(fade: str, u: float) -> float:
    """A playback type's factor at ``u`` in [0, 1] of its span (linear ramps)."""
    if fade == "FADE_IN":
        return u
    if fade == "FADE_OUT":
        return 1.0 - u
    if fade == "FADE_IN_OUT":
        return 1.0 - abs(2.0 * u - 1.0)
    return 1.0
