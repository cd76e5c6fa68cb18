"""The window's title names the scene that plays: a preset's, pattern's or .tact file's name
only while the scene plays that content, what plays otherwise; a star once the scene differs
from where it came from."""

import pytest

import tactile_core as tc
from tactile_core.files.pattern import Pattern, example_patterns

pytestmark = pytest.mark.usefixtures("qt_settings")


def _named(window) -> str:
    """The title's name part: ``tactile-tuner - NAME - method, mu, gamma``."""
    return window.windowTitle().split(" - ")[1]


def test_a_profile_the_pattern_does_not_fit_plays_the_default_shape_and_the_title_says_so(
    window, qtbot
):
    # The vest sweep on vest-front-back, then the palm array: the Experiment 1 line played
    # with BA while the title still read "front to back * - BA".
    window.files.use_profile("vest-front-back")
    assert window.files.open_pattern_file(example_patterns()["vest-sweep"])
    assert window.windowTitle().startswith("tactile-tuner - front to back - BA")
    window.files.use_profile("palm-5x6")
    assert window.state.scene.source is None
    assert window.state.scene.shape == tc.Line((0.5, 1.84), (4.5, 4.16))
    assert window.windowTitle().startswith("tactile-tuner - Experiment 1 line * - BA")


def test_draw_mode_and_a_kept_drawing_are_named_for_what_they_play(window, qtbot):
    # After draw mode and File -> Keep the drawing as the shape the title kept the pattern's
    # name.
    window.files.use_profile("vest-front-back")
    assert window.files.open_pattern_file(example_patterns()["vest-sweep"])
    window.files.use_profile("palm-5x6")
    window.tune.gestures.set_draw_mode(True)
    assert _named(window) == "free point (draw mode) *"
    heatmap = window.tune.heatmap
    for x in (1.0, 2.0, 3.0):
        heatmap.point_drawn.emit(x, 2.0)
    heatmap.draw_released.emit()
    assert window.files.keep_drawing()
    assert isinstance(window.state.scene.shape, tc.TimedPath)
    assert _named(window) == "drawn path *"


def test_leaving_draw_mode_gives_the_preset_its_name_back(window):
    window.tune.gestures.set_draw_mode(True)
    assert _named(window) == "free point (draw mode) *"
    window.tune.gestures.set_draw_mode(False)
    assert _named(window) == "Experiment 1 line"


def test_a_presets_shape_edited_keeps_its_name_and_another_kind_is_named_by_it(window):
    window.state.update(shape=tc.Line((0.5, 1.0), (4.5, 5.0)))  # the line's ends moved
    assert _named(window) == "Experiment 1 line *"
    window.state.update(shape=tc.Circle((2.5, 3.5), 2.05))  # the Experiment 3 preset's circle
    assert _named(window) == "Experiment 3 circle *"
    window.state.update(shape=tc.Circle((2.0, 3.0), 1.5))
    assert _named(window) == "circle *"


def test_a_pattern_is_named_by_its_file_while_it_plays_and_by_its_own_name_after():
    from tactile_core.rendering.scene import Scene
    from tactile_tuner.titles import scene_name

    taps = Pattern.load(example_patterns()["taps"])
    letter = Pattern.load(example_patterns()["letter-a"])
    came_from = Scene(source=taps)
    assert scene_name(Scene(source=taps, mu=0.5), came_from, "my taps") == "my taps"
    assert scene_name(Scene(source=letter), came_from, "my taps") == letter.name
    assert scene_name(Scene(shape=None), came_from, "my taps") == "nothing"


def test_a_tact_pattern_with_other_bhaptics_options_keeps_its_files_name(window, tmp_path):
    from . import tact_support as ts

    assert window.files.import_tact_file(ts.write(tmp_path, ts.simple(), "crossing.tact"))
    assert _named(window) == "crossing"
    window.controls.shape.tact_fields["duration"].setValue(2.0)  # the same file, slower
    assert _named(window) == "crossing *"
