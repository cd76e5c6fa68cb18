"""Pattern files: versioned JSON read field by field, every bad field refused by its path, large
and deep files refused within bounds (docs/patterns.md, The file and Bad files)."""

import copy
import json
from pathlib import Path

import pytest
import tomllib

import tactile_core as tc
from tactile_core.device.profile import find_profile
from tactile_core.files.pattern import (
    MAX_EFFECTS,
    MAX_PATTERN_BYTES,
    Dot,
    Dots,
    Effect,
    Pattern,
    PatternError,
    TactEffect,
    example_patterns,
)
from tactile_core.rendering.shapes import TimedPath

ROOT = Path(__file__).resolve().parents[1]
PALM = tc.Grid(5, 6)


def every_field() -> Pattern:
    """A pattern using every field of the file."""
    path = TimedPath([(0.5, 0.5), (2.0, 3.0), (4.5, 5.5)], [0.0, 0.3, 1.0], [1.0, 0.5, 0.8],
                     "CONST_SPEED", "FADE_OUT")  # fmt: skip
    tact = TactEffect([TimedPath([(0.0, 0.0), (1.0, 1.0)], [0.1, 0.5])],
                      [Dot((0.5, 0.25), 0.7, 0.0, 0.2, "FADE_IN")], 0.6, "VestFront")  # fmt: skip
    return Pattern(
        [
            Effect(tc.Line((0.5, 0.5), (4.5, 5.5)), 0.0, 0.6, "TB", name="stroke"),
            Effect(
                tc.Circle((2.5, 3.0), 1.5),
                0.2,
                1.0,
                "RO:r=1.5",
                [(0.0, 0.0), (0.5, 1.0)],
                repeat=2,
                track=3,
            ),
            Effect(tc.Square((2.5, 3.0), 2.0), 1.0, 0.5, group=None),
            Effect(tc.Polyline([(0.5, 0.5), (1.5, 2.5), (3.0, 1.0)], closed=True), duration_s=0.4),
            Effect(path, start_s=2.0),
            Effect(
                Dots([Dot(3, 0.5, 0.1, 0.2), Dot((2.5, 3.0), 1.0, 0.0, 0.1, "FADE_IN_OUT")]),
                start_s=0.5,
                repeat=3,
                duration_s=0.3,
            ),
            Effect(tact, start_s=1.5, track=2),
        ],
        combine="sum",
        name="every field",
        notes="two lines\nof notes",
    )


def write(tmp_path, data, name="p.json") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(data) if not isinstance(data, str) else data)
    return path


def test_a_pattern_round_trips_through_its_file(tmp_path):
    pattern = every_field()
    saved = pattern.save(tmp_path / "p.json")
    again = Pattern.load(saved)
    assert again == pattern
    assert again.to_dict() == pattern.to_dict() == json.loads(saved.read_text())
    _, before = pattern.frames("AS", PALM, rate_hz=50.0)
    _, after = again.frames("AS", PALM, rate_hz=50.0)
    assert (before == after).all() and before.any()


def test_the_example_patterns_are_bundled_and_load():
    examples = example_patterns()
    assert sorted(examples) == ["letter-a", "taps", "vest-sweep"]
    vest = find_profile("vest-front-back").layout
    letter = Pattern.load(examples["letter-a"], PALM)
    assert len(letter.effects) == 3 and letter.duration_s == pytest.approx(2.1)
    assert Pattern.load(examples["vest-sweep"], vest).groups == ("front", "back")
    assert Pattern.load(examples["taps"], PALM).effects[0].repeat == 4
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert "tactile_core._assets.patterns" in config["packages"]
    assert config["package-data"]["tactile_core._assets.patterns"] == ["*.json"]


def good() -> dict:
    return {
        "format": "tactile-pattern", "version": 1, "name": "p", "combine": "max",
        "effects": [
            {"start_s": 0.0, "duration_s": 1.0, "shape": {"type": "line", "p0": [0, 0],
                                                          "p1": [1, 1]}},
            {"start_s": 0.5, "dots": [{"at": 1, "intensity": 0.5, "duration_s": 0.2}]},
            {"start_s": 0.0, "duration_s": 0.5, "envelope": [{"time_s": 0, "gain": 0},
                                                             {"time_s": 0.3, "gain": 1}],
             "dots": [{"at": [2.5, 3.0]}]},
            {"start_s": 1.0, "duration_s": 2.0, "repeat": 2, "method": "RO", "group": None,
             "track": 2, "envelope": [{"time_s": 0.0, "gain": 1.0}, {"time_s": 0.1, "gain": 0.5}],
             "shape": {"type": "circle", "center": [2.5, 3], "radius": 1}},
            {"tact": {"paths": [{"type": "timed_path", "points": [[0, 0], [1, 1]],
                                 "times_s": [0, 0.4]}],
                      "dots": [{"at": [0.5, 0.5], "duration_s": 0.1}], "length_s": 0.5}},
        ],
    }  # fmt: skip


