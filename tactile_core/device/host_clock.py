"""The host's clock as the streamer uses it, real or virtual.

:class:`HostClock` is ``time.perf_counter`` with the two ways the output thread waits: on an
event with a timeout (a scene change wakes it) and a short busy spin before a deadline.
:class:`VirtualClock` has the same interface over time that moves only when the thread waits:
a wait returns at once with the clock that much later. A stream on a virtual clock makes its
frames as fast as the machine can and stamps each with the time it would have had, so a test
checks intervals, keep-alives and watchdogs exactly, whatever else the machine is doing.
"""

from __future__ import annotations

import os
import threading
import time


class HostClock:
    """The real clock: ``time.perf_counter`` seconds."""

    def now(self) -> float:
        """Seconds on the clock."""
        return time.perf_counter()

    def wait(self, event: threading.Event, timeout_s: float) -> bool:
        """Wait up to ``timeout_s`` for ``event``; True if it was set."""
        return event.wait(timeout_s)

    def spin_until(self, deadline_s: float) -> None:
        """Busy-wait until the clock reads ``deadline_s`` (the last fraction of a millisecond)."""
        while time.perf_counter() < deadline_s:
            pass

    def sleep(self, seconds: float) -> None:
        """Sleep for ``seconds``."""
        time.sleep(seconds)


class VirtualClock(HostClock):
    """Time that passes only when waited for.

    A wait on an event that is not set moves the clock forward by its whole timeout and returns
    at once (after yielding to other threads); a spin moves it to the deadline. Several threads
    may wait on it: each wait moves the one shared clock.

    Parameters
    ----------
    start_s : float
        The clock's first reading.
    """

    def __init__(self, start_s: float = 1000.0):
        self._now = float(start_s)
        self._lock = threading.Lock()

    def now(self) -> float:
        return self._now

    def advance(self, seconds: float) -> None:
        """Move the clock ``seconds`` forward."""
        with self._lock:
            self._now += max(float(seconds), 0.0)

    def wait(self, event: threading.Event, timeout_s: float) -> bool:
        if event.is_set():
            return True
        self.advance(timeout_s)
        time.sleep(0)  # let the other threads run: the waiting is what they would have had
        return event.is_set()

    def spin_until(self, deadline_s: float) -> None:
        with self._lock:
            self._now = max(self._now, float(deadline_s))

    def sleep(self, seconds: float) -> None:
        self.advance(seconds)
        time.sleep(0)


def raise_priority(priority: int = 10) -> str:
    """Try to give the calling thread real-time priority (SCHED_FIFO ``priority``, 10 for the
    output thread); say what happened (empty when granted).

    Linux grants it to root or to users with an ``rtprio`` limit (``ulimit -r``, or
    ``/etc/security/limits.conf``). The output thread sleeps most of each frame and spins at most
    ``spin_s``, so it cannot starve the machine.

    Parameters
    ----------
    priority : int
        The SCHED_FIFO priority, 1-99.

    Returns
    -------
    str
        Empty when granted; otherwise why not, for a status line.
    """
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(priority))
    except AttributeError:
        return "real-time priority is not available on this system"
    except PermissionError:
        return "real-time priority not permitted (raise the rtprio limit: ulimit -r 10)"
    except OSError as exc:
        return f"real-time priority failed: {exc}"
    return ""
