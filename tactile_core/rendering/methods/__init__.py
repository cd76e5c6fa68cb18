"""Rendering methods, one module each, behind one registry: the paper's four, the peer methods
other haptic systems use, and plug-ins.

========  ==========================  ===================  ================================
name      method                      from                 tactors lit at one instant
========  ==========================  ===================  ================================
``CT``    closest tactor              paper 2.2            exactly 1 (bi-level)
``MM``    midpoint                    paper 2.3            exactly 1 (bi-level)
``AS``    area sampling               paper 2.4            up to 4 (anti-aliased)
``IM``    interpolated midpoint       paper 2.5            up to 2 (anti-aliased)
``EN``    energy model on AS's cells  Tactile Brush 2011   up to 4, ``sum I^2 = 1``
``PK``    inverse distance, 3 nearest Park et al. 2016     up to 3, ``sum I^2 = 1``
``RO``    roll-off, ``r``, ``curve``  Syntacts 2021        up to 4 at ``r = 1``
``GS``    Gaussian, ``sigma``         this project         up to 6 at ``sigma = 0.5``
``VRCH``  every tactor within ``r``   VRCH-Server          up to 4 at ``r = 1`` (bi-level)
``TB``    timed onsets along a stroke Tactile Brush 2011   up to 4 virtual points on at once
========  ==========================  ===================  ================================

**The method protocol.** A method is a module (or any object) with these attributes:

- ``NAME``: 1-16 capital letters, digits or ``_``, starting with a letter;
- ``TITLE``: a short description; ``BILEVEL`` (bool); ``NEEDS_SHAPE`` (bool: it picks tactors
  from the shape's strokes and cannot render free points);
- ``MAX_TACTORS``: the most tactors one frame lights (an int, or a function of the parameters);
- ``sample(shape, x, y, t, tol, **params) -> [(cols, rows, values), ...]`` on arrays of shape
  ``(n,)``, one entry per tactor it may light (cells as float arrays, may fall outside the grid;
  the caller drops them), values in [0, 1];
- ``sample1(shape, x, y, t, tol, **params) -> ((col, row, value), ...)`` with plain floats: the
  live path, equal to ``sample`` at one point;
- ``PARAMS`` (optional): ``{name: (default, low, high, description)}`` of float parameters;
- ``CHOICES`` (optional): ``{name: (options, description)}`` of word parameters, the first
  option the default (``RO:curve=linear``);
- ``CORRECTION`` (optional): the correction the method is designed to be driven with, by
  default: ``"set"`` (the threshold/gamma correction set by the user, the paper's for AS and
  IM; the default when absent), ``"threshold"`` (the set threshold, gamma 1) or ``"none"``
  (driven as computed: EN and PK, whose energy normalisation is their own correction);
- ``DURATION_S`` (optional): for a method whose intensities depend on the *time* along the
  trace, not only on the point (TB), how many seconds ``t`` from 0 to 1 lasts when nothing
  says otherwise; its samplers then take a keyword ``duration_s``. The trace clock binds its
  own duration (:meth:`Method.on_clock`: :func:`~..trace.render_frames`,
  :class:`~..trace.LiveFrames`, so scenes and streams, and the activation curves); a bare
  ``render`` or ``render_point`` uses ``DURATION_S``. The duration is not part of the spec:
  it belongs to the trace, not to the method.

``tol`` is the snap tolerance of the cell lookup (:data:`~..geometry.SNAP_ULPS`).

**Parameters** travel with the method's name as a *spec*, ``"RO:r=1.5"``, ``"RO:curve=linear"``
or ``"GS:sigma=0.7"`` (defaults left out, so ``"RO"`` is ``"RO:r=1"``): the same string works in
:func:`tactile_core.render`, :class:`tactile_core.Scene`, ``--method`` on the command line,
presets and session records. :func:`get_method` parses and validates it.

**Plug-ins** register under the entry-point group ``tactile_tuner.methods``; the entry point
names a module or object that follows the protocol. They load on the first lookup of a name that
is not built in, or on :func:`load_plugins`. A plug-in that fails to load, breaks the protocol or
takes a built-in's name is listed in :data:`UNAVAILABLE` with its error and never takes the
program down (``sys.exit()`` and ``KeyboardInterrupt`` in its import included). Its output is
checked like any method's (``_plugin``): cells whole numbers, no cell twice at one point, values
finite within [0, 1]; one that breaks that, or raises anything while rendering or computing
``MAX_TACTORS``, is refused with a ``ValueError`` naming it.
"""

from __future__ import annotations

import math
import re
import threading

