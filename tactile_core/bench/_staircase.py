"""Experiment 2's staircase: how many trials its estimate needs to settle, with simulated
participants."""

from __future__ import annotations

import numpy as np

from ._common import Table


def staircase_table(trials=(20, 30, 40, 60, 80, 120, 160), slopes=(2.0, 4.0, 8.0),
                    tracks: int = 2000, seed: int = 0) -> Table:  # fmt: skip
    """How many trials Experiment 2's estimate needs to settle within 10% of the 70.7% length.

    Simulated participants answer from a psychometric function (logistic in log length, guess
    rate 0.25, lapse 0.02) of slope ``slope``; each track runs the paper's staircase (start 2.0,
    x 0.685 / x 1.46, 2-down/1-up, capped at 4) for ``N`` trials. Two estimates per track: the
    paper's (mean of the last 4 reversals) and the mean of all reversals after the first three.
    """
    from ..experiments.participants import Psychometric
    from ..experiments.staircase import Staircase

    rng = np.random.default_rng(seed)
    rows = []

    def summary(est, target):
        ok = np.isfinite(est)
        if not ok.any():
            return ["-", "-", "0"]
        rel = (est[ok] - target) / target
        within = np.abs(np.where(ok, est, np.inf) - target) <= 0.1 * target
        return [f"{100 * np.median(rel):+.1f}", f"{100 * np.median(np.abs(rel)):.1f}",
                f"{100 * within.mean():.0f}"]  # fmt: skip

    for slope in slopes:
        f = Psychometric(midpoint=0.5, slope=slope)
        target = f.length_at(0.707)
        for n in trials:
            paper, all_but_3 = [], []
            for _ in range(tracks):
                sc = Staircase(2.0, 0.685, 1.46, 2, 1, min_level=0.01, max_level=4.0)
                draws = rng.random(n)
                for k in range(n):
                    sc.update(bool(draws[k] < f.p_correct(sc.level)))
                rev = sc.reversal_levels
                paper.append(np.mean(rev[-4:]) if len(rev) >= 4 else np.nan)
                all_but_3.append(np.mean(rev[3:]) if len(rev) >= 4 else np.nan)
            paper, all_but_3 = np.array(paper), np.array(all_but_3)
            rows.append(
                [f"{slope:g}", f"{n}", f"{100 * np.isfinite(paper).mean():.0f}",
                 *summary(paper, target), *summary(all_but_3, target)]
            )  # fmt: skip
    headers = [
        "slope", "trials", "% with 4 reversals",
        "last 4: bias %", "last 4: median |err| %", "last 4: % within 10%",
        "all but first 3: bias %", "all but first 3: median |err| %",
        "all but first 3: % within 10%",
    ]  # fmt: skip
    notes = (
        f"{tracks} simulated tracks per row, errors relative to the true 70.7% length. Slope: of "
        "the psychometric function in log length (2 shallow, 8 steep). 'last 4' is the paper's "
        "estimate (last two peaks and valleys); the paper ran 30 trials per condition."
    )
    return Table("Experiment 2: trials needed for the estimate to settle", headers, rows, notes)
