"""The tuner's .tact pieces: File -> Import .tact..., Export .tact..., and a drawing kept as the
scene's shape."""

import numpy as np
import pytest

from tactile_core.files.tact import load_pattern, read_tact
from tactile_core.rendering.shapes import TimedPath

from . import tact_support as ts

pytestmark = pytest.mark.usefixtures("qt_settings")


def test_the_file_menu_offers_the_tact_actions(window):
    menu = next(a.menu() for a in window.menuBar().actions() if a.text() == "&File")
    texts = [a.text() for a in menu.actions()]
    for text in ("Import .tact...", "Export .tact...", "Keep the drawing as the shape"):
        assert text in texts


def test_a_one_path_file_becomes_the_scenes_shape_and_exports_back(window, tmp_path):
    points = [ts.point(0, 1, 0.5, 0), ts.point(1, 0, 1.0, 800)]
    data = ts.document(ts.effect({"VestFront": ts.path_mode(points)}, start_ms=300))
    assert window.files.import_tact_file(ts.write(tmp_path, data, "sweep.tact"))
    scene = window.state.scene
    assert isinstance(scene.shape, TimedPath) and scene.source is None
    assert scene.shape.points == ((0.5, 0.5), (4.5, 5.5)) and scene.shape.times_s == (0.0, 0.8)
    assert scene.duration_s == pytest.approx(0.8) and window.files.preset_name == "sweep"
    assert window.files.export_tact_file(tmp_path / "back.tact")
    (back,) = load_pattern(tmp_path / "back.tact").paths(window.device.profile.layout)
    assert back.points == ((0.5, 0.5), (4.5, 5.5)) and back.times_s == (0.0, 0.8)


def test_paths_and_dots_play_as_the_scenes_pattern(window, qtbot, tmp_path):
    assert window.files.import_tact_file(ts.write(tmp_path, ts.simple()))
    scene = window.state.scene
    assert scene.shape is None and scene.source is not None
    assert "1 path and 1 dot play as a pattern" in window.statusBar().currentMessage()
    frames = window.device.stats.frames
    qtbot.waitUntil(lambda: window.device.stats.frames > frames + 10, timeout=10000)
    assert window.device.stats.state == "streaming"
    assert not window.files.export_tact_file(tmp_path / "x.tact")  # no shape to export
    assert "no shape to export" in window.last_error


def test_a_bad_file_changes_nothing_and_says_why(window, tmp_path):
    before = window.state.scene
    bad = ts.mutate(ts.simple(), ["project", "tracks", 0, "effects", 0, "startTime"], -3)
    assert not window.files.import_tact_file(ts.write(tmp_path, bad))
    assert window.state.scene is before
    assert "tracks[0].effects[0].startTime must be within" in window.last_error


def test_a_drawing_is_kept_as_a_time_keyed_path(window, qtbot, tmp_path, monkeypatch):
    import types

    import tactile_tuner.drawing

    assert not window.files.keep_drawing()
    assert "draw a path first" in window.last_error
    window.controls.playback.draw_check.setChecked(True)
    heatmap = window.tune.heatmap
    drawn_at = iter([100.0, 100.1, 100.25, 100.3])  # the clock the drawing is timed on
    fake_time = types.SimpleNamespace(perf_counter=lambda: next(drawn_at))
    monkeypatch.setattr(tactile_tuner.drawing, "time", fake_time)
    for x in (0.5, 1.5, 2.5, 3.5):
        heatmap.point_drawn.emit(x, 2.5)
    monkeypatch.undo()
    heatmap.draw_released.emit()
    assert window.files.keep_drawing()
    assert not heatmap.drawing
    shape = window.state.scene.shape
    assert isinstance(shape, TimedPath) and shape.pattern == "CONST_TDM"
    assert shape.points == ((0.5, 2.5), (1.5, 2.5), (2.5, 2.5), (3.5, 2.5))
    assert shape.times_s == pytest.approx((0.0, 0.1, 0.25, 0.3))  # at the pace it was drawn
    assert window.state.scene.duration_s == shape.duration_s
    assert window.files.save_preset_file(tmp_path / "drawn.json")
    assert window.files.export_tact_file(tmp_path / "drawn.tact")
    assert len(read_tact(tmp_path / "drawn.tact").paths[0].points) == 4


