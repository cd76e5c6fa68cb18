"""bHaptics' compiled ``.tact`` form: frames of motor values, read, played and written.

The form, as bHaptics' SDK sources read it (``TactosyFile``/``TactosyFileBridge`` in
``src/Tactosy.Common/TactosyFile.cs`` and ``Signal.cs`` of bhaptics/haptic-library, 2017;
``HapticFile`` in ``include/shared/model.h`` and ``Util::parseFromTactFileString`` in
``src/util.cpp``, which requires ``intervalMillis``, ``size`` and ``durationMillis``)::

    {"intervalMillis": 20, "size": 20, "durationMillis": 220,
     "feedback": {"0": [{"position": "VestFront", "mode": "DOT_MODE",
                         "values": [0, 100, ...], "texture": 0}, ...],
                  "20": [...], ...}}

Each key of ``feedback`` is a frame's time in ms; each entry gives one position's motor values
0..100 (``values[i]`` is motor ``i``), held until the next frame. The 2017 SDK reads them as
bytes (``byte[] values``) and caps what it plays at 100; some of bHaptics' early files hold
values up to 228, so 0..255 is read and anything above 100 plays as 100. ``PATH_MODE`` entries are
bHaptics' 2017 point format (a count, then ``x, y, intensity`` triples); they are read and
checked but not played.
"""

from __future__ import annotations

import math

import numpy as np

from ._tact_records import TactCompiled, TactDot

MAX_INTERVAL_MS = 10_000
"""Longest frame interval read (bHaptics writes 20 ms)."""
MAX_FRAMES = 180_000
"""Most frames (``feedback`` keys) in a file: an hour at 20 ms."""
INTERVAL_MS = 20
"""The interval written: bHaptics' own."""

_GRIDS = {  # (position family, motors) -> (columns, rows) of the motors, numbered row by row
    ("Vest", 20): (4, 5), ("Arm", 20): (5, 4), ("Forearm", 6): (3, 2), ("Hand", 10): (5, 2),
    ("Racket", 10): (5, 2), ("Hand", 3): (1, 3),
}  # fmt: skip
_FAMILIES = {"VestFront": "Vest", "VestBack": "Vest", "Left": "Arm", "Right": "Arm",
             "ForearmL": "Forearm", "ForearmR": "Forearm", "HandL": "Hand", "HandR": "Hand",
             "Racket": "Racket"}  # fmt: skip


DEVICE_MOTORS = {
    **{"VestFront": 20, "VestBack": 20, "Left": 20, "Right": 20, "ForearmL": 6, "ForearmR": 6},
    **{"Head": 6, "HandL": 3, "HandR": 3, "FootL": 3, "FootR": 3},
}
"""Motors of each device position, as its Designer files list them (the head's most often): the
layout of a file whose ``layout`` gives its ``type`` but no ``layouts``."""


def device_places(position: str, n: int) -> dict:
    """Motor places ``{index: (x, y)}`` (0..1, y downward) of a bHaptics device position with
    ``n`` motors, as its Designer files lay them out: the vest's 4 x 5 per side, the arms'
    (``Left``/``Right``) 5 x 4, a forearm's 3 x 2, a hand's 5 x 2 or 1 x 3, numbered from the top
    left row by row; anything else (the head's 4-7, a foot's 3) evenly along the middle row."""
    cols, rows = _GRIDS.get((_FAMILIES.get(position, ""), n), (n, 1))
    places = {}
    for i in range(n):
        row, col = divmod(i, cols)
        x = col / (cols - 1) if cols > 1 else 0.5
        y = row / (rows - 1) if rows > 1 else 0.5
        places[i] = (x, y)
    return places


def read_compiled(reader, data: dict) -> TactCompiled:
    """Check the compiled form of a parsed file (``reader``: the file's ``_Reader``, which names
    the fields and counts the bounds)."""
    interval = reader.whole(reader.get(data, "intervalMillis", ""), "intervalMillis", 1,
                            MAX_INTERVAL_MS)  # fmt: skip
    size = reader.whole(reader.get(data, "size", ""), "size", 0, reader.max_layout)
    duration = reader.whole(reader.get(data, "durationMillis", ""), "durationMillis", 0,
                            reader.max_time_ms)  # fmt: skip
    feedback = reader.object(reader.get(data, "feedback", ""), "feedback")
    if len(feedback) > MAX_FRAMES:
        reader.fail("feedback", f"holds {len(feedback)} frames, more than the {MAX_FRAMES} "
                    "allowed")  # fmt: skip
    frames: dict = {}
    widths: dict = {}
    path_frames = 0
    for key in sorted(feedback, key=lambda k: _key_ms(reader, k)):
        ms = _key_ms(reader, key)
        where = f"feedback.{key}"
        entries = reader.array(feedback[key], where, reader.max_positions)
        seen = set()
        for k, entry in enumerate(entries):
            at = f"{where}[{k}]"
            entry = reader.object(entry, at)
            position = reader.position(reader.get(entry, "position", at), f"{at}.position")
            if position in seen:
                reader.fail(f"{at}.position", f"repeats {position} in one frame")
            seen.add(position)
            mode = reader.choice(reader.get(entry, "mode", at), f"{at}.mode", reader.modes)
            values = reader.array(reader.get(entry, "values", at), f"{at}.values",
                                  reader.max_layout)  # fmt: skip
            values = tuple(reader.whole(v, f"{at}.values[{i}]", 0, 255)
                           for i, v in enumerate(values))  # fmt: skip
            if "texture" in entry:
                reader.whole(entry["texture"], f"{at}.texture", 0, 1 << 16)
            if mode == "PATH_MODE":
                path_frames += any(values)
                continue
            if widths.setdefault(position, len(values)) != len(values):
                reader.fail(f"{at}.values", f"holds {len(values)} values where the frames before "
                            f"give {position} {widths[position]}")  # fmt: skip
            times, rows = frames.setdefault(position, ([], []))
            times.append(ms)
            rows.append(values)
    frames = {p: (tuple(t), tuple(r)) for p, (t, r) in frames.items()}
    return TactCompiled(interval, size, duration, frames, path_frames)


