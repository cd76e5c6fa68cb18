"""The tuner plays a pattern file: File -> Open pattern... and Example patterns."""

import json

import numpy as np
import pytest

from tactile_core.files.pattern import Pattern, example_patterns

from .helpers import record_sent

pytestmark = pytest.mark.usefixtures("qt_settings")


def test_the_file_menu_opens_patterns_and_lists_the_examples(window):
    menu = next(a.menu() for a in window.menuBar().actions() if a.text() == "&File")
    texts = [a.text() for a in menu.actions()]
    assert "Open pattern..." in texts and "Example patterns" in texts
    examples = next(a.menu() for a in menu.actions() if a.text() == "Example patterns")
    assert [a.text() for a in examples.actions()] == ["letter-a", "taps", "vest-sweep"]


def test_open_pattern_plays_it_as_the_scenes_source(window, qtbot):
    sent = record_sent(window)
    window.state.update(playing=False)  # the scene before it off (its line crosses actuator 17)
    qtbot.waitUntil(lambda: bool(sent) and not sent[-1].any(), timeout=10000)
    before = len(sent)
    assert window.files.open_pattern_file(example_patterns()["taps"])
    scene = window.state.scene
    assert isinstance(scene.source, Pattern) and scene.shape is None
    assert scene.source == Pattern.load(example_patterns()["taps"])
    assert "opened the pattern taps.json: 1 effect over 1 s" in window.statusBar().currentMessage()
    assert window.files.preset_name == "taps"
    assert (
        "The pattern taps: 1 effect on 1 track over 1 s."
        in window.controls.shape.other_label.text()
    )
    # the stream plays its taps: only actuator 17 lights (channel order is the palm's cells)
    qtbot.waitUntil(lambda: sum(f[17] > 0 for f in sent[before:]) >= 5, timeout=10000)
    lit = {int(i) for f in sent[before:] for i in np.flatnonzero(f)}
    assert lit == {17}
    # the curves are redrawn at most every 50 ms after a scene changes: wait for them
    shown = lambda: window.tune.shown_curves  # noqa: E731
    qtbot.waitUntil(lambda: shown() is not None and list(shown().cells) == [(2, 3)],
                    timeout=10000)  # fmt: skip


def test_a_pattern_that_does_not_fit_the_array_is_refused_by_field(window, tmp_path):
    before = window.state.scene
    assert not window.files.open_pattern_file(example_patterns()["vest-sweep"])  # palm: no groups
    assert "effects[0].group must name a group of the layout (it has none)" in window.last_error
    # and where it does play: the bundled profiles with groups front and back
    assert window.last_error.endswith(
        ". It plays on the device profile vest-front-back: choose it in the device dock's "
        "profile box (or the Array menu's Device profile), then open the pattern again"
    )
    assert window.device.profile.name == "palm-5x6"
    bad = tmp_path / "bad.json"
    data = json.loads(example_patterns()["taps"].read_text())
    data["effects"][0]["repeat"] = 0
    bad.write_text(json.dumps(data))
    assert not window.files.open_pattern_file(bad)
    assert "effects[0].repeat must be >= 1" in window.last_error
    assert window.state.scene is before


def test_the_next_start_opens_the_pattern_again(qtbot, tmp_path):
    from tactile_tuner.window import MainWindow

    path = tmp_path / "letter.json"
    path.write_bytes(example_patterns()["letter-a"].read_bytes())
    first = MainWindow(restore=False, process=False)
    qtbot.addWidget(first)
    assert first.files.open_pattern_file(path)
    first.confirm = lambda title, text: True
    first.close()
    second = MainWindow(restore=True, process=False)
    qtbot.addWidget(second)
    try:
        assert second.state.scene.source == Pattern.load(path)
        assert f"the last session's pattern again: {path}" in second.statusBar().currentMessage()
    finally:
        second.confirm = lambda title, text: True
        second.close()


def test_the_next_start_names_an_example_by_its_file_not_the_package_path(qtbot):
    # "the last session's pattern again: .../site-packages/tactile_core/_assets/patterns/..."
    from tactile_tuner.window import MainWindow

    first = MainWindow(restore=False, process=False)
    qtbot.addWidget(first)
    assert first.files.open_pattern_file(example_patterns()["taps"], example=True)
    first.confirm = lambda title, text: True
    first.close()
    second = MainWindow(restore=True, process=False)
    qtbot.addWidget(second)
    try:
        said = second.statusBar().currentMessage()
        assert "the last session's pattern again: the example taps.json" in said
        assert "_assets" not in said and "assets/" not in said
    finally:
        second.confirm = lambda title, text: True
        second.close()


