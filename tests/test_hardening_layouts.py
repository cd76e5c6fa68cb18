"""Layout profiles, .tact files and the command line's files broken as an operator would break
them (the review of the live features): each is refused with one line naming the file and the
field, or handled, never a traceback and never a file left behind."""

import copy
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from tactile_core.device.profile import ProfileError, load_profile, profile_from_dict
from tactile_core.files.tact import TactError, read_tact
from tactile_core.rendering.layout import Layout

from . import tact_support as ts
from .helpers import run_cli_last_line

CLI = [sys.executable, "-m", "tactile_core.cli"]
BELT = {
    "format": "tactile-device-profile",
    "version": 1,
    "name": "belt",
    "pitch_mm": 100.0,
    "levels": 23,
    "layout": {
        "units": "mm",
        "actuators": [{"x": 100.0 * k, "y": 0.0, "name": f"m{k}"} for k in range(8)],
        "wrap": {"axis": "x", "circumference": 800.0},
    },
}


run_cli = run_cli_last_line


def strip(n, wrap=False):
    """A profile of ``n`` actuators in a row, one pitch apart."""
    data = copy.deepcopy(BELT)
    data["layout"] = {"units": "pitch", "actuators": [[float(k), 0.0] for k in range(n)]}
    if wrap:
        data["layout"]["wrap"] = {"axis": "x", "circumference": float(n)}
    return data


# --- profiles with layouts ---------------------------------------------------------------------


@pytest.mark.parametrize("wrap", [False, True])
def test_render_takes_a_layout_of_255_actuators(tmp_path, capsys, wrap):
    """A layout is its own channel strip, not a grid of up to 64 columns: 255 actuators (the
    most a profile holds) render to CSV and WAV (was: 'cols must be >= 1 and <= 64')."""
    path = tmp_path / "strip.json"
    path.write_text(json.dumps(strip(255, wrap)))
    for out in ("frames.csv", "carriers.wav"):
        code, line = run_cli(capsys, "render", "--profile", path, "--shape", "line:0,0,254,0",
                             "--method", "BA", "--rate", "10", "--duration", "0.2",
                             "--out", tmp_path / out)  # fmt: skip
        assert code == 0, line
    header = (tmp_path / "frames.csv").read_text().splitlines()[0].split(",")
    assert len(header) == 256 and header[:2] == ["time", "a0"]


def test_render_refuses_cols_and_rows_with_a_layout(tmp_path, capsys):
    code, line = run_cli(capsys, "render", "--profile", "belt-8", "--cols", "8", "--shape",
                         "line:0,0,7,0", "--method", "BA", "--out", tmp_path / "x.csv")  # fmt: skip
    assert code == 2 and "--cols" in line and "belt-8" in line and "layout" in line


@pytest.mark.parametrize("pitch", [1e308, 1e-308, 0.001, 1e7])
def test_profile_pitch_out_of_range_is_refused_naming_it(pitch):
    """pitch_mm 1e308 made every actuator 'duplicate' at (0, 0); 1e-308 an infinite wrap,
    reported without the file's name."""
    data = copy.deepcopy(BELT)
    data["pitch_mm"] = pitch
    with pytest.raises(ProfileError, match=r"^belt.json: field 'pitch_mm' must be within"):
        profile_from_dict(data, "belt.json")


def test_profile_wrap_beyond_the_coordinate_bound_names_the_file_and_field():
    data = copy.deepcopy(BELT)
    data["layout"]["wrap"]["circumference"] = 1e12
    with pytest.raises(ProfileError, match=r"^belt.json: field 'layout.wrap.circumference'"):
        profile_from_dict(data, "belt.json")


@pytest.mark.parametrize("name", ["a\nb", "front,left", 'say "hi"', "tab\there", " front",
                                  "front ", "\x00", "bell\x07"])  # fmt: skip
def test_profile_actuator_names_that_would_break_a_csv_header_are_refused(name):
    """Names become the column headers of render's CSV and the recorder's (and LSL's channel
    labels): a newline, comma or quote in one made a header with the wrong number of columns."""
    data = copy.deepcopy(BELT)
    data["layout"]["actuators"][1]["name"] = name
    with pytest.raises(ProfileError, match=r"layout.actuators\[1\].name"):
        profile_from_dict(data, "belt.json")
    with pytest.raises(ValueError, match="layout names"):
        Layout([(0.0, 0.0), (1.0, 0.0)], names=["ok", name])


