"""bHaptics ``.tact`` files in and out: import a file as a pattern, export a path or a scene.

Import (:func:`read_tact`, :func:`load_pattern`) checks the whole file, in either of its forms
(the Designer project, bHaptics' compiled ``feedback`` frames, or both), then plays it on
*this* array (:class:`TactPattern`): each device position on the array's group for that part of
the body (``VestFront`` on ``front``, ...) or one position over the whole array; paths become
:class:`~tactile_core.rendering.shapes.TimedPath` shapes in this array's layout coordinates and
are rendered by the scene's method, dots light the actuators nearest to their motors as
bHaptics adds them up. bHaptics' play-time ``ScaleOption`` and ``RotationOption`` apply
(:class:`ScaleOption`, :class:`RotationOption`). A pattern is a frame source:
``Scene(source=pattern)`` streams it, :meth:`TactPattern.frames` renders it to arrays.

Export (:func:`write_tact`) writes a time-keyed path, e.g. :func:`path_of_scene` of a scene or a
drawing (:func:`~tactile_core.rendering.shapes.path_from_samples`), as a file with one
``PATH_MODE`` effect, and with ``compiled=True`` its frames in bHaptics' compiled form beside it
(:func:`compiled_document`). ``docs/tact.md`` lists what is supported and what is not.

>>> import tactile_core as tc
>>> from tactile_core.rendering.shapes import TimedPath
>>> doc = tact_document(TimedPath([(0.5, 0.5), (4.5, 5.5)], [0.0, 1.0]), tc.Grid(5, 6))
>>> doc["project"]["tracks"][0]["effects"][0]["modes"]["VestFront"]["pathMode"]["feedback"][0][
...     "pointList"]
[{'x': 0, 'y': 1, 'intensity': 1, 'time': 0}, {'x': 1, 'y': 0, 'intensity': 1, 'time': 1000}]
"""

from __future__ import annotations

from ._tact_compiled import compiled_document, device_places
from ._tact_coords import layout_box, layout_to_unit, unit_to_layout
from ._tact_frames import MAX_TABLE_FRAMES, NOTHING_TO_PLAY, PatternFrames, TactPattern
from ._tact_options import RotationOption, ScaleOption
from ._tact_oracle import Comparison, compare_compiled
from ._tact_place import POSITION_GROUPS, matching_layout
from ._tact_read import (
    FORMS,
    MAX_EFFECTS,
    MAX_LAYOUT,
    MAX_NAME_CHARS,
    MAX_TACT_BYTES,
    MAX_TOTAL_POINTS,
    TactDot,
    TactError,  # fmt: skip
    TactFile,
    TactPath,
    parse_tact,
    read_tact,
)
from ._tact_records import TactCompiled
from ._tact_write import POSITIONS, compile_frames, path_of_scene, tact_document, write_tact

__all__ = [
    "FORMS",
    "MAX_EFFECTS",
    "MAX_LAYOUT",
    "MAX_NAME_CHARS",
    "MAX_TABLE_FRAMES",
    "MAX_TACT_BYTES",
    "MAX_TOTAL_POINTS",
    "POSITIONS",
    "POSITION_GROUPS",
    "Comparison",
    "PatternFrames",
    "RotationOption",
    "ScaleOption",
    "TactCompiled",
    "TactDot",
    "TactError",
    "TactFile",
    "TactPath",
    "TactPattern",
    "compare_compiled",
    "compile_frames",
    "compiled_document",
    "device_places",
    "layout_box",
    "layout_to_unit",
    "load_pattern",
    "matching_layout",
    "parse_tact",
    "path_of_scene",
    "read_tact",
    "tact_document",
    "unit_to_layout",
    "write_tact",
]


def load_pattern(path, position: str | None = None, *, scale=None, rotation=None,
                 form: str | None = None) -> TactPattern:  # fmt: skip
    """Read a ``.tact`` file as a pattern.

    Parameters
    ----------
    path : path
        The file.
    position : str, optional
        A device position to play alone over the whole array. By default every position plays
        on the array's group for it (``VestFront`` on ``front``, docs/tact.md), or the first
        that holds paths or dots on an array without such groups.
    scale : ScaleOption or (float, float), optional
        bHaptics' ``ScaleOption``: ``(intensity, duration)`` multipliers, e.g. ``(0.5, 2.0)``
        plays at half the intensity and half the speed.
    rotation : RotationOption or (float, float), optional
        bHaptics' ``RotationOption`` for the vest: ``(angle_deg, offset_y)``, degrees round
        the body (90: a quarter turn towards the wearer's left) and panel heights up.
    form : {"project", "compiled"}, optional
        Play the Designer project or bHaptics' compiled frames (default: the project, or the
        frames of a file without one).

    Raises
    ------
    TactError
        Naming the file and the field (see :func:`read_tact`), a file without content
        (``FILE: no paths or dots to play ...``, as ``tactile render`` says it) or a position
        without content.
    ValueError
        A scale, rotation or form out of range, naming it.
    """
    file = read_tact(path, form)
    if not file.positions:
        raise TactError(f"{path}: {NOTHING_TO_PLAY}")
    return TactPattern(file, position, scale, rotation)
