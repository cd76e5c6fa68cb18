"""The stream process's side: open the link, stream, obey the parent's commands.

:func:`serve` is the whole life of the child that :class:`~.process.StreamerProcess` starts
(``python -m tactile_core.stream``). It reads commands from one pipe and writes events
to the other:

- commands: ``("config", url, profile, scene, options)`` first (``options`` a
  :class:`~.options.StreamOptions`), then ``("scene", id, scene)``, ``("all_off",)``,
  ``("stop",)``, and the services' commands (``osc-start``, ``lsl``, …: see
  :mod:`tactile_core.serve`);
- events, each ``(kind, payload)``: ``opened``, ``frame`` (about 100 a second), ``stats``,
  ``onset``, ``stopped`` last (:data:`STREAM_EVENTS`), and the services' events.

The OSC server and the LSL outlets (:class:`~tactile_core.serve.ServicesHost`) live here beside
the output thread, so another program's points never cross into the parent (a GUI).
"""

from __future__ import annotations

import os
import threading
import time
from multiprocessing.connection import Connection

from ..device.link import LinkError
from ..device.profile import profile_from_dict
from ..serve import SWITCH_INTERVAL_S, ServicesHost

CHILD_SWITCH_INTERVAL_S = 5e-5
"""The child's interpreter switch interval: its other threads (commands, publishing) then hold
the interpreter lock for at most ~50 us when the output thread wants it at a deadline. (The
streamer's own default, 0.5 ms, suits a process with other work to do; the child has none. In
the tuner with the mu slider dragged, 30 scenes a second, the stream's p99 interval error after
each write was 0.29-0.33 ms at 0.5 ms and 0.12-0.20 ms at 50 us.)"""

STREAM_EVENTS = ("opened", "frame", "stats", "onset", "stopped")
"""Event kinds of the stream itself; any other kind is its services'."""


def pin_to(cpus) -> bool:
    """Run this process on ``cpus`` only (Linux); False where that is not possible."""
    try:
        os.sched_setaffinity(0, cpus)
    except (AttributeError, OSError, ValueError):
        return False
    return True


def serve(cmd: Connection, events: Connection) -> None:
    """The child: open the link, stream, obey commands until told to stop or orphaned."""
    from ..device.link import open_link
    from .streamer import Streamer

    _, url, profile_data, scene, options, cpu = cmd.recv()
    profile = profile_from_dict(profile_data, source="profile")
    if cpu is not None:
        pin_to(cpu)
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
        options=options,
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
    services = None
    try:
        services = ServicesHost(streamer, profile, send, switch_interval_s=SWITCH_INTERVAL_S)
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
            else:
                try:
                    services.handle(message)
                except Exception as exc:  # a bad command or a bug: said, and the stream goes on
                    send(("error", f"{kind}: {type(exc).__name__}: {exc}"))
    finally:
        if services is not None:
            try:
                services.close()  # its own threads end before the stream's all-off frame
            except Exception:
                pass
        stats = streamer.stop()
        alive.clear()
        publisher.join(1.0)
        link.close()
        send(frame_message())  # the all-off frame
        send(("stopped", stats))
