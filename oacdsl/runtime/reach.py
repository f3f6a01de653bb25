"""Which hand takes an object: the one whose arm reaches it (adaptive execution, issue 22).

The whole-body IK reaches nearly every spot on the table with either hand: the platform
shifts and turns, the torso leans. But a hand taken across the body that way sweeps its arm
over the other objects and presses into them (the left hand sent for a cup 50 cm to the
right stopped at 153 N). How far a hand's *arm alone* — platform and torso held still —
stays from an object's grasp tells the near hand from the far one: at the dough scene's
start the left arm misses the red cup by 5 cm and the green cup by 25 cm, the right arm the
opposite.

:func:`out_of_reach` looks at a step about to run: when it makes a hand that holds nothing
touch an object standing on the table (a grasp), the arm of that hand misses the object by
more than :data:`ARM_MISS_M` and the other hand, holding nothing either, misses it by less
than half as much, the object is the other hand's to take. The adaptive executor
(:mod:`oacdsl.runtime.adaptive`) then runs the same steps with the other hand, up to the step
that lets go of the object (:func:`with_other_hand`), when they still reach the goal, else
replans with the far hand's binding excluded.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.matching.conditions import bind_atoms
from oacdsl.runtime.binding import Step
from oacdsl.world import WorldState

__all__ = [
    "ARM_MISS_M", "CROSS_M", "FarHand", "arm_miss_m", "crossed", "exchanged_hands", "out_of_reach",
    "with_other_hand",
]

#: An arm that misses an object's grasp by more than this (m) with the platform and the torso
#: still does not take it when the other arm misses it by less than half as much.
ARM_MISS_M = 0.3
#: Hands that reach farther than this (m, in all) across the robot's middle for what they take
#: are exchanged when the other hands would reach less than half as far
#: (:func:`exchanged_hands`): about a hand's width (the palm is 11 cm across).
CROSS_M = 0.10


@dataclass(frozen=True)
class FarHand:
    """A step's hand that should leave its object to the other hand, and why."""

    hand: str
    other: str
    obj: str
    text: str


def arm_miss_m(ctx: Any, hand: str, obj: str) -> float:
    """How far (m) ``hand``'s arm alone stays from the nearest of ``obj``'s grasps."""
    from oacdsl.runtime.skills.grasp_choice import grasp_candidates

    side = ctx.side(hand)
    plans = grasp_candidates(ctx, hand, obj)
    if not plans:
        return float("inf")
    return min(ctx.ctl.ik.try_reach(side, p.grasp, arm_only=True).position_m for p in plans)


def _reaches(
    step: Step, state: WorldState, hands: set[str], objects: frozenset[str]
) -> list[tuple[str, str]]:
    """(hand, object) for each free hand the step makes touch an object on the table."""
    out = []
    for atom in bind_atoms(step.oac.effect, step.binding):
        if atom.negated or atom.about_nothing:
            continue
        for hand, obj in ((atom.left, atom.right), (atom.right, atom.left)):
            if hand in hands and obj in objects and state.touches_nothing(hand):
                out.append((hand, obj))
    return out


def out_of_reach(ctx: Any, step: Step, state: WorldState) -> FarHand | None:
    """Why ``step``'s hand should leave its object to the other hand (module docstring), or
    None when it takes it as demonstrated."""
    hands = dict(ctx.world.layout.hands)
    if len(hands) != 2:
        return None
    for hand, obj in _reaches(step, state, set(hands), ctx.objects()):
        other = next(h for h in hands if h != hand)
        if not state.touches_nothing(other):
            continue
        try:
            miss = arm_miss_m(ctx, hand, obj)
            if miss <= ARM_MISS_M:
                continue
            other_miss = arm_miss_m(ctx, other, obj)
        except RuntimeFailure:  # no grasp declared: the skill itself will say so
            continue
        if other_miss < miss / 2:
            text = (
                f"{obj} is out of {hand}'s reach (its arm alone misses it by {100 * miss:.0f} cm,"
                f" {other}'s by {100 * other_miss:.0f} cm)"
            )
            return FarHand(hand, other, obj, text)
    return None


