"""A participant's measured correction on disk: ``correction.json``, its format and its bounds.

The tuning procedure (:mod:`tactile_core.experiments.tuning`) writes the record; every runner
reads it, to note the participant's correction in the runs it records. Both import it from
here, so neither imports the other for it.
"""

from __future__ import annotations

from pathlib import Path

from .._shared import validate as _validate
from .._shared.jsonfile import read_json

CORRECTION_FILE = "correction.json"
FORMAT = "tactile-correction"
VERSION = 1
MU_MAX = 0.95
"""The largest threshold mu a correction may hold (drive fraction)."""
GAMMA_MIN, GAMMA_MAX = 0.1, 10.0
"""The range of gamma a correction may hold."""


def load_correction(folder) -> dict | None:
    """The participant's measured correction.

    Parameters
    ----------
    folder : path
        The participant's folder.

    Returns
    -------
    dict or None
        ``correction.json`` as written by
        :func:`~tactile_core.experiments.tuning.save_correction` (``mu`` and ``gamma`` checked
        against :data:`MU_MAX`, :data:`GAMMA_MIN` and :data:`GAMMA_MAX`); None if there is none.

    Raises
    ------
    ValueError
        If the file exists but is not a valid correction record (it names the file).
    """
    path = Path(folder) / CORRECTION_FILE
    if not path.exists():
        return None
    data = read_json(path)
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise ValueError(f"{path}: not a correction record (format {FORMAT!r})")
    try:
        mu = _validate.in_range("mu", data.get("mu"), 0.0, MU_MAX)
        gamma = _validate.in_range("gamma", data.get("gamma"), GAMMA_MIN, GAMMA_MAX)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    return {**data, "mu": mu, "gamma": gamma}
