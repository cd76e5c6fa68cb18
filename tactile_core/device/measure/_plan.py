"""What ``tactile measure`` plays to one tactor, and the levels it commands, as data.

A tactor's block (:meth:`MeasurePlan.block`) is, in order:

1. **silence** (``lead_in_s``): the sensor's noise and any mains hum, before anything moves;
2. **scan**: a short full-drive pulse on the tactor asked for, then on each of its
   neighbours: which tactor the sensor sits on (the asked one must answer loudest);
3. **steps**: for each level of ``step_drives``, the level for ``hold_s`` then off for
   ``rest_s``: spin-up and run-down from rest at several drives;
4. **ramp**: every ramp level in turn for ``ramp_step_s`` each, from the lowest to full drive,
   then off: amplitude and vibration frequency against level;
5. **pulses**: ``pulses`` pulses of ``pulse_s`` at full drive, ``pulse_gap_s`` apart: the
   delay to the first vibration, as a stimulus of an experiment starts;
6. silence (``tail_s``): the last run-down.

:class:`Commands` holds what was commanded (times, cells, levels): from the plan itself (the
simulated run) or read back from the frames a stream wrote (:func:`commands_from_frames`).
:class:`PlanFrames` plays a block as a stream's frame source.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._shared import validate as _validate

KINDS = ("scan", "step", "ramp", "pulse")


@dataclass(frozen=True)
class Stimulus:
    """One part of a block: ``kind`` (one of :data:`KINDS`), the ``cell`` driven at
    ``level`` from ``start_s`` to ``end_s`` (s from the block's start; a ramp's level is its
    top, its levels in :attr:`MeasurePlan.ramp_levels`)."""

    kind: str
    cell: int
    level: int
    start_s: float
    end_s: float


@dataclass(frozen=True)
class Commands:
    """Commanded levels: at ``time_s[i]`` cell ``cell[i]`` goes to ``level[i]``.

    Attributes
    ----------
    time_s : ndarray of float64, shape (n,)
        Host seconds (or seconds from a block's start), non-decreasing.
    cell : ndarray of int, shape (n,)
        Flat cell index (``row * cols + col`` on a grid; actuator index on a layout).
    level : ndarray of int, shape (n,)
        Device level from then on (0 = off).
    """

    time_s: np.ndarray
    cell: np.ndarray
    level: np.ndarray

    def of(self, cell: int, top: int) -> tuple[np.ndarray, np.ndarray]:
        """``(change_s, drive)`` of one cell: when its level changes and the drive fraction
        ``level / top`` from then on (repeats of the same level left out)."""
        mine = self.cell == cell
        t, lv = self.time_s[mine], self.level[mine]
        keep = np.r_[True, np.diff(lv) != 0] if lv.size else np.zeros(0, dtype=bool)
        return t[keep], lv[keep] / float(top)

    def shifted(self, offset_s: float) -> Commands:
        """The same commands ``offset_s`` later."""
        return Commands(self.time_s + offset_s, self.cell, self.level)


def commands_from_frames(time_s, levels, cells) -> Commands:
    """The changes in frames a stream wrote.

    Parameters
    ----------
    time_s : array_like of float, shape (frames,)
        Each frame's time (a streamer tap's ``time_s``: when it was written, or played).
    levels : array_like of int, shape (frames, channels)
        Each frame's levels in channel order.
    cells : array_like of int, shape (channels,)
        The cell of each channel.

    Returns
    -------
    Commands
        One entry per channel and frame at which its level differs from the frame before
        (the first frame against all off).
    """
    t = np.asarray(time_s, dtype=np.float64)
    lv = np.asarray(levels, dtype=np.int64).reshape(t.size, -1)
    before = np.vstack([np.zeros((1, lv.shape[1]), dtype=np.int64), lv[:-1]])
    k, ch = np.nonzero(lv != before)
    order = np.lexsort((ch, k))
    k, ch = k[order], ch[order]
    return Commands(t[k], np.asarray(cells, dtype=np.int64)[ch], lv[k, ch])


@dataclass(frozen=True)
class MeasurePlan:
    """The stimulus of one tactor's measurement (durations in seconds, drives in [0, 1]).

    The defaults suit ERMs with time constants up to about 100 ms (spin-up) and 200 ms
    (run-down): the fit takes the whole block at once, so a step need not settle fully.
    """

    lead_in_s: float = 0.4
    scan_on_s: float = 0.1
    scan_off_s: float = 0.25
    step_drives: tuple = (0.35, 0.5, 0.65, 0.8, 1.0)
    hold_s: float = 0.4
    rest_s: float = 0.5
    ramp_points: int = 22
    ramp_step_s: float = 0.15
    pulses: int = 5
    pulse_s: float = 0.04
    pulse_gap_s: float = 0.3
    tail_s: float = 0.5

    def __post_init__(self):
        for name in ("lead_in_s", "scan_on_s", "scan_off_s", "hold_s", "rest_s", "ramp_step_s",
                     "pulse_s", "pulse_gap_s", "tail_s"):  # fmt: skip
            _validate.in_range(name, getattr(self, name), 0.005, 60.0)
        if self.lead_in_s < 0.1:
            raise ValueError(f"lead_in_s must be at least 0.1 s (the noise before anything "
                             f"moves), got {self.lead_in_s:g}")  # fmt: skip
        drives = tuple(float(_validate.in_range("step_drives", d, 0.01, 1.0))
                       for d in np.atleast_1d(self.step_drives))  # fmt: skip
        if not drives:
            raise ValueError("step_drives must hold at least one drive")
        object.__setattr__(self, "step_drives", drives)
        _validate.integer("ramp_points", self.ramp_points, 2, 255)
        _validate.integer("pulses", self.pulses, 1, 100)

    def step_levels(self, levels: int) -> tuple[int, ...]:
        """The step levels on a device with ``levels`` levels (distinct, increasing, >= 1)."""
        top = levels - 1
        return tuple(sorted({max(1, round(d * top)) for d in self.step_drives}))

    def ramp_levels(self, levels: int) -> tuple[int, ...]:
        """The ramp's levels: every level from 1 to full, or ``ramp_points`` spread evenly."""
        top = levels - 1
        n = min(self.ramp_points, top)
        return tuple(sorted({max(1, round(x)) for x in np.linspace(top / n, top, n)}))

    def block(self, cell: int, neighbours=(), levels: int = 23) -> list[Stimulus]:
        """The stimuli of one tactor's block, in time order (times from the block's start).

        Parameters
        ----------
        cell : int
            The tactor measured (flat cell index).
        neighbours : sequence of int
            The tactors the scan pulses after it.
        levels : int
            The device's levels (full drive is ``levels - 1``).
        """
        top = levels - 1
        out = []
        t = self.lead_in_s
        for c in (cell, *neighbours):
            out.append(Stimulus("scan", int(c), top, t, t + self.scan_on_s))
            t += self.scan_on_s + self.scan_off_s
        t += self.rest_s - self.scan_off_s
        for lv in self.step_levels(levels):
            out.append(Stimulus("step", cell, lv, t, t + self.hold_s))
            t += self.hold_s + self.rest_s
        ramp = self.ramp_levels(levels)
        out.append(Stimulus("ramp", cell, ramp[-1], t, t + len(ramp) * self.ramp_step_s))
        t += len(ramp) * self.ramp_step_s + self.rest_s
        for _ in range(self.pulses):
            out.append(Stimulus("pulse", cell, top, t, t + self.pulse_s))
            t += self.pulse_s + self.pulse_gap_s
        return out

    def duration_s(self, neighbours: int = 8, levels: int = 23) -> float:
        """Seconds of one tactor's block with ``neighbours`` scanned (8 inside a grid)."""
        return self.block(0, range(1, neighbours + 1), levels)[-1].end_s + self.tail_s

    def commands(self, cell: int, neighbours=(), levels: int = 23) -> Commands:
        """The levels the block commands (times from its start)."""
        rows = []
        ramp = self.ramp_levels(levels)
        for s in self.block(cell, neighbours, levels):
            if s.kind == "ramp":
                rows += [(s.start_s + i * self.ramp_step_s, s.cell, lv)
                         for i, lv in enumerate(ramp)]  # fmt: skip
            else:
                rows.append((s.start_s, s.cell, s.level))
            rows.append((s.end_s, s.cell, 0))
        rows.sort(key=lambda r: r[0])
        t, c, lv = (np.array(v) for v in zip(*rows))
        return Commands(t.astype(np.float64), c.astype(np.int64), lv.astype(np.int64))


