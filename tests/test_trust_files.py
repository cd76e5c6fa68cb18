"""A participant's files, trusted only as far as they replay (issue 19, items 2-5): a row the
session's procedure does not reproduce is refused naming file:row and the field; a header cut
short is set aside; anything but a regular file in the folder is refused without blocking or
writing through; reads are bounded and streamed; JSON nested past a small bound is refused."""

import csv
import io
import json
import os
import shutil
import tracemalloc

import pytest

from tactile_core.experiments import (
    RUNNERS,
    Experiment2,
    SimulatedObserver,
    SimulatedParticipant,
    open_session,
)
from tactile_core.experiments.results import MAX_RESULTS_BYTES, MAX_ROW_BYTES, SessionError

HEALTH = {"late_frames": 0, "skipped_frames": 0, "link_errors": 0, "presentations": 1}


def record(root, name, n, seed=7):
    """``n`` answers of experiment ``name`` for participant p01; the CSV's path."""
    runner = RUNNERS[name](open_session(root, "p01", seed=seed, index=2))
    respond = (SimulatedObserver(0.25, 1.0, seed=5) if name == "correction"
               else SimulatedParticipant(seed=5)).respond  # fmt: skip
    while runner.done < n and not runner.finished:
        if runner.current.kind == "prepare":
            for key in (1, 2, 3, 4, 2):
                runner.select(key)
        runner.answer(respond(runner.current), rt_s=0.8, health=HEALTH)
    runner.close()
    return root / "participant-p01" / f"{name}.csv"


@pytest.fixture(scope="module")
def exp2_run(tmp_path_factory):
    """40 answers of Experiment 2 (two stages under way)."""
    return record(tmp_path_factory.mktemp("exp2"), "exp2", 40).parent.parent


@pytest.fixture
def run(exp2_run, tmp_path):
    root = tmp_path / "run"
    shutil.copytree(exp2_run, root)
    return root


def table(path):
    rows = list(csv.reader(io.StringIO(path.read_text())))
    return rows[0], rows[1:]


def write_table(path, header, rows):
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows([header, *rows])
    path.write_text(out.getvalue())


def change(root, line, field, value):
    """Set ``field`` of the row on ``line`` (the header is line 1) of exp2.csv."""
    path = root / "participant-p01" / "exp2.csv"
    header, rows = table(path)
    rows[line - 2][header.index(field)] = value
    write_table(path, header, rows)
    return rows[line - 2]


# --- item 2: resume replays the procedure ------------------------------------------------------


def test_a_flipped_correct_flag_is_refused_naming_file_row_and_field(run):
    # Before: a flipped flag was built upon (and the analysis moved L1 from 0.791 to 1.155).
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
        ("direction", ""),  # before: blank trial fields were accepted
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


def test_a_changed_last_row_is_refused_not_set_aside(run):
    change(run, 41, "next_length", "0.5")
    with pytest.raises(SessionError, match=r"exp2\.csv:41: field next_length"):
        Experiment2(open_session(run, "p01"))
    assert not (run / "participant-p01" / "exp2.csv.torn").exists()


MEASURED = {"rt_s", "time", *HEALTH}


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


HEADER = Experiment2.fields


@pytest.mark.parametrize("cut", [1, 7, 12, 40, 90, len(",".join(HEADER)) - 1])
@pytest.mark.parametrize(
    "junk", [b"", b"\x00" * 64, b"\xff\xfe garbage\nmore, junk\n\x01", b"\nL1,3\n", b"Zq"]
)
def test_a_header_cut_short_then_junk_is_set_aside(tmp_path, cut, junk):
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
def test_a_torn_row_then_lines_of_junk_is_set_aside(run, junk):
    path = run / "participant-p01" / "exp2.csv"
    data = path.read_bytes()
    start = data.rstrip(b"\n").rfind(b"\n") + 1  # the last row
    path.write_bytes(data[: start + 20] + junk)  # before: refused, needing hand repair
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
def test_another_files_columns_are_refused_not_set_aside(tmp_path, first):
    folder = tmp_path / "participant-p01"
    open_session(tmp_path, "p01", seed=7)
    data = (first + "\np01,L1,0\n").encode()
    (folder / "exp2.csv").write_bytes(data)
    with pytest.raises(SessionError, match=r"exp2\.csv:1: columns"):
        Experiment2(open_session(tmp_path, "p01"))
    assert (folder / "exp2.csv").read_bytes() == data
    assert not (folder / "exp2.csv.torn").exists()


