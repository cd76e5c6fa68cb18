"""The ``layout`` field of a device profile: actuators anywhere, checked field by field.

::

    "pitch_mm": 100,                      # one layout unit: what radii and shapes are measured in
    "layout": {
      "units": "mm",                      # "mm", "pitch" or "normalized" (0..1 across size_mm)
      "size_mm": [300, 400],              # "normalized" only: the extent 0..1 stands for
      "actuators": [                      # in channel order; [x, y] pairs or objects
        {"x": 50, "y": 0, "name": "navel"},
        [150, 0],
        ...
      ],
      "wrap": {"axis": "x", "circumference": 800},   # optional, in the layout's units
      "groups": {"front": [0, 1, 2], "back": [3, 4, 5]}  # optional
    }

Positions become layout units (pitches): millimetres divided by ``pitch_mm``, normalised
coordinates scaled by ``size_mm`` first. Every refusal names the profile, the field and the
problem.
"""

from __future__ import annotations

from .._shared import validate as _validate
from ..rendering.layout import MAX_ACTUATORS, Layout, Wrap, name_problem

UNITS = ("mm", "pitch", "normalized")
MAX_CHANNELS = 255
"""Most actuators a device profile may have: one byte per channel count on the wire."""


def _number(value, key: str, source: str) -> float:
    if not _validate.is_number(value):
        raise ValueError(
            f"{source}: field '{key}' must be a finite number, got {_validate.shown(value)}"
        )
    try:
        return _validate.real(key, value)
    except ValueError:
        raise ValueError(
            f"{source}: field '{key}' must be a finite number, got {_validate.shown(value)}"
        ) from None


def layout_from_json(field, pitch_mm: float, source: str) -> Layout:
    """Build the :class:`Layout` of a profile's ``layout`` object.

    Parameters
    ----------
    field : dict
        The JSON object (see the module's docstring).
    pitch_mm : float
        The profile's pitch: one layout unit in millimetres.
    source : str
        Where the profile came from, for messages.

    Raises
    ------
    ValueError
        Naming ``source`` and the field (``layout.actuators[3].x``, ``layout.wrap``, ...).
    """
    if not isinstance(field, dict):
        raise ValueError(f"{source}: field 'layout' must be an object with 'actuators'")
    unknown = sorted(set(field) - {"units", "size_mm", "actuators", "wrap", "groups", "note"})
    if unknown:
        raise ValueError(
            f"{source}: field 'layout.{unknown[0]}' is not a layout field (layout fields: units, "
            f"size_mm, actuators, wrap, groups, note)"
        )
    units = field.get("units", "pitch")
    if units not in UNITS:
        raise ValueError(
            f"{source}: field 'layout.units' must be one of {', '.join(UNITS)}, got "
            f"{_validate.shown(units)}"
        )
    scale = (1.0 / pitch_mm, 1.0 / pitch_mm) if units == "mm" else (1.0, 1.0)
    if units == "normalized":
        size = field.get("size_mm")
        if not isinstance(size, list) or len(size) != 2:
            raise ValueError(
                f"{source}: field 'layout.size_mm' must be [width, height] in mm for normalized "
                f"units, got {_validate.shown(size)}"
            )
        w, h = (_number(v, f"layout.size_mm[{i}]", source) for i, v in enumerate(size))
        if w <= 0 or h <= 0:
            raise ValueError(f"{source}: field 'layout.size_mm' must be two sizes > 0")
        scale = (w / pitch_mm, h / pitch_mm)
    elif "size_mm" in field:
        raise ValueError(f"{source}: field 'layout.size_mm' is for normalized units only")
    actuators = field.get("actuators")
    if not isinstance(actuators, list) or not actuators:
        raise ValueError(
            f"{source}: field 'layout.actuators' must be a list of at least 1 actuator, got "
            f"{_validate.shown(actuators)}"
        )
    if len(actuators) > min(MAX_CHANNELS, MAX_ACTUATORS):
        raise ValueError(
            f"{source}: field 'layout.actuators' holds {len(actuators)} actuators, at most "
            f"{MAX_CHANNELS} (one channel each)"
        )
    positions, names, raw = [], [], []
    for i, item in enumerate(actuators):
        key = f"layout.actuators[{i}]"
        if isinstance(item, list) and len(item) == 2:
            x, y, name = item[0], item[1], None
        elif isinstance(item, dict):
            extra = sorted(set(item) - {"x", "y", "name"})
            if extra or "x" not in item or "y" not in item:
                raise ValueError(
                    f"{source}: field '{key}' must have 'x', 'y' and optionally 'name', got "
                    f"keys {sorted(item)}"
                )
            x, y, name = item["x"], item["y"], item.get("name")
        else:
            raise ValueError(
                f'{source}: field \'{key}\' must be [x, y] or {{"x": .., "y": ..}}, got '
                f"{_validate.shown(item)}"
            )
        x = _number(x, f"{key}.x", source)
        y = _number(y, f"{key}.y", source)
        if units == "normalized" and not (0.0 <= x <= 1.0 and 0.0 <= y <= 1.0):
            raise ValueError(f"{source}: field '{key}' must lie within 0..1 (normalized units)")
        if name is not None:
            problem = name_problem(name)
            if problem:
                raise ValueError(f"{source}: field '{key}.name' {problem}")
        raw.append((x, y))
        positions.append((x * scale[0], y * scale[1]))
        names.append(name if name is not None else f"a{i}")
    wrap = None
    if field.get("wrap") is not None:
        wrap = _wrap(field["wrap"], scale, source)
        _check_around(raw, field["wrap"], units, source)
    groups = _groups(field.get("groups") or {}, len(raw), source)
    try:
        return Layout(positions, names, wrap=wrap, groups=groups)
    except ValueError as exc:
        raise ValueError(f"{source}: field 'layout': {exc}") from None


