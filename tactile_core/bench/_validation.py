"""The correction tuning against observers it was not built for, and its threshold part with a
3-down/1-up track against QUEST+."""

from __future__ import annotations

import math

import numpy as np

from ._common import Table
from ._tuning import TUNING_OBSERVERS

BASE = {"threshold": 0.25, "exponent": 1.0, "threshold_sd": 0.015, "weber": 0.10, "lapse": 0.02}
"""The observer every validation row starts from: the tuning table's steep one."""

DEPARTURES = (
    ("as modelled", {}),
    ("tactor thresholds spread, SD 0.05", {"tactor_sd": 0.05}),
    ("tactor thresholds spread, SD 0.1", {"tactor_sd": 0.10}),
    ("linear summation (p = 1)", {"summation": 1.0}),
    ("masking neighbour (+0.05 drive)", {"masking": 0.05}),
    ("lapse 5%", {"lapse": 0.05}),
    ("shallow slope (trial SD 0.04, Weber 0.25)", {"threshold_sd": 0.04, "weber": 0.25}),
)
"""The rows of the validation table: what departs from the procedure's model."""


def right_gamma(observer, mu: float) -> float:
    """The gamma that makes a point midway between two tactors feel, without noise, as strong
    as a point on one for ``observer`` at ``mu``: the geometric mean over the procedure's two
    places of each place's point of equality, by bisection in log gamma on [0.1, 10]."""
    from ..experiments.tuning import default_layout
    from ..rendering.correction import correct
    from ..rendering.rasterize import render_xy

    grid = observer.profile.layout
    _, places = default_layout(grid)
    found = []
    for name in ("side", "above"):
        place = places[name]
        raw = render_xy("AS", *place["point"], grid=grid)
        reference = observer.felt(render_xy("AS", *place["reference"], grid=grid))
        lo, hi = math.log(0.1), math.log(10.0)
        for _ in range(60):
            mid = (lo + hi) / 2
            felt = observer.felt(correct(raw, mu, math.exp(mid)))
            lo, hi = (mid, hi) if felt > reference else (lo, mid)
        found.append((lo + hi) / 2)
    return math.exp(sum(found) / len(found))


def _validation_run(job):
    from ..experiments.tuning import SimulatedObserver, simulate_tuning

    label, seed = job
    kw = {**BASE, **dict(DEPARTURES)[label]}
    r = simulate_tuning(kw.pop("threshold"), kw.pop("exponent"), seed=seed, **kw)
    sim = SimulatedObserver(BASE["threshold"], BASE["exponent"], seed=seed,
                            **{k: v for k, v in kw.items() if k != "lapse"})  # fmt: skip
    warned = r.corner_agrees is False
    return (
        label,
        r.ok,
        r.mu,
        r.gamma,
        r.mu_ci,
        r.gamma_ci,
        warned,
        right_gamma(sim, BASE["threshold"]),
    )


def validation_table(runs: int = 200, processes: int = 2) -> Table:
    """The procedure against observers that depart from its model (:data:`DEPARTURES`):
    bias, spread and interval coverage of mu and gamma, and how often the corner check warns."""
    import multiprocessing

    jobs = [(label, seed) for label, _ in DEPARTURES for seed in range(runs)]
    with multiprocessing.get_context("spawn").Pool(processes) as pool:
        results = pool.map(_validation_run, jobs, chunksize=8)
    mu_true = BASE["threshold"]
    rows = []
    for label, _ in DEPARTURES:
        got = [r for r in results if r[0] == label]
        ok = [r for r in got if r[1]]
        n = len(got)
        g_true = np.array([r[7] for r in ok])
        mu_err = np.array([r[2] - mu_true for r in ok])
        g_err = np.array([r[3] for r in ok]) / g_true - 1.0
        mu_cover = np.mean([r[4][0] <= mu_true <= r[4][1] for r in ok])
        g_cover = np.mean([not (lo > t) and not (hi < t) for (lo, hi), t in
                           zip((r[5] for r in ok), g_true)])  # fmt: skip
        rows.append([
            label, f"{mu_true:g} / {np.median(g_true):.2f}", f"{100 * (n - len(ok)) / n:.0f}",
            f"{mu_err.mean():+.3f} / {np.median(mu_err):+.3f}", f"{mu_err.std(ddof=1):.3f}",
            f"{100 * mu_cover:.0f}", f"{100 * g_err.mean():+.1f} / {100 * np.median(g_err):+.1f}",
            f"{100 * g_err.std(ddof=1):.1f}", f"{100 * g_cover:.0f}",
            f"{100 * np.mean([r[6] for r in got]):.0f}",
        ])  # fmt: skip
    headers = ["observer", "right mu / gamma", "% no result", "mu error mean / median",
               "mu error SD", "% mu CI covers", "gamma error % mean / median",
               "gamma error SD %", "% gamma CI covers", "% corner check warns"]  # fmt: skip
    notes = (
        f"{runs} simulated runs per row (seeds 0..{runs - 1}) of `tactile tune-correction` with "
        "the default plan (192 trials). Every row starts from the steep observer (TH 0.25, K "
        "1.0, trial-to-trial threshold SD 0.015, Weber 0.10, lapse 0.02) and changes what the "
        "row says: each tactor's own threshold drawn around 0.25; magnitudes summed linearly "
        "instead of by energy; a tactor's threshold raised by 0.05 while a neighbour is felt; "
        "a lapse rate of 5%; a shallow psychometric function. Right mu: 0.25, the centre of the "
        "thresholds. Right gamma: the one that makes the point between two tactors feel, "
        "without noise, as strong as a tactor at mu 0.25 for that observer (per run, median "
        "shown; 1 / (p K) under a power sum). Errors of the runs with a result; '% corner "
        "check warns': runs whose corner interval excluded the pooled gamma."
    )
    return Table("Tuning against observers it was not built for", headers, rows, notes)


