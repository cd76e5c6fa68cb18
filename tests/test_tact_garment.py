"""Every position of a garment at once, connected dots, and bHaptics' play-time options
(ScaleOption, RotationOption): docs/tact.md, "Every position of a garment"."""

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.cli import main
from tactile_core.device.profile import load_profile
from tactile_core.files.tact import (
    POSITION_GROUPS,
    RotationOption,
    ScaleOption,
    TactPattern,
    load_pattern,
    parse_tact,
)

from . import tact_support as ts

VEST = load_profile("vest-front-back").layout
SLEEVES = load_profile("sleeves-pair").layout
PALM = tc.Grid(5, 6)
FRONT, BACK = range(20), range(20, 40)


def sweep():
    """A sweep round the body: across the front's middle row in 0-500 ms, then the back's in
    500-1000 ms."""
    row = [ts.point(0, 0.5, 1, 0), ts.point(1, 0.5, 1, 500)]
    return ts.document(ts.effect({"VestFront": ts.path_mode(row)}, 0, 500),
                       ts.effect({"VestBack": ts.path_mode(row)}, 500, 500))  # fmt: skip


def lit_in(frames, actuators) -> np.ndarray:
    """Per frame, whether any of ``actuators`` is lit."""
    return (frames[:, list(actuators)] > 0).any(axis=1)


def test_a_front_to_back_sweep_lights_the_front_then_the_back():
    """Before: one position played (VestFront over the whole vest), VestBack 'not played'."""
    pattern = TactPattern(parse_tact(sweep()))
    assert pattern.played(VEST) == (("VestFront", "front"), ("VestBack", "back"))
    assert pattern.skipped_on(VEST) == () and pattern.duration_on(VEST) == pytest.approx(1.0)
    time_s, frames = pattern.frames("BA", VEST, rate_hz=20.0, corrected=False)
    first, second = time_s < 0.5, time_s >= 0.5
    assert lit_in(frames[first], FRONT).all() and not lit_in(frames[first], BACK).any()
    assert lit_in(frames[second], BACK).all() and not lit_in(frames[second], FRONT).any()
    # on each panel the point moves left to right along the middle row (row 2)
    for panel, rows in (("front", frames[first]), ("back", frames[second])):
        columns = [np.average(range(4), weights=r[[VEST.names.index(f"{panel}-r2c{c}")
                                                    for c in range(4)]]) for r in rows]  # fmt: skip
        assert columns == sorted(columns) and columns[-1] - columns[0] > 2


def test_the_command_line_plays_every_position_and_says_where(tmp_path, capsys):
    path = ts.write(tmp_path, sweep())
    out = tmp_path / "f.csv"
    assert main(["render", "--shape", f"tact:{path}", "--method", "BA", "--profile",
                 "vest-front-back", "--rate", "20", "--out", str(out)]) == 0  # fmt: skip
    said = capsys.readouterr().out
    assert "wrote 20 frames of VestFront on front and VestBack on back of" in said
    assert main(["stream", "--shape", f"tact:{path}", "--method", "BA", "--profile",
                 "vest-front-back", "--device", "sim"]) == 0  # fmt: skip
    assert "playing VestFront on front and VestBack on back of" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("position", "groups", "expected"),
    [
        ("VestFront", ("front", "back"), "front"),
        ("VestBack", ("Front", "Back"), "Back"),  # any case
        ("ForearmL", ("left", "right"), "left"),
        ("ForearmR", ("left", "right"), "right"),
        ("Head", ("left", "right"), None),
        ("VestFront", ("left", "right"), None),
        ("Custom", ("custom",), "custom"),  # a group named as the position
    ],
)
def test_positions_map_onto_groups_by_the_table(position, groups, expected):
    from tactile_core.files._tact_place import group_for

    assert group_for(position, groups) == expected
    assert POSITION_GROUPS["VestFront"] == ("front",)


def test_forearms_play_on_a_pair_of_sleeves():
    row = [ts.point(0, 0, 1, 0), ts.point(1, 1, 1, 400)]
    data = ts.document(ts.effect({"ForearmL": ts.path_mode(row)}, 0, 400))
    data["project"]["layout"]["layouts"]["ForearmL"] = ts.VEST_LAYOUT[:6]
    pattern = TactPattern(parse_tact(data))
    assert pattern.played(SLEEVES) == (("ForearmL", "left"),)
    _, frames = pattern.frames("BA", SLEEVES, rate_hz=50.0, corrected=False)
    assert lit_in(frames, range(12)).all() and not lit_in(frames, range(12, 24)).any()


