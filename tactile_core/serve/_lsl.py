"""Stimulus markers, and the levels sent, on Lab Streaming Layer (``pylsl``, which bundles liblsl).

Two outlets, both off unless asked for:

- ``tactile-markers`` (type ``Markers``, one string channel, irregular rate): one sample per
  presentation (an :class:`~tactile_core.device.Onset` of the streamer), a JSON object with its
  kind (the scene's ``marker``: ``trial``, ``interval``, ``ab``, ``osc-shape``, ``script``, …;
  ``scene`` when it has none), method, shape, μ, γ, gain, duration, the presentation's number
  on this outlet (``presentation``: 1, 2, 3, …, never wrapping) and the frame's wire sequence
  number (``seq``, 0 to 255: it wraps every 256 frames), stamped with the time its first frame
  was written to the device (or, for a frame scheduled ahead, the host time it is to play at);
- ``tactile-levels`` (type ``Levels``, one int16 channel per actuator in channel order, at the
  frame rate): the levels of every frame written, stamped likewise.

Clocks: the streamer's times are ``time.perf_counter`` seconds; LSL's are
``pylsl.local_clock()`` (liblsl's ``std::chrono::steady_clock``). On Linux both read
``CLOCK_MONOTONIC``; elsewhere both are monotonic clocks of the same machine that differ by a
constant. :func:`lsl_offset_s` measures that constant once (the read of ``local_clock``
bracketed by two ``perf_counter`` reads, the tightest of 50), and every time is sent as
``perf_counter time + offset``.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import stat
import tempfile
import time

from .._version import __version__
from ..device.profile import DeviceProfile, default_profile

MARKERS_NAME = "tactile-markers"
LEVELS_NAME = "tactile-levels"
VALIDATION_NAME = "tactile-validation"


MAX_SAME_ID = 99
"""Most outlets of one source id on this machine at once (``-2`` ... ``-99`` after the first)."""


class LslError(RuntimeError):
    """An outlet that cannot be opened (pylsl missing, liblsl refusing); the message says why."""


def _pylsl():
    try:
        import pylsl
    except (ImportError, OSError, RuntimeError) as exc:  # a broken install (no liblsl) says why
        raise LslError(f"Lab Streaming Layer needs pylsl (pip install pylsl): {exc}") from None
    return pylsl


def _lock_folder() -> str:
    """``$XDG_RUNTIME_DIR/tactile-tuner-UID/lsl`` (the temporary folder without it), created
    private; ``OSError`` unless both folders are this user's own, not symbolic links and not
    writable by others (in a shared /tmp another user could have made them, or linked a lock
    file to one of this user's files)."""
    base = os.environ.get("XDG_RUNTIME_DIR") or tempfile.gettempdir()
    uid = os.getuid()
    mine = os.path.join(base, f"tactile-tuner-{uid}")
    for folder in (mine, os.path.join(mine, "lsl")):
        try:
            os.mkdir(folder, 0o700)
        except FileExistsError:
            pass
        info = os.lstat(folder)
        if not stat.S_ISDIR(info.st_mode) or info.st_uid != uid or info.st_mode & 0o022:
            raise OSError(f"{folder} is not a private folder of this user")
    return folder


_CLAIMS: dict = {}
"""Lock descriptor -> its file, for :func:`release_source_id`."""


def _same_file(fd: int, path: str) -> bool:
    """True if ``path`` still names the file open as ``fd`` (not unlinked or replaced)."""
    try:
        mine, there = os.fstat(fd), os.stat(path, follow_symlinks=False)
    except OSError:
        return False
    return (mine.st_dev, mine.st_ino) == (there.st_dev, there.st_ino)


def release_source_id(lock: int | None) -> None:
    """Give up a source id :func:`claim_source_id` returned ``lock`` for: its lock file is
    removed while still locked (so the folder does not fill with the ids of past outlets),
    then the lock is released. A claim that opened the file just before checks, once it holds
    the lock, that the file is still there (:func:`_same_file`) and otherwise opens it anew."""
    if lock is None:
        return
    path = _CLAIMS.pop(lock, None)
    if path is not None and _same_file(lock, path):
        try:
            os.unlink(path)
        except OSError:
            pass
    os.close(lock)


def claim_source_id(source_id: str) -> tuple[str, int | None, str]:
    """A source id no other outlet of this tool on this machine uses: ``(id, lock, holder)``.

    LSL takes a source id as the key of one stream: a recorder that loses a stream finds it
    again by its source id, so two outlets sharing one (two ``tactile serve --lsl`` on the same
    profile) could swap in a recording. The first outlet of ``source_id`` gets it; while it is
    open the next gets ``source_id-2``, then ``-3``... Each claim is an exclusive ``flock`` on a
    file in ``$XDG_RUNTIME_DIR/tactile-tuner-UID/lsl`` (the temporary folder without it), which
    the system releases when the process ends however it ends. ``lock`` is the descriptor that
    holds it (None where locks are not available: the id is then taken as given),
    ``holder`` the process id that holds ``source_id`` when another one was given. Release
    it with :func:`release_source_id`.
    """
    try:
        import fcntl

        folder = _lock_folder()
    except (ImportError, OSError, AttributeError):  # no flock or getuid (Windows), no folder
        return source_id, None, ""
    holder = ""
    for k in range(1, MAX_SAME_ID + 1):
        claimed = source_id if k == 1 else f"{source_id}-{k}"
        name = hashlib.sha256(claimed.encode("utf-8", "replace")).hexdigest()[:24]
        path = os.path.join(folder, f"{name}.lock")
        for _ in range(8):  # a lock file its holder removed as we opened it: open it again
            try:
                flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0) | os.O_NOFOLLOW
                fd = os.open(path, flags, 0o600)
            except OSError:
                return source_id, None, ""
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                if k == 1:
                    try:
                        holder = os.pread(fd, 32, 0).decode("ascii", "replace").strip()
                    except OSError:
                        pass
                os.close(fd)
                break  # held: the next id
            if _same_file(fd, path):
                os.ftruncate(fd, 0)
                os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
                _CLAIMS[fd] = path
                return claimed, fd, holder
            os.close(fd)  # locked a file already unlinked by the one releasing it
    raise LslError(f"Lab Streaming Layer: {MAX_SAME_ID} outlets named {source_id} are open on "
                   "this machine already")  # fmt: skip


