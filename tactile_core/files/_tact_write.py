"""Writing ``.tact`` files: a scene's trace or a time-keyed path as one ``PATH_MODE`` effect.

The document has the keys, types and nesting of the files bHaptics' Designer writes and their
parsers read (``ProjectFile``/``Project``/``Track``/``HapticEffect``/``HapticEffectMode`` in
``ProjectModel.cpp`` of bhaptics/haptic-library require ``intervalMillis``, ``size``,
``durationMillis``, ``project.tracks``, ``project.layout`` (``type``, ``layouts``), per effect
``startTime``, ``offsetTime``, ``modes``, per mode ``mode``, ``dotMode`` (``dotConnected``,
``feedback``) and ``pathMode`` (``feedback`` of ``playbackType``, ``movingPattern``,
``pointList`` of ``x``, ``y``, ``intensity``, ``time``)). ``tests/data/testfeedback.tact`` is
a Designer file the tests compare the structure against.

Coordinates go out in 0..1 of the array's actuator extent, y downward (the inverse of the
import's mapping, clipped to [0, 1]); x, y and intensity rounded to 4 decimals, times to whole
milliseconds (a point less than 1 ms after the one before it is dropped). The layout written is
this array's own actuators, in the same coordinates, numbered as the Designer numbers motors:
from the top left, row by row (:func:`motor_places`). With ``compiled=METHOD`` the document
also carries the compiled form: the path's frames by that method every 20 ms
(:func:`compile_frames`), as bHaptics' own exports carry both forms.
"""

from __future__ import annotations

import itertools
import math
import uuid

import numpy as np

from .._shared import validate as _validate
from .._shared.jsonfile import write_json_atomic
from .._shared.outfile import check_output
from ..rendering.methods import get_method
from ..rendering.rasterize import check_renders, check_target, render
from ..rendering.shapes import MAX_POINTS, Line, Polyline, Shape, Square, TimedPath
from ..rendering.trace import Trace
from ._tact_compiled import INTERVAL_MS, compiled_document, frame_count
from ._tact_coords import layout_box, layout_to_unit
from ._tact_read import MAX_NAME_CHARS

POSITIONS = {"VestFront": "Tactot", "VestBack": "Tactot", "Head": "Tactal",
             "ForearmL": "Tactosy2", "ForearmR": "Tactosy2", "Left": "Tactosy",
             "Right": "Tactosy"}  # fmt: skip
"""Device positions an export may name, with the layout type bHaptics' files give them."""
SAMPLE_MS = 20
"""Step of a sampled trace (a circle, corner emphasis): bHaptics' 20 ms frame interval."""
DECIMALS = 4


def path_of_scene(scene) -> TimedPath:
    """A scene's trace (its shape over ``duration_s``, direction and corner emphasis) as a
    time-keyed path starting at 0.

    Lines, polylines and squares without corner emphasis go out as their vertices at constant
    speed (exact); a time-keyed path as it is (its times shifted to start at 0); anything else
    (circles, emphasis) is sampled every :data:`SAMPLE_MS` ms as ``CONST_TDM`` (at most
    ``MAX_POINTS`` samples: longer traces at that many evenly spaced times). The pause and
    the repeats are not part of it: a ``.tact`` effect plays once.
    """
    shape = scene.shape
    if not isinstance(shape, Shape):
        raise ValueError("the scene has no shape to export (an idle scene, or a frame source)")
    reverse = scene.direction == "reverse"
    if isinstance(shape, TimedPath):
        t0, end = shape.times_s[0], shape.times_s[-1]
        points, levels = list(shape.points), list(shape.intensities)
        times = [s - t0 for s in shape.times_s]
        if reverse:
            points, levels = points[::-1], levels[::-1]
            times = [end - t0 - s for s in times[::-1]]
        fade = {"FADE_IN": "FADE_OUT", "FADE_OUT": "FADE_IN"}.get(shape.fade, shape.fade)
        return TimedPath(points, times, levels, shape.pattern, fade if reverse else shape.fade)
    duration = scene.duration_s
    if isinstance(shape, (Line, Polyline, Square)) and scene.emphasis == 0.0:
        points = [tuple(p) for p in shape.outline().tolist()]
        if reverse:
            points = points[::-1]
        points = [p for k, p in enumerate(points) if k == 0 or p != points[k - 1]]
        if len(points) == 1:
            return TimedPath(points * 2, [0.0, duration], pattern="CONST_SPEED")
        steps = np.cumsum([math.dist(a, b) for a, b in itertools.pairwise(points)])
        times = [0.0, *(duration * float(c) / float(steps[-1]) for c in steps)]
        times[-1] = duration
        return TimedPath(points, times, pattern="CONST_SPEED")
    n = min(max(2, math.ceil(duration * 1000 / SAMPLE_MS) + 1), MAX_POINTS)
    times = np.linspace(0.0, duration, n)
    trace = Trace(shape, duration, 0.0, scene.direction, False, scene.emphasis)
    t, _ = trace.parameter(np.minimum(times, np.nextafter(duration, 0.0)))
    t[-1] = 0.0 if reverse else 1.0
    points = shape.f(t).tolist()
    return TimedPath(points, times.tolist(), pattern="CONST_TDM")