def test_a_pattern_that_does_not_fit_a_new_profile_gives_way_to_its_default_shape(window, qtbot):
    # the sweep names the vest's groups: on the palm array it cannot play
    window.files.use_profile("vest-front-back")
    qtbot.waitUntil(lambda: window.device.profile.name == "vest-front-back", timeout=10000)
    assert window.files.open_pattern_file(example_patterns()["vest-sweep"])
    assert isinstance(window.state.scene.source, Pattern)
    window.files.use_profile("palm-5x6")
    qtbot.waitUntil(lambda: window.device.profile.name == "palm-5x6", timeout=10000)
    scene = window.state.scene
    assert scene.source is None and scene.shape is not None
    assert (
        "the pattern does not play on this layout (effects[0].group must name a group of "
        "the layout (it has none), got 'front')" in window.state.last_message
    )
    frames = window.device.stats.frames
    qtbot.waitUntil(lambda: window.device.stats.frames > frames + 10, timeout=10000)
    assert window.device.stats.state == "streaming"


def test_the_profiles_a_pattern_plays_on_are_those_with_its_groups():
    from tactile_core.device.profile import find_profile, profile_names
    from tactile_tuner.files import profiles_playing

    sweep = Pattern.load(example_patterns()["vest-sweep"])
    with_groups = [
        name
        for name in profile_names()
        if {"front", "back"} <= dict(find_profile(name).layout.groups).keys()
    ]
    assert profiles_playing(sweep) == with_groups == ["vest-front-back"]
    assert profiles_playing(Pattern.load(example_patterns()["letter-a"]))[0] == "palm-5x6"


def test_an_example_pattern_for_another_array_switches_to_a_profile_it_plays_on(window, qtbot):
    # On the palm array the vest sweep opened a modal error naming effects[0].group; a preset
    # switches to its own profile, and so does an example pattern, saying so.
    menu = next(a.menu() for a in window.menuBar().actions() if a.text() == "&File")
    examples = next(a.menu() for a in menu.actions() if a.text() == "Example patterns")
    next(a for a in examples.actions() if a.text() == "vest-sweep").trigger()
    assert window.last_error == ""
    assert window.device.profile.name == "vest-front-back"
    assert window.state.scene.source == Pattern.load(example_patterns()["vest-sweep"])
    said = window.statusBar().currentMessage()
    assert said.startswith("opened the pattern vest-sweep.json on the device profile "
                           "vest-front-back (it does not play on palm-5x6): 2 effects over "
                           "1.6 s")  # fmt: skip
    assert window.device_panel.profile_combo.currentText() == "vest-front-back"
    frames = window.device.stats.frames
    qtbot.waitUntil(lambda: window.device.stats.frames > frames + 10, timeout=10000)


def test_an_example_pattern_does_not_switch_while_the_profile_may_not_change(window):
    window.files.profile_blocked = lambda: "not now: the Blind A/B ratings are unsaved"
    assert not window.files.open_pattern_file(example_patterns()["vest-sweep"], example=True)
    assert window.last_error.endswith(
        "It plays on the device profile vest-front-back: not now: the Blind A/B ratings are unsaved"
    )
    assert window.device.profile.name == "palm-5x6"


def test_a_pattern_shows_its_own_duration_and_its_timing_is_not_editable(window):
    # The duration box read 1.00 s (the scene's) and stayed editable while the letter A, 2.1 s,
    # played: a pattern's effects set its timing.
    trace = window.controls.trace
    letter = Pattern.load(example_patterns()["letter-a"])
    end_s = max(e.start_s + e.duration_s * e.repeat for e in letter.effects)  # the last play
    assert window.files.open_pattern_file(example_patterns()["letter-a"])
    assert trace.duration_spin.value() == pytest.approx(end_s) == pytest.approx(2.1)
    assert trace.duration_spin.text() == "2.10 s"
    for box in (trace.duration_spin, trace.pause_spin, trace.direction_combo,
                trace.emphasis_spin):  # fmt: skip
        assert not box.isEnabled()
        assert "The pattern sets its own timing" in box.toolTip()
    assert trace.rate_spin.isEnabled()  # its frames are the scene's: rate, filter, dithering
    window.controls.shape.shape_combo.setCurrentIndex(0)  # a line again: its own trace
    assert trace.duration_spin.isEnabled() and "The pattern" not in trace.duration_spin.toolTip()
    assert trace.duration_spin.value() == window.state.scene.duration_s
