"""Results a lab can trust: a failing write, a torn last row at every offset, a second writer,
a killed holder of the lock, a malformed row. Each fault is injected; the data must come out as
an uninterrupted run's, or be refused naming the file, the row and the problem."""

import copy
import csv
import errno
import io
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from tactile_core.experiments import RUNNERS, SimulatedParticipant, open_session
from tactile_core.experiments.results import SessionError

IGNORED = ("time", "rt_s")


def answer_all(runner, participant, stop_after=None):
    while not runner.finished and (stop_after is None or runner.done < stop_after):
        if runner.current.kind == "prepare":
            for key in (1, 2, 3, 4, 2, 3):
                runner.select(key)
        runner.answer(participant.respond(runner.current), rt_s=1.0)


def rows_of(path):
    with open(path, newline="", encoding="utf-8") as f:
        return [{k: v for k, v in r.items() if k not in IGNORED} for r in csv.DictReader(f)]


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """An uninterrupted run of each experiment: the rows every faulty run must end with."""
    root = tmp_path_factory.mktemp("reference")
    out = {}
    for name in ("exp1", "exp2", "exp3"):
        runner = RUNNERS[name](open_session(root, "p01", seed=7, index=2))
        answer_all(runner, SimulatedParticipant(seed=5))
        runner.close()
        out[name] = rows_of(root / "participant-p01" / f"{name}.csv")
    return out


@pytest.mark.parametrize("name", ["exp1", "exp2", "exp3"])
def test_a_failed_write_keeps_the_trial_and_a_retry_records_it_once(
    tmp_path, monkeypatch, reference, name
):
    runner = RUNNERS[name](open_session(tmp_path, "p01", seed=7, index=2))
    participant = SimulatedParticipant(seed=5)
    answer_all(runner, participant, stop_after=17)
    trial = runner.current
    answer = participant.respond(trial)
    real_fsync = os.fsync
    failures = []

    def full_disk(fd):
        failures.append(fd)
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full_disk)
    for _ in range(3):  # the disk stays full: every attempt fails, nothing moves
        with pytest.raises(OSError, match="No space"):
            runner.answer(answer, rt_s=1.0)
        assert runner.current == trial and runner.done == 17
    monkeypatch.setattr(os, "fsync", real_fsync)
    runner.answer(answer, rt_s=1.0)  # space again: recorded once
    answer_all(runner, participant)
    runner.close()
    assert failures
    assert rows_of(tmp_path / "participant-p01" / f"{name}.csv") == reference[name]


