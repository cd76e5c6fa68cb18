"""The console's set-up of a session: which experiment, for whom, where the results go."""

from __future__ import annotations

from pathlib import Path

from PySide6 import QtGui, QtWidgets

from tactile_core.rendering.methods import PAPER_METHODS

from .. import dialogs
from ..widgets import MethodSetWidget

TITLES = {
    "exp1": "Experiment 1: ratings of the four methods",
    "exp2": "Experiment 2: shortest line whose direction is felt (AS)",
    "exp3": "Experiment 3: circle or square, per method",
    "calibration": "Tactor calibration: detection threshold of every tactor",
    "correction": "Tune the correction by feel: measure mu and gamma",
}


class SessionWidget(QtWidgets.QGroupBox):
    """The experiment, the participant's id (required), the results folder, the seed, the
    corner emphasis (Experiment 3), the methods (Experiments 1 and 3), the participant's
    screen; and the Start / Stop / Present again buttons, which the console connects."""

    def __init__(self, parent=None):
        super().__init__("Session", parent)
        form = QtWidgets.QFormLayout(self)
        self.experiment_combo = QtWidgets.QComboBox()
        for key, title in TITLES.items():
            self.experiment_combo.addItem(title, key)
        self.participant_edit = QtWidgets.QLineEdit()
        self.participant_edit.setObjectName("participant")
        self.participant_edit.setPlaceholderText("required: letters, digits, _ . -")
        self.participant_edit.setToolTip(
            "The participant's id (it names the folder of their results); no default, so that "
            "nobody resumes someone else's session by accident"
        )
        folder_row = QtWidgets.QHBoxLayout()
        self.folder_edit = QtWidgets.QLineEdit(str(Path.home() / "tactile-results"))
        browse = self.browse_button = QtWidgets.QPushButton("Browse...")
        browse.clicked.connect(self._on_browse_clicked)
        folder_row.addWidget(self.folder_edit)
        folder_row.addWidget(browse)
        self.seed_spin = QtWidgets.QSpinBox()
        self.seed_spin.setRange(0, 2**31 - 1)
        self.seed_spin.setToolTip("Seeds the orders and every random choice of the session")
        self.emphasis_spin = QtWidgets.QDoubleSpinBox()
        self.emphasis_spin.setRange(0.0, 0.9)
        self.emphasis_spin.setSingleStep(0.1)
        self.emphasis_spin.setToolTip(
            "Experiment 3: slow the point down near corners (0 = the paper; 4.3 suggests it)"
        )
        self.screen_combo = QtWidgets.QComboBox()
        self.screen_combo.setObjectName("participant_screen")
        self.screen_combo.setToolTip(
            "Where the participant's window goes: full screen on a screen, or a window"
        )
        self._fill_screens()
        # Long titles elide rather than widen the tab past a 1280-pixel screen.
        for combo in (self.experiment_combo, self.screen_combo):
            combo.setSizeAdjustPolicy(
                QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon
            )
            combo.setMinimumContentsLength(18)
        self.experiment_combo.setToolTip("The paper's experiment to run (Section 5)")
        form.addRow("experiment", self.experiment_combo)
        form.addRow("participant id", self.participant_edit)
        form.addRow("results folder", folder_row)
        form.addRow("seed", self.seed_spin)
        form.addRow("corner emphasis (Exp. 3)", self.emphasis_spin)
        self.methods_edit = MethodSetWidget(PAPER_METHODS, 2, 8, label=None)
        self.methods_edit.setToolTip(
            "The methods Experiments 1 and 3 compare: the paper's four by default (in the "
            "paper's 12 orders); any other set of 2-8 is ordered by a balanced Latin square"
        )
        form.addRow("methods (Exp. 1, 3)", self.methods_edit)
        form.addRow("participant window", self.screen_combo)
        buttons = QtWidgets.QHBoxLayout()
        self.start_button = QtWidgets.QPushButton("Start / resume")
        self.start_button.setObjectName("experiment_start")
        self.stop_button = QtWidgets.QPushButton("Stop")
        self.resume_button = QtWidgets.QPushButton("Present again")
        self.resume_button.setToolTip("After a pause or a lost link: present the trial again")
        self.resume_button.setEnabled(False)
        for b in (self.start_button, self.stop_button, self.resume_button):
            buttons.addWidget(b)
        form.addRow(buttons)

    def _fill_screens(self) -> None:
        self.screen_combo.clear()
        self.screen_combo.addItem("a window (this screen)", None)
        for i, screen in enumerate(QtGui.QGuiApplication.screens()):
            size = screen.geometry()
            self.screen_combo.addItem(
                f"full screen on {screen.name() or f'screen {i + 1}'} "
                f"({size.width()} x {size.height()})",
                i,
            )
        if len(QtGui.QGuiApplication.screens()) > 1:  # a second screen: the participant's
            self.screen_combo.setCurrentIndex(self.screen_combo.count() - 1)

    def set_running(self, running: bool) -> None:
        """During a run the session's fields are the run's: a participant id, experiment,
        folder or seed changed meanwhile was taken by nothing, or by a later Save; Start is
        off (it did nothing)."""
        for widget in (self.experiment_combo, self.participant_edit, self.folder_edit,
                       self.browse_button, self.seed_spin, self.emphasis_spin,
                       self.screen_combo, self.start_button):  # fmt: skip
            widget.setEnabled(not running)

    def _on_browse_clicked(self) -> None:
        folder = dialogs.folder_path(self, "results", "Results folder", self.folder_edit.text())
        if folder:
            self.folder_edit.setText(str(folder))

    @property
    def experiment(self) -> str:
        """The key of the selected experiment (``exp1`` ... ``correction``)."""
        return self.experiment_combo.currentData()

    def select(self, experiment: str) -> None:
        """Select ``experiment`` by its key."""
        self.experiment_combo.setCurrentIndex(self.experiment_combo.findData(experiment))
