"""Stop an audio stream many times and measure the silence it ends in (issue 31).

    python tools/audio_fades.py [--runs 30] [--signal SIGINT|SIGTERM]

Each run streams a 1 s line with a 0.2 s pause (AS, 8 channels at 48 kHz, timed frames at
300 Hz) through ALSA's ``file`` plugin into the test suite's capture sink
(``tests/audio_support.py``: a named pipe read at the samplerate), stops it with the signal at a
random moment, and prints the exact zeros at the end of the capture beside where in the trace
the stop came (``trace_s``: past 1.0 s, in the trace's own pause) and, from inside the stream,
when the link's close began and ended after the final all-off frame.
"""

from __future__ import annotations

import argparse
import json
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.audio_support import CaptureSink, require_audio  # noqa: E402

PROFILE = {
    "format": "tactile-device-profile", "version": 1, "name": "audio-2x4", "columns": 2,
    "rows": 4, "pitch_mm": 20.0, "levels": 23,
    "carrier_hz": [150.0, 200.0, 250.0, 300.0, 350.0, 400.0, 450.0, 500.0],
}  # fmt: skip
CYCLE_S = 1.2  # --duration 1 --pause 0.2

# tactile stream, with the times of the final all-off and of the link's close on stderr
CHILD = """
import sys, time
from tactile_core.device import audio
from tactile_core.stream import streamer
times = {}
final, close = streamer.Streamer._all_off_final, audio.AudioLink.close
def all_off(self):
    times["off"] = time.perf_counter()
    t = self.last_frame[1]
    times["trace_s"] = -1.0 if t is None else t % CYCLE_S
    final(self)
def closing(self):
    if self._stream is not None and "off" in times:
        times["close_ms"] = (time.perf_counter() - times["off"]) * 1e3
        close(self)
        times["closed_ms"] = (time.perf_counter() - times["off"]) * 1e3
    else:
        close(self)
streamer.Streamer._all_off_final, audio.AudioLink.close = all_off, closing
from tactile_core.cli import main
try:
    main(sys.argv[1:])
finally:
    times.pop("off", None)
    print("FADE " + " ".join(f"{k}={v:.2f}" for k, v in times.items()), file=sys.stderr)
""".replace("CYCLE_S", repr(CYCLE_S))


def one_run(seed: int, how: str) -> tuple[float, dict]:
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        (folder / "p.json").write_text(json.dumps(PROFILE))
        sink = CaptureSink(folder, channels=8, samplerate=48000)
        args = ["stream", "--device", "audio:tactcap?samplerate=48000", "--profile",
                str(folder / "p.json"), "--shape", "line:0.5,0.5,1.5,3.5", "--method", "AS",
                "--mu", "0.2", "--gamma", "0.7", "--duration", "1", "--pause", "0.2",
                "--rate", "300", "--lead-ms", "20"]  # fmt: skip
        proc = subprocess.Popen([sys.executable, "-c", CHILD, *args], env=sink.env(),
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                cwd=ROOT)  # fmt: skip
        for line in proc.stderr:
            if line.startswith("[streaming]"):
                break
        time.sleep(0.5 + np.random.default_rng(seed).uniform(0, CYCLE_S))
        proc.send_signal(getattr(signal, how))
        _, err = proc.communicate(timeout=60)
        x = sink.samples()
    sounding = np.flatnonzero(np.abs(x).max(axis=1) > 0)
    silence_ms = (len(x) - 1 - sounding[-1]) / 48000 * 1e3
    fade = next((line for line in err.splitlines() if line.startswith("FADE")), "FADE")
    return silence_ms, dict(item.split("=") for item in fade.split()[1:])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=30)
    parser.add_argument("--signal", default="SIGINT", choices=["SIGINT", "SIGTERM"])
    args = parser.parse_args()
    require_audio()
    playing, paused = [], []
    for seed in range(args.runs):
        silence_ms, times = one_run(seed, args.signal)
        in_pause = float(times.get("trace_s", 0)) > 1.0
        (paused if in_pause else playing).append(silence_ms)
        print(f"{seed:3d} silence {silence_ms:6.1f} ms  "
              + "  ".join(f"{k} {v}" for k, v in times.items())
              + ("  (stopped in the trace's pause)" if in_pause else ""), flush=True)  # fmt: skip
    if playing:
        print(f"stopped while a frame played: {len(playing)}, silence {min(playing):.1f}-"
              f"{max(playing):.1f} ms, median {np.median(playing):.1f}")  # fmt: skip
    if paused:
        print(f"stopped in the pause: {len(paused)}, silence {min(paused):.1f}-"
              f"{max(paused):.1f} ms")  # fmt: skip


if __name__ == "__main__":
    main()
