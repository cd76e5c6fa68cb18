"""What the procedure found: the correction, its intervals, and what to tell the user."""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass
class TuningResult:
    """What the procedure found.

    Attributes
    ----------
    ok : bool
        False when it could not find a correction (``message`` says why; ``mu`` and ``gamma`` are
        then None and nothing may be applied).
    message : str
    mu, gamma : float or None
    mu_ci, gamma_ci : tuple of float
        95% intervals (NaN for an end the data did not bound).
    trials : int
        Answers given (instructions not counted).
    thresholds : dict
        ``{"col,row": {"threshold", "ci", "trials", "felt"}}`` per tactor measured.
    places : dict
        ``{place: {"gamma", "ci", "trials"}}`` per constancy place, the corner included.
    corner_agrees : bool or None
        Whether gamma lies within the corner's interval (None without a corner track).
    warnings : list of str
    """

    ok: bool
    message: str
    mu: float | None = None
    gamma: float | None = None
    mu_ci: tuple = (math.nan, math.nan)
    gamma_ci: tuple = (math.nan, math.nan)
    trials: int = 0
    thresholds: dict = field(default_factory=dict)
    places: dict = field(default_factory=dict)
    corner_agrees: bool | None = None
    warnings: list = field(default_factory=list)

    def to_dict(self) -> dict:
        """JSON form (NaN written as null)."""

        def clean(value):
            if isinstance(value, float):
                return value if math.isfinite(value) else None
            if isinstance(value, (list, tuple)):
                return [clean(v) for v in value]
            if isinstance(value, dict):
                return {k: clean(v) for k, v in value.items()}
            return value

        return clean({
            "ok": self.ok, "message": self.message, "mu": self.mu, "mu_ci": list(self.mu_ci),
            "gamma": self.gamma, "gamma_ci": list(self.gamma_ci), "trials": self.trials,
            "thresholds": self.thresholds, "places": self.places,
            "corner_agrees": self.corner_agrees, "warnings": self.warnings,
        })  # fmt: skip

    def summary(self) -> str:
        """A few lines for a terminal or a dialog."""
        if not self.ok:
            return f"No correction: {self.message}"
        lines = [
            f"mu    {self.mu:.3f}  (95% {_interval(self.mu_ci, '.3f')})",
            f"gamma {self.gamma:.3f}  (95% {_interval(self.gamma_ci, '.3f')})",
            f"{self.trials} trials",
        ]
        for cell, t in self.thresholds.items():
            felt = "" if t["felt"] else f"  ({t['problem']}: left out)"
            lines.append(f"  threshold at ({cell}): {t['threshold']:.3f} "
                         f"({_interval(t['ci'], '.3f')}){felt}")  # fmt: skip
        for name, p in self.places.items():
            lines.append(f"  gamma at {name}: {p['gamma']:.3f} ({_interval(p['ci'], '.3f')})")
        lines += [f"note: {w}" for w in self.warnings]
        return "\n".join(lines)


def _interval(ci, fmt: str) -> str:
    return " .. ".join("open" if not math.isfinite(v) else format(v, fmt) for v in ci)
