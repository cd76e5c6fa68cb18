"""Experiments' arithmetic: the staircase, the simulated psychometric function, the paper's
statistics (Wilcoxon with its rounding, Friedman, effect sizes, d', the ML fit) and its
counterbalanced orders."""

import math
import random

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.experiments import Psychometric
from tactile_core.experiments.stats import apply_order, assign_orders

# --- staircase ---------------------------------------------------------------------------


def test_staircase_two_down_one_up_worked_by_hand():
    sc = tc.Staircase(start=2.0, down=0.685, up=1.46, n_down=2, n_up=1)
    assert sc.level == 2.0
    assert sc.update(True) == 2.0  # one correct: stay
    assert sc.update(True) == pytest.approx(1.37)  # two correct: x 0.685
    assert sc.update(False) == pytest.approx(1.37 * 1.46)  # wrong: x 1.46; a valley at 1.37
    assert sc.reversal_levels == [pytest.approx(1.37)]
    assert sc.update(True) == pytest.approx(2.0002)
    assert sc.update(False) == pytest.approx(2.0002 * 1.46)  # the correct run is broken
    # going up twice in a row is no reversal
    assert sc.reversal_levels == [pytest.approx(1.37)]
    sc.update(True)
    sc.update(True)  # down: a peak at 2.0002 * 1.46
    assert sc.reversal_levels[-1] == pytest.approx(2.0002 * 1.46)
    sc.update(False)  # up: a valley
    sc.update(True)
    sc.update(True)  # down: a peak
    levels = sc.reversal_levels
    assert len(levels) == 4
    assert sc.estimate(4) == pytest.approx(sum(levels) / 4)
    assert sc.estimate(2) == pytest.approx(sum(levels[-2:]) / 2)


def test_staircase_estimate_needs_enough_reversals_and_checks_arguments():
    sc = tc.Staircase()
    with pytest.raises(ValueError, match="reversals"):
        sc.estimate(4)
    for kwargs, word in [({"start": 0}, "start"), ({"down": 1.2}, "down"), ({"up": 0.9}, "up"),
                         ({"n_down": 0}, "n_down")]:  # fmt: skip
        with pytest.raises(ValueError, match=word):
            tc.Staircase(**kwargs)
    with pytest.raises(ValueError, match="correct"):
        sc.update("yes")


def test_staircase_is_clipped_to_its_bounds():
    sc = tc.Staircase(start=2.0, max_level=4.0)
    for _ in range(5):
        sc.update(False)
    assert sc.level == 4.0


def test_staircase_accepts_numpy_booleans_and_0_or_1():
    sc = tc.Staircase()
    sc.update(np.True_)
    sc.update(1)
    assert sc.level == pytest.approx(1.37)
    for bad in (2, 0.5, "yes", None):
        with pytest.raises(ValueError, match="correct"):
            sc.update(bad)


def test_psychometric_function():
    f = Psychometric(midpoint=0.8, slope=4.0)
    assert f.p_correct(1e-9) == pytest.approx(0.25, abs=1e-6)  # guessing
    assert f.p_correct(1e9) == pytest.approx(0.98, abs=1e-6)  # 1 - lapse
    assert f.p_correct(0.8) == pytest.approx(0.25 + 0.73 / 2)
    length = f.length_at(0.707)
    assert f.p_correct(length) == pytest.approx(0.707)


def test_staircase_converges_near_the_70_7_percent_point():
    rng = np.random.default_rng(5)
    f = Psychometric(midpoint=0.6, slope=4.0)
    target = f.length_at(0.707)
    estimates = []
    for _ in range(300):
        sc = tc.Staircase(2.0, 0.685, 1.46, 2, 1)
        for _ in range(80):
            sc.update(rng.random() < f.p_correct(sc.level))
        estimates.append(sc.estimate(4))
    median = float(np.median(estimates))
    assert median == pytest.approx(target, rel=0.10), (median, target)
    # the track really depends on the participant: a far easier observer converges lower
    easy = Psychometric(midpoint=0.2, slope=4.0)
    sc = tc.Staircase(2.0, 0.685, 1.46, 2, 1)
    for _ in range(80):
        sc.update(rng.random() < easy.p_correct(sc.level))
    assert sc.estimate(4) < 0.5 * target


