"""Opening a sensor from what a user gives: an ``audio:`` input URL, ``sim``, or an object."""

from __future__ import annotations

from ..._shared import validate as _validate
from ._audio_input import AudioInput
from ._live import LiveSimulatedSensor
from ._simulate import sensor_model

SIM_SENSOR = "sim"


def is_sensor(value) -> bool:
    """True for an object with a sensor's methods (``start``, ``stop``, ``clear``,
    ``wait_until``, ``recording``)."""
    return all(callable(getattr(value, name, None))
               for name in ("start", "stop", "clear", "wait_until", "recording"))  # fmt: skip


def open_sensor(spec, *, link=None, profile=None, sim_options: dict | None = None):
    """A sensor, not yet started.

    Parameters
    ----------
    spec : str or sensor
        ``audio:NAME?channel=N&samplerate=R&latency_ms=L`` (:class:`AudioInput`), ``sim``
        (:class:`LiveSimulatedSensor` on ``link``, which must be the simulated array), or an
        object with a sensor's methods (returned as it is).
    link : object, optional
        The array's link (for ``sim``).
    profile : DeviceProfile, optional
        The array (for ``sim``).
    sim_options : dict, optional
        For ``sim``: ``tau_up_ms``, ``tau_down_ms``, ``delay_ms``, ``noise``, ``seed`` and
        further :class:`SensorModel` fields (30, 60, 5 ms, 0.02, 0 by default).

    Raises
    ------
    ValueError
        A spec that is none of these, or ``sim`` on another link than the simulated array.
    LinkError
        The audio input cannot be opened.
    """
    if is_sensor(spec):
        return spec
    if not isinstance(spec, str):
        raise ValueError(f"the sensor must be an audio: URL, 'sim' or a sensor object, got "
                         f"{_validate.shown(spec)}")  # fmt: skip
    if spec.strip().lower() == SIM_SENSOR:
        from ..link import SimulatedArray

        if not isinstance(link, SimulatedArray):
            raise ValueError("the simulated sensor ('sim') sits on the simulated array: use it "
                             "with the device 'sim'")  # fmt: skip
        options = dict(tau_up_ms=30.0, tau_down_ms=60.0, delay_ms=5.0, noise=0.02, seed=0)
        options.update(sim_options or {})
        seed = options["seed"]
        model = sensor_model(profile or link.profile, **options)
        return LiveSimulatedSensor(link, model, seed=seed)
    return AudioInput(spec)
