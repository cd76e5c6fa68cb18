"""The audio link on a stand-in for sounddevice (tests/audio_fake.py): URLs and what they refuse,
devices and what they cannot do, the wire messages received as the firmware does, frames played
at their sample, the watchdog, the fade at close, and failures as status lines."""

import math
import sys

import numpy as np
import pytest

from tactile_core.device import audio
from tactile_core.device._audio_synth import synthesize
from tactile_core.device._audio_url import AudioURL, load_sounddevice, parse_audio_url
from tactile_core.device.audio import AudioLink
from tactile_core.device.link import LinkError, identify, open_link
from tactile_core.device.profile import default_profile, profile_from_dict
from tactile_core.device.wire import (
    Info,
    MessageReader,
    Status,
    encode_frame,
    encode_query,
    encode_timed,
    level_bits,
)

from .audio_fake import card, fake_audio

RATE = 48000
BLOCK = 256


def profile(channels=8, **extra):
    data = default_profile().to_dict()
    data.update(name=f"audio-{channels}", columns=channels, rows=1, **extra)
    return profile_from_dict(data)


def test_audio_urls_read_as_documented():
    assert parse_audio_url("audio:") == AudioURL()
    assert parse_audio_url("audio:USB?channels=8&carrier_hz=170") == AudioURL(
        "USB", 8, 170.0, None, 1.5
    )
    assert parse_audio_url("audio://hw%3F1?samplerate=96000&ramp_ms=0") == AudioURL(
        "hw?1", None, None, 96000, 0.0
    )


@pytest.mark.parametrize(
    "url, words",
    [
        ("audio:?chanels=8", ["unknown key 'chanels'", "channels, carrier_hz"]),
        ("audio:?channels=8&channels=9", ["'channels' given twice"]),
        ("audio:?channels", ["'channels' has no value"]),
        ("audio:?channels=eight", ["channels must be a whole number", "'eight'"]),
        ("audio:?channels=2.5", ["channels must be a whole number"]),
        ("audio:?channels=0", ["channels must be within 1-1024", "got 0"]),
        ("audio:?carrier_hz=0.5", ["carrier_hz must be within 1-1000 Hz"]),
        ("audio:?carrier_hz=1001", ["carrier_hz must be within 1-1000 Hz"]),
        ("audio:?carrier_hz=nan", ["carrier_hz must be within"]),
        ("audio:?samplerate=7999", ["samplerate must be within 8000-384000 Hz"]),
        ("audio:?samplerate=384001", ["samplerate must be within 8000-384000 Hz"]),
        ("audio:?ramp_ms=-1", ["ramp_ms must be within 0-20 ms"]),
        ("audio:?ramp_ms=x", ["ramp_ms must be a number"]),
    ],
)
def test_bad_audio_urls_are_refused_naming_the_key(url, words):
    with pytest.raises(LinkError) as caught:
        parse_audio_url(url)
    message = str(caught.value)
    assert message.startswith(f"invalid device URL {url!r}")
    for word in words:
        assert word in message


def test_an_unknown_device_is_refused_listing_what_there_is(monkeypatch):
    fake_audio(monkeypatch)
    with pytest.raises(LinkError) as caught:
        AudioLink("audio:Nope", profile())
    message = str(caught.value)
    assert "no audio output device 'Nope'" in message
    assert "'USB 8ch' (ALSA): at most 8 output channels, default samplerate 48000 Hz" in message
    assert "'Speakers' (ALSA): at most 2 output channels, default samplerate 44100 Hz" in message


def test_a_name_two_devices_share_is_ambiguous_and_an_index_picks_one(monkeypatch):
    fake_audio(monkeypatch, devices=[card("USB A", 8), card("USB B", 8)])
    with pytest.raises(LinkError, match="'usb' is ambiguous: it matches 'USB A', 'USB B'"):
        AudioLink("audio:usb", profile())
    assert AudioLink("audio:1", profile()).device["name"] == "USB B"
    assert AudioLink("audio:usb b", profile()).device["name"] == "USB B"


