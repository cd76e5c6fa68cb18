"""bHaptics' compiled .tact form (``feedback`` frames of motor values): read, played, written
and refused by field (docs/tact.md, "The compiled form")."""

import json

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.cli import main
from tactile_core.device.profile import find_profile
from tactile_core.files import _tact_compiled
from tactile_core.files.tact import (
    TactError,
    TactPattern,
    compile_frames,
    compiled_document,
    device_places,
    load_pattern,
    parse_tact,
    read_tact,
    write_tact,
)
from tactile_core.rendering.shapes import TimedPath

from . import tact_support as ts

VEST = find_profile("vest-4x5").layout
GRID = tc.Grid(4, 5)


def frames_of(values, position="VestFront", interval=20):
    """A compiled-only file: ``values`` (frames x motors) every ``interval`` ms."""
    return compiled_document({position: values}, interval_ms=interval)


def vest_values():
    """Three frames of the vest: motor 0 at 100 then 50, motor 19 at 40 in the last."""
    values = np.zeros((3, 20), dtype=int)
    values[0, 0], values[1, 0], values[2, 19] = 100, 50, 40
    return values


def test_a_compiled_document_has_bhaptics_keys_and_frames():
    doc = frames_of(vest_values())
    assert doc["intervalMillis"] == 20 and doc["size"] == 20
    assert doc["durationMillis"] == 80  # the frames' end (60 ms) plus one interval, as bHaptics
    assert list(doc["feedback"]) == ["0", "20", "40"]
    (entry,) = doc["feedback"]["20"]
    assert entry == {"position": "VestFront", "mode": "DOT_MODE", "texture": 0,
                     "values": [50] + [0] * 19}  # fmt: skip


def test_compiled_frames_round_trip_through_the_reader():
    file = parse_tact(frames_of(vest_values()))
    assert file.form == "compiled" and file.positions == ("VestFront",)
    times, rows = file.compiled.frames["VestFront"]
    assert times == (0, 20, 40) and np.array_equal(rows, vest_values())
    assert file.duration_s == pytest.approx(0.06)
    # each motor's run of one value is one dot, until the next frame (an open end)
    dots = sorted((d.index, d.intensity, d.start_s, d.end_s, d.closed) for d in file.dots)
    assert dots == [(0, 0.5, 0.02, 0.04, False), (0, 1.0, 0.0, 0.02, False),
                    (19, 0.4, 0.04, 0.06, False)]  # fmt: skip


def test_a_run_of_one_value_is_one_dot():
    values = np.zeros((50, 20), dtype=int)
    values[:, 5] = 30  # a second of one value
    file = parse_tact(frames_of(values))
    assert [(d.index, d.start_s, d.end_s) for d in file.dots] == [(5, 0.0, 1.0)]


def test_compiled_frames_play_motor_for_motor_on_the_vest():
    # vest-4x5 lists its actuators from the bottom row: motor 0 (top left) is r4c0, index 16,
    # and motor 19 (bottom right) is r0c3, index 3
    pattern = TactPattern(parse_tact(frames_of(vest_values())))
    time_s, frames = pattern.frames("BA", VEST, rate_hz=50.0, corrected=False)
    expected = np.zeros((3, 20))
    expected[0, 16], expected[1, 16], expected[2, 3] = 1.0, 0.5, 0.4
    assert time_s == pytest.approx([0.0, 0.02, 0.04]) and frames == pytest.approx(expected)
    assert VEST.names[16] == "r4c0" and VEST.names[3] == "r0c3"


def test_values_above_100_play_as_100():
    # bHaptics' 2017 SDK reads the values as bytes and caps what it plays at 100; some of its
    # early files hold up to 228
    data = frames_of(vest_values())
    data["feedback"]["0"][0]["values"][0] = 228
    (dot, *_) = sorted(parse_tact(data).dots, key=lambda d: d.start_s)
    assert dot.intensity == 1.0


