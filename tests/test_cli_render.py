"""``tactile render`` driven as a user would, and the rule that the core never loads Qt."""

import subprocess
import sys

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.cli import main


def run_cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "tactile_core.cli", *args],
        capture_output=True,
        text=True,
        timeout=60,
    )


def test_render_csv_matches_the_api(tmp_path):
    out = tmp_path / "circle.csv"
    proc = run_cli(
        "render",
        "--shape",
        "circle:2.5,3,2",
        "--method",
        "IM",
        "--mu",
        "0.33",
        "--gamma",
        "0.7",
        "--rate",
        "100",
        "--duration",
        "2",
        "--out",
        str(out),
    )
    assert proc.returncode == 0, proc.stderr
    header = out.read_text().splitlines()[0].split(",")
    assert header[0] == "time" and len(header) == 31
    assert header[1] == "r0c0" and header[6] == "r1c0" and header[-1] == "r5c4"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape == (201, 31)
    np.testing.assert_allclose(data[:, 0], np.arange(201) / 100)
    expected = tc.correct(tc.render(tc.Circle((2.5, 3), 2), "IM", np.arange(201) / 200), 0.33, 0.7)
    np.testing.assert_allclose(data[:, 1:], expected.reshape(201, 30), atol=1e-9)


def test_render_npz_holds_time_and_frames(tmp_path):
    out = tmp_path / "line.npz"
    assert (
        main(
            [
                "render",
                "--shape",
                "line:0.5,1.84,4.5,4.16",
                "--method",
                "CT",
                "--rate",
                "50",
                "--duration",
                "1",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    with np.load(out) as data:
        assert sorted(data.files) == ["frames", "time"]
        assert data["frames"].shape == (51, 6, 5)
        assert (data["frames"].sum(axis=(1, 2)) == 1).all()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--shape", "circle:2.5,3", "--method", "AS"], "shape circle: needs 3 numbers"),
        (["--shape", "blob:1,2", "--method", "AS"], "shape kind"),
        (["--shape", "line:0,0,1,1", "--method", "QQ"], "method must be one of"),
        (["--shape", "line:0,0,1,1", "--method", "AS", "--mu", "1.5"], "mu must be within"),
        (["--shape", "line:0,0,1,1", "--method", "AS", "--gamma", "0"], "gamma must be > 0"),
        (["--shape", "line:0,0,1,1", "--method", "AS", "--rate", "-1"], "rate must be within"),
        (["--shape", "line:0,0,nan,1", "--method", "AS"], "coordinates must be decimal numbers"),
    ],
)
def test_render_bad_arguments_exit_2_with_a_clear_message(tmp_path, capsys, args, message):
    assert main(["render", *args, "--out", str(tmp_path / "x.csv")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("tactile render: error:") and message in err
    assert not (tmp_path / "x.csv").exists()


def test_render_unwritable_output(tmp_path, capsys):
    target = tmp_path / "missing-dir" / "x.csv"
    assert main(["render", "--shape", "line:0,0,1,1", "--method", "AS", "--out", str(target)]) == 2
    assert "missing-dir' does not exist" in capsys.readouterr().err
    assert (
        main(
            [
                "render",
                "--shape",
                "line:0,0,1,1",
                "--method",
                "AS",
                "--out",
                str(tmp_path / "x.txt"),
            ]
        )
        == 2
    )


def test_core_never_imports_qt():
    code = (
        "import sys, importlib, pkgutil, tactile_core;"
        "[importlib.import_module(m.name) for m in"
        " pkgutil.walk_packages(tactile_core.__path__, 'tactile_core.')"
        " if not m.name.startswith('tactile_core._assets')];"
        "import tactile_core.files.export as e;"
        "e.correction_lut(0.33, 0.7);"
        "qt = ('PySide6', 'pyqtgraph', 'PyQt5', 'PyQt6');"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] in qt);"
        "print(','.join(bad))"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "", f"tactile_core loaded Qt: {proc.stdout}"


def test_render_of_a_shape_off_the_array_warns_that_no_tactor_is_ever_lit(tmp_path, capsys):
    """circle:9,9,2 spans x and y 7 to 11; the palm array spans x 0 to 5, y 0 to 6 (before:
    201 all-zero frames written and exit 0 without a word). The file is still written."""
    out = tmp_path / "off.csv"
    assert main(["render", "--shape", "circle:9,9,2", "--method", "AS", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert err.startswith("tactile render: warning: circle:9,9,2 ")
    assert "x 0 to 5, y 0 to 6" in err and "x 7 to 11, y 7 to 11" in err
    assert "no tactor is ever lit" in err
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape == (201, 31) and not data[:, 1:].any()


def test_render_of_a_shape_half_on_the_array_warns_of_nothing(tmp_path, capsys):
    out = tmp_path / "half.csv"
    assert main(["render", "--shape", "circle:5,3,2", "--method", "CT", "--out", str(out)]) == 0
    assert capsys.readouterr().err == ""


def test_stream_of_a_shape_off_the_array_warns_before_it_streams(capsys):
    args = ["stream", "--device", "sim", "--shape", "line:-3,-1,-1,-3", "--method", "IM",
            "--seconds", "0.1"]  # fmt: skip
    assert main(args) == 0
    err = capsys.readouterr().err
    assert "tactile stream: warning: line:-3,-1,-1,-3 " in err
    assert "x 0 to 5, y 0 to 6" in err and "no tactor is ever lit" in err
