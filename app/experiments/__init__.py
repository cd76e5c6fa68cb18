"""The Experiments tab: an experimenter's console, and a separate window for the participant.

As in PsychoPy's split between the experimenter and the participant, the participant's window
(:class:`ParticipantWindow`, full screen on a second screen when there is one) shows only the
instructions, the response prompt, the rating box and the feedback; the console
(:class:`ExperimentsPanel`, the tuner's Experiments tab) shows the run: the participant id in
large type, the experiment, the progress, what the current trial plays, the array's health (rate,
late frames, link errors), where the results go, and an event log.

A run refuses to start while the array is disconnected. If the link drops during a run, the run
pauses with the array off, the console says so, and once the array is back the experimenter
presents the interrupted trial again (its row records how often it was presented). The tuning
scene is saved when a run starts and restored, paused, when it ends; a run never writes the
tuner's settings.

The modules, one subject each: ``console`` (the tab), ``session`` (the session's set-up),
``trials`` (presenting a run's trials, their keys and timing: ``GAP_S``; the two-interval
timing ``INTERVAL_S`` and ``INTERVAL_GAP_S`` comes from the core), ``participant`` (the
participant's window), ``analysis`` (``tactile analyze`` in the background) and ``guided``
(tuning the correction by feel: its introduction and its result).
"""

from .analysis import AnalysisWidget
from .console import ExperimentsPanel
from .guided import GuidedTuning, TuningResultDialog
from .participant import ParticipantWindow
from .session import TITLES, SessionWidget
from .trials import KEYS, LINK_DOWN, TrialPresenter

__all__ = [
    "KEYS",
    "LINK_DOWN",
    "TITLES",
    "AnalysisWidget",
    "ExperimentsPanel",
    "GuidedTuning",
    "ParticipantWindow",
    "SessionWidget",
    "TrialPresenter",
    "TuningResultDialog",
]
