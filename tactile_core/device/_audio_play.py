"""What the audio callback plays: frames as events on the host's clock, blocks of carrier.

:class:`Player` sits between two threads. The writer (the streamer's thread, through
:class:`~.audio.AudioLink`) turns what the array model applied or queued into *events* — ``(id,
host time, amplitudes, timed, voices)``, ``voices`` the waveforms the frame asks for (None: each
channel its own) — and swaps in a new immutable tuple of them. PortAudio's thread
calls :meth:`Player.play` once per block: it maps the block onto the host's clock
(:class:`BlockClock`), applies each event at the first sample at or after its time (a frame for
now, stamped with its arrival, lands at the start of the next block), enforces the 250 ms
watchdog sample-exactly, and renders the carriers (:class:`~._audio_synth.CarrierSynth`). Each
number is written by one thread only; the callback allocates no arrays.
"""

from __future__ import annotations

import math

import numpy as np

from ._audio_synth import CarrierSynth
from .wire import WATCHDOG_S, Frame

RESYNC_S = 0.01
"""A block measured this far from the clock map is off the map (a stall, or a dropout)."""
RESYNC_AFTER_S = 0.15
"""How long the blocks must stay off the map before it lets go and finds the stream again: a
stall of the callback and the burst that catches up are over sooner (a stall of 50 ms puts
eight blocks more than 10 ms off)."""
SETTLE_BLOCKS = 4
"""Blocks in a row on time before the clock map locks."""
STEP_S = 2e-6
"""The most the locked map moves per block: it follows the median of the measurements, so a
late callback or a burst moves it by this much at most (ten times as much during its first
:data:`QUICK_BLOCKS`, to leave the error of the one block it locked on quickly)."""
QUICK_BLOCKS = 32
FADE = "fade"
"""The voices of the event that closes the stream: all off along the ramp, releases cut."""


class BlockClock:
    """The host time of each block's first sample, from PortAudio's timing.

    A block measured to start at ``measured`` that is the stream's sample ``s`` says the stream
    started at ``measured - s / samplerate``. Until the stream runs steadily
    (:data:`SETTLE_BLOCKS` blocks in a row that agree: PortAudio's first blocks fill the buffers
    at once) each block is taken at its measured time. Then the map locks on that start and
    follows the median of the measurements, moving at most :data:`STEP_S` a block (more during
    its first blocks), so that neither the callback's jitter, nor a stall of it and the burst
    that catches up, moves a frame; the crystal's drift against the host's clock (tens of ppm:
    well under a microsecond a block) it follows. Measurements off by more than
    :data:`RESYNC_S` for :data:`RESYNC_AFTER_S` (a dropout that shifted the stream) unlock it.
    """

    def __init__(self, samplerate: float):
        self.samplerate = samplerate
        self.locked = False
        self.resyncs = 0
        self._sample = 0  # the stream's samples so far
        self._start = 0.0  # the stream's start on the host's clock, as locked
        self._last: float | None = None
        self._steady = 0
        self._since = 0  # blocks since the lock
        self._far = 0  # samples in a row off the map

    def block(self, measured: float, frames: int) -> float:
        """The host time of the next block of ``frames`` samples, measured at ``measured``."""
        first = self._sample
        self._sample += frames
        start = measured - first / self.samplerate
        if self.locked:
            error = start - self._start
            self._far = self._far + frames if abs(error) > RESYNC_S else 0
            if self._far < RESYNC_AFTER_S * self.samplerate:
                step = STEP_S * (10 if self._since < QUICK_BLOCKS else 1)
                self._since += 1
                self._start += min(max(error, -step), step)
                return self._start + first / self.samplerate
            self.locked = False
            self.resyncs += 1
            self._steady = 0
        steady = (
            self._last is not None and abs(start - self._last) < 0.25 * frames / self.samplerate
        )
        self._last = start
        self._steady = self._steady + 1 if steady else 0
        if self._steady >= SETTLE_BLOCKS:
            self.locked = True
            self._start, self._since, self._far = start, 0, 0
        return measured


