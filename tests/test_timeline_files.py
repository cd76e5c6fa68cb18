"""The pattern editor's files: save and open give back the same pattern, a ``.tact`` file
imports as editable effects on the garment's groups, the pattern exports to ``.tact`` (the
Designer project, and with the compiled frames) and to WAV, a bad file is refused by field,
and the next start brings the editor's pattern back."""

import json
import wave

import pytest

import tactile_core as tc
from tactile_core.files.pattern import Pattern, PatternCue
from tactile_core.files.tact import load_pattern

from . import tact_support
from .timeline_support import editor_of

pytestmark = pytest.mark.usefixtures("qt_settings")


def mixed() -> Pattern:
    """One of each kind the editor adds: a shape with the scene's method, a drawn path, dots,
    a Tactile Brush stroke; an envelope, a repeat, a second track."""
    drawn = tc.TimedPath([(0.5, 0.5), (2.5, 3.0), (4.5, 5.5)], [0.0, 0.3, 0.7])
    return tc.Pattern([
        tc.Effect(tc.Line((0.5, 1.5), (4.5, 1.5)), duration_s=0.5, name="bar"),
        tc.Effect(drawn, start_s=0.6, track=1),
        tc.Effect(tc.Dots([tc.Dot(17, 1.0, 0.0, 0.08)]), start_s=1.0, duration_s=0.25, repeat=3,
                  envelope=[(0.0, 0.4), (0.08, 1.0)]),
        tc.Effect(tc.Circle((2.5, 3.0), 1.5), start_s=0.2, duration_s=1.0, method="TB", track=2),
    ], name="mixed", combine="sum")  # fmt: skip


def test_save_then_open_gives_back_the_same_pattern(window, tmp_path):
    editor = editor_of(window)
    editor.open_pattern(mixed(), None, "Open")
    files = editor.files
    assert not files.save_file()  # no file yet: Save as first
    assert "Save as" in window.last_error
    assert files.save_file(tmp_path / "mixed.json")
    assert editor.undo_stack.isClean() and not editor.dock.windowTitle().endswith("*")
    assert Pattern.load(tmp_path / "mixed.json") == mixed()
    editor.push(lambda: editor.model.delete(0))
    assert editor.dock.windowTitle().endswith("*")  # unsaved
    assert files.open_file(tmp_path / "mixed.json")
    assert editor.model.pattern == mixed() and editor.model.path == tmp_path / "mixed.json"
    assert editor.undo_stack.isClean()
    editor.undo_stack.undo()  # the open undone: the edit before it is back, and its file
    assert len(editor.model.pattern.effects) == 3


def test_a_bad_file_is_refused_by_field_and_changes_nothing(window, tmp_path):
    editor = editor_of(window)
    editor.open_pattern(mixed(), None, "Open")
    data = mixed().to_dict()
    data["effects"][2]["repeat"] = 0
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    assert not editor.files.open_file(bad)
    assert "effects[2].repeat must be >= 1" in window.last_error
    assert editor.model.pattern == mixed()


def test_a_tact_file_imports_as_effects_on_the_garments_groups(window, qtbot, tmp_path):
    window.files.use_profile("vest-front-back")
    qtbot.waitUntil(lambda: window.device.profile.name == "vest-front-back", timeout=10_000)
    path = tact_support.write(tmp_path, tact_support.dots_only(), "beat.tact")
    editor = editor_of(window)
    assert editor.files.import_tact(path)
    pattern = editor.model.pattern
    assert pattern == Pattern.from_tact(path, groups={"VestFront": "front", "VestBack": "back"})
    assert sorted(e.group for e in pattern.effects) == ["back", "back", "front", "front"]
    assert editor.model.path is None  # Save asks where
    # it plays as the file does
    layout = window.device.profile.layout
    _, ours = pattern.frames("BA", layout, rate_hz=100.0)
    _, theirs = load_pattern(path).frames("BA", layout, rate_hz=100.0)
    assert ours.shape == theirs.shape and abs(ours - theirs).max() < 1e-12


def test_exports_to_both_tact_forms_and_to_wav(window, tmp_path):
    editor = editor_of(window)
    editor.open_pattern(mixed().replace(combine="max"), None, "Open")
    files = editor.files
    assert files.export_tact(tmp_path / "mixed.tact")
    assert files.export_tact(tmp_path / "compiled.tact", compiled=True)
    project = json.loads((tmp_path / "mixed.tact").read_text())
    both = json.loads((tmp_path / "compiled.tact").read_text())
    assert "project" in project and "feedback" not in project
    assert "project" in both and both["intervalMillis"] == 20 and both["feedback"]
    assert files.export_wav(tmp_path / "mixed.wav")
    profile = window.device.profile
    with wave.open(str(tmp_path / "mixed.wav")) as wav:
        assert wav.getnchannels() == profile.channels and wav.getframerate() == 48000
        assert wav.getnframes() / 48000 > mixed().duration_s
    assert "exported the pattern's carriers" in window.statusBar().currentMessage()


