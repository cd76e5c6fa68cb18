"""Motor dynamics: a first-order response per tactor, the low-pass an ERM motor puts on its drive.

A vibrating DC (ERM) motor takes tens of milliseconds to spin up and to run down, against the
3.3 ms frames of a 300 Hz stream. :class:`MotorResponse` models each tactor's *effective drive*
``s`` (the steady drive that would give the vibration it has now) as a first-order lag of the
drive ``d`` it gets, with one time constant while it speeds up and another while it slows down:

    ds/dt = (d - s) / tau,   tau = tau_up if d > s else tau_down

Frames hold their drive for one frame period, so the lag is solved exactly per frame: from
``s0`` under a held ``d`` for ``dt``, ``s(dt) = d + (s0 - d) exp(-dt / tau)`` and its mean over
the frame is ``d + (s0 - d) (tau / dt) (1 - exp(-dt / tau))``. The felt magnitude is then taken
of ``s`` (:func:`tactile_core.rendering.percept.felt_magnitude`).

Only the tactors that are lit at some frame are simulated (a tactor that is never driven stays
at rest); a tactor decays from its last lit frame on until the sequence ends. The device layer
builds a :class:`MotorResponse` from a device profile's ``motor`` field; the rendering layer
takes it as a value (it never reads profiles).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._shared import validate as _validate

PALM_TAU_UP_S = 0.030
"""Spin-up time constant assumed for the palm array's motors (an estimate, not a measurement:
small ERMs take a few tens of milliseconds to reach their vibration)."""
PALM_TAU_DOWN_S = 0.060
"""Run-down time constant assumed for the palm array's motors (an estimate: an ERM without
active braking coasts down more slowly than it spins up)."""


def _taus(name: str, value, size: int | None) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(value, dtype=np.float64))
    if arr.ndim != 1 or arr.size == 0 or not np.isfinite(arr).all() or (arr < 0).any():
        raise ValueError(f"{name} must be a time constant >= 0 s (or one per tactor), got "
                         f"{_validate.shown(value)}")  # fmt: skip
    if (arr > 10.0).any():
        raise ValueError(f"{name} must be at most 10 s, got {_validate.shown(value)}")
    if size is not None and arr.size not in (1, size):
        raise ValueError(f"{name} must hold 1 or {size} values, got {arr.size}")
    return arr


@dataclass(frozen=True)
class MotorResponse:
    """First-order motor response: spin-up and run-down time constants, per tactor or shared.

    Parameters
    ----------
    tau_up_s, tau_down_s : float or tuple of float
        Time constants in seconds while the drive is above (below) the effective drive: one
        value for every tactor, or one per tactor in flat cell order (``row * cols + col``).
        0 is an ideal motor (no lag).
    note : str
        Where the values come from (the palm array's are estimates).
    """

    tau_up_s: float | tuple = PALM_TAU_UP_S
    tau_down_s: float | tuple = PALM_TAU_DOWN_S
    note: str = ""

    def __post_init__(self):
        for name in ("tau_up_s", "tau_down_s"):
            arr = _taus(name, getattr(self, name), None)
            value = float(arr[0]) if arr.size == 1 else tuple(arr.tolist())
            object.__setattr__(self, name, value)

    @property
    def measured(self) -> bool:
        """True when the constants were measured (``tactile measure`` writes a note that starts
        with "measured"); False for estimates."""
        return self.note.strip().lower().startswith("measured")

    @property
    def source(self) -> str:
        """``"measured"`` or ``"estimate"``: what the tables and views say of the constants."""
        return "measured" if self.measured else "estimate"

    def describe(self) -> str:
        """``"spin-up 30 ms, run-down 60 ms (estimate)"``; per-tactor constants as their range
        (``"spin-up 28-33 ms"``), measured ones with the date of their note."""

        def ms(value) -> str:
            v = np.atleast_1d(np.asarray(value, dtype=np.float64)) * 1e3
            lo, hi = float(v.min()), float(v.max())
            return f"{lo:.3g} ms" if hi - lo < 0.05 else f"{lo:.3g}-{hi:.3g} ms"

        what = self.source
        if self.measured:
            words = self.note.split()
            when = words[1] if len(words) > 1 and words[1][:1].isdigit() else ""
            what = f"measured {when}".strip()
        return f"spin-up {ms(self.tau_up_s)}, run-down {ms(self.tau_down_s)} ({what})"

    def taus(self, size: int) -> tuple[np.ndarray, np.ndarray]:
        """``(tau_up, tau_down)``, each of shape ``(size,)``, in seconds."""
        up = _taus("tau_up_s", self.tau_up_s, size)
        down = _taus("tau_down_s", self.tau_down_s, size)
        return np.broadcast_to(up, (size,)), np.broadcast_to(down, (size,))

    def select(self, cells) -> MotorResponse:
        """The motors of ``cells`` (flat indices), in that order (itself if shared)."""
        if isinstance(self.tau_up_s, float) and isinstance(self.tau_down_s, float):
            return self
        cells = np.asarray(cells, dtype=np.intp)
        size = int(cells.max()) + 1 if cells.size else 1
        up, down = self.taus(max(size, _count(self)))
        return MotorResponse(tuple(up[cells].tolist()), tuple(down[cells].tolist()), self.note)

    def effective(self, drive, rate_hz: float, state=None) -> tuple[np.ndarray, np.ndarray]:
        """The effective drive of each tactor, frame by frame.

        Parameters
        ----------
        drive : array_like of float, shape (n, size)
            Drive fractions in [0, 1], one frame of ``1 / rate_hz`` s per row, held for it.
        rate_hz : float
            Frames per second.
        state : array_like of float, shape (size,), optional
            Effective drive at the start (at rest, 0, by default).

        Returns
        -------
        mean : ndarray of float64, shape (n, size)
            The effective drive averaged over each frame.
        end : ndarray of float64, shape (size,)
            The effective drive at the end of the last frame.
        """
        d = np.asarray(drive, dtype=np.float64)
        if d.ndim != 2:
            raise ValueError(f"drive must be frames x tactors, got shape {d.shape}")
        rate_hz = _validate.positive("rate_hz", rate_hz)
        n, size = d.shape
        s0 = np.zeros(size) if state is None else np.asarray(state, dtype=np.float64).copy()
        if s0.shape != (size,):
            raise ValueError(f"state must have shape ({size},), got {s0.shape}")
        mean = np.zeros((n, size))
        end = s0.copy()
        # Only tactors lit at some frame, or still running down from the start, are simulated.
        cols = np.flatnonzero((d > 0.0).any(axis=0) | (s0 > 0.0))
        if cols.size == 0 or n == 0:
            return mean, end
        dt = 1.0 / rate_hz
        up, down = (t[cols] for t in self.taus(size))
        a_up, a_down = _decay(up, dt), _decay(down, dt)
        m_up, m_down = _mean_factor(up, dt), _mean_factor(down, dt)
        s = s0[cols]
        sub = d[:, cols]
        out = np.empty_like(sub)
        for k in range(n):
            target = sub[k]
            rising = target > s
            gap = s - target
            out[k] = target + gap * np.where(rising, m_up, m_down)
            s = target + gap * np.where(rising, a_up, a_down)
        mean[:, cols] = out
        end[cols] = s
        return mean, end

    def onsets_s(self, drive, rate_hz: float, level: float) -> np.ndarray:
        """When each tactor's effective drive first rises above ``level``, from rest.

        Parameters
        ----------
        drive : array_like of float, shape (n, size)
            Drive fractions in [0, 1], one frame of ``1 / rate_hz`` s per row, held for it.
        rate_hz : float
            Frames per second.
        level : float
            Effective drive to cross, in [0, 1) (a participant's threshold: the felt onset).

        Returns
        -------
        ndarray of float64, shape (size,)
            Seconds from the start of the first frame, solved exactly within the frame
            (``t = tau_up ln((d - s0) / (d - level))`` into a frame that starts at ``s0`` under
            the drive ``d``); ``inf`` for a tactor whose effective drive never gets above it.
        """
        d = np.asarray(drive, dtype=np.float64)
        if d.ndim != 2:
            raise ValueError(f"drive must be frames x tactors, got shape {d.shape}")
        rate_hz = _validate.positive("rate_hz", rate_hz)
        level = _validate.in_range("level", level, 0.0, 0.999)
        n, size = d.shape
        onset = np.full(size, np.inf)
        cols = np.flatnonzero((d > level).any(axis=0))
        if cols.size == 0:
            return onset
        dt = 1.0 / rate_hz
        up, down = (t[cols] for t in self.taus(size))
        a_up, a_down = _decay(up, dt), _decay(down, dt)
        s = np.zeros(cols.size)
        found = np.full(cols.size, np.inf)
        for k in range(n):
            target = d[k, cols]
            end = target + (s - target) * np.where(target > s, a_up, a_down)
            new = np.isinf(found) & (end > level) & (target > level)
            if new.any():
                gap = target[new] - s[new]
                with np.errstate(divide="ignore", invalid="ignore"):
                    into = np.where(s[new] > level, 0.0,
                                    up[new] * np.log(gap / (target[new] - level)))  # fmt: skip
                found[new] = k * dt + np.minimum(np.nan_to_num(into), dt)
            s = end
        onset[cols] = found
        return onset


def _count(motor: MotorResponse) -> int:
    """How many tactors per-tactor time constants describe (1 when shared)."""
    return max(len(v) if isinstance(v, tuple) else 1 for v in (motor.tau_up_s, motor.tau_down_s))


def _decay(tau: np.ndarray, dt: float) -> np.ndarray:
    """``exp(-dt / tau)``: what is left of a gap after one frame (0 for an ideal motor)."""
    with np.errstate(divide="ignore"):
        return np.where(tau > 0.0, np.exp(-dt / np.where(tau > 0.0, tau, 1.0)), 0.0)


def _mean_factor(tau: np.ndarray, dt: float) -> np.ndarray:
    """``(tau / dt) (1 - exp(-dt / tau))``: the share of a gap left on average over a frame."""
    safe = np.where(tau > 0.0, tau, 1.0)
    return np.where(tau > 0.0, safe / dt * -np.expm1(-dt / safe), 0.0)


PALM_MOTOR = MotorResponse(PALM_TAU_UP_S, PALM_TAU_DOWN_S, "estimates, not measured")
"""The palm array's assumed motor response (see :data:`PALM_TAU_UP_S`)."""
