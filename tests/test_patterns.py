"""Patterns: effects on a time line, their frames worked out by hand (docs/patterns.md)."""

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import find_profile
from tactile_core.files.pattern import Dot, Dots, Effect, Pattern, TactEffect
from tactile_core.rendering.methods import get_method
from tactile_core.rendering.shapes import TimedPath

PALM = tc.Grid(5, 6)
VEST = find_profile("vest-front-back").layout  # groups front (0-19) and back (20-39)


def frames_at(pattern, rate_hz, target=PALM, method="AS", **correction):
    """The pattern's frames, flat: ``(n, size)``."""
    _, frames = pattern.frames(method, target, rate_hz=rate_hz, **correction)
    return frames.reshape(len(frames), -1)


def dot_pattern(*effects, combine="max"):
    return Pattern(list(effects), combine=combine)


def test_a_dot_at_half_intensity_from_0_2_to_0_4_s():
    # one dot on actuator 14 (column 4, row 2), 0.5 from 0.2 s to 0.4 s; at 10 frames a second
    # frame k samples (k + 0.5) / 10 s: on in frames 2 (0.25 s) and 3 (0.35 s), nowhere else
    pattern = dot_pattern(Effect(Dots([Dot(14, 0.5, start_s=0.2, duration_s=0.2)])))
    assert pattern.duration_s == pytest.approx(0.4)
    frames = frames_at(pattern, 10.0)
    expected = np.zeros((4, 30))
    expected[2:4, 14] = 0.5
    assert np.array_equal(frames, expected)
    # the correction applies after: mu + (1 - mu) 0.5^gamma where lit, 0 elsewhere
    corrected = frames_at(pattern, 10.0, mu=0.2, gamma=0.5)
    assert corrected[2, 14] == pytest.approx(0.2 + 0.8 * np.sqrt(0.5)) and corrected[1].sum() == 0


@pytest.mark.parametrize(
    "combine, levels, expected",
    [("max", (0.4, 0.7), 0.7), ("sum", (0.4, 0.7), 1.0), ("sum", (0.4, 0.3), 0.7)],
)
def test_overlapping_effects_combine_by_the_maximum_or_the_clipped_sum(combine, levels, expected):
    # two effects on actuator 7 from 0 to 1 s; a third, alone on actuator 3, is untouched
    a, b = (Effect(Dots([Dot(7, v, duration_s=1.0)])) for v in levels)
    alone = Effect(Dots([Dot(3, 0.6, duration_s=1.0)]))
    frames = frames_at(dot_pattern(a, b, alone, combine=combine), 4.0)
    assert frames[:, 7] == pytest.approx([expected] * 4, abs=1e-15)
    assert frames[:, 3] == pytest.approx([0.6] * 4, abs=0)
    assert np.count_nonzero(frames) == 8


def test_two_overlapping_strokes_combine_per_actuator():
    # two lines through the middle of the palm at once: under max an actuator both light gets
    # the larger of the two values, under sum their sum (each line alone computed by tc.render)
    one, two = tc.Line((0.5, 2.5), (4.5, 2.5)), tc.Line((2.5, 0.5), (2.5, 5.5))
    t = (np.arange(20) + 0.5) / 20  # frame k of one second at 20 Hz samples t = (k + 0.5) / 20
    alone = [tc.render(shape, "AS", t).reshape(20, -1) for shape in (one, two)]
    effects = [Effect(one, duration_s=1.0), Effect(two, duration_s=1.0)]
    for combine, expected in (("max", np.maximum(*alone)),
                              ("sum", np.minimum(alone[0] + alone[1], 1.0))):  # fmt: skip
        frames = frames_at(Pattern(effects, combine=combine), 20.0)
        assert frames == pytest.approx(expected, abs=1e-12)
    assert (alone[0] * alone[1]).any()  # they do overlap (the middle actuator)


def test_an_envelope_interpolates_its_keyframes_and_holds_its_ends():
    # keyframes (0.2, 0.5) and (0.6, 1.0) over a one-second dot at 0.8: 0.5 held before 0.2 s,
    # a line to 1.0 at 0.6 s, 1.0 held after; at 8 Hz the samples are 0.0625 + k / 8 s
    dot = Dots([Dot(0, 0.8, duration_s=1.0)])
    pattern = dot_pattern(Effect(dot, envelope=[(0.2, 0.5), (0.6, 1.0)]))
    when = (np.arange(8) + 0.5) / 8
    gain = np.where(when <= 0.2, 0.5, np.where(when >= 0.6, 1.0, 0.5 + (when - 0.2) / 0.4 * 0.5))
    assert frames_at(pattern, 8.0)[:, 0] == pytest.approx(0.8 * gain, abs=1e-12)
    ramp = dot_pattern(Effect(dot, envelope=[(0.0, 0.0), (1.0, 1.0)]))
    assert frames_at(ramp, 2.0)[0, 0] == pytest.approx(0.8 * 0.25)  # the sample at 0.25 s
    assert Effect(dot, envelope=[(0.2, 0.5), (0.6, 1.0)]).gain1(0.4) == pytest.approx(0.75)


