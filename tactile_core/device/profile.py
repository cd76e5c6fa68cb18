"""Device profiles: a versioned JSON description of a physical array.

A profile (``assets/devices/palm-5x6.json`` is the paper's array) holds::

    {
      "format": "tactile-device-profile",   # required, exactly this
      "version": 1,                         # required; newer versions are refused
      "name": "palm-5x6",
      "description": "...",                 # optional
      "columns": 5, "rows": 6,              # grid, each >= 1
      "pitch_mm": 18.0,                     # > 0
      "levels": 23,                         # 2..256 (one byte per channel on the wire)
      "baud": 115200,                       # > 0; caps the frame rate: baud / 10 / frame bytes
      "channel_order": "row-major",         # or "column-major", or a list: cell of channel k
      "response": {                         # optional motor response curve, piecewise linear
        "drive": [0, 0.2, ..., 1],          #   strictly increasing from 0 to 1
        "output": [0, 0, ..., 1]            #   non-decreasing, within [0, 1]
      },
      "calibration": {                      # optional, one value per tactor, row-major
        "offset": [0.0, ...],               #   added to a lit tactor's drive, within [-1, 1]
        "gain": [1.0, ...],                 #   multiplies it, within (0, 10]
        "threshold": [0.25, ...]            #   optional: measured detection thresholds, [0, 1]
      },
      "carrier_hz": 250,                    # optional, audio: one, or one per channel
      "waveform": "square+adsr:5,20,0.7,50" # optional, audio: one spec, or one per channel
    }

Unknown keys are ignored (so a newer minor addition does not break an older reader). A file
that is not valid JSON, misses a field, or holds a bad value raises :class:`ProfileError`
naming the file, the field and the problem.

Calibration maps a corrected intensity ``I > 0`` to the drive sent to that tactor:
``clip(offset + gain * I, 0, 1)``; zero stays zero. It lets one choice of mu and gamma feel the
same on tactors whose thresholds and sensitivities differ (paper section 4.2).

This module finds and loads profiles; the class lives in ``_device_profile`` and the checks of
the JSON fields in ``_profile_json`` (both importable from here).
"""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

from .._shared import validate as _validate
from .._shared.assets import asset_path, assets_dir
from .._shared.jsonfile import read_json_digest
from ._device_profile import DeviceProfile, profile_from_dict
from ._profile_json import FORMAT, MAX_BAUD, MIN_BAUD, NAME, VERSION, ProfileError

# ``_name as _name``: helpers of the module before the split, still importable from here.
from ._profile_json import _field as _field
from ._profile_json import _integer as _integer
from ._profile_json import _number as _number
from ._profile_json import _numbers as _numbers

__all__ = [
    "DEFAULT_PROFILE",
    "FORMAT",
    "MAX_BAUD",
    "MIN_BAUD",
    "NAME",
    "VERSION",
    "DeviceProfile",
    "ProfileError",
    "default_profile",
    "find_profile",
    "load_profile",
    "profile_from_dict",
    "profile_names",
    "user_profiles_dir",
]

DEFAULT_PROFILE = "palm-5x6"


def load_profile(path_or_name=None) -> DeviceProfile:
    """Load a device profile from a file, or a bundled one by name (default: the palm array).

    Parameters
    ----------
    path_or_name : str or Path, optional
        A path to a JSON file, or the name of a bundled profile (``"palm-5x6"``).

    Raises
    ------
    ProfileError
        When the file is missing, unreadable, not JSON, or invalid.
    """
    if path_or_name is None:
        path_or_name = DEFAULT_PROFILE
    if not isinstance(path_or_name, (str, os.PathLike)):
        raise ProfileError(
            f"device profile must be a name, a path or a DeviceProfile, got "
            f"{_validate.shown(path_or_name)}"
        )
    if not str(path_or_name).strip():  # Path('') is '.', the current folder
        raise ProfileError(
            f"device profile: an empty path names no file (got {_validate.shown(path_or_name)}); "
            "leave the option out for the palm array"
        )
    path = Path(path_or_name)
    if not path.suffix and not path.exists():
        try:
            path = asset_path("devices", f"{path_or_name}.json")
        except FileNotFoundError:
            raise ProfileError(f"{path_or_name}: no such profile file or bundled profile") from None
    if not path.exists() and path.suffix.lower() == ".json" and path.name == str(path_or_name):
        try:  # belt-8.json for the bundled belt-8: say how it is named
            asset_path("devices", path.name)
        except FileNotFoundError:
            pass
        else:
            raise ProfileError(
                f"{path}: no such file (the bundled profile is named without .json: {path.stem})"
            )
    data, digest = read_json_digest(path, ProfileError)
    source = str(path)
    profile = profile_from_dict(data, source=source)
    return dataclasses.replace(profile, path=source, file_sha256=digest)


def user_profiles_dir() -> Path:
    """Where a user's own device profiles live: ``$XDG_CONFIG_HOME/tactile-tuner/devices``
    (``~/.config/tactile-tuner/devices`` by default)."""
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "tactile-tuner" / "devices"


def profile_names() -> dict[str, Path]:
    """Known profiles by name: the bundled ones, then the user's (a user's file of the same name
    takes precedence). A file whose name is not a valid profile name is ignored."""
    found = {}
    for folder in (assets_dir() / "devices", user_profiles_dir()):
        if folder.is_dir():
            for path in sorted(folder.glob("*.json")):
                if NAME.fullmatch(path.stem):
                    found[path.stem] = path
    return found


def find_profile(name) -> DeviceProfile:
    """The profile called ``name`` among the bundled and the user's profiles (never a path).

    Raises
    ------
    ProfileError
        When ``name`` is not a profile name, or no such profile exists, or its file is invalid.
    """
    if not isinstance(name, str) or not NAME.fullmatch(name):
        raise ProfileError(
            f"device profile must be a profile name (letters, digits, '_', '.', '-'), "
            f"not a path: got {_validate.shown(name)}"
        )
    known = profile_names()
    if name not in known:
        raise ProfileError(
            f"no device profile named {_validate.shown(name)} "
            f"(bundled or in {user_profiles_dir()}); "
            f"known: {', '.join(known) or 'none'}"
        )
    profile = load_profile(known[name])
    if profile.name != name:
        raise ProfileError(
            f"{known[name]}: its field 'name' is {_validate.shown(profile.name)}, "
            f"not {_validate.shown(name)}"
        )
    return profile


def default_profile() -> DeviceProfile:
    """The bundled profile of the paper's palm array (the simulated array's default)."""
    return load_profile(DEFAULT_PROFILE)
