"""A blocking-friendly API for experiment scripts (PsychoPy or plain Python).

>>> import tactile_core as tc
>>> with tc.open_array("sim") as array:                       # doctest: +SKIP
...     shown = array.play("circle:2.5,3,2", method="IM", duration_s=1.0)
...     print(f"first frame at {shown.first_frame_s:.4f} s (time.perf_counter)")

:func:`open_array` opens a device (the same URLs as ``tactile stream``: ``sim``, a serial port,
a pseudo-terminal from ``tactile emulate``) and streams to it from a thread of this process.
:meth:`Array.play` presents a shape once and, by default, returns when it has played; the
:class:`Presentation` it returns carries the time its first frame was written to the device
(the same moment an LSL marker is stamped with, ``lsl=True``). :meth:`Array.point` drives
free points. This module never imports Qt (a test imports it in a fresh interpreter).

Safety: leaving the ``with`` block in any way (an exception, Ctrl-C) turns the array off and
stops the stream; so do :meth:`Array.close`, interpreter exit, and SIGTERM (``open_array``
makes it raise ``SystemExit`` in the main thread while the array is open, unless the script
has its own handler). Ctrl-C while :meth:`Presentation.wait` blocks turns the array off before
the ``KeyboardInterrupt`` goes on up.
"""

from __future__ import annotations

import heapq
import itertools
import math
import os
import signal
import threading
import time

from ._shared import validate as _validate
from .device.link import open_link
from .device.profile import DeviceProfile, load_profile
from .rendering.correction import check_correction
from .rendering.placement import default_method
from .rendering.points import TIMEOUT_RANGE_S as POINT_TIMEOUT_RANGE_S
from .rendering.points import FreePoints, free_method
from .rendering.scene import Scene
from .rendering.shapes import Shape, parse_shape
from .stream import Streamer, StreamOptions, check_lead_ms

__all__ = ["Array", "Presentation", "open_array"]

START_TIMEOUT_S = 5.0
"""How long :meth:`Presentation.wait` waits for the first frame before saying why not."""


class Presentation:
    """One stimulus handed to the array by :meth:`Array.play`.

    Attributes
    ----------
    scene : Scene
        What was played.
    started, done : threading.Event
        Set when the first frame was written; when the stimulus has played (or was cut short
        by another play, ``all_off`` or ``close``).
    first_frame_s : float or None
        ``time.perf_counter`` seconds when its first frame was written to the device (for a
        frame scheduled ahead, ``lead_ms``: when the array is to play it); None before.
    seq : int or None
        The first frame's sequence number on the wire.
    interrupted : bool
        True when it was cut short.
    failed : str
        Why the stream stopped while it waited or played (the device went away), else "".
    """

    def __init__(self, scene: Scene, array: Array):
        self.scene = scene
        self.started = threading.Event()
        self.done = threading.Event()
        self.first_frame_s: float | None = None
        self.seq: int | None = None
        self.interrupted = False
        self.failed = ""
        self._array = array

    @property
    def duration_s(self) -> float:
        """How long the stimulus plays."""
        return self.scene.duration_s

    def wait(self, timeout_s: float | None = None) -> Presentation:
        """Block until the stimulus has played (or ``timeout_s`` passed); return it.

        ``RuntimeError`` if no frame went out within :data:`START_TIMEOUT_S` (the stream
        stopped: its status says why), or at once when the stream stops before the stimulus
        has played (the device went away: :attr:`failed`). A presentation cut short before its
        first frame (another ``play``, ``all_off``, ``close``) returns at once, ``interrupted``.
        Ctrl-C here turns the array off, then propagates. ``timeout_s`` is None (or infinite)
        to wait as long as it plays, else seconds >= 0.
        """
        if timeout_s is not None:
            if not (_validate.is_number(timeout_s) and timeout_s == math.inf):
                timeout_s = _validate.non_negative("timeout_s", timeout_s)
            if timeout_s >= threading.TIMEOUT_MAX:  # inf, 1e300: threading's wait overflows
                timeout_s = None
        try:
            deadline = time.monotonic() + START_TIMEOUT_S
            while not (self.started.is_set() or self.done.is_set()):
                left = deadline - time.monotonic()
                if left <= 0:
                    stats = self._array.streamer.stats
                    raise RuntimeError(f"no frame went out within {START_TIMEOUT_S:g} s: "
                                       f"[{stats.state}] {stats.status}")  # fmt: skip
                self.started.wait(min(left, 0.01))
            self.done.wait(timeout_s)
            if self.failed:
                raise RuntimeError(f"the stream stopped before the stimulus had played: "
                                   f"{self.failed}")  # fmt: skip
        except KeyboardInterrupt:
            self._array.all_off()
            raise
        return self

    def __repr__(self) -> str:
        when = "not started" if self.first_frame_s is None else f"{self.first_frame_s:.6f} s"
        shape = self.scene.shape.spec if self.scene.shape is not None else "source"
        return f"Presentation({shape}, {self.scene.method}, first frame {when})"


