"""The speed/accuracy trade in felt terms (``tactile bench --part trade``): the table's shape,
and the sanity the model guarantees (more levels never send a worse drive, an ideal motor adds
no lag, a lead delays every onset by itself and nothing else, slower motors lag more)."""

import numpy as np
import pytest

from tactile_core.bench import (
    PAPER,
    SCENES,
    Target,
    felt_runs,
    trade_settings,
    trade_tables,
)
from tactile_core.cli import main
from tactile_core.device.profile import find_profile
from tactile_core.rendering.methods import method_names
from tactile_core.rendering.motor import MotorResponse
from tactile_core.rendering.percept import predict

PALM = MotorResponse(0.030, 0.060)
LINE = SCENES["line"]


def test_the_quick_table_has_a_row_per_setting_and_motor_and_every_figure_a_spread():
    target = Target.of(find_profile("palm-5x6"))
    trade, by_method = trade_tables(target, quick=True)
    settings = trade_settings(PAPER, target.lead_ms, quick=True)
    assert len(trade.rows) == len(settings) + 2 * 2  # the key rows again for 0/0 and 30/60
    assert trade.headers[2:6] == [
        "felt ripple",
        "felt centroid lag mm",
        "onset error at the skin ms",
        "drive energy error %",
    ]
    for row in trade.rows:
        assert all(" ± " in cell for cell in row[2:6]), row
    assert [r[0] for r in trade.rows[: len(settings)]] == ["30/60"] * len(settings)
    assert trade.rows[0][1].startswith("base: 300 Hz, point, 23 levels, rounded, lead 0")
    assert [r[0] for r in by_method.rows] == ["CT", "AS"]
    assert "30/60 ms (the profile's, estimate)" in trade.notes


def test_the_base_row_is_the_papers_pipeline_at_the_devices_levels():
    assert PAPER.rate_hz == 300 and PAPER.filter == "point" and PAPER.levels == 23
    assert not PAPER.dither and PAPER.lead_ms == 0 and not PAPER.compensate
    rows = trade_settings(PAPER.replace(levels=16), 20.0)
    changed = [r for r in rows[1:] if sum(getattr(r, f) != getattr(rows[0], f) for f in
                                          ("rate_hz", "filter", "levels", "dither", "lead_ms",
                                           "host", "compensate")) == 1]  # fmt: skip
    # every rate, the box filter, the other levels, dithering, the lead, the busy host and
    # motor-aware drive, one at a time
    assert len(changed) == 5 + 1 + 5 + 1 + 1 + 1 + 1
    assert {r.levels for r in changed} >= {4, 8, 23, 64, 256}


@pytest.mark.parametrize("dither", [False, True])
@pytest.mark.parametrize("method", ["AS", "IM"])
def test_the_levels_add_at_most_half_a_level_to_the_drive_error(method, dither):
    """Each lit frame's level is within half a step (rounding; dithering carries what it drops
    on, so its sum is within half a step too) of the corrected drive, which is at least
    mu = 0.33 where lit: relative to a tactor's energy, the levels add at most
    0.5 / ((L - 1) 0.33) to the error the frame rate already has (256 levels: 0.6%)."""
    floor = felt_runs(PAPER.replace(levels=256), LINE, method, PALM, phases=3).drive_pct
    for levels in (4, 8, 16, 23, 64):
        runs = felt_runs(PAPER.replace(levels=levels, dither=dither), LINE, method, PALM,
                         phases=3)  # fmt: skip
        bound = 100 * 0.5 / (0.33 * (levels - 1)) + 100 * 0.5 / (0.33 * 255)
        assert (runs.drive_pct <= floor + bound).all(), (levels, runs.drive_pct, floor)


def test_at_16_levels_as_sends_its_threshold_closer_than_at_23():
    """Rounding is not monotone in the levels: mu = 0.33 goes out as 7 / 22 = 0.318 (3.6% low)
    at 23 levels and as 5 / 15 = 0.333 at 16, so AS's drive energy (most of its lit frames
    near mu) is nearer at 16 levels (docs/benchmarks.md, reading the trade table)."""
    assert round(0.33 * 22) / 22 == pytest.approx(0.318, abs=5e-4)
    assert round(0.33 * 15) / 15 == pytest.approx(0.333, abs=5e-4)
    at = {n: felt_runs(PAPER.replace(levels=n), LINE, "AS", PALM, phases=3).drive_pct
          for n in (16, 23)}  # fmt: skip
    assert at[16].mean() < at[23].mean()


