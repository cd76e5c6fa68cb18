"""The stream process's side: open the link, stream, obey the parent's commands.

:func:`serve` is the whole life of the child that :class:`~.process.StreamerProcess` starts
(``python -m tactile_core.device.process``, or an entry module of a layer above that passes an
*extension*). It reads commands from one pipe and writes events to the other:

- commands: ``("config", url, profile, scene, options)`` first, then ``("scene", id, scene)``,
  ``("all_off",)``, ``("stop",)``, and any other kind for the extension;
- events, each ``(kind, payload)``: ``opened``, ``frame`` (about 100 a second), ``stats``,
  ``onset``, ``stopped`` last, and any other kind the extension sends.

An extension lets a layer above the device (the OSC server and the LSL outlets of
:mod:`tactile_core.live`) live in the child beside the output thread without this layer
importing it: ``extension(streamer, profile, send)`` is called once the stream runs and returns
an object with ``handle(message)`` (a command of a kind this module does not know) and
``close()`` (called before the stream stops, on every way out); ``send((kind, payload))``
writes an event to the parent from any thread.
"""

from __future__ import annotations

import os
import threading
import time
from multiprocessing.connection import Connection

from .link import LinkError
from .profile import profile_from_dict

CHILD_SWITCH_INTERVAL_S = 5e-5
"""The child's interpreter switch interval: its other threads (commands, publishing) then hold
the interpreter lock for at most ~50 us when the output thread wants it at a deadline. (The
streamer's own default, 0.5 ms, suits a process with other work to do; the child has none. In
the tuner with the mu slider dragged, 30 scenes a second, the stream's p99 interval error after
each write was 0.29-0.33 ms at 0.5 ms and 0.12-0.20 ms at 50 us.)"""

BUILT_IN_EVENTS = ("opened", "frame", "stats", "onset", "stopped")
"""Event kinds of the stream itself; any other kind is an extension's."""


def pin_to(cpus) -> bool:
    """Run this process on ``cpus`` only (Linux); False where that is not possible."""
    try:
        os.sched_setaffinity(0, cpus)
    except (AttributeError, OSError, ValueError):
        return False
    return True


def serve(cmd: Connection, events: Connection, extension=None) -> None:
    """The child: open the link, stream, obey commands until told to stop or orphaned."""
    from .link import open_link
    from .streamer import Streamer

    _, url, profile_data, scene, options = cmd.recv()
    profile = profile_from_dict(profile_data, source="profile")
    if options.get("cpu") is not None:
        pin_to(options["cpu"])
    lock = threading.Lock()

    def send(message) -> None:
        with lock:
            try:
                events.send(message)
            except (OSError, EOFError):
                pass

    try:
        link = open_link(url, profile)
    except LinkError as exc:
        send(("opened", False, str(exc)))
        return
    send(("opened", True, getattr(link, "description", str(url))))
    scene_ids = {} if scene is None else {id(scene): 0}

    def onset(o) -> None:  # a presentation's first frame, for the parent's hooks
        send(("onset", (scene_ids.get(id(o.scene), -1), o.time_s, o.seq, o.timed, o.cycle)))

    streamer = Streamer(
        link,
        profile,
        scene=scene,
        reconnect=options["reconnect"],
        realtime=options["realtime"],
        lead_s=options["lead_s"],
        on_status=lambda s: send(("stats", s)),
        on_onset=[onset],
        switch_interval_s=CHILD_SWITCH_INTERVAL_S,
    )
    streamer.start()
    alive = threading.Event()
    alive.set()

    def frame_message():
        frame_scene, trace_time = streamer.last_frame
        levels = streamer.last_levels.tobytes()  # cell order
        return ("frame", (levels, trace_time, scene_ids.get(id(frame_scene), -1)))

    def publish() -> None:
        last_stats = 0.0
        while alive.is_set():
            send(frame_message())
            now = time.monotonic()
            if now - last_stats > 0.1:
                last_stats = now
                send(("stats", streamer.stats))
            time.sleep(0.01)

    publisher = threading.Thread(target=publish, name="publish", daemon=True)
    publisher.start()
    helper = None
    try:
        helper = None if extension is None else extension(streamer, profile, send)
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
            elif helper is not None:
                try:
                    helper.handle(message)
                except Exception as exc:  # an extension's bug: said, and the stream goes on
                    send(("error", f"{kind}: {type(exc).__name__}: {exc}"))
    finally:
        if helper is not None:
            try:
                helper.close()  # its own threads end before the stream's all-off frame
            except Exception:
                pass
        stats = streamer.stop()
        alive.clear()
        publisher.join(1.0)
        link.close()
        send(frame_message())  # the all-off frame
        send(("stopped", stats))
