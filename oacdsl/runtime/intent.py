"""What each step of a run is meant to leave behind: the predicted world state after it.

The effects decide the motion: a skill that has a choice (where ``place`` sets an object
down, whether it lets go of an object another hand holds) reads the world state its step
is predicted to leave. The prediction applies the steps' effects one after the other to
the world state observed before the run, as Algorithm 1 composes them: a relation holds
until an effect removes it (``not a <-> b``, or ``a <-> nothing``). A relation the run's
own effects name that no step establishes (a demonstration where the sponge ends on the
tray, matched to ``place``, whose effect is only ``h <-> nothing``) is added to the state
after the last step that acts on one of its two instances: that step is meant to make it.

Light on purpose (no MuJoCo): it is a function of the OACs and the binding only.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence

from oacdsl.runtime.binding import Step, bound_atoms
from oacdsl.world import NOTHING, WorldState, relation

__all__ = ["apply_effects", "coming_takes", "predicted_states"]


def apply_effects(state: WorldState, atoms: Sequence[tuple[str, str, bool]]) -> WorldState:
    """``state`` after bound effects ``(a, b, negated)``: ``a <-> nothing`` removes every
    relation of ``a``, ``not a <-> b`` removes one, ``a <-> b`` adds one."""
    removed: set[tuple[str, str]] = set()
    added: set[tuple[str, str]] = set()
    for a, b, negated in atoms:
        if NOTHING in (a, b):
            x = a if b == NOTHING else b
            if not negated:
                removed.update(r for r in state.relations if x in r)
        elif a in state.instances and b in state.instances and a != b:
            (removed if negated else added).add(relation(a, b))
    return state.with_changes(added=added, removed=removed)


def predicted_states(
    initial: WorldState, steps: Sequence[Step], goal: Sequence[tuple[str, str, bool]] = ()
) -> list[WorldState]:
    """The predicted world state after each of ``steps`` (one per step), starting from
    ``initial``; ``goal`` are the run's own bound effects (a composed OAC's), whose positive
    relations that no step establishes are given to the last step acting on them."""
    states: list[WorldState] = []
    state = initial
    for step in steps:
        state = apply_effects(state, bound_atoms(step.oac.effect, step.binding))
        states.append(state)
    if not states:
        return states
    for a, b, negated in goal:
        if negated or NOTHING in (a, b) or a not in initial.instances or b not in initial.instances:
            continue
        if states[-1].touches(a, b):
            continue
        acting = [k for k, s in enumerate(steps) if {a, b} & set(s.binding.values())]
        first = acting[-1] if acting else len(states) - 1
        for k in range(first, len(states)):
            states[k] = states[k].with_changes(added=[relation(a, b)])
    return states


def coming_takes(steps: Sequence[Step], hands: Collection[str]) -> tuple[tuple[str, str], ...]:
    """(hand, object) of each take ``steps`` are predicted to make, in order, each once: a
    positive effect relating one of ``hands`` to something (``grasp(h, o)``'s ``h <-> o``).
    A skill that leaves an object in the way of a later take (``place``) reads them."""
    out: list[tuple[str, str]] = []
    for step in steps:
        for a, b, negated in bound_atoms(step.oac.effect, step.binding):
            if negated or NOTHING in (a, b) or (a in hands) == (b in hands):
                continue
            take = (a, b) if a in hands else (b, a)
            if take not in out:
                out.append(take)
    return tuple(out)
