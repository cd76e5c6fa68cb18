"""The paper's experiments (section 3.4) and a per-tactor calibration, as runners without Qt.

A runner is a state machine that a user interface drives: :attr:`Runner.current` is the trial
to present (what the array plays, what to ask, which answers are valid); :meth:`Runner.answer`
records the answer as one CSV row, flushed to disk before it returns, and moves on. The tuner
drives runners from the keyboard; tests and study planning drive them with simulated
participants (:mod:`tactile_core.experiments.participants`). Starting a runner again on the
same session folder resumes it: the recorded answers are replayed and checked against what the
session's seed generates.

The machinery every runner shares (:class:`Trial`, :class:`Runner`) is in ``_runner``; what the
experiments vary (methods, their order, mu and gamma) in ``_conditions``; each experiment in its
own module.
"""

from ._calibration import Calibration, calibration_from_thresholds
from ._conditions import DIRECTIONS, GAMMA, MAX_SET, METHODS, MU, SHAPES, method_set
from ._exp1_ratings import Experiment1
from ._exp2_direction import CONDITIONS_EXP2, Experiment2, direction_line
from ._exp3_shape import Experiment3
from ._runner import HEALTH_FIELDS, INTERVAL_GAP_S, INTERVAL_S, Runner, Trial

# isort: split
RUNNERS = {
    "exp1": Experiment1,
    "exp2": Experiment2,
    "exp3": Experiment3,
    "calibration": Calibration,
}
"""Runner classes by experiment name (``"correction"``, the tuning procedure, is added by
:mod:`tactile_core.experiments`, which imports both: the runners never import the tuning)."""

__all__ = [
    "CONDITIONS_EXP2",
    "DIRECTIONS",
    "GAMMA",
    "HEALTH_FIELDS",
    "INTERVAL_GAP_S",
    "INTERVAL_S",
    "MAX_SET",
    "METHODS",
    "MU",
    "RUNNERS",
    "SHAPES",
    "Calibration",
    "Experiment1",
    "Experiment2",
    "Experiment3",
    "Runner",
    "Trial",
    "calibration_from_thresholds",
    "direction_line",
    "method_set",
]
