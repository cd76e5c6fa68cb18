"""The parts of a pattern: an :class:`Effect` and what it plays (a shape, :class:`Dots`, an
imported ``.tact`` effect as :class:`TactEffect`).

Every value here is immutable and checked when it is made; a refusal is a ``ValueError`` whose
message starts with the field's name as the pattern file spells it (``envelope[1].time_s must
be ...``), so that the file reader only puts ``effects[3].`` in front of it.
"""

from __future__ import annotations

import bisect
import dataclasses
from dataclasses import dataclass
from functools import cached_property

from .._shared import validate as _validate
from ..device.waveform import parse_waveform
from ..rendering.layout import MAX_ACTUATORS
from ..rendering.methods import get_method
from ..rendering.shapes import FADES, Shape, TimedPath

MAX_DOTS = 10_000
"""Most dots in one effect."""
MAX_KEYFRAMES = 1_000
"""Most keyframes in one envelope."""
MAX_REPEAT = 10_000
"""Most repetitions of one effect."""
MAX_TRACKS = 1_000
"""Tracks are numbered 0 .. MAX_TRACKS - 1."""
MAX_TEXT_CHARS = 200
"""Longest name of a pattern or an effect, of a group or a device position."""
GROUP_CHARS = 32
"""Longest group name (as a layout allows)."""
MAX_EFFECTS = 10_000
"""Most effects in a pattern (bHaptics' Designer files hold tens; the issue's bulk ask, 400)."""
MAX_TOTAL_POINTS = 200_000
"""Most path points and dots in a pattern, all effects together (as a ``.tact`` file)."""
MAX_NOTES_CHARS = 10_000
"""Longest notes of a pattern."""
COMBINE = ("max", "sum")
"""How overlapping effects combine per actuator: the maximum, or the sum clipped to 1."""


def _text(name: str, value, longest: int = MAX_TEXT_CHARS, *, empty: bool = True) -> str:
    if not isinstance(value, str) or len(value) > longest or (not empty and not value):
        least = "0" if empty else "1"
        raise ValueError(f"{name} must be a string of {least} to {longest} characters, got "
                         f"{_validate.shown(value)}")  # fmt: skip
    if not value.isprintable():
        raise ValueError(f"{name} must be printable characters, got {value!r}")
    return value


@dataclass(frozen=True)
class Dot:
    """One actuator on at one intensity for a while.

    Parameters
    ----------
    at : int or (float, float)
        The actuator: its index on the array, or a place ``(x, y)`` in layout units (pitches;
        in a :class:`TactEffect`, bHaptics' 0..1 with y downward) whose nearest actuator plays.
    intensity : float
        Raw intensity in [0, 1] (before the correction).
    start_s : float
        When it comes on, in seconds from the start of its effect.
    duration_s : float
        How long it stays on, in seconds (> 0).
    fade : {"NONE", "FADE_IN", "FADE_OUT", "FADE_IN_OUT"}
        A linear ramp over its span (bHaptics' playback types).
    """

    at: int | tuple
    intensity: float = 1.0
    start_s: float = 0.0
    duration_s: float = 0.1
    fade: str = "NONE"

    def __post_init__(self):
        at = self.at
        if _validate.is_number(at) and not isinstance(at, float):
            at = _validate.integer("at", at, 0, MAX_ACTUATORS - 1)
        else:
            at = _validate.point("at", at)
        object.__setattr__(self, "at", at)
        object.__setattr__(self, "intensity",
                           _validate.in_range("intensity", self.intensity, 0.0, 1.0))  # fmt: skip
        object.__setattr__(self, "start_s", _validate.in_range(
            "start_s", self.start_s, 0.0, _validate.MAX_DURATION_S))  # fmt: skip
        object.__setattr__(self, "duration_s", _validate.duration("duration_s", self.duration_s))
        _validate.choice("fade", self.fade, FADES)

    @property
    def end_s(self) -> float:
        """When it goes off, in seconds from the start of its effect."""
        return self.start_s + self.duration_s

    def to_dict(self) -> dict:
        """The JSON form (``docs/patterns.md``)."""
        at = self.at if isinstance(self.at, int) else list(self.at)
        out = {"at": at, "intensity": self.intensity, "start_s": self.start_s,
               "duration_s": self.duration_s}  # fmt: skip
        if self.fade != "NONE":
            out["fade"] = self.fade
        return out


