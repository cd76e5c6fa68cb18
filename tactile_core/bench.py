"""``tactile bench``: what rendering costs, and what speed buys in accuracy.

Timings are the minimum over repeated runs (the least disturbed by other processes) of
``time.perf_counter`` around many calls; they are reported, never asserted in tests.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .correction import quantize
from .geometry import Grid
from .methods import METHOD_NAMES
from .shapes import Circle, Line, Square
from .trace import LiveFrames, Sampling, Trace, render_frames

SCENES = {
    "line": Line((0.5, 1.84), (4.5, 4.16)),  # Experiment 1 line, slope 0.58
    "circle": Circle((2.5, 3.0), 2.0),  # Experiment 1 circle
    "square": Square((2.5, 3.5), 4.0),  # Experiment 3 square
}
MU, GAMMA = 0.33, 0.7  # the paper's values for all experiments but two stages of Exp. 2
RATES_HZ = (25, 50, 100, 200, 300, 1000)
FILTERS = (("point", 1), ("box", 4), ("box", 16))


def best_time(fn, *, repeat: int = 7, min_s: float = 0.05) -> float:
    """Seconds per call of ``fn()``: the minimum over ``repeat`` runs of enough calls."""
    number = 1
    while True:
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        elapsed = time.perf_counter() - t0
        if elapsed >= min_s or number >= 1 << 20:
            break
        number *= 2
    runs = [elapsed]
    for _ in range(repeat - 1):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        runs.append(time.perf_counter() - t0)
    return min(runs) / number


def dense_area_sampling(shape, t, grid: Grid) -> np.ndarray:
    """The textbook vectorised AS: the box's overlap with every cell, broadcast over frames.

    For each frame and each cell, the overlap of ``[px - 0.5, px + 0.5]`` with
    ``[col, col + 1]`` times the same in y: the yardstick the issue quotes (~0.25 us/frame).
    """
    x, y = shape.xy(t)
    cols = np.arange(grid.cols, dtype=np.float64)
    rows = np.arange(grid.rows, dtype=np.float64)
    wx = np.minimum(x[:, None] + 0.5, cols + 1) - np.maximum(x[:, None] - 0.5, cols)
    wy = np.minimum(y[:, None] + 0.5, rows + 1) - np.maximum(y[:, None] - 0.5, rows)
    return np.maximum(wy, 0.0)[:, :, None] * np.maximum(wx, 0.0)[:, None, :]


def naive_area_sampling(shape, t, grid: Grid) -> np.ndarray:
    """A leaner straightforward AS: only the four overlapped corners, masked fancy indexing.

    Plain ``floor`` (no float-noise snapping), boolean masks to drop cells outside the grid,
    and fancy-index assignment per corner: a stricter yardstick than :func:`dense_area_sampling`.
    """
    x, y = shape.xy(t)
    a, b = x - 0.5, y - 0.5
    c, r = np.floor(a), np.floor(b)
    fx, fy = a - c, b - r
    out = np.zeros((len(t), grid.rows, grid.cols))
    sample = np.arange(len(t))
    for dc, dr, w in (
        (0, 0, (1 - fx) * (1 - fy)),
        (1, 0, fx * (1 - fy)),
        (0, 1, (1 - fx) * fy),
        (1, 1, fx * fy),
    ):
        cc, rr = (c + dc).astype(int), (r + dr).astype(int)
        ok = (cc >= 0) & (cc < grid.cols) & (rr >= 0) & (rr < grid.rows)
        out[sample[ok], rr[ok], cc[ok]] = w[ok]
    return out


@dataclass
class Table:
    """A titled table of rows, printed as Markdown."""

    title: str
    headers: list
    rows: list
    notes: str = ""

    def markdown(self) -> str:
        """The table as GitHub-flavoured Markdown, with its title and notes."""
        widths = [
            max(len(str(h)), *(len(str(r[i])) for r in self.rows))
            for i, h in enumerate(self.headers)
        ]

        def line(cells):
            return "| " + " | ".join(str(c).ljust(w) for c, w in zip(cells, widths)) + " |"

        out = [f"### {self.title}", "", line(self.headers)]
        out.append("|" + "|".join("-" * (w + 2) for w in widths) + "|")
        out += [line(r) for r in self.rows]
        if self.notes:
            out += ["", self.notes]
        return "\n".join(out)


def batch_table(sizes=(2000, 100_000), grid: Grid | None = None) -> Table:
    """Table 1a: batch cost per frame of ``render`` for every method and shape."""
    from .render import render

    grid = grid or Grid()
    rows = []
    for name, shape in SCENES.items():
        for method in ("dense AS", "corner AS", *METHOD_NAMES):
            row = [name, method]
            for n in sizes:
                t = np.linspace(0.0, 1.0, n)
                if method == "dense AS":
                    seconds = best_time(lambda t=t, s=shape: dense_area_sampling(s, t, grid))
                elif method == "corner AS":
                    seconds = best_time(lambda t=t, s=shape: naive_area_sampling(s, t, grid))
                else:
                    seconds = best_time(lambda t=t, s=shape, m=method: render(s, m, t, grid=grid))
                row.append(f"{seconds / n * 1e6:.3f}")
            rows.append(row)
    headers = ["shape", "method", *(f"us/frame @ {n:,}" for n in sizes)]
    notes = (
        "Yardsticks on the same shape: `dense AS` is the textbook vectorised area sampling "
        "(the box's overlap with every cell, broadcast over all frames); `corner AS` a leaner "
        "straightforward one (the four overlapped cells, masked fancy indexing)."
    )
    return Table("Batch rendering cost (render, raw intensities)", headers, rows, notes)


def live_table(rate_hz: float = 300.0) -> Table:
    """Table 1b: cost of one live frame (render, correct, filter) per method and filter."""
    from .render import render

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


def _cycling(frame_of, cycle):
    """A no-argument callable that computes successive frames ``k % cycle``."""
    counter = iter(range(1 << 62))
    return lambda: frame_of(next(counter) % cycle)


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


def _frame_metrics(frames, rate_hz, period_s, periods, grid):
    """Energy per period and worst onset error inputs from streamed frames."""
    flat = frames.reshape(len(frames), grid.size)
    energy = flat.sum(axis=0) / rate_hz / periods
    per_period = []
    times = np.arange(len(frames)) / rate_hz
    for p in range(periods):
        in_p = (times >= p * period_s - 1e-12) & (times < (p + 1) * period_s - 1e-12)
        on = flat[in_p] > 0
        first = np.where(on.any(axis=0), times[in_p][np.argmax(on, axis=0)] - p * period_s, np.inf)
        per_period.append(first)
    return energy, np.array(per_period)


def accuracy_table(
    rates=RATES_HZ, filters=FILTERS, step_s: float = 5e-6, levels: int = 23, quick: bool = False
) -> Table:
    """Table 2: speed against accuracy of streamed frames, against a continuous reference.

    For each rate and filter, over the four methods on the Experiment 1 line and circle (2 s
    traces, 0.5 s pause, mu = 0.33, gamma = 0.7): each tactor's delivered energy (time
    integral of its corrected intensity) and onset time against a point sampling every
    ``step_s``, with and without quantisation to ``levels``, and the batch and live CPU cost
    per frame.
    """
    grid = Grid()
    if quick:
        step_s = 2e-5
    scenes = [(n, m) for n in ("line", "circle") for m in METHOD_NAMES]
    refs = {}
    for name, method in scenes:
        trace = Trace(SCENES[name])
        refs[name, method] = _reference(trace, method, MU, GAMMA, step_s, grid)
    rows = []
    for rate in rates:
        for filt, s in filters:
            sampling = Sampling(rate, filt, s)
            e_err, e_err_q, o_err, o_err_q = [], [], [], []
            for name, method in scenes:
                trace = Trace(SCENES[name])
                periods = 2 if abs(trace.period_s * rate - round(trace.period_s * rate)) else 1
                n = round(periods * trace.period_s * rate)
                _, frames = render_frames(
                    trace, method, sampling=sampling, mu=MU, gamma=GAMMA, grid=grid, n_frames=n
                )
                quantised = quantize(frames, levels) / (levels - 1)
                ref_e, ref_o = refs[name, method]
                lit = ref_e > 0
                interior = lit & (ref_o > 0)  # onsets after the trace starts
                for fr, e_list, o_list in (
                    (frames, e_err, o_err),
                    (quantised, e_err_q, o_err_q),
                ):
                    energy, onsets = _frame_metrics(fr, rate, trace.period_s, periods, grid)
                    e_list.extend(np.abs(energy[lit] - ref_e[lit]) / ref_e[lit])
                    o_list.extend(np.abs(onsets[:, interior] - ref_o[interior]).ravel())
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
            e_err, e_err_q = np.array(e_err) * 100, np.array(e_err_q) * 100
            o_err, o_err_q = np.array(o_err) * 1e3, np.array(o_err_q) * 1e3
            rows.append(
                [
                    f"{rate:g}",
                    sampling.label,
                    f"{e_err.mean():.3f}",
                    f"{e_err.max():.2f}",
                    f"{o_err.mean():.2f}",
                    f"{o_err.max():.2f}",
                    f"{e_err_q.mean():.3f}",
                    f"{e_err_q.max():.2f}",
                    f"{o_err_q.max():.2f}",
                    f"{cost / 750 * 1e6:.2f}",
                    f"{live_cost * 1e6:.1f}",
                ]
            )
    headers = [
        "rate Hz",
        "filter",
        "energy err mean %",
        "energy err max %",
        "onset err mean ms",
        "onset err max ms",
        f"{levels} levels: energy mean %",
        f"{levels} levels: energy max %",
        f"{levels} levels: onset max ms",
        "batch us/frame",
        "live us/frame",
    ]
    notes = (
        f"Errors per tactor against a point sampling every {step_s * 1e6:g} us, pooled over "
        "CT, MM, AS and IM on the Experiment 1 line and circle (mu = 0.33, gamma = 0.7, 2 s "
        "trace + 0.5 s pause). Energy: relative error of the time integral of the corrected "
        "intensity over one period. Onset: first frame a tactor is on vs. when it turns on, "
        "for tactors that turn on after the trace starts. The level columns quantise the "
        f"frames to {levels} levels first. Costs: AS on the circle, batch `render_frames` "
        "per frame and the scalar live path per frame."
    )
    return Table("Speed against accuracy", headers, rows, notes)


def run(part: str = "core", quick: bool = False, out=print) -> list[Table]:
    """Run the benchmark tables of ``part`` ("core") and print them as Markdown."""
    tables = []
    if part in ("core", "all"):
        sizes = (2000, 20_000) if quick else (2000, 100_000)
        for make in (
            lambda: batch_table(sizes),
            live_table,
            lambda: accuracy_table(quick=quick),
        ):
            table = make()
            out(table.markdown())
            out("")
            tables.append(table)
    return tables
