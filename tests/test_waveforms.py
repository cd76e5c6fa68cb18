"""Waveforms per channel (tactile_core.device.waveform): their specs, and the samples the audio
synthesiser makes of each, against values worked from the definitions in docs/device.md
("Waveforms") by hand or by an independent computation (exact fractions, a scalar SplitMix64,
the sweeps' phase integrals)."""

import math
from fractions import Fraction

import numpy as np
import pytest

from tactile_core.device._audio_synth import CarrierSynth, synthesize
from tactile_core.device.waveform import Adsr, Waveform, WaveformError, parse_waveform

SR = 48000


def play(
    spec,
    length,
    frames=((0, 1.0),),
    *,
    channels=1,
    carrier_hz=250.0,
    ramp_s=0.0,
    voices=None,
    block=4096,
):
    """What the synthesiser plays: ``frames`` = [(onset sample, amplitude of every channel)]
    (levels 0..1000 of ``top`` 1000), each channel on waveform ``spec`` (one for all, or a
    list)."""
    specs = [spec] if isinstance(spec, str) else list(spec)
    levels = np.array([[round(a * 1000)] * channels for _, a in frames])
    onsets = [s for s, _ in frames]
    blocks = synthesize(
        levels,
        onsets,
        top=1000,
        carrier_hz=[carrier_hz] * channels,
        samplerate=SR,
        ramp_s=ramp_s,
        length=length,
        waveforms=[parse_waveform(s) for s in specs],
        voices=voices,
        block=block,
    )
    return np.concatenate([b.astype(np.float64) for b in blocks])


# --- the specs ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "spec, fields",
    [
        ("sine", dict(shape="sine", carrier_hz=None)),
        ("sine:250", dict(shape="sine", carrier_hz=250.0)),
        ("square:200", dict(shape="square", carrier_hz=200.0)),
        ("saw:172.5", dict(shape="saw", carrier_hz=172.5)),
        ("triangle", dict(shape="triangle", carrier_hz=None)),
        ("noise", dict(shape="noise", seed=0)),
        ("noise:seed=7", dict(shape="noise", seed=7)),
        (
            "sweep:100-300:500ms",
            dict(shape="sweep", carrier_hz=100.0, end_hz=300.0, sweep_ms=500.0, scale="lin"),
        ),
        (
            "sweep:300-100:1.5ms:log",
            dict(shape="sweep", carrier_hz=300.0, end_hz=100.0, sweep_ms=1.5, scale="log"),
        ),
        ("sine:250+adsr:5,20,0.7,50", dict(shape="sine", adsr=Adsr(5.0, 20.0, 0.7, 50.0))),
        ("square+adsr:0,0,1,0", dict(shape="square", adsr=Adsr(0.0, 0.0, 1.0, 0.0))),
    ],
)
def test_specs_read_as_documented_and_write_back_the_same(spec, fields):
    w = parse_waveform(spec)
    for name, value in fields.items():
        assert getattr(w, name) == value, name
    assert w.spec == spec and str(w) == spec
    assert parse_waveform(w.spec) == w


def test_only_the_plain_sine_is_the_plain_carrier_and_a_bare_shape_takes_the_channels_one():
    assert parse_waveform("sine").plain
    assert not any(parse_waveform(s).plain for s in ("sine:250", "square", "sine+adsr:1,1,1,1"))
    assert parse_waveform("square").at_carrier(170.0) == Waveform("square", carrier_hz=170.0)
    assert parse_waveform("square:200").at_carrier(170.0).carrier_hz == 200.0
    assert parse_waveform("noise").at_carrier(170.0) == parse_waveform("noise")