def lsl_offset_s(tries: int = 50) -> float:
    """``pylsl.local_clock() - time.perf_counter()`` in seconds, measured now.

    Each try reads LSL's clock between two ``perf_counter`` reads; the tightest bracket wins,
    and its midpoint is taken (the error is at most half the bracket, well under a
    microsecond).
    """
    local_clock = _pylsl().local_clock
    best_width, offset = math.inf, 0.0
    for _ in range(tries):
        before = time.perf_counter()
        lsl = local_clock()
        after = time.perf_counter()
        if after - before < best_width:
            best_width, offset = after - before, lsl - (before + after) / 2
    return offset


def marker_text(onset, presentation: int | None = None) -> str:
    """The JSON string of an :class:`~tactile_core.device.Onset`'s marker.

    Parameters
    ----------
    onset : Onset
    presentation : int, optional
        The presentation's number (1 for the first an outlet sends; it never wraps, unlike
        the wire's ``seq``); left out of the object when None.
    """
    scene = onset.scene
    source = getattr(scene, "source", None)
    data = {
        "kind": getattr(scene, "marker", "") or "scene",
        "method": scene.method,
        "shape": None if scene.shape is None else scene.shape.spec,
        "source": None if source is None else type(source).__name__,
        "mu": scene.mu,
        "gamma": scene.gamma,
        "gain": scene.gain,
        "duration_s": scene.duration_s if scene.shape is not None else None,
        "cycle": onset.cycle,
        "seq": onset.seq,
        "presentation": presentation,
        "timed": onset.timed,
    }
    if presentation is None:
        del data["presentation"]
    return json.dumps(data, separators=(",", ":"))


