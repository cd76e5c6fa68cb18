"""Table 2, speed against accuracy: streamed frames at several rates and filters against a
continuous reference (drive energy and onset per tactor, with and without quantisation)."""

from __future__ import annotations

import numpy as np

from ..rendering.correction import Dither, quantize
from ..rendering.geometry import Grid
from ..rendering.methods import METHOD_NAMES
from ..rendering.trace import LiveFrames, Sampling, Trace, render_frames
from ._common import FILTERS, GAMMA, MU, RATES_HZ, SCENES, Table, _cycling, best_time


def _reference(trace: Trace, method: str, mu: float, gamma: float, step_s: float, grid: Grid):
    """Energy (s) and onset (s) per tactor over one period, from a very fine point sampling."""
    n = round(trace.period_s / step_s)
    energy = np.zeros(grid.size)
    onset = np.full(grid.size, np.inf)
    chunk = 50_000
    sampling = Sampling(1.0 / step_s, "point")
    for first in range(0, n, chunk):
        count = min(chunk, n - first)
        start, frames = render_frames(
            trace,
            method,
            sampling=sampling,
            mu=mu,
            gamma=gamma,
            grid=grid,
            n_frames=count,
            first_frame=first,
        )
        flat = frames.reshape(count, grid.size)
        energy += flat.sum(axis=0) * step_s
        on = flat > 0
        seen = on.any(axis=0) & np.isinf(onset)
        onset[seen] = start[np.argmax(on[:, seen], axis=0)]
    return energy, onset


MOTOR_STEP_S = 1e-4
"""Step of the motor reference: the continuous drive through the motors, every 0.1 ms."""


def _motor_reference(trace, method, mu, gamma, grid, motor):
    """The continuous drive of three periods through the motors, as a cumulative integral
    ``(time_s, integral)`` per tactor (shape (n + 1,), (n + 1, size)), from rest (the first
    period is the warm-up :func:`_motor_errors` leaves out)."""
    n = round(3 * trace.period_s / MOTOR_STEP_S)
    _, frames = render_frames(trace, method, sampling=Sampling(1.0 / MOTOR_STEP_S, "point"),
                              mu=mu, gamma=gamma, grid=grid, n_frames=n)  # fmt: skip
    mean, _ = motor.effective(frames.reshape(n, grid.size), 1.0 / MOTOR_STEP_S)
    integral = np.vstack([np.zeros(grid.size), np.cumsum(mean, axis=0) * MOTOR_STEP_S])
    return np.arange(n + 1) * MOTOR_STEP_S, integral


def _motor_errors(frames, rate_hz, phase_s, grid, motor, reference, warmup_s):
    """Per frame and tactor, |streamed - continuous| of the effective drive through the motors,
    each averaged over the frame, over the frames where either is above 1% (lit or running
    down), in steady state: frames starting before ``warmup_s`` are left out.

    Both motors start at rest, the reference at t = 0 and the streamed one at its first frame,
    ``phase_s`` later: over the first frames the streamed motor lags by that start alone (a
    random phase up to a frame), which is not an error of the frame rate. One period of warm-up
    (the 0.5 s pause runs every motor down) makes both start each period alike.
    """
    n = len(frames)
    mean, _ = motor.effective(frames.reshape(n, grid.size), rate_hz)
    time_s, integral = reference
    edges = np.arange(n + 1) / rate_hz + phase_s
    keep = (edges[1:] <= time_s[-1]) & (edges[:-1] >= warmup_s)
    at = np.column_stack([np.interp(edges, time_s, integral[:, i]) for i in range(grid.size)])
    ref = np.diff(at, axis=0) * rate_hz
    mean, ref = mean[keep], ref[keep]
    active = (mean > 0.01) | (ref > 0.01)
    return np.abs(mean - ref)[active]


def _frame_metrics(frames, rate_hz, period_s, periods, grid, phase_s, ref_onset):
    """Energy per period and onset errors (s, per period and tactor) of streamed frames.

    Frame ``k`` starts at ``k / rate + phase_s``. A tactor's streamed onset in period ``p`` is
    the start of its first lit frame from one frame before its true onset ``ref_onset`` on (a
    point-sampled frame lights at most half a frame early, a box-filtered one less than a
    frame early).
    """
    flat = frames.reshape(len(frames), grid.size)
    energy = flat.sum(axis=0) / rate_hz / periods
    times = np.arange(len(frames)) / rate_hz + phase_s
    errors = np.full((periods, grid.size), np.nan)
    for i in np.flatnonzero(np.isfinite(ref_onset) & (ref_onset > 0)):
        on_times = times[flat[:, i] > 0]
        for p in range(periods):
            due = p * period_s + ref_onset[i]
            later = on_times[on_times >= due - 1.0 / rate_hz - 1e-9]
            if len(later):
                errors[p, i] = later[0] - due
    return energy, errors


