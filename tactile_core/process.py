"""The streamer in its own process, for programs whose main thread is busy (the GUI).

A :class:`~tactile_core.streamer.Streamer` thread shares Python's global interpreter lock with
every other thread of its process. A GUI repainting plots holds that lock for milliseconds at a
time inside C++ drawing calls, and each frame waits that long: with the tuner's display running,
an in-process stream at 300 Hz showed p99 interval errors of 5-12 ms. :class:`StreamerProcess`
runs the same streamer in a child process (``spawn``) with the link opened there, so nothing in
the parent can delay a frame.

- Scenes go to the child through a pipe (a pickled :class:`~tactile_core.scene.Scene`, ~0.1 ms).
- The child publishes, about 200 times a second, the last levels sent and the trace time of
  the last frame into shared memory, and sends statistics through a second pipe.
- If the parent dies the child sees the pipe close and stops: all off. If the child dies the
  parent reports it, and the array's watchdog turns it off.
"""

from __future__ import annotations

import atexit
import math
import multiprocessing as mp
import threading
import time
import weakref

import numpy as np

from .device import DeviceProfile, default_profile, profile_from_dict
from .link import LinkError
from .scene import Scene
from .streamer import StreamStats

_CHILDREN: weakref.WeakSet = weakref.WeakSet()


@atexit.register
def _stop_children() -> None:
    for child in list(_CHILDREN):
        child.stop(timeout=2.0)


def _child_main(cmd, events, url, profile_data, scene, reconnect, levels, meta):
    """Entry point of the child: open the link, stream, obey commands until told to stop."""
    from .link import open_link
    from .streamer import Streamer

    profile = profile_from_dict(profile_data, source="profile")
    try:
        link = open_link(url, profile)
    except LinkError as exc:
        events.send(("opened", False, str(exc)))
        return
    events.send(("opened", True, getattr(link, "description", str(url))))
    lock = threading.Lock()

    def send(message):
        with lock:
            try:
                events.send(message)
            except (OSError, EOFError):
                pass

    scene_ids = {}
    if scene is not None:
        scene_ids[id(scene)] = 0
    streamer = Streamer(
        link, profile, scene=scene, reconnect=reconnect, on_status=lambda s: send(("stats", s))
    )
    streamer.start()
    alive = threading.Event()
    alive.set()

    def publish_once():
        frame_scene, trace_time = streamer.last_frame
        levels[:] = streamer.last_levels.reshape(-1).tobytes()  # cell order
        meta[0] = -1.0 if trace_time is None else trace_time
        meta[1] = scene_ids.get(id(frame_scene), -1)
        meta[2] = -1 if streamer.last_seq is None else streamer.last_seq

    def publish():
        last = None
        while alive.is_set():
            publish_once()
            now = time.monotonic()
            if last is None or now - last > 0.1:
                last = now
                send(("stats", streamer.stats))
            time.sleep(0.005)

    publisher = threading.Thread(target=publish, name="publish", daemon=True)
    publisher.start()
    try:
        while True:
            try:
                message = cmd.recv()
            except (EOFError, OSError):
                break  # the parent is gone: turn everything off
            kind = message[0]
            if kind == "scene":
                _, sid, new = message
                if new is not None:
                    scene_ids[id(new)] = sid
                streamer.set_scene(new)
            elif kind == "all_off":
                streamer.all_off()
            elif kind == "stop":
                break
    finally:
        stats = streamer.stop()
        alive.clear()
        publisher.join(1.0)
        publish_once()  # the all-off frame
        link.close()
        send(("stopped", stats))


