"""Patterns: a time line of effects on tracks, composed in Python or a file, played like a shape.

A :class:`Pattern` holds :class:`Effect` values; an effect plays a shape (a line, circle,
square, polyline, a drawn or time-keyed path; with ``method="TB"`` a Tactile Brush stroke), a
set of :class:`Dots`, or an imported ``.tact`` effect (:class:`TactEffect`), from ``start_s``
for ``duration_s``, ``repeat`` times, through an intensity ``envelope``, on the actuators of a
layout ``group``. Overlapping effects combine by the maximum per actuator or, where the pattern
says ``combine="sum"``, by the sum clipped to 1. Everything is immutable: the builder methods
return new patterns.

A pattern is a frame source: ``Scene(source=pattern)`` streams it, ``open_array(...).play``
plays it, :meth:`Pattern.frames` renders it; ``tactile render`` and ``tactile stream`` take it
as ``--shape pattern:FILE``. Its file is versioned JSON (``"format": "tactile-pattern"``),
read field by field (:class:`PatternError` names the field); it exports to ``.tact``
(:meth:`Pattern.to_tact`). ``docs/patterns.md`` documents the file and the rules.
:class:`PatternCue` plays a pattern from a moment of it, or holds that moment (an editor's
playhead).

>>> import tactile_core as tc
>>> taps = tc.Pattern([tc.Effect(tc.Dots([tc.Dot(14, 0.5, 0.0, 0.1)]), start_s=0.2, repeat=3,
...                              duration_s=0.3)])
>>> round(taps.duration_s, 9)  # the last tap's play ends at 0.2 + 3 x 0.3 s
1.1
>>> _, frames = taps.frames("AS", tc.Grid(5, 6), rate_hz=10.0)
>>> frames[:, 2, 4].tolist()  # actuator 14 is column 4 of row 2
[0.0, 0.0, 0.5, 0.0, 0.0, 0.5, 0.0, 0.0, 0.5, 0.0, 0.0]
"""

from __future__ import annotations

from pathlib import Path

from .._shared.assets import assets_dir
from ._pattern_cue import CueFrames, PatternCue
from ._pattern_effects import (
    COMBINE,
    MAX_DOTS,
    MAX_EFFECTS,
    MAX_KEYFRAMES,
    MAX_REPEAT,
    MAX_TOTAL_POINTS,
    MAX_TRACKS,
    Dot,
    Dots,
    Effect,
    TactEffect,
)
from ._pattern_frames import PatternFrames
from ._pattern_json import FORMAT, MAX_PATTERN_BYTES, MAX_PATTERN_DEPTH, VERSION, PatternError
from ._pattern_model import Pattern
from ._pattern_tact import pattern_tact_document, write_pattern_tact

__all__ = [
    "COMBINE",
    "FORMAT",
    "MAX_DOTS",
    "MAX_EFFECTS",
    "MAX_KEYFRAMES",
    "MAX_PATTERN_BYTES",
    "MAX_PATTERN_DEPTH",
    "MAX_REPEAT",
    "MAX_TOTAL_POINTS",
    "MAX_TRACKS",
    "VERSION",
    "CueFrames",
    "Dot",
    "Dots",
    "Effect",
    "Pattern",
    "PatternCue",
    "PatternError",
    "PatternFrames",
    "TactEffect",
    "example_patterns",
    "is_example",
    "pattern_tact_document",
    "profiles_playing",
    "write_pattern_tact",
]


def example_patterns() -> dict[str, Path]:
    """The bundled example patterns (``assets/patterns``: the letter, the vest sweep and the
    taps of ``docs/patterns.md``), by file stem, in file-name order."""
    folder = assets_dir() / "patterns"
    return {p.stem: p for p in sorted(folder.glob("*.json"))}


def is_example(path) -> bool:
    """Whether ``path`` is in the bundled example patterns' folder (the installed package's
    own files: an editor saves a changed example elsewhere).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    bool
    """
    folder = (assets_dir() / "patterns").resolve()
    return Path(path).resolve().parent == folder


def profiles_playing(pattern) -> list[str]:
    """The known device profiles (the bundled ones and the user's, by name) whose layout
    ``pattern`` plays on with the layout's own method: the default profile first, then in name
    order (``vest-front-back`` for the vest sweep, whose groups are ``front`` and ``back``).

    Parameters
    ----------
    pattern : Pattern

    Returns
    -------
    list of str
    """
    from ..device.profile import DEFAULT_PROFILE, ProfileError, load_profile, profile_names

    names = []
    for name, path in profile_names().items():
        try:
            pattern.check(load_profile(path).layout)
        except (ProfileError, ValueError):  # a user's broken profile: not one to offer
            continue
        names.append(name)
    return sorted(names, key=lambda name: name != DEFAULT_PROFILE)