def test_a_write_that_stops_halfway_leaves_no_half_row(tmp_path, monkeypatch, reference):
    runner = RUNNERS["exp2"](open_session(tmp_path, "p01", seed=7, index=2))
    participant = SimulatedParticipant(seed=5)
    answer_all(runner, participant, stop_after=40)
    path = tmp_path / "participant-p01" / "exp2.csv"
    size = path.stat().st_size
    real_write = os.write

    def half_then_full(fd, data):
        if fd == runner._file._fd:
            real_write(fd, bytes(data)[: len(data) // 2])
            raise OSError(errno.ENOSPC, "No space left on device")
        return real_write(fd, data)

    answer = participant.respond(runner.current)
    monkeypatch.setattr(os, "write", half_then_full)
    with pytest.raises(OSError):
        runner.answer(answer)
    monkeypatch.setattr(os, "write", real_write)
    assert path.stat().st_size == size  # the half row was cut away
    runner.answer(answer)
    answer_all(runner, participant)
    runner.close()
    assert rows_of(path) == reference["exp2"]


def test_a_torn_last_row_at_every_offset_is_moved_aside_and_presented_again(tmp_path, reference):
    # A complete run to tear: 60 answers of Experiment 2 (staircases in flight).
    src = tmp_path / "src"
    runner = RUNNERS["exp2"](open_session(src, "p01", seed=7, index=2))
    answer_all(runner, SimulatedParticipant(seed=5), stop_after=60)
    runner.close()
    data = (src / "participant-p01" / "exp2.csv").read_bytes()
    last_start = data.rstrip(b"\n").rfind(b"\n") + 1
    offsets = range(last_start, len(data))  # every cut inside the last row and its line end
    assert len(offsets) > 60
    # The participant as it was when the row was torn: the same random state the run had.
    answered = SimulatedParticipant(seed=5)
    replay = RUNNERS["exp2"](open_session(tmp_path / "ref", "p01", seed=7, index=2))
    answer_all(replay, answered, stop_after=59)
    replay.close()
    for cut in offsets:
        run = tmp_path / f"cut{cut}"
        folder = run / "participant-p01"
        folder.mkdir(parents=True)
        (folder / "session.json").write_bytes(
            (src / "participant-p01" / "session.json").read_bytes()
        )
        (folder / "exp2.csv").write_bytes(data[:cut])
        runner = RUNNERS["exp2"](open_session(run, "p01"))
        torn = folder / "exp2.csv.torn"
        if cut > last_start:
            assert runner.done == 59, cut  # the torn trial is presented again
            assert torn.read_bytes().rstrip(b"\n") == data[last_start:cut].rstrip(b"\n")
        else:
            assert runner.done == 59 and not torn.exists()
        # The participant answers on as if nothing happened: the same answers, the same data.
        answer_all(runner, copy.deepcopy(answered))
        runner.close()
        assert rows_of(folder / "exp2.csv") == reference["exp2"], cut


def test_a_malformed_row_before_the_last_is_refused_naming_file_and_row(tmp_path):
    runner = RUNNERS["exp3"](open_session(tmp_path, "p01", seed=7))
    answer_all(runner, SimulatedParticipant(seed=5), stop_after=12)
    runner.close()
    path = tmp_path / "participant-p01" / "exp3.csv"
    lines = path.read_text().splitlines(keepends=True)
    lines[5] = lines[5].replace(",square,", ",hexagon,").replace(",circle,", ",hexagon,")
    path.write_text("".join(lines))
    with pytest.raises(SessionError, match=r"exp3\.csv:6: .*shape"):
        RUNNERS["exp3"](open_session(tmp_path, "p01"))
    lines[5] = "a,b,c\n"
    path.write_text("".join(lines))
    with pytest.raises(SessionError, match=r"exp3\.csv:6: 3 fields, the header has"):
        RUNNERS["exp3"](open_session(tmp_path, "p01"))


def test_a_second_writer_on_the_same_participant_is_refused(tmp_path):
    first = RUNNERS["exp2"](open_session(tmp_path, "p01", seed=7))
    with pytest.raises(SessionError, match=f"being recorded by PID {os.getpid()}"):
        RUNNERS["exp3"](open_session(tmp_path, "p01"))
    first.close()
    RUNNERS["exp3"](open_session(tmp_path, "p01")).close()  # free again once closed


HOLDER = textwrap.dedent(
    """
    import signal, sys
    from tactile_core.experiments import RUNNERS, open_session
    runner = RUNNERS["exp2"](open_session(sys.argv[1], "p01", seed=7))
    print("holding", flush=True)
    signal.pause()  # until killed
    """
)


def test_another_process_holding_the_participant_is_refused_until_it_is_killed(tmp_path):
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(tmp_path)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert holder.stdout.readline().strip() == "holding"
        with pytest.raises(SessionError, match=f"PID {holder.pid}"):
            RUNNERS["exp2"](open_session(tmp_path, "p01"))
        os.kill(holder.pid, signal.SIGKILL)  # its lock stays behind, stale
        holder.wait()
        runner = RUNNERS["exp2"](open_session(tmp_path, "p01"))  # taken over
        assert runner._lock.held
        runner.close()
    finally:
        if holder.poll() is None:
            holder.kill()
            holder.wait()
        holder.stdout.close()


def test_two_processes_racing_for_one_participant_leave_one_writer(tmp_path):
    race = textwrap.dedent(
        """
        import sys, time
        from tactile_core.experiments import RUNNERS, SimulatedParticipant, open_session
        from tactile_core.experiments.results import SessionError
        try:
            runner = RUNNERS["exp2"](open_session(sys.argv[1], "p01", seed=7, index=0))
        except SessionError as exc:
            print("refused", flush=True)
            sys.exit(3)
        p = SimulatedParticipant(seed=5)
        while not runner.finished:
            runner.answer(p.respond(runner.current))
            time.sleep(0.001)  # fixed: widens the race the test is about (both outcomes pass)
        runner.close()
        print("wrote", flush=True)
        """
    )
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", race, str(tmp_path)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for _ in range(2)
    ]
    outs = [p.communicate(timeout=60) for p in procs]
    results = sorted(out.strip() for out, _ in outs)
    assert results in (["refused", "wrote"], ["wrote", "wrote"]), [e for _, e in outs]
    rows = list(
        csv.DictReader(io.StringIO((tmp_path / "participant-p01" / "exp2.csv").read_text()))
    )
    assert len(rows) == RUNNERS["exp2"].total  # each trial exactly once, never interleaved
    keys = [(r["stage"], r["trial"]) for r in rows]
    assert len(set(keys)) == len(keys)


def test_a_lock_file_left_half_written_is_stale(tmp_path):
    open_session(tmp_path, "p01")
    (tmp_path / "participant-p01" / ".lock").write_text('{"host": "x", "pi')
    start = time.monotonic()
    RUNNERS["exp3"](open_session(tmp_path, "p01")).close()
    assert time.monotonic() - start < 5
