"""``tactile measure``: motor constants, amplitude and frequency against level, and the onset
delay per tactor, from a sensor on an audio input (or the simulated sensor)."""

from __future__ import annotations

import json
import math
import sys

from ._common import DEVICE_HELP, UsageError, number, profile_help, whole

SIM_DEFAULTS = {"tau_up_ms": 30.0, "tau_down_ms": 60.0, "delay_ms": 5.0, "noise": 0.02}


def add_measure_parser(sub) -> None:
    """The ``measure`` sub-command."""
    p = sub.add_parser(
        "measure",
        help="measure the motors (time constants, amplitude and frequency against level, "
        "onset delay) with a sensor on an audio input",
        description="Per tactor, play steps at several levels, a slow level ramp and short "
        "pulses while a sensor (accelerometer, piezo disc, contact microphone) on that tactor "
        "records through an audio input; fit a first-order motor to the vibration's envelope. "
        "--simulate runs the same procedure against the built-in simulated sensor, at once. "
        "docs/measuring.md says how to mount and set up the sensor.",
    )
    p.add_argument("--input", metavar="URL", default=None,
                   help="the sensor: audio:NAME?channel=N&samplerate=R&latency_ms=L (an audio "
                   "input; channel from 1, default 1), or 'sim' (the simulated sensor, in real "
                   "time, on --device sim)")  # fmt: skip
    p.add_argument("--device", metavar="URL", default=None, help=DEVICE_HELP)
    p.add_argument("--profile", default=None, help=profile_help())
    p.add_argument("--out", metavar="PROFILE.json", default=None,
                   help="write a copy of the profile with the measured constants per tactor, "
                   "the amplitude curve, the date and the sensor (nothing is written after "
                   "an error, nor after a warning about the input unless "
                   "--accept-warnings)")  # fmt: skip
    p.add_argument("--tactors", default="all", metavar="LIST",
                   help="the tactors to measure, in order: names (r0c0,r2c3) or indices, or "
                   "'all' (default)")  # fmt: skip
    p.add_argument("--quick", action="store_true",
                   help="a shorter block per tactor (8.0 s instead of 14.0 s with 8 neighbours; "
                   "for motors up to ~60 ms)")  # fmt: skip
    p.add_argument("--rate", type=number, default=300.0, help="frames per second (default 300)")
    p.add_argument(
        "--yes",
        action="store_true",
        help="do not wait for Enter before each tactor (the sensor is in place)",
    )
    p.add_argument("--accept-warnings", action="store_true",
                   help="write --out despite warnings about the input (mains hum, a sensor "
                   "between two tactors)")  # fmt: skip
    p.add_argument("--json", action="store_true",
                   help="print the result as JSON on standard output (progress on standard "
                   "error): medians tau_up_ms, tau_down_ms, delay_ms, onset_ms and every "
                   "tactor")  # fmt: skip
    sim = p.add_argument_group("the simulated sensor (--simulate, or --input sim)")
    sim.add_argument("--simulate", action="store_true",
                     help="run against the simulated sensor in virtual time (no device, no "
                     "waiting)")  # fmt: skip
    sim.add_argument(
        "--tau-up-ms",
        type=number,
        default=None,
        help=f"its motors' spin-up (default {SIM_DEFAULTS['tau_up_ms']:g})",
    )
    sim.add_argument(
        "--tau-down-ms",
        type=number,
        default=None,
        help=f"run-down (default {SIM_DEFAULTS['tau_down_ms']:g})",
    )
    sim.add_argument(
        "--delay-ms",
        type=number,
        default=None,
        help=f"from a frame to its drive (default {SIM_DEFAULTS['delay_ms']:g})",
    )
    sim.add_argument("--noise", type=number, default=None,
                     help="white noise, RMS, as a fraction of the full-drive vibration "
                     f"(default {SIM_DEFAULTS['noise']:g})")  # fmt: skip
    sim.add_argument("--seed", type=whole, default=0, help="seeds the simulation (default 0)")
    p.set_defaults(func=cmd_measure)


def _check(args):
    """Everything the command line says, checked before anything opens: ``(profile, cells,
    plan, sim options)``."""
    from ..device.measure import QUICK_PLAN, MeasurePlan
    from ..device.profile import ProfileError, load_profile

    sim_given = [k for k in SIM_DEFAULTS if getattr(args, k) is not None]
    if args.simulate:
        if args.input is not None or args.device is not None:
            raise UsageError("--simulate runs without --input and --device (it simulates both)")
    elif args.input is None or args.device is None:
        raise UsageError("give --input URL and --device URL (or --simulate)")
    elif args.input.strip().lower() != "sim" and sim_given:
        raise UsageError(f"--{sim_given[0].replace('_', '-')} sets the simulated sensor: give "
                         "it with --simulate or --input sim")  # fmt: skip
    try:
        profile = load_profile(args.profile)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    options = {k: (getattr(args, k) if getattr(args, k) is not None else v)
               for k, v in SIM_DEFAULTS.items()}  # fmt: skip
    for key, (lo, hi) in {"tau_up_ms": (0.5, 2000.0), "tau_down_ms": (0.5, 2000.0),
                          "delay_ms": (0.0, 400.0), "noise": (0.0, 1.0)}.items():  # fmt: skip
        if not (math.isfinite(options[key]) and lo <= options[key] <= hi):
            raise UsageError(f"--{key.replace('_', '-')} must be within [{lo:g}, {hi:g}], got "
                             f"{options[key]:g}")  # fmt: skip
    options["seed"] = args.seed
    if not 10.0 <= args.rate <= 1000.0:
        raise UsageError(f"--rate must be within [10, 1000], got {args.rate:g}")
    if args.out is not None:
        from .._shared.outfile import check_output

        check_output(args.out, (".json",), "--out")
    plan = QUICK_PLAN if args.quick else MeasurePlan()
    return profile, tactor_list(args.tactors, profile), plan, options


