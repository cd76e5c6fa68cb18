"""bHaptics' compiled frames as an oracle: a file carrying both forms, its dots reproduced
motor value for motor value, its paths measured per method (docs/tact.md, "bHaptics' own
frames"); the expected frames are worked out by hand from the rules that page states."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.files.tact import (
    compare_compiled,
    compiled_document,
    matching_layout,
    parse_tact,
)

from . import tact_support as ts

TOOL = Path(__file__).resolve().parents[1] / "tools" / "tact_oracle.py"


def dot_feedback(start_ms, end_ms, motors, fade="NONE"):
    return {"startTime": start_ms, "endTime": end_ms, "playbackType": fade,
            "pointList": [{"index": i, "intensity": v} for i, v in motors]}  # fmt: skip


def dots_effect(entries, start_ms, length_ms, connected=False):
    mode = ts.dot_mode([], 0, 0)
    mode["dotMode"] = {"dotConnected": connected, "feedback": entries}
    return ts.effect({"VestFront": mode}, start_ms, length_ms)


def both_forms():
    """Dots of every kind on the vest's front, and bHaptics' frames of them every 20 ms, by hand:

    - effect A (0-200 ms): motors 0 (1.0) and 5 (0.5) fading out over 0-100 ms, then motor 5
      at 0.7 from 100 ms to an endTime of 300 ms, which the effect's end cuts at 200;
    - effect B (100-200 ms), dotConnected: motor 10 (1.0) at 0 ms, 11 (0.6) at 50, 12 (0.4)
      at 100: each fading into the next;
    - effect C (0-40 ms): motor 19 listed twice at 0.6, which add up and are capped at 100.
    """
    a = dots_effect([dot_feedback(0, 100, [(0, 1.0), (5, 0.5)], "FADE_OUT"),
                     dot_feedback(100, 300, [(5, 0.7)])], 0, 200)  # fmt: skip
    b = dots_effect([dot_feedback(0, 50, [(10, 1.0)]), dot_feedback(50, 100, [(11, 0.6)]),
                     dot_feedback(100, 100, [(12, 0.4)])], 100, 100, connected=True)  # fmt: skip
    c = dots_effect([dot_feedback(0, 40, [(19, 0.6), (19, 0.6)])], 0, 40)
    by_hand = {  # ms: {motor: value}, value = floor(100 x intensity x ramp), added per motor
        0: {0: 100, 5: 50, 19: 100},
        20: {0: 80, 5: 40, 19: 100},  # 1 - 20/100 of each
        40: {0: 60, 5: 30, 19: 100},
        60: {0: 40, 5: 20},
        80: {0: 20, 5: 10},
        100: {5: 70, 10: 100},  # the fade ends at 0; motor 5's second dot starts
        120: {5: 70, 10: 60, 11: 24},  # u = 20/50: 1.0 x 0.6, 0.6 x 0.4
        140: {5: 70, 10: 20, 11: 48},  # u = 0.8
        160: {5: 70, 11: 48, 12: 8},  # u = 10/50 into the second step: 0.6 x 0.8, 0.4 x 0.2
        180: {5: 70, 11: 24, 12: 24},
        200: {5: 70, 12: 40},  # both effects' ends, included
    }
    values = np.zeros((len(by_hand), 20), dtype=int)
    for k, ms in enumerate(sorted(by_hand)):
        for motor, value in by_hand[ms].items():
            values[k, motor] = value
    data = ts.document(a, b, c)
    data.update(compiled_document({"VestFront": values}))
    return data


def test_a_vest_position_plays_on_a_4_by_5_grid_motor_for_motor():
    grid, order = matching_layout({i: (m["x"], m["y"]) for i, m in enumerate(ts.VEST_LAYOUT)})
    assert grid == tc.Grid(4, 5)
    assert order[0] == grid.flat(0, 4) and order[3] == grid.flat(3, 4)  # top row: the grid's 4
    assert order[19] == grid.flat(3, 0)


def test_dots_reproduce_bhaptics_frames_exactly():
    (comparison,) = compare_compiled(parse_tact(both_forms()), ["AS", "CT"])
    assert comparison.kind == "dots" and comparison.frames == 11
    assert comparison.exact == 11 and not comparison.within.any()


def test_a_frame_that_differs_is_counted():
    data = both_forms()
    data["feedback"]["120"][0]["values"][11] = 25
    (comparison,) = compare_compiled(parse_tact(data))
    assert comparison.exact == 10 and comparison.within.tolist()[6] == 1


def path_file(their_middle=90):
    """A path along the vest's middle row reaching motors 8, 9 and 10 at 0, 20 and 40 ms, and
    bHaptics' frames lighting them at 100, ``their_middle`` and 100."""
    points = [ts.point(x, 0.5, 1.0, ms) for x, ms in ((0, 0), (1 / 3, 20), (2 / 3, 40), (1, 60))]
    data = ts.document(ts.effect({"VestFront": ts.path_mode(points, "CONST_TDM")}, 0, 60))
    values = np.zeros((3, 20), dtype=int)
    values[0, 8], values[1, 9], values[2, 10] = 100, their_middle, 100
    data.update(compiled_document({"VestFront": values}))
    return data


