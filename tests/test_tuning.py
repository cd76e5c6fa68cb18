"""Tuning the correction by feel (contract: "Tuning the correction by feel").

Expected values come from the model's algebra: a participant who feels ``((d - TH) / (1 - TH))^K``
above ``TH`` and adds tactors by energy needs ``mu = TH`` and ``gamma = 1 / (2K)``.
"""

import json
import math
import random
import subprocess
import sys
import time

import numpy as np
import pytest
from scipy.special import ndtr

import tactile_core as tc
from tactile_core.cli import main
from tactile_core.device.profile import default_profile
from tactile_core.experiments import open_session
from tactile_core.experiments.results import Session, read_rows
from tactile_core.experiments.runners import Experiment1, calibration_from_thresholds
from tactile_core.experiments.tuning import (
    CorrectionTuning,
    SimulatedObserver,
    TuningPlan,
    felt_total,
    fit_cumulative,
    fit_gamma,
    interval_drive,
    load_correction,
    save_correction,
    simulate_tuning,
)
from tactile_core.files.presets import load_preset
from tactile_core.rendering.geometry import Grid
from tactile_core.rendering.percept import felt_magnitude
from tactile_core.rendering.scene import Scene

EXP1_LINE = tc.Line((0.5, 1.84), (4.5, 4.16))
EXP1_CIRCLE = tc.Circle((2.5, 3.0), 2.0)
OBSERVERS = [(0.15, 0.5), (0.3, 1.0), (0.45, 2.0)]


# --- the model ---------------------------------------------------------------------------------


def test_felt_magnitude_is_the_contracts_power_law_worked_by_hand():
    # TH 0.2, K 2: d = 0.6 -> (0.4 / 0.8)^2 = 0.25; at or below TH nothing; full drive 1.
    m = felt_magnitude([0.6, 0.2, 0.1, 1.0, 0.0], 0.2, 2.0)
    assert m == pytest.approx([0.25, 0.0, 0.0, 1.0, 0.0])
    # Two tactors at 0.6 add by energy: sqrt(2 x 0.25^2) = 0.35355.
    assert felt_total(np.array([[0.6, 0.6]]), 0.2, 2.0) == pytest.approx(math.sqrt(2) * 0.25)


@pytest.mark.parametrize("shape", [EXP1_LINE, EXP1_CIRCLE], ids=["line", "circle"])
@pytest.mark.parametrize("method", ["AS", "IM"])
@pytest.mark.parametrize(("threshold", "exponent"), OBSERVERS)
def test_mu_TH_gamma_1_over_2K_makes_the_felt_magnitude_constant(shape, method, threshold,
                                                                   exponent):  # fmt: skip
    # m_i = I_i^(1/2) under this correction, so M = sqrt(sum I_i) = 1 along the whole trace.
    t = np.linspace(0.0, 1.0, 4001)
    drive = tc.correct(tc.render(shape, method, t), threshold, 1.0 / (2.0 * exponent))
    felt = np.sqrt((felt_magnitude(drive, threshold, exponent) ** 2).sum(axis=(1, 2)))
    assert np.abs(felt - 1.0).max() < 0.01


def test_the_papers_gamma_does_not_make_it_constant_for_such_a_participant():
    # The control: the same check fails for gamma 0.7 with K = 1 (the right gamma is 0.5).
    t = np.linspace(0.0, 1.0, 4001)
    drive = tc.correct(tc.render(EXP1_LINE, "AS", t), 0.33, 0.7)
    felt = np.sqrt((felt_magnitude(drive, 0.33, 1.0) ** 2).sum(axis=(1, 2)))
    assert np.abs(felt - 1.0).max() > 0.05


