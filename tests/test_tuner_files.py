"""The files the tuner opens and saves: dialogs that keep a typed extension, name files after the
tuning and remember a folder per kind; presets whose names and notes load back (and none for a
.tact pattern, which a preset cannot hold); names read from files shown as written, never as
markup; exported curves named as the window names the tactors."""

import csv

from PySide6 import QtCore

import tactile_core as tc
from tactile_core.device.profile import load_profile
from tactile_core.files.presets import MAX_NAME_CHARS, builtin_presets, load_preset
from tactile_core.files.tact import load_pattern

from . import tact_support as ts


def test_dialog_names_and_extensions():
    from tactile_core.rendering.scene import Scene
    from tactile_tuner import dialogs

    assert dialogs.with_filter_extension("/tmp/curves", "PNG (*.png)").name == "curves.png"
    assert dialogs.with_filter_extension("/tmp/a.csv", "CSV (*.csv)").name == "a.csv"
    assert dialogs.tuning_tag(Scene(tc.Circle((2, 3), 1), "IM", 0.33, 0.7)) == (
        "IM-mu0.33-gamma0.70"
    )
    assert dialogs.safe_name("P 01/x") == "P-01-x"


def test_a_typed_extension_of_any_filter_is_kept():
    from tactile_tuner.dialogs import with_filter_extension

    filters = ["CSV (*.csv)", "PNG (*.png)", "SVG (*.svg)"]
    assert with_filter_extension("/a/curves.png", "CSV (*.csv)", filters).name == "curves.png"
    assert with_filter_extension("/a/curves", "CSV (*.csv)", filters).name == "curves.csv"
    assert with_filter_extension("/a/v1.2", "PNG (*.png)", filters).name == "v1.2.png"


def test_dialogs_remember_their_folder_per_kind(tmp_path, qt_settings):
    from tactile_tuner import dialogs

    (tmp_path / "exports").mkdir()
    dialogs._remember("exports", tmp_path / "exports" / "x.csv")
    assert dialogs._folder("exports") == str(tmp_path / "exports")
    assert dialogs._folder("presets") != str(tmp_path / "exports")


def test_exported_curves_name_tactors_as_the_gui_does(window, tmp_path):
    assert window.files.export_curves(tmp_path / "c.csv")
    with open(tmp_path / "c.csv", newline="") as f:
        header = next(csv.reader(f))
    cells = window.tune.shown_curves.cells
    assert header[1:3] == [f"({cells[0][0]},{cells[0][1]}) raw",
                           f"({cells[0][0]},{cells[0][1]}) corrected"]  # fmt: skip
    assert f"({cells[0][0]},{cells[0][1]})" == window.tune.curves._solid[cells[0]].toolTip()


def test_preset_notes_are_shown_and_editable(window, qtbot, tmp_path):
    path = builtin_presets()["exp2-L1"]
    assert window.files.load_preset_file(path)
    notes = window.controls.preset.notes_edit
    assert notes.toPlainText() == load_preset(path).notes and notes.isVisible()
    notes.setPlainText("lines 1 mm lower on this array")
    assert window.files.save_preset_file(tmp_path / "mine.json")
    assert load_preset(tmp_path / "mine.json").notes == "lines 1 mm lower on this array"


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
    # drawn outlines cost the display thread seconds (4,000 paths: 4.5 s); past the cap, none
    from tactile_tuner.tune.widget import MAX_OUTLINE_POINTS, pattern_outlines

    points = [ts.point(i / 999, (i % 2) * 0.5, 1.0, i) for i in range(1000)]
    effects = [ts.effect({"VestFront": ts.path_mode(points)}) for _ in range(21)]
    pattern = load_pattern(ts.write(tmp_path, ts.document(*effects)))
    target = load_profile(None).layout
    assert sum(len(p.points) for p in pattern.paths(target)) > MAX_OUTLINE_POINTS
    assert pattern_outlines(pattern, target) is None
    few = load_pattern(ts.write(tmp_path, ts.document(*effects[:2]), "few.tact"))
    assert len(pattern_outlines(few, target)) == 2
