"""``tactile bench``: what rendering costs, and what speed buys in accuracy.

Timings are the minimum over repeated runs (the least disturbed by other processes) of
``time.perf_counter`` around many calls; they are reported, never asserted in tests.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from importlib.metadata import entry_points
from pathlib import Path

import numpy as np

from .rendering.correction import Dither, quantize
from .rendering.geometry import Grid
from .rendering.methods import METHOD_NAMES
from .rendering.shapes import Circle, Line, Square
from .rendering.trace import LiveFrames, Sampling, Trace, render_frames

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
    from .rendering.rasterize import render

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
    from .rendering.rasterize import render

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
    refs = {}
    for name, method in scenes:
        trace = Trace(SCENES[name])
        refs[name, method] = _reference(trace, method, MU, GAMMA, step_s, grid)
    rows = []
    for rate in rates:
        phase_list = rng.uniform(0.0, 1.0 / rate, phases)
        for filt, s in filters:
            sampling = Sampling(rate, filt, s)
            errs = {k: [] for k in ("e", "o", "eq", "oq", "ed")}
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
            e = {k: np.array(v) * (100 if k[0] == "e" else 1e3) for k, v in errs.items()}
            rows.append(
                [
                    f"{rate:g}",
                    sampling.label,
                    f"{e['e'].mean():.3f} / {e['e'].max():.2f}",
                    f"{e['o'].mean():.2f} / {e['o'].max():.2f}",
                    f"{e['eq'].mean():.3f} / {e['eq'].max():.2f}",
                    f"{e['oq'].max():.2f}",
                    f"{e['ed'].mean():.3f} / {e['ed'].max():.2f}",
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
        "batch us/frame",
        "live us/frame",
    ]
    notes = (
        f"Errors per tactor against a point sampling every {step_s * 1e6:g} us, pooled over "
        "CT, MM, AS and IM on the Experiment 1 line and circle (mu = 0.33, gamma = 0.7, 2 s "
        f"trace + 0.5 s pause) and over {phases} random phases of the trace's start against the "
        "frame clock (mean over tactors and phases / worst tactor in the worst phase). Drive "
        "energy: relative error of the time integral of the corrected drive intensity over one "
        "period, what the host sends; there is no motor model, so nothing here says what is "
        "felt. Onset: the start of the first frame a tactor is lit in vs. when it turns on, for "
        "tactors that turn on after the trace starts. The frame rate is how often the host "
        "sends levels, not the array's PWM carrier (about 300 Hz on the paper's array). The "
        f"level columns quantise the frames to {levels} levels first, by plain rounding (the "
        "paper's pipeline) or with temporal dithering (error feedback per tactor). Costs: AS on "
        "the circle, batch `render_frames` per frame and the scalar live path per frame."
    )
    return Table("Speed against accuracy", headers, rows, notes)


class _EmulatorProcess:
    """``tactile emulate`` in a subprocess, for the device benchmark."""

    def __init__(self, tmpdir, rate_hz, name):
        import subprocess
        import sys

        self.report = Path(tmpdir) / f"{name}.json"
        self.log = Path(tmpdir) / f"{name}.csv"
        cmd = [sys.executable, "-m", "tactile_core.cli", "emulate", "--rate", str(rate_hz)]
        cmd += ["--json", str(self.report), "--log", str(self.log)]
        self.proc = subprocess.Popen(
            cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True
        )
        self.path = self.proc.stdout.readline().strip()

    def finish(self):
        import signal

        self.proc.send_signal(signal.SIGINT)
        self.proc.communicate(timeout=30)
        report = json.loads(self.report.read_text())
        rows = self.log.read_text().splitlines()[1:]
        log = np.array([[float(v) for v in r.split(",")] for r in rows]).reshape(len(rows), -1)
        return report, log


class _Busy:
    """Another process keeping one core busy (``with _Busy(): ...``)."""

    def __enter__(self):
        import subprocess
        import sys

        self.proc = subprocess.Popen([sys.executable, "-c", "while True: pass"])
        return self

    def __exit__(self, *exc):
        self.proc.kill()
        self.proc.wait()


def device_tables(rates=(100, 200, 300), seconds: float = 10.0, changes: int = 30):
    """Tables 3 and 4: streaming into the emulator, and parameter-change latency."""
    import contextlib
    import tempfile

    from .device.link import SerialLink
    from .device.streamer import Streamer
    from .rendering.scene import Scene

    rows = []
    latency_rows = []
    with tempfile.TemporaryDirectory() as tmpdir:
        for load in ("idle", "other core busy"):
            busy = _Busy() if load != "idle" else contextlib.nullcontext()
            with busy:
                for rate in rates:
                    emu = _EmulatorProcess(tmpdir, rate, f"{load[:4]}-{rate}")
                    link = SerialLink(emu.path)
                    scene = Scene(SCENES["circle"], "AS", MU, GAMMA, rate_hz=rate)
                    streamer = Streamer(link, scene=scene)
                    streamer.start()
                    time.sleep(seconds)
                    stats = streamer.stop()
                    link.close()
                    report, log = emu.finish()
                    lost = stats.frames - report["frames"] + report["seq_gaps"]
                    # Receiver side, without the final all-off frame (sent at once on stop,
                    # off the deadline grid).
                    received = log[:-1, 0]
                    received_hz = (len(received) - 1) / (received[-1] - received[0])
                    err = np.abs(np.diff(received) - 1.0 / rate) * 1e3
                    rows.append(
                        [
                            load,
                            f"{rate}",
                            f"{received_hz:.2f}",
                            f"{100 * received_hz / rate:.2f}",
                            f"{stats.interval_error_p50_ms:.3f} / "
                            f"{stats.interval_error_p99_ms:.3f}",
                            f"{np.percentile(err, 50):.3f} / {np.percentile(err, 99):.3f}",
                            f"{err.max():.1f}",
                            f"{stats.late}",
                            f"{stats.skipped}",
                            f"{max(lost, 0)}",
                        ]
                    )
        for rate in rates:
            emu = _EmulatorProcess(tmpdir, rate, f"latency-{rate}")
            link = SerialLink(emu.path)
            corner_a = Line((0.5, 0.5), (0.5, 0.5))  # lights channel 0 only
            corner_b = Line((4.5, 5.5), (4.5, 5.5))  # lights channel 29 only
            scene = Scene(corner_a, "CT", rate_hz=rate, dither=False)
            streamer = Streamer(link, scene=scene)
            streamer.start()
            rng = np.random.default_rng(1)
            marks = []
            time.sleep(0.3)
            for i in range(changes):
                time.sleep(0.05 + rng.uniform(0, 1.0 / rate))  # a random phase of the frame
                target = corner_b if i % 2 == 0 else corner_a
                marks.append((time.monotonic(), 29 if target is corner_b else 0))
                streamer.set_scene(scene.replace(shape=target))
            time.sleep(0.1)
            streamer.stop()
            link.close()
            report, log = emu.finish()
            received = report["started_monotonic"] + log[:, 0]
            latencies = []
            for k, (when, channel) in enumerate(marks):
                after = np.flatnonzero((received >= when) & (log[:, 2 + channel] > 0))
                next_change = marks[k + 1][0] if k + 1 < len(marks) else np.inf
                if len(after) and received[after[0]] < next_change:  # not overtaken
                    latencies.append(received[after[0]] - when)
            lat = np.array(latencies) * 1e3
            period_ms = 1e3 / rate
            latency_rows.append(
                [
                    f"{rate}",
                    f"{len(lat)} / {changes}",
                    f"{np.median(lat):.2f}",
                    f"{lat.max():.2f}",
                    f"{period_ms + 1:.2f}",
                    f"{(lat <= period_ms + 1).mean() * 100:.0f}",
                ]
            )
    headers = [
        "load",
        "rate Hz",
        "received Hz",
        "% of requested",
        "sender interval err p50 / p99 ms",
        "emulator interval err p50 / p99 ms",
        "emulator max err ms",
        "late > 1 ms",
        "skipped",
        "lost",
    ]
    notes = (
        f"{seconds:g} s of the Experiment 1 circle (AS, box S=4, dithered) per row, streamed by "
        "`Streamer` through pyserial into `tactile emulate` on a pseudo-terminal (a separate "
        "process). Interval error: |interval between successive frames - period|, at the sender "
        "(after each write) and at the emulator (on receipt). Lost: frames written but not "
        "decoded, plus gaps in the sequence numbers. `other core busy`: a second process "
        "spinning `while True: pass` for the whole run."
    )
    stream_table = Table("Streaming into the emulator", headers, rows, notes)
    latency_table = Table(
        "Parameter change to the wire",
        ["rate Hz", "changes seen", "median ms", "max ms", "target ms", "% within target"],
        latency_rows,
        f"{changes} scene changes at random phases of the frame; latency from `set_scene` "
        "to the emulator's receipt of the first frame of the new scene (both on the monotonic "
        "clock). Target: one frame period + 1 ms.",
    )
    return stream_table, latency_table


def staircase_table(trials=(20, 30, 40, 60, 80, 120, 160), slopes=(2.0, 4.0, 8.0),
                    tracks: int = 2000, seed: int = 0) -> Table:  # fmt: skip
    """How many trials Experiment 2's estimate needs to settle within 10% of the 70.7% length.

    Simulated participants answer from a psychometric function (logistic in log length, guess
    rate 0.25, lapse 0.02) of slope ``slope``; each track runs the paper's staircase (start 2.0,
    x 0.685 / x 1.46, 2-down/1-up, capped at 4) for ``N`` trials. Two estimates per track: the
    paper's (mean of the last 4 reversals) and the mean of all reversals after the first three.
    """
    from .experiments.participants import Psychometric
    from .experiments.staircase import Staircase

    rng = np.random.default_rng(seed)
    rows = []

    def summary(est, target):
        ok = np.isfinite(est)
        if not ok.any():
            return ["-", "-", "0"]
        rel = (est[ok] - target) / target
        within = np.abs(np.where(ok, est, np.inf) - target) <= 0.1 * target
        return [f"{100 * np.median(rel):+.1f}", f"{100 * np.median(np.abs(rel)):.1f}",
                f"{100 * within.mean():.0f}"]  # fmt: skip

    for slope in slopes:
        f = Psychometric(midpoint=0.5, slope=slope)
        target = f.length_at(0.707)
        for n in trials:
            paper, all_but_3 = [], []
            for _ in range(tracks):
                sc = Staircase(2.0, 0.685, 1.46, 2, 1, min_level=0.01, max_level=4.0)
                draws = rng.random(n)
                for k in range(n):
                    sc.update(bool(draws[k] < f.p_correct(sc.level)))
                rev = sc.reversal_levels
                paper.append(np.mean(rev[-4:]) if len(rev) >= 4 else np.nan)
                all_but_3.append(np.mean(rev[3:]) if len(rev) >= 4 else np.nan)
            paper, all_but_3 = np.array(paper), np.array(all_but_3)
            rows.append(
                [f"{slope:g}", f"{n}", f"{100 * np.isfinite(paper).mean():.0f}",
                 *summary(paper, target), *summary(all_but_3, target)]
            )  # fmt: skip
    headers = [
        "slope", "trials", "% with 4 reversals",
        "last 4: bias %", "last 4: median |err| %", "last 4: % within 10%",
        "all but first 3: bias %", "all but first 3: median |err| %",
        "all but first 3: % within 10%",
    ]  # fmt: skip
    notes = (
        f"{tracks} simulated tracks per row, errors relative to the true 70.7% length. Slope: of "
        "the psychometric function in log length (2 shallow, 8 steep). 'last 4' is the paper's "
        "estimate (last two peaks and valleys); the paper ran 30 trials per condition."
    )
    return Table("Experiment 2: trials needed for the estimate to settle", headers, rows, notes)


TUNING_OBSERVERS = {
    "steep": {"threshold": 0.25, "exponent": 1.0, "threshold_sd": 0.015, "weber": 0.10,
              "lapse": 0.02},
    "shallow": {"threshold": 0.35, "exponent": 0.6, "threshold_sd": 0.04, "weber": 0.25,
                "lapse": 0.04},
}  # fmt: skip
"""The two simulated observers of the tuning benchmark: steep and shallow psychometric
functions (threshold spread in drive units, Weber fraction of felt magnitude in log units)."""

TUNING_PLANS = (
    (8, 12, 6),
    (12, 16, 8),
    (16, 24, 12),
    (20, 40, 12),
    (24, 60, 16),
    (30, 90, 20),
    (40, 140, 30),
)
"""(trials per tactor, per place, at the corner) of the tuning benchmark's rows."""


