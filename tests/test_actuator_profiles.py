"""The bundled profiles of the actuator families a lab meets (ERM wired and wireless, LRA,
voice coil on an audio interface): they load, their motor constants are within the ranges their
notes source or estimate, and they say which is which."""

import json
import math

import pytest

from tactile_core._shared.assets import asset_path
from tactile_core.bench import FAMILIES, Setting, Target
from tactile_core.device.profile import find_profile, profile_names


@pytest.mark.parametrize("family", FAMILIES, ids=lambda f: f.profile)
def test_each_family_has_a_bundled_profile_whose_constants_are_within_its_range(family):
    profile = find_profile(family.profile)
    assert family.profile in profile_names()
    up_ms, down_ms = profile.motor.tau_up_s * 1e3, profile.motor.tau_down_s * 1e3
    assert family.tau_up_ms[0] <= up_ms <= family.tau_up_ms[1]
    assert family.tau_down_ms[0] <= down_ms <= family.tau_down_ms[1]
    # The profile's note states the same range (or the palm array's, which it refers to).
    note = profile.motor.note
    assert "estimate" in note
    lo, hi = family.tau_up_ms
    assert f"tau_up {lo:g}-{hi:g} ms" in note or "see palm-5x6" in note


def test_the_ranges_follow_the_sources_arithmetic():
    """A first-order motor is at 90% after ln(10) tau: the ERM's 50-180 ms to full amplitude
    (Precision Microdrives) is tau 22-78 ms, inside 20-80. A resonator's envelope decays with
    tau = Q / (pi f0): LRA f0 150-235 Hz at Q 5-20 is 6.8-42 ms; a 200 Hz voice coil at Q 1-5
    is 1.6-8.0 ms."""
    erm = next(f for f in FAMILIES if f.profile == "palm-5x6")
    assert erm.tau_up_ms[0] <= 50 / math.log(10) and 180 / math.log(10) <= erm.tau_up_ms[1]
    lra = next(f for f in FAMILIES if f.profile == "lra-5x6")
    assert lra.tau_up_ms[0] <= 5 / (math.pi * 0.235) and 20 / (math.pi * 0.150) <= lra.tau_up_ms[1]
    coil = next(f for f in FAMILIES if f.profile == "voicecoil-8")
    assert coil.tau_up_ms[0] <= 1 / (math.pi * 0.2) and 5 / (math.pi * 0.2) <= coil.tau_up_ms[1]


def test_the_palm_arrays_constants_stay_marked_as_estimates():
    profile = find_profile("palm-5x6")
    assert (profile.motor.tau_up_s, profile.motor.tau_down_s) == (0.030, 0.060)
    assert "estimates, not measured on the paper's array" in profile.motor.note


def test_the_voice_coils_play_on_an_audio_interface_and_the_others_on_a_serial_link():
    targets = {f.profile: Target.of(find_profile(f.profile)) for f in FAMILIES}
    assert targets["voicecoil-8"].audio and find_profile("voicecoil-8").carrier_hz == (250.0,)
    assert not any(t.audio for name, t in targets.items() if name != "voicecoil-8")
    # An audio interface takes 8 channels x 48000 samples x 4 bytes a second, any frame rate.
    assert targets["voicecoil-8"].bytes_per_s(Setting(rate_hz=25)) == 8 * 48000 * 4


def test_the_wireless_profile_carries_20_to_50_frames_a_second_of_16_levels():
    profile = find_profile("wireless-4x4")
    target = Target.of(profile)
    assert profile.levels == 16 and 20 <= profile.max_rate_hz <= 50
    # 16 channels: 'F', seq, N, 16 levels, 2 CRC bytes = 21, COBS + delimiter = 23 bytes;
    # 9600 baud is 960 bytes a second: 41.7 frames.
    assert target.bytes_per_s(Setting(rate_hz=40, levels=16)) == 40 * 23
    assert target.carries(Setting(rate_hz=40, levels=16))
    assert not target.carries(Setting(rate_hz=50, levels=16))


def test_timed_frames_pack_the_levels_in_the_bytes_column():
    # 30 channels of 23 levels: 5 bits each, 19 bytes + 'T', seq, time (4), N, 2 CRC = 28,
    # COBS + delimiter = 30 bytes (docs/device.md); frames for now 37.
    target = Target.of(find_profile("palm-5x6"))
    assert target.bytes_per_s(Setting(rate_hz=300)) == 300 * 37
    assert target.bytes_per_s(Setting(rate_hz=300, lead_ms=20)) == 300 * 30
    assert not target.carries(Setting(rate_hz=1000))
    assert target.link_label(Setting(rate_hz=1000)) == "37,000 (over 11,520)"


def test_the_new_profiles_are_plain_json_with_their_notes():
    for name in ("lra-5x6", "voicecoil-8", "wireless-4x4"):
        data = json.loads(asset_path("devices", f"{name}.json").read_text())
        assert data["name"] == name and data["motor"]["note"]
