"""What a frame costs on actuators anywhere: the live path and batch rendering of the methods
that work on layouts, on the shipped belt, sleeve and vest."""

from __future__ import annotations

import numpy as np

from ..device.profile import load_profile
from ..rendering.methods import LAYOUT_METHODS
from ..rendering.rasterize import render
from ..rendering.shapes import Circle, Line
from ..rendering.trace import LiveFrames, Sampling, Trace
from ._common import GAMMA, MU, Table, _cycling, best_time

LAYOUT_SCENES = {
    "belt-8": Line((0.0, 0.0), (8.0, 0.0)),  # once round the waist, across the seam
    "sleeve-2x6": Line((0.0, 0.0), (6.0, 1.5)),  # a helix from wrist to elbow
    "vest-4x5": Circle((1.5, 2.0), 1.6),
}


def layouts_table(rate_hz: float = 300.0, samples: int = 2000) -> Table:
    """Live frame (scalar path, from the actuators near the point) and batch cost per frame
    of each layout method on each shipped layout."""
    rows = []
    for name, shape in LAYOUT_SCENES.items():
        layout = load_profile(name).layout
        trace = Trace(shape, duration_s=2.0, pause_s=0.0)
        t = np.linspace(0.0, 1.0, samples)
        for method in LAYOUT_METHODS:
            live = LiveFrames(trace, method, Sampling(rate_hz), MU, GAMMA, layout)
            scalar = best_time(_cycling(live.compute, live.cycle))
            batch = best_time(
                lambda m=method, s=shape, t=t, g=layout: render(s, m, t, grid=g), repeat=5
            )
            rows.append([name, layout.size, method, f"{scalar * 1e6:.2f}",
                         f"{batch / samples * 1e6:.3f}"])  # fmt: skip
    return Table(
        "Layouts: cost of a frame on actuators anywhere",
        ["profile", "actuators", "method", "live us/frame", f"batch us/frame @ {samples:,}"],
        rows,
        notes=(
            f"One frame at {rate_hz:g} Hz with mu = {MU}, gamma = {GAMMA}: the live path visits "
            "the candidates of the point's bucket only (tactile_core.rendering.methods._layout); "
            "batch renders the trace's samples at once. Traces: once round the belt across its "
            "seam, a helix round the sleeve, a circle on the vest."
        ),
    )
