"""The cases the hardening review found, kept as regression tests: each is refused cleanly
(one line naming the parameter, the right exit status) or handled, never a traceback or a hang.
"""

import json
import os
import signal
import subprocess
import sys
import time

import pytest

import tactile_core as tc
from tactile_core._shared.assets import asset_path
from tactile_core.device.profile import ProfileError, find_profile, load_profile, profile_from_dict
from tactile_core.experiments.results import check_participant
from tactile_core.files.export import write_lut_csv
from tactile_core.files.presets import PresetError, load_preset

from .emulator_support import wait_streaming
from .helpers import run_cli_last_line

CLI = [sys.executable, "-m", "tactile_core.cli"]
PRESET = json.loads(asset_path("presets", "exp3-square.json").read_text())
PROFILE = json.loads(asset_path("devices", "palm-5x6.json").read_text())


run_cli = run_cli_last_line


@pytest.mark.parametrize(
    ("shape", "field"),
    [
        ("square:2.5,3,1e308", "edge"),
        ("circle:1e308,1e308,1e308", "center[0]"),
        ("line:-1e308,0,1e308,0", "p0[0]"),
        ("polygon:0,0,1e308,0,0,1e308", "points[1][0]"),
    ],
)
def test_huge_finite_coordinates_are_refused(capsys, tmp_path, shape, field):
    code, err = run_cli(capsys, "render", "--shape", shape, "--method", "AS", "--out",
                        str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and field in err and "within" in err


@pytest.mark.parametrize(
    ("option", "value", "word"),
    [
        ("--duration", "1e308", "duration"),
        ("--rate", "1e9", "rate"),
        ("--duration", "nan", "duration"),
    ],
)
def test_render_numbers_beyond_their_bounds(capsys, tmp_path, option, value, word):
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "AS",
                        option, value, "--out", str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and err.startswith(f"tactile render: error: {word}")
    assert not (tmp_path / "f.csv").exists()


def test_render_frame_count_is_bounded(capsys, tmp_path):
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "AS",
                        "--duration", "3600", "--rate", "100000", "--out",
                        str(tmp_path / "f.npz"))  # fmt: skip
    assert code == 2 and "at most 1000000 frames" in err


@pytest.mark.parametrize(("option", "value"), [("--pause", "1e308"), ("--duration", "1e308")])
def test_stream_refuses_huge_pauses_before_starting(capsys, option, value):
    code, err = run_cli(capsys, "stream", "--device", "sim", "--shape", "circle:2.5,3,2",
                        "--method", "AS", option, value, "--seconds", "0.2")  # fmt: skip
    assert code == 2 and option[2:] in err and "at most 3600 s" in err


def test_emulate_seconds_nan_is_refused_not_a_hang():
    proc = subprocess.run([*CLI, "emulate", "--seconds", "nan"], capture_output=True, text=True,
                          timeout=20)  # fmt: skip
    assert proc.returncode == 2 and "seconds must be a finite number" in proc.stderr


@pytest.mark.parametrize(
    "argv",
    [
        [
            "stream",
            "--device",
            "sim",
            "--shape",
            "circle:2.5,3,2",
            "--method",
            "AS",
            "--seconds",
            "30",
            "--record",
            "/proc/nope/r.csv",
        ],
        ["emulate", "--seconds", "30", "--log", "/proc/nope/log.csv"],
        ["emulate", "--seconds", "30", "--json", "/nonexistent-folder/r.json"],
    ],
)
def test_unwritable_outputs_are_refused_before_the_work(capsys, argv):
    started = time.monotonic()
    code, err = run_cli(capsys, *argv)
    assert code == 2 and "does not exist" in err
    assert time.monotonic() - started < 15.0  # refused up front, not after its 30 s of work


def test_simulate_into_a_file_is_refused_and_into_a_missing_folder_creates_it(capsys, tmp_path):
    target = tmp_path / "a-file"
    target.write_text("x")
    code, err = run_cli(capsys, "simulate", str(target), "--participants", "1",
                        "--experiments", "exp3")  # fmt: skip
    assert code == 2 and "is a file, not a folder" in err
    code, _ = run_cli(capsys, "simulate", str(tmp_path / "new" / "results"), "--participants",
                      "1", "--experiments", "exp3")  # fmt: skip
    assert code == 0 and (tmp_path / "new" / "results" / "participant-sim01").is_dir()


def write_json(tmp_path, name, data):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return path


@pytest.mark.parametrize(
    ("change", "word"),
    [
        ({"shape": {"type": []}}, "shape.type"),
        ({"shape": {"type": "square", "center": [2.5, 3.5], "edge": 1e308}}, "edge"),
        ({"shape": {"type": "circle", "center": [2.5, 3.5], "radius": "1_0"}}, "radius"),
        ({"shape": {"type": "circle", "center": "25", "radius": 1.0}}, "center"),
        ({"shape": {"type": "polyline", "points": [[0, 0], [1, 1]], "closed": "false"}}, "closed"),
        ({"device_profile": "/dev/zero"}, "device_profile"),
        ({"device_profile": "../../etc/passwd.json"}, "device_profile"),
        ({"mu": "0.5"}, "mu"),
        ({"dither": 1}, "dither"),
        ({"name": "x" * 100_000}, "name"),
    ],
)
def test_bad_presets_are_refused_naming_the_field(tmp_path, change, word):
    path = write_json(tmp_path, "p.json", {**PRESET, **change})
    with pytest.raises(PresetError) as info:
        load_preset(path)
    message = str(info.value)
    assert word in message and str(path) in message and len(message) < 400


def test_a_4300_digit_integer_is_a_preset_error(tmp_path):
    text = json.dumps(PRESET).replace('"mu": 0.33', '"mu": ' + "9" * 5000)
    with pytest.raises(PresetError, match="not valid JSON"):
        load_preset(write_json(tmp_path, "p.json", text))


