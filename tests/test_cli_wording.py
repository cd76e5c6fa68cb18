"""Command-line messages name the option a user typed and read once (new-user pass)."""

import subprocess
import sys

import pytest

CLI = [sys.executable, "-m", "tactile_core.cli"]


@pytest.mark.parametrize("command", [
    ["stream", "--device", "sim", "--shape", "circle:2.5,3,2", "--method", "AS", "--seconds", "1"],
    ["serve", "--device", "sim", "--osc-port", "0"],
])  # fmt: skip
def test_a_rate_out_of_range_names_the_option_not_the_field(command):
    # it said "rate_hz must be within [1, 10000]", the scene's field, for --rate 0
    out = subprocess.run([*CLI, *command, "--rate", "0"], capture_output=True, text=True,
                         timeout=60)  # fmt: skip
    assert out.returncode == 2 and "--rate must be within [1, 10000], got 0" in out.stderr
    assert "rate_hz" not in out.stderr


def test_a_broken_json_file_says_where_in_plain_words(tmp_path):
    # "Unterminated string starting at at line 5"
    from tactile_core.files.presets import PresetError, load_preset

    bad = tmp_path / "p.json"
    bad.write_text('{\n  "format": "tactile-preset",\n  "name": "unterminated\n}\n')
    with pytest.raises(PresetError) as caught:
        load_preset(bad)
    message = str(caught.value)
    assert "at at" not in message and "line 3, column" in message
