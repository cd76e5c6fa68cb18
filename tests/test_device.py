"""Device profiles: the bundled palm array, validation messages, calibration, fuzzing."""

import copy
import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tactile_core.device.profile import (
    ProfileError,
    default_profile,
    load_profile,
    profile_from_dict,
)


def palm_dict():
    return default_profile().to_dict()


def test_bundled_palm_profile_is_the_papers_array():
    p = default_profile()
    assert (p.layout.cols, p.layout.rows) == (5, 6)
    assert p.array.pitch_mm == 18.0 and p.levels == 23 and p.baud == 115200
    assert p.array.channels == tuple(range(30))  # channel = row * cols + col
    assert p.frame_bytes == 37
    assert p.max_rate_hz == pytest.approx(115200 / 10 / 37)  # 311 frames/s
    assert p.response is not None and not p.calibrated


def test_response_curve_has_no_output_below_0_2_and_is_steepest_at_0_2_to_0_4():
    p = default_profile()
    drive = np.linspace(0, 1, 101)
    out = p.felt(drive)
    assert (out[drive <= 0.2] == 0).all()
    slope = np.gradient(out, drive)
    assert 0.2 <= drive[np.argmax(slope)] <= 0.4
    assert out[-1] == 1.0 and (np.diff(out) >= 0).all()


def test_profile_round_trips_through_json(tmp_path):
    p = default_profile().with_calibration(np.linspace(-0.1, 0.1, 30), np.linspace(0.8, 1.2, 30))
    path = p.save(tmp_path / "mine.json")
    q = load_profile(path)
    assert q == p
    np.testing.assert_allclose(q.offset, p.offset)
    np.testing.assert_allclose(q.gain, p.gain)
    assert q.path == str(path)


def test_calibration_maps_lit_intensities_and_keeps_zero():
    offset = np.zeros(30)
    gain = np.ones(30)
    offset[7], gain[7] = 0.1, 0.5
    p = default_profile().with_calibration(offset, gain)
    frame = np.zeros(30)
    frame[7] = 0.6
    frame[8] = 0.6
    out = p.calibrate(frame)
    assert out[7] == pytest.approx(0.1 + 0.5 * 0.6)
    assert out[8] == 0.6  # identity elsewhere
    assert out[0] == 0.0  # zero stays zero, even with an offset
    p2 = default_profile().with_calibration(np.full(30, 0.5), np.full(30, 2.0))
    assert p2.calibrate(np.full(30, 0.9)).max() == 1.0  # clipped


def test_column_major_and_explicit_channel_orders():
    data = palm_dict()
    data["channel_order"] = "column-major"
    p = profile_from_dict(data)
    assert p.array.channels[:7] == (0, 5, 10, 15, 20, 25, 1)  # channel 1 drives cell (0, 1)
    data["channel_order"] = list(reversed(range(30)))
    assert profile_from_dict(data).array.channels[0] == 29


def mutate(data, path, value):
    data = copy.deepcopy(data)
    target = data
    for key in path[:-1]:
        target = target[key]
    if value is KeyError:
        del target[path[-1]]
    else:
        target[path[-1]] = value
    return data


@pytest.mark.parametrize(
    ("path", "value", "words"),
    [
        (("format",), "other", "'format'"),
        (("version",), 2, "newer"),
        (("version",), "1", "'version'"),
        (("columns",), KeyError, "'columns' is missing"),
        (("columns",), 0, "'columns'"),
        (("rows",), 2.5, "'rows' must be an integer"),
        (("levels",), 300, "'levels' must be 2..256"),
        (("levels",), True, "'levels'"),
        (("pitch_mm",), -18, "'pitch_mm' must be > 0"),
        (("pitch_mm",), float("nan"), "'pitch_mm'"),
        (("baud",), 0, "'baud'"),
        (("channel_order",), [0] * 30, "'channel_order' must list each"),
        (("channel_order",), "diagonal", "'channel_order'"),
        (("response", "drive"), [0, 0.5, 0.4, 1.0, 1.0, 1.0, 1.0], "increase strictly"),
        (("response", "output"), [0, 0, 0.3, 2.0, 1, 1, 1], "non-decreasing within [0, 1]"),
        (("response", "output"), [0, 1], "same length"),
        (("response",), [1, 2], "'response' must be an object"),
        (("name",), "", "'name'"),
    ],
)
def test_bad_fields_are_named(path, value, words):
    with pytest.raises(ProfileError, match=None) as info:
        profile_from_dict(mutate(palm_dict(), path, value), source="my.json")
    message = str(info.value)
    assert message.startswith("my.json: ") and words in message, message


def test_bad_calibration_is_named():
    data = palm_dict()
    data["calibration"] = {"offset": [0.0] * 29, "gain": [1.0] * 30}
    with pytest.raises(ProfileError, match=r"'calibration\.offset' must hold 30 values"):
        profile_from_dict(data)
    data["calibration"] = {"offset": [0.0] * 30, "gain": [0.0] * 30}
    with pytest.raises(ProfileError, match=r"'calibration\.gain'"):
        profile_from_dict(data)
    data["calibration"] = {"offset": [[0.0] * 5] * 6, "gain": [[1.0] * 5] * 6}  # rows form
    assert profile_from_dict(data).calibrated


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("{", "not valid JSON"),
        ("[1, 2]", "must be a JSON object"),
        ("[" * 100_000 + "]" * 100_000, "nested too deeply"),
        ('{"format": "tactile-device-profile", "version": 1, "columns": 1e999}', "'columns'"),
    ],
)
def test_unreadable_files_say_why(tmp_path, text, words):
    path = tmp_path / "p.json"
    path.write_text(text)
    with pytest.raises(ProfileError, match=words):
        load_profile(path)


def test_missing_file_and_unknown_bundled_name():
    with pytest.raises(ProfileError, match="no such"):
        load_profile("/nonexistent/profile.json")
    with pytest.raises(ProfileError, match="no such profile"):
        load_profile("not-a-bundled-profile")


json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
    lambda children: (
        st.lists(children, max_size=6) | st.dictionaries(st.text(max_size=8), children, max_size=6)
    ),
    max_leaves=30,
)


@given(
    st.dictionaries(st.sampled_from([*sorted(palm_dict()), "calibration", "extra"]), json_values)
)
def test_fuzzed_profiles_never_crash_the_loader(overrides):
    data = {**palm_dict(), **overrides}
    try:
        profile = profile_from_dict(data)
    except ProfileError:
        return
    assert profile.layout.size == len(profile.array.channels)


@given(json_values)
def test_arbitrary_json_never_crashes_the_loader(value):
    try:
        profile_from_dict(value)
    except ProfileError:
        pass


@given(st.binary(max_size=200))
def test_arbitrary_bytes_on_disk_never_crash_the_loader(tmp_path_factory, blob):
    path = tmp_path_factory.mktemp("fuzz") / "p.json"
    path.write_bytes(blob)
    with pytest.raises(ProfileError):
        load_profile(path)


def test_bundled_file_is_valid_json_with_a_version():
    from tactile_core._shared.assets import asset_path

    data = json.loads(asset_path("devices", "palm-5x6.json").read_text())
    assert data["version"] == 1 and data["format"] == "tactile-device-profile"
