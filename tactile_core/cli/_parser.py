"""The argument parser of ``tactile``: one sub-command per ``cmd_*`` function."""

from __future__ import annotations

import argparse

from .._version import __version__
from ..stream import DEFAULT_LEAD_MS
from ._common import (
    DEVICE_HELP,
    _add_scene_arguments,
    add_compensate_motors,
    number,
    profile_help,
    whole,
)
from ._experiments import cmd_analyze, cmd_bench, cmd_simulate, cmd_tune_correction
from ._measure import add_measure_parser
from ._render import cmd_emulate, cmd_render, cmd_stream
from ._serve import add_lsl_arguments, add_serve_parser
from ._tact import add_export_parser, add_tact_option


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``tactile``."""
    parser = argparse.ArgumentParser(
        prog="tactile",
        description="Rendering methods for low-resolution 2D vibrotactile arrays (CT, MM, AS, IM).",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    parser.commands = sub.choices  # {name: its parser}, for main's usage errors

    p = sub.add_parser(
        "render", help="write the frames of one trace to .csv or .npz, or its signal to .wav"
    )
    _add_scene_arguments(p, duration=2.0)
    p.set_defaults(cols=None, rows=None)  # None: 5 x 6, or the profile's grid
    p.add_argument("--rate", type=number, default=100.0, help="frames per second (default 100)")
    p.add_argument("--out", required=True, help="output file, .csv, .npz or .wav")
    p.add_argument("--profile", default=None,
                   help=profile_help(" (its grid or layout, and for .wav its channels, levels, "
                                     "calibration, carriers and waveforms)"))  # fmt: skip
    p.add_argument("--samplerate", type=whole, default=None,
                   help=".wav: samples per second, 8000-384000 (default 48000)")  # fmt: skip
    p.add_argument("--carrier-hz", type=number, default=None,
                   help=".wav: one carrier for every channel, 1-1000 Hz (default: the profile's, "
                   "else 250)")  # fmt: skip
    p.add_argument("--ramp-ms", type=number, default=None,
                   help=".wav: the raised-cosine ramp between levels, 0-20 ms "
                   "(default 1.5)")  # fmt: skip
    p.add_argument("--waveform", default=None, metavar="SPEC",
                   help=".wav: one waveform for every channel, e.g. square:200, noise, "
                   "sweep:100-300:500ms, sine+adsr:5,20,0.7,50 (default: the profile's, else "
                   "the plain carrier)")  # fmt: skip
    add_compensate_motors(p)
    add_tact_option(p)
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("stream", help="stream a scene to a device without the GUI")
    p.add_argument(
        "--device",
        required=True,
        metavar="URL",
        help=DEVICE_HELP,
    )
    _add_scene_arguments(p, duration=2.0)
    p.add_argument(
        "--pause", type=number, default=0.5, help="seconds off between traces (default 0.5)"
    )
    p.add_argument("--rate", type=number, default=300.0, help="frames per second (default 300)")
    p.add_argument(
        "--seconds", type=number, default=None, help="stop after this long (default: Ctrl-C)"
    )
    p.add_argument("--profile", default=None, help=profile_help())
    p.add_argument(
        "--filter",
        choices=("point", "box"),
        default="point",
        help="temporal filter (default point: the paper's pipeline)",
    )
    p.add_argument("--subsamples", type=whole, default=4, help="box filter sub-samples (default 4)")
    dither = p.add_mutually_exclusive_group()
    dither.add_argument(
        "--dither", action="store_true", help="temporal dithering of the device levels"
    )
    dither.add_argument(
        "--no-dither", action="store_true", help="plain rounding to device levels (the default)"
    )
    p.add_argument("--felt-amplitude", action="store_true",
                   help="mu and gamma act on felt amplitude: send the drive that the profile's "
                   "motor response curve turns into the corrected value")  # fmt: skip
    add_compensate_motors(p)
    p.add_argument("--record", default=None, help="record the frames sent to .csv or .npz")
    p.add_argument("--reconnect", action="store_true", help="keep retrying after the link fails")
    p.add_argument(
        "--realtime", action="store_true", help="real-time priority (Linux; rtprio or root)"
    )
    p.add_argument(
        "--lead-ms",
        type=number,
        default=DEFAULT_LEAD_MS,
        help="send frames this far ahead, to be played at their time by the array's clock "
        f"(arrays with scheduled frames; 0: played on arrival; default {DEFAULT_LEAD_MS:g})",
    )
    add_tact_option(p)
    add_lsl_arguments(p)
    p.set_defaults(func=cmd_stream)
    add_serve_parser(sub)

    add_export_parser(sub)

    p = sub.add_parser(
        "emulate", help="run the device emulator on a pseudo-terminal (or a local TCP port)"
    )
    p.add_argument("--profile", default=None, help=profile_help())
    p.add_argument("--rate", type=number, default=None, help="nominal rate for the interval error")
    p.add_argument(
        "--seconds", type=number, default=None, help="end after this long (default: Ctrl-C)"
    )
    p.add_argument("--log", default=None, help="write every received frame to this CSV")
    p.add_argument(
        "--keep-frames",
        type=whole,
        default=None,
        help="frames kept for --log and the statistics, the latest (default 1080000: an hour "
        "at 300 Hz, ~42 MB)",
    )
    p.add_argument(
        "--plain",
        action="store_true",
        help="a format 2 array without scheduled frames (timed frames are dropped as unknown)",
    )
    p.add_argument("--json", default=None, help="write the report to this JSON file")
    p.add_argument(
        "--realtime",
        action="store_true",
        help="receive at real-time priority (Linux; rtprio or root), as an array's own "
        "processor would: what it logs is then the host's timing, not its own waits",
    )
    p.add_argument(
        "--socket",
        action="store_true",
        help="listen on a local TCP port instead of a pseudo-terminal; the first line is then "
        "its socket:// URL (loopback delivers in the writer's context, with no kernel worker "
        "between)",
    )
    p.add_argument(
        "--close-after",
        type=number,
        default=None,
        help="close the device this long after the first frame arrives (fault test: a device "
        "that goes away mid-stream)",
    )
    p.set_defaults(func=cmd_emulate)

    p = sub.add_parser("analyze", help="the paper's tables and figures from a results folder")
    p.add_argument("results", metavar="RESULTS_DIR")
    p.add_argument(
        "--paper-rounding",
        action="store_true",
        help="round each p to 3 decimals before x 6, as the paper's tables did",
    )
    p.set_defaults(func=cmd_analyze)

    p = sub.add_parser("simulate", help="run the experiments with simulated participants")
    p.add_argument("results", metavar="RESULTS_DIR")
    p.add_argument("--participants", type=whole, default=12)
    p.add_argument("--seed", type=whole, default=1)
    p.add_argument(
        "--experiments", default="exp1,exp2,exp3", help="comma-separated (and calibration)"
    )
    p.add_argument("--methods", metavar="'M M ...'", default=None,
                   help="the method set of Experiments 1 and 3, e.g. 'AS EN RO:r=1.5' "
                   "(default: the paper's four)")  # fmt: skip
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser(
        "tune-correction",
        help="measure mu and gamma by feel (a participant at an array, or simulated)",
        description="Two-interval forced choices find the drive one tactor is just felt at "
        "(mu) and the gamma at which a point between tactors feels as strong as one on a "
        "tactor. --simulate runs it against the simulated participant of the contract.",
    )
    p.add_argument("--simulate", action="store_true", help="the simulated participant")
    p.add_argument("--threshold", type=number, default=None, help="simulated TH in [0, 0.95]")
    p.add_argument("--exponent", type=number, default=None, help="simulated K in [0.1, 10]")
    p.add_argument("--threshold-sd", type=number, default=0.02,
                   help="simulated threshold spread, drive units (default 0.02)")  # fmt: skip
    p.add_argument("--weber", type=number, default=0.15,
                   help="simulated magnitude noise, log units (default 0.15)")  # fmt: skip
    p.add_argument("--lapse", type=number, default=0.03,
                   help="simulated lapse rate (default 0.03)")  # fmt: skip
    p.add_argument("--seed", type=whole, default=0, help="seeds the procedure (and simulation)")
    p.add_argument("--device", metavar="URL", default=None, help="port or URL; 'sim' for the "
                   "simulated array")  # fmt: skip
    p.add_argument("--participant", metavar="ID", default=None)
    p.add_argument("--results", metavar="DIR", default=None, help="results folder")
    p.add_argument("--profile", default=None, help=profile_help())
    p.add_argument("--trials-per-tactor", type=whole, default=20, help="threshold trials per "
                   "tactor, 5 tactors (default 20)")  # fmt: skip
    p.add_argument("--trials-per-place", type=whole, default=40,
                   help="constancy trials at each of 2 places (default 40)")  # fmt: skip
    p.add_argument("--corner-trials", type=whole, default=12,
                   help="constancy trials at the cell corner, the check (default 12)")  # fmt: skip
    p.add_argument("--threshold-procedure", choices=("staircase", "quest+"),
                   default="staircase", help="how threshold levels are placed: a 3-down/1-up "
                   "track (default) or QUEST+")  # fmt: skip
    p.add_argument("--interval-ms", type=number, default=500.0,
                   help="at the array: how long each interval plays, and the silence between "
                   "the two (default 500, 20 to 5000)")  # fmt: skip
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=cmd_tune_correction)

    p = sub.add_parser("bench", help="print the speed/accuracy tables")
    p.add_argument(
        "--part",
        choices=(
            "core",
            "methods",
            "motor",
            "trade",
            "device",
            "link",
            "gui",
            "experiments",
            "tuning",
            "all",
        ),
        default="all",
    )
    p.add_argument("--quick", action="store_true", help="smaller sizes, coarser reference")
    p.add_argument("--profile", default=None,
                   help=profile_help(" of --part trade: its motors, levels and link, and the "
                                     "setting recommended for it"))  # fmt: skip
    p.set_defaults(func=cmd_bench)

    add_measure_parser(sub)
    return parser
