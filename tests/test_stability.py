"""Numerical stability at the extremes, one named case each, and errors on bad input.

Every render here runs with numpy's overflow, invalid-value and divide-by-zero signals raised as
errors, so any such warning fails the test (underflow to zero or subnormals, which numpy ignores
by default, is expected: a radius of 1e-300 makes ``r cos(2 pi t)`` subnormal). Every output is
checked finite and in [0, 1].
"""

import math
import re

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.rendering.scene import Scene

from .helpers import lit

T = np.linspace(0.0, 1.0, 1001)
GAMMAS = [1e-6, 0.3, 7.0, 1e3]
EXTREME_I = np.array([0.0, 1e-300, 1e-12, 0.25, 0.5, 1 - 1e-12, 1.0])


def checked(frames):
    assert np.isfinite(frames).all()
    assert (frames >= 0).all() and (frames <= 1).all()
    return frames


def render_all(shape, t=T, grid=None):
    with np.errstate(over="raise", divide="raise", invalid="raise"):
        grid = grid or tc.Grid()
        return {m: checked(tc.render(shape, m, t, grid=grid)) for m in tc.METHOD_NAMES}


# --- correction at the extremes --------------------------------------------------------------


def test_correct_mu_zero_is_a_pure_power():
    with np.errstate(over="raise", divide="raise", invalid="raise"):
        out = tc.correct(EXTREME_I, mu=0.0, gamma=2.0)
    np.testing.assert_allclose(out, EXTREME_I**2, rtol=1e-15, atol=0)


def test_correct_mu_one_lights_every_active_tactor_fully():
    with np.errstate(over="raise", divide="raise", invalid="raise"):
        out = tc.correct(EXTREME_I, mu=1.0, gamma=0.7)
    np.testing.assert_array_equal(out, np.where(EXTREME_I > 0, 1.0, 0.0))


@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("mu", [0.0, 0.33, 1.0])
def test_correct_extreme_gamma_and_intensities(mu, gamma):
    with np.errstate(over="raise", divide="raise", invalid="raise"):
        out = checked(tc.correct(EXTREME_I, mu=mu, gamma=gamma))
    assert out[0] == 0.0  # zero stays zero
    assert (out[1:] >= mu).all()  # lit tactors get at least the threshold
    assert (np.diff(out[1:]) >= 0).all()  # monotone
    assert out[-1] == 1.0  # full stays full


def test_correct_tiny_intensity_values_by_hand():
    # 1e-300 ** 1e-6 = exp(-690.8e-6) = 0.99930947...
    assert tc.correct(1e-300, mu=0.0, gamma=1e-6) == pytest.approx(
        math.exp(1e-6 * math.log(1e-300))
    )
    # 1e-300 ** 1000 underflows to 0: a lit tactor gets exactly mu.
    assert tc.correct(1e-300, mu=0.2, gamma=1e3) == 0.2
    # (1 - 1e-12) ** 1000 = 1 - 1e-9
    assert tc.correct(1 - 1e-12, mu=0.0, gamma=1e3) == pytest.approx(1 - 1e-9, abs=1e-12)


@pytest.mark.parametrize("gain", [0.0, 0.2, 0.5, 1.0])
def test_master_intensity_scales_only_the_part_above_mu(gain):
    # mu + gain (1 - mu) I^gamma: at 0.25 with mu = 0.33, gamma = 0.7:
    # 0.33 + gain * 0.67 * 0.25^0.7 = 0.33 + gain * 0.67 * 0.37893...
    out = tc.correct([0.0, 0.25, 1.0], mu=0.33, gamma=0.7, gain=gain)
    assert out[0] == 0.0
    assert out[1] == pytest.approx(0.33 + gain * 0.67 * 0.25**0.7, abs=1e-15)
    assert out[2] == pytest.approx(0.33 + gain * 0.67, abs=1e-15)
    assert (out[1:] >= 0.33).all()  # no lit tactor below the threshold


def test_master_intensity_on_the_live_path_keeps_lit_tactors_at_or_above_mu():
    scene = Scene(tc.Circle((2.5, 3.0), 2.0), "IM", mu=0.33, gamma=0.7, gain=0.1)
    scene = scene.replace(filter="point")
    live = scene.live(tc.Grid())
    for k in range(0, 750, 7):
        for _, value in live.entries(k):
            assert 0.33 <= value <= 0.33 + 0.1 * 0.67 + 1e-12


