"""What the trade takes from a device profile: its motors, levels and link; and the actuator
families a lab meets, with their motor constants' sourced (or estimated) ranges."""

from __future__ import annotations

from dataclasses import dataclass

from ..device.audio import BLOCK, DEFAULT_RAMP_MS
from ..device.wire import frame_length
from ..rendering.motor import PALM_MOTOR, MotorResponse
from ..stream.options import DEFAULT_LEAD_MS
from ._trade_model import Link, Setting, shared_motor

AUDIO_SAMPLERATE = 48_000
"""Samples a second an audio interface plays (the usual default): its data rate is
``channels x samplerate x 4`` bytes (float32), whatever the frame rate."""


@dataclass(frozen=True)
class Family:
    """An actuator family and the range of its motor constants.

    Attributes
    ----------
    name : str
    profile : str
        The bundled profile that stands for it.
    tau_up_ms, tau_down_ms : (float, float)
        The range of the time constants (ms) the sources (or estimates) give.
    basis : str
        Where the range comes from.
    """

    name: str
    profile: str
    tau_up_ms: tuple
    tau_down_ms: tuple
    basis: str


FAMILIES = (
    Family("ERM, wired (the paper's palm array)", "palm-5x6", (20.0, 80.0), (40.0, 160.0),
           "small ERMs reach full amplitude in ~50-180 ms at rated voltage (Precision "
           "Microdrives: ~180 ms for the 5 mm 305-000), t90 = 2.3 tau; run-down without braking "
           "slower (estimate)"),
    Family("ERM, wireless (BLE, like VibraForge)", "wireless-4x4", (20.0, 80.0), (40.0, 160.0),
           "as the wired ERMs; 16 levels and 41.7 frames/s of 16 channels"),
    Family("LRA", "lra-5x6", (4.0, 45.0), (4.0, 45.0),
           "tau = Q / (pi f0), f0 150-235 Hz, Q 5-20 (estimate): 7-42 ms open loop; a closed-"
           "loop driver's overdrive and braking (TI DRV2605) shortens it"),
    Family("voice coil on an audio interface", "voicecoil-8", (1.0, 10.0), (1.0, 10.0),
           "tau = Q / (pi f0), f0 ~200 Hz (Dayton Audio DAEX-13-4SM), Q 1-5 (estimate): "
           "1.6-8 ms"),
)  # fmt: skip
"""The actuator families of the recommendations, each with its bundled profile."""


@dataclass(frozen=True)
class Target:
    """The device the trade is for: its motors, levels, channels and link.

    Attributes
    ----------
    name : str
        The profile's name.
    motor : MotorResponse
        Shared time constants (a per-tactor profile's medians; the palm array's estimates for a
        profile without motor constants, ``motor_from_profile`` False).
    levels, channels, baud : int
    audio : bool
        An audio interface (the profile gives ``carrier_hz``): frames go to the callback, the
        interface takes ``channels x samplerate x 4`` bytes a second.
    lead_ms : float
        The lead the stream, the server and the tuner use unless told.
    motor_from_profile : bool
    """

    name: str
    motor: MotorResponse
    levels: int
    channels: int
    baud: int = 115200
    audio: bool = False
    lead_ms: float = DEFAULT_LEAD_MS
    motor_from_profile: bool = True

    @classmethod
    def of(cls, profile) -> Target:
        """The target of a :class:`~tactile_core.device.DeviceProfile`."""
        motor = profile.motor if profile.motor is not None else PALM_MOTOR
        return cls(profile.name, shared_motor(motor), profile.levels, profile.channels,
                   profile.baud, profile.carrier_hz is not None,
                   motor_from_profile=profile.motor is not None)  # fmt: skip

    @property
    def motor_label(self) -> str:
        """``"30/60 ms"``: the motors' spin-up / run-down time constants."""
        return f"{self.motor.tau_up_s * 1e3:g}/{self.motor.tau_down_s * 1e3:g} ms"

    @property
    def motor_source(self) -> str:
        """Where the constants come from: ``"measured 2026-05-01"`` (``tactile measure``) or
        ``"estimate"`` (:meth:`~tactile_core.rendering.motor.MotorResponse.describe`)."""
        return self.motor.describe().rpartition(" (")[2].rstrip(")")

    @property
    def max_rate_hz(self) -> float:
        """Frames a second the link carries (frames for now; an audio frame must outlast its
        ramp)."""
        if self.audio:
            return min(1000.0, 1e3 / DEFAULT_RAMP_MS)
        return self.baud / 10.0 / frame_length(self.channels)

    def link(self) -> Link:
        """What a frame for now waits for: its transmission, or an audio block."""
        if self.audio:
            return Link(0.0, BLOCK / AUDIO_SAMPLERATE)
        return Link(frame_length(self.channels) * 10.0 / self.baud, 0.0)

    def bytes_per_s(self, setting: Setting) -> float:
        """Bytes a second on the link: frames x frame bytes (timed frames with a lead pack
        their levels); an audio interface's sample stream."""
        if self.audio:
            return float(self.channels * AUDIO_SAMPLERATE * 4)
        bits = (setting.levels - 1).bit_length()
        timed = setting.lead_ms > 0
        return setting.rate_hz * frame_length(self.channels, timed=timed, bits=bits)

    def carries(self, setting: Setting) -> bool:
        """True when the link carries ``setting`` (the streamer caps a faster rate)."""
        if self.audio:
            return setting.rate_hz <= self.max_rate_hz + 1e-9
        return self.bytes_per_s(setting) <= self.baud / 10.0 + 1e-9

    def link_label(self, setting: Setting) -> str:
        """``"11,100"``, ``"37,000 (over 11,520)"``, ``"1,536,000 (audio)"``."""
        if self.audio:
            over = "" if self.carries(setting) else f", over {self.max_rate_hz:.0f} frames/s"
            return f"{self.bytes_per_s(setting):,.0f} (audio{over})"
        text = f"{self.bytes_per_s(setting):,.0f}"
        return text if self.carries(setting) else f"{text} (over {self.baud / 10:,.0f})"
