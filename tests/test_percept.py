"""The predicted percept: felt intensity and the felt-energy centroid under energy summation,
worked by hand at chosen points; the identity that makes AS and IM even for the participant a
correction is tailored to (and only for that one); predictions from what is sent."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.rendering.percept import PITCH_MM, predict, tailored


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
    p = predict(still(2.0, 3.0), "AS", 0.0, 1.0, threshold=0.0, exponent=0.5, samples=2)
    np.testing.assert_allclose(p.felt, 1.0)
    np.testing.assert_allclose(p.centroid, [[2.0, 3.0]] * 2, atol=1e-12)
    # A quarter of the way up from tactor (2,2) to (2,3): areas 3/4 and 1/4, felt sqrt(3)/2 and
    # 1/2, felt energies 3/4 and 1/4: the energy-weighted centroid is the point itself.
    p = predict(still(2.5, 2.75), "AS", 0.0, 1.0, threshold=0.0, exponent=0.5, samples=2)
    np.testing.assert_allclose(p.centroid[0], [2.5, 2.75])
    assert p.error_mm[0] == pytest.approx(0.0, abs=1e-9)


def test_the_centroid_is_weighted_by_felt_energy():
    # The linear-energy participant (TH 0, K 1) at the same point: m = 3/4 and 1/4, energies
    # 9/16 and 1/16: y = (2.5 x 9 + 3.5 x 1) / 10 = 2.6, 0.15 pitches from the point (the
    # energy model's location rule beta = A2^2 / (A1^2 + A2^2) = 1/10 of the way up).
    p = predict(still(2.5, 2.75), "AS", 0.0, 1.0, threshold=0.0, exponent=1.0, samples=2)
    np.testing.assert_allclose(p.centroid[0], [2.5, 2.6])
    assert p.error_mm[0] == pytest.approx(0.15 * PITCH_MM)
    assert p.felt[0] == pytest.approx(math.sqrt(10) / 4)


def test_the_linear_energy_participant_feels_as_and_im_uneven():
    # No correction, TH 0, K 1: at a cell corner AS's four quarters give M = sqrt(4/16) = 1/2;
    # midway between two tactors IM's halves give sqrt(1/2); on a tactor both give 1.
    corner = predict(still(2.0, 3.0), "AS", 0.0, 1.0, threshold=0.0, exponent=1.0, samples=2)
    np.testing.assert_allclose(corner.felt, 0.5)
    mid = predict(tc.Line((1.5, 2.5), (2.5, 2.5)), "IM", 0.0, 1.0, threshold=0.0, exponent=1.0,
                  samples=3)  # fmt: skip
    np.testing.assert_allclose(mid.felt, [1.0, math.sqrt(0.5), 1.0])
    assert mid.ripple == pytest.approx(math.sqrt(2))


def test_en_ripple_from_a_centre_to_a_corner_is_root_two():
    # Along the diagonal from tactor (1,2)'s centre to the corner (2,3) the point is f = t / 2
    # of a pitch past the centre on both axes; EN drives sqrt(a_i) with a = (1-f)^2, f(1-f),
    # f(1-f), f^2; at mu 0, gamma 1 the matched participant feels m_i = a_i^(1/4), so
    # M^2 = sum sqrt(a_i) = 1 + 2 sqrt(f(1-f)): 1 at the centre, sqrt(2) at the corner.
    p = predict(tc.Line((1.5, 2.5), (2.0, 3.0)), "EN", 0.0, 1.0, threshold=0.0, exponent=0.5,
                samples=101)  # fmt: skip
    f = np.linspace(0, 1, 101) / 2
    np.testing.assert_allclose(p.felt, np.sqrt(1 + 2 * np.sqrt(f * (1 - f))), atol=1e-12)
    assert p.ripple == pytest.approx(math.sqrt(2))


@settings(max_examples=30, deadline=None)
@given(st.floats(0.0, 0.8), st.floats(0.2, 3.0), st.sampled_from(["AS", "IM"]))
def test_as_and_im_feel_even_for_the_matched_participant(mu, gamma, method):
    who = tailored(mu, gamma)
    for shape in (tc.Line((0.5, 1.84), (4.5, 4.16)), tc.Circle((2.5, 3.0), 2.0)):
        p = predict(shape, method, mu, gamma, threshold=who.threshold, exponent=who.exponent,
                    samples=501)  # fmt: skip
        # exact but for rounding: a level just above mu minus mu cancels (at mu 0.5, gamma
        # 2.89 the circle's ripple is 1 + 1.3e-9)
        assert p.ripple == pytest.approx(1.0, abs=1e-7)


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


def test_the_prediction_from_what_is_sent_rounds_to_the_levels():
    # AS at a cell corner, mu 0.33, gamma 0.7: drive 0.33 + 0.67 x 0.25^0.7 = 0.5839, sent as
    # level round(0.5839 x 22) = 13, i.e. 13/22; the tailored participant (TH 0.33, K 1/1.4)
    # feels each of four tactors at m = ((13/22 - 0.33) / 0.67)^(1/1.4), together 2 m.
    drive = 0.33 + 0.67 * 0.25**0.7
    assert round(drive * 22) == 13
    m = ((13 / 22 - 0.33) / 0.67) ** (1 / 1.4)
    p = predict(still(2.0, 3.0), "AS", 0.33, 0.7, threshold=0.33, exponent=1 / 1.4, rate_hz=300,
                levels=23, duration_s=0.1)  # fmt: skip
    assert len(p.felt) == 30
    np.testing.assert_allclose(p.felt, 2 * m)
    assert 2 * m == pytest.approx(1.0197, abs=1e-4)  # 2% above the tactor's 1: not even


def test_the_motors_low_pass_what_is_felt():
    # CT held on a tactor from rest: the effective drive's mean over frame k is
    # 1 - (tau / dt) (exp(-k dt / tau) - exp(-(k + 1) dt / tau)); the linear participant
    # feels it as it is. The first 3 tau (90 ms at 30 ms) are left out of the summaries.
    from tactile_core.rendering.motor import MotorResponse

    p = predict(still(1.5, 2.5), "CT", 0.0, 1.0, threshold=0.0, exponent=1.0, rate_hz=100,
                duration_s=0.2, motor=MotorResponse(0.03, 0.06))  # fmt: skip
    k, dt = np.arange(20), 0.01
    expected = 1 - 3.0 * (np.exp(-k * dt / 0.03) - np.exp(-(k + 1) * dt / 0.03))
    np.testing.assert_allclose(p.felt, expected, rtol=1e-12)
    np.testing.assert_array_equal(p.valid, k * dt >= 0.09 - 1e-12)
    assert p.ripple == pytest.approx(expected[-1] / expected[9])


def test_a_range_of_participants_and_each_methods_own_correction():
    from tactile_core.rendering.percept import (
        LINEAR_ENERGY,
        REFERENCE,
        participant_grid,
        predict_range,
    )

    grid = participant_grid()
    assert len(grid) == 25 and REFERENCE in grid and LINEAR_ENERGY in grid
    line = tc.Line((0.5, 1.84), (4.5, 4.16))
    got = predict_range(line, "EN", 0.33, 0.7, samples=301)
    # EN carries no correction: for the linear-energy participant it is even (sum I^2 = 1).
    assert got.at("continuous", LINEAR_ENERGY)[0] == pytest.approx(1.0, abs=1e-12)
    plain = predict(line, "EN", 0.0, 1.0, threshold=0.2, exponent=1.0, samples=301)
    assert got.at("continuous", REFERENCE) == pytest.approx((plain.ripple, plain.mean_error_mm))
    assert set(got.ripple) == {"continuous", "sent"}
