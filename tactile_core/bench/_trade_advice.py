"""The recommended setting for a device: the cheapest whose felt error is within a stated
tolerance of the best measured.

:func:`recommend` is the rule, on numbers alone (tested on hand-made tables); :func:`advise`
measures the candidates for a :class:`~._trade_target.Target` and applies it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ._common import SCENES, Table
from ._trade_model import Setting, felt_runs, pool

CANDIDATE_RATES_HZ = (20, 25, 30, 40, 50, 100, 200, 300, 1000)
"""Frame rates a recommendation chooses among (those the link carries)."""


@dataclass(frozen=True)
class Tolerance:
    """How far from the best measured a setting's felt figures may be.

    Attributes
    ----------
    ripple : float
        Felt ripple (ratio units) above the best.
    lag_mm : float
        Felt centroid lag above the best, mm.
    onset_ms : float
        Onset error at the skin above the best, ms.
    """

    ripple: float = 0.02
    lag_mm: float = 0.5
    onset_ms: float = 5.0


@dataclass(frozen=True)
class Candidate:
    """One setting's felt figures per method and what it costs.

    Attributes
    ----------
    setting : Setting
    figures : dict
        ``{method: (ripple, lag_mm, onset_ms)}``, each over the shapes and phases (one key
        ``"all"`` for figures pooled already).
    cost_us : float
        CPU per frame on the live path.
    bytes_per_s : float
        On the link.
    """

    setting: Setting
    figures: dict
    cost_us: float = 0.0
    bytes_per_s: float = 0.0

    @property
    def price(self) -> tuple:
        """What makes a setting cheaper: fewer frames a second, then fewer levels, then less
        CPU per frame, then fewer bytes."""
        s = self.setting
        return (s.rate_hz, s.levels, self.cost_us, self.bytes_per_s)

    def median(self) -> tuple:
        """``(ripple, lag_mm, onset_ms)``: each figure's median over the methods."""
        values = np.array(list(self.figures.values()), dtype=float)
        with np.errstate(all="ignore"):
            return tuple(float(np.median(v[~np.isnan(v)])) if (~np.isnan(v)).any() else np.nan
                         for v in values.T)  # fmt: skip


@dataclass(frozen=True)
class Advice:
    """A recommendation.

    Attributes
    ----------
    chosen : Candidate or None
        The cheapest candidate within the tolerance of the best setting (None: no candidates).
    best : Candidate or None
        The best setting measured: the one nearest to every method's best of every figure
        (see :func:`recommend`).
    tolerance : Tolerance
    candidates : tuple of Candidate
        What was measured.
    basis : str
        What the figures are over (methods, shapes, phases), for the table's notes.
    """

    chosen: Candidate | None
    best: Candidate | None
    tolerance: Tolerance
    candidates: tuple = ()
    basis: str = ""

    def excess(self, c: Candidate) -> tuple:
        """``c``'s figures less the best setting's, the largest among the methods, per figure
        (ripple, lag mm, onset ms); negative where ``c`` is better on every method."""
        return excess(c, self.best.figures) if self.best is not None else (np.nan,) * 3


def excess(c: Candidate, reference: dict) -> tuple:
    """``c``'s figures less ``reference`` (``{method: (ripple, lag_mm, onset_ms)}``), the
    largest among the methods, per figure; a figure the reference lacks (NaN) does not count,
    one ``c`` lacks (NaN, inf) is an infinite excess."""
    worst = [-np.inf] * 3
    for method, ref in reference.items():
        got = c.figures.get(method, (np.nan,) * 3)
        for i in range(3):
            if not np.isfinite(ref[i]):
                continue
            worst[i] = max(worst[i], got[i] - ref[i] if np.isfinite(got[i]) else np.inf)
    return tuple(0.0 if w == -np.inf else float(w) for w in worst)


def within(gap: tuple, tol: Tolerance) -> bool:
    """True when an :func:`excess` is within ``tol`` on every figure."""
    return gap[0] <= tol.ripple and gap[1] <= tol.lag_mm and gap[2] <= tol.onset_ms


