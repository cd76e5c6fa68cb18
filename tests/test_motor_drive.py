"""Motor-aware drive: the inverse of the first-order motor over one frame, worked by hand from
``s(dt) = d + (s0 - d) exp(-dt / tau)``; the live path against the batch one; and the bound it
keeps against plain drive when the motors' time constants are wrong."""

import math

import numpy as np
import pytest

from tactile_core.rendering.motor import MotorResponse
from tactile_core.rendering.motor_drive import REST, LiveMotorDrive, motor_drive

RATE = 300.0
DT = 1.0 / RATE
E_UP = math.exp(-DT / 0.030)  # 0.8948: what is left of a gap after one 3.33 ms frame, 30 ms
E_DOWN = math.exp(-DT / 0.060)


def _end_states(drive, motor, rate=RATE):
    """The effective drive at the end of every frame, by the motor model itself."""
    s = np.zeros(drive.shape[1])
    out = []
    for frame in drive:
        _, s = motor.effective(frame[None, :], rate, state=s)
        out.append(s)
    return np.array(out)


def test_a_step_to_half_is_full_drive_until_the_motor_can_get_there_then_half():
    motor = MotorResponse(0.030, 0.060)
    step = np.array([[0.5]] * 10 + [[0.0]])
    sent, _ = motor_drive(step, motor, RATE)
    # Frame 1 by hand: d = (0.5 - 0 * e) / (1 - e) = 0.5 / 0.10516 = 4.755: clamped to 1.
    inverse = (0.5 - 0.0 * E_UP) / (1 - E_UP)
    assert round(inverse, 3) == 4.755 and sent[0, 0] == 1.0
    # At full drive the motor is at 1 - e^k after k frames: 0.4866 after 6 (< 0.5), so frames
    # 1-6 are clamped; frame 7 needs (0.5 - s6 e) / (1 - e), below 1.
    s6 = 1 - E_UP**6
    assert s6 == pytest.approx(0.4866, abs=1e-4)
    np.testing.assert_array_equal(sent[:6, 0], 1.0)
    assert sent[6, 0] == pytest.approx((0.5 - s6 * E_UP) / (1 - E_UP))
    assert sent[6, 0] == pytest.approx(0.614, abs=1e-3)
    # From then on the effective drive is on target at every frame's end, held by d = 0.5.
    ends = _end_states(sent, motor)[:, 0]
    np.testing.assert_allclose(ends[6:10], 0.5, atol=1e-12)
    np.testing.assert_allclose(sent[7:10, 0], 0.5, atol=1e-12)
    # The run-down frame: the target is 0, the inverse negative, the drive off.
    assert (0.0 - 0.5 * E_DOWN) / (1 - E_DOWN) < 0 and sent[10, 0] == 0.0
    assert ends[10] == pytest.approx(0.5 * E_DOWN)


def test_an_unclamped_step_is_on_target_after_one_frame():
    # 0.05 above a motor running at 0.3 needs d = (0.35 - 0.3 e) / (1 - e) = 0.7755 < 1.
    motor = MotorResponse(0.030, 0.060)
    sent, end = motor_drive([[0.35]], motor, RATE, state=[0.3])
    assert sent[0, 0] == pytest.approx((0.35 - 0.3 * E_UP) / (1 - E_UP))
    assert sent[0, 0] == pytest.approx(0.7755, abs=1e-4)
    assert end[0] == pytest.approx(0.35)
    # And down: 0.34 from 0.35 with tau_down 60 ms: d = (0.34 - 0.35 e) / (1 - e) = 0.165.
    sent, end = motor_drive([[0.34]], motor, RATE, state=[0.35])
    assert sent[0, 0] == pytest.approx((0.34 - 0.35 * E_DOWN) / (1 - E_DOWN))
    assert sent[0, 0] == pytest.approx(0.165, abs=1e-3) and end[0] == pytest.approx(0.34)
    # 0.30 from 0.35 is beyond one frame of coasting (0.35 (1 - e) = 0.019): off, and the
    # motor ends where coasting takes it.
    sent, end = motor_drive([[0.30]], motor, RATE, state=[0.35])
    assert sent[0, 0] == 0.0 and end[0] == pytest.approx(0.35 * E_DOWN)


