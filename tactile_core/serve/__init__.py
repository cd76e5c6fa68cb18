"""Driven by other programs: free points over OSC, stimulus markers on Lab Streaming Layer.

A layer above :mod:`tactile_core.device` and below :mod:`tactile_core.stream`: it is handed a
stream's output thread (a :class:`~tactile_core.stream.Streamer`) and feeds it (points and
scenes) and listens to it (the first frame of each presentation, the levels sent).

- :class:`OscServer` (``tactile serve``): OSC messages from a game, Unity, Max, a VRChat bridge
  or a script move free points (:class:`~tactile_core.rendering.points.FreePoints`) rendered by
  the scene's method, play shapes and set the method and correction; its counters are a
  :class:`ServeStats`.
- :class:`LslOutlets` (``--lsl``): a marker per presentation stamped with its first frame's
  time on LSL's clock, and optionally the levels of every frame; :class:`ValidationOutlet`
  the validator's markers (the sensor's onset of each presentation).
- :class:`ServicesHost`: both of them beside a stream's output thread, run by commands; every
  stream carries one (in its child process, or in this one), and the program that owns the
  stream drives it through :class:`~tactile_core.stream.StreamServices`.

``docs/serve.md`` documents the address space and the streams.
"""

from ._lsl import (
    LEVELS_NAME,
    MARKERS_NAME,
    VALIDATION_NAME,
    LslError,
    LslOutlets,
    ValidationOutlet,
    lsl_offset_s,
    marker_text,
)
from ._osc_server import DEFAULT_PORT, SWITCH_INTERVAL_S, OscServer
from ._osc_socket import check_listen, listen_host
from ._osc_wire import Malformed, read_packet
from ._serve_stats import ServeStats
from ._services_host import ServicesHost

__all__ = [
    "DEFAULT_PORT",
    "LEVELS_NAME",
    "MARKERS_NAME",
    "SWITCH_INTERVAL_S",
    "VALIDATION_NAME",
    "LslError",
    "LslOutlets",
    "Malformed",
    "OscServer",
    "ServeStats",
    "ServicesHost",
    "ValidationOutlet",
    "check_listen",
    "listen_host",
    "lsl_offset_s",
    "marker_text",
    "read_packet",
]
