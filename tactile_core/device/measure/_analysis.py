"""One tactor's recording read into its constants: the checks, the fit, frequency and onset.

All times here are *recording seconds* (a sample's index over the samplerate); the caller
turns the host times of the commands into them (:meth:`Recording.to_recording_s`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._checks import (
    MIN_SNR,
    MeasureError,
    check_clipping,
    check_scan,
    check_second_vibration,
    hum_warning,
    no_response,
)
from ._fit import fit_envelope
from ._plan import Commands, MeasurePlan
from ._response import first_order
from ._signal import bandpass, crossing_s, envelope, hum, peaks, remove_hum

ONSET_FRACTION = 0.1
"""A pulse's first vibration: its amplitude reaching this fraction of the full-drive one."""
EXTRAPOLATE = 0.1
"""How far above the highest effective drive read a frequency is extrapolated (drive units)."""
RESIDUAL_NOTE = 0.1
"""A fit residual above this (and twice the noise's) says first order does not fit well."""


@dataclass(frozen=True)
class TactorResult:
    """What one tactor's block measured.

    Attributes
    ----------
    cell : int
        Flat cell index.
    name : str
        Its name (``r2c4`` on a grid).
    delay_s : float
        From a frame's time to the motor's drive changing (the first-order model's dead time).
    onset_s : float
        From a full-drive pulse's frame to its vibration reaching :data:`ONSET_FRACTION` of the
        full-drive amplitude (median over the pulses): what the skin and a validator see.
    tau_up_s, tau_down_s : float
        Spin-up and run-down time constants.
    residual : float
        RMS fit residual as a fraction of the full-drive amplitude.
    noise : float
        The envelope's RMS in silence, as the same fraction (what the residual cannot beat).
    levels : tuple of int
        The levels the amplitude is given at (0 first).
    amplitude : tuple of float
        Vibration amplitude at each level, sensor units (full scale 1).
    frequency_hz : tuple of float
        Vibration frequency at each level (NaN where too weak to read).
    snr_db : float
        Full-drive vibration power over the noise's, dB.
    warnings : tuple of str
        Problems with the input (``--out`` writes nothing unless accepted).
    notes : tuple of str
        Remarks on the result (first order fitting poorly).
    """

    cell: int
    name: str
    delay_s: float
    onset_s: float
    tau_up_s: float
    tau_down_s: float
    residual: float
    noise: float
    levels: tuple
    amplitude: tuple
    frequency_hz: tuple
    snr_db: float
    warnings: tuple = ()
    notes: tuple = field(default=())

    @property
    def response(self) -> tuple[tuple, tuple]:
        """``(drive, output)``: the amplitude against drive, 1 at full drive."""
        top = self.levels[-1]
        full = self.amplitude[-1] if self.amplitude[-1] > 0 else 1.0
        return (tuple(lv / top for lv in self.levels), tuple(a / full for a in self.amplitude))

    def to_dict(self) -> dict:
        """The JSON form (ms, Hz; NaN as None)."""

        def plain(v):
            return None if isinstance(v, float) and not math.isfinite(v) else v

        return {
            "cell": self.cell,
            "name": self.name,
            "tau_up_ms": round(self.tau_up_s * 1e3, 3),
            "tau_down_ms": round(self.tau_down_s * 1e3, 3),
            "delay_ms": round(self.delay_s * 1e3, 3),
            "onset_ms": plain(round(self.onset_s * 1e3, 3)),
            "residual": round(self.residual, 4),
            "noise": round(self.noise, 4),
            "snr_db": round(self.snr_db, 1),
            "levels": list(self.levels),
            "amplitude": [round(a, 6) for a in self.amplitude],
            "frequency_hz": [plain(round(f, 1)) for f in self.frequency_hz],
            "warnings": list(self.warnings),
            "notes": list(self.notes),
        }


@dataclass(frozen=True)
class Block:
    """Where one tactor's block lies in a recording.

    Attributes
    ----------
    cell : int
    neighbours : tuple of int
        The tactors scanned after it.
    start_s : float
        Recording seconds at which the block's time 0 falls.
    commands : Commands
        What was commanded, in recording seconds.
    """

    cell: int
    neighbours: tuple
    start_s: float
    commands: Commands


