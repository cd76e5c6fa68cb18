"""The statistics a journal asks for, beside the paper's: exact signed-rank tests with ties,
Holm beside Bonferroni, bootstrap intervals on the effect sizes, one-sample tests against a
reference (Experiment 2's 1 grid unit, Experiment 3's chance) and mixed models with a random
intercept per participant.

The paper's own test, :func:`~tactile_core.experiments.stats.pairwise_wilcoxon` (the normal
approximation without continuity correction, Bonferroni), stays as it is; these functions are
reported beside it by ``tactile analyze``.

**Exact signed-rank test.** With 12 participants the normal approximation is coarse and the
ratings tie. :func:`signed_rank_exact` drops zero differences (Wilcoxon's convention, as the
paper's test), gives tied absolute differences their mean rank, and computes the p-value from
the exact distribution of the statistic over all ``2^n`` equally likely sign assignments given
those ranks (a permutation test: exact with ties).

**Mixed models** (statsmodels). For Experiment 3's trials, a logistic model with a random
intercept per participant, ``BinomialBayesMixedGLM`` (a Bayesian model fitted by variational
Bayes: posterior means and standard deviations, not p-values). For the ratings, statsmodels
has no ordinal model with random effects (``OrderedModel`` has fixed effects only), and the
ratings, 0-100 per shape, are nearly continuous: a linear mixed model with a random intercept
per participant (``MixedLM``, REML) is fitted instead, and said so.
"""

from __future__ import annotations

import itertools
import math
import warnings

import numpy as np

ORDINAL_NOTE = (
    "no ordinal mixed model: statsmodels' OrderedModel fits cumulative-link models with fixed "
    "effects only (no random intercept per participant), and the 0-100 ratings would need a "
    "threshold per distinct value; a linear mixed model with a random intercept per "
    "participant is reported instead"
)
"""Why the ratings get a linear, not an ordinal, mixed model."""


def _signed_ranks(d):
    """Mid-ranks of ``|d|`` over the nonzero differences, and their signs."""
    from scipy.stats import rankdata

    d = np.asarray(d, dtype=np.float64)
    d = d[d != 0]
    return rankdata(np.abs(d)), np.sign(d)


def signed_rank_exact(d, *, alternative: str = "two-sided") -> tuple[float, float]:
    """Exact Wilcoxon signed-rank test of differences ``d`` against 0, ties allowed.

    Parameters
    ----------
    d : array_like of float, shape (n,)
        Paired differences (zeros are dropped), at most 60 nonzero.
    alternative : {"two-sided", "greater", "less"}
        ``"greater"``: the differences tend to be positive.

    Returns
    -------
    (float, float)
        ``T+``, the sum of the ranks of the positive differences, and its exact p-value: the
        share of the ``2^n`` sign assignments (given the mid-ranks) with a ``T+`` at least as
        extreme (two-sided: as far from its mean ``sum(r) / 2``). 1 when every difference is 0.
    """
    if alternative not in ("two-sided", "greater", "less"):
        raise ValueError(f"alternative must be two-sided, greater or less, got {alternative!r}")
    ranks, signs = _signed_ranks(d)
    if ranks.size == 0:
        return 0.0, 1.0
    if ranks.size > 60:
        raise ValueError(f"an exact test takes at most 60 nonzero differences, got {ranks.size}")
    twice = np.rint(2 * ranks).astype(np.int64)  # mid-ranks are whole or half numbers
    counts = np.zeros(int(twice.sum()) + 1)
    counts[0] = 1.0
    for r in twice:  # the distribution of 2 T+: each rank adds 0 or 2 r with probability 1/2
        shifted = np.zeros_like(counts)
        shifted[r:] = counts[:-r] if r else counts
        counts = (counts + shifted) / 2.0
    values = np.arange(counts.size)
    t2 = int(twice[signs > 0].sum())
    eps = 1e-9
    if alternative == "greater":
        p = counts[values >= t2 - eps].sum()
    elif alternative == "less":
        p = counts[values <= t2 + eps].sum()
    else:
        mean = twice.sum() / 2.0
        p = counts[np.abs(values - mean) >= abs(t2 - mean) - eps].sum()
    return t2 / 2.0, float(min(1.0, p))


