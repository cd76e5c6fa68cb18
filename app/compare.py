"""Comparing methods: all four side by side, and blind A/B ratings on the array."""

from __future__ import annotations

import csv
import datetime as dt
import random
import time
from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtWidgets

import tactile_core as tc
from tactile_core.curves import activation_curves
from tactile_core.methods import METHODS

from .state import TunerState
from .views import CurvesView, HeatmapView, cell_colors

RATINGS = ("quality", "smoothness", "thickness")


class CompareView(QtWidgets.QWidget):
    """Four heatmaps (CT, MM, AS, IM) and their activation curves on one time axis, all at the
    current time of the trace. The array plays the method selected in the controls."""

    def __init__(self, state: TunerState, parent=None):
        super().__init__(parent)
        self.state = state
        grid = QtWidgets.QGridLayout(self)
        self.heatmaps = {}
        self.curves = {}
        for i, (name, method) in enumerate(METHODS.items()):
            # Short titles: a plot item never shrinks below its title's width.
            heat = HeatmapView(title=name, colorbar=False)
            heat.setToolTip(f"{name}: {method.title}")
            heat.plot.setLabel("bottom", "")
            heat.plot.setLabel("left", "")
            heat.setMinimumSize(120, 160)
            curve = CurvesView(title=f"{name} activation")
            curve.setMinimumSize(120, 120)
            curve.setLabel("left", "")
            grid.addWidget(heat, 0, i)
            grid.addWidget(curve, 1, i)
            self.heatmaps[name] = heat
            self.curves[name] = curve
        first = self.curves["CT"]
        for name in ("MM", "AS", "IM"):
            self.curves[name].setXLink(first)
        grid.setRowStretch(0, 3)
        grid.setRowStretch(1, 2)
        for column in range(4):
            grid.setColumnStretch(column, 1)
        self._shown_scene = None

    def _refresh(self) -> None:
        """Recompute the four methods' curves if the scene changed since last time."""
        scene = self.state.scene
        if scene is self._shown_scene:
            return
        self._shown_scene = scene
        if scene.shape is None:
            return
        outline = scene.shape.outline()
        for name in METHODS:
            curves = activation_curves(
                scene.shape,
                name,
                duration_s=scene.duration_s,
                direction=scene.direction,
                mu=scene.mu,
                gamma=scene.gamma,
                samples=600,
            )
            colors = cell_colors(curves.cells)
            self.curves[name].set_curves(
                curves, colors, scene.duration_s + scene.pause_s, raw=False
            )
            self.heatmaps[name].set_cell_frames(colors)
            self.heatmaps[name].set_outline(outline)

    def tick(self, scene, t, phase_s) -> None:
        """Show every method's corrected frame at trace parameter ``t`` (None while off).

        Called by the display timer only while the view is visible; its curves are brought up
        to date here, at most every 100 ms, so a hidden compare view costs nothing."""
        now = time.perf_counter()
        if scene is not self._shown_scene and now - getattr(self, "_last_refresh", 0.0) > 0.1:
            self._last_refresh = now
            self._refresh()
        for name in METHODS:
            heat = self.heatmaps[name]
            if t is None or scene.shape is None:
                heat.set_frame(np.zeros((heat.rows, heat.cols)))
                heat.set_point(None)
            else:
                frame = tc.render(scene.shape, name, t)
                heat.set_frame(tc.correct(frame, scene.mu, scene.gamma, gain=scene.gain))
                heat.set_point(scene.shape.point(t))
            self.curves[name].set_cursor(phase_s)