def _check_around(raw: list, wrap: dict, units: str, source: str) -> None:
    """Every actuator within ``[0, circumference)`` along the wrap, in the profile's units."""
    index = 0 if wrap["axis"] == "x" else 1
    c = float(wrap["circumference"])
    unit = {"mm": " mm", "pitch": " pitches"}.get(units, "")
    for i, point in enumerate(raw):
        v = point[index]
        if not 0.0 <= v < c:
            raise ValueError(
                f"{source}: field 'layout.actuators[{i}].{wrap['axis']}' is {v:g}{unit}, outside "
                f"the wrap [0, {c:g}){unit} ('layout.wrap.circumference'): a wrapped axis runs "
                f"from 0 round to the circumference"
            )


def _groups(groups, n: int, source: str) -> dict:
    """``layout.groups`` checked field by field: names to lists of actuator indices."""
    if not isinstance(groups, dict):
        raise ValueError(
            f"{source}: field 'layout.groups' must map names to lists of actuator indices, got "
            f"{_validate.shown(groups)}"
        )
    for name, members in groups.items():
        key = f"layout.groups.{name}"
        if not isinstance(members, list):
            raise ValueError(
                f"{source}: field '{key}' must be a list of actuator indices, got "
                f"{_validate.shown(members)}"
            )
        for j, m in enumerate(members):
            if (isinstance(m, bool) or not isinstance(m, (int, float))
                    or (isinstance(m, float) and not m.is_integer())):  # fmt: skip
                raise ValueError(
                    f"{source}: field '{key}[{j}]' must be an actuator index (a whole number), "
                    f"got {_validate.shown(m)}"
                )
            if not 0 <= m < n:
                raise ValueError(
                    f"{source}: field '{key}[{j}]' names actuator {_validate.shown(m)}, which "
                    f"does not exist: the layout has {n} actuator{'s' if n != 1 else ''}, "
                    f"0..{n - 1}"
                )
    return groups


def _wrap(field, scale, source) -> Wrap:
    if not isinstance(field, dict) or set(field) - {"axis", "circumference"}:
        raise ValueError(
            f'{source}: field \'layout.wrap\' must be {{"axis": "x" or "y", '
            f'"circumference": length}}, got {_validate.shown(field)}'
        )
    axis = field.get("axis")
    if axis not in ("x", "y"):
        raise ValueError(
            f"{source}: field 'layout.wrap.axis' must be 'x' or 'y', got {_validate.shown(axis)}"
        )
    c = _number(field.get("circumference"), "layout.wrap.circumference", source)
    if c <= 0:
        raise ValueError(f"{source}: field 'layout.wrap.circumference' must be > 0, got {c:g}")
    try:
        return Wrap(axis, c * scale[0 if axis == "x" else 1])
    except ValueError as exc:  # beyond the coordinate bound once in pitches
        raise ValueError(f"{source}: field 'layout.wrap.circumference': {exc}") from None


def layout_to_json(layout: Layout, pitch_mm: float) -> dict:
    """The ``layout`` object of a profile (positions in pitches, ``units: "pitch"``)."""
    data = {
        "units": "pitch",
        "actuators": [
            {"x": x, "y": y, "name": name} if name != f"a{i}" else [x, y]
            for i, ((x, y), name) in enumerate(zip(layout.positions, layout.names))
        ],
    }
    if layout.wrap is not None:
        data["wrap"] = {"axis": layout.wrap.axis, "circumference": layout.wrap.circumference}
    if layout.groups:
        data["groups"] = {name: list(members) for name, members in layout.groups}
    return data
