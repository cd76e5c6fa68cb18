"""The statistics a journal asks for, printed after each experiment's own tables: exact
signed-rank tests with Holm beside Bonferroni, bootstrap intervals on the effect sizes,
Experiment 2's thresholds against 1 grid unit, Experiment 3's accuracy against chance, and the
mixed models (:mod:`tactile_core.experiments.inference`)."""

from __future__ import annotations

import numpy as np

from .. import inference
from ..stats import friedman


def _p(p: float) -> str:
    return "<0.0001" if p < 1e-4 else f"{p:.4f}"


def _pairwise(out, scores, label: str) -> dict:
    exact = inference.pairwise_exact(scores)
    effects = inference.effect_sizes_with_intervals(scores)
    out(f"  {label}exact signed-rank p (raw / Bonferroni / Holm); r [95% bootstrap CI]:")
    for pair, e in exact.items():
        r, lo, hi = effects[pair]
        out(f"    {pair[0]}, {pair[1]}\t{_p(e['p'])} / {_p(e['bonferroni'])} / "
            f"{_p(e['holm'])}\tr {r:+.2f} [{lo:+.2f}, {hi:+.2f}]")  # fmt: skip
    return {"exact": exact, "effect_intervals": effects}


def _mixed(out, model) -> None:
    for m, (estimate, se, p) in model["effects"].items():
        out(f"    {m}\t{estimate:+.1f} (SE {se:.1f}, p {_p(p)})")
    boundary = " (at its boundary, 0)" if model["boundary"] else ""
    out(f"    participant SD {np.sqrt(model['participant_var']):.1f}{boundary}, residual SD "
        f"{np.sqrt(model['residual_var']):.1f}; {model['note']}")  # fmt: skip


def exp1(out, scores: dict) -> dict:
    """Experiment 1: per property the exact pairwise tests, r with intervals, and a linear
    mixed model of the scores (random intercept per participant)."""
    out("Journal statistics (exact tests with ties, Holm, bootstrap intervals, mixed models):")
    result = {}
    for prop, per in scores.items():
        result[prop] = _pairwise(out, per, f"{prop}: ")
        model = inference.ratings_mixed_model(per)
        out(f"  {prop}: linear mixed model, difference from {next(iter(per))} (score points):")
        _mixed(out, model)
        result[prop]["mixed_model"] = model
    return result


def exp2(out, estimates: dict, fits: dict, participants=None) -> dict:
    """Experiment 2: each condition's threshold against 1 grid unit (one-sided: shorter), by
    the reversal estimate and by the fit (the estimates the group means took), and the
    conditions compared over the participants with an estimate in every condition.

    Parameters
    ----------
    out : callable
        Called with each line of text.
    estimates : dict
        ``{condition: reversal estimates}``, each of shape ``(n_participants,)`` in the same
        participant order, NaN where a participant's track is left out.
    fits : dict
        ``{condition: [fit, ...]}``, the fits the group means took (``"threshold"`` each).
    participants : sequence of str, optional
        The participants' names in the order of ``estimates`` (to say who is left out).

    Returns
    -------
    dict
        ``against_1``: ``{(estimate, condition): one_sample result}``; with 3 or more
        conditions and 2 or more participants with every condition, ``across``: the Friedman
        test and the exact pairwise tests over those participants (``participants``: their
        names), rows paired by participant.
    """
    out("Journal statistics: each condition against 1 grid unit (one-sided, shorter; t-test, "
        "exact signed-rank, Cohen's d [95% bootstrap CI]):")  # fmt: skip
    result = {"against_1": {}}
    table = {c: np.asarray(v, dtype=float) for c, v in estimates.items()}
    usable = {c: v[np.isfinite(v)] for c, v in table.items()}
    fitted = {c: [f["threshold"] for f in fits[c]] for c in fits}
    for name, per in (("reversals", usable), ("fit", fitted)):
        for c, values in per.items():
            if len(values) < 2:  # left out of the means (the report lists why)
                out(f"  {c} {name}\t(fewer than 2 estimates: no test)")
                continue
            r = inference.one_sample(values, 1.0, alternative="less")
            result["against_1"][(name, c)] = r
            lo, hi = r["ci"]
            note = f"\t({r['note']})" if r["note"] else ""
            d_lo, d_hi = r["d_ci"]
            d_ci = "" if np.isnan(d_lo) else f" [{d_lo:+.2f}, {d_hi:+.2f}]"
            out(f"  {c} {name}\tmean {r['mean']:.3f} [{lo:.3f}, {hi:.3f}]\tt p {_p(r['p_t'])}"
                f"\texact p {_p(r['p_exact'])}\td {r['d']:+.2f}{d_ci}{note}")  # fmt: skip
    if len(table) >= 3:
        _across(out, table, participants, result)
    return result