def test_interval_drive_is_what_the_array_gets():
    profile = default_profile()
    # One tactor at level 7 of 22: the CT point at its centre with gain 7/22.
    scene = Scene(tc.Line((1.5, 2.5), (1.5, 2.5)), "CT", 0.0, 1.0, duration_s=0.5, pause_s=0.0,
                     repeat=False, gain=7 / 22)  # fmt: skip
    d = interval_drive(scene, profile)
    assert d[2, 1] == pytest.approx(7 / 22)
    assert d.sum() == pytest.approx(7 / 22)
    # A point midway between two tactors, corrected (mu 0.25, gamma 0.5) and dithered: the mean
    # drive is 0.25 + 0.75 x 0.5^0.5 = 0.78033 to within one level over the 150 frames.
    mid = Scene(tc.Line((2.0, 2.5), (2.0, 2.5)), "AS", 0.25, 0.5, duration_s=0.5, pause_s=0.0,
                   repeat=False, dither=True)  # fmt: skip
    d = interval_drive(mid, profile)
    expected = 0.25 + 0.75 * math.sqrt(0.5)
    assert d[2, 1] == pytest.approx(expected, abs=1 / 22 / 150 + 1e-9)
    assert d[2, 2] == pytest.approx(expected, abs=1 / 22 / 150 + 1e-9)
    assert interval_drive(None, profile).sum() == 0.0


# --- fitting -----------------------------------------------------------------------------------


def test_fit_cumulative_recovers_a_known_threshold():
    rng = np.random.default_rng(1)
    x = rng.uniform(0.0, 0.6, 3000)
    p = 0.5 + 0.5 * ndtr((x - 0.3) / 0.05)
    y = rng.random(3000) < p
    fit = fit_cumulative(x, y, guess=0.5, locations=np.linspace(0, 1, 401),
                         scales=np.geomspace(0.004, 0.4, 24))  # fmt: skip
    assert fit.location == pytest.approx(0.3, abs=0.01)
    assert fit.ci[0] <= 0.3 <= fit.ci[1]
    assert fit.p_flat < 1e-6


def test_fit_gamma_recovers_a_known_point_of_equality_and_its_interval_covers_it():
    rng = np.random.default_rng(2)
    g = rng.uniform(0.3, 1.2, 1000)  # 1,000 answers: the location's SE is about 1%
    y = rng.random(1000) < ndtr(-(g - 0.6) / (0.3 * 0.6))
    assert fit_gamma(g, y).location == pytest.approx(0.6, rel=0.03)
    # A 95% interval covers the truth in about 95% of data sets (binomial: 40 sets, >= 34).
    covered = 0
    for _ in range(40):
        g = rng.uniform(0.3, 1.2, 150)
        fit = fit_gamma(g, rng.random(150) < ndtr(-(g - 0.6) / (0.3 * 0.6)))
        covered += fit.ci[0] <= 0.6 <= fit.ci[1]
    assert covered >= 34


def test_answers_that_do_not_depend_on_the_stimulus_are_flat():
    rng = np.random.default_rng(3)
    x = rng.uniform(0, 1, 200)
    fit = fit_cumulative(x, rng.random(200) < 0.5, guess=0.0, locations=np.linspace(0, 1, 101),
                         scales=np.geomspace(0.01, 1, 12))  # fmt: skip
    assert fit.p_flat > 0.01


def test_calibration_from_thresholds_worked_by_hand():
    grid = Grid(cols=4, rows=1)
    offset, gain, threshold = calibration_from_thresholds({(0, 0): 0.2, (1, 0): 0.3,
                                                           (2, 0): 0.4}, grid)  # fmt: skip
    # t_ref = 0.3 (the median). Tactor 0: gain 0.8 / 0.7, offset 0.2 - 0.3 x 0.8 / 0.7.
    assert gain[0] == pytest.approx(0.8 / 0.7)
    assert offset[0] == pytest.approx(0.2 - 0.3 * 0.8 / 0.7)
    assert (offset[1], gain[1]) == pytest.approx((0.0, 1.0))
    # Tactor 3 was not measured: left as it is.
    assert (offset[3], gain[3], threshold[3]) == pytest.approx((0.0, 1.0, 0.3))


