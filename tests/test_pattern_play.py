"""Patterns played: streamed into the simulated array and the emulator, through open_array,
`tactile render`/`stream`/`export-tact --shape pattern:FILE`, and exported to .tact and back."""

import json
import sys

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.cli import main
from tactile_core.device.link import SimulatedArray
from tactile_core.device.profile import find_profile
from tactile_core.files.pattern import Pattern, example_patterns
from tactile_core.files.tact import load_pattern, read_tact
from tactile_core.rendering.scene import Scene

from .emulator_support import stream
from .helpers import align
from .test_streamer import Taps, virtual

PALM = find_profile("palm-5x6")
VEST = find_profile("vest-front-back")
EXAMPLES = example_patterns()
LETTER, SWEEP, TAPS = (Pattern.load(EXAMPLES[k]) for k in ("letter-a", "vest-sweep", "taps"))


def onsets(on) -> int:
    """How many times ``on`` (a boolean per frame) turns on."""
    return int(np.count_nonzero(np.diff(np.concatenate([[0], np.asarray(on, int)])) == 1))


def levels_of(pattern, profile, method, rate_hz, mu=0.0, gamma=1.0):
    """What the array should receive: the batch frames quantised, in channel order."""
    _, frames = pattern.frames(method, profile.layout, rate_hz=rate_hz, mu=mu, gamma=gamma)
    flat = frames.reshape(len(frames), -1)
    return tc.quantize(flat, profile.levels)[:, profile.array.channel_index]


@pytest.mark.parametrize("pattern, profile, method", [(LETTER, PALM, "AS"), (SWEEP, VEST, "BA"),
                                                      (TAPS, PALM, "IM")])  # fmt: skip
def test_a_pattern_streamed_into_the_simulated_array_is_its_frames(pattern, profile, method):
    scene = Scene(None, method, mu=0.2, gamma=0.8, rate_hz=100.0, source=pattern)
    expected = levels_of(pattern, profile, method, 100.0, 0.2, 0.8)
    n = len(expected)
    taps = Taps()
    sim = SimulatedArray(profile)
    with virtual(sim, profile, scene=scene, taps=[taps]):
        taps.wait_for(n + 20)
    # on a virtual clock no deadline is missed: frame k of the stream is frame k of the pattern
    sent = np.array([f[2] for f in taps.frames])
    assert np.array_equal(sent[:n], expected) and expected.any()
    assert not sent[n:].any()  # then off


def test_open_array_plays_the_pattern_for_its_duration_into_the_array():
    received = []
    with tc.open_array("sim", rate_hz=100.0) as array:
        array.streamer.taps.append(lambda _t, _seq, levels: received.append(
            np.frombuffer(levels, np.uint8).copy()))  # fmt: skip
        shown = array.play(TAPS, "AS", mu=0.0, gamma=1.0)
        live = TAPS.live("AS", PALM.layout, tc.Sampling(100.0), 0.0, 1.0)
        assert live.precomputed  # tabulated before it played
    assert shown.duration_s == pytest.approx(TAPS.duration_s) and not shown.interrupted
    expected = levels_of(TAPS, PALM, "AS", 100.0)
    lit = [f for f in received if f.any()]
    assert align(lit, expected) >= 0 and len(lit) >= 10
    # four taps on actuator 17 (column 2, row 3), nothing else
    channel = int(np.flatnonzero(PALM.array.channel_index == 17)[0])
    on = np.array([f[channel] > 0 for f in received])
    assert onsets(on) == 4
    assert all(np.flatnonzero(f).tolist() == [channel] for f in lit)


def test_render_writes_a_patterns_frames_to_csv_npz_and_wav(tmp_path, capsys):
    args = ["render", "--shape", f"pattern:{EXAMPLES['letter-a']}", "--method", "AS",
            "--mu", "0.2", "--gamma", "0.8", "--rate", "50"]  # fmt: skip
    assert main([*args, "--out", str(tmp_path / "a.csv")]) == 0
    assert "pattern 'letter A' of" in capsys.readouterr().out
    table = np.loadtxt(tmp_path / "a.csv", delimiter=",", skiprows=1)
    time_s, frames = LETTER.frames("AS", PALM.layout, rate_hz=50.0, mu=0.2, gamma=0.8)
    assert table[:, 0] == pytest.approx(time_s) and len(table) == 105
    assert table[:, 1:] == pytest.approx(frames.reshape(105, 30), abs=1e-6)
    assert main([*args, "--out", str(tmp_path / "a.npz")]) == 0
    with np.load(tmp_path / "a.npz") as saved:
        assert np.array_equal(saved["frames"], frames)
    wav = ["render", "--shape", f"pattern:{EXAMPLES['vest-sweep']}", "--method", "BA",
           "--profile", "vest-front-back", "--rate", "100",
           "--out", str(tmp_path / "s.wav")]  # fmt: skip
    assert main(wav) == 0
    assert "40 channels of 1.6" in capsys.readouterr().out


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--shape", "pattern:"], "--shape pattern: needs a file"),
        (["--shape", "pattern:missing.json"], "missing.json: no such file"),
        (["--shape", f"pattern:{EXAMPLES['vest-sweep']}"],
         "effects[0].group must name a group of the layout (it has none), got 'front'. It "
         "plays on the device profile vest-front-back: --profile vest-front-back"),
        (["--shape", f"pattern:{EXAMPLES['letter-a']}", "--direction", "reverse"],
         "--direction reverse does not apply to a pattern"),
    ],
)  # fmt: skip
def test_render_refuses_a_pattern_it_cannot_play_by_field(tmp_path, capsys, extra, message):
    args = ["render", "--method", "AS", "--out", str(tmp_path / "x.csv"), *extra]
    assert main(args) == 2
    assert message in capsys.readouterr().err or pytest.fail(capsys.readouterr().err)


