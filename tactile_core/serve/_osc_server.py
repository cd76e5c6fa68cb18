"""The OSC server: points and commands from another program, fed to a stream's live path.

Two threads of its own, neither of them the stream's output thread:

- the *receiver* reads UDP datagrams, parses them (:mod:`._osc_wire`), checks every value and
  writes the :class:`~tactile_core.rendering.points.FreePoints` table or swaps in a new scene
  (the address space, :mod:`._osc_addresses`);
- the *keeper* releases points that were not refreshed within the timeout, ends a shape when
  its time is up, and measures the message rate.

The output thread reads the points table (an immutable snapshot swapped by reference) and the
scene (likewise) and never waits on either thread. A message that cannot be honoured is
counted (:class:`ServeStats`) and dropped, with a reply to a sender that asked for replies
(:mod:`._osc_replies`); the server goes on. The rate limit counts what a datagram costs, not
how many there are (:mod:`._osc_limits`): each sender has a share of ``max_rate_hz`` units a
second, and datagrams beyond it are dropped unread, except ``/tactile/off`` and
``/tactile/release``, which are always read; a datagram over
:data:`~._osc_wire.MAX_DATAGRAM_BYTES` is never read. A flood costs the receiver a ``recvmsg``
and a count per datagram, not a parse.
"""

from __future__ import annotations

import math
import socket
import struct
import sys
import threading
import time
from collections import deque

from .._shared import validate as _validate
from ..device.profile import DeviceProfile, default_profile
from ..rendering.points import DEFAULT_TIMEOUT_S, FreePoints, free_method
from ..rendering.rasterize import check_renders
from ..rendering.scene import Scene
from ..rendering.shapes import parse_shape
from ._osc_addresses import AddressSpace, shape_label
from ._osc_limits import SenderBudgets, datagram_units, message_units
from ._osc_replies import REPLY_ADDRESSES, Replies
from ._osc_socket import _loopback, _open_socket, _printable, listen_host, where
from ._osc_wire import MAX_DATAGRAM_BYTES, Malformed, read_packet
from ._serve_stats import MAX_TEXT, PROBLEMS, ServeStats, shortened

DEFAULT_PORT = 9100
"""The UDP port ``tactile serve`` listens on unless told otherwise."""
MAX_MESSAGES = 256
"""Most messages read from one datagram (a bundle); the rest are counted as dropped."""
_ALWAYS_READ = (b"/tactile/off\x00", b"/tactile/release\x00")
"""The addresses read whatever the rate, with the NUL that ends them: '/tactile/offset' is not."""
_SO_RXQ_OVFL = getattr(socket, "SO_RXQ_OVFL", 40 if sys.platform.startswith("linux") else None)

SWITCH_INTERVAL_S = 0.0001
"""Python's thread switch interval while ``tactile serve`` streams (the streamer's default is
0.5 ms): the server's receiver thread shares the interpreter lock with the frame thread, and
under a flood of messages the frame thread waits at most this long for it (measured in
``docs/serve.md``: p99 interval error at the array 2.7-3.3 ms during a 50,000 messages/s flood,
5.9-7.1 ms at 0.5 ms)."""


