"""The whole procedure against the simulated sensor, in virtual time (``tactile measure
--simulate``).

For each tactor the block is played as a stream would play it (frames at ``rate_hz`` from
:class:`PlanFrames`, the changes read back from the frames by :func:`commands_from_frames`),
the simulated sensor (:class:`SimulatedSensor`, moved onto the tactor, or wherever
``sensor_on`` puts it) records it, and :func:`analyse` reads it: the same steps as a run at an
array, without waiting for the seconds to pass.
"""

from __future__ import annotations

import math

import numpy as np

from ..profile import DeviceProfile, default_profile
from ._analysis import Block, analyse
from ._checks import MeasureError
from ._plan import Commands, MeasurePlan, PlanFrames, commands_from_frames
from ._recording import Recording
from ._result import ArrayMeasurement, now_text
from ._sim import PALM_CURVE, SensorModel, SimulatedSensor

NEIGHBOUR_REACH = 1.5
"""Tactors within this many pitches are a tactor's neighbours in the scan (8 inside a grid)."""
SIM_SAMPLERATE = 8000
"""The simulated sensor's samplerate: ample for vibrations below 1 kHz."""


def neighbours(layout, cell: int, reach: float = NEIGHBOUR_REACH) -> tuple[int, ...]:
    """The tactors within ``reach`` pitches of ``cell`` (itself left out), nearest first."""
    d = layout.distances(*layout.xy[cell])
    near = [int(i) for i in np.argsort(d, kind="stable") if i != cell and d[i] <= reach]
    return tuple(near)


def stream_frames(commands: Commands, levels: int, rate_hz: float, start_s: float,
                  channels) -> Commands:  # fmt: skip
    """The commands as a stream plays them: frames at ``rate_hz`` from ``start_s`` (host s),
    each holding the levels due by its time, read back into changes.

    Parameters
    ----------
    channels : array_like of int, shape (size,)
        The cell of each channel (the profile's channel order).
    """
    source = PlanFrames(commands, levels, rate_hz)
    n = math.ceil(source.end_s * rate_hz) + 2
    cells = np.asarray(channels, dtype=np.int64)
    channel_of = np.argsort(cells)
    frames = np.zeros((n, cells.size), dtype=np.uint8)
    top = levels - 1
    for k in range(n):
        for cell, value in source.entries(k):
            frames[k, channel_of[cell]] = math.floor(value * top + 0.5)
    return commands_from_frames(start_s + np.arange(n) / rate_hz, frames, cells)


def sensor_model(profile: DeviceProfile, *, tau_up_ms: float, tau_down_ms: float,
                 delay_ms: float, noise: float, seed: int, **changes) -> SensorModel:  # fmt: skip
    """The simulated array's motors for ``profile``: the time constants given, the profile's
    response curve (the palm array's without one), and per tactor an amplitude within +-10 %
    of 0.3 and a top frequency within +-6 % of 220 Hz (seeded)."""
    rng = np.random.default_rng(10_007 * seed + 17)
    size = profile.channels
    curve = profile.response if profile.response is not None else PALM_CURVE
    base = dict(
        xy=profile.layout.xy, tau_up_s=tau_up_ms / 1e3, tau_down_s=tau_down_ms / 1e3,
        delay_s=delay_ms / 1e3, amplitude=0.3 * (1 + 0.1 * rng.uniform(-1, 1, size)),
        curve=curve, freq_hi_hz=220.0 * (1 + 0.06 * rng.uniform(-1, 1, size)), noise=noise,
        levels=profile.levels,
    )  # fmt: skip
    base.update(changes)
    return SensorModel(**base)


