"""Lab Streaming Layer outlets that cannot open or whose source id is taken: an outlet liblsl
refuses is one line naming LSL, with nothing left open or streaming; a second program with the
same source id gets its own (SID-2) and says so; the locks that claim ids live in this user's
own folder and go with their outlets."""

import os
import uuid

import pylsl
import pytest

import tactile_core as tc
from tactile_core.device.profile import default_profile
from tactile_core.serve import LslError, LslOutlets

from .helpers import run_cli_here, stream_threads


def run_cli(capsys, *argv):
    """``(status, standard error)`` of ``tactile ARGV`` run here."""
    code, _, err = run_cli_here(capsys, *argv)
    return code, err


@pytest.fixture
def outlets_refused(monkeypatch):
    """liblsl that cannot open an outlet (no free port, no network interface)."""

    def refuse(*args, **kwargs):
        raise RuntimeError("could not create stream outlet.")

    monkeypatch.setattr(pylsl, "StreamOutlet", refuse)


@pytest.mark.parametrize(
    "argv",
    [
        ["stream", "--shape", "circle:2.5,3,2", "--method", "AS", "--seconds", "5"],
        ["serve", "--osc-port", "0", "--seconds", "5", "--status-s", "0"],
    ],
)
def test_lsl_that_cannot_open_an_outlet_is_one_line_and_exit_1(capsys, outlets_refused, argv):
    """Was a traceback ending in pylsl's 'could not create stream outlet.'; the command says
    so before it opens the device, and nothing streams."""
    code, err = run_cli(capsys, *argv, "--device", "sim", "--lsl")
    assert code == 1
    assert f"tactile {argv[0]}: error: Lab Streaming Layer: cannot open the outlets" in err
    assert "could not create stream outlet" in err and "[streaming]" not in err
    assert stream_threads() == []


def test_open_array_with_lsl_that_cannot_open_names_lsl_and_leaves_nothing_open(outlets_refused):
    with pytest.raises(LslError, match="Lab Streaming Layer: cannot open the outlets"):
        tc.open_array("sim", lsl=True)
    assert stream_threads() == []


def test_lsl_outlets_of_one_source_id_at_once_get_their_own():
    """Two `tactile serve --lsl` of one profile opened two streams with one source id, which a
    recorder finds a lost stream again by: the second is SID-2, and says why."""
    sid = f"tactile-test-{uuid.uuid4().hex[:8]}"
    profile = default_profile()
    first = LslOutlets(profile, source_id=sid)
    try:
        second = LslOutlets(profile, source_id=sid)
        try:
            assert (first.source_id, second.source_id) == (sid, f"{sid}-2")
            assert (
                first.note == "" and f"sends {sid}; this one's source id is {sid}-2" in second.note
            )
            found = pylsl.resolve_bypred(f"starts-with(source_id, '{sid}')", 2, 20)
            assert sorted(s.source_id() for s in found) == [f"{sid}-2-markers", f"{sid}-markers"]
        finally:
            second.close()
    finally:
        first.close()
    again = LslOutlets(profile, source_id=sid)  # closed: the id is free again
    try:
        assert again.source_id == sid and again.note == ""
    finally:
        again.close()


def test_cli_lsl_says_when_its_source_id_is_taken(capsys):
    held = LslOutlets(default_profile())  # the id tactile stream --lsl would take
    try:
        code, err = run_cli(capsys, "stream", "--device", "sim", "--shape", "circle:2.5,3,2",
                            "--method", "AS", "--seconds", "0.2", "--lsl")  # fmt: skip
    finally:
        held.close()
    assert code == 0
    assert "tactile stream: LSL: another program on this machine (process " in err
    assert "sends tactile-palm-5x6; this one's source id is tactile-palm-5x6-" in err


def test_lsl_source_id_locks_only_in_a_private_folder(tmp_path, monkeypatch):
    """The locks live in a folder of this user's own: in a shared /tmp another user could have
    made it first, or linked a lock file to one of this user's files, which a claim truncated."""
    from tactile_core.serve._lsl import claim_source_id

    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    sid = f"tactile-test-{uuid.uuid4().hex[:8]}"
    claimed, lock, _ = claim_source_id(sid)
    assert claimed == sid and lock is not None
    os.close(lock)
    folder = tmp_path / f"tactile-tuner-{os.getuid()}"
    folder.chmod(0o777)  # as if someone else could write there: no locks, the id as given
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    assert claim_source_id(sid) == (sid, None, "")
    assert victim.read_text() == "keep me"


def test_lsl_source_id_lock_files_go_with_their_outlets(tmp_path, monkeypatch):
    """Every claimed id left a lock file behind (192 in the folder after one suite run); a
    release removes it, and a claim that opened the file as it was being removed opens it
    anew rather than holding a lock on a file nobody else can see."""
    import fcntl

    from tactile_core.serve._lsl import _same_file, claim_source_id, release_source_id

    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    folder = tmp_path / f"tactile-tuner-{os.getuid()}" / "lsl"
    sid = f"tactile-test-{uuid.uuid4().hex[:8]}"
    first, lock1, _ = claim_source_id(sid)
    second, lock2, holder = claim_source_id(sid)
    assert (first, second, holder) == (sid, f"{sid}-2", str(os.getpid()))
    assert len(list(folder.iterdir())) == 2
    (path,) = [p for p in folder.iterdir() if int(p.read_text()) == os.getpid()
               and os.path.samestat(p.stat(), os.fstat(lock1))]  # fmt: skip
    late = os.open(path, os.O_RDWR)  # a claim that opened the file just before the release
    release_source_id(lock1)
    assert not path.exists()
    fcntl.flock(late, fcntl.LOCK_EX | fcntl.LOCK_NB)  # it gets the lock of the unlinked file...
    assert not _same_file(late, str(path))  # ...and sees that it is not the id's file
    again, lock3, _ = claim_source_id(sid)  # while -2 is held, the first id is free again
    assert again == sid and path.exists()
    os.close(late)
    release_source_id(lock2)
    release_source_id(lock3)
    release_source_id(None)
    assert list(folder.iterdir()) == []