def recommend(candidates, tolerance: Tolerance = Tolerance(), best_among=None) -> Advice:
    """The cheapest candidate whose felt figures are within ``tolerance`` of the best setting
    measured, for every method.

    The *best setting* is the candidate nearest to the best of everything: for each method and
    figure the minimum over the candidates; each candidate's largest excess over those minima,
    in units of the tolerance (ripple / 0.02, lag / 0.5 mm, onset / 5 ms), over the methods and
    figures; the best has the least (the per-figure minima may come from different settings:
    a box filter at 20 Hz gives CT its earliest onsets and its worst ripple).

    Parameters
    ----------
    candidates : iterable of Candidate
        Measured settings (a non-finite figure never passes).
    tolerance : Tolerance
    best_among : iterable of Candidate, optional
        Where the best setting is looked for (default: among all the candidates).

    Returns
    -------
    Advice
        ``chosen`` is the one with the lowest :attr:`Candidate.price` among those whose every
        method is within the tolerance of the best setting's on every figure (the best setting
        itself is, so there is one whenever there are candidates).

    Examples
    --------
    >>> fast = Candidate(Setting(rate_hz=300), {"AS": (1.10, 0.6, 11.0)}, cost_us=3.0)
    >>> slow = Candidate(Setting(rate_hz=50), {"AS": (1.11, 0.9, 14.0)}, cost_us=3.0)
    >>> recommend([fast, slow]).chosen.setting.rate_hz
    50.0
    """
    candidates = tuple(candidates)
    if not candidates:
        return Advice(None, None, tolerance)
    pool_ = candidates if best_among is None else tuple(best_among)
    methods = sorted({m for c in pool_ for m in c.figures})
    minima = {}
    for m in methods:
        values = np.array([c.figures.get(m, (np.nan,) * 3) for c in pool_], dtype=float)
        values[~np.isfinite(values)] = np.nan
        minima[m] = tuple(float(np.min(v[~np.isnan(v)])) if (~np.isnan(v)).any() else np.nan
                          for v in values.T)  # fmt: skip
    scale = (tolerance.ripple, tolerance.lag_mm, tolerance.onset_ms)

    def distance(c):
        return max(g / t for g, t in zip(excess(c, minima), scale))

    best = min(pool_, key=lambda c: (distance(c), c.price))
    passing = [c for c in candidates if within(excess(c, best.figures), tolerance)]
    chosen = min(passing, key=lambda c: c.price) if passing else None
    return Advice(chosen, best, tolerance, candidates)


def _combos(quick: bool):
    """The pipeline options tried at each rate: filter x dithering x motor-aware drive."""
    filters = ("point",) if quick else ("point", "box")
    dithers = (False,) if quick else (False, True)
    return [dict(filter=f, dither=d, compensate=c)
            for f in filters for d in dithers for c in (False, True)]  # fmt: skip


