"""Method specs after other tools' methods: Syntacts' linear roll-off (RO:curve=linear), PK's
crossfade (PK:blend=w) and its jump, VRCH-Server's one-contact rule (VRCH), and the correction
each method is designed for. Expected values worked by hand from the sources' definitions."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.rendering.methods import get_method


def at(method, x, y):
    frame = tc.render_xy(method, x, y)
    rows, cols = np.nonzero(frame)
    return {(int(c), int(r)): float(frame[r, c]) for r, c in zip(rows, cols)}


def coord(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def test_ro_linear_is_syntacts_default_curve():
    # Syntacts: volume = curve(1 - clamp(d / r)); linear at a corner, d = sqrt(1/2) from four.
    corner = 1 - math.sqrt(0.5)
    four = [(1, 2), (2, 2), (1, 3), (2, 3)]
    assert at("RO:curve=linear", 2.0, 3.0) == pytest.approx(dict.fromkeys(four, corner))
    assert at("RO:curve=linear", 2.5, 3.25) == pytest.approx({(2, 2): 0.25, (2, 3): 0.75})
    assert at("RO:r=2,curve=linear", 2.5, 3.5)[(1, 3)] == pytest.approx(0.5)


def test_choice_parameters_travel_as_specs():
    assert get_method("RO:curve=smoothstep").spec == "RO"
    assert get_method("ro:curve=LINEAR,r=1.5").spec == "RO:r=1.5,curve=linear"
    assert get_method("RO", curve="linear").values == {"r": 1.0, "curve": "linear"}
    assert get_method("RO:curve=linear") is get_method("RO:curve=linear")  # bound once
    with pytest.raises(ValueError, match="method RO: curve must be one of"):
        get_method("RO:curve=cubic")
    with pytest.raises(ValueError, match="method GS has no parameter 'curve'"):
        get_method("GS:curve=linear")
    with pytest.raises(ValueError, match="r must be finite"):
        get_method("RO:r=nan")


def test_pk_jumps_at_a_centre_line_and_the_blend_does_not():
    # Crossing x = 2.0 at y = 3.1 to the right: the lower tactor left of the line, (1,2), at
    # hypot(0.5, 0.6) from the point, with (1,3) and (2,3) at hypot(0.5, 0.4) each, gets
    # sqrt((1/0.781) / (1/0.781 + 2/0.640)) = 0.539; past the line (2,2) takes its place.
    inv = [1 / math.hypot(0.5, 0.6), 1 / math.hypot(0.5, 0.4), 1 / math.hypot(0.5, 0.4)]
    jump = math.sqrt(inv[0] / sum(inv))
    before, after = at("PK", 2.0 - 1e-6, 3.1), at("PK", 2.0 + 1e-6, 3.1)
    assert before[(1, 2)] == pytest.approx(jump, abs=1e-5) and (1, 2) not in after
    assert after[(2, 2)] == pytest.approx(jump, abs=1e-5) and (2, 2) not in before
    assert jump == pytest.approx(0.539, abs=1e-3)
    blended = [at("PK:blend=0.2", 2.0 + s, 3.1) for s in (-1e-6, 1e-6)]
    for cell in ((1, 2), (2, 2)):
        assert abs(blended[1][cell] - blended[0][cell]) < 1e-4
    # Mid-band the left-out tactor carries half of its three-tactor energy: x = 2.0 exactly,
    # the two choices (leave out (1,2) or (2,2)) mixed half and half.
    mid = at("PK:blend=0.2", 2.0, 3.1)
    assert mid[(1, 2)] ** 2 == pytest.approx(0.5 * jump**2)


@given(st.tuples(coord(1.5, 3.4999), coord(1.5, 4.4999)), st.floats(0.01, 0.5))
def test_pk_blend_keeps_unit_energy(p, blend):
    frame = tc.render_xy(f"PK:blend={blend}", *p)
    assert (frame > 0).sum() <= get_method(f"PK:blend={blend}").max_tactors == 6
    assert float((frame**2).sum()) == pytest.approx(1.0, abs=1e-12)


def test_pk_jumps_at_a_line_of_tactor_centres_too():
    # Crossing x = 2.5 (column 2's centre line) at y = 3.0, midway between rows 2 and 3: the
    # third tactor moves from column 1 to column 3, at hypot(1, 0.5) with the two nearest at
    # 0.5: sqrt((1/1.118) / (1/1.118 + 2/0.5)) = 0.427.
    w = 1 / math.hypot(1, 0.5)
    jump = math.sqrt(w / (w + 4))
    before, after = at("PK", 2.5 - 1e-9, 3.0), at("PK", 2.5 + 1e-9, 3.0)
    assert before[(1, 3)] == pytest.approx(jump) and (3, 3) in after and (1, 3) not in after
    blended = [at("PK:blend=0.2", 2.5 + s, 3.0) for s in (-1e-9, 1e-9)]
    for cell in ((1, 3), (3, 3)):
        assert abs(blended[1].get(cell, 0) - blended[0].get(cell, 0)) < 1e-6


def test_pk_blend_outside_the_band_is_parks_rule():
    for x, y in [(1.7, 2.6), (3.3, 4.85), (2.9, 1.1)]:
        assert at("PK:blend=0.1", x, y) == pytest.approx(at("PK", x, y), abs=1e-15)


def test_vrch_lights_every_tactor_within_r_at_full():
    assert at("VRCH", 2.0, 3.0) == dict.fromkeys([(1, 2), (2, 2), (1, 3), (2, 3)], 1.0)
    assert at("VRCH", 2.5, 3.5) == {(2, 3): 1.0}  # neighbours at d = 1 = r: off
    wide = at("VRCH:r=1.5", 2.5, 3.5)  # d = 1 and sqrt(2) < 1.5: the 3 x 3 block
    assert wide == dict.fromkeys([(c, r) for c in (1, 2, 3) for r in (2, 3, 4)], 1.0)
    method = get_method("VRCH")
    assert method.bilevel and method.max_tactors == 4


def test_each_method_carries_its_own_correction():
    own = {name: get_method(name).own_correction(0.33, 0.7) for name in tc.METHODS}
    for name in ("CT", "MM", "AS", "IM", "GS"):
        assert own[name] == (0.33, 0.7)
    assert own["EN"] == own["PK"] == own["RO"] == (0.0, 1.0)
    assert own["VRCH"] == (0.33, 1.0)
    assert get_method("EN").correction_label == "no correction"