class OscServer(AddressSpace):
    """Points and commands over OSC (UDP), fed to a stream: ``tactile serve`` and the tuner.

    Parameters
    ----------
    stream : Streamer, LocalStream or anything with ``set_scene(scene)``
        Where scenes go. Free points are read by the stream's output thread in this process,
        so not a stream process (its scenes are pickled). If it has an ``on_onset`` list (a
        :class:`~tactile_core.device.Streamer`), the server adds itself to it: a shape then
        ends ``DURATION_S`` after its first frame went out.
    profile : DeviceProfile, optional
        The array the points are rendered onto (the palm array by default).
    scene : Scene, optional
        Method, correction, rate and the rest for the points (AS, μ 0.33, γ 0.7 at 300 Hz by
        default); its shape is ignored. The method must render free points.
    host, port : str, int
        Where to listen: 127.0.0.1 (this machine only) by default. Another address is used only
        when asked, with a warning (``on_warning``). Port 0 takes a free port (see ``address``).
    timeout_s : float
        A point not refreshed within this long is released (0.1 s).
    interpolate : bool
        Interpolate points between their last two updates instead of showing the newest.
    max_rate_hz : float
        Units of work read per second at most, shared among the senders (10,000; a point
        message is one unit, see :mod:`._osc_limits`); more are dropped unread, and counted.
    reply_port : int, optional
        Replies to every sender go to its host at this port (``/tactile/error`` for a refused
        message; see :mod:`._osc_replies`) unless it asked otherwise; None (the default): only
        senders that sent ``/tactile/reply`` get replies.
    on_scene : callable, optional
        Called as ``on_scene(scene)`` from the server's threads after it swaps in a scene
        (``/tactile/method``, ``mu``, ``gamma``, ``shape``, ``off``; a shape's end).
    on_tuning : callable, optional
        Called as ``on_tuning({field: value})`` with what a sender's ``/tactile/method``,
        ``mu`` or ``gamma`` changed (only the fields it set that differ from the points'
        scene then; nothing when none do), decided under the lock that orders scene swaps, so
        an owner's :meth:`set_scene` is never reported as a sender's change.
    on_warning : callable, optional
        Called with a sentence when listening beyond this machine (default: standard error).
    clock : callable
        The stream's clock (``time.perf_counter``).
    """

    def __init__(self, stream, profile: DeviceProfile | None = None, *, scene: Scene | None = None,
                 host: str = "127.0.0.1", port: int = DEFAULT_PORT,
                 timeout_s: float = DEFAULT_TIMEOUT_S, interpolate: bool = False,
                 max_rate_hz: float = 10_000.0, reply_port: int | None = None, on_scene=None,
                 on_tuning=None, on_warning=None, clock=time.perf_counter):  # fmt: skip
        self.stream = stream
        self.profile = profile or default_profile()
        self.host = host
        self.port = _validate.integer("port", port, 0, 65535)
        self.max_rate_hz = _validate.in_range("max_rate_hz", max_rate_hz, 1.0, 1e7)
        if reply_port is not None:
            reply_port = _validate.integer("reply_port", reply_port, 1, 65535)
        self.replies = Replies(reply_port)
        self.on_scene = on_scene
        self.on_tuning = on_tuning
        self.on_warning = on_warning or (lambda text: print(text, file=sys.stderr, flush=True))
        self.clock = clock
        self.points = FreePoints(timeout_s=timeout_s, interpolate=interpolate, clock=clock)
        self._lock = threading.RLock()  # scene swaps: receiver, keeper, owner; never output
        self._base = self._points_scene(scene or Scene(method="AS"))
        self._current = self._base
        self._epoch = self._base.epoch
        self._shape = None  # the shape scene playing, or None
        self._playing = "points"  # what the status line says it plays (bounded)
        self._shape_until = math.inf
        self._n = dict.fromkeys(
            ("datagrams", "messages", "points", "releases", "controls", "shapes", "queries",
             *(key for key, _ in PROBLEMS)), 0)  # fmt: skip
        self._from = None  # the sender of the datagram being read (the receiver's)
        self._reading = ""  # the address of the message being read
        self._timed_out = 0
        self._rate_hz = 0.0
        self._sender = ""
        self._last_address = ""
        self._problem = ""
        self._sock = None
        self._ovfl = False
        self.address = ("", 0)
        """``(host, port)`` the server is bound to, once started."""
        self._started = self._stopped = None
        self._stopping = threading.Event()
        self._wake = threading.Event()
        self._threads: list[threading.Thread] = []
        hooks = getattr(stream, "on_onset", None)
        self._hooks = hooks if isinstance(hooks, list) else None

    # --- owner ---------------------------------------------------------------------------------

    def start(self) -> OscServer:
        """Bind the socket, start the threads and hand the points scene to the stream (again
        after :meth:`stop`: a tuner's toggle; the counters go on).

        Raises ``OSError`` (the address in use, not an address of this machine) with the
        address in the message, and ``TypeError`` for a stream in another process."""
        with self._lock:  # first: a stream that cannot take free points refuses them here
            self.stream.set_scene(self._current)
        try:
            self._sock = self._bind()
        except OSError:
            with self._lock:
                if getattr(self.stream, "scene", None) is self._current:
                    self.stream.set_scene(None)
            raise
        self._stopping.clear()
        self._started, self._stopped = self.clock(), None
        if self._hooks is not None:
            self._hooks.append(self.on_onset)
        for name, target in (("tactile-osc", self._receive), ("tactile-osc-keeper", self._keep)):
            thread = threading.Thread(target=target, name=name, daemon=True)
            thread.start()
            self._threads.append(thread)
        return self

    def stop(self, timeout: float = 2.0) -> ServeStats:
        """Stop listening, release every point and leave the stream idle (all off) if it still
        plays the server's scene; the final counters."""
        self._stopping.set()
        self._wake.set()
        if self._started is not None and self._stopped is None:
            self._stopped = self.clock()
        for thread in self._threads:
            thread.join(timeout)
        self._threads = []
        if self._sock is not None:
            self._sock.close()
            self._sock = None
        self.points.release()
        if self._hooks is not None and self.on_onset in self._hooks:
            self._hooks.remove(self.on_onset)
        with self._lock:
            if getattr(self.stream, "scene", None) is self._current:
                self.stream.set_scene(None)
        return self.stats

    def __enter__(self) -> OscServer:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    @property
    def running(self) -> bool:
        """True while the receiver thread is alive."""
        return bool(self._threads) and self._threads[0].is_alive()

    @property
    def scene(self) -> Scene:
        """The scene the server last handed to the stream."""
        return self._current

    def set_scene(self, scene: Scene) -> None:
        """Take method, correction, rate and the rest from ``scene`` for the points (a tuner's
        controls); ``ValueError`` if its method cannot render free points here."""
        base = self._points_scene(scene)
        with self._lock:
            self._base = base
            if self._shape is None:
                self._swap(base)

    def off(self) -> None:
        """Release every point and end a shape: all off at the next frame."""
        self.points.release()
        with self._lock:
            if self._shape is None and self._showing(self._base):
                return  # nothing to swap: a flood of offs costs the output thread nothing
            self._shape = None
            self._playing = "points"
            self._swap(self._base)

    @property
    def stats(self) -> ServeStats:
        """The counters now."""
        return ServeStats(
            address=where(*self.address),
            **self._n,
            replies=self.replies.sent,
            replies_dropped=self.replies.dropped,
            timed_out=self._timed_out,
            active_points=len(self.points.points),
            rate_hz=self._rate_hz,
            last_sender=self._sender,
            last_address=self._last_address,
            last_problem=self._problem,
            playing=self._playing,
            elapsed_s=0.0
            if self._started is None
            else (self._stopped or self.clock()) - self._started,
        )

    def on_onset(self, onset) -> None:
        """A presentation's first frame went out (the stream's hook): time a shape from it."""
        shape = self._shape
        if (
            shape is not None
            and onset.scene.marker == "osc-shape"
            and (onset.scene.epoch == shape.epoch)
        ):
            self._shape_until = onset.time_s + shape.duration_s
            self._wake.set()

    # --- scenes (under self._lock) -------------------------------------------------------------

    def _points_scene(self, scene: Scene) -> Scene:
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a Scene, got {_validate.shown(scene)}")
        method = free_method(scene.method)
        check_renders(method.spec, self.profile.layout)
        return scene.replace(shape=None, source=self.points, marker="osc-points", hold_s=None)

    def _showing(self, scene: Scene) -> bool:
        """Whether the stream plays ``scene``, the server's current one."""
        return scene is self._current and getattr(self.stream, "scene", None) is scene

    def _swap(self, scene: Scene) -> None:
        self._current = scene
        self.stream.set_scene(scene)
        if self.on_scene is not None:
            try:
                self.on_scene(scene)
            except Exception:
                pass

    def _change(self, **changes) -> None:
        """New method or correction for the points, and for a shape playing."""
        with self._lock:
            changed = {k: v for k, v in changes.items() if getattr(self._base, k) != v}
            if not changed and self._showing(self._shape or self._base):
                return  # the same again: no new scene for the output thread to take up
            self._base = self._base.replace(**changes)
            if changed and self.on_tuning is not None:
                try:
                    self.on_tuning(changed)
                except Exception:
                    pass
            if self._shape is not None:
                self._shape = self._shape.replace(**changes)
                self._swap(self._shape)
            else:
                self._swap(self._base)

    def _play(self, spec: str, duration_s: float, now: float) -> None:
        shape = parse_shape(spec)
        with self._lock:
            self._epoch += 1
            self._shape = self._base.replace(
                shape=shape, source=None, duration_s=duration_s, pause_s=0.0, repeat=False,
                marker="osc-shape", epoch=self._epoch,
            )  # fmt: skip
            self._playing = shape_label(shape)
            self._shape_until = now + duration_s + 0.1  # until its first frame says when
            self._swap(self._shape)
        self._wake.set()

    # --- the receiver --------------------------------------------------------------------------

    def _bind(self) -> socket.socket:
        sock = _open_socket(listen_host(self.host), self.port)
        try:  # a bigger buffer and its overflow count (Linux): best effort
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 << 20)
        except OSError:
            pass
        self._ovfl = _SO_RXQ_OVFL is not None
        if self._ovfl:
            try:
                sock.setsockopt(socket.SOL_SOCKET, _SO_RXQ_OVFL, 1)
            except OSError:
                self._ovfl = False
        sock.settimeout(0.1)
        self.address = sock.getsockname()[:2]
        if not _loopback(self.address[0]):
            self.on_warning(
                f"warning: listening on {where(*self.address)}, beyond this machine: anyone "
                "who can send it UDP drives the array"
            )
        return sock

    def _problem_of(self, kind: str, text: str) -> None:
        """Count a message (a datagram) that did nothing, keep why (bounded, printable), and
        tell its sender if it asked for replies."""
        self._n[kind] += 1
        self._problem = problem = shortened(text if text.isprintable() else _printable(text))
        sender, address = self._from, self._reading
        if sender is None or address in REPLY_ADDRESSES:
            return
        to = self.replies.destination(sender)
        if to is not None:
            name = dict(PROBLEMS)[kind]
            self.replies.send(self._sock, to, "/tactile/error", (address, name, problem),
                              self.clock())  # fmt: skip

    def _receive(self) -> None:
        sock, n, clock = self._sock, self._n, self.clock
        space = socket.CMSG_SPACE(4) if self._ovfl else 0
        budgets = SenderBudgets(self.max_rate_hz)
        size = MAX_DATAGRAM_BYTES + 1  # one byte more: a longer datagram shows as too long
        while not self._stopping.is_set():
            too_long = False
            try:
                if space:
                    data, ancillary, _, sender = sock.recvmsg(size, space)
                else:
                    (data, sender), ancillary = sock.recvfrom(size), ()
            except TimeoutError:
                continue
            except OSError as exc:
                if self._stopping.is_set():
                    break
                if getattr(exc, "winerror", None) != 10040:  # WSAEMSGSIZE: too long, on Windows
                    self._from = None
                    self._problem_of("errors", f"receive: {exc}")
                    time.sleep(0.01)
                    continue
                data, ancillary, sender, too_long = b"", (), None, True
            now = clock()
            n["datagrams"] += 1
            for level, kind, payload in ancillary:
                if level == socket.SOL_SOCKET and kind == _SO_RXQ_OVFL and len(payload) >= 4:
                    n["kernel_dropped"] = struct.unpack("=I", payload[:4])[0]
            if sender is not None:
                self._sender = where(*sender[:2])
            self._from, self._reading = sender, ""
            if too_long or len(data) > MAX_DATAGRAM_BYTES:
                self._problem_of("too_large", f"a datagram from {self._sender} longer than "
                                 f"{MAX_DATAGRAM_BYTES} bytes, not read")  # fmt: skip
                continue
            bucket = budgets.bucket(sender, now)
            if bucket[0] < 1.0 and not data.startswith(_ALWAYS_READ):
                n["flood_dropped"] += 1
                continue
            bucket[0] -= datagram_units(len(data))
            floor = bucket[0] - bucket[2]  # what its messages cost may take one bucket more
            try:
                messages, skipped = read_packet(data, MAX_MESSAGES)
            except Malformed as exc:
                self._problem_of("malformed", f"malformed datagram from {self._sender}: {exc}")
                continue
            n["flood_dropped"] += skipped
            for j, (address, args) in enumerate(messages):
                if bucket[0] < floor:  # the rest are not read
                    n["flood_dropped"] += len(messages) - j
                    break
                bucket[0] -= message_units(address, args)
                n["messages"] += 1
                self._last_address = self._reading = address[:MAX_TEXT]
                try:
                    self._handle(address, args, now)
                except Exception as exc:  # a bug: counted, and the server goes on
                    self._problem_of("errors", f"{address}: {type(exc).__name__}: {exc}")

    # --- the keeper ----------------------------------------------------------------------------

    def _keep(self) -> None:
        history: deque = deque()
        while not self._stopping.is_set():
            now = self.clock()
            self._timed_out += self.points.expire(now)
            if self._shape is not None and now >= self._shape_until:
                with self._lock:
                    if self._shape is not None and now >= self._shape_until:
                        self._shape = None
                        self._playing = "points"
                        self._swap(self._base)
            history.append((now, self._n["datagrams"] + self._n["kernel_dropped"]))
            while len(history) > 2 and now - history[1][0] >= 1.0:
                history.popleft()
            (t0, d0), (t1, d1) = history[0], history[-1]
            self._rate_hz = (d1 - d0) / (t1 - t0) if t1 > t0 else 0.0
            wait = 0.02 if self._shape is None else min(0.02, max(0.0, self._shape_until - now))
            self._wake.wait(wait)
            self._wake.clear()
