"""The analysis of a pilot's results, which are rarely complete: a track without reversals at
the cap is left out with a note, a group mean leaves out the fits the track does not bound and
says per condition how many contributed, and a track whose rows do not replay, or a file that is
not a regular file, is named and left out while the rest is analysed."""

import csv
import math
import shutil
import statistics

import pytest

from tactile_core.experiments import Experiment2, SimulatedParticipant, Staircase, open_session
from tactile_core.experiments.analysis import analyze, exp2_tracks
from tactile_core.experiments.analysis._reading import Problems
from tactile_core.experiments.analysis._report import exp2_usable

from . import results_support as support
from .results_support import link_out, link_to_zero, make_fifo

exp2_run, run = support.exp2_run, support.run


def run_exp2(root, pid, wrong=(), stop_after=None):
    runner = Experiment2(open_session(root, pid, index=0, seed=3))
    sim = SimulatedParticipant(seed=1)
    while not runner.finished and (stop_after is None or runner.done < stop_after):
        trial = runner.current
        if trial.kind == "direction" and trial.stage in wrong:
            runner.answer(next(d for d in trial.options if d != trial.info["direction"]))
        else:
            runner.answer(sim.respond(trial))
    runner.close()
    return root / f"participant-{pid}" / "exp2.csv"


def track(path, stage):
    """(lengths, correct) of one stage, read from the CSV by hand."""
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["stage"] == stage]
    return [float(r["length"]) for r in rows], [r["answer"] == r["direction"] for r in rows]


def stub_fit(lengths, correct):
    """A stand-in for the maximum-likelihood fit (tested in test_statistics; seconds a track):
    the geometric mean of the lengths, or where nothing was right, the end of the real fitter's
    range above the longest line (x e^1.5), as it returns for such a track."""
    if not any(correct):
        return {"threshold": max(lengths) * math.exp(1.5), "ci": (math.nan, math.nan)}
    return {"threshold": math.exp(statistics.fmean(map(math.log, lengths))), "ci": (0.1, 9.0)}


@pytest.fixture(scope="module")
def pilot(tmp_path_factory):
    """One participant, never right in L1 and L4 (their tracks climb to the cap and stay)."""
    root = tmp_path_factory.mktemp("pilot")
    path = run_exp2(root, "p00", wrong=("L1", "L4"))
    out = []
    with pytest.MonkeyPatch.context() as mp:  # neither the fitter nor the figures is tested here
        mp.setattr("tactile_core.experiments.analysis._scores.fit_psychometric", stub_fit)
        mp.setattr("tactile_core.experiments.analysis._report._exp2_figure", lambda *a: None)
        mp.setattr("tactile_core.experiments.analysis._report._staircase_figure", lambda *a: None)
        result = analyze(root, out=out.append)  # (it failed: "zero-size array ... minimum", exit 2)
    return path, "\n".join(out), result


def test_a_condition_whose_tracks_give_no_estimate_is_left_out_with_a_note(pilot):
    _, text, result = pilot
    for c in ("L1", "L4"):
        assert f"{c}\t0\t-\t-\t0\t-\t-\t-\t-\t(no participant's track gives an estimate" in text
        assert result["exp2"]["n"][c] == (0, 0)
        assert all(math.isnan(v) for v in result["exp2"]["summary"][c])
    assert result["exp2"]["n"]["L2"] == (1, 1) and result["exp2"]["n"]["L3"] == (1, 1)


def test_each_exclusion_is_listed_with_its_reason(pilot):
    path, text, _ = pilot
    # Never right from 2.0: x 1.46 to 2.92, then the cap of 4 for the other 28 trials; never a
    # step down, so no reversal, and nothing bounds a fit from above.
    assert track(path, "L1")[0] == [2.0, 2.92] + [4.0] * 28
    assert "left out of the means (4):" in text
    for c in ("L1", "L4"):
        cap = "0 reversal(s), 4 needed (28 of 30 trials at the 4-unit cap)"
        assert f"  p00 {c} reversals: {cap}" in text
        assert f"  p00 {c} fit: " in text
    assert text.count("lies beyond the lengths presented (2.000-4.000)") == 2


def test_a_group_mean_is_the_mean_of_the_estimates_that_remain(pilot):
    path, _, result = pilot
    lengths, answers = track(path, "L2")
    sc = Staircase(2.0, 0.685, 1.46, 2, 1, min_level=0.01, max_level=4.0)
    for answer in answers:
        sc.update(answer)
    assert result["exp2"]["summary"]["L2"][0] == pytest.approx(sum(sc.reversal_levels[-4:]) / 4)
    fit = math.exp(sum(math.log(v) for v in lengths) / len(lengths))
    assert result["exp2"]["fit_summary"]["L2"][0] == pytest.approx(fit)


def test_the_rule_for_fits_the_track_does_not_bound():
    lengths = [2.0, 1.37, 0.94, 1.37, 0.94, 0.64, 0.94]
    answers = [True] * len(lengths)
    inside = {"threshold": 0.9, "ci": (0.7, 1.2)}
    assert exp2_usable(lengths, answers, 1.0, inside) == ("", "")
    for threshold in (0.5, 2.5, 17.93, float("nan")):  # below, above, at e^1.5 x 4, none
        why = exp2_usable(lengths, answers, 1.0, {"threshold": threshold, "ci": (0.1, 9)})[1]
        assert "beyond the lengths presented (0.640-2.000)" in why
    assert exp2_usable(lengths, answers, float("nan"), inside)[0].startswith("0 reversal(s)")


def test_a_track_whose_rows_do_not_replay_is_reported_and_left_out(tmp_path):
    path = run_exp2(tmp_path, "p02", stop_after=31)  # the first stage, complete
    lines = path.read_text().splitlines(keepends=True)
    fields = lines[8].split(",")
    at = Experiment2.fields.index("correct")
    fields[at] = "0" if fields[at] == "1" else "1"  # (the analysis built on it)
    lines[8] = ",".join(fields)
    path.write_text("".join(lines))
    problems = Problems()
    assert exp2_tracks(tmp_path, problems) == {}
    assert problems.items == [
        f"{path}:9: correct {fields[at]} does not follow from the answers (the staircase gives "
        f"{1 - int(fields[at])}): the row was changed after it was written; its stage is left out"
    ]


@pytest.mark.parametrize("make", [make_fifo, link_to_zero, link_out])
def test_the_analysis_names_a_special_file_and_goes_on(run, make):
    path = run / "participant-p01" / "exp2.csv"
    outside = run / "outside.csv"
    shutil.move(path, outside)
    make(path, outside)
    problems = Problems()
    assert exp2_tracks(run, problems) == {}
    assert problems.items and f"{path}:1: cannot be read: not a regular file" in problems.items[0]
