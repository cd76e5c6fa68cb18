"""What the analysis reads: the participant folders of a results folder, their CSV rows (a row
that cannot be read is reported as ``file:row: problem`` and left out), the checks each value
passes, and the method set each participant ran."""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..runners import METHODS


@dataclass
class Problems:
    """Rows left out of the analysis, as ``file:row: problem``."""

    items: list = field(default_factory=list)

    def add(self, path, line: int, problem: str) -> None:
        self.items.append(f"{path}:{line}: {problem}")

    def __len__(self) -> int:
        return len(self.items)


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
    root = Path(results_dir)
    if not root.is_dir():
        raise ValueError(f"results folder {str(root)!r} does not exist")
    return sorted(p for p in root.glob("participant-*") if p.is_dir())


def numbered_rows(path, problems: Problems) -> list[tuple[int, dict]]:
    """Each complete row of a results CSV, with its line number.

    Parameters
    ----------
    path : path
        The CSV (a missing file has no rows).
    problems : Problems
        Where a file that cannot be read, a torn last line (no line end) or a row with the
        wrong number of fields is reported; such rows are left out.

    Returns
    -------
    list of (int, dict)
        ``(line, row)``, the line counted from 1 with the header as line 1.
    """
    path = Path(path)
    if not path.exists():
        return []
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        problems.add(path, 1, f"cannot be read: {exc}")
        return []
    if text and not text.endswith("\n"):
        problems.add(path, text.count("\n") + 1, "torn last row (no line end)")
        text = text[: text.rfind("\n") + 1]
    reader = csv.DictReader(io.StringIO(text))
    out = []
    for row in reader:
        if None in row or None in row.values():
            problems.add(path, reader.line_num, "wrong number of fields")
            continue
        out.append((reader.line_num, row))
    return out


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
    import json

    try:
        with open(Path(folder) / "session.json", encoding="utf-8") as f:
            recorded = json.load(f).get("parameters", {}).get(f"{experiment}_methods")
    except (OSError, ValueError, AttributeError):
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
