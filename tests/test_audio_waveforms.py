"""Waveforms per channel on the audio transport: the profile's ``waveform`` and the URL's, the
link's callback through the fake PortAudio (tests/audio_fake.py), the waveforms a stream hands
the link frame by frame, a per-channel mixture written to WAV and read back with ``wave``, and
one stream of a pattern through ALSA's file plugin (tests/audio_support.py)."""

import json
import signal
import sys
import threading
import wave

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.cli import main
from tactile_core.device.audio import AudioLink
from tactile_core.device.host_clock import VirtualClock
from tactile_core.device.link import LinkError, SimulatedArray
from tactile_core.device.profile import ProfileError, default_profile, load_profile
from tactile_core.device.profile import profile_from_dict as from_dict
from tactile_core.device.waveform import parse_waveform
from tactile_core.device.wire import encode_frame
from tactile_core.rendering.scene import Scene
from tactile_core.stream import Streamer

from .audio_fake import fake_audio
from .audio_support import CaptureSink, require_audio, run_cli
from .serve_support import wait_for
from .test_waveforms import noise_sample

RATE = 48000
BLOCK = 256
SQUARE = parse_waveform("square:200")


def profile_json(channels=8, **extra):
    data = default_profile().to_dict()
    data.update(name=f"audio-{channels}", columns=channels, rows=1, **extra)
    return data


def read_wav(path):
    with wave.open(str(path), "rb") as f:
        assert f.getsampwidth() == 2
        data = np.frombuffer(f.readframes(f.getnframes()), dtype="<i2")
        return data.reshape(-1, f.getnchannels()) / 32767.0, f.getframerate()


# --- the profile and the URL ----------------------------------------------------------------


def test_a_profile_gives_one_waveform_for_all_or_one_per_channel_and_writes_them_back():
    one = from_dict(profile_json(4, waveform="square:200+adsr:5,20,0.7,50"))
    assert one.waveform == (parse_waveform("square:200+adsr:5,20,0.7,50"),)
    assert one.to_dict()["waveform"] == "square:200+adsr:5,20,0.7,50"
    specs = ["sine", "square", "noise:seed=3", "sweep:100-300:500ms:log"]
    each = from_dict(profile_json(4, waveform=specs))
    assert [w.spec for w in each.waveform] == specs
    assert from_dict(each.to_dict()) == each
    # the bundled profiles name none, and say none
    for name in ("voicecoil-8", "palm-5x6", "belt-8"):
        prof = load_profile(name)
        assert prof.waveform is None and "waveform" not in prof.to_dict()


@pytest.mark.parametrize(
    "waveform, words",
    [
        ("squar", "field 'waveform' 'squar': shape must be one of sine, square"),
        (["sine", "sine", "noise:seed=x", "sine"], "field 'waveform[2]' 'noise:seed=x': seed must"),
        (["sine", "sine"], "field 'waveform' must hold 4 specs (one per channel) or be one spec"),
        (250, "field 'waveform' must be a spec such as 'square:200', got 250"),
        (["sine", "sine", "sine", 1], "field 'waveform[3]' must be a spec such as"),
    ],
)
def test_a_bad_profile_waveform_is_refused_naming_the_field(waveform, words):
    with pytest.raises(ProfileError) as caught:
        from_dict(profile_json(4, waveform=waveform), source="four.json")
    assert str(caught.value).startswith("four.json: ")
    assert words in str(caught.value)


def test_the_url_gives_one_waveform_for_every_channel_and_a_bad_one_names_the_key(monkeypatch):
    fake_audio(monkeypatch)
    prof = from_dict(profile_json(8, waveform="noise"))
    link = AudioLink("audio:USB?waveform=square:200", prof)
    assert link.waveforms == (SQUARE,) * 8
    assert AudioLink("audio:USB", prof).waveforms == (parse_waveform("noise"),) * 8
    with pytest.raises(LinkError) as caught:
        AudioLink("audio:USB?waveform=square:2000", prof)
    assert str(caught.value) == (
        "invalid device URL 'audio:USB?waveform=square:2000': waveform 'square:2000': "
        "frequency must be within 1-1000 Hz, got 2000"
    )


# --- the link's callback ----------------------------------------------------------------------


def open_fake(monkeypatch, **extra):
    sd, _ = fake_audio(monkeypatch)
    link = AudioLink("audio:USB?ramp_ms=0", from_dict(profile_json(8, **extra)))
    return link, sd.streams[-1]


