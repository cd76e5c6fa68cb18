"""Crafted input and small lies (issue 19, items 10, 11, 12 and part of 14): a shape checked
whole, --screenshot that says "saved" only when it saved, plug-ins checked and contained, the
umask honoured, strict command-line numbers, empty output paths refused, the correction tuning
simulated."""

import json
import os
import stat
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import tactile_core as tc
from tactile_core._shared.assets import asset_path
from tactile_core._shared.jsonfile import write_json_atomic
from tactile_core.cli import main as cli
from tactile_core.files.presets import PresetError, load_preset
from tactile_core.rendering import methods as registry
from tactile_core.rendering.shapes import parse_shape


def run_cli(capsys, *argv):
    try:
        code = cli(list(argv))
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return code, err.strip().splitlines()[-1] if err.strip() else ""


# --- item 10: a shape is checked whole ---------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "reach"),
    [("square:2.5,999999,10", "1000004"), ("square:-999998,0,6", "-1000001"),
     ("circle:0,999999.5,1", "1000000.5")],
)  # fmt: skip
def test_a_shape_reaching_past_the_bound_is_refused_when_parsed(text, reach):
    with pytest.raises(ValueError, match=rf"takes the \w+ to {reach}: every point"):
        parse_shape(text)  # before: accepted, then "internal error ... rc 70" while streaming


def test_a_shape_just_inside_the_bound_is_accepted():
    square = parse_shape("square:2.5,999995,10")  # its top edge at exactly 1e6
    assert square.f(0.25)[1] == 1e6  # (f of a scalar t raised TypeError for squares before)
    assert parse_shape("circle:-999999,0,1").f(0.5)[0] == -1e6


def test_a_preset_with_such_a_square_is_refused_by_load_preset(tmp_path):
    preset = json.loads(asset_path("presets", "exp3-square.json").read_text())
    preset["shape"] = {"type": "square", "center": [2.5, 999999], "edge": 10}
    (tmp_path / "far.json").write_text(json.dumps(preset))
    with pytest.raises(PresetError, match=r"edge 10\.0 takes the square to 1000004"):
        load_preset(tmp_path / "far.json")


def test_streaming_such_a_square_is_refused_before_it_starts(capsys):
    code, err = run_cli(capsys, "stream", "--device", "sim", "--shape", "square:2.5,999999,10",
                        "--method", "AS", "--seconds", "0.2")  # fmt: skip
    assert code == 2 and "takes the square to 1000004" in err


# --- item 11: --screenshot ---------------------------------------------------------------------


@pytest.mark.parametrize("where", ["missing/shot.png", "fifo.png", "folder.png", "shot.txt"])
def test_screenshot_refuses_a_path_it_cannot_write_before_starting(tmp_path, where):
    os.mkfifo(tmp_path / "fifo.png")
    (tmp_path / "folder.png").mkdir()
    proc = subprocess.run(
        [sys.executable, "-m", "tactile_tuner.main", "--screenshot", str(tmp_path / where)],
        capture_output=True, text=True, timeout=60,
        env={"QT_QPA_PLATFORM": "offscreen", "HOME": str(tmp_path), "PATH": "/usr/bin:/bin"},
    )  # fmt: skip
    # Before: "saved ..." and exit 0 with nothing written; the FIFO blocked for ever.
    assert proc.returncode == 2 and "--screenshot" in proc.stderr
    assert "saved" not in proc.stdout


# --- item 12: plug-ins -------------------------------------------------------------------------

PLUGIN = """
import math, sys
import numpy as np

NAME = "{name}"
TITLE = "a plug-in of the tests"
BILEVEL = False
NEEDS_SHAPE = False
PARAMS = {{"k": (1.0, 0.0, 2.0, "a parameter")}}


def MAX_TACTORS(k):
    return int(2 / k)


def sample(shape, x, y, t, tol, k=1.0):
    {sample}


def sample1(shape, x, y, t, tol, k=1.0):
    return tuple((float(c[0]), float(r[0]), float(np.broadcast_to(v, (1,))[0]))
                 for c, r, v in sample(shape, np.array([x]), np.array([y]), t, tol, k))
"""
CELL = "np.floor(x + tol), np.floor(y + tol)"
PLUGINS = {
    "twice": f"return [({CELL}, 0.75), ({CELL}, 0.75)]",  # before: 1.5 on one tactor
    "offgrid": "return [(x * 0 - 1, y * 0 - 1, 0.5), (x * 0 - 1, y * 0 - 1, 0.5)]",  # dropped
    "nan": f"return [({CELL}, x * np.nan)]",
    "halfk": f"return [({CELL}, 0.5)]",  # MAX_TACTORS divides by k: k=0 raises
    "quits": "sys.exit(3)",
    "ctrlc": "raise KeyboardInterrupt",
    "short": f"return [({CELL}, np.zeros(len(x) + 1))]",  # one value too many
}


