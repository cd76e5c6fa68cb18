"""Bundled files: device profiles (``assets/devices``), presets (``assets/presets``) and example
patterns (``assets/patterns``).

The files live in the repository's top-level ``assets/`` folder. A wheel installs them as
``tactile_core/_assets``; a source checkout or editable install reads them in place.
"""

from __future__ import annotations

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parents[1]  # tactile_core/
_ROOTS = (_PACKAGE / "_assets", _PACKAGE.parent / "assets")


def assets_dir() -> Path:
    """The folder holding ``devices/``, ``presets/`` and ``patterns/``."""
    for root in _ROOTS:
        if root.is_dir():
            return root
    raise FileNotFoundError(f"bundled assets not found (looked in {', '.join(map(str, _ROOTS))})")


def asset_path(*parts: str) -> Path:
    """Path of a bundled file, e.g. ``asset_path("devices", "palm-5x6.json")``."""
    path = assets_dir().joinpath(*parts)
    if not path.exists():
        raise FileNotFoundError(f"bundled asset {'/'.join(parts)} not found in {assets_dir()}")
    return path