def test_a_paths_error_is_measured_per_method():
    (ct,) = compare_compiled(parse_tact(path_file()), ["CT"])
    assert ct.kind == "paths" and ct.method == "CT"
    # CT lights the point's motor at 100 in each frame: 10 off in one motor of 3 x 20
    assert ct.mean_abs_error() == pytest.approx(10 / 60)
    assert ct.mean_abs_error(lit=True) == pytest.approx(10 / 3)
    assert ct.within.tolist() == [0, 10, 0]
    assert compare_compiled(parse_tact(path_file(100)), ["CT"])[0].exact == 3


def test_single_held_points_are_left_out_of_the_comparison():
    # bHaptics' frames of a path of one point are empty in every file that has one
    data = ts.document(ts.effect({"VestFront": ts.path_mode([ts.point(0.5, 0.5, 1, 0)])}, 0, 60))
    data.update(compiled_document({"VestFront": np.zeros((3, 20), dtype=int)}))
    assert compare_compiled(parse_tact(data)) == []


def test_the_tool_prints_the_table(tmp_path, capsys):
    spec = importlib.util.spec_from_file_location("tact_oracle", TOOL)
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    ts.write(tmp_path, both_forms(), "dots.tact")
    ts.write(tmp_path, both_forms(), "same.tact")  # the same bytes: counted once
    ts.write(tmp_path, path_file(), "path.tact")
    ts.write(tmp_path, ts.simple(), "project-only.tact")
    assert tool.main([str(tmp_path), "--methods", "CT,AS", "--markdown"]) == 0
    out = capsys.readouterr().out
    assert "3 distinct files read (1 more with the same bytes, 0 refused), 2 carry both" in out
    assert "| dots only | 1 | 1 | 11 | 11 | 0 | 0 |" in out
    assert "| CT | 3 | 0.17 | 3.3 | 66.7 % |" in out  # 10 over the 3 lit motors


def test_a_file_exported_with_both_forms_is_its_own_oracle(tmp_path):
    """Export writes bHaptics' frames as bHaptics cuts them: played back on the array's own
    motors, the project gives the very frames the file carries."""
    from tactile_core.files.tact import read_tact, write_tact
    from tactile_core.rendering.shapes import TimedPath

    path = TimedPath([(0.5, 0.5), (3.5, 4.5), (0.5, 4.5)], [0.0, 0.3, 0.5], [1.0, 0.4, 0.8])
    out = write_tact(tmp_path / "both.tact", path, tc.Grid(4, 5), compiled="AS")
    (comparison,) = compare_compiled(read_tact(out), ["AS"])
    assert comparison.frames == 25 and comparison.exact == 25