def test_stream_plays_the_pattern_then_stops(tmp_path, capsys):
    record = tmp_path / "sent.csv"
    args = ["stream", "--device", "sim", "--shape", f"pattern:{EXAMPLES['vest-sweep']}",
            "--method", "BA", "--profile", "vest-front-back", "--rate", "100",
            "--record", str(record)]  # fmt: skip
    assert main(args) == 0
    err = capsys.readouterr().err
    assert "playing pattern 'front to back' of" in err and "(2 effects, 1.6 s)" in err
    levels = np.loadtxt(record, delimiter=",", skiprows=1)[:, -40:]
    lit = levels[levels.any(axis=1)]
    # the front lights first, then the back; never both in one frame
    front, back = lit[:, :20].any(axis=1), lit[:, 20:].any(axis=1)
    assert front.any() and back.any() and not (front & back).any()
    assert np.flatnonzero(front).max() < np.flatnonzero(back).min()


@pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals are POSIX")
def test_stream_plays_the_taps_into_the_emulator(emulator):
    emu = emulator("--rate", "100")
    proc = stream(emu.path, "--shape", f"pattern:{EXAMPLES['taps']}", "--method", "AS",
                  "--rate", "100", "--lead-ms", "0")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    report, log = emu.finish()
    assert report["bad_frames"] == {k: 0 for k in report["bad_frames"]}
    levels = log[:, 2:].astype(np.uint8)
    channel = int(np.flatnonzero(PALM.array.channel_index == 17)[0])
    on = levels[:, channel] > 0
    assert onsets(on) == 4  # four taps arrived
    assert not np.delete(levels, channel, axis=1).any() and not levels[-1].any()
    expected = levels_of(TAPS, PALM, "AS", 100.0)
    assert align(levels[on], expected) >= 0  # each lit frame is one of the pattern's


@pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals are POSIX")
def test_stream_plays_the_letter_to_its_last_frame_before_it_stops(emulator):
    # Timed frames go out 20 ms ahead; the stream stopped when the pattern's duration had passed
    # since the hello, and its final all-off dropped the stroke's last 6 scheduled frames.
    emu = emulator("--rate", "300")
    proc = stream(emu.path, "--shape", f"pattern:{EXAMPLES['letter-a']}", "--method", "AS")
    assert proc.returncode == 0, proc.stderr
    _, log = emu.finish()
    levels = log[:, 2:].astype(np.uint8)
    expected = levels_of(LETTER, PALM, "AS", 300.0)  # 630 frames, the last one lit
    assert expected[-1].any() and not levels[-1].any()  # the stroke's end, then all off
    lit = np.flatnonzero(levels.any(axis=1))
    played = levels[lit[0] : lit[-1] + 1]  # from the first lit frame to the last
    # each frame is the pattern's, in order (a stalled host may skip some), to its last
    assert align(played, expected) == len(expected) - 1


