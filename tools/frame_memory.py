"""How much memory the recorder and the emulator hold for an hour (or more) of frames.

Usage::

    python tools/frame_memory.py [--hours 1 2] [--rate 300]

Each frame is what a stream at ``--rate`` delivers: its time, a sequence number and 30 fresh
level bytes (a new ``bytes`` object per frame, as the link delivers them). It feeds the
recorder (``tactile stream --record``) and the emulator (``tactile emulate``) the frames of
each duration and prints the memory they hold afterwards (``tracemalloc``).
"""

from __future__ import annotations

import argparse
import tracemalloc

import numpy as np

from tactile_core.device.emulator import Emulator
from tactile_core.device.profile import default_profile
from tactile_core.files.frames import Recorder


class _Frame:
    __slots__ = ("levels", "seq")

    def __init__(self, seq, levels):
        self.seq, self.levels = seq, levels


def held_mb(feed, n: int, patterns: list[bytes]) -> float:
    """Memory (MB) held after ``feed(i, levels)`` for ``n`` frames."""
    tracemalloc.start()
    sink = feed(n, patterns)
    current, _ = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    del sink
    return current / 1e6


def _recorder(n, patterns):
    recorder = Recorder(default_profile().array)
    for i in range(n):
        recorder(i / 300.0, i % 256, bytes(bytearray(patterns[i % 256])))
    return recorder


def _emulator(n, patterns):
    emulator = Emulator(default_profile(), 300.0)
    emulator.started = 0.0
    for i in range(n):
        emulator._log([_Frame(i % 256, bytes(bytearray(patterns[i % 256])))], i / 300.0)
    return emulator


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hours", type=float, nargs="+", default=[1.0, 2.0])
    parser.add_argument("--rate", type=float, default=300.0)
    args = parser.parse_args()
    rng = np.random.default_rng(1)
    patterns = [rng.integers(0, 23, 30, dtype=np.uint8).tobytes() for _ in range(256)]
    print("| hours | frames | recorder MB | emulator MB |")
    print("|---|---|---|---|")
    for hours in args.hours:
        n = int(args.rate * 3600 * hours)
        rec = held_mb(_recorder, n, patterns)
        emu = held_mb(_emulator, n, patterns)
        print(f"| {hours:g} | {n:,} | {rec:.1f} | {emu:.1f} |")


if __name__ == "__main__":
    main()
