"""What the hands do on the tune tab's plots: pulse a tactor, draw a free point, scrub."""

from __future__ import annotations

from PySide6 import QtCore

import tactile_core as tc
from tactile_core.files.pattern import Pattern, PatternCue
from tactile_core.rendering import placement
from tactile_core.rendering.methods import get_method

from ..texts import DRAW_HELP


class HeatmapGestures(QtCore.QObject):
    """Clicks and drags on the heatmap and the curves, turned into scenes.

    - A click on a cell (a disc on a layout) pulses its tactor alone (0.3 s), Shift+click holds
      it. The pulse goes to the array beside the state (:meth:`DeviceController.play_apart`):
      the controls, the titles and the curves keep showing the tuning, and a change to the
      tuning meanwhile (a key, a slider) releases the tactor and plays at once; otherwise the
      tuning plays again, from its beginning, when the pulse ends.
    - Draw mode: dragging on the heatmap moves a free point (the methods that need no shape);
      leaving it puts back the whole scene it changed. Round a wrap the point is taken into
      one turn, so a path drawn across the seam goes on at the other end.
    - Dragging the curves' cursor holds the trace at that time (:attr:`scrub_s`): the views
      and the array show that instant until it plays again (Space); a pattern is held there
      (a held :class:`~tactile_core.files.pattern.PatternCue`) and plays on from there.

    Parameters
    ----------
    state : TunerState
    heatmap : HeatmapView
    curves : CurvesView
    device : DeviceController
        Plays the pulses (the array), beside the state.
    """

    draw_mode_changed = QtCore.Signal(bool)
    message_posted = QtCore.Signal(str, int)
    """A status line and how long to show it (ms)."""

    def __init__(self, state, heatmap, curves, device, parent=None):
        super().__init__(parent)
        self.state = state
        self.heatmap = heatmap
        self.curves = curves
        self.device = device
        self.can_pulse = lambda: True
        """Whether a click may pulse now (the window says no during a run or blind A/B)."""
        self._pulse = None  # (what is pulsed, held) while a tactor is pulsed from the heatmap
        self._draw_backup = None
        self._draw_method = None
        self._pulse_timer = QtCore.QTimer(self)
        self._pulse_timer.setSingleShot(True)
        self._pulse_timer.timeout.connect(self.end_pulse)
        device.connection_changed.connect(lambda _: self.end_pulse())  # a new stream: the tuning
        heatmap.point_drawn.connect(self._on_heatmap_point_drawn)
        heatmap.draw_released.connect(self._on_heatmap_draw_released)
        heatmap.cell_clicked.connect(self.pulse_cell)
        heatmap.actuator_clicked.connect(self.pulse_actuator)
        curves.scrubbed.connect(self._on_curves_scrubbed)

    @property
    def scrub_s(self) -> float | None:
        """Trace time the cursor was dragged to and the array holds, or None."""
        return self.state.scene.hold_s

    @property
    def pulsing(self) -> bool:
        """True while a tactor is pulsed or held."""
        return self._pulse is not None

    # --- pulses ------------------------------------------------------------------------------

    def pulse_cell(self, col: int, row: int, hold: bool = False) -> None:
        """Play one tactor alone at full drive: a 0.3 s pulse, or held (Shift+click) until the
        next click, Space, Esc or a change to the tuning. The state's scene stays as it is: the
        tuning plays again afterwards."""
        self._pulse_at((col + 0.5, row + 0.5), "CT", f"tactor ({col},{row})", hold)

    def pulse_actuator(self, index: int, hold: bool = False) -> None:
        """:meth:`pulse_cell` for an actuator of a layout (PK at its position: it alone, at
        full drive)."""
        layout = self.state.layout
        self._pulse_at(layout.positions[index], "PK", f"actuator {layout.names[index]}", hold)

    def _pulse_at(self, centre, method: str, name: str, hold: bool) -> None:
        if not self.can_pulse() or self.heatmap.drawing:
            return
        held = self._pulse is not None and self._pulse[1]
        self.end_pulse()
        if held:
            return  # a click releases a held tactor
        tuning = self.state.scene
        pulse = tuning.replace(
            shape=tc.Line(centre, centre), source=None, method=method, mu=0.0, gamma=1.0,
            gain=1.0, duration_s=0.3, pause_s=0.0, repeat=hold, playing=True, hold_s=None,
            epoch=tuning.epoch + 1, marker="",
        )  # fmt: skip
        self._pulse = (name, hold)
        what = "holding" if hold else "pulsing"
        self.device.play_apart(pulse, self._on_tuning_changed, f"{what} {name} ({method})")
        self.message_posted.emit(
            f"{what} {name}"
            + (": click again, press Space or Esc, or change the tuning to release" if hold
               else ""),
            4000,
        )  # fmt: skip
        if not hold:
            self._pulse_timer.start(400)

    def _on_tuning_changed(self, _scene) -> None:
        """The tuning changed while a tactor was pulsed (a key, a slider, a preset): the
        tactor is let go and the tuning, with the change, plays at once."""
        name, held = self._pulse
        self.end_pulse()
        if held:
            self.message_posted.emit(f"released {name}: the tuning changed and plays", 4000)

    def end_pulse(self, restore: bool = True) -> None:
        """Stop a pulse or a held tactor; ``restore``: the tuning (the state's scene) goes to
        the array again at once (False: the caller sends something else, such as all off)."""
        if self._pulse is None:
            return
        self._pulse = None
        self._pulse_timer.stop()
        if self.device.divert == self._on_tuning_changed:  # (not the OSC server's, started since)
            self.device.divert = None
            if restore:
                self.device.resume()

    # --- scrubbing -----------------------------------------------------------------------------

    def _on_curves_scrubbed(self, time_s: float) -> None:
        """The cursor dragged: the array holds the trace at that time, as the views do."""
        if self.heatmap.drawing or self.pulsing:
            return
        scene = self.state.scene
        pattern = scene.source if scene.shape is None else None
        pattern = pattern.pattern if isinstance(pattern, PatternCue) else pattern
        if isinstance(pattern, Pattern):  # held at that moment of it (a cue)
            at_s = min(max(0.0, float(time_s)), pattern.duration_s)
            self.state.update(playing=True, source=PatternCue(pattern, at_s, hold=True))
            return
        period = scene.duration_s + scene.pause_s
        self.state.update(playing=True, hold_s=min(max(0.0, float(time_s)), period))

    # --- draw mode -----------------------------------------------------------------------------

    def set_draw_mode(self, on: bool) -> None:
        """Drag on the heatmap to move a free point (CT and AS only). Leaving draw mode puts back
        the whole scene it changed (shape, method, pause, playing)."""
        on = bool(on)
        if on == self.heatmap.drawing:
            return
        if on:
            self.end_pulse()
            self._draw_backup = self.state.scene
            changes = {"pause_s": 0.0, "playing": False}
            if get_method(self.state.scene.method).needs_shape:
                free = placement.default_method(self.state.layout, free_points=True)
                changes["method"] = free
                self.message_posted.emit(f"draw mode uses {free}: {DRAW_HELP}", 10_000)
            centre = self.heatmap.centre()
            self.heatmap.set_drawing(True)
            self.state.update(shape=tc.Line(centre, centre), **changes)
            self._draw_method = self.state.scene.method
            self.curves.clear_curves()  # a free point has no trace to plot
        else:
            self.heatmap.set_drawing(False)
            backup, self._draw_backup = self._draw_backup, None
            if backup is not None:
                restored = backup.replace(epoch=self.state.scene.epoch + 1)
                if self.state.scene.method != self._draw_method:  # picked while drawing: kept
                    restored = restored.replace(method=self.state.scene.method)
                self.state.set_scene(restored)
        self.draw_mode_changed.emit(on)

    def _on_heatmap_point_drawn(self, x: float, y: float) -> None:
        x, y = self.heatmap.clamp(x, y)
        self.state.update(shape=tc.Line((x, y), (x, y)), playing=True)

    def _on_heatmap_draw_released(self) -> None:
        self.state.update(playing=False)