def test_without_groups_for_it_one_position_plays_over_the_array():
    pattern = TactPattern(parse_tact(sweep()))
    assert pattern.played(PALM) == (("VestFront", None),)
    assert pattern.skipped_on(PALM) == ("VestBack",)
    assert pattern.duration_on(PALM) == pytest.approx(0.5)  # the front's own effect
    named = TactPattern(parse_tact(sweep()), "VestBack")
    assert named.played(VEST) == (("VestBack", None),)  # named: alone, over the whole vest
    assert named.duration_on(VEST) == pytest.approx(1.0)


def connected():
    """Connected dots on the front: motor 0 (1.0) at 0 ms, motor 1 (0.5) at 100 ms, motor 2
    (0.5) at 200 ms, the effect ending there."""
    mode = ts.dot_mode([], 0, 0)
    mode["dotMode"] = {"dotConnected": True, "feedback": [
        {"startTime": s, "endTime": e, "playbackType": "NONE",
         "pointList": [{"index": i, "intensity": v}]}
        for s, e, i, v in ((0, 100, 0, 1.0), (100, 200, 1, 0.5), (200, 200, 2, 0.5))]}  # fmt: skip
    return ts.document(ts.effect({"VestFront": mode}, 0, 200))


def test_connected_dots_fade_into_each_other_as_bhaptics_plays_them():
    """Before: the dots played as separate dots, each on alone over its own span."""
    pattern = TactPattern(parse_tact(connected()))
    grid = tc.Grid(4, 5)  # the vest's front, motor for motor: motors 0, 1, 2 on the top row
    live = pattern.live("AS", grid, tc.Sampling(50.0), 0.0, 1.0)
    raw = live.raw_at([0.0, 0.05, 0.1, 0.15, 0.2])[:, [grid.flat(c, 4) for c in range(3)]]
    assert raw.tolist() == [
        [1.0, 0.0, 0.0],
        [0.5, 0.25, 0.0],  # half way: 1.0 x 0.5 and 0.5 x 0.5
        [0.0, 1.0, 0.0],  # motor 1's entry: its fade in ends as its fade out starts; both count
        [0.0, 0.25, 0.25],
        [0.0, 0.0, 0.5],
    ]
    assert pattern.notes == ()
    # on another array the motors' nearest actuators cross-fade the same way: frame 1 at 20 Hz
    # samples 75 ms, motor 0 at 1.0 x 0.25, motor 1 at 0.5 x 0.75 = 0.375, cut to 0.37
    _, frames = pattern.frames("AS", PALM, rate_hz=20.0, corrected=False)
    top_left, next_one = PALM.flat(0, 5), PALM.flat(1, 5)
    assert frames.reshape(len(frames), -1)[1, [top_left, next_one]].tolist() == [0.25, 0.37]


ACROSS = [ts.point(0, 0.5, 1.0, 0), ts.point(1, 0.5, 0.6, 1000)]


def dot_and_path():
    """Motor 3 (top right) at 0.8 from 100 to 300 ms; a path across the middle row 0-1 s."""
    return ts.document(
        ts.effect({"VestFront": ts.dot_mode([(3, 0.8)], 0, 200)}, 100, 200),
        ts.effect({"VestFront": ts.path_mode(ACROSS)}, 0, 1000),
    )


def test_scale_multiplies_intensities_and_times():
    pattern = TactPattern(parse_tact(dot_and_path()), scale=(0.5, 2.0))
    paths, (dot,) = pattern.content
    assert (dot.intensity, dot.start_s, dot.end_s) == pytest.approx((0.4, 0.2, 0.6))
    (path,) = paths
    assert path.times_s == pytest.approx((0.0, 2.0)) and path.intensities == (0.5, 0.3)
    assert pattern.duration_s == pytest.approx(2.0)
    loud = TactPattern(parse_tact(dot_and_path()), scale=ScaleOption(2.0, 1.0))
    assert loud.content[1][0].intensity == 1.0  # capped
    assert loud.content[0][0].intensities == (1.0, 1.0)


