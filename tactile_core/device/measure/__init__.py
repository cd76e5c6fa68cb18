"""Measuring an array's motors with a sensor on an audio input (``tactile measure``).

An accelerometer, a piezo disc or a contact microphone on a tactor, into an audio interface,
records the vibration while the array plays a plan of steps, a ramp and pulses
(:class:`MeasurePlan`). From the recording this package estimates, per tactor:

- the spin-up and run-down time constants and the delay from a frame to the motor, by a
  first-order fit of the vibration's envelope (:func:`fit_envelope`), with its residual;
- the vibration amplitude against level: the physical response curve, apart from the
  perceptual μ/γ;
- the vibration frequency against level (an ERM's rises with its drive);
- the onset: from a pulse's frame to its first vibration, what a validator sees.

It checks the input first (:class:`MeasureError`: clipping, no signal, a wrong channel, a
tactor that does not move, the sensor on another tactor, two vibrations; a warning for mains
hum). :func:`simulate_measurement` runs the procedure against :class:`SimulatedSensor` in
virtual time; :class:`LiveSimulatedSensor` records in real time on the simulated array;
:class:`AudioInput` records a real sensor through PortAudio. :func:`write_measured_profile`
writes the result into a copy of the device profile.

Inside: ``_plan`` (the stimulus and the commands), ``_response`` (the first-order model),
``_sim`` (the simulated sensor), ``_signal`` (envelope, spectra), ``_fit``, ``_checks``,
``_analysis`` (one tactor), ``_detect`` (a validator's onset), ``_result`` (a whole run, the
profile), ``_recording`` (samples and their clock), ``_audio_input``, ``_live``,
``_simulate``, ``_open``.
"""

from ._analysis import ONSET_FRACTION, Block, TactorResult, analyse
from ._audio_input import AudioInput, InputURL, input_devices, parse_input_url
from ._checks import MeasureError
from ._detect import EDGE_S, Detection, detect_onset
from ._fit import Fit, fit_envelope
from ._live import LiveSimulatedSensor
from ._open import SIM_SENSOR, is_sensor, open_sensor
from ._plan import (
    QUICK_PLAN,
    Commands,
    MeasurePlan,
    PlanFrames,
    Stimulus,
    commands_from_frames,
)
from ._recording import Recording, fit_sample_clock
from ._response import first_order
from ._result import (
    ArrayMeasurement,
    measured_profile,
    median_response,
    not_written,
    now_text,
    save_measured,
    write_measured_profile,
)
from ._signal import bandpass, crossing_s, envelope, peaks
from ._sim import PALM_CURVE, SensorModel, SimulatedSensor
from ._simulate import (
    neighbours,
    sensor_model,
    simulate_block,
    simulate_measurement,
    stream_frames,
)

__all__ = [
    "EDGE_S",
    "ONSET_FRACTION",
    "PALM_CURVE",
    "QUICK_PLAN",
    "SIM_SENSOR",
    "ArrayMeasurement",
    "AudioInput",
    "Block",
    "Commands",
    "Detection",
    "Fit",
    "InputURL",
    "LiveSimulatedSensor",
    "MeasureError",
    "MeasurePlan",
    "PlanFrames",
    "Recording",
    "SensorModel",
    "SimulatedSensor",
    "Stimulus",
    "TactorResult",
    "analyse",
    "bandpass",
    "commands_from_frames",
    "crossing_s",
    "detect_onset",
    "envelope",
    "first_order",
    "fit_envelope",
    "fit_sample_clock",
    "input_devices",
    "is_sensor",
    "measured_profile",
    "median_response",
    "neighbours",
    "not_written",
    "now_text",
    "open_sensor",
    "parse_input_url",
    "peaks",
    "save_measured",
    "sensor_model",
    "simulate_block",
    "simulate_measurement",
    "stream_frames",
    "write_measured_profile",
]
