"""Statistics and counterbalancing as in the paper (sections 3.1, 4.1, 4.3)."""

from __future__ import annotations

import itertools
import math
import random

import numpy as np

ORDERS = (
    "ABCD", "DCBA", "ACBD", "DBCA", "BADC", "CDAB",
    "BDAC", "CADB", "ADBC", "CBDA", "BCAD", "DACB",
)  # fmt: skip
"""The paper's 12 counterbalanced orders of four conditions A-D, in the paper's order."""


def assign_orders(participants, seed: int = 0) -> dict:
    """Give each participant an order from :data:`ORDERS`, no two the same.

    The orders are shuffled once with ``seed`` and dealt out in the participants' order; past
    12 participants the shuffled list is dealt again (the paper had exactly 12).

    Parameters
    ----------
    participants : sequence of str
        Participant identifiers in the order they were recruited.
    seed : int

    Returns
    -------
    dict
        ``{participant: order}``.
    """
    orders = list(ORDERS)
    random.Random(seed).shuffle(orders)
    return {p: orders[i % len(orders)] for i, p in enumerate(participants)}


def order_for(index: int, seed: int = 0) -> str:
    """The order of the ``index``-th participant (0-based) under :func:`assign_orders`."""
    orders = list(ORDERS)
    random.Random(seed).shuffle(orders)
    return orders[index % len(orders)]


def williams_orders(n: int) -> tuple[str, ...]:
    """A balanced Latin square of ``n`` conditions (Williams 1949), as orders of letters.

    Every condition appears once in every position, and follows every other condition equally
    often: ``n`` orders for even ``n``, ``2n`` for odd ``n`` (the square and its mirror image).
    Row ``i`` is ``(first + i) mod n`` with ``first = 0, 1, n-1, 2, n-2, ...``.

    Parameters
    ----------
    n : int
        2 to 26 conditions (letters A onwards).
    """
    if not isinstance(n, int) or not 2 <= n <= 26:
        raise ValueError(f"a balanced Latin square needs 2 to 26 conditions, got {n!r}")
    first, lo, hi = [0], 1, n - 1
    while len(first) < n:
        first.append(lo)
        lo += 1
        if len(first) < n:
            first.append(hi)
            hi -= 1
    rows = [[(c + i) % n for c in first] for i in range(n)]
    if n % 2:
        rows += [row[::-1] for row in rows]
    return tuple("".join(chr(ord("A") + c) for c in row) for row in rows)


def order_for_set(index: int, n: int, seed: int = 0) -> str:
    """The order of the ``index``-th participant (0-based) for a set of ``n`` conditions other
    than the paper's four: the rows of :func:`williams_orders`, shuffled once with ``seed`` and
    dealt out in recruitment order (a multiple of ``n`` participants, ``2n`` for odd ``n``,
    completes the square)."""
    orders = list(williams_orders(n))
    random.Random(seed).shuffle(orders)
    return orders[index % len(orders)]


def apply_order(order: str, conditions) -> list:
    """Conditions in the order given by letters A-D (A = the first condition)."""
    conditions = list(conditions)
    if sorted(order) != [chr(ord("A") + i) for i in range(len(conditions))]:
        last = chr(ord("A") + len(conditions) - 1)
        raise ValueError(f"order must be a permutation of A..{last}, got {order!r}")
    return [conditions[ord(letter) - ord("A")] for letter in order]


def pairwise_wilcoxon(
    scores: dict, *, correction: str = "bonferroni", paper_rounding: bool = False
) -> dict:
    """Pairwise two-sided Wilcoxon signed-rank tests on paired scores, Bonferroni-adjusted.

    Parameters
    ----------
    scores : dict
        ``{condition: scores}``, each a sequence with one score per participant, in the same
        participant order.
    correction : {"bonferroni", "none"}
        Multiply each p by the number of pairs and cap at 1 (the paper), or not.
    paper_rounding : bool
        Round each uncorrected p to three decimals before the multiplication, as the paper's
        tables were made (its statistics package printed three decimals, which the authors
        multiplied by 6: every value in its Tables 1 and 2 is a multiple of 0.006). With
        12 participants whose differences all have one sign, p = 0.00222 gives 0.013 exactly
        and 0.012 with this rounding, the paper's value.

    Returns
    -------
    dict
        ``{(a, b): p}`` for each pair in the order of ``scores`` (CT/MM, CT/AS, ...).

    Notes
    -----
    As the paper's statistics package reported it: the normal approximation of the signed-rank
    statistic, ties in the ranks given average ranks and corrected for in the variance, zero
    differences dropped, no continuity correction. Pairs whose differences are all zero get
    p = 1.
    """
    from scipy import stats

    names = list(scores)
    data = {k: np.asarray(v, dtype=np.float64) for k, v in scores.items()}
    lengths = {len(v) for v in data.values()}
    if len(lengths) != 1:
        raise ValueError(
            f"scores must have the same number of participants per condition, got {sorted(lengths)}"
        )
    pairs = list(itertools.combinations(names, 2))
    out = {}
    for a, b in pairs:
        diff = data[a] - data[b]
        if not np.any(diff != 0):
            p = 1.0
        else:
            result = stats.wilcoxon(
                data[a], data[b], zero_method="wilcox", correction=False,
                alternative="two-sided", method="approx",
            )  # fmt: skip
            p = float(result.pvalue)
        if paper_rounding:
            p = math.floor(p * 1000.0 + 0.5) / 1000.0
        if correction == "bonferroni":
            p = min(1.0, p * len(pairs))
        elif correction != "none":
            raise ValueError(f"correction must be 'bonferroni' or 'none', got {correction!r}")
        out[(a, b)] = p
    return out


