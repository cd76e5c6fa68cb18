"""The audio input's own logic on a stand-in for sounddevice: the URL, the device and channel
chosen, the blocks kept and let go, and the host time of each sample from the blocks' arrival
times (injected, so nothing depends on how fast this machine is)."""

import types

import numpy as np
import pytest

from tactile_core.device.link import LinkError
from tactile_core.device.measure import AudioInput, parse_input_url
from tactile_core.device.measure import _audio_input as audio_input_module


class FakeInputStream:
    def __init__(self, *, device, channels, samplerate, dtype, callback):
        self.device, self.channels, self.samplerate = device, channels, samplerate
        self.callback = callback
        self.started = self.closed = False

    def start(self):
        self.started = True

    def stop(self):
        self.started = False

    def close(self):
        self.closed = True


def fake_sd(inputs=((0, "Built-in Mic", 2), (3, "USB Audio CODEC", 4))):
    devices = [{"index": i, "name": name, "max_input_channels": n, "max_output_channels": 0,
                "default_samplerate": 48000.0, "hostapi": 0} for i, name, n in inputs]  # fmt: skip
    sd = types.SimpleNamespace(
        query_hostapis=lambda: [{"name": "ALSA"}],
        query_devices=lambda: devices,
        default=types.SimpleNamespace(device=(inputs[0][0], -1)),
        check_input_settings=lambda **kw: None,
        InputStream=FakeInputStream,
    )
    return sd


@pytest.fixture
def clock(monkeypatch):
    """The input's ``time.perf_counter``, set by the test."""
    now = {"t": 50.0}
    fake = types.SimpleNamespace(perf_counter=lambda: now["t"], monotonic=lambda: now["t"])
    monkeypatch.setattr(audio_input_module, "time", fake)
    return now


def deliver(sensor, clock, blocks, block=480, start=100.0, late=0.002, ratio=1.0):
    """Hand ``blocks`` blocks to the callback, each arriving ``late`` after its last sample
    (host time ``start + samples / 48000 * ratio``); block k holds the value k on input 1."""
    stream = sensor._stream
    for k in range(blocks):
        data = np.zeros((block, stream.channels), dtype=np.float32)
        data[:, 0] = k
        clock["t"] = start + (k + 1) * block / 48000 * ratio + late * (1 + k % 3)
        stream.callback(data, block, None, None)


def test_input_url_reads_its_keys_and_refuses_unknown_ones():
    got = parse_input_url("audio:USB%20Audio?channel=3&samplerate=44100&latency_ms=1.5")
    assert (got.device, got.channel, got.samplerate, got.latency_ms) == ("USB Audio", 3, 44100,
                                                                          1.5)  # fmt: skip
    with pytest.raises(ValueError, match="unknown key 'channels'"):
        parse_input_url("audio:?channels=2")
    with pytest.raises(ValueError, match="channel must be within 1-64, got 0"):
        parse_input_url("audio:?channel=0")
    with pytest.raises(ValueError, match="a sensor's input must be an audio: URL"):
        parse_input_url("/dev/ttyUSB0")


def test_input_picks_the_device_and_the_inputs_to_record():
    sensor = AudioInput("audio:USB?channel=2", sd=fake_sd())
    assert sensor.device["index"] == 3 and sensor.channel == 1
    assert sensor.channels == 4  # all of them, up to 8
    assert sensor.description == "an audio input ('USB Audio CODEC', input 2, 48000 Hz)"
    with pytest.raises(LinkError, match="has 2 inputs: channel=3 is not one of them"):
        AudioInput("audio:?channel=3", sd=fake_sd())
    with pytest.raises(LinkError, match="audio input 'Focusrite' not found; the inputs are 0: "):
        AudioInput("audio:Focusrite", sd=fake_sd())


def test_recording_places_each_sample_at_its_host_time(clock):
    sensor = AudioInput("audio:USB?latency_ms=1", sd=fake_sd()).start()
    deliver(sensor, clock, blocks=300)  # 3 s, each block 2-6 ms late
    rec = sensor.recording()
    assert rec.samples.shape == (300 * 480, 4)
    # sample n was taken at 100 + n / 48000 (the earliest arrival: 2 ms late); the 1 ms
    # converter latency of the URL is taken off as well
    assert rec.start_s == pytest.approx(100.0 + 0.002 - 0.001, abs=1e-6)
    assert rec.ratio == pytest.approx(1.0, abs=1e-9)
    assert float(rec.to_recording_s(101.0 + 0.001)) == pytest.approx(1.0, abs=1e-6)
    assert sensor.covers(100.0 + 2.9) and not sensor.covers(104.0)


def test_clear_and_since_keep_only_what_is_asked(clock):
    sensor = AudioInput("audio:USB", sd=fake_sd()).start()
    deliver(sensor, clock, blocks=100)  # 1 s
    sensor.clear()
    deliver(sensor, clock, blocks=50, start=101.0)
    rec = sensor.recording()
    assert len(rec.samples) == 50 * 480 and rec.sensor[0] == 0.0
    assert rec.start_s == pytest.approx(101.002, abs=1e-6)  # the clock spans both
    later = sensor.recording(since_s=101.2)
    assert later.start_s <= 101.2 < later.start_s + 0.01 + 480 / 48000
    assert len(later.samples) < len(rec.samples)


def test_a_fast_interfaces_drift_is_followed(clock):
    sensor = AudioInput("audio:USB", sd=fake_sd()).start()
    deliver(sensor, clock, blocks=1000, ratio=1.0 + 1e-4)  # 10 s, its crystal 100 ppm slow
    rec = sensor.recording()
    assert rec.ratio == pytest.approx(1.0 + 1e-4, abs=2e-6)
    end = len(rec.samples)
    assert float(rec.host_s(end / 48000)) == pytest.approx(100.0 + 10.0 * (1 + 1e-4) + 0.002,
                                                          abs=1e-4)  # fmt: skip


def test_old_blocks_are_let_go(clock):
    sensor = AudioInput("audio:USB", sd=fake_sd(), keep_s=2.0).start()
    deliver(sensor, clock, blocks=500)  # 5 s
    rec = sensor.recording()
    assert 2.0 <= rec.duration_s <= 2.0 + 480 / 48000
    assert rec.sensor[-1] == 499 and rec.start_s == pytest.approx(100.0 + 3.0, abs=0.011)
