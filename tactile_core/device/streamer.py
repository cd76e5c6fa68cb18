"""The real-time streamer: one output thread sending frames to a link on deadlines.

Per frame the thread takes the current :class:`~tactile_core.Scene` snapshot, computes
the lit tactors' corrected intensities (:class:`~tactile_core.LiveFrames`), applies the
device's per-tactor calibration, quantises (optionally with temporal dithering), orders the
levels by channel, encodes the frame and writes it. Deadlines come from a monotonic clock
(``k / rate`` after the start, never ``sleep(period)``, which drifts); the thread sleeps until
shortly before each deadline and spins the last fraction of a millisecond.

The array must never be left buzzing. The streamer sends an all-zero frame when it stops, when
the scene pauses or goes idle, on any error path (``finally``), and at interpreter exit
(``atexit``); the command line adds signal handlers. While connected and idle it keeps sending
zero frames at ``idle_rate_hz`` (>= 10 Hz) so the array's 250 ms watchdog never trips while the
host is alive. The requested rate is capped at what the link carries (``baud / 10 / frame
bytes``: 320 Hz for the palm array at 115200 baud), and the status says so.
"""

from __future__ import annotations

import atexit
import ctypes
import math
import os
import sys
import threading
import time
import traceback
import weakref
from dataclasses import dataclass

import numpy as np

from ..rendering.correction import Dither, quantize1
from ..rendering.scene import Scene, check_scene
from .link import LinkError, identify
from .profile import DeviceProfile, default_profile
from .wire import KEEPALIVE_S, Info, MessageReader, Status, encode_frame, encode_query

_RUNNING: weakref.WeakSet = weakref.WeakSet()


@atexit.register
def _stop_all() -> None:
    """Interpreter exit: stop every running streamer (each sends its all-off frame)."""
    for streamer in list(_RUNNING):
        streamer.stop(timeout=1.0)


def _reduce_timer_slack() -> None:
    """Linux: wake this thread within ~1 us of the requested time instead of ~50 us."""
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None).prctl(29, 1000, 0, 0, 0)  # PR_SET_TIMERSLACK, 1 us
        except (OSError, AttributeError):
            pass


def _raise_priority() -> str:
    """Try to give the calling thread real-time priority (SCHED_FIFO 10); say what happened.

    Linux grants it to root or to users with an ``rtprio`` limit (``ulimit -r``, or
    ``/etc/security/limits.conf``). The output thread sleeps most of each frame and spins at most
    ``spin_s``, so it cannot starve the machine.
    """
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(10))
    except AttributeError:
        return "real-time priority is not available on this system"
    except PermissionError:
        return "real-time priority not permitted (raise the rtprio limit: ulimit -r 10)"
    except OSError as exc:
        return f"real-time priority failed: {exc}"
    return ""


