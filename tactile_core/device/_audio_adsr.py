"""The ADSR envelopes of an audio array's channels, block by block, without allocating.

A channel whose waveform has an envelope (:class:`~.waveform.Adsr`) multiplies its amplitude by
``E``, counted in samples from the *stage*'s start (an onset, or the channel going off): for the
``j``-th sample since (``j = 0`` the first), with ``u = j + 1`` and the times ``A``, ``D``,
``R`` in samples (``ms * samplerate / 1000``, at least 1)::

    lit:     E = e0 + (1 - e0) clip(u / A) - (1 - S) clip((u - A) / D)
    release: E = r0 max(1 - u / R, 0)
    off:     E = 0

``clip`` to [0, 1]; ``e0`` is where the envelope was at the onset (0 from silence, else where
a release had left it), ``r0`` where it was when the channel went off. So the attack reaches 1
on sample ``A - 1`` after the onset, the decay reaches ``S`` on sample ``A + D - 1``, the release
reaches 0 on sample ``R - 1`` after the channel went off. A channel without an envelope has
``E = 1``.

Each of the clipped ramps is a difference of two hinges, ``w clip(x) = max(w x, 0) - max(w x -
w, 0)`` for ``w >= 0``, and each hinge's argument is affine in ``u``: so the whole envelope of
every channel is two matrix products ``[j, 1] @ K``, a constant ``(n, channels)`` and four
hinges ``(n, 4 channels)``, one ``max(., 0)`` and four additions.
"""

from __future__ import annotations

import numpy as np

from ._audio_voices import ATTACK_N, DECAY_N, HAS_ADSR, RELEASE_N, SUSTAIN


