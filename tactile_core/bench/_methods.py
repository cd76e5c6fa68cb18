"""The methods side by side: predicted felt ripple and centroid error next to each method's
batch and live cost."""

from __future__ import annotations

import numpy as np

from ..rendering.geometry import Grid
from ..rendering.trace import LiveFrames, Sampling, Trace
from ._common import GAMMA, MU, Table, _cycling, best_time


def methods_table(samples: int = 2001) -> Table:
    """The methods side by side: predicted felt ripple and centroid error on the Experiment 1
    line and circle (:mod:`~tactile_core.rendering.percept`), next to each method's batch and
    live cost."""
    from ..experiments.runners import Experiment1
    from ..rendering.methods import method_names
    from ..rendering.percept import predict
    from ..rendering.rasterize import render

    grid = Grid()
    rows = []
    for name, shape in (("line", Experiment1.LINE), ("circle", Experiment1.CIRCLE)):
        trace = Trace(shape)
        t = np.linspace(0.0, 1.0, 20_000)
        for method in method_names():
            p = predict(shape, method, MU, GAMMA, grid=grid, samples=samples)
            batch = best_time(lambda m=method, s=shape, t=t: render(s, m, t, grid=grid)) / t.size
            live = LiveFrames(trace, method, Sampling(300.0, "point", 1), MU, GAMMA, grid)
            scalar = best_time(_cycling(live.compute, live.cycle))
            lit = int((render(shape, method, t[::20], grid=grid) > 0).sum(axis=(1, 2)).max())
            rows.append([name, method, f"{p.ripple:.3f}", f"{p.mean_error_mm:.1f}",
                         f"{p.max_error_mm:.1f}", str(lit), f"{batch * 1e6:.3f}",
                         f"{scalar * 1e6:.2f}"])  # fmt: skip
    headers = ["shape", "method", "felt ripple max/min", "centroid error mean mm",
               "centroid error max mm", "most lit", "batch us/frame", "live us/frame"]  # fmt: skip
    notes = (
        f"Predicted for the participant the correction mu = {MU}, gamma = {GAMMA} is right for "
        f"(TH = {MU}, K = 1 / (2 gamma) = {1 / (2 * GAMMA):.3g}), {samples} points of the "
        "Experiment 1 line and circle in continuous time; felt intensity M = sqrt(sum m_i^2), "
        "centroid weighted by m_i, error in mm at the 18 mm pitch. `batch`: `render` over "
        "20,000 t; `live`: one 300 Hz point-sampled frame from the lit tactors only (corrected)."
    )
    return Table("Methods side by side: predicted percept and cost", headers, rows, notes)