# --- the procedure -------------------------------------------------------------------------------


@pytest.mark.parametrize(("threshold", "exponent"), OBSERVERS)
def test_recovers_mu_and_gamma_over_many_seeds(threshold, exponent):
    plan = TuningPlan(20, 60, 12)
    results = [simulate_tuning(threshold, exponent, seed=s, plan=plan) for s in range(12)]
    assert all(r.ok for r in results), [r.message for r in results if not r.ok]
    mu_err = np.array([r.mu - threshold for r in results])
    gamma_err = np.array([r.gamma * 2 * exponent - 1 for r in results])
    assert np.mean(np.abs(mu_err) <= 0.03) >= 0.9, mu_err
    assert np.median(np.abs(gamma_err)) <= 0.12, gamma_err
    assert np.mean(np.abs(gamma_err) <= 0.25) >= 0.8, gamma_err
    assert all(0.0 <= r.mu <= 0.95 and 0.1 <= r.gamma <= 10 for r in results)
    assert all(r.trials == 5 * 20 + 2 * 60 + 12 for r in results)


class _Participant:
    """Answers like ``inner`` except in the phases given, where it tosses a coin."""

    def __init__(self, inner, random_in=("threshold", "constancy"), seed=0):
        self.inner, self.random_in, self.rng = inner, random_in, random.Random(seed)

    def run(self, runner):
        while not runner.finished:
            trial = runner.current
            if trial.kind == "interval" and trial.info["phase"] in self.random_in:
                answer = self.rng.choice(("1", "2"))
            else:
                answer = self.inner.respond(trial)
            runner.answer(answer)


def _run(participant, plan=None, seed=0):
    runner = CorrectionTuning(Session(participant="p", seed=seed), plan, write=False)
    participant.run(runner)
    return runner


@pytest.mark.parametrize("seed", range(4))
def test_random_answers_end_with_a_message_and_no_correction(seed):
    runner = _run(_Participant(SimulatedObserver(seed=seed), seed=seed), seed=seed)
    result = runner.result()
    assert not result.ok and result.mu is None and result.gamma is None
    assert "not felt reliably" in result.message
    assert runner.done < runner.total  # ended after the threshold part
    with pytest.raises(ValueError, match="nothing to save"):
        save_correction(runner, result)


def test_a_participant_who_never_feels_anything_gets_no_correction():
    class Numb:
        def respond(self, trial):
            return "continue" if trial.kind == "continue" else "1"

        def run(self, runner):
            while not runner.finished:
                runner.answer(self.respond(runner.current))

    result = _run(Numb()).result()
    assert not result.ok and "no threshold" in result.message


@pytest.mark.parametrize("seed", range(3))
def test_random_answers_to_strength_end_with_no_point_of_equality(seed):
    inner = SimulatedObserver(0.25, 1.0, seed=seed)
    result = _run(_Participant(inner, random_in=("constancy",), seed=seed), seed=seed).result()
    if result.ok:  # a coin can settle by chance; then gamma must still be in range
        assert 0.1 <= result.gamma <= 10
    else:
        assert "no point of equality" in result.message and result.gamma is None


def test_trials_play_what_the_procedure_says():
    runner = CorrectionTuning(Session(participant="p", seed=5), write=False)
    runner.answer("continue")
    trial = runner.current
    assert trial.kind == "interval" and trial.options == ("1", "2")
    assert len(trial.intervals) == 2 and trial.intervals.count(None) == 1
    stim = next(s for s in trial.intervals if s is not None)
    assert trial.info["stimulus"] == str(trial.intervals.index(stim) + 1)
    # Starts clearly felt: level 11 of 22, one tactor, the session's (paper's) pipeline.
    assert trial.info["level"] == 11 and stim.gain == pytest.approx(0.5)
    assert not stim.dither and stim.rate_hz == 300.0
    with pytest.raises(ValueError, match="answer must be one of 1, 2"):
        runner.answer("3")


