"""The live features broken as an operator would break them (LSL outlets that cannot open or
share a source id, the scripting API used wrongly, OSC senders that dodge the rate limit): each
is refused with one line naming what was wrong, or handled, and nothing is left running."""

import os
import threading
import time
import uuid

import pylsl
import pytest

import tactile_core as tc
from tactile_core.device.profile import ProfileError, default_profile
from tactile_core.serve import LslError, LslOutlets

from .helpers import run_cli_here


def run_cli(capsys, *argv, stdout=None):
    """``(status, standard error)``; standard output appended to ``stdout`` if given."""
    code, out, err = run_cli_here(capsys, *argv)
    if stdout is not None:
        stdout.append(out)
    return code, err


def stream_threads():
    """Threads of streams and servers. A trace's table is built by a daemon thread of its own
    (``tactile-precompute``) that nothing waits for; one a previous test left is not a leak."""
    return [t.name for t in threading.enumerate()
            if t.name.startswith("tactile-") and not t.name.endswith("-precompute")]  # fmt: skip


@pytest.fixture
def outlets_refused(monkeypatch):
    """liblsl that cannot open an outlet (no free port, no network interface)."""

    def refuse(*args, **kwargs):
        raise RuntimeError("could not create stream outlet.")

    monkeypatch.setattr(pylsl, "StreamOutlet", refuse)


# --- Lab Streaming Layer -----------------------------------------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ["stream", "--shape", "circle:2.5,3,2", "--method", "AS", "--seconds", "5"],
        ["serve", "--osc-port", "0", "--seconds", "5", "--status-s", "0"],
    ],
)
def test_lsl_that_cannot_open_an_outlet_is_one_line_and_exit_1(capsys, outlets_refused, argv):
    """Was a traceback ending in pylsl's 'could not create stream outlet.'; now the command
    says so before it opens the device, and nothing streams."""
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
    recorder finds a lost stream again by: the second is now SID-2, and says why."""
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


# --- the scripting API -------------------------------------------------------------------------


@pytest.mark.parametrize("cut", ["all_off", "play"])
def test_waiting_for_a_presentation_cut_short_before_its_first_frame_returns_at_once(cut):
    """wait() waited 5 s, then raised 'no frame went out' with the stream's status, for a
    presentation that was only replaced or turned off before its first frame."""
    with tc.open_array("sim") as array:
        shown = array.play("circle:2.5,3,2", duration_s=1.0, wait=False)
        if cut == "all_off":
            array.all_off()
        else:
            array.play("line:0.5,0.5,4.5,5.5", duration_s=0.05, wait=False)
        start = time.monotonic()
        assert shown.wait() is shown
        assert time.monotonic() - start < 2.0  # not the 5 s start timeout
        assert shown.interrupted and shown.done.is_set()


def test_a_closed_array_refuses_points_as_it_refuses_play():
    """point() after close() did nothing and said nothing: the script believed a point on."""
    array = tc.open_array("sim")
    array.close()
    # its threads are gone when close() returns (the keeper used to linger: under load the
    # next test found it still running)
    assert not array._keeper.is_alive() and not array.streamer.running
    array.close()  # twice: nothing happens
    for call in (lambda: array.point(2.5, 3.0), lambda: array.play("circle:2.5,3,2"),
                 array.__enter__):  # fmt: skip
        with pytest.raises(ValueError, match="the array is closed"):
            call()
    array.release()  # harmless: all is off already
    array.all_off()
    assert not array.streamer.running


def test_open_array_names_its_own_arguments():
    with pytest.raises(ProfileError, match="device profile must be a name, a path"):
        tc.open_array("sim", profile=5)
    with pytest.raises(ValueError, match=r"^point_timeout_s must be within"):
        tc.open_array("sim", point_timeout_s=-1)
    assert stream_threads() == []


# --- OSC ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("address", ["/tactile/offset", "/tactile/release_everything"])
def test_serve_flood_guard_reads_only_the_exact_off_and_release_addresses(address):
    """Every datagram starting with the bytes '/tactile/off' or '/tactile/release' was read
    whatever the rate: a flood of '/tactile/offset' went round the limit."""
    from pythonosc.osc_message_builder import OscMessageBuilder

    from .serve_support import ServerRig

    with ServerRig(max_rate_hz=100.0) as rig:  # a bucket of 5 messages
        sock = rig.client._sock
        junk = OscMessageBuilder(address).build().dgram
        for _ in range(200):
            sock.sendto(junk, rig.server.address)
        sock.sendto(OscMessageBuilder("/tactile/off").build().dgram, rig.server.address)
        rig.wait_count("controls", 1)
        s = rig.server.stats
        assert s.flood_dropped > 100
        assert s.unknown + s.flood_dropped == s.datagrams - 1


def test_serve_prints_an_ipv6_address_as_a_url(capsys):
    """The first line was osc://::1:9100, which no URL parser splits into host and port."""
    import socket

    try:
        with socket.socket(socket.AF_INET6, socket.SOCK_DGRAM) as probe:
            probe.bind(("::1", 0))
    except OSError:
        pytest.skip("no IPv6 loopback on this machine")
    out = []
    code, _ = run_cli(capsys, "serve", "--device", "sim", "--host", "::1", "--osc-port", "0",
                      "--seconds", "0.1", "--status-s", "0", stdout=out)  # fmt: skip
    assert code == 0
    first = out[0].splitlines()[0]
    assert first.startswith("osc://[::1]:") and int(first.rsplit(":", 1)[1]) > 0


