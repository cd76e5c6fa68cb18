"""A pattern and bHaptics ``.tact`` files: a file's effects imported as pattern effects, and a
pattern exported as the Designer's project form (paths and dots per effect).

**Import** (:func:`tact_effects`): each effect of the file's enabled tracks that holds
paths or dots for the position becomes one :class:`~._pattern_effects.TactEffect` effect at its
``startTime``, lasting its ``offsetTime``, on the track of the file's track (its index).

**Export** (:func:`pattern_tact_document`): each play of each effect (a repeated effect once per
repetition) becomes up to two bHaptics effects on its track: a ``PATH_MODE`` one with a path per
stroke (a shape traced as :func:`~._tact_write.path_of_scene` traces a scene; a ``.tact``
path as it is), and a ``DOT_MODE`` one with its dots on their actuators' motors. An envelope
goes into the paths' point intensities (sampled every 20 ms with the path's own) and splits a
dot into 20 ms pieces at its value there. bHaptics has no methods and no groups: paths keep
their place on the array, and a group mapped to a device position (``positions``) is written
to that position in 0..1 of the group's own actuators.
"""

from __future__ import annotations

import itertools
import math
import uuid

import numpy as np

from .._shared import validate as _validate
from .._shared.jsonfile import parse_json, read_bytes, write_json_atomic
from .._shared.outfile import check_output
from ..rendering.methods import get_method
from ..rendering.placement import default_method
from ..rendering.rasterize import check_target
from ..rendering.scene import Scene
from ..rendering.shapes import FADES, MAX_POINTS, TimedPath
from ..rendering.trace import Sampling
from ._pattern_effects import MAX_TEXT_CHARS, MAX_TRACKS, Dot, Effect, TactEffect
from ._pattern_frames import PatternFrames
from ._pattern_parts import compile_parts, layout_group
from ._tact_compiled import INTERVAL_MS, frame_count
from ._tact_write import DECIMALS, SAMPLE_MS, _now_ms, _r
from .tact import (
    MAX_EFFECTS,
    MAX_NAME_CHARS,
    MAX_TACT_BYTES,
    POSITIONS,
    TactError,
    compiled_document,
    layout_to_unit,
    parse_tact,
    path_of_scene,
)


def tact_effects(path, position: str | None = None, groups: dict | None = None):
    """A ``.tact`` file's effects as pattern effects, and the project's name (see the
    module): ``(effects, name)``.

    Parameters
    ----------
    path : path
        The file (read and checked as :func:`~tactile_core.files.tact.read_tact` does).
    position : str, optional
        The device position; by default the first that holds paths or dots.
    groups : dict of str to str, optional
        Instead of one position, several, each to play on a layout group:
        ``{"VestFront": "front", "VestBack": "back"}`` (positions without content are left
        out; each effect gets its position's group).

    Raises
    ------
    TactError
        Naming the file and the field, or a position without content.
    """
    data = parse_json(read_bytes(path, TactError, max_bytes=MAX_TACT_BYTES), path, TactError)
    file = parse_tact(data, str(path))
    if not file.positions:
        raise TactError(f"{path}: no paths or dots to play (no enabled track holds any)")
    if groups is None:
        position = file.positions[0] if position is None else position
        if position not in file.positions:
            held = ", ".join(file.positions)
            raise TactError(f"{path}: position {_validate.shown(position)} holds no paths or "
                            f"dots (positions with content: {held})")  # fmt: skip
        groups = {position: None}
    project = data.get("project", data)
    held: dict[tuple, tuple[list, list]] = {}
    for kind, items in enumerate((file.paths, file.dots)):
        for item in items:
            if item.position in groups:
                key = (*_effect_of(item.field), item.position)
                held.setdefault(key, ([], []))[kind].append(item)
    effects = []
    for (track, index, where), (paths, dots) in sorted(held.items()):
        if track >= 0:  # an effect of the project
            raw = project["tracks"][track]["effects"][index]
            start_s, length_s = _ms(raw["startTime"]) / 1e3, _ms(raw["offsetTime"]) / 1e3
        else:  # frames of the file not in a project's effect: one effect from 0
            raw, start_s, length_s, track = {}, 0.0, file.duration_s, 0
        motors = file.layouts.get(where, {})
        shapes = tuple(TimedPath(p.points, [max(t - start_s, 0.0) for t in p.times_s],
                                 p.intensities, p.pattern, p.fade) for p in paths)  # fmt: skip
        places = tuple(Dot(_place(d, motors), d.intensity, max(d.start_s - start_s, 0.0),
                           d.end_s - d.start_s, d.fade) for d in dots)  # fmt: skip
        content = TactEffect(shapes, places, max(length_s, _end(shapes, places)), where)
        name = raw.get("name") if isinstance(raw.get("name"), str) else ""
        try:
            effects.append(Effect(content, start_s=start_s, track=min(track, MAX_TRACKS - 1),
                                  name=_printable(name), group=groups[where]))  # fmt: skip
        except ValueError as exc:
            raise TactError(f"{path}: tracks[{track}].effects[{index}]: {exc}") from None
    return tuple(effects), _printable(file.name)


