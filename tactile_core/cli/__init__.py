"""The ``tactile`` command: render, stream, emulate, analyze, simulate, tune-correction, bench,
measure.

Errors in arguments or files print ``tactile <command>: error: <what was wrong>`` on standard
error and exit with status 2; no traceback for anything the user can fix.

Inside: ``_parser`` builds the parser, ``_render`` holds render, stream and emulate,
``_experiments`` analyze, simulate, tune-correction and bench, ``_measure`` measure,
``_common`` what they share;
:func:`main` runs one. ``python -m tactile_core.cli`` runs it too (``__main__``).
"""

from __future__ import annotations

import signal
import sys

from .._shared.threads import one_blas_thread
from ._common import Ended, UsageError, ending_signals, unknown_arguments_hint

# ``_name as _name``: helpers of the module before the split, still importable from here.
from ._experiments import cmd_analyze, cmd_bench, cmd_simulate, cmd_tune_correction
from ._parser import build_parser
from ._render import MAX_RENDER_FRAMES, cmd_emulate, cmd_render, cmd_stream

__all__ = [
    "MAX_RENDER_FRAMES",
    "UsageError",
    "build_parser",
    "cmd_analyze",
    "cmd_bench",
    "cmd_emulate",
    "cmd_render",
    "cmd_simulate",
    "cmd_stream",
    "cmd_tune_correction",
    "main",
]


def main(argv=None) -> int:
    """Entry point of the ``tactile`` console script."""
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # the command's usage, not the top level's, and a hint where one helps
        hint = unknown_arguments_hint(args, extra)
        parser.commands[args.command].error(f"unrecognized arguments: {' '.join(extra)}{hint}")
    try:
        with one_blas_thread(), ending_signals():  # small fits: extra BLAS threads only wait
            return args.func(args)
    except Ended as exc:  # SIGTERM or SIGHUP: cleaned up on the way here, like Ctrl-C
        name = signal.Signals(exc.signum).name
        print(f"tactile {args.command}: ended by {name}", file=sys.stderr)
        return 128 + exc.signum
    except (ValueError, UsageError) as exc:
        print(f"tactile {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # a disk that fills up, a folder that vanished mid-run
        where = f" {exc.filename}" if getattr(exc, "filename", None) else ""
        print(f"tactile {args.command}: error:{where} {exc.strerror or exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"tactile {args.command}: interrupted", file=sys.stderr)
        return 130
