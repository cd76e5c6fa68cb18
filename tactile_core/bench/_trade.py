"""``tactile bench --part trade``: the speed/accuracy trade in felt terms, and what to choose.

One table: from the paper's pipeline (300 Hz, point sampling, 23 levels, plain rounding, frames
for now, plain drive) one setting varied at a time, then the key combinations, then the key
rows again for motor constants from an ideal motor through 10/20 to 150/300 ms; every felt figure
the mean over the methods of the registry (the paper's four, the peers, BA, and any that
registers) on the Experiment 1 line and circle and the Experiment 3 square, ± its standard
deviation over random phases of the trace's start against the frame clock. Beside it: the
methods one by one at the key settings, and the recommended setting per device
(:mod:`._trade_advice`). The model of one setting is :mod:`._trade_model`.
"""

from __future__ import annotations

import time

import numpy as np

from ..rendering.correction import Dither, quantize1
from ..rendering.geometry import Grid
from ..rendering.methods import get_method, method_names
from ..rendering.motor import MotorResponse
from ..rendering.motor_drive import LiveMotorDrive
from ..rendering.trace import LiveFrames, Trace
from ._common import RATES_HZ, SCENES, Table
from ._trade_advice import advice_table, advise
from ._trade_model import FIGURES, PAPER, References, Setting, felt_runs, pool, spread
from ._trade_target import FAMILIES, Target

LEVELS = (4, 8, 16, 23, 64, 256)
"""Device levels the table varies."""
MOTORS_MS = ((0, 0), (10, 20), (30, 60), (50, 100), (100, 200), (150, 300))
"""Motor constants (spin-up / run-down, ms) the key rows are repeated for: an ideal motor, then
fast to slow ERMs."""
SHAPES = ("line", "circle", "square")


def _changes(setting: Setting, base: Setting) -> str:
    """What ``setting`` changes from ``base``, in words (``"25 Hz, 16 levels"``)."""
    parts = []
    if setting.rate_hz != base.rate_hz:
        parts.append(f"{setting.rate_hz:g} Hz")
    if setting.filter != base.filter:
        parts.append(setting.sampling.label)
    if setting.levels != base.levels:
        parts.append(f"{setting.levels} levels")
    if setting.dither != base.dither:
        parts.append("dithered" if setting.dither else "rounded")
    if setting.lead_ms != base.lead_ms:
        parts.append(f"lead {setting.lead_ms:g} ms")
    if setting.host != base.host:
        parts.append(f"{setting.host} host")
    if setting.compensate != base.compensate:
        parts.append("motor-aware" if setting.compensate else "plain drive")
    if not parts:
        return (f"base: {base.rate_hz:g} Hz, {base.sampling.label}, {base.levels} levels, "
                f"{'dithered' if base.dither else 'rounded'}, lead {base.lead_ms:g}, "
                f"{'motor-aware' if base.compensate else 'plain'}")  # fmt: skip
    return ", ".join(parts)


def trade_settings(base: Setting, lead_ms: float, quick: bool = False) -> list[Setting]:
    """The table's rows: ``base``, one setting varied at a time, then the key combinations."""
    if quick:
        return [base, base.replace(rate_hz=25), base.replace(levels=8),
                base.replace(dither=True), base.replace(lead_ms=lead_ms),
                base.replace(compensate=True)]  # fmt: skip
    rows = [base]
    rows += [base.replace(rate_hz=r) for r in RATES_HZ if r != base.rate_hz]
    rows.append(base.replace(filter="box"))
    rows += [base.replace(levels=n) for n in LEVELS if n != base.levels]
    rows += [base.replace(dither=True), base.replace(lead_ms=lead_ms),
             base.replace(host="busy"), base.replace(compensate=True)]  # fmt: skip
    rows += [
        base.replace(compensate=True, lead_ms=lead_ms),
        base.replace(rate_hz=100, compensate=True),
        base.replace(rate_hz=50, levels=16),
        base.replace(rate_hz=50, levels=16, compensate=True),
        base.replace(rate_hz=25, levels=16, dither=True, compensate=True),
        base.replace(rate_hz=1000, levels=256, filter="box", compensate=True),
    ]
    return list(dict.fromkeys(rows))