def test_the_good_file_of_the_mutation_table_loads(tmp_path):
    pattern = Pattern.load(write(tmp_path, good()))
    assert [e.kind for e in pattern.effects] == ["shape", "dots", "dots", "shape", "tact"]


def change(path, value):
    """A mutation: the value at ``path`` (keys and indices) set to ``value`` (or removed)."""

    def mutate(data):
        *parents, last = path
        node = data
        for key in parents:
            node = node[key]
        if value is _REMOVE:
            del node[last]
        else:
            node[last] = value
        return data

    return mutate


_REMOVE = object()
E3 = ("effects", 3)


MUTATIONS = [
    (change(("format",), "tactile-preset"), "format must be 'tactile-pattern'"),
    (change(("version",), 3), r"version is 3, newer than this software reads \(2\)"),
    (change(("version",), "1"), "version must be a whole number"),
    (change(("version",), _REMOVE), "version is missing"),
    (change(("effects",), _REMOVE), "effects is missing"),
    (change(("effects",), {}), "effects must be a list"),
    (change(("combine",), "mean"), "combine must be one of max, sum"),
    (change(("name",), 7), "name must be a string"),
    (change(("name",), "x" * 201), "name must be a string of 0 to 200 characters"),
    (change(("colour",), "red"), r"colour is not a field here"),
    (change(("effects", 0), 3), r"effects\[0\] must be an object"),
    (change(("effects", 0, "duraton_s"), 1.0), r"effects\[0\]\.duraton_s is not a field here"),
    (change(("effects", 0, "dots"), []), r"effects\[0\] must hold exactly one of shape, dots, "
     "tact"),
    (change(("effects", 0, "shape"), _REMOVE), r"effects\[0\] must hold exactly one"),
    (change(("effects", 0, "duration_s"), _REMOVE), r"effects\[0\]\.duration_s must be given "
     "for a line"),
    (change(("effects", 0, "start_s"), "0"), r"effects\[0\]\.start_s must be a number"),
    (change(("effects", 0, "start_s"), True), r"effects\[0\]\.start_s must be a number"),
    (change(("effects", 0, "start_s"), -1), r"effects\[0\]\.start_s must be within \[0, 3600\]"),
    (change(("effects", 0, "duration_s"), 0), r"effects\[0\]\.duration_s must be > 0"),
    (change(("effects", 0, "shape", "p0"), [0, "a"]), r"effects\[0\]\.shape\.p0\[1\] must be"),
    (change(("effects", 0, "shape", "type"), "star"), r"effects\[0\]\.shape\.type must be one "
     "of"),
    (change(("effects", 1, "dots", 0, "at"), 1.5), r"effects\[1\]\.dots\[0\]\.at must be a "
     "whole number"),
    (change(("effects", 1, "dots", 0, "at"), [1]), r"effects\[1\]\.dots\[0\]\.at must be an "
     r"actuator's index or a place"),
    (change(("effects", 1, "dots", 0, "at"), _REMOVE), r"effects\[1\]\.dots\[0\]\.at is missing"),
    (change(("effects", 1, "dots", 0, "intensity"), 1.5), r"effects\[1\]\.dots\[0\]\.intensity "
     r"must be within \[0, 1\]"),
    (change(("effects", 1, "dots", 0, "fade"), "SLOW"), r"effects\[1\]\.dots\[0\]\.fade must be "
     "one of"),
    (change(("effects", 1, "dots", 0, "size"), 2), r"effects\[1\]\.dots\[0\]\.size is not a "
     "field here"),
    (change(("effects", 1, "dots"), []), r"effects\[1\]\.dots must hold at least one Dot"),
    (change(("effects", 2, "envelope", 1, "time_s"), 0.7), r"effects\[2\]\.envelope\[1\]\.time_s "
     r"must be within \[0, 0\.5\]"),
    (change(("effects", 2, "envelope", 1, "time_s"), 0.0), r"effects\[2\]\.envelope\[1\]\.time_s "
     "must be later than"),
    (change(("effects", 2, "envelope", 1, "gain"), -0.1), r"effects\[2\]\.envelope\[1\]\.gain "
     "must be within"),
    (change(("effects", 2, "envelope", 1, "gain"), _REMOVE), r"effects\[2\]\.envelope\[1\]\.gain "
     "is missing"),
    (change(("effects", 2, "envelope", 1), [0.3, 1]), r"effects\[2\]\.envelope\[1\] must be an "
     "object"),
    (change((*E3, "repeat"), 0), r"effects\[3\]\.repeat must be >= 1"),
    (change((*E3, "repeat"), 2.5), r"effects\[3\]\.repeat must be a whole number"),
    (change((*E3, "repeat"), 2000), r"effects\[3\]\.repeat 2000 of 2 s .* ends the effect at "
     "4001 s"),
    (change((*E3, "method"), "ZZ"), r"effects\[3\]\.method"),
    (change((*E3, "method"), 3), r"effects\[3\]\.method must be a string or null"),
    (change((*E3, "group"), ""), r"effects\[3\]\.group must be a string of 1 to 32"),
    (change((*E3, "group"), "front\n"), r"effects\[3\]\.group must be printable"),
    (change((*E3, "track"), -1), r"effects\[3\]\.track must be >= 0"),
    (change((*E3, "track"), 1000), r"effects\[3\]\.track must be >= 0 and <= 999"),
    (change((*E3, "envelope"), "up"), r"effects\[3\]\.envelope must be a list"),
    (change(("effects", 4, "tact", "paths", 0, "points", 1), [1, 1.5]), r"effects\[4\]\.tact"
     r"\.paths\[0\]\.points\[1\] must lie within \[0, 1\]"),
    (change(("effects", 4, "tact", "paths", 0, "type"), "line"), r"effects\[4\]\.tact\.paths\[0\]"
     " must be a timed_path object"),
    (change(("effects", 4, "tact", "paths", 0, "times_s"), [0, 0.9]), r"effects\[4\]\.tact\."
     r"length_s must be at least 0\.9 s"),
    (change(("effects", 4, "tact", "dots", 0, "at"), 3), r"effects\[4\]\.tact\.dots\[0\]\.at "
     r"must be a place"),
    (change(("effects", 4, "tact", "speed"), 1), r"effects\[4\]\.tact\.speed is not a field"),
]  # fmt: skip