def test_profile_named_like_a_bundled_file_says_how_to_name_it(tmp_path, monkeypatch):
    """docs/device.md said --profile belt-8.json; the bundled profiles go by name."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ProfileError, match=r"belt-8.json: no such file.*belt-8"):
        load_profile("belt-8.json")


# --- .tact files -------------------------------------------------------------------------------


def test_tact_time_as_a_huge_integer_is_refused_naming_the_field(tmp_path):
    """JSON integers of a few hundred digits parse; float() of one overflowed (a traceback in
    tactile render and in the tuner's import)."""
    doc = ts.document(ts.effect({"VestFront": ts.path_mode(
        [ts.point(0.1, 0.5, 1, 0), ts.point(0.9, 0.5, 1, 10**400)])}))  # fmt: skip
    path = tmp_path / "huge.tact"
    path.write_text(json.dumps(doc))
    with pytest.raises(TactError, match=r"pointList\[1\].time must be within .*got inf"):
        read_tact(path)


def test_render_tact_with_a_huge_integer_is_a_usage_error(tmp_path, capsys):
    doc = ts.document(ts.effect({"VestFront": ts.path_mode(
        [ts.point(10**400, 0.5, 1, 0), ts.point(0.9, 0.5, 1, 500)])}))  # fmt: skip
    path = tmp_path / "huge.tact"
    path.write_text(json.dumps(doc))
    code, line = run_cli(capsys, "render", "--shape", f"tact:{path}", "--method", "AS",
                         "--out", tmp_path / "x.csv")  # fmt: skip
    assert code == 2 and "pointList[0].x must be within" in line


# --- files written by the command line ---------------------------------------------------------


@pytest.mark.parametrize("signame", ["SIGTERM", "SIGHUP"])
def test_render_ended_by_a_signal_leaves_no_temporary_file(tmp_path, signame):
    """SIGTERM in the middle of a long render left its half-written temporary file (hundreds
    of MB for a WAV) beside the output; now it ends as Ctrl-C does: removed, status 128+N."""
    out = tmp_path / "long.wav"
    proc = subprocess.Popen(
        [*CLI, "render", "--profile", "belt-8", "--shape", "line:0,0,7,0", "--method", "BA",
         "--duration", "1200", "--rate", "300", "--samplerate", "96000", "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    deadline = time.monotonic() + 60
    while not any(p.name.endswith(".tmp") for p in tmp_path.iterdir()):
        assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
        time.sleep(0.05)
    proc.send_signal(getattr(signal, signame))
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + getattr(signal, signame), err
    assert "Traceback" not in err and "tactile render: ended by" in err
    assert sorted(os.listdir(tmp_path)) == []


@pytest.mark.parametrize(
    "device, said",
    [
        ("", "the device URL is empty"),
        ("/dev/" + "x" * 100_000, "longer than 1024 characters"),
        ("audio:" + "x" * 100_000, "longer than 1024 characters"),
    ],
)
def test_stream_device_urls_empty_or_huge_are_one_short_line(capsys, device, said):
    """'--device ""' said 'no such port:  (is the device plugged in?)'; a 100,000-character
    URL came back three times in a 300 KB error line."""
    code, line = run_cli(capsys, "stream", "--device", device, "--shape", "circle:2.5,3,2",
                         "--method", "AS", "--seconds", "0.1")  # fmt: skip
    assert code == 1 and said in line and len(line) < 300


@pytest.mark.parametrize("where", ["modes", "layouts"])
def test_tact_position_names_that_a_terminal_would_act_on_are_refused(tmp_path, where):
    """Position names are printed ('not played: VestBack'): a file's ESC sequences in one went
    raw to the terminal of whoever rendered it."""
    evil = "\x1b[2J\x1b]0;owned\x07"
    doc = ts.document(ts.effect({"VestFront": ts.path_mode(
        [ts.point(0.1, 0.5, 1, 0), ts.point(0.9, 0.5, 1, 500)])}))  # fmt: skip
    if where == "modes":
        modes = doc["project"]["tracks"][0]["effects"][0]["modes"]
        modes[evil] = modes["VestFront"]
    else:
        layouts = doc["project"]["layout"]["layouts"]
        layouts[evil] = layouts["VestFront"]
    path = tmp_path / "evil.tact"
    path.write_text(json.dumps(doc))
    with pytest.raises(TactError, match="a position's name is 1-64 printable") as caught:
        read_tact(path)
    assert "\x1b" not in str(caught.value)


def test_profile_groups_are_bounded_and_printable():
    """10,000 groups fit a 1 MiB profile and took the tuner 50 s to draw (a box and a label
    each, in every view); a group name is a label, so no control characters either."""
    data = copy.deepcopy(BELT)
    data["layout"]["groups"] = {f"g{k}": [0] for k in range(65)}
    with pytest.raises(ProfileError, match="layout groups: at most 64, got 65"):
        profile_from_dict(data, "belt.json")
    data["layout"]["groups"] = {f"g{k}": [0] for k in range(64)}
    assert len(profile_from_dict(data, "belt.json").layout.groups) == 64
    data["layout"]["groups"] = {"front\x1b[2J": [0]}
    with pytest.raises(ProfileError, match="group names must be 1-32 printable"):
        profile_from_dict(data, "belt.json")


def test_profile_version_of_hundreds_of_digits_is_shown_cut():
    data = copy.deepcopy(BELT)
    data["version"] = 10**400
    with pytest.raises(ProfileError, match="newer than this software reads") as caught:
        profile_from_dict(data, "belt.json")
    assert len(str(caught.value)) < 200
