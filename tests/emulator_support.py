"""``tactile emulate`` as a test fixture, and ``tactile stream`` into it (real processes, a
real pseudo-terminal)."""

import json
import signal
import subprocess
import sys
import time

import numpy as np

CLI = [sys.executable, "-m", "tactile_core.cli"]


class Emulator:
    def __init__(self, tmp_path, *args):
        self.report_path = tmp_path / "report.json"
        self.log_path = tmp_path / "log.csv"
        self.proc = subprocess.Popen(
            [*CLI, "emulate", "--json", str(self.report_path), "--log", str(self.log_path), *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        self.path = self.proc.stdout.readline().strip()
        assert self.path.startswith(("/dev/", "socket://")), self.proc.stderr.read()
        self.output = ""
        self.errors = ""

    def finish(self, *, ends_itself=False):
        """Stop the emulator (Ctrl-C) and read its report and log. ``ends_itself``: it stops on
        its own (``--close-after``, ``--seconds``); wait for it rather than race its exit with a
        signal that could land after its handlers are gone."""
        if not ends_itself and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        out, err = self.proc.communicate(timeout=30)
        self.output, self.errors = out, err
        assert self.proc.returncode == 0
        report = json.loads(self.report_path.read_text())
        rows = self.log_path.read_text().splitlines()[1:]
        log = [[float(x) for x in row.split(",")] for row in rows]
        return report, np.array(log).reshape(-1, 32)

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.communicate(timeout=10)


def stream(path, *args, timeout=30):
    return subprocess.run(
        [*CLI, "stream", "--device", path, *args], capture_output=True, text=True, timeout=timeout
    )


def wait_streaming(proc, timeout_s=30.0):
    """Read the stream's standard error until it says it streams: the frames flow and its stop
    handlers are in place (a fixed sleep assumed a start-up a loaded machine may not make)."""
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        line = proc.stderr.readline()
        assert line, f"the stream ended before streaming (exit {proc.poll()})"
        if line.startswith("[streaming]"):
            return
    raise AssertionError("the stream did not start streaming")