def accuracy_table(
    rates=RATES_HZ,
    filters=FILTERS,
    step_s: float = 5e-6,
    levels: int = 23,
    quick: bool = False,
    phases: int = 8,
    seed: int = 0,
) -> Table:
    """Table 2: speed against accuracy of streamed frames, against a continuous reference.

    For each rate and filter, over the four methods on the Experiment 1 line and circle (2 s
    traces, 0.5 s pause, mu = 0.33, gamma = 0.7) and ``phases`` random phases of the trace's
    start against the frame clock: each tactor's delivered drive energy (time integral of its
    corrected intensity; no motor model) and onset time against a point sampling every
    ``step_s``, with and without quantisation to ``levels``, and the batch and live CPU cost
    per frame.
    """
    grid = Grid()
    if quick:
        step_s, phases = 2e-5, 3
    rng = np.random.default_rng(seed)
    scenes = [(n, m) for n in ("line", "circle") for m in METHOD_NAMES]
    from ..rendering.motor import PALM_MOTOR

    refs, motor_refs = {}, {}
    for name, method in scenes:
        trace = Trace(SCENES[name])
        refs[name, method] = _reference(trace, method, MU, GAMMA, step_s, grid)
        motor_refs[name, method] = _motor_reference(trace, method, MU, GAMMA, grid, PALM_MOTOR)
    rows = []
    for rate in rates:
        phase_list = rng.uniform(0.0, 1.0 / rate, phases)
        for filt, s in filters:
            sampling = Sampling(rate, filt, s)
            errs = {k: [] for k in ("e", "o", "eq", "oq", "ed", "m")}
            for name, method in scenes:
                trace = Trace(SCENES[name])
                periods = 2 if abs(trace.period_s * rate - round(trace.period_s * rate)) else 1
                n = round(periods * trace.period_s * rate)
                ref_e, ref_o = refs[name, method]
                lit = ref_e > 0
                for phase in phase_list:
                    _, frames = render_frames(
                        trace, method, sampling=sampling, mu=MU, gamma=GAMMA, grid=grid,
                        n_frames=n, phase_s=phase,
                    )  # fmt: skip
                    quantised = quantize(frames, levels) / (levels - 1)
                    _, warm = render_frames(
                        trace, method, sampling=sampling, mu=MU, gamma=GAMMA, grid=grid,
                        n_frames=n + round(trace.period_s * rate), phase_s=phase,
                    )  # fmt: skip
                    errs["m"].extend(_motor_errors(
                        quantize(warm, levels) / (levels - 1), rate, phase, grid, PALM_MOTOR,
                        motor_refs[name, method], trace.period_s))  # fmt: skip
                    dithered = Dither(grid.size, levels).frames(frames) / (levels - 1)
                    for fr, e_key, o_key in (
                        (frames, "e", "o"), (quantised, "eq", "oq"), (dithered, "ed", None),
                    ):  # fmt: skip
                        energy, onsets = _frame_metrics(
                            fr, rate, trace.period_s, periods, grid, phase, ref_o
                        )
                        errs[e_key].extend(np.abs(energy[lit] - ref_e[lit]) / ref_e[lit])
                        if o_key:
                            errs[o_key].extend(np.abs(onsets[np.isfinite(onsets)]))
            cost = best_time(
                lambda sampling=sampling: render_frames(
                    Trace(SCENES["circle"]),
                    "AS",
                    sampling=sampling,
                    mu=MU,
                    gamma=GAMMA,
                    grid=grid,
                    n_frames=750,
                ),
                repeat=3,
            )
            live = LiveFrames(Trace(SCENES["circle"]), "AS", sampling, MU, GAMMA, grid)
            live_cost = best_time(_cycling(live.compute, live.cycle), repeat=3)
            e = {k: np.array(v) * (1e3 if k[0] == "o" else 100) for k, v in errs.items()}
            rows.append(
                [
                    f"{rate:g}",
                    sampling.label,
                    f"{e['e'].mean():.3f} / {e['e'].max():.2f}",
                    f"{e['o'].mean():.2f} / {e['o'].max():.2f}",
                    f"{e['eq'].mean():.3f} / {e['eq'].max():.2f}",
                    f"{e['oq'].max():.2f}",
                    f"{e['ed'].mean():.3f} / {e['ed'].max():.2f}",
                    f"{e['m'].mean():.2f} / {e['m'].max():.1f}",
                    f"{cost / 750 * 1e6:.2f}",
                    f"{live_cost * 1e6:.1f}",
                ]
            )
    headers = [
        "frame rate Hz",
        "filter",
        "drive energy err % mean / worst",
        "onset err ms mean / worst",
        f"{levels} levels rounded: energy % mean / worst",
        f"{levels} levels rounded: onset worst ms",
        f"{levels} levels dithered: energy % mean / worst",
        f"{levels} levels rounded, through the motors: drive err % mean / worst",
        "batch us/frame",
        "live us/frame",
    ]
    notes = (
        f"Errors per tactor against a point sampling every {step_s * 1e6:g} us, pooled over "
        "CT, MM, AS and IM on the Experiment 1 line and circle (mu = 0.33, gamma = 0.7, 2 s "
        f"trace + 0.5 s pause) and over {phases} random phases of the trace's start against the "
        "frame clock (mean over tactors and phases / worst tactor in the worst phase). Drive "
        "energy: relative error of the time integral of the corrected drive intensity over one "
        "period, what the host sends (no motor model: the last error column adds one). Onset: "
        "the start of the first frame a tactor is lit in vs. when it turns on, for tactors "
        "that turn on after the trace starts. The frame rate is how often the host "
        "sends levels, not the array's PWM carrier (about 300 Hz on the paper's array). The "
        f"level columns quantise the frames to {levels} levels first, by plain rounding (the "
        "paper's pipeline) or with temporal dithering (error feedback per tactor). Through the "
        "motors: the rounded frames and the continuous drive (every 0.1 ms) each through the "
        "palm array's first-order motors (spin-up 30 ms, run-down 60 ms: estimates), the "
        "effective drive compared frame by frame in steady state, after one period of warm-up "
        "(mean over frames where either is above 1% of full drive / worst), in % of full "
        "drive. Costs: AS on the circle, batch `render_frames` per frame and the scalar live "
        "path per frame."
    )
    return Table("Speed against accuracy", headers, rows, notes)
