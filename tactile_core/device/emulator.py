"""A device emulator on a pseudo-terminal: what an array would receive, measured.

``tactile emulate`` opens a pseudo-terminal, prints the path of its device end on the first
line (or, with ``--socket``, listens on a local TCP port and prints its ``socket://`` URL), and
then behaves as the reference firmware does (:class:`~.array.ArrayModel`):
it applies valid frames, answers hello with its info and query with its counters, turns
everything off when no valid frame has arrived for 250 ms (the watchdog, counted when it turns
something off), and counts dropped messages by reason; it also counts gaps in the sequence
numbers and measures the intervals between frames. Timed frames (the scheduled-frame extension)
wait for their time on the emulated array's clock, which starts at 0 when the emulator opens;
the log has each one at the time it was to be played, and the report counts those that came late
or found the queue full and how late the emulator's own loop played the others. When it ends
(Ctrl-C, SIGTERM, ``--seconds``) it prints a report: frames, rate, p50/p99 interval error,
dropped messages, watchdog trips, the last levels; its counters are the ones a status answer
reports. It keeps the latest ``keep_frames`` frames (an hour at 300 Hz by default, 39 bytes a
frame for the palm array: ~42 MB at most), so it can run for days; the interval statistics and
``--log`` cover the frames kept, and the report says how many were let go.
"""

from __future__ import annotations

import os
import select
import socket
import time
import tty
from collections import deque

import numpy as np

from .._shared.jsonfile import write_json_atomic
from .._shared.outfile import atomic_file, check_output
from .array import ArrayModel
from .frame_log import FrameLog
from .profile import DeviceProfile, default_profile

KEEP_FRAMES = 1_080_000
"""Frames the emulator keeps by default: an hour at 300 Hz."""


