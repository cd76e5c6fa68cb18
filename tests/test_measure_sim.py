"""The whole procedure against the simulated sensor recovers what the simulation was given:
time constants within +-10 %, the delay within +-1 ms, the amplitude curve within 0.05 of the
full-drive amplitude and the vibration frequency within 3 %, over noise levels, motor constants
and seeds (docs/measuring.md states these bounds)."""

import numpy as np
import pytest

from tactile_core.device.measure import MeasurePlan, simulate_measurement
from tactile_core.device.measure._sim import PALM_CURVE
from tactile_core.device.profile import default_profile, load_profile

TAU_REL = 0.10
DELAY_MS = 1.0
CURVE_ABS = 0.05
FREQ_REL = 0.03

CASES = [  # (spin-up, run-down, delay) ms: fast, the palm's estimates, slow, a lag of its own
    (10.0, 20.0, 2.0),
    (30.0, 60.0, 5.0),
    (100.0, 200.0, 20.0),
    (60.0, 60.0, 35.0),
]


def check_tactor(t, up_ms, down_ms, delay_ms, curve=PALM_CURVE):
    assert t.tau_up_s * 1e3 == pytest.approx(up_ms, rel=TAU_REL), t.name
    assert t.tau_down_s * 1e3 == pytest.approx(down_ms, rel=TAU_REL), t.name
    assert abs(t.delay_s * 1e3 - delay_ms) <= DELAY_MS, t.name
    drive, output = t.response
    assert np.max(np.abs(np.asarray(output) - np.interp(drive, *curve))) <= CURVE_ABS, t.name


@pytest.mark.parametrize("noise", [0.0, 0.05, 0.15])
@pytest.mark.parametrize("up_ms, down_ms, delay_ms", CASES)
def test_simulated_measurement_recovers_the_motor(up_ms, down_ms, delay_ms, noise):
    profile = default_profile()
    for seed in (1, 2):
        got = simulate_measurement(profile, tau_up_ms=up_ms, tau_down_ms=down_ms,
                                   delay_ms=delay_ms, noise=noise, seed=seed,
                                   cells=[0, 14])  # fmt: skip
        assert got.failures == {}
        assert len(got.tactors) == 2
        for t in got.tactors:
            check_tactor(t, up_ms, down_ms, delay_ms)
            assert t.warnings == ()


def test_vibration_frequency_against_level_rises_as_an_erms_does():
    profile = default_profile()
    got = simulate_measurement(profile, noise=0.05, seed=3, cells=[7],
                               freq_lo_hz=40.0, freq_hi_hz=220.0)  # fmt: skip
    (t,) = got.tactors
    levels = np.asarray(t.levels)
    freq = np.asarray(t.frequency_hz)
    read = np.isfinite(freq)
    # the simulated ERM turns at 40 + 180 s Hz at effective drive s; below the motor's start
    # (drive 0.2) there is nothing to read
    assert not read[levels / 22 < 0.19].any()
    truth = 40.0 + 180.0 * levels[read] / 22
    np.testing.assert_allclose(freq[read], truth, rtol=FREQ_REL)
    assert read.sum() >= 15


def test_each_tactor_gets_its_own_constants():
    profile = load_profile("grid-3x3")
    up = np.linspace(15.0, 45.0, 9)
    down = np.linspace(80.0, 40.0, 9)
    got = simulate_measurement(profile, noise=0.05, seed=5, cells=[0, 4, 8],
                               tau_up_s=up / 1e3, tau_down_s=down / 1e3)  # fmt: skip
    assert [t.cell for t in got.tactors] == [0, 4, 8]
    for t in got.tactors:
        check_tactor(t, up[t.cell], down[t.cell], 5.0, profile.response or PALM_CURVE)


def test_onset_is_the_delay_plus_the_spin_up_to_a_tenth_of_full_vibration():
    # palm curve: a tenth of full amplitude at drive 0.2 + 0.1 / 3; the motor gets there
    # tau_up ln(1 / (1 - s)) after its drive changes, the delay after the frame
    got = simulate_measurement(default_profile(), tau_up_ms=30.0, delay_ms=5.0, noise=0.02,
                               seed=2, cells=[3])  # fmt: skip
    s = 0.2 + 0.1 / 3
    assert got.tactors[0].onset_s * 1e3 == pytest.approx(5.0 + 30.0 * np.log(1 / (1 - s)), abs=1.0)


def test_summary_gives_the_medians_of_the_contract():
    got = simulate_measurement(default_profile(), tau_up_ms=20.0, tau_down_ms=50.0,
                               delay_ms=8.0, seed=1, cells=[0, 1, 2])  # fmt: skip
    summary = got.summary()
    assert summary["tau_up_ms"] == pytest.approx(20.0, rel=TAU_REL)
    assert summary["tau_down_ms"] == pytest.approx(50.0, rel=TAU_REL)
    assert summary["delay_ms"] == pytest.approx(8.0, abs=DELAY_MS)
    assert [t["name"] for t in summary["tactors"]] == ["r0c0", "r0c1", "r0c2"]
    assert summary["seconds_per_tactor"] == pytest.approx(MeasurePlan().duration_s(8, 23))
