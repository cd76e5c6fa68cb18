"""Live points (tactile_core.rendering.points): each frame renders the current points with the
scene's method, max per tactor, releases stale points, resamples to the frame rate."""

import threading

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import load_profile
from tactile_core.rendering.geometry import Grid
from tactile_core.rendering.points import FreePoints
from tactile_core.rendering.scene import Scene


class Clock:
    def __init__(self, now=100.0):
        self.now = now

    def __call__(self):
        return self.now


def frame_of(live, size=30):
    out = np.zeros(size)
    for i, v in live.entries(0):
        out[i] = v
    return out


def expected(method, x, y, mu, gamma, gain=1.0, grid=None):
    raw = tc.render_xy(method, x, y, grid=grid or Grid()).reshape(-1)
    return np.where(raw > 0, np.minimum(mu + gain * (1 - mu) * raw**gamma, 1.0), 0.0)


@pytest.mark.parametrize("method", ["CT", "AS", "EN", "PK", "RO:r=1.5", "GS", "VRCH"])
def test_points_one_point_equals_render_xy_corrected(method):
    clock = Clock()
    points = FreePoints(clock=clock)
    live = Scene(method=method, mu=0.33, gamma=0.7, source=points).live(Grid(), 300)
    for x, y in [(1.2, 2.7), (0.5, 0.5), (4.9, 5.9), (2.5, 3.0), (-0.3, 2.0)]:
        points.set("p", x, y)
        np.testing.assert_allclose(frame_of(live), expected(method, x, y, 0.33, 0.7), atol=1e-12)


def test_points_intensity_scales_above_the_threshold_like_the_master_intensity():
    points = FreePoints(clock=Clock())
    live = Scene(method="AS", mu=0.2, gamma=0.5, gain=0.8, source=points).live(Grid(), 300)
    points.set("", 1.5, 1.5, 0.25)  # on the centre of tactor (1, 1): raw 1
    got = frame_of(live)
    assert got[1 * 5 + 1] == pytest.approx(0.2 + 0.8 * 0.25 * 0.8)
    assert np.count_nonzero(got) == 1
    points.set("", 1.5, 1.5, 0.0)  # intensity 0 lights nothing (not mu)
    assert live.entries(1) == ()


def test_points_on_one_tactor_combine_by_max():
    points = FreePoints(clock=Clock())
    live = Scene(method="AS", mu=0.0, gamma=1.0, source=points).live(Grid(), 300)
    points.set("a", 1.5, 1.5, 0.5)  # tactor 6 at 0.5
    points.set("b", 2.0, 1.5, 1.0)  # halfway between tactors 6 and 7: 0.5 each
    points.set("c", 1.5, 1.5, 0.3)  # tactor 6 at 0.3
    got = frame_of(live)
    assert got[6] == pytest.approx(0.5)  # max(0.5, 0.5, 0.3), not the sum 1.3
    assert got[7] == pytest.approx(0.5)
    points.set("b", 2.0, 1.5, 0.2)
    assert frame_of(live)[6] == pytest.approx(0.5)
    assert frame_of(live)[7] == pytest.approx(0.1)


def test_points_stale_point_is_not_rendered_and_expire_counts_it():
    clock = Clock()
    points = FreePoints(clock=clock, timeout_s=0.1)
    live = Scene(method="CT", source=points).live(Grid(), 300)
    points.set("a", 0.5, 0.5)
    clock.now += 0.099
    assert live.entries(0) == ((0, 1.0),)
    points.set("b", 4.5, 5.5)
    clock.now += 0.002  # a is 101 ms old, b 2 ms
    assert live.entries(1) == ((29, 1.0),)
    assert points.expire() == 1
    assert set(points.points) == {"b"}
    clock.now += 1.0
    assert live.entries(2) == ()
    assert points.expire() == 1 and points.points == {}


def test_points_without_timeout_stay_until_released():
    clock = Clock()
    points = FreePoints(clock=clock, timeout_s=None)
    live = Scene(method="CT", source=points).live(Grid(), 300)
    points.set("a", 0.5, 0.5)
    clock.now += 3600
    assert live.entries(0) == ((0, 1.0),) and points.expire() == 0
    assert points.release("a") == 1 and live.entries(1) == ()
    assert points.release("a") == 0


def test_points_newest_update_wins_within_a_frame():
    clock = Clock()
    points = FreePoints(clock=clock)
    live = Scene(method="CT", source=points).live(Grid(), 300)
    for k in range(5):  # five updates between two frames: the frame shows the last
        points.set("a", 0.5 + k, 0.5)
        clock.now += 0.0005
    assert live.entries(0) == ((4, 1.0),)


