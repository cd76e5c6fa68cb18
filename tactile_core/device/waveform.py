"""What an audio array's channel plays: a waveform, as an immutable value with a compact spec.

The audio transport (:mod:`tactile_core.device.audio`) plays one waveform per channel at the
amplitude the level sets; ``tactile render --out FILE.wav`` writes the same samples. A waveform
is a *shape* at a frequency, with an optional ADSR envelope applied at each onset of the channel
(the channel going from off to lit). Its spec, as profiles, patterns and URLs write it::

    sine                     the plain carrier: a sine at the channel's carrier frequency
    sine:250                 a sine at 250 Hz; square:200, saw:150, triangle:150 likewise
    square                   a square wave at the channel's carrier frequency
    noise                    white noise, uniform in [-1, 1); noise:seed=7 another sequence
    sweep:100-300:500ms      a sine whose frequency glides from 100 to 300 Hz in 500 ms after
                             each onset, then stays at 300 Hz; sweep:100-300:500ms:log
                             glides exponentially (equal time per octave)
    square:200+adsr:5,20,0.7,50
                             any of them with an envelope: attack 5 ms, decay 20 ms to a
                             sustain of 0.7, release 50 ms

``docs/device.md`` ("Waveforms") gives the samples each one makes. :func:`parse_waveform`
reads a spec strictly: every refusal is a :class:`WaveformError` that shows the spec and names
the field (``frequency``, ``duration``, ``adsr release`` ...).

>>> w = parse_waveform("sweep:100-300:500ms+adsr:5,20,0.7,50")
>>> w.shape, w.carrier_hz, w.end_hz, w.sweep_ms, w.adsr.sustain
('sweep', 100.0, 300.0, 500.0, 0.7)
>>> w.spec
'sweep:100-300:500ms+adsr:5,20,0.7,50'
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .._shared import validate as _validate

SHAPES = ("sine", "square", "saw", "triangle", "noise", "sweep")
"""The waveform shapes, as a spec names them."""
PERIODIC = ("sine", "square", "saw", "triangle")
"""The shapes that repeat at one frequency (the channel's carrier unless the spec gives one)."""
SCALES = ("lin", "log")
"""How a sweep's frequency glides: linearly in hertz, or exponentially (equal time an octave)."""
CARRIER_RANGE_HZ = (1.0, 1000.0)
"""Frequencies a waveform or a profile may give (vibrotactile: up to ~1 kHz)."""
SWEEP_RANGE_MS = (1.0, 60_000.0)
"""Durations a sweep may glide over."""
ADSR_RANGE_MS = (0.0, 10_000.0)
"""Attack, decay and release times an envelope may take."""
MAX_SEED = 999
"""Noise seeds are 0 .. MAX_SEED."""
MAX_SPEC_CHARS = 200
"""Longest spec read."""


class WaveformError(ValueError):
    """A waveform spec or value that cannot be used; the message names the field."""


def _num(x: float) -> str:
    """A number as a spec writes it: the shortest text that reads back equal, no ``.0``."""
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


@dataclass(frozen=True)
class Adsr:
    """An attack-decay-sustain-release envelope, applied at each onset of a channel.

    From an onset the envelope rises linearly from 0 (or from where a release had left it) to 1
    over ``attack_ms``, falls linearly to ``sustain`` over ``decay_ms`` and holds there while
    the channel stays lit; when the channel goes off it falls linearly from where it is to 0
    over ``release_ms``, the channel holding its last level meanwhile. It multiplies the
    amplitude the level sets.

    Parameters
    ----------
    attack_ms, decay_ms, release_ms : float
        Milliseconds, within :data:`ADSR_RANGE_MS`.
    sustain : float
        The level it holds, a fraction of the peak in [0, 1].
    """

    attack_ms: float
    decay_ms: float
    sustain: float
    release_ms: float

    def __post_init__(self):
        for name in ("attack_ms", "decay_ms", "release_ms"):
            value = _checked(name, getattr(self, name), *ADSR_RANGE_MS, " ms")
            object.__setattr__(self, name, value)
        object.__setattr__(self, "sustain", _checked("sustain", self.sustain, 0.0, 1.0, ""))

    @property
    def spec(self) -> str:
        """``adsr:A,D,S,R`` (the suffix of a waveform spec, without its ``+``)."""
        values = (self.attack_ms, self.decay_ms, self.sustain, self.release_ms)
        return "adsr:" + ",".join(_num(v) for v in values)


def _checked(name: str, value, lo: float, hi: float, unit: str) -> float:
    """``value`` as a float within ``[lo, hi]``; :class:`WaveformError` naming ``name``."""
    if not _validate.is_number(value) or not math.isfinite(float(value)):
        raise WaveformError(f"{name} must be a finite number, got {_validate.shown(value)}")
    value = float(value)
    if not lo <= value <= hi:
        raise WaveformError(f"{name} must be within {lo:g}-{hi:g}{unit}, got {_num(value)}")
    return value


@dataclass(frozen=True)
class Waveform:
    """One channel's signal: a shape at a frequency, with an optional envelope.

    Parameters
    ----------
    shape : {"sine", "square", "saw", "triangle", "noise", "sweep"}
        Sine, square (+1 for the first half of each period, -1 for the second), saw (rising
        from 0 through +1, jumping to -1 at half a period), triangle (0, +1, 0, -1 a quarter
        period apart), white noise, or a sine sweep.
    carrier_hz : float, optional
        The frequency of a periodic shape, or where a sweep starts, in Hz. None: the channel's
        carrier (the profile's ``carrier_hz``); a sweep needs one.
    end_hz : float, optional
        Where a sweep ends, in Hz (a sweep only; not equal to ``carrier_hz``).
    sweep_ms : float, optional
        How long a sweep glides after each onset, in ms (a sweep only).
    scale : {"lin", "log"}
        How a sweep glides (a sweep only).
    seed : int
        Which noise sequence (noise only), 0 .. :data:`MAX_SEED`.
    adsr : Adsr, optional
        The envelope applied at each onset; None: the amplitude follows the level alone.
    """

    shape: str = "sine"
    carrier_hz: float | None = None
    end_hz: float | None = None
    sweep_ms: float | None = None
    scale: str = "lin"
    seed: int = 0
    adsr: Adsr | None = None

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise WaveformError(f"shape must be one of {', '.join(SHAPES)}, got "
                                f"{_validate.shown(self.shape)}")  # fmt: skip
        sweep = self.shape == "sweep"
        if self.carrier_hz is not None:
            if self.shape == "noise":
                raise WaveformError("carrier_hz does not apply to noise")
            hz = _checked("carrier_hz", self.carrier_hz, *CARRIER_RANGE_HZ, " Hz")
            object.__setattr__(self, "carrier_hz", hz)
        for name in ("end_hz", "sweep_ms"):
            if (getattr(self, name) is None) == sweep:
                raise WaveformError(f"{name} {'is needed by' if sweep else 'applies only to'} "
                                    f"a sweep")  # fmt: skip
        if sweep:
            if self.carrier_hz is None:
                raise WaveformError("carrier_hz (where the sweep starts) is needed by a sweep")
            end = _checked("end_hz", self.end_hz, *CARRIER_RANGE_HZ, " Hz")
            if end == self.carrier_hz:
                raise WaveformError(f"end_hz must differ from carrier_hz (a sweep glides "
                                    f"between two frequencies), both are {_num(end)}")  # fmt: skip
            object.__setattr__(self, "end_hz", end)
            ms = _checked("sweep_ms", self.sweep_ms, *SWEEP_RANGE_MS, " ms")
            object.__setattr__(self, "sweep_ms", ms)
        if self.scale not in SCALES or (self.scale != "lin" and not sweep):
            raise WaveformError(f"scale must be 'lin' or, for a sweep, 'log', got "
                                f"{_validate.shown(self.scale)}")  # fmt: skip
        if isinstance(self.seed, bool) or not isinstance(self.seed, int):
            raise WaveformError(f"seed must be a whole number, got {_validate.shown(self.seed)}")
        if not 0 <= self.seed <= MAX_SEED or (self.seed and self.shape != "noise"):
            raise WaveformError(f"seed must be within 0-{MAX_SEED} (noise only), got "
                                f"{self.seed}")  # fmt: skip
        if self.adsr is not None and not isinstance(self.adsr, Adsr):
            raise WaveformError(f"adsr must be an Adsr, got {_validate.shown(self.adsr)}")

    @property
    def spec(self) -> str:
        """The compact spec that :func:`parse_waveform` reads back equal."""
        if self.shape == "sweep":
            text = f"sweep:{_num(self.carrier_hz)}-{_num(self.end_hz)}:{_num(self.sweep_ms)}ms"
            text += ":log" if self.scale == "log" else ""
        elif self.shape == "noise":
            text = f"noise:seed={self.seed}" if self.seed else "noise"
        else:
            hz = self.carrier_hz
            text = self.shape if hz is None else f"{self.shape}:{_num(hz)}"
        return text if self.adsr is None else f"{text}+{self.adsr.spec}"

    def __str__(self) -> str:
        return self.spec

    @property
    def plain(self) -> bool:
        """True for the plain carrier: a sine at the channel's carrier, no envelope (what
        every array without a ``waveform`` plays, and all a serial array can)."""
        return self == PLAIN

    def at_carrier(self, carrier_hz: float) -> Waveform:
        """This waveform with ``carrier_hz`` filled in where it gives no frequency (a
        periodic shape at the channel's carrier); itself otherwise."""
        if self.shape in PERIODIC and self.carrier_hz is None:
            return replace(self, carrier_hz=carrier_hz)
        return self


PLAIN = Waveform()
"""The plain carrier, ``sine``: what a channel plays without a waveform of its own."""


def parse_waveform(spec, what: str = "waveform") -> Waveform:
    """Read a waveform spec (the grammar is in the module's notes and ``docs/device.md``).

    Parameters
    ----------
    spec : str or Waveform
        ``"square:200"``, ``"sweep:100-300:500ms"``, ``"noise"``, ``"sine:250+adsr:5,20,0.7,50"``;
        a :class:`Waveform` is returned as it is.
    what : str
        How messages name the spec (``"waveform"``, ``"effects[2].waveform"``).

    Raises
    ------
    WaveformError
        ``waveform 'square:2000': frequency must be within 1-1000 Hz, got 2000``: the spec and
        the field (``shape``, ``frequency``, ``start frequency``, ``end frequency``,
        ``duration``, ``scale``, ``seed``, ``adsr``, ``adsr attack``, ``adsr decay``, ``adsr
        sustain``, ``adsr release``).
    """
    if isinstance(spec, Waveform):
        return spec
    if not isinstance(spec, str):
        raise WaveformError(f"{what} must be a spec such as 'square:200', got "
                            f"{_validate.shown(spec)}")  # fmt: skip
    if len(spec) > MAX_SPEC_CHARS:
        raise WaveformError(f"{what} must be at most {MAX_SPEC_CHARS} characters, got "
                            f"{len(spec)}")  # fmt: skip
    head = f"{what} {spec!r}"
    body, plus, tail = spec.partition("+")
    adsr = _adsr(tail, head) if plus else None
    name, _, rest = body.partition(":")
    if name not in SHAPES:
        raise WaveformError(f"{head}: shape must be one of {', '.join(SHAPES)}, got {name!r}")
    fields = rest.split(":") if rest else []
    try:
        if name == "sweep":
            return _sweep(fields, head, adsr)
        if name == "noise":
            return Waveform("noise", seed=_seed(fields, head), adsr=adsr)
        if len(fields) > 1:
            raise WaveformError(f"{head}: {name} takes one field, its frequency ({name}:HZ), "
                                f"got {len(fields)}")  # fmt: skip
        hz = _number(fields[0], head, "frequency", *CARRIER_RANGE_HZ, " Hz") if fields else None
        return Waveform(name, carrier_hz=hz, adsr=adsr)
    except WaveformError as exc:
        if str(exc).startswith(head):
            raise
        raise WaveformError(f"{head}: {exc}") from None


def _number(text: str, head: str, field: str, lo: float, hi: float, unit: str) -> float:
    try:
        value = float(_validate.decimal_text(field, text))
    except ValueError:
        raise WaveformError(f"{head}: {field} must be a number, got {text!r}") from None
    if not (math.isfinite(value) and lo <= value <= hi):
        raise WaveformError(f"{head}: {field} must be within {lo:g}-{hi:g}{unit}, got {text}")
    return value


def _sweep(fields: list, head: str, adsr) -> Waveform:
    if len(fields) not in (2, 3):
        raise WaveformError(f"{head}: a sweep is sweep:F0-F1:DURATIONms[:log], got "
                            f"{len(fields)} field{'s' * (len(fields) != 1)}")  # fmt: skip
    start, dash, end = fields[0].partition("-")
    if not dash:
        raise WaveformError(f"{head}: frequencies must be F0-F1 in Hz (sweep:100-300:500ms), "
                            f"got {fields[0]!r}")  # fmt: skip
    f0 = _number(start, head, "start frequency", *CARRIER_RANGE_HZ, " Hz")
    f1 = _number(end, head, "end frequency", *CARRIER_RANGE_HZ, " Hz")
    if f0 == f1:
        raise WaveformError(f"{head}: end frequency must differ from the start frequency, "
                            f"both are {_num(f0)} Hz")  # fmt: skip
    if not fields[1].endswith("ms"):
        raise WaveformError(f"{head}: duration must be milliseconds with 'ms' (500ms), got "
                            f"{fields[1]!r}")  # fmt: skip
    ms = _number(fields[1][:-2], head, "duration", *SWEEP_RANGE_MS, " ms")
    scale = fields[2] if len(fields) == 3 else "lin"
    if scale not in SCALES:
        raise WaveformError(f"{head}: scale must be lin or log, got {scale!r}")
    return Waveform("sweep", carrier_hz=f0, end_hz=f1, sweep_ms=ms, scale=scale, adsr=adsr)


def _seed(fields: list, head: str) -> int:
    if not fields:
        return 0
    key, eq, text = fields[0].partition("=")
    if len(fields) > 1 or key != "seed" or not eq:
        raise WaveformError(f"{head}: noise takes one field, seed=N (noise:seed=7), got "
                            f"{':'.join(fields)!r}")  # fmt: skip
    if not _validate.WHOLE.fullmatch(text) or not 0 <= int(text) <= MAX_SEED:
        raise WaveformError(f"{head}: seed must be a whole number within 0-{MAX_SEED}, got "
                            f"{text!r}")  # fmt: skip
    return int(text)


def _adsr(text: str, head: str) -> Adsr:
    name, colon, values = text.partition(":")
    if name != "adsr" or not colon:
        raise WaveformError(f"{head}: adsr must follow '+' as adsr:A,D,S,R, got {text!r}")
    parts = values.split(",")
    if len(parts) != 4:
        raise WaveformError(f"{head}: adsr takes four values, attack, decay and release in ms "
                            f"and sustain in 0-1 (adsr:5,20,0.7,50), got {len(parts)}")  # fmt: skip
    lo, hi = ADSR_RANGE_MS
    attack = _number(parts[0], head, "adsr attack", lo, hi, " ms")
    decay = _number(parts[1], head, "adsr decay", lo, hi, " ms")
    sustain = _number(parts[2], head, "adsr sustain", 0.0, 1.0, "")
    release = _number(parts[3], head, "adsr release", lo, hi, " ms")
    return Adsr(attack, decay, sustain, release)


__all__ = [
    "ADSR_RANGE_MS",
    "CARRIER_RANGE_HZ",
    "MAX_SEED",
    "PERIODIC",
    "PLAIN",
    "SCALES",
    "SHAPES",
    "SWEEP_RANGE_MS",
    "Adsr",
    "Waveform",
    "WaveformError",
    "parse_waveform",
]
