"""The report: :func:`analyze` prints the paper's tables and the statistics beyond them, one
experiment at a time, and has the figures drawn."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..runners import CONDITIONS_EXP2, METHODS, SHAPES
from ..stats import friedman, pairwise_effect_sizes, pairwise_wilcoxon
from . import _extended
from ._figures import _exp1_figure, _exp2_figure, _exp3_figure, _staircase_figure
from ._reading import Problems, check_sessions, participants, study_methods
from ._scores import (
    PROPERTIES,
    confusion,
    exp1_scores,
    exp2_estimates,
    exp2_tracks,
    exp3_answers,
    exp3_scores,
    track_estimate,
)


def format_pvalues(table: dict, label: str = "") -> str:
    """One row of the paper's tables: the pairs' p-values to three decimals.

    Parameters
    ----------
    table : dict
        ``{(a, b): p}`` (:func:`~tactile_core.experiments.stats.pairwise_wilcoxon`).
    label : str
        The row's first cell.

    Returns
    -------
    str
        Tab-separated cells.
    """
    return label + "\t" + "\t".join(f"{p:.3f}" for p in table.values())


def _omnibus_and_effects(out, scores, label=""):
    chi2, p = friedman(scores)
    shown = "< 0.0001" if p < 1e-4 else f"= {p:.4f}"
    out(f"{label}Friedman chi2({len(scores) - 1}) = {chi2:.2f}, p {shown}")
    return (chi2, p), pairwise_effect_sizes(scores)


def _pairs(methods) -> int:
    return len(methods) * (len(methods) - 1) // 2


def _say_set(out, methods, others) -> None:
    """Name a method set other than the paper's four, and who was left out for another."""
    if tuple(methods) != METHODS:
        out(f"methods: {' '.join(methods)} (orders: balanced Latin square rows)")
    if others:
        out(f"left out, another method set: {', '.join(others)}")


def analyze(results_dir, out=print, *, paper_rounding: bool = False, progress=None) -> dict:
    """Print the tables, write the figures; return what was computed.

    Parameters
    ----------
    results_dir : path
        Folder of ``participant-*`` folders; the figures are written into it.
    out : callable
        Called with each line of text (``print`` by default).
    paper_rounding : bool
        Round each uncorrected p to three decimals before the Bonferroni multiplication, as the
        paper's tables did (see :func:`~tactile_core.experiments.stats.pairwise_wilcoxon`).
    progress : callable, optional
        Called with a fraction (0..1) and a word as the analysis goes (for a progress bar).

    Returns
    -------
    dict
        ``participants`` (folder names), ``figures`` (paths written), ``problems`` (rows left
        out, ``file:row: problem``) and, per experiment with complete participants, ``exp1``
        (scores, tables, friedman, effect_sizes), ``exp2`` (estimates, summary, fits,
        fit_summary; lengths in grid units) and ``exp3`` (scores, table, friedman,
        effect_sizes, confusion), each with its ``participants`` and ``journal`` (the
        statistics beyond the paper's: :mod:`~tactile_core.experiments.analysis._extended`).

    Raises
    ------
    ValueError
        If the folder does not exist or holds no participant.
    """
    progress = progress or (lambda fraction, what: None)
    folders = participants(results_dir)  # refuses '' (not the current folder)
    root = Path(results_dir)
    if not folders:
        raise ValueError(f"no participant-* folders in {str(root)!r}")
    problems = Problems()
    check_sessions(folders, problems)
    result: dict = {"participants": [f.name for f in folders]}
    out(f"{len(folders)} participant folder(s) in {root}")
    if paper_rounding:
        out("p-values: each rounded to three decimals before x 6, as the paper's tables")

    progress(0.05, "Experiment 1")
    _experiment1(root, problems, result, out, paper_rounding)
    progress(0.3, "Experiment 2")
    _experiment2(root, problems, result, out)
    progress(0.75, "Experiment 3")
    _experiment3(root, problems, result, out, paper_rounding)
    progress(1.0, "done")
    if problems:
        out(f"\nLeft out {len(problems)} row(s) that could not be read:")
        for item in problems.items[:20]:
            out(f"  {item}")
        if len(problems) > 20:
            out(f"  ... and {len(problems) - 20} more")
    result["problems"] = list(problems.items)
    written = sorted(Path(p).name for p in result.get("figures", []))
    if written:
        out(f"\nwrote {', '.join(written)} in {root}")
    return result


