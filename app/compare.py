"""Comparing methods: any set side by side, their heatmaps and curves on one time axis."""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from PySide6 import QtWidgets

from tactile_core.rendering import placement
from tactile_core.rendering.curves import activation_curves
from tactile_core.rendering.methods import PAPER_METHODS, get_method

from .frames import SceneFrames
from .state import TunerState
from .titles import source_kind
from .views import CurvesView, HeatmapView, cell_colors
from .widgets import MethodSetWidget


class CompareView(QtWidgets.QWidget):
    """Any 2-6 methods (the paper's four by default): their heatmaps and activation curves on
    one time axis, all at the current time of the trace. The array plays the method selected in
    the controls.

    Each column is corrected as its method is designed to be driven
    (:meth:`~tactile_core.rendering.methods.Method.own_correction`): the paper's four and GS
    with the correction set, EN, PK and RO with none, VRCH with the threshold only; its curve's
    title says which.

    The heatmaps draw the device's layout. On a layout that is not a grid only the methods that
    render there can be compared: a set with others loses them (BA, RO, GS and EN when fewer
    than two are left), with a note under the set, and gets them back on a grid.

    With motor-aware drive on (the scene's ``compensate_motors``), each column's curves are the
    drive sent for the device's motors (``motors()``, its profile's), solid, beside the plain
    corrected drive, dashed."""

    def __init__(self, state: TunerState, parent=None, methods=PAPER_METHODS, motors=None):
        super().__init__(parent)
        self.state = state
        self._motors = motors or (lambda: None)
        outer = QtWidgets.QVBoxLayout(self)
        outer.setContentsMargins(0, 0, 0, 0)
        self.chooser = MethodSetWidget(methods, 2, 6)
        self.chooser.methods_changed.connect(self.set_methods)
        outer.addWidget(self.chooser)
        self._holder = None
        self.methods: list[str] = []
        self._heatmaps: dict = {}
        self._curves: dict = {}
        self._built_for = None
        self._shown_scene = None
        self._frames: dict = {}  # per method, its frames as the stream renders them
        self._frames_scene, self._variants = None, {}
        self._grid_methods = None  # the set chosen on a grid, while a layout restricts it
        self.chooser.check = lambda spec: placement.refusal(spec, state.layout)
        self.set_methods(list(methods))
        state.layout_changed.connect(self._on_state_layout_changed)
        self._on_state_layout_changed(state.layout)

    @property
    def chosen_methods(self) -> list[str]:
        """The set to remember between sessions: the one chosen on a grid while a layout
        restricts it."""
        return list(self._grid_methods or self.methods)

    def _on_state_layout_changed(self, layout) -> None:
        self._built_for = None  # the views are built anew for the layout (when next shown)
        self._shown_scene = None
        wanted = self._grid_methods or self.methods
        methods, dropped = placement.restricted(wanted, layout)
        self._grid_methods = list(wanted) if dropped else None
        if methods != self.methods:
            self.set_methods(methods)
        elif self.isVisible():
            self._build()
        self.chooser.refuse(placement.restriction_note(dropped, methods, layout, "comparing"),
                            warn=False)  # fmt: skip

    # The views are built the first time they are needed (the tab shown, or asked for): a tuner
    # that never opens Compare never pays for its eight plots (half its start-up time).
    @property
    def heatmaps(self) -> dict:
        """The heatmap view of each method shown, by spec."""
        self._build()
        return self._heatmaps

    @property
    def curves(self) -> dict:
        """The activation-curve view of each method shown, by spec."""
        self._build()
        return self._curves

    def showEvent(self, event) -> None:  # Qt override
        self._build()
        super().showEvent(event)

    def set_methods(self, methods) -> None:
        """Show ``methods`` (2-6 specs) side by side."""
        methods = [get_method(m).spec for m in methods]
        if not 2 <= len(methods) <= 6 or len(set(methods)) != len(methods):
            raise ValueError(f"compare needs 2 to 6 distinct methods, got {methods}")
        self.methods = methods
        self.chooser.methods = list(methods)
        self.chooser.show_methods()
        self._shown_scene = None
        if self.isVisible():
            self._build()

    def _build(self) -> None:
        """Build the views of :attr:`methods` unless they are built already."""
        methods = self.methods
        if self._built_for == methods:
            return
        self._built_for = list(methods)
        # A fresh holder replaces the old one, views and all; the old is hidden at once (its
        # deletion waits for the event loop).
        holder = QtWidgets.QWidget()
        if self._holder is not None:
            self.layout().replaceWidget(self._holder, holder)
            self._holder.hide()
            self._holder.deleteLater()
        else:
            self.layout().addWidget(holder, 1)
        self._holder = holder
        grid = QtWidgets.QGridLayout(holder)
        self._heatmaps, self._curves = {}, {}
        for i, spec in enumerate(methods):
            method = get_method(spec)
            # Short titles: a plot item never shrinks below its title's width.
            heat = HeatmapView(title=spec, colorbar=False, layout=self.state.layout)
            heat.setToolTip(f"{spec}: {method.title}")
            heat.plot.setLabel("bottom", "")
            heat.plot.setLabel("left", "")
            heat.setMinimumSize(100, 160)
            curve = CurvesView()
            # the longest that fits (with 5 or 6 methods the title had been left out)
            said = f"{method.name}, {method.correction_label}"
            curve.set_titles(said, (said, "9pt"),
                             (f"{method.name}<br>{method.correction_label}", "9pt"),
                             (method.name, "9pt"))  # fmt: skip
            curve.setToolTip(f"{spec} is driven with {method.correction_label}")
            curve.setMinimumSize(100, 120)
            curve.setLabel("left", "")
            grid.addWidget(heat, 0, i)
            grid.addWidget(curve, 1, i)
            grid.setColumnStretch(i, 1)
            self._heatmaps[spec] = heat
            self._curves[spec] = curve
        first = self._curves[methods[0]]
        for spec in methods[1:]:
            self._curves[spec].setXLink(first)
        # A strip (a belt: wider than tall) needs less height than a grid; the curves get it.
        w, h = self._heatmaps[methods[0]].extent()
        strip = not self.state.layout.is_grid and h < 0.6 * w
        grid.setRowStretch(0, 1 if strip else 3)
        grid.setRowStretch(1, 2)
        self._shown_scene = None

    def _refresh(self) -> None:
        """Recompute the four methods' curves if the scene changed since last time."""
        scene = self.state.scene
        if scene is self._shown_scene:
            return
        self._shown_scene = scene
        if scene.shape is None:  # a pattern, free points: Compare renders shapes' traces only
            caption = f"{source_kind(scene.source)} plays: Compare needs a shape"
            for name in self.methods:
                self.curves[name].clear_curves()
                self.heatmaps[name].set_cell_frames({})
                self.heatmaps[name].set_outline(None)
                self.heatmaps[name].set_caption(caption)
            return
        for name in self.methods:
            self.heatmaps[name].set_caption("")
        outline = scene.shape.outline()
        motors = self._motors() if scene.compensate_motors else None
        for name in self.methods:
            mu, gamma = get_method(name).own_correction(scene.mu, scene.gamma)
            curves = activation_curves(
                scene.shape,
                name,
                duration_s=scene.duration_s,
                direction=scene.direction,
                mu=mu,
                gamma=gamma,
                samples=600,
                grid=self.state.layout,
                compensate=motors,
            )
            if motors is not None:  # motor-aware drive solid, the plain drive dashed
                curves = dataclasses.replace(curves, raw=curves.corrected, corrected=curves.drive)
            colors = cell_colors(curves.cells)
            self.curves[name].set_curves(
                curves, colors, scene.duration_s + scene.pause_s, raw=motors is not None
            )
            self.heatmaps[name].set_cell_frames(colors)
            self.heatmaps[name].set_outline(outline)

    def tick(self, scene, start_s, rate_hz, phase_s) -> None:
        """Show every method's corrected frame, the one that starts ``start_s`` seconds into
        the trace clock (None while off), as the stream renders it at ``rate_hz``.

        Called by the display timer only while the view is visible; its curves are brought up
        to date here, at most every 100 ms, so a hidden compare view costs nothing."""
        now = time.perf_counter()
        if scene is not self._shown_scene and now - getattr(self, "_last_refresh", 0.0) > 0.1:
            self._last_refresh = now
            self._refresh()
        on = start_s is not None and scene.shape is not None
        t = scene.trace().parameter1(start_s) if on else None
        point = None if t is None else scene.shape.point(t)
        for name in self.methods:
            heat = self.heatmaps[name]
            frame = np.zeros(heat.values.shape)
            if on:
                for i, v in self._frames_of(name, scene, rate_hz, start_s):
                    frame.flat[i] = v
            heat.set_frame(frame)
            heat.set_point(point)
            self.curves[name].set_cursor(phase_s)

    def _frames_of(self, name, scene, rate_hz, start_s) -> tuple:
        """Method ``name``'s lit tactors of that frame: the scene with ``name`` and its own
        correction, rendered as the stream renders a scene."""
        frames = self._frames.get(name)
        if frames is None:
            frames = self._frames[name] = SceneFrames()
        if self._frames_scene is not scene:  # one variant of the scene per method, made once
            self._frames_scene, self._variants = scene, {}
        variant = self._variants.get(name)
        if variant is None:
            mu, gamma = get_method(name).own_correction(scene.mu, scene.gamma)
            variant = self._variants[name] = scene.replace(method=name, mu=mu, gamma=gamma)
        return frames.at(variant, self.state.layout, rate_hz, start_s)
