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
      }
    }

Unknown keys are ignored (so a newer minor addition does not break an older reader). A file
that is not valid JSON, misses a field, or holds a bad value raises :class:`ProfileError`
naming the file, the field and the problem.

Calibration maps a corrected intensity ``I > 0`` to the drive sent to that tactor:
``clip(offset + gain * I, 0, 1)``; zero stays zero. It lets one choice of mu and gamma feel the
same on tactors whose thresholds and sensitivities differ (paper section 4.2).
"""

from __future__ import annotations

import bisect
import dataclasses
import hashlib
import json
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._shared import validate as _validate
from .._shared.assets import asset_path, assets_dir
from .._shared.jsonfile import read_json_digest, write_json_atomic
from ..rendering.geometry import ArraySpec, Grid
from .wire import frame_length

FORMAT = "tactile-device-profile"
VERSION = 1
DEFAULT_PROFILE = "palm-5x6"
NAME = re.compile(r"[A-Za-z0-9_.-]{1,64}")
"""A profile's name: what presets and sessions refer to it by, and what the firmware reports."""
MIN_BAUD, MAX_BAUD = 9600, 4_000_000
"""Link speeds a profile may give: at 9600 baud the palm array still gets 25 frames a second."""


class ProfileError(ValueError):
    """A device profile that cannot be used; the message names the field and the problem."""