def _printable(name: str) -> str:
    """A file's name for an effect or a pattern: cut to the longest kept, "" if it holds
    control characters."""
    return name[:MAX_TEXT_CHARS] if name.isprintable() else ""


def _effect_of(field: str) -> tuple[int, int]:
    """``(track, effect)`` of a field path ``tracks[T].effects[E]...``; ``(-1, -1)`` for what
    no project effect holds (bHaptics' compiled frames)."""
    track, sep, rest = field.removeprefix("tracks[").partition("].effects[")
    if not field.startswith("tracks[") or not sep:
        return -1, -1
    return int(track), int(rest.partition("]")[0])


def _place(dot, motors: dict) -> tuple[float, float]:
    """A file's dot's place in 0..1: its motor's in the position's layout (or the place the
    record carries itself)."""
    if dot.index in motors:
        return motors[dot.index]
    return (dot.x, dot.y)


def _ms(value) -> float:
    """A checked time of the file (a number, or numeric text as the Designer writes some)."""
    return float(value.strip()) if isinstance(value, str) else float(value)


def _end(paths, dots) -> float:
    return max([p.times_s[-1] for p in paths] + [d.end_s for d in dots])


def pattern_tact_document(pattern, target, *, name: str = "tactile-tuner",
                          position: str = "VestFront", positions: dict | None = None,
                          compiled: str | None = None,
                          created_ms: int | None = None) -> dict:  # fmt: skip
    """The ``.tact`` document (the Designer's project form) of a pattern on an array.

    Parameters
    ----------
    pattern : Pattern
    target : Grid or Layout
        The array it plays on: its actuators span 0..1 in the file.
    name : str, keyword-only
        The project's name.
    position : str, keyword-only
        The device position everything is written to (one of ``POSITIONS``)...
    positions : dict of str to str, optional
        ...except the effects of these groups, each written to its position in 0..1 of the
        group's actuators (``{"front": "VestFront", "back": "VestBack"}`` on a vest).
    compiled : str, optional
        A rendering method (for the effects that name none): the document then carries
        bHaptics' compiled form too, the pattern's combined raw intensities every 20 ms on each
        position's motors (x 100, cut to whole numbers, as :func:`~._tact_write.compile_frames`
        makes a path's).
    created_ms : int, optional
        ``createdAt``/``updatedAt`` in ms since the epoch (default: now).

    Returns
    -------
    dict
        JSON-ready.

    Raises
    ------
    ValueError
        A position bHaptics does not know, a group the layout lacks, or more bHaptics effects
        than a file holds (``MAX_EFFECTS``, repetitions counted).
    """
    target = check_target(target)
    positions = dict(positions or {})
    for where in (position, *positions.values()):
        _validate.choice("position", where, tuple(POSITIONS))
    if not isinstance(name, str) or len(name) > MAX_NAME_CHARS:
        raise ValueError(f"name must be a string of at most {MAX_NAME_CHARS} characters, got "
                         f"{_validate.shown(name)}")  # fmt: skip
    places = {}  # position: (box, motor index of each actuator)
    for group, where in positions.items():
        places[where] = _places(target, layout_group(target, group, f"positions[{group!r}]"))
    if position not in places:
        places[position] = _places(target, None)
    tracks: dict[int, list] = {}
    count = 0
    method = get_method(default_method(target))
    owner = {where: group for group, where in positions.items()}
    for i, effect in enumerate(pattern.effects):
        where = positions.get(effect.group, position)
        if where in owner and owner[where] != effect.group:
            what = "every actuator" if effect.group is None else f"group {effect.group!r}"
            raise ValueError(f"effects[{i}] plays on {what}, which would be written to {where}, "
                             f"the position of group {owner[where]!r} alone: give the effect one "
                             f"of the groups {', '.join(map(repr, positions))}, or write the "
                             "rest to another position")  # fmt: skip
        box, motor_of = places[where]
        parts = compile_parts(type(pattern)((effect,)), method, target)
        for r in range(effect.repeat):
            start_s = effect.start_s + r * effect.duration_s
            for mode, body in _modes(effect, parts, box, motor_of):
                count += 1
                if count > MAX_EFFECTS:
                    raise ValueError(f"effects[{i}] brings the file past the {MAX_EFFECTS} "
                                     "bHaptics effects a .tact file holds (each repetition is "
                                     "one)")  # fmt: skip
                tracks.setdefault(effect.track, []).append({
                    "name": effect.name or f"Effect {count}", "startTime": _ms_of(start_s),
                    "offsetTime": _ms_of(effect.duration_s),
                    "modes": {where: {"mode": mode, **body}}})  # fmt: skip
    now = created_ms if created_ms is not None else _now_ms()
    kind = POSITIONS[position]
    layouts = {}
    for where, place in places.items():
        motors = enumerate(_sorted_places(target, place))
        layouts[where] = [{"index": k, "x": _r(u), "y": _r(v)} for k, (u, v) in motors]
    end_ms = _ms_of(pattern.duration_s)
    frames = {} if compiled is None else _compiled(pattern, target, compiled, places)
    return {
        "project": {
            "name": name,
            "description": "exported by tactile-tuner",
            "id": uuid.uuid4().hex[:20],
            "mediaFileDuration": math.ceil(end_ms / 1000.0),
            "createdAt": now,
            "updatedAt": now,
            "layout": {"name": kind, "type": kind, "layouts": layouts},
            "tracks": [{"enable": True, "effects": tracks[k]} for k in sorted(tracks)],
        },
        "durationMillis": 0,
        "intervalMillis": SAMPLE_MS,
        "size": max(len(v) for v in layouts.values()),
        **frames,
    }


