"""A stream as a thread of this process, with the interface of
:class:`~.process.StreamerProcess` (for programs without a busy main thread, for tests, and to
measure what the child process buys)."""

from __future__ import annotations

from ..device.profile import DeviceProfile, default_profile
from ..serve import ServicesHost
from ._stats import StreamStats
from .options import StreamOptions


class LocalStream:
    """The interface of :class:`~.process.StreamerProcess` with the streamer as a thread of
    this process; its services (OSC server, LSL outlets) run here too, on the first command.

    Parameters are those of :class:`~.process.StreamerProcess`.
    """

    def __init__(
        self,
        url=None,
        profile: DeviceProfile | None = None,
        *,
        scene=None,
        on_status=None,
        options: StreamOptions | None = None,
        on_onset=(),
        on_event=(),
    ):
        from ..device.link import open_link
        from .streamer import Streamer

        self.url = url
        self.profile = profile or default_profile()
        self.options = StreamOptions() if options is None else options
        self.link = open_link(url, self.profile)  # LinkError says why it cannot
        self.description = getattr(self.link, "description", str(url))
        self.streamer = Streamer(
            self.link,
            self.profile,
            scene=scene,
            options=self.options,
            on_status=on_status,
            on_onset=on_onset,
        )
        self.on_onset = self.streamer.on_onset
        """The streamer's ``on_onset`` hooks (LSL markers, an OSC server's shapes)."""
        self.taps = self.streamer.taps
        """The streamer's taps (the LSL levels stream, a recorder)."""
        self.on_event = list(on_event)
        """Hooks for the events of the services, ``hook(kind, payload)``."""
        self._services: ServicesHost | None = None

    def start(self) -> LocalStream:
        """Start the output thread."""
        self.streamer.start()
        return self

    def stop(self, timeout: float = 3.0) -> StreamStats:
        """Close the services, stop (all off) and close the link."""
        if self._services is not None:
            self._services.close()
            self._services = None
        stats = self.streamer.stop(timeout)
        self.link.close()
        return stats

    def command(self, kind: str, *args) -> None:
        """A command for the services, run here (see :class:`~tactile_core.serve.ServicesHost`);
        what came of it arrives as an event."""
        if self._services is None:
            self._services = ServicesHost(self.streamer, self.profile, self._event)
        try:
            self._services.handle((kind, *args))
        except Exception as exc:  # as in the stream process: said, and the stream goes on
            self._event(("error", f"{kind}: {type(exc).__name__}: {exc}"))

    def _event(self, message) -> None:
        kind, payload = message
        for hook in list(self.on_event):
            try:
                hook(kind, payload)
            except Exception:  # an observer's bug must not stop the services
                pass

    @property
    def running(self) -> bool:
        """True while the output thread runs."""
        return self.streamer.running

    @property
    def scene(self):
        """The scene being played."""
        return self.streamer.scene

    @property
    def stats(self) -> StreamStats:
        """The stream's statistics now."""
        return self.streamer.stats

    @property
    def last_levels(self):
        """Levels of the last frame written, in the layout's frame shape."""
        return self.streamer.last_levels

    @property
    def last_frame(self):
        """``(scene, trace_time_s)`` of the last frame written."""
        return self.streamer.last_frame

    def set_scene(self, scene) -> None:
        """Hand a new scene to the output thread."""
        self.streamer.set_scene(scene)

    def all_off(self) -> None:
        """Pause at once: the next frame is all zeros."""
        self.streamer.all_off()
