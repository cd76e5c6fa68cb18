"""Playback and view: play/pause, restart, all off, the heatmap's view mode, draw mode."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

from ..state import VIEW_MODES
from ..texts import DRAW_HELP, tip
from ._common import SceneGroupWidget

VIEW_TIPS = {
    "raw": "The methods' intensities before the correction (paper 2.2-2.5).",
    "corrected": "After the threshold/gamma correction (paper 2.6).",
    "sent": "What went to the array: the device levels (23 on the palm array).",
    "felt": "What the motors would make of it: the profile's response curve.",
    "predicted": "The predicted percept (energy summation, a participant matched to "
    "mu/gamma): felt magnitude per tactor; the orange line is the felt centroid's path, "
    "the curve the felt intensity over time.",
}


class PlaybackWidget(SceneGroupWidget):
    """Play/pause, restart and all off; the view mode, values in cells and draw mode.

    All off and draw mode concern more than the scene (the window pulses, the heatmap draws):
    they are signals the window connects.
    """

    draw_mode_toggled = QtCore.Signal(bool)
    all_off_requested = QtCore.Signal()

    def __init__(self, state, parent=None):
        super().__init__("Playback and view", state, parent)
        grid = QtWidgets.QGridLayout(self)
        self.play_button = QtWidgets.QPushButton("Pause (Space)")
        self.play_button.setObjectName("play")
        # A held instant (a scrubbed trace, a held pattern moment) plays again, as Space does.
        self.play_button.clicked.connect(
            lambda: self._set(playing=self.state.held or not self.state.scene.playing)
        )
        self.restart_button = QtWidgets.QPushButton("Restart")
        self.restart_button.clicked.connect(self.state.restart)
        self.off_button = QtWidgets.QPushButton("All off (Esc)")
        self.off_button.setObjectName("all_off")
        # White on a strong red: readable on light and dark palettes alike (contrast 5.4:1).
        self.off_button.setStyleSheet(
            "QPushButton { font-weight: bold; color: white; background: #c0392b; "
            "border: 1px solid #922b21; border-radius: 3px; padding: 4px 10px; } "
            "QPushButton:pressed { background: #922b21; }"
        )
        self.off_button.clicked.connect(self.all_off_requested.emit)
        grid.addWidget(self.play_button, 0, 0)
        grid.addWidget(self.restart_button, 0, 1)
        grid.addWidget(self.off_button, 0, 2)
        self.view_buttons = QtWidgets.QButtonGroup(self)
        row = QtWidgets.QHBoxLayout()
        for i, mode in enumerate(VIEW_MODES):
            button = QtWidgets.QRadioButton(mode)
            button.setObjectName(f"view_{mode}")
            button.setToolTip(tip(VIEW_TIPS[mode]))
            self.view_buttons.addButton(button, i)
            row.addWidget(button)
        self.view_buttons.idClicked.connect(lambda i: self.state.set_view_mode(VIEW_MODES[i]))
        grid.addLayout(row, 1, 0, 1, 3)
        self.levels_check = QtWidgets.QCheckBox("values in cells")
        self.levels_check.setToolTip(tip("Write each cell's value (or device level) in it"))
        self.play_button.setToolTip(
            tip("Play or pause the trace (Space); paused, the array is off")
        )
        self.restart_button.setToolTip(tip("Start the trace again from t = 0"))
        self.off_button.setToolTip(tip("Everything off now and pause (Esc, from anywhere)"))
        self.levels_check.toggled.connect(self.state.set_show_levels)
        self.draw_check = QtWidgets.QCheckBox("draw mode (drag on the heatmap)")
        self.draw_check.setToolTip(tip(DRAW_HELP))
        self.draw_check.toggled.connect(self.draw_mode_toggled.emit)
        grid.addWidget(self.levels_check, 2, 0)
        grid.addWidget(self.draw_check, 2, 1, 1, 2)
        state.scene_changed.connect(self.refresh)
        state.view_mode_changed.connect(self.refresh)
        state.layout_changed.connect(self._on_state_layout_changed)
        self._on_state_layout_changed(state.layout)

    def _on_state_layout_changed(self, layout) -> None:
        """'predicted' needs a grid (the percept model sums a grid's tactors)."""
        button = self.view_buttons.button(VIEW_MODES.index("predicted"))
        button.setEnabled(layout.is_grid)
        button.setToolTip(tip(
            VIEW_TIPS["predicted"] if layout.is_grid else
            f"Not available on this layout ({layout.describe()}): the predicted percept is "
            "modelled on a grid of tactors."
        ))  # fmt: skip
        # (the same words on a layout: a longer label would widen the dock past its width)
        self.levels_check.setToolTip(tip(
            "Write each cell's value (or device level) in it" if layout.is_grid
            else "Write each actuator's value (or device level) on its disc, where it fits"
        ))  # fmt: skip
        self.refresh()

    def _show(self, scene) -> None:
        playing = scene.playing and not self.state.held  # a held instant is not playing
        self.play_button.setText("Pause (Space)" if playing else "Play (Space)")
        self.view_buttons.button(VIEW_MODES.index(self.state.view_mode)).setChecked(True)

    def set_felt_available(self, available: bool) -> None:
        """'felt' needs the device profile's motor response curve."""
        button = self.view_buttons.button(VIEW_MODES.index("felt"))
        button.setEnabled(available)
        button.setToolTip(tip(
            "What the motors would make of the levels sent: the profile's response curve."
            if available
            else "Not available: the device profile has no motor response curve ('response')."
        ))  # fmt: skip

    def set_draw_mode(self, on: bool) -> None:
        """Show draw mode's state in its check box (without emitting the toggle again)."""
        if self.draw_check.isChecked() != on:
            self.draw_check.blockSignals(True)
            self.draw_check.setChecked(on)
            self.draw_check.blockSignals(False)
