"""The pattern file: versioned JSON, read field by field as strictly as a preset.

Every refusal is a :class:`PatternError` naming the file and the field path,
``effects[3].envelope[1].time_s must be ...``: a field missing, of the wrong type (a number is
never a string or a boolean, a whole number never 1.5), out of range, unknown (a misspelt
``duraton_s`` is refused rather than ignored), or a file too large, nested too deep or holding
too much (``docs/patterns.md`` lists the bounds). Reading is bounded in bytes before parsing and
in depth and counts while walking, so a hostile file costs at most a parse of
:data:`MAX_PATTERN_BYTES`.
"""

from __future__ import annotations

import json
import re

from .._shared import validate as _validate
from .._shared.jsonfile import MAX_JSON_DEPTH, parse_json, read_bytes, write_json_atomic
from ..rendering.shapes import TimedPath, shape_from_dict
from ._pattern_effects import (
    COMBINE,
    MAX_EFFECTS,
    MAX_TOTAL_POINTS,
    Dot,
    Dots,
    Effect,
    TactEffect,
)

FORMAT = "tactile-pattern"
VERSION = 2
"""The newest version read; a file is written as version 1 unless it needs 2."""
WAVEFORM_VERSION = 2
"""The first version whose effects may name a ``waveform`` (version 1 files read as before)."""
MAX_PATTERN_BYTES = 4 << 20
"""Largest pattern file read (4 MiB: 10,000 effects of a few hundred bytes each)."""
MAX_PATTERN_DEPTH = 8
"""Deepest nesting a pattern file has: the file, ``effects``, an effect, ``tact``, ``paths``, a
path, ``points``, a point."""

_TOP = ("format", "version", "name", "notes", "combine", "effects")
_EFFECT = ("track", "name", "start_s", "duration_s", "repeat", "method", "group", "envelope",
           "waveform", "shape", "dots", "tact")  # fmt: skip
_CONTENT = ("shape", "dots", "tact")
_DOT = ("at", "intensity", "start_s", "duration_s", "fade")
_KEYFRAME = ("time_s", "gain")
_TACT = ("paths", "dots", "length_s", "position")
_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}:,]')


class PatternError(ValueError):
    """A pattern file that cannot be used; the message names the file and the field."""


def read_pattern_json(path):
    """The parsed JSON of a pattern file, bounded in bytes and depth; :class:`PatternError`
    names the file and, for a file nested too deep, the field where it goes too deep."""
    data = read_bytes(path, PatternError, max_bytes=MAX_PATTERN_BYTES)
    try:
        return parse_json(data, path, PatternError)
    except PatternError as exc:
        if "nested too deeply" not in str(exc):
            raise
        field = deep_field(data.decode("utf-8", "replace"), MAX_PATTERN_DEPTH)
        raise PatternError(f"{path}: {field} is nested too deeply: a pattern file nests at "
                           f"most {MAX_PATTERN_DEPTH} levels of arrays and objects (this one more "
                           f"than {MAX_JSON_DEPTH})") from None  # fmt: skip


def deep_field(text: str, limit: int) -> str:
    """The field path of the first value of ``text`` (JSON) nested deeper than ``limit``
    arrays and objects, found with a tokenizer that stops there (no recursion, no parse).

    >>> deep_field('{"effects": [{"shape": [[[1]]]}]}', 4)
    'effects[0].shape[0]'
    """
    stack: list = []  # per open container: [kind, key or index, expecting a key]
    for match in _TOKEN.finditer(text):
        token = match.group()
        top = stack[-1] if stack else None
        if token[0] == '"':
            if top is not None and top[0] == "{" and top[2]:
                try:
                    top[1] = json.loads(token)
                except ValueError:
                    top[1] = token[1:-1]
        elif token in "[{":
            stack.append([token, 0 if token == "[" else "", token == "{"])
            if len(stack) > limit:
                return _path(stack[:-1]) or "the file"
        elif token in "]}":
            if stack:
                stack.pop()
        elif token == ":" and top is not None:
            top[2] = False
        elif token == "," and top is not None:
            if top[0] == "[":
                top[1] += 1
            else:
                top[2] = True
    return "the file"


def _path(stack) -> str:
    """``effects[0].shape``: the keys and indices of the containers on ``stack``."""
    return "".join(f"[{where}]" if kind == "[" else f".{where}" for kind, where, _ in stack)[
        1 if stack and stack[0][0] == "{" else 0 :
    ]


