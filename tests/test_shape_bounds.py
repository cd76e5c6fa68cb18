"""Shapes and method specs parsed from text: every point a shape reaches lies within the
coordinate bound (checked whole, when parsed, not only its numbers), numbers are plain ASCII
decimals, and a refusal never echoes a huge value back."""

import pytest

import tactile_core as tc
from tactile_core.rendering.shapes import parse_shape


@pytest.mark.parametrize(
    ("text", "reach"),
    [("square:2.5,999999,10", "1000004"), ("square:-999998,0,6", "-1000001"),
     ("circle:0,999999.5,1", "1000000.5")],
)  # fmt: skip
def test_a_shape_reaching_past_the_bound_is_refused_when_parsed(text, reach):
    # its numbers each within the bound, it was accepted and failed in the output thread
    with pytest.raises(ValueError, match=rf"takes the \w+ to {reach}: every point"):
        parse_shape(text)


def test_a_shape_just_inside_the_bound_is_accepted():
    square = parse_shape("square:2.5,999995,10")  # its top edge at exactly 1e6
    assert square.f(0.25)[1] == 1e6  # (f of a scalar t raised TypeError for squares before)
    assert parse_shape("circle:-999999,0,1").f(0.5)[0] == -1e6


@pytest.mark.parametrize("text", ["circle:2.5,\uff13,2", "circle:2.5,3,1_0"])
def test_shape_and_method_numbers_are_ascii_decimals(text):
    with pytest.raises(ValueError, match="decimal numbers"):
        parse_shape(text)
    with pytest.raises(ValueError, match="method must be NAME"):
        tc.get_method("RO:r=1_5")


def test_refusals_do_not_echo_huge_values():
    with pytest.raises(ValueError) as info:
        tc.parse_shape("circle:" + "9" * 100_000)
    assert len(str(info.value)) < 300
    with pytest.raises(ValueError) as info:
        tc.Line(("x" * 100_000, 0), (1, 1))
    assert len(str(info.value)) < 300
