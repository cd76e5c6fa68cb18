"""The files of a blind A/B session: a saved ratings file and the autosave.

Both are CSV, one row per key (:data:`COLUMNS`); an autosave adds ``methods`` (the set in the
order it was shuffled) and leaves ``method`` empty until Reveal, so that it never gives the
mapping away. Both are written atomically (:func:`~tactile_core._shared.outfile.atomic_file`):
a full disk or a crash leaves the previous file, never half of one.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

from .._shared import validate as _validate
from .._shared.jsonfile import read_bytes
from .._shared.outfile import atomic_file, check_output

RATINGS = ("quality", "smoothness", "thickness")
"""What each key is rated on, 0-100 (the paper's Experiment 1)."""
SCENE_COLUMNS = ("shape", "mu", "gamma", "duration_s", "pause_s")
"""The scene the ratings were given on, as each row records it."""
COLUMNS = ("session", "key", "method", "felt", "felt_s", *RATINGS, *SCENE_COLUMNS, "seed",
           "revealed_before_save")  # fmt: skip
"""The columns of a saved ratings file, one row per key."""
AUTOSAVE_COLUMNS = (*COLUMNS, "methods")
"""An autosave's columns: those of :data:`COLUMNS` and the methods in the order shuffled."""
MAX_AUTOSAVE_BYTES = 1 << 16
"""Largest autosave read back (one of 8 keys is under 2 KB)."""


def scene_columns(scene) -> dict:
    """The :data:`SCENE_COLUMNS` of ``scene`` (a :class:`~tactile_core.rendering.scene.Scene`,
    or None: all empty); a pattern without a shape has an empty ``shape``."""
    if scene is None:
        return dict.fromkeys(SCENE_COLUMNS, "")
    return {
        "shape": scene.shape.spec if scene.shape is not None else "",
        "mu": scene.mu,
        "gamma": scene.gamma,
        "duration_s": scene.duration_s,
        "pause_s": scene.pause_s,
    }


def write_rows(f, rows: list[dict], *, header: bool) -> None:
    """``rows`` (dicts, the columns in order) as CSV lines to the open text file ``f``."""
    writer = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
    if header:
        writer.writeheader()
    writer.writerows(rows)


def write_autosave(path: Path, rows: list[dict]) -> None:
    """Replace the autosave ``path`` with ``rows`` (in :data:`AUTOSAVE_COLUMNS`), its folder
    made if missing. Raises ``OSError`` when it cannot be written (the old file stays)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_file(path) as f:
        write_rows(f, rows, header=True)


def append_rows(path, rows: list[dict]) -> Path:
    """Append ``rows`` (in :data:`COLUMNS`) to the ratings file ``path``, the header first in a
    new file, rewriting it atomically; ``ValueError`` for a path that cannot be written or a
    file with other columns."""
    path = check_output(path, (".csv",), "ratings file")
    old = path.read_text(encoding="utf-8") if path.exists() else ""
    if old and not old.startswith(",".join(COLUMNS) + "\n"):
        raise ValueError(f"{path} holds other columns: save the ratings to a new file")
    with atomic_file(path) as f:
        f.write(old)
        write_rows(f, rows, header=not old)
    return path


def read_autosave(path) -> dict:
    """What the autosave ``path`` holds: ``methods`` (list), ``seed``, ``session``,
    ``revealed``, ``revealed_methods`` (the ``method`` column, "" while hidden), ``felt_s`` and
    ``ratings`` per key (None where not rated) and the ``scene`` columns as written.
    ``ValueError`` names the file and what is wrong with it."""
    text = read_bytes(path, max_bytes=MAX_AUTOSAVE_BYTES).decode("utf-8", errors="replace")
    reader = csv.DictReader(io.StringIO(text))
    if tuple(reader.fieldnames or ()) != AUTOSAVE_COLUMNS:
        raise ValueError(f"{path}: not a blind A/B autosave (columns {reader.fieldnames}, "
                         f"expected {list(AUTOSAVE_COLUMNS)})")  # fmt: skip
    rows = list(reader)
    first = rows[0] if rows else None
    if first is None or any(
        (r["key"], r["methods"], r["seed"], r["session"])
        != (str(k + 1), first["methods"], first["seed"], first["session"])
        for k, r in enumerate(rows)
    ) or len(rows) != len(first["methods"].split()):  # fmt: skip
        keys = len(first["methods"].split()) if first else "N"
        raise ValueError(f"{path}: expected one row per key 1-{keys} of one session")
    try:
        seed = _validate.integer("seed", int(first["seed"]), 0)
        felt_s, ratings = [], []
        for k, row in enumerate(rows):
            felt = _validate.real(f"felt_s of key {k + 1}", float(row["felt_s"]))
            felt_s.append(_validate.non_negative(f"felt_s of key {k + 1}", felt))
            ratings.append({
                name: None if row[name] == "" else
                _validate.integer(f"{name} of key {k + 1}", int(row[name]), 0, 100)
                for name in RATINGS
            })  # fmt: skip
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    return {
        "methods": first["methods"].split(),
        "seed": seed,
        "session": first["session"],
        "revealed": first["revealed_before_save"] == "True",
        "revealed_methods": [r["method"] for r in rows],
        "felt_s": felt_s,
        "ratings": ratings,
        "scene": {name: first[name] for name in SCENE_COLUMNS},
    }
