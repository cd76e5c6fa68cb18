"""The tuner's window fits the screen it is on: at 1280 x 720 every tab fits and the controls
never scroll sideways, titles and problems stay inside their panels, a saved size larger than
the screen is fitted, docs come back from the View menu, choices come back with the next
start, and --screenshot writes the size asked or refuses a path before starting."""

import itertools
import os
import subprocess
import sys

import pytest
from PySide6 import QtCore, QtGui, QtWidgets

from .tuner_support import WAIT_MS, settle

Key = QtCore.Qt.Key


def _right_edge(widget, window):
    return widget.mapTo(window, QtCore.QPoint(widget.width(), 0)).x()


def test_the_view_menu_brings_a_closed_dock_back(window, qtbot):
    actions = {a.text(): a for a in window.view_menu.actions()}
    window.controls_dock.close()
    assert not actions["Controls panel"].isChecked()
    actions["Controls panel"].trigger()
    assert window.controls_dock.isVisible()
    window.device_dock.setFloating(True)
    window.reset_layout()
    assert not window.device_dock.isFloating() and window.device_dock.isVisible()


def test_a_saved_size_larger_than_the_screen_is_fitted(qtbot, qt_settings):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False)
    qtbot.addWidget(win)
    win.resize(5000, 4000)
    win.fit_to_screen()
    area = win.screen().availableGeometry()
    assert win.frameGeometry().width() <= area.width()
    assert win.frameGeometry().height() <= area.height()
    win.close()


def test_at_1280x720_the_controls_never_scroll_sideways(window, qtbot):
    window.resize(1280, 720)
    settle()
    scroll = window.controls_scroll
    assert scroll.horizontalScrollBarPolicy() == QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff
    assert scroll.viewport().width() >= window.controls.minimumSizeHint().width()


def test_at_1280x720_the_window_fits_on_every_tab(window, qtbot):
    # The window cannot be narrower than its widest tab: one wide tab widened it to 1472 px.
    for i in range(window.tabs.count()):
        window.tabs.setCurrentIndex(i)
        window.resize(1280, 720)
        settle()
        assert window.minimumSizeHint().width() <= 1280, window.tabs.tabText(i)
        assert window.width() <= 1280, window.tabs.tabText(i)
    window.tabs.setCurrentIndex(0)


@pytest.mark.parametrize("size", [(1280, 720), (1600, 1000)])
def test_the_curve_title_and_hint_fit_their_panel(window, qtbot, size):
    # A title wider than its plot is cut off at the right (it was, at 1600 x 1000).
    window.resize(*size)
    settle()
    window.tune.fit_heatmap()
    settle()
    title = window.tune.curves.plotItem.titleLabel.item.boundingRect().width()
    assert 0 < title <= window.tune.curves.width()
    hint = window.findChild(QtWidgets.QLabel, "curves_hint")
    assert hint.minimumSizeHint().width() == 0  # elides; never sets the panel's width
    assert "drag the dashed cursor" in hint.toolTip()


def _title_shown_whole(view) -> bool:
    """Whether a plot view's title lies inside it, and its plot too (pyqtgraph widens a plot
    to its title's width, pushing the plot and the title's ends out of the view)."""
    item = view.plotItem.titleLabel.item
    shown = view.mapFromScene(item.mapRectToScene(item.boundingRect())).boundingRect()
    plot = view.plotItem.geometry()
    inside = shown.left() >= 0 and shown.right() <= view.viewport().width()
    return inside and plot.right() <= view.viewport().width() + 1


@pytest.mark.parametrize("size", [(1280, 720), (1400, 900), (1600, 1000)])
def test_the_felt_views_curve_title_is_shown_whole_with_its_values(window, qtbot, size):
    # At 1400 px it read "IM felt (motor lag and response), motor-aware drive, mu 0.33, gamma"
    window.state.update(method="IM", mu=0.33, gamma=0.7, compensate_motors=True)
    window.state.set_view_mode("felt")
    window.resize(*size)
    settle()
    window.tune.fit_heatmap()
    settle()
    window.tune.refresh()
    settle()
    curves = window.tune.curves
    text = curves.plotItem.titleLabel.text
    assert "IM felt" in text and "motor-aware" in text and text.endswith("mu 0.33, gamma 0.70")
    assert _title_shown_whole(curves)


