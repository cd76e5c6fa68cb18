"""The carrier signal of an audio array: one sine per channel, its amplitude set by the level.

:class:`CarrierSynth` is the one piece of synthesis in the package. The audio link's PortAudio
callback runs it on every block (:mod:`tactile_core.device.audio`), and ``tactile render --out
FILE.wav`` runs it over a whole trace (:func:`synthesize`), so a file and a live stream of the
same frames are the same samples.

Per channel ``c`` the output at sample ``s`` is ``a_c(s) sin(2 pi f_c s / samplerate)``: the
carrier's phase is fixed by the sample index alone (continuous across blocks, the same in every
run), and its amplitude ``a_c`` follows the frames. A new frame sets each channel's target
amplitude ``level / (levels - 1)``; the amplitude moves there along a raised cosine of
``ramp`` samples, ``w(j) = (1 - cos(pi (j + 0.5) / ramp)) / 2``, from wherever it was (a frame
that arrives mid-ramp starts a new ramp from the amplitude reached), so a level change never
clicks. ``ramp = 0`` steps.

Nothing here allocates once constructed: every block is computed into preallocated buffers
with numpy's ``out=`` (the callback runs on the audio thread, where a pause of the garbage
collector or the allocator would be heard as a dropout).
"""

from __future__ import annotations

import math

import numpy as np

TWO_PI = 2.0 * math.pi
DEFAULT_CARRIER_HZ = 250.0
"""The carrier when neither the device profile nor the URL names one: where the skin's Pacinian
channel is most sensitive, and the resonance of many voice-coil and LRA tactors."""
DEFAULT_RAMP_MS = 1.5
"""The raised-cosine ramp between two amplitudes: under half a frame at 300 frames a second
(3.3 ms), long enough that the step's spectrum stays within a few hundred hertz of the
carrier."""
MAX_BLOCK = 8192
"""Largest block the synthesiser renders at once (PortAudio's blocks are smaller)."""


def ramp_table(ramp: int) -> np.ndarray:
    """The raised cosine from 0 to 1 over ``ramp`` samples, float64 ``(ramp,)``.

    >>> ramp_table(4).round(3).tolist()
    [0.038, 0.309, 0.691, 0.962]
    """
    j = np.arange(ramp, dtype=np.float64)
    return 0.5 - 0.5 * np.cos(math.pi * (j + 0.5) / max(ramp, 1))


