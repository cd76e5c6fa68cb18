"""The device side: device profiles, the wire format, links, the array's side and its emulator.

Levels become bytes on a link here; :mod:`tactile_core.stream` above decides which levels go
when::

    profile (layout, channels, levels, calibration) -> wire (COBS + CRC messages)
        -> link (serial port, pyserial URL, simulated array, audio interface)

``array`` is the array's side of the wire format in Python (what the reference firmware does),
``emulator`` puts it on a pseudo-terminal, ``clock`` estimates the array's clock from clock
exchanges, ``host_clock`` is the host's (and a virtual one for tests), ``frame_log`` keeps
frames received or sent.
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

__all__ = [
    "DeviceProfile",
    "LinkError",
    "ProfileError",
    "SimulatedArray",
    "default_profile",
    "find_profile",
    "load_profile",
    "open_link",
    "profile_from_dict",
    "profile_names",
]
