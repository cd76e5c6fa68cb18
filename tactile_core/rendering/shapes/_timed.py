"""A time-keyed path: points with times and intensities, as bHaptics' path mode keys them.

The point passes the vertices in order. Under ``CONST_TDM`` it reaches each vertex at that
vertex's time, so each segment takes the time between its two points' times; under
``CONST_SPEED`` it moves at one speed along the whole polyline from the first time to the last
(the times between only order the points). ``t`` in [0, 1] is the fraction of the path's
duration, so every method renders it and a trace of ``duration_s`` plays it at its own pace.

Besides its geometry the path carries an *intensity envelope* ``intensity(t)``: the points'
intensities interpolated linearly in ``t`` (each point's intensity holds at the moment the
moving point passes it), times a linear fade over the whole path. The renderer multiplies a
method's raw intensities by it before the correction (docs/decisions.md, "The envelope of a
time-keyed path"), so an envelope of 0 leaves the tactors off rather than at ``mu``.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..._shared import validate as _validate
from ._polyline import MAX_POINTS, _continues, checked_points
from ._shape import Shape, _fmt
from ._strokes import LineStrokes

PATTERNS = ("CONST_TDM", "CONST_SPEED")
"""bHaptics' moving patterns: each segment on its points' times, or one speed throughout."""
FADES = ("NONE", "FADE_IN", "FADE_OUT", "FADE_IN_OUT")
"""bHaptics' playback types, read as linear ramps over the path: 0 -> 1, 1 -> 0, 0 -> 1 -> 0."""
_SPEED_REL = 1e-9
"""Two consecutive collinear segments with speeds this close (relative) are one stroke."""


