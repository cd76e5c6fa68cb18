"""Fuzzing every way in: presets, device profiles, session files, shape strings, the command
line and the wire receiver. The property everywhere: a clean refusal (the loader's own error,
or the CLI's one-line error and status 2) or a valid result whose output stays within [0, 1];
never another exception, never a hang.

Hypothesis keeps these bounded (120 examples each; the deadline is off because the first call
of a shape builds its tables); ``FUZZ_EXAMPLES=5000`` runs many more.
"""

import copy
import json
import math
import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core._shared.assets import asset_path
from tactile_core.cli import main as cli
from tactile_core.device.array import ArrayModel
from tactile_core.device.profile import ProfileError, load_profile
from tactile_core.device.wire import encode_frame
from tactile_core.experiments import RUNNERS, open_session
from tactile_core.experiments.results import SessionError
from tactile_core.files.presets import PresetError, load_preset
from tactile_core.rendering.methods import PEER_METHODS

FUZZ = settings(
    max_examples=int(os.environ.get("FUZZ_EXAMPLES", "120")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)

# JSON values of every kind, the awkward ones included.
scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**30), 10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([1e308, -1e308, 5e-324, 0.0, -0.0, 2.5, 1e6, 1e6 + 1, 22, 23, 256]),
    st.text(max_size=20),
    st.sampled_from(["1_0", "25", "false", "nan", "/dev/zero", "palm-5x6", "", "AS"]),
)
json_values = st.recursive(
    scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=6), st.dictionaries(st.text(max_size=8), inner, max_size=5)
    ),
    max_leaves=20,
)


def mutate(draw, document: dict) -> dict:
    """A copy of ``document`` with a few fields (at any depth) replaced, deleted or added."""
    doc = copy.deepcopy(document)
    for _ in range(draw(st.integers(1, 4))):
        path, node = [], doc
        while isinstance(node, (dict, list)) and node and draw(st.booleans()):
            key = draw(
                st.sampled_from(sorted(node) if isinstance(node, dict) else range(len(node)))
            )
            path.append((node, key))
            node = node[key]
        if not path:
            parent, key = doc, draw(st.sampled_from([*sorted(doc), "extra"]))
        else:
            parent, key = path[-1]
        action = draw(st.sampled_from(["replace", "delete", "replace"]))
        if action == "delete" and isinstance(parent, dict) and key in parent:
            del parent[key]
        elif isinstance(parent, list):
            parent[key] = draw(json_values)
        else:
            parent[key] = draw(json_values)
    return doc


@st.composite
def mutated(draw, document):
    return mutate(draw, document)


def write(tmp_path, name, data) -> str:
    path = tmp_path / name
    path.write_text(json.dumps(data, allow_nan=True), encoding="utf-8")
    return str(path)


def check_frames(frames):
    assert np.isfinite(frames).all()
    assert (frames >= 0).all() and (frames <= 1).all()


PRESET = json.loads(asset_path("presets", "exp3-square.json").read_text())
PROFILE = json.loads(asset_path("devices", "palm-5x6.json").read_text())


@FUZZ
@given(mutated(PRESET))
def test_fuzz_presets(tmp_path, data):
    path = write(tmp_path, "p.json", data)
    try:
        preset = load_preset(path)
    except PresetError as exc:
        assert path in str(exc) and len(str(exc)) < 600
        return
    scene = preset.scene
    t = np.linspace(0, 1, 33)
    frames = tc.correct(tc.render(scene.shape, scene.method, t), scene.mu, scene.gamma)
    check_frames(frames)
    live = scene.live(tc.Grid())
    for k in range(0, 60, 7):
        assert all(0 <= v <= 1 for _, v in live.entries(k))


@FUZZ
@given(mutated(PROFILE))
def test_fuzz_profiles(tmp_path, data):
    path = write(tmp_path, "d.json", data)
    try:
        profile = load_profile(path)
    except ProfileError as exc:
        assert path in str(exc) and len(str(exc)) < 600
        return
    assert sorted(profile.array.channels) == list(range(profile.channels))
    assert 9600 <= profile.baud <= 4_000_000 and profile.max_rate_hz >= 10
    if profile.offset is not None:
        flat = profile.calibrate(np.linspace(0, 1, profile.channels))
        check_frames(flat)
    check_frames(profile.felt(np.linspace(0, 1, 11)))


@FUZZ
@given(st.data())
def test_fuzz_session_files(tmp_path_factory, data):
    root = tmp_path_factory.mktemp("results")
    session = open_session(root, "fz01", seed=3)
    original = json.loads(session.path.read_text())
    broken = data.draw(mutated(original))
    session.path.write_text(json.dumps(broken, allow_nan=True))
    try:
        resumed = open_session(root, "fz01")
        for name in ("exp1", "exp2", "exp3"):
            runner = RUNNERS[name](resumed)
            assert runner.current is not None
            runner.close()
    except SessionError as exc:
        assert "session.json" in str(exc)
    except ValueError as exc:  # e.g. an order the runner cannot use, named
        assert str(exc)


