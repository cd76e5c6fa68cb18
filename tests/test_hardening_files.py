"""An operator's pass on the files the tuner and the CLI read and write (presets, .tact, the
correction table, curves): each test failed on the code before its fix."""

import errno
import os
import wave

import numpy as np
import pytest

from tactile_core.device.profile import load_profile
from tactile_core.files import export
from tactile_core.files.presets import (
    MAX_NAME_CHARS,
    Preset,
    PresetError,
    load_preset,
    preset_from_dict,
    save_preset,
)
from tactile_core.files.tact import load_pattern, parse_tact, read_tact
from tactile_core.rendering.correction import correct, quantize

from . import tact_support as ts
from .helpers import run_cli_last_line


def timed_preset(**shape_fields):
    shape = {"type": "timed_path", "points": [[1, 2], [2, 3]], "times_s": [0, 1], **shape_fields}
    return {"format": "tactile-preset", "version": 1, "method": "AS", "mu": 0.3, "gamma": 0.7,
            "shape": shape}  # fmt: skip


@pytest.mark.parametrize("value", [None, 5, True])
def test_a_time_keyed_paths_intensities_of_the_wrong_type_are_named(value):
    # "intensities": null raised TypeError (no len()) out of the tuner's slot and the CLI.
    with pytest.raises(PresetError, match=r"shape\.intensities must be a list of 2 numbers"):
        preset_from_dict(timed_preset(intensities=value))


def test_an_empty_intensities_list_still_means_full_intensity():
    preset = preset_from_dict(timed_preset(intensities=[]))
    assert preset.scene.shape.intensities == (1.0, 1.0)


def test_a_preset_that_would_not_load_back_is_not_written(tmp_path):
    # the tuner wrote such files ("saved"), and then could not open them
    path = tmp_path / "p.json"
    good = preset_from_dict(timed_preset())
    for bad in (Preset(good.scene, notes="n" * 10_001), Preset(good.scene, name="x" * 201),
                Preset(good.scene.replace(shape=None))):  # fmt: skip
        with pytest.raises(PresetError):
            save_preset(bad, path)
        assert not path.exists() and list(tmp_path.iterdir()) == []
    save_preset(Preset(good.scene, name="x" * MAX_NAME_CHARS, notes="n" * 10_000), path)
    assert load_preset(path).name == "x" * MAX_NAME_CHARS


def test_a_tact_project_name_is_cut_to_200_characters():
    data = ts.simple()
    data["project"]["name"] = "<h1>" + "n" * 100_000
    assert parse_tact(data).name == "<h1>" + "n" * 196  # (3.5 MB froze the import 22 s)


def test_a_file_name_of_up_to_255_bytes_can_be_written(tmp_path):
    # the temporary file was named .NAME.<12 hex>.tmp: 17 bytes more than the name
    for name in ("a" * 251 + ".csv", "é" * 125 + ".h"):
        path = tmp_path / name
        assert len(os.fsencode(name)) <= 255
        writer = export.write_lut_csv if name.endswith(".csv") else export.write_lut_header
        writer(path, 0.33, 0.7)
        assert path.exists() and [p.name for p in tmp_path.iterdir()] == [name]
        path.unlink()


def test_the_correction_table_is_what_the_stream_sends():
    # It held the correction alone: at mu 0.3, gamma 0.7 and master intensity 0.5 a full raw
    # byte is 0.3 + 0.7 * 0.5 = 0.65, level round(0.65 * 22) = 14 (the table said 22).
    lut = export.correction_lut(0.3, 0.7, 23, gain=0.5)
    assert lut[255] == 14 and lut[0] == 0
    raw = np.arange(256) / 255
    assert np.array_equal(lut, quantize(correct(raw, 0.3, 0.7, gain=0.5), 23))
    palm = load_profile(None)
    felt = export.correction_lut(0.3, 0.7, 23, drive_for=palm.drive_for)
    assert np.array_equal(felt, quantize(palm.drive_for(correct(raw, 0.3, 0.7)), 23))
    header = export.lut_c_header(0.3, 0.7, gain=0.5, drive_for=palm.drive_for)
    assert "Then master intensity 0.5, then the motors' inverse response" in header


