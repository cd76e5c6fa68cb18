"""A scene: everything that decides what goes on the array, as one immutable snapshot.

The GUI or the command line builds a new :class:`Scene` whenever a parameter changes and hands
it to the streamer, whose output thread picks up whichever snapshot is current at its next tick.
Validation happens here, on the caller's thread, so a bad value (NaN from a slider, a negative
duration) raises ``ValueError`` naming the field before anything reaches the output thread.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from .._shared import validate as _validate
from .correction import check_correction
from .methods import get_method
from .shapes import Shape
from .trace import DIRECTIONS, FILTERS, LiveFrames, Sampling, Trace, check_hold


def check_scene(scene):
    """Return ``scene`` if it is a :class:`Scene` or None; else ``ValueError`` naming it."""
    if scene is not None and not isinstance(scene, Scene):
        raise ValueError(f"scene must be a Scene or None, got {_validate.shown(scene)}")
    return scene


@dataclass(frozen=True)
class Scene:
    """What to render and how.

    Parameters
    ----------
    shape : Shape or None
        The traced shape; None for an idle scene (all off).
    method : {"CT", "MM", "AS", "IM"}
    mu, gamma : float
        Threshold in [0, 1] and gamma > 0 (the paper's 0.33 and 0.7 by default).
    duration_s, pause_s : float
        Seconds per trace (> 0) and off between traces (>= 0), each at most an hour.
    direction : {"forward", "reverse"}
    repeat : bool
    rate_hz : float
        Requested frame rate, 1 to 10,000 Hz (the streamer caps it at what the link carries,
        and sends at least 10 frames a second, repeating frames, below that).
    filter : {"point", "box"}
        Temporal filter; ``"point"`` (the paper's pipeline) by default.
    subsamples : int
        Sub-samples of the box filter (used when ``filter`` is ``"box"``).
    dither : bool
        Temporal dithering of the quantisation; off (plain rounding, the paper's) by default.
    playing : bool
        False: the array is all off (paused); the trace clock stops.
    gain : float
        Master intensity in [0, 1], part of the correction: a lit tactor gets
        ``mu + gain (1 - mu) I**gamma``, so the master intensity scales only the part above the
        threshold and never pushes a lit tactor below ``mu`` (1 by default; the calibration
        procedure, at ``mu = 0`` and ``gamma = 1``, uses it to present one tactor at a chosen
        drive).
    emphasis : float
        Corner emphasis of the trace in [0, 0.9] (see :class:`~tactile_core.rendering.trace.Trace`).
    felt_domain : bool
        Correct in felt amplitude: with a motor response curve in the device profile, the
        corrected intensity is the motor output wanted and the array gets the least drive that
        gives it (:meth:`~tactile_core.device.DeviceProfile.drive_for`), so mu and gamma act on
        felt amplitude rather than drive. Off (the paper's: on drive) by default; without a
        response curve it changes nothing.
    compensate_motors : bool
        Motor-aware drive (:mod:`~tactile_core.rendering.motor_drive`): after the correction
        and before quantisation, each lit tactor's drive pre-compensates its motor's
        first-order lag (the device profile's ``motor`` constants): overdrive while it spins
        up, off while it runs down, within [0, 1]. Off (the paper's pipeline) by default;
        without motor constants in the profile it changes nothing.
    epoch : int
        Changing it restarts the trace from its beginning.
    hold_s : float or None
        Hold the trace at this many seconds into it, the array playing that instant (the
        tuner's scrubbing); None (default) runs the trace. Not part of a preset.
    source : object or None
        Instead of a shape's trace, a *source* of frames (points driven live by another
        program, an imported pattern): an object with ``live(method, target, sampling, mu,
        gamma, gain)`` that returns what :meth:`live` returns, something with
        ``entries(k) -> ((index, value), ...)`` (corrected values of frame ``k`` counted from
        the scene's start), ``precompute(background=False)`` and ``precomputed``. The scene's
        method, correction, rate and filter apply; its shape and trace timing do not. Not part
        of a preset.
    marker : str
        What kind of presentation this is for stimulus markers (Lab Streaming Layer), such as
        ``"trial"``, ``"ab"``, ``"osc-shape"``, ``"script"``; empty for an ordinary scene (at
        most 64 characters). Travels with the scene (also to the stream process); not part of a
        preset.
    """

    shape: Shape | None = None
    method: str = "AS"
    mu: float = 0.33
    gamma: float = 0.7
    duration_s: float = 2.0
    pause_s: float = 0.5
    direction: str = "forward"
    repeat: bool = True
    rate_hz: float = 300.0
    filter: str = "point"
    subsamples: int = 4
    dither: bool = False
    playing: bool = True
    gain: float = 1.0
    emphasis: float = 0.0
    felt_domain: bool = False
    compensate_motors: bool = False
    epoch: int = 0
    hold_s: float | None = None
    source: object = None
    marker: str = ""

    def __post_init__(self):
        if self.source is not None and not callable(getattr(self.source, "live", None)):
            raise ValueError(
                f"source must have a live(...) method (a frame source), got "
                f"{_validate.shown(self.source)}"
            )
        if self.shape is not None and not isinstance(self.shape, Shape):
            raise ValueError(
                "shape must be a Line, Circle, Square or Polyline, "
                f"got {_validate.shown(self.shape)}"
            )
        object.__setattr__(self, "method", get_method(self.method).spec)
        mu, gamma = check_correction(self.mu, self.gamma)
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "gamma", gamma)
        object.__setattr__(self, "duration_s", _validate.duration("duration_s", self.duration_s))
        object.__setattr__(
            self, "pause_s", _validate.duration("pause_s", self.pause_s, allow_zero=True)
        )
        _validate.choice("direction", self.direction, DIRECTIONS)
        object.__setattr__(self, "rate_hz", _validate.rate("rate_hz", self.rate_hz, 1.0, 10_000.0))
        _validate.choice("filter", self.filter, FILTERS)
        object.__setattr__(
            self, "subsamples", _validate.integer("subsamples", self.subsamples, 1, 1024)
        )
        for name in ("repeat", "dither", "playing", "felt_domain", "compensate_motors"):
            object.__setattr__(self, name, _validate.boolean(name, getattr(self, name)))
        object.__setattr__(self, "gain", _validate.in_range("gain", self.gain, 0.0, 1.0))
        object.__setattr__(
            self, "emphasis", _validate.in_range("emphasis", self.emphasis, 0.0, 0.9)
        )
        object.__setattr__(self, "epoch", _validate.integer("epoch", self.epoch, 0))
        object.__setattr__(self, "hold_s", check_hold(self.hold_s))
        if not isinstance(self.marker, str) or len(self.marker) > 64:
            raise ValueError(f"marker must be a string of at most 64 characters, got "
                             f"{_validate.shown(self.marker)}")  # fmt: skip

    @property
    def active(self) -> bool:
        """True when the scene renders something (a shape or a source, playing)."""
        return (self.shape is not None or self.source is not None) and self.playing

    def trace(self) -> Trace:
        """The :class:`Trace` of the scene's shape and timing."""
        if self.shape is None:
            raise ValueError("shape is None: an idle scene has no trace")
        return Trace(
            self.shape,
            self.duration_s,
            self.pause_s,
            self.direction,
            self.repeat,
            self.emphasis,
            self.hold_s,
        )

    def sampling(self, rate_hz: float | None = None) -> Sampling:
        """The :class:`Sampling` at ``rate_hz`` (default: the scene's rate)."""
        return Sampling(rate_hz or self.rate_hz, self.filter, self.subsamples)

    def live(self, grid, rate_hz: float | None = None) -> LiveFrames:
        """Frames of the scene at ``rate_hz`` on a Grid or Layout, for the output thread."""
        if self.source is not None:
            return self.source.live(
                get_method(self.method), grid, self.sampling(rate_hz), self.mu, self.gamma,
                self.gain,
            )  # fmt: skip
        return LiveFrames(
            self.trace(), self.method, self.sampling(rate_hz), self.mu, self.gamma, grid, self.gain
        )

    def replace(self, **changes) -> Scene:
        """A copy with ``changes`` (validated)."""
        return dataclasses.replace(self, **changes)


@dataclass(frozen=True)
class Pipeline:
    """How a scene's trace becomes device levels: frame rate, temporal filter, dithering.

    The default is the paper's pipeline, which the experiments run unless told otherwise: point
    sampling at the frame rate and plain rounding to the device levels (no temporal filter, no
    dithering), so CT and MM stay strictly bi-level and the array plays its own levels only. The
    frame rate is how often the host sends levels; it is not the PWM carrier of the array (about
    300 Hz on the paper's array, which then holds each level for one or more PWM periods).

    Parameters
    ----------
    rate_hz : float
        Frames per second sent to the array (300 by default: one frame per PWM period of the
        paper's array, within the 311 frames a second that 115200 baud carries).
    filter : {"point", "box"}
    subsamples : int
        Sub-samples of the box filter (1 for point sampling).
    dither : bool
        Temporal dithering of the quantisation (error feedback per tactor).
    compensate_motors : bool
        Motor-aware drive (see :class:`Scene`); off, as the paper ran, by default.
    """

    rate_hz: float = 300.0
    filter: str = "point"
    subsamples: int = 1
    dither: bool = False
    compensate_motors: bool = False

    def __post_init__(self):
        Scene(None, rate_hz=self.rate_hz, filter=self.filter, subsamples=self.subsamples)
        object.__setattr__(self, "rate_hz", float(self.rate_hz))
        object.__setattr__(self, "subsamples", int(self.subsamples))
        for name in ("dither", "compensate_motors"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name} must be true or false, got "
                                 f"{_validate.shown(getattr(self, name))}")  # fmt: skip

    def apply(self, scene: Scene) -> Scene:
        """``scene`` with this pipeline's rate, filter, dithering and motor-aware drive."""
        return scene.replace(rate_hz=self.rate_hz, filter=self.filter, subsamples=self.subsamples,
                             dither=self.dither,
                             compensate_motors=self.compensate_motors)  # fmt: skip

    @property
    def is_paper(self) -> bool:
        """True for point sampling and plain rounding without motor-aware drive, as the paper
        ran."""
        return self.filter == "point" and not self.dither and not self.compensate_motors

    def to_dict(self) -> dict:
        """The JSON form (what ``session.json`` records)."""
        return {
            "rate_hz": self.rate_hz,
            "filter": self.filter,
            "subsamples": self.subsamples if self.filter == "box" else 1,
            "dither": self.dither,
            "compensate_motors": self.compensate_motors,
        }

    @classmethod
    def from_dict(cls, data, source: str = "pipeline") -> Pipeline:
        """Validate the JSON form; ``ValueError`` names the field. ``compensate_motors`` may
        be missing (sessions recorded before it existed ran without it)."""
        if not isinstance(data, dict):
            raise ValueError(f"{source} must be an object, got {type(data).__name__}")
        kwargs = {}
        for key, kinds in (("rate_hz", (int, float)), ("filter", str), ("subsamples", int),
                           ("dither", bool), ("compensate_motors", bool)):  # fmt: skip
            if key not in data:
                if key == "compensate_motors":
                    continue
                raise ValueError(f"{source}.{key} is missing")
            value = data[key]
            wrong_bool = isinstance(value, bool) and key not in ("dither", "compensate_motors")
            if wrong_bool or not isinstance(value, kinds):
                raise ValueError(f"{source}.{key} has the wrong type: {_validate.shown(value)}")
            kwargs[key] = value
        try:
            return cls(**kwargs)
        except ValueError as exc:
            raise ValueError(f"{source}: {exc}") from None


PAPER_PIPELINE = Pipeline()
"""Point sampling at 300 frames a second, plain rounding: what the experiments run by default."""
