"""Import paths of release 0.1, kept for one release: each still works and warns.

In 0.1 ``tactile_core`` was one flat folder; 0.2 groups it by layer (``rendering``, ``device``,
``files``, ``experiments``, and ``_shared`` beneath them all). A script that imports an old deep
path, ``from tactile_core.scene import Scene``, gets the same object and a
``DeprecationWarning`` naming the new path. The public face, ``import tactile_core as tc;
tc.render, tc.Line, ...``, never moved and does not warn. The old paths go in 0.3.

The old paths are module objects placed in ``sys.modules`` when ``tactile_core`` is imported
(no files: a file ``tactile_core/render.py`` would replace the function ``tc.render`` with a
module the moment it was imported). Each forwards attribute access to its new home, importing it
on first use, so nothing is loaded before a script asks for it.
"""

from __future__ import annotations

import importlib
import sys
import types
import warnings

REMOVED_IN = "0.3"

#: old module path -> new module path
MOVED = {
    "tactile_core._validate": "tactile_core._shared.validate",
    "tactile_core.outfile": "tactile_core._shared.outfile",
    "tactile_core.jsonfile": "tactile_core._shared.jsonfile",
    "tactile_core.assets": "tactile_core._shared.assets",
    "tactile_core.geometry": "tactile_core.rendering.geometry",
    "tactile_core.shapes": "tactile_core.rendering.shapes",
    "tactile_core.methods": "tactile_core.rendering.methods",
    "tactile_core.correction": "tactile_core.rendering.correction",
    "tactile_core.render": "tactile_core.rendering.rasterize",
    "tactile_core.trace": "tactile_core.rendering.trace",
    "tactile_core.curves": "tactile_core.rendering.curves",
    "tactile_core.percept": "tactile_core.rendering.percept",
    "tactile_core.scene": "tactile_core.rendering.scene",
    "tactile_core.wire": "tactile_core.device.wire",
    "tactile_core.array": "tactile_core.device.array",
    "tactile_core.link": "tactile_core.device.link",
    "tactile_core.emulator": "tactile_core.device.emulator",
    "tactile_core.streamer": "tactile_core.device.streamer",
    "tactile_core.process": "tactile_core.device.process",
    "tactile_core.recorder": "tactile_core.device.recorder",
    "tactile_core.presets": "tactile_core.files.presets",
    "tactile_core.export": "tactile_core.files.export",
}
MOVED.update(
    {
        f"tactile_core.methods.{name}": f"tactile_core.rendering.methods.{name}"
        for name in (
            "_radial",
            "area",
            "closest",
            "energy",
            "gaussian",
            "interpolated",
            "midpoint",
            "park",
            "rolloff",
        )
    }
)


def warn_moved(old: str, new: str, name: str, stacklevel: int = 3) -> None:
    """Warn that ``old.name`` is now ``new.name``."""
    warnings.warn(
        f"{old} moved to {new} in tactile_core 0.2; import {name} from {new} "
        f"(the old path goes away in {REMOVED_IN})",
        DeprecationWarning,
        stacklevel=stacklevel,
    )


class MovedModule(types.ModuleType):
    """Stands in for a module that moved: every attribute comes from its new home, with a
    ``DeprecationWarning``."""

    def __init__(self, old: str, new: str):
        super().__init__(old, f"Moved to {new} in tactile_core 0.2 (goes away in {REMOVED_IN}).")
        self._new = new

    def __getattr__(self, name: str):
        if name.startswith("__") and name.endswith("__"):
            raise AttributeError(name)
        target = importlib.import_module(self._new)
        try:
            value = getattr(target, name)
        except AttributeError:
            raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}") from None
        warn_moved(self.__name__, self._new, name)
        return value

    def __dir__(self):
        return dir(importlib.import_module(self._new))


def install() -> None:
    """Place a :class:`MovedModule` in ``sys.modules`` for every old path not yet imported."""
    for old, new in MOVED.items():
        sys.modules.setdefault(old, MovedModule(old, new))


def moved_attribute(name: str):
    """The package attribute ``tactile_core.<name>`` of an old top-level module, or None."""
    return sys.modules.get(f"tactile_core.{name}") if f"tactile_core.{name}" in MOVED else None
