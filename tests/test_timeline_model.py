"""The pattern editor's model without Qt (app/timeline/model.py): edits are functions from one
pattern to the next, snapped to the 10 ms grid, refused with the pattern's own message; and
the frame source it plays, PatternCue: a pattern from a moment of it, or held there."""

import ast
from pathlib import Path

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.files.pattern import PatternCue
from tactile_tuner.timeline.model import (
    SNAP_S,
    TimelineModel,
    envelope_text,
    parse_envelope,
    peak_gain,
    resized,
    snap,
    with_intensity,
)

LINE = tc.Line((0.5, 0.5), (4.5, 5.5))


def letter():
    return (tc.Pattern(name="L").add(LINE, duration_s=0.5)
            .then(tc.Line((1, 1), (4, 1)), gap_s=0.2, duration_s=0.4))  # fmt: skip


def test_the_model_imports_nothing_of_qt_or_the_tuner():
    # what style.md asks of a model ("One thing, one model"): the editor's state can be scripted
    # and tested without a window
    import tactile_tuner.timeline.model as model

    tree = ast.parse(Path(model.__file__).read_text())
    names = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    names |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.level == 0}
    relative = [n for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.level > 0]
    assert relative == []
    assert {name.split(".")[0] for name in names} <= {"__future__", "math", "re", "dataclasses",
                                                      "tactile_core"}  # fmt: skip


def test_snap_rounds_to_the_10_ms_grid():
    assert SNAP_S == 0.01
    assert snap(0.123) == 0.12 and snap(0.126) == 0.13 and snap(0.3) == 0.3
    assert snap(0.1 + 0.2) == 0.3  # not 0.30000000000000004
    assert snap(0.1234, 0.0) == 0.1234  # no grid


def test_move_snaps_and_changes_only_that_effect():
    model = TimelineModel(letter())
    edit = model.move(1, 1.234, 2)
    assert [(e.start_s, e.track) for e in edit.pattern.effects] == [(0.0, 0), (1.23, 2)]
    assert edit.selected == 1 and edit.text == "Move effect 2"
    assert model.pattern == letter()  # nothing applied yet
    assert model.move(0, -0.5, 0).pattern.effects[0].start_s == 0.0  # not before 0


def test_resize_stretches_the_envelope_with_the_play():
    effect = tc.Effect(LINE, duration_s=0.5, envelope=[(0.0, 0.2), (0.25, 1.0), (0.5, 0.0)])
    longer = resized(effect, 1.0)
    assert longer.duration_s == 1.0
    assert longer.envelope == ((0.0, 0.2), (0.5, 1.0), (1.0, 0.0))
    model = TimelineModel(tc.Pattern([effect]))
    assert model.resize(0, 0.254).pattern.effects[0].duration_s == 0.25
    assert model.resize(0, 0.001).pattern.effects[0].duration_s == SNAP_S  # a grid step at least


def test_intensity_scales_the_envelope_to_its_peak():
    effect = tc.Effect(LINE, duration_s=1.0)
    assert peak_gain(effect) == 1.0
    assert with_intensity(effect, 0.5).envelope == ((0.0, 0.5),)
    shaped = effect.replace(envelope=[(0.0, 0.4), (0.5, 0.8)])
    scaled = with_intensity(shaped, 0.4).envelope
    assert [t for t, _ in scaled] == [0.0, 0.5]
    assert [g for _, g in scaled] == pytest.approx([0.2, 0.4], abs=1e-15)
    silent = effect.replace(envelope=[(0.0, 0.0), (1.0, 0.0)])
    assert with_intensity(silent, 0.3).envelope == ((0.0, 0.3), (1.0, 0.3))
    with pytest.raises(ValueError, match="intensity must be within"):
        with_intensity(effect, 1.5)


def test_a_change_the_pattern_refuses_raises_its_message():
    model = TimelineModel(letter())
    with pytest.raises(ValueError, match="repeat must be >= 1"):
        model.change(0, repeat=0)
    with pytest.raises(ValueError, match=r"envelope\[1\].time_s must be later"):
        model.change(0, envelope=((0.2, 1.0), (0.1, 0.5)))
    with pytest.raises(ValueError, match="method"):
        model.change(0, method="NOPE")
    assert model.change(0, repeat=3).pattern.effects[0].end_s == 1.5


def test_envelope_text_round_trips_and_names_a_bad_pair():
    assert parse_envelope("0:0.4, 0.08:1") == ((0.0, 0.4), (0.08, 1.0))
    assert parse_envelope("  ") == ()
    assert envelope_text(((0.0, 0.4), (0.08, 1.0))) == "0:0.4, 0.08:1"
    with pytest.raises(ValueError, match=r"envelope\[1\] must be time_s:gain"):
        parse_envelope("0:0.4, 0.08")
    with pytest.raises(ValueError, match=r"envelope\[0\].gain must be a decimal number"):
        parse_envelope("0:x")


