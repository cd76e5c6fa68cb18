"""Blind A/B stays blind and never loses a rating (issue 19, items 6 and 7): every string the
window shows is read while blind; ratings survive a reshuffle, a quit and a cancel."""

import csv
import re

import pytest
from PySide6 import QtCore, QtWidgets

from tactile_core.rendering.methods import method_names

from .gui_strings import visible_strings

pytestmark = pytest.mark.usefixtures("qt_settings")
Key = QtCore.Qt.Key
FOUR, SIX = ["CT", "MM", "AS", "IM"], ["CT", "MM", "AS", "IM", "EN", "RO"]
NAMES = re.compile(r"\b(" + "|".join(method_names()) + r")\b")


@pytest.fixture
def window(qtbot, tmp_path):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)  # the stream as a thread: quicker
    qtbot.addWidget(win)
    win.resize(1280, 720)
    win.show()
    qtbot.waitExposed(win)
    win.blind.autosave_dir = tmp_path / "autosave"
    win.confirm = lambda title, text: True
    win.blind.confirm = lambda title, text: True
    win.tabs.setCurrentWidget(win.blind)
    yield win
    win.confirm = win.blind.confirm = lambda title, text: True
    win.close()


def _mapping(methods, seed):
    import random

    mapping = list(methods)
    random.Random(seed).shuffle(mapping)
    return mapping


def _strings_per_key(qtbot, win, seed):
    """{key: set of (where, text) naming a method} while the key plays, blind."""
    win.blind.start(seed=seed)
    out = {}
    checked = 0
    for key in range(1, len(win.blind.mapping) + 1):
        qtbot.keyClick(win.blind, getattr(Key, f"Key_{key}"))
        qtbot.waitUntil(lambda k=key: win.state.scene.method == win.blind.mapping[k - 1])
        QtWidgets.QApplication.processEvents()
        strings = visible_strings(QtWidgets.QApplication.topLevelWidgets())
        checked += len(strings)
        out[key] = {(where, text) for where, text in strings if NAMES.search(text)}
    return out, checked


@pytest.mark.parametrize("methods", [FOUR, SIX], ids=["4", "6"])
def test_no_string_in_the_window_names_the_method_behind_a_key(window, qtbot, methods):
    window.blind.set_methods(methods)
    # Two sessions whose keys hide different methods: what the window shows must not differ.
    a = 1
    b = next(s for s in range(2, 500) if all(
        x != y for x, y in zip(_mapping(methods, a), _mapping(methods, s))))  # fmt: skip
    first, n1 = _strings_per_key(qtbot, window, a)
    window.blind.cancel()
    second, n2 = _strings_per_key(qtbot, window, b)
    assert n1 > 150 and n2 > 150  # the walk reads the whole window
    leaks = {k: first[k] ^ second[k] for k in first if first[k] ^ second[k]}
    assert not leaks, leaks
    assert not NAMES.search(window.windowTitle())


def test_exports_and_presets_refuse_while_blind(window, qtbot, tmp_path):
    errors = []
    window.files.error_raised.connect(errors.append)
    window.blind.start(seed=5)
    assert not window.files.export_curves(tmp_path / "c.csv")
    assert not window.files.save_preset_file(tmp_path / "p.json")
    assert not (tmp_path / "c.csv").exists() and not (tmp_path / "p.json").exists()
    assert all("blind" in e.lower() for e in errors) and len(errors) == 2
    menu = {a.text(): a for m in window.menuBar().actions() if m.menu()
            for a in m.menu().actions()}  # fmt: skip
    assert not menu["Save preset as..."].isEnabled()
    assert not menu["Export activation curves (CSV, PNG, SVG)..."].isEnabled()
    window.controls.playback.draw_check.click()  # draw mode would switch to AS and say so
    assert not window.tune.heatmap.drawing


# --- item 7: ratings are never lost without a word ------------------------------------------


def _rate(blind, key, value=50):
    for spin in blind.rating_spins[key - 1]:
        spin.setValue(value)


