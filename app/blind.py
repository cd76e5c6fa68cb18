"""Blind A/B on the array: the view of a :class:`~tactile_core.experiments.BlindSession`."""

from __future__ import annotations

import time
from pathlib import Path

from PySide6 import QtCore, QtWidgets

from tactile_core.experiments import BlindSession
from tactile_core.experiments.blind import RATINGS
from tactile_core.rendering import placement
from tactile_core.rendering.methods import PAPER_METHODS, get_method

from . import dialogs
from .state import TunerState
from .widgets import MethodSetWidget

NOT_RATED = -1
"""A rating spin box's value while its rating is not given (shown as "not rated")."""
FELT_TICK_MS = 200
"""How often the *felt* column is redrawn while a key plays (a tenth of a second shown)."""


def default_autosave_dir() -> Path:
    """Where blind sessions are autosaved: ``blind-ab`` in the application's data folder."""
    location = QtCore.QStandardPaths.StandardLocation.AppDataLocation
    return Path(QtCore.QStandardPaths.writableLocation(location) or Path.home()) / "blind-ab"


class BlindPanel(QtWidgets.QWidget):
    """Blind A/B on the array (the paper's Experiment 1 preparation stage): the view of
    :attr:`session`, a :class:`~tactile_core.experiments.BlindSession`, which holds the mapping,
    the felt time, the ratings and the rules.

    Start shuffles the methods onto keys 1-N and plays nothing: the array is off until the
    rater presses a key, so the order of presentation is the rater's (no key is always first,
    and none counts as felt before it is pressed). Pressing a key plays its method without
    saying which it is; before the first key Space, Restart and the play button play nothing
    (the scene from before the session would pass for a key). Each key the rater felt gets
    0-100 ratings of quality, smoothness and thickness (a rating starts empty, "not rated");
    Reveal and Save need every felt key rated, and a refusal's list of what is still empty
    shrinks as the ratings come in. The panel shows the session and writes what the user does
    to it; the session plays nothing itself: the panel puts the key's method in the tuner's
    scene and tells the session whether it plays.

    Start over a session with unsaved ratings, and *Cancel session*, ask first
    (:attr:`confirm`). Cancelling puts back the scene from before the session.

    On a layout that is not a grid the set keeps only the methods that render there (BA, RO,
    GS and EN when fewer than two are left), with a note, and gets the others back on a grid.

    Parameters
    ----------
    state : TunerState
    methods : sequence of str, optional
        The paper's four by default.
    clock : callable
        Monotonic seconds for the session's felt time (tests pass a fake one).
    """

    blind_changed = QtCore.Signal(bool)
    """True while the mapping is hidden: the window then hides method-revealing views."""

    def __init__(self, state: TunerState, parent=None, methods=None, clock=time.monotonic):
        super().__init__(parent)
        self.state = state
        self.session = BlindSession(methods or PAPER_METHODS, clock=clock,
                                    autosave_dir=default_autosave_dir())  # fmt: skip
        self.session.scene = state.scene
        self.confirm = lambda title, text: dialogs.confirm(self, title, text)
        """Asks yes or no before ratings are discarded (tests answer it themselves)."""
        self._blind_shown = False  # what blind_changed said last
        self._refused = ""  # the action (Reveal, Save) whose refusal the status shows
        state.play_guard = self._play_guard
        self._grid_methods = None  # the set chosen on a grid, while a layout restricts it
        layout = QtWidgets.QVBoxLayout(self)
        intro = QtWidgets.QLabel(
            "Start shuffles the methods onto number keys; nothing plays until you press one. "
            "Press the keys in any order to feel their methods on the array (the display hides "
            "which one it is), rate every key you felt from 0 to 100, then Reveal and Save."
        )
        intro.setWordWrap(True)
        layout.addWidget(intro)
        self.chooser = MethodSetWidget(self.session.methods, 2, 8)
        self.chooser.check = lambda spec: placement.refusal(spec, state.layout)
        self.chooser.methods_changed.connect(self._on_chooser_methods_changed)
        layout.addWidget(self.chooser)
        buttons = QtWidgets.QHBoxLayout()
        self.start_button = QtWidgets.QPushButton("Start (shuffle)")
        self.start_button.setObjectName("blind_start")
        self.reveal_button = QtWidgets.QPushButton("Reveal")
        self.reveal_button.setObjectName("blind_reveal")
        self.save_button = QtWidgets.QPushButton("Save ratings...")
        self.cancel_button = QtWidgets.QPushButton("Cancel session")
        self.cancel_button.setObjectName("blind_cancel")
        self.cancel_button.setToolTip(
            "End the session without rating everything: the scene from before it comes back; "
            "the ratings entered stay in the autosave"
        )
        for b in (self.start_button, self.reveal_button, self.save_button, self.cancel_button):
            buttons.addWidget(b)
        buttons.addStretch(1)
        layout.addLayout(buttons)
        self.table = QtWidgets.QGridLayout()
        layout.addLayout(self.table)
        self.status = QtWidgets.QLabel("not started")
        self.status.setObjectName("blind_status")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        layout.addStretch(1)
        self.key_buttons: list = []
        self.method_labels: list = []
        self.rating_spins: list = []
        self.felt_labels: list = []
        self._felt_timer = QtCore.QTimer(self)  # the felt column counts while a key plays
        self._felt_timer.setInterval(FELT_TICK_MS)
        self._felt_timer.timeout.connect(self._show_felt)
        self.start_button.clicked.connect(lambda: self.start())
        self.reveal_button.clicked.connect(self.reveal)
        self.save_button.clicked.connect(self._on_save_clicked)
        self.cancel_button.clicked.connect(lambda: self.cancel())
        self.session.listeners.append(self._on_session_changed)
        state.playing_changed.connect(self._on_state_playing_changed)
        state.scene_changed.connect(self._on_state_scene_changed)
        state.layout_changed.connect(self._on_state_layout_changed)
        self._on_session_changed()
        self._on_state_layout_changed(state.layout)

    @property
    def chosen_methods(self) -> list[str]:
        """The set to remember between sessions: the one chosen on a grid while a layout
        restricts it."""
        return list(self._grid_methods or self.session.methods)

    # --- what the user does, written to the session --------------------------------------------

    def set_methods(self, methods) -> None:
        """Use another set of methods (2-8) from the next Start (``ValueError`` during a
        session or with unsaved ratings)."""
        self.session.set_methods(methods)

    def start(self, seed: int | None = None) -> bool:
        """Shuffle the methods onto keys 1-N, hide the mapping and turn the array off until
        the rater's first key; over a session with unsaved ratings, only once :attr:`confirm`
        says yes (False otherwise)."""
        if self.session.unsaved and not self.confirm(
            "Start a new blind session",
            f"The ratings of this session are not saved{self._where()}.\n\nDiscard them and "
            "shuffle again?",
        ):
            return False
        self.session.start(seed, discard=True)
        self.state.update(playing=False)  # the scene from before: no key's, so not played
        return True

    def _play_guard(self) -> str:
        """Why the scene may not play now: blind, before the first key (it is no key's)."""
        session = self.session
        if session.active and session.current_key is None:
            return f"press a key 1-{len(session.mapping)} first: nothing plays before a key"
        return ""

    def select_key(self, key: int) -> None:
        """Play the method behind ``key`` (1-N)."""
        session = self.session
        if not session.mapping or not 1 <= key <= len(session.mapping):
            return
        method = session.select(key)
        # A play starts the trace again: one presentation (one LSL marker, kind "ab") per play.
        self.state.update(method=method, playing=True, marker="ab",
                          epoch=self.state.scene.epoch + 1)  # fmt: skip
        session.set_playing(self.state.scene.playing)  # (a refused method does not play)
        self._say(f"playing key {key}" + (f" ({method})" if session.revealed else ""))
        self._follow_felt()

    def reveal(self) -> bool:
        """Show which method was behind each key (once every felt key is rated)."""
        try:
            self.session.reveal()
        except ValueError as exc:
            self._say(str(exc), refused="Reveal")
            return False
        self._say("revealed")
        return True

    def cancel(self) -> bool:
        """End the session without rating everything (asking first when ratings are unsaved):
        the scene from before it comes back, paused; the ratings stay in the autosave."""
        session = self.session
        if not session.mapping:
            return False
        if session.unsaved and not self.confirm(
            "Cancel the blind session",
            f"The ratings of this session are not saved{self._where()}.\n\nCancel the session?",
        ):
            return False
        kept = self._where() if session.unsaved else ""
        before = session.scene_before if session.active else None
        if before is not None:  # put back while the method is still hidden
            self.state.set_scene(before.replace(playing=False, epoch=self.state.scene.epoch + 1))
        session.cancel()
        self._say("cancelled" + (f": the unsaved ratings are kept{kept}" if kept else ""))
        return True

    def save(self, path) -> Path | None:
        """Append the ratings to a CSV (:meth:`BlindSession.save`); None, and why in the status,
        when they cannot be saved (a felt key unrated, a path that cannot be written)."""
        try:
            path = self.session.save(path)
        except OSError as exc:
            self._say(f"could not save: {exc}")
            return None
        except ValueError as exc:
            self._say(str(exc), refused="Save")
            return None
        self._say(f"saved to {path}")
        return path

    def _on_save_clicked(self) -> None:
        name = f"blind-ab-{dialogs.today()}.csv"
        path = dialogs.save_path(self, "ratings", "Save ratings", name, ["CSV (*.csv)"])
        if path:
            self.save(path)

    def _on_rating_spin_changed(self, key: int, name: str, value: int) -> None:
        try:
            self.session.rate(key, name, None if value == NOT_RATED else value)
        except ValueError as exc:
            self._say(str(exc))
            self._on_session_changed()  # the spin shows the session's rating again
            return
        if self.session.autosave_error:
            self._say("")

    def _on_chooser_methods_changed(self, methods) -> None:
        try:
            self.set_methods(methods)
        except ValueError as exc:
            self.chooser.refuse(str(exc), keep=self.session.methods)

    def _on_state_playing_changed(self, playing: bool) -> None:
        session = self.session
        key = session.current_key
        session.set_playing(playing and key is not None)
        if session.mapping and key is not None:  # Space: the status line says so
            method = f" ({session.mapping[key - 1]})" if session.revealed else ""
            self._say(f"playing key {key}{method}" if playing else
                      f"key {key}{method} paused: Space plays it again")  # fmt: skip
        self._follow_felt()

    def _follow_felt(self) -> None:
        """Count the felt column up on the display while a key is felt (the session's clock
        runs; its labels changed only with the session)."""
        session = self.session
        felt = session.active and session.current_key is not None and self.state.scene.playing
        if felt and not self._felt_timer.isActive():
            self._felt_timer.start()
        elif not felt:
            self._felt_timer.stop()
        self._show_felt()

    def _show_felt(self) -> None:
        session = self.session
        felt_s = session.felt_s if session.mapping else ()
        for k, label in enumerate(self.felt_labels):
            shown = k < len(felt_s) and felt_s[k] > 0.0
            label.setText(f"{felt_s[k]:.1f} s" if shown else "-")

    def _on_state_scene_changed(self, scene) -> None:
        self.session.scene = scene

    def _on_state_layout_changed(self, layout) -> None:
        """Keep the methods that render on ``layout`` (the window allows no layout change
        during a session or with unsaved ratings)."""
        wanted = self._grid_methods or self.session.methods
        methods, dropped = placement.restricted(wanted, layout)
        if tuple(methods) != self.session.methods:
            try:
                self.set_methods(methods)
            except ValueError as exc:
                self.chooser.refuse(str(exc))
                return
        self._grid_methods = list(wanted) if dropped else None
        self.chooser.refuse(placement.restriction_note(dropped, methods, layout, "blind test of"),
                            warn=False)  # fmt: skip

    # --- the view of the session ---------------------------------------------------------------

    def _say(self, text: str, refused: str = "") -> None:
        """``text`` in the status line, with why the last autosave failed, if it did;
        ``refused``: the text is why that action (Reveal, Save) was refused, kept up to date
        as the session changes (:meth:`_on_session_changed`)."""
        self._refused = refused
        problem = self.session.autosave_error
        self.status.setText("; ".join(t for t in (text, problem) if t) or self.status.text())

    def _update_refusal(self) -> None:
        """The refusal on show, as it stands now: what is still empty, or that it may go on."""
        action = self._refused
        if not action or not self.session.mapping:
            return
        why = self.session.refusal(action)
        self._say(why or f"every key you felt is rated: {action} now", refused=action if why
                  else "")  # fmt: skip

    def _where(self) -> str:
        path = self.session.autosave_path
        return f" (autosaved in {path})" if path else ""

    def _on_session_changed(self) -> None:
        """Show the session: the chooser's set, one row per key, the buttons that apply; tell
        the window when the mapping is hidden or shown."""
        session = self.session
        if list(session.methods) != self.chooser.methods:
            self.chooser.methods = list(session.methods)
            self.chooser.show_methods()
        if len(self.key_buttons) != len(session.methods):
            self._build_rows()
        on, dealt = session.active, bool(session.mapping)
        for k, (button, label, spins) in enumerate(
            zip(self.key_buttons, self.method_labels, self.rating_spins)
        ):
            button.setEnabled(dealt)
            button.setChecked(session.current_key == k + 1)
            method = session.mapping[k] if session.revealed else None
            label.setText(f"{method} ({get_method(method).title})" if method else "?")
            for name, spin in zip(RATINGS, spins):
                value = session.rating(k + 1, name) if dealt else None
                spin.blockSignals(True)
                spin.setValue(NOT_RATED if value is None else value)
                spin.blockSignals(False)
                spin.setEnabled(dealt)
        self._follow_felt()
        self.reveal_button.setEnabled(on)
        self.save_button.setEnabled(dealt)
        self.cancel_button.setEnabled(dealt)
        self.chooser.setEnabled(not on)
        self._update_refusal()
        if on != self._blind_shown:
            self._blind_shown = on
            if on:
                self._say(f"blind: press a key 1-{len(session.mapping)} to feel its method, in "
                          "any order (nothing plays until you do)")  # fmt: skip
            self.blind_changed.emit(on)

    def _build_rows(self) -> None:
        """One row per key: the key, its method (hidden), the ratings, the time felt."""
        while self.table.count():
            item = self.table.takeAt(0)
            if item.widget() is not None:
                item.widget().deleteLater()
        headers = ("key", "method", *RATINGS, "felt")
        for j, text in enumerate(headers):
            self.table.addWidget(QtWidgets.QLabel(f"<b>{text}</b>"), 0, j)
        self.key_buttons, self.method_labels, self.rating_spins, self.felt_labels = [], [], [], []
        for k in range(len(self.session.methods)):
            button = QtWidgets.QPushButton(f"{k + 1}")
            button.setCheckable(True)
            button.setObjectName(f"blind_key_{k + 1}")
            button.clicked.connect(lambda _=False, k=k: self.select_key(k + 1))
            label = QtWidgets.QLabel("?")
            label.setObjectName(f"blind_method_{k + 1}")
            spins = []
            for j, name in enumerate(RATINGS):
                spin = QtWidgets.QSpinBox()
                spin.setRange(NOT_RATED, 100)
                spin.setSpecialValueText("not rated")  # shown at NOT_RATED
                spin.setValue(NOT_RATED)
                spin.setObjectName(f"blind_{name}_{k + 1}")
                spin.setToolTip(f"{name} of key {k + 1}, 0-100 (empty until you rate it)")
                spin.valueChanged.connect(
                    lambda value, k=k, name=name: self._on_rating_spin_changed(k + 1, name, value)
                )
                self.table.addWidget(spin, 1 + k, 2 + j)
                spins.append(spin)
            felt = QtWidgets.QLabel("-")
            felt.setObjectName(f"blind_felt_{k + 1}")
            self.table.addWidget(button, 1 + k, 0)
            self.table.addWidget(label, 1 + k, 1)
            self.table.addWidget(felt, 1 + k, 2 + len(RATINGS))
            self.key_buttons.append(button)
            self.method_labels.append(label)
            self.rating_spins.append(spins)
            self.felt_labels.append(felt)
