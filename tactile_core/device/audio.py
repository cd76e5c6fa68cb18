"""A multichannel audio interface as an array: one actuator per channel, through PortAudio.

:class:`AudioLink` is a link like the serial one (``write``, ``read``, ``close``, ``reopen``,
``description``; only :class:`~.link.LinkError` escapes). Behind it the bytes the streamer writes
are received by :class:`~.array.ArrayModel`, exactly as the reference firmware receives them:
frames, hello (its info names the profile's array and announces scheduled frames), query, the
clock exchange and timed frames, the 250 ms watchdog. What the model applies becomes *events*
for the audio callback: a frame for now starts at the next block, a timed frame at the sample
whose time is its time. The callback turns them into each channel's waveform
(:mod:`._audio_synth`: the profile's, or what a frame asks for), sample for sample, with a
raised-cosine ramp between levels.

The array's clock is the host's (``time.perf_counter``, microseconds from the link's start):
clock exchanges cost nothing in-process (:attr:`AudioLink.byte_s` is 0), and the callback maps
each block onto that clock from PortAudio's timing (the time its first sample reaches the
converter), smoothed by a first-order loop and re-anchored after a dropout
(:class:`~._audio_play.BlockClock`). A timed frame that the callback meets only after its time
has passed plays at once and counts as late.

Threads: the streamer's thread writes; PortAudio's thread runs the callback. They share the
:class:`~._audio_play.Player`: one immutable tuple of events that the writer replaces (the
callback reads it once per block) and a few numbers each of them alone writes.
"""

from __future__ import annotations

import atexit
import math
import threading
import weakref

import numpy as np

from ._audio_play import Player
from ._audio_synth import DEFAULT_CARRIER_HZ, DEFAULT_RAMP_MS, synthesize
from ._audio_url import (
    CARRIER_RANGE_HZ,
    RAMP_RANGE_MS,
    SAMPLERATE_RANGE,
    check_device,
    device_url,
    find_device,
    is_audio_url,
    load_sounddevice,
    output_devices,
    parse_audio_url,
)
from ._link_error import LinkError
from .array import ArrayModel
from .host_clock import HostClock
from .profile import DeviceProfile, default_profile
from .waveform import PLAIN, Waveform

_WHAT_TO_CHECK = (
    "is it plugged in and not held by another program? For ALSA's file plugin: does something "
    "read the file it writes? A named pipe without a reader blocks its opening"
)

BLOCK = 256
"""Samples per callback: 5.3 ms at 48 kHz."""
STALL_S = 0.5
"""A stream whose callback has not run for this long is taken for a device that vanished."""
OPEN_TIMEOUT_S = 0.5
"""Opening waits at most this long for the stream to run steadily (its clock map locked)."""
OPEN_DEVICE_TIMEOUT_S = 5.0
"""Opening the device (PortAudio's check of the settings, then the stream) may take this long:
an opening that never returns (ALSA's ``file`` plugin writing into a named pipe nobody reads
waits in ``open(2)``) is given up, and said."""
FADE_TIMEOUT_S = 0.5
"""Closing waits at most this long for the callback to fade out and play silence."""

_OPEN: weakref.WeakSet = weakref.WeakSet()
_EXIT_HOOK: list = []
_STUCK: list[threading.Thread] = []
"""Openings given up on that are still waiting in the system: PortAudio is not to be asked
anything else meanwhile (it is not safe from two threads at once)."""


def _still_stuck() -> bool:
    _STUCK[:] = [t for t in _STUCK if t.is_alive()]
    return bool(_STUCK)


def _within(timeout_s: float, call, gave_up):
    """``call()`` on a thread of its own, waited for ``timeout_s`` seconds; past that the
    thread is left waiting (in :data:`_STUCK`) and ``gave_up()`` (a :class:`LinkError`) is
    raised. Whatever ``call`` raises is raised here."""
    done: dict = {}

    def run():
        try:
            done["value"] = call()
        except BaseException as exc:  # handed to the caller
            done["error"] = exc

    thread = threading.Thread(target=run, name="tactile-audio-open", daemon=True)
    thread.start()
    thread.join(timeout_s)
    if thread.is_alive():
        _STUCK.append(thread)
        raise gave_up()
    if "error" in done:
        raise done["error"]
    return done["value"]


def _close_all() -> None:
    """Interpreter exit: fade every open audio link to silence (before PortAudio ends)."""
    for link in list(_OPEN):
        link.close()


def _active(stream) -> bool:
    """``stream.active``, False where PortAudio cannot say (sounddevice raises
    ``PortAudioError`` for a stream it has lost: that is a stopped device, not a traceback)."""
    try:
        return bool(stream.active)
    except Exception:
        return False


