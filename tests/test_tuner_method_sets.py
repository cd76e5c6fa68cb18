"""The method set of Compare and of Blind A/B, typed in a field: Enter applies it, and a set that
is refused stays explained under the field, in red, until another set is applied."""

import pytest
from PySide6 import QtCore

from .tuner_support import WAIT_MS

Key = QtCore.Qt.Key


def _chooser(window, tab):
    part = window.compare if tab == "compare" else window.blind
    window.tabs.setCurrentWidget(part)
    return part.chooser


def _type(qtbot, chooser, text):
    """Click into the field, replace its text as a user types it, press Enter."""
    chooser.edit.setFocus()
    qtbot.waitUntil(chooser.edit.hasFocus, timeout=WAIT_MS)
    chooser.edit.selectAll()
    qtbot.keyClicks(chooser.edit, text)
    qtbot.keyClick(chooser.edit, Key.Key_Return)
    # Enter gives the keys back to the window (the field loses the focus): wait for that
    qtbot.waitUntil(lambda: not chooser.edit.hasFocus(), timeout=WAIT_MS)


@pytest.mark.parametrize("tab", ["compare", "blind"])
def test_a_refused_set_stays_explained_after_enter(window, qtbot, tab):
    # Enter applied the set, refused it, and then gave the focus back to the window: the field's
    # editingFinished came again with the set restored, which hid the reason.
    chooser = _chooser(window, tab)
    before = list(chooser.methods)
    _type(qtbot, chooser, "AS XX RO:r=abc")
    assert chooser.problem.isVisible()
    assert (
        "got 'XX'" in chooser.problem.text() and "method must be one of" in chooser.problem.text()
    )
    assert chooser.methods == before and chooser.edit.text() == " ".join(before)
    _type(qtbot, chooser, "AS IM")  # a good set applies, and the reason goes
    assert chooser.methods == ["AS", "IM"] and not chooser.problem.isVisible()


def test_a_refused_set_stays_explained_when_the_field_loses_the_focus(window, qtbot):
    chooser = _chooser(window, "compare")
    chooser.edit.setFocus()
    qtbot.waitUntil(chooser.edit.hasFocus, timeout=WAIT_MS)
    chooser.edit.selectAll()
    qtbot.keyClicks(chooser.edit, "CT")  # one method: fewer than two
    window.tabs.setFocus()  # Tab, or a click elsewhere
    qtbot.waitUntil(chooser.problem.isVisible, timeout=WAIT_MS)
    assert "choose 2 to 6 methods, got 1" in chooser.problem.text()
    chooser.edit.setFocus()  # back in, and out again without typing: still explained
    qtbot.waitUntil(chooser.edit.hasFocus, timeout=WAIT_MS)
    window.tabs.setFocus()
    qtbot.waitUntil(lambda: not chooser.edit.hasFocus(), timeout=WAIT_MS)
    assert chooser.problem.isVisible()
