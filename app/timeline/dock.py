"""The pattern editor's dock: a tool bar (files, adding effects, undo and redo, play), the time
line and the property panel; and :func:`install_timeline`, which gives the main window all of
it."""

from __future__ import annotations

from PySide6 import QtCore, QtGui, QtWidgets

from ..texts import tip
from .editor import TimelineEditor
from .files import PatternFiles
from .panel import EffectPanel
from .view import TimelineView

SNAPS = (("snap 10 ms", 0.01), ("snap 50 ms", 0.05), ("snap 100 ms", 0.1), ("no snap", 0.0))


class TimelinePanel(QtWidgets.QWidget):
    """The dock's contents: the tool bar over the time line beside the property panel.

    Parameters
    ----------
    editor : TimelineEditor
    files : PatternFiles
    """

    def __init__(self, editor, files, parent=None):
        super().__init__(parent)
        self.setObjectName("timeline_panel")
        self.editor = editor
        self.files = files
        self.model = editor.model
        self.view = TimelineView(editor)
        self.panel = EffectPanel(editor)
        bar = QtWidgets.QHBoxLayout()
        bar.setSpacing(4)
        self.file_button = self._menu_button("File", (
            ("Open...", files.ask_open),
            ("Save", files.ask_save),
            ("Save as...", files.ask_save_as),
            None,
            ("Import .tact as effects...", files.ask_import_tact),
            ("Export .tact (Designer project)...", lambda: files.ask_export_tact(False)),
            ("Export .tact with compiled frames...", lambda: files.ask_export_tact(True)),
            ("Export WAV...", files.ask_export_wav),
        ))  # fmt: skip
        self.add_button = self._menu_button("Add", (
            ("The scene's shape (its method and duration)", editor.add_from_scene),
            ("The drawing (draw mode's last drag)", editor.add_from_drawing),
            ("Pick tactors on the heatmap", None),  # checkable: toggled below
            ("Dots: the tactors picked", editor.add_dots),
            ("A Tactile Brush stroke (TB) along the scene's shape", editor.add_brush),
        ))  # fmt: skip
        self.pick_action = self.add_button.menu().actions()[2]
        self.pick_action.setCheckable(True)
        self.pick_action.toggled.connect(editor.set_picking)
        editor.picking_changed.connect(self.pick_action.setChecked)
        self.duplicate_button = self._button(
            "Duplicate",
            editor.duplicate_selected,
            "A copy of the selected effect after it (Ctrl+D)",
        )
        self.delete_button = self._button("Delete", editor.delete_selected,
                                          "Delete the selected effect (Delete)")  # fmt: skip
        self.undo_action = editor.undo_stack.createUndoAction(self, "Undo")
        self.undo_action.setShortcut(QtGui.QKeySequence("Ctrl+Z"))
        self.redo_action = editor.undo_stack.createRedoAction(self, "Redo")
        self.redo_action.setShortcuts([QtGui.QKeySequence("Ctrl+Shift+Z"),
                                       QtGui.QKeySequence("Ctrl+Y")])  # fmt: skip
        for action in (self.undo_action, self.redo_action):
            action.setShortcutContext(QtCore.Qt.ShortcutContext.WindowShortcut)
            self.addAction(action)
        undo, redo = QtWidgets.QToolButton(), QtWidgets.QToolButton()
        undo.setDefaultAction(self.undo_action)
        redo.setDefaultAction(self.redo_action)
        for button in (undo, redo):
            button.setToolButtonStyle(QtCore.Qt.ToolButtonStyle.ToolButtonTextOnly)
            button.setMaximumWidth(190)
        self.play_button = self._button(
            "Play (Space)", editor.toggle_play, "Play the pattern from the playhead, or pause it"
        )
        self.time_label = QtWidgets.QLabel()
        self.time_label.setObjectName("timeline_time")
        self.snap_combo = QtWidgets.QComboBox()
        self.snap_combo.addItems([text for text, _ in SNAPS])
        self.snap_combo.setToolTip(tip("The grid moves and resizes snap to"))
        self.snap_combo.activated.connect(
            lambda i: setattr(self.model, "grid_s", SNAPS[i][1]))  # fmt: skip
        for widget in (self.file_button, self.add_button, self.duplicate_button,
                       self.delete_button, undo, redo, self.play_button):  # fmt: skip
            bar.addWidget(widget)
        bar.addWidget(self.time_label)
        bar.addStretch(1)
        bar.addWidget(self.snap_combo)
        side = QtWidgets.QScrollArea()
        side.setWidget(self.panel)
        side.setWidgetResizable(True)
        side.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        side.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
        self.split = QtWidgets.QSplitter(QtCore.Qt.Orientation.Horizontal)
        self.split.addWidget(self.view)
        self.split.addWidget(side)
        self.split.setStretchFactor(0, 3)
        self.split.setStretchFactor(1, 2)
        self.split.setCollapsible(0, False)
        self.split.setCollapsible(1, False)
        self.side = side
        self._split_moved = False  # by the user: then the split stays theirs
        self.split.splitterMoved.connect(lambda *_: setattr(self, "_split_moved", True))
        column = QtWidgets.QVBoxLayout(self)
        column.setContentsMargins(4, 2, 4, 2)
        column.addLayout(bar)
        column.addWidget(self.split, 1)
        self.model.connect("pattern", self._show_time)
        self.model.connect("playhead", self._show_time)
        editor.state.scene_changed.connect(self._on_state_scene_changed)
        self._show_time()
        self._on_state_scene_changed(editor.state.scene)

    def resizeEvent(self, event) -> None:  # Qt override
        super().resizeEvent(event)
        width = self.split.width()
        if not self._split_moved and width > 0:  # the properties whole, the rest: the time
            least = self.panel.minimumSizeHint().width() + 16
            side = min(max(least, round(width * 0.3)), max(least, 460))
            self.split.setSizes([max(width - side, 200), side])

    def _button(self, text: str, slot, hint: str) -> QtWidgets.QPushButton:
        button = QtWidgets.QPushButton(text)
        button.setToolTip(tip(hint))
        button.setFocusPolicy(QtCore.Qt.FocusPolicy.NoFocus)  # the keys stay the time line's
        button.clicked.connect(lambda: slot())
        return button

    def _menu_button(self, text: str, items) -> QtWidgets.QToolButton:
        button = QtWidgets.QToolButton()
        button.setText(text)
        button.setPopupMode(QtWidgets.QToolButton.ToolButtonPopupMode.InstantPopup)
        menu = QtWidgets.QMenu(button)
        for item in items:
            if item is None:
                menu.addSeparator()
            else:
                label, slot = item
                menu.addAction(label).triggered.connect(lambda _=False, s=slot: s()
                                                        if s is not None else None)  # fmt: skip
        button.setMenu(menu)
        return button

    def _show_time(self) -> None:
        model = self.model
        self.time_label.setText(f"{model.playhead_s:.2f} / {model.pattern.duration_s:.2f} s")

    def _on_state_scene_changed(self, scene) -> None:
        playing = self.editor.owns_scene() and scene.playing and not self.editor.state.held
        self.play_button.setText("Pause (Space)" if playing else "Play (Space)")

    def title(self, clean: bool | None = None) -> str:
        """The dock's title: the pattern's name (or file), a star while it has unsaved edits
        (``clean``: whether it has none, if known)."""
        model = self.model
        name = model.pattern.name or (model.path.name if model.path else "untitled")
        clean = self.editor.undo_stack.isClean() if clean is None else clean
        return f"Pattern editor - {name}{'' if clean else ' *'}"

    def retitle(self, clean=None) -> None:
        """Title the dock (the pattern changed, its file, or whether it is saved)."""
        dock = self.parentWidget()
        if isinstance(dock, QtWidgets.QDockWidget):
            dock.setWindowTitle(self.title(clean if isinstance(clean, bool) else None))


