"""bHaptics' compiled frames as an oracle: this tool's rendering of a file's project beside
bHaptics' own, frame for frame.

Many ``.tact`` files carry both forms; there the compiled ``feedback`` frames are bHaptics'
rendering of the project. Played on the position's own motors (:func:`matching_layout`: the
vest's 4 x 5 per side as a grid, motor ``i`` on its cell), the project's dots must give the
same motor values, and its paths show how far each rendering method lands from bHaptics' own
path interpolation. ``tools/tact_oracle.py`` runs :func:`compare_compiled` over a folder.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..rendering.trace import Sampling
from ._tact_frames import TactPattern
from ._tact_place import matching_layout
from ._tact_play import PatternFrames


@dataclass(frozen=True)
class Comparison:
    """One position of one file, this tool's frames beside bHaptics' own.

    Attributes
    ----------
    position : str
    kind : {"dots", "paths", "mixed"}
        What the position's project holds.
    method : str
        The method the paths were rendered by ("" for dots alone).
    ours, theirs : ndarray of int64, shape (n, motors)
        Motor values 0..100 at bHaptics' frame times: this tool's (``floor(100 v)``, as
        bHaptics cuts them) and the compiled frames'.
    """

    position: str
    kind: str
    method: str
    ours: np.ndarray
    theirs: np.ndarray

    @property
    def frames(self) -> int:
        return len(self.theirs)

    @property
    def exact(self) -> int:
        """Frames equal in every motor."""
        return int((self.ours == self.theirs).all(axis=1).sum())

    @property
    def within(self) -> np.ndarray:
        """Per frame, the largest difference over the motors."""
        return np.abs(self.ours - self.theirs).max(axis=1, initial=0)

    def active(self) -> np.ndarray:
        """Frames where either side lights a motor."""
        return (self.ours > 0).any(axis=1) | (self.theirs > 0).any(axis=1)

    def mean_abs_error(self, lit: bool = False) -> float:
        """Mean |ours - theirs| (motor value 0..100) over the motors of the active frames, or
        with ``lit=True`` over the motors either side lights."""
        on = self.active()
        diff = np.abs(self.ours[on] - self.theirs[on])
        if lit:
            diff = diff[(self.ours[on] > 0) | (self.theirs[on] > 0)]
        return float(diff.mean()) if diff.size else 0.0


def compiled_values(file, position: str) -> tuple[np.ndarray, np.ndarray] | None:
    """``(times_ms, values)`` of a position's compiled frames, or None when it has none."""
    if file.compiled is None or position not in file.compiled.frames:
        return None
    times, rows = file.compiled.frames[position]
    return np.asarray(times, dtype=np.int64), np.asarray(rows, dtype=np.int64)


def kind_of(file, position: str) -> str | None:
    """``"dots"``, ``"paths"`` or ``"mixed"``: what the project holds at ``position``; None
    for nothing (or a position whose paths are single held points only, which bHaptics' frames
    leave out: they are empty in every file that has them)."""
    paths = [p for p in file.paths if p.position == position]
    moving = [p for p in paths if len(set(p.points)) > 1 or len(p.points) > 2]
    dots = any(d.position == position for d in file.dots)
    if dots and moving:
        return "mixed"
    if dots:
        return "dots" if not paths else "mixed"
    return "paths" if moving and len(moving) == len(paths) else None


def compare_compiled(file, methods=("AS",)) -> list[Comparison]:
    """This tool's frames of each position of ``file``'s project beside its compiled frames.

    Parameters
    ----------
    file : TactFile
        Read in its project form, carrying a compiled form too.
    methods : sequence of str
        The methods a position with paths is rendered by, each on the position's own motors.

    Returns
    -------
    list of Comparison
        One per position with content and compiled frames (per method for paths).
    """
    out = []
    for position in file.positions:
        kind = kind_of(file, position)
        found = compiled_values(file, position)
        places = file.layouts.get(position)
        if kind is None or found is None or not places:
            continue
        times, theirs = found
        target, order = matching_layout(places)
        if theirs.shape[1] != len(order):
            continue  # a layout of another size than the frames: nothing to compare motor by motor
        pattern = TactPattern(file, position)
        for method in methods if kind != "dots" else ("AS",):
            try:
                live = PatternFrames(pattern, method, target, Sampling(50.0), 0.0, 1.0)
            except ValueError:
                continue  # a method that does not render there
            raw = live.raw_at(times / 1e3).reshape(len(times), target.size)[:, order]
            ours = np.floor(raw * 100.0 + 1e-9).astype(np.int64)
            out.append(Comparison(position, kind, method if kind != "dots" else "", ours,
                                  np.minimum(theirs, 100)))  # fmt: skip
    return out
