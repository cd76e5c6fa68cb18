"""The tuner's application-wide keys: Esc, Space and the number keys, wherever the focus is."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets


def is_text_input(widget) -> bool:
    """True for a widget that takes typed text (a field, a spin box, an editable drop-down)."""
    if isinstance(
        widget,
        (QtWidgets.QLineEdit, QtWidgets.QAbstractSpinBox, QtWidgets.QTextEdit,
         QtWidgets.QPlainTextEdit),
    ):  # fmt: skip
        return True
    return isinstance(widget, QtWidgets.QComboBox) and widget.isEditable()


class KeyFilter(QtCore.QObject):
    """Application-wide keys (an event filter on the application).

    - **Esc** turns everything off from anywhere in the window, even with the cursor in a text
      box; but with a menu, a drop-down or a dialog open, Esc is theirs (it closes them).
    - **Space** and **1-8** (play/pause, methods) act unless a text input has the focus, so
      typing ``COM2`` or ``0.35`` never switches the method; Space is a widget's own when it
      says so (``takes_space``: the pattern editor's time line plays its pattern). **Enter**
      in a field commits its value and gives the keys back to the window.
    - During an experiment the run owns the keyboard.

    The window says what the keys do, with callables.

    Parameters
    ----------
    windows : callable
        The windows whose keys these are (the main window, the participant's).
    run_only : callable, optional
        Of those, the windows whose keys count only during a run (the participant's, which
        may stay open on its "finished" screen): at other times only their Esc acts.
    on_escape : callable
        Esc: everything off (and a run paused).
    run_active : callable
        Whether a run owns the keyboard now.
    on_run_key : callable
        A key event during a run; True if the run used it.
    on_space : callable
        Space: play or pause.
    on_number : callable
        A number key 1-8; True if it meant something.
    on_return : callable
        After Enter in a field: give the keys back to the window.
    """

    def __init__(self, parent, *, windows, on_escape, run_active, on_run_key, on_space,
                 on_number, on_return, run_only=tuple):  # fmt: skip
        super().__init__(parent)
        self.windows = windows
        self.run_only = run_only
        self.on_escape = on_escape
        self.run_active = run_active
        self.on_run_key = on_run_key
        self.on_space = on_space
        self.on_number = on_number
        self.on_return = on_return

    def eventFilter(self, obj, event):  # Qt override
        if event.type() != QtCore.QEvent.Type.KeyPress or event.isAutoRepeat():
            return False
        app = QtWidgets.QApplication
        if app.activePopupWidget() is not None or app.activeModalWidget() is not None:
            first = app.focusWidget() or app.activeModalWidget() or app.activePopupWidget()
            if event.key() == QtCore.Qt.Key.Key_Escape and self.run_active() and obj is first:
                self.on_escape()  # during a run Esc stops the array whatever is open (once)
            return False  # a menu, a drop-down list or a dialog: Esc closes it, nothing more
        active = app.activeWindow()
        ours = self.windows()
        if active is not None and active not in ours:
            return False  # another window: its keys are its own
        if not isinstance(obj, QtWidgets.QWidget) or obj.window() not in ours:
            return False  # the event on its way to a widget's parent: act on it once
        key = event.key()
        if key == QtCore.Qt.Key.Key_Escape:
            self.on_escape()
            return False
        if self.run_active():
            # A run owns the keyboard (its rating box takes digits and Enter itself).
            return self.on_run_key(event)
        if obj.window() in self.run_only():
            return True  # the participant's keys, with no run: nothing may play
        focus = app.focusWidget()
        if is_text_input(focus):
            multi_line = isinstance(focus, (QtWidgets.QPlainTextEdit, QtWidgets.QTextEdit))
            if key in (QtCore.Qt.Key.Key_Return, QtCore.Qt.Key.Key_Enter) and not multi_line:
                # Let the field commit its value first, then give the keys back.
                QtCore.QTimer.singleShot(0, self.on_return)
            return False
        if key == QtCore.Qt.Key.Key_Space:
            if getattr(focus, "takes_space", False):
                return False  # a view that plays on its own (the pattern editor's time line)
            self.on_space()
            return True
        if QtCore.Qt.Key.Key_1 <= key <= QtCore.Qt.Key.Key_8:
            return self.on_number(key - QtCore.Qt.Key.Key_1 + 1)
        return False
