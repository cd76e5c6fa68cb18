"""The output thread's cursor: which frame is due, and how a stall is skipped, worked by hand."""

import pytest

from tactile_core.device.profile import default_profile
from tactile_core.rendering.scene import Scene
from tactile_core.rendering.shapes import Circle
from tactile_core.stream._plan import Cursor, _Plan, restarts

CIRCLE = Circle((2.5, 3.0), 2.0)


def plan_at(rate_hz):
    return _Plan(Scene(CIRCLE, rate_hz=rate_hz), default_profile(), 20.0, None, 0.0)


def test_a_frame_on_time_moves_the_deadline_and_the_trace_by_one_tick():
    cur = Cursor(plan=plan_at(100.0), deadline=1.0, trace_time=0.5)
    assert cur.frame_index() == 50  # 0.5 s at 100 Hz
    missed, behind = cur.advance(now_s=1.004)  # sent 4 ms after its deadline
    assert missed == 0 and cur.deadline == pytest.approx(1.01)
    assert cur.trace_time == pytest.approx(0.51) and behind == pytest.approx(-0.006)


def test_a_stall_skips_the_missed_deadlines_and_keeps_the_trace_time_moving():
    cur = Cursor(plan=plan_at(100.0), deadline=1.0, trace_time=0.0, last_sent=0.99)
    # the host came back 55 ms after the deadline: the next was due at 1.01, so 45 ms behind,
    # 4 whole ticks missed (floor(0.045 / 0.01)); the deadline lands at 1.05, the trace at 0.05
    missed, behind = cur.advance(now_s=1.055)
    assert missed == 4 and behind == pytest.approx(0.045)
    assert cur.deadline == pytest.approx(1.05) and cur.trace_time == pytest.approx(0.05)
    assert cur.last_sent is None  # the interval across the stall is not a frame interval


def test_a_new_shape_restarts_the_trace_and_new_mu_goes_on():
    a = Scene(CIRCLE, mu=0.2)
    assert not restarts(a, a.replace(mu=0.4))
    assert restarts(a, a.replace(shape=Circle((2.5, 3.0), 1.0)))
    assert restarts(None, a) and restarts(a, None)