def test_more_channels_than_the_device_has_is_refused_naming_the_field(monkeypatch):
    fake_audio(monkeypatch)
    with pytest.raises(LinkError) as caught:
        AudioLink("audio:USB", default_profile())  # the palm array: 30 actuators
    message = str(caught.value)
    assert (
        "has 8 output channels: channels=30 (the 30 actuators of the profile palm-5x6)" in message
    )
    assert "at most 8 output channels, default samplerate 48000 Hz" in message
    with pytest.raises(LinkError, match="channels=16 \\(the URL's\\) is more"):
        AudioLink("audio:USB?channels=16", profile(4))
    with pytest.raises(LinkError, match="channels=2 is fewer than the 4 actuators"):
        AudioLink("audio:USB?channels=2", profile(4))


def test_a_samplerate_the_device_cannot_play_lists_what_it_supports(monkeypatch):
    fake_audio(monkeypatch)
    with pytest.raises(LinkError) as caught:
        AudioLink("audio:USB?samplerate=22050", profile())
    message = str(caught.value)
    assert "cannot play 8 channels at 22050 Hz (Invalid sample rate" in message
    assert "it supports at most 8 output channels, default samplerate 48000 Hz" in message


def test_no_default_device_and_no_portaudio_say_what_to_do(monkeypatch):
    fake_audio(monkeypatch, default_output=-1)
    with pytest.raises(LinkError, match="no default audio output device; the output devices"):
        AudioLink("audio:", profile())

    class NoPortAudio:
        def find_spec(self, name, path=None, target=None):
            if name == "sounddevice":
                raise OSError("PortAudio library not found")

    monkeypatch.delitem(sys.modules, "sounddevice", raising=False)
    monkeypatch.setattr(sys, "meta_path", [NoPortAudio(), *sys.meta_path])
    with pytest.raises(LinkError, match=r"audio needs the PortAudio library .*libportaudio2"):
        load_sounddevice()


def test_open_link_opens_audio_urls_and_hello_gets_the_profiles_array(monkeypatch):
    fake_audio(monkeypatch)
    link = open_link("audio:USB", profile(8, carrier_hz=170))
    assert isinstance(link, AudioLink)
    assert link.description.startswith("audio:USB (USB 8ch, 8 channels at 48000 Hz, latency")
    info, problem = identify(link, link.profile, timeout_s=0.1)
    assert problem == "" and isinstance(info, Info)
    assert (info.cols, info.rows, info.levels, info.pwm_hz) == (8, 1, 23, 170)
    assert info.scheduled  # timed frames play on the audio clock
    link.write(encode_frame(0, [22] * 8) + encode_query(7))
    (status,) = MessageReader(accept=(Status,)).feed(link.read())
    assert (status.seq, status.frames_applied, status.dropped) == (7, 1, 0)


def open_fake(monkeypatch, url="audio:USB", prof=None):
    sd, clock = fake_audio(monkeypatch)
    link = AudioLink(url, prof or profile(8, carrier_hz=[150, 200, 250, 300, 350, 400, 450, 500]))
    stream = sd.streams[-1]
    assert link.player.clock.locked  # opening waited for a steady stream
    return link, stream, clock


def expected(stream, link, frames):
    """What the synthesiser plays for ``frames`` = [(onset sample, levels)], over what the fake
    stream played."""
    onsets = [s for s, _ in frames]
    levels = np.array([lv for _, lv in frames])
    top = link.profile.levels - 1
    length = len(stream.played())
    blocks = synthesize(levels, onsets, top=top, carrier_hz=link.carrier_hz, samplerate=RATE,
                        ramp_s=link.ramp_s, length=length)  # fmt: skip
    return np.concatenate([b.copy() for b in blocks])


def same(played, want):
    """Sample for sample: the same arithmetic but for where the blocks split (1e-14 at most)."""
    np.testing.assert_allclose(played, want, rtol=0, atol=1e-7)


