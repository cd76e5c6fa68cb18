"""A sensor on an audio interface's input, through PortAudio (``sounddevice.InputStream``).

``audio:NAME?channel=N&samplerate=R&latency_ms=L``: the input device ``NAME`` (its index, its
name, or a part of its name only one input device has; the default input device for
``audio:``), the sensor on input ``N`` (from 1, as the interface labels them; 1 by default),
``R`` samples per second (the device's default otherwise), and ``L`` ms of converter latency to
take off the sample clock (0 by default; see :mod:`._recording`). Up to :data:`MAX_CHANNELS`
inputs are recorded, so that a sensor on another input than asked is found.
"""

from __future__ import annotations

import math
import threading
import time
import urllib.parse
from collections import deque
from dataclasses import dataclass

import numpy as np

from ..._shared import validate as _validate
from .._audio_url import SAMPLERATE_RANGE, is_audio_url, is_index, load_sounddevice
from .._link_error import LinkError
from ._recording import Recording, fit_sample_clock

KEYS = ("channel", "samplerate", "latency_ms")
MAX_CHANNELS = 8
"""Inputs recorded at most (the sensor's and those before and after it)."""
KEEP_S = 40.0
"""Seconds of samples an input keeps (older ones are let go): a tactor's block and more; 61 MB
at most (8 inputs at 48 kHz)."""


@dataclass(frozen=True)
class InputURL:
    """What an ``audio:`` input URL asks for."""

    device: str = ""
    channel: int = 1
    samplerate: int | None = None
    latency_ms: float = 0.0


def parse_input_url(url: str) -> InputURL:
    """Read an ``audio:`` input URL.

    Raises
    ------
    ValueError
        Naming the key: an unknown or repeated one, or a value out of range (channel < 1, a
        samplerate outside 8000-384000 Hz, a latency outside 0-500 ms).

    Examples
    --------
    >>> parse_input_url("audio:USB?channel=2")
    InputURL(device='USB', channel=2, samplerate=None, latency_ms=0.0)
    """
    if not is_audio_url(url):
        raise ValueError(f"a sensor's input must be an audio: URL (audio:NAME?channel=N) or "
                         f"'sim', got {_validate.shown(url)}")  # fmt: skip
    rest = url[len("audio:") :]
    name, _, query = rest.partition("?")
    fields: dict = {"device": urllib.parse.unquote(name).strip()}
    for pair in query.split("&") if query else ():
        key, eq, text = pair.partition("=")
        if key not in KEYS:
            raise ValueError(f"input URL {url!r}: unknown key {key!r} (known: {', '.join(KEYS)})")
        if key in fields or not eq:
            raise ValueError(f"input URL {url!r}: key {key!r} given twice or without a value")
        fields[key] = _validate.decimal_text(key, urllib.parse.unquote(text),
                                             whole=key != "latency_ms")  # fmt: skip
    checks = {"channel": (1, 64), "samplerate": SAMPLERATE_RANGE, "latency_ms": (0.0, 500.0)}
    for key, (lo, hi) in checks.items():
        value = fields.get(key)
        if value is not None and not (math.isfinite(value) and lo <= value <= hi):
            raise ValueError(f"input URL {url!r}: {key} must be within {lo:g}-{hi:g}, "
                             f"got {_validate.shown(value)}")  # fmt: skip
    return InputURL(**fields)


def input_devices(sd) -> list[dict]:
    """The input devices PortAudio knows, with ``index``, ``name``, ``max_input_channels``,
    ``default_samplerate`` and ``hostapi`` (its name)."""
    apis = [api["name"] for api in sd.query_hostapis()]
    return [{**d, "hostapi": apis[d["hostapi"]]} for d in sd.query_devices()
            if d["max_input_channels"] > 0]  # fmt: skip


def find_input_device(sd, name: str) -> dict:
    """The input device ``name`` names ('' the default one, digits an index, else the exact
    name or the only one containing it); :class:`LinkError` listing the inputs otherwise."""
    devices = input_devices(sd)
    listing = "; ".join(
        f"{d['index']}: {d['name']!r} ({d['max_input_channels']} inputs)" for d in devices[:20]
    )
    listing = listing or "PortAudio finds no audio input device"
    if name == "":
        try:
            index = int(sd.default.device[0])
        except (TypeError, ValueError, IndexError, KeyError):
            index = -1
        chosen = [d for d in devices if d["index"] == index]
    elif is_index(name):
        chosen = [d for d in devices if d["index"] == int(name)]
    else:
        chosen = [d for d in devices if d["name"] == name] or [
            d for d in devices if name.lower() in d["name"].lower()
        ]
    if len(chosen) != 1:
        what = "ambiguous" if chosen else "not found"
        raise LinkError(f"audio input {name or '(default)'!r} {what}; the inputs are {listing}")
    return chosen[0]