def test_export_tact_then_import_gives_the_same_frames(tmp_path, capsys):
    out = tmp_path / "sweep.tact"
    args = ["export-tact", "--shape", f"pattern:{EXAMPLES['vest-sweep']}", "--profile",
            "vest-front-back", "--group", "front=VestFront", "--group", "back=VestBack",
            "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    assert "wrote pattern 'front to back'" in capsys.readouterr().out
    file = read_tact(out)
    assert file.positions == ("VestFront", "VestBack") and len(file.paths) == 2
    groups = {"VestFront": "front", "VestBack": "back"}
    again = Pattern.from_tact(out, groups=groups)
    _, before = SWEEP.frames("BA", VEST.layout, rate_hz=100.0)
    _, after = again.frames("BA", VEST.layout, rate_hz=100.0)
    assert after == pytest.approx(before, abs=1e-12) and before.any()
    # the letter on the palm, re-imported as bHaptics' pattern: the same frames
    LETTER.save_tact(tmp_path / "a.tact", PALM.layout)
    _, imported = load_pattern(tmp_path / "a.tact").frames("AS", PALM.layout, rate_hz=100.0)
    _, own = LETTER.frames("AS", PALM.layout, rate_hz=100.0)
    assert imported == pytest.approx(own, abs=1e-9) and own.any()


def test_an_exported_pattern_has_an_effect_per_play_and_its_dots_on_motors(tmp_path):
    doc = TAPS.to_tact(PALM.layout, created_ms=0)
    (track,) = doc["project"]["tracks"]
    starts = [e["startTime"] for e in track["effects"]]
    assert starts == [0, 250, 500, 750] and {e["offsetTime"] for e in track["effects"]} == {250}
    mode = track["effects"][0]["modes"]["VestFront"]
    assert mode["mode"] == "DOT_MODE"
    pieces = mode["dotMode"]["feedback"]  # the rising envelope: four 20 ms pieces
    assert [(p["startTime"], p["endTime"]) for p in pieces] == [(0, 20), (20, 40), (40, 60),
                                                                (60, 80)]  # fmt: skip
    # the envelope at each piece's middle (0.4 -> 1 over 80 ms: 0.475, 0.625, 0.775, 0.925)
    assert [p["pointList"][0]["intensity"] for p in pieces] == [0.475, 0.625, 0.775, 0.925]
    # actuator 17 (column 2, row 3) is the Designer's motor 12: rows from the top, 5 a row
    assert {p["pointList"][0]["index"] for p in pieces} == {12}
    json.dumps(doc)  # JSON-ready
    with pytest.raises(ValueError, match=r"positions\['front'\] must name a group"):
        TAPS.to_tact(PALM.layout, positions={"front": "VestFront"})
    # an effect of no group written where a group's actuators are numbered: refused, not a
    # dot on a motor that position does not have
    mixed = SWEEP.add(TAPS.effects[0].replace(content=tc.Dots([tc.Dot(36)])))
    with pytest.raises(ValueError, match=r"effects\[2\] plays on every actuator, which would be "
                       r"written to VestFront, the position of group 'front' alone: give the "
                       r"effect one of the groups 'front', 'back'"):  # fmt: skip
        mixed.to_tact(VEST.layout, positions={"front": "VestFront", "back": "VestBack"})
    back = mixed.to_tact(VEST.layout, position="Head",
                         positions={"front": "VestFront", "back": "VestBack"})  # fmt: skip
    assert len(back["project"]["layout"]["layouts"]["Head"]) == 40


@pytest.mark.parametrize("source", ["designer", "paths and dots"])
def test_a_tact_file_imported_as_effects_plays_as_the_file_does(tmp_path, source):
    # each .tact effect becomes one TactEffect at its startTime; played, the pattern gives the
    # frames bHaptics' file gives played as a .tact pattern (the same mapping, the same max)
    from . import tact_support as ts

    if source == "designer":
        path = "tests/data/testfeedback.tact"
    else:
        path = ts.write(tmp_path, ts.crossing_paths_and_a_dot())
    vest = find_profile("vest-4x5").layout
    imported = Pattern.from_tact(path)
    assert all(e.kind == "tact" for e in imported.effects)
    _, own = imported.frames("BA", vest, rate_hz=100.0, mu=0.2, gamma=0.8)
    _, theirs = load_pattern(path).frames("BA", vest, rate_hz=100.0, mu=0.2, gamma=0.8)
    assert own.shape == theirs.shape and own == pytest.approx(theirs, abs=1e-12)
    again = Pattern.load(imported.save(tmp_path / "imported.json"))
    assert again == imported


def test_the_compiled_form_holds_the_patterns_frames_every_20_ms(tmp_path, capsys):
    out = tmp_path / "sweep.tact"
    args = ["export-tact", "--shape", f"pattern:{EXAMPLES['vest-sweep']}", "--profile",
            "vest-front-back", "--group", "front=VestFront", "--group", "back=VestBack",
            "--compiled", "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    assert "and its frames by BA every 20 ms (compiled form)" in capsys.readouterr().out
    doc = json.loads(out.read_text())
    assert doc["intervalMillis"] == 20 and len(doc["feedback"]) == 80  # 1.6 s
    # frame 10 (0.2 s) is a quarter of the way along the front's line (0.8 s), BA on the vest;
    # bHaptics numbers a panel's motors from the top left, row by row
    layout = VEST.layout
    motors = sorted(range(20), key=lambda a: (-layout.xy[a][1], layout.xy[a][0]))
    raw = tc.render(tc.Line((0.0, 2.0), (3.0, 2.0)), "BA", 0.25, grid=layout)
    expected = np.floor(raw[motors] * 100 + 1e-9).astype(int).tolist()
    frame = {e["position"]: e["values"] for e in doc["feedback"]["200"]}
    assert frame["VestFront"] == expected and any(expected)
    assert not any(frame["VestBack"])  # the back waits for its turn
    assert read_tact(out, form="compiled").positions == ("VestFront", "VestBack")
