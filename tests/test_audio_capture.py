"""The audio transport end to end: ``tactile stream --device audio:...`` plays into ALSA's file
plugin (tests/audio_support.py), and what it played is read back against the frames it recorded:
each channel's carrier, each frame's level and onset, and silence after Ctrl-C and SIGTERM.
"""

import json
import math
import signal

import numpy as np
import pytest

from .audio_support import CaptureSink, read_back, require_audio, run_cli
from .serve_support import wait_for

SAMPLERATE = 48000
CARRIERS = [150.0, 200.0, 250.0, 300.0, 350.0, 400.0, 450.0, 500.0]
RAMP_N = 72  # the default 1.5 ms at 48 kHz
BLOCK = 256
PROFILE = {
    "format": "tactile-device-profile",
    "version": 1,
    "name": "audio-2x4",
    "columns": 2,
    "rows": 4,
    "pitch_mm": 20.0,
    "levels": 23,
    "carrier_hz": CARRIERS,
}


def stream_and_capture(tmp_path, how: str, extra: list[str], seconds: float = 1.5):
    """Stream a line under AS into the sink for ``seconds``, stop the stream with signal
    ``how``; the capture, the recording and the command's output."""
    require_audio()
    profile = tmp_path / "audio-2x4.json"
    profile.write_text(json.dumps(PROFILE))
    record = tmp_path / "sent.npz"
    sink = CaptureSink(tmp_path, channels=8, samplerate=SAMPLERATE)
    args = ["stream", "--device", f"audio:tactcap?samplerate={SAMPLERATE}"]
    args += ["--profile", str(profile), "--record", str(record)]
    args += ["--shape", "line:0.5,0.5,1.5,3.5", "--method", "AS", "--mu", "0.2", "--gamma", "0.7"]
    args += ["--duration", "1", "--pause", "0.2", *extra]
    proc = run_cli(sink, args)
    try:
        seen = []
        for line in proc.stderr:  # wait until it streams (the hello and clock are done)
            seen.append(line)
            if line.startswith("[streaming]"):
                break
        assert seen and seen[-1].startswith("[streaming]"), "".join(seen)
        # a whole trace and its pause at least, in the audio the sink has read (its clock)
        wait_for(lambda: sink.played_frames >= seconds * SAMPLERATE, timeout_s=60 + 10 * seconds,
                 what=f"{seconds:g} s of audio at the sink")  # fmt: skip
        proc.send_signal(getattr(signal, how))
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    x = sink.samples()
    sent = np.load(record)
    levels = sent["levels"].reshape(len(sent["time"]), -1)  # 2 x 4 row-major: channel order
    return x, sent["time"], levels, proc.returncode, out, "".join(seen) + err


@pytest.mark.parametrize(
    "how, rate, lead_ms",
    [("SIGINT", 300, 20), ("SIGTERM", 50, 0)],
    ids=["ctrl-c-timed-300hz", "sigterm-for-now-50hz"],
)
def test_audio_stream_plays_the_frames_sent_and_ends_in_silence(tmp_path, how, rate, lead_ms):
    extra = ["--rate", str(rate), "--lead-ms", str(lead_ms)]
    # at 50 Hz, 3 s: enough frames that a few a loaded host puts off do not reach a tenth
    seconds = 1.5 if rate >= 100 else 3.0
    x, time_s, levels, code, out, err = stream_and_capture(tmp_path, how, extra, seconds)
    assert code == 0, out + err
    assert "stopped: all off" in out
    timed = lead_ms > 0
    assert ("timed frames 20 ms ahead" in out) == timed, out
    figures = read_back(
        x,
        time_s,
        levels,
        carriers=CARRIERS,
        samplerate=SAMPLERATE,
        ramp_n=RAMP_N,
        top=22,
        reach=40 if timed else BLOCK + RAMP_N,
        timed=timed,
    )
    onset = np.abs(figures["onset_error"])
    print(
        f"\n{how}: {figures['frames']} onsets ({figures['missed']} further), error |p50| "
        f"{np.median(onset):.0f} / p99 "
        f"{np.percentile(onset, 99):.1f} / max {onset.max():.0f} samples; level error max "
        f"{figures['level_error']:.4f} levels over {figures['levels_read']} plateaus; "
        f"{figures['silence_ms']:.1f} ms of silence at the end; carriers "
        f"{ {c: round(f, 2) for c, f in figures['carrier_hz'].items()} }"
    )
    # every channel on its own carrier
    assert sorted(figures["carrier_hz"]) == list(range(8))
    for c, hz in figures["carrier_hz"].items():
        assert hz == pytest.approx(CARRIERS[c], abs=0.05)
    # every level read back as sent (half a level either way would be another level)
    assert figures["levels_read"] > 8 * (100 if timed else 25)
    assert figures["level_error"] < 0.25
    # the onsets where the frames' times put them: timed ones within a ramp on the audio clock
    # (searched within 40 samples, and typically within 2), frames for now within a block and
    # a ramp, as they start with the next block. On a machine busy beyond its cores a stall of
    # the streaming process longer than the lead makes frames late, and the sink's reader (the
    # test's sound card) loses its pace: a few frames may be further off, and the rest wander
    # by a few samples (idle: within 2, none further; beside two CPU hogs and another suite,
    # load 6 on 2 cores: up to 28 samples, at most 1 of 144 further).
    fitted, missed = figures["frames"], figures["missed"]
    assert fitted > (100 if timed else 20)
    assert missed <= 0.1 * (fitted + missed), f"{missed} of {fitted + missed} onsets off"
    assert np.median(onset) <= (RAMP_N / 4 if timed else BLOCK / 2 + RAMP_N / 4)
    # no click: no step larger than the fastest carrier and the ramp make
    bound = 2 * math.pi * max(CARRIERS) / SAMPLERATE + math.pi / (2 * RAMP_N)
    assert figures["max_step"] <= bound
    # and the stream ends in silence: faded out, then whole blocks of zeros
    assert figures["silence_ms"] >= 2 * BLOCK / SAMPLERATE * 1e3


def test_without_portaudio_the_capture_tests_fail_in_ci_and_skip_elsewhere(monkeypatch):
    import ctypes.util

    monkeypatch.setattr(ctypes.util, "find_library", lambda name: None)
    monkeypatch.setenv("TACTILE_REQUIRE_AUDIO", "1")
    with pytest.raises(pytest.fail.Exception, match="apt-get install libportaudio2"):
        require_audio()
    monkeypatch.delenv("TACTILE_REQUIRE_AUDIO")
    with pytest.raises(pytest.skip.Exception, match="portaudio, asound"):
        require_audio()
