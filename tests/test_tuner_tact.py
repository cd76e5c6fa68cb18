"""The tuner's .tact pieces: File -> Import .tact..., Export .tact..., and a drawing kept as the
scene's shape."""

import pytest

from tactile_core.files.tact import load_pattern, read_tact
from tactile_core.rendering.shapes import TimedPath

from . import tact_support as ts

pytestmark = pytest.mark.usefixtures("qt_settings")


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=10000)
    yield win
    win.confirm = lambda title, text: True
    win.close()


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
    (back,) = load_pattern(tmp_path / "back.tact").paths(window.device.profile.target)
    assert back.points == ((0.5, 0.5), (4.5, 5.5)) and back.times_s == (0.0, 0.8)


def test_paths_and_dots_play_as_the_scenes_pattern(window, qtbot, tmp_path):
    assert window.files.import_tact_file(ts.write(tmp_path, ts.simple()))
    scene = window.state.scene
    assert scene.shape is None and scene.source is not None
    assert "1 paths and 1 dots play as a pattern" in window.statusBar().currentMessage()
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


def test_a_drawing_is_kept_as_a_time_keyed_path(window, qtbot, tmp_path):
    assert not window.files.keep_drawing()
    assert "draw a path first" in window.last_error
    window.controls.playback.draw_check.setChecked(True)
    heatmap = window.tune.heatmap
    for x in (0.5, 1.5, 2.5, 3.5):
        heatmap.point_drawn.emit(x, 2.5)
        qtbot.wait(20)
    heatmap.draw_released.emit()
    assert window.files.keep_drawing()
    assert not heatmap.drawing
    shape = window.state.scene.shape
    assert isinstance(shape, TimedPath) and shape.pattern == "CONST_TDM"
    assert shape.points == ((0.5, 2.5), (1.5, 2.5), (2.5, 2.5), (3.5, 2.5))
    assert 0.05 < shape.duration_s < 5.0 and window.state.scene.duration_s == shape.duration_s
    assert window.files.save_preset_file(tmp_path / "drawn.json")
    assert window.files.export_tact_file(tmp_path / "drawn.tact")
    assert len(read_tact(tmp_path / "drawn.tact").paths[0].points) == 4
