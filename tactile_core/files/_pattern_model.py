"""The pattern: a time line of effects on tracks, an immutable value that plays as a frame
source (``Scene(source=pattern)``) and reads and writes its JSON file."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import lru_cache

from .._shared import validate as _validate
from ..rendering.curves import ActivationCurves, curves_from_frames
from ..rendering.methods import get_method
from ..rendering.placement import default_method
from ..rendering.rasterize import check_target
from ..rendering.trace import Sampling
from ._pattern_effects import (
    COMBINE,
    CONTENTS,
    MAX_EFFECTS,
    MAX_NOTES_CHARS,
    MAX_TEXT_CHARS,
    MAX_TOTAL_POINTS,
    Effect,
    _text,
)
from ._pattern_frames import PatternFrames
from ._pattern_parts import compile_parts


@dataclass(frozen=True)
class Pattern:
    """A time line of effects on tracks: letters traced in strokes, taps, sweeps.

    Immutable: :meth:`add`, :meth:`then` and :meth:`replace` return new patterns. It plays as a
    scene's frame source (``Scene(source=pattern)``, ``open_array(...).play(pattern)``,
    ``tactile stream --shape pattern:FILE``): each frame, the effects playing then are rendered
    on the array (shapes by their method or the scene's, dots on their actuators), combined by
    :attr:`combine`, then corrected by the scene's mu, gamma and gain.

    Parameters
    ----------
    effects : sequence of Effect
        Up to :data:`MAX_EFFECTS`, holding up to :data:`MAX_TOTAL_POINTS` path points and dots.
    combine : {"max", "sum"}
        Overlapping effects: the maximum per actuator (as an imported ``.tact`` file combines
        its paths and dots), or the sum, clipped to 1. Raw intensities are combined, before
        the correction.
    name : str
        The pattern's name.
    notes : str
        Free text.

    Examples
    --------
    >>> import tactile_core as tc
    >>> letter = (tc.Pattern(name="L")
    ...     .add(tc.Line((1, 5), (1, 1)), duration_s=0.5)
    ...     .then(tc.Line((1, 1), (4, 1)), gap_s=0.2, duration_s=0.4))
    >>> letter.duration_s, [e.start_s for e in letter.effects]
    (1.1, [0.0, 0.7])
    """

    effects: tuple = ()
    combine: str = "max"
    name: str = ""
    notes: str = ""

    def __post_init__(self):
        effects = self.effects
        if isinstance(effects, (str, bytes, dict)) or not hasattr(effects, "__len__"):
            raise ValueError(f"effects must be a list of Effect, got {_validate.shown(effects)}")
        if len(effects) > MAX_EFFECTS:
            raise ValueError(f"effects holds {len(effects)} entries, more than the {MAX_EFFECTS} "
                             "allowed")  # fmt: skip
        points = 0
        for i, effect in enumerate(effects):
            if not isinstance(effect, Effect):
                raise ValueError(f"effects[{i}] must be an Effect, got {_validate.shown(effect)}")
            points += effect.points()
            if points > MAX_TOTAL_POINTS:
                raise ValueError(f"effects[{i}] brings the pattern past {MAX_TOTAL_POINTS} path "
                                 "points and dots")  # fmt: skip
        object.__setattr__(self, "effects", tuple(effects))
        _validate.choice("combine", self.combine, COMBINE)
        _text("name", self.name, MAX_TEXT_CHARS)
        if not isinstance(self.notes, str) or len(self.notes) > MAX_NOTES_CHARS:
            raise ValueError(f"notes must be a string of at most {MAX_NOTES_CHARS} characters, "
                             f"got {_validate.shown(self.notes)}")  # fmt: skip

    # --- building ------------------------------------------------------------------------------

    def add(self, what, **fields) -> Pattern:
        """This pattern with one more effect.

        Parameters
        ----------
        what : Effect, Shape, Dots or TactEffect
            An effect (``fields`` then change it), or what it plays (``fields`` are the
            :class:`Effect`'s: ``start_s``, ``duration_s``, ``method``, ``envelope``,
            ``repeat``, ``group``, ``track``, ``name``).

        Returns
        -------
        Pattern
        """
        if isinstance(what, Effect):
            effect = what.replace(**fields) if fields else what
        elif isinstance(what, (*CONTENTS, list, tuple)):
            effect = Effect(what, **fields)
        else:
            raise ValueError(f"what must be an Effect, a shape, a Dots or a TactEffect, got "
                             f"{_validate.shown(what)}")  # fmt: skip
        return self.replace(effects=(*self.effects, effect))

    def then(self, what, *, gap_s: float = 0.0, track: int = 0, **fields) -> Pattern:
        """:meth:`add` ``what`` on ``track``, starting ``gap_s`` seconds after the last effect
        of that track ends (at ``gap_s`` on an empty track)."""
        gap_s = _validate.in_range("gap_s", gap_s, 0.0, _validate.MAX_DURATION_S)
        ends = [e.end_s for e in self.effects if e.track == track]
        return self.add(what, start_s=max(ends, default=0.0) + gap_s, track=track, **fields)

    def replace(self, **changes) -> Pattern:
        """A copy with ``changes`` (checked)."""
        return dataclasses.replace(self, **changes)

    # --- what it is ----------------------------------------------------------------------------

    @property
    def duration_s(self) -> float:
        """When its last effect ends, in seconds (0 for an empty pattern)."""
        return max((e.end_s for e in self.effects), default=0.0)

    def duration_on(self, target) -> float:
        """:attr:`duration_s`, whatever the array (a ``.tact`` pattern's may depend on the
        positions the array's groups play)."""
        return self.duration_s

    @property
    def key(self) -> Pattern:
        """What makes two patterns the same content: the pattern itself (a value), so a copy
        of a scene in the stream's process goes on playing rather than restarting."""
        return self

    @property
    def tracks(self) -> tuple:
        """The track numbers in use, ascending."""
        return tuple(sorted({e.track for e in self.effects}))

    @property
    def groups(self) -> tuple:
        """The layout groups its effects name, in order of first use."""
        return tuple(dict.fromkeys(e.group for e in self.effects if e.group is not None))

    @property
    def waveforms(self) -> tuple:
        """The waveforms its effects ask for (:class:`~tactile_core.device.waveform.Waveform`),
        in order of first use; what an audio interface plays and a serial array drops."""
        return tuple(dict.fromkeys(e.waveform for e in self.effects if e.waveform is not None))

    def check(self, target, method: str | None = None) -> Pattern:
        """Return the pattern if it plays on ``target`` (a Grid or Layout) with the scene's
        ``method`` (None: the layout's default, IM on a grid, BA elsewhere); ``ValueError``
        naming the field otherwise: ``effects[2].group``, ``effects[0].dots[3].at``,
        ``effects[1].method``."""
        target = check_target(target)
        method = default_method(target) if method is None else method
        PatternFrames(self, method, target, Sampling(), 0.0, 1.0)
        return self

    def paths(self, target) -> tuple:
        """The shapes its effects trace on ``target``, in layout units (the tuner outlines
        them): each shape effect's, each ``.tact`` path mapped onto its group."""
        target = check_target(target)
        parts = compile_parts(self, get_method(default_method(target)), target)
        return tuple(p.shape for p in parts if p.shape is not None)

    # --- playing -------------------------------------------------------------------------------

    def live(self, method, target, sampling, mu, gamma, gain=1.0) -> PatternFrames:
        """The frame source a :class:`~tactile_core.rendering.scene.Scene` plays
        (:class:`PatternFrames`); the same object for the same arguments (the latest few are
        kept), so a table tabulated before a stream starts is the one it plays from."""
        if not self.effects:
            raise ValueError("the pattern has no effects to play")
        try:
            return _live(self, get_method(method), target, sampling, mu, gamma, gain)
        except TypeError:  # an argument that cannot be a key: a fresh one, checked there
            return PatternFrames(self, method, target, sampling, mu, gamma, gain)

    def frames(self, method, target, *, rate_hz: float = 300.0, sampling: Sampling | None = None,
               mu: float = 0.0, gamma: float = 1.0, gain: float = 1.0,
               corrected: bool = True):  # fmt: skip
        """All frames of the pattern, as they are streamed.

        Parameters
        ----------
        method : str
            The scene's method (effects that name one use theirs).
        target : Grid or Layout
        rate_hz : float, keyword-only
            Frames per second (used when ``sampling`` is None, with point sampling).
        sampling : Sampling, optional
            Rate and temporal filter, as the stream's.
        mu, gamma, gain : float, keyword-only
            The correction; the defaults leave intensities as rendered.
        corrected : bool
            False: the combined raw intensities (filtered, uncorrected).

        Returns
        -------
        time_s : ndarray of float64, shape (n,)
            Start of each frame, ``n = ceil(duration_s * rate)``; frame ``k`` samples
            ``[k / rate, (k + 1) / rate)``.
        frames : ndarray of float64, shape ``(n, rows, cols)`` (``(n, size)`` on a layout)
            Intensities in [0, 1].
        """
        sampling = Sampling(rate_hz, "point") if sampling is None else sampling
        live = self.live(method, target, sampling, mu, gamma, gain)
        return live.render(0, live.n_frames, corrected=corrected)

    def curves(self, method, target, *, mu: float, gamma: float, samples: int = 400,
               motor=None, compensate=None) -> ActivationCurves:  # fmt: skip
        """The activation curves of each actuator it lights, over its duration (``samples``
        frames, the middle of each), raw and corrected; as
        :meth:`TactPattern.curves <tactile_core.files.tact.TactPattern.curves>`."""
        samples = _validate.integer("samples", samples, 3)
        if self.duration_s <= 0.0:
            raise ValueError("the pattern has no duration to plot")
        sampling = Sampling(samples / self.duration_s, "point")
        start_s, frames = self.frames(method, target, sampling=sampling, corrected=False)
        return curves_from_frames(frames, start_s + sampling.offsets_s()[0], mu=mu,
                                  gamma=gamma, grid=check_target(target), motor=motor,
                                  compensate=compensate)  # fmt: skip

    # --- files ---------------------------------------------------------------------------------

    def to_dict(self) -> dict:
        """The JSON form (``docs/patterns.md``)."""
        from ._pattern_json import pattern_to_json

        return pattern_to_json(self)

    @classmethod
    def from_dict(cls, data, source: str = "pattern", target=None) -> Pattern:
        """Check the JSON form field by field (:class:`PatternError` names the field); with
        ``target`` also that it plays there (its groups, its actuators)."""
        from ._pattern_json import PatternError, pattern_fields

        fields = pattern_fields(data, source)
        try:
            pattern = cls(**fields)
            return pattern if target is None else pattern.check(target)
        except ValueError as exc:
            raise PatternError(f"{source}: {exc}") from None

    @classmethod
    def load(cls, path, target=None) -> Pattern:
        """Read and check a pattern file (``"format": "tactile-pattern"``).

        Parameters
        ----------
        path : path
            The file, JSON, at most ``MAX_PATTERN_BYTES``.
        target : Grid or Layout, optional
            Also check that it plays on this array (the groups it names exist, its dots'
            actuators are there).

        Raises
        ------
        PatternError
            Naming the file and the field: ``effects[3].envelope[1].time_s must be ...``.
        """
        from ._pattern_json import read_pattern_json

        return cls.from_dict(read_pattern_json(path), str(path), target)

    @classmethod
    def from_tact(cls, path, position: str | None = None, *, groups: dict | None = None
                  ) -> Pattern:  # fmt: skip
        """A bHaptics ``.tact`` file's effects as a pattern of :class:`TactEffect` effects,
        each at its time on its track: one device position's (the first with content by
        default), or with ``groups`` (``{"VestFront": "front", "VestBack": "back"}``) several,
        each effect on its position's group; ``TactError`` names the file and the field."""
        from ._pattern_tact import tact_effects

        effects, name = tact_effects(path, position, groups)
        return cls(effects, name=name)

    def to_tact(self, target, **options) -> dict:
        """The ``.tact`` document (the Designer's project form) of the pattern on ``target``:
        paths and dots per effect (``docs/patterns.md``); ``options`` as
        :func:`~tactile_core.files.pattern.pattern_tact_document`."""
        from ._pattern_tact import pattern_tact_document

        return pattern_tact_document(self, target, **options)

    def save_tact(self, out, target, **options):
        """Write :meth:`to_tact` to ``out`` atomically; returns the path written."""
        from ._pattern_tact import write_pattern_tact

        return write_pattern_tact(out, self, target, **options)

    def save_wav(self, out, profile, method: str | None = None, *, rate_hz: float = 300.0,
                 mu: float = 0.0, gamma: float = 1.0, **options):  # fmt: skip
        """Write what an audio interface plays for the pattern on ``profile`` (a
        :class:`~tactile_core.device.profile.DeviceProfile`) as a multichannel WAV file: each
        channel on its waveform, an effect's own where it names one (``docs/patterns.md``);
        ``options`` as :func:`~tactile_core.files.wav.write_wav` (``samplerate``,
        ``carrier_hz``, ``ramp_ms``, ``waveform``). Returns the samples per channel written."""
        from .wav import write_pattern_wav

        return write_pattern_wav(out, self, profile, method, rate_hz=rate_hz, mu=mu,
                                 gamma=gamma, **options)  # fmt: skip

    def save(self, path):
        """Write the pattern to ``path`` atomically (a file :meth:`load` reads back equal);
        returns the path written."""
        from ._pattern_json import write_pattern_json

        return write_pattern_json(path, self.to_dict())


@lru_cache(maxsize=4)
def _live(pattern, method, target, sampling, mu, gamma, gain) -> PatternFrames:
    return PatternFrames(pattern, method, target, sampling, mu, gamma, gain)