@pytest.mark.parametrize(
    "spec, words",
    [
        ("squar:200", "shape must be one of sine, square, saw, triangle, noise, sweep, got 'sq"),
        ("square:2000", "frequency must be within 1-1000 Hz, got 2000"),
        ("square:0.5", "frequency must be within 1-1000 Hz"),
        ("square:abc", "frequency must be a number, got 'abc'"),
        ("square:nan", "frequency must be within 1-1000 Hz, got nan"),
        ("square:200:3", "square takes one field, its frequency"),
        ("sweep:100:500ms", "frequencies must be F0-F1"),
        ("sweep:100-x:500ms", "end frequency must be a number, got 'x'"),
        ("sweep:0-300:500ms", "start frequency must be within 1-1000 Hz"),
        ("sweep:100-100:500ms", "end frequency must differ from the start frequency"),
        ("sweep:100-300:500", "duration must be milliseconds with 'ms'"),
        ("sweep:100-300:0ms", "duration must be within 1-60000 ms, got 0"),
        ("sweep:100-300", "a sweep is sweep:F0-F1:DURATIONms[:log]"),
        ("sweep:100-300:500ms:cubic", "scale must be lin or log, got 'cubic'"),
        ("noise:3", "noise takes one field, seed=N"),
        ("noise:seed=1000", "seed must be a whole number within 0-999, got '1000'"),
        ("noise:seed=-1", "seed must be a whole number within 0-999"),
        ("sine+adsr:1,2,3", "adsr takes four values"),
        ("sine+env:1,2,0.5,3", "adsr must follow '+' as adsr:A,D,S,R"),
        ("sine+adsr:x,2,0.5,3", "adsr attack must be a number, got 'x'"),
        ("sine+adsr:1,20001,0.5,3", "adsr decay must be within 0-10000 ms"),
        ("sine+adsr:1,2,1.5,3", "adsr sustain must be within 0-1, got 1.5"),
        ("sine+adsr:1,2,0.5,-3", "adsr release must be within 0-10000 ms"),
        ("", "shape must be one of"),
        ("x" * 201, "waveform must be at most 200 characters"),
    ],
)
def test_bad_specs_are_refused_naming_the_field(spec, words):
    with pytest.raises(WaveformError) as caught:
        parse_waveform(spec)
    message = str(caught.value)
    assert words in message
    if len(spec) <= 200:
        assert message.startswith(f"waveform {spec!r}: ")


def test_waveform_values_are_checked_by_their_names_too():
    with pytest.raises(ValueError, match="end_hz is needed by a sweep"):
        Waveform("sweep", carrier_hz=100.0)
    with pytest.raises(ValueError, match="carrier_hz does not apply to noise"):
        Waveform("noise", carrier_hz=100.0)
    with pytest.raises(ValueError, match="sustain must be within 0-1, got 2"):
        Adsr(1.0, 1.0, 2.0, 1.0)
    with pytest.raises(ValueError, match="waveform must be a spec such as 'square:200', got 5"):
        parse_waveform(5)


# --- the samples of each shape --------------------------------------------------------------


def test_a_square_carrier_changes_sign_where_its_half_periods_end():
    # 200 Hz at 48 kHz: a period of 240 samples, +1 on samples 0-119, -1 on 120-239, ...
    x = play("square:200", 1200)[:, 0]
    assert np.array_equal(x, np.where(np.arange(1200) % 240 < 120, 1.0, -1.0))
    # 170 Hz: -1 where frac(170 s / 48000) >= 1/2, in exact integers: 2 (170 s mod 48000) >= 48000
    x = play("square:170", 4800)[:, 0]
    s = np.arange(4800)
    minus = 2 * ((170 * s) % 48000) >= 48000
    assert np.array_equal(x, np.where(minus, -1.0, 1.0))
    changes = np.flatnonzero(np.diff(np.sign(x))) + 1
    half = Fraction(48000, 2 * 170)  # 141 3/17 samples
    assert changes.tolist() == [math.ceil(m * half) for m in range(1, len(changes) + 1)]


