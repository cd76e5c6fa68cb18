"""Activation curves: each tactor's intensity over one trace (the paper's Figures 3 and 4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._shared import validate as _validate
from .correction import check_correction, correct
from .geometry import Grid
from .methods import get_method
from .motor_drive import motor_drive
from .rasterize import check_target, render
from .trace import DIRECTIONS

_DEFAULT_GRID = Grid()


@dataclass(frozen=True)
class ActivationCurves:
    """Intensity against time of every tactor a trace activates.

    Attributes
    ----------
    time_s : ndarray of float64, shape (n,)
        Sample times over one trace, 0 .. ``duration_s``.
    cells : tuple of (int, int), or tuple of int
        ``(col, row)`` of the ``k`` tactors that are ever active, in order of first activation;
        on a layout that is not a grid, their actuator indices.
    raw : ndarray of float64, shape (n, k)
        Intensities before correction.
    corrected : ndarray of float64, shape (n, k)
        After threshold/gamma correction.
    felt : ndarray of float64, shape (n, k), or None
        The corrected curves through the motors' dynamics (the effective drive, see
        :mod:`tactile_core.rendering.motor`), when a motor model was given.
    """

    time_s: np.ndarray
    cells: tuple
    raw: np.ndarray
    corrected: np.ndarray
    felt: np.ndarray | None = None
    names: tuple = ()
    """Each cell's name as the tuner shows it: ``"(4,2)"`` on a grid, the actuator's name
    (``"front-left"``) on a layout."""
    drive: np.ndarray | None = None
    """``(n, k)``: the motor-aware drive of the corrected curves
    (:mod:`tactile_core.rendering.motor_drive`, each sample held until the next), when motors
    to compensate were given; ``felt`` is then of this drive."""

    def onsets_s(self) -> np.ndarray:
        """``(k,)`` time of each tactor's first sample with nonzero intensity, in seconds."""
        return self.time_s[np.argmax(self.raw > 0.0, axis=0)]


def activation_curves(
    shape,
    method,
    *,
    duration_s: float = 2.0,
    direction: str = "forward",
    mu: float = 0.0,
    gamma: float = 1.0,
    samples: int = 2001,
    grid: Grid = _DEFAULT_GRID,
    motor=None,
    compensate=None,
) -> ActivationCurves:
    """Sample the activation curves of one trace.

    Parameters
    ----------
    shape : Shape
    method : str or Method
        Any registered method; one timed by the trace (TB) is timed by ``duration_s``.
    duration_s : float, keyword-only
        Trace duration in seconds (the paper's figures use 1 s; its experiments 2 s).
    direction : {"forward", "reverse"}
    mu, gamma : float
        Correction for the ``corrected`` curves.
    samples : int
        Number of samples over the trace, >= 2.
    grid : Grid or Layout
        On a :class:`~tactile_core.rendering.layout.Layout` that is not a grid, with the
        methods that work there (the paper's four raise ``ValueError`` saying why).
    motor : MotorResponse, optional
        Also low-pass the corrected curves through the motors (``felt``): each sample is held
        until the next, from motors at rest; only the tactors the trace lights are simulated.
    compensate : MotorResponse, optional
        Also the motor-aware drive for these motors (``drive``), at the curves' sample rate,
        from motors at rest; ``felt`` is then of that drive.

    Returns
    -------
    ActivationCurves
    """
    duration_s = _validate.positive("duration_s", duration_s)
    _validate.choice("direction", direction, DIRECTIONS)
    mu, gamma = check_correction(mu, gamma)
    samples = _validate.integer("samples", samples, 2)
    grid = check_target(grid)
    u = np.linspace(0.0, 1.0, samples)
    t = 1.0 - u if direction == "reverse" else u
    method = get_method(method).on_clock(duration_s)  # TB times its onsets by the trace
    frames = render(shape, method, t, grid=grid)
    return curves_from_frames(frames, u * duration_s, mu=mu, gamma=gamma, grid=grid, motor=motor,
                              compensate=compensate)  # fmt: skip


def curves_from_frames(frames, time_s, *, mu: float, gamma: float, grid: Grid = _DEFAULT_GRID,
                       motor=None, compensate=None) -> ActivationCurves:  # fmt: skip
    """The activation curves of frames sampled evenly in time: of a shape's trace
    (:func:`activation_curves`), or of any frame source, such as a ``.tact`` pattern.

    Parameters
    ----------
    frames : ndarray of float64, shape (n, rows, cols), or (n, size) on a layout
        Raw intensities in [0, 1], ``n >= 2`` samples.
    time_s : ndarray of float64, shape (n,)
        When each was sampled, in seconds, evenly spaced (the motors' simulation takes their
        rate from it).
    mu, gamma : float, keyword-only
        Correction for the ``corrected`` curves.
    grid : Grid or Layout, keyword-only
    motor, compensate : MotorResponse, optional
        As :func:`activation_curves`.

    Returns
    -------
    ActivationCurves
    """
    mu, gamma = check_correction(mu, gamma)
    grid = check_target(grid)
    frames = np.asarray(frames, dtype=np.float64)
    time_s = np.asarray(time_s, dtype=np.float64)
    samples = len(frames)
    if samples < 2 or frames.size != samples * grid.size:
        raise ValueError(f"frames must hold at least 2 frames of {grid.size} intensities, got "
                         f"shape {frames.shape}")  # fmt: skip
    if time_s.shape != (samples,) or not time_s[-1] > time_s[0]:
        raise ValueError(f"time_s must hold one increasing time per frame ({samples}), got "
                         f"shape {time_s.shape}")  # fmt: skip
    frames = frames.reshape(samples, grid.size)
    active = np.flatnonzero((frames > 0.0).any(axis=0))
    first = np.argmax(frames[:, active] > 0.0, axis=0)
    order = active[np.argsort(first, kind="stable")]
    raw = frames[:, order]
    corrected = correct(raw, mu, gamma)
    felt = drive = None
    rate = (samples - 1) / (time_s[-1] - time_s[0])
    if compensate is not None:
        drive, _ = motor_drive(corrected, compensate.select(order), rate)
    if motor is not None:
        felt, _ = motor.select(order).effective(corrected if drive is None else drive, rate)
    if not grid.is_grid:
        cells = tuple(int(i) for i in order)
        names = tuple(grid.names[i] for i in cells)
    else:
        cells = tuple(grid.cell(int(i)) for i in order)
        names = tuple(f"({col},{row})" for col, row in cells)
    return ActivationCurves(time_s=time_s, cells=cells, raw=raw, corrected=corrected, felt=felt,
                            names=names, drive=drive)  # fmt: skip
