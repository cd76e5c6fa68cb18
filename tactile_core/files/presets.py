"""Presets: a tuned scene saved as versioned JSON, with the built-in ones of the paper.

A preset file::

    {
      "format": "tactile-preset", "version": 1,
      "name": "Experiment 1 line", "notes": "...",
      "device_profile": "palm-5x6",          # a profile's name (bundled or the user's), no path
      "method": "AS", "mu": 0.33, "gamma": 0.7,
      "shape": {"type": "line", "p0": [0.5, 1.84], "p1": [4.5, 4.16]},
      "trace": {"duration_s": 2.0, "pause_s": 0.5, "direction": "forward", "repeat": true},
      "rate_hz": 300.0, "filter": "box", "subsamples": 4, "dither": true,
      "compensate_motors": false,            # optional: motor-aware drive (off by default)
      "lead_ms": 20.0                        # optional: frames sent ahead to scheduled arrays
    }

Loading validates everything before returning: a malformed or out-of-range file raises
:class:`PresetError` naming the file and the field, and nothing else changes. Writes are atomic
(a temporary file in the same folder, then a rename), so a crash never leaves half a preset.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .._shared import validate as _validate
from .._shared.assets import assets_dir
from .._shared.jsonfile import read_json, write_json_atomic
from ..device.profile import NAME as PROFILE_NAME
from ..rendering.scene import Scene
from ..rendering.shapes import shape_from_dict
from ..stream import DEFAULT_LEAD_MS, check_lead_ms

FORMAT = "tactile-preset"
VERSION = 1

MAX_PRESET_BYTES = 4 << 20
"""Largest preset file read (4 MiB): a preset holding a drawn or imported path of 10,000 points
(:class:`~tactile_core.rendering.shapes.TimedPath`) is about 1.2 MB; the others a few KB."""

_SCENE_KEYS = ("method", "mu", "gamma", "rate_hz", "filter", "subsamples", "dither", "gain",
               "felt_domain", "compensate_motors")  # fmt: skip
_TRACE_KEYS = ("duration_s", "pause_s", "direction", "repeat", "emphasis")


MAX_NAME_CHARS = 200
"""Longest preset name read (the tuner names a preset after its file, cut to this)."""
MAX_NOTES_CHARS = 10_000
"""Longest notes read."""


class PresetError(ValueError):
    """A preset that cannot be used; the message names the file, the field and the problem."""


@dataclass(frozen=True)
class Preset:
    """A named scene with its device profile, its lead and notes.

    ``lead_ms`` is how far ahead frames go to an array that plays them at their time (0: frames
    for now; see docs/device.md, Scheduled frames); it is how the scene is delivered, not what
    it renders, so it sits beside the scene rather than in it."""

    scene: Scene
    name: str = "untitled"
    notes: str = ""
    device_profile: str = "palm-5x6"
    lead_ms: float = DEFAULT_LEAD_MS

    def to_dict(self) -> dict:
        """The JSON form."""
        s = self.scene
        return {
            "format": FORMAT,
            "version": VERSION,
            "name": self.name,
            "notes": self.notes,
            "device_profile": self.device_profile,
            "method": s.method,
            "mu": s.mu,
            "gamma": s.gamma,
            "shape": None if s.shape is None else s.shape.to_dict(),
            "trace": {
                "duration_s": s.duration_s,
                "pause_s": s.pause_s,
                "direction": s.direction,
                "repeat": s.repeat,
                "emphasis": s.emphasis,
            },
            "rate_hz": s.rate_hz,
            "filter": s.filter,
            "subsamples": s.subsamples,
            "dither": s.dither,
            "gain": s.gain,
            "felt_domain": s.felt_domain,
            "compensate_motors": s.compensate_motors,
            "lead_ms": self.lead_ms,
        }


def preset_from_dict(data, source: str = "preset") -> Preset:
    """Validate a preset's JSON object; :class:`PresetError` names the bad field."""
    if not isinstance(data, dict):
        raise PresetError(f"{source}: a preset must be a JSON object, got {type(data).__name__}")
    if data.get("format") != FORMAT:
        raise PresetError(
            f"{source}: field 'format' must be {FORMAT!r}, "
            f"got {_validate.shown(data.get('format'))}"
        )
    try:  # a whole number written as 1.0 (some JSON writers do) reads as 1, as everywhere
        version = _validate.integer("field 'version'", data.get("version"), 1)
    except ValueError as exc:
        raise PresetError(f"{source}: {exc}") from None
    if version > VERSION:
        raise PresetError(
            f"{source}: field 'version' is {version}, newer than this software reads ({VERSION})"
        )
    for key, longest in (("name", MAX_NAME_CHARS), ("notes", MAX_NOTES_CHARS),
                         ("device_profile", 64)):  # fmt: skip
        if key in data and (not isinstance(data[key], str) or len(data[key]) > longest):
            raise PresetError(
                f"{source}: field '{key}' must be a string of at most {longest} characters, "
                f"got {_validate.shown(data[key])}"
            )
    if "device_profile" in data and not PROFILE_NAME.fullmatch(data["device_profile"]):
        raise PresetError(
            f"{source}: field 'device_profile' must name a profile (letters, digits, '_', '.', "
            f"'-'), not a path: got {_validate.shown(data['device_profile'])}"
        )
    if "shape" not in data:
        raise PresetError(f"{source}: field 'shape' is missing")
    try:
        shape = shape_from_dict(data["shape"])
    except ValueError as exc:
        raise PresetError(f"{source}: field {exc}") from None
    kwargs = {}
    for key in _SCENE_KEYS:
        if key in data:
            kwargs[key] = data[key]
    trace = data.get("trace", {})
    if not isinstance(trace, dict):
        raise PresetError(
            f"{source}: field 'trace' must be an object, got {_validate.shown(trace)}"
        )
    for key in _TRACE_KEYS:
        if key in trace:
            kwargs[key] = trace[key]
    for key, value in kwargs.items():
        if key in ("dither", "repeat", "felt_domain", "compensate_motors"):
            if not isinstance(value, bool):
                raise PresetError(
                    f"{source}: field '{key}' must be true or false, got {_validate.shown(value)}"
                )
        elif key in ("method", "filter", "direction"):
            if not isinstance(value, str):
                raise PresetError(
                    f"{source}: field '{key}' must be a string, got {_validate.shown(value)}"
                )
        elif not _validate.is_number(value):
            raise PresetError(
                f"{source}: field '{key}' must be a number, got {_validate.shown(value)}"
            )
    try:
        scene = Scene(shape, **kwargs)
    except ValueError as exc:
        field = str(exc).split(" ")[0]
        where = f"trace.{field}" if field in _TRACE_KEYS else field
        raise PresetError(f"{source}: field '{where}': {exc}") from None
    try:
        lead_ms = check_lead_ms(data.get("lead_ms", DEFAULT_LEAD_MS), "field 'lead_ms'")
    except ValueError as exc:
        raise PresetError(f"{source}: {exc}") from None
    return Preset(
        scene=scene,
        name=data.get("name", Path(source).stem),
        notes=data.get("notes", ""),
        device_profile=data.get("device_profile", "palm-5x6"),
        lead_ms=float(lead_ms),
    )


def load_preset(path) -> Preset:
    """Read and validate a preset file.

    Raises
    ------
    PresetError
        When the file is missing, unreadable, not JSON, or invalid; nothing is changed.
    """
    data = read_json(path, PresetError, max_bytes=MAX_PRESET_BYTES)
    return preset_from_dict(data, source=str(path))


def save_preset(preset: Preset, path) -> Path:
    """Write a preset atomically (temporary file, then rename).

    Raises
    ------
    PresetError
        Before anything is written, when the preset would not load back (a scene without a
        shape, a name or notes too long): a preset this writes is one :func:`load_preset`
        reads.
    """
    data = preset.to_dict()
    preset_from_dict(data, source=f"the preset for {path}")
    return write_json_atomic(path, data)


def builtin_presets() -> dict[str, Path]:
    """Bundled presets for the paper's conditions, by file stem, in file-name order."""
    folder = assets_dir() / "presets"
    return {p.stem: p for p in sorted(folder.glob("*.json"))}