def test_an_ideal_motor_leaves_the_drive_unchanged():
    drive = np.random.default_rng(1).random((40, 30))
    drive[drive < 0.3] = 0.0
    sent, end = motor_drive(drive, MotorResponse(0.0, 0.0), RATE)
    np.testing.assert_array_equal(sent, drive)
    np.testing.assert_array_equal(end, drive[-1])
    live = LiveMotorDrive(MotorResponse(0.0, 0.0), 30)
    live.set_rate(RATE)
    for frame in drive:
        entries = [(int(i), float(frame[i])) for i in np.flatnonzero(frame)]
        assert live.frame(entries) == entries


def test_zero_stays_zero_for_tactors_never_lit():
    frames = np.zeros((50, 6, 5))
    frames[:20, 2, 3] = 0.6  # one tactor lit, then dark
    sent, end = motor_drive(frames, MotorResponse(0.030, 0.060), RATE)
    others = np.ones((6, 5), dtype=bool)
    others[2, 3] = False
    assert (sent[:, others] == 0.0).all() and (end.reshape(6, 5)[others] == 0.0).all()
    assert (sent[20:, 2, 3] == 0.0).all()  # dark: off while it runs down
    live = LiveMotorDrive(MotorResponse(0.030, 0.060), 30)
    live.set_rate(RATE)
    live.frame([(13, 0.6)])
    assert set(live.state) == {13}  # only the lit tactor carries state


def test_a_dark_tactor_is_forgotten_once_it_has_run_down():
    live = LiveMotorDrive(MotorResponse(0.030, 0.060), 30)
    live.set_rate(RATE)
    for _ in range(30):
        live.frame([(4, 0.8)])
    s = live.state[4]
    # Dark from here: s e_down^k; it is dropped at the first k where that is <= REST.
    k_rest = math.ceil(math.log(REST / s) / math.log(E_DOWN))
    for k in range(1, k_rest):
        assert live.frame([]) == [] and live.state[4] == pytest.approx(s * E_DOWN**k)
    live.frame([])
    assert live.state == {}


def test_per_tactor_time_constants_are_each_tactors_own():
    taus = tuple(0.01 * (1 + i) for i in range(30))
    motor = MotorResponse(taus, 0.05)
    frames = np.zeros((1, 30))
    frames[0, [0, 20]] = 0.4
    sent, _ = motor_drive(frames, motor, 100.0)
    for i in (0, 20):  # d = 0.4 / (1 - exp(-0.01 / tau_i)), clamped
        assert sent[0, i] == pytest.approx(min(1.0, 0.4 / (1 - math.exp(-0.01 / taus[i]))))
    # tau 10 ms: 0.4 / (1 - e^-1) = 0.633; tau 210 ms: 0.4 / 0.0465, clamped
    assert sent[0, 0] == pytest.approx(0.633, abs=1e-3) and sent[0, 20] == 1.0


def test_the_live_path_gives_the_batch_drive():
    rng = np.random.default_rng(7)
    drive = rng.choice([0.0, 0.0, 0.33, 0.5, 0.8, 1.0], size=(300, 30))
    drive[100:140] = 0.0  # everything dark for a while: states run down and are dropped
    motor = MotorResponse(0.030, 0.060)
    sent, end = motor_drive(drive, motor, RATE)
    live = LiveMotorDrive(motor, 30)
    live.set_rate(RATE)
    for k, frame in enumerate(drive):
        entries = [(int(i), float(frame[i])) for i in np.flatnonzero(frame)]
        got = live.frame(entries)
        assert [c for c, _ in got] == [c for c, _ in entries]
        np.testing.assert_allclose([d for _, d in got], sent[k, frame > 0], rtol=0, atol=1e-12)
    final = np.zeros(30)
    final[list(live.state)] = list(live.state.values())
    np.testing.assert_allclose(final, end, atol=1e-12)