# --- statistics --------------------------------------------------------------------------


def normal_p(z):
    return math.erfc(abs(z) / math.sqrt(2))


def test_wilcoxon_without_ties_by_hand():
    # 12 participants all better under X, no tied differences: W+ = 78, mean 39,
    # variance n(n+1)(2n+1)/24 = 162.5.
    x = np.arange(1, 13) + 10.0
    y = np.zeros(12)
    p = tc.pairwise_wilcoxon({"X": x, "Y": y})[("X", "Y")]
    assert p == pytest.approx(normal_p((78 - 39) / math.sqrt(162.5)), rel=1e-9)


def test_paper_rounding_reproduces_the_papers_0012():
    # 12 of 12 with one sign (no ties): p = erfc(39 / sqrt(162.5) / sqrt 2) = 0.002222;
    # x 6 = 0.01333 prints as 0.013. The paper rounded p to 0.002 first: x 6 = 0.012, the value
    # its Tables 1 and 2 show for every such pair.
    x, y = np.arange(1, 13) + 10.0, np.zeros(12)
    raw = normal_p(39 / math.sqrt(162.5))
    assert round(raw, 4) == 0.0022
    scores = {"CT": x, "MM": y, "AS": y, "IM": y}  # six pairs: x 6
    assert f"{tc.pairwise_wilcoxon(scores)[('CT', 'MM')]:.3f}" == "0.013"
    p = tc.pairwise_wilcoxon(scores, paper_rounding=True)[("CT", "MM")]
    assert p == pytest.approx(0.012, abs=1e-15)


def test_wilcoxon_with_ties_and_a_zero_by_hand():
    # differences 1,1,2,2,3,...,10 and one zero (dropped): n = 12, average ranks for the
    # ties, variance 162.5 - sum(t^3 - t)/48 = 162.5 - 12/48.
    d = np.array([1, 1, 2, 2, 3, 4, 5, 6, 7, 8, 9, 10, 0], dtype=float)
    p = tc.pairwise_wilcoxon({"X": d, "Y": np.zeros(13)}, correction="none")[("X", "Y")]
    assert p == pytest.approx(normal_p((78 - 39) / math.sqrt(162.5 - 12 / 48)), rel=1e-9)


def test_wilcoxon_mixed_signs_by_hand():
    # differences +5, -1, +3, +2, -4, +6: ranks 5, 1, 3, 2, 4, 6; W+ = 5+3+2+6 = 16; n = 6,
    # mean 10.5, variance 6*7*13/24 = 22.75.
    x = np.array([5, 0, 3, 2, 0, 6], dtype=float)
    y = np.array([0, 1, 0, 0, 4, 0], dtype=float)
    p = tc.pairwise_wilcoxon({"A": x, "B": y}, correction="none")[("A", "B")]
    assert p == pytest.approx(normal_p((16 - 10.5) / math.sqrt(22.75)), rel=1e-9)


def test_pairwise_wilcoxon_layout_and_bonferroni():
    rng = np.random.default_rng(0)
    scores = {m: rng.normal(50, 10, 12) for m in ("CT", "MM", "AS", "IM")}
    scores["AS"] += 40
    adjusted = tc.pairwise_wilcoxon(scores)
    raw = tc.pairwise_wilcoxon(scores, correction="none")
    assert list(adjusted) == [
        ("CT", "MM"),
        ("CT", "AS"),
        ("CT", "IM"),
        ("MM", "AS"),
        ("MM", "IM"),
        ("AS", "IM"),
    ]
    for pair in adjusted:
        assert adjusted[pair] == pytest.approx(min(1.0, 6 * raw[pair]))
    assert tc.pairwise_wilcoxon({"A": [1, 2, 3], "B": [1, 2, 3]})[("A", "B")] == 1.0
    with pytest.raises(ValueError, match="same number"):
        tc.pairwise_wilcoxon({"A": [1, 2], "B": [1, 2, 3]})


