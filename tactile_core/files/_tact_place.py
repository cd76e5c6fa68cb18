"""Where a file's device positions play on an array: each onto the profile's group of the same
part of the body, or one position over the whole array.

A vest file's ``VestFront`` and ``VestBack`` play at once on a profile whose layout has groups
``front`` and ``back`` (``vest-front-back``), a pair of sleeves' ``ForearmL`` and ``ForearmR`` on
groups ``left`` and ``right`` (``sleeves-pair``); :data:`POSITION_GROUPS` is the table. Each
position's 0..1 coordinates then map onto the extent of its group's actuators, and its paths
are rendered on those actuators alone (a sub-layout), so a sweep from the front to the back
lights the front's actuators, then the back's. Without such groups one position plays over the
whole array, as before.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..rendering.geometry import Grid
from ..rendering.layout import Layout

POSITION_GROUPS = {
    "VestFront": ("front",),
    "VestBack": ("back",),
    "ForearmL": ("left", "forearm-left"),
    "ForearmR": ("right", "forearm-right"),
    "Left": ("left",),
    "Right": ("right",),
    "HandL": ("left", "hand-left"),
    "HandR": ("right", "hand-right"),
    "GloveL": ("left", "glove-left"),
    "GloveR": ("right", "glove-right"),
    "FootL": ("left", "foot-left"),
    "FootR": ("right", "foot-right"),
    "Head": ("head",),
}
"""bHaptics' device positions and the layout groups each plays on, in order of preference; a
group named as the position itself (``VestFront``, any case) also matches."""


@dataclass(frozen=True, eq=False)
class Placement:
    """One position on an array: ``target`` is what its content is rendered on (the whole array
    or its group's actuators as a layout) and ``index`` the array's actuator of each of
    ``target``'s (None: the whole array, in its own order)."""

    position: str
    group: str | None
    target: object
    index: np.ndarray | None

    def full(self, i: int) -> int:
        """The array's actuator of ``target``'s actuator ``i``."""
        return int(i) if self.index is None else int(self.index[i])


def group_for(position: str, groups) -> str | None:
    """The name of the group of ``groups`` (names) that ``position`` plays on, or None."""
    by_lower = {name.lower(): name for name in groups}
    for wanted in (position.lower(), *POSITION_GROUPS.get(position, ())):
        if wanted in by_lower:
            return by_lower[wanted]
    return None


def placements(target, positions, named: str | None = None) -> tuple:
    """How ``positions`` (those with content, in the file's order) play on ``target``.

    A named position plays alone over the whole array. Otherwise every position whose group
    the layout has plays on it (two positions never share a group: the first takes it); when
    none has one, the first position plays over the whole array.
    """
    if named is not None:
        return (Placement(named, None, target, None),)
    groups = dict(target.groups)
    taken, out = set(), []
    for position in positions:
        group = group_for(position, groups)
        if group is not None and group not in taken:
            taken.add(group)
            members = np.asarray(groups[group], dtype=np.intp)
            out.append(Placement(position, group, sub_layout(target, members), members))
    if out:
        return tuple(out)
    return (Placement(positions[0], None, target, None),) if positions else ()


def sub_layout(target, members) -> Layout:
    """The actuators ``members`` of ``target`` as a layout of their own (same coordinates and
    names; the wrap kept when they go round it)."""
    xy = target.xy[members]
    wrap = target.wrap
    if wrap is not None:
        along = xy[:, wrap.index]
        if along.max() - along.min() < wrap.circumference / 2:
            wrap = None  # one side of a ring: no seam to cross
    return Layout([tuple(p) for p in xy.tolist()], [target.names[i] for i in members], wrap=wrap)


def matching_layout(places: dict):
    """The layout of a position's own motors (``{index: (x, y)}`` in 0..1, y downward), motor
    ``i`` as actuator ``i``: a :class:`Grid` when the motors fill a lattice of distinct columns
    and rows (the vest's 4 x 5, the arms' 5 x 4, the head's 7 x 1), else a layout at their
    places scaled so the closest two are one pitch apart. Returns ``(target, order)``: ``order[i]``
    is the actuator (a grid's flat cell) of motor ``i``."""
    indices = sorted(places)
    xs = sorted({round(places[i][0], 6) for i in indices})
    ys = sorted({round(places[i][1], 6) for i in indices})
    if len(xs) * len(ys) == len(indices) == len({(round(x, 6), round(y, 6))
                                                for x, y in places.values()}):  # fmt: skip
        grid = Grid(len(xs), len(ys))
        order = [xs.index(round(places[i][0], 6)) + (len(ys) - 1 - ys.index(
            round(places[i][1], 6))) * len(xs) for i in indices]  # fmt: skip
        return grid, np.asarray(order, dtype=np.intp)
    pts = np.array([(places[i][0], 1.0 - places[i][1]) for i in indices], dtype=np.float64)
    gaps = np.hypot(*(pts[:, None, :] - pts[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(gaps, np.inf)
    scale = 1.0 / float(gaps.min()) if len(pts) > 1 else 1.0
    layout = Layout([tuple(p) for p in (pts * scale).tolist()], [f"m{i}" for i in indices])
    return layout, np.arange(len(indices), dtype=np.intp)
