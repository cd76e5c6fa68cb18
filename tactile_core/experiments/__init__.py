"""Running, simulating and analysing the paper's experiments (section 3), and calibration.

The sub-packages, each importing only those before it in this list: ``results`` (a participant's
session and results files), ``runners`` (the experiments and the calibration as runners),
``tuning`` (measuring mu and gamma by feel, itself a runner) and ``analysis`` (the paper's tables
and figures); beside them ``stats``, ``staircase``, ``participants`` (simulated ones) and
``blind`` (a blind A/B session: :class:`BlindSession`).
``_correction_record`` (a participant's measured correction on disk) is read by the runners and
written by the tuning.

>>> import tactile_core as tc
>>> sc = tc.Staircase(start=2.0, down=0.685, up=1.46, n_down=2, n_up=1)
>>> sc.level
2.0
"""

from .blind import BlindSession
from .participants import Psychometric, SimulatedParticipant
from .results import Session, open_session
from .runners import RUNNERS, Calibration, Experiment1, Experiment2, Experiment3, Trial
from .staircase import Staircase
from .stats import ORDERS, assign_orders, pairwise_wilcoxon
from .tuning import (
    CorrectionTuning,
    SimulatedObserver,
    TuningPlan,
    TuningResult,
    save_correction,
    simulate_tuning,
)

RUNNERS["correction"] = CorrectionTuning

__all__ = [
    "ORDERS",
    "RUNNERS",
    "BlindSession",
    "Calibration",
    "CorrectionTuning",
    "Experiment1",
    "Experiment2",
    "Experiment3",
    "Psychometric",
    "Session",
    "SimulatedObserver",
    "SimulatedParticipant",
    "Staircase",
    "Trial",
    "TuningPlan",
    "TuningResult",
    "assign_orders",
    "open_session",
    "pairwise_wilcoxon",
    "save_correction",
    "simulate_tuning",
]