def test_a_frame_for_now_plays_from_the_next_block_sample_for_sample(monkeypatch):
    link, stream, _ = open_fake(monkeypatch)
    before = len(stream.blocks)
    levels = [0, 3, 7, 11, 15, 19, 22, 1]
    link.write(encode_frame(0, levels))
    stream.pump(4)
    played = stream.played()
    want = expected(stream, link, [(before * BLOCK, levels)])
    same(played, want)  # the callback is the WAV export's synthesiser
    s = np.arange(before * BLOCK + 100, len(played))  # after the ramp: level / 22 x carrier
    for c, hz in enumerate(link.carrier_hz):
        carrier = np.sin(2 * np.pi * hz * s / RATE)
        np.testing.assert_allclose(played[s, c], levels[c] / 22 * carrier, atol=1e-6)


def test_a_timed_frame_starts_at_the_sample_its_time_falls_on(monkeypatch):
    link, stream, clock = open_fake(monkeypatch)
    now = clock.now()
    first = len(stream.blocks)
    at = now + 0.02 + 123.4 / RATE  # 20 ms ahead, between two samples
    at_us = link.model.clock_us(at)
    link.write(encode_timed(0, at_us, [22] * 8, level_bits(23)))
    stream.pump(8)
    host = link.model.epoch + at_us / 1e6  # the frame's time as the array's clock gives it
    k = max(i for i in range(first, len(stream.starts)) if stream.starts[i] <= host)
    onset = k * BLOCK + math.ceil((host - stream.starts[k]) * RATE - 1e-6)
    same(stream.played(), expected(stream, link, [(onset, [22] * 8)]))
    assert link.player.late == 0


def test_a_timed_frame_the_callback_meets_too_late_plays_at_once_and_counts(monkeypatch):
    link, stream, clock = open_fake(monkeypatch)
    # due before the next block starts (the stream plays 8 ms ahead of the clock)
    link.write(encode_timed(0, link.model.clock_us(clock.now() + 0.004), [9] * 8, 5))
    first = len(stream.blocks)
    stream.pump(2)
    assert link.player.late == 1
    same(stream.played(), expected(stream, link, [(first * BLOCK, [9] * 8)]))
    link.write(encode_frame(1, [9] * 8))
    assert link.model.late == 1  # the array's count, which its clock replies report


def test_the_watchdog_fades_everything_out_250_ms_after_the_last_frame(monkeypatch):
    link, stream, clock = open_fake(monkeypatch)
    fed = clock.now()
    first = len(stream.blocks)
    link.write(encode_frame(0, [22] * 8))
    stream.pump(round(0.3 * RATE / BLOCK))
    trip = fed + 0.25
    k = max(i for i in range(len(stream.starts)) if stream.starts[i] <= trip)
    off = k * BLOCK + math.ceil((trip - stream.starts[k]) * RATE - 1e-6)
    want = expected(stream, link, [(first * BLOCK, [22] * 8), (off, [0] * 8)])
    same(stream.played(), want)
    link.write(encode_query(1))
    (status,) = MessageReader(accept=(Status,)).feed(link.read())
    assert status.watchdog_trips == 1


def test_closing_fades_out_plays_silence_and_stops(monkeypatch):
    link, stream, _ = open_fake(monkeypatch)
    link.write(encode_frame(0, [22] * 8))
    stream.pump(3)
    link.close()
    played = stream.played()
    assert stream.stopped_by == "stop" and stream.closed  # stopped (buffers played), not aborted
    assert not played[-2 * BLOCK :].any()  # two whole blocks of silence at the end
    bound = 2 * math.pi * 500 / RATE + math.pi / (2 * 72)
    assert np.abs(np.diff(played, axis=0)).max() <= bound  # faded, never cut
    link.close()  # again: nothing
    with pytest.raises(LinkError, match="not connected: audio:USB"):
        link.write(encode_frame(1, [0] * 8))