class CarrierSynth:
    """The carriers of ``len(carrier_hz)`` channels, rendered block by block.

    Parameters
    ----------
    carrier_hz : sequence of float
        One carrier frequency per channel, in channel order.
    samplerate : float
        Samples per second.
    ramp_s : float
        Length of the raised-cosine ramp between two amplitudes (0: a step).
    outputs : int, optional
        Channels of the output buffer; those beyond ``len(carrier_hz)`` stay silent (an
        interface with more outputs than the array has actuators). Default: one per carrier.

    Attributes
    ----------
    sample : int
        Index of the next sample to render (the carrier's phase clock).
    """

    def __init__(self, carrier_hz, samplerate: float, *, ramp_s: float,
                 outputs: int | None = None):  # fmt: skip
        carriers = np.asarray(carrier_hz, dtype=np.float64).reshape(-1)
        self.channels = n = carriers.size
        self.outputs = n if outputs is None else int(outputs)
        if n < 1 or self.outputs < n:
            raise ValueError(f"outputs must be >= channels >= 1, got {self.outputs} and {n}")
        self.samplerate = float(samplerate)
        self.carrier_hz = carriers
        self.ramp = round(ramp_s * self.samplerate)
        self._table = ramp_table(self.ramp)
        # Every block is two small matrix products and two element-wise passes, so that no
        # operand is broadcast: numpy buffers (allocates) for a broadcast operand.
        #   phase = [s, 1] @ [step; start]          (the sample within the segment, the phase)
        #   envelope = [w - 1, 1] @ [delta; to]     (w: the ramp at each sample; 1 once over)
        self._times = np.ones((MAX_BLOCK, 2))
        self._times[:, 0] = np.arange(MAX_BLOCK)
        self._carrier = np.zeros((2, n))
        self._carrier[0] = carriers * (TWO_PI / self.samplerate)  # radians per sample
        self._weights = np.ones((self.ramp + MAX_BLOCK, 2))
        self._weights[:, 0] = 0.0
        self._weights[: self.ramp, 0] = self._table - 1.0
        self._levels = np.zeros((2, n))
        self._delta = self._levels[0]  # the step of the ramp under way: to - from
        self._to = self._levels[1]  # the amplitudes the channels are at or heading to
        self._phase = np.zeros((MAX_BLOCK, n))
        self._envelope = np.zeros((MAX_BLOCK, n))
        self._from = np.zeros(n)  # scratch: the amplitudes a new ramp starts from
        self._pos = self.ramp  # samples since the last change: >= ramp once settled
        self.sample = 0

    @property
    def silent(self) -> bool:
        """True when every channel has reached amplitude 0."""
        return self._pos >= self.ramp and not self._to.any()

    @property
    def active(self) -> bool:
        """True when some channel is at or heading to a non-zero amplitude."""
        return bool(self._to.any())

    @property
    def target(self) -> np.ndarray:
        """The amplitudes the channels are at or heading to (a read-only view)."""
        view = self._to.view()
        view.flags.writeable = False
        return view

    def set_target(self, amplitudes) -> None:
        """From the next sample on, move every channel towards ``amplitudes`` (``(channels,)``,
        each in [0, 1]) along the ramp, starting from the amplitude reached now."""
        self._reached(self._from)
        np.copyto(self._to, amplitudes)
        np.subtract(self._to, self._from, out=self._delta)
        self._pos = 0 if self.ramp and self._delta.any() else self.ramp

    def _reached(self, out: np.ndarray) -> None:
        """The amplitudes of the last sample rendered, into ``out``: ``to + delta (w - 1)``
        with ``w`` the ramp's value at that sample (0 before the ramp's first sample, 1 once
        it is over)."""
        if self._pos >= self.ramp:
            np.copyto(out, self._to)
            return
        w = self._table[self._pos - 1] if self._pos else 0.0
        np.multiply(self._delta, w - 1.0, out=out)
        np.add(out, self._to, out=out)

    def render(self, out: np.ndarray, start: int, stop: int) -> None:
        """Render samples ``start:stop`` of ``out`` (``(frames, outputs)``, float32 or float64),
        continuing from the last sample rendered."""
        n = stop - start
        while n > MAX_BLOCK:
            self.render(out, start, start + MAX_BLOCK)
            start += MAX_BLOCK
            n -= MAX_BLOCK
        if n <= 0:
            return
        dest = out[start:stop, : self.channels]
        if self.outputs > self.channels:
            out[start:stop, self.channels :] = 0.0
        if self.silent:
            dest.fill(0.0)
        else:
            start_phase = self._carrier[1]
            np.multiply(self._carrier[0], float(self.sample), out=start_phase)
            np.remainder(start_phase, TWO_PI, out=start_phase)
            phase = np.matmul(self._times[:n], self._carrier, out=self._phase[:n])
            np.sin(phase, out=phase)
            envelope = np.matmul(self._weights[self._pos : self._pos + n], self._levels,
                                 out=self._envelope[:n])  # fmt: skip
            np.multiply(phase, envelope, out=phase)
            np.copyto(dest, phase)
        self._pos = min(self._pos + n, self.ramp)
        self.sample += n


def synthesize(levels, onsets, *, top: int, carrier_hz, samplerate: float, ramp_s: float,
               length: int, block: int = 4096):  # fmt: skip
    """The carrier signal of a sequence of frames, block by block (what the audio link would
    play for them, sample for sample).

    Parameters
    ----------
    levels : array_like of int, ``(frames, channels)``
        Device levels in channel order, 0 .. ``top``.
    onsets : array_like of int, ``(frames,)``
        The sample at which each frame starts (non-decreasing; the first may be 0).
    top : int
        The highest level (``levels - 1`` of the profile): full amplitude.
    carrier_hz, samplerate, ramp_s
        As for :class:`CarrierSynth`.
    length : int
        Samples in all.

    Yields
    ------
    ndarray of float32, ``(m, channels)``
        Consecutive blocks of at most ``block`` samples (one buffer, reused: copy or write it
        out before taking the next).
    """
    levels = np.asarray(levels)
    onsets = np.asarray(onsets, dtype=np.int64)
    synth = CarrierSynth(carrier_hz, samplerate, ramp_s=ramp_s)
    scale = 1.0 / top
    amplitudes = np.zeros(synth.channels)
    buffer = np.zeros((block, synth.channels), dtype=np.float32)
    k = 0
    for first in range(0, length, block):
        m = min(block, length - first)
        done = 0
        while k < len(onsets) and onsets[k] < first + m:
            at = max(int(onsets[k]) - first, done)
            synth.render(buffer, done, at)
            done = at
            np.multiply(levels[k], scale, out=amplitudes)
            synth.set_target(amplitudes)
            k += 1
        synth.render(buffer, done, m)
        yield buffer[:m]