def test_a_full_disk_during_a_run_exits_1_naming_the_file(tmp_path, capsys, monkeypatch):
    # docs/cli.md: an operating-system error during a run exits with 1 (it exited with 2,
    # the status of bad arguments)
    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    for out in ("f.csv", "f.npz"):
        code, line = run_cli_last_line(capsys, "render", "--shape", "circle:2.5,3,2",
                                       "--method", "AS", "--out", tmp_path / out)  # fmt: skip
        assert code == 1 and f"cannot write {tmp_path / out}: No space left on device" in line
    code, line = run_cli_last_line(capsys, "export-tact", "--shape", "line:0.5,0.5,4.5,5.5",
                                   "--out", tmp_path / "t.tact")  # fmt: skip
    assert code == 1 and "No space left on device" in line
    assert list(tmp_path.iterdir()) == []


def test_export_tact_names_a_long_file_by_its_first_200_characters(tmp_path, capsys):
    out = tmp_path / ("q" * 230 + ".tact")
    code, _ = run_cli_last_line(capsys, "export-tact", "--shape", "line:0.5,0.5,4.5,5.5",
                                "--out", out)  # fmt: skip
    assert code == 0 and read_tact(out).name == "q" * 200


# --- the tuner ---------------------------------------------------------------------------------


@pytest.fixture
def window(qtbot, qt_settings):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    yield win
    win.confirm = lambda title, text: True
    win.close()


def test_the_tuner_refuses_a_preset_of_a_pattern_it_could_not_open(window, tmp_path):
    # It said "saved" and wrote "shape": null, which no preset reader opens.
    assert window.files.import_tact_file(ts.write(tmp_path, ts.crossing_paths_and_a_dot()))
    path = tmp_path / "pattern.json"
    assert not window.files.save_preset_file(path)
    assert "a preset holds a shape, and this scene plays a .tact pattern" in window.last_error
    assert not path.exists()


def test_the_tuners_own_names_and_notes_load_back(window, tmp_path):
    long = tmp_path / ("s" * 210 + ".json")
    assert window.files.save_preset_file(long)
    assert load_preset(long).name == "s" * MAX_NAME_CHARS
    assert window.files.export_tact_file(tmp_path / ("t" * 220 + ".tact"))
    assert not window.files.save_preset_file(tmp_path / "n.json", notes="n" * 10_001)
    assert "'notes' must be a string of at most 10000 characters" in window.last_error
    assert not (tmp_path / "n.json").exists()


def test_names_from_files_are_shown_as_written_not_as_markup(window, tmp_path):
    from PySide6 import QtCore

    data = ts.crossing_paths_and_a_dot()
    data["project"]["name"] = '<h1 style="color:red">HUGE</h1>'
    assert window.files.import_tact_file(ts.write(tmp_path, data))
    label = window.controls.shape.other_label
    assert label.textFormat() == QtCore.Qt.TextFormat.PlainText
    assert '<h1 style="color:red">HUGE</h1>' in label.text()
    preset = window.controls.preset.name_label
    assert preset.textFormat() == QtCore.Qt.TextFormat.PlainText
    from tactile_tuner.texts import tip

    assert tip("<b>a & b</b>") == "<qt>&lt;b&gt;a &amp; b&lt;/b&gt;</qt>"
    # the device's name stays bold (rich text, its name escaped): not "<b>simulated array</b>"
    link = window.device_panel.link_label
    assert link.text() == "<b>simulated array</b>"
    assert link.textFormat() == QtCore.Qt.TextFormat.RichText


