"""The scripting API used wrongly: every argument ``open_array``, ``play``, ``point``,
``release`` and ``wait`` cannot use is refused naming it (a ValueError, not the TypeError of
whatever library it reached), and a refused call changes nothing on the array."""

import math

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import ProfileError

from .helpers import stream_threads
from .serve_support import wait_for


def settled_levels(array, frames=10):
    """The simulated array's levels once ``frames`` more frames have reached it."""
    seen = array.link.frames
    wait_for(lambda: array.link.frames >= seen + frames, what=f"{frames} frames at the array")
    return array.link.levels()


def test_a_refused_point_call_lights_nothing():
    # point(..., mu=nan) was refused only after the point had gone into the live set: it lit
    # at the next frame, and after release() a refused call turned the array back on.
    with tc.open_array("sim") as array:
        array.point(0.5, 0.5, 1.0)  # the corner tactor, alone
        wait_for(lambda: array.link.levels().any(), what="the first point at the array")
        before = settled_levels(array)
        assert np.count_nonzero(before) == 1
        with pytest.raises(ValueError, match="mu must be a finite number"):
            array.point(4.5, 5.5, 1.0, point_id="b", mu=float("nan"))
        assert np.array_equal(settled_levels(array), before)
        array.release()
        wait_for(lambda: not array.link.levels().any(), what="all off after release")
        with pytest.raises(ValueError, match="gamma must be > 0"):
            array.point(4.5, 5.5, 1.0, point_id="c", gamma=-1.0)
        assert not settled_levels(array).any()
        with pytest.raises(ValueError, match=r"point id must be a string or None, got \[1\]"):
            array.release([1])  # was Python's "unhashable type: 'list'"


def test_wait_takes_an_infinite_timeout_and_refuses_a_bad_one_by_name():
    # wait(math.inf) raised OverflowError from threading; wait("1") a TypeError naming nothing;
    # wait(nan) returned at once as if the stimulus had played.
    with tc.open_array("sim") as array:
        shown = array.play("circle:2.5,3,2", "AS", duration_s=0.05, wait=False)
        for bad in (float("nan"), -1.0, "1", [1]):
            with pytest.raises(ValueError, match="timeout_s"):
                shown.wait(bad)
        assert shown.wait(math.inf) is shown
        assert shown.done.is_set() and not shown.interrupted
        assert shown.wait(1e300) is shown  # past threading's largest timeout: as long as it plays


@pytest.mark.parametrize("wait", ["no", None, 2, [True]])
def test_play_refuses_a_wait_that_is_not_a_boolean(wait):
    # wait="no" blocked (a truthy string), wait=None returned at once: neither said why.
    with tc.open_array("sim") as array:
        with pytest.raises(ValueError, match="wait must be true or false"):
            array.play("circle:2.5,3,2", "AS", duration_s=0.05, wait=wait)
        assert array.streamer.scene is None  # nothing was handed to the stream


def test_open_array_refuses_a_url_that_is_not_text_by_name():
    # b"sim" reached pyserial, whose TypeError ("a bytes-like object is required") named no
    # argument.
    with pytest.raises(ValueError, match="url must be a device URL"):
        tc.open_array(b"sim")


def test_open_array_names_its_own_arguments_and_starts_nothing():
    with pytest.raises(ProfileError, match="device profile must be a name, a path"):
        tc.open_array("sim", profile=5)
    with pytest.raises(ValueError, match=r"^point_timeout_s must be within"):
        tc.open_array("sim", point_timeout_s=-1)
    assert stream_threads() == []
