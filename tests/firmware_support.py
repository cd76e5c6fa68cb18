"""Building the reference firmware and its helpers for the tests (test_firmware*.py).

The tests need ``gcc`` (the host build of the parser), ``avr-gcc`` with avr-libc (the firmware)
and simavr with its parts and ``libelf`` (the harness): on Debian, ``apt-get install gcc-avr
avr-libc libsimavr-dev simavr libelf-dev``. ``.ci/run`` installs them and sets
``TACTILE_REQUIRE_FIRMWARE=1``, under which a missing tool fails the tests instead of skipping
them.
"""

import importlib.util
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

FIRMWARE = Path(__file__).resolve().parent.parent / "firmware"
TOOLS = {
    "host": ("gcc", "make"),
    "elf": ("avr-gcc", "avr-objcopy", "make"),
    "sim": ("gcc", "make"),
}


def require(kind: str) -> None:
    """Skip (or, in CI, fail) when the tools for ``kind`` are missing."""
    missing = [t for t in TOOLS[kind] if shutil.which(t) is None]
    if kind == "sim" and not Path("/usr/include/simavr/sim_avr.h").exists():
        missing.append("libsimavr-dev")
    if missing:
        message = f"firmware tests need {', '.join(missing)} (apt-get install gcc-avr avr-libc "
        message += "libsimavr-dev simavr libelf-dev)"
        if os.environ.get("TACTILE_REQUIRE_FIRMWARE"):
            pytest.fail(message)
        pytest.skip(message)


def build(target: str, build_dir: Path) -> Path:
    """``make -C firmware TARGET BUILD=build_dir``; the product's path."""
    products = {
        "host": "libtactile_host.so",
        "all": "tactile.elf",
        "sim": "harness",
    }
    result = subprocess.run(
        ["make", "-C", str(FIRMWARE), target, f"BUILD={build_dir}"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    return build_dir / products[target]


def _pinlog():
    spec = importlib.util.spec_from_file_location("pinlog", FIRMWARE / "sim" / "pinlog.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["pinlog"] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


pinlog = _pinlog()


def as_the_array(pid: int) -> bool:
    """Real-time priority for the harness where permitted (root, or an rtprio limit), as a
    stand-in for the array's own processor, which the host's load never slows; False if not."""
    try:
        os.sched_setscheduler(pid, os.SCHED_FIFO, os.sched_param(20))
    except (AttributeError, OSError):
        return False
    return True


class Simulation:
    """The harness running the firmware; ``finish()`` stops it and reads its log."""

    def __init__(self, firmware, tmp_path, seconds=60):
        elf, harness = firmware
        self.elf = elf
        self.log_path = tmp_path / "pins.log"
        self.proc = subprocess.Popen(
            [str(harness), str(elf), str(self.log_path), str(seconds)],
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )
        self.realtime = as_the_array(self.proc.pid)
        self.path = ""
        for line in self.proc.stdout:  # simavr's loader prints its own lines first
            if line.startswith("pty: "):
                self.path = line.split(None, 1)[1].strip()
                break
        assert self.path.startswith("/dev/"), "the harness did not open its pseudo-terminal"

    def finish(self):
        self.proc.send_signal(signal.SIGTERM)
        self.proc.wait(timeout=10)
        self.proc.stdout.close()
        return pinlog.PinLog.read(self.log_path)


def simulation(firmware, tmp_path):
    """A running simulation, killed afterwards if a test left it running (a generator for a
    fixture)."""
    running = Simulation(firmware, tmp_path)
    yield running
    if running.proc.poll() is None:
        running.proc.kill()
        running.proc.wait()
        running.proc.stdout.close()


def wait_logged(sim, pattern: str, timeout_s: float = 30.0) -> None:
    """Wait until a line of the harness's pin log matches ``pattern`` (a regular expression).
    The harness writes its log through stdio's buffer: a line shows once later lines fill it."""
    import re
    import time

    deadline = time.monotonic() + timeout_s
    line = re.compile(pattern, re.MULTILINE)
    while not (sim.log_path.exists() and line.search(sim.log_path.read_text())):
        assert sim.proc.poll() is None, "the simulation ended"
        assert time.monotonic() < deadline, f"no line {pattern!r} in the pin log"
        time.sleep(0.01)  # polling the log (a bound of timeout_s above)