def tact_document(path: TimedPath, target, *, name: str = "tactile-tuner",
                  position: str = "VestFront", created_ms: int | None = None,
                  compiled: str | None = None) -> dict:  # fmt: skip
    """The ``.tact`` document of one time-keyed path on an array.

    Parameters
    ----------
    path : TimedPath
        In layout units of ``target``; its times are shifted to start at 0.
    target : Grid or Layout
        The array the path is drawn on: its actuator extent is 0..1 in the file.
    name : str, keyword-only
        The project's name.
    position : str, keyword-only
        The bHaptics device position the effect is for (one of :data:`POSITIONS`).
    created_ms : int, optional
        ``createdAt``/``updatedAt`` in ms since the epoch (default: now).
    compiled : str, optional
        A rendering method: the document then carries the compiled form too, the path's frames
        by that method every 20 ms (:func:`compile_frames`), as bHaptics' exports carry both.

    Returns
    -------
    dict
        JSON-ready; :func:`write_tact` writes it.
    """
    if not isinstance(path, TimedPath):
        raise ValueError(f"path must be a TimedPath, got {_validate.shown(path)}")
    if position not in POSITIONS:
        raise ValueError(
            f"position must be one of {', '.join(POSITIONS)}, got {_validate.shown(position)}"
        )
    if not isinstance(name, str) or len(name) > MAX_NAME_CHARS:
        raise ValueError(f"name must be a string of at most {MAX_NAME_CHARS} characters, got "
                         f"{_validate.shown(name)}")  # fmt: skip
    if path.duration_s < 1e-3:
        raise ValueError(f"path lasts {path.duration_s * 1e3:g} ms: a .tact path needs >= 1 ms")
    target = check_target(target)
    box = layout_box(target)
    t0 = path.times_s[0]
    points, last = [], None
    for (x, y), s, level in zip(path.points, path.times_s, path.intensities):
        ms = round((s - t0) * 1000.0)
        if last is not None and ms <= last:
            continue  # less than 1 ms after the point before it
        u, v = layout_to_unit(x, y, box)
        points.append({"x": _r(u), "y": _r(v), "intensity": _r(level), "time": ms})
        last = ms
    end = round(path.duration_s * 1000.0)
    if points[-1]["time"] != end:  # the last point always goes out, at the path's end
        x, y = path.points[-1]
        u, v = layout_to_unit(x, y, box)
        points[-1] = {"x": _r(u), "y": _r(v), "intensity": _r(path.intensities[-1]), "time": end}
    motors = [{"index": i, "x": _r(u), "y": _r(v)} for i, (u, v) in enumerate(motor_places(target))]
    mode = {
        "mode": "PATH_MODE",
        "dotMode": {"dotConnected": False, "feedback": [
            {"startTime": 0, "endTime": end, "playbackType": "NONE", "pointList": []}]},
        "pathMode": {"feedback": [
            {"playbackType": path.fade, "movingPattern": path.pattern, "visible": True,
             "pointList": points}]},
    }  # fmt: skip
    effect = {"name": "Effect 1", "startTime": 0, "offsetTime": end, "modes": {position: mode}}
    now = created_ms if created_ms is not None else _now_ms()
    kind = POSITIONS[position]
    frames = {}
    if compiled is not None:
        frames = compiled_document({position: compile_frames(path, target, compiled)})
    return {
        "project": {
            "name": name,
            "description": "exported by tactile-tuner",
            "id": uuid.uuid4().hex[:20],
            "mediaFileDuration": math.ceil(end / 1000.0),
            "createdAt": now,
            "updatedAt": now,
            "layout": {"name": kind, "type": kind, "layouts": {position: motors}},
            "tracks": [{"enable": True, "effects": [effect]}],
        },
        "durationMillis": 0,
        "intervalMillis": SAMPLE_MS,
        "size": len(motors),
        **frames,
    }


