"""Method plug-ins through a real entry point: a distribution's ``.dist-info`` on a temporary
path declares methods under ``tactile_tuner.methods``; they render, compare and stream like the
built-in ones, and broken ones are listed as unavailable without taking anything down."""

import os
import subprocess
import textwrap

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.rendering import methods as registry

from .emulator_support import CLI, Emulator

HALF = '''
"""Closest tactor at half intensity: a plug-in method for the tests."""
import math
import numpy as np

NAME = "HALF"
TITLE = "closest tactor at half"
BILEVEL = True
NEEDS_SHAPE = False
MAX_TACTORS = 1


def sample(shape, x, y, t, tol):
    return [(np.floor(x + tol), np.floor(y + tol), 0.5)]


def sample1(shape, x, y, t, tol):
    return ((math.floor(x + tol), math.floor(y + tol), 0.5),)
'''

BAD_VALUES = HALF.replace('"HALF"', '"LOUD"').replace("0.5", "1.5")
RAISES = HALF.replace('"HALF"', '"BOOM"').replace(
    "    return [(np", "    raise ZeroDivisionError('oops')\n    return [(np"
)
NO_PROTOCOL = 'NAME = "HALFWAY"\n'


@pytest.fixture
def site(tmp_path, monkeypatch):
    """A site folder with one distribution declaring four methods (one good, three broken)
    and one more that fails to import; the registry is restored afterwards."""
    root = tmp_path / "site"
    root.mkdir()
    for name, text in [
        ("tt_half", HALF),
        ("tt_loud", BAD_VALUES),
        ("tt_boom", RAISES),
        ("tt_noproto", NO_PROTOCOL),
        ("tt_broken", "raise ImportError('needs a library that is missing')\n"),
    ]:
        (root / f"{name}.py").write_text(textwrap.dedent(text))  # fmt: skip
    info = root / "tt_methods-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: tt-methods\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(
        "[tactile_tuner.methods]\nhalf = tt_half\nloud = tt_loud\nboom = tt_boom\n"
        "noproto = tt_noproto\nbroken = tt_broken\n"
    )
    monkeypatch.syspath_prepend(str(root))
    before, unavailable = dict(registry.METHODS), dict(registry.UNAVAILABLE)
    monkeypatch.setattr(registry, "_plugins_loaded", False)
    yield root
    registry.METHODS.clear()
    registry.METHODS.update(before)
    registry.UNAVAILABLE.clear()
    registry.UNAVAILABLE.update(unavailable)


def test_a_plugin_is_found_through_its_entry_point_and_renders(site):
    assert "HALF" in registry.method_names()
    method = tc.get_method("half")
    assert method.plugin and method.source == "plugin tt-methods" and method.bilevel
    frame = tc.render(tc.Line((1.2, 2.7), (1.2, 2.7)), "HALF", 0.0)
    expected = np.zeros((6, 5))
    expected[2, 1] = 0.5  # the cell (1, 2) of the point, at half
    np.testing.assert_array_equal(frame, expected)
    # t = 0.25: the top, (2.5, 5.0), on the edge of rows 4 and 5: the upper, cell (2, 5).
    assert tc.render_point(tc.Circle((2.5, 3), 2), "HALF", 0.25) == ((5 * 5 + 2, 0.5),)


def test_broken_plugins_are_listed_with_their_errors_and_nothing_else_breaks(site):
    names = registry.method_names()
    assert "HALFWAY" not in names
    assert "needs a library that is missing" in registry.UNAVAILABLE["broken"]
    assert "does not follow the method protocol" in registry.UNAVAILABLE["noproto"]
    assert {"CT", "MM", "AS", "IM", "EN", "PK", "RO", "GS"} <= set(names)
    loud = r"method LOUD \(a plug-in\) returned .* values in \[0, 1\]"
    with pytest.raises(ValueError, match=loud):
        tc.render(tc.Circle((2.5, 3), 2), "LOUD", np.linspace(0, 1, 5))
    with pytest.raises(ValueError, match=r"method BOOM \(a plug-in\) failed: ZeroDivisionError"):
        tc.render(tc.Circle((2.5, 3), 2), "BOOM", np.linspace(0, 1, 5))
    with pytest.raises(ValueError, match="got 'BROKEN'"):
        tc.get_method("BROKEN")


def test_a_plugin_cannot_take_a_built_in_name(tmp_path, monkeypatch):
    (tmp_path / "tt_fake_as.py").write_text(HALF.replace('"HALF"', '"AS"'))
    monkeypatch.syspath_prepend(str(tmp_path))
    from importlib.metadata import EntryPoint

    before = dict(registry.UNAVAILABLE)
    try:
        registry.load_plugins([EntryPoint("fake", "tt_fake_as", registry.ENTRY_POINT_GROUP)])
        assert "takes the name AS of a built-in" in registry.UNAVAILABLE["fake"]
        assert not registry.METHODS["AS"].plugin
    finally:
        registry.UNAVAILABLE.clear()
        registry.UNAVAILABLE.update(before)


