"""What a datagram costs the OSC server, and each sender's share of the rate limit.

The rate limit (``max_rate_hz``, ``--max-rate``) counts *units* of work, not datagrams; a unit
is about what a point message costs (5-10 µs to receive, read and apply). A datagram costs one
unit per started :data:`BYTES_PER_UNIT` bytes, charged before it is read (a point message,
28-48 bytes, is one; a bundle of 256 point messages 256); a message that changes the scene
(``/tactile/method``, ``mu``, ``gamma``, ``shape``) :data:`SCENE_UNITS` more (20-50 µs to apply,
and the output thread takes up a new plan), and a ``/tactile/shape`` one more per point of its
shape (reading a polyline costs about 4 µs a point). What a datagram may hold is bounded before
it is read (:data:`~._osc_wire.MAX_DATAGRAM_BYTES`, :data:`~._osc_wire.MAX_ARGUMENTS`,
:data:`~._osc_addresses.MAX_SHAPE_NUMBERS`), and its messages are read only while what they
cost beyond its bytes stays within one bucket (the rest are dropped), so no datagram costs more
than a few milliseconds and the work per second stays within ``max_rate_hz`` units whatever
arrives.

Each sender (address and port) has a token bucket of its own, filled at an equal share of the
rate (``max_rate_hz`` over the senders heard within the last second) and holding
:data:`WINDOW_S` of it: a sender that floods spends its own share, and a patch holding a point
from another socket is read as before. A datagram is read while its sender's bucket is above
zero, and its cost may take the bucket below (a debt paid back before the next is read), so the
units read per second are the rate limit, the buckets' size aside.
"""

from __future__ import annotations

import math

from ._osc_addresses import MAX_SHAPE_NUMBERS

BYTES_PER_UNIT = 64
"""Bytes of a datagram charged as one unit of the rate limit."""
SCENE_UNITS = 10
"""Units a message that changes the scene costs beyond its bytes."""
SCENE_ADDRESSES = ("/tactile/method", "/tactile/mu", "/tactile/gamma", "/tactile/shape")
WINDOW_S = 0.05
"""Seconds of its share a sender's bucket holds: the burst it may send at once."""
IDLE_S = 1.0
"""A sender not heard for this long no longer takes a share."""
MAX_SENDERS = 256
"""Senders with a bucket of their own; beyond, new ones share one bucket."""


def datagram_units(size: int) -> int:
    """Units a datagram of ``size`` bytes is charged before it is read (at least 1)."""
    return max(1, -(-size // BYTES_PER_UNIT))


def message_units(address: str, args: list) -> int:
    """Units a message read from a datagram costs beyond the datagram's bytes: 0 for most,
    :data:`SCENE_UNITS` for a scene change, plus a point per two numbers of a shape's spec."""
    if address not in SCENE_ADDRESSES:
        return 0
    if address == "/tactile/shape" and args and type(args[0]) is str:
        numbers = args[0].count(",") + 1
        return SCENE_UNITS + (numbers // 2 if numbers <= MAX_SHAPE_NUMBERS else 0)  # (beyond:
        # refused unread)
    return SCENE_UNITS


class SenderBudgets:
    """Token buckets per sender, sharing ``rate_hz`` units a second equally.

    Parameters
    ----------
    rate_hz : float
        Units a second for all senders together.
    """

    def __init__(self, rate_hz: float):
        self.rate_hz = float(rate_hz)
        self._buckets: dict = {}  # sender -> [tokens, last heard]
        self._pruned = -math.inf

    def bucket(self, sender, now: float) -> list:
        """``sender``'s bucket, filled up to ``now``: ``[tokens, time, size]`` (a datagram is
        read while ``tokens >= 1``; subtract what it costs from ``bucket[0]``, its bytes first,
        then its messages while that takes at most ``size`` more)."""
        buckets = self._buckets
        if now - self._pruned > 0.25:
            self._prune(now)
        found = buckets.get(sender)
        if found is None:
            if len(buckets) >= MAX_SENDERS:
                sender = None  # the shared bucket of the senders beyond
                found = buckets.get(None)
            if found is None:
                size = max(1.0, self.rate_hz / (len(buckets) + 1) * WINDOW_S)
                found = buckets[sender] = [size, now, size]
                return found
        share = self.rate_hz / len(buckets)
        found[2] = size = max(1.0, share * WINDOW_S)
        found[0] = min(size, found[0] + (now - found[1]) * share)
        found[1] = now
        return found

    def _prune(self, now: float) -> None:
        self._pruned = now
        idle = [s for s, (_, last, _) in self._buckets.items() if now - last > IDLE_S]
        for sender in idle:
            del self._buckets[sender]

    @property
    def senders(self) -> int:
        """Senders holding a bucket now."""
        return len(self._buckets)