def test_serve_refuses_an_empty_host(capsys):
    code, err = run_cli(capsys, "serve", "--device", "sim", "--host", "", "--osc-port", "0")
    assert code == 2 and "--host" in err and "Name or service" not in err


def test_serve_on_a_layout_profile_starts_with_its_default_method(capsys):
    """`tactile serve --profile belt-8` refused its own default method (AS needs a grid); the
    default is now BA there, AS's weights for any layout, as the tuner falls back to."""
    code, err = run_cli(capsys, "serve", "--device", "sim", "--profile", "belt-8",
                        "--osc-port", "0", "--seconds", "0.1", "--status-s", "0")  # fmt: skip
    assert code == 0 and "serving belt-8 (BA," in err
    code, err = run_cli(capsys, "serve", "--device", "sim", "--profile", "belt-8",
                        "--method", "AS", "--osc-port", "0")  # fmt: skip
    assert code == 2 and "method AS cannot render on this layout" in err


def test_serve_summary_escapes_what_a_sender_wrote_for_the_terminal():
    """A sender's method name (or address) went raw into the summary printed on the operator's
    terminal: ESC sequences in one could clear it or retitle it."""
    from .serve_support import ServerRig

    with ServerRig() as rig:
        rig.send("/tactile/method", "\x1b[2J\x1b]0;owned\x07")
        rig.wait_count("refused", 1)
        rig.send("/\x1b[31mred", 1.0)
        rig.wait_count("unknown", 1)
        summary = rig.server.stats.summary()
    assert "\x1b" not in summary and "\x07" not in summary
    assert "last problem: unknown address /\\x1b[31mred" in summary


def test_a_device_lost_while_a_presentation_plays_fails_its_wait_and_the_next_play():
    """wait() returned as if the stimulus had played when the device went away under it (a
    trial recorded as presented), and the next play() waited 5 s before saying why."""
    from tactile_core.device.link import LinkError

    with tc.open_array("sim") as array:
        shown = array.play("circle:2.5,3,2", duration_s=30.0, wait=False)
        assert shown.started.wait(5)

        def unplugged(data):
            raise LinkError("device disconnected: sim (unplugged in a test)")

        array.link.write = unplugged
        start = time.monotonic()
        with pytest.raises(RuntimeError, match=r"stopped before the stimulus had played.*unplug"):
            shown.wait()
        assert shown.interrupted and "unplugged" in shown.failed
        with pytest.raises(RuntimeError, match=r"the stream has stopped: .*unplugged"):
            array.play("line:0.5,0.5,4.5,5.5", duration_s=0.1)
        with pytest.raises(RuntimeError, match="the stream has stopped"):
            array.point(2.5, 3.0)
        assert time.monotonic() - start < 4.0  # at once, not after the 5 s start timeout


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


def test_serve_json_that_cannot_be_written_names_the_file(capsys, tmp_path, monkeypatch):
    """A full disk at the end said 'tactile serve: error: No space left on device', naming no
    file; the counters printed above it stand."""
    import errno

    from tactile_core.cli import _serve

    def full(path, data):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(_serve, "write_json_atomic", full)
    out = []
    json_path = tmp_path / "c.json"
    code, err = run_cli(capsys, "serve", "--device", "sim", "--osc-port", "0", "--seconds", "0.1",
                        "--status-s", "0", "--json", json_path, stdout=out)  # fmt: skip
    assert code == 1 and f"cannot write --json {tmp_path / 'c.json'}: No space left" in err
    assert "served " in out[0]


def test_an_emulators_report_may_be_read_while_its_thread_logs_events():
    # report() iterated the events deque that the emulator's thread appends to (an answer to
    # every status query); a report read meanwhile raised "deque mutated during iteration".
    from tactile_core.device.emulator import Emulator

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
