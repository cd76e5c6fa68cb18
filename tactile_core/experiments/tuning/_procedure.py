"""The procedure as a runner: the threshold tracks, then the constancy tracks, and the estimates
of mu and gamma (see the package notes)."""

from __future__ import annotations

import math
import statistics
from typing import ClassVar

from ...rendering.shapes import Line
from .._correction_record import GAMMA_MAX, GAMMA_MIN, MU_MAX
from ..results import Session
from ..runners import HEALTH_FIELDS, INTERVAL_S, Runner, Trial, calibration_from_thresholds
from ._fits import fit_gamma, fit_thresholds, median_interval
from ._plan import TuningPlan, default_layout
from ._result import TuningResult, _interval
from ._tracks import _LevelTrack, _LogTrack, _QuestTrack

EXPERIMENT = "correction"


def mu_from_tracks(tactors, tracks) -> tuple[float | None, dict, str]:
    """mu from the threshold tracks: each tactor's fit, the tactors left out and why, and the
    median of the rest.

    Parameters
    ----------
    tactors : sequence of (col, row)
    tracks : sequence of (drives, correct)
        Per tactor, in the order of ``tactors``: each trial's drive and whether it was right.

    Returns
    -------
    mu : float or None
        The median threshold (rounded to 1e-4), None when more than half the tactors were left
        out.
    fits : dict
        ``{(col, row): (CumulativeFit, felt, problem)}``.
    failure : str
        Why there is no mu ("" when there is one).
    """
    felt, problems, fits = [], [], {}
    for cell, fit, (drives, correct) in zip(tactors, fit_thresholds(tracks), tracks):
        share = sum(correct) / len(correct)
        problem = ""
        if fit.location >= MU_MAX or math.isnan(fit.ci[1]):
            problem = f"not felt reliably ({share:.0%} right; chance is 50%)"
        elif math.isnan(fit.ci[0]):
            problem = (
                f"not bounded from below (mostly right down to drive {min(drives):.2f}): "
                "the track did not reach the threshold"
            )
        fits[cell] = (fit, not problem, problem)
        if problem:
            problems.append(f"({cell[0]},{cell[1]}) {problem}")
        else:
            felt.append(fit)
    if len(felt) * 2 <= len(tactors):
        failure = (
            f"no threshold: {len(problems)} of {len(tactors)} tactors: "
            + "; ".join(problems)
            + ". Check that the hand is on the array and the array is on; a participant who "
            "answers at random looks like this too; more trials per tactor help a track "
            "that did not reach its threshold"
        )
        return None, fits, failure
    return round(statistics.median(f.location for f in felt), 4), fits, ""


