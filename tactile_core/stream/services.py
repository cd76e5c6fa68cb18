"""The OSC server and the LSL outlets of a stream, from the program that owns the stream.

Every stream (:class:`~.process.StreamerProcess`, :class:`~._local.LocalStream`) carries its
services where its output thread runs: a :class:`~tactile_core.serve.ServicesHost` in the child
process, or in this one for a thread. :class:`StreamServices` is the owner's side: commands go
down through the stream's ``command`` and the news comes back through its ``on_event`` hooks, so
another program's points never pass through the owner's (GUI) thread.

Everything is asynchronous: a call returns at once and what came of it arrives as an event
``on_event(kind, payload)`` (``osc-started``, ``osc-failed``, ``osc-stats``, ``osc-scene``,
``lsl-opened``, …; the list is in :mod:`tactile_core.serve`), from another thread.
"""

from __future__ import annotations

from .._shared import validate as _validate
from ..rendering.points import DEFAULT_TIMEOUT_S
from ..rendering.scene import Scene
from ..serve import DEFAULT_PORT


class StreamServices:
    """The OSC server and LSL outlets of ``stream``, by commands; their news by events.

    Parameters
    ----------
    stream : StreamerProcess or LocalStream
        Anything with ``command(kind, *args)`` and an ``on_event`` list of hooks.
    on_event : callable
        ``on_event(kind, payload)`` from another thread: hand it to your own thread.
    """

    def __init__(self, stream, on_event):
        self.stream = stream
        self.on_event = on_event
        stream.on_event.append(self._event)
        self._command = stream.command

    def _event(self, kind, payload) -> None:
        self.on_event(kind, payload)

    def start_osc(self, scene: Scene, *, host: str = "127.0.0.1", port: int = DEFAULT_PORT,
                  timeout_s: float = DEFAULT_TIMEOUT_S, interpolate: bool = False,
                  max_rate_hz: float = 10_000.0) -> None:  # fmt: skip
        """Start serving OSC on the stream with ``scene``'s method and correction for the
        points (see :class:`~tactile_core.serve.OscServer`); ``osc-started`` or ``osc-failed``
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
        """No more events (the stream closes its services when it stops)."""
        if self._event in self.stream.on_event:
            self.stream.on_event.remove(self._event)
        self.on_event = lambda kind, payload: None
