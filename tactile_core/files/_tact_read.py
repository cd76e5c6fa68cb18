"""Reading bHaptics ``.tact`` files: the JSON checked field by field into plain records.

The structure follows bHaptics' own parsers (``ProjectModel.cpp`` of bhaptics/haptic-library,
``HapticFeedbackFile``/``BhapticsProject`` of their C# SDK)::

    {"project": {"layout": {"type": ..., "layouts": {POSITION: [{"index", "x", "y"}, ...]}},
                 "tracks": [{"enable": true, "effects": [
                     {"startTime": MS, "offsetTime": MS, "modes": {POSITION: {
                         "mode": "PATH_MODE" | "DOT_MODE",
                         "pathMode": {"feedback": [{"movingPattern", "playbackType",
                                                    "pointList": [{"x", "y", "intensity",
                                                                   "time"}]}]},
                         "dotMode": {"dotConnected", "feedback": [{"startTime", "endTime",
                                     "playbackType", "pointList": [{"index", "intensity"}]}]}
                     }}}]}]},
     "durationMillis": ..., "intervalMillis": ..., "size": ...,
     "feedback": {MS: [{"position", "mode", "values": [0..100, ...]}, ...]}}

``feedback`` is the compiled form, bHaptics' own frames (``_tact_compiled``); a file may carry
either form or both. An effect starts ``startTime`` ms into the file and lasts ``offsetTime``
ms; its points' and dots' times count from its start. Coordinates are in 0..1 of the device
position, y downward.
Every problem raises :class:`TactError` naming the field, e.g.
``tracks[0].effects[2].modes.VestFront.pathMode.feedback[3].pointList[1].x``.
"""

from __future__ import annotations

import dataclasses
import math

from .._shared import validate as _validate
from .._shared.jsonfile import parse_json, read_bytes
from ..rendering.shapes import FADES, MAX_POINTS, PATTERNS
from ._tact_compiled import DEVICE_MOTORS, compiled_dots, device_places, read_compiled
from ._tact_records import TactDot, TactError, TactFile, TactPath

MAX_TACT_BYTES = 4 << 20
"""Largest ``.tact`` file read (4 MiB; bHaptics' sample files are under 100 KB)."""
MAX_EFFECTS = 5_000
"""Most effects in a file (over all tracks)."""
MAX_TOTAL_POINTS = 200_000
"""Most path points and dots in a file, all together."""
MAX_NAME_CHARS = 200
"""Longest project name kept (a longer one is cut) or written (a default taken from the file's
name is cut to this)."""
MAX_LAYOUT = 1024
"""Most motors in one position's layout."""
MAX_TIME_MS = 3_600_000.0
"""Latest moment anything may end, in ms from the file's start (an hour)."""
MODES = ("PATH_MODE", "DOT_MODE")
FORMS = ("project", "compiled")
"""The two forms of a file: the Designer project and bHaptics' compiled frames."""

__all__ = ["TactDot", "TactError", "TactFile", "TactPath", "parse_tact", "read_tact"]


def read_tact(path, form: str | None = None) -> TactFile:
    """Read and check a ``.tact`` file.

    Parameters
    ----------
    path : path
        The file (JSON, UTF-8, a byte-order mark allowed), at most :data:`MAX_TACT_BYTES`.
    form : {"project", "compiled"}, optional
        Which form to play: the Designer project (``project``) or bHaptics' compiled frames
        (``feedback``). By default the project, or the frames of a file without one. Both are
        checked whenever present.

    Returns
    -------
    TactFile

    Raises
    ------
    TactError
        Naming the file and the field when anything is missing, of the wrong type, out of range
        (coordinates or intensities outside 0..1, motor values outside 0..100, negative
        durations, times out of order or after their effect's end) or too large, or the form
        asked for is not in the file.
    """
    data = read_bytes(path, TactError, max_bytes=MAX_TACT_BYTES)
    return parse_tact(parse_json(data, path, TactError), str(path), form)


def parse_tact(data, source: str = "tact", form: str | None = None) -> TactFile:
    """Check a parsed ``.tact`` document (see :func:`read_tact`)."""
    if form is not None and form not in FORMS:
        raise ValueError(f"form must be one of {', '.join(FORMS)}, got {_validate.shown(form)}")
    reader = _Reader(source)
    return reader.file(data, form)