def test_a_pattern_is_drawn_plotted_and_named_and_a_shape_replaces_it(window, tmp_path):
    # The views used to keep the previous shape's outline, curves and fields while a pattern
    # played. Paths as in tact_support.crossing_paths_and_a_dot: (0.5, 0.5) -> (4.5, 5.5) and
    # (0.5, 5.5) -> (4.5, 0.5); the dot lights tactor (3, 4) from 0.3 to 0.5 s.
    assert window.files.import_tact_file(ts.write(tmp_path, ts.crossing_paths_and_a_dot()))
    assert "2 paths and 1 dot play as a pattern" in window.statusBar().currentMessage()
    tune = window.tune
    tune.refresh()
    x, y = tune.heatmap.outline.getData()
    gap = int(np.flatnonzero(np.isnan(x))[0])  # one gap: two outlines, not joined
    assert np.isnan(x).sum() == 1
    assert (x[0], y[0], x[gap - 1], y[gap - 1]) == pytest.approx((0.5, 0.5, 4.5, 5.5))
    assert (x[gap + 1], y[gap + 1], x[-1], y[-1]) == pytest.approx((0.5, 5.5, 4.5, 0.5))
    curves = tune.shown_curves
    k = curves.cells.index((3, 4))
    on = (curves.time_s > 0.301) & (curves.time_s < 0.499)
    assert curves.raw[on, k] == pytest.approx(np.full(on.sum(), 0.8))
    shape_box = window.controls.shape
    assert shape_box.shape_combo.currentText() == "Other"
    assert "2 paths and 1 dot over 1 s" in shape_box.other_label.text()
    assert window.files.export_curves(tmp_path / "pattern.csv")  # the pattern's curves
    assert "(3,4) raw" in (tmp_path / "pattern.csv").read_text().splitlines()[0]
    compare = window.compare
    compare._refresh()
    for heatmap in compare.heatmaps.values():  # no shape's outline left over
        x, _ = heatmap.outline.getData()
        assert x is None or len(x) == 0
        assert heatmap.caption.text == "a .tact pattern plays: Compare needs a shape"
    shape_box.shape_combo.setCurrentIndex(1)  # Circle: it replaces the pattern
    scene = window.state.scene
    assert type(scene.shape).__name__ == "Circle" and scene.source is None
    tune.refresh()
    assert not np.isnan(tune.heatmap.outline.getData()[0]).any()
    assert shape_box.shape_combo.currentText() == "Circle"


def test_curves_export_without_curves_on_show_says_why(window, tmp_path):
    # The predicted view and a pattern in it show no activation curves; exporting them used to
    # fail inside the CSV writer on None.
    assert window.files.import_tact_file(ts.write(tmp_path, ts.crossing_paths_and_a_dot()))
    window.state.set_view_mode("predicted")
    window.tune.refresh()
    assert window.tune.shown_curves is None
    assert "needs a shape" in window.tune.curves.plotItem.titleLabel.text
    assert not window.files.export_curves(tmp_path / "none.csv")
    assert "no activation curves on show" in window.last_error
    assert not (tmp_path / "none.csv").exists()


def test_dots_only_tact_import_draws_no_outline(window, tmp_path):
    # A file of dots alone (bHaptics' HeartBeat_Vest.tact is one) raised "ValueError: need at
    # least one array to concatenate" in the heatmap's outline, and the line's outline stayed.
    tune = window.tune
    tune.refresh()
    assert len(tune.heatmap.outline.getData()[0]) > 0  # the line's
    assert window.files.import_tact_file(ts.write(tmp_path, ts.dots_only(), "beat.tact"))
    assert "0 paths and 3 dots play as a pattern" in window.statusBar().currentMessage()
    tune.refresh()
    x, _ = tune.heatmap.outline.getData()
    assert x is None or len(x) == 0
    # The dots are plotted: motors 1 and 2 of the vest's top row are tactors (1, 5) and (3, 5)
    # of the palm array (0..1 across its 5 x 6 cells), motor 5 of the second row (1, 4).
    curves = tune.shown_curves
    assert set(curves.cells) == {(1, 5), (3, 5), (1, 4)}
    k = curves.cells.index((1, 4))
    on = (curves.time_s > 0.301) & (curves.time_s < 0.399)
    assert curves.raw[on, k] == pytest.approx(np.full(on.sum(), 0.5))


