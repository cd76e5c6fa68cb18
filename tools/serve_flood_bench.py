"""Floods of costly OSC datagrams against ``tactile serve``: the frames the array gets, and how
late a held point is obeyed, before, during and after the flood.

    python tools/serve_flood_bench.py [--kind brackets|bundle|shape|mu] [--rate 50]
                                      [--seconds 4] [--pythonpath DIR]

Three processes, as in use: the array (the emulator on a pseudo-terminal, recording the
``CLOCK_MONOTONIC`` time it received each frame), ``tactile serve`` (CT at 300 Hz, frames for
now: ``--lead-ms 0``, so the receipt times are the host's own timing), a flooder sending one
datagram ``--rate`` times a second for ``--seconds``; and this process holding a point, as a
patch does: ``/tactile/point/held`` every 50 ms, moved between two corner tactors every 0.5 s.
The delay of a move is from the first datagram that says it to the first frame at the array
that shows it.

Kinds of datagram (the heaviest of each form):

- ``brackets``: 65,000 ``[`` type tags in 64 KB (issue 31: 41 ms to parse before the bound);
- ``bundle``: a bundle of point messages filling ``MAX_DATAGRAM_BYTES``;
- ``shape``: ``/tactile/shape`` with a polyline of the most points a datagram may carry;
- ``mu``: a bundle of ``/tactile/mu`` messages filling ``MAX_DATAGRAM_BYTES``: scene changes;
- ``mu1``: one ``/tactile/mu`` message a datagram (send it at thousands a second).

``--pythonpath DIR`` runs the emulator and the server from another checkout (``git archive``
of an older commit): the same flood against the code before a change.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np
from serve_bench import EMULATOR, cpu_s

CLI = [sys.executable, "-m", "tactile_core.cli"]
FLOOD = textwrap.dedent("""
    import socket, sys, time
    port, rate, seconds = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
    data = bytes.fromhex(sys.stdin.readline())
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 22)
    sent = 0
    start = time.perf_counter()
    print(start, flush=True)
    while (now := time.perf_counter() - start) < seconds:
        while sent < int(now * rate) + 1:
            try:
                sock.sendto(data, ("127.0.0.1", port))
            except OSError:
                pass
            sent += 1
        time.sleep(min(0.001, 1 / rate))
    print(sent, time.perf_counter(), flush=True)
