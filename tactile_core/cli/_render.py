"""The commands of the rendering pipeline: ``render`` (frames to a file), ``stream`` (frames to
a device) and ``emulate`` (a device on a pseudo-terminal)."""

from __future__ import annotations

import sys
import threading
import time

import numpy as np

from .._shared import validate as _validate
from .._shared.outfile import atomic_file, check_output
from ..rendering.correction import correct
from ..rendering.rasterize import render
from ._common import UsageError, _install_stop_handlers, _scene, _seconds

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


def cmd_stream(args) -> int:
    """Stream a scene to a device without the GUI; print statistics at the end."""
    from ..device.link import LinkError, open_link
    from ..device.profile import ProfileError, load_profile
    from ..device.recorder import Recorder
    from ..device.streamer import Streamer
    from ..rendering.scene import Scene

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
    lead_ms = args.lead_ms
    if not (isinstance(lead_ms, float) and 0.0 <= lead_ms <= 500.0):
        raise UsageError(f"--lead-ms must be within [0, 500] milliseconds, got {lead_ms!r}")
    if args.record is not None:  # '' too: refused, not ignored
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
        lead_s=lead_ms / 1e3,
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
    unsaved = 0
    if recorder is not None:
        try:
            path = recorder.save(args.record)
        except OSError as exc:  # a full disk: the statistics above stand, the file does not
            print(
                f"tactile stream: cannot write the recording of {len(recorder)} frames to "
                f"{args.record}: {exc.strerror or exc}",
                file=sys.stderr,
            )
            unsaved = 1
        else:
            print(f"recorded {len(recorder)} frames to {path}")
    if stats.state == "failed":
        print(f"tactile stream: {stats.status}", file=sys.stderr)
        print(streamer.failure_traceback, file=sys.stderr, end="")
        return 70  # EX_SOFTWARE: a bug, reported; the array was turned off
    if stats.state == "refused":
        print(f"tactile stream: {stats.status}", file=sys.stderr)
        return 1
    return 0 if stats.errors == 0 and not unsaved else 1


EMULATOR_PRIORITY = 20
"""SCHED_FIFO priority of ``tactile emulate --realtime`` (the stream's output thread has 10)."""


def cmd_emulate(args) -> int:
    """Run the device emulator on a pseudo-terminal until stopped."""
    from ..device.emulator import KEEP_FRAMES, Emulator
    from ..device.profile import ProfileError, load_profile

    try:
        profile = load_profile(args.profile)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    args.seconds = _seconds(args.seconds)
    args.close_after = _seconds(args.close_after, "close-after")
    if args.rate is not None:
        _validate.rate("rate", args.rate, 1e-3, _validate.MAX_RATE_HZ)
    for option, value in (("--log", args.log), ("--json", args.json)):
        if value is not None:  # '' too: refused, not ignored
            check_output(value, (), option)
    stop = threading.Event()
    _install_stop_handlers(stop)
    keep = KEEP_FRAMES if args.keep_frames is None else args.keep_frames
    if not 1 <= keep <= 1 << 31:
        raise UsageError(f"--keep-frames must be within [1, 2147483648], got {keep}")
    if args.realtime:  # before the path is printed: a caller that reads it finds it set
        from ..device._stream_plan import _raise_priority

        # Above a host stream's output thread (10): an array's own processor never waits
        # for the host.
        why_not = _raise_priority(EMULATOR_PRIORITY)
        print(
            f"tactile emulate: {why_not}" if why_not else
            f"tactile emulate: receiving at real-time priority (SCHED_FIFO {EMULATOR_PRIORITY})",
            file=sys.stderr, flush=True,
        )  # fmt: skip
    emulator = Emulator(
        profile, expected_rate_hz=args.rate, scheduled=not args.plain, keep_frames=keep
    )
    path = emulator.open_socket() if args.socket else emulator.open()
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
        print(emulator.summary(), flush=True)
    failed = 0
    for path, save in ((args.log, emulator.save_log), (args.json, emulator.save_report)):
        if path:
            try:
                save(path)
            except OSError as exc:  # a full disk: say which file, still try the other
                reason = exc.strerror or exc
                print(f"tactile emulate: cannot write {path}: {reason}", file=sys.stderr)
                failed = 1
    return failed