@pytest.mark.parametrize("n", [4, 5, 6])
@pytest.mark.parametrize("size", [(1280, 720), (1600, 1000)])
def test_compare_titles_say_each_columns_correction_inside_it(window, qtbot, size, n):
    # With 5 or 6 methods the titles were left out (a title had widened its plot past the
    # column); shown, they did so again once the column had its width.
    methods = ["CT", "MM", "AS", "IM", "EN", "VRCH"][:n]
    window.resize(*size)
    window.tabs.setCurrentWidget(window.compare)
    assert window.compare.chooser.apply(methods)
    settle()
    for spec, view in window.compare.curves.items():
        qtbot.waitUntil(lambda v=view: _title_shown_whole(v), timeout=WAIT_MS)
        text = view.plotItem.titleLabel.text
        assert text.startswith(spec), text  # the method, at least
        if n <= 5:  # and how it is corrected, on one line or two
            said = {"EN": "no correction", "VRCH": "threshold only"}.get(spec, "set correction")
            assert said in text, text


@pytest.mark.parametrize("width", [1280, 1400, 1600])
def test_a_refused_method_set_is_shown_inside_the_window(window, qtbot, width):
    window.resize(width, 720)
    for tab, chooser in ((window.compare, window.compare.chooser),
                         (window.blind, window.blind.chooser)):  # fmt: skip
        window.tabs.setCurrentWidget(tab)
        chooser.edit.setText("CT XX")
        qtbot.keyClick(chooser.edit, Key.Key_Return)
        problem = chooser.problem
        qtbot.waitUntil(problem.isVisible, timeout=WAIT_MS)
        assert "XX" in problem.text()
        assert _right_edge(problem, window) <= window.width()
        lines = max(1, problem.height() // problem.fontMetrics().lineSpacing())
        assert problem.fontMetrics().horizontalAdvance(problem.text()) <= problem.width() * lines
        assert chooser.pick.width() >= chooser.pick.sizeHint().width()  # "pick" not clipped


def test_serving_keeps_the_window_at_1280_with_the_lsl_state_on_a_line_of_its_own(window, qtbot):
    # Serving at 1280 x 720 made the window 1320 px wide, and "LSL markers: off" sat squeezed
    # at the end of the counters' line.
    window.serve.port = 0  # any free port
    assert window.serve.set_serving(True)
    qtbot.waitUntil(lambda: window.serve.serving == "on", timeout=WAIT_MS)
    box = window.serve_panel
    qtbot.waitUntil(lambda: box.counters.text().startswith("malformed"), timeout=WAIT_MS)
    window.resize(1280, 720)
    settle()
    assert window.width() <= 1280 and window.minimumSizeHint().width() <= 1280
    lines = (box.toggle, box.traffic, box.counters, box.lsl_label)
    for above, below in itertools.pairwise(lines):  # one under the other, none beside another
        assert above.geometry().bottom() < below.geometry().top()
    assert box.lsl_label.text() == "LSL markers: off"
    for label in (box.traffic, box.counters, box.lsl_label):
        assert _right_edge(label, window) <= window.width()
        needed = label.fontMetrics().horizontalAdvance(label.text())
        lines = max(1, label.height() // label.fontMetrics().lineSpacing())
        assert needed <= label.width() * lines  # shown whole (wrapped, if need be)
    assert window.serve.set_serving(False)


def test_felt_amplitude_keeps_the_plots_inside_a_1280_window(window, qtbot):
    check = window.controls.correction.felt_domain_check
    assert check.isEnabled()
    for on in (True, False, True):
        check.setChecked(on)
        qtbot.waitUntil(lambda on=on: window.tune.correction._felt_domain == on, timeout=WAIT_MS)
        settle()
        window.tune.fit_heatmap()
        for view in (window.tune.correction, window.tune.curves):
            assert _right_edge(view, window) <= window.width(), on
            # the plot inside its view: never pushed past it by a title wider than the view
            assert view.plotItem.geometry().right() <= view.viewport().width() + 1, on
            assert view.width() >= 250


def test_compare_methods_and_results_folder_come_back(qtbot, qt_settings, tmp_path):
    from tactile_tuner.window import MainWindow

    first = MainWindow(restore=True)
    qtbot.addWidget(first)
    first.compare.chooser.apply(["AS", "IM", "EN"])
    first.experiments.setup.folder_edit.setText(str(tmp_path / "study"))
    first.close()
    second = MainWindow(restore=True)
    qtbot.addWidget(second)
    assert second.compare.methods == ["AS", "IM", "EN"]
    assert second.experiments.setup.folder_edit.text() == str(tmp_path / "study")
    second.close()


def test_screenshot_size_is_the_size_asked(tmp_path):
    out = tmp_path / "shot.png"
    env = {"QT_QPA_PLATFORM": "offscreen", "HOME": str(tmp_path), "PATH": "/usr/bin:/bin"}
    proc = subprocess.run(
        [sys.executable, "-m", "tactile_tuner.main", "--screenshot", str(out), "--size",
         "1280x720"], capture_output=True, text=True, timeout=120, env=env,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    image = QtGui.QImage(str(out))
    assert (image.width(), image.height()) == (1280, 720)


@pytest.mark.parametrize("where", ["missing/shot.png", "fifo.png", "folder.png", "shot.txt"])
def test_screenshot_refuses_a_path_it_cannot_write_before_starting(tmp_path, where):
    os.mkfifo(tmp_path / "fifo.png")
    (tmp_path / "folder.png").mkdir()
    proc = subprocess.run(
        [sys.executable, "-m", "tactile_tuner.main", "--screenshot", str(tmp_path / where)],
        capture_output=True, text=True, timeout=60,
        env={"QT_QPA_PLATFORM": "offscreen", "HOME": str(tmp_path), "PATH": "/usr/bin:/bin"},
    )  # fmt: skip
    # It said "saved ..." and exited 0 with nothing written; the FIFO blocked for ever.
    assert proc.returncode == 2 and "--screenshot" in proc.stderr
    assert "saved" not in proc.stdout


class X11Window:
    """A top-level window as an X11 window manager places one: moved by its frame (a title bar
    ``title`` px high above it); before it is framed, Qt reports its own rectangle as its frame."""

    def __init__(self, x, y, w, h, screen=(1280, 720), title=20):
        from PySide6 import QtCore

        self.rect = QtCore.QRect(x, y, w, h)
        self.title, self.framed = title, False
        self.area = QtCore.QRect(0, 0, *screen)

    def screen(self):
        return type("Screen", (), {"availableGeometry": lambda _: self.area})()

    def geometry(self):
        return self.rect

    def frameGeometry(self):
        if not self.framed:
            return self.rect
        return self.rect.adjusted(0, -self.title, 0, 0)

    def width(self):
        return self.rect.width()

    def height(self):
        return self.rect.height()

    def resize(self, w, h):
        self.rect.setSize(type(self.rect.size())(w, h))

    def move(self, x, y):  # the frame's corner: the window sits a title bar lower
        self.rect.moveTo(x, y + self.title)


def test_a_window_that_fits_comes_back_where_it_was_at_every_start():
    # The window came back 20 px lower at every start (y 45 -> 65 -> 85): fit_window moved it
    # to its own place before it was framed, and Qt places a window by its frame.
    from tactile_tuner.settings import fit_window

    y = 45
    for _ in range(3):  # three starts, each restoring where the last one was
        win = X11Window(100, y, 1000, 600)
        fit_window(win)
        win.framed = True
        fit_window(win)  # again once framed, as the tuner does after show()
        assert (win.geometry().x(), win.geometry().y()) == (100, 45)
        y = win.geometry().y()


def test_a_session_from_a_larger_screen_fits_a_1280x720_one_with_its_title_bar():
    # A 1600 x 1000 session restored at 1280 x 720 came back 1278 x 694 at y 45: 19 px of it,
    # the status bar, below the screen.
    from tactile_tuner.settings import fit_window

    win = X11Window(0, 45, 1600, 1000)
    fit_window(win)  # before show(): the frame not known yet
    win.framed = True  # shown, framed by the window manager: it fits as it is
    frame = win.frameGeometry()
    assert frame.top() >= 0 and frame.bottom() <= 719 and frame.right() <= 1279
    assert win.height() >= 720 - 32  # shrunk for a title bar, not more
    fit_window(win)  # the tuner's second look after show() changes nothing then
    assert win.frameGeometry() == frame


def test_a_size_asked_for_larger_than_the_screen_keeps_its_title_bar_on_it():
    # --size 1600x1000 on a 1280 x 720 screen put the window at y -285: its title bar, by
    # which it is moved, above the screen.
    from tactile_tuner.settings import fit_window

    win = X11Window(0, 45, 1600, 1000)
    fit_window(win, keep_size=True)
    win.framed = True
    fit_window(win, keep_size=True)
    assert (win.width(), win.height()) == (1600, 1000)  # the size asked for
    assert win.frameGeometry().topLeft().toTuple() == (0, 0)
