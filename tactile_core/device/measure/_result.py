"""A whole measurement (every tactor measured, or why not), and the profile it writes.

``--out`` writes a copy of the device profile with the measured constants: ``motor`` gets one
spin-up and one run-down time constant per tactor (tactors not measured keep the profile's, or,
without any, the median of those measured) and a ``note`` that starts with "measured";
``response`` gets the amplitude against drive, the median over the tactors of each one's curve
(1 at full drive); ``measured`` keeps everything else (date, sensor, per tactor the delay,
onset, residual, amplitude and frequency at each level). A reader of the profile format ignores
``measured``; the motor-aware drive, the percept model and the tables read ``motor`` and
``response`` and say "measured" from the note.
"""

from __future__ import annotations

import datetime as dt
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..._shared.jsonfile import read_json, write_json_atomic
from ..profile import DeviceProfile, ProfileError, profile_from_dict
from ._analysis import TactorResult


@dataclass(frozen=True)
class ArrayMeasurement:
    """Every tactor of one run of the procedure.

    Attributes
    ----------
    profile_name : str
    tactors : tuple of TactorResult
        Those measured, in the order measured.
    failures : dict
        ``{tactor name: why}`` for those that gave no constants.
    sensor : str
        The sensor and its input.
    when : str
        ISO date and time of the run.
    seconds_per_tactor : float
        Stimulus seconds of one tactor's block (with 8 neighbours scanned).
    """

    profile_name: str
    tactors: tuple
    failures: dict = field(default_factory=dict)
    sensor: str = ""
    when: str = ""
    seconds_per_tactor: float = 0.0

    @property
    def warnings(self) -> list[str]:
        """Every input warning, prefixed with its tactor."""
        return [f"{t.name}: {w}" for t in self.tactors for w in t.warnings]

    def median(self, name: str) -> float:
        """The median over the tactors measured of attribute ``name`` (NaN if none)."""
        values = [getattr(t, name) for t in self.tactors]
        values = [v for v in values if math.isfinite(v)]
        return float(np.median(values)) if values else float("nan")

    def summary(self) -> dict:
        """The JSON form: medians in ms (``tau_up_ms``, ``tau_down_ms``, ``delay_ms``,
        ``onset_ms``), the worst residual, the amplitude curve, and every tactor."""

        def ms(name):
            v = self.median(name)
            return round(v * 1e3, 3) if math.isfinite(v) else None

        curve = median_response(self.tactors)
        return {
            "profile": self.profile_name,
            "sensor": self.sensor,
            "when": self.when,
            "tau_up_ms": ms("tau_up_s"),
            "tau_down_ms": ms("tau_down_s"),
            "delay_ms": ms("delay_s"),
            "onset_ms": ms("onset_s"),
            "residual_max": max((t.residual for t in self.tactors), default=None),
            "response": None if curve is None else {"drive": list(curve[0]),
                                                     "output": list(curve[1])},
            "seconds_per_tactor": round(self.seconds_per_tactor, 2),
            "tactors": [t.to_dict() for t in self.tactors],
            "failures": dict(self.failures),
            "warnings": self.warnings,
        }  # fmt: skip


def median_response(tactors) -> tuple[tuple, tuple] | None:
    """The median of the tactors' amplitude curves, each normalised to 1 at full drive, made
    non-decreasing: ``(drive, output)``, or None without tactors.

    Parameters
    ----------
    tactors : sequence of TactorResult or dict
        Results, or their JSON form (``levels``, ``amplitude``); those on other levels than
        the first are left out.
    """
    rows = [t.to_dict() if isinstance(t, TactorResult) else t for t in tactors]
    rows = [r for r in rows if _curve_ok(r)]
    if not rows:
        return None
    levels = rows[0]["levels"]
    curves = np.array([np.asarray(r["amplitude"]) / r["amplitude"][-1] for r in rows
                       if r["levels"] == levels])  # fmt: skip
    out = np.maximum.accumulate(np.clip(np.median(curves, axis=0), 0.0, 1.0))
    out[-1] = 1.0
    top = levels[-1]
    return tuple(round(lv / top, 6) for lv in levels), tuple(round(float(v), 4) for v in out)


def _curve_ok(row) -> bool:
    """A tactor's JSON form whose curve can be used (a file may have been edited by hand)."""
    try:
        levels, amplitude = list(row["levels"]), list(row["amplitude"])
        return (len(levels) == len(amplitude) >= 2 and levels[0] == 0
                and all(isinstance(v, int) for v in levels) and levels == sorted(set(levels))
                and all(isinstance(a, (int, float)) and math.isfinite(a) for a in amplitude)
                and amplitude[-1] > 0)  # fmt: skip
    except (KeyError, TypeError):
        return False


