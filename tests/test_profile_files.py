"""Device profile files as a lab writes them (and gets them wrong): read only from regular files
of a bounded size and found by name, each bad field refused in one line naming the file and the
field, and names that end up in CSV headers, labels and terminals kept printable."""

import copy
import json
import os
import threading

import pytest

from tactile_core._shared.assets import asset_path
from tactile_core.device.profile import ProfileError, find_profile, load_profile, profile_from_dict
from tactile_core.files.presets import PresetError, load_preset
from tactile_core.rendering.layout import Layout

PROFILE = json.loads(asset_path("devices", "palm-5x6.json").read_text())
BELT = {
    "format": "tactile-device-profile",
    "version": 1,
    "name": "belt",
    "pitch_mm": 100.0,
    "levels": 23,
    "layout": {
        "units": "mm",
        "actuators": [{"x": 100.0 * k, "y": 0.0, "name": f"m{k}"} for k in range(8)],
        "wrap": {"axis": "x", "circumference": 800.0},
    },
}


@pytest.mark.parametrize("path", ["/dev/zero", "/dev/null", "/"])
def test_profiles_are_read_only_from_regular_files(path):
    with pytest.raises(ProfileError, match="not a regular file"):
        load_profile(path)


def test_a_fifo_preset_or_profile_is_refused_without_blocking(tmp_path):
    # opening a FIFO to read it blocks until a writer opens it: a reader must look first
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    refused = []

    def read_both():
        for load, error in ((load_preset, PresetError), (load_profile, ProfileError)):
            try:
                load(fifo)
            except error as exc:
                refused.append(str(exc))

    reader = threading.Thread(target=read_both, daemon=True)
    reader.start()
    reader.join(20)  # a bound: a reader that blocks never returns
    blocked = reader.is_alive()
    if blocked:  # a writer lets the blocked open return, so the thread ends
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
    assert not blocked, "reading a FIFO blocked"
    assert len(refused) == 2 and all("not a regular file" in text for text in refused)


def test_a_huge_file_is_refused_by_its_size(tmp_path):
    path = tmp_path / "big.json"
    path.write_text(" " * (2 << 20) + "{}")
    with pytest.raises(ProfileError, match="larger than"):
        load_profile(path)


def test_presets_name_profiles_never_paths(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path))
    assert find_profile("palm-5x6").name == "palm-5x6"
    with pytest.raises(ProfileError, match="not a path"):
        find_profile(str(asset_path("devices", "palm-5x6.json")))
    mine = tmp_path / "tactile-tuner" / "devices"
    mine.mkdir(parents=True)
    data = {**PROFILE, "name": "lab-array"}
    (mine / "lab-array.json").write_text(json.dumps(data))
    assert find_profile("lab-array").name == "lab-array"
    with pytest.raises(ProfileError, match="no device profile named 'other'"):
        find_profile("other")


def test_a_profile_named_like_a_bundled_file_says_how_to_name_it(tmp_path, monkeypatch):
    """docs/device.md said --profile belt-8.json; the bundled profiles go by name."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ProfileError, match=r"belt-8.json: no such file.*belt-8"):
        load_profile("belt-8.json")


@pytest.mark.parametrize(
    ("change", "word"),
    [
        ({"calibration": {"offset": [[0.0] * 6] * 5, "gain": [[1.0] * 6] * 5}}, "6 rows of 5"),
        ({"response": {"drive": [[0, 0.5], [1]], "output": [0, 0.5, 1]}}, "response.drive"),
        ({"baud": 1}, "baud"),
        ({"columns": "5"}, "columns"),
        ({"name": "../x"}, "name"),
    ],
)
def test_bad_profiles_are_refused_naming_the_field(change, word):
    with pytest.raises(ProfileError) as info:
        profile_from_dict({**PROFILE, **change}, source="lab.json")
    assert word in str(info.value)


def test_a_calibration_table_in_rows_is_read_row_by_row():
    rows = [[r * 0.01 + c * 0.001 for c in range(5)] for r in range(6)]
    profile = profile_from_dict(
        {**PROFILE, "calibration": {"offset": rows, "gain": [[1.0] * 5] * 6}}
    )
    assert profile.offset[7] == pytest.approx(0.012)  # row 1, column 2


@pytest.mark.parametrize("pitch", [1e308, 1e-308, 0.001, 1e7])
def test_a_profile_pitch_out_of_range_is_refused_naming_it(pitch):
    """pitch_mm 1e308 made every actuator 'duplicate' at (0, 0); 1e-308 an infinite wrap,
    reported without the file's name."""
    data = copy.deepcopy(BELT)
    data["pitch_mm"] = pitch
    with pytest.raises(ProfileError, match=r"^belt.json: field 'pitch_mm' must be within"):
        profile_from_dict(data, "belt.json")


def test_a_profile_wrap_beyond_the_coordinate_bound_names_the_file_and_field():
    data = copy.deepcopy(BELT)
    data["layout"]["wrap"]["circumference"] = 1e12
    with pytest.raises(ProfileError, match=r"^belt.json: field 'layout.wrap.circumference'"):
        profile_from_dict(data, "belt.json")


@pytest.mark.parametrize("name", ["a\nb", "front,left", 'say "hi"', "tab\there", " front",
                                  "front ", "\x00", "bell\x07"])  # fmt: skip
def test_actuator_names_that_would_break_a_csv_header_are_refused(name):
    """Names become the column headers of render's CSV and the recorder's (and LSL's channel
    labels): a newline, comma or quote in one made a header with the wrong number of columns."""
    data = copy.deepcopy(BELT)
    data["layout"]["actuators"][1]["name"] = name
    with pytest.raises(ProfileError, match=r"layout.actuators\[1\].name"):
        profile_from_dict(data, "belt.json")
    with pytest.raises(ValueError, match="layout names"):
        Layout([(0.0, 0.0), (1.0, 0.0)], names=["ok", name])


def test_profile_groups_are_bounded_and_printable():
    """10,000 groups fit a 1 MiB profile and took the tuner 50 s to draw (a box and a label
    each, in every view); a group name is a label, so no control characters either."""
    data = copy.deepcopy(BELT)
    data["layout"]["groups"] = {f"g{k}": [0] for k in range(65)}
    with pytest.raises(ProfileError, match="layout groups: at most 64, got 65"):
        profile_from_dict(data, "belt.json")
    data["layout"]["groups"] = {f"g{k}": [0] for k in range(64)}
    assert len(profile_from_dict(data, "belt.json").layout.groups) == 64
    data["layout"]["groups"] = {"front\x1b[2J": [0]}
    with pytest.raises(ProfileError, match="group names must be 1-32 printable"):
        profile_from_dict(data, "belt.json")


def test_a_profile_version_of_hundreds_of_digits_is_shown_cut():
    data = copy.deepcopy(BELT)
    data["version"] = 10**400
    with pytest.raises(ProfileError, match="newer than this software reads") as caught:
        profile_from_dict(data, "belt.json")
    assert len(str(caught.value)) < 200