def test_export_tact_proposes_a_new_name_and_never_overwrites_the_imported_file(
    window, tmp_path, monkeypatch
):
    # Export .tact offered the imported file's own name, in its folder: one click replaced the
    # Designer's file (every other position, path and dot in it) with the tuner's one path.
    from PySide6 import QtCore

    from tactile_tuner import dialogs

    points = [ts.point(0, 1, 0.5, 0), ts.point(1, 0, 1.0, 800)]
    source = ts.write(tmp_path, ts.document(ts.effect({"VestFront": ts.path_mode(points)})),
                      "sweep.tact")  # fmt: skip
    before = source.read_bytes()
    QtCore.QSettings().setValue("folders/tact", str(tmp_path))
    assert window.files.import_tact_file(source)
    proposed = []
    monkeypatch.setattr(dialogs, "save_path", lambda parent, kind, title, name, filters, **_:
                        proposed.append((kind, name)))  # fmt: skip
    window.files.ask_export_tact()
    (tmp_path / "sweep-export.tact").write_text("{}")
    window.files.ask_export_tact()
    assert proposed == [("tact", "sweep-export.tact"), ("tact", "sweep-export-2.tact")]
    assert not window.files.export_tact_file(source)
    assert "it is the .tact file this session imported" in window.last_error
    assert source.read_bytes() == before
    assert window.files.export_tact_file(tmp_path / "sweep-export-2.tact")


def test_keeping_the_drawing_is_offered_only_in_draw_mode_with_a_drawing(window, tmp_path):
    # It was enabled outside draw mode, and after a drawing, a .tact import and a built-in
    # preset it replaced the preset's scene with the old drawing.
    from tactile_core.files.presets import builtin_presets

    menu = next(a.menu() for a in window.menuBar().actions() if a.text() == "&File")
    keep = next(a for a in menu.actions() if a.text() == "Keep the drawing as the shape")
    assert not keep.isEnabled()  # no draw mode
    window.controls.playback.draw_check.setChecked(True)
    assert not keep.isEnabled()  # draw mode, nothing drawn yet
    heatmap = window.tune.heatmap
    for x in (0.5, 1.5, 2.5):
        heatmap.point_drawn.emit(x, 2.5)
    heatmap.draw_released.emit()
    assert keep.isEnabled()
    points = [ts.point(0, 1, 0.5, 0), ts.point(1, 0, 1.0, 800)]
    data = ts.document(ts.effect({"VestFront": ts.path_mode(points)}))
    assert window.files.import_tact_file(ts.write(tmp_path, data, "sweep.tact"))
    assert not heatmap.drawing and not keep.isEnabled()  # the import left draw mode
    window.files.load_preset_file(builtin_presets()["exp3-circle"])
    preset = window.state.scene
    assert not keep.isEnabled()
    assert not window.files.keep_drawing()  # (from a script: refused, saying why)
    assert window.state.scene == preset and "draw a path first" in window.last_error
    window.controls.playback.draw_check.setChecked(True)  # a new draw mode: a new drawing
    assert not keep.isEnabled()


def test_bhaptics_options_change_the_playing_pattern_and_are_remembered(window, tmp_path):
    """bHaptics' ScaleOption and RotationOption had no control in the tuner."""
    assert window.files.import_tact_file(ts.write(tmp_path, ts.simple()))
    box = window.controls.shape
    assert box.tact_options.isVisibleTo(box)
    fields = box.tact_fields
    assert [f.value() for f in fields.values()] == [1.0, 1.0, 0.0, 0.0]
    fields["duration"].setValue(2.0)
    fields["angle"].setValue(180.0)
    source = window.state.scene.source
    assert (source.scale.duration, source.rotation.angle_deg) == (2.0, 180.0)
    assert "over 2 s" in box.other_label.text()  # the file's 1 s, twice as slow
    assert window.files.pattern_file(source)["rotation"] == [180.0, 0.0]
    assert window.files.pattern_file(source)["scale"] == [1.0, 2.0]
    box.shape_combo.setCurrentIndex(1)  # a shape: no options to show
    assert not box.tact_options.isVisibleTo(box)


