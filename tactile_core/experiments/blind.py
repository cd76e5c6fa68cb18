"""Blind A/B: methods shuffled onto number keys, felt, rated, and only then revealed.

The paper's Experiment 1 preparation stage (section 3.4.2) as a session without a window: the
tuner's *Blind A/B* tab is its view, and a plain script drives it just as well (see
``docs/scripting.md``). A :class:`BlindSession` holds

- the **mapping**: the methods shuffled onto keys 1-N with a seed (:func:`shuffled`);
- the **felt time** per key, measured on an injected clock (a callable returning monotonic
  seconds, :func:`time.monotonic` by default) while a key plays, until *Reveal* (what is felt once
  the mapping is known is not blind);
- the **ratings**: 0-100 for each of :data:`RATINGS` per key, None while not rated (never a
  value that could pass for a rating);
- the **rules**: only a key that was played can be rated; *Reveal* and *Save* need every key
  that was felt rated; a key never played is saved as not rated;
- the **autosave**: every rating is written at once, atomically, to a CSV in ``autosave_dir``
  whose ``method`` column stays empty until *Reveal*; :meth:`BlindSession.from_autosave` reads
  one back (the mapping recovered from its ``methods`` and ``seed`` columns). The files'
  columns, writing and reading are in ``_blind_file``.

>>> clock = iter([0.0, 2.5]).__next__  # seconds: a fake clock
>>> session = BlindSession(["AS", "IM"], clock=clock)
>>> session.start(seed=1)
>>> session.select(1) in ("AS", "IM")  # key 1 plays from 0 s
True
>>> session.set_playing(False)  # off at 2.5 s
>>> session.felt_s
(2.5, 0.0)
>>> session.missing()
['key 1 quality', 'key 1 smoothness', 'key 1 thickness']
"""

from __future__ import annotations

import datetime as dt
import random
import time
from pathlib import Path

from .._shared import validate as _validate
from ..rendering.methods import PAPER_METHODS, get_method
from ._blind_file import (
    AUTOSAVE_COLUMNS,
    COLUMNS,
    RATINGS,
    append_rows,
    read_autosave,
    scene_columns,
    write_autosave,
)

__all__ = ["AUTOSAVE_COLUMNS", "COLUMNS", "RATINGS", "BlindSession", "shuffled"]

MIN_METHODS, MAX_METHODS = 2, 8
"""How many methods a session shuffles onto keys."""


def shuffled(methods, seed: int) -> list[str]:
    """The methods on keys 1-N of a session with ``seed``: ``methods`` shuffled by
    ``random.Random(seed)``. How :meth:`BlindSession.start` deals them, and how an autosave's
    mapping is recovered from its ``methods`` and ``seed`` columns."""
    mapping = list(methods)
    random.Random(seed).shuffle(mapping)
    return mapping


def _check_methods(methods) -> tuple[str, ...]:
    if isinstance(methods, str) or not hasattr(methods, "__iter__"):
        raise ValueError(f"methods must be a list of method names, got {_validate.shown(methods)}")
    methods = tuple(methods)
    for m in methods:
        if not isinstance(m, str):
            raise ValueError(f"methods must be method names, got {_validate.shown(m)}")
        get_method(m)  # an unknown name or bad parameters: ValueError naming it
    if not MIN_METHODS <= len(methods) <= MAX_METHODS or len(set(methods)) != len(methods):
        raise ValueError(f"blind A/B needs {MIN_METHODS} to {MAX_METHODS} distinct methods, "
                         f"got {list(methods)}")  # fmt: skip
    return methods


