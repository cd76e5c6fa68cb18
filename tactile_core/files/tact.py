"""bHaptics ``.tact`` files in and out: import a file as a pattern, export a path or a scene.

Import (:func:`read_tact`, :func:`load_pattern`) checks the whole file, then plays one device
position of it on *this* array (:class:`TactPattern`): paths become
:class:`~tactile_core.rendering.shapes.TimedPath` shapes in this array's layout coordinates and
are rendered by the scene's method, dots light the actuators nearest to their motors, and the
two combine by the maximum per actuator before the correction. A pattern is a frame source:
``Scene(source=pattern)`` streams it, :meth:`TactPattern.frames` renders it to arrays.

Export (:func:`write_tact`) writes a time-keyed path, e.g. :func:`path_of_scene` of a scene or a
drawing (:func:`~tactile_core.rendering.shapes.path_from_samples`), as a file with one
``PATH_MODE`` effect. ``docs/tact.md`` lists what is supported and what is not.

>>> import tactile_core as tc
>>> from tactile_core.rendering.shapes import TimedPath
>>> doc = tact_document(TimedPath([(0.5, 0.5), (4.5, 5.5)], [0.0, 1.0]), tc.Grid(5, 6))
>>> doc["project"]["tracks"][0]["effects"][0]["modes"]["VestFront"]["pathMode"]["feedback"][0][
...     "pointList"]
[{'x': 0, 'y': 1, 'intensity': 1, 'time': 0}, {'x': 1, 'y': 0, 'intensity': 1, 'time': 1000}]
"""

from __future__ import annotations

from ._tact_coords import layout_box, layout_to_unit, unit_to_layout
from ._tact_frames import MAX_TABLE_FRAMES, NOTHING_TO_PLAY, PatternFrames, TactPattern
from ._tact_read import (
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
from ._tact_write import POSITIONS, path_of_scene, tact_document, write_tact

__all__ = [
    "MAX_EFFECTS",
    "MAX_LAYOUT",
    "MAX_NAME_CHARS",
    "MAX_TABLE_FRAMES",
    "MAX_TACT_BYTES",
    "MAX_TOTAL_POINTS",
    "POSITIONS",
    "PatternFrames",
    "TactDot",
    "TactError",
    "TactFile",
    "TactPath",
    "TactPattern",
    "layout_box",
    "layout_to_unit",
    "load_pattern",
    "parse_tact",
    "path_of_scene",
    "read_tact",
    "tact_document",
    "unit_to_layout",
    "write_tact",
]


def load_pattern(path, position: str | None = None) -> TactPattern:
    """Read a ``.tact`` file and take one device position of it as a pattern.

    Parameters
    ----------
    path : path
        The file.
    position : str, optional
        The device position to play; by default the first that holds paths or dots.

    Raises
    ------
    TactError
        Naming the file and the field (see :func:`read_tact`), a file without content
        (``FILE: no paths or dots to play ...``, as ``tactile render`` says it) or a position
        without content.
    """
    file = read_tact(path)
    if not file.positions:
        raise TactError(f"{path}: {NOTHING_TO_PLAY}")
    return TactPattern(file, position)