def _experiment1(root: Path, problems: Problems, result: dict, out, paper_rounding: bool) -> None:
    """Table 1, the Friedman tests and effect sizes, and Figure 6 (into ``result["exp1"]``)."""
    methods1, others1 = study_methods(root, "exp1")
    scores1, ids1 = exp1_scores(root, problems, methods1)
    if ids1:
        out(f"\nExperiment 1 ({len(ids1)} participants with complete ratings)")
        _say_set(out, methods1, others1)
        out(f"Table 1. Pairwise Wilcoxon p-values, after multiplication by {_pairs(methods1)} "
            "for Bonferroni adjustment. Values below 0.05 are significant.")  # fmt: skip
        tables = {
            prop: pairwise_wilcoxon(scores1[prop], paper_rounding=paper_rounding)
            for prop in PROPERTIES
        }
        out("\t" + "\t".join(f"{a}, {b}" for a, b in tables["quality"]))
        for prop in PROPERTIES:
            out(format_pvalues(tables[prop], prop.capitalize()))
        out(f"medians ({'/'.join(PROPERTIES)}):\t" + "\t".join(
            f"{m} " + "/".join(f"{np.median(scores1[p][m]):g}" for p in PROPERTIES)
            for m in methods1
        ))  # fmt: skip
        out("Beyond the paper: Friedman omnibus tests and effect sizes r = Z / sqrt(N)")
        omnibus, effects = {}, {}
        for prop in PROPERTIES:
            omnibus[prop], effects[prop] = _omnibus_and_effects(out, scores1[prop], f"  {prop}: ")
        out("r\t" + "\t".join(f"{a}, {b}" for a, b in effects["quality"]))
        for prop in PROPERTIES:
            out(prop.capitalize() + "\t" + "\t".join(f"{r:+.2f}" for r in effects[prop].values()))
        journal = _extended.exp1(out, scores1)
        _exp1_figure(root, scores1, result)
        result["exp1"] = {"scores": scores1, "tables": tables, "participants": ids1,
                          "friedman": omnibus, "effect_sizes": effects,
                          "journal": journal}  # fmt: skip


def _experiment2(root: Path, problems: Problems, result: dict, out) -> None:
    """Each condition's 70.7% length by reversals and by fit, Figure 7 and the staircases (into
    ``result["exp2"]``).

    A group mean takes, per condition, only the participants whose track gives an estimate
    (:func:`exp2_usable`); how many contributed and who was left out, and why, are printed."""
    estimates, ids2, fits = exp2_estimates(root, problems, fits=True)
    if not ids2:
        return
    tracks = exp2_tracks(root, Problems())
    out(f"\nExperiment 2 ({len(ids2)} participants with all four stages)")
    out("Line length (grid units) for 70.7% correct. Reversals: the paper's estimate, the "
        "mean of the last two peaks and valleys (biased upward for these steps: +8-14% in the "
        "median, +11-21% in the mean at 30 trials). "
        "Fit: maximum likelihood over the whole track (logistic in log length, guess 0.25, "
        "lapse fitted), with its 95% profile-likelihood interval.")  # fmt: skip
    out("Each mean takes the participants whose track gives an estimate (n): a track with "
        "fewer than 4 reversals (one that sat at the 4-unit cap, say) has no reversal "
        "estimate, and a fit whose length lies beyond the lengths its track presented is "
        "not bounded by the data (the fitter ran to the end of its range); both are left out "
        "and listed below.")  # fmt: skip
    out("condition\tn\treversals mean\tSE\tn\tfit mean\tSE\tmin\tmax")
    summary, fit_summary, counts, excluded = {}, {}, {}, []
    by_participant, usable_fit = {}, {}
    for c in CONDITIONS_EXP2:
        rev, fit = [], []
        by_participant[c] = np.full(len(ids2), np.nan)  # NaN: left out (the tests pair by row)
        for i, pid in enumerate(ids2):
            lengths, answers = tracks[pid][c]
            why_rev, why_fit = exp2_usable(lengths, answers, estimates[c][i], fits[c][i])
            if why_rev:
                excluded.append(f"{pid} {c} reversals: {why_rev}")
            else:
                rev.append(estimates[c][i])
                by_participant[c][i] = estimates[c][i]
            if why_fit:
                excluded.append(f"{pid} {c} fit: {why_fit}")
            else:
                fit.append(fits[c][i]["threshold"])
        usable_fit[c] = [{"threshold": x} for x in fit]
        summary[c], fit_summary[c] = _mean_se(rev), _mean_se(fit)
        counts[c] = (len(rev), len(fit))
        if not rev and not fit:
            out(f"{c}\t0\t-\t-\t0\t-\t-\t-\t-\t(no participant's track gives an "
                "estimate: left out)")  # fmt: skip
            continue
        both = rev + fit
        cells = [str(len(rev)), *_cells(summary[c]), str(len(fit)), *_cells(fit_summary[c])]
        out(f"{c}\t" + "\t".join(cells) + f"\t{min(both):.3f}\t{max(both):.3f}")
    if excluded:
        out(f"left out of the means ({len(excluded)}):")
        for item in excluded:
            out(f"  {item}")
    out("per participant (reversals / fit [95% CI]):")
    for i, pid in enumerate(ids2):
        cells = []
        for c in CONDITIONS_EXP2:
            fit = fits[c][i]
            lo, hi = (f"{v:.3f}" if np.isfinite(v) else "open" for v in fit["ci"])
            rev = f"{estimates[c][i]:.3f}" if np.isfinite(estimates[c][i]) else "none"
            cells.append(f"{c} {rev} / {fit['threshold']:.3f} [{lo}, {hi}]")
        out(f"  {pid}: " + "; ".join(cells))
    journal = _extended.exp2(out, by_participant, usable_fit, participants=ids2)
    _exp2_figure(root, summary, fit_summary, result)
    _staircase_figure(root, tracks, result)
    result["exp2"] = {"estimates": estimates, "summary": summary, "participants": ids2,
                      "fits": fits, "fit_summary": fit_summary, "n": counts,
                      "excluded": excluded, "journal": journal}  # fmt: skip


