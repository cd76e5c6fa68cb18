"""The first-order motor model and the device profile's ``motor`` field: step responses worked
from the differential equation's solution, integrated numerically as an independent check."""

import json
import math

import numpy as np
import pytest

from tactile_core._shared.assets import asset_path
from tactile_core.device._device_profile import profile_from_dict
from tactile_core.device.profile import ProfileError, default_profile
from tactile_core.rendering.motor import MotorResponse


def test_a_step_rises_as_one_minus_exp_and_falls_with_the_other_constant():
    motor = MotorResponse(0.03, 0.06)
    rate = 300.0
    drive = np.zeros((60, 2))
    drive[:30, 0] = 1.0  # 100 ms on, then off
    mean, end = motor.effective(drive, rate)
    dt = 1 / rate
    # Mean over frame k of 1 - exp(-t / tau) for t in [k dt, (k + 1) dt].
    k = np.arange(30)
    rise = 1 - (0.03 / dt) * (np.exp(-k * dt / 0.03) - np.exp(-(k + 1) * dt / 0.03))
    np.testing.assert_allclose(mean[:30, 0], rise, rtol=1e-12)
    top = 1 - math.exp(-30 * dt / 0.03)
    j = np.arange(30)
    fall = top * (0.06 / dt) * (np.exp(-j * dt / 0.06) - np.exp(-(j + 1) * dt / 0.06))
    np.testing.assert_allclose(mean[30:, 0], fall, rtol=1e-12)
    assert end[0] == pytest.approx(top * math.exp(-30 * dt / 0.06))
    assert (mean[:, 1] == 0).all() and end[1] == 0  # never driven: at rest, not simulated


def test_the_exact_solution_matches_a_fine_euler_integration():
    rng = np.random.default_rng(3)
    drive = rng.choice([0.0, 0.3, 0.7, 1.0], size=(40, 3))
    motor = MotorResponse((0.01, 0.03, 0.05), (0.04, 0.02, 0.08))
    mean, _ = motor.effective(drive, 200.0)
    steps = 2000  # per frame
    h = 1 / 200.0 / steps
    up, down = np.array([0.01, 0.03, 0.05]), np.array([0.04, 0.02, 0.08])
    s = np.zeros(3)
    ref = np.zeros_like(drive)
    for k, d in enumerate(drive):
        acc = np.zeros(3)
        for _ in range(steps):
            tau = np.where(d > s, up, down)
            s = s + (d - s) * h / tau
            acc += s
        ref[k] = acc / steps
    np.testing.assert_allclose(mean, ref, atol=2e-3)


def test_an_ideal_motor_follows_its_drive():
    drive = np.random.default_rng(0).random((10, 4))
    mean, end = MotorResponse(0.0, 0.0).effective(drive, 300.0)
    np.testing.assert_array_equal(mean, drive)
    np.testing.assert_array_equal(end, drive[-1])


def test_bad_time_constants_are_refused_by_name():
    with pytest.raises(ValueError, match="tau_up_s"):
        MotorResponse(-0.01, 0.05)
    with pytest.raises(ValueError, match="tau_down_s must hold 1 or 30"):
        MotorResponse(0.01, (0.05, 0.06)).taus(30)


def test_the_palm_profile_carries_estimated_time_constants():
    profile = default_profile()
    assert profile.motor.tau_up_s == 0.030 and profile.motor.tau_down_s == 0.060
    assert "estimates" in profile.motor.note
    again = profile_from_dict(profile.to_dict())
    assert again.motor == profile.motor


def test_the_motor_field_is_checked_and_takes_a_table_per_tactor():
    data = json.loads(asset_path("devices", "palm-5x6.json").read_text())
    data["motor"] = {"tau_up_ms": [[10 + c + 5 * r for c in range(5)] for r in range(6)],
                     "tau_down_ms": 50}  # fmt: skip
    motor = profile_from_dict(data).motor
    assert motor.tau_up_s[7] == pytest.approx(0.017)  # row 1, col 2: 10 + 2 + 5
    for bad, message in [({"tau_up_ms": -1, "tau_down_ms": 5}, "motor.tau_up_ms"),
                         ({"tau_up_ms": 5}, "tau_down_ms' is missing"),
                         ({"tau_up_ms": [1, 2], "tau_down_ms": 5}, "must hold 30"),
                         ("fast", "'motor' must be an object")]:  # fmt: skip
        data["motor"] = bad
        with pytest.raises(ProfileError, match=message):
            profile_from_dict(data)


def test_activation_curves_felt_through_per_tactor_motors():
    import tactile_core as tc
    from tactile_core.rendering.curves import activation_curves

    taus = tuple(0.01 * (1 + i) for i in range(30))  # tactor i: (i + 1) x 10 ms
    motor = MotorResponse(taus, 0.05)
    curves = activation_curves(tc.Line((0.5, 2.5), (4.5, 2.5)), "CT", samples=401, motor=motor)
    assert curves.felt.shape == curves.corrected.shape
    # Each curve goes through its own tactor's motor: the first, (0,2) = flat 10, rises with
    # tau 0.11 s from rest over samples 5 ms apart.
    first = 10
    assert curves.cells[0] == (0, 2)
    dt = 2.0 / 400
    expected = 1 - (taus[first] / dt) * (1 - math.exp(-dt / taus[first]))
    assert curves.felt[0, 0] == pytest.approx(expected)
