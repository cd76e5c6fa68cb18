"""The commands around the experiments: ``analyze`` and ``simulate`` (the paper's studies),
``tune-correction`` (mu and gamma by feel) and ``bench`` (the speed and accuracy tables)."""

from __future__ import annotations

import sys

from .._shared import validate as _validate
from .._shared.outfile import check_folder
from ._common import UsageError, _install_stop_handlers
from ._keys import read_key


def cmd_analyze(args) -> int:
    """Print the paper's tables and write its figures from a results folder."""
    from ..experiments.analysis import analyze

    analyze(args.results, paper_rounding=args.paper_rounding)
    return 0


def cmd_simulate(args) -> int:
    """Run every experiment with simulated participants into a results folder (the correction
    tuning with the contract's simulated participant, its measured correction kept)."""
    from ..experiments import RUNNERS, SimulatedParticipant, open_session, save_correction

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
                if name == "correction" and runner.result().ok:
                    save_correction(runner)  # as tune-correction keeps a measured one
            finally:
                runner.close()
    print(
        f"simulated {args.participants} participant(s) ({', '.join(experiments)}) in {args.results}"
    )
    return 0


def _tuning_plan(args):
    from ..experiments.tuning import TuningPlan

    return TuningPlan(args.trials_per_tactor, args.trials_per_place, args.corner_trials,
                      threshold_procedure=args.threshold_procedure)  # fmt: skip


def _print_tuning(result, args, extra: dict) -> int:
    import json

    if args.json:
        extra = {"threshold_procedure": args.threshold_procedure, **extra}
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
    from ..experiments.tuning import simulate_tuning

    plan = _tuning_plan(args)
    seed = _validate.integer("seed", args.seed, 0, 2**31 - 1)
    if args.simulate:
        if args.device is not None:
            raise UsageError("--simulate and --device exclude each other")
        if args.threshold is None or args.exponent is None:
            raise UsageError("--simulate needs --threshold TH and --exponent K")
        extra = {}
        if args.profile is not None:  # the simulated participant feels this array
            from ..device.profile import ProfileError, load_profile

            try:
                extra["profile"] = load_profile(args.profile)
            except ProfileError as exc:
                raise UsageError(str(exc)) from None
        result = simulate_tuning(
            args.threshold, args.exponent, seed=seed, plan=plan, threshold_sd=args.threshold_sd,
            weber=args.weber, lapse=args.lapse, **extra,
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
    from ..device.link import LinkError, open_link
    from ..device.profile import ProfileError, load_profile
    from ..experiments.results import check_participant, open_session
    from ..experiments.tuning import CorrectionTuning, save_correction
    from ..stream.streamer import Streamer

    interval_s = args.interval_ms / 1e3
    if not 0.02 <= interval_s <= 5.0:  # NaN fails too
        raise UsageError(f"--interval-ms must be within [20, 5000], got {args.interval_ms!r}")
    pid = check_participant(args.participant)
    check_folder(args.results, "--results")
    try:
        profile = load_profile(args.profile)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    session = open_session(args.results, pid, seed=seed, device_profile=profile.name)
    runner = CorrectionTuning(session, plan, profile=profile)
    stop = _install_stop_handlers()
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
        print(f"{runner.done} of {runner.total} answered so far; keys: 1 or 2 answer, r plays "
              "again, q stops (resume later with the same command)", file=sys.stderr)  # fmt: skip
        while not runner.finished and not stop.is_set():
            trial = runner.current
            done, total = runner.progress()
            if trial.kind == "continue":
                answer = read_key(f"[{done + 1}/{total}] {trial.prompt} (Enter or Space) ",
                                  whitespace=True, stop=stop)  # fmt: skip
                if answer == "q":
                    break
                runner.answer("continue")
                continue
            while not stop.is_set():
                for k, scene in enumerate(trial.intervals):
                    print(f"  interval {k + 1}", file=sys.stderr, flush=True)
                    play(scene, interval_s)
                    if k == 0:
                        stop.wait(interval_s)
                answer = read_key(f"[{done + 1}/{total}] {trial.prompt} ", stop=stop)
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
    from .. import bench

    if args.profile is not None:
        if args.part not in ("trade", "all"):
            raise UsageError(f"--profile is for --part trade, not --part {args.part}")
        from ..device.profile import load_profile

        load_profile(args.profile)  # a bad name or file is refused before any table runs
    bench.run(part=args.part, quick=args.quick, profile=args.profile)
    return 0