def test_saw_and_triangle_start_at_zero_rising_like_the_sine():
    s = np.arange(480)
    p = s % 240 / 240  # 200 Hz: the phase of each sample, exact
    saw = play("saw:200", 480)[:, 0]
    assert np.allclose(saw, np.where(p < 0.5, 2 * p, 2 * p - 2), atol=1e-7)
    tri = play("triangle:200", 480)[:, 0]
    assert np.allclose(tri[[0, 60, 120, 180, 240]], [0, 1, 0, -1, 0], atol=1e-7)
    assert np.allclose(tri, np.interp(p, [0, 0.25, 0.75, 1], [0, 1, -1, 0]), atol=1e-7)
    sine = play("sine:200", 480)[:, 0]
    assert np.allclose(sine, np.sin(2 * np.pi * p), atol=1e-6)


def crossings(x):
    """Zero crossings (both ways), interpolated, in samples (a sample that is exactly 0 between
    two of opposite signs is one)."""
    nz = np.flatnonzero(x != 0)
    m = np.flatnonzero(np.sign(x[nz[:-1]]) != np.sign(x[nz[1:]]))
    i, j = nz[m], nz[m + 1]
    return i + x[i] / (x[i] - x[j]) * (j - i)


def local_hz(x, at_s):
    """The frequency around ``at_s`` from the two zero crossings about it: half a cycle
    between them (exact for a linear sweep at their middle)."""
    c = crossings(x)
    k = int(np.searchsorted(c, at_s * SR))
    return SR / (2 * (c[k] - c[k - 1])), (c[k] + c[k - 1]) / 2 / SR


@pytest.mark.parametrize(
    "spec",
    [
        "sweep:100-300:500ms",
        "sweep:300-100:500ms",
        "sweep:100-300:500ms:log",
        "sweep:400-50:500ms:log",
    ],
)
def test_a_sweeps_frequency_at_its_start_middle_and_end(spec):
    w = parse_waveform(spec)
    f0, f1, t_s = w.carrier_hz, w.end_hz, w.sweep_ms / 1e3

    def f(t):  # the documented instantaneous frequency
        u = min(t / t_s, 1.0)
        return f0 * (f1 / f0) ** u if w.scale == "log" else f0 + (f1 - f0) * u

    x = play(spec, SR)[:, 0]  # lit from sample 0: the sweep starts there, at phase 0
    assert x[0] == 0.0
    for at in (0.05 * t_s, 0.5 * t_s, 0.95 * t_s, 1.5 * t_s):
        hz, mid = local_hz(x, at)
        assert hz == pytest.approx(f(mid), rel=2e-3), (at, hz, f(mid))
    if w.scale == "log":  # the middle of an exponential sweep is the geometric mean
        assert local_hz(x, 0.5 * t_s)[0] == pytest.approx(math.sqrt(f0 * f1), rel=5e-3)
    # its first half cycle ends where its phase integral reaches 1/2
    k = (f1 - f0) / t_s
    first = crossings(x)[0] / SR
    if w.scale == "lin":  # f0 t + k t^2 / 2 = 1/2
        want = (-f0 + math.sqrt(f0 * f0 + k)) / k
    else:  # f0 T (r^(t/T) - 1) / ln r = 1/2
        r = f1 / f0
        want = t_s * math.log(1 + math.log(r) / (2 * f0 * t_s)) / math.log(r)
    assert first == pytest.approx(want, abs=0.01 / SR)


def test_a_sweep_starts_again_at_each_onset():
    frames = [(0, 1.0), (12000, 0.0), (24000, 1.0)]
    x = play("sweep:100-300:100ms", SR, frames)[:, 0]
    again = x[24000:]
    assert np.allclose(again[:4800], x[:4800], atol=1e-6)


def splitmix64(z: int) -> int:
    """SplitMix64's output for the counter ``z`` (Python integers)."""
    m = 2**64 - 1
    z = (z + 0x9E3779B97F4A7C15) & m
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & m
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & m
    return z ^ (z >> 31)


