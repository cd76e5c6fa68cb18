"""The lead against latency: when frames reach the pins of the reference firmware in simavr.

For each lead ``L`` (0: frames for now) and each host condition (idle, or both cores busy with
spinning processes), the streamer sends Experiment 3's kind of stimulus with CT at full drive on
a fast circle (so that a change of tactor shows on the pins whatever the PWM slot) to the
firmware running in simavr, and the pin log says when each frame's onset happened:

- timed frames (``L`` > 0): the onset against the frame's time on the array's clock;
- frames for now (``L`` = 0): the onset against the frame's deadline on the host plus the
  median latency, i.e. the jitter the host's scheduler and the PWM period add.

The host's clock is tied to the simulated cycles by the earliest arrival of a written message's
first byte (a one-way bound, good to the pseudo-terminal's least latency). The latency a
parameter change costs is the time from the change to the next frame's deadline (half a frame
on average) plus the median time from a deadline to the onset.

It needs a source checkout (``firmware/``), ``avr-gcc`` with avr-libc and simavr; without them
the table says what is missing.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ._common import Table

FIRMWARE = Path(__file__).resolve().parents[2] / "firmware"
CPU_HZ = 16_000_000


def _pinlog():
    spec = importlib.util.spec_from_file_location("pinlog", FIRMWARE / "sim" / "pinlog.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["pinlog"] = module
    spec.loader.exec_module(module)
    return module


class _Spy:
    """A link that remembers when each message was written (host time, bytes)."""

    def __init__(self, link):
        self.link = link
        self.writes: list[tuple[float, bytes]] = []
        self.description = link.description

    def write(self, data: bytes) -> None:
        self.writes.append((time.perf_counter(), bytes(data)))
        self.link.write(data)

    def read(self) -> bytes:
        return self.link.read()

    def reopen(self) -> None:
        self.link.reopen()

    def close(self) -> None:
        self.link.close()


def _missing() -> str:
    if not (FIRMWARE / "src" / "main.c").exists():
        return "needs a source checkout (firmware/)"
    tools = [t for t in ("make", "gcc", "avr-gcc") if shutil.which(t) is None]
    if not Path("/usr/include/simavr/sim_avr.h").exists():
        tools.append("libsimavr-dev")
    return f"needs {', '.join(tools)}" if tools else ""


def _run_one(build: Path, lead_ms: float, busy: bool, seconds: float, rate_hz: float, pinlog):
    from ..device.link import SerialLink
    from ..rendering.scene import Scene
    from ..rendering.shapes import Circle
    from ..stream import Streamer, StreamOptions

    log_path = build / f"pins-{lead_ms:g}-{int(busy)}.log"
    harness = subprocess.Popen(
        [str(build / "harness"), str(build / "tactile.elf"), str(log_path), str(seconds + 30)],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
    )  # fmt: skip
    try:
        os.sched_setscheduler(harness.pid, os.SCHED_FIFO, os.sched_param(20))
    except (AttributeError, OSError):
        pass  # the simulation then shares the host's load too
    path = next(line.split()[1] for line in harness.stdout if line.startswith("pty: "))
    hogs = []
    if busy:
        hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    link = _Spy(SerialLink(path))
    scene = Scene(Circle((2.5, 3.0), 2.0), "CT", duration_s=0.2, pause_s=0.0, rate_hz=rate_hz)
    try:
        streamer = Streamer(link, scene=scene, options=StreamOptions(lead_ms=lead_ms)).start()
        streamer.identified.wait(10.0)
        time.sleep(seconds)
        stats = streamer.stop()
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
        link.close()
        harness.send_signal(signal.SIGTERM)
        harness.wait(10)
        harness.stdout.close()
    log = pinlog.PinLog.read(log_path)
    return _measure(log, link.writes, lead_ms, rate_hz, build, pinlog), stats


def _measure(log, writes, lead_ms, rate_hz, build, pinlog) -> dict:
    # Tie the host's clock to the cycles: message k written at host time t_k began to arrive at
    # cycle c_k; the least c_k / f - t_k is the offset plus the least latency.
    starts, buf_start = [], None
    for cycle, byte in log.received:
        if buf_start is None:
            buf_start = cycle
        if byte == 0:
            starts.append(buf_start)
            buf_start = None
    n = min(len(starts), len(writes))
    offset = min(starts[k] / CPU_HZ - writes[k][0] for k in range(n))

    def host(cycle):
        return cycle / CPU_HZ - offset

    rx_entry = pinlog.handler_cycles(build / "tactile.elf", 25, "0x0084")
    onset_err, latency, late = [], [], 0
    period = 1.0 / rate_hz
    if lead_ms > 0:
        origin, _ = pinlog.clock_origin(log, rx_entry)
        stopped = pinlog.received_frames(log)[-1][0]
        frames = [f for f in pinlog.timed_frames(log) if origin + f.at_us * 16 < stopped]
        for frame, err in zip(frames, pinlog.onset_errors(log, frames, origin)):
            margin_ms = (origin + frame.at_us * 16 - frame.arrived) / 16_000
            latency.append(lead_ms * 1e-3 + max(-margin_ms, 0.0) * 1e-3)  # deadline -> onset
            # a frame in less than ~2 ms before its time may be played late (parsing and
            # building its table take ~1.2 ms): those count under "late", not here
            if err is not None and not np.isnan(err) and margin_ms > 2.0:
                onset_err.append(err)
        counters = pinlog.last_clock_reply(log)
        late = counters["late"] if counters else late
    else:
        # Frames for now show from the first PWM period after they are in; their deadlines are
        # periodic, and the earliest-written frame is the one closest to its deadline.
        sent = [t for t, data in writes if data[1] == 0x46][:-1]  # the last is the all-off
        ks = np.arange(len(sent))
        first = float(np.min(np.array(sent) - ks * period))
        starts_p, measured, _ = pinlog.levels_per_period(log)
        previous = None
        for k, (end, levels) in enumerate(pinlog.received_frames(log)[: len(sent)]):
            if previous is not None and not np.array_equal(levels, previous):
                i = int(np.searchsorted(starts_p, end))
                shown = [j for j in range(i, min(i + 3, len(starts_p)))
                         if np.array_equal(measured[j], levels)]  # fmt: skip
                if shown:
                    latency.append(host(starts_p[shown[0]]) - (first + k * period))
            previous = levels
        if latency:
            median = float(np.median(latency))
            onset_err = [(x - median) * 1e6 for x in latency]
    err = np.abs(np.array(onset_err)) if onset_err else np.array([np.nan])
    lat = np.array(latency) if latency else np.array([np.nan])
    return {
        "frames": len(latency),
        "onsets": len(onset_err),
        "late": late,
        "p50": float(np.median(err)),
        "p99": float(np.percentile(err, 99)),
        "max": float(err.max()),
        "latency_mean_ms": float((np.median(lat) + period / 2) * 1e3),
        "latency_max_ms": float((np.percentile(lat, 99) + period) * 1e3),
    }


def link_table(leads_ms=(0, 5, 10, 20, 50), seconds: float = 5.0, rate_hz: float = 200.0) -> Table:
    """Onset error, late frames and the latency each lead costs, idle and with both cores busy
    (reference firmware in simavr)."""
    headers = ["lead", "host", "frames", "late", "onsets measured", "onset error p50 / p99 / max",
               "change → felt, mean / p99"]  # fmt: skip
    title = f"The lead against latency: the reference firmware in simavr, CT at {rate_hz:g} Hz"
    missing = _missing()
    if missing:
        return Table(title, headers, [], notes=f"(skipped: {missing})")
    pinlog = _pinlog()
    rows = []
    with tempfile.TemporaryDirectory(prefix="tactile-link-") as tmp:
        build = Path(tmp)
        for target in ("all", "sim"):
            result = subprocess.run(["make", "-C", str(FIRMWARE), target, f"BUILD={build}"],
                                    capture_output=True, text=True)  # fmt: skip
            if result.returncode != 0:
                return Table(title, headers, [], notes=f"(build failed: {result.stderr[-300:]})")
        for lead_ms in leads_ms:
            for busy in (False, True):
                m, _ = _run_one(build, lead_ms, busy, seconds, rate_hz, pinlog)
                what = "timed" if lead_ms else "for now"
                rows.append([
                    f"{lead_ms:g} ms ({what})", "2 cores busy" if busy else "idle", m["frames"],
                    m["late"], m["onsets"], f"{m['p50']:.1f} / {m['p99']:.1f} / {m['max']:.1f} µs",
                    f"{m['latency_mean_ms']:.1f} / {m['latency_max_ms']:.1f} ms",
                ])  # fmt: skip
    notes = (
        "Onset error: for timed frames in on time, the pins' change against the frame's time on "
        "the array's clock; for frames for now, against the deadline plus the median latency "
        "(the jitter). Onsets measured: frames whose onset changes a pin (a change of tactor "
        "away from a slot boundary). Late: timed frames the array played after their time (the "
        "firmware's count; they came less than ~1.2 ms ahead). Change → "
        "felt: from a parameter change to the first onset showing it (the wait for the next "
        "deadline, half a frame on average, plus deadline → onset). The simulator runs with "
        "real-time priority where permitted, as the array's own processor would."
    )
    return Table(title, headers, rows, notes=notes)
