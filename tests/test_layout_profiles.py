"""Layouts in device profiles: the shipped profiles, refusals naming the field, the live path and
the stream on a layout, the command line."""

import copy
import json
import math

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.link import SimulatedArray
from tactile_core.device.profile import ProfileError, load_profile, profile_from_dict
from tactile_core.rendering.correction import quantize
from tactile_core.rendering.scene import Scene
from tactile_core.rendering.trace import Sampling, Trace, render_frames
from tactile_core.stream.streamer import Streamer

BELT = {
    "format": "tactile-device-profile",
    "version": 1,
    "name": "belt",
    "pitch_mm": 100.0,
    "levels": 23,
    "layout": {
        "units": "mm",
        "actuators": [[100.0 * k, 0.0] for k in range(8)],
        "wrap": {"axis": "x", "circumference": 800.0},
    },
}


def with_layout(**changes):
    data = copy.deepcopy(BELT)
    data["layout"].update(changes)
    return data


@pytest.mark.parametrize(
    "name, size, grid",
    [("palm-5x6", 30, True), ("grid-3x3", 9, True), ("belt-8", 8, False),
     ("sleeve-2x6", 12, False), ("vest-4x5", 20, False), ("vest-front-back", 40, False)],
)  # fmt: skip
def test_shipped_profiles(name, size, grid):
    profile = load_profile(name)
    assert profile.channels == profile.layout.size == size
    assert profile.layout.is_grid is grid


def test_sleeve_positions_in_pitches_and_groups():
    sleeve = load_profile("sleeve-2x6")  # 40 mm round (wrapping, 240 mm), rings 60 mm apart
    np.testing.assert_allclose(sleeve.layout.xy[:2], [[0.5, 0.0], [1.5, 0.0]])
    np.testing.assert_allclose(sleeve.layout.xy[6], [0.5, 1.5])
    assert sleeve.layout.wrap.circumference == 6.0
    assert dict(sleeve.layout.groups)["elbow"] == tuple(range(6, 12))
    assert sleeve.layout.group_of(7) == ("elbow",)


def test_profile_round_trip_keeps_the_layout():
    for name in ("belt-8", "sleeve-2x6", "vest-4x5"):
        profile = load_profile(name)
        again = profile_from_dict(json.loads(json.dumps(profile.to_dict())))
        assert again.layout == profile.layout
        assert again.array == profile.array


@pytest.mark.parametrize(
    "data, field",
    [
        (with_layout(actuators=[]), "layout.actuators"),
        (with_layout(actuators=[[0.0, 0.0], [0.0, 0.0]]), "duplicate positions"),
        (with_layout(actuators=[[0.0, 0.0], ["1", 0.0]]), r"layout.actuators\[1\].x"),
        (with_layout(actuators=[[0.0, 0.0], [1e999, 0.0]]), r"layout.actuators\[1\].x"),
        (
            with_layout(actuators=[[0.0, 0.0], [900.0, 0.0]]),
            r"'layout.actuators\[1\].x' is 900 mm, outside the wrap \[0, 800\) mm",
        ),
        (with_layout(actuators=[[0.0, 0.0]] * 1 + [[k, 1.0] for k in range(300)]), "at most 255"),
        (with_layout(wrap={"axis": "z", "circumference": 800}), "layout.wrap.axis"),
        (with_layout(wrap={"axis": "x", "circumference": -1}), "layout.wrap.circumference"),
        (with_layout(units="inch"), "layout.units"),
        (with_layout(units="normalized"), "layout.size_mm"),
        (
            with_layout(groups={"a": [0, 99]}),
            r"'layout.groups.a\[1\]' names actuator 99, which does not exist: the layout has 8",
        ),
        (with_layout(groups={"a": [-1]}), r"'layout.groups.a\[0\]' names actuator -1"),
        (with_layout(groups={"a": "x"}), r"'layout.groups.a' must be a list of actuator indices"),
        (with_layout(groups={"a": [0.5]}), r"'layout.groups.a\[0\]' must be an actuator index"),
        (with_layout(groups={"a": [True]}), r"'layout.groups.a\[0\]' must be an actuator index"),
        (with_layout(groups=["a"]), "'layout.groups' must map names to lists"),
        (with_layout(shape="round"), "layout.shape"),
        ({**BELT, "columns": 8}, "'columns' and field 'layout'"),
        ({**BELT, "channel_order": "column-major"}, "needs a grid"),
    ],
)
def test_bad_layout_profiles_are_refused_naming_the_field(data, field):
    with pytest.raises(ProfileError, match=field):
        profile_from_dict(data, source="belt.json")


