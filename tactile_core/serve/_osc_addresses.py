"""The address space of the OSC server: what each message does, and what is wrong with it.

:class:`AddressSpace` is the half of :class:`~tactile_core.serve.OscServer` that turns one
message (an address and its arguments, already read from a datagram) into a point update, a
release, a new scene, or one count of a problem with the reason kept as ``last_problem``. It runs
on the server's receiver thread; everything it changes is swapped in whole (the points table,
the scene), so the stream's output thread never waits for it.
"""

from __future__ import annotations

import math
import struct

from .._shared import validate as _validate
from .._shared.validate import MAX_COORD
from ..rendering.correction import check_correction
from ..rendering.points import MAX_ID_CHARS

MAX_SHAPE_S = 3600.0
"""Longest ``/tactile/shape`` duration, in seconds."""


_F32 = struct.Struct(">f")


def decimal32(value: float) -> float:
    """``value`` as the shortest decimal that is the same 32-bit float, when it is one (an OSC
    ``f`` argument: python-osc, Max and Unity send 0.33 as 0.33000001311302185), else as it is.

    Parameters
    ----------
    value : float

    Returns
    -------
    float
        ``0.33`` for ``0.33000001311302185``; a value no 32-bit float equals (an OSC ``d``
        argument such as 0.1) unchanged.
    """
    if not math.isfinite(value):
        return value
    try:
        packed = _F32.pack(value)
    except OverflowError:
        return value
    if _F32.unpack(packed)[0] != value:
        return value
    for digits in range(1, 10):  # 9 significant digits always round-trip a float32
        shorter = float(f"{value:.{digits}g}")
        try:
            if _F32.pack(shorter) == packed:
                return shorter
        except OverflowError:  # rounded up past the largest float32 (3.4028235e38)
            continue
    return value


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class AddressSpace:
    """``/tactile/point``, ``/tactile/point/<id>``, ``/tactile/release``, ``/tactile/method``,
    ``/tactile/mu``, ``/tactile/gamma``, ``/tactile/shape``, ``/tactile/off``.

    The server provides ``points``, ``_n`` (the counters), ``_base`` (the points' scene),
    ``_problem_of``, ``_points_scene``, ``_change``, ``_play`` and ``off``.
    """

    def _handle(self, address: str, args: list, now: float) -> None:
        if address == "/tactile/point" or address.startswith("/tactile/point/"):
            self._point(address, address[len("/tactile/point/") :], args, now)
        elif address == "/tactile/release":
            if (
                len(args) > 1
                or (args and not isinstance(args[0], (str, int)))
                or (args and isinstance(args[0], bool))
            ):
                return self._problem_of("wrong_type", f"{address} takes an optional id")
            self.points.release(str(args[0]) if args else None)
            self._n["releases"] += 1
        elif address == "/tactile/off":  # whatever its arguments: off is never refused
            self.off()
            self._n["controls"] += 1
        elif address == "/tactile/method":
            if len(args) != 1 or not isinstance(args[0], str):
                return self._problem_of("wrong_type", f"{address} takes one string")
            try:
                scene = self._points_scene(self._base.replace(method=args[0]))
            except ValueError as exc:
                return self._problem_of("refused", f"{address} {args[0][:40]}: {exc}")
            self._change(method=scene.method)
            self._n["controls"] += 1
        elif address in ("/tactile/mu", "/tactile/gamma"):
            self._correction(address, address[len("/tactile/") :], args)
        elif address == "/tactile/shape":
            self._shape_message(address, args, now)
        else:
            self._problem_of("unknown", f"unknown address {address[:60]}")

    def _numbers(self, address: str, args: list, counts: tuple, what: str) -> list | None:
        """The arguments as floats, or None after counting what is wrong with them."""
        values = []
        if len(args) in counts:
            for a in args:
                kind = type(a)  # exact types: True is not a number here
                if kind is float:
                    values.append(a)
                elif kind is int:
                    values.append(float(a))
                else:
                    break
        if len(values) != len(args) or not values:
            self._problem_of("wrong_type", f"{address} takes {what}, got {_validate.shown(args)}")
            return None
        if not all(math.isfinite(v) for v in values):
            self._problem_of("non_finite", f"{address}: {_validate.shown(args)}")
            return None
        return values

    def _point(self, address: str, point_id: str, args: list, now: float) -> None:
        if address != "/tactile/point" and not point_id:
            return self._problem_of("unknown", "/tactile/point/ needs an id after the slash")
        values = self._numbers(address, args, (2, 3), "x y [intensity]")
        if values is None:
            return
        x, y = values[0], values[1]
        intensity = values[2] if len(values) == 3 else 1.0
        if not (abs(x) <= MAX_COORD and abs(y) <= MAX_COORD and 0.0 <= intensity <= 1.0):
            return self._problem_of("out_of_range", f"{address}: x and y must be within "
                                    f"±{MAX_COORD:g}, intensity within [0, 1], got "
                                    f"{_validate.shown(args)}")  # fmt: skip
        if len(point_id) > MAX_ID_CHARS:
            return self._problem_of("out_of_range", f"{address[:40]}...: an id has at most "
                                    f"{MAX_ID_CHARS} characters")  # fmt: skip
        try:
            self.points.put(point_id, x, y, intensity, now)
        except ValueError as exc:  # more points than the table holds
            return self._problem_of("out_of_range", f"{address}: {exc}")
        self._n["points"] += 1

    def _correction(self, address: str, name: str, args: list) -> None:
        values = self._numbers(address, args, (1,), "one number")
        if values is None:
            return
        base, value = self._base, decimal32(values[0])
        try:
            check_correction(value if name == "mu" else base.mu,
                             value if name == "gamma" else base.gamma)  # fmt: skip
        except ValueError as exc:
            return self._problem_of("out_of_range", f"{address}: {exc}")
        self._change(**{name: value})
        self._n["controls"] += 1

    def _shape_message(self, address: str, args: list, now: float) -> None:
        if len(args) != 2 or not isinstance(args[0], str) or not _number(args[1]):
            return self._problem_of("wrong_type", f"{address} takes SHAPE DURATION_S")
        duration = decimal32(float(args[1]))
        if not math.isfinite(duration):
            return self._problem_of("non_finite", f"{address}: duration {args[1]!r}")
        if not 0.0 < duration <= MAX_SHAPE_S:
            return self._problem_of("out_of_range", f"{address}: duration must be within "
                                    f"(0, {MAX_SHAPE_S:g}] s, got {duration:g}")  # fmt: skip
        try:
            self._play(args[0], duration, now)
        except ValueError as exc:
            return self._problem_of("refused", f"{address} {args[0][:40]}: {exc}")
        self._n["shapes"] += 1
