"""The streamer in its own process, for programs whose main thread is busy (the GUI).

A :class:`~.streamer.Streamer` thread shares Python's global interpreter lock with
every other thread of its process. A GUI repainting plots holds that lock for milliseconds at a
time inside C++ drawing calls, and each frame waits that long: with the tuner's display running,
an in-process stream at 300 Hz showed p99 interval errors of 10-12 ms. :class:`StreamerProcess`
runs the same streamer in a child process (``python -m tactile_core.stream``) with the link
opened there, so nothing in the parent can delay a frame.

- Scenes go to the child through a pipe (a pickled :class:`~tactile_core.Scene`, ~0.1 ms).
- The child reports back, about 100 times a second, the levels and trace time of the last
  frame sent (for display), and its statistics every 0.1 s.
- If the parent dies, the child sees the pipe close and stops: all off. If the child dies, the
  parent reports it, and the array's watchdog turns it off.

The child is a plain subprocess talking over two inherited pipes, not ``multiprocessing``:
``spawn`` would re-import the parent's main script, so a caller without an
``if __name__ == "__main__"`` guard would run its own top level twice.
"""

from __future__ import annotations

import atexit
import os
import subprocess
import sys
import threading
import weakref
from multiprocessing.connection import Connection

import numpy as np

from ..device.link import LinkError
from ..device.profile import DeviceProfile, default_profile
from ..rendering.scene import Scene, check_scene
from ._child import STREAM_EVENTS, pin_to, serve
from ._local import LocalStream
from .options import StreamOptions
from .streamer import Onset, StreamStats

_CHILDREN: weakref.WeakSet = weakref.WeakSet()
CHILD_MODULE = "tactile_core.stream"
"""The stream process's entry: ``python -m tactile_core.stream`` (its ``__main__``)."""

PROCESS_SUPPORTED = os.name == "posix"
"""Child-process streaming needs inherited pipe descriptors (POSIX); elsewhere threads."""


@atexit.register
def _stop_children() -> None:
    for child in list(_CHILDREN):
        child.stop(timeout=2.0)


def own_core() -> tuple[set, set] | None:
    """A core for the stream and the rest for everything else: ``(stream's, others)``, or None
    with fewer than two cores to choose from (or no affinity on this system)."""
    try:
        cpus = sorted(os.sched_getaffinity(0))
    except AttributeError:
        return None
    if len(cpus) < 2:
        return None
    return {cpus[-1]}, set(cpus[:-1])


def main(argv=None) -> int:
    """Entry point of the child: ``python -m tactile_core.stream CMD_FD EVENTS_FD``.

    Ctrl-C and SIGHUP from the terminal reach the whole process group; the child ignores them
    and lets the parent stop it (or notices the parent is gone when its pipe closes), so a
    Ctrl-C in the tuner's terminal prints no traceback from here and always ends all-off.
    """
    import signal

    for name in ("SIGINT", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_IGN)
    argv = sys.argv[1:] if argv is None else argv
    cmd = Connection(int(argv[0]), writable=False)
    events = Connection(int(argv[1]), readable=False)
    try:
        serve(cmd, events)
    finally:
        events.close()
        cmd.close()
    return 0