def test_a_failing_callback_is_a_status_line_and_silence(monkeypatch):
    link, stream, _ = open_fake(monkeypatch)

    def boom(*args):
        raise RuntimeError("boom")

    monkeypatch.setattr(link.player, "play", boom)
    stream.pump()
    assert not stream.blocks[-1].any() and not stream.active
    with pytest.raises(LinkError) as caught:
        link.write(encode_frame(0, [1] * 8))
    assert (
        str(caught.value) == "audio stopped on 'USB 8ch': the callback failed (RuntimeError: boom)"
    )
    link.close()  # never raises
    assert stream.closed


def test_a_vanished_or_stalled_device_is_a_status_line(monkeypatch):
    link, stream, _ = open_fake(monkeypatch)
    stream.abort()  # PortAudio ends the stream when the device goes
    with pytest.raises(LinkError, match="audio device stopped: 'USB 8ch' \\(unplugged"):
        link.write(encode_frame(0, [1] * 8))
    link.reopen()  # plugged back in: a new stream
    assert link.player.clock.locked
    link.write(encode_frame(0, [1] * 8))
    clock = stream.sd.clock
    clock.advance(0.6)  # and now the callback stops being called
    with pytest.raises(LinkError, match=r"'USB 8ch' has asked for no samples in 0\.6 s"):
        link.read()


def test_outputs_beyond_the_actuators_stay_silent_and_a_url_carrier_wins(monkeypatch):
    link, stream, _ = open_fake(monkeypatch, "audio:USB?channels=8&carrier_hz=80", profile(3))
    assert link.carrier_hz.tolist() == [80.0, 80.0, 80.0]
    link.write(encode_frame(0, [22, 22, 22]))
    stream.pump(4)
    played = stream.played()
    assert played.shape[1] == 8 and played[:, :3].any() and not played[:, 3:].any()


def measure_callback_allocations():
    """Traced bytes before and after 200 callback blocks, and the peak between (run in a
    process of its own: a pytest-xdist worker's other threads allocate while it measures)."""
    import tracemalloc

    with pytest.MonkeyPatch.context() as monkeypatch:
        link, _, clock = open_fake(monkeypatch)
        out = np.zeros((BLOCK, 8), dtype=np.float32)
        player = link.player
        for k in range(20):  # events to play: frames for now and timed ones within the blocks
            link.write(encode_frame(k, [k % 23] * 8))
            link.write(encode_timed(k, link.model.clock_us(clock.now() + 0.01), [22] * 8, 5))
        events = player.events
        tracemalloc.start()
        try:
            start = clock.now()
            player.play(out, BLOCK, start)  # warm: numpy's first calls cache things
            before, _ = tracemalloc.get_traced_memory()
            tracemalloc.reset_peak()
            for k in range(200):
                player.events = events if k % 10 == 0 else player.events
                player.play(out, BLOCK, start + (k + 1) * BLOCK / RATE)
            after, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
    return before, after, peak


def test_the_callback_allocates_no_arrays():
    import json
    import subprocess
    from pathlib import Path

    code = ("import json; from tests.test_audio_link import measure_callback_allocations as m; "
            "print(json.dumps(m()))")  # fmt: skip
    root = Path(__file__).resolve().parents[1]
    proc = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True,
                          text=True, timeout=120)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    before, after, peak = json.loads(proc.stdout.splitlines()[-1])
    assert peak - before < 4096  # not one block's worth (8 KB): views and scalars come and go
    assert after - before < 256


def test_the_streamer_takes_the_links_own_rate_limit():
    import tactile_core as tc
    from tactile_core.rendering.scene import Scene
    from tactile_core.stream._plan import _Plan
    from tactile_core.stream._talk import ArrayTalk

    class Link:
        description = "audio:x"
        max_rate_hz = 666.0
        rate_limit = "a frame must outlast its 1.5 ms ramp"
        byte_s = 0.0

    talk = ArrayTalk(Link(), default_profile(), lead_s=0.0, update=lambda **k: None)
    assert talk.max_rate_hz == 666.0 and talk.clock.s_request == 0.0
    plan = _Plan(
        Scene(tc.Line((0.5, 0.5), (4.5, 5.5)), rate_hz=1000), default_profile(), 20.0, 666.0
    )
    _, status = plan.describe(default_profile(), Link(), "")
    assert "the link carries 666 frames/s (a frame must outlast its 1.5 ms ramp)" in status
    assert audio.AudioLink.byte_s == 0.0