def measured_note(result: ArrayMeasurement, measured: list, size: int) -> str:
    """The ``motor.note`` of a measured profile: starts with "measured"."""
    names = ", ".join(str(t.get("name")) for t in measured[:8])
    more = f" and {len(measured) - 8} more" if len(measured) > 8 else ""
    worst = max((t.get("residual") or 0.0) for t in measured)
    return (
        f"measured {result.when[:10]} with {result.sensor} by tactile measure: tactors "
        f"{names}{more} ({len(measured)} of {size}); first-order fit of the vibration "
        f"envelope, residual at most {worst:.1%} of the full-drive amplitude"
    )


def measured_profile(profile: DeviceProfile, result: ArrayMeasurement) -> dict:
    """The JSON object of ``profile`` with ``result`` written in (see the module's text).

    A profile measured before keeps its other tactors: their constants stay in ``motor``,
    their entries in ``measured``, and their curves count in ``response``, so that an array
    can be measured a tactor at a time into one file.

    Raises
    ------
    ValueError
        When ``result`` measured no tactor.
    """
    if not result.tactors:
        raise ValueError("no tactor was measured: nothing to write into the profile")
    if profile.path and Path(profile.path).is_file():
        data = read_json(profile.path, ProfileError)
    else:
        data = profile.to_dict()
    size = profile.channels
    up, down = _expand(profile, result, size)
    for t in result.tactors:
        up[t.cell], down[t.cell] = t.tau_up_s * 1e3, t.tau_down_s * 1e3
    before = data.get("measured") if isinstance(data.get("measured"), dict) else {}
    kept = [t for t in before.get("tactors", []) if isinstance(t, dict)
            and t.get("cell") not in {r.cell for r in result.tactors}
            and isinstance(t.get("cell"), int) and 0 <= t["cell"] < size]  # fmt: skip
    measured = sorted(kept + [t.to_dict() for t in result.tactors], key=lambda t: t["cell"])
    data["motor"] = {"tau_up_ms": [round(v, 3) for v in up],
                     "tau_down_ms": [round(v, 3) for v in down],
                     "note": measured_note(result, measured, size)}  # fmt: skip
    drive, output = median_response(measured) or median_response(result.tactors)
    data["response"] = {
        "note": f"measured {result.when[:10]} with {result.sensor}: vibration amplitude "
        f"against drive, 1 at full drive, the median over {len(measured)} tactors",
        "drive": list(drive),
        "output": list(output),
    }
    data["measured"] = {"when": result.when, "sensor": result.sensor, "tactors": measured}
    profile_from_dict(data, source="the measured profile")  # what a reader will check
    return data


def _expand(profile: DeviceProfile, result: ArrayMeasurement, size: int):
    """Per-tactor spin-up and run-down lists (ms) before the measured ones go in."""
    if profile.motor is not None:
        up, down = (t * 1e3 for t in profile.motor.taus(size))
        return list(map(float, up)), list(map(float, down))
    return ([result.median("tau_up_s") * 1e3] * size, [result.median("tau_down_s") * 1e3] * size)


def write_measured_profile(path, profile: DeviceProfile, result: ArrayMeasurement) -> Path:
    """Write :func:`measured_profile` to ``path`` atomically."""
    return write_json_atomic(path, measured_profile(profile, result))


def not_written(result: ArrayMeasurement, *, accept_warnings: bool = False) -> str:
    """Why ``result`` must not go into a profile ("" when it may): a tactor that gave no
    constants, nothing measured, or (unless ``accept_warnings``) a warning about the input."""
    if result.failures:
        names = ", ".join(result.failures)
        return f"not written: no constants for {names} (the errors above say why)"
    if not result.tactors:
        return "not written: no tactor was measured"
    if result.warnings and not accept_warnings:
        return (
            "not written: the input was not as it should be (the warnings above); fix it "
            "and measure again, or --accept-warnings to write these constants anyway"
        )
    return ""


def save_measured(path, profile: DeviceProfile, result: ArrayMeasurement, *,
                  accept_warnings: bool = False) -> str:  # fmt: skip
    """Write the measured profile to ``path`` unless :func:`not_written` says why not; returns
    that reason ("" once written)."""
    why = not_written(result, accept_warnings=accept_warnings)
    if not why:
        write_measured_profile(path, profile, result)
    return why


def now_text() -> str:
    """The local date and time, ISO 8601 to the second."""
    return dt.datetime.now().astimezone().isoformat(timespec="seconds")
