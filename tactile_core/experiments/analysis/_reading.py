"""What the analysis reads: the participant folders of a results folder, their CSV rows (a row
that cannot be read is reported as ``file:row: problem`` and left out), and from them each
experiment's scores, staircase tracks and answers."""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..runners import CONDITIONS_EXP2, METHODS, SHAPES
from ..staircase import Staircase
from ..stats import d_prime, fit_psychometric

PROPERTIES = ("quality", "smoothness", "thickness")


@dataclass
class Problems:
    """Rows left out of the analysis, as ``file:row: problem``."""

    items: list = field(default_factory=list)

    def add(self, path, line: int, problem: str) -> None:
        self.items.append(f"{path}:{line}: {problem}")

    def __len__(self) -> int:
        return len(self.items)


def participants(results_dir) -> list[Path]:
    """Participant folders, sorted by name."""
    root = Path(results_dir)
    if not root.is_dir():
        raise ValueError(f"results folder {str(root)!r} does not exist")
    return sorted(p for p in root.glob("participant-*") if p.is_dir())


def numbered_rows(path, problems: Problems) -> list[tuple[int, dict]]:
    """``(line, row)`` of each complete row of a results CSV (a torn last line is reported and
    left out)."""
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
    """The method set ``experiment`` ran for the participant in ``folder`` (``session.json``'s
    ``parameters``); the paper's four when none is recorded or the file cannot be read."""
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
    """The method set of the study's ``experiment``: the set most participants ran (the first
    participant's on a tie; the paper's four by default), and the participants who ran another
    set (left out of its analysis). Only participants with the experiment's CSV count."""
    sets = {f.name.removeprefix("participant-"): session_methods(f, experiment)
            for f in participants(results_dir) if (f / f"{experiment}.csv").exists()}  # fmt: skip
    if not sets:
        return METHODS, []
    counts: dict = {}
    for s in sets.values():
        counts[s] = counts.get(s, 0) + 1
    chosen = max(counts, key=lambda s: counts[s])  # dicts keep order: the first on a tie
    return chosen, [pid for pid, s in sets.items() if s != chosen]


def exp1_scores(results_dir, problems: Problems | None = None, methods=None):
    """``({property: {method: [score per participant]}}, ids)``: line + circle ratings of the
    participants who ran ``methods`` (default: :func:`study_methods`)."""
    problems = problems if problems is not None else Problems()
    methods = tuple(methods) if methods is not None else study_methods(results_dir, "exp1")[0]
    scores = {p: {m: [] for m in methods} for p in PROPERTIES}
    ids = []
    for folder in participants(results_dir):
        if session_methods(folder, "exp1") != methods:
            continue
        path = folder / "exp1.csv"
        table = {}
        for line, r in numbered_rows(path, problems):
            if r.get("stage") not in ("line", "circle"):
                continue
            got = _parse(path, line, problems, {
                "property": (r["property"], _one_of(PROPERTIES)),
                "method": (r["method"], _one_of(methods)),
                "answer": (r["answer"], _rating),
            })  # fmt: skip
            if got is None:
                continue
            key = (r["stage"], got["property"], got["method"])
            if key in table:
                problems.add(path, line, f"duplicate rating of {' '.join(key)} (the first kept)")
                continue
            table[key] = got["answer"]
        if len(table) != 2 * len(PROPERTIES) * len(methods):
            continue  # incomplete
        ids.append(folder.name.removeprefix("participant-"))
        for prop in PROPERTIES:
            for m in methods:
                scores[prop][m].append(table[("line", prop, m)] + table[("circle", prop, m)])
    return scores, ids


def exp2_tracks(results_dir, problems: Problems | None = None) -> dict:
    """``{participant: {condition: (lengths, answers)}}`` of complete Experiment 2 stages."""
    problems = problems if problems is not None else Problems()
    tracks = {}
    for folder in participants(results_dir):
        path = folder / "exp2.csv"
        per: dict = {}
        for line, r in numbered_rows(path, problems):
            if r.get("stage") not in CONDITIONS_EXP2:
                continue
            got = _parse(path, line, problems, {
                "trial": (r["trial"], int),
                "length": (r["length"], _length),
                "correct": (r["correct"], _flag),
            })  # fmt: skip
            if got is None:
                continue
            lengths, answers = per.setdefault(r["stage"], ([], []))
            if got["trial"] != len(lengths):
                problems.add(path, line, f"trial {got['trial']} out of order in {r['stage']}")
                continue
            lengths.append(got["length"])
            answers.append(got["correct"])
        complete = {c: v for c, v in per.items() if len(v[0]) >= 30}
        if complete:
            tracks[folder.name.removeprefix("participant-")] = complete
    return tracks


