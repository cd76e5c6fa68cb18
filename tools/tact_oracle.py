"""This tool's rendering of ``.tact`` files beside bHaptics' own compiled frames.

Usage::

    python tools/tact_oracle.py FOLDER [--methods CT,MM,AS,...] [--markdown]

Reads every ``*.tact`` file under FOLDER (recursively) that carries both forms, the Designer
project and the compiled ``feedback`` frames, and compares, position by position, the project
played on the position's own motors (the vest's 4 x 5 per side as a grid, motor ``i`` on its
cell; ``tactile_core.files.tact.matching_layout``) with bHaptics' frames at bHaptics' frame
times:

- positions holding dots only (``DOT_MODE``): frames equal in every motor, frames off by at most
  1 (of 100) in some motor, and frames off by more;
- positions holding moving paths only (``PATH_MODE``), per method: the mean absolute error in
  motor value (0..100) over all motors of the frames either side lights and over the motors
  either side lights, and the share of those frames within +-5 in every motor.

Files with the same bytes count once. Positions holding both, and paths that are single held
points only (their compiled frames are empty in every such file), are counted and left out.
Prints a table (``--markdown``: the table docs/tact.md carries).
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from pathlib import Path

import numpy as np

from tactile_core.files.tact import TactError, compare_compiled, read_tact
from tactile_core.rendering.methods import method_names

METHODS = ("CT", "MM", "AS", "IM", "EN", "PK", "RO", "GS", "VRCH", "BA", "TB")


def collect(folder: Path):
    """Distinct files carrying both forms, read in the project form: ``[(path, TactFile)]``,
    and how many files were read, refused or carried one form only."""
    seen, files, counts = set(), [], {"read": 0, "refused": 0, "one form": 0, "same bytes": 0}
    for path in sorted(folder.rglob("*.tact")):
        digest = hashlib.sha256(path.read_bytes()).hexdigest()
        if digest in seen:
            counts["same bytes"] += 1
            continue
        seen.add(digest)
        try:
            file = read_tact(path)
        except TactError:
            counts["refused"] += 1
            continue
        counts["read"] += 1
        if file.compiled is None or file.form != "project":
            counts["one form"] += 1
            continue
        files.append((path, file))
    return files, counts


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path)
    parser.add_argument("--methods", default=",".join(METHODS))
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args(argv)
    methods = [m.strip().upper() for m in args.methods.split(",") if m.strip()]
    unknown = [m for m in methods if m not in method_names()]
    if unknown:
        parser.error(f"unknown methods: {', '.join(unknown)}")
    files, counts = collect(args.folder)
    dots = {"positions": 0, "frames": 0, "exact": 0, "off by 1": 0, "more": 0, "files": set()}
    paths: dict = {m: {"err": [], "lit": [], "within": [], "frames": 0} for m in methods}
    path_positions, path_files, mixed = 0, set(), 0
    for path, file in files:
        for c in compare_compiled(file, methods):
            if c.kind == "mixed":
                mixed += 1 if c.method == methods[0] else 0
                continue
            if c.kind == "dots":
                worst = c.within
                dots["positions"] += 1
                dots["files"].add(path)
                dots["frames"] += c.frames
                dots["exact"] += int((worst == 0).sum())
                dots["off by 1"] += int((worst == 1).sum())
                dots["more"] += int((worst > 1).sum())
                continue
            on = c.active()
            row = paths[c.method]
            row["err"].append(np.abs(c.ours[on] - c.theirs[on]))
            lit = (c.ours[on] > 0) | (c.theirs[on] > 0)
            row["lit"].append(np.abs(c.ours[on] - c.theirs[on])[lit])
            row["within"].append(c.within[on] <= 5)
            row["frames"] += int(on.sum())
            if c.method == methods[0]:
                path_positions += 1
                path_files.add(path)
    n_files = len({p for p, _ in files})
    print(f"{counts['read']} distinct files read ({counts['same bytes']} more with the same "
          f"bytes, {counts['refused']} refused), {n_files} carry both forms; "
          f"{mixed} positions with both paths and dots left out")  # fmt: skip
    bar = "|" if args.markdown else ""
    print()
    print(f"{bar} DOT_MODE | files | positions | frames | equal | off by 1 | off by more {bar}")
    if args.markdown:
        print("|---|---|---|---|---|---|---|")
    print(f"{bar} dots only | {len(dots['files'])} | {dots['positions']} | {dots['frames']} | "
          f"{dots['exact']} | {dots['off by 1']} | {dots['more']} {bar}")  # fmt: skip
    print()
    print(f"{bar} PATH_MODE ({len(path_files)} files, {path_positions} positions) | frames | "
          f"mean abs. error, all motors | mean abs. error, lit motors | frames within +-5 "
          f"{bar}")  # fmt: skip
    if args.markdown:
        print("|---|---|---|---|---|")
    for method in methods:
        row = paths[method]
        if not row["err"]:
            print(f"{bar} {method} | 0 | - | - | - {bar}")
            continue
        err = float(np.concatenate([e.ravel() for e in row["err"]]).mean())
        lit = float(np.concatenate(row["lit"]).mean())
        share = float(np.concatenate(row["within"]).mean())
        print(f"{bar} {method} | {row['frames']} | {err:.2f} | {lit:.1f} | {100 * share:.1f} % "
              f"{bar}")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
