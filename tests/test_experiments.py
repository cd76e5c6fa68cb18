"""Experiments: staircase, statistics, orders, runners with simulated participants, results on
disk, resuming, calibration, analysis."""

import csv
import math
import subprocess
import sys

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.experiments import (
    RUNNERS,
    Calibration,
    Experiment1,
    Experiment2,
    Experiment3,
    Psychometric,
    SimulatedParticipant,
    open_session,
)
from tactile_core.experiments.runners import CONDITIONS_EXP2
from tactile_core.experiments.stats import apply_order, assign_orders

# --- staircase ---------------------------------------------------------------------------


def test_staircase_two_down_one_up_worked_by_hand():
    sc = tc.Staircase(start=2.0, down=0.685, up=1.46, n_down=2, n_up=1)
    assert sc.level == 2.0
    assert sc.update(True) == 2.0  # one correct: stay
    assert sc.update(True) == pytest.approx(1.37)  # two correct: x 0.685
    assert sc.update(False) == pytest.approx(1.37 * 1.46)  # wrong: x 1.46; a valley at 1.37
    assert sc.reversal_levels == [pytest.approx(1.37)]
    assert sc.update(True) == pytest.approx(2.0002)
    assert sc.update(False) == pytest.approx(2.0002 * 1.46)  # the correct run is broken
    # going up twice in a row is no reversal
    assert sc.reversal_levels == [pytest.approx(1.37)]
    sc.update(True)
    sc.update(True)  # down: a peak at 2.0002 * 1.46
    assert sc.reversal_levels[-1] == pytest.approx(2.0002 * 1.46)
    sc.update(False)  # up: a valley
    sc.update(True)
    sc.update(True)  # down: a peak
    levels = sc.reversal_levels
    assert len(levels) == 4
    assert sc.estimate(4) == pytest.approx(sum(levels) / 4)
    assert sc.estimate(2) == pytest.approx(sum(levels[-2:]) / 2)


def test_staircase_estimate_needs_enough_reversals_and_checks_arguments():
    sc = tc.Staircase()
    with pytest.raises(ValueError, match="reversals"):
        sc.estimate(4)
    for kwargs, word in [({"start": 0}, "start"), ({"down": 1.2}, "down"), ({"up": 0.9}, "up"),
                         ({"n_down": 0}, "n_down")]:  # fmt: skip
        with pytest.raises(ValueError, match=word):
            tc.Staircase(**kwargs)
    with pytest.raises(ValueError, match="correct"):
        sc.update("yes")


def test_staircase_is_clipped_to_its_bounds():
    sc = tc.Staircase(start=2.0, max_level=4.0)
    for _ in range(5):
        sc.update(False)
    assert sc.level == 4.0


def test_psychometric_function():
    f = Psychometric(midpoint=0.8, slope=4.0)
    assert f.p_correct(1e-9) == pytest.approx(0.25, abs=1e-6)  # guessing
    assert f.p_correct(1e9) == pytest.approx(0.98, abs=1e-6)  # 1 - lapse
    assert f.p_correct(0.8) == pytest.approx(0.25 + 0.73 / 2)
    length = f.length_at(0.707)
    assert f.p_correct(length) == pytest.approx(0.707)


def test_staircase_converges_near_the_70_7_percent_point():
    rng = np.random.default_rng(5)
    f = Psychometric(midpoint=0.6, slope=4.0)
    target = f.length_at(0.707)
    estimates = []
    for _ in range(300):
        sc = tc.Staircase(2.0, 0.685, 1.46, 2, 1)
        for _ in range(80):
            sc.update(rng.random() < f.p_correct(sc.level))
        estimates.append(sc.estimate(4))
    median = float(np.median(estimates))
    assert median == pytest.approx(target, rel=0.10), (median, target)
    # the track really depends on the participant: a far easier observer converges lower
    easy = Psychometric(midpoint=0.2, slope=4.0)
    sc = tc.Staircase(2.0, 0.685, 1.46, 2, 1)
    for _ in range(80):
        sc.update(rng.random() < easy.p_correct(sc.level))
    assert sc.estimate(4) < 0.5 * target


