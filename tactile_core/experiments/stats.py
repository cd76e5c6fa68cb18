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
