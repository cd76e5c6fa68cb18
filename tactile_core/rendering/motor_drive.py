"""Motor-aware drive: pre-compensate each lit tactor's first-order motor.

An ERM motor is a first-order lag between the drive ``d`` it gets and its *effective drive*
``s`` (:mod:`tactile_core.rendering.motor`): held for one frame of ``dt`` seconds from ``s0``,

    s(dt) = d + (s0 - d) e,   e = exp(-dt / tau),   tau = tau_up if d > s0 else tau_down.

Motor-aware drive inverts that over one frame: to bring the effective drive from ``s0`` to the
intended drive ``r`` at the end of the frame it sends

    d = (r - s0 e) / (1 - e),   clamped to [0, 1],

which is *overdrive* while the motor spins up (``d > r``) and *drive off*, or less than ``r``,
while it runs down. The clamp is the drive range: a motor already asked for full drive cannot be
overdriven (CT and MM light their tactors at 1), and a motor running down can only coast, since
the wire carries levels ``0 .. levels - 1`` and no braking (reverse) drive. The state is then
re-derived from the clamped drive with the exact per-frame solution above, so a clamped frame is
made up in the frames after it. For an ideal motor (``tau = 0``, ``e = 0``) the drive is left as
it is; a tactor never lit stays at exactly 0; a tactor that goes dark gets 0 while its motor runs
down.

**Why the frame's end, not its mean.** The felt model averages the effective drive over a frame
(:meth:`MotorResponse.effective`). Aiming that mean at ``r`` instead (``d = (r - s0 m) / (1 -
m)``, ``m = (tau / dt)(1 - e)`` the share of the gap left on average) overshoots at the frame's
end, and the next frame must undershoot: the error is multiplied by ``e - m (1 - e) / (1 - m)``
per frame, about ``-1 + dt / (3 tau)`` for ``dt << tau`` (-0.99 at 300 Hz and 30 ms), a ringing at
half the frame rate that dies out over seconds. Aiming at the end value is dead-beat: unclamped,
the effective drive is on target at the end of the first frame and stays there; its mean over
that one frame lags by about half a frame, as any held frame does.

**What it is computed from.** The state is derived from the clamped drive, before quantisation
and calibration, not from the level sent: deriving it from the rounded level would make the
stage chase the rounding error with the gain ``1 / (1 - e)`` (9.5 at 300 Hz and 30 ms), a limit
cycle between levels. Only lit tactors and those still running down carry state; a tactor whose
effective drive has run down below :data:`REST` is at rest again and forgotten.

:func:`motor_drive` compensates frames in batch (a whole trace); :class:`LiveMotorDrive`
compensates the live path frame by frame from the lit tactors only.
"""

from __future__ import annotations

import math

import numpy as np

from .._shared import validate as _validate
from .motor import MotorResponse

REST = 1e-4
"""Effective drive (fraction of full drive) below which a dark tactor's motor counts as at rest:
its state is dropped, and it is driven as a motor at rest when it is lit again."""