def _key_ms(reader, key) -> int:
    """A ``feedback`` key: a frame's time, whole ms as decimal text."""
    if not (isinstance(key, str) and key.isascii() and key.isdigit() and len(key) <= 8):
        reader.fail("feedback", f"has a key {key!r}: a frame's time in whole ms ('0', '20', ...)")
    ms = int(key)
    if ms > reader.max_time_ms:
        reader.fail(f"feedback.{key}", f"is after {reader.max_time_ms / 3.6e6:g} h")
    return ms


def compiled_dots(reader, compiled: TactCompiled) -> tuple:
    """The compiled frames as dots: each motor's run of one non-zero value over consecutive
    frames is one dot, on from the run's first frame until the next frame after it (an open
    end), at the value / 100, placed by :func:`device_places`. Returns ``(dots, layouts,
    ends_s, positions)``; ``reader`` counts the dots against the file's bound."""
    interval = compiled.interval_ms
    dots, layouts, ends, positions = [], {}, {}, []
    for position, (times, rows) in compiled.frames.items():
        width = len(rows[0]) if rows else 0
        places = device_places(position, width)
        layouts[position] = places
        values = np.asarray(rows, dtype=np.int64).reshape(len(rows), width)
        found = 0
        for motor in range(width):
            column = values[:, motor]
            k = 0
            while k < len(times):
                if column[k] == 0:
                    k += 1
                    continue
                first = k
                while (k + 1 < len(times) and column[k + 1] == column[first]
                       and times[k + 1] == times[k] + interval):  # fmt: skip
                    k += 1
                reader.count(1, f"feedback.{times[first]}")
                x, y = places[motor]
                dots.append(TactDot(position, motor, min(float(column[first]), 100.0) / 100.0,
                                    times[first] / 1e3, (times[k] + interval) / 1e3, "NONE",
                                    f"feedback.{times[first]}", x, y, closed=False))  # fmt: skip
                found += 1
                k += 1
        if found:
            positions.append(position)
            ends[position] = (times[-1] + interval) / 1e3
    return tuple(dots), layouts, ends, tuple(positions)


def compiled_document(values: dict, *, interval_ms: int = INTERVAL_MS) -> dict:
    """The compiled form's keys for frames of motor values.

    Parameters
    ----------
    values : dict of str to array_like of int, shape (n, motors)
        Per device position, one row per frame of values 0..100 in the position's motor order
        (frame ``k`` at ``k * interval_ms``). Every position has the same ``n``.
    interval_ms : int, keyword-only
        The frames' spacing, 1..10,000 ms.

    Returns
    -------
    dict
        ``intervalMillis``, ``size`` (the most motors of a position), ``durationMillis`` (the
        frames' end plus one interval, as bHaptics' exports give it) and ``feedback``.
    """
    if not isinstance(interval_ms, int) or not 1 <= interval_ms <= MAX_INTERVAL_MS:
        raise ValueError(f"interval_ms must be a whole number of ms in [1, {MAX_INTERVAL_MS}], "
                         f"got {interval_ms!r}")  # fmt: skip
    arrays = {}
    for position, rows in values.items():
        rows = np.asarray(rows)
        if rows.ndim != 2 or (rows.size and (rows.min() < 0 or rows.max() > 100)):
            raise ValueError(f"values[{position!r}] must be frames x motors of 0..100, got an "
                             f"array of shape {rows.shape}")  # fmt: skip
        arrays[position] = rows.astype(np.int64)
    counts = {len(rows) for rows in arrays.values()}
    if len(counts) > 1:
        raise ValueError(f"values must give every position as many frames, got {sorted(counts)}")
    n = counts.pop() if counts else 0
    feedback = {
        str(k * interval_ms): [
            {"position": p, "mode": "DOT_MODE", "values": rows[k].tolist(), "texture": 0}
            for p, rows in arrays.items()
        ]
        for k in range(n)
    }
    size = max((rows.shape[1] for rows in arrays.values()), default=0)
    return {"intervalMillis": interval_ms, "size": size,
            "durationMillis": (n + 1) * interval_ms if n else 0, "feedback": feedback}  # fmt: skip


def frame_count(end_s: float, interval_ms: int = INTERVAL_MS) -> int:
    """Frames ``k * interval_ms`` before ``end_s`` (bHaptics' exports stop before the end)."""
    return max(0, math.ceil(end_s * 1e3 / interval_ms - 1e-9))
