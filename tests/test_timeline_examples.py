"""The issue's three stimuli built in the pattern editor as a researcher would (shapes from the
scene at the playhead, a tactor clicked on the heatmap, the property panel), each the pattern
the 20-line script of docs/patterns.md makes (assets/patterns), then saved, opened again,
played into the array and exported to .tact (both forms) and WAV."""

import json
import wave

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.files.pattern import Pattern, example_patterns
from tactile_core.files.wav import frame_levels

from .helpers import record_sent
from .timeline_support import click_tactor, editor_of

pytestmark = pytest.mark.usefixtures("qt_settings")


def named(editor, name: str) -> None:
    """The pattern's name, typed into the panel (nothing selected: the pattern's fields)."""
    editor.model.select(None)
    panel = editor.panel.panel
    panel.pattern_name.setText(name)
    panel.pattern_name.editingFinished.emit()


def the_scenes_method(editor) -> None:
    """The selected effect renders with the scene's method (the first entry of the box)."""
    combo = editor.panel.panel.method_combo
    combo.setCurrentIndex(0)
    combo.activated.emit(0)


def add_strokes(window, editor, strokes) -> None:
    """Each ``(shape, start_s, duration_s, group)`` picked in the controls, added at the
    playhead, on the scene's method and the group picked in the panel."""
    for shape, start, duration, group in strokes:
        window.state.update(shape=shape, duration_s=duration)
        editor.model.set_playhead(start)
        assert editor.add_from_scene()
        the_scenes_method(editor)
        if group is not None:
            combo = editor.panel.panel.group_combo
            combo.setCurrentIndex(combo.findData(group))
            combo.activated.emit(combo.currentIndex())


def save_reopen_play_export(window, qtbot, editor, tmp_path, stem: str) -> Pattern:
    built = editor.model.pattern
    assert built == Pattern.load(example_patterns()[stem])  # what the script makes
    assert editor.files.save_file(tmp_path / f"{stem}.json")
    editor.open_pattern(Pattern(), None, "New")
    assert editor.files.open_file(tmp_path / f"{stem}.json")
    assert editor.model.pattern == built
    # played into the array: every frame sent while it plays is one of the pattern's own, at
    # the rate the stream renders (the vest's link carries fewer than 300 frames a second)
    from tactile_tuner.frames import stream_rate

    scene = window.state.scene
    rate = stream_rate(scene, window.device.stats)
    _, frames = built.frames(scene.method, window.state.layout, rate_hz=rate, mu=scene.mu,
                             gamma=scene.gamma)  # fmt: skip
    levels = frame_levels(frames, window.device.profile).astype(np.uint8)
    expected = {bytes(row) for row in levels}
    sent = record_sent(window)
    window.state.update(playing=False)  # what played before it, off first
    qtbot.waitUntil(lambda: bool(sent) and not sent[-1].any(), timeout=10_000)
    del sent[:]
    editor.model.set_playhead(0.0)
    assert editor.play()
    qtbot.waitUntil(lambda: not window.state.scene.playing, timeout=15_000)  # its end
    lit = [bytes(f) for f in sent if f.any()]
    assert len(lit) > 0.5 * sum(row.any() for row in levels)
    assert set(lit) <= expected
    # exported
    assert editor.files.export_tact(tmp_path / f"{stem}.tact")
    assert editor.files.export_tact(tmp_path / f"{stem}-compiled.tact", compiled=True)
    assert "feedback" in json.loads((tmp_path / f"{stem}-compiled.tact").read_text())
    assert editor.files.export_wav(tmp_path / f"{stem}.wav")
    with wave.open(str(tmp_path / f"{stem}.wav")) as wav:
        assert wav.getnchannels() == window.device.profile.channels
    return built


def test_a_three_stroke_letter(window, qtbot, tmp_path):
    editor = editor_of(window)
    named(editor, "letter A")
    add_strokes(window, editor, ((tc.Line((0.5, 0.5), (2.5, 5.5)), 0.0, 0.6, None),
                                 (tc.Line((2.5, 5.5), (4.5, 0.5)), 0.85, 0.6, None),
                                 (tc.Line((1.3, 2.5), (3.7, 2.5)), 1.7, 0.4, None)))  # fmt: skip
    letter = save_reopen_play_export(window, qtbot, editor, tmp_path, "letter-a")
    # the .tact file gives the same frames back (docs/patterns.md: to 1e-15)
    layout = window.state.layout
    again = Pattern.from_tact(tmp_path / "letter-a.tact")
    np.testing.assert_allclose(
        again.frames("AS", layout, rate_hz=100.0)[1],
        letter.frames("AS", layout, rate_hz=100.0)[1],
        atol=1e-12,
    )


def test_a_front_to_back_sweep_on_the_vest(window, qtbot, tmp_path):
    window.files.use_profile("vest-front-back")
    qtbot.waitUntil(lambda: window.device.profile.name == "vest-front-back", timeout=10_000)
    editor = editor_of(window)
    named(editor, "front to back")
    add_strokes(window, editor, ((tc.Line((0, 2), (3, 2)), 0.0, 0.8, "front"),
                                 (tc.Line((5, 2), (8, 2)), 0.8, 0.8, "back")))  # fmt: skip
    save_reopen_play_export(window, qtbot, editor, tmp_path, "vest-sweep")
    project = json.loads((tmp_path / "vest-sweep.tact").read_text())["project"]
    positions = {p for track in project["tracks"] for e in track["effects"] for p in e["modes"]}
    assert positions == {"VestFront", "VestBack"}  # each group on its side of the vest


def test_a_tap_sequence(window, qtbot, tmp_path):
    editor = editor_of(window)
    named(editor, "taps")
    editor.set_picking(True)
    click_tactor(qtbot, window.tune.heatmap, 2.5, 3.5)  # mid-palm: actuator 17
    qtbot.waitUntil(lambda: editor.picked == [17], timeout=5000)
    assert editor.add_dots()
    panel = editor.panel.panel
    panel.dot_spin.setValue(0.08)  # each tap 80 ms...
    panel.duration_spin.setValue(0.25)  # ...every 0.25 s...
    panel.repeat_spin.setValue(4)  # ...four of them...
    panel.envelope_edit.setText("0:0.4, 0.08:1")  # ...each rising from 40 % to full
    panel.envelope_edit.editingFinished.emit()
    save_reopen_play_export(window, qtbot, editor, tmp_path, "taps")