""")
CORNERS = ((0.5, 0.5), (4.5, 5.5))  # CT: tactor 0, tactor 29


def _padded(text: bytes) -> bytes:
    text += b"\x00"
    return text + b"\x00" * (-len(text) % 4)


def message(address: str, tags: str, *args) -> bytes:
    out = _padded(address.encode()) + _padded(("," + tags).encode())
    for tag, value in zip(tags, args):
        if tag == "f":
            out += struct.pack(">f", value)
        elif tag == "s":
            out += _padded(value.encode())
    return out


def bundle(elements: list[bytes], limit: int) -> bytes:
    out = b"#bundle\x00" + b"\x00" * 7 + b"\x01"
    for element in elements:
        if len(out) + 4 + len(element) > limit:
            break
        out += struct.pack(">i", len(element)) + element
    return out


BOUNDS = (
    "try:\n"
    "    from tactile_core.serve._osc_addresses import MAX_SHAPE_NUMBERS as n\n"
    "    from tactile_core.serve._osc_wire import MAX_DATAGRAM_BYTES as b\n"
    "    print(b, n)\n"
    "except ImportError:\n"
    "    print(65000, 20000)\n"  # the code before the bounds: 64 KB, a shape of 10,000 points
)


def datagram(kind: str, env: dict) -> bytes:
    """The heaviest datagram of ``kind`` (see the module's docstring) that the server run with
    ``env`` accepts."""
    found = subprocess.run([sys.executable, "-c", BOUNDS], env=env, capture_output=True,
                           text=True, check=True)  # fmt: skip
    limit, numbers = map(int, found.stdout.split())
    if kind == "brackets":
        return _padded(b"/tactile/point") + _padded(b"," + b"[" * 65_000)
    if kind == "bundle":
        points = [message(f"/tactile/point/f{k % 48}", "fff", 2.5, 3.0, 0.5) for k in range(4096)]
        return bundle(points, limit)
    if kind == "mu":
        return bundle([message("/tactile/mu", "f", 0.1 + (k % 5) * 0.01) for k in range(4096)],
                      limit)  # fmt: skip
    if kind == "mu1":
        return message("/tactile/mu", "f", 0.125)
    if kind == "shape":
        spec = "polyline:" + ",".join(["1,1,2,2"] * (numbers // 4))
        while len(message("/tactile/shape", "sf", spec, 0.1)) > limit:
            spec = spec[: spec.rfind(",", 0, spec.rfind(","))]
        return message("/tactile/shape", "sf", spec, 0.1)
    raise SystemExit(f"unknown kind {kind}")


def run(args) -> None:
    env = dict(os.environ)
    if args.pythonpath:
        env["PYTHONPATH"] = args.pythonpath
    data = datagram(args.kind, env)
    with tempfile.TemporaryDirectory() as folder:
        record, summary = Path(folder) / "frames.npz", Path(folder) / "serve.json"
        emulator = subprocess.Popen([sys.executable, "-c", EMULATOR, str(record)], env=env,
                                    stdout=subprocess.PIPE, text=True)  # fmt: skip
        path = emulator.stdout.readline().strip()
        serve = subprocess.Popen(
            [*CLI, "serve", "--device", path, "--osc-port", "0", "--status-s", "0",
             "--method", "CT", "--lead-ms", "0", "--json", str(summary)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
        )  # fmt: skip
        port = int(serve.stdout.readline().strip().rsplit(":", 1)[1])
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        moves = []  # (time of the first datagram of a position, which corner)

        def hold(seconds: float, start_k: int) -> int:
            end = time.perf_counter() + seconds
            k = start_k
            while time.perf_counter() < end:
                corner = (k // 10) % 2  # a new corner every 10 sends (0.5 s)
                t = time.perf_counter()
                sock.sendto(message("/tactile/point/held", "ff", *CORNERS[corner]), ("127.0.0.1",
                            port))  # fmt: skip
                if k % 10 == 0:
                    moves.append((t, corner))
                k += 1
                time.sleep(0.05)
            return k

        k = hold(2.0, 0)  # before
        before0 = cpu_s(serve.pid)
        flood = subprocess.Popen([sys.executable, "-c", FLOOD, str(port), str(args.rate),
                                  str(args.seconds)], stdin=subprocess.PIPE,
                                 stdout=subprocess.PIPE, text=True)  # fmt: skip
        flood.stdin.write(data.hex() + "\n")
        flood.stdin.flush()
        start = float(flood.stdout.readline())
        k = hold(args.seconds, k)
        sent, end = flood.stdout.readline().split()
        cpu = (cpu_s(serve.pid) - before0) / (float(end) - start)
        hold(4.0, k)  # after
        serve.send_signal(signal.SIGINT)
        serve.communicate(timeout=60)
        emulator.send_signal(signal.SIGINT)
        emulator.communicate(timeout=60)
        with np.load(record) as npz:
            times, levels = npz["time"], npz["levels"]
        served = json.loads(summary.read_text())
    end = float(end)
    print(f"{args.kind}: {len(data)} bytes, {sent} sent at {args.rate:g}/s for {args.seconds:g} s"
          f"{' (code from ' + args.pythonpath + ')' if args.pythonpath else ''}")  # fmt: skip
    s = served["serve"]
    print(f"  server: {s['datagrams']} datagrams, {s['messages']} messages read, "
          f"{s['flood_dropped']} over the rate limit, {s.get('too_large', 0)} too large, "
          f"{s['malformed']} malformed, {s['points']} points; "
          f"tactile serve's CPU during the flood {cpu:.0%}")  # fmt: skip
    st = served["stream"]
    print(f"  stream: {st['frames']} frames, {st['late']} late (> 1 ms), {st['skipped']} skipped")
    for name, lo, hi in (("before", start - 2.0, start), ("during", start, end),
                         ("after", end, end + 4.0)):  # fmt: skip
        inside = times[(times >= lo) & (times < hi)]
        gaps = np.diff(inside) * 1e3
        delays = []
        for t, corner in moves:
            if lo <= t < hi:
                lit = levels[:, 0 if corner == 0 else 29] > 0
                shown = np.flatnonzero((times >= t) & lit)
                delays.append((times[shown[0]] - t) * 1e3 if len(shown) else np.inf)
        d = np.array(delays)
        print(f"  {name:6}: {len(inside) / (hi - lo):5.0f} frames/s of 300, largest gap "
              f"{gaps.max() if len(gaps) else np.nan:6.1f} ms; held point moved {len(d)} times, "
              f"obeyed after median {np.median(d):.1f} ms, max {d.max():.1f} ms")  # fmt: skip


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    kinds = ("brackets", "bundle", "shape", "mu", "mu1")
    p.add_argument("--kind", default="brackets", choices=kinds)
    p.add_argument("--rate", type=float, default=50.0, help="datagrams a second")
    p.add_argument("--seconds", type=float, default=4.0)
    p.add_argument("--pythonpath", default=None, help="run the code of this checkout")
    run(p.parse_args(argv))
    return 0


if __name__ == "__main__":
    sys.exit(main())
