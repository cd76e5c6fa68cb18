"""A trace as the signal an audio interface would play: a multichannel WAV file.

``tactile render ... --out trace.wav`` writes, for labs that play stimuli from their own
software, exactly what :class:`~.audio.AudioLink` would play for the same frames: the same
synthesiser (:func:`~._audio_synth.synthesize`), one channel per actuator in channel order,
each its waveform (the profile's, or what a pattern's effect asks for), frame ``k`` starting at
sample ``round(k * samplerate / rate)``.
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
    waveforms_for,
)
from ..device.profile import DeviceProfile
from ..device.waveform import parse_waveform
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
              carrier_hz: float | None = None, ramp_ms: float = DEFAULT_RAMP_MS,
              waveform=None, voices=None):  # fmt: skip
    """Write the signal of a sequence of frames as a 16-bit PCM WAV file.

    Parameters
    ----------
    path : str or Path
        The ``.wav`` file (written atomically).
    levels : array_like of int, ``(frames, channels)``
        Device levels in channel order (``profile.channels`` of them), 0 .. levels - 1.
    rate_hz : float
        Frames a second.
    profile : DeviceProfile
        The array: its levels, its carriers (``carrier_hz``; 250 Hz if it has none) and its
        waveforms (``waveform``; the plain carrier if it has none).
    samplerate : int
        Samples a second.
    carrier_hz : float, optional
        One carrier for every channel instead of the profile's.
    ramp_ms : float
        The raised-cosine ramp between levels.
    waveform : Waveform or str, optional
        One waveform for every channel instead of the profile's (a spec such as
        ``"square:200"``).
    voices : sequence, optional
        Per frame, None or one waveform-or-None per channel (channel order): what a pattern's
        effects ask for (:meth:`~tactile_core.files.pattern.PatternFrames.voices`).

    Returns
    -------
    int
        Samples per channel written. Full scale (32767) is level ``levels - 1`` at the crest of
        its waveform.

    Raises
    ------
    ValueError
        Naming the argument: levels of the wrong shape or outside 0 .. levels - 1, a rate,
        samplerate, carrier or ramp out of range (those of an ``audio:`` URL), a waveform that
        does not read (naming its field), voices not one per frame, or a signal too long for a
        WAV file (naming the duration).
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
    if waveform is not None:
        waveform = parse_waveform(waveform)
    if voices is not None and len(voices) != len(levels):
        raise ValueError(f"voices must be one per frame ({len(levels)}), got {len(voices)}")
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
                        ramp_s=ramp_s, length=length, waveforms=waveforms_for(profile, waveform),
                        voices=voices)  # fmt: skip
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


def frame_voices(live, profile: DeviceProfile, count: int) -> list | None:
    """The waveforms frames ``0 .. count - 1`` of a frame source ask for, in channel order:
    per frame None or one waveform-or-None per channel (what :func:`write_wav` takes as
    ``voices``); None when the source asks for none (a pattern whose effects name no
    ``waveform``, a shape, a ``.tact`` file)."""
    if not getattr(live, "waveforms", False):
        return None
    cells = profile.array.channel_index.tolist()  # the cell of each channel
    out = []
    for k in range(count):
        chosen = live.voices(k)
        out.append(None if chosen is None else tuple(chosen[c] for c in cells))
    return out


def write_pattern_wav(path, pattern, profile: DeviceProfile, method: str | None = None, *,
                      rate_hz: float = 300.0, mu: float = 0.0, gamma: float = 1.0,
                      **options) -> int:  # fmt: skip
    """Write what an audio interface plays for ``pattern`` on ``profile``: its frames at
    ``rate_hz`` (point sampling), corrected by ``mu`` and ``gamma``, calibrated and quantised as
    the streamer sends them, each channel on its waveform (an effect's own where it asks for
    one). ``options`` are :func:`write_wav`'s (``samplerate``, ``carrier_hz``, ``ramp_ms``,
    ``waveform``). Returns the samples per channel written."""
    from ..rendering.correction import quantize
    from ..rendering.placement import default_method
    from ..rendering.trace import Sampling

    if not isinstance(profile, DeviceProfile):
        raise ValueError(f"profile must be a DeviceProfile, got {type(profile).__name__}")
    target = profile.layout
    method = default_method(target) if method is None else method
    rate_hz = _validate.rate("rate_hz", rate_hz, 1e-3, _validate.MAX_RATE_HZ)
    live = pattern.live(method, target, Sampling(rate_hz, "point"), mu, gamma)
    _, frames = live.render(0, live.n_frames)
    flat = profile.calibrate(frames.reshape(len(frames), -1))  # cell order
    levels = quantize(flat, profile.levels)[:, profile.array.channel_index]
    voices = frame_voices(live, profile, len(levels))
    return write_wav(path, levels, rate_hz, profile, voices=voices, **options)
