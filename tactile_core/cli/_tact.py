"""bHaptics ``.tact`` files on the command line: ``--shape tact:FILE`` for ``render`` and
``stream`` (the file as a pattern on the profile's array, with bHaptics' play-time options
``--tact-scale`` and ``--tact-rotate``), and ``tactile export-tact`` (``--compiled`` adds the
compiled frames)."""

from __future__ import annotations

import argparse

from .._shared import validate as _validate
from .._shared.outfile import check_output
from ..files.tact import (
    FORMS,
    MAX_NAME_CHARS,
    POSITIONS,
    TactError,
    load_pattern,
    path_of_scene,
    write_tact,
)
from ._common import UsageError, number, whole, write_failed
from ._pattern import export_pattern, is_pattern

PREFIX = "tact:"


def is_tact(shape_text) -> bool:
    """True for ``--shape tact:FILE``."""
    return isinstance(shape_text, str) and shape_text.startswith(PREFIX)


def add_tact_option(p: argparse.ArgumentParser) -> None:
    """``--tact-position``, ``--tact-scale``, ``--tact-rotate`` and ``--tact-form`` of
    ``render`` and ``stream``."""
    p.add_argument("--tact-position", default=None, metavar="NAME",
                   help="with --shape tact:FILE, one device position to play over the whole "
                   "array (VestFront, ...; default: every position on the profile's group for "
                   "it, front/back/left/right, or the first with content)")  # fmt: skip
    p.add_argument("--tact-scale", default=None, metavar="INTENSITY,DURATION",
                   help="bHaptics' ScaleOption: multiply the file's intensities and times "
                   "(0.5,2 = half as strong, half as fast)")  # fmt: skip
    p.add_argument("--tact-rotate", default=None, metavar="ANGLE,OFFSET",
                   help="bHaptics' RotationOption for the vest: degrees round the body (90 = "
                   "a quarter turn to the wearer's left) and panel heights up")  # fmt: skip
    p.add_argument("--tact-form", choices=FORMS, default=None,
                   help="play the Designer project or bHaptics' compiled frames (default: the "
                   "project, or the frames of a file without one)")  # fmt: skip


def _pair(option: str, text):
    """``A,B`` as two numbers, or None; a usage error names the option."""
    if text is None:
        return None
    parts = str(text).split(",")
    try:
        if len(parts) != 2:
            raise ValueError
        return tuple(float(part) for part in parts)
    except ValueError:
        raise UsageError(f"{option} takes two numbers A,B, got {text!r}") from None


def load_tact_arg(args):
    """The pattern of ``--shape tact:FILE`` (None for another shape); a bad file is a usage
    error naming the field."""
    if not is_tact(args.shape):
        return None
    path = args.shape[len(PREFIX) :]
    if not path:
        raise UsageError("--shape tact: needs a file, as in tact:pattern.tact")
    if getattr(args, "direction", "forward") != "forward":
        raise UsageError("--direction reverse does not apply to a .tact file (it plays as written)")
    scale = _pair("--tact-scale", getattr(args, "tact_scale", None))
    rotation = _pair("--tact-rotate", getattr(args, "tact_rotate", None))
    try:
        pattern = load_pattern(path, getattr(args, "tact_position", None), scale=scale,
                               rotation=rotation,
                               form=getattr(args, "tact_form", None))  # fmt: skip
    except TactError as exc:  # an empty file too: the library refuses it
        raise UsageError(str(exc)) from None
    except ValueError as exc:  # a scale or rotation out of range
        option = "--tact-scale" if str(exc).startswith(("intensity", "duration", "scale")) else (
            "--tact-rotate")  # fmt: skip
        raise UsageError(f"{option}: {exc}") from None
    return pattern


def warn_of_notes(command: str, pattern) -> None:
    """Each of the pattern's notes (what does not play as the file asks) as a warning on
    standard error."""
    import sys

    for note in pattern.notes:
        print(f"tactile {command}: warning: {note}", file=sys.stderr, flush=True)


def not_played(pattern, target) -> str:
    """``"; not played: VestBack, ..."``: the positions of the file left out on ``target``
    ("" if none)."""
    skipped = pattern.skipped_on(target)
    return f"; not played: {', '.join(skipped)}" if skipped else ""


