"""Dump the renderer's outputs on a large varied set of cases, or compare against a dump.

A speed change to a method must not change what it renders. Before the change::

    python tools/render_reference.py dump /tmp/render-ref

and after it::

    python tools/render_reference.py compare /tmp/render-ref

The cases (about 100,000 frames per method spec, every built-in method and a few parameter
sets of each, on three grids): lines, circles, squares and polylines, open and closed, with
ends, centres and corners on tactor centres, on cell edges and anywhere (seeded); ``t`` from a
uniform grid that hits every shape's corners and keyframes and from random draws; free points
(``render_xy``) on the lattice of tactor centres, cell corners and edges and at random; single
points through ``render`` (the scalar path) and ``render_point`` (the live path). ``compare``
prints the largest absolute difference and the number of frames whose set of lit tactors
differs, per method spec, and exits 1 if any difference exceeds ``--tol`` (1e-15) or any set
of lit tactors differs.
"""

from __future__ import annotations

import argparse
import pathlib
import sys

import numpy as np

import tactile_core as tc
from tactile_core.rendering.rasterize import render_point, render_xy

SPECS = (
    "CT", "MM", "AS", "IM", "EN", "PK", "PK:blend=0.2", "RO", "RO:curve=linear", "RO:r=1.5",
    "RO:r=0.7", "GS", "GS:sigma=0.3", "GS:sigma=0.7", "GS:sigma=1.3", "VRCH", "VRCH:r=1.5",
)  # fmt: skip
GRIDS = (tc.Grid(cols=5, rows=6), tc.Grid(cols=3, rows=4), tc.Grid(cols=9, rows=8))


def _shapes(rng: np.random.Generator) -> list:
    """Shapes on special places (tactor centres, cell edges) and anywhere."""
    out = [
        tc.Line((0.5, 1.84), (4.5, 4.16)),
        tc.Circle((2.5, 3.0), 2.0),
        tc.Square((2.5, 3.5), 4.0),
        tc.Line((0.5, 0.5), (4.5, 5.5)),
        tc.Line((0.0, 0.0), (5.0, 6.0)),
        tc.Line((1.5, 3.0), (1.5, 3.0)),
        tc.Circle((2.0, 3.0), 1.0),
        tc.Circle((2.5, 2.5), 1.5),
        tc.Circle((2.5, 3.5), 0.5),
        tc.Square((2.0, 3.0), 2.0),
        tc.Square((2.5, 3.5), 2.0),
        tc.Square((2.5, 3.0), 3.0),
        tc.Polyline(((0.5, 0.5), (2.5, 4.5), (4.5, 0.5)), closed=True),
        tc.Polyline(((0.0, 1.0), (5.0, 1.0), (5.0, 5.0), (0.0, 5.0))),
    ]
    for _ in range(12):  # lattice-aligned: halves and wholes
        p = rng.integers(-1, 12, size=4) / 2.0
        out.append(tc.Line((p[0], p[1]), (p[2], p[3])))
        c = rng.integers(0, 11, size=2) / 2.0
        out.append(tc.Circle((c[0], c[1]), rng.integers(1, 7) / 2.0))
        out.append(tc.Square((c[0], c[1]), float(rng.integers(1, 9))))
    for _ in range(12):  # anywhere, a little beyond the grid too
        p = rng.uniform(-1.0, 7.0, size=4)
        out.append(tc.Line((p[0], p[1]), (p[2], p[3])))
        c = rng.uniform(0.0, 6.0, size=2)
        out.append(tc.Circle((c[0], c[1]), rng.uniform(0.2, 3.5)))
        out.append(tc.Square((c[0], c[1]), rng.uniform(0.3, 6.0)))
        pts = rng.uniform(-0.5, 6.5, size=(int(rng.integers(3, 7)), 2))
        out.append(tc.Polyline(tuple(map(tuple, pts)), closed=bool(rng.integers(2))))
    return out


