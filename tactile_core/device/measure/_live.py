"""The simulated sensor in real time, on the simulated array (``--input sim`` with ``--device
sim``): the input stand-in for a run without hardware.

It listens to the frames the :class:`~tactile_core.device.link.SimulatedArray` applies (their
host times and levels) and renders the acceleration of :class:`SimulatedSensor` up to the
present whenever it is read: a recording with an exact sample clock, that grows as time
passes, as an audio input's does.
"""

from __future__ import annotations

import threading
import time

import numpy as np

from ._plan import Commands
from ._recording import Recording
from ._sim import SensorModel, SimulatedSensor

MARGIN_S = 0.002
"""The recording stops this far before the present (frames still on their way)."""


class LiveSimulatedSensor:
    """A simulated sensor on a simulated array, recording in real time.

    Parameters
    ----------
    array : SimulatedArray
        The array it sits on (it adds itself to ``array.listeners``).
    model : SensorModel
        Motors and sensor; its ``on_cell`` is where the sensor sits (see :meth:`place`).
    samplerate : int
    seed : int
    clock : callable
        Host seconds (``time.perf_counter``).
    """

    def __init__(self, array, model: SensorModel, *, samplerate: int = 8000, seed: int = 0,
                 clock=time.perf_counter):  # fmt: skip
        self.array = array
        self.model = model
        self.samplerate = int(samplerate)
        self.channel = model.channel
        self.seed = seed
        self.clock = clock
        self.description = "the simulated sensor (live, on the simulated array)"
        self._cells = np.asarray(array.profile.array.channel_index, dtype=np.int64)
        self._lock = threading.Lock()
        self._last = np.zeros(self._cells.size, dtype=np.int64)
        self._changes: list[tuple[float, int, int]] = []
        self._sim = SimulatedSensor(model, self.samplerate, seed)
        self._chunks: list[np.ndarray] = []
        self._start = self._end = None

    def _on_frame(self, time_s: float, levels: bytes) -> None:
        lv = np.frombuffer(levels, dtype=np.uint8).astype(np.int64)
        with self._lock:
            for ch in np.flatnonzero(lv != self._last):
                self._changes.append((time_s, int(self._cells[ch]), int(lv[ch])))
            self._last = lv

    def place(self, cell: int) -> None:
        """Move the sensor onto tactor ``cell`` (the procedure asks for it; a script of a
        test may put it elsewhere with :attr:`model`)."""
        with self._lock:
            self.model = self.model.replace(on_cell=cell)
            self._sim = SimulatedSensor(self.model, self.samplerate, self.seed + cell)

    def start(self) -> LiveSimulatedSensor:
        """Start listening and recording from now."""
        self.array.listeners.append(self._on_frame)
        self._start = self._end = self.clock()
        return self

    def _render(self) -> None:
        """(Under the lock.) Render up to the present."""
        n = int((self.clock() - MARGIN_S - self._end) * self.samplerate)
        if n <= 0:
            return
        if len(self._changes) > 10_000:  # keep each tactor's last level before the present
            self._changes = _trim(self._changes, self._end - 1.0)
        changes = self._changes
        commands = Commands(np.array([c[0] for c in changes], dtype=np.float64),
                            np.array([c[1] for c in changes], dtype=np.int64),
                            np.array([c[2] for c in changes], dtype=np.int64))  # fmt: skip
        self._chunks.append(self._sim.render(commands, self._end, n))
        self._end += n / self.samplerate

    def _catch_up(self) -> None:
        """Have the array play the timed frames due by now (it tells us of them): the render
        up to the present must not miss one that is waiting for the next write."""
        self.array.levels()

    def clear(self) -> None:
        """Let go of what is recorded so far."""
        self._catch_up()
        with self._lock:
            self._render()
            self._chunks.clear()
            self._start = self._end

    def covers(self, host_s: float) -> bool:
        """True once the present is past ``host_s`` (the recording reaches it when read)."""
        return self.clock() - MARGIN_S >= host_s

    def wait_until(self, host_s: float, timeout_s: float) -> bool:
        """Wait until :meth:`covers` ``host_s``; False after ``timeout_s``."""
        deadline = time.monotonic() + timeout_s
        while not self.covers(host_s):
            if time.monotonic() >= deadline:
                return False
            time.sleep(min(0.01, max(host_s - self.clock(), 0.001)))
        return True

    def recording(self, since_s: float | None = None) -> Recording:
        """Everything since :meth:`start` (or :meth:`clear`; or host time ``since_s``), up to
        the present."""
        self._catch_up()
        with self._lock:
            self._render()
            if len(self._chunks) > 64:  # a long validator session: keep it bounded
                drop = self._chunks[:-64]
                self._start += sum(len(c) for c in drop) / self.samplerate
                del self._chunks[:-64]
            chunks = list(self._chunks)
            start = self._start
        while since_s is not None and len(chunks) > 1:
            if start + len(chunks[0]) / self.samplerate > since_s:
                break
            start += len(chunks.pop(0)) / self.samplerate
        x = (np.concatenate(chunks) if chunks
             else np.zeros((0, self.model.channels), dtype=np.float32))  # fmt: skip
        return Recording(x, self.samplerate, start, 1.0, self.channel, self.description)

    def stop(self) -> None:
        """Stop listening."""
        if self._on_frame in self.array.listeners:
            self.array.listeners.remove(self._on_frame)

    def __enter__(self) -> LiveSimulatedSensor:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()


def _trim(changes: list, before_s: float) -> list:
    """``changes`` from ``before_s`` on, with each tactor's last change before it."""
    last: dict = {}
    later = []
    for change in changes:
        if change[0] < before_s:
            last[change[1]] = change
        else:
            later.append(change)
    return sorted(last.values()) + later
