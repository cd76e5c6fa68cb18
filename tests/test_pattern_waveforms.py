"""A pattern's effects may name a waveform (docs/patterns.md): in the file (version 2, and
version 1 files reading as before), per actuator in each frame, in the pattern's WAV export,
and on a serial array, which plays levels only and says once what it drops."""

import json
import wave

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.cli import main
from tactile_core.device.host_clock import VirtualClock
from tactile_core.device.link import SimulatedArray
from tactile_core.device.profile import load_profile, profile_from_dict
from tactile_core.device.waveform import parse_waveform
from tactile_core.files.pattern import Effect, Pattern, PatternError, example_patterns
from tactile_core.rendering.scene import Scene
from tactile_core.stream import Streamer

from .serve_support import wait_for

SQUARE = parse_waveform("square:200")
NOISE = parse_waveform("noise")
NOTE = "needs an audio interface: the serial array plays levels only"


def tap(actuator, intensity=1.0, start_s=0.0, duration_s=0.2):
    return tc.Dots([tc.Dot(actuator, intensity, start_s, duration_s)])


# --- the effect and its file ------------------------------------------------------------------


def test_an_effect_takes_a_waveform_spec_or_value_and_refuses_a_bad_one_by_name():
    assert Effect(tap(0), waveform="square:200").waveform == SQUARE
    assert Effect(tap(0), waveform=SQUARE).waveform == SQUARE
    assert Effect(tap(0)).waveform is None
    with pytest.raises(ValueError, match=r"^waveform 'squar': shape must be one of sine, square"):
        Effect(tap(0), waveform="squar")
    pattern = Pattern(
        [
            Effect(tap(0), waveform="noise"),
            Effect(tap(1)),
            Effect(tap(2), waveform="square:200"),
            Effect(tap(3), waveform="noise"),
        ]
    )
    assert pattern.waveforms == (NOISE, SQUARE)


def pattern_file(tmp_path, version, effect):
    path = tmp_path / "p.json"
    data = {"format": "tactile-pattern", "version": version, "effects": [effect]}
    path.write_text(json.dumps(data))
    return path


@pytest.mark.parametrize(
    "version, waveform, message",
    [
        (1, "square:200", "effects[0].waveform needs version 2 (the file says 1)"),
        (2, "squar", "effects[0].waveform 'squar': shape must be one of sine, square"),
        (2, "sweep:100-300:0ms", "effects[0].waveform 'sweep:100-300:0ms': duration must be"),
        (2, 200, "effects[0].waveform must be a string or null, got 200"),
        (3, "square", "version is 3, newer than this software reads (2)"),
    ],
)
def test_a_bad_waveform_in_a_file_is_refused_naming_the_field(tmp_path, version, waveform, message):
    effect = {"dots": [{"at": 0}], "waveform": waveform}
    path = pattern_file(tmp_path, version, effect)
    with pytest.raises(PatternError) as caught:
        Pattern.load(path)
    assert str(caught.value) == f"{path}: {message}" or message in str(caught.value)
    assert str(caught.value).startswith(f"{path}: ")


def test_a_file_is_version_1_without_waveforms_and_2_with_them(tmp_path):
    plain = Pattern([Effect(tap(0)), Effect(tap(1), start_s=0.3)])
    plain.save(tmp_path / "plain.json")
    assert json.loads((tmp_path / "plain.json").read_text())["version"] == 1
    voiced = plain.add(tap(2), waveform="sweep:100-300:500ms:log+adsr:5,20,0.7,50")
    voiced.save(tmp_path / "voiced.json")
    data = json.loads((tmp_path / "voiced.json").read_text())
    assert data["version"] == 2
    assert data["effects"][2]["waveform"] == "sweep:100-300:500ms:log+adsr:5,20,0.7,50"
    assert "waveform" not in data["effects"][0]
    assert Pattern.load(tmp_path / "voiced.json") == voiced
    assert Pattern.load(tmp_path / "plain.json") == plain
    null = pattern_file(tmp_path, 2, {"dots": [{"at": 0}], "waveform": None})
    assert Pattern.load(null).effects[0].waveform is None


def test_the_bundled_version_1_patterns_read_as_before():
    for name, path in example_patterns().items():
        assert json.loads(path.read_text())["version"] == 1, name
        pattern = Pattern.load(path)
        assert pattern.waveforms == ()
        assert json.loads(json.dumps(pattern.to_dict()))["version"] == 1