class CorrectionTuning(Runner):
    """The guided procedure that measures mu and gamma (see the module notes).

    Parameters
    ----------
    session : Session
    plan : TuningPlan, optional
        Trial counts (the defaults: 20 per tactor, 40 per place, 12 at the corner: 192 trials,
        about 10 minutes at 3.2 s a trial; the README's benchmark table shows why).
    write, profile
        As for every runner.
    """

    experiment = EXPERIMENT
    fields = ("participant", "stage", "trial", "phase", "tactor", "level", "drive", "place",
              "mu", "gamma", "stimulus", "answer", "correct", "test_stronger", "rt_s", "time",
              *HEALTH_FIELDS)  # fmt: skip
    conditions: ClassVar[dict] = {}

    def __init__(self, session: Session, plan: TuningPlan | None = None, **kwargs):
        from ...device.profile import default_profile

        self.plan = plan or TuningPlan()
        profile = kwargs.get("profile") or default_profile()
        kwargs["profile"] = profile
        tactors, self.places = default_layout(profile.layout)
        if self.plan.tactors is not None:
            tactors = tuple((int(c), int(r)) for c, r in self.plan.tactors)
            for c, r in tactors:
                if not (0 <= c < profile.layout.cols and 0 <= r < profile.layout.rows):
                    raise ValueError(f"tactor ({c},{r}) is not on the {profile.layout.cols} x "
                                     f"{profile.layout.rows} grid")  # fmt: skip
        self.tactors = tactors
        if self.plan.corner_trials == 0:
            self.places = {k: v for k, v in self.places.items() if k != "corner"}
        self.conditions = {
            "plan": self.plan.to_dict(),
            "tactors": [f"{c},{r}" for c, r in tactors],
            "places": {k: {"point": list(v["point"]), "reference": list(v["reference"])}
                       for k, v in self.places.items()},
            "constancy_dither": True,
        }  # fmt: skip
        self.total = (
            2
            + len(tactors) * self.plan.threshold_trials
            + 2 * self.plan.gamma_trials
            + self.plan.corner_trials
        )
        self.failure = ""
        self.mu: float | None = None
        self.threshold_fits: dict = {}
        self.gamma_fits: dict = {}
        self.trials_by_stage: dict = {}
        super().__init__(session, **kwargs)

    # --- trials --------------------------------------------------------------------------------

    def _point_scene(self, point, mu, gamma, **extra):
        return self.make_scene(Line(point, point), "AS", mu, gamma, duration_s=INTERVAL_S,
                               pause_s=0.0, repeat=False, **extra)  # fmt: skip

    def _trials(self):
        self.failure, self.mu = "", None
        self.threshold_fits, self.gamma_fits = {}, {}
        data: dict = {}
        self.trials_by_stage = data
        top = self.profile.levels - 1
        yield Trial(
            EXPERIMENT, "intro-threshold", 0, "continue",
            "Part 1 of 2: two short intervals follow, 1 then 2; one of them holds a weak "
            "vibration. Press 1 or 2 for the one that held it; guess if unsure. Press a key to "
            "start.",
        )  # fmt: skip
        if self.plan.threshold_procedure == "quest+":
            tracks = {cell: _QuestTrack(top) for cell in self.tactors}
        else:
            tracks = {cell: _LevelTrack(round(top / 2), top) for cell in self.tactors}
        counts = dict.fromkeys(self.tactors, 0)
        while True:
            open_cells = [c for c in self.tactors if counts[c] < self.plan.threshold_trials]
            if not open_cells:
                break
            cell = self.rng.choice(open_cells)
            track = tracks[cell]
            level = track.level
            centre = (cell[0] + 0.5, cell[1] + 0.5)
            stim = self.make_scene(Line(centre, centre), "CT", 0.0, 1.0, duration_s=INTERVAL_S,
                                   pause_s=0.0, repeat=False, gain=level / top)  # fmt: skip
            first = self.rng.random() < 0.5
            stage = f"threshold-c{cell[0]}r{cell[1]}"
            answer = yield Trial(
                EXPERIMENT, stage, counts[cell], "interval",
                "Which interval held the vibration? 1 or 2 (R: feel both again).",
                intervals=(stim, None) if first else (None, stim), options=("1", "2"),
                info={"phase": "threshold", "tactor": f"{cell[0]} {cell[1]}", "level": level,
                      "drive": f"{level / top:.6g}", "stimulus": "1" if first else "2"},
            )  # fmt: skip
            correct = answer == ("1" if first else "2")
            track.update(correct)
            data.setdefault(stage, []).append((level / top, correct))
            counts[cell] += 1
            self._after = {"correct": int(correct)}
        self._estimate_mu()
        if self.failure:
            return
        mu = self.mu
        yield Trial(
            EXPERIMENT, "intro-constancy", 0, "continue",
            "Part 2 of 2: two intervals again, both vibrating. Press 1 or 2 for the one that "
            "felt stronger; guess if they feel the same. Press a key to start.",
        )  # fmt: skip
        budget = {name: self.plan.corner_trials if name == "corner" else self.plan.gamma_trials
                  for name in self.places}  # fmt: skip
        tracks = {name: _LogTrack(p["start"]) for name, p in self.places.items()}
        counts = dict.fromkeys(self.places, 0)
        while True:
            open_places = [p for p in self.places if counts[p] < budget[p]]
            if not open_places:
                break
            name = self.rng.choice(open_places)
            place, track = self.places[name], tracks[name]
            gamma = round(track.level, 6)
            test = self._point_scene(place["point"], mu, gamma).replace(dither=True)
            reference = self._point_scene(place["reference"], mu, gamma).replace(dither=True)
            first = self.rng.random() < 0.5
            stage = f"gamma-{name}"
            answer = yield Trial(
                EXPERIMENT, stage, counts[name], "interval",
                "Which interval felt stronger? 1 or 2 (R: feel both again).",
                intervals=(test, reference) if first else (reference, test), options=("1", "2"),
                info={"phase": "constancy", "place": name, "mu": f"{mu:.6g}",
                      "gamma": f"{gamma:.6g}", "stimulus": "1" if first else "2"},
            )  # fmt: skip
            stronger = answer == ("1" if first else "2")
            track.update(stronger)
            data.setdefault(stage, []).append((gamma, stronger))
            counts[name] += 1
            self._after = {"test_stronger": int(stronger)}
        self._estimate_gamma()

    def _row(self, trial, answer):
        if trial.kind == "continue":
            return {"phase": trial.stage.removeprefix("intro-"), "answer": ""}
        return {**trial.info, "answer": answer, **self._after}

    # --- estimates -------------------------------------------------------------------------------

    def _estimate_mu(self) -> None:
        tracks = []
        for cell in self.tactors:
            rows = self.trials_by_stage[f"threshold-c{cell[0]}r{cell[1]}"]
            tracks.append(tuple(zip(*rows)))
        self.mu, self.threshold_fits, self.failure = mu_from_tracks(self.tactors, tracks)

    def _estimate_gamma(self) -> None:
        for name in self.places:
            rows = self.trials_by_stage.get(f"gamma-{name}", [])
            if rows:
                gammas, stronger = zip(*rows)
                self.gamma_fits[name] = fit_gamma(gammas, stronger)
        pooled = [r for n in self.places if n != "corner"
                  for r in self.trials_by_stage.get(f"gamma-{n}", [])]  # fmt: skip
        gammas, stronger = zip(*pooled)
        fit = fit_gamma(gammas, stronger)
        self.gamma_fits["pooled"] = fit
        edge = GAMMA_MIN * 1.05, GAMMA_MAX / 1.05
        if not edge[0] < fit.location < edge[1]:
            self.failure = (
                f"no point of equality between gamma {GAMMA_MIN:g} and {GAMMA_MAX:g}: the test "
                "point felt "
                + ("stronger" if fit.location >= edge[1] else "weaker")
                + " than the tactor at every gamma tried"
            )
        elif math.isnan(fit.ci[0]) and math.isnan(fit.ci[1]):
            # A 1-up/1-down track sits where the answers are 50/50 by design, so random answers
            # are told by where they leave the point of equality: anywhere.
            share = sum(stronger) / len(stronger)
            self.failure = (
                f"no point of equality: the answers did not settle on a gamma (the test point "
                f"was chosen {share:.0%} of the time over gammas {min(gammas):.2f}.."
                f"{max(gammas):.2f}; its 95% interval is {_interval(fit.ci, '.2f')}): "
                "the participant answered at random or could not compare the intervals; more "
                "trials may settle it"
            )

    def result(self) -> TuningResult:
        """The measured correction (only once :attr:`finished`)."""
        if not self.finished:
            raise ValueError("result: the procedure has not finished")
        trials = sum(len(v) for v in self.trials_by_stage.values())
        thresholds = {
            f"{c},{r}": {"threshold": fit.location, "ci": list(fit.ci), "trials": fit.trials,
                         "felt": ok, "problem": problem}
            for (c, r), (fit, ok, problem) in self.threshold_fits.items()
        }  # fmt: skip
        places = {
            name: {"gamma": fit.location, "ci": list(fit.ci), "trials": fit.trials}
            for name, fit in self.gamma_fits.items() if name != "pooled"
        }  # fmt: skip
        if self.failure:
            return TuningResult(False, self.failure, trials=trials, thresholds=thresholds,
                                places=places)  # fmt: skip
        felt = [fit for fit, ok, _ in self.threshold_fits.values() if ok]
        warnings = [
            f"tactor ({c},{r}) {problem}: left out of mu (check its motor if it was not felt)"
            for (c, r), (_, ok, problem) in self.threshold_fits.items() if not ok
        ]  # fmt: skip
        pooled = self.gamma_fits["pooled"]
        gamma = round(pooled.location, 4)
        corner = self.gamma_fits.get("corner")
        agrees = None
        if corner is not None:
            lo, hi = corner.ci
            agrees = (math.isnan(lo) or lo <= gamma) and (math.isnan(hi) or gamma <= hi)
            if not agrees:
                warnings.append(
                    f"at the cell corner gamma {corner.location:.2f} "
                    f"({_interval((lo, hi), '.2f')}) differs from {gamma:.2f}: mu may be off "
                    "(the corner's four tactors are driven nearer the threshold than a pair's "
                    "two, so an error in mu moves its gamma more), or tactors add up "
                    "differently at this place of the array; this check cannot tell energy "
                    "summation from another power-sum rule, which moves both places alike"
                )
        return TuningResult(
            True, "measured", mu=self.mu, gamma=gamma,
            mu_ci=median_interval(felt, seed=self.session.seed),
            gamma_ci=tuple(pooled.ci), trials=trials,
            thresholds=thresholds, places=places, corner_agrees=agrees, warnings=warnings,
        )  # fmt: skip

    def calibration(self) -> tuple[list[float], list[float], list[float]]:
        """Per-tactor ``(offset, gain, threshold)`` in flat cell order from the thresholds
        measured, for the device profile (see
        :meth:`~tactile_core.experiments.runners.Calibration.calibration`); tactors not measured
        are left as they are (offset 0, gain 1, the median threshold)."""
        measured = {cell: fit.location for cell, (fit, ok, _) in self.threshold_fits.items() if ok}
        if not measured:
            raise ValueError("calibration: no tactor threshold was measured")
        return calibration_from_thresholds(measured, self.profile.layout)