class Player:
    """The events the writer schedules and the callback plays.

    Parameters
    ----------
    carrier_hz : sequence of float
        One carrier per channel of the array.
    samplerate : int
    ramp_s : float
    outputs : int
        The stream's channels (those beyond the array's stay silent).
    top : int
        The array's highest level (full amplitude).
    waveforms : sequence of Waveform, optional
        Each channel's own waveform (one for all, or one per channel); the plain carrier by
        default.
    """

    def __init__(self, carrier_hz, samplerate: int, *, ramp_s: float, outputs: int, top: int,
                 waveforms=None):  # fmt: skip
        self.samplerate = samplerate
        self.synth = CarrierSynth(carrier_hz, samplerate, ramp_s=ramp_s, outputs=outputs,
                                  waveforms=waveforms)  # fmt: skip
        self.clock = BlockClock(samplerate)
        self._scale = 1.0 / top
        self._zeros = np.zeros(self.synth.channels)
        self.events: tuple = ()  # replaced by the writer, read once per block by the callback
        self._queued: list = []  # the model's queue as last scheduled (writer)
        self._next_id = 0
        self.done = 0  # the last event applied (callback)
        self.fed_at: float | None = None  # the last valid frame's arrival (writer)
        self.late = 0  # timed frames the callback met after their time (callback)
        self.silent_blocks = 0  # whole blocks of silence in a row (callback)
        self.blocks = 0

    # --- the writer's side ------------------------------------------------------------------

    def _event(self, at: float, levels: bytes, timed: bool, voices=None) -> tuple:
        self._next_id += 1
        amplitudes = np.frombuffer(levels, dtype=np.uint8) * self._scale
        return (self._next_id, at, amplitudes, timed, voices)

    def schedule(self, model, frames: list, now: float, voices=None) -> None:
        """After :meth:`~.array.ArrayModel.receive` at host time ``now``: events for the frames
        the model applied (``frames``) and queued (``model.queue``); the new ones play
        ``voices`` (a waveform or None per channel, None: each channel its own)."""
        voices = self.synth.voices(voices)
        if not frames and len(model.queue) == len(self._queued):
            return
        done = self.done
        pending = [e for e in self.events if e[0] > done]
        before = self._queued
        for msg in frames:
            if any(msg is q for q in before):
                continue  # played from the queue: scheduled when it was queued
            if isinstance(msg, Frame):  # a frame for now drops what was still to come
                pending = [e for e in pending if e[1] <= now]
            pending.append(self._event(now, msg.levels, False, voices))
        for msg in model.queue:
            if not any(msg is q for q in before):
                at = model.host_time(msg.at_us, now)
                pending.append(self._event(at, msg.levels, True, voices))
        self._queued = list(model.queue)
        if model.last_valid == now:
            self.fed_at = now  # before the events: the callback reads them first, then this
        self.events = tuple(pending)

    def fade_out(self, now: float) -> None:
        """All off from the next block, dropping whatever was still to come."""
        self.silent_blocks = 0
        self._queued = []
        self.events = (self._event(now, bytes(self.synth.channels), False, FADE),)

    # --- the callback's side ----------------------------------------------------------------

    def play(self, out, frames: int, measured: float) -> None:
        """Fill ``out`` (``(frames, outputs)`` float32) with the block measured to start at host
        time ``measured``."""
        start_s = self.clock.block(measured, frames)
        synth = self.synth
        quiet = synth.silent  # silent all through, if still silent at the end
        rate = self.samplerate
        events = self.events  # first the events, then the time of the last feed
        fed = self.fed_at
        watch = math.inf if fed is None else fed + WATCHDOG_S
        done = 0
        last_id = self.done
        for event in events:
            eid, at, amplitudes, timed, voices = event
            if eid <= last_id:
                continue
            if at > watch:
                break  # the watchdog trips first (below) and drops it
            offset = math.ceil((at - start_s) * rate - 1e-6)
            if offset >= frames:
                break
            if offset < done:
                if timed and offset < 0:
                    self.late += 1
                offset = done
            synth.render(out, done, offset)
            done = offset
            if voices is FADE:  # closing: every channel fades along the ramp, releases too
                synth.set_target(amplitudes, release=False)
            else:
                synth.set_target(amplitudes, voices)
            self.done = last_id = eid
        if watch < start_s + frames / rate:  # no valid frame for 250 ms: all off
            if synth.active:
                offset = min(max(math.ceil((watch - start_s) * rate - 1e-6), done), frames)
                synth.render(out, done, offset)
                done = offset
                synth.set_target(self._zeros)
            if events:
                self.done = max(self.done, events[-1][0])  # and what waits is dropped
        synth.render(out, done, frames)
        self.silent_blocks = self.silent_blocks + 1 if quiet and synth.silent else 0
        self.blocks += 1
