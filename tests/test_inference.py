"""The statistics beyond the paper's, each cross-checked against scipy or statsmodels (or a
hand computation from the definition) on the same data; the paper's pairwise_wilcoxon keeps
its contract (tests/test_statistics.py)."""

import math

import numpy as np
import pytest
from scipy import stats

from tactile_core.experiments.inference import (
    against_chance,
    bonferroni,
    effect_sizes_with_intervals,
    exp3_mixed_model,
    holm,
    one_sample,
    pairwise_exact,
    ratings_mixed_model,
    signed_rank_exact,
)
from tactile_core.experiments.stats import pairwise_effect_sizes

EXACT = stats.PermutationMethod(n_resamples=np.inf)  # scipy enumerates all 2^n sign flips


def tied_scores(seed, n=12, k=4):
    rng = np.random.default_rng(seed)
    return {m: rng.integers(0, 8, n).astype(float) * 10 for m in "ABCD"[:k]}


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_exact_signed_rank_test_equals_scipys_permutation_test_with_ties(seed):
    s = tied_scores(seed)
    d = s["A"] - s["B"]
    nonzero = d[d != 0]
    assert len(np.unique(np.abs(nonzero))) < len(nonzero)  # ties present
    for alternative in ("two-sided", "greater", "less"):
        _, p = signed_rank_exact(d, alternative=alternative)
        ref = stats.wilcoxon(nonzero, alternative=alternative, method=EXACT).pvalue
        assert p == pytest.approx(ref, rel=1e-12)


def test_without_ties_it_is_scipys_exact_distribution():
    d = np.array([1.5, -2.0, 3.1, 4.2, 5.0, -6.3, 7.7, 8.1, 9.9, 10.4, -11.0, 12.6])
    t, p = signed_rank_exact(d)
    ref = stats.wilcoxon(d, method="exact")
    assert p == pytest.approx(ref.pvalue, rel=1e-12)
    assert t == 1 + 3 + 4 + 5 + 7 + 8 + 9 + 10 + 12  # ranks of the positive differences
    # All 12 one way: p = 2 / 2^12 (the paper's smallest Wilcoxon p, exactly).
    assert signed_rank_exact(np.arange(1, 13.0))[1] == pytest.approx(2 / 4096)


def test_holm_and_bonferroni_equal_statsmodels():
    from statsmodels.stats.multitest import multipletests

    p = np.array([0.01, 0.04, 0.03, 0.005, 0.2, 0.5])
    assert holm(p) == pytest.approx(multipletests(p, method="holm")[1])
    assert bonferroni(p) == pytest.approx(multipletests(p, method="bonferroni")[1])
    table = pairwise_exact(tied_scores(3))
    raw = [v["p"] for v in table.values()]
    assert [v["holm"] for v in table.values()] == pytest.approx(
        multipletests(raw, method="holm")[1]
    )
    assert all(v["holm"] <= v["bonferroni"] for v in table.values())


def test_effect_sizes_and_their_bootstrap_intervals():
    s = tied_scores(4)
    got = effect_sizes_with_intervals(s, n_resamples=4000)
    ref = pairwise_effect_sizes(s)
    for pair, (r, lo, hi) in got.items():
        assert r == pytest.approx(ref[pair], abs=1e-12)  # the same r as the analysis reports
        assert lo <= r <= hi
    # The interval against scipy's percentile bootstrap of the same statistic.
    from tactile_core.experiments.inference import _rank_r

    d = s["A"] - s["C"]
    boot = stats.bootstrap((d,), lambda x, axis: _rank_r(np.moveaxis(x, axis, -1)),
                           n_resamples=4000, method="percentile", rng=1)  # fmt: skip
    _, lo, hi = got[("A", "C")]
    assert lo == pytest.approx(boot.confidence_interval.low, abs=0.06)
    assert hi == pytest.approx(boot.confidence_interval.high, abs=0.06)


def test_one_sample_against_one_grid_unit():
    v = np.array([0.42, 0.55, 0.61, 0.70, 0.78, 0.80, 0.85, 0.93, 1.05, 1.12, 0.38, 0.66])
    got = one_sample(v, 1.0, alternative="less")
    t = stats.ttest_1samp(v, 1.0, alternative="less")
    assert got["t"] == pytest.approx(t.statistic) and got["p_t"] == pytest.approx(t.pvalue)
    exact = stats.wilcoxon(v - 1.0, alternative="less", method="exact").pvalue
    assert got["p_exact"] == pytest.approx(exact, rel=1e-12)
    lo, hi = got["ci"]
    half = stats.t.ppf(0.975, 11) * v.std(ddof=1) / math.sqrt(12)
    assert (lo, hi) == pytest.approx((v.mean() - half, v.mean() + half))
    assert got["d"] == pytest.approx((v.mean() - 1) / v.std(ddof=1))


