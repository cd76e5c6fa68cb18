"""The pattern editor's property panel: the selected effect's fields (or, with none selected,
the pattern's), each change an undoable edit; a change the pattern refuses is explained under
the fields and the field shows the value in force again."""

from __future__ import annotations

from PySide6 import QtWidgets

from tactile_core.files.pattern import COMBINE, MAX_REPEAT, MAX_TRACKS
from tactile_core.rendering import placement
from tactile_core.rendering.methods import method_names

from ..texts import tip
from ..widgets import WrappedLabel, guard_wheel, spin_box
from .model import describe, dot_length, envelope_text, parse_envelope, peak_gain

SCENE_METHOD = "the scene's"
EVERY_ACTUATOR = "every actuator"


class EffectPanel(QtWidgets.QWidget):
    """The selected effect's kind, start, duration, repeat, track, method (or the scene's),
    group (the layout's), intensity, envelope keyframes and name (and for a set of dots, how
    long each lasts); with none selected, the pattern's name and how overlapping effects
    combine.

    Parameters
    ----------
    editor : TimelineEditor
        Its model is shown; changes go through :meth:`~.editor.TimelineEditor.push`.
    """

    def __init__(self, editor, parent=None):
        super().__init__(parent)
        self.setObjectName("effect_panel")
        self.editor = editor
        self.model = editor.model
        self.state = editor.state
        self._showing = False
        self.stack = QtWidgets.QStackedWidget()
        self.stack.addWidget(self._pattern_page())
        self.stack.addWidget(self._effect_page())
        self.message = WrappedLabel("")
        self.message.setObjectName("timeline_message")
        self.message.setStyleSheet("color: #c0392b;")
        column = QtWidgets.QVBoxLayout(self)
        column.setContentsMargins(4, 0, 0, 0)
        column.addWidget(self.stack)
        column.addWidget(self.message)
        column.addStretch(1)
        guard_wheel(self)
        self.model.connect("pattern", self.show_model)
        self.model.connect("selection", self._on_model_selection)
        editor.refused.connect(self.message.setText)
        self.state.layout_changed.connect(lambda _: self.show_model())
        self.show_model()

    # --- the pages -----------------------------------------------------------------------------

    def _pattern_page(self) -> QtWidgets.QWidget:
        page = QtWidgets.QWidget()
        form = QtWidgets.QFormLayout(page)
        form.setContentsMargins(0, 0, 0, 0)
        self.pattern_name = QtWidgets.QLineEdit()
        self.pattern_name.setObjectName("pattern_name")
        self.pattern_name.editingFinished.connect(
            lambda: self._pattern(name=self.pattern_name.text())
        )
        self.combine_combo = QtWidgets.QComboBox()
        self.combine_combo.addItems(COMBINE)
        self.combine_combo.setToolTip(tip(
            "How overlapping effects combine on an actuator: max, the larger (as bHaptics "
            "combines paths and dots); sum, added up and clipped to 1"))  # fmt: skip
        self.combine_combo.activated.connect(
            lambda i: self._pattern(combine=COMBINE[i]))  # fmt: skip
        self.summary = WrappedLabel("")
        form.addRow("pattern", self.pattern_name)
        form.addRow("combine", self.combine_combo)
        form.addRow(self.summary)
        return page

    def _effect_page(self) -> QtWidgets.QWidget:
        page = QtWidgets.QWidget()
        grid = QtWidgets.QGridLayout(page)
        grid.setContentsMargins(0, 0, 0, 0)
        grid.setHorizontalSpacing(6)
        grid.setVerticalSpacing(3)
        self.kind_label = QtWidgets.QLabel()
        self.kind_label.setObjectName("effect_kind")
        self.name_edit = QtWidgets.QLineEdit()
        self.start_spin = spin_box(0.0, 3600.0, 0.01, 3, " s")
        self.duration_spin = spin_box(0.001, 3600.0, 0.01, 3, " s")
        self.repeat_spin = QtWidgets.QSpinBox()
        self.repeat_spin.setRange(1, MAX_REPEAT)
        self.repeat_spin.setKeyboardTracking(False)
        self.track_spin = QtWidgets.QSpinBox()
        self.track_spin.setRange(1, MAX_TRACKS)
        self.track_spin.setKeyboardTracking(False)
        self.method_combo = QtWidgets.QComboBox()
        self.method_combo.setEditable(True)
        self.method_combo.setInsertPolicy(QtWidgets.QComboBox.InsertPolicy.NoInsert)
        self.group_combo = QtWidgets.QComboBox()
        self.intensity_spin = spin_box(0.0, 1.0, 0.05, 2)
        self.dot_spin = spin_box(0.001, 3600.0, 0.01, 3, " s")
        self.dot_label = QtWidgets.QLabel("dots last")
        self.envelope_edit = QtWidgets.QLineEdit()
        self.envelope_edit.setPlaceholderText("none (gain 1)")
        tips = {
            self.name_edit: "A label for the effect (shown on its block)",
            self.start_spin: "When it starts, in seconds from the pattern's start",
            self.duration_spin: "How long one play lasts, in seconds (the envelope's keyframes "
            "stretch with it)",
            self.repeat_spin: "How many times it plays, back to back",
            self.track_spin: "The editor's row (it does not change what plays)",
            self.method_combo: "The method that renders its shapes (TB: a Tactile Brush stroke; "
            "a spec such as RO:r=1.5); the scene's: whatever the scene plays with",
            self.group_combo: "The layout group it plays on: only those actuators light",
            self.intensity_spin: "Its highest envelope gain: the keyframes are scaled to it",
            self.envelope_edit: "Keyframes time_s:gain over one play, comma-separated, e.g. "
            "0:0.4, 0.08:1 (gains 0 to 1, times increasing within the duration)",
            self.dot_spin: "How long each dot of the set lasts, in seconds: a dot shorter "
            "than the play is a tap and a pause (what plays past the play's end is cut)",
        }
        for widget, text in tips.items():
            widget.setToolTip(tip(text))
        rows = (("kind", self.kind_label, "name", self.name_edit),
                ("start", self.start_spin, "duration", self.duration_spin),
                ("repeat", self.repeat_spin, "track", self.track_spin),
                ("method", self.method_combo, "group", self.group_combo),
                ("intensity", self.intensity_spin, "envelope", self.envelope_edit))  # fmt: skip
        for r, (a, wa, b, wb) in enumerate(rows):
            grid.addWidget(QtWidgets.QLabel(a), r, 0)
            grid.addWidget(wa, r, 1)
            grid.addWidget(QtWidgets.QLabel(b), r, 2)
            grid.addWidget(wb, r, 3)
        grid.addWidget(self.dot_label, len(rows), 0)
        grid.addWidget(self.dot_spin, len(rows), 1)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(3, 1)
        self.name_edit.editingFinished.connect(lambda: self._change(name=self.name_edit.text()))
        self.start_spin.valueChanged.connect(lambda v: self._change(start_s=v))
        self.duration_spin.valueChanged.connect(lambda v: self._change(duration_s=v))
        self.repeat_spin.valueChanged.connect(lambda v: self._change(repeat=v))
        self.track_spin.valueChanged.connect(lambda v: self._change(track=v - 1))
        self.method_combo.activated.connect(self._on_method_combo_activated)
        self.method_combo.lineEdit().editingFinished.connect(self._on_method_combo_activated)
        self.group_combo.activated.connect(self._on_group_combo_activated)
        self.intensity_spin.valueChanged.connect(lambda v: self._change(intensity=v))
        self.dot_spin.valueChanged.connect(lambda v: self._change(dot_s=v))
        self.envelope_edit.editingFinished.connect(self._on_envelope_edit_finished)
        return page

    # --- writing -------------------------------------------------------------------------------

    def _change(self, **fields) -> None:
        i = self.model.selected
        if self._showing or i is None:
            return
        if self.editor.push(lambda: self.model.change(i, **fields)):
            self.message.setText("")
        else:
            self.show_model()  # the field shows the value in force again (the message stays)

    def _pattern(self, **fields) -> None:
        if self._showing or all(getattr(self.model.pattern, k) == v for k, v in fields.items()):
            return
        if self.editor.push(lambda: self.model.change_pattern(**fields)):
            self.message.setText("")
        else:
            self.show_model()

    def _on_method_combo_activated(self, _index=None) -> None:
        text = self.method_combo.currentText().strip()
        method = None if text in ("", SCENE_METHOD) else text
        effect = self.model.effect
        if effect is not None and method != effect.method:
            self._change(method=method)

    def _on_group_combo_activated(self, index: int) -> None:
        self._change(group=self.group_combo.itemData(index))

    def _on_envelope_edit_finished(self) -> None:
        effect = self.model.effect
        if self._showing or effect is None:
            return
        try:
            envelope = parse_envelope(self.envelope_edit.text())
        except ValueError as exc:
            self.message.setText(str(exc))
            self.show_model()
            return
        if envelope != effect.envelope:
            self._change(envelope=envelope)

    # --- showing -------------------------------------------------------------------------------

    def _on_model_selection(self) -> None:
        self.message.setText("")
        self.show_model()

    def show_model(self) -> None:
        """Show the selected effect's fields (the pattern's with none selected)."""
        self._showing = True
        try:
            effect = self.model.effect
            self.stack.setCurrentIndex(0 if effect is None else 1)
            if effect is None:
                self._show_pattern(self.model.pattern)
            else:
                self._show_effect(effect)
        finally:
            self._showing = False

    def _show_pattern(self, pattern) -> None:
        self.pattern_name.setText(pattern.name)
        self.combine_combo.setCurrentIndex(COMBINE.index(pattern.combine))
        n, tracks = len(pattern.effects), len(pattern.tracks)
        self.summary.setText(f"{n} effect{'' if n == 1 else 's'} on {tracks} track"
                             f"{'' if tracks == 1 else 's'}, {pattern.duration_s:g} s. Click an "
                             "effect (or Tab in the time line) to edit it.")  # fmt: skip

    def _show_effect(self, effect) -> None:
        self.kind_label.setText(describe(effect))
        self.name_edit.setText(effect.name)
        self.start_spin.setValue(effect.start_s)
        self.duration_spin.setValue(effect.duration_s)
        self.repeat_spin.setValue(effect.repeat)
        self.track_spin.setValue(effect.track + 1)
        self.intensity_spin.setValue(peak_gain(effect))
        self.envelope_edit.setText(envelope_text(effect.envelope))
        length = dot_length(effect)
        for widget in (self.dot_label, self.dot_spin):
            widget.setVisible(effect.kind == "dots")
        self.dot_spin.setValue(length if length is not None else 0.0)
        layout = self.state.layout
        combo = self.method_combo
        combo.clear()
        combo.addItem(SCENE_METHOD)
        for name in method_names():
            if not placement.refusal(name, layout):
                combo.addItem(name)
        if effect.method is not None and combo.findText(effect.method) < 0:
            combo.addItem(effect.method)
        combo.setCurrentText(SCENE_METHOD if effect.method is None else effect.method)
        groups = self.group_combo
        groups.clear()
        groups.addItem(EVERY_ACTUATOR, None)
        for name, _ in layout.groups:
            groups.addItem(name, name)
        if effect.group is not None and groups.findData(effect.group) < 0:
            groups.addItem(f"{effect.group} (not on this layout)", effect.group)
        groups.setCurrentIndex(max(groups.findData(effect.group), 0))