def _tuning_run(job):
    from .experiments.tuning import TuningPlan, simulate_tuning

    observer, plan, seed = job
    o = dict(TUNING_OBSERVERS[observer])
    r = simulate_tuning(o.pop("threshold"), o.pop("exponent"), seed=seed,
                        plan=TuningPlan(*plan), **o)  # fmt: skip
    return observer, plan, r.ok, r.mu, r.gamma, r.mu_ci, r.gamma_ci, r.trials


def methods_table(samples: int = 2001) -> Table:
    """The methods side by side: predicted felt ripple and centroid error on the Experiment 1
    line and circle (:mod:`~tactile_core.rendering.percept`), next to each method's batch and
    live cost."""
    from .experiments.runners import Experiment1
    from .rendering.methods import method_names
    from .rendering.percept import predict
    from .rendering.rasterize import render

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


def tuning_table(runs: int = 200, plans=TUNING_PLANS, processes: int = 2) -> Table:
    """How many trials the correction tuning needs: the share of simulated runs that recover
    mu within +-0.03 and gamma within +-15%, against the trial count, for two observers."""
    import multiprocessing

    jobs = [(o, plan, seed) for o in TUNING_OBSERVERS for plan in plans for seed in range(runs)]
    with multiprocessing.get_context("spawn").Pool(processes) as pool:
        results = pool.map(_tuning_run, jobs, chunksize=8)
    rows = []
    for observer, o in TUNING_OBSERVERS.items():
        mu_true, gamma_true = o["threshold"], 1.0 / (2.0 * o["exponent"])
        for plan in plans:
            got = [r for r in results if r[0] == observer and r[1] == plan]
            ok = [r for r in got if r[2]]
            mu_err = np.array([r[3] - mu_true for r in ok])
            g_err = np.array([r[4] / gamma_true - 1.0 for r in ok])
            mu_in = np.abs(mu_err) <= 0.03 + 1e-9
            g_in = np.abs(g_err) <= 0.15 + 1e-9
            covers_mu = [r[5][0] <= mu_true <= r[5][1] for r in ok]
            covers_g = [not (r[6][0] > gamma_true) and not (r[6][1] < gamma_true) for r in ok]
            n = len(got)
            rows.append([
                observer, f"{5 * plan[0] + 2 * plan[1] + plan[2]}", "/".join(map(str, plan)),
                f"{100 * mu_in.sum() / n:.0f}", f"{100 * g_in.sum() / n:.0f}",
                f"{100 * (mu_in & g_in).sum() / n:.0f}", f"{100 * (n - len(ok)) / n:.0f}",
                f"{np.median(np.abs(mu_err)):.3f}" if ok else "-",
                f"{100 * np.median(np.abs(g_err)):.1f}" if ok else "-",
                f"{100 * np.mean(covers_mu):.0f}" if ok else "-",
                f"{100 * np.mean(covers_g):.0f}" if ok else "-",
            ])  # fmt: skip
    headers = ["observer", "trials", "per tactor / place / corner", "% mu within 0.03",
               "% gamma within 15%", "% both", "% no result", "median |mu err|",
               "median |gamma err| %", "% mu CI covers", "% gamma CI covers"]  # fmt: skip
    notes = (
        f"{runs} simulated runs per row (seeds 0..{runs - 1}) of `tactile tune-correction` "
        "against the simulated participant. steep: TH 0.25, K 1.0 (gamma 0.5), threshold sd "
        "0.015, Weber 0.10, lapse 0.02; shallow: TH 0.35, K 0.6 (gamma 0.83), threshold sd 0.04, "
        "Weber 0.25, lapse 0.04. Trials: answers (5 tactors x per tactor + 2 places x per place + "
        "corner), as planned. '% no result': runs that ended with no correction (a track did "
        "not settle). Shares are of all runs; the interval columns of the runs with a result."
    )
    return Table("Tuning the correction: trials against accuracy", headers, rows, notes)


