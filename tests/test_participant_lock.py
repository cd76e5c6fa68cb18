"""The participant lock under races: exactly one writer wins every race, fresh or over a lock
left behind by a killed holder, whatever record that lock holds; and anything but a regular file
in the lock's place is refused without blocking."""

import importlib.util
import json
import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from tactile_core.experiments import RUNNERS, open_session
from tactile_core.experiments.results import ParticipantLock, SessionError
from tactile_core.experiments.results import _lock as lock_module
from tactile_core.experiments.results._lock import _alive

TOOLS = Path(__file__).resolve().parents[1] / "tools"


@pytest.fixture(scope="module")
def races():
    spec = importlib.util.spec_from_file_location("lock_races", TOOLS / "lock_races.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize(("kind", "writers", "rounds"),
                         [("fresh", 2, 20), ("stale", 4, 30), ("empty", 4, 30)])  # fmt: skip
def test_exactly_one_of_the_racing_writers_holds_the_lock(races, tmp_path, kind, writers, rounds):
    # Without an OS lock, 40 of 200 four-writer races over a stale lock had two holders.
    counts = races.race(kind, writers, rounds, tmp_path)
    assert counts["one"] == rounds, counts
    assert counts["errors"] == 0, counts


def test_writers_taking_and_releasing_one_lock_never_overlap(races, tmp_path):
    # A release removes the file while other writers open it: none may lock the removed file
    # while another holds the new one (it did: 5 overlaps in 8000 attempts).
    counts = races.churn(4, 300, tmp_path)
    assert counts["won"] > 0 and counts["overlaps"] == 0, counts


def test_a_lock_on_a_file_released_meanwhile_is_not_a_lock(tmp_path, monkeypatch):
    folder = tmp_path / "participant-p01"
    folder.mkdir()
    first = ParticipantLock(folder)
    real = lock_module._try_lock
    third, calls = [], []

    def release_then_lock(fd):
        calls.append(fd)
        if len(calls) == 1:  # the writer opened the holder's file; the holder lets go of it
            first.release()
            third.append(ParticipantLock(folder))  # and a third writer takes a new file
        return real(fd)

    monkeypatch.setattr(lock_module, "_try_lock", release_then_lock)
    with pytest.raises(SessionError, match=f"PID {os.getpid()}"):
        ParticipantLock(folder)  # it locks the removed file, sees it, starts again: refused
    assert third[0].held and (folder / ".lock").exists()
    third[0].release()
    assert not (folder / ".lock").exists()


def test_a_lock_left_by_a_killed_holder_is_taken(tmp_path):
    open_session(tmp_path, "p01")
    holder = subprocess.Popen(
        [sys.executable, "-c", "import sys; from tactile_core.experiments.results import "
         "ParticipantLock; ParticipantLock(sys.argv[1]); print('held', flush=True); "
         "sys.stdin.read()", str(tmp_path / "participant-p01")],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(SessionError, match=f"PID {holder.pid} on "):
            RUNNERS["exp3"](open_session(tmp_path, "p01"))
        holder.kill()
        holder.wait()
        assert (tmp_path / "participant-p01" / ".lock").exists()  # left behind, holding nothing
        RUNNERS["exp3"](open_session(tmp_path, "p01")).close()
    finally:
        holder.kill()
        holder.wait()
        holder.stdin.close()
        holder.stdout.close()


@pytest.mark.parametrize("record", [2**40, -1, "1e999", [1] * 3, None])
def test_any_record_in_a_lock_nobody_holds_is_taken_over(tmp_path, record):
    folder = tmp_path / "participant-p01"
    folder.mkdir()
    host = socket.gethostname()
    (folder / ".lock").write_text(json.dumps({"host": host, "pid": record, "since": "x"}))
    lock = ParticipantLock(folder)  # pid 2**40 raised OverflowError
    assert lock.held
    assert json.loads((folder / ".lock").read_text())["pid"] == os.getpid()
    lock.release()
    assert _alive(2**40) is False and _alive(-(2**70)) is False


def _fifo(path):
    os.mkfifo(path)


def _folder(path):
    path.mkdir()


def _link_out(path):
    outside = path.parent.parent / "outside.txt"
    outside.write_text("not yours")
    path.symlink_to(outside)


def _dangling(path):
    path.symlink_to(path.parent.parent / "nowhere")


@pytest.mark.parametrize("make", [_fifo, _folder, _link_out, _dangling])
def test_a_lock_that_is_not_a_regular_file_is_refused_without_blocking(tmp_path, make):
    open_session(tmp_path, "p01")
    folder = tmp_path / "participant-p01"
    make(folder / ".lock")
    with pytest.raises(SessionError, match=r"\.lock: not a regular file"):
        RUNNERS["exp2"](open_session(tmp_path, "p01"))
    outside = tmp_path / "outside.txt"
    assert not outside.exists() or outside.read_text() == "not yours"
    assert not (folder / "exp2.csv").exists() or (folder / "exp2.csv").stat().st_size == 0
