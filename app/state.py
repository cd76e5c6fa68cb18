"""The tuner's state: the current scene and how it is displayed, with change signals."""

from __future__ import annotations

from PySide6 import QtCore

import tactile_core as tc
from tactile_core.files.pattern import Pattern, PatternCue
from tactile_core.rendering import placement
from tactile_core.rendering.geometry import Grid
from tactile_core.rendering.layout import Layout
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

    The state also holds the device's :attr:`layout` (the views draw it, the scene renders on
    it). On a layout that is not a grid the paper's four methods cannot render: choosing one
    (:meth:`update`) is refused saying why, and a whole scene that has one (a preset, the last
    session, the scene before a layout change) plays BA instead, with a status message
    (:attr:`message_posted`); the same for a shape that lies off the layout, and for the
    predicted view, which needs a grid.

    Parameters
    ----------
    scene : Scene, optional
        The Experiment 1 line with AS by default.
    layout : Layout, optional
        The device's layout; the paper's palm array by default.
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
    layout_changed = QtCore.Signal(object)
    """The device's :class:`Layout` changed (another profile)."""
    message_posted = QtCore.Signal(str, int)
    """A status line and how long to show it (ms): what a layout change changed."""

    _TIMING = ("duration_s", "pause_s", "direction", "repeat")
    _SAMPLING = ("rate_hz", "filter", "subsamples", "dither")

    def __init__(self, scene: Scene | None = None, parent=None, layout: Layout | None = None):
        super().__init__(parent)
        self._scene = scene or DEFAULT_SCENE
        self._view_mode = "corrected"
        self._show_levels = False
        self._layout = Grid()
        self.last_message = ""
        """The last status message (one posted before anything listened: shown at start-up)."""
        self.method_guard = None
        """A callable ``guard(name) -> why`` ("" when allowed) consulted by :meth:`update`
        besides the layout (another program driving free points refuses MM and IM); a refusal
        goes to the status line."""
        self.play_guard = None
        """A callable ``guard() -> why`` ("" when allowed) consulted by :meth:`update` before
        the scene plays (Blind A/B before the rater's first key: nothing plays that is not a
        key); a refusal goes to the status line."""
        self.run_owner = None
        """The experiment run that alone sets the scene meanwhile (:meth:`lock`), or None."""
        if layout is not None:
            self.set_layout(layout)

    def lock(self, owner) -> None:
        """Only ``owner`` (an experiment run's trials) changes the scene until :meth:`unlock`:
        a preset opened from the menu, the controls or a restart would otherwise change what
        plays while the row records the trial's condition."""
        self.run_owner = owner

    def unlock(self, owner) -> None:
        """Release :meth:`lock` (if ``owner`` holds it)."""
        if self.run_owner is owner:
            self.run_owner = None

    def _refused_by_run(self, owner) -> bool:
        if self.run_owner is None or owner is self.run_owner:
            return False
        self._post("an experiment run sets the stimulus: Stop the run first to change it")
        return True

    @property
    def scene(self) -> Scene:
        """The current scene."""
        return self._scene

    def update(self, *, owner=None, **changes) -> bool:
        """Apply field changes; False (and :attr:`error_raised`) if they are invalid. Playing
        (``playing=True``) without a ``hold_s`` plays the trace: a held instant is let go (a
        held :class:`PatternCue` plays on from its moment); :attr:`play_guard` may refuse it.

        A change that starts a new presentation (a new epoch or shape, playing after a pause)
        without naming its ``marker`` is the tuner's own: the kind a part gave the scene before
        (``ab``, ``trial``) is dropped. During an experiment run only its ``owner`` changes
        the scene (:meth:`lock`)."""
        if self._refused_by_run(owner):
            return False
        why = self.play_guard() if changes.get("playing") and self.play_guard else ""
        if why:
            self._post(why)
            return False
        if changes.get("playing") and "hold_s" not in changes:
            changes["hold_s"] = None
            if "source" not in changes and isinstance(self._scene.source, PatternCue):
                changes["source"] = self._scene.source.played()  # held: plays on from there
        if changes.get("shape") is not None and "source" not in changes:
            changes["source"] = None  # a shape picked replaces a pattern, which would win
        why = placement.refusal(changes["method"], self._layout) if "method" in changes else ""
        if why:
            self.error_raised.emit(why)
            return False
        guard = self.method_guard
        why = guard(changes["method"]) if guard is not None and "method" in changes else ""
        if why:
            self._post(why)
            return False
        old = self._scene
        starts = (
            changes.get("epoch", old.epoch) != old.epoch
            or changes.get("shape", old.shape) != old.shape
            or (changes.get("playing") and not old.playing)
        )
        if starts and old.marker and "marker" not in changes:
            changes["marker"] = ""
        try:
            new = self._scene.replace(**changes)
        except (ValueError, TypeError) as exc:
            self.error_raised.emit(str(exc))
            return False
        return self.set_scene(new, owner=owner)

    def set_scene(self, scene: Scene, *, owner=None) -> bool:
        """Replace the whole scene (e.g. from a preset) and emit what changed (during an
        experiment run, only its ``owner``: :meth:`lock`)."""
        if self._refused_by_run(owner):
            return False
        if not isinstance(scene, Scene):
            self.error_raised.emit(f"scene must be a Scene, got {scene!r}")
            return False
        why = placement.refusal(scene.method, self._layout)
        if why:  # a preset's or an earlier scene's method: the layout's smooth method instead
            self._post(placement.fallback_note(scene.method, self._layout))
            scene = scene.replace(method=placement.FALLBACK)
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

    @property
    def held(self) -> bool:
        """Whether the scene holds an instant: a scrubbed trace (``hold_s``) or a held
        pattern (:class:`PatternCue`); playing lets it go."""
        source = self._scene.source
        return self._scene.hold_s is not None or (isinstance(source, PatternCue) and source.hold)

    def restart(self) -> None:
        """Start the trace again from its beginning (a pattern played from a moment of it,
        from its own beginning)."""
        source = self._scene.source
        if isinstance(source, PatternCue):
            self.update(source=PatternCue(source.pattern), epoch=self._scene.epoch + 1,
                        playing=True)  # fmt: skip
            return
        self.update(epoch=self._scene.epoch + 1, playing=True)

    @property
    def layout(self) -> Layout:
        """Where the device's actuators are, and what the scene renders onto (a
        :class:`~tactile_core.rendering.geometry.Grid` is one)."""
        return self._layout

    def set_layout(self, layout: Layout) -> None:
        """Follow the device's layout: a method that cannot render on it becomes BA, a shape
        that lies off it the layout's default shape, the predicted view (grids only) the
        corrected one; each change is said in a status message."""
        if layout == self._layout:
            return
        self._layout = layout
        if not layout.is_grid and self._view_mode == "predicted":
            self._view_mode = "corrected"
            self.view_mode_changed.emit("corrected")
            self._post("the predicted view needs a grid: showing corrected intensities")
        self.layout_changed.emit(layout)
        self.fit_scene()

    def fit_scene(self) -> None:
        """Make the scene one the layout can play: BA for a method that cannot render on it, the
        layout's default shape for a shape that lies off it (a scene made for another array) or
        a pattern that does not play there (a group it names, an actuator), each said in a
        status message."""
        scene, layout = self._scene, self._layout
        if scene.shape is not None and not placement.fits(scene.shape, layout):
            shape = placement.default_shape(layout)
            self._post(f"the shape lies off this layout ({layout.describe()}): {shape} instead")
            scene = scene.replace(shape=shape, hold_s=None)
        if isinstance(scene.source, (Pattern, PatternCue)):  # its groups, dots, methods
            try:
                scene.source.check(layout)
            except ValueError as exc:
                shape = placement.default_shape(layout)
                self._post(f"the pattern does not play on this layout ({exc}): {shape} instead")
                scene = scene.replace(shape=shape, source=None, hold_s=None)
        self.set_scene(scene)

    def _post(self, text: str) -> None:
        self.last_message = text
        self.message_posted.emit(text, 10_000)

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
        if mode == "predicted" and not self._layout.is_grid:
            self.error_raised.emit(
                "the predicted view needs a grid (the percept model sums tactors of a grid); "
                f"this layout is {self._layout.describe()}"
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
