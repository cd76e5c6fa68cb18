"""The tuner's state: the current scene and how it is displayed, with change signals."""

from __future__ import annotations

from PySide6 import QtCore

import tactile_core as tc
from tactile_core.rendering.scene import Scene

DEFAULT_SCENE = Scene(tc.Line((0.5, 1.84), (4.5, 4.16)), "AS", mu=0.33, gamma=0.7)
"""The Experiment 1 line with area sampling at the paper's mu and gamma."""

VIEW_MODES = ("raw", "corrected", "sent", "felt", "predicted")


def plugin_problem(scene: Scene) -> str:
    """Try a plug-in method on the scene's whole trace (257 points, batch and live) before it
    plays: its error, with the plug-in taken out of the registry, or "" when it renders (or
    is built in)."""
    import numpy as np

    from tactile_core.rendering.methods import get_method, mark_unavailable
    from tactile_core.rendering.rasterize import render_point

    try:
        method = get_method(scene.method)
        if not method.plugin:
            return ""
        t = np.linspace(0.0, 1.0, 257)
        tc.render(scene.shape, scene.method, t)
        for x in t[::16]:
            render_point(scene.shape, scene.method, float(x))
    except ValueError as exc:
        mark_unavailable(scene.method, str(exc))
        return f"{exc}; the plug-in is listed as unavailable"
    return ""


class TunerState(QtCore.QObject):
    """The one source of truth the widgets write to and the views listen to.

    :meth:`update` validates a change by building a new immutable :class:`Scene`; a bad value
    (NaN, out of range) emits :attr:`error_raised` and changes nothing.
    """

    scene_changed = QtCore.Signal(object)
    """Any scene field changed: the new :class:`Scene`."""
    method_changed = QtCore.Signal(str)
    correction_changed = QtCore.Signal(float, float)
    shape_changed = QtCore.Signal(object)
    timing_changed = QtCore.Signal()
    sampling_changed = QtCore.Signal()
    playing_changed = QtCore.Signal(bool)
    view_mode_changed = QtCore.Signal(str)
    show_levels_changed = QtCore.Signal(bool)
    error_raised = QtCore.Signal(str)
    plugins_changed = QtCore.Signal()
    """A plug-in method was found broken and taken out of the list."""

    _TIMING = ("duration_s", "pause_s", "direction", "repeat")
    _SAMPLING = ("rate_hz", "filter", "subsamples", "dither")

    def __init__(self, scene: Scene | None = None, parent=None):
        super().__init__(parent)
        self._scene = scene or DEFAULT_SCENE
        self._view_mode = "corrected"
        self._show_levels = False

    @property
    def scene(self) -> Scene:
        """The current scene."""
        return self._scene

    def update(self, **changes) -> bool:
        """Apply field changes; False (and :attr:`error_raised`) if they are invalid. Playing
        (``playing=True``) without a ``hold_s`` plays the trace: a held instant is let go."""
        if changes.get("playing") and "hold_s" not in changes:
            changes["hold_s"] = None
        try:
            new = self._scene.replace(**changes)
        except (ValueError, TypeError) as exc:
            self.error_raised.emit(str(exc))
            return False
        return self.set_scene(new)

    def set_scene(self, scene: Scene) -> bool:
        """Replace the whole scene (e.g. from a preset) and emit what changed."""
        if not isinstance(scene, Scene):
            self.error_raised.emit(f"scene must be a Scene, got {scene!r}")
            return False
        old = self._scene
        if scene == old:
            return True
        if scene.shape is not None and (scene.method, scene.shape) != (old.method, old.shape):
            problem = plugin_problem(scene)
            if problem:
                self.error_raised.emit(problem)
                self.plugins_changed.emit()
                return False
        self._scene = scene
        if scene.method != old.method:
            self.method_changed.emit(scene.method)
        if (scene.mu, scene.gamma) != (old.mu, old.gamma):
            self.correction_changed.emit(scene.mu, scene.gamma)
        if scene.shape != old.shape:
            self.shape_changed.emit(scene.shape)
        if any(getattr(scene, k) != getattr(old, k) for k in self._TIMING):
            self.timing_changed.emit()
        if any(getattr(scene, k) != getattr(old, k) for k in self._SAMPLING):
            self.sampling_changed.emit()
        if scene.playing != old.playing:
            self.playing_changed.emit(scene.playing)
        self.scene_changed.emit(scene)
        return True

    def restart(self) -> None:
        """Start the trace again from its beginning."""
        self.update(epoch=self._scene.epoch + 1, playing=True)

    @property
    def view_mode(self) -> str:
        """What the heatmap shows: raw, corrected, sent or felt intensities."""
        return self._view_mode

    def set_view_mode(self, mode: str) -> None:
        """Switch the heatmap's view mode."""
        if mode not in VIEW_MODES:
            self.error_raised.emit(
                f"view mode must be one of {', '.join(VIEW_MODES)}, got {mode!r}"
            )
            return
        if mode != self._view_mode:
            self._view_mode = mode
            self.view_mode_changed.emit(mode)

    @property
    def show_levels(self) -> bool:
        """Whether the heatmap writes each cell's value in it."""
        return self._show_levels

    def set_show_levels(self, show: bool) -> None:
        """Show or hide per-cell numbers."""
        show = bool(show)
        if show != self._show_levels:
            self._show_levels = show
            self.show_levels_changed.emit(show)
