"""Building the reference firmware and its helpers for the tests (test_firmware*.py).

The tests need ``gcc`` (the host build of the parser), ``avr-gcc`` with avr-libc (the firmware)
and simavr with its parts and ``libelf`` (the harness): on Debian, ``apt-get install gcc-avr
avr-libc libsimavr-dev simavr libelf-dev``. ``.ci/run`` installs them and sets
``TACTILE_REQUIRE_FIRMWARE=1``, under which a missing tool fails the tests instead of skipping
them.
"""

import os
import shutil
import subprocess
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
