"""Control panels: method, correction, shape, timing and playback; the device panel."""

from __future__ import annotations

import math

from PySide6 import QtCore, QtWidgets
from serial.tools import list_ports

import tactile_core as tc
from tactile_core.rendering.methods import (
    METHODS,
    PAPER_METHODS,
    UNAVAILABLE,
    get_method,
    method_names,
)

from .device import DeviceController
from .state import VIEW_MODES, TunerState

GAMMA_MIN, GAMMA_MAX = 0.1, 10.0
_GAMMA_STEPS = 1000

DRAW_HELP = (
    "MM and IM pick one tactor per column (or row) of a stroke of the shape, so they need a "
    "shape: a free point has no stroke. CT and AS depend on the point alone, as the paper "
    "notes for its touchpad."
)


def gamma_to_slider(gamma: float) -> int:
    """Slider position (0..1000, log scale) of ``gamma`` in [0.1, 10]."""
    gamma = min(max(gamma, GAMMA_MIN), GAMMA_MAX)
    return round((math.log10(gamma) + 1.0) / 2.0 * _GAMMA_STEPS)


def slider_to_gamma(position: int) -> float:
    """``gamma`` at a slider position (log scale)."""
    return round(10.0 ** (2.0 * position / _GAMMA_STEPS - 1.0), 3)


def tip(text: str) -> str:
    """A tooltip that wraps (rich text) instead of one line as wide as the screen."""
    return f"<qt>{text}</qt>"


METHOD_TIPS = {
    "CT": "Closest tactor (paper 2.2): the tactor of the cell containing the point, at full "
    "intensity. Bi-level.",
    "MM": "Midpoint (paper 2.3): one tactor per column (row) of a stroke, as a scan-converted "
    "line. Bi-level.",
    "AS": "Area sampling (paper 2.4): each of up to 4 tactors gets the overlap of a unit box "
    "around the point. Anti-aliased.",
    "IM": "Interpolated midpoint (paper 2.5): MM's tactors, intensity interpolated between "
    "column centres. Anti-aliased.",
    "EN": "Energy model (Tactile Brush, Israr and Poupyrev 2011) on AS's cells: sqrt of the "
    "areas, so the squares sum to 1.",
    "PK": "Inverse distance over the 3 nearest tactors (Park et al. 2016), energy-normalised.",
    "RO": "Smoothstep roll-off within radius r (Syntacts' spatializer).",
    "GS": "Gaussian weights of spread sigma, cut below 0.05 (VRCH-Server and others).",
}


def _spin(lo, hi, step, decimals, suffix="") -> QtWidgets.QDoubleSpinBox:
    box = QtWidgets.QDoubleSpinBox()
    box.setRange(lo, hi)
    box.setSingleStep(step)
    box.setDecimals(decimals)
    box.setKeyboardTracking(False)
    if suffix:
        box.setSuffix(suffix)
    return box


