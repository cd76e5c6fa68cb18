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
MAX_SHAPE_NUMBERS = 512
"""Most numbers in a ``/tactile/shape`` spec (a polyline of 256 points, a timed path of 128),
counted before it is read: reading a point costs about what a point message does, and a
spec of 4,000 points took 34 ms (a file or ``tactile render`` takes up to 10,000)."""
LABEL_CHARS = 48
"""A shape's spec longer than this is shown cut, with its number of points."""


def shape_label(shape) -> str:
    """A shape's spec for a status line: whole when short, else its start and how many points
    (``polyline:0.5,0.5,1,1,… (4000 points)``), at most about 70 characters."""
    spec = shape.spec
    if len(spec) <= LABEL_CHARS:
        return spec
    points = getattr(shape, "points", None)
    count = f" ({len(points)} points)" if points is not None else ""
    return spec[: spec.rfind(",", 0, LABEL_CHARS) + 1] + "…" + count


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
    ``/tactile/mu``, ``/tactile/gamma``, ``/tactile/shape``, ``/tactile/off``,
    ``/tactile/state`` and ``/tactile/reply``.

    The server provides ``points``, ``_n`` (the counters), ``_base`` (the points' scene),
    ``_problem_of``, ``_points_scene``, ``_change``, ``_play``, ``off``, ``replies``, ``_from``
    (the datagram's sender), ``_sock``, ``_current``, ``_playing`` and ``clock``.
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
        elif address == "/tactile/state":
            self._state(address, args)
        elif address == "/tactile/reply":
            if (
                len(args) > 1
                or (args and type(args[0]) is not int)
                or not (not args or 0 <= args[0] <= 65535)
            ):
                return self._problem_of("wrong_type", f"{address} takes an optional port "
                                        "(an int: 0 for no replies)")  # fmt: skip
            self.replies.ask(self._from, args[0] if args else None)
            self._n["queries"] += 1
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

    def _state(self, address: str, args: list) -> None:
        """Answer ``/tactile/state`` with ``/tactile/state METHOD MU GAMMA POINTS PLAYING``."""
        if args:  # another server's answer, not a query: never answered
            return self._problem_of("wrong_type", f"{address} takes no arguments")
        self._n["queries"] += 1
        scene = self._current
        to = self.replies.destination(self._from, query=True)
        state = (scene.method, float(scene.mu), float(scene.gamma), len(self.points.points),
                 self._playing)  # fmt: skip
        self.replies.send(self._sock, to, "/tactile/state", state, self.clock())

    def _shape_message(self, address: str, args: list, now: float) -> None:
        if len(args) != 2 or not isinstance(args[0], str) or not _number(args[1]):
            return self._problem_of("wrong_type", f"{address} takes SHAPE DURATION_S")
        numbers = args[0].count(",") + 1  # counted before the spec is read
        if numbers > MAX_SHAPE_NUMBERS:
            return self._problem_of("out_of_range", f"{address}: a shape of at most "
                                    f"{MAX_SHAPE_NUMBERS // 2} points ({MAX_SHAPE_NUMBERS} "
                                    f"numbers) over OSC, got {numbers} numbers")  # fmt: skip
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
