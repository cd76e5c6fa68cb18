"""Helpers of the OSC server and LSL tests: waiting on conditions, an in-process server on a
free port streaming to the simulated array with a recording tap, expected levels."""

import threading
import time

import numpy as np

import tactile_core as tc
from tactile_core.device.link import SimulatedArray
from tactile_core.device.profile import default_profile
from tactile_core.rendering.scene import Scene
from tactile_core.serve import OscServer
from tactile_core.stream.streamer import Streamer


def wait_for(predicate, timeout_s=10.0, what="the condition"):
    """Poll ``predicate`` until true; fail after ``timeout_s`` (a bound, never a duration the
    test relies on)."""
    deadline = time.monotonic() + timeout_s
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"{what} did not happen within {timeout_s:g} s")
        time.sleep(0.002)


class Taps:
    """Every frame written: ``(time_s, seq, levels bytes)``, and a condition to wait on."""

    def __init__(self):
        self.frames = []
        self.changed = threading.Condition()

    def __call__(self, time_s, seq, levels):
        with self.changed:
            self.frames.append((time_s, seq, bytes(levels)))
            self.changed.notify_all()

    def wait_levels(self, levels: bytes, timeout_s=10.0, after=0) -> int:
        """Index of the first frame from ``after`` on with ``levels``."""
        deadline = time.monotonic() + timeout_s
        with self.changed:
            while True:
                for i in range(after, len(self.frames)):
                    if self.frames[i][2] == levels:
                        return i
                after = len(self.frames)
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise AssertionError(f"no frame with levels {list(levels)}")
                self.changed.wait(remaining)


def send_until_shown(send, taps, levels: bytes, tries=40) -> int:
    """``send()`` until a frame shows ``levels`` (a point may time out before a frame shows it
    on a machine that stalls longer than the timeout); the frame's index."""
    for _ in range(tries):
        start = len(taps.frames)
        send()
        try:
            return taps.wait_levels(levels, timeout_s=0.5, after=start)
        except AssertionError:
            continue
    raise AssertionError(f"no frame with levels {list(levels)} after {tries} sends")


def levels_of(method, points, mu, gamma, profile=None):
    """Channel-ordered levels of ``points`` [(x, y, intensity)] rendered as the server does:
    each corrected with its intensity as master intensity, max per tactor, quantised."""
    profile = profile or default_profile()
    best = np.zeros(profile.channels)
    for x, y, a in points:
        raw = tc.render_xy(method, x, y, grid=profile.layout).reshape(-1)
        value = np.where(raw > 0, np.minimum(mu + a * (1 - mu) * raw**gamma, 1.0), 0.0)
        best = np.maximum(best, value)
    cells = tc.quantize(best, profile.levels)
    return bytes(cells[profile.array.channel_index].tolist())


class ServerRig:
    """An :class:`OscServer` on a free port of 127.0.0.1, streaming to a simulated array."""

    def __init__(self, scene=None, link=None, **options):
        self.profile = default_profile()
        self.taps = Taps()
        self.link = link or SimulatedArray(self.profile)
        self.streamer = Streamer(self.link, self.profile, taps=[self.taps], identify=False)
        self.scene = scene or Scene(method="AS", mu=0.33, gamma=0.7)
        self.warnings = []
        # Points stay until released: with the 100 ms default, a point sent once could time out
        # before a loaded host's test sends the next one (the timeout's tests pass their own).
        options.setdefault("timeout_s", 10.0)
        self.server = OscServer(self.streamer, self.profile, scene=self.scene, port=0,
                                on_warning=self.warnings.append, **options)  # fmt: skip

    def __enter__(self):
        self.streamer.start()
        self.server.start()
        from pythonosc.udp_client import SimpleUDPClient

        self.client = SimpleUDPClient(*self.server.address)
        return self

    def __exit__(self, *exc):
        self.client.close()
        self.server.stop()
        self.streamer.stop()
        self.link.close()

    def send(self, address, *args):
        self.client.send_message(address, list(args))

    def wait_count(self, name, n, timeout_s=10.0):
        wait_for(lambda: getattr(self.server.stats, name) >= n, timeout_s, f"{name} >= {n}")