from ..._shared import validate as _validate
from . import (
    area,
    barycentric,
    brush,
    closest,
    energy,
    gaussian,
    interpolated,
    midpoint,
    park,
    rolloff,
    vrch,
)
from ._cells import ZIP as ZIP
from ._cells import Block as Block
from ._cells import Indexed as Indexed
from ._cells import outer as outer
from ._layout import LAYOUT_METHODS as LAYOUT_METHODS
from ._layout import TRACED_LAYOUT_METHODS as TRACED_LAYOUT_METHODS
from ._layout import layout_sampler as layout_sampler
from ._method import CORRECTIONS as CORRECTIONS
from ._method import Method as Method
from ._method import _make
from ._plugin import CONTAINED as _CONTAINED
from ._plugin import checked as _checked  # noqa: F401  (how the registry wraps a plug-in)

ENTRY_POINT_GROUP = "tactile_tuner.methods"
"""Entry-point group under which third-party methods register."""

_NAME = re.compile(r"[A-Z][A-Z0-9_]{0,15}\Z")
_WORD = re.compile(r"[a-z][a-z0-9_]{0,31}\Z")
_NOT_WORDS = ("inf", "infinity", "nan")  # float() reads them: refused as not finite
_ATTRS = ("NAME", "TITLE", "BILEVEL", "NEEDS_SHAPE", "MAX_TACTORS", "sample", "sample1")


PAPER_METHODS = ("CT", "MM", "AS", "IM")
"""The paper's four methods, in the paper's order."""

PEER_METHODS = ("EN", "PK", "RO", "GS", "VRCH")
"""The methods of other haptic systems and this project's Gaussian spread (Tactile Brush, Park
et al., Syntacts, GS, VRCH-Server)."""

LAYOUT_ONLY = ("BA",)
"""This project's method for actuators anywhere (AS's weights on a grid)."""

METHODS: dict[str, Method] = {
    **{m.NAME: _make(m, "paper") for m in (closest, midpoint, area, interpolated)},
    **{m.NAME: _make(m, "peer") for m in (energy, park, rolloff, gaussian, vrch)},
    barycentric.NAME: _make(barycentric, "layout"),
    brush.NAME: _make(brush, "peer"),
}
"""Registry of the methods by name: the paper's four, the peers, BA, TB, then loaded
plug-ins."""

METHOD_NAMES = PAPER_METHODS
"""The paper's four method names (what the experiments and the paper's tables use)."""

UNAVAILABLE: dict[str, str] = {}
"""Plug-ins that could not be used: entry-point name -> the error."""

_BOUND: dict[tuple, Method] = {}
"""Methods with parameters, by ``(name, params)``: one instance per spec, so its bound
samplers are built once (scenes and the display look specs up all the time)."""

_plugins_loaded = False
_plugins_lock = threading.Lock()


def load_plugins(entry_points=None) -> dict[str, str]:
    """Register the methods of the ``tactile_tuner.methods`` entry points (once).

    Parameters
    ----------
    entry_points : iterable of importlib.metadata.EntryPoint, optional
        Load these instead of the installed ones (and again, even if loaded before).

    Returns
    -------
    dict
        :data:`UNAVAILABLE`: plug-ins that failed, with their errors.
    """
    global _plugins_loaded
    with _plugins_lock:
        if entry_points is None:
            if _plugins_loaded:
                return UNAVAILABLE
            from importlib.metadata import entry_points as installed

            try:
                entry_points = list(installed(group=ENTRY_POINT_GROUP))
            except Exception as exc:  # a broken distribution's metadata
                UNAVAILABLE["(entry points)"] = f"could not be listed: {exc}"
                entry_points = []
        _plugins_loaded = True
        _BOUND.clear()
        for ep in entry_points:
            label = ep.name
            try:
                module = ep.load()
                _check_protocol(module)
                if module.NAME in METHODS and not METHODS[module.NAME].plugin:
                    raise ValueError(f"takes the name {module.NAME} of a built-in method")
                dist = getattr(getattr(ep, "dist", None), "name", None) or ep.value
                method = _make(module, f"plugin {dist}")
            except _CONTAINED as exc:  # anything a broken plug-in does (even sys.exit() or
                # KeyboardInterrupt in its import) is reported, not raised
                UNAVAILABLE[label] = f"{type(exc).__name__}: {exc}"
                continue
            METHODS[method.name] = method
            UNAVAILABLE.pop(label, None)
        return UNAVAILABLE


def mark_unavailable(name: str, error: str) -> None:
    """Take a plug-in method that failed while rendering out of :data:`METHODS` and list it in
    :data:`UNAVAILABLE` with ``error`` (built-in methods are never taken out)."""
    key = name.partition(":")[0].upper()
    method = METHODS.get(key)
    if method is not None and method.plugin:
        del METHODS[key]
        UNAVAILABLE[key.lower()] = error
        _BOUND.clear()


