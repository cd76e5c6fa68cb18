"""What the audio link's callback costs per block: the carriers of 8 and 30 channels at 48 kHz,
256 samples a block, steady, with a new frame in every block, and silent; and the waveforms of
8 and 32 channels (square, noise, sweeps, envelopes, a mixture, frames that bring their own)."""

from __future__ import annotations

import time

import numpy as np

from ..device.audio import Player
from ..device.waveform import parse_waveform
from ._common import Table

SAMPLERATE = 48000
BLOCK = 256


def _cost(channels: int, case: str, blocks: int, waveforms=None, voices=None) -> np.ndarray:
    """Seconds of :meth:`Player.play` for each of ``blocks`` blocks (``voices``: what every
    other frame asks for, a waveform or None per channel)."""
    carriers = np.linspace(150.0, 500.0, channels)
    player = Player(carriers, SAMPLERATE, ramp_s=0.0015, outputs=channels, top=22,
                    waveforms=waveforms)  # fmt: skip
    own = player.synth.voices(voices)
    out = np.zeros((BLOCK, channels), dtype=np.float32)
    block_s = BLOCK / SAMPLERATE
    rng = np.random.default_rng(0)
    # Events as the writer makes them: (id, host time, amplitudes, timed); two frames a block
    # at 300 frames a second, each landing mid-block.
    frames = [
        (k + 1, (k // 2 + 0.3 + 0.5 * (k % 2)) * block_s, rng.integers(0, 23, channels) / 22, True,
         own if k % 2 else None)
        for k in range(2 * (blocks + 8))
    ]  # fmt: skip
    if case == "steady":
        player.events = (frames[0],)
    elif case == "silent":
        player.events = ()
    times = np.empty(blocks)
    for i in range(blocks + 8):  # the first 8: the clock map locks, numpy warms up
        if case == "a new frame every block":
            player.events = (frames[2 * i], frames[2 * i + 1])
        t0 = time.perf_counter()
        player.play(out, BLOCK, i * block_s)
        t1 = time.perf_counter()
        if i >= 8:
            times[i - 8] = t1 - t0
    return times


def audio_table(blocks: int = 4000) -> Table:
    """The callback's cost per block, p50 / p99 / max, and its share of the block's time."""
    rows = []
    budget_us = BLOCK / SAMPLERATE * 1e6
    for channels in (8, 30):
        for case in ("steady", "a new frame every block", "silent"):
            us = _cost(channels, case, blocks) * 1e6
            p50, p99 = np.percentile(us, [50, 99])
            rows.append(
                [
                    f"{channels}",
                    case,
                    f"{p50:.1f} / {p99:.1f} / {us.max():.0f}",
                    f"{100 * p50 / budget_us:.1f}",
                ]
            )
    return Table(
        "The audio callback per block",
        ["channels", "frames", "µs per block p50 / p99 / max", "% of the block (p50)"],
        rows,
        f"{blocks} blocks of {BLOCK} samples at {SAMPLERATE} Hz ({budget_us:.0f} µs each) "
        "rendered by `Player.play`, the body of the audio link's PortAudio callback (carriers "
        "of 150-500 Hz, 1.5 ms ramps, float32 out); `a new frame every block`: two frames "
        "landing mid-block, 300 frames a second. The callback itself adds two clock readings "
        "and a few attribute reads. Measured in this process with the interpreter's other "
        "threads idle; the max includes the operating system's interruptions.",
    )


MIXTURE = ("sine", "square", "saw", "triangle", "noise", "sweep:100-300:200ms",
           "sweep:300-100:200ms:log", "sine+adsr:5,20,0.7,50")  # fmt: skip
"""One of each, round the channels."""


def waveform_table(blocks: int = 4000) -> Table:
    """The callback's cost per block with waveforms, for 8 and 32 channels."""
    rows = []
    budget_us = BLOCK / SAMPLERATE * 1e6
    cases = [
        ("the plain carrier (sine)", "steady", None, None),
        ("square", "steady", ("square",), None),
        ("noise", "steady", ("noise",), None),
        ("linear sweep", "steady", ("sweep:100-300:200ms",), None),
        ("log sweep", "steady", ("sweep:100-300:200ms:log",), None),
        ("sine + ADSR", "a new frame every block", ("sine+adsr:5,20,0.7,50",), None),
        ("a mixture of all eight", "steady", MIXTURE, None),
        ("a mixture of all eight", "a new frame every block", MIXTURE, None),
        ("a mixture, every other frame its own", "a new frame every block", MIXTURE, "own"),
    ]
    for channels in (8, 32):
        for name, case, specs, own in cases:
            waveforms = None
            if specs is not None:
                waveforms = [parse_waveform(specs[c % len(specs)]) for c in range(channels)]
            voices = None
            if own:  # a square on the even channels, the channel's own on the odd ones
                voices = [parse_waveform("square:200") if c % 2 == 0 else None
                          for c in range(channels)]  # fmt: skip
            us = _cost(channels, case, blocks, waveforms, voices) * 1e6
            p50, p99 = np.percentile(us, [50, 99])
            rows.append([f"{channels}", name, case, f"{p50:.1f} / {p99:.1f} / {us.max():.0f}",
                         f"{100 * p50 / budget_us:.1f}"])  # fmt: skip
    return Table(
        "Waveforms in the audio callback",
        ["channels", "waveforms", "frames", "µs per block p50 / p99 / max", "% of the block (p50)"],
        rows,
        f"{blocks} blocks of {BLOCK} samples at {SAMPLERATE} Hz rendered by `Player.play` as in "
        "the table above (carriers of 150-500 Hz, 1.5 ms ramps, float32 out); each row's "
        "waveform on every channel, or the mixture round the channels (sine, square, saw, "
        "triangle, noise, linear and log sweeps of 200 ms, sine with an ADSR of 5, 20, 0.7, "
        "50); `a new frame every block`: two frames landing mid-block, 300 frames a second, "
        "with onsets and releases; `every other frame its own`: those frames ask for a square "
        "on every other channel. Measured in this process with the interpreter's other "
        "threads idle; the max includes the operating system's interruptions.",
    )