def pairwise_effect_sizes(scores: dict) -> dict:
    """Effect size ``r = Z / sqrt(N)`` of each pairwise Wilcoxon test (Rosenthal's r).

    ``Z`` is the normal approximation of the signed-rank statistic as in
    :func:`pairwise_wilcoxon` (ties corrected, zeros dropped, no continuity correction), signed so
    that ``r > 0`` when the first of the pair scores higher; ``N`` is the number of paired
    observations (participants). About 0.1 is small, 0.3 medium, 0.5 large.

    Returns
    -------
    dict
        ``{(a, b): r}`` in the order of :func:`pairwise_wilcoxon`; 0 for identical scores.
    """
    from scipy import stats

    data = {k: np.asarray(v, dtype=np.float64) for k, v in scores.items()}
    out = {}
    for a, b in itertools.combinations(list(scores), 2):
        diff = data[a] - data[b]
        n = len(diff)
        if not np.any(diff != 0):
            out[(a, b)] = 0.0
            continue
        result = stats.wilcoxon(
            data[a], data[b], zero_method="wilcox", correction=False, method="approx"
        )
        nonzero = diff[diff != 0]
        ranks = stats.rankdata(np.abs(nonzero))
        direction = np.sign(np.sum(np.sign(nonzero) * ranks))
        out[(a, b)] = float(direction * abs(result.zstatistic) / math.sqrt(n))
    return out


def friedman(scores: dict) -> tuple[float, float]:
    """Friedman's omnibus test over the conditions of ``scores`` (paired, one score per
    participant and condition): ``(chi-square, p)``; ``(0, 1)`` when every score is equal."""
    from scipy import stats

    data = [np.asarray(v, dtype=np.float64) for v in scores.values()]
    if len(data) < 3:
        raise ValueError(f"scores must hold at least 3 conditions, got {len(data)}")
    if all(np.array_equal(data[0], d) for d in data[1:]) and np.ptp(np.stack(data)) == 0:
        return 0.0, 1.0
    result = stats.friedmanchisquare(*data)
    if not np.isfinite(result.pvalue):
        return 0.0, 1.0
    return float(result.statistic), float(result.pvalue)


def d_prime(hits: int, signal: int, false_alarms: int, noise: int) -> float:
    """Sensitivity ``d' = z(H) - z(F)`` with the log-linear correction (Hautus 1995): 0.5 is
    added to the hits and false alarms and 1 to each count of trials, so that perfect or empty
    cells give finite values. Experiment 3 takes "square" as the signal."""
    from scipy.stats import norm

    h = (hits + 0.5) / (signal + 1.0)
    f = (false_alarms + 0.5) / (noise + 1.0)
    return float(norm.ppf(h) - norm.ppf(f))


def _psychometric_nll_grid(x, y, log_t, slopes, lapses, guess, target) -> np.ndarray:
    """The negative log-likelihood of :func:`fit_psychometric` on a grid:
    shape ``(len(log_t), len(slopes), len(lapses))``."""
    span = 1.0 - guess - lapses  # (L,)
    q = (target - guess) / span
    c = np.log(q / (1.0 - q))
    z = slopes[None, :, None, None] * (x[None, None, None, :] - log_t[:, None, None, None])
    z = z + c[None, None, :, None]
    with np.errstate(over="ignore"):  # exp(-z) = inf gives p = guess, as it should
        p = guess + span[None, None, :, None] / (1.0 + np.exp(-z))
    p = np.clip(p, 1e-9, 1 - 1e-9)
    return -np.where(y, np.log(p), np.log1p(-p)).sum(axis=-1)


