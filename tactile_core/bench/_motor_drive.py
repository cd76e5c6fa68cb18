"""Motor-aware drive in felt terms: felt ripple, centroid lag and onset at the skin with and
without it, when the profile's motor constants are right and when they are off by x0.5 and x2;
and what the stage costs per lit tactor on the live path."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..rendering.geometry import Grid
from ..rendering.motor import MotorResponse
from ._common import GAMMA, MU, SCENES, Table, _cycling, best_time

PROFILE_TAUS_S = ((0.030, 0.060), (0.100, 0.200))
"""The profile's (spin-up, run-down) time constants of the table: the palm array's estimates,
and slow ERMs (a manufacturer's 50-180 ms spin-up)."""
MISMATCH = (0.5, 1.0, 2.0)
"""The true motors' time constants as multiples of the profile's."""
MOTOR_DRIVE_METHODS = ("AS", "IM", "CT")

BOUND_RIPPLE = 0.25
"""Motor-aware drive's felt ripple is never more than this above plain drive's (ratio units),
for the methods, shapes, motors and mismatches of :func:`motor_drive_table`."""
BOUND_LAG_MM = 1.5
"""Its felt centroid error is never more than this many mm above plain drive's."""
BOUND_ONSET_MS = 0.5
"""Its mean onset error at the skin is never more than this many ms above plain drive's."""


@dataclass(frozen=True)
class FeltEffect:
    """What the skin gets of one trace through the true motors (reference participant).

    Attributes
    ----------
    ripple : float
        Felt ripple, ``max M / min M`` after the motors' spin-up
        (:attr:`~tactile_core.rendering.percept.Percept.ripple`).
    lag_mm : float
        Felt centroid's mean distance from the point, mm
        (:attr:`~tactile_core.rendering.percept.Percept.mean_error_mm`).
    onset_ms, worst_onset_ms : float
        Mean and largest ``|felt onset - intended onset|`` over the tactors felt during their
        first activation, ms (NaN if none).
    missed : int
        Tactors whose first activation is not felt at all (the motor never reached the
        threshold before the drive went away).
    """

    ripple: float
    lag_mm: float
    onset_ms: float
    worst_onset_ms: float
    missed: int


def _first_activation(drive: np.ndarray, time_s: np.ndarray, level: float):
    """Per tactor: start and end (s) of the first stretch above ``level`` (inf if none)."""
    above = drive > level
    seen = above.any(axis=0)
    on = np.full(drive.shape[1], np.inf)
    off = np.full(drive.shape[1], np.inf)
    first = np.argmax(above, axis=0)
    on[seen] = time_s[first[seen]]
    for i in np.flatnonzero(seen):
        after = np.flatnonzero(~above[first[i] :, i])
        off[i] = time_s[first[i] + after[0]] if after.size else time_s[-1]
    return on, off


def felt_effect(shape, method: str, true: MotorResponse, compensate: MotorResponse | None, *,
                rate_hz: float = 300.0, levels: int = 23, mu: float = MU, gamma: float = GAMMA,
                grid: Grid | None = None, duration_s: float = 2.0) -> FeltEffect:  # fmt: skip
    """The felt effect of one trace sent at ``rate_hz`` and ``levels``, with motor-aware drive
    for ``compensate`` (None: plain drive), felt through the motors ``true``.

    Onsets are against the intended drive in continuous time (the corrected trace sampled
    every 50 us): a tactor's intended onset is when it first rises above the reference
    participant's threshold, its felt onset when its effective drive does
    (:meth:`MotorResponse.onsets_s <tactile_core.rendering.motor.MotorResponse.onsets_s>`,
    exact within the frame), from motors at rest at the start of the trace.
    """
    from ..rendering.percept import REFERENCE, percept_of, trace_drive

    grid = grid or Grid()
    th = REFERENCE.threshold
    kw = dict(grid=grid, duration_s=duration_s, rate_hz=rate_hz, levels=levels)
    felt = trace_drive(shape, method, mu, gamma, motor=true, compensate=compensate, **kw)
    percept = percept_of(felt, th, REFERENCE.exponent, grid=grid)
    sent = trace_drive(shape, method, mu, gamma, compensate=compensate, **kw).drive
    n = len(sent)
    onset = true.onsets_s(sent.reshape(n, grid.size), rate_hz, th)
    samples = round(duration_s / 50e-6) + 1
    ideal = trace_drive(shape, method, mu, gamma, grid=grid, samples=samples).drive
    on, off = _first_activation(ideal.reshape(samples, grid.size),
                                np.linspace(0.0, duration_s, samples), th)  # fmt: skip
    wanted = np.isfinite(on)
    felt_in_time = wanted & (onset <= off + 1.0 / rate_hz)
    error = np.abs(onset[felt_in_time] - on[felt_in_time]) * 1e3
    return FeltEffect(
        percept.ripple,
        percept.mean_error_mm,
        float(error.mean()) if error.size else float("nan"),
        float(error.max()) if error.size else float("nan"),
        int((wanted & ~felt_in_time).sum()),
    )


def motor_drive_rows(shapes=("line", "circle"), methods=MOTOR_DRIVE_METHODS,
                     taus=PROFILE_TAUS_S, mismatch=MISMATCH, **kw) -> list:  # fmt: skip
    """``[(shape, method, profile MotorResponse, factor, plain FeltEffect, motor-aware
    FeltEffect), ...]`` over every combination (``kw`` to :func:`felt_effect`)."""
    rows = []
    for up, down in taus:
        profile = MotorResponse(up, down)
        for factor in mismatch:
            true = MotorResponse(up * factor, down * factor)
            for name in shapes:
                for method in methods:
                    plain = felt_effect(SCENES[name], method, true, None, **kw)
                    aware = felt_effect(SCENES[name], method, true, profile, **kw)
                    rows.append((name, method, profile, factor, plain, aware))
    return rows


def _pair(a: float, b: float, digits: int) -> str:
    return f"{a:.{digits}f} → {b:.{digits}f}"


def motor_drive_table(rate_hz: float = 300.0, levels: int = 23) -> Table:
    """Felt ripple, centroid lag and onset at the skin, plain → motor-aware drive, for AS, IM
    and CT on the Experiment 1 line and circle, at the profile's motor constants 30/60 and
    100/200 ms and with true motors x0.5 and x2 the profile's."""
    rows = []
    worst = [0.0, 0.0, 0.0]
    for name, method, profile, factor, plain, aware in motor_drive_rows(rate_hz=rate_hz,
                                                                        levels=levels):  # fmt: skip
        up, down = profile.tau_up_s * 1e3, profile.tau_down_s * 1e3
        rows.append([
            name, method, f"{up:g}/{down:g}", f"x{factor:g} ({up * factor:g}/{down * factor:g})",
            _pair(plain.ripple, aware.ripple, 3), _pair(plain.lag_mm, aware.lag_mm, 2),
            f"{_pair(plain.onset_ms, aware.onset_ms, 1)} (worst {plain.worst_onset_ms:.1f} → "
            f"{aware.worst_onset_ms:.1f})", f"{plain.missed} → {aware.missed}",
        ])  # fmt: skip
        worst = [max(worst[0], aware.ripple - plain.ripple),
                 max(worst[1], aware.lag_mm - plain.lag_mm),
                 max(worst[2], aware.onset_ms - plain.onset_ms)]  # fmt: skip
    headers = ["shape", "method", "profile tau up/down ms", "true motor", "felt ripple",
               "centroid lag mm", "onset error ms mean", "first activations missed"]  # fmt: skip
    notes = (
        f"Plain → motor-aware drive (`--compensate-motors`), the Experiment 1 line and circle "
        f"(2 s, mu = {MU}, gamma = {GAMMA}) point-sampled at {rate_hz:g} Hz and rounded to "
        f"{levels} levels, the motor-aware stage compensating the profile's motors and the "
        "frames felt through the true ones (first order, from rest), by the reference "
        "participant (TH 0.2, K 1). Felt ripple: max / min of the felt intensity, the first "
        "3 tau_up (of the true motor) left out; centroid lag: the felt centroid's mean distance "
        "from the point (18 mm pitch); onset: |felt - intended| for each tactor's first "
        "activation, the intended onset from the corrected trace every 50 us, the felt one the "
        "effective drive crossing TH (exact within the frame); missed: first activations the "
        "motor never brought above TH. Largest increase over plain drive in this table: "
        f"ripple {worst[0]:+.3f}, lag {worst[1]:+.2f} mm, onset {worst[2]:+.1f} ms (bounds "
        f"{BOUND_RIPPLE:g}, {BOUND_LAG_MM:g} mm, {BOUND_ONSET_MS:g} ms)."
    )
    return Table("Motor-aware drive, felt", headers, rows, notes)


def motor_drive_cost_table(rate_hz: float = 300.0) -> Table:
    """What motor-aware drive costs on the live path: the stage
    (:class:`~tactile_core.rendering.motor_drive.LiveMotorDrive`) per frame and per lit tactor,
    on the frames the stream computes for the Experiment 1 line and circle."""
    from ..device.profile import default_profile
    from ..rendering.motor_drive import LiveMotorDrive
    from ..rendering.scene import Scene

    profile = default_profile()
    rows = []
    for name in ("line", "circle"):
        for method in ("CT", "AS", "IM", "GS"):
            live = Scene(SCENES[name], method, MU, GAMMA, rate_hz=rate_hz).live(Grid(), rate_hz)
            live.precompute()
            cycle = live.cycle
            entries = [live.entries(k) for k in range(cycle)]
            lit = sum(len(e) for e in entries) / cycle
            stage = LiveMotorDrive(profile.motor, profile.layout.size)
            stage.set_rate(rate_hz)
            carried = []
            for k in range(cycle):
                stage.frame(entries[k])
                carried.append(len(stage.state))
            frame = _cycling(lambda k, stage=stage, entries=entries: stage.frame(entries[k]), cycle)
            stage_s = best_time(frame)
            rows.append([name, method, f"{lit:.2f}", f"{np.mean(carried):.2f}",
                         f"{stage_s * 1e6:.2f}", f"{stage_s / lit * 1e6:.2f}"])  # fmt: skip
    headers = ["shape", "method", "lit per frame", "carrying state", "us per frame",
               "us per lit tactor"]  # fmt: skip
    notes = (
        f"The Experiment 1 shapes at {rate_hz:g} Hz (mu = {MU}, gamma = {GAMMA}, the palm "
        "array's motors, 30/60 ms): the stage's work on each frame's lit tactors as the output "
        "thread hands them over (served from the precomputed cycle, so that only the stage is "
        "timed), minimum of 7 runs. `carrying state`: tactors lit or still running down (above "
        "1e-4 of full drive) after a frame, the ones a frame updates. Budget: 2 us per lit "
        "tactor."
    )
    return Table("Motor-aware drive, cost on the live path", headers, rows, notes)
