"""A pattern's parts are compiled in time proportional to them: each effect's new strokes and
dots are filtered once, not the whole list so far again at every effect (a 10,000-effect
pattern's check took 1.22 s, now 0.04 s; the pattern editor checks at each edit). Counted in
reads of a part's window, not in seconds."""

import pytest

import tactile_core as tc
from tactile_core.files import _pattern_parts
from tactile_core.files.pattern import Pattern

SLOT = _pattern_parts.Part.a  # the slot of the part's window start


class CountedPart(_pattern_parts.Part):
    """A part that counts how often its window's start (``a``) is read."""

    __slots__ = ()
    reads = 0

    @property
    def a(self):
        CountedPart.reads += 1
        return SLOT.__get__(self)

    @a.setter
    def a(self, value):
        SLOT.__set__(self, value)


@pytest.mark.parametrize("n", [100, 800])
def test_compiling_reads_each_part_a_bounded_number_of_times(monkeypatch, n):
    monkeypatch.setattr(_pattern_parts, "Part", CountedPart)
    effects = []
    for i in range(n):
        shape = tc.Line((0.5, 0.5), (4.5, 5.5))
        effects.append(tc.Effect(shape, start_s=0.01 * i, duration_s=0.2))
        effects.append(tc.Effect(tc.Dots([tc.Dot(i % 30, 1.0, 0.0, 0.05)]), start_s=0.01 * i))
    CountedPart.reads = 0
    parts = _pattern_parts.compile_parts(Pattern(effects), tc.get_method("AS"), tc.Grid())
    assert len(parts) == 2 * n
    assert CountedPart.reads <= 4 * len(parts)  # the quadratic filter read it ~n times each