@dataclass(frozen=True)
class StreamStats:
    """A snapshot of the streamer's statistics.

    Attributes
    ----------
    state : str
        ``"starting"``, ``"streaming"``, ``"paused"``, ``"idle"``, ``"disconnected"``,
        ``"stopped"``, ``"refused"`` (the array is not the profile's) or ``"failed"`` (an
        internal error ended the stream; the array was turned off).
    status : str
        One line for the user (what happened last, e.g. why the stream stopped).
    requested_rate_hz, rate_hz : float
        Rate the scene asks for and rate in use (capped by the link).
    capped : bool
        True when the link cannot carry the requested rate.
    frames, bytes, errors : int
        Frames and bytes written, and link errors.
    late : int
        Frames written more than 1 ms after their deadline.
    skipped : int
        Deadlines passed over after a stall of more than one frame (the trace stays on time).
    achieved_rate_hz : float
        Frames per second over the last second.
    interval_error_p50_ms, interval_error_p99_ms : float
        Median and 99th percentile of ``|interval - period|`` between successive frames at a
        steady rate (last 8192 intervals).
    elapsed_s : float
        Seconds since the thread started.
    realtime : bool
        True when the output thread runs with real-time priority.
    array : str
        What the array said it is (its info), or why not ("unidentified: ...").
    array_frames, array_dropped, array_watchdog_trips : int
        The array's own counters from its last status answer (-1 before any): frames applied,
        messages dropped, watchdog trips.
    """

    state: str = "stopped"
    status: str = ""
    requested_rate_hz: float = 0.0
    rate_hz: float = 0.0
    capped: bool = False
    frames: int = 0
    bytes: int = 0
    errors: int = 0
    late: int = 0
    skipped: int = 0
    achieved_rate_hz: float = 0.0
    interval_error_p50_ms: float = 0.0
    interval_error_p99_ms: float = 0.0
    elapsed_s: float = 0.0
    realtime: bool = False
    array: str = ""
    array_frames: int = -1
    array_dropped: int = -1
    array_watchdog_trips: int = -1

    def summary(self) -> str:
        """Multi-line human summary (what ``tactile stream`` prints at the end)."""
        cap = " (capped by the link)" if self.capped else ""
        return "\n".join(
            [
                f"state:           {self.state} - {self.status}",
                f"rate:            {self.rate_hz:.1f} Hz "
                f"(requested {self.requested_rate_hz:g} Hz){cap}",
                f"achieved:        {self.achieved_rate_hz:.1f} Hz over the last second",
                f"frames:          {self.frames} ({self.bytes} bytes) in {self.elapsed_s:.2f} s",
                f"interval error:  p50 {self.interval_error_p50_ms:.3f} ms, "
                f"p99 {self.interval_error_p99_ms:.3f} ms",
                f"late (>1 ms):    {self.late}, skipped deadlines: {self.skipped}",
                f"link errors:     {self.errors}",
                f"priority:        {'real-time' if self.realtime else 'normal'}",
                f"array:           {self.array or '-'}",
                (
                    f"array counters:  frames applied {self.array_frames}, messages dropped "
                    f"{self.array_dropped}, watchdog trips {self.array_watchdog_trips}"
                    if self.array_frames >= 0
                    else "array counters:  not reported"
                ),
            ]
        )


class _Plan:
    """What the output thread derived from one scene: frames, rate, period."""

    def __init__(self, scene: Scene | None, profile: DeviceProfile, idle_rate_hz: float):
        self.scene = scene
        self.requested = scene.rate_hz if scene is not None else idle_rate_hz
        self.active = scene is not None and scene.active
        if self.active:
            self.rate = min(scene.rate_hz, profile.max_rate_hz)
            self.capped = scene.rate_hz > profile.max_rate_hz
            self.live = scene.live(profile.grid, self.rate)
        else:
            self.rate = idle_rate_hz
            self.capped = False
            self.live = None
        # Felt-amplitude correction: the drive is the motor response's inverse of the value.
        self.inverse = (profile.drive_for1 if self.active and scene.felt_domain
                        and profile.response is not None else None)  # fmt: skip
        self.period = 1.0 / self.rate
        # At any rate a frame goes out at least every KEEPALIVE_S (repeating the last one), so
        # the array's 250 ms watchdog never trips while the host is alive.
        self.tick = min(self.period, KEEPALIVE_S)
        self.since = time.perf_counter()
        self.precompute_started = False
        self.last_k = None
        self.last_levels = None