def test_quantize_extremes():
    levels = tc.quantize(tc.correct(EXTREME_I, mu=0.0, gamma=1.0), levels=23)
    # floor(I * 22 + 0.5): 0.25 -> 6, 0.5 -> 11, 1 - 1e-12 -> 22
    assert levels.tolist() == [0, 0, 0, 6, 11, 22, 22]
    assert tc.quantize([1.0], levels=2).tolist() == [1]
    assert tc.quantize([0.5 - 1e-12, 0.5], levels=256).tolist() == [127, 128]


# --- points on edges, corners and centres ----------------------------------------------------


def test_point_exactly_on_a_column_edge():
    frames = {m: tc.render_xy(m, 3.0, 2.5) for m in ("CT", "AS")}
    assert lit(frames["CT"]) == {(3, 2): 1.0}  # tie -> right
    assert lit(frames["AS"]) == {(2, 2): 0.5, (3, 2): 0.5}


def test_point_exactly_on_a_cell_corner():
    assert lit(tc.render_xy("CT", 1.0, 4.0)) == {(1, 4): 1.0}  # tie -> upper right
    assert lit(tc.render_xy("AS", 1.0, 4.0)) == {
        (0, 3): 0.25,
        (1, 3): 0.25,
        (0, 4): 0.25,
        (1, 4): 0.25,
    }


NOISY_X = [0.3 / 0.1 - 0.5, 2.1 / 0.6 - 1.0]  # 2.4999999999999996, 2.5000000000000004
NOISY_Y = [0.7 / 0.2, 2.1 / 0.6]  # 3.4999999999999996, 3.5000000000000004


@pytest.mark.parametrize("x", NOISY_X)
@pytest.mark.parametrize("y", NOISY_Y)
def test_tactor_centre_reached_through_float_noise_lights_one_tactor(x, y):
    assert x != 2.5 and y != 3.5  # the noise is really there
    with np.errstate(over="raise", divide="raise", invalid="raise"):
        raw = tc.render_xy("AS", x, y)
        corrected = tc.correct(raw, mu=0.33, gamma=0.7)
    assert lit(corrected) == {(2, 3): 1.0}  # no neighbour at mu
    entries = tc.render_point(tc.Line((x, y), (x, y)), "AS", 0.0)
    assert entries == ((3 * 5 + 2, 1.0),)
    line = tc.Line((x - 2.0, y), (x + 2.0, y))  # IM, halfway: at the noisy centre
    assert lit(tc.correct(tc.render(line, "IM", 0.5), mu=0.33, gamma=0.7)) == {(2, 3): 1.0}


def test_cell_edge_reached_through_float_noise_breaks_the_tie_the_same_way():
    x = 0.3 / 0.1  # 2.9999999999999996
    below = 3.0 - 4e-16
    assert x != 3.0
    for px in (x, below, 3.0):
        assert lit(tc.render_xy("CT", px, 0.5)) == {(3, 0): 1.0}


# --- lines -----------------------------------------------------------------------------------


def test_zero_length_line_lights_the_point_cell():
    frames = render_all(tc.Line((2.3, 4.7), (2.3, 4.7)))
    for method in ("CT", "MM", "IM"):
        assert all(lit(f) == {(2, 4): 1.0} for f in frames[method]), method
    # box [1.8, 2.8] x [4.2, 5.2]: columns 1 and 2 by 0.2 and 0.8, rows 4 and 5 by 0.8 and 0.2
    expected = {(1, 4): 0.2 * 0.8, (2, 4): 0.8 * 0.8, (1, 5): 0.2 * 0.2, (2, 5): 0.8 * 0.2}
    assert lit(frames["AS"][0]) == pytest.approx(expected)


def test_zero_length_line_at_a_tactor_centre():
    frames = render_all(tc.Line((1.5, 2.5), (1.5, 2.5)))
    for method, f in frames.items():
        assert all(lit(x) == {(1, 2): 1.0} for x in f), method


def test_vertical_line_one_tactor_per_row():
    frames = render_all(tc.Line((3.2, 0.5), (3.2, 5.5)))
    assert {c for f in frames["MM"] for c in lit(f)} == {(3, r) for r in range(6)}
    np.testing.assert_allclose(frames["IM"].sum(axis=(1, 2)), 1.0, atol=1e-12)


