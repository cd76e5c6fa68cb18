"""`tactile render`/`stream` of a .tact file and `tactile export-tact`, run as a user runs them."""

import json

import numpy as np
import pytest

from tactile_core.cli import main
from tactile_core.device.profile import find_profile
from tactile_core.files.presets import Preset, save_preset
from tactile_core.files.tact import load_pattern, read_tact
from tactile_core.rendering.scene import Scene
from tactile_core.rendering.shapes import TimedPath

from . import tact_support as ts

SAMPLE = "tests/data/testfeedback.tact"
VEST = find_profile("vest-4x5")


def test_render_writes_the_patterns_frames(tmp_path, capsys):
    out = tmp_path / "frames.csv"
    args = ["render", "--shape", f"tact:{SAMPLE}", "--method", "BA", "--profile", "vest-4x5",
            "--mu", "0.2", "--gamma", "0.8", "--rate", "50", "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    assert "wrote 50 frames of VestFront" in capsys.readouterr().out
    header = out.read_text().splitlines()[0].split(",")
    assert header == ["time", *VEST.layout.names]
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    time_s, frames = load_pattern(SAMPLE).frames("BA", VEST.layout, rate_hz=50.0, mu=0.2,
                                                 gamma=0.8)  # fmt: skip
    np.testing.assert_allclose(data[:, 0], time_s)
    np.testing.assert_allclose(data[:, 1:], frames, atol=1e-9)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--shape", "tact:"], "needs a file"),
        (["--shape", "tact:missing.tact"], "missing.tact: no such file"),
        (["--shape", f"tact:{SAMPLE}", "--tact-position", "Head"], "position 'Head' holds no"),
        (["--shape", f"tact:{SAMPLE}", "--direction", "reverse"], "does not apply to a .tact"),
        (["--shape", f"tact:{SAMPLE}", "--method", "AS"], "AS cannot render on this layout"),
        (["--shape", "tact:EMPTY"], "no paths or dots to play"),
    ],
)
def test_render_refuses_what_it_cannot_play(tmp_path, capsys, extra, message):
    empty = ts.write(tmp_path, ts.document(), "empty.tact")
    extra = [f"tact:{empty}" if a == "tact:EMPTY" else a for a in extra]  # a file with nothing
    args = ["render", "--method", "EN", "--profile", "vest-4x5", "--out", str(tmp_path / "f.csv")]
    assert main(args + extra) == 2
    assert message in capsys.readouterr().err


def test_render_names_the_bad_field(tmp_path, capsys):
    bad = ts.write(tmp_path, ts.mutate(ts.simple(), ["project", "tracks", 0, "effects", 0,
                                                     "offsetTime"], -1))  # fmt: skip
    args = ["render", "--shape", f"tact:{bad}", "--method", "IM", "--out", str(tmp_path / "f.csv")]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "tactile render: error:" in err and "tracks[0].effects[0].offsetTime must be" in err


def test_stream_plays_the_file_then_stops(tmp_path, capsys):
    record = tmp_path / "sent.csv"
    args = ["stream", "--device", "sim", "--shape", f"tact:{SAMPLE}", "--method", "BA",
            "--profile", "vest-4x5", "--rate", "100", "--record", str(record)]  # fmt: skip
    assert main(args) == 0
    captured = capsys.readouterr()
    out = captured.out
    assert "frames applied" in out
    assert f"playing VestFront of {SAMPLE}\n" in captured.err  # the sample's only position
    table = np.loadtxt(record, delimiter=",", skiprows=1)
    levels = table[:, -20:]
    # the file lasts 1 s at 100 Hz, then the all-off frame: ~100 frames over ~1 s (a loaded
    # machine skips deadlines, never the file's time: fewer frames, the same span)
    assert 10 <= len(levels) <= 130
    assert 0.9 <= table[-1, 0] - table[0, 0] <= 1.6
    assert levels[: len(levels) // 2].any() and not levels[-1].any()


def test_stream_names_the_positions_it_leaves_out(tmp_path, capsys):
    # render said "not played: VestBack"; stream said nothing of which position played
    with open(SAMPLE, encoding="utf-8-sig") as f:
        data = json.load(f)
    for track in data["project"]["tracks"]:
        for effect in track["effects"]:
            effect["modes"]["VestBack"] = json.loads(json.dumps(effect["modes"]["VestFront"]))
    both = tmp_path / "both.tact"
    both.write_text(json.dumps(data))
    args = ["stream", "--device", "sim", "--shape", f"tact:{both}", "--method", "BA",
            "--profile", "vest-4x5", "--seconds", "0.1"]  # fmt: skip
    assert main(args) == 0
    assert f"playing VestFront of {both}; not played: VestBack" in capsys.readouterr().err


def test_export_tact_writes_a_shapes_trace(tmp_path, capsys):
    out = tmp_path / "circle.tact"
    args = ["export-tact", "--shape", "circle:2.5,3,2", "--duration", "1.5", "--out", str(out)]
    assert main(args) == 0
    assert "wrote 76 points over 1.5 s (CONST_TDM)" in capsys.readouterr().out
    data = json.loads(out.read_text())
    assert data["project"]["name"] == "circle"
    (path,) = read_tact(out).paths
    assert path.points[0] == (1.0, 0.5) and path.times_s[-1] == 1.5


def test_export_tact_writes_a_presets_drawn_path(tmp_path):
    drawn = TimedPath([(0.0, 0.0), (3.0, 4.0), (1.5, 2.0)], [0.0, 0.7, 1.2], [1.0, 0.5, 0.8])
    preset = tmp_path / "drawn.json"
    save_preset(Preset(Scene(drawn, "BA", duration_s=1.2), device_profile="vest-4x5"), preset)
    out = tmp_path / "drawn.tact"
    assert main(["export-tact", "--preset", str(preset), "--position", "VestBack",
                 "--out", str(out)]) == 0  # fmt: skip
    (back,) = load_pattern(out).paths(VEST.layout)
    assert np.array(back.points) == pytest.approx(np.array(drawn.points), abs=1e-3)
    assert back.times_s == pytest.approx(drawn.times_s) and back.intensities == drawn.intensities


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--shape", "timed:0,0,0,1,1,1,1,1", "--duration", "3"], "--duration does not apply"),
        (["--shape", "circle:2.5,3,2", "--profile", "vest-4x5", "--cols", "4"], "twice"),
        (["--shape", "circle:2.5,3,2", "--cols", "0"], "cols must be >= 1"),
        (["--shape", "circle:2.5,3"], "needs 3 numbers"),
    ],
)
def test_export_tact_refuses_bad_arguments(tmp_path, capsys, extra, message):
    assert main(["export-tact", *extra, "--out", str(tmp_path / "x.tact")]) == 2
    assert message in capsys.readouterr().err