def test_a_run_is_resumed_where_it_stopped_and_ends_as_an_unbroken_one(tmp_path):
    sim = SimulatedObserver(0.3, 1.0, seed=9)
    plan = TuningPlan(10, 16, 4)
    session = open_session(tmp_path, "p1", seed=9)
    runner = CorrectionTuning(session, plan)
    for _ in range(40):
        runner.answer(sim.respond(runner.current))
    runner.close()
    rows = read_rows(tmp_path / "participant-p1" / "correction.csv")
    assert len(rows) == 40
    runner = CorrectionTuning(open_session(tmp_path, "p1", seed=9), plan)
    assert runner.done == 40
    sim.run(runner)
    resumed = runner.result()
    runner.close()
    # The same answers in one go, in memory.
    again = SimulatedObserver(0.3, 1.0, seed=9)
    whole = CorrectionTuning(Session(participant="p1", seed=9), plan, write=False)
    again.run(whole)
    assert resumed.to_dict() == whole.result().to_dict()


def test_the_correction_is_saved_recorded_and_loadable(tmp_path):
    sim = SimulatedObserver(0.3, 1.0, seed=1)
    session = open_session(tmp_path, "p2", seed=1)
    runner = CorrectionTuning(session, TuningPlan(16, 30, 8))
    sim.run(runner)
    result = runner.result()
    assert result.ok
    record_path, preset_path = save_correction(runner, result)
    runner.close()
    record = load_correction(record_path.parent)
    assert (record["mu"], record["gamma"], record["trials"]) == (result.mu, result.gamma,
                                                                 result.trials)  # fmt: skip
    assert record["participant"] == "p2" and record["device_profile"]["name"] == "palm-5x6"
    preset = load_preset(preset_path)
    assert (preset.scene.mu, preset.scene.gamma) == (result.mu, result.gamma)
    # A later experiment session records the participant's correction (not applied).
    exp1 = Experiment1(open_session(tmp_path, "p2", seed=1))
    exp1.close()
    data = json.loads((tmp_path / "participant-p2" / "session.json").read_text())
    assert data["runs"]["exp1"]["participant_correction"]["gamma"] == result.gamma
    assert data["runs"]["exp1"]["conditions"]["AS"] == {"mu": 0.33, "gamma": 0.7}


def test_a_malformed_correction_record_is_refused_by_name(tmp_path):
    (tmp_path / "correction.json").write_text('{"format": "tactile-correction", "mu": 3}')
    with pytest.raises(ValueError, match=r"correction\.json: mu must be within"):
        load_correction(tmp_path)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"threshold_trials": 1}, "threshold_trials"), ({"gamma_trials": 1.5}, "gamma_trials"),
     ({"corner_trials": -1}, "corner_trials")],
)  # fmt: skip
def test_a_bad_plan_is_refused_by_name(kwargs, message):
    with pytest.raises(ValueError, match=message):
        TuningPlan(**kwargs)


# --- command line --------------------------------------------------------------------------------


def test_cli_simulate_prints_mu_gamma_and_trials_as_json(capsys):
    code = main(["tune-correction", "--simulate", "--threshold", "0.3", "--exponent", "1.25",
                 "--seed", "2", "--json"])  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    assert abs(out["mu"] - 0.3) <= 0.03
    assert abs(out["gamma"] / 0.4 - 1) <= 0.3
    assert out["trials"] == 5 * 20 + 2 * 40 + 12
    assert out["expected"] == {"mu": 0.3, "gamma": 0.4}


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--simulate", "--threshold", "0.3"], "needs --threshold TH and --exponent K"),
        (["--simulate", "--threshold", "1.2", "--exponent", "1"], "threshold must be within"),
        (["--simulate", "--threshold", "0.3", "--exponent", "inf"], "exponent must be a finite"),
        (["--simulate", "--threshold", "0.3", "--exponent", "1", "--device", "sim"],
         "exclude each other"),
        (["--device", "sim"], "--participant ID --results DIR"),
        (["--simulate", "--threshold", "0.3", "--exponent", "1", "--trials-per-tactor", "0"],
         "threshold_trials"),
    ],
)  # fmt: skip
def test_cli_refuses_bad_arguments_by_name(args, message, capsys):
    assert main(["tune-correction", *args]) == 2
    assert message in capsys.readouterr().err


