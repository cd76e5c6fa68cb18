"""The ``tactile`` command: render, bench (and, as they land, stream, emulate, analyze).

Errors in arguments or files print ``tactile <command>: error: <what was wrong>`` on standard
error and exit with status 2; no traceback for anything the user can fix.
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
import time

import numpy as np

from ._shared import validate as _validate
from ._shared.outfile import atomic_file, check_folder, check_output
from ._version import __version__
from .rendering.correction import check_correction, correct
from .rendering.geometry import Grid
from .rendering.methods import METHOD_NAMES, PEER_METHODS, get_method
from .rendering.rasterize import render
from .rendering.shapes import parse_shape
from .rendering.trace import DIRECTIONS


class UsageError(Exception):
    """A problem with the command line or its files, reported without a traceback."""


def _add_scene_arguments(p: argparse.ArgumentParser, *, duration: float) -> None:
    p.add_argument(
        "--shape",
        required=True,
        metavar="SHAPE",
        help="line:X0,Y0,X1,Y1 | circle:CX,CY,R | square:CX,CY,EDGE (grid units)",
    )
    paper, peers = ", ".join(METHOD_NAMES), ", ".join(PEER_METHODS)
    p.add_argument("--method", required=True, metavar="M",
                   help=f"the paper's {paper}, the peers {peers} or a plug-in; parameters as "
                   "RO:r=1.5 or GS:sigma=0.7")  # fmt: skip
    p.add_argument("--mu", type=float, default=0.0, help="threshold in [0, 1] (default 0)")
    p.add_argument("--gamma", type=float, default=1.0, help="gamma > 0 (default 1)")
    p.add_argument(
        "--duration", type=float, default=duration, help=f"seconds per trace (default {duration:g})"
    )
    p.add_argument("--direction", choices=DIRECTIONS, default="forward")
    p.add_argument("--cols", type=int, default=5, help="grid columns (default 5)")
    p.add_argument("--rows", type=int, default=6, help="grid rows (default 6)")


def _scene(args):
    """Validate the shared scene arguments; ValueError names what is wrong."""
    shape = parse_shape(args.shape)
    method = get_method(args.method).spec
    mu, gamma = check_correction(args.mu, args.gamma)
    _validate.duration("duration", args.duration)
    for name in ("cols", "rows"):
        _validate.integer(name, getattr(args, name), 1, 64)
    grid = Grid(cols=args.cols, rows=args.rows)
    return shape, method, mu, gamma, grid


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


MAX_RENDER_FRAMES = 1_000_000
"""Most frames ``tactile render`` writes (duration x rate + 1): 240 MB of floats."""


def cmd_render(args) -> int:
    """Write the frames of one trace to CSV or NPZ."""
    shape, method, mu, gamma, grid = _scene(args)
    _validate.rate("rate", args.rate, 1e-3, _validate.MAX_RATE_HZ)
    out = check_output(args.out, (".csv", ".npz"), "--out")
    n = int(np.floor(args.duration * args.rate + 1e-9))
    if n + 1 > MAX_RENDER_FRAMES:
        raise ValueError(
            f"duration x rate must give at most {MAX_RENDER_FRAMES} frames, got {n + 1} "
            f"({args.duration:g} s at {args.rate:g} Hz)"
        )
    time_s = np.arange(n + 1) / args.rate
    u = np.minimum(time_s / args.duration, 1.0)
    t = 1.0 - u if args.direction == "reverse" else u
    frames = correct(render(shape, method, t, grid=grid), mu, gamma)
    try:
        if out.suffix.lower() == ".npz":
            with atomic_file(out, binary=True) as f:
                np.savez(f, time=time_s, frames=frames)
        else:
            names = [grid.cell_name(i) for i in range(grid.size)]
            table = np.column_stack([time_s, frames.reshape(len(t), grid.size)])
            with atomic_file(out) as f:
                np.savetxt(
                    f,
                    table,
                    delimiter=",",
                    header=",".join(["time", *names]),
                    comments="",
                    fmt="%.10g",
                )
    except OSError as exc:
        raise UsageError(f"cannot write {out}: {exc.strerror or exc}") from None
    print(f"wrote {len(t)} frames of {shape.spec} ({method}, mu={mu:g}, gamma={gamma:g}) to {out}")
    return 0


def _install_stop_handlers(stop: threading.Event) -> None:
    """Ctrl-C, SIGTERM and SIGHUP (the terminal closed) set ``stop``: the caller then turns the
    array off and reports, quietly."""

    def handler(signum, frame):
        stop.set()

    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), handler)


def cmd_stream(args) -> int:
    """Stream a scene to a device without the GUI; print statistics at the end."""
    from .device.link import LinkError, open_link
    from .device.profile import ProfileError, load_profile
    from .device.recorder import Recorder
    from .device.streamer import Streamer
    from .rendering.scene import Scene

    shape, method, mu, gamma, _ = _scene(args)
    try:
        profile = load_profile(args.profile)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    scene = Scene(
        shape,
        method,
        mu,
        gamma,
        duration_s=args.duration,
        pause_s=args.pause,
        direction=args.direction,
        rate_hz=args.rate,
        filter=args.filter,
        subsamples=args.subsamples,
        dither=args.dither,
        felt_domain=args.felt_amplitude,
    )
    if args.felt_amplitude and profile.response is None:
        raise UsageError(f"--felt-amplitude needs a motor response curve: profile "
                         f"{profile.name} has none ('response')")  # fmt: skip
    args.seconds = _seconds(args.seconds)
    if args.record:
        check_output(args.record, (".csv", ".npz"), "--record")
    stop = threading.Event()
    _install_stop_handlers(stop)
    try:
        link = open_link(args.device, profile)
    except LinkError as exc:
        print(f"tactile stream: {exc}", file=sys.stderr)
        return 1
    recorder = Recorder(profile.array) if args.record else None
    streamer = Streamer(
        link,
        profile,
        scene=scene,
        taps=[] if recorder is None else [recorder],
        reconnect=args.reconnect,
        realtime=args.realtime,
        on_status=lambda stats: print(
            f"[{stats.state}] {stats.status}", file=sys.stderr, flush=True
        ),
    )
    try:
        streamer.start()
        while not stop.is_set() and not streamer.identified.wait(0.05):
            pass  # --seconds counts from the end of the hello exchange
        deadline = None if args.seconds is None else time.monotonic() + args.seconds
        while not stop.is_set() and streamer.running:
            remaining = None if deadline is None else deadline - time.monotonic()
            if remaining is not None and remaining <= 0:
                break
            stop.wait(0.1 if remaining is None else min(0.1, remaining))
    finally:
        stats = streamer.stop()
        link.close()
    print(stats.summary())
    if recorder is not None:
        path = recorder.save(args.record)
        print(f"recorded {len(recorder)} frames to {path}")
    if stats.state == "failed":
        print(f"tactile stream: {stats.status}", file=sys.stderr)
        print(streamer.failure_traceback, file=sys.stderr, end="")
        return 70  # EX_SOFTWARE: a bug, reported; the array was turned off
    if stats.state == "refused":
        print(f"tactile stream: {stats.status}", file=sys.stderr)
        return 1
    return 0 if stats.errors == 0 else 1


def cmd_emulate(args) -> int:
    """Run the device emulator on a pseudo-terminal until stopped."""
    from .device.emulator import Emulator
    from .device.profile import ProfileError, load_profile

    try:
        profile = load_profile(args.profile)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    args.seconds = _seconds(args.seconds)
    args.close_after = _seconds(args.close_after, "close-after")
    if args.rate is not None:
        _validate.rate("rate", args.rate, 1e-3, _validate.MAX_RATE_HZ)
    for option, value in (("--log", args.log), ("--json", args.json)):
        if value:
            check_output(value, (), option)
    stop = threading.Event()
    _install_stop_handlers(stop)
    emulator = Emulator(profile, expected_rate_hz=args.rate)
    path = emulator.open()
    print(path, flush=True)
    print(
        f"emulating {profile.name} ({profile.grid.cols} x {profile.grid.rows}, "
        f"{profile.levels} levels) on {path}; Ctrl-C to end",
        file=sys.stderr,
        flush=True,
    )
    try:
        emulator.run(stop.is_set, seconds=args.seconds, close_after=args.close_after)
    finally:
        emulator.close()
        if args.log:
            emulator.save_log(args.log)
        if args.json:
            emulator.save_report(args.json)
        print(emulator.summary(), flush=True)
    return 0


def cmd_analyze(args) -> int:
    """Print the paper's tables and write its figures from a results folder."""
    from .experiments.analysis import analyze

    analyze(args.results, paper_rounding=args.paper_rounding)
    return 0


