"""A participant's rows are trusted only as far as they replay: on resuming, every row must be
what the session's procedure gives for the answers before it, so a row changed after it was
written (a flipped correct flag, a blanked or edited field, in any runner) is refused naming
the file, the row and the field, never built upon."""

import pytest

from tactile_core.experiments import RUNNERS, Experiment2, open_session
from tactile_core.experiments.results import SessionError

from . import results_support as support
from .results_support import HEALTH, change, record, table, write_table

exp2_run, run = support.exp2_run, support.run
MEASURED = {"rt_s", "time", *HEALTH}


def test_a_flipped_correct_flag_is_refused_naming_file_row_and_field(run):
    # one built upon moved the analysis's L1 threshold from 0.791 to 1.155
    header, rows = table(run / "participant-p01" / "exp2.csv")
    old = rows[8][header.index("correct")]
    change(run, 10, "correct", {"0": "1", "1": "0"}[old])
    with pytest.raises(SessionError, match=rf"exp2\.csv:10: field correct is '{1 - int(old)}'"):
        Experiment2(open_session(run, "p01"))


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("participant", "p02"),
        ("participant", ""),
        ("direction", ""),  # blank trial fields were accepted
        ("midpoint", ""),
        ("length", "1.5"),
        ("next_length", "3.9"),
        ("reversal", ""),
        ("mu", "0.34"),
        ("answer", ""),
        ("rt_s", "abc"),
        ("rt_s", "-1"),
        ("time", "yesterday"),
        ("late_frames", "-1"),
        ("presentations", "1.5"),
    ],
)
def test_a_changed_field_is_refused_at_its_row(run, field, value):
    change(run, 25, field, value)
    with pytest.raises(SessionError, match=rf"exp2\.csv:25: field {field} is"):
        Experiment2(open_session(run, "p01"))


def test_a_changed_last_row_is_refused_not_set_aside_as_torn(run):
    change(run, 41, "next_length", "0.5")
    with pytest.raises(SessionError, match=r"exp2\.csv:41: field next_length"):
        Experiment2(open_session(run, "p01"))
    assert not (run / "participant-p01" / "exp2.csv.torn").exists()


def test_every_field_of_a_row_blanked_or_changed_is_refused(run):
    path = run / "participant-p01" / "exp2.csv"
    original = path.read_bytes()
    header, rows = table(path)
    tried = 0
    for field, old in zip(header, rows[20]):
        # A measured field may hold any measurement (or be empty but for the time): only what
        # the runner never writes is wrong there; every other field follows from the session.
        values = ["x9", ""] if field == "time" else ["x9"] if field in MEASURED else ["", "9"]
        for value in values:
            if value == old:
                continue
            path.write_bytes(original)
            change(run, 22, field, value)
            with pytest.raises(SessionError, match=r"exp2\.csv:22: field \w+ is"):
                Experiment2(open_session(run, "p01"))
            tried += 1
    assert tried >= 2 * len(header) - len(MEASURED) - 1


@pytest.mark.parametrize(
    ("name", "n", "field"),
    [("exp1", 8, "method"), ("exp3", 8, "correct"), ("calibration", 12, "next_level"),
     ("correction", 12, "correct")],
)  # fmt: skip
def test_each_runner_refuses_a_changed_derived_field(tmp_path, name, n, field):
    path = record(tmp_path, name, n)
    header, rows = table(path)
    line = next(k for k in range(len(rows) - 1, 0, -1) if rows[k][header.index(field)] != "")
    old = rows[line][header.index(field)]
    rows[line][header.index(field)] = {"0": "1", "1": "0"}.get(old, "MM" if old != "MM" else "AS")
    if field == "next_level":
        rows[line][header.index(field)] = f"{float(old) * 1.5:.6g}"
    write_table(path, header, rows)
    with pytest.raises(SessionError, match=rf"{name}\.csv:{line + 2}: field "):
        RUNNERS[name](open_session(tmp_path, "p01"))
