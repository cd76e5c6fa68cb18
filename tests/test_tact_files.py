"""Bad .tact files are refused naming the field; what bHaptics' own files vary in is read."""

import json
import re

import pytest

from tactile_core.files import _tact_read
from tactile_core.files.tact import (
    MAX_EFFECTS,
    MAX_TACT_BYTES,
    MAX_TOTAL_POINTS,
    TactError,
    parse_tact,
    read_tact,
)
from tactile_core.rendering.shapes import MAX_POINTS

from . import tact_support as ts
from .tact_support import DELETE

EFFECT = ["project", "tracks", 0, "effects", 0]
PATH = [*EFFECT, "modes", "VestFront", "pathMode", "feedback", 0]
DOTS = ["project", "tracks", 0, "effects", 1, "modes", "VestFront", "dotMode", "feedback", 0]
MOTOR = ["project", "layout", "layouts", "VestFront", 5]
P = "tracks[0].effects[0].modes.VestFront.pathMode.feedback[0]"
D = "tracks[0].effects[1].modes.VestFront.dotMode.feedback[0]"

CASES = [
    (["project", "tracks"], DELETE, "tracks is missing"),
    (["project", "tracks"], {}, "tracks must be a list, got an object"),
    (["project", "layout"], DELETE, "layout is missing"),
    (["project", "layout", "layouts"], [], "layout.layouts must be an object, got a list"),
    ([*MOTOR, "x"], 1.2, "layout.layouts.VestFront[5].x must be within [0, 1], got 1.2"),
    ([*MOTOR, "index"], 0, "layout.layouts.VestFront[5].index repeats motor 0"),
    ([*MOTOR, "index"], 1.5, "layout.layouts.VestFront[5].index must be a whole number"),
    (["project", "tracks", 0, "enable"], "yes", "tracks[0].enable must be true or false"),
    (["project", "tracks", 0, "effects"], None, "tracks[0].effects must be a list, got null"),
    ([*EFFECT, "startTime"], DELETE, "tracks[0].effects[0].startTime is missing"),
    (
        [*EFFECT, "offsetTime"],
        -5,
        "tracks[0].effects[0].offsetTime must be within [0, 3.6e+06], got -5",
    ),
    ([*EFFECT, "startTime"], "soon", "tracks[0].effects[0].startTime must be a number, got 'soon'"),
    ([*EFFECT, "startTime"], 3_599_500, "tracks[0].effects[0].offsetTime ends the effect after"),
    ([*EFFECT, "modes"], [], "tracks[0].effects[0].modes must be an object, got a list"),
    (
        [*EFFECT, "modes", "VestFront", "mode"],
        "WAVE_MODE",
        "tracks[0].effects[0].modes.VestFront.mode must be one of PATH_MODE, DOT_MODE",
    ),
    (
        [*EFFECT, "modes", "VestFront", "pathMode"],
        DELETE,
        "tracks[0].effects[0].modes.VestFront.pathMode is missing",
    ),
    ([*PATH, "movingPattern"], "CONST_FAST", f"{P}.movingPattern must be one of CONST_TDM"),
    ([*PATH, "movingPattern"], DELETE, f"{P}.movingPattern is missing"),
    ([*PATH, "playbackType"], "BLINK", f"{P}.playbackType must be one of NONE"),
    ([*PATH, "pointList"], "none", f"{P}.pointList must be a list, got a string"),
    ([*PATH, "pointList", 1, "x"], 1.5, f"{P}.pointList[1].x must be within [0, 1], got 1.5"),
    ([*PATH, "pointList", 1, "y"], "-0.1", f"{P}.pointList[1].y must be within [0, 1], got -0.1"),
    ([*PATH, "pointList", 1, "x"], "1,5", f"{P}.pointList[1].x must be a number, got '1,5'"),
    ([*PATH, "pointList", 1, "x"], "nan", f"{P}.pointList[1].x must be within [0, 1], got nan"),
    ([*PATH, "pointList", 1, "x"], True, f"{P}.pointList[1].x must be a number, got a boolean"),
    (
        [*PATH, "pointList", 1, "intensity"],
        [1],
        f"{P}.pointList[1].intensity must be a number, got a list",
    ),
    ([*PATH, "pointList", 1, "intensity"], DELETE, f"{P}.pointList[1].intensity is missing"),
    (
        [*PATH, "pointList", 1, "time"],
        0,
        f"{P}.pointList[1].time is 0 ms, not after the point before it (0 ms): times must increase",
    ),
    (
        [*PATH, "pointList", 1, "time"],
        1200,
        f"{P}.pointList[1].time is 1200 ms, after its effect's end (offsetTime 1000 ms)",
    ),
    ([*PATH, "pointList", 0, "time"], -1, f"{P}.pointList[0].time must be within [0, 3.6e+06]"),
    ([*PATH, "pointList", 1], 7, f"{P}.pointList[1] must be an object, got a number"),
    (
        [*DOTS, "endTime"],
        50,
        f"{D}.endTime is 50 ms, before its startTime (100 ms): a negative duration",
    ),
    ([*DOTS, "endTime"], 4e6, f"{D}.endTime must be within [0, 3.6e+06], got 4e+06"),
    (
        [*DOTS, "pointList", 0, "index"],
        25,
        f"{D}.pointList[0].index is motor 25, which layout.layouts.VestFront does not list",
    ),
    ([*DOTS, "pointList", 0, "intensity"], 2, f"{D}.pointList[0].intensity must be within [0, 1]"),
    ([*DOTS, "pointList", 0, "index"], -1, f"{D}.pointList[0].index must be within [0, 1024]"),
]


