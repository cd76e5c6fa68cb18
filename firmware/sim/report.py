"""Measure the reference firmware in simavr and print the README's table.

    python firmware/sim/report.py [--seconds 5] [--rate 250]

Builds the firmware and the harness (make), runs ``tactile stream`` into the simulated array
for each shape and method, then reads the pins: PWM frequency, each channel's duty against the
level sent, the time from a frame's last byte to the pins, and whether any period showed
levels that were never sent. Then a stream killed with SIGKILL: the time to all-off.
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import pinlog  # noqa: E402

CLI = [sys.executable, "-m", "tactile_core.cli"]
MS = pinlog.CPU_HZ / 1000


def run(build: Path, args, seconds: float, kill_after: float | None = None):
    log_path = build / "pins.log"
    harness = subprocess.Popen(
        [str(build / "harness"), str(build / "tactile.elf"), str(log_path), "120"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
    )  # fmt: skip
    path = next(line.split()[1] for line in harness.stdout if line.startswith("pty: "))
    stream = subprocess.Popen(
        [*CLI, "stream", "--device", path, *args, "--seconds", str(seconds), "--lead-ms", "0"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
    )  # fmt: skip
    if kill_after is not None:
        time.sleep(kill_after)
        os.kill(stream.pid, signal.SIGKILL)
        time.sleep(0.6)
    out, _ = stream.communicate(timeout=seconds + 30)
    harness.send_signal(signal.SIGTERM)
    harness.wait(10)
    harness.stdout.close()
    return pinlog.PinLog.read(log_path), out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--rate", type=float, default=250.0)
    args = parser.parse_args()
    build = Path(tempfile.mkdtemp(prefix="firmware-"))
    for target in ("all", "sim"):
        subprocess.run(["make", "-C", str(HERE.parent), target, f"BUILD={build}"],
                       check=True, capture_output=True)  # fmt: skip
    rows = []
    for shape in ("circle:2.5,3,2", "line:0.5,1.84,4.5,4.16"):
        for method in ("CT", "MM", "AS", "IM"):
            log, _ = run(
                build,
                ["--shape", shape, "--method", method, "--mu", "0.33", "--gamma", "0.7",
                 "--rate", f"{args.rate:g}"],
                args.seconds,
            )  # fmt: skip
            c = pinlog.check(log)
            lat = c.latency_cycles / MS
            rows.append(
                f"| {shape.split(':')[0]} | {method} | {c.periods} | {c.mismatched} | "
                f"{c.shown} / {c.frames} ({c.superseded} superseded) | "
                f"{c.duty_error_cycles / 16:.2f} | {c.pwm_hz:.2f} | "
                f"{lat.min():.2f} / {np.median(lat):.2f} / {lat.max():.2f} |"
            )
    print(
        "| shape | method | PWM periods | periods not showing a sent frame | distinct frames "
        "shown | worst duty error us | PWM Hz | last byte to pins ms min / median / max |"
    )
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    offs = []
    for _ in range(5):
        log, _ = run(build, ["--shape", "line:2.5,3.5,2.5,3.5", "--method", "CT",
                             "--rate", "100"], 30, kill_after=1.5)  # fmt: skip
        frames = pinlog.received_frames(log)
        offs.append((log.all_off_since() - frames[-1][0]) / MS)
    print(f"\nSIGKILL mid-stream, 5 runs: all pins off {min(offs):.2f} - {max(offs):.2f} ms "
          "after the last frame's last byte")  # fmt: skip


if __name__ == "__main__":
    main()
