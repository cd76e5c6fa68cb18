"""The scripting API (tactile_core.script, tc.open_array): presentations with their first
frame's time, free points, the context manager, and Ctrl-C / SIGTERM leaving the array off."""

import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.script import Array, Presentation, open_array

from .serve_support import Taps, wait_for

ROOT = Path(__file__).resolve().parents[1]
QT = ("PySide6", "pyqtgraph", "PyQt5", "PyQt6", "shiboken6")


def test_script_play_blocks_until_played_and_gives_the_first_frames_time():
    taps = Taps()
    with open_array("sim") as array:
        assert isinstance(array, Array)
        array.streamer.taps.append(taps)
        shown = array.play("line:0.5,0.5,4.5,0.5", method="CT", duration_s=0.2)
        assert time.perf_counter() >= shown.first_frame_s + 0.2  # returns once played, not before
        assert isinstance(shown, Presentation)
        assert shown.started.is_set() and shown.done.is_set() and not shown.interrupted
        frames = {t: (seq, levels) for t, seq, levels in taps.frames}
        seq, levels = frames[shown.first_frame_s]  # the time of a frame written
        assert seq == shown.seq and levels[0] == 22 and sum(levels) == 22  # its first frame
        # Off once played: from the frame after the trace's 60 (0.2 s at 300 Hz) on. Counted
        # in frames, not by when they were written: a loaded host writes a lit frame late.
        first = next(i for i, f in enumerate(taps.frames) if f[0] == shown.first_frame_s)
        wait_for(lambda: len(taps.frames) > first + 71, what="frames after the end")
        after = taps.frames[first + 61 :]
        assert all(f[2] == bytes(30) for f in after)
    assert array.streamer.stats.state == "stopped"
    assert not array.link.levels().any()


def test_script_wait_false_returns_at_once_and_a_new_play_cuts_the_old_one_short():
    with tc.open_array("sim") as array:
        long = array.play("circle:2.5,3,2", method="IM", duration_s=30, wait=False)
        assert long.started.wait(10) and not long.done.is_set()
        short = array.play(tc.Square((2.5, 3), 2), method="AS", mu=0.2, gamma=0.5,
                           duration_s=0.1, wait=False)  # fmt: skip
        assert long.done.is_set() and long.interrupted
        assert short.wait(10) is short and short.done.is_set() and not short.interrupted
        assert short.first_frame_s > long.first_frame_s
        assert "first frame" in repr(short)
        cut = array.play("circle:2.5,3,2", duration_s=30, wait=False)
        array.all_off()
        assert cut.done.is_set() and cut.interrupted
        wait_for(lambda: not array.streamer.last_levels.any(), what="all off")


def test_script_points_stay_until_released():
    with tc.open_array("sim") as array:
        array.point(2.5, 3.0, 0.5)
        want = tc.quantize(tc.correct(tc.render_xy("AS", 2.5, 3.0), 0.33, 0.7 * 1), 23)
        assert want.any()
        wait_for(lambda: array.streamer.last_levels.any(), what="the point lit")
        levels = array.streamer.last_levels
        assert np.count_nonzero(levels) == 2 and levels[2, 2] == levels[3, 2] == 12
        array.point(0.5, 0.5, point_id="b", method="CT", mu=0.0, gamma=1.0)
        wait_for(lambda: array.streamer.last_levels[0, 0] == 22, what="the second point")
        array.release()
        wait_for(lambda: not array.streamer.last_levels.any(), what="released")


def test_script_refuses_by_name():
    with tc.open_array("sim") as array:
        with pytest.raises(ValueError, match="shape"):
            array.play("blob:1")
        with pytest.raises(ValueError, match="needs a shape"):
            array.point(1.0, 1.0, method="IM")
        with pytest.raises(ValueError, match="duration"):
            array.play("circle:2.5,3,2", duration_s=-1)
    with pytest.raises(ValueError, match="closed"):
        array.play("circle:2.5,3,2")
    with tc.open_array("sim", profile="belt-8") as belt, pytest.raises(ValueError, match="IM"):
        belt.play("line:0,0,7,0", method="IM")
    with pytest.raises(ValueError, match="lead_ms"):
        tc.open_array("sim", lead_ms=900)


def test_script_lsl_marker_per_play():
    import json
    import uuid

    import pylsl

    with tc.open_array("sim", lsl=True) as array:
        array.lsl.close()  # a fresh outlet with an id of this test's own
        from tactile_core.serve import LslOutlets

        sid = f"test-{uuid.uuid4().hex}"
        array.lsl = LslOutlets(array.profile, source_id=sid).attach(array.streamer)
        found = pylsl.resolve_bypred(f"source_id='{sid}-markers'", 1, 20)
        inlet = pylsl.StreamInlet(found[0])
        inlet.open_stream(20)
        shown = array.play("circle:2.5,3,1", method="GS", duration_s=0.1, marker="trial-7")
        sample, stamp = inlet.pull_sample(timeout=20)
    marker = json.loads(sample[0])
    assert marker["kind"] == "trial-7" and marker["seq"] == shown.seq
    assert abs(stamp - (shown.first_frame_s + array.lsl.offset_s)) < 1e-6


def test_script_never_imports_qt():
    code = (
        "import sys\nimport tactile_core as tc\nimport tactile_core.script\ntc.open_array\n"
        f"print([m for m in sys.modules if m.split('.')[0] in {QT!r}])"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


SCRIPT = textwrap.dedent("""
    import sys
    import tactile_core as tc
    how = sys.argv[2]
    if how == "with":
        with tc.open_array(sys.argv[1]) as array:
            shown = array.play("circle:2.5,3,2", method="AS", duration_s=60, wait=False)
            shown.started.wait(10)
            print("playing", flush=True)
            shown.wait()
    else:  # no with, no close: Ctrl-C in wait() and the interpreter's exit still end all off
        array = tc.open_array(sys.argv[1])
        shown = array.play("circle:2.5,3,2", method="AS", duration_s=60, wait=False)
        shown.started.wait(10)
        print("playing", flush=True)
        shown.wait()
""")


@pytest.mark.parametrize(
    "how, sig", [("with", signal.SIGINT), ("plain", signal.SIGINT), ("with", signal.SIGTERM)]
)
def test_script_interrupted_ends_with_the_array_all_off(emulator_thread, how, sig):
    emulator, path = emulator_thread
    start = len(emulator.log)
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT, path, how], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert proc.stdout.readline().strip() == "playing", proc.stderr.read()
        wait_for(lambda: any(emulator.log.last() or b""), what="the circle at the array")
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=20)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode != 0  # interrupted, and says so
    assert ("KeyboardInterrupt" if sig == signal.SIGINT else "") in err
    levels = emulator.log.arrays(start)[2]
    assert levels[:-1].any() and not levels[-1].any()  # lit, then an all-off frame
    wait_for(lambda: emulator.log.last() == bytes(30), what="all off")
    assert emulator.watchdog_trips == 0  # turned off by the host, not by the array's watchdog


def test_two_interval_example_runs_against_sim():
    out = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "examples" / "two_interval_trial.py"),
         "--duration", "0.1", "--gap", "0.05", "--seed", "3"],
        input="x\n2\n", capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0].startswith("interval 1: first frame at ")
    assert lines[1].startswith("interval 2: first frame at ")
    assert '"answer": 2' in lines[-1] and "please type 1 or 2" in out.stderr