def cmd_simulate(args) -> int:
    """Run every experiment with simulated participants into a results folder."""
    from .experiments import RUNNERS, SimulatedParticipant, open_session

    _validate.integer("participants", args.participants, 1, 1000)
    _validate.integer("seed", args.seed, 0, 2**31 - 1)
    check_folder(args.results, "RESULTS_DIR")
    experiments = args.experiments.split(",")
    unknown = set(experiments) - set(RUNNERS)
    if unknown:
        raise ValueError(f"experiments must be among {', '.join(RUNNERS)}, got {sorted(unknown)}")
    methods = None if args.methods is None else args.methods.split()
    for i in range(args.participants):
        session = open_session(args.results, f"sim{i + 1:02d}", index=i, seed=args.seed)
        participant = SimulatedParticipant(seed=args.seed * 1000 + i)
        for name in experiments:
            extra = {"methods": methods} if name in ("exp1", "exp3") else {}
            runner = RUNNERS[name](session, **extra)
            try:
                participant.run(runner)
            finally:
                runner.close()
    print(
        f"simulated {args.participants} participant(s) ({', '.join(experiments)}) in {args.results}"
    )
    return 0


def _tuning_plan(args):
    from .experiments.tuning import TuningPlan

    return TuningPlan(args.trials_per_tactor, args.trials_per_place, args.corner_trials)


