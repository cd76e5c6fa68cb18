"""What can be wrong with a sensor's recording, found before anything is fitted.

Each check raises :class:`MeasureError` (the measurement cannot give constants) or returns a
warning (the constants are measured, but the input was not as it should be: ``tactile measure
--out`` then writes nothing unless told to). Every message names the cause and what to check.
"""

from __future__ import annotations

import numpy as np

from ._signal import peaks

CLIP_LEVEL = 0.999
"""A sample this close to full scale (1) counts as clipped."""
MIN_SNR = 4.0
"""Vibration power over noise power (6 dB) below which a tactor counts as not moving."""
OTHER_TACTOR = 1.5
"""A scanned neighbour this many times louder than the asked tactor: the sensor is on it."""
BETWEEN_TACTORS = 0.7
"""A neighbour at least this loud against the asked tactor: the sensor may sit between them."""
SECOND_VIBRATION = 0.08
"""A second spectral line, not a harmonic nor hum, this strong against the first: two motors."""
HUM_WARNING = 0.05
"""Mains hum above this fraction of the full-drive amplitude is worth a warning."""


class MeasureError(ValueError):
    """A recording that gives no motor constants; the message says why and what to check."""


def check_clipping(x, what: str) -> None:
    """Refuse a recording that reaches full scale (the amplitudes and the fit would be
    wrong)."""
    x = np.asarray(x)
    clipped = int(np.count_nonzero(np.abs(x) >= CLIP_LEVEL))
    if clipped:
        raise MeasureError(
            f"{what}: the sensor's signal clips ({clipped} samples at full scale, "
            f"{clipped / max(x.size, 1):.2%} of the recording): turn the audio interface's "
            "input gain down (or the sensor's own) until full drive peaks near -6 dBFS"
        )


def no_response(what: str, cell_name: str, responding: dict, channels: dict) -> MeasureError:
    """The error for a tactor whose full-drive step shows no vibration.

    Parameters
    ----------
    responding : dict
        ``{tactor name: SNR}`` of the scanned tactors that did vibrate.
    channels : dict
        ``{input: SNR}`` of the interface's other inputs at the full-drive step, numbered
        from 1 as on the interface.
    """
    loud = {ch: snr for ch, snr in channels.items() if snr >= MIN_SNR}
    if responding:
        names = ", ".join(sorted(responding))
        return MeasureError(
            f"{what} does not move: no vibration while it is driven at full drive, though the "
            f"sensor picks up {names} when they are; check {cell_name}'s "
            "motor and its wiring, and that the profile's channel order sends its channel "
            "to it"
        )
    if loud:
        best = max(loud, key=loud.get)
        return MeasureError(
            f"{what}: no signal on the sensor's input channel, but input {best} of the "
            f"interface follows the stimulus ({10 * np.log10(loud[best]):.0f} dB above its "
            f"noise): the sensor is on input {best}; give ?channel={best} in the --input URL"
        )
    return MeasureError(
        f"{what}: no signal on the sensor: nothing above the noise while tactor {cell_name} "
        "is driven at full drive (nor while its neighbours are). Check that the array is "
        "on and receives the frames (the device URL), the sensor's cable and its power (an "
        "IEPE accelerometer needs the interface's constant-current supply), the input "
        "channel (?channel=N), the interface's gain, and that the sensor touches tactor "
        f"{cell_name}"
    )


def check_scan(what: str, cell_name: str, amplitudes: dict) -> str:
    """Which tactor the sensor sits on, from the scan's amplitudes ``{name: amplitude}`` (the
    asked tactor's under ``cell_name``): an error if another is clearly louder, a warning if
    one is nearly as loud, else ""."""
    own = amplitudes.get(cell_name, 0.0)
    others = {k: v for k, v in amplitudes.items() if k != cell_name}
    if not others:
        return ""
    loudest = max(others, key=others.get)
    ratio = others[loudest] / own if own > 0 else np.inf
    if ratio >= OTHER_TACTOR:
        raise MeasureError(
            f"{what}: the sensor is on tactor {loudest}, not on {cell_name} as asked: "
            f"{loudest} gives {ratio:.1f} times the vibration of {cell_name} when each is "
            f"pulsed. Move the sensor onto {cell_name} (or measure {loudest}: --tactors "
            f"{loudest})"
        )
    if ratio >= BETWEEN_TACTORS:
        return (
            f"the sensor picks up tactor {loudest} at {ratio:.0%} of {cell_name}: it may sit "
            f"between them or on the array's frame; mount it on {cell_name}'s housing"
        )
    return ""


def check_second_vibration(what: str, cell_name: str, steady, samplerate: float,
                           hum_hz: float | None) -> None:  # fmt: skip
    """Refuse a steady full-drive stretch with two vibrations: one motor's line and its
    harmonics are expected (and mains hum, when there is some), not a second line."""
    found = peaks(steady, samplerate, count=6)
    if len(found) < 2:
        return
    f1, a1 = found[0]
    width = 2.5 * samplerate / max(len(steady), 1)
    for f, a in found[1:]:
        harmonic = any(abs(f - k * f1) <= width for k in (0.5, 2, 3, 4))
        mains = hum_hz is not None and any(abs(f - k * hum_hz) <= 2.0 for k in range(1, 8))
        if not harmonic and not mains and a >= SECOND_VIBRATION * a1:
            raise MeasureError(
                f"{what}: two vibrations while only tactor {cell_name} is driven, at "
                f"{f1:.0f} Hz and {f:.0f} Hz ({a / a1:.0%} of the first): two motors move on "
                "its channel (a wiring fault, or a wrong channel order in the profile), or "
                "the sensor touches two tactors. Check the wiring and the profile's "
                "channel_order, and that the sensor touches only this tactor"
            )


def hum_warning(hz: float, amplitude: float, full_amplitude: float) -> str:
    """A warning for mains hum of ``amplitude`` at ``hz`` in the silence before the stimulus,
    against the full-drive vibration's amplitude ("" when it is too weak to matter)."""
    if full_amplitude <= 0 or amplitude < HUM_WARNING * full_amplitude:
        return ""
    return (
        f"mains hum at {hz:g} Hz, {amplitude / full_amplitude:.0%} of the vibration at full "
        "drive: a ground loop between the interface, the array's supply and the computer, "
        "or an unshielded sensor cable. It is taken off (fitted where nothing moves), but "
        "weak levels read less reliably: power the array from a separate supply or a "
        "battery, use a shielded cable, or lift the interface's ground"
    )
