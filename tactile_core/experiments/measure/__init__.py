"""Measuring an array's motors at the array, and validating onsets during an experiment.

- :func:`measure_array` (``tactile measure --input ... --device ...``): each tactor's block
  played over any link while a sensor records, then read
  (:mod:`tactile_core.device.measure` holds the analysis, the plan and the sensors).
- :class:`Validator` (``open_array(..., validate=...)``, ``tactile serve --validate``): the
  sensor's onset of each presentation logged beside its commanded time, with the delay and its
  spread, to a CSV and an LSL marker stream.
"""

from ._procedure import MeasureAborted, measure_array, result_lines
from ._validator import FIELDS, WINDOW_S, Validator, default_log_path

__all__ = [
    "FIELDS",
    "WINDOW_S",
    "MeasureAborted",
    "Validator",
    "default_log_path",
    "measure_array",
    "result_lines",
]
