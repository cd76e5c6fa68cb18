"""The commands of the rendering pipeline: ``render`` (frames to a file), ``stream`` (frames to
a device) and ``emulate`` (a device on a pseudo-terminal)."""

from __future__ import annotations

import sys
import time

import numpy as np

from .._shared import validate as _validate
from .._shared.outfile import check_output
from ..files.frames import write_frames
from ..files.tact import MAX_TABLE_FRAMES
from ..rendering.correction import correct
from ..rendering.methods import get_method
from ..rendering.motor_drive import motor_drive
from ..rendering.rasterize import check_renders, render
from ..stream import StreamOptions, check_lead_ms
from ._common import (
    UsageError,
    _install_stop_handlers,
    _scene,
    _seconds,
    motors_to_compensate,
    write_failed,
)
from ._pattern import describe, load_pattern_arg, say_playing
from ._tact import load_tact_arg, not_played, warn_of_notes

MAX_RENDER_FRAMES = 1_000_000
"""Most frames ``tactile render`` writes (duration x rate + 1)."""
MAX_RENDER_VALUES = 30_000_000
"""Most intensities it writes, frames x tactors: 240 MB of floats (a million frames of the
palm array's 30; a 64 x 64 grid at 1 kHz for 48 s made several 1.5 GB copies)."""