def test_cli_session_at_the_simulated_array_stops_on_q_and_resumes(tmp_path):
    # A person at the array types answers; q stops with everything answered on disk.
    cmd = [sys.executable, "-m", "tactile_core.cli", "tune-correction", "--device", "sim",
           "--participant", "p3", "--results", str(tmp_path), "--trials-per-tactor", "2",
           "--trials-per-place", "2", "--corner-trials", "0", "--interval-ms", "20"]  # fmt: skip
    done = subprocess.run(cmd, input="\n1\nr\n2\nq\n", capture_output=True, text=True,
                          timeout=60)  # fmt: skip
    assert done.returncode == 1, done.stderr
    assert "stopped at 3 of" in done.stderr
    rows = read_rows(tmp_path / "participant-p3" / "correction.csv")
    assert [r["answer"] for r in rows] == ["", "1", "2"]
    again = subprocess.run(cmd, input="q\n", capture_output=True, text=True, timeout=60)
    assert "3 of 16 answered so far" in again.stderr


def test_at_a_terminal_single_keys_answer_without_enter(tmp_path):
    import os
    import pty
    import select

    cmd = [sys.executable, "-m", "tactile_core.cli", "tune-correction", "--device", "sim",
           "--participant", "k1", "--results", str(tmp_path), "--trials-per-tactor", "2",
           "--trials-per-place", "2", "--corner-trials", "0", "--interval-ms", "20"]  # fmt: skip
    master, slave = pty.openpty()
    proc = subprocess.Popen(cmd, stdin=slave, stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    seen = b""

    def wait_for(text, timeout=15.0):
        nonlocal seen
        deadline = time.monotonic() + timeout
        while text not in seen:
            assert time.monotonic() < deadline, repr(seen.decode(errors="replace"))
            if select.select([master], [], [], 0.1)[0]:
                try:
                    seen += os.read(master, 4096)
                except OSError:
                    break

    try:
        wait_for(b"(Enter or Space)")
        os.write(master, b" ")  # the introduction: one key, no Enter
        wait_for(b"[2/")
        os.write(master, b"1")  # an answer: the key alone
        wait_for(b"[3/")
        os.write(master, b"q")
        assert proc.wait(60) == 1
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)
    rows = read_rows(tmp_path / "participant-k1" / "correction.csv")
    assert [r["answer"] for r in rows] == ["", "1"]


def test_simulate_runs_the_correction_tuning(tmp_path, capsys):
    # tactile simulate --experiments correction failed: "trial kind 'interval' is not known"
    code = main(["simulate", str(tmp_path), "--participants", "1", "--experiments", "correction"])
    assert code == 0, capsys.readouterr().err
    folder = tmp_path / "participant-sim01"
    rows = (folder / "correction.csv").read_text().splitlines()
    # The default plan: 2 instruction screens, 20 trials at each of 5 tactors, 40 at each of 2
    # places, 12 at the cell corner; and the header.
    assert len(rows) == 1 + 2 + 5 * 20 + 2 * 40 + 12
    record = json.loads((folder / "correction.json").read_text())
    # The simulated participant of the contract, TH 0.25 and K 1: mu = TH, gamma = 1 / (2K).
    assert abs(record["mu"] - 0.25) < 0.05 and abs(record["gamma"] - 0.5) < 0.1
