"""``audio:`` device URLs and the audio devices they name, through PortAudio (``sounddevice``).

``audio:`` is the default output device; ``audio:NAME`` a device by its index, its name, or a
part of its name that only one output device has; a query sets ``channels``, ``carrier_hz``,
``samplerate``, ``ramp_ms`` and ``waveform`` (``audio:USB?channels=8&carrier_hz=170``,
``audio:USB?waveform=square:200``). Every problem is a :class:`~.link.LinkError` whose message
names the key or lists what the devices offer.
"""

from __future__ import annotations

import math
import urllib.parse
from dataclasses import dataclass

from .._shared import validate as _validate
from ._audio_synth import DEFAULT_RAMP_MS
from ._link_error import LinkError
from .waveform import CARRIER_RANGE_HZ, Waveform, WaveformError, parse_waveform

SCHEME = "audio:"
KEYS = ("channels", "carrier_hz", "samplerate", "ramp_ms", "waveform")
"""The keys an ``audio:`` URL's query may set."""
SAMPLERATE_RANGE = (8000, 384000)
RAMP_RANGE_MS = (0.0, 20.0)
MAX_CHANNELS = 1024
INSTALL = "Debian/Ubuntu: apt-get install libportaudio2"
PA_DEVICE_UNAVAILABLE = -9985
"""PortAudio's ``paDeviceUnavailable``: the device is open in another program (or gone)."""


@dataclass(frozen=True)
class AudioURL:
    """What an ``audio:`` URL asks for (None: the profile's, or the device's, default)."""

    device: str = ""
    channels: int | None = None
    carrier_hz: float | None = None
    samplerate: int | None = None
    ramp_ms: float = DEFAULT_RAMP_MS
    waveform: Waveform | None = None


def is_audio_url(url) -> bool:
    """True for ``audio:`` URLs (any case of the scheme)."""
    return isinstance(url, str) and url[: len(SCHEME)].lower() == SCHEME


def _value(url: str, key: str, text: str, whole: bool):
    try:
        value = _validate.decimal_text(key, text, whole=whole)
    except ValueError:
        kind = "a whole number" if whole else "a number"
        raise LinkError(
            f"invalid device URL {url!r}: {key} must be {kind}, got {_validate.shown(text)}"
        ) from None
    return value


def parse_audio_url(url: str) -> AudioURL:
    """Read an ``audio:`` URL.

    Raises
    ------
    LinkError
        Naming the key: an unknown or repeated key, a value that is not a number, or one out of
        range (channels < 1, a carrier outside 1-1000 Hz, a samplerate outside 8000-384000 Hz,
        a ramp outside 0-20 ms), a waveform spec that does not read (naming its field).

    Examples
    --------
    >>> parse_audio_url("audio:USB%3F?channels=8&carrier_hz=170")  # doctest: +NORMALIZE_WHITESPACE
    AudioURL(device='USB?', channels=8, carrier_hz=170.0, samplerate=None, ramp_ms=1.5,
             waveform=None)
    >>> parse_audio_url("audio:USB?waveform=square:200").waveform.spec
    'square:200'
    """
    if not is_audio_url(url):
        raise LinkError(f"invalid device URL {url!r}: an audio URL starts with 'audio:'")
    rest = url[len(SCHEME) :]
    if rest.startswith("//"):  # audio://NAME reads as audio:NAME
        rest = rest[2:]
    name, _, query = rest.partition("?")
    fields: dict = {"device": urllib.parse.unquote(name).strip()}
    for pair in query.split("&") if query else ():
        key, eq, text = pair.partition("=")
        key = urllib.parse.unquote(key)
        if key not in KEYS:
            raise LinkError(
                f"invalid device URL {url!r}: unknown key {key!r} (known: {', '.join(KEYS)})"
            )
        if key in fields:
            raise LinkError(f"invalid device URL {url!r}: key {key!r} given twice")
        if not eq:
            raise LinkError(f"invalid device URL {url!r}: key {key!r} has no value ({key}=...)")
        text = urllib.parse.unquote(text)
        if key == "waveform":
            try:
                fields[key] = parse_waveform(text)
            except WaveformError as exc:
                raise LinkError(f"invalid device URL {url!r}: {exc}") from None
            continue
        fields[key] = _value(url, key, text, key in ("channels", "samplerate"))
    checks = {
        "channels": (1, MAX_CHANNELS, ""),
        "carrier_hz": (*CARRIER_RANGE_HZ, " Hz"),
        "samplerate": (*SAMPLERATE_RANGE, " Hz"),
        "ramp_ms": (*RAMP_RANGE_MS, " ms"),
    }
    for key, (lo, hi, unit) in checks.items():
        value = fields.get(key)
        if value is not None and not (math.isfinite(value) and lo <= value <= hi):
            raise LinkError(
                f"invalid device URL {url!r}: {key} must be within {lo:g}-{hi:g}{unit}, "
                f"got {_validate.shown(value)}"
            )
    return AudioURL(**fields)