@pytest.mark.parametrize(("where", "value", "message"), CASES)
def test_bad_fields_are_refused_by_name(where, value, message):
    with pytest.raises(TactError) as info:
        parse_tact(ts.mutate(ts.simple(), where, value), "bad.tact")
    assert str(info.value).startswith(f"bad.tact: {message}")


def test_files_that_are_not_tact_json_are_refused(tmp_path):
    cases = {
        "text.tact": (b"not json at all", "not valid JSON"),
        "list.tact": (b"[1, 2]", "the file must be an object, got a list"),
        "latin.tact": ('{"name": "\xe9"}'.encode("latin-1"), "not UTF-8 text"),
        "deep.tact": (b"[" * 50 + b"]" * 50, "nested too deeply"),
        "nan.tact": (b'{"project": NaN}', "not valid JSON"),
    }
    for name, (data, message) in cases.items():
        (tmp_path / name).write_bytes(data)
        with pytest.raises(TactError, match=message):
            read_tact(tmp_path / name)
    with pytest.raises(TactError, match="no such file"):
        read_tact(tmp_path / "missing.tact")
    with pytest.raises(TactError, match="not a regular file"):
        read_tact(tmp_path)


def test_huge_files_are_refused_before_they_are_parsed(tmp_path):
    big = tmp_path / "big.tact"
    big.write_bytes(b" " * (MAX_TACT_BYTES + 1))
    with pytest.raises(TactError, match=f"larger than the {MAX_TACT_BYTES} allowed"):
        read_tact(big)


def test_too_many_points_or_effects_are_refused(monkeypatch):
    point = ts.point(0.5, 0.5, 1, 0)
    too_long = ts.mutate(ts.simple(), [*PATH, "pointList"], [point] * (MAX_POINTS + 1))
    with pytest.raises(TactError, match=re.escape(f"{P}.pointList holds 10001 entries, more")):
        parse_tact(too_long)
    assert MAX_TOTAL_POINTS == 200_000  # 20 paths of 10,000 points; here a smaller bound
    monkeypatch.setattr(_tact_read, "MAX_TOTAL_POINTS", 250)
    points = [ts.point(0.5, 0.5, 1, k / 10) for k in range(100)]
    many = ts.document(*[ts.effect({"VestFront": ts.path_mode(points)}) for _ in range(3)])
    with pytest.raises(
        TactError,
        match=re.escape(
            "tracks[0].effects[2].modes.VestFront.pathMode"
            ".feedback[0].pointList brings the file past "
            "250 path points and dots"
        ),
    ):
        parse_tact(many)
    monkeypatch.undo()
    tracks = [{"effects": [ts.effect({})] * 1000} for _ in range(6)]
    with pytest.raises(
        TactError,
        match=rf"tracks\[5\].effects\[0\] is one effect too many: at "
        rf"most {MAX_EFFECTS}",
    ):
        parse_tact(ts.document(tracks=tracks))


