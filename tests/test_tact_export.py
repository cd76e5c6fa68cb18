"""Exporting .tact files: the Designer's structure, and export-then-import giving the same path."""

import json
import math

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import find_profile
from tactile_core.files.tact import (
    TactPattern,
    load_pattern,
    parse_tact,
    path_of_scene,
    read_tact,
    tact_document,
    write_tact,
)
from tactile_core.rendering.scene import Scene
from tactile_core.rendering.shapes import TimedPath, path_from_samples

SAMPLE = "tests/data/testfeedback.tact"
PALM = tc.Grid(5, 6)
VEST = find_profile("vest-4x5").layout
POSITION_KEYS = ("layouts", "modes")


def structure(value, path="", out=None):
    """{key path: JSON type}, list items as ``[]`` and device positions as ``<position>``."""
    out = {} if out is None else out
    if isinstance(value, dict):
        out[path] = "object"
        for key, item in value.items():
            name = "<position>" if path.rsplit(".", 1)[-1] in POSITION_KEYS else key
            structure(item, f"{path}.{name}", out)
    elif isinstance(value, list):
        out[path] = "list"
        for item in value:
            structure(item, f"{path}[]", out)
    else:
        kind = {bool: "boolean", str: "string", int: "number", float: "number"}[type(value)]
        out.setdefault(path, kind)
    return out


def test_export_has_the_designers_key_structure():
    with open(SAMPLE, encoding="utf-8") as f:
        sample = structure(json.load(f))
    path = TimedPath([(0.5, 0.5), (4.5, 5.5), (2.5, 1.0)], [0.0, 0.8, 1.5], [0.2, 1.0, 0.6])
    exported = structure(tact_document(path, PALM))
    assert exported == sample
    assert sample[".project.tracks[].effects[].modes.<position>.pathMode.feedback[].pointList[].x"]
    assert len(sample) > 40  # every key of the sample, typed


def test_a_path_round_trips_through_a_file(tmp_path):
    path = TimedPath(
        [(0.5, 0.5), (2.5, 3.5), (2.5, 3.5), (2.25, 1.0)],
        [0.3, 1.1, 1.4, 2.0513],
        [0.2, 1.0, 1.0, 0.6],
        "CONST_TDM",
        "FADE_IN_OUT",
    )
    for target in (PALM, VEST):
        out = write_tact(tmp_path / "p.tact", path, target, name="drawn", position="VestBack")
        pattern = load_pattern(out)
        assert pattern.position == "VestBack" and pattern.name == "drawn"
        (back,) = pattern.paths(target)
        assert np.array(back.points) == pytest.approx(np.array(path.points), abs=1e-3)
        assert np.array(back.times_s) == pytest.approx(np.array(path.times_s) - 0.3, abs=5e-4)
        assert back.intensities == pytest.approx(path.intensities, abs=5e-5)
        assert (back.pattern, back.fade) == (path.pattern, path.fade)
        assert pattern.duration_s == pytest.approx(path.duration_s, abs=5e-4)


def test_points_outside_the_actuators_are_clipped_and_sub_millisecond_points_dropped():
    path = TimedPath([(0.0, 6.0), (2.5, 3.0), (2.6, 3.0), (5.0, 0.0)], [0.0, 0.5, 0.5004, 1.0])
    doc = tact_document(path, PALM)
    points = doc["project"]["tracks"][0]["effects"][0]["modes"]["VestFront"]["pathMode"][
        "feedback"
    ][0]["pointList"]
    assert [p["time"] for p in points] == [0, 500, 1000]
    assert (points[0]["x"], points[0]["y"]) == (0, 0) and (points[2]["x"], points[2]["y"]) == (1, 1)
    assert doc["project"]["layout"]["layouts"]["VestFront"][29] == {"index": 29, "x": 1, "y": 1}


def test_scenes_export_their_trace():
    line = Scene(tc.Line((0.5, 1.84), (4.5, 4.16)), duration_s=2.0, direction="reverse")
    path = path_of_scene(line)
    assert path.points == ((4.5, 4.16), (0.5, 1.84)) and path.times_s == (0.0, 2.0)
    assert path.pattern == "CONST_SPEED"
    square = path_of_scene(Scene(tc.Square((2.5, 3.0), 2.0), duration_s=4.0))
    assert len(square.points) == 6 and square.times_s[1] == pytest.approx(0.5)
    circle = Scene(tc.Circle((2.5, 3.0), 2.0), duration_s=2.0, emphasis=0.3)
    sampled = path_of_scene(circle)
    assert len(sampled.points) == 101 and sampled.pattern == "CONST_TDM"
    trace = circle.trace()
    t = np.array([trace.parameter1(s) for s in sampled.times_s[:-1]])
    assert np.array(sampled.points[:-1]) == pytest.approx(tc.Circle((2.5, 3.0), 2.0).f(t))
    assert sampled.points[-1] == pytest.approx((4.5, 3.0))
    drawn = path_from_samples([0.0, 0.1, 0.3], [(1, 1), (2, 2), (3, 1)])
    back = path_of_scene(Scene(drawn, direction="reverse"))
    assert back.points == ((3.0, 1.0), (2.0, 2.0), (1.0, 1.0))
    assert back.times_s == pytest.approx((0.0, 0.2, 0.3))
    with pytest.raises(ValueError, match="no shape to export"):
        path_of_scene(Scene(None))


