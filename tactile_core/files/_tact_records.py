"""What a ``.tact`` file holds once checked: plain records, times in seconds, places in
bHaptics' 0..1 (y downward). The reader (``_tact_read``) makes them; the pattern
(``_tact_frames``) plays them."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass


class TactError(ValueError):
    """A ``.tact`` file that cannot be used; the message names the file and the field."""


@dataclass(frozen=True)
class TactPath:
    """One path (one ``pathMode.feedback`` entry), times in seconds from the file's start.

    ``points`` are in bHaptics' 0..1 (y downward). A single point is held from its time to
    the end of its effect: it is stored as two points at the same place.
    """

    position: str
    points: tuple
    times_s: tuple
    intensities: tuple
    pattern: str
    fade: str
    field: str


@dataclass(frozen=True)
class TactDot:
    """One motor of one ``dotMode.feedback`` entry, on from ``start_s`` to ``end_s``.

    Attributes
    ----------
    position : str
    index : int
        The motor's number in the file's layout.
    intensity : float
        In [0, 1].
    start_s, end_s : float
        Seconds from the file's start.
    fade : str
        Its playback type, a linear ramp over the span.
    field : str
        Where it is in the file, for messages.
    x, y : float
        The motor's place in 0..1 (y downward), from ``layout.layouts``.
    closed : bool
        True: on at ``end_s`` too, as bHaptics' compiled frames show a dot at its end time
        (docs/tact.md, "bHaptics' own frames"); False for a compiled frame's value, which holds
        until the next frame starts.
    """

    position: str
    index: int
    intensity: float
    start_s: float
    end_s: float
    fade: str
    field: str
    x: float = 0.0
    y: float = 0.0
    closed: bool = True


@dataclass(frozen=True)
class TactCompiled:
    """A file's compiled form: bHaptics' own frames of motor values.

    Attributes
    ----------
    interval_ms : int
        ``intervalMillis``: the frames' spacing.
    size : int
        ``size``: motors per position (20 on the vest).
    duration_ms : int
        ``durationMillis`` as written.
    frames : dict of str to (tuple of int, tuple of tuple of int)
        Per position, the frames' times (ms, ascending, the ``feedback`` keys) and each
        frame's ``DOT_MODE`` ``values`` (one per motor; 100 is full, more plays as 100).
    path_frames : int
        ``PATH_MODE`` entries, bHaptics' 2017 point format, which are read but not played.
    """

    interval_ms: int
    size: int
    duration_ms: int
    frames: dict
    path_frames: int = 0

    @property
    def end_s(self) -> float:
        """When the last frame ends (its time plus one interval), in seconds."""
        last = max((times[-1] for times, _ in self.frames.values() if times), default=None)
        return 0.0 if last is None else (last + self.interval_ms) / 1e3


@dataclass(frozen=True)
class TactFile:
    """What a ``.tact`` file holds, checked.

    Attributes
    ----------
    name : str
        The project's name ('' when it has none).
    layouts : dict of str to dict of int to (float, float)
        Per device position, each motor's ``(x, y)`` in 0..1 by its index.
    paths, dots : tuple
        :class:`TactPath` and :class:`TactDot` records of the enabled tracks (of the compiled
        frames, each motor's runs of one value, when the file is played in that form).
    duration_s : float
        When the last effect of an enabled track ends, in seconds.
    positions : tuple of str
        The positions that hold paths or dots, in the order they first appear.
    connected : tuple of (str, str, int)
        ``(position, field, dots)`` of each played dot effect with ``dotConnected: true``
        (played as bHaptics plays it: each dot fading into the next entry's).
    ends_s : dict of str to float
        Per position with content, when the last effect holding its paths or dots ends, in
        seconds (what that position lasts played alone).
    compiled : TactCompiled or None
        The compiled form (``feedback`` frames), when the file carries one.
    form : {"project", "compiled"}
        Which form ``paths`` and ``dots`` were read from.
    """

    name: str
    layouts: dict
    paths: tuple
    dots: tuple
    duration_s: float
    positions: tuple
    connected: tuple = ()
    ends_s: dict = dataclasses.field(default_factory=dict)
    compiled: TactCompiled | None = None
    form: str = "project"

    @property
    def notes(self) -> tuple:
        """What of the file does not play, in words (empty if nothing)."""
        compiled = self.compiled
        if compiled is not None and compiled.path_frames and self.form == "compiled":
            return (f"{compiled.path_frames} compiled PATH_MODE entries (bHaptics' 2017 "
                    "point format) are not played",)  # fmt: skip
        return ()
