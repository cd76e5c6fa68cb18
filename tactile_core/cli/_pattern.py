"""Patterns on the command line: ``--shape pattern:FILE`` for ``render``, ``stream`` and
``export-tact`` (a :class:`~tactile_core.files.pattern.Pattern` file played on the profile's
array)."""

from __future__ import annotations

import sys

from ..files.pattern import Pattern, PatternError, profiles_playing
from ._common import PATTERN_PREFIX, UsageError

PREFIX = PATTERN_PREFIX


def is_pattern(shape_text) -> bool:
    """True for ``--shape pattern:FILE``."""
    return isinstance(shape_text, str) and shape_text.startswith(PREFIX)


def pattern_path(args) -> str:
    """The FILE of ``--shape pattern:FILE``."""
    return args.shape[len(PREFIX) :]


def load_pattern_arg(args, target, method: str | None = None):
    """The pattern of ``--shape pattern:FILE`` checked for ``target`` (a Grid or Layout) and
    the scene's ``method`` (None for another shape); a bad file, a group the layout lacks or
    an empty pattern is a usage error naming the field."""
    if not is_pattern(args.shape):
        return None
    path = pattern_path(args)
    if not path:
        raise UsageError("--shape pattern: needs a file, as in pattern:letter.json")
    if getattr(args, "direction", None) not in (None, "forward"):
        raise UsageError("--direction reverse does not apply to a pattern (it plays as written)")
    try:
        pattern = Pattern.load(path)
        if not pattern.effects:
            raise UsageError(f"{path}: the pattern has no effects to play")
        pattern.check(target, method)
    except PatternError as exc:
        raise UsageError(str(exc)) from None
    except ValueError as exc:  # what does not play on this array, by field
        raise UsageError(f"{path}: {exc}{_plays_on(pattern, args)}") from None
    return pattern


def _plays_on(pattern, args) -> str:
    """Where a refused pattern plays, as the option to give: ``. It plays on the device
    profile vest-front-back: --profile vest-front-back`` (nothing if on none)."""
    names = [name for name in profiles_playing(pattern) if name != getattr(args, "profile", None)]
    if not names:
        return ""
    return f". It plays on the device profile {' or '.join(names)}: --profile {names[0]}"


def describe(args, pattern) -> str:
    """``pattern 'A' of FILE (3 effects, 2.1 s)``: what a command says it played."""
    name = f" {pattern.name!r}" if pattern.name else ""
    n = len(pattern.effects)
    return (f"pattern{name} of {pattern_path(args)} ({n} effect{'s' if n != 1 else ''}, "
            f"{pattern.duration_s:g} s)")  # fmt: skip


def say_playing(args, pattern) -> None:
    """``playing pattern ...`` on standard error, as ``tactile stream`` says what it plays."""
    print(f"playing {describe(args, pattern)}", file=sys.stderr, flush=True)


def parse_group_positions(items) -> dict:
    """``--group front=VestFront`` (repeated) as ``{"front": "VestFront"}``; a usage error
    for an item without ``=``."""
    out = {}
    for item in items or ():
        group, sep, position = item.partition("=")
        if not sep or not group or not position:
            raise UsageError(f"--group must be GROUP=POSITION, as in front=VestFront, got "
                             f"{item!r}")  # fmt: skip
        out[group] = position
    return out


def export_pattern(args, out, target, name: str) -> int:
    """``tactile export-tact --shape pattern:FILE``: the pattern's effects as a ``.tact``
    file (paths and dots per effect) on ``target``."""
    from ..rendering.placement import default_method
    from ._common import write_failed

    compiled = None
    if getattr(args, "compiled", False):
        compiled = args.method if args.method is not None else default_method(target)
    elif getattr(args, "method", None) is not None:
        raise UsageError("--method applies with --compiled (the frames it renders)")
    pattern = load_pattern_arg(args, target, compiled)
    try:
        written = pattern.save_tact(out, target, name=name, position=args.position,
                                    positions=parse_group_positions(args.group),
                                    compiled=compiled)  # fmt: skip
    except OSError as exc:
        raise write_failed(out, exc) from None
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    frames = f" and its frames by {compiled} every 20 ms (compiled form)" if compiled else ""
    print(f"wrote {describe(args, pattern)}{frames} to {written}")
    return 0
