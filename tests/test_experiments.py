"""Experiments: the runners with simulated participants, results on disk, resuming, sessions,
calibration, and the paper's pipeline recorded. (Statistics: test_statistics.py; analysis:
test_analysis.py.)"""

import csv
import os
import subprocess

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.experiments import (
    RUNNERS,
    Calibration,
    Experiment1,
    Experiment2,
    Experiment3,
    SimulatedParticipant,
    open_session,
)
from tactile_core.experiments.runners import CONDITIONS_EXP2
from tactile_core.experiments.stats import apply_order

# --- runners -----------------------------------------------------------------------------


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_experiment1_runs_with_a_simulated_participant(tmp_path):
    session = open_session(tmp_path, "p01", seed=2)
    runner = Experiment1(session)
    prep = runner.current
    assert prep.kind == "prepare" and prep.scene.shape == Experiment1.LINE
    assert prep.scene.duration_s == 2.0 and (prep.scene.mu, prep.scene.gamma) == (0.33, 0.7)
    mapping = runner.mapping
    assert sorted(mapping) == ["AS", "CT", "IM", "MM"]
    assert runner.select(3).method == mapping[2]
    SimulatedParticipant(seed=1).run(runner)
    runner.close()
    data = rows(session.folder + "/exp1.csv")
    assert (
        len(data) == 25
        and data[0]["stage"] == "prepare"
        and data[0]["mapping"] == " ".join(mapping)
    )
    order = apply_order(session.orders["exp1"], ["CT", "MM", "AS", "IM"])
    line = [r for r in data if r["stage"] == "line"]
    assert [r["property"] for r in line] == ["quality"] * 4 + ["smoothness"] * 4 + ["thickness"] * 4
    assert [r["method"] for r in line[:4]] == order  # the counterbalanced order
    assert [r["stage"] for r in data[13:]] == ["circle"] * 12
    assert all(0 <= int(r["answer"]) <= 100 for r in data[1:])


def test_experiment2_follows_the_papers_procedure(tmp_path):
    session = open_session(tmp_path, "p02", seed=4)
    runner = Experiment2(session)
    scenes = []
    feedback = []
    participant = SimulatedParticipant(seed=3)
    while not runner.finished:
        trial = runner.current
        if trial.kind == "direction":
            scenes.append((trial, trial.scene))
        feedback.append((trial, runner.answer(participant.respond(trial))))
    runner.close()
    data = [r for r in rows(session.folder + "/exp2.csv") if r["stage"] in CONDITIONS_EXP2]
    assert len(data) == 4 * 30
    stages = list(dict.fromkeys(r["stage"] for r in data))
    assert stages == apply_order(session.orders["exp2"], ["L1", "L2", "L3", "L4"])
    for stage in stages:
        track = [r for r in data if r["stage"] == stage]
        assert float(track[0]["length"]) == 2.0
        run = 0
        for r in track:  # every next length follows the 2-down/1-up rule, worked here
            length, correct = float(r["length"]), r["correct"] == "1"
            run = run + 1 if correct else 0
            if not correct:
                expected = min(length * 1.46, 4.0)
            elif run == 2:
                expected, run = length * 0.685, 0
            else:
                expected = length
            assert float(r["next_length"]) == pytest.approx(expected, rel=1e-5)
        assert {r["direction"] for r in track} <= {"up", "down", "left", "right"}
    for trial, scene in scenes:
        midpoint, mu, gamma = CONDITIONS_EXP2[trial.stage]
        assert scene.method == "AS" and (scene.mu, scene.gamma) == (mu, gamma)
        assert (scene.duration_s, scene.pause_s) == (2.0, 0.5)
        p0, p1 = np.array(scene.shape.p0), np.array(scene.shape.p1)
        assert np.allclose((p0 + p1) / 2, midpoint)
        assert np.linalg.norm(p1 - p0) == pytest.approx(float(trial.info["length"]), rel=1e-5)
        step = {"up": (0, 1), "down": (0, -1), "left": (-1, 0), "right": (1, 0)}[
            trial.info["direction"]
        ]
        assert np.allclose(np.sign(p1 - p0), step)
    for trial, text in feedback:
        if trial.kind == "direction" and text != "Correct.":
            assert text == f"Wrong: the line moved {trial.info['direction']}."
    assert runner.estimate(stages[0]) > 0


