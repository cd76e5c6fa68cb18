"""Keeping a result: the participant's ``correction.json`` and a preset beside it."""

from __future__ import annotations

from pathlib import Path

from ..._shared.jsonfile import write_json_atomic
from .._correction_record import CORRECTION_FILE, FORMAT, VERSION
from ..results import now
from ..runners import Experiment1
from ._procedure import CorrectionTuning
from ._result import TuningResult, _interval


def save_correction(runner: CorrectionTuning, result: TuningResult | None = None) -> tuple:
    """Keep a successful result as the participant's correction.

    Writes ``correction.json`` in the participant's folder (the result, the participant, when,
    the device profile and the plan) and a preset ``correction-<participant>.json`` beside it
    (the Experiment 1 line with the measured mu and gamma), both atomically. Later experiment
    sessions of the participant record the correction (``session.json``, ``runs``).

    Returns
    -------
    (Path, Path)
        The correction record and the preset.

    Raises
    ------
    ValueError
        If the result is not a correction (``ok`` false): nothing is written.
    """
    from ...files.presets import Preset, save_preset
    from ...rendering.scene import Scene

    result = result or runner.result()
    if not result.ok:
        raise ValueError(f"nothing to save: {result.message}")
    folder = Path(runner.session.folder)
    pid = runner.session.participant
    record = {
        "format": FORMAT,
        "version": VERSION,
        "participant": pid,
        "measured": now(),
        "device_profile": runner.profile.record(),
        "plan": runner.plan.to_dict(),
        **result.to_dict(),
    }
    path = write_json_atomic(folder / CORRECTION_FILE, record)
    notes = (
        f"Measured for participant {pid} on {record['measured']}: mu {result.mu:.3f} "
        f"(95% {_interval(result.mu_ci, '.3f')}), gamma {result.gamma:.3f} "
        f"(95% {_interval(result.gamma_ci, '.3f')}), {result.trials} trials."
    )
    scene = Scene(Experiment1.LINE, "IM", result.mu, result.gamma)
    preset = save_preset(
        Preset(scene, name=f"correction {pid}", notes=notes, device_profile=runner.profile.name),
        folder / f"correction-{pid}.json",
    )
    return path, preset