def add_export_parser(sub) -> None:
    """The ``export-tact`` sub-command."""
    p = sub.add_parser("export-tact", help="write a shape's trace or a preset's as a bHaptics "
                       ".tact file")  # fmt: skip
    source = p.add_mutually_exclusive_group(required=True)
    source.add_argument("--shape", metavar="SHAPE",
                        help="line:..., circle:..., timed:..., pattern:FILE.json")  # fmt: skip
    source.add_argument("--preset", metavar="FILE", help="a preset (its shape and timing)")
    p.add_argument(
        "--duration",
        type=number,
        default=None,
        help="seconds per trace (default 2; a preset's; a timed path's own)",
    )
    p.add_argument("--direction", choices=("forward", "reverse"), default=None)
    p.add_argument("--profile", default=None,
                   help="the array the shape is drawn on (default: the preset's, else the palm "
                   "array); its actuators span 0..1 in the file")  # fmt: skip
    p.add_argument("--cols", type=whole, default=None, help="a grid instead of a profile")
    p.add_argument("--rows", type=whole, default=None)
    p.add_argument("--position", choices=tuple(POSITIONS), default="VestFront",
                   help="the bHaptics device position (default VestFront)")  # fmt: skip
    p.add_argument("--group", action="append", metavar="GROUP=POSITION",
                   help="with --shape pattern:FILE, write the effects of a layout group to this "
                   "device position, in 0..1 of the group's actuators (front=VestFront); "
                   "repeat for each group")  # fmt: skip
    p.add_argument("--name", default=None, help="the project's name (default: the file's stem)")
    p.add_argument("--compiled", action="store_true",
                   help="also write bHaptics' compiled form: the trace's motor values every 20 "
                   "ms, rendered by --method (the file then carries both forms)")  # fmt: skip
    p.add_argument("--method", default=None,
                   help="with --compiled, the rendering method (default: the preset's, else "
                   "the array's default)")  # fmt: skip
    p.add_argument("--out", required=True, help="output file, .tact")
    p.set_defaults(func=cmd_export_tact)


def cmd_export_tact(args) -> int:
    """Write a scene's trace as a ``.tact`` file with one ``PATH_MODE`` effect."""
    from ..device.profile import ProfileError, find_profile, load_profile
    from ..files.presets import PresetError, load_preset
    from ..rendering.geometry import Grid
    from ..rendering.scene import Scene
    from ..rendering.shapes import TimedPath, parse_shape

    out = check_output(args.out, (".tact",), "--out")
    profile_name = args.profile
    if args.preset is not None:
        try:
            preset = load_preset(args.preset)
        except PresetError as exc:
            raise UsageError(str(exc)) from None
        scene = preset.scene
        if profile_name is None and args.cols is None:
            try:
                target = find_profile(preset.device_profile).layout
            except ProfileError as exc:
                raise UsageError(f"{exc} (name the array with --profile)") from None
    elif is_pattern(args.shape):
        scene = None  # its effects, written by export_pattern
        for option in ("duration", "direction"):
            if getattr(args, option) is not None:
                raise UsageError(f"--{option} does not apply to a pattern (its effects keep "
                                 "theirs)")  # fmt: skip
    else:
        shape = parse_shape(args.shape)
        duration = shape.duration_s if isinstance(shape, TimedPath) else 2.0
        scene = Scene(shape, duration_s=duration)
    changes = {}
    if args.duration is not None:
        changes["duration_s"] = _validate.duration("duration", args.duration)
        if isinstance(scene.shape, TimedPath):
            raise UsageError("--duration does not apply to a timed path (it keeps its times)")
    if args.direction is not None:
        changes["direction"] = args.direction
    scene = scene.replace(**changes) if scene is not None else None
    if args.cols is not None or args.rows is not None:
        if profile_name is not None:
            raise UsageError("--profile and --cols/--rows name the array twice: give one")
        cols = 5 if args.cols is None else args.cols
        rows = 6 if args.rows is None else args.rows
        for name, value in (("cols", cols), ("rows", rows)):
            _validate.integer(name, value, 1, 64)
        target = Grid(cols, rows)
    elif profile_name is not None or args.preset is None:
        try:
            target = load_profile(profile_name).layout
        except ProfileError as exc:
            raise UsageError(str(exc)) from None
    name = args.name if args.name is not None else out.stem[:MAX_NAME_CHARS]
    if is_pattern(args.shape):
        return export_pattern(args, out, target, name)
    if args.group:
        raise UsageError("--group applies to --shape pattern:FILE only")
    path = path_of_scene(scene)
    compiled, frames = None, ""
    if args.compiled:
        compiled = _compiled_method(args, scene, target)
        frames = f" and its frames by {compiled} every 20 ms (compiled form)"
    elif args.method is not None:
        raise UsageError("--method applies with --compiled (the frames it renders)")
    try:
        write_tact(out, path, target, name=name, position=args.position, compiled=compiled)
    except OSError as exc:
        raise write_failed(out, exc) from None
    print(f"wrote {len(path.points)} points over {path.duration_s:g} s ({path.pattern}){frames} "
          f"to {out}")  # fmt: skip
    return 0


def _compiled_method(args, scene, target) -> str:
    """The method ``--compiled`` renders the frames by, checked on ``target``."""
    from ..rendering.methods import get_method
    from ..rendering.placement import default_method
    from ..rendering.rasterize import check_renders

    name = args.method if args.method is not None else (
        scene.method if args.preset is not None else default_method(target))  # fmt: skip
    try:
        method = get_method(name)
        check_renders(method, target)
    except ValueError as exc:
        raise UsageError(f"--method: {exc}") from None
    return method.spec
