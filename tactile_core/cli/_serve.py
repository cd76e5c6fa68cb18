"""``tactile serve``: an OSC server feeding free points to a device; ``--lsl`` for it and for
``tactile stream``."""

from __future__ import annotations

import argparse
import dataclasses
import errno
import math
import sys
import time

from .._shared import validate as _validate
from .._shared.jsonfile import write_json_atomic
from .._shared.outfile import check_output
from ..rendering.correction import check_correction
from ..serve import SWITCH_INTERVAL_S
from ..stream import DEFAULT_LEAD_MS, StreamOptions, check_lead_ms
from ._common import (
    DEVICE_HELP,
    UsageError,
    _install_stop_handlers,
    _seconds,
    add_compensate_motors,
    motors_to_compensate,
    number,
    profile_help,
    whole,
)


def add_lsl_arguments(p: argparse.ArgumentParser) -> None:
    """``--lsl`` and ``--lsl-levels``."""
    p.add_argument(
        "--lsl",
        action="store_true",
        help="a Lab Streaming Layer marker stream (tactile-markers): one sample per "
        "presentation, stamped with its first frame's send time",
    )
    p.add_argument(
        "--lsl-levels",
        action="store_true",
        help="also the levels of every frame on LSL (tactile-levels)",
    )


def add_serve_parser(sub) -> None:
    """The ``serve`` sub-command."""
    from ..serve import DEFAULT_PORT

    p = sub.add_parser(
        "serve",
        help="drive a device from another program over OSC (UDP)",
        description="Listen for OSC messages (/tactile/point x y [intensity], "
        "/tactile/point/<id> ..., /tactile/release [id], /tactile/method NAME, "
        "/tactile/mu F, /tactile/gamma F, /tactile/shape SHAPE DURATION_S, "
        "/tactile/off) and render the points on the device. The first line of "
        "standard output is osc://HOST:PORT; a status line goes to standard "
        "error every --status-s seconds, a summary to standard output at the "
        "end.",
    )
    p.add_argument(
        "--osc-port",
        type=whole,
        default=DEFAULT_PORT,
        help=f"UDP port to listen on (default {DEFAULT_PORT}; 0: any free port)",
    )
    p.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on: 127.0.0.1 (the default) or ::1 (also written [::1]): this "
        "machine only; 0.0.0.0, :: or a LAN address or host name let other machines drive the "
        "array, with a warning",
    )
    p.add_argument(
        "--device",
        required=True,
        metavar="URL",
        help=DEVICE_HELP,
    )
    p.add_argument("--profile", default=None, help=profile_help())
    p.add_argument(
        "--method",
        default=None,
        metavar="M",
        help="a method that renders free points (not MM or IM): CT, AS, EN, PK, RO, "
        "GS, VRCH, BA or a plug-in (default AS; BA, AS's weights for any layout, on a "
        "profile that is not a grid)",
    )
    p.add_argument("--mu", type=number, default=0.0, help="threshold in [0, 1] (default 0)")
    p.add_argument("--gamma", type=number, default=1.0, help="gamma > 0 (default 1)")
    p.add_argument("--rate", type=number, default=300.0, help="frames per second (default 300)")
    add_compensate_motors(p)
    p.add_argument(
        "--timeout-ms",
        type=number,
        default=100.0,
        help="release a point not refreshed within this long (default 100)",
    )
    p.add_argument(
        "--interpolate",
        action="store_true",
        help="move each point between its last two updates (smooth, one update "
        "interval later) instead of showing the newest at once",
    )
    p.add_argument(
        "--max-rate",
        type=number,
        default=10_000.0,
        help="units of work read per second at most, shared among the senders (a point "
        "message is one unit, a datagram one per 64 bytes, a shape one more per point); "
        "more are dropped and counted (default 10000)",
    )
    p.add_argument(
        "--reply-port",
        type=whole,
        default=None,
        metavar="PORT",
        help="send replies (/tactile/error for a refused message) to each sender's host at "
        "this port, e.g. a Max [udpreceive PORT] (default: only to senders that send "
        "/tactile/reply)",
    )
    p.add_argument(
        "--lead-ms",
        type=number,
        default=DEFAULT_LEAD_MS,
        help="send frames this far ahead to arrays with scheduled frames (0: played "
        f"on arrival; default {DEFAULT_LEAD_MS:g})",
    )
    p.add_argument(
        "--status-s",
        type=number,
        default=2.0,
        help="seconds between status lines on standard error (default 2; 0: none)",
    )
    p.add_argument(
        "--seconds", type=number, default=None, help="stop after this long (default: Ctrl-C)"
    )
    p.add_argument("--json", default=None, help="write the final counters to this JSON file")
    p.add_argument("--reconnect", action="store_true", help="keep retrying after the link fails")
    p.add_argument(
        "--realtime", action="store_true", help="real-time priority (Linux; rtprio or root)"
    )
    add_lsl_arguments(p)
    add_validate_arguments(p)
    p.set_defaults(func=cmd_serve)