# --- statistics --------------------------------------------------------------------------


def normal_p(z):
    return math.erfc(abs(z) / math.sqrt(2))


def test_wilcoxon_without_ties_by_hand():
    # 12 participants all better under X, no tied differences: W+ = 78, mean 39,
    # variance n(n+1)(2n+1)/24 = 162.5.
    x = np.arange(1, 13) + 10.0
    y = np.zeros(12)
    p = tc.pairwise_wilcoxon({"X": x, "Y": y})[("X", "Y")]
    assert p == pytest.approx(normal_p((78 - 39) / math.sqrt(162.5)), rel=1e-9)


def test_paper_rounding_reproduces_the_papers_0012():
    # 12 of 12 with one sign (no ties): p = erfc(39 / sqrt(162.5) / sqrt 2) = 0.002222;
    # x 6 = 0.01333 prints as 0.013. The paper rounded p to 0.002 first: x 6 = 0.012, the value
    # its Tables 1 and 2 show for every such pair.
    x, y = np.arange(1, 13) + 10.0, np.zeros(12)
    raw = normal_p(39 / math.sqrt(162.5))
    assert round(raw, 4) == 0.0022
    scores = {"CT": x, "MM": y, "AS": y, "IM": y}  # six pairs: x 6
    assert f"{tc.pairwise_wilcoxon(scores)[('CT', 'MM')]:.3f}" == "0.013"
    p = tc.pairwise_wilcoxon(scores, paper_rounding=True)[("CT", "MM")]
    assert p == pytest.approx(0.012, abs=1e-15)


def test_analyze_paper_rounding_prints_the_papers_value(tmp_path):
    sim = [sys.executable, "-m", "tactile_core.cli", "simulate", str(tmp_path), "--participants",
           "12", "--experiments", "exp3", "--seed", "4"]  # fmt: skip
    subprocess.run(sim, check=True, capture_output=True, timeout=120)
    cmd = [sys.executable, "-m", "tactile_core.cli", "analyze", str(tmp_path)]
    plain = subprocess.run(cmd, check=True, capture_output=True, text=True, timeout=120).stdout
    paper = subprocess.run([*cmd, "--paper-rounding"], check=True, capture_output=True,
                           text=True, timeout=120).stdout  # fmt: skip
    assert "rounded to three decimals" in paper and "rounded to three decimals" not in plain
    row = paper.split("Table 2")[1].splitlines()[2].split("\t")
    assert all(round(float(v) / 0.006, 6).is_integer() or float(v) == 1.0 for v in row), row


def test_wilcoxon_with_ties_and_a_zero_by_hand():
    # differences 1,1,2,2,3,...,10 and one zero (dropped): n = 12, average ranks for the
    # ties, variance 162.5 - sum(t^3 - t)/48 = 162.5 - 12/48.
    d = np.array([1, 1, 2, 2, 3, 4, 5, 6, 7, 8, 9, 10, 0], dtype=float)
    p = tc.pairwise_wilcoxon({"X": d, "Y": np.zeros(13)}, correction="none")[("X", "Y")]
    assert p == pytest.approx(normal_p((78 - 39) / math.sqrt(162.5 - 12 / 48)), rel=1e-9)


def test_wilcoxon_mixed_signs_by_hand():
    # differences +5, -1, +3, +2, -4, +6: ranks 5, 1, 3, 2, 4, 6; W+ = 5+3+2+6 = 16; n = 6,
    # mean 10.5, variance 6*7*13/24 = 22.75.
    x = np.array([5, 0, 3, 2, 0, 6], dtype=float)
    y = np.array([0, 1, 0, 0, 4, 0], dtype=float)
    p = tc.pairwise_wilcoxon({"A": x, "B": y}, correction="none")[("A", "B")]
    assert p == pytest.approx(normal_p((16 - 10.5) / math.sqrt(22.75)), rel=1e-9)


