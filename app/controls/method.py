"""The method: the paper's four on keys 1-4, the field's others and plug-ins, a parameter."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

from tactile_core.rendering import placement
from tactile_core.rendering.methods import (
    METHODS,
    PAPER_METHODS,
    UNAVAILABLE,
    get_method,
    method_names,
)

from ..texts import DRAW_HELP, tip
from ._common import SceneGroupWidget, spin_box

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
    "PK": "Inverse distance over the 3 nearest tactors (Park et al. 2016), energy-normalised; "
    "it switches a tactor at each centre line (PK:blend=0.2 crossfades instead).",
    "RO": "Roll-off within radius r (Syntacts' spatializer): smoothstep; RO:curve=linear is "
    "Syntacts' own default.",
    "GS": "This project's Gaussian spread: weights of spread sigma, cut below 0.05.",
    "VRCH": "VRCH-Server's rule for one contact: every tactor within r at full. Bi-level.",
    "BA": "Barycentric weights over the layout's Delaunay triangles (rectangles bilinear): AS's "
    "weights on a grid, and the smooth method on actuators anywhere (sum of weights 1 inside "
    "the hull).",
    "TB": "Tactile Brush (Israr and Poupyrev 2011): the actuators along the stroke start one "
    "after another, SOA = 0.32 d + 47.3 ms apart, each for d ms (from the scene's duration); "
    "points between two actuators split the energy, sqrt(1 - beta) and sqrt(beta).",
}


class MethodWidget(SceneGroupWidget):
    """The paper's four methods as radio buttons; *other* with a list of the peer methods and
    the plug-ins (an unavailable plug-in greyed out), and the chosen method's parameter.

    On a layout that is not a grid, the methods that cannot render there (the paper's four,
    grid-only plug-ins) are greyed out, their tooltip saying why; in draw mode, MM and IM."""

    def __init__(self, state, parent=None):
        super().__init__("Method (keys 1-4)", state, parent)
        grid = QtWidgets.QGridLayout(self)
        self.method_buttons = QtWidgets.QButtonGroup(self)
        self._method_hidden = False
        self._drawing = False
        self._free_only = ""  # why only free-point methods may be picked (another program)
        for i, name in enumerate(PAPER_METHODS):
            method = METHODS[name]
            button = QtWidgets.QRadioButton(f"{i + 1}  {name}  {method.title}")
            button.setObjectName(f"method_{name}")
            button.setToolTip(tip(METHOD_TIPS.get(name, method.title)))
            self.method_buttons.addButton(button, i)
            grid.addWidget(button, i, 0, 1, 3)
        self.method_buttons.idClicked.connect(self._on_method_buttons_clicked)
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
        self.param_spin = spin_box(0.1, 10.0, 0.05, 2)
        self.param_spin.setObjectName("method_param")
        self.param_spin.setKeyboardTracking(False)
        row = len(PAPER_METHODS)
        grid.addWidget(self.other_button, row, 0)
        grid.addWidget(self.other_combo, row, 1, 1, 2)
        grid.addWidget(self.param_label, row + 1, 1, QtCore.Qt.AlignmentFlag.AlignRight)
        grid.addWidget(self.param_spin, row + 1, 2)
        grid.setColumnStretch(1, 1)
        self.fill_other_methods()
        self.other_combo.activated.connect(self._on_other_combo_activated)
        self.param_spin.valueChanged.connect(self._on_param_spin_changed)
        state.scene_changed.connect(self.refresh)
        state.plugins_changed.connect(self.fill_other_methods)
        state.plugins_changed.connect(self.refresh)
        state.layout_changed.connect(self._on_state_layout_changed)
        self._on_state_layout_changed(state.layout)

    def _on_method_buttons_clicked(self, index: int) -> None:
        if index < len(PAPER_METHODS):
            self._set(method=PAPER_METHODS[index])
            if self.state.scene.method != PAPER_METHODS[index]:
                self.refresh()  # refused (the status line says why): the method in use
        else:
            self._on_other_combo_activated(max(self.other_combo.currentIndex(), 0))

    def fill_other_methods(self) -> None:
        """List the peer methods and the plug-ins (an unavailable plug-in is listed, greyed
        out, with its error as the tooltip)."""
        combo = self.other_combo
        combo.blockSignals(True)
        combo.clear()
        model = combo.model()
        for name in method_names():
            if name in PAPER_METHODS:
                continue
            method = METHODS[name]
            combo.addItem(f"{name}  {method.title}", name)
            text = METHOD_TIPS.get(name, method.title)
            if method.plugin:
                text += f" Plug-in ({method.source.removeprefix('plugin ')})."
            why = placement.refusal(name, self.state.layout)
            model.item(combo.count() - 1).setEnabled(not why)
            combo.setItemData(combo.count() - 1, tip(why or text),
                              QtCore.Qt.ItemDataRole.ToolTipRole)  # fmt: skip
        for label, error in UNAVAILABLE.items():
            combo.addItem(f"{label}  (unavailable)", None)
            item = model.item(combo.count() - 1)
            item.setEnabled(False)
            item.setToolTip(tip(f"Plug-in {label} could not be used: {error}"))
        combo.blockSignals(False)

    def _on_other_combo_activated(self, index: int) -> None:
        name = self.other_combo.itemData(index)
        if name is None or self._updating:
            return
        method = get_method(name)
        current = get_method(self.state.scene.method)
        if current.name == method.name:
            return
        self._set(method=method.spec)

    def _on_param_spin_changed(self, value: float) -> None:
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

    def _on_state_layout_changed(self, layout) -> None:
        grid = layout.is_grid
        self.setTitle("Method (keys 1-4)" if grid else "Method (keys 1-4 need a grid)")
        self.fill_other_methods()
        self._enable_buttons()
        self.refresh()

    def _enable_buttons(self) -> None:
        """Each of the paper's buttons on unless the layout, draw mode or a blind test says no;
        its tooltip says why."""
        for i, name in enumerate(PAPER_METHODS):
            why = placement.refusal(name, self.state.layout)
            if not why and self._drawing and name in ("MM", "IM"):
                why = DRAW_HELP
            if not why and self._free_only and name in ("MM", "IM"):
                why = self._free_only
            button = self.method_buttons.button(i)
            button.setEnabled(not (why or self._method_hidden))
            button.setToolTip(tip(why or METHOD_TIPS[name]))
        self.other_button.setEnabled(not self._method_hidden)
        self.other_combo.setEnabled(not self._method_hidden)

    def set_draw_mode(self, on: bool) -> None:
        """Reflect draw mode: MM and IM are unavailable on free points."""
        self._drawing = bool(on)
        self._enable_buttons()

    def set_free_only(self, why: str) -> None:
        """Only methods that render free points (another program drives them): MM and IM off,
        ``why`` their tooltip ("" lifts it)."""
        self._free_only = why
        self._enable_buttons()

    def set_method_hidden(self, hidden: bool) -> None:
        """Blind A/B testing: hide which method is selected (and its parameter)."""
        self._method_hidden = hidden
        self._enable_buttons()
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

    def _check_method(self, method) -> None:
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

    def _show(self, scene) -> None:
        method = get_method(scene.method)
        hidden = self._method_hidden
        if not hidden:
            self._check_method(method)
        specs = {} if hidden else method.param_specs
        self.param_label.setVisible(bool(specs))
        self.param_spin.setVisible(bool(specs))
        if specs:
            key, (_, lo, hi, doc) = next(iter(specs.items()))
            self.param_label.setText(key)
            self.param_spin.setRange(lo, hi)
            self.param_spin.setValue(method.values[key])
            self.param_spin.setToolTip(tip(f"{method.name}'s {key}: {doc}"))