def add_validate_arguments(p: argparse.ArgumentParser) -> None:
    """``--validate`` and ``--validate-log``."""
    p.add_argument("--validate", metavar="INPUT", default=None,
                   help="a sensor on the array (audio:NAME?channel=N, or 'sim' on --device sim): "
                   "log its onset of every presentation beside the commanded time, with the "
                   "delay (and with --lsl, on the LSL stream tactile-validation)")  # fmt: skip
    p.add_argument("--validate-log", metavar="PATH", default=None,
                   help="the validator's CSV, or a folder for validate-<date>.csv (default: "
                   "the current folder)")  # fmt: skip


def lsl_outlets(args, profile, rate_hz: float):
    """The LSL outlets ``--lsl`` / ``--lsl-levels`` ask for, or None; opened before the device
    so that outlets that cannot open (:class:`~tactile_core.serve.LslError`, which the command
    reports) never leave a device half-started. A source id taken by another program on this
    machine is said on standard error."""
    if not (getattr(args, "lsl", False) or getattr(args, "lsl_levels", False)):
        return None
    from ..serve import LslOutlets

    outlets = LslOutlets(profile, rate_hz=rate_hz, markers=True, levels=args.lsl_levels)
    if outlets.note:
        print(f"tactile {args.command}: {outlets.note}", file=sys.stderr, flush=True)
    return outlets


RETRY_S = 0.5
"""How often ``--reconnect`` tries a link that cannot open yet, s (as the stream retries one
that failed)."""


def open_outputs(args, profile, rate_hz: float, stop=None):
    """The LSL outlets (:func:`lsl_outlets`) and then the device link, for ``tactile stream``
    and ``serve``: ``(outlets or None, link)``, or None once it has said on standard error why
    one could not open (the command then exits 1, nothing left open).

    With ``--reconnect`` a link that cannot open yet (a port not plugged in) is tried again
    every :data:`RETRY_S` until it opens, ``stop`` (a :class:`StopRequest`) is set or
    ``--seconds`` have passed, saying once what it waits for (and again when the reason
    changes): a stream started before its array is plugged in waits for it, as one whose
    array is unplugged later does.
    """
    from ..device.link import LinkError, open_link
    from ..serve import LslError

    try:
        lsl = lsl_outlets(args, profile, rate_hz)
    except LslError as exc:
        print(f"tactile {args.command}: error: {exc}", file=sys.stderr)
        return None
    from ..device.audio import OPEN_DEVICE_TIMEOUT_S

    seconds = getattr(args, "seconds", None)  # no longer than the run: an opening may hang
    timeout_s = OPEN_DEVICE_TIMEOUT_S if seconds is None else min(OPEN_DEVICE_TIMEOUT_S, seconds)
    end = None if seconds is None else time.monotonic() + seconds
    said = ""
    while True:
        try:
            return lsl, open_link(args.device, profile, open_timeout_s=timeout_s)
        except LinkError as exc:
            waiting = getattr(args, "reconnect", False) and stop is not None
            if waiting and not stop.is_set() and (end is None or time.monotonic() < end):
                if str(exc) != said:
                    said = str(exc)
                    print(f"tactile {args.command}: {exc}; waiting for it (--reconnect, "
                          f"every {RETRY_S:g} s; Ctrl-C to give up)", file=sys.stderr)  # fmt: skip
                if not stop.wait(RETRY_S):
                    continue
            print(f"tactile {args.command}: {exc}", file=sys.stderr)
            if lsl is not None:
                lsl.close()
            return None