def simulate_measurement(profile: DeviceProfile | None = None, *, tau_up_ms: float = 30.0,
                         tau_down_ms: float = 60.0, delay_ms: float = 5.0, noise: float = 0.02,
                         seed: int = 0, cells=None, plan: MeasurePlan | None = None,
                         samplerate: int = SIM_SAMPLERATE, rate_hz: float = 300.0,
                         sensor_on: dict | None = None, input_channel: int | None = None,
                         **changes) -> ArrayMeasurement:  # fmt: skip
    """Measure ``cells`` of ``profile`` against the simulated sensor.

    Parameters
    ----------
    profile : DeviceProfile, optional
        The array (the palm array by default).
    tau_up_ms, tau_down_ms, delay_ms : float
        The simulated motors' time constants and the delay from a frame to its drive (ms).
    noise : float
        White noise on the sensor, RMS, as a fraction of the full-drive amplitude.
    seed : int
        Seeds the motors' spread and the noise.
    cells : sequence of int, optional
        The tactors to measure (all by default).
    plan : MeasurePlan, optional
    samplerate : int
        The simulated sensor's samples per second.
    rate_hz : float
        Frames per second of the simulated stream.
    sensor_on : dict, optional
        ``{cell: other}``: when ``cell`` is measured the sensor sits on ``other``.
    input_channel : int, optional
        The input channel read (the one the sensor is on by default).
    **changes
        Further fields of the :class:`SensorModel` (``hum``, ``gain``, ``dead``, ``also``,
        ``channels``, ``channel``, ...).

    Returns
    -------
    ArrayMeasurement
        The tactors measured, and the errors of those that could not be.
    """
    profile = profile or default_profile()
    plan = plan or MeasurePlan()
    layout = profile.layout
    cells = range(profile.channels) if cells is None else cells
    model = sensor_model(profile, tau_up_ms=tau_up_ms, tau_down_ms=tau_down_ms,
                         delay_ms=delay_ms, noise=noise, seed=seed, **changes)  # fmt: skip
    names = [layout.cell_name(i) for i in range(profile.channels)]
    rng = np.random.default_rng(seed)
    results, failures = [], {}
    description = (
        f"the simulated sensor (first-order ERMs, spin-up {tau_up_ms:g} ms, run-down "
        f"{tau_down_ms:g} ms, delay {delay_ms:g} ms, noise {noise:g})"
    )
    for cell in cells:
        here = model.replace(on_cell=(sensor_on or {}).get(cell, cell))
        channel = here.channel if input_channel is None else input_channel
        rec, block = simulate_block(profile, cell, here, plan=plan, samplerate=samplerate,
                                    rate_hz=rate_hz, rng=rng, seed=1000 * seed + cell,
                                    channel=channel, description=description)  # fmt: skip
        try:
            results.append(analyse(rec.sensor, samplerate, block, plan, levels=profile.levels,
                                   names=names, others=rec.others))  # fmt: skip
        except MeasureError as exc:
            failures[names[cell]] = str(exc)
    return ArrayMeasurement(profile.name, tuple(results), failures, description, now_text(),
                            plan.duration_s(8, profile.levels))  # fmt: skip


def simulate_block(profile: DeviceProfile, cell: int, model: SensorModel, *, plan: MeasurePlan,
                   samplerate: int = SIM_SAMPLERATE, rate_hz: float = 300.0, rng=None,
                   seed: int = 0, channel: int | None = None,
                   description: str = "") -> tuple[Recording, Block]:  # fmt: skip
    """One tactor's block played to ``model`` (the sensor where its ``on_cell`` says): the
    recording (from a little before the block's first frame to just after its end) and where
    the block lies in it.

    Parameters
    ----------
    rng : numpy.random.Generator, optional
        Draws the block's start (a host time near 100 s) and the recording's lead.
    seed : int
        Seeds the sensor's noise.
    channel : int, optional
        The input read (the model's by default).
    """
    rng = rng if rng is not None else np.random.default_rng(seed)
    near = neighbours(profile.layout, cell)
    block_s = 100.0 + rng.uniform(0.0, 1.0)  # host time of the block's first frame
    commands = stream_frames(plan.commands(cell, near, profile.levels), profile.levels,
                             rate_hz, block_s, profile.array.channel_index)  # fmt: skip
    start_s = block_s - 0.05 - rng.uniform(0.0, 0.01)
    n = int((plan.duration_s(len(near), profile.levels) + 0.1) * samplerate)
    x = SimulatedSensor(model, samplerate, seed=seed).render(commands, start_s, n)
    channel = model.channel if channel is None else channel
    rec = Recording(x, samplerate, start_s, channel=channel, description=description)
    block = Block(cell, near, float(rec.to_recording_s(block_s)), commands.shifted(-start_s))
    return rec, block
