"""``tactile render --out FILE.wav``: the carrier signal the audio transport would play for a
trace, read back against ``tc.render`` + correction + quantisation of the same trace."""

import json
import math
import wave

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.cli import main
from tactile_core.device.profile import load_profile

SAMPLERATE = 48000
RAMP_N = 72  # 1.5 ms


def read_wav(path):
    with wave.open(str(path), "rb") as f:
        assert f.getsampwidth() == 2
        data = np.frombuffer(f.readframes(f.getnframes()), dtype="<i2")
        return data.reshape(-1, f.getnchannels()) / 32767.0, f.getframerate()


def ramp(n):
    j = np.arange(n)
    return 0.5 - 0.5 * np.cos(np.pi * (j + 0.5) / n)


def expected_signal(levels, rate_hz, carriers, samplerate, ramp_n, top):
    """The documented signal, built here from the definitions: carrier ``sin(2 pi f s / sr)``,
    frame ``k`` from ``round(k sr / rate)``, a raised-cosine ramp from the previous level,
    then all off and 10 ms of silence."""
    levels = np.vstack([levels, np.zeros_like(levels[:1])]) / top
    onsets = np.round(np.arange(len(levels)) * samplerate / rate_hz).astype(int)
    length = onsets[-1] + ramp_n + round(0.01 * samplerate)
    s = np.arange(length)
    k = np.searchsorted(onsets, s, side="right") - 1
    j = s - onsets[k]
    w = np.where(j < ramp_n, ramp(ramp_n)[np.minimum(j, ramp_n - 1)], 1.0)
    before = np.vstack([np.zeros_like(levels[:1]), levels[:-1]])
    envelope = before[k] + (levels[k] - before[k]) * w[:, None]
    carrier = np.sin(2 * np.pi * np.outer(s, carriers) / samplerate)
    return envelope * carrier, onsets


def test_wav_holds_each_tactors_carrier_at_its_quantised_level(tmp_path):
    out = tmp_path / "circle.wav"
    args = ["render", "--shape", "circle:2.5,3,2", "--method", "IM", "--mu", "0.33"]
    args += ["--gamma", "0.7", "--rate", "100", "--duration", "2", "--out", str(out)]
    assert main(args) == 0
    x, rate = read_wav(out)
    assert rate == SAMPLERATE and x.shape[1] == 30  # the palm array, one channel per tactor
    t = np.arange(201) / 200
    frames = tc.correct(tc.render(tc.Circle((2.5, 3), 2), "IM", t), 0.33, 0.7)
    levels = tc.quantize(frames, 23).reshape(201, 30)  # row-major: the palm's channel order
    want, onsets = expected_signal(levels, 100, [250.0] * 30, SAMPLERATE, RAMP_N, 22)
    assert x.shape == want.shape
    # sample for sample, to the 16-bit step
    assert np.abs(x - want).max() <= 1 / 32767
    # and the envelope of each frame, read back by least squares between the ramps
    s = np.arange(len(x))
    carrier = np.sin(2 * np.pi * 250 * s / SAMPLERATE)
    worst = 0.0
    for k in range(len(levels)):
        a, b = onsets[k] + RAMP_N, onsets[k + 1]
        c = carrier[a:b]
        amplitude = (x[a:b] * c[:, None]).sum(axis=0) / (c @ c)
        worst = max(worst, np.abs(amplitude * 22 - levels[k]).max())
    assert worst < 0.01  # levels, read back
    assert not x[-round(0.01 * SAMPLERATE) :].any()  # it ends in silence
    assert np.abs(np.diff(x, axis=0)).max() <= 2 * math.pi * 250 / SAMPLERATE + math.pi / (
        2 * RAMP_N
    )  # never a click


def test_wav_follows_the_profiles_channel_order_carriers_and_calibration(tmp_path):
    profile = {
        "format": "tactile-device-profile",
        "version": 1,
        "name": "four",
        "columns": 2,
        "rows": 2,
        "pitch_mm": 20,
        "levels": 16,
        "channel_order": "column-major",
        "carrier_hz": [100, 170, 230, 320],
        "calibration": {"offset": [0.0, 0.1, 0.0, 0.0], "gain": [1.0, 1.0, 0.5, 1.0]},
    }
    path = tmp_path / "four.json"
    path.write_text(json.dumps(profile))
    out = tmp_path / "line.wav"
    args = ["render", "--shape", "line:0.5,0.5,1.5,1.5", "--method", "AS", "--rate", "50"]
    args += ["--duration", "1", "--profile", str(path), "--samplerate", "8000"]
    args += ["--ramp-ms", "2", "--out", str(out)]
    assert main(args) == 0
    x, rate = read_wav(out)
    assert rate == 8000 and x.shape[1] == 4
    prof = load_profile(path)
    frames = tc.render(tc.Line((0.5, 0.5), (1.5, 1.5)), "AS", np.arange(51) / 50, grid=prof.layout)
    cells = tc.quantize(prof.calibrate(frames.reshape(51, 4)), 16)
    # column-major: channel 0 is cell 0 (r0c0), channel 1 cell 2 (r1c0), 2 cell 1, 3 cell 3
    levels = cells[:, [0, 2, 1, 3]]
    want, _ = expected_signal(levels, 50, [100, 170, 230, 320], 8000, 16, 15)
    assert np.abs(x - want).max() <= 1 / 32767


def test_wav_carrier_option_and_what_only_wav_takes(tmp_path, capsys):
    out = tmp_path / "one.wav"
    base = ["render", "--shape", "line:0.5,0.5,0.5,1.5", "--method", "CT", "--duration", "0.5"]
    assert main([*base, "--carrier-hz", "80", "--out", str(out)]) == 0
    x, _ = read_wav(out)
    lit = x[:, (x**2).sum(axis=0).argmax()]  # one of the two tactors, lit 0.25 s
    up = np.flatnonzero((lit[:-1] < 0) & (lit[1:] >= 0))
    assert np.median(np.diff(up)) == pytest.approx(SAMPLERATE / 80, abs=1)
    capsys.readouterr()
    for extra, word in [
        (["--samplerate", "44100", "--out", str(tmp_path / "x.csv")], "--samplerate"),
        (["--carrier-hz", "1001", "--out", str(out)], "carrier-hz"),
        (["--carrier-hz", "0", "--out", str(out)], "carrier-hz"),
        (["--samplerate", "7999", "--out", str(out)], "samplerate"),
        (["--ramp-ms", "21", "--out", str(out)], "ramp-ms"),
        (["--cols", "4", "--out", str(out)], "--cols"),
        (["--out", str(tmp_path / "x.mp3")], "--out"),
    ]:
        assert main([*base, *extra]) == 2, extra
        assert word in capsys.readouterr().err, extra
