"""``tactile analyze``: the paper's tables and figures from a results folder, and more.

Reads every ``participant-*/`` folder of a results folder and prints:

- Table 1 (Experiment 1): per property (quality, smoothness, thickness; each the sum of the
  line and circle ratings), Bonferroni-adjusted pairwise Wilcoxon p-values between methods,
  with a Friedman omnibus test before them and effect sizes ``r = Z / sqrt(N)`` beside them.
- Experiment 2: each participant's 70.7% line length per condition by the paper's estimate (the
  mean of the last two peaks and two valleys of the staircase) and by a maximum-likelihood fit
  of a psychometric function to the whole track (with a 95% confidence interval), and the mean
  +- SE per condition of both. The reversal estimate is biased upward for the paper's steps (at
  30 trials +8-14% in the median, +11-21% in the mean: docs/benchmarks.md); the fit's median is
  within 0.4% for a moderately steep psychometric function and +2.3% for a shallow one.
- Table 2 (Experiment 3): pairwise Wilcoxon p-values of the discrimination scores (correct
  answers out of 10 per method), the Friedman test and effect sizes, the confusion matrix and
  d' per method.
- After each experiment, the statistics a journal asks for (``_extended``, with
  :mod:`tactile_core.experiments.inference`): exact signed-rank tests with ties, Holm beside
  Bonferroni, bootstrap intervals on the effect sizes, Experiment 2 against 1 grid unit,
  Experiment 3 against chance, and mixed models with a random intercept per participant.

and writes beside the results: ``fig6-exp1-scores.png`` (box plots), ``fig7-exp2-lengths.png``
(mean +- SE), ``fig8-exp3-scores.png`` (box plots) and ``exp2-staircases.png`` (every track
with its reversals). Only participants with complete data for an experiment enter its tests.

A row that cannot be read (a bad number, an unknown method, a duplicate) is reported as
``file:row: problem`` and left out; the rest is analysed, and the output says what was left out.

The modules: ``_reading`` (participant folders and their rows, checked), ``_scores`` (each
experiment's scores, tracks and answers), ``_report`` (:func:`analyze`: the tables and
statistics) and ``_figures`` (the figures).
"""

from ._reading import Problems, numbered_rows, participants, session_methods, study_methods
from ._report import analyze, format_pvalues
from ._scores import (
    PROPERTIES,
    confusion,
    exp1_scores,
    exp2_estimates,
    exp2_tracks,
    exp3_answers,
    exp3_scores,
    track_estimate,
)

# isort: split
__all__ = [
    "PROPERTIES",
    "Problems",
    "analyze",
    "confusion",
    "exp1_scores",
    "exp2_estimates",
    "exp2_tracks",
    "exp3_answers",
    "exp3_scores",
    "format_pvalues",
    "numbered_rows",
    "participants",
    "session_methods",
    "study_methods",
    "track_estimate",
]
