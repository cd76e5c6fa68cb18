"""``tactile measure`` at an array: each tactor's block streamed over any link while a sensor
records, and the recording read.

For each tactor the procedure asks for the sensor to be put on it (``prompt``), lets go of what
the sensor recorded so far, plays the block as a frame source of a scene (μ 0, γ 1, the profile
without its calibration: the levels go out as planned), and takes the frames that went out,
with their times, from a tap of the stream: the commands are what was sent and when, not what
was planned. Once the sensor's samples reach past the block's end the scene stops and the
block is read (:func:`~tactile_core.device.measure.analyse`).
"""

from __future__ import annotations

import dataclasses
import threading
import time

import numpy as np

from ...device.measure import (
    ArrayMeasurement,
    Block,
    Commands,
    MeasureError,
    MeasurePlan,
    PlanFrames,
    analyse,
    commands_from_frames,
    neighbours,
    now_text,
)
from ...rendering.placement import default_method
from ...rendering.scene import Scene
from ...stream import Streamer, StreamOptions

START_TIMEOUT_S = 5.0
"""How long the first frame of a block may take to go out."""
RECORD_SLACK_S = 10.0
"""How much longer than a block the sensor may take to deliver its samples."""


class MeasureAborted(RuntimeError):
    """The run stopped before every tactor was measured (the stream or the sensor failed)."""


def measure_array(link, profile, sensor, *, cells, plan: MeasurePlan | None = None,
                  rate_hz: float = 300.0, prompt=None, log=None, stop=None,
                  streamer_options: dict | None = None) -> ArrayMeasurement:  # fmt: skip
    """Measure ``cells`` of the array on ``link`` with ``sensor``.

    Parameters
    ----------
    link : object
        An open link (:func:`~tactile_core.device.open_link`); closed by the caller.
    profile : DeviceProfile
        The array (its calibration is left out while measuring).
    sensor : object
        A sensor (:func:`~tactile_core.device.measure.open_sensor`), started by the caller.
    cells : sequence of int
        The tactors to measure, in order.
    plan : MeasurePlan, optional
    rate_hz : float
        Frames per second (capped at what the link carries).
    prompt : callable, optional
        ``prompt(cell, name)`` before each tactor: ask for the sensor to be put on it (may
        raise ``KeyboardInterrupt`` to stop).
    log : callable, optional
        ``log(text)`` for progress lines.
    stop : threading.Event, optional
        Set to stop after the tactor being measured.
    streamer_options : dict, optional
        Further keyword arguments of the :class:`~tactile_core.stream.Streamer`.

    Returns
    -------
    ArrayMeasurement

    Raises
    ------
    MeasureAborted
        The stream stopped, or the sensor stopped delivering samples.
    """
    plan = plan or MeasurePlan()
    log = log or (lambda text: None)
    bare = profile.without_calibration()
    rate = min(float(rate_hz), bare.max_rate_hz)
    streamer = Streamer(link, bare, options=StreamOptions(lead_ms=0.0),
                        **(streamer_options or {}))  # fmt: skip
    results, failures = [], {}
    layout = profile.layout
    names = [layout.cell_name(i) for i in range(profile.channels)]
    streamer.start()
    try:
        streamer.identified.wait(START_TIMEOUT_S)
        for cell in cells:
            if stop is not None and stop.is_set():
                break
            if prompt is not None:
                prompt(cell, names[cell])
            if callable(getattr(sensor, "place", None)):
                sensor.place(cell)  # the simulated sensor moves as asked
            seconds = plan.duration_s(len(neighbours(layout, cell)), profile.levels)
            log(f"measuring {names[cell]} ({seconds:.1f} s)")
            block, rec = _play(streamer, bare, sensor, cell, plan, rate)
            try:
                results.append(analyse(rec.sensor, rec.samplerate, block, plan,
                                       levels=profile.levels, names=names,
                                       others=rec.others))  # fmt: skip
                log(_line(results[-1]))
            except MeasureError as exc:
                failures[names[cell]] = str(exc)
                log(f"error: {exc}")
    finally:
        streamer.set_scene(None)
        streamer.stop()
    description = getattr(sensor, "description", "a sensor")
    return ArrayMeasurement(profile.name, tuple(results), failures, description, now_text(),
                            plan.duration_s(8, profile.levels))  # fmt: skip