class _Reader:
    """Checks of JSON values that name the field (``fail`` raises :class:`PatternError`)."""

    def __init__(self, source: str):
        self.source = source

    def fail(self, message: str):
        raise PatternError(f"{self.source}: {message}")

    def object(self, value, field: str, keys) -> dict:
        if not isinstance(value, dict):
            self.fail(f"{field} must be an object, got {_validate.shown(value)}")
        for key in value:
            if key not in keys:
                where = f"{field}.{key}" if field != "the file" else key
                self.fail(f"{where} is not a field here (the fields: {', '.join(keys)})")
        return value

    def array(self, value, field: str, most: int) -> list:
        if not isinstance(value, list):
            self.fail(f"{field} must be a list, got {_validate.shown(value)}")
        if len(value) > most:
            self.fail(f"{field} holds {len(value)} entries, more than the {most} allowed")
        return value

    def number(self, value, field: str):
        if not _validate.is_number(value):
            self.fail(f"{field} must be a number, got {_validate.shown(value)}")
        return value

    def whole(self, value, field: str):
        if not _validate.is_number(value) or not float(value).is_integer():
            self.fail(f"{field} must be a whole number, got {_validate.shown(value)}")
        return int(value)

    def text(self, value, field: str, *, null: bool = False):
        if value is None and null:
            return None
        if not isinstance(value, str):
            kind = "a string or null" if null else "a string"
            self.fail(f"{field} must be {kind}, got {_validate.shown(value)}")
        return value

    def build(self, field: str, make, *args, **kwargs):
        """``make(*args, **kwargs)``; its ValueError named as ``field``'s."""
        try:
            return make(*args, **kwargs)
        except PatternError:
            raise
        except ValueError as exc:
            self.fail(f"{field}.{exc}" if field else str(exc))


def pattern_fields(data, source: str = "pattern") -> dict:
    """The :class:`~tactile_core.files.pattern.Pattern` arguments of a parsed pattern file,
    checked field by field; :class:`PatternError` names the field."""
    r = _Reader(source)
    data = r.object(data, "the file", _TOP)
    if data.get("format") != FORMAT:
        r.fail(f"format must be {FORMAT!r}, got {_validate.shown(data.get('format'))}")
    if "version" not in data:
        r.fail("version is missing")
    version = r.whole(data["version"], "version")
    if version < 1:
        r.fail(f"version must be >= 1, got {version}")
    if version > VERSION:
        r.fail(f"version is {version}, newer than this software reads ({VERSION})")
    fields = {}
    for key in ("name", "notes", "combine"):
        if key in data:
            fields[key] = r.text(data[key], key)
    if fields.get("combine", "max") not in COMBINE:
        r.fail(f"combine must be one of {', '.join(COMBINE)}, got {fields['combine']!r}")
    if "effects" not in data:
        r.fail("effects is missing")
    effects = r.array(data["effects"], "effects", MAX_EFFECTS)
    out, points = [], 0
    for i, item in enumerate(effects):
        if isinstance(item, dict) and "waveform" in item and version < WAVEFORM_VERSION:
            r.fail(f"effects[{i}].waveform needs version {WAVEFORM_VERSION} (the file says "
                   f"{version})")  # fmt: skip
        effect = _effect(r, item, f"effects[{i}]")
        points += effect.points()
        if points > MAX_TOTAL_POINTS:
            r.fail(f"effects[{i}] brings the pattern past {MAX_TOTAL_POINTS} path points and dots")
        out.append(effect)
    fields["effects"] = tuple(out)
    return fields


def _effect(r: _Reader, item, field: str) -> Effect:
    item = r.object(item, field, _EFFECT)
    held = [key for key in _CONTENT if key in item]
    if len(held) != 1:
        r.fail(f"{field} must hold exactly one of shape, dots, tact (what it plays), got "
               f"{', '.join(held) or 'none'}")  # fmt: skip
    kind = held[0]
    if kind == "shape":
        content = r.build(field, shape_from_dict, item["shape"])
    elif kind == "dots":
        dots = r.array(item["dots"], f"{field}.dots", 10_000)
        content = r.build(field, Dots, tuple(_dot(r, d, f"{field}.dots[{j}]")
                                             for j, d in enumerate(dots)))  # fmt: skip
    else:
        content = _tact(r, item["tact"], f"{field}.tact")
    kwargs = {}
    for key in ("start_s", "duration_s"):
        if item.get(key) is not None:
            kwargs[key] = r.number(item[key], f"{field}.{key}")
    for key in ("repeat", "track"):
        if key in item:
            kwargs[key] = r.whole(item[key], f"{field}.{key}")
    for key in ("method", "group", "waveform"):
        if key in item:
            kwargs[key] = r.text(item[key], f"{field}.{key}", null=True)
    if "name" in item:
        kwargs["name"] = r.text(item["name"], f"{field}.name")
    if "envelope" in item:
        keys = r.array(item["envelope"], f"{field}.envelope", 1000)
        envelope = []
        for k, keyframe in enumerate(keys):
            where = f"{field}.envelope[{k}]"
            keyframe = r.object(keyframe, where, _KEYFRAME)
            for name in _KEYFRAME:
                if name not in keyframe:
                    r.fail(f"{where}.{name} is missing")
                r.number(keyframe[name], f"{where}.{name}")
            envelope.append((keyframe["time_s"], keyframe["gain"]))
        kwargs["envelope"] = tuple(envelope)
    return r.build(field, Effect, content, **kwargs)