def test_an_envelope_scales_a_shape_before_the_correction():
    # a line at gain 0.5 is the line's raw frames halved; corrected, 0 stays 0
    line = tc.Line((0.5, 0.5), (4.5, 0.5))
    plain = frames_at(Pattern([Effect(line, duration_s=1.0)]), 10.0)
    half = frames_at(Pattern([Effect(line, duration_s=1.0, envelope=[(0.0, 0.5)])]), 10.0)
    assert half == pytest.approx(0.5 * plain, abs=1e-15) and plain.any()
    quiet = Pattern([Effect(line, duration_s=1.0, envelope=[(0.0, 0.0)])])
    assert not frames_at(quiet, 10.0, mu=0.33, gamma=0.7).any()  # not mu: off


def test_repeat_plays_the_effect_back_to_back():
    # a dot of 0.1 s in a play of 0.3 s, three times from 0.1 s: on 0.1-0.2, 0.4-0.5, 0.7-0.8 s
    pattern = dot_pattern(Effect(Dots([Dot(5, 1.0, duration_s=0.1)]), start_s=0.1,
                                 duration_s=0.3, repeat=3))  # fmt: skip
    assert pattern.duration_s == pytest.approx(1.0)
    on = frames_at(pattern, 20.0)[:, 5] > 0  # samples at 0.025 + k / 20 s
    assert np.flatnonzero(on).tolist() == [2, 3, 8, 9, 14, 15]
    # a repeated shape: each play traces the whole line again
    line = tc.Line((0.5, 0.5), (4.5, 0.5))
    twice = frames_at(Pattern([Effect(line, duration_s=0.5, repeat=2)]), 20.0)
    assert twice[:10] == pytest.approx(twice[10:], abs=1e-12) and twice.any()


def test_a_group_restricts_a_shape_on_the_vest_to_the_front():
    # a line across both panels at y = 2: alone it lights front and back; on group "front"
    # exactly its front actuators, at the values it gives them alone
    line = tc.Line((0.0, 2.0), (8.0, 2.0))
    everywhere = frames_at(Pattern([Effect(line, duration_s=1.0)]), 20.0, VEST, "BA")
    front = frames_at(Pattern([Effect(line, duration_s=1.0, group="front")]), 20.0, VEST, "BA")
    assert everywhere[:, :20].any() and everywhere[:, 20:].any()
    assert np.array_equal(front[:, :20], everywhere[:, :20]) and not front[:, 20:].any()


def test_a_dot_by_place_lights_the_nearest_actuator_of_its_group():
    # (4.2, 0) is nearest to the front's r0c3 at (3, 0)... unless the dot must stay on the
    # back: then r0c0 of the back, at (5, 0)
    anywhere = Effect(Dots([Dot((4.2, 0.0))]))
    back = Effect(Dots([Dot((4.2, 0.0))]), group="back")
    assert np.flatnonzero(frames_at(Pattern([anywhere]), 10.0, VEST, "BA")[0]).tolist() == [20]
    assert np.flatnonzero(frames_at(Pattern([back]), 10.0, VEST, "BA")[0]).tolist() == [20]
    near_front = Effect(Dots([Dot((3.8, 0.0))]))
    on_back = Effect(Dots([Dot((3.8, 0.0))]), group="back")
    assert np.flatnonzero(frames_at(Pattern([near_front]), 10.0, VEST, "BA")[0]).tolist() == [3]
    assert np.flatnonzero(frames_at(Pattern([on_back]), 10.0, VEST, "BA")[0]).tolist() == [20]