def _plain(data: dict) -> dict:
    return {
        k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in data.items()
    }


def _check(args):
    """Everything the command line says, checked before anything opens."""
    from ..device.profile import ProfileError, load_profile
    from ..rendering.placement import default_method
    from ..rendering.points import free_method
    from ..rendering.rasterize import check_renders
    from ..rendering.scene import Scene
    from ..serve import listen_host

    try:
        profile = load_profile(args.profile)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    if args.method is None:  # AS, or its generalisation where AS needs the grid it lacks
        args.method = default_method(profile.layout, free_points=True)
    method = free_method(args.method).spec
    check_renders(method, profile.layout)
    mu, gamma = check_correction(args.mu, args.gamma)
    _validate.rate("--rate", args.rate, 1.0, 10_000.0)  # as the stream's scene takes it
    compensate = motors_to_compensate(args, profile) is not None
    scene = Scene(
        method=method, mu=mu, gamma=gamma, rate_hz=args.rate, compensate_motors=compensate
    )
    if not 1.0 <= args.timeout_ms <= 60_000.0:
        raise UsageError(f"--timeout-ms must be within [1, 60000], got {args.timeout_ms:g}")
    try:
        check_lead_ms(args.lead_ms, "--lead-ms")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if not (args.status_s == 0 or 0.1 <= args.status_s <= 3600):
        raise UsageError(f"--status-s must be 0 or within [0.1, 3600], got {args.status_s:g}")
    if not 1.0 <= args.max_rate <= 1e7:
        raise UsageError(f"--max-rate must be within [1, 10000000], got {args.max_rate:g}")
    try:
        args.host = listen_host(args.host)
    except ValueError as exc:
        raise UsageError(f"--{exc}") from None
    if not 0 <= args.osc_port <= 65535:
        raise UsageError(f"--osc-port must be within [0, 65535], got {args.osc_port}")
    if args.reply_port is not None and not 1 <= args.reply_port <= 65535:
        raise UsageError(f"--reply-port must be within [1, 65535], got {args.reply_port}")
    args.seconds = _seconds(args.seconds)
    if args.json is not None:
        check_output(args.json, (), "--json")
    return profile, scene


def _cannot_listen(exc: OSError) -> str:
    """The line for a port the server cannot have, with what to do about one in use."""
    text = f"tactile serve: {exc}"
    if exc.errno == errno.EADDRINUSE:
        text += ("; another program listens there (another tactile serve?): --osc-port 0 "
                 "takes any free port and prints it on the first line")  # fmt: skip
    return text


