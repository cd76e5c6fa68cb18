"""A pattern played from a moment of it, or held at that moment: the frame source an editor
plays from its playhead and shows while it is scrubbed (``Scene(source=PatternCue(...))``)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from .._shared import validate as _validate
from ._pattern_model import Pattern


@dataclass(frozen=True)
class PatternCue:
    """A pattern from ``start_s`` on, or (``hold=True``) its frame at ``start_s`` for as long as
    it plays: a frame source like the pattern itself.

    A stream that plays a cue from its beginning plays the pattern's frames from the one that
    contains ``start_s`` (frame ``k`` of the cue is the pattern's frame ``k0 + k``, ``k0 =
    floor(start_s * rate)``), and after the pattern's end nothing. Held, every frame is the
    pattern's frame ``k0`` (the last one for a ``start_s`` at or past the end), the way a
    scene's ``hold_s`` holds a trace. Its curves, outlines and duration are the pattern's (an
    editor's views show the whole pattern, the cursor at :meth:`pattern_time_s`).

    Parameters
    ----------
    pattern : Pattern
    start_s : float
        Seconds into the pattern, 0 to an hour.
    hold : bool
        Hold that instant rather than play on from it.

    Examples
    --------
    >>> import tactile_core as tc
    >>> taps = tc.Pattern().add(tc.Dots([tc.Dot(14, 0.5)]), start_s=0.2, duration_s=0.3)
    >>> cue = PatternCue(taps, 0.25, hold=True)
    >>> frames = cue.live("AS", tc.Grid(5, 6), tc.Sampling(10.0), 0.0, 1.0)
    >>> frames.entries(0), frames.entries(7)  # frame 2 of the pattern (0.2 to 0.3 s), held
    (((14, 0.5),), ((14, 0.5),))
    >>> cue.pattern_time_s(3.0)
    0.25
    """

    pattern: Pattern
    start_s: float = 0.0
    hold: bool = False

    def __post_init__(self):
        if not isinstance(self.pattern, Pattern):
            raise ValueError(f"pattern must be a Pattern, got {_validate.shown(self.pattern)}")
        start = _validate.in_range("start_s", self.start_s, 0.0, _validate.MAX_DURATION_S)
        object.__setattr__(self, "start_s", start)
        object.__setattr__(self, "hold", _validate.boolean("hold", self.hold))

    # --- what it plays: the pattern's --------------------------------------------------------

    @property
    def key(self) -> PatternCue:
        """What makes two cues the same content: the cue itself (a value)."""
        return self

    @property
    def effects(self) -> tuple:
        """The pattern's effects."""
        return self.pattern.effects

    @property
    def name(self) -> str:
        """The pattern's name."""
        return self.pattern.name

    @property
    def duration_s(self) -> float:
        """The pattern's duration in seconds (what its curves span)."""
        return self.pattern.duration_s

    def duration_on(self, target) -> float:
        """:attr:`duration_s`, whatever the array."""
        return self.pattern.duration_s

    def paths(self, target) -> tuple:
        """The pattern's :meth:`~Pattern.paths` on ``target``."""
        return self.pattern.paths(target)

    def curves(self, method, target, **options):
        """The pattern's :meth:`~Pattern.curves` (over its whole duration)."""
        return self.pattern.curves(method, target, **options)

    def check(self, target, method: str | None = None) -> PatternCue:
        """The cue if its pattern plays on ``target`` (:meth:`Pattern.check`)."""
        self.pattern.check(target, method)
        return self

    # --- playing -----------------------------------------------------------------------------

    def pattern_time_s(self, played_s: float) -> float:
        """The pattern's time ``played_s`` seconds after a stream began to play the cue:
        ``start_s`` when held, ``start_s + played_s`` otherwise, at most the pattern's end."""
        when = self.start_s if self.hold else self.start_s + max(float(played_s), 0.0)
        return min(when, self.pattern.duration_s)

    def played(self) -> PatternCue:
        """This cue playing on from its moment (not held); from the pattern's start when its
        moment is the pattern's end (a player's Play at the end plays it again)."""
        start = 0.0 if self.start_s >= self.pattern.duration_s else self.start_s
        return dataclasses.replace(self, start_s=start, hold=False)

    def live(self, method, target, sampling, mu, gamma, gain=1.0) -> CueFrames:
        """The frame source a scene plays (the ``Scene.source`` protocol): the pattern's
        :meth:`~Pattern.live` frames, from the cue's moment or held there."""
        return CueFrames(self.pattern.live(method, target, sampling, mu, gamma, gain),
                         self.start_s, self.hold)  # fmt: skip


class CueFrames:
    """A cue's frames: the pattern's (a :class:`PatternFrames`) from frame ``first`` on, or
    that frame held (see :class:`PatternCue`)."""

    def __init__(self, frames, start_s: float, hold: bool):
        self.frames = frames
        self.sampling = frames.sampling
        first = math.floor(start_s * self.sampling.rate_hz + 1e-9)
        self.hold = hold
        self.first = min(first, max(frames.n_frames - 1, 0)) if hold else first
        self.n_frames = 1 if hold else max(frames.n_frames - first, 0)

    @property
    def precomputed(self) -> bool:
        """True once the pattern's table is in use (a held frame needs none)."""
        return self.hold or self.frames.precomputed

    def precompute(self, background: bool = False) -> None:
        """Tabulate the pattern's frames (nothing to do for a held frame)."""
        if not self.hold:
            self.frames.precompute(background)

    def entries(self, k: int) -> tuple:
        """Lit actuators of the cue's frame ``k``: ``((index, corrected value), ...)``."""
        return self.frames.entries(self.first if self.hold else self.first + k)

    def entries_at(self, start_s: float) -> tuple:
        """:meth:`entries` of the frame that starts ``start_s`` seconds into the cue."""
        return self.entries(round(start_s * self.sampling.rate_hz))
