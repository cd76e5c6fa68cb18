"""Resume and analyse a participant whose results CSV is huge; report the peak memory.

Usage::

    python tools/big_results.py [--sizes 30 50 500] [--limit-gb 3]

For each size (MB) it writes a participant folder whose ``exp2.csv`` starts with a complete,
valid run of Experiment 2 and goes on with copies of its rows up to that size, then, each in a
child process under an address-space limit, resumes Experiment 2 and runs ``tactile analyze``.
It prints the outcome (the first line of the message, or the exception), the time and the
child's peak resident memory (``ru_maxrss``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

RESUME = textwrap.dedent(
    """
    import resource, sys
    limit = int(sys.argv[2])
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    from tactile_core.experiments import Experiment2, open_session
    try:
        Experiment2(open_session(sys.argv[1], "p01")).close()
        print("resumed")
    except ValueError as exc:
        print(f"refused: {exc}")
    """
)
ANALYZE = textwrap.dedent(
    """
    import resource, sys
    limit = int(sys.argv[2])
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    from tactile_core.cli import main
    sys.exit(main(["analyze", sys.argv[1]]))
    """
)


def build(root: Path, megabytes: int) -> Path:
    """A results folder with participant p01's exp2.csv of about ``megabytes`` MB."""
    from tactile_core.experiments import Experiment2, SimulatedParticipant, open_session

    runner = Experiment2(open_session(root, "p01", seed=1, index=0))
    SimulatedParticipant(seed=1).run(runner)
    runner.close()
    path = root / "participant-p01" / "exp2.csv"
    data = path.read_bytes()
    rows = data.split(b"\n", 1)[1]
    target = megabytes << 20
    with path.open("ab") as f:
        block = rows * max(1, (4 << 20) // len(rows))
        while f.tell() < target:
            f.write(block[: target - f.tell()])
    return path


def run(script: str, root: Path, limit: int) -> tuple[str, float, float]:
    """Run ``script`` on ``root``; (first line of its output, seconds, peak RSS in MB)."""
    start = time.monotonic()
    proc = subprocess.Popen(
        [sys.executable, "-c", script, str(root), str(limit)],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
    )  # fmt: skip
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    seconds = time.monotonic() - start
    lines = [line for line in out.splitlines() if line.strip()]
    if "Traceback" in out:
        first = "traceback: " + lines[-1]
    else:
        first = next((line for line in lines if "exp2.csv" in line or "refused" in line
                      or "resumed" in line), lines[0] if lines else "")  # fmt: skip
    first = first.replace(str(root), "…")
    return f"exit {proc.returncode}: {first[:150]}", seconds, usage.ru_maxrss / 1024


def main(argv=None) -> int:
    """Build each file, resume and analyse it, print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[30, 50, 500])
    parser.add_argument("--limit-gb", type=float, default=3.0)
    args = parser.parse_args(argv)
    limit = int(args.limit_gb * (1 << 30))
    print("| exp2.csv | command | outcome | seconds | peak RSS (MB) |")
    print("|---|---|---|---|---|")
    for size in args.sizes:
        root = Path(tempfile.mkdtemp(prefix=f"big{size}-"))
        try:
            build(root, size)
            for label, script in (("resume", RESUME), ("analyze", ANALYZE)):
                outcome, seconds, rss = run(script, root, limit)
                print(f"| {size} MB | {label} | {outcome} | {seconds:.1f} | {rss:.0f} |",
                      flush=True)  # fmt: skip
        finally:
            shutil.rmtree(root)
    return 0


if __name__ == "__main__":
    sys.exit(main())
