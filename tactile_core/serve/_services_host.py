"""The OSC server and the LSL outlets beside a stream's output thread, run by commands.

:class:`ServicesHost` is what every stream carries with it so that another program may drive it
(the tuner): it lives where the stream's output thread lives, in the stream process
(:mod:`tactile_core.stream._child`) or in this one, so free points never cross a process and a
flood of datagrams never reaches the program's own (GUI) thread. The program that owns the
stream drives it through :class:`~tactile_core.stream.StreamServices`.

Commands (tuples; ``handle``):

- ``("osc-start", options)``: start an :class:`~tactile_core.serve.OscServer` on the stream
  (``options``: ``scene``, ``host``, ``port``, ``timeout_s``, ``interpolate``,
  ``max_rate_hz``); ``("osc-scene", scene)``: the owner's method, correction and the rest for the
  points; ``("osc-off",)``: release every point; ``("osc-stop",)``: close it (all off);
- ``("lsl", options)``: open :class:`~tactile_core.serve.LslOutlets` on the stream
  (``options``: ``levels``, ``rate_hz``, ``source_id``), or close them (``options`` None).

Events (``send((kind, payload))``, from any thread):

- ``osc-started`` ``(host, port)``; ``osc-failed`` the reason; ``osc-warning`` a sentence;
- ``osc-stats`` ``(ServeStats, points)`` ten times a second while serving, ``points`` the
  driven points ``((id, x, y, intensity), ...)`` (at most :data:`MAX_SHOWN`);
- ``osc-scene`` ``{field: value}`` with what a sender changed (``method``, ``mu``, ``gamma``:
  ``/tactile/method``, ``/tactile/mu``, ``/tactile/gamma``), never the owner's own changes: only
  the fields the sender's message set (the server decides them as it applies the message, in
  order with the owner's scenes), so an owner's change on its way down the pipe is not undone;
- ``osc-refused`` the reason (the owner's scene cannot drive points: MM, IM);
- ``osc-stopped`` the final ``ServeStats``;
- ``lsl-opened`` ``{"levels": bool, "source_id": str}`` (and ``"note"``, why the source id
  is not the one asked for, when it is not), ``lsl-failed`` the reason,
  ``lsl-closed`` None.
"""

from __future__ import annotations

import sys
import threading

from ._lsl import LslOutlets
from ._osc_server import OscServer

STATS_S = 0.1
"""Seconds between two ``osc-stats`` events."""
MAX_SHOWN = 8
"""Most driven points an ``osc-stats`` event carries (for display)."""


class ServicesHost:
    """Runs the OSC server and the LSL outlets of one stream, by commands.

    Parameters
    ----------
    streamer : Streamer
        The stream, in this process: its ``set_scene``, ``on_onset`` hooks and ``taps``.
    profile : DeviceProfile
        The array the points render onto and the outlets describe.
    send : callable
        ``send((kind, payload))``: an event for the owner (the pipe to the parent process, or a
        callback), from any thread.
    switch_interval_s : float or None
        While serving, Python's thread switch interval (``sys.setswitchinterval``), put back
        when the server stops; None leaves it. The receiver shares the interpreter lock with the
        output thread: ``tactile serve``'s 0.1 ms keeps a flood out of the frames' tail, and the
        stream process uses it too (:mod:`._child`).
    """

    def __init__(self, streamer, profile, send, *, switch_interval_s: float | None = None):
        self.streamer = streamer
        self.profile = profile
        self.send = send
        self.server: OscServer | None = None
        self.outlets: LslOutlets | None = None
        self.switch_interval_s = switch_interval_s
        self._saved_switch = None
        self._quit = threading.Event()  # the publisher's, one per server
        self._publisher: threading.Thread | None = None

    def handle(self, message) -> None:
        """Obey one command (see the module); ``ValueError`` for a kind it does not know."""
        kind = message[0]
        if kind == "osc-start":
            self._start(dict(message[1]))
        elif kind == "osc-scene":
            self._scene(message[1])
        elif kind == "osc-off":
            if self.server is not None:
                self.server.off()
        elif kind == "osc-stop":
            self._stop()
        elif kind == "lsl":
            self._lsl(message[1])
        else:
            raise ValueError(f"unknown command {kind!r}")

    def close(self) -> None:
        """Close the server and the outlets (the stream is about to stop)."""
        self._stop()
        self._lsl(None, say=False)

    # --- OSC ---------------------------------------------------------------------------------

    def _start(self, options: dict) -> None:
        self._stop(say=False)
        scene = options.pop("scene")
        try:
            server = OscServer(self.streamer, self.profile, scene=scene, on_tuning=self._on_tuning,
                               on_warning=lambda text: self.send(("osc-warning", text)),
                               **options)  # fmt: skip
            server.start()
        except (OSError, ValueError, TypeError) as exc:
            self.send(("osc-failed", str(exc)))
            return
        self.server = server
        if self.switch_interval_s is not None:
            self._saved_switch = sys.getswitchinterval()  # never longer than it is (the
            # tuner's stream process already runs at 50 us)
            sys.setswitchinterval(min(self.switch_interval_s, self._saved_switch))
        self.send(("osc-started", tuple(server.address)))
        self._quit = threading.Event()
        self._publisher = threading.Thread(target=self._publish, args=(server, self._quit),
                                           name="osc-stats", daemon=True)  # fmt: skip
        self._publisher.start()

    def _scene(self, scene) -> None:
        server = self.server
        if server is None:
            return
        try:
            server.set_scene(scene)
        except ValueError as exc:
            self.send(("osc-refused", str(exc)))

    def _on_tuning(self, changed: dict) -> None:
        """A sender changed the points' method or correction: tell the owner what."""
        self.send(("osc-scene", changed))

    def _stop(self, say: bool = True) -> None:
        server, self.server = self.server, None
        self._quit.set()
        if self._publisher is not None:
            self._publisher.join(2.0)
            self._publisher = None
        if server is None:
            return
        stats = server.stop()
        if self._saved_switch is not None:
            sys.setswitchinterval(self._saved_switch)
            self._saved_switch = None
        if say:
            self.send(("osc-stopped", stats))

    def _publish(self, server: OscServer, quit: threading.Event) -> None:
        while True:
            points = server.points.points  # a snapshot: never changes once read
            shown = tuple((str(i), p.x, p.y, p.intensity)
                          for i, p in list(points.items())[:MAX_SHOWN])  # fmt: skip
            self.send(("osc-stats", (server.stats, shown)))
            if quit.wait(STATS_S):
                return

    # --- LSL ---------------------------------------------------------------------------------

    def _lsl(self, options, say: bool = True) -> None:
        if self.outlets is not None:
            self.outlets.detach(self.streamer)
            self.outlets.close()
            self.outlets = None
            if say and options is None:
                self.send(("lsl-closed", None))
        if options is None:
            return
        try:
            self.outlets = LslOutlets(self.profile, rate_hz=options.get("rate_hz", 300.0),
                                      levels=bool(options.get("levels")),
                                      source_id=options.get("source_id"))  # fmt: skip
        except (RuntimeError, ValueError, OSError) as exc:
            self.send(("lsl-failed", str(exc)))
            return
        self.outlets.attach(self.streamer)
        opened = {"levels": bool(options.get("levels")), "source_id": self.outlets.source_id}
        if self.outlets.note:  # another program has the source id asked for
            opened["note"] = self.outlets.note
        self.send(("lsl-opened", opened))
