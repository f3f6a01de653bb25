"""Which grasps of an object a hand tries, most preferred first (:func:`grasp_candidates`):
the declared grasp's variants (:func:`~oacdsl.runtime.grasping.plan_grasps`) ordered by
whether their way in is free of the objects standing on the table, of the other hand and
what it holds (:mod:`oacdsl.runtime.motion.approach`), whether the arm keeps off what that
hand holds, and, when none is free, whether the IK reaches them without leaning the torso as
far as it goes (:func:`fallback_rank`); a side approach near a neighbour starts closer
(:func:`clear_pre_grasp`); and, while the other hand holds the object, the grasps that leave
it room (:func:`handover_candidates`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from oacdsl.runtime.grasping import GraspPlan, plan_grasps
from oacdsl.runtime.handgap import hands_gap
from oacdsl.runtime.hands import OPEN, TOP_PRESHAPE
from oacdsl.runtime.motion.approach import (
    approach_gap,
    approach_postures,
    arm_room_in,
    other_side_boxes,
    torso_margin_rad,
)
from oacdsl.runtime.motion.tuning import TUNING, Tuning
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.transforms import make_T

__all__ = [
    "HAND_HALF_WIDTH_M",
    "HANDS_APART_M",
    "clear_pre_grasp",
    "fallback_rank",
    "grasp_candidates",
    "handover_candidates",
    "preshape",
]

#: Half the hand's width across the fingers, plus a margin: the free corridor an approach needs, m.
HAND_HALF_WIDTH_M = 0.07
#: Room kept between two hands that grasp at once, m: the smallest distance between their
#: collision boxes (palm, fingers, the thumb held out) at the two grasp poses
#: (:func:`~oacdsl.runtime.handgap.hands_gap`), for the IK's tracking error and the approach.
HANDS_APART_M = 0.03


def grasp_candidates(ctx: SkillContext, hand: str, obj: str, shared: bool = False) -> list[GraspPlan]:
    """The grasps of ``obj`` by ``hand`` its declaration allows, most natural first, those
    whose approach corridor is free of other objects before the others.

    ``shared``: both hands take the object (a rolling pin). One that is not round is then
    taken at its declared grasp point or at that point mirrored through its axis (offset
    ``(-x, -y, z)``), whichever lies on the hand's own side of the object."""
    side = ctx.side(hand)
    t_obj = ctx.world.body_pose(obj)
    support = ctx.support_height(t_obj[:2, 3], exclude=obj, below=float(t_obj[2, 3]) + 0.01)
    if ctx.other_holder(side, obj) is not None:
        # held up by the other hand (a hand-over): taken as high above its base as if it stood
        # there, so that this hand sets it down later before its own lower edge meets the
        # support (a cup taken 6 cm above its base: the palm met the table first, 60 N)
        support = max(support, float(t_obj[2, 3]))
    top = float(t_obj[2, 3] + t_obj[2, 2] * ctx.body(obj).height)  # upright: its base + height, m
    grasp = ctx.grasp_for(obj)
    plans = plan_grasps(grasp, ctx.body(obj).round, t_obj, side, support_z=support, top_z=top)
    if shared and not ctx.body(obj).round:
        x, y, z = grasp.offset
        mirrored = grasp.model_copy(update={"offset": (-x, -y, z)})
        plans += plan_grasps(mirrored, False, t_obj, side, support_z=support, top_z=top)
        left = ctx.world.frame_pose("grasp_l")[:3, 3] - ctx.world.frame_pose("grasp_r")[:3, 3]
        own = left if side == "l" else -left
        plans = [p for p in plans if float((p.grasp[:3, 3] - t_obj[:3, 3]) @ own) > 0] or plans
    # free: past the objects on the table, and past the other hand and what it holds: the hand
    # coming in keeps room from them, and the arm does not lie on what that hand holds
    # (motion/approach.py: a left hand taking a peeler came in through the cucumber the right
    # hand held up beside it, 66 N; taken from behind instead, its forearm lay on it, 61 N)
    still, fingers = other_side_boxes(ctx.world, side, {obj}), preshape(ctx, obj)
    held = ctx.world.held.get("l" if side == "r" else "r")
    postures: dict[int, list[Mapping[str, float]]] = {}

    def room(p: GraspPlan) -> float:
        return approach_gap(side, p, fingers, still)

    def posture(p: GraspPlan) -> list[Mapping[str, float]]:
        if id(p) not in postures:
            postures[id(p)] = approach_postures(ctx.ctl.ik, side, p)
        return postures[id(p)]

    arm: dict[int, bool] = {}

    def arm_clear(p: GraspPlan) -> bool:
        if held is None or held == obj:
            return True
        if id(p) not in arm:
            arm[id(p)] = arm_room_in(ctx.world, side, posture(p), held) >= 0.0
        return arm[id(p)]

    def free(p: GraspPlan) -> bool:
        return (ctx.clearance(p.pre_grasp[:3, 3], p.grasp[:3, 3], {obj}) >= HAND_HALF_WIDTH_M
                and room(p) >= HANDS_APART_M and arm_clear(p))

    # the planned approaches whose corridor is free first; then those made free by a shorter
    # approach (clear_pre_grasp: a left hand pouring a cup across its body, taken so, reached
    # it past the bowl, 111 N, where a planned free approach was there); then the others, those
    # ranked by fallback_rank
    clear = [p for p in plans if free(p)]
    moved = [clear_pre_grasp(ctx, p, obj, room) for p in plans if not free(p)]
    rest = sorted((p for p in moved if not free(p)),
                  key=lambda p: fallback_rank(arm_clear(p), room(p), torso_margin_rad(posture(p)[-1])))
    return clear + [p for p in moved if free(p)] + rest


