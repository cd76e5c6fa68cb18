"""A scene: everything that decides what goes on the array, as one immutable snapshot.

The GUI or the command line builds a new :class:`Scene` whenever a parameter changes and hands
it to the streamer, whose output thread picks up whichever snapshot is current at its next tick.
Validation happens here, on the caller's thread, so a bad value (NaN from a slider, a negative
duration) raises ``ValueError`` naming the field before anything reaches the output thread.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from . import _validate
from .correction import check_correction
from .geometry import Grid
from .methods import get_method
from .shapes import Shape
from .trace import DIRECTIONS, FILTERS, LiveFrames, Sampling, Trace


def check_scene(scene):
    """Return ``scene`` if it is a :class:`Scene` or None; else ``ValueError`` naming it."""
    if scene is not None and not isinstance(scene, Scene):
        raise ValueError(f"scene must be a Scene or None, got {scene!r}")
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
        Seconds per trace and off between traces.
    direction : {"forward", "reverse"}
    repeat : bool
    rate_hz : float
        Requested frame rate (the streamer caps it at what the link carries).
    filter : {"point", "box"}
    subsamples : int
        Sub-samples of the box filter.
    dither : bool
        Temporal dithering of the quantisation.
    playing : bool
        False: the array is all off (paused); the trace clock stops.
    gain : float
        Master intensity in [0, 1] multiplying every corrected intensity before calibration
        and quantisation (1 by default; the calibration procedure uses it to present one
        tactor at a chosen drive).
    emphasis : float
        Corner emphasis of the trace in [0, 0.9] (see :class:`~tactile_core.trace.Trace`).
    epoch : int
        Changing it restarts the trace from its beginning.
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
    filter: str = "box"
    subsamples: int = 4
    dither: bool = True
    playing: bool = True
    gain: float = 1.0
    emphasis: float = 0.0
    epoch: int = 0

    def __post_init__(self):
        if self.shape is not None and not isinstance(self.shape, Shape):
            raise ValueError(
                f"shape must be a Line, Circle, Square or Polyline, got {self.shape!r}"
            )
        object.__setattr__(self, "method", get_method(self.method).name)
        mu, gamma = check_correction(self.mu, self.gamma)
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "gamma", gamma)
        object.__setattr__(self, "duration_s", _validate.positive("duration_s", self.duration_s))
        object.__setattr__(self, "pause_s", _validate.non_negative("pause_s", self.pause_s))
        _validate.choice("direction", self.direction, DIRECTIONS)
        object.__setattr__(
            self, "rate_hz", _validate.in_range("rate_hz", self.rate_hz, 1.0, 10_000.0)
        )
        _validate.choice("filter", self.filter, FILTERS)
        object.__setattr__(
            self, "subsamples", _validate.integer("subsamples", self.subsamples, 1, 1024)
        )
        for name in ("repeat", "dither", "playing"):
            object.__setattr__(self, name, bool(getattr(self, name)))
        object.__setattr__(self, "gain", _validate.in_range("gain", self.gain, 0.0, 1.0))
        object.__setattr__(
            self, "emphasis", _validate.in_range("emphasis", self.emphasis, 0.0, 0.9)
        )
        object.__setattr__(self, "epoch", _validate.integer("epoch", self.epoch, 0))

    @property
    def active(self) -> bool:
        """True when the scene renders something (a shape, playing)."""
        return self.shape is not None and self.playing

    def trace(self) -> Trace:
        """The :class:`Trace` of the scene's shape and timing."""
        if self.shape is None:
            raise ValueError("shape is None: an idle scene has no trace")
        return Trace(
            self.shape, self.duration_s, self.pause_s, self.direction, self.repeat, self.emphasis
        )

    def sampling(self, rate_hz: float | None = None) -> Sampling:
        """The :class:`Sampling` at ``rate_hz`` (default: the scene's rate)."""
        return Sampling(rate_hz or self.rate_hz, self.filter, self.subsamples)

    def live(self, grid: Grid, rate_hz: float | None = None) -> LiveFrames:
        """Frames of the scene at ``rate_hz``, for the output thread."""
        return LiveFrames(
            self.trace(), self.method, self.sampling(rate_hz), self.mu, self.gamma, grid
        )

    def replace(self, **changes) -> Scene:
        """A copy with ``changes`` (validated)."""
        return dataclasses.replace(self, **changes)