def _dot(r: _Reader, item, field: str) -> Dot:
    item = r.object(item, field, _DOT)
    if "at" not in item:
        r.fail(f"{field}.at is missing")
    at = item["at"]
    if isinstance(at, list):
        if len(at) != 2:
            r.fail(f"{field}.at must be an actuator's index or a place [x, y], got "
                   f"{_validate.shown(at)}")  # fmt: skip
        at = tuple(r.number(v, f"{field}.at[{n}]") for n, v in enumerate(at))
    else:
        at = r.whole(at, f"{field}.at")
    kwargs = {key: r.number(item[key], f"{field}.{key}")
              for key in ("intensity", "start_s", "duration_s") if key in item}  # fmt: skip
    if "fade" in item:
        kwargs["fade"] = r.text(item["fade"], f"{field}.fade")
    return r.build(field, Dot, at, **kwargs)


def _tact(r: _Reader, item, field: str) -> TactEffect:
    item = r.object(item, field, _TACT)
    paths = []
    for j, path in enumerate(r.array(item.get("paths", []), f"{field}.paths", 10_000)):
        where = f"{field}.paths[{j}]"
        shape = r.build("", _timed_path, path, where)
        paths.append(shape)
    dots = r.array(item.get("dots", []), f"{field}.dots", 10_000)
    dots = [_dot(r, d, f"{field}.dots[{j}]") for j, d in enumerate(dots)]
    kwargs = {}
    if "length_s" in item:
        kwargs["length_s"] = r.number(item["length_s"], f"{field}.length_s")
    if "position" in item:
        kwargs["position"] = r.text(item["position"], f"{field}.position")
    return r.build(field, TactEffect, tuple(paths), tuple(dots), **kwargs)


def _timed_path(data, field: str) -> TimedPath:
    if not isinstance(data, dict) or data.get("type") != "timed_path":
        raise ValueError(f"{field} must be a timed_path object (a shape), got "
                         f"{_validate.shown(data)}")  # fmt: skip
    try:
        return shape_from_dict(data)
    except ValueError as exc:
        raise ValueError(f"{field}.{str(exc).removeprefix('shape.')}") from None


def pattern_to_json(pattern) -> dict:
    """The JSON form of a pattern (what :func:`pattern_fields` reads back equal)."""
    waveforms = any(e.waveform is not None for e in pattern.effects)
    return {
        "format": FORMAT,
        "version": WAVEFORM_VERSION if waveforms else 1,
        "name": pattern.name,
        "notes": pattern.notes,
        "combine": pattern.combine,
        "effects": [_effect_json(e) for e in pattern.effects],
    }


def _effect_json(effect) -> dict:
    out = {"track": effect.track, "start_s": effect.start_s, "duration_s": effect.duration_s}
    if effect.repeat != 1:
        out["repeat"] = effect.repeat
    for key in ("method", "group"):
        if getattr(effect, key) is not None:
            out[key] = getattr(effect, key)
    if effect.name:
        out["name"] = effect.name
    if effect.waveform is not None:
        out["waveform"] = effect.waveform.spec
    if effect.envelope:
        out["envelope"] = [{"time_s": t, "gain": g} for t, g in effect.envelope]
    content = effect.content
    if isinstance(content, Dots):
        out["dots"] = [d.to_dict() for d in content.dots]
    elif isinstance(content, TactEffect):
        tact = {
            "paths": [p.to_dict() for p in content.paths],
            "dots": [d.to_dict() for d in content.dots],
            "length_s": content.length_s,
        }
        if content.position:
            tact["position"] = content.position
        out["tact"] = tact
    else:
        out["shape"] = content.to_dict()
    return out


def write_pattern_json(path, data: dict):
    """Write a pattern's JSON form atomically, after checking it reads back (a file this
    writes is one the reader takes); returns the path written."""
    pattern_fields(json.loads(json.dumps(data)), f"the pattern for {path}")
    return write_json_atomic(path, data)