def install_timeline(window) -> TimelineEditor:
    """Give ``window`` (a ``MainWindow``) the pattern editor: its controller, the dock (tabbed
    with the device dock, hidden at first; *View → Pattern editor panel* and *File → Pattern
    editor* show it), and what excludes it (a blind test, an experiment run)."""
    tune = window.tune
    editor = TimelineEditor(window.state, tune.heatmap, window)
    editor.before_play = lambda: tune.gestures.set_draw_mode(False)
    editor.file_of = window.files.pattern_file
    editor.error_raised.connect(window.show_error)
    editor.message_posted.connect(window.statusBar().showMessage)
    tune.display.frame_shown.connect(editor.on_frame_shown)
    editor.files = PatternFiles(editor, window.device, window)
    editor.files.saved.connect(window.files.pattern_saved)  # the title names the file's pattern
    panel = TimelinePanel(editor, editor.files)
    dock = QtWidgets.QDockWidget("Pattern editor", window)
    dock.setObjectName("timeline_dock")
    dock.setWidget(panel)
    window.addDockWidget(QtCore.Qt.DockWidgetArea.BottomDockWidgetArea, dock)
    window.tabifyDockWidget(window.device_dock, dock)
    dock.hide()
    editor.dock, editor.panel = dock, panel

    for event in ("pattern", "path"):
        editor.model.connect(event, panel.retitle)
    editor.undo_stack.cleanChanged.connect(panel.retitle)  # (gone with the panel)
    toggle = dock.toggleViewAction()
    toggle.setText("Pattern editor panel")
    toggle.setShortcut(QtGui.QKeySequence("Ctrl+E"))
    # shown means in front of the device dock it shares a place with, its time line taking keys
    toggle.triggered.connect(lambda shown: show_editor(editor) if shown else None)
    lanes = next(a for a in window.view_menu.actions() if a.text() == "Activation curves in lanes")
    window.view_menu.insertAction(lanes, toggle)
    file_menu = next(a.menu() for a in window.menuBar().actions() if a.text() == "&File")
    opening = next(a for a in file_menu.actions() if a.text() == "Open pattern...")
    edit = QtGui.QAction("Pattern editor", file_menu)
    edit.triggered.connect(lambda: show_editor(editor))
    file_menu.insertAction(opening, edit)
    can_pulse = tune.gestures.can_pulse
    tune.gestures.can_pulse = lambda: can_pulse() and not editor.picking
    window.blind.blind_changed.connect(lambda on: panel.setEnabled(not on))
    window.experiments.running_changed.connect(lambda on: _hide_during_run(dock, on))
    reset = next(a for a in window.view_menu.actions() if a.text() == "Reset layout")
    reset.triggered.connect(dock.hide)  # as at first start
    return editor


def show_editor(editor) -> None:
    """Show the pattern editor's dock in front of the device dock, the keys in its time line."""
    editor.dock.show()
    editor.dock.raise_()
    editor.panel.view.setFocus()


def _hide_during_run(dock, running: bool) -> None:
    """A run hides the editor (participants see the screen); it comes back after the run."""
    if running:
        dock.setProperty("shown_before_run", dock.isVisible())
        dock.hide()
    elif dock.property("shown_before_run"):
        dock.show()