def _gains(tau: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """``(e, 1 / (1 - e))`` per tactor, ``e = exp(-dt / tau)`` (``(0, 1)`` for an ideal
    motor)."""
    with np.errstate(divide="ignore", over="ignore"):
        e = np.where(tau > 0.0, np.exp(-dt / np.where(tau > 0.0, tau, 1.0)), 0.0)
        gain = np.where(tau > 0.0, -1.0 / np.expm1(-dt / np.where(tau > 0.0, tau, 1.0)), 1.0)
    return e, gain


def motor_drive(drive, motor: MotorResponse, rate_hz: float, *,
                state=None) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The motor-aware drive of frames: each lit tactor's motor pre-compensated.

    Parameters
    ----------
    drive : array_like of float, shape (n, ...)
        The intended drive (corrected intensities) in [0, 1], one frame of ``1 / rate_hz`` s per
        row, held for it; each frame ``(rows, cols)`` on a grid or ``(size,)`` in flat cell
        order.
    motor : MotorResponse
        The motors to compensate (a device profile's ``motor``).
    rate_hz : float
        Frames per second.
    state : array_like of float, shape (size,), optional
        Effective drive of each motor at the start (at rest, 0, by default).

    Returns
    -------
    drive : ndarray of float64, same shape as ``drive``
        What to send instead, in [0, 1]; exactly 0 for a tactor never lit.
    end : ndarray of float64, shape (size,)
        The effective drive at the end of the last frame (the motors fed the returned drive).

    Notes
    -----
    See the module notes: ``d = (r - s0 e) / (1 - e)`` per frame, clamped to [0, 1], the state
    then advanced from the clamped drive as :meth:`MotorResponse.effective` does.

    Examples
    --------
    One tactor stepped to 0.5 at 300 Hz with a 30 ms spin-up: full drive (the exact inverse,
    4.75 in the first frame, is clamped) until the motor can reach 0.5 within a frame, then the
    drive that holds it there, and nothing while it runs down.

    >>> step = [[0.5]] * 9 + [[0.0]]
    >>> d, end = motor_drive(step, MotorResponse(0.03, 0.06), 300)
    >>> d.round(3).ravel().tolist()
    [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.614, 0.5, 0.5, 0.0]
    """
    frames = np.asarray(drive, dtype=np.float64)
    if frames.ndim < 2:
        raise ValueError(f"drive must be frames x tactors, got shape {frames.shape}")
    bad = ~np.isfinite(frames) | (frames < -1e-12) | (frames > 1.0 + 1e-12)
    if bad.any():
        raise ValueError(f"drive must hold fractions of full drive in [0, 1], got "
                         f"{_validate.shown(float(frames[bad][0]))}")  # fmt: skip
    frames = np.clip(frames, 0.0, 1.0)  # (rounding by a few ulps either side)
    if not isinstance(motor, MotorResponse):
        raise ValueError(f"motor must be a MotorResponse, got {_validate.shown(motor)}")
    rate_hz = _validate.positive("rate_hz", rate_hz)
    n = len(frames)
    flat = frames.reshape(n, -1)
    size = flat.shape[1]
    s0 = np.zeros(size) if state is None else np.asarray(state, dtype=np.float64).copy()
    if s0.shape != (size,) or not np.isfinite(s0).all() or (s0 < 0).any() or (s0 > 1).any():
        raise ValueError(f"state must hold {size} effective drives in [0, 1], got "
                         f"{_validate.shown(state)}")  # fmt: skip
    out = np.zeros_like(flat)
    end = s0.copy()
    cols = np.flatnonzero((flat > 0.0).any(axis=0) | (s0 > 0.0))
    if cols.size == 0 or n == 0:
        return out.reshape(frames.shape), end
    dt = 1.0 / rate_hz
    up, down = (t[cols] for t in motor.taus(size))
    e_up, g_up = _gains(up, dt)
    e_down, g_down = _gains(down, dt)
    s = s0[cols]
    sub = flat[:, cols]
    sent = np.empty_like(sub)
    for k in range(n):
        r = sub[k]
        rising = r > s
        d = np.clip((r - s * np.where(rising, e_up, e_down)) * np.where(rising, g_up, g_down),
                    0.0, 1.0)  # fmt: skip
        sent[k] = d
        s = d + (s - d) * np.where(d > s, e_up, e_down)
        s[(r <= 0.0) & (s <= REST)] = 0.0  # run down: at rest again, as the live path has it
    out[:, cols] = sent
    end[cols] = s
    return out.reshape(frames.shape), end


class LiveMotorDrive:
    """Motor-aware drive on the live path: one frame at a time, from the lit tactors only.

    The state is a dict of the tactors that are lit or still running down (their effective
    drive at the end of the last frame); a frame costs a few arithmetic operations per such
    tactor and nothing for the others.

    Parameters
    ----------
    motor : MotorResponse
        The motors to compensate, shared or one pair of constants per tactor.
    size : int
        Tactors (flat cell indices ``0 .. size - 1``).
    """

    def __init__(self, motor: MotorResponse, size: int):
        if not isinstance(motor, MotorResponse):
            raise ValueError(f"motor must be a MotorResponse, got {_validate.shown(motor)}")
        self.motor = motor
        self.size = _validate.integer("size", size, 1)
        self.state: dict[int, float] = {}
        """``{cell: effective drive}`` at the end of the last frame, lit or running down."""
        self._held: list = []  # (cell, drive) of the last frame
        self._rate = None
        self._tables = None
        self._taus = motor.taus(self.size)

    def set_rate(self, rate_hz: float) -> None:
        """Frames of ``1 / rate_hz`` s from now on (the state carries over)."""
        if rate_hz == self._rate:
            return
        rate_hz = _validate.positive("rate_hz", rate_hz)
        up, down = self._taus
        e_up, g_up = _gains(up, 1.0 / rate_hz)
        e_down, g_down = _gains(down, 1.0 / rate_hz)
        self._tables = tuple(x.tolist() for x in (e_up, g_up, e_down, g_down))
        self._rate = rate_hz

    def reset(self) -> None:
        """Every motor at rest (the stage was off, so its state is unknown)."""
        self.state, self._held = {}, []

    def frame(self, entries, held_frames: int = 1) -> list:
        """The drive of one frame.

        Parameters
        ----------
        entries : iterable of (int, float)
            ``(cell, intended drive)`` of the lit tactors (the corrected intensities).
        held_frames : int
            How many frame periods the last frame's drive was held before this one (1; more
            after deadlines the stream skipped).

        Returns
        -------
        list of (int, float)
            ``(cell, drive)`` of the same tactors, in the same order, in [0, 1].
        """
        if self._tables is None:
            raise ValueError("set_rate first: the frame's length is not known")
        if held_frames > 1:
            self._hold(held_frames - 1)
        e_up, g_up, e_down, g_down = self._tables
        state = self.state
        new = {}
        out = []
        for cell, r in entries:
            s = state.pop(cell, 0.0)
            if r > s:
                d = (r - s * e_up[cell]) * g_up[cell]
                if d > 1.0:
                    d = 1.0
                new[cell] = d + (s - d) * e_up[cell]
            elif r < s:
                d = (r - s * e_down[cell]) * g_down[cell]
                if d < 0.0:
                    d = 0.0
                new[cell] = d + (s - d) * e_down[cell]
            else:
                d = r
                new[cell] = s
            out.append((cell, d))
        for cell, s in state.items():  # dark now: driven 0 while it runs down
            s *= e_down[cell]
            if s > REST:
                new[cell] = s
        self.state = new
        self._held = out
        return out

    def _hold(self, frames: int) -> None:
        """The last frame's drive held ``frames`` periods more (deadlines skipped)."""
        e_up, _, e_down, _ = self._tables
        held = dict(self._held)
        for cell, s in list(self.state.items()):
            d = held.get(cell, 0.0)
            e = e_up[cell] if d > s else e_down[cell]
            self.state[cell] = d + (s - d) * e**frames
        self._drop_rest()

    def coast(self, seconds: float) -> None:
        """Every motor driven 0 for ``seconds`` (the stream paused or idle)."""
        if seconds <= 0.0:
            return
        _, down = self._taus
        for cell, s in list(self.state.items()):
            tau = down[cell]
            self.state[cell] = s * math.exp(-seconds / tau) if tau > 0.0 else 0.0
        self._held = []
        self._drop_rest()

    def _drop_rest(self) -> None:
        self.state = {cell: s for cell, s in self.state.items() if s > REST}