def test_what_bhaptics_files_vary_in_is_read(tmp_path):
    data = ts.simple()
    # numbers as strings, a byte-order mark, the project without its wrapper, no playbackType,
    # no effects on a track, extra keys, a whole number written as 100.0
    data["project"]["tracks"][0]["effects"][0]["startTime"] = "0"
    del data["project"]["tracks"][0]["effects"][0]["modes"]["VestFront"]["pathMode"]["feedback"][0][
        "playbackType"
    ]
    data["project"]["tracks"].append({"enable": True})
    data["project"]["layout"]["layouts"]["VestFront"][0]["distance"] = 0
    data["project"]["tracks"][0]["effects"][1]["modes"]["VestFront"]["dotMode"]["feedback"][0][
        "pointList"
    ][0]["index"] = 6.0
    path = tmp_path / "bom.tact"
    path.write_bytes(b"\xef\xbb\xbf" + json.dumps(data).encode())
    read = read_tact(path)
    assert len(read.paths) == 1 and len(read.dots) == 1 and read.paths[0].fade == "NONE"
    bare = parse_tact(data["project"])
    assert bare.paths == read.paths and bare.dots == read.dots


def test_load_pattern_refuses_an_empty_file_as_the_command_line_does(tmp_path, capsys):
    """Before: load_pattern returned an empty pattern (position '') that played nothing, while
    `tactile render` refused the file; now both refuse it with the same message."""
    from tactile_core.cli import main
    from tactile_core.files.tact import TactPattern, load_pattern

    empty = ts.write(tmp_path, ts.document(), "empty.tact")
    message = f"{empty}: no paths or dots to play (no enabled track holds any)"
    with pytest.raises(TactError) as error:
        load_pattern(empty)
    assert str(error.value) == message
    with pytest.raises(TactError, match="no paths or dots to play"):
        TactPattern(parse_tact(ts.document()))
    args = ["render", "--shape", f"tact:{empty}", "--method", "EN", "--profile", "vest-4x5",
            "--out", str(tmp_path / "f.csv")]  # fmt: skip
    assert main(args) == 2
    assert capsys.readouterr().err == f"tactile render: error: {message}\n"


def test_real_files_that_were_refused_now_read():
    """Files in bHaptics' own repositories that the reader refused: a dot whose endTime is past
    its effect's end (bhaptics/haptic-library's Teleport_Left.tact: 1000 ms in a 500 ms effect,
    which bHaptics' compiled frames end with the effect), a path point repeated at the same time
    (bhaptics/haptic-guide's Reload_L.tact), a layout giving only its type (PingLeft.tact)."""
    late = ts.document(ts.effect({"VestFront": ts.dot_mode([(6, 0.8)], 100, 900)}, 0, 400))
    (dot,) = parse_tact(late).dots
    assert (dot.start_s, dot.end_s) == (0.1, 0.4)  # cut at the effect's end
    twice = [ts.point(0.5, 0.5, 1, 0), ts.point(0, 1, 0.5, 300), ts.point(0, 1, 0.7, 300)]
    (path,) = parse_tact(ts.document(ts.effect({"VestFront": ts.path_mode(twice)}))).paths
    assert path.points == ((0.5, 0.5), (0.0, 1.0)) and path.intensities == (1.0, 0.7)
    moved = [ts.point(0, 1, 0.5, 300), ts.point(1, 1, 0.5, 300)]  # two places at once: no
    with pytest.raises(TactError, match=r"pointList\[1\].time is 300 ms, not after the point"):
        parse_tact(ts.document(ts.effect({"VestFront": ts.path_mode(moved)})))
    typed = ts.document(ts.effect({"VestBack": ts.dot_mode([(19, 0.7)], 0, 100)}))
    typed["project"]["layout"] = {"name": "Tactot", "type": "Tactot"}
    (dot,) = parse_tact(typed).dots
    assert (dot.x, dot.y) == (1.0, 1.0)  # the vest's motor 19: bottom right
