"""The bounds of bHaptics .tact files, read and written: a name is cut to 200 characters, a time
that does not fit a float and a position name a terminal would act on are refused naming the
field, and an export holds at most 10,000 points, evenly spaced."""

import json

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.files.tact import TactError, parse_tact, path_of_scene, read_tact, tact_document
from tactile_core.rendering.scene import Scene

from . import tact_support as ts
from .helpers import run_cli_last_line

PALM = tc.Grid(5, 6)


def test_a_tact_project_name_is_cut_to_200_characters():
    data = ts.simple()
    data["project"]["name"] = "<h1>" + "n" * 100_000
    assert parse_tact(data).name == "<h1>" + "n" * 196  # (3.5 MB froze the import 22 s)


def test_export_tact_names_a_long_file_by_its_first_200_characters(tmp_path, capsys):
    out = tmp_path / ("q" * 230 + ".tact")
    code, _ = run_cli_last_line(capsys, "export-tact", "--shape", "line:0.5,0.5,4.5,5.5",
                                "--out", out)  # fmt: skip
    assert code == 0 and read_tact(out).name == "q" * 200


def test_a_tact_time_as_a_huge_integer_is_refused_naming_the_field(tmp_path):
    """JSON integers of a few hundred digits parse; float() of one overflowed (a traceback in
    tactile render and in the tuner's import)."""
    doc = ts.document(ts.effect({"VestFront": ts.path_mode(
        [ts.point(0.1, 0.5, 1, 0), ts.point(0.9, 0.5, 1, 10**400)])}))  # fmt: skip
    path = tmp_path / "huge.tact"
    path.write_text(json.dumps(doc))
    with pytest.raises(TactError, match=r"pointList\[1\].time must be within .*got inf"):
        read_tact(path)


def test_render_tact_with_a_huge_integer_is_a_usage_error(tmp_path, capsys):
    doc = ts.document(ts.effect({"VestFront": ts.path_mode(
        [ts.point(10**400, 0.5, 1, 0), ts.point(0.9, 0.5, 1, 500)])}))  # fmt: skip
    path = tmp_path / "huge.tact"
    path.write_text(json.dumps(doc))
    code, line = run_cli_last_line(capsys, "render", "--shape", f"tact:{path}", "--method",
                                   "AS", "--out", tmp_path / "x.csv")  # fmt: skip
    assert code == 2 and "pointList[0].x must be within" in line


@pytest.mark.parametrize("where", ["modes", "layouts"])
def test_tact_position_names_that_a_terminal_would_act_on_are_refused(tmp_path, where):
    """Position names are printed ('not played: VestBack'): a file's ESC sequences in one went
    raw to the terminal of whoever rendered it."""
    evil = "\x1b[2J\x1b]0;owned\x07"
    doc = ts.document(ts.effect({"VestFront": ts.path_mode(
        [ts.point(0.1, 0.5, 1, 0), ts.point(0.9, 0.5, 1, 500)])}))  # fmt: skip
    if where == "modes":
        modes = doc["project"]["tracks"][0]["effects"][0]["modes"]
        modes[evil] = modes["VestFront"]
    else:
        layouts = doc["project"]["layout"]["layouts"]
        layouts[evil] = layouts["VestFront"]
    path = tmp_path / "evil.tact"
    path.write_text(json.dumps(doc))
    with pytest.raises(TactError, match="a position's name is 1-64 printable") as caught:
        read_tact(path)
    assert "\x1b" not in str(caught.value)


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
