"""A pattern's effects on one array, as *parts*: each shape or ``.tact`` path a stroke drawn
by its method over each play, each dot a dot part; checked against the array (its groups, its
actuators, the methods that render there). :mod:`._pattern_frames` finds and combines them."""

from __future__ import annotations

import numpy as np

from ..rendering.methods import get_method, layout_sampler
from ..rendering.rasterize import check_renders, layout_entries, point_entries
from ..rendering.shapes import FADES, TimedPath
from ._pattern_effects import Dots, TactEffect
from ._tact_coords import unit_to_layout

MARGIN_S = 1e-9
"""Widens a part's window in the index by far more than the rounding of ``start + a``."""


class Part:
    """One stroke or dot of an effect on this array (see the module notes)."""

    __slots__ = ("a", "actuator", "b", "effect", "end", "entries", "fade", "hi", "index",
                 "level", "lo", "mask", "mask_vec", "method", "period", "repeat", "shape",
                 "start", "stop")  # fmt: skip

    def __init__(self, effect, index: int, a: float, b: float):
        self.effect, self.index = effect, index
        self.start, self.end = effect.start_s, effect.end_s
        self.period, self.repeat = effect.duration_s, effect.repeat
        self.a, self.b = a, b  # its span within a play (u runs from 0 at a to 1 at b)...
        self.stop = min(b, self.period)  # ...cut at the play's end
        # when it may be on: its own window in a single play, else the effect's whole span
        # (widened by far more than the rounding of ``start + a``)
        single = effect.repeat == 1
        self.lo = self.start + a - MARGIN_S if single else self.start
        self.hi = self.start + self.stop + MARGIN_S if single else self.end
        self.shape = self.method = self.entries = self.mask = self.mask_vec = None
        self.actuator, self.level, self.fade = -1, 0.0, 0


def group_members(effect, index: int, target) -> tuple | None:
    """The actuators of ``effect``'s group on ``target`` (None: all); ``ValueError`` naming
    ``effects[index].group`` when the layout has no such group."""
    if effect.group is None:
        return None
    return layout_group(target, effect.group, f"effects[{index}].group")


def layout_group(target, name: str, field: str) -> tuple:
    """The actuators of group ``name`` of ``target``; ``ValueError`` naming ``field`` when the
    layout has no such group."""
    groups = dict(target.groups)
    if name not in groups:
        held = ", ".join(groups) if groups else "it has none"
        raise ValueError(f"{field} must name a group of the layout ({held}), got {name!r}")
    return groups[name]


def _entries_of(method, target):
    """``entries(shape, t)``: the raw ``((index, value), ...)`` of ``method`` on ``target``."""
    if not target.is_grid:
        sampler = layout_sampler(method, target)
        return lambda shape, t: layout_entries(shape, sampler, t)
    sample1, cols, rows = method.sample1, target.cols, target.rows
    return lambda shape, t: point_entries(shape, sample1, t, cols, rows)


def _nearest(target, members, x: float, y: float) -> int:
    """The actuator of ``members`` (None: all) nearest to ``(x, y)``, the lowest on a tie."""
    if members is None:
        return target.nearest(x, y)
    d = target.distances(float(x), float(y))[list(members)]
    return int(members[int(np.argmin(d))])


def compile_parts(pattern, method, target) -> list:
    """The parts of ``pattern`` on ``target`` with the scene's ``method`` (a Method): strokes
    first, then dots, each in the order of the effects.

    Raises
    ------
    ValueError
        Naming the field: a group the layout lacks (``effects[2].group``), a dot's actuator
        beyond the layout or outside its effect's group (``effects[0].dots[3].at``), an
        effect's method that does not render on this layout (``effects[1].method``).
    """
    strokes, dots = [], []
    for i, effect in enumerate(pattern.effects):
        _Effect(effect, i, method, target).parts(strokes, dots)
    return strokes + dots


class _Effect:
    """One effect on ``target``: its group and method, and its parts."""

    def __init__(self, effect, index: int, method, target):
        self.effect, self.index, self.target = effect, index, target
        self.members = group_members(effect, index, target)
        self.mask = self.mask_vec = None
        if self.members is not None:
            self.mask = frozenset(self.members)
            self.mask_vec = np.zeros(target.size)
            self.mask_vec[list(self.members)] = 1.0
        self.method = method
        if effect.method is not None:
            self.method = get_method(effect.method)
            try:
                check_renders(self.method, target)
            except ValueError as exc:
                raise ValueError(f"effects[{index}].method {effect.method}: {exc}") from None

    def parts(self, strokes: list, dots: list) -> None:
        """Append the effect's strokes and dots (those that start within a play: dots and
        ``.tact`` content keep their own times and are cut at the end of the play)."""
        content, target, members = self.effect.content, self.target, self.members
        first_stroke, first_dot = len(strokes), len(dots)  # only this effect's are filtered
        if isinstance(content, Dots):
            for j, d in enumerate(content.dots):
                at = d.at if isinstance(d.at, int) else _nearest(target, members, *d.at)
                dots.append(self.dot(d, at, f"dots[{j}]"))
        elif isinstance(content, TactEffect):
            box = _box(target, members)
            for path in content.paths:
                points = [unit_to_layout(x, y, box) for x, y in path.points]
                shape = TimedPath(points, path.times_s, path.intensities, path.pattern, path.fade)
                strokes.append(self.stroke(shape, path.times_s[0], path.times_s[-1]))
            for j, d in enumerate(content.dots):
                at = _nearest(target, members, *unit_to_layout(*d.at, box))
                dots.append(self.dot(d, at, f"tact.dots[{j}]"))
        else:  # a shape: traced over the whole play, whatever its own duration
            strokes.append(self.stroke(content, 0.0, self.effect.duration_s))
        strokes[first_stroke:] = [p for p in strokes[first_stroke:] if p.a < p.stop]
        dots[first_dot:] = [p for p in dots[first_dot:] if p.a < p.stop]

    def stroke(self, shape, a_s: float, b_s: float) -> Part:
        """A stroke over ``[a_s, b_s]`` of a play."""
        part = Part(self.effect, self.index, a_s, b_s)
        part.shape, part.mask, part.mask_vec = shape, self.mask, self.mask_vec
        part.method = self.method.on_clock(part.b - part.a)  # TB: onsets over this stroke
        part.entries = _entries_of(part.method, self.target)
        return part

    def dot(self, dot, actuator: int, field: str) -> Part:
        """A dot part lighting ``actuator``; ``ValueError`` naming ``field`` if it may not."""
        size, i = self.target.size, self.index
        if not 0 <= actuator < size:
            raise ValueError(f"effects[{i}].{field}.at is actuator {actuator}, but the layout "
                             f"has {size} (0 to {size - 1})")  # fmt: skip
        if self.mask is not None and actuator not in self.mask:
            raise ValueError(f"effects[{i}].{field}.at is actuator {actuator}, which is not in "
                             f"the effect's group {self.effect.group!r}")  # fmt: skip
        part = Part(self.effect, i, dot.start_s, dot.end_s)
        part.actuator, part.level, part.fade = actuator, dot.intensity, FADES.index(dot.fade)
        return part


def _box(target, members) -> tuple[float, float, float, float]:
    """The extent ``(x0, x1, y0, y1)`` of the centres of ``members`` (None: all actuators)."""
    xy = target.xy if members is None else target.xy[list(members)]
    return (float(xy[:, 0].min()), float(xy[:, 0].max()), float(xy[:, 1].min()),
            float(xy[:, 1].max()))  # fmt: skip
