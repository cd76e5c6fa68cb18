"""The stream: frames at a fixed rate from one output thread, in this process or a child.

Above :mod:`tactile_core.device` (links, wire format, profiles) and :mod:`tactile_core.serve`
(the OSC server and LSL outlets a stream carries)::

    scene -> plan (rate, filter, levels, channel order) -> streamer (frame clock, keep-alive,
        all-off, the array's clock and timed frames) -> link

- :class:`Streamer`: the output thread; :class:`StreamStats` its counters, :class:`Onset` a
  presentation's first frame.
- :class:`StreamOptions`: reconnect, real-time priority, the lead (:data:`MAX_LEAD_MS`,
  :func:`check_lead_ms`) and a core of its own, from :func:`open_stream` down to the thread.
- :func:`open_stream`: a :class:`StreamerProcess` (the streamer in a child process, so that a
  busy GUI never delays a frame) or a :class:`LocalStream` (a thread of this process), with one
  interface; :class:`StreamServices` runs the OSC server and LSL outlets beside either.
"""

from ._local import LocalStream
from .options import DEFAULT_LEAD_MS, MAX_LEAD_MS, StreamOptions, check_lead_ms
from .process import PROCESS_SUPPORTED, StreamerProcess, open_stream
from .services import StreamServices
from .streamer import FINAL_STATUS_WAIT_S, Onset, Streamer, StreamStats

__all__ = [
    "DEFAULT_LEAD_MS",
    "FINAL_STATUS_WAIT_S",
    "MAX_LEAD_MS",
    "PROCESS_SUPPORTED",
    "LocalStream",
    "Onset",
    "StreamOptions",
    "StreamServices",
    "StreamStats",
    "Streamer",
    "StreamerProcess",
    "check_lead_ms",
    "open_stream",
]