# --- item 3: only regular files inside the folder ----------------------------------------------


def _fifo(path, outside):
    os.mkfifo(path)


def _folder(path, outside):
    path.mkdir()


def _zero(path, outside):
    path.symlink_to("/dev/zero")


def _out(path, outside):
    path.symlink_to(outside)


def _dangling(path, outside):
    path.symlink_to(outside.parent / "nowhere")


@pytest.mark.parametrize("member", ["exp2.csv", "exp2.csv.torn", "session.json", "correction.json"])
@pytest.mark.parametrize("make", [_fifo, _folder, _zero, _out, _dangling])
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


@pytest.mark.parametrize("make", [_fifo, _zero, _out])
def test_the_analysis_names_a_special_file_and_goes_on(run, make):
    from tactile_core.experiments.analysis import exp2_tracks
    from tactile_core.experiments.analysis._reading import Problems

    path = run / "participant-p01" / "exp2.csv"
    outside = run / "outside.csv"
    shutil.move(path, outside)
    make(path, outside)
    problems = Problems()
    assert exp2_tracks(run, problems) == {}
    assert problems.items and f"{path}:1: cannot be read: not a regular file" in problems.items[0]


# --- item 4: bounded, streamed reads -----------------------------------------------------------


def _peak(call):
    tracemalloc.start()
    try:
        call()
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return peak


def test_a_500_mb_results_file_is_refused_by_its_size_without_reading_it(run):
    path = run / "participant-p01" / "exp2.csv"
    with path.open("r+b") as f:
        f.truncate(500 << 20)  # sparse: its rows are zeros, as a reader would see them

    def resume():
        with pytest.raises(SessionError, match=r"524,288,000 bytes, more than the 32 MiB"):
            Experiment2(open_session(run, "p01"))

    assert _peak(resume) < 4 << 20  # before: MemoryError (the file read whole)
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


# --- item 5: deep JSON -------------------------------------------------------------------------


def nested(depth):
    value = 1
    for _ in range(depth):
        value = [value]
    return value


def test_a_session_nested_500_deep_is_refused_at_load(run):
    path = run / "participant-p01" / "session.json"
    data = json.loads(path.read_text())
    data["parameters"]["deep"] = nested(500)
    path.write_text(json.dumps(data))
    with pytest.raises(
        SessionError, match=r"session\.json: nested too deeply \(more than 20 levels"
    ):
        open_session(run, "p01")  # before: accepted, then Experiment2 raised RecursionError


def test_a_correction_nested_500_deep_is_refused(run):
    correction = {"format": "tactile-correction", "mu": 0.3, "gamma": 0.6, "x": nested(500)}
    (run / "participant-p01" / "correction.json").write_text(json.dumps(correction))
    with pytest.raises(
        ValueError, match=r"correction\.json: nested too deeply \(more than 20 levels"
    ):
        Experiment2(open_session(run, "p01"))


def test_deep_presets_and_profiles_are_refused_by_the_cli(tmp_path, capsys):
    from tactile_core._shared.assets import asset_path
    from tactile_core.cli import main
    from tactile_core.device.profile import ProfileError, load_profile
    from tactile_core.files.presets import PresetError, load_preset

    preset = json.loads(asset_path("presets", "exp3-square.json").read_text())
    profile = json.loads(asset_path("devices", "palm-5x6.json").read_text())
    preset["notes"], profile["notes"] = nested(300), nested(300)
    (tmp_path / "preset.json").write_text(json.dumps(preset))
    (tmp_path / "profile.json").write_text(json.dumps(profile))
    with pytest.raises(PresetError, match=r"nested too deeply \(more than 20 levels"):
        load_preset(tmp_path / "preset.json")
    with pytest.raises(ProfileError, match=r"nested too deeply \(more than 20 levels"):
        load_profile(tmp_path / "profile.json")
    code = main(["emulate", "--profile", str(tmp_path / "profile.json"), "--seconds", "0.1"])
    assert code == 2 and "nested too deeply (more than 20 levels" in capsys.readouterr().err
