"""Touching conditions on world states: binding, evaluation, explanation, application.

An OAC's preconditions and effects are :class:`~oacdsl.model.Atom` s over its
variables. Bound to instances (``bind_atom``) they become statements about a
:class:`~oacdsl.world.WorldState`:

========================  =============================================
``a <-> b``               a and b touch
``not a <-> b``           a and b do not touch
``x <-> nothing``         x is a known instance that touches no other one
``not x <-> nothing``     x touches at least one other instance
========================  =============================================

``apply_effects`` is the update an OAC makes: every removal first (``not a <-> b``
removes the pair, ``x <-> nothing`` removes all of x's relations), then every
addition (``a <-> b``). ``not x <-> nothing`` says something about the result
but prescribes no update; it is left out.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from oacdsl.errors import MatchingError
from oacdsl.model import Atom, atom_text
from oacdsl.world import NOTHING, Relation, WorldState, relation

__all__ = [
    "apply_effects",
    "bind_atom",
    "bind_atoms",
    "holds",
    "why_not",
]


def bind_atom(atom: Atom, binding: Mapping[str, str]) -> Atom:
    """The atom with its variables replaced by instances (unbound names stay as they are)."""
    left = binding.get(atom.left, atom.left)
    right = atom.right if atom.right == NOTHING else binding.get(atom.right, atom.right)
    return Atom(left=left, right=right, negated=atom.negated, note=atom.note)


def bind_atoms(atoms: Iterable[Atom], binding: Mapping[str, str]) -> tuple[Atom, ...]:
    """``bind_atom`` over several atoms, in their order."""
    return tuple(bind_atom(a, binding) for a in atoms)


def holds(atom: Atom, state: WorldState) -> bool:
    """True when the bound ``atom`` holds in ``state`` (see the module table)."""
    if atom.about_nothing:
        if atom.negated:
            return bool(state.partners(atom.left))
        return state.touches_nothing(atom.left)
    if atom.left == atom.right:
        return atom.negated  # an instance never touches itself
    return state.touches(atom.left, atom.right) != atom.negated


def why_not(atom: Atom, state: WorldState) -> str:
    """Why the bound ``atom`` fails in ``state``: ``left_hand touches red_cup``."""
    x = atom.left
    if atom.about_nothing:
        if atom.negated:
            return f"{x} touches nothing"
        if x not in state.instances:
            return f"{x} is not an instance of the world state"
        return f"{x} touches {', '.join(sorted(state.partners(x)))}"
    if atom.negated:
        return f"{x} touches {atom.right}"
    return f"{x} and {atom.right} do not touch"


def _known(state: WorldState, *names: str) -> None:
    for name in names:
        if name not in state.instances:
            raise MatchingError(f"effect names {name!r}, which is not an instance of the world state")


def apply_effects(state: WorldState, effects: Iterable[Atom]) -> WorldState:
    """The state after bound ``effects``: removals first, then additions."""
    effects = tuple(effects)
    removed: set[Relation] = set()
    added: set[Relation] = set()
    for atom in effects:
        if atom.about_nothing:
            if not atom.negated:
                _known(state, atom.left)
                removed.update(r for r in state.relations if atom.left in r)
        elif atom.negated:
            if atom.left != atom.right:
                removed.add(relation(atom.left, atom.right))
        else:
            _known(state, atom.left, atom.right)
            if atom.left == atom.right:
                raise MatchingError(f"effect {atom_text(atom)}: an instance cannot touch itself")
            added.add(relation(atom.left, atom.right))
    return state.with_changes(added=added, removed=removed)
