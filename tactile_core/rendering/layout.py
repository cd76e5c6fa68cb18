"""Actuator layouts: where the actuators of an array are, the grid as one kind among them.

A :class:`Layout` lists actuator positions in *layout units*, where one unit is the device
profile's pitch (so shapes, radii and sigmas mean the same on a grid and on any layout). Sleeves
and belts wrap around one axis (:class:`Wrap`): coordinates along it are taken modulo the
circumference and distances are measured the short way round, so a point crossing the seam
moves on without a jump. Vests group actuators (a front and a back panel).

A :class:`~tactile_core.rendering.geometry.Grid` *is* a layout (its actuators at the cell
centres ``(col + 0.5, row + 0.5)``, in row-major order) whose :attr:`Layout.is_grid` is True:
the one property the paper's four methods ask for. Everything else — size, frame shape,
positions, distances, bounds — is asked of any layout the same way. Frames on a layout are
flat, ``(..., size)`` in actuator order; on a grid they keep ``(..., rows, cols)``
(:attr:`Layout.frame_shape`).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .._shared import validate as _validate

MAX_ACTUATORS = 1024
"""Most actuators of a layout (a device profile allows at most 255: one byte on the wire)."""
MAX_GROUPS = 64
"""Most groups of a layout (a vest's sides and panels, a sleeve's rings: a handful). 10,000
groups, which a 1 MiB profile holds, took the tuner 50 s to draw."""
MIN_SPACING = 1e-6
"""Closest two actuators may be, in layout units (closer is a duplicate)."""
AXES = ("x", "y")


@dataclass(frozen=True)
class Wrap:
    """A layout that wraps around one axis (a sleeve, a belt).

    Parameters
    ----------
    axis : {"x", "y"}
        The axis that goes round.
    circumference : float
        Length of one turn, in layout units (> 0). Coordinates along ``axis`` are taken modulo
        it; the actuators' own coordinates must lie within ``[0, circumference)``.
    """

    axis: str = "x"
    circumference: float = 1.0

    def __post_init__(self):
        _validate.choice("wrap axis", self.axis, AXES)
        c = _validate.real("wrap circumference", self.circumference)
        if not 0.0 < c <= _validate.MAX_COORD:
            raise ValueError(
                f"wrap circumference must be > 0 and at most {_validate.MAX_COORD:g}, got "
                f"{_validate.shown(self.circumference)}"
            )
        object.__setattr__(self, "circumference", c)

    @property
    def index(self) -> int:
        """0 for x, 1 for y."""
        return AXES.index(self.axis)


@dataclass(frozen=True)
class Layout:
    """Where the actuators of an array are.

    Parameters
    ----------
    positions : sequence of (x, y)
        One position per actuator, in layout units (pitches), actuator (and channel) order.
        Finite, within :data:`~tactile_core._shared.validate.MAX_COORD`, no two closer than
        :data:`MIN_SPACING`; 1 to :data:`MAX_ACTUATORS` of them.
    names : sequence of str, optional
        A short name per actuator (``"front-3"``); the index as text by default.
    wrap : Wrap, optional
        The axis that goes round, for sleeves and belts.
    groups : mapping of str to sequence of int, optional
        Named groups of actuator indices (a vest's ``front`` and ``back``); an actuator may be
        in no group or in several.

    Examples
    --------
    >>> belt = Layout([(k + 0.5, 0.5) for k in range(8)], wrap=Wrap("x", 8.0))
    >>> belt.size, belt.frame_shape, belt.is_grid
    (8, (8,), False)
    >>> round(float(belt.distances(0.2, 0.5)[7]), 6)  # across the seam: 0.2 - (-0.5)
    0.7
    """

    positions: tuple
    names: tuple = ()
    wrap: Wrap | None = None
    groups: tuple = ()

    def __post_init__(self):
        pts = _positions(self.positions)
        object.__setattr__(self, "positions", tuple(map(tuple, pts.tolist())))
        n = len(pts)
        names = tuple(self.names) if self.names else tuple(f"a{i}" for i in range(n))
        if len(names) != n or not all(isinstance(s, str) and 0 < len(s) <= 32 for s in names):
            raise ValueError(
                f"layout names must be {n} strings of 1-32 characters (one per actuator), got "
                f"{_validate.shown(self.names)}"
            )
        for i, name in enumerate(names):
            problem = name_problem(name)
            if problem:
                raise ValueError(f"layout names[{i}] {problem}")
        if len(set(names)) != n:
            twice = sorted({s for s in names if names.count(s) > 1})
            raise ValueError(f"layout names must differ, got {twice[0]!r} twice")
        object.__setattr__(self, "names", names)
        if self.wrap is not None:
            if not isinstance(self.wrap, Wrap):
                raise ValueError(f"layout wrap must be a Wrap, got {_validate.shown(self.wrap)}")
            along = pts[:, self.wrap.index]
            c = self.wrap.circumference
            bad = np.flatnonzero((along < 0.0) | (along >= c))
            if bad.size:
                i = int(bad[0])
                raise ValueError(
                    f"layout wrap: actuator {i} ({names[i]}) at {self.wrap.axis} = "
                    f"{along[i]:g} lies outside the circumference [0, {c:g})"
                )
        object.__setattr__(self, "groups", _groups(self.groups, n))
        _check_spacing(pts, self.wrap, names)

    @property
    def size(self) -> int:
        """Number of actuators."""
        return len(self.positions)

    @property
    def is_grid(self) -> bool:
        """True for a :class:`~tactile_core.rendering.geometry.Grid`: the paper's methods
        apply. False for actuators anywhere."""
        return False

    @property
    def frame_shape(self) -> tuple:
        """Shape of one frame: ``(size,)`` (a grid's is ``(rows, cols)``)."""
        return (self.size,)

    @property
    def wire_shape(self) -> tuple[int, int]:
        """``(cols, rows)`` the wire format's info announces: ``(size, 1)``, the *channel
        strip* (a grid announces its own columns and rows)."""
        return (self.size, 1)

    @property
    def xy(self) -> np.ndarray:
        """``(size, 2)`` float64: the positions as an array (read-only)."""
        return _xy(self)

    def cell_name(self, index: int) -> str:
        """The name of actuator ``index`` (as :meth:`Grid.cell_name` names a cell)."""
        return self.names[index]

    def group_of(self, index: int) -> tuple[str, ...]:
        """Names of the groups actuator ``index`` belongs to."""
        return tuple(name for name, members in self.groups if index in members)

    def canonical(self, x, y):
        """``(x, y)`` with the wrapped coordinate taken into ``[0, circumference)``."""
        x = np.asarray(x, dtype=np.float64)
        y = np.asarray(y, dtype=np.float64)
        if self.wrap is None:
            return x, y
        c = self.wrap.circumference
        if self.wrap.axis == "x":
            return np.mod(x, c), y
        return x, np.mod(y, c)

    def deltas(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Offsets from each actuator to each point, the short way round a wrap.

        Parameters
        ----------
        x, y : float or array_like, broadcast together, shape ``S``
            Points in layout units.

        Returns
        -------
        dx, dy : ndarray of float64, shape ``S + (size,)``
            ``point - actuator`` per axis; along a wrap within ``[-C/2, C/2]``.
        """
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        return _deltas(self.xy, self.wrap, x, y)

    def distances(self, x, y) -> np.ndarray:
        """Distances from each point to each actuator in layout units, ``S + (size,)``
        (along a wrap, the short way round)."""
        dx, dy = self.deltas(x, y)
        return np.hypot(dx, dy)

    def nearest(self, x: float, y: float) -> int:
        """Index of the actuator nearest to ``(x, y)`` (the lowest index on a tie)."""
        return int(np.argmin(self.distances(float(x), float(y))))

    def bounds(self, margin: float = 0.5) -> tuple[float, float, float, float]:
        """``(x0, x1, y0, y1)``: the actuators' extent plus ``margin``; along a wrap, one
        turn ``[0, circumference]``."""
        xy = self.xy
        lo = xy.min(axis=0) - margin
        hi = xy.max(axis=0) + margin
        if self.wrap is not None:
            lo[self.wrap.index] = 0.0
            hi[self.wrap.index] = self.wrap.circumference
        return (float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1]))

    def describe(self) -> str:
        """A few words: ``"8 actuators, wrapping in x (circumference 8)"``."""
        text = f"{self.size} actuator{'s' if self.size != 1 else ''}"
        if self.wrap is not None:
            text += f", wrapping in {self.wrap.axis} (circumference {self.wrap.circumference:g})"
        if self.groups:
            text += ", groups " + ", ".join(name for name, _ in self.groups)
        return text


def _positions(positions) -> np.ndarray:
    try:
        if isinstance(positions, (str, bytes)):
            raise TypeError
        pts = np.array(positions, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(
            f"layout positions must be a list of (x, y) pairs of numbers, got "
            f"{_validate.shown(positions)}"
        ) from None
    if pts.size == 0:
        raise ValueError(f"layout positions must hold 1 to {MAX_ACTUATORS} actuators, got 0")
    if pts.ndim != 2 or pts.shape[1:] != (2,):
        raise ValueError(
            f"layout positions must be a list of (x, y) pairs, got an array of shape {pts.shape}"
        )
    if not 1 <= len(pts) <= MAX_ACTUATORS:
        raise ValueError(
            f"layout positions must hold 1 to {MAX_ACTUATORS} actuators, got {len(pts)}"
        )
    bad = np.flatnonzero(~np.isfinite(pts).all(axis=1) | (np.abs(pts) > _validate.MAX_COORD).any(1))
    if bad.size:
        i = int(bad[0])
        raise ValueError(
            f"layout positions[{i}] must be finite coordinates within "
            f"{_validate.MAX_COORD:g}, got {_validate.shown(tuple(pts[i].tolist()))}"
        )
    return pts


def name_problem(name) -> str:
    """What is wrong with an actuator's name ("" if nothing): 1-32 printable characters, no
    comma or double quote, no space at either end.

    Names head the columns of ``tactile render``'s CSV and the recorder's, and label LSL's
    channels: a newline, comma or quote in one gave a header with the wrong number of columns.

    >>> name_problem("front-left")
    ''
    >>> name_problem("a,b")
    "must not hold a comma or a double quote, got 'a,b'"
    """
    if not isinstance(name, str) or not 0 < len(name) <= 32:
        return f"must be 1-32 characters, got {_validate.shown(name)}"
    if not name.isprintable():
        return f"must be printable characters (no tab, newline or control), got {name!r}"
    if "," in name or '"' in name:
        return f"must not hold a comma or a double quote, got {name!r}"
    if name != name.strip():
        return f"must not start or end with a space, got {name!r}"
    return ""


def _groups(groups, n: int) -> tuple:
    items = groups.items() if isinstance(groups, dict) else groups
    out = []
    try:
        if len(items) > MAX_GROUPS:  # each is outlined and labelled in every view of the tuner
            raise ValueError(f"layout groups: at most {MAX_GROUPS}, got {len(items)}")
        for name, members in items:
            if not isinstance(name, str) or not 0 < len(name) <= 32 or not name.isprintable():
                raise ValueError(f"layout group names must be 1-32 printable characters, got "
                                 f"{_validate.shown(name)}")  # fmt: skip
            idx = tuple(_validate.integer(f"layout group {name}", m, 0, n - 1) for m in members)
            if len(set(idx)) != len(idx):
                raise ValueError(f"layout group {name} lists an actuator twice")
            out.append((name, idx))
    except (TypeError, ValueError) as exc:
        if isinstance(exc, ValueError) and str(exc).startswith("layout group"):
            raise
        raise ValueError(
            f"layout groups must map names to lists of actuator indices 0..{n - 1}, got "
            f"{_validate.shown(groups)}"
        ) from None
    names = [name for name, _ in out]
    if len(set(names)) != len(names):
        raise ValueError("layout groups must have different names")
    return tuple(out)


def _check_spacing(pts: np.ndarray, wrap: Wrap | None, names: tuple) -> None:
    """Refuse two actuators at one place (within :data:`MIN_SPACING`, round a wrap too)."""
    if len(pts) < 2:
        return
    dx, dy = _deltas(pts, wrap, pts[:, 0], pts[:, 1])
    dist = np.hypot(dx, dy)
    np.fill_diagonal(dist, np.inf)
    pair = np.argwhere(dist < MIN_SPACING)
    if pair.size:
        i, j = sorted(pair[0].tolist())
        where = " (round the wrap)" if abs(pts[i] - pts[j]).max() >= MIN_SPACING else ""
        raise ValueError(
            f"layout positions: actuators {i} ({names[i]}) and {j} ({names[j]}) are both at "
            f"{_validate.shown(tuple(pts[i].tolist()))}{where} (duplicate positions)"
        )


def _deltas(xy: np.ndarray, wrap: Wrap | None, x, y) -> tuple[np.ndarray, np.ndarray]:
    dx = x[..., None] - xy[:, 0]
    dy = y[..., None] - xy[:, 1]
    if wrap is not None:
        c = wrap.circumference
        d = dx if wrap.axis == "x" else dy
        d -= c * np.round(d / c)
    return dx, dy


@functools.lru_cache(maxsize=64)
def _xy(layout: Layout) -> np.ndarray:
    xy = np.array(layout.positions, dtype=np.float64).reshape(-1, 2)
    xy.flags.writeable = False
    return xy


def check_layout(target, name: str = "grid") -> Layout:
    """``target`` if it is a :class:`Layout` (a :class:`~tactile_core.rendering.geometry.Grid`
    is one); otherwise ``ValueError`` naming ``name``."""
    if isinstance(target, Layout):
        return target
    raise ValueError(f"{name} must be a Grid or a Layout, got {_validate.shown(target)}")
