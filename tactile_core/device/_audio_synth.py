"""The signal of an audio array: one waveform per channel, its amplitude set by the level.

:class:`CarrierSynth` is the one piece of synthesis in the package. The audio link's PortAudio
callback runs it on every block (:mod:`tactile_core.device.audio`), and ``tactile render --out
FILE.wav`` runs it over a whole trace (:func:`synthesize`), so a file and a live stream of the
same frames are the same samples.

Per channel ``c`` the output at sample ``s`` is ``a_c(s) E_c(s) x_c(s)``: ``x_c`` the
channel's waveform (:mod:`._audio_voices`: by default the plain carrier ``sin(2 pi f_c s /
samplerate)``, whose phase is fixed by the sample index alone: continuous across blocks, the
same in every run), ``E_c`` its ADSR envelope if the waveform has one (:mod:`._audio_adsr`, 1
otherwise), and ``a_c`` the amplitude, which follows the frames. A new frame sets each
channel's target amplitude ``level / (levels - 1)``; the amplitude moves there along a raised
cosine of ``ramp`` samples, ``w(j) = (1 - cos(pi (j + 0.5) / ramp)) / 2``, from wherever it was
(a frame that arrives mid-ramp starts a new ramp from the amplitude reached), so a level change
never clicks. ``ramp = 0`` steps. A channel whose envelope has a release keeps its last
amplitude when it goes off, and the release takes it to 0.

A frame may also carry a waveform per channel (a pattern's effect that asks for its own): a lit
channel takes it from that frame on, a channel that is off keeps the one it had. An *onset* (a
channel going from off to lit, or a lit channel given another waveform) starts its envelope
and its sweep.

Nothing here allocates once constructed: every block is computed into preallocated buffers
with numpy's ``out=`` (the callback runs on the audio thread, where a pause of the garbage
collector or the allocator would be heard as a dropout).
"""

from __future__ import annotations

import math

import numpy as np

from ._audio_adsr import Envelopes
from ._audio_voices import HOLD, VoiceSet, Waves, resolve
from .waveform import Waveform

TWO_PI = 2.0 * math.pi
DEFAULT_CARRIER_HZ = 250.0
"""The carrier when neither the device profile nor the URL names one: where the skin's Pacinian
channel is most sensitive, and the resonance of many voice-coil and LRA tactors."""
DEFAULT_RAMP_MS = 1.5
"""The raised-cosine ramp between two amplitudes: under half a frame at 300 frames a second
(3.3 ms), long enough that the step's spectrum stays within a few hundred hertz of the
carrier."""
MAX_BLOCK = 1024
"""Largest block the synthesiser renders at once (PortAudio's blocks are smaller; a longer
render is done in pieces)."""
MAX_VOICE_SETS = 512
"""Waveform assignments the writer keeps built (a pattern has a few)."""


def ramp_table(ramp: int) -> np.ndarray:
    """The raised cosine from 0 to 1 over ``ramp`` samples, float64 ``(ramp,)``.

    >>> ramp_table(4).round(3).tolist()
    [0.038, 0.309, 0.691, 0.962]
    """
    j = np.arange(ramp, dtype=np.float64)
    return 0.5 - 0.5 * np.cos(math.pi * (j + 0.5) / max(ramp, 1))