def key_settings(base: Setting, quick: bool = False) -> list[Setting]:
    """The key rows repeated for every motor of :data:`MOTORS_MS`."""
    if quick:
        return [base, base.replace(compensate=True)]
    return [base, base.replace(compensate=True), base.replace(rate_hz=50, levels=16),
            base.replace(rate_hz=50, levels=16, compensate=True)]  # fmt: skip


class LiveCost:
    """What one frame costs on the live path for a setting, per method, cached by what
    matters (filter, levels, dithering, motor-aware drive): the scalar live path
    (:meth:`LiveFrames.compute`), the motor-aware stage, and rounding or dithering of each lit
    tactor, on the Experiment 1 circle at the setting's rate."""

    def __init__(self, methods, motor: MotorResponse, runs: int = 5, frames: int = 300):
        self.methods, self.motor = tuple(methods), motor
        self.runs, self.frames = runs, frames
        self._cache: dict = {}

    def __call__(self, setting: Setting) -> np.ndarray:
        """Microseconds per frame, averaged over the methods, one value per run ``(runs,)``."""
        key = (setting.sampling.label, setting.levels, setting.dither, setting.compensate,
               setting.rate_hz)  # fmt: skip
        if key not in self._cache:
            self._cache[key] = self._measure(setting)
        return self._cache[key]

    def _measure(self, setting: Setting) -> np.ndarray:
        grid = Grid()
        pipes = []
        for name in self.methods:
            m = get_method(name)
            live = LiveFrames(Trace(SCENES["circle"]), m, setting.sampling,
                              *m.own_correction(0.33, 0.7), grid)  # fmt: skip
            stage = None
            if setting.compensate:
                stage = LiveMotorDrive(self.motor, grid.size)
                stage.set_rate(setting.rate_hz)
            dither = Dither(grid.size, setting.levels) if setting.dither else None
            pipes.append((live, stage, dither))
        levels = setting.levels

        def frames(first: int) -> None:
            for k in range(first, first + self.frames):
                for live, stage, dither in pipes:
                    entries = live.compute(k % (live.cycle or 1))
                    if stage is not None:
                        entries = stage.frame(entries)
                    if dither is not None:
                        [dither.level1(i, v) for i, v in entries]
                    else:
                        [quantize1(v, levels) for _, v in entries]

        frames(0)  # warm up
        times = []
        for run in range(self.runs):
            t0 = time.perf_counter()
            frames((run + 1) * self.frames)
            times.append((time.perf_counter() - t0) / self.frames / len(pipes) * 1e6)
        return np.array(times)


def _cost_text(us: np.ndarray) -> str:
    return f"{us.min():.2f} / {np.median(us):.2f}"


def measure(settings, motor: MotorResponse, target: Target, methods, shapes, *, phases: int,
            seed: int, refs: References) -> list[dict]:  # fmt: skip
    """Per setting, ``{(method, shape): Runs}`` through ``motor``."""
    return [{(m, s): felt_runs(setting, SCENES[s], m, motor, phases=phases, seed=seed,
                               link=target.link(), refs=refs)
             for m in methods for s in shapes} for setting in settings]  # fmt: skip


def _row(motor: MotorResponse, setting, base, runs: dict, target: Target, cost) -> list:
    figures = {k: pool(runs.values(), k) for k in FIGURES}
    return [f"{motor.tau_up_s * 1e3:g}/{motor.tau_down_s * 1e3:g}", _changes(setting, base),
            spread(figures["ripple"], 3), spread(figures["lag_mm"], 2),
            spread(figures["onset_ms"], 1), spread(figures["drive_pct"], 2),
            _cost_text(cost(setting)), target.link_label(setting)]  # fmt: skip


