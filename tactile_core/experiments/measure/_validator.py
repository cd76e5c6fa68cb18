"""The validator: a sensor's onset of each presentation logged beside its commanded time.

The tactile counterpart of PsychoPy's photodiode validator: the time a stimulus's first frame
left the host (what the stream's markers say) is not when the skin got it. With a sensor on a
tactor the stimuli light (or a contact microphone on the array's frame), every presentation's
first vibration is detected (:func:`~tactile_core.device.measure.detect_onset`) and written
beside the commanded time, with the delay, to a CSV (one row per presentation, flushed and
synced as it happens, :class:`~tactile_core.experiments.results.ResultsFile`), and, when LSL
is on, sent as a marker on ``tactile-validation`` stamped with the detected time.

The stream's output thread only queues each onset; a thread of the validator waits until the
sensor's samples reach past the presentation's window, reads them and writes the row.
"""

from __future__ import annotations

import datetime as dt
import math
import sys
import threading
import time
from collections import deque
from pathlib import Path

import numpy as np

from ...device.measure import EDGE_S, detect_onset, open_sensor
from ...rendering.points import FreePoints
from ..results import ResultsFile

FIELDS = ("presentation", "kind", "seq", "commanded_s", "detected_s", "delay_ms", "peak",
          "noise", "note")  # fmt: skip
"""The CSV's columns: times in ``time.perf_counter`` seconds, the delay in ms, amplitudes in
sensor units (full scale 1)."""
WINDOW_S = 0.5
"""How long after its command a presentation's vibration is looked for."""
WAIT_SLACK_S = 5.0
"""How much longer than that the sensor may take to deliver its samples."""
PRE_S = 0.25
"""Seconds a validator that opens its sensor records before it lets the first presentation
go (the noise before it)."""
MIN_BEFORE_S = 0.03
"""Samples needed before a command to measure the noise (less: not compared)."""


def default_log_path(folder=None) -> Path:
    """``validate-YYYYmmdd-HHMMSS.csv`` in ``folder`` (default: beside the running script, or
    the current folder)."""
    if folder is None:
        script = Path(sys.argv[0]) if sys.argv and sys.argv[0] else None
        folder = script.parent if script is not None and script.is_file() else Path.cwd()
    stamp = dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    return Path(folder) / f"validate-{stamp}.csv"