class AudioInput:
    """Records a sensor on an audio interface's input.

    Parameters
    ----------
    url : str
        ``audio:NAME?channel=N&samplerate=R&latency_ms=L``.
    keep_s : float
        Seconds of samples kept.
    sd : module, optional
        ``sounddevice`` (or a stand-in with its interface, for tests).

    Raises
    ------
    ValueError, LinkError
        A bad URL; PortAudio missing; no such input; too few inputs; a samplerate the device
        does not take.
    """

    def __init__(self, url: str, *, keep_s: float = KEEP_S, sd=None):
        asked = parse_input_url(url)
        self.sd = sd if sd is not None else load_sounddevice()
        device = find_input_device(self.sd, asked.device)
        have = int(device["max_input_channels"])
        if asked.channel > have:
            raise LinkError(f"audio input {device['name']!r} has {have} inputs: channel="
                            f"{asked.channel} is not one of them")  # fmt: skip
        self.samplerate = int(asked.samplerate or round(device["default_samplerate"]))
        self.channels = min(have, max(asked.channel, MAX_CHANNELS))
        self.channel = asked.channel - 1
        self.latency_s = asked.latency_ms / 1e3
        self.keep_s = keep_s
        self.device = device
        try:
            self.sd.check_input_settings(device=device["index"], channels=self.channels,
                                         dtype="float32", samplerate=self.samplerate)  # fmt: skip
        except Exception as exc:  # sounddevice.PortAudioError, ValueError
            raise LinkError(f"audio input {device['name']!r} cannot record {self.channels} "
                            f"channels at {self.samplerate} Hz: {exc}") from None  # fmt: skip
        self.description = (f"an audio input ({device['name']!r}, input {asked.channel}, "
                            f"{self.samplerate} Hz)")  # fmt: skip
        self._lock = threading.Condition()
        self._chunks: deque = deque()
        self._first = 0  # global index of the first sample kept
        self._total = 0
        self._arrivals: deque = deque()
        self.overflows = 0
        self._stream = None

    def start(self) -> AudioInput:
        """Open the input stream and start recording."""
        self._stream = self.sd.InputStream(device=self.device["index"], channels=self.channels,
                                           samplerate=self.samplerate, dtype="float32",
                                           callback=self._callback)  # fmt: skip
        self._stream.start()
        return self

    def _callback(self, indata, frames, time_info, status) -> None:
        now = time.perf_counter()
        with self._lock:
            if status:
                self.overflows += 1
            self._chunks.append(np.array(indata, dtype=np.float32, copy=True))
            self._total += frames
            self._arrivals.append((self._total, now))
            keep = int(self.keep_s * self.samplerate)
            while self._chunks and self._total - self._first - len(self._chunks[0]) >= keep:
                self._first += len(self._chunks.popleft())
            while len(self._arrivals) > 2 and self._arrivals[1][0] <= self._first:
                self._arrivals.popleft()
            self._lock.notify_all()

    @property
    def recorded(self) -> int:
        """Samples recorded since the stream started (those let go included)."""
        return self._total

    def clear(self) -> None:
        """Let go of everything recorded so far (the sample clock keeps its history)."""
        with self._lock:
            self._first = self._total
            self._chunks.clear()

    def covers(self, host_s: float) -> bool:
        """True once samples taken after host time ``host_s`` have arrived."""
        with self._lock:
            return bool(self._arrivals) and self._arrivals[-1][1] >= host_s + self.latency_s

    def wait_until(self, host_s: float, timeout_s: float) -> bool:
        """Wait until :meth:`covers` ``host_s`` (at most ``timeout_s``); True if it does."""
        deadline = time.monotonic() + timeout_s
        with self._lock:
            while not (self._arrivals and self._arrivals[-1][1] >= host_s + self.latency_s):
                left = deadline - time.monotonic()
                if left <= 0:
                    return False
                self._lock.wait(min(left, 0.1))
        return True

    def recording(self, since_s: float | None = None) -> Recording:
        """What is kept so far (from host time ``since_s`` on, if given), with its sample
        clock."""
        with self._lock:
            chunks, first = list(self._chunks), self._first
            arrivals = list(self._arrivals)
        if arrivals:
            end, when = zip(*arrivals)
            zero_s, ratio = fit_sample_clock(end, when, self.samplerate)
        else:
            zero_s, ratio = time.perf_counter(), 1.0
        zero_s -= self.latency_s
        if since_s is not None:  # whole chunks from the one holding since_s
            wanted = (since_s - zero_s) / ratio * self.samplerate
            while len(chunks) > 1 and first + len(chunks[0]) <= wanted:
                first += len(chunks.pop(0))
        samples = (np.concatenate(chunks) if chunks
                   else np.zeros((0, self.channels), dtype=np.float32))  # fmt: skip
        start_s = zero_s + first / self.samplerate * ratio
        return Recording(samples, self.samplerate, start_s, ratio, self.channel, self.description)

    def stop(self) -> None:
        """Stop recording and close the stream."""
        stream, self._stream = self._stream, None
        if stream is not None:
            stream.stop()
            stream.close()

    def __enter__(self) -> AudioInput:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
