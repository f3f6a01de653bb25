"""Draft OACs for sub-actions that match no OAC (the paper's future work).

A draft describes the observed change, lifted to classes: its effects are the
relations that started (``a <-> b``) and ended (``not a <-> b``); its
preconditions are what the instances taking part in the change touched before
(``x <-> y``, or ``x <-> nothing``). Every instance it names becomes a parameter
of its most specific class, with the demonstration's instance as default. It
executes the placeholder skill ``TODO``, which ``oacc compile`` reports
(E016, unknown skill) until the author picks a real one: a draft is for review,
never silently executable. It matches its own sub-action under the strict rule.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from oacdsl.matching.lift import lift
from oacdsl.model import Atom, Oac
from oacdsl.world import NOTHING, WorldState

__all__ = ["PLACEHOLDER_SKILL", "propose_draft"]

#: The skill a draft executes until its author chooses one (not a runtime skill).
PLACEHOLDER_SKILL = "TODO"


def propose_draft(
    name: str,
    before: WorldState,
    after: WorldState,
    classes: Mapping[str, frozenset[str]],
    ancestors: Callable[[str], frozenset[str]],
    *,
    comments: tuple[str, ...] = (),
) -> tuple[Oac, dict[str, str]]:
    """A draft OAC called ``name`` for the change ``before → after``, and its binding
    (parameter → instance) for that sub-action."""
    added = sorted(after.relations - before.relations)
    removed = sorted(before.relations - after.relations)
    involved: list[str] = []
    for a, b in (*added, *removed):
        for x in (a, b):
            if x not in involved:
                involved.append(x)
    pre: list[Atom] = []
    for x in list(involved):
        partners = sorted(before.partners(x))
        if not partners:
            pre.append(Atom(left=x, right=NOTHING))
        for y in partners:
            pre.append(Atom(left=x, right=y))
            if y not in involved:
                involved.append(y)
    effect = [Atom(left=a, right=b) for a, b in added]
    effect += [Atom(left=a, right=b, negated=True) for a, b in removed]
    params, names = lift(involved, classes, {}, ancestors)

    def up(a: Atom) -> Atom:
        return Atom(left=names[a.left], right=names.get(a.right, a.right), negated=a.negated)

    oac = Oac(
        name=name,
        params=params,
        pre=tuple(map(up, pre)),
        effect=tuple(map(up, effect)),
        skill=PLACEHOLDER_SKILL,
        comments=comments,
    )
    return oac, {names[i]: i for i in involved}