def test_skipped_frames_hold_the_last_drive_and_a_pause_coasts():
    motor = MotorResponse(0.030, 0.060)
    live = LiveMotorDrive(motor, 30)
    live.set_rate(RATE)
    live.frame([(0, 0.5)])  # full drive: the motor at 1 - e after it
    live.frame([(0, 0.5)], held_frames=3)  # that drive held for 3 frames, then this one
    expected = np.array([[1.0], [1.0], [1.0]])
    _, s3 = motor.effective(expected, RATE)
    d = min(1.0, (0.5 - s3[0] * E_UP) / (1 - E_UP))
    assert live.state[0] == pytest.approx(d + (s3[0] - d) * E_UP)
    s = live.state[0]
    live.coast(0.1)  # off for 100 ms: s exp(-0.1 / 0.06)
    assert live.state[0] == pytest.approx(s * math.exp(-0.1 / 0.060))


def test_bad_input_is_refused_by_name():
    motor = MotorResponse(0.03, 0.06)
    with pytest.raises(ValueError, match=r"drive must hold fractions .* got 1\.5"):
        motor_drive([[1.5]], motor, RATE)
    with pytest.raises(ValueError, match="rate_hz"):
        motor_drive([[0.5]], motor, 0.0)
    with pytest.raises(ValueError, match="motor must be a MotorResponse"):
        motor_drive([[0.5]], (0.03, 0.06), RATE)
    with pytest.raises(ValueError, match="state must hold 1"):
        motor_drive([[0.5]], motor, RATE, state=[0.2, 0.3])
    with pytest.raises(ValueError, match="set_rate first"):
        LiveMotorDrive(motor, 30).frame([(0, 0.5)])


def test_the_felt_onset_is_solved_within_the_frame():
    # From rest at full drive with tau_up 30 ms the effective drive is 1 - exp(-t / 0.03):
    # above 0.2 at t = 0.03 ln(1 / 0.8) = 6.69 ms, inside the third 3.33 ms frame.
    motor = MotorResponse(0.030, 0.060)
    onsets = motor.onsets_s(np.ones((5, 2)) * [1.0, 0.1], RATE, 0.2)
    assert onsets[0] == pytest.approx(0.030 * math.log(1 / 0.8))
    assert onsets[1] == np.inf  # held at 0.1: never above 0.2
    assert MotorResponse(0.0, 0.0).onsets_s(np.array([[0.0], [0.5]]), RATE, 0.2)[0] == DT


@pytest.mark.parametrize("factor", [0.5, 1.0, 2.0])
@pytest.mark.parametrize("method", ["AS", "IM", "CT", "MM"])
@pytest.mark.parametrize("shape", ["line", "circle"])
@pytest.mark.parametrize("taus", [(0.030, 0.060), (0.100, 0.200)])
def test_motor_aware_drive_is_never_worse_than_plain_by_more_than_the_bound(taus, shape, method,
                                                                            factor):  # fmt: skip
    from tactile_core.bench import BOUND_LAG_MM, BOUND_ONSET_MS, BOUND_RIPPLE, SCENES, felt_effect

    profile = MotorResponse(*taus)
    true = MotorResponse(taus[0] * factor, taus[1] * factor)
    plain = felt_effect(SCENES[shape], method, true, None)
    aware = felt_effect(SCENES[shape], method, true, profile)
    assert aware.ripple <= plain.ripple + BOUND_RIPPLE
    assert aware.lag_mm <= plain.lag_mm + BOUND_LAG_MM
    assert aware.onset_ms <= plain.onset_ms + BOUND_ONSET_MS
    assert aware.missed <= plain.missed
    if factor == 1.0 and method in ("AS", "IM"):  # right constants: onset and lag improve
        assert aware.lag_mm < plain.lag_mm and aware.onset_ms < plain.onset_ms / 2
        if taus[0] == 0.030:  # and at the palm array's constants the ripple too
            assert aware.ripple < plain.ripple
    if method in ("CT", "MM"):  # at full drive already: nothing to overdrive, the same drive
        assert aware == plain
