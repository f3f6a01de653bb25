"""Why a goal has no plan: relaxed reachability of each goal atom.

The relaxation ignores that an action's effects take something away: a literal — a pair
touching, or a pair not touching — is *reachable* when it holds at the start or an action
whose conditions are all reachable makes it true. A goal atom that is not reachable in this
relaxation has no plan, whatever else happens; its explanation names the OAC that would
make it true and the condition of it that can never hold, or says that no OAC makes it true
at all. This is a fixpoint over the actions' groundings, not a search: the plans come from
the planners (:mod:`oacdsl.planning.engines`).
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from dataclasses import dataclass

from oacdsl.matching.conditions import bind_atom
from oacdsl.model import Atom, atom_text
from oacdsl.planning.task import Action, Task
from oacdsl.world import relation

__all__ = ["Ground", "ground", "unreachable"]

Literal = tuple[str, str, bool]  # (a, b, touching?) with a < b


@dataclass(frozen=True)
class Ground:
    """An action with every parameter bound."""

    action: Action
    binding: dict[str, str]

    def label(self) -> str:
        return f"{self.action.oac.name}({', '.join(self.binding[p.name] for p in self.action.oac.params)})"


def ground(task: Task) -> Iterator[Ground]:
    """Every injective binding of each action's free parameters to instances of their classes."""
    for action in task.actions:
        free = action.free()
        options = [sorted(i for i, cls in task.classes.items() if c in cls) for _, c in free]
        taken = {i for _, i in action.fixed}
        for pick in itertools.product(*options):
            if len(set(pick)) < len(pick) or taken & set(pick):
                continue
            binding = dict(action.fixed) | {name: inst for (name, _), inst in zip(free, pick, strict=True)}
            yield Ground(action, binding)


def _lit(a: str, b: str, touching: bool) -> Literal:
    x, y = relation(a, b)
    return (x, y, touching)


class _Relaxed:
    def __init__(self, task: Task) -> None:
        self.names = sorted(task.classes)
        self.reached: set[Literal] = set()
        for a, b in itertools.combinations(self.names, 2):
            self.reached.add(_lit(a, b, task.init.touches(a, b)))
        self.grounds = list(ground(task))
        self.adders: dict[Literal, list[Ground]] = {}
        changed = True
        while changed:
            changed = False
            for g in self.grounds:
                if self.blocked(g) is None:
                    for lit in self.adds(g):
                        self.adders.setdefault(lit, [])
                        if lit not in self.reached:
                            self.reached.add(lit)
                            changed = True

    def holds(self, atom: Atom) -> bool:
        x = atom.left
        if atom.about_nothing:
            others = [y for y in self.names if y != x]
            if atom.negated:
                return any(_lit(x, y, True) in self.reached for y in others)
            return all(_lit(x, y, False) in self.reached for y in others)
        if x == atom.right:
            return atom.negated
        return _lit(x, atom.right, not atom.negated) in self.reached

    def blocked(self, g: Ground) -> Atom | None:
        """The first precondition of ``g`` that is not reachable, else None."""
        bound = (bind_atom(p, g.binding) for p in g.action.oac.pre)
        return next((a for a in bound if not self.holds(a)), None)

    def adds(self, g: Ground) -> list[Literal]:
        out: list[Literal] = []
        for atom in (bind_atom(e, g.binding) for e in g.action.oac.effect):
            if atom.about_nothing:
                if not atom.negated:
                    out += [_lit(atom.left, y, False) for y in self.names if y != atom.left]
            elif atom.left != atom.right:
                out.append(_lit(atom.left, atom.right, not atom.negated))
        return out

    def makers(self, atom: Atom) -> list[Ground]:
        """The groundings whose effects make ``atom`` (or, for ``nothing``, part of it) true."""
        wanted: set[Literal]
        if atom.about_nothing:
            others = [y for y in self.names if y != atom.left]
            wanted = {_lit(atom.left, y, atom.negated) for y in others}
        else:
            wanted = {_lit(atom.left, atom.right, not atom.negated)}
        return [g for g in self.grounds if wanted & set(self.adds(g))]


def unreachable(task: Task) -> list[tuple[Atom, str]]:
    """The goal atoms no plan can reach, each with the reason (empty: each is reachable alone)."""
    relaxed = _Relaxed(task)
    out: list[tuple[Atom, str]] = []
    for atom in task.goal:
        if relaxed.holds(atom):
            continue
        makers = relaxed.makers(atom)
        if not makers:
            unbound = "".join(
                f"; {oac} needs a {cls}, which the scene has none of" for oac, cls in task.left_out
            )
            out.append((atom, f"no OAC of the library makes {atom_text(atom)} true{unbound}"))
            continue
        shown = []
        for g in makers[:3]:
            blocked = relaxed.blocked(g)
            shown.append(f"{g.label()} needs {atom_text(blocked) if blocked else '?'}, which never holds")
        more = f" (and {len(makers) - 3} more)" if len(makers) > 3 else ""
        out.append((atom, "; ".join(shown) + more))
    return out