def trade_tables(target: Target, *, quick: bool = False, phases: int = 8, seed: int = 0,
                 refs: References | None = None, methods=None) -> list[Table]:  # fmt: skip
    """The trade table for ``target`` and the methods one by one.

    Parameters
    ----------
    target : Target
        The device: its motors (those of the table's first block), levels (the base row's),
        link (the bytes column, the delay of frames for now) and default lead.
    quick : bool
        A few rows, CT and AS on the line, 2 phases: seconds, for tests.
    phases, seed : int
        Random phases of the trace's start against the frame clock, and their seed.
    refs : References, optional
    methods : sequence of str, optional
        Default: every registered method (``"CT"`` and ``"AS"`` when quick).
    """
    refs = refs or References()
    if methods is None:
        methods = ("CT", "AS") if quick else method_names()
    shapes = ("line",) if quick else SHAPES
    phases = 2 if quick else phases
    base = PAPER.replace(levels=target.levels)
    settings = trade_settings(base, target.lead_ms, quick)
    cost = LiveCost(methods, target.motor, runs=3 if quick else 5, frames=60 if quick else 300)
    kw = dict(phases=phases, seed=seed, refs=refs)
    main = measure(settings, target.motor, target, methods, shapes, **kw)
    rows = [_row(target.motor, s, base, r, target, cost) for s, r in zip(settings, main)]
    motors = [(0, 0), (30, 60)] if quick else MOTORS_MS
    for up, down in motors:
        motor = MotorResponse(up / 1e3, down / 1e3)
        keys = key_settings(base, quick)
        for setting, runs in zip(keys, measure(keys, motor, target, methods, shapes, **kw)):
            rows.append(_row(motor, setting, base, runs, target, cost))
    headers = ["motor tau up/down ms", "setting (from the base row)", "felt ripple",
               "felt centroid lag mm", "onset error at the skin ms", "drive energy error %",
               "cost us/frame, min / median", "link bytes/s"]  # fmt: skip
    note_motor = (f"the profile's, {target.motor_source}" if target.motor_from_profile else
                  "none in the profile, so the palm array's estimates")  # fmt: skip
    notes = (
        f"Device profile {target.name}: {target.levels} levels, {target.channels} channels, "
        f"motors {target.motor_label} ({note_motor}), default lead {target.lead_ms:g} ms. "
        f"Rows 1-{len(settings)}: motors {target.motor_label}; then the key rows again for "
        "each motor in the first column (0/0: an ideal motor). Each setting varies one thing "
        "at a time from the base row (the paper's pipeline at the device's levels), then the "
        "key combinations; not the full cross product. Figures: the median over "
        f"{', '.join(methods)} (each with its own correction of mu 0.33, gamma 0.7) x "
        f"{', '.join(shapes)} (2 s traces on the palm array's 5 x 6 grid, 18 mm pitch; each "
        "method alone: the next table), ± the standard deviation over "
        f"{phases} random phases of the trace's start against the frame clock. Felt: the "
        "reference participant (TH 0.2, K 1) feels the motors' effective drive every 1/3 ms, "
        "the first 3 tau_up left out; ripple max/min of the "
        "felt intensity, lag the felt centroid's mean distance from the point. Onset: "
        "|felt - intended| of each tactor's first activation at the skin: a lead delays every "
        "frame by itself and removes the host's jitter; frames for now (lead 0) play after "
        "their transmission plus the host's measured jitter (idle: p50 0.8 / p99 2.35 ms; "
        "busy host: 14.2 / 43.9 ms), on an audio interface up to a block later. Drive energy "
        "error: of the levels sent against the continuous corrected drive, per lit tactor "
        "(motor-aware drive sends more on purpose). Cost: the live path per frame (scalar "
        "render, the motor-aware stage, rounding or dithering), the mean over the methods on "
        f"the circle, the least and the median of {cost.runs} runs (the least is the least "
        "disturbed by other processes). Link: frames x frame bytes "
        "(timed frames with a lead pack their levels), or an audio interface's samples "
        "(channels x 48 kHz x 4 bytes); '(over ...)': more than the link carries (the streamer "
        "caps the rate), the felt figures assume a link that does."
    )
    trade = Table(f"The trade in felt terms ({target.name})", headers, rows, notes)
    return [trade, methods_trade_table(settings, main, base, methods, target)]