def _dot_tuple(name: str, dots, most: int) -> tuple:
    if isinstance(dots, (str, bytes, dict)) or not hasattr(dots, "__len__"):
        raise ValueError(f"{name} must be a list of Dot, got {_validate.shown(dots)}")
    if len(dots) > most:
        raise ValueError(f"{name} holds {len(dots)} dots, more than the {most} allowed")
    for i, dot in enumerate(dots):
        if not isinstance(dot, Dot):
            raise ValueError(f"{name}[{i}] must be a Dot, got {_validate.shown(dot)}")
    return tuple(dots)


@dataclass(frozen=True)
class Dots:
    """A set of dots played together: taps, a chord of actuators, a beat.

    Parameters
    ----------
    dots : sequence of Dot
        1 to :data:`MAX_DOTS` of them; their times count from the start of the effect.

    Examples
    --------
    >>> taps = Dots([Dot(12, 0.8, start_s=0.0, duration_s=0.1), Dot(12, 0.8, start_s=0.3)])
    >>> taps.duration_s
    0.4
    """

    dots: tuple

    def __post_init__(self):
        dots = _dot_tuple("dots", self.dots, MAX_DOTS)
        if not dots:
            raise ValueError("dots must hold at least one Dot, got none")
        object.__setattr__(self, "dots", dots)

    @property
    def duration_s(self) -> float:
        """When the last dot goes off, in seconds from the effect's start."""
        return max(d.end_s for d in self.dots)


@dataclass(frozen=True)
class TactEffect:
    """One effect of a bHaptics ``.tact`` file, as imported: paths and dots in bHaptics'
    0..1 coordinates (y downward) of its device position, mapped onto the actuators of the
    effect's group (or of the whole array) when it plays, as ``docs/tact.md`` maps a file.

    Parameters
    ----------
    paths : sequence of TimedPath
        Points in [0, 1], times in seconds from the effect's start.
    dots : sequence of Dot
        Each ``at`` a motor's place ``(x, y)`` in [0, 1].
    length_s : float
        The effect's length (bHaptics' ``offsetTime``), at least as long as its content.
    position : str
        The device position it was written for (``"VestFront"``), "" if unknown.
    """

    paths: tuple = ()
    dots: tuple = ()
    length_s: float = 0.0
    position: str = ""

    def __post_init__(self):
        paths = tuple(self.paths) if isinstance(self.paths, (list, tuple)) else self.paths
        if not isinstance(paths, tuple):
            raise ValueError(f"paths must be a list of TimedPath, got {_validate.shown(paths)}")
        for i, path in enumerate(paths):
            if not isinstance(path, TimedPath):
                raise ValueError(f"paths[{i}] must be a TimedPath, got {_validate.shown(path)}")
            for k, point in enumerate(path.points):
                if not (0.0 <= point[0] <= 1.0 and 0.0 <= point[1] <= 1.0):
                    raise ValueError(f"paths[{i}].points[{k}] must lie within [0, 1] x [0, 1] "
                                     f"(bHaptics' coordinates), got {point}")  # fmt: skip
        dots = _dot_tuple("dots", self.dots, MAX_DOTS)
        for i, dot in enumerate(dots):
            if isinstance(dot.at, int) or not all(0.0 <= c <= 1.0 for c in dot.at):
                raise ValueError(f"dots[{i}].at must be a place (x, y) within [0, 1] x [0, 1] "
                                 f"(bHaptics' coordinates), got "
                                 f"{_validate.shown(dot.at)}")  # fmt: skip
        if not paths and not dots:
            raise ValueError("a .tact effect must hold a path or a dot, got neither")
        object.__setattr__(self, "paths", paths)
        object.__setattr__(self, "dots", dots)
        content = max([p.times_s[-1] for p in paths] + [d.end_s for d in dots])
        length = _validate.duration("length_s", self.length_s, allow_zero=True)
        if length < content:
            raise ValueError(f"length_s must be at least {content:g} s (when its content ends), "
                             f"got {length:g}")  # fmt: skip
        object.__setattr__(self, "length_s", length)
        _text("position", self.position, 64)

    @property
    def duration_s(self) -> float:
        """The effect's length in seconds."""
        return self.length_s


