"""What the analysis reads: the participant folders of a results folder, their CSV rows (a row
that cannot be read is reported as ``file:row: problem`` and left out), the checks each value
passes, and the method set each participant ran."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..._shared.jsonfile import read_json
from ..results import scan_rows
from ..runners import METHODS


@dataclass
class Problems:
    """Rows left out of the analysis, as ``file:row: problem``.

    ``items`` keeps the first :data:`MAX_KEPT`; ``len()`` counts them all."""

    items: list = field(default_factory=list)
    total: int = 0
    per_file: dict = field(default_factory=dict)

    def add(self, path, line: int, problem: str) -> None:
        """Report ``problem`` at ``path:line``."""
        self.total += 1
        self.per_file[str(path)] = self.per_file.get(str(path), 0) + 1
        if len(self.items) < MAX_KEPT:
            self.items.append(f"{path}:{line}: {problem}")

    def in_file(self, path) -> int:
        """How many problems ``path`` has had."""
        return self.per_file.get(str(path), 0)

    def __len__(self) -> int:
        return self.total


MAX_KEPT = 1000
"""Problems kept with their text (the rest are counted)."""


def check_sessions(folders, problems: Problems) -> None:
    """Report each ``session.json`` that exists but cannot be read (its method sets are then
    taken as the paper's four)."""
    for folder in folders:
        path = Path(folder) / "session.json"
        if os.path.lexists(path):
            try:
                read_json(path, follow_symlinks=False)
            except ValueError as exc:
                problems.add(path, 1, f"{str(exc).replace(f'{path}: ', '', 1)}; its method sets "
                             "are taken as the paper's four")  # fmt: skip


def participants(results_dir) -> list[Path]:
    """The participant folders of a results folder.

    Parameters
    ----------
    results_dir : path
        Folder holding one ``participant-<id>`` folder per participant.

    Returns
    -------
    list of Path
        The ``participant-*`` folders, sorted by name.

    Raises
    ------
    ValueError
        If ``results_dir`` is not a folder.
    """
    if not isinstance(results_dir, (str, os.PathLike)) or not str(results_dir):
        raise ValueError(f"results folder must be a folder path, got {results_dir!r}")
    root = Path(results_dir)
    if not root.is_dir():
        raise ValueError(f"results folder {str(root)!r} does not exist")
    return sorted(p for p in root.glob("participant-*") if p.is_dir())


MAX_PROBLEMS_PER_FILE = 100
"""Rows of one file that cannot be read or used before the rest of it is left out."""


def numbered_rows(path, problems: Problems):
    """Each complete row of a results CSV, with its line number, streamed.

    Parameters
    ----------
    path : path
        The CSV (a missing file has no rows). Only a regular file inside the participant's
        folder of at most :data:`~tactile_core.experiments.results.MAX_RESULTS_BYTES` is read
        (:func:`~tactile_core.experiments.results.scan_rows`); anything else is reported and
        left out.
    problems : Problems
        Where a file that cannot be read, a torn last line (no line end) or a row with the
        wrong number of fields is reported; such rows are left out. After
        :data:`MAX_PROBLEMS_PER_FILE` problems in the file (these, or those its readers
        report) the rest of the file is left out too.

    Yields
    ------
    (int, dict)
        ``(line, row)``, the line counted from 1 with the header as line 1.
    """
    path = Path(path)
    if not os.path.lexists(path):
        return
    try:
        for line, row, problem in scan_rows(path, _Unreadable):
            if problems.in_file(path) >= MAX_PROBLEMS_PER_FILE:
                problems.add(path, line, f"{problems.in_file(path)} rows cannot be used: the "
                             "rest of the file is left out")  # fmt: skip
                return
            if row is not None:
                yield line, row
            else:
                problems.add(path, line, problem)
    except _Unreadable as exc:
        problems.add(path, 1, f"cannot be read: {exc}".replace(f"{path}: ", "", 1))


class _Unreadable(ValueError):
    """A results file the analysis cannot read at all (its message names the file)."""


def _parse(path, line, problems, checks) -> dict | None:
    """Apply ``checks`` ``{name: (value, converter)}``; the converted values, or None (and a
    problem reported) at the first that fails."""
    out = {}
    for name, (value, convert) in checks.items():
        try:
            out[name] = convert(value)
        except (ValueError, TypeError) as exc:
            problems.add(path, line, f"{name} {value!r}: {exc}")
            return None
    return out


def _one_of(options):
    def convert(value):
        if value not in options:
            raise ValueError(f"not one of {', '.join(options)}")
        return value

    return convert


def _rating(value):
    number = int(value)
    if not 0 <= number <= 100:
        raise ValueError("not within 0-100")
    return number


def _flag(value):
    if value not in ("0", "1"):
        raise ValueError("not 0 or 1")
    return value == "1"


def _length(value):
    number = float(value)
    if not (np.isfinite(number) and number > 0):
        raise ValueError("not a positive length")
    return number


def session_methods(folder: Path, experiment: str) -> tuple[str, ...]:
    """The method set ``experiment`` ran for one participant.

    Parameters
    ----------
    folder : path
        The participant's folder; its ``session.json`` records the set in ``parameters``.
    experiment : str
        ``"exp1"`` or ``"exp3"``.

    Returns
    -------
    tuple of str
        The method specs; the paper's four when none is recorded or the file cannot be read.
    """
    try:
        data = read_json(Path(folder) / "session.json", follow_symlinks=False)
        recorded = data.get("parameters", {}).get(f"{experiment}_methods")
    except (ValueError, AttributeError):
        recorded = None
    if isinstance(recorded, list) and all(isinstance(m, str) for m in recorded):
        return tuple(recorded)
    return METHODS


def study_methods(results_dir, experiment: str) -> tuple[tuple[str, ...], list[str]]:
    """The method set of the study's ``experiment``, and who ran another.

    Only participants with the experiment's CSV count.

    Parameters
    ----------
    results_dir : path
    experiment : str
        ``"exp1"`` or ``"exp3"``.

    Returns
    -------
    methods : tuple of str
        The set most participants ran (the first participant's on a tie; the paper's four when
        nobody ran the experiment).
    others : list of str
        Participant ids who ran another set (left out of its analysis).
    """
    sets = {f.name.removeprefix("participant-"): session_methods(f, experiment)
            for f in participants(results_dir) if (f / f"{experiment}.csv").exists()}  # fmt: skip
    if not sets:
        return METHODS, []
    counts: dict = {}
    for s in sets.values():
        counts[s] = counts.get(s, 0) + 1
    chosen = max(counts, key=lambda s: counts[s])  # dicts keep order: the first on a tie
    return chosen, [pid for pid, s in sets.items() if s != chosen]
