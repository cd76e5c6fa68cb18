"""The peer methods (EN, PK, RO, GS): values worked by hand, their defining properties, the live
path against the batch path, and their parameters as specs."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.rendering.methods import PEER_METHODS, gaussian, get_method

GRID = tc.Grid()  # 5 x 6


def coord(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def at(method, x, y, grid=GRID):
    """The frame of one free point, as {(col, row): value} of the lit tactors."""
    frame = tc.render_xy(method, x, y, grid=grid)
    rows, cols = np.nonzero(frame)
    return {(int(c), int(r)): float(frame[r, c]) for r, c in zip(rows, cols)}


def smoothstep(x):
    return x * x * (3 - 2 * x)


# --- worked by hand ------------------------------------------------------------------------------


def test_en_is_the_square_root_of_the_as_areas():
    # A cell corner: AS gives the four tactors around it 1/4 each, EN sqrt(1/4) = 1/2.
    assert at("EN", 2.0, 3.0) == pytest.approx({(1, 2): 0.5, (2, 2): 0.5, (1, 3): 0.5, (2, 3): 0.5})
    # On column 2's centre line, a quarter of the way from row 2's tactor to row 3's:
    # AS 0.75 / 0.25, EN sqrt(0.75) / sqrt(0.25).
    assert at("EN", 2.5, 2.75) == pytest.approx({(2, 2): math.sqrt(0.75), (2, 3): 0.5})
    assert at("EN", 1.5, 2.5) == {(1, 2): 1.0}


def test_pk_is_inverse_distance_over_the_three_nearest():
    # (2.5, 3.0): tactors (2,2) and (2,3) at 0.5; the third nearest ties between (1,3)/(3,3)
    # and (1,2)/(3,2) at sqrt(1.25); the tie goes up and right: (3,3).
    w = {(2, 2): 2.0, (2, 3): 2.0, (3, 3): 1 / math.sqrt(1.25)}
    total = sum(w.values())
    assert at("PK", 2.5, 3.0) == pytest.approx({k: math.sqrt(v / total) for k, v in w.items()})
    # (1.8, 2.6): nearest (1,2) at hypot(0.3, 0.1), then (2,2) at hypot(0.7, 0.1), (1,3) at
    # hypot(0.3, 0.9); (2,3), diagonally opposite the nearest, is left out.
    d = {(1, 2): math.hypot(0.3, 0.1), (2, 2): math.hypot(0.7, 0.1), (1, 3): math.hypot(0.3, 0.9)}
    total = sum(1 / v for v in d.values())
    assert at("PK", 1.8, 2.6) == pytest.approx({k: math.sqrt(1 / v / total) for k, v in d.items()})
    assert at("PK", 3.5, 4.5) == {(3, 4): 1.0}  # on a centre: that tactor alone


def test_ro_is_the_smoothstep_roll_off_within_r():
    corner = smoothstep(1 - math.sqrt(0.5))  # d = 0.707 from each of four tactors
    assert corner == pytest.approx(0.2071, abs=1e-4)
    assert at("RO", 2.0, 3.0) == pytest.approx(dict.fromkeys([(1, 2), (2, 2), (1, 3), (2, 3)],
                                                             corner))  # fmt: skip
    assert at("RO", 2.5, 3.0) == pytest.approx({(2, 2): 0.5, (2, 3): 0.5})  # s(0.5) = 0.5
    assert at("RO", 2.5, 3.5) == {(2, 3): 1.0}  # neighbours at d = 1 = r: off
    # r = 2 on a centre: neighbours at d = 1 get s(1/2), diagonals at sqrt(2) get s(1 - 0.707),
    # tactors 2 away (d = 2 = r) are off.
    wide = at("RO:r=2", 2.5, 3.5)
    assert len(wide) == 9
    assert wide[(2, 3)] == 1.0 and wide[(1, 3)] == pytest.approx(0.5)
    assert wide[(1, 2)] == pytest.approx(smoothstep(1 - math.sqrt(2) / 2))


def test_gs_is_the_gaussian_cut_at_five_percent():
    # sigma 0.5 on a centre: the tactor at 1, its four neighbours at exp(-1 / 0.5) = exp(-2);
    # the diagonals' exp(-4) = 0.018 is below 0.05: off.
    got = at("GS", 2.5, 3.5)
    assert got == pytest.approx({(2, 3): 1.0, (1, 3): math.exp(-2), (3, 3): math.exp(-2),
                                 (2, 2): math.exp(-2), (2, 4): math.exp(-2)})  # fmt: skip
    # Midway between two tactors: both at exp(-0.25 / 0.5); the four at d^2 = 1.25 at
    # exp(-2.5) = 0.082: six tactors.
    got = at("GS", 2.5, 3.0)
    assert got[(2, 2)] == pytest.approx(math.exp(-0.5)) and len(got) == 6
    assert got[(1, 2)] == pytest.approx(math.exp(-2.5))
    narrow = at("GS:sigma=0.25", 2.5, 3.0)  # exp(-0.25 / 0.125) = exp(-2); the rest cut
    assert narrow == pytest.approx({(2, 2): math.exp(-2), (2, 3): math.exp(-2)})


def brute_max(radius, strict):
    """Most lattice points within ``radius`` of a point of a 201 x 201 grid over one cell."""
    f = np.linspace(0, 1, 201)
    px, py = np.meshgrid(f, f)
    k = np.arange(-4, 6)
    d = np.hypot(px[..., None, None] - k[:, None], py[..., None, None] - k[None, :])
    return int(((d < radius) if strict else (d <= radius)).sum(axis=(-1, -2)).max())


def test_max_tactors_is_what_the_method_can_light():
    expected = {"EN": 4, "PK": 3, "RO": 4, "GS": 6,
                "RO:r=2": brute_max(2.0, True),
                "GS:sigma=0.25": brute_max(gaussian.radius(0.25), False)}  # fmt: skip
    assert expected["GS:sigma=0.25"] == 2  # radius 0.61: a cell corner is 0.707 from all four
    for spec, count in expected.items():
        assert get_method(spec).max_tactors == count, spec
    rng = np.random.default_rng(1)
    xy = rng.uniform([0.5, 0.5], [4.5, 5.5], size=(4000, 2))
    for spec, count in expected.items():
        frames = tc.render_xy(spec, xy[:, 0], xy[:, 1], grid=tc.Grid(12, 12))
        assert (frames > 0).sum(axis=(1, 2)).max() <= count, spec


# --- properties ----------------------------------------------------------------------------------

hull = st.tuples(coord(0.5, 4.5), coord(0.5, 5.5))


@given(hull)
def test_en_energy_sums_to_one_inside_the_hull(p):
    frame = tc.render_xy("EN", *p)
    assert float((frame**2).sum()) == pytest.approx(1.0, abs=1e-12)


@given(st.tuples(coord(0.5, 4.4999), coord(0.5, 5.4999)))
def test_pk_lights_at_most_three_with_unit_energy(p):
    frame = tc.render_xy("PK", *p)
    assert (frame > 0).sum() <= 3
    assert float((frame**2).sum()) == pytest.approx(1.0, abs=1e-12)


@given(st.integers(0, 4), st.integers(0, 5))
def test_pk_on_a_centre_lights_that_tactor_alone(col, row):
    assert at("PK", col + 0.5, row + 0.5) == {(col, row): 1.0}


@pytest.mark.parametrize("spec", ["RO", "RO:r=1.7", "GS", "GS:sigma=0.8"])
@given(p=st.tuples(coord(1.5, 3.5), coord(1.5, 4.5)), q=st.tuples(coord(-1, 1), coord(-1, 1)))
def test_ro_and_gs_depend_on_distance_only_and_stay_within_their_radius(spec, p, q):
    method = get_method(spec)
    radius = method.values.get("r") or gaussian.radius(method.values["sigma"])
    frame = tc.render_xy(spec, *p, grid=tc.Grid(12, 12))
    for (col, row), value in np.ndenumerate(frame.T):
        d = math.hypot(col + 0.5 - p[0], row + 0.5 - p[1])
        if value > 0:
            assert d <= radius + 1e-12
        if spec.startswith("RO"):
            expected = smoothstep(1 - d / radius) if d < radius else 0.0
        else:
            w = math.exp(-(d**2) / (2 * method.values["sigma"] ** 2))
            expected = w if w >= 0.05 else 0.0
        assert value == pytest.approx(expected, abs=1e-12)
    # Symmetric: the point mirrored through a tactor centre mirrors the frame.
    centre = (5.5, 5.5)  # tactor (5, 5) of a 12 x 12 grid
    a = (centre[0] + q[0], centre[1] + q[1])
    b = (centre[0] - q[0], centre[1] - q[1])
    fa = tc.render_xy(spec, *a, grid=tc.Grid(12, 12))
    fb = tc.render_xy(spec, *b, grid=tc.Grid(12, 12))
    np.testing.assert_allclose(fa[:11, :11], fb[:11, :11][::-1, ::-1], atol=1e-12)


shapes = st.one_of(
    st.builds(
        tc.Line, st.tuples(coord(-1, 6), coord(-1, 7)), st.tuples(coord(-1, 6), coord(-1, 7))
    ),
    st.builds(tc.Circle, st.tuples(coord(1, 4), coord(1, 5)), coord(0, 2.5)),
    st.builds(tc.Square, st.tuples(coord(1, 4), coord(1, 5)), coord(0, 4)),
)


@given(shapes, st.lists(coord(0, 1), min_size=1, max_size=8),
       st.sampled_from([*PEER_METHODS, "RO:r=1.6", "GS:sigma=0.3", "RO:curve=linear",
                        "PK:blend=0.2", "VRCH:r=1.4"]))  # fmt: skip
def test_live_path_equals_batch(shape, ts, spec):
    batch = tc.render(shape, spec, np.array(ts)).reshape(len(ts), -1)
    for t, row in zip(ts, batch):
        sparse = np.zeros(GRID.size)
        for i, v in tc.render_point(shape, spec, t):
            sparse[i] = v
        np.testing.assert_allclose(sparse, row, atol=1e-15, rtol=0)


@pytest.mark.parametrize("method", PEER_METHODS)
def test_values_stay_in_range_on_every_shape(method):
    t = np.linspace(0, 1, 4001)
    for shape in (tc.Line((-3, -2), (9, 8)), tc.Circle((2.5, 3), 2), tc.Square((2.5, 3.5), 4)):
        frames = tc.render(shape, method, t)
        assert frames.min() >= 0.0 and frames.max() <= 1.0
        assert np.isfinite(frames).all()


# --- parameters travel as specs ------------------------------------------------------------------


def test_specs_are_canonical_and_validated():
    assert get_method("ro").spec == "RO" and get_method("RO:r=1.0").spec == "RO"
    assert get_method("RO:r=1.5").spec == "RO:r=1.5"
    assert get_method("GS", sigma=0.7).spec == "GS:sigma=0.7"
    assert get_method("RO:r=0.3").values == {"r": 0.3, "curve": "smoothstep"}
    for bad, message in [
        ("RO:r=0", "method RO: r must be within"),
        ("RO:radius=1", "method RO has no parameter 'radius'"),
        ("AS:r=1", "method AS has no parameter 'r'"),
        ("RO:r", "NAME:param=value"),
        ("RO:r=nan", "method RO: r must be finite"),
        ("RO:r=1,r=2", "method RO: r is given twice"),
        ("ZZ", "got 'ZZ'"),
    ]:
        with pytest.raises(ValueError, match=message):
            get_method(bad)


def test_a_scene_and_a_preset_keep_the_parameters(tmp_path):
    from tactile_core.files.presets import Preset, load_preset, save_preset
    from tactile_core.rendering.scene import Scene

    scene = Scene(tc.Circle((2.5, 3), 2), "ro:r=1.50")
    assert scene.method == "RO:r=1.5"
    path = save_preset(Preset(scene, name="wide roll-off"), tmp_path / "p.json")
    assert load_preset(path).scene.method == "RO:r=1.5"
    frames = tc.render(scene.shape, scene.method, np.linspace(0, 1, 11))
    assert (frames > 0).sum(axis=(1, 2)).max() > 4  # r = 1.5 reaches beyond AS's four


def test_cli_renders_a_peer_method_with_its_parameter(tmp_path):
    from tactile_core.cli import main

    out = tmp_path / "ro.npz"
    assert main(["render", "--shape", "circle:2.5,3,2", "--method", "RO:r=1.5", "--mu", "0",
                 "--gamma", "1", "--rate", "100", "--out", str(out)]) == 0  # fmt: skip
    data = np.load(out)
    t = data["time"] / 2.0  # a 2 s trace
    np.testing.assert_allclose(data["frames"], tc.render(tc.Circle((2.5, 3), 2), "RO:r=1.5", t),
                               atol=1e-12)  # fmt: skip
    assert not np.allclose(data["frames"], tc.render(tc.Circle((2.5, 3), 2), "RO", t))
