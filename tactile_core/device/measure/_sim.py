"""The simulated sensor: the acceleration an array of first-order ERMs gives a sensor on one of
its tactors, at an audio samplerate.

Each tactor's motor follows its drive (the level commanded, ``delay_s`` after the frame's
time) with the first-order model of :mod:`._response` (``tau_up_s``, ``tau_down_s``). At
effective drive ``s`` it vibrates with amplitude ``amplitude * curve(s)`` (``curve``: a
piecewise-linear response, 0 below the drive an ERM needs to start, 1 at full drive) at the
frequency ``freq_lo_hz + (freq_hi_hz - freq_lo_hz) s`` (an ERM's vibration is its rotation: it
speeds up with the drive). The sensor sits on tactor ``on_cell`` and picks up another tactor
``d`` pitches away at ``coupling ** d`` of its amplitude. To that come white noise (``noise``
times the full-drive amplitude, RMS), mains hum (``hum`` times it, at ``hum_hz`` and a third
of that at its third harmonic), the interface's ``gain`` and its clipping at +-1 (full scale),
on ``channel`` of ``channels`` (the others carry the noise alone).

Faults for the bad-input checks: ``dead`` tactors do not move; ``also`` maps a tactor to
another that moves with it (a wiring fault: one channel, two motors).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..._shared import validate as _validate
from ._plan import Commands
from ._response import first_order

PALM_CURVE = ((0.0, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0), (0.0, 0.0, 0.3, 0.55, 0.78, 0.92, 1.0))
"""The palm profile's illustrative response (drive, output): nothing below 0.2 of full drive."""


def _per_cell(name: str, value, size: int, lo: float, hi: float) -> np.ndarray:
    arr = np.broadcast_to(np.asarray(value, dtype=np.float64), (size,)).copy()
    if not np.isfinite(arr).all() or (arr < lo).any() or (arr > hi).any():
        raise ValueError(f"{name} must be within [{lo:g}, {hi:g}] (one value or one per tactor), "
                         f"got {_validate.shown(value)}")  # fmt: skip
    return arr


@dataclass(frozen=True)
class SensorModel:
    """The motors of an array and a sensor on one of its tactors (see the module's text).

    Parameters
    ----------
    xy : array_like of float, shape (size, 2)
        Tactor positions in pitches (a layout's ``xy``).
    tau_up_s, tau_down_s : float or array_like, shape (size,)
        Motor time constants (s).
    delay_s : float
        From a frame's time to the motor's drive changing (s): host, link, driver.
    amplitude : float or array_like, shape (size,)
        Vibration amplitude at full drive on the tactor itself (full scale 1).
    curve : (drive, output)
        The steady amplitude against drive, as fractions (increasing drives from 0 to 1).
    freq_lo_hz, freq_hi_hz : float or array_like, shape (size,)
        Vibration frequency at drive 0 and 1.
    on_cell : int
        The tactor the sensor sits on.
    coupling : float
        What the sensor picks up of a tactor one pitch away (``coupling ** distance``).
    noise, hum : float
        White noise and mains hum, RMS and amplitude, as fractions of ``amplitude``.
    hum_hz : float
        Mains frequency (50 or 60).
    gain : float
        The interface's gain; the signal clips at +-1.
    channels, channel : int
        The interface's input channels and the one the sensor is on.
    dead : tuple of int
        Tactors that do not move.
    also : dict
        ``{cell: other}``: driving ``cell`` moves ``other`` too.
    levels : int
        The device's levels.
    """

    xy: np.ndarray
    tau_up_s: object = 0.03
    tau_down_s: object = 0.06
    delay_s: float = 0.005
    amplitude: object = 0.3
    curve: tuple = PALM_CURVE
    freq_lo_hz: object = 40.0
    freq_hi_hz: object = 220.0
    on_cell: int = 0
    coupling: float = 0.12
    noise: float = 0.02
    hum: float = 0.0
    hum_hz: float = 50.0
    gain: float = 1.0
    channels: int = 1
    channel: int = 0
    dead: tuple = ()
    also: dict = field(default_factory=dict)
    levels: int = 23

    def __post_init__(self):
        xy = np.asarray(self.xy, dtype=np.float64).reshape(-1, 2)
        object.__setattr__(self, "xy", xy)
        n = len(xy)
        for name, lo, hi in (("tau_up_s", 0.0, 10.0), ("tau_down_s", 0.0, 10.0),
                             ("amplitude", 0.0, 100.0), ("freq_lo_hz", 1.0, 5000.0),
                             ("freq_hi_hz", 1.0, 5000.0)):  # fmt: skip
            object.__setattr__(self, name, _per_cell(name, getattr(self, name), n, lo, hi))
        _validate.in_range("delay_s", self.delay_s, 0.0, 5.0)
        for name in ("noise", "hum"):
            _validate.in_range(name, getattr(self, name), 0.0, 100.0)
        _validate.in_range("coupling", self.coupling, 0.0, 1.0)
        _validate.in_range("gain", self.gain, 1e-6, 1e6)
        _validate.integer("on_cell", self.on_cell, 0, n - 1)
        _validate.integer("channels", self.channels, 1, 64)
        _validate.integer("channel", self.channel, 0, self.channels - 1)
        _validate.integer("levels", self.levels, 2, 256)
        drive, output = (np.asarray(v, dtype=np.float64) for v in self.curve)
        if drive.size < 2 or drive.size != output.size or np.any(np.diff(drive) <= 0):
            raise ValueError(f"curve must be (drive, output) of one length, drives increasing, "
                             f"got {_validate.shown(self.curve)}")  # fmt: skip
        object.__setattr__(self, "curve", (tuple(drive.tolist()), tuple(output.tolist())))

    def replace(self, **changes) -> SensorModel:
        """A copy with ``changes``."""
        return dataclasses.replace(self, **changes)

    def steady(self, cell: int, drive) -> np.ndarray:
        """The steady amplitude of ``cell`` at ``drive`` on itself (sensor units)."""
        if cell in self.dead:
            return np.zeros(np.shape(drive))
        return self.amplitude[cell] * np.interp(drive, *self.curve)

    def frequency_hz(self, cell: int, drive) -> np.ndarray:
        """The vibration frequency of ``cell`` at effective drive ``drive``."""
        lo, hi = self.freq_lo_hz[cell], self.freq_hi_hz[cell]
        return lo + (hi - lo) * np.asarray(drive, dtype=np.float64)

    def pickup(self) -> np.ndarray:
        """What the sensor gets of each tactor's vibration, ``(size,)``."""
        d = np.hypot(*(self.xy - self.xy[self.on_cell]).T)
        return np.where(d < 3.5, self.coupling**d, 0.0)