class Array:
    """An open array: play shapes, drive points, turn it off. Made by :func:`open_array`."""

    def __init__(self, link, profile: DeviceProfile, *, rate_hz: float, options: StreamOptions,
                 lsl: bool, lsl_levels: bool, point_timeout_s: float | None,
                 compensate_motors: bool = False, validate=None,
                 validate_log=None):  # fmt: skip
        self.link = link
        self.profile = profile
        self.rate_hz = _validate.rate("rate_hz", rate_hz, 1.0, 10_000.0)
        self.compensate_motors = compensate_motors
        """Whatever is played goes out as motor-aware drive (``open_array(...,
        compensate_motors=True)``)."""
        self.points = FreePoints(timeout_s=point_timeout_s)
        self.streamer = Streamer(link, profile, options=options, on_onset=[self._on_onset],
                                 on_status=self._on_stream_status)  # fmt: skip
        self._lost = ""  # the stream's last status once it stopped on its own
        self.lsl = None
        self._lock = threading.Lock()
        self._waiting: dict[int, Presentation] = {}
        self._current: Presentation | None = None
        self._due: list = []  # heap of (time_s, n, presentation) to mark done
        self._n = itertools.count()
        self._wake = threading.Event()
        self._closed = threading.Event()
        self._epochs = itertools.count(1)
        if lsl or lsl_levels:
            from .serve import LslOutlets

            self.lsl = LslOutlets(profile, rate_hz=self.rate_hz, levels=lsl_levels)
            self.lsl.attach(self.streamer)
        self.validator = None
        """The validator (``validate=``): the sensor's onset of each presentation, in
        :attr:`Validator.rows <tactile_core.experiments.measure.Validator.rows>` and its CSV."""
        if validate is not None:
            from .experiments.measure import Validator

            try:
                self.validator = Validator(validate, log=validate_log, link=link,
                                           profile=profile, lsl=lsl)  # fmt: skip
                self.validator.attach(self.streamer)
            except BaseException:
                if self.lsl is not None:
                    self.lsl.close()
                raise
        self._keeper = threading.Thread(target=self._keep, name="tactile-script", daemon=True)

    def _start(self) -> Array:
        self.streamer.start()
        self._keeper.start()
        self.streamer.identified.wait(START_TIMEOUT_S)
        if self._lost:  # (open_array closes the link)
            raise RuntimeError(f"the stream did not start: {self._lost}")
        if threading.current_thread() is threading.main_thread():
            with _SIGTERM_LOCK:
                if signal.getsignal(signal.SIGTERM) == signal.SIG_DFL:
                    signal.signal(signal.SIGTERM, _terminate)
                if signal.getsignal(signal.SIGTERM) is _terminate:
                    _SIGTERM_ARRAYS.add(self)
        return self

    # --- presenting ----------------------------------------------------------------------------

    def play(self, shape, method: str | None = None, *, mu: float = 0.33, gamma: float = 0.7,
             duration_s: float | None = None, gain: float = 1.0, direction: str = "forward",
             wait: bool = True, marker: str = "script") -> Presentation:  # fmt: skip
        """Present ``shape`` once with ``method`` and the correction ``(mu, gamma)``.

        Parameters
        ----------
        shape : Shape or str
            A shape (``tc.Circle(...)``) or its spec (``"circle:2.5,3,2"``); or a frame source
            (any object with ``live(...)``: a :class:`~tactile_core.files.pattern.Pattern`, an
            imported ``.tact`` pattern), played for ``duration_s``.
        method : str, optional
            Any method that renders on the array (the paper's four, the peers, a plug-in;
            ``"RO:r=1.5"``); IM by default on a grid, BA on a layout that is not one.
        mu, gamma, gain : float
            The correction and master intensity.
        duration_s : float, optional
            How long the trace takes, in seconds; the array is off afterwards. By default 1 s
            for a shape, and a frame source's own ``duration_s`` (a pattern's: when its last
            effect ends).
        wait : bool
            Block until it has played (default), or return at once.
        marker : str
            The kind of presentation in its LSL marker.

        Returns
        -------
        Presentation
            With the first frame's time once it went out.
        """
        self._check_open()
        wait = _validate.boolean("wait", wait)  # "no" would block, None would not
        if method is None:
            method = default_method(self.profile.layout)
        if isinstance(shape, str):
            shape = parse_shape(shape)
        kind = {"shape": shape} if isinstance(shape, Shape) else {"source": shape}
        if duration_s is None:
            own = getattr(shape, "duration_s", None) if "source" in kind else None
            duration_s = own if _validate.is_number(own) and own > 0 else 1.0
        scene = Scene(method=method, mu=mu, gamma=gamma, duration_s=duration_s, pause_s=0.0,
                      repeat=False, rate_hz=self.rate_hz, gain=gain, direction=direction,
                      marker=marker, epoch=next(self._epochs),
                      compensate_motors=self.compensate_motors, **kind)  # fmt: skip
        live = scene.live(self.profile.layout, self.rate_hz)  # refused here, by name
        if "source" in kind:  # a pattern: its table now, not beside the output thread
            live.precompute()  # (the stream plays from it: the same frames, see TactPattern.live)
        presentation = Presentation(scene, self)
        with self._lock:
            self._finish_current()
            self._waiting[id(scene)] = presentation
            self._current = presentation
        self.streamer.set_scene(scene)
        return presentation.wait() if wait else presentation

    def point(self, x: float, y: float, intensity: float = 1.0, *, point_id: str = "",
              method: str | None = None, mu: float = 0.33, gamma: float = 0.7) -> None:  # fmt: skip
        """Put a free point at ``(x, y)`` (grid units) with ``intensity``; it stays until
        :meth:`release` (or, with ``point_timeout_s``, until not refreshed for that long).
        ``method`` must render free points (not MM or IM): AS by default on a grid, BA on a
        layout that is not one."""
        self._check_open()
        if method is None:
            method = default_method(self.profile.layout, free_points=True)
        spec = free_method(method).spec
        mu, gamma = check_correction(mu, gamma)  # a refused call must not light the point
        self.points.set(point_id, x, y, intensity)
        scene = self.streamer.scene
        if (
            scene is None
            or scene.source is not self.points
            or ((scene.method, scene.mu, scene.gamma) != (spec, mu, gamma))
        ):
            with self._lock:
                self._finish_current()
            self.streamer.set_scene(Scene(method=method, mu=mu, gamma=gamma, rate_hz=self.rate_hz,
                                          source=self.points, marker="script-points",
                                          compensate_motors=self.compensate_motors))  # fmt: skip

    def _check_open(self) -> None:
        if self._closed.is_set():
            raise ValueError("the array is closed: open_array(...) again to present more")
        if self._lost:  # nothing would go out: say so now, not after START_TIMEOUT_S
            raise RuntimeError(f"the stream has stopped: {self._lost}")

    def release(self, point_id: str | None = None) -> None:
        """Release one free point (None: all)."""
        self.points.release(point_id)

    def all_off(self) -> None:
        """Everything off at the next frame: points released, a presentation cut short."""
        self.points.release()
        with self._lock:
            self._finish_current()
        self.streamer.set_scene(None)

    def close(self) -> None:
        """All off, stop the stream (its last frame is all zeros) and close the device."""
        if self._closed.is_set():
            return
        self._closed.set()
        try:
            self.all_off()
        finally:
            self._wake.set()
            self.streamer.stop()
            if self.validator is not None:  # the last presentations' windows, then its log
                self.validator.close()
            self.link.close()
            if self.lsl is not None:
                self.lsl.close()
            _release_sigterm(self)
            keeper = self._keeper  # gone when close() returns: nothing left running
            if keeper.ident is not None and keeper is not threading.current_thread():
                keeper.join(timeout=2.0)

    def __enter__(self) -> Array:
        self._check_open()
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # --- threads -------------------------------------------------------------------------------

    def _finish_current(self) -> None:
        """(Under the lock.) The presentation playing is cut short."""
        current = self._current
        if current is not None and not current.done.is_set():
            current.interrupted = True
            current.done.set()
            self._waiting.pop(id(current.scene), None)
        self._current = None

    def _on_onset(self, onset) -> None:
        """The output thread: the first frame of a presentation went out."""
        with self._lock:
            presentation = self._waiting.pop(id(onset.scene), None)
            if presentation is None:
                return
            presentation.first_frame_s = onset.time_s
            presentation.seq = onset.seq
            end = onset.time_s + presentation.duration_s
            heapq.heappush(self._due, (end, next(self._n), presentation))
        presentation.started.set()
        self._wake.set()

    def _on_stream_status(self, stats) -> None:
        """The output thread: the stream stopped on its own (a device that went away)."""
        if stats.state in ("stopped", "failed", "refused") and not self._closed.is_set():
            self._lost = stats.status or stats.state
            self._wake.set()

    def _keep(self) -> None:
        """Mark presentations done when their time is up (failed, when the stream stopped)."""
        while not self._closed.is_set():
            with self._lock:
                now = time.perf_counter()
                while self._due and self._due[0][0] <= now:
                    _, _, presentation = heapq.heappop(self._due)
                    presentation.done.set()
                if self._lost:
                    pending = [p for _, _, p in self._due] + list(self._waiting.values())
                    self._due, self._waiting, self._current = [], {}, None
                    for presentation in pending:
                        presentation.failed = self._lost
                        presentation.interrupted = True
                        presentation.done.set()
                wait = self._due[0][0] - now if self._due else 1.0
            self._wake.wait(min(wait, 1.0))
            self._wake.clear()
        with self._lock:
            for _, _, presentation in self._due:
                presentation.interrupted = True
                presentation.done.set()