def _play(streamer, profile, sensor, cell: int, plan: MeasurePlan, rate: float):
    """Play one tactor's block while the sensor records; ``(Block, Recording)``."""
    layout = profile.layout
    near = neighbours(layout, cell)
    source = PlanFrames(plan.commands(cell, near, profile.levels), profile.levels, rate)
    scene = Scene(source=source, method=default_method(layout), mu=0.0, gamma=1.0,
                  rate_hz=rate, repeat=False, marker="measure")  # fmt: skip
    frames: list = []
    started = threading.Event()
    first: list = []

    def tap(time_s, seq, levels):
        frames.append((time_s, levels))

    def on_onset(onset):
        if onset.scene is scene and not first:
            first.append(onset.time_s)
            started.set()

    streamer.taps.append(tap)
    streamer.on_onset.append(on_onset)
    try:
        sensor.clear()
        streamer.set_scene(scene)
        if not started.wait(START_TIMEOUT_S):
            stats = streamer.stats
            raise MeasureAborted(f"no frame went out within {START_TIMEOUT_S:g} s: "
                                 f"[{stats.state}] {stats.status}")  # fmt: skip
        t0 = first[0]
        end = t0 + source.end_s + plan.tail_s
        while not sensor.wait_until(end, 0.2):
            if not streamer.running:
                raise MeasureAborted(f"the stream stopped: {streamer.stats.status}")
            if time.perf_counter() > end + RECORD_SLACK_S:
                raise MeasureAborted(
                    f"the sensor delivered no samples past {RECORD_SLACK_S:g} s after the "
                    "block ended: is the audio input still recording (unplugged? in use?)"
                )
        streamer.set_scene(None)
    finally:
        streamer.taps.remove(tap)
        streamer.on_onset.remove(on_onset)
    rec = sensor.recording()
    times = np.array([t for t, _ in frames])
    levels = np.array([np.frombuffer(lv, dtype=np.uint8) for _, lv in frames])
    keep = times >= t0 - 1e-9
    sent = commands_from_frames(times[keep], levels[keep], profile.array.channel_index)
    commands = Commands(rec.to_recording_s(sent.time_s), sent.cell, sent.level)
    return Block(cell, near, float(rec.to_recording_s(t0)), commands), rec


def _line(t) -> str:
    """One tactor's result in a line."""
    return (f"{t.name}: spin-up {t.tau_up_s * 1e3:.1f} ms, run-down {t.tau_down_s * 1e3:.1f} "
            f"ms, delay {t.delay_s * 1e3:.1f} ms, onset {t.onset_s * 1e3:.1f} ms, residual "
            f"{t.residual:.1%}, SNR {t.snr_db:.0f} dB"
            + "".join(f"\n  warning: {w}" for w in t.warnings)
            + "".join(f"\n  note: {n}" for n in t.notes))  # fmt: skip


def result_lines(result: ArrayMeasurement) -> list[str]:
    """The result as lines of text: every tactor, then the medians."""
    lines = [_line(t) for t in result.tactors]
    lines += [f"{name}: error: {why}" for name, why in result.failures.items()]
    if result.tactors:
        lines.append(
            f"median over {len(result.tactors)} tactor{'s' if len(result.tactors) > 1 else ''}: "
            "spin-up "
            f"{result.median('tau_up_s') * 1e3:.1f} ms, run-down "
            f"{result.median('tau_down_s') * 1e3:.1f} ms, delay "
            f"{result.median('delay_s') * 1e3:.1f} ms, onset "
            f"{result.median('onset_s') * 1e3:.1f} ms"
        )
    return lines


def replace_plan(plan: MeasurePlan, **changes) -> MeasurePlan:
    """``plan`` with ``changes`` (validated)."""
    return dataclasses.replace(plan, **changes)
