"""``tactile analyze``: the paper's tables and figures from a results folder of simulated
participants, incomplete participants left out, bad rows reported."""

import subprocess
import sys

import pytest

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