def test_layout_profile_file_with_nan_is_refused(tmp_path):
    path = tmp_path / "belt.json"
    path.write_text(json.dumps(BELT).replace("[700.0, 0.0]", "[NaN, 0.0]"))
    with pytest.raises(ProfileError, match="not valid JSON: NaN"):
        load_profile(path)


def test_live_frames_on_a_layout_equal_the_batch_frames():
    layout = load_profile("sleeve-2x6").layout
    trace = Trace(tc.Line((4.0, 0.2), (8.5, 1.3)), duration_s=1.0, pause_s=0.0, repeat=True)
    for method in ("BA", "RO", "GS", "PK", "EN"):
        for sampling in (Sampling(300.0), Sampling(300.0, "box", 4)):
            live = tc.LiveFrames(trace, method, sampling, 0.33, 0.7, layout)
            _, batch = render_frames(
                trace, method, sampling=sampling, mu=0.33, gamma=0.7, grid=layout
            )
            assert batch.shape == (300, 12)
            for k in range(0, 300, 7):
                np.testing.assert_allclose(live.compute(k) and live.frame(k), batch[k], atol=1e-12)


def test_streaming_a_layout_sends_its_actuators_levels():
    profile = load_profile("belt-8")
    array = SimulatedArray(profile)
    scene = Scene(
        tc.Line((6.5, 0.0), (9.5, 0.0)), "BA", mu=0.33, gamma=0.7, duration_s=1.0, hold_s=0.25
    )
    with Streamer(array, profile, scene=scene) as streamer:
        assert streamer.identified.wait(5)
        deadline = 200
        while array.frames < 5 and deadline:
            streamer.clock.sleep(0.01)
            deadline -= 1
        levels = array.levels()
    assert levels.shape == (8,)
    # a quarter of the way along 6.5 -> 9.5 is x = 7.25: actuator 7 at 0.75, actuator 0 at 0.25
    expected = np.zeros(8)
    expected[7], expected[0] = 0.75, 0.25
    want = quantize(tc.correct(expected, 0.33, 0.7), 23)
    np.testing.assert_array_equal(levels, want)
    assert math.isclose(want[7] / 22, 0.33 + 0.67 * 0.75**0.7, abs_tol=0.5 / 22)


def test_paper_method_on_a_layout_profile_is_refused_by_the_cli(capsys, tmp_path):
    from tactile_core.cli import main

    code = main(["stream", "--device", "sim", "--profile", "belt-8", "--shape",
                 "line:0,0,3,0", "--method", "AS", "--seconds", "0.1"])  # fmt: skip
    assert code != 0
    assert "cannot render on this layout" in capsys.readouterr().err


def test_render_onto_a_profile_names_its_actuators(tmp_path):
    from tactile_core.cli import main

    out = tmp_path / "sleeve.csv"
    args = ["--shape", "line:0,0.75,6,0.75", "--method", "BA", "--rate", "10", "--duration", "1"]
    code = main(["render", "--profile", "sleeve-2x6", *args, "--out", str(out)])
    assert code == 0
    header, *rows = out.read_text().splitlines()
    assert header.split(",")[:3] == ["time", "wrist-0", "wrist-1"]
    assert len(header.split(",")) == 13 and len(rows) == 11
    # halfway between the rings (y = 0.75 of 1.5) at x = 0 = actuator 0's... seam: each
    # ring's actuator 5 (x = 5.5) and 0 (x = 0.5) share the point 0.5 / 0.5 -> 0.25 each
    first = np.array(rows[0].split(","), dtype=float)[1:]
    expected = np.zeros(12)
    expected[[0, 5, 6, 11]] = 0.25
    np.testing.assert_allclose(first, expected, atol=1e-9)


def test_experiments_refuse_a_layout_profile(tmp_path):
    from tactile_core.experiments.results import open_session
    from tactile_core.experiments.runners import Experiment1

    session = open_session(tmp_path, "p1", device_profile="belt-8")
    with pytest.raises(ValueError, match="need a grid profile"):
        Experiment1(session, profile=load_profile("belt-8"))


def test_tuning_the_correction_on_a_layout_says_it_needs_a_grid(capsys):
    from tactile_core.cli import main

    code = main(["tune-correction", "--simulate", "--threshold", "0.2", "--exponent", "1",
                 "--profile", "belt-8"])  # fmt: skip
    assert code != 0
    err = capsys.readouterr().err
    assert "needs a grid of at least 3 x 3" in err and "got a layout: 8 actuators" in err


def test_the_scripting_api_defaults_to_a_method_the_layout_renders():
    # IM (play) and AS (point), the grid's defaults, would be refused on a belt
    with tc.open_array("sim", profile=load_profile("belt-8")) as array:
        shown = array.play("line:0,0,8,0", duration_s=0.1)
        assert shown.scene.method == "BA"
        array.point(1.0, 0.0)
        assert array.streamer.scene.method == "BA"