# --- which waveform each actuator plays ------------------------------------------------------


def test_each_actuator_plays_the_waveform_of_the_effect_that_lights_it_most():
    # worked at 10 frames a second (the middles 0.05, 0.15, ... s) on a 4 x 1 grid
    pattern = Pattern(
        [
            Effect(tap(0, 0.4, 0.0, 0.3), waveform="square:200"),  # 0.4 on actuator 0, 0-0.3 s
            Effect(tap(0, 0.7, 0.1, 0.1), waveform="noise"),  # 0.7 on actuator 0, 0.1-0.2 s
            Effect(tap(1, 0.9, 0.0, 0.2)),  # actuator 1: the device's own
            Effect(tap(2, 0.5, 0.2, 0.2), waveform="noise"),  # actuator 2 from 0.2 s
        ]
    )
    live = pattern.live("AS", tc.Grid(4, 1), tc.Sampling(10.0, "point"), 0.0, 1.0)
    assert live.waveforms
    assert live.voices(0) == (SQUARE, None, None, None)
    assert live.voices(1) == (NOISE, None, None, None)  # 0.7 over 0.4
    assert live.voices(2) == (SQUARE, None, NOISE, None)
    assert live.voices(3) == (None, None, NOISE, None)  # actuator 0 is off from 0.3 s
    assert live.voices(4) is None  # after the pattern
    plain = Pattern([Effect(tap(0))]).live("AS", tc.Grid(4, 1), tc.Sampling(10.0, "point"), 0, 1)
    assert not plain.waveforms and plain.voices(0) is None


def test_under_sum_the_largest_contribution_chooses():
    pattern = Pattern([Effect(tap(0, 0.3), waveform="noise"), Effect(tap(0, 0.5))], combine="sum")
    live = pattern.live("AS", tc.Grid(2, 1), tc.Sampling(10.0, "point"), 0.0, 1.0)
    assert live.voices(0) is None  # the plain effect gives more: the device's own
    pattern = pattern.replace(
        effects=(pattern.effects[0].replace(content=tap(0, 0.6)), pattern.effects[1])
    )
    live = pattern.live("AS", tc.Grid(2, 1), tc.Sampling(10.0, "point"), 0.0, 1.0)
    assert live.voices(0) == (NOISE, None)


# --- the WAV export ---------------------------------------------------------------------------


def read_wav(path):
    with wave.open(str(path), "rb") as f:
        data = np.frombuffer(f.readframes(f.getnframes()), dtype="<i2")
        return data.reshape(-1, f.getnchannels()) / 32767.0


def test_a_patterns_wav_export_plays_each_effects_waveform(tmp_path):
    profile = load_profile("voicecoil-8")  # 4 x 2, row-major, 250 Hz, 256 levels
    pattern = Pattern(
        [
            Effect(tap(0, 1.0, 0.0, 0.5), waveform="square:200"),
            Effect(tap(5, 1.0, 0.0, 0.5)),
            Effect(tap(6, 1.0, 0.1, 0.4), waveform="noise:seed=2"),
        ]
    )
    n = pattern.save_wav(tmp_path / "api.wav", profile, rate_hz=100, ramp_ms=0)
    pattern.save(tmp_path / "p.json")
    args = ["render", "--shape", f"pattern:{tmp_path / 'p.json'}", "--method", "AS"]
    args += ["--profile", "voicecoil-8", "--rate", "100", "--ramp-ms", "0"]
    assert main([*args, "--out", str(tmp_path / "cli.wav")]) == 0
    x = read_wav(tmp_path / "api.wav")
    assert len(x) == n and np.array_equal(x, read_wav(tmp_path / "cli.wav"))
    s = np.arange(24000)  # the taps' 0.5 s
    assert np.array_equal(x[:24000, 0], np.where(s % 240 < 120, 1.0, -1.0))
    assert np.allclose(x[:24000, 5], np.sin(2 * np.pi * 250 * s / 48000), atol=1e-4)
    noise = x[4800:24000, 6]
    assert np.mean(noise**2) == pytest.approx(1 / 3, abs=0.02)
    assert not x[:4800, 6].any() and not x[:, [1, 2, 3, 4, 7]].any()
    # the whole file with one waveform instead of the profile's: the effects' own still win
    assert main([*args, "--waveform", "triangle:100", "--out", str(tmp_path / "t.wav")]) == 0
    t = read_wav(tmp_path / "t.wav")
    assert np.array_equal(t[:, 0], x[:, 0])
    assert np.allclose(t[[120, 360], 5], [1.0, -1.0], atol=1e-4)  # 100 Hz: 480 samples a period


