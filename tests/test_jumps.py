"""The largest jump of a method as the point moves: sizes worked by hand from the methods'
definitions (PK's switch at a square's centre, the threshold's step for AS)."""

import math

import pytest

from tactile_core.rendering.jumps import largest_jump


def test_bilevel_methods_jump_by_full_intensity():
    assert largest_jump("CT") == 1.0 and largest_jump("MM") == 1.0


def test_pk_jumps_by_its_weight_at_a_squares_centre():
    # At a cell corner all four tactors are at sqrt(1/2): three of them lit, sqrt(1/3) each;
    # the path through the corners switches one of them off as another comes on.
    assert largest_jump("PK") == pytest.approx(math.sqrt(1 / 3), abs=1e-3)
    assert largest_jump("PK:blend=0.2") < 0.01


def test_smooth_methods_do_not_jump_until_the_threshold_lifts_them():
    for method in ("AS", "IM", "RO", "RO:curve=linear"):
        assert largest_jump(method) < 1e-3, method
    # mu lifts a tactor from 0 to mu as it comes on: AS jumps by 0.33 (+ 0.67 I^0.7, I tiny).
    assert largest_jump("AS", 0.33, 0.7) == pytest.approx(0.33, abs=0.01)