def test_dots_keep_their_times_and_a_play_cuts_them():
    # a play of 0.25 s holds a dot from 0.1 to 0.2 s and half of one from 0.2 to 0.4 s; the
    # dot from 0.3 s never plays. A time-keyed path as a shape is fitted to the play instead.
    dots = Dots([Dot(1, start_s=0.1, duration_s=0.1), Dot(2, start_s=0.2, duration_s=0.2),
                 Dot(3, start_s=0.3, duration_s=0.1)])  # fmt: skip
    frames = frames_at(Pattern([Effect(dots, duration_s=0.25)]), 20.0)  # 0.025 + k / 20 s
    assert np.flatnonzero(frames[:, 1]).tolist() == [2, 3]
    assert np.flatnonzero(frames[:, 2]).tolist() == [4]
    assert not frames[:, 3].any() and len(frames) == 5
    slow = TimedPath([(0.5, 0.5), (4.5, 0.5)], [0.0, 2.0], [1.0, 0.2])
    fast = TimedPath([(0.5, 0.5), (4.5, 0.5)], [0.0, 0.5], [1.0, 0.2])
    fitted = frames_at(Pattern([Effect(slow, duration_s=0.5)]), 20.0)
    assert fitted == pytest.approx(frames_at(Pattern([Effect(fast)]), 20.0), abs=1e-12)


def test_a_shape_effect_is_the_shape_traced_over_its_play():
    circle = tc.Circle((2.5, 3.0), 1.5)
    frames = frames_at(Pattern([Effect(circle, start_s=0.5, duration_s=2.0)]), 10.0)
    t = (np.arange(20) + 0.5) / 20  # the 20 frames of the play sample t = (k + 0.5) / 20
    assert frames[:5].sum() == 0 and len(frames) == 25
    assert frames[5:] == pytest.approx(tc.render(circle, "AS", t).reshape(20, -1), abs=1e-12)


def test_an_effects_method_overrides_the_scenes_and_tb_is_timed_by_the_effect():
    line = tc.Line((0.5, 3.0), (4.5, 3.0))
    t = (np.arange(30) + 0.5) / 30
    ct = frames_at(Pattern([Effect(line, duration_s=1.0, method="CT")]), 30.0, method="AS")
    assert ct == pytest.approx(tc.render(line, "CT", t).reshape(30, -1), abs=0)
    brush = frames_at(Pattern([Effect(line, duration_s=1.5, method="TB")]), 20.0)
    timed = get_method("TB").on_clock(1.5)  # onsets over the stroke's 1.5 s, not one second
    assert brush == pytest.approx(tc.render(line, timed, t).reshape(30, -1), abs=1e-12)


def test_a_tact_effect_maps_onto_its_groups_extent():
    # bHaptics' (0, 0) top left and (1, 1) bottom right: on group "back" they are the back
    # panel's corners, r4c0 (actuator 36, at (5, 4)) and r0c3 (23, at (8, 0))
    content = TactEffect(dots=[Dot((0.0, 0.0), 0.9, 0.0, 0.5), Dot((1.0, 1.0), 0.4, 0.0, 0.5)],
                         length_s=0.5)  # fmt: skip
    frames = frames_at(Pattern([Effect(content, group="back")]), 10.0, VEST, "BA")
    assert {i: frames[0, i] for i in np.flatnonzero(frames[0])} == {36: 0.9, 23: 0.4}
    frames = frames_at(Pattern([Effect(content)]), 10.0, VEST, "BA")  # the whole vest: 0..8
    assert {i: frames[0, i] for i in np.flatnonzero(frames[0])} == {16: 0.9, 23: 0.4}


@pytest.mark.parametrize("combine", ["max", "sum"])
@pytest.mark.parametrize("target, method", [(PALM, "IM"), (VEST, "BA")])
def test_the_table_and_the_scalar_path_give_the_same_frames(combine, target, method):
    rng = np.random.default_rng(3)
    x1, y1 = target.bounds(0.0)[1], target.bounds(0.0)[3]
    effects = []
    for k in range(40):
        start = float(rng.uniform(0, 3))
        if k % 2:
            line = tc.Line(tuple(rng.uniform(0, [x1, y1])), tuple(rng.uniform(0, [x1, y1])))
            length, rise = float(rng.uniform(0.1, 1)), [(0.0, 0.3), (0.05, 1.0)]
            effects.append(Effect(line, start_s=start, duration_s=length, envelope=rise,
                                  repeat=1 + k % 3))  # fmt: skip
        else:
            dots = [Dot(int(rng.integers(target.size)), float(rng.uniform(0.1, 1)),
                        float(rng.uniform(0, 0.3)), float(rng.uniform(0.05, 0.4)), fade)
                    for fade in ("NONE", "FADE_IN", "FADE_OUT", "FADE_IN_OUT")]  # fmt: skip
            effects.append(Effect(Dots(dots), start_s=start, repeat=1 + k % 2,
                                  envelope=[(0.0, 1.0), (0.2, 0.2)] if k % 4 else ()))  # fmt: skip
    pattern = Pattern(effects, combine=combine)
    sampling = tc.Sampling(120.0, "box", 3)
    live = pattern.live(method, target, sampling, 0.2, 0.8)
    _, table = live.render(0, live.n_frames)
    scalar = np.array([live.frame(k) for k in range(live.n_frames)])
    assert scalar == pytest.approx(table, abs=1e-12) and table.any()


