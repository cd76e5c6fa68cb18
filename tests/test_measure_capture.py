"""The sensor's capture path through real PortAudio: ALSA's ``file`` plugin reads what the
simulated sensor recorded from its ``infile`` (tests/audio_support.py has the playing side), and
``AudioInput`` records it with ``sounddevice.InputStream``, sample for sample.

The ``infile`` is a regular file, not a pipe the simulation writes as time passes: the plugin's
slave here is the ``null`` PCM, which takes samples as fast as they are asked for, and a pipe
cannot pace it (the plugin fills each period with one ``read`` and leaves what a short read did
not bring as it was: the capture ran at 1.6-6 times real time with garbage between the
samples). So this captures a recording made beforehand, and the measurement's timing in real
time is tested on the input stand-in (``--input sim``, tests/test_measure_cli.py).
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from tactile_core.device.measure import (
    QUICK_PLAN,
    Recording,
    analyse,
    sensor_model,
    simulate_block,
)
from tactile_core.device.profile import default_profile

from .audio_support import require_audio

DEVICE = "tactin"
SAMPLERATE = 8000
CHANNELS = 8  # what AudioInput opens on a device with more inputs (the sensor's and others)

CHILD = r"""
import json, sys, time
import numpy as np
from tactile_core.device.measure import AudioInput, input_devices
url, n, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
sensor = AudioInput(url, keep_s=600.0)  # the null PCM runs faster than real time: keep all
names = [d["name"] for d in input_devices(sensor.sd)]
deadline = time.monotonic() + 60
with sensor:
    while sensor.recorded < n:
        assert time.monotonic() < deadline, "the capture did not bring the samples"
        time.sleep(0.005)  # a poll of a counter (the test's bound is the deadline)
    rec = sensor.recording()
np.save(out, rec.samples[:n])
print(json.dumps({"names": names, "channel": rec.channel, "channels": sensor.channels,
                  "samplerate": rec.samplerate, "description": sensor.description}))
"""


def capture(tmp_path, x: np.ndarray, url: str) -> tuple[np.ndarray, dict]:
    """Capture ``x`` (samples x channels) through PortAudio from ``url`` in a child process
    whose ALSA reads the ``infile``."""
    infile = tmp_path / "sensor.raw"
    x.astype("<f4").tofile(infile)
    config = tmp_path / "asound.conf"
    config.write_text(
        "</usr/share/alsa/alsa.conf>\n"
        f"pcm.{DEVICE} {{\n"
        "    type file\n"
        "    slave.pcm { type null }\n"
        '    file "/dev/null"\n'
        f'    infile "{infile}"\n'
        '    format "raw"\n'
        "}\n"
    )
    out = tmp_path / "captured.npy"
    env = {**os.environ, "ALSA_CONFIG_PATH": str(config)}
    done = subprocess.run([sys.executable, "-c", CHILD, url, str(len(x)), str(out)], env=env,
                          capture_output=True, text=True, timeout=120)  # fmt: skip
    assert done.returncode == 0, done.stderr
    return np.load(out), json.loads(done.stdout.strip().splitlines()[-1])


def test_audio_input_captures_the_sensor_sample_for_sample_and_it_measures(tmp_path):
    require_audio()
    profile = default_profile()
    cell = 7
    # the sensor on input 2 of the interface; the other inputs carry their noise
    model = sensor_model(profile, tau_up_ms=25.0, tau_down_ms=70.0, delay_ms=6.0, noise=0.03,
                         seed=2, channels=CHANNELS, channel=1, on_cell=cell)  # fmt: skip
    rec, block = simulate_block(profile, cell, model, plan=QUICK_PLAN, samplerate=SAMPLERATE,
                                seed=2)  # fmt: skip
    got, info = capture(tmp_path, rec.samples, f"audio:{DEVICE}?channel=2&samplerate={SAMPLERATE}")
    assert DEVICE in info["names"]
    assert (info["channel"], info["channels"], info["samplerate"]) == (1, CHANNELS, SAMPLERATE)
    assert "input 2" in info["description"]
    np.testing.assert_array_equal(got, rec.samples)  # every sample, every input, in order
    # the capture read as the procedure reads it (the commands in recording seconds: the
    # null PCM's clock is not real time, so the block's place comes from the simulation)
    captured = Recording(got, SAMPLERATE, rec.start_s, channel=info["channel"])
    names = [profile.layout.cell_name(i) for i in range(profile.channels)]
    result = analyse(captured.sensor, SAMPLERATE, block, QUICK_PLAN, levels=profile.levels,
                     names=names, others=captured.others)  # fmt: skip
    assert result.tau_up_s * 1e3 == pytest.approx(25.0, rel=0.1)
    assert result.tau_down_s * 1e3 == pytest.approx(70.0, rel=0.1)
    assert abs(result.delay_s * 1e3 - 6.0) <= 1.0


def test_audio_input_on_the_wrong_input_is_told_which_one_carries_the_sensor(tmp_path):
    require_audio()
    profile = default_profile()
    model = sensor_model(profile, tau_up_ms=30.0, tau_down_ms=60.0, delay_ms=5.0, noise=0.02,
                         seed=1, channels=CHANNELS, channel=3, on_cell=0)  # fmt: skip
    rec, block = simulate_block(profile, 0, model, plan=QUICK_PLAN, samplerate=SAMPLERATE,
                                seed=1)  # fmt: skip
    got, info = capture(tmp_path, rec.samples, f"audio:{DEVICE}?samplerate={SAMPLERATE}")
    captured = Recording(got, SAMPLERATE, rec.start_s, channel=info["channel"])
    assert info["channel"] == 0  # input 1, the default
    names = [profile.layout.cell_name(i) for i in range(profile.channels)]
    with pytest.raises(ValueError, match=r"input 4 of the interface follows the stimulus"):
        analyse(captured.sensor, SAMPLERATE, block, QUICK_PLAN, levels=profile.levels,
                names=names, others=captured.others)  # fmt: skip
