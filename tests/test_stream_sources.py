"""A scene's frame source goes on playing when an equal copy arrives (the tuner sends every
scene to its stream process as a copy), and restarts when the content changes."""

import pickle
from pathlib import Path

import tactile_core as tc
from tactile_core.files.tact import load_pattern
from tactile_core.stream._plan import same_source

SAMPLE = Path(__file__).parent / "data" / "testfeedback.tact"


def test_a_copied_pattern_is_the_same_source():
    pattern = load_pattern(SAMPLE)
    copy = pickle.loads(pickle.dumps(pattern))
    assert copy is not pattern
    assert same_source(pattern, copy)
    assert same_source(None, None)


def test_another_file_or_position_is_another_source(tmp_path):
    pattern = load_pattern(SAMPLE)
    assert not same_source(pattern, None)
    assert not same_source(None, pattern)
    assert not same_source(pattern, tc.Line((0, 0), (1, 1)))  # another type, no key
    other = tmp_path / "other.tact"
    other.write_bytes(SAMPLE.read_bytes().replace(b'"intensity":', b'"intensity" :', 1))
    same_text = load_pattern(other)  # the same content, written differently: the same source
    assert same_source(pattern, same_text)


def test_sources_without_a_key_compare_by_identity():
    class Points:
        def live(self, *args):
            raise NotImplementedError

    a, b = Points(), Points()
    assert same_source(a, a)
    assert not same_source(a, b)