def bonferroni(pvalues) -> np.ndarray:
    """Bonferroni-adjusted p-values: each times their number, capped at 1."""
    p = np.asarray(pvalues, dtype=np.float64)
    return np.minimum(1.0, p * p.size)


def holm(pvalues) -> np.ndarray:
    """Holm's step-down adjusted p-values (Holm 1979), in the order given.

    The ``i``-th smallest of ``m`` p-values is multiplied by ``m - i`` (``i`` from 0), the
    results made non-decreasing in that order and capped at 1. It controls the family-wise
    error rate as Bonferroni does and rejects at least as much.
    """
    p = np.asarray(pvalues, dtype=np.float64)
    order = np.argsort(p, kind="stable")
    m = p.size
    stepped = np.maximum.accumulate((m - np.arange(m)) * p[order])
    out = np.empty(m)
    out[order] = np.minimum(1.0, stepped)
    return out


def pairwise_exact(scores: dict) -> dict:
    """Every pair's exact signed-rank test, with Bonferroni and Holm adjustments.

    Parameters
    ----------
    scores : dict
        ``{condition: scores}``, one score per participant, same order.

    Returns
    -------
    dict
        ``{(a, b): {"T": T+, "p": exact p, "bonferroni": p, "holm": p}}`` in the order of
        :func:`~tactile_core.experiments.stats.pairwise_wilcoxon`.
    """
    data = {k: np.asarray(v, dtype=np.float64) for k, v in scores.items()}
    pairs = list(itertools.combinations(list(scores), 2))
    tests = [signed_rank_exact(data[a] - data[b]) for a, b in pairs]
    raw = [p for _, p in tests]
    bon, hol = bonferroni(raw), holm(raw)
    return {pair: {"T": t, "p": p, "bonferroni": float(b), "holm": float(h)}
            for pair, (t, p), b, h in zip(pairs, tests, bon, hol)}  # fmt: skip


def _rank_r(diffs: np.ndarray) -> np.ndarray:
    """Rosenthal's ``r = Z / sqrt(N)`` of each row of paired differences ``(B, N)``: ``Z`` the
    signed-rank statistic's normal deviate with mid-ranks and zeros dropped (its variance
    ``sum r_i^2 / 4`` is the tie-corrected one), ``N`` the participants."""
    from scipy.stats import rankdata

    d = np.atleast_2d(diffs)
    nonzero = d != 0
    ranks = rankdata(np.where(nonzero, np.abs(d), np.inf), axis=1)
    ranks = np.where(nonzero, ranks, 0.0)
    t_plus = (ranks * (d > 0)).sum(axis=1)
    var = (ranks**2).sum(axis=1) / 4.0
    with np.errstate(invalid="ignore", divide="ignore"):
        z = (t_plus - ranks.sum(axis=1) / 2.0) / np.sqrt(var)
    return np.where(var > 0, z, 0.0) / math.sqrt(d.shape[1])


