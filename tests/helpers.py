"""Small helpers for reading frames in tests (independent of the code under test)."""

import numpy as np


def lit(frame, tol=0.0):
    """{(col, row): intensity} of a (rows, cols) frame's tactors above ``tol``."""
    rows, cols = np.nonzero(frame > tol)
    return {(int(c), int(r)): float(frame[r, c]) for r, c in zip(rows, cols)}


def sequence(frames):
    """Ordered distinct (col, row) cells of frames that light exactly one tactor."""
    out = []
    for f in frames:
        (cell,) = lit(f)
        if not out or out[-1] != cell:
            out.append(cell)
    return out


def on_fraction(frames):
    """{(col, row): fraction of frames in which the tactor is on}."""
    n = len(frames)
    counts = (frames > 0).sum(axis=0)
    return {(int(c), int(r)): counts[r, c] / n for r, c in zip(*np.nonzero(counts))}


def align(received, expected):
    """Match each received frame (levels) to the next equal frame of ``expected`` (a later one
    if the streamer skipped deadlines); return the last trace frame index matched."""
    k = -1
    for levels in received:
        for step in range(1, 60):
            if np.array_equal(levels, expected[(k + step) % len(expected)]):
                k += step
                break
        else:
            raise AssertionError(f"frame after trace frame {k} is not a rendering of the core")
    return k


def stop_with(proc, signum, timeout_s=30.0):
    """Send ``signum`` to the subprocess ``proc`` and wait for its end: ``(out, err)``. A
    process still running when the wait fails is killed, so no test leaves one behind."""
    try:
        proc.send_signal(signum)
        return proc.communicate(timeout=timeout_s)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def run_cli_here(capsys, *argv):
    """``tactile ARGV`` in this process (the command line's own code): ``(status, standard
    output, standard error)``, an exit by ``SystemExit`` (argparse) included; fails on a
    traceback."""
    from tactile_core.cli import main

    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    assert "Traceback" not in out.err
    return code, out.out, out.err


def run_cli_last_line(capsys, *argv):
    """:func:`run_cli_here`'s status and the last line of standard error ("" if none)."""
    code, _, err = run_cli_here(capsys, *argv)
    return code, err.strip().splitlines()[-1] if err.strip() else ""


def record_sent(window):
    """Every frame the tuner's stream sends from now on, as channel levels (a list of numpy
    arrays that grows). Polling ``sent_levels()`` sees only the newest frame: a pulse shorter
    than a loaded machine's gap between two polls is missed. Needs a window that streams from
    a thread (``process=False``)."""
    frames = []
    window.device.streamer.taps.append(
        lambda _t, _seq, levels: frames.append(np.frombuffer(levels, np.uint8))
    )
    return frames


def dealt(methods, seed):
    """The methods on keys 1-N of a blind A/B session with ``seed``, dealt as docs/tuner.md
    says an autosave's mapping is recovered: ``random.Random(seed).shuffle``."""
    import random

    mapping = list(methods)
    random.Random(seed).shuffle(mapping)
    return mapping


def stream_threads():
    """Names of the running threads of streams and servers (``tactile-*``). A trace's table is
    built by a daemon thread of its own (``tactile-precompute``) that nothing waits for; one a
    previous test left is not a leak."""
    import threading

    return [t.name for t in threading.enumerate()
            if t.name.startswith("tactile-") and not t.name.endswith("-precompute")]  # fmt: skip


def array_status(path: str, seq: int = 9, timeout_s: float = 10.0):
    """An array's answer to a status query (its counters: frames applied, dropped, watchdog
    trips), asked on ``path`` (the firmware in simavr, ``tactile emulate``). It answers in the
    order it reads its line: after everything written before. A query does not feed the
    watchdog (only a valid frame does)."""
    import time

    from tactile_core.device.link import SerialLink
    from tactile_core.device.wire import MessageReader, Status, encode_query

    link = SerialLink(path)
    try:
        reader = MessageReader(accept=(Status,))
        link.write(encode_query(seq))
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            got = reader.feed(link.read())
            if got:
                return got[-1]
            time.sleep(0.005)  # polling the link (a bound of timeout_s above)
    finally:
        link.close()
    raise AssertionError(f"no status answer within {timeout_s:g} s")
