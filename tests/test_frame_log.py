"""Frames kept in bounded, compact memory, and outputs that fail on a full disk say which file.

``--record`` once grew ~144 MB/h while its docstring said ~32 MB/h, the emulator kept every
frame (+120 MB/h), and the disk-full messages of ``stream`` and ``emulate`` did not name the
file; the emulator's logs are read while its thread writes them.
"""

import errno
import threading

import numpy as np
import pytest

from tactile_core._shared import outfile
from tactile_core.cli import main as cli
from tactile_core.device.emulator import Emulator
from tactile_core.device.frame_log import BLOCK, FrameLog
from tactile_core.device.profile import default_profile
from tactile_core.files.frames import Recorder


def frames(n, channels=30, seed=0):
    """n random frames as the lists a naive log would keep."""
    rng = np.random.default_rng(seed)
    times = np.cumsum(rng.uniform(0.001, 0.005, n))
    seqs = np.arange(n) % 256
    levels = rng.integers(0, 23, (n, channels), dtype=np.uint8)
    return times, seqs, levels


def test_the_log_returns_exactly_what_was_appended_across_blocks():
    n = 2 * BLOCK + 17
    times, seqs, levels = frames(n)
    log = FrameLog(30)
    assert log.last() is None and log.arrays()[0].shape == (0,)
    for t, s, lv in zip(times, seqs, levels):
        log.append(t, s, lv.tobytes())
    got_t, got_s, got_l = log.arrays()
    np.testing.assert_array_equal(got_t, times)
    np.testing.assert_array_equal(got_s, seqs)
    np.testing.assert_array_equal(got_l, levels)
    assert len(log) == log.kept == n and log.dropped == 0
    assert log.last() == levels[-1].tobytes() and log.last_seq() == seqs[-1]
    np.testing.assert_array_equal(log.arrays(n - 5)[2], levels[-5:])


def test_a_bounded_log_keeps_the_latest_frames_and_stops_growing():
    capacity = BLOCK + 100
    n = 6 * BLOCK + 3
    times, seqs, levels = frames(n, channels=4)
    log = FrameLog(4, capacity)
    peak = 0
    for t, s, lv in zip(times, seqs, levels):
        log.append(t, s, lv.tobytes())
        peak = max(peak, log.nbytes)
    assert len(log) == n and capacity <= log.kept < capacity + 2 * BLOCK
    assert log.dropped == n - log.kept and log.dropped % BLOCK == 0
    got_t, _, got_l = log.arrays()
    np.testing.assert_array_equal(got_t, times[-log.kept :])
    np.testing.assert_array_equal(got_l, levels[-log.kept :])
    assert peak <= (capacity + 2 * BLOCK) * (9 + 4)  # bounded, whatever n
    # counted over every frame appended: a start before the kept ones gives all that is kept
    assert len(log.arrays(10)[0]) == log.kept
    assert len(log.arrays(n - 3)[0]) == 3


def test_a_log_needs_room_for_a_frame():
    with pytest.raises(ValueError, match="capacity 0"):
        FrameLog(30, 0)


def test_a_reader_in_another_thread_only_sees_whole_frames():
    """The tests read the emulator's log while its thread appends: never a row not written."""
    log = FrameLog(2)
    stop = threading.Event()
    seen_bad = []

    def reader():
        while not stop.is_set():
            last = log.last()
            if last is not None and last[0] != last[1]:
                seen_bad.append(last)
            lv = log.arrays(max(0, len(log) - BLOCK - 10))[2]
            if len(lv) and not (lv[:, 0] == lv[:, 1]).all():
                seen_bad.append("arrays")

    thread = threading.Thread(target=reader)
    thread.start()
    try:
        for i in range(3 * BLOCK):
            v = 1 + i % 200  # both channels equal in every written frame
            log.append(float(i), i % 256, bytes((v, v)))
    finally:
        stop.set()
        thread.join()
    assert seen_bad == []


