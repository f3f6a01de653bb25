"""Lift the instances of a demonstration to typed parameters of a composed OAC.

Each instance becomes a parameter whose class is the most specific class of the
instance that is a subclass of every class the steps bind it as (so every step
call type-checks); its default is the instance itself (the demonstration's
binding). Parameter names come from the class: ``hand1, hand2, cup1, cup2,
bowl, mixer`` — numbered, in order of first appearance in the steps, only when
a class has several instances. Names are deterministic and independent of the
instances' names, so a renamed demonstration gives the same OAC.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence

from oacdsl.errors import MatchingError
from oacdsl.model import Param

__all__ = ["RESERVED", "lift", "most_specific", "snake"]

#: Words a parameter may not be called (keywords of the language, ``nothing``).
RESERVED = frozenset({
    "class", "scene", "grasp", "oac", "markers", "environment", "type", "approach", "offset",
    "pre", "effect", "execute", "steps", "not", "nothing", "ignored", "untracked", "layout", "at",
    "in", "balls",
})


def snake(name: str) -> str:
    """``GraspableObject`` → ``graspable_object``."""
    s = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", name).lower()
    s = re.sub(r"[^a-z0-9_]", "_", s)
    return s if s and not s[0].isdigit() else f"p_{s}"


def most_specific(
    instance: str,
    classes: frozenset[str],
    required: Sequence[str],
    ancestors: Callable[[str], frozenset[str]],
) -> str:
    """The class of ``instance`` with the most ancestors that is below every ``required`` class."""
    fits = [c for c in classes if all(r in ancestors(c) for r in required)]
    if not fits:
        need = ", ".join(sorted(set(required)))
        raise MatchingError(
            f"instance {instance} is bound as {need} by the steps, and none of its classes"
            f" ({', '.join(sorted(classes))}) is all of these; declare a class that inherits from them"
        )
    return min(fits, key=lambda c: (-len(ancestors(c)), c))


def lift(
    order: Sequence[str],
    classes: Mapping[str, frozenset[str]],
    required: Mapping[str, Sequence[str]],
    ancestors: Callable[[str], frozenset[str]],
) -> tuple[tuple[Param, ...], dict[str, str]]:
    """Parameters for the instances in ``order`` and the map instance → parameter name.

    ``required`` lists, per instance, the classes of the step parameters it was bound to.
    """
    chosen = {i: most_specific(i, classes.get(i, frozenset()), required.get(i, ()), ancestors) for i in order}
    by_base: dict[str, list[str]] = {}
    for inst in order:
        by_base.setdefault(snake(chosen[inst]), []).append(inst)
    names: dict[str, str] = {}
    taken: set[str] = set()
    for base, members in by_base.items():
        numbered = len(members) > 1 or base in RESERVED
        for k, inst in enumerate(members, start=1):
            name = f"{base}{k}" if numbered else base
            while name in taken:  # e.g. class "Cup1" next to two "Cup"s
                name += "_"
            names[inst] = name
            taken.add(name)
    params = tuple(Param(name=names[i], cls=chosen[i], default=i) for i in order)
    return params, names
