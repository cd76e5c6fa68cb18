"""What the streamer's output thread works from: the plan of a scene, and device levels.

:class:`_Plan` holds what one scene sets: its live frames, rate, period and keep-alive tick, and
the stream's state and status under it. :class:`_ChannelLevels` turns a frame into device
levels in channel order (calibrated, quantised). The two functions ask the operating system for
punctual wake-ups (timer slack) and real-time priority.
"""

from __future__ import annotations

import ctypes
import math
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from ..device.profile import DeviceProfile
from ..device.wire import KEEPALIVE_S
from ..rendering.correction import Dither, quantize1
from ..rendering.motor_drive import LiveMotorDrive
from ..rendering.scene import Scene


def _reduce_timer_slack() -> None:
    """Linux: wake this thread within ~1 us of the requested time instead of ~50 us."""
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None).prctl(29, 1000, 0, 0, 0)  # PR_SET_TIMERSLACK, 1 us
        except (OSError, AttributeError):
            pass


def same_source(a, b) -> bool:
    """Whether two scenes' frame sources are the same content (then a new scene with other
    μ/γ goes on from the same frame instead of restarting): the same object, or two of one
    type whose ``key`` (a value such as a file's content and position) is equal. A scene sent
    to the stream's child process arrives as a copy, so identity alone would restart an
    imported pattern on every slider move."""
    if a is b:
        return True
    if a is None or b is None or type(a) is not type(b):
        return False
    key = getattr(a, "key", None)
    return key is not None and key == getattr(b, "key", None)


class _Plan:
    """What the output thread derived from one scene: frames, rate, period."""

    def __init__(self, scene: Scene | None, profile: DeviceProfile, idle_rate_hz: float,
                 max_rate_hz: float | None = None, now_s: float | None = None):  # fmt: skip
        self.scene = scene
        self.requested = scene.rate_hz if scene is not None else idle_rate_hz
        self.active = scene is not None and scene.active
        self.max_rate = profile.max_rate_hz if max_rate_hz is None else max_rate_hz
        if self.active:
            self.rate = min(scene.rate_hz, self.max_rate)
            self.capped = scene.rate_hz > self.max_rate
            self.live = scene.live(profile.layout, self.rate)
        else:
            self.rate = idle_rate_hz
            self.capped = False
            self.live = None
        # Felt-amplitude correction: the drive is the motor response's inverse of the value.
        self.inverse = (profile.drive_for1 if self.active and scene.felt_domain
                        and profile.response is not None else None)  # fmt: skip
        # Motor-aware drive: the motors whose lag the drive pre-compensates (None: plain).
        self.motor = profile.motor if self.active and scene.compensate_motors else None
        self.period = 1.0 / self.rate
        # At any rate a frame goes out at least every KEEPALIVE_S (repeating the last one), so
        # the array's 250 ms watchdog never trips while the host is alive; the ticks divide
        # the period, so that each new frame still goes out on its own deadline.
        self.tick = self.period / math.ceil(self.period / KEEPALIVE_S - 1e-9)
        self.since = time.perf_counter() if now_s is None else now_s
        self.precompute_started = False
        self.last_k = None
        self.last_levels = None
        self.last_voices = None

    def describe(self, profile: DeviceProfile, link, priority_note: str) -> tuple[str, str]:
        """State and status line of the stream under this plan, to ``link`` (its
        ``description`` names it) with the note on the thread's priority, if any."""
        if self.scene is None:
            return "idle", f"idle: all off, keep-alive at {self.rate:g} Hz"
        if not self.scene.playing:
            return "paused", f"paused: all off, keep-alive at {self.rate:g} Hz"
        if self.capped:
            why = getattr(link, "rate_limit", None) or (
                f"{profile.baud} baud, {profile.baud / 10 / self.max_rate:.0f} bytes per frame"
            )
            return "streaming", (
                f"streaming {self.scene.method} at {self.rate:.0f} Hz: {self.requested:g} Hz "
                f"requested, the link carries {self.max_rate:.0f} frames/s ({why})"
                f"{dropped_waveforms(self.scene, profile, link)}"
            )
        note = f" ({priority_note})" if priority_note else ""
        if self.motor is not None:
            note += ", motor-aware drive"
        elif self.scene.compensate_motors:
            note += f", plain drive: profile {profile.name} has no motor constants ('motor')"
        return "streaming", (
            f"streaming {self.scene.method} at {self.rate:g} Hz to {link.description}{note}"
            f"{dropped_waveforms(self.scene, profile, link)}"
        )


