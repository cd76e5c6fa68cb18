"""The Blind A/B tab is the view of its BlindSession: it shows the session, writes what the user
does to it, and keeps the window blind while the mapping is hidden.

What the session itself does (the mapping, felt time, the rules, the files) is in
tests/test_blind.py. Here time is the session's virtual clock: nothing sleeps.
"""

import csv
import re

import pytest
from PySide6 import QtCore, QtWidgets

from tactile_core.device.host_clock import VirtualClock
from tactile_core.files.presets import builtin_presets, load_preset
from tactile_core.rendering.methods import method_names

from .gui_strings import visible_strings
from .helpers import dealt

pytestmark = pytest.mark.usefixtures("qt_settings")
Key = QtCore.Qt.Key
FOUR, SIX = ["CT", "MM", "AS", "IM"], ["CT", "MM", "AS", "IM", "EN", "RO"]
NAMES = re.compile(r"\b(" + "|".join(method_names()) + r")\b")
RATINGS = ("quality", "smoothness", "thickness")


def _open(qtbot, tmp_path, clock, **kwargs):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False, **kwargs)  # the stream as a thread: quicker
    qtbot.addWidget(win)
    win.resize(1280, 720)
    win.show()
    qtbot.waitExposed(win)
    win.blind.session.autosave_dir = tmp_path / "autosave"
    win.blind.session.clock = clock.now
    win.confirm = lambda title, text: True
    win.blind.confirm = lambda title, text: True
    win.tabs.setCurrentWidget(win.blind)
    return win


@pytest.fixture
def clock():
    """The Blind A/B session's clock: time passes only when a test says so."""
    return VirtualClock()


@pytest.fixture
def window(qtbot, tmp_path, clock):
    win = _open(qtbot, tmp_path, clock)
    yield win
    win.confirm = win.blind.confirm = lambda title, text: True
    win.close()


def _feel(blind, clock, key, seconds=1.0):
    blind.select_key(key)
    clock.advance(seconds)


def _rate(blind, key, value=50):
    for spin in blind.rating_spins[key - 1]:
        spin.setValue(value)


# --- the view shows the session -----------------------------------------------------------------


def test_the_panel_shows_a_session_driven_directly(window, clock):
    blind, session = window.blind, window.blind.session
    session.start(seed=5)
    assert window.tune.currentIndex() == 1  # blind: the display that would give it away hides
    session.select(3)
    clock.advance(1.5)
    session.rate(3, "smoothness", 42)
    assert [b.isChecked() for b in blind.key_buttons] == [False, False, True, False]
    assert blind.rating_spins[2][1].value() == 42
    assert blind.rating_spins[2][0].text() == "not rated"
    assert blind.felt_labels[2].text() == "1.5 s" and blind.felt_labels[0].text() == "-"
    assert all(label.text() == "?" for label in blind.method_labels)
    session.rate(3, "quality", 1)
    session.rate(3, "thickness", 2)
    session.reveal()
    mapping = dealt(FOUR, 5)
    assert [label.text().split()[0] for label in blind.method_labels] == mapping
    assert window.tune.currentIndex() == 0 and not blind.reveal_button.isEnabled()


def test_blind_ab_hides_the_mapping_and_records_it(window, qtbot, tmp_path, clock):
    blind = window.blind
    blind.start(seed=7)
    mapping = list(blind.session.mapping)
    assert sorted(mapping) == ["AS", "CT", "IM", "MM"]
    assert all(label.text() == "?" for label in blind.method_labels)
    assert window.tune.currentIndex() == 1  # the display that would give it away is hidden
    assert window.controls.method.method_buttons.checkedButton() is None
    assert not window.device_panel.status_label.isVisible()
    # Every rating starts empty: nothing could pass for a rating that was never given.
    assert all(s.value() == -1 and s.text() == "not rated" for r in blind.rating_spins
               for s in r)  # fmt: skip
    for key in (3, 1, 4, 2):
        qtbot.keyClick(blind, getattr(Key, f"Key_{key}"))
        assert window.state.scene.method == mapping[key - 1]
        clock.advance(0.5)
    assert not blind.reveal()  # felt keys are not rated yet
    assert "key 1 quality" in blind.status.text()
    assert blind.save(tmp_path / "blind.csv") is None
    for k, spins in enumerate(blind.rating_spins):
        for j, spin in enumerate(spins):
            spin.setValue(10 * k + j)
    assert blind.session.rating(3, "smoothness") == 21  # the spin box wrote it to the session
    assert blind.reveal()
    assert window.tune.currentIndex() == 0
    assert [label.text().split()[0] for label in blind.method_labels] == mapping
    assert blind.save(tmp_path / "blind.csv") is not None
    rows = list(csv.DictReader((tmp_path / "blind.csv").read_text().splitlines()))
    assert [r["method"] for r in rows] == mapping and rows[2]["smoothness"] == "21"
    assert [r["felt_s"] for r in rows] == ["0.50"] * 4