class BlindSession:
    """One blind A/B session: shuffle, feel, rate, reveal, save.

    Parameters
    ----------
    methods : sequence of str
        2-8 distinct method specs (the paper's four by default).
    clock : callable, keyword-only
        Monotonic seconds now (:func:`time.monotonic` by default; tests pass a fake one).
    autosave_dir : str or Path or None, keyword-only
        Where each session's ratings are autosaved as they are entered (None: not autosaved).

    Attributes
    ----------
    mapping : tuple of str
        The method behind each key, key 1 first (empty before :meth:`start`).
    seed : int or None
    session : str
        When the session started (ISO 8601, to the second): the ``session`` column.
    current_key : int or None
        The key selected last (1-N).
    playing : bool
        Whether the selected key is being played (felt time runs while it is, before Reveal).
    revealed : bool
    unsaved : bool
        True once a rating was entered that no :meth:`save` has written yet.
    autosave_path : Path or None
        This session's autosave (None without ``autosave_dir`` or before a session).
    autosave_error : str
        Why the last autosave failed ("" when it did not); the ratings stay in the session.
    scene_before : Scene or None
        The :attr:`scene` when the session started (what :meth:`cancel` gives back).
    listeners : list of callable
        Called with no arguments after every change (the tuner's panel redraws from them).

    Notes
    -----
    Felt time accrues on the selected key while :attr:`playing`, from :meth:`select` or
    :meth:`set_playing` to the next such call, :meth:`reveal` or :meth:`cancel`; a key felt for
    no time at all counts as not felt.
    """

    def __init__(self, methods=PAPER_METHODS, *, clock=time.monotonic, autosave_dir=None):
        if not callable(clock):
            raise ValueError(f"clock must be a callable returning seconds, got "
                             f"{_validate.shown(clock)}")  # fmt: skip
        self.clock = clock
        self.autosave_dir = None if autosave_dir is None else Path(autosave_dir)
        self._methods = _check_methods(methods)
        self.mapping: tuple[str, ...] = ()
        self.seed: int | None = None
        self.session = ""
        self.current_key: int | None = None
        self.playing = False
        self.revealed = False
        self.unsaved = False
        self.autosave_path: Path | None = None
        self.autosave_error = ""
        self.scene_before = None
        self.listeners: list = []
        self._scene = None
        self._scene_columns = scene_columns(None)
        self._felt: list[float] = []
        self._ratings: list[dict] = []
        self._since: float | None = None  # clock time the running stretch of felt time began

    # --- what it holds -------------------------------------------------------------------------

    @property
    def methods(self) -> tuple[str, ...]:
        """The methods the next :meth:`start` shuffles (:meth:`set_methods` changes them)."""
        return self._methods

    @property
    def active(self) -> bool:
        """True while a mapping is dealt and not yet revealed (the method must stay hidden)."""
        return bool(self.mapping) and not self.revealed

    @property
    def scene(self):
        """The scene the ratings are given on (its shape, mu, gamma and timing go in each row);
        the owner keeps it current. Setting it notifies no one."""
        return self._scene

    @scene.setter
    def scene(self, scene) -> None:
        self._scene = scene
        self._scene_columns = scene_columns(scene)

    @property
    def felt_s(self) -> tuple[float, ...]:
        """Seconds each key was played before Reveal, up to now."""
        felt = list(self._felt)
        if self._since is not None:
            felt[self.current_key - 1] += max(0.0, self._now() - self._since)
        return tuple(felt)

    def felt(self) -> list[bool]:
        """Per key: was it played (for any time) before Reveal?"""
        return [s > 0.0 for s in self.felt_s]

    def rating(self, key: int, name: str) -> int | None:
        """Key ``key``'s rating ``name`` (one of :data:`RATINGS`): 0-100, or None (not rated)."""
        key = self._check_key(key)
        _validate.choice("name", name, RATINGS)
        return self._ratings[key - 1][name]

    def missing(self) -> list[str]:
        """What is still to rate: ``"key 2 smoothness"`` for each felt key's empty rating."""
        return [f"key {k + 1} {name}"
                for k, was_felt in enumerate(self.felt()) if was_felt
                for name in RATINGS if self._ratings[k][name] is None]  # fmt: skip

    def refusal(self, action: str) -> str:
        """Why ``action`` ("Reveal", "Save") may not happen now ("" when it may)."""
        if not self.mapping:
            return f"{action}: no session (start one first)"
        if not any(self.felt()):
            return f"{action}: no key was felt yet"
        missing = self.missing()
        if missing:
            return f"{action} needs every key you felt rated: still empty: {', '.join(missing)}"
        return ""

    # --- what changes it -----------------------------------------------------------------------

    def set_methods(self, methods) -> None:
        """Use another set of methods (2-8 distinct specs) from the next :meth:`start`; refused
        (``ValueError``) during a session or while its ratings are not saved."""
        methods = _check_methods(methods)
        if self.active:
            raise ValueError("blind A/B is running: reveal it before changing the methods")
        if self.unsaved:
            raise ValueError("the session's ratings are not saved: save them or cancel the "
                             "session before changing the methods")  # fmt: skip
        self._methods = methods
        self._reset(())
        self._changed()

    def start(self, seed: int | None = None, *, started=None, discard: bool = False) -> None:
        """Shuffle the methods onto keys 1-N (``seed``: a whole number >= 0, None for a random
        one) and hide the mapping; every rating empty, no key selected or felt.

        ``started`` (a :class:`datetime.datetime`, now by default) names the session. Over a
        session whose ratings are not saved, only with ``discard=True`` (they stay in its
        autosave); otherwise ``ValueError`` says so.
        """
        if self.unsaved and not discard:
            raise ValueError(f"the ratings of this session are not saved{self._where()}: save "
                             "them, or start again with discard=True")  # fmt: skip
        if seed is None:
            seed = random.SystemRandom().randrange(2**31)
        seed = _validate.integer("seed", seed, 0)
        started = dt.datetime.now() if started is None else started
        if not isinstance(started, dt.datetime):
            raise ValueError(f"started must be a datetime, got {_validate.shown(started)}")
        if not self.active:
            self.scene_before = self._scene
        self.seed = seed
        self._reset(tuple(shuffled(self._methods, seed)))
        self.session = started.isoformat(timespec="seconds")
        if self.autosave_dir is not None:
            stamp = self.session.replace(":", "")
            self.autosave_path = self.autosave_dir / f"blind-ab-{stamp}-seed{seed}.csv"
        self._changed()

    def select(self, key: int, *, playing: bool = True) -> str:
        """Select ``key`` (1-N), playing from now (``playing=False``: selected, off); returns
        the method behind it, for the caller to play."""
        key = self._check_key(key)
        self._fold()
        self.current_key = key
        self.playing = _validate.boolean("playing", playing)
        self._run()
        if self.unsaved:
            self.autosave()
        self._changed()
        return self.mapping[key - 1]

    def set_playing(self, playing: bool) -> None:
        """Whether the selected key is playing now (felt time runs only while it is)."""
        playing = _validate.boolean("playing", playing)
        if playing == self.playing:
            return
        self._fold()
        self.playing = playing
        self._run()
        self._changed()

    def rate(self, key: int, name: str, value: int | None) -> None:
        """Rate ``key``'s ``name`` (one of :data:`RATINGS`) ``value``, a whole number 0-100, or
        None to clear it; autosaved at once. Only a key that was played can be rated."""
        key = self._check_key(key)
        _validate.choice("name", name, RATINGS)
        if value is not None:
            value = _validate.integer(f"{name} of key {key}", value, 0, 100)
            if not self.felt()[key - 1]:
                raise ValueError(f"key {key} was not played: play it before rating it (a key "
                                 "never played is saved as not rated)")  # fmt: skip
        if self._ratings[key - 1][name] == value:
            return
        self._ratings[key - 1][name] = value
        self.unsaved = True
        self.autosave()
        self._changed()

    def reveal(self) -> None:
        """Reveal the mapping; ``ValueError`` (:meth:`refusal`) while a felt key is unrated.
        Felt time stops here."""
        why = self.refusal("Reveal")
        if why:
            raise ValueError(why)
        if self.revealed:
            return
        self._fold()
        self.revealed = True
        self._since = None
        if self.unsaved:
            self.autosave()
        self._changed()

    def cancel(self):
        """End the session without rating everything; its ratings, if not saved, stay in the
        autosave. Returns the scene from before the session when it was still blind (for the
        owner to put back), else None."""
        if not self.mapping:
            return None
        was_blind = self.active
        self._fold()
        if self.unsaved:
            self.autosave()
        before, self.scene_before = self.scene_before, None
        self._reset(())
        self._changed()
        return before if was_blind else None

    # --- files ---------------------------------------------------------------------------------

    def rows(self) -> list[dict]:
        """One row per key in :data:`COLUMNS`: the mapping, whether and how long each key was
        felt, its ratings ("" when not rated), the scene and the seed."""
        felt = self.felt_s
        return [
            {
                "session": self.session,
                "key": k + 1,
                "method": method,
                "felt": int(felt[k] > 0.0),
                "felt_s": f"{felt[k]:.2f}",
                **{name: "" if v is None else v for name, v in self._ratings[k].items()},
                **self._scene_columns,
                "seed": self.seed,
                "revealed_before_save": self.revealed,
            }
            for k, method in enumerate(self.mapping)
        ]

    def autosave(self) -> bool:
        """Write the session as it stands to :attr:`autosave_path` (atomically; the method
        column empty until Reveal, the methods in ``methods``). False, and the reason in
        :attr:`autosave_error`, when it could not be written."""
        if self.autosave_path is None or not self.mapping:
            return False
        rows = self.rows()
        for row in rows:
            if not self.revealed:
                row["method"] = ""
            row["methods"] = " ".join(self._methods)
        try:
            write_autosave(self.autosave_path, rows)
        except (OSError, ValueError) as exc:
            self.autosave_error = f"could not autosave the ratings: {exc}"
            return False
        self.autosave_error = ""
        return True

    def save(self, path) -> Path:
        """Append the rows to the CSV ``path`` (the header for a new file), rewriting it
        atomically so that a full disk never loses the earlier rows; the autosave then goes.

        Raises
        ------
        ValueError
            While a felt key is unrated (:meth:`refusal`), or ``path`` cannot be written or
            holds other columns (an ``OutputError``).
        """
        why = self.refusal("Save")
        if why:
            raise ValueError(why)
        path = append_rows(path, self.rows())
        self.unsaved = False
        if self.autosave_path is not None:
            self.autosave_path.unlink(missing_ok=True)
        self._changed()
        return path

    @classmethod
    def from_autosave(cls, path, *, clock=time.monotonic) -> BlindSession:
        """The session an autosave holds, to go on with (no key selected; further ratings are
        autosaved to the same file). ``ValueError`` names what is wrong with the file."""
        held = read_autosave(path)
        session = cls(held["methods"], clock=clock)
        session.seed = held["seed"]
        session._reset(tuple(shuffled(held["methods"], held["seed"])))
        revealed = [m for m in held["revealed_methods"] if m]
        if revealed and list(held["revealed_methods"]) != list(session.mapping):
            raise ValueError(f"{path}: its methods do not follow from its seed and methods")
        session._felt = list(held["felt_s"])
        session._ratings = [dict(r) for r in held["ratings"]]
        session.session = held["session"]
        session.revealed = held["revealed"]
        session._scene_columns = dict(held["scene"])
        session.unsaved = True
        session.autosave_path = Path(path)
        return session

    # --- machinery -----------------------------------------------------------------------------

    def _now(self) -> float:
        return float(self.clock())

    def _check_key(self, key) -> int:
        if not self.mapping:
            raise ValueError("no blind A/B session: start() one first")
        return _validate.integer("key", key, 1, len(self.mapping))

    def _fold(self) -> None:
        """Add the running stretch of felt time to the selected key."""
        if self._since is not None:
            now = self._now()
            self._felt[self.current_key - 1] += max(0.0, now - self._since)
            self._since = now

    def _run(self) -> None:
        """Felt time runs from now while a key plays before Reveal."""
        running = self.playing and self.current_key is not None and self.active
        self._since = self._now() if running else None

    def _reset(self, mapping: tuple) -> None:
        self.mapping = mapping
        self.current_key = None
        self.revealed = False
        self.unsaved = False
        self._since = None
        self._felt = [0.0] * len(mapping)
        self._ratings = [dict.fromkeys(RATINGS) for _ in mapping]

    def _where(self) -> str:
        return f" (autosaved in {self.autosave_path})" if self.autosave_path else ""

    def _changed(self) -> None:
        for listener in list(self.listeners):
            listener()