def _env(site):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(site), env.get("PYTHONPATH", "")])
    return env


def test_a_plugin_renders_and_streams_from_the_command_line(site, tmp_path):
    out = tmp_path / "half.npz"
    proc = subprocess.run(
        [*CLI, "render", "--shape", "circle:2.5,3,2", "--method", "HALF", "--rate", "50",
         "--out", str(out)],
        capture_output=True, text=True, env=_env(site), timeout=60,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    with np.load(out) as data:
        assert set(np.unique(data["frames"])) == {0.0, 0.5}
        assert ((data["frames"] > 0).sum(axis=(1, 2)) == 1).all()
    emu = Emulator(tmp_path)
    try:
        proc = subprocess.run(
            [*CLI, "stream", "--device", emu.path, "--shape", "circle:2.5,3,2", "--method", "HALF",
             "--mu", "0", "--gamma", "1", "--rate", "100", "--seconds", "1", "--no-dither"],
            capture_output=True, text=True, env=_env(site), timeout=60,
        )  # fmt: skip
        assert proc.returncode == 0, proc.stderr
        _, log = emu.finish()
    finally:
        emu.kill()
    levels = log[:, 2:]
    lit = levels[levels > 0]
    assert lit.size > 50 and set(np.unique(lit)) == {11.0}  # 0.5 x 22 = level 11
    assert ((levels > 0).sum(axis=1) <= 1).all() and not levels[-1].any()
    # A plug-in that breaks is refused by name before anything streams.
    proc = subprocess.run(
        [*CLI, "render", "--shape", "circle:2.5,3,2", "--method", "LOUD", "--out",
         str(tmp_path / "loud.npz")],
        capture_output=True, text=True, env=_env(site), timeout=60,
    )  # fmt: skip
    assert proc.returncode != 0 and "method LOUD (a plug-in)" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_a_plugin_appears_in_the_tuner_streams_and_compares(site, qtbot, monkeypatch):
    from tactile_tuner.window import MainWindow

    monkeypatch.setenv("PYTHONPATH", _env(site)["PYTHONPATH"])  # the stream's own process
    win = MainWindow(restore=False)
    qtbot.addWidget(win)
    win.show()
    combo = win.controls.method.other_combo
    win.controls.method.fill_other_methods()
    assert combo.findData("HALF") >= 0
    broken = [combo.itemText(i) for i in range(combo.count()) if combo.itemData(i) is None]
    assert any("broken" in text for text in broken)
    win.state.update(method="HALF", mu=0.0, gamma=1.0, dither=False)
    assert win.controls.method.other_button.isChecked()

    def half_lit():
        levels = win.device.sent_levels()
        return (levels > 0).sum() == 1 and levels.max() == 11  # 0.5 x 22

    qtbot.waitUntil(half_lit, timeout=5000)
    win.compare.set_methods(["AS", "HALF", "RO:r=1.5"])
    assert list(win.compare.heatmaps) == ["AS", "HALF", "RO:r=1.5"]
    win.compare._refresh()
    assert win.compare.curves["HALF"].listDataItems()  # its activation curves are drawn
    win.blind.set_methods(["AS", "HALF"])
    win.blind.start(seed=1)
    assert sorted(win.blind.session.mapping) == ["AS", "HALF"]
    win.close()


def test_a_plugin_that_breaks_in_the_tuner_is_listed_and_nothing_else_breaks(
    site, qtbot, monkeypatch
):
    from tactile_tuner.window import MainWindow

    monkeypatch.setenv("PYTHONPATH", _env(site)["PYTHONPATH"])
    win = MainWindow(restore=False)
    qtbot.addWidget(win)
    win.show()
    errors = []
    win.state.error_raised.connect(errors.append)
    registry.method_names()
    assert not win.state.update(method="BOOM")  # tried before it plays: refused
    assert "method BOOM (a plug-in) failed" in errors[-1] and "unavailable" in errors[-1]
    assert "BOOM" not in registry.METHODS and "ZeroDivisionError" in registry.UNAVAILABLE["boom"]
    assert win.state.scene.method == "AS"
    combo = win.controls.method.other_combo
    assert combo.findData("BOOM") < 0
    assert any("boom" in combo.itemText(i) for i in range(combo.count()))
    # One that fails only while playing: back to AS, paused, listed.
    win.state.update(method="HALF")
    failing = registry._checked("HALF", lambda *a: 1 / 0, True)  # as the registry wraps it
    registry.METHODS["HALF"]._samplers["sample1"] = failing
    win.state.update(playing=True)
    qtbot.waitUntil(lambda: win.state.scene.method == "AS", timeout=3000)
    assert not win.state.scene.playing and "HALF" not in registry.METHODS
    win.close()