def advise(target, *, quick: bool = False, phases: int = 8, seed: int = 0, refs=None,
           cost_of=None, tolerance: Tolerance = Tolerance()) -> Advice:  # fmt: skip
    """Measure candidate settings for ``target`` and :func:`recommend` one.

    The candidates are the rates of :data:`CANDIDATE_RATES_HZ` the link carries, each with the
    point and box filters, rounding and dithering, plain and motor-aware drive, at the device's
    levels, frames for now (the lead is advised apart), each of the paper's four methods over
    the Experiment 1 line and circle and the Experiment 3 square. The fastest rate's candidates
    are measured first and the best setting is the best of them (:func:`recommend`); then the
    rates from the slowest up until one has a candidate within the tolerance of it (no slower
    rate had one, so it is the cheapest of the whole set).

    Parameters
    ----------
    target : Target
    quick : bool
        Three rates, point sampling and rounding, AS on the line, 2 phases.
    phases, seed : int
        As for :func:`~._trade_model.felt_runs`.
    refs : References, optional
    cost_of : callable, optional
        ``cost_of(setting) -> us per frame``; 0 without it.
    tolerance : Tolerance
    """
    methods = ("AS",) if quick else ("CT", "MM", "AS", "IM")
    shapes = ("line",) if quick else ("line", "circle", "square")
    phases = 2 if quick else phases
    rates = (25, 100, 300) if quick else CANDIDATE_RATES_HZ
    base = Setting(levels=target.levels)
    rates = [r for r in rates if target.carries(base.replace(rate_hz=r))]
    measured = []

    def measure(rate):
        for combo in _combos(quick):
            setting = base.replace(rate_hz=rate, **combo)
            figures = {}
            for m in methods:
                runs = [felt_runs(setting, SCENES[s], m, target.motor, phases=phases, seed=seed,
                                  link=target.link(), refs=refs) for s in shapes]  # fmt: skip
                figures[m] = tuple(float(np.mean(pool(runs, k, "mean")))
                                   for k in ("ripple", "lag_mm", "onset_ms"))  # fmt: skip
            cost = cost_of(setting) if cost_of else 0.0
            measured.append(Candidate(setting, figures, cost, target.bytes_per_s(setting)))

    basis = f"{', '.join(methods)} on {', '.join(shapes)} ({phases} phases)"
    if not rates:
        return replace(recommend([], tolerance), basis=basis)
    measure(rates[-1])
    fastest = tuple(measured)
    for rate in rates[:-1]:
        measure(rate)
        advice = recommend(measured, tolerance, best_among=fastest)
        if advice.chosen is not None and advice.chosen.setting.rate_hz == rate:
            return replace(advice, basis=basis)
    return replace(recommend(measured, tolerance, best_among=fastest), basis=basis)


def setting_words(s: Setting) -> str:
    """``"40 Hz, point, 23 levels, rounded, motor-aware drive"``."""
    return (f"{s.rate_hz:g} Hz, {s.sampling.label}, {s.levels} levels, "
            f"{'dithered' if s.dither else 'rounded'}, "
            f"{'motor-aware' if s.compensate else 'plain'} drive")  # fmt: skip


def advice_table(advices: dict, notes_extra: str = "") -> Table:
    """The recommendations, one row per device: ``{(family, Target): Advice}``."""
    rows = []
    for (family, target), advice in advices.items():
        c = advice.chosen
        if c is None:
            rows.append([family, target.name, target.motor_label, "no rate the link carries",
                         "", "", "", "", "", ""])  # fmt: skip
            continue
        ripple, lag, onset = c.median()
        gap = advice.excess(c)
        rows.append([
            family, target.name, target.motor_label, setting_words(c.setting),
            f"{ripple:.3f} / {lag:.2f} / {onset:.1f}", setting_words(advice.best.setting),
            f"{gap[0]:+.3f} / {gap[1]:+.2f} / {gap[2]:+.1f}", f"{c.cost_us:.2f}",
            target.link_label(c.setting), f"{len(advice.candidates)}",
        ])  # fmt: skip
    first = next(iter(advices.values()), None)
    tol = first.tolerance if first else Tolerance()
    headers = ["actuators", "profile", "motor tau up/down", "recommended setting",
               "felt ripple / lag mm / onset ms (median over methods)", "best setting measured",
               "its excess over the best (largest over methods)", "cost us/frame",
               "link bytes/s", "settings measured"]  # fmt: skip
    notes = (
        f"The cheapest setting (fewest frames a second, then levels, CPU, bytes) whose felt "
        f"ripple is within {tol.ripple:g}, centroid lag within {tol.lag_mm:g} mm and onset "
        f"error within {tol.onset_ms:g} ms of the best setting measured, for every method: "
        "each method's figures (the mean over the shapes and phases) against the best "
        "setting's for that method. The best setting: among the candidates at the fastest rate "
        "the link carries, the one nearest to every method's best of every figure, counted in "
        "tolerances (the largest excess over those bests, divided by the tolerance, is least). "
        f"{first.basis if first else ''}, through the "
        "profile's motor "
        "constants (column 3), the reference participant. Candidates: the rates the link "
        f"carries among {', '.join(map(str, CANDIDATE_RATES_HZ))} Hz x point / box S=4 x "
        "rounded / dithered x plain / motor-aware drive, at the device's levels, frames for "
        "now (onsets include the link's transmission); the lead is advised below." + notes_extra
    )
    return Table("Recommended settings per device", headers, rows, notes)