def test_experiment3_follows_the_papers_procedure(tmp_path):
    session = open_session(tmp_path, "p03", seed=5)
    runner = Experiment3(session)
    participant = SimulatedParticipant(seed=2, timeout_rate=0.1)
    trials = []
    while not runner.finished:
        trial = runner.current
        trials.append(trial)
        runner.answer(participant.respond(trial))
    runner.close()
    questions = [t for t in trials if t.kind == "shape"]
    assert len(questions) == 40
    for method in ("CT", "MM", "AS", "IM"):
        shapes = [t.info["shape"] for t in questions if t.stage == method]
        assert sorted(shapes) == ["circle"] * 5 + ["square"] * 5
    for t in questions:
        s = t.scene
        assert t.time_limit_s == 20.0 and s.pause_s == 0.0 and s.duration_s == 2.0
        assert s.direction == "forward" and s.shape.center == (2.5, 3.5)
        if t.info["shape"] == "square":
            assert s.shape.edge == 4.0
        else:
            assert 4.0 < 2 * s.shape.radius < 4.3  # "just over 4"
    data = [r for r in rows(session.folder + "/exp3.csv") if r["stage"] in ("CT", "MM", "AS", "IM")]
    assert list(dict.fromkeys(r["stage"] for r in data)) == apply_order(
        session.orders["exp3"], ["CT", "MM", "AS", "IM"]
    )
    timeouts = [r for r in data if r["timeout"] == "1"]
    assert timeouts and all(r["answer"] == "" and r["correct"] == "0" for r in timeouts)


def test_rows_are_on_disk_before_answer_returns(tmp_path):
    session = open_session(tmp_path, "p04")
    runner = Experiment3(session)
    runner.answer("continue")
    runner.answer("circle", rt_s=1.25)
    # not closed: read through another handle
    data = rows(session.folder + "/exp3.csv")
    runner.close()
    assert len(data) == 2 and data[1]["rt_s"] == "1.250"


def make_lock_stale(lock):
    """Leave a participant's lock as a process that has ended would have left it: its record
    names a process that no longer runs, and its descriptor is closed (the kernel closes a dead
    process's descriptors, which ends its file lock)."""
    import json
    import socket

    pid = subprocess.Popen(["true"])
    pid.wait()
    lock.path.write_text(json.dumps({"host": socket.gethostname(), "pid": pid.pid, "since": "x"}))
    os.close(lock._fd)


def test_bad_answers_are_refused_and_nothing_is_recorded(tmp_path):
    session = open_session(tmp_path, "p05")
    runner = Experiment1(session)
    runner.answer("continue")
    for bad in (101, -1, 50.5, "lots", float("nan")):
        with pytest.raises(ValueError, match="answer"):
            runner.answer(bad)
    runner.answer(70)
    runner.close()
    e2 = Experiment2(session)
    e2.answer("continue")
    with pytest.raises(ValueError, match="answer must be one of"):
        e2.answer("sideways")
    with pytest.raises(ValueError, match="answer must be one of"):
        e2.answer(None)  # no time limit in Experiment 2
    e2.close()
    assert len(rows(session.folder + "/exp1.csv")) == 2
    assert len(rows(session.folder + "/exp2.csv")) == 1


@pytest.mark.parametrize("name", ["exp1", "exp2", "exp3"])
def test_a_crash_loses_nothing_and_the_session_resumes(tmp_path, name):
    # Uninterrupted reference run.
    ref = open_session(tmp_path / "ref", "p06", seed=9, index=3)
    runner = RUNNERS[name](ref)
    SimulatedParticipant(seed=8).run(runner)
    runner.close()
    # The same participant, "crashing" halfway (the runner is dropped, never closed).
    broken = open_session(tmp_path / "run", "p06", seed=9, index=3)
    runner = RUNNERS[name](broken)
    participant = SimulatedParticipant(seed=8)
    half = runner.total // 2
    while runner.done < half:
        if runner.current.kind == "prepare":
            for key in (1, 2, 3, 4, 2, 3):
                runner.select(key)
        runner.answer(participant.respond(runner.current), rt_s=1.0)
    # A crash: every answered row is already synced (test_rows_are_on_disk_before_answer_
    # returns); the dead process leaves its file handle (closed here) and its lock behind.
    runner._file.close()
    make_lock_stale(runner._lock)
    del runner
    resumed = RUNNERS[name](open_session(tmp_path / "run", "p06"))
    assert resumed.done == half
    participant.run(resumed)
    resumed.close()
    drop = ("time", "rt_s")
    a = [{k: v for k, v in r.items() if k not in drop} for r in rows(ref.folder + f"/{name}.csv")]
    b = [
        {k: v for k, v in r.items() if k not in drop} for r in rows(broken.folder + f"/{name}.csv")
    ]
    assert a == b