def test_an_ideal_motor_adds_no_lag_to_the_frames_sent():
    # tau = 0: the skin gets the levels as sent; their felt centroid error is the percept of
    # the frames themselves (percept.predict, point-sampled at 300 Hz and 23 levels, no motor).
    ideal = felt_runs(PAPER.replace(lead_ms=20), LINE, "AS", MotorResponse(0.0, 0.0), phases=4)
    sent = predict(LINE, "AS", rate_hz=300, levels=23)
    np.testing.assert_allclose(ideal.lag_mm, sent.mean_error_mm, atol=0.05)
    slow = felt_runs(PAPER.replace(lead_ms=20), LINE, "AS", PALM, phases=4)
    assert (slow.lag_mm > ideal.lag_mm + 1.0).all()  # 30/60 ms motors: 1.8 against 0.6 mm


def test_a_lead_delays_every_onset_by_itself_and_changes_nothing_else():
    runs = {lead: felt_runs(PAPER.replace(lead_ms=lead), LINE, "AS", PALM, phases=3)
            for lead in (20.0, 45.0)}  # fmt: skip
    np.testing.assert_allclose(runs[45.0].onset_ms - runs[20.0].onset_ms, 25.0, atol=1e-9)
    for figure in ("ripple", "lag_mm", "drive_pct", "missed"):
        np.testing.assert_array_equal(getattr(runs[45.0], figure), getattr(runs[20.0], figure))


def test_with_a_lead_the_hosts_load_no_longer_reaches_the_skin():
    idle = felt_runs(PAPER.replace(lead_ms=20), LINE, "AS", PALM, phases=3)
    busy = felt_runs(PAPER.replace(lead_ms=20, host="busy"), LINE, "AS", PALM, phases=3)
    for figure in ("ripple", "lag_mm", "onset_ms"):
        np.testing.assert_array_equal(getattr(idle, figure), getattr(busy, figure))
    now_busy = felt_runs(PAPER.replace(host="busy"), LINE, "AS", PALM, phases=3)
    assert (now_busy.onset_ms > idle.onset_ms - 20 + 10).all()  # 14 ms p50 jitter, and more


def test_slower_motors_lag_more():
    lags = [felt_runs(PAPER.replace(lead_ms=20), LINE, "AS", MotorResponse(up, 2 * up),
                      phases=2).lag_mm.mean() for up in (0.0, 0.010, 0.030, 0.100)]  # fmt: skip
    assert lags == sorted(lags) and lags[-1] > lags[0] + 3.0


def test_every_registered_method_runs_through_the_trade():
    # the table takes its methods from the registry: TB and plug-ins join when registered
    target = Target.of(find_profile("palm-5x6"))
    _, by_method = trade_tables(target, quick=True, methods=method_names())
    assert [r[0] for r in by_method.rows] == list(method_names())


def test_tactile_bench_part_trade_quick_prints_the_table_and_the_recommendations(capsys):
    assert main(["bench", "--part", "trade", "--quick"]) == 0
    out = capsys.readouterr().out
    assert "### The trade in felt terms (palm-5x6)" in out
    assert "### The trade by method (palm-5x6)" in out
    assert "### Recommended settings per device" in out
    for profile in ("palm-5x6", "wireless-4x4", "lra-5x6", "voicecoil-8"):
        assert f"| {profile} " in out


def test_tactile_bench_part_trade_with_a_profile_recommends_for_it(capsys):
    assert main(["bench", "--part", "trade", "--quick", "--profile", "voicecoil-8"]) == 0
    out = capsys.readouterr().out
    assert "### The trade in felt terms (voicecoil-8)" in out
    assert "| profile voicecoil-8 " in out and "(audio" in out


@pytest.mark.parametrize(("args", "message"), [
    (["--part", "core", "--profile", "palm-5x6"], "--profile is for --part trade"),
    (["--part", "trade", "--profile", "no-such-array"], "no-such-array"),
])  # fmt: skip
def test_a_bad_profile_for_the_bench_is_refused_before_any_table(capsys, args, message):
    assert main(["bench", "--quick", *args]) == 2
    captured = capsys.readouterr()
    assert message in captured.err and "###" not in captured.out
