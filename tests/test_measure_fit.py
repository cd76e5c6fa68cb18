"""The measurement's analysis core on hand-made signals: the first-order model, the plan, the
commands read back from frames, the envelope, the fit and the sample clock."""

import math

import numpy as np
import pytest

from tactile_core.device.measure import (
    Commands,
    MeasurePlan,
    PlanFrames,
    bandpass,
    commands_from_frames,
    envelope,
    first_order,
    fit_envelope,
    fit_sample_clock,
    peaks,
)
from tactile_core.device.measure._response import hat_basis
from tactile_core.rendering.motor import MotorResponse


def test_first_order_step_up_and_down_by_hand():
    # up from rest at t = 0 to drive 0.8 with tau 10 ms, down at t = 0.1 with tau 20 ms
    t = np.array([0.0, 0.01, 0.02, 0.1, 0.12, 0.14])
    s = first_order(t, [0.0, 0.1], [0.8, 0.0], tau_up_s=0.01, tau_down_s=0.02)
    at_down = 0.8 * (1 - math.exp(-10))
    expected = [0.0, 0.8 * (1 - math.exp(-1)), 0.8 * (1 - math.exp(-2)), at_down,
                at_down * math.exp(-1), at_down * math.exp(-2)]  # fmt: skip
    np.testing.assert_allclose(s, expected, atol=1e-12)


def test_first_order_agrees_with_the_percept_models_motor_frame_by_frame():
    # MotorResponse.effective solves the same lag frame by frame (its own code): the state at
    # the end of each frame must be the continuous solution at that time
    rng = np.random.default_rng(4)
    rate = 300.0
    drive = np.repeat(rng.choice([0.0, 0.3, 0.7, 1.0], 40), 9)[:, None]
    motor = MotorResponse(0.03, 0.06)
    ends = []
    state = None
    for k in range(drive.shape[0]):
        _, end = motor.effective(drive[k : k + 1], rate, state)
        state = end
        ends.append(end[0])
    changes = np.flatnonzero(np.r_[True, np.diff(drive[:, 0]) != 0])
    s = first_order((np.arange(drive.shape[0]) + 1) / rate, changes / rate, drive[changes, 0],
                    tau_up_s=0.03, tau_down_s=0.06, start_s=0.0)  # fmt: skip
    np.testing.assert_allclose(s, ends, atol=1e-12)


def test_hat_basis_adds_up_to_the_piecewise_linear_curve():
    nodes = np.array([0.0, 0.25, 0.5, 1.0])
    inc = np.array([0.1, 0.4, 0.5])  # curve 0, 0.1, 0.5, 1.0 at the nodes
    s = np.array([0.0, 0.125, 0.25, 0.375, 0.75, 1.0])
    np.testing.assert_allclose(hat_basis(s, nodes) @ inc, [0.0, 0.05, 0.1, 0.3, 0.75, 1.0])


def test_plan_block_lasts_as_its_parts_add_up():
    plan = MeasurePlan()
    # silence, 9 scan pulses, the rest after them, 5 steps, 22 ramp levels and a rest,
    # 5 pulses (the last without its gap), the tail
    by_hand = (0.4 + 9 * 0.35 + (0.5 - 0.25) + 5 * (0.4 + 0.5) + 22 * 0.15 + 0.5
               + 4 * 0.34 + 0.04 + 0.5)  # fmt: skip
    assert plan.duration_s(8, 23) == pytest.approx(by_hand)
    assert plan.step_levels(23) == (8, 11, 14, 18, 22)
    assert plan.ramp_levels(23) == tuple(range(1, 23))
    assert plan.ramp_levels(256) == tuple(round(x) for x in np.linspace(255 / 22, 255, 22))


def test_plan_frames_hold_each_commanded_level_from_its_frame_on():
    commands = Commands(np.array([0.0, 0.01, 0.02]), np.array([3, 3, 5]), np.array([22, 0, 11]))
    frames = PlanFrames(commands, levels=23, rate_hz=100.0)
    assert frames.entries(0) == ((3, 1.0),)
    assert frames.entries(1) == ()
    assert frames.entries(2) == ((5, 0.5),)
    assert frames.entries(50) == ((5, 0.5),)


def test_commands_from_frames_keeps_only_changes_per_channel():
    t = np.array([0.0, 0.1, 0.2, 0.3])
    levels = np.array([[0, 5], [3, 5], [3, 0], [3, 0]])
    got = commands_from_frames(t, levels, cells=[7, 2])
    np.testing.assert_array_equal(got.time_s, [0.0, 0.1, 0.2])
    np.testing.assert_array_equal(got.cell, [2, 7, 2])
    np.testing.assert_array_equal(got.level, [5, 3, 0])
    _change, drive = got.of(2, top=10)
    np.testing.assert_array_equal(drive, [0.5, 0.0])


def test_envelope_of_a_steady_sinusoid_is_its_squared_amplitude():
    sr = 8000
    t = np.arange(sr) / sr
    x = 0.3 * np.sin(2 * np.pi * 150.0 * t)
    env = envelope(bandpass(x, sr), sr)
    middle = env.window(0.2, 0.8)
    np.testing.assert_allclose(env.power[middle], 0.09, rtol=0.01)
    (f, a), *_ = peaks(x[2000:6000], sr)
    assert f == pytest.approx(150.0, abs=0.2)
    assert a == pytest.approx(0.3, rel=0.02)


@pytest.mark.parametrize(
    "delay_s, up_s, down_s",
    [(0.002, 0.01, 0.02), (0.005, 0.03, 0.06), (0.02, 0.1, 0.2), (0.0, 0.03, 0.03)],
)
def test_fit_recovers_constants_and_curve_from_an_exact_envelope(delay_s, up_s, down_s):
    plan = MeasurePlan()
    commands = plan.commands(0, (), 23)
    change, drive = commands.of(0, 22)
    t = np.arange(1.0, plan.duration_s(0), 0.001)
    curve = (np.array([0.0, 0.2, 0.5, 1.0]), np.array([0.0, 0.0, 0.6, 1.0]))  # a dead zone
    s = first_order(t, change + delay_s, drive, tau_up_s=up_s, tau_down_s=down_s, start_s=0)
    a = 0.25 * np.interp(s, *curve)
    nodes = np.arange(23) / 22
    fit = fit_envelope(t, a, change, drive, nodes)
    assert fit.delay_s == pytest.approx(delay_s, abs=2e-4)
    assert fit.tau_up_s == pytest.approx(up_s, rel=0.02)
    assert fit.tau_down_s == pytest.approx(down_s, rel=0.02)
    # the curve between nodes is linear; at the nodes it is the true one
    np.testing.assert_allclose(fit.amplitude, 0.25 * np.interp(nodes, *curve), atol=0.01)
    assert fit.residual < 0.02


def test_sample_clock_lies_under_the_earliest_arrivals_and_follows_drift():
    # blocks of 256 samples from an interface 100 ppm fast, each arriving 0.2-5 ms late
    rng = np.random.default_rng(1)
    sr, true_start, ratio = 48000, 10.0, 1.0 - 1e-4
    end = np.arange(1, 2000) * 256
    arrival = true_start + end / sr * ratio + rng.uniform(0.0002, 0.005, end.size)
    start, got = fit_sample_clock(end, arrival, sr)
    assert got == pytest.approx(ratio, abs=2e-5)
    assert true_start <= start <= true_start + 0.0006
