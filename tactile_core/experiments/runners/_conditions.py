"""What the paper's experiments vary and hold fixed: the methods compared (the paper's four, or
another set of 2 to 8), their counterbalanced order per participant, and the fixed mu and gamma,
directions and shapes."""

from __future__ import annotations

from ..._shared import validate as _validate
from ..results import Session
from ..stats import apply_order

METHODS = ("CT", "MM", "AS", "IM")
DIRECTIONS = ("up", "down", "left", "right")
SHAPES = ("circle", "square")
MU, GAMMA = 0.33, 0.7


MAX_SET = 8
"""Most methods an experiment compares (number keys 1-8 in Experiment 1's preparation)."""


def method_set(session: Session, experiment: str, methods=None) -> list[str]:
    """The methods ``experiment`` compares for this session: ``methods`` (specs, validated and
    made canonical), else the set the session recorded, else the paper's four.

    The set is kept in ``session.json`` (``parameters[experiment + "_methods"]``) so that a
    resumed run compares the same methods; another set is refused.

    Parameters
    ----------
    session : Session
    experiment : str
        ``"exp1"`` or ``"exp3"``.
    methods : sequence of str, optional
        Method specs (names, or names with parameters).

    Returns
    -------
    list of str
        The canonical specs, 2 to :data:`MAX_SET` of them.

    Raises
    ------
    ValueError
        Naming the method or the set when a method is unknown, the set has fewer than 2 or
        more than 8 methods or one twice, or differs from the session's.
    """
    from ...rendering.methods import get_method

    key = f"{experiment}_methods"
    recorded = session.parameters.get(key)
    if recorded is not None and (
        not isinstance(recorded, list) or not all(isinstance(m, str) for m in recorded)
    ):
        raise ValueError(f"session parameter {key} must be a list of method names, got "
                         f"{_validate.shown(recorded)}")  # fmt: skip
    chosen = methods if methods is not None else recorded if recorded is not None else METHODS
    if isinstance(chosen, str) or not hasattr(chosen, "__iter__"):
        raise ValueError(f"methods must be a list of method names, got {_validate.shown(chosen)}")
    chosen = [get_method(m).spec for m in chosen]
    if not 2 <= len(chosen) <= MAX_SET or len(set(chosen)) != len(chosen):
        raise ValueError(
            f"methods must be 2 to {MAX_SET} different methods, got {' '.join(chosen) or 'none'}"
        )
    if recorded is not None and not session.answered(experiment):
        # started and stopped before an answer: the set may change, its order with it
        if [get_method(m).spec for m in recorded] != chosen:
            session.orders.pop(experiment, None)
        recorded = None
    if recorded is not None and [get_method(m).spec for m in recorded] != chosen:
        raise ValueError(
            f"methods {' '.join(chosen)} differ from the session's {' '.join(recorded)} for "
            f"{experiment}: resume with the same set, or use another participant id"
        )
    if recorded is None:  # (written once the runner holds the participant: Runner.__init__)
        session.parameters[key] = chosen
    return chosen


def _ordered(session: Session, experiment: str, methods: list) -> list:
    """``methods`` in the participant's counterbalanced order: one of the paper's 12 orders
    for the paper's four (in the paper's order), a balanced Latin square row for any other
    set."""
    paper = list(methods) == list(METHODS)
    order = session.order(experiment, len(methods), paper=paper)
    try:
        return apply_order(order, methods)
    except ValueError:
        raise ValueError(
            f"{session.path}: the order {order!r} of {experiment} does not fit its "
            f"{len(methods)} methods"
        ) from None