def exp2_usable(lengths, answers, estimate: float, fit: dict) -> tuple[str, str]:
    """Why a track's reversal estimate and fit are left out of the group means ("" if not).

    Parameters
    ----------
    lengths, answers : sequence
        The track (:func:`exp2_tracks`).
    estimate : float
        Its reversal estimate (NaN with fewer than 4 reversals).
    fit : dict
        Its psychometric fit (:func:`~tactile_core.experiments.stats.fit_psychometric`).

    Returns
    -------
    (str, str)
        The reason for the reversal estimate and for the fit. The rules: a track with fewer than
        4 reversals has no reversal estimate; a fit whose 70.7% length lies beyond the lengths
        the track presented (longer than its longest line or shorter than its shortest) is not
        bounded by the data.
    """
    why_rev = ""
    if not np.isfinite(estimate):
        reversals = len(track_estimate(lengths, answers)[1].reversal_levels)
        at_cap = sum(1 for v in lengths if v >= 4.0 * (1 - 1e-9))
        why_rev = f"{reversals} reversal(s), 4 needed" + (
            f" ({at_cap} of {len(lengths)} trials at the 4-unit cap)" if at_cap else ""
        )
    threshold = fit["threshold"]
    why_fit = ""
    if not (np.isfinite(threshold) and min(lengths) <= threshold <= max(lengths)):
        why_fit = (f"{threshold:.3f} lies beyond the lengths presented "
                   f"({min(lengths):.3f}-{max(lengths):.3f})")  # fmt: skip
    return why_rev, why_fit


def _mean_se(values) -> tuple[float, float]:
    v = np.asarray(values, dtype=float)
    mean = float(v.mean()) if len(v) else float("nan")
    se = float(v.std(ddof=1) / np.sqrt(len(v))) if len(v) > 1 else float("nan")
    return mean, se


def _cells(mean_se) -> list[str]:
    return [f"{x:.3f}" if np.isfinite(x) else "-" for x in mean_se]


def _experiment3(root: Path, problems: Problems, result: dict, out, paper_rounding: bool) -> None:
    """Table 2, the Friedman test, effect sizes, the confusion matrix and d', and Figure 8 (into
    ``result["exp3"]``)."""
    methods3, others3 = study_methods(root, "exp3")
    answers3 = exp3_answers(root, problems, methods3)
    scores3, ids3 = exp3_scores(root, Problems(), methods3)
    if ids3:
        n3 = "four" if len(methods3) == 4 else str(len(methods3))
        out(f"\nExperiment 3 ({len(ids3)} participants with all {n3} sets)")
        _say_set(out, methods3, others3)
        out(f"Table 2. Pairwise Wilcoxon p-values, after multiplication by {_pairs(methods3)} "
            "for Bonferroni adjustment. Values below 0.05 are significant.")  # fmt: skip
        table2 = pairwise_wilcoxon(scores3, paper_rounding=paper_rounding)
        out("\t".join(f"{a}, {b}" for a, b in table2))
        out("\t".join(f"{p:.3f}" for p in table2.values()))
        out("mean correct of 10:\t" + "\t".join(f"{m} {np.mean(scores3[m]):.2f}"
                                                for m in methods3))  # fmt: skip
        out("Beyond the paper:")
        omnibus3, effects3 = _omnibus_and_effects(out, scores3, "  ")
        out("  r\t" + "\t".join(f"{a}, {b} {r:+.2f}" for (a, b), r in effects3.items()))
        conf = confusion(answers3)
        out(
            "  confusion (rows: shown; columns: answered circle / square / no answer) and "
            "d' (square as signal; mean +- SE over participants):"
        )
        for m in methods3:
            c = conf[m]["counts"]
            dp = np.array(conf[m]["d_prime"])
            se = dp.std(ddof=1) / np.sqrt(len(dp)) if len(dp) > 1 else float("nan")
            cells = [
                f"{shape}: " + " / ".join(f"{c.get((shape, a), 0):3d}"
                                          for a in ("circle", "square", None))
                for shape in SHAPES
            ]  # fmt: skip
            out(f"  {m}  " + "   ".join(cells) + f"   d' {dp.mean():+.2f} +- {se:.2f}")
        journal = _extended.exp3(out, scores3, answers3, conf)
        _exp3_figure(root, scores3, result)
        result["exp3"] = {"scores": scores3, "table": table2, "participants": ids3,
                          "friedman": omnibus3, "effect_sizes": effects3,
                          "confusion": conf, "journal": journal}  # fmt: skip