def _print_tuning(result, args, extra: dict) -> int:
    import json

    if args.json:
        print(json.dumps({**result.to_dict(), **extra}, indent=2))
    else:
        print(result.summary())
    if not result.ok:
        print(f"tactile tune-correction: no correction: {result.message}", file=sys.stderr)
        return 1
    return 0


def cmd_tune_correction(args) -> int:
    """Measure mu and gamma by feel: against the simulated participant, or a person at an
    array (keys typed in the terminal)."""
    from .experiments.tuning import simulate_tuning

    plan = _tuning_plan(args)
    seed = _validate.integer("seed", args.seed, 0, 2**31 - 1)
    if args.simulate:
        if args.device is not None:
            raise UsageError("--simulate and --device exclude each other")
        if args.threshold is None or args.exponent is None:
            raise UsageError("--simulate needs --threshold TH and --exponent K")
        result = simulate_tuning(
            args.threshold, args.exponent, seed=seed, plan=plan, threshold_sd=args.threshold_sd,
            weber=args.weber, lapse=args.lapse,
        )  # fmt: skip
        expected = {"mu": args.threshold, "gamma": 1.0 / (2.0 * args.exponent)}
        return _print_tuning(result, args, {"simulated": True, "expected": expected,
                                            "seed": seed})  # fmt: skip
    if args.device is None or args.participant is None or args.results is None:
        raise UsageError("a session needs --device URL --participant ID --results DIR "
                         "(or --simulate)")  # fmt: skip
    return _tune_at_array(args, plan, seed)


def _tune_at_array(args, plan, seed) -> int:
    """The procedure at a real array: trials played by the streamer, answers typed."""
    from .device.link import LinkError, open_link
    from .device.profile import ProfileError, load_profile
    from .device.streamer import Streamer
    from .experiments.results import check_participant, open_session
    from .experiments.runners import INTERVAL_GAP_S, INTERVAL_S
    from .experiments.tuning import CorrectionTuning, save_correction

    pid = check_participant(args.participant)
    check_folder(args.results, "--results")
    try:
        profile = load_profile(args.profile)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    session = open_session(args.results, pid, seed=seed, device_profile=profile.name)
    runner = CorrectionTuning(session, plan, profile=profile)
    stop = threading.Event()
    _install_stop_handlers(stop)
    try:
        link = open_link(args.device, profile)
    except LinkError as exc:
        runner.close()
        print(f"tactile tune-correction: {exc}", file=sys.stderr)
        return 1
    streamer = Streamer(link, profile, scene=None)
    streamer.start()

    def play(scene, seconds):
        streamer.set_scene(scene)
        stop.wait(seconds)
        streamer.all_off()

    try:
        if runner.recovered:
            print(f"resumed after a crash: {runner.recovered}", file=sys.stderr)
        print(f"{runner.done} of {runner.total} answered so far; q then Enter stops (resume "
              "later with the same command)", file=sys.stderr)  # fmt: skip
        while not runner.finished and not stop.is_set():
            trial = runner.current
            done, total = runner.progress()
            if trial.kind == "continue":
                answer = input(f"[{done + 1}/{total}] {trial.prompt} (Enter) ")
                if answer.strip().lower() == "q":
                    break
                runner.answer("continue")
                continue
            while not stop.is_set():
                for k, scene in enumerate(trial.intervals):
                    print(f"  interval {k + 1}", file=sys.stderr, flush=True)
                    play(scene, INTERVAL_S)
                    if k == 0:
                        stop.wait(INTERVAL_GAP_S)
                answer = input(f"[{done + 1}/{total}] {trial.prompt} ").strip().lower()
                if answer in ("1", "2", "q"):
                    break
                if answer != "r":
                    print("  type 1 or 2 (r: again, q: stop)", file=sys.stderr)
            if stop.is_set() or answer == "q":
                break
            runner.answer(answer)
    except EOFError:
        pass  # standard input closed: stop; everything answered is on disk
    finally:
        stats = streamer.stop()
        link.close()
        runner.close()
    if not runner.finished:
        print(f"stopped at {runner.done} of {runner.total}; {stats.summary()}", file=sys.stderr)
        return 1
    result = runner.result()
    if result.ok:
        record, preset = save_correction(runner, result)
        print(f"saved {record} and {preset}", file=sys.stderr)
    return _print_tuning(result, args, {"participant": pid})