def fit_psychometric(lengths, correct, *, guess: float = 0.25, target: float = 0.707,
                     max_lapse: float = 0.06) -> dict:  # fmt: skip
    """Maximum-likelihood fit of a psychometric function to one staircase track.

    ``p(L) = guess + (1 - guess - lapse) / (1 + exp(-(slope (ln L - ln T) + c)))`` where ``c``
    places the ``target`` proportion correct (70.7%) exactly at ``L = T``: the fitted threshold
    ``T`` is the length answered correctly 70.7% of the time, the quantity the paper's reversal
    average estimates. The guess rate is fixed (0.25 for four alternatives), the lapse rate a
    free parameter within ``[0, max_lapse]``, the slope within [0.2, 50] (in log length).

    The 95% confidence interval of ``T`` comes from the profile likelihood: the thresholds whose
    best fit is within ``chi2(1, 0.95) / 2 = 1.92`` of the maximum log-likelihood. An end that
    the track does not constrain is reported as NaN.

    Parameters
    ----------
    lengths : sequence of float
        The line length of each trial (> 0).
    correct : sequence of bool
        Whether each answer was right.

    Returns
    -------
    dict
        ``threshold``, ``ci`` (low, high), ``slope``, ``lapse``, ``log_likelihood``, ``trials``.
    """
    from scipy.optimize import minimize

    x = np.log(np.asarray(lengths, dtype=np.float64))
    y = np.asarray(correct, dtype=bool)
    if len(x) < 5 or not np.isfinite(x).all():
        raise ValueError(f"lengths must be at least 5 positive lengths, got {len(x)}")

    def nll(log_t, slope, lapse):
        """Negative log-likelihood and its gradient in (log_t, slope, lapse)."""
        span = 1.0 - guess - lapse
        q = (target - guess) / span
        c = math.log(q / (1.0 - q))
        d = x - log_t
        s = 1.0 / (1.0 + np.exp(-(slope * d + c)))
        p = guess + span * s
        inside = (p > 1e-9) & (p < 1 - 1e-9)  # clipped: flat, no gradient
        p = np.clip(p, 1e-9, 1 - 1e-9)
        dnll_dp = np.where(inside, np.where(y, -1.0 / p, 1.0 / (1.0 - p)), 0.0)
        ds = span * s * (1.0 - s)  # dp/dz
        grad = (
            float(np.dot(dnll_dp, -ds * slope)),
            float(np.dot(dnll_dp, ds * d)),
            float(np.dot(dnll_dp, -s + ds / ((1.0 - q) * span))),  # dc/dlapse = 1/((1-q) span)
        )
        return -float(np.sum(np.where(y, np.log(p), np.log1p(-p)))), grad

    bounds_sl = [(0.2, 50.0), (0.0, max_lapse)]

    def best_given(log_t, start=(4.0, 0.02)):
        def f(v):
            value, grad = nll(log_t, v[0], v[1])
            return value, np.array(grad[1:])

        result = minimize(f, start, jac=True, method="L-BFGS-B", bounds=bounds_sl)
        return result.fun, result.x

    lo, hi = x.min() - 1.5, x.max() + 1.5
    grid = np.linspace(lo, hi, 61)
    # The likelihood can have several maxima in the slope (a nearly separable track has one at
    # the steepest slope): each threshold's search starts from the best of a coarse grid.
    slopes = np.geomspace(bounds_sl[0][0], bounds_sl[0][1], 25)
    lapses = np.linspace(0.0, max_lapse, 7)
    coarse = _psychometric_nll_grid(x, y, grid, slopes, lapses, guess, target)
    fits = []
    for k, t in enumerate(grid):
        i, j = np.unravel_index(int(np.argmin(coarse[k])), coarse[k].shape)
        starts = ((slopes[i], lapses[j]), (4.0, 0.02))  # the grid's best, and a moderate slope
        fits.append(min((best_given(t, start) for start in starts), key=lambda f: f[0]))
    profile = np.array([f[0] for f in fits])
    # The joint fit from the profile's 6 lowest points (a maximum between two grid points can
    # belong to the basin of either neighbour): the best wins.
    results = [
        minimize(
            lambda v: (lambda value, grad: (value, np.array(grad)))(*nll(v[0], v[1], v[2])),
            (grid[k], *fits[k][1]),
            jac=True,
            method="L-BFGS-B",
            bounds=[(lo, hi), *bounds_sl],
        )
        for k in np.argsort(profile, kind="stable")[:6]
    ]
    result = min(results, key=lambda r: r.fun)
    log_t, slope, lapse = result.x
    best = result.fun
    inside = grid[profile - best <= 1.92]
    ci_lo = float(np.exp(inside.min())) if inside.min() > grid[0] else float("nan")
    ci_hi = float(np.exp(inside.max())) if inside.max() < grid[-1] else float("nan")
    return {
        "threshold": float(np.exp(log_t)),
        "ci": (ci_lo, ci_hi),
        "slope": float(slope),
        "lapse": float(lapse),
        "log_likelihood": -float(best),
        "trials": len(x),
    }