QUEST_TRIALS = (8, 12, 16, 20, 24, 30, 40)
"""Trials per tactor at which the threshold part is scored."""


def _quest_run(job):
    from ..experiments.results import Session
    from ..experiments.tuning import CorrectionTuning, SimulatedObserver, TuningPlan, mu_from_tracks

    observer, procedure, seed = job
    o = dict(TUNING_OBSERVERS[observer])
    sim = SimulatedObserver(o.pop("threshold"), o.pop("exponent"), seed=seed, **o)
    plan = TuningPlan(max(QUEST_TRIALS), 2, 0, threshold_procedure=procedure)
    runner = CorrectionTuning(Session(participant="simulated", seed=seed), plan, write=False,
                              profile=sim.profile)  # fmt: skip
    sim.run(runner)
    stages = [runner.trials_by_stage[f"threshold-c{c}r{r}"] for c, r in runner.tactors]
    mus = []
    for n in QUEST_TRIALS:
        tracks = [tuple(zip(*rows[:n])) for rows in stages]
        mus.append(mu_from_tracks(runner.tactors, tracks)[0])
    return observer, procedure, mus


def quest_table(runs: int = 200, processes: int = 2) -> Table:
    """Trials the threshold part needs: the share of runs with mu within +-0.03 against the
    trials per tactor, for the 3-down/1-up track and QUEST+, two observers."""
    import multiprocessing

    procedures = ("staircase", "quest+")
    jobs = [(o, p, seed) for o in TUNING_OBSERVERS for p in procedures for seed in range(runs)]
    with multiprocessing.get_context("spawn").Pool(processes) as pool:
        results = pool.map(_quest_run, jobs, chunksize=4)
    rows = []
    for observer, o in TUNING_OBSERVERS.items():
        for procedure in procedures:
            got = [r[2] for r in results if r[0] == observer and r[1] == procedure]
            shares = []
            for k in range(len(QUEST_TRIALS)):
                within = [m is not None and abs(m - o["threshold"]) <= 0.03 + 1e-9
                          for m in (g[k] for g in got)]  # fmt: skip
                shares.append(100 * np.mean(within))
            enough = next((5 * n for n, s in zip(QUEST_TRIALS, shares) if s >= 95), None)
            rows.append([observer, procedure, *(f"{s:.0f}" for s in shares),
                         str(enough) if enough else f"> {5 * max(QUEST_TRIALS)}"])  # fmt: skip
    headers = ["observer", "procedure", *(f"% within 0.03 at {n}/tactor" for n in QUEST_TRIALS),
               "trials to 95%"]  # fmt: skip
    notes = (
        f"{runs} simulated runs per row (seeds 0..{runs - 1}): the threshold part of `tactile "
        "tune-correction` on 5 tactors over the device's 23 levels, each tactor's threshold "
        "the same maximum-likelihood fit to its first N trials, mu their median. staircase: "
        "the 3-down/1-up track (2-down/1-up until the second wrong answer); quest+: QUEST+ "
        "(`questplus`, minimum expected entropy, prior uniform over threshold 0-1, SD "
        "0.01-0.3, lapse 0-0.05). Observers as in the tuning table. Trials to 95%: 5 x the "
        "fewest trials per tactor with mu within +-0.03 in at least 95% of runs."
    )
    return Table("Thresholds: 3-down/1-up against QUEST+", headers, rows, notes)
