"""What a participant's folder may hold, and how much of it is read: only regular files inside
the folder are read or written (a FIFO, a folder, a device or a link out is refused without
blocking or writing through), a results file is refused by its size before it is read and its
rows are streamed with a bound on each, and JSON nested past a small depth is refused."""

import json
import tracemalloc

import pytest

from tactile_core.experiments import Experiment2, open_session
from tactile_core.experiments.results import MAX_RESULTS_BYTES, MAX_ROW_BYTES, SessionError

from . import results_support as support
from .results_support import link_dangling, link_out, link_to_zero, make_fifo, make_folder

exp2_run, run = support.exp2_run, support.run


@pytest.mark.parametrize("member", ["exp2.csv", "exp2.csv.torn", "session.json", "correction.json"])
@pytest.mark.parametrize("make", [make_fifo, make_folder, link_to_zero, link_out, link_dangling])
def test_anything_but_a_regular_file_in_the_folder_is_refused(run, member, make):
    folder = run / "participant-p01"
    csv_path = folder / "exp2.csv"
    csv_path.write_bytes(csv_path.read_bytes()[:-5])  # a torn last row: resuming writes .torn
    target = folder / member
    outside = run / "outside"
    outside.write_bytes(target.read_bytes() if target.exists() else b"kept\n")
    before = outside.read_bytes()
    target.unlink(missing_ok=True)
    make(target, outside)
    with pytest.raises(ValueError, match=rf"{member}: not a regular file"):
        Experiment2(open_session(run, "p01"))
    assert outside.read_bytes() == before  # never written through


def _peak(call):
    tracemalloc.start()
    try:
        call()
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return peak


def test_a_500_mb_results_file_is_refused_by_its_size_without_reading_it(run):
    # it was read whole: a MemoryError
    path = run / "participant-p01" / "exp2.csv"
    with path.open("r+b") as f:
        f.truncate(500 << 20)  # sparse: its rows are zeros, as a reader would see them

    def resume():
        with pytest.raises(SessionError, match=r"524,288,000 bytes, more than the 32 MiB"):
            Experiment2(open_session(run, "p01"))

    assert _peak(resume) < 4 << 20
    assert path.stat().st_size == 500 << 20  # left as it was


def test_rows_are_streamed_and_a_surplus_stops_the_reading(run):
    path = run / "participant-p01" / "exp2.csv"
    body = path.read_bytes().split(b"\n", 1)[1]
    copies = (MAX_RESULTS_BYTES // 2) // len(body)
    with path.open("ab") as f:
        f.write(body * copies)  # 16 MiB of rows beyond the last trial's

    def resume():
        with pytest.raises(SessionError, match=r"exp2\.csv:\d+: "):
            Experiment2(open_session(run, "p01"))

    assert _peak(resume) < 4 << 20


def test_a_row_longer_than_the_bound_is_refused(run):
    path = run / "participant-p01" / "exp2.csv"
    data = path.read_bytes()
    cut = data.index(b"\n", data.index(b"\n") + 1) + 1
    path.write_bytes(data[:cut] + b"x" * (MAX_ROW_BYTES + 10) + b"\n" + data[cut:])
    with pytest.raises(SessionError, match=rf"exp2\.csv:3: a row longer than {MAX_ROW_BYTES}"):
        Experiment2(open_session(run, "p01"))


def nested(depth):
    value = 1
    for _ in range(depth):
        value = [value]
    return value


def test_a_session_nested_500_deep_is_refused_at_load(run):
    # it was accepted, and Experiment2 then raised RecursionError walking it
    path = run / "participant-p01" / "session.json"
    data = json.loads(path.read_text())
    data["parameters"]["deep"] = nested(500)
    path.write_text(json.dumps(data))
    with pytest.raises(
        SessionError, match=r"session\.json: nested too deeply \(more than 20 levels"
    ):
        open_session(run, "p01")


def test_a_correction_nested_500_deep_is_refused(run):
    correction = {"format": "tactile-correction", "mu": 0.3, "gamma": 0.6, "x": nested(500)}
    (run / "participant-p01" / "correction.json").write_text(json.dumps(correction))
    with pytest.raises(
        ValueError, match=r"correction\.json: nested too deeply \(more than 20 levels"
    ):
        Experiment2(open_session(run, "p01"))
