"""Maximum-likelihood fits of a cumulative normal to the procedure's answers: each tactor's
threshold, the gamma of subjective equality, and the interval of their median."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._correction_record import GAMMA_MAX, GAMMA_MIN

CHI2_95 = 1.920729410347062  # chi2(1 df) 95% quantile / 2: the profile-likelihood drop


@dataclass(frozen=True)
class CumulativeFit:
    """Maximum-likelihood fit of a cumulative normal to binary answers (see
    :func:`fit_cumulative`).

    Attributes
    ----------
    location : float
        Where the underlying function crosses one half (the threshold, or the PSE).
    ci : tuple of float
        95% profile-likelihood interval of ``location``; an end the data do not bound is NaN.
    scale : float
        Standard deviation of the cumulative normal (the inverse slope), in units of ``x``.
    lapse : float
        Fitted lapse rate.
    log_likelihood : float
    trials : int
    p_flat : float
        p of the likelihood-ratio test against answers that do not depend on ``x`` (2 df):
        large when the answers look random.
    """

    location: float
    ci: tuple
    scale: float
    lapse: float
    log_likelihood: float
    trials: int
    p_flat: float

    @property
    def bounded(self) -> bool:
        """True when both ends of the interval are finite."""
        return all(math.isfinite(v) for v in self.ci)


LAPSES = (0.0, 0.02, 0.05)


def _loglik_grid(x, answers, guess, locations, scales, decreasing, lapses, relative=False):
    """``(log-likelihood, lapse)`` grids over ``locations x scales``, the lapse maximised."""
    from scipy.special import ndtr

    xs = np.asarray(x, dtype=np.float64)
    ys = np.asarray(answers, dtype=bool)
    if xs.ndim != 1 or xs.shape != ys.shape or xs.size < 2 or not np.isfinite(xs).all():
        raise ValueError(f"a psychometric fit needs at least 2 finite trials, got {xs.size}")
    loc = np.asarray(locations, dtype=np.float64)
    sc = np.asarray(scales, dtype=np.float64)
    best = np.full((loc.size, sc.size), -np.inf)
    best_lapse = np.zeros((loc.size, sc.size))
    # In blocks of locations, so that the (locations, scales, trials) arrays stay small enough
    # to be fast (a whole 401 x 24 x 3000 grid is 230 MB per array); answered "yes" and "no"
    # apart, so each takes only the logarithm it needs.
    x_yes, x_no = xs[ys], xs[~ys]
    block = max(1, 2_000_000 // max(sc.size * xs.size, 1))
    for start in range(0, loc.size, block):
        part = slice(start, start + block)
        lp = loc[part][:, None, None]
        spread = sc[None, :, None] * (lp if relative else 1.0)
        f_yes, f_no = (ndtr(-(v - lp) / spread if decreasing else (v - lp) / spread)
                       for v in (x_yes[None, None, :], x_no[None, None, :]))  # fmt: skip
        for lapse in lapses:
            p_yes = lapse / 2 + (1.0 - lapse) * (guess + (1.0 - guess) * f_yes)
            p_no = lapse / 2 + (1.0 - lapse) * (guess + (1.0 - guess) * f_no)
            ll = np.log(np.clip(p_yes, 1e-12, 1.0 - 1e-12)).sum(axis=-1)
            ll += np.log1p(-np.clip(p_no, 1e-12, 1.0 - 1e-12)).sum(axis=-1)
            better = ll > best[part]
            best[part] = np.where(better, ll, best[part])
            best_lapse[part] = np.where(better, lapse, best_lapse[part])
    return best, best_lapse


def _fit_from_grid(ll, lapse, answers, locations, scales, scale_index=None) -> CumulativeFit:
    """The fit at the grid's maximum (over every scale, or at ``scale_index``), its profile
    interval, and the test against flat answers."""
    loc = np.asarray(locations, dtype=np.float64)
    if scale_index is None:
        profile = ll.max(axis=1)
        i, j = np.unravel_index(np.argmax(ll), ll.shape)
    else:
        j = scale_index
        profile = ll[:, j]
        i = int(np.argmax(profile))
    top = ll[i, j]
    inside = profile >= top - CHI2_95
    lo_i = i
    while lo_i > 0 and inside[lo_i - 1]:
        lo_i -= 1
    hi_i = i
    while hi_i < loc.size - 1 and inside[hi_i + 1]:
        hi_i += 1
    lo = math.nan if lo_i == 0 else float(loc[lo_i])
    hi = math.nan if hi_i == loc.size - 1 else float(loc[hi_i])
    ys = np.asarray(answers, dtype=bool)
    k, n = int(ys.sum()), int(ys.size)
    flat = sum(c * math.log(c / n) for c in (k, n - k) if c)
    p_flat = math.exp(-max(top - flat, 0.0))  # chi-square with 2 df: sf(x) = exp(-x / 2)
    return CumulativeFit(float(loc[i]), (lo, hi), float(scales[j]), float(lapse[i, j]),
                         float(top), n, p_flat)  # fmt: skip


def fit_cumulative(x, answers, *, guess: float, locations, scales, decreasing: bool = False,
                   lapses=LAPSES, relative: bool = False) -> CumulativeFit:  # fmt: skip
    """Fit ``p(x) = lapse/2 + (1 - lapse) (guess + (1 - guess) Phi(+-(x - location) / scale))``.

    A grid search (vectorised; exact to the grid's step) over ``locations`` x ``scales`` x
    ``lapses``: robust on the short, clustered tracks a staircase leaves, where a local
    optimiser can run off. ``guess`` is 0.5 for a two-interval detection (the chance of picking
    the right interval without feeling anything) and 0 for "which was stronger"; a lapse is a
    coin toss.

    Parameters
    ----------
    x : array_like of float, shape (n,)
        The stimulus value of each trial.
    answers : array_like of bool, shape (n,)
        Correct (detection) or "the test was stronger" (constancy).
    guess : float
        In [0, 1).
    locations, scales : array_like of float
        The grids searched (ascending; scales > 0).
    decreasing : bool
        True when ``p`` falls as ``x`` grows (the test weakens as gamma grows).
    lapses : sequence of float
    relative : bool
        The scale is a fraction of the location (``Phi((x - location) / (scale location))``),
        for a spread that grows with the location (gamma).

    Returns
    -------
    CumulativeFit
    """
    ll, lapse = _loglik_grid(x, answers, guess, locations, scales, decreasing, lapses, relative)
    return _fit_from_grid(ll, lapse, answers, locations, scales)


def fit_shared_scale(tracks, *, guess: float, locations, scales, decreasing: bool = False,
                     lapses=LAPSES) -> list[CumulativeFit]:  # fmt: skip
    """Fit several tracks with one common scale (slope) and a location each.

    The tactors of one participant share a slope; a short staircase track alone cannot tell a
    shallow function far away from a steep one nearby, and a lucky guess at a low level can
    then pull its location to the bottom of the grid. The common scale maximises the summed
    profile likelihood of the tracks; each location (and its interval) is then fitted at it.

    Parameters
    ----------
    tracks : sequence of (x, answers)
        One pair of arrays per track, as for :func:`fit_cumulative`.
    guess, locations, scales, decreasing, lapses
        As for :func:`fit_cumulative`.

    Returns
    -------
    list of CumulativeFit
        One per track, in order, all with the same ``scale``.
    """
    grids = [_loglik_grid(x, a, guess, locations, scales, decreasing, lapses) for x, a in tracks]
    total = sum(ll.max(axis=0) for ll, _ in grids)
    j = int(np.argmax(total))
    return [_fit_from_grid(ll, lapse, a, locations, scales, scale_index=j)
            for (ll, lapse), (_, a) in zip(grids, tracks)]  # fmt: skip


THRESHOLD_LOCATIONS = np.linspace(0.0, 1.0, 401)
THRESHOLD_SCALES = np.geomspace(0.004, 0.4, 24)
GAMMA_LOCATIONS = np.geomspace(GAMMA_MIN, GAMMA_MAX, 601)
GAMMA_SCALES = np.geomspace(0.02, 3.0, 24)


def fit_thresholds(tracks) -> list[CumulativeFit]:
    """Each tactor's threshold, the drive felt half the time (75% correct in two intervals),
    with a slope common to the tactors (:func:`fit_shared_scale`).

    Parameters
    ----------
    tracks : sequence of (drives, correct)
        Per tactor: the drive of each trial (fraction of full drive, shape (n,)) and whether
        the interval was picked right (shape (n,)).

    Returns
    -------
    list of CumulativeFit
        One per track; ``location`` is the threshold, a drive fraction.
    """
    return fit_shared_scale(tracks, guess=0.5, locations=THRESHOLD_LOCATIONS,
                            scales=THRESHOLD_SCALES)  # fmt: skip


def fit_gamma(gammas, test_stronger) -> CumulativeFit:
    """The gamma of subjective equality.

    Fitted in gamma itself, with a spread proportional to it: under the model the felt
    difference between the test point and the tactor is linear in gamma (``ln M_test -
    ln M_tactor = ln(n) / 2 - K gamma ln(n)`` for ``n`` tactors at ``1 / n``), so the
    psychometric function is symmetric in gamma, not in ``ln gamma``; a fit in ``ln gamma``
    lands ~5% low on such data. The track still steps in log units.

    Parameters
    ----------
    gammas : array_like of float, shape (n,)
        The candidate gamma of each trial.
    test_stronger : array_like of bool, shape (n,)
        Whether the point between tactors felt stronger than the point on one.

    Returns
    -------
    CumulativeFit
        ``location`` is the gamma of subjective equality.
    """
    return fit_cumulative(gammas, test_stronger, guess=0.0, locations=GAMMA_LOCATIONS,
                          scales=GAMMA_SCALES, decreasing=True, relative=True)  # fmt: skip


def median_interval(fits, seed: int = 0, draws: int = 4000) -> tuple[float, float]:
    """95% interval of the median of several fitted locations.

    A parametric bootstrap: each location is drawn from a normal whose standard deviation is its
    profile interval's width / 3.92 (an open end counts as the grid's end), the median taken, and
    the 2.5th and 97.5th percentiles of the medians reported. It carries the measurement error
    of each tactor's threshold into mu.

    Parameters
    ----------
    fits : sequence of CumulativeFit
        One per tactor (thresholds, drive fractions).
    seed : int
        Seeds the draws.
    draws : int
        Bootstrap samples.

    Returns
    -------
    (float, float)
        The interval's ends, drive fractions.
    """
    rng = np.random.default_rng(seed)
    loc = np.array([f.location for f in fits])
    lo = np.array([f.ci[0] if math.isfinite(f.ci[0]) else THRESHOLD_LOCATIONS[0] for f in fits])
    hi = np.array([f.ci[1] if math.isfinite(f.ci[1]) else THRESHOLD_LOCATIONS[-1] for f in fits])
    se = np.maximum(hi - lo, 1e-6) / 3.92
    samples = np.median(rng.normal(loc, se, size=(draws, loc.size)), axis=1)
    return float(np.percentile(samples, 2.5)), float(np.percentile(samples, 97.5))