def test_an_exported_scene_plays_back_as_the_scene(tmp_path):
    # AS depends on the point alone: the 20 ms chords of the circle (sagitta 2 (1 - cos 1.8°) =
    # 0.001 pitches) and the file's 4 decimals move its intensities by about as much. (The
    # circle stays within the tactor centres: beyond them an export clips to 0..1.)
    scene = Scene(tc.Circle((2.5, 3.0), 2.0), "AS", duration_s=2.0)
    out = write_tact(tmp_path / "c.tact", path_of_scene(scene), PALM)
    _, played = load_pattern(out).frames("AS", PALM, rate_hz=50.0)
    _, traced = tc.render_frames(scene.trace(), "AS", sampling=tc.Sampling(50.0), n_frames=100)
    assert played.shape == traced.shape
    assert np.abs(played - traced).max() < 0.003


def test_exports_refuse_what_they_cannot_write():
    path = TimedPath([(0, 0), (1, 1)], [0.0, 0.0004])
    with pytest.raises(ValueError, match=r"a \.tact path needs >= 1 ms"):
        tact_document(path, PALM)
    with pytest.raises(ValueError, match="position must be one of"):
        tact_document(TimedPath([(0, 0), (1, 1)], [0, 1]), PALM, position="Tail")


def test_the_sample_file_re_exports_to_the_same_path(tmp_path):
    (path,) = load_pattern(SAMPLE).paths(VEST)
    out = write_tact(tmp_path / "again.tact", path, VEST)
    again = read_tact(out).paths[0]
    original = read_tact(SAMPLE).paths[0]
    assert again.pattern == original.pattern == "CONST_SPEED"
    assert np.array(again.points) == pytest.approx(np.array(original.points), abs=1e-4)
    assert again.times_s == pytest.approx(original.times_s)
    assert math.isclose(read_tact(out).duration_s, 1.0)


def test_the_exported_vest_layout_numbers_its_motors_as_the_designer_does():
    """bHaptics' Designer numbers a Tactot (vest) panel's 20 motors from the top left, rows of
    four downwards (tests/data/testfeedback.tact; bhaptics/tact-python's CenterX.tact). Before,
    the export numbered them in the profile's order, motor 0 at the bottom left (0, 1)."""
    with open(SAMPLE, encoding="utf-8-sig") as f:
        designer = json.load(f)["project"]["layout"]["layouts"]["VestFront"]
    path = TimedPath([(0.0, 0.0), (3.0, 4.0)], [0.0, 1.0])
    ours = tact_document(path, VEST)["project"]["layout"]["layouts"]["VestFront"]
    assert [m["index"] for m in ours] == [m["index"] for m in designer] == list(range(20))
    for mine, theirs in zip(ours, designer):
        assert (mine["x"], mine["y"]) == pytest.approx((theirs["x"], theirs["y"]), abs=5e-4)


def test_motor_0_of_an_exported_file_is_the_top_left_actuator_when_imported():
    """Export on the palm array, then a dot on motors 0, 4, 25 and 29 (as a Designer user adds
    them by number) comes back on the top-left, top-right, bottom-left and bottom-right tactors:
    cells (0, 5), (4, 5), (0, 0), (4, 0), flat index row * 5 + col."""
    doc = tact_document(TimedPath([(0.5, 0.5), (4.5, 5.5)], [0.0, 1.0]), PALM)
    layout = doc["project"]["layout"]["layouts"]["VestFront"]
    assert [(m["x"], m["y"]) for m in layout[:6]] == [(0, 0), (0.25, 0), (0.5, 0), (0.75, 0),
                                                      (1, 0), (0, 0.2)]  # fmt: skip
    mode = doc["project"]["tracks"][0]["effects"][0]["modes"]["VestFront"]
    mode["mode"] = "DOT_MODE"
    for motor, cell in {0: 5 * 5 + 0, 4: 5 * 5 + 4, 25: 0, 29: 4}.items():
        mode["dotMode"]["feedback"][0]["pointList"] = [{"index": motor, "intensity": 1}]
        ((_, _, actuator, _, _),) = TactPattern(parse_tact(doc)).dots(PALM)
        assert actuator == cell, motor
