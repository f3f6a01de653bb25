"""Which steps may run together: two steps are independent when neither changes what the other
needs or changes.

A step is its bound preconditions and effects (atoms over instances, or over the parameters of
a composed OAC). Two atoms *interact* when they are about the same pair (``a <-> b``,
``not a <-> b``), or one is about all relations of ``x`` (``x <-> nothing``,
``not x <-> nothing``) and the other names ``x``. Steps A and B are *independent* when no
effect of A interacts with a precondition or effect of B, and no effect of B with one of A's:
then each one's preconditions hold whether the other ran before or not, and both orders give
the same state. The composer groups such steps of one keyframe into a ``together { … }``
block, and the compiler checks every block with the same rule (E051).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

from oacdsl.model import Atom
from oacdsl.world import NOTHING

__all__ = ["Cond", "bound", "conflict", "independent", "text", "StepConds"]

#: An atom as (left, right, negated), with ``nothing`` for ``x <-> nothing``.
Cond = tuple[str, str, bool]
#: A step: its preconditions and its effects.
StepConds = tuple[Sequence[Cond], Sequence[Cond]]


def bound(atoms: Iterable[Atom], binding: Mapping[str, str] | None = None) -> tuple[Cond, ...]:
    """``atoms`` as conditions, their names replaced through ``binding`` (others kept)."""
    names = binding or {}
    return tuple((names.get(a.left, a.left), names.get(a.right, a.right), a.negated) for a in atoms)


def _names(c: Cond) -> frozenset[str]:
    return frozenset(n for n in c[:2] if n != NOTHING)


def _whole(c: Cond) -> str | None:
    """``x`` when the condition is about all relations of x (``x <-> nothing``), else None."""
    if c[1] == NOTHING:
        return c[0]
    if c[0] == NOTHING:
        return c[1]
    return None


def _interact(effect: Cond, other: Cond) -> bool:
    a, b = _whole(effect), _whole(other)
    if a is not None or b is not None:
        return (a is not None and a in _names(other)) or (b is not None and b in _names(effect))
    return _names(effect) == _names(other)


def conflict(first: StepConds, second: StepConds) -> tuple[Cond, Cond] | None:
    """An effect of one step and a condition (precondition or effect) of the other that
    interact (see the module docstring), or None when the steps are independent."""
    for (_, effects), (pre, other_effects) in ((first, second), (second, first)):
        for e in effects:
            for c in (*pre, *other_effects):
                if _interact(e, c):
                    return e, c
    return None


def independent(steps: Iterable[StepConds]) -> bool:
    """True when every two of ``steps`` are independent."""
    items = list(steps)
    return all(conflict(a, b) is None for i, a in enumerate(items) for b in items[i + 1:])


def text(c: Cond) -> str:
    """``not a <-> b`` as written in ``.oac``."""
    return f"{'not ' if c[2] else ''}{c[0]} <-> {c[1]}"