def tactor_list(text: str, profile) -> list[int]:
    """``--tactors``: ``all``, or names and indices separated by commas; ``UsageError``
    naming one that is not a tactor of the profile."""
    layout = profile.layout
    size = profile.channels
    if text.strip().lower() == "all":
        return list(range(size))
    names = {layout.cell_name(i).lower(): i for i in range(size)}
    cells = []
    for word in (w.strip() for w in text.split(",")):
        if word.isascii() and word.isdigit() and int(word) < size:
            cells.append(int(word))
        elif word.lower() in names:
            cells.append(names[word.lower()])
        else:
            some = ", ".join(list(names)[:4])
            raise UsageError(f"--tactors: {word!r} is not a tactor of {profile.name} (names "
                             f"such as {some}, or indices 0-{size - 1})")  # fmt: skip
    if len(set(cells)) != len(cells):
        raise UsageError(f"--tactors names a tactor twice: {text!r}")
    return cells


def cmd_measure(args) -> int:
    """Run the procedure; print (and write) the result."""
    profile, cells, plan, options = _check(args)
    out = sys.stderr if args.json else sys.stdout

    def log(text):
        print(text, file=out, flush=True)

    per_tactor = plan.duration_s(8, profile.levels)
    n = len(cells)
    log(f"{per_tactor:.1f} s of stimulus per tactor (8 neighbours scanned); {n} "
        f"tactor{'s' if n != 1 else ''}: {n * per_tactor / 60:.1f} min, plus moving the "
        "sensor")  # fmt: skip
    if args.simulate:
        from ..device.measure import simulate_measurement

        sim = {k: options[k] for k in ("tau_up_ms", "tau_down_ms", "delay_ms", "noise", "seed")}
        result = simulate_measurement(profile, cells=cells, plan=plan, rate_hz=args.rate, **sim)
    else:
        result = _at_the_array(args, profile, cells, plan, options, log)
        if result is None:
            return 1
    from ..experiments.measure import result_lines

    if args.simulate:
        for line in result_lines(result):
            log(line)
    if args.json:
        print(json.dumps(result.summary(), allow_nan=False), flush=True)
    code = 1 if result.failures else 0
    if args.out is not None:
        from ..device.measure import save_measured

        why = save_measured(args.out, profile, result, accept_warnings=args.accept_warnings)
        if why:
            print(f"tactile measure: {why}", file=sys.stderr)
            return 1
        log(f"wrote {args.out}: {len(result.tactors)} tactors measured")
    return code


def _at_the_array(args, profile, cells, plan, options, log):
    """Open the device and the sensor and run the procedure; None after saying why one could
    not open."""
    from ..device.audio import OPEN_DEVICE_TIMEOUT_S
    from ..device.link import LinkError, open_link
    from ..device.measure import open_sensor
    from ..experiments.measure import MeasureAborted, measure_array

    try:
        link = open_link(args.device, profile, open_timeout_s=OPEN_DEVICE_TIMEOUT_S)
    except LinkError as exc:
        print(f"tactile measure: {exc}", file=sys.stderr)
        return None
    try:
        try:
            sensor = open_sensor(args.input, link=link, profile=profile, sim_options=options)
        except (LinkError, ValueError) as exc:
            print(f"tactile measure: --input: {exc}", file=sys.stderr)
            return None
        prompt = None
        if not args.yes and not callable(getattr(sensor, "place", None)):
            prompt = _prompt
        sensor.start()
        try:
            return measure_array(link, profile, sensor, cells=cells, plan=plan,
                                 rate_hz=args.rate, prompt=prompt, log=log)  # fmt: skip
        except MeasureAborted as exc:
            print(f"tactile measure: {exc}", file=sys.stderr)
            return None
        finally:
            sensor.stop()
    finally:
        link.close()


def _prompt(cell: int, name: str) -> None:
    """Ask for the sensor on tactor ``name``; Enter goes on, end of input stops."""
    print(f"put the sensor on tactor {name} (index {cell}), then press Enter", file=sys.stderr,
          flush=True)  # fmt: skip
    if not sys.stdin.readline():
        raise KeyboardInterrupt
