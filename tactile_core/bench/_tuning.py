"""Tuning the correction: how many trials ``tactile tune-correction`` needs to recover mu and
gamma, over many simulated runs of two observers."""

from __future__ import annotations

import numpy as np

from ._common import Table

TUNING_OBSERVERS = {
    "steep": {"threshold": 0.25, "exponent": 1.0, "threshold_sd": 0.015, "weber": 0.10,
              "lapse": 0.02},
    "shallow": {"threshold": 0.35, "exponent": 0.6, "threshold_sd": 0.04, "weber": 0.25,
                "lapse": 0.04},
}  # fmt: skip
"""The two simulated observers of the tuning benchmark: steep and shallow psychometric
functions (threshold spread in drive units, Weber fraction of felt magnitude in log units)."""

TUNING_PLANS = (
    (8, 12, 6),
    (12, 16, 8),
    (16, 24, 12),
    (20, 40, 12),
    (24, 60, 16),
    (30, 90, 20),
    (40, 140, 30),
)
"""(trials per tactor, per place, at the corner) of the tuning benchmark's rows."""


def _tuning_run(job):
    from ..experiments.tuning import TuningPlan, simulate_tuning

    observer, plan, seed = job
    o = dict(TUNING_OBSERVERS[observer])
    r = simulate_tuning(o.pop("threshold"), o.pop("exponent"), seed=seed,
                        plan=TuningPlan(*plan), **o)  # fmt: skip
    return observer, plan, r.ok, r.mu, r.gamma, r.mu_ci, r.gamma_ci, r.trials


def tuning_table(runs: int = 200, plans=TUNING_PLANS, processes: int = 2) -> Table:
    """How many trials the correction tuning needs: the share of simulated runs that recover
    mu within +-0.03 and gamma within +-15%, against the trial count, for two observers."""
    import multiprocessing

    jobs = [(o, plan, seed) for o in TUNING_OBSERVERS for plan in plans for seed in range(runs)]
    with multiprocessing.get_context("spawn").Pool(processes) as pool:
        results = pool.map(_tuning_run, jobs, chunksize=8)
    rows = []
    for observer, o in TUNING_OBSERVERS.items():
        mu_true, gamma_true = o["threshold"], 1.0 / (2.0 * o["exponent"])
        for plan in plans:
            got = [r for r in results if r[0] == observer and r[1] == plan]
            ok = [r for r in got if r[2]]
            mu_err = np.array([r[3] - mu_true for r in ok])
            g_err = np.array([r[4] / gamma_true - 1.0 for r in ok])
            mu_in = np.abs(mu_err) <= 0.03 + 1e-9
            g_in = np.abs(g_err) <= 0.15 + 1e-9
            covers_mu = [r[5][0] <= mu_true <= r[5][1] for r in ok]
            covers_g = [not (r[6][0] > gamma_true) and not (r[6][1] < gamma_true) for r in ok]
            n = len(got)
            rows.append([
                observer, f"{5 * plan[0] + 2 * plan[1] + plan[2]}", "/".join(map(str, plan)),
                f"{100 * mu_in.sum() / n:.0f}", f"{100 * g_in.sum() / n:.0f}",
                f"{100 * (mu_in & g_in).sum() / n:.0f}", f"{100 * (n - len(ok)) / n:.0f}",
                f"{np.median(np.abs(mu_err)):.3f}" if ok else "-",
                f"{100 * np.median(np.abs(g_err)):.1f}" if ok else "-",
                f"{100 * np.mean(covers_mu):.0f}" if ok else "-",
                f"{100 * np.mean(covers_g):.0f}" if ok else "-",
            ])  # fmt: skip
    headers = ["observer", "trials", "per tactor / place / corner", "% mu within 0.03",
               "% gamma within 15%", "% both", "% no result", "median |mu err|",
               "median |gamma err| %", "% mu CI covers", "% gamma CI covers"]  # fmt: skip
    notes = (
        f"{runs} simulated runs per row (seeds 0..{runs - 1}) of `tactile tune-correction` "
        "against the simulated participant. steep: TH 0.25, K 1.0 (gamma 0.5), threshold sd "
        "0.015, Weber 0.10, lapse 0.02; shallow: TH 0.35, K 0.6 (gamma 0.83), threshold sd 0.04, "
        "Weber 0.25, lapse 0.04. Trials: answers (5 tactors x per tactor + 2 places x per place + "
        "corner), as planned. '% no result': runs that ended with no correction (a track did "
        "not settle). Shares are of all runs; the interval columns of the runs with a result."
    )
    return Table("Tuning the correction: trials against accuracy", headers, rows, notes)