class StreamerProcess:
    """A streamer running in a child process; the parent-side API mirrors
    :class:`~.streamer.Streamer`.

    Parameters
    ----------
    url : str or None
        Device URL for :func:`tactile_core.device.link.open_link`; None for the simulated array.
    profile : DeviceProfile, optional
    scene : Scene, optional
    on_status : callable, optional
        Called with a :class:`StreamStats` from a listener thread when the state or status
        changes (a GUI hands it to its own thread).
    options : StreamOptions, optional
        Handed to the child's streamer as they are; with ``own_core`` and two or more cores,
        the child runs on a core of its own and this process on the others until :meth:`stop`
        (Linux), so that nothing of the parent (a GUI repainting) competes with the stream.
    on_onset : sequence of callables
        The streamer's ``on_onset`` hooks, called from a listener thread with an ``Onset``
        whose scene is the one handed to :meth:`set_scene` (LSL markers: the list is
        ``self.on_onset``, so ``LslOutlets.attach`` adds its marker hook; the levels stream
        needs the stream in this process).
    on_event : sequence of callables
        Called as ``hook(kind, payload)`` from the listener thread with every event of the
        stream's services (the OSC server and LSL outlets in the child, driven by
        :meth:`command`; see :class:`~.services.StreamServices`); the list is
        ``self.on_event``.

    Raises
    ------
    LinkError
        From :meth:`start` when the child cannot open the link (the message says why).
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
        self.on_onset = list(on_onset)
        self.on_event = list(on_event)
        self.options = StreamOptions() if options is None else options
        self._saved_affinity = None
        self.url = url
        self.profile = profile or default_profile()
        self.on_status = on_status
        self._scene = scene
        self._scenes = {0: scene}
        self._next_id = 1
        self._stats = StreamStats(state="starting", status="starting the stream process")
        self._levels = bytes(self.profile.channels)
        self._frame = (-1, None)  # (scene id, trace time)
        self._proc = None
        self._cmd = None
        self._events = None
        self._listener = None
        self._lock = threading.Lock()
        self.description = "simulated array" if url is None else str(url)

    def start(self, timeout: float = 20.0) -> StreamerProcess:
        """Start the child and wait until it has opened the link."""
        cmd_read, cmd_write = os.pipe()
        events_read, events_write = os.pipe()
        try:
            self._proc = subprocess.Popen(
                [
                    sys.executable,
                    "-m",
                    CHILD_MODULE,
                    str(cmd_read),
                    str(events_write),
                ],
                pass_fds=(cmd_read, events_write),
                stdin=subprocess.DEVNULL,
            )
        finally:
            os.close(cmd_read)
            os.close(events_write)
        self._cmd = Connection(cmd_write, readable=False)
        self._events = Connection(events_read, writable=False)
        cores = own_core() if self.options.own_core else None
        cpu = None if cores is None else cores[0]
        self._send(("config", self.url, self.profile.to_dict(), self._scene, self.options, cpu))
        if cores is not None:
            self._saved_affinity = os.sched_getaffinity(0)
            pin_to(cores[1])
        if not self._events.poll(timeout):
            self._kill()
            raise LinkError(f"the stream process did not start within {timeout:g} s")
        try:
            _, ok, message = self._events.recv()
        except (EOFError, OSError):
            self._kill()
            raise LinkError("the stream process ended while opening the link") from None
        if not ok:
            self._kill()
            raise LinkError(message)
        self.description = message
        _CHILDREN.add(self)
        self._listener = threading.Thread(target=self._listen, name="stream-events", daemon=True)
        self._listener.start()
        return self

    def _kill(self) -> None:
        if self._proc is not None and self._proc.poll() is None:
            self._proc.kill()
        if self._proc is not None:
            self._proc.wait(2.0)
        self._close_pipes()
        self._restore_affinity()

    def _close_pipes(self) -> None:
        for conn in (self._cmd, self._events):
            if conn is not None:
                conn.close()
        self._cmd = self._events = None

    def _listen(self) -> None:
        events = self._events
        while True:
            try:
                kind, payload = events.recv()
            except (EOFError, OSError):
                break
            if kind == "frame":
                levels, trace_time, sid = payload
                self._levels = levels
                self._frame = (sid, trace_time)
                continue
            if kind == "onset":
                self._onset(*payload)
                continue
            if kind not in STREAM_EVENTS:
                self._event(kind, payload)
                continue
            with self._lock:
                old = self._stats
                self._stats = payload
            if kind == "stopped":
                break
            if self.on_status is not None and (payload.state, payload.status) != (
                old.state,
                old.status,
            ):
                try:
                    self.on_status(payload)
                except Exception:
                    pass
        with self._lock:
            if self._stats.state != "stopped":
                self._stats = StreamStats(
                    **{**self._stats.__dict__, "state": "stopped", "status": "stream process ended"}
                )
            final = self._stats
        if self.on_status is not None:
            try:
                self.on_status(final)
            except Exception:
                pass

    def _onset(self, sid, time_s, seq, timed, cycle) -> None:
        onset = Onset(self._scenes.get(sid), time_s, seq, timed, cycle)
        for hook in list(self.on_onset):
            try:
                hook(onset)
            except Exception:  # an observer's bug must not stop the listener
                pass

    def _event(self, kind, payload) -> None:
        for hook in list(self.on_event):
            try:
                hook(kind, payload)
            except Exception:  # an observer's bug must not stop the listener
                pass

    def command(self, kind: str, *args) -> None:
        """Send the child's services a command (``osc-start``, ``lsl``, …: see
        :class:`~tactile_core.serve.ServicesHost`); what came of it arrives as an event."""
        if kind in ("config", "scene", "all_off", "stop"):
            raise ValueError(f"command kind {kind!r} is the stream's own")
        self._send((kind, *args))

    def _send(self, message) -> None:
        if self._cmd is None:
            return
        try:
            self._cmd.send(message)
        except (OSError, EOFError):
            pass  # the child is gone; the listener reports it

    # --- the Streamer API --------------------------------------------------------------------

    @property
    def running(self) -> bool:
        """True while the child is alive."""
        return self._proc is not None and self._proc.poll() is None

    @property
    def scene(self) -> Scene | None:
        """The last scene handed to the child."""
        return self._scene

    def set_scene(self, scene: Scene | None) -> None:
        """Hand a new scene to the child (it takes effect at its next frame)."""
        check_scene(scene)
        sid = self._next_id
        self._next_id += 1
        self._scene = scene
        self._scenes[sid] = scene
        if len(self._scenes) > 64:
            for old in sorted(self._scenes)[:-32]:
                del self._scenes[old]
        self._send(("scene", sid, scene))

    def all_off(self) -> None:
        """Pause at once: the next frame is all zeros."""
        scene = self._scene
        self._scene = None if scene is None else scene.replace(playing=False)
        self._send(("all_off",))

    def stop(self, timeout: float = 3.0) -> StreamStats:
        """Stop the child (it sends the all-off frame) and return the final statistics."""
        if self._proc is None:
            return self.stats
        self._send(("stop",))
        try:
            self._proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait(2.0)
        if self._listener is not None:
            self._listener.join(2.0)
        self._close_pipes()
        _CHILDREN.discard(self)
        self._restore_affinity()
        return self.stats

    def _restore_affinity(self) -> None:
        if self._saved_affinity is not None:
            pin_to(self._saved_affinity)
            self._saved_affinity = None

    @property
    def stats(self) -> StreamStats:
        """The latest statistics from the child (sent every 0.1 s)."""
        with self._lock:
            return self._stats

    @property
    def last_levels(self) -> np.ndarray:
        """Levels of the last frame sent, uint8 in the layout's frame shape (``(rows, cols)``
        on a grid, ``(size,)`` on a layout; the all-off frame last)."""
        return (
            np.frombuffer(self._levels, dtype=np.uint8)
            .copy()
            .reshape(self.profile.layout.frame_shape)
        )

    @property
    def last_frame(self):
        """``(scene, trace_time_s)`` of the last frame sent (time None while off)."""
        sid, trace_time = self._frame
        scene = self._scenes.get(sid)
        if not self.running:
            return scene, None
        return scene, trace_time


def open_stream(url=None, profile=None, *, scene=None, on_status=None,
                options: StreamOptions | None = None, process: bool = True, on_onset=(),
                on_event=()):  # fmt: skip
    """Open a link and start streaming to it, in a child process (default) or a thread.

    Parameters
    ----------
    url : str or None
        A device URL (:func:`tactile_core.device.open_link`); None for the simulated array.
    profile : DeviceProfile, optional
        The array; the palm array by default.
    scene : Scene, optional
        What to play first; idle (all off) if None.
    on_status : callable, optional
        ``on_status(stats)`` when the stream's state or status changes, from another thread.
    options : StreamOptions, optional
        Reconnect, real-time priority, the lead and a core of its own, as they are for every
        kind of stream.
    process : bool
        A child process (default) or a thread of this one; a thread where child processes are
        not supported.
    on_onset : sequence of callables
        Hooks for each presentation's first frame (an ``Onset``; ``stream.on_onset`` is the
        list).
    on_event : sequence of callables
        Hooks for the events of the stream's services (``stream.on_event`` is the list).

    Returns
    -------
    StreamerProcess or LocalStream
        Started; both have the same interface.

    Raises
    ------
    LinkError
        When the link cannot be opened; nothing keeps running.
    """
    kind = StreamerProcess if process and PROCESS_SUPPORTED else LocalStream
    stream = kind(url, profile, scene=scene, on_status=on_status, options=options,
                  on_onset=on_onset, on_event=on_event)  # fmt: skip
    return stream.start()
