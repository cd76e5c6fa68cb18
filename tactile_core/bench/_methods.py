"""The methods side by side: predicted percept over a range of participants, from what is sent
and through the motors, each method's largest jump, and its batch and live cost; and which
method wins for which participant."""

from __future__ import annotations

import numpy as np

from ..rendering.geometry import Grid
from ..rendering.trace import LiveFrames, Sampling, Trace
from ._common import GAMMA, MU, Table, _cycling, best_time

VARIANTS = ("RO:curve=linear", "PK:blend=0.2")
"""Specs shown beside the registered methods: Syntacts' own roll-off, PK without its jumps."""


def _shapes():
    from ..experiments.runners import Experiment1

    return (("line", Experiment1.LINE), ("circle", Experiment1.CIRCLE))


def _ranges(samples: int, methods, motor, rate_hz: float = 300.0, levels: int = 23) -> dict:
    """``{(shape, method): PerceptRange}`` with each method's own correction."""
    from ..rendering.percept import predict_range

    return {(name, m): predict_range(shape, m, MU, GAMMA, samples=samples, rate_hz=rate_hz,
                                     levels=levels, motor=motor)
            for name, shape in _shapes() for m in methods}  # fmt: skip


def methods_table(samples: int = 2001, ranges: dict | None = None) -> Table:
    """The methods side by side on the Experiment 1 line and circle.

    For the reference participant (:data:`~tactile_core.rendering.percept.REFERENCE`) the felt
    ripple in continuous time, as sent (300 Hz, 23 levels) and through the palm array's motors,
    and the felt centroid's mean error; the ripple's range over the 25 participants of
    :func:`~tactile_core.rendering.percept.participant_grid` through the motors; the largest
    jump of one tactor's intensity (:func:`~tactile_core.rendering.jumps.largest_jump`), raw and
    after the method's own correction; the most tactors lit; batch and live cost.
    """
    from ..rendering.jumps import largest_jump
    from ..rendering.methods import get_method, method_names
    from ..rendering.motor import PALM_MOTOR
    from ..rendering.percept import REFERENCE, participant_grid
    from ..rendering.rasterize import render

    grid = Grid()
    methods = [*method_names(), *VARIANTS]
    if ranges is None:
        ranges = _ranges(samples, methods, PALM_MOTOR)
    jumps = {}
    for m in methods:
        own = get_method(m).own_correction(MU, GAMMA)
        jumps[m] = (largest_jump(m, grid=grid), largest_jump(m, *own, grid=grid))
    rows = []
    for name, shape in _shapes():
        trace = Trace(shape)
        t = np.linspace(0.0, 1.0, 20_000)
        for m in methods:
            method = get_method(m)
            mu, gamma = method.own_correction(MU, GAMMA)
            got = ranges[name, m]
            cont, sent, felt = (got.at(s, REFERENCE) for s in ("continuous", "sent", "felt"))
            batch = best_time(lambda m=m, s=shape, t=t: render(s, m, t, grid=grid)) / t.size
            live = LiveFrames(trace, m, Sampling(300.0, "point", 1), mu, gamma, grid)
            scalar = best_time(_cycling(live.compute, live.cycle))
            lit = int((render(shape, m, t[::20], grid=grid) > 0).sum(axis=(1, 2)).max())
            rows.append([
                name, m, method.correction_label.replace(" correction", ""),
                f"{cont[0]:.3f} / {sent[0]:.3f} / {felt[0]:.3f}", got.span("felt"),
                f"{cont[1]:.1f} / {felt[1]:.1f}", f"{jumps[m][0]:.2f} / {jumps[m][1]:.2f}",
                str(lit), f"{batch * 1e6:.3f}", f"{scalar * 1e6:.2f}",
            ])  # fmt: skip
    headers = ["shape", "method", "correction", "ripple: continuous / sent / felt",
               f"felt ripple over {len(participant_grid())} participants",
               "centroid error mm: continuous / felt", "largest jump: raw / corrected",
               "most lit", "batch us/frame", "live us/frame"]  # fmt: skip
    notes = (
        f"Reference participant {REFERENCE.label} (felt magnitude ((d - TH) / (1 - TH))^K, "
        "summed by energy); the range is over TH 0, 0.1, 0.2, 0.33, 0.45 x K 0.36, 0.5, 0.71, "
        f"1.0, 1.4. Each method with its own correction (`set`: mu = {MU}, gamma = {GAMMA}; "
        "`no`: none; `threshold only`: mu, gamma 1). continuous: "
        f"{samples} points of one 2 s trace; sent: point-sampled at 300 Hz and rounded to 23 "
        "levels (the paper's pipeline); felt: those frames through the palm array's motors "
        f"(first order, spin-up {PALM_MOTOR.tau_up_s * 1e3:g} ms, run-down "
        f"{PALM_MOTOR.tau_down_s * 1e3:g} ms: estimates), from rest, the first "
        f"{3 * PALM_MOTOR.tau_up_s * 1e3:g} ms left out. Centroid: tactor centres weighted by "
        "felt energy m_i^2, error to the true point in mm at the 18 mm pitch. Largest jump: of "
        "one tactor's intensity between points 1e-5 pitches apart along six paths. `batch`: "
        "`render` over 20,000 t; `live`: one 300 Hz point-sampled frame from the lit tactors "
        "only (corrected)."
    )
    return Table("Methods side by side: predicted percept, jumps and cost", headers, rows, notes)


def winners_table(samples: int = 2001, ranges: dict | None = None) -> Table:
    """Which method is felt most evenly, and which places the centroid best, for each
    participant of the grid (through the motors, on the line and circle together)."""
    from ..rendering.methods import method_names
    from ..rendering.motor import PALM_MOTOR
    from ..rendering.percept import EXPONENTS, THRESHOLDS, Participant

    methods = [*method_names(), *VARIANTS]
    if ranges is None:
        ranges = _ranges(samples, methods, PALM_MOTOR)
    rows = []
    for th in THRESHOLDS:
        row = [f"{th:g}"]
        for k in EXPONENTS:
            who = Participant(th, k)
            worst = {m: max(ranges[s, m].at("felt", who)[0] for s, _ in _shapes())
                     for m in methods}  # fmt: skip
            error = {m: np.mean([ranges[s, m].at("felt", who)[1] for s, _ in _shapes()])
                     for m in methods}  # fmt: skip
            even = sorted(worst, key=worst.get)
            near = min(error, key=error.get)
            row.append(f"{even[0]} {worst[even[0]]:.2f}, {even[1]} {worst[even[1]]:.2f}; "
                       f"{near} {error[near]:.1f} mm")  # fmt: skip
        rows.append(row)
    headers = ["TH \\ K", *(f"K {k:g}" for k in EXPONENTS)]
    notes = (
        "For each participant (threshold TH, exponent K): the two methods felt most evenly "
        "(the larger felt ripple of the Experiment 1 line and circle, through the motors, as "
        "in the table above), then the method whose felt centroid is nearest the point (mean "
        f"of the two shapes). Among {', '.join(methods)}, each with its own correction."
    )
    return Table("Which method wins where", headers, rows, notes)
