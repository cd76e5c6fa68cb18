"""The predicted percept: felt intensity and felt centroid under energy summation, worked by
hand at chosen points, and the identity that makes AS and IM even."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.rendering.percept import PITCH_MM, predict


def still(x, y):
    """A point held still: a zero-length line."""
    return tc.Line((x, y), (x, y))


def test_one_tactor_at_full_drive_is_felt_as_one_at_its_centre():
    p = predict(still(1.5, 2.5), "CT", 0.33, 0.7, samples=3)
    np.testing.assert_allclose(p.felt, 1.0)
    np.testing.assert_allclose(p.centroid, [[1.5, 2.5]] * 3)
    np.testing.assert_allclose(p.error_mm, 0.0)
    # CT off the centre: the centroid stays on the tactor; the error is the distance to it.
    p = predict(still(1.8, 2.9), "CT", 0.33, 0.7, samples=2)
    np.testing.assert_allclose(p.error_mm, math.hypot(0.3, 0.4) * PITCH_MM)


def test_as_at_a_cell_corner_worked_by_hand():
    # mu 0, gamma 1, the matched participant TH 0, K 1/2: each of the four tactors gets 1/4,
    # felt as (1/4)^(1/2) = 1/2; M = sqrt(4 x 1/4) = 1; the centroid is the corner.
    p = predict(still(2.0, 3.0), "AS", 0.0, 1.0, samples=2)
    np.testing.assert_allclose(p.felt, 1.0)
    np.testing.assert_allclose(p.centroid, [[2.0, 3.0]] * 2, atol=1e-12)
    # A quarter of the way up from tactor (2,2) to (2,3): areas 3/4 and 1/4, felt sqrt(3)/2 and
    # 1/2; the centroid's y is (2.5 sqrt(3)/2 + 3.5 / 2) / (sqrt(3)/2 + 1/2).
    p = predict(still(2.5, 2.75), "AS", 0.0, 1.0, samples=2)
    a, b = math.sqrt(3) / 2, 0.5
    y = (2.5 * a + 3.5 * b) / (a + b)
    np.testing.assert_allclose(p.centroid[0], [2.5, y])
    assert p.error_mm[0] == pytest.approx(abs(y - 2.75) * PITCH_MM)


def test_en_ripple_from_a_centre_to_a_corner_is_root_two():
    # Along the diagonal from tactor (1,2)'s centre to the corner (2,3) the point is f = t / 2
    # of a pitch past the centre on both axes; EN drives sqrt(a_i) with a = (1-f)^2, f(1-f),
    # f(1-f), f^2; at mu 0, gamma 1 the matched participant feels m_i = a_i^(1/4), so
    # M^2 = sum sqrt(a_i) = 1 + 2 sqrt(f(1-f)): 1 at the centre, sqrt(2) at the corner.
    p = predict(tc.Line((1.5, 2.5), (2.0, 3.0)), "EN", 0.0, 1.0, samples=101)
    f = np.linspace(0, 1, 101) / 2
    np.testing.assert_allclose(p.felt, np.sqrt(1 + 2 * np.sqrt(f * (1 - f))), atol=1e-12)
    assert p.ripple == pytest.approx(math.sqrt(2))


@settings(max_examples=30, deadline=None)
@given(st.floats(0.0, 0.8), st.floats(0.2, 3.0), st.sampled_from(["AS", "IM"]))
def test_as_and_im_feel_even_for_the_matched_participant(mu, gamma, method):
    for shape in (tc.Line((0.5, 1.84), (4.5, 4.16)), tc.Circle((2.5, 3.0), 2.0)):
        p = predict(shape, method, mu, gamma, samples=501)
        assert p.ripple == pytest.approx(1.0, abs=1e-9)


def test_a_mismatched_participant_feels_the_papers_correction_unevenly():
    # A participant with K = 1 (the matched one would have K = 1 / 1.4). Midway between two
    # tactors AS gives each 0.5, driven at d = 0.33 + 0.67 x 0.5^0.7 and felt as
    # (d - 0.33) / 0.67 = 0.5^0.7 each: M = sqrt(2) 0.5^0.7 = 0.87, below the 1 on a tactor.
    p = predict(still(2.5, 3.0), "AS", 0.33, 0.7, threshold=0.33, exponent=1.0, samples=2)
    np.testing.assert_allclose(p.felt, math.sqrt(2) * 0.5**0.7)
    line = predict(tc.Line((0.5, 1.84), (4.5, 4.16)), "AS", 0.33, 0.7, threshold=0.33,
                   exponent=1.0)  # fmt: skip
    assert line.felt.max() <= 1.0 and line.ripple > 1.15  # 0.96 near a centre, 0.76 near a corner


def test_nothing_felt_is_no_centroid_and_an_infinite_ripple():
    # mu 0.5 and a participant whose threshold is 0.9: nothing below 0.9 is felt; AS at the
    # corner drives 0.5 + 0.5 x 0.25 = 0.625 per tactor.
    p = predict(still(2.0, 3.0), "AS", 0.5, 1.0, threshold=0.9, exponent=1.0, samples=2)
    assert (p.felt == 0).all() and np.isnan(p.centroid).all()
    assert p.ripple == math.inf and math.isnan(p.mean_error_mm)


def test_bad_input_is_refused_by_name():
    line = tc.Line((0.5, 1.84), (4.5, 4.16))
    for kwargs, name in [({"threshold": 1.5}, "threshold"), ({"exponent": 0}, "exponent"),
                         ({"samples": 1}, "samples"), ({"pitch_mm": -1}, "pitch_mm")]:  # fmt: skip
        with pytest.raises(ValueError, match=name):
            predict(line, "AS", 0.33, 0.7, **kwargs)
    with pytest.raises(ValueError, match="method"):
        predict(line, "NOPE", 0.33, 0.7)