def cmd_bench(args) -> int:
    """Print the benchmark tables."""
    from . import bench

    bench.run(part=args.part, quick=args.quick)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``tactile``."""
    parser = argparse.ArgumentParser(
        prog="tactile",
        description="Rendering methods for low-resolution 2D vibrotactile arrays (CT, MM, AS, IM).",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    p = sub.add_parser("render", help="write the frames of one trace to .csv or .npz")
    _add_scene_arguments(p, duration=2.0)
    p.add_argument("--rate", type=float, default=100.0, help="frames per second (default 100)")
    p.add_argument("--out", required=True, help="output file, .csv or .npz")
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("stream", help="stream a scene to a device without the GUI")
    p.add_argument(
        "--device",
        required=True,
        metavar="URL",
        help="port or pyserial URL; 'sim' for the simulated array",
    )
    _add_scene_arguments(p, duration=2.0)
    p.add_argument(
        "--pause", type=float, default=0.5, help="seconds off between traces (default 0.5)"
    )
    p.add_argument("--rate", type=float, default=300.0, help="frames per second (default 300)")
    p.add_argument(
        "--seconds", type=float, default=None, help="stop after this long (default: Ctrl-C)"
    )
    p.add_argument("--profile", default=None, help="device profile JSON (default: the palm array)")
    p.add_argument(
        "--filter",
        choices=("point", "box"),
        default="point",
        help="temporal filter (default point: the paper's pipeline)",
    )
    p.add_argument("--subsamples", type=int, default=4, help="box filter sub-samples (default 4)")
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
    p.add_argument("--record", default=None, help="record the frames sent to .csv or .npz")
    p.add_argument("--reconnect", action="store_true", help="keep retrying after the link fails")
    p.add_argument(
        "--realtime", action="store_true", help="real-time priority (Linux; rtprio or root)"
    )
    p.set_defaults(func=cmd_stream)

    p = sub.add_parser("emulate", help="run the device emulator on a pseudo-terminal")
    p.add_argument("--profile", default=None, help="device profile JSON (default: the palm array)")
    p.add_argument("--rate", type=float, default=None, help="nominal rate for the interval error")
    p.add_argument(
        "--seconds", type=float, default=None, help="end after this long (default: Ctrl-C)"
    )
    p.add_argument("--log", default=None, help="write every received frame to this CSV")
    p.add_argument("--json", default=None, help="write the report to this JSON file")
    p.add_argument(
        "--close-after",
        type=float,
        default=None,
        help="close the device after this long (fault test)",
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
    p.add_argument("--participants", type=int, default=12)
    p.add_argument("--seed", type=int, default=1)
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
    p.add_argument("--threshold", type=float, default=None, help="simulated TH in [0, 0.95]")
    p.add_argument("--exponent", type=float, default=None, help="simulated K in [0.1, 10]")
    p.add_argument("--threshold-sd", type=float, default=0.02,
                   help="simulated threshold spread, drive units (default 0.02)")  # fmt: skip
    p.add_argument("--weber", type=float, default=0.15,
                   help="simulated magnitude noise, log units (default 0.15)")  # fmt: skip
    p.add_argument("--lapse", type=float, default=0.03,
                   help="simulated lapse rate (default 0.03)")  # fmt: skip
    p.add_argument("--seed", type=int, default=0, help="seeds the procedure (and simulation)")
    p.add_argument("--device", metavar="URL", default=None, help="port or URL; 'sim' for the "
                   "simulated array")  # fmt: skip
    p.add_argument("--participant", metavar="ID", default=None)
    p.add_argument("--results", metavar="DIR", default=None, help="results folder")
    p.add_argument("--profile", default=None, help="device profile JSON (default: the palm array)")
    p.add_argument("--trials-per-tactor", type=int, default=20, help="threshold trials per "
                   "tactor, 5 tactors (default 20)")  # fmt: skip
    p.add_argument("--trials-per-place", type=int, default=40,
                   help="constancy trials at each of 2 places (default 40)")  # fmt: skip
    p.add_argument("--corner-trials", type=int, default=12,
                   help="constancy trials at the cell corner, the check (default 12)")  # fmt: skip
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=cmd_tune_correction)

    p = sub.add_parser("bench", help="print the speed/accuracy tables")
    p.add_argument(
        "--part",
        choices=("core", "methods", "device", "gui", "experiments", "tuning", "all"),
        default="all",
    )
    p.add_argument("--quick", action="store_true", help="smaller sizes, coarser reference")
    p.set_defaults(func=cmd_bench)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``tactile`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
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


if __name__ == "__main__":
    sys.exit(main())