def test_device_places_follow_the_designers_layouts():
    assert device_places("VestBack", 20)[3] == (1.0, 0.0)  # 4 x 5, top left first
    assert device_places("VestBack", 20)[4] == (0.0, 0.25)
    assert device_places("Right", 20)[5] == (0.0, 1 / 3)  # the arms' 5 x 4
    assert device_places("ForearmL", 6)[4] == (0.5, 1.0)  # 3 x 2
    assert device_places("Head", 7)[6] == (1.0, 0.5)  # along the middle row


def test_a_file_with_both_forms_plays_the_project_unless_asked():
    data = ts.simple()
    data.update(frames_of(vest_values()))
    assert parse_tact(data).form == "project" and parse_tact(data).compiled is not None
    assert parse_tact(data, form="compiled").form == "compiled"
    with pytest.raises(TactError, match="feedback is missing: the file has no compiled frames"):
        parse_tact(ts.simple(), form="compiled")
    with pytest.raises(TactError, match="layout is missing"):
        parse_tact(frames_of(vest_values()), form="project")
    with pytest.raises(ValueError, match="form must be one of project, compiled, got 'both'"):
        parse_tact(data, form="both")


def test_a_path_exports_with_its_compiled_frames_and_reads_back(tmp_path):
    path = TimedPath([(0.5, 2.5), (3.5, 2.5)], [0.0, 0.1])  # the middle row of a 4 x 5 grid
    out = write_tact(tmp_path / "p.tact", path, GRID, compiled="CT")
    data = json.loads(out.read_text())
    assert {"project", "feedback", "intervalMillis", "size", "durationMillis"} <= set(data)
    file = read_tact(out)
    times, rows = file.compiled.frames["VestFront"]
    assert times == (0, 20, 40, 60, 80)  # frames before the path's end (0.1 s)
    # CT at 0, 20, ... ms: x = 0.5 + 3 k / 5 = 0.5, 1.1, 1.7, 2.3, 2.9, the cell floor(x); the
    # Designer numbers the middle row's motors 8-11 from the left: motor 8 + floor(x), at 100
    expected = np.zeros((5, 20), dtype=int)
    for k, col in enumerate([0, 1, 1, 2, 2]):
        expected[k, 8 + col] = 100
    assert np.array_equal(rows, expected)
    assert np.array_equal(compile_frames(path, GRID, "CT"), expected)
    # the project still plays as the path, the frames as the frames
    (back,) = TactPattern(file).paths(GRID)
    assert back.points == path.points
    assert len(TactPattern(read_tact(out, "compiled")).dots(GRID)) == 3  # 3 runs of one motor