def test_start_plays_nothing_until_the_raters_first_key(window, qtbot, clock):
    # Start played key 1 by itself: it was always presented first, and it counted as felt
    # (to be rated before Reveal) whether the rater chose it or not.
    blind = window.blind
    window.state.update(playing=True)  # the tuning from before plays
    blind.start(seed=4)
    session = blind.session
    assert session.current_key is None and not window.state.scene.playing
    assert not any(b.isChecked() for b in blind.key_buttons)
    qtbot.waitUntil(lambda: not window.device.sent_levels().any(), timeout=5000)  # all off
    clock.advance(3.0)
    # Space, Restart, the play button: the scene from before is no key's, and does not play
    window.tabs.setFocus()
    qtbot.keyClick(window.tabs, Key.Key_Space)
    window.state.restart()
    window.controls.playback.play_button.click()
    assert not window.state.scene.playing
    assert "press a key 1-4 first" in window.statusBar().currentMessage()
    assert session.felt_s == (0.0, 0.0, 0.0, 0.0) and session.refusal("Reveal").endswith(
        "no key was felt yet")  # fmt: skip
    qtbot.keyClick(window.tabs, Key.Key_3)  # the rater's first key
    assert window.state.scene.playing and window.state.scene.method == session.mapping[2]
    clock.advance(1.0)
    assert session.felt() == [False, False, True, False]
    qtbot.keyClick(window.tabs, Key.Key_Space)  # now Space pauses and plays that key
    assert not window.state.scene.playing
    qtbot.keyClick(window.tabs, Key.Key_Space)
    assert window.state.scene.playing and window.state.scene.method == session.mapping[2]


def test_the_reveal_refusal_follows_the_ratings_as_they_come_in(window, clock):
    # It stayed on screen, listing key 1's ratings as empty, after they had all been entered.
    blind = window.blind
    blind.start(seed=8)
    _feel(blind, clock, 1)
    _feel(blind, clock, 2)
    assert not blind.reveal()
    text = blind.status.text()
    assert "still empty: key 1 quality" in text and "key 2 thickness" in text
    _rate(blind, 1)
    text = blind.status.text()
    assert "key 1" not in text and "still empty: key 2 quality" in text
    blind.rating_spins[1][0].setValue(40)
    assert "still empty: key 2 smoothness, key 2 thickness" in blind.status.text()
    _rate(blind, 2)
    assert "still empty" not in blind.status.text()
    assert "every key you felt is rated: Reveal" in blind.status.text()
    assert blind.reveal()


def test_rating_a_key_never_played_is_refused_and_shows_not_rated(window, clock):
    blind = window.blind
    blind.start(seed=3)
    _feel(blind, clock, 1, 0.5)
    blind.rating_spins[2][0].setValue(50)  # key 3 was never played
    assert blind.rating_spins[2][0].value() == -1 and blind.session.rating(3, "quality") is None
    assert "key 3 was not played" in blind.status.text()


def test_the_felt_column_stops_at_reveal(window, clock):
    blind = window.blind
    blind.start(seed=6)
    _feel(blind, clock, 1, 0.6)
    _rate(blind, 1)
    assert blind.reveal()
    assert blind.felt_labels[0].text() == "0.6 s"
    clock.advance(5.0)  # still playing after the reveal
    _feel(blind, clock, 2)
    assert window.state.scene.playing
    assert blind.felt_labels[0].text() == "0.6 s" and blind.felt_labels[1].text() == "-"


