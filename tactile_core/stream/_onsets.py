"""Presentations as they start: the first frame written of each new stimulus, with its time.

The streamer's output thread tells an :class:`OnsetWatch` when it takes up a new plan and when
it has written a frame; the watch calls each hook once per presentation with an :class:`Onset`.
A presentation starts with the first frame written of a playing scene that restarts the trace
(another shape, another frame source, a new ``epoch``) or that follows a scene that was not
playing (idle, paused); and, for a trace that repeats, with the first frame of each further
cycle (``cycle`` 1, 2, …: ``tactile stream`` marks every trace). A change that keeps the trace
running (μ, γ, method) is the same presentation; if it comes before the first frame, the onset
names the newest scene. A held trace (the tuner's scrubbing) and a frame source have no cycles.

The time is the one the streamer's taps get for that frame: when it was written, on the host's
``time.perf_counter`` clock, or, for a frame scheduled ahead (``lead_s``), the host time at
which the array is to play it. Markers on Lab Streaming Layer
(:class:`tactile_core.serve.LslOutlets`), the OSC server's shapes and the scripting API's
presentations all take their times from here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Onset", "OnsetWatch"]


@dataclass(frozen=True)
class Onset:
    """The first frame of a presentation, as it went out.

    Attributes
    ----------
    scene : Scene
        The scene the frame was rendered from.
    time_s : float
        ``time.perf_counter`` seconds: when the frame was written, or the host time it was
        scheduled to play at (``timed``).
    seq : int
        The frame's sequence number on the wire (0 to 255).
    timed : bool
        True for a frame scheduled ahead on the array's clock.
    cycle : int
        Which cycle of a repeating trace begins (0: the presentation's first frame).
    """

    scene: object
    time_s: float
    seq: int
    timed: bool = False
    cycle: int = 0


class OnsetWatch:
    """Finds the first frame of each presentation in the output thread's calls.

    Parameters
    ----------
    hooks : list of callables
        Called as ``hook(onset)`` from the output thread; the list is read at each onset, so
        the owner may append to it while streaming. A hook that raises is skipped: it never
        stops the stream.
    """

    def __init__(self, hooks: list):
        self.hooks = hooks
        self._pending = None
        self._scene = None
        self._cycle_frames = None  # frames per cycle of a repeating trace, or None
        self._cycle = 0

    def planned(self, plan, starts: bool) -> None:
        """The output thread took up ``plan``; ``starts``: it restarts the trace or follows a
        plan that was not playing."""
        self._scene = plan.scene if plan.active else None
        trace = getattr(plan.live, "trace", None)
        repeats = trace is not None and trace.repeat and trace.hold_s is None
        self._cycle_frames = trace.period_s * plan.rate if repeats and plan.active else None
        if not plan.active:
            self._pending = None
        elif starts or self._pending is not None:
            self._pending = plan.scene

    def written(self, time_s: float, seq: int, timed: bool, k: int = 0) -> None:
        """Frame ``k`` of the current plan was written (``time_s`` as the taps got it)."""
        cycle = 0 if self._cycle_frames is None else math.floor(k / self._cycle_frames + 1e-9)
        if self._pending is not None:
            scene, self._pending = self._pending, None
        elif self._scene is not None and cycle > self._cycle:
            scene = self._scene
        else:
            return
        self._cycle = cycle
        onset = Onset(scene, time_s, seq & 0xFF, timed, cycle)
        for hook in list(self.hooks):
            try:
                hook(onset)
            except Exception:  # an observer's bug must not stop the array
                pass
