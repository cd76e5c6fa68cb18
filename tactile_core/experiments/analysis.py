"""``tactile analyze``: the paper's tables and figures from a results folder.

Reads every ``participant-*/`` folder of a results folder and prints:

- Table 1 (Experiment 1): per property (quality, smoothness, thickness; each the sum of the
  line and circle ratings), Bonferroni-adjusted pairwise Wilcoxon p-values between methods.
- Experiment 2: each participant's 70.7% line length per condition (mean of the last two peaks
  and two valleys of the staircase) and the mean +- SE per condition.
- Table 2 (Experiment 3): pairwise Wilcoxon p-values of the discrimination scores (correct
  answers out of 10 per method).

and writes beside the results: ``fig6-exp1-scores.png`` (box plots), ``fig7-exp2-lengths.png``
(mean +- SE), ``fig8-exp3-scores.png`` (box plots) and ``exp2-staircases.png`` (every track
with its reversals). Only participants with complete data for an experiment enter its tests.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .results import read_rows
from .runners import CONDITIONS_EXP2, METHODS
from .staircase import Staircase
from .stats import pairwise_wilcoxon

PROPERTIES = ("quality", "smoothness", "thickness")


def participants(results_dir) -> list[Path]:
    """Participant folders, sorted by name."""
    root = Path(results_dir)
    if not root.is_dir():
        raise ValueError(f"results folder {str(root)!r} does not exist")
    return sorted(p for p in root.glob("participant-*") if p.is_dir())


def exp1_scores(results_dir) -> tuple[dict, list[str]]:
    """``{property: {method: [score per participant]}}`` (line + circle rating) and the ids."""
    scores = {p: {m: [] for m in METHODS} for p in PROPERTIES}
    ids = []
    for folder in participants(results_dir):
        rows = [r for r in read_rows(folder / "exp1.csv") if r["stage"] in ("line", "circle")]
        table = {}
        for r in rows:
            table[(r["stage"], r["property"], r["method"])] = int(r["answer"])
        if len(table) != 2 * len(PROPERTIES) * len(METHODS):
            continue  # incomplete
        ids.append(folder.name.removeprefix("participant-"))
        for prop in PROPERTIES:
            for m in METHODS:
                scores[prop][m].append(table[("line", prop, m)] + table[("circle", prop, m)])
    return scores, ids


def exp2_tracks(results_dir) -> dict:
    """``{participant: {condition: (lengths, answers)}}`` of complete Experiment 2 stages."""
    tracks = {}
    for folder in participants(results_dir):
        rows = [r for r in read_rows(folder / "exp2.csv") if r["stage"] in CONDITIONS_EXP2]
        per = {}
        for r in rows:
            per.setdefault(r["stage"], ([], []))
            per[r["stage"]][0].append(float(r["length"]))
            per[r["stage"]][1].append(r["correct"] == "1")
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


def exp2_estimates(results_dir) -> tuple[dict, list[str]]:
    """``{condition: [estimate per participant]}`` for participants with all four stages."""
    tracks = exp2_tracks(results_dir)
    out = {c: [] for c in CONDITIONS_EXP2}
    ids = []
    for pid, per in tracks.items():
        if set(per) != set(CONDITIONS_EXP2):
            continue
        ids.append(pid)
        for c in CONDITIONS_EXP2:
            out[c].append(track_estimate(*per[c])[0])
    return out, ids


def exp3_scores(results_dir) -> tuple[dict, list[str]]:
    """``{method: [correct answers out of 10 per participant]}``."""
    out = {m: [] for m in METHODS}
    ids = []
    for folder in participants(results_dir):
        rows = [r for r in read_rows(folder / "exp3.csv") if r["stage"] in METHODS]
        per = {m: [r for r in rows if r["stage"] == m] for m in METHODS}
        if any(len(v) != 10 for v in per.values()):
            continue
        ids.append(folder.name.removeprefix("participant-"))
        for m in METHODS:
            out[m].append(sum(r["correct"] == "1" for r in per[m]))
    return out, ids


def format_pvalues(table: dict, label: str = "") -> str:
    """One row of the paper's tables: the pairs' p-values to three decimals."""
    return label + "\t" + "\t".join(f"{p:.3f}" for p in table.values())


def _boxplot(ax, data: dict, ylabel: str):
    """Box plots in the paper's style: medians and quartiles; whiskers over the range within
    1.5 IQR; mild outliers (1.5-3 IQR) as 'o', extreme ones (> 3 IQR) as '*'."""
    names = list(data)
    values = [np.asarray(data[n], dtype=float) for n in names]
    ax.boxplot(values, whis=1.5, showfliers=False, widths=0.55)
    ax.set_xticks(range(1, len(names) + 1), names)
    for i, v in enumerate(values, start=1):
        if len(v) == 0:
            continue
        q1, q3 = np.percentile(v, [25, 75])
        iqr = q3 - q1
        mild = v[
            ((v < q1 - 1.5 * iqr) & (v >= q1 - 3 * iqr))
            | ((v > q3 + 1.5 * iqr) & (v <= q3 + 3 * iqr))
        ]
        extreme = v[(v < q1 - 3 * iqr) | (v > q3 + 3 * iqr)]
        ax.plot([i] * len(mild), mild, "o", mfc="none", color="k")
        ax.plot([i] * len(extreme), extreme, "*", color="k")
    ax.set_ylabel(ylabel)


def _figure(path, width=7.0, height=3.4, ncols=1):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=150, layout="constrained")
    axes = fig.subplots(1, ncols, squeeze=False)[0]
    return fig, axes


def analyze(results_dir, out=print, *, paper_rounding: bool = False) -> dict:
    """Print the tables, write the figures; return what was computed.

    ``paper_rounding`` rounds each uncorrected p to three decimals before the Bonferroni
    multiplication, as the paper's tables did (see :func:`pairwise_wilcoxon`).

    Raises
    ------
    ValueError
        If the folder does not exist or holds no participant.
    """
    root = Path(results_dir)
    folders = participants(root)
    if not folders:
        raise ValueError(f"no participant-* folders in {str(root)!r}")
    result: dict = {"participants": [f.name for f in folders]}
    out(f"{len(folders)} participant folder(s) in {root}")
    if paper_rounding:
        out("p-values: each rounded to three decimals before x 6, as the paper's tables")

    scores1, ids1 = exp1_scores(root)
    if ids1:
        out(f"\nExperiment 1 ({len(ids1)} participants with complete ratings)")
        out("Table 1. Pairwise Wilcoxon p-values, after multiplication by 6 for Bonferroni "
            "adjustment. Values below 0.05 are significant.")  # fmt: skip
        tables = {
            prop: pairwise_wilcoxon(scores1[prop], paper_rounding=paper_rounding)
            for prop in PROPERTIES
        }
        out("\t" + "\t".join(f"{a}, {b}" for a, b in tables["quality"]))
        for prop in PROPERTIES:
            out(format_pvalues(tables[prop], prop.capitalize()))
        out("medians:\t" + "\t".join(
            f"{m} " + "/".join(f"{np.median(scores1[p][m]):g}" for p in PROPERTIES) for m in METHODS
        ))  # fmt: skip
        fig, axes = _figure(root, width=9.0, ncols=3)
        for ax, prop in zip(axes, PROPERTIES):
            _boxplot(ax, scores1[prop], f"{prop} score (line + circle)")
            ax.set_ylim(-5, 205)
        fig.suptitle("Experiment 1: quality, smoothness and thickness scores")
        fig.savefig(root / "fig6-exp1-scores.png")
        result["exp1"] = {"scores": scores1, "tables": tables, "participants": ids1}

    estimates, ids2 = exp2_estimates(root)
    if ids2:
        out(f"\nExperiment 2 ({len(ids2)} participants with all four stages)")
        out("Line length (grid units) for 70.7% correct: mean of the last two peaks and valleys")
        out("condition\tmean\tSE\tmin\tmax")
        summary = {}
        for c, v in estimates.items():
            v = np.asarray(v, dtype=float)
            v = v[np.isfinite(v)]
            se = v.std(ddof=1) / np.sqrt(len(v)) if len(v) > 1 else float("nan")
            summary[c] = (float(v.mean()) if len(v) else float("nan"), float(se))
            out(
                f"{c}\t{summary[c][0]:.3f}\t{se:.3f}\t{v.min():.3f}\t{v.max():.3f}"
                if len(v)
                else f"{c}\t-"
            )
        fig, axes = _figure(root, width=5.0)
        ax = axes[0]
        names = list(summary)
        ax.errorbar(range(len(names)), [summary[c][0] for c in names],
                    yerr=[summary[c][1] for c in names], fmt="o", capsize=6, color="k")  # fmt: skip
        ax.set_xticks(range(len(names)), names)
        ax.set_xlim(-0.5, len(names) - 0.5)
        ax.set_ylabel("line length (grid units), mean +- 1 SE")
        ax.set_title("Experiment 2: shortest line for 70.7% correct")
        fig.savefig(root / "fig7-exp2-lengths.png")
        _staircase_figure(root, exp2_tracks(root))
        result["exp2"] = {"estimates": estimates, "summary": summary, "participants": ids2}

    scores3, ids3 = exp3_scores(root)
    if ids3:
        out(f"\nExperiment 3 ({len(ids3)} participants with all four sets)")
        out("Table 2. Pairwise Wilcoxon p-values, after multiplication by 6 for Bonferroni "
            "adjustment. Values below 0.05 are significant.")  # fmt: skip
        table2 = pairwise_wilcoxon(scores3, paper_rounding=paper_rounding)
        out("\t".join(f"{a}, {b}" for a, b in table2))
        out("\t".join(f"{p:.3f}" for p in table2.values()))
        out("mean correct of 10:\t" + "\t".join(f"{m} {np.mean(scores3[m]):.2f}" for m in METHODS))
        fig, axes = _figure(root, width=5.0)
        _boxplot(axes[0], scores3, "correct answers (of 10)")
        axes[0].set_ylim(-0.5, 10.5)
        axes[0].axhline(5, color="0.6", ls=":", lw=1)
        axes[0].set_title("Experiment 3: circle or square")
        fig.savefig(root / "fig8-exp3-scores.png")
        result["exp3"] = {"scores": scores3, "table": table2, "participants": ids3}
    written = sorted(p.name for p in root.glob("*.png"))
    if written:
        out(f"\nwrote {', '.join(written)} in {root}")
    return result


def _staircase_figure(root: Path, tracks: dict) -> None:
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    conditions = list(CONDITIONS_EXP2)
    fig, axes = _figure(root, width=10.0, height=3.0, ncols=len(conditions))
    for ax, c in zip(axes, conditions):
        for pid, per in tracks.items():
            if c not in per:
                continue
            lengths, answers = per[c]
            _, sc = track_estimate(lengths, answers)
            (line,) = ax.plot(range(1, len(lengths) + 1), lengths, lw=0.9, label=pid)
            ax.plot([t + 1 for t in sc.reversal_trials], sc.reversal_levels, "o", ms=3,
                    color=line.get_color())  # fmt: skip
        ax.set_title(c)
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(ScalarFormatter())
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("trial")
    axes[0].set_ylabel("line length (grid units)")
    fig.suptitle("Experiment 2 staircases (dots: reversals)")
    fig.savefig(root / "exp2-staircases.png")
