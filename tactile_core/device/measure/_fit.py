"""The first-order fit of one tactor's vibration envelope: delay, spin-up and run-down.

The model: the drive commanded (``change_s``, ``drive``) reaches the motor ``delay_s`` later;
its effective drive ``s(t)`` follows with ``tau_up_s`` / ``tau_down_s``
(:func:`._response.first_order`); the vibration's amplitude is a non-decreasing function
``A(s)``, piecewise linear through the device's levels (the physical response curve), so that
``a(t) = A(s(t))``. The three time parameters are fitted by nonlinear least squares
(:func:`scipy.optimize.least_squares`); for each trial of them the curve ``A`` is the
non-negative least-squares solution (its increments ``>= 0``: ``scipy.optimize.nnls``), which
is linear in them (variable projection). The whole block is fitted at once, so steps that do not
settle, the ramp and the pulses all count.

The residual is the RMS difference between the envelope and the model over the samples fitted,
as a fraction of the amplitude at full drive: a few percent for a motor that first order
describes; much more for one that overshoots, has two time constants, or beats.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import linalg, optimize

from ._response import first_order, hat_basis

DELAY_RANGE_S = (0.0, 0.5)
TAU_RANGE_S = (0.0005, 3.0)
_START_DELAYS_S = (0.002, 0.01, 0.03, 0.08)
_START_TAUS_S = ((0.01, 0.02), (0.03, 0.06), (0.1, 0.2), (0.3, 0.6))
"""Where the search starts from: the best of these (delay x (spin-up, run-down)) pairs; never
on a bound (the trust region would not leave it)."""


@dataclass(frozen=True)
class Fit:
    """A tactor's first-order fit.

    Attributes
    ----------
    delay_s : float
        From a command's time to the motor's drive changing (s).
    tau_up_s, tau_down_s : float
        Spin-up and run-down time constants (s).
    nodes : ndarray of float64, shape (m + 1,)
        The drives the amplitude curve is given at (0 first).
    amplitude : ndarray of float64, shape (m + 1,)
        The steady vibration amplitude at each node (sensor units: full scale 1).
    residual : float
        RMS of envelope minus model over the samples fitted, as a fraction of the amplitude
        at full drive (the last node).
    samples : int
        Envelope samples fitted.
    """

    delay_s: float
    tau_up_s: float
    tau_down_s: float
    nodes: np.ndarray
    amplitude: np.ndarray
    residual: float
    samples: int

    def model(self, t_s, change_s, drive) -> np.ndarray:
        """The fitted amplitude at times ``t_s`` for commands ``(change_s, drive)``."""
        s = first_order(t_s, np.asarray(change_s) + self.delay_s, drive,
                        tau_up_s=self.tau_up_s, tau_down_s=self.tau_down_s,
                        start_s=float(np.min(t_s)) - 1.0)  # fmt: skip
        return np.interp(s, self.nodes, self.amplitude)


class _Problem:
    """The envelope samples and commands of one fit; :meth:`solve` the curve for given times."""

    def __init__(self, t_s, amplitude, change_s, drive, nodes, weight):
        self.t = np.asarray(t_s, dtype=np.float64)
        self.a = np.asarray(amplitude, dtype=np.float64)
        self.change = np.asarray(change_s, dtype=np.float64)
        self.drive = np.asarray(drive, dtype=np.float64)
        self.nodes = np.asarray(nodes, dtype=np.float64)
        self.w = np.sqrt(np.asarray(weight, dtype=np.float64))
        self.weighted = bool(np.any(self.w != 1.0))
        self.start = float(min(self.t[0], self.change[0] if self.change.size else self.t[0]))
        self.start -= 1.0

    def solve(self, params) -> tuple[np.ndarray, np.ndarray]:
        """The curve's increments for ``params`` (delay in ms, ln tau_up, ln tau_down; taus in
        s) and the weighted residuals."""
        delay, up, down = params[0] / 1e3, np.exp(params[1]), np.exp(params[2])
        s = first_order(self.t, self.change + delay, self.drive, tau_up_s=up,
                        tau_down_s=down, start_s=self.start)  # fmt: skip
        moving = s > 0.0  # the rows of a motor at rest are all zero
        b = hat_basis(s[moving], self.nodes)
        y = self.a[moving]
        if self.weighted:
            b *= self.w[moving, None]
            y = y * self.w[moving]
        gram = b.T @ b
        gram[np.diag_indices_from(gram)] += 1e-9 * (np.trace(gram) / len(gram) + 1e-30)
        try:
            r = linalg.cholesky(gram, lower=False)
            inc, _ = optimize.nnls(r, linalg.solve_triangular(r, b.T @ y, trans="T"),
                                   maxiter=50 * len(gram))  # fmt: skip
        except (linalg.LinAlgError, RuntimeError):
            inc = np.clip(np.linalg.lstsq(b, y, rcond=None)[0], 0.0, None)
        res = -self.a * self.w
        res[moving] += b @ inc
        return inc, res


def fit_envelope(t_s, amplitude, change_s, drive, nodes, *, weight=None) -> Fit:
    """Fit delay, time constants and the amplitude curve to an amplitude envelope.

    Parameters
    ----------
    t_s : array_like of float, shape (n,)
        Envelope sample times (s, the commands' clock).
    amplitude : array_like of float, shape (n,)
        The vibration's amplitude there (noise power taken off).
    change_s, drive : array_like of float, shape (m,)
        When the commanded drive changes, and to what (fractions of full drive).
    nodes : array_like of float
        Increasing drives from 0 to 1 where the amplitude curve is given (the levels
        commanded).
    weight : array_like of float, shape (n,), optional
        Least-squares weight of each sample (1).

    Returns
    -------
    Fit
    """
    weight = np.ones(np.shape(t_s)) if weight is None else weight
    problem = _Problem(t_s, amplitude, change_s, drive, nodes, weight)
    lo = [DELAY_RANGE_S[0] * 1e3, np.log(TAU_RANGE_S[0]), np.log(TAU_RANGE_S[0])]
    hi = [DELAY_RANGE_S[1] * 1e3, np.log(TAU_RANGE_S[1]), np.log(TAU_RANGE_S[1])]
    best, start = np.inf, None
    for d in _START_DELAYS_S:
        for up, down in _START_TAUS_S:
            x = np.array([d * 1e3, np.log(up), np.log(down)])
            cost = float(np.sum(problem.solve(x)[1] ** 2))
            if cost < best:
                best, start = cost, x
    found = optimize.least_squares(lambda x: problem.solve(x)[1], start, bounds=(lo, hi),
                                   diff_step=1e-4, x_scale=[1.0, 0.1, 0.1], xtol=1e-8,
                                   ftol=1e-8, max_nfev=300)  # fmt: skip
    inc, res = problem.solve(found.x)
    curve = np.concatenate([[0.0], np.cumsum(inc)])
    full = curve[-1] if curve[-1] > 0 else 1.0
    residual = float(np.sqrt(np.sum(res**2) / np.sum(problem.w**2)) / full)
    return Fit(float(found.x[0] / 1e3), float(np.exp(found.x[1])), float(np.exp(found.x[2])),
               problem.nodes.copy(), curve, residual, int(problem.t.size))  # fmt: skip