class _Reader:
    """Walks the document once, counting what it reads against the bounds."""

    max_layout = MAX_LAYOUT
    max_time_ms = MAX_TIME_MS
    max_positions = 64
    modes = MODES

    def __init__(self, source: str):
        self.source = source
        self.points = 0
        self.effects = 0
        self.connected = []
        self.ends_ms = {}

    def fail(self, field: str, problem: str):
        raise TactError(f"{self.source}: {field} {problem}")

    def get(self, obj: dict, key: str, field: str):
        if key not in obj:
            self.fail(f"{field}.{key}" if field else key, "is missing")
        return obj[key]

    def object(self, value, field: str) -> dict:
        if not isinstance(value, dict):
            self.fail(field, f"must be an object, got {_kind(value)}")
        return value

    def array(self, value, field: str, longest: int) -> list:
        if not isinstance(value, list):
            self.fail(field, f"must be a list, got {_kind(value)}")
        if len(value) > longest:
            self.fail(field, f"holds {len(value)} entries, more than the {longest} allowed")
        return value

    def number(self, value, field: str, lo: float, hi: float) -> float:
        """A number within ``[lo, hi]``; numeric text (as bHaptics' Designer writes) too."""
        if isinstance(value, str):
            try:
                value = _validate.decimal_text(field, value.strip())
            except ValueError:
                self.fail(field, f"must be a number, got {_validate.shown(value)}")
        if not _validate.is_number(value):
            self.fail(field, f"must be a number, got {_kind(value)} {_validate.shown(value)}")
        try:
            value = float(value)
        except OverflowError:  # a JSON integer of hundreds of digits
            value = float("inf")
        if not lo <= value <= hi:
            self.fail(field, f"must be within [{lo:g}, {hi:g}], got {value:g}")
        return value

    def whole(self, value, field: str, lo: int, hi: int) -> int:
        number = self.number(value, field, lo, hi)
        if not number.is_integer():
            self.fail(field, f"must be a whole number, got {number:g}")
        return int(number)

    def choice(self, value, field: str, options) -> str:
        if not isinstance(value, str) or value not in options:
            self.fail(field, f"must be one of {', '.join(options)}, got {_validate.shown(value)}")
        return value

    def file(self, data, form: str | None = None) -> TactFile:
        data = self.object(data, "the file")
        has_project = any(key in data for key in ("project", "layout", "tracks"))
        compiled = read_compiled(self, data) if "feedback" in data else None
        if form is None:
            form = "project" if has_project or compiled is None else "compiled"
        if form == "compiled":
            if compiled is None:
                self.fail("feedback", "is missing: the file has no compiled frames")
            if has_project:  # checked, though the frames play
                self.project(data)
            self.points = 0
            dots, layouts, ends, positions = compiled_dots(self, compiled)
            return TactFile(name=self.name(data), layouts=layouts, paths=(), dots=dots,
                            duration_s=compiled.end_s, positions=positions, ends_s=ends,
                            compiled=compiled, form="compiled")  # fmt: skip
        return dataclasses.replace(self.project(data), compiled=compiled)

    def name(self, data) -> str:
        project = data.get("project", data)
        name = project.get("name", "") if isinstance(project, dict) else ""
        return name[:MAX_NAME_CHARS] if isinstance(name, str) else ""

    def project(self, data) -> TactFile:
        project = self.object(data["project"], "project") if "project" in data else data
        layout = self.object(self.get(project, "layout", ""), "layout")
        if "layouts" in layout or "type" not in layout:
            layouts = self.layouts(self.object(self.get(layout, "layouts", "layout"),
                                               "layout.layouts"))  # fmt: skip
        else:  # a layout named by its type alone: the device's own places
            layouts = {p: device_places(p, n) for p, n in DEVICE_MOTORS.items()}
        paths, dots, end_ms, positions = [], [], 0.0, []
        tracks = self.array(self.get(project, "tracks", ""), "tracks", MAX_EFFECTS)
        for i, track in enumerate(tracks):
            field = f"tracks[{i}]"
            track = self.object(track, field)
            enable = track.get("enable", True)
            if not isinstance(enable, bool):
                self.fail(f"{field}.enable", f"must be true or false, got {_kind(enable)}")
            effects = self.array(track.get("effects", []), f"{field}.effects", MAX_EFFECTS)
            for j, effect in enumerate(effects):
                end = self.effect(effect, f"{field}.effects[{j}]", layouts, paths, dots, enable,
                                  positions)  # fmt: skip
                if enable:
                    end_ms = max(end_ms, end)
        return TactFile(
            name=self.name(data),
            layouts=layouts,
            paths=tuple(paths),
            dots=tuple(dots),
            duration_s=end_ms / 1e3,
            positions=tuple(positions),
            connected=tuple(self.connected),
            ends_s={p: ms / 1e3 for p, ms in self.ends_ms.items()},
        )

    def position(self, name, field: str) -> str:
        """A device position's name (a key of ``layouts`` or ``modes``): 1-64 printable
        characters. Names are printed (``not played: VestBack``); a file's escape sequences in
        one would act on the operator's terminal."""
        if not (0 < len(name) <= 64 and name.isprintable()):
            self.fail(field, f"has a position named {_validate.shown(name)}: a position's name is "
                      "1-64 printable characters (VestFront, ForearmL, ...)")  # fmt: skip
        return name

    def layouts(self, layouts: dict) -> dict:
        out = {}
        for position, motors in layouts.items():
            position = self.position(position, "layout.layouts")
            field = f"layout.layouts.{position}"
            motors = self.array(motors, field, MAX_LAYOUT)
            table = {}
            for k, motor in enumerate(motors):
                where = f"{field}[{k}]"
                motor = self.object(motor, where)
                index = self.whole(self.get(motor, "index", where), f"{where}.index", 0, MAX_LAYOUT)
                if index in table:
                    self.fail(f"{where}.index", f"repeats motor {index}")
                x = self.number(self.get(motor, "x", where), f"{where}.x", 0.0, 1.0)
                y = self.number(self.get(motor, "y", where), f"{where}.y", 0.0, 1.0)
                table[index] = (x, y)
            out[position] = table
        return out

    def effect(self, effect, field, layouts, paths, dots, enabled, positions) -> float:
        """Check one effect, add its paths and dots (when ``enabled``) and the positions that
        hold them to ``positions`` (in the file's order); return its end (ms)."""
        self.effects += 1
        if self.effects > MAX_EFFECTS:
            self.fail(field, f"is one effect too many: at most {MAX_EFFECTS} in a file")
        effect = self.object(effect, field)
        start = self.number(self.get(effect, "startTime", field), f"{field}.startTime", 0.0,
                            MAX_TIME_MS)  # fmt: skip
        length = self.number(self.get(effect, "offsetTime", field), f"{field}.offsetTime", 0.0,
                             MAX_TIME_MS)  # fmt: skip
        if start + length > MAX_TIME_MS:
            self.fail(f"{field}.offsetTime", f"ends the effect after {MAX_TIME_MS / 3.6e6:g} h")
        modes = self.object(self.get(effect, "modes", field), f"{field}.modes")
        for position, mode in modes.items():
            position = self.position(position, f"{field}.modes")
            where = f"{field}.modes.{position}"
            mode = self.object(mode, where)
            kind = self.choice(self.get(mode, "mode", where), f"{where}.mode", MODES)
            if kind == "PATH_MODE":
                found = self.path_mode(mode, where, position, start, length)
                paths.extend(found if enabled else ())
            else:
                found = self.dot_mode(mode, where, position, start, length, layouts)
                dots.extend(found if enabled else ())
                if enabled and found and mode["dotMode"].get("dotConnected") is True:
                    self.connected.append((position, f"{where}.dotMode", len(found)))
            if enabled and found and position not in positions:
                positions.append(position)
            if enabled and found:
                self.ends_ms[position] = max(self.ends_ms.get(position, 0.0), start + length)
        return start + length

    def feedback(self, mode, key, field):
        """``(field path, entry)`` of each entry of ``mode[key].feedback``, checked objects."""
        field = f"{field}.{key}"
        body = self.object(self.get(mode, key, field.rpartition(".")[0]), field)
        feedback = self.array(self.get(body, "feedback", field), f"{field}.feedback", MAX_POINTS)
        for k, entry in enumerate(feedback):
            where = f"{field}.feedback[{k}]"
            yield where, self.object(entry, where)

    def path_mode(self, mode, field, position, start, length) -> list:
        out = []
        for where, entry in self.feedback(mode, "pathMode", field):
            pattern = self.choice(self.get(entry, "movingPattern", where),
                                  f"{where}.movingPattern", PATTERNS)  # fmt: skip
            fade = self.choice(entry.get("playbackType", "NONE"), f"{where}.playbackType", FADES)
            points = self.array(self.get(entry, "pointList", where), f"{where}.pointList",
                                MAX_POINTS)  # fmt: skip
            self.count(len(points), f"{where}.pointList")
            xy, times, levels = [], [], []
            for n, point in enumerate(points):
                at = f"{where}.pointList[{n}]"
                point = self.object(point, at)
                x = self.number(self.get(point, "x", at), f"{at}.x", 0.0, 1.0)
                y = self.number(self.get(point, "y", at), f"{at}.y", 0.0, 1.0)
                level = self.number(self.get(point, "intensity", at), f"{at}.intensity", 0.0, 1.0)
                time = self.number(self.get(point, "time", at), f"{at}.time", 0.0, MAX_TIME_MS)
                if time > length:
                    self.fail(f"{at}.time", f"is {time:g} ms, after its effect's end "
                              f"(offsetTime {length:g} ms)")  # fmt: skip
                if times and time == times[-1] and (x, y) == xy[-1]:
                    levels[-1] = level  # the same point again (bHaptics' files repeat some)
                    continue
                if times and time <= times[-1]:
                    self.fail(f"{at}.time", f"is {time:g} ms, not after the point before it "
                              f"({times[-1]:g} ms): times must increase")  # fmt: skip
                xy.append((x, y))
                times.append(time)
                levels.append(level)
            if not xy:
                continue
            if len(xy) == 1:  # a point held to the end of its effect
                if times[0] >= length:
                    continue
                xy, times, levels = xy * 2, [times[0], length], levels * 2
            out.append(TactPath(position, tuple(xy), tuple((start + s) / 1e3 for s in times),
                                tuple(levels), pattern, fade, where))  # fmt: skip
        return out

    def dot_mode(self, mode, field, position, start, length, layouts) -> list:
        """The dots of a ``dotMode``; with ``dotConnected: true`` each entry fades into the next
        (:func:`_connect`)."""
        entries = []
        for where, entry in self.feedback(mode, "dotMode", field):
            begin = self.number(self.get(entry, "startTime", where), f"{where}.startTime", 0.0,
                                MAX_TIME_MS)  # fmt: skip
            end = self.number(self.get(entry, "endTime", where), f"{where}.endTime", 0.0,
                              MAX_TIME_MS)  # fmt: skip
            if end < begin:
                self.fail(f"{where}.endTime", f"is {end:g} ms, before its startTime "
                          f"({begin:g} ms): a negative duration")  # fmt: skip
            begin, end = min(begin, length), min(end, length)  # the effect ends them
            fade = self.choice(entry.get("playbackType", "NONE"), f"{where}.playbackType", FADES)
            dots = self.array(self.get(entry, "pointList", where), f"{where}.pointList",
                              MAX_LAYOUT)  # fmt: skip
            self.count(len(dots), f"{where}.pointList")
            motors = []
            for n, dot in enumerate(dots):
                at = f"{where}.pointList[{n}]"
                dot = self.object(dot, at)
                index = self.whole(self.get(dot, "index", at), f"{at}.index", 0, MAX_LAYOUT)
                level = self.number(self.get(dot, "intensity", at), f"{at}.intensity", 0.0, 1.0)
                if index not in layouts.get(position, {}):
                    self.fail(f"{at}.index", f"is motor {index}, which layout.layouts."
                              f"{position} does not list")  # fmt: skip
                motors.append((index, level, at))
            entries.append((begin, end, fade, motors))
        body = mode["dotMode"]
        places = layouts.get(position, {})
        if body.get("dotConnected") is True:
            return _connect(entries, position, start, places)
        out = []
        for begin, end, fade, motors in entries:
            if end > begin:
                out.extend(TactDot(position, i, level, (start + begin) / 1e3, (start + end) / 1e3,
                                   fade, at, *places[i]) for i, level, at in motors)  # fmt: skip
        return out

    def count(self, n: int, field: str) -> None:
        self.points += n
        if self.points > MAX_TOTAL_POINTS:
            self.fail(field, f"brings the file past {MAX_TOTAL_POINTS} path points and dots")