class LslOutlets:
    """The marker outlet and, optionally, the levels outlet of one array.

    Parameters
    ----------
    profile : DeviceProfile, optional
        The array: channels, their names, levels (the palm array by default).
    rate_hz : float
        Nominal rate of the levels stream (the stream's frame rate).
    markers, levels : bool
        Which outlets to open (markers only by default).
    source_id : str, optional
        LSL's source id, a recording's key to the same stream after a restart
        (``tactile-<profile name>`` by default; the outlets add ``-markers`` and ``-levels``).
        While another outlet of this tool on this machine has it, ``-2`` (``-3``, ...) is
        added and :attr:`note` says so (:func:`claim_source_id`).

    Raises
    ------
    LslError
        When an outlet cannot be opened (pylsl missing; liblsl finds no free port or network
        interface); nothing stays open.

    Use :meth:`attach` to feed them from a :class:`~tactile_core.device.Streamer`, or call
    :meth:`onset` and :meth:`push_levels` from a stream's hooks yourself.
    """

    def __init__(
        self,
        profile: DeviceProfile | None = None,
        *,
        rate_hz: float = 300.0,
        markers: bool = True,
        levels: bool = False,
        source_id: str | None = None,
    ):
        pylsl = _pylsl()
        self.profile = profile or default_profile()
        self._markers = self._levels = None
        wanted = source_id or f"tactile-{self.profile.name}"
        self.source_id, self._lock, holder = claim_source_id(wanted)
        self.note = ""
        """Why the source id is not the one asked for ("" when it is)."""
        if self.source_id != wanted:
            by = f" (process {holder})" if holder else ""
            self.note = (f"LSL: another program on this machine{by} sends {wanted}; this "
                         f"one's source id is {self.source_id}")  # fmt: skip
        try:
            self._open(pylsl, markers, levels, rate_hz)
        except Exception as exc:  # liblsl: no free port, no network interface, ...
            self.close()
            raise LslError(
                f"Lab Streaming Layer: cannot open the outlets of {self.source_id}: {exc} "
                "(liblsl's messages above say why)"
            ) from None

    def _open(self, pylsl, markers: bool, levels: bool, rate_hz: float) -> None:
        self.offset_s = lsl_offset_s()
        """LSL clock minus ``time.perf_counter``, added to every time sent."""
        self.markers_sent = 0
        self.levels_sent = 0
        if markers:
            info = pylsl.StreamInfo(MARKERS_NAME, "Markers", 1, pylsl.IRREGULAR_RATE,
                                    pylsl.cf_string, f"{self.source_id}-markers")  # fmt: skip
            self._describe(info)
            self._markers = pylsl.StreamOutlet(info)
        if levels:
            n = self.profile.channels
            info = pylsl.StreamInfo(LEVELS_NAME, "Levels", n, float(rate_hz), pylsl.cf_int16,
                                    f"{self.source_id}-levels")  # fmt: skip
            desc = self._describe(info)
            desc.append_child_value("levels", str(self.profile.levels))
            channels = desc.append_child("channels")
            names = list(self.profile.layout.names)
            order = self.profile.array.channel_index
            for ch in range(n):
                channel = channels.append_child("channel")
                channel.append_child_value("label", str(names[int(order[ch])]))
                channel.append_child_value("unit", "level")
            self._levels = pylsl.StreamOutlet(info)

    def _describe(self, info):
        desc = info.desc()
        desc.append_child_value("software", f"tactile-tuner {__version__}")
        desc.append_child_value("device", self.profile.name)
        desc.append_child_value("pid", str(os.getpid()))
        return desc

    def onset(self, onset) -> None:
        """Push the marker of a presentation (a streamer's ``on_onset`` hook)."""
        if self._markers is not None:
            text = marker_text(onset, self.markers_sent + 1)
            self._markers.push_sample([text], onset.time_s + self.offset_s)
            self.markers_sent += 1

    def push_levels(self, time_s: float, seq: int, levels: bytes) -> None:
        """Push one frame's levels (a streamer's tap)."""
        if self._levels is not None:
            self._levels.push_sample(list(levels), time_s + self.offset_s)
            self.levels_sent += 1

    def attach(self, streamer) -> LslOutlets:
        """Feed the outlets from ``streamer`` (its ``on_onset`` hooks and taps)."""
        if self._markers is not None:
            streamer.on_onset.append(self.onset)
        if self._levels is not None:
            streamer.taps.append(self.push_levels)
        return self

    def detach(self, streamer) -> None:
        """Stop feeding the outlets from ``streamer``."""
        for hooks, hook in ((streamer.on_onset, self.onset), (streamer.taps, self.push_levels)):
            if hook in hooks:
                hooks.remove(hook)

    def close(self) -> None:
        """Close the outlets (recorders see the streams end) and give up the source id."""
        self._markers = self._levels = None
        lock, self._lock = getattr(self, "_lock", None), None
        release_source_id(lock)

    def __enter__(self) -> LslOutlets:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class ValidationOutlet:
    """The validator's marker stream ``tactile-validation`` (type ``Markers``, one string
    channel): one JSON sample per presentation, stamped with the time the sensor detected its
    first vibration (the commanded time when none was found).

    Parameters
    ----------
    profile : DeviceProfile, optional
        The array (its name goes into the stream's description and source id).

    Raises
    ------
    LslError
        When the outlet cannot be opened.
    """

    def __init__(self, profile: DeviceProfile | None = None):
        pylsl = _pylsl()
        self.profile = profile or default_profile()
        wanted = f"tactile-{self.profile.name}-validation"
        self.source_id, self._lock, _ = claim_source_id(wanted)
        try:
            self.offset_s = lsl_offset_s()
            info = pylsl.StreamInfo(VALIDATION_NAME, "Markers", 1, pylsl.IRREGULAR_RATE,
                                    pylsl.cf_string, self.source_id)  # fmt: skip
            desc = info.desc()
            desc.append_child_value("software", f"tactile-tuner {__version__}")
            desc.append_child_value("device", self.profile.name)
            self._outlet = pylsl.StreamOutlet(info)
        except Exception as exc:
            self.close()
            raise LslError(f"Lab Streaming Layer: cannot open {VALIDATION_NAME}: {exc}") from None
        self.sent = 0

    def push(self, data: dict, time_s: float) -> None:
        """Send ``data`` as JSON stamped ``time_s`` (``time.perf_counter`` seconds)."""
        if self._outlet is not None:
            self._outlet.push_sample([json.dumps(data, separators=(",", ":"))],
                                     time_s + self.offset_s)  # fmt: skip
            self.sent += 1

    def close(self) -> None:
        """Close the outlet and give up its source id."""
        self._outlet = None
        lock, self._lock = getattr(self, "_lock", None), None
        release_source_id(lock)
