"""The recommended setting: the cheapest whose felt error is within the stated tolerance of the
best, worked on hand-made tables (no model run)."""

import math

import pytest

from tactile_core.bench import Candidate, Setting, Tolerance, recommend


def candidate(rate_hz, ripple, lag_mm, onset_ms, *, levels=23, cost_us=3.0, **setting):
    return Candidate(Setting(rate_hz=rate_hz, levels=levels, **setting),
                     {"all": (ripple, lag_mm, onset_ms)}, cost_us, rate_hz * 37.0)  # fmt: skip


def test_the_slowest_rate_within_the_tolerance_is_chosen():
    table = [
        candidate(300, 1.090, 0.60, 11.0),  # the best on every figure
        candidate(100, 1.105, 0.90, 12.0),  # within 0.02, 0.5 mm, 5 ms
        candidate(50, 1.115, 1.20, 14.0),  # lag 0.6 mm over the best
        candidate(25, 1.200, 0.70, 13.0),  # ripple 0.11 over
    ]
    advice = recommend(table, Tolerance(ripple=0.02, lag_mm=0.5, onset_ms=5.0))
    assert advice.best is table[0]
    assert advice.chosen is table[1]
    assert advice.excess(table[1]) == pytest.approx((0.015, 0.30, 1.0))


def test_each_figure_must_be_within_its_own_tolerance():
    best = candidate(300, 1.10, 0.60, 10.0)
    late = candidate(50, 1.10, 0.60, 15.5)  # onset 5.5 ms over: out
    uneven = candidate(100, 1.13, 0.60, 10.0)  # ripple 0.03 over: out
    assert recommend([best, late, uneven]).chosen is best


def test_a_figure_exactly_at_the_tolerance_passes():
    best = candidate(300, 1.125, 0.5, 10.0)
    edge = candidate(50, 1.125 + 0.0625, 0.5 + 0.25, 10.0 + 2.5)  # exact in binary
    assert recommend([best, edge], Tolerance(0.0625, 0.25, 2.5)).chosen is edge


def test_the_best_setting_is_the_one_nearest_every_best_in_tolerances():
    # Each figure's minimum comes from another setting: box at 20 Hz gives the earliest onsets
    # (2 ms) and the worst ripple. Counted in tolerances, the 300 Hz point setting is 1.0
    # from every best (its onset: 5 ms over 2), the 100 Hz one 1.1 (onset 5.5 over), the
    # 20 Hz box one 6.5 (its ripple: 0.13 over).
    point = candidate(300, 1.10, 0.60, 7.0)
    box = candidate(20, 1.23, 0.90, 2.0, filter="box")
    middle = candidate(100, 1.11, 0.75, 7.5)
    advice = recommend([point, box, middle])
    assert advice.best is point
    assert advice.chosen is middle  # within 0.02 / 0.5 mm / 5 ms of the best setting
    assert advice.excess(box) == pytest.approx((0.13, 0.30, -5.0))


def test_the_best_setting_can_be_looked_for_among_some_candidates_only():
    fast = candidate(300, 1.10, 0.60, 11.0)
    slow_but_better = candidate(50, 1.08, 0.55, 10.0)
    advice = recommend([fast, slow_but_better], best_among=[fast])
    assert advice.best is fast and advice.chosen is slow_but_better


def test_at_one_rate_fewer_levels_then_less_cpu_is_cheaper():
    fine = candidate(100, 1.10, 0.6, 10.0, levels=64, cost_us=2.0)
    coarse_slow_cpu = candidate(100, 1.10, 0.6, 10.0, levels=16, cost_us=5.0)
    coarse_fast_cpu = candidate(100, 1.10, 0.6, 10.0, levels=16, cost_us=4.0, dither=True)
    advice = recommend([fine, coarse_slow_cpu, coarse_fast_cpu])
    assert advice.chosen is coarse_fast_cpu


def test_a_setting_with_something_unfelt_never_passes():
    gap = candidate(25, math.inf, 0.6, 10.0)  # infinite ripple: a moment felt as nothing
    ok = candidate(300, 1.10, 0.6, 10.0)
    advice = recommend([gap, ok])
    assert advice.best is ok and advice.chosen is ok


def test_every_method_must_be_within_the_tolerance_of_its_own_best():
    # 50 Hz is as good as 300 Hz for CT (bi-level) but leaves AS's lag 0.7 mm behind
    fast = Candidate(Setting(rate_hz=300), {"CT": (1.40, 6.0, 11.0), "AS": (1.10, 0.6, 11.0)})
    slow = Candidate(Setting(rate_hz=50), {"CT": (1.40, 6.0, 11.0), "AS": (1.11, 1.3, 12.0)})
    advice = recommend([fast, slow])
    assert advice.best is fast
    assert advice.excess(slow) == pytest.approx((0.01, 0.7, 1.0))
    assert advice.chosen is fast


def test_a_figure_no_candidate_has_does_not_count():
    # nothing felt in time anywhere (NaN onsets): the choice rests on ripple and lag
    slow = candidate(50, 1.10, 0.6, math.nan)
    fast = candidate(300, 1.10, 0.6, math.nan)
    assert recommend([fast, slow]).chosen is slow


def test_no_candidates_no_recommendation():
    advice = recommend([])
    assert advice.chosen is None and advice.best is None


@pytest.mark.parametrize("field", ["rate_hz", "levels", "filter", "lead_ms", "host"])
def test_a_bad_setting_is_refused_naming_the_field(field):
    bad = {"rate_hz": 0.0, "levels": 300, "filter": "median", "lead_ms": 900.0, "host": "x"}
    with pytest.raises(ValueError, match=field):
        Setting(**{field: bad[field]})
