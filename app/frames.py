"""What the views show of a scene's frames: computed as the stream computes them.

The Tune tab's *raw*, *corrected* and *predicted* heatmaps and the Compare tab's columns show the
frame the stream sent last (its place on the trace clock, :attr:`Streamer.last_frame
<tactile_core.stream.Streamer.last_frame>`) through the stream's own function,
:meth:`Scene.live <tactile_core.rendering.scene.Scene.live>` and
:meth:`LiveFrames.entries_at <tactile_core.rendering.trace.LiveFrames.entries_at>`: the same
method, correction, temporal filter and rate, never a copy of them. No Qt here.
"""

from __future__ import annotations


def stream_rate(scene, stats) -> float:
    """The rate the stream renders ``scene`` at: the scene's, or what the link carries when the
    stream's statistics ``stats`` (a ``StreamStats``) say it capped that rate."""
    capped = stats.capped and stats.requested_rate_hz == scene.rate_hz and stats.rate_hz > 0
    return stats.rate_hz if capped else scene.rate_hz


class SceneFrames:
    """The frames of one scene as the stream renders them, rebuilt only when the scene, the
    target or the rate changes; ``raw=True``: before the correction (the scene at mu 0,
    gamma 1, gain 1, which the correction leaves as they are)."""

    def __init__(self, raw: bool = False):
        self.raw = raw
        self._key = None
        self._frames = None

    def at(self, scene, target, rate_hz: float, start_s: float) -> tuple:
        """``((flat index, value), ...)`` of the lit tactors of the frame that starts
        ``start_s`` seconds into ``scene``'s trace clock (a pattern's: since the stream began to
        play it), rendered at ``rate_hz`` on ``target`` (a Grid or Layout)."""
        key = self._key
        if key is None or key[0] is not scene or key[1] is not target or key[2] != rate_hz:
            source = scene.replace(mu=0.0, gamma=1.0, gain=1.0) if self.raw else scene
            self._frames = source.live(target, rate_hz)
            self._key = (scene, target, rate_hz)
        frames = self._frames
        if hasattr(frames, "entries_at"):
            return frames.entries_at(start_s)
        return frames.entries(round(start_s * rate_hz))  # a pattern's: frame k starts at k / rate