class ControlsPanel(QtWidgets.QWidget):
    """Widgets that write to :class:`TunerState` and follow it."""

    draw_mode_toggled = QtCore.Signal(bool)
    all_off_requested = QtCore.Signal()

    SHAPES = ("line", "circle", "square")

    def __init__(self, state: TunerState, parent=None):
        super().__init__(parent)
        self.state = state
        self._updating = False
        layout = QtWidgets.QVBoxLayout(self)

        # Playback and view -------------------------------------------------------------------
        box = QtWidgets.QGroupBox("Playback and view")
        grid = QtWidgets.QGridLayout(box)
        self.play_button = QtWidgets.QPushButton("Pause (Space)")
        self.play_button.setObjectName("play")
        self.play_button.clicked.connect(lambda: self._set(playing=not self.state.scene.playing))
        self.restart_button = QtWidgets.QPushButton("Restart")
        self.restart_button.clicked.connect(self.state.restart)
        self.off_button = QtWidgets.QPushButton("All off (Esc)")
        self.off_button.setObjectName("all_off")
        self.off_button.setStyleSheet("font-weight: bold; color: #b00000;")
        self.off_button.clicked.connect(self.all_off_requested.emit)
        grid.addWidget(self.play_button, 0, 0)
        grid.addWidget(self.restart_button, 0, 1)
        grid.addWidget(self.off_button, 0, 2)
        self.view_buttons = QtWidgets.QButtonGroup(self)
        row = QtWidgets.QHBoxLayout()
        view_tips = {
            "raw": "The methods' intensities before the correction (paper 2.2-2.5).",
            "corrected": "After the threshold/gamma correction (paper 2.6).",
            "sent": "What went to the array: the device levels (23 on the palm array).",
            "felt": "What the motors would make of it: the profile's response curve.",
            "predicted": "The predicted percept (energy summation, a participant matched to "
            "mu/gamma): felt magnitude per tactor; the orange line is the felt centroid's path, "
            "the curve the felt intensity over time.",
        }
        for i, mode in enumerate(VIEW_MODES):
            button = QtWidgets.QRadioButton(mode)
            button.setObjectName(f"view_{mode}")
            button.setToolTip(tip(view_tips[mode]))
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
        layout.addWidget(box)

        # Method ------------------------------------------------------------------------------
        box = QtWidgets.QGroupBox("Method (keys 1-4)")
        grid = QtWidgets.QGridLayout(box)
        self.method_buttons = QtWidgets.QButtonGroup(self)
        self._method_hidden = False
        for i, name in enumerate(PAPER_METHODS):
            method = METHODS[name]
            button = QtWidgets.QRadioButton(f"{i + 1}  {name}  {method.title}")
            button.setObjectName(f"method_{name}")
            button.setToolTip(tip(METHOD_TIPS.get(name, method.title)))
            self.method_buttons.addButton(button, i)
            grid.addWidget(button, i, 0, 1, 3)
        self.method_buttons.idClicked.connect(self._on_method_clicked)
        # The field's methods and plug-ins: a list and the method's parameter.
        self.other_button = QtWidgets.QRadioButton("other")
        self.other_button.setObjectName("method_other")
        self.other_button.setToolTip(tip("A method of another haptic system, or a plug-in"))
        self.method_buttons.addButton(self.other_button, len(PAPER_METHODS))
        self.other_combo = QtWidgets.QComboBox()
        self.other_combo.setObjectName("other_method")
        self.other_combo.setSizeAdjustPolicy(
            QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon
        )
        self.other_combo.setMinimumContentsLength(14)
        self.other_combo.setPlaceholderText("peer methods, plug-ins")
        self.param_label = QtWidgets.QLabel("")
        self.param_spin = _spin(0.1, 10.0, 0.05, 2)
        self.param_spin.setObjectName("method_param")
        self.param_spin.setKeyboardTracking(False)
        row = len(PAPER_METHODS)
        grid.addWidget(self.other_button, row, 0)
        grid.addWidget(self.other_combo, row, 1, 1, 2)
        grid.addWidget(self.param_label, row + 1, 1, QtCore.Qt.AlignmentFlag.AlignRight)
        grid.addWidget(self.param_spin, row + 1, 2)
        grid.setColumnStretch(1, 1)
        self.fill_other_methods()
        self.other_combo.activated.connect(self._on_other_chosen)
        self.param_spin.valueChanged.connect(self._on_param_changed)
        layout.addWidget(box)

        # Correction --------------------------------------------------------------------------
        box = QtWidgets.QGroupBox("Correction  (1 - mu) I^gamma + mu")
        form = QtWidgets.QGridLayout(box)
        self.mu_slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.mu_slider.setRange(0, 100)
        self.mu_spin = _spin(0.0, 1.0, 0.01, 2)
        self.gamma_slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.gamma_slider.setRange(0, _GAMMA_STEPS)
        self.gamma_spin = _spin(GAMMA_MIN, GAMMA_MAX, 0.01, 2)
        mu_tip = tip(
            "Threshold mu, 0-1 of full drive (paper 2.6): the least a lit tactor gets, "
            "(1 - mu) I^gamma + mu. The paper uses 0.33."
        )
        gamma_tip = tip(
            "Gamma, 0.1-10, no unit (paper 2.6): below 1 raises weak intensities, above 1 lowers "
            "them. The paper uses 0.7 (1.4 in two stages of Experiment 2)."
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
        self.felt_domain_check = QtWidgets.QCheckBox("on felt amplitude (motor response)")
        self.felt_domain_check.setObjectName("felt_domain")
        self.felt_domain_check.toggled.connect(lambda on: self._set(felt_domain=on))
        form.addWidget(self.felt_domain_check, 2, 0, 1, 3)
        layout.addWidget(box)

        # Shape -------------------------------------------------------------------------------
        box = QtWidgets.QGroupBox("Shape (grid units)")
        v = QtWidgets.QVBoxLayout(box)
        self.shape_combo = QtWidgets.QComboBox()
        self.shape_combo.addItems([s.capitalize() for s in self.SHAPES])
        v.addWidget(self.shape_combo)
        self.shape_stack = QtWidgets.QStackedWidget()
        self.shape_fields = {}
        for kind, labels in (
            ("line", ("x0", "y0", "x1", "y1")),
            ("circle", ("centre x", "centre y", "radius")),
            ("square", ("centre x", "centre y", "edge")),
        ):
            page = QtWidgets.QWidget()
            form = QtWidgets.QFormLayout(page)
            form.setContentsMargins(0, 0, 0, 0)
            fields = []
            for label in labels:
                lo = 0.0 if label in ("radius", "edge") else -10.0
                spin = _spin(lo, 20.0, 0.05, 3)
                spin.setToolTip(tip(
                    f"{label} in grid units (paper 2.1): 1 unit = one tactor pitch (18 mm on the "
                    "palm array); tactors sit at the cells' centres, x + 0.5, y + 0.5"
                ))  # fmt: skip
                spin.valueChanged.connect(self._on_shape_edited)
                form.addRow(label, spin)
                fields.append(spin)
            self.shape_fields[kind] = fields
            self.shape_stack.addWidget(page)
        self.shape_combo.currentIndexChanged.connect(self._on_shape_kind_changed)
        v.addWidget(self.shape_stack)
        layout.addWidget(box)

        # Trace -------------------------------------------------------------------------------
        box = QtWidgets.QGroupBox("Trace and frames")
        form = QtWidgets.QFormLayout(box)
        self.duration_spin = _spin(0.1, 60.0, 0.1, 2, " s")
        self.pause_spin = _spin(0.0, 30.0, 0.1, 2, " s")
        self.direction_combo = QtWidgets.QComboBox()
        self.direction_combo.addItems(["forward (counter-clockwise)", "reverse (clockwise)"])
        self.rate_spin = _spin(10.0, 1000.0, 10.0, 0, " Hz")
        self.filter_combo = QtWidgets.QComboBox()
        self.filter_combo.addItems(["point", "box"])
        self.subsamples_spin = QtWidgets.QSpinBox()
        self.subsamples_spin.setRange(1, 64)
        self.subsamples_spin.setKeyboardTracking(False)
        self.dither_check = QtWidgets.QCheckBox("temporal dithering")
        tips = {
            self.duration_spin: "Trace duration in seconds, t from 0 to 1 (paper 3.4.2: 2 s).",
            self.pause_spin: "Seconds off between traces (paper 3.4.2 and 3.4.3: 0.5 s; "
            "Experiment 3 retraces continuously: 0).",
            self.direction_combo: "Forward follows f(t): counter-clockwise for circles and "
            "squares (paper 3.4.2, 3.4.4); reverse runs t from 1 to 0.",
            self.rate_spin: "Frames a second sent to the array, 10-1000 Hz (capped at what the "
            "link carries: 311 at 115200 baud). Not the PWM carrier, about 300 Hz on the "
            "paper's array (3.3).",
            self.filter_combo: "point: each frame is the trace at the middle of its interval "
            "(the paper's pipeline). box: the average of S sub-samples over the interval.",
            self.subsamples_spin: "Sub-samples S of the box filter, 1-64.",
            self.dither_check: "Error feedback per tactor, so averages finer than the device's "
            "23 levels go out; off: plain rounding (the paper's pipeline).",
        }
        for widget, text in tips.items():
            widget.setToolTip(tip(text))
        self.emphasis_spin = _spin(0.0, 0.9, 0.1, 2)
        self.emphasis_spin.setToolTip(tip(
            "Corner emphasis 0-0.9 (beyond the paper; its 4.3 suggests it): the point slows near "
            "corners; 0.5 doubles the dwell; 0 = constant speed"
        ))  # fmt: skip
        self.gain_spin = _spin(0.0, 1.0, 0.05, 2)
        self.gain_spin.setToolTip(tip(
            "Master intensity 0-1 (beyond the paper): scales the part above the threshold, "
            "mu + gain (1 - mu) I^gamma, so no lit tactor drops below mu"
        ))  # fmt: skip
        form.addRow("duration", self.duration_spin)
        form.addRow("pause", self.pause_spin)
        form.addRow("direction", self.direction_combo)
        form.addRow("frame rate", self.rate_spin)
        form.addRow("filter", self.filter_combo)
        form.addRow("box sub-samples", self.subsamples_spin)
        form.addRow("", self.dither_check)
        form.addRow("corner emphasis", self.emphasis_spin)
        form.addRow("master intensity", self.gain_spin)
        self.duration_spin.valueChanged.connect(lambda v: self._set(duration_s=v))
        self.pause_spin.valueChanged.connect(lambda v: self._set(pause_s=v))
        self.direction_combo.currentIndexChanged.connect(
            lambda i: self._set(direction=("forward", "reverse")[i])
        )
        self.rate_spin.valueChanged.connect(lambda v: self._set(rate_hz=v))
        self.filter_combo.currentTextChanged.connect(lambda t: self._set(filter=t))
        self.subsamples_spin.valueChanged.connect(lambda v: self._set(subsamples=v))
        self.dither_check.toggled.connect(lambda on: self._set(dither=on))
        self.emphasis_spin.valueChanged.connect(lambda v: self._set(emphasis=v))
        self.gain_spin.valueChanged.connect(lambda v: self._set(gain=v))
        layout.addWidget(box)

        layout.addStretch(1)

        state.scene_changed.connect(self.refresh)
        state.view_mode_changed.connect(self.refresh)
        state.plugins_changed.connect(self.fill_other_methods)
        state.plugins_changed.connect(self.refresh)
        self.refresh()

    def _set(self, **changes) -> None:
        if not self._updating:
            self.state.update(**changes)

    def _on_method_clicked(self, index: int) -> None:
        if index < len(PAPER_METHODS):
            self._set(method=PAPER_METHODS[index])
        else:
            self._on_other_chosen(max(self.other_combo.currentIndex(), 0))

    def fill_other_methods(self) -> None:
        """List the peer methods and the plug-ins (an unavailable plug-in is listed, greyed
        out, with its error as the tooltip)."""
        combo = self.other_combo
        combo.blockSignals(True)
        combo.clear()
        for name in method_names():
            if name in PAPER_METHODS:
                continue
            method = METHODS[name]
            combo.addItem(f"{name}  {method.title}", name)
            text = METHOD_TIPS.get(name, method.title)
            if method.plugin:
                text += f" Plug-in ({method.source.removeprefix('plugin ')})."
            combo.setItemData(combo.count() - 1, tip(text), QtCore.Qt.ItemDataRole.ToolTipRole)
        model = combo.model()
        for label, error in UNAVAILABLE.items():
            combo.addItem(f"{label}  (unavailable)", None)
            item = model.item(combo.count() - 1)
            item.setEnabled(False)
            item.setToolTip(tip(f"Plug-in {label} could not be used: {error}"))
        combo.blockSignals(False)

    def _on_other_chosen(self, index: int) -> None:
        name = self.other_combo.itemData(index)
        if name is None or self._updating:
            return
        method = get_method(name)
        current = get_method(self.state.scene.method)
        if current.name == method.name:
            return
        self._set(method=method.spec)

    def _on_param_changed(self, value: float) -> None:
        if self._updating:
            return
        method = get_method(self.state.scene.method)
        specs = method.param_specs
        if not specs:
            return
        key = next(iter(specs))
        try:
            spec = method.with_params(**{key: value}).spec
        except ValueError as exc:
            self.state.error_raised.emit(str(exc))
            return
        self._set(method=spec)

    def _on_shape_kind_changed(self, index: int) -> None:
        if self._updating:
            return
        kind = self.SHAPES[index]
        scene = self.state.scene
        # Sensible defaults centred where the current shape is.
        cx, cy = 2.5, 3.0
        defaults = {
            "line": tc.Line((0.5, 1.84), (4.5, 4.16)),
            "circle": tc.Circle((cx, cy), 2.0),
            "square": tc.Square((cx, 3.5), 4.0),
        }
        if scene.shape is None or type(scene.shape).__name__.lower() != kind:
            self.state.update(shape=defaults[kind])

    def _on_shape_edited(self, _value=None) -> None:
        if self._updating:
            return
        kind = self.SHAPES[self.shape_combo.currentIndex()]
        values = [f.value() for f in self.shape_fields[kind]]
        try:
            if kind == "line":
                shape = tc.Line(values[0:2], values[2:4])
            elif kind == "circle":
                shape = tc.Circle(values[0:2], values[2])
            else:
                shape = tc.Square(values[0:2], values[2])
        except ValueError as exc:
            self.state.error_raised.emit(str(exc))
            return
        self.state.update(shape=shape)

    def method_names(self) -> list[str]:
        """The methods of the number keys, in key order (key 1 first): the paper's four."""
        return list(PAPER_METHODS)

    def set_felt_available(self, available: bool) -> None:
        """'felt' needs the device profile's motor response curve."""
        button = self.view_buttons.button(VIEW_MODES.index("felt"))
        button.setEnabled(available)
        button.setToolTip(tip(
            "What the motors would make of the levels sent: the profile's response curve."
            if available
            else "Not available: the device profile has no motor response curve ('response')."
        ))  # fmt: skip
        if not available and self.state.view_mode == "felt":
            self.state.set_view_mode("sent")
        self.felt_domain_check.setEnabled(available)
        self.felt_domain_check.setToolTip(tip(
            "mu and gamma act on felt amplitude: the corrected value is the motor output "
            "wanted, and the array gets the least drive that gives it (the inverse of the "
            "profile's response curve). Off: on drive, as the paper."
            if available
            else "Not available: the device profile has no motor response curve ('response')."
        ))  # fmt: skip

    def set_draw_mode(self, on: bool) -> None:
        """Reflect draw mode: MM and IM are unavailable on free points."""
        for name in ("MM", "IM"):
            button = self.method_buttons.button(PAPER_METHODS.index(name))
            button.setEnabled(not on)
            button.setToolTip(tip(DRAW_HELP) if on else tip(METHOD_TIPS[name]))
        self.shape_combo.setEnabled(not on)
        self.shape_stack.setEnabled(not on)
        if self.draw_check.isChecked() != on:
            self.draw_check.blockSignals(True)
            self.draw_check.setChecked(on)
            self.draw_check.blockSignals(False)

    def set_method_hidden(self, hidden: bool) -> None:
        """Blind A/B testing: hide which method is selected (and its parameter)."""
        self._method_hidden = hidden
        for button in self.method_buttons.buttons():
            button.setEnabled(not hidden)
        self.other_combo.setEnabled(not hidden)
        if hidden:
            self.method_buttons.setExclusive(False)
            for button in self.method_buttons.buttons():
                button.setChecked(False)
            self.method_buttons.setExclusive(True)
            self.other_combo.setCurrentIndex(-1)
            self.param_label.setVisible(False)
            self.param_spin.setVisible(False)
        else:
            self.refresh()

    def _show_method(self, method) -> None:
        if method.name in PAPER_METHODS:
            index = PAPER_METHODS.index(method.name)
            self.other_combo.setCurrentIndex(-1)  # the placeholder: no other method is on
        else:
            index = len(PAPER_METHODS)
            found = self.other_combo.findData(method.name)
            if found < 0:  # a plug-in loaded since the list was filled
                self.fill_other_methods()
                found = self.other_combo.findData(method.name)
            self.other_combo.setCurrentIndex(found)
        if self.method_buttons.button(index).isEnabled():
            self.method_buttons.button(index).setChecked(True)

    def refresh(self, *_):
        """Show the state's values (without writing them back)."""
        scene = self.state.scene
        self._updating = True
        try:
            method = get_method(scene.method)
            hidden = self._method_hidden
            if not hidden:
                self._show_method(method)
            specs = {} if hidden else method.param_specs
            self.param_label.setVisible(bool(specs))
            self.param_spin.setVisible(bool(specs))
            if specs:
                key, (_, lo, hi, doc) = next(iter(specs.items()))
                self.param_label.setText(key)
                self.param_spin.setRange(lo, hi)
                self.param_spin.setValue(method.values[key])
                self.param_spin.setToolTip(tip(f"{method.name}'s {key}: {doc}"))
            self.felt_domain_check.setChecked(scene.felt_domain)
            self.mu_slider.setValue(round(scene.mu * 100))
            self.mu_spin.setValue(scene.mu)
            self.gamma_slider.setValue(gamma_to_slider(scene.gamma))
            self.gamma_spin.setValue(scene.gamma)
            shape = scene.shape
            if shape is not None:
                kind = type(shape).__name__.lower()
                if kind in self.SHAPES:
                    self.shape_combo.setCurrentIndex(self.SHAPES.index(kind))
                    self.shape_stack.setCurrentIndex(self.SHAPES.index(kind))
                    if kind == "line":
                        values = (*shape.p0, *shape.p1)
                    elif kind == "circle":
                        values = (*shape.center, shape.radius)
                    else:
                        values = (*shape.center, shape.edge)
                    for field, value in zip(self.shape_fields[kind], values):
                        field.setValue(value)
            self.duration_spin.setValue(scene.duration_s)
            self.pause_spin.setValue(scene.pause_s)
            self.direction_combo.setCurrentIndex(0 if scene.direction == "forward" else 1)
            self.rate_spin.setValue(scene.rate_hz)
            self.filter_combo.setCurrentText(scene.filter)
            self.subsamples_spin.setValue(scene.subsamples)
            self.subsamples_spin.setEnabled(scene.filter == "box")
            self.dither_check.setChecked(scene.dither)
            self.emphasis_spin.setValue(scene.emphasis)
            self.gain_spin.setValue(scene.gain)
            self.play_button.setText("Pause (Space)" if scene.playing else "Play (Space)")
            self.view_buttons.button(VIEW_MODES.index(self.state.view_mode)).setChecked(True)
        finally:
            self._updating = False


class DevicePanel(QtWidgets.QWidget):
    """Ports, connect/disconnect, the device profile, and the stream's status line."""

    profile_requested = QtCore.Signal()

    def __init__(self, device: DeviceController, parent=None):
        super().__init__(parent)
        self.device = device
        layout = QtWidgets.QGridLayout(self)
        self.port_combo = QtWidgets.QComboBox()
        self.port_combo.setEditable(True)
        self.port_combo.setMinimumWidth(260)
        self.port_combo.lineEdit().setPlaceholderText(
            "port or URL: /dev/ttyUSB0, COM3, socket://host:port"
        )
        self.refresh_button = QtWidgets.QPushButton("Refresh")
        self.connect_button = QtWidgets.QPushButton("Connect")
        self.connect_button.setObjectName("connect")
        self.disconnect_button = QtWidgets.QPushButton("Disconnect")
        self.disconnect_button.setObjectName("disconnect")
        self.profile_button = QtWidgets.QPushButton("Profile...")
        self.profile_label = QtWidgets.QLabel()
        self.link_label = QtWidgets.QLabel()
        self.status_label = QtWidgets.QLabel("starting")
        self.status_label.setObjectName("status")
        self.status_label.setWordWrap(True)
        layout.addWidget(QtWidgets.QLabel("device"), 0, 0)
        layout.addWidget(self.port_combo, 0, 1)
        layout.addWidget(self.refresh_button, 0, 2)
        layout.addWidget(self.connect_button, 0, 3)
        layout.addWidget(self.disconnect_button, 0, 4)
        layout.addWidget(QtWidgets.QLabel("profile"), 1, 0)
        layout.addWidget(self.profile_label, 1, 1)
        layout.addWidget(self.profile_button, 1, 2)
        layout.addWidget(self.link_label, 1, 3, 1, 2)
        layout.addWidget(self.status_label, 2, 0, 1, 5)
        layout.setColumnStretch(1, 1)
        self.port_combo.setToolTip(tip(
            "A serial port or any pyserial URL (/dev/ttyUSB0, COM3, socket://host:port, "
            "rfc2217://..., spy://...); sim for the built-in simulated array. Enter connects."
        ))  # fmt: skip
        self.connect_button.setToolTip(tip("Stream to the device; it is asked who it is first"))
        self.profile_button.setToolTip(tip("Load a device profile (grid, levels, baud, channel "
                                           "order, calibration, motor response)"))  # fmt: skip
        self.port_combo.lineEdit().returnPressed.connect(self._on_connect_clicked)
        self.refresh_button.clicked.connect(self.refresh_ports)
        self.connect_button.clicked.connect(self._on_connect_clicked)
        self.disconnect_button.clicked.connect(device.disconnect_device)
        self.profile_button.clicked.connect(self.profile_requested.emit)
        device.connection_changed.connect(self._on_device_connection_changed)
        device.status_changed.connect(self.show_stats)
        self._timer = QtCore.QTimer(self)
        self._timer.timeout.connect(lambda: self.show_stats(device.stats))
        self._timer.start(500)
        self.refresh_ports()
        self._on_device_connection_changed(device.description)

    def refresh_ports(self) -> None:
        """List serial ports (``serial.tools.list_ports``) and the simulated array."""
        current = self.port_combo.currentText()
        self.port_combo.clear()
        self.port_combo.addItem("sim")
        for port in sorted(list_ports.comports(), key=lambda p: p.device):
            label = f"{port.device}"
            self.port_combo.addItem(label)
        if current:
            self.port_combo.setCurrentText(current)

    def _on_connect_clicked(self) -> None:
        self.device.connect_device(self.port_combo.currentText())

    def _on_device_connection_changed(self, description: str) -> None:
        profile = self.device.profile
        self.profile_label.setText(
            f"{profile.name}: {profile.grid.cols} x {profile.grid.rows}, {profile.levels} levels, "
            f"{profile.baud} baud (max {profile.max_rate_hz:.0f} frames/s)"
        )
        self.link_label.setText(f"<b>{description}</b>")
        self.disconnect_button.setEnabled(not self.device.simulated)

    def show_stats(self, stats) -> None:
        """Status line: state, achieved rate, interval error, errors."""
        self.status_label.setText(
            f"[{stats.state}] {stats.status} | achieved {stats.achieved_rate_hz:.0f} Hz, "
            f"interval error p99 {stats.interval_error_p99_ms:.2f} ms, late {stats.late}, "
            f"errors {stats.errors}, {stats.frames} frames"
        )
