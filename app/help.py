"""The Help menu's dialogs: the keyboard shortcuts, and what the tuner is."""

from __future__ import annotations

import html

from PySide6 import QtCore, QtWidgets

from tactile_core import __version__

from .experiments.trials import KEYS as RUN_KEYS

SHORTCUTS = (
    ("Tune, Compare", ""),
    ("1-4", "method CT, MM, AS, IM"),
    ("Space", "play or pause (also releases a held tactor)"),
    ("Esc", "all off, from anywhere (in an open menu, drop-down or dialog: closes only that)"),
    ("Enter", "in a field: commit the value and give the keys back to the window"),
    (
        "click / Shift+click a cell",
        "pulse that tactor for 0.3 s / hold it on (a change to the tuning releases it)",
    ),
    ("drag the time cursor", "scrub: the heatmap and the array hold that instant"),
    ("Pattern editor (Ctrl+E shows it; in its time line)", ""),
    ("Tab / Shift+Tab", "select the next / previous effect in time (also Ctrl+Right / Ctrl+Left)"),
    ("Left / Right", "move the effect 10 ms earlier / later (with Shift: 100 ms)"),
    ("Up / Down", "move the effect to the track above / below"),
    ("Alt+Right / Alt+Left, ] / [", "lengthen / shorten one play by 10 ms (with Shift: 100 ms)"),
    ("Delete / Ctrl+D", "delete / duplicate the effect"),
    ("Space", "play the pattern from the playhead, or pause it"),
    ("Home / End", "scrub to the pattern's start / end"),
    ("Ctrl+Z / Ctrl+Shift+Z", "undo / redo an edit (also Ctrl+Y)"),
    (
        "drag a block / its right edge / the ruler",
        "move it (snapped to 10 ms; up or down: another track) / resize it / scrub",
    ),
    ("Blind A/B", ""),
    (
        "1-8",
        "play the method behind the key (which one stays hidden until Reveal); "
        "nothing plays after Start until a key is pressed",
    ),
    ("Space", "pause or play the key selected"),
    ("During an experiment (the participant's keys)", ""),
    *((kind, text.format(n="N")) for kind, text in RUN_KEYS.items()),
    ("Esc", "pause the run, array off; Enter or Present again resumes"),
    ("Menus", ""),
    ("Ctrl+O / Ctrl+S", "open / save a preset"),
    ("Ctrl+Q", "quit (asks first during a run or with unsaved ratings)"),
    ("F1", "this list"),
)
"""``(keys, what they do)``; a row with no description is a heading."""


def shortcuts_html() -> str:
    """The keyboard shortcuts as an HTML table."""
    rows = []
    for keys, what in SHORTCUTS:
        if not what:
            rows.append(f"<tr><td colspan='2'><br><b>{html.escape(keys)}</b></td></tr>")
        else:
            rows.append(f"<tr><td><b>{html.escape(keys)}</b>&nbsp;&nbsp;</td>"
                        f"<td>{html.escape(what)}</td></tr>")  # fmt: skip
    return "<table>" + "".join(rows) + "</table>"


def about_html() -> str:
    """What the tuner is: version, the paper, the licence."""
    return (
        f"<h3>tactile-tuner {__version__}</h3>"
        "<p>Tune and compare rendering methods for a 2D vibrotactile array, after "
        "<i>Bi-level and Anti-aliased Rendering Methods for a Low-Resolution 2D Vibrotactile "
        "Array</i>: closest tactor, midpoint, area sampling, interpolated midpoint; the "
        "threshold/gamma correction; its three experiments.</p>"
        "<p>PySide6 and pyqtgraph over the numpy core <code>tactile_core</code>. MIT licence.</p>"
    )


def _dialog(parent, title: str, text: str, name: str) -> QtWidgets.QDialog:
    dialog = QtWidgets.QDialog(parent)
    dialog.setObjectName(name)
    dialog.setWindowTitle(title)
    layout = QtWidgets.QVBoxLayout(dialog)
    label = QtWidgets.QLabel(text)
    label.setTextFormat(QtCore.Qt.TextFormat.RichText)
    label.setWordWrap(True)
    label.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
    scroll = QtWidgets.QScrollArea()
    scroll.setWidget(label)
    scroll.setWidgetResizable(True)
    scroll.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
    layout.addWidget(scroll, 1)
    buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Close)
    buttons.rejected.connect(dialog.reject)
    layout.addWidget(buttons)
    dialog.resize(560, 520 if name == "shortcuts" else 260)
    dialog.setAttribute(QtCore.Qt.WidgetAttribute.WA_DeleteOnClose)
    dialog.open()
    return dialog


def show_shortcuts(parent) -> QtWidgets.QDialog:
    """Help → Keyboard shortcuts."""
    return _dialog(parent, "Keyboard shortcuts", shortcuts_html(), "shortcuts")


def show_about(parent) -> QtWidgets.QDialog:
    """Help → About tactile-tuner."""
    return _dialog(parent, "About tactile-tuner", about_html(), "about")
