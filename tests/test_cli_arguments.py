"""The command line's arguments: a value it cannot use (out of bounds, not a plain decimal, an
empty or unwritable path, options that contradict the profile) is refused before any work with
one line naming the argument and exit status 2, never a traceback, and nothing is written."""

import subprocess
import sys

import pytest

from .helpers import run_cli_here, run_cli_last_line

CLI = [sys.executable, "-m", "tactile_core.cli"]
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
def test_huge_finite_coordinates_are_refused_naming_the_field(capsys, tmp_path, shape, field):
    code, err = run_cli(capsys, "render", "--shape", shape, "--method", "AS", "--out",
                        str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and field in err and "within" in err


def test_stream_refuses_a_shape_reaching_past_the_bound_before_it_starts(capsys):
    # every coordinate within bounds, the square's edge taking it past: it was streamed, and
    # the output thread failed ("internal error", exit 70)
    code, err = run_cli(capsys, "stream", "--device", "sim", "--shape", "square:2.5,999999,10",
                        "--method", "AS", "--seconds", "0.2")  # fmt: skip
    assert code == 2 and "takes the square to 1000004" in err


@pytest.mark.parametrize(
    ("option", "value", "word"),
    [
        ("--duration", "1e308", "duration"),
        ("--rate", "1e9", "rate"),
        ("--duration", "nan", "duration"),
    ],
)
def test_render_numbers_beyond_their_bounds_write_nothing(capsys, tmp_path, option, value, word):
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "AS",
                        option, value, "--out", str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and err.startswith(f"tactile render: error: {word}")
    assert not (tmp_path / "f.csv").exists()


def test_render_frame_count_is_bounded(capsys, tmp_path):
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "AS",
                        "--duration", "3600", "--rate", "100000", "--out",
                        str(tmp_path / "f.npz"))  # fmt: skip
    assert code == 2 and "at most 1000000 frames" in err


def test_render_caps_the_values_it_writes_not_only_the_frames(tmp_path, capsys):
    # 48,001 frames of a 64 x 64 grid (197 million values) passed the frame cap and ended in
    # a MemoryError traceback under a 3 GB limit; 30 million values (240 MB) is the cap.
    code, line = run_cli(capsys, "render", "--shape", "line:0,0,64,64", "--method", "AS",
                         "--cols", "64", "--rows", "64", "--rate", "1000", "--duration", "48",
                         "--out", tmp_path / "big.npz")  # fmt: skip
    assert code == 2 and "at most 7324 frames of 4096 tactors, got 48001" in line
    assert list(tmp_path.iterdir()) == []


def test_render_refuses_cols_and_rows_with_a_layout(tmp_path, capsys):
    code, line = run_cli(capsys, "render", "--profile", "belt-8", "--cols", "8", "--shape",
                         "line:0,0,7,0", "--method", "BA", "--out", tmp_path / "x.csv")  # fmt: skip
    assert code == 2 and "--cols" in line and "belt-8" in line and "layout" in line


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
        ["stream", "--device", "sim", "--shape", "circle:2.5,3,2", "--method", "AS", "--seconds",
         "30", "--record", "/proc/nope/r.csv"],
        ["emulate", "--seconds", "30", "--log", "/proc/nope/log.csv"],
        ["emulate", "--seconds", "30", "--json", "/nonexistent-folder/r.json"],
    ],
)  # fmt: skip
def test_unwritable_outputs_are_refused_before_the_work(capsys, argv):
    code, out, err = run_cli_here(capsys, *argv)
    assert code == 2 and "does not exist" in err
    # Refused up front: a stream that ran prints its counters on standard output, an emulator
    # its port, and neither said "[streaming]" (these ran their 30 s, then failed to write).
    assert out == "" and "[streaming]" not in err


def test_simulate_into_a_file_is_refused_and_into_a_missing_folder_creates_it(capsys, tmp_path):
    target = tmp_path / "a-file"
    target.write_text("x")
    code, err = run_cli(capsys, "simulate", str(target), "--participants", "1",
                        "--experiments", "exp3")  # fmt: skip
    assert code == 2 and "is a file, not a folder" in err
    code, _ = run_cli(capsys, "simulate", str(tmp_path / "new" / "results"), "--participants",
                      "1", "--experiments", "exp3")  # fmt: skip
    assert code == 0 and (tmp_path / "new" / "results" / "participant-sim01").is_dir()


@pytest.mark.parametrize("value", ["1_0", "\uff11", " 0.5", "0.5 ", "0x1", "1,5", "\u0661"])
def test_cli_numbers_are_ascii_decimals(capsys, tmp_path, value):
    # Python's float() and int() take underscores, full-width and Arabic-Indic digits and
    # spaces: the CLI took them, and a number a person cannot read back was used
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "AS",
                        "--mu", value, "--out", str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and "argument --mu: must be a decimal number" in err
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "AS",
                        "--rows", value, "--out", str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and "argument --rows: must be a whole number" in err
    assert not (tmp_path / "f.csv").exists()


@pytest.mark.parametrize(
    "argv",
    [["stream", "--device", "sim", "--shape", "circle:2.5,3,2", "--method", "AS", "--seconds",
      "0.2", "--record", ""],
     ["emulate", "--seconds", "0.1", "--log", ""],
     ["emulate", "--seconds", "0.1", "--json", ""],
     ["emulate", "--seconds", "0.1", "--profile", ""],
     ["stream", "--device", "sim", "--shape", "circle:2.5,3,2", "--method", "AS", "--seconds",
      "0.2", "--profile", ""],
     ["analyze", ""]],
)  # fmt: skip
def test_empty_output_paths_are_refused_not_ignored(capsys, argv):
    code, err = run_cli(capsys, *argv)
    assert code == 2 and "got ''" in err


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