@dataclass(frozen=True)
class TimedPath(Shape):
    """A path through ``points`` reached at ``times_s``, with an intensity per point.

    Parameters
    ----------
    points : sequence of (float, float)
        2 to :data:`MAX_POINTS` vertices in grid (layout) units. Consecutive repeats are a
        pause under ``CONST_TDM`` (the point rests there between the two times).
    times_s : sequence of float
        One time per point in seconds, strictly increasing, within [0, 3600]. The path lasts
        ``times_s[-1] - times_s[0]`` (:attr:`duration_s`); ``t = 0`` is the first time.
    intensities : sequence of float, optional
        One intensity in [0, 1] per point (all 1 by default).
    pattern : {"CONST_TDM", "CONST_SPEED"}
        How the point moves between the vertices (see the module notes).
    fade : {"NONE", "FADE_IN", "FADE_OUT", "FADE_IN_OUT"}
        A linear ramp over the whole path multiplying the envelope: ``t``, ``1 - t`` or
        ``1 - |2t - 1|``.

    Examples
    --------
    >>> path = TimedPath([(0.5, 3.0), (4.5, 3.0)], [0.0, 2.0], [1.0, 0.5])
    >>> path.f(0.25), path.duration_s, float(path.intensity(0.5))
    (array([1.5, 3. ]), 2.0, 0.75)
    """

    points: tuple
    times_s: tuple
    intensities: tuple = ()
    pattern: str = "CONST_TDM"
    fade: str = "NONE"

    def __post_init__(self):
        pts = checked_points(self.points)
        n = len(pts)
        times = _numbers("times_s", self.times_s, n)
        for i, value in enumerate(times):
            _validate.in_range(f"times_s[{i}]", value, 0.0, _validate.MAX_DURATION_S)
            if i and value <= times[i - 1]:
                raise ValueError(
                    f"times_s[{i}] must be later than times_s[{i - 1}] ({times[i - 1]:g} s): "
                    f"times must increase, got {value:g}"
                )
        given = self.intensities  # () by default: every point at full intensity
        empty = isinstance(given, (tuple, list, np.ndarray)) and len(given) == 0
        levels = _numbers("intensities", (1.0,) * n if empty else given, n)
        for i, value in enumerate(levels):
            _validate.in_range(f"intensities[{i}]", value, 0.0, 1.0)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "times_s", times)
        object.__setattr__(self, "intensities", levels)
        _validate.choice("pattern", self.pattern, PATTERNS)
        _validate.choice("fade", self.fade, FADES)
        flat = self.fade == "NONE" and all(v == 1.0 for v in levels)
        object.__setattr__(self, "has_envelope", not flat)

    @property
    def duration_s(self) -> float:
        """The path's natural duration: from its first time to its last, in seconds."""
        return self.times_s[-1] - self.times_s[0]

    @cached_property
    def knots(self) -> tuple:
        """``t`` at which the point passes each vertex: the times' fractions of the duration
        (``CONST_TDM``), or of the arc length (``CONST_SPEED``; the times' fractions again for a
        path of zero length). First 0, last exactly 1."""
        t0, span = self.times_s[0], self.duration_s
        fractions = [(s - t0) / span for s in self.times_s]
        if self.pattern == "CONST_SPEED":
            steps = [math.dist(a, b) for a, b in zip(self.points, self.points[1:])]
            total = math.fsum(steps)
            if total > 0.0:
                fractions = [0.0, *(float(c) / total for c in np.cumsum(steps))]
        fractions[0], fractions[-1] = 0.0, 1.0
        return tuple(fractions)

    @cached_property
    def _tables(self):
        """Knots without repeats (a zero-length segment under ``CONST_SPEED`` takes no time:
        the later point stands for both), with x, y and the intensities there, as arrays and
        as lists."""
        keep = [i for i in range(len(self.knots)) if i == 0 or self.knots[i] > self.knots[i - 1]]
        keep[-1] = len(self.knots) - 1
        knots = [self.knots[i] for i in keep]
        xs = [self.points[i][0] for i in keep]
        ys = [self.points[i][1] for i in keep]
        levels = [self.intensities[i] for i in keep]
        arrays = tuple(np.array(v, dtype=np.float64) for v in (knots, xs, ys, levels))
        return arrays, (knots, xs, ys, levels)

    def xy(self, t):
        (knots, xs, ys, _), _ = self._tables
        return np.interp(t, knots, xs), np.interp(t, knots, ys)

    def point(self, t):
        _, (knots, xs, ys, _) = self._tables
        i = min(max(bisect.bisect_right(knots, t) - 1, 0), len(knots) - 2)
        s = min(max((t - knots[i]) / (knots[i + 1] - knots[i]), 0.0), 1.0)
        r = 1.0 - s
        return (r * xs[i] + s * xs[i + 1], r * ys[i] + s * ys[i + 1])

    def intensity(self, t) -> np.ndarray:
        """The envelope at ``t``.

        Parameters
        ----------
        t : float or array_like
            Trace parameter(s) in [0, 1] (not checked).

        Returns
        -------
        ndarray of float64, shape of ``t``
            The points' intensities interpolated linearly in ``t``, times the fade; in [0, 1].
        """
        (knots, _, _, levels), _ = self._tables
        t = np.asarray(t, dtype=np.float64)
        out = np.interp(t, knots, levels)
        if self.fade == "FADE_IN":
            out = out * t
        elif self.fade == "FADE_OUT":
            out = out * (1.0 - t)
        elif self.fade == "FADE_IN_OUT":
            out = out * (1.0 - np.abs(2.0 * t - 1.0))
        return out

    def intensity1(self, t: float) -> float:
        """Scalar :meth:`intensity` with plain floats, for the live path."""
        _, (knots, _, _, levels) = self._tables
        i = min(max(bisect.bisect_right(knots, t) - 1, 0), len(knots) - 2)
        s = min(max((t - knots[i]) / (knots[i + 1] - knots[i]), 0.0), 1.0)
        value = (1.0 - s) * levels[i] + s * levels[i + 1]
        if self.fade == "FADE_IN":
            value *= t
        elif self.fade == "FADE_OUT":
            value *= 1.0 - t
        elif self.fade == "FADE_IN_OUT":
            value *= 1.0 - abs(2.0 * t - 1.0)
        return value

    @cached_property
    def strokes(self):
        """One piece per segment that takes time; a stroke per straight run at one speed.

        Consecutive collinear segments merge into one stroke only when the point crosses them
        at the same speed, so that on every stroke ``t`` is proportional to arc length, as the
        midpoint methods (MM, IM) assume; a pause (a repeated vertex under ``CONST_TDM``) is a
        stroke of zero length.
        """
        pts, knots = self.points, self.knots
        ends, breaks, stroke_of = [], [0.0], []
        last = None  # (start, end, speed) of the previous piece
        for i in range(len(pts) - 1):
            a, b, width = pts[i], pts[i + 1], knots[i + 1] - knots[i]
            if width <= 0.0:
                continue  # a zero-length segment under CONST_SPEED: no time, no piece
            length = math.dist(a, b)
            speed = length / width
            if last is not None and _joins(last, (a, b, speed)):
                ends[-1] = (*ends[-1][:2], *b)
            else:
                ends.append((*a, *b))
            breaks.append(knots[i + 1])
            stroke_of.append(len(ends) - 1)
            last = (a, b, speed)
        breaks[-1] = 1.0
        return LineStrokes(ends, breaks, stroke_of, self.snap_tol)

    @property
    def scale(self):
        return max(abs(c) for p in self.points for c in p)

    @property
    def corners(self):
        """Parameters where the path changes direction or speed (stroke boundaries)."""
        strokes = self.strokes
        return tuple(
            float(strokes.breaks[j])
            for j in range(1, len(strokes.piece_stroke))
            if strokes.piece_stroke[j] != strokes.piece_stroke[j - 1]
        )

    @property
    def length(self) -> float:
        """Length of the path in grid units."""
        return math.fsum(math.dist(a, b) for a, b in zip(self.points, self.points[1:]))

    @property
    def spec(self):
        values = (v for p, s, i in zip(self.points, self.times_s, self.intensities)
                  for v in (*p, s, i))  # fmt: skip
        options = "".join(f";{_OPTION_OF[v]}" for v in (self.pattern, self.fade)
                          if v not in ("CONST_TDM", "NONE"))  # fmt: skip
        return "timed:" + _fmt(*values) + options

    def to_dict(self):
        return {
            "type": "timed_path",
            "points": [list(p) for p in self.points],
            "times_s": list(self.times_s),
            "intensities": list(self.intensities),
            "pattern": self.pattern,
            "fade": self.fade,
        }

    def outline(self, n=0):
        return np.array(self.points)