def test_resuming_with_another_seed_is_refused(tmp_path):
    session = open_session(tmp_path, "p07", seed=1)
    runner = Experiment2(session)
    for _ in range(5):
        runner.answer(SimulatedParticipant(seed=0).respond(runner.current))
    runner.close()
    session.seed = 2
    with pytest.raises(ValueError, match=r"different seed|does not match"):
        Experiment2(session)


def test_session_file_holds_the_essentials(tmp_path):
    import json

    session = open_session(tmp_path, "p08", seed=11, device_profile="palm-5x6", notes="pilot")
    runner = Experiment3(session, emphasis=0.5)
    runner.close()
    data = json.loads((tmp_path / "participant-p08" / "session.json").read_text())
    assert data["participant"] == "p08" and data["seed"] == 11 and data["notes"] == "pilot"
    assert data["software_version"] == tc.__version__ and data["device_profile"] == "palm-5x6"
    assert data["orders"]["exp3"] in tc.ORDERS
    assert data["parameters"]["exp3_emphasis"] == 0.5
    assert runner.current.kind == "continue"
    with pytest.raises(ValueError, match="participant"):
        open_session(tmp_path, "../escape")


def test_participants_get_distinct_orders(tmp_path):
    orders = [open_session(tmp_path, f"p{i:02d}", seed=3).order("exp1") for i in range(12)]
    assert sorted(orders) == sorted(tc.ORDERS)


def test_experiment3_corner_emphasis_reaches_the_scene(tmp_path):
    with Experiment3(open_session(tmp_path, "p09"), emphasis=0.6) as runner:
        runner.answer("continue")
        assert runner.current.scene.emphasis == 0.6
    with pytest.raises(ValueError, match="differs from the session"):
        Experiment3(open_session(tmp_path, "p09"), emphasis=0.2)


# --- calibration -------------------------------------------------------------------------


def test_calibration_finds_each_tactors_threshold(tmp_path):
    rng = np.random.default_rng(1)
    truth = {(c, r): float(rng.uniform(0.15, 0.45)) for r in range(6) for c in range(5)}
    runner = Calibration(open_session(tmp_path, "cal"))
    first = runner.current
    assert first.kind == "detect" and first.scene.gain == 0.5 and first.scene.method == "CT"
    assert first.scene.repeat is False and first.scene.duration_s == 0.5
    SimulatedParticipant(seed=4, tactor_thresholds=truth, detection_spread=0.02).run(runner)
    runner.close()
    errors = [runner.thresholds[c] - truth[c] for c in truth]
    assert np.median(np.abs(errors)) < 0.05
    offset, gain, thresholds = runner.calibration()
    import statistics

    t_ref = statistics.median(runner.thresholds.values())
    grid = tc.Grid()
    for i in range(30):
        th = runner.thresholds[grid.cell(i)]
        assert offset[i] + gain[i] * t_ref == pytest.approx(th)  # threshold to threshold
        assert offset[i] + gain[i] * 1.0 == pytest.approx(1.0)  # full stays full
    from tactile_core.device.profile import default_profile

    calibrated = default_profile().with_calibration(offset, gain, thresholds)
    assert calibrated.calibrated
    assert calibrated.threshold[0] == pytest.approx(runner.thresholds[(0, 0)])


# --- corner emphasis ---------------------------------------------------------------------


def test_corner_emphasis_slows_the_point_near_corners():
    square = tc.Square((2.5, 3.5), 4.0)
    times = np.linspace(0, 1.999, 4000)
    near = {}
    for e in (0.0, 0.3, 0.6):
        t, _ = tc.Trace(square, 2.0, 0.0, emphasis=e).parameter(times)
        d = np.abs(((t[:, None] - np.array(square.corners)) + 0.5) % 1.0 - 0.5).min(axis=1)
        near[e] = (d < 0.02).mean()
        assert (np.diff(t) >= 0).all() and t[0] == 0.0  # monotonic, starts at 0
    assert near[0.0] == pytest.approx(0.16, abs=0.01)  # uniform: 4 x 0.04 of the trace
    assert near[0.0] < near[0.3] < near[0.6]
    circle = tc.Trace(tc.Circle((2.5, 3.5), 2.05), 2.0, 0.0, emphasis=0.6)
    np.testing.assert_allclose(
        circle.parameter(times)[0], tc.Trace(square, 2.0, 0.0, emphasis=0.6).parameter(times)[0]
    )
    line = tc.Trace(tc.Line((0, 0), (1, 1)), 2.0, 0.0, emphasis=0.6)  # no corners: unchanged
    np.testing.assert_allclose(line.parameter(times)[0], times / 2.0)
    with pytest.raises(ValueError, match="emphasis"):
        tc.Trace(square, emphasis=0.95)


