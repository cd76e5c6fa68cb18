"""Each experiment's data from a results folder: Experiment 1's scores, Experiment 2's staircase
tracks and their estimates, Experiment 3's answers, scores and confusion matrix."""

from __future__ import annotations

from ..runners import CONDITIONS_EXP2, METHODS, SHAPES
from ..staircase import Staircase
from ..stats import d_prime, fit_psychometric
from ._reading import (
    Problems,
    _flag,
    _length,
    _one_of,
    _parse,
    _rating,
    numbered_rows,
    participants,
    session_methods,
    study_methods,
)

PROPERTIES = ("quality", "smoothness", "thickness")


def exp1_scores(results_dir, problems: Problems | None = None, methods=None):
    """Experiment 1's scores: each property's line + circle rating per method.

    Parameters
    ----------
    results_dir : path
    problems : Problems, optional
        Where unreadable or duplicate rows are reported.
    methods : sequence of str, optional
        The set analysed (default: :func:`study_methods`); participants who ran another are
        left out, as are those without every rating.

    Returns
    -------
    scores : dict
        ``{property: {method: [score per participant]}}``, each score 0-200.
    ids : list of str
        The participants, in the order of the scores.
    """
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
    """Experiment 2's staircase tracks, for the stages with all 30 answers.

    Parameters
    ----------
    results_dir : path
    problems : Problems, optional
        Where unreadable or out-of-order rows are reported.

    Returns
    -------
    dict
        ``{participant: {condition: (lengths, answers)}}``: the line length of each trial (grid
        units) and whether it was answered right.
    """
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
    """Replay a recorded track through the paper's staircase.

    Parameters
    ----------
    lengths : sequence of float
        Line length of each trial, grid units (the first is the start).
    answers : sequence of bool
        Whether each was answered right.
    n : int
        Reversals averaged (the paper: the last two peaks and two valleys).

    Returns
    -------
    estimate : float
        Line length for 70.7% correct, grid units; NaN with fewer than ``n`` reversals.
    staircase : Staircase
        The replayed staircase (its reversals, for the figure).
    """
    sc = Staircase(lengths[0], 0.685, 1.46, 2, 1, min_level=0.01, max_level=4.0)
    for answer in answers:
        sc.update(answer)
    try:
        return sc.estimate(n), sc
    except ValueError:
        return float("nan"), sc


def exp2_estimates(results_dir, problems: Problems | None = None, *, fits: bool = False):
    """Experiment 2's 70.7% line lengths, for the participants with all four stages.

    Parameters
    ----------
    results_dir : path
    problems : Problems, optional
    fits : bool
        Also fit a psychometric function to each whole track
        (:func:`~tactile_core.experiments.stats.fit_psychometric`).

    Returns
    -------
    estimates : dict
        ``{condition: [estimate per participant]}``, grid units (:func:`track_estimate`).
    ids : list of str
    fitted : dict
        Only with ``fits``: ``{condition: [fit dict per participant]}``.
    """
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
    """Experiment 3's answers, for the participants with all ten answers for every method.

    Parameters
    ----------
    results_dir : path
    problems : Problems, optional
    methods : sequence of str, optional
        The set analysed (default: :func:`study_methods`).

    Returns
    -------
    dict
        ``{participant: {method: [(shape, answer), ...]}}``, ``answer`` None for a timeout.
    """
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
    """Experiment 3's discrimination scores.

    Parameters
    ----------
    results_dir : path
    problems : Problems, optional
    methods : sequence of str, optional
        The set analysed (default: :func:`study_methods`).

    Returns
    -------
    scores : dict
        ``{method: [correct answers out of 10 per participant]}``.
    ids : list of str
    """
    methods = tuple(methods) if methods is not None else study_methods(results_dir, "exp3")[0]
    answers = exp3_answers(results_dir, problems, methods)
    out = {m: [] for m in methods}
    for per in answers.values():
        for m in methods:
            out[m].append(sum(shape == answer for shape, answer in per[m]))
    return out, list(answers)


def confusion(answers: dict) -> dict:
    """Experiment 3's confusion matrix and d' per method.

    Parameters
    ----------
    answers : dict
        ``{participant: {method: [(shape, answer), ...]}}`` (:func:`exp3_answers`).

    Returns
    -------
    dict
        ``{method: {"counts": {(shape, answer): n}, "d_prime": [d' per participant]}}``: the
        counts pooled over participants (answer None: timed out); d' takes the square as the
        signal, and a timeout counts as a miss or a correct rejection (not "square").
    """
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