QUICK_PLAN = MeasurePlan(step_drives=(0.5, 1.0), hold_s=0.3, rest_s=0.4, ramp_points=11,
                         ramp_step_s=0.12, pulses=3)  # fmt: skip
"""A shorter block (``tactile measure --quick``: 8.0 s with 8 neighbours, against 14.0 s):
two steps, an 11-level ramp, three pulses; for motors up to about 60 ms (spin-up)."""


class PlanFrames:
    """A block as a stream's frame source: frame ``k`` holds the levels commanded at
    ``k / rate_hz`` s into the block (all off after it). The scene that plays it must leave
    the values alone (μ 0, γ 1, no calibration, felt domain off): :func:`measure_scene`."""

    precomputed = True

    def __init__(self, commands: Commands, levels: int, rate_hz: float):
        self.commands, self.levels = commands, levels
        self.top = levels - 1
        self.rate_hz = _validate.rate("rate_hz", rate_hz, 1.0, 10_000.0)
        self.times = commands.time_s
        self._states = []
        now: dict[int, int] = {}
        for c, lv in zip(commands.cell.tolist(), commands.level.tolist()):
            now = {**now, c: lv}
            self._states.append(tuple((k, v / self.top) for k, v in sorted(now.items()) if v))
        self.end_s = float(self.times[-1]) if self.times.size else 0.0

    def live(self, method, target, sampling, mu, gamma, gain=1.0) -> PlanFrames:
        """Itself at the stream's frame rate (the scene's method and correction do not
        apply)."""
        if sampling.rate_hz == self.rate_hz:
            return self
        return PlanFrames(self.commands, self.levels, sampling.rate_hz)

    def precompute(self, background: bool = False) -> None:
        """Nothing to tabulate."""

    def entries(self, k: int) -> tuple:
        """``((cell, drive), ...)`` of the cells lit at frame ``k``."""
        i = int(np.searchsorted(self.times, k / self.rate_hz + 1e-9, side="right")) - 1
        return self._states[i] if i >= 0 else ()