def fallback_rank(
    arm_clear: bool, room_m: float, torso_margin: float, tuning: Tuning = TUNING
) -> tuple[bool, bool, bool, float]:
    """The rank (smaller first) of a grasp whose way in keeps less than :data:`HANDS_APART_M`
    from the other hand and what it holds, among such grasps: those whose arm keeps off what
    the other hand holds (``arm_clear``) first, then those whose way in does not overlap the
    other hand (``room_m`` ≥ 0), then those the whole-body IK reaches without leaning the torso
    as far as it goes (``torso_margin``, rad, :func:`~oacdsl.runtime.motion.approach.torso_margin_rad`,
    at least the tuning's ``torso_margin_rad``: a lid taken so was held 10-16° tilted and
    missed the bottle), then the roomiest."""
    return (not arm_clear, room_m < 0.0, torso_margin < tuning.torso_margin_rad, -min(room_m, HANDS_APART_M))


def clear_pre_grasp(
    ctx: SkillContext, plan: GraspPlan, obj: str, room: Callable[[GraspPlan], float] | None = None
) -> GraspPlan:
    """``plan`` with its pre-grasp moved in along the approach, by ``TUNING.pre_grasp_step_m`` at a
    time down to ``TUNING.pre_grasp_min_m`` from the grasp, until the hand there keeps
    :data:`HAND_HALF_WIDTH_M` from every other object's footprint and, with ``room`` (the gap
    an approach keeps from the other hand and what it holds, m), the shortened approach keeps
    :data:`HANDS_APART_M` from them: the hand comes down to its pre-grasp from above, and one
    that starts a side approach over a neighbour came down on it (a left hand taking a block
    past a crate: 83 N; a left hand taking a peeler, onto the cucumber the right hand held up
    beside it: 66 N). When no shorter approach keeps that room, the roomiest of those clear of
    the objects, if roomier than ``plan``. Unchanged when it is clear already, when the
    approach is from above, or when nothing shorter is better."""
    d = plan.approach
    if abs(float(d[2])) > float(np.hypot(d[0], d[1])):  # from above: the pre-grasp is over the grasp
        return plan
    point = plan.grasp[:3, 3]
    length = float(np.linalg.norm(plan.pre_grasp[:3, 3] - point))
    best, most = plan, (-np.inf if room is None else room(plan))
    while length >= TUNING.pre_grasp_min_m:
        pre = point - length * d
        shorter = GraspPlan(plan.grasp, make_T(plan.grasp[:3, :3], pre), d, plan.end)
        if ctx.clearance(pre, pre, {obj}) >= HAND_HALF_WIDTH_M:
            gap = np.inf if room is None else room(shorter)
            if gap >= HANDS_APART_M:
                return plan if np.allclose(pre, plan.pre_grasp[:3, 3]) else shorter
            if gap > most:
                best, most = shorter, gap
        length -= TUNING.pre_grasp_step_m
    return best


def handover_candidates(ctx: SkillContext, hand: str, obj: str) -> list[GraspPlan]:
    """The grasps of ``obj`` by ``hand`` while the other hand holds it: its declared grasps and,
    for an object that is not round, the declared point mirrored through its axis; those that
    leave room for the other hand where it holds the object (its hand boxes, as they are,
    :data:`~oacdsl.runtime.skills.bimanual.HANDS_APART_M` apart) come first, the grasp point
    the other hand occupies last (taking it there pressed both hands together: 69 N)."""

    side = ctx.side(hand)
    other = "l" if side == "r" else "r"
    plans = grasp_candidates(ctx, hand, obj, shared=True)
    held = (other, ctx.world.frame_pose(f"grasp_{other}"), ctx.ctl.fingers[other])
    room = [hands_gap((side, p.grasp, preshape(ctx, obj)), held) >= HANDS_APART_M for p in plans]
    return [p for p, ok in zip(plans, room, strict=True) if ok] + [
        p for p, ok in zip(plans, room, strict=True) if not ok
    ]


def preshape(ctx: SkillContext, obj: str) -> dict[str, float]:
    """The fingers of a hand coming to grasp ``obj`` (the thumb folded for a grasp from above)."""
    return TOP_PRESHAPE if ctx.grasp_for(obj).approach == "top" else OPEN
