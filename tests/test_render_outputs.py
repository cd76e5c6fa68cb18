"""What ``tactile render`` writes (CSV frames, WAV carriers) for time-keyed paths, .tact
patterns and layouts of any size, and what ``write_wav`` refuses when Python calls it with
values the command line never passes."""

import json
import wave

import numpy as np
import pytest

from tactile_core.device.profile import default_profile, profile_from_dict
from tactile_core.files.wav import write_wav

from .helpers import run_cli_last_line

run_cli = run_cli_last_line


def strip_profile(n, wrap=False):
    """A profile of ``n`` actuators in a row, one pitch apart."""
    layout = {"units": "pitch", "actuators": [[float(k), 0.0] for k in range(n)]}
    if wrap:
        layout["wrap"] = {"axis": "x", "circumference": float(n)}
    return {"format": "tactile-device-profile", "version": 1, "name": "strip", "pitch_mm": 100.0,
            "levels": 23, "layout": layout}  # fmt: skip


def audio_profile(channels):
    data = default_profile().to_dict()
    data.update(name=f"audio-{channels}", columns=channels, rows=1)
    return profile_from_dict(data)


def test_a_timed_path_renders_at_its_own_pace_unless_told(tmp_path, capsys):
    # A 0.5 s path was stretched to --duration's default 2 s by render and stream, though
    # export-tact kept its times and the docs say it plays at its own pace.
    out = tmp_path / "t.csv"
    spec = "timed:1,1,0,1,4,5,0.5,1"  # (1, 1) at 0 s to (4, 5) at 0.5 s
    code, _ = run_cli(capsys, "render", "--shape", spec, "--method", "AS", "--rate", "10",
                      "--out", out)  # fmt: skip
    assert code == 0 and len(out.read_text().splitlines()) == 1 + 6  # 0, 0.1 .. 0.5 s
    code, _ = run_cli(capsys, "render", "--shape", spec, "--method", "AS", "--rate", "10",
                      "--duration", "1", "--out", out)  # fmt: skip
    assert code == 0 and len(out.read_text().splitlines()) == 1 + 11  # told: 1 s


def test_render_writes_a_patterns_carriers_to_wav(tmp_path, capsys):
    out = tmp_path / "t.wav"
    shape = "tact:tests/data/testfeedback.tact"
    code, _ = run_cli(capsys, "render", "--shape", shape, "--method", "BA", "--profile",
                      "vest-4x5", "--out", out)  # fmt: skip
    assert code == 0
    with wave.open(str(out)) as f:  # 100 frames at 100 Hz: 1 s and the ramp
        assert f.getnchannels() == 20 and 1.0 <= f.getnframes() / f.getframerate() < 1.05


@pytest.mark.parametrize("wrap", [False, True])
def test_render_takes_a_layout_of_255_actuators(tmp_path, capsys, wrap):
    """A layout is its own channel strip, not a grid of up to 64 columns: 255 actuators (the
    most a profile holds) render to CSV and WAV (was: 'cols must be >= 1 and <= 64')."""
    path = tmp_path / "strip.json"
    path.write_text(json.dumps(strip_profile(255, wrap)))
    for out in ("frames.csv", "carriers.wav"):
        code, line = run_cli(capsys, "render", "--profile", path, "--shape", "line:0,0,254,0",
                             "--method", "BA", "--rate", "10", "--duration", "0.2",
                             "--out", tmp_path / out)  # fmt: skip
        assert code == 0, line
    header = (tmp_path / "frames.csv").read_text().splitlines()[0].split(",")
    assert len(header) == 256 and header[:2] == ["time", "a0"]


@pytest.mark.parametrize(
    "change, words",
    [
        ({"levels": np.full((3, 4), 23)}, "levels[0, 0] must be a device level 0..22, got 23"),
        ({"levels": np.full((3, 4), -1)}, "levels[0, 0] must be a device level 0..22, got -1"),
        ({"levels": np.full((3, 4), 0.5)}, "levels[0, 0] must be a device level 0..22, got 0.5"),
        ({"levels": np.full((3, 4), np.nan)}, "must be a device level 0..22, got nan"),
        ({"levels": np.full((3, 4), "7")}, "levels must be device levels 0..22"),
        ({"rate_hz": 0}, "rate_hz must be within"),
        ({"rate_hz": float("nan")}, "rate_hz must be a finite number"),
        ({"samplerate": 0}, "samplerate must be >= 8000 and <= 384000"),
        ({"samplerate": 44100.5}, "samplerate must be an integer"),
        ({"carrier_hz": 1e6}, "carrier_hz must be within [1, 1000]"),
        ({"carrier_hz": float("nan")}, "carrier_hz must be a finite number"),
        ({"ramp_ms": -1}, "ramp_ms must be within [0, 20]"),
        ({"ramp_ms": float("nan")}, "ramp_ms must be a finite number"),
        ({"ramp_ms": "1.5"}, "ramp_ms must be a finite number"),
    ],
)
def test_write_wav_refuses_what_no_device_level_or_audio_url_allows(tmp_path, change, words):
    args = {"levels": np.full((3, 4), 22), "rate_hz": 300.0, "samplerate": 48000,
            "carrier_hz": None, "ramp_ms": 1.5, **change}  # fmt: skip
    out = tmp_path / "x.wav"
    with pytest.raises(ValueError) as caught:
        write_wav(out, args.pop("levels"), args.pop("rate_hz"), audio_profile(4), **args)
    assert words in str(caught.value)
    assert not out.exists() and not list(tmp_path.iterdir())  # nothing half-written