@dataclass(frozen=True)
class DeviceProfile:
    """A physical array and its link.

    Attributes
    ----------
    name : str
    array : ArraySpec
        Grid, pitch, levels and channel order.
    baud : int
        Serial link speed in bit/s (8N1: 10 bits per byte).
    response : tuple of (tuple of float, tuple of float) or None
        ``(drive, output)`` of the motor response curve, if known.
    offset, gain : tuple of float, length rows * cols, or None
        Per-tactor calibration in flat cell order (``row * cols + col``).
    threshold : tuple of float or None
        The detection thresholds the calibration was computed from (informational).
    description : str
    path : str or None
        Where the profile was loaded from.
    file_sha256 : str or None
        SHA-256 of the bytes of that file (None for a profile built or changed in memory).
    """

    name: str
    array: ArraySpec
    baud: int = 115200
    response: tuple | None = None
    offset: tuple | None = None
    gain: tuple | None = None
    threshold: tuple | None = None
    description: str = ""
    path: str | None = field(default=None, compare=False)
    file_sha256: str | None = field(default=None, compare=False)

    @property
    def grid(self) -> Grid:
        """The tactor grid."""
        return self.array.grid

    @property
    def levels(self) -> int:
        """Number of device levels."""
        return self.array.levels

    @property
    def channels(self) -> int:
        """Number of channels (one per tactor)."""
        return self.array.grid.size

    @property
    def frame_bytes(self) -> int:
        """Bytes on the wire per frame (36 for 30 channels)."""
        return frame_length(self.channels)

    @property
    def max_rate_hz(self) -> float:
        """Frames per second the link carries: ``baud / 10 / frame_bytes`` (320 for the palm)."""
        return self.baud / 10.0 / self.frame_bytes

    @property
    def calibrated(self) -> bool:
        """True when the profile carries per-tactor calibration."""
        return self.offset is not None

    def felt(self, drive) -> np.ndarray:
        """Motor output for drive fractions in [0, 1] (the drive itself without a curve)."""
        drive = np.asarray(drive, dtype=np.float64)
        if self.response is None:
            return drive
        return np.interp(drive, *self.response)

    def drive_for(self, felt) -> np.ndarray:
        """The inverse of the motor response: the least drive whose output reaches ``felt``.

        Parameters
        ----------
        felt : array_like of float, any shape
            Wanted motor output in [0, 1] (0 stays 0: off).

        Returns
        -------
        ndarray of float64, same shape
            Drive fractions in [0, 1]; ``felt`` itself without a response curve. Where the
            curve is flat (a motor that starts only above some drive) the drive jumps to the
            end of the flat part; above the curve's largest output, full drive.
        """
        felt = np.asarray(felt, dtype=np.float64)
        if self.response is None:
            return felt
        drive, output = (np.asarray(v) for v in self.response)
        i = np.clip(np.searchsorted(output, felt, side="left"), 1, len(output) - 1)
        lo, hi = output[i - 1], output[i]
        span = np.where(hi > lo, hi - lo, 1.0)
        d = drive[i - 1] + (felt - lo) / span * (drive[i] - drive[i - 1])
        d = np.where(felt > output[-1], 1.0, np.clip(d, 0.0, 1.0))
        return np.where(felt > 0.0, d, 0.0)

    def drive_for1(self, felt: float) -> float:
        """Scalar :meth:`drive_for` with plain Python numbers (the streamer's live path)."""
        if self.response is None or felt <= 0.0:
            return felt if self.response is None else 0.0
        drive, output = self.response
        if felt > output[-1]:
            return 1.0
        i = min(max(bisect.bisect_left(output, felt), 1), len(output) - 1)
        lo, hi = output[i - 1], output[i]
        if hi <= lo:
            return min(max(drive[i], 0.0), 1.0)
        d = drive[i - 1] + (felt - lo) / (hi - lo) * (drive[i] - drive[i - 1])
        return min(max(d, 0.0), 1.0)

    def calibrate(self, flat_frame) -> np.ndarray:
        """Apply per-tactor calibration to a frame in flat cell order, ``(..., size)``."""
        values = np.asarray(flat_frame, dtype=np.float64)
        if self.offset is None:
            return values
        adjusted = np.clip(np.asarray(self.offset) + np.asarray(self.gain) * values, 0.0, 1.0)
        return np.where(values > 0.0, adjusted, 0.0)

    def to_dict(self) -> dict:
        """The JSON form of the profile."""
        grid = self.grid
        identity = self.array.channels == tuple(range(grid.size))
        data = {
            "format": FORMAT,
            "version": VERSION,
            "name": self.name,
            "description": self.description,
            "columns": grid.cols,
            "rows": grid.rows,
            "pitch_mm": self.array.pitch_mm,
            "levels": self.levels,
            "baud": self.baud,
            "channel_order": "row-major" if identity else list(self.array.channels),
        }
        if self.response is not None:
            data["response"] = {"drive": list(self.response[0]), "output": list(self.response[1])}
        if self.offset is not None:
            data["calibration"] = {"offset": list(self.offset), "gain": list(self.gain)}
            if self.threshold is not None:
                data["calibration"]["threshold"] = list(self.threshold)
        return data

    @property
    def sha256(self) -> str:
        """SHA-256 of the profile's bytes: of its file if it is as loaded, else of its JSON form
        (sorted keys, compact)."""
        if self.file_sha256 is not None:
            return self.file_sha256
        text = json.dumps(self.to_dict(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()

    def record(self) -> dict:
        """What an experiment session records of the profile: name, SHA-256 (of the file's
        bytes, or of the JSON form if it was built or changed in memory), path, the
        calibration applied."""
        calibration = None
        if self.offset is not None:
            calibration = {"offset": list(self.offset), "gain": list(self.gain)}
        return {
            "name": self.name,
            "sha256": self.sha256,
            "sha256_of": "file" if self.file_sha256 is not None else "json",
            "path": self.path,
            "levels": self.levels,
            "columns": self.grid.cols,
            "rows": self.grid.rows,
            "calibration": calibration,
        }

    def without_calibration(self) -> DeviceProfile:
        """A copy with no per-tactor calibration (no longer the file it came from)."""
        return dataclasses.replace(
            self, offset=None, gain=None, threshold=None, path=None, file_sha256=None
        )

    def save(self, path) -> Path:
        """Write the profile as JSON, atomically (temporary file, then rename)."""
        return write_json_atomic(path, self.to_dict())

    def with_calibration(self, offset, gain, threshold=None) -> DeviceProfile:
        """A copy with per-tactor calibration (validated like a loaded file)."""
        data = self.to_dict()
        data["calibration"] = {"offset": list(map(float, offset)), "gain": list(map(float, gain))}
        if threshold is not None:
            data["calibration"]["threshold"] = list(map(float, threshold))
        return profile_from_dict(data, source=self.path or self.name)


def _field(data, key, source, *, required=True, default=None):
    if key not in data:
        if required:
            raise ProfileError(f"{source}: field '{key}' is missing")
        return default
    return data[key]


def _integer(value, key, source, lo, hi=None):
    if isinstance(value, bool) or not isinstance(value, int):
        raise ProfileError(
            f"{source}: field '{key}' must be an integer, got {_validate.shown(value)}"
        )
    if value < lo or (hi is not None and value > hi):
        bound = f"{lo}..{hi}" if hi is not None else f">= {lo}"
        raise ProfileError(f"{source}: field '{key}' must be {bound}, got {_validate.shown(value)}")
    return value


def _number(value, key, source):
    try:
        return _validate.real(key, value)
    except ValueError:
        raise ProfileError(
            f"{source}: field '{key}' must be a finite number, got {_validate.shown(value)}"
        ) from None


def _numbers(value, key, source, size=None, grid=None):
    """A flat list of JSON numbers; with ``grid`` also a table of ``rows`` lists of ``cols``
    numbers, row 0 (the bottom row) first."""
    if grid is not None and isinstance(value, list) and value and isinstance(value[0], list):
        rows, cols = grid
        if len(value) != rows or not all(isinstance(r, list) and len(r) == cols for r in value):
            shape = [len(r) if isinstance(r, list) else "?" for r in value][:8]
            raise ProfileError(
                f"{source}: field '{key}' as a table must be {rows} rows of {cols} values "
                f"(row 0 at the bottom first), got {len(value)} rows of {shape}"
            )
        value = [x for row in value for x in row]
    if not isinstance(value, list):
        raise ProfileError(
            f"{source}: field '{key}' must be a list of numbers, got {_validate.shown(value)}"
        )
    if size is not None and len(value) != size:
        raise ProfileError(f"{source}: field '{key}' must hold {size} values, got {len(value)}")
    if len(value) > 4096:
        raise ProfileError(f"{source}: field '{key}' holds {len(value)} values, at most 4096")
    return np.array([_number(v, f"{key}[{i}]", source) for i, v in enumerate(value)])


def profile_from_dict(data, source: str = "profile") -> DeviceProfile:
    """Validate a profile's JSON object and build a :class:`DeviceProfile`.

    Raises
    ------
    ProfileError
        Naming ``source``, the field and the problem.
    """
    if not isinstance(data, dict):
        raise ProfileError(
            f"{source}: a device profile must be a JSON object, got {type(data).__name__}"
        )
    if data.get("format") != FORMAT:
        raise ProfileError(
            f"{source}: field 'format' must be {FORMAT!r}, "
            f"got {_validate.shown(data.get('format'))}"
        )
    version = _integer(_field(data, "version", source), "version", source, 1)
    if version > VERSION:
        raise ProfileError(
            f"{source}: field 'version' is {version}, newer than this software reads ({VERSION})"
        )
    name = _field(data, "name", source, required=False, default=Path(source).stem)
    if not isinstance(name, str) or not NAME.fullmatch(name):
        raise ProfileError(
            f"{source}: field 'name' must be 1-64 letters, digits, '_', '.' or '-', "
            f"got {_validate.shown(name)}"
        )
    description = _field(data, "description", source, required=False, default="")
    if not isinstance(description, str) or len(description) > 2000:
        raise ProfileError(f"{source}: field 'description' must be a string of <= 2000 chars")
    cols = _integer(_field(data, "columns", source), "columns", source, 1, 64)
    rows = _integer(_field(data, "rows", source), "rows", source, 1, 64)
    if cols * rows > 255:
        raise ProfileError(
            f"{source}: fields 'columns' x 'rows' must be at most 255 channels, got {cols * rows}"
        )
    pitch = _number(_field(data, "pitch_mm", source), "pitch_mm", source)
    if pitch <= 0:
        raise ProfileError(f"{source}: field 'pitch_mm' must be > 0, got {_validate.shown(pitch)}")
    levels = _integer(_field(data, "levels", source), "levels", source, 2, 256)
    baud = _integer(
        _field(data, "baud", source, required=False, default=115200),
        "baud",
        source,
        MIN_BAUD,
        MAX_BAUD,
    )
    order = _field(data, "channel_order", source, required=False, default="row-major")
    size = cols * rows
    if order == "row-major":
        channels = tuple(range(size))
    elif order == "column-major":
        channels = tuple(r * cols + c for c in range(cols) for r in range(rows))
    elif isinstance(order, list):
        channels = tuple(
            _integer(v, f"channel_order[{i}]", source, 0, size - 1) for i, v in enumerate(order)
        )
        if sorted(channels) != list(range(size)):
            raise ProfileError(
                f"{source}: field 'channel_order' must list each of the {size} cells once "
                f"(flat index row * columns + col)"
            )
    else:
        raise ProfileError(
            f"{source}: field 'channel_order' must be 'row-major', 'column-major' or a list, "
            f"got {_validate.shown(order)}"
        )
    array = ArraySpec(Grid(cols=cols, rows=rows), pitch_mm=pitch, levels=levels, channels=channels)

    response = None
    if data.get("response") is not None:
        curve = data["response"]
        if not isinstance(curve, dict):
            raise ProfileError(
                f"{source}: field 'response' must be an object with 'drive' and 'output'"
            )
        drive = _numbers(_field(curve, "drive", f"{source}: response"), "response.drive", source)
        output = _numbers(_field(curve, "output", f"{source}: response"), "response.output", source)
        if len(drive) < 2 or len(drive) != len(output):
            raise ProfileError(
                f"{source}: fields 'response.drive' and 'response.output' must have the same "
                f"length (>= 2), got {len(drive)} and {len(output)}"
            )
        if drive[0] != 0.0 or drive[-1] != 1.0 or np.any(np.diff(drive) <= 0):
            raise ProfileError(
                f"{source}: field 'response.drive' must increase strictly from 0 to 1"
            )
        if np.any(output < 0) or np.any(output > 1) or np.any(np.diff(output) < 0):
            raise ProfileError(
                f"{source}: field 'response.output' must be non-decreasing within [0, 1]"
            )
        response = (tuple(drive.tolist()), tuple(output.tolist()))

    offset = gain = threshold = None
    if data.get("calibration") is not None:
        cal = data["calibration"]
        if not isinstance(cal, dict):
            raise ProfileError(
                f"{source}: field 'calibration' must be an object with 'offset' and 'gain'"
            )
        table = (rows, cols)
        offset = _numbers(
            _field(cal, "offset", f"{source}: calibration"), "calibration.offset", source, size,
            table,
        )  # fmt: skip
        gain = _numbers(
            _field(cal, "gain", f"{source}: calibration"), "calibration.gain", source, size, table
        )
        if np.any(np.abs(offset) > 1):
            raise ProfileError(
                f"{source}: field 'calibration.offset' values must be within [-1, 1]"
            )
        if np.any(gain <= 0) or np.any(gain > 10):
            raise ProfileError(f"{source}: field 'calibration.gain' values must be within (0, 10]")
        offset, gain = tuple(offset.tolist()), tuple(gain.tolist())
        if cal.get("threshold") is not None:
            threshold = _numbers(cal["threshold"], "calibration.threshold", source, size, table)
            if np.any(threshold < 0) or np.any(threshold > 1):
                raise ProfileError(
                    f"{source}: field 'calibration.threshold' values must be within [0, 1]"
                )
            threshold = tuple(threshold.tolist())
    return DeviceProfile(
        name=name,
        array=array,
        baud=baud,
        response=response,
        offset=offset,
        gain=gain,
        threshold=threshold,
        description=description,
        path=None,
    )


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
    path = Path(path_or_name)
    if not path.suffix and not path.exists():
        try:
            path = asset_path("devices", f"{path_or_name}.json")
        except FileNotFoundError:
            raise ProfileError(f"{path_or_name}: no such profile file or bundled profile") from None
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