class Streamer:
    """Streams a scene to a link at a fixed rate from one output thread.

    Parameters
    ----------
    link : SerialLink or SimulatedArray
        Where frames go (``write`` / ``reopen`` / ``close``).
    profile : DeviceProfile, optional
        The array (grid, levels, channel order, calibration, baud); the palm array by default.
    scene : Scene, optional
        Initial scene; idle (all off) if None.
    taps : sequence of callables, optional
        Called after each successful write as ``tap(time_s, seq, levels)``: monotonic time,
        sequence number and the channel-ordered levels (``bytes``). The recorder is one.
    on_status : callable, optional
        Called as ``on_status(stats)`` from the output thread whenever the state or status
        changes (a GUI must hand it to its own thread).
    idle_rate_hz : float
        Rate of the all-zero keep-alive frames while paused or idle (>= 10 Hz).
    spin_s : float
        The last part of each wait is a busy spin of at most this long, for sub-100-us timing.
    reconnect : bool
        After a link error, retry every ``reconnect_interval_s`` instead of stopping.
    switch_interval_s : float or None
        While streaming, the interpreter's thread switch interval (``sys.setswitchinterval``)
        is lowered to this so the output thread gets the GIL back quickly from a busy GUI
        thread; restored on stop. None leaves it alone.
    realtime : bool
        Ask for real-time scheduling (SCHED_FIFO) of the output thread, so that other busy
        processes cannot delay a frame (Linux, with privileges; the status says if refused).
    identify : bool
        On connecting (and reconnecting), send a hello and check the array's info against the
        profile: a mismatch refuses to stream (state ``"refused"``); no answer within 0.5 s is
        an array that does not identify itself, which is driven anyway and reported so.

    Examples
    --------
    >>> from tactile_core.device.link import SimulatedArray
    >>> from tactile_core.rendering.scene import Scene
    >>> import tactile_core as tc
    >>> with Streamer(SimulatedArray(), scene=Scene(tc.Circle((2.5, 3), 2))) as s:
    ...     time.sleep(0.1)
    >>> s.stats.frames > 10
    True
    """

    def __init__(
        self,
        link,
        profile: DeviceProfile | None = None,
        *,
        scene: Scene | None = None,
        taps=(),
        on_status=None,
        idle_rate_hz: float = 20.0,
        spin_s: float = 0.0003,
        reconnect: bool = False,
        reconnect_interval_s: float = 0.5,
        switch_interval_s: float | None = 0.0005,
        realtime: bool = False,
        identify: bool = True,
    ):
        if not 10.0 <= idle_rate_hz <= 1000.0:
            raise ValueError(f"idle_rate_hz must be within [10, 1000], got {idle_rate_hz!r}")
        self.link = link
        self.profile = profile or default_profile()
        self._scene = scene
        self.taps = list(taps)
        self.on_status = on_status
        self.idle_rate_hz = idle_rate_hz
        self.spin_s = spin_s
        self.reconnect = reconnect
        self.reconnect_interval_s = reconnect_interval_s
        self.switch_interval_s = switch_interval_s
        self.realtime = realtime
        self.identify = identify
        self.array_info: Info | None = None
        """The array's answer to the hello (None: not asked, or no answer)."""
        self.array_status: Status | None = None
        """The array's last status answer."""
        self._replies = MessageReader(accept=(Info, Status))
        self.identified = threading.Event()
        """Set once the hello is answered or given up on (or the thread ended): the stream's
        duration counts from here."""
        self._failure = ""
        self.failure_traceback = ""
        """The traceback of an internal error in the output thread (its status says what)."""
        self._query_seq = 0
        self._query_wanted = threading.Event()
        self._status_arrived = threading.Condition()
        self._priority_note = ""
        self._wake = threading.Event()
        self._stopping = threading.Event()
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()
        self._intervals = np.zeros(8192)
        self._n_intervals = 0
        self._recent: list[float] = []
        self._stats = StreamStats(state="starting", status="not started")
        self._counts = {"frames": 0, "bytes": 0, "errors": 0, "late": 0, "skipped": 0}
        self._started_at = None
        self._saved_switch = None
        self.last_levels = np.zeros(self.profile.grid.shape, dtype=np.uint8)
        """Levels of the last frame written, ``(rows, cols)`` uint8, for display."""
        self.last_frame = (None, None)
        """``(scene, trace_time_s)`` of the last frame written (time None while off), one
        tuple assigned at once so a reader on another thread sees a consistent pair."""
        self.last_seq = None
        channel_of_cell = np.empty(self.profile.channels, dtype=np.intp)
        channel_of_cell[self.profile.array.channel_index] = np.arange(self.profile.channels)
        self._channel_of_cell = channel_of_cell.tolist()
        self._cell_of_channel = self.profile.array.channel_index
        self._offset = None if self.profile.offset is None else list(self.profile.offset)
        self._gain = None if self.profile.gain is None else list(self.profile.gain)

    # --- control (any thread) ------------------------------------------------------------------

    def start(self) -> Streamer:
        """Start the output thread (idempotent)."""
        if self._thread is not None and self._thread.is_alive():
            return self
        self._stopping.clear()
        if self.switch_interval_s is not None:
            self._saved_switch = sys.getswitchinterval()
            sys.setswitchinterval(self.switch_interval_s)
        self._thread = threading.Thread(target=self._run, name="tactile-stream", daemon=True)
        _RUNNING.add(self)
        self._thread.start()
        return self

    def stop(self, timeout: float = 2.0) -> StreamStats:
        """Stop the thread (it sends the all-off frame) and return the final statistics."""
        self._stopping.set()
        self._wake.set()
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout)
        _RUNNING.discard(self)
        if self._saved_switch is not None:
            sys.setswitchinterval(self._saved_switch)
            self._saved_switch = None
        return self.stats

    def __enter__(self) -> Streamer:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    @property
    def running(self) -> bool:
        """True while the output thread is alive."""
        return self._thread is not None and self._thread.is_alive()

    @property
    def scene(self) -> Scene | None:
        """The current scene snapshot."""
        return self._scene

    def set_scene(self, scene: Scene | None) -> None:
        """Swap in a new scene; the output thread uses it from its next frame."""
        check_scene(scene)
        self._scene = scene
        self._wake.set()

    def all_off(self) -> None:
        """Pause at once: the next frame, sent immediately, is all zeros."""
        scene = self._scene
        self.set_scene(None if scene is None else scene.replace(playing=False))

    def query_status(self, timeout_s: float = 0.5) -> Status | None:
        """Ask the array for its counters (the output thread sends the query after its next
        frame) and wait up to ``timeout_s`` for the answer; None if none came."""
        with self._status_arrived:
            before = self.array_status
            self._query_wanted.set()
            self._wake.set()
            self._status_arrived.wait_for(
                lambda: self.array_status is not before or not self.running, timeout_s
            )
            return self.array_status if self.array_status is not before else None

    @property
    def stats(self) -> StreamStats:
        """A snapshot of the statistics."""
        with self._lock:
            stats = StreamStats(**{**self._stats.__dict__, **self._counts})
            n = min(self._n_intervals, len(self._intervals))
            errors = self._intervals[:n].copy()
            recent = list(self._recent)
        now = time.perf_counter()
        recent = [t for t in recent if now - t <= 1.0]
        p50, p99 = (np.percentile(errors, [50, 99]) * 1e3) if n else (0.0, 0.0)
        elapsed = now - self._started_at if self._started_at and self.running else stats.elapsed_s
        if len(recent) > 1:
            achieved = (len(recent) - 1) / (recent[-1] - recent[0])
        else:
            achieved = 0.0
        return StreamStats(
            **{
                **stats.__dict__,
                "achieved_rate_hz": achieved,
                "interval_error_p50_ms": float(p50),
                "interval_error_p99_ms": float(p99),
                "elapsed_s": elapsed,
            }
        )

    # --- output thread -------------------------------------------------------------------------

    def _count(self, name: str, n: int = 1) -> None:
        with self._lock:
            self._counts[name] += n

    def _set(self, **changes) -> None:
        with self._lock:
            old = self._stats
            self._stats = StreamStats(**{**old.__dict__, **changes})
        if self.on_status is not None and (
            changes.get("state", old.state) != old.state
            or changes.get("status", old.status) != old.status
        ):
            try:
                self.on_status(self.stats)
            except Exception:  # a faulty observer must not stop the array from going off
                pass

    def _wait_until(self, deadline: float) -> bool:
        """Sleep until ``deadline`` (perf_counter seconds); True if woken by a scene change."""
        while True:
            remaining = deadline - time.perf_counter()
            if remaining <= 0.0:
                return False
            if remaining > self.spin_s:
                if self._wake.wait(remaining - self.spin_s):
                    self._wake.clear()
                    return True
            else:
                while time.perf_counter() < deadline:
                    pass
                return False

    def _levels(self, plan: _Plan, k: int, dither: Dither | None, lit_before: set) -> tuple:
        """Channel-ordered levels of frame ``k`` and the set of lit channels."""
        n = self.profile.channels
        levels = bytearray(n)
        lit = set()
        if plan.live is None:
            return levels, lit
        top = self.profile.levels - 1
        offset, gain = self._offset, self._gain
        channel_of_cell = self._channel_of_cell
        inverse = plan.inverse
        for cell, value in plan.live.entries(k):
            if inverse is not None:
                value = inverse(value)
            if offset is not None:
                value = min(max(offset[cell] + gain[cell] * value, 0.0), 1.0)
            ch = channel_of_cell[cell]
            level = dither.level1(ch, value) if dither is not None else quantize1(value, top + 1)
            levels[ch] = level
            lit.add(ch)
        if dither is not None:
            for ch in lit_before - lit:
                dither.residual[ch] = 0.0
        return levels, lit

    def _write(self, seq: int, levels: bytes) -> float:
        data = encode_frame(seq, levels)
        self.link.write(data)
        now = time.perf_counter()
        flat = np.zeros(self.profile.channels, dtype=np.uint8)
        flat[self._cell_of_channel] = np.frombuffer(bytes(levels), dtype=np.uint8)
        self.last_levels = flat.reshape(self.profile.grid.shape)
        self.last_seq = seq & 0xFF
        with self._lock:
            self._counts["frames"] += 1
            self._counts["bytes"] += len(data)
            self._recent.append(now)
            if len(self._recent) > 4 * 1024:
                del self._recent[: len(self._recent) - 2048]
        for tap in self.taps:
            tap(now, seq & 0xFF, bytes(levels))
        return now

    def _poll_replies(self) -> None:
        """Read what the array sent (info and status answers) without waiting."""
        data = self.link.read()
        if not data:
            return
        for msg in self._replies.feed(data):
            if isinstance(msg, Status):
                with self._status_arrived:
                    self.array_status = msg
                    self._status_arrived.notify_all()
                self._set(
                    array_frames=msg.frames_applied,
                    array_dropped=msg.dropped,
                    array_watchdog_trips=msg.watchdog_trips,
                )

    def _send_query(self) -> None:
        self._query_seq = (self._query_seq + 1) & 0xFF
        self.link.write(encode_query(self._query_seq))

    def _identify(self) -> bool:
        """Hello and check; False (state refused) when the array is not the profile's."""
        if not self.identify:
            return True
        self._set(state="starting", status=f"identifying the array on {self.link.description}")
        info, problem = identify(self.link, self.profile)
        self.array_info = info
        if problem:
            self._set(state="refused", status=problem, array=info.describe())
            return False
        if info is None:
            self._set(
                array=(
                    "unidentified: no answer to hello within 0.5 s; driven as "
                    f"{self.profile.name} ({self.profile.grid.cols} x {self.profile.grid.rows}, "
                    f"{self.profile.levels} levels)"
                )
            )
        else:
            self._set(array=info.describe())
        return True

    def _record_interval(self, error_s: float) -> None:
        with self._lock:
            self._intervals[self._n_intervals % len(self._intervals)] = abs(error_s)
            self._n_intervals += 1

    def _describe(self, plan: _Plan) -> tuple[str, str]:
        if plan.scene is None:
            return "idle", f"idle: all off, keep-alive at {plan.rate:g} Hz"
        if not plan.scene.playing:
            return "paused", f"paused: all off, keep-alive at {plan.rate:g} Hz"
        if plan.capped:
            return "streaming", (
                f"streaming {plan.scene.method} at {plan.rate:.0f} Hz: {plan.requested:g} Hz "
                f"requested, the link carries {self.profile.max_rate_hz:.0f} frames/s "
                f"({self.profile.baud} baud, {self.profile.frame_bytes} bytes per frame)"
            )
        note = f" ({self._priority_note})" if self._priority_note else ""
        return "streaming", (
            f"streaming {plan.scene.method} at {plan.rate:g} Hz to {self.link.description}{note}"
        )

    def _run(self) -> None:
        _reduce_timer_slack()
        if self.realtime:
            self._priority_note = _raise_priority()
            self._set(realtime=not self._priority_note)
        self._started_at = time.perf_counter()
        seq = 0
        plan = None
        dither = None
        lit: set = set()
        trace_time = 0.0  # seconds into the trace clock (advances only while playing)
        try:
            try:
                if not self._identify():
                    return
            except LinkError as exc:
                self._count("errors")
                self._set(state="disconnected", status=str(exc))
                if not self._recover():
                    return
            finally:
                self.identified.set()
            deadline = time.perf_counter()
            last_sent = None
            while not self._stopping.is_set():
                scene = self._scene
                if plan is None or scene is not plan.scene:
                    try:
                        new = _Plan(scene, self.profile, self.idle_rate_hz)
                    except ValueError as exc:  # cannot render this scene: go idle, say why
                        new = _Plan(None, self.profile, self.idle_rate_hz)
                        self._set(status=f"scene rejected: {exc}")
                    restart = (
                        plan is None
                        or plan.scene is None
                        or scene is None
                        or scene.shape != plan.scene.shape
                        or scene.epoch != plan.scene.epoch
                    )
                    if restart:
                        trace_time = 0.0
                    immediate = plan is not None and (
                        new.active != plan.active or new.tick != plan.tick
                    )
                    plan = new
                    dither = (
                        Dither(self.profile.channels, self.profile.levels)
                        if (plan.active and plan.scene.dither)
                        else None
                    )
                    lit = set()
                    state, status = self._describe(plan)
                    self._set(
                        state=state,
                        status=status,
                        requested_rate_hz=plan.requested,
                        rate_hz=plan.rate,
                        capped=plan.capped,
                    )
                    last_sent = None
                    if immediate:
                        deadline = time.perf_counter()
                stable = time.perf_counter() - plan.since > 0.2
                if plan.live is not None and not plan.precompute_started and stable:
                    plan.precompute_started = True  # the scene settled: tabulate its cycle
                    plan.live.precompute(background=True)

                if self._wait_until(deadline):
                    continue  # a new scene arrived while waiting: pick it up first
                if plan.tick == plan.period:
                    k = round(trace_time * plan.rate)
                else:  # keep-alive ticks between frames repeat the frame
                    k = math.floor(trace_time * plan.rate + 1e-9)
                if k != plan.last_k:
                    levels, lit = self._levels(plan, k, dither, lit)
                    plan.last_k, plan.last_levels = k, levels
                levels = plan.last_levels
                try:
                    sent = self._write(seq, levels)
                    self.last_frame = (plan.scene, k / plan.rate if plan.active else None)
                    if self._query_wanted.is_set():
                        self._query_wanted.clear()
                        self._send_query()
                    self._poll_replies()
                except LinkError as exc:
                    self._count("errors")
                    self._set(state="disconnected", status=str(exc))
                    if not self._recover():
                        return
                    deadline = time.perf_counter()
                    last_sent = None
                    continue
                seq += 1
                lateness = sent - deadline
                if lateness > 1e-3:
                    self._count("late")
                if last_sent is not None:
                    self._record_interval(sent - last_sent - plan.tick)
                last_sent = sent
                if plan.active:
                    trace_time += plan.tick
                deadline += plan.tick
                behind = time.perf_counter() - deadline
                if behind > plan.tick:  # stalled: skip missed deadlines, keep trace time
                    missed = math.floor(behind / plan.tick)
                    deadline += missed * plan.tick
                    if plan.active:
                        trace_time += missed * plan.tick
                    self._count("skipped", missed)
                    last_sent = None
        except Exception as exc:  # a bug must still end with the array off, and say so
            self._failure = f"internal error: {type(exc).__name__}: {exc}"
            self.failure_traceback = traceback.format_exc()
            self._set(state="failed", status=self._failure)
        finally:
            self._all_off_final(seq)

    def _recover(self) -> bool:
        """After a link error: reconnect (True) or give up (False)."""
        if not self.reconnect:
            self._set(state="stopped", status=f"stopped: {self._stats.status}")
            return False
        while not self._stopping.wait(self.reconnect_interval_s):
            try:
                self.link.reopen()
                if not self._identify():
                    return False
            except LinkError as exc:
                self._set(status=f"reconnecting: {exc}")
                continue
            self._set(state="streaming", status=f"reconnected to {self.link.description}")
            return True
        return False

    def _all_off_final(self, seq: int) -> None:
        zeros = bytes(self.profile.channels)
        try:
            self._write(seq, zeros)
            if self.array_info is not None:  # an array that answers: read its counters
                self._send_query()
                deadline = time.perf_counter() + 0.3
                seen = self.array_status
                while time.perf_counter() < deadline and self.array_status is seen:
                    self._poll_replies()
                    time.sleep(0.002)
        except LinkError:
            pass  # the link is gone: the array's watchdog turns it off within 250 ms
        except Exception:
            pass
        finally:
            state, status = self._stats.state, self._stats.status
            if self._failure:
                state, status = "failed", f"{self._failure}; all off"
            elif state != "refused":
                status = status if state == "stopped" else "stopped: all off"
                state = "stopped"
            self._set(state=state, status=status, elapsed_s=time.perf_counter() - self._started_at)
            self.identified.set()
            with self._status_arrived:
                self._status_arrived.notify_all()
