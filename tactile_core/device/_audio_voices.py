"""The waveform of each channel, block by block: what :class:`~._audio_synth.CarrierSynth`
multiplies by the amplitude the levels set.

A :class:`VoiceSet` is the parameters of one waveform per channel (:mod:`.waveform`), built by
the writing thread (it may allocate); :class:`Waves` holds the parameters the channels play now
and renders a block of their values into preallocated buffers, on the audio thread.

Per channel ``c`` at sample ``s`` (``sr`` the samplerate, ``f`` the frequency in Hz):

- a periodic shape reads the phase ``p = frac(f s / sr)`` (fixed by the sample index, as the
  plain carrier's): sine ``sin(2 pi p)``; square ``+1`` for ``p < 1/2``, else ``-1``; saw
  ``2 frac(p + 1/2) - 1``; triangle ``4 |frac(p + 3/4) - 1/2| - 1``. The phase is computed with
  a guard of 1e-9 cycles, so that a period boundary that falls on a sample (200 Hz at 48 kHz:
  every 120 samples) takes that sample;
- a sweep is ``sin(2 pi phi(tau))`` with ``tau = s - onset`` samples since the channel's last
  onset and ``phi`` the integral of its frequency: linear ``f(tau) = f0 + (f1 - f0) tau / T``
  or exponential ``f(tau) = f0 (f1 / f0) ** (tau / T)`` for ``tau <= T``, ``f1`` after;
- noise is white, uniform in [-1, 1): the top 53 bits of SplitMix64's output for the counter
  ``(seed * 1024 + c) * 2**32 + s mod 2**32``, a function of the seed, the channel and the
  sample alone (the same samples in a file and a stream, whatever their blocks).

No operand is ever broadcast (numpy allocates a buffer for a broadcast operand): a value per
channel becomes a block of values by a small matrix product, ``[j, 1] @ [slope; start]``.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from .waveform import PERIODIC, PLAIN, Waveform

TWO_PI = 2.0 * math.pi
GUARD_CYCLES = 1e-9
"""Added to every periodic phase: a boundary that falls on a sample takes that sample."""
SINE, SQUARE, SAW, TRIANGLE, NOISE, SWEEP, LOGSWEEP = range(7)
KIND_OF = {"sine": SINE, "square": SQUARE, "saw": SAW, "triangle": TRIANGLE, "noise": NOISE}
# Rows of a parameter block (one column per channel).
(KIND, HZ, RATE0, RATE1, SWEEP_N, SLOPE, LOG_H, LOG_G, INV_H, NOISE_KEY,
 ATTACK_N, DECAY_N, SUSTAIN, RELEASE_N, HAS_ADSR, HOLD) = range(16)  # fmt: skip
ROWS = 16
_IDS: dict = {}
_COUNTER = itertools.count(1)
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)


def voice_id(waveform: Waveform) -> float:
    """A number per distinct (resolved) waveform in this process: what tells a channel that its
    waveform changed."""
    found = _IDS.get(waveform)
    if found is None:
        found = _IDS[waveform] = float(next(_COUNTER))
    return found


class VoiceSet:
    """One waveform per channel, as the parameters :class:`Waves` plays.

    Parameters
    ----------
    waveforms : sequence of Waveform
        One per channel, each with its frequency (:meth:`Waveform.at_carrier`).
    samplerate : float

    Attributes
    ----------
    waveforms : tuple of Waveform
    params : ndarray of float64, ``(ROWS, channels)``
    ids : ndarray of float64, ``(channels,)``
    """

    def __init__(self, waveforms, samplerate: float):
        self.waveforms = tuple(waveforms)
        n = len(self.waveforms)
        self.params = p = np.zeros((ROWS, n))
        self.ids = np.zeros(n)
        sr = float(samplerate)
        for c, w in enumerate(self.waveforms):
            self.ids[c] = voice_id(w)
            hz = w.carrier_hz if w.carrier_hz is not None else 0.0
            p[HZ, c] = hz
            p[KIND, c] = KIND_OF.get(w.shape, SWEEP)
            p[RATE0, c] = p[RATE1, c] = hz / sr
            p[SWEEP_N, c] = 1.0
            if w.shape == "sweep":
                p[KIND, c] = LOGSWEEP if w.scale == "log" else SWEEP
                t = max(w.sweep_ms * sr / 1e3, 1.0)
                p[RATE1, c] = w.end_hz / sr
                p[SWEEP_N, c] = t
                p[SLOPE, c] = (p[RATE1, c] - p[RATE0, c]) / t
                if w.scale == "log":
                    h = math.log(w.end_hz / w.carrier_hz) / t
                    p[LOG_H, c], p[INV_H, c], p[LOG_G, c] = h, 1.0 / h, p[RATE0, c] / h
            p[NOISE_KEY, c] = float((w.seed * 1024 + c) * 2**32)
            p[SUSTAIN, c] = 1.0
            p[ATTACK_N, c] = p[DECAY_N, c] = p[RELEASE_N, c] = 1.0
            if w.adsr is not None:
                a = w.adsr
                p[HAS_ADSR, c] = 1.0
                p[HOLD, c] = 1.0 if a.release_ms > 0.0 else 0.0
                p[SUSTAIN, c] = a.sustain
                p[ATTACK_N, c] = max(a.attack_ms * sr / 1e3, 1.0)
                p[DECAY_N, c] = max(a.decay_ms * sr / 1e3, 1.0)
                p[RELEASE_N, c] = max(a.release_ms * sr / 1e3, 1.0)


def resolve(waveforms, carrier_hz, channels: int) -> tuple:
    """One waveform per channel with its frequency: ``waveforms`` (None: the plain carrier; one
    for all; or one per channel) at ``carrier_hz`` (one per channel)."""
    if waveforms is None:
        waveforms = (PLAIN,)
    waveforms = tuple(waveforms)
    if len(waveforms) == 1:
        waveforms *= channels
    if len(waveforms) != channels:
        raise ValueError(f"waveforms must be one for all channels or one per channel "
                         f"({channels}), got {len(waveforms)}")  # fmt: skip
    for c, w in enumerate(waveforms):
        if not isinstance(w, Waveform):
            raise ValueError(f"waveforms[{c}] must be a Waveform, got {type(w).__name__}")
    return tuple(w.at_carrier(float(hz)) for w, hz in zip(waveforms, carrier_hz, strict=True))


class Waves:
    """The waveforms the channels play, rendered block by block without allocating.

    Parameters
    ----------
    voices : VoiceSet
        What every channel plays at first.
    samplerate : float
    block : int
        The most samples :meth:`render` is asked for at once.
    """

    def __init__(self, voices: VoiceSet, samplerate: float, block: int):
        n = voices.params.shape[1]
        self.channels = n
        self.samplerate = float(samplerate)
        self.params = voices.params.copy()
        self.ids = voices.ids.copy()
        self.onset = np.zeros(n)  # each channel's last onset (sample): the sweeps' clock
        j = np.arange(block, dtype=np.float64)
        self._lin = np.stack([j, np.ones(block)], axis=1)  # [j, 1]
        self._quad = np.stack([j**2, j, np.ones(block)], axis=1)  # [j^2, j, 1]
        self._ones = np.ones((block, 1))
        self._masks = np.zeros((LOGSWEEP + 1, n))
        self._planes = np.zeros((LOGSWEEP + 1, block, n))
        self._k2 = np.zeros((2, n))
        self._kc = np.zeros((2, n))  # the fixed-frequency phases: [cycles a sample; start]
        self._k3 = np.zeros((3, n))
        self._v = np.zeros((7, n))  # per-channel scratch
        self._changed = np.zeros(n, dtype=bool)
        self._is_kind = np.zeros(n, dtype=bool)
        self._inside = np.zeros(n, dtype=bool)
        self._ends = np.zeros(n, dtype=bool)
        self._spare = np.zeros(n, dtype=bool)
        self._present = np.zeros(LOGSWEEP + 1, dtype=bool)
        for name in ("_wave", "_phase", "_tmp", "_f", "_aux", "_plane"):
            setattr(self, name, np.zeros((block, n)))
        self._x32 = np.zeros((block, n), dtype=np.float32)
        self._u = np.zeros((block, n), dtype=np.uint64)
        self._w = np.zeros((block, n), dtype=np.uint64)
        self._refresh()

    def _refresh(self) -> None:
        """The kinds in play, their masks and what the channels need, after a change."""
        for k in range(LOGSWEEP + 1):
            np.equal(self.params[KIND], k, out=self._is_kind)
            np.copyto(self._masks[k], self._is_kind)
            self._present[k] = self._is_kind.any()
        if self._present.sum() > 1:  # the masks as blocks, for merging kinds (no broadcast)
            for k in range(LOGSWEEP + 1):
                if self._present[k]:
                    np.copyto(self._planes[k], self._masks[k])
        self.adsr = bool(self.params[HAS_ADSR].any())
        """Some channel has an envelope."""
        p = self.params
        self.settle_s = float(max((p[ATTACK_N] + p[DECAY_N]).max(), p[RELEASE_N].max()))
        """Samples after an onset or a release within which every envelope holds still."""
        np.divide(p[HZ], self.samplerate, out=self._kc[0])  # cycles a sample
        self.clocked = self.adsr or bool(self._present[SWEEP] or self._present[LOGSWEEP])
        """Some channel counts time from its onsets (an envelope, a sweep)."""

    @property
    def kinds(self) -> tuple:
        """The kinds of waveform the channels play (``SINE`` ... ``LOGSWEEP``)."""
        return tuple(k for k in range(LOGSWEEP + 1) if self._present[k])

    def assign(self, voices: VoiceSet, where: np.ndarray) -> bool:
        """Channels ``where`` (bool, ``(channels,)``) take their waveform from ``voices``; those
        whose waveform changes are marked in :attr:`changed`. True if any changed."""
        changed = self._changed
        np.not_equal(voices.ids, self.ids, out=changed)
        np.logical_and(changed, where, out=changed)
        if not changed.any():
            return False
        np.copyto(self.params, voices.params, where=changed)
        np.copyto(self.ids, voices.ids, where=changed)
        self._refresh()
        return True

    @property
    def changed(self) -> np.ndarray:
        """The channels whose waveform the last :meth:`assign` changed (bool; do not write)."""
        return self._changed

    # --- rendering ------------------------------------------------------------------------

    def render(self, n: int, sample: int) -> np.ndarray:
        """The waveforms of samples ``sample .. sample + n - 1``: a ``(n, channels)`` view of a
        buffer (valid until the next call)."""
        wave = self._wave[:n]
        first, present = True, self._present
        if present[SINE] or present[SQUARE] or present[SAW] or present[TRIANGLE]:
            phase = self._cycles(n, sample)
            for kind in (SINE, SQUARE, SAW, TRIANGLE):
                if not present[kind]:
                    continue
                dest = wave if first else self._f[:n]
                _SHAPES[kind](self, phase, dest, n)
                if not first:
                    self._merge(wave, dest, kind, n)
                first = False
        for kind in (SWEEP, LOGSWEEP, NOISE):
            if not present[kind]:
                continue
            dest = wave if first else self._f[:n]
            if kind == NOISE:
                self._noise(dest, n, sample)
            else:
                self._sweep(dest, n, sample, kind == LOGSWEEP)
            if not first:
                self._merge(wave, dest, kind, n)
            first = False
        return wave

    def _merge(self, wave, dest, kind: int, n: int) -> None:
        """``wave`` takes ``dest`` on the channels of ``kind``: ``wave += m (dest - wave)``."""
        np.subtract(dest, wave, out=dest)
        np.multiply(dest, self._planes[kind, :n], out=dest)
        np.add(wave, dest, out=wave)

    def _cycles(self, n: int, sample: int) -> np.ndarray:
        """``frac(f s / sr)`` (+ the guard) of the fixed-frequency shapes, ``(n, channels)``;
        ``f s`` is reduced modulo ``sr`` first (exact for whole hertz)."""
        k = self._kc
        sr = self.samplerate
        np.multiply(self.params[HZ], float(sample), out=k[1])
        np.remainder(k[1], sr, out=k[1])
        np.divide(k[1], sr, out=k[1])
        np.add(k[1], GUARD_CYCLES, out=k[1])
        phase = np.matmul(self._lin[:n], k, out=self._phase[:n])
        return _frac(phase, self._tmp[:n])

    def _sine(self, phase, dest, n: int) -> None:
        """``sin(2 pi phase)``, ``phase`` in [0, 1): numpy's vectorised float32 sine (within
        3e-7 of the exact value, a hundredth of a 16-bit step)."""
        tmp = np.multiply(phase, TWO_PI, out=self._tmp[:n])
        x = self._x32[:n]
        np.copyto(x, tmp)
        np.sin(x, out=x)
        np.copyto(dest, x)

    def _square(self, phase, dest, n: int) -> None:
        np.multiply(phase, 2.0, out=dest)
        np.floor(dest, out=dest)
        np.multiply(dest, -2.0, out=dest)
        np.add(dest, 1.0, out=dest)

    def _saw(self, phase, dest, n: int) -> None:
        np.add(phase, 0.5, out=dest)
        _frac(dest, self._tmp[:n])
        np.multiply(dest, 2.0, out=dest)
        np.subtract(dest, 1.0, out=dest)

    def _triangle(self, phase, dest, n: int) -> None:
        np.add(phase, 0.75, out=dest)
        _frac(dest, self._tmp[:n])
        np.subtract(dest, 0.5, out=dest)
        np.abs(dest, out=dest)
        np.multiply(dest, 4.0, out=dest)
        np.subtract(dest, 1.0, out=dest)

    def _noise(self, dest, n: int, sample: int) -> None:
        """White noise: SplitMix64 of each channel's counter, to [-1, 1)."""
        k = self._k2
        k[0].fill(1.0)
        np.add(self.params[NOISE_KEY], float(sample % 2**32), out=k[1])
        counter = np.matmul(self._lin[:n], k, out=self._tmp[:n])  # exact: below 2**53
        u, w = self._u[:n], self._w[:n]
        np.copyto(u, counter, casting="unsafe")
        np.add(u, _GOLDEN, out=u)
        for shift, factor in ((30, _MIX1), (27, _MIX2)):
            np.right_shift(u, shift, out=w)
            np.bitwise_xor(u, w, out=u)
            np.multiply(u, factor, out=u)
        np.right_shift(u, 31, out=w)
        np.bitwise_xor(u, w, out=u)
        np.right_shift(u, 11, out=u)
        np.copyto(dest, u, casting="unsafe")
        np.multiply(dest, 2.0**-52, out=dest)
        np.subtract(dest, 1.0, out=dest)

    def _sweep(self, dest, n: int, sample: int, log: bool) -> None:
        """The sine of each sweep's phase since its onset (the module's notes). At the block's
        start ``c`` samples of the sweep are gone and ``rem`` left; in the block ``y = max(j -
        rem, 0)`` counts the samples past its end. A block in which no sweep ends takes the
        short way: each channel is wholly in its sweep, or wholly past it."""
        p, k, lin = self.params, self._k2, self._lin[:n]
        tau, c, rem, after, phi0, fs, tmp = self._v
        np.subtract(float(sample), self.onset, out=tau)
        np.minimum(tau, p[SWEEP_N], out=c)
        np.subtract(p[SWEEP_N], c, out=rem)
        np.subtract(tau, c, out=after)
        if log:  # the phase and the frequency at c
            np.multiply(p[LOG_H], c, out=fs)
            np.exp(fs, out=fs)
            np.subtract(fs, 1.0, out=phi0)
            np.multiply(phi0, p[LOG_G], out=phi0)  # G (r^(c / T) - 1)
            np.multiply(fs, p[RATE0], out=fs)
        else:
            np.multiply(p[SLOPE], c, out=fs)
            np.multiply(fs, 0.5, out=phi0)
            np.add(phi0, p[RATE0], out=phi0)
            np.multiply(phi0, c, out=phi0)  # rate0 c + slope c^2 / 2
            np.add(fs, p[RATE0], out=fs)
        self._phi0(phi0, after, tmp)
        inside, ends = self._inside, self._ends
        np.greater_equal(rem, float(n), out=inside)  # wholly in the sweep this block
        np.greater(rem, 0.0, out=ends)
        np.logical_not(inside, out=self._spare)
        np.logical_and(ends, self._spare, out=ends)  # its end falls within the block
        if not ends.any():
            np.copyto(tmp, inside)  # 1 in the sweep, 0 past it
            if log:
                self._log_short(dest, n, tmp, phi0, fs)
            else:  # phi0 + fs j + [in] (slope / 2) j^2
                k3 = self._k3
                np.multiply(p[SLOPE], 0.5, out=k3[0])
                np.multiply(k3[0], tmp, out=k3[0])
                np.copyto(k3[1], fs)
                np.copyto(k3[2], phi0)
                np.matmul(self._quad[:n], k3, out=dest)
        else:
            k[0].fill(1.0)
            np.negative(rem, out=k[1])
            y = np.matmul(lin, k, out=self._aux[:n])
            np.maximum(y, 0.0, out=y)
            if log:
                self._log_long(dest, n, y, rem, phi0, fs)
            else:  # phi0 + fs j + (slope / 2) j^2 - (slope / 2) y^2
                k3 = self._k3
                np.multiply(p[SLOPE], 0.5, out=k3[0])
                np.copyto(k3[1], fs)
                np.copyto(k3[2], phi0)
                np.matmul(self._quad[:n], k3, out=dest)
                np.negative(k3[0], out=k[0])
                np.multiply(k3[0], rem, out=k[1])
                b = np.matmul(lin, k, out=self._tmp[:n])  # -(slope / 2) (j - rem)
                np.multiply(b, y, out=b)
                np.add(dest, b, out=dest)
        _frac(dest, self._tmp[:n])
        self._sine(dest, dest, n)

    def _log_short(self, dest, n: int, inside, phi0, fs) -> None:
        """A block no log sweep ends in: ``phi0 + G' (exp(h j) - 1)`` in the sweep (``G' = fs /
        h``), ``phi0 + f1 j`` past it."""
        p, k, lin = self.params, self._k2, self._lin[:n]
        np.multiply(p[LOG_H], inside, out=k[0])
        k[1].fill(0.0)
        np.matmul(lin, k, out=dest)
        np.exp(dest, out=dest)
        gp = self._v[2]  # (rem: no longer needed)
        np.multiply(fs, p[INV_H], out=gp)
        np.multiply(gp, inside, out=gp)
        plane = np.matmul(self._ones[:n], gp[None, :], out=self._plane[:n])
        np.multiply(dest, plane, out=dest)
        np.subtract(1.0, inside, out=k[0])
        np.multiply(k[0], p[RATE1], out=k[0])
        np.subtract(phi0, gp, out=k[1])
        tail = np.matmul(lin, k, out=self._tmp[:n])
        np.add(dest, tail, out=dest)

    def _log_long(self, dest, n: int, y, rem, phi0, fs) -> None:
        """A block some log sweep ends in: ``phi0 + G' (exp(h x) - 1) + f1 y`` with ``h x = h j
        - [y > 0] h (j - rem)``."""
        p, k, lin = self.params, self._k2, self._lin[:n]
        np.sign(y, out=y)
        np.copyto(k[0], p[LOG_H])
        k[1].fill(0.0)
        np.matmul(lin, k, out=dest)
        np.multiply(p[LOG_H], rem, out=k[1])
        np.negative(k[1], out=k[1])
        past = np.matmul(lin, k, out=self._tmp[:n])
        np.multiply(past, y, out=past)
        np.subtract(dest, past, out=dest)
        np.exp(dest, out=dest)
        np.multiply(fs, p[INV_H], out=fs)  # G' = fs / h
        plane = np.matmul(self._ones[:n], fs[None, :], out=self._plane[:n])
        np.multiply(dest, plane, out=dest)
        np.copyto(k[0], p[RATE1])
        np.multiply(p[RATE1], rem, out=k[1])
        np.negative(k[1], out=k[1])
        tail = np.matmul(lin, k, out=self._tmp[:n])
        np.multiply(tail, y, out=tail)
        np.add(dest, tail, out=dest)
        k[0].fill(0.0)
        np.subtract(phi0, fs, out=k[1])
        const = np.matmul(lin, k, out=self._tmp[:n])
        np.add(dest, const, out=dest)

    def _phi0(self, phi0, after, tmp) -> None:
        """``phi0 = frac(phi0 + f1 after)``: the phase at the block's start."""
        np.multiply(self.params[RATE1], after, out=tmp)
        np.add(phi0, tmp, out=phi0)
        np.remainder(phi0, 1.0, out=phi0)


def _frac(x: np.ndarray, scratch: np.ndarray) -> np.ndarray:
    """``x - floor(x)`` in place (``scratch`` of the same shape); returns ``x``."""
    np.floor(x, out=scratch)
    np.subtract(x, scratch, out=x)
    return x


_SHAPES = {SINE: Waves._sine, SQUARE: Waves._square, SAW: Waves._saw, TRIANGLE: Waves._triangle}

__all__ = ["PERIODIC", "VoiceSet", "Waves", "resolve", "voice_id"]