def test_horizontal_line_one_tactor_per_column():
    frames = render_all(tc.Line((4.5, 2.9), (0.5, 2.9)))
    assert {c for f in frames["MM"] for c in lit(f)} == {(c, 2) for c in range(5)}
    assert {c for f in frames["CT"] for c in lit(f)} == {(c, 2) for c in range(5)}


@pytest.mark.parametrize("sign", [1, -1])
def test_diagonal_lines_at_45_degrees_are_x_major(sign):
    start = (0.5, 2.5 - 2 * sign)
    end = (4.5, 2.5 + 2 * sign)
    frames = render_all(tc.Line(start, end))
    expected = {(c, int(2 - 2 * sign + sign * c)) for c in range(5)}
    assert {c for f in frames["MM"] for c in lit(f)} == expected
    np.testing.assert_allclose(frames["IM"].sum(axis=(1, 2)), 1.0, atol=1e-12)


def test_line_exactly_on_a_row_boundary():
    frames = render_all(tc.Line((0.5, 3.0), (4.5, 3.0)))
    for method in ("CT", "MM", "IM"):
        assert {cell[1] for f in frames[method] for cell in lit(f)} == {3}, method  # tie: up
    mid = lit(frames["AS"][500])  # x = 2.5
    assert mid == {(2, 2): 0.5, (2, 3): 0.5}


def test_line_exactly_on_a_column_boundary():
    frames = render_all(tc.Line((2.0, 0.5), (2.0, 5.5)))
    for method in ("CT", "MM", "IM"):
        assert {cell[0] for f in frames[method] for cell in lit(f)} == {2}, method  # tie: right


# --- circles ---------------------------------------------------------------------------------


@pytest.mark.parametrize("radius", [0.0, 5e-324, 1e-300, 1e-12, 1e-3])
def test_tiny_circle_inside_one_cell(radius):
    frames = render_all(tc.Circle((2.5, 3.5), radius))
    for method in ("CT", "MM", "IM"):
        assert all(lit(f) == {(2, 3): 1.0} for f in frames[method]), method
    # The box never moves more than r from the centre: the centre tactor keeps (1 - r)^2.
    assert (frames["AS"][:, 3, 2] >= (1 - radius) ** 2 - 1e-12).all()
    np.testing.assert_allclose(frames["AS"].sum(axis=(1, 2)), 1.0, atol=1e-12)


def test_tiny_circle_around_a_cell_corner():
    # Column centres fall outside the circle: MM clamps them to the arcs' ends.
    frames = render_all(tc.Circle((2.0, 3.0), 0.3))
    for method in ("MM", "CT"):
        assert ((frames[method] > 0).sum(axis=(1, 2)) == 1).all()
    assert {c for f in frames["MM"] for c in lit(f)} == {(1, 2), (2, 2), (1, 3), (2, 3)}
    np.testing.assert_allclose(frames["IM"].sum(axis=(1, 2)), 1.0, atol=1e-12)


@pytest.mark.parametrize("radius", [1e3, 1e5, 5e5])
def test_huge_circle_through_the_grid(radius):
    # Centred below the grid so that its top passes through (2.5, 3.0) (to rounding).
    frames = render_all(tc.Circle((2.5, 3.0 - radius), radius), t=np.linspace(0.2499, 0.2501, 201))
    assert frames["MM"].sum(axis=(1, 2)).max() == 1.0
    np.testing.assert_allclose(frames["IM"].sum(axis=(1, 2))[100], 1.0, atol=1e-9)


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: tc.Circle((2.5, 3.0 - 1e9), 1e9), "center[1]"),
        (lambda: tc.Circle((2.5, 3.0), 1e300), "radius"),
        (lambda: tc.Square((2.5, 3.0), 1e308), "edge"),
        (lambda: tc.Line((-1e308, 0), (1e308, 0)), "p0[0]"),
        (lambda: tc.Polyline([(0, 0), (1e308, 0), (0, 1e308)], closed=True), "points[1][0]"),
    ],
)
def test_coordinates_beyond_a_million_grid_units_are_refused(make, field):
    with pytest.raises(ValueError, match=re.escape(field) + " must be within"):
        make()