SPEC_OPTIONS = {"speed": ("pattern", "CONST_SPEED"), "tdm": ("pattern", "CONST_TDM"),
                "fade-in": ("fade", "FADE_IN"), "fade-out": ("fade", "FADE_OUT"),
                "fade-in-out": ("fade", "FADE_IN_OUT")}  # fmt: skip
"""The words after ``;`` in a ``timed:`` spec and what they set."""
_OPTION_OF = {value: word for word, (_, value) in SPEC_OPTIONS.items()}


def _numbers(name: str, values, n: int) -> tuple:
    """``values`` as ``n`` finite floats, or ``ValueError`` naming ``name``."""
    if isinstance(values, (str, bytes, dict)):
        raise ValueError(f"{name} must be a list of {n} numbers, got {_validate.shown(values)}")
    try:
        out = list(values)
    except TypeError:
        raise ValueError(
            f"{name} must be a list of {n} numbers, got {_validate.shown(values)}"
        ) from None
    if len(out) != n:
        raise ValueError(f"{name} must hold {n} numbers (one per point), got {len(out)}")
    return tuple(_validate.real(f"{name}[{i}]", v) for i, v in enumerate(out))


def _joins(previous, current) -> bool:
    """True when segment ``current`` continues ``previous``'s stroke: both pauses at one
    place, or collinear in the same direction at the same speed."""
    (a0, a1, v0), (b0, b1, v1) = previous, current
    if v0 == 0.0 or v1 == 0.0:
        return v0 == v1 == 0.0 and a1 == b0 == b1
    same_speed = abs(v1 - v0) <= _SPEED_REL * max(v0, v1)
    return same_speed and _continues(a0, a1, b0, b1)


def path_from_samples(times_s, points, intensities=None, *, pattern: str = "CONST_TDM"):
    """A :class:`TimedPath` from recorded samples (a mouse drag, a stream of points).

    Samples whose time does not increase are dropped (events can share a timestamp); the
    times are shifted to start at 0; more than :data:`MAX_POINTS` samples are thinned evenly,
    keeping the first and the last.

    Parameters
    ----------
    times_s : sequence of float, shape (n,)
        When each sample was taken, in seconds (any origin).
    points : sequence of (float, float), shape (n, 2)
        Where, in grid (layout) units.
    intensities : sequence of float, shape (n,), optional
        Intensity per sample in [0, 1] (1 by default).
    pattern : {"CONST_TDM", "CONST_SPEED"}
        ``CONST_TDM`` replays the drawing at its own pace.

    Returns
    -------
    TimedPath

    Raises
    ------
    ValueError
        Fewer than two samples with increasing times, or a bad value (named).
    """
    times = _numbers("times_s", times_s, len(list(times_s)))
    pts = list(points)
    if len(pts) != len(times):
        raise ValueError(f"points must hold {len(times)} points (one per time), got {len(pts)}")
    levels = [1.0] * len(times) if intensities is None else list(intensities)
    keep = []
    for i, s in enumerate(times):
        if not keep or s > times[keep[-1]]:
            keep.append(i)
    if len(keep) < 2:
        raise ValueError(
            f"a path needs at least 2 samples at increasing times, got {len(keep)} of {len(times)}"
        )
    if len(keep) > MAX_POINTS:
        picks = np.linspace(0, len(keep) - 1, MAX_POINTS).round().astype(int)
        keep = [keep[j] for j in picks]
    start = times[keep[0]]
    return TimedPath(
        [pts[i] for i in keep],
        [times[i] - start for i in keep],
        [levels[i] for i in keep],
        pattern,
    )
