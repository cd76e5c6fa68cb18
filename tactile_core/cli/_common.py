"""What the commands share: the usage error, the scene arguments and their checks,
``--seconds``, and the signals that stop a command quietly."""

from __future__ import annotations

import argparse
import contextlib
import signal
import threading
import time

from .._shared import validate as _validate
from ..rendering.correction import check_correction
from ..rendering.geometry import Grid
from ..rendering.methods import METHOD_NAMES, PEER_METHODS, get_method
from ..rendering.shapes import SHAPE_FORMS, SHAPE_KINDS, TimedPath, parse_shape
from ..rendering.trace import DIRECTIONS


class UsageError(Exception):
    """A problem with the command line or its files, reported without a traceback."""


def number(text: str) -> float:
    """``type=`` of a decimal option: ASCII digits only (``1_0``, full-width digits and padded
    spaces are refused, though ``float()`` takes them)."""
    try:
        return _validate.decimal_text("the value", text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("the value ")) from None


def whole(text: str) -> int:
    """``type=`` of a whole-number option (see :func:`number`)."""
    try:
        return _validate.decimal_text("the value", text, whole=True)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("the value ")) from None


DEVICE_HELP = (
    "a serial port (/dev/ttyUSB0, COM3), socket://HOST:PORT (tactile emulate --socket) or "
    "another pyserial URL; audio:[NAME][?channels=N&carrier_hz=F&...] for an audio interface, one "
    "channel per actuator; 'sim' for the simulated array"
)
"""``--device`` of the commands that open one."""


TACT_FORM = "tact:FILE.tact"
"""The ``--shape`` form of a bHaptics file (render and stream)."""
PATTERN_PREFIX = "pattern:"
PATTERN_FORM = "pattern:FILE.json"
"""The ``--shape`` form of a pattern file (render, stream, export-tact)."""
FILE_FORMS = f"{TACT_FORM} | {PATTERN_FORM}"
SHAPE_HELP = (
    " | ".join(SHAPE_FORMS) + f" | {FILE_FORMS}: one word, in grid units; a polygon closes; "
    "timed: each point's time (s) and intensity, OPTION speed (one speed) or tdm (at the "
    "points' times, the default), fade-in, fade-out or fade-in-out (;speed;fade-in for two); "
    "tact: a bHaptics file; pattern: a pattern file (docs/patterns.md)"
)
"""``--shape``: every form the parser takes."""


def profile_help(what: str = "") -> str:
    """``--profile``'s help: a bundled profile's name (each listed) or a JSON file; ``what``
    says what the command takes from it."""
    from .._shared.assets import assets_dir

    names = sorted(p.stem for p in (assets_dir() / "devices").glob("*.json"))
    return (f"device profile{what}: a name ({', '.join(names)}) or a JSON file (default: the "
            "palm array)")  # fmt: skip


def _add_scene_arguments(p: argparse.ArgumentParser, *, duration: float) -> None:
    p.add_argument(
        "--shape",
        required=True,
        metavar="SHAPE",
        help=SHAPE_HELP,
    )
    paper, peers = ", ".join(METHOD_NAMES), ", ".join(PEER_METHODS)
    p.add_argument("--method", required=True, metavar="M",
                   help=f"the paper's {paper}, the peers {peers}, BA (AS's weights on any "
                   "layout) or a plug-in; parameters as RO:r=1.5 or GS:sigma=0.7")  # fmt: skip
    p.add_argument("--mu", type=number, default=0.0, help="threshold in [0, 1] (default 0)")
    p.add_argument("--gamma", type=number, default=1.0, help="gamma > 0 (default 1)")
    p.add_argument(
        "--duration",
        type=number,
        default=None,
        help=f"seconds per trace (default {duration:g}; a timed path's own)",
    )
    p.set_defaults(default_duration=duration)
    p.add_argument("--direction", choices=DIRECTIONS, default="forward")
    p.add_argument("--cols", type=whole, default=5, help="grid columns (default 5)")
    p.add_argument("--rows", type=whole, default=6, help="grid rows (default 6)")


def add_compensate_motors(p: argparse.ArgumentParser) -> None:
    """``--compensate-motors``: motor-aware drive from the profile's motor constants."""
    p.add_argument("--compensate-motors", action="store_true",
                   help="motor-aware drive: pre-compensate each lit tactor's motor lag with the "
                   "profile's motor constants (overdrive while it spins up, off while it runs "
                   "down; the paper's pipeline has none)")  # fmt: skip


def motors_to_compensate(args, profile):
    """The profile's :class:`~tactile_core.rendering.motor.MotorResponse` when
    ``--compensate-motors`` is given (None otherwise); a profile without motor constants is a
    usage error, as the stage would change nothing."""
    if not getattr(args, "compensate_motors", False):
        return None
    if profile.motor is None:
        raise UsageError(f"--compensate-motors needs the motors' time constants: profile "
                         f"{profile.name} has none ('motor')")  # fmt: skip
    return profile.motor


def _scene(args):
    """Validate the shared scene arguments; ValueError names what is wrong. The shape is None
    for ``--shape tact:FILE`` and ``--shape pattern:FILE`` (loaded by the command)."""
    from_file = args.shape.startswith(("tact:", PATTERN_PREFIX))
    shape = None if from_file else _parse_shape_arg(args.shape)
    method = get_method(args.method).spec
    mu, gamma = check_correction(args.mu, args.gamma)
    if args.duration is None:  # a timed path plays at its own pace (its times are the point)
        own = isinstance(shape, TimedPath)
        args.duration = shape.duration_s if own else args.default_duration
    _validate.duration("duration", args.duration)
    for name in ("cols", "rows"):
        _validate.integer(name, getattr(args, name), 1, 64)
    grid = Grid(cols=args.cols, rows=args.rows)
    return shape, method, mu, gamma, grid