def bootstrap_interval(statistic, data, *, n_resamples: int = 9999, level: float = 0.95,
                       seed: int = 0) -> tuple[float, float]:  # fmt: skip
    """Percentile bootstrap interval of ``statistic`` over participants.

    Parameters
    ----------
    statistic : callable
        Maps an array of resampled rows ``(B, n, ...)`` to ``(B,)`` values.
    data : array_like, shape (n, ...)
        One row per participant; rows are resampled with replacement.
    n_resamples, level, seed
        Resamples, coverage, and the seed of the draws.

    Returns
    -------
    (float, float)
        The ``(1 - level) / 2`` and ``(1 + level) / 2`` quantiles of the resampled statistic.
        Resamples where it is undefined (NaN: Cohen's ``d`` of a resample that drew one value
        ``n`` times) are left out; NaN, NaN if every one is.
    """
    x = np.asarray(data, dtype=np.float64)
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, x.shape[0], size=(n_resamples, x.shape[0]))
    values = np.asarray(statistic(x[idx]), dtype=np.float64)
    values = values[~np.isnan(values)]
    if values.size == 0:
        return math.nan, math.nan
    alpha = (1.0 - level) / 2.0
    lo, hi = np.quantile(values, [alpha, 1.0 - alpha])
    return float(lo), float(hi)


def effect_sizes_with_intervals(scores: dict, **bootstrap) -> dict:
    """Each pair's ``r = Z / sqrt(N)`` (as
    :func:`~tactile_core.experiments.stats.pairwise_effect_sizes`) with a 95% percentile
    bootstrap interval over participants: ``{(a, b): (r, low, high)}``."""
    data = {k: np.asarray(v, dtype=np.float64) for k, v in scores.items()}
    out = {}
    for a, b in itertools.combinations(list(scores), 2):
        d = data[a] - data[b]
        r = float(_rank_r(d)[0])
        out[(a, b)] = (r, *bootstrap_interval(lambda rows: _rank_r(rows), d, **bootstrap))
    return out


def mean_with_interval(values, **bootstrap) -> tuple[float, float, float]:
    """The mean of ``values`` and its 95% percentile bootstrap interval."""
    v = np.asarray(values, dtype=np.float64)
    return (float(v.mean()),
            *bootstrap_interval(lambda rows: rows.mean(axis=1), v, **bootstrap))  # fmt: skip


MIN_BOOTSTRAP_N = 10
"""Fewest values a bootstrap interval of Cohen's ``d`` is given for. Below it too many resamples
draw nearly one value ``n`` times: their SD is tiny and their ``d`` enormous, so the interval's
ends say nothing (four participants gave ``d -0.46 [-2245.64, +0.71]``)."""


def _cohens_d(rows: np.ndarray, reference: float) -> np.ndarray:
    """Cohen's ``(mean - reference) / SD`` of each row of ``rows`` ``(B, n)``; NaN for a row
    whose values are all equal (no SD: ``d`` is undefined)."""
    spread = np.ptp(rows, axis=1) > 0
    sd = np.where(spread, rows.std(axis=1, ddof=1), 1.0)
    return np.where(spread, (rows.mean(axis=1) - reference) / sd, np.nan)


