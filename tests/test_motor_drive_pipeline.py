"""Motor-aware drive wherever a scene goes: the stream's levels, across scene changes and
pauses, the scene and preset field, the experiments' pipeline record, the command line and the
scripting API. Expected drive comes from :func:`motor_drive`, whose values
tests/test_motor_drive.py works by hand."""

import json
import math

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import default_profile, load_profile
from tactile_core.files.presets import Preset, PresetError, load_preset, save_preset
from tactile_core.rendering.motor_drive import motor_drive
from tactile_core.rendering.percept import predict
from tactile_core.rendering.scene import PAPER_PIPELINE, Pipeline, Scene
from tactile_core.stream._plan import _ChannelLevels, _Plan

from .helpers import run_cli_here
from .test_streamer import run

CIRCLE = tc.Circle((2.5, 3.0), 2.0)
LINE = tc.Line((0.5, 1.84), (4.5, 4.16))
PALM = default_profile()


def _expected_levels(scene, n):
    """The scene's first ``n`` frames corrected, motor-aware for the palm motors from rest if
    the scene says so, rounded to 23 levels: ``(n, 30)``."""
    _, frames = tc.render_frames(scene.trace(), scene.method, sampling=scene.sampling(),
                                 mu=scene.mu, gamma=scene.gamma, n_frames=n)  # fmt: skip
    frames = frames.reshape(n, 30)
    if scene.compensate_motors:
        frames, _ = motor_drive(frames, PALM.motor, scene.rate_hz)
    return tc.quantize(frames, 23)


def _levels(channels, plan, ks):
    return np.array([np.frombuffer(channels.levels(plan, k, None, set())[0], np.uint8) for k in ks])


def test_the_stream_sends_motor_aware_levels():
    scene = Scene(CIRCLE, "AS", mu=0.33, gamma=0.7, rate_hz=100.0, compensate_motors=True)
    frames, _ = run(scene, 120)
    sent = np.array([f[2] for f in frames[:100]])
    np.testing.assert_array_equal(sent, _expected_levels(scene, 100))
    plain = _expected_levels(scene.replace(compensate_motors=False), 100)
    assert (sent > plain).any() and (sent < plain).any()  # overdrive and drive off


def test_plain_drive_is_the_default_and_unchanged():
    scene = Scene(CIRCLE, "IM", mu=0.33, gamma=0.7)
    assert scene.compensate_motors is False and PAPER_PIPELINE.compensate_motors is False
    plan = _Plan(scene, PALM, 20.0, now_s=0.0)
    assert plan.motor is None
    _, frames = tc.render_frames(scene.trace(), "IM", sampling=scene.sampling(), mu=0.33,
                                 gamma=0.7, n_frames=300)  # fmt: skip
    got = _levels(_ChannelLevels(PALM), plan, range(300))
    np.testing.assert_array_equal(got, tc.quantize(frames, 23).reshape(300, 30))


def test_a_new_scene_snapshot_keeps_the_spinning_motors_instead_of_overdriving_from_rest():
    scene = Scene(LINE, "AS", mu=0.33, gamma=0.7, compensate_motors=True)
    channels = _ChannelLevels(PALM)
    _levels(channels, _Plan(scene, PALM, 20.0, now_s=0.0), range(150))
    # Another snapshot of the same frames (the tuner swaps one in on every change): a new plan.
    again = _Plan(scene.replace(marker="moved"), PALM, 20.0, now_s=0.5)
    got = _levels(channels, again, [150])[0]
    fresh = _levels(_ChannelLevels(PALM), again, [150])[0]  # what motors at rest would need
    continued = _levels(_ChannelLevels(PALM), _Plan(scene, PALM, 20.0, now_s=0), range(151))[-1]
    np.testing.assert_array_equal(got, continued)
    assert (fresh == 22).sum() > (got == 22).sum()


