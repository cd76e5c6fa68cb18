"""The Tune tab: the heatmap beside the activation curves and the correction curve."""

from __future__ import annotations

import dataclasses

from PySide6 import QtCore, QtWidgets

from tactile_core.rendering.curves import activation_curves
from tactile_core.rendering.percept import REFERENCE, predict, predict_range

from ..texts import value3
from ..views import CorrectionView, CurvesView, HeatmapView, cell_colors
from ..widgets import WrappedLabel
from .display import FrameDisplay
from .gestures import HeatmapGestures

MAX_PLOTTED_EFFECTS = 2000
"""A ``.tact`` pattern with more paths and dots than this is played but neither plotted nor
outlined: its curves are rendered effect by effect, ~0.1 ms each, and drawing 4,000 paths'
outlines took the display's thread 4.5 s."""
MAX_OUTLINE_POINTS = 20_000
"""Most points of a pattern's outlines drawn (beyond, none: a partial drawing would mislead)."""


MAX_CURVE_INTERVALS = 6000
"""Most sample periods the activation curves span (20 s at 300 frames/s); a longer trace is
sampled at its duration / 6000."""


def curve_samples(duration_s: float, rate_hz: float) -> int:
    """How many samples the activation curves take over a trace of ``duration_s`` at the
    scene's ``rate_hz``: one per frame period, from 0 to the duration, both included (N + 1
    for N = duration x rate periods, 1 to :data:`MAX_CURVE_INTERVALS`), so that an exported
    curve's time column steps 1 / rate (exactly, when the duration is whole periods)."""
    return min(max(round(duration_s * rate_hz), 1), MAX_CURVE_INTERVALS) + 1


def plotted_effects(pattern) -> int:
    """How many paths and dots a pattern's curves and outlines draw: an imported ``.tact``
    pattern counts them (``effects``); a pattern file holds its effects, each counted by its
    path points and dots."""
    effects = pattern.effects
    return effects if isinstance(effects, int) else sum(e.points() for e in effects)


def pattern_outlines(pattern, target) -> list | None:
    """The outline of each of a ``.tact`` pattern's paths on ``target``, for the heatmap; None
    when there are more than :data:`MAX_PLOTTED_EFFECTS` effects or
    :data:`MAX_OUTLINE_POINTS` points."""
    if plotted_effects(pattern) > MAX_PLOTTED_EFFECTS:
        return None
    outlines = [path.outline() for path in pattern.paths(target)]
    return outlines if sum(map(len, outlines)) <= MAX_OUTLINE_POINTS else None