def _ts(rng: np.random.Generator) -> np.ndarray:
    """A uniform grid (every 1/1,024 and 1/1,000: corners, keyframes) and random draws."""
    return np.unique(
        np.concatenate([np.linspace(0, 1, 1025), np.linspace(0, 1, 1001), rng.uniform(0, 1, 800)])
    )


def _free_points(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    half = np.arange(-2, 21) / 2.0
    qx, qy = np.meshgrid(np.arange(-4, 41) / 4.0, np.arange(-4, 41) / 4.0)
    x = np.concatenate([np.repeat(half, len(half)), qx.ravel(), rng.uniform(-1, 10, 20_000)])
    y = np.concatenate([np.tile(half, len(half)), qy.ravel(), rng.uniform(-1, 10, 20_000)])
    return x, y


def cases():
    """Yield ``(key, frames)`` of every case, deterministically."""
    rng = np.random.default_rng(21)
    shapes, ts = _shapes(rng), _ts(rng)
    x, y = _free_points(rng)
    single = rng.choice(ts, 40, replace=False)
    for spec in SPECS:
        free = not tc.get_method(spec).needs_shape
        for g, grid in enumerate(GRIDS):
            shape_list = shapes if g == 0 else shapes[::4]
            blocks = [tc.render(s, spec, ts, grid=grid) for s in shape_list]
            yield f"{spec}|grid{g}|render", np.concatenate(blocks)
            if free:
                yield f"{spec}|grid{g}|xy", render_xy(spec, x, y, grid=grid)
        points = []
        lives = []
        for s in shapes[:: max(1, len(shapes) // 25)]:
            for t in single:
                points.append(tc.render(s, spec, float(t)))
                frame = np.zeros(30)
                for index, value in render_point(s, spec, float(t)):
                    frame[index] = value
                lives.append(frame.reshape(6, 5))
        yield f"{spec}|point", np.stack(points)
        yield f"{spec}|live", np.stack(lives)


def dump(folder: pathlib.Path) -> None:
    """Write every case to ``folder`` (one ``.npy`` per case) and report the counts."""
    folder.mkdir(parents=True, exist_ok=True)
    total = 0
    for key, frames in cases():
        np.save(folder / (key.replace("|", "__").replace(":", "_") + ".npy"), frames)
        total += len(frames)
    print(f"{total:,} frames written to {folder}")


def compare(folder: pathlib.Path, tol: float) -> int:
    """Compare every case with the dump in ``folder``; 1 if any differs beyond ``tol``."""
    worst: dict[str, list] = {}
    total = 0
    for key, frames in cases():
        ref = np.load(folder / (key.replace("|", "__").replace(":", "_") + ".npy"))
        spec = key.split("|")[0]
        row = worst.setdefault(spec, [0, 0.0, 0])
        if ref.shape != frames.shape:
            print(f"{key}: shape {frames.shape} against {ref.shape}")
            row[2] += len(ref)
            continue
        row[0] += len(ref)
        total += len(ref)
        row[1] = max(row[1], float(np.abs(frames - ref).max()))
        lit = (frames > 0).reshape(len(ref), -1) != (ref > 0).reshape(len(ref), -1)
        row[2] += int(lit.any(axis=1).sum())
    failed = False
    print(f"{'spec':16} {'frames':>9} {'max |diff|':>11} {'lit differs':>12}")
    for spec, (n, diff, lit) in worst.items():
        failed |= diff > tol or lit > 0
        print(f"{spec:16} {n:9,} {diff:11.3g} {lit:12,}")
    print(f"{total:,} frames compared; {'DIFFERENT' if failed else 'equal'} (tol {tol:g})")
    return 1 if failed else 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("action", choices=("dump", "compare"))
    parser.add_argument("folder", type=pathlib.Path)
    parser.add_argument("--tol", type=float, default=1e-15)
    args = parser.parse_args(argv)
    if args.action == "dump":
        dump(args.folder)
        return 0
    return compare(args.folder, args.tol)


if __name__ == "__main__":
    sys.exit(main())