def test_export_tact_compiled_on_the_command_line(tmp_path, capsys):
    out = tmp_path / "line.tact"
    args = ["export-tact", "--shape", "line:0.5,2.5,3.5,2.5", "--duration", "0.1", "--cols", "4",
            "--rows", "5", "--compiled", "--method", "CT", "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    assert "and its frames by CT every 20 ms (compiled form)" in capsys.readouterr().out
    assert read_tact(out).compiled.frames["VestFront"][0] == (0, 20, 40, 60, 80)
    assert load_pattern(out, form="compiled").file.form == "compiled"
    assert main(["export-tact", "--shape", "line:0,2,3,2", "--method", "CT", "--out",
                 str(tmp_path / "x.tact")]) == 2  # fmt: skip
    assert "--method applies with --compiled" in capsys.readouterr().err
    y = str(tmp_path / "y.tact")
    assert main(["export-tact", "--shape", "line:0,2,3,2", "--profile", "vest-4x5",
                 "--compiled", "--method", "AS", "--out", y]) == 2  # fmt: skip
    assert "--method:" in capsys.readouterr().err  # AS is a grid's method; vest-4x5 is not one


def test_old_path_mode_frames_are_read_and_said_not_to_play():
    data = frames_of(vest_values())
    data["feedback"]["0"].append({"position": "Left", "mode": "PATH_MODE",
                                  "values": [3, 0, 29, 100] + [0] * 16})  # fmt: skip
    pattern = TactPattern(parse_tact(data))
    assert pattern.positions == ("VestFront",)
    assert pattern.notes == ("1 compiled PATH_MODE entries (bHaptics' 2017 point format) are "
                             "not played",)  # fmt: skip


F = ["feedback", "0", 0]
BAD = [
    (["intervalMillis"], ts.DELETE, "intervalMillis is missing"),
    (["intervalMillis"], 0, "intervalMillis must be within [1, 10000], got 0"),
    (["intervalMillis"], 20.5, "intervalMillis must be a whole number, got 20.5"),
    (["size"], -1, "size must be within [0, 1024], got -1"),
    (["durationMillis"], ts.DELETE, "durationMillis is missing"),
    (["feedback"], [], "feedback must be an object, got a list"),
    (["feedback", "x0"], [], "feedback has a key 'x0': a frame's time in whole ms"),
    (["feedback", "4000000"], [], "feedback.4000000 is after 1 h"),
    (["feedback", "0"], {}, "feedback.0 must be a list, got an object"),
    ([*F, "values"], ts.DELETE, "feedback.0[0].values is missing"),
    ([*F, "values", 3], 256, "feedback.0[0].values[3] must be within [0, 255], got 256"),
    ([*F, "values", 3], 2.5, "feedback.0[0].values[3] must be a whole number, got 2.5"),
    ([*F, "values", 3], "x", "feedback.0[0].values[3] must be a number, got 'x'"),
    ([*F, "mode"], "WAVE", "feedback.0[0].mode must be one of PATH_MODE, DOT_MODE, got 'WAVE'"),
    ([*F, "position"], "\x1b[2J", "feedback.0[0].position has a position named"),
    ([*F, "texture"], -1, "feedback.0[0].texture must be within [0, 65536], got -1"),
    (
        ["feedback", "20", 0, "values"],
        [0] * 7,
        "feedback.20[0].values holds 7 values where the frames before give VestFront 20",
    ),
]


@pytest.mark.parametrize(("where", "value", "message"), BAD)
def test_bad_compiled_files_are_refused_by_field(where, value, message):
    data = ts.mutate(frames_of(vest_values()), where, value)
    with pytest.raises(TactError) as caught:
        parse_tact(data, "bad.tact")
    assert str(caught.value).startswith("bad.tact: ") and message in str(caught.value)


def test_a_position_twice_in_a_frame_is_refused():
    data = frames_of(vest_values())
    data["feedback"]["0"].append(dict(data["feedback"]["0"][0]))
    with pytest.raises(TactError, match=r"feedback.0\[1\].position repeats VestFront"):
        parse_tact(data)


def test_too_many_frames_or_dots_are_refused_in_bounded_work(monkeypatch):
    monkeypatch.setattr(_tact_compiled, "MAX_FRAMES", 2)
    with pytest.raises(TactError, match="feedback holds 3 frames, more than the 2 allowed"):
        parse_tact(frames_of(vest_values()))
    monkeypatch.setattr(_tact_compiled, "MAX_FRAMES", 180_000)
    from tactile_core.files import _tact_read

    monkeypatch.setattr(_tact_read, "MAX_TOTAL_POINTS", 2)
    with pytest.raises(TactError, match="brings the file past 2 path points and dots"):
        parse_tact(frames_of(vest_values()))


def test_compiled_documents_refuse_what_they_cannot_write():
    with pytest.raises(ValueError, match="interval_ms must be a whole number of ms"):
        compiled_document({"VestFront": vest_values()}, interval_ms=0)
    with pytest.raises(ValueError, match=r"values\['VestFront'\] must be frames x motors"):
        compiled_document({"VestFront": vest_values() * 3})
    with pytest.raises(ValueError, match="values must give every position as many frames"):
        compiled_document({"VestFront": vest_values(), "VestBack": vest_values()[:2]})
