"""Race writers for one participant's lock and count how many won each race.

Usage::

    python tools/lock_races.py [--races 200] [--writers 2 4] [--kinds fresh stale]

Each writer is a separate process that waits for "go", then takes
:class:`~tactile_core.experiments.results.ParticipantLock` on the same participant folder and
keeps it until every writer of the round has answered, so two holders at once cannot hide
behind a quick release. A round passes when exactly one writer holds the lock and the others
were refused with :class:`~tactile_core.experiments.results.SessionError` (anything else
raised counts as an error). ``fresh``: the folder has no ``.lock``; ``stale``: it holds the
lock file of a holder that was killed (a process that no longer runs, its record left behind);
``empty``: it holds an empty ``.lock`` (as one just created, or cut short by a crash).

``--churn N``: the writers then take and release one lock N times each, all at once (a
release removes the file while others open it): a holder that finds another holder counts as
an overlap.

Prints one line per (kind, writers): rounds, rounds won by exactly one writer, rounds with
two or more holders, rounds with none, and errors; exits 1 if any round failed.
"""

from __future__ import annotations

import argparse
import json
import socket
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

WORKER = textwrap.dedent(
    """
    import os, sys
    from tactile_core.experiments.results import ParticipantLock, SessionError
    lock = None
    for line in sys.stdin:
        command, _, arg = line.strip().partition(" ")
        if command == "go":
            try:
                lock = ParticipantLock(arg)
                print("won", flush=True)
            except SessionError:
                print("refused", flush=True)
            except Exception as exc:
                print(f"error {type(exc).__name__}: {exc}".replace("\\n", " "), flush=True)
        elif command == "churn":  # take and release the lock over and over
            folder, n = arg.rsplit(" ", 1)
            won = overlaps = 0
            for _ in range(int(n)):
                try:
                    held = ParticipantLock(folder)
                except SessionError:
                    continue
                won += 1
                try:  # a second holder at this moment would find the mark in place
                    os.close(os.open(f"{folder}/held", os.O_CREAT | os.O_EXCL | os.O_WRONLY))
                except FileExistsError:
                    overlaps += 1
                else:
                    os.unlink(f"{folder}/held")
                held.release()
            print(f"churned {won} {overlaps}", flush=True)
        elif command == "release":
            if lock is not None:
                lock.release()
                lock = None
            print("released", flush=True)
    """
)


def _stale_record(dead_pid: int) -> bytes:
    record = {"host": socket.gethostname(), "pid": dead_pid, "process_start": "1",
              "since": "2025-01-01T00:00:00"}  # fmt: skip
    return json.dumps(record).encode()


def race(kind: str, writers: int, races: int, root: Path) -> dict:
    """Run ``races`` rounds of ``writers`` processes; count the outcomes."""
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()  # its PID now names no process
    procs = [
        subprocess.Popen([sys.executable, "-c", WORKER], stdin=subprocess.PIPE,
                         stdout=subprocess.PIPE, text=True, bufsize=1)
        for _ in range(writers)
    ]  # fmt: skip
    counts = {"rounds": 0, "one": 0, "several": 0, "none": 0, "errors": 0, "examples": []}
    try:
        for i in range(races):
            folder = root / f"{kind}-{writers}-{i}" / "participant-p01"
            folder.mkdir(parents=True)
            if kind == "stale":
                (folder / ".lock").write_bytes(_stale_record(dead.pid))
            elif kind == "empty":
                (folder / ".lock").write_bytes(b"")
            for p in procs:
                p.stdin.write(f"go {folder}\n")
            for p in procs:
                p.stdin.flush()
            answers = [p.stdout.readline().strip() for p in procs]
            for p in procs:
                p.stdin.write("release\n")
                p.stdin.flush()
            for p in procs:
                assert p.stdout.readline().strip() == "released"
            won = answers.count("won")
            errors = [a for a in answers if a.startswith("error")]
            counts["rounds"] += 1
            counts["errors"] += len(errors)
            key = "one" if won == 1 else "several" if won > 1 else "none"
            counts[key] += 1
            if (won != 1 or errors) and len(counts["examples"]) < 3:
                counts["examples"].append(answers)
    finally:
        for p in procs:
            p.stdin.close()
            p.wait(30)
            p.stdout.close()
    return counts


def churn(writers: int, attempts: int, root: Path) -> dict:
    """``writers`` processes each take and release one lock ``attempts`` times at once; count
    the times a holder found another holder (an overlap)."""
    folder = root / f"churn-{writers}" / "participant-p01"
    folder.mkdir(parents=True)
    procs = [
        subprocess.Popen([sys.executable, "-c", WORKER], stdin=subprocess.PIPE,
                         stdout=subprocess.PIPE, text=True, bufsize=1)
        for _ in range(writers)
    ]  # fmt: skip
    try:
        for p in procs:
            p.stdin.write(f"churn {folder} {attempts}\n")
        for p in procs:
            p.stdin.flush()
        answers = [p.stdout.readline().split() for p in procs]
    finally:
        for p in procs:
            p.stdin.close()
            p.wait(60)
            p.stdout.close()
    return {"attempts": writers * attempts, "won": sum(int(a[1]) for a in answers),
            "overlaps": sum(int(a[2]) for a in answers)}  # fmt: skip


def main(argv=None) -> int:
    """Run the races and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--races", type=int, default=200)
    parser.add_argument("--writers", type=int, nargs="+", default=[2, 4])
    parser.add_argument(
        "--churn",
        type=int,
        default=2000,
        help="attempts per writer taking and releasing one lock (0: none)",
    )
    parser.add_argument("--kinds", nargs="+", default=["fresh", "stale", "empty"])
    args = parser.parse_args(argv)
    failed = False
    print("| lock | writers | races | one writer | two or more | none | errors |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for kind in args.kinds:
            for writers in args.writers:
                c = race(kind, writers, args.races, Path(tmp))
                print(f"| {kind} | {writers} | {c['rounds']} | {c['one']} | {c['several']} | "
                      f"{c['none']} | {c['errors']} |", flush=True)  # fmt: skip
                for example in c["examples"]:
                    print(f"  e.g. {example}", file=sys.stderr)
                failed |= c["one"] != c["rounds"] or c["errors"] > 0
        if args.churn:
            print()
            print("| churn: writers | attempts | held | held while another held |")
            print("|---|---|---|---|")
            for writers in args.writers:
                c = churn(writers, args.churn, Path(tmp))
                print(f"| {writers} | {c['attempts']} | {c['won']} | {c['overlaps']} |")
                failed |= c["overlaps"] > 0
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
