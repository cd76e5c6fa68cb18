"""Tuning the correction by feel, guided: what the console says before, and the result after.

The procedure itself is an experiment ("correction", :mod:`tactile_core.experiments.tuning`)
run from the console. Here: the console's introduction, keeping a measured correction in the
participant's folder, and :class:`GuidedTuning`, which shows the result in a dialog that applies
it to the tuner or saves it as a preset.
"""

from __future__ import annotations

from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.device.profile import default_profile
from tactile_core.experiments import TuningPlan, save_correction
from tactile_core.experiments.tuning import default_layout

from ..texts import value3


def planned_trials(plan: TuningPlan | None = None, grid=None) -> int:
    """How many trials tuning by feel presents: its two introductions, the threshold trials
    of every tactor, the gamma trials of both places and the corner trials (the runner's
    ``total``, which the console's progress bar counts)."""
    plan = plan or TuningPlan()
    tactors, _ = default_layout(grid or default_profile().layout)
    if plan.tactors is not None:
        tactors = plan.tactors
    return 2 + len(tactors) * plan.threshold_trials + 2 * plan.gamma_trials + plan.corner_trials


def tuning_intro() -> str:
    """What the console says when the experimenter asks to tune the correction by feel."""
    trials = planned_trials()
    return (
        f"Tune by feel: type the id, then Start. {trials} trials (about "
        f"{round(trials * 3.2 / 60)} min): mu, then gamma. Esc pauses, array off."
    )


def keep_correction(runner, result):
    """Save a measured correction (record and preset) in the participant's folder.

    Returns
    -------
    preset : Path or None
        The preset written, None if it could not be.
    error : str
        Why not ("" when it was saved).
    """
    try:
        _, preset = save_correction(runner, result)
    except (OSError, ValueError) as exc:
        return None, f"could not save the correction: {exc}"
    return preset, ""


class TuningResultDialog(QtWidgets.QDialog):
    """The result of tuning the correction by feel: mu and gamma with their intervals, and
    *Apply* (to the tuner now) and *Save as preset...*; without a correction, why not."""

    applied = QtCore.Signal()
    save_requested = QtCore.Signal()

    def __init__(self, result, preset_path=None, parent=None):
        super().__init__(parent)
        self.setWindowTitle("Correction measured" if result.ok else "No correction")
        self.setObjectName("tuning_result")
        layout = QtWidgets.QVBoxLayout(self)
        text = QtWidgets.QPlainTextEdit(result.summary())
        text.setReadOnly(True)
        text.setFont(QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont))
        text.setMinimumSize(520, 220)
        layout.addWidget(text)
        if preset_path is not None:
            where = QtWidgets.QLabel(f"Kept in {preset_path.parent} (correction.json and "
                                     f"{preset_path.name}).")  # fmt: skip
            where.setWordWrap(True)
            layout.addWidget(where)
        buttons = QtWidgets.QDialogButtonBox()
        self.apply_button = buttons.addButton(
            "Apply", QtWidgets.QDialogButtonBox.ButtonRole.AcceptRole
        )
        self.save_button = buttons.addButton(
            "Save as preset...", QtWidgets.QDialogButtonBox.ButtonRole.ActionRole
        )
        buttons.addButton(QtWidgets.QDialogButtonBox.StandardButton.Close)
        for b in (self.apply_button, self.save_button):
            b.setEnabled(result.ok)
        self.apply_button.setToolTip("Set the tuner's mu and gamma to the measured ones")
        self.apply_button.clicked.connect(self.applied)
        self.apply_button.clicked.connect(self.accept)
        self.save_button.clicked.connect(self.save_requested)
        buttons.rejected.connect(self.reject)
        layout.addWidget(buttons)


class GuidedTuning(QtCore.QObject):
    """The window's side of tuning by feel: the measured correction in a dialog (kept as
    :attr:`dialog`) whose *Apply* sets the state's mu and gamma, and whose *Save as preset...*
    applies them and asks the window to save a preset (:attr:`save_preset_requested`).

    Parameters
    ----------
    state : TunerState
    parent : QWidget
        The dialogs' parent (the main window).
    """

    message_posted = QtCore.Signal(str, int)
    save_preset_requested = QtCore.Signal()

    def __init__(self, state, parent):
        super().__init__(parent)
        self.state = state
        self.dialog: TuningResultDialog | None = None

    def show_result(self, result, preset_path) -> None:
        """Show a tuning run's result (with or without a correction)."""
        self.dialog = dialog = TuningResultDialog(result, preset_path, self.parent())
        dialog.applied.connect(lambda: self.apply(result.mu, result.gamma))
        dialog.save_requested.connect(lambda: self.apply(result.mu, result.gamma))
        dialog.save_requested.connect(self.save_preset_requested)
        dialog.setAttribute(QtCore.Qt.WidgetAttribute.WA_DeleteOnClose)
        dialog.open()

    def apply(self, mu: float, gamma: float) -> None:
        """Set the tuner's mu and gamma (a measured correction)."""
        self.state.update(mu=mu, gamma=gamma)
        self.message_posted.emit(f"applied the measured correction: mu {value3(mu)}, "
                                 f"gamma {value3(gamma)}", 8000)  # fmt: skip