@pytest.mark.parametrize("mutate, message", MUTATIONS)
def test_each_bad_field_is_refused_naming_its_path(tmp_path, mutate, message):
    path = write(tmp_path, mutate(copy.deepcopy(good())))
    with pytest.raises(PatternError, match=message) as caught:
        Pattern.load(path)
    assert str(caught.value).startswith(f"{path}: ")


def test_text_that_is_not_json_is_refused_naming_the_file(tmp_path):
    for text, message in (("{", "not valid JSON"), ('{"effects": NaN}', "not valid JSON"),
                          ("", "not valid JSON")):  # fmt: skip
        with pytest.raises(PatternError, match=f"{tmp_path}.*{message}"):
            Pattern.load(write(tmp_path, text))
    with pytest.raises(PatternError, match="no such file"):
        Pattern.load(tmp_path / "missing.json")


def test_a_huge_pattern_is_refused_by_count_and_by_size(tmp_path):
    # 10^5 one-dot effects (2 MB) parse, and are refused at the list: more than MAX_EFFECTS
    data = good()
    data["effects"] = [{"dots": [{"at": 0}]}] * 100_000
    with pytest.raises(PatternError, match=rf"effects holds 100000 entries, more than the "
                       rf"{MAX_EFFECTS} allowed"):  # fmt: skip
        Pattern.load(write(tmp_path, data))
    # a larger file is refused before it is parsed
    big = write(tmp_path, " " * (MAX_PATTERN_BYTES + 1), "big.json")
    with pytest.raises(PatternError, match=f"larger than the {MAX_PATTERN_BYTES} allowed"):
        Pattern.load(big)
    # 200,001 path points and dots in all
    data["effects"] = [{"dots": [{"at": 0}] * 10_000}] * 20 + [{"dots": [{"at": 0}]}]
    with pytest.raises(PatternError, match=r"effects\[20\] brings the pattern past 200000"):
        Pattern.load(write(tmp_path, data))
    with pytest.raises(ValueError, match=r"effects holds 10001 entries"):
        Pattern([Effect(Dots([Dot(0)]))] * 10_001)


@pytest.mark.parametrize("levels", [25, 100_000])
def test_a_deeply_nested_file_is_refused_naming_the_field(tmp_path, levels):
    # nested past what json or the bounded reader takes, in a file of a few hundred KB: the
    # field where it goes too deep is named, found without parsing it
    data = good()
    data["effects"][0]["shape"]["p0"] = "DEEP"
    text = json.dumps(data).replace('"DEEP"', "[" * levels + "]" * levels)
    # (depth 9 of the file: itself, effects, an effect, shape, p0, then four more lists)
    with pytest.raises(PatternError, match=r"effects\[0\]\.shape\.p0\[0\]\[0\]\[0\]\[0\] is "
                       "nested too deeply: a pattern file nests at most 8"):  # fmt: skip
        Pattern.load(write(tmp_path, text))
    # nested within the parser's bound but where a number belongs: that field named
    data["effects"][0]["shape"]["p0"] = [0, 0]
    data["effects"][0]["start_s"] = [[[[[1]]]]]
    with pytest.raises(PatternError, match=r"effects\[0\]\.start_s must be a number"):
        Pattern.load(write(tmp_path, data))


def test_a_group_the_layout_lacks_is_refused_naming_the_field(tmp_path):
    data = good()
    data["effects"][3]["group"] = "front"
    path = write(tmp_path, data)
    Pattern.load(path)  # the file alone is fine: groups belong to the array
    with pytest.raises(PatternError, match=rf"{path}: effects\[3\]\.group must name a group of "
                       r"the layout \(left, right\), got 'front'"):  # fmt: skip
        Pattern.load(path, find_profile("vest-4x5").layout)
    assert Pattern.load(path, find_profile("vest-front-back").layout).groups == ("front",)
