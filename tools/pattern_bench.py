"""Measure patterns: how long a pattern file takes to load, and whether a big pattern streams
on time.

    python tools/pattern_bench.py load [--counts 1000,10000,100000]
    python tools/pattern_bench.py stream [--effects 10000] [--rate 300] [--seconds 60]

load: a file of N effects (a third each lines, dot taps and time-keyed paths of 8 points, spread
over 50 minutes), and one of N effects of one dot each (the smallest effect), written as compact
JSON; each in a fresh process, reporting the file's size, the time ``Pattern.load`` takes to
read it or refuse it (the best of three: 10^5 effects are more than ``MAX_EFFECTS``, and their
file more than ``MAX_PATTERN_BYTES``) and the peak of Python's allocations then
(``tracemalloc``, in a fourth run).

stream: a pattern of N effects of the same mix packed into ``--seconds``, played by
``tc.open_array("sim").play`` (which tabulates it first): the time to tabulate, then the
stream's own statistics over the play: frames sent, late (> 1 ms after the deadline) and
skipped deadlines; then a circle for as long on the same array by AS (4 tactors lit a frame)
and by GS at sigma 1.5 (22 lit, as dense as the pattern's frames), for what the machine does
to any stream and to one as dense. Numbers go into docs/patterns.md.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def effect_json(k: int, span_s: float, n: int) -> dict:
    start = round(span_s * k / n, 6)
    kind = k % 3
    if kind == 0:
        return {
            "track": k % 8,
            "start_s": start,
            "duration_s": 0.3,
            "shape": {"type": "line", "p0": [0.5, 0.5 + k % 5], "p1": [4.5, 5.5 - k % 5]},
        }
    if kind == 1:
        return {
            "track": k % 8,
            "start_s": start,
            "duration_s": 0.2,
            "repeat": 2,
            "envelope": [{"time_s": 0.0, "gain": 0.3}, {"time_s": 0.05, "gain": 1.0}],
            "dots": [{"at": k % 30, "intensity": 0.8, "start_s": 0.0, "duration_s": 0.08}],
        }
    points = [[0.5 + j * 0.5, 0.5 + (j * 7 + k) % 6 * 0.8] for j in range(8)]
    return {
        "track": k % 8,
        "start_s": start,
        "duration_s": 0.4,
        "method": "RO",
        "shape": {
            "type": "timed_path",
            "points": points,
            "times_s": [j * 0.05 for j in range(8)],
            "intensities": [1.0] * 8,
            "pattern": "CONST_TDM",
            "fade": "NONE",
        },
    }


def write_file(path: Path, n: int, span_s: float, small: bool = False) -> None:
    """N effects of the mix; ``small``: each the smallest effect there is (one dot)."""
    if small:
        effects = [{"dots": [{"at": k % 30}]} for k in range(n)]
    else:
        effects = [effect_json(k, span_s, n) for k in range(n)]
    data = {
        "format": "tactile-pattern",
        "version": 1,
        "name": f"{n} effects",
        "combine": "max",
        "effects": effects,
    }
    path.write_text(json.dumps(data, separators=(",", ":")))


LOAD_CHILD = """
import sys, time, tracemalloc
from tactile_core.files.pattern import Pattern, PatternError
path = sys.argv[1]


def load():
    try:
        return f"loaded {len(Pattern.load(path).effects)} effects"
    except PatternError as exc:
        return "refused: " + str(exc).split(": ", 1)[1][:70]


took = []
for _ in range(3):  # the best of three, then once more for the allocations
    start = time.perf_counter()
    what = load()
    took.append(time.perf_counter() - start)
tracemalloc.start()
load()
peak = tracemalloc.get_traced_memory()[1]
print(f"{min(took):.3f}\\t{peak / 1e6:.1f}\\t{what}")
"""


def cmd_load(args) -> None:
    counts = [int(c) for c in args.counts.split(",")]
    print("| effects | file (MB) | load (s) | peak allocations (MB) | result |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for n in counts:
            for small in (False, True):
                path = Path(folder) / f"p{n}.json"
                write_file(path, n, 3000.0, small)
                out = subprocess.run(
                    [sys.executable, "-c", LOAD_CHILD, str(path)],
                    check=True,
                    capture_output=True,
                    text=True,
                ).stdout.strip()
                took, peak, what = out.split("\t")
                size = path.stat().st_size / 1e6
                kind = "one dot each" if small else "the mix"
                print(f"| {n} ({kind}) | {size:.2f} | {took} | {peak} | {what} |")


def cmd_stream(args) -> None:
    import tactile_core as tc
    from tactile_core.files.pattern import Pattern

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "big.json"
        write_file(path, args.effects, args.seconds - 0.5)
        pattern = Pattern.load(path)
    with tc.open_array("sim", rate_hz=args.rate) as array:
        live = pattern.live("AS", array.profile.layout, tc.Sampling(args.rate), 0.33, 0.7)
        start = time.perf_counter()
        live.precompute()
        tabulated = time.perf_counter() - start
        before = array.streamer.stats
        shown = array.play(pattern, "AS", mu=0.33, gamma=0.7, wait=True)
        after = array.streamer.stats
        assert not shown.interrupted
        # the same time on the same array, a circle by AS (4 tactors lit) and by GS at
        # sigma 1.5 (22 lit): what the machine does to any stream, and to one as dense
        rows = []
        for method in ("AS", "GS:sigma=1.5"):
            middle = array.streamer.stats
            array.play(tc.Circle((2.5, 3.0), 2.0), method, duration_s=pattern.duration_s)
            last = array.streamer.stats
            rows.append((method, middle, last))
    _, frames = pattern.frames("AS", tc.Grid(5, 6), rate_hz=args.rate, mu=0.33, gamma=0.7)
    lit = (frames.reshape(len(frames), -1) > 0).sum(axis=1).mean()
    print(
        "| played | duration (s) | tactors lit a frame | tabulate (s) | frames | late (>1 ms) "
        "| skipped deadlines | busiest frame, scalar path (ms) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    print(
        f"| pattern of {args.effects} effects | {pattern.duration_s:.1f} | {lit:.1f} | "
        f"{tabulated:.1f} | {after.frames - before.frames} | {after.late - before.late} | "
        f"{after.skipped - before.skipped} | {live.busiest_frame_s() * 1e3:.2f} |"
    )
    for method, middle, last in rows:
        shown_lit = 4.0 if method == "AS" else 22.0
        print(
            f"| a circle, {method} | {pattern.duration_s:.1f} | {shown_lit:.0f} | - | "
            f"{last.frames - middle.frames} | {last.late - middle.late} | "
            f"{last.skipped - middle.skipped} | - |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="part", required=True)
    p = sub.add_parser("load")
    p.add_argument("--counts", default="1000,10000,100000")
    p.set_defaults(func=cmd_load)
    p = sub.add_parser("stream")
    p.add_argument("--effects", type=int, default=10_000)
    p.add_argument("--rate", type=float, default=300.0)
    p.add_argument("--seconds", type=float, default=60.0)
    p.set_defaults(func=cmd_stream)
    args = parser.parse_args()
    args.func(args)


if __name__ == "__main__":
    main()
