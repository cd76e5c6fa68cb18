"""Preset files: a bad field is refused naming the file and the field in a short message; what a
writer other than this tool puts in a good file (a byte order mark, a version written 1.0) is
read; a preset that would not load back is never written."""

import json

import pytest

from tactile_core._shared.assets import asset_path
from tactile_core.files.presets import (
    MAX_NAME_CHARS,
    Preset,
    PresetError,
    load_preset,
    preset_from_dict,
    save_preset,
)

PRESET = json.loads(asset_path("presets", "exp3-square.json").read_text())


def write_json(tmp_path, name, data):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return path


def timed_preset(**shape_fields):
    shape = {"type": "timed_path", "points": [[1, 2], [2, 3]], "times_s": [0, 1], **shape_fields}
    return {"format": "tactile-preset", "version": 1, "method": "AS", "mu": 0.3, "gamma": 0.7,
            "shape": shape}  # fmt: skip


@pytest.mark.parametrize(
    ("change", "word"),
    [
        ({"shape": {"type": []}}, "shape.type"),
        ({"shape": {"type": "square", "center": [2.5, 3.5], "edge": 1e308}}, "edge"),
        ({"shape": {"type": "circle", "center": [2.5, 3.5], "radius": "1_0"}}, "radius"),
        ({"shape": {"type": "circle", "center": "25", "radius": 1.0}}, "center"),
        ({"shape": {"type": "polyline", "points": [[0, 0], [1, 1]], "closed": "false"}}, "closed"),
        ({"device_profile": "/dev/zero"}, "device_profile"),
        ({"device_profile": "../../etc/passwd.json"}, "device_profile"),
        ({"mu": "0.5"}, "mu"),
        ({"dither": 1}, "dither"),
        ({"name": "x" * 100_000}, "name"),
    ],
)
def test_bad_presets_are_refused_naming_the_field(tmp_path, change, word):
    path = write_json(tmp_path, "p.json", {**PRESET, **change})
    with pytest.raises(PresetError) as info:
        load_preset(path)
    message = str(info.value)
    assert word in message and str(path) in message and len(message) < 400


def test_a_4300_digit_integer_is_a_preset_error(tmp_path):
    # Python refuses to convert integers of more than 4300 digits with a ValueError of its own
    text = json.dumps(PRESET).replace('"mu": 0.33', '"mu": ' + "9" * 5000)
    with pytest.raises(PresetError, match="not valid JSON"):
        load_preset(write_json(tmp_path, "p.json", text))


def test_a_preset_with_a_square_reaching_past_the_bound_is_refused(tmp_path):
    preset = json.loads(asset_path("presets", "exp3-square.json").read_text())
    preset["shape"] = {"type": "square", "center": [2.5, 999999], "edge": 10}
    (tmp_path / "far.json").write_text(json.dumps(preset))
    with pytest.raises(PresetError, match=r"edge 10\.0 takes the square to 1000004"):
        load_preset(tmp_path / "far.json")


@pytest.mark.parametrize("value", [None, 5, True])
def test_a_time_keyed_paths_intensities_of_the_wrong_type_are_named(value):
    # "intensities": null raised TypeError (no len()) out of the tuner's slot and the CLI.
    with pytest.raises(PresetError, match=r"shape\.intensities must be a list of 2 numbers"):
        preset_from_dict(timed_preset(intensities=value))


def test_an_empty_intensities_list_still_means_full_intensity():
    preset = preset_from_dict(timed_preset(intensities=[]))
    assert preset.scene.shape.intensities == (1.0, 1.0)


def test_a_preset_that_would_not_load_back_is_not_written(tmp_path):
    # the tuner wrote such files ("saved"), and then could not open them
    path = tmp_path / "p.json"
    good = preset_from_dict(timed_preset())
    for bad in (Preset(good.scene, notes="n" * 10_001), Preset(good.scene, name="x" * 201),
                Preset(good.scene.replace(shape=None))):  # fmt: skip
        with pytest.raises(PresetError):
            save_preset(bad, path)
        assert not path.exists() and list(tmp_path.iterdir()) == []
    save_preset(Preset(good.scene, name="x" * MAX_NAME_CHARS, notes="n" * 10_000), path)
    assert load_preset(path).name == "x" * MAX_NAME_CHARS


def test_a_preset_saved_with_a_byte_order_mark_opens(tmp_path):
    # Windows' Notepad writes one; .tact files were read past it, presets were refused.
    good = preset_from_dict(timed_preset())
    path = save_preset(good, tmp_path / "p.json")
    path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    assert load_preset(path).scene.shape == good.scene.shape


@pytest.mark.parametrize("version", [1.0, 1])
def test_a_preset_version_written_as_a_whole_float_is_read(version):
    # some JSON writers store 1 as 1.0; it was refused although every other whole number reads
    data = {**timed_preset(), "version": version}
    assert preset_from_dict(data).scene.method == "AS"


@pytest.mark.parametrize(
    ("version", "message"),
    [(1.5, "must be an integer"), (0, "must be >= 1"), (True, "must be an integer"),
     ("1", "must be an integer"), (None, "must be an integer"), (2, "newer than")],
)  # fmt: skip
def test_a_bad_preset_version_names_the_field(version, message):
    with pytest.raises(PresetError, match=rf"field 'version'.*{message}"):
        preset_from_dict({**timed_preset(), "version": version})


def nested(depth):
    value = 1
    for _ in range(depth):
        value = [value]
    return value


def test_presets_and_profiles_nested_deeply_are_refused_by_the_cli(tmp_path, capsys):
    # JSON nested hundreds deep parses, then breaks whatever walks it (a RecursionError): the
    # readers refuse more than 20 levels
    from tactile_core.cli import main
    from tactile_core.device.profile import ProfileError, load_profile

    preset = json.loads(asset_path("presets", "exp3-square.json").read_text())
    profile = json.loads(asset_path("devices", "palm-5x6.json").read_text())
    preset["notes"], profile["notes"] = nested(300), nested(300)
    (tmp_path / "preset.json").write_text(json.dumps(preset))
    (tmp_path / "profile.json").write_text(json.dumps(profile))
    with pytest.raises(PresetError, match=r"nested too deeply \(more than 20 levels"):
        load_preset(tmp_path / "preset.json")
    with pytest.raises(ProfileError, match=r"nested too deeply \(more than 20 levels"):
        load_profile(tmp_path / "profile.json")
    code = main(["emulate", "--profile", str(tmp_path / "profile.json"), "--seconds", "0.1"])
    assert code == 2 and "nested too deeply (more than 20 levels" in capsys.readouterr().err
