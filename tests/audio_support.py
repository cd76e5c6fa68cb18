"""An audio interface without hardware, for the audio tests (test_audio*.py).

PortAudio plays into ALSA's ``file`` plugin (slave: a ``null`` PCM), whose file is a named pipe
that a thread of the test reads at the samplerate: the thread is the sound card's converter, so
the stream is paced as a real one is (the ``null`` PCM alone takes samples as fast as they come,
hundreds of times real time). ALSA reads its configuration once per process, so the audio side
runs in a child process started with :meth:`CaptureSink.env`.

The tests need PortAudio (``apt-get install libportaudio2``) and ALSA's library; without them
they are skipped with a note, and under ``TACTILE_REQUIRE_AUDIO=1`` (``.ci/run`` sets it) they
fail instead.

The analysis reads what was captured back into frames: each channel's carrier (phase from the
whole capture), each frame's onset (the ramp fitted where the frame's levels change) and the
level it holds (the carrier's amplitude between ramps, by least squares).
"""

from __future__ import annotations

import ctypes.util
import fcntl
import math
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

DEVICE = "tactcap"
F_SETPIPE_SZ = 1031
CHUNK_FRAMES = 64


def require_audio() -> None:
    """Skip (or, under TACTILE_REQUIRE_AUDIO=1, fail) without PortAudio and ALSA (Linux)."""
    if not sys.platform.startswith("linux"):
        pytest.skip("the audio capture tests play through ALSA (Linux)")
    missing = [lib for lib in ("portaudio", "asound") if ctypes.util.find_library(lib) is None]
    if not missing:
        try:
            import sounddevice  # noqa: F401
        except (OSError, ImportError) as exc:
            missing.append(f"sounddevice ({exc})")
    if missing:
        message = f"audio tests need {', '.join(missing)} (apt-get install libportaudio2)"
        if os.environ.get("TACTILE_REQUIRE_AUDIO"):
            pytest.fail(message)
        pytest.skip(message)


class CaptureSink:
    """An ALSA PCM named :data:`DEVICE` whose samples land in :meth:`samples`.

    Parameters
    ----------
    folder : Path
        Where the configuration and the pipe go (a test's ``tmp_path``).
    channels, samplerate : int
        The stream's, to pace the reading (float32 samples).
    """

    def __init__(self, folder: Path, channels: int, samplerate: int):
        self.frame_bytes = 4 * channels
        self.channels = channels
        self.samplerate = samplerate
        self.pipe = folder / "capture.pipe"
        os.mkfifo(self.pipe)
        self.config = folder / "asound.conf"
        self.config.write_text(
            "</usr/share/alsa/alsa.conf>\n"
            f"pcm.{DEVICE} {{\n"
            "    type file\n"
            "    slave.pcm { type null }\n"
            f'    file "{self.pipe}"\n'
            '    format "raw"\n'
            "}\n"
        )
        self.sessions: list[bytes] = []
        self.played_frames = 0
        """Sample frames read of the PCM's current opening so far: the stream's audio time."""
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._read, name="sink", daemon=True)
        self._thread.start()

    def env(self) -> dict:
        """The environment of a child process that plays into this sink."""
        return {**os.environ, "ALSA_CONFIG_PATH": str(self.config)}

    def _read(self) -> None:
        # Every opening of the PCM (PortAudio's probes too) opens the pipe: read each session to
        # its end; the one with samples is the stream.
        while not self._stop.is_set():
            fd = os.open(self.pipe, os.O_RDONLY)
            try:
                fcntl.fcntl(fd, F_SETPIPE_SZ, 4096)  # one page: little slack before the reader
            except OSError:
                pass
            chunks, total, start = [], 0, None
            self.played_frames = 0
            while True:
                if start is not None:
                    due = start + total / self.frame_bytes / self.samplerate
                    wait = due - time.perf_counter()
                    if wait > 0:
                        time.sleep(wait)
                data = os.read(fd, CHUNK_FRAMES * self.frame_bytes)
                if not data:
                    break
                start = time.perf_counter() if start is None else start
                chunks.append(data)
                total += len(data)
                self.played_frames = total // self.frame_bytes
            os.close(fd)
            if chunks:
                self.sessions.append(b"".join(chunks))

    def samples(self, timeout_s: float = 10.0) -> np.ndarray:
        """Stop reading; what the stream played, ``(samples, channels)`` float32."""
        self._stop.set()
        try:  # wake the reader if it waits for another opening
            os.close(os.open(self.pipe, os.O_WRONLY | os.O_NONBLOCK))
        except OSError:
            pass
        self._thread.join(timeout_s)
        assert not self._thread.is_alive(), "the sink's reader did not finish"
        assert len(self.sessions) == 1, f"{len(self.sessions)} streams with samples"
        data = self.sessions[0]
        usable = len(data) - len(data) % self.frame_bytes
        return np.frombuffer(data[:usable], dtype=np.float32).reshape(-1, self.channels)


