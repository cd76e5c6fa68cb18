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
        The cheapest candidate within the tolerance of the best (None: none is).
    best : dict
        ``{method: (ripple, lag_mm, onset_ms)}``: each figure's best over the candidates.
    tolerance : Tolerance
    candidates : tuple of Candidate
        What was measured.
    basis : str
        What the figures are over (methods, shapes, phases), for the table's notes.
    """

    chosen: Candidate | None
    best: dict
    tolerance: Tolerance
    candidates: tuple = ()
    basis: str = ""

    def excess(self, c: Candidate) -> tuple:
        """``c``'s largest excess over the best among the methods, per figure (ripple, lag mm,
        onset ms); a figure no candidate has (NaN best) does not count."""
        worst = [0.0, 0.0, 0.0]
        for method, best in self.best.items():
            got = c.figures.get(method, (np.nan,) * 3)
            for i in range(3):
                if np.isnan(best[i]):
                    continue
                gap = got[i] - best[i] if np.isfinite(got[i]) else np.inf
                worst[i] = max(worst[i], gap)
        return tuple(worst)


def within(excess: tuple, tol: Tolerance) -> bool:
    """True when a candidate's :meth:`Advice.excess` is within ``tol`` on every figure."""
    return (excess[0] <= tol.ripple and excess[1] <= tol.lag_mm
            and excess[2] <= tol.onset_ms)  # fmt: skip


def recommend(candidates, tolerance: Tolerance = Tolerance()) -> Advice:
    """The cheapest candidate whose felt figures are within ``tolerance`` of the best, for
    every method.

    Parameters
    ----------
    candidates : iterable of Candidate
        Measured settings (a non-finite figure never passes).
    tolerance : Tolerance

    Returns
    -------
    Advice
        ``best`` holds each method's minimum of each figure over the candidates; ``chosen`` is
        the one with the lowest :attr:`Candidate.price` among those whose every method is
        within the tolerance of that method's best on every figure.

    Examples
    --------
    >>> fast = Candidate(Setting(rate_hz=300), {"AS": (1.10, 0.6, 11.0)}, cost_us=3.0)
    >>> slow = Candidate(Setting(rate_hz=50), {"AS": (1.11, 0.9, 14.0)}, cost_us=3.0)
    >>> recommend([fast, slow]).chosen.setting.rate_hz
    50.0
    """
    candidates = tuple(candidates)
    methods = sorted({m for c in candidates for m in c.figures})
    best = {}
    for m in methods:
        values = np.array([c.figures.get(m, (np.nan,) * 3) for c in candidates], dtype=float)
        values[~np.isfinite(values)] = np.nan
        best[m] = tuple(float(np.min(v[~np.isnan(v)])) if (~np.isnan(v)).any() else np.nan
                        for v in values.T)  # fmt: skip
    advice = Advice(None, best, tolerance, candidates)
    passing = [c for c in candidates if within(advice.excess(c), tolerance)]
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
    levels, frames for now (the lead is advised apart), pooled over the paper's four methods on
    the Experiment 1 line and circle and the Experiment 3 square. The fastest rate's candidates
    are measured first, then the rates from the slowest up until one has a candidate within the
    tolerance (no slower rate had one, so it is the cheapest of the whole set).

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
    for rate in rates[:-1]:
        measure(rate)
        advice = recommend(measured, tolerance)
        if advice.chosen is not None and advice.chosen.setting.rate_hz == rate:
            return replace(advice, basis=basis)
    return replace(recommend(measured, tolerance), basis=basis)


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
            why = "no rate the link carries" if not advice.candidates else "none within"
            rows.append([family, target.name, target.motor_label, why, "", "", "", "", ""])
            continue
        ripple, lag, onset = c.median()
        excess = advice.excess(c)
        rows.append([
            family, target.name, target.motor_label, setting_words(c.setting),
            f"{ripple:.3f} / {lag:.2f} / {onset:.1f}",
            f"+{excess[0]:.3f} / +{excess[1]:.2f} / +{excess[2]:.1f}", f"{c.cost_us:.2f}",
            target.link_label(c.setting), f"{len(advice.candidates)}",
        ])  # fmt: skip
    first = next(iter(advices.values()), None)
    tol = first.tolerance if first else Tolerance()
    headers = ["actuators", "profile", "motor tau up/down", "recommended setting",
               "felt ripple / lag mm / onset ms (median over methods)",
               "largest excess over the best (any method)", "cost us/frame", "link bytes/s",
               "settings measured"]  # fmt: skip
    notes = (
        f"The cheapest setting (fewest frames a second, then levels, CPU, bytes) whose felt "
        f"ripple is within {tol.ripple:g}, centroid lag within {tol.lag_mm:g} mm and onset "
        f"error within {tol.onset_ms:g} ms of the best measured, for every method: each "
        "method's figures (the mean over the shapes and phases) against that method's best "
        f"over the candidates; {first.basis if first else ''}, through the profile's motor "
        "constants (column 3), the reference participant. Candidates: the rates the link "
        f"carries among {', '.join(map(str, CANDIDATE_RATES_HZ))} Hz x point / box S=4 x "
        "rounded / dithered x plain / motor-aware drive, at the device's levels, frames for "
        "now (onsets include the link's transmission); the lead is advised below." + notes_extra
    )
    return Table("Recommended settings per device", headers, rows, notes)