def cmd_serve(args) -> int:
    """Serve OSC until stopped; all off on every way out; print the counters."""
    from ..serve import OscServer, check_listen
    from ..stream import Streamer

    profile, scene = _check(args)
    try:  # before the device and the outlets: a port in use is said first, nothing touched
        check_listen(args.host, args.osc_port)
    except OSError as exc:
        print(_cannot_listen(exc), file=sys.stderr)
        return 1
    stop = _install_stop_handlers()
    opened = open_outputs(args, profile, scene.rate_hz, stop)
    if opened is None:
        return 1
    lsl, link = opened
    validator = _validator(args, link, profile, lsl)
    if validator is False:
        link.close()
        if lsl is not None:
            lsl.close()
        return 1
    streamer = Streamer(
        link,
        profile,
        options=StreamOptions(
            reconnect=args.reconnect, realtime=args.realtime, lead_ms=args.lead_ms
        ),
        switch_interval_s=SWITCH_INTERVAL_S,
        on_status=lambda s: print(f"[{s.state}] {s.status}", file=sys.stderr, flush=True),
    )
    server = OscServer(
        streamer,
        profile,
        scene=scene,
        host=args.host,
        port=args.osc_port,
        timeout_s=args.timeout_ms / 1e3,
        interpolate=args.interpolate,
        max_rate_hz=args.max_rate,
        reply_port=args.reply_port,
    )
    try:
        if lsl is not None:
            lsl.attach(streamer)
        if validator is not None:
            validator.attach(streamer)
        streamer.start()
        try:
            server.start()
        except OSError as exc:  # taken since the check
            print(_cannot_listen(exc), file=sys.stderr)
            return 1
        host, port = server.address
        where = f"[{host}]:{port}" if ":" in host else f"{host}:{port}"  # IPv6 in brackets
        print(f"osc://{where}", flush=True)
        print(
            f"serving {profile.name} ({scene.method}, mu={scene.mu:g}, gamma={scene.gamma:g}"
            f"{', motor-aware drive' if scene.compensate_motors else ''}) to "
            f"{link.description} on udp {where}; Ctrl-C to end",
            file=sys.stderr,
            flush=True,
        )
        _wait(args, stop, streamer, server)
    finally:
        served = server.stop()
        stats = streamer.stop()
        if validator is not None:
            validator.close()
        link.close()
        if lsl is not None:
            lsl.close()
    print(served.summary())
    print(stats.summary())
    if validator is not None:
        print(validator.summary_line())
    if args.json:
        try:
            write_json_atomic(
                args.json, {"serve": served.to_dict(), "stream": _plain(dataclasses.asdict(stats))}
            )
        except OSError as exc:  # a full disk: the counters above stand, the file does not
            print(f"tactile serve: cannot write --json {args.json}: {exc.strerror or exc}",
                  file=sys.stderr)  # fmt: skip
            return 1
    if stats.state == "failed":
        print(f"tactile serve: {stats.status}", file=sys.stderr)
        print(streamer.failure_traceback, file=sys.stderr, end="")
        return 70
    return 0 if stats.state != "refused" and stats.errors == 0 else 1


def _validator(args, link, profile, lsl):
    """The validator ``--validate`` asks for (None without it; False once it has said on
    standard error why it cannot open)."""
    if args.validate is None:
        return None
    from ..device.link import LinkError
    from ..experiments.measure import Validator
    from ..experiments.results import SessionError
    from ..serve import LslError

    try:
        return Validator(args.validate, log=args.validate_log or ".", link=link, profile=profile,
                         lsl=lsl is not None)  # fmt: skip
    except (LinkError, LslError, SessionError, ValueError) as exc:
        print(f"tactile {args.command}: --validate: {exc}", file=sys.stderr)
        return False


def _wait(args, stop, streamer, server) -> None:
    """Until Ctrl-C, ``--seconds`` or the stream ending; a status line every ``--status-s``."""
    start = time.monotonic()
    deadline = None if args.seconds is None else start + args.seconds
    next_line = start + args.status_s if args.status_s else math.inf
    while not stop.is_set() and streamer.running and server.running:
        now = time.monotonic()
        if deadline is not None and now >= deadline:
            break
        if now >= next_line:
            print(server.stats.line(), file=sys.stderr, flush=True)
            next_line += args.status_s
        until = min(next_line, deadline if deadline is not None else math.inf)
        stop.wait(max(0.0, min(0.1, until - now)))