def test_pairwise_wilcoxon_layout_and_bonferroni():
    rng = np.random.default_rng(0)
    scores = {m: rng.normal(50, 10, 12) for m in ("CT", "MM", "AS", "IM")}
    scores["AS"] += 40
    adjusted = tc.pairwise_wilcoxon(scores)
    raw = tc.pairwise_wilcoxon(scores, correction="none")
    assert list(adjusted) == [
        ("CT", "MM"),
        ("CT", "AS"),
        ("CT", "IM"),
        ("MM", "AS"),
        ("MM", "IM"),
        ("AS", "IM"),
    ]
    for pair in adjusted:
        assert adjusted[pair] == pytest.approx(min(1.0, 6 * raw[pair]))
    assert tc.pairwise_wilcoxon({"A": [1, 2, 3], "B": [1, 2, 3]})[("A", "B")] == 1.0
    with pytest.raises(ValueError, match="same number"):
        tc.pairwise_wilcoxon({"A": [1, 2], "B": [1, 2, 3]})


def test_orders_are_the_papers():
    assert tc.ORDERS == ("ABCD", "DCBA", "ACBD", "DBCA", "BADC", "CDAB",
                         "BDAC", "CADB", "ADBC", "CBDA", "BCAD", "DACB")  # fmt: skip
    assert len(set(tc.ORDERS)) == 12 and all(sorted(o) == list("ABCD") for o in tc.ORDERS)
    # each condition appears in each position three times (counterbalanced)
    for position in range(4):
        assert sorted(o[position] for o in tc.ORDERS) == sorted("ABCD" * 3)
    given = assign_orders([f"p{i}" for i in range(12)], seed=3)
    assert sorted(given.values()) == sorted(tc.ORDERS)  # no two share an order
    assert apply_order("CADB", ["CT", "MM", "AS", "IM"]) == ["AS", "CT", "IM", "MM"]


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


def make_lock_stale(path):
    """Rewrite a participant's lock as a process that has ended would have left it."""
    import json
    import socket

    pid = subprocess.Popen(["true"])
    pid.wait()
    path.write_text(json.dumps({"host": socket.gethostname(), "pid": pid.pid, "since": "then"}))


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
    make_lock_stale(runner._lock.path)
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