def noise_sample(seed: int, channel: int, s: int) -> float:
    """The documented noise: the top 53 bits of SplitMix64 of ``(seed * 1024 + c) * 2**32 + s
    mod 2**32``, as a number in [-1, 1)."""
    bits = splitmix64((seed * 1024 + channel) * 2**32 + int(s) % 2**32) >> 11
    return bits * 2.0**-52 - 1.0


def test_noise_is_white_with_an_rms_of_one_over_root_three_and_repeats_by_its_seed():
    n = 10 * SR
    x = play(["noise", "noise", "noise:seed=7"], n, channels=3)
    # uniform in [-1, 1): mean square 1/3 (its standard error here: sqrt(4/45/n) = 1.4e-4)
    assert np.mean(x**2, axis=0) == pytest.approx([1 / 3] * 3, abs=1e-3)
    assert x.min() >= -1.0 and x.max() < 1.0
    assert abs(np.mean(x[:, 0])) < 3e-3
    # white: no correlation from one sample to the next, nor between channels or seeds
    assert abs(np.corrcoef(x[:-1, 0], x[1:, 0])[0, 1]) < 5e-3
    assert abs(np.corrcoef(x[:, 0], x[:, 1])[0, 1]) < 5e-3
    assert abs(np.corrcoef(x[:, 0], x[:, 2])[0, 1]) < 5e-3
    # the same seed, the same samples, run after run and whatever the blocks
    again = play(["noise", "noise", "noise:seed=7"], SR, channels=3, block=331)
    assert np.array_equal(again, x[:SR])
    # the documented sequence, computed here one sample at a time (float32 out)
    for c, seed in ((0, 0), (1, 0), (2, 7)):
        for s in (0, 1, 47, 12345, SR - 1):
            assert x[s, c] == pytest.approx(noise_sample(seed, c, s), abs=1e-7)


def adsr_expected(n, on, off, a_n, d_n, sustain, r_n):
    """|E| from the documented envelope: lit from ``on`` (from silence), off at ``off``."""
    e = np.zeros(n)
    j = np.arange(off - on)
    u = j + 1.0
    lit = np.minimum(u / a_n, 1.0) - (1 - sustain) * np.clip((u - a_n) / d_n, 0.0, 1.0)
    e[on:off] = lit
    r0 = lit[-1]
    k = np.arange(n - off)
    e[off:] = r0 * (1.0 - np.minimum((k + 1.0) / r_n, 1.0))
    return e


def test_an_envelope_reaches_its_values_at_the_ends_of_attack_decay_and_release():
    # a square's magnitude is 1 on every sample: |x| is the envelope (a step of level: no ramp)
    x = play("square:170+adsr:5,20,0.7,50", SR, [(0, 1.0), (24000, 0.0)])[:, 0]
    a = np.abs(x)
    # 5 ms = 240 samples, 20 ms = 960, 50 ms = 2400 at 48 kHz
    assert a[119] == pytest.approx(0.5, abs=1e-7)  # half way up: 120 of 240
    assert a[239] == pytest.approx(1.0, abs=1e-7)  # the attack's end
    assert a[719] == pytest.approx(0.85, abs=1e-7)  # half way down: 1 - 0.3 x 480 / 960
    assert a[1199] == pytest.approx(0.7, abs=1e-7)  # the decay's end: the sustain
    assert a[23999] == pytest.approx(0.7, abs=1e-7)  # held while lit
    assert a[24000 + 1199] == pytest.approx(0.35, abs=1e-7)  # half the release: level held
    assert a[24000 + 2399] == pytest.approx(0.0, abs=1e-7)  # the release's end
    assert not a[24000 + 2400 :].any()
    assert np.allclose(a, adsr_expected(SR, 0, 24000, 240, 960, 0.7, 2400), atol=1e-7)


