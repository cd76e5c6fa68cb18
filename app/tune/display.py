"""The tune tab's live frames: what the array gets now, on the heatmap, at about 60 Hz."""

from __future__ import annotations

import math
import time

import numpy as np
from PySide6 import QtCore

from tactile_core.rendering.methods import mark_unavailable
from tactile_core.rendering.percept import REFERENCE, felt_magnitude
from tactile_core.rendering.placement import default_method

from ..frames import SceneFrames, stream_rate

DISPLAY_HZ = 60


class FrameDisplay(QtCore.QObject):
    """A display timer on the GUI thread that reads the stream's latest frame time and shows
    that instant on the heatmap (in the state's view mode) and as the curves' cursor.

    The output thread (or process) never touches a widget; this timer's rate is independent of
    the stream's frame rate. While another program drives the array (the OSC server) or a
    tactor is pulsed from the heatmap, the array plays no trace of the state's: every view but
    *felt* shows the levels sent, with the first driven point (the shape's outline stays: the
    curves beside are of the tuning, its shape, method and correction).

    Parameters
    ----------
    tune : TuneWidget
        Its state, device, heatmap, curves and gestures; while its method is hidden (blind A/B)
        nothing is shown.
    """

    frame_shown = QtCore.Signal(object, object, object, object)
    """``(scene, start_s, rate_hz, phase_s)`` after each frame shown: where on the trace clock
    the frame shown starts and the rate it is rendered at (``start_s`` None while off), and the
    time into the period (None while off), for other views of the same frame."""
    error_raised = QtCore.Signal(str)

    def __init__(self, tune, parent=None):
        super().__init__(parent)
        self.tune = tune
        self.state = tune.state
        self.device = tune.device
        self.tick_times: list[float] = []
        """``time.perf_counter()`` of the recent ticks (for :meth:`display_rate`)."""
        self._trace_cache = (None, None)
        self._last = None  # (start, phase) of the last frame played: paused, the views stay there
        self._buffer = np.zeros(0)
        self._frames = {raw: SceneFrames(raw) for raw in (False, True)}
        self.timer = QtCore.QTimer(self)
        self.timer.setTimerType(QtCore.Qt.TimerType.PreciseTimer)
        self.timer.timeout.connect(self._on_timer_timeout)

    def start(self) -> None:
        """Show frames from now on."""
        self.timer.start(round(1000 / DISPLAY_HZ))

    def stop(self) -> None:
        """Show no more frames (the window closes)."""
        self.timer.stop()

    def _trace(self, scene):
        cached_scene, trace = self._trace_cache
        if cached_scene is not scene:
            trace = scene.trace() if scene.shape is not None else None
            self._trace_cache = (scene, trace)
        return trace

    def _on_timer_timeout(self) -> None:
        now = time.perf_counter()
        self.tick_times.append(now)
        if len(self.tick_times) > 4096:
            del self.tick_times[:2048]
        tune, scene = self.tune, self.state.scene
        heatmap = tune.heatmap
        if self._show_driven():
            return
        frame_scene, trace_time = self.device.streamer.last_frame
        trace = self._trace(scene)
        start = phase = None  # the frame shown: where it starts on the trace clock
        pattern = scene.source if trace is None and hasattr(scene.source, "curves") else None
        if pattern is not None:  # a pattern, played or held (an editor's cue)
            taken = frame_scene is not None and frame_scene.source is pattern and (
                frame_scene.epoch == scene.epoch)  # fmt: skip
            start, phase = self._pattern_instant(scene, pattern, trace_time if taken else None)
        elif trace is not None and scene.hold_s is not None:
            start = phase = min(scene.hold_s, trace.period_s)  # scrubbed: the array holds it
        elif trace is not None and trace_time is not None and scene.playing:
            start = trace_time
            phase = math.fmod(trace_time, trace.period_s) if trace.repeat else trace_time
            self._last = (start, phase)
        elif trace is not None and not scene.playing and self._last is not None:
            start, phase = self._last  # paused (Space, Esc): where it was, the array off
        if heatmap.drawing:
            phase = None  # a free point: no trace, so no time cursor
        rate_hz = stream_rate(scene, self.device.stats)
        values, labels = self._values(scene, start, rate_hz)
        if values is None:
            return
        if not tune.method_hidden:
            heatmap.set_frame(values, labels)
            traced = start is not None and trace is not None and not heatmap.drawing
            t = trace.parameter1(start) if traced else None  # (a pattern has no point)
            point = None if t is None else scene.shape.point(t)
            if heatmap.drawing and scene.playing and scene.shape is not None:
                point = scene.shape.point(0.0)
            heatmap.set_point(point)
            tune.curves.set_cursor(phase)
            self.frame_shown.emit(scene, start, rate_hz, phase)

    def _pattern_instant(self, scene, pattern, trace_time) -> tuple:
        """A pattern's frame to show: ``(start, phase)``, where it starts on the stream's clock
        (seconds since the stream began to play it) and the pattern's time then (the curves'
        cursor: a cue's own, from its moment on). A held cue: its moment. Paused: where it was;
        ``(None, None)`` until the stream plays it (``trace_time`` None)."""
        if getattr(pattern, "hold", False):  # whatever the stream's clock: that one frame
            self._last = (0.0, pattern.pattern_time_s(0.0))
        elif scene.playing and trace_time is not None:
            when = getattr(pattern, "pattern_time_s", None)
            end = pattern.duration_on(self.state.layout)  # (a .tact file's positions here)
            phase = when(trace_time) if when is not None else min(trace_time, end)
            self._last = (trace_time, phase)
        elif scene.playing or self._last is None:
            return None, None
        return self._last

    def _show_driven(self) -> bool:
        """Another program's points or a pulsed tactor, as the stream sends them (True); False
        while the array plays the state's scene."""
        driven = self.device.divert is not None
        tune = self.tune
        if not driven or tune.method_hidden:
            return driven
        values = self.device.sent()
        if values.shape != self.state.layout.frame_shape:
            return True  # the stream of another layout, not yet replaced
        felt = self.device.felt() if self.state.view_mode == "felt" else None
        values = values if felt is None else felt
        labels = None
        if self.state.show_levels:
            in_levels = felt is None and self.state.view_mode == "sent"
            labels = self.device.sent_levels() if in_levels else np.char.mod("%.2f", values)
        tune.heatmap.set_frame(values, labels)
        points = self.device.driven_points
        tune.heatmap.set_point(points[0][1:3] if points else None)
        tune.curves.set_cursor(None)
        self.frame_shown.emit(self.state.scene, None, None, None)
        return True

    def _values(self, scene, start_s, rate_hz):
        """The heatmap's values (``(rows, cols)`` on a grid, ``(size,)`` on a layout) and
        per-tactor labels (or None) in the view mode; None for the values when a plug-in
        failed.

        *raw*, *corrected* and *predicted* are the frame that starts ``start_s`` seconds into
        the trace clock as the stream renders it at ``rate_hz`` (its temporal filter too):
        before the correction, as corrected, and that through
        :func:`~tactile_core.rendering.percept.felt_magnitude` for the reference participant.
        *sent* and *felt* are the levels the stream sent last."""
        mode = self.state.view_mode
        shape = self.state.layout.frame_shape
        show_levels = self.state.show_levels
        labels = None
        if mode in ("raw", "corrected", "predicted"):
            # One buffer, reused: only the (at most a few) lit tactors are computed and written.
            if self._buffer.shape != shape:
                self._buffer = np.zeros(shape)
            values = self._buffer
            flat = values.reshape(-1)
            flat.fill(0.0)
            if start_s is not None:
                try:
                    entries = self._frames[mode == "raw"].at(scene, self.state.layout, rate_hz,
                                                             start_s)  # fmt: skip
                except ValueError as exc:  # only a plug-in raises here (it is checked first)
                    self._plugin_failed(scene, exc)
                    return None, None
                for i, v in entries:
                    flat[i] = v
                if mode == "predicted":
                    values[...] = felt_magnitude(values, REFERENCE.threshold, REFERENCE.exponent)
            if show_levels:
                labels = np.char.mod("%.2f", values)
        else:
            values = self.device.sent()
            if values.shape != shape:  # the stream of another layout, not yet replaced
                return None, None
            if mode == "felt":
                felt = self.device.felt()
                values = felt if felt is not None else values
                if show_levels:
                    labels = np.char.mod("%.2f", values)
            elif show_levels:
                labels = self.device.sent_levels()
        return values, labels

    def _plugin_failed(self, scene, exc) -> None:
        """A plug-in method failed while playing: say so, list it as unavailable, and go back
        to AS (BA on a layout) with the array paused (all off)."""
        mark_unavailable(scene.method, str(exc))
        back = default_method(self.state.layout, free_points=True)
        self.error_raised.emit(f"{exc}; the plug-in is listed as unavailable, back to {back} "
                               "(paused)")  # fmt: skip
        self.state.update(method=back, playing=False)
        self.state.plugins_changed.emit()

    def display_rate(self) -> tuple[float, float]:
        """Achieved display refresh rate (Hz) and p99 interval (ms) over the last second."""
        times = np.array(self.tick_times)
        times = times[times > times[-1] - 1.0] if len(times) else times
        if len(times) < 3:
            return 0.0, 0.0
        intervals = np.diff(times)
        return 1.0 / intervals.mean(), float(np.percentile(intervals, 99) * 1e3)