class CarrierSynth:
    """The waveforms of ``len(carrier_hz)`` channels, rendered block by block.

    Parameters
    ----------
    carrier_hz : sequence of float
        One carrier frequency per channel, in channel order (Hz): what a waveform that gives
        no frequency of its own plays at.
    samplerate : float
        Samples per second.
    ramp_s : float
        Length of the raised-cosine ramp between two amplitudes (0: a step).
    outputs : int, optional
        Channels of the output buffer; those beyond ``len(carrier_hz)`` stay silent (an
        interface with more outputs than the array has actuators). Default: one per carrier.
    waveforms : sequence of Waveform, optional
        One for every channel or one per channel (:mod:`.waveform`); default the plain carrier.

    Attributes
    ----------
    sample : int
        Index of the next sample to render (the carriers' phase clock).
    waveforms : tuple of Waveform
        Each channel's own waveform, its frequency filled in.
    """

    def __init__(self, carrier_hz, samplerate: float, *, ramp_s: float,
                 outputs: int | None = None, waveforms=None):  # fmt: skip
        carriers = np.asarray(carrier_hz, dtype=np.float64).reshape(-1)
        self.channels = n = carriers.size
        self.outputs = n if outputs is None else int(outputs)
        if n < 1 or self.outputs < n:
            raise ValueError(f"outputs must be >= channels >= 1, got {self.outputs} and {n}")
        self.samplerate = float(samplerate)
        self.carrier_hz = carriers
        self.waveforms = resolve(waveforms, carriers, n)
        self.default_voices = VoiceSet(self.waveforms, self.samplerate)
        self._voice_sets: dict = {}
        self._waves = Waves(self.default_voices, self.samplerate, MAX_BLOCK)
        self._env = Envelopes(n, MAX_BLOCK)
        self._enveloped = self._waves.adsr  # an envelope was ever assigned
        self.ramp = round(ramp_s * self.samplerate)
        self._table = ramp_table(self.ramp)
        # The amplitude of every channel is one small matrix product, so that no operand is
        # broadcast (numpy buffers, allocates, for a broadcast operand):
        #   amplitude = [w - 1, 1] @ [delta; to]   (w: the ramp at each sample; 1 once over)
        self._weights = np.ones((self.ramp + MAX_BLOCK, 2))
        self._weights[:, 0] = 0.0
        self._weights[: self.ramp, 0] = self._table - 1.0
        self._levels = np.zeros((2, n))
        self._delta = self._levels[0]  # the step of the ramp under way: to - from
        self._to = self._levels[1]  # the amplitudes the channels are at or heading to
        self._amplitude = np.zeros((MAX_BLOCK, n))
        self._scaled = np.zeros((2, n))  # the levels times steady envelopes
        self._from = np.zeros(n)  # scratch: the amplitudes a new ramp starts from
        self._goal = np.zeros(n)  # the amplitudes the frames ask for (0: off)
        self._held = np.zeros(n)  # scratch: the targets before a frame
        self._e = np.zeros(n)  # scratch: the envelopes now
        self._flags = np.zeros((4, n), dtype=bool)  # scratch: lit, was lit, onset, goes off
        self._pos = self.ramp  # samples since the last change: >= ramp once settled
        self._own = True  # every channel plays its own waveform
        self.sample = 0

    @property
    def silent(self) -> bool:
        """True when every channel has reached amplitude 0 (releases over)."""
        return self._pos >= self.ramp and not self._to.any()

    @property
    def active(self) -> bool:
        """True when some channel is asked for a non-zero amplitude."""
        return bool(self._goal.any())

    @property
    def target(self) -> np.ndarray:
        """The amplitudes the frames ask of the channels (a read-only view)."""
        view = self._goal.view()
        view.flags.writeable = False
        return view

    def voices(self, choice) -> VoiceSet | None:
        """The waveforms of a frame, built for :meth:`set_target` (on the writer's side: this
        allocates). ``choice``: a waveform or None (the channel's own) per channel; None for
        all the channels' own."""
        if choice is None:
            return None
        key = tuple(choice)
        found = self._voice_sets.get(key)
        if found is None:
            if len(key) != self.channels:
                raise ValueError(f"voices must be one per channel ({self.channels}), got "
                                 f"{len(key)}")  # fmt: skip
            chosen = []
            for c, w in enumerate(key):
                if w is not None and not isinstance(w, Waveform):
                    raise ValueError(f"voices[{c}] must be a Waveform or None, got "
                                     f"{type(w).__name__}")  # fmt: skip
                own = self.waveforms[c]
                chosen.append(own if w is None else w.at_carrier(float(self.carrier_hz[c])))
            found = VoiceSet(chosen, self.samplerate)
            if len(self._voice_sets) >= MAX_VOICE_SETS:
                self._voice_sets.clear()
            self._voice_sets[key] = found
        return found

    def set_target(self, amplitudes, voices: VoiceSet | None = None, *,
                   release: bool = True) -> None:  # fmt: skip
        """From the next sample on, move every channel towards ``amplitudes`` (``(channels,)``,
        each in [0, 1]) along the ramp, starting from the amplitude reached now.

        ``voices`` (from :meth:`voices`; None: each channel's own waveform) is what the lit
        channels play from now. ``release=False`` fades every channel going off along the ramp
        even where its envelope has a release, and ends the releases under way (closing)."""
        waves, env, now = self._waves, self._env, self.sample
        voices = voices or self.default_voices
        if self._own and voices is self.default_voices and not (waves.clocked or self._enveloped):
            self._reached(self._from)  # every channel plays its own waveform: levels only
            np.copyto(self._goal, amplitudes)
            np.copyto(self._to, amplitudes)
            np.subtract(self._to, self._from, out=self._delta)
            self._pos = 0 if self.ramp and self._delta.any() else self.ramp
            return
        if self._enveloped:
            self._finish_releases()
            env.now(now, self._e)
        self._reached(self._from)
        lit, was, onset, off = self._flags
        np.greater(self._goal, 0.0, out=was)
        np.copyto(self._goal, amplitudes)
        np.greater(self._goal, 0.0, out=lit)
        changed = waves.assign(voices, lit)
        if changed:  # do all the channels play their own waveform (again)?
            np.not_equal(waves.ids, self.default_voices.ids, out=onset)
            self._own = not onset.any()
        self._enveloped = self._enveloped or waves.adsr
        if waves.clocked or self._enveloped:
            np.logical_not(was, out=onset)
            np.logical_and(onset, lit, out=onset)
            if changed:
                np.logical_or(onset, waves.changed, out=onset)
            if onset.any():
                np.copyto(waves.onset, float(now), where=onset)
                if self._enveloped:  # from where the envelope is, if the channel sounds
                    np.logical_or(was, env.releasing, out=off)
                    np.logical_not(off, out=off)
                    np.copyto(self._e, 0.0, where=off)
                    env.start(onset, now, self._e, waves.params, waves.settle_s)
        np.copyto(self._held, self._to)
        np.copyto(self._to, amplitudes)
        if self._enveloped:
            if release:  # lit before, off now, with a release: held while it releases
                np.logical_not(lit, out=off)
                np.logical_and(off, was, out=off)
                np.greater(waves.params[HOLD], 0.0, out=onset)
                np.logical_and(off, onset, out=off)
                if off.any():
                    env.now(now, self._e)
                    env.release(off, now, self._e, waves.params, waves.settle_s)
                np.copyto(self._to, self._held, where=env.releasing)
            else:
                env.releasing.fill(False)
                env.any_releasing = False
        np.subtract(self._to, self._from, out=self._delta)
        self._pos = 0 if self.ramp and self._delta.any() else self.ramp

    def _finish_releases(self) -> None:
        """Channels whose release is over go off (their envelope is 0 already)."""
        done = self._env.finished(self.sample, self._waves.params)
        if done is not None:
            np.copyto(self._to, 0.0, where=done)
            np.copyto(self._delta, 0.0, where=done)

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
            wave = self._waves.render(n, self.sample)
            levels, moving = self._levels, self._enveloped
            if moving:
                steady = self._env.steady(self.sample)
                if steady is not None:  # the same on every sample: scale the levels instead
                    levels, moving = self._scaled, False
                    np.multiply(self._delta, steady, out=levels[0])
                    np.multiply(self._to, steady, out=levels[1])
            amplitude = np.matmul(self._weights[self._pos : self._pos + n], levels,
                                  out=self._amplitude[:n])  # fmt: skip
            if moving:
                np.multiply(amplitude, self._env.render(n, self.sample), out=amplitude)
            np.multiply(wave, amplitude, out=wave)
            np.copyto(dest, wave)
        self._pos = min(self._pos + n, self.ramp)
        self.sample += n
        if self._enveloped:
            self._finish_releases()


