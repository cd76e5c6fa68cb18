"""A stream as a thread of this process, with the interface of
:class:`~.process.StreamerProcess` (for programs without a busy main thread, for tests, and to
measure what the child process buys)."""

from __future__ import annotations

from ..device.link import open_link
from ..device.profile import DeviceProfile, default_profile
from ..serve import ServicesHost
from ._stats import StreamStats
from .options import StreamOptions
from .streamer import Streamer


class LocalStream(Streamer):
    """A :class:`~.streamer.Streamer` that opens its own link, with the interface of
    :class:`~.process.StreamerProcess`: its services (OSC server, LSL outlets) run in this
    process too, from the first :meth:`command`; :meth:`stop` closes them and the link.

    Parameters are those of :class:`~.process.StreamerProcess`.

    Raises
    ------
    LinkError
        When the link cannot be opened (nothing keeps running).
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
        profile = profile or default_profile()
        link = open_link(url, profile)  # LinkError says why it cannot
        super().__init__(link, profile, scene=scene, options=options, on_status=on_status,
                         on_onset=on_onset)  # fmt: skip
        self.url = url
        self.description = getattr(link, "description", str(url))
        self.on_event = list(on_event)
        """Hooks for the events of the services, ``hook(kind, payload)``."""
        self._services: ServicesHost | None = None

    def stop(self, timeout: float = 3.0) -> StreamStats:
        """Close the services, stop (all off) and close the link."""
        if self._services is not None:
            self._services.close()
            self._services = None
        stats = super().stop(timeout)
        self.link.close()
        return stats

    def command(self, kind: str, *args) -> None:
        """A command for the services, run here (see :class:`~tactile_core.serve.ServicesHost`);
        what came of it arrives as an event."""
        if self._services is None:
            self._services = ServicesHost(self, self.profile, self._event)
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