def _kind(value) -> str:
    """The JSON name of a value's type, for messages."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, dict):
        return "an object"
    return type(value).__name__


def _connect(entries, position: str, start: float, places: dict) -> list:
    """Connected dots as bHaptics plays them (measured on its compiled frames, docs/tact.md):
    entry ``j``'s dots fade out (1 -> 0) from its ``startTime`` to the next entry's while the
    next entry's dots fade in (0 -> 1), both ends included, so at an entry's start the two add;
    the last entry then holds until its ``endTime``, from just after its start."""
    out = []
    for j, (begin, end, _, motors) in enumerate(entries):
        if j + 1 < len(entries):
            following = entries[j + 1]
            if following[0] > begin:
                a, b = (start + begin) / 1e3, (start + following[0]) / 1e3
                out.extend(TactDot(position, i, level, a, b, "FADE_OUT", at, *places[i])
                           for i, level, at in motors)  # fmt: skip
                out.extend(TactDot(position, i, level, a, b, "FADE_IN", at, *places[i])
                           for i, level, at in following[3])  # fmt: skip
        elif end > begin:
            a = (start + begin) / 1e3
            a = math.nextafter(a, math.inf) if j else a  # (the fade into it ends at its start)
            out.extend(TactDot(position, i, level, a, (start + end) / 1e3, "NONE", at,
                               *places[i]) for i, level, at in motors)  # fmt: skip
    return out
