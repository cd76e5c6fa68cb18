"""Keeping the array's clock from clock exchanges (tactile_core.device.clock), against a model
array clock with a known offset and drift and random latencies either way."""

import numpy as np
import pytest

from tactile_core.device.clock import ArrayClock
from tactile_core.device.wire import CLOCK_WRAP, ClockReply

BYTE_S = 10 / 115200


class ModelArray:
    """An array clock: ``array_s = offset_s + (1 + drift) * host_s`` (wrapping in µs)."""

    def __init__(self, offset_s, drift_ppm):
        self.offset_s, self.drift = offset_s, drift_ppm * 1e-6

    def us(self, host_s):
        return round((self.offset_s + (1 + self.drift) * host_s) * 1e6) % CLOCK_WRAP

    def exchange(self, clock, t0, up_s, down_s, turnaround_s=100e-6):
        """A request written at t0 reaching the array up_s later (+ its bytes), the reply
        leaving turnaround_s later and read down_s after its bytes."""
        arrive = t0 + up_s + 6 * BYTE_S
        leave = arrive + turnaround_s
        t3 = leave + 23 * BYTE_S + down_s
        reply = ClockReply(0, self.us(arrive), self.us(leave), 0, 0, 0)
        return clock.add(t0, t3, reply)


def test_symmetric_latency_gives_the_offset_exactly():
    array = ModelArray(offset_s=12.345678, drift_ppm=0)
    clock = ArrayClock(byte_s=BYTE_S)
    sample = array.exchange(clock, t0=100.0, up_s=1e-3, down_s=1e-3)
    assert sample.offset_s == pytest.approx(12.345678, abs=1e-6)
    assert sample.delay_s == pytest.approx(2e-3, abs=2e-6)
    assert clock.to_array_us(100.5) == array.us(100.5)


def test_asymmetric_latency_errs_by_at_most_half_the_delay():
    array = ModelArray(offset_s=-3.0, drift_ppm=0)
    clock = ArrayClock(byte_s=BYTE_S)
    sample = array.exchange(clock, t0=50.0, up_s=4e-3, down_s=0.0)  # all of it one way
    assert abs(sample.offset_s - (-3.0)) == pytest.approx(2e-3, abs=2e-6)
    assert clock.error_s == pytest.approx(2e-3, abs=2e-6)


def test_the_least_delay_exchanges_win_over_many_slow_ones():
    rng = np.random.default_rng(1)
    array = ModelArray(offset_s=7.0, drift_ppm=0)
    clock = ArrayClock(byte_s=BYTE_S)
    for k in range(60):
        if k % 10 == 0:  # a quiet moment: 100 µs either way
            up, down = 100e-6, 100e-6
        else:  # a busy host: up to 20 ms, mostly on the way back
            up, down = rng.uniform(0, 2e-3), rng.uniform(0, 20e-3)
        array.exchange(clock, t0=k * 0.25, up_s=up, down_s=down)
    truth = 7.0
    assert abs(clock.offset_at(10.0) - truth) < 20e-6
    assert clock.error_s < 200e-6


def test_drift_is_estimated_and_followed():
    rng = np.random.default_rng(2)
    array = ModelArray(offset_s=1.0, drift_ppm=80.0)  # a crystal 80 ppm fast
    clock = ArrayClock(byte_s=BYTE_S)
    for k in range(64):
        t0 = k * 0.25
        array.exchange(clock, t0, rng.uniform(50e-6, 150e-6), rng.uniform(50e-6, 150e-6))
    assert clock.drift_ppm == pytest.approx(80.0, abs=5.0)
    later = 64 * 0.25 + 2.0  # 2 s after the last exchange
    error_us = abs(clock.to_array_us(later) - array.us(later))
    assert error_us < 100


def test_the_wrap_of_the_arrays_clock_is_invisible():
    array = ModelArray(offset_s=CLOCK_WRAP * 1e-6 - 0.5, drift_ppm=0)  # wraps 0.5 s in
    clock = ArrayClock(byte_s=BYTE_S)
    for k in range(8):
        array.exchange(clock, t0=k * 0.25, up_s=200e-6, down_s=200e-6)
    offsets = [s.offset_s for s in clock.samples]
    assert max(offsets) - min(offsets) < 1e-5  # unwrapped: no jump of 71.6 minutes
    for host_s in (0.1, 0.6, 1.9):
        assert clock.to_array_us(host_s) == pytest.approx(array.us(host_s), abs=2)
    at = array.us(1.0)
    assert clock.to_host(at, near_host_s=0.9) == pytest.approx(1.0, abs=2e-6)


def test_before_any_exchange_the_error_is_unbounded():
    clock = ArrayClock()
    assert not clock.synced and clock.error_s == float("inf")


def test_a_restarted_arrays_clock_is_a_jump_and_a_slow_or_paused_exchange_is_not():
    array = ModelArray(offset_s=40.0, drift_ppm=30.0)  # an array up for 40 s
    clock = ArrayClock(byte_s=BYTE_S)
    for k in range(40):
        array.exchange(clock, t0=k * 0.25, up_s=150e-6, down_s=150e-6)

    def measured(model, t0, up_s, down_s):
        arrive = t0 + up_s + 6 * BYTE_S
        t3 = arrive + 100e-6 + 23 * BYTE_S + down_s
        reply = ClockReply(0, model.us(arrive), model.us(arrive + 100e-6), 0, 0, 0)
        return clock.measure(t0, t3, reply)

    # an answer held up 300 ms on its way back, a host paused 2 s with a request out: both only
    # widen what the exchange can say (half its delay), neither is a jump
    assert clock.jump_s(measured(array, 10.0, 150e-6, 0.3)) == 0.0
    assert clock.jump_s(measured(array, 10.25, 2.0, 150e-6)) == 0.0
    assert clock.jump_s(measured(array, 10.5, 150e-6, 150e-6)) == 0.0
    # the array starts again at host time 10.6: its clock reads 0 there where the old one would
    # have read 40 s + 10.6 s (the same crystal: the drifts cancel)
    restarted = ModelArray(offset_s=-10.6, drift_ppm=30.0)
    jump = clock.jump_s(measured(restarted, 10.75, 150e-6, 150e-6))
    assert jump == pytest.approx(-(40.0 + 10.6), abs=1e-3)
    assert len(clock.samples) == 40  # measuring records nothing
