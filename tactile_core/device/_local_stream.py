"""A stream as a thread of this process, with the interface of
:class:`~.process.StreamerProcess` (for programs without a busy main thread, for tests, and to
measure what the child process buys)."""

from __future__ import annotations

from ._stream_stats import StreamStats
from .profile import DeviceProfile, default_profile


class LocalStream:
    """The same interface with the streamer as a thread of this process (for programs without
    a busy main thread, for tests, and to measure what the process buys)."""

    def __init__(
        self,
        url=None,
        profile: DeviceProfile | None = None,
        *,
        scene=None,
        on_status=None,
        reconnect=False,
        realtime=False,
        lead_s: float = 0.0,
        own_core: bool = False,
        on_onset=(),
    ):
        from .link import open_link
        from .streamer import Streamer

        self.url = url
        self.profile = profile or default_profile()
        self.link = open_link(url, self.profile)  # LinkError says why it cannot
        self.description = getattr(self.link, "description", str(url))
        self.streamer = Streamer(
            self.link,
            self.profile,
            scene=scene,
            on_status=on_status,
            reconnect=reconnect,
            realtime=realtime,
            lead_s=lead_s,
            on_onset=on_onset,
        )
        self.on_onset = self.streamer.on_onset
        """The streamer's ``on_onset`` hooks (LSL markers, an OSC server's shapes)."""
        self.taps = self.streamer.taps
        """The streamer's taps (the LSL levels stream, a recorder)."""

    def start(self) -> LocalStream:
        """Start the output thread."""
        self.streamer.start()
        return self

    def stop(self, timeout: float = 3.0) -> StreamStats:
        """Stop (all off) and close the link."""
        stats = self.streamer.stop(timeout)
        self.link.close()
        return stats

    running = property(lambda self: self.streamer.running)
    scene = property(lambda self: self.streamer.scene)
    stats = property(lambda self: self.streamer.stats)
    last_levels = property(lambda self: self.streamer.last_levels)
    last_frame = property(lambda self: self.streamer.last_frame)

    def set_scene(self, scene) -> None:
        """Hand a new scene to the output thread."""
        self.streamer.set_scene(scene)

    def all_off(self) -> None:
        """Pause at once: the next frame is all zeros."""
        self.streamer.all_off()
