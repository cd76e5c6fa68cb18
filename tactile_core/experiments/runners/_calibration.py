"""Per-tactor detection thresholds, and the device calibration they give (beyond the paper)."""

from __future__ import annotations

import statistics
from typing import ClassVar

from ...rendering.shapes import Line
from ..staircase import Staircase
from ._runner import HEALTH_FIELDS, Runner, Trial


class Calibration(Runner):
    """Per-tactor detection thresholds (beyond the paper; its section 4.2 calls for them).

    Each tactor in turn (in random order) vibrates alone for 0.5 s at a drive level set by a
    1-up/1-down staircase (start 0.5 of full drive, x 0.7 down after "felt", / 0.7 up after "not
    felt"), converging on the level felt half the time; a tactor's threshold is the mean of its
    last 6 reversals (after at most 24 trials). :meth:`calibration` turns the thresholds into
    the device profile's per-tactor offset and gain, so that the median tactor is left as it is
    and every other tactor's drive is mapped to feel like it.

    Parameters
    ----------
    session : Session
    grid : Grid, optional
        The array's tactors (the 5 x 6 palm array by default).
    write, profile
        As for every :class:`Runner`.
    """

    experiment = "calibration"
    fields = ("participant", "stage", "trial", "tactor", "level", "answer", "next_level",
              "rt_s", "time", *HEALTH_FIELDS)  # fmt: skip
    conditions: ClassVar[dict] = {"all": {"mu": 0.0, "gamma": 1.0}}
    MAX_TRIALS = 24
    REVERSALS = 8

    def __init__(self, session, grid=None, **kwargs):
        from ...rendering.geometry import Grid

        self.grid = grid or Grid()
        self.total = self.grid.size * self.MAX_TRIALS
        self.thresholds: dict[tuple, float] = {}
        super().__init__(session, **kwargs)

    def _trials(self):
        cells = [(c, r) for r in range(self.grid.rows) for c in range(self.grid.cols)]
        self.rng.shuffle(cells)
        for col, row in cells:
            sc = Staircase(0.5, 0.7, 1 / 0.7, 1, 1, min_level=0.02, max_level=1.0)
            centre = (col + 0.5, row + 0.5)
            for i in range(self.MAX_TRIALS):
                level = sc.level
                scene = self.make_scene(Line(centre, centre), "CT", 0.0, 1.0, duration_s=0.5,
                                        pause_s=0.0, repeat=False, gain=level)  # fmt: skip
                answer = yield Trial(
                    "calibration", f"c{col}r{row}", i, "detect",
                    "Did you feel a vibration? Y or N (R to feel it again).",
                    scene=scene, options=("yes", "no"),
                    info={"tactor": f"{col} {row}", "level": f"{level:.6g}"},
                )  # fmt: skip
                sc.update(answer == "yes")
                self._after = {"next_level": f"{sc.level:.6g}"}
                if len(sc.reversal_levels) >= self.REVERSALS:
                    break
            n = min(6, len(sc.reversal_levels))
            self.thresholds[(col, row)] = sc.estimate(n) if n else sc.level

    def _row(self, trial, answer):
        return {**trial.info, "answer": answer, **self._after}

    def calibration(self) -> tuple[list[float], list[float], list[float]]:
        """Per-tactor ``(offset, gain, threshold)`` in flat cell order from the measurements
        (:func:`calibration_from_thresholds`; every tactor must have been measured)."""
        if len(self.thresholds) < self.grid.size:
            raise ValueError(
                f"calibration needs all {self.grid.size} thresholds, has {len(self.thresholds)}"
            )
        return calibration_from_thresholds(self.thresholds, self.grid)


def calibration_from_thresholds(thresholds: dict, grid) -> tuple[list, list, list]:
    """Per-tactor ``(offset, gain, threshold)`` in flat cell order from detection thresholds.

    With a tactor's threshold ``th`` and the median threshold ``t_ref``, perceived intensity is
    modelled as linear in drive above threshold, ``(d - th) / (1 - th)``. Matching the median
    tactor at every corrected intensity ``I`` gives
    ``d = th + (1 - th) / (1 - t_ref) * (I - t_ref)``: gain ``(1 - th) / (1 - t_ref)`` and offset
    ``th - t_ref * gain``. ``I = t_ref`` maps to the tactor's own threshold and ``I = 1`` to full
    drive. A tactor without a threshold is left as it is (offset 0, gain 1) and given ``t_ref``.

    Parameters
    ----------
    thresholds : dict
        ``{(col, row): threshold}`` (drive fractions in [0, 1]); at least one.
    grid : Grid

    Returns
    -------
    offset, gain, threshold : list of float, each of length ``grid.size``
    """
    if not thresholds:
        raise ValueError("calibration needs at least one threshold")
    t_ref = statistics.median(thresholds.values())
    offset, gain, threshold = [], [], []
    for i in range(grid.size):
        cell = grid.cell(i)
        if cell not in thresholds:
            offset.append(0.0)
            gain.append(1.0)
            threshold.append(t_ref)
            continue
        th = thresholds[cell]
        g = (1.0 - th) / (1.0 - t_ref) if t_ref < 1.0 else 1.0
        offset.append(min(max(th - t_ref * g, -1.0), 1.0))
        gain.append(min(max(g, 1e-3), 10.0))
        threshold.append(th)
    return offset, gain, threshold