def test_accuracy_against_chance():
    correct = np.array([6, 7, 5, 8, 9, 6, 7, 5, 4, 8, 7, 6])
    got = against_chance(correct, 10)
    k, n = int(correct.sum()), 120
    tail = sum(math.comb(n, j) for j in range(k, n + 1)) / 2**n  # P(X >= k), X ~ B(120, 1/2)
    assert got["p_binomial"] == pytest.approx(tail, rel=1e-9)
    nonzero = (correct - 5)[correct != 5]
    ref = stats.wilcoxon(nonzero, alternative="greater", method=EXACT).pvalue
    assert got["p_exact"] == pytest.approx(ref, rel=1e-12)


def test_the_linear_mixed_model_of_a_balanced_design_by_hand():
    # Balanced participants x conditions with participant effects: REML's fixed effects are
    # the differences of condition means, its residual variance the two-way ANOVA's residual
    # mean square, and a difference's SE sqrt(2 MS_res / n).
    rng = np.random.default_rng(5)
    n, k = 12, 4
    y = rng.normal(0, 15, (n, 1)) + np.array([100.0, 104, 118, 125]) + rng.normal(0, 8, (n, k))
    got = ratings_mixed_model({m: y[:, j] for j, m in enumerate("ABCD")})
    resid = y - y.mean(axis=1, keepdims=True) - y.mean(axis=0) + y.mean()
    ms_res = (resid**2).sum() / ((n - 1) * (k - 1))
    assert got["residual_var"] == pytest.approx(ms_res, rel=1e-4)
    ms_participant = k * ((y.mean(axis=1) - y.mean()) ** 2).sum() / (n - 1)
    assert got["participant_var"] == pytest.approx((ms_participant - ms_res) / k, rel=1e-3)
    for j, m in enumerate("BCD", start=1):
        estimate, se, _ = got["effects"][m]
        assert estimate == pytest.approx(y[:, j].mean() - y[:, 0].mean(), abs=1e-6)
        assert se == pytest.approx(math.sqrt(2 * ms_res / n), rel=1e-3)
    assert not got["boundary"] and "OrderedModel" in got["note"]


def test_the_logistic_mixed_model_is_the_intended_posterior():
    # The posterior mode statsmodels finds equals an independent maximisation (scipy) of the
    # log posterior written from the model's definition: Bernoulli log-likelihood, a random
    # intercept per participant ~ N(0, exp(v)^2), v ~ N(0, 1), fixed effects ~ N(0, 2^2).
    from scipy.optimize import minimize

    rng = np.random.default_rng(6)
    methods = ["A", "B", "C"]
    answers = {}
    for i in range(6):
        bias = rng.normal(0, 0.5)
        answers[f"p{i}"] = {
            m: [("circle", "circle" if rng.random() < 1 / (1 + math.exp(-(0.2 + j * 0.6 + bias)))
                 else "square") for _ in range(10)]
            for j, m in enumerate(methods)
        }  # fmt: skip
    got = exp3_mixed_model(answers, methods)
    y = np.array([a == "circle" for p in answers.values() for m in methods for _, a in p[m]])
    x = np.array([[1.0, m == "B", m == "C"] for _ in answers for m in methods for _ in range(10)])
    who = np.repeat(np.arange(6), 30)

    def negative(theta):
        fe, v, u = theta[:3], theta[3], theta[4:]
        eta = x @ fe + u[who]
        ll = np.sum(y * eta - np.logaddexp(0, eta))
        ll -= 0.5 * np.sum(u**2) / math.exp(2 * v) + 6 * v + 0.5 * v**2 + 0.5 * fe @ fe / 4
        return -ll

    best = minimize(negative, np.zeros(10), method="BFGS", options={"gtol": 1e-8})
    assert got["map"] == pytest.approx(best.x[:3], abs=2e-3)
    assert set(got["effects"]) == {"B", "C"} and got["participant_sd"] > 0