# --- the paper's pipeline, recorded ---------------------------------------------------------


def test_experiments_run_the_papers_pipeline_by_default(tmp_path):
    session = open_session(tmp_path, "pp01", seed=1)
    for name in ("exp1", "exp2", "exp3", "calibration"):
        runner = RUNNERS[name](session)
        while runner.current.scene is None:
            runner.answer(SimulatedParticipant(seed=0).respond(runner.current))
        scene = runner.current.scene
        assert (scene.filter, scene.dither, scene.rate_hz) == ("point", False, 300.0), name
        runner.close()


def test_bilevel_methods_stay_bilevel_on_the_papers_pipeline():
    # Point sampling: every frame is one instant of the trace, so CT and MM send only 0 and 22.
    from tactile_core.rendering.scene import PAPER_PIPELINE, Scene

    for method in ("CT", "MM"):
        scene = PAPER_PIPELINE.apply(Scene(tc.Circle((2.5, 3.0), 2.0), method, 0.33, 0.7))
        live = scene.live(tc.Grid())
        values = {v for k in range(750) for _, v in live.entries(k)}
        assert values == {1.0}, method


def test_session_records_the_whole_pipeline(tmp_path):
    import hashlib
    import json

    from tactile_core._shared.assets import asset_path

    session = open_session(tmp_path, "pp02", seed=3)
    Experiment2(session).close()
    data = json.loads((tmp_path / "participant-pp02" / "session.json").read_text())
    assert data["pipeline"] == {"rate_hz": 300.0, "filter": "point", "subsamples": 1,
                                "dither": False, "compensate_motors": False}  # fmt: skip
    run = data["runs"]["exp2"]
    assert run["pipeline"] == data["pipeline"] and run["levels"] == 23
    paper, l2 = {"mu": 0.33, "gamma": 0.7}, {"mu": 0.0, "gamma": 1.4}
    assert run["conditions"] == {"L1": paper, "L2": l2, "L3": paper, "L4": l2}
    profile_bytes = asset_path("devices", "palm-5x6.json").read_bytes()
    assert run["device_profile"]["name"] == "palm-5x6"
    assert run["device_profile"]["sha256"] == hashlib.sha256(profile_bytes).hexdigest()
    assert run["device_profile"]["calibration"] is None
    assert run["software_version"] == tc.__version__


def test_resuming_under_another_profile_or_pipeline_is_refused(tmp_path):
    from tactile_core.device.profile import default_profile
    from tactile_core.experiments.results import SessionError
    from tactile_core.rendering.scene import Pipeline

    session = open_session(tmp_path, "pp03", seed=3)
    runner = Experiment3(session)
    runner.answer("continue")
    runner.close()
    calibrated = default_profile().with_calibration([0.1] * 30, [0.9] * 30)
    with pytest.raises(SessionError, match="device_profile"):
        Experiment3(open_session(tmp_path, "pp03"), profile=calibrated)
    with pytest.raises(SessionError, match="pipeline"):
        open_session(tmp_path, "pp03", pipeline=Pipeline(300.0, "box", 4, True))
    Experiment3(open_session(tmp_path, "pp03")).close()  # the same settings resume


def test_filter_and_dithering_are_explicit_recorded_choices(tmp_path):
    import json

    from tactile_core.rendering.scene import Pipeline

    session = open_session(tmp_path, "pp04", pipeline=Pipeline(200.0, "box", 4, True))
    runner = Experiment1(session)
    assert (runner.current.scene.filter, runner.current.scene.subsamples) == ("box", 4)
    assert runner.current.scene.dither and runner.current.scene.rate_hz == 200.0
    runner.close()
    data = json.loads((tmp_path / "participant-pp04" / "session.json").read_text())
    assert data["runs"]["exp1"]["pipeline"] == {"rate_hz": 200.0, "filter": "box",
                                                "subsamples": 4, "dither": True,
                                                "compensate_motors": False}  # fmt: skip


def test_each_trial_row_notes_the_stream_health(tmp_path):
    session = open_session(tmp_path, "pp05")
    runner = Experiment3(session)
    runner.answer("continue", health={"late_frames": 0, "skipped_frames": 0, "link_errors": 0})
    runner.answer("circle", rt_s=1.0, health={"late_frames": 3, "skipped_frames": 1,
                                              "link_errors": 2})  # fmt: skip
    runner.close()
    with open(tmp_path / "participant-pp05" / "exp3.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert (rows[1]["late_frames"], rows[1]["skipped_frames"], rows[1]["link_errors"]) == (
        "3",
        "1",
        "2",
    )
