"""The four rendering methods of the paper, one module each, behind one registry.

========  ==========================  ===========  =======================================
name      method                      paper        tactors lit at one instant
========  ==========================  ===========  =======================================
``CT``    closest tactor              2.2          exactly 1 (bi-level)
``MM``    midpoint                    2.3          exactly 1 (bi-level)
``AS``    area sampling               2.4          up to 4 (anti-aliased)
``IM``    interpolated midpoint       2.5          up to 2 (anti-aliased)
========  ==========================  ===========  =======================================

Each module provides ``sample(shape, x, y, t, tol) -> [(cols, rows, values), ...]`` on arrays,
one entry per tactor it may light (cells may fall outside the grid; the caller drops them), and
``sample1`` with plain floats for the live path. ``tol`` is the snap tolerance of the cell
lookup (:data:`tactile_core.geometry.SNAP_ULPS`). CT and AS depend on the point only, so they
also render free coordinates (``shape`` may be None); MM and IM need the shape's strokes.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import ModuleType

from .. import _validate
from . import area, closest, interpolated, midpoint


@dataclass(frozen=True)
class Method:
    """A rendering method as registered: its name, description and sampling functions."""

    name: str
    title: str
    bilevel: bool
    needs_shape: bool
    max_tactors: int
    module: ModuleType

    @property
    def sample(self):
        """Vectorised sampler, see :func:`tactile_core.methods.area.sample`."""
        return self.module.sample

    @property
    def sample1(self):
        """Scalar sampler for the live path."""
        return self.module.sample1


def _register(module) -> Method:
    return Method(
        name=module.NAME,
        title=module.TITLE,
        bilevel=module.BILEVEL,
        needs_shape=module.NEEDS_SHAPE,
        max_tactors=module.MAX_TACTORS,
        module=module,
    )


METHODS: dict[str, Method] = {
    m.name: m for m in map(_register, (closest, midpoint, area, interpolated))
}
"""Registry of the methods by name, in the paper's order: CT, MM, AS, IM."""

METHOD_NAMES = tuple(METHODS)


def get_method(name) -> Method:
    """Look up a method by name (``"CT"``, ``"MM"``, ``"AS"``, ``"IM"``; case-insensitive).

    Raises
    ------
    ValueError
        Naming ``method`` when the name is unknown.
    """
    if isinstance(name, Method):
        return name
    key = name.upper() if isinstance(name, str) else name
    if key not in METHODS:
        raise ValueError(
            f"method must be one of {', '.join(METHOD_NAMES)}, got {_validate.shown(name)}"
        )
    return METHODS[key]