def _check_protocol(module) -> None:
    missing = [a for a in _ATTRS if not hasattr(module, a)]
    if missing:
        raise ValueError(f"does not follow the method protocol: no {', '.join(missing)}")
    if not isinstance(module.NAME, str) or not _NAME.match(module.NAME):
        raise ValueError(
            f"NAME must be 1-16 capital letters, digits or _, starting with a letter, got "
            f"{_validate.shown(module.NAME)}"
        )
    if not isinstance(module.TITLE, str) or not module.TITLE.strip():
        raise ValueError("TITLE must be a non-empty string")
    for flag in ("BILEVEL", "NEEDS_SHAPE"):
        if not isinstance(getattr(module, flag), bool):
            raise ValueError(f"{flag} must be True or False")
    if not (callable(module.sample) and callable(module.sample1)):
        raise ValueError("sample and sample1 must be functions")
    params = getattr(module, "PARAMS", None) or {}
    if not isinstance(params, dict):
        raise ValueError("PARAMS must be a dict of name: (default, low, high, description)")
    for key, spec in params.items():
        ok = isinstance(key, str) and key.isidentifier() and isinstance(spec, tuple)
        ok = ok and len(spec) == 4 and all(_validate.is_number(v) for v in spec[:3])
        if not ok or not spec[1] <= spec[0] <= spec[2]:
            raise ValueError(f"PARAMS[{key!r}] must be (default, low, high, description)")
    clock = getattr(module, "DURATION_S", None)
    if clock is not None:
        _validate.duration("DURATION_S", clock)
        if "duration_s" in params:
            raise ValueError("PARAMS must not name duration_s: the trace clock binds it")
    _make(module, "plugin")  # MAX_TACTORS at the defaults: a whole number from 1 to 1024


def method_names(include_plugins: bool = True) -> tuple[str, ...]:
    """Names of every registered method: the paper's four, the peers, then plug-ins."""
    if include_plugins:
        load_plugins()
    return tuple(METHODS)


def parse_spec(text: str) -> tuple[str, dict]:
    """Split a method spec ``"RO:r=1.5,..."`` into the name (upper case) and its parameters.

    Raises
    ------
    ValueError
        Naming ``method`` when the text is not a spec.
    """
    name, _, rest = text.partition(":")
    params = {}
    if rest.strip():
        for part in rest.split(","):
            key, eq, value = part.partition("=")
            key = key.strip()
            word = value.strip().lower()
            try:
                if not eq or not key:
                    raise ValueError
                if _WORD.match(word) and word not in _NOT_WORDS:
                    number = word
                else:
                    number = _validate.decimal_text(key, value.strip())
            except ValueError:
                raise ValueError(
                    f"method must be NAME or NAME:param=value,..., got {_validate.shown(text)}"
                ) from None
            if not isinstance(number, str) and not math.isfinite(number):
                raise ValueError(f"method {name.strip().upper()}: {key} must be finite, got "
                                 f"{_validate.shown(value.strip())}")  # fmt: skip
            if key in params:
                raise ValueError(f"method {name.strip().upper()}: {key} is given twice in "
                                 f"{_validate.shown(text)}")  # fmt: skip
            params[key] = number
    return name.strip().upper(), params


def get_method(name, **params) -> Method:
    """Look up a method by name or spec, case-insensitive: ``"AS"``, ``"ro"``, ``"RO:r=1.5"``.

    Parameters
    ----------
    name : str or Method
    **params : float
        Parameter values (override those of the spec).

    Raises
    ------
    ValueError
        Naming ``method`` when the name is unknown, or the method and parameter when a value is
        out of range.
    """
    if isinstance(name, Method):
        return name.with_params(**params) if params else name
    if not isinstance(name, str):
        raise ValueError(f"method must be a method name such as 'AS', got {_validate.shown(name)}")
    key, spec_params = parse_spec(name)
    if key not in METHODS:
        load_plugins()
    if key not in METHODS:
        why = next((f" (plug-in {k}: {v})" for k, v in UNAVAILABLE.items() if k.upper() == key),
                   "")  # fmt: skip
        raise ValueError(
            f"method must be one of {', '.join(METHODS)}, got {_validate.shown(name)}{why}"
        )
    method = METHODS[key]
    merged = {**spec_params, **params}
    if not merged:
        return method
    bound_key = hit = None
    if all(_validate.is_number(v) or isinstance(v, str) for v in merged.values()):
        # (True == 1: not a key)
        bound_key = (key, tuple(sorted((k, v if isinstance(v, str) else float(v))
                                       for k, v in merged.items())))  # fmt: skip
        hit = _BOUND.get(bound_key)
    if hit is None or hit.module is not method.module:
        hit = method.with_params(**merged)
        if bound_key is not None and len(_BOUND) < 1024:
            _BOUND[bound_key] = hit
    return hit