def analyse(x, samplerate: float, block: Block, plan: MeasurePlan, *, levels: int,
            names, others=None) -> TactorResult:  # fmt: skip
    """Measure one tactor from its block of a recording.

    Parameters
    ----------
    x : array_like of float, shape (n,)
        The sensor's channel (full scale 1).
    samplerate : float
    block : Block
    plan : MeasurePlan
        The plan the block played.
    levels : int
        The device's levels.
    names : sequence of str
        The name of every cell (``layout.cell_name``).
    others : dict, optional
        ``{input number: samples}`` of the interface's other inputs (numbered from 1 as on
        the interface), to tell a wrong channel from no signal.

    Raises
    ------
    MeasureError
        Clipping, no signal, a wrong channel, a tactor that does not move, the sensor on
        another tactor, two vibrations.
    """
    name = names[block.cell]
    what = f"tactor {name}"
    x = np.asarray(x, dtype=np.float64)
    check_clipping(x, what)
    top = levels - 1
    stimuli = [s for s in plan.block(block.cell, block.neighbours, levels)]
    t0 = block.start_s
    y = bandpass(x, samplerate)
    env = envelope(y, samplerate)
    quiet = (t0 + 0.05, t0 + plan.lead_in_s - 0.02)
    noise_power = env.mean(*quiet)
    if not np.isfinite(noise_power):
        raise MeasureError(f"{what}: the recording does not cover the silence before the "
                           "stimulus (the sensor started late?)")  # fmt: skip
    i0, i1 = (round(v * samplerate) for v in quiet)
    hum_hz, hum_amplitude = hum(y[max(i0, 0) : i1], samplerate)
    if hum_amplitude**2 / 2 > 0.25 * noise_power:  # much of the noise: take it off
        still = env.power < 1.5 * noise_power  # where nothing moves
        width = max(round(samplerate * (env.t_s[1] - env.t_s[0])), 1)
        at = np.minimum(np.arange(y.size) // width, still.size - 1)
        y = remove_hum(y, samplerate, still[at], hum_hz)
        env = envelope(y, samplerate)
        noise_power = env.mean(*quiet)
    full = [s for s in stimuli if s.kind == "step"][-1]
    steady = (t0 + full.start_s + 0.5 * plan.hold_s, t0 + full.end_s)
    full_power = env.mean(*steady) - noise_power
    snr = full_power / max(noise_power, 1e-30)
    scan = {names[s.cell]: _response(env, t0 + s.start_s + 0.5 * plan.scan_on_s,
                                     t0 + s.end_s + 0.03, noise_power)
            for s in stimuli if s.kind == "scan"}  # fmt: skip
    if not snr >= MIN_SNR:
        responding = {k: v for k, v in scan.items() if k != name and v[1] >= MIN_SNR}
        raise no_response(what, name, responding, _channel_snr(others, samplerate, quiet, steady))
    full_amplitude = math.sqrt(full_power)
    warnings = []
    scan_warning = check_scan(what, name, {k: v[0] for k, v in scan.items()})
    if scan_warning:
        warnings.append(scan_warning)
    hum_text = hum_warning(hum_hz, hum_amplitude, full_amplitude)
    if hum_text:
        warnings.append(hum_text)
    j0, j1 = (round(v * samplerate) for v in steady)
    check_second_vibration(what, name, y[j0:j1], samplerate, hum_hz if hum_amplitude else None)

    amplitude = np.sqrt(np.clip(env.power - noise_power, 0.0, None))
    fit_from = t0 + next(s for s in stimuli if s.kind == "step").start_s - 0.05
    fitted = env.t_s >= fit_from
    change, drive = block.commands.of(block.cell, top)
    nodes_lv = sorted({0, *plan.ramp_levels(levels), *plan.step_levels(levels)})
    fit = fit_envelope(env.t_s[fitted], amplitude[fitted], change, drive,
                       np.asarray(nodes_lv) / top)  # fmt: skip
    noise = float(np.sqrt(np.mean(amplitude[env.window(*quiet)] ** 2)) / fit.amplitude[-1])
    notes = []
    if fit.residual > max(RESIDUAL_NOTE, 2.0 * noise):
        notes.append(
            f"first order fits {name} poorly (residual {fit.residual:.0%} of the full-drive "
            f"amplitude, noise {noise:.0%}): the motor may overshoot, have two time constants "
            "or rattle; the constants are the best single time constants"
        )

    def effective(t):
        return first_order(t, change + fit.delay_s, drive, tau_up_s=fit.tau_up_s,
                           tau_down_s=fit.tau_down_s, start_s=float(env.t_s[0]))  # fmt: skip

    readable = max(3.0 * math.sqrt(noise_power), 0.02 * fit.amplitude[-1])
    freq = _frequencies(y, samplerate, plan, stimuli, t0 + fit.delay_s, levels, effective,
                        lambda s: np.interp(s, fit.nodes, fit.amplitude) >= readable,
                        np.asarray(nodes_lv) / top)  # fmt: skip
    onset = _onset(env, amplitude, [t0 + s.start_s for s in stimuli if s.kind == "pulse"],
                   ONSET_FRACTION * fit.amplitude[-1], plan.pulse_s + plan.pulse_gap_s)  # fmt: skip
    return TactorResult(
        cell=block.cell, name=name, delay_s=fit.delay_s, onset_s=onset, tau_up_s=fit.tau_up_s,
        tau_down_s=fit.tau_down_s, residual=fit.residual, noise=noise,
        levels=tuple(nodes_lv), amplitude=tuple(float(a) for a in fit.amplitude),
        frequency_hz=tuple(freq), snr_db=float(10 * np.log10(snr)), warnings=tuple(warnings),
        notes=tuple(notes),
    )  # fmt: skip


def _response(env, start_s: float, end_s: float, noise_power: float) -> tuple[float, float]:
    """``(amplitude, SNR)`` of a scan pulse from its mean power within the window."""
    mean = env.mean(start_s, end_s)
    power = max(mean - noise_power, 0.0) if np.isfinite(mean) else 0.0
    return math.sqrt(power), power / max(noise_power, 1e-30)


def _channel_snr(others, samplerate: float, quiet, steady) -> dict:
    """``{input: SNR}`` of the interface's other inputs at the full-drive step (``others``:
    ``{input number: samples}``)."""
    out = {}
    for k, x in (others or {}).items():
        env = envelope(bandpass(x, samplerate), samplerate)
        noise = env.mean(*quiet)
        out[k] = (env.mean(*steady) - noise) / max(noise, 1e-30)
    return out


def _frequencies(y, samplerate, plan, stimuli, t0, levels, effective, loud, drives):
    """The vibration frequency at each of ``drives``: the spectral peak of the steady part of
    each ramp step and step hold, placed at the motor's mean effective drive there (from the
    fit: a slow motor lags the ramp), and interpolated onto the drives; NaN outside the
    effective drives read (but up to :data:`EXTRAPOLATE` past the highest, along the last two
    readings: a slow motor never settles at full drive within a step), and where the vibration
    is too weak to read (``loud`` false)."""
    ramp = plan.ramp_levels(levels)
    windows = []
    for s in stimuli:
        if s.kind == "ramp":
            for i in range(len(ramp)):
                a = s.start_s + i * plan.ramp_step_s
                windows.append((a + 0.4 * plan.ramp_step_s, a + plan.ramp_step_s))
        elif s.kind == "step":
            windows.append((s.start_s + 0.5 * plan.hold_s, s.end_s))
    read = []
    for a, b in windows:
        t = np.linspace(t0 + a, t0 + b, 16)
        s_mean = float(np.mean(effective(t)))
        if not loud(s_mean):
            continue
        i, j = (round(v * samplerate) for v in (t0 + a, t0 + b))
        found = peaks(y[max(i, 0) : j], samplerate, count=1)
        if found:
            read.append((s_mean, found[0][0]))
    out = np.full(len(drives), np.nan)
    if read:
        read.sort()
        s_read, f_read = (np.array(v) for v in zip(*read))
        inside = (drives >= s_read[0] - 0.02) & (drives <= s_read[-1]) & (drives > 0)
        out[inside] = np.interp(drives[inside], s_read, f_read)
        beyond = (drives > s_read[-1]) & (drives <= s_read[-1] + EXTRAPOLATE)
        if beyond.any() and s_read.size >= 2 and s_read[-1] - s_read[-2] > 1e-3:
            slope = (f_read[-1] - f_read[-2]) / (s_read[-1] - s_read[-2])
            out[beyond] = f_read[-1] + slope * (drives[beyond] - s_read[-1])
    return out.tolist()


def _onset(env, amplitude, starts, level: float, reach_s: float) -> float:
    """Median time from each pulse's command to the amplitude reaching ``level``: the last
    upward crossing of ``level`` before the pulse reaches half its peak (noise that pokes above
    ``level`` earlier does not count); NaN for pulses that stay below it."""
    found = []
    for start in starts:
        inside = env.window(start - 0.002, start + reach_s)
        t, a = env.t_s[inside], amplitude[inside]
        if a.size < 3 or a.max() < level:
            continue
        half = int(np.argmax(a >= max(0.5 * a.max(), level)))
        below = np.flatnonzero(a[: half + 1] < level)
        if below.size == 0:
            continue
        i = int(below[-1])
        found.append(crossing_s(t[i : half + 1], a[i : half + 1], level) - start)
    return float(np.median(found)) if found else float("nan")
