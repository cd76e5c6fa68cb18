"""What ``tactile`` says about its own arguments: ``--help`` names every form an option takes,
and a usage error shows the form that was meant."""

import re

import pytest

from tactile_core.cli import main
from tactile_core.rendering.shapes import SHAPE_KINDS, parse_shape


def help_text(capsys, command) -> str:
    """``tactile COMMAND --help`` with the line breaks and indents taken out (argparse wraps,
    at hyphens too), so that a phrase is found wherever it was wrapped."""
    capsys.readouterr()
    with pytest.raises(SystemExit) as exit_:
        main([command, "--help"])
    assert exit_.value.code == 0
    return re.sub(r"\s+", "", capsys.readouterr().out)


def usage_error(capsys, argv) -> str:
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    return capsys.readouterr().err


def test_a_shape_written_as_words_gets_the_commands_usage_and_the_one_word_form(tmp_path, capsys):
    """Before: the top-level usage and "unrecognized arguments: 2.5 3 2", nothing of
    circle:CX,CY,R."""
    err = usage_error(capsys, ["render", "--shape", "circle", "2.5", "3", "2", "--method", "AS",
                               "--out", str(tmp_path / "x.csv")])  # fmt: skip
    assert err.startswith("usage: tactile render")
    assert "tactile render: error: unrecognized arguments: 2.5 3 2" in err
    assert "--shape circle:2.5,3,2" in err  # the spec as one word
    assert "circle:CX,CY,R" in err and "line:X0,Y0,X1,Y1" in err


def test_another_stray_argument_still_gets_the_commands_usage(capsys):
    err = usage_error(capsys, ["emulate", "--seconds", "1", "extra"])
    assert err.startswith("usage: tactile emulate")
    assert err.rstrip().endswith("tactile emulate: error: unrecognized arguments: extra")


@pytest.mark.parametrize("text", ["circle", "circle 2.5 3 2", "ring:1,2,3"])
def test_a_shape_that_is_not_a_spec_is_told_every_form(text):
    with pytest.raises(ValueError) as error:
        parse_shape(text)
    for form in ("line:X0,Y0,X1,Y1", "circle:CX,CY,R", "square:CX,CY,EDGE", "polyline:",
                 "polygon:", "timed:X0,Y0,T0,I0"):  # fmt: skip
        assert form in str(error.value)


@pytest.mark.parametrize("command", ["render", "stream"])
def test_help_lists_every_shape_spec_the_parser_accepts(capsys, command):
    """Before: line, circle, square and tact only (polyline, polygon and timed were taken)."""
    text = help_text(capsys, command)
    for kind in (*SHAPE_KINDS, "tact", "pattern"):
        assert f"{kind}:" in text
    for option in ("speed", "fade-in", "fade-out", "fade-in-out"):  # the timed path's
        assert option in text


@pytest.mark.parametrize("command", ["emulate", "serve", "stream", "render", "tune-correction"])
def test_profile_help_says_a_name_or_a_json_file(capsys, command):
    """Before: emulate, serve, stream and tune-correction said "device profile JSON", though
    the bundled names work."""
    text = help_text(capsys, command)
    names = (
        "belt-8,grid-3x3,lra-5x6,palm-5x6,sleeve-2x6,sleeves-pair,vest-4x5,vest-front-back,"
        "voicecoil-8,wireless-4x4"
    )
    assert f"aname({names})oraJSONfile" in text


def test_a_shape_spec_error_in_the_program_names_the_forms(tmp_path, capsys):
    assert main(["render", "--shape", "circle", "--method", "AS",
                 "--out", str(tmp_path / "x.csv")]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert err.startswith("tactile render: error: shape must")
    assert "circle:CX,CY,R" in err and "tact:FILE.tact" in err
