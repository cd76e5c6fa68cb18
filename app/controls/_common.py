"""What the control boxes share: a spin box for one scene field, and the write-back guard."""

from __future__ import annotations

from PySide6 import QtWidgets

from ..texts import value3
from ..widgets import spin_box  # noqa: F401 (the boxes' spin box, shared with the editor)


class CorrectionSpinBox(QtWidgets.QDoubleSpinBox):
    """A spin box for mu or gamma that writes its value as the titles and the status line do
    (:func:`~app.texts.value3`: ``0.70``, ``0.142``), not always to three decimals."""

    def textFromValue(self, value: float) -> str:  # Qt override
        return value3(value)


class SceneGroupWidget(QtWidgets.QGroupBox):
    """A group of controls that writes scene fields to the state and shows the state's values.

    While :meth:`refresh` shows the state's values, the widgets' change signals are not written
    back (``_updating``).
    """

    def __init__(self, title: str, state, parent=None):
        super().__init__(title, parent)
        self.state = state
        self._updating = False

    def _set(self, **changes) -> None:
        if not self._updating:
            self.state.update(**changes)

    def refresh(self, *_) -> None:
        """Show the state's values (without writing them back)."""
        self._updating = True
        try:
            self._show(self.state.scene)
        finally:
            self._updating = False

    def _show(self, scene) -> None:  # each box shows its own fields
        raise NotImplementedError
