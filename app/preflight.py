"""Before Qt starts: can it open a window here? (No Qt import in this module.)

The PySide6 wheels bring Qt but not the X11 libraries its window-system plugin (``xcb``) links
against. When one is missing, Qt aborts the process with a long message that names only the
first. :func:`missing_libraries` asks the dynamic linker (``ldd``) which of the plugin's
libraries cannot be found, and :func:`check` turns that into one line naming them and the
Debian/Ubuntu packages that provide them.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

PACKAGES = {
    "libxcb-cursor.so.0": "libxcb-cursor0",
    "libxcb-icccm.so.4": "libxcb-icccm4",
    "libxcb-keysyms.so.1": "libxcb-keysyms1",
    "libxcb-image.so.0": "libxcb-image0",
    "libxcb-render-util.so.0": "libxcb-render-util0",
    "libxcb-util.so.1": "libxcb-util1",
    "libxkbcommon-x11.so.0": "libxkbcommon-x11-0",
    "libxkbcommon.so.0": "libxkbcommon0",
    "libX11-xcb.so.1": "libx11-xcb1",
    "libX11.so.6": "libx11-6",
    "libGL.so.1": "libgl1",
    "libEGL.so.1": "libegl1",
    "libfontconfig.so.1": "libfontconfig1",
    "libfreetype.so.6": "libfreetype6",
    "libdbus-1.so.3": "libdbus-1-3",
    "libglib-2.0.so.0": "libglib2.0-0",
}
"""Debian/Ubuntu package of each library the xcb plugin needs that a minimal system may lack."""

APT_LINE = (
    "$(command -v sudo) apt-get install -y python3-venv libxcb-cursor0 libxcb-icccm4 "
    "libxcb-keysyms1 libxcb-image0 libxcb-render-util0 libxcb-shape0 libxcb-randr0 libxcb-xkb1 "
    "libxkbcommon-x11-0 libgl1 libegl1 libfontconfig1 libdbus-1-3 libportaudio2"
)
"""The README's line: everything the window needs on Debian 12 / Ubuntu 22.04 and later, and
PortAudio for ``audio:`` devices (the README's first command runs it after ``apt-get update``;
``$(command -v sudo)`` is empty as root without sudo, ``-y`` needs no terminal)."""


def package_of(soname: str) -> str:
    """The Debian package that provides ``soname`` (a best guess beyond :data:`PACKAGES`:
    ``libxcb-foo.so.1`` is in ``libxcb-foo1``)."""
    if soname in PACKAGES:
        return PACKAGES[soname]
    match = re.fullmatch(r"(lib[\w.+-]+?)\.so\.(\d+)", soname)
    if not match:
        return soname
    name, version = match.group(1).lower(), match.group(2)
    return f"{name}-{version}" if name[-1].isdigit() else f"{name}{version}"


def xcb_plugin() -> Path | None:
    """The path of PySide6's ``libqxcb.so``, found without importing PySide6."""
    spec = importlib.util.find_spec("PySide6")
    if spec is None or not spec.submodule_search_locations:
        return None
    path = Path(spec.submodule_search_locations[0]) / "Qt" / "plugins" / "platforms"
    path /= "libqxcb.so"
    return path if path.exists() else None


def parse_ldd(text: str) -> list[str]:
    """The sonames ``ldd`` reports as ``not found``, in order, each once."""
    out = []
    for line in text.splitlines():
        match = re.match(r"\s*(\S+)\s+=>\s+not found", line)
        if match and match.group(1) not in out:
            out.append(match.group(1))
    return out


def missing_libraries(plugin: Path | None = None) -> list[str] | None:
    """Libraries the xcb plugin links against that cannot be found; None if it cannot tell
    (not Linux, no ``ldd``, no plugin)."""
    plugin = plugin or xcb_plugin()
    ldd = shutil.which("ldd")
    if plugin is None or ldd is None or not sys.platform.startswith("linux"):
        return None
    try:
        result = subprocess.run([ldd, str(plugin)], capture_output=True, text=True, timeout=20)
    except (OSError, subprocess.SubprocessError):
        return None
    return parse_ldd(result.stdout)


def check(environ=None) -> str:
    """Empty if Qt can open its window here; else one line saying what is missing."""
    environ = os.environ if environ is None else environ
    if not sys.platform.startswith("linux"):
        return ""
    platform = environ.get("QT_QPA_PLATFORM", "")
    if platform and not platform.startswith("xcb"):
        return ""  # offscreen, wayland, vnc...: not the xcb plugin
    if not platform and environ.get("WAYLAND_DISPLAY") and not environ.get("DISPLAY"):
        return ""
    if not environ.get("DISPLAY"):
        return (
            "no display: DISPLAY is not set. Run it on a desktop, or with "
            "QT_QPA_PLATFORM=offscreen for --screenshot"
        )
    missing = missing_libraries()
    if not missing:
        return ""
    packages = sorted({package_of(name) for name in missing})
    return (
        f"Qt's window plugin (xcb) needs libraries that are missing: {', '.join(missing)}. "
        f"Install them with: sudo apt-get install {' '.join(packages)}"
    )