def compile_frames(path: TimedPath, target, method: str, *, interval_ms: int = INTERVAL_MS):
    """A path's frames as bHaptics' compiled form holds them: motor values every
    ``interval_ms``.

    Parameters
    ----------
    path : TimedPath
        In layout units of ``target``; its times are taken from its start.
    target : Grid or Layout
        The array it is rendered on.
    method : str
        The rendering method (its raw intensities: no correction, which is this array's).
    interval_ms : int, keyword-only
        The frames' spacing (bHaptics' 20 ms).

    Returns
    -------
    ndarray of int64, shape (n, size)
        Frame ``k`` at ``k * interval_ms`` (``n`` frames before the path's end), values 0..100
        (the raw intensity x 100 cut to a whole number, as bHaptics' values are), columns in
        the Designer's motor order (:func:`motor_order`).
    """
    if not isinstance(path, TimedPath):
        raise ValueError(f"path must be a TimedPath, got {_validate.shown(path)}")
    target = check_target(target)
    method = get_method(method)
    check_renders(method, target)
    n = frame_count(path.duration_s, interval_ms)
    t = np.clip(np.arange(n) * interval_ms / 1e3 / path.duration_s, 0.0, 1.0)
    raw = render(path, method.on_clock(path.duration_s), t, grid=target).reshape(n, target.size)
    return np.clip(np.floor(raw[:, motor_order(target)] * 100.0 + 1e-9), 0, 100).astype(np.int64)


def motor_places(target) -> list[tuple[float, float]]:
    """The actuators of ``target`` (a Grid or Layout) as bHaptics motors: ``(x, y)`` in 0..1,
    y downward, in the Designer's motor order.

    The Designer numbers a panel's motors from the top left, row by row downwards, left to
    right in a row (its Tactot layout: motor 0 at (0, 0), 3 at (1, 0), 16 at (0, 1);
    ``tests/data/testfeedback.tact`` and ``CenterX.tact`` of bhaptics/tact-python). Places are
    ordered by ``y`` then ``x``, each rounded as written, so motor ``i`` of the file is the
    ``i``-th of them. Importing maps every motor by its place (not its number), so a file
    exported then imported puts each motor back on the actuator it came from.
    """
    box = layout_box(target)
    places = [layout_to_unit(x, y, box) for x, y in check_target(target).positions]
    return [places[i] for i in motor_order(target)]


def motor_order(target) -> list[int]:
    """The actuators of ``target`` in the Designer's motor order (:func:`motor_places`):
    ``motor_order(target)[m]`` is motor ``m``'s actuator."""
    box = layout_box(target)
    places = [layout_to_unit(x, y, box) for x, y in check_target(target).positions]
    return sorted(range(len(places)), key=lambda i: (round(places[i][1], DECIMALS),
                                                     round(places[i][0], DECIMALS)))  # fmt: skip


def write_tact(out, path: TimedPath, target, **options):
    """Write :func:`tact_document` to ``out`` atomically; returns the path written.

    ``out`` is checked first (:func:`~tactile_core._shared.outfile.check_output`): a folder, a
    device such as ``/dev/null`` or a missing folder is refused by name (``ValueError``), where
    the atomic rename would otherwise put a regular file in a device's place.
    """
    out = check_output(out, (), "out")
    return write_json_atomic(out, tact_document(path, target, **options))


def _r(value: float) -> float:
    """Rounded to :data:`DECIMALS`; whole values as ints, as the Designer writes 0 and 1."""
    value = round(float(value), DECIMALS)
    return int(value) if value.is_integer() else value


def _now_ms() -> int:
    import time

    return int(time.time() * 1000)
