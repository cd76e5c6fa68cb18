"""Replies of the OSC server to its senders: a refused message's reason, the state on request.

A Max or TouchDesigner patch sends from one port and listens on another (``[udpsend]`` and
``[udpreceive 9101]``; an OSC Out and an OSC In DAT), so a reply to a datagram's source port
would reach nobody there. Replies therefore go where the sender asked:

- ``/tactile/reply PORT``: from now on, replies to this sender go to its host at ``PORT``;
  ``/tactile/reply`` without a port: to the address the datagram came from (a client that
  sends and listens on one socket: python-osc's server socket, liblo, SuperCollider, Pd's
  ``[netsend -u -b]``); ``/tactile/reply 0``: none again;
- ``tactile serve --reply-port PORT``: every sender that did not say otherwise gets its replies
  at its host on ``PORT``.

Without either, a refused message gets no reply (the default: nothing unasked goes out), and a
``/tactile/state`` query is answered to the address it came from. Replies are rate-limited
(:data:`REPLY_RATE_HZ`, all senders together; beyond, they are dropped and counted) and sent
without blocking: a reply that does not fit the socket's send buffer is dropped, never waited
for, so the receiver is never held up by them.
"""

from __future__ import annotations

import socket

from ._osc_wire import encode_message

REPLY_RATE_HZ = 100.0
"""Replies sent per second at most, to all senders together."""
REPLY_BURST = 20
"""Replies that may go at once after a quiet spell."""
MAX_DESTINATIONS = 64
"""Senders whose reply address is remembered; beyond, the oldest is forgotten."""
REPLY_ADDRESSES = ("/tactile/error", "/tactile/state")
"""What the server sends: another server's replies arriving here are never answered (two
servers replying to each other's errors would ping-pong)."""
_OFF = "off"
_DONTWAIT = getattr(socket, "MSG_DONTWAIT", 0)


class Replies:
    """Where each sender's replies go, and sending them.

    Parameters
    ----------
    port : int or None
        Every sender's replies go to its host at this port unless it asked otherwise (``tactile
        serve --reply-port``); None: only to senders that asked.
    """

    def __init__(self, port: int | None = None):
        self.port = port
        self._to: dict = {}  # sender -> destination address, or _OFF
        self._tokens = float(REPLY_BURST)
        self._last = None
        self.sent = 0
        self.dropped = 0

    def ask(self, sender: tuple, port: int | None) -> None:
        """``sender`` asked for replies at its host on ``port`` (None: where it sends from;
        0: no replies)."""
        if len(self._to) >= MAX_DESTINATIONS and sender not in self._to:
            del self._to[next(iter(self._to))]
        if port == 0:
            self._to[sender] = _OFF
        else:
            self._to[sender] = sender if port is None else (sender[0], port, *sender[2:])

    def destination(self, sender: tuple, query: bool = False):
        """Where a reply to ``sender`` goes, or None; a ``query`` is always answered (where it
        came from, if the sender named no other place)."""
        found = self._to.get(sender)
        if found is _OFF:
            return sender if query else None
        if found is not None:
            return found
        if self.port is not None:
            return (sender[0], self.port, *sender[2:])
        return sender if query else None

    def send(self, sock, to, address: str, args, now: float) -> bool:
        """Send one reply (at most :data:`REPLY_RATE_HZ` a second; never blocking); whether it
        went."""
        if self._last is not None:
            self._tokens = min(REPLY_BURST, self._tokens + (now - self._last) * REPLY_RATE_HZ)
        self._last = now
        if self._tokens < 1.0 or sock is None:
            self.dropped += 1
            return False
        self._tokens -= 1.0
        try:
            sock.sendto(encode_message(address, args), _DONTWAIT, to)
        except OSError:  # the send buffer is full, the host unreachable: dropped, not waited for
            self.dropped += 1
            return False
        self.sent += 1
        return True
