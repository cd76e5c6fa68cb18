"""How a stream runs: one options object from ``open_stream`` down to the output thread.

:class:`StreamOptions` travels unchanged from the program that opens a stream (the tuner, the
command line, a script) through :func:`~tactile_core.stream.open_stream` and, for a stream in
a child process, down the pipe to the child's :class:`~tactile_core.stream.Streamer`. The lead
is checked here and nowhere else: :func:`check_lead_ms` is what a command-line flag, a preset
field, a tuner setting and a script's argument all call.
"""

from __future__ import annotations

from dataclasses import dataclass

from .._shared import validate as _validate

MAX_LEAD_MS = 500.0
"""Longest lead, in ms: frames are never scheduled further ahead than this on the array's clock.
Half a second is already far beyond a felt delay (an onset a person notices as late); a longer
lead would only hide a host that cannot keep up."""

DEFAULT_LEAD_MS = 20.0
"""The lead ``tactile stream``, ``tactile serve``, the tuner and presets use unless told: from the
lead table in docs/benchmarks.md, the shortest lead that kept every timed frame on time with both
host cores busy."""


def check_lead_ms(value, name: str = "lead_ms") -> float:
    """``value`` as milliseconds within ``[0, MAX_LEAD_MS]``; ``ValueError`` naming ``name``.

    Parameters
    ----------
    value : float
        The lead, in milliseconds.
    name : str
        How the caller calls it in a message (``"--lead-ms"``, ``"field 'lead_ms'"``).

    Returns
    -------
    float

    Examples
    --------
    >>> check_lead_ms(20)
    20.0
    >>> check_lead_ms(600, "--lead-ms")
    Traceback (most recent call last):
    ...
    ValueError: --lead-ms must be within [0, 500] milliseconds, got 600
    """
    if not _validate.is_number(value) or not 0.0 <= value <= MAX_LEAD_MS:
        raise ValueError(
            f"{name} must be within [0, {MAX_LEAD_MS:g}] milliseconds, got {_validate.shown(value)}"
        )
    return float(value)


@dataclass(frozen=True)
class StreamOptions:
    """How a stream runs (immutable; pickled to a stream's child process as it is).

    Parameters
    ----------
    reconnect : bool
        After a link error, retry every 0.5 s instead of stopping (a pulled USB cable).
    realtime : bool
        Ask for real-time scheduling (SCHED_FIFO) of the output thread (Linux, with
        privileges; the stream's status says when it is refused).
    lead_ms : float
        Send frames this far ahead, timed on the array's clock, to arrays that announce
        scheduled frames (0 to :data:`MAX_LEAD_MS`; 0: every frame is played on arrival).
    own_core : bool
        With two or more cores, a stream in a child process runs on a core of its own and the
        program on the others until the stream stops (Linux); ignored by a stream in a thread.

    Examples
    --------
    >>> StreamOptions(lead_ms=20).lead_s
    0.02
    """

    reconnect: bool = False
    realtime: bool = False
    lead_ms: float = 0.0
    own_core: bool = False

    def __post_init__(self):
        for name in ("reconnect", "realtime", "own_core"):
            value = getattr(self, name)
            if not isinstance(value, bool):
                raise ValueError(f"{name} must be True or False, got {_validate.shown(value)}")
        object.__setattr__(self, "lead_ms", check_lead_ms(self.lead_ms))

    @property
    def lead_s(self) -> float:
        """The lead in seconds."""
        return self.lead_ms / 1e3