def methods_trade_table(settings, runs, base: Setting, methods, target: Target) -> Table:
    """The methods one by one at the base row, the slowest rate and motor-aware drive (mean
    over the shapes ± SD over phases), from the trade table's runs."""
    slow = next(s for s in settings if s == base.replace(rate_hz=min(RATES_HZ)))
    aware = next(s for s in settings if s == base.replace(compensate=True))
    at = {s: r for s, r in zip(settings, runs)}
    rows = []
    for m in methods:

        def of(setting, figure, digits, m=m):
            return spread(pool([v for (mm, _), v in at[setting].items() if mm == m], figure,
                               "mean"), digits)  # fmt: skip

        rows.append([m, *(of(s, "ripple", 3) for s in (base, slow, aware)),
                     *(of(s, "lag_mm", 2) for s in (base, slow, aware)),
                     of(base, "onset_ms", 1), of(aware, "onset_ms", 1)])  # fmt: skip
    rate = f"{slow.rate_hz:g} Hz"
    headers = ["method", "ripple: base", f"ripple: {rate}", "ripple: motor-aware",
               "lag mm: base", f"lag mm: {rate}", "lag mm: motor-aware", "onset ms: base",
               "onset ms: motor-aware"]  # fmt: skip
    notes = (f"From the trade table's first block (motors {target.motor_label}): each method "
             "alone, the mean over the shapes ± SD over the phases, at the base row, at "
             f"{rate} and with motor-aware drive.")  # fmt: skip
    return Table(f"The trade by method ({target.name})", headers, rows, notes)


def trade_run(profile=None, *, quick: bool = False, show=print) -> list[Table]:
    """``tactile bench --part trade [--profile P]``: the trade table, the methods one by one,
    and the recommendation: for ``profile`` (a name or path), or without one for the palm array
    and each actuator family of :data:`~._trade_target.FAMILIES`."""
    from ..device.profile import find_profile, load_profile

    t0 = time.perf_counter()
    refs = References()
    target = Target.of(load_profile(profile))
    tables = trade_tables(target, quick=quick, refs=refs)
    for table in tables:
        show(table)
    if profile is None:
        devices = [(f.name, Target.of(find_profile(f.profile))) for f in FAMILIES]
    else:
        devices = [(f"profile {target.name}", target)]
    advices = {}
    for family, device in devices:
        cost = LiveCost(("CT", "MM", "AS", "IM"), device.motor, runs=3, frames=60 if quick
                        else 200)  # fmt: skip
        advices[family, device] = advise(
            device, quick=quick, refs=refs, cost_of=lambda s, c=cost: float(np.min(c(s)))
        )
    extra = _lead_notes(advices, refs, quick)
    extra += f" This part ran in {time.perf_counter() - t0:.0f} s."
    table = advice_table(advices, extra)
    show(table)
    return [*tables, table]


def _lead_notes(advices: dict, refs: References, quick: bool) -> str:
    """The lead: the recommended setting's onsets for frames for now (idle and busy host) and
    with the device's default lead."""
    texts = []
    for (_, device), advice in advices.items():
        if advice.chosen is None:
            continue
        s = advice.chosen.setting
        methods, shapes = (("AS",), ("line",)) if quick else (("CT", "MM", "AS", "IM"), SHAPES)
        onset = {}
        for label, setting in (("idle", s), ("busy", s.replace(host="busy")),
                               ("lead", s.replace(lead_ms=device.lead_ms))):  # fmt: skip
            runs = [felt_runs(setting, SCENES[sh], m, device.motor, phases=2 if quick else 8,
                              link=device.link(), refs=refs)
                    for m in methods for sh in shapes]  # fmt: skip
            onset[label] = spread(pool(runs, "onset_ms"), 1)
        texts.append(f"{device.name} {onset['idle']} ms idle, {onset['busy']} busy, "
                     f"{onset['lead']} with a {device.lead_ms:g} ms lead;")  # fmt: skip
    return (
        " Lead, at the recommended setting (onset error at the skin, median over the methods, "
        "for frames for now on an idle and on a busy host, and with the lead on either): "
        + " ".join(texts)
        + " Use the lead where onsets must not depend on the host (experiments, stimuli timed "
        "against other events): it delays every onset by itself and the host's load no longer "
        "reaches the skin. Use frames for now (lead 0) for interaction on an idle host, where "
        "onsets come sooner by the lead less the link's transmission."
    )