def one_sample(values, reference: float, *, alternative: str = "less") -> dict:
    """Tests of ``values`` (one per participant) against ``reference``.

    Parameters
    ----------
    values : array_like of float, shape (n,)
        One value per participant (non-finite ones are dropped), at least 2.
    reference : float
        The value tested against (Experiment 2: 1 grid unit).
    alternative : {"less", "greater", "two-sided"}
        The direction of the one-sided tests.

    Returns
    -------
    dict
        ``n``, ``median``, ``mean``, ``ci`` (the mean's 95% t interval), ``t`` and ``p_t``
        (one-sample t-test), ``T`` and ``p_exact`` (:func:`signed_rank_exact` of
        ``values - reference``), ``d`` (Cohen's ``(mean - reference) / SD``) with its
        bootstrap interval ``d_ci``; one-sided in the direction ``alternative``. ``note``: why
        some of them are undefined ("" when none is).

    Notes
    -----
    When every value is equal (SD 0) the t statistic divides by zero. ``t`` and ``p_t`` are
    then what scipy's ``ttest_1samp`` gives for the same input: ``t = +-inf`` with ``p`` 0 in
    the direction of the difference and 1 against it, and NaN for both when every value
    equals ``reference``. The t interval and Cohen's ``d`` and its interval, which need an SD,
    are NaN, and ``note`` says why. The exact signed-rank test is defined and reported as
    usual. Bootstrap resamples that draw one value ``n`` times have no SD either; they are
    left out of ``d``'s interval (:func:`bootstrap_interval`). With fewer than
    :data:`MIN_BOOTSTRAP_N` values ``d_ci`` is NaN, NaN and ``note`` says so.
    """
    from scipy import stats

    v = np.asarray(values, dtype=np.float64)
    v = v[np.isfinite(v)]
    mean = float(v.mean())
    w, p_exact = signed_rank_exact(v - reference, alternative=alternative)
    if np.ptp(v) == 0:  # no spread: everything that divides by the SD is undefined
        diff = mean - reference
        t = math.copysign(math.inf, diff) if diff else math.nan
        toward = {"less": diff < 0, "greater": diff > 0, "two-sided": True}[alternative]
        p_t = math.nan if not diff else (0.0 if toward else 1.0)
        ci = d_ci = (math.nan, math.nan)
        d = math.nan
        note = (f"every value is {v[0]:g} (SD 0): the t interval and Cohen's d are undefined, "
                "and t is infinite (NaN at the reference) as scipy gives it")  # fmt: skip
    else:
        result = stats.ttest_1samp(v, reference, alternative=alternative)
        t, p_t = float(result.statistic), float(result.pvalue)
        ci = stats.t.interval(0.95, v.size - 1, loc=mean, scale=stats.sem(v))
        d = float(_cohens_d(v[None, :], reference)[0])
        if v.size >= MIN_BOOTSTRAP_N:
            d_ci = bootstrap_interval(lambda rows: _cohens_d(rows, reference), v)
            note = ""
        else:
            d_ci = (math.nan, math.nan)
            note = (f"n = {v.size}: too few for a bootstrap interval of Cohen's d "
                    f"(at least {MIN_BOOTSTRAP_N})")  # fmt: skip
    return {"n": int(v.size), "median": float(np.median(v)), "mean": mean,
            "ci": (float(ci[0]), float(ci[1])), "t": t, "p_t": p_t, "T": w,
            "p_exact": p_exact, "d": d, "d_ci": d_ci, "note": note}  # fmt: skip


def against_chance(correct, trials: int, chance: float = 0.5) -> dict:
    """Accuracy against chance: per participant ``correct`` of ``trials``.

    Returns
    -------
    dict
        ``correct`` and ``total`` pooled, ``p_binomial`` (exact one-sided binomial test of the
        pooled count; it treats the trials as independent, which they are not across
        participants), ``T`` and ``p_exact`` (:func:`signed_rank_exact` of the per-participant
        scores against ``chance x trials``, one-sided: the test that respects participants),
        ``mean`` and its bootstrap ``ci``.
    """
    from scipy.stats import binomtest

    c = np.asarray(correct, dtype=np.int64)
    total = int(trials * c.size)
    p_binomial = binomtest(int(c.sum()), total, chance, alternative="greater").pvalue
    w, p_exact = signed_rank_exact(c - chance * trials, alternative="greater")
    mean, lo, hi = mean_with_interval(c)
    return {"correct": int(c.sum()), "total": total, "p_binomial": float(p_binomial),
            "T": w, "p_exact": p_exact, "mean": mean, "ci": (lo, hi)}  # fmt: skip


