"""Method plug-ins that misbehave: a plug-in whose import calls sys.exit or raises
KeyboardInterrupt is listed as unavailable, not the end of the program; what its sample returns
is checked (a cell named twice, values outside [0, 1], the wrong length) and its exits become
its error, naming the plug-in, so a bad plug-in never takes a render or a stream down."""

import textwrap

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.rendering import methods as registry

from .helpers import run_cli_last_line

PLUGIN = """
import math, sys
import numpy as np

NAME = "{name}"
TITLE = "a plug-in of the tests"
BILEVEL = False
NEEDS_SHAPE = False
PARAMS = {{"k": (1.0, 0.0, 2.0, "a parameter")}}


def MAX_TACTORS(k):
    return int(2 / k)


def sample(shape, x, y, t, tol, k=1.0):
    {sample}


def sample1(shape, x, y, t, tol, k=1.0):
    return tuple((float(c[0]), float(r[0]), float(np.broadcast_to(v, (1,))[0]))
                 for c, r, v in sample(shape, np.array([x]), np.array([y]), t, tol, k))
"""
CELL = "np.floor(x + tol), np.floor(y + tol)"
PLUGINS = {
    "twice": f"return [({CELL}, 0.75), ({CELL}, 0.75)]",  # summed to 1.5 on one tactor
    "offgrid": "return [(x * 0 - 1, y * 0 - 1, 0.5), (x * 0 - 1, y * 0 - 1, 0.5)]",  # dropped
    "nan": f"return [({CELL}, x * np.nan)]",
    "halfk": f"return [({CELL}, 0.5)]",  # MAX_TACTORS divides by k: k=0 raises
    "quits": "sys.exit(3)",
    "ctrlc": "raise KeyboardInterrupt",
    "short": f"return [({CELL}, np.zeros(len(x) + 1))]",  # one value too many
}


@pytest.fixture
def plugins(tmp_path, monkeypatch):
    root = tmp_path / "site"
    root.mkdir()
    points = []
    for name, body in PLUGINS.items():
        text = PLUGIN.format(name=name.upper(), sample=body)
        (root / f"faulty_{name}.py").write_text(textwrap.dedent(text))
        points.append(f"{name} = faulty_{name}")
    (root / "faulty_exits.py").write_text("import sys\nsys.exit(1)\n")
    (root / "faulty_interrupts.py").write_text("raise KeyboardInterrupt\n")
    points += ["exits = faulty_exits", "interrupts = faulty_interrupts"]
    info = root / "faulty-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: faulty\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text("[tactile_tuner.methods]\n" + "\n".join(points) + "\n")
    monkeypatch.syspath_prepend(str(root))
    before, unavailable = dict(registry.METHODS), dict(registry.UNAVAILABLE)
    monkeypatch.setattr(registry, "_plugins_loaded", False)
    registry.load_plugins()
    yield root
    registry.METHODS.clear()
    registry.METHODS.update(before)
    registry.UNAVAILABLE.clear()
    registry.UNAVAILABLE.update(unavailable)


LINE = tc.Line((1.2, 2.7), (3.6, 2.7))


def test_sys_exit_and_ctrl_c_in_a_plugins_import_are_contained(plugins):
    assert registry.UNAVAILABLE["exits"] == "SystemExit: 1"
    assert registry.UNAVAILABLE["interrupts"].startswith("KeyboardInterrupt")
    assert {"TWICE", "HALFK", "QUITS"} <= set(registry.METHODS)


def test_a_cell_named_twice_at_one_point_is_refused(plugins):
    with pytest.raises(
        ValueError, match=r"method TWICE \(a plug-in\) named the cell \(1, 2\) twice"
    ):
        tc.render(LINE, "TWICE", np.linspace(0, 1, 5))
    with pytest.raises(ValueError, match=r"named the cell \(1, 2\) twice at one point"):
        tc.render_point(LINE, "TWICE", 0.0)


def test_cells_off_the_grid_are_dropped_as_for_every_method(plugins):
    assert not tc.render(LINE, "OFFGRID", np.linspace(0, 1, 5)).any()


@pytest.mark.parametrize(
    ("name", "error"),
    [("NAN", r"values in \[0, 1\]"), ("SHORT", "entries"), ("QUITS", "failed: SystemExit: 3"),
     ("CTRLC", "failed: KeyboardInterrupt")],
)  # fmt: skip
def test_a_plugins_bad_output_and_exits_become_its_error(plugins, name, error):
    with pytest.raises(ValueError, match=rf"method {name} \(a plug-in\) .*{error}"):
        tc.render(LINE, name, np.linspace(0, 1, 5))
    with pytest.raises(ValueError, match=rf"method {name} \(a plug-in\)"):
        tc.render_point(LINE, name, 0.5)


def test_max_tactors_that_raises_is_a_clean_error_from_render(plugins, tmp_path, capsys):
    # (it was a ZeroDivisionError traceback)
    code, err = run_cli_last_line(capsys, "render", "--shape", "circle:2.5,3,2", "--method",
                                  "HALFK:k=0", "--out", str(tmp_path / "f.csv"))  # fmt: skip
    assert code == 2 and "MAX_TACTORS failed at k=0: ZeroDivisionError" in err
    assert tc.get_method("HALFK:k=0.5").max_tactors == 4
