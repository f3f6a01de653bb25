"""A plan replayed through the matcher's semantics: each step's preconditions checked on a
:class:`~oacdsl.world.WorldState`, then its effects applied (:mod:`oacdsl.matching.conditions`).

An independent check of what a planner returned: the PDDL encoding and the planner are
not trusted to agree with the matcher, this replay is.
"""

from __future__ import annotations

from collections.abc import Sequence

from oacdsl.errors import PlanningError
from oacdsl.library import Library
from oacdsl.matching.conditions import apply_effects, bind_atoms, holds, why_not
from oacdsl.model import Atom, atom_text
from oacdsl.planning.engines import PlannedStep
from oacdsl.world import WorldState

__all__ = ["replay", "unmet"]


def unmet(atoms: Sequence[Atom], state: WorldState) -> list[str]:
    """The bound atoms that do not hold in ``state``, each with why (empty: all hold)."""
    return [f"{atom_text(a)} ({why_not(a, state)})" for a in atoms if not holds(a, state)]


def replay(library: Library, state: WorldState, plan: Sequence[PlannedStep]) -> list[WorldState]:
    """The states along ``plan`` from ``state`` (the first is ``state``); PlanningError names
    the first step whose preconditions do not hold."""
    states = [state]
    for index, step in enumerate(plan):
        oac = library.oacs.get(step.oac)
        if oac is None:
            raise PlanningError(f"step {index + 1}: no oac {step.oac!r} in the library")
        failed = unmet(bind_atoms(oac.pre, step.binding), states[-1])
        if failed:
            raise PlanningError(f"step {index + 1} {step.label()}: precondition not met: {'; '.join(failed)}")
        states.append(apply_effects(states[-1], bind_atoms(oac.effect, step.binding)))
    return states