def test_profile_carriers_one_for_all_or_one_per_channel_refused_naming_the_field():
    from tactile_core.device.audio import carriers_for
    from tactile_core.device.profile import ProfileError

    one = profile(4, carrier_hz=170)
    assert one.carrier_hz == (170.0,) and one.to_dict()["carrier_hz"] == 170.0
    assert carriers_for(one).tolist() == [170.0] * 4
    each = profile(4, carrier_hz=[100, 150, 200, 250.5])
    assert profile_from_dict(each.to_dict()) == each  # written back by to_dict
    assert carriers_for(each).tolist() == [100.0, 150.0, 200.0, 250.5]
    assert carriers_for(profile(4)).tolist() == [250.0] * 4  # neither says: 250 Hz
    assert carriers_for(each, 80.0).tolist() == [80.0] * 4  # a URL's wins
    for bad, words in [
        (0.5, "field 'carrier_hz' must be within [1, 1000] Hz, got 0.5"),
        ([100, 2000, 100, 100], "field 'carrier_hz[1]' must be within [1, 1000] Hz, got 2000"),
        ([100, 100], "field 'carrier_hz' must hold 4 values, got 2"),
        ("x", "field 'carrier_hz' must be a finite number"),
    ]:
        with pytest.raises(ProfileError) as caught:
            profile(4, carrier_hz=bad)
        assert words in str(caught.value)


def test_the_block_clock_ignores_a_stall_and_follows_a_real_shift():
    from tactile_core.device._audio_play import BlockClock

    period = BLOCK / RATE
    clock = BlockClock(RATE)
    # the first blocks arrive at once (PortAudio fills its buffers), then one a period
    starts = [clock.block(10.0 + max(k - 3, 0) * period, BLOCK) for k in range(3)]
    starts += [clock.block(10.0 + k * period, BLOCK) for k in range(3, 60)]
    assert clock.locked and starts[-1] == pytest.approx(10.0 + 59 * period, abs=1e-9)
    k = 60
    # a 50 ms stall: blocks measured late, then a burst that catches up
    late = [0.05 - j * period for j in range(10)]
    for extra in late:
        assert clock.block(10.0 + k * period + max(extra, 0.0), BLOCK) == pytest.approx(
            10.0 + k * period, abs=21e-6
        )  # 2 us a block at most
        k += 1
    assert clock.locked and clock.resyncs == 0
    # the stream really moved by 20 ms (a dropout): followed within 150 ms and a few blocks
    for _ in range(60):
        start = clock.block(10.02 + k * period, BLOCK)
        k += 1
    assert clock.resyncs == 1 and clock.locked
    assert start == pytest.approx(10.02 + (k - 1) * period, abs=30e-6)


def test_audio_output_of_names_the_device_a_url_opens(monkeypatch):
    fake_audio(monkeypatch, devices=[card("Speakers", 2, 44100), card("USB 8ch", 8)],
               default_output=1)  # fmt: skip
    label = "USB 8ch (ALSA, 8 channels, 48000 Hz)"
    assert audio.audio_output_of("audio:") == ("audio:USB 8ch", label)  # the default device
    assert audio.audio_output_of("audio:usb?carrier_hz=170") == ("audio:USB 8ch", label)
    assert audio.audio_output_of("audio:0")[0] == "audio:Speakers"
    for url in ("audio:Nowhere", "socket://localhost:5000", "/dev/ttyUSB0"):
        assert audio.audio_output_of(url) is None
