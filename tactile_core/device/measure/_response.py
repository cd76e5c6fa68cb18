"""A first-order motor under piecewise-constant drive, sampled at any times.

The model is the one :class:`~tactile_core.rendering.motor.MotorResponse` simulates frame by
frame: the effective drive ``s`` (the steady drive that would give the vibration the motor has
now) follows the drive ``d`` with ``ds/dt = (d - s) / tau``, ``tau = tau_up`` while ``d > s``
and ``tau_down`` otherwise. Between two changes of the drive the solution is exact,
``s(t) = d + (s0 - d) exp(-(t - t0) / tau)``, and ``s`` never crosses ``d``, so one time
constant holds for the whole stretch. Both the simulated sensor and the fit evaluate it here.
"""

from __future__ import annotations

import numpy as np


def first_order(t_s, change_s, drive, *, tau_up_s: float, tau_down_s: float, s0: float = 0.0,
                start_s: float | None = None) -> np.ndarray:  # fmt: skip
    """The effective drive of a first-order motor at times ``t_s``.

    Parameters
    ----------
    t_s : array_like of float, shape (n,)
        Increasing times (s) to evaluate at.
    change_s : array_like of float, shape (m,)
        Increasing times (s) at which the drive changes.
    drive : array_like of float, shape (m,)
        The drive from each change on, in [0, 1]; before the first change the drive is 0.
    tau_up_s, tau_down_s : float
        Time constants (s) while the motor speeds up and slows down; 0 is no lag.
    s0 : float
        The effective drive at ``start_s``.
    start_s : float, optional
        When ``s0`` holds (default: the first of ``t_s`` and ``change_s``); the drive before
        the first change is 0 from then on.

    Returns
    -------
    ndarray of float64, shape (n,)
        The effective drive (drive units), exact at every time.

    Examples
    --------
    >>> s = first_order([0.0, 0.01, 1.0], [0.0], [1.0], tau_up_s=0.01, tau_down_s=0.02)
    >>> np.round(s, 4).tolist()
    [0.0, 0.6321, 1.0]
    """
    t = np.asarray(t_s, dtype=np.float64)
    change = np.asarray(change_s, dtype=np.float64)
    drive = np.asarray(drive, dtype=np.float64)
    out = np.empty_like(t)
    if t.size == 0:
        return out
    if start_s is None:
        start_s = float(min(t[0], change[0])) if change.size else float(t[0])
    bounds = np.concatenate([[start_s], change, [np.inf]])
    levels = np.concatenate([[0.0], drive])
    first = np.searchsorted(t, bounds, side="left")
    s = float(s0)
    for k in range(levels.size):
        t0, d = bounds[k], levels[k]
        if not np.isfinite(t0):
            break
        tau = tau_up_s if d > s else tau_down_s
        lo, hi = first[k], first[k + 1]
        if hi > lo:
            out[lo:hi] = _settle(t[lo:hi] - t0, s, d, tau)
        t1 = bounds[k + 1]
        if np.isfinite(t1):
            s = float(_settle(np.array([t1 - t0]), s, d, tau)[0])
    return out


def _settle(dt: np.ndarray, s: float, d: float, tau: float) -> np.ndarray:
    """``d + (s - d) exp(-dt / tau)`` (``d`` at once for ``tau`` 0)."""
    if tau <= 0.0:
        return np.full(dt.shape, d)
    return d + (s - d) * np.exp(-np.maximum(dt, 0.0) / tau)


def hat_basis(s, nodes) -> np.ndarray:
    """Ramps that build a non-decreasing piecewise-linear curve through ``nodes``.

    ``A(s) = sum_j delta_j B_j(s)`` with ``B_j`` rising from 0 at ``nodes[j]`` to 1 at
    ``nodes[j + 1]``: with every ``delta_j >= 0`` the curve is non-decreasing, 0 at
    ``nodes[0]``, and ``A(nodes[k]) = delta_0 + ... + delta_{k-1}``.

    Parameters
    ----------
    s : array_like of float, shape (n,)
        Effective drive.
    nodes : array_like of float, shape (m + 1,)
        Increasing drives (the device's levels as fractions: ``k / (levels - 1)``).

    Returns
    -------
    ndarray of float64, shape (n, m)
    """
    s = np.asarray(s, dtype=np.float64)
    nodes = np.asarray(nodes, dtype=np.float64)
    out = np.subtract.outer(s, nodes[:-1])
    out *= 1.0 / np.diff(nodes)
    return np.clip(out, 0.0, 1.0, out=out)