# --- far away --------------------------------------------------------------------------------


def test_coordinates_near_the_bound():
    far = 9.99e5
    frames = render_all(tc.Line((far, far + 0.25), (far + 3.0, far + 1.75)))
    for f in frames.values():
        assert not f.any()  # entirely outside the array
    big = tc.Grid(cols=3, rows=3)
    line = tc.Line((0.5, 1.5), (far, 1.5))  # starts inside, leaves for a million units
    t = np.array([0.0, 1e-7, 2e-7, 0.5, 1.0])
    frames = render_all(line, t=t, grid=big)
    assert lit(frames["MM"][0]) == {(0, 1): 1.0}
    assert not frames["AS"][3].any()


def test_negative_coordinates_outside_the_grid_are_dropped():
    frames = render_all(tc.Circle((-3.0, -3.0), 1.0))
    assert not any(f.any() for f in frames.values())


# --- bad input -------------------------------------------------------------------------------


LINE = tc.Line((0.5, 1.0), (4.5, 2.0))


@pytest.mark.parametrize(
    ("call", "word"),
    [
        (lambda: tc.Line((float("nan"), 0), (1, 1)), "p0"),
        (lambda: tc.Line((0, 0), (1, float("inf"))), "p1"),
        (lambda: tc.Circle((0, 0), float("nan")), "radius"),
        (lambda: tc.Circle((0, 0), -1.0), "radius"),
        (lambda: tc.Square((0, float("-inf")), 1.0), "center"),
        (lambda: tc.Polyline([(0, 0)]), "points"),
        (lambda: tc.render(LINE, "AS", [0.5, 1.5]), "t"),
        (lambda: tc.render(LINE, "AS", [-1e-12]), "t"),
        (lambda: tc.render(LINE, "AS", float("nan")), "t"),
        (lambda: tc.render(LINE, "AS", [0.2, float("inf")]), "t"),
        (lambda: tc.render(LINE, "XX", 0.5), "method"),
        (lambda: tc.render(LINE, None, 0.5), "method"),
        (lambda: tc.render(LINE, "AS", 0.5, grid=tc.Grid(cols=0, rows=6)), "grid"),
        (lambda: tc.render(LINE, "AS", 0.5, grid=(5, 6)), "grid"),
        (lambda: tc.render("line", "AS", 0.5), "shape"),
        (lambda: tc.correct([0.5], mu=1.5, gamma=1.0), "mu"),
        (lambda: tc.correct([0.5], mu=-0.1, gamma=1.0), "mu"),
        (lambda: tc.correct([0.5], mu=float("nan"), gamma=1.0), "mu"),
        (lambda: tc.correct([0.5], mu=0.3, gamma=0.0), "gamma"),
        (lambda: tc.correct([0.5], mu=0.3, gamma=-2.0), "gamma"),
        (lambda: tc.correct([0.5], mu=0.3, gamma=float("nan")), "gamma"),
        (lambda: tc.correct([0.5], mu=0.3, gamma=float("inf")), "gamma"),
        (lambda: tc.correct([1.5], mu=0.3, gamma=1.0), "intensity"),
        (lambda: tc.correct([float("nan")], mu=0.3, gamma=1.0), "intensity"),
        (lambda: tc.quantize([0.5], levels=1), "levels"),
        (lambda: tc.quantize([0.5], levels=2.5), "levels"),
        (lambda: tc.render_point(LINE, "AS", 2.0), "t"),
        (lambda: tc.render_point(LINE, "AS", float("nan")), "t"),
    ],
)
def test_bad_input_raises_value_error_naming_the_parameter(call, word):
    with pytest.raises(ValueError, match=word):
        call()


def test_error_message_shows_the_value():
    with pytest.raises(ValueError, match=r"mu must be within \[0, 1\], got 1.5"):
        tc.correct([0.5], mu=1.5, gamma=1.0)
    with pytest.raises(ValueError, match=r"got 1.5 at index 1"):
        tc.render(LINE, "AS", [0.5, 1.5])


def test_empty_parameter_array_gives_no_frames():
    for method in tc.METHOD_NAMES:
        frames = tc.render(tc.Circle((2.5, 3.0), 2.0), method, np.array([]))
        assert frames.shape == (0, 6, 5)