class TuneWidget(QtWidgets.QStackedWidget):
    """The tune tab's views, or in their place a notice while they would give something away.

    Page 0 holds the heatmap (the frames sent, :class:`FrameDisplay`) and, beside it, the
    activation curves over one trace and the correction curve, redrawn when the scene changes
    (at most every 50 ms while a slider is dragged); page 1 a notice (:meth:`hide_views`).

    Parameters
    ----------
    state : TunerState
    device : DeviceController
        The profile (grid, levels, motor response) and the stream's latest frame.

    Attributes
    ----------
    gestures : HeatmapGestures
        Pulses, draw mode and scrubbing.
    display : FrameDisplay
        The display timer.
    shown_curves : ActivationCurves or None
        The activation curves on show (None in the predicted view).
    """

    error_raised = QtCore.Signal(str)

    def __init__(self, state, device, parent=None):
        super().__init__(parent)
        self.state = state
        self.device = device
        self.method_hidden = False
        self.shown_curves = None
        self.heatmap = HeatmapView(layout=state.layout, title="Array")
        self.heatmap.setObjectName("heatmap")
        self._caption()
        self.curves = CurvesView()
        self.lanes_check = QtWidgets.QCheckBox("one lane per tactor")
        self.lanes_check.setObjectName("lanes")
        self.lanes_check.setToolTip(
            "Activation curves in lanes, one row per tactor labelled (col,row): the sequence of a "
            "bi-level method, whose curves all sit at 1, can be read (the paper's Figure 3)"
        )
        self.lanes_check.toggled.connect(self.curves.set_lanes)
        self.correction = CorrectionView()
        self.split = QtWidgets.QSplitter(QtCore.Qt.Orientation.Horizontal)
        self.split.addWidget(self.heatmap)
        self.split.addWidget(self._curves_column())
        self.split.setStretchFactor(0, 0)
        self.split.setStretchFactor(1, 1)
        self.hidden_label = QtWidgets.QLabel()
        self.hidden_label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.hidden_label.setWordWrap(True)
        self.addWidget(self.split)
        self.addWidget(self.hidden_label)

        self.gestures = HeatmapGestures(state, self.heatmap, self.curves, device, self)
        self.display = FrameDisplay(self, self)
        self.display.error_raised.connect(self.error_raised)
        # Scene changes arrive up to ~100 times a second while a slider is dragged: the array
        # gets each one at once (DeviceController), the views are rebuilt at most every 50 ms.
        self._views_timer = QtCore.QTimer(self)
        self._views_timer.setSingleShot(True)
        self._views_timer.setInterval(50)
        self._views_timer.timeout.connect(self.refresh)
        state.scene_changed.connect(self._on_state_scene_changed)
        state.view_mode_changed.connect(self._on_state_view_mode_changed)
        state.show_levels_changed.connect(self.heatmap.set_show_values)
        state.layout_changed.connect(self._on_state_layout_changed)
        self.heatmap.cell_hovered.connect(self.curves.highlight)
        self.curves.curve_hovered.connect(self.heatmap.highlight)

    def _curves_column(self) -> QtWidgets.QWidget:
        """The curves with their bar (lanes, a hint) above the correction curve."""
        curves_box = QtWidgets.QWidget()
        box = QtWidgets.QVBoxLayout(curves_box)
        box.setContentsMargins(0, 0, 0, 0)
        bar = QtWidgets.QHBoxLayout()
        # wrapped, never cut off (at 1280 and 1400 px it was: "...; hove...")
        hint = WrappedLabel("drag the cursor to scrub; hover for values; dashed: raw")
        hint.setObjectName("curves_hint")
        hint.setToolTip(
            "Solid curves are corrected, dashed ones raw. Pause, then drag the dashed cursor to "
            "show any instant of the trace on the heatmap; hover a curve or a heatmap cell to "
            "read its tactor and value"
        )
        hint.setAlignment(QtCore.Qt.AlignmentFlag.AlignRight | QtCore.Qt.AlignmentFlag.AlignVCenter)
        bar.addWidget(self.lanes_check)
        bar.addWidget(hint, 1)
        box.addLayout(bar)
        box.addWidget(self.curves, 1)
        right = self.plots = QtWidgets.QSplitter(QtCore.Qt.Orientation.Vertical)
        right.addWidget(curves_box)
        right.addWidget(self.correction)
        right.setSizes([600, 360])
        return right

    # --- what is shown ---------------------------------------------------------------------------

    def hide_views(self, text: str) -> None:
        """Show ``text`` in place of the views."""
        self.hidden_label.setText(text)
        self.setCurrentIndex(1)

    def show_views(self) -> None:
        """Show the views again."""
        self.setCurrentIndex(0)

    def set_method_hidden(self, hidden: bool) -> None:
        """Blind A/B: no live frames and no curve titles, which would give the method away;
        shown again (a reveal), the plots and their titles are redrawn for the scene now, not
        left naming the method from before the session."""
        was_hidden, self.method_hidden = self.method_hidden, bool(hidden)
        if was_hidden and not self.method_hidden:
            self.refresh()

    @property
    def stacked(self) -> bool:
        """Whether the heatmap spans the tab above the plots (a wide layout: a belt, a sleeve)
        rather than standing beside them."""
        return self.split.orientation() == QtCore.Qt.Orientation.Vertical

    def fit_heatmap(self) -> None:
        """Give the heatmap the room at which its array fills it: beside the plots, the width
        at which its square cells fill its height; a layout drawn larger across the tab (a
        belt: beside the plots it used a third of the panel's height) spans it above them, at
        most half its height, the curves and the correction curve side by side below."""
        width, height = self.split.width(), self.split.height()
        if width <= 0 or height <= 0:
            return
        right = self.plots.minimumSizeHint().width()
        beside = min(max(self.heatmap.preferred_width(height), 220), round(width * 0.55),
                     width - right)  # fmt: skip
        above = min(max(self.heatmap.preferred_height(width), 160), round(height * 0.5))
        heatmap = self.heatmap
        stack = heatmap.scale_in(width, above) > 1.1 * heatmap.scale_in(beside, height)
        if stack != self.stacked:
            vertical, horizontal = QtCore.Qt.Orientation.Vertical, QtCore.Qt.Orientation.Horizontal
            self.split.setOrientation(vertical if stack else horizontal)
            self.plots.setOrientation(horizontal if stack else vertical)
            self.plots.setSizes([600, 360])
        if stack:
            self.split.setSizes([above, height - above])
        else:
            self.split.setSizes([beside, width - beside])

    # --- the scene's plots -----------------------------------------------------------------------

    def _on_state_scene_changed(self, _scene) -> None:
        if not self._views_timer.isActive():
            self._views_timer.start()

    def _on_state_view_mode_changed(self, _mode) -> None:
        # The predicted view has its own curves and path: switching the mode redraws them.
        if not self._views_timer.isActive():
            self._views_timer.start()

    def _on_state_layout_changed(self, layout) -> None:
        """Another device layout: draw mode and a pulse end (their scenes were for the old
        one), the heatmap draws the new layout, the plots are redrawn."""
        self.gestures.set_draw_mode(False)
        self.gestures.end_pulse()
        self.heatmap.set_layout(layout)
        self._caption()
        self.curves.clear_curves()
        self.heatmap.set_path(None)
        if not self._views_timer.isActive():
            self._views_timer.start()
        QtCore.QTimer.singleShot(0, self.fit_heatmap)

    def _caption(self) -> None:
        """Under a layout, its profile's description (which way it runs, where it wraps)."""
        profile = self.device.profile
        grid = self.state.layout.is_grid
        self.heatmap.set_caption("" if grid else f"{profile.name}: {profile.description}")

    def refresh(self) -> None:
        """Redraw the correction curve, the activation curves and the heatmap's frames and
        outline for the state's scene now."""
        scene = self.state.scene
        profile = self.device.profile
        self.correction.set_params(scene.mu, scene.gamma, profile.levels, profile.response,
                                   profile.drive_for if scene.felt_domain else None)  # fmt: skip
        heatmap = self.heatmap
        pattern = scene.source if scene.shape is None else None
        if heatmap.drawing:  # a free point has no trace worth plotting: no curves, no frames
            self._no_trace("a drawn point has no trace")
            return
        if scene.shape is None and not hasattr(pattern, "curves"):
            self._no_trace("free points have no trace")  # (driven by another program)
            return
        if self.state.view_mode == "predicted":
            if pattern is not None:
                self._no_trace("the predicted view needs a shape, not a pattern")
                heatmap.set_outline(pattern_outlines(pattern, self.state.layout))
                return
            self._show_predicted(scene)
            return
        heatmap.set_path(None)
        felt_view = self.state.view_mode == "felt" and profile.motor is not None
        motor = profile.motor if felt_view else None
        aware = motor if scene.compensate_motors else None  # felt of the motor-aware drive
        period = scene.duration_s + scene.pause_s
        try:
            if pattern is not None:
                if plotted_effects(pattern) > MAX_PLOTTED_EFFECTS:
                    self._no_trace(f"{plotted_effects(pattern)} paths and dots: too many to plot")
                    return
                outline = pattern_outlines(pattern, self.state.layout)
                # one sample a frame (the middle of each), as the stream takes them
                # what plays on this array: a .tact file's positions on its groups
                period = pattern.duration_on(self.state.layout)
                frames = max(curve_samples(period, scene.rate_hz) - 1, 3)
                curves = pattern.curves(scene.method, self.state.layout, mu=scene.mu,
                                        gamma=scene.gamma, samples=frames,
                                        motor=motor,
                                        compensate=aware)  # fmt: skip
            else:
                outline = scene.shape.outline()
                curves = activation_curves(
                    scene.shape,
                    scene.method,
                    duration_s=scene.duration_s,
                    direction=scene.direction,
                    mu=scene.mu,
                    gamma=scene.gamma,
                    samples=curve_samples(scene.duration_s, scene.rate_hz),
                    grid=self.state.layout,
                    motor=motor,
                    compensate=aware,
                )
        except ValueError as exc:  # a plug-in that cannot render here (the state checks ours)
            self.error_raised.emit(f"no activation curves: {exc}")
            return
        if felt_view:
            # What the motors make of the corrected drive: their lag, then their response.
            curves = dataclasses.replace(curves, corrected=profile.felt(curves.felt))
        self.shown_curves = curves
        colors = cell_colors(curves.cells)
        self.curves.set_curves(curves, colors, period)
        heatmap.set_cell_frames(colors)
        heatmap.set_outline(outline)
        if not self.method_hidden:
            what = (f"felt (motor lag and response, {profile.motor.source})" if felt_view
                    else "activation")  # fmt: skip
            what = f"{what}, motor-aware drive" if aware is not None else what
            short = "felt" if felt_view else "activation"
            short = f"{short}, motor-aware" if aware is not None else short
            values = f"mu {value3(scene.mu)}, gamma {value3(scene.gamma)}"
            # One line where it fits; else two (at 1400 px the felt view's lost its gamma)
            self.curves.set_titles(f"{scene.method} {what}, {values}",
                                   f"{scene.method} {what}<br>{values}",
                                   (f"{scene.method} {what}<br>{values}", "9pt"),
                                   (f"{scene.method} {short}<br>{values}", "9pt"))  # fmt: skip

    def _no_trace(self, why: str) -> None:
        """No curves, no tactor frames, no outline; ``why`` in the curves' title."""
        self.shown_curves = None
        self.curves.clear_curves()
        self.heatmap.set_cell_frames({})
        self.heatmap.set_outline(None)
        self.heatmap.set_path(None)
        if why and not self.method_hidden:
            self.curves.set_titles(f"{self.state.scene.method}: {why}",
                                   (f"{self.state.scene.method}: {why}", "9pt"))  # fmt: skip

    def _show_predicted(self, scene) -> None:
        """The predicted view, from what is sent (the scene's rate, the device's levels, its
        motors): for the reference participant, the felt centroid's path on the heatmap and the
        felt intensity over time in the curves view; in the title the ripple and centroid
        error, and the ripple's range over the grid of participants."""
        profile = self.device.profile
        sent = dict(grid=profile.layout, rate_hz=min(scene.rate_hz, 1000.0), levels=profile.levels,
                    motor=profile.motor, duration_s=scene.duration_s,
                    compensate=profile.motor if scene.compensate_motors else None)  # fmt: skip
        try:
            percept = predict(scene.shape, scene.method, scene.mu, scene.gamma, **sent)
            band = predict_range(scene.shape, scene.method, scene.mu, scene.gamma,
                                 own_correction=False, samples=400, **sent)  # fmt: skip
        except ValueError as exc:
            self.error_raised.emit(f"no prediction: {exc}")
            return
        times = percept.t * scene.duration_s
        if scene.direction == "reverse":
            times = times[::-1]
        self.shown_curves = None
        self.heatmap.set_cell_frames({})
        self.heatmap.set_outline(scene.shape.outline())
        self.heatmap.set_path(percept.centroid)
        self.curves.set_series(times, percept.felt, scene.duration_s + scene.pause_s,
                               "felt intensity M")  # fmt: skip
        if not self.method_hidden:
            stage = "felt" if profile.motor is not None else "sent"
            motors = f"; motors {profile.motor.source}" if profile.motor is not None else ""
            title = (  # two lines: on one it was cut off at both ends at 1600 x 1000
                f"{scene.method}, {REFERENCE.label}: ripple {percept.ripple:.2f}, off "
                f"{percept.mean_error_mm:.1f} mm (max {percept.max_error_mm:.1f})<br>ripple "
                f"{band.span(stage)} over {len(band.participants)} participants{motors}"
            )
            self.curves.set_titles((title, "9pt"))