def run_cli(sink: CaptureSink, args: list[str], **kwargs) -> subprocess.Popen:
    """``python -m tactile_core.cli ARGS`` in a child that plays into ``sink``."""
    return subprocess.Popen(
        [sys.executable, "-m", "tactile_core.cli", *args],
        env=sink.env(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **kwargs,
    )


# --- reading a capture back ------------------------------------------------------------------


def ramp(n: int) -> np.ndarray:
    """The documented raised cosine: ``(1 - cos(pi (j + 0.5) / n)) / 2``, ``j < n``."""
    j = np.arange(n)
    return 0.5 - 0.5 * np.cos(np.pi * (j + 0.5) / max(n, 1))


def carrier_phase(x: np.ndarray, hz: float, samplerate: float) -> np.ndarray:
    """The unit carrier ``sin(2 pi hz s / samplerate + phi)`` of one channel, ``phi`` fitted
    over the whole capture (the amplitude is never negative, so the fit is the phase)."""
    s = np.arange(len(x))
    w = 2 * np.pi * hz / samplerate
    phi = math.atan2(float(x @ np.cos(w * s)), float(x @ np.sin(w * s)))
    return np.sin(w * s + phi)


def carrier_hz(x: np.ndarray, samplerate: float) -> float:
    """The carrier of one channel from its upward zero crossings (interpolated): the median
    period between neighbours, those spanning a silence left out."""
    below = np.flatnonzero((x[:-1] < 0) & (x[1:] > 0))  # not into or out of a silence
    crossings = below + x[below] / (x[below] - x[below + 1])
    periods = np.diff(crossings)
    typical = np.median(periods)
    periods = periods[np.abs(periods - typical) < 0.2 * typical]
    assert len(periods) >= 20, f"too few carrier periods to measure ({len(periods)})"
    return samplerate / float(np.median(periods))


def distinct(time_s: np.ndarray, amplitudes: np.ndarray):
    """The frames that change something: their times and amplitudes (``(k,)``, ``(k, n)``)."""
    keep = np.r_[True, np.any(np.diff(amplitudes, axis=0) != 0, axis=1)]
    return time_s[keep], amplitudes[keep]


def fit_onsets(x, carriers, starts, amplitudes, ramp_n: int, reach: int):
    """Where each frame's ramp starts: for frame ``k``, the start within ``starts[k] +- reach``
    that best explains the channels that change there (from silence, for the first), where the
    frames around it are far enough not to blur it.

    Returns ``(frames, shift)``: the frames fitted and each one's start minus ``starts[k]``.
    """
    w_ext = np.concatenate([np.zeros(2 * reach + ramp_n), ramp(ramp_n), np.ones(2 * reach)])
    zero = 2 * reach + ramp_n  # index of w(0) in w_ext
    window = np.arange(-reach, ramp_n + reach)
    shifts = np.arange(-reach, reach + 1)
    fitted, found = [], []
    before = np.vstack([np.zeros_like(amplitudes[:1]), amplitudes[:-1]])  # silence first
    for k in range(len(starts)):
        lo = starts[k] - reach
        hi = starts[k] + ramp_n + reach
        if lo < 0 or hi > len(x):
            continue
        if k and starts[k] - starts[k - 1] < ramp_n + 2 * reach:
            continue
        if k + 1 < len(starts) and starts[k + 1] - starts[k] < ramp_n + 2 * reach:
            continue
        changed = np.flatnonzero(amplitudes[k] != before[k])
        j = window[None, :] - shifts[:, None] + zero  # (shifts, window) ramp indices
        error = np.zeros(len(shifts))
        for c in changed:
            a, b = before[k, c], amplitudes[k, c]
            seg, car = x[lo:hi, c], carriers[lo:hi, c]
            model = (a + (b - a) * w_ext[j]) * car[None, :]
            error += ((seg[None, :] - model) ** 2).sum(axis=1)
        fitted.append(k)
        found.append(int(shifts[np.argmin(error)]))
    return np.array(fitted), np.array(found)


def plateau_levels(x, carriers, onsets, ramp_n: int, margin: int = 8):
    """Each frame's amplitude per channel between its ramp and the next onset (each known to
    ``margin`` samples), by least squares against the unit carrier: ``(frames - 1,
    channels)``, NaN where too short to tell."""
    out = np.full((len(onsets) - 1, x.shape[1]), np.nan)
    for k in range(len(onsets) - 1):
        a, b = onsets[k] + ramp_n + margin, onsets[k + 1] - margin
        if b - a < 16 or b > len(x):
            continue
        car = carriers[a:b]
        power = (car**2).sum(axis=0)
        ok = power > 2.0  # at least a few samples' worth of carrier
        out[k, ok] = (x[a:b] * car).sum(axis=0)[ok] / power[ok]
    return out


def read_back(x, time_s, levels, *, carriers, samplerate, ramp_n, top, reach, timed=True):
    """Compare a capture with the frames a stream recorded.

    Parameters
    ----------
    x : ndarray ``(samples, channels)``
        What was played.
    time_s, levels : ndarray ``(frames,)``, ``(frames, channels)``
        The recording: each frame's time (its time to play, for a timed frame) and its levels
        in channel order. The last row is the all-off frame of the stream's end, a frame for
        now: it drops the timed frames still waiting (those recorded after its time are left
        out), and plays at the next block, off the grid of timed frames (its onset is left
        out; the silence after it is measured instead).
    reach : int
        How far from where the recording puts it an onset is looked for (samples): the onsets
        of frames closer together than a ramp and twice this are not fitted, and their levels
        not read; nor are those of frames found at the bound (``missed``: further off).
    timed : bool
        The frames were timed: the final frame (for now) starts at its time or later, so the
        plateau before it ends there. Frames for now start anywhere in the block after their
        time, the final one too, up to half a block before where the others' median shift
        puts it: the plateau before it is not read (it read a level low when the final frame
        came early in its block, 1 run in ~20).

    Returns
    -------
    dict
        ``carrier_hz`` (each playing channel's measured carrier), ``frames`` (onsets fitted
        within the reach), ``missed`` (found at its bound),
        ``onset_error`` (samples: each fitted onset minus where the recording puts it, less
        their median, the sink's constant latency), ``level_error`` (levels: the largest
        difference between a read-back plateau and the level sent), ``levels_read``,
        ``silence_ms`` (exact zeros at the end), ``max_step`` (the largest sample-to-sample
        change).
    """
    played = time_s <= time_s[-1]
    order = np.argsort(time_s[played], kind="stable")
    time_s, amps = time_s[played][order], levels[played][order] / top
    t, a = distinct(time_s, amps)
    playing = np.flatnonzero(a.any(axis=0))
    car = np.zeros_like(x, dtype=np.float64)
    measured = {}
    for c in playing:
        car[:, c] = carrier_phase(x[:, c], carriers[c], samplerate)
        measured[int(c)] = carrier_hz(x[:, c].astype(np.float64), samplerate)
    lit = int(np.flatnonzero(np.abs(x).max(axis=1) > 1e-3)[0])
    first = int(np.flatnonzero(a.any(axis=1))[0])
    starts = np.round(lit + (t - t[first]) * samplerate).astype(int)
    for _ in range(2):  # centre the grid on the median onset, then fit again
        fitted, shift = fit_onsets(x, car, starts, a, ramp_n, reach)
        starts = starts + int(np.median(shift[fitted < len(t) - 1]))
    fitted, shift = fit_onsets(x, car, starts, a, ramp_n, reach)
    keep = fitted < len(t) - 1  # not the final frame
    fitted, shift = fitted[keep], shift[keep]
    inside = np.abs(shift) < reach  # at the bound: further off than the search (a stall)
    missed = int((~inside).sum())
    fitted, shift = fitted[inside], shift[inside]
    onsets = starts.copy()
    onsets[fitted] += shift
    plateau = plateau_levels(x, car, onsets, ramp_n)
    known = np.zeros(len(t), dtype=bool)
    known[fitted] = True
    known[-1] = timed  # the final frame starts at its time or later: the one before holds until
    plateau[~(known[:-1] & known[1:])] = np.nan  # a plateau between two known onsets only
    nonzero = np.flatnonzero(np.abs(x).max(axis=1) > 0)
    return {
        "carrier_hz": measured,
        "frames": len(shift),
        "missed": missed,
        "onset_error": shift - np.median(shift),
        "level_error": float(np.nanmax(np.abs(plateau - a[:-1])) * top),
        "levels_read": int(np.isfinite(plateau).sum()),
        "silence_ms": (len(x) - 1 - nonzero[-1]) / samplerate * 1e3,
        "max_step": float(np.abs(np.diff(x, axis=0)).max()),
    }
