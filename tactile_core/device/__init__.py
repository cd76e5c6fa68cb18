"""The device side: device profiles, the wire format, links, the streamer and the emulator.

Frames leave :mod:`tactile_core.rendering` as intensities; here they become device levels on a
schedule and bytes on a link::

    profile (channels, levels, calibration) -> streamer (frame clock, keep-alive, all-off)
        -> wire (COBS + CRC messages) -> link (serial port, pyserial URL, simulated array)

``array`` is the array's side of the wire format in Python (what the reference firmware does),
``emulator`` puts it on a pseudo-terminal, ``process`` runs a streamer in a child process and
``recorder`` keeps what was sent.
"""

from .link import LinkError, SimulatedArray, open_link
from .profile import (
    DeviceProfile,
    ProfileError,
    default_profile,
    find_profile,
    load_profile,
    profile_from_dict,
    profile_names,
)
from .streamer import Onset, Streamer, StreamStats

__all__ = [
    "DeviceProfile",
    "LinkError",
    "Onset",
    "ProfileError",
    "SimulatedArray",
    "StreamStats",
    "Streamer",
    "default_profile",
    "find_profile",
    "load_profile",
    "open_link",
    "profile_from_dict",
    "profile_names",
]