def test_start_mid_session_asks_and_no_keeps_the_ratings(window, qtbot):
    blind = window.blind
    blind.start(seed=2)
    qtbot.wait(30)
    _rate(blind, 1, 70)
    mapping = list(blind.mapping)
    asked = []
    blind.confirm = lambda title, text: asked.append(text) or False
    qtbot.mouseClick(blind.start_button, QtCore.Qt.MouseButton.LeftButton)
    assert asked and "rating" in asked[0]
    assert blind.mapping == mapping and blind.rating_spins[0][0].value() == 70
    blind.confirm = lambda title, text: True
    qtbot.mouseClick(blind.start_button, QtCore.Qt.MouseButton.LeftButton)
    assert blind.rating_spins[0][0].value() == blind.NOT_RATED


def test_a_blind_session_can_be_cancelled_without_rating_everything(window, qtbot):
    blind = window.blind
    before = window.state.scene.method
    blind.start(seed=4)
    qtbot.keyClick(blind, Key.Key_2)
    qtbot.wait(30)
    _rate(blind, 2, 40)
    assert blind.cancel_button.isEnabled()
    blind.confirm = lambda title, text: False
    qtbot.mouseClick(blind.cancel_button, QtCore.Qt.MouseButton.LeftButton)
    assert blind.active  # asked, and the answer was no
    blind.confirm = lambda title, text: True
    qtbot.mouseClick(blind.cancel_button, QtCore.Qt.MouseButton.LeftButton)
    assert not blind.active and not blind.mapping
    assert window.tune.currentIndex() == 0  # the display is back
    assert window.state.scene.method == before  # the scene before the session, not a key's
    assert all(label.text() == "?" for label in blind.method_labels)  # never revealed
    assert "autosave" in blind.status.text()


def test_ratings_are_autosaved_as_they_are_entered(window, qtbot, tmp_path):
    blind = window.blind
    blind.start(seed=9)
    qtbot.wait(30)
    blind.rating_spins[0][1].setValue(33)
    path = blind.autosave_path
    assert path is not None and path.parent == tmp_path / "autosave"
    rows = list(csv.DictReader(path.read_text().splitlines()))
    assert rows[0]["smoothness"] == "33" and rows[0]["quality"] == ""
    assert all(r["method"] == "" for r in rows)  # the file does not give the mapping away
    assert rows[0]["methods"] == " ".join(blind.methods) and rows[0]["seed"] == "9"
    _rate(blind, 1)
    assert blind.reveal()
    rows = list(csv.DictReader(path.read_text().splitlines()))
    assert [r["method"] for r in rows] == blind.mapping
    assert blind.save(tmp_path / "ratings.csv") is not None
    assert not path.exists()  # saved: the autosave has done its work


def test_ctrl_q_with_unsaved_ratings_asks_first(window, qtbot):
    blind = window.blind
    blind.start(seed=3)
    qtbot.wait(30)
    blind.rating_spins[0][0].setValue(10)
    asked = []
    window.confirm = lambda title, text: asked.append(text) or False
    window.activateWindow()
    qtbot.keyClick(window, Key.Key_Q, QtCore.Qt.KeyboardModifier.ControlModifier)
    assert asked and "rating" in asked[0] and window.isVisible()
    window.confirm = lambda title, text: True
    qtbot.keyClick(window, Key.Key_Q, QtCore.Qt.KeyboardModifier.ControlModifier)
    qtbot.waitUntil(lambda: not window.isVisible())


def test_felt_time_stops_at_reveal(window, qtbot):
    blind = window.blind
    blind.start(seed=6)
    qtbot.wait(60)
    _rate(blind, 1)
    assert blind.reveal()
    felt = blind.ratings()[0]["felt_s"]
    label = blind.felt_labels[0].text()
    qtbot.wait(150)  # still playing after the reveal
    assert window.state.scene.playing
    assert blind.ratings()[0]["felt_s"] == felt and blind.felt_labels[0].text() == label
