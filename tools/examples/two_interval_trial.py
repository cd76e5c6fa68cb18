"""A two-interval trial with the scripting API: the same stroke rendered by two methods, in a
random order; the participant says at the keyboard which interval felt smoother.

    python tools/examples/two_interval_trial.py                  # the simulated array
    python tools/examples/two_interval_trial.py --device /dev/ttyUSB0 --lsl

Each interval prints the time its first frame was written to the array (``time.perf_counter``
seconds; with ``--lsl`` the same moment goes out as a marker on Lab Streaming Layer). Ctrl-C at
any point leaves the array off. The script imports no Qt (``tactile_core`` never does), so it
runs beside PsychoPy.
"""

from __future__ import annotations

import argparse
import json
import random
import sys
import time

import tactile_core as tc


def ask(prompt: str) -> str:
    """A line from the keyboard: '1' or '2' (asked again otherwise)."""
    while True:
        answer = input(prompt).strip()
        if answer in ("1", "2"):
            return answer
        print("please type 1 or 2", file=sys.stderr)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--device", default="sim", help="device URL (default: the simulated array)")
    p.add_argument("--profile", default=None, help="device profile (default: the palm array)")
    p.add_argument("--methods", default="AS,IM", help="the two methods (default AS,IM)")
    p.add_argument("--duration", type=float, default=1.0, help="seconds per interval")
    p.add_argument("--gap", type=float, default=0.5, help="seconds of silence between them")
    p.add_argument("--seed", type=int, default=None, help="seed of the order")
    p.add_argument("--lsl", action="store_true", help="a marker per interval on LSL")
    args = p.parse_args(argv)

    methods = args.methods.split(",")
    random.Random(args.seed).shuffle(methods)
    stroke = tc.Line((0.5, 1.84), (4.5, 4.16))  # the paper's Experiment 1 line
    with tc.open_array(args.device, args.profile, lsl=args.lsl) as array:
        times = []
        for i, method in enumerate(methods, 1):
            shown = array.play(stroke, method=method, mu=0.33, gamma=0.7,
                               duration_s=args.duration, marker=f"interval-{i}")  # fmt: skip
            times.append(shown.first_frame_s)
            print(f"interval {i}: first frame at {shown.first_frame_s:.6f} s", flush=True)
            if i < len(methods):
                time.sleep(args.gap)
        answer = ask("Which interval felt smoother, 1 or 2? ")
    chosen = methods[int(answer) - 1]
    result = {"order": methods, "answer": int(answer), "chosen": chosen, "first_frames_s": times}
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
