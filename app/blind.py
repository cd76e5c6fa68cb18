"""Blind A/B on the array: methods shuffled onto number keys, rated before they are revealed."""

from __future__ import annotations

import csv
import datetime as dt
import random
import time
from pathlib import Path

from PySide6 import QtCore, QtWidgets

from tactile_core._shared.outfile import atomic_file, check_output
from tactile_core.rendering import placement
from tactile_core.rendering.methods import PAPER_METHODS, get_method

from . import dialogs
from .state import TunerState
from .widgets import MethodSetWidget

RATINGS = ("quality", "smoothness", "thickness")


def default_autosave_dir() -> Path:
    """Where blind sessions are autosaved: ``blind-ab`` in the application's data folder."""
    location = QtCore.QStandardPaths.StandardLocation.AppDataLocation
    return Path(QtCore.QStandardPaths.writableLocation(location) or Path.home()) / "blind-ab"


def shuffled(methods, seed: int) -> list[str]:
    """The methods on keys 1-N of a session with ``seed`` (what *Start* does, and how an
    autosave's mapping is recovered from its ``methods`` and ``seed`` columns)."""
    mapping = list(methods)
    random.Random(seed).shuffle(mapping)
    return mapping


class BlindPanel(QtWidgets.QWidget):
    """Blind A/B on the array (the paper's Experiment 1 preparation stage).

    Start shuffles the methods onto keys 1-N; pressing a key plays its method without saying
    which it is. Each key the rater felt gets 0-100 ratings of quality, smoothness and
    thickness; a rating starts empty (not rated), never at a value that could pass for one.
    Reveal and Save need every felt key rated. The saved file records which keys were felt and
    for how long (until Reveal); a key never played is saved as not rated. The mapping stays
    hidden until Reveal.

    Ratings are autosaved as they are entered (:attr:`autosave_path`, with the method column
    empty until Reveal); Start over a session with unsaved ratings, and *Cancel session*, ask
    first (:attr:`confirm`). Cancelling puts back the scene from before the session.

    On a layout that is not a grid the set keeps only the methods that render there (BA, RO,
    GS and EN when fewer than two are left), with a note, and gets the others back on a grid.
    """

    blind_changed = QtCore.Signal(bool)
    """True while the mapping is hidden: the window then hides method-revealing views."""

    NOT_RATED = -1

    def __init__(self, state: TunerState, parent=None, methods=None):
        super().__init__(parent)
        self.state = state
        self.methods = list(methods or PAPER_METHODS)
        self.mapping: list[str] = []
        self.seed: int | None = None
        self.current_key: int | None = None
        self.revealed = False
        self.session = ""
        self.felt_s: list[float] = []
        self._since: float | None = None
        self.confirm = lambda title, text: dialogs.confirm(self, title, text)
        """Asks yes or no before ratings are discarded (tests answer it themselves)."""
        self.autosave_dir = default_autosave_dir()
        self.autosave_path: Path | None = None
        """The session's autosave (None before a session or after its ratings were saved)."""
        self.unsaved = False
        """True once a rating was entered that no Save has written yet."""
        self._scene_before = None
        self._resetting = False
        layout = QtWidgets.QVBoxLayout(self)
        intro = QtWidgets.QLabel(
            "Start shuffles the methods onto number keys. Press a key to feel its method on the "
            "array (the display hides which one it is), rate every key you felt from 0 to 100, "
            "then Reveal and Save."
        )
        intro.setWordWrap(True)
        layout.addWidget(intro)
        self.chooser = MethodSetWidget(self.methods, 2, 8)
        self.chooser.check = lambda spec: placement.refusal(spec, state.layout)
        self.chooser.methods_changed.connect(self._on_methods_chosen)
        self._grid_methods = None  # the set chosen on a grid, while a layout restricts it
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
        self._build_rows()
        self.start_button.clicked.connect(lambda: self.start())
        self.reveal_button.clicked.connect(self.reveal)
        self.save_button.clicked.connect(self._on_save_clicked)
        self.cancel_button.clicked.connect(lambda: self.cancel())
        state.playing_changed.connect(lambda _: self._account())
        state.layout_changed.connect(self._on_state_layout_changed)
        self._enable(False)
        self._on_state_layout_changed(state.layout)

    @property
    def chosen_methods(self) -> list[str]:
        """The set to remember between sessions: the one chosen on a grid while a layout
        restricts it."""
        return list(self._grid_methods or self.methods)

    def _on_state_layout_changed(self, layout) -> None:
        """Keep the methods that render on ``layout`` (the window allows no layout change
        during a session or with unsaved ratings)."""
        wanted = self._grid_methods or self.methods
        methods, dropped = placement.restricted(wanted, layout)
        if methods != self.methods:
            try:
                self.set_methods(methods)
            except ValueError as exc:
                self.chooser.refuse(str(exc))
                return
        self._grid_methods = list(wanted) if dropped else None
        self.chooser.refuse(placement.restriction_note(dropped, methods, layout, "blind test of"),
                            warn=False)  # fmt: skip

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
        for k in range(len(self.methods)):
            button = QtWidgets.QPushButton(f"{k + 1}")
            button.setCheckable(True)
            button.setObjectName(f"blind_key_{k + 1}")
            button.clicked.connect(lambda _=False, k=k: self.select_key(k + 1))
            label = QtWidgets.QLabel("?")
            label.setObjectName(f"blind_method_{k + 1}")
            spins = []
            for j, name in enumerate(RATINGS):
                spin = QtWidgets.QSpinBox()
                spin.setRange(self.NOT_RATED, 100)
                spin.setSpecialValueText("not rated")  # shown at NOT_RATED
                spin.setValue(self.NOT_RATED)
                spin.setObjectName(f"blind_{name}_{k + 1}")
                spin.setToolTip(f"{name} of key {k + 1}, 0-100 (empty until you rate it)")
                spin.valueChanged.connect(self._on_rating_spin_changed)
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

    def set_methods(self, methods) -> None:
        """Use another set of methods (2-8); takes effect at the next Start."""
        methods = list(methods)
        if not 2 <= len(methods) <= 8 or len(set(methods)) != len(methods):
            raise ValueError(f"blind A/B needs 2 to 8 distinct methods, got {methods}")
        if self.active:
            raise ValueError("blind A/B is running: reveal it before changing the methods")
        if self.unsaved:
            raise ValueError("the session's ratings are not saved: save them or cancel the "
                             "session before changing the methods")  # fmt: skip
        self.methods = methods
        self.chooser.methods = list(methods)
        self.chooser.edit.setText(" ".join(methods))
        self.mapping = []
        self._build_rows()
        self._enable(False)

    def _on_methods_chosen(self, methods) -> None:
        try:
            self.set_methods(methods)
        except ValueError as exc:
            self.chooser.refuse(str(exc), keep=self.methods)

    @property
    def active(self) -> bool:
        """True while a shuffled mapping is in use and not yet revealed."""
        return bool(self.mapping) and not self.revealed

    def _enable(self, on: bool) -> None:
        for b in self.key_buttons:
            b.setEnabled(on)
        self.reveal_button.setEnabled(on and not self.revealed)
        self.save_button.setEnabled(on)
        self.cancel_button.setEnabled(on)
        self.chooser.setEnabled(not (on and not self.revealed))

    def _account(self) -> None:
        """Add the time since the last event to the key being felt (while playing, before
        Reveal: what is felt after the mapping is known is not blind)."""
        if self.revealed:
            self._since = None
            return
        now = time.monotonic()
        if self._since is not None and self.current_key is not None:
            self.felt_s[self.current_key - 1] += now - self._since
            k = self.current_key - 1
            self.felt_labels[k].setText(f"{self.felt_s[k]:.1f} s")
        self._since = now if self.state.scene.playing and self.mapping else None

    def start(self, seed: int | None = None) -> bool:
        """Shuffle the methods onto keys 1-N and hide the mapping; over a session with unsaved
        ratings, only once :attr:`confirm` says yes (False otherwise)."""
        if self.unsaved and not self.confirm(
            "Start a new blind session",
            f"The ratings of this session are not saved{self._where()}.\n\nDiscard them and "
            "shuffle again?",
        ):
            return False
        if not self.active:
            self._scene_before = self.state.scene
        self.seed = random.SystemRandom().randrange(2**31) if seed is None else seed
        self.mapping = shuffled(self.methods, self.seed)
        self.revealed = False
        self.unsaved = False
        self.current_key = None
        self._since = None
        self.felt_s = [0.0] * len(self.mapping)
        self.session = dt.datetime.now().isoformat(timespec="seconds")
        stamp = self.session.replace(":", "")
        self.autosave_path = self.autosave_dir / f"blind-ab-{stamp}-seed{self.seed}.csv"
        self._resetting = True
        for label in self.method_labels:
            label.setText("?")
        for spins in self.rating_spins:
            for spin in spins:
                spin.setValue(self.NOT_RATED)
        for label in self.felt_labels:
            label.setText("-")
        for b in self.key_buttons:
            b.setChecked(False)
        self._resetting = False
        self._enable(True)
        self.status.setText(f"blind: press 1-{len(self.mapping)} to switch methods")
        self.blind_changed.emit(True)
        self.select_key(1)
        return True

    def cancel(self) -> bool:
        """End the session without rating everything (asking first when ratings are unsaved):
        the scene from before it comes back, paused; the ratings stay in the autosave."""
        if not self.mapping:
            return False
        if self.unsaved and not self.confirm(
            "Cancel the blind session",
            f"The ratings of this session are not saved{self._where()}.\n\nCancel the session?",
        ):
            return False
        was_blind = self.active
        self._account()
        if self.unsaved:
            self._autosave()
        where = self._where() if self.unsaved else ""
        before, self._scene_before = self._scene_before, None
        if before is not None and was_blind:
            self.state.set_scene(before.replace(playing=False, epoch=self.state.scene.epoch + 1))
        self.mapping, self.current_key, self.revealed, self.unsaved = [], None, False, False
        self._resetting = True
        for label in self.method_labels:
            label.setText("?")
        for spins in self.rating_spins:
            for spin in spins:
                spin.setValue(self.NOT_RATED)
        for b in self.key_buttons:
            b.setChecked(False)
        self._resetting = False
        self._enable(False)
        self.status.setText("cancelled" + (f": the unsaved ratings are kept{where}" if where
                                           else ""))  # fmt: skip
        if was_blind:
            self.blind_changed.emit(False)
        return True

    def _where(self) -> str:
        return f" (autosaved in {self.autosave_path})" if self.autosave_path else ""

    def _on_rating_spin_changed(self, _value: int) -> None:
        if self._resetting or not self.mapping:
            return
        self.unsaved = True
        self._autosave()

    def _autosave(self) -> None:
        """Write the session as it stands (the method column empty until Reveal; the seed and
        the ``methods`` column recover the mapping, :func:`shuffled`)."""
        if self.autosave_path is None or not self.mapping:
            return
        rows = self.ratings()
        for row in rows:
            if not self.revealed:
                row["method"] = ""
            row["methods"] = " ".join(self.methods)
        try:
            self.autosave_path.parent.mkdir(parents=True, exist_ok=True)
            with atomic_file(self.autosave_path) as f:
                writer = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
                writer.writeheader()
                writer.writerows(rows)
        except (OSError, ValueError) as exc:
            self.status.setText(f"could not autosave the ratings: {exc}")

    def select_key(self, key: int) -> None:
        """Play the method behind ``key`` (1-N)."""
        if not self.mapping or not 1 <= key <= len(self.mapping):
            return
        self._account()
        self.current_key = key
        for i, b in enumerate(self.key_buttons):
            b.setChecked(i == key - 1)
        # A play starts the trace again: one presentation (one LSL marker, kind "ab") per play.
        self.state.update(method=self.mapping[key - 1], playing=True, marker="ab",
                          epoch=self.state.scene.epoch + 1)  # fmt: skip
        self._account()
        if self.unsaved:
            self._autosave()
        self.status.setText(
            f"playing key {key}" + (f" ({self.mapping[key - 1]})" if self.revealed else "")
        )

    def felt(self) -> list[bool]:
        """Per key: was it played?"""
        return [s > 0.0 for s in self.felt_s]

    def missing(self) -> list[str]:
        """What is still to rate: ``"key 2 smoothness"`` for each felt key's empty rating."""
        self._account()
        out = []
        for k, (was_felt, spins) in enumerate(zip(self.felt(), self.rating_spins)):
            if was_felt:
                out += [
                    f"key {k + 1} {name}"
                    for name, spin in zip(RATINGS, spins)
                    if spin.value() == self.NOT_RATED
                ]
        return out

    def _refuse_if_unrated(self, action: str) -> bool:
        missing = self.missing()
        if not any(self.felt()):
            self.status.setText(f"{action}: no key was felt yet")
            return True
        if missing:
            self.status.setText(
                f"{action} needs every key you felt rated: still empty: {', '.join(missing)}"
            )
            return True
        return False

    def reveal(self) -> bool:
        """Show which method was behind each key (once every felt key is rated)."""
        if not self.mapping or self._refuse_if_unrated("Reveal"):
            return False
        self._account()  # felt time ends here: what is felt from now on is not blind
        self.revealed = True
        for label, method in zip(self.method_labels, self.mapping):
            label.setText(f"{method} ({get_method(method).title})")
        self.reveal_button.setEnabled(False)
        self.status.setText("revealed")
        self._enable(True)
        if self.unsaved:
            self._autosave()
        self.blind_changed.emit(False)
        return True

    def ratings(self) -> list[dict]:
        """One record per key: mapping, whether and how long it was felt, ratings (empty when
        not rated), and the scene they were given on."""
        self._account()
        scene = self.state.scene
        rows = []
        for k, method in enumerate(self.mapping):
            values = {
                name: ("" if self.rating_spins[k][j].value() == self.NOT_RATED else
                       self.rating_spins[k][j].value())
                for j, name in enumerate(RATINGS)
            }  # fmt: skip
            rows.append(
                {
                    "session": self.session,
                    "key": k + 1,
                    "method": method,
                    "felt": int(self.felt_s[k] > 0.0),
                    "felt_s": f"{self.felt_s[k]:.2f}",
                    **values,
                    "shape": scene.shape.spec if scene.shape is not None else "",
                    "mu": scene.mu,
                    "gamma": scene.gamma,
                    "duration_s": scene.duration_s,
                    "pause_s": scene.pause_s,
                    "seed": self.seed,
                    "revealed_before_save": self.revealed,
                }
            )
        return rows

    def save(self, path) -> Path | None:
        """Append the ratings and mapping to a CSV (header written for a new file); the file
        is rewritten atomically, so a full disk never loses the earlier rows. None (and a
        status) while a felt key is unrated."""
        if self._refuse_if_unrated("Save"):
            return None
        path = check_output(path, (".csv",), "ratings file")
        rows = self.ratings()
        old = path.read_text(encoding="utf-8") if path.exists() else ""
        if old and not old.startswith(",".join(rows[0]) + "\n"):
            raise ValueError(f"{path} holds other columns: save the ratings to a new file")
        with atomic_file(path) as f:
            f.write(old)
            writer = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
            if not old:
                writer.writeheader()
            writer.writerows(rows)
        self.unsaved = False
        if self.autosave_path is not None:
            self.autosave_path.unlink(missing_ok=True)
        self.status.setText(f"saved to {path}")
        return path

    def _on_save_clicked(self) -> None:
        name = f"blind-ab-{dialogs.today()}.csv"
        path = dialogs.save_path(self, "ratings", "Save ratings", name, ["CSV (*.csv)"])
        if path:
            try:
                self.save(path)
            except (OSError, ValueError) as exc:
                self.status.setText(f"could not save: {exc}")
