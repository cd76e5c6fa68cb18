"""An imported ``.tact`` file as a *pattern*: frames on this array, by the scene's method.

A :class:`TactPattern` is a file's content, kept in bHaptics' 0..1 coordinates, with the SDK's
play-time options (:class:`ScaleOption`, :class:`RotationOption`, ``_tact_options``) applied;
it is mapped onto an array only when it is played (:meth:`TactPattern.live`, the frame source a
:class:`~tactile_core.rendering.scene.Scene` takes) or rendered (:meth:`TactPattern.frames`).

**Where it plays** (``_tact_place``): every position onto the array's group for that part of
the body (``VestFront`` onto ``front``, ``VestBack`` onto ``back``, ...), or, on an array
without such groups or when a position is named, one position over the whole array.

**The coordinate mapping.** bHaptics' ``(x, y)`` in 0..1, y downward, goes onto the extent of
the actuator centres ``[x0, x1] x [y0, y1]`` of the position's placement (:func:`layout_box`):
``X = x0 + x (x1 - x0)``, ``Y = y1 - y (y1 - y0)``. Corner motors land on corner actuators, so a
4 x 5 vest file plays motor for motor on a 4 x 5 vest panel; on the 5 x 6 palm array the path
stretches over the tactors' centres (0.5..4.5 x 0.5..5.5). An axis along which all actuators
line up (a belt's y) maps every coordinate to that line. How a frame is made: ``_tact_play``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from .._shared import validate as _validate
from ..rendering.curves import ActivationCurves, curves_from_frames
from ..rendering.methods import get_method
from ..rendering.rasterize import check_target
from ..rendering.shapes import TimedPath
from ..rendering.trace import Sampling
from ._tabled import MAX_TABLE_FRAMES
from ._tact_coords import layout_box, unit_to_layout
from ._tact_options import RotationOption, ScaleOption, option, rotated, scaled
from ._tact_place import placements
from ._tact_play import PatternFrames
from ._tact_records import TactError, TactFile

NOTHING_TO_PLAY = "no paths or dots to play (no enabled track holds any)"
"""Why a file without content is refused (:class:`TactPattern`, ``load_pattern`` with the
file's name before it)."""

__all__ = ["MAX_TABLE_FRAMES", "NOTHING_TO_PLAY", "PatternFrames", "TactPattern"]


@dataclass(frozen=True, eq=False)
class TactPattern:
    """A ``.tact`` file's content, to play on any array.

    Parameters
    ----------
    file : TactFile
        The checked file (:func:`~tactile_core.files.tact.read_tact`).
    position : str, optional
        A device position to play alone over the whole array (``"VestFront"``...). By default
        every position plays on the array's group for it (``VestFront`` on ``front``...), and
        on an array without such groups the first position that holds paths or dots does.
    scale : ScaleOption or (float, float), optional
        bHaptics' ``ScaleOption``: intensity and duration multipliers.
    rotation : RotationOption or (float, float), optional
        bHaptics' ``RotationOption`` for the vest: degrees round the body and the vertical
        offset in panel heights.

    Raises
    ------
    TactError
        When no position of the file holds paths or dots (an empty file: nothing to play), or
        ``position`` holds none.
    ValueError
        A scale or rotation out of range, naming it.
    """

    file: TactFile
    position: str | None = None
    scale: ScaleOption | None = None
    rotation: RotationOption | None = None
    named: bool = field(init=False, default=False)

    def __post_init__(self):
        positions = self.file.positions
        if not positions:
            raise TactError(NOTHING_TO_PLAY)
        object.__setattr__(self, "scale", option(ScaleOption, self.scale))
        object.__setattr__(self, "rotation", option(RotationOption, self.rotation))
        object.__setattr__(self, "named", self.position is not None)
        if self.position is None:
            object.__setattr__(self, "position", positions[0])
        elif self.position not in positions:
            held = ", ".join(positions) or "none"
            raise TactError(
                f"position {_validate.shown(self.position)} holds no paths or dots in this file "
                f"(positions with content: {held})"
            )
        if (self.file.duration_s * self.scale.duration) * 1e3 > 3_600_000.0:
            raise ValueError(f"scale duration {self.scale.duration:g} makes the file last more "
                             "than an hour")  # fmt: skip

    @property
    def name(self) -> str:
        """The project's name."""
        return self.file.name

    @property
    def key(self) -> tuple:
        """What makes two patterns the same content (the file, the position and the options):
        a copy of the scene in the stream's process goes on playing, not from its start."""
        return (self.file, self.position, self.named, self.scale, self.rotation)

    @property
    def content(self) -> tuple:
        """``(paths, dots)``: the file's :class:`TactPath` and :class:`TactDot` records with
        the scale and rotation applied."""
        return _content(self)

    @property
    def positions(self) -> tuple:
        """The positions with content once the options applied (a rotation may move the
        front's content to the back), in the file's order."""
        paths, dots = self.content
        held = {r.position for r in (*paths, *dots)}
        order = [*self.file.positions, "VestFront", "VestBack"]
        return tuple(dict.fromkeys(p for p in order if p in held))

    def ends_s(self) -> dict:
        """Per position, when its content ends, in seconds: its last effect's end (scaled),
        or, when rotated, its last path or dot's end."""
        if self.rotation.identity:
            d = self.scale.duration
            return {p: end * d for p, end in self.file.ends_s.items()}
        paths, dots = self.content
        out: dict = {}
        for p, end in [(r.position, r.times_s[-1]) for r in paths] + [
            (r.position, r.end_s) for r in dots
        ]:
            out[p] = max(out.get(p, 0.0), end)
        return out

    @property
    def duration_s(self) -> float:
        """When the content of :attr:`position` ends, in seconds: what that position lasts
        played alone (frames after it are empty). The file's other positions do not count:
        the front of a file whose back plays after it ends with its own effects
        (``TactFile.duration_s`` is the whole file's). :meth:`duration_on` gives what plays on
        an array."""
        return self.ends_s().get(self.position, self.file.duration_s * self.scale.duration)

    def duration_on(self, target) -> float:
        """When what plays on ``target`` ends (the positions :meth:`played` lists), in s."""
        ends = self.ends_s()
        return max((ends.get(p, 0.0) for p, _ in self.played(target)), default=0.0)

    @property
    def notes(self) -> tuple:
        """What of the file does not play, in words (empty if nothing)."""
        return self.file.notes

    @property
    def skipped(self) -> tuple:
        """The file's other positions with content, which :attr:`position` played alone over
        a whole array leaves out (:meth:`skipped_on` for an array with groups)."""
        return tuple(p for p in self.file.positions if p != self.position)

    def placement(self, target) -> tuple:
        """Where the positions play on ``target``: ``Placement`` records (``_tact_place``)."""
        return _placement(self, check_target(target))

    def played(self, target) -> tuple:
        """``((position, group or None), ...)``: what plays on ``target``, and where."""
        return tuple((p.position, p.group) for p in self.placement(target))

    def skipped_on(self, target) -> tuple:
        """The positions with content that do not play on ``target``."""
        played = {p for p, _ in self.played(target)}
        return tuple(p for p in self.positions if p not in played)

    def describe(self, target) -> str:
        """``"VestFront on front and VestBack on back"`` or ``"VestFront"``: what plays."""
        return " and ".join(p if g is None else f"{p} on {g}" for p, g in self.played(target))

    def placed(self, target) -> tuple:
        """Per placement: ``(placement, paths, dots)``, the paths as :class:`TimedPath` shapes
        in the placement's layout units, the dots as ``(start_s, end_s, actuator, intensity,
        fade, closed)`` with the whole array's actuator nearest to the motor's place."""
        return _placed(self, check_target(target))

    def paths(self, target) -> tuple:
        """The paths that play on ``target`` (a Grid or Layout): :class:`TimedPath` shapes in
        its layout units, their times in seconds from the file's start."""
        return tuple(p for _, shapes, _ in self.placed(target) for p in shapes)

    def dots(self, target) -> tuple:
        """The dots that play on ``target``: ``(start_s, end_s, actuator, intensity, fade)``,
        each motor on the actuator nearest to its place."""
        return tuple(d[:5] for _, _, dots in self.placed(target) for d in dots)

    def live(self, method, target, sampling, mu, gamma, gain=1.0) -> PatternFrames:
        """The frame source a :class:`~tactile_core.rendering.scene.Scene` plays (see
        :class:`PatternFrames`): the same object for the same arguments (the latest few are
        kept), so a table tabulated before a stream starts is the one it plays from."""
        try:  # (keyed by the Method, however it was named)
            return _live(self, get_method(method), target, sampling, mu, gamma, gain)
        except TypeError:  # (an argument that cannot be a key: a fresh one, checked there)
            return PatternFrames(self, method, target, sampling, mu, gamma, gain)

    def frames(self, method, target, *, rate_hz: float = 300.0, sampling: Sampling | None = None,
               mu: float = 0.0, gamma: float = 1.0, gain: float = 1.0,
               corrected: bool = True) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """All frames of the pattern, as they are streamed.

        Parameters
        ----------
        method : str
            The rendering method (on a layout that is not a grid, one that works there).
        target : Grid or Layout
            The array.
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
            Start of each frame, ``n = ceil(duration_on(target) * rate)``.
        frames : ndarray of float64, shape ``(n, rows, cols)`` (``(n, size)`` on a layout)
            Intensities in [0, 1].
        """
        sampling = Sampling(rate_hz, "point") if sampling is None else sampling
        live = self.live(method, target, sampling, mu, gamma, gain)
        return live.render(0, live.n_frames, corrected=corrected)

    @property
    def effects(self) -> int:
        """How many paths and dots the pattern holds (what drawing its curves costs)."""
        paths, dots = self.content
        return len(paths) + len(dots)

    def curves(self, method, target, *, mu: float, gamma: float, samples: int = 400,
               motor=None, compensate=None) -> ActivationCurves:  # fmt: skip
        """The pattern's activation curves with ``method`` on ``target``: each actuator it
        lights, raw and corrected, over what plays there (``samples`` point samples, the
        frames' own combination of paths and dots).

        Parameters
        ----------
        method : str
        target : Grid or Layout
        mu, gamma : float, keyword-only
            The correction of the ``corrected`` curves.
        samples : int, keyword-only
            Samples over the duration, >= 3.
        motor : MotorResponse, optional
            Also the curves through the motors (``felt``).
        compensate : MotorResponse, optional
            Also the motor-aware drive for these motors (``drive``; ``felt`` is of it).

        Returns
        -------
        ActivationCurves
            ``time_s``: when each sample was taken (the middle of each of ``samples`` frames
            over :meth:`duration_on`, as the stream's point sampling takes them).
        """
        samples = _validate.integer("samples", samples, 3)
        duration = self.duration_on(target)
        if duration <= 0.0:
            raise ValueError("the pattern has no duration to plot")
        sampling = Sampling(samples / duration, "point")
        start_s, frames = self.frames(method, target, sampling=sampling, corrected=False)
        return curves_from_frames(frames, start_s + sampling.offsets_s()[0], mu=mu,
                                  gamma=gamma, grid=check_target(target), motor=motor,
                                  compensate=compensate)  # fmt: skip


@lru_cache(maxsize=4)
def _live(pattern, method, target, sampling, mu, gamma, gain) -> PatternFrames:
    return PatternFrames(pattern, method, target, sampling, mu, gamma, gain)


@lru_cache(maxsize=16)
def _content(pattern: TactPattern) -> tuple:
    paths, dots = scaled(pattern.file.paths, pattern.file.dots, pattern.scale)
    paths, dots = rotated(paths, dots, pattern.rotation)
    return tuple(paths), tuple(dots)


@lru_cache(maxsize=16)
def _placement(pattern: TactPattern, target) -> tuple:
    named = pattern.position if pattern.named else None
    return placements(target, pattern.positions or (pattern.position,), named)


@lru_cache(maxsize=16)
def _placed(pattern: TactPattern, target) -> tuple:
    paths, dots = pattern.content
    out = []
    for place in _placement(pattern, target):
        sub = place.target
        box = layout_box(sub)
        shapes, lit = [], []
        for p in paths:
            if p.position == place.position:
                points = [unit_to_layout(x, y, box) for x, y in p.points]
                shapes.append(TimedPath(points, p.times_s, p.intensities, p.pattern, p.fade))
        for d in dots:
            if d.position == place.position:
                i = place.full(sub.nearest(*unit_to_layout(d.x, d.y, box)))
                lit.append((d.start_s, d.end_s, i, d.intensity, d.fade, d.closed))
        out.append((place, tuple(shapes), tuple(lit)))
    return tuple(out)
