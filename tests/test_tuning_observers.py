"""The correction tuning against observers it was not built for: the departures of the
simulated observer worked by hand, the corner check's blind spot (a power-sum rule moves both
places alike), and QUEST+ as the threshold procedure, selected per run and recorded."""

import math

import numpy as np
import pytest
import questplus  # noqa: F401 - imported with the module: xarray and pandas take 1.5 s

from tactile_core.bench._validation import right_gamma
from tactile_core.experiments.results import Session
from tactile_core.experiments.tuning import (
    CorrectionTuning,
    SimulatedObserver,
    TuningPlan,
    simulate_tuning,
)


def frame(cells):
    f = np.zeros((6, 5))
    for (c, r), d in cells.items():
        f[r, c] = d
    return f


def test_the_departures_of_the_observer_worked_by_hand():
    # Two tactors side by side at drive 0.6, TH 0.2, K 1: m = 0.4 / 0.8 = 0.5 each.
    two = frame({(1, 2): 0.6, (2, 2): 0.6})
    assert SimulatedObserver(0.2, 1.0).felt(two) == pytest.approx(math.sqrt(0.5))  # energy
    assert SimulatedObserver(0.2, 1.0, summation=1.0).felt(two) == pytest.approx(1.0)
    # Masking: each is the other's neighbour, threshold 0.2 + 0.1 = 0.3: m = 0.3 / 0.7 each.
    masked = SimulatedObserver(0.2, 1.0, masking=0.1).felt(two)
    assert masked == pytest.approx(math.sqrt(2) * 0.3 / 0.7)
    # A lone tactor has no neighbour on: no masking.
    assert SimulatedObserver(0.2, 1.0, masking=0.1).felt(frame({(1, 2): 0.6})) == pytest.approx(0.5)
    # Per-tactor thresholds: drawn once per observer with the given spread, seeded.
    spread = SimulatedObserver(0.25, 1.0, seed=4, tactor_sd=0.1)
    again = SimulatedObserver(0.25, 1.0, seed=4, tactor_sd=0.1)
    np.testing.assert_array_equal(spread.thresholds, again.thresholds)
    assert 0.03 < spread.thresholds.std() < 0.2 and not spread.contract


@pytest.mark.parametrize("p", [1.0, 2.0, 3.0])
def test_a_power_sum_moves_the_pair_and_the_corner_alike(p):
    # n tactors at raw 1/n, corrected at mu = TH: m = (1/n)^(gamma K) each, M = n^(1/p - gamma K)
    # equals the one tactor's 1 at gamma = 1 / (p K) whatever n: the corner check cannot see p.
    k, th = 0.8, 0.25
    sim = SimulatedObserver(th, k, summation=p)
    for cells in ([(1, 2), (2, 2)], [(1, 3), (2, 3), (1, 4), (2, 4)]):
        n = len(cells)
        lo, hi = 0.05, 10.0
        for _ in range(80):
            g = math.sqrt(lo * hi)
            felt = sim.felt(frame(dict.fromkeys(cells, th + (1 - th) * (1 / n) ** g)))
            lo, hi = (g, hi) if felt > 1.0 else (lo, g)
        assert math.sqrt(lo * hi) == pytest.approx(1 / (p * k), rel=1e-9)


def test_the_right_gamma_of_an_observer():
    assert right_gamma(SimulatedObserver(0.25, 1.0), 0.25) == pytest.approx(0.5)
    assert right_gamma(SimulatedObserver(0.25, 1.0, summation=1.0), 0.25) == pytest.approx(1.0)
    # Masking weakens the pair, not the lone tactor: more drive, a lower gamma, is right.
    assert right_gamma(SimulatedObserver(0.25, 1.0, masking=0.05), 0.25) < 0.49


def test_quest_plus_places_the_thresholds_and_is_recorded():
    plan = TuningPlan(8, 2, 0, threshold_procedure="quest+")
    assert plan.to_dict()["threshold_procedure"] == "quest+"
    sim = SimulatedObserver(0.3, 1.0, seed=2, threshold_sd=0.015, weber=0.1, lapse=0.02)
    runner = CorrectionTuning(Session(participant="simulated", seed=2), plan, write=False,
                              profile=sim.profile)  # fmt: skip
    assert runner.conditions["plan"]["threshold_procedure"] == "quest+"
    sim.run(runner)
    stages = runner.trials_by_stage
    levels = [d for c, r in runner.tactors for d, _ in stages[f"threshold-c{c}r{r}"]]
    assert len(levels) == 40 and all(0 < d <= 1 for d in levels)
    assert runner.mu == pytest.approx(0.3, abs=0.06)
    with pytest.raises(ValueError, match="threshold_procedure"):
        TuningPlan(threshold_procedure="quest")


def test_a_departing_observer_still_gets_an_answer_from_the_procedure():
    r = simulate_tuning(0.25, 1.0, seed=1, plan=TuningPlan(8, 8, 4), summation=1.0,
                        threshold_sd=0.015, weber=0.1, lapse=0.02)  # fmt: skip
    assert r.ok and r.gamma > 0.7  # linear summation: the right gamma is 1 / K = 1


def test_the_command_line_selects_and_reports_the_threshold_procedure(capsys):
    import json

    from tactile_core.cli import main

    main(["tune-correction", "--simulate", "--threshold", "0.3", "--exponent", "1", "--seed", "3",
          "--trials-per-tactor", "6", "--trials-per-place", "6", "--corner-trials", "0",
          "--threshold-procedure", "quest+", "--json"])  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    assert out["threshold_procedure"] == "quest+" and out["trials"] == 5 * 6 + 2 * 6