def test_pausing_the_tuner_stops_the_felt_time(window, clock):
    blind = window.blind
    blind.start(seed=2)
    _feel(blind, clock, 1, 0.25)
    window.state.update(playing=False)  # Space: the array is off, the key is not felt
    clock.advance(10.0)
    window.state.update(playing=True)
    clock.advance(0.25)
    assert blind.session.felt_s[0] == pytest.approx(0.5)


def test_the_felt_column_counts_while_a_key_plays(window, qtbot, clock):
    # It said "-" (or 0.0 s) after key 1 had played 1.5 s, until another key was pressed.
    blind = window.blind
    blind.start(seed=4)
    qtbot.keyClick(window.blind, Key.Key_1)
    clock.advance(1.5)
    qtbot.waitUntil(lambda: blind.felt_labels[0].text() == "1.5 s", timeout=5000)  # on a timer
    clock.advance(0.75)
    qtbot.waitUntil(lambda: blind.felt_labels[0].text() == "2.2 s", timeout=5000)  # 2.25 s


def test_space_pauses_the_key_and_the_session_line_says_so(window, qtbot, clock):
    # After key 3 and Space the play button read "Play (Space)" but the session line still
    # said "playing key 3".
    blind = window.blind
    blind.start(seed=4)
    qtbot.keyClick(window.blind, Key.Key_3)
    assert blind.status.text() == "playing key 3"
    clock.advance(1.0)
    qtbot.keyClick(window.blind, Key.Key_Space)
    assert not window.state.scene.playing
    assert blind.status.text() == "key 3 paused: Space plays it again"
    assert blind.felt_labels[2].text() == "1.0 s"
    clock.advance(10.0)  # paused: not felt, and the column stays
    QtWidgets.QApplication.processEvents()
    assert blind.felt_labels[2].text() == "1.0 s"
    qtbot.keyClick(window.blind, Key.Key_Space)
    assert blind.status.text() == "playing key 3"


# --- the window stays blind ---------------------------------------------------------------------


def _strings_per_key(qtbot, win, seed):
    """{key: set of (where, text) naming a method} while the key plays, blind."""
    win.blind.start(seed=seed)
    out = {}
    checked = 0
    for key in range(1, len(win.blind.session.mapping) + 1):
        qtbot.keyClick(win.blind, getattr(Key, f"Key_{key}"))
        qtbot.waitUntil(lambda k=key: win.state.scene.method == win.blind.session.mapping[k - 1])
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
        x != y for x, y in zip(dealt(methods, a), dealt(methods, s))))  # fmt: skip
    first, n1 = _strings_per_key(qtbot, window, a)
    window.blind.cancel()
    second, n2 = _strings_per_key(qtbot, window, b)
    assert n1 > 150 and n2 > 150  # the walk reads the whole window
    leaks = {k: first[k] ^ second[k] for k in first if first[k] ^ second[k]}
    assert not leaks, leaks
    assert not NAMES.search(window.windowTitle())


def test_exports_and_presets_refuse_while_blind(window, tmp_path):
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


# --- after the reveal: the window names the revealed method -------------------------------------


def _reveal_onto(window, clock, method_wanted):
    """Play the key hiding ``method_wanted`` last, rate it, reveal."""
    blind = window.blind
    blind.start(seed=1)
    key = list(blind.session.mapping).index(method_wanted) + 1
    _feel(blind, clock, key)
    _rate(blind, key)
    window.tune.refresh()  # the plots were redrawn while hidden (their 50 ms timer fired)
    assert blind.reveal()
    return key


def test_after_reveal_the_curves_title_names_the_revealed_method_not_the_one_before(window, clock):
    window.state.update(method="IM")
    window.tune.refresh()
    assert window.tune.curves.plotItem.titleLabel.text.startswith("IM activation")
    _reveal_onto(window, clock, "CT")
    assert window.state.scene.method == "CT"
    assert window.tune.curves.plotItem.titleLabel.text.startswith("CT activation")


def test_a_reveal_that_changed_the_scene_stars_the_title(window, clock):
    # Started without a preset or a last session: the Experiment 1 line (AS) is the reference.
    assert window.windowTitle() == "tactile-tuner - Experiment 1 line - AS, mu 0.33, gamma 0.70"
    _reveal_onto(window, clock, "MM")
    assert window.windowTitle() == "tactile-tuner - Experiment 1 line * - MM, mu 0.33, gamma 0.70"