def _terminate(signum, frame):
    raise SystemExit(128 + signum)


_SIGTERM_LOCK = threading.Lock()
_SIGTERM_ARRAYS: set = set()
"""The open arrays that rely on :func:`_terminate`: SIGTERM goes back to its default only when
the last of them closes, and only if the script has not put its own handler in since."""


def _release_sigterm(array: Array) -> None:
    with _SIGTERM_LOCK:
        if array not in _SIGTERM_ARRAYS:
            return
        _SIGTERM_ARRAYS.discard(array)
        if not _SIGTERM_ARRAYS and signal.getsignal(signal.SIGTERM) is _terminate:
            try:
                signal.signal(signal.SIGTERM, signal.SIG_DFL)
            except ValueError:  # not the main thread: the handler stays, harmless
                pass


def open_array(url: str = "sim", profile=None, *, rate_hz: float = 300.0, lead_ms: float = 0.0,
               lsl: bool = False, lsl_levels: bool = False, point_timeout_s: float | None = None,
               compensate_motors: bool = False, validate=None,
               validate_log=None) -> Array:  # fmt: skip
    """Open a device and start streaming to it (all off until something is played).

    Parameters
    ----------
    url : str
        ``"sim"`` (the simulated array), a serial port, a pyserial URL, a pseudo-terminal.
    profile : str, Path or DeviceProfile, optional
        The device profile (the palm array by default).
    rate_hz : float
        Frames per second (300).
    lead_ms : float
        Send frames this far ahead to arrays that play them at their time (0: on arrival).
    lsl, lsl_levels : bool
        Open the LSL marker outlet (``tactile-markers``), and the levels outlet.
    point_timeout_s : float or None
        Release a free point not refreshed within this long (None: it stays until released).
    compensate_motors : bool
        Motor-aware drive: pre-compensate each lit tactor's motor lag with the profile's
        motor constants (:mod:`tactile_core.rendering.motor_drive`); off, the paper's
        pipeline, by default. A profile without motor constants (``motor``) is refused.
    validate : str or sensor, optional
        A sensor on the array (``"audio:NAME?channel=N"``, ``"sim"`` on the simulated array, or
        a sensor object): the onset it detects of each presentation is logged beside the
        commanded time (:class:`~tactile_core.experiments.measure.Validator`), and sent on the
        LSL stream ``tactile-validation`` with ``lsl=True``.
    validate_log : path, optional
        The validator's CSV, or a folder for ``validate-<date>.csv`` (a results folder);
        beside the running script by default.

    Returns
    -------
    Array
        Use it as a context manager, or call :meth:`Array.close`.
    """
    if isinstance(url, os.PathLike):
        url = os.fspath(url)
    if url is not None and not isinstance(url, str):  # pyserial's TypeError names no argument
        raise ValueError(f"url must be a device URL such as 'sim' or '/dev/ttyUSB0', got "
                         f"{_validate.shown(url)}")  # fmt: skip
    if not isinstance(profile, DeviceProfile):
        profile = load_profile(profile)
    options = StreamOptions(lead_ms=check_lead_ms(lead_ms))
    _validate.rate("rate_hz", rate_hz, 1.0, 10_000.0)
    if point_timeout_s is not None:  # named as the caller wrote it, before anything opens
        _validate.in_range("point_timeout_s", point_timeout_s, *POINT_TIMEOUT_RANGE_S)
    compensate_motors = _validate.boolean("compensate_motors", compensate_motors)
    if compensate_motors and profile.motor is None:
        raise ValueError(f"compensate_motors needs the motors' time constants: profile "
                         f"{profile.name} has none ('motor')")  # fmt: skip
    link = open_link(url, profile)
    array = None
    try:
        array = Array(link, profile, rate_hz=rate_hz, options=options, lsl=lsl,
                      lsl_levels=lsl_levels, point_timeout_s=point_timeout_s,
                      compensate_motors=compensate_motors, validate=validate,
                      validate_log=validate_log)  # fmt: skip
        return array._start()
    except BaseException:
        if array is not None and array.validator is not None:
            array.validator.close(timeout_s=0.5)
        link.close()
        raise