def test_add_delete_duplicate_and_their_selection():
    model = TimelineModel(letter())
    edit = model.duplicate(0)
    assert edit.pattern.effects[2] == letter().effects[0].replace(start_s=0.5)
    assert edit.selected == 2
    model.apply(edit.pattern, edit.selected)
    edit = model.delete(2)
    assert edit.pattern == letter() and edit.selected == 1
    model.apply(edit.pattern, edit.selected)
    model.apply(model.delete(0).pattern, 0)
    assert model.delete(0).selected is None  # the last one gone


def test_tab_order_and_the_free_track():
    pattern = tc.Pattern([tc.Effect(LINE, start_s=1.0, duration_s=0.5),
                          tc.Effect(LINE, start_s=0.0, duration_s=0.5, track=1),
                          tc.Effect(LINE, start_s=0.0, duration_s=2.0)])  # fmt: skip
    model = TimelineModel(pattern)
    assert model.in_time_order() == [2, 1, 0]
    assert model.neighbour(1) == 2 and model.neighbour(-1) == 0
    model.select(1)
    assert model.neighbour(1) == 0 and model.neighbour(-1) == 2
    model.select(0)
    assert model.neighbour(1) is None
    assert model.free_track(0.2, 0.4) == 2 and model.free_track(2.5, 3.0) == 0


def test_listeners_hear_each_part_that_changes():
    model = TimelineModel(letter())
    heard = []
    for event in ("pattern", "selection", "playhead", "path"):
        model.connect(event, lambda e=event: heard.append(e))
    edit = model.move(0, 0.1, 0)
    model.apply(edit.pattern, edit.selected)
    model.set_playhead(0.5)
    model.set_playhead(0.5)  # no change, no event
    model.set_path("x.json")
    assert heard == ["pattern", "selection", "playhead", "path"]
    with pytest.raises(ValueError, match="event must be one of"):
        model.connect("effects", print)


# --- PatternCue: what the editor plays --------------------------------------------------------


def test_a_cue_plays_the_pattern_from_its_moment():
    pattern = letter()
    grid, rate = tc.Grid(), 100.0
    _, frames = pattern.frames("AS", grid, rate_hz=rate, mu=0.33, gamma=0.7)
    live = PatternCue(pattern, 0.3).live("AS", grid, tc.Sampling(rate), 0.33, 0.7)
    for k in range(len(frames) - 30):
        got = np.zeros(grid.size)
        for i, v in live.entries(k):
            got[i] = v
        np.testing.assert_allclose(got.reshape(frames[0].shape), frames[30 + k], atol=1e-12)
    assert live.entries(len(frames)) == ()  # after the end, nothing


def test_a_held_cue_holds_the_frame_that_contains_its_moment():
    pattern = letter()
    grid, rate = tc.Grid(), 100.0
    _, frames = pattern.frames("AS", grid, rate_hz=rate, mu=0.33, gamma=0.7)
    cue = PatternCue(pattern, 0.834, hold=True)
    live = cue.live("AS", grid, tc.Sampling(rate), 0.33, 0.7)
    for k in (0, 5, 1000):
        got = np.zeros(grid.size)
        for i, v in live.entries(k):
            got[i] = v
        np.testing.assert_allclose(got.reshape(frames[0].shape), frames[83], atol=1e-12)
    assert cue.pattern_time_s(5.0) == 0.834
    assert PatternCue(pattern, 0.5).pattern_time_s(0.25) == 0.75
    assert PatternCue(pattern, 0.5).pattern_time_s(9.0) == pattern.duration_s


def test_a_held_cue_plays_on_from_its_moment_but_from_the_start_at_the_end():
    pattern = letter()
    assert PatternCue(pattern, 0.4, hold=True).played() == PatternCue(pattern, 0.4)
    assert PatternCue(pattern, pattern.duration_s, hold=True).played() == PatternCue(pattern, 0.0)


def test_a_cue_is_checked_and_is_a_value():
    with pytest.raises(ValueError, match="pattern must be a Pattern"):
        PatternCue("letter.json")
    with pytest.raises(ValueError, match="start_s must be within"):
        PatternCue(letter(), -1.0)
    assert PatternCue(letter(), 0.2) == PatternCue(letter(), 0.2)
    assert PatternCue(letter(), 0.2).key == PatternCue(letter(), 0.2).key


def test_the_dots_of_a_set_last_as_long_as_asked():
    taps = tc.Effect(tc.Dots([tc.Dot(17, 1.0, 0.0, 0.2), tc.Dot(12, 0.5, 0.0, 0.2)]))
    model = TimelineModel(tc.Pattern([taps]))
    changed = model.change(0, dot_s=0.08, duration_s=0.25).pattern.effects[0]
    assert [(d.at, d.intensity, d.duration_s) for d in changed.content.dots] == [
        (17, 1.0, 0.08), (12, 0.5, 0.08)]  # fmt: skip
    assert changed.duration_s == 0.25
    with pytest.raises(ValueError, match="dot_s applies to a set of dots, not to a line"):
        TimelineModel(letter()).change(0, dot_s=0.1)
