"""What the current setting costs in felt terms: one row of the trade table for the scene on
the array (the tuner's read-out).

The scene's shape, method, correction and trace duration, the pipeline it sets (frame rate,
capped by the link as the streamer caps it; filter; dithering; motor-aware drive) and the
lead, at the profile's levels and through its motors (the palm array's estimates when it has
none), against the best of three settings on the same array: the current one, with motor-aware
drive, and at the fastest rate the link carries (up to 1000 Hz) with motor-aware drive.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._trade_model import References, Setting, felt_runs
from ._trade_target import Target

MAX_TRACE_S = 20.0
"""Longest trace the read-out predicts (a longer one only costs more to compute)."""


@dataclass(frozen=True)
class FeltReadout:
    """The felt figures of the current setting and the best of the array.

    Attributes
    ----------
    ripple, lag_mm, onset_ms : float
        The current setting's felt ripple, centroid lag (mm) and onset error at the skin (ms),
        each the mean over the phases.
    best : (float, float, float)
        The best of each over the settings compared.
    setting : Setting
        The current setting as predicted (its rate capped by the link).
    motor_label : str
        The motor constants assumed (``"30/60 ms"``).
    motor_source : str
        Where they come from: ``"estimate"``, or ``"measured 2026-05-01"`` (``tactile
        measure``).
    """

    ripple: float
    lag_mm: float
    onset_ms: float
    best: tuple
    setting: Setting
    motor_label: str
    motor_source: str = "estimate"

    @property
    def text(self) -> str:
        """``"felt ripple 1.14 (best 1.09), lag 1.8 mm (best 0.6), onset +23 ms at 300 Hz /
        23 levels"``."""
        onset = "no onset" if np.isnan(self.onset_ms) else f"onset +{self.onset_ms:.0f} ms"
        ripple = (f"felt ripple {self.ripple:.2f} (best {self.best[0]:.2f})"
                  if np.isfinite(self.ripple) else "felt with gaps")  # fmt: skip
        return (f"{ripple}, lag {self.lag_mm:.1f} mm (best {self.best[1]:.1f}), {onset} at "
                f"{self.setting.rate_hz:.4g} Hz / {self.setting.levels} levels")  # fmt: skip


def felt_readout(scene, profile, lead_ms: float = 0.0, *, phases: int = 2, seed: int = 0,
                 refs: References | None = None) -> FeltReadout | None:  # fmt: skip
    """The felt cost of ``scene`` on ``profile``'s array, or None where the model does not
    reach (no shape: an idle scene or a live source; actuators that are not a grid; a trace
    longer than :data:`MAX_TRACE_S`).

    Parameters
    ----------
    scene : Scene
    profile : DeviceProfile
    lead_ms : float
        The lead the stream uses (0: frames for now, on an idle host).
    phases, seed : int
        As for :func:`~._trade_model.felt_runs` (2: a fraction of a second on the palm array).
    refs : References, optional
        Continuous references kept between calls.

    Returns
    -------
    FeltReadout or None
    """
    grid = profile.layout
    if scene.shape is None or scene.source is not None or not grid.is_grid:
        return None
    if scene.duration_s > MAX_TRACE_S:
        return None
    target = Target.of(profile)
    has_motor = profile.motor is not None
    compensate = scene.compensate_motors and has_motor
    current = Setting(rate_hz=min(scene.rate_hz, target.max_rate_hz), filter=scene.filter,
                      subsamples=scene.subsamples, levels=target.levels, dither=scene.dither,
                      lead_ms=lead_ms, compensate=compensate)  # fmt: skip
    fastest = min(1000.0, target.max_rate_hz)
    others = [current.replace(compensate=True), current.replace(rate_hz=fastest, compensate=True)]
    settings = [current, *(others if has_motor else [current.replace(rate_hz=fastest)])]
    refs = refs or References()
    figures = []
    for setting in settings:
        runs = felt_runs(setting, scene.shape, scene.method, target.motor, phases=phases,
                         seed=seed, link=target.link(), refs=refs, duration_s=scene.duration_s,
                         correction=(scene.mu, scene.gamma), grid=grid,
                         pitch_mm=profile.array.pitch_mm)  # fmt: skip
        onset = runs.onset_ms[~np.isnan(runs.onset_ms)]
        figures.append((float(np.mean(runs.ripple)), float(np.mean(runs.lag_mm)),
                        float(onset.mean()) if onset.size else np.nan))  # fmt: skip
    table = np.array(figures)
    best = tuple(float(np.min(col[~np.isnan(col)])) if (~np.isnan(col)).any() else np.nan
                 for col in table.T)  # fmt: skip
    return FeltReadout(*figures[0], best, current, target.motor_label, target.motor_source)