CONTENTS = (Shape, Dots, TactEffect)


def natural_duration(content) -> float | None:
    """How long ``content`` lasts on its own, in seconds (None for a shape without times)."""
    if isinstance(content, (TimedPath, Dots, TactEffect)):
        return content.duration_s
    return None


def _envelope(envelope, duration_s: float) -> tuple:
    """Checked keyframes ``((time_s, gain), ...)``."""
    if isinstance(envelope, (str, bytes, dict)) or not hasattr(envelope, "__len__"):
        raise ValueError(f"envelope must be a list of (time_s, gain) pairs, got "
                         f"{_validate.shown(envelope)}")  # fmt: skip
    if len(envelope) > MAX_KEYFRAMES:
        raise ValueError(f"envelope holds {len(envelope)} keyframes, more than the "
                         f"{MAX_KEYFRAMES} allowed")  # fmt: skip
    out = []
    for i, pair in enumerate(envelope):
        if isinstance(pair, (str, bytes, dict)) or not hasattr(pair, "__len__") or len(pair) != 2:
            raise ValueError(f"envelope[{i}] must be a pair (time_s, gain), got "
                             f"{_validate.shown(pair)}")  # fmt: skip
        time_s = _validate.real(f"envelope[{i}].time_s", pair[0])
        if not 0.0 <= time_s <= duration_s:
            raise ValueError(f"envelope[{i}].time_s must be within [0, {duration_s:g}] (the "
                             f"effect's duration_s), got {_validate.shown(time_s)}")  # fmt: skip
        if out and time_s <= out[-1][0]:
            raise ValueError(f"envelope[{i}].time_s must be later than envelope[{i - 1}]."
                             f"time_s ({out[-1][0]:g} s): times must increase, got "
                             f"{time_s:g}")  # fmt: skip
        gain = _validate.in_range(f"envelope[{i}].gain", pair[1], 0.0, 1.0)
        out.append((time_s, gain))
    return tuple(out)


