"""A trace as the carrier signal an audio interface would play: a multichannel WAV file.

``tactile render ... --out trace.wav`` writes, for labs that play stimuli from their own
software, exactly what :class:`~.audio.AudioLink` would play for the same frames: the same
synthesiser (:func:`~._audio_synth.synthesize`), one channel per actuator in channel order,
frame ``k`` starting at sample ``round(k * samplerate / rate)``.
"""

from __future__ import annotations

import wave

import numpy as np

from .._shared import validate as _validate
from .._shared.outfile import atomic_file
from ..device.audio import (
    CARRIER_RANGE_HZ,
    DEFAULT_RAMP_MS,
    RAMP_RANGE_MS,
    SAMPLERATE_RANGE,
    carriers_for,
    synthesize,
)
from ..device.profile import DeviceProfile
from ..rendering.correction import quantize

TAIL_S = 0.01
"""Silence after the final fade: the file ends as the stream does, in zeros."""
MAX_WAV_BYTES = 2**32 - 2**20
"""A WAV file's sizes are 32-bit: a little under 4 GiB of samples."""


def wav_layout(frames: int, rate_hz: float, samplerate: int, ramp_s: float) -> tuple:
    """Where a trace's frames start in its signal and how long it is: ``(onsets, length)``.

    The ``frames`` frames start at ``round(k * samplerate / rate_hz)``; the last one holds for a
    frame's time, then every channel fades out (an all-off frame: the stream's end) and the
    file ends :data:`TAIL_S` after the fade, so it ends in silence.
    """
    onsets = np.round(np.arange(frames + 1) * samplerate / rate_hz).astype(np.int64)
    length = int(onsets[-1] + round(ramp_s * samplerate) + round(TAIL_S * samplerate))
    return onsets, length


def _check_levels(levels: np.ndarray, top: int) -> None:
    """``ValueError`` naming the first entry of ``levels`` that is not a level 0 .. ``top``."""
    if levels.dtype.kind not in "iuf":
        raise ValueError(f"levels must be device levels 0..{top} (integers), got {levels.dtype}")
    with np.errstate(invalid="ignore"):
        bad = ~((levels >= 0) & (levels <= top) & (levels == np.round(levels)))
    if bad.any():
        k, c = np.argwhere(bad)[0]
        raise ValueError(f"levels[{k}, {c}] must be a device level 0..{top}, got "
                         f"{_validate.shown(levels[k, c].item())}")  # fmt: skip


def frame_levels(frames, profile: DeviceProfile) -> np.ndarray:
    """Corrected frames as the device levels the streamer sends, in channel order: calibrated
    by the profile, quantised to its levels (what :func:`write_wav` takes).

    Parameters
    ----------
    frames : array_like of float, ``(n, rows, cols)`` or ``(n, size)``
        Corrected intensities in [0, 1], in the layout's cell order.
    profile : DeviceProfile

    Returns
    -------
    ndarray of int, ``(n, channels)``
    """
    frames = np.asarray(frames, dtype=np.float64)
    flat = profile.calibrate(frames.reshape(len(frames), -1))  # cell order
    return quantize(flat, profile.levels)[:, profile.array.channel_index]


def write_wav(path, levels, rate_hz: float, profile: DeviceProfile, *, samplerate: int = 48000,
              carrier_hz: float | None = None, ramp_ms: float = DEFAULT_RAMP_MS):  # fmt: skip
    """Write the carrier signal of a sequence of frames as a 16-bit PCM WAV file.

    Parameters
    ----------
    path : str or Path
        The ``.wav`` file (written atomically).
    levels : array_like of int, ``(frames, channels)``
        Device levels in channel order (``profile.channels`` of them), 0 .. levels - 1.
    rate_hz : float
        Frames a second.
    profile : DeviceProfile
        The array: its levels and its carriers (``carrier_hz``; 250 Hz if it has none).
    samplerate : int
        Samples a second.
    carrier_hz : float, optional
        One carrier for every channel instead of the profile's.
    ramp_ms : float
        The raised-cosine ramp between levels.

    Returns
    -------
    int
        Samples per channel written. Full scale (32767) is level ``levels - 1`` at the crest of
        its carrier.

    Raises
    ------
    ValueError
        Naming the argument: levels of the wrong shape or outside 0 .. levels - 1, a rate,
        samplerate, carrier or ramp out of range (those of an ``audio:`` URL), or a signal too
        long for a WAV file (naming the duration).
    """
    levels = np.asarray(levels)
    n = profile.channels
    if levels.ndim != 2 or levels.shape[1] != n:
        raise ValueError(f"levels must be (frames, {n}) in channel order, got {levels.shape}")
    _check_levels(levels, profile.levels - 1)
    rate_hz = _validate.rate("rate_hz", rate_hz, 1e-3)
    samplerate = _validate.integer("samplerate", samplerate, *SAMPLERATE_RANGE)
    ramp_s = _validate.in_range("ramp_ms", ramp_ms, *RAMP_RANGE_MS) / 1e3
    if carrier_hz is not None:
        carrier_hz = _validate.in_range("carrier_hz", carrier_hz, *CARRIER_RANGE_HZ)
    frames = np.vstack([levels, np.zeros((1, n), dtype=levels.dtype)])  # then all off
    onsets, length = wav_layout(len(levels), rate_hz, samplerate, ramp_s)
    size = length * n * 2
    if size > MAX_WAV_BYTES:
        raise ValueError(
            f"a WAV file holds at most 4 GiB: {length / samplerate:.0f} s at {samplerate} Hz "
            f"on {n} channels is {size / 2**30:.1f} GiB (shorten the duration or lower the "
            "samplerate)"
        )
    blocks = synthesize(frames, onsets, top=profile.levels - 1,
                        carrier_hz=carriers_for(profile, carrier_hz), samplerate=samplerate,
                        ramp_s=ramp_s, length=length)  # fmt: skip
    pcm = np.empty((4096, n), dtype="<i2")
    with atomic_file(path, binary=True) as f, wave.open(f, "wb") as out:
        out.setnchannels(n)
        out.setsampwidth(2)
        out.setframerate(samplerate)
        out.setnframes(length)
        for block in blocks:
            m = len(block)
            np.multiply(block, 32767.0, out=block)
            np.rint(block, out=block)
            pcm[:m] = block
            out.writeframes(pcm[:m].tobytes())
    return length
