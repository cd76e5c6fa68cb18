"""Tuning the correction by feel: measure mu and gamma for this array and this hand.

The paper sets the threshold mu and the gamma of ``(1 - mu) I^gamma + mu`` by its authors'
judgement. This procedure measures them.

**The model.** A participant feels one tactor driven at ``d`` (the fraction of full drive the
array gets) with magnitude ``m(d) = ((d - TH) / (1 - TH))^K`` above a threshold ``TH`` and nothing
below, and adds several tactors by energy, ``M = sqrt(sum m_i^2)``. With ``mu = TH`` and
``gamma = 1 / (2K)`` the correction gives ``m_i = I_i^(1/2)``, so ``M = sqrt(sum I_i)``: wherever
the raw intensities sum to 1 (AS inside the hull, IM everywhere) a point between tactors feels
exactly as strong as a point on one, and the paper's correction becomes Tactile Brush's energy
law. Hence:

- **mu is the drive at which one tactor is just felt.** Two-interval forced choice (which of two
  intervals held the vibration?) over the device's own levels, one 3-down/1-up track per tactor
  for several tactors across the array, interleaved at random. A forced choice does not depend on
  the participant's criterion, as yes/no answers do. Each tactor's threshold is the drive at which
  it is felt half the time (75% correct), from a maximum-likelihood fit of a cumulative normal to
  all its trials; mu is their median, with a 95% interval from a parametric bootstrap of the
  median over the fits' profile-likelihood intervals.
- **gamma makes a point between tactors feel as strong as a point on a tactor.** Which of two
  intervals felt stronger: a point held midway between two tactors (raw 0.5 each, corrected with
  the candidate gamma and the measured mu) or a point on a tactor (raw 1, full drive)? gamma
  follows a 1-up/1-down track in log steps (x 1.4, then x 1.2 after two reversals) to the point
  of subjective equality, at two places on the array (one pair side by side, one above each
  other; their tracks start below and above the usual values). gamma is the PSE of one fit to
  both places' trials, with its profile-likelihood interval. A cell corner (four tactors at raw
  0.25 each) is tracked the same way, as a check: under the model it has the same PSE. Under
  any power-sum rule ``M = (sum m_i^p)^(1/p)`` the PSE is ``1 / (p K)`` at two tactors and at
  four alike, so the check cannot detect a departure from energy summation; what it detects is
  an error in mu (the corner's tactors are driven nearer the threshold) or summation that
  differs across the array. The constancy stimuli are dithered in time, so that the drive of
  a candidate gamma is not rounded to a level: one level (1/22 of full drive) moves the point
  of equality by 23% at mu 0.33 / gamma 0.7 and 25% at mu 0.25 / gamma 0.5, so rounding to the
  nearest level would err by up to half that, about 12%.

A participant who never feels the array, or answers at random, ends the procedure with a
message and no correction; it never yields a mu or gamma outside [0, 0.95] and [0.1, 10].

The procedure is a :class:`~tactile_core.experiments.runners.Runner` like the experiments: one
CSV row per answer, flushed before it moves on, resumable, one participant at a time.
:func:`save_correction` writes the result as the participant's ``correction.json`` and a preset.

The modules: ``_observer`` (the model and the simulated observer), ``_fits`` (the psychometric
fits), ``_tracks`` (the adaptive tracks), ``_plan`` (trial counts and where the stimuli go),
``_procedure`` (the runner), ``_result`` (what it found) and ``_save`` (keeping it).
"""

from .._correction_record import (
    CORRECTION_FILE,
    FORMAT,
    GAMMA_MAX,
    GAMMA_MIN,
    MU_MAX,
    VERSION,
    load_correction,
)
from ._fits import (
    CHI2_95,
    GAMMA_LOCATIONS,
    GAMMA_SCALES,
    LAPSES,
    THRESHOLD_LOCATIONS,
    THRESHOLD_SCALES,
    CumulativeFit,
    fit_cumulative,
    fit_gamma,
    fit_shared_scale,
    fit_thresholds,
    median_interval,
)
from ._observer import SimulatedObserver, felt_total, interval_drive, simulate_tuning
from ._plan import TuningPlan, default_layout
from ._procedure import EXPERIMENT, CorrectionTuning, mu_from_tracks
from ._result import TuningResult
from ._save import save_correction

# isort: split
__all__ = [
    "CHI2_95",
    "CORRECTION_FILE",
    "EXPERIMENT",
    "FORMAT",
    "GAMMA_LOCATIONS",
    "GAMMA_MAX",
    "GAMMA_MIN",
    "GAMMA_SCALES",
    "LAPSES",
    "MU_MAX",
    "THRESHOLD_LOCATIONS",
    "THRESHOLD_SCALES",
    "VERSION",
    "CorrectionTuning",
    "CumulativeFit",
    "SimulatedObserver",
    "TuningPlan",
    "TuningResult",
    "default_layout",
    "felt_total",
    "fit_cumulative",
    "fit_gamma",
    "fit_shared_scale",
    "fit_thresholds",
    "interval_drive",
    "load_correction",
    "median_interval",
    "mu_from_tracks",
    "save_correction",
    "simulate_tuning",
]