def dropped_waveforms(scene: Scene | None, profile: DeviceProfile, link) -> str:
    """``"; waveform square:200 needs an audio interface: the serial array plays levels
    only"``: what a link that plays levels only (not an audio interface) drops of the waveforms
    the profile (its ``waveform``) and the scene's pattern (its effects') ask for; "" when it
    drops nothing. Said in the status line, once a scene."""
    if getattr(link, "takes_voices", False):
        return ""
    asked = [w for w in (profile.waveform or ()) if not w.plain]
    asked += list(getattr(getattr(scene, "source", None), "waveforms", ()) or ())
    specs = list(dict.fromkeys(w.spec for w in asked))
    if not specs:
        return ""
    if len(specs) == 1:
        what = f"waveform {specs[0]} needs"
    else:
        what = f"waveforms {', '.join(specs[:4])}{' ...' if len(specs) > 4 else ''} need"
    return f"; {what} an audio interface: the serial array plays levels only"


class _ChannelLevels:
    """A frame as device levels in channel order, and back on the grid for display.

    Per lit tactor of a plan's frame: the inverse of the motor response (felt-amplitude
    correction, if the plan has one), motor-aware drive (if the plan has motors to compensate),
    the profile's calibration ``clip(offset + gain * I, 0, 1)`` of a driven tactor, then
    quantisation to the profile's levels, by rounding or by temporal dithering per channel.

    Motor-aware drive carries its motors' state from frame to frame and across plans (the
    motors go on spinning when a slider moves): one frame period per frame, the periods of
    skipped deadlines, and the time a paused or idle plan held them off. A plan with plain
    drive forgets the state (the next motor-aware frame starts from motors at rest).
    """

    def __init__(self, profile: DeviceProfile):
        self.profile = profile
        channel_of_cell = np.empty(profile.channels, dtype=np.intp)
        channel_of_cell[profile.array.channel_index] = np.arange(profile.channels)
        self._channel_of_cell = channel_of_cell.tolist()
        self._cell_of_channel = profile.array.channel_index
        self._cells = self._cell_of_channel.tolist()
        self._offset = None if profile.offset is None else list(profile.offset)
        self._gain = None if profile.gain is None else list(profile.gain)
        self._drive: LiveMotorDrive | None = None
        self._drive_at = None  # (plan, k) of the last motor-aware frame
        self._off_since = None  # when a paused or idle plan turned the motors off (plan.since)

    def _motor_aware(self, plan: _Plan, k: int, entries) -> list:
        """The motor-aware drive of frame ``k``'s entries (see the class notes)."""
        drive = self._drive
        if drive is None or drive.motor is not plan.motor:
            drive = self._drive = LiveMotorDrive(plan.motor, self.profile.layout.size)
            self._drive_at = self._off_since = None
        if self._off_since is not None:
            drive.coast(plan.since - self._off_since)
            self._off_since = None
        last = self._drive_at
        held = k - last[1] if last is not None and last[0] is plan and k > last[1] else 1
        drive.set_rate(plan.rate)
        self._drive_at = (plan, k)
        return drive.frame(entries, held)

    def _plain(self, plan: _Plan) -> None:
        """A frame without motor-aware drive: off (the motors coast from now) or plain."""
        if plan.live is None:
            if self._off_since is None and self._drive_at is not None:
                self._off_since = plan.since
            self._drive_at = None
        else:
            self._drive = self._drive_at = self._off_since = None

    def levels(self, plan: _Plan, k: int, dither: Dither | None, lit_before: set) -> tuple:
        """Levels of frame ``k`` of ``plan``: a ``bytearray`` with one level per channel, and
        the set of lit channels. Dithering forgets the residual of a channel that went dark
        since ``lit_before``."""
        n = self.profile.channels
        levels = bytearray(n)
        lit = set()
        if plan.motor is None and self._drive is not None:
            self._plain(plan)
        if plan.live is None:
            return levels, lit
        top = self.profile.levels - 1
        offset, gain = self._offset, self._gain
        channel_of_cell = self._channel_of_cell
        inverse = plan.inverse
        entries = plan.live.entries(k)
        if plan.motor is not None:
            if inverse is not None:  # the drive wanted, then what gets the motor there
                entries = [(cell, inverse(value)) for cell, value in entries]
                inverse = None
            entries = self._motor_aware(plan, k, entries)
        for cell, value in entries:
            if inverse is not None:
                value = inverse(value)
            if offset is not None and value > 0.0:  # (motor-aware drive off stays off)
                value = min(max(offset[cell] + gain[cell] * value, 0.0), 1.0)
            ch = channel_of_cell[cell]
            level = dither.level1(ch, value) if dither is not None else quantize1(value, top + 1)
            levels[ch] = level
            lit.add(ch)
        if dither is not None:
            for ch in lit_before - lit:
                dither.residual[ch] = 0.0
        return levels, lit

    def voices(self, plan: _Plan, k: int) -> tuple | None:
        """The waveforms frame ``k`` of ``plan`` asks for, in channel order (a waveform or None
        per channel), or None when it asks for none (only a pattern's effects do)."""
        voices = getattr(plan.live, "voices", None)
        chosen = voices(k) if voices is not None else None
        if chosen is None:
            return None
        return tuple(chosen[cell] for cell in self._cells)

    def grid(self, levels: bytes) -> np.ndarray:
        """Channel-ordered ``levels`` on the grid: ``(rows, cols)`` uint8, for display
        (``(size,)`` in actuator order on a layout that is not a grid)."""
        flat = np.zeros(self.profile.channels, dtype=np.uint8)
        flat[self._cell_of_channel] = np.frombuffer(bytes(levels), dtype=np.uint8)
        return flat.reshape(self.profile.layout.frame_shape)


