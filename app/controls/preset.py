"""The preset the tuning came from: its name and its notes, which can be edited and are saved
with the next preset."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

from ..texts import tip


class PresetWidget(QtWidgets.QGroupBox):
    """The preset's name and notes (where the paper left a choice open, what was tuned for
    whom); editing the notes changes what *Save preset as...* writes (:attr:`notes_edited`)."""

    notes_edited = QtCore.Signal(str)

    def __init__(self, parent=None):
        super().__init__("Preset", parent)
        layout = QtWidgets.QVBoxLayout(self)
        self.name_label = QtWidgets.QLabel("")
        self.name_label.setObjectName("preset_name")
        self.name_label.setWordWrap(True)
        self.name_label.setTextFormat(QtCore.Qt.TextFormat.PlainText)  # a file's name, as is
        self.notes_edit = QtWidgets.QPlainTextEdit()
        self.notes_edit.setObjectName("preset_notes")
        self.notes_edit.setPlaceholderText("notes, saved with the preset")
        self.notes_edit.setToolTip(tip(
            "The preset's notes: where the paper left a choice open, what this tuning is for. "
            "Edit them here; Save preset as... writes them."
        ))  # fmt: skip
        self.notes_edit.setTabChangesFocus(True)
        self.notes_edit.setFixedHeight(self.notes_edit.fontMetrics().lineSpacing() * 4 + 12)
        layout.addWidget(self.name_label)
        layout.addWidget(self.notes_edit)
        self._showing = False
        self.notes_edit.textChanged.connect(self._on_notes_edit_changed)

    def show_preset(self, name: str, notes: str) -> None:
        """Show a preset's name and notes (without emitting :attr:`notes_edited`)."""
        self._showing = True
        try:
            self.name_label.setText(name)
            self.notes_edit.setPlainText(notes)
        finally:
            self._showing = False

    def _on_notes_edit_changed(self) -> None:
        if not self._showing:
            self.notes_edited.emit(self.notes_edit.toPlainText())