def test_a_pause_lets_the_motors_run_down_for_as_long_as_it_lasted():
    scene = Scene(LINE, "AS", mu=0.33, gamma=0.7, compensate_motors=True)
    for pause_s, expect_full in ((0.005, False), (1.0, True)):
        channels = _ChannelLevels(PALM)
        playing = _Plan(scene, PALM, 20.0, now_s=0.0)
        before = _levels(channels, playing, range(100))[-1]
        paused = _Plan(scene.replace(playing=False), PALM, 20.0, now_s=1.0)
        assert not _levels(channels, paused, [100]).any()
        again = _Plan(scene, PALM, 20.0, now_s=1.0 + pause_s)
        after = _levels(channels, again, [100])[0]
        lit = before > 0
        # After 5 ms the motors still run near their drive; after 1 s (16 tau_down) they are
        # at rest and the lit tactors get the spin-up overdrive again.
        assert (after[lit] == 22).all() == expect_full


def test_skipped_deadlines_count_as_the_last_drive_held():
    scene = Scene(LINE, "IM", mu=0.33, gamma=0.7, compensate_motors=True)
    plan = _Plan(scene, PALM, 20.0, now_s=0.0)
    skipping = _levels(_ChannelLevels(PALM), plan, [*range(60), 70])[-1]
    # Frames 60-69 were never computed: frame 59's drive held 11 periods, then frame 70.
    _, frames = tc.render_frames(scene.trace(), "IM", sampling=scene.sampling(), mu=0.33,
                                 gamma=0.7, n_frames=71)  # fmt: skip
    flat = frames.reshape(71, 30)
    sent, state = motor_drive(flat[:60], PALM.motor, 300.0)
    held = np.repeat(sent[59:60], 10, axis=0)
    _, state = PALM.motor.effective(held, 300.0, state=state)
    expected, _ = motor_drive(flat[70:71], PALM.motor, 300.0, state=state)
    np.testing.assert_array_equal(skipping, tc.quantize(expected, 23)[0])


def test_the_status_says_which_drive_and_a_profile_without_motors_gets_plain_drive():
    link = type("Link", (), {"description": "sim"})()
    scene = Scene(tc.Circle((4.0, 0.0), 1.0), "RO", compensate_motors=True)
    _, status = _Plan(scene, PALM, 20.0, now_s=0.0).describe(PALM, link, "")
    assert status.endswith("to sim, motor-aware drive")
    belt = load_profile("belt-8")
    plan = _Plan(scene, belt, 20.0, now_s=0.0)
    assert belt.motor is None and plan.motor is None
    _, status = plan.describe(belt, link, "")
    assert status.endswith("plain drive: profile belt-8 has no motor constants ('motor')")


def test_the_scene_and_preset_carry_the_setting(tmp_path):
    with pytest.raises(ValueError, match="compensate_motors must be true or false"):
        Scene(CIRCLE, compensate_motors="yes")
    path = save_preset(Preset(Scene(CIRCLE, "IM", compensate_motors=True)), tmp_path / "p.json")
    data = json.loads(path.read_text())
    assert data["compensate_motors"] is True and load_preset(path).scene.compensate_motors
    del data["compensate_motors"]  # a preset from before the setting: plain drive
    path.write_text(json.dumps(data))
    assert load_preset(path).scene.compensate_motors is False
    data["compensate_motors"] = 1
    path.write_text(json.dumps(data))
    with pytest.raises(PresetError, match="'compensate_motors' must be true or false"):
        load_preset(path)


def test_experiments_record_motor_aware_drive_in_the_session(tmp_path):
    from tactile_core.experiments.results import SessionError, open_session
    from tactile_core.experiments.runners import Experiment1

    pipeline = Pipeline(compensate_motors=True)
    assert not pipeline.is_paper
    runner = Experiment1(open_session(tmp_path, "pp01", pipeline=pipeline))
    assert runner.current.scene.compensate_motors
    runner.close()
    data = json.loads((tmp_path / "participant-pp01" / "session.json").read_text())
    assert data["pipeline"]["compensate_motors"] is True
    assert data["runs"]["exp1"]["pipeline"]["compensate_motors"] is True
    with pytest.raises(SessionError, match="pipeline"):
        open_session(tmp_path, "pp01", pipeline=PAPER_PIPELINE)


