"""bHaptics' play-time options on a file's content: ``ScaleOption`` and ``RotationOption``.

The SDK sends them with a registered file to its Player (``submitRegistered(key, altKey,
ScaleOption, RotationOption)`` in ``src/hapticsManager.cpp``; the structs in
``include/shared/model.h`` of bhaptics/haptic-library), which applies them; the Player's code is
not published, so this module follows the SDK's own definitions:

- ``ScaleOption{Intensity, Duration}``: "the value multiplied by the original value" (the
  Unity SDK's ``PlayParam``); the 2017 SDK's ``FeedbackSignal.Copy`` multiplies each motor value
  by the intensity (capped at 100) and stretches the frames' times by the duration.
- ``RotationOption{OffsetAngleX, OffsetY}``: the angle "rotates around global Vector3.up
  (0~360)" and the offset "moves up and down (-0.5~0.5)"; it "applies to only VestHapticClip".
  The SDK computes both from a hit (``HapticClip.Play(contactPos, targetPos, targetForward,
  targetHeight)`` with ``BhapticsUtils.Angle``): the angle is 0 for a hit from the front and
  grows towards the wearer's left (90) and back (180); the offset is the hit's height above
  the vest's centre in vest heights.

So the two vest panels are one ring round the body: the front's ``x`` (0 at the wearer's right,
1 at the left, as seen from the front) is the ring's ``r = x``, the back's (0 at the wearer's
left, as seen from behind) ``r = 1 + x``, ``r`` modulo 2. Rotating by ``angle`` degrees adds
``angle / 180`` to ``r``: a pattern on the front's middle turned by 90 plays on the wearer's
left side, by 180 on the back's middle. The offset moves the pattern up: ``y - offset``
(bHaptics' y grows downwards); what leaves the panel does not play. A path crossing a side of
the body is cut there into one path on each panel, at the time it crosses.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass

from .._shared import validate as _validate
from ._tact_coords import fade1
from ._tact_records import TactPath

VEST = ("VestFront", "VestBack")
MAX_SCALE = 100.0
"""Largest intensity or duration multiplier."""


@dataclass(frozen=True)
class ScaleOption:
    """bHaptics' ``ScaleOption``: multipliers of a file's intensities and times.

    Parameters
    ----------
    intensity : float
        Every intensity times this, capped at 1; in [0, 100].
    duration : float
        Every time (starts, ends, points' times) times this: 2 plays the file at half speed;
        in (0, 100].
    """

    intensity: float = 1.0
    duration: float = 1.0

    def __post_init__(self):
        intensity = _validate.in_range("intensity", self.intensity, 0.0, MAX_SCALE)
        object.__setattr__(self, "intensity", intensity)
        duration = _validate.positive("duration", self.duration)
        if duration > MAX_SCALE:
            raise ValueError(f"duration must be at most {MAX_SCALE:g}, got {duration:g}")
        object.__setattr__(self, "duration", duration)

    @property
    def identity(self) -> bool:
        return self.intensity == 1.0 and self.duration == 1.0


@dataclass(frozen=True)
class RotationOption:
    """bHaptics' ``RotationOption`` for the vest (``VestFront`` and ``VestBack``).

    Parameters
    ----------
    angle_deg : float
        ``OffsetAngleX``: degrees round the body, 0 = as designed, 90 = a quarter turn towards the
        wearer's left, 180 = front and back swapped; any finite value (taken modulo 360).
    offset_y : float
        ``OffsetY``: how far up the pattern moves, in panel heights, in [-1, 1] (bHaptics' SDK
        gives -0.5..0.5).
    """

    angle_deg: float = 0.0
    offset_y: float = 0.0

    def __post_init__(self):
        angle = _validate.real("angle_deg", self.angle_deg)
        object.__setattr__(self, "angle_deg", math.fmod(angle, 360.0) % 360.0)
        offset = _validate.in_range("offset_y", self.offset_y, -1.0, 1.0)
        object.__setattr__(self, "offset_y", offset)

    @property
    def identity(self) -> bool:
        return self.angle_deg == 0.0 and self.offset_y == 0.0


def scaled(paths, dots, scale: ScaleOption) -> tuple[list, list]:
    """``paths`` and ``dots`` (:class:`TactPath`, :class:`TactDot`) with ``scale`` applied."""
    if scale.identity:
        return list(paths), list(dots)
    k, d = scale.intensity, scale.duration
    paths = [dataclasses.replace(p, times_s=tuple(t * d for t in p.times_s),
                                 intensities=tuple(min(v * k, 1.0) for v in p.intensities))
             for p in paths]  # fmt: skip
    dots = [dataclasses.replace(o, start_s=o.start_s * d, end_s=o.end_s * d,
                                intensity=min(o.intensity * k, 1.0)) for o in dots]  # fmt: skip
    return paths, dots


def rotated(paths, dots, rotation: RotationOption) -> tuple[list, list]:
    """``paths`` and ``dots`` with the vest's content turned round the body and moved up (see
    the module notes); other positions are left as they are."""
    if rotation.identity:
        return list(paths), list(dots)
    shift = rotation.angle_deg / 180.0
    out_dots = []
    for dot in dots:
        if dot.position not in VEST:
            out_dots.append(dot)
            continue
        y = dot.y - rotation.offset_y
        if not 0.0 <= y <= 1.0:
            continue  # moved off the vest
        position, x = _panel(_ring(dot.position, dot.x) + shift) if shift else (dot.position, dot.x)
        out_dots.append(dataclasses.replace(dot, position=position, x=x, y=y))
    out_paths = []
    for path in paths:
        if path.position not in VEST:
            out_paths.append(path)
        else:
            out_paths.extend(_rotate_path(path, shift, rotation.offset_y))
    return out_paths, out_dots


def _ring(position: str, x: float) -> float:
    return x if position == "VestFront" else 1.0 + x


def _panel(r: float) -> tuple[str, float]:
    """The panel and its x of ring coordinate ``r``; on a side of the body (``r`` whole) the
    panel that starts there: the front's x = 0 at the right side, the back's x = 0 at the
    left."""
    r = r % 2.0
    return ("VestFront", r) if r < 1.0 else ("VestBack", r - 1.0)


def _rotate_path(path: TactPath, shift: float, offset: float) -> list:
    """A path turned by ``shift`` (ring units) and moved up by ``offset``: cut where it crosses
    a side of the body or leaves the panel, its pieces ``CONST_TDM`` with the fade folded into
    the intensities (exact where a segment's intensity is constant)."""
    times = list(path.times_s)
    if path.pattern == "CONST_SPEED":
        times = _speed_times(path.points, times)
    t0, t1 = times[0], times[-1]
    span = t1 - t0
    points = [(_ring(path.position, x) + shift, y - offset) for x, y in path.points]
    samples = []  # (time, r, y, intensity) at every vertex and every cut
    for k in range(len(points) - 1):
        (ra, ya), (rb, yb) = points[k], points[k + 1]
        ta, tb = times[k], times[k + 1]
        ia, ib = path.intensities[k], path.intensities[k + 1]
        cuts = {0.0, 1.0}
        for lo, hi, value in ((ra, rb, None), (ya, yb, 0.0), (ya, yb, 1.0)):
            if value is None:  # every side of the body (a whole ring unit) crossed
                for n in range(math.floor(min(lo, hi)) + 1, math.ceil(max(lo, hi))):
                    cuts.add((n - lo) / (hi - lo))
            elif (lo - value) * (hi - value) < 0.0:
                cuts.add((value - lo) / (hi - lo))
        if path.fade == "FADE_IN_OUT" and span > 0 and ta < t0 + span / 2 < tb:
            cuts.add((t0 + span / 2 - ta) / (tb - ta))  # the fade's peak
        for u in sorted(cuts):
            samples.append((ta + u * (tb - ta), ra + u * (rb - ra), ya + u * (yb - ya),
                            ia + u * (ib - ia)))  # fmt: skip
    pieces, current, where = [], [], None  # runs of samples on one panel, inside it
    for a, b in itertools.pairwise(samples):
        if b[0] <= a[0]:
            continue
        mid_r, mid_y = (a[1] + b[1]) / 2, (a[2] + b[2]) / 2
        panel = math.floor(mid_r) if shift else 0 if path.position == "VestFront" else 1
        here = panel if 0.0 <= mid_y <= 1.0 else None  # the panel's start on the ring
        if here != where or not current:
            if len(current) > 1 and where is not None:
                pieces.append((where, current))
            current, where = [a], here
        current.append(b)
    if len(current) > 1 and where is not None:
        pieces.append((where, current))
    out = []
    for base, run in pieces:
        panel = "VestFront" if base % 2 == 0 else "VestBack"
        pts = tuple((min(max(r - base, 0.0), 1.0), min(max(y, 0.0), 1.0)) for _, r, y, _ in run)
        levels = tuple(min(max(i * fade1(path.fade, (t - t0) / span if span else 0.0), 0.0), 1.0)
                       for t, _, _, i in run)  # fmt: skip
        out.append(TactPath(panel, pts, tuple(t for t, *_ in run), levels, "CONST_TDM", "NONE",
                            path.field))  # fmt: skip
    return out


def _speed_times(points, times) -> list:
    """The times a ``CONST_SPEED`` path passes its vertices (one speed along its length in the
    file's 0..1 coordinates)."""
    lengths = [math.dist(a, b) for a, b in itertools.pairwise(points)]
    total = sum(lengths)
    if total == 0.0:
        return list(times)
    out, run = [times[0]], 0.0
    for length in lengths:
        run += length
        out.append(times[0] + (times[-1] - times[0]) * run / total)
    return out


def option(kind, value):
    """``value`` as a ``kind`` (:class:`ScaleOption` or :class:`RotationOption`): the option
    itself, a pair of numbers, or None for none."""
    if value is None:
        return kind()
    if isinstance(value, kind):
        return value
    name = "scale" if kind is ScaleOption else "rotation"
    try:
        first, second = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a {kind.__name__} or a pair of numbers, got "
                         f"{_validate.shown(value)}") from None  # fmt: skip
    return kind(first, second)
