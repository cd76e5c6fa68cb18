"""The tuner driven by another program: the OSC server of ``tactile serve`` on the tuner's
stream, and the tuner's presentations as Lab Streaming Layer markers.

The server runs in the stream process, beside the output thread (the device controller's
:class:`~tactile_core.serve.LiveServices`): another program's points never pass through the GUI,
and a flood of datagrams never reaches it. What the tuner does meanwhile:

- its method, μ and γ (the controls) go to the server instead of the stream: they apply to the
  driven points; a method that needs a shape (MM, IM) is refused in the status line;
- ``/tactile/method``, ``/tactile/mu`` and ``/tactile/gamma`` from the sender update the
  tuner's controls, so the sliders always show what the array plays (the last change wins,
  whoever made it);
- the heatmap shows the levels sent (:mod:`.tune.display`), with the first driven point;
- Space pauses the points (all off until Space again), Esc is all off;
- off, the window closing, the stream process ending: the server closes with every point
  released, and the array is off (the tuner's scene paused).

An experiment run and a Blind A/B session present the tuner's own scenes: they turn the server
off, and it cannot be turned on while they last.
"""

from __future__ import annotations

import math
import time

from PySide6 import QtCore

from tactile_core.rendering import placement
from tactile_core.rendering.methods import get_method
from tactile_core.rendering.points import free_method
from tactile_core.serve import DEFAULT_PORT

from .texts import value3

LOOPBACK = ("127.0.0.1", "localhost", "::1")
SENDER_SAID_MS = 5000
"""How long the status line says what the sender set; what it sets meanwhile is added."""


