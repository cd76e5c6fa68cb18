"""Break-it pass on the scripting API and bHaptics .tact files: each test is a defect found by
attacking them as an operator or a script author would, and the behaviour that replaced it."""

import math
import os
import signal
import stat
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.files.tact import path_of_scene, tact_document, write_tact
from tactile_core.rendering.scene import Scene
from tactile_core.rendering.shapes import TimedPath

from .helpers import stop_with
from .serve_support import wait_for

PALM = tc.Grid(5, 6)


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


SIGTERM_SCRIPT = textwrap.dedent("""
    import signal
    import tactile_core as tc
    first, second = tc.open_array("sim"), tc.open_array("sim")
    first.close()
    try:
        with second:
            shown = second.play("circle:2.5,3,2", method="AS", duration_s=60, wait=False)
            shown.started.wait(10)
            print("playing", flush=True)
            shown.wait()
    except SystemExit:
        print("off" if not second.link.levels().any() else "ON", flush=True)
        raise
""")


def test_sigterm_still_turns_the_array_off_after_another_array_closed():
    # Closing the first of two arrays put SIGTERM back to its default while the second was
    # still open: SIGTERM then killed the script outright, no `with` block ran, and the array
    # stayed on until its watchdog.
    proc = subprocess.Popen([sys.executable, "-c", SIGTERM_SCRIPT], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert proc.stdout.readline().strip() == "playing", proc.stderr.read()
    except BaseException:
        stop_with(proc, signal.SIGKILL)
        raise
    out, err = stop_with(proc, signal.SIGTERM)
    assert out.split() == ["off"], err
    assert proc.returncode == 128 + signal.SIGTERM


HANDLER_SCRIPT = textwrap.dedent("""
    import signal
    import tactile_core as tc
    from tactile_core import script
    def mine(signum, frame):
        pass
    first, second = tc.open_array("sim"), tc.open_array("sim")
    first.close()
    print(signal.getsignal(signal.SIGTERM) is script._terminate)
    second.close()
    print(signal.getsignal(signal.SIGTERM) == signal.SIG_DFL)
    array = tc.open_array("sim")
    signal.signal(signal.SIGTERM, mine)  # the script's own, put in while the array is open
    array.close()
    print(signal.getsignal(signal.SIGTERM) is mine)
""")


def test_closing_arrays_restores_sigterm_only_after_the_last_and_keeps_the_scripts_handler():
    out = subprocess.run([sys.executable, "-c", HANDLER_SCRIPT], capture_output=True, text=True,
                         timeout=60)  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True", "True", "True"]


def test_write_tact_refuses_what_is_not_a_regular_file_and_leaves_it_in_place(tmp_path):
    # write_tact's atomic rename replaced whatever was at the path: as root, write_tact to
    # /dev/null put a regular file in the device's place (a FIFO stands in for it here).
    path = TimedPath([(0.5, 0.5), (4.5, 5.5)], [0.0, 1.0])
    fifo = tmp_path / "pipe.tact"
    os.mkfifo(fifo)
    with pytest.raises(ValueError, match="not a regular file"):
        write_tact(fifo, path, PALM)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    with pytest.raises(ValueError, match="is a folder"):
        write_tact(tmp_path, path, PALM)
    with pytest.raises(ValueError, match="does not exist"):
        write_tact(tmp_path / "missing" / "x.tact", path, PALM)
    with pytest.raises(ValueError, match="must be a file path"):
        write_tact("", path, PALM)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe.tact"]  # no temporary left


def test_a_long_sampled_trace_exports_at_most_10000_evenly_spaced_points():
    # docs/tact.md said "sampled every 20 ms": past 200 s the path's 10,000-point limit spaces
    # the samples further apart (400 s: 9,999 steps of 40.004 ms).
    scene = Scene(tc.Circle((2.5, 3.0), 2.0), "AS", duration_s=400.0)
    path = path_of_scene(scene)
    assert len(path.points) == 10_000
    assert np.diff(path.times_s) == pytest.approx(400.0 / 9_999)
    doc = tact_document(path, PALM)
    feedback = doc["project"]["tracks"][0]["effects"][0]["modes"]["VestFront"]["pathMode"]
    points = feedback["feedback"][0]["pointList"]
    assert len(points) == 10_000 and points[-1]["time"] == 400_000