# --- analysis ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    root = tmp_path_factory.mktemp("study")
    proc = subprocess.run(
        [sys.executable, "-m", "tactile_core.cli", "simulate", str(root),
         "--participants", "12", "--seed", "7"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    return root


def test_analyze_prints_the_papers_tables_and_writes_figures(study):
    proc = subprocess.run([sys.executable, "-m", "tactile_core.cli", "analyze", str(study)],
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    assert "Table 1" in out and "Table 2" in out
    assert "CT, MM\tCT, AS\tCT, IM\tMM, AS\tMM, IM\tAS, IM" in out
    for name in ("fig6-exp1-scores", "fig7-exp2-lengths", "fig8-exp3-scores", "exp2-staircases"):
        assert (study / f"{name}.png").stat().st_size > 10_000


def test_analysis_recovers_the_simulated_effects(study):
    from tactile_core.experiments.analysis import analyze

    result = analyze(study, out=lambda *_: None)
    quality = result["exp1"]["tables"]["quality"]
    # Anti-aliased rated far higher than bi-level for all 12: the smallest p for n = 12.
    assert quality[("CT", "AS")] < 0.05 and quality[("MM", "IM")] < 0.05
    assert quality[("CT", "MM")] > 0.05
    means = {c: m for c, (m, _) in result["exp2"]["summary"].items()}
    assert means["L2"] < means["L1"]  # the model's L2 is much shorter
    assert result["exp3"]["table"][("CT", "IM")] < 0.05
    assert len(result["exp1"]["participants"]) == 12


def test_analysis_skips_incomplete_participants(tmp_path):
    for i in range(3):
        session = open_session(tmp_path, f"p{i}", seed=1)
        runner = Experiment3(session)
        if i < 2:
            SimulatedParticipant(seed=i).run(runner)
        else:
            runner.answer("continue")  # stopped early
        runner.close()
    from tactile_core.experiments.analysis import exp3_scores

    scores, ids = exp3_scores(tmp_path)
    assert ids == ["p0", "p1"] and all(len(v) == 2 for v in scores.values())


def test_analyze_errors(tmp_path, capsys):
    from tactile_core.cli import main

    assert main(["analyze", str(tmp_path / "missing")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["analyze", str(tmp_path)]) == 2
    assert "no participant" in capsys.readouterr().err


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


def test_staircase_accepts_numpy_booleans_and_0_or_1():
    sc = tc.Staircase()
    sc.update(np.True_)
    sc.update(1)
    assert sc.level == pytest.approx(1.37)
    for bad in (2, 0.5, "yes", None):
        with pytest.raises(ValueError, match="correct"):
            sc.update(bad)


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
                                "dither": False}  # fmt: skip
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
                                                "subsamples": 4, "dither": True}  # fmt: skip


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


# --- analysis that reads what it can -----------------------------------------------------------


def test_analyze_reports_bad_rows_and_goes_on(tmp_path):
    from tactile_core.experiments.analysis import analyze

    for i in range(4):
        session = open_session(tmp_path, f"q{i}", index=i, seed=2)
        for name in ("exp1", "exp3"):
            runner = RUNNERS[name](session)
            SimulatedParticipant(seed=i).run(runner)
            runner.close()
    path = tmp_path / "participant-q1" / "exp3.csv"
    lines = path.read_text().splitlines(keepends=True)
    lines[4] = lines[4].replace(",circle,", ",cirlce,", 1).replace(",square,", ",sqaure,", 1)
    path.write_text("".join(lines))
    with (tmp_path / "participant-q2" / "exp1.csv").open("a") as f:
        f.write("p,line,1,quality,AS,,x,y")  # a torn last row
    out = []
    result = analyze(tmp_path, out=out.append)
    text = "\n".join(out)
    assert f"{path}:5: shape" in text
    assert "exp1.csv" in text and "torn last row" in text
    assert "Left out 2 row(s)" in text
    assert result["exp3"]["participants"] == ["q0", "q2", "q3"]  # q1's set is now incomplete
    assert len(result["exp1"]["participants"]) == 4  # q2's complete ratings still count


def test_psychometric_fit_recovers_a_known_threshold():
    import random

    from tactile_core.experiments.stats import fit_psychometric

    psy = Psychometric(0.5, 6.0)
    rng = random.Random(4)
    lengths = [math.exp(rng.uniform(-2.5, 1.0)) for _ in range(400)]
    correct = [rng.random() < psy.p_correct(length) for length in lengths]
    fit = fit_psychometric(lengths, correct)
    assert fit["threshold"] == pytest.approx(psy.length_at(0.707), rel=0.1)
    lo, hi = fit["ci"]
    assert lo < psy.length_at(0.707) < hi


def test_friedman_effect_sizes_and_d_prime_by_hand():
    from tactile_core.experiments.stats import d_prime, friedman, pairwise_effect_sizes

    # Three conditions, four participants, always ranked A < B < C: ranks 1, 2, 3 each time.
    # chi2 = 12 / (n k (k + 1)) * sum R^2 - 3 n (k + 1) = 12/48 * (16 + 64 + 144) - 48 = 8.
    chi2, p = friedman({"A": [1, 2, 3, 4], "B": [2, 3, 4, 5], "C": [3, 4, 5, 6]})
    assert chi2 == pytest.approx(8.0) and p == pytest.approx(math.exp(-4.0))  # chi2(2) tail
    # 12 of 12 with one sign: Z = 39 / sqrt(162.5) = 3.059, r = Z / sqrt(12) = 0.883.
    r = pairwise_effect_sizes({"X": np.arange(1, 13) + 10.0, "Y": np.zeros(12)})
    assert r[("X", "Y")] == pytest.approx(39 / math.sqrt(162.5) / math.sqrt(12))
    # 5 of 5 hits, 0 of 5 false alarms: H = 5.5/6, F = 0.5/6 -> d' = 2 * 1.3830 = 2.766.
    assert d_prime(5, 5, 0, 5) == pytest.approx(2 * 1.3830, abs=1e-3)