class ServeController(QtCore.QObject):
    """Whether another program drives the array, and whether presentations go out on LSL.

    Parameters
    ----------
    state : TunerState
    device : DeviceController
        Its :attr:`~app.device.DeviceController.services` run the server and the outlets, its
        ``divert`` takes the state's scenes while serving.

    Attributes
    ----------
    serving : str
        ``"off"``, ``"starting"`` or ``"on"``.
    host, port : str, int
        Where to listen (127.0.0.1 and 9100 by default; port 0: any free port).
    address : tuple or None
        ``(host, port)`` the server listens on, once on.
    stats : ServeStats or None
        The server's latest counters.
    lsl_markers, lsl_levels : bool
        The LSL setting: the marker outlet, and the levels outlet beside it.
    lsl_status : str
        ``"off"``, ``"opening"`` or the markers' source id once open.
    blocked : callable
        ``blocked() -> why`` ("" when the server may start): the shell's (a run, a blind test).
    """

    changed = QtCore.Signal()
    """Serving or LSL changed (for the panel and the menu)."""
    stats_changed = QtCore.Signal(object)
    """The server's counters (:class:`~tactile_core.serve.ServeStats`)."""
    message_posted = QtCore.Signal(str, int)
    error_raised = QtCore.Signal(str)

    def __init__(self, state, device, parent=None):
        super().__init__(parent)
        self.state = state
        self.device = device
        self.serving = "off"
        self.host = "127.0.0.1"
        self.port = DEFAULT_PORT
        self.address = None
        self.stats = None
        self.lsl_markers = False
        self.lsl_levels = False
        self.lsl_source_id = None
        """LSL's source id (``tactile-<profile name>`` when None)."""
        self.lsl_status = "off"
        self.blocked = lambda: ""
        self._paused_before = False
        self.clock = time.monotonic
        """Seconds, for how long a sender's changes are told together (tests may set it)."""
        self._said: dict = {}  # what the sender set, as the status line says it
        self._said_at = -math.inf
        state.method_guard = self._method_guard
        device.service_event.connect(self._on_device_service_event)
        device.connection_changed.connect(self._on_device_connection_changed)
        device.status_changed.connect(self._on_device_status_changed)

    def _post(self, text: str, ms: int = 10_000) -> None:
        self.message_posted.emit(text, ms)

    # --- the server ----------------------------------------------------------------------------

    def set_serving(self, on: bool, why: str = "OSC server off: all off") -> bool:
        """Start or stop serving; False (and why, in the status line) when it may not start."""
        if bool(on) == (self.serving != "off"):
            return True
        if not on:
            self._stopped(why, command=True)
            return True
        blocked = self.blocked()
        if blocked:
            self._post(blocked)
            self.changed.emit()
            return False
        method = self.state.scene.method
        if get_method(method).needs_shape:
            instead = placement.default_method(self.state.layout, free_points=True)
            self.state.update(method=instead)
            self._post(f"{method} needs a shape: the driven points play {instead}")
        self.serving = "starting"
        self.device.divert = self._divert
        self._paused_before = not self.state.scene.playing
        if self._paused_before:  # the sender's points play at once (Space pauses them)
            self.state.update(playing=True)
        self._start(self.port)
        self.changed.emit()
        return self.serving != "off"

    def _start(self, port: int) -> None:
        try:
            self.device.services.start_osc(self.state.scene, host=self.host, port=port)
        except ValueError as exc:
            self._failed(str(exc))

    def _failed(self, why: str) -> None:
        self.device.divert = None
        self.serving = "off"
        self.address = None
        if self._paused_before:
            self.state.update(playing=False)  # as it was, and to the stream
        else:
            self.device.resume()
        self.error_raised.emit(f"the OSC server could not start: {why}")
        self.changed.emit()

    def _stopped(self, why: str, command: bool) -> None:
        """Serving ends: the server closed (``command``: told to), the tuner's scene paused."""
        if command:
            self.device.services.stop_osc()
        self.device.divert = None
        self.device.driven_points = ()
        self.serving = "off"
        self.address = None
        if self.state.scene.playing:
            self.state.update(playing=False)  # to the stream now: all off until Space
        else:
            self.device.resume()
        self._post(why)
        self.changed.emit()

    def _divert(self, scene) -> None:
        why = self._method_guard(scene.method)
        if why:  # a whole scene (a preset) with MM or IM: the points keep theirs, and so the state
            instead = placement.default_method(self.state.layout, free_points=True)
            QtCore.QTimer.singleShot(0, lambda: self.state.update(method=instead))
            self._post(f"{why}; playing {instead}")
            return
        self.device.services.set_osc_scene(scene)

    def _sender_set(self, changed: dict) -> str:
        """Every field the sender set while the line saying so is on show, with the value in
        use (``method AS, mu 0.50, gamma 50.00``): a sender's ``/tactile/mu`` followed by its
        ``/tactile/gamma`` said only the gamma. A field changed since by someone else (a
        slider) is left out."""
        now = self.clock()
        if now - self._said_at > SENDER_SAID_MS / 1000:
            self._said = {}
        self._said_at = now
        self._said.update(changed)
        scene = self.state.scene
        self._said = {k: v for k, v in self._said.items() if getattr(scene, k) == v}
        return ", ".join(f"{k} {v}" if k == "method" else f"{k} {value3(v)}"
                         for k, v in self._said.items())  # fmt: skip

    def _method_guard(self, name: str) -> str:
        if self.serving == "off":
            return ""
        try:
            free_method(name)
        except ValueError as exc:
            return f"another program drives free points over OSC: {exc}"
        return ""

    # --- LSL -----------------------------------------------------------------------------------

    def set_lsl(self, markers: bool, levels: bool | None = None) -> None:
        """Open (or close) the marker outlet, and with ``levels`` the levels outlet beside it."""
        self.lsl_markers = bool(markers)
        if levels is not None:
            self.lsl_levels = bool(levels)
        if self.lsl_markers:
            self._open_lsl()
        elif self.lsl_status != "off":
            self.device.services.close_lsl()
            self.lsl_status = "off"
        self.changed.emit()

    def _open_lsl(self) -> None:
        self.lsl_status = "opening"
        self.device.services.open_lsl(levels=self.lsl_levels, rate_hz=self.state.scene.rate_hz,
                                      source_id=self.lsl_source_id)  # fmt: skip

    # --- what the stream says ------------------------------------------------------------------

    def _on_device_service_event(self, kind: str, payload) -> None:
        if kind == "osc-started" and self.serving == "starting":
            self.serving, self.address = "on", tuple(payload)
            self._post(f"serving OSC on udp {payload[0]}:{payload[1]}: another program drives "
                       "the array", 5000)  # fmt: skip
        elif kind == "osc-failed" and self.serving != "off":
            self._failed(str(payload))
        elif kind == "osc-stats":
            stats, points = payload
            if self.serving != "off":
                self.device.driven_points = points
            self.stats = stats
            self.stats_changed.emit(stats)
            return
        elif kind == "osc-stopped":
            self.stats = payload
            self.stats_changed.emit(payload)
            return
        elif kind == "osc-scene" and self.serving != "off":
            if self.state.update(**payload):  # only what the sender changed
                self._post(f"the sender set {self._sender_set(payload)}", SENDER_SAID_MS)
        elif kind in ("osc-refused", "osc-warning"):
            self._post(str(payload))
        elif kind == "lsl-opened":
            self.lsl_status = f"{payload['source_id']}-markers"
            if payload.get("note"):  # another program on this machine has the usual id
                self._post(payload["note"])
        elif kind == "lsl-failed":
            self.lsl_markers, self.lsl_status = False, "off"
            said = str(payload)  # an LslError names LSL itself
            lsl = "" if said.startswith("Lab Streaming Layer") else "Lab Streaming Layer: "
            self.error_raised.emit(f"{lsl}{said}")
        elif kind == "lsl-closed":
            self.lsl_status = "off"
        elif kind == "error":
            self.error_raised.emit(str(payload))
        self.changed.emit()

    def _on_device_connection_changed(self, _description: str) -> None:
        """Another stream (a device, a profile, a lead): the services again, on it."""
        if self.serving != "off":
            self.serving = "starting"
            self._start(self.address[1] if self.address else self.port)
        if self.lsl_markers:
            self._open_lsl()
        self.changed.emit()

    def _on_device_status_changed(self, stats) -> None:
        if self.lsl_markers and stats.state == "stopped" and self.lsl_status != "off":
            self.lsl_status = "closed with the stream"  # a new stream opens them again
            self.changed.emit()
        if self.serving != "off" and stats.state in ("stopped", "failed"):
            self._stopped(f"the stream {stats.state} ({stats.status}): the OSC server is off",
                          command=stats.state == "failed")  # fmt: skip
