"""Faults between ``tactile stream`` and an array, measured from outside (issue 31, F2-F4).

    python tools/link_faults.py stalls [--stalls 40] [--socket]
    python tools/link_faults.py socket [--seconds 25] [--rate 300] [--pty]
    python tools/link_faults.py delayed [--seconds 20] [--delay-ms 300]
    python tools/link_faults.py reset [--seconds 24] [--reset-at 16]
    python tools/link_faults.py reconnect [--seconds 16] [--reconnect-at 8]

Real processes: ``tactile emulate`` (a pseudo-terminal or ``--socket``) as the array and
``tactile stream --lead-ms 20`` into it, both reporting ``CLOCK_MONOTONIC`` times, and this
process between or beside them.

stalls: SIGSTOP and SIGCONT of the streaming process, each stall 0.25-2 s with 0.3-1 s of
running between; a stream that ends is restarted. Counts the stalls that ended a stream, and
the array's sequence gaps.

socket: a stream straight into ``tactile emulate --socket`` (``--pty``: a pseudo-terminal, to
compare): timed frames the array played late.

delayed: a TCP proxy between the two that, from ``--delay-after`` s in (after the start-up
burst), holds every byte from the array 300 ms (its clock replies): late frames, what the host
says of its clock.

reset: the proxy keeps the host's line up and, ``--reset-at`` s in, swaps the array behind it
for a fresh emulator (its clock and counters start again, as after a brown-out behind a USB
bridge): how long the new array stays dark, and what it dropped.

reconnect: the proxy closes the host's connection ``--reconnect-at`` s in, and the next one
reaches a fresh emulator (``--reconnect``): how long until that array plays frames.
"""

from __future__ import annotations

import argparse
import heapq
import json
import random
import select
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

CLI = [sys.executable, "-m", "tactile_core.cli"]  # (the code of the working folder: run it from an
# older checkout to measure that one)