def test_orders_are_the_papers():
    assert tc.ORDERS == ("ABCD", "DCBA", "ACBD", "DBCA", "BADC", "CDAB",
                         "BDAC", "CADB", "ADBC", "CBDA", "BCAD", "DACB")  # fmt: skip
    assert len(set(tc.ORDERS)) == 12 and all(sorted(o) == list("ABCD") for o in tc.ORDERS)
    # each condition appears in each position three times (counterbalanced)
    for position in range(4):
        assert sorted(o[position] for o in tc.ORDERS) == sorted("ABCD" * 3)
    given = assign_orders([f"p{i}" for i in range(12)], seed=3)
    assert sorted(given.values()) == sorted(tc.ORDERS)  # no two share an order
    assert apply_order("CADB", ["CT", "MM", "AS", "IM"]) == ["AS", "CT", "IM", "MM"]


def test_psychometric_fit_recovers_a_known_threshold():
    from tactile_core.experiments.stats import fit_psychometric

    psy = Psychometric(0.5, 6.0)
    rng = random.Random(4)
    lengths = [math.exp(rng.uniform(-2.5, 1.0)) for _ in range(400)]
    correct = [rng.random() < psy.p_correct(length) for length in lengths]
    fit = fit_psychometric(lengths, correct)
    assert fit["threshold"] == pytest.approx(psy.length_at(0.707), rel=0.1)
    lo, hi = fit["ci"]
    assert lo < psy.length_at(0.707) < hi


def test_friedman_effect_sizes_and_d_prime_by_hand():
    from tactile_core.experiments.stats import d_prime, friedman, pairwise_effect_sizes

    # Three conditions, four participants, always ranked A < B < C: ranks 1, 2, 3 each time.
    # chi2 = 12 / (n k (k + 1)) * sum R^2 - 3 n (k + 1) = 12/48 * (16 + 64 + 144) - 48 = 8.
    chi2, p = friedman({"A": [1, 2, 3, 4], "B": [2, 3, 4, 5], "C": [3, 4, 5, 6]})
    assert chi2 == pytest.approx(8.0) and p == pytest.approx(math.exp(-4.0))  # chi2(2) tail
    # 12 of 12 with one sign: Z = 39 / sqrt(162.5) = 3.059, r = Z / sqrt(12) = 0.883.
    r = pairwise_effect_sizes({"X": np.arange(1, 13) + 10.0, "Y": np.zeros(12)})
    assert r[("X", "Y")] == pytest.approx(39 / math.sqrt(162.5) / math.sqrt(12))
    # 5 of 5 hits, 0 of 5 false alarms: H = 5.5/6, F = 0.5/6 -> d' = 2 * 1.3830 = 2.766.
    assert d_prime(5, 5, 0, 5) == pytest.approx(2 * 1.3830, abs=1e-3)


def test_the_psychometric_fit_finds_the_maximum_a_brute_force_search_finds():
    """The fit (with its analytic gradient) against a dense grid over all three parameters,
    the likelihood written out independently."""
    from tactile_core.experiments.stats import fit_psychometric

    psy = Psychometric(0.7, 4.0)
    rng = random.Random(11)
    lengths = [math.exp(rng.uniform(-1.5, 0.8)) for _ in range(60)]
    correct = np.array([rng.random() < psy.p_correct(length) for length in lengths])
    fit = fit_psychometric(lengths, correct)
    x = np.log(lengths)
    best = -np.inf
    for lapse in np.linspace(0.0, 0.06, 13):
        q = (0.707 - 0.25) / (0.75 - lapse)  # p(T) = 0.707 exactly at the threshold
        c = math.log(q / (1 - q))
        log_t = np.linspace(-1.5, 0.8, 231)[:, None, None]
        slope = np.geomspace(0.2, 50.0, 241)[None, :, None]
        p = 0.25 + (0.75 - lapse) / (1 + np.exp(-(slope * (x - log_t) + c)))
        p = np.clip(p, 1e-9, 1 - 1e-9)
        ll = np.where(correct, np.log(p), np.log1p(-p)).sum(axis=-1)
        best = max(best, ll.max())
    assert fit["log_likelihood"] >= best - 1e-9  # at least as good as any grid point
    assert fit["log_likelihood"] <= best + 0.05  # and the grid comes close to it
