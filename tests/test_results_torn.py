"""A results file whose end was torn (a crash or a full disk mid-row): the torn header or row,
and any junk after it, is moved aside to ``NAME.torn`` and the run resumes from the last whole
row, with no hand repair and nothing lost; a file with another file's columns is refused, not
moved aside."""

import pytest

from tactile_core.experiments import Experiment2, open_session
from tactile_core.experiments.results import SessionError

from . import results_support as support

exp2_run, run = support.exp2_run, support.run
HEADER = Experiment2.fields


@pytest.mark.parametrize("cut", [1, 7, 12, 40, 90, len(",".join(HEADER)) - 1])
@pytest.mark.parametrize(
    "junk", [b"", b"\x00" * 64, b"\xff\xfe garbage\nmore, junk\n\x01", b"\nL1,3\n", b"Zq"]
)
def test_a_header_cut_short_then_junk_is_moved_aside(tmp_path, cut, junk):
    folder = tmp_path / "participant-p01"
    open_session(tmp_path, "p01", seed=7)
    header = (",".join(HEADER) + "\n").encode()
    torn = header[:cut] + junk
    (folder / "exp2.csv").write_bytes(torn)
    runner = Experiment2(open_session(tmp_path, "p01"))
    assert runner.done == 0 and (runner.recovered or not torn)
    runner.close()
    assert (folder / "exp2.csv").read_bytes() == header
    kept = (folder / "exp2.csv.torn").read_bytes()
    assert kept == (torn if torn.endswith(b"\n") else torn + b"\n")


@pytest.mark.parametrize("junk", [b"\x00" * 30 + b"\n" + b"\x00" * 30 + b"\n", b"z\nq,q\n\xff"])
def test_a_torn_last_row_then_lines_of_junk_is_moved_aside_not_lost(run, junk):
    # it was refused, and the participant's run needed a repair by hand
    path = run / "participant-p01" / "exp2.csv"
    data = path.read_bytes()
    start = data.rstrip(b"\n").rfind(b"\n") + 1  # the last row
    path.write_bytes(data[: start + 20] + junk)
    runner = Experiment2(open_session(run, "p01"))
    assert runner.done == 39 and "what follows it" in runner.recovered
    runner.close()
    assert path.read_bytes() == data[:start]
    torn = data[start : start + 20] + junk
    assert (path.parent / "exp2.csv.torn").read_bytes() == torn + b"\n" * (not junk.endswith(b"\n"))


@pytest.mark.parametrize(
    "first",
    [
        "participant,stage,trial,midpoint,mu,gamma,len,direction",  # another layout
        "participant,stage,trial",  # fewer columns (an older layout), then rows
        "time,r0c0,r0c1",  # a tactile render CSV
    ],
)
def test_another_files_columns_are_refused_not_moved_aside(tmp_path, first):
    folder = tmp_path / "participant-p01"
    open_session(tmp_path, "p01", seed=7)
    data = (first + "\np01,L1,0\n").encode()
    (folder / "exp2.csv").write_bytes(data)
    with pytest.raises(SessionError, match=r"exp2\.csv:1: columns"):
        Experiment2(open_session(tmp_path, "p01"))
    assert (folder / "exp2.csv").read_bytes() == data
    assert not (folder / "exp2.csv.torn").exists()