def run(part: str = "core", quick: bool = False, out=print) -> list[Table]:
    """Run the benchmark tables of ``part`` ("core", "methods", "device", "experiments",
    "tuning", "gui" or "all"), printed as Markdown."""
    tables = []

    def show(table: Table) -> None:
        out(table.markdown())
        out("")
        tables.append(table)

    if part in ("core", "all"):
        sizes = (2000, 20_000) if quick else (2000, 100_000)
        show(batch_table(sizes))
        show(live_table())
        show(accuracy_table(quick=quick))
    if part in ("methods", "all"):
        show(methods_table(samples=501 if quick else 2001))
    if part in ("device", "all"):
        for table in device_tables(seconds=3.0 if quick else 10.0):
            show(table)
    if part in ("experiments", "all"):
        show(staircase_table(tracks=300 if quick else 2000))
    if part in ("tuning", "all"):
        show(tuning_table(runs=20 if quick else 200))
    if part in ("gui", "all"):
        # The GUI's benchmark lives with the GUI (tactile_tuner), registered under the entry
        # point group "tactile.bench": the core never imports Qt or the GUI package.
        hooks = [ep for ep in entry_points(group="tactile.bench") if ep.name == "gui"]
        if not hooks:
            out("(GUI benchmark skipped: the tuner is not installed)")
        for hook in hooks:
            try:
                run_gui = hook.load()
            except ImportError as exc:
                out(f"(GUI benchmark skipped: {exc})")
                continue
            tables += run_gui(quick=quick, out=out)
    return tables
