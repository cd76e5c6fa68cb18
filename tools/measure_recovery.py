"""The tables of docs/measuring.md: what ``tactile measure`` recovers of the simulated sensor's
known motors (recovered against true, over motor constants and noise levels), how long a
tactor and the palm array take, and a validator run's log beside the commanded onsets.

    python tools/measure_recovery.py            # all three (about a minute)
    python tools/measure_recovery.py --quick    # fewer tactors and seeds
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import tactile_core as tc
from tactile_core.device.measure import (
    QUICK_PLAN,
    MeasurePlan,
    neighbours,
    sensor_model,
    simulate_measurement,
)
from tactile_core.device.profile import default_profile

CASES = [(10.0, 20.0, 2.0), (30.0, 60.0, 5.0), (100.0, 200.0, 20.0), (150.0, 300.0, 40.0)]
NOISES = (0.0, 0.05, 0.15)
CELLS = (0, 4, 14, 25, 29, 7)  # corners, middle, an edge


def recovery_table(seeds, cells) -> None:
    profile = default_profile()
    print("| true spin-up / run-down / delay ms | noise | recovered spin-up ms | run-down ms "
          "| delay ms | onset ms | worst curve error | worst frequency error "
          "| residual |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    for up, down, delay in CASES:
        for noise in NOISES:
            rows, freq = [], 0.0
            for seed in seeds:
                got = simulate_measurement(profile, tau_up_ms=up, tau_down_ms=down,
                                           delay_ms=delay, noise=noise, seed=seed,
                                           cells=cells)  # fmt: skip
                assert not got.failures, got.failures
                rows += list(got.tactors)
                model = sensor_model(profile, tau_up_ms=up, tau_down_ms=down, delay_ms=delay,
                                     noise=noise, seed=seed)  # fmt: skip
                freq = max([freq] + [_freq_error(t, model) for t in got.tactors])
            ups = np.array([t.tau_up_s for t in rows]) * 1e3
            downs = np.array([t.tau_down_s for t in rows]) * 1e3
            delays = np.array([t.delay_s for t in rows]) * 1e3
            onsets = np.array([t.onset_s for t in rows]) * 1e3
            curve = max(_curve_error(t, profile.response) for t in rows)
            residual = max(t.residual for t in rows)

            def span(v):
                return f"{np.median(v):.1f} ({v.min():.1f}-{v.max():.1f})"

            print(f"| {up:g} / {down:g} / {delay:g} | {noise:g} | {span(ups)} | {span(downs)} "
                  f"| {span(delays)} | {np.median(onsets):.1f} | {curve:.3f} | {freq:.1%} "
                  f"| {residual:.1%} |")  # fmt: skip


def _curve_error(t, curve) -> float:
    drive, output = t.response
    return float(np.max(np.abs(np.asarray(output) - np.interp(drive, *curve))))


def _freq_error(t, model) -> float:
    """Against the simulated ERM: ``freq_lo + (freq_hi - freq_lo) s`` Hz at drive ``s``."""
    levels = np.asarray(t.levels) / t.levels[-1]
    f = np.asarray(t.frequency_hz)
    ok = np.isfinite(f)
    truth = model.frequency_hz(t.cell, levels[ok])
    return float(np.max(np.abs(f[ok] / truth - 1.0)))


def timing_table() -> None:
    profile = default_profile()
    print("| plan | one tactor inside the grid (8 neighbours) | a corner (3) "
          "| the palm array (30) |")  # fmt: skip
    print("|---|---|---|---|")
    for name, plan in (("default", MeasurePlan()), ("--quick", QUICK_PLAN)):
        inside, corner = plan.duration_s(8, 23), plan.duration_s(3, 23)
        layout = profile.layout
        palm = sum(plan.duration_s(len(neighbours(layout, c)), 23) for c in range(30))
        print(f"| {name} | {inside:.1f} s | {corner:.1f} s | {palm:.0f} s ({palm / 60:.1f} "
              f"min; {30 * inside / 60:.1f} min as 30 x the inside tactor) |")  # fmt: skip


def validator_run() -> None:
    import tempfile

    folder = tempfile.mkdtemp()
    with tc.open_array("sim", validate="sim", validate_log=folder, lead_ms=20) as array:
        for k in range(6):
            array.play("circle:0.5,0.5,0.1", method="CT", duration_s=0.2 + 0.05 * k)
            time.sleep(0.25)
        validator = array.validator
    print("| presentation | commanded (s) | detected (s) | delay (ms) | peak |")
    print("|---|---|---|---|---|")
    for row in validator.rows:
        print(f"| {row['presentation']} | {row['commanded_s']} | {row['detected_s']} | "
              f"{row['delay_ms']} | {float(row['peak']):.3f} |")  # fmt: skip
    print()
    print(validator.summary_line())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    seeds, cells = ((1,), CELLS[:2]) if args.quick else ((1, 2, 3), CELLS)
    recovery_table(seeds, cells)
    print()
    timing_table()
    print()
    validator_run()


if __name__ == "__main__":
    main()