def audio_outputs(rescan: bool = False) -> list[tuple[str, str]]:
    """``(url, label)`` of every audio output device (``("audio:USB 8ch", "USB 8ch (ALSA, 8
    channels, 48000 Hz)")``), for a device box; empty without PortAudio. A device whose name
    would not open it (one that several devices share, or digits) is ``audio:INDEX``.

    PortAudio lists the devices it found when it started; ``rescan`` starts it again to find
    devices plugged in since, unless an audio link is open in this process (its stream would
    end).
    """
    try:
        sd = load_sounddevice()
        if rescan and not _OPEN and not _still_stuck() and hasattr(sd, "_terminate"):
            sd._terminate()
            sd._initialize()
        devices = output_devices(sd)
    except Exception:  # no PortAudio, no audio system: nothing to list
        return []
    return [(device_url(d, devices), _label(d)) for d in devices]


def _label(device: dict) -> str:
    return (f"{device['name']} ({device['hostapi']}, {device['max_output_channels']} channels, "
            f"{device['default_samplerate']:g} Hz)")  # fmt: skip


def audio_output_of(url: str) -> tuple[str, str] | None:
    """The output device an ``audio:`` URL opens, as :func:`audio_outputs` lists it: ``(url,
    label)`` (``audio:`` is the default device, ``audio:USB`` the one whose name holds
    "USB"), for a device box to name the device in use; None for a URL that is not ``audio:``
    or names no device here (no PortAudio, none of that name, several)."""
    if not is_audio_url(url):
        return None
    try:
        sd = load_sounddevice()
        devices = output_devices(sd)
        device = find_device(sd, parse_audio_url(url).device)
    except Exception:  # LinkError, no PortAudio: nothing to name
        return None
    return device_url(device, devices), _label(device)


def carriers_for(profile: DeviceProfile, carrier_hz: float | None = None) -> np.ndarray:
    """One carrier per channel: ``carrier_hz`` (a URL's) for all, else the profile's (one for
    all or one per channel), else :data:`~._audio_synth.DEFAULT_CARRIER_HZ`."""
    n = profile.channels
    if carrier_hz is not None:
        return np.full(n, float(carrier_hz))
    given = getattr(profile, "carrier_hz", None)
    if given is None:
        return np.full(n, DEFAULT_CARRIER_HZ)
    return np.broadcast_to(np.asarray(given, dtype=np.float64), (n,)).copy()


def waveforms_for(profile: DeviceProfile, waveform: Waveform | None = None) -> tuple:
    """One waveform per channel: ``waveform`` (a URL's) for all, else the profile's (one for
    all or one per channel), else the plain carrier; a waveform that gives no frequency plays
    at the channel's carrier (:func:`carriers_for`)."""
    n = profile.channels
    if waveform is not None:
        return (waveform,) * n
    given = getattr(profile, "waveform", None)
    if given is None:
        return (PLAIN,) * n
    return tuple(given) * n if len(given) == 1 else tuple(given)


