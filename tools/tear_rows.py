"""Tear a results file at random and append junk; see whether resuming repairs it.

Usage::

    python tools/tear_rows.py [--count 250] [--seed 1]

A run of Experiment 2 (60 answers) is cut at a random byte and followed by 0-64 random bytes
(as a crash in the middle of a write, then garbage from the file system), ``--count`` times.
Each torn file is resumed; the outcome:

- ``repaired``: the runner resumed, the torn bytes moved to ``exp2.csv.torn``, and every row it
  kept is a row of the original file, in order;
- ``refused``: resuming stopped with a message (then the file is left as it was for a person to
  look at);
- ``wrong``: the runner resumed on rows that are not the original's.

Prints the counts; the cuts that land in the header are counted separately.
"""

from __future__ import annotations

import argparse
import random
import shutil
import sys
import tempfile
from pathlib import Path


def main(argv=None) -> int:
    """Tear, resume, count."""
    from tactile_core.experiments import Experiment2, SimulatedParticipant, open_session

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=250)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    rng = random.Random(args.seed)
    counts: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        template = Path(tmp) / "template"
        runner = Experiment2(open_session(template, "p01", seed=7))
        participant = SimulatedParticipant(seed=5)
        for _ in range(60):
            runner.answer(participant.respond(runner.current))
        runner.close()
        data = (template / "participant-p01" / "exp2.csv").read_bytes()
        header = data.index(b"\n") + 1
        lines = data.splitlines(keepends=True)
        for k in range(args.count):
            cut = rng.randrange(1, len(data))
            junk = bytes(rng.randrange(256) for _ in range(rng.randrange(65)))
            run = Path(tmp) / f"run{k}"
            shutil.copytree(template, run)
            path = run / "participant-p01" / "exp2.csv"
            path.write_bytes(data[:cut] + junk)
            where = "header" if cut < header else "rows"
            try:
                runner = Experiment2(open_session(run, "p01"))
                runner.close()
                kept = path.read_bytes().splitlines(keepends=True)
                outcome = "repaired" if kept == lines[: len(kept)] else "wrong"
            except ValueError:
                outcome = "refused"
            counts.setdefault(where, {}).setdefault(outcome, 0)
            counts[where][outcome] += 1
            shutil.rmtree(run)
    print("| cut in | tears | repaired | refused | wrong |")
    print("|---|---|---|---|---|")
    for where, c in sorted(counts.items()):
        print(f"| {where} | {sum(c.values())} | {c.get('repaired', 0)} | {c.get('refused', 0)} | "
              f"{c.get('wrong', 0)} |")  # fmt: skip
    return 1 if any(c.get("wrong") for c in counts.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
