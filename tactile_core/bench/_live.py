"""Table 1b, what one live frame costs: the scalar path, the precomputed cycle and ``render``
on a single ``t``, per method and temporal filter."""

from __future__ import annotations

import numpy as np

from ..rendering.geometry import Grid
from ..rendering.methods import METHOD_NAMES
from ..rendering.trace import LiveFrames, Sampling, Trace
from ._common import FILTERS, GAMMA, MU, SCENES, Table, _cycling, best_time


def live_table(rate_hz: float = 300.0) -> Table:
    """Table 1b: cost of one live frame (render, correct, filter) per method and filter."""
    from ..rendering.rasterize import render

    shape = SCENES["circle"]
    trace = Trace(shape)
    grid = Grid()
    rows = []
    for filt, s in FILTERS[:2]:
        sampling = Sampling(rate_hz, filt, s)
        for method in METHOD_NAMES:
            live = LiveFrames(trace, method, sampling, MU, GAMMA, grid)
            scalar = best_time(_cycling(live.compute, live.cycle))
            live.precompute()
            table = best_time(_cycling(live.entries, live.cycle))
            one = np.array([0.3])
            batch = best_time(lambda m=method, one=one: render(shape, m, one, grid=grid))
            rows.append(
                [
                    sampling.label,
                    method,
                    f"{scalar * 1e6:.2f}",
                    f"{table * 1e6:.2f}",
                    f"{batch * 1e6:.1f}",
                ]
            )
    headers = ["filter", "method", "live scalar us", "live table us", "batch render, 1 frame us"]
    notes = (
        f"One frame of the Experiment 1 circle at {rate_hz:g} Hz with mu = {MU}, "
        f"gamma = {GAMMA}: `live scalar` computes it from the lit tactors only; `live table` "
        "serves it from the precomputed cycle; the last column is `render` on a single t."
    )
    return Table("Live frame cost", headers, rows, notes)