class AudioLink:
    """An ``audio:`` device: the profile's channels on an output stream.

    Parameters
    ----------
    url : str
        ``audio:`` or ``audio:NAME?channels=N&carrier_hz=F&samplerate=SR&ramp_ms=R&waveform=W``.
    profile : DeviceProfile, optional
        The array (its channels, levels, carriers, waveforms); the palm array by default.
    clock : HostClock, optional
        The host's clock (``time.perf_counter``); the tests drive a fake stream on a
        :class:`~.host_clock.VirtualClock`.
    open_timeout_s : float
        Opening the device (each time, reopening too) is given up after this many seconds
        (real time, > 0; :data:`OPEN_DEVICE_TIMEOUT_S` by default).

    Raises
    ------
    LinkError
        A bad URL (naming the key), no PortAudio, no such device, a device that cannot play
        the channels at the samplerate (listing what it supports), or one that does not open
        within ``open_timeout_s``.
    TypeError
        A ``profile`` that is not a :class:`~.profile.DeviceProfile`.
    ValueError
        An ``open_timeout_s`` that is not a positive number of seconds.
    """

    byte_s = 0.0
    """Seconds a byte takes on this link: none, it is received in-process."""

    def __init__(self, url: str, profile: DeviceProfile | None = None, *, clock=None,
                 open_timeout_s: float = OPEN_DEVICE_TIMEOUT_S):  # fmt: skip
        if profile is not None and not isinstance(profile, DeviceProfile):
            raise TypeError(f"profile must be a DeviceProfile, got {type(profile).__name__}")
        if not (isinstance(open_timeout_s, (int, float)) and 0 < open_timeout_s < math.inf):
            raise ValueError(f"open_timeout_s must be a positive number of seconds, got "
                             f"{open_timeout_s!r}")  # fmt: skip
        self.open_timeout_s = float(open_timeout_s)
        self.url = url
        self.profile = profile or default_profile()
        self.settings = parse_audio_url(url)
        n = self.profile.channels
        self.channels = self.settings.channels or n
        if self.channels < n:
            raise LinkError(
                f"invalid device URL {url!r}: channels={self.channels} is fewer than the "
                f"{n} actuators of the profile {self.profile.name} (one channel each)"
            )
        self.carrier_hz = carriers_for(self.profile, self.settings.carrier_hz)
        self.waveforms = waveforms_for(self.profile, self.settings.waveform)
        self.ramp_s = self.settings.ramp_ms / 1e3
        self._clock = clock or HostClock()
        self.model = ArrayModel(self.profile, pwm_hz=round(float(self.carrier_hz[0])),
                                epoch=self._clock.now(), queue_channels=255)  # fmt: skip
        self._lock = threading.Lock()
        self._replies = bytearray()
        self._stream = None
        self._sd = None
        self.player: Player | None = None
        self.device: dict | None = None
        self.samplerate = 0
        self.latency_s = 0.0
        self.description = url
        self.reopen()

    # --- the stream ----------------------------------------------------------------------------

    def reopen(self) -> None:
        """(Re)open the output stream; :class:`LinkError` with the reason if it cannot."""
        self.close()
        if _still_stuck():
            raise LinkError(
                f"audio device for {self.url!r} not opened: an earlier opening still waits in "
                f"the system ({_WHAT_TO_CHECK})"
            )
        sd = self._sd = load_sounddevice()
        device = find_device(sd, self.settings.device)
        rate = self.settings.samplerate or round(device["default_samplerate"])
        if not SAMPLERATE_RANGE[0] <= rate <= SAMPLERATE_RANGE[1]:
            raise LinkError(
                f"audio device {device['name']!r}: its default samplerate {rate} Hz is outside "
                f"{SAMPLERATE_RANGE[0]}-{SAMPLERATE_RANGE[1]} Hz; give samplerate= in the URL"
            )
        profile = self.profile
        asked = (
            "the URL's"
            if self.settings.channels
            else (f"the {profile.channels} actuators of the profile {profile.name}")
        )

        def gave_up():
            return LinkError(
                f"audio device {device['name']!r} did not open within "
                f"{self.open_timeout_s:g} s: PortAudio still waits in the system "
                f"({_WHAT_TO_CHECK})"
            )

        opened_by = self._clock.now() + self.open_timeout_s  # both openings together
        _within(self.open_timeout_s, lambda: check_device(sd, device, self.channels, rate,
                                                          asked=asked), gave_up)  # fmt: skip
        self.device, self.samplerate = device, rate
        self.player = Player(self.carrier_hz, rate, ramp_s=self.ramp_s, outputs=self.channels,
                             top=self.profile.levels - 1, waveforms=self.waveforms)  # fmt: skip
        self._last_callback = self._clock.now()
        self._failure = ""
        self._finished = False
        self.underflows = 0
        self._late_taken = 0
        left = max(opened_by - self._clock.now(), 0.05)
        self._stream = stream = _within(left, lambda: self._start(sd, device, rate), gave_up)
        deadline = self._clock.now() + OPEN_TIMEOUT_S  # frames wait for a steady stream
        while not self.player.clock.locked and self._clock.now() < deadline and _active(stream):
            self._clock.sleep(0.002)
        self.description = (
            f"{self.url} ({device['name']}, {self.channels} channels at {rate} Hz, latency "
            f"{self.latency_s * 1e3:.1f} ms)"
        )
        _OPEN.add(self)
        if not _EXIT_HOOK:  # after sounddevice's own hook, so that it runs before it
            _EXIT_HOOK.append(atexit.register(_close_all))

    def _start(self, sd, device: dict, rate: int):
        """Open and start the output stream (on the opening's thread); :class:`LinkError`."""
        stream = None
        try:
            stream = sd.OutputStream(
                device=device["index"],
                channels=self.channels,
                samplerate=rate,
                blocksize=BLOCK,
                dtype="float32",
                latency="low",
                callback=self._callback,
                finished_callback=self._on_finished,
            )
            self.latency_s = float(stream.latency)
            stream.start()
        except Exception as exc:  # sounddevice.PortAudioError
            if stream is not None:  # opened, then failed to start: let go of the device
                try:
                    stream.close(ignore_errors=True)
                except Exception:
                    pass
            raise LinkError(
                f"cannot open audio device {device['name']!r} ({self.channels} channels at "
                f"{rate} Hz): {exc}"
            ) from None
        return stream

    @property
    def max_rate_hz(self) -> float:
        """Frames a second this link plays: each must last at least its ramp (1000 at most)."""
        return min(1000.0, 1.0 / self.ramp_s) if self.ramp_s > 0 else 1000.0

    @property
    def rate_limit(self) -> str:
        """Why :attr:`max_rate_hz` is the limit, for the streamer's status line."""
        return f"a frame must outlast its {self.ramp_s * 1e3:g} ms ramp"

    def _alive(self) -> None:
        """:class:`LinkError` if the stream is gone: closed, failed, stopped or stalled."""
        stream = self._stream
        if stream is None:
            raise LinkError(f"not connected: {self.url}")
        name = self.device["name"]
        if self._failure:
            raise LinkError(f"audio stopped on {name!r}: the callback failed ({self._failure})")
        if self._finished or not _active(stream):
            raise LinkError(
                f"audio device stopped: {name!r} (unplugged, or taken by another program?)"
            )
        silent_for = self._clock.now() - self._last_callback
        if silent_for > STALL_S:
            raise LinkError(
                f"audio device stalled: {name!r} has asked for no samples in {silent_for:.1f} s"
            )

    # --- the writer's side (the streamer's thread) ---------------------------------------------

    takes_voices = True
    """It plays a waveform per channel: a writer may hand each frame's (:meth:`write`)."""

    def write(self, data: bytes, *, voices=None) -> None:
        """Receive bytes as the array would; what it applies or queues goes to the callback.

        ``voices``: the waveforms the frames in ``data`` ask for, one per channel in channel
        order (a :class:`~.waveform.Waveform`, or None for the channel's own), as a pattern's
        effects give them; None: every channel its own. A lit channel takes its waveform from
        the frame that lights it; one that is off keeps the one it had."""
        self._alive()
        now = self._clock.now()
        with self._lock:
            model, player = self.model, self.player
            late = player.late  # the callback's count, into the model's (its clock replies)
            model.late += late - self._late_taken
            self._late_taken = late
            model.watchdog(now)
            replies, frames = model.receive(data, now)
            model.onsets.clear()  # nobody reads them here; they would pile up
            self._replies += replies
            player.schedule(model, frames, now, voices)

    def read(self) -> bytes:
        """What the array answered since the last read."""
        self._alive()
        with self._lock:
            data, self._replies = bytes(self._replies), bytearray()
        return data

    # --- the callback's side (PortAudio's thread) ----------------------------------------------

    def _callback(self, outdata, frames, time_info, status) -> None:
        try:
            now = self._clock.now()
            self._last_callback = now
            ahead = time_info.outputBufferDacTime - time_info.currentTime
            if not (time_info.currentTime and 0.0 <= ahead < 1.0):
                ahead = self.latency_s  # a host API without timing: the nominal latency
            if status.output_underflow:
                self.underflows += 1
            self.player.play(outdata, frames, now + ahead)
        except Exception as exc:  # never a traceback on the audio thread: a status, silence
            outdata.fill(0.0)
            self._failure = f"{type(exc).__name__}: {exc}"
            raise self._sd.CallbackAbort from None

    def _on_finished(self) -> None:
        self._finished = True

    # --- closing -------------------------------------------------------------------------------

    def close(self) -> None:
        """Fade every channel to zero, play silence, then stop and close the stream
        (idempotent; never raises)."""
        stream = self._stream
        if stream is None:
            return
        _OPEN.discard(self)
        try:
            if not (self._failure or self._finished) and stream.active:
                with self._lock:
                    self.player.fade_out(self._clock.now())
                deadline = self._clock.now() + FADE_TIMEOUT_S
                while self.player.silent_blocks < 2 and self._clock.now() < deadline:
                    self._clock.sleep(0.002)
                if self.player.silent_blocks >= 2:
                    stream.stop()  # plays out what is buffered: silence
                else:
                    stream.abort()  # the callback is not running: nothing more will play
            else:
                stream.abort()
        except Exception:  # a device that vanished while closing
            pass
        finally:
            self._stream = None
            try:
                stream.close(ignore_errors=True)
            except Exception:
                pass

    @property
    def amplitudes(self) -> np.ndarray:
        """The amplitudes the carriers are at or heading to, in channel order (a copy)."""
        return self.player.synth.target.copy()


__all__ = [
    "CARRIER_RANGE_HZ",
    "DEFAULT_CARRIER_HZ",
    "DEFAULT_RAMP_MS",
    "RAMP_RANGE_MS",
    "SAMPLERATE_RANGE",
    "AudioLink",
    "Player",
    "audio_outputs",
    "carriers_for",
    "check_device",
    "device_url",
    "find_device",
    "load_sounddevice",
    "output_devices",
    "parse_audio_url",
    "synthesize",
    "waveforms_for",
]