def ratings_mixed_model(scores: dict) -> dict:
    """A linear mixed model of scores: a fixed effect per condition (treatment coding against
    the first), a random intercept per participant (statsmodels ``MixedLM``, REML).

    Returns
    -------
    dict
        ``{"effects": {condition: (estimate, SE, p)} for all but the first,
        "participant_var", "residual_var", "boundary": the participant variance fitted at 0,
        "note": ORDINAL_NOTE}``.
    """
    import pandas as pd
    from statsmodels.regression.mixed_linear_model import MixedLM

    names = list(scores)
    rows = [(str(i), m, float(v)) for m in names for i, v in enumerate(scores[m])]
    df = pd.DataFrame(rows, columns=["participant", "condition", "score"])
    exog = pd.get_dummies(df["condition"]).reindex(columns=names).astype(float)
    exog[names[0]] = 1.0  # the intercept: the first condition's mean
    with warnings.catch_warnings(record=True) as caught:
        # A participant variance estimated at 0 (its boundary) is a result, not an error: the
        # fit says so in "boundary".
        warnings.simplefilter("always")
        fit = MixedLM(df["score"], exog, groups=df["participant"]).fit(reml=True)
    effects = {m: (float(fit.params[m]), float(fit.bse[m]), float(fit.pvalues[m]))
               for m in names[1:]}  # fmt: skip
    boundary = any("boundary" in str(w.message) or "singular" in str(w.message).lower()
                   for w in caught)  # fmt: skip
    return {"effects": effects, "participant_var": float(fit.cov_re.iloc[0, 0]),
            "residual_var": float(fit.scale), "boundary": boundary,
            "note": ORDINAL_NOTE}  # fmt: skip


def exp3_mixed_model(answers: dict, methods, *, seed: int = 0) -> dict:
    """A logistic model of Experiment 3's answers with a random intercept per participant
    (statsmodels ``BinomialBayesMixedGLM``, variational Bayes).

    Parameters
    ----------
    answers : dict
        ``{participant: {method: [(shape, answer), ...]}}``
        (:func:`~tactile_core.experiments.analysis.exp3_answers`).
    methods : sequence of str
        The first is the reference.
    seed : int
        Seeds the random effects' starting values (statsmodels draws them).

    Returns
    -------
    dict
        ``{"effects": {method: (posterior mean, posterior SD)} of the log-odds of a right
        answer against the first method, "intercept": (mean, SD), "participant_sd": posterior
        mean of the participants' SD (log-odds), "participant_sd_median": its posterior median,
        "map": the posterior mode of the fixed effects (``fit_map``), intercept first,
        "converged": False when an optimiser warned}``.

    Notes
    -----
    statsmodels' variational posterior of the participants' log SD is normal, ``N(m, s^2)``, so
    their SD is log-normal: ``exp(m)`` is its median and ``exp(m + s^2 / 2)`` its mean (0.3 reported
    ``exp(m)`` and called it the mean).
    """
    import pandas as pd
    from statsmodels.genmod.bayes_mixed_glm import BinomialBayesMixedGLM

    methods = list(methods)
    rows = [(str(pid), m, int(shape == answer)) for pid, per in answers.items()
            for m in methods for shape, answer in per[m]]  # fmt: skip
    df = pd.DataFrame(rows, columns=["participant", "method", "correct"])
    exog = pd.get_dummies(df["method"]).reindex(columns=methods).astype(float)
    exog[methods[0]] = 1.0
    groups = pd.get_dummies(df["participant"]).astype(float)
    model = BinomialBayesMixedGLM(df["correct"].to_numpy(float), exog.to_numpy(),
                                  groups.to_numpy(), np.zeros(groups.shape[1], dtype=int),
                                  fep_names=methods, vcp_names=["participant"])  # fmt: skip
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = model.fit_vb(rng=seed)
        mode = model.fit_map(rng=seed, minim_opts={"gtol": 1e-6}).fe_mean
    mean, sd = fit.fe_mean, fit.fe_sd
    effects = {m: (float(mean[i]), float(sd[i])) for i, m in enumerate(methods) if i}
    return {"effects": effects, "intercept": (float(mean[0]), float(sd[0])),
            "participant_sd": float(np.exp(fit.vcp_mean[0] + fit.vcp_sd[0] ** 2 / 2)),
            "participant_sd_median": float(np.exp(fit.vcp_mean[0])),
            "map": tuple(float(v) for v in mode), "converged": not caught}  # fmt: skip
