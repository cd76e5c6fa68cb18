"""The pattern editor's state without Qt: the pattern being edited, the effect selected, the
playhead and the file; every edit a function from one pattern to the next.

A :class:`TimelineModel` holds the state and tells its listeners when a part of it changes
(``"pattern"``, ``"selection"``, ``"playhead"``, ``"path"``). An edit (:meth:`TimelineModel.move`,
:meth:`~TimelineModel.resize`, :meth:`~TimelineModel.change`, :meth:`~TimelineModel.add`, ...)
changes nothing: it returns an :class:`Edit`, the pattern and selection after it, or raises the
pattern's own ``ValueError`` (``repeat must be >= 1, got 0``); the editor's undo stack applies
it (:meth:`TimelineModel.apply`) and puts the state before it back on undo. Patterns are
immutable values, so an undo restores exactly the pattern there was.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass

from tactile_core._shared import validate as _validate
from tactile_core.files.pattern import MAX_TRACKS, Dots, Effect, Pattern

SNAP_S = 0.01
"""The time grid of the editor: starts and durations snap to 10 ms."""
BIG_STEP_S = 0.1
"""A move or resize with Shift: ten grid steps."""
EVENTS = ("pattern", "selection", "playhead", "path")
KEEP = "keep"
"""An :class:`Edit` that leaves the pattern's file as it was."""


def snap(time_s: float, grid_s: float = SNAP_S) -> float:
    """``time_s`` on the grid (the nearest multiple of ``grid_s``; a tie goes to the even
    one, as :func:`round` does), rounded to 1 ns so that 0.3 is 0.3, not 0.30000000000000004;
    no grid (``grid_s`` 0) leaves it as it is."""
    if grid_s <= 0.0:
        return float(time_s)
    return round(round(float(time_s) / grid_s) * grid_s, 9)


def peak_gain(effect: Effect) -> float:
    """An effect's intensity: the highest gain of its envelope (1 without keyframes)."""
    return max((g for _, g in effect.envelope), default=1.0)


def with_intensity(effect: Effect, gain: float) -> Effect:
    """``effect`` at intensity ``gain`` (0 to 1): its envelope's gains scaled so that the
    highest is ``gain`` (an envelope of zeros, or none, becomes ``gain`` throughout)."""
    gain = _validate.in_range("intensity", gain, 0.0, 1.0)
    peak = peak_gain(effect)
    if not effect.envelope:
        envelope = () if gain == 1.0 else ((0.0, gain),)
    elif peak <= 0.0:
        envelope = tuple((t, gain) for t, _ in effect.envelope)
    else:
        envelope = tuple((t, min(g * gain / peak, 1.0)) for t, g in effect.envelope)
    return effect.replace(envelope=envelope)


def resized(effect: Effect, duration_s: float) -> Effect:
    """``effect`` with one play lasting ``duration_s``, its envelope's keyframes at the same
    fractions of the play (they stretch with it)."""
    duration_s = _validate.duration("duration_s", duration_s)
    scale = duration_s / effect.duration_s
    envelope = tuple((min(t * scale, duration_s), g) for t, g in effect.envelope)
    return effect.replace(duration_s=duration_s, envelope=envelope)


def with_dot_length(effect: Effect, dot_s: float) -> Effect:
    """A set of dots whose every dot lasts ``dot_s`` seconds (a tap; what plays past the end
    of a play is cut); ``ValueError`` for an effect that plays no set of dots."""
    if not isinstance(effect.content, Dots):
        raise ValueError(f"dot_s applies to a set of dots, not to a {describe(effect)}")
    dot_s = _validate.duration("dot_s", dot_s)
    dots = [dataclasses.replace(d, duration_s=dot_s) for d in effect.content.dots]
    return effect.replace(content=Dots(dots))


def dot_length(effect: Effect) -> float | None:
    """How long the dots of a set last, if they all last as long (else None)."""
    if not isinstance(effect.content, Dots):
        return None
    lengths = {d.duration_s for d in effect.content.dots}
    return lengths.pop() if len(lengths) == 1 else None


ENVELOPE_PAIR = re.compile(r"\s*([^\s:,;]+)\s*:\s*([^\s:,;]+)\s*")


def envelope_text(envelope) -> str:
    """Keyframes as the property panel writes them: ``0:0.4, 0.08:1``."""
    return ", ".join(f"{t:g}:{g:g}" for t, g in envelope)


def parse_envelope(text: str) -> tuple:
    """Keyframes written as ``time_s:gain`` pairs separated by commas (``0:0.4, 0.08:1``; empty:
    none); ``ValueError`` naming ``envelope`` and the pair that is not one."""
    if not text.strip():
        return ()
    pairs = []
    for i, item in enumerate(text.split(",")):
        found = ENVELOPE_PAIR.fullmatch(item)
        if found is None:
            raise ValueError(f"envelope[{i}] must be time_s:gain, such as 0.08:1, got "
                             f"{item.strip()!r}")  # fmt: skip
        pairs.append((_validate.decimal_text(f"envelope[{i}].time_s", found[1]),
                      _validate.decimal_text(f"envelope[{i}].gain", found[2])))  # fmt: skip
    return tuple(pairs)


