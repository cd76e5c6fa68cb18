"""Reading and writing the project's JSON files (device profiles, presets, sessions)."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path


def read_json(path, error=ValueError):
    """Parse a JSON file; any problem raises ``error`` with the path and what is wrong.

    Parameters
    ----------
    path : path
    error : type of Exception
        Raised for a missing or unreadable file, or text that is not JSON.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(f"{path}: cannot read: {exc}") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise error(f"{path}: not valid JSON: {exc.msg} at line {exc.lineno}") from None
    except RecursionError:
        raise error(f"{path}: not valid JSON: nested too deeply") from None


def write_json_atomic(path, data) -> Path:
    """Write ``data`` as indented JSON to ``path`` through a temporary file and a rename, so a
    crash leaves either the old file or the new one, never half of it."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            json.dump(data, f, indent=2)
            f.write("\n")
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
