"""What the procedure presents: how many trials each part gets, which tactors it measures and
where on the array the constancy stimuli go."""

from __future__ import annotations

from dataclasses import dataclass

from ..._shared import validate as _validate

THRESHOLD_PROCEDURES = ("staircase", "quest+")
"""The threshold procedures a plan may choose (:attr:`TuningPlan.threshold_procedure`)."""


@dataclass(frozen=True)
class TuningPlan:
    """How many trials each part of the procedure gets.

    Attributes
    ----------
    threshold_trials : int
        Per tactor (2..200).
    gamma_trials : int
        Per place (2..400), at each of the two places.
    corner_trials : int
        At the cell corner, the validation (0..400; 0 skips it).
    tactors : tuple of (col, row), optional
        The tactors whose thresholds are measured; default: five across the array
        (:func:`default_layout`).
    threshold_procedure : {"staircase", "quest+"}
        How each tactor's levels are placed: the 3-down/1-up track over the device's levels
        (the default), or QUEST+ (Watson 2017, the ``questplus`` package) over the same levels,
        each trial at the level expected to shrink the posterior's entropy most. Either way the
        threshold is the same maximum-likelihood fit to the tactor's trials.
    """

    threshold_trials: int = 20
    gamma_trials: int = 40
    corner_trials: int = 12
    tactors: tuple | None = None
    threshold_procedure: str = "staircase"

    def __post_init__(self):
        _validate.integer("threshold_trials", self.threshold_trials, 2, 200)
        _validate.integer("gamma_trials", self.gamma_trials, 2, 400)
        _validate.integer("corner_trials", self.corner_trials, 0, 400)
        _validate.choice("threshold_procedure", self.threshold_procedure, THRESHOLD_PROCEDURES)

    def to_dict(self) -> dict:
        """The JSON form (recorded in ``session.json``)."""
        return {
            "threshold_trials": self.threshold_trials,
            "gamma_trials": self.gamma_trials,
            "corner_trials": self.corner_trials,
            "tactors": None if self.tactors is None else [list(c) for c in self.tactors],
            "threshold_procedure": self.threshold_procedure,
        }


def default_layout(grid) -> tuple[tuple, dict]:
    """The tactors measured and the constancy places on ``grid`` (at least 3 x 3).

    On the 5 x 6 palm array: tactors (1,1), (3,1), (2,2), (1,4), (3,4); the pair side by side
    is (1,2)-(2,2) (test point (2.0, 2.5), reference on (1,2)); the pair above each other is
    (3,3)-(3,4) (test point (3.5, 4.0), reference on (3,3)); the corner joins (1,3), (2,3), (1,4)
    and (2,4) (test point (2.0, 4.0), reference on (1,3)).

    Returns
    -------
    tactors : tuple of (col, row)
    places : dict
        ``{name: {"point": (x, y), "reference": (x, y), "start": gamma}}``.
    """
    if not grid.is_grid:
        raise ValueError(
            f"tuning the correction needs a grid of at least 3 x 3 (its checks sit between "
            f"tactors in rows and columns), got a layout: {grid.describe()}"
        )
    cols, rows = grid.cols, grid.rows
    if cols < 3 or rows < 3:
        raise ValueError(
            f"tuning the correction needs a grid of at least 3 x 3, got {cols} x {rows}"
        )
    lo_c, lo_r = max(0, round((cols - 1) / 4)), max(0, round((rows - 1) / 4))
    hi_c, hi_r = cols - 1 - lo_c, rows - 1 - lo_r
    mid_c, mid_r = (cols - 1) // 2, (rows - 1) // 2
    tactors = tuple(dict.fromkeys(
        [(lo_c, lo_r), (hi_c, lo_r), (mid_c, mid_r), (lo_c, hi_r), (hi_c, hi_r)]
    ))  # fmt: skip
    h_c = min(lo_c, cols - 2)
    r1 = min(mid_r + 1, rows - 2)
    corner_c = max(mid_c, 1)
    places = {
        "side": {"point": (h_c + 1.0, mid_r + 0.5), "reference": (h_c + 0.5, mid_r + 0.5),
                 "start": 0.35},
        "above": {"point": (hi_c + 0.5, r1 + 1.0), "reference": (hi_c + 0.5, r1 + 0.5),
                  "start": 1.4},
        "corner": {"point": (float(corner_c), r1 + 1.0),
                   "reference": (corner_c - 0.5, r1 + 0.5), "start": 0.7},
    }  # fmt: skip
    return tactors, places