class Envelopes:
    """The channels' envelopes: the stage each is in, and a block of their values.

    Parameters
    ----------
    channels : int
    block : int
        The most samples :meth:`render` is asked for at once.

    Notes
    -----
    Per channel and term (the constant, then the four hinges) a stage holds a slope and a bias
    in ``u`` and the sample it started on. A block is one batched product ``[j, 1] @ [slope;
    slope u0 + bias]`` per term into ``(5, n, channels)``, one ``max(., 0)`` on the hinges and
    four additions. Once every channel's envelope holds still (sustaining, off, or without an
    envelope) :meth:`steady` gives its value per channel instead, and a block costs nothing
    more.
    """

    def __init__(self, channels: int, block: int):
        n = self.channels = channels
        self.slope = np.zeros((5, n))  # per term and channel, in u: constant, four hinges
        self.bias = np.zeros((5, n))
        self.bias[0] = 1.0  # E = 1: no envelope
        self.since = np.zeros((5, n))  # the sample the stage started on
        self.releasing = np.zeros(n, dtype=bool)
        self.any_releasing = False
        """Some channel may be releasing (:attr:`releasing` says which)."""
        self._new = np.zeros((2, 5, n))  # scratch: a stage's slopes and biases
        self.steady_from = 0.0
        """From this sample on every channel's envelope holds still (:meth:`steady`)."""
        self._steady = np.ones(n)
        self._steady_valid = False
        self._k = np.zeros((5, 2, n))  # per term: [slope; value at the block's first sample]
        self._lin = np.ones((5, block, 2))
        self._lin[:, :, 0] = np.arange(block)
        self._z = np.zeros((5, block, n))
        self._u = np.zeros((5, n))
        self._v = np.zeros((2, n))
        self._b = np.zeros((2, n), dtype=bool)

    def now(self, sample: int, out: np.ndarray) -> np.ndarray:
        """``E`` of the last sample rendered (the one before ``sample``), ``(channels,)``."""
        u = self._u
        np.subtract(float(sample), self.since, out=u)
        np.multiply(u, self.slope, out=u)
        np.add(u, self.bias, out=u)
        np.maximum(u, 0.0, out=u)  # (the constant is never negative)
        return self._sum(u, out)

    @staticmethod
    def _sum(terms, out):
        """``K0 + H1 - H2 - H3 + H4`` of the five terms (rows or blocks), into ``out``."""
        np.add(terms[0], terms[1], out=out)
        np.subtract(out, terms[2], out=out)
        np.subtract(out, terms[3], out=out)
        np.add(out, terms[4], out=out)
        return out

    def _commit(self, where: np.ndarray, sample: int, settle_s: float) -> None:
        """Channels ``where`` start at ``sample`` the stage whose slopes and biases are in
        ``self._new``; every envelope holds still ``settle_s`` samples on at the latest."""
        new_slope, new_bias = self._new
        np.copyto(self.slope, new_slope, where=where)
        np.copyto(self.bias, new_bias, where=where)
        np.copyto(self.since, float(sample), where=where)
        self.steady_from = max(self.steady_from, sample + settle_s)
        self._steady_valid = False

    def steady(self, sample: int) -> np.ndarray | None:
        """Each channel's envelope, ``(channels,)``, if none changes from ``sample`` on (then
        it is the same on every sample); None while some channel's may still move."""
        if sample < self.steady_from:
            return None
        if not self._steady_valid:
            self.now(sample + 1, self._steady)
            self._steady_valid = True
        return self._steady

    def start(self, where: np.ndarray, sample: int, e0: np.ndarray, params: np.ndarray,
              settle_s: float) -> None:  # fmt: skip
        """Channels ``where`` are lit from ``sample`` (an onset, or a new waveform): attack from
        ``e0`` (``(channels,)``), decay, sustain, as their ``params`` say (rows of a
        :class:`~._audio_voices.VoiceSet`); ``E = 1`` for those without an envelope. Every
        envelope holds still ``settle_s`` samples on at the latest (the longest attack and
        decay)."""
        has, a, d = params[HAS_ADSR], params[ATTACK_N], params[DECAY_N]
        slope, bias = self._new
        w1, w2 = self._v[0], self._v[1]
        slope[0].fill(0.0)
        np.multiply(e0, has, out=bias[0])  # the constant: e0 with an envelope, 1 without
        np.subtract(1.0, has, out=w1)
        np.add(bias[0], w1, out=bias[0])
        np.subtract(1.0, bias[0], out=w1)  # attack: from e0 to 1 (nothing without an envelope)
        np.divide(w1, a, out=slope[1])
        bias[1].fill(0.0)
        np.copyto(slope[2], slope[1])
        np.negative(w1, out=bias[2])
        np.subtract(1.0, params[SUSTAIN], out=w2)
        np.multiply(w2, has, out=w2)  # decay: from 1 to S, A samples in
        np.divide(w2, d, out=slope[3])
        np.multiply(slope[3], a, out=bias[3])
        np.negative(bias[3], out=bias[3])
        np.copyto(slope[4], slope[3])
        np.subtract(bias[3], w2, out=bias[4])
        self._commit(where, sample, settle_s)
        spare = self._b[1]
        np.logical_not(where, out=spare)
        np.logical_and(self.releasing, spare, out=self.releasing)

    def release(self, where: np.ndarray, sample: int, r0: np.ndarray, params: np.ndarray,
                settle_s: float) -> None:  # fmt: skip
        """Channels ``where`` go off at ``sample``: from ``r0`` to 0 over their release (one
        hinge, ``max(r0 - r0 u / R, 0)``: exactly 0 after it); every envelope holds still
        ``settle_s`` samples on at the latest (the longest release)."""
        slope, bias = self._new
        slope.fill(0.0)
        bias.fill(0.0)
        np.divide(r0, params[RELEASE_N], out=slope[1])
        np.negative(slope[1], out=slope[1])
        np.copyto(bias[1], r0)
        self._commit(where, sample, settle_s)
        np.logical_or(self.releasing, where, out=self.releasing)
        self.any_releasing = True

    def finished(self, sample: int, params: np.ndarray) -> np.ndarray | None:
        """The releasing channels whose release is over by ``sample`` (bool ``(channels,)``),
        turned off (``E = 0``); None if there are none."""
        if not self.any_releasing:
            return None
        done, spare = self._b
        elapsed = self._v[0]
        np.subtract(float(sample), self.since[0], out=elapsed)
        np.greater_equal(elapsed, params[RELEASE_N], out=done)
        np.logical_and(done, self.releasing, out=done)
        if not done.any():
            return None
        self._new.fill(0.0)
        self._commit(done, sample, 0.0)
        np.logical_not(done, out=spare)
        np.logical_and(self.releasing, spare, out=self.releasing)
        self.any_releasing = bool(self.releasing.any())
        return done

    def render(self, n: int, sample: int) -> np.ndarray:
        """``E`` for samples ``sample .. sample + n - 1``: a ``(n, channels)`` view (valid until
        the next call)."""
        k, z = self._k, self._z[:, :n]
        at = self._u
        np.subtract(float(sample + 1), self.since, out=at)  # u of the block's first sample
        np.multiply(at, self.slope, out=at)
        np.add(at, self.bias, out=at)
        np.copyto(k[:, 0], self.slope)
        np.copyto(k[:, 1], at)
        np.matmul(self._lin[:, :n], k, out=z)
        np.maximum(z[1:], 0.0, out=z[1:])
        return self._sum(z, z[0])
