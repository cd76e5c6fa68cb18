"""``tactile analyze``: the paper's tables and figures from a results folder, and more.

Reads every ``participant-*/`` folder of a results folder and prints:

- Table 1 (Experiment 1): per property (quality, smoothness, thickness; each the sum of the
  line and circle ratings), Bonferroni-adjusted pairwise Wilcoxon p-values between methods,
  with a Friedman omnibus test before them and effect sizes ``r = Z / sqrt(N)`` beside them.
- Experiment 2: each participant's 70.7% line length per condition by the paper's estimate (the
  mean of the last two peaks and two valleys of the staircase) and by a maximum-likelihood fit
  of a psychometric function to the whole track (with a 95% confidence interval), and the mean
  +- SE per condition of both. The reversal estimate is biased upward by 8-15% for the paper's
  steps (see the README's staircase table); the fit is not.
- Table 2 (Experiment 3): pairwise Wilcoxon p-values of the discrimination scores (correct
  answers out of 10 per method), the Friedman test and effect sizes, the confusion matrix and
  d' per method.

and writes beside the results: ``fig6-exp1-scores.png`` (box plots), ``fig7-exp2-lengths.png``
(mean +- SE), ``fig8-exp3-scores.png`` (box plots) and ``exp2-staircases.png`` (every track
with its reversals). Only participants with complete data for an experiment enter its tests.

A row that cannot be read (a bad number, an unknown method, a duplicate) is reported as
``file:row: problem`` and left out; the rest is analysed, and the output says what was left out.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .runners import CONDITIONS_EXP2, METHODS, SHAPES
from .staircase import Staircase
from .stats import d_prime, fit_psychometric, friedman, pairwise_effect_sizes, pairwise_wilcoxon

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


def _figure(width=7.0, height=3.4, ncols=1):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=150, layout="constrained")
    axes = fig.subplots(1, ncols, squeeze=False)[0]
    return fig, axes


def _save(fig, path: Path, result: dict) -> None:
    from .._shared.outfile import atomic_file

    with atomic_file(path, binary=True) as f:
        fig.savefig(f, format="png")
    result.setdefault("figures", []).append(str(path))


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

    ``paper_rounding`` rounds each uncorrected p to three decimals before the Bonferroni
    multiplication, as the paper's tables did (see :func:`pairwise_wilcoxon`). ``progress`` is
    called with a fraction (0..1) and a word as the analysis goes (for a progress bar).

    Raises
    ------
    ValueError
        If the folder does not exist or holds no participant.
    """
    progress = progress or (lambda fraction, what: None)
    root = Path(results_dir)
    folders = participants(root)
    if not folders:
        raise ValueError(f"no participant-* folders in {str(root)!r}")
    problems = Problems()
    result: dict = {"participants": [f.name for f in folders]}
    out(f"{len(folders)} participant folder(s) in {root}")
    if paper_rounding:
        out("p-values: each rounded to three decimals before x 6, as the paper's tables")

    progress(0.05, "Experiment 1")
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
        out("medians:\t" + "\t".join(
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
        fig, axes = _figure(width=9.0, ncols=3)
        for ax, prop in zip(axes, PROPERTIES):
            _boxplot(ax, scores1[prop], f"{prop} score (line + circle)")
            ax.set_ylim(-5, 205)
        fig.suptitle("Experiment 1: quality, smoothness and thickness scores")
        _save(fig, root / "fig6-exp1-scores.png", result)
        result["exp1"] = {"scores": scores1, "tables": tables, "participants": ids1,
                          "friedman": omnibus, "effect_sizes": effects}  # fmt: skip

    progress(0.3, "Experiment 2")
    estimates, ids2, fits = exp2_estimates(root, problems, fits=True)
    if ids2:
        out(f"\nExperiment 2 ({len(ids2)} participants with all four stages)")
        out("Line length (grid units) for 70.7% correct. Reversals: the paper's estimate, the "
            "mean of the last two peaks and valleys (biased upward by 8-15% for these steps). "
            "Fit: maximum likelihood over the whole track (logistic in log length, guess 0.25, "
            "lapse fitted), with its 95% profile-likelihood interval.")  # fmt: skip
        out("condition\treversals mean\tSE\tfit mean\tSE\tmin\tmax")
        summary, fit_summary = {}, {}
        for c in CONDITIONS_EXP2:
            v = np.asarray(estimates[c], dtype=float)
            v = v[np.isfinite(v)]
            f = np.array([x["threshold"] for x in fits[c]])
            se = v.std(ddof=1) / np.sqrt(len(v)) if len(v) > 1 else float("nan")
            fse = f.std(ddof=1) / np.sqrt(len(f)) if len(f) > 1 else float("nan")
            summary[c] = (float(v.mean()) if len(v) else float("nan"), float(se))
            fit_summary[c] = (float(f.mean()), float(fse))
            out(f"{c}\t{summary[c][0]:.3f}\t{se:.3f}\t{f.mean():.3f}\t{fse:.3f}\t"
                f"{min(v.min(), f.min()):.3f}\t{max(v.max(), f.max()):.3f}")  # fmt: skip
        out("per participant (reversals / fit [95% CI]):")
        for i, pid in enumerate(ids2):
            cells = []
            for c in CONDITIONS_EXP2:
                fit = fits[c][i]
                lo, hi = (f"{v:.3f}" if np.isfinite(v) else "open" for v in fit["ci"])
                cells.append(f"{c} {estimates[c][i]:.3f} / {fit['threshold']:.3f} [{lo}, {hi}]")
            out(f"  {pid}: " + "; ".join(cells))
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
        _staircase_figure(root, exp2_tracks(root, Problems()), result)
        result["exp2"] = {"estimates": estimates, "summary": summary, "participants": ids2,
                          "fits": fits, "fit_summary": fit_summary}  # fmt: skip

    progress(0.75, "Experiment 3")
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
        fig, axes = _figure(width=5.0)
        _boxplot(axes[0], scores3, "correct answers (of 10)")
        axes[0].set_ylim(-0.5, 10.5)
        axes[0].axhline(5, color="0.6", ls=":", lw=1)
        axes[0].set_title("Experiment 3: circle or square")
        _save(fig, root / "fig8-exp3-scores.png", result)
        result["exp3"] = {"scores": scores3, "table": table2, "participants": ids3,
                          "friedman": omnibus3, "effect_sizes": effects3,
                          "confusion": conf}  # fmt: skip
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


def _staircase_figure(root: Path, tracks: dict, result: dict) -> None:
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