@pytest.mark.parametrize("path", ["/dev/zero", "/dev/null", "/"])
def test_profiles_are_read_only_from_regular_files(path):
    with pytest.raises(ProfileError, match="not a regular file"):
        load_profile(path)


def test_a_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    started = time.monotonic()
    with pytest.raises(PresetError, match="not a regular file"):
        load_preset(fifo)
    with pytest.raises(ProfileError, match="not a regular file"):
        load_profile(fifo)
    assert time.monotonic() - started < 1.0


def test_a_huge_file_is_refused_by_its_size(tmp_path):
    path = tmp_path / "big.json"
    path.write_text(" " * (2 << 20) + "{}")
    with pytest.raises(ProfileError, match="larger than"):
        load_profile(path)


def test_presets_name_profiles_never_paths(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path))
    assert find_profile("palm-5x6").name == "palm-5x6"
    with pytest.raises(ProfileError, match="not a path"):
        find_profile(str(asset_path("devices", "palm-5x6.json")))
    mine = tmp_path / "tactile-tuner" / "devices"
    mine.mkdir(parents=True)
    data = {**PROFILE, "name": "lab-array"}
    (mine / "lab-array.json").write_text(json.dumps(data))
    assert find_profile("lab-array").name == "lab-array"
    with pytest.raises(ProfileError, match="no device profile named 'other'"):
        find_profile("other")


@pytest.mark.parametrize(
    ("change", "word"),
    [
        ({"calibration": {"offset": [[0.0] * 6] * 5, "gain": [[1.0] * 6] * 5}}, "6 rows of 5"),
        ({"response": {"drive": [[0, 0.5], [1]], "output": [0, 0.5, 1]}}, "response.drive"),
        ({"baud": 1}, "baud"),
        ({"columns": "5"}, "columns"),
        ({"name": "../x"}, "name"),
    ],
)
def test_bad_profiles_are_refused_naming_the_field(change, word):
    with pytest.raises(ProfileError) as info:
        profile_from_dict({**PROFILE, **change}, source="lab.json")
    assert word in str(info.value)


def test_a_calibration_table_in_rows_is_read_row_by_row():
    rows = [[r * 0.01 + c * 0.001 for c in range(5)] for r in range(6)]
    profile = profile_from_dict(
        {**PROFILE, "calibration": {"offset": rows, "gain": [[1.0] * 5] * 6}}
    )
    assert profile.offset[7] == pytest.approx(0.012)  # row 1, column 2


def test_refusals_do_not_echo_huge_values():
    with pytest.raises(ValueError) as info:
        tc.parse_shape("circle:" + "9" * 100_000)
    assert len(str(info.value)) < 300
    with pytest.raises(ValueError) as info:
        tc.Line(("x" * 100_000, 0), (1, 1))
    assert len(str(info.value)) < 300


@pytest.mark.parametrize("pid", ["P1\n", "P1 ", "", "a" * 65, "../x", "P1/2"])
def test_participant_ids_are_strict(pid):
    with pytest.raises(ValueError, match="participant"):
        check_participant(pid)


def test_a_failed_export_keeps_the_previous_file(tmp_path, monkeypatch):
    path = tmp_path / "lut.csv"
    write_lut_csv(path, 0.33, 0.7)
    before = path.read_bytes()

    def full_disk(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full_disk)
    with pytest.raises(OSError, match="No space"):
        write_lut_csv(path, 0.0, 1.0)
    assert path.read_bytes() == before  # not a 0-byte file
    assert [p.name for p in tmp_path.iterdir()] == ["lut.csv"]  # no temporary left behind


def test_stream_sighup_ends_quietly_all_off(tmp_path):
    proc = subprocess.Popen(
        [*CLI, "stream", "--device", "sim", "--shape", "circle:2.5,3,2", "--method", "AS"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    wait_streaming(proc)  # its handlers are in place (before, SIGHUP ends it with 129)
    proc.send_signal(signal.SIGHUP)
    out, err = proc.communicate(timeout=10)
    assert proc.returncode == 0, err
    assert "stopped: all off" in out and "Traceback" not in err


def test_an_internal_error_in_the_output_thread_is_told_and_ends_all_off(monkeypatch):
    from tactile_core.device.link import SimulatedArray
    from tactile_core.rendering.scene import Scene
    from tactile_core.stream.streamer import Streamer

    array = SimulatedArray()
    streamer = Streamer(array, scene=Scene(tc.Circle((2.5, 3), 2)))

    def broken(*args):
        raise RuntimeError("boom")

    monkeypatch.setattr(streamer, "_levels", broken)
    streamer.start()
    deadline = time.monotonic() + 20
    while streamer.running and time.monotonic() < deadline:  # the error ends the thread
        time.sleep(0.01)
    stats = streamer.stop()
    assert stats.state == "failed" and "internal error: RuntimeError: boom" in stats.status
    assert "all off" in stats.status and "RuntimeError" in streamer.failure_traceback
    assert not array.levels().any()


def test_ctrl_c_reaches_the_stream_child_without_a_traceback(capfd):
    from tactile_core.rendering.scene import Scene
    from tactile_core.stream.process import StreamerProcess

    stream = StreamerProcess(None, scene=Scene(tc.Circle((2.5, 3), 2))).start()
    try:
        os.kill(stream._proc.pid, signal.SIGINT)  # what Ctrl-C in the terminal sends it
        time.sleep(0.5)
        assert stream.running  # the parent decides when the child stops
    finally:
        stats = stream.stop()
    assert stats.state == "stopped" and stream._proc.returncode == 0
    assert "KeyboardInterrupt" not in capfd.readouterr().err