def _compiled(pattern, target, method: str, places: dict) -> dict:
    """The compiled form's keys: the pattern's raw frames at ``k * 20`` ms, per position its
    motors' values in their order."""
    live = PatternFrames(pattern, method, target, Sampling(), 0.0, 1.0)
    n = frame_count(pattern.duration_s, INTERVAL_MS)
    raw = live.raw_at(np.arange(n) * INTERVAL_MS / 1e3)
    values = {}
    for where, (_, motor_of) in places.items():
        order = sorted(motor_of, key=motor_of.get)
        values[where] = np.clip(np.floor(raw[:, order] * 100.0 + 1e-9), 0, 100).astype(np.int64)
    return compiled_document(values, interval_ms=INTERVAL_MS)


def _ms_of(seconds: float) -> int:
    return round(seconds * 1000.0)


def _places(target, members) -> tuple:
    """``(box, {actuator: motor index})`` of ``members`` (None: all) in the Designer's order:
    from the top left, row by row (as :func:`~._tact_write.motor_places` numbers them)."""
    chosen = range(target.size) if members is None else members
    xy = target.xy[list(chosen)]
    box = (float(xy[:, 0].min()), float(xy[:, 0].max()), float(xy[:, 1].min()),
           float(xy[:, 1].max()))  # fmt: skip
    uv = {a: layout_to_unit(*target.xy[a], box) for a in chosen}
    order = sorted(chosen, key=lambda a: (round(uv[a][1], DECIMALS), round(uv[a][0], DECIMALS)))
    return box, {a: k for k, a in enumerate(order)}


def _sorted_places(target, place) -> list:
    box, motor_of = place
    by_motor = sorted(motor_of, key=motor_of.get)
    return [layout_to_unit(*target.xy[a], box) for a in by_motor]


