"""docs/patterns.md's first script runs as written, in at most 20 lines, and saves the bundled
example patterns (tests/test_docs.py reads the pages; this one runs the script)."""

import json
import re
from pathlib import Path

from tactile_core.files.pattern import Pattern, example_patterns

ROOT = Path(__file__).resolve().parents[1]


def first_script() -> str:
    text = (ROOT / "docs" / "patterns.md").read_text()
    section = text.split("## A first script", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_first_script_builds_saves_and_plays_the_three_examples(tmp_path, monkeypatch):
    script = first_script()
    assert len(script.strip().splitlines()) <= 20
    monkeypatch.chdir(tmp_path)
    played = []
    import tactile_core.script as script_module

    real_play = script_module.Array.play

    def play(array, pattern, *args, **kwargs):  # what each array was asked to play, and did
        shown = real_play(array, pattern, *args, **kwargs)
        played.append((array.profile.name, pattern.name, shown.interrupted))
        return shown

    monkeypatch.setattr(script_module.Array, "play", play)
    exec(compile(script, "docs/patterns.md", "exec"), {"__name__": "__docs__"})
    assert played == [("palm-5x6", "letter A", False), ("palm-5x6", "taps", False),
                      ("vest-front-back", "front to back", False)]  # fmt: skip
    for stem, path in example_patterns().items():
        saved = tmp_path / f"{stem}.json"
        assert json.loads(saved.read_text()) == json.loads(path.read_text()), stem
        assert Pattern.load(saved) == Pattern.load(path)