@pytest.fixture
def plugins(tmp_path, monkeypatch):
    root = tmp_path / "site"
    root.mkdir()
    points = []
    for name, body in PLUGINS.items():
        text = PLUGIN.format(name=name.upper(), sample=body)
        (root / f"trust19_{name}.py").write_text(textwrap.dedent(text))
        points.append(f"{name} = trust19_{name}")
    (root / "trust19_exits.py").write_text("import sys\nsys.exit(1)\n")
    (root / "trust19_interrupts.py").write_text("raise KeyboardInterrupt\n")
    points += ["exits = trust19_exits", "interrupts = trust19_interrupts"]
    info = root / "trust19-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: trust19\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text("[tactile_tuner.methods]\n" + "\n".join(points) + "\n")
    monkeypatch.syspath_prepend(str(root))
    before, unavailable = dict(registry.METHODS), dict(registry.UNAVAILABLE)
    monkeypatch.setattr(registry, "_plugins_loaded", False)
    registry.load_plugins()
    yield root
    registry.METHODS.clear()
    registry.METHODS.update(before)
    registry.UNAVAILABLE.clear()
    registry.UNAVAILABLE.update(unavailable)


LINE = tc.Line((1.2, 2.7), (3.6, 2.7))


def test_sys_exit_and_ctrl_c_in_a_plugins_import_are_contained(plugins):
    assert registry.UNAVAILABLE["exits"] == "SystemExit: 1"
    assert registry.UNAVAILABLE["interrupts"].startswith("KeyboardInterrupt")
    assert {"TWICE", "HALFK", "QUITS"} <= set(registry.METHODS)


def test_a_cell_named_twice_at_one_point_is_refused(plugins):
    with pytest.raises(
        ValueError, match=r"method TWICE \(a plug-in\) named the cell \(1, 2\) twice"
    ):
        tc.render(LINE, "TWICE", np.linspace(0, 1, 5))
    with pytest.raises(ValueError, match=r"named the cell \(1, 2\) twice at one point"):
        tc.render_point(LINE, "TWICE", 0.0)


def test_cells_off_the_grid_are_dropped_as_for_every_method(plugins):
    assert not tc.render(LINE, "OFFGRID", np.linspace(0, 1, 5)).any()


@pytest.mark.parametrize(
    ("name", "error"),
    [("NAN", r"values in \[0, 1\]"), ("SHORT", "entries"), ("QUITS", "failed: SystemExit: 3"),
     ("CTRLC", "failed: KeyboardInterrupt")],
)  # fmt: skip
def test_a_plugins_bad_output_and_exits_become_its_error(plugins, name, error):
    with pytest.raises(ValueError, match=rf"method {name} \(a plug-in\) .*{error}"):
        tc.render(LINE, name, np.linspace(0, 1, 5))
    with pytest.raises(ValueError, match=rf"method {name} \(a plug-in\)"):
        tc.render_point(LINE, name, 0.5)


def test_max_tactors_that_raises_is_a_clean_error_from_render(plugins, tmp_path, capsys):
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "HALFK:k=0",
                        "--out", str(tmp_path / "f.csv"))  # fmt: skip
    # Before: a ZeroDivisionError traceback.
    assert code == 2 and "MAX_TACTORS failed at k=0: ZeroDivisionError" in err
    assert tc.get_method("HALFK:k=0.5").max_tactors == 4


# --- item 14: modes, numbers, empty paths, simulate correction ---------------------------------


