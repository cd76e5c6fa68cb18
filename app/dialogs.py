"""File dialogs that remember their folder per kind of file and propose useful names.

Each kind (presets, exports, ratings, profiles, results) remembers the folder last used for it
(in the tuner's settings); a proposed name carries what the file holds (method, mu and gamma,
participant, date); a name typed without an extension gets the selected filter's.
"""

from __future__ import annotations

import datetime as dt
import html
import re
from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from .texts import value3


def today() -> str:
    """``YYYY-MM-DD``, for file names."""
    return dt.date.today().isoformat()


def tuning_tag(scene) -> str:
    """``AS-mu0.33-gamma0.70``: a scene's method and correction, for file names (to the 0.001
    of the controls: ``gamma0.143``)."""
    return f"{scene.method}-mu{value3(scene.mu)}-gamma{value3(scene.gamma)}"


def safe_name(text: str) -> str:
    """``text`` with anything but letters, digits and ``._-`` turned into ``-``."""
    return re.sub(r"[^A-Za-z0-9._-]+", "-", text).strip("-") or "untitled"


def filter_extensions(selected_filter: str) -> list[str]:
    """The extensions of a dialog filter such as ``"CSV (*.csv)"``: ``[".csv"]``."""
    return [f".{e.lower()}" for e in re.findall(r"\*\.(\w+)", selected_filter)]


def with_filter_extension(path, selected_filter: str, filters=()) -> Path:
    """``path``, with the selected filter's extension added if it has none of the filter's nor
    of the dialog's other ``filters`` (``curves.png`` typed under the CSV filter stays a PNG)."""
    path = Path(path)
    extensions = filter_extensions(selected_filter)
    known = {e for f in (selected_filter, *filters) for e in filter_extensions(f)}
    if extensions and path.suffix.lower() not in known:
        path = path.with_name(path.name + extensions[0])
    return path


def _folder(kind: str) -> str:
    value = QtCore.QSettings().value(f"folders/{kind}")
    if value and Path(str(value)).is_dir():
        return str(value)
    return str(Path.home())


def _remember(kind: str, path: Path) -> None:
    QtCore.QSettings().setValue(f"folders/{kind}", str(path.parent))


def unused_name(kind: str, name: str) -> str:
    """``name``, or ``stem-2.ext``, ``stem-3.ext``... if a file of that name is already in the
    folder last used for ``kind`` (a proposed name never points at an existing file)."""
    folder, path = Path(_folder(kind)), Path(name)
    n = 1
    while (folder / name).exists():
        n += 1
        name = f"{path.stem}-{n}{path.suffix}"
    return name


def save_path(parent, kind: str, title: str, name: str, filters: list[str], *,
              confirm_overwrite: bool = True) -> Path | None:  # fmt: skip
    """Ask where to save; the chosen path (extension added), or None if cancelled.
    ``confirm_overwrite=False``: the dialog does not ask before an existing file is chosen (the
    caller checks the path first, and asks only when the write would replace a file)."""
    start = str(Path(_folder(kind)) / name)
    dialog = QtWidgets.QFileDialog
    options = dialog.Option(0) if confirm_overwrite else dialog.Option.DontConfirmOverwrite
    path, selected = dialog.getSaveFileName(parent, title, start, ";;".join(filters), "", options)
    if not path:
        return None
    path = with_filter_extension(path, selected or filters[0], filters)
    _remember(kind, path)
    return path


def open_path(parent, kind: str, title: str, filters: list[str]) -> Path | None:
    """Ask for a file to open (starting in the folder last used for ``kind``)."""
    path, _ = QtWidgets.QFileDialog.getOpenFileName(
        parent, title, _folder(kind), ";;".join(filters)
    )
    if not path:
        return None
    path = Path(path)
    _remember(kind, path)
    return path


_PATH = re.compile(r"(?<![^\s(])(?:~|\.{1,2}|[A-Za-z]:)?[/\\]\S+")
"""A word that is a path: it starts with ``/``, ``~/``, ``./`` or ``C:\\`` (not "A/B");
with what sticks to its end."""


def message_html(text: str, metrics: QtGui.QFontMetrics, width_px: int) -> tuple[str, bool]:
    """``text`` (lines apart by a newline, paragraphs by a blank line) as a message box's rich
    text, and whether a path had to be shortened. A path is never broken (Qt broke an autosave
    path after ``/home/`` and ``blind-``): it is a line of its own that does not wrap, elided
    in the middle when wider than ``width_px``."""
    shortened, blocks = False, []
    for n, paragraph in enumerate(text.split("\n\n")):
        parts = []
        for line in paragraph.split("\n"):
            start = 0
            for found in _PATH.finditer(line):
                parts.append((False, line[start : found.start()].strip()))
                shown = metrics.elidedText(found.group(0), QtCore.Qt.TextElideMode.ElideMiddle,
                                           width_px)  # fmt: skip
                shortened |= shown != found.group(0)
                parts.append((True, shown))
                start = found.end()
            parts.append((False, line[start:].strip()))
        for i, (whole, words) in enumerate([p for p in parts if p[1]]):
            style = f"margin-top:{12 if n and not i else 0}px; margin-bottom:0px;"
            style += " white-space:pre;" if whole else ""
            blocks.append(f'<p style="{style}">{html.escape(words, quote=False)}</p>')
    return "".join(blocks), shortened


def confirm(parent, title: str, text: str) -> bool:
    """Ask yes or no (No is the default: Enter never discards anything by accident). A path in
    ``text`` stays whole on its line (:func:`message_html`); one too long for the box is
    elided in the middle, and *Show Details...* holds the whole text."""
    box = QtWidgets.QMessageBox(parent)
    box.setIcon(QtWidgets.QMessageBox.Icon.Question)
    box.setWindowTitle(title)
    screen = (
        parent.screen() if parent is not None else None
    ) or QtGui.QGuiApplication.primaryScreen()
    # QMessageBox widens its text to the screen's width less 480 px (at most 1000); the icon
    # and the margins take about 120 of that.
    room = min(screen.availableGeometry().width() - 480, 1000) - 120 if screen else 500
    rich, shortened = message_html(text, box.fontMetrics(), max(room, 240))
    box.setTextFormat(QtCore.Qt.TextFormat.RichText)
    box.setText(rich)
    box.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
    if shortened:
        box.setDetailedText(text)
    buttons = QtWidgets.QMessageBox.StandardButton
    box.setStandardButtons(buttons.Yes | buttons.No)
    box.setDefaultButton(buttons.No)
    return box.exec() == buttons.Yes


def folder_path(parent, kind: str, title: str, start: str = "") -> Path | None:
    """Ask for a folder."""
    folder = QtWidgets.QFileDialog.getExistingDirectory(parent, title, start or _folder(kind))
    if not folder:
        return None
    QtCore.QSettings().setValue(f"folders/{kind}", folder)
    return Path(folder)
