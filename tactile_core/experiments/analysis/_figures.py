"""The analysis's figures, each written beside the results as a PNG (matplotlib, no display):
the paper's Figures 6-8 and every Experiment 2 staircase."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..runners import CONDITIONS_EXP2
from ._scores import PROPERTIES, track_estimate


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


def _figure(width=7.0, height=3.4, ncols=1):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=150, layout="constrained")
    axes = fig.subplots(1, ncols, squeeze=False)[0]
    return fig, axes


def _save(fig, path: Path, result: dict) -> None:
    from ..._shared.outfile import atomic_file

    with atomic_file(path, binary=True) as f:
        fig.savefig(f, format="png")
    result.setdefault("figures", []).append(str(path))


def _exp1_figure(root: Path, scores: dict, result: dict) -> None:
    """Figure 6, ``fig6-exp1-scores.png``: box plots of each property's scores per method.

    ``scores`` is ``{property: {method: [score per participant]}}`` (line + circle ratings,
    0-200); the figure's path is added to ``result["figures"]``.
    """
    fig, axes = _figure(width=9.0, ncols=3)
    for ax, prop in zip(axes, PROPERTIES):
        _boxplot(ax, scores[prop], f"{prop} score (line + circle)")
        ax.set_ylim(-5, 205)
    fig.suptitle("Experiment 1: quality, smoothness and thickness scores")
    _save(fig, root / "fig6-exp1-scores.png", result)


def _exp2_figure(root: Path, summary: dict, fit_summary: dict, result: dict) -> None:
    """Figure 7, ``fig7-exp2-lengths.png``: each condition's 70.7% line length (grid units),
    mean +- 1 SE, by the paper's reversals and by the ML fit.

    ``summary`` and ``fit_summary`` are ``{condition: (mean, SE)}``.
    """
    fig, axes = _figure(width=5.0)
    ax = axes[0]
    names = list(summary)
    xs = np.arange(len(names))
    ax.errorbar(xs - 0.08, [summary[c][0] for c in names],
                yerr=[summary[c][1] for c in names], fmt="o", capsize=6, color="k",
                label="reversals (paper)")  # fmt: skip
    ax.errorbar(xs + 0.08, [fit_summary[c][0] for c in names],
                yerr=[fit_summary[c][1] for c in names], fmt="s", capsize=6,
                color="0.45", mfc="none", label="ML fit")  # fmt: skip
    ax.set_xticks(xs, names)
    ax.set_xlim(-0.5, len(names) - 0.5)
    ax.set_ylabel("line length (grid units), mean +- 1 SE")
    ax.set_title("Experiment 2: shortest line for 70.7% correct")
    ax.legend(fontsize=7, frameon=False)
    _save(fig, root / "fig7-exp2-lengths.png", result)


def _exp3_figure(root: Path, scores: dict, result: dict) -> None:
    """Figure 8, ``fig8-exp3-scores.png``: box plots of the correct answers (of 10) per method.

    ``scores`` is ``{method: [correct answers per participant]}``.
    """
    fig, axes = _figure(width=5.0)
    _boxplot(axes[0], scores, "correct answers (of 10)")
    axes[0].set_ylim(-0.5, 10.5)
    axes[0].axhline(5, color="0.6", ls=":", lw=1)
    axes[0].set_title("Experiment 3: circle or square")
    _save(fig, root / "fig8-exp3-scores.png", result)


def _staircase_figure(root: Path, tracks: dict, result: dict) -> None:
    """``exp2-staircases.png``: every Experiment 2 track (line length per trial, log scale),
    one panel per condition, its reversals as dots.

    ``tracks`` is ``{participant: {condition: (lengths, answers)}}``.
    """
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    conditions = list(CONDITIONS_EXP2)
    fig, axes = _figure(width=10.0, height=3.0, ncols=len(conditions))
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
    _save(fig, root / "exp2-staircases.png", result)