@dataclass(frozen=True)
class Edit:
    """What an edit leaves: the pattern, the effect selected (an index or None), and the words
    the undo stack shows (``Move effect 2``)."""

    text: str
    pattern: Pattern
    selected: int | None
    merge: tuple | None = None
    """Consecutive edits with the same ``merge`` key (a key held down to move one effect)
    undo as one."""
    path: object = KEEP
    """The pattern's file after the edit (another pattern opened or imported: its file, or
    None); :data:`KEEP` for the file it had."""


class TimelineModel:
    """The pattern being edited, the effect selected, the playhead and the pattern's file.

    Parameters
    ----------
    pattern : Pattern, optional
        An empty pattern by default.

    Attributes
    ----------
    pattern : Pattern
    selected : int or None
        The index of the selected effect in ``pattern.effects``.
    playhead_s : float
        Where the editor plays from and what the heatmap shows when it is scrubbed, in seconds.
    path : Path or None
        The file it was opened from or saved to.
    grid_s : float
        The time grid moves and resizes snap to (:data:`SNAP_S`; 0: none).
    """

    def __init__(self, pattern: Pattern | None = None):
        self.pattern = Pattern() if pattern is None else pattern
        self.selected = None
        self.playhead_s = 0.0
        self.path = None
        self.grid_s = SNAP_S
        self._listeners = {name: [] for name in EVENTS}

    # --- listening -----------------------------------------------------------------------------

    def connect(self, event: str, callback) -> None:
        """Call ``callback()`` whenever ``event`` (``"pattern"``, ``"selection"``,
        ``"playhead"`` or ``"path"``) changes."""
        if event not in self._listeners:
            raise ValueError(f"event must be one of {', '.join(EVENTS)}, got {event!r}")
        self._listeners[event].append(callback)

    def _emit(self, event: str) -> None:
        for callback in list(self._listeners[event]):
            callback()

    # --- the state -----------------------------------------------------------------------------

    @property
    def effect(self) -> Effect | None:
        """The selected effect, or None."""
        return None if self.selected is None else self.pattern.effects[self.selected]

    def apply(self, pattern: Pattern, selected: int | None, path=KEEP) -> None:
        """Make ``pattern`` the one edited, with ``selected`` (and its file ``path``, unless
        :data:`KEEP`): what an edit, its undo and its redo do."""
        changed = pattern is not self.pattern
        if path != KEEP:
            self.set_path(path)
        if selected is not None:
            selected = _validate.integer("selected", selected, 0, len(pattern.effects) - 1)
        moved = selected != self.selected
        self.pattern, self.selected = pattern, selected  # both before anyone hears of either
        if changed:
            self._emit("pattern")
        if moved or changed:
            self._emit("selection")

    def select(self, index: int | None) -> None:
        """Select effect ``index`` (None: none)."""
        if index is not None:
            index = _validate.integer("index", index, 0, len(self.pattern.effects) - 1)
        if index != self.selected:
            self.selected = index
            self._emit("selection")

    def set_path(self, path) -> None:
        """The pattern's file is now ``path`` (None: none)."""
        if path != self.path:
            self.path = path
            self._emit("path")

    def set_playhead(self, time_s: float) -> None:
        """Put the playhead at ``time_s`` seconds (0 to an hour)."""
        time_s = _validate.in_range("playhead", time_s, 0.0, _validate.MAX_DURATION_S)
        if time_s != self.playhead_s:
            self.playhead_s = time_s
            self._emit("playhead")

    def in_time_order(self) -> list:
        """Effect indices by start, then track, then index: the order Tab goes through."""
        effects = self.pattern.effects
        return sorted(range(len(effects)), key=lambda i: (effects[i].start_s,
                                                          effects[i].track, i))  # fmt: skip

    def neighbour(self, step: int) -> int | None:
        """The effect ``step`` places after the selected one in time order (the first or the
        last with none selected); None past either end."""
        order = self.in_time_order()
        if not order:
            return None
        if self.selected is None:
            return order[0] if step > 0 else order[-1]
        k = order.index(self.selected) + step
        return order[k] if 0 <= k < len(order) else None

    def free_track(self, start_s: float, end_s: float) -> int:
        """The lowest track with nothing playing within ``[start_s, end_s)``."""
        busy = {e.track for e in self.pattern.effects if e.start_s < end_s and start_s < e.end_s}
        return next((t for t in range(MAX_TRACKS) if t not in busy), 0)

    # --- edits (nothing changes until the undo stack applies one) ------------------------------

    def _with(self, index: int, effect: Effect, text: str, merge=None) -> Edit:
        effects = list(self.pattern.effects)
        effects[index] = effect
        return Edit(text, self.pattern.replace(effects=effects), index, merge)

    def move(self, index: int, start_s: float, track: int, merge=None) -> Edit:
        """Effect ``index`` starting at ``start_s`` (snapped to the grid, at least 0) on
        ``track``."""
        effect = self.pattern.effects[index]
        start = max(snap(start_s, self.grid_s), 0.0)
        moved = effect.replace(start_s=start, track=track)
        return self._with(index, moved, f"Move effect {index + 1}", merge)

    def nudge(self, index: int, step_s: float = 0.0, tracks: int = 0) -> Edit:
        """Effect ``index`` moved by ``step_s`` seconds and ``tracks`` tracks (the arrow
        keys); a key held down (the same step again and again) undoes as one edit."""
        effect = self.pattern.effects[index]
        track = min(max(effect.track + tracks, 0), MAX_TRACKS - 1)
        merge = ("move", index, step_s, tracks)
        return self.move(index, effect.start_s + step_s, track, merge=merge)

    def resize(self, index: int, duration_s: float, merge=None) -> Edit:
        """Effect ``index`` with one play lasting ``duration_s`` (snapped, at least one grid
        step), its envelope stretched with it (:func:`resized`)."""
        effect = self.pattern.effects[index]
        duration = max(snap(duration_s, self.grid_s), self.grid_s or 1e-3)
        return self._with(index, resized(effect, duration), f"Resize effect {index + 1}", merge)

    def stretch(self, index: int, step_s: float) -> Edit:
        """Effect ``index``'s play ``step_s`` seconds longer (shorter when negative); a key held
        down undoes as one edit."""
        effect = self.pattern.effects[index]
        return self.resize(index, effect.duration_s + step_s, merge=("resize", index, step_s))

    def change(self, index: int, **fields) -> Edit:
        """Effect ``index`` with ``fields`` changed (the property panel): any of
        :class:`Effect`'s, ``duration_s`` stretching the envelope (:func:`resized`),
        ``intensity`` scaling it (:func:`with_intensity`) and ``dot_s`` the length of every
        dot of a set (:func:`with_dot_length`); the effect's ``ValueError`` when one is
        refused."""
        effect = self.pattern.effects[index]
        if "dot_s" in fields:
            effect = with_dot_length(effect, fields.pop("dot_s"))
        if "duration_s" in fields:
            effect = resized(effect, fields.pop("duration_s"))
        if "intensity" in fields:
            effect = with_intensity(effect, fields.pop("intensity"))
        if fields:
            effect = effect.replace(**fields)
        names = ", ".join(fields) or "its timing"
        return self._with(index, effect, f"Change effect {index + 1}: {names}")

    def change_pattern(self, **fields) -> Edit:
        """The pattern's ``name``, ``combine`` or ``notes`` changed."""
        pattern = self.pattern.replace(**fields)
        return Edit(f"Change the pattern: {', '.join(fields)}", pattern, self.selected)

    def add(self, effect: Effect, text: str = "Add an effect") -> Edit:
        """``effect`` added at the end of the list, and selected."""
        pattern = self.pattern.add(effect)
        return Edit(text, pattern, len(pattern.effects) - 1)

    def delete(self, index: int) -> Edit:
        """Effect ``index`` taken out; the next one in the list selected (else the one before,
        else none)."""
        effects = list(self.pattern.effects)
        del effects[index]
        selected = min(index, len(effects) - 1) if effects else None
        return Edit(f"Delete effect {index + 1}", self.pattern.replace(effects=effects), selected)

    def duplicate(self, index: int) -> Edit:
        """A copy of effect ``index`` right after it (at its end, on its track), selected."""
        effect = self.pattern.effects[index]
        return self.add(effect.replace(start_s=effect.end_s), f"Duplicate effect {index + 1}")

    def replace_all(self, pattern: Pattern, text: str, path=None) -> Edit:
        """Another pattern altogether (opened from ``path``, or imported: None), nothing
        selected."""
        if not isinstance(pattern, Pattern):
            raise ValueError(f"pattern must be a Pattern, got {_validate.shown(pattern)}")
        return Edit(text, pattern, None, path=path)


def describe(effect: Effect) -> str:
    """What an effect plays, in a few words: ``line``, ``3 dots``, ``.tact VestFront``."""
    kind = effect.kind
    if kind == "dots":
        n = len(effect.content.dots)
        return f"{n} dot" + ("" if n == 1 else "s")
    if kind == "tact":
        return f".tact {effect.content.position}".rstrip()
    name = type(effect.content).__name__
    shape = {"TimedPath": "drawn path"}.get(name, name.lower())
    return f"{shape} (TB)" if effect.method == "TB" else shape


def ends_of(effect: Effect) -> list:
    """The times each play of an effect ends, in seconds (``repeat`` of them)."""
    return [effect.start_s + effect.duration_s * (r + 1) for r in range(effect.repeat)]


def span_text(time_s: float) -> str:
    """A time as the editor shows it: ``1.25 s``."""
    return f"{time_s:.2f} s" if math.isfinite(time_s) else "-"