class BlindPanel(QtWidgets.QWidget):
    """Blind A/B on the array (the paper's Experiment 1 preparation stage).

    Start shuffles the four methods onto keys 1-4; pressing a key plays its method without
    saying which it is. Each key gets 0-100 ratings of quality, smoothness and thickness. The
    mapping stays hidden until Reveal; Save writes ratings and mapping to CSV.
    """

    blind_changed = QtCore.Signal(bool)
    """True while the mapping is hidden: the window then hides method-revealing views."""

    def __init__(self, state: TunerState, parent=None):
        super().__init__(parent)
        self.state = state
        self.mapping: list[str] = []
        self.seed: int | None = None
        self.current_key: int | None = None
        self.revealed = False
        self.session = ""
        layout = QtWidgets.QVBoxLayout(self)
        intro = QtWidgets.QLabel(
            "Start shuffles the methods onto keys 1-4. Press a key to feel its method on the "
            "array (the display hides which one it is), rate each key from 0 to 100, then "
            "Reveal and Save."
        )
        intro.setWordWrap(True)
        layout.addWidget(intro)
        buttons = QtWidgets.QHBoxLayout()
        self.start_button = QtWidgets.QPushButton("Start (shuffle)")
        self.start_button.setObjectName("blind_start")
        self.reveal_button = QtWidgets.QPushButton("Reveal")
        self.reveal_button.setObjectName("blind_reveal")
        self.save_button = QtWidgets.QPushButton("Save ratings...")
        for b in (self.start_button, self.reveal_button, self.save_button):
            buttons.addWidget(b)
        buttons.addStretch(1)
        layout.addLayout(buttons)
        table = QtWidgets.QGridLayout()
        table.addWidget(QtWidgets.QLabel("<b>key</b>"), 0, 0)
        table.addWidget(QtWidgets.QLabel("<b>method</b>"), 0, 1)
        for j, name in enumerate(RATINGS):
            table.addWidget(QtWidgets.QLabel(f"<b>{name}</b>"), 0, 2 + j)
        self.key_buttons = []
        self.method_labels = []
        self.rating_spins = []
        for k in range(4):
            button = QtWidgets.QPushButton(f"{k + 1}")
            button.setCheckable(True)
            button.setObjectName(f"blind_key_{k + 1}")
            button.clicked.connect(lambda _=False, k=k: self.select_key(k + 1))
            label = QtWidgets.QLabel("?")
            label.setObjectName(f"blind_method_{k + 1}")
            spins = []
            for j in range(len(RATINGS)):
                spin = QtWidgets.QSpinBox()
                spin.setRange(0, 100)
                spin.setValue(50)
                spin.setObjectName(f"blind_{RATINGS[j]}_{k + 1}")
                table.addWidget(spin, 1 + k, 2 + j)
                spins.append(spin)
            table.addWidget(button, 1 + k, 0)
            table.addWidget(label, 1 + k, 1)
            self.key_buttons.append(button)
            self.method_labels.append(label)
            self.rating_spins.append(spins)
        layout.addLayout(table)
        self.status = QtWidgets.QLabel("not started")
        layout.addWidget(self.status)
        layout.addStretch(1)
        self.start_button.clicked.connect(lambda: self.start())
        self.reveal_button.clicked.connect(self.reveal)
        self.save_button.clicked.connect(self._on_save_clicked)
        self._enable(False)

    @property
    def active(self) -> bool:
        """True while a shuffled mapping is in use and not yet revealed."""
        return bool(self.mapping) and not self.revealed

    def _enable(self, on: bool) -> None:
        for b in self.key_buttons:
            b.setEnabled(on)
        self.reveal_button.setEnabled(on and not self.revealed)
        self.save_button.setEnabled(on)

    def start(self, seed: int | None = None) -> None:
        """Shuffle the methods onto keys 1-4 and hide the mapping."""
        self.seed = random.SystemRandom().randrange(2**31) if seed is None else seed
        self.mapping = list(METHODS)
        random.Random(self.seed).shuffle(self.mapping)
        self.revealed = False
        self.current_key = None
        self.session = dt.datetime.now().isoformat(timespec="seconds")
        for label in self.method_labels:
            label.setText("?")
        for spins in self.rating_spins:
            for spin in spins:
                spin.setValue(50)
        for b in self.key_buttons:
            b.setChecked(False)
        self._enable(True)
        self.status.setText("blind: press 1-4 to switch methods")
        self.blind_changed.emit(True)
        self.select_key(1)

    def select_key(self, key: int) -> None:
        """Play the method behind ``key`` (1-4)."""
        if not self.mapping:
            return
        self.current_key = key
        for i, b in enumerate(self.key_buttons):
            b.setChecked(i == key - 1)
        self.state.update(method=self.mapping[key - 1], playing=True)
        self.status.setText(
            f"playing key {key}" + (f" ({self.mapping[key - 1]})" if self.revealed else "")
        )

    def reveal(self) -> None:
        """Show which method was behind each key."""
        if not self.mapping:
            return
        self.revealed = True
        for label, method in zip(self.method_labels, self.mapping):
            label.setText(f"{method} ({METHODS[method].title})")
        self.reveal_button.setEnabled(False)
        self.status.setText("revealed")
        self.blind_changed.emit(False)

    def ratings(self) -> list[dict]:
        """One record per key: mapping, ratings and the scene they were given on."""
        scene = self.state.scene
        rows = []
        for k, method in enumerate(self.mapping):
            row = {
                "session": self.session,
                "key": k + 1,
                "method": method,
                **{name: self.rating_spins[k][j].value() for j, name in enumerate(RATINGS)},
                "shape": scene.shape.spec if scene.shape is not None else "",
                "mu": scene.mu,
                "gamma": scene.gamma,
                "duration_s": scene.duration_s,
                "pause_s": scene.pause_s,
                "seed": self.seed,
                "revealed_before_save": self.revealed,
            }
            rows.append(row)
        return rows

    def save(self, path) -> Path:
        """Append the ratings and mapping to a CSV (header written for a new file)."""
        path = Path(path)
        rows = self.ratings()
        new = not path.exists() or path.stat().st_size == 0
        with path.open("a", newline="", encoding="utf-8") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            if new:
                writer.writeheader()
            writer.writerows(rows)
            f.flush()
        self.status.setText(f"saved to {path}")
        return path

    def _on_save_clicked(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, "Save ratings", "blind-ab.csv", "CSV (*.csv)"
        )
        if path:
            try:
                self.save(path)
            except (OSError, ValueError) as exc:
                self.status.setText(f"could not save: {exc}")
