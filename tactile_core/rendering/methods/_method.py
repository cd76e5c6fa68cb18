"""The record of a registered method: its module, its parameters and (TB) its clock bound, and
its samplers made once.

:func:`~tactile_core.rendering.methods.get_method` hands these out; the protocol a method's
module follows is in :mod:`tactile_core.rendering.methods`.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass, field
from types import ModuleType

from ..._shared import validate as _validate
from ._plugin import checked as _checked
from ._plugin import max_tactors as _max_tactors

_MISSING = object()
_BUILT_IN_ONLY = ("sample_cells", "sample1_exact")


@dataclass(frozen=True)
class Method:
    """A rendering method as registered, with its parameter values bound.

    Attributes
    ----------
    name, title : str
    bilevel, needs_shape : bool
    max_tactors : int
        The most tactors one frame lights, at these parameters.
    module : module or object
        The implementation (see the protocol above).
    params : tuple of (str, float or str)
        Parameter values that differ from the defaults, in the order of ``PARAMS``, then of
        ``CHOICES``.
    source : str
        ``"paper"``, ``"peer"`` or ``"plugin <distribution>"``.
    correction : {"set", "threshold", "none"}
        The correction the method is designed to be driven with (see the protocol above and
        :meth:`own_correction`).
    clock_s : float or None
        For a method with a clock (``DURATION_S``, TB): the duration in seconds the trace
        clock bound (:meth:`on_clock`); None: the method's ``DURATION_S``.
    """

    name: str
    title: str
    bilevel: bool
    needs_shape: bool
    max_tactors: int
    module: ModuleType
    params: tuple = ()
    source: str = "paper"
    correction: str = "set"
    clock_s: float | None = None
    _samplers: dict = field(default_factory=dict, repr=False, compare=False, hash=False)

    @property
    def spec(self) -> str:
        """The name with its non-default parameters: ``"RO"``, ``"RO:r=1.5"``."""
        if not self.params:
            return self.name
        return self.name + ":" + ",".join(f"{k}={_number(v)}" for k, v in self.params)

    @property
    def param_specs(self) -> dict:
        """``{name: (default, low, high, description)}`` of the number parameters (empty for
        most methods)."""
        return dict(getattr(self.module, "PARAMS", None) or {})

    @property
    def choice_specs(self) -> dict:
        """``{name: (options, description)}`` of the word parameters (``RO``'s ``curve``); the
        first option is the default."""
        return dict(getattr(self.module, "CHOICES", None) or {})

    @property
    def values(self) -> dict:
        """Every parameter's value, defaults included."""
        out = {k: spec[0] for k, spec in self.param_specs.items()}
        out.update({k: spec[0][0] for k, spec in self.choice_specs.items()})
        out.update(self.params)
        return out

    def own_correction(self, mu: float, gamma: float) -> tuple[float, float]:
        """The correction this method is driven with when the user has set ``mu``/``gamma``.

        ``"set"`` methods (the paper's four, GS, plug-ins unless they say otherwise) take
        ``(mu, gamma)``; ``"threshold"`` ones (VRCH, whose server maps a value ``v > 0`` to
        ``offset + (1 - offset) v``) ``(mu, 1)``; ``"none"`` ones ``(0, 1)``, the identity: EN
        and PK normalise energy themselves, so a gamma on top compresses them a second time,
        and Syntacts' roll-off (RO) is played as computed.

        Returns
        -------
        (float, float)
            ``(mu, gamma)`` for :func:`~tactile_core.rendering.correction.correct`.
        """
        if self.correction == "none":
            return 0.0, 1.0
        if self.correction == "threshold":
            return float(mu), 1.0
        return float(mu), float(gamma)

    @property
    def correction_label(self) -> str:
        """A few words for a title: ``"set correction"``, ``"threshold only"``,
        ``"no correction"``."""
        return {"none": "no correction", "threshold": "threshold only"}.get(
            self.correction, "set correction"
        )

    @property
    def plugin(self) -> bool:
        """True for a method loaded from an entry point."""
        return self.source.startswith("plugin")

    @property
    def clocked(self) -> bool:
        """True for a method whose intensities depend on the time along the trace (it declares
        ``DURATION_S``: TB)."""
        return getattr(self.module, "DURATION_S", None) is not None

    @property
    def duration_s(self) -> float | None:
        """The seconds ``t`` from 0 to 1 lasts for a clocked method (the bound trace's, else
        its ``DURATION_S``); None for the others."""
        if not self.clocked:
            return None
        return self.clock_s if self.clock_s is not None else float(self.module.DURATION_S)

    def on_clock(self, duration_s: float) -> Method:
        """This method timed by a trace of ``duration_s`` seconds (``t`` from 0 to 1): itself
        for a method without a clock (all but TB), so callers bind unconditionally.

        Parameters
        ----------
        duration_s : float
            Seconds, > 0 (a trace's ``duration_s``).

        Returns
        -------
        Method
        """
        if not self.clocked:
            return self
        duration_s = _validate.duration("duration_s", duration_s)
        if duration_s == self.duration_s:
            return self
        return dataclasses.replace(self, clock_s=duration_s, _samplers={})

    @property
    def sample(self):
        """Vectorised sampler with the parameters bound, see the protocol above."""
        return self._sampler("sample")

    @property
    def sample1(self):
        """Scalar sampler for the live path, parameters bound."""
        return self._sampler("sample1")

    @property
    def sample_cells(self):
        """A built-in method's batch sampler in the renderer's form (:mod:`._cells`),
        parameters bound; None for plug-ins and methods without one."""
        return self._sampler("sample_cells")

    @property
    def sample1_exact(self):
        """A built-in method's scalar sampler that returns None where a decision lies within
        rounding of its edge (there the array arithmetic may decide otherwise); None for
        plug-ins. Methods whose scalar arithmetic decides as the arrays' do use ``sample1``."""
        return self._sampler("sample1_exact")

    def _sampler(self, which: str):
        hit = self._samplers.get(which, _MISSING)
        if hit is _MISSING:
            fn = getattr(self.module, which, None)
            if which == "sample1_exact" and fn is None:
                fn = self.module.sample1
            bound = dict(self.params)
            if self.clocked:
                bound["duration_s"] = self.duration_s
            if which in _BUILT_IN_ONLY and self.plugin:
                fn = None  # plug-ins go through the protocol's checked samplers only
            elif fn is not None and bound:
                fn = functools.partial(fn, **bound)
            if fn is not None and self.plugin:
                fn = _checked(self.spec, fn, which == "sample1")  # output checked, failures
                # contained (see ``_plugin``)
            hit = self._samplers[which] = fn
        return hit

    def with_params(self, **params) -> Method:
        """This method with other parameter values (validated; ``ValueError`` names them)."""
        values = self.values
        specs, choices = self.param_specs, self.choice_specs
        for key, value in params.items():
            if key in choices:
                options = choices[key][0]
                word = value.lower() if isinstance(value, str) else value
                values[key] = _validate.choice(f"method {self.name}: {key}", word, options)
                continue
            if key not in specs:
                known = ", ".join([*specs, *choices]) or "none"
                raise ValueError(
                    f"method {self.name} has no parameter {_validate.shown(key)} "
                    f"(its parameters: {known})"
                )
            _, lo, hi, _ = specs[key]
            values[key] = _validate.in_range(f"method {self.name}: {key}", value, lo, hi)
        bound = tuple((k, float(values[k])) for k in specs if values[k] != specs[k][0])
        bound += tuple((k, values[k]) for k in choices if values[k] != choices[k][0][0])
        made = _make(self.module, self.source, bound)
        return made if self.clock_s is None else dataclasses.replace(made, clock_s=self.clock_s)


def _number(value) -> str:
    """Shortest text that reads back as ``value`` (``1`` for 1.0; a word as it is)."""
    if isinstance(value, str):
        return value
    return f"{value:g}" if float(f"{value:g}") == value else repr(float(value))


def _make(module, source: str, params: tuple = ()) -> Method:
    defaults = {k: spec[0] for k, spec in (getattr(module, "PARAMS", None) or {}).items()}
    numbers = {k: v for k, v in {**defaults, **dict(params)}.items() if not isinstance(v, str)}
    plugin = " (a plug-in)" if source.startswith("plugin") else ""
    label = f"{getattr(module, 'NAME', '?')}{plugin}"
    correction = getattr(module, "CORRECTION", "set")
    if correction not in CORRECTIONS:
        raise ValueError(f"method {label}: CORRECTION must be one of {', '.join(CORRECTIONS)}, "
                         f"got {_validate.shown(correction)}")  # fmt: skip
    return Method(
        name=module.NAME,
        title=module.TITLE,
        bilevel=bool(module.BILEVEL),
        needs_shape=bool(module.NEEDS_SHAPE),
        max_tactors=_max_tactors(module, numbers, label),
        module=module,
        params=params,
        source=source,
        correction=correction,
    )


CORRECTIONS = ("set", "threshold", "none")
"""The corrections a method may be designed for (its ``CORRECTION``)."""
