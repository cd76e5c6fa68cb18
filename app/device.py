"""The device side of the tuner: which link the stream goes to, and its status."""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore

from tactile_core.device.link import SIMULATED_URLS, LinkError
from tactile_core.device.profile import DeviceProfile, default_profile
from tactile_core.stream import (
    DEFAULT_LEAD_MS,
    StreamOptions,
    StreamServices,
    StreamStats,
    check_lead_ms,
    open_stream,
)

from .state import TunerState

TUNE_MARKER = "tune"
"""The presentation kind of the tuner's ordinary playing (a scene no part gave a kind)."""


def outgoing(scene):
    """``scene`` as it goes to the stream: with :data:`TUNE_MARKER` when it has no kind."""
    return scene if scene is None or scene.marker else scene.replace(marker=TUNE_MARKER)


class DeviceController(QtCore.QObject):
    """Owns the stream; follows the state's scene.

    The stream runs in its own process (:class:`tactile_core.stream.process.StreamerProcess`): the
    GUI's painting holds Python's interpreter lock for milliseconds at a time, and a stream
    thread in this process would wait that long for every frame. The simulated array is used
    whenever no device is connected, so the views always have "sent" and "felt" levels to show.
    Problems become :attr:`error_raised` messages, never exceptions in the GUI. A real device
    streams with ``reconnect=True``: unplugging it shows a status, and the stream resumes when
    it comes back.

    Parameters
    ----------
    state : TunerState
    profile : DeviceProfile, optional
    process : bool
        Stream from a child process (default) or from a thread of this one.
    realtime : bool
        Ask for real-time priority for the output thread (Linux, with privileges).
    lead_ms : float
        Frames go this far ahead to an array that plays them at its own time (0: frames for now).

    A stream child gets a core of its own where there are two or more (the GUI runs on the
    others), so that repainting never competes with it for a core. It runs the OSC server and
    the LSL outlets beside its output thread when asked (:attr:`services`, a
    :class:`~tactile_core.stream.StreamServices`; their news as :attr:`service_event`).

    Every scene goes out with a presentation kind for the LSL markers: the one a part gave it
    (``trial``, ``interval``, ``ab``) or :data:`TUNE_MARKER`.
    """

    status_changed = QtCore.Signal(object)
    """A :class:`StreamStats` snapshot (emitted on the GUI thread)."""
    connection_changed = QtCore.Signal(str)
    """Description of the link now in use."""
    error_raised = QtCore.Signal(str)
    profile_changed = QtCore.Signal(object)
    """Another :class:`DeviceProfile` is in use (its layout is the state's now)."""
    service_event = QtCore.Signal(str, object)
    """``(kind, payload)`` from the stream's services (OSC server, LSL outlets; GUI thread)."""

    _status_from_thread = QtCore.Signal(object)
    _service_from_thread = QtCore.Signal(str, object)

    def __init__(self, state: TunerState, profile: DeviceProfile | None = None, parent=None,
                 process: bool = True, realtime: bool = False,
                 lead_ms: float = DEFAULT_LEAD_MS):  # fmt: skip
        super().__init__(parent)
        self.state = state
        self.profile = profile or default_profile()
        self.process = process
        self.realtime = realtime
        self.lead_ms = lead_ms
        self.url: str | None = None
        # Emitted from a worker thread; Qt queues it to this object's (the GUI) thread.
        self._status_from_thread.connect(self.status_changed.emit)
        self._service_from_thread.connect(self.service_event.emit)
        self._generation = 0
        self._apart = (None, "")  # (divert, what plays) of play_apart
        self.divert = None
        """While something else than the state's scene plays on the array (another program's
        points, a pulsed tactor): a callable that takes the state's scenes instead of the
        stream (the OSC server's method and correction; the pulse lets go of the tactor)."""
        self.driven_points: tuple = ()
        """The points another program drives, ``((id, x, y, intensity), ...)``, for display."""
        state.set_layout(self.profile.layout)  # the scene follows the layout before it streams
        self.streamer, self.services = self._open(None)
        state.scene_changed.connect(self._on_state_scene_changed)

    def _open(self, url):
        self._generation += 1
        generation = self._generation

        def on_status(stats):
            # A stream that has been replaced may still report its last words (its all-off,
            # "stopped") after the new one started: those are not the device's state now.
            if generation == self._generation:
                self._status_from_thread.emit(stats)

        def on_event(kind, payload):
            if generation == self._generation:
                self._service_from_thread.emit(kind, payload)

        stream = open_stream(
            url,
            self.profile,
            scene=None if self.divert is not None else outgoing(self.state.scene),
            on_status=on_status,
            options=StreamOptions(
                reconnect=url is not None,
                realtime=self.realtime,
                lead_ms=self.lead_ms,
                own_core=True,
            ),
            process=self.process,
        )
        return stream, StreamServices(stream, on_event)

    def _switch(self, url) -> bool:
        previous = self._generation
        try:
            new, services = self._open(url)
        except LinkError as exc:
            self._generation = previous  # the current stream stays, and so do its reports
            self.error_raised.emit(str(exc))
            return False
        self.services.close()
        self.streamer.stop()  # all off on the old link (its server closed)
        self.streamer, self.services = new, services
        self.url = url
        self.connection_changed.emit(self.description)
        return True

    @property
    def description(self) -> str:
        """What the stream goes to."""
        return "simulated array" if self.url is None else self.url

    @property
    def simulated(self) -> bool:
        """True when no device is connected."""
        return self.url is None

    def connect_device(self, url: str | None) -> bool:
        """Stream to ``url`` (a port or pyserial URL); the simulated array for None/"sim".
        False, with :attr:`error_raised`, if it cannot be opened (the current link stays)."""
        url = (url or "").strip() or None
        if url is None or url in SIMULATED_URLS:
            self.disconnect_device()
            return True
        if url == self.url:
            return True  # already streaming there: opening it again would find it busy
        return self._switch(url)

    def disconnect_device(self) -> None:
        """All off on the device, then back to the simulated array."""
        if self.url is not None:
            self._switch(None)

    def set_profile(self, profile: DeviceProfile) -> None:
        """Use another device profile (reopens the current link with it); the state follows
        its layout first, so the new stream starts with a scene that renders there."""
        self.profile = profile
        self.state.set_layout(profile.layout)
        self.profile_changed.emit(profile)
        url = self.url
        self.url = "reopen"  # force the switch below even for the simulated array
        if not self._switch(url):
            self._switch(None)

    def set_lead(self, lead_ms: float) -> bool:
        """Send frames ``lead_ms`` ahead from now on (reopens the current link); False, with
        :attr:`error_raised`, for a lead outside [0, MAX_LEAD_MS] or a link that cannot
        reopen."""
        try:
            check_lead_ms(lead_ms, "lead")
        except ValueError as exc:
            self.error_raised.emit(str(exc))
            return False
        if lead_ms == self.lead_ms:
            return True
        self.lead_ms = float(lead_ms)
        url = self.url
        self.url = "reopen"  # force the switch below even for the simulated array
        if not self._switch(url):
            self._switch(None)
            return False
        return True

    def _on_state_scene_changed(self, scene) -> None:
        if self.divert is not None:
            self.divert(scene)
        else:
            self.streamer.set_scene(outgoing(scene))

    def play_apart(self, scene, divert, what: str = "") -> None:
        """Play ``scene`` on the array instead of the state's, which stays as it is (a tactor
        pulsed from the heatmap: the controls and the views keep showing the tuning). The
        state's scenes go to ``divert`` (:attr:`divert`) until that is None again and
        :meth:`resume` hands the state's scene back to the stream. ``what``: what plays, in a
        user's words, for the status line (:attr:`playing_apart`)."""
        self.divert = divert
        self._apart = (divert, what)
        self.streamer.set_scene(outgoing(scene))

    @property
    def playing_apart(self) -> str:
        """What :meth:`play_apart` plays while it does (``pulsing tactor (2,3) (CT)``), else
        "" (the state's scene plays, or another program's points)."""
        divert, what = self._apart
        return what if divert is not None and self.divert is divert else ""

    def resume(self) -> None:
        """Hand the state's scene to the stream again (after another program or a pulse
        played)."""
        self.streamer.set_scene(outgoing(self.state.scene))

    def all_off(self) -> None:
        """Everything off at once, and pause."""
        self.streamer.all_off()
        self.state.update(playing=False)

    @property
    def stats(self) -> StreamStats:
        """The stream's statistics now."""
        return self.streamer.stats

    def sent_levels(self) -> np.ndarray:
        """Levels of the last frame sent, ``(rows, cols)`` ints (``(size,)`` on a layout that
        is not a grid)."""
        return self.streamer.last_levels

    def sent(self) -> np.ndarray:
        """Levels of the last frame sent as fractions of full drive, ``(rows, cols)`` (or
        ``(size,)``)."""
        return self.sent_levels() / (self.profile.levels - 1)

    def felt(self) -> np.ndarray | None:
        """What the motors would do (the profile's response curve), or None without one."""
        if self.profile.response is None:
            return None
        return self.profile.felt(self.sent())

    def shutdown(self) -> None:
        """All off and close (window close, application exit): the OSC server and the LSL
        outlets close with the stream."""
        self.services.close()
        self.streamer.stop()
