"""Corrupt one field of one recorded row and see whether resuming builds on it.

Usage::

    python tools/corrupt_rows.py [--count 400] [--seed 1]

Records part of a run of each experiment (Experiments 1-3, the calibration, the correction
tuning) with simulated participants, then, ``--count`` times, changes one field of one complete
row (a 0/1 flag flipped, a number scaled, a choice swapped for another, a field blanked, a
participant renamed; the measured fields ``rt_s``, ``time``, the stream's health and
Experiment 1's ``switches`` given a value that is not a measurement) and resumes the run. The
outcome of each:

- ``refused at the row``: the resume stopped with ``file:row`` of the corrupted row (and the
  field that disagrees: the one changed, or one that no longer follows from it, such as
  ``correct`` after a changed ``answer``);
- ``refused elsewhere``: it stopped, naming another row;
- ``set aside``: the row was moved to ``.torn`` as if a crash had torn it;
- ``built upon``: the resume went on from the corrupted row.

Prints the counts per experiment and in total; exits 1 if any corruption was built upon or set
aside.
"""

from __future__ import annotations

import argparse
import csv
import io
import random
import shutil
import sys
import tempfile
from pathlib import Path

MEASURED = {"rt_s", "time", "late_frames", "skipped_frames", "link_errors", "presentations",
            "switches"}  # fmt: skip
PLAN = {"exp1": 20, "exp2": 70, "exp3": 30, "calibration": 60, "correction": 60}


def _answerer(name: str, seed: int):
    from tactile_core.experiments import SimulatedObserver, SimulatedParticipant

    if name == "correction":
        return SimulatedObserver(0.25, 1.0, seed=seed).respond
    return SimulatedParticipant(seed=seed).respond


def record(root: Path) -> dict:
    """Part of a run of every experiment, for participant p01: ``{name: (header, rows)}``."""
    from tactile_core.experiments import RUNNERS, open_session

    out = {}
    for name, n in PLAN.items():
        runner = RUNNERS[name](open_session(root, "p01", seed=7, index=1))
        respond = _answerer(name, 5)
        while runner.done < n and not runner.finished:
            if runner.current.kind == "prepare":
                for key in (1, 2, 3, 4, 2):
                    runner.select(key)
            runner.answer(respond(runner.current), rt_s=0.8,
                          health={"late_frames": 0, "skipped_frames": 0, "link_errors": 0,
                                  "presentations": 1})  # fmt: skip
        runner.close()
        text = (root / "participant-p01" / f"{name}.csv").read_text()
        rows = list(csv.reader(io.StringIO(text)))
        out[name] = (rows[0], rows[1:])
    return out


def corrupt(field: str, value: str, rng: random.Random) -> str:
    """A different value for ``field``."""
    if field in MEASURED:
        return rng.choice(["abc", "-1", "nan", "1e999", " 1"])
    if field == "participant":
        return rng.choice(["p02", ""])
    if value in ("0", "1"):
        return rng.choice(["1" if value == "0" else "0", ""])
    options = {"direction": ("up", "down", "left", "right"), "answer": ("up", "down", "left",
               "right", "circle", "square", "yes", "no", "1", "2"),
               "shape": ("circle", "square"), "method": ("CT", "MM", "AS", "IM")}  # fmt: skip
    if field in options and value in options[field]:
        return rng.choice([o for o in options[field] if o != value] + [""])
    try:
        number = float(value)
    except ValueError:
        return rng.choice(["", value + "x"]) if value else "1"
    return rng.choice([f"{number * 1.5 + 0.01:.6g}", ""])


def resume(name: str, folder: Path) -> tuple[str, str]:
    """Resume ``name`` on ``folder``'s results; ``(outcome, message)``."""
    from tactile_core.experiments import RUNNERS, open_session
    from tactile_core.experiments.results import SessionError

    try:
        runner = RUNNERS[name](open_session(folder, "p01"))
    except (SessionError, ValueError) as exc:
        return "refused", str(exc)
    recovered = runner.recovered
    runner.close()
    return ("set aside", recovered) if recovered else ("built upon", "")


def main(argv=None) -> int:
    """Run the corruptions and print the counts."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=400)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--show", type=int, default=0, help="print this many messages")
    args = parser.parse_args(argv)
    rng = random.Random(args.seed)
    counts: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        template = work / "template"
        recorded = record(template)
        names = list(recorded)
        shown = 0
        for k in range(args.count):
            name = names[k % len(names)]
            header, rows = recorded[name]
            i = rng.randrange(len(rows))
            j = rng.randrange(len(header))
            new = corrupt(header[j], rows[i][j], rng)
            if new == rows[i][j]:
                new = new + "0"
            changed = [list(r) for r in rows]
            changed[i][j] = new
            out = io.StringIO()
            csv.writer(out, lineterminator="\n").writerows([header, *changed])
            run = work / f"run{k}"
            shutil.copytree(template, run)
            (run / "participant-p01" / f"{name}.csv").write_text(out.getvalue())
            outcome, message = resume(name, run)
            if outcome == "refused":
                here = f"{name}.csv:{i + 2}: " in message
                outcome = "refused at the row" if here else "refused elsewhere"
            if shown < args.show and outcome != "refused at the row":
                shown += 1
                print(f"  {name} row {i + 2} {header[j]} {rows[i][j]!r} -> {new!r}: {outcome} "
                      f"{message[:160]}", file=sys.stderr)  # fmt: skip
            counts.setdefault(name, {}).setdefault(outcome, 0)
            counts[name][outcome] += 1
            shutil.rmtree(run)
    outcomes = ("refused at the row", "refused elsewhere", "set aside", "built upon")
    print("| experiment | corruptions | " + " | ".join(outcomes) + " |")
    print("|---|---|" + "---|" * len(outcomes))
    total = {o: 0 for o in outcomes}
    for name, c in counts.items():
        print(f"| {name} | {sum(c.values())} | " + " | ".join(str(c.get(o, 0)) for o in outcomes)
              + " |")  # fmt: skip
        for o in outcomes:
            total[o] += c.get(o, 0)
    print(f"| all | {sum(total.values())} | " + " | ".join(str(total[o]) for o in outcomes) + " |")
    return 1 if total["built upon"] or total["set aside"] else 0


if __name__ == "__main__":
    sys.exit(main())