def test_the_callback_plays_each_channels_waveform_and_a_frames_own(monkeypatch):
    specs = ["square:200", "sine:200", "noise", "saw:200"] + ["sine"] * 4
    link, stream = open_fake(monkeypatch, waveform=specs, carrier_hz=200)
    first = len(stream.blocks) * BLOCK
    link.write(encode_frame(0, [22] * 8))
    stream.pump(10)
    s = np.arange(first, first + 10 * BLOCK)
    x = stream.played()[first:]
    assert np.array_equal(x[:, 0], np.where(s % 240 < 120, 1.0, -1.0).astype(np.float32))
    assert np.allclose(x[:, 1], np.sin(2 * np.pi * s / 240), atol=1e-6)
    assert np.allclose(x[:, 2], [noise_sample(0, 2, k) for k in s], atol=1e-7)
    assert np.allclose(x[:, 3], np.where(s % 240 < 120, s % 240, s % 240 - 240) / 120, atol=1e-6)
    # a frame asks for a square on channel 4 (lit) and on 5 (off: it keeps its own)
    second = len(stream.blocks) * BLOCK
    levels = [22, 22, 22, 22, 22, 0, 22, 22]
    link.write(encode_frame(1, levels), voices=(None, None, None, None, SQUARE, SQUARE, None, None))
    stream.pump(4)
    s = np.arange(second, second + 4 * BLOCK)
    y = stream.played()[second:]
    assert np.array_equal(y[:, 4], np.where(s % 240 < 120, 1.0, -1.0).astype(np.float32))
    assert np.allclose(y[:, 6], np.sin(2 * np.pi * 200 * s / RATE), atol=1e-6)
    assert not y[:, 5].any()
    link.write(encode_frame(2, [0, 0, 0, 0, 0, 22, 0, 0]))  # lit by a frame without waveforms
    stream.pump(2)
    z = stream.played()[len(stream.played()) - BLOCK :]
    s = np.arange(len(stream.played()) - BLOCK, len(stream.played()))
    assert np.allclose(z[:, 5], np.sin(2 * np.pi * 200 * s / RATE), atol=1e-6)


def test_closing_cuts_a_release_short_and_ends_in_silence(monkeypatch):
    link, stream = open_fake(monkeypatch, waveform="sine:200+adsr:0,0,1,5000")
    link.write(encode_frame(0, [22] * 8))
    stream.pump(4)
    link.write(encode_frame(1, [0] * 8))  # a 5 s release begins
    stream.pump(4)
    assert np.abs(stream.played()[-BLOCK:]).max() > 0.9
    link.close()  # fades within the ramp and plays silence, then stops: no 5 s wait
    assert stream.stopped_by == "stop"
    assert not stream.played()[-2 * BLOCK :].any()


def measure_waveform_allocations():
    """Traced bytes before and after 200 callback blocks of mixed waveforms with frames that
    change them, and the peak between (run in a process of its own)."""
    import tracemalloc

    specs = [
        "sine",
        "square:200",
        "noise",
        "sweep:100-300:100ms",
        "sweep:300-100:50ms:log",
        "saw",
        "triangle+adsr:5,20,0.7,50",
        "sine:170+adsr:0,0,1,30",
    ]
    with pytest.MonkeyPatch.context() as monkeypatch:
        link, _ = open_fake(monkeypatch, waveform=specs)
        player = link.player
        out = np.zeros((BLOCK, 8), dtype=np.float32)
        voices = (SQUARE, None, parse_waveform("noise:seed=3"), None, None, None, None, SQUARE)
        for k in range(24):  # frames now and then, some with their own waveforms
            link.write(
                encode_frame(k, [(k * 7 + c) % 23 for c in range(8)]),
                voices=voices if k % 3 == 0 else None,
            )
        events = player.events
        start = 0.0
        player.play(out, BLOCK, start)  # warm: numpy's first calls cache things
        tracemalloc.start()
        try:
            for k in range(30):
                player.events = events
                player.play(out, BLOCK, start + (k + 1) * BLOCK / RATE)
            before, _ = tracemalloc.get_traced_memory()
            tracemalloc.reset_peak()
            for k in range(200):
                player.events = events if k % 10 == 0 else player.events
                player.play(out, BLOCK, start + (k + 31) * BLOCK / RATE)
            after, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
    return before, after, peak


