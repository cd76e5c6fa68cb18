"""The JSON form of a device profile: its format's constants and the check of every field.

:func:`profile_fields` turns a profile's JSON object (described in :mod:`.profile`) into the
fields of a :class:`~tactile_core.device.profile.DeviceProfile`, or raises
:class:`ProfileError` naming the source, the field and the problem.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from .._shared import validate as _validate
from ..rendering.geometry import ArraySpec, Grid
from ..rendering.motor import MotorResponse
from ._layout_json import layout_from_json
from .waveform import CARRIER_RANGE_HZ, WaveformError, parse_waveform

FORMAT = "tactile-device-profile"
VERSION = 1
NAME = re.compile(r"[A-Za-z0-9_.-]{1,64}")
"""A profile's name: what presets and sessions refer to it by, and what the firmware reports."""
MIN_BAUD, MAX_BAUD = 9600, 4_000_000
"""Link speeds a profile may give: at 9600 baud the palm array still gets 25 frames a second."""
PITCH_RANGE_MM = (0.01, 10_000.0)
"""Pitches a profile may give: one layout unit, from a 10 um MEMS array to actuators 10 m apart.
Beyond them millimetre positions turn into numbers no array has (1e308 mm made every actuator a
'duplicate' at 0; 1e-308 an infinite circumference)."""


class ProfileError(ValueError):
    """A device profile that cannot be used; the message names the field and the problem."""


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


def profile_fields(data, source: str = "profile") -> dict:
    """Validate a profile's JSON object: the keyword arguments of a :class:`DeviceProfile`.

    Returns
    -------
    dict
        ``name``, ``array`` (:class:`ArraySpec`), ``baud``, ``response``, ``motor``, ``offset``,
        ``gain``, ``threshold``, ``description``, ``path`` (None), ``carrier_hz`` and
        ``waveform``, checked and as the class holds them.

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
            f"{source}: field 'version' is {_validate.shown(version)}, newer than this software "
            f"reads ({VERSION})"
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
    layout = None
    if data.get("layout") is None:
        cols = _integer(_field(data, "columns", source), "columns", source, 1, 64)
        rows = _integer(_field(data, "rows", source), "rows", source, 1, 64)
    pitch = _number(_field(data, "pitch_mm", source), "pitch_mm", source)
    if pitch <= 0:
        raise ProfileError(f"{source}: field 'pitch_mm' must be > 0, got {_validate.shown(pitch)}")
    if not PITCH_RANGE_MM[0] <= pitch <= PITCH_RANGE_MM[1]:
        raise ProfileError(
            f"{source}: field 'pitch_mm' must be within [{PITCH_RANGE_MM[0]:g}, "
            f"{PITCH_RANGE_MM[1]:g}] mm, got {_validate.shown(pitch)}"
        )
    if data.get("layout") is not None:
        for key in ("columns", "rows"):
            if key in data:
                raise ProfileError(
                    f"{source}: field '{key}' and field 'layout' exclude each other (a layout "
                    f"lists its actuators; a grid gives columns and rows)"
                )
        try:
            layout = layout_from_json(data["layout"], pitch, source)
        except ValueError as exc:
            raise ProfileError(str(exc)) from None
        cols, rows = layout.size, 1
    if cols * rows > 255:
        what = "'layout.actuators'" if layout is not None else "'columns' x 'rows'"
        raise ProfileError(
            f"{source}: field {what} must be at most 255 channels, got {cols * rows}"
        )
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
    if layout is not None and order == "column-major":
        raise ProfileError(
            f"{source}: field 'channel_order' 'column-major' needs a grid; a layout's channels "
            f"follow its actuators (or give a list)"
        )
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
    layout = Grid(cols=cols, rows=rows) if layout is None else layout
    array = ArraySpec(layout, pitch_mm=pitch, levels=levels, channels=channels)

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

    motor = _motor(data.get("motor"), source, size, (rows, cols))

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
    return dict(
        name=name,
        array=array,
        baud=baud,
        response=response,
        motor=motor,
        offset=offset,
        gain=gain,
        threshold=threshold,
        description=description,
        path=None,
        carrier_hz=_carrier_hz(data.get("carrier_hz"), source, size),
        waveform=_waveform(data.get("waveform"), source, size),
    )


def _motor(field, source, size, table):
    """The ``motor`` field: ``{"tau_up_ms", "tau_down_ms", "note"}``, each time constant one
    number for every tactor or one per tactor (a flat list or a table of rows)."""
    if field is None:
        return None
    if not isinstance(field, dict):
        raise ProfileError(
            f"{source}: field 'motor' must be an object with 'tau_up_ms' and 'tau_down_ms'"
        )
    taus = []
    for key in ("tau_up_ms", "tau_down_ms"):
        value = _field(field, key, f"{source}: motor")
        if isinstance(value, list):
            ms = _numbers(value, f"motor.{key}", source, size, table)
        else:
            ms = np.array([_number(value, f"motor.{key}", source)])
        if np.any(ms < 0) or np.any(ms > 10_000):
            raise ProfileError(f"{source}: field 'motor.{key}' values must be within [0, 10000]")
        taus.append(float(ms[0]) / 1e3 if ms.size == 1 else tuple((ms / 1e3).tolist()))
    note = field.get("note", "")
    if not isinstance(note, str) or len(note) > 2000:
        raise ProfileError(f"{source}: field 'motor.note' must be a string of <= 2000 chars")
    return MotorResponse(taus[0], taus[1], note)


def _carrier_hz(field, source, channels):
    """The ``carrier_hz`` field (audio arrays): one frequency for every channel, or a list of
    one per channel in channel order, each within :data:`CARRIER_RANGE_HZ`; None if absent."""
    if field is None:
        return None
    if isinstance(field, list):
        hz = _numbers(field, "carrier_hz", source, channels)
    else:
        hz = np.array([_number(field, "carrier_hz", source)])
    lo, hi = CARRIER_RANGE_HZ
    bad = np.flatnonzero((hz < lo) | (hz > hi))
    if bad.size:
        key = f"carrier_hz[{bad[0]}]" if isinstance(field, list) else "carrier_hz"
        raise ProfileError(
            f"{source}: field '{key}' must be within [{lo:g}, {hi:g}] Hz, got {hz[bad[0]]:g}"
        )
    return tuple(hz.tolist())


def _waveform(field, source, channels):
    """The ``waveform`` field (audio arrays): one spec for every channel, or a list of one per
    channel in channel order (:mod:`.waveform`); a tuple of :class:`Waveform`, None if
    absent."""
    if field is None:
        return None
    if isinstance(field, list):
        if len(field) != channels:
            raise ProfileError(f"{source}: field 'waveform' must hold {channels} specs (one per "
                               f"channel) or be one spec, got {len(field)}")  # fmt: skip
        specs = [(f"field 'waveform[{i}]'", spec) for i, spec in enumerate(field)]
    else:
        specs = [("field 'waveform'", field)]
    try:
        return tuple(parse_waveform(spec, what) for what, spec in specs)
    except WaveformError as exc:
        raise ProfileError(f"{source}: {exc}") from None
