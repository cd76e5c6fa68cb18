"""The device profile: a physical array and its link, as one immutable value."""

from __future__ import annotations

import bisect
import dataclasses
import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._shared.jsonfile import write_json_atomic
from ..rendering.geometry import ArraySpec
from ..rendering.layout import Layout
from ..rendering.motor import MotorResponse
from ._layout_json import layout_to_json
from ._profile_json import FORMAT, VERSION, profile_fields
from .wire import frame_length


@dataclass(frozen=True)
class DeviceProfile:
    """A physical array and its link.

    Attributes
    ----------
    name : str
    array : ArraySpec
        Layout (a grid, or actuators anywhere), pitch, levels and channel order.
    baud : int
        Serial link speed in bit/s (8N1: 10 bits per byte).
    response : tuple of (tuple of float, tuple of float) or None
        ``(drive, output)`` of the motor response curve, if known.
    motor : MotorResponse or None
        The motors' first-order dynamics (spin-up and run-down time constants), if known
        (:mod:`tactile_core.rendering.motor`); the palm array's are estimates.
    offset, gain : tuple of float, length rows * cols, or None
        Per-tactor calibration in flat cell order (``row * cols + col``).
    threshold : tuple of float or None
        The detection thresholds the calibration was computed from (informational).
    description : str
    path : str or None
        Where the profile was loaded from.
    file_sha256 : str or None
        SHA-256 of the bytes of that file (None for a profile built or changed in memory).
    carrier_hz : tuple of float or None
        An audio array's carrier frequencies: one for every channel, or one per channel in
        channel order (:mod:`tactile_core.device.audio`; 250 Hz when None).
    waveform : tuple of Waveform or None
        An audio array's waveforms (:mod:`tactile_core.device.waveform`): one for every channel,
        or one per channel in channel order; the plain carrier (a sine at ``carrier_hz``) when
        None. A serial array plays levels only.
    """

    name: str
    array: ArraySpec
    baud: int = 115200
    response: tuple | None = None
    motor: MotorResponse | None = None
    offset: tuple | None = None
    gain: tuple | None = None
    threshold: tuple | None = None
    description: str = ""
    path: str | None = field(default=None, compare=False)
    file_sha256: str | None = field(default=None, compare=False)
    carrier_hz: tuple | None = None
    waveform: tuple | None = None

    @property
    def layout(self) -> Layout:
        """Where the actuators are, and what frames are rendered onto: a
        :class:`~tactile_core.rendering.geometry.Grid` (the paper's methods and experiments
        apply: ``layout.is_grid``) or actuators anywhere."""
        return self.array.layout

    @property
    def levels(self) -> int:
        """Number of device levels."""
        return self.array.levels

    @property
    def channels(self) -> int:
        """Number of channels (one per tactor)."""
        return self.array.size

    @property
    def frame_bytes(self) -> int:
        """Bytes on the wire per frame (37 for 30 channels: 35 payload bytes, COBS and the
        delimiter)."""
        return frame_length(self.channels)

    @property
    def max_rate_hz(self) -> float:
        """Frames per second the link carries: ``baud / 10 / frame_bytes``
        (311 for the palm array)."""
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
        cols, rows = self.layout.wire_shape
        identity = self.array.channels == tuple(range(self.array.size))
        data = {
            "format": FORMAT,
            "version": VERSION,
            "name": self.name,
            "description": self.description,
            "columns": cols,
            "rows": rows,
            "pitch_mm": self.array.pitch_mm,
            "levels": self.levels,
            "baud": self.baud,
            "channel_order": "row-major" if identity else list(self.array.channels),
        }
        if not self.layout.is_grid:
            del data["columns"], data["rows"]
            data["layout"] = layout_to_json(self.layout, self.array.pitch_mm)
        if self.response is not None:
            data["response"] = {"drive": list(self.response[0]), "output": list(self.response[1])}
        if self.motor is not None:
            data["motor"] = {
                key: (round(v * 1e3, 9) if isinstance(v, float) else [round(x * 1e3, 9) for x in v])
                for key, v in (("tau_up_ms", self.motor.tau_up_s),
                               ("tau_down_ms", self.motor.tau_down_s))
            }  # fmt: skip
            if self.motor.note:
                data["motor"]["note"] = self.motor.note
        if self.offset is not None:
            data["calibration"] = {"offset": list(self.offset), "gain": list(self.gain)}
            if self.threshold is not None:
                data["calibration"]["threshold"] = list(self.threshold)
        if self.carrier_hz is not None:
            hz = self.carrier_hz
            data["carrier_hz"] = hz[0] if len(hz) == 1 else list(hz)
        if self.waveform is not None:
            specs = [w.spec for w in self.waveform]
            data["waveform"] = specs[0] if len(specs) == 1 else specs
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
            "columns": self.layout.wire_shape[0],
            "rows": self.layout.wire_shape[1],
            "layout": None if self.layout.is_grid else self.layout.describe(),
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


def profile_from_dict(data, source: str = "profile") -> DeviceProfile:
    """Validate a profile's JSON object and build a :class:`DeviceProfile`.

    Raises
    ------
    ProfileError
        Naming ``source``, the field and the problem.
    """
    return DeviceProfile(**profile_fields(data, source))
