"""A stand-in for ``sounddevice``, for testing the audio link exactly and without PortAudio.

:class:`FakeSoundDevice` has the calls the link makes (``query_devices``, ``query_hostapis``,
``default``, ``check_output_settings``, ``OutputStream``, ``CallbackAbort``). Its stream runs no
thread: :class:`AudioClock`, the link's clock, runs one block of the callback each time the link
waits (``sleep``), and the test runs more with :meth:`FakeStream.pump`; each block advances the
clock by the block's length, so every block starts exactly where the last one ended.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from tactile_core.device import audio
from tactile_core.device.host_clock import VirtualClock


class CallbackAbort(Exception):
    pass


class PortAudioError(Exception):
    pass


class AudioClock(VirtualClock):
    """Virtual time in which the audio callback runs whenever the link waits."""

    stream = None

    def sleep(self, seconds: float) -> None:
        if self.stream is not None and self.stream.active:
            self.stream.pump()
        else:
            self.advance(seconds)


class FakeStream:
    def __init__(self, sd, *, device, channels, samplerate, blocksize, dtype, latency, callback,
                 finished_callback):  # fmt: skip
        self.sd = sd
        self.channels = channels
        self.samplerate = samplerate
        self.blocksize = blocksize
        self.callback = callback
        self.finished_callback = finished_callback
        self.latency = 0.008
        self.active = False
        self.closed = False
        self.stopped_by = None
        self.blocks: list[np.ndarray] = []
        self.starts: list[float] = []  # each block's DAC time as reported (host clock)
        self.ahead = 0.008  # the DAC time the fake reports: this far after "now"
        sd.streams.append(self)
        sd.clock.stream = self

    def start(self):
        self.active = True

    def pump(self, n: int = 1) -> None:
        """Run the callback on ``n`` blocks (while the stream is active)."""
        clock = self.sd.clock
        for _ in range(n):
            if not self.active:
                return
            out = np.full((self.blocksize, self.channels), np.nan, dtype=np.float32)
            now = clock.now()
            info = SimpleNamespace(currentTime=now, outputBufferDacTime=now + self.ahead)
            self.starts.append(now + self.ahead)
            status = SimpleNamespace(output_underflow=False)
            try:
                self.callback(out, self.blocksize, info, status)
            except CallbackAbort:
                self._finish("abort")
            self.blocks.append(out)
            clock.advance(self.blocksize / self.samplerate)

    def played(self) -> np.ndarray:
        return np.concatenate(self.blocks) if self.blocks else np.zeros((0, self.channels))

    def _finish(self, how: str) -> None:
        self.active = False
        self.stopped_by = how
        self.finished_callback()

    def stop(self):
        self._finish("stop")

    def abort(self):
        self._finish("abort")

    def close(self, ignore_errors=True):
        self.closed = True


class FakeSoundDevice:
    """``sounddevice`` with the output devices ``devices`` (dicts of ``name``,
    ``max_output_channels``, ``default_samplerate``; ``hostapi`` 0 is ALSA)."""

    CallbackAbort = CallbackAbort
    PortAudioError = PortAudioError

    def __init__(self, clock: AudioClock, devices=None, default_output: int = 0,
                 rates=(44100, 48000, 96000)):  # fmt: skip
        self.clock = clock
        self.devices = [
            {"index": i, "hostapi": 0, "max_input_channels": 0, **d}
            for i, d in enumerate(devices or [card("USB 8ch", 8), card("Speakers", 2, 44100)])
        ]
        self.default = SimpleNamespace(device=[-1, default_output])
        self.rates = rates
        self.streams: list[FakeStream] = []

    def query_hostapis(self):
        return [{"name": "ALSA"}]

    def query_devices(self):
        return list(self.devices)

    def check_output_settings(self, device, channels, dtype, samplerate):
        if samplerate not in self.rates:
            raise PortAudioError("Invalid sample rate [PaErrorCode -9997]")
        if channels > self.devices[device]["max_output_channels"]:
            raise PortAudioError("Invalid number of channels [PaErrorCode -9998]")

    def OutputStream(self, **kwargs):  # sounddevice's name
        return FakeStream(self, **kwargs)


def card(name: str, channels: int, rate: float = 48000.0) -> dict:
    return {"name": name, "max_output_channels": channels, "default_samplerate": rate}


def fake_audio(monkeypatch, **kwargs) -> tuple[FakeSoundDevice, AudioClock]:
    """Install a fake ``sounddevice`` for the audio link, and its clock for every audio link
    opened; ``(sd, clock)``."""
    clock = AudioClock()
    sd = FakeSoundDevice(clock, **kwargs)
    monkeypatch.setattr(audio, "load_sounddevice", lambda: sd)
    monkeypatch.setattr(audio, "HostClock", lambda: clock)
    return sd, clock