def test_a_reveal_onto_the_tuning_from_before_shows_no_star(qtbot, tmp_path, clock):
    win = _open(qtbot, tmp_path, clock, preset=load_preset(builtin_presets()["exp1-line"]))
    assert win.state.scene.method == "AS" and " * " not in win.windowTitle()
    _reveal_onto(win, clock, "AS")  # only the kind of presentation ("ab") and the restart differ
    assert win.state.scene.marker == "ab"
    assert win.windowTitle() == "tactile-tuner - Experiment 1 line - AS, mu 0.33, gamma 0.70"
    win.close()


# --- ratings are never lost without a word ------------------------------------------------------


def test_start_mid_session_asks_and_no_keeps_the_ratings(window, qtbot, clock):
    blind = window.blind
    blind.start(seed=2)
    _feel(blind, clock, 1)
    _rate(blind, 1, 70)
    mapping = blind.session.mapping
    asked = []
    blind.confirm = lambda title, text: asked.append(text) or False
    qtbot.mouseClick(blind.start_button, QtCore.Qt.MouseButton.LeftButton)
    assert asked and "rating" in asked[0]
    assert blind.session.mapping == mapping and blind.rating_spins[0][0].value() == 70
    blind.confirm = lambda title, text: True
    qtbot.mouseClick(blind.start_button, QtCore.Qt.MouseButton.LeftButton)
    assert blind.rating_spins[0][0].value() == -1 and blind.session.rating(1, "quality") is None


def test_a_blind_session_can_be_cancelled_without_rating_everything(window, qtbot, clock):
    blind = window.blind
    before = window.state.scene.method
    blind.start(seed=4)
    qtbot.keyClick(blind, Key.Key_2)
    clock.advance(1.0)
    _rate(blind, 2, 40)
    assert blind.cancel_button.isEnabled()
    blind.confirm = lambda title, text: False
    qtbot.mouseClick(blind.cancel_button, QtCore.Qt.MouseButton.LeftButton)
    assert blind.session.active  # asked, and the answer was no
    blind.confirm = lambda title, text: True
    qtbot.mouseClick(blind.cancel_button, QtCore.Qt.MouseButton.LeftButton)
    assert not blind.session.active and not blind.session.mapping
    assert window.tune.currentIndex() == 0  # the display is back
    assert window.state.scene.method == before  # the scene before the session, not a key's
    assert not window.state.scene.playing
    assert all(label.text() == "?" for label in blind.method_labels)  # never revealed
    assert "autosave" in blind.status.text()


def test_a_rating_entered_is_autosaved_at_once(window, tmp_path, clock):
    blind = window.blind
    blind.start(seed=9)
    _feel(blind, clock, 1)
    blind.rating_spins[0][1].setValue(33)
    path = blind.session.autosave_path
    assert path is not None and path.parent == tmp_path / "autosave"
    rows = list(csv.DictReader(path.read_text().splitlines()))
    assert rows[0]["smoothness"] == "33" and rows[0]["method"] == ""


def test_an_autosave_that_fails_is_said_in_the_status(window, tmp_path, clock):
    (tmp_path / "autosave").write_text("a file where the folder should be")
    blind = window.blind
    blind.start(seed=9)
    _feel(blind, clock, 1)
    blind.rating_spins[0][0].setValue(12)
    assert blind.session.rating(1, "quality") == 12  # kept in the session
    assert "could not autosave the ratings" in blind.status.text()


def test_ctrl_q_with_unsaved_ratings_asks_first(window, qtbot, clock):
    blind = window.blind
    blind.start(seed=3)
    _feel(blind, clock, 1)
    blind.rating_spins[0][0].setValue(10)
    asked = []
    window.confirm = lambda title, text: asked.append(text) or False
    window.activateWindow()
    qtbot.keyClick(window, Key.Key_Q, QtCore.Qt.KeyboardModifier.ControlModifier)
    assert asked and "rating" in asked[0] and window.isVisible()
    window.confirm = lambda title, text: True
    qtbot.keyClick(window, Key.Key_Q, QtCore.Qt.KeyboardModifier.ControlModifier)
    qtbot.waitUntil(lambda: not window.isVisible())
