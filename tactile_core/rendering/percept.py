"""Predicted percept: what a method should feel like, before anyone feels it.

Under the energy-summation model of correction tuning (see
:mod:`tactile_core.experiments.tuning`), a tactor driven at ``d`` is felt with magnitude
``m(d) = ((d - TH) / (1 - TH))^K`` above a threshold ``TH`` and nothing below, and several
tactors add by energy, ``M = sqrt(sum m_i^2)``. For each frame of a trace this module gives

- the **felt intensity** ``M``, and its **ripple** along the trace, ``max M / min M`` over the
  frames in which something is felt (1 is perfectly even);
- the **centroid**, the tactor centres weighted by their felt magnitudes ``m_i``, and its
  distance from the true point ``f(t)``, in millimetres (the array's pitch).

By default the participant is the one the correction is right for, ``TH = mu`` and
``K = 1 / (2 gamma)``: then AS and IM feel exactly even inside the hull (ripple 1) and what
differs between methods is the geometry of their activations, not a mismatch of the
correction. A measured participant (``threshold``, ``exponent``) can be given instead.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._shared import validate as _validate
from .correction import correct
from .geometry import Grid
from .rasterize import render

PITCH_MM = 18.0
"""The palm array's tactor pitch."""


@dataclass(frozen=True)
class Percept:
    """The predicted percept of one trace.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Trace parameters.
    felt : ndarray, shape (n,)
        Felt intensity ``M`` per frame (1 = one tactor at full drive).
    centroid : ndarray, shape (n, 2)
        Felt-magnitude-weighted centroid in grid units (NaN where nothing is felt).
    point : ndarray, shape (n, 2)
        The true point ``f(t)`` in grid units.
    error_mm : ndarray, shape (n,)
        Distance from the centroid to the point, in mm (NaN where nothing is felt).
    """

    t: np.ndarray
    felt: np.ndarray
    centroid: np.ndarray
    point: np.ndarray
    error_mm: np.ndarray

    @property
    def ripple(self) -> float:
        """``max / min`` of the felt intensity over the frames in which something is felt
        (inf if some frame is felt as nothing)."""
        felt = self.felt
        if not (felt > 0).all():
            return float("inf")
        return float(felt.max() / felt.min())

    @property
    def mean_error_mm(self) -> float:
        """Mean centroid error over the felt frames, in mm."""
        e = self.error_mm[np.isfinite(self.error_mm)]
        return float(e.mean()) if e.size else float("nan")

    @property
    def max_error_mm(self) -> float:
        """Largest centroid error over the felt frames, in mm."""
        e = self.error_mm[np.isfinite(self.error_mm)]
        return float(e.max()) if e.size else float("nan")


def felt_magnitude(drive, threshold: float, exponent: float) -> np.ndarray:
    """Per-tactor felt magnitude ``((d - TH) / (1 - TH))^K`` above ``TH``, 0 at or below.

    Parameters
    ----------
    drive : array_like, any shape
        Drive fractions in [0, 1].
    threshold : float
        ``TH`` in [0, 1).
    exponent : float
        ``K`` > 0.
    """
    d = np.asarray(drive, dtype=np.float64)
    x = np.clip((d - threshold) / (1.0 - threshold), 0.0, None)
    return np.where(d > threshold, x**exponent, 0.0)


def predict(shape, method, mu: float, gamma: float, *, threshold: float | None = None,
            exponent: float | None = None, grid: Grid | None = None, samples: int = 2001,
            pitch_mm: float = PITCH_MM) -> Percept:  # fmt: skip
    """The predicted percept of ``shape`` rendered by ``method`` with the correction
    ``mu``/``gamma``.

    Parameters
    ----------
    shape : Shape
    method : str
        Any registered method or spec (``"AS"``, ``"RO:r=1.5"``, a plug-in).
    mu, gamma : float
        The correction the frames are played with.
    threshold, exponent : float, optional
        The participant's ``TH`` and ``K``; by default ``mu`` and ``1 / (2 gamma)`` (the
        participant this correction is right for).
    grid : Grid, optional
        The palm array's 5 x 6 by default.
    samples : int
        Points along the trace (continuous time: no frame rate, no quantisation).
    pitch_mm : float
        Tactor pitch, for the centroid error.

    Returns
    -------
    Percept
    """
    grid = grid or Grid()
    samples = _validate.integer("samples", samples, 2, 1_000_000)
    pitch_mm = _validate.positive("pitch_mm", pitch_mm)
    threshold = mu if threshold is None else _validate.in_range("threshold", threshold, 0, 0.99)
    if exponent is None:
        exponent = 1.0 / (2.0 * _validate.positive("gamma", gamma))
    exponent = _validate.in_range("exponent", exponent, 0.01, 100.0)
    t = np.linspace(0.0, 1.0, samples)
    drive = correct(render(shape, method, t, grid=grid), mu, gamma)
    m = felt_magnitude(drive, threshold, exponent)
    felt = np.sqrt(np.einsum("nij,nij->n", m, m))
    weight = m.sum(axis=(1, 2))
    cx = np.arange(grid.cols) + 0.5
    cy = np.arange(grid.rows) + 0.5
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = np.stack(
            [np.einsum("nij,j->n", m, cx) / weight, np.einsum("nij,i->n", m, cy) / weight], axis=1
        )
    centroid[weight <= 0] = np.nan
    point = np.stack(shape.xy(t), axis=1)
    error_mm = np.hypot(*(centroid - point).T) * pitch_mm
    return Percept(t, felt, centroid, point, error_mm)
