"""A library and a world state as a planning task: the OACs as actions, the instances as objects.

The encoding keeps the matcher's semantics (:mod:`oacdsl.matching.conditions`):

* touching is symmetric: ``a <-> b`` is the fact ``(touching a b)`` *and* ``(touching b a)``;
  an effect adds or deletes both, a condition asks for one;
* ``x <-> nothing`` as a condition: ``(forall (?y) (not (touching x ?y)))``; as an effect it
  deletes all of x's relations; ``not x <-> nothing`` as a condition: x touches some instance,
  as an effect it prescribes nothing (the matcher leaves it out);
* an effect's deletions come before its additions (PDDL's own order: an added fact stays);
* different parameters bind different instances (the matcher's bindings are injective);
* classes are unary facts (``(is-cup x)``) holding for every class of an instance, inherited
  ones included: a parameter ``c: Container`` asks for ``(is-container ?c)``. PDDL's types form
  a tree, and the language's classes may have several parents (``Cup : Container, Graspable``).

Only OACs that execute a skill are actions (a composed OAC is what a plan is made of).
An :class:`Action` may fix some parameters to instances and carry a cost: the adaptive
executor prefers the demonstrated steps this way (:mod:`oacdsl.planning.adaptive`).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from oacdsl.errors import PlanningError
from oacdsl.library import Library
from oacdsl.model import Atom, Oac
from oacdsl.world import WorldState

__all__ = ["Action", "Task", "make_task", "pddl_name", "primitive_actions"]

_NAME = re.compile(r"[a-z][a-z0-9_-]*")


@dataclass(frozen=True)
class Action:
    """One action schema: an OAC, some of its parameters fixed to instances, a cost ≥ 1."""

    name: str  # the PDDL name (lower case)
    oac: Oac
    fixed: tuple[tuple[str, str], ...] = ()  # (parameter, instance), in parameter order
    cost: int = 1
    #: Bindings the planner may not choose (a step that failed): each (parameter, instance) pairs.
    banned: tuple[tuple[tuple[str, str], ...], ...] = ()

    def free(self) -> list[tuple[str, str]]:
        """The parameters left to the planner: (name, class)."""
        fixed = dict(self.fixed)
        return [(p.name, p.cls) for p in self.oac.params if p.name not in fixed]


@dataclass(frozen=True)
class Task:
    """A planning task: actions, the instances with their classes, an initial state, a goal."""

    name: str
    actions: tuple[Action, ...]
    classes: Mapping[str, frozenset[str]]  # instance → its classes (inherited included)
    init: WorldState
    goal: tuple[Atom, ...]
    costs: bool = False  # write action costs (a :metric minimising total-cost)
    pddl_names: dict[str, str] = field(default_factory=dict)  # instance → PDDL name
    class_names: dict[str, str] = field(default_factory=dict)  # class → its predicate (is-cup)
    left_out: tuple[tuple[str, str], ...] = ()  # (OAC, a parameter class no instance has)

    def pddl(self, name: str) -> str:
        return self.pddl_names[name]

    def original(self) -> dict[str, str]:
        """PDDL name → language name (to read a plan back)."""
        return {v: k for k, v in self.pddl_names.items()}


def pddl_name(name: str) -> str:
    """``name`` as a PDDL name: lower case, prefixed ``n`` when it is not one already."""
    text = name.lower()
    return text if _NAME.fullmatch(text) else "n" + re.sub(r"[^a-z0-9_-]", "_", text)


def _names(all_names: Iterable[str]) -> dict[str, str]:
    out: dict[str, str] = {}
    seen: dict[str, str] = {}
    for name in sorted(set(all_names)):
        pddl = pddl_name(name)
        if pddl in seen:
            raise PlanningError(f"names {seen[pddl]!r} and {name!r} are one name in PDDL (case is ignored)")
        seen[pddl] = name
        out[name] = pddl
    return out


def primitive_actions(library: Library) -> list[Action]:
    """Every OAC of ``library`` that executes a skill, as an action of cost 1, by name."""
    return [Action(pddl_name(o.name), o) for o in sorted(library.oacs.values(), key=lambda o: o.name)
            if not o.composed]


def make_task(
    name: str,
    actions: Sequence[Action],
    classes: Mapping[str, frozenset[str]],
    init: WorldState,
    goal: Sequence[Atom],
    *,
    costs: bool = False,
) -> Task:
    """A task whose names are checked to be distinct in PDDL. Actions with a parameter whose
    class no instance has are left out (nothing could bind it)."""
    have = set().union(*classes.values()) if classes else set()
    usable = tuple(a for a in actions if all(c in have for _, c in a.free()))
    left_out = tuple(
        (a.oac.name, next(c for _, c in a.free() if c not in have)) for a in actions if a not in usable
    )
    names = _names(classes)
    predicates = {c: f"is-{p}" for c, p in _names(have).items()}
    if len({a.name for a in usable}) != len(usable):
        raise PlanningError("two actions have the same name")
    missing = init.instances - set(classes)
    if missing:
        raise PlanningError(f"the state names instances without classes: {', '.join(sorted(missing))}")
    return Task(name, usable, dict(classes), init, tuple(goal), costs, names, predicates, left_out)