def test_the_recorder_costs_39_bytes_a_frame_for_the_palm_array():
    profile = default_profile()
    recorder = Recorder(profile.array)
    times, seqs, levels = frames(3 * BLOCK)
    for t, s, lv in zip(times, seqs, levels):
        recorder(t, s, lv.tobytes())
    assert recorder.log.nbytes == 3 * BLOCK * 39  # 42 MB for an hour at 300 Hz
    time_s, seq, cells = recorder.arrays()
    np.testing.assert_allclose(time_s, times - times[0])
    np.testing.assert_array_equal(seq, seqs)
    # cells are (rows, cols) with channel i at flat cell channel_index[i]
    flat = cells.reshape(len(seq), -1)
    np.testing.assert_array_equal(flat[:, profile.array.channel_index], levels)


def test_the_emulator_keeps_only_its_latest_frames():
    emulator = Emulator(default_profile(), expected_rate_hz=300.0, keep_frames=BLOCK)
    emulator.started = 0.0
    _, seqs, levels = frames(4 * BLOCK)

    class Frame:
        def __init__(self, seq, lv):
            self.seq, self.levels = int(seq), lv.tobytes()

    for i, (s, lv) in enumerate(zip(seqs, levels)):
        emulator._log([Frame(s, lv)], i / 300.0)
    report = emulator.report()
    assert report["frames"] == 4 * BLOCK and BLOCK <= report["frames_kept"] < 3 * BLOCK
    assert report["seq_gaps"] == 0
    assert abs(report["rate_hz"] - 300.0) < 1e-6
    assert "kept" in emulator.summary().splitlines()[0]


def test_an_emulators_report_may_be_read_while_its_thread_logs_events():
    # report() iterated the events deque that the emulator's thread appends to (an answer to
    # every status query); a report read meanwhile raised "deque mutated during iteration".
    emulator = Emulator()
    emulator.open()
    try:
        for k in range(emulator.events.maxlen):  # full: each append also drops the oldest
            emulator.events.append((float(k), "answered 20 bytes"))
        stop = threading.Event()

        def log_events():
            while not stop.is_set():
                emulator.events.append((0.0, "answered 20 bytes"))

        thread = threading.Thread(target=log_events, daemon=True)
        thread.start()
        try:
            for _ in range(50):
                assert len(emulator.report()["events"]) == emulator.events.maxlen
        finally:
            stop.set()
            thread.join(5)
    finally:
        emulator.close()


@pytest.fixture
def full_disk(monkeypatch):
    """Every atomic output fails as on a full disk, when it is synced."""

    def fsync(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(outfile.os, "fsync", fsync)


def test_stream_names_the_recording_it_could_not_write(capsys, tmp_path, full_disk):
    target = tmp_path / "rec.csv"
    code = cli(["stream", "--device", "sim", "--shape", "circle:2,2.5,1.5", "--method", "AS",
                "--seconds", "0.2", "--record", str(target)])  # fmt: skip
    out = capsys.readouterr()
    assert code == 1
    assert "frames:" in out.out  # the statistics still printed
    line = out.err.strip().splitlines()[-1]
    assert line.startswith("tactile stream: cannot write the recording of ")
    assert str(target) in line and "No space left on device" in line
    assert list(tmp_path.iterdir()) == []  # no partial file, no temporary left behind


def test_emulate_names_each_file_it_could_not_write(capsys, tmp_path, full_disk):
    log, report = tmp_path / "log.csv", tmp_path / "r.json"
    code = cli(["emulate", "--seconds", "0.05", "--log", str(log), "--json", str(report)])
    out = capsys.readouterr()
    assert code == 1 and "received 0 frames" in out.out
    errors = out.err.strip().splitlines()[-2:]
    assert errors == [
        f"tactile emulate: cannot write {log}: No space left on device",
        f"tactile emulate: cannot write {report}: No space left on device",
    ]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("value", ["0", "-1", "1e3"])
def test_keep_frames_must_be_a_positive_whole_number(capsys, value):
    try:
        code = cli(["emulate", "--seconds", "0.05", "--keep-frames", value])
    except SystemExit as exc:
        code = exc.code
    assert code == 2 and "keep-frames" in capsys.readouterr().err