def test_rotation_turns_the_vest_round_the_body():
    file = parse_tact(dot_and_path())
    # a quarter turn to the wearer's left: the front's right edge (motor 3, x = 1) goes half
    # way across the back; the path from the front's middle (x = 0 .. 1) is cut at the
    # wearer's left side (the front's x = 1, the back's x = 0) half way through
    (front, back), (dot,) = TactPattern(file, rotation=(90, 0)).content
    assert (dot.position, dot.x, dot.y) == ("VestBack", 0.5, 0.0)
    assert front.position == "VestFront" and back.position == "VestBack"
    assert front.points == ((0.5, 0.5), (1.0, 0.5)) and front.times_s == (0.0, 0.5)
    assert back.points == ((0.0, 0.5), (0.5, 0.5)) and back.times_s == (0.5, 1.0)
    assert front.intensities == pytest.approx((1.0, 0.8)) and back.intensities[-1] == 0.6
    # half a turn: front and back swap; the front's x = 1 (the wearer's left side) goes to the
    # right side, the front's x = 0 (the back's x = 1)
    (path,), (dot,) = TactPattern(file, rotation=(180, 0)).content
    assert (dot.position, dot.x) == ("VestFront", 0.0) and path.position == "VestBack"
    assert path.points == ((0.0, 0.5), (1.0, 0.5))
    # up by a quarter of the panel: the middle row to the second; what leaves the panel is gone
    (path,), dots = TactPattern(file, rotation=(0, 0.25)).content
    assert path.points == ((0.0, 0.25), (1.0, 0.25)) and dots == ()  # motor 3 (top row) is gone
    (path,), (dot,) = TactPattern(file, rotation=(0, -0.5)).content  # down by half
    assert path.points == ((0.0, 1.0), (1.0, 1.0)) and (dot.x, dot.y) == (1.0, 0.5)
    assert RotationOption(-90.0, 0).angle_deg == 270.0


def test_a_rotated_sweep_plays_on_both_panels():
    pattern = TactPattern(parse_tact(dot_and_path()), rotation=(90, 0))
    time_s, frames = pattern.frames("BA", VEST, rate_hz=10.0, corrected=False)
    assert pattern.played(VEST) == (("VestFront", "front"), ("VestBack", "back"))
    assert lit_in(frames[time_s < 0.4], FRONT).all()
    assert lit_in(frames[time_s > 0.5], BACK).all()
    assert not lit_in(frames[time_s > 0.5], FRONT).any()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"scale": (-1, 1)}, "intensity must be within [0, 100], got -1"),
        ({"scale": (1, 0)}, "duration must be > 0"),
        ({"scale": (1, 1000)}, "duration must be at most 100, got 1000"),
        ({"scale": "loud"}, "scale must be a ScaleOption or a pair of numbers, got 'loud'"),
        ({"rotation": (float("nan"), 0)}, "angle_deg"),
        ({"rotation": (0, 2)}, "offset_y must be within [-1, 1], got 2"),
        ({"rotation": (1, 2, 3)}, "rotation must be a RotationOption or a pair of numbers"),
    ],
)
def test_bad_options_are_refused_by_name(tmp_path, options, message):
    path = ts.write(tmp_path, sweep())
    with pytest.raises(ValueError) as caught:
        load_pattern(path, **options)
    assert message in str(caught.value)


def test_the_command_line_takes_the_options(tmp_path, capsys):
    path = ts.write(tmp_path, dot_and_path())
    out = tmp_path / "f.csv"
    args = ["render", "--shape", f"tact:{path}", "--method", "BA", "--profile", "vest-front-back",
            "--rate", "10", "--out", str(out)]  # fmt: skip
    assert main([*args, "--tact-scale", "1,2", "--tact-rotate", "90,0"]) == 0
    assert "wrote 20 frames of VestFront on front and VestBack on back" in capsys.readouterr().out
    assert main([*args, "--tact-scale", "loud"]) == 2
    assert "--tact-scale takes two numbers A,B, got 'loud'" in capsys.readouterr().err
    assert main([*args, "--tact-rotate", "0,3"]) == 2
    assert "--tact-rotate: offset_y must be within [-1, 1], got 3" in capsys.readouterr().err
    assert main([*args, "--tact-scale=-1,1"]) == 2  # (a value starting with - takes the =)
    assert "--tact-scale: intensity must be within [0, 100], got -1" in capsys.readouterr().err
