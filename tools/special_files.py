"""Put special files in a participant's folder and see what resuming and analysing do.

Usage::

    python tools/special_files.py [--timeout 10]

For each file of a participant's folder (``exp2.csv``, ``exp2.csv.torn``, ``.lock``,
``session.json``, ``correction.json``) and each thing that is not a regular file inside the
folder (a symbolic link to ``/dev/zero``, a FIFO, a folder, a symbolic link to a regular file
outside the folder holding what the file would hold), it resumes Experiment 2 (one answer, then
close) and runs ``tactile analyze``, each in a child process with a time limit and a 3 GB
address-space limit, and sorts the outcome:

- ``refused``: the run stopped with a message naming the file (resume), or the analysis went on
  and named the file as left out (analyze);
- ``hung``: no end within the time limit;
- ``crashed``: a traceback (MemoryError, IsADirectoryError, ...);
- ``accepted``: the run went on using the file (``written through`` when the file outside the
  folder changed);
- ``not read``: the analysis ended normally without opening the file (it reads only the CSVs
  and ``session.json``).

Prints a table and the totals; exits 1 unless every case is refused (or, for the analysis,
not read).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

RESUME = textwrap.dedent(
    """
    import resource, sys
    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
    from tactile_core.experiments import Experiment2, SimulatedParticipant, open_session
    try:
        runner = Experiment2(open_session(sys.argv[1], "p01"))
        runner.answer(SimulatedParticipant(seed=5).respond(runner.current))
        runner.close()
    except ValueError as exc:  # SessionError is a ValueError
        print(f"refused: {exc}")
        sys.exit(2)
    print("ok")
    """
)
ANALYZE = textwrap.dedent(
    """
    import resource, sys
    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
    from tactile_core.cli import main
    sys.exit(main(["analyze", sys.argv[1]]))
    """
)
MEMBERS = ("exp2.csv", "exp2.csv.torn", ".lock", "session.json", "correction.json")
READ_BY_ANALYSIS = ("exp2.csv", "session.json")
KINDS = ("link to /dev/zero", "FIFO", "folder", "link outside")


def _reference(root: Path) -> dict:
    """A participant with 40 answers of Experiment 2, a torn last row and a correction."""
    from tactile_core.experiments import Experiment2, SimulatedParticipant, open_session

    runner = Experiment2(open_session(root, "p01", seed=7, index=0))
    participant = SimulatedParticipant(seed=5)
    for _ in range(40):
        runner.answer(participant.respond(runner.current))
    runner.close()
    folder = root / "participant-p01"
    data = (folder / "exp2.csv").read_bytes()
    (folder / "exp2.csv").write_bytes(data[:-7])  # a torn last row: resuming writes .torn
    correction = {"format": "tactile-correction", "version": 1, "mu": 0.3, "gamma": 0.6}
    (folder / "correction.json").write_text(json.dumps(correction))
    contents = {name: (folder / name).read_bytes() for name in ("exp2.csv", "session.json",
                                                                  "correction.json")}  # fmt: skip
    contents["exp2.csv.torn"] = b""
    contents[".lock"] = b""
    return contents


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else ""


def case(member: str, kind: str, template: Path, contents: dict, work: Path, timeout: float):
    """One member replaced by one kind of special file; the outcome of resume and analyze."""
    root = work / f"{member}-{kind}".replace(" ", "_").replace("/", "_")
    shutil.copytree(template, root, symlinks=True)
    target = root / "participant-p01" / member
    target.unlink(missing_ok=True)
    outside = root.parent / f"{root.name}-outside"
    outside.write_bytes(contents[member])
    if kind == "link to /dev/zero":
        target.symlink_to("/dev/zero")
    elif kind == "FIFO":
        os.mkfifo(target)
    elif kind == "folder":
        target.mkdir()
    else:
        target.symlink_to(outside)
    out = {}
    for label, script in (("resume", RESUME), ("analyze", ANALYZE)):
        before = _digest(outside)
        try:
            proc = subprocess.run([sys.executable, "-c", script, str(root)], capture_output=True,
                                  text=True, timeout=timeout)  # fmt: skip
        except subprocess.TimeoutExpired:
            out[label] = "hung"
            continue
        text = proc.stdout + proc.stderr
        if "Traceback" in text:
            last = [line for line in text.splitlines() if line.strip()][-1]
            out[label] = "crashed: " + last[:80]
        elif (label == "resume" and proc.returncode == 2 and member in text) or (
            label == "analyze" and proc.returncode in (0, 2) and f"{member}:" in text
        ):
            out[label] = "refused"
        elif _digest(outside) != before:
            out[label] = "written through"
        elif label == "analyze" and member not in READ_BY_ANALYSIS and proc.returncode == 0:
            out[label] = "not read"
        else:
            out[label] = f"accepted (exit {proc.returncode})"
    return out


def main(argv=None) -> int:
    """Run every case and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timeout", type=float, default=10.0)
    args = parser.parse_args(argv)
    counts: dict = {}
    print("| file | in its place | resume | analyze |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        template = work / "template"
        contents = _reference(template)
        for member in MEMBERS:
            for kind in KINDS:
                out = case(member, kind, template, contents, work, args.timeout)
                print(f"| `{member}` | {kind} | {out['resume']} | {out['analyze']} |", flush=True)
                for label, outcome in out.items():
                    key = (label, outcome.split(":")[0].split(" (")[0])
                    counts[key] = counts.get(key, 0) + 1
    total = len(MEMBERS) * len(KINDS)
    for label in ("resume", "analyze"):
        cells = ", ".join(f"{o} {n}" for (lb, o), n in sorted(counts.items()) if lb == label)
        print(f"{label}: {cells} (of {total})")
    fine = sum(n for (lb, o), n in counts.items() if o in ("refused", "not read"))
    return 0 if fine == 2 * total else 1


if __name__ == "__main__":
    sys.exit(main())