def _parse_shape_arg(text: str):
    """:func:`parse_shape`; a text that names no shape kind is told the command line's forms,
    ``tact:`` and ``pattern:`` included."""
    try:
        return parse_shape(text)
    except ValueError:
        kind = text.partition(":")[0].strip().lower() if ":" in text else None
        if kind in SHAPE_KINDS:  # a kind's own numbers were wrong: its message says which
            raise
        forms = f"{' | '.join(SHAPE_FORMS)} | {FILE_FORMS}"
        if kind is None:
            raise ValueError(
                f"shape must be one word such as circle:2.5,3,2, one of {forms}; "
                f"got {_validate.shown(text)}"
            ) from None
        raise ValueError(
            f"shape kind must be one of {', '.join(SHAPE_KINDS)}, tact, pattern ({forms}), "
            f"got {_validate.shown(kind)}"
        ) from None


def unknown_arguments_hint(args, extra) -> str:
    """What to add to argparse's "unrecognized arguments" for ``--shape`` written as words
    (``--shape circle 2.5 3 2``): the one-word spec meant, and every form."""
    shape = getattr(args, "shape", None)
    if not isinstance(shape, str) or ":" in shape or shape.strip().lower() not in SHAPE_KINDS:
        return ""
    numbers = [a for a in extra if _validate.DECIMAL.fullmatch(a)]
    meant = f"{shape}:{','.join(numbers)}" if numbers else f"{shape}:..."
    return (f" (a shape is one word: --shape {meant}; the forms: {' | '.join(SHAPE_FORMS)} | "
            f"{FILE_FORMS})")  # fmt: skip


def _seconds(value, name="seconds"):
    """``--seconds``: None (until stopped), or finite, > 0 and at most a week."""
    if value is None:
        return None
    value = _validate.real(name, value)
    if not 0 < value <= 7 * 86400:
        raise ValueError(
            f"{name} must be > 0 and at most a week (604800 s), got {_validate.shown(value)}"
        )
    return value


class StopRequest:
    """Set by a signal handler, read by the command's loop: a plain attribute, no lock.

    A ``threading.Event`` cannot be set from a handler. The handler runs in the main thread
    between two bytecodes, and that may be inside ``Event.wait`` while it holds the event's
    lock (re-taking it after a timeout): ``set()`` then waits for that lock forever, and the
    stream goes on playing. Beside a busy stream thread that happened in 2 of 300 Ctrl-C's.
    """

    POLL_S = 0.01
    """How often :meth:`wait` looks at the flag (a signal also cuts its sleep short), s."""

    def __init__(self) -> None:
        self._set = False

    def set(self) -> None:
        """Ask the command to stop (safe in a signal handler)."""
        self._set = True

    def is_set(self) -> bool:
        """True once asked to stop."""
        return self._set

    def wait(self, timeout_s: float) -> bool:
        """Sleep up to ``timeout_s`` seconds or until asked to stop; True if asked."""
        end = time.monotonic() + max(0.0, timeout_s)
        while not self._set:
            left = end - time.monotonic()
            if left <= 0:
                return False
            time.sleep(min(left, self.POLL_S))
        return True


def _install_stop_handlers(stop: StopRequest | None = None) -> StopRequest:
    """Ctrl-C, SIGTERM and SIGHUP (the terminal closed) set ``stop`` (a new
    :class:`StopRequest` if not given; never a ``threading.Event``, whose ``set()`` may
    deadlock in a handler) and return it: the caller then turns the array off and reports,
    quietly."""
    stop = StopRequest() if stop is None else stop

    def handler(signum, frame):
        stop.set()

    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), handler)
    return stop


class Ended(BaseException):
    """SIGTERM or SIGHUP ended a command that has no handler of its own: raised in the main
    thread so that ``finally`` clauses run (a half-written output's temporary file is removed,
    a stream turns the array off), as Ctrl-C's ``KeyboardInterrupt`` does."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


@contextlib.contextmanager
def ending_signals():
    """SIGTERM and SIGHUP raise :class:`Ended` while the block runs (main thread only); the
    handlers before it are put back afterwards. A command's own handlers
    (:func:`_install_stop_handlers`) replace these for the rest of the block."""

    def handler(signum, frame):
        raise Ended(signum)

    saved = {}
    if threading.current_thread() is threading.main_thread():
        for name in ("SIGTERM", "SIGHUP"):
            if hasattr(signal, name):
                signum = getattr(signal, name)
                saved[signum] = signal.signal(signum, handler)
    saved_int = signal.getsignal(signal.SIGINT) if saved else None
    try:
        yield
    finally:
        for signum, previous in saved.items():
            signal.signal(signum, previous)
        if saved_int is not None:  # a command's stop handler for Ctrl-C goes with the command
            signal.signal(signal.SIGINT, saved_int)


def write_failed(out, exc: OSError) -> OSError:
    """The error to raise when writing ``out`` fails during a run (a full disk): ``main``
    prints ``cannot write OUT: REASON`` and exits with 1, as for any operating-system error
    (the arguments were fine; status 2 is for those)."""
    return OSError(exc.errno, f"cannot write {out}: {exc.strerror or exc}")
