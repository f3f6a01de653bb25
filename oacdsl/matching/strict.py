"""The strict rule's conditions on a binding: what its bound effects must say about the change.

Besides the paper's rule (preconditions hold before, effects hold after), a strict match

1. **accounts for every change** (:func:`accounts_all`): every relation that started is a
   bound positive effect, every one that ended a bound ``not a <-> b`` or ``x <-> nothing``
   for one of its ends;
2. **acts only on what changed** (:func:`untouched`): every instance a bound effect names
   takes part in some changed relation.

The second is the paper's reading of an effect: "we are detecting actions by their effects on
the environment", and a composed OAC's effects are "the changes of the world state before the
new OAC to the world state after it" (Wächter et al. 2013, III and III-B). An effect literal that
already held may still belong to an action that changes its instances (``place_both``'s
``not o1 <-> o2``: both objects leave their hands), but an effect about an instance the
sub-action leaves as it was ascribes to the action something that did not happen. Without it a
whole-task OAC such as ``stack_block(h, b, c)`` (``pre h <-> nothing``, ``effect b <-> c,
not h <-> b``) matched the sub-action where the other hand, holding the block, sets it on the
crate, with the idle hand as ``h`` (its ``not h <-> b`` held all along).
"""

from __future__ import annotations

from collections.abc import Sequence
from collections.abc import Set as AbstractSet

from oacdsl.matching.search import AFTER, CompiledOac
from oacdsl.world import Relation

__all__ = ["accounts_all", "changed_instances", "effect_variables", "explained", "untouched"]


def _pairs(b: Sequence[str], pairs: tuple[tuple[int, int], ...]) -> set[Relation]:
    return {(b[i], b[j]) if b[i] < b[j] else (b[j], b[i]) for i, j in pairs}


def accounts_all(
    co: CompiledOac, b: Sequence[str], added: AbstractSet[Relation], removed: AbstractSet[Relation]
) -> bool:
    """True when the bound effects account for every changed relation (condition 1)."""
    if added and not added <= _pairs(b, co.eff_pos):
        return False
    if removed:
        neg = _pairs(b, co.eff_neg)
        cleared = {b[i] for i in co.eff_none}
        for r in removed:
            if r not in neg and r[0] not in cleared and r[1] not in cleared:
                return False
    return True


def explained(
    co: CompiledOac, b: Sequence[str], added: AbstractSet[Relation], removed: AbstractSet[Relation]
) -> int:
    """How many changed relations the bound effects account for."""
    pos, neg = _pairs(b, co.eff_pos), _pairs(b, co.eff_neg)
    cleared = {b[i] for i in co.eff_none}
    n = sum(r in pos for r in added)
    n += sum(r in neg or r[0] in cleared or r[1] in cleared for r in removed)
    return n


def effect_variables(co: CompiledOac) -> tuple[int, ...]:
    """The variables the OAC's effects name (``x <-> nothing`` and ``not x <-> nothing`` too)."""
    found = {v for pair in (*co.eff_pos, *co.eff_neg) for v in pair}
    found.update(co.eff_none)
    found.update(i for i, when in co.some if when == AFTER)
    return tuple(sorted(found))


def changed_instances(added: AbstractSet[Relation], removed: AbstractSet[Relation]) -> frozenset[str]:
    """The instances that take part in a changed relation."""
    return frozenset(x for r in (*added, *removed) for x in r)


def untouched(co: CompiledOac, b: Sequence[str], changed: AbstractSet[str],
              variables: Sequence[int] | None = None) -> list[str]:
    """The instances named by the bound effects that take part in no change (condition 2
    holds when there are none), in the order of the variables."""
    return [b[v] for v in (effect_variables(co) if variables is None else variables) if b[v] not in changed]
