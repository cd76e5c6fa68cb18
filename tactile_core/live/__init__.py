"""Driven by other programs: live points over OSC, stimulus markers on Lab Streaming Layer.

A layer above :mod:`tactile_core.device`: it feeds a stream (points and scenes) and listens to
it (the first frame of each presentation, the levels sent).

- :class:`OscServer` (``tactile serve``): OSC messages from a game, Unity, Max, a VRChat bridge
  or a script move live points (:class:`~tactile_core.rendering.points.LivePoints`) rendered by
  the scene's method, play shapes and set the method and correction; its counters are a
  :class:`ServeStats`.
- :class:`LslOutlets` (``--lsl``): a marker per presentation stamped with its first frame's
  time on LSL's clock, and optionally the levels of every frame.
- :class:`LiveServices` (the tuner): both of them beside a stream's output thread, also in a
  stream process started with ``child=CHILD_MODULE``, run by commands from the program that
  owns the stream.

``docs/serve.md`` documents the address space and the streams.
"""

from ._lsl import LEVELS_NAME, MARKERS_NAME, LslError, LslOutlets, lsl_offset_s, marker_text
from ._osc_server import DEFAULT_PORT, SWITCH_INTERVAL_S, OscServer
from ._osc_wire import Malformed, read_packet
from ._serve_stats import ServeStats
from ._services import CHILD_MODULE, LiveServices

__all__ = [
    "CHILD_MODULE",
    "DEFAULT_PORT",
    "LEVELS_NAME",
    "MARKERS_NAME",
    "SWITCH_INTERVAL_S",
    "LiveServices",
    "LslError",
    "LslOutlets",
    "Malformed",
    "OscServer",
    "ServeStats",
    "lsl_offset_s",
    "marker_text",
    "read_packet",
]
