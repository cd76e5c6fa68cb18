"""A participant's results on disk for the tests that change them (test_results_replay.py,
test_results_torn.py, test_results_files.py, test_analysis_exclusions.py): recorded runs, a
fresh copy per test, and the CSV read and changed by hand."""

import csv
import io
import os
import shutil

import pytest

from tactile_core.experiments import (
    RUNNERS,
    SimulatedObserver,
    SimulatedParticipant,
    open_session,
)

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
    """A copy of :func:`exp2_run`'s results folder of this test's own."""
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


# What is not a regular file, made at ``path`` (``outside``: a file outside the folder)


def make_fifo(path, outside):
    os.mkfifo(path)


def make_folder(path, outside):
    path.mkdir()


def link_to_zero(path, outside):
    path.symlink_to("/dev/zero")


def link_out(path, outside):
    path.symlink_to(outside)


def link_dangling(path, outside):
    path.symlink_to(outside.parent / "nowhere")
