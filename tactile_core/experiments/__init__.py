"""Running, simulating and analysing the paper's experiments (section 3), and calibration.

>>> import tactile_core as tc
>>> sc = tc.Staircase(start=2.0, down=0.685, up=1.46, n_down=2, n_up=1)
>>> sc.level
2.0
"""

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