# --- a serial array ---------------------------------------------------------------------------


def stream_status(profile, scene):
    clock = VirtualClock()
    statuses = []
    sim = SimulatedArray(profile, clock=clock)
    streamer = Streamer(
        sim,
        profile,
        scene=scene,
        clock=clock,
        spin_s=0.0,
        on_status=lambda stats: statuses.append(stats.status),
    )
    with streamer:
        wait_for(lambda: streamer.stats.frames >= 30, timeout_s=60, what="30 frames")
    return statuses


def coil(tmp_path=None, **extra):
    """voicecoil-8 at 255 levels (an array's info carries its levels in a byte: 256 does not
    identify), its JSON form, written to ``tmp_path`` if given."""
    data = {**load_profile("voicecoil-8").to_dict(), "levels": 255, **extra}
    if tmp_path is not None:
        (tmp_path / "coil.json").write_text(json.dumps(data))
    return data


def test_a_serial_array_plays_levels_and_says_once_which_waveforms_it_drops():
    data = coil()
    voiced = profile_from_dict({**data, "waveform": "square:200"})
    statuses = stream_status(voiced, Scene(tc.Circle((1.5, 0.5), 1.0), "AS", rate_hz=100.0))
    said = [s for s in statuses if "an audio interface" in s]
    assert len(said) == 1, statuses
    assert said[0].startswith("streaming AS at 100 Hz to simulated array")
    assert said[0].endswith(f"; waveform square:200 {NOTE}")
    # a pattern's effects' waveforms, and none for the plain carrier
    plain = profile_from_dict({**data, "waveform": "sine"})
    pattern = Pattern(
        [Effect(tap(0), waveform="noise"), Effect(tap(1), waveform="square:200"), Effect(tap(2))]
    )
    statuses = stream_status(plain, Scene(source=pattern, method="AS", rate_hz=100.0))
    said = [s for s in statuses if "an audio interface" in s]
    assert len(said) == 1, statuses
    assert said[0].endswith(
        "; waveforms noise, square:200 need an audio interface: the serial array plays levels only"
    )
    statuses = stream_status(plain, Scene(tc.Circle((1.5, 0.5), 1.0), "AS", rate_hz=100.0))
    assert not any("audio interface" in s for s in statuses)


def test_tactile_stream_to_a_serial_array_says_what_it_drops_once(tmp_path, capsys):
    pattern = Pattern([Effect(tap(0, 1.0, 0.0, 0.3), waveform="sweep:100-300:500ms")])
    pattern.save(tmp_path / "p.json")
    coil(tmp_path)
    args = ["stream", "--device", "sim", "--profile", str(tmp_path / "coil.json"), "--method", "AS"]
    args += ["--shape", f"pattern:{tmp_path / 'p.json'}", "--rate", "100"]
    assert main(args) == 0
    out, err = capsys.readouterr()
    text = out + err
    assert text.count(f"waveform sweep:100-300:500ms {NOTE}") == 1, text


def test_the_waveforms_example_in_the_docs_writes_its_wav(tmp_path, monkeypatch):
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "patterns.md").read_text()
    section = text.split("## Waveforms", 1)[1]
    script = section.split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    exec(compile(script, "docs/patterns.md", "exec"), {"__name__": "__docs__"})
    x = read_wav(tmp_path / "buzz.wav")
    assert x.shape[1] == 8
    square = x[240:1200, 0]  # after the 5 ms attack, in its decay: a square, +-E
    s = np.arange(240, 1200)
    assert np.array_equal(np.sign(square), np.where(s % 240 < 120, 1.0, -1.0))
    assert np.abs(x[1200:14000, 0]).max() == pytest.approx(0.7, abs=1e-3)  # the sustain
    assert np.abs(x[14400:38400, 7]).max() > 0.1  # the line ends at (3, 1): actuator 7
    assert not x[38400 + 100 :].any()  # 0.8 s: over, faded