def _across(out, table: dict, participants, result: dict) -> None:
    """Friedman and the pairwise tests over the participants with every condition (complete
    cases): a participant left out of one condition is left out of all, so that every row is
    one person's."""
    rows = np.stack(list(table.values()), axis=1)  # (participants, conditions)
    complete = np.isfinite(rows).all(axis=1)
    names = list(participants) if participants is not None else [
        f"#{i + 1}" for i in range(len(rows))
    ]  # fmt: skip
    kept = [n for n, ok in zip(names, complete) if ok]
    lacking = [n for n, ok in zip(names, complete) if not ok]
    if len(kept) < 2:
        out(f"  across conditions (reversals): {len(kept)} participant(s) with every "
            "condition's estimate: no test")  # fmt: skip
        return
    paired = {c: rows[complete, i] for i, c in enumerate(table)}
    who = f"{len(kept)} of {len(names)} participants"
    if lacking:
        who += f" ({', '.join(lacking)} lack a condition)"
    chi2, p = friedman(paired)
    out(f"  across conditions (reversals, {who}): Friedman chi2({len(paired) - 1}) = "
        f"{chi2:.2f}, p {_p(p)}")  # fmt: skip
    result["across"] = {"friedman": (chi2, p), "participants": kept,
                        **_pairwise(out, paired, "")}  # fmt: skip


def exp3(out, scores: dict, answers: dict, confusion: dict) -> dict:
    """Experiment 3: accuracy against chance per method, the exact pairwise tests with r and
    intervals, d' with intervals, and the logistic mixed model of the answers."""
    out("Journal statistics:")
    out("  against chance (5 of 10): pooled exact binomial p (trials taken as independent) / "
        "exact signed-rank p over participants, one-sided; mean [95% bootstrap CI]:")  # fmt: skip
    result = {"chance": {}}
    for m, values in scores.items():
        r = inference.against_chance(values, 10)
        result["chance"][m] = r
        out(f"    {m}\t{r['correct']}/{r['total']}\t{_p(r['p_binomial'])} / {_p(r['p_exact'])}"
            f"\t{r['mean']:.2f} [{r['ci'][0]:.2f}, {r['ci'][1]:.2f}]")  # fmt: skip
    result.update(_pairwise(out, scores, ""))
    out("  d' mean [95% bootstrap CI]: " + "  ".join(
        f"{m} {mean:+.2f} [{lo:+.2f}, {hi:+.2f}]"
        for m, (mean, lo, hi) in ((m, inference.mean_with_interval(confusion[m]["d_prime"]))
                                  for m in scores)
    ))  # fmt: skip
    model = inference.exp3_mixed_model(answers, list(scores))
    result["mixed_model"] = model
    first = next(iter(scores))
    out(f"  logistic mixed model (variational Bayes, statsmodels), log-odds of a right answer "
        f"against {first}, posterior mean (SD):")  # fmt: skip
    out("    " + "  ".join(f"{m} {mean:+.2f} ({sd:.2f})"
                          for m, (mean, sd) in model["effects"].items()))  # fmt: skip
    note = "" if model["converged"] else " (an optimiser did not converge fully)"
    out(f"    participant SD {model['participant_sd']:.2f} (log-odds; posterior mean, median "
        f"{model['participant_sd_median']:.2f}){note}")  # fmt: skip
    return result
