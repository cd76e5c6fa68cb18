"""Messages read as a researcher would write them: a count agrees with its noun, a bound is
named once (each was a new-user finding)."""

import pytest

import tactile_core as tc
from tactile_core.serve import ServeStats


def test_one_timed_out_point_is_a_point_and_one_reply_a_reply():
    stats = ServeStats(address="127.0.0.1:9000", timed_out=1, replies=1)
    assert "1 point timed out" in stats.line() and "1 points" not in stats.line()
    assert "1 point timed out; 1 reply sent" in stats.summary()
    two = ServeStats(address="127.0.0.1:9000", timed_out=2, replies=2)
    assert "2 points timed out" in two.line() and "2 replies sent" in two.summary()


@pytest.mark.parametrize("call", [lambda: tc.correct([0.5, 2.0], 0.3, 0.7),
                                  lambda: tc.quantize([0.5, 2.0], 23)])  # fmt: skip
def test_an_intensity_out_of_range_names_the_bound_once(call):
    # it read "intensity must be intensities within [0, 1]"
    with pytest.raises(
        ValueError, match=r"^intensity must be within \[0, 1\], got 2.0 at index 1$"
    ):
        call()