def test_a_frame_evaluates_only_the_effects_playing_then():
    # 2,000 strokes one after another, 0.1 s each: a frame computes one of them
    line = tc.Line((0.5, 0.5), (4.5, 5.5))
    pattern = Pattern([Effect(line, start_s=0.1 * k, duration_s=0.1) for k in range(2000)])
    live = pattern.live("AS", PALM, tc.Sampling(100.0, "point"), 0.0, 1.0)
    calls = []
    for part in live._parts:  # count what each stroke is asked for
        part.entries = (lambda f, n: lambda shape, t: calls.append(n) or f(shape, t))(
            part.entries, part.index
        )
    entries = live.compute(12345)  # 123.455 s: effect 1234
    assert calls == [1234] and entries
    assert len(live._spans.at(123.455)) <= 10  # the index's candidates, not the 2,000


def test_the_builder_returns_new_equal_values():
    empty = Pattern()
    one = empty.add(tc.Line((0, 0), (1, 1)), duration_s=0.5, track=1)
    two = one.then(Dots([Dot(3)]), gap_s=0.2, track=1)
    assert empty.effects == () and len(one.effects) == 1 and len(two.effects) == 2
    assert two.effects[1].start_s == pytest.approx(0.7) and two.effects[1].track == 1
    assert two.then(tc.Line((0, 0), (1, 1)), duration_s=1.0).effects[2].start_s == 0.0
    again = Pattern(list(two.effects))
    assert again == two and hash(again) == hash(two) and again is not two
    assert two.replace(combine="sum").combine == "sum" and two.combine == "max"
    assert two.tracks == (1,) and Pattern().add(two.effects[0], group="front").groups == ("front",)
    with pytest.raises(Exception, match="cannot assign"):
        two.name = "x"  # frozen


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Effect(tc.Line((0, 0), (1, 1))), "duration_s must be given for a line"),
        (lambda: Effect(Dots([Dot(0)]), envelope=[(0.05, 1), (0.02, 1)]),
         r"envelope\[1\]\.time_s must be later"),
        (lambda: Effect(Dots([Dot(0)]), envelope=[(0.5, 1)]), r"envelope\[0\]\.time_s must be"),
        (lambda: Effect(Dots([Dot(0)]), envelope=[(0.0, 2)]), r"envelope\[0\]\.gain must be"),
        (lambda: Effect(Dots([Dot(0)]), repeat=0), "repeat must be >= 1"),
        (lambda: Effect(Dots([Dot(0)]), method="XX"), "method"),
        (lambda: Effect("line:0,0,1,1"), "content must be a shape"),
        (lambda: Dot(1.5), r"at must be a point"),
        (lambda: Dot(0, intensity=1.2), "intensity must be within"),
        (lambda: Dots([Dot(0), 3]), r"dots\[1\] must be a Dot"),
        (lambda: Pattern([Effect(Dots([Dot(0)]))], combine="avg"), "combine must be one of"),
        (lambda: Pattern([Dots([Dot(0)])]), r"effects\[0\] must be an Effect"),
        (lambda: Effect(Dots([Dot(0)]), duration_s=3000, repeat=2), "after the 3600 s"),
    ],
)  # fmt: skip
def test_bad_arguments_are_refused_by_name(make, message):
    with pytest.raises(ValueError, match=message):
        make()


@pytest.mark.parametrize(
    "effect, message",
    [
        (Effect(Dots([Dot(0)]), group="front"), r"effects\[0\]\.group must name a group of the "
         r"layout \(it has none\), got 'front'"),
        (Effect(Dots([Dot(30)])), r"effects\[0\]\.dots\[0\]\.at is actuator 30, but the layout "
         r"has 30 \(0 to 29\)"),
    ],
)  # fmt: skip
def test_what_the_array_lacks_is_refused_by_field(effect, message):
    with pytest.raises(ValueError, match=message):
        Pattern([effect]).check(PALM)
    on_vest = Pattern([Effect(Dots([Dot(3)]), group="back")])
    with pytest.raises(ValueError, match=r"effects\[0\]\.dots\[0\]\.at is actuator 3, which is "
                       "not in the effect's group 'back'"):  # fmt: skip
        on_vest.check(VEST)
    with pytest.raises(ValueError, match=r"effects\[0\]\.method IM"):
        Pattern([Effect(tc.Line((0, 0), (3, 3)), duration_s=1.0, method="IM")]).check(VEST)
