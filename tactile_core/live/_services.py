"""The OSC server and the LSL outlets of a stream, from the program that owns the stream.

:class:`LiveServices` gives a program (the tuner) one way to run another program's points and
the stimulus markers on its stream, wherever the stream's output thread runs:

- a stream process started with ``child=CHILD_MODULE`` (``python -m tactile_core.live._child``)
  runs a :class:`~._services_host.ServicesHost` beside its output thread; commands go down the
  stream's pipe (``StreamerProcess.command``) and events come back through its ``on_event``
  hooks;
- a stream in this process (``open_stream(..., process=False)``) gets a ``ServicesHost`` here,
  with the same commands and events.

Everything is asynchronous: a call returns at once and what came of it arrives as an event
``on_event(kind, payload)`` (``osc-started``, ``osc-failed``, ``osc-stats``, ``osc-scene``,
``lsl-opened``, …; the list is in :mod:`._services_host`), from another thread.
"""

from __future__ import annotations

from .._shared import validate as _validate
from ..rendering.points import DEFAULT_TIMEOUT_S
from ..rendering.scene import Scene
from ._osc_server import DEFAULT_PORT
from ._services_host import ServicesHost

CHILD_MODULE = "tactile_core.live._child"
"""The stream process's entry module with the services: ``open_stream(..., child=...)``."""


class LiveServices:
    """The OSC server and LSL outlets of ``stream``, by commands; their news by events.

    Parameters
    ----------
    stream : StreamerProcess or LocalStream
        A stream process must run :data:`CHILD_MODULE` (``TypeError`` otherwise: its child
        would ignore the commands); a stream of this process (anything with ``streamer`` or
        itself a ``Streamer``) gets the services in this process.
    on_event : callable
        ``on_event(kind, payload)`` from another thread (or, in this process, from the caller's
        or the server's threads): hand it to your own thread.
    """

    def __init__(self, stream, on_event):
        self.stream = stream
        self.on_event = on_event
        self.host: ServicesHost | None = None
        if hasattr(stream, "command"):  # a stream process
            if getattr(stream, "child", None) != CHILD_MODULE:
                raise TypeError(f"the stream process runs {getattr(stream, 'child', '?')}, "
                                f"not {CHILD_MODULE}: open it with child=CHILD_MODULE")  # fmt: skip
            stream.on_event.append(self._event)
            self._command = stream.command
        else:
            streamer = getattr(stream, "streamer", stream)
            self.host = ServicesHost(streamer, stream.profile, lambda m: self._event(*m))
            self._command = lambda kind, *args: self.host.handle((kind, *args))

    def _event(self, kind, payload) -> None:
        self.on_event(kind, payload)

    def start_osc(self, scene: Scene, *, host: str = "127.0.0.1", port: int = DEFAULT_PORT,
                  timeout_s: float = DEFAULT_TIMEOUT_S, interpolate: bool = False,
                  max_rate_hz: float = 10_000.0) -> None:  # fmt: skip
        """Start serving OSC on the stream with ``scene``'s method and correction for the
        points (see :class:`~tactile_core.live.OscServer`); ``osc-started`` or ``osc-failed``
        says how it went. ``ValueError`` here for a value that is wrong whatever the stream."""
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a Scene, got {_validate.shown(scene)}")
        if not isinstance(host, str) or not host:
            raise ValueError(f"host must be an address, got {_validate.shown(host)}")
        options = {
            "scene": scene,
            "host": host,
            "port": _validate.integer("port", port, 0, 65535),
            "timeout_s": timeout_s,
            "interpolate": bool(interpolate),
            "max_rate_hz": max_rate_hz,
        }
        self._command("osc-start", options)

    def set_osc_scene(self, scene: Scene) -> None:
        """The owner's method, correction and the rest for the points (``osc-refused`` for a
        method that needs a shape)."""
        self._command("osc-scene", scene)

    def osc_off(self) -> None:
        """Release every point now."""
        self._command("osc-off")

    def stop_osc(self) -> None:
        """Stop serving: the socket closed, every point released, the stream idle (all off);
        ``osc-stopped`` with the final counters."""
        self._command("osc-stop")

    def open_lsl(self, *, levels: bool = False, rate_hz: float = 300.0,
                 source_id: str | None = None) -> None:  # fmt: skip
        """Open the LSL marker outlet (and the levels outlet) on the stream: ``lsl-opened`` or
        ``lsl-failed``."""
        self._command("lsl", {"levels": bool(levels), "rate_hz": float(rate_hz),
                              "source_id": source_id})  # fmt: skip

    def close_lsl(self) -> None:
        """Close the LSL outlets: ``lsl-closed``."""
        self._command("lsl", None)

    def close(self) -> None:
        """Before the stream stops: in this process, the server and outlets close (a stream
        process closes its own when it stops); no more events."""
        hooks = getattr(self.stream, "on_event", None)
        if hooks is not None and self._event in hooks:
            hooks.remove(self._event)
        if self.host is not None:
            self.host.close()
        self.on_event = lambda kind, payload: None
