"""What the window's title calls the scene that plays: the name of the preset, pattern or
``.tact`` file it came from while it plays that content, else what it plays."""

from __future__ import annotations

import functools

import tactile_core as tc
from tactile_core.files.pattern import Pattern, PatternCue
from tactile_core.files.presets import builtin_presets, load_preset

EDITABLE = (tc.Line, tc.Circle, tc.Square)
"""Shapes the shape box edits field by field: a preset's line moved is still that preset's."""


def scene_name(scene, came_from, name: str) -> str:
    """What the title calls ``scene``.

    Parameters
    ----------
    scene : Scene
        What plays.
    came_from : Scene or None
        The scene of the preset (pattern, ``.tact`` file) it came from.
    name : str
        That preset's name.

    Returns
    -------
    str
        ``name`` while ``scene`` plays the content it came with (the same pattern or ``.tact``
        file, options aside; a line, circle or square of the same kind, its fields edited; the
        same path); otherwise what plays: a pattern's own name (``untitled`` if it has none),
        ``free point (draw mode)``,
        ``drawn path``, a built-in preset's name for its shape (``Experiment 1 line``, the
        scene a profile that a pattern does not fit gives way to), else the kind of shape
        (``circle``), or ``nothing``.
    """
    if came_from is None or _same_content(scene, came_from):
        return name
    shape, source = scene.shape, played(scene.source)
    if source is not None:
        return getattr(source, "name", "") or "untitled"
    if shape is None:
        return "nothing"
    if _point(shape):
        return "free point (draw mode)"
    if isinstance(shape, tc.TimedPath):
        return "drawn path"
    return _builtin_names().get(shape, type(shape).__name__.lower())


def played(source):
    """A scene's frame source as content: a pattern played from a moment of it (the editor's
    :class:`PatternCue`) is that pattern."""
    return source.pattern if isinstance(source, PatternCue) else source


def _same_content(a, b) -> bool:
    if a.source is not None or b.source is not None:
        one, other = played(a.source), played(b.source)
        file = getattr(one, "file", None)  # a .tact file, whatever its options
        return one == other or (file is not None and file is getattr(other, "file", None))
    if isinstance(a.shape, EDITABLE):
        return type(a.shape) is type(b.shape) and _point(a.shape) == _point(b.shape)
    return a.shape == b.shape


def _point(shape) -> bool:
    """Draw mode's free point: a line from a point to itself."""
    return isinstance(shape, tc.Line) and shape.p0 == shape.p1


@functools.cache
def _builtin_names() -> dict:
    """The built-in presets' names by their shape, for the shapes only one of them has."""
    named: dict = {}
    for path in builtin_presets().values():
        preset = load_preset(path)
        shape = preset.scene.shape
        named[shape] = None if shape in named else preset.name
    return {shape: name for shape, name in named.items() if name is not None}


def source_kind(source) -> str:
    """What a shapeless scene plays, in words: ``a pattern`` (a pattern file, the editor's),
    ``a .tact pattern`` (an imported bHaptics file), else ``free points`` (another program's)."""
    source = played(source)
    if isinstance(source, Pattern):
        return "a pattern"
    return "a .tact pattern" if hasattr(source, "file") else "free points"


def same_tuning(a, b) -> bool:
    """Whether two scenes are the same tuning (playing state, restarts, where a pattern plays
    from and the kind of presentation, such as a Blind A/B play's ``ab``, aside)."""
    a, b = (s.replace(playing=True, epoch=0, marker="", source=played(s.source)) for s in (a, b))
    return a == b  # (a pattern played from a moment of it is that pattern)
