"""What every benchmark table shares: the scenes, the paper's mu and gamma, the frame rates
and temporal filters, the timer and the table."""

from __future__ import annotations

import time
from dataclasses import dataclass

from ..rendering.shapes import Circle, Line, Square

SCENES = {
    "line": Line((0.5, 1.84), (4.5, 4.16)),  # Experiment 1 line, slope 0.58
    "circle": Circle((2.5, 3.0), 2.0),  # Experiment 1 circle
    "square": Square((2.5, 3.5), 4.0),  # Experiment 3 square
}
MU, GAMMA = 0.33, 0.7  # the paper's values for all experiments but two stages of Exp. 2
RATES_HZ = (25, 50, 100, 200, 300, 1000)
FILTERS = (("point", 1), ("box", 4), ("box", 16))


def best_time(fn, *, repeat: int = 7, min_s: float = 0.05) -> float:
    """Seconds per call of ``fn()``: the minimum over ``repeat`` runs of enough calls."""
    number = 1
    while True:
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        elapsed = time.perf_counter() - t0
        if elapsed >= min_s or number >= 1 << 20:
            break
        number *= 2
    runs = [elapsed]
    for _ in range(repeat - 1):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        runs.append(time.perf_counter() - t0)
    return min(runs) / number


@dataclass
class Table:
    """A titled table of rows, printed as Markdown."""

    title: str
    headers: list
    rows: list
    notes: str = ""

    def markdown(self) -> str:
        """The table as GitHub-flavoured Markdown, with its title and notes."""
        widths = [
            max(len(str(h)), *(len(str(r[i])) for r in self.rows))
            for i, h in enumerate(self.headers)
        ]

        def line(cells):
            return "| " + " | ".join(str(c).ljust(w) for c, w in zip(cells, widths)) + " |"

        out = [f"### {self.title}", "", line(self.headers)]
        out.append("|" + "|".join("-" * (w + 2) for w in widths) + "|")
        out += [line(r) for r in self.rows]
        if self.notes:
            out += ["", self.notes]
        return "\n".join(out)


def _cycling(frame_of, cycle):
    """A no-argument callable that computes successive frames ``k % cycle``."""
    counter = iter(range(1 << 62))
    return lambda: frame_of(next(counter) % cycle)