def _modes(effect, parts, box, motor_of) -> list:
    """``[(mode, body), ...]`` of one play of ``effect``: a PATH_MODE body with its strokes'
    paths, a DOT_MODE body with its dots (either missing when it has none)."""
    out = []
    end_ms = _ms_of(effect.duration_s)
    strokes = [p for p in parts if p.shape is not None]
    dots = [p for p in parts if p.shape is None]
    empty_dots = {"dotConnected": False, "feedback": []}
    if strokes:
        feedback = [_path_feedback(effect, p, box) for p in strokes]
        out.append(("PATH_MODE", {"dotMode": empty_dots, "pathMode": {"feedback": feedback}}))
    if dots:
        feedback = []
        for p in dots:
            for a_s, b_s, level in _dot_pieces(effect, p):
                begin, end = _ms_of(a_s), min(_ms_of(b_s), end_ms)
                if end > begin:
                    feedback.append({"startTime": begin, "endTime": end,
                                     "playbackType": "NONE" if effect.envelope else
                                     FADES[p.fade], "pointList": [
                                         {"index": motor_of[p.actuator],
                                          "intensity": _r(level)}]})  # fmt: skip
        out.append(("DOT_MODE", {"dotMode": {"dotConnected": False, "feedback": feedback},
                                 "pathMode": {"feedback": []}}))  # fmt: skip
    return out


def _dot_pieces(effect, part) -> list:
    """``[(start_s, end_s, level), ...]`` of a dot within a play: itself, or with an envelope
    20 ms pieces at the envelope's (and its fade's) value in their middle."""
    a, b = part.a, part.b
    if not effect.envelope:
        return [(a, b, part.level)]
    n = max(1, math.ceil((b - a) * 1000.0 / SAMPLE_MS - 1e-9))
    edges = np.linspace(a, b, n + 1)
    out = []
    for lo, hi in itertools.pairwise(edges.tolist()):
        mid = 0.5 * (lo + hi)
        u = (mid - a) / (b - a)
        fade = {1: u, 2: 1.0 - u, 3: 1.0 - abs(2.0 * u - 1.0)}.get(part.fade, 1.0)
        out.append((float(lo), float(hi), part.level * fade * effect.gain1(mid)))
    return out


def _path_feedback(effect, part, box) -> dict:
    """One ``pathMode.feedback`` entry: the stroke as a time-keyed path over its window of a
    play, the envelope in its intensities."""
    span = part.b - part.a
    path = path_of_scene(Scene(part.shape, duration_s=span)) if not isinstance(
        part.shape, TimedPath) else part.shape  # fmt: skip
    t0, own = path.times_s[0], path.times_s[-1] - path.times_s[0]
    times = [part.a + (s - t0) * span / own for s in path.times_s]
    points, levels, fade = list(path.points), list(path.intensities), path.fade
    if effect.envelope:
        extra = [t for t, _ in effect.envelope if part.a < t < part.b]
        step = max(SAMPLE_MS / 1000.0, span / (MAX_POINTS - len(times) - len(extra) - 2))
        grid = np.arange(part.a, part.b, step).tolist()
        when = sorted(set(times) | set(extra) | set(grid) | {part.b})
        t = np.clip((np.array(when) - part.a) / span, 0.0, 1.0)
        points = [tuple(p) for p in path.f(t).tolist()]
        levels = [float(v) * effect.gain1(w) for v, w in zip(path.intensity(t), when)]
        times, fade = when, "NONE"
    pattern = path.pattern if not effect.envelope else "CONST_TDM"
    out, last = [], None
    for (x, y), s, level in zip(points, times, levels):
        ms = _ms_of(s)
        if last is not None and ms <= last:
            continue  # less than 1 ms after the point before it
        u, v = layout_to_unit(x, y, box)
        out.append({"x": _r(u), "y": _r(v), "intensity": _r(min(level, 1.0)), "time": ms})
        last = ms
    return {"playbackType": fade, "movingPattern": pattern, "visible": True, "pointList": out}


def write_pattern_tact(out, pattern, target, **options):
    """Write :func:`pattern_tact_document` to ``out`` atomically (checked first, as
    :func:`~tactile_core.files.tact.write_tact` does); returns the path written."""
    out = check_output(out, (), "out")
    return write_json_atomic(out, pattern_tact_document(pattern, target, **options))
