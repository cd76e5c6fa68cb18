"""What the OSC server counts, as one immutable snapshot, and how it reads on a terminal."""

from __future__ import annotations

from dataclasses import asdict, dataclass

MAX_TEXT = 160
"""Longest text the counters keep (a problem, an address): a status line stays one line."""
LINE_PROBLEM = 100
"""Characters of the latest problem a status line shows."""

PROBLEMS = (
    ("malformed", "malformed"),
    ("too_large", "too large"),
    ("unknown", "unknown address"),
    ("wrong_type", "wrong arguments"),
    ("non_finite", "non-finite"),
    ("out_of_range", "out of range"),
    ("refused", "refused"),
    ("flood_dropped", "dropped (over the rate limit)"),
    ("kernel_dropped", "dropped by the system (buffer full)"),
    ("errors", "internal errors"),
)
"""The counters of messages that did nothing, with their names on the status line."""


def shortened(text: str, limit: int = MAX_TEXT) -> str:
    """``text`` cut to ``limit`` characters, an ellipsis saying so."""
    return text if len(text) <= limit else text[: limit - 1] + "…"


@dataclass(frozen=True)
class ServeStats:
    """Counters of an :class:`~tactile_core.serve.OscServer`, read at one moment.

    Attributes
    ----------
    address : str
        ``host:port`` the server listens on.
    datagrams, messages : int
        UDP datagrams received; OSC messages read from them (bundles hold several).
    points, releases, controls, shapes : int
        Point updates applied; releases (``/tactile/release``); ``/tactile/method``, ``mu``,
        ``gamma`` and ``off`` applied; shapes started.
    malformed : int
        Datagrams that are not OSC packets (or exceed a bound before they are read: more than
        16 type tags in a message, bundles too deep).
    too_large : int
        Datagrams longer than :data:`~._osc_wire.MAX_DATAGRAM_BYTES`, never read.
    unknown : int
        Messages to an address the server does not have.
    wrong_type : int
        Messages with the wrong number or types of arguments.
    non_finite : int
        Messages with a NaN or an infinity.
    out_of_range : int
        Values outside their range (intensity, coordinates, a point id, more than the points
        the table holds).
    refused : int
        Well-formed messages the server cannot honour (a method that needs a shape for points,
        an unknown method, a bad shape spec), with the reason in ``last_problem``.
    flood_dropped : int
        Datagrams over their sender's share of the rate limit, dropped unread (``/tactile/off``
        and ``/tactile/release`` are always read), and the messages of a bundle beyond the 256
        read.
    kernel_dropped : int
        Datagrams the operating system dropped because the receive buffer was full (Linux).
    errors : int
        Messages whose handling raised unexpectedly (a bug; the server goes on).
    queries : int
        ``/tactile/state`` and ``/tactile/reply`` messages read.
    replies, replies_dropped : int
        Replies sent (``/tactile/error``, ``/tactile/state``); replies over the reply rate or
        that did not fit the socket's buffer.
    timed_out : int
        Points released because they were not refreshed within the timeout.
    active_points : int
        Points in the table now.
    rate_hz : float
        Messages per second over about the last second (all received, read or not).
    last_sender, last_address, last_problem : str
        Who sent the latest datagram (``host:port``), the latest address read, and the latest
        problem with the message's address and why (at most :data:`MAX_TEXT` characters).
    playing : str
        ``"points"``, or the shape being played (its spec, or the start of it and its number of
        points when it is long).
    elapsed_s : float
        Seconds since the server started.
    """

    address: str = ""
    datagrams: int = 0
    messages: int = 0
    points: int = 0
    releases: int = 0
    controls: int = 0
    shapes: int = 0
    queries: int = 0
    malformed: int = 0
    too_large: int = 0
    unknown: int = 0
    wrong_type: int = 0
    non_finite: int = 0
    out_of_range: int = 0
    refused: int = 0
    flood_dropped: int = 0
    kernel_dropped: int = 0
    errors: int = 0
    replies: int = 0
    replies_dropped: int = 0
    timed_out: int = 0
    active_points: int = 0
    rate_hz: float = 0.0
    last_sender: str = ""
    last_address: str = ""
    last_problem: str = ""
    playing: str = "points"
    elapsed_s: float = 0.0

    @property
    def problems(self) -> int:
        """Messages (and datagrams) that did nothing: the sum of the problem counters."""
        return sum(getattr(self, key) for key, _ in PROBLEMS)

    def line(self) -> str:
        """One status line: traffic, sender, points, any problems and the latest of them
        (bounded: a few hundred characters whatever a sender sends)."""
        sender = f" from {self.last_sender}" if self.last_sender else ""
        text = (
            f"osc {self.address}: {self.messages} messages ({self.rate_hz:.0f}/s){sender}; "
            f"{self.active_points} points, playing {self.playing}"
        )
        problems = [f"{getattr(self, k)} {name}" for k, name in PROBLEMS if getattr(self, k)]
        if self.timed_out:
            problems.append(f"{self.timed_out} {_plural(self.timed_out, 'point')} timed out")
        if problems:
            text += "; " + ", ".join(problems)
        if self.last_problem:
            text += f"; last: {shortened(self.last_problem, LINE_PROBLEM)}"
        return text

    def summary(self) -> str:
        """The final report, a few lines."""
        lines = [
            f"served {self.elapsed_s:.1f} s on {self.address}: {self.datagrams} datagrams, "
            f"{self.messages} messages",
            f"  applied: {self.points} point updates, {self.releases} releases, "
            f"{self.controls} controls, {self.shapes} shapes, {self.queries} queries; "
            f"{self.timed_out} {_plural(self.timed_out, 'point')} timed out; {self.replies} "
            f"{'reply' if self.replies == 1 else 'replies'} sent, "
            f"{self.replies_dropped} dropped",
            "  did nothing: " + ", ".join(f"{getattr(self, k)} {name}" for k, name in PROBLEMS),
        ]
        if self.last_problem:
            lines.append(f"  last problem: {self.last_problem}")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """The JSON form (``tactile serve --json``)."""
        return {**asdict(self), "problems": self.problems}


def _plural(n: int, word: str) -> str:
    """``word`` for one, ``word + "s"`` for any other count."""
    return word if n == 1 else word + "s"
