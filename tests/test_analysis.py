"""``tactile analyze``: the paper's tables and figures from a results folder of simulated
participants, incomplete participants left out, bad rows reported."""

import math
import subprocess
import sys

import numpy as np
import pytest
from scipy import stats

from tactile_core.experiments import RUNNERS, Experiment3, SimulatedParticipant, open_session


def run_cli(capsys, *argv) -> str:
    """``tactile ARGV`` in this process (the command line's own code): its standard output."""
    from tactile_core.cli import main

    capsys.readouterr()
    assert main(list(argv)) == 0
    return capsys.readouterr().out


def test_analyze_paper_rounding_prints_the_papers_value(tmp_path, capsys):
    run_cli(capsys, "simulate", str(tmp_path), "--participants", "12", "--experiments", "exp3",
            "--seed", "4")  # fmt: skip
    plain = run_cli(capsys, "analyze", str(tmp_path))
    paper = run_cli(capsys, "analyze", str(tmp_path), "--paper-rounding")
    assert "rounded to three decimals" in paper and "rounded to three decimals" not in plain
    row = paper.split("Table 2")[1].splitlines()[2].split("\t")
    assert all(round(float(v) / 0.006, 6).is_integer() or float(v) == 1.0 for v in row), row


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


@pytest.fixture(scope="module")
def analysed(study):
    """One analysis of the study for the tests below: what it printed and what it returned."""
    from tactile_core.experiments.analysis import analyze

    lines = []
    result = analyze(study, out=lambda *args: lines.append(" ".join(map(str, args))))
    return "\n".join(lines), result


def test_analyze_prints_the_papers_tables_and_writes_figures(study, analysed):
    out, _ = analysed
    assert "Table 1" in out and "Table 2" in out
    assert "CT, MM\tCT, AS\tCT, IM\tMM, AS\tMM, IM\tAS, IM" in out
    assert "medians (quality/smoothness/thickness):\tCT " in out  # not "CT 72/59/138" unlabelled
    for name in ("fig6-exp1-scores", "fig7-exp2-lengths", "fig8-exp3-scores", "exp2-staircases"):
        assert (study / f"{name}.png").stat().st_size > 10_000


def test_analysis_recovers_the_simulated_effects(analysed):
    _, result = analysed
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


# --- Experiment 2 across conditions: rows pair by participant ------------------------------------


def _exp2_participant(root, pid, seed, wrong=()):
    """An Experiment 2 session of a simulated participant (seeded), never right in the stages
    ``wrong`` (those tracks climb to the 4-unit cap: no reversal estimate); its CSV."""
    from tactile_core.experiments import Experiment2

    runner = Experiment2(open_session(root, pid, index=seed, seed=seed))
    sim = SimulatedParticipant(seed=seed)
    while not runner.finished:
        trial = runner.current
        if trial.kind == "direction" and trial.stage in wrong:
            runner.answer(next(d for d in trial.options if d != trial.info["direction"]))
        else:
            runner.answer(sim.respond(trial))
    runner.close()
    return root / f"participant-{pid}" / "exp2.csv"


def _reversal_estimate(path, stage):
    """The paper's estimate of one track, replayed by hand from the CSV (NaN under 4
    reversals): the mean of the last two peaks and two valleys."""
    import csv

    from tactile_core.experiments import Staircase

    with open(path, newline="") as f:
        answers = [r["answer"] == r["direction"] for r in csv.DictReader(f) if r["stage"] == stage]
    sc = Staircase(2.0, 0.685, 1.46, 2, 1, min_level=0.01, max_level=4.0)
    for answer in answers:
        sc.update(answer)
    levels = sc.reversal_levels
    return float(np.mean(levels[-4:])) if len(levels) >= 4 else math.nan


def test_exp2_across_conditions_leaves_out_a_participant_missing_any_condition(tmp_path):
    """p00 has no L1 and L3 estimate, p01 no L2 and L4 estimate: every column then holds 5
    values, but not from the same people. Friedman and the pairwise tests must take the 4
    participants with every condition (complete cases), not the leftover columns side by side
    (before: they did, pairing p01's L1 with p00's L2: chi2 and p of other rows)."""
    from tactile_core.experiments.analysis import analyze

    paths = {"p00": _exp2_participant(tmp_path, "p00", 0, wrong=("L1", "L3")),
             "p01": _exp2_participant(tmp_path, "p01", 1, wrong=("L2", "L4"))}  # fmt: skip
    for seed in range(2, 6):
        paths[f"p{seed:02d}"] = _exp2_participant(tmp_path, f"p{seed:02d}", seed)
    conditions = ("L1", "L2", "L3", "L4")
    table = {pid: [_reversal_estimate(path, c) for c in conditions] for pid, path in paths.items()}
    assert np.isnan(table["p00"]).tolist() == [True, False, True, False]
    assert np.isnan(table["p01"]).tolist() == [False, True, False, True]
    complete = np.array([row for row in table.values() if np.isfinite(row).all()])
    assert complete.shape == (4, 4)  # p02..p05
    out = []
    with pytest.MonkeyPatch.context() as mp:  # neither the fitter nor the figures is tested here
        mp.setattr("tactile_core.experiments.analysis._scores.fit_psychometric",
                   lambda lengths, correct: {"threshold": 1.0, "ci": (0.5, 2.0)})  # fmt: skip
        mp.setattr("tactile_core.experiments.analysis._report._exp2_figure", lambda *a: None)
        mp.setattr("tactile_core.experiments.analysis._report._staircase_figure", lambda *a: None)
        result = analyze(tmp_path, out=out.append)
    across = result["exp2"]["journal"]["across"]
    chi2, p = stats.friedmanchisquare(*complete.T)
    assert across["friedman"] == pytest.approx((chi2, p), rel=1e-12)
    exact = stats.PermutationMethod(n_resamples=np.inf)
    for i, j in ((0, 1), (0, 3), (1, 2)):
        d = complete[:, i] - complete[:, j]
        expected = stats.wilcoxon(d[d != 0], method=exact).pvalue if d.any() else 1.0
        assert across["exact"][(conditions[i], conditions[j])]["p"] == pytest.approx(expected)
    assert across["participants"] == ["p02", "p03", "p04", "p05"]
    assert "4 of 6 participants (p00, p01 lack a condition)" in "\n".join(out)