def test_atomic_writes_keep_the_umasks_mode_and_the_replaced_files(tmp_path):
    old = os.umask(0o022)
    try:
        write_json_atomic(tmp_path / "new.json", {})
        (tmp_path / "kept.json").write_text("{}")
        os.chmod(tmp_path / "kept.json", 0o640)
        write_json_atomic(tmp_path / "kept.json", {"a": 1})
        os.umask(0o027)
        write_json_atomic(tmp_path / "strict.json", {})
    finally:
        os.umask(old)
    modes = {p: stat.S_IMODE(os.stat(tmp_path / p).st_mode)
             for p in ("new.json", "kept.json", "strict.json")}  # fmt: skip
    # Before: 0600 for all three (mkstemp's mode).
    assert modes == {"new.json": 0o644, "kept.json": 0o640, "strict.json": 0o640}
    assert sorted(os.listdir(tmp_path)) == ["kept.json", "new.json", "strict.json"]


def test_atomic_writes_leave_nothing_when_a_signal_lands_as_the_file_is_made(tmp_path, monkeypatch):
    # Beside stress-ng, 1 in 24 signalled renders left their .tmp file: the handler ran as
    # os.open returned, before the cleanup that removes it was in force. Here the signal is
    # made to land exactly there.
    from tactile_core._shared import outfile

    real_open = os.open

    def open_then_interrupted(*args, **kwargs):
        real_open(*args, **kwargs)  # the file exists now
        raise KeyboardInterrupt

    monkeypatch.setattr(outfile.os, "open", open_then_interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_json_atomic(tmp_path / "out.json", {"a": 1})
    monkeypatch.undo()
    assert os.listdir(tmp_path) == []


def test_atomic_writes_never_replace_what_is_not_a_regular_file(tmp_path):
    # As root, write_tact("/dev/null", ...) replaced /dev/null with a regular file (the rename
    # of the temporary file took the device's place). Every atomic writer refuses first.
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    folder = tmp_path / "folder"
    folder.mkdir()
    link = tmp_path / "link-to-pipe"
    link.symlink_to(fifo)
    for target in (fifo, folder, link):
        with pytest.raises(OSError, match="not a regular file") as caught:
            write_json_atomic(target, {"a": 1})
        assert caught.value.filename == str(target)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode) and folder.is_dir() and link.is_symlink()
    assert sorted(os.listdir(tmp_path)) == ["folder", "link-to-pipe", "pipe"]  # no temporaries


@pytest.mark.parametrize("value", ["1_0", "\uff11", " 0.5", "0.5 ", "0x1", "1,5", "\u0661"])
def test_cli_numbers_are_ascii_decimals(capsys, tmp_path, value):
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "AS",
                        "--mu", value, "--out", str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and "argument --mu: must be a decimal number" in err
    code, err = run_cli(capsys, "render", "--shape", "circle:2.5,3,2", "--method", "AS",
                        "--rows", value, "--out", str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and "argument --rows: must be a whole number" in err
    assert not (tmp_path / "f.csv").exists()


@pytest.mark.parametrize("text", ["circle:2.5,\uff13,2", "circle:2.5,3,1_0"])
def test_shape_and_method_numbers_are_ascii_decimals(text):
    with pytest.raises(ValueError, match="decimal numbers"):
        parse_shape(text)
    with pytest.raises(ValueError, match="method must be NAME"):
        tc.get_method("RO:r=1_5")


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


def test_simulate_runs_the_correction_tuning(tmp_path, capsys):
    code = cli(["simulate", str(tmp_path), "--participants", "1", "--experiments", "correction"])
    assert code == 0, capsys.readouterr().err  # before: "trial kind 'interval' is not known"
    folder = tmp_path / "participant-sim01"
    rows = (folder / "correction.csv").read_text().splitlines()
    # The default plan: 2 instruction screens, 20 trials at each of 5 tactors, 40 at each of 2
    # places, 12 at the cell corner; and the header.
    assert len(rows) == 1 + 2 + 5 * 20 + 2 * 40 + 12
    record = json.loads((folder / "correction.json").read_text())
    # The simulated participant of the contract, TH 0.25 and K 1: mu = TH, gamma = 1 / (2K).
    assert abs(record["mu"] - 0.25) < 0.05 and abs(record["gamma"] - 0.5) < 0.1