shape_text = st.one_of(
    st.text(max_size=40),
    st.builds(
        lambda kind, nums: f"{kind}:" + ",".join(nums),
        st.sampled_from(["line", "circle", "square", "polyline", "polygon", "LINE", "blob"]),
        st.lists(
            st.one_of(
                st.floats(-1e7, 1e7, allow_nan=False).map(repr),
                st.sampled_from(["1e308", "-1e308", "nan", "inf", "1_0", "", " 2 ", "0x10", "2.5"]),
            ),
            max_size=9,
        ),
    ),
)


@FUZZ
@given(shape_text, st.lists(st.floats(0, 1), min_size=1, max_size=12))
def test_fuzz_shape_strings(text, ts):
    try:
        shape = tc.parse_shape(text)
    except ValueError as exc:
        assert len(str(exc)) < 300
        return
    t = np.array(ts)
    for method in (*tc.METHOD_NAMES, *PEER_METHODS):
        check_frames(tc.render(shape, method, t))
        for value in ts[:3]:
            assert all(0 <= v <= 1 for _, v in tc.render_point(shape, method, value))


spec_text = st.one_of(
    st.text(max_size=30),
    st.builds(
        lambda name, key, value, more: f"{name}:{key}={value}{more}",
        st.sampled_from(["RO", "GS", "ro", "gs", "AS", "EN", "PK", "X"]),
        st.sampled_from(["r", "sigma", "R", "", "r ", "level"]),
        st.one_of(
            st.floats(allow_nan=True, allow_infinity=True).map(repr),
            st.sampled_from(["1e308", "-1", "0", "1_0", "abc", "", "0.1", "10", "5"]),
        ),
        st.sampled_from(["", ",r=1", ",", ":", ",sigma=2"]),
    ),
)


@FUZZ
@given(spec_text, st.sampled_from([tc.Circle((2.5, 3), 2), tc.Line((-2, -1), (8, 9))]))
def test_fuzz_method_specs(text, shape):
    """A method spec is a method with valid parameters, or a ValueError naming the method."""
    from tactile_core.rendering.methods import get_method

    try:
        method = get_method(text)
    except ValueError as exc:
        assert "method" in str(exc) and len(str(exc)) < 300
        return
    assert get_method(method.spec) == method  # the canonical spec reads back as itself
    t = np.linspace(0, 1, 33)
    frames = tc.render(shape, method.spec, t)
    check_frames(frames)
    assert (frames > 0).sum(axis=(1, 2)).max() <= method.max_tactors


numbers_text = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["1e308", "1e9", "-1", "0", "nan", "1_0", "abc", "", "2", "300", "0.001"]),
)


@FUZZ
@given(
    shape_text,
    st.sampled_from(["CT", "MM", "AS", "IM", "EN", "PK", "RO:r=2", "GS:sigma=nan", "xx", ""]),
    numbers_text,
    numbers_text,
    numbers_text,
    numbers_text,
)
def test_fuzz_cli_render(tmp_path, capsys, shape, method, mu, gamma, duration, rate):
    out = tmp_path / "frames.npz"
    argv = ["render", "--shape", shape, "--method", method, "--mu", mu, "--gamma", gamma,
            "--duration", duration, "--rate", rate, "--out", str(out)]  # fmt: skip
    try:
        code = cli(argv)
    except SystemExit as exc:  # argparse refuses a value it cannot parse as a number: status 2
        code = exc.code
    err = capsys.readouterr().err
    assert code in (0, 2), err
    if code == 2:  # one error line (after argparse's usage, for what argparse refuses)
        assert "Traceback" not in err
        assert err.strip().splitlines()[-1].startswith("tactile render: error: ")
    else:
        with np.load(out) as data:
            check_frames(data["frames"])
        out.unlink()


good_shapes = st.sampled_from(["circle:2.5,3,2", "line:0.5,1.84,4.5,4.16", "square:2.5,3.5,4"])


@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.one_of(good_shapes, shape_text), numbers_text, numbers_text, numbers_text)
def test_fuzz_cli_stream(capsys, shape, pause, rate, seconds):
    argv = ["stream", "--device", "sim", "--shape", shape, "--method", "AS", "--pause", pause,
            "--rate", rate, "--seconds", seconds]  # fmt: skip
    try:
        finite = math.isfinite(float(seconds))
    except ValueError:
        finite = False
    if finite and float(seconds) > 0.2:
        argv[-1] = "0.2"  # keep each example short
    try:
        code = cli(argv)
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    assert code in (0, 2), out.err
    assert "Traceback" not in out.err
    if code == 0:
        assert "all off" in out.out


@FUZZ
@given(st.binary(max_size=400), st.integers(0, 36), st.integers(0, 7))
def test_fuzz_wire_receiver(noise, index, bit):
    model = ArrayModel()
    good = list(range(23)) + [0] * 7
    model.receive(encode_frame(1, good), 0.0)
    frame = bytearray(encode_frame(2, [22] * 30))
    frame[index % (len(frame) - 1)] ^= 1 << bit  # one flipped bit, the delimiter kept
    _, applied = model.receive(noise + b"\x00" + bytes(frame), 0.0)
    for f in applied:
        assert len(f.levels) == 30 and max(f.levels) < 23
    assert all(f.levels != bytes([22] * 30) or f.seq != 2 for f in applied)
    assert model.dropped >= 1 or applied