class Emulator:
    """The array's receiving side, on a pseudo-terminal.

    Parameters
    ----------
    profile : DeviceProfile, optional
        The emulated array (channels, levels, channel order); the palm array by default.
    expected_rate_hz : float, optional
        Nominal frame rate for the interval error; the median interval if not given.
    scheduled : bool
        Speak the scheduled-frame extension (False: a plain format 2 array).
    keep_frames : int
        Frames kept for the log and the interval statistics (the latest ones).
    """

    def __init__(self, profile: DeviceProfile | None = None, expected_rate_hz: float | None = None,
                 *, scheduled: bool = True, keep_frames: int = KEEP_FRAMES):  # fmt: skip
        self.profile = profile or default_profile()
        self.expected_rate_hz = expected_rate_hz
        self.model = ArrayModel(self.profile, scheduled=scheduled)
        self.reader = self.model.reader
        self.master = self.slave = None
        self.listener = None  # the listening socket in socket mode (:meth:`open_socket`)
        self._client = None  # its client's socket
        self.path = None
        self.log = FrameLog(self.profile.channels, keep_frames)
        """Each valid frame: its monotonic time (received, or due if timed), seq, levels in
        channel order."""
        self.events: deque[tuple[float, str]] = deque(maxlen=10_000)  # the latest
        self.unplugged = False
        """Set (from any thread) to close the device as if it were unplugged; the run ends."""
        self.hellos = 0
        self.queries = 0
        self.refused = 0  # clients closed at once because another one was connected
        self.bytes_received = 0
        self.started = None
        # how long after its time each timed frame was played: the latest keep_frames
        self._lag = np.empty(max(1, min(keep_frames, 1 << 24)))
        self._lags = 0

    def open(self) -> str:
        """Create the pseudo-terminal; return the path a client opens."""
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)  # no line discipline: bytes pass unchanged (0x11, 0x13, \\r)
        tty.setraw(self.master)
        os.set_blocking(self.master, False)
        self.path = os.ttyname(self.slave)
        self.started = time.monotonic()
        self.model.epoch = self.started  # the emulated array's clock starts now
        return self.path

    def open_socket(self, host: str = "127.0.0.1", port: int = 0) -> str:
        """Listen on a TCP port instead of a pseudo-terminal; return the ``socket://`` URL a
        client opens. One client at a time; when it goes, the next one may connect.

        Loopback delivers a write in the writer's own context, where a pseudo-terminal hands
        the bytes to a kernel worker that any busy process on the machine can keep waiting:
        over a socket the emulator sees the host's timing as a separate device would.
        """
        listener = socket.create_server((host, port))
        listener.setblocking(False)
        self.listener = listener
        self.path = f"socket://{host}:{listener.getsockname()[1]}"
        self.started = time.monotonic()
        self.model.epoch = self.started
        return self.path

    def _accept(self) -> None:
        try:
            client, _ = self.listener.accept()
        except (BlockingIOError, OSError):
            return
        client.setblocking(False)
        client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._client = client  # (kept: closing the object would close the descriptor)
        self.master = client.fileno()

    def _refuse(self, now: float) -> None:
        """Close a second client at once, as a serial port held by one program refuses
        another: otherwise its connection would complete in the kernel's backlog and its
        frames wait there, unplayed, while it believed them sent."""
        try:
            extra, _ = self.listener.accept()
        except (BlockingIOError, OSError):
            return
        extra.close()
        self.refused += 1
        self.events.append((now, "refused a second client"))

    def _drop_client(self) -> None:
        client, self._client = self._client, None
        self.master = None
        if client is not None:
            client.close()

    def close(self) -> None:
        """Close both ends: a client writing then gets an I/O error. The array's own timing
        (timed frames, the watchdog) is brought up to date first."""
        if self.started is not None:
            now = time.monotonic()
            self._log(self.model.advance(now), now)
            self._watchdog(now)
        if self.listener is not None:
            self._drop_client()
            self.listener.close()
            self.listener = None
            return
        for fd in (self.master, self.slave):
            if fd is not None:
                try:
                    os.close(fd)
                except OSError:
                    pass
        self.master = self.slave = None

    @property
    def current(self) -> bytes:
        """The levels now, in channel order."""
        return self.model.levels

    @property
    def play_lag(self) -> np.ndarray:
        """How long after its time each timed frame (the latest ones) was played, in s."""
        return self._lag[: min(self._lags, len(self._lag))]

    @property
    def watchdog_trips(self) -> int:
        """Watchdog trips so far."""
        return self.model.watchdog_trips

    def _log(self, frames: list, now: float) -> None:
        """Record applied frames: a timed one at the time it was to be played."""
        onsets = {id(msg): (t, late) for t, msg, late in self.model.onsets}
        self.model.onsets.clear()
        for frame in frames:
            at, late = onsets.get(id(frame), (now, True))
            if not late:
                self._lag[self._lags % len(self._lag)] = now - at
                self._lags += 1
            self.log.append(at, frame.seq, frame.levels)

    def _receive(self, data: bytes, now: float) -> None:
        self.bytes_received += len(data)
        replies, frames = self.model.receive(data, now)
        self._log(frames, now)
        if replies:
            self.events.append((now, f"answered {len(replies)} bytes"))
            try:
                os.write(self.master, replies)
            except OSError:
                pass  # no client: the answer is lost, as on a real line

    def _watchdog(self, now: float) -> None:
        last = self.model.last_valid
        if self.model.watchdog(now):
            # logged at the moment the array's watchdog fires, not when this loop (which the
            # host may have kept waiting) noticed: the firmware checks every microsecond
            self.events.append((last + self.model.watchdog_s, "watchdog"))

    def run(self, should_stop, seconds: float | None = None, close_after: float | None = None):
        """Receive until ``should_stop()`` is true or ``seconds`` have passed.

        ``close_after`` closes the pseudo-terminal that many seconds after the first frame
        arrives (for testing how a client copes with a device that goes away mid-stream,
        however long the client took to start) and ends the run.
        """
        if self.master is None and self.listener is None:
            self.open()
        end = None if seconds is None else self.started + seconds
        close_at = None  # close_after from the first frame
        while not should_stop():
            now = time.monotonic()
            if end is not None and now >= end:
                break
            if close_at is None and close_after is not None and len(self.log):
                close_at = now + close_after
            if self.unplugged or (close_at is not None and now >= close_at):
                self.events.append((now, "closed"))
                self.close()
                break
            timeout = 0.05
            due = self.model.due()
            if due is not None:  # wake exactly when the watchdog or a timed frame is due
                timeout = min(timeout, max(due - now, 0.0))
            if self.listener is not None and self.master is None:
                ready, _, _ = select.select([self.listener], [], [], timeout)
                if ready:
                    self._accept()
                ready = []
            elif self.listener is not None:
                ready, _, _ = select.select([self.master, self.listener], [], [], timeout)
                if self.listener in ready:
                    self._refuse(time.monotonic())
                ready = [fd for fd in ready if fd is not self.listener]
            else:
                ready, _, _ = select.select([self.master], [], [], timeout)
            now = time.monotonic()
            if ready:
                try:
                    data = os.read(self.master, 65536)
                except BlockingIOError:
                    data = b""
                except OSError:  # no client has the device end open (EIO): keep listening
                    data = b""
                    if self.listener is not None:
                        self._drop_client()
                    else:
                        time.sleep(0.005)
                else:
                    if not data and self.listener is not None:  # the client went
                        self._drop_client()
                if data:
                    self._receive(data, now)
            now = time.monotonic()
            self._log(self.model.advance(now), now)
            self._watchdog(now)

    def report(self) -> dict:
        """What was received, as a JSON-ready dict."""
        times = self.log.arrays()[0]
        n = len(times)
        intervals = np.diff(times)
        if self.expected_rate_hz:
            period = 1.0 / self.expected_rate_hz
        else:
            period = float(np.median(intervals)) if len(intervals) else 0.0
        errors = np.abs(intervals - period) if len(intervals) else np.zeros(0)
        span = float(times[-1] - times[0]) if n > 1 else 0.0
        cells = np.zeros(self.profile.channels, dtype=int)
        cols, rows = self.profile.layout.wire_shape
        cells[self.profile.array.channel_index] = np.frombuffer(self.current, dtype=np.uint8)
        return {
            "path": self.path,
            "started_monotonic": self.started,
            "frames": len(self.log),
            "frames_kept": n,
            "bytes": self.bytes_received,
            "duration_s": span,
            "rate_hz": (n - 1) / span if span > 0 else 0.0,
            "nominal_period_ms": period * 1e3,
            "interval_error_p50_ms": float(np.percentile(errors, 50) * 1e3) if len(errors) else 0.0,
            "interval_error_p99_ms": float(np.percentile(errors, 99) * 1e3) if len(errors) else 0.0,
            "interval_error_max_ms": float(errors.max() * 1e3) if len(errors) else 0.0,
            "bad_frames": dict(self.reader.errors),
            "crc_errors": self.reader.errors["crc"],
            "dropped": self.model.dropped,
            "frames_applied": self.model.frames_applied,
            "seq_gaps": self.model.seq_gaps,
            "watchdog_trips": self.watchdog_trips,
            "clients_refused": self.refused,
            "timed_late": self.model.late,
            "timed_full": self.model.full,
            "timed_flushed": self.model.flushed,
            "play_lag_p99_ms": (
                float(np.percentile(self.play_lag, 99) * 1e3) if self._lags else 0.0
            ),
            "info": self.model.info.describe(),
            # list() copies in one step: the emulator's thread may append while this is read
            "events": [(round(t - (self.started or 0.0), 6), e) for t, e in list(self.events)],
            "last_levels": cells.reshape(rows, cols)[::-1].tolist(),  # top row first, as seen
        }

    def summary(self) -> str:
        """The report in words (what ``tactile emulate`` prints when it ends)."""
        r = self.report()
        bad = ", ".join(f"{k} {v}" for k, v in r["bad_frames"].items() if v) or "none"
        lines = [
            f"received {r['frames']} frames ({r['bytes']} bytes) in {r['duration_s']:.2f} s: "
            f"{r['rate_hz']:.1f} Hz"
            if r["frames_kept"] == r["frames"]
            else f"received {r['frames']} frames ({r['bytes']} bytes); the latest "
            f"{r['frames_kept']} kept, over {r['duration_s']:.2f} s: {r['rate_hz']:.1f} Hz",
            f"interval error: p50 {r['interval_error_p50_ms']:.3f} ms, "
            f"p99 {r['interval_error_p99_ms']:.3f} ms, max {r['interval_error_max_ms']:.3f} ms "
            f"(nominal {r['nominal_period_ms']:.3f} ms)",
            f"dropped messages: {r['dropped']} ({bad}); sequence gaps: {r['seq_gaps']}",
            f"watchdog trips: {r['watchdog_trips']}"
            + (f"; second clients refused: {r['clients_refused']}" if r["clients_refused"] else ""),
            f"timed frames: late {r['timed_late']}, queue full {r['timed_full']}, dropped "
            f"unplayed {r['timed_flushed']}, played "
            f"p99 {r['play_lag_p99_ms']:.3f} ms after their time",
            f"status counters: frames applied {r['frames_applied']}, messages dropped "
            f"{r['dropped']}, watchdog trips {r['watchdog_trips']}",
            f"identifies as: {r['info']}",
            "last levels (top row first):",
        ]
        lines += ["  " + " ".join(f"{v:2d}" for v in row) for row in r["last_levels"]]
        return "\n".join(lines)

    def save_log(self, path) -> None:
        """The frames kept (every valid frame unless more than ``keep_frames`` came) as CSV:
        ``time,seq,ch0,...`` (seconds from the start, levels in channel order). Watchdog trips
        and closing are in the report's ``events``."""
        times, seqs, levels = self.log.arrays()
        with atomic_file(check_output(path, (), "--log")) as f:
            f.write("time,seq," + ",".join(f"ch{i}" for i in range(self.profile.channels)) + "\n")
            for t, s, lv in zip((times - self.started).tolist(), seqs.tolist(), levels.tolist()):
                f.write(f"{t:.6f},{s}," + ",".join(map(str, lv)) + "\n")

    def save_report(self, path) -> None:
        """The report as JSON."""
        write_json_atomic(path, self.report())