def test_a_pattern_of_many_long_paths_is_not_outlined(tmp_path):
    from tactile_tuner.tune.widget import MAX_OUTLINE_POINTS, pattern_outlines

    points = [ts.point(i / 999, (i % 2) * 0.5, 1.0, i) for i in range(1000)]
    effects = [ts.effect({"VestFront": ts.path_mode(points)}) for _ in range(21)]
    pattern = load_pattern(ts.write(tmp_path, ts.document(*effects)))
    target = load_profile(None).layout
    assert sum(len(p.points) for p in pattern.paths(target)) > MAX_OUTLINE_POINTS
    assert pattern_outlines(pattern, target) is None
    few = load_pattern(ts.write(tmp_path, ts.document(*effects[:2]), "few.tact"))
    assert len(pattern_outlines(few, target)) == 2


def test_a_timed_path_renders_at_its_own_pace_unless_told(tmp_path, capsys):
    # A 0.5 s path was stretched to --duration's default 2 s by render and stream, though
    # export-tact kept its times and the docs say it plays at its own pace.
    out = tmp_path / "t.csv"
    spec = "timed:1,1,0,1,4,5,0.5,1"  # (1, 1) at 0 s to (4, 5) at 0.5 s
    code, _ = run_cli_last_line(capsys, "render", "--shape", spec, "--method", "AS",
                                "--rate", "10", "--out", out)  # fmt: skip
    assert code == 0 and len(out.read_text().splitlines()) == 1 + 6  # 0, 0.1 .. 0.5 s
    code, _ = run_cli_last_line(capsys, "render", "--shape", spec, "--method", "AS",
                                "--rate", "10", "--duration", "1", "--out", out)  # fmt: skip
    assert code == 0 and len(out.read_text().splitlines()) == 1 + 11  # told: 1 s


def test_render_caps_the_values_it_writes_not_only_the_frames(tmp_path, capsys):
    # 48,001 frames of a 64 x 64 grid (197 million values) passed the frame cap and ended in
    # a MemoryError traceback under a 3 GB limit; 30 million values (240 MB) is the cap.
    code, line = run_cli_last_line(capsys, "render", "--shape", "line:0,0,64,64", "--method",
                                   "AS", "--cols", "64", "--rows", "64", "--rate", "1000",
                                   "--duration", "48", "--out", tmp_path / "big.npz")  # fmt: skip
    assert code == 2 and "at most 7324 frames of 4096 tactors, got 48001" in line
    assert list(tmp_path.iterdir()) == []


def test_render_writes_a_patterns_carriers_to_wav(tmp_path, capsys):
    out = tmp_path / "t.wav"
    shape = "tact:tests/data/testfeedback.tact"
    code, _ = run_cli_last_line(capsys, "render", "--shape", shape, "--method", "BA",
                                "--profile", "vest-4x5", "--out", out)  # fmt: skip
    assert code == 0
    with wave.open(str(out)) as f:  # 100 frames at 100 Hz: 1 s and the ramp
        assert f.getnchannels() == 20 and 1.0 <= f.getnframes() / f.getframerate() < 1.05


def test_a_preset_saved_with_a_byte_order_mark_opens(tmp_path):
    # Windows' Notepad writes one; .tact files were read past it, presets were refused.
    good = preset_from_dict(timed_preset())
    path = save_preset(good, tmp_path / "p.json")
    path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    assert load_preset(path).scene.shape == good.scene.shape


@pytest.mark.parametrize("version", [1.0, 1])
def test_a_preset_version_written_as_a_whole_float_is_read(version):
    # some JSON writers store 1 as 1.0; it was refused although every other whole number reads
    data = {**timed_preset(), "version": version}
    assert preset_from_dict(data).scene.method == "AS"


@pytest.mark.parametrize(
    ("version", "message"),
    [(1.5, "must be an integer"), (0, "must be >= 1"), (True, "must be an integer"),
     ("1", "must be an integer"), (None, "must be an integer"), (2, "newer than")],
)  # fmt: skip
def test_a_bad_preset_version_names_the_field(version, message):
    with pytest.raises(PresetError, match=rf"field 'version'.*{message}"):
        preset_from_dict({**timed_preset(), "version": version})