def synthesize(levels, onsets, *, top: int, carrier_hz, samplerate: float, ramp_s: float,
               length: int, block: int = 4096, waveforms=None, voices=None):  # fmt: skip
    """The signal of a sequence of frames, block by block (what the audio link would play for
    them, sample for sample).

    Parameters
    ----------
    levels : array_like of int, ``(frames, channels)``
        Device levels in channel order, 0 .. ``top``.
    onsets : array_like of int, ``(frames,)``
        The sample at which each frame starts (non-decreasing; the first may be 0).
    top : int
        The highest level (``levels - 1`` of the profile): full amplitude.
    carrier_hz, samplerate, ramp_s, waveforms
        As for :class:`CarrierSynth`.
    length : int
        Samples in all.
    voices : sequence, optional
        Per frame, None (every channel its own waveform) or one waveform-or-None per channel
        (what :meth:`CarrierSynth.voices` takes): a pattern's effects' own waveforms.

    Yields
    ------
    ndarray of float32, ``(m, channels)``
        Consecutive blocks of at most ``block`` samples (one buffer, reused: copy or write it
        out before taking the next).
    """
    levels = np.asarray(levels)
    onsets = np.asarray(onsets, dtype=np.int64)
    if voices is not None and len(voices) > len(onsets):
        raise ValueError(f"voices must be at most one per frame ({len(onsets)}), got "
                         f"{len(voices)}")  # fmt: skip
    synth = CarrierSynth(carrier_hz, samplerate, ramp_s=ramp_s, waveforms=waveforms)
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
            chosen = voices[k] if voices is not None and k < len(voices) else None
            synth.set_target(amplitudes, synth.voices(chosen))
            k += 1
        synth.render(buffer, done, m)
        yield buffer[:m]