def restarts(old: Scene | None, new: Scene | None) -> bool:
    """Whether going from scene ``old`` to ``new`` starts the trace again (a new shape, frame
    source or epoch; to or from nothing), rather than going on from the same trace time with
    other μ, γ or rate."""
    return (
        old is None
        or new is None
        or new.shape != old.shape
        or not same_source(new.source, old.source)
        or new.epoch != old.epoch
    )


@dataclass
class Cursor:
    """Where the output thread is: the plan it plays, its trace time, the next deadline, and
    what carries from one frame to the next (dithering's error, the tactors lit).

    Attributes
    ----------
    plan : _Plan or None
        The plan of the scene being played (None before the first).
    dither : Dither or None
        Temporal dithering's error feedback, for a scene that asks for it.
    lit : set of int
        Channels lit in the last frame computed.
    trace_time : float
        Seconds into the trace clock; advances only while playing.
    deadline : float
        When the next frame is due, on the stream's clock (s).
    last_sent : float or None
        When the last frame went out (None after a gap: a new plan, a stall, a link error).
    """

    plan: _Plan | None = None
    dither: Dither | None = None
    lit: set = field(default_factory=set)
    trace_time: float = 0.0
    deadline: float = 0.0
    last_sent: float | None = None

    def frame_index(self) -> int:
        """The frame of the trace due now: the nearest at the frame rate, or, on a keep-alive
        tick between two frames, the one before (it is repeated)."""
        plan = self.plan
        if plan.tick == plan.period:
            return round(self.trace_time * plan.rate)
        return math.floor(self.trace_time * plan.rate + 1e-9)

    def advance(self, now_s: float) -> tuple[int, float]:
        """After a frame went out: the next deadline and trace time. When the clock is more
        than a tick past the deadline (a stall), the missed deadlines are skipped and the trace
        time moves on by them. Returns ``(missed ticks, seconds behind)``."""
        plan = self.plan
        if plan.active:
            self.trace_time += plan.tick
        self.deadline += plan.tick
        behind = now_s - self.deadline
        if behind <= plan.tick:
            return 0, behind
        missed = math.floor(behind / plan.tick)
        self.deadline += missed * plan.tick
        if plan.active:
            self.trace_time += missed * plan.tick
        self.last_sent = None
        return missed, behind