def test_the_callback_with_waveforms_allocates_no_arrays():
    import subprocess
    from pathlib import Path

    code = (
        "import json; from tests.test_audio_waveforms import measure_waveform_allocations "
        "as m; print(json.dumps(m()))"
    )
    root = Path(__file__).resolve().parents[1]
    proc = subprocess.run(
        [sys.executable, "-c", code], cwd=root, capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    before, after, peak = json.loads(proc.stdout.splitlines()[-1])
    assert peak - before < 4096  # not one block's worth (2 KB a channel): scalars and views
    assert after - before < 1024


# --- the stream hands the link each frame's waveforms ------------------------------------------


class VoicedArray(SimulatedArray):
    """A simulated array that says it plays waveforms, and keeps what each write asked for."""

    takes_voices = True

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.voices = []
        self.lock = threading.Lock()

    def write(self, data, *, voices=None):
        super().write(data)
        with self.lock:
            self.voices.append(voices)


def test_a_stream_hands_the_link_each_frames_waveforms_in_channel_order():
    prof = from_dict({**profile_json(4), "channel_order": [3, 2, 1, 0]})
    noise = parse_waveform("noise")
    pattern = tc.Pattern(
        [
            tc.Effect(tc.Dots([tc.Dot(0, 1.0, 0.0, 0.2)]), waveform="square:200"),
            tc.Effect(tc.Dots([tc.Dot(1, 1.0, 0.0, 0.2)]), start_s=0.1, waveform=noise),
            tc.Effect(tc.Dots([tc.Dot(2, 0.5, 0.0, 0.3)])),
        ]
    )
    clock = VirtualClock()
    sim = VoicedArray(prof, clock=clock)
    scene = Scene(source=pattern, method="AS", rate_hz=50.0)
    with Streamer(sim, prof, scene=scene, clock=clock, spin_s=0.0) as streamer:
        wait_for(lambda: streamer.stats.frames >= 20, timeout_s=60, what="20 frames")
    with sim.lock:
        asked = [v for v in sim.voices if v is not None]
    # channel c plays actuator 3 - c: the square is on channel 3, the noise on channel 2
    assert (None, None, None, SQUARE) in asked  # the first 0.1 s
    assert (None, None, noise, SQUARE) in asked  # then both
    assert all(v[0] is None and v[1] is None for v in asked)  # no waveform of their own
    assert "needs an audio interface" not in streamer.stats.status


# --- a per-channel mixture in a WAV file ------------------------------------------------------


def test_a_per_channel_mixture_written_to_wav_reads_back_channel_by_channel(tmp_path):
    specs = [
        "sine",
        "square",
        "noise:seed=5",
        "sweep:100-400:2000ms",
        "triangle:50",
        "saw",
        "sine:300+adsr:20,0,1,0",
        "square:150+adsr:0,100,0,0",
    ]
    path = tmp_path / "mix.json"
    path.write_text(json.dumps(profile_json(8, carrier_hz=250, levels=256, waveform=specs)))
    out = tmp_path / "mix.wav"
    args = ["render", "--shape", "line:-1,0,9,0", "--method", "CT", "--duration", "0.5"]
    args += ["--rate", "100", "--profile", str(path), "--ramp-ms", "0", "--out", str(out)]
    assert main(args) == 0
    x, rate = read_wav(out)
    assert rate == RATE and x.shape[1] == 8
    lit = np.abs(x).max(axis=0) > 0.2
    assert lit.all(), lit  # every channel lit by the line at some point
    for c in range(8):
        on = np.flatnonzero(np.abs(x[:, c]) > 0)
        a, b = on[0], on[-1] + 1  # its span: one level, held (CT lights one at a time)
        seg = x[a:b, c]
        s = np.arange(a, b)
        peak = np.abs(seg).max()
        assert peak == pytest.approx(1.0, abs=1e-3) or c >= 6  # level 255 of 255
        if c == 0:  # the plain carrier at the profile's 250 Hz
            assert np.allclose(seg, peak * np.sin(2 * np.pi * 250 * s / RATE), atol=2e-4)
        elif c == 1:  # a square at the carrier, 250 Hz: -1 where frac(250 s / 48000) >= 1/2
            assert np.array_equal(seg, np.where(2 * ((250 * s) % RATE) < RATE, 1.0, -1.0))
        elif c == 2:  # noise of seed 5 on channel 2: the documented sequence, at full level
            assert np.allclose(seg, [noise_sample(5, 2, k) for k in s], atol=1e-4)
        elif c == 4:  # a triangle at 50 Hz: 0, +1, 0, -1 a quarter period (240 samples) apart
            q = s[(s % 960) == 240]
            assert np.allclose(x[q, c], peak, atol=1e-4)
    # the sweep (channel 3) from its onset at phase 0: 100 Hz rising 150 Hz a second, so its
    # first period ends where 100 t + 75 t^2 = 1
    on = np.flatnonzero(np.abs(x[:, 3]) > 0)[0]
    seg = x[on - 1 : on + 2400, 3]
    up = np.flatnonzero((seg[:-1] <= 0) & (seg[1:] > 0))
    t1 = (-100 + np.sqrt(100**2 + 4 * 75)) / (2 * 75)
    assert (up[1] - up[0]) / RATE == pytest.approx(t1, abs=2 / RATE)


# --- through ALSA's file plugin --------------------------------------------------------------

PROFILE = {
    "format": "tactile-device-profile",
    "version": 1,
    "name": "audio-2x4",
    "columns": 2,
    "rows": 4,
    "pitch_mm": 20.0,
    "levels": 23,
    "carrier_hz": [150.0, 200.0, 250.0, 300.0, 350.0, 400.0, 450.0, 500.0],
    "waveform": ["sine", "sine", "sine", "sine", "sine", "sine", "noise", "noise"],
}


def test_a_patterns_waveforms_stream_through_alsas_file_plugin(tmp_path):
    require_audio()
    profile = tmp_path / "audio-2x4.json"
    profile.write_text(json.dumps(PROFILE))
    pattern = tc.Pattern(
        [
            tc.Effect(tc.Dots([tc.Dot(a, 1.0, 0.0, 1.0) for a in (0, 1)]), waveform="square:200"),
            tc.Effect(tc.Dots([tc.Dot(a, 1.0, 0.0, 1.0) for a in (2, 3, 6, 7)])),
        ]
    )
    pattern.save(tmp_path / "p.json")
    sink = CaptureSink(tmp_path, channels=8, samplerate=RATE)
    args = ["stream", "--device", f"audio:tactcap?samplerate={RATE}", "--profile", str(profile)]
    args += ["--shape", f"pattern:{tmp_path / 'p.json'}", "--method", "AS", "--rate", "100"]
    proc = run_cli(sink, args)
    try:
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 0, out + err
    assert "needs an audio interface" not in out + err
    x = sink.samples().astype(np.float64)
    lit = np.flatnonzero(np.abs(x[:, 0]) > 0.999)  # the square at full level
    assert len(lit) > 0.8 * RATE, len(lit)
    a, b = lit[0] + 200, lit[-1] - 200
    # channels 0 and 1: the effect's square at 200 Hz, +-1, turning every 120 samples of the
    # stream's sample clock
    for c in (0, 1):
        seg = x[a:b, c]
        assert np.array_equal(np.abs(seg), np.ones(b - a))
        turns = np.flatnonzero(np.diff(np.sign(seg))) + 1 + a
        assert len(set((turns % 120).tolist())) == 1
    # where the stream's sample 0 is in the capture (PortAudio primes the device with silence
    # first): the shift that makes channel 6 the documented noise, a whole number of periods
    # from where the square says
    found = [
        d
        for d in range(int(turns[0] % 120), 24000, 120)
        if all(x[a + i, 6] == np.float32(noise_sample(0, 6, a + i - d)) for i in (0, 1))
    ]
    assert len(found) == 1, "the noise of channel 6 is not the documented sequence"
    shift = found[0]
    print(f"\nthe stream's first sample is the capture's {shift}")
    # channels 2 and 3: the profile's sine at their carriers; 6 and 7: its noise
    for c, hz in ((2, 250.0), (3, 300.0)):
        s = np.arange(a, b)
        fit = x[a:b, c] @ np.exp(-2j * np.pi * hz * s / RATE) * 2 / (b - a)
        assert abs(fit) == pytest.approx(1.0, abs=0.01)
    for c in (6, 7):
        seg = x[a:b, c]
        assert np.mean(seg**2) == pytest.approx(1 / 3, abs=0.01)
        want = np.array([noise_sample(0, c, k - shift) for k in range(a, a + 2000)])
        assert np.allclose(seg[:2000], want, atol=1e-6)
    assert not x[:, 4:6].any()  # not lit
    assert not x[-2 * BLOCK :].any()  # and it ends in silence