class SimulatedSensor:
    """Renders the sensor's signal for commanded levels, block after block.

    Parameters
    ----------
    model : SensorModel
    samplerate : int
        Samples per second.
    seed : int
        Seeds the noise.

    Each :meth:`render` continues where the one before ended (the motors' states and phases
    carry over), so a live recording can be made a block at a time.
    """

    def __init__(self, model: SensorModel, samplerate: int = 8000, seed: int = 0):
        self.model = model
        self.samplerate = int(_validate.integer("samplerate", samplerate, 1000, 384000))
        self.rng = np.random.default_rng(seed)
        size = len(model.xy)
        self._s = np.zeros(size)
        self._phase = np.zeros(size)
        self._end: float | None = None

    def render(self, commands: Commands, t0_s: float, n: int) -> np.ndarray:
        """The signal of ``n`` samples from host time ``t0_s``.

        Parameters
        ----------
        commands : Commands
            Every level commanded so far (host times); those before the block set its drive.
        t0_s : float
            Host time of the first sample (after the previous block's end, if any).
        n : int
            Samples.

        Returns
        -------
        ndarray of float32, shape (n, channels)
            Within [-1, 1].
        """
        m, sr = self.model, self.samplerate
        t = t0_s + np.arange(n) / sr
        top = m.levels - 1
        pickup = m.pickup()
        x = np.zeros(n)
        drives = self._drives(commands, top)
        for cell, (change, drive) in drives.items():
            if cell in m.dead or pickup[cell] == 0.0:
                continue
            if self._s[cell] == 0.0 and not (drive > 0).any():
                continue
            change = change + m.delay_s
            start = t0_s if self._end is None else self._end
            before = change <= start
            d_prev = drive[before][-1] if before.any() else 0.0
            later = ~before & (change < t0_s + n / sr)
            s = first_order(np.r_[t, t0_s + n / sr], np.r_[start, change[later]],
                            np.r_[d_prev, drive[later]], tau_up_s=m.tau_up_s[cell],
                            tau_down_s=m.tau_down_s[cell], s0=self._s[cell],
                            start_s=start)  # fmt: skip
            s, self._s[cell] = s[:-1], s[-1]
            step = 2.0 * np.pi * m.frequency_hz(cell, s) / sr
            phase = self._phase[cell] + np.cumsum(step)
            x += pickup[cell] * m.steady(cell, s) * np.sin(phase - step)
            if n:
                self._phase[cell] = phase[-1] % (2.0 * np.pi)
        self._end = t0_s + n / sr
        full = float(np.max(m.amplitude))
        if m.hum:
            w = 2.0 * np.pi * m.hum_hz * t
            x += m.hum * full * (np.sin(w) + np.sin(3.0 * w + 0.5) / 3.0)
        out = self.rng.normal(0.0, m.noise * full, (n, m.channels))
        out[:, m.channel] += x
        return np.clip(out * m.gain, -1.0, 1.0).astype(np.float32)

    def _drives(self, commands: Commands, top: int) -> dict:
        """``{cell: (change_s, drive)}`` of every motor that moves, faults included."""
        out = {int(c): commands.of(int(c), top) for c in np.unique(commands.cell)}
        for cell, other in self.model.also.items():
            if cell in out:
                mine = out[cell]
                theirs = out.get(other, (np.zeros(0), np.zeros(0)))
                t = np.r_[mine[0], theirs[0]]
                order = np.argsort(t, kind="stable")
                which = np.r_[np.zeros(mine[0].size, int), np.ones(theirs[0].size, int)]
                level = np.round(np.r_[mine[1], theirs[1]] * top).astype(int)
                both = Commands(t[order], which[order], level[order])
                out[other] = _max_of(both, top)
        return out


def _max_of(both: Commands, top: int) -> tuple[np.ndarray, np.ndarray]:
    """The larger of two commanded drives (cells 0 and 1 of ``both``) at each change."""
    now = [0, 0]
    drive = []
    for c, lv in zip(both.cell.tolist(), both.level.tolist()):
        now[c] = lv
        drive.append(max(now) / top)
    return both.time_s, np.asarray(drive)