def test_a_session_recorded_before_the_setting_resumes_as_plain_drive(tmp_path):
    from tactile_core.experiments.results import open_session
    from tactile_core.experiments.runners import Experiment3

    session = open_session(tmp_path, "pp02")
    runner = Experiment3(session)
    runner.answer("continue")
    runner.close()
    path = tmp_path / "participant-pp02" / "session.json"
    data = json.loads(path.read_text())
    for record in (data["pipeline"], data["runs"]["exp3"]["pipeline"]):
        del record["compensate_motors"]  # as version 0.3 wrote it
    path.write_text(json.dumps(data))
    resumed = open_session(tmp_path, "pp02", pipeline=PAPER_PIPELINE)
    assert resumed.get_pipeline() == PAPER_PIPELINE
    Experiment3(resumed).close()  # the run's record is the same pipeline: it resumes


def test_tactile_render_writes_motor_aware_frames(tmp_path, capsys):
    out = tmp_path / "f.npz"
    code, stdout, _ = run_cli_here(capsys, "render", "--shape", "line:0.5,1.84,4.5,4.16",
                                   "--method", "AS", "--mu", "0.33", "--gamma", "0.7", "--rate",
                                   "300", "--compensate-motors", "--out", out)  # fmt: skip
    assert code == 0 and "motor-aware drive for 30/60 ms motors" in stdout
    got = np.load(out)["frames"]
    t = np.minimum(np.arange(601) / 300 / 2.0, 1.0)
    plain = tc.correct(tc.render(LINE, "AS", t), 0.33, 0.7)
    expected, _ = motor_drive(plain, PALM.motor, 300.0)
    np.testing.assert_allclose(got, expected, atol=1e-12)
    # The first lit tactor at full drive while its motor spins up: more than the 0.33+ asked.
    first = np.unravel_index(np.argmax(plain[0]), plain[0].shape)
    assert got[0][first] == 1.0 > plain[0][first]


def test_the_command_line_refuses_compensation_without_motor_constants(tmp_path, capsys):
    for argv in (
        ["render", "--shape", "circle:4,0,1", "--method", "RO", "--profile", "belt-8", "--out",
         tmp_path / "x.csv"],
        ["stream", "--device", "sim", "--shape", "circle:4,0,1", "--method", "RO", "--profile",
         "belt-8", "--seconds", "0.1"],
        ["serve", "--device", "sim", "--profile", "belt-8", "--seconds", "0.1"],
    ):  # fmt: skip
        code, _, err = run_cli_here(capsys, *argv, "--compensate-motors")
        assert code == 2, argv[0]
        assert "--compensate-motors needs the motors' time constants: profile belt-8" in err
    assert not (tmp_path / "x.csv").exists()


def test_tactile_serve_and_stream_take_the_option():
    from tactile_core.cli._parser import build_parser
    from tactile_core.cli._serve import _check

    parser = build_parser()
    args = parser.parse_args(["serve", "--device", "sim", "--compensate-motors"])
    _, scene = _check(args)
    assert scene.compensate_motors
    _, scene = _check(parser.parse_args(["serve", "--device", "sim"]))
    assert not scene.compensate_motors
    args = parser.parse_args(["stream", "--device", "sim", "--shape", "circle:2.5,3,2",
                              "--method", "AS", "--compensate-motors"])  # fmt: skip
    assert args.compensate_motors


def test_open_array_plays_motor_aware_drive():
    with tc.open_array("sim", compensate_motors=True) as array:
        shown = array.play(CIRCLE, "AS", duration_s=0.05, wait=False)
        assert shown.scene.compensate_motors
        array.point(2.5, 3.0, 0.5)
        assert array.streamer.scene.compensate_motors
    with pytest.raises(ValueError, match="compensate_motors needs the motors' time constants"):
        tc.open_array("sim", "belt-8", compensate_motors=True)
    with pytest.raises(ValueError, match="compensate_motors must be true or false"):
        tc.open_array("sim", compensate_motors="on")


def test_predict_sees_the_lag_the_stage_takes_away():
    motor = PALM.motor
    kw = dict(rate_hz=300.0, levels=23, motor=motor)
    plain = predict(LINE, "AS", **kw)
    aware = predict(LINE, "AS", compensate=motor, **kw)
    assert aware.mean_error_mm < plain.mean_error_mm / 2  # 1.8 -> 0.6 mm (docs/benchmarks.md)
    with pytest.raises(ValueError, match="compensate need rate_hz"):
        predict(LINE, "AS", compensate=motor)
    assert math.isfinite(aware.ripple)