def test_the_next_start_brings_the_editors_pattern_back(qtbot, qt_settings, tmp_path):
    from tactile_tuner.window import MainWindow

    first = MainWindow(restore=False, process=False)
    qtbot.addWidget(first)
    editor = first.timeline
    editor.open_pattern(mixed(), None, "Open")
    editor.push(lambda: editor.model.move(0, 0.1, 0))
    editor.model.set_playhead(0.5)
    assert editor.play()
    first.confirm = lambda title, text: True
    first.close()
    second = MainWindow(restore=True, process=False)
    qtbot.addWidget(second)
    try:
        model = second.timeline.model
        assert model.pattern == mixed().replace(
            effects=(mixed().effects[0].replace(start_s=0.1), *mixed().effects[1:])
        )
        assert not second.timeline.undo_stack.isClean()  # still unsaved
        assert model.selected == 0  # as it was left
        assert isinstance(second.state.scene.source, PatternCue)  # and it plays again
        assert second.state.scene.source.pattern is model.pattern
        assert second.state.scene.source.start_s >= 0.5  # from where the playhead was
        assert "from the pattern editor" in second.statusBar().currentMessage()
        second.timeline.seek(0.4)  # scrubbed, then paused (Esc): so it comes back
        second.state.update(playing=False)
    finally:
        second.confirm = lambda title, text: True
        second.close()
    third = MainWindow(restore=True, process=False)
    qtbot.addWidget(third)
    try:
        pattern = third.timeline.model.pattern
        assert third.state.scene.source == PatternCue(pattern, 0.4, hold=True)
        assert not third.state.scene.playing
    finally:
        third.confirm = lambda title, text: True
        third.close()


def test_a_pattern_saved_without_a_name_is_called_by_its_file_everywhere(window, qtbot, tmp_path):
    # Saved as mypat.json without a name, it was "pattern *" in the title (a star right after
    # saving), "untitled" in the Shape panel and "mypat.json" on the dock; the file held "".
    editor = editor_of(window)
    editor.open_pattern(mixed().replace(name=""), None, "New")
    assert editor.play()
    assert editor.files.save_file(tmp_path / "mypat.json")
    assert Pattern.load(tmp_path / "mypat.json").name == "mypat"
    assert editor.dock.windowTitle() == "Pattern editor - mypat"
    assert window.windowTitle().split(" - ")[1] == "mypat"  # and no star: it is that file's
    assert window.controls.shape.other_label.text().startswith("The pattern mypat:")
    editor.undo_stack.undo()  # the name is an edit like any other
    assert editor.model.pattern.name == ""
    editor.undo_stack.redo()
    assert editor.files.open_file(tmp_path / "mypat.json") and editor.play()
    assert window.windowTitle().split(" - ")[1] == "mypat"
    assert window.controls.shape.other_label.text().startswith("The pattern mypat:")


def test_an_example_pattern_is_never_saved_over(window):
    # File > Example patterns, an effect moved, File > Save: it wrote into the installed
    # package's assets/patterns/letter-a.json, which every later Example patterns served.
    from tactile_core.files.pattern import example_patterns

    example = example_patterns()["letter-a"]
    before = example.read_bytes()
    assert window.files.open_pattern_file(example, example=True)
    editor = editor_of(window)
    assert editor.model.pattern == Pattern.load(example)
    assert editor.model.path is None and editor.undo_stack.isClean()  # Save asks where
    editor.push(lambda: editor.model.move(0, 0.01, 0))
    assert not editor.files.save_file()
    assert "Save as" in window.last_error
    assert not editor.files.save_file(example)  # chosen by hand in Save as: refused too
    assert "letter-a.json is a bundled example" in window.last_error
    assert example.read_bytes() == before


def test_a_tact_export_says_in_the_editors_words_which_effect_needs_a_group(window, tmp_path):
    # The vest sweep with the scene's shape added (every actuator) on vest-front-back: "effects[2]
    # (group None) would go to VestFront, which holds group 'front''s actuators", counted from
    # 0 while the time line says 3, None for what the panel calls every actuator.
    from tactile_core.files.pattern import example_patterns

    assert window.files.open_pattern_file(example_patterns()["vest-sweep"], example=True)
    editor = editor_of(window)
    editor.model.set_playhead(1.6)
    assert editor.add_from_scene()  # effect 3, on every actuator
    assert not editor.files.export_tact(tmp_path / "sweep.tact")
    assert window.last_error == (
        "could not export sweep.tact: effect 3 plays on every actuator, but a .tact file holds "
        "each group here as a device position (front as VestFront, back as VestBack): choose its "
        "group in the properties (front or back), then export again"
    )
    assert not (tmp_path / "sweep.tact").exists()
    editor.push(lambda: editor.model.change(2, group="back"))
    assert editor.files.export_tact(tmp_path / "sweep.tact")  # as the message says