def audio_url(name: str) -> str:
    """The ``audio:`` URL of a device name (``%`` and ``?`` escaped, the rest as it is)."""
    return SCHEME + name.replace("%", "%25").replace("?", "%3F")


def load_sounddevice():
    """The ``sounddevice`` module; :class:`LinkError` saying what to install if PortAudio or the
    package is missing."""
    try:
        import sounddevice
    except OSError as exc:  # the package is there, the PortAudio library is not
        raise LinkError(f"audio needs the PortAudio library ({INSTALL}): {exc}") from None
    except ImportError:
        raise LinkError(
            "audio needs the Python package sounddevice (pip install sounddevice)"
        ) from None
    return sounddevice


def output_devices(sd) -> list[dict]:
    """The output devices PortAudio knows: dicts with ``index``, ``name``,
    ``max_output_channels``, ``default_samplerate`` and ``hostapi`` (its name)."""
    apis = [api["name"] for api in sd.query_hostapis()]
    found = []
    for info in sd.query_devices():
        if info["max_output_channels"] > 0:
            found.append({**info, "hostapi": apis[info["hostapi"]]})
    return found


def describe_device(device: dict) -> str:
    """``'NAME' (ALSA): at most 8 output channels, default samplerate 48000 Hz``."""
    return (
        f"{device['name']!r} ({device['hostapi']}): at most {device['max_output_channels']} "
        f"output channels, default samplerate {device['default_samplerate']:g} Hz"
    )


def _listing(devices: list[dict]) -> str:
    if not devices:
        return "PortAudio finds no audio output device"
    shown = "; ".join(f"{d['index']}: {describe_device(d)}" for d in devices[:20])
    more = f"; and {len(devices) - 20} more" if len(devices) > 20 else ""
    return f"the output devices are {shown}{more}"


def find_device(sd, name: str) -> dict:
    """The output device ``name`` names: '' the default one, digits an index, else the device
    of that exact name, or the only one whose name contains it (ignoring case).

    Raises
    ------
    LinkError
        No such device, or several match; the message lists the output devices.
    """
    devices = output_devices(sd)
    if name == "":
        try:  # sounddevice's default.device is an (input, output) pair, not a list
            index = int(sd.default.device[1])
        except (TypeError, ValueError, IndexError, KeyError):
            index = -1
        chosen = [d for d in devices if d["index"] == index]
        if not chosen:
            raise LinkError(f"no default audio output device; {_listing(devices)}")
        return chosen[0]
    if is_index(name):
        chosen = [d for d in devices if d["index"] == int(name)]
    else:
        chosen = [d for d in devices if d["name"] == name] or [
            d for d in devices if name.lower() in d["name"].lower()
        ]
    if len(chosen) == 1:
        return chosen[0]
    if chosen:
        names = ", ".join(repr(d["name"]) for d in chosen[:10])
        raise LinkError(f"audio device {name!r} is ambiguous: it matches {names}; name one by "
                        f"its index (audio:N): {_listing(chosen)}")  # fmt: skip
    raise LinkError(f"no audio output device {name!r}; {_listing(devices)}")


def is_index(name: str) -> bool:
    """True for a device name that ``audio:NAME`` reads as an index: ASCII digits only."""
    return name.isascii() and name.isdigit()


def device_url(device: dict, devices: list[dict]) -> str:
    """The ``audio:`` URL that opens ``device`` among ``devices``: by its name, or by its index
    where the name would not find it (a name several devices share, as the host APIs of
    Windows do; a name of digits, read as an index; an empty or space-padded one)."""
    name = device["name"]
    if (
        name
        and name == name.strip()
        and not is_index(name)
        and not name.startswith("//")
        and sum(d["name"] == name for d in devices) == 1
    ):
        return audio_url(name)
    return f"{SCHEME}{device['index']}"


def check_device(sd, device: dict, channels: int, samplerate: int, *, asked: str) -> None:
    """Refuse a device that cannot play ``channels`` at ``samplerate``; the message names the
    field (``asked`` says where the channel count came from) and what the device supports."""
    have = device["max_output_channels"]
    if channels > have:
        raise LinkError(
            f"audio device {device['name']!r} has {have} output channels: channels={channels} "
            f"({asked}) is more; {describe_device(device)}"
        )
    try:
        sd.check_output_settings(
            device=device["index"], channels=channels, dtype="float32", samplerate=samplerate
        )
    except Exception as exc:  # sounddevice.PortAudioError, ValueError
        if exc.args[1:2] == (PA_DEVICE_UNAVAILABLE,):  # busy: not a matter of channels or rate
            raise LinkError(
                f"audio device {device['name']!r} is busy or unavailable (in use by another "
                f"program, or unplugged?): {exc}"
            ) from None
        raise LinkError(
            f"audio device {device['name']!r} cannot play {channels} channels at "
            f"{samplerate} Hz ({exc}); it supports {describe_device(device).split(': ', 1)[1]}"
        ) from None
