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
bytes``: 311 Hz for the palm array at 115200 baud, 37 bytes a frame), and the status says so.

With a lead (``lead_s`` > 0) and an array that announces scheduled frames, each frame goes out
timed: to be played ``lead_s`` after its deadline on the array's own clock, which the host keeps
from clock exchanges. The host's scheduler then only has to get each frame there within the
lead; the array's timer decides when it reaches the motors. Pausing, all-off and the final
frame stay frames for now (they also drop what is scheduled). An array without the extension is
driven with frames for now, and the status says so. A host that stops running the thread
(SIGSTOP, a VM pause) finds it skipping the deadlines it missed, and the pause is reported.

Here is the thread; its statistics in ``_stats``, what it derives from a scene in ``_plan``,
and what it says to the array besides frames (hello, counters, the clock) in ``_talk``.
"""

from __future__ import annotations

import atexit
import sys
import threading
import traceback
import weakref

import numpy as np

from .._shared import validate as _validate
from ..device.host_clock import HostClock, raise_priority
from ..device.link import LinkError
from ..device.profile import DeviceProfile, default_profile
from ..device.wire import Info, Status, encode_frame, encode_timed, level_bits
from ..rendering.correction import Dither
from ..rendering.scene import Scene, check_scene
from ._onsets import Onset, OnsetWatch
from ._plan import Cursor, _ChannelLevels, _Plan, _reduce_timer_slack, restarts
from ._stats import PAUSE_S, StatsBook, StreamStats
from ._talk import ArrayTalk
from .options import StreamOptions

__all__ = ["Onset", "StreamStats", "Streamer"]

_RUNNING: weakref.WeakSet = weakref.WeakSet()
FINAL_STATUS_WAIT_S = 0.3  # how long a stop waits for the array's counters after all-off, s


@atexit.register
def _stop_all() -> None:
    """Interpreter exit: stop every running streamer (each sends its all-off frame)."""
    for streamer in list(_RUNNING):
        streamer.stop(timeout=1.0)


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
        Called after each successful write as ``tap(time_s, seq, levels)``: the frame's time
        (``time.perf_counter`` seconds: when it was written, or for a timed frame when the array
        is to play it), sequence number and the channel-ordered levels (``bytes``). The
        recorder is one.
    on_onset : sequence of callables
        Called as ``hook(onset)`` with an :class:`Onset` (the scene, time and seq of the first
        frame of each presentation, see ``_onsets``): LSL markers, scripts waiting for a stimulus.
    on_status : callable, optional
        Called as ``on_status(stats)`` from the output thread whenever the state or status
        changes (a GUI must hand it to its own thread).
    idle_rate_hz : float
        Rate of the all-zero keep-alive frames while paused or idle (>= 10 Hz).
    spin_s : float
        The last part of each wait is a busy spin of at most this long, for sub-100-us timing.
    options : StreamOptions, optional
        Reconnect, real-time priority and the lead (:class:`~.options.StreamOptions`; its
        ``own_core`` is for a stream process). With ``reconnect``, a link error is retried
        every ``reconnect_interval_s`` instead of stopping. A lead sends frames that far ahead,
        timed to be played at their deadline plus the lead on the array's clock; it needs
        ``identify`` and an array that announces scheduled frames (others get frames for now).
    switch_interval_s : float or None
        While streaming, the interpreter's thread switch interval (``sys.setswitchinterval``)
        is lowered to this so the output thread gets the GIL back quickly from a busy GUI
        thread; restored on stop. None leaves it alone.
    identify : bool
        On connecting (and reconnecting), send a hello and check the array's info against the
        profile: a mismatch refuses to stream (state ``"refused"``); no answer within 0.5 s is
        an array that does not identify itself, which is driven anyway and reported so.
    clock : HostClock, optional
        The clock deadlines are kept on (``time.perf_counter`` by default; a
        :class:`~.host_clock.VirtualClock` makes a stream's timing exact in tests).

    Examples
    --------
    >>> from tactile_core.device.link import SimulatedArray
    >>> from tactile_core.rendering.scene import Scene
    >>> import tactile_core as tc
    >>> import time
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
        options: StreamOptions | None = None,
        taps=(),
        on_status=None,
        idle_rate_hz: float = 20.0,
        spin_s: float = 0.0003,
        reconnect_interval_s: float = 0.5,
        switch_interval_s: float | None = 0.0005,
        identify: bool = True,
        clock: HostClock | None = None,
        on_onset=(),
    ):
        if not 10.0 <= idle_rate_hz <= 1000.0:
            raise ValueError(f"idle_rate_hz must be within [10, 1000], got {idle_rate_hz!r}")
        options = StreamOptions() if options is None else options
        if not isinstance(options, StreamOptions):
            raise ValueError(f"options must be StreamOptions, got {_validate.shown(options)}")
        self.options = options
        self.link = link
        self.profile = profile or default_profile()
        self._scene = scene
        self.taps = list(taps)
        self.on_onset = list(on_onset)
        self._onsets = OnsetWatch(self.on_onset)
        self.on_status = on_status
        self.idle_rate_hz = idle_rate_hz
        self.spin_s = spin_s
        self.reconnect = options.reconnect
        self.reconnect_interval_s = reconnect_interval_s
        self.switch_interval_s = switch_interval_s
        self.realtime = options.realtime
        self.identify = identify
        self.lead_s = options.lead_s if identify else 0.0
        self.clock = clock or HostClock()
        self._talk = ArrayTalk(link, self.profile, lead_s=self.lead_s, update=self._set,
                               clock=self.clock)  # fmt: skip
        self.identified = threading.Event()
        """Set once the hello is answered or given up on (or the thread ended): the stream's
        duration counts from here."""
        self._failure = ""
        self.failure_traceback = ""
        """The traceback of an internal error in the output thread (its status says what)."""
        self._priority_note = ""
        self._wake = threading.Event()
        self._stopping = threading.Event()
        self._thread: threading.Thread | None = None
        self._book = StatsBook()
        self._started_at = None
        self._saved_switch = None
        self.last_levels = np.zeros(self.profile.layout.frame_shape, dtype=np.uint8)
        """Levels of the last frame written, uint8 in the layout's frame shape (``(rows, cols)``
        on a grid, ``(size,)`` on a layout), for display."""
        self.last_frame = (None, None)
        """``(scene, trace_time_s)`` of the last frame written (time None while off), one
        tuple assigned at once so a reader on another thread sees a consistent pair."""
        self.last_seq = None
        self._seq = 0  # the next frame's; taken before its write, which may go out and fail
        self._channels = _ChannelLevels(self.profile)
        self._bits = level_bits(self.profile.levels)
        self._voiced = bool(getattr(link, "takes_voices", False))
        """The link plays a waveform per channel (an audio interface): frames carry theirs."""

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

    @property
    def array_info(self) -> Info | None:
        """The array's answer to the hello (None: not asked, or no answer)."""
        return self._talk.info

    @property
    def array_status(self) -> Status | None:
        """The array's last status answer."""
        return self._talk.status

    def query_status(self, timeout_s: float = 0.5) -> Status | None:
        """Ask the array for its counters (the output thread sends the query after its next
        frame) and wait up to ``timeout_s`` for the answer; None if none came."""
        talk = self._talk
        with talk.status_arrived:
            before = talk.status
            talk.query_wanted.set()
            self._wake.set()
            talk.status_arrived.wait_for(
                lambda: talk.status is not before or not self.running, timeout_s
            )
            return talk.status if talk.status is not before else None

    @property
    def stats(self) -> StreamStats:
        """A snapshot of the statistics."""
        return self._book.snapshot(self._started_at if self.running else None, self.clock.now())

    # --- output thread -------------------------------------------------------------------------

    def _count(self, name: str, n: int = 1) -> None:
        self._book.count(name, n)

    def _set(self, **changes) -> None:
        old = self._book.update(**changes)
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
        clock = self.clock
        while True:
            remaining = deadline - clock.now()
            if remaining <= 0.0:
                return False
            if remaining > self.spin_s:
                if clock.wait(self._wake, remaining - self.spin_s):
                    self._wake.clear()
                    return True
            else:
                clock.spin_until(deadline)
                return False

    def _levels(self, plan: _Plan, k: int, dither: Dither | None, lit_before: set) -> tuple:
        """Channel-ordered levels of frame ``k`` and the set of lit channels."""
        return self._channels.levels(plan, k, dither, lit_before)

    def _write(self, seq: int, levels: bytes, at: tuple | None = None, voices=None) -> float:
        """Write a frame; ``at = (array_us, host_s)`` makes it a timed frame played at
        ``array_us`` on the array's clock (``host_s`` on the host's); ``voices``, the waveforms
        it asks for in channel order, go to a link that plays them. The time written."""
        if at is None:
            data = encode_frame(seq, levels)
        else:
            data = encode_timed(seq, at[0], levels, self._bits)
        if voices is None:
            self.link.write(data)
        else:
            self.link.write(data, voices=voices)
        now = self.clock.now()
        self.last_levels = self._channels.grid(levels)
        self.last_seq = seq & 0xFF
        self._book.wrote(now, len(data))
        for tap in self.taps:
            tap(now if at is None else at[1], seq & 0xFF, bytes(levels))
        return now

    def _identify(self) -> bool:
        """Hello and check (False: refused), then learn the array's clock for a lead."""
        return not self.identify or self._talk.connect()

    def _run(self) -> None:
        _reduce_timer_slack()
        if self.realtime:
            self._priority_note = raise_priority()
            self._set(realtime=not self._priority_note)
        self._started_at = self.clock.now()
        cur = Cursor()
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
            cur.deadline = self.clock.now()
            while not self._stopping.is_set():
                if cur.plan is None or self._scene is not cur.plan.scene:
                    self._switch(cur, self._scene)
                plan = cur.plan
                stable = self.clock.now() - plan.since > 0.2
                if plan.live is not None and not plan.precompute_started and stable:
                    plan.precompute_started = True  # the scene settled: tabulate its cycle
                    plan.live.precompute(background=True)

                if self._wait_until(cur.deadline):
                    continue  # a new scene arrived while waiting: pick it up first
                k = cur.frame_index()
                if k != plan.last_k:
                    levels, cur.lit = self._levels(plan, k, cur.dither, cur.lit)
                    plan.last_k, plan.last_levels = k, levels
                    if self._voiced:  # the waveforms the frame asks for, if any
                        plan.last_voices = self._channels.voices(plan, k)
                levels = plan.last_levels
                seq, self._seq = self._seq, self._seq + 1
                try:
                    at = None
                    self._talk.before_frame(cur.deadline)
                    if plan.active and self._talk.scheduled:  # pausing and all-off are for now
                        at_s = cur.deadline + self.lead_s
                        at = (self._talk.at_us(at_s), at_s)
                    sent = self._write(seq, levels, at, plan.last_voices)
                    self._onsets.written(sent if at is None else at[1], seq, at is not None, k)
                    self.last_frame = (plan.scene, k / plan.rate if plan.active else None)
                    self._talk.after_frame()
                except LinkError as exc:
                    self._count("errors")
                    self._set(state="disconnected", status=str(exc))
                    if not self._recover():
                        return
                    cur.deadline, cur.last_sent = self.clock.now(), None
                    continue
                if sent - cur.deadline > 1e-3:
                    self._count("late")
                if cur.last_sent is not None:
                    self._book.record_interval(sent - cur.last_sent - plan.tick)
                cur.last_sent = sent
                missed, behind = cur.advance(self.clock.now())
                if missed:  # stalled: the missed deadlines were skipped, the trace time kept
                    self._count("skipped", missed)
                    if behind + plan.tick > PAUSE_S:  # held up (wherever in the frame): say so
                        self._set(status=self._book.paused(behind + plan.tick))
        except Exception as exc:  # a bug must still end with the array off, and say so
            self._failure = f"internal error: {type(exc).__name__}: {exc}"
            self.failure_traceback = traceback.format_exc()
            self._set(state="failed", status=self._failure)
        finally:
            self._all_off_final()

    def _switch(self, cur: Cursor, scene: Scene | None) -> None:
        """Take up ``scene``: a new plan (idle, saying why, for a scene that cannot render),
        the trace restarted or going on, dithering and the tactors lit afresh, the status; a
        change of activity or tick is due at once."""
        top = self._talk.max_rate_hz
        old = cur.plan
        try:
            new = _Plan(scene, self.profile, self.idle_rate_hz, top, self.clock.now())
        except ValueError as exc:  # cannot render this scene: go idle, say why
            new = _Plan(None, self.profile, self.idle_rate_hz, top, self.clock.now())
            self._set(status=f"scene rejected: {exc}")
        restart = old is None or restarts(old.scene, scene)
        if restart:
            cur.trace_time = 0.0
        self._onsets.planned(new, restart or not old.active)
        cur.plan = new
        cur.dither = (Dither(self.profile.channels, self.profile.levels)
                      if new.active and new.scene.dither else None)  # fmt: skip
        cur.lit = set()
        state, status = new.describe(self.profile, self.link, self._priority_note)
        self._set(state=state, status=status, requested_rate_hz=new.requested, rate_hz=new.rate,
                  capped=new.capped)  # fmt: skip
        cur.last_sent = None
        if old is not None and (new.active != old.active or new.tick != old.tick):
            cur.deadline = self.clock.now()

    def _recover(self) -> bool:
        """After a link error: reconnect (True) or give up (False)."""
        if not self.reconnect:
            self._set(state="stopped", status=f"stopped: {self._book.current.status}")
            return False
        while not self.clock.wait(self._stopping, self.reconnect_interval_s):
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

    def _all_off_final(self) -> None:
        zeros = bytes(self.profile.channels)
        try:  # the count goes on: a reused number reads as 255 frames lost at the array
            seq, self._seq = self._seq, self._seq + 1
            self._write(seq, zeros)  # a frame for now: also drops what is scheduled
            if self.array_info is not None:  # an array that answers: read its counters
                self._talk.send_query()
                deadline = self.clock.now() + FINAL_STATUS_WAIT_S
                seen = self.array_status
                while self.clock.now() < deadline and self.array_status is seen:
                    self._talk.poll()
                    self.clock.sleep(0.002)
        except LinkError:
            pass  # the link is gone: the array's watchdog turns it off within 250 ms
        except Exception:
            pass
        finally:
            state, status = self._book.current.state, self._book.current.status
            if self._failure:
                state, status = "failed", f"{self._failure}; all off"
            elif state != "refused":
                status = status if state == "stopped" else "stopped: all off"
                state = "stopped"
            self._set(state=state, status=status, elapsed_s=self.clock.now() - self._started_at)
            self.identified.set()
            with self._talk.status_arrived:
                self._talk.status_arrived.notify_all()
