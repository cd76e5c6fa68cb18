"""Files the tool writes are whole or not there: each goes to a temporary file renamed over the
target, so a full disk, a signal or a refusal leaves the previous file and no temporary one;
the file keeps the mode the umask (or the file it replaces) gives; what is not a regular file
is never replaced; a command cut short says why in its exit status."""

import errno
import os
import signal
import stat
import subprocess
import sys
import time

import pytest

import tactile_core as tc
from tactile_core._shared.jsonfile import write_json_atomic
from tactile_core.files import export
from tactile_core.files.export import write_lut_csv
from tactile_core.files.tact import write_tact
from tactile_core.rendering.shapes import TimedPath

from .helpers import run_cli_last_line

CLI = [sys.executable, "-m", "tactile_core.cli"]
PALM = tc.Grid(5, 6)


def test_a_failed_export_keeps_the_previous_file(tmp_path, monkeypatch):
    path = tmp_path / "lut.csv"
    write_lut_csv(path, 0.33, 0.7)
    before = path.read_bytes()

    def full_disk(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full_disk)
    with pytest.raises(OSError, match="No space"):
        write_lut_csv(path, 0.0, 1.0)
    assert path.read_bytes() == before  # not a 0-byte file
    assert [p.name for p in tmp_path.iterdir()] == ["lut.csv"]  # no temporary left behind


def test_a_file_name_of_up_to_255_bytes_can_be_written(tmp_path):
    # the temporary file was named .NAME.<12 hex>.tmp: 17 bytes more than the name
    for name in ("a" * 251 + ".csv", "é" * 125 + ".h"):
        path = tmp_path / name
        assert len(os.fsencode(name)) <= 255
        writer = export.write_lut_csv if name.endswith(".csv") else export.write_lut_header
        writer(path, 0.33, 0.7)
        assert path.exists() and [p.name for p in tmp_path.iterdir()] == [name]
        path.unlink()


def test_atomic_writes_keep_the_umasks_mode_and_the_replaced_files(tmp_path):
    old = os.umask(0o022)
    try:
        write_json_atomic(tmp_path / "new.json", {})
        (tmp_path / "kept.json").write_text("{}")
        os.chmod(tmp_path / "kept.json", 0o640)
        write_json_atomic(tmp_path / "kept.json", {"a": 1})
        os.umask(0o027)
        write_json_atomic(tmp_path / "strict.json", {})
    finally:
        os.umask(old)
    modes = {p: stat.S_IMODE(os.stat(tmp_path / p).st_mode)
             for p in ("new.json", "kept.json", "strict.json")}  # fmt: skip
    # mkstemp makes 0600: the files were unreadable to those the umask lets read them
    assert modes == {"new.json": 0o644, "kept.json": 0o640, "strict.json": 0o640}
    assert sorted(os.listdir(tmp_path)) == ["kept.json", "new.json", "strict.json"]


def test_atomic_writes_leave_nothing_when_a_signal_lands_as_the_file_is_made(tmp_path, monkeypatch):
    # Beside stress-ng, 1 in 24 signalled renders left their .tmp file: the handler ran as
    # os.open returned, before the cleanup that removes it was in force. Here the signal is
    # made to land exactly there.
    from tactile_core._shared import outfile

    real_open = os.open

    def open_then_interrupted(*args, **kwargs):
        real_open(*args, **kwargs)  # the file exists now
        raise KeyboardInterrupt

    monkeypatch.setattr(outfile.os, "open", open_then_interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_json_atomic(tmp_path / "out.json", {"a": 1})
    monkeypatch.undo()
    assert os.listdir(tmp_path) == []


def test_atomic_writes_never_replace_what_is_not_a_regular_file(tmp_path):
    # As root, a rename over /dev/null would put a regular file in the device's place: every
    # atomic writer refuses first.
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    folder = tmp_path / "folder"
    folder.mkdir()
    link = tmp_path / "link-to-pipe"
    link.symlink_to(fifo)
    for target in (fifo, folder, link):
        with pytest.raises(OSError, match="not a regular file") as caught:
            write_json_atomic(target, {"a": 1})
        assert caught.value.filename == str(target)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode) and folder.is_dir() and link.is_symlink()
    assert sorted(os.listdir(tmp_path)) == ["folder", "link-to-pipe", "pipe"]  # no temporaries


def test_write_tact_refuses_what_is_not_a_regular_file_and_leaves_it_in_place(tmp_path):
    # write_tact's rename replaced whatever was at the path: as root, write_tact to /dev/null
    # put a regular file in the device's place (a FIFO stands in for it here).
    path = TimedPath([(0.5, 0.5), (4.5, 5.5)], [0.0, 1.0])
    fifo = tmp_path / "pipe.tact"
    os.mkfifo(fifo)
    with pytest.raises(ValueError, match="not a regular file"):
        write_tact(fifo, path, PALM)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    with pytest.raises(ValueError, match="is a folder"):
        write_tact(tmp_path, path, PALM)
    with pytest.raises(ValueError, match="does not exist"):
        write_tact(tmp_path / "missing" / "x.tact", path, PALM)
    with pytest.raises(ValueError, match="must be a file path"):
        write_tact("", path, PALM)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe.tact"]  # no temporary left


def test_a_full_disk_during_a_run_exits_1_naming_the_file(tmp_path, capsys, monkeypatch):
    # docs/cli.md: an operating-system error during a run exits with 1 (it exited with 2,
    # the status of bad arguments)
    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    for out in ("f.csv", "f.npz"):
        code, line = run_cli_last_line(capsys, "render", "--shape", "circle:2.5,3,2",
                                       "--method", "AS", "--out", tmp_path / out)  # fmt: skip
        assert code == 1 and f"cannot write {tmp_path / out}: No space left on device" in line
    code, line = run_cli_last_line(capsys, "export-tact", "--shape", "line:0.5,0.5,4.5,5.5",
                                   "--out", tmp_path / "t.tact")  # fmt: skip
    assert code == 1 and "No space left on device" in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("signame", ["SIGTERM", "SIGHUP"])
def test_render_ended_by_a_signal_leaves_no_temporary_file(tmp_path, signame):
    """SIGTERM in the middle of a long render left its half-written temporary file (hundreds
    of MB for a WAV) beside the output; it ends as Ctrl-C does: removed, status 128+N."""
    out = tmp_path / "long.wav"
    proc = subprocess.Popen(
        [*CLI, "render", "--profile", "belt-8", "--shape", "line:0,0,7,0", "--method", "BA",
         "--duration", "1200", "--rate", "300", "--samplerate", "96000", "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    deadline = time.monotonic() + 60
    while not any(p.name.endswith(".tmp") for p in tmp_path.iterdir()):
        assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
        time.sleep(0.05)  # polling for the temporary file (a bound of 60 s above)
    proc.send_signal(getattr(signal, signame))
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + getattr(signal, signame), err
    assert "Traceback" not in err and "tactile render: ended by" in err
    assert sorted(os.listdir(tmp_path)) == []