def track_estimate(lengths, answers, n: int = 4) -> tuple[float, Staircase]:
    """Replay a recorded track through the paper's staircase; its estimate (NaN if too few
    reversals) and the staircase."""
    sc = Staircase(lengths[0], 0.685, 1.46, 2, 1, min_level=0.01, max_level=4.0)
    for answer in answers:
        sc.update(answer)
    try:
        return sc.estimate(n), sc
    except ValueError:
        return float("nan"), sc


def exp2_estimates(results_dir, problems: Problems | None = None, *, fits: bool = False):
    """``({condition: [estimate per participant]}, ids)`` for participants with all four
    stages; with ``fits`` also ``{condition: [fit dict per participant]}``."""
    tracks = exp2_tracks(results_dir, problems)
    out = {c: [] for c in CONDITIONS_EXP2}
    fitted = {c: [] for c in CONDITIONS_EXP2}
    ids = []
    for pid, per in tracks.items():
        if set(per) != set(CONDITIONS_EXP2):
            continue
        ids.append(pid)
        for c in CONDITIONS_EXP2:
            out[c].append(track_estimate(*per[c])[0])
            if fits:
                fitted[c].append(fit_psychometric(*per[c]))
    return (out, ids, fitted) if fits else (out, ids)


def exp3_answers(results_dir, problems: Problems | None = None, methods=None) -> dict:
    """``{participant: {method: [(shape, answer or None), ...]}}`` of complete sets, for the
    participants who ran ``methods`` (default: :func:`study_methods`)."""
    problems = problems if problems is not None else Problems()
    methods = tuple(methods) if methods is not None else study_methods(results_dir, "exp3")[0]
    out = {}
    for folder in participants(results_dir):
        if session_methods(folder, "exp3") != methods:
            continue
        path = folder / "exp3.csv"
        per = {m: [] for m in methods}
        for line, r in numbered_rows(path, problems):
            if r.get("stage") not in methods:
                continue
            got = _parse(path, line, problems, {
                "shape": (r["shape"], _one_of(SHAPES)),
                "answer": (r["answer"], _one_of((*SHAPES, ""))),
            })  # fmt: skip
            if got is None:
                continue
            per[r["stage"]].append((got["shape"], got["answer"] or None))
        if all(len(v) == 10 for v in per.values()):
            out[folder.name.removeprefix("participant-")] = per
        else:
            for m, v in per.items():
                if len(v) > 10:
                    problems.add(path, 0, f"{len(v)} answers for {m}, a set has 10")
    return out


def exp3_scores(results_dir, problems: Problems | None = None, methods=None):
    """``({method: [correct answers out of 10 per participant]}, ids)``."""
    methods = tuple(methods) if methods is not None else study_methods(results_dir, "exp3")[0]
    answers = exp3_answers(results_dir, problems, methods)
    out = {m: [] for m in methods}
    for per in answers.values():
        for m in methods:
            out[m].append(sum(shape == answer for shape, answer in per[m]))
    return out, list(answers)


def confusion(answers: dict) -> dict:
    """Per method, the pooled counts ``{(shape, answer): n}`` (answer ``None``: timed out)
    and each participant's d' (square as the signal; a timeout counts as a miss or a
    correct rejection, i.e. not "square")."""
    out = {}
    methods = next(iter(answers.values())).keys() if answers else METHODS
    for m in methods:
        counts: dict = {}
        dprimes = []
        for per in answers.values():
            trials = per[m]
            for shape, answer in trials:
                counts[(shape, answer)] = counts.get((shape, answer), 0) + 1
            squares = [a for s, a in trials if s == "square"]
            circles = [a for s, a in trials if s == "circle"]
            dprimes.append(d_prime(squares.count("square"), len(squares),
                                   circles.count("square"), len(circles)))  # fmt: skip
        out[m] = {"counts": counts, "d_prime": dprimes}
    return out
