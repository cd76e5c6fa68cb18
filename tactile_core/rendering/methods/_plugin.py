"""What a plug-in method must hold to: its output checked like any method's, its failures
contained.

A plug-in is someone else's code running inside the renderer and the output thread. Whatever
it does (raises, returns a cell twice, returns values above 1 or NaN, calls ``sys.exit()``, raises
``KeyboardInterrupt``) becomes a ``ValueError`` naming the method, which the command line
reports in one line and the tuner answers by taking the method out (back to AS).
"""

from __future__ import annotations

import math

import numpy as np

from ..._shared import validate as _validate

CONTAINED = (Exception, SystemExit, KeyboardInterrupt)
"""What a plug-in may raise that is caught and reported (``GeneratorExit`` is left alone)."""

MAX_CELL = 4096
"""Cells at or beyond this index (or below 0) are outside any grid: they are dropped by the
renderer, so two of them never add up (grids are at most 1024 x 1024)."""


def max_tactors(module, params: dict, label: str) -> int:
    """A method's ``MAX_TACTORS`` at ``params`` (called if it is a function): a whole number
    from 1 to 1024; ``ValueError`` naming ``label`` otherwise, whatever the plug-in raises."""
    value = module.MAX_TACTORS
    if callable(value):
        try:
            value = value(**params)
        except CONTAINED as exc:
            shown = ", ".join(f"{k}={v:g}" for k, v in params.items()) or "its defaults"
            raise ValueError(f"method {label}: MAX_TACTORS failed at {shown}: "
                             f"{type(exc).__name__}: {exc}") from None  # fmt: skip
    if (not _validate.is_number(value) or not math.isfinite(value)
            or not float(value).is_integer() or not 1 <= value <= 1024):  # fmt: skip
        raise ValueError(
            f"method {label}: MAX_TACTORS must be from 1 to 1024, got {_validate.shown(value)}"
        )
    return int(value)


def checked(spec: str, fn, scalar: bool):
    """Wrap a plug-in's sampler: its exceptions and any output the protocol does not allow
    become a ``ValueError`` naming the method.

    Allowed output: ``(col, row, value)`` entries; cells whole numbers (cells off the grid are
    dropped, as for every method), values finite and within [0, 1], and no cell named twice
    with a value above 0 at the same point (two entries for one tactor would add up past 1).
    For ``sample`` each of ``col``, ``row`` and ``value`` is a number or an array of one value
    per point.
    """

    def bad(detail):
        return ValueError(f"method {spec} (a plug-in) {detail}")

    def run(*args):
        try:
            out = fn(*args)
            entries = list(out)
        except CONTAINED as exc:  # a plug-in's bug, or its exit, must not look like ours
            raise bad(f"failed: {type(exc).__name__}: {exc}") from None
        try:
            problem = _check_scalar(entries) if scalar else _check_arrays(entries, len(args[1]))
        except CONTAINED:
            problem = "returned something other than (col, row, value) entries"
        if problem:
            raise bad(f"{problem}: {_validate.shown(out)}")
        return tuple(entries) if scalar else entries

    return run


_SHAPE = (
    "returned something other than (col, row, value) entries with whole cells and values in [0, 1]"
)


def _check_scalar(entries) -> str:
    seen = set()
    for entry in entries:
        c, r, v = entry
        ok = all(_validate.is_number(a) and math.isfinite(a) for a in (c, r, v))
        if not (ok and float(c).is_integer() and float(r).is_integer() and 0.0 <= v <= 1.0):
            return _SHAPE
        if v > 0.0:
            if (c, r) in seen:
                return f"named the cell ({c:g}, {r:g}) twice at one point"
            seen.add((c, r))
    return ""


def _check_arrays(entries, n: int) -> str:
    cols, rows, values = [], [], []
    for entry in entries:
        c, r, v = (np.broadcast_to(np.asarray(a, dtype=np.float64), (n,)) for a in entry)
        whole = np.isfinite(c) & np.isfinite(r) & (c == np.floor(c)) & (r == np.floor(r))
        if not (whole.all() and np.all((v >= 0.0) & (v <= 1.0))):
            return _SHAPE
        cols.append(c)
        rows.append(r)
        values.append(v)
    if len(entries) < 2 or n == 0:
        return ""
    c, r, v = np.stack(cols), np.stack(rows), np.stack(values)
    on_grid = (v > 0.0) & (c >= 0) & (c < MAX_CELL) & (r >= 0) & (r < MAX_CELL)
    codes = np.where(on_grid, r * MAX_CELL + c, -1.0 - np.arange(len(entries))[:, None])
    codes.sort(axis=0)
    twice = (codes[1:] == codes[:-1]) & (codes[1:] >= 0)
    if twice.any():
        k, i = np.argwhere(twice)[0]
        code = codes[k + 1, i]
        return f"named the cell ({code % MAX_CELL:g}, {code // MAX_CELL:g}) twice at point {i}"
    return ""
