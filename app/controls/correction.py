"""The correction (1 - mu) I^gamma + mu: threshold and gamma, on drive or on felt amplitude, and
motor-aware drive after it."""

from __future__ import annotations

import math
import sys

from PySide6 import QtCore, QtWidgets

from ..texts import tip
from ._common import CorrectionSpinBox, SceneGroupWidget

GAMMA_MIN, GAMMA_MAX = 0.1, 10.0
"""The gamma slider's ends (log scale); the box takes any gamma the core accepts."""
_GAMMA_STEPS = 1000
GAMMA_BOX = (math.ulp(0.0), sys.float_info.max)
"""The gamma box's range: every finite gamma above 0 (a preset's, another program's)."""


def gamma_to_slider(gamma: float) -> int:
    """Slider position (0..1000, log scale) of ``gamma`` in [0.1, 10]; the end beyond them."""
    gamma = min(max(gamma, GAMMA_MIN), GAMMA_MAX)
    return round((math.log10(gamma) + 1.0) / 2.0 * _GAMMA_STEPS)


def slider_to_gamma(position: int) -> float:
    """``gamma`` at a slider position (log scale)."""
    return round(10.0 ** (2.0 * position / _GAMMA_STEPS - 1.0), 3)


class CorrectionWidget(SceneGroupWidget):
    """mu and gamma, each a slider (gamma's logarithmic) and a spin box, and whether they act
    on felt amplitude (the motor response) instead of drive."""

    def __init__(self, state, parent=None):
        super().__init__("Correction  (1 - mu) I^gamma + mu", state, parent)
        form = QtWidgets.QGridLayout(self)
        self.mu_slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.mu_slider.setRange(0, 100)
        # The value in use, written to the 0.001 the gamma slider steps in (it set 0.143 while
        # the box showed 0.14), over every value a preset or another program may set.
        self.mu_spin = CorrectionSpinBox(0.0, 1.0)
        self.gamma_slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.gamma_slider.setRange(0, _GAMMA_STEPS)
        self.gamma_spin = CorrectionSpinBox(*GAMMA_BOX, relative=True)
        mu_tip = tip(
            "Threshold mu, 0-1 of full drive (paper 2.6): the least a lit tactor gets, "
            "(1 - mu) I^gamma + mu. The paper uses 0.33."
        )
        gamma_tip = tip(
            "Gamma, above 0, no unit (paper 2.6): below 1 raises weak intensities, above 1 lowers "
            "them. The paper uses 0.7 (1.4 in two stages of Experiment 2). The slider spans "
            "0.1-10 on a log scale (at its end beyond); the box takes any value."
        )
        for widget in (self.mu_slider, self.mu_spin):
            widget.setToolTip(mu_tip)
        for widget in (self.gamma_slider, self.gamma_spin):
            widget.setToolTip(gamma_tip)
        form.addWidget(QtWidgets.QLabel("threshold mu"), 0, 0)
        form.addWidget(self.mu_slider, 0, 1)
        form.addWidget(self.mu_spin, 0, 2)
        form.addWidget(QtWidgets.QLabel("gamma (log)"), 1, 0)
        form.addWidget(self.gamma_slider, 1, 1)
        form.addWidget(self.gamma_spin, 1, 2)
        self.mu_slider.valueChanged.connect(lambda v: self._set(mu=v / 100.0))
        self.mu_spin.valueChanged.connect(lambda v: self._set(mu=v))
        self.gamma_slider.valueChanged.connect(lambda v: self._set(gamma=slider_to_gamma(v)))
        self.gamma_spin.valueChanged.connect(lambda v: self._set(gamma=v))
        for spin, what in ((self.mu_spin, "mu must be within [0, 1]"),
                           (self.gamma_spin, "gamma must be a finite number above 0")):  # fmt: skip
            spin.refused.connect(
                lambda text, what=what: state.message_posted.emit(
                    f"not taken: {what}, got {text} (the value in use is kept)", 10_000
                )
            )
        self.felt_domain_check = QtWidgets.QCheckBox("on felt amplitude (motor response)")
        self.felt_domain_check.setObjectName("felt_domain")
        self.felt_domain_check.toggled.connect(lambda on: self._set(felt_domain=on))
        form.addWidget(self.felt_domain_check, 2, 0, 1, 3)
        self.motor_drive_check = QtWidgets.QCheckBox("motor-aware drive (spin-up overdrive)")
        self.motor_drive_check.setObjectName("compensate_motors")
        self.motor_drive_check.toggled.connect(lambda on: self._set(compensate_motors=on))
        form.addWidget(self.motor_drive_check, 3, 0, 1, 3)
        state.scene_changed.connect(self.refresh)
        self.refresh()

    def _show(self, scene) -> None:
        self.felt_domain_check.setChecked(scene.felt_domain)
        self.motor_drive_check.setChecked(scene.compensate_motors)
        self.mu_slider.setValue(round(scene.mu * 100))
        self.mu_spin.setValue(scene.mu)
        self.gamma_slider.setValue(gamma_to_slider(scene.gamma))
        self.gamma_spin.setValue(scene.gamma)

    def set_felt_available(self, available: bool) -> None:
        """The felt-amplitude domain needs the device profile's motor response curve."""
        self.felt_domain_check.setEnabled(available)
        self.felt_domain_check.setToolTip(tip(
            "mu and gamma act on felt amplitude: the corrected value is the motor output "
            "wanted, and the array gets the least drive that gives it (the inverse of the "
            "profile's response curve). Off: on drive, as the paper."
            if available
            else "Not available: the device profile has no motor response curve ('response')."
        ))  # fmt: skip

    def set_motor_available(self, available: bool, motors: str = "") -> None:
        """Motor-aware drive needs the device profile's motor time constants; ``motors`` says
        which (:meth:`MotorResponse.describe <tactile_core.rendering.motor.MotorResponse.describe>`:
        measured or estimates)."""
        self.motor_drive_check.setEnabled(available)
        self.motor_drive_check.setToolTip(tip(
            "After the correction, each lit tactor's drive makes up for its motor's lag (the "
            f"profile's time constants{': ' + motors if motors else ''}): full drive while it "
            "spins up, off while it runs down. Off: plain drive, as the paper."
            if available
            else "Not available: the device profile has no motor time constants ('motor')."
        ))  # fmt: skip
