"""The device side of the tuner: which link the streamer writes to, and its status."""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore

from tactile_core.device import DeviceProfile, default_profile
from tactile_core.link import SIMULATED_URLS, LinkError, SimulatedArray, open_link
from tactile_core.streamer import Streamer, StreamStats

from .state import TunerState


class DeviceController(QtCore.QObject):
    """Owns the link and the streamer; follows the state's scene.

    The simulated array is used whenever no device is connected, so the views always have
    "sent" and "felt" levels to show. Problems become :attr:`error_raised` messages, never
    exceptions in the GUI. A real device streams with ``reconnect=True``: unplugging it shows a
    status and the stream resumes when it comes back.
    """

    status_changed = QtCore.Signal(object)
    """A :class:`StreamStats` snapshot (emitted on the GUI thread)."""
    connection_changed = QtCore.Signal(str)
    """Description of the link now in use."""
    error_raised = QtCore.Signal(str)

    _status_from_thread = QtCore.Signal(object)

    def __init__(self, state: TunerState, profile: DeviceProfile | None = None, parent=None):
        super().__init__(parent)
        self.state = state
        self.profile = profile or default_profile()
        self.url: str | None = None
        self.link = SimulatedArray(self.profile)
        # Emitted from the output thread; Qt queues it to this object's (the GUI) thread.
        self._status_from_thread.connect(self.status_changed.emit)
        self.streamer = self._start(self.link, reconnect=False)
        state.scene_changed.connect(self._on_state_scene_changed)

    # --- links -------------------------------------------------------------------------------

    def _start(self, link, reconnect: bool) -> Streamer:
        streamer = Streamer(
            link,
            self.profile,
            scene=self.state.scene,
            on_status=self._status_from_thread.emit,
            reconnect=reconnect,
        )
        return streamer.start()

    def _switch(self, link, url: str | None) -> None:
        self.streamer.stop()  # all off on the old link
        self.link.close()
        self.link = link
        self.url = url
        self.streamer = self._start(link, reconnect=url is not None)
        self.connection_changed.emit(self.description)

    @property
    def description(self) -> str:
        """What the streamer writes to."""
        return "simulated array" if self.url is None else self.url

    @property
    def simulated(self) -> bool:
        """True when no device is connected."""
        return isinstance(self.link, SimulatedArray)

    def connect_device(self, url: str | None) -> bool:
        """Open ``url`` (a port or pyserial URL) and stream to it; the simulated array for
        None/"sim". False, with :attr:`error_raised`, if it cannot be opened (the current link
        stays in use)."""
        url = (url or "").strip() or None
        if url is None or url in SIMULATED_URLS:
            self.disconnect_device()
            return True
        try:
            link = open_link(url, self.profile)
        except LinkError as exc:
            self.error_raised.emit(str(exc))
            return False
        self._switch(link, url)
        return True

    def disconnect_device(self) -> None:
        """All off on the device, then back to the simulated array."""
        if not self.simulated or self.url is not None:
            self._switch(SimulatedArray(self.profile), None)

    def set_profile(self, profile: DeviceProfile) -> None:
        """Use another device profile (reopens the current link with it)."""
        self.profile = profile
        if self.url is None:
            self._switch(SimulatedArray(profile), None)
        else:
            url = self.url
            self._switch(SimulatedArray(profile), None)
            self.connect_device(url)

    # --- streaming ---------------------------------------------------------------------------

    def _on_state_scene_changed(self, scene) -> None:
        self.streamer.set_scene(scene)

    def all_off(self) -> None:
        """Everything off at once, and pause."""
        self.streamer.all_off()
        self.state.update(playing=False)

    @property
    def stats(self) -> StreamStats:
        """The streamer's statistics now."""
        return self.streamer.stats

    def sent(self) -> np.ndarray:
        """Levels on the array as fractions of full drive, ``(rows, cols)``."""
        if self.simulated:
            return self.link.sent()
        return self.streamer.last_levels / (self.profile.levels - 1)

    def sent_levels(self) -> np.ndarray:
        """Levels on the array, ``(rows, cols)`` ints."""
        if self.simulated:
            return self.link.levels()
        return self.streamer.last_levels

    def felt(self) -> np.ndarray | None:
        """What the motors would do (the profile's response curve), or None without one."""
        if self.profile.response is None:
            return None
        return self.profile.felt(self.sent())

    def shutdown(self) -> None:
        """All off and close (window close, application exit)."""
        self.streamer.stop()
        self.link.close()