def _choose_in_save_dialog(monkeypatch, path):
    """The save dialog answers ``path``; returns what it was asked with (its options)."""
    from PySide6 import QtWidgets

    asked = {}

    def chosen(parent, title, start, filters, selected="", options=None):
        asked["options"] = options
        return str(path), "bHaptics (*.tact)"

    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName", chosen)
    return asked


def test_export_onto_the_imported_file_is_refused_before_anything_is_asked(
    window, tmp_path, monkeypatch
):
    # Qt asked "already exists. Do you want to replace it?" and after Yes the export refused.
    from PySide6 import QtWidgets

    imported = ts.write(tmp_path, ts.simple(), "heart.tact")
    before = imported.read_bytes()
    assert window.files.import_tact_file(imported)
    asked = _choose_in_save_dialog(monkeypatch, imported)
    questions = []
    window.files.confirm = lambda title, text: questions.append(text) or True
    window.files.ask_export_tact()
    assert asked["options"] & QtWidgets.QFileDialog.Option.DontConfirmOverwrite
    assert questions == []
    assert "it is the .tact file this session imported" in window.last_error
    assert imported.read_bytes() == before


@pytest.mark.parametrize("replace", [False, True])
def test_export_onto_another_file_asks_before_replacing_it(window, tmp_path, monkeypatch,
                                                           replace):  # fmt: skip
    other = tmp_path / "other.tact"
    other.write_text("not yet a .tact file")
    _choose_in_save_dialog(monkeypatch, other)
    questions = []
    window.files.confirm = lambda title, text: questions.append(text) or replace
    window.files.ask_export_tact()
    assert questions == [f"{other}\nalready exists.\n\nReplace it?"]
    assert (other.read_text() == "not yet a .tact file") != replace
    if replace:
        assert read_tact(other)  # the scene's trace, written whole


def test_export_to_a_new_file_asks_nothing(window, tmp_path, monkeypatch):
    new = tmp_path / "new.tact"
    _choose_in_save_dialog(monkeypatch, new)
    window.files.confirm = lambda title, text: pytest.fail(f"asked {text!r}")
    window.files.ask_export_tact()
    assert read_tact(new)


def test_a_tact_pattern_shows_its_own_duration_with_bhaptics_scale(window, tmp_path):
    trace = window.controls.trace
    assert window.files.import_tact_file(ts.write(tmp_path, ts.simple()))  # a path over 1 s
    assert trace.duration_spin.text() == "1.00 s" and not trace.duration_spin.isEnabled()
    window.controls.shape.tact_fields["duration"].setValue(2.0)  # twice as slow
    assert trace.duration_spin.text() == "2.00 s" and not trace.duration_spin.isEnabled()


def test_a_front_then_back_file_is_plotted_over_both_positions(window, qtbot, tmp_path):
    # The vest sweep exported with VestFront (0-0.8 s) and VestBack (0.8-1.6 s), imported on
    # vest-front-back: the curves ended at 0.8 s (the front's own duration) and the back's
    # lanes were flat, though the stream played both.
    from tactile_core.device.profile import find_profile
    from tactile_core.files.pattern import Pattern, example_patterns

    from .tuner_support import WAIT_MS

    vest = find_profile("vest-front-back")
    sweep = Pattern.load(example_patterns()["vest-sweep"])
    out = sweep.save_tact(tmp_path / "sweep.tact", vest.layout,
                          positions={"front": "VestFront", "back": "VestBack"})  # fmt: skip
    combo = window.device_panel.profile_combo
    combo.setCurrentIndex(combo.findData("vest-front-back"))
    combo.activated.emit(combo.currentIndex())
    assert window.files.import_tact_file(out)
    curves = window.tune.curves
    qtbot.waitUntil(lambda: curves.curves is not None and curves.curves.raw.shape[1] == 8,
                    timeout=WAIT_MS)  # fmt: skip
    assert curves.curves.time_s[-1] == pytest.approx(sweep.duration_s, abs=0.01)  # 1.6 s
    assert curves.plotItem.vb.viewRange()[0][1] >= sweep.duration_s
    back = [k for k, cell in enumerate(curves.curves.cells) if cell >= 20]  # the back's 20-39
    assert back and curves.curves.raw[:, back].max() > 0.5