def exchanged_hands(ctx: Any, steps: Sequence[Step]) -> tuple[dict[str, str], str] | None:
    """The two hands exchanged for the whole task ({hand: the hand that does its part}, and
    why), when the objects the steps send the hands for stand on the other arms' sides: a
    left-handed demonstration in a scene laid out for the right hand. Each object a hand takes
    (its first ``hand <-> object``) counts with how far the arm alone misses it now; the hands
    are exchanged when the demonstrated ones miss by more than :data:`ARM_MISS_M` in all and
    the exchanged ones by less than half as much (the rule :func:`out_of_reach` applies to one
    object); and when the demonstrated hands reach more than :data:`CROSS_M` in all across the
    robot's middle (:func:`crossed`; not counting an object both hands take at once), the
    exchanged ones less than half as far, and the
    exchanged arms miss no more: objects within reach of both arms but on the other hand's
    side (a left-handed Peel: the right hand held the cucumber up on the left, and the left
    hand, sent for the peeler on the right, reached past it and met it, 66 N, or, kept off
    it, pushed the right arm aside; a left-handed hand-over: the mug, taken on the right by
    the left hand, was set down by the right hand on its own side, where it started). None:
    as demonstrated."""
    hands = dict(ctx.world.layout.hands)
    if len(hands) != 2:
        return None
    objects = ctx.objects()
    taken: dict[str, str] = {}
    together: set[str] = set()  # taken first by both hands in one step (a rolling pin)
    for step in steps:
        now: dict[str, list[str]] = {}
        for atom in bind_atoms(step.oac.effect, step.binding):
            if atom.negated or atom.about_nothing:
                continue
            for hand, obj in ((atom.left, atom.right), (atom.right, atom.left)):
                if hand in hands and obj in objects and obj not in taken and hand not in now.get(obj, []):
                    now.setdefault(obj, []).append(hand)
        for obj, by in now.items():
            taken[obj] = by[0]
            if len(by) > 1:
                together.add(obj)
    if not taken:
        return None
    swap = dict(zip(hands, reversed(list(hands)), strict=True))
    try:
        demonstrated = sum(arm_miss_m(ctx, hand, obj) for obj, hand in taken.items())
        exchanged = sum(arm_miss_m(ctx, swap[hand], obj) for obj, hand in taken.items())
    except RuntimeFailure:  # an object without a grasp: the skill itself will say so
        return None
    alone = {o: h for o, h in taken.items() if o not in together}  # either hand's side for the others
    across, why = crossed(ctx, alone)
    if across > CROSS_M and crossed(ctx, {o: swap[h] for o, h in alone.items()})[0] < across / 2 \
            and exchanged <= demonstrated:
        return swap, (f"the hands are exchanged: as demonstrated they reach {100 * across:.0f} cm across"
                      f" the robot's middle in all ({why})")
    if demonstrated <= ARM_MISS_M or exchanged >= demonstrated / 2:
        return None
    text = (f"the hands are exchanged: the arms alone miss what they take ({', '.join(sorted(taken))})"
            f" by {100 * demonstrated:.0f} cm in all as demonstrated, by {100 * exchanged:.0f} cm exchanged")
    return swap, text


def crossed(ctx: Any, taken: Mapping[str, str]) -> tuple[float, str]:
    """How far (m, in all) the hands of ``taken`` (object → the hand that takes it first) reach
    across the robot's middle for what they take — the left hand for an object right of the
    middle between the two hands now, the right hand for one left of it — and the farthest
    such object, for a message ("" when none)."""
    sides = dict(ctx.world.layout.hands)
    t_l, t_r = ctx.world.frame_pose("grasp_l")[:3, 3], ctx.world.frame_pose("grasp_r")[:3, 3]
    left = t_l - t_r
    left[2] = 0.0
    left /= max(float(np.linalg.norm(left)), 1e-9)
    middle = 0.5 * (t_l + t_r)
    total, worst, text = 0.0, 0.0, ""
    for obj, hand in taken.items():
        sign = 1.0 if sides[hand] == "r" else -1.0
        beyond = sign * float((ctx.world.body_pose(obj)[:3, 3] - middle) @ left)
        if beyond > 0.0:
            total += beyond
            if beyond > worst:
                worst, text = beyond, f"{hand} takes {obj} {100 * beyond:.0f} cm past the middle"
    return total, text


def _lets_go(step: Step, hand: str, obj: str) -> bool:
    """True when ``step``'s effects free ``hand`` or part it from ``obj``."""
    for atom in bind_atoms(step.oac.effect, step.binding):
        if atom.left == hand and atom.about_nothing and not atom.negated:
            return True
        if atom.negated and {atom.left, atom.right} == {hand, obj}:
            return True
    return False


def with_other_hand(steps: Sequence[Step], far: FarHand) -> list[Step] | None:
    """``steps`` (the first takes ``far.obj`` with ``far.hand``) with ``far.other`` in place of
    ``far.hand`` up to and including the step that lets go of the object; None when a step of
    that stretch already uses the other hand (it is busy then)."""
    out: list[Step] = []
    swapping = True
    for step in steps:
        if swapping:
            if far.other in step.binding.values():
                return None
            binding = {k: far.other if v == far.hand else v for k, v in step.binding.items()}
            out.append(dataclasses.replace(step, binding=binding))
            swapping = not _lets_go(step, far.hand, far.obj)
        else:
            out.append(step)
    return out