def test_the_envelope_multiplies_the_level_and_its_ramp():
    ramp_n = 72  # 1.5 ms
    x = play(
        "square:200+adsr:10,10,0.5,20", 12000, [(0, 0.6), (4800, 0.3), (9600, 0.0)], ramp_s=0.0015
    )[:, 0]
    j = np.arange(ramp_n)
    w = 0.5 - 0.5 * np.cos(np.pi * (j + 0.5) / ramp_n)
    level = np.zeros(12000)
    level[:4800] = 0.6
    level[:ramp_n] = 0.6 * w
    level[4800:] = 0.3  # the release holds the last level: no ramp down at 9600
    level[4800 : 4800 + ramp_n] = 0.6 + (0.3 - 0.6) * w
    e = adsr_expected(12000, 0, 9600, 480, 480, 0.5, 960)
    assert np.allclose(np.abs(x), level * e, atol=2e-7)


def test_an_onset_during_a_release_attacks_from_where_the_release_had_got():
    x = play("square:200+adsr:10,0,1,40", 9600, [(0, 1.0), (4800, 0.0), (4800 + 960, 1.0)])
    a = np.abs(x[:, 0])
    e0 = 1.0 * (1 - 960 / 1920)  # half of the 40 ms release: 0.5
    assert a[4800 + 959] == pytest.approx(e0, abs=1e-7)
    j = np.arange(480)
    assert np.allclose(a[5760 : 5760 + 480], e0 + (1 - e0) * (j + 1) / 480, atol=1e-7)


def test_blocks_of_any_size_give_the_same_samples():
    specs = [
        "sine",
        "square:200",
        "noise",
        "sweep:100-300:100ms",
        "sweep:300-100:100ms:log",
        "saw",
        "triangle+adsr:5,20,0.7,50",
        "sine:170+adsr:0,0,1,30",
    ]
    rng = np.random.default_rng(1)
    levels = rng.integers(0, 23, (200, 8))
    levels[levels < 8] = 0
    waveforms = [parse_waveform(s) for s in specs]

    def render(block):
        carriers = np.linspace(150, 500, 8)
        blocks = synthesize(
            levels,
            np.arange(200) * 160,
            top=22,
            carrier_hz=carriers,
            samplerate=SR,
            ramp_s=0.0015,
            length=32500,
            waveforms=waveforms,
            block=block,
        )
        return np.concatenate([b.copy() for b in blocks])

    whole, pieces = render(4096), render(257)
    assert np.isfinite(whole).all() and np.abs(whole).max() <= 1.0
    np.testing.assert_allclose(pieces, whole, rtol=0, atol=1e-7)


def test_a_frames_waveforms_play_on_the_channels_it_lights_and_the_others_keep_theirs():
    square = parse_waveform("square:200")
    frames = [(0, 1.0), (2400, 1.0), (4800, 0.0)]
    levels = np.array([[1000, 1000], [1000, 0], [0, 0]])
    voices = [None, (square, square), (square, square)]
    blocks = synthesize(
        levels,
        [s for s, _ in frames],
        top=1000,
        carrier_hz=[200.0, 200.0],
        samplerate=SR,
        ramp_s=0.0,
        length=7200,
        voices=voices,
    )
    x = np.concatenate([b.astype(np.float64) for b in blocks])
    s = np.arange(7200)
    sine, sq = np.sin(2 * np.pi * s / 240), np.where(s % 240 < 120, 1.0, -1.0)
    assert np.allclose(x[:2400, 0], sine[:2400], atol=1e-6)  # its own waveform
    assert np.allclose(x[2400:4800, 0], sq[2400:4800], atol=1e-7)  # lit: the frame's
    assert not x[2400:, 1].any()  # off: the frame's waveform is not played


def test_voices_must_be_one_waveform_or_none_per_channel():
    synth = CarrierSynth([250.0, 250.0], SR, ramp_s=0.0)
    assert synth.voices(None) is None
    with pytest.raises(ValueError, match="voices must be one per channel \\(2\\), got 1"):
        synth.voices([None])
    with pytest.raises(ValueError, match="voices\\[1\\] must be a Waveform or None, got str"):
        synth.voices([None, "square"])