def test_points_interpolated_move_from_the_previous_update_over_its_interval():
    clock = Clock()
    points = FreePoints(clock=clock, interpolate=True)
    live = Scene(method="AS", mu=0.0, gamma=1.0, source=points).live(Grid(), 300)
    points.set("a", 0.5, 0.5)
    assert frame_of(live)[0] == 1.0  # a new point: where it is
    clock.now += 0.04
    points.set("a", 1.5, 0.5)  # 40 ms later, one pitch to the right
    assert frame_of(live)[0] == pytest.approx(1.0)  # at the update: still at the previous
    clock.now += 0.01  # a quarter of the interval
    np.testing.assert_allclose(frame_of(live)[:2], [0.75, 0.25])
    clock.now += 0.02
    np.testing.assert_allclose(frame_of(live)[:2], [0.25, 0.75])
    clock.now += 0.02  # past the interval: at the newest
    np.testing.assert_allclose(frame_of(live)[:2], [0.0, 1.0])


def test_points_interpolation_skips_a_pause_longer_than_the_timeout():
    clock = Clock()
    points = FreePoints(clock=clock, interpolate=True, timeout_s=0.1)
    live = Scene(method="CT", source=points).live(Grid(), 300)
    points.set("a", 0.5, 0.5)
    clock.now += 0.5  # the sender paused (the point timed out); it comes back elsewhere
    points.set("a", 3.5, 0.5)
    assert live.entries(0) == ((3, 1.0),)


def test_points_box_filter_averages_over_the_frame_period():
    clock = Clock()
    points = FreePoints(clock=clock, interpolate=True)
    scene = Scene(method="AS", mu=0.0, gamma=1.0, source=points, filter="box", subsamples=4)
    live = scene.live(Grid(), 100)  # 10 ms frames; sub-samples 1.25, 3.75, 6.25, 8.75 ms in
    points.set("a", 0.5, 0.5)
    clock.now += 0.01
    points.set("a", 1.5, 0.5)
    clock.now += 0.01  # the frame period just ended spans the whole move
    np.testing.assert_allclose(frame_of(live)[:2], [0.5, 0.5])


def test_points_refuse_methods_that_need_a_shape_naming_the_free_ones():
    points = FreePoints()
    for method in ("IM", "MM"):
        with pytest.raises(ValueError, match=f"method {method} needs a shape.*free points work"):
            Scene(method=method, source=points).live(Grid(), 300)


def test_points_bad_values_are_refused_by_name():
    points = FreePoints(max_points=2)
    for args, name in [((float("nan"), 1.0), "x"), ((1.0, float("inf")), "y"),
                       ((1.0, 1.0, 1.5), "intensity"), ((1e7, 1.0), "x"),
                       ((True, 1.0), "x")]:  # fmt: skip
        with pytest.raises(ValueError, match=f"^{name} must"):
            points.set("a", *args)
    with pytest.raises(ValueError, match="point id"):
        points.set("x" * 65, 1.0, 1.0)
    points.set("a", 1, 1)
    points.set("b", 1, 1)
    points.set("a", 2, 2)  # an existing id moves
    with pytest.raises(ValueError, match="already 2 points"):
        points.set("c", 1, 1)


def test_points_on_a_layout_equal_render_xy_there():
    profile = load_profile("belt-8")
    points = FreePoints(clock=Clock())
    live = Scene(method="GS", mu=0.1, gamma=0.8, source=points).live(profile.layout, 300)
    for x in (0.0, 2.3, 7.9, 8.2):  # across the belt's seam too
        points.set("p", x, 0.0)
        want = expected("GS", x, 0.0, 0.1, 0.8, grid=profile.layout)
        np.testing.assert_allclose(frame_of(live, 8), want, atol=1e-12)


def test_points_cannot_cross_to_a_stream_process():
    import pickle

    with pytest.raises(TypeError, match="process=False"):
        pickle.dumps(Scene(source=FreePoints()))


def test_points_writers_never_disturb_the_reader():
    points = FreePoints(timeout_s=None)
    live = Scene(method="AS", source=points).live(Grid(), 300)
    stop = threading.Event()
    errors = []

    def write(name):
        k = 0
        while not stop.is_set():
            points.set(name, (k % 40) / 8, (k % 48) / 8)
            if k % 7 == 0:
                points.release(name)
            k += 1

    writers = [threading.Thread(target=write, args=(str(i),)) for i in range(3)]
    for w in writers:
        w.start()
    try:
        for k in range(3000):
            for i, v in live.entries(k):
                if not (0 <= i < 30 and 0.0 < v <= 1.0):
                    errors.append((i, v))
    finally:
        stop.set()
        for w in writers:
            w.join(5)
    assert errors == []