class Emulator:
    """``tactile emulate`` in a child process; its report and log when it ends."""

    def __init__(self, folder: Path, name: str, *args: str):
        self.report_path = folder / f"{name}.json"
        self.log_path = folder / f"{name}.csv"
        self.proc = subprocess.Popen(
            [*CLI, "emulate", "--json", str(self.report_path), "--log", str(self.log_path),
             *args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        self.path = self.proc.stdout.readline().strip()

    @property
    def address(self) -> tuple[str, int]:
        host, port = self.path[len("socket://") :].rsplit(":", 1)
        return host, int(port)

    def finish(self) -> tuple[dict, list]:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        self.proc.communicate(timeout=60)
        report = json.loads(self.report_path.read_text())
        rows = self.log_path.read_text().splitlines()[1:]
        start = report["started_monotonic"]
        log = []
        for row in rows:
            fields = row.split(",")
            log.append((start + float(fields[0]), int(fields[1]), any(int(v) for v in fields[2:])))
        return report, log


def start_stream(device: str, *args: str) -> subprocess.Popen:
    return subprocess.Popen(
        [*CLI, "stream", "--device", device, "--shape", "circle:2.5,3,2", "--method", "IM",
         "--lead-ms", "20", *args],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip


def end_stream(proc: subprocess.Popen) -> tuple[int, str, str]:
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    return proc.returncode, out, err


def field(summary: str, name: str) -> str:
    for line in summary.splitlines():
        if line.startswith(name):
            return line[len(name) :].strip()
    return ""


class Proxy:
    """One client at a time, forwarded to an upstream TCP address that can be swapped while
    the client stays connected; bytes from upstream may be held ``down_delay_s``."""

    def __init__(self, upstream: tuple[str, int], down_delay_s: float = 0.0):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.url = f"socket://127.0.0.1:{self.listener.getsockname()[1]}"
        self.upstream = upstream
        self.down_delay_s = down_delay_s
        self.client = self.server = None
        self._held: list = []  # (due, n, bytes) from upstream
        self._n = 0
        self._lock = threading.Lock()
        self._stop = False
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def swap(self, upstream: tuple[str, int]) -> None:
        """The array behind the line is another one from now on (the line stays up)."""
        with self._lock:
            self.upstream = upstream
            if self.server is not None:
                self.server.close()
                self.server = socket.create_connection(upstream)
                self.server.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

    def drop_client(self) -> None:
        """Close the host's connection (an unplug); the next one reaches ``upstream``."""
        with self._lock:
            for sock in (self.client, self.server):
                if sock is not None:
                    sock.close()
            self.client = self.server = None
            self._held.clear()

    def close(self) -> None:
        self._stop = True
        self.thread.join(5)
        self.drop_client()
        self.listener.close()

    def _run(self) -> None:
        while not self._stop:
            with self._lock:
                socks = [self.listener] + [s for s in (self.client, self.server) if s]
                due = self._held[0][0] if self._held else None
            timeout = 0.01 if due is None else max(0.0, min(0.01, due - time.monotonic()))
            ready, _, _ = select.select(socks, [], [], timeout)
            with self._lock:
                for sock in ready:
                    if sock is self.listener:
                        client, _ = self.listener.accept()
                        if self.client is not None:
                            client.close()
                            continue
                        client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                        self.client = client
                        self.server = socket.create_connection(self.upstream)
                        self.server.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                    elif sock is self.client:
                        try:
                            data = sock.recv(65536)
                        except OSError:
                            data = b""
                        if not data:
                            self.client.close()
                            if self.server is not None:
                                self.server.close()
                            self.client = self.server = None
                            self._held.clear()
                        else:
                            self.server.sendall(data)
                    elif sock is self.server:
                        try:
                            data = sock.recv(65536)
                        except OSError:
                            data = b""
                        if data:
                            self._n += 1
                            due = time.monotonic() + self.down_delay_s
                            heapq.heappush(self._held, (due, self._n, data))
                now = time.monotonic()
                while self._held and self._held[0][0] <= now:
                    _, _, data = heapq.heappop(self._held)
                    if self.client is not None:
                        try:
                            self.client.sendall(data)
                        except OSError:
                            pass


def cmd_stalls(args, folder: Path) -> None:
    rng = random.Random(args.seed)
    emu = Emulator(folder, "stalls", *(["--socket"] if args.socket else []))
    ended, done, paused_s = [], 0, []
    proc = start_stream(emu.path, "--seconds", "3600")
    time.sleep(1.5)
    while done < args.stalls:
        if proc.poll() is not None:  # it ended: note why, start another
            rc, out, _ = end_stream(proc)
            ended.append((rc, field(out, "state:")))
            proc = start_stream(emu.path, "--seconds", "3600")
            time.sleep(1.5)
            continue
        stall = rng.uniform(0.25, 2.0)
        proc.send_signal(signal.SIGSTOP)
        time.sleep(stall)
        proc.send_signal(signal.SIGCONT)
        paused_s.append(stall)
        done += 1
        time.sleep(rng.uniform(0.3, 1.0))
    time.sleep(0.5)
    if proc.poll() is not None:
        rc, out, _ = end_stream(proc)
        ended.append((rc, field(out, "state:")))
        last = ""
    else:
        rc, last, _ = end_stream(proc)
    report, _ = emu.finish()
    print(f"{done} stalls of 0.25-2 s ({sum(paused_s):.1f} s paused): "
          f"{len(ended)} ended a stream")  # fmt: skip
    for rc, state in ended:
        print(f"  rc {rc}: {state}")
    print(f"the last stream: {field(last, 'state:')}")
    for name in ("late (>1 ms):", "host paused:", "timing:"):
        if field(last, name):
            print(f"  {name} {field(last, name)}")
    print(f"array: {report['frames']} frames, sequence gaps {report['seq_gaps']}, watchdog trips "
          f"{report['watchdog_trips']}, timed late {report['timed_late']}")  # fmt: skip


def cmd_socket(args, folder: Path) -> None:
    emu = Emulator(folder, "socket", *([] if args.pty else ["--socket"]))
    proc = start_stream(emu.path, "--seconds", str(args.seconds), "--rate", str(args.rate))
    rc, out, _ = end_stream_after(proc, args.seconds + 30)
    report, _ = emu.finish()
    print(f"stream rc {rc}; timing: {field(out, 'timing:')}")
    print(f"array: {report['frames']} frames played, timed late {report['timed_late']}, queue "
          f"full {report['timed_full']}")  # fmt: skip


def end_stream_after(proc, timeout_s):
    out, err = proc.communicate(timeout=timeout_s)
    return proc.returncode, out, err


def timed_lines(err: str) -> list[str]:
    return [line for line in err.splitlines() if "timed" in line or "frames for now" in line]


def cmd_delayed(args, folder: Path) -> None:
    emu = Emulator(folder, "delayed", "--socket")
    proxy = Proxy(emu.address)
    proc = start_stream(proxy.url, "--seconds", str(args.seconds))
    time.sleep(args.delay_after)  # the start-up burst answered in time, then every reply held
    proxy.down_delay_s = args.delay_ms / 1e3
    rc, out, err = end_stream_after(proc, args.seconds + 30)
    proxy.close()
    report, _ = emu.finish()
    print(f"replies held {args.delay_ms:g} ms: stream rc {rc}; timing: {field(out, 'timing:')}")
    print(f"array: {report['frames']} frames played, timed late {report['timed_late']}, queue "
          f"full {report['timed_full']}")  # fmt: skip
    for line in timed_lines(err)[:6]:
        print("  " + line)


def first_lit(log: list, after: float) -> float | None:
    for t, _, lit in log:
        if t >= after and lit:
            return t
    return None


def cmd_reset(args, folder: Path) -> None:
    first = Emulator(folder, "before", "--socket")
    proxy = Proxy(first.address)
    proc = start_stream(proxy.url, "--seconds", str(args.seconds))
    time.sleep(args.reset_at - 2.0)
    second = Emulator(folder, "after", "--socket")  # a fresh array: its clock starts now
    time.sleep(2.0)
    reset = time.monotonic()
    proxy.swap(second.address)
    rc, out, err = end_stream_after(proc, args.seconds + 30)
    proxy.close()
    first.finish()
    report, log = second.finish()
    lit = first_lit(log, reset)
    dark = "never lit again" if lit is None else f"{(lit - reset) * 1e3:.0f} ms"
    print(f"array reset {args.reset_at:g} s in: dark for {dark}; the new array played "
          f"{report['frames']} frames, queue full {report['timed_full']}, late "
          f"{report['timed_late']}")  # fmt: skip
    print(f"stream rc {rc}; timing at the end: {field(out, 'timing:')}")
    for line in timed_lines(err)[-4:]:
        print("  " + line)


def cmd_reconnect(args, folder: Path) -> None:
    first = Emulator(folder, "before", "--socket")
    proxy = Proxy(first.address)
    proc = start_stream(proxy.url, "--seconds", str(args.seconds), "--reconnect")
    time.sleep(args.reconnect_at - 2.0)
    second = Emulator(folder, "after", "--socket")
    time.sleep(2.0)
    with proxy._lock:
        proxy.upstream = second.address
    cut = time.monotonic()
    proxy.drop_client()
    rc, _, err = end_stream_after(proc, args.seconds + 30)
    proxy.close()
    first.finish()
    report, log = second.finish()
    hello = next((t for t, e in report["events"] if e.startswith("answered")), None)
    hello = None if hello is None else report["started_monotonic"] + hello
    lit = first_lit(log, cut)
    print(
        f"link cut {args.reconnect_at:g} s in; the fresh array answered its hello "
        f"{(hello - cut) * 1e3:.0f} ms later"
        if hello
        else "no hello on the fresh array"
    )
    if lit is None:
        print("  the fresh array never played a lit frame")
    else:
        print(
            f"  first lit frame played {(lit - cut) * 1e3:.0f} ms after the cut"
            + (f" ({(lit - hello) * 1e3:.0f} ms after the hello)" if hello else "")
        )
    print(f"  the fresh array: {report['frames']} frames, queue full {report['timed_full']}, "
          f"late {report['timed_late']}; stream rc {rc}")  # fmt: skip
    for line in timed_lines(err)[-3:]:
        print("  " + line)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("stalls")
    p.add_argument("--stalls", type=int, default=40)
    p.add_argument("--socket", action="store_true")
    p.add_argument("--seed", type=int, default=31)
    p = sub.add_parser("socket")
    p.add_argument("--seconds", type=float, default=25.0)
    p.add_argument("--rate", type=float, default=300.0)
    p.add_argument("--pty", action="store_true", help="a pseudo-terminal instead, to compare")
    p = sub.add_parser("delayed")
    p.add_argument("--seconds", type=float, default=24.0)
    p.add_argument("--delay-ms", type=float, default=300.0)
    p.add_argument("--delay-after", type=float, default=3.0)
    p = sub.add_parser("reset")
    p.add_argument("--seconds", type=float, default=24.0)
    p.add_argument("--reset-at", type=float, default=16.0)
    p = sub.add_parser("reconnect")
    p.add_argument("--seconds", type=float, default=16.0)
    p.add_argument("--reconnect-at", type=float, default=8.0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        globals()[f"cmd_{args.command}"](args, Path(folder))


if __name__ == "__main__":
    main()