@dataclass(frozen=True)
class Effect:
    """One item of a pattern's time line: what plays, when, how long, how, how loud, where.

    Parameters
    ----------
    content : Shape, Dots or TactEffect
        A shape traced over the effect (a line, circle, square, polyline, or a drawn or
        time-keyed path, in layout units), a set of dots, or an imported ``.tact`` effect.
    start_s : float
        When it starts, in seconds from the pattern's start.
    duration_s : float, optional
        How long one play of it takes, in seconds. By default the content's own duration (a
        time-keyed path's, the dots' last end, the ``.tact`` effect's length); a line,
        circle, square or polyline has none and needs one. A shape is traced over the whole
        play (a time-keyed path faster or slower to fit); dots and a ``.tact`` effect keep
        their own times, and what would play after the end of a play is cut (a tap of
        0.1 s in a play of 0.3 s is a tap and a pause).
    method : str, optional
        The rendering method of its shapes (``"TB"``: a Tactile Brush stroke; ``"RO:r=1.5"``);
        None: the scene's. Dots light their actuators whatever the method.
    envelope : sequence of (time_s, gain)
        Keyframes over one play: ``time_s`` within ``[0, duration_s]`` and increasing,
        ``gain`` in [0, 1]; the gain is linear between them and holds the first's before it
        and the last's after it. Empty (default): gain 1 throughout. It multiplies the raw
        intensities, before the correction (0 stays off).
    repeat : int
        How many times it plays, back to back (1 to :data:`MAX_REPEAT`).
    group : str, optional
        The layout group it plays on (a vest's ``"front"``); only those actuators light.
        None: every actuator.
    track : int
        The editor's row it sits on (0 to ``MAX_TRACKS - 1``); it does not change what plays.
    name : str
        A label, "" by default.
    waveform : Waveform or str, optional
        What the actuators it lights play on an audio interface (a
        :class:`~tactile_core.device.waveform.Waveform` or its spec: ``"square:200"``,
        ``"sweep:100-300:500ms"``, ``"noise"``); a frequency left out is the channel's carrier.
        None: the device profile's waveform. A serial array plays levels only.

    Examples
    --------
    >>> from tactile_core.rendering.shapes import Line
    >>> stroke = Effect(Line((0.5, 0.5), (4.5, 5.5)), start_s=0.2, duration_s=0.5, repeat=2)
    >>> stroke.end_s
    1.2
    """

    content: object
    start_s: float = 0.0
    duration_s: float | None = None
    method: str | None = None
    envelope: tuple = ()
    repeat: int = 1
    group: str | None = None
    track: int = 0
    name: str = ""
    waveform: object = None

    def __post_init__(self):
        content = self.content
        if isinstance(content, (list, tuple)) and content and isinstance(content[0], Dot):
            content = Dots(tuple(content))  # a list of dots is a Dots
        if not isinstance(content, CONTENTS):
            raise ValueError(f"content must be a shape, a Dots or a TactEffect, got "
                             f"{_validate.shown(content)}")  # fmt: skip
        object.__setattr__(self, "content", content)
        start = _validate.in_range("start_s", self.start_s, 0.0, _validate.MAX_DURATION_S)
        object.__setattr__(self, "start_s", start)
        duration = self.duration_s
        if duration is None:
            duration = natural_duration(content)
            if duration is None:
                kind = type(content).__name__.lower()
                raise ValueError(f"duration_s must be given for a {kind}: it has no duration of "
                                 "its own")  # fmt: skip
            if duration <= 0.0:
                raise ValueError(f"duration_s must be given: the content lasts {duration:g} s")
        object.__setattr__(self, "duration_s", _validate.duration("duration_s", duration))
        if self.method is not None:
            object.__setattr__(self, "method", get_method(self.method).spec)
        object.__setattr__(self, "envelope", _envelope(self.envelope, self.duration_s))
        object.__setattr__(self, "repeat", _validate.integer("repeat", self.repeat, 1, MAX_REPEAT))
        if self.group is not None:
            _text("group", self.group, GROUP_CHARS, empty=False)
        object.__setattr__(self, "track",
                           _validate.integer("track", self.track, 0, MAX_TRACKS - 1))  # fmt: skip
        _text("name", self.name)
        if self.waveform is not None:
            object.__setattr__(self, "waveform", parse_waveform(self.waveform))
        end = self.end_s
        if end > _validate.MAX_DURATION_S * (1.0 + 1e-12):
            raise ValueError(f"repeat {self.repeat} of {self.duration_s:g} s from start_s "
                             f"{self.start_s:g} ends the effect at {end:g} s, after the "
                             f"{_validate.MAX_DURATION_S:g} s a pattern may last")  # fmt: skip

    @property
    def end_s(self) -> float:
        """When its last play ends, in seconds from the pattern's start."""
        return self.start_s + self.duration_s * self.repeat

    @property
    def kind(self) -> str:
        """``"shape"``, ``"dots"`` or ``"tact"``: the key of its content in the file."""
        if isinstance(self.content, Dots):
            return "dots"
        if isinstance(self.content, TactEffect):
            return "tact"
        return "shape"

    def gain1(self, phase_s: float) -> float:
        """The envelope's gain ``phase_s`` seconds into one play (1 without keyframes): on the
        segment that ends at the first keyframe at or after ``phase_s``."""
        env = self.envelope
        if not env:
            return 1.0
        if phase_s <= env[0][0]:
            return env[0][1]
        if phase_s > env[-1][0]:
            return env[-1][1]
        j = bisect.bisect_left(self._key_times, phase_s)
        (t0, g0), (t1, g1) = env[j - 1], env[j]
        return g0 + (g1 - g0) * (phase_s - t0) / (t1 - t0)

    @cached_property
    def _key_times(self) -> list:
        return [t for t, _ in self.envelope]

    def replace(self, **changes) -> Effect:
        """A copy with ``changes`` (checked). Changing ``duration_s`` of an effect whose content
        has a duration of its own keeps the given value (the content is played to fit)."""
        return dataclasses.replace(self, **changes)

    def points(self) -> int:
        """How many path points and dots it holds (what the pattern's bounds count)."""
        content = self.content
        if isinstance(content, Dots):
            return len(content.dots)
        if isinstance(content, TactEffect):
            return len(content.dots) + sum(len(p.points) for p in content.paths)
        return len(getattr(content, "points", ())) or 2