class Validator:
    """Logs the sensor's onset of every presentation of a stream.

    Parameters
    ----------
    sensor : str or sensor
        ``audio:NAME?channel=N`` (opened and started here, stopped by :meth:`close`), ``sim``
        (on the simulated array ``link``) or a sensor object (started by its owner).
    log : path, optional
        The CSV, or a folder to put ``validate-<date>.csv`` in (a results folder); by default
        beside the running script.
    link, profile : optional
        The array's link (for ``sim``) and profile (for LSL's stream description).
    lsl : bool
        Also send each detection on the LSL marker stream ``tactile-validation``.
    window_s : float
        How long after its command a presentation's vibration is looked for.
    """

    def __init__(self, sensor, *, log=None, link=None, profile=None, lsl: bool = False,
                 window_s: float = WINDOW_S):  # fmt: skip
        owned = isinstance(sensor, str)
        self.sensor = open_sensor(sensor, link=link, profile=profile)
        self.window_s = float(window_s)
        path = Path(log) if log is not None else None
        self.path = default_log_path(path) if path is None or path.is_dir() else path
        self.file = ResultsFile(self.path, FIELDS)
        self.file.load()  # creates it with its header (or resumes one)
        self.outlet = None
        if lsl:
            from ...serve import ValidationOutlet

            self.outlet = ValidationOutlet(profile)
        self.rows: list[dict] = []
        self._pending: deque = deque()
        self._wake = threading.Event()
        self._closing = threading.Event()
        self._count = 0
        self._floor: float | None = None
        self._owned = owned
        if owned:  # a little silence first: the noise before the first presentation
            self.sensor.start()
            self.sensor.wait_until(time.perf_counter() + PRE_S, PRE_S + WAIT_SLACK_S)
        self._thread = threading.Thread(target=self._run, name="tactile-validator", daemon=True)
        self._thread.start()

    # --- the stream's side ---------------------------------------------------------------------

    def attach(self, streamer) -> Validator:
        """Validate every presentation of ``streamer`` (its ``on_onset`` hook)."""
        streamer.on_onset.append(self.onset)
        return self

    def detach(self, streamer) -> None:
        """Stop validating ``streamer``'s presentations."""
        if self.onset in streamer.on_onset:
            streamer.on_onset.remove(self.onset)

    def onset(self, onset) -> None:
        """(The output thread.) Queue a presentation: an :class:`~tactile_core.stream.Onset`.
        Free points (``tactile serve``'s, a script's ``point``) are left out: they come and go
        within one scene, whose start is no stimulus."""
        if isinstance(getattr(onset.scene, "source", None), FreePoints):
            return
        self._count += 1
        kind = getattr(onset.scene, "marker", "") or "scene"
        self._pending.append((self._count, kind, onset.seq, onset.time_s))
        self._wake.set()

    # --- the validator's thread ----------------------------------------------------------------

    def _run(self) -> None:
        while True:
            if not self._pending:
                if self._closing.is_set():
                    return
                self._wake.wait(0.1)
                self._wake.clear()
                continue
            n, kind, seq, command = self._pending[0]
            until = command + self.window_s + EDGE_S
            if not self.sensor.wait_until(until, 0.2):
                if not self._closing.is_set():
                    continue  # not yet: wait on
                if not self.sensor.wait_until(until, WAIT_SLACK_S):
                    self._write(n, kind, seq, command, None, "no samples from the sensor")
                    self._pending.popleft()
                    continue
            self._pending.popleft()
            self._detect(n, kind, seq, command)

    def _detect(self, n: int, kind: str, seq: int, command: float) -> None:
        rec = self.sensor.recording(since_s=command - 1.0)
        at = float(rec.to_recording_s(command))
        if at < MIN_BEFORE_S:  # the samples start (almost) after the command: nothing to compare
            self._write(n, kind, seq, command, None, "the sensor was not recording yet")
            return
        found = detect_onset(rec.sensor, rec.samplerate, at, self.window_s,
                             noise_floor=self._floor)  # fmt: skip
        if math.isfinite(found.noise) and found.noise > 0:
            self._floor = found.noise if self._floor is None else min(self._floor, found.noise)
        detected = float(rec.host_s(found.onset_s)) if found.found else None
        note = "" if found.found else "no vibration detected (is the sensor on a lit tactor?)"
        self._write(n, kind, seq, command, detected, note, found.peak, found.noise)

    def _write(self, n, kind, seq, command, detected, note, peak=0.0, noise=float("nan")):
        delay_ms = (detected - command) * 1e3 if detected is not None else None
        row = {
            "presentation": n,
            "kind": kind,
            "seq": seq,
            "commanded_s": f"{command:.6f}",
            "detected_s": "" if detected is None else f"{detected:.6f}",
            "delay_ms": "" if delay_ms is None else f"{delay_ms:.3f}",
            "peak": f"{peak:.6f}",
            "noise": "" if not math.isfinite(noise) else f"{noise:.6f}",
            "note": note,
        }
        self.file.append(row)
        self.rows.append(row)
        if self.outlet is not None:
            data = {"presentation": n, "kind": kind, "seq": seq, "delay_ms": delay_ms,
                    "detected": detected is not None}  # fmt: skip
            self.outlet.push(data, detected if detected is not None else command)

    # --- results ---------------------------------------------------------------------------------

    def delays_ms(self) -> np.ndarray:
        """The delays of the presentations detected so far, ms."""
        return np.array([float(r["delay_ms"]) for r in self.rows if r["delay_ms"]])

    def summary(self) -> dict:
        """Presentations, how many were detected, and the delay's mean, SD, median, min and
        max (ms; None without detections)."""
        d = self.delays_ms()

        def stat(f):
            return round(float(f(d)), 3) if d.size else None

        return {
            "presentations": len(self.rows),
            "detected": int(d.size),
            "delay_mean_ms": stat(np.mean),
            "delay_sd_ms": round(float(np.std(d, ddof=1)), 3) if d.size > 1 else None,
            "delay_median_ms": stat(np.median),
            "delay_min_ms": stat(np.min),
            "delay_max_ms": stat(np.max),
            "log": str(self.path),
        }

    def summary_line(self) -> str:
        """The summary in a line."""
        s = self.summary()
        if not s["detected"]:
            return f"validator: {s['presentations']} presentations, none detected ({s['log']})"
        sd = "" if s["delay_sd_ms"] is None else f" +- {s['delay_sd_ms']:.1f}"
        return (f"validator: {s['detected']} of {s['presentations']} presentations detected, "
                f"delay {s['delay_mean_ms']:.1f}{sd} ms (median {s['delay_median_ms']:.1f}, "
                f"{s['delay_min_ms']:.1f}-{s['delay_max_ms']:.1f}); log {s['log']}")  # fmt: skip

    def close(self, timeout_s: float = WINDOW_S + WAIT_SLACK_S + 2.0) -> dict:
        """Finish the presentations queued (waiting up to ``timeout_s``), close the log's
        stream and the outlet, stop a sensor opened here; the summary."""
        self._closing.set()
        self._wake.set()
        self._thread.join(timeout_s)
        if self.outlet is not None:
            self.outlet.close()
            self.outlet = None
        self.file.close()
        if self._owned:
            self.sensor.stop()
        return self.summary()

    def __enter__(self) -> Validator:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