class StreamerProcess:
    """A streamer running in a child process; the parent-side API mirrors
    :class:`~tactile_core.streamer.Streamer`.

    Parameters
    ----------
    url : str or None
        Device URL for :func:`tactile_core.link.open_link`; None for the simulated array.
    profile : DeviceProfile, optional
    scene : Scene, optional
    on_status : callable, optional
        Called with a :class:`StreamStats` from a listener thread when the state or status
        changes (a GUI hands it to its own thread).
    reconnect : bool
        Passed to the streamer.

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
        reconnect=False,
    ):
        self.url = url
        self.profile = profile or default_profile()
        self.on_status = on_status
        self.reconnect = reconnect
        self._scene = scene
        self._scenes = {0: scene}
        self._next_id = 1
        self._stats = StreamStats(state="starting", status="starting the stream process")
        self._ctx = mp.get_context("spawn")
        n = self.profile.channels
        self._levels = self._ctx.RawArray("B", n)
        self._meta = self._ctx.RawArray("d", [-1.0, -1.0, -1.0])
        self._proc = None
        self._cmd = None
        self._events = None
        self._listener = None
        self._lock = threading.Lock()
        self.description = "simulated array" if url is None else str(url)

    def start(self, timeout: float = 20.0) -> StreamerProcess:
        """Start the child and wait until it has opened the link."""
        cmd_parent, cmd_child = self._ctx.Pipe()
        events_parent, events_child = self._ctx.Pipe(duplex=False)
        self._proc = self._ctx.Process(
            target=_child_main,
            args=(cmd_child, events_child, self.url, self.profile.to_dict(), self._scene,
                  self.reconnect, self._levels, self._meta),
            name="tactile-stream-process",
            daemon=True,
        )  # fmt: skip
        self._proc.start()
        cmd_child.close()
        events_child.close()
        self._cmd, self._events = cmd_parent, events_parent
        if not events_parent.poll(timeout):
            self._proc.kill()
            raise LinkError(f"the stream process did not start within {timeout:g} s")
        try:
            _, ok, message = events_parent.recv()
        except (EOFError, OSError):
            raise LinkError("the stream process ended while opening the link") from None
        if not ok:
            self._proc.join(2.0)
            raise LinkError(message)
        self.description = message
        _CHILDREN.add(self)
        self._listener = threading.Thread(target=self._listen, name="stream-events", daemon=True)
        self._listener.start()
        return self

    def _listen(self) -> None:
        while True:
            try:
                kind, payload = self._events.recv()
            except (EOFError, OSError):
                break
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
        if self.on_status is not None:
            try:
                self.on_status(self._stats)
            except Exception:
                pass

    def _send(self, message) -> None:
        if self._cmd is None:
            return
        try:
            self._cmd.send(message)
        except (OSError, EOFError, BrokenPipeError):
            pass  # the child is gone; the listener reports it

    # --- the Streamer API --------------------------------------------------------------------

    @property
    def running(self) -> bool:
        """True while the child is alive."""
        return self._proc is not None and self._proc.is_alive()

    @property
    def scene(self) -> Scene | None:
        """The last scene handed to the child."""
        return self._scene

    def set_scene(self, scene: Scene | None) -> None:
        """Hand a new scene to the child (it takes effect at its next frame)."""
        if scene is not None and not isinstance(scene, Scene):
            raise ValueError(f"scene must be a Scene or None, got {scene!r}")
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
        self._proc.join(timeout)
        if self._proc.is_alive():
            self._proc.kill()
            self._proc.join(1.0)
        if self._listener is not None:
            self._listener.join(1.0)
        for conn in (self._cmd, self._events):
            if conn is not None:
                conn.close()
        self._cmd = self._events = None
        _CHILDREN.discard(self)
        return self.stats

    @property
    def stats(self) -> StreamStats:
        """The latest statistics from the child (sent every 0.1 s)."""
        with self._lock:
            return self._stats

    @property
    def last_levels(self) -> np.ndarray:
        """Levels of the last frame sent, ``(rows, cols)`` uint8 (the all-off frame last)."""
        return np.frombuffer(self._levels, dtype=np.uint8).copy().reshape(self.profile.grid.shape)

    @property
    def last_frame(self):
        """``(scene, trace_time_s)`` of the last frame sent (time None while off)."""
        trace_time, sid = self._meta[0], int(self._meta[1])
        scene = self._scenes.get(sid)
        if trace_time < 0 or math.isnan(trace_time) or not self.running:
            return scene, None
        return scene, trace_time


class LocalStream:
    """The same interface with the streamer as a thread of this process (for programs without
    a busy main thread, for tests, and to measure what the process buys)."""

    def __init__(
        self,
        url=None,
        profile: DeviceProfile | None = None,
        *,
        scene=None,
        on_status=None,
        reconnect=False,
    ):
        from .link import open_link
        from .streamer import Streamer

        self.url = url
        self.profile = profile or default_profile()
        self.link = open_link(url, self.profile)  # LinkError says why it cannot
        self.description = getattr(self.link, "description", str(url))
        self.streamer = Streamer(
            self.link, self.profile, scene=scene, on_status=on_status, reconnect=reconnect
        )

    def start(self) -> LocalStream:
        """Start the output thread."""
        self.streamer.start()
        return self

    def stop(self, timeout: float = 3.0) -> StreamStats:
        """Stop (all off) and close the link."""
        stats = self.streamer.stop(timeout)
        self.link.close()
        return stats

    running = property(lambda self: self.streamer.running)
    scene = property(lambda self: self.streamer.scene)
    stats = property(lambda self: self.streamer.stats)
    last_levels = property(lambda self: self.streamer.last_levels)
    last_frame = property(lambda self: self.streamer.last_frame)

    def set_scene(self, scene) -> None:
        """Hand a new scene to the output thread."""
        self.streamer.set_scene(scene)

    def all_off(self) -> None:
        """Pause at once: the next frame is all zeros."""
        self.streamer.all_off()


def open_stream(url=None, profile=None, *, scene=None, on_status=None, reconnect=False,
                process=True):  # fmt: skip
    """Open a link and start streaming to it, in a child process (default) or a thread.

    Raises
    ------
    LinkError
        When the link cannot be opened; nothing keeps running.
    """
    cls = StreamerProcess if process else LocalStream
    stream = cls(url, profile, scene=scene, on_status=on_status, reconnect=reconnect)
    return stream.start()