def jittered_layout(cols=15, rows=17, seed=255):
    """255 actuators on a jittered lattice (no two rectangles: BA's cells are triangles)."""
    from tactile_core.rendering.layout import Layout

    rng = np.random.default_rng(seed)
    xy = [(c + 0.5 + rng.uniform(-0.2, 0.2), r + 0.5 + rng.uniform(-0.2, 0.2))
          for r in range(rows) for c in range(cols)]  # fmt: skip
    return Layout(xy)


def many_points(target, n, seed, clock):
    """``n`` points anywhere near ``target`` and a few hard ones: on actuators, far away, at
    intensity 0, stale, and with a previous update to interpolate from."""
    rng = np.random.default_rng(seed)
    if isinstance(target, Grid):
        x0, x1, y0, y1 = 0.0, target.cols, 0.0, target.rows
        on = [(c + 0.5, r + 0.5) for c, r in ((0, 0), (2, 3))]
    else:
        x0, x1, y0, y1 = target.bounds(0.0)
        on = [target.positions[0], target.positions[-1]]
    points = FreePoints(timeout_s=0.1, clock=clock, max_points=n + 8)
    for k in range(n):
        x, y = rng.uniform(x0 - 2, x1 + 2), rng.uniform(y0 - 2, y1 + 2)
        points.put(str(k), x - 0.3, y + 0.2, rng.uniform(0, 1), clock.now - 0.05)  # previous
        points.put(str(k), x, y, rng.uniform(0, 1), clock.now - rng.uniform(0, 0.04))
    for k, (x, y) in enumerate(on):
        points.put(f"on{k}", x, y, 1.0, clock.now)
    points.put("far", 1e5, -3e4, 1.0, clock.now)
    points.put("dark", x0 + 0.5, y0 + 0.5, 0.0, clock.now)
    points.put("stale", x0 + 1.0, y0 + 1.0, 1.0, clock.now - 0.5)
    return points


TARGETS = {
    "palm grid": lambda: Grid(),
    "belt-8": lambda: load_profile("belt-8").layout,
    "sleeve-2x6": lambda: load_profile("sleeve-2x6").layout,
    "vest-4x5": lambda: load_profile("vest-4x5").layout,
    "255 jittered": jittered_layout,
}


@pytest.mark.parametrize("interpolate", [False, True])
@pytest.mark.parametrize(
    ("method", "target"),
    [(m, t) for t in TARGETS for m in ("RO", "BA", "PK", "GS", "EN", "VRCH", "RO:r=2.5")]
    + [("AS", "palm grid"), ("CT", "palm grid")],
)
def test_points_many_at_once_equal_one_at_a_time_and_render_xy(method, target, interpolate):
    grid = TARGETS[target]()
    clock = Clock()
    points = many_points(grid, 64, seed=len(target) + len(method), clock=clock)
    points.interpolate = interpolate
    live = Scene(method=method, mu=0.33, gamma=0.7, gain=0.9, source=points).live(grid, 300)
    now = clock.now
    one_by_one, at_once = live.at_each(points.points, now), live.at_many(points.points, now)
    assert set(at_once) == set(one_by_one)
    for i, v in one_by_one.items():
        assert at_once[i] == pytest.approx(v, abs=1e-12)
    # and an independent computation: render_xy's dense frames of the free points, corrected
    # with each point's intensity as the master intensity, max over points
    size = grid.size
    want = np.zeros(size)
    for p in points.points.values():
        age = now - p.time_s
        x, y, a = p.x, p.y, p.intensity
        if age > 0.1:
            continue
        if interpolate and p.previous is not None and age < p.time_s - p.previous[3]:
            f = age / (p.time_s - p.previous[3])
            x, y, a = (q + (v - q) * f for v, q in zip((x, y, a), p.previous[:3]))
        if a > 0:
            want = np.maximum(want, expected(method, x, y, 0.33, 0.7, 0.9 * a, grid).reshape(-1))
    got = np.zeros(size)
    for i, v in at_once.items():
        got[i] = v
    np.testing.assert_allclose(got, want, atol=1e-12)


def test_points_many_points_render_without_a_python_loop_per_point():
    points = many_points(jittered_layout(), 64, seed=1, clock=Clock())
    live = Scene(method="PK", source=points).live(jittered_layout(), 300)
    calls = []
    one = live._entries1
    live._entries1 = lambda *a: calls.append(a) or one(*a)
    assert live.entries(0)  # 64 points on 255 actuators: a handful of numpy calls
    assert calls == []
    points.release()
    points.set("a", 2.0, 3.0)
    assert live.entries(1) and len(calls) == 1  # one point: the scalar path, cheaper there