def test_the_mixed_models_participant_sd_is_the_posterior_mean_not_the_median():
    # statsmodels' variational posterior of the log SD is N(m, s^2): the SD is log-normal, with
    # median exp(m) and mean exp(m + s^2 / 2). 0.3 reported exp(m) as the "posterior mean".
    from statsmodels.genmod.bayes_mixed_glm import BinomialBayesMixedGLM

    rng = np.random.default_rng(3)
    methods = ["A", "B"]
    answers = {
        f"p{i}": {m: [("circle", "circle" if rng.random() < 0.5 + 0.3 * j * (i % 2) else "square")
                      for _ in range(12)] for j, m in enumerate(methods)}
        for i in range(8)
    }  # fmt: skip
    got = exp3_mixed_model(answers, methods, seed=5)
    y = np.array([a == "circle" for p in answers.values() for m in methods for _, a in p[m]])
    x = np.array([[1.0, m == "B"] for _ in answers for m in methods for _ in range(12)])
    groups = np.repeat(np.eye(8), 24, axis=0)
    fit = BinomialBayesMixedGLM(y.astype(float), x, groups, np.zeros(8, dtype=int)).fit_vb(rng=5)
    m, s = fit.vcp_mean[0], fit.vcp_sd[0]
    assert got["participant_sd_median"] == pytest.approx(math.exp(m), rel=1e-9)
    assert got["participant_sd"] == pytest.approx(math.exp(m + s * s / 2), rel=1e-9)
    assert got["participant_sd"] > got["participant_sd_median"]


def _scipy_t_quietly(values, reference, alternative):
    """scipy's one-sample t-test; on equal values it warns of catastrophic cancellation."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return stats.ttest_1samp(values, reference, alternative=alternative)


@pytest.mark.parametrize("alternative", ["less", "greater", "two-sided"])
def test_one_sample_of_equal_values_gives_scipys_t_and_says_d_is_undefined(alternative):
    """Every difference from 1 equal (before: a divide-by-zero RuntimeWarning, an error here):
    the t-test as scipy gives it (t = -inf, p 0 or 1 by the side), the signed-rank test as
    usual (all 6 below: 1/64 one-sided), the t interval and Cohen's d NaN, with the reason."""
    v = np.full(6, 0.75)
    r = one_sample(v, 1.0, alternative=alternative)
    ref = _scipy_t_quietly(v, 1.0, alternative)
    assert (r["t"], r["p_t"]) == (ref.statistic, ref.pvalue)
    assert r["p_exact"] == pytest.approx(stats.wilcoxon(v - 1.0, alternative=alternative).pvalue)
    assert all(math.isnan(x) for x in (*r["ci"], r["d"], *r["d_ci"]))
    assert "every value is 0.75" in r["note"] and "undefined" in r["note"]


def test_one_sample_at_the_reference_with_no_spread_is_nan_like_scipy():
    r = one_sample(np.ones(5), 1.0)
    ref = _scipy_t_quietly(np.ones(5), 1.0, "less")
    assert math.isnan(ref.statistic) and math.isnan(ref.pvalue)
    assert math.isnan(r["t"]) and math.isnan(r["p_t"])
    assert r["p_exact"] == 1.0  # every difference 0: nothing to rank
    assert "every value is 1" in r["note"]


def test_cohens_d_interval_leaves_out_resamples_without_spread():
    """Five values, two alike: 35/3125 (1.1%) of the resamples draw one value five times,
    whose SD is 0 (before: a divide-by-zero RuntimeWarning). Those resamples have no d and are
    left out of the percentile interval, computed here from the documented draws."""
    from tactile_core.experiments.inference import _cohens_d, bootstrap_interval

    v = np.array([0.62, 0.79, 0.79, 0.90, 1.16])
    got = bootstrap_interval(lambda rows: _cohens_d(rows, 1.0), v)
    rows = v[np.random.default_rng(0).integers(0, v.size, size=(9999, v.size))]
    defined = rows[np.ptp(rows, axis=1) > 0]
    assert 50 < len(rows) - len(defined) < 200  # 113 of 9,999 here
    d = (defined.mean(axis=1) - 1.0) / defined.std(axis=1, ddof=1)
    assert got == pytest.approx(tuple(np.quantile(d, [0.025, 0.975])), rel=1e-12)


def test_cohens_d_gets_no_interval_from_too_few_participants():
    # Four participants: resamples with nearly one value have a tiny SD and an enormous d, so
    # the percentile interval's end was meaningless (new-user pass: d -0.46 [-2245.64, +0.71]).
    v = np.array([0.62, 0.79, 0.80, 1.16])
    r = one_sample(v, 1.0)
    assert r["d"] == pytest.approx((v.mean() - 1.0) / np.std(v, ddof=1))
    assert all(math.isnan(x) for x in r["d_ci"]) and "n = 4" in r["note"]
    many = one_sample(np.linspace(0.5, 1.1, 12), 1.0)
    assert np.isfinite(many["d_ci"]).all() and many["note"] == ""