def _check_render_size(frames: int, size: int, duration_s: float, rate_hz: float) -> None:
    if frames > MAX_RENDER_FRAMES or frames * size > MAX_RENDER_VALUES:
        most = min(MAX_RENDER_FRAMES, MAX_RENDER_VALUES // size)
        raise ValueError(
            f"duration x rate must give at most {most} frames of {size} tactors, got {frames} "
            f"({duration_s:g} s at {rate_hz:g} Hz)"
        )


DARK_CHECK_FRAMES = 20_000
"""Most frames of one trace ``tactile stream`` renders before it starts to see whether any
tactor is lit (a longer trace is checked at this many times spread over it)."""


def warn_if_dark(command: str, shape, target, frames: np.ndarray) -> bool:
    """Say on standard error that no tactor is ever lit, when ``frames`` are all zero.

    Parameters
    ----------
    command : str
        ``"render"`` or ``"stream"``, for the ``tactile COMMAND: warning:`` prefix.
    shape : Shape or None
        The shape drawn (None for a ``.tact`` pattern); its extent is named beside the array's.
    target : Grid or Layout
        What the frames were rendered onto.
    frames : ndarray, shape (n, ...)
        The frames (uncorrected or corrected: 0 stays 0).

    Returns
    -------
    bool
        True if the warning was given. The command goes on either way (docs/cli.md): a scene
        that lights nothing is not an error, but it is never silent.
    """
    if np.any(frames):
        return False
    layout = target
    x0, x1, y0, y1 = layout.bounds()
    units = "grid units" if layout.is_grid else "pitches"
    where = f"the {layout.describe()} (x {x0:g} to {x1:g}, y {y0:g} to {y1:g}, {units})"
    if shape is None:
        what = "the pattern lights nothing on " + where
    else:
        xy = shape.outline()
        (sx0, sy0), (sx1, sy1) = xy.min(axis=0), xy.max(axis=0)
        wrapped = None if layout.wrap is None else layout.wrap.index  # no outside along a wrap
        apart = (wrapped != 0 and (sx1 < x0 or sx0 > x1)) or (
            wrapped != 1 and (sy1 < y0 or sy0 > y1)
        )
        what = (f"{shape.spec} (x {sx0:.3g} to {sx1:.3g}, y {sy0:.3g} to {sy1:.3g}) "
                f"{'lies outside' if apart else 'lights nothing on'} {where}")  # fmt: skip
    print(f"tactile {command}: warning: {what}: no tactor is ever lit (every frame is zero)",
          file=sys.stderr, flush=True)  # fmt: skip
    return True


def cmd_render(args) -> int:
    """Write the frames of one trace or pattern to CSV or NPZ, or its carrier signal to
    WAV."""
    out = check_output(args.out, (".csv", ".npz", ".wav"), "--out")
    wav = out.suffix.lower() == ".wav"
    profile = _render_profile(args, wav)
    shape, method, mu, gamma, grid = _scene(args)
    names = [grid.cell_name(i) for i in range(grid.size)]
    if profile is not None:  # its grid or layout, and its actuators' names
        grid = profile.layout
        check_renders(method, grid)
        names = list(profile.layout.names)
    motor = _motor_of(args, profile)
    pattern = load_tact_arg(args)
    composed = load_pattern_arg(args, grid, method)  # a pattern file
    _validate.rate("rate", args.rate, 1e-3, _validate.MAX_RATE_HZ)
    if composed is not None:
        pattern, what, left_out = composed, describe(args, composed), ""
    elif pattern is not None:
        what = f"{pattern.describe(grid)} of {args.shape[len('tact:') :]}"
        left_out = not_played(pattern, grid)
        warn_of_notes("render", pattern)
    voices = None
    if pattern is not None:  # frame k samples the middle of [k / rate, (k + 1) / rate)
        duration = pattern.duration_on(grid)
        n = int(np.ceil(duration * args.rate - 1e-9))
        _check_render_size(n, grid.size, duration, args.rate)
        time_s, frames = pattern.frames(method, grid, rate_hz=args.rate, mu=mu, gamma=gamma)
        if wav and composed is not None:  # its effects' waveforms (the same source, cached)
            from ..files.wav import frame_voices
            from ..rendering.trace import Sampling

            live = pattern.live(method, grid, Sampling(args.rate, "point"), mu, gamma)
            voices = frame_voices(live, profile, len(frames))
    else:
        n = int(np.floor(args.duration * args.rate + 1e-9)) + 1
        _check_render_size(n, grid.size, args.duration, args.rate)
        time_s = np.arange(n) / args.rate
        u = np.minimum(time_s / args.duration, 1.0)
        t = 1.0 - u if args.direction == "reverse" else u
        timed = get_method(method).on_clock(args.duration)  # TB: onsets by the trace's duration
        frames = correct(render(shape, timed, t, grid=grid), mu, gamma)
        what, left_out = shape.spec, ""
    warn_if_dark("render", shape, grid, frames)
    what = f"{what} ({method}, mu={mu:g}, gamma={gamma:g})"
    if motor is not None:  # after the correction, before any quantisation
        frames, _ = motor_drive(frames, motor, args.rate)
        taus = "/".join(f"{np.max(t) * 1e3:g}" for t in (motor.tau_up_s, motor.tau_down_s))
        source = motor.describe().rpartition(" (")[2].rstrip(")")  # estimate, measured DATE
        what = f"{what[:-1]}, motor-aware drive for {taus} ms motors ({source}))"
    if wav:
        return _write_wav(args, out, profile, frames, what, voices)
    try:
        write_frames(out, time_s, frames, names)
    except OSError as exc:
        raise write_failed(out, exc) from None
    print(f"wrote {len(time_s)} frames of {what} to {out}{left_out}")
    return 0


def _motor_of(args, profile):
    """``--compensate-motors``: the motors to compensate, the profile's (the palm array's
    without ``--profile``); None without the option."""
    from ..device.profile import default_profile

    return motors_to_compensate(args, profile or default_profile())


def _render_profile(args, wav: bool):
    """``tactile render``'s device profile (None for frames without one), and the grid it
    sets in ``args``: the profile's, which ``--cols``/``--rows`` may only repeat."""
    from ..device.profile import ProfileError, default_profile, load_profile

    audio_options = ("samplerate", "carrier_hz", "ramp_ms", "waveform")
    if not wav:
        for name in audio_options:
            if getattr(args, name) is not None:
                option = "--" + name.replace("_", "-")
                raise UsageError(f"{option} applies to .wav output only")
    profile = None
    if wav or args.profile is not None:
        try:
            profile = load_profile(args.profile) if args.profile is not None else default_profile()
        except ProfileError as exc:
            raise UsageError(str(exc)) from None
        layout = profile.layout
        cols, rows = layout.wire_shape
        for name, value in (("cols", cols), ("rows", rows)):
            given = getattr(args, name)
            if given is not None and not layout.is_grid:  # its actuators, not a grid's cells
                raise UsageError(f"--{name} applies to a grid; the profile {profile.name} is a "
                                 f"layout of {profile.channels} actuators")  # fmt: skip
            if given is not None and given != value:
                raise UsageError(f"--{name} {given} disagrees with the profile {profile.name}'s "
                                 f"{layout.describe()}")  # fmt: skip
            if layout.is_grid:  # a layout's channel strip (up to 255 x 1) is not --cols
                setattr(args, name, value)
    args.cols = 5 if args.cols is None else args.cols
    args.rows = 6 if args.rows is None else args.rows
    return profile


def _write_wav(args, out, profile, frames, what: str, voices=None) -> int:
    """``tactile render --out FILE.wav``: the corrected frames calibrated and quantised as the
    streamer does, in channel order, as the waveforms an audio interface would play (a
    pattern's effects' own where ``voices`` names them)."""
    from ..device.audio import CARRIER_RANGE_HZ, DEFAULT_RAMP_MS, RAMP_RANGE_MS, SAMPLERATE_RANGE
    from ..device.waveform import WaveformError, parse_waveform
    from ..files.wav import frame_levels, write_wav

    samplerate = 48000 if args.samplerate is None else args.samplerate
    ramp_ms = DEFAULT_RAMP_MS if args.ramp_ms is None else args.ramp_ms
    _validate.integer("samplerate", samplerate, *SAMPLERATE_RANGE)
    _validate.in_range("ramp-ms", ramp_ms, *RAMP_RANGE_MS)
    if args.carrier_hz is not None:
        _validate.in_range("carrier-hz", args.carrier_hz, *CARRIER_RANGE_HZ)
    waveform = None
    if args.waveform is not None:
        try:
            waveform = parse_waveform(args.waveform, "--waveform")
        except WaveformError as exc:
            raise UsageError(str(exc)) from None
    levels = frame_levels(frames, profile)
    try:
        written = write_wav(out, levels, args.rate, profile, samplerate=samplerate,
                            carrier_hz=args.carrier_hz, ramp_ms=ramp_ms, waveform=waveform,
                            voices=voices)  # fmt: skip
    except OSError as exc:
        raise write_failed(out, exc) from None
    print(f"wrote {len(frames)} frames of {what} to {out}: {profile.channels} channels of "
          f"{written / samplerate:.3f} s at {samplerate} Hz (profile {profile.name})")  # fmt: skip
    return 0


def _tabulate(scene, profile) -> None:
    """Tabulate a pattern's frames before streaming it: the stream then plays from the table
    (:meth:`TactPattern.live` gives it the same frames). Computed as it plays, a frame of many
    effects at once can cost more than a frame lasts, and a table built in the background
    meanwhile takes the output thread's turns: 400 paths at once made 197 of 285 frames late.
    A pattern longer than the table holds plays as before (frame by frame); a pattern file
    (``--shape pattern:FILE``) is tabulated the same way."""
    live = scene.live(profile.layout, scene.rate_hz)
    if live.n_frames > MAX_TABLE_FRAMES:
        return
    if live.busiest_frame_s() * live.n_frames > 1.0:  # (an upper bound: the table is faster)
        print(f"tabulating the pattern's {live.n_frames} frames before playing it",
              file=sys.stderr, flush=True)  # fmt: skip
    start = time.perf_counter()
    live.precompute()
    took = time.perf_counter() - start
    if took > 0.5:
        print(f"tabulated in {took:.1f} s", file=sys.stderr, flush=True)


def cmd_stream(args) -> int:
    """Stream a scene to a device without the GUI; print statistics at the end."""
    from ..device.profile import ProfileError, load_profile
    from ..files.frames import Recorder
    from ..rendering.scene import Scene
    from ..stream.streamer import Streamer

    shape, method, mu, gamma, _ = _scene(args)
    _validate.rate("--rate", args.rate, 1.0, 10_000.0)  # as the stream's scene takes it
    try:
        profile = load_profile(args.profile)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    check_renders(method, profile.layout)
    pattern = load_tact_arg(args)
    composed = load_pattern_arg(args, profile.layout, method)  # a pattern file
    if composed is not None:
        pattern = composed
        say_playing(args, pattern)
    elif pattern is not None:
        print(f"playing {pattern.describe(profile.layout)} of {args.shape[len('tact:') :]}"
              f"{not_played(pattern, profile.layout)}", file=sys.stderr, flush=True)  # fmt: skip
        warn_of_notes("stream", pattern)
    own_end = pattern is not None and args.seconds is None
    if own_end:
        args.seconds = max(pattern.duration_on(profile.layout), 0.1)  # the file, then off
    if shape is not None:  # one trace at the stream's frame times (at most DARK_CHECK_FRAMES)
        n = min(int(np.floor(args.duration * args.rate + 1e-9)) + 1, DARK_CHECK_FRAMES)
        timed = get_method(method).on_clock(args.duration)
        trace = render(shape, timed, np.linspace(0.0, 1.0, n), grid=profile.layout)
        warn_if_dark("stream", shape, profile.layout, trace)
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
        compensate_motors=args.compensate_motors,
        source=pattern,
        marker="stream",
    )
    if args.felt_amplitude and profile.response is None:
        raise UsageError(f"--felt-amplitude needs a motor response curve: profile "
                         f"{profile.name} has none ('response')")  # fmt: skip
    motors_to_compensate(args, profile)
    args.seconds = _seconds(args.seconds)
    try:
        options = StreamOptions(reconnect=args.reconnect, realtime=args.realtime,
                                lead_ms=check_lead_ms(args.lead_ms, "--lead-ms"))  # fmt: skip
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if args.record is not None:  # '' too: refused, not ignored
        check_output(args.record, (".csv", ".npz"), "--record")
    stop = _install_stop_handlers()
    if pattern is not None:
        _tabulate(scene, profile)
    from ._serve import open_outputs

    opened = open_outputs(args, profile, scene.rate_hz, stop)
    if opened is None:
        return 1
    lsl, link = opened
    recorder = Recorder(profile.array) if args.record else None
    streamer = Streamer(
        link,
        profile,
        scene=scene,
        taps=[] if recorder is None else [recorder],
        options=options,
        on_status=lambda stats: print(
            f"[{stats.state}] {stats.status}", file=sys.stderr, flush=True
        ),
    )
    try:
        if lsl is not None:
            lsl.attach(streamer)
        streamer.start()
        while not stop.is_set() and not streamer.identified.wait(0.05):
            pass  # --seconds counts from the end of the hello exchange
        deadline = None if args.seconds is None else time.monotonic() + args.seconds
        if own_end:  # the file's last frame, not its duration since the hello (a lead and a
            deadline += END_SLACK_S  # clock exchange come between), then off
        while not stop.is_set() and streamer.running:
            if own_end and _played_through(streamer, args.seconds):
                own_end, deadline = False, time.monotonic() + options.lead_s + 2.0 / scene.rate_hz
            remaining = None if deadline is None else deadline - time.monotonic()
            if remaining is not None and remaining <= 0:
                break
            stop.wait(0.1 if remaining is None else min(0.1, remaining))
    finally:
        stats = streamer.stop()
        link.close()
        if lsl is not None:
            lsl.close()
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


END_SLACK_S = 5.0
"""How long past its duration ``tactile stream`` waits at most for a pattern's last frame to go
out (a host stall, a reconnection), before it stops anyway."""


def _played_through(streamer, duration_s: float) -> bool:
    """Whether the stream has written a frame at or past ``duration_s`` of the trace: every
    frame of a pattern has gone out (timed ones play a lead later)."""
    _, trace_time = streamer.last_frame
    return trace_time is not None and trace_time >= duration_s - 1e-9


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
    stop = _install_stop_handlers()
    keep = KEEP_FRAMES if args.keep_frames is None else args.keep_frames
    if not 1 <= keep <= 1 << 31:
        raise UsageError(f"--keep-frames must be within [1, 2147483648], got {keep}")
    if args.realtime:  # before the path is printed: a caller that reads it finds it set
        from ..device.host_clock import raise_priority

        # Above a host stream's output thread (10): an array's own processor never waits
        # for the host.
        why_not = raise_priority(EMULATOR_PRIORITY)
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
        f"emulating {profile.name} ({profile.layout.describe()}, "
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
